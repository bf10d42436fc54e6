//! Spherical parameterization of closed genus-0 meshes (Hormann, Polthier & Sheffer 2008, §7):
//! Tutte–gnomonic, Gauss–Seidel relaxation, stereographic conformal, circle patterns.

use super::status::UvfStatus;
use super::MeshSource;
use super::{borrow_slice_mut, checked_count, guard, progress_closure, read_options, UvfProgressFn};
use std::os::raw::c_void;
use uvflat_core::error::Error;
use uvflat_core::methods::sphere::{spherical_map_with_progress, SphereMethod, SphereOptions};
use uvflat_core::progress::Progress;

/// Tutte embedding of the mesh minus one vertex star, gnomonic lift, flip-guarded relaxation:
/// never flips (the default).
pub const UVF_SPHERE_TUTTE_GNOMONIC: u32 = 0;

/// Projected Gauss–Seidel barycentric iteration (course notes §6.1; no guarantee).
pub const UVF_SPHERE_GAUSS_SEIDEL: u32 = 1;

/// Haker et al. 2000: harmonic map of the mesh minus one triangle + inverse stereographic
/// projection (no guarantee).
pub const UVF_SPHERE_STEREOGRAPHIC: u32 = 2;

/// Kharevych, Springborn & Schröder 2006: the planar circle pattern of the mesh minus one vertex
/// star (its link on a convex polygon whose corners are the removed spokes' intersection
/// angles), balanced so the vertex areas' centroid is the sphere's centre, inverse
/// stereographic projection: conformal (no guarantee against flips; they are counted).
pub const UVF_SPHERE_CIRCLE_PATTERNS: u32 = 3;

/// Options of `uvf_spherical_map`. Initialise with `uvf_sphere_options_default`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct UvfSphereOptions {
    /// `sizeof(UvfSphereOptions)`, set by the default initialiser.
    pub struct_size: usize,
    /// One of `UVF_SPHERE_*` (default `UVF_SPHERE_TUTTE_GNOMONIC`).
    pub method: u32,
    /// Relaxation sweeps (default 100); ignored by the stereographic and circle-pattern methods.
    pub sweeps: u32,
    /// Optional progress callback (may be NULL); a non-zero return cancels (`UVF_CANCELLED`).
    pub progress: UvfProgressFn,
    /// Passed to `progress` unchanged.
    pub progress_user: *mut c_void,
}

impl Default for UvfSphereOptions {
    fn default() -> Self {
        UvfSphereOptions {
            struct_size: std::mem::size_of::<Self>(),
            method: UVF_SPHERE_TUTTE_GNOMONIC,
            sweeps: 100,
            progress: None,
            progress_user: std::ptr::null_mut(),
        }
    }
}

/// Fills `options` with defaults (Tutte–gnomonic, 100 sweeps).
///
/// # Safety
/// `options` must be NULL or point to a writable struct.
#[no_mangle]
pub unsafe extern "C" fn uvf_sphere_options_default(options: *mut UvfSphereOptions) {
    if !options.is_null() {
        options.write(UvfSphereOptions::default());
    }
}

/// Size of the first version of `UvfSphereOptions` (without the progress callback).
const SPHERE_OPTIONS_V1: usize = std::mem::offset_of!(UvfSphereOptions, progress);

/// Spherical parameterization of a closed genus-0 mesh (course notes §6.1): unit-sphere
/// positions, 3 doubles per vertex in `sphere_out` (`vertex_count` triples; NaN for
/// unreferenced vertices), and in `*flipped_out` the number of triangles with
/// `det[p0, p1, p2] ≤ 0` (0 for `UVF_SPHERE_TUTTE_GNOMONIC` by construction). `options` may be
/// NULL. Returns `UVF_OK`, `UVF_INVALID_ARGUMENT`, `UVF_INVALID_MESH`,
/// `UVF_UNSUPPORTED_TOPOLOGY` (not one closed genus-0 surface), `UVF_NUMERICAL_FAILURE`,
/// `UVF_CANCELLED` (the progress callback returned non-zero), `UVF_INTERNAL_ERROR`. On failure
/// the outputs are untouched.
///
/// # Safety
/// The arrays must hold the stated number of elements; `flipped_out` must be writable.
#[no_mangle]
pub unsafe extern "C" fn uvf_spherical_map(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    options: *const UvfSphereOptions,
    sphere_out: *mut f64,
    flipped_out: *mut usize,
) -> UvfStatus {
    unsafe {
        spherical_map_from(
            MeshSource::arrays(positions, vertex_count, triangles, triangle_count),
            options,
            sphere_out,
            flipped_out,
        )
    }
}

/// `uvf_spherical_map` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_spherical_map`.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_spherical_map(
    mesh: *const super::mesh_handle::UvfMesh,
    options: *const UvfSphereOptions,
    sphere_out: *mut f64,
    flipped_out: *mut usize,
) -> UvfStatus {
    unsafe { spherical_map_from(MeshSource::Handle(mesh), options, sphere_out, flipped_out) }
}

/// `uvf_spherical_map` on either kind of mesh.
///
/// # Safety
/// As for `uvf_spherical_map`.
unsafe fn spherical_map_from(
    source: MeshSource,
    options: *const UvfSphereOptions,
    sphere_out: *mut f64,
    flipped_out: *mut usize,
) -> UvfStatus {
    guard(|| {
        let (vertex_count, _) = unsafe { source.counts() }?;
        let o = read_options(options, UvfSphereOptions::default(), SPHERE_OPTIONS_V1, "UvfSphereOptions")?;
        let method = match o.method {
            UVF_SPHERE_TUTTE_GNOMONIC => SphereMethod::TutteGnomonic,
            UVF_SPHERE_GAUSS_SEIDEL => SphereMethod::GaussSeidel,
            UVF_SPHERE_STEREOGRAPHIC => SphereMethod::Stereographic,
            UVF_SPHERE_CIRCLE_PATTERNS => SphereMethod::CirclePatterns,
            m => return Err(Error::InvalidArgument(format!("unknown sphere method {m}; use one of UVF_SPHERE_*"))),
        };
        let mesh = unsafe { source.mesh() }?;
        let flipped = borrow_slice_mut(flipped_out, 1, "flipped_out")?;
        let out = borrow_slice_mut(sphere_out, checked_count(vertex_count, 3, "sphere")?, "sphere_out")?;
        let mut callback = progress_closure(o.progress, o.progress_user);
        let options = SphereOptions { method, sweeps: o.sweeps as usize };
        let map = spherical_map_with_progress(&mesh, &options, &mut Progress::new(&mut callback))?;
        for (d, p) in out.chunks_exact_mut(3).zip(&map.positions) {
            d.copy_from_slice(p);
        }
        flipped[0] = map.flipped;
        Ok(())
    })
}
