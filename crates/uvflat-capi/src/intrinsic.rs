//! Desbrun–Meyer–Alliez 2002 interactive tools: Lagrange point constraints (§4.1), the boundary
//! editor and its Green-function basis (§4.2), near-optimal λ (§5.1), boundary optimization
//! (§5.2); and the spectral conformal map (Mullen et al. 2008).

use super::methods::{
    distribution_from_code, shape_from_parts, UvfFixedBoundaryOptions, UVF_BOUNDARY_CIRCLE, UVF_DISTRIBUTION_CHORD,
};
use super::status::UvfStatus;
use super::MeshSource;
use super::SizedOut;
use super::{
    borrow_slice, borrow_slice_mut, checked_count, guard, progress_closure, read_options, write_uv, UvfProgressFn,
};
use std::os::raw::c_void;
use uvflat_core::error::{Error, Result};
use uvflat_core::methods::boundary_optimization::{boundary_optimized_map, BoundaryOptimizationOptions};
use uvflat_core::methods::constraints::{
    constrained_fixed_boundary_map, constrained_natural_conformal_map, pinned_natural_conformal_map, PointConstraint,
};
use uvflat_core::methods::intrinsic::BoundaryEditor;
use uvflat_core::methods::length_area_distortion::DistortionEnergy;
use uvflat_core::methods::near_optimal::{near_optimal_map, NearOptimalOptions};
use uvflat_core::methods::spectral_conformal::{spectral_conformal_map, SpectralOptions};
use uvflat_core::progress::Progress;

/// A point of the surface (triangle index and barycentric coordinates with respect to its
/// three corners, normalized by their sum) and the UV it must map to.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct UvfPointConstraint {
    /// Triangle index (< triangle_count).
    pub triangle: u32,
    /// Barycentric coordinates of the point (must not sum to zero).
    pub barycentric: [f64; 3],
    /// Target UV.
    pub uv: [f64; 2],
}

/// Options of the constrained natural conformal maps and of the boundary editor. Initialise
/// with `uvf_intrinsic_tool_options_default`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct UvfIntrinsicToolOptions {
    /// `sizeof(UvfIntrinsicToolOptions)`, set by the default initialiser.
    pub struct_size: usize,
    /// Optional progress callback (may be NULL).
    pub progress: UvfProgressFn,
    /// Passed to `progress` unchanged.
    pub progress_user: *mut c_void,
}

impl Default for UvfIntrinsicToolOptions {
    fn default() -> Self {
        UvfIntrinsicToolOptions {
            struct_size: std::mem::size_of::<Self>(),
            progress: None,
            progress_user: std::ptr::null_mut(),
        }
    }
}

const TOOL_OPTIONS_V1: usize = std::mem::size_of::<UvfIntrinsicToolOptions>();

/// Fills `options` with defaults (no progress callback).
///
/// # Safety
/// `options` must be NULL or point to a writable struct.
#[no_mangle]
pub unsafe extern "C" fn uvf_intrinsic_tool_options_default(options: *mut UvfIntrinsicToolOptions) {
    if !options.is_null() {
        options.write(UvfIntrinsicToolOptions::default());
    }
}

fn constraints_from(ptr: *const UvfPointConstraint, count: usize) -> Result<Vec<PointConstraint>> {
    Ok(borrow_slice(ptr, count, "constraints")?
        .iter()
        .map(|c| PointConstraint { triangle: c.triangle, barycentric: c.barycentric, uv: c.uv })
        .collect())
}

/// Fixed-boundary map with point constraints (Desbrun et al. 2002 §4.1, Lagrange multipliers):
/// the map of `uvf_fixed_boundary_map` (same `options`, any weights and boundary) with each of
/// the `constraint_count` points of `constraints` placed exactly on its target. Already
/// satisfied constraints leave the map unchanged.
///
/// `uv_out` receives 2 doubles per vertex. Returns `UVF_OK`; `UVF_INVALID_ARGUMENT` for a bad
/// pointer, option, triangle index, zero-sum barycentric coordinates, a non-finite target, or
/// conflicting constraints (linearly dependent ones with different targets, or a point whose
/// triangle lies entirely on the fixed boundary given another position — the message names the
/// constraint); `UVF_INVALID_MESH`, `UVF_UNSUPPORTED_TOPOLOGY`, `UVF_NUMERICAL_FAILURE`,
/// `UVF_CANCELLED`, `UVF_INTERNAL_ERROR`. On failure `uv_out` is untouched.
///
/// # Safety
/// The arrays must hold the stated number of elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_constrained_fixed_boundary_map(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    options: *const UvfFixedBoundaryOptions,
    constraints: *const UvfPointConstraint,
    constraint_count: usize,
    uv_out: *mut f64,
) -> UvfStatus {
    unsafe {
        constrained_fixed_boundary_map_from(
            MeshSource::arrays(positions, vertex_count, triangles, triangle_count),
            options,
            constraints,
            constraint_count,
            uv_out,
        )
    }
}

