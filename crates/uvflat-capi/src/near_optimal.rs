//! The near-optimal intrinsic map (Desbrun, Meyer & Alliez 2002, §5.1): the λ·DCP + (1−λ)·DAP map
//! of least distortion energy, and the energy codes it shares with boundary optimization.

use super::barycentric::{distribution_from_code, shape_from_parts, UVF_BOUNDARY_CIRCLE, UVF_DISTRIBUTION_CHORD};
use super::status::UvfStatus;
use super::MeshSource;
use super::SizedOut;
use super::{borrow_slice_mut, checked_count, guard, progress_closure, read_options, write_uv, UvfProgressFn};
use std::os::raw::c_void;
use uvflat_core::error::{Error, Result};
use uvflat_core::methods::length_area_distortion::DistortionEnergy;
use uvflat_core::methods::near_optimal::{near_optimal_map, NearOptimalOptions};
use uvflat_core::progress::Progress;

/// Edge-length distortion `Σ_edges (|u_i − u_j|² / |x_i − x_j|² − 1)²` (Desbrun et al. 2002 §5.1).
pub const UVF_ENERGY_EDGE_LENGTH: u32 = 0;

/// Area distortion `Σ_faces ((A^uv / A^3D)² − 1)²` (Desbrun et al. 2002 §5.1, as printed).
pub const UVF_ENERGY_AREA: u32 = 1;

pub(crate) fn energy_from(code: u32) -> Result<DistortionEnergy> {
    match code {
        UVF_ENERGY_EDGE_LENGTH => Ok(DistortionEnergy::EdgeLength),
        UVF_ENERGY_AREA => Ok(DistortionEnergy::Area),
        e => Err(Error::InvalidArgument(format!("unknown energy {e}; use UVF_ENERGY_EDGE_LENGTH or UVF_ENERGY_AREA"))),
    }
}

/// Options of `uvf_intrinsic_optimal_map`. Initialise with
/// `uvf_intrinsic_optimal_options_default`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct UvfIntrinsicOptimalOptions {
    /// `sizeof(UvfIntrinsicOptimalOptions)`, set by the default initialiser.
    pub struct_size: usize,
    /// `UVF_ENERGY_EDGE_LENGTH` (default) or `UVF_ENERGY_AREA`.
    pub energy: u32,
    /// One of `UVF_BOUNDARY_*` (default circle); a circle or square is scaled so that the DCP
    /// map's UV area equals the surface area, given positions are used as given.
    pub boundary: u32,
    /// One of `UVF_DISTRIBUTION_*` (default chord length).
    pub distribution: u32,
    /// Smallest λ allowed (default -INFINITY).
    pub lambda_min: f64,
    /// Largest λ allowed (default +INFINITY).
    pub lambda_max: f64,
    /// Number of entries of `given_vertices` for `UVF_BOUNDARY_GIVEN`.
    pub given_count: usize,
    /// Boundary vertices whose UV is given; must cover whole boundary loops.
    pub given_vertices: *const u32,
    /// 2 doubles per given vertex.
    pub given_uv: *const f64,
    /// Optional progress callback (may be NULL).
    pub progress: UvfProgressFn,
    /// Passed to `progress` unchanged.
    pub progress_user: *mut c_void,
}

impl Default for UvfIntrinsicOptimalOptions {
    fn default() -> Self {
        UvfIntrinsicOptimalOptions {
            struct_size: std::mem::size_of::<Self>(),
            energy: UVF_ENERGY_EDGE_LENGTH,
            boundary: UVF_BOUNDARY_CIRCLE,
            distribution: UVF_DISTRIBUTION_CHORD,
            lambda_min: f64::NEG_INFINITY,
            lambda_max: f64::INFINITY,
            given_count: 0,
            given_vertices: std::ptr::null(),
            given_uv: std::ptr::null(),
            progress: None,
            progress_user: std::ptr::null_mut(),
        }
    }
}

/// What `uvf_intrinsic_optimal_map` reports.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct UvfIntrinsicOptimalReport {
    /// `sizeof(UvfIntrinsicOptimalReport)`, set by the caller before the call; the library writes only the fields
    /// that fit in that many bytes (see Versioning at the top of the header).
    pub struct_size: usize,
    /// The minimizing λ of `λ·U^A + (1 − λ)·U^χ`.
    pub lambda: f64,
    /// The energy at λ.
    pub energy: f64,
    /// The energy of the DCP map (λ = 1).
    pub energy_conformal: f64,
    /// The energy of the DAP map (λ = 0).
    pub energy_authalic: f64,
    /// Factor applied to the circle or square boundary (1 for given positions).
    pub boundary_scale: f64,
    /// Clockwise or degenerate UV triangles of the result (λ outside [0, 1] can fold).
    pub flipped: usize,
}

