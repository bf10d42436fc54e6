//! The C ABI. Nothing here but pointer checks, conversions and calls into the Rust API:
//! every entry point runs inside [`guard`], which catches panics and turns a `Result` into a
//! [`UvfStatus`] while storing the error text for [`errors::uvf_last_error_message`].
//!
//! Conventions (DESIGN.md): borrowed flat input arrays with explicit counts; caller-allocated
//! outputs whose lengths are documented; options structs whose first field is their own size;
//! outputs are left untouched when a call fails.

pub mod abf;
pub mod atlas;
pub mod circle_patterns;
pub mod closed;
pub mod cone_placement;
pub mod errors;
pub mod intrinsic;
pub mod mesh;
pub mod methods;
pub mod metrics;
pub mod nonlinear;
pub mod pgp;
pub mod quadcover;
pub mod unwrap;

use crate::error::{Error, Result, UvfStatus};
use crate::TriMesh;
use std::os::raw::{c_int, c_void};
use std::panic::{catch_unwind, AssertUnwindSafe};

/// Progress callback: receives the caller's `user` pointer and the fraction done in [0, 1];
/// returning non-zero cancels the computation (the call then returns `UVF_CANCELLED`).
pub type UvfProgressFn = Option<unsafe extern "C" fn(user: *mut c_void, fraction: f64) -> c_int>;

/// Runs `f`, converting errors and panics into a status and the thread-local message.
pub(crate) fn guard(f: impl FnOnce() -> Result<()>) -> UvfStatus {
    let outcome = catch_unwind(AssertUnwindSafe(f));
    let result = match outcome {
        Ok(r) => r,
        Err(payload) => {
            let text = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            Err(Error::Internal(format!("uvflat panicked: {text} (please report this bug)")))
        }
    };
    match result {
        Ok(()) => {
            errors::clear_last_error();
            UvfStatus::UVF_OK
        }
        Err(e) => {
            errors::set_last_error(&e);
            e.status()
        }
    }
}

/// Borrows `count` elements, rejecting null pointers and byte sizes that overflow.
pub(crate) fn borrow_slice<'a, T>(ptr: *const T, count: usize, what: &'static str) -> Result<&'a [T]> {
    if count == 0 {
        return Ok(&[]);
    }
    if ptr.is_null() {
        return Err(Error::InvalidArgument(format!("{what} is NULL but its count is {count}")));
    }
    if count.checked_mul(std::mem::size_of::<T>()).is_none_or(|b| b > isize::MAX as usize) {
        return Err(Error::SizeOverflow { what, count });
    }
    if (ptr as usize) % std::mem::align_of::<T>() != 0 {
        return Err(Error::InvalidArgument(format!("{what} is not aligned for its element type")));
    }
    // SAFETY: non-null, aligned, and the caller promises `count` readable elements.
    Ok(unsafe { std::slice::from_raw_parts(ptr, count) })
}

/// Mutable counterpart of [`borrow_slice`].
pub(crate) fn borrow_slice_mut<'a, T>(ptr: *mut T, count: usize, what: &'static str) -> Result<&'a mut [T]> {
    if count == 0 {
        return Ok(&mut []);
    }
    if ptr.is_null() {
        return Err(Error::InvalidArgument(format!("{what} is NULL but {count} elements must be written")));
    }
    if count.checked_mul(std::mem::size_of::<T>()).is_none_or(|b| b > isize::MAX as usize) {
        return Err(Error::SizeOverflow { what, count });
    }
    if (ptr as usize) % std::mem::align_of::<T>() != 0 {
        return Err(Error::InvalidArgument(format!("{what} is not aligned for its element type")));
    }
    // SAFETY: non-null, aligned, and the caller promises `count` writable elements.
    Ok(unsafe { std::slice::from_raw_parts_mut(ptr, count) })
}

/// `a × b` or a size-overflow error naming `what`.
pub(crate) fn checked_count(count: usize, per: usize, what: &'static str) -> Result<usize> {
    count.checked_mul(per).ok_or(Error::SizeOverflow { what, count })
}

/// Validates the mesh arrays and builds a [`TriMesh`].
pub(crate) fn mesh_from_raw(
    positions: *const f64,
    vertex_count: usize,
    triangles: *const u32,
    triangle_count: usize,
) -> Result<TriMesh> {
    let p = borrow_slice(positions, checked_count(vertex_count, 3, "vertex")?, "positions")?;
    let t = borrow_slice(triangles, checked_count(triangle_count, 3, "triangle")?, "triangles")?;
    TriMesh::new(p, t)
}

/// Reads a versioned options struct: the first field (`struct_size`, a `size_t`) says how many
/// bytes the caller's struct has; fields beyond it keep their defaults; a struct smaller than
/// `min_size` (the first released layout) is rejected.
pub(crate) fn read_options<T: Copy>(ptr: *const T, default: T, min_size: usize, what: &str) -> Result<T> {
    if ptr.is_null() {
        return Ok(default);
    }
    // SAFETY: every options struct starts with a size_t field; the caller owns at least that.
    let size = unsafe { *(ptr as *const usize) };
    if size < min_size {
        return Err(Error::InvalidArgument(format!(
            "{what}.struct_size is {size} but must be at least {min_size}; initialise the struct with its _default() function"
        )));
    }
    let mut out = default;
    let n = size.min(std::mem::size_of::<T>());
    // SAFETY: copying the first `n` bytes the caller declared valid into a defaulted struct.
    unsafe { std::ptr::copy_nonoverlapping(ptr as *const u8, &mut out as *mut T as *mut u8, n) };
    Ok(out)
}

/// Copies `values` into a caller array that must hold at least `values.len()` elements.
pub(crate) fn copy_out<T: Copy>(values: &[T], out: *mut T, capacity: usize, what: &'static str) -> Result<()> {
    if capacity < values.len() {
        return Err(Error::InvalidArgument(format!(
            "{what} holds {capacity} elements but {} are needed",
            values.len()
        )));
    }
    borrow_slice_mut(out, values.len(), what)?.copy_from_slice(values);
    Ok(())
}

/// Wraps an optional C progress callback as a Rust closure.
pub(crate) fn progress_closure(callback: UvfProgressFn, user: *mut c_void) -> impl FnMut(f64) -> bool {
    move |fraction| match callback {
        // SAFETY: the caller provided this function pointer and user data together.
        Some(f) => unsafe { f(user, fraction) == 0 },
        None => true,
    }
}

/// Copies UVs into the caller's output array (2 doubles per vertex).
pub(crate) fn write_uv(uv: &[[f64; 2]], out: *mut f64) -> Result<()> {
    let dst = borrow_slice_mut(out, checked_count(uv.len(), 2, "uv")?, "uv_out")?;
    for (d, s) in dst.chunks_exact_mut(2).zip(uv) {
        d.copy_from_slice(s);
    }
    Ok(())
}

/// The two pins of an options struct's `pin_count`, `pin_vertices`, `pin_uv` fields (natural
/// conformal, ABF and circle-pattern options): `None` for 0 (automatic pins), both for 2.
pub(crate) fn pins_from_options(
    count: u32,
    vertices: [u32; 2],
    uv: [f64; 4],
) -> Result<Option<[crate::methods::conformal::Pin; 2]>> {
    match count {
        0 => Ok(None),
        2 => Ok(Some([(vertices[0], [uv[0], uv[1]]), (vertices[1], [uv[2], uv[3]])])),
        n => Err(Error::InvalidArgument(format!("pin_count must be 0 or 2, not {n}"))),
    }
}
