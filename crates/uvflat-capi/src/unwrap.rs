//! The default unwrap through the C ABI: `uvf_unwrap` runs the whole pipeline (`uvflat_core::unwrap`)
//! and returns a handle holding the packed, verified layout (read with the `uvf_atlas_*`
//! accessors through `uvf_unwrap_atlas`), the seams and the report.

use super::atlas::{UvfAtlas, UVF_ATLAS_CHART_MEAN_VALUE, UVF_ATLAS_CHART_NATURAL_CONFORMAL};
use super::atlas::{UVF_ATLAS_CHART_SLIM, UVF_ATLAS_CHART_STRETCH};
use super::status::UvfStatus;
use super::MeshSource;
use super::SizedOut;
use super::{
    borrow_slice, borrow_slice_mut, checked_count, copy_out, guard, progress_closure, read_options, UvfProgressFn,
};
use std::os::raw::c_void;
use uvflat_core::atlas::ChartMethod;
use uvflat_core::error::{Error, Result};
use uvflat_core::progress::Progress;
use uvflat_core::unwrap::{unwrap_arrays, unwrap_with_progress, UnwrapOptions, UnwrapReport};

/// Options of `uvf_unwrap`. Initialise with `uvf_unwrap_options_default`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct UvfUnwrapOptions {
    /// `sizeof(UvfUnwrapOptions)`, set by the default initialiser.
    pub struct_size: usize,
    /// Largest L2 stretch of an island, ≥ 1 (default 1.5); `INFINITY` turns the bound off:
    /// every connected component stays one island (split only if no valid layout is found).
    pub max_stretch: f64,
    /// Gap between islands in the unit square, in [0, 0.5) (default 0.005).
    pub margin: f64,
    /// How islands are flattened before verification: one of `UVF_ATLAS_CHART_*` (default
    /// natural conformal).
    pub method: u32,
    /// Iteration limit of the non-linear solves, the bijective repair included (default 100).
    pub iterations: u32,
    /// Non-zero: the packer may rotate islands (default 1).
    pub rotate: u32,
    /// Optional progress callback (may be NULL); returning non-zero cancels with
    /// `UVF_CANCELLED`.
    pub progress: UvfProgressFn,
    /// Passed to `progress` unchanged.
    pub progress_user: *mut c_void,
}

impl Default for UvfUnwrapOptions {
    fn default() -> Self {
        let d = UnwrapOptions::default();
        UvfUnwrapOptions {
            struct_size: std::mem::size_of::<Self>(),
            max_stretch: d.max_stretch,
            margin: d.margin,
            method: UVF_ATLAS_CHART_NATURAL_CONFORMAL,
            iterations: d.iterations as u32,
            rotate: d.rotate as u32,
            progress: None,
            progress_user: std::ptr::null_mut(),
        }
    }
}

/// What `uvf_unwrap` did, measured on its result. The caller sets `struct_size` (to
/// `sizeof(UvfUnwrapReport)`); `uvf_unwrap_report` writes only that many bytes, so a caller
/// built against an older, shorter struct keeps working when fields are appended.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct UvfUnwrapReport {
    /// `sizeof(UvfUnwrapReport)`, set by the caller.
    pub struct_size: usize,
    /// Islands of the layout.
    pub islands: usize,
    /// Islands the method could not lay out validly, laid out by bijective SLIM instead.
    pub repaired_islands: usize,
    /// Input edges cut (see `uvf_unwrap_copy_seams`).
    pub seam_edges: usize,
    /// UV vertices (one per island vertex).
    pub uv_vertex_count: usize,
    /// Flipped or degenerate UV triangles, by the independent exact checker (always 0).
    pub flipped: usize,
    /// Touching boundary-edge pairs and nested islands, by the same checker (always 0).
    pub overlaps: usize,
    /// L2 stretch of the whole layout (Sander et al. 2001; 1 = isometric up to scale).
    pub stretch_l2: f64,
    /// Largest L2 stretch of one island.
    pub max_island_stretch: f64,
    /// Mean angle distortion over corners, in degrees.
    pub angle_error_mean_deg: f64,
    /// Fraction of the unit square covered by islands.
    pub utilization: f64,
    /// Input vertices welded onto another for the solve: snapped together but not merged
    /// (`uvf_unwrap` only; a mesh handle cannot hold them).
    pub welded_vertices: usize,
    /// Zero-area input triangles left out of the solve and the verification (`uvf_unwrap` only);
    /// each gets UVs of its vertices, of zero area where its corners were welded.
    pub left_out_triangles: usize,
}

/// The result of `uvf_unwrap`: released with `uvf_unwrap_free`.
pub struct UvfUnwrap {
    layout: UvfAtlas,
    seams: Vec<u32>,
    report: UvfUnwrapReport,
}

