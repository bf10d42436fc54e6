//! Status codes of the C ABI: every Rust [`Error`] variant maps to one code, and
//! `uvf_status_string` names each code.

use std::os::raw::{c_char, c_int};
use uvflat_core::error::Error;

/// Status codes of the C ABI. `Ok` is 0; every failure class has its own code.
#[repr(C)]
#[allow(non_camel_case_types)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UvfStatus {
    /// Success.
    UVF_OK = 0,
    /// A pointer, count, option or index given by the caller is invalid.
    UVF_INVALID_ARGUMENT = 1,
    /// The mesh data is invalid: bad index, non-finite coordinate, degenerate, duplicate or
    /// non-manifold triangles, inconsistent orientation, empty mesh.
    UVF_INVALID_MESH = 2,
    /// The mesh is valid but its topology does not suit the method (for example not a disk).
    UVF_UNSUPPORTED_TOPOLOGY = 3,
    /// The linear system or optimisation failed numerically.
    UVF_NUMERICAL_FAILURE = 4,
    /// The progress callback asked to stop.
    UVF_CANCELLED = 5,
    /// The method exists in the API but is not implemented yet.
    UVF_NOT_IMPLEMENTED = 6,
    /// A bug in uvflat (a caught panic) or an allocation failure.
    UVF_INTERNAL_ERROR = 7,
    /// Reading or writing a file failed.
    UVF_IO_ERROR = 8,
}

/// The C status code of an error.
pub fn status_of(error: &Error) -> UvfStatus {
    use Error::*;
    match error {
        InvalidArgument(_) | SizeOverflow { .. } | BadArrayLength { .. } => UvfStatus::UVF_INVALID_ARGUMENT,
        EmptyMesh
        | IndexOutOfRange { .. }
        | NonFiniteCoordinate { .. }
        | RepeatedVertex { .. }
        | DegenerateTriangle { .. }
        | DuplicateTriangle { .. }
        | NonManifoldEdge { .. }
        | NonManifoldVertex { .. }
        | InconsistentOrientation { .. } => UvfStatus::UVF_INVALID_MESH,
        InvalidFace { problem, .. } => status_of(problem),
        NotADisk { .. } | NotASphere { .. } | MultipleComponents { .. } => UvfStatus::UVF_UNSUPPORTED_TOPOLOGY,
        Numerical(_) => UvfStatus::UVF_NUMERICAL_FAILURE,
        Cancelled => UvfStatus::UVF_CANCELLED,
        NotImplemented(_) => UvfStatus::UVF_NOT_IMPLEMENTED,
        Internal(_) => UvfStatus::UVF_INTERNAL_ERROR,
        Io { .. } => UvfStatus::UVF_IO_ERROR,
    }
}

/// A short English description of a status code, as a static NUL-terminated string (never
/// NULL; an unknown code gives "unknown uvflat status"). `status` is a `UvfStatus` value.
/// The details of a failed call are in `uvf_last_error`.
#[no_mangle]
pub extern "C" fn uvf_status_string(status: c_int) -> *const c_char {
    // Taken as an int, not as the enum: C may pass any value, and a Rust enum must hold a
    // valid variant.
    let text: &'static str = match status {
        0 => "success\0",
        1 => "invalid argument\0",
        2 => "invalid mesh\0",
        3 => "unsupported topology\0",
        4 => "numerical failure\0",
        5 => "cancelled\0",
        6 => "not implemented\0",
        7 => "internal error\0",
        8 => "input/output error\0",
        _ => "unknown uvflat status\0",
    };
    text.as_ptr() as *const c_char
}
