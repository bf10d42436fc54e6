//! Progress reporting and cancellation for long computations. A callback receives the
//! fraction done in [0, 1] and returns `true` to continue or `false` to cancel; cancelling
//! makes the method return [`Error::Cancelled`].

use crate::error::{Error, Result};

/// An optional progress callback.
pub struct Progress<'a> {
    callback: Option<&'a mut dyn FnMut(f64) -> bool>,
}

impl<'a> Progress<'a> {
    /// No reporting, never cancels.
    pub fn none() -> Self {
        Progress { callback: None }
    }
    /// Reports to `callback`.
    pub fn new(callback: &'a mut dyn FnMut(f64) -> bool) -> Self {
        Progress { callback: Some(callback) }
    }
    /// Reports `fraction`; fails with [`Error::Cancelled`] when the callback says stop.
    pub fn report(&mut self, fraction: f64) -> Result<()> {
        let keep_going = match &mut self.callback {
            Some(cb) => cb(fraction.clamp(0.0, 1.0)),
            None => true,
        };
        if keep_going {
            Ok(())
        } else {
            Err(Error::Cancelled)
        }
    }
}