/// Fills `options` with defaults.
///
/// # Safety
/// `options` must be NULL or point to a writable struct.
#[no_mangle]
pub unsafe extern "C" fn uvf_unwrap_options_default(options: *mut UvfUnwrapOptions) {
    if !options.is_null() {
        options.write(UvfUnwrapOptions::default());
    }
}

const UNWRAP_OPTIONS_V1: usize = std::mem::size_of::<UvfUnwrapOptions>();

fn chart_method(code: u32) -> Result<ChartMethod> {
    Ok(match code {
        UVF_ATLAS_CHART_NATURAL_CONFORMAL => ChartMethod::NaturalConformal,
        UVF_ATLAS_CHART_MEAN_VALUE => ChartMethod::MeanValue,
        UVF_ATLAS_CHART_SLIM => ChartMethod::Slim,
        UVF_ATLAS_CHART_STRETCH => ChartMethod::Stretch,
        m => return Err(Error::InvalidArgument(format!("unknown method {m}; use one of UVF_ATLAS_CHART_*"))),
    })
}

fn report_of(r: &UnwrapReport, uv_vertex_count: usize) -> UvfUnwrapReport {
    UvfUnwrapReport {
        struct_size: std::mem::size_of::<UvfUnwrapReport>(),
        islands: r.islands,
        repaired_islands: r.repaired_islands,
        seam_edges: r.seam_edges,
        uv_vertex_count,
        flipped: r.flipped,
        overlaps: r.overlaps,
        stretch_l2: r.stretch_l2,
        max_island_stretch: r.max_island_stretch,
        angle_error_mean_deg: r.angle_error_mean_deg,
        utilization: r.utilization,
        welded_vertices: r.welded_vertices,
        left_out_triangles: r.left_out_triangles,
    }
}

/// UVs for any manifold mesh in one call — disk, holes, closed, any genus, several
/// components: every component starts as one island (cut into a disk by a tree–cotree cut when
/// closed or with handles), flattened by `method`; an island whose map flips a triangle or
/// overlaps its boundary is laid out again by bijective SLIM (a scaffold around the free
/// boundary, Jiang et al. 2017), and one over `max_stretch` is split in two (VSA on normals)
/// until every piece is valid under the bound; adjacent islands are merged back where still
/// valid, then all are packed into the unit square at one texel density.
///
/// Zero-area triangles (vertices snapped together but not merged, collinear corners), which
/// `uvf_mesh_info` and the methods refuse, are accepted here: in each, the ends of an edge
/// shorter than 1e-6 of its longest are welded for the solve, and the triangles still of zero
/// area are left out of the solve and the verification, each getting the UVs of its vertices
/// (`uvf_snapped_repair`; the report counts both). A group of welded vertices is then named by
/// its lowest input vertex in the original vertices and the seams.
///
/// The result is verified with an exact checker independent of the method: no flipped or
/// degenerate UV triangle, no overlap within or between islands, every UV finite and in
/// [0, 1]² — a layout failing that is returned as `UVF_INTERNAL_ERROR`, never as a result.
/// On success `*unwrap_out` receives a handle to free with `uvf_unwrap_free`; `options` may be
/// NULL. Returns `UVF_OK`, `UVF_INVALID_ARGUMENT` (NULL pointer, bad option),
/// `UVF_INVALID_MESH`, `UVF_NUMERICAL_FAILURE` (a triangle too degenerate to lay out alone),
/// `UVF_CANCELLED`, `UVF_INTERNAL_ERROR`; on failure `*unwrap_out` is untouched.
///
/// # Safety
/// The arrays must hold the stated number of elements; `unwrap_out` must be writable.
#[no_mangle]
pub unsafe extern "C" fn uvf_unwrap(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    options: *const UvfUnwrapOptions,
    unwrap_out: *mut *mut UvfUnwrap,
) -> UvfStatus {
    unsafe { unwrap_from(MeshSource::arrays(positions, vertex_count, triangles, triangle_count), options, unwrap_out) }
}

/// `uvf_unwrap` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_unwrap`.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_unwrap(
    mesh: *const super::mesh_handle::UvfMesh,
    options: *const UvfUnwrapOptions,
    unwrap_out: *mut *mut UvfUnwrap,
) -> UvfStatus {
    unsafe { unwrap_from(MeshSource::Handle(mesh), options, unwrap_out) }
}

