//! Prescribed boundary curvature for the circle-pattern map (Kharevych, Springborn & Schröder
//! 2006, §5: the boundary of the planar domain is controlled by prescribing the angle sums
//! at boundary vertices; course notes 2008 §4.4: "equality and inequality constraints on the
//! angles along the boundary").
//!
//! At a boundary vertex v the pattern's angle sum is Σ α over v's corners (see the parent
//! module), and the uv boundary turns by κ_v = π − Σ α there. Prescribing κ_v adds the row
//! Σ α = π − κ_v to the angle program. Summing every constraint (π per triangle, 2π per
//! interior vertex) over a disk with h holes gives Σ_boundary κ_v = 2π (1 − h) (discrete
//! Gauss–Bonnet with flat interior vertices), so a fully prescribed boundary must add up to
//! that, and each prescribed angle sum must be possible for the vertex's corners (each in
//! (0, π)).

use super::MIN_ANGLE;
use crate::error::{Error, Result};
use crate::mesh::TriMesh;
use std::f64::consts::PI;

/// Checks a per-vertex boundary curvature (NaN = free) against `mesh`, the triangulation the
/// program runs on.
pub(super) fn check(mesh: &TriMesh, curvature: &[f64]) -> Result<()> {
    if curvature.len() != mesh.vertex_count() {
        return Err(Error::InvalidArgument(format!(
            "boundary curvature has {} values for {} vertices",
            curvature.len(),
            mesh.vertex_count()
        )));
    }
    let mut corners = vec![0u32; mesh.vertex_count()];
    for v in mesh.triangles().iter().flatten() {
        corners[*v as usize] += 1;
    }
    let (mut total, mut all_prescribed) = (0.0, true);
    for lp in mesh.boundary_loops() {
        for &v in lp {
            let k = curvature[v as usize];
            if k.is_nan() {
                all_prescribed = false;
                continue;
            }
            let sum = PI - k;
            let d = corners[v as usize] as f64;
            if !(k.is_finite() && sum > d * MIN_ANGLE && sum < d * PI) {
                return Err(Error::InvalidArgument(format!(
                    "boundary curvature {k} at vertex {v} asks for an angle sum of {sum} over its {d} triangle(s), outside (0, {d}π)"
                )));
            }
            total += k;
        }
    }
    let holes = mesh.boundary_loops().len().saturating_sub(1) as f64;
    let expected = 2.0 * PI * (1.0 - holes);
    if all_prescribed && (total - expected).abs() > 1e-9 * (1.0 + mesh.vertex_count() as f64) {
        return Err(Error::InvalidArgument(format!(
            "the prescribed boundary curvatures sum to {total}, but a disk with {holes} hole(s) needs 2π (1 − {holes}) = {expected} (Gauss–Bonnet)"
        )));
    }
    Ok(())
}

/// Boundary curvature that makes the longest boundary loop a convex polygon with the given
/// corner vertices (in any order): turning 2π / k at each of the k ≥ 3 corners, 0 (straight)
/// at the loop's other vertices, free (NaN) elsewhere — e.g. four corners give a rectangle
/// whose side lengths the map chooses. A boundary vertex in a single triangle (an "ear") must
/// be a corner: a straight side through it would flatten its triangle, and leaving it free
/// does not help (its turning, π minus its one angle, is positive, while the corners already
/// take the whole 2π), so such a mesh is refused with the ear named.
pub fn polygon_boundary_curvature(mesh: &TriMesh, corners: &[u32]) -> Result<Vec<f64>> {
    let outer = mesh.longest_boundary_loop().ok_or_else(|| {
        let t = mesh.topology();
        Error::NotADisk { components: t.components, boundary_loops: 0, genus: t.genus }
    })?;
    let lp = &mesh.boundary_loops()[outer];
    if corners.len() < 3 {
        return Err(Error::InvalidArgument(format!("a polygon needs at least 3 corners (got {})", corners.len())));
    }
    let mut fan = vec![0u32; mesh.vertex_count()];
    for v in mesh.triangles().iter().flatten() {
        fan[*v as usize] += 1;
    }
    let mut curvature = vec![f64::NAN; mesh.vertex_count()];
    let mut on_loop = vec![false; mesh.vertex_count()];
    for &v in lp {
        on_loop[v as usize] = true;
        curvature[v as usize] = 0.0;
    }
    let turn = 2.0 * PI / corners.len() as f64;
    for &c in corners {
        if !on_loop.get(c as usize).copied().unwrap_or(false) {
            return Err(Error::InvalidArgument(format!("corner {c} is not a vertex of the longest boundary loop")));
        }
        if curvature[c as usize] == turn {
            return Err(Error::InvalidArgument(format!("corner {c} is given twice")));
        }
        curvature[c as usize] = turn;
    }
    if let Some(ear) = lp.iter().find(|&&v| fan[v as usize] == 1 && curvature[v as usize] == 0.0) {
        return Err(Error::InvalidArgument(format!(
            "boundary vertex {ear} is in a single triangle, so no straight side can pass through it: make it a corner (or prescribe the curvature per vertex)"
        )));
    }
    Ok(curvature)
}
