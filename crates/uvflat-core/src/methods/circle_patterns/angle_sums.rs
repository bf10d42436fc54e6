//! Prescribed angle sums of the circle-pattern map (Kharevych, Springborn & Schröder 2006,
//! §5): the boundary of the planar domain is controlled by prescribing the angle sums at
//! boundary vertices, and cone singularities by prescribing them at interior vertices (course
//! notes 2008 §4.4: "equality and inequality constraints on the angles along the boundary";
//! "cone singularities").
//!
//! The pattern's angle sum at a vertex is Σ α over its corners (see the parent module). At a
//! boundary vertex the uv boundary turns by κ_v = π − Σ α; at an interior vertex the cone
//! curvature is κ_v = 2π − Σ α (0: flat, the default). Each prescription is one row of the
//! angle program. Summing every constraint (π per triangle) gives Σ_v κ_v = 2π χ over all
//! vertices (discrete Gauss–Bonnet), so when every vertex is prescribed — a closed mesh, or a
//! disk whose whole boundary is — the values must add up to that and one row is implied; and
//! each sum must be possible for the vertex's corners (each in (0, π)).

use super::MIN_ANGLE;
use crate::error::{Error, Result};
use crate::mesh::TriMesh;
use std::f64::consts::PI;

/// The angle sum to prescribe at every vertex of `mesh` (the triangulation the program runs
/// on): 2π − κ at interior vertices (κ from `cones`, else 0), π − κ at boundary vertices whose
/// `boundary_curvature` is not NaN, NaN (free) elsewhere. Checks lengths, ranges and, when
/// every vertex is prescribed, Gauss–Bonnet.
pub(super) fn vertex_sums(
    mesh: &TriMesh,
    boundary_curvature: Option<&[f64]>,
    cones: &[(u32, f64)],
) -> Result<Vec<f64>> {
    let n = mesh.vertex_count();
    if let Some(c) = boundary_curvature.filter(|c| c.len() != n) {
        return Err(Error::InvalidArgument(format!("boundary curvature has {} values for {n} vertices", c.len())));
    }
    let mut sums = vec![f64::NAN; n];
    for v in 0..n as u32 {
        if mesh.is_referenced(v) && !mesh.is_boundary_vertex(v) {
            sums[v as usize] = 2.0 * PI;
        } else if let Some(k) =
            boundary_curvature.map(|c| c[v as usize]).filter(|k| mesh.is_referenced(v) && !k.is_nan())
        {
            sums[v as usize] = PI - k;
        }
    }
    let mut coned = vec![false; n];
    for &(v, k) in cones {
        if v as usize >= n || !mesh.is_referenced(v) || mesh.is_boundary_vertex(v) {
            return Err(Error::InvalidArgument(format!("cone vertex {v} is not an interior vertex of the mesh")));
        }
        if !k.is_finite() {
            return Err(Error::InvalidArgument(format!("the cone curvature at vertex {v} is not finite ({k})")));
        }
        if std::mem::replace(&mut coned[v as usize], true) {
            return Err(Error::InvalidArgument(format!("cone vertex {v} is given twice")));
        }
        sums[v as usize] = 2.0 * PI - k;
    }
    check_ranges(mesh, &sums)?;
    check_gauss_bonnet(mesh, &sums)?;
    Ok(sums)
}

/// Each prescribed sum must be finite and in (d·MIN_ANGLE, d·π) for a vertex of d corners.
fn check_ranges(mesh: &TriMesh, sums: &[f64]) -> Result<()> {
    let corners = mesh.corner_counts();
    for (v, &sum) in sums.iter().enumerate().filter(|(_, s)| !s.is_nan()) {
        let d = corners[v] as f64;
        if !(sum.is_finite() && sum > d * MIN_ANGLE && sum < d * PI) {
            let what = if mesh.is_boundary_vertex(v as u32) { "boundary curvature" } else { "cone curvature" };
            return Err(Error::InvalidArgument(format!(
                "the {what} at vertex {v} asks for an angle sum of {sum} over its {d} triangle(s), outside (0, {d}π)"
            )));
        }
    }
    Ok(())
}

/// With every referenced vertex prescribed, Σ κ must be 2π χ.
fn check_gauss_bonnet(mesh: &TriMesh, sums: &[f64]) -> Result<()> {
    if (0..mesh.vertex_count() as u32).any(|v| mesh.is_referenced(v) && sums[v as usize].is_nan()) {
        return Ok(());
    }
    let total = prescribed_curvature(mesh, sums);
    let chi = mesh.topology().euler_characteristic as f64;
    if (total - 2.0 * PI * chi).abs() > gauss_bonnet_tolerance(mesh) {
        return Err(Error::InvalidArgument(format!(
            "the prescribed curvatures (boundary turning and cones) sum to {total}, but Gauss–Bonnet needs 2π χ = {} (χ = {chi})",
            2.0 * PI * chi
        )));
    }
    Ok(())
}

/// Σ κ_v over the prescribed vertices: π − sum at boundary vertices, 2π − sum inside.
fn prescribed_curvature(mesh: &TriMesh, sums: &[f64]) -> f64 {
    (0..mesh.vertex_count() as u32)
        .filter(|&v| mesh.is_referenced(v) && !sums[v as usize].is_nan())
        .map(|v| if mesh.is_boundary_vertex(v) { PI } else { 2.0 * PI } - sums[v as usize])
        .sum()
}

/// Rounding allowed in a Gauss–Bonnet sum over the mesh's vertices.
fn gauss_bonnet_tolerance(mesh: &TriMesh) -> f64 {
    1e-9 * (1.0 + mesh.vertex_count() as f64)
}

/// Per vertex, an upper bound on the angle sum (NaN: none): with `convex`, π at every boundary
/// vertex whose sum `sums` leaves free (its turning π − Σ α at least 0). Checks that the
/// bounded vertices can take the turning Gauss–Bonnet leaves them: with every vertex prescribed
/// or bounded, Σ κ = 2π χ, so the prescribed curvatures may add up to at most 2π χ.
pub(super) fn convex_bounds(mesh: &TriMesh, sums: &[f64], convex: bool) -> Result<Vec<f64>> {
    let mut bounds = vec![f64::NAN; mesh.vertex_count()];
    if !convex {
        return Ok(bounds);
    }
    for v in (0..mesh.vertex_count() as u32).filter(|&v| mesh.is_referenced(v) && sums[v as usize].is_nan()) {
        bounds[v as usize] = PI;
    }
    let prescribed = prescribed_curvature(mesh, sums);
    let chi = mesh.topology().euler_characteristic as f64;
    if bounds.iter().any(|b| !b.is_nan()) && prescribed > 2.0 * PI * chi + gauss_bonnet_tolerance(mesh) {
        return Err(Error::InvalidArgument(format!(
            "a convex boundary is impossible: the prescribed curvatures already sum to {prescribed}, more than 2π χ = {} (χ = {chi}), which would leave the free boundary vertices turning backwards",
            2.0 * PI * chi
        )));
    }
    Ok(bounds)
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
    let fan = mesh.corner_counts();
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
