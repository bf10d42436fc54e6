//! Atlas mode through the C ABI: `uvf_atlas` computes charts under a stretch bound, flattens and
//! packs them, and returns a result handle read with the `uvf_atlas_*` accessors.

use super::status::UvfStatus;
use super::MeshSource;
use super::SizedOut;
use super::{borrow_slice_mut, copy_out, guard, progress_closure, read_options, UvfProgressFn};
use std::os::raw::c_void;
use uvflat_core::atlas::{atlas_with_progress, Atlas, AtlasOptions, ChartMethod};
use uvflat_core::error::{Error, Result};
use uvflat_core::progress::Progress;

/// Charts flattened by the natural conformal map / LSCM (the default; charts that flip are split).
pub const UVF_ATLAS_CHART_NATURAL_CONFORMAL: u32 = 0;
/// Charts flattened by the mean value map on a circle (never flips).
pub const UVF_ATLAS_CHART_MEAN_VALUE: u32 = 1;
/// Charts flattened by SLIM from the natural conformal map (or mean value) start; never flips.
pub const UVF_ATLAS_CHART_SLIM: u32 = 2;
/// Charts flattened by minimizing Sander's L2 stretch from the same start; never flips.
pub const UVF_ATLAS_CHART_STRETCH: u32 = 3;

/// Options of `uvf_atlas`. Initialise with `uvf_atlas_options_default`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct UvfAtlasOptions {
    /// `sizeof(UvfAtlasOptions)`, set by the default initialiser.
    pub struct_size: usize,
    /// Largest L2 stretch of a chart, ≥ 1 (default 1.004); `INFINITY` splits only charts that
    /// flip or overlap.
    pub max_stretch: f64,
    /// Gap between charts in the unit square, in [0, 0.5) (default 0.005); refused with
    /// `UVF_INVALID_ARGUMENT` when the gaps alone would take more than a quarter of the square
    /// (charts · margin² > 0.25).
    pub margin: f64,
    /// One of `UVF_ATLAS_CHART_*` (default natural conformal).
    pub method: u32,
    /// Iterations of the non-linear chart methods (default 20).
    pub iterations: u32,
    /// Non-zero: the packer may rotate charts (default 1).
    pub rotate: u32,
    /// Non-zero: merge adjacent charts after splitting when still valid (default 1).
    pub merge: u32,
    /// L2-stretch minimization iterations per chart (default 10; 0: none): a chart slightly
    /// over `max_stretch` is polished before it is judged, and every accepted chart is polished
    /// before packing (kept only where it lowers the chart's stretch and stays valid).
    pub polish_iterations: u32,
    /// Optional progress callback (may be NULL), called between segmentation levels; returning
    /// non-zero cancels with `UVF_CANCELLED`.
    pub progress: UvfProgressFn,
    /// Passed to `progress` unchanged.
    pub progress_user: *mut c_void,
}

impl Default for UvfAtlasOptions {
    fn default() -> Self {
        let d = AtlasOptions::default();
        UvfAtlasOptions {
            struct_size: std::mem::size_of::<Self>(),
            max_stretch: d.max_stretch,
            margin: d.margin,
            method: UVF_ATLAS_CHART_NATURAL_CONFORMAL,
            iterations: d.iterations as u32,
            rotate: d.rotate as u32,
            merge: d.merge as u32,
            polish_iterations: d.polish as u32,
            progress: None,
            progress_user: std::ptr::null_mut(),
        }
    }
}

/// Sizes and figures of an atlas (see `uvf_atlas_info`).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct UvfAtlasInfo {
    /// `sizeof(UvfAtlasInfo)`, set by the caller before the call; the library writes only the fields
    /// that fit in that many bytes (see Versioning at the top of the header).
    pub struct_size: usize,
    /// Atlas (UV) vertices: one per chart vertex.
    pub vertex_count: usize,
    /// Triangles (the input's, same order).
    pub triangle_count: usize,
    /// Charts.
    pub chart_count: usize,
    /// Fraction of the unit square covered by charts.
    pub utilization: f64,
    /// L2 stretch of the whole atlas (Sander et al. 2001; 1 = isometric up to scale).
    pub stretch_l2: f64,
    /// Largest L2 stretch of one chart.
    pub max_chart_stretch: f64,
}

/// A packed atlas: created by `uvf_atlas`, read with the `uvf_atlas_*` accessors, released with
/// `uvf_atlas_free`.
pub struct UvfAtlas {
    atlas: Atlas,
    info: UvfAtlasInfo,
}