/// `uvf_constrained_fixed_boundary_map` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_constrained_fixed_boundary_map`.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_constrained_fixed_boundary_map(
    mesh: *const super::mesh_handle::UvfMesh,
    options: *const UvfFixedBoundaryOptions,
    constraints: *const UvfPointConstraint,
    constraint_count: usize,
    uv_out: *mut f64,
) -> UvfStatus {
    unsafe {
        constrained_fixed_boundary_map_from(MeshSource::Handle(mesh), options, constraints, constraint_count, uv_out)
    }
}

/// `uvf_constrained_fixed_boundary_map` on either kind of mesh.
///
/// # Safety
/// As for `uvf_constrained_fixed_boundary_map`.
unsafe fn constrained_fixed_boundary_map_from(
    source: MeshSource,
    options: *const UvfFixedBoundaryOptions,
    constraints: *const UvfPointConstraint,
    constraint_count: usize,
    uv_out: *mut f64,
) -> UvfStatus {
    guard(|| {
        let o = read_options(
            options,
            UvfFixedBoundaryOptions::default(),
            std::mem::size_of::<UvfFixedBoundaryOptions>(),
            "UvfFixedBoundaryOptions",
        )?;
        let opts = super::methods::fixed_options_from(&o)?;
        let c = constraints_from(constraints, constraint_count)?;
        let mesh = unsafe { source.mesh() }?;
        let mut callback = progress_closure(o.progress, o.progress_user);
        let uv = constrained_fixed_boundary_map(&mesh, &opts, &c, &mut Progress::new(&mut callback))?;
        write_uv(&uv, uv_out)
    })
}

/// Natural conformal map (Desbrun et al. 2002 §4.2 eq. 7 = LSCM) with point constraints
/// instead of two pins (§4.1): minimizes the conformal energy subject to every constraint.
/// Needs at least 2 constraints, not all with the same target; two vertex constraints give
/// the 2-pin natural conformal map.
///
/// `uv_out` receives 2 doubles per vertex (NaN for unreferenced vertices); `options` may be
/// NULL. Statuses as `uvf_constrained_fixed_boundary_map`.
///
/// # Safety
/// The arrays must hold the stated number of elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_constrained_natural_conformal_map(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    constraints: *const UvfPointConstraint,
    constraint_count: usize,
    options: *const UvfIntrinsicToolOptions,
    uv_out: *mut f64,
) -> UvfStatus {
    unsafe {
        constrained_natural_conformal_map_from(
            MeshSource::arrays(positions, vertex_count, triangles, triangle_count),
            constraints,
            constraint_count,
            options,
            uv_out,
        )
    }
}

/// `uvf_constrained_natural_conformal_map` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_constrained_natural_conformal_map`.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_constrained_natural_conformal_map(
    mesh: *const super::mesh_handle::UvfMesh,
    constraints: *const UvfPointConstraint,
    constraint_count: usize,
    options: *const UvfIntrinsicToolOptions,
    uv_out: *mut f64,
) -> UvfStatus {
    unsafe {
        constrained_natural_conformal_map_from(MeshSource::Handle(mesh), constraints, constraint_count, options, uv_out)
    }
}

