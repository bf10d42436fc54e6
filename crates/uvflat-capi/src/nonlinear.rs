//! Distortion-minimizing parameterizations: SLIM, ARAP, MIPS, stretch, Green–Lagrange,
//! Degener (`uvf_nonlinear_map`).

use super::status::UvfStatus;
use super::MeshSource;
use super::SizedOut;
use super::{guard, progress_closure, read_options, write_uv, UvfProgressFn};
use std::os::raw::c_void;
use uvflat_core::error::{Error, Result};
use uvflat_core::methods::nonlinear::{nonlinear_map_with_progress, NonlinearMethod, NonlinearOptions};
use uvflat_core::progress::Progress;

/// Symmetric Dirichlet energy minimized by SLIM (Rabinovich et al. 2017).
pub const UVF_NONLINEAR_SLIM: u32 = 0;
/// As-rigid-as-possible, local-global (Liu et al. 2008).
pub const UVF_NONLINEAR_ARAP: u32 = 1;
/// MIPS (Hormann & Greiner 2000), conformal.
pub const UVF_NONLINEAR_MIPS: u32 = 2;
/// L2 stretch (Sander et al. 2001).
pub const UVF_NONLINEAR_STRETCH: u32 = 3;
/// Green–Lagrange deformation tensor (Maillot et al. 1993).
pub const UVF_NONLINEAR_GREEN_LAGRANGE: u32 = 4;
/// Degener et al. 2003 θ-energy (angle × area^θ).
pub const UVF_NONLINEAR_DEGENER: u32 = 5;

/// Options of `uvf_nonlinear_map`. Initialise with `uvf_nonlinear_options_default`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct UvfNonlinearOptions {
    /// `sizeof(UvfNonlinearOptions)`, set by the default initialiser.
    pub struct_size: usize,
    /// One of `UVF_NONLINEAR_*` (default `UVF_NONLINEAR_SLIM`).
    pub method: u32,
    /// Maximum number of iterations (default 100).
    pub iterations: u32,
    /// Stop when an iteration lowers the energy by less than `tolerance × energy` (default
    /// 1e-7; must be ≥ 0).
    pub tolerance: f64,
    /// θ of `UVF_NONLINEAR_DEGENER` (default 3; must be > 0).
    pub theta: f64,
    /// Optional progress callback (may be NULL), called once per iteration; returning
    /// non-zero cancels within that iteration.
    pub progress: UvfProgressFn,
    /// Passed to `progress` unchanged.
    pub progress_user: *mut c_void,
    /// Non-zero: keep the whole map bijective: a scaffold around the free boundary (Jiang et al.
    /// 2017) keeps the boundary from running into itself (default 0). SLIM optimizes chart and
    /// scaffold together (SCAF); the other methods keep their own search direction and the
    /// scaffold bounds their steps, so their boundary stops where it meets itself (a higher
    /// final energy than without the bound where it would have crossed).
    pub bijective: u32,
}

impl Default for UvfNonlinearOptions {
    fn default() -> Self {
        let d = NonlinearOptions::new(NonlinearMethod::Slim);
        UvfNonlinearOptions {
            struct_size: std::mem::size_of::<Self>(),
            method: UVF_NONLINEAR_SLIM,
            iterations: d.iterations as u32,
            tolerance: d.tolerance,
            theta: d.theta,
            progress: None,
            progress_user: std::ptr::null_mut(),
            bijective: d.bijective as u32,
        }
    }
}

/// What `uvf_nonlinear_map` reports about its run.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct UvfNonlinearReport {
    /// `sizeof(UvfNonlinearReport)`, set by the caller before the call; the library writes only the fields
    /// that fit in that many bytes (see Versioning at the top of the header).
    pub struct_size: usize,
    /// Iterations done.
    pub iterations: u32,
    /// 1 when the tolerance was reached or no step could lower the energy; 0 when the
    /// iteration limit stopped the method.
    pub converged: u32,
    /// Energy of the starting map (3D-area-weighted mean of the method's local measure).
    pub initial_energy: f64,
    /// Energy of the returned map (never above `initial_energy`).
    pub final_energy: f64,
}

/// Fills `options` with defaults (SLIM, 100 iterations, tolerance 1e-7, θ = 3).
///
/// # Safety
/// `options` must be NULL or point to a writable struct.
#[no_mangle]
pub unsafe extern "C" fn uvf_nonlinear_options_default(options: *mut UvfNonlinearOptions) {
    if !options.is_null() {
        options.write(UvfNonlinearOptions::default());
    }
}

/// Size of the first version of the struct (before `bijective`): older callers stay accepted.
const NONLINEAR_OPTIONS_V1: usize = std::mem::offset_of!(UvfNonlinearOptions, bijective);

fn method_from(code: u32) -> Result<NonlinearMethod> {
    Ok(match code {
        UVF_NONLINEAR_SLIM => NonlinearMethod::Slim,
        UVF_NONLINEAR_ARAP => NonlinearMethod::Arap,
        UVF_NONLINEAR_MIPS => NonlinearMethod::Mips,
        UVF_NONLINEAR_STRETCH => NonlinearMethod::Stretch,
        UVF_NONLINEAR_GREEN_LAGRANGE => NonlinearMethod::GreenLagrange,
        UVF_NONLINEAR_DEGENER => NonlinearMethod::Degener,
        m => return Err(Error::InvalidArgument(format!("unknown method {m}; use one of UVF_NONLINEAR_*"))),
    })
}

