//! Direction fields on triangle meshes, shared by the methods that follow them (the Periodic
//! Global Parameterization of Ray et al. 2006 and QuadCover of Kälberer, Nieser & Polthier
//! 2007) and owned by neither:
//!
//! - [`frames`]: tangent frames, per-triangle normals, rotation matching across edges;
//! - [`curvature`]: principal curvature directions (Cohen-Steiner & Morvan 2003 normal-cycle
//!   tensor), the default input field;
//! - [`smoothing`]: field smoothing modulo 2π, π or π/2 (Ray et al. 2006, §4.2, eqs. 21–22);
//! - [`indices`]: indices of a direction field at the vertices (Hopf–Poincaré);
//! - [`pairs`]: ± quarter singularities of a field closer than a given distance cancelled
//!   together;
//! - [`block_newton`]: the minimization of a quadratic energy over per-vertex blocks of unit
//!   (cosine, sine) pairs (Ray et al. 2006, §2.5: a linear solve, then Newton on the penalized
//!   energy), used by the smoothing and by PGP's periodic solve.

pub mod block_newton;
pub mod curvature;
pub mod frames;
pub mod indices;
pub mod pairs;
pub mod smoothing;
