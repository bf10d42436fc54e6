//! C ABI of the circle-pattern conformal map (`methods::circle_patterns`).

use super::status::UvfStatus;
use super::MeshSource;
use super::SizedOut;
use super::{
    borrow_slice, borrow_slice_mut, checked_count, guard, progress_closure, read_options, write_uv, UvfProgressFn,
};
use std::os::raw::c_void;
use uvflat_core::error::Error;
use uvflat_core::methods::circle_patterns::{
    circle_pattern_cone_map, circle_pattern_map, polygon_boundary_curvature, CirclePatternOptions, CirclePatternReport,
};
use uvflat_core::progress::Progress;

/// Options of `uvf_circle_pattern_map`. Initialise with `uvf_circle_pattern_options_default`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct UvfCirclePatternOptions {
    /// `sizeof(UvfCirclePatternOptions)`, set by the default initialiser.
    pub struct_size: usize,
    /// Newton steps allowed for the radii, for the primal–dual angle solve (at most 40) and
    /// for each barrier stage of its fallback (default 100; ≥ 1).
    pub max_iterations: u32,
    /// Stop the radii when every circle closes to within this angle in radians (default 1e-11;
    /// > 0).
    pub tolerance: f64,
    /// 0: pin the two boundary vertices farthest apart at (0, 0) and (d, 0), d their 3D
    /// distance (default); 2: use `pin_vertices`.
    pub pin_count: u32,
    /// The two pinned vertices when `pin_count` is 2.
    pub pin_vertices: [u32; 2],
    /// Their UVs: u0, v0, u1, v1.
    pub pin_uv: [f64; 4],
    /// Optional progress callback (may be NULL), called once per barrier stage and per Newton
    /// step of the radii.
    pub progress: UvfProgressFn,
    /// Passed to `progress` unchanged.
    pub progress_user: *mut c_void,
    /// 1: flip the edges to the intrinsic Delaunay triangulation of the mesh's metric first, as
    /// the paper does (default); 0: enforce the Delaunay condition on the mesh's own edges,
    /// which never flips a triangle but distorts the angles at non-Delaunay edges.
    pub intrinsic_delaunay: u32,
    /// NULL (default): free boundary. Otherwise `vertex_count` doubles: the prescribed turning
    /// angle κ_v of the uv boundary at each boundary vertex (its uv angle sum is π − κ_v; 0 keeps
    /// the boundary straight there), NaN where the boundary is free; values at interior vertices
    /// are ignored. A fully prescribed boundary must sum to 2π (1 − holes) (Kharevych et al.
    /// 2006 §5). `uvf_circle_pattern_polygon_curvature` fills it for a convex polygon.
    pub boundary_curvature: *const f64,
    /// 1: keep the uv boundary convex (the paper's inequality constraints on the boundary
    /// angles): every boundary vertex whose curvature is not prescribed turns by at least 0, so
    /// the pattern embeds its triangulation (a local immersion with a convex boundary). 0: free
    /// (default).
    pub convex_boundary: u32,
}

impl Default for UvfCirclePatternOptions {
    fn default() -> Self {
        let d = CirclePatternOptions::default();
        UvfCirclePatternOptions {
            struct_size: std::mem::size_of::<Self>(),
            max_iterations: d.max_iterations,
            tolerance: d.tolerance,
            pin_count: 0,
            pin_vertices: [0, 0],
            pin_uv: [0.0, 0.0, 1.0, 0.0],
            progress: None,
            progress_user: std::ptr::null_mut(),
            intrinsic_delaunay: d.intrinsic_delaunay as u32,
            boundary_curvature: std::ptr::null(),
            convex_boundary: d.convex_boundary as u32,
        }
    }
}

/// What `uvf_circle_pattern_map` reports.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct UvfCirclePatternReport {
    /// `sizeof(UvfCirclePatternReport)`, set by the caller before the call; the library writes only the fields
    /// that fit in that many bytes (see Versioning at the top of the header).
    pub struct_size: usize,
    /// Iterations of the angle program: primal–dual steps, plus the log-barrier Newton steps
    /// where it fell back.
    pub angle_iterations: u32,
    /// Newton steps of the radii.
    pub radius_iterations: u32,
    /// Largest |Σ φ − π| over the circles at the end (radians).
    pub closure_error: f64,
    /// Interior edges of the triangulation used (after the intrinsic flips, if any) whose
    /// angles violate the Delaunay condition (the program moves them).
    pub non_delaunay_edges: u32,
    /// Largest |α − β| between a planar and a 3D angle (radians).
    pub max_angle_change: f64,
    /// Intrinsic edge flips made before the program.
    pub intrinsic_flips: u32,
    /// Mesh triangles whose uv area is not positive (always 0 with `intrinsic_delaunay` = 0).
    pub flipped_triangles: u32,
    /// log₁₀ of the largest over the smallest circle radius: the orders of magnitude the map's
    /// scale spans (3–4 on typical free maps). Beyond about 12 the layout loses the smallest
    /// triangles to double-precision rounding (counted in `flipped_triangles` or degenerate).
    pub radius_span: f64,
}

