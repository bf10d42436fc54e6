//! The integration tests of the parameterization core, in one test binary (one link instead of
//! one per file): each module checks the claims of one method family's papers on the
//! repository's meshes with an independent check, plus the repository's own rules.

mod abf;
mod atlas;
mod cgal_crosscheck;
mod circle_patterns;
mod closed_surfaces;
mod intrinsic_optimization;
mod intrinsic_tools;
mod nonlinear;
mod ordering;
mod pgp;
mod pgp_charts;
mod properties;
mod quadcover;
mod repository;
