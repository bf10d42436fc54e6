//! The C ABI. Nothing here but pointer checks, conversions and calls into the Rust API:
//! every entry point runs inside [`guard`], which catches panics and turns a `Result` into a
//! [`UvfStatus`] while storing the error text for [`errors::uvf_last_error_message`].
//!
//! Conventions (DESIGN.md): borrowed flat input arrays with explicit counts; caller-allocated
//! outputs whose lengths are documented; options structs whose first field is their own size;
//! outputs are left untouched when a call fails.

pub mod abf;
pub mod atlas;
pub mod barycentric;
pub mod boundary_editor;
pub mod boundary_optimization;
pub mod circle_patterns;
pub mod cone_placement;
pub mod conformal;
pub mod constraints;
pub mod cut;
pub mod errors;
pub mod islands;
pub mod mesh;
pub mod mesh_handle;
pub mod metrics;
pub mod near_optimal;
pub mod nonlinear;
pub mod pack;
pub mod pgp;
pub mod quadcover;
pub mod snapped;
pub mod spectral;
pub mod sphere;
pub mod status;
pub mod threads;
pub mod unwrap;

pub use status::{status_of, UvfStatus};
use std::os::raw::{c_int, c_void};
use std::panic::{catch_unwind, AssertUnwindSafe};
use uvflat_core::error::{Error, Result};
use uvflat_core::TriMesh;

/// Progress callback: receives the caller's `user` pointer and the fraction done in [0, 1];
/// returning non-zero cancels the computation (the call then returns `UVF_CANCELLED`).
pub type UvfProgressFn = Option<unsafe extern "C" fn(user: *mut c_void, fraction: f64) -> c_int>;

/// Runs `f`, converting errors and panics into a status and the thread-local message.
pub(crate) fn guard(f: impl FnOnce() -> Result<()>) -> UvfStatus {
    let outcome = errors::in_entry_point(|| catch_unwind(AssertUnwindSafe(f)));
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
            status::status_of(&e)
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

/// Where a C call's mesh comes from: flat arrays, validated and built for this call, or a
/// handle of `uvf_mesh_new`, built once.
#[derive(Clone, Copy)]
pub(crate) enum MeshSource {
    Arrays { positions: *const f64, vertex_count: usize, triangles: *const u32, triangle_count: usize },
    Handle(*const mesh_handle::UvfMesh),
}

/// A mesh built for one call, or borrowed from a handle.
pub(crate) enum MeshRef<'a> {
    Built(TriMesh),
    Borrowed(&'a TriMesh),
}

impl MeshRef<'_> {
    /// The mesh as an owned value (a copy of a handle's), for results that keep it.
    pub(crate) fn into_owned(self) -> TriMesh {
        match self {
            MeshRef::Built(m) => m,
            MeshRef::Borrowed(m) => m.clone(),
        }
    }
}

impl std::ops::Deref for MeshRef<'_> {
    type Target = TriMesh;
    fn deref(&self) -> &TriMesh {
        match self {
            MeshRef::Built(m) => m,
            MeshRef::Borrowed(m) => m,
        }
    }
}

impl MeshSource {
    pub(crate) fn arrays(
        positions: *const f64,
        vertex_count: usize,
        triangles: *const u32,
        triangle_count: usize,
    ) -> Self {
        MeshSource::Arrays { positions, vertex_count, triangles, triangle_count }
    }

    /// The vertex and triangle counts (of the arrays as given, or of the handle's mesh).
    ///
    /// # Safety
    /// A handle must be live or NULL.
    pub(crate) unsafe fn counts(self) -> Result<(usize, usize)> {
        match self {
            MeshSource::Arrays { vertex_count, triangle_count, .. } => Ok((vertex_count, triangle_count)),
            MeshSource::Handle(mesh) => {
                let m = &unsafe { mesh_handle::handle(mesh) }?.mesh;
                Ok((m.vertex_count(), m.triangle_count()))
            }
        }
    }

    /// The mesh: validated and built from the arrays, or the handle's.
    ///
    /// # Safety
    /// The arrays must hold the stated counts; a handle must be live or NULL.
    pub(crate) unsafe fn mesh<'a>(self) -> Result<MeshRef<'a>> {
        match self {
            MeshSource::Arrays { positions, vertex_count, triangles, triangle_count } => {
                mesh_from_raw(positions, vertex_count, triangles, triangle_count).map(MeshRef::Built)
            }
            MeshSource::Handle(mesh) => Ok(MeshRef::Borrowed(&unsafe { mesh_handle::handle(mesh) }?.mesh)),
        }
    }
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

/// A struct the library writes into (a report or info struct), checked before the work starts.
/// Its first field, `struct_size`, is set by the caller to the size of the struct as the
/// caller's header declares it; the library writes only the fields that fit in that many bytes
/// and never touches `struct_size`, so a program built against an older, shorter struct keeps
/// working when fields are appended.
pub(crate) struct SizedOut<T> {
    ptr: *mut T,
    size: usize,
}

impl<T: Copy> SizedOut<T> {
    /// `ptr` checked: NULL gives `None` (the caller does not want this output).
    ///
    /// # Safety
    /// A non-null `ptr` must point to `(*ptr).struct_size` writable bytes.
    pub(crate) unsafe fn optional(ptr: *mut T, what: &'static str, type_name: &'static str) -> Result<Option<Self>> {
        if ptr.is_null() {
            return Ok(None);
        }
        if (ptr as usize) % std::mem::align_of::<T>() != 0 {
            return Err(Error::InvalidArgument(format!("{what} is not aligned for {type_name}")));
        }
        // SAFETY: non-null and aligned; every such struct starts with its size, a size_t.
        let size = unsafe { (ptr as *const usize).read() };
        if size <= std::mem::size_of::<usize>() {
            return Err(Error::InvalidArgument(format!(
                "{what}->struct_size is {size}: set it to sizeof({type_name}) before the call"
            )));
        }
        Ok(Some(SizedOut { ptr, size }))
    }

    /// As [`SizedOut::optional`], but NULL is an error.
    ///
    /// # Safety
    /// As for [`SizedOut::optional`].
    pub(crate) unsafe fn required(ptr: *mut T, what: &'static str, type_name: &'static str) -> Result<Self> {
        unsafe { Self::optional(ptr, what, type_name) }?
            .ok_or_else(|| Error::InvalidArgument(format!("{what} is NULL; it must point to a {type_name}")))
    }

    /// Writes `value`'s fields after `struct_size`, as many bytes of them as the caller's
    /// struct holds.
    pub(crate) fn write(&self, value: T) {
        let start = std::mem::size_of::<usize>();
        let end = self.size.min(std::mem::size_of::<T>());
        if end > start {
            // SAFETY: the caller declared `size` ≥ `end` writable bytes at `ptr`; `value` is a
            // `T` of at least `end` bytes, copied as possibly-uninitialised bytes (its padding).
            unsafe {
                std::ptr::copy_nonoverlapping(
                    (&value as *const T as *const std::mem::MaybeUninit<u8>).add(start),
                    (self.ptr as *mut std::mem::MaybeUninit<u8>).add(start),
                    end - start,
                )
            };
        }
    }
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
) -> Result<Option<[uvflat_core::methods::conformal::Pin; 2]>> {
    match count {
        0 => Ok(None),
        2 => Ok(Some([(vertices[0], [uv[0], uv[1]]), (vertices[1], [uv[2], uv[3]])])),
        n => Err(Error::InvalidArgument(format!("pin_count must be 0 or 2, not {n}"))),
    }
}
