//! Boundary optimization (Desbrun, Meyer & Alliez 2002, §5.2): an intrinsic map whose boundary
//! descends a distortion energy, never flipping.

use super::barycentric::{distribution_from_code, shape_from_parts, UVF_BOUNDARY_CIRCLE, UVF_DISTRIBUTION_CHORD};
use super::status::UvfStatus;
use super::MeshSource;
use super::SizedOut;
use super::{borrow_slice_mut, checked_count, guard, progress_closure, read_options, write_uv, UvfProgressFn};
use crate::near_optimal::{energy_from, UVF_ENERGY_EDGE_LENGTH};
use std::os::raw::c_void;
use uvflat_core::methods::boundary_optimization::{boundary_optimized_map, BoundaryOptimizationOptions};
use uvflat_core::progress::Progress;

/// Options of `uvf_boundary_optimized_map`. Initialise with
/// `uvf_boundary_optimization_options_default`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct UvfBoundaryOptimizationOptions {
    /// `sizeof(UvfBoundaryOptimizationOptions)`, set by the default initialiser.
    pub struct_size: usize,
    /// `UVF_ENERGY_EDGE_LENGTH` (default) or `UVF_ENERGY_AREA`.
    pub energy: u32,
    /// Iteration limit (default 100).
    pub iterations: u32,
    /// λ of the intrinsic map λ·DCP + μ·DAP (default 1).
    pub lambda: f64,
    /// μ of the intrinsic map (default 0).
    pub mu: f64,
    /// Stop when an iteration lowers the energy by less than `tolerance × energy` (default
    /// 1e-6; ≥ 0).
    pub tolerance: f64,
    /// Starting boundary: one of `UVF_BOUNDARY_*` (default circle, scaled to the surface
    /// area); given positions must cover exactly the outer (longest) loop.
    pub boundary: u32,
    /// One of `UVF_DISTRIBUTION_*` (default chord length).
    pub distribution: u32,
    /// Number of entries of `given_vertices` for `UVF_BOUNDARY_GIVEN`.
    pub given_count: usize,
    /// Outer-loop vertices whose starting UV is given.
    pub given_vertices: *const u32,
    /// 2 doubles per given vertex.
    pub given_uv: *const f64,
    /// Optional progress callback (may be NULL), called once before each iteration; returning
    /// non-zero cancels before that iteration.
    pub progress: UvfProgressFn,
    /// Passed to `progress` unchanged.
    pub progress_user: *mut c_void,
}

impl Default for UvfBoundaryOptimizationOptions {
    fn default() -> Self {
        let d = BoundaryOptimizationOptions::default();
        UvfBoundaryOptimizationOptions {
            struct_size: std::mem::size_of::<Self>(),
            energy: UVF_ENERGY_EDGE_LENGTH,
            iterations: d.iterations as u32,
            lambda: d.lambda,
            mu: d.mu,
            tolerance: d.tolerance,
            boundary: UVF_BOUNDARY_CIRCLE,
            distribution: UVF_DISTRIBUTION_CHORD,
            given_count: 0,
            given_vertices: std::ptr::null(),
            given_uv: std::ptr::null(),
            progress: None,
            progress_user: std::ptr::null_mut(),
        }
    }
}

/// What `uvf_boundary_optimized_map` reports.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct UvfBoundaryOptimizationReport {
    /// `sizeof(UvfBoundaryOptimizationReport)`, set by the caller before the call; the library writes only the fields
    /// that fit in that many bytes (see Versioning at the top of the header).
    pub struct_size: usize,
    /// Accepted iterations.
    pub iterations: u32,
    /// 1 when the tolerance was met or no step could lower the energy; 0 when the iteration
    /// limit stopped the descent.
    pub converged: u32,
    /// Entries of the energy history (iterations + 1: the start, then each iteration), also
    /// when `history_capacity` was smaller.
    pub history_length: usize,
    /// Energy of the starting map.
    pub initial_energy: f64,
    /// Energy of the returned map (never above `initial_energy`).
    pub final_energy: f64,
    /// Factor applied to the circle or square start (1 for given positions).
    pub boundary_scale: f64,
    /// Triangles flipped or degenerate in the starting map; no iteration changes any
    /// triangle's orientation, so the result has the same ones (0 for a flip-free start).
    pub flipped: usize,
}

/// Fills `options` with defaults (edge-length energy, DCP, circle, 100 iterations).
///
/// # Safety
/// `options` must be NULL or point to a writable struct.
#[no_mangle]
pub unsafe extern "C" fn uvf_boundary_optimization_options_default(options: *mut UvfBoundaryOptimizationOptions) {
    if !options.is_null() {
        options.write(UvfBoundaryOptimizationOptions::default());
    }
}

const BOUNDARY_OPTIONS_V1: usize = std::mem::size_of::<UvfBoundaryOptimizationOptions>();

