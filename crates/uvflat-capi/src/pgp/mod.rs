//! Periodic Global Parameterization (Ray et al. 2006): principal curvatures (`curvature`), the PGP
//! solve and its result handle (`solve`), the quad-dominant remesh (`quad_mesh`), the chart layout
//! and per-chart parameterization (`charts`); and the optional-output checks they share.

pub mod charts;
pub mod curvature;
pub mod quad_mesh;
pub mod solve;

use crate::copy_out;
use uvflat_core::error::{Error, Result};

/// Checks the capacity of an output that may be NULL (skipped).
pub(crate) fn check_optional<T>(out: *mut T, capacity: usize, needed: usize, what: &str) -> Result<()> {
    if out.is_null() {
        Ok(())
    } else {
        check_capacity(capacity, needed, what)
    }
}

/// Copies `src` into an output that may be NULL (skipped).
pub(crate) fn copy_optional<T: Copy>(src: &[T], out: *mut T, capacity: usize, what: &'static str) -> Result<()> {
    if out.is_null() {
        Ok(())
    } else {
        copy_out(src, out, capacity, what)
    }
}

pub(crate) fn check_capacity(capacity: usize, needed: usize, what: &str) -> Result<()> {
    if capacity < needed {
        return Err(Error::InvalidArgument(format!("{what} holds {capacity} elements but {needed} are needed")));
    }
    Ok(())
}