/// Distortion-minimizing parameterization with a free boundary that never flips a triangle.
///
/// Starts from the mean value map with a circle boundary (bijective; ARAP: from the natural
/// conformal map when it has no flipped triangle), scaled to the input's area, and minimizes
/// the method's energy (local measure of the Jacobian's singular values σ1 ≥ σ2, weighted by
/// 3D area; course notes §4.3–4.4) with a line search that stops every step before any
/// triangle's signed area reaches zero (Smith & Schaefer 2015), so the result has no flipped
/// triangle and the energy decreases monotonically:
/// - `UVF_NONLINEAR_SLIM`: symmetric Dirichlet σ1² + σ1⁻² + σ2² + σ2⁻², by SLIM's reweighted
///   local-global proxy (Rabinovich et al. 2017 eq. 8–9).
/// - `UVF_NONLINEAR_ARAP`: (σ1 − 1)² + (σ2 − 1)², local-global (Liu et al. 2008 eq. 3–6).
/// - `UVF_NONLINEAR_MIPS`: σ1/σ2 + σ2/σ1 (Hormann & Greiner 2000).
/// - `UVF_NONLINEAR_STRETCH`: Sander et al. 2001 L2 stretch (squared, scale-normalized).
/// - `UVF_NONLINEAR_GREEN_LAGRANGE`: (σ1² − 1)² + (σ2² − 1)² (Maillot et al. 1993).
/// - `UVF_NONLINEAR_DEGENER`: (σ1/σ2 + σ2/σ1)(σ1σ2 + 1/(σ1σ2))^θ (Degener et al. 2003).
///
/// The last four use L-BFGS preconditioned by the cotangent Laplacian. ARAP and Green–Lagrange
/// stay finite as a triangle's area goes to zero, so their line search also keeps every
/// triangle's UV area at or above 1% of its share of the map's area (its 3D area's share of
/// the surface), or half its area in the start when that is less; the other energies grow
/// without bound there and need no floor.
///
/// `uv_out` receives 2 doubles per vertex (`vertex_count` pairs); unreferenced vertices get
/// NaN. `options` may be NULL for defaults; `report_out` may be NULL. Results are
/// deterministic. Returns `UVF_OK`, `UVF_INVALID_ARGUMENT` (unknown method, tolerance < 0,
/// θ ≤ 0, bad pointers), `UVF_INVALID_MESH`, `UVF_UNSUPPORTED_TOPOLOGY` (not a single genus-0
/// component with a boundary), `UVF_NUMERICAL_FAILURE`, `UVF_CANCELLED`,
/// `UVF_INTERNAL_ERROR`. On failure `uv_out` and `report_out` are untouched.
///
/// # Safety
/// The arrays must hold the stated number of elements; `report_out` must be NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn uvf_nonlinear_map(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    options: *const UvfNonlinearOptions,
    uv_out: *mut f64,
    report_out: *mut UvfNonlinearReport,
) -> UvfStatus {
    unsafe {
        nonlinear_map_from(
            MeshSource::arrays(positions, vertex_count, triangles, triangle_count),
            options,
            uv_out,
            report_out,
        )
    }
}

/// `uvf_nonlinear_map` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_nonlinear_map`.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_nonlinear_map(
    mesh: *const super::mesh_handle::UvfMesh,
    options: *const UvfNonlinearOptions,
    uv_out: *mut f64,
    report_out: *mut UvfNonlinearReport,
) -> UvfStatus {
    unsafe { nonlinear_map_from(MeshSource::Handle(mesh), options, uv_out, report_out) }
}

/// `uvf_nonlinear_map` on either kind of mesh.
///
/// # Safety
/// As for `uvf_nonlinear_map`.
unsafe fn nonlinear_map_from(
    source: MeshSource,
    options: *const UvfNonlinearOptions,
    uv_out: *mut f64,
    report_out: *mut UvfNonlinearReport,
) -> UvfStatus {
    guard(|| {
        // Checked before the work, so that a bad report pointer leaves every output untouched.
        let report_out = unsafe { SizedOut::optional(report_out, "report_out", "UvfNonlinearReport") }?;
        let o = read_options(options, UvfNonlinearOptions::default(), NONLINEAR_OPTIONS_V1, "UvfNonlinearOptions")?;
        let mut opts = NonlinearOptions::new(method_from(o.method)?);
        opts.iterations = o.iterations as usize;
        opts.tolerance = o.tolerance;
        opts.theta = o.theta;
        opts.bijective = o.bijective != 0;
        let mesh = unsafe { source.mesh() }?;
        let mut callback = progress_closure(o.progress, o.progress_user);
        let result = nonlinear_map_with_progress(&mesh, &opts, &mut Progress::new(&mut callback))?;
        write_uv(&result.uv, uv_out)?;
        if let Some(report_out) = &report_out {
            report_out.write(UvfNonlinearReport {
                struct_size: 0,
                iterations: result.iterations as u32,
                converged: result.converged as u32,
                initial_energy: result.energy[0],
                final_energy: *result.energy.last().unwrap_or(&result.energy[0]),
            });
        }
        Ok(())
    })
}