/// `uvf_constrained_natural_conformal_map` on either kind of mesh.
///
/// # Safety
/// As for `uvf_constrained_natural_conformal_map`.
unsafe fn constrained_natural_conformal_map_from(
    source: MeshSource,
    constraints: *const UvfPointConstraint,
    constraint_count: usize,
    options: *const UvfIntrinsicToolOptions,
    uv_out: *mut f64,
) -> UvfStatus {
    guard(|| {
        let o = read_options(options, UvfIntrinsicToolOptions::default(), TOOL_OPTIONS_V1, "UvfIntrinsicToolOptions")?;
        let c = constraints_from(constraints, constraint_count)?;
        let mesh = unsafe { source.mesh() }?;
        let mut callback = progress_closure(o.progress, o.progress_user);
        let uv = constrained_natural_conformal_map(&mesh, &c, &mut Progress::new(&mut callback))?;
        write_uv(&uv, uv_out)
    })
}

/// Natural conformal map with any number (≥ 2) of pinned vertices: `pin_vertices[i]` goes to
/// (`pin_uv[2i]`, `pin_uv[2i+1]`) (vertex constraints, Desbrun et al. 2002 §4.1). Pins that
/// conflict (one vertex pinned twice to different places) give `UVF_INVALID_ARGUMENT`.
///
/// `pin_vertices` holds `pin_count` indices, `pin_uv` 2·`pin_count` doubles; `uv_out` 2 doubles
/// per vertex. Statuses as `uvf_constrained_fixed_boundary_map`.
///
/// # Safety
/// The arrays must hold the stated number of elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_pinned_natural_conformal_map(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    pin_vertices: *const u32,
    pin_uv: *const f64,
    pin_count: usize,
    options: *const UvfIntrinsicToolOptions,
    uv_out: *mut f64,
) -> UvfStatus {
    unsafe {
        pinned_natural_conformal_map_from(
            MeshSource::arrays(positions, vertex_count, triangles, triangle_count),
            pin_vertices,
            pin_uv,
            pin_count,
            options,
            uv_out,
        )
    }
}

/// `uvf_pinned_natural_conformal_map` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_pinned_natural_conformal_map`.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_pinned_natural_conformal_map(
    mesh: *const super::mesh_handle::UvfMesh,
    pin_vertices: *const u32,
    pin_uv: *const f64,
    pin_count: usize,
    options: *const UvfIntrinsicToolOptions,
    uv_out: *mut f64,
) -> UvfStatus {
    unsafe {
        pinned_natural_conformal_map_from(MeshSource::Handle(mesh), pin_vertices, pin_uv, pin_count, options, uv_out)
    }
}

/// `uvf_pinned_natural_conformal_map` on either kind of mesh.
///
/// # Safety
/// As for `uvf_pinned_natural_conformal_map`.
unsafe fn pinned_natural_conformal_map_from(
    source: MeshSource,
    pin_vertices: *const u32,
    pin_uv: *const f64,
    pin_count: usize,
    options: *const UvfIntrinsicToolOptions,
    uv_out: *mut f64,
) -> UvfStatus {
    guard(|| {
        let o = read_options(options, UvfIntrinsicToolOptions::default(), TOOL_OPTIONS_V1, "UvfIntrinsicToolOptions")?;
        let v = borrow_slice(pin_vertices, pin_count, "pin_vertices")?;
        let p = borrow_slice(pin_uv, checked_count(pin_count, 2, "pin")?, "pin_uv")?;
        let pins: Vec<(u32, [f64; 2])> = v.iter().zip(p.chunks_exact(2)).map(|(&v, p)| (v, [p[0], p[1]])).collect();
        let mesh = unsafe { source.mesh() }?;
        let mut callback = progress_closure(o.progress, o.progress_user);
        let uv = pinned_natural_conformal_map(&mesh, &pins, &mut Progress::new(&mut callback))?;
        write_uv(&uv, uv_out)
    })
}

/// A factored intrinsic map whose boundary can be moved (opaque; create with
/// `uvf_boundary_editor_new`, free with `uvf_boundary_editor_free`).
pub struct UvfBoundaryEditor {
    inner: BoundaryEditor,
}

