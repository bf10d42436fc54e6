//! C ABI of QuadCover (`methods::quadcover`).

use super::pgp::quad_mesh::UvfQuadMesh;
use super::status::UvfStatus;
use super::MeshSource;
use super::SizedOut;
use super::{borrow_slice, borrow_slice_mut, checked_count, guard, progress_closure, read_options, UvfProgressFn};
use std::os::raw::c_void;
use uvflat_core::error::{Error, Result};
use uvflat_core::methods::pgp::isolines::check_density;
use uvflat_core::methods::quadcover::{quad_mesh, quadcover, QuadCoverOptions, QuadCoverResult};
use uvflat_core::progress::Progress;

/// Options of `uvf_quadcover`. Initialise with `uvf_quadcover_options_default`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct UvfQuadCoverOptions {
    /// `sizeof(UvfQuadCoverOptions)`, set by the default initialiser.
    pub struct_size: usize,
    /// Surface length of one grid cell (one unit of u and v); 0 (default): 3 mean edge lengths.
    pub grid_spacing: f64,
    /// Alignment of the default frame field to the principal curvature directions: default 1,
    /// must be positive; larger follows the curvature more closely and gives more cones. Unused
    /// when a field is given.
    pub alignment: f64,
    /// 1 (default): round the gaps and cone positions to integers (seamless grid); 0: return the
    /// continuous solve (the gaps are real numbers).
    pub round: u32,
    /// 1: also put every cone on an integer point (cones become irregular vertices of the
    /// grid, as in mixed-integer quadrangulation); 0 (default): only the gaps are integers, as
    /// in the course notes (fewer folds).
    pub cones_on_grid: u32,
    /// Optional progress callback (may be NULL).
    pub progress: UvfProgressFn,
    /// Passed to `progress` unchanged.
    pub progress_user: *mut c_void,
    /// Cone-pair cancellation distance in grid cells (default 2; 0 keeps the field's cones): ±
    /// cone pairs of the field closer than this are cancelled and cones this close to the
    /// boundary moved onto it, the field re-solved around them, before the cut and the
    /// integration. Fewer clustered cones fold the map less. Must be finite and >= 0.
    pub pair_cells: f64,
    /// 1 (default): after rounding, untangle the folded triangles by moving the regular
    /// vertices near them (Garanzha et al. 2021's untangling energy), keeping every gap, seam
    /// and cone position; 0: return the rounded and stiffened map as it is. Only with `round`.
    pub untangle: u32,
}

/// Size of the first version of `UvfQuadCoverOptions` (without `pair_cells`).
const QUADCOVER_OPTIONS_V1: usize = std::mem::offset_of!(UvfQuadCoverOptions, pair_cells);

impl Default for UvfQuadCoverOptions {
    fn default() -> Self {
        let d = QuadCoverOptions::default();
        UvfQuadCoverOptions {
            struct_size: std::mem::size_of::<Self>(),
            grid_spacing: 0.0,
            alignment: d.alignment,
            round: 1,
            cones_on_grid: 0,
            progress: None,
            progress_user: std::ptr::null_mut(),
            pair_cells: d.pair_cells,
            untangle: u32::from(d.untangle),
        }
    }
}

/// What `uvf_quadcover` reports.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct UvfQuadCoverReport {
    /// `sizeof(UvfQuadCoverReport)`, set by the caller before the call; the library writes only the fields
    /// that fit in that many bytes (see Versioning at the top of the header).
    pub struct_size: usize,
    /// Cone (singular) vertices of the frame field.
    pub cone_count: u32,
    /// Cutting paths (each carries one integer gap).
    pub chain_count: u32,
    /// Triangles whose (u, v) image has non-positive signed area.
    pub flipped_count: u32,
    /// The grid spacing used.
    pub grid_spacing: f64,
    /// Largest distance of a free gap or cone coordinate to an integer before rounding.
    pub rounding_offset: f64,
    /// Largest distance of any gap (with `cones_on_grid`, also cone coordinate) to an integer in
    /// the result.
    pub lattice_error: f64,
    /// Σ A |∇f − K|² / Σ A |K|² after the continuous solve, and in the result.
    pub energy_continuous: f64,
    pub energy: f64,
    /// Cones of the field before the cone-pair cancellation (`cone_count` after it).
    pub cones_before_cancellation: u32,
    /// ± pair moves the cancellation kept (re-matching the field can open cones elsewhere, so
    /// the net change is `cones_before_cancellation − cone_count`).
    pub cancelled_pairs: u32,
    /// Cone-to-boundary moves the cancellation kept.
    pub cones_moved_to_boundary: u32,
    /// Folded triangles before the untangling (`flipped_count` after it; equal when it is off).
    pub flipped_before_untangling: u32,
    /// Folded triangles that no untangling can open: two of their corners are fixed at the same
    /// point by the integer unknowns (e.g. two cones rounded onto one grid point); 0 when
    /// `untangle` is 0.
    pub forced_flat_count: u32,
}

