//! The UV layout of prescribed triangle angles (Sheffer, Lévy, Mogilnitsky & Bogomyakov 2005,
//! "ABF++", §5): the layout whose triangles are most similar, in the least-squares sense of the
//! conformal energy (Lévy et al. 2002, LSCM), to triangles with the given angles, two vertices
//! pinned. One sparse Cholesky solve of the cotangent system (the cotangents of the given
//! angles instead of the mesh's own). Used by ABF/ABF++ and by the circle-pattern maps, whose
//! angles are those of a planar layout (exact there).
//!
//! Cost: one sparse Cholesky factorization and solve over the free vertices.

use crate::error::{Error, Result};
use crate::mesh::TriMesh;
use crate::methods::conformal::{ConformalSystem, Pin};
use std::f64::consts::PI;
use uvflat_sparse::require_finite;

/// ABF++ §5: the uv layout whose triangles are as similar as possible (least squares, LSCM
/// style) to the triangles with the given angles, two vertices pinned. With every triple in
/// (0, π) and summing to π the energy of each triangle is the conformal energy of a map from a
/// real triangle, never negative, and the system is positive semi-definite; with triples off π
/// an obtuse corner's negative cotangent can make it indefinite (see [`triangle_shapes`]).
pub fn reconstruct_uv(mesh: &TriMesh, angles: &[[f64; 3]], pins: [Pin; 2]) -> Result<Vec<[f64; 2]>> {
    if angles.len() != mesh.triangle_count() {
        return Err(Error::InvalidArgument(format!(
            "{} angle triples for {} triangles",
            angles.len(),
            mesh.triangle_count()
        )));
    }
    let cot: Vec<[f64; 3]> = angles.iter().map(|a| a.map(|x| x.cos() / x.sin())).collect();
    require_finite(cot.iter().flatten().copied(), "ABF angle")?;
    let mut system = ConformalSystem::with_cotangents(mesh, &pins, &cot)?;
    let coords = system.unknowns.positions(mesh);
    uvflat_sparse::CholeskySolver::new(&system.matrix, Some(&coords))?.solve_in_place(&mut system.rhs)?;
    system.uv(mesh)
}

/// Each angle triple scaled to sum to π: the shapes of real triangles, for the layout of angles
/// that stopped short of the triangle constraints (an iteration cut off by `max_iterations`),
/// whose layout system could otherwise be indefinite. Converged angles are laid out as they
/// are: scaling them moves the vertex sums the seams of cone maps depend on (circle patterns
/// share the layout).
pub fn triangle_shapes(angles: &[[f64; 3]]) -> Vec<[f64; 3]> {
    angles.iter().map(|a| a.map(|x| x * PI / (a[0] + a[1] + a[2]))).collect()
}
