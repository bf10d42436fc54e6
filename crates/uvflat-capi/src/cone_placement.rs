//! C ABI of the automatic cone placement (`methods::cone_placement`).

use super::status::UvfStatus;
use super::MeshSource;
use super::{borrow_slice_mut, guard, progress_closure, read_options, UvfProgressFn};
use std::os::raw::c_void;
use uvflat_core::error::Error;
use uvflat_core::methods::cone_placement::{place_cones, ConePlacementOptions};
use uvflat_core::progress::Progress;

/// Options of `uvf_place_cones`. Initialise with `uvf_cone_placement_options_default`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct UvfConePlacementOptions {
    /// `sizeof(UvfConePlacementOptions)`, set by the default initialiser.
    pub struct_size: usize,
    /// Most cones placed (default 64); the output arrays must hold this many, or
    /// `vertex_count` if that is fewer (a vertex is a cone at most once).
    pub max_cones: u32,
    /// Stop once the conformal flattening's log scale |u| is at most this everywhere (default
    /// 0.7, about a factor of 2 in length; ≥ 0).
    pub max_log_scale: f64,
    /// Optional progress callback (may be NULL), called after each cone.
    pub progress: UvfProgressFn,
    /// Passed to `progress` unchanged.
    pub progress_user: *mut c_void,
}

impl Default for UvfConePlacementOptions {
    fn default() -> Self {
        let d = ConePlacementOptions::default();
        UvfConePlacementOptions {
            struct_size: std::mem::size_of::<Self>(),
            max_cones: d.max_cones,
            max_log_scale: d.max_log_scale,
            progress: None,
            progress_user: std::ptr::null_mut(),
        }
    }
}

/// Fills `options` with defaults (at most 64 cones, log scale 0.7, no callback).
///
/// # Safety
/// `options` must be NULL or point to a writable struct.
#[no_mangle]
pub unsafe extern "C" fn uvf_cone_placement_options_default(options: *mut UvfConePlacementOptions) {
    if !options.is_null() {
        options.write(UvfConePlacementOptions::default());
    }
}

/// Places cone singularities for a conformal map greedily (Ben-Chen, Gotsman & Bunin 2008):
/// with the cones placed so far (and the boundary, if any) at log scale 0, the flattening's log
/// scale u solves a Poisson equation in the angle defects; the vertex with the largest |u| is
/// the next cone, until |u| ≤ `max_log_scale` everywhere or `max_cones` are placed. Each cone's
/// curvature (2π minus its cone angle) is the one that flattening gives it; on a closed mesh they
/// sum to 2π χ. The result is meant for `uvf_circle_pattern_cone_map`.
///
/// `cone_vertices_out` and `cone_curvatures_out` must hold min(`max_cones`, `vertex_count`)
/// elements; `count_out`
/// receives the number of cones written, `max_log_scale_out` (may be NULL) the largest |u| left.
/// Needs a connected mesh (closed of any genus, or with boundary; a torus may need none).
/// Returns `UVF_OK`, `UVF_INVALID_ARGUMENT`, `UVF_INVALID_MESH`, `UVF_UNSUPPORTED_TOPOLOGY`
/// (several components), `UVF_NUMERICAL_FAILURE`, `UVF_CANCELLED`, `UVF_INTERNAL_ERROR`. On
/// failure the outputs are untouched.
///
/// # Safety
/// The arrays must hold the stated number of elements; `count_out` must be writable,
/// `max_log_scale_out` NULL or writable.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn uvf_place_cones(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    options: *const UvfConePlacementOptions,
    cone_vertices_out: *mut u32,
    cone_curvatures_out: *mut f64,
    count_out: *mut usize,
    max_log_scale_out: *mut f64,
) -> UvfStatus {
    unsafe {
        place_cones_from(
            MeshSource::arrays(positions, vertex_count, triangles, triangle_count),
            options,
            cone_vertices_out,
            cone_curvatures_out,
            count_out,
            max_log_scale_out,
        )
    }
}

/// `uvf_place_cones` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_place_cones`.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn uvf_mesh_place_cones(
    mesh: *const super::mesh_handle::UvfMesh,
    options: *const UvfConePlacementOptions,
    cone_vertices_out: *mut u32,
    cone_curvatures_out: *mut f64,
    count_out: *mut usize,
    max_log_scale_out: *mut f64,
) -> UvfStatus {
    unsafe {
        place_cones_from(
            MeshSource::Handle(mesh),
            options,
            cone_vertices_out,
            cone_curvatures_out,
            count_out,
            max_log_scale_out,
        )
    }
}

/// `uvf_place_cones` on either kind of mesh.
///
/// # Safety
/// As for `uvf_place_cones`.
#[allow(clippy::too_many_arguments)]
unsafe fn place_cones_from(
    source: MeshSource,
    options: *const UvfConePlacementOptions,
    cone_vertices_out: *mut u32,
    cone_curvatures_out: *mut f64,
    count_out: *mut usize,
    max_log_scale_out: *mut f64,
) -> UvfStatus {
    guard(|| {
        let (vertex_count, _) = unsafe { source.counts() }?;
        let full = std::mem::size_of::<UvfConePlacementOptions>();
        let o = read_options(options, UvfConePlacementOptions::default(), full, "UvfConePlacementOptions")?;
        let opts = ConePlacementOptions { max_cones: o.max_cones, max_log_scale: o.max_log_scale };
        let mesh = unsafe { source.mesh() }?;
        let capacity = (o.max_cones as usize).min(vertex_count);
        // Checked before the work so that a bad output pointer leaves everything untouched.
        borrow_slice_mut(cone_vertices_out, capacity, "cone_vertices_out")?;
        borrow_slice_mut(cone_curvatures_out, capacity, "cone_curvatures_out")?;
        borrow_slice_mut(count_out, 1, "count_out")?;
        let mut callback = progress_closure(o.progress, o.progress_user);
        let placement = place_cones(&mesh, &opts, &mut Progress::new(&mut callback))?;
        if placement.cones.len() > capacity {
            return Err(Error::Internal(format!("{} cones for {capacity} places", placement.cones.len())));
        }
        let vertices = borrow_slice_mut(cone_vertices_out, capacity, "cone_vertices_out")?;
        let curvatures = borrow_slice_mut(cone_curvatures_out, capacity, "cone_curvatures_out")?;
        for (k, &(v, kappa)) in placement.cones.iter().enumerate() {
            vertices[k] = v;
            curvatures[k] = kappa;
        }
        // SAFETY: checked non-null above; the caller promises writable outputs.
        count_out.write(placement.cones.len());
        if !max_log_scale_out.is_null() {
            max_log_scale_out.write(placement.max_log_scale);
        }
        Ok(())
    })
}
