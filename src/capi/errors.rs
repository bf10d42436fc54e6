//! Thread-local error message and version queries.

use crate::error::Error;
use std::cell::RefCell;
use std::ffi::CString;
use std::os::raw::c_char;

/// ABI version: incremented on every incompatible change of the C interface.
pub const UVF_ABI_VERSION: u32 = 1;

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

pub(crate) fn set_last_error(e: &Error) {
    let text = e.to_string().replace('\0', " ");
    LAST_ERROR.with(|m| *m.borrow_mut() = CString::new(text).unwrap_or_default());
}

pub(crate) fn clear_last_error() {
    LAST_ERROR.with(|m| *m.borrow_mut() = CString::default());
}

/// Human-readable message of the last failed call on this thread ("" after a success).
/// The pointer stays valid until the next uvflat call on the same thread.
#[no_mangle]
pub extern "C" fn uvf_last_error_message() -> *const c_char {
    LAST_ERROR.with(|m| m.borrow().as_ptr())
}

/// Library version as a static NUL-terminated string, e.g. "0.1.0".
#[no_mangle]
pub extern "C" fn uvf_version() -> *const c_char {
    static VERSION: &str = concat!(env!("CARGO_PKG_VERSION"), "\0");
    VERSION.as_ptr() as *const c_char
}

/// ABI version of the loaded library; compare with `UVF_ABI_VERSION` from the header.
#[no_mangle]
pub extern "C" fn uvf_abi_version() -> u32 {
    UVF_ABI_VERSION
}
