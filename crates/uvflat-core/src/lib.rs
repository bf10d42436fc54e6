//! # uvflat-core — mesh parameterization
//!
//! Computes UV maps of triangle meshes: the methods of Desbrun–Meyer–Alliez 2002
//! (*Intrinsic Parameterizations*), of the Hormann–Lévy–Sheffer 2008 course
//! (*Mesh Parameterization: Theory and Practice*) and Ray et al. 2006 (*Periodic Global
//! Parameterization*), plus [`unwrap::unwrap`], which validates, cuts, flattens, verifies, repairs
//! and packs any manifold mesh in one call. The C ABI (`libuvflat`, `include/uvflat.h`) is the
//! `uvflat-capi` crate and the command-line tool the `uvflat-cli` crate; both call this one.
//!
//! Modules:
//! - [`error`]: the error type, one variant per failure class.
//! - [`mesh`]: [`TriMesh`], the validated mesh (connectivity, boundary loops, topology).
//! - [`geometry`]: per-triangle areas, angles and cotangents.
//! - [`unwrap`](mod@unwrap): the default pipeline, valid UVs for any manifold mesh.
//! - [`atlas`]: atlas mode: charts under a stretch bound, flattened and packed.
//! - [`verify`]: the exact, method-independent check of a UV layout (flips, overlaps).
//! - [`boundary`]: boundary shapes and distributions for fixed-boundary maps.
//! - [`methods`]: the parameterization methods.
//! - [`metrics`]: distortion measures.
//! - [`io`]: OBJ input/output and SVG pictures of UV layouts.
//! - [`progress`]: progress callbacks and cancellation.
//!
//! ```
//! use uvflat_core::{TriMesh, natural_conformal_map};
//! // Two triangles forming a folded square.
//! let positions = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.3, 0.0, 1.0, 0.0];
//! let triangles = [0, 1, 2, 0, 2, 3];
//! let mesh = TriMesh::new(&positions, &triangles).unwrap();
//! let uv = natural_conformal_map(&mesh, None).unwrap();
//! assert_eq!(uv.len(), 4);
//! ```

// The library never prints: callers see progress through `Progress` and failures through
// `Error`; clippy refuses prints.
#![deny(clippy::print_stdout, clippy::print_stderr)]

pub mod atlas;
pub mod boundary;
pub mod error;
pub mod fields;
pub mod geometry;
pub mod io;
pub mod mesh;
pub mod methods;
pub mod metrics;
pub(crate) use uvflat_sparse::parallel;
pub mod progress;
pub mod unwrap;
pub mod verify;

pub use boundary::{BoundaryShape, Distribution};
pub use error::{Error, Result};
pub use mesh::TriMesh;
pub use methods::barycentric::{fixed_boundary_map, FixedBoundaryOptions, Weights};
pub use methods::conformal::{area_weighted_conformal_map, natural_conformal_map};
pub use methods::nonlinear::{nonlinear_map, NonlinearMethod, NonlinearOptions};

/// Crate version, as reported by `uvf_version()`.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