/// Fills `options` with defaults (automatic grid spacing, alignment 1, rounding on, no callback).
///
/// # Safety
/// `options` must be NULL or point to a writable struct.
#[no_mangle]
pub unsafe extern "C" fn uvf_quadcover_options_default(options: *mut UvfQuadCoverOptions) {
    if !options.is_null() {
        options.write(UvfQuadCoverOptions::default());
    }
}

/// QuadCover (Kälberer, Nieser & Polthier 2007; course notes ch. 8): a global parameterization
/// whose integer iso-lines close up over the whole surface, guided by a frame field. Field:
/// `field` (3 doubles per triangle, a tangent vector of each triangle, projected on its plane),
/// or when NULL a smooth cross field aligned with the principal curvature directions. ± cone
/// pairs of the field closer than `pair_cells` grid cells are cancelled and cones that close
/// to the boundary moved onto it (not in the paper; `pair_cells` = 0 keeps the field's cones).
/// The field's matchings (§8.2.1), its cones (vertices of non-zero index), a cut through the cones,
/// the covering's transition functions J^r z + t across the cut (eq. 8.2), the minimizer of
/// ∫|∇f − K|² (eq. 8.6, the Hodge projection of eq. 8.7), then the gaps (and with
/// `cones_on_grid` the cone positions) rounded to integers one at a time (closest first), the
/// map solved again (§8.3.1), folded triangles stiffened, and with `untangle` the folds left
/// untangled by moving the regular vertices near them (gaps, seams and cones kept).
///
/// Any genus, with or without boundary, one connected component. `corner_uv_out` receives
/// (u, v) for every corner in grid units: 6 doubles per triangle, corner k of triangle t at
/// `6t + 2k`; across every interior edge the two triangles' (u, v) differ by a quarter turn and
/// an integer translation (and, with `cones_on_grid`, every cone is on an integer point).
/// `cone_index_out` (may be NULL) receives 1 int32 per vertex: 4 × the
/// field's index at cones (±1 for ±¼), 0 elsewhere. The map may fold near cones closer than a
/// grid cell or two (reported in `flipped_count`). `options` and `report_out` may be NULL.
///
/// Returns `UVF_OK`, `UVF_INVALID_ARGUMENT` (bad options; a field vector that is not finite
/// or normal to its triangle — the message names it; a surface without anisotropic curvature
/// and no field), `UVF_INVALID_MESH`, `UVF_UNSUPPORTED_TOPOLOGY` (several components),
/// `UVF_NUMERICAL_FAILURE`, `UVF_CANCELLED`, `UVF_INTERNAL_ERROR`. On failure the outputs are
/// untouched.
///
/// # Safety
/// The arrays must hold the stated number of elements (`field` NULL or 3 per triangle);
/// `report_out` must be NULL or writable.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn uvf_quadcover(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    options: *const UvfQuadCoverOptions,
    field: *const f64,
    corner_uv_out: *mut f64,
    cone_index_out: *mut i32,
    report_out: *mut UvfQuadCoverReport,
) -> UvfStatus {
    unsafe {
        quadcover_from(
            MeshSource::arrays(positions, vertex_count, triangles, triangle_count),
            options,
            field,
            corner_uv_out,
            cone_index_out,
            report_out,
        )
    }
}

/// `uvf_quadcover` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_quadcover`.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn uvf_mesh_quadcover(
    mesh: *const super::mesh_handle::UvfMesh,
    options: *const UvfQuadCoverOptions,
    field: *const f64,
    corner_uv_out: *mut f64,
    cone_index_out: *mut i32,
    report_out: *mut UvfQuadCoverReport,
) -> UvfStatus {
    unsafe { quadcover_from(MeshSource::Handle(mesh), options, field, corner_uv_out, cone_index_out, report_out) }
}

