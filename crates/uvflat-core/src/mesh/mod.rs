//! The validated triangle mesh every method consumes: positions, triangles, half-edge
//! connectivity, boundary loops, components, Euler characteristic and genus, plus the
//! per-triangle geometry ([`TriangleGeometry`]) computed once.
//!
//! [`TriMesh::new`] is the single entry point for caller data; it rejects every malformed input
//! with an [`Error`] naming the offending element. Unreferenced vertices are allowed: they get
//! no connectivity, and methods return NaN for their UV.

pub(crate) mod connectivity;
pub mod cut;
pub(crate) mod fill;
pub(crate) mod intrinsic_delaunay;
pub mod islands;
pub mod polygon;
pub mod snapped;
pub(crate) mod topology;
pub(crate) mod unknowns;
pub(crate) mod validate;

use crate::error::{Error, Result};
use crate::geometry::{distance, TriangleGeometry};
pub use connectivity::{next, prev, Connectivity, NONE};
pub use unknowns::Unknowns;

/// A validated, manifold, consistently oriented triangle mesh.
#[derive(Debug, Clone)]
pub struct TriMesh {
    points: Vec<[f64; 3]>,
    triangles: Vec<[u32; 3]>,
    conn: Connectivity,
    loops: Vec<Vec<u32>>,
    component: Vec<u32>,
    component_count: usize,
    referenced_count: usize,
    geometry: TriangleGeometry,
    angles: std::sync::OnceLock<Vec<[f64; 3]>>,
}

/// Summary of a mesh's topology, as reported by `uvflat info` and `uvf_mesh_info`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TopologySummary {
    /// Vertices in the input arrays (including unreferenced ones).
    pub vertices: usize,
    /// Vertices used by at least one triangle.
    pub referenced_vertices: usize,
    /// Triangles.
    pub triangles: usize,
    /// Undirected edges.
    pub edges: usize,
    /// Connected components.
    pub components: usize,
    /// Boundary loops.
    pub boundary_loops: usize,
    /// Euler characteristic V − E + F (referenced vertices only).
    pub euler_characteristic: i64,
    /// Total genus, Σ over components of (2 − b − χ)/2.
    pub genus: i64,
}

impl TriMesh {
    /// Validates flat arrays (3 coordinates per vertex, 3 vertex indices per triangle,
    /// counter-clockwise) and builds the mesh.
    pub fn new(positions: &[f64], triangles: &[u32]) -> Result<Self> {
        let (points, tris) = validate::split_arrays(positions, triangles)?;
        // The degeneracy check shares the geometry's pass over the vertices.
        let (geometry, degenerate) = TriangleGeometry::new_rejecting(&points, &tris, validate::is_degenerate);
        if let Some((triangle, relative_area)) = degenerate {
            return Err(Error::DegenerateTriangle { triangle, relative_area });
        }
        Self::with_geometry(points, tris, geometry)
    }

    /// Builds a mesh from points and triangles that passed index and degeneracy checks.
    pub(crate) fn from_checked(points: Vec<[f64; 3]>, tris: Vec<[u32; 3]>) -> Result<Self> {
        let geometry = TriangleGeometry::new(&points, &tris);
        Self::with_geometry(points, tris, geometry)
    }

    /// Builds a mesh from checked points and triangles and their geometry.
    fn with_geometry(points: Vec<[f64; 3]>, tris: Vec<[u32; 3]>, geometry: TriangleGeometry) -> Result<Self> {
        // Independent passes run side by side; a duplicate triangle is reported before the
        // connectivity's errors, as when they ran one after the other.
        let (duplicates, conn) = crate::parallel::join(
            tris.len(),
            || validate::check_duplicates(&tris),
            || Connectivity::new(points.len(), &tris),
        );
        duplicates?;
        let conn = conn?;
        let (loops, (component, component_count)) = crate::parallel::join(
            tris.len(),
            || topology::boundary_loops(&tris, &conn),
            || topology::triangle_components(tris.len(), &conn),
        );
        let referenced_count = conn.vertex_halfedge.iter().filter(|&&h| h != NONE).count();
        Ok(TriMesh {
            points,
            triangles: tris,
            conn,
            loops,
            component,
            component_count,
            referenced_count,
            geometry,
            angles: std::sync::OnceLock::new(),
        })
    }