/// Fills `options` with defaults (100 iterations, tolerance 1e-11, automatic pins, no callback,
/// intrinsic Delaunay flips on).
///
/// # Safety
/// `options` must be NULL or point to a writable struct.
#[no_mangle]
pub unsafe extern "C" fn uvf_circle_pattern_options_default(options: *mut UvfCirclePatternOptions) {
    if !options.is_null() {
        options.write(UvfCirclePatternOptions::default());
    }
}

/// Conformal map by circle patterns (Kharevych, Springborn & Schröder 2006; course notes §4.4),
/// free boundary: the edges flipped to the intrinsic Delaunay triangulation of the mesh's
/// metric (paper §4; `intrinsic_delaunay`), planar angles from the paper's quadratic program
/// (closest to the 3D angles under the triangle and interior-vertex sums, positivity and the
/// local Delaunay condition, solved by a primal–dual interior-point method, or a log barrier
/// where rounding stops it), the intersection angles of the
/// triangles' circumcircles from them, the log radii as the minimizer of the paper's convex
/// energy (Newton), and the layout of the pattern's triangles. Every planar angle of the
/// pattern is in (0, π) and they close around every interior vertex; the mesh's triangles take
/// their vertices' uv, so after intrinsic flips some may be flipped (counted in
/// `flipped_triangles`; none without the flips). The boundary is free, or its turning angles
/// are prescribed where `boundary_curvature` says (paper §5; a straight-sided polygon with
/// `uvf_circle_pattern_polygon_curvature`). Cone singularities: `uvf_circle_pattern_cone_map`.
///
/// Needs a connected genus-0 mesh with at least one boundary; holes (every loop but the
/// longest) are filled by virtual cones for the pattern and the layout, so that each turns
/// exactly once in the plane. `uv_out` receives 2 doubles per
/// vertex (NaN for unreferenced ones); `options` and `report_out` may be NULL. Returns `UVF_OK`,
/// `UVF_INVALID_ARGUMENT`, `UVF_INVALID_MESH`, `UVF_UNSUPPORTED_TOPOLOGY`,
/// `UVF_NUMERICAL_FAILURE` (the barrier or the radii did not converge within the iteration
/// limit), `UVF_CANCELLED`, `UVF_INTERNAL_ERROR`. On failure the outputs are untouched.
///
/// # Safety
/// The arrays must hold the stated number of elements; `report_out` must be NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn uvf_circle_pattern_map(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    options: *const UvfCirclePatternOptions,
    uv_out: *mut f64,
    report_out: *mut UvfCirclePatternReport,
) -> UvfStatus {
    unsafe {
        circle_pattern_map_from(
            MeshSource::arrays(positions, vertex_count, triangles, triangle_count),
            options,
            uv_out,
            report_out,
        )
    }
}

/// `uvf_circle_pattern_map` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_circle_pattern_map`.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_circle_pattern_map(
    mesh: *const super::mesh_handle::UvfMesh,
    options: *const UvfCirclePatternOptions,
    uv_out: *mut f64,
    report_out: *mut UvfCirclePatternReport,
) -> UvfStatus {
    unsafe { circle_pattern_map_from(MeshSource::Handle(mesh), options, uv_out, report_out) }
}

/// `uvf_circle_pattern_map` on either kind of mesh.
///
/// # Safety
/// As for `uvf_circle_pattern_map`.
unsafe fn circle_pattern_map_from(
    source: MeshSource,
    options: *const UvfCirclePatternOptions,
    uv_out: *mut f64,
    report_out: *mut UvfCirclePatternReport,
) -> UvfStatus {
    guard(|| {
        let (vertex_count, _) = unsafe { source.counts() }?;
        // Checked before the work, so that a bad report pointer leaves every output untouched.
        let report_out = unsafe { SizedOut::optional(report_out, "report_out", "UvfCirclePatternReport") }?;
        let (o, opts) = options_from_c(options, vertex_count)?;
        let mesh = unsafe { source.mesh() }?;
        // Checked before the work so that a bad output pointer leaves everything untouched.
        borrow_slice_mut(uv_out, checked_count(vertex_count, 2, "uv")?, "uv_out")?;
        let mut callback = progress_closure(o.progress, o.progress_user);
        let result = circle_pattern_map(&mesh, &opts, &mut Progress::new(&mut callback))?;
        write_uv(&result.uv, uv_out)?;
        write_report(&result.report, report_out.as_ref());
        Ok(())
    })
}