/// `uvf_unwrap` on either kind of mesh.
///
/// # Safety
/// As for `uvf_unwrap`.
unsafe fn unwrap_from(
    source: MeshSource,
    options: *const UvfUnwrapOptions,
    unwrap_out: *mut *mut UvfUnwrap,
) -> UvfStatus {
    guard(|| {
        let out = borrow_slice_mut(unwrap_out, 1, "unwrap_out")?;
        let o = read_options(options, UvfUnwrapOptions::default(), UNWRAP_OPTIONS_V1, "UvfUnwrapOptions")?;
        let options = UnwrapOptions {
            max_stretch: o.max_stretch,
            margin: o.margin,
            method: chart_method(o.method)?,
            iterations: o.iterations as usize,
            rotate: o.rotate != 0,
        };
        let mut callback = progress_closure(o.progress, o.progress_user);
        let mut progress = Progress::new(&mut callback);
        let result = match source {
            // Flat arrays may hold zero-area triangles (snapped vertices): welded for the solve.
            MeshSource::Arrays { positions, vertex_count, triangles, triangle_count } => {
                let p = borrow_slice(positions, checked_count(vertex_count, 3, "vertex")?, "positions")?;
                let t = borrow_slice(triangles, checked_count(triangle_count, 3, "triangle")?, "triangles")?;
                unwrap_arrays(p, t, &options, &mut progress)?
            }
            MeshSource::Handle(_) => unwrap_with_progress(&*unsafe { source.mesh() }?, &options, &mut progress)?,
        };
        let report = report_of(&result.report, result.atlas.uv.len());
        let seams = result.seams.iter().flatten().copied().collect();
        out[0] = Box::into_raw(Box::new(UvfUnwrap { layout: UvfAtlas::new(result.atlas), seams, report }));
        Ok(())
    })
}

/// Borrows the handle, rejecting NULL.
unsafe fn handle<'a>(unwrap: *const UvfUnwrap) -> Result<&'a UvfUnwrap> {
    // SAFETY: the caller passes a handle from `uvf_unwrap` not yet freed, or NULL.
    unsafe { unwrap.as_ref() }.ok_or_else(|| Error::InvalidArgument("unwrap handle is NULL".into()))
}

/// The report of an unwrap, written into `report_out` up to `report_out->struct_size` bytes
/// (which the caller sets, at least the size of its first two fields). Returns `UVF_OK` or
/// `UVF_INVALID_ARGUMENT` (NULL, `struct_size` too small; nothing written).
///
/// # Safety
/// `unwrap` must be a live handle or NULL; `report_out` must be NULL or point to at least
/// `report_out->struct_size` writable bytes.
#[no_mangle]
pub unsafe extern "C" fn uvf_unwrap_report(unwrap: *const UvfUnwrap, report_out: *mut UvfUnwrapReport) -> UvfStatus {
    guard(|| {
        let u = unsafe { handle(unwrap) }?;
        unsafe { SizedOut::required(report_out, "report_out", "UvfUnwrapReport") }?.write(u.report);
        Ok(())
    })
}

/// The packed layout as an atlas handle, read with `uvf_atlas_info`, `uvf_atlas_copy_uv`,
/// `uvf_atlas_copy_triangles` (per-corner UV indices), `uvf_atlas_copy_corner_uv`,
/// `uvf_atlas_copy_charts` (island per triangle) and `uvf_atlas_copy_original_vertices`. It
/// belongs to the unwrap handle: valid until `uvf_unwrap_free`, and never passed to
/// `uvf_atlas_free`. Returns `UVF_OK` or `UVF_INVALID_ARGUMENT` (NULL).
///
/// # Safety
/// `unwrap` must be a live handle or NULL; `atlas_out` writable.
#[no_mangle]
pub unsafe extern "C" fn uvf_unwrap_atlas(unwrap: *const UvfUnwrap, atlas_out: *mut *const UvfAtlas) -> UvfStatus {
    guard(|| {
        let u = unsafe { handle(unwrap) }?;
        borrow_slice_mut(atlas_out, 1, "atlas_out")?[0] = &u.layout;
        Ok(())
    })
}

/// The cut input edges: `2 × seam_edges` input vertex indices, pairs `a < b`, sorted. Returns
/// `UVF_OK` or `UVF_INVALID_ARGUMENT` (NULL, capacity too small; output untouched).
///
/// # Safety
/// `unwrap` must be a live handle or NULL; `seams_out` must hold `capacity` elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_unwrap_copy_seams(
    unwrap: *const UvfUnwrap,
    seams_out: *mut u32,
    capacity: usize,
) -> UvfStatus {
    guard(|| {
        let u = unsafe { handle(unwrap) }?;
        copy_out(&u.seams, seams_out, capacity, "seams_out")
    })
}

/// Releases an unwrap handle and its layout (NULL is ignored).
///
/// # Safety
/// `unwrap` must come from `uvf_unwrap` and not have been freed.
#[no_mangle]
pub unsafe extern "C" fn uvf_unwrap_free(unwrap: *mut UvfUnwrap) {
    if !unwrap.is_null() {
        let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            // SAFETY: the pointer came from Box::into_raw in `uvf_unwrap`.
            drop(unsafe { Box::from_raw(unwrap) });
        }));
    }
}
