//! Failures of the sparse solvers. The parameterization crate turns each into its own error of
//! the same class (`From<uvflat_sparse::Error>`), so callers see one error type.

use std::fmt;

/// Every failure of the sparse solvers.
#[derive(Debug, Clone, PartialEq)]
pub enum Error {
    /// A caller-given argument is invalid; the text says which and why.
    InvalidArgument(String),
    /// A factorization or solve failed (not positive definite, singular, non-finite result).
    Numerical(String),
    /// A bug, or memory that could not be allocated.
    Internal(String),
}

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, Error>;

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::InvalidArgument(s) => write!(f, "invalid argument: {s}"),
            Error::Numerical(s) => write!(f, "numerical failure: {s}"),
            Error::Internal(s) => write!(f, "internal error: {s}"),
        }
    }
}

impl std::error::Error for Error {}
