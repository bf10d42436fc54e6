//! Desbrun–Meyer–Alliez 2002 interactive tools: Lagrange point constraints (§4.1), the boundary
//! editor and its Green-function basis (§4.2); entry points of the methods not implemented yet
//! (spectral conformal, near-optimal λ, boundary optimization) return `UVF_NOT_IMPLEMENTED`.

use super::methods::UvfFixedBoundaryOptions;
use super::{
    borrow_slice, borrow_slice_mut, checked_count, guard, mesh_from_raw, progress_closure, read_options, write_uv,
    UvfProgressFn,
};
use crate::error::{Error, Result, UvfStatus};
use crate::methods::constraints::{
    constrained_fixed_boundary_map, constrained_natural_conformal_map, pinned_natural_conformal_map, PointConstraint,
};
use crate::methods::intrinsic::BoundaryEditor;
use crate::progress::Progress;
use std::os::raw::c_void;

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
    guard(|| {
        let o = read_options(
            options,
            UvfFixedBoundaryOptions::default(),
            std::mem::size_of::<UvfFixedBoundaryOptions>(),
            "UvfFixedBoundaryOptions",
        )?;
        let opts = super::methods::fixed_options_from(&o)?;
        let c = constraints_from(constraints, constraint_count)?;
        let mesh = mesh_from_raw(positions, vertex_count, triangles, triangle_count)?;
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
    guard(|| {
        let o = read_options(options, UvfIntrinsicToolOptions::default(), TOOL_OPTIONS_V1, "UvfIntrinsicToolOptions")?;
        let c = constraints_from(constraints, constraint_count)?;
        let mesh = mesh_from_raw(positions, vertex_count, triangles, triangle_count)?;
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
    guard(|| {
        let o = read_options(options, UvfIntrinsicToolOptions::default(), TOOL_OPTIONS_V1, "UvfIntrinsicToolOptions")?;
        let v = borrow_slice(pin_vertices, pin_count, "pin_vertices")?;
        let p = borrow_slice(pin_uv, checked_count(pin_count, 2, "pin")?, "pin_uv")?;
        let pins: Vec<(u32, [f64; 2])> = v.iter().zip(p.chunks_exact(2)).map(|(&v, p)| (v, [p[0], p[1]])).collect();
        let mesh = mesh_from_raw(positions, vertex_count, triangles, triangle_count)?;
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
    if !editor_out.is_null() {
        editor_out.write(std::ptr::null_mut());
    }
    guard(|| {
        if editor_out.is_null() {
            return Err(Error::InvalidArgument("editor_out is NULL".into()));
        }
        let o = read_options(options, UvfIntrinsicToolOptions::default(), TOOL_OPTIONS_V1, "UvfIntrinsicToolOptions")?;
        let mesh = mesh_from_raw(positions, vertex_count, triangles, triangle_count)?;
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

/// Spectral conformal map (Mullen, Tong, Alliez, Desbrun 2008). Not implemented yet: always
/// returns `UVF_NOT_IMPLEMENTED` (or `UVF_INVALID_ARGUMENT` for NULL mesh arrays).
///
/// # Safety
/// The arrays must hold the stated number of elements.
#[no_mangle]
pub unsafe extern "C" fn uvf_spectral_conformal_map(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    uv_out: *mut f64,
) -> UvfStatus {
    guard(|| {
        let _ = (positions, vertex_count, triangles, triangle_count, uv_out);
        Err(Error::NotImplemented("spectral conformal map (Mullen et al. 2008)"))
    })
}

/// Near-optimal intrinsic map (Desbrun et al. 2002 §5.1). Not implemented yet: always returns
/// `UVF_NOT_IMPLEMENTED`.
///
/// # Safety
/// Never reads its arguments.
#[no_mangle]
pub unsafe extern "C" fn uvf_intrinsic_optimal_map(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    energy: u32,
    lambda_out: *mut f64,
    uv_out: *mut f64,
) -> UvfStatus {
    guard(|| {
        let _ = (positions, vertex_count, triangles, triangle_count, energy, lambda_out, uv_out);
        Err(Error::NotImplemented("near-optimal intrinsic map (Desbrun et al. 2002 §5.1)"))
    })
}

/// Boundary-optimized intrinsic map (Desbrun et al. 2002 §5.2). Not implemented yet: always
/// returns `UVF_NOT_IMPLEMENTED`.
///
/// # Safety
/// Never reads its arguments.
#[no_mangle]
pub unsafe extern "C" fn uvf_boundary_optimized_map(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
    energy: u32,
    uv_out: *mut f64,
) -> UvfStatus {
    guard(|| {
        let _ = (positions, vertex_count, triangles, triangle_count, energy, uv_out);
        Err(Error::NotImplemented("boundary optimization (Desbrun et al. 2002 §5.2)"))
    })
}