/// `uvf_quadcover` on either kind of mesh.
///
/// # Safety
/// As for `uvf_quadcover`.
#[allow(clippy::too_many_arguments)]
unsafe fn quadcover_from(
    source: MeshSource,
    options: *const UvfQuadCoverOptions,
    field: *const f64,
    corner_uv_out: *mut f64,
    cone_index_out: *mut i32,
    report_out: *mut UvfQuadCoverReport,
) -> UvfStatus {
    guard(|| {
        let (vertex_count, triangle_count) = unsafe { source.counts() }?;
        // Checked before the work, so that a bad report pointer leaves every output untouched.
        let report_out = unsafe { SizedOut::optional(report_out, "report_out", "UvfQuadCoverReport") }?;
        let (opts, progress, progress_user) = options_from_c(options, field, triangle_count)?;
        let mesh = unsafe { source.mesh() }?;
        // Checked before the work so that a bad output pointer leaves everything untouched.
        let uv = borrow_slice_mut(corner_uv_out, checked_count(triangle_count, 6, "corner")?, "corner_uv_out")?;
        let cones = if cone_index_out.is_null() {
            None
        } else {
            Some(borrow_slice_mut(cone_index_out, vertex_count, "cone_index_out")?)
        };
        let mut callback = progress_closure(progress, progress_user);
        let result = quadcover(&mesh, &opts, &mut Progress::new(&mut callback))?;
        for (d, c) in uv.chunks_exact_mut(6).zip(&result.uv) {
            d.copy_from_slice(c.as_flattened());
        }
        if let Some(out) = cones {
            out.fill(0);
            for &(v, index) in &result.cones {
                out[v as usize] = (4.0 * index).round() as i32;
            }
        }
        write_report(report_out.as_ref(), &result);
        Ok(())
    })
}

/// The integer grid lines of a QuadCover map (run as `uvf_quadcover` does, same `options`,
/// `field` and `report_out`) as a polygon mesh on the input surface: the lines u, v ∈ ℤ /
/// `density` (a whole number ≥ 1; 1: one quad per grid cell), traced exactly and joined across
/// every seam of the map; its faces are the faces of the line graph, those that are not quads
/// (around cones, next to folded triangles and on the boundary) split into quads and at most
/// one triangle. Where the map has no cone and no fold every face is a quad, one per grid cell;
/// with `cones_on_grid` the faces around cones are mostly quads as well.
///
/// Returns `UVF_OK` (a handle in `*mesh_out`, read it with `uvf_quad_mesh_info` and
/// `uvf_quad_mesh_copy`, free it with `uvf_quad_mesh_free`) or the errors of `uvf_quadcover`
/// (a bad density or a NULL `mesh_out`: `UVF_INVALID_ARGUMENT`, before any work). On failure
/// `*mesh_out` and `report_out` are untouched.
///
/// # Safety
/// As `uvf_quadcover`; `mesh_out` must be NULL or writable.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn uvf_quadcover_quad_mesh(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    options: *const UvfQuadCoverOptions,
    field: *const f64,
    density: f64,
    mesh_out: *mut *mut UvfQuadMesh,
    report_out: *mut UvfQuadCoverReport,
) -> UvfStatus {
    unsafe {
        quadcover_quad_mesh_from(
            MeshSource::arrays(positions, vertex_count, triangles, triangle_count),
            options,
            field,
            density,
            mesh_out,
            report_out,
        )
    }
}

/// `uvf_quadcover_quad_mesh` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_quadcover_quad_mesh`.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn uvf_mesh_quadcover_quad_mesh(
    mesh: *const super::mesh_handle::UvfMesh,
    options: *const UvfQuadCoverOptions,
    field: *const f64,
    density: f64,
    mesh_out: *mut *mut UvfQuadMesh,
    report_out: *mut UvfQuadCoverReport,
) -> UvfStatus {
    unsafe { quadcover_quad_mesh_from(MeshSource::Handle(mesh), options, field, density, mesh_out, report_out) }
}

