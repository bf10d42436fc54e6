//! What the workspace's integration tests and benchmarks share (a dev-dependency of the other
//! crates, never shipped): the repository's test meshes ([`meshes`]), C/C++ compilation
//! ([`compiler`]), the CGAL reference program ([`cgal`]), sampled surfaces with known geometry
//! ([`surfaces`]) and the checks of polygon remeshes ([`polygon_mesh`]).

pub mod cgal;
pub mod compiler;
pub mod meshes;
pub mod polygon_mesh;
pub mod surfaces;

/// The repository root (the workspace).
pub const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
