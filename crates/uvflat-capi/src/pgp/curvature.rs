//! Principal curvatures and directions (Ray et al. 2006, §3.1: the input frame field of PGP).

use crate::status::UvfStatus;
use crate::MeshSource;
use crate::{borrow_slice_mut, checked_count, guard, read_options};
use uvflat_core::error::{Error, Result};
use uvflat_core::fields::curvature::{principal_curvatures, CurvatureOptions, Neighbourhood};

/// Curvature neighbourhood: the triangles around the vertices at most `rings − 1` edges away.
pub const UVF_CURVATURE_RINGS: u32 = 0;

/// Curvature neighbourhood: the triangles around the vertices within `radius` (graph distance).
pub const UVF_CURVATURE_RADIUS: u32 = 1;

/// Options of `uvf_curvature`. Initialise with `uvf_curvature_options_default`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct UvfCurvatureOptions {
    /// `sizeof(UvfCurvatureOptions)`, set by the default initialiser.
    pub struct_size: usize,
    /// `UVF_CURVATURE_RINGS` (default) or `UVF_CURVATURE_RADIUS`.
    pub neighbourhood: u32,
    /// Rings for `UVF_CURVATURE_RINGS` (default 2; ≥ 1).
    pub rings: u32,
    /// Radius for `UVF_CURVATURE_RADIUS` (finite, > 0; default 0 = unset).
    pub radius: f64,
}

impl Default for UvfCurvatureOptions {
    fn default() -> Self {
        UvfCurvatureOptions {
            struct_size: std::mem::size_of::<Self>(),
            neighbourhood: UVF_CURVATURE_RINGS,
            rings: 2,
            radius: 0.0,
        }
    }
}

const CURVATURE_OPTIONS_V1: usize = std::mem::size_of::<UvfCurvatureOptions>();

/// Fills `options` with defaults (two rings).
///
/// # Safety
/// `options` must be NULL or point to a writable struct.
#[no_mangle]
pub unsafe extern "C" fn uvf_curvature_options_default(options: *mut UvfCurvatureOptions) {
    if !options.is_null() {
        options.write(UvfCurvatureOptions::default());
    }
}

pub(crate) fn curvature_options(neighbourhood: u32, rings: u32, radius: f64) -> Result<CurvatureOptions> {
    let neighbourhood = match neighbourhood {
        UVF_CURVATURE_RINGS => Neighbourhood::Rings(rings),
        UVF_CURVATURE_RADIUS => Neighbourhood::Radius(radius),
        n => return Err(Error::InvalidArgument(format!("unknown curvature neighbourhood {n}; use UVF_CURVATURE_*"))),
    };
    Ok(CurvatureOptions { neighbourhood })
}

/// Principal curvatures per vertex by the normal-cycle tensor of Cohen-Steiner & Morvan 2003
/// (the input field of Ray et al. 2006, §4.2), averaged over a neighbourhood of each vertex.
///
/// Outputs (each may be NULL to skip it): `kmin_direction_out` and `kmax_direction_out`, 3
/// doubles per vertex (unit tangent directions, kmax = normal × kmin); `kmin_out` and
/// `kmax_out`, 1 double per vertex (signed curvatures, kmin ≤ kmax; a sphere with outward
/// normals has 1/r). Unreferenced vertices get zeros. `options` may be NULL. Returns `UVF_OK`,
/// `UVF_INVALID_ARGUMENT` (bad neighbourhood, bad pointers), `UVF_INVALID_MESH`,
/// `UVF_INTERNAL_ERROR`. On failure the outputs are untouched.
///
/// # Safety
/// The arrays must hold the stated number of elements or be NULL.
#[no_mangle]
pub unsafe extern "C" fn uvf_curvature(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    options: *const UvfCurvatureOptions,
    kmin_direction_out: *mut f64,
    kmax_direction_out: *mut f64,
    kmin_out: *mut f64,
    kmax_out: *mut f64,
) -> UvfStatus {
    unsafe {
        curvature_from(
            MeshSource::arrays(positions, vertex_count, triangles, triangle_count),
            options,
            kmin_direction_out,
            kmax_direction_out,
            kmin_out,
            kmax_out,
        )
    }
}

/// `uvf_curvature` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_curvature`.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_curvature(
    mesh: *const crate::mesh_handle::UvfMesh,
    options: *const UvfCurvatureOptions,
    kmin_direction_out: *mut f64,
    kmax_direction_out: *mut f64,
    kmin_out: *mut f64,
    kmax_out: *mut f64,
) -> UvfStatus {
    unsafe {
        curvature_from(MeshSource::Handle(mesh), options, kmin_direction_out, kmax_direction_out, kmin_out, kmax_out)
    }
}

/// `uvf_curvature` on either kind of mesh.
///
/// # Safety
/// As for `uvf_curvature`.
unsafe fn curvature_from(
    source: MeshSource,
    options: *const UvfCurvatureOptions,
    kmin_direction_out: *mut f64,
    kmax_direction_out: *mut f64,
    kmin_out: *mut f64,
    kmax_out: *mut f64,
) -> UvfStatus {
    guard(|| {
        let (vertex_count, _) = unsafe { source.counts() }?;
        let o = read_options(options, UvfCurvatureOptions::default(), CURVATURE_OPTIONS_V1, "UvfCurvatureOptions")?;
        let opts = curvature_options(o.neighbourhood, o.rings, o.radius)?;
        let mesh = unsafe { source.mesh() }?;
        let n3 = checked_count(vertex_count, 3, "vertex")?;
        let kmin_dir = optional_out(kmin_direction_out, n3, "kmin_direction_out")?;
        let kmax_dir = optional_out(kmax_direction_out, n3, "kmax_direction_out")?;
        let kmin = optional_out(kmin_out, vertex_count, "kmin_out")?;
        let kmax = optional_out(kmax_out, vertex_count, "kmax_out")?;
        let c = principal_curvatures(&mesh, &opts)?;
        if let Some(d) = kmin_dir {
            d.copy_from_slice(c.kmin_direction.as_flattened());
        }
        if let Some(d) = kmax_dir {
            d.copy_from_slice(c.kmax_direction.as_flattened());
        }
        if let Some(d) = kmin {
            d.copy_from_slice(&c.kmin);
        }
        if let Some(d) = kmax {
            d.copy_from_slice(&c.kmax);
        }
        Ok(())
    })
}

/// A caller array of `count` elements, or None for NULL.
fn optional_out<'a>(ptr: *mut f64, count: usize, what: &'static str) -> Result<Option<&'a mut [f64]>> {
    if ptr.is_null() {
        Ok(None)
    } else {
        borrow_slice_mut(ptr, count, what).map(Some)
    }
}
