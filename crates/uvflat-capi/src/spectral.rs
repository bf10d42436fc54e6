//! The spectral conformal map (Mullen, Tong, Alliez & Desbrun 2008): conformal without pins, the
//! smallest generalized eigenvector.

use super::status::UvfStatus;
use super::MeshSource;
use super::SizedOut;
use super::{borrow_slice_mut, checked_count, guard, progress_closure, read_options, write_uv, UvfProgressFn};
use std::os::raw::c_void;
use uvflat_core::methods::spectral_conformal::{spectral_conformal_map, SpectralOptions};
use uvflat_core::progress::Progress;

/// Options of `uvf_spectral_conformal_map`. Initialise with `uvf_spectral_options_default`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct UvfSpectralOptions {
    /// `sizeof(UvfSpectralOptions)`, set by the default initialiser.
    pub struct_size: usize,
    /// Inverse-iteration limit (default 200; ≥ 1).
    pub iterations: u32,
    /// Stop when the eigenpair's normwise backward error is at most this (default 1e-12; > 0).
    pub tolerance: f64,
    /// Optional progress callback (may be NULL), called once per iteration.
    pub progress: UvfProgressFn,
    /// Passed to `progress` unchanged.
    pub progress_user: *mut c_void,
}

impl Default for UvfSpectralOptions {
    fn default() -> Self {
        let d = SpectralOptions::default();
        UvfSpectralOptions {
            struct_size: std::mem::size_of::<Self>(),
            iterations: d.iterations as u32,
            tolerance: d.tolerance,
            progress: None,
            progress_user: std::ptr::null_mut(),
        }
    }
}

/// What `uvf_spectral_conformal_map` reports.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct UvfSpectralReport {
    /// `sizeof(UvfSpectralReport)`, set by the caller before the call; the library writes only the fields
    /// that fit in that many bytes (see Versioning at the top of the header).
    pub struct_size: usize,
    /// Inverse iterations done.
    pub iterations: u32,
    /// 1 when the backward error reached the tolerance, 0 when the iteration limit stopped.
    pub converged: u32,
    /// The eigenvalue λ of `L_C z = λ B z` (the conformal energy of the boundary-normalized map).
    pub eigenvalue: f64,
    /// Normwise backward error `‖L_C z − λBz‖ / ((‖L_C‖∞ + |λ|)‖z‖)` of the eigenpair.
    pub residual: f64,
}

/// Fills `options` with defaults (200 iterations, tolerance 1e-12, no callback).
///
/// # Safety
/// `options` must be NULL or point to a writable struct.
#[no_mangle]
pub unsafe extern "C" fn uvf_spectral_options_default(options: *mut UvfSpectralOptions) {
    if !options.is_null() {
        options.write(UvfSpectralOptions::default());
    }
}

/// Spectral conformal map (Mullen, Tong, Alliez, Desbrun 2008): the free-boundary conformal map
/// without pinned vertices, the generalized eigenvector of `L_C z = λ B z` (L_C the conformal
/// energy, B 1 on boundary vertices) with the smallest non-trivial eigenvalue, by inverse
/// iteration on one sparse factorization. The result is scaled to the surface area with the
/// two boundary vertices farthest apart at (0, 0) and on the +u axis; it is invariant (up to
/// that placement) to rigid motions and scaling of the input, and a developable mesh gets its
/// exact development.
///
/// `uv_out` receives 2 doubles per vertex (NaN for unreferenced ones); `options` and
/// `report_out` may be NULL. A run that reaches the iteration limit without the tolerance
/// still returns `UVF_OK` with `report_out->converged = 0`. Returns `UVF_OK`,
/// `UVF_INVALID_ARGUMENT` (bad pointer or option), `UVF_INVALID_MESH`,
/// `UVF_UNSUPPORTED_TOPOLOGY` (not a connected genus-0 mesh with a boundary),
/// `UVF_NUMERICAL_FAILURE`, `UVF_CANCELLED`, `UVF_INTERNAL_ERROR`. On failure the outputs are
/// untouched.
///
/// # Safety
/// The arrays must hold the stated number of elements; `report_out` must be NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn uvf_spectral_conformal_map(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    options: *const UvfSpectralOptions,
    uv_out: *mut f64,
    report_out: *mut UvfSpectralReport,
) -> UvfStatus {
    unsafe {
        spectral_conformal_map_from(
            MeshSource::arrays(positions, vertex_count, triangles, triangle_count),
            options,
            uv_out,
            report_out,
        )
    }
}

/// `uvf_spectral_conformal_map` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_spectral_conformal_map`.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_spectral_conformal_map(
    mesh: *const super::mesh_handle::UvfMesh,
    options: *const UvfSpectralOptions,
    uv_out: *mut f64,
    report_out: *mut UvfSpectralReport,
) -> UvfStatus {
    unsafe { spectral_conformal_map_from(MeshSource::Handle(mesh), options, uv_out, report_out) }
}

/// `uvf_spectral_conformal_map` on either kind of mesh.
///
/// # Safety
/// As for `uvf_spectral_conformal_map`.
unsafe fn spectral_conformal_map_from(
    source: MeshSource,
    options: *const UvfSpectralOptions,
    uv_out: *mut f64,
    report_out: *mut UvfSpectralReport,
) -> UvfStatus {
    guard(|| {
        let (vertex_count, _) = unsafe { source.counts() }?;
        // Checked before the work, so that a bad report pointer leaves every output untouched.
        let report_out = unsafe { SizedOut::optional(report_out, "report_out", "UvfSpectralReport") }?;
        let o = read_options(options, UvfSpectralOptions::default(), SPECTRAL_OPTIONS_V1, "UvfSpectralOptions")?;
        let opts = SpectralOptions { iterations: o.iterations as usize, tolerance: o.tolerance };
        let mesh = unsafe { source.mesh() }?;
        // Checked before the work so that a bad output pointer leaves everything untouched.
        borrow_slice_mut(uv_out, checked_count(vertex_count, 2, "uv")?, "uv_out")?;
        let mut callback = progress_closure(o.progress, o.progress_user);
        let r = spectral_conformal_map(&mesh, &opts, &mut Progress::new(&mut callback))?;
        write_uv(&r.uv, uv_out)?;
        if let Some(report_out) = &report_out {
            report_out.write(UvfSpectralReport {
                struct_size: 0,
                iterations: r.iterations as u32,
                converged: u32::from(r.converged),
                eigenvalue: r.eigenvalue,
                residual: r.residual,
            });
        }
        Ok(())
    })
}

const SPECTRAL_OPTIONS_V1: usize = std::mem::size_of::<UvfSpectralOptions>();