/// `uvf_quadcover_quad_mesh` on either kind of mesh.
///
/// # Safety
/// As for `uvf_quadcover_quad_mesh`.
#[allow(clippy::too_many_arguments)]
unsafe fn quadcover_quad_mesh_from(
    source: MeshSource,
    options: *const UvfQuadCoverOptions,
    field: *const f64,
    density: f64,
    mesh_out: *mut *mut UvfQuadMesh,
    report_out: *mut UvfQuadCoverReport,
) -> UvfStatus {
    guard(|| {
        let (_, triangle_count) = unsafe { source.counts() }?;
        // Checked before the work, so that a bad report pointer leaves every output untouched.
        let report_out = unsafe { SizedOut::optional(report_out, "report_out", "UvfQuadCoverReport") }?;
        let (opts, progress, progress_user) = options_from_c(options, field, triangle_count)?;
        check_density(density)?;
        let slot = borrow_slice_mut(mesh_out, 1, "mesh_out")?;
        let mesh = unsafe { source.mesh() }?;
        let mut callback = progress_closure(progress, progress_user);
        let result = quadcover(&mesh, &opts, &mut Progress::new(&mut callback))?;
        let quads = quad_mesh(&mesh, &result, density)?;
        slot[0] = Box::into_raw(Box::new(UvfQuadMesh { mesh: quads }));
        write_report(report_out.as_ref(), &result);
        Ok(())
    })
}

/// The Rust options (and the progress callback) of a C options struct and field.
///
/// # Safety
/// `options` NULL or a readable struct; `field` NULL or 3 doubles per triangle.
unsafe fn options_from_c(
    options: *const UvfQuadCoverOptions,
    field: *const f64,
    triangle_count: usize,
) -> Result<(QuadCoverOptions, UvfProgressFn, *mut c_void)> {
    let o = read_options(options, UvfQuadCoverOptions::default(), QUADCOVER_OPTIONS_V1, "UvfQuadCoverOptions")?;
    if !(o.grid_spacing.is_finite() && o.grid_spacing >= 0.0) {
        return Err(Error::InvalidArgument(format!(
            "grid_spacing must be finite and >= 0 (0: automatic; got {})",
            o.grid_spacing
        )));
    }
    if o.round > 1 || o.cones_on_grid > 1 || o.untangle > 1 {
        return Err(Error::InvalidArgument(format!(
            "round, cones_on_grid and untangle must be 0 or 1 (got {}, {} and {})",
            o.round, o.cones_on_grid, o.untangle
        )));
    }
    if !(o.pair_cells.is_finite() && o.pair_cells >= 0.0) {
        return Err(Error::InvalidArgument(format!("pair_cells must be finite and >= 0 (got {})", o.pair_cells)));
    }
    let field = if field.is_null() {
        None
    } else {
        let f = borrow_slice(field, checked_count(triangle_count, 3, "field")?, "field")?;
        Some(f.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
    };
    let opts = QuadCoverOptions {
        grid_spacing: (o.grid_spacing > 0.0).then_some(o.grid_spacing),
        field,
        alignment: o.alignment,
        round: o.round == 1,
        cones_on_grid: o.cones_on_grid == 1,
        pair_cells: o.pair_cells,
        untangle: o.untangle == 1,
        ..QuadCoverOptions::default()
    };
    Ok((opts, o.progress, o.progress_user))
}

/// Writes the report of `result` when the caller asked for it.
fn write_report(report_out: Option<&SizedOut<UvfQuadCoverReport>>, result: &QuadCoverResult) {
    if let Some(report_out) = report_out {
        report_out.write(UvfQuadCoverReport {
            struct_size: 0,
            cone_count: result.cones.len() as u32,
            chain_count: result.chains as u32,
            flipped_count: result.flipped as u32,
            grid_spacing: result.grid_spacing,
            rounding_offset: result.rounding_offset,
            lattice_error: result.lattice_error,
            energy_continuous: result.energy_continuous,
            energy: result.energy,
            cones_before_cancellation: result.cone_pairs.cones_before as u32,
            cancelled_pairs: result.cone_pairs.pairs as u32,
            cones_moved_to_boundary: result.cone_pairs.moved_to_boundary as u32,
            flipped_before_untangling: if result.untangled == Default::default() {
                result.flipped as u32
            } else {
                result.untangled.folded_before as u32
            },
            forced_flat_count: result.untangled.forced_flat as u32,
        });
    }
}
