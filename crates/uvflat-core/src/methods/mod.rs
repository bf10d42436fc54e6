//! Parameterization methods, one file per family (see each file's header for the paper and
//! equations it implements).

pub mod abf;
pub mod angle_layout;
pub mod barycentric;
pub mod boundary_optimization;
pub mod circle_patterns;
pub mod cone_placement;
pub mod conformal;
pub mod constraints;
pub(crate) mod fixed_system;
pub(crate) mod floater;
pub mod intrinsic;
pub mod length_area_distortion;
pub mod near_optimal;
pub mod nonlinear;
pub mod pgp;
pub mod quadcover;
pub mod spectral_conformal;
pub mod sphere;
pub(crate) mod sphere_geometry;
