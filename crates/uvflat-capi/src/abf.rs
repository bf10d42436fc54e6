//! C ABI of ABF / ABF++ (`methods::abf`).

use super::status::UvfStatus;
use super::MeshSource;
use super::SizedOut;
use super::{guard, progress_closure, read_options, write_uv, UvfProgressFn};
use std::os::raw::c_void;
use uvflat_core::error::Error;
use uvflat_core::methods::abf::{abf_with_progress, AbfOptions, AbfVariant, AbfWeights};
use uvflat_core::progress::Progress;

/// Original ABF (Sheffer & de Sturler 2001): full Newton steps, sparse LU of the whole system.
pub const UVF_ABF_VARIANT_ABF: u32 = 0;
/// ABF++ (Sheffer et al. 2005): Gauss–Newton steps on the reduced ~2·n_interior system.
pub const UVF_ABF_VARIANT_ABF_PLUS_PLUS: u32 = 1;

/// Objective weights w = 1/(β(π − β)) (default): the angle's and its supplement's inverse.
pub const UVF_ABF_WEIGHTS_ANGLE_AND_SUPPLEMENT: u32 = 0;
/// Objective weights w = 1/β², the papers' relative angle error.
pub const UVF_ABF_WEIGHTS_INVERSE_SQUARE: u32 = 1;
/// Objective weights w = 1/β.
pub const UVF_ABF_WEIGHTS_INVERSE: u32 = 2;

/// Options of `uvf_abf`. Initialise with `uvf_abf_options_default`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct UvfAbfOptions {
    /// `sizeof(UvfAbfOptions)`, set by the default initialiser.
    pub struct_size: usize,
    /// `UVF_ABF_VARIANT_ABF_PLUS_PLUS` (default) or `UVF_ABF_VARIANT_ABF`.
    pub variant: u32,
    /// Most Newton / Gauss–Newton iterations (default 20).
    pub max_iterations: u32,
    /// Stop when the Euclidean norm of the Lagrangian's gradient is at most this (default 1e-6).
    pub tolerance: f64,
    /// 0: pin the two boundary vertices farthest apart (default); 2: use `pin_vertices`.
    pub pin_count: u32,
    /// The two pinned vertices when `pin_count` is 2.
    pub pin_vertices: [u32; 2],
    /// Their UVs: u0, v0, u1, v1.
    pub pin_uv: [f64; 4],
    /// Optional progress callback (may be NULL), called once per iteration.
    pub progress: UvfProgressFn,
    /// Passed to `progress` unchanged.
    pub progress_user: *mut c_void,
    /// Weights w of the objective Σ w (α − β)²: `UVF_ABF_WEIGHTS_ANGLE_AND_SUPPLEMENT`
    /// (default) or `UVF_ABF_WEIGHTS_INVERSE_SQUARE` (the papers') or `UVF_ABF_WEIGHTS_INVERSE`.
    /// Added after version 1 of the struct; callers built against it get the default.
    pub weights: u32,
    /// μ ≥ 0 of the angle barrier μ Σ (α/β − ln(α/β) − 1) (default 1); 0 with
    /// `UVF_ABF_WEIGHTS_INVERSE_SQUARE` is the papers' objective, which has no minimiser with
    /// every angle in (0, π) on some folded meshes. Added after version 1 of the struct.
    pub barrier: f64,
}

impl Default for UvfAbfOptions {
    fn default() -> Self {
        UvfAbfOptions {
            struct_size: std::mem::size_of::<Self>(),
            variant: UVF_ABF_VARIANT_ABF_PLUS_PLUS,
            max_iterations: 20,
            tolerance: 1e-6,
            pin_count: 0,
            pin_vertices: [0, 0],
            pin_uv: [0.0, 0.0, 1.0, 0.0],
            progress: None,
            progress_user: std::ptr::null_mut(),
            weights: UVF_ABF_WEIGHTS_ANGLE_AND_SUPPLEMENT,
            barrier: AbfOptions::default().barrier,
        }
    }
}

/// What `uvf_abf` reports about the angle optimisation.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct UvfAbfReport {
    /// `sizeof(UvfAbfReport)`, set by the caller before the call; the library writes only the fields
    /// that fit in that many bytes (see Versioning at the top of the header).
    pub struct_size: usize,
    /// Iterations taken.
    pub iterations: u32,
    /// 1 when `gradient_norm <= tolerance`, else 0 (the UVs are still returned).
    pub converged: u32,
    /// Norm of the Lagrangian's gradient at the returned angles.
    pub gradient_norm: f64,
    /// Corners whose planar angle is outside (0, π) (their triangles flip).
    pub invalid_angles: u64,
}

/// Fills `options` with defaults (ABF++, 20 iterations, tolerance 1e-6, automatic pins,
/// weights 1/(β(π − β)), barrier 1).
///
/// # Safety
/// `options` must be NULL or point to a writable struct.
#[no_mangle]
pub unsafe extern "C" fn uvf_abf_options_default(options: *mut UvfAbfOptions) {
    if !options.is_null() {
        options.write(UvfAbfOptions::default());
    }
}

