//! The unknowns of a linear system over mesh vertices: the referenced vertices that are not
//! fixed, numbered consecutively (the rows and columns of the barycentric, conformal and SLIM
//! systems).

use super::{TriMesh, NONE};

/// Numbering of the free (unknown) vertices of a system: referenced vertices that are not
/// fixed get consecutive indices.
pub struct Unknowns {
    /// Row/column of each vertex, or `NONE` for fixed and unreferenced vertices.
    pub index: Vec<u32>,
    /// Vertex of each unknown.
    pub vertex: Vec<u32>,
}

impl Unknowns {
    /// Numbers the referenced vertices of `mesh` for which `is_fixed` is false.
    pub fn free_vertices(mesh: &TriMesh, is_fixed: impl Fn(u32) -> bool) -> Self {
        let mut index = vec![NONE; mesh.vertex_count()];
        let mut vertex = Vec::new();
        for v in 0..mesh.vertex_count() as u32 {
            if mesh.is_referenced(v) && !is_fixed(v) {
                index[v as usize] = vertex.len() as u32;
                vertex.push(v);
            }
        }
        Unknowns { index, vertex }
    }
    /// Number of unknowns.
    pub fn count(&self) -> usize {
        self.vertex.len()
    }
    /// 3D position of each unknown (for the nested-dissection ordering).
    pub fn positions(&self, mesh: &TriMesh) -> Vec<[f64; 3]> {
        self.vertex.iter().map(|&v| mesh.points()[v as usize]).collect()
    }
}
