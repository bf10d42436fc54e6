//! Errors of the whole library: one variant per failure class, each carrying the data a caller
//! needs to find and fix the problem (which triangle, which vertex, which count).
//!
//! The C ABI (the `uvflat-capi` crate) maps every variant to a `UvfStatus` code, and its `Display` text
//! becomes the C caller's error message.

use std::fmt;

/// Every failure of the library.
#[derive(Debug, Clone, PartialEq)]
pub enum Error {
    /// A caller-given argument is invalid; the text says which and why.
    InvalidArgument(String),
    /// The mesh has no triangles.
    EmptyMesh,
    /// A count whose size in bytes overflows the address space.
    SizeOverflow { what: &'static str, count: usize },
    /// The positions array length is not a multiple of 3, or the triangles array of 3.
    BadArrayLength { what: &'static str, len: usize, multiple_of: usize },
    /// A triangle refers to a vertex that does not exist.
    IndexOutOfRange { triangle: usize, vertex: u64, vertex_count: usize },
    /// A coordinate is NaN or infinite.
    NonFiniteCoordinate { vertex: usize, value: f64 },
    /// A triangle uses the same vertex twice.
    RepeatedVertex { triangle: usize, vertex: u32 },
    /// A triangle has zero or near-zero area (relative to its longest edge squared).
    DegenerateTriangle { triangle: usize, relative_area: f64 },
    /// Two triangles use the same three vertices.
    DuplicateTriangle { triangle: usize, first: usize },
    /// An edge is shared by more than two triangles.
    NonManifoldEdge { a: u32, b: u32, triangles: Vec<usize> },
    /// A vertex whose triangles form more than one fan (a "bow-tie").
    NonManifoldVertex { vertex: u32, fans: usize },
    /// Two neighbouring triangles traverse their shared edge in the same direction.
    InconsistentOrientation { a: u32, b: u32, first: usize, second: usize },
    /// A polygon of a polygon mesh is invalid, or a triangle cut from it is (the inner error
    /// numbers triangles after triangulation; `face` is the input polygon).
    InvalidFace { face: usize, problem: Box<Error> },
    /// The method needs a topological disk (or a disk with holes) and the mesh is not one.
    NotADisk { components: usize, boundary_loops: usize, genus: i64 },
    /// The method needs a closed genus-0 surface (spherical parameterization) and the mesh is
    /// not one.
    NotASphere { boundary_loops: usize, genus: i64 },
    /// The mesh has more than one connected component.
    MultipleComponents { components: usize },
    /// A solver failed (matrix not positive definite, singular, non-finite result).
    Numerical(String),
    /// The progress callback asked to stop.
    Cancelled,
    /// Not implemented yet.
    NotImplemented(&'static str),
    /// A panic or other bug inside uvflat.
    Internal(String),
    /// File input/output failed.
    Io { path: String, message: String },
}

/// Result alias used throughout the crate.
pub type Result<T> = std::result::Result<T, Error>;

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        use Error::*;
        match self {
            InvalidArgument(s) => write!(f, "invalid argument: {s}"),
            EmptyMesh => write!(f, "the mesh has no triangles"),
            SizeOverflow { what, count } => {
                write!(f, "{what} count {count} is too large: its size in bytes overflows")
            }
            BadArrayLength { what, len, multiple_of } => {
                write!(f, "{what} array has length {len}, which is not a multiple of {multiple_of}")
            }
            IndexOutOfRange { triangle, vertex, vertex_count } => write!(
                f,
                "triangle {triangle} references vertex {vertex} but the mesh has {vertex_count} vertices"
            ),
            NonFiniteCoordinate { vertex, value } => {
                write!(f, "vertex {vertex} has a non-finite coordinate ({value})")
            }
            RepeatedVertex { triangle, vertex } => {
                write!(f, "triangle {triangle} uses vertex {vertex} more than once")
            }
            DegenerateTriangle { triangle, relative_area } => write!(
                f,
                "triangle {triangle} is degenerate (area / longest edge^2 = {relative_area:.3e})"
            ),
            DuplicateTriangle { triangle, first } => write!(
                f,
                "triangle {triangle} uses the same three vertices as triangle {first}"
            ),
            NonManifoldEdge { a, b, triangles } => write!(
                f,
                "edge ({a}, {b}) is non-manifold: it is shared by {} triangles {:?}",
                triangles.len(),
                triangles
            ),
            NonManifoldVertex { vertex, fans } => write!(
                f,
                "vertex {vertex} is non-manifold: its triangles form {fans} separate fans"
            ),
            InvalidFace { face, problem } => write!(f, "face {face}: {problem}"),
            InconsistentOrientation { a, b, first, second } => write!(
                f,
                "triangles {first} and {second} are inconsistently oriented: both traverse edge ({a}, {b}) in the same direction"
            ),
            NotADisk { components, boundary_loops, genus } => write!(
                f,
                "the mesh is not a topological disk: {components} component(s), {boundary_loops} boundary loop(s), genus {genus}"
            ),
            NotASphere { boundary_loops, genus } => write!(
                f,
                "the mesh is not a closed genus-0 surface: {boundary_loops} boundary loop(s), genus {genus}"
            ),
            MultipleComponents { components } => write!(
                f,
                "the mesh has {components} connected components; parameterize each separately"
            ),
            Numerical(s) => write!(f, "numerical failure: {s}"),
            Cancelled => write!(f, "cancelled by the progress callback"),
            NotImplemented(s) => write!(f, "not implemented: {s}"),
            Internal(s) => write!(f, "internal error: {s}"),
            Io { path, message } => write!(f, "{path}: {message}"),
        }
    }
}

impl std::error::Error for Error {}

impl From<uvflat_sparse::Error> for Error {
    fn from(e: uvflat_sparse::Error) -> Self {
        match e {
            uvflat_sparse::Error::InvalidArgument(s) => Error::InvalidArgument(s),
            uvflat_sparse::Error::Numerical(s) => Error::Numerical(s),
            uvflat_sparse::Error::Internal(s) => Error::Internal(s),
        }
    }
}
