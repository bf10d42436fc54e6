//! Temporary hole filling for fixed-boundary methods: every boundary loop except the outer one
//! is closed by a cone of triangles around one virtual vertex, so the holes' vertices become
//! interior vertices of a disk and a convex-boundary barycentric map with positive weights
//! (Tutte, Floater, mean value) stays an embedding (Tutte/Floater theorem, course notes §2.2).
//!
//! The apex sits above the loop's centroid, lifted along the loop's Newell normal by half its
//! mean radius, so that no cone triangle is degenerate even for a planar, non-convex hole.

use super::TriMesh;
use crate::error::Result;
use crate::geometry::{cross, distance, norm, sub};

/// A disk made from a mesh with holes, and how its vertices relate to the original ones.
pub struct FilledDisk {
    /// The filled mesh: the original vertices first, then one virtual vertex per hole.
    pub mesh: TriMesh,
}

/// Closes every boundary loop `i` with `keep[i] == false` by a cone around a virtual vertex.
pub fn fill_holes(mesh: &TriMesh, keep: &[bool]) -> Result<FilledDisk> {
    let mut points = mesh.points().to_vec();
    let mut tris = mesh.triangles().to_vec();
    for (i, lp) in mesh.boundary_loops().iter().enumerate() {
        if keep[i] {
            continue;
        }
        let apex = points.len() as u32;
        points.push(cone_apex(mesh.points(), lp));
        for k in 0..lp.len() {
            // Boundary half-edges a→b have the surface on their left; the cone triangle holds b→a.
            let (a, b) = (lp[k], lp[(k + 1) % lp.len()]);
            tris.push([b, a, apex]);
        }
    }
    let filled = TriMesh::from_checked(points, tris)?;
    Ok(FilledDisk { mesh: filled })
}

fn cone_apex(points: &[[f64; 3]], lp: &[u32]) -> [f64; 3] {
    let n = lp.len() as f64;
    let mut c = [0.0; 3];
    for &v in lp {
        for d in 0..3 {
            c[d] += points[v as usize][d] / n;
        }
    }
    let mut normal = [0.0; 3];
    for k in 0..lp.len() {
        let (p, q) = (points[lp[k] as usize], points[lp[(k + 1) % lp.len()] as usize]);
        let x = cross(sub(p, c), sub(q, c));
        for d in 0..3 {
            normal[d] += x[d];
        }
    }
    let len = norm(normal);
    let radius = lp.iter().map(|&v| distance(points[v as usize], c)).sum::<f64>() / n;
    if len > 0.0 {
        // The loop runs clockwise seen from the hole's side; lift against its normal.
        for d in 0..3 {
            c[d] -= 0.5 * radius * normal[d] / len;
        }
    }
    c
}