/// The caller's options (defaults for NULL) checked and converted.
///
/// # Safety
/// `options` must be NULL or valid, its `boundary_curvature` NULL or `vertex_count` long.
unsafe fn options_from_c(
    options: *const UvfCirclePatternOptions,
    vertex_count: usize,
) -> uvflat_core::error::Result<(UvfCirclePatternOptions, CirclePatternOptions)> {
    let full = std::mem::size_of::<UvfCirclePatternOptions>();
    let o = read_options(options, UvfCirclePatternOptions::default(), full, "UvfCirclePatternOptions")?;
    let pins = super::pins_from_options(o.pin_count, o.pin_vertices, o.pin_uv)?;
    if o.max_iterations == 0 {
        return Err(Error::InvalidArgument("max_iterations must be at least 1".into()));
    }
    if o.intrinsic_delaunay > 1 {
        return Err(Error::InvalidArgument(format!(
            "intrinsic_delaunay must be 0 or 1 (got {})",
            o.intrinsic_delaunay
        )));
    }
    if o.convex_boundary > 1 {
        return Err(Error::InvalidArgument(format!("convex_boundary must be 0 or 1 (got {})", o.convex_boundary)));
    }
    let boundary_curvature = if o.boundary_curvature.is_null() {
        None
    } else {
        Some(borrow_slice(o.boundary_curvature, vertex_count, "boundary_curvature")?.to_vec())
    };
    let opts = CirclePatternOptions {
        pins,
        max_iterations: o.max_iterations,
        tolerance: o.tolerance,
        intrinsic_delaunay: o.intrinsic_delaunay == 1,
        boundary_curvature,
        convex_boundary: o.convex_boundary == 1,
    };
    Ok((o, opts))
}

/// Writes `report` when the caller asked for it.
fn write_report(report: &CirclePatternReport, report_out: Option<&SizedOut<UvfCirclePatternReport>>) {
    if let Some(report_out) = report_out {
        let r = report;
        report_out.write(UvfCirclePatternReport {
            struct_size: 0,
            angle_iterations: r.angle_iterations,
            radius_iterations: r.radius_iterations,
            closure_error: r.closure_error,
            non_delaunay_edges: r.non_delaunay_edges,
            max_angle_change: r.max_angle_change,
            intrinsic_flips: r.intrinsic_flips,
            flipped_triangles: r.flipped_triangles,
            radius_span: r.radius_span,
        });
    }
}

/// Conformal map with cone singularities by circle patterns (Kharevych, Springborn & Schröder
/// 2006 §5), for a connected mesh of any genus, closed or with boundary: cone `i` sits at
/// interior vertex `cone_vertices[i]` with curvature `cone_curvature[i]` (2π minus the cone
/// angle, radians; π/2 for a cube corner); the other interior vertices are flat. On a closed
/// mesh the curvatures must sum to 2π χ (4π on a sphere; none needed on a torus:
/// `cone_count` = 0). The mesh is cut through the cones (and its handles), flipped to its
/// intrinsic Delaunay triangulation keeping the cut (with `options->intrinsic_delaunay`), the
/// pattern solved as by `uvf_circle_pattern_map`, and laid out per corner: the two sides of
/// every seam are congruent, and the uv angles around each cone sum to its cone angle.
///
/// `corner_uv_out` receives 6 doubles per triangle (u, v of corners 0, 1, 2); `options` must
/// have `pin_count` 0 (the map is placed by the two farthest boundary vertices of the opened
/// mesh); `options->boundary_curvature` applies to the mesh's own boundary. Returns `UVF_OK`,
/// `UVF_INVALID_ARGUMENT` (a cone off the interior or given twice, curvatures against
/// Gauss–Bonnet, pins), `UVF_INVALID_MESH`, `UVF_UNSUPPORTED_TOPOLOGY` (several components),
/// `UVF_NUMERICAL_FAILURE`, `UVF_CANCELLED`, `UVF_INTERNAL_ERROR`. On failure the outputs are
/// untouched.
///
/// # Safety
/// The arrays must hold the stated number of elements; `report_out` must be NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn uvf_circle_pattern_cone_map(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    cone_vertices: *const u32,
    cone_curvature: *const f64,
    cone_count: usize,
    options: *const UvfCirclePatternOptions,
    corner_uv_out: *mut f64,
    report_out: *mut UvfCirclePatternReport,
) -> UvfStatus {
    unsafe {
        circle_pattern_cone_map_from(
            MeshSource::arrays(positions, vertex_count, triangles, triangle_count),
            cone_vertices,
            cone_curvature,
            cone_count,
            options,
            corner_uv_out,
            report_out,
        )
    }
}