/// Factors the intrinsic map λ·DCP + μ·DAP (Desbrun et al. 2002 §3.4) of a disk (holes are
/// filled) with its outer boundary fixed, for real-time boundary editing (§4.2). On success
/// `*editor_out` owns the editor (free it with `uvf_boundary_editor_free`); it does not keep
/// pointers to the input arrays. Cost: one sparse factorization (Cholesky when μ = 0, LU
/// otherwise).
///
/// Returns `UVF_OK`, `UVF_INVALID_ARGUMENT` (NULL `editor_out`, non-finite λ/μ or both zero),
/// `UVF_INVALID_MESH`, `UVF_UNSUPPORTED_TOPOLOGY`, `UVF_NUMERICAL_FAILURE`, `UVF_CANCELLED`,
/// `UVF_INTERNAL_ERROR`. On failure `*editor_out` is set to NULL.
///
/// # Safety
/// The arrays must hold the stated number of elements; `editor_out` must be writable.
#[no_mangle]
pub unsafe extern "C" fn uvf_boundary_editor_new(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    lambda: f64,
    mu: f64,
    options: *const UvfIntrinsicToolOptions,
    editor_out: *mut *mut UvfBoundaryEditor,
) -> UvfStatus {
    unsafe {
        boundary_editor_new_from(
            MeshSource::arrays(positions, vertex_count, triangles, triangle_count),
            lambda,
            mu,
            options,
            editor_out,
        )
    }
}

/// `uvf_boundary_editor_new` on a mesh handle of `uvf_mesh_new` (validated once; polygons triangulated):
/// the same options, outputs and statuses, with the handle's vertex and triangle counts.
///
/// # Safety
/// `mesh` must be a live handle or NULL; the other pointers as for `uvf_boundary_editor_new`.
#[no_mangle]
pub unsafe extern "C" fn uvf_mesh_boundary_editor_new(
    mesh: *const super::mesh_handle::UvfMesh,
    lambda: f64,
    mu: f64,
    options: *const UvfIntrinsicToolOptions,
    editor_out: *mut *mut UvfBoundaryEditor,
) -> UvfStatus {
    unsafe { boundary_editor_new_from(MeshSource::Handle(mesh), lambda, mu, options, editor_out) }
}

/// `uvf_boundary_editor_new` on either kind of mesh.
///
/// # Safety
/// As for `uvf_boundary_editor_new`.
unsafe fn boundary_editor_new_from(
    source: MeshSource,
    lambda: f64,
    mu: f64,
    options: *const UvfIntrinsicToolOptions,
    editor_out: *mut *mut UvfBoundaryEditor,
) -> UvfStatus {
    if !editor_out.is_null() {
        editor_out.write(std::ptr::null_mut());
    }
    guard(|| {
        if editor_out.is_null() {
            return Err(Error::InvalidArgument("editor_out is NULL".into()));
        }
        let o = read_options(options, UvfIntrinsicToolOptions::default(), TOOL_OPTIONS_V1, "UvfIntrinsicToolOptions")?;
        let mesh = unsafe { source.mesh() }?;
        let mut callback = progress_closure(o.progress, o.progress_user);
        let inner = BoundaryEditor::new(&mesh, lambda, mu, &mut Progress::new(&mut callback))?;
        // SAFETY: checked non-null above.
        unsafe { editor_out.write(Box::into_raw(Box::new(UvfBoundaryEditor { inner }))) };
        Ok(())
    })
}

/// Frees an editor made by `uvf_boundary_editor_new` (NULL is ignored).
///
/// # Safety
/// `editor` must be NULL or an editor not yet freed, and no solve may be running on it.
#[no_mangle]
pub unsafe extern "C" fn uvf_boundary_editor_free(editor: *mut UvfBoundaryEditor) {
    if !editor.is_null() {
        // SAFETY: made by Box::into_raw in uvf_boundary_editor_new.
        let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| drop(unsafe { Box::from_raw(editor) })));
    }
}

fn editor_ref<'a>(editor: *const UvfBoundaryEditor) -> Result<&'a BoundaryEditor> {
    if editor.is_null() {
        return Err(Error::InvalidArgument("editor is NULL".into()));
    }
    // SAFETY: the caller passes a live editor.
    Ok(unsafe { &(*editor).inner })
}

