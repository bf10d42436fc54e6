//! Parameterization methods, one file per family (see each file's header for the paper and
//! equations it implements).

pub mod abf;
pub mod barycentric;
pub mod conformal;
pub mod constraints;
pub mod fixed_system;
pub mod floater;
pub mod intrinsic;
pub mod nonlinear;
pub mod sphere;