/// `uvf_circle_pattern_cone_map` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_circle_pattern_cone_map`.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_circle_pattern_cone_map(
    mesh: *const super::mesh_handle::UvfMesh,
    cone_vertices: *const u32,
    cone_curvature: *const f64,
    cone_count: usize,
    options: *const UvfCirclePatternOptions,
    corner_uv_out: *mut f64,
    report_out: *mut UvfCirclePatternReport,
) -> UvfStatus {
    unsafe {
        circle_pattern_cone_map_from(
            MeshSource::Handle(mesh),
            cone_vertices,
            cone_curvature,
            cone_count,
            options,
            corner_uv_out,
            report_out,
        )
    }
}

/// `uvf_circle_pattern_cone_map` on either kind of mesh.
///
/// # Safety
/// As for `uvf_circle_pattern_cone_map`.
unsafe fn circle_pattern_cone_map_from(
    source: MeshSource,
    cone_vertices: *const u32,
    cone_curvature: *const f64,
    cone_count: usize,
    options: *const UvfCirclePatternOptions,
    corner_uv_out: *mut f64,
    report_out: *mut UvfCirclePatternReport,
) -> UvfStatus {
    guard(|| {
        let (vertex_count, triangle_count) = unsafe { source.counts() }?;
        // Checked before the work, so that a bad report pointer leaves every output untouched.
        let report_out = unsafe { SizedOut::optional(report_out, "report_out", "UvfCirclePatternReport") }?;
        let (o, opts) = options_from_c(options, vertex_count)?;
        let mesh = unsafe { source.mesh() }?;
        let vertices = borrow_slice(cone_vertices, cone_count, "cone_vertices")?;
        let curvature = borrow_slice(cone_curvature, cone_count, "cone_curvature")?;
        let cones: Vec<(u32, f64)> = vertices.iter().copied().zip(curvature.iter().copied()).collect();
        let out = borrow_slice_mut(corner_uv_out, checked_count(triangle_count, 6, "corner uv")?, "corner_uv_out")?;
        let mut callback = progress_closure(o.progress, o.progress_user);
        let result = circle_pattern_cone_map(&mesh, &cones, &opts, &mut Progress::new(&mut callback))?;
        for (slot, value) in out.iter_mut().zip(result.corner_uv.iter().flatten().flatten()) {
            *slot = *value;
        }
        write_report(&result.report, report_out.as_ref());
        Ok(())
    })
}

/// Fills `curvature_out` (`vertex_count` doubles) with the boundary curvature that makes the
/// longest boundary loop a convex polygon with the `corner_count` ≥ 3 given corner vertices:
/// turning 2π / corner_count at each corner, 0 (straight) at the loop's other vertices, NaN
/// (free) everywhere else. Four corners give a rectangle whose side lengths the map chooses.
/// Pass the result as `UvfCirclePatternOptions::boundary_curvature`.
///
/// Returns `UVF_OK`, `UVF_INVALID_ARGUMENT` (fewer than 3 corners, a corner twice or not on
/// the longest loop, NULL arrays), `UVF_INVALID_MESH`, `UVF_UNSUPPORTED_TOPOLOGY` (no boundary),
/// `UVF_INTERNAL_ERROR`. On failure `curvature_out` is untouched.
///
/// # Safety
/// The arrays must hold the stated number of elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_circle_pattern_polygon_curvature(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    corners: *const u32,
    corner_count: usize,
    curvature_out: *mut f64,
) -> UvfStatus {
    unsafe {
        polygon_curvature_from(
            MeshSource::arrays(positions, vertex_count, triangles, triangle_count),
            corners,
            corner_count,
            curvature_out,
        )
    }
}

/// `uvf_circle_pattern_polygon_curvature` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_circle_pattern_polygon_curvature`.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_circle_pattern_polygon_curvature(
    mesh: *const super::mesh_handle::UvfMesh,
    corners: *const u32,
    corner_count: usize,
    curvature_out: *mut f64,
) -> UvfStatus {
    unsafe { polygon_curvature_from(MeshSource::Handle(mesh), corners, corner_count, curvature_out) }
}

/// `uvf_circle_pattern_polygon_curvature` on either kind of mesh.
///
/// # Safety
/// As for `uvf_circle_pattern_polygon_curvature`.
unsafe fn polygon_curvature_from(
    source: MeshSource,
    corners: *const u32,
    corner_count: usize,
    curvature_out: *mut f64,
) -> UvfStatus {
    guard(|| {
        let (vertex_count, _) = unsafe { source.counts() }?;
        let mesh = unsafe { source.mesh() }?;
        let corners = borrow_slice(corners, corner_count, "corners")?;
        let out = borrow_slice_mut(curvature_out, vertex_count, "curvature_out")?;
        out.copy_from_slice(&polygon_boundary_curvature(&mesh, corners)?);
        Ok(())
    })
}