impl UvfAtlas {
    /// The handle's contents for a computed atlas.
    pub(crate) fn new(atlas: Atlas) -> Self {
        let info = UvfAtlasInfo {
            struct_size: 0,
            vertex_count: atlas.uv.len(),
            triangle_count: atlas.triangles.len(),
            chart_count: atlas.charts.len(),
            utilization: atlas.utilization,
            stretch_l2: atlas.stretch_l2,
            max_chart_stretch: atlas.charts.iter().map(|c| c.stretch_l2).fold(0.0, f64::max),
        };
        UvfAtlas { atlas, info }
    }
}

/// Fills `options` with defaults.
///
/// # Safety
/// `options` must be NULL or point to a writable struct.
#[no_mangle]
pub unsafe extern "C" fn uvf_atlas_options_default(options: *mut UvfAtlasOptions) {
    if !options.is_null() {
        options.write(UvfAtlasOptions::default());
    }
}

const ATLAS_OPTIONS_V1: usize = std::mem::size_of::<UvfAtlasOptions>();

/// Atlas of any manifold mesh (closed or with boundaries, any genus, any number of components;
/// course notes §6.2): top-down segmentation — every component starts as one chart, cut into a
/// disk if needed, flattened by the chosen method, and split in two (two-proxy VSA on normals,
/// Cohen-Steiner et al. 2004) while it flips, overlaps itself or exceeds `max_stretch` — then
/// greedy merging of adjacent charts that stay valid, then skyline packing of the charts'
/// minimum-area rectangles into the unit square with `margin` between charts.
///
/// Every chart of the result has no flipped or degenerate UV triangle, no crossing boundary
/// edges and L2 stretch ≤ `max_stretch`; charts do not overlap; all UVs are in [0, 1]². On
/// success `*atlas_out` receives a handle to free with `uvf_atlas_free`. `options` and
/// `progress` may be NULL. Returns `UVF_OK`, `UVF_INVALID_ARGUMENT` (NULL pointer, bad option),
/// `UVF_INVALID_MESH`, `UVF_NUMERICAL_FAILURE` (a triangle too degenerate to flatten alone),
/// `UVF_CANCELLED`, `UVF_INTERNAL_ERROR`. On failure `*atlas_out` is untouched.
///
/// # Safety
/// The arrays must hold the stated number of elements; `atlas_out` must be writable.
#[no_mangle]
pub unsafe extern "C" fn uvf_atlas(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    options: *const UvfAtlasOptions,
    atlas_out: *mut *mut UvfAtlas,
) -> UvfStatus {
    unsafe { atlas_from(MeshSource::arrays(positions, vertex_count, triangles, triangle_count), options, atlas_out) }
}

/// `uvf_atlas` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_atlas`.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_atlas(
    mesh: *const super::mesh_handle::UvfMesh,
    options: *const UvfAtlasOptions,
    atlas_out: *mut *mut UvfAtlas,
) -> UvfStatus {
    unsafe { atlas_from(MeshSource::Handle(mesh), options, atlas_out) }
}

/// `uvf_atlas` on either kind of mesh.
///
/// # Safety
/// As for `uvf_atlas`.
unsafe fn atlas_from(source: MeshSource, options: *const UvfAtlasOptions, atlas_out: *mut *mut UvfAtlas) -> UvfStatus {
    guard(|| {
        let out = borrow_slice_mut(atlas_out, 1, "atlas_out")?;
        let o = read_options(options, UvfAtlasOptions::default(), ATLAS_OPTIONS_V1, "UvfAtlasOptions")?;
        let method = match o.method {
            UVF_ATLAS_CHART_NATURAL_CONFORMAL => ChartMethod::NaturalConformal,
            UVF_ATLAS_CHART_MEAN_VALUE => ChartMethod::MeanValue,
            UVF_ATLAS_CHART_SLIM => ChartMethod::Slim,
            UVF_ATLAS_CHART_STRETCH => ChartMethod::Stretch,
            m => {
                return Err(Error::InvalidArgument(format!(
                    "unknown atlas chart method {m}; use one of UVF_ATLAS_CHART_*"
                )))
            }
        };
        let mesh = unsafe { source.mesh() }?;
        let options = AtlasOptions {
            max_stretch: o.max_stretch,
            margin: o.margin,
            method,
            iterations: o.iterations as usize,
            rotate: o.rotate != 0,
            merge: o.merge != 0,
            polish: o.polish_iterations as usize,
            repair: false,
        };
        let mut callback = progress_closure(o.progress, o.progress_user);
        let atlas = atlas_with_progress(&mesh, &options, &mut Progress::new(&mut callback))?;
        out[0] = Box::into_raw(Box::new(UvfAtlas::new(atlas)));
        Ok(())
    })
}