/// Size of the first version of `UvfAbfOptions` (without `weights` and `barrier`).
const ABF_OPTIONS_V1: usize = std::mem::offset_of!(UvfAbfOptions, weights);

/// Angle Based Flattening: ABF (Sheffer & de Sturler 2001) or ABF++ (Sheffer, Lévy,
/// Mogilnitsky, Bogomyakov 2005; course notes §4.5). Finds planar corner angles closest to the
/// 3D ones (energy Σ (α − β)²/(β(π − β)) plus the barrier Σ (α/β − ln(α/β) − 1), see the Rust
/// `methods::abf`) under the triangle, planarity and sine-law reconstruction
/// constraints by Newton (ABF) or Gauss–Newton (ABF++, reduced 2·n_interior system) steps on
/// the Lagrangian, then lays the angles out by least squares (ABF++ §5, the natural conformal
/// system with the cotangents of the angles) with two pinned vertices.
///
/// Needs a connected genus-0 mesh with at least one boundary. `uv_out` receives 2 doubles per
/// vertex (`vertex_count` pairs); unreferenced vertices get NaN. `options` may be NULL.
/// `report_out` may be NULL; otherwise it receives the iterations and final gradient norm.
/// Reaching `max_iterations` without convergence is not an error (see `report_out->converged`).
/// Returns `UVF_OK`, `UVF_INVALID_ARGUMENT`, `UVF_INVALID_MESH`, `UVF_UNSUPPORTED_TOPOLOGY`,
/// `UVF_NUMERICAL_FAILURE` (singular system, divergence), `UVF_CANCELLED` (the progress
/// callback returned non-zero; checked once per iteration), `UVF_INTERNAL_ERROR`. On failure
/// the outputs are untouched.
///
/// # Safety
/// The arrays must hold the stated number of elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_abf(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    options: *const UvfAbfOptions,
    uv_out: *mut f64,
    report_out: *mut UvfAbfReport,
) -> UvfStatus {
    unsafe {
        abf_from(MeshSource::arrays(positions, vertex_count, triangles, triangle_count), options, uv_out, report_out)
    }
}

/// `uvf_abf` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_abf`.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_abf(
    mesh: *const super::mesh_handle::UvfMesh,
    options: *const UvfAbfOptions,
    uv_out: *mut f64,
    report_out: *mut UvfAbfReport,
) -> UvfStatus {
    unsafe { abf_from(MeshSource::Handle(mesh), options, uv_out, report_out) }
}

/// `uvf_abf` on either kind of mesh.
///
/// # Safety
/// As for `uvf_abf`.
unsafe fn abf_from(
    source: MeshSource,
    options: *const UvfAbfOptions,
    uv_out: *mut f64,
    report_out: *mut UvfAbfReport,
) -> UvfStatus {
    guard(|| {
        // Checked before the work, so that a bad report pointer leaves every output untouched.
        let report_out = unsafe { SizedOut::optional(report_out, "report_out", "UvfAbfReport") }?;
        let o = read_options(options, UvfAbfOptions::default(), ABF_OPTIONS_V1, "UvfAbfOptions")?;
        let variant = match o.variant {
            UVF_ABF_VARIANT_ABF => AbfVariant::Abf,
            UVF_ABF_VARIANT_ABF_PLUS_PLUS => AbfVariant::AbfPlusPlus,
            v => return Err(Error::InvalidArgument(format!("unknown ABF variant {v}; use one of UVF_ABF_VARIANT_*"))),
        };
        let pins = super::pins_from_options(o.pin_count, o.pin_vertices, o.pin_uv)?;
        let weights = match o.weights {
            UVF_ABF_WEIGHTS_ANGLE_AND_SUPPLEMENT => AbfWeights::AngleAndSupplement,
            UVF_ABF_WEIGHTS_INVERSE_SQUARE => AbfWeights::InverseSquare,
            UVF_ABF_WEIGHTS_INVERSE => AbfWeights::Inverse,
            w => return Err(Error::InvalidArgument(format!("unknown ABF weights {w}; use one of UVF_ABF_WEIGHTS_*"))),
        };
        let options = AbfOptions {
            variant,
            max_iterations: o.max_iterations,
            tolerance: o.tolerance,
            pins,
            weights,
            barrier: o.barrier,
            ..AbfOptions::default()
        };
        let mesh = unsafe { source.mesh() }?;
        let mut callback = progress_closure(o.progress, o.progress_user);
        let result = abf_with_progress(&mesh, &options, &mut Progress::new(&mut callback))?;
        write_uv(&result.uv, uv_out)?;
        if let Some(report_out) = &report_out {
            let r = result.report;
            report_out.write(UvfAbfReport {
                struct_size: 0,
                iterations: r.iterations,
                converged: r.converged as u32,
                gradient_norm: r.gradient_norm,
                invalid_angles: r.invalid_angles as u64,
            });
        }
        Ok(())
    })
}
