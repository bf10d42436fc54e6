//! The boundary editor (Desbrun, Meyer & Alliez 2002, §4.2): a fixed-boundary map factored once,
//! then solved for every new boundary, and its Green-function basis.

use super::status::UvfStatus;
use super::MeshSource;
use super::{borrow_slice, borrow_slice_mut, checked_count, guard, progress_closure, read_options, write_uv};
use crate::constraints::{UvfIntrinsicToolOptions, TOOL_OPTIONS_V1};
use uvflat_core::error::{Error, Result};
use uvflat_core::methods::intrinsic::BoundaryEditor;
use uvflat_core::progress::Progress;

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