/// Fills `options` with defaults (edge-length energy, circle, chord length, λ unbounded).
///
/// # Safety
/// `options` must be NULL or point to a writable struct.
#[no_mangle]
pub unsafe extern "C" fn uvf_intrinsic_optimal_options_default(options: *mut UvfIntrinsicOptimalOptions) {
    if !options.is_null() {
        options.write(UvfIntrinsicOptimalOptions::default());
    }
}

const OPTIMAL_OPTIONS_V1: usize = std::mem::size_of::<UvfIntrinsicOptimalOptions>();

/// Near-optimal intrinsic map (Desbrun et al. 2002 §5.1, eq. 8): the map
/// `λ·U^A + (1 − λ)·U^χ` (U^A the DCP map, U^χ the DAP map, same boundary) minimizing the
/// chosen distortion energy over λ in [`lambda_min`, `lambda_max`]. The energy is an exact
/// polynomial in λ (degree 4 for edge lengths, 8 for areas); its minimum is found by root
/// finding on the derivative and compared with the range's ends and with λ = 0 and λ = 1, so
/// the result is never worse than pure DCP or pure DAP when they are in the range.
///
/// `uv_out` receives 2 doubles per vertex; `options` and `report_out` may be NULL. Returns
/// `UVF_OK`, `UVF_INVALID_ARGUMENT` (bad pointer, unknown energy/boundary/distribution, empty
/// or NaN λ range, bad given boundary), `UVF_INVALID_MESH`, `UVF_UNSUPPORTED_TOPOLOGY`,
/// `UVF_NUMERICAL_FAILURE`, `UVF_CANCELLED`, `UVF_INTERNAL_ERROR`. On failure the outputs are
/// untouched.
///
/// # Safety
/// The arrays must hold the stated number of elements; `report_out` must be NULL or writable.
#[no_mangle]
pub unsafe extern "C" fn uvf_intrinsic_optimal_map(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    options: *const UvfIntrinsicOptimalOptions,
    uv_out: *mut f64,
    report_out: *mut UvfIntrinsicOptimalReport,
) -> UvfStatus {
    unsafe {
        intrinsic_optimal_map_from(
            MeshSource::arrays(positions, vertex_count, triangles, triangle_count),
            options,
            uv_out,
            report_out,
        )
    }
}

/// `uvf_intrinsic_optimal_map` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_intrinsic_optimal_map`.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_intrinsic_optimal_map(
    mesh: *const super::mesh_handle::UvfMesh,
    options: *const UvfIntrinsicOptimalOptions,
    uv_out: *mut f64,
    report_out: *mut UvfIntrinsicOptimalReport,
) -> UvfStatus {
    unsafe { intrinsic_optimal_map_from(MeshSource::Handle(mesh), options, uv_out, report_out) }
}

/// `uvf_intrinsic_optimal_map` on either kind of mesh.
///
/// # Safety
/// As for `uvf_intrinsic_optimal_map`.
unsafe fn intrinsic_optimal_map_from(
    source: MeshSource,
    options: *const UvfIntrinsicOptimalOptions,
    uv_out: *mut f64,
    report_out: *mut UvfIntrinsicOptimalReport,
) -> UvfStatus {
    guard(|| {
        let (vertex_count, _) = unsafe { source.counts() }?;
        // Checked before the work, so that a bad report pointer leaves every output untouched.
        let report_out = unsafe { SizedOut::optional(report_out, "report_out", "UvfIntrinsicOptimalReport") }?;
        let o = read_options(
            options,
            UvfIntrinsicOptimalOptions::default(),
            OPTIMAL_OPTIONS_V1,
            "UvfIntrinsicOptimalOptions",
        )?;
        let opts = NearOptimalOptions {
            energy: energy_from(o.energy)?,
            shape: shape_from_parts(o.boundary, o.given_count, o.given_vertices, o.given_uv)?,
            distribution: distribution_from_code(o.distribution)?,
            lambda_min: o.lambda_min,
            lambda_max: o.lambda_max,
        };
        let mesh = unsafe { source.mesh() }?;
        borrow_slice_mut(uv_out, checked_count(vertex_count, 2, "uv")?, "uv_out")?;
        let mut callback = progress_closure(o.progress, o.progress_user);
        let r = near_optimal_map(&mesh, &opts, &mut Progress::new(&mut callback))?;
        write_uv(&r.uv, uv_out)?;
        if let Some(report_out) = &report_out {
            report_out.write(UvfIntrinsicOptimalReport {
                struct_size: 0,
                lambda: r.lambda,
                energy: r.energy,
                energy_conformal: r.energy_conformal,
                energy_authalic: r.energy_authalic,
                boundary_scale: r.boundary_scale,
                flipped: r.flipped,
            });
        }
        Ok(())
    })
}
