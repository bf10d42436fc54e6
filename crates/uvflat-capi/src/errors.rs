//! Thread-local error message, version queries and the panic hook that keeps panics quiet.

use std::cell::{Cell, RefCell};
use std::ffi::CString;
use std::os::raw::c_char;
use std::sync::atomic::{AtomicUsize, Ordering};
use uvflat_core::error::Error;

/// ABI version: the major version of the library. A program built against a header whose
/// `UVF_ABI_VERSION` equals the loaded library's `uvf_abi_version()` can call it. (The header's
/// macro is written with the other version macros by `crates/uvflat-capi/tests/it/c_abi.rs`.)
pub(crate) const UVF_ABI_VERSION: u32 = 1;

thread_local! {
    /// The last failure's message; kept (not freed) by successful calls, so a pointer from
    /// `uvf_last_error_message` stays valid until the next failing call on this thread.
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
    /// Whether the last call on this thread failed.
    static FAILED: Cell<bool> = const { Cell::new(false) };
    /// Whether this thread is inside a C entry point (its panics are caught and reported).
    static IN_ENTRY_POINT: Cell<bool> = const { Cell::new(false) };
}

pub(crate) fn set_last_error(e: &Error) {
    let text = e.to_string().replace('\0', " ");
    LAST_ERROR.with(|m| *m.borrow_mut() = CString::new(text).unwrap_or_default());
    FAILED.with(|f| f.set(true));
}

pub(crate) fn clear_last_error() {
    FAILED.with(|f| f.set(false));
}

/// Human-readable message of the last call on this thread if it failed, "" if it succeeded.
/// The pointer stays valid until the next *failing* uvflat call on the same thread (successful
/// calls do not invalidate it) or the thread's exit; copy it with `uvf_last_error` to keep it.
#[no_mangle]
pub extern "C" fn uvf_last_error_message() -> *const c_char {
    if FAILED.with(|f| f.get()) {
        LAST_ERROR.with(|m| m.borrow().as_ptr())
    } else {
        c"".as_ptr()
    }
}

/// Copies the message of `uvf_last_error_message` into `buffer` (capacity `capacity` bytes,
/// always NUL-terminated when `capacity > 0`, truncated if needed; `buffer` may be NULL when
/// `capacity` is 0). Returns the message's full length in bytes without the NUL, as `snprintf`
/// does, so a result ≥ `capacity` means it was truncated.
///
/// # Safety
/// `buffer` must point to `capacity` writable bytes.
#[no_mangle]
pub unsafe extern "C" fn uvf_last_error(buffer: *mut c_char, capacity: usize) -> usize {
    let failed = FAILED.with(|f| f.get());
    LAST_ERROR.with(|m| {
        let message = m.borrow();
        let bytes = if failed { message.as_bytes() } else { &[] };
        if capacity > 0 && !buffer.is_null() {
            let n = bytes.len().min(capacity - 1);
            // SAFETY: the caller owns `capacity` bytes at `buffer`; n + 1 ≤ capacity.
            unsafe {
                std::ptr::copy_nonoverlapping(bytes.as_ptr(), buffer as *mut u8, n);
                *buffer.add(n) = 0;
            }
        }
        bytes.len()
    })
}

/// Library version as a static NUL-terminated string, e.g. "1.0.0" (`UVF_VERSION_STRING` in
/// the header the program was built with).
#[no_mangle]
pub extern "C" fn uvf_version() -> *const c_char {
    static VERSION: &str = concat!(env!("CARGO_PKG_VERSION"), "\0");
    VERSION.as_ptr() as *const c_char
}

/// Library version as one number, `major * 10000 + minor * 100 + patch` (the encoding of
/// `UVF_VERSION_NUMBER` in the header).
#[no_mangle]
pub extern "C" fn uvf_version_number() -> u32 {
    let part = |s: &str| s.parse::<u32>().unwrap_or(0);
    part(env!("CARGO_PKG_VERSION_MAJOR")) * 10000
        + part(env!("CARGO_PKG_VERSION_MINOR")) * 100
        + part(env!("CARGO_PKG_VERSION_PATCH"))
}

/// ABI version of the loaded library; compare with `UVF_ABI_VERSION` from the header.
#[no_mangle]
pub extern "C" fn uvf_abi_version() -> u32 {
    UVF_ABI_VERSION
}

/// Runs `f` marked as inside a C entry point, so that the panic hook keeps quiet about a panic
/// in it (the entry point catches the panic and returns its message as the error).
pub(crate) fn in_entry_point<R>(f: impl FnOnce() -> R) -> R {
    install_quiet_panic_hook();
    let outer = IN_ENTRY_POINT.with(|c| c.replace(true));
    ACTIVE_ENTRY_POINTS.fetch_add(1, Ordering::SeqCst);
    let result = f();
    ACTIVE_ENTRY_POINTS.fetch_sub(1, Ordering::SeqCst);
    IN_ENTRY_POINT.with(|c| c.set(outer));
    result
}

/// C entry points running now, on any thread.
static ACTIVE_ENTRY_POINTS: AtomicUsize = AtomicUsize::new(0);

/// Installs (once) a panic hook that prints nothing for panics inside C entry points and on the
/// library's worker threads while an entry point runs (a worker's panic reaches the entry point
/// that started the work),
/// and hands every other panic to the hook that was installed before. A host application's
/// stderr then never shows a uvflat panic: the caller gets `UVF_INTERNAL_ERROR` and the message.
fn install_quiet_panic_hook() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            let worker = rayon::current_thread_index().is_some() && ACTIVE_ENTRY_POINTS.load(Ordering::SeqCst) > 0;
            let quiet = IN_ENTRY_POINT.with(|c| c.get()) || worker;
            if !quiet {
                previous(info);
            }
        }));
    });
}

#[cfg(test)]
mod tests {
    use super::super::{guard, UvfStatus};
    use super::*;

    #[test]
    fn a_panic_in_an_entry_point_becomes_an_internal_error_with_its_message() {
        let status = guard(|| panic!("boom in a test"));
        assert_eq!(status, UvfStatus::UVF_INTERNAL_ERROR);
        let mut buffer = [0 as c_char; 128];
        // SAFETY: a writable buffer of the stated size.
        let length = unsafe { uvf_last_error(buffer.as_mut_ptr(), buffer.len()) };
        // SAFETY: uvf_last_error NUL-terminates.
        let text = unsafe { std::ffi::CStr::from_ptr(buffer.as_ptr()) }.to_string_lossy().into_owned();
        assert_eq!(length, text.len());
        assert!(text.contains("boom in a test") && text.contains("please report"), "{text}");
        assert!(!IN_ENTRY_POINT.with(|c| c.get()), "the entry-point mark is cleared after a panic");
    }
}