    /// Number of vertices (including unreferenced ones).
    pub fn vertex_count(&self) -> usize {
        self.points.len()
    }
    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }
    /// Vertex positions.
    pub fn points(&self) -> &[[f64; 3]] {
        &self.points
    }
    /// Triangles (counter-clockwise vertex triples).
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }
    /// Half-edge connectivity.
    pub fn connectivity(&self) -> &Connectivity {
        &self.conn
    }
    /// Per-triangle areas and cotangents.
    pub fn geometry(&self) -> &TriangleGeometry {
        &self.geometry
    }
    /// Interior angle (radians) at each corner, `[t][k]` at vertex `triangles()[t][k]`;
    /// computed on first use.
    pub fn corner_angles(&self) -> &[[f64; 3]] {
        self.angles.get_or_init(|| crate::geometry::corner_angles(&self.points, &self.triangles))
    }
    /// Boundary loops, each ordered counter-clockwise (surface on the left).
    pub fn boundary_loops(&self) -> &[Vec<u32>] {
        &self.loops
    }
    /// Number of triangle corners at each vertex (0 for unreferenced vertices).
    pub fn corner_counts(&self) -> Vec<u32> {
        let mut counts = vec![0u32; self.vertex_count()];
        for v in self.triangles.iter().flatten() {
            counts[*v as usize] += 1;
        }
        counts
    }
    /// Component id of each triangle.
    pub fn triangle_components(&self) -> &[u32] {
        &self.component
    }
    /// Whether a vertex is used by a triangle.
    pub fn is_referenced(&self, v: u32) -> bool {
        self.conn.vertex_halfedge[v as usize] != NONE
    }
    /// Whether a vertex lies on a boundary loop.
    pub fn is_boundary_vertex(&self, v: u32) -> bool {
        let h = self.conn.vertex_halfedge[v as usize];
        h != NONE && self.conn.is_boundary(h)
    }
    /// Vertex at the tail of half-edge `h`.
    #[inline]
    pub fn tail(&self, h: u32) -> u32 {
        self.triangles[(h / 3) as usize][(h % 3) as usize]
    }
    /// Vertex at the head of half-edge `h`.
    #[inline]
    pub fn head(&self, h: u32) -> u32 {
        self.tail(next(h))
    }

    /// Counts and topological invariants.
    pub fn topology(&self) -> TopologySummary {
        let boundary_halfedges = self.conn.twin.iter().filter(|&&t| t == NONE).count();
        let edges = (3 * self.triangles.len() + boundary_halfedges) / 2;
        let chi = self.referenced_count as i64 - edges as i64 + self.triangles.len() as i64;
        let b = self.loops.len() as i64;
        let c = self.component_count as i64;
        TopologySummary {
            vertices: self.points.len(),
            referenced_vertices: self.referenced_count,
            triangles: self.triangles.len(),
            edges,
            components: self.component_count,
            boundary_loops: self.loops.len(),
            euler_characteristic: chi,
            genus: (2 * c - b - chi) / 2,
        }
    }

    /// Checks that the mesh is one connected genus-0 surface with at least one boundary loop
    /// (a disk, possibly with holes).
    pub fn require_disk_with_holes(&self) -> Result<()> {
        let t = self.topology();
        if t.components != 1 {
            return Err(Error::MultipleComponents { components: t.components });
        }
        if t.boundary_loops == 0 || t.genus != 0 {
            return Err(Error::NotADisk { components: t.components, boundary_loops: t.boundary_loops, genus: t.genus });
        }
        Ok(())
    }

    /// Index of the boundary loop with the greatest 3D length (the outer boundary).
    pub fn longest_boundary_loop(&self) -> Option<usize> {
        let length = |lp: &Vec<u32>| -> f64 {
            (0..lp.len())
                .map(|i| distance(self.points[lp[i] as usize], self.points[lp[(i + 1) % lp.len()] as usize]))
                .sum()
        };
        (0..self.loops.len()).max_by(|&a, &b| length(&self.loops[a]).total_cmp(&length(&self.loops[b])))
    }

    /// Outgoing half-edges of vertex `v` in counter-clockwise order (starting with the
    /// boundary half-edge for boundary vertices).
    pub fn outgoing_halfedges(&self, v: u32) -> impl Iterator<Item = u32> + '_ {
        let first = self.conn.vertex_halfedge[v as usize];
        let mut h = first;
        std::iter::from_fn(move || {
            if h == NONE {
                return None;
            }
            let current = h;
            let r = self.conn.rotate_ccw(h);
            h = if r == first { NONE } else { r };
            Some(current)
        })
    }
}