/// Boundary-optimized intrinsic map (Desbrun et al. 2002 §5.2): the map λ·DCP + μ·DAP whose
/// outer boundary minimizes the chosen distortion energy, by descent on the boundary positions
/// (gradient through the impulse responses of the factored map, L-BFGS directions, exact line
/// search on the energy polynomial, steps that never flip or degenerate a triangle).
///
/// `uv_out` receives 2 doubles per vertex. `history_out` receives the first
/// `min(history_capacity, history_length)` energies (start first; may be NULL when
/// `history_capacity` is 0); `report_out->history_length` says how many there were. `options`
/// and `report_out` may be NULL. Returns `UVF_OK`, `UVF_INVALID_ARGUMENT`, `UVF_INVALID_MESH`,
/// `UVF_UNSUPPORTED_TOPOLOGY`, `UVF_NUMERICAL_FAILURE`, `UVF_CANCELLED` (the callback stops the
/// run before its next iteration), `UVF_INTERNAL_ERROR`. On failure the outputs are untouched.
///
/// # Safety
/// The arrays must hold the stated number of elements; `report_out` must be NULL or writable.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn uvf_boundary_optimized_map(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    options: *const UvfBoundaryOptimizationOptions,
    uv_out: *mut f64,
    history_out: *mut f64,
    history_capacity: usize,
    report_out: *mut UvfBoundaryOptimizationReport,
) -> UvfStatus {
    unsafe {
        boundary_optimized_map_from(
            MeshSource::arrays(positions, vertex_count, triangles, triangle_count),
            options,
            uv_out,
            history_out,
            history_capacity,
            report_out,
        )
    }
}

/// `uvf_boundary_optimized_map` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_boundary_optimized_map`.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn uvf_mesh_boundary_optimized_map(
    mesh: *const super::mesh_handle::UvfMesh,
    options: *const UvfBoundaryOptimizationOptions,
    uv_out: *mut f64,
    history_out: *mut f64,
    history_capacity: usize,
    report_out: *mut UvfBoundaryOptimizationReport,
) -> UvfStatus {
    unsafe {
        boundary_optimized_map_from(
            MeshSource::Handle(mesh),
            options,
            uv_out,
            history_out,
            history_capacity,
            report_out,
        )
    }
}

/// `uvf_boundary_optimized_map` on either kind of mesh.
///
/// # Safety
/// As for `uvf_boundary_optimized_map`.
#[allow(clippy::too_many_arguments)]
unsafe fn boundary_optimized_map_from(
    source: MeshSource,
    options: *const UvfBoundaryOptimizationOptions,
    uv_out: *mut f64,
    history_out: *mut f64,
    history_capacity: usize,
    report_out: *mut UvfBoundaryOptimizationReport,
) -> UvfStatus {
    guard(|| {
        let (vertex_count, _) = unsafe { source.counts() }?;
        // Checked before the work, so that a bad report pointer leaves every output untouched.
        let report_out = unsafe { SizedOut::optional(report_out, "report_out", "UvfBoundaryOptimizationReport") }?;
        let o = read_options(
            options,
            UvfBoundaryOptimizationOptions::default(),
            BOUNDARY_OPTIONS_V1,
            "UvfBoundaryOptimizationOptions",
        )?;
        let opts = BoundaryOptimizationOptions {
            energy: energy_from(o.energy)?,
            lambda: o.lambda,
            mu: o.mu,
            shape: shape_from_parts(o.boundary, o.given_count, o.given_vertices, o.given_uv)?,
            distribution: distribution_from_code(o.distribution)?,
            iterations: o.iterations as usize,
            tolerance: o.tolerance,
        };
        let mesh = unsafe { source.mesh() }?;
        borrow_slice_mut(uv_out, checked_count(vertex_count, 2, "uv")?, "uv_out")?;
        borrow_slice_mut(history_out, history_capacity, "history_out")?;
        let mut callback = progress_closure(o.progress, o.progress_user);
        let r = boundary_optimized_map(&mesh, &opts, &mut Progress::new(&mut callback))?;
        write_uv(&r.uv, uv_out)?;
        let written = r.history.len().min(history_capacity);
        borrow_slice_mut(history_out, written, "history_out")?.copy_from_slice(&r.history[..written]);
        if let Some(report_out) = &report_out {
            report_out.write(UvfBoundaryOptimizationReport {
                struct_size: 0,
                iterations: r.iterations as u32,
                converged: u32::from(r.converged),
                history_length: r.history.len(),
                initial_energy: r.history.first().copied().unwrap_or(f64::NAN),
                final_energy: r.history.last().copied().unwrap_or(f64::NAN),
                boundary_scale: r.boundary_scale,
                flipped: r.flipped,
            });
        }
        Ok(())
    })
}