/// Number of boundary vertices of the editor's outer loop (`*count_out`), and, when
/// `vertices_out` is not NULL, their indices in the order `uvf_boundary_editor_solve` expects
/// (`vertices_out` must hold `*count_out` entries: call once with NULL to get the count).
/// Returns `UVF_OK` or `UVF_INVALID_ARGUMENT`.
///
/// # Safety
/// `editor` must be a live editor; `count_out` writable; `vertices_out` NULL or large enough.
#[no_mangle]
pub unsafe extern "C" fn uvf_boundary_editor_boundary(
    editor: *const UvfBoundaryEditor,
    count_out: *mut usize,
    vertices_out: *mut u32,
) -> UvfStatus {
    guard(|| {
        let e = editor_ref(editor)?;
        let count = borrow_slice_mut(count_out, 1, "count_out")?;
        count[0] = e.boundary_vertices().len();
        if !vertices_out.is_null() {
            borrow_slice_mut(vertices_out, e.boundary_vertices().len(), "vertices_out")?
                .copy_from_slice(e.boundary_vertices());
        }
        Ok(())
    })
}

/// The map for new boundary positions (Desbrun et al. 2002 §4.2): `boundary_uv` holds 2
/// doubles per boundary vertex, in `uvf_boundary_editor_boundary` order (`boundary_count`
/// vertices); `uv_out` receives 2 doubles per mesh vertex (`vertex_count` of the mesh given to
/// `uvf_boundary_editor_new`; NaN for unreferenced vertices). One sparse product and one pair
/// of triangular solves; safe to call concurrently on one editor from several threads.
///
/// Returns `UVF_OK`, `UVF_INVALID_ARGUMENT` (NULL pointers, wrong count, non-finite position),
/// `UVF_NUMERICAL_FAILURE`, `UVF_INTERNAL_ERROR`. On failure `uv_out` is untouched.
///
/// # Safety
/// `editor` must be a live editor; the arrays must hold the stated number of elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_boundary_editor_solve(
    editor: *const UvfBoundaryEditor,
    boundary_uv: *const f64,
    boundary_count: usize,
    uv_out: *mut f64,
) -> UvfStatus {
    guard(|| {
        let e = editor_ref(editor)?;
        let b = borrow_slice(boundary_uv, checked_count(boundary_count, 2, "boundary")?, "boundary_uv")?;
        let pts: Vec<[f64; 2]> = b.chunks_exact(2).map(|p| [p[0], p[1]]).collect();
        let uv = e.solve(&pts)?;
        write_uv(&uv, uv_out)
    })
}

/// The explicit Green-function basis (impulse responses, Desbrun et al. 2002 §4.2): `basis_out`
/// receives b × n doubles (b boundary vertices, n mesh vertices), `basis_out[i * n + v]` being
/// the weight of boundary vertex i in the UV of vertex v, so that
/// `uv[v] = Σ_i basis_out[i * n + v] · boundary_uv[i]`. Memory: 8·n·b bytes; when that exceeds
/// `max_bytes` the call returns `UVF_INVALID_ARGUMENT` without computing anything. Cost: b
/// solves (in blocks of 32).
///
/// Returns `UVF_OK`, `UVF_INVALID_ARGUMENT`, `UVF_NUMERICAL_FAILURE`, `UVF_INTERNAL_ERROR`.
///
/// # Safety
/// `editor` must be a live editor; `basis_out` must hold b·n doubles.
#[no_mangle]
pub unsafe extern "C" fn uvf_boundary_editor_basis(
    editor: *const UvfBoundaryEditor,
    max_bytes: usize,
    basis_out: *mut f64,
) -> UvfStatus {
    guard(|| {
        let e = editor_ref(editor)?;
        let basis = e.green_basis(max_bytes, &mut Progress::none())?;
        borrow_slice_mut(basis_out, basis.values.len(), "basis_out")?.copy_from_slice(&basis.values);
        Ok(())
    })
}

/// Edge-length distortion `Σ_edges (|u_i − u_j|² / |x_i − x_j|² − 1)²` (Desbrun et al. 2002 §5.1).
pub const UVF_ENERGY_EDGE_LENGTH: u32 = 0;
/// Area distortion `Σ_faces ((A^uv / A^3D)² − 1)²` (Desbrun et al. 2002 §5.1, as printed).
pub const UVF_ENERGY_AREA: u32 = 1;

fn energy_from(code: u32) -> Result<DistortionEnergy> {
    match code {
        UVF_ENERGY_EDGE_LENGTH => Ok(DistortionEnergy::EdgeLength),
        UVF_ENERGY_AREA => Ok(DistortionEnergy::Area),
        e => Err(Error::InvalidArgument(format!("unknown energy {e}; use UVF_ENERGY_EDGE_LENGTH or UVF_ENERGY_AREA"))),
    }
}

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