/// Borrows the handle, rejecting NULL.
unsafe fn handle<'a>(atlas: *const UvfAtlas) -> Result<&'a UvfAtlas> {
    // SAFETY: the caller passes a handle from `uvf_atlas` not yet freed, or NULL.
    unsafe { atlas.as_ref() }.ok_or_else(|| Error::InvalidArgument("atlas handle is NULL".into()))
}

/// Sizes and figures of an atlas. Returns `UVF_OK` or `UVF_INVALID_ARGUMENT` (NULL).
///
/// # Safety
/// `atlas` must be a live handle or NULL; `info_out` writable.
#[no_mangle]
pub unsafe extern "C" fn uvf_atlas_info(atlas: *const UvfAtlas, info_out: *mut UvfAtlasInfo) -> UvfStatus {
    guard(|| {
        let a = unsafe { handle(atlas) }?;
        unsafe { SizedOut::required(info_out, "info_out", "UvfAtlasInfo") }?.write(a.info);
        Ok(())
    })
}

/// UV of every atlas vertex: `2 × vertex_count` doubles in [0, 1] written to `uv_out` (capacity
/// in doubles). Returns `UVF_OK` or `UVF_INVALID_ARGUMENT` (NULL, capacity too small; output
/// untouched).
///
/// # Safety
/// `atlas` must be a live handle or NULL; `uv_out` must hold `capacity` elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_atlas_copy_uv(atlas: *const UvfAtlas, uv_out: *mut f64, capacity: usize) -> UvfStatus {
    guard(|| {
        let a = unsafe { handle(atlas) }?;
        let flat: Vec<f64> = a.atlas.uv.iter().flatten().copied().collect();
        copy_out(&flat, uv_out, capacity, "uv_out")
    })
}

/// Per-corner UV indices: `3 × triangle_count` atlas-vertex indices (corner k of input triangle
/// t at `3t + k`). Statuses as `uvf_atlas_copy_uv`.
///
/// # Safety
/// `atlas` must be a live handle or NULL; `triangles_out` must hold `capacity` elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_atlas_copy_triangles(
    atlas: *const UvfAtlas,
    triangles_out: *mut u32,
    capacity: usize,
) -> UvfStatus {
    guard(|| {
        let a = unsafe { handle(atlas) }?;
        let flat: Vec<u32> = a.atlas.triangles.iter().flatten().copied().collect();
        copy_out(&flat, triangles_out, capacity, "triangles_out")
    })
}

/// Per-corner UVs: `6 × triangle_count` doubles (u, v of corner k of triangle t at
/// `6t + 2k`). Statuses as `uvf_atlas_copy_uv`.
///
/// # Safety
/// `atlas` must be a live handle or NULL; `corner_uv_out` must hold `capacity` elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_atlas_copy_corner_uv(
    atlas: *const UvfAtlas,
    corner_uv_out: *mut f64,
    capacity: usize,
) -> UvfStatus {
    guard(|| {
        let a = unsafe { handle(atlas) }?;
        let flat: Vec<f64> = a.atlas.corner_uv().iter().flatten().flatten().copied().collect();
        copy_out(&flat, corner_uv_out, capacity, "corner_uv_out")
    })
}

/// Chart id of every input triangle: `triangle_count` entries in `[0, chart_count)`. Statuses
/// as `uvf_atlas_copy_uv`.
///
/// # Safety
/// `atlas` must be a live handle or NULL; `charts_out` must hold `capacity` elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_atlas_copy_charts(
    atlas: *const UvfAtlas,
    charts_out: *mut u32,
    capacity: usize,
) -> UvfStatus {
    guard(|| {
        let a = unsafe { handle(atlas) }?;
        copy_out(&a.atlas.chart_of_triangle, charts_out, capacity, "charts_out")
    })
}

/// The input vertex of every atlas vertex: `vertex_count` entries. Statuses as
/// `uvf_atlas_copy_uv`.
///
/// # Safety
/// `atlas` must be a live handle or NULL; `original_out` must hold `capacity` elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_atlas_copy_original_vertices(
    atlas: *const UvfAtlas,
    original_out: *mut u32,
    capacity: usize,
) -> UvfStatus {
    guard(|| {
        let a = unsafe { handle(atlas) }?;
        copy_out(&a.atlas.original, original_out, capacity, "original_out")
    })
}

/// Releases an atlas handle (NULL is ignored).
///
/// # Safety
/// `atlas` must come from `uvf_atlas` and not have been freed.
#[no_mangle]
pub unsafe extern "C" fn uvf_atlas_free(atlas: *mut UvfAtlas) {
    if !atlas.is_null() {
        let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            // SAFETY: the pointer came from Box::into_raw in `uvf_atlas`.
            drop(unsafe { Box::from_raw(atlas) });
        }));
    }
}
