//! The natural conformal map (Desbrun, Meyer & Alliez 2002, eq. 7; LSCM of Lévy et al. 2002): free
//! boundary, two pinned vertices.

use super::status::UvfStatus;
use super::MeshSource;
use super::{guard, progress_closure, read_options, write_uv, UvfProgressFn};
use std::os::raw::c_void;
use uvflat_core::methods::conformal::natural_conformal_map_with_progress;
use uvflat_core::progress::Progress;

/// Options of `uvf_natural_conformal_map`. Initialise with
/// `uvf_natural_conformal_options_default`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct UvfNaturalConformalOptions {
    /// `sizeof(UvfNaturalConformalOptions)`, set by the default initialiser.
    pub struct_size: usize,
    /// 0: pin the two boundary vertices farthest apart (default); 2: use `pin_vertices`.
    pub pin_count: u32,
    /// The two pinned vertices when `pin_count` is 2.
    pub pin_vertices: [u32; 2],
    /// Their UVs: u0, v0, u1, v1.
    pub pin_uv: [f64; 4],
    /// Optional progress callback (may be NULL).
    pub progress: UvfProgressFn,
    /// Passed to `progress` unchanged.
    pub progress_user: *mut c_void,
}

impl Default for UvfNaturalConformalOptions {
    fn default() -> Self {
        UvfNaturalConformalOptions {
            struct_size: std::mem::size_of::<Self>(),
            pin_count: 0,
            pin_vertices: [0, 0],
            pin_uv: [0.0, 0.0, 1.0, 0.0],
            progress: None,
            progress_user: std::ptr::null_mut(),
        }
    }
}

/// Fills `options` with defaults (automatic pins).
///
/// # Safety
/// `options` must be NULL or point to a writable struct.
#[no_mangle]
pub unsafe extern "C" fn uvf_natural_conformal_options_default(options: *mut UvfNaturalConformalOptions) {
    if !options.is_null() {
        options.write(UvfNaturalConformalOptions::default());
    }
}

const CONFORMAL_OPTIONS_V1: usize = std::mem::size_of::<UvfNaturalConformalOptions>();

/// Natural conformal map (Desbrun et al. 2002 §4.2 eq. 7; identical to LSCM): free boundary,
/// two pinned vertices (automatic: the farthest boundary pair, at (0,0) and (d,0)).
///
/// `uv_out` receives 2 doubles per vertex; unreferenced vertices get NaN. `options` may be
/// NULL. Statuses as `uvf_fixed_boundary_map`.
///
/// # Safety
/// The arrays must hold the stated number of elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_natural_conformal_map(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    options: *const UvfNaturalConformalOptions,
    uv_out: *mut f64,
) -> UvfStatus {
    unsafe {
        natural_conformal_map_from(
            MeshSource::arrays(positions, vertex_count, triangles, triangle_count),
            options,
            uv_out,
        )
    }
}

/// `uvf_natural_conformal_map` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_natural_conformal_map`.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_natural_conformal_map(
    mesh: *const super::mesh_handle::UvfMesh,
    options: *const UvfNaturalConformalOptions,
    uv_out: *mut f64,
) -> UvfStatus {
    unsafe { natural_conformal_map_from(MeshSource::Handle(mesh), options, uv_out) }
}

/// `uvf_natural_conformal_map` on either kind of mesh.
///
/// # Safety
/// As for `uvf_natural_conformal_map`.
unsafe fn natural_conformal_map_from(
    source: MeshSource,
    options: *const UvfNaturalConformalOptions,
    uv_out: *mut f64,
) -> UvfStatus {
    guard(|| {
        let o = read_options(
            options,
            UvfNaturalConformalOptions::default(),
            CONFORMAL_OPTIONS_V1,
            "UvfNaturalConformalOptions",
        )?;
        let pins = super::pins_from_options(o.pin_count, o.pin_vertices, o.pin_uv)?;
        let mesh = unsafe { source.mesh() }?;
        let mut callback = progress_closure(o.progress, o.progress_user);
        let uv = natural_conformal_map_with_progress(&mesh, pins, &mut Progress::new(&mut callback))?;
        write_uv(&uv, uv_out)
    })
}
