//! The fewest singular triangles any PGP parameterization of a mesh can have, whatever the
//! field, ω or solve: a lower bound from the rotation matching of Ray et al. 2006 (§2.4, eq. 13;
//! Algorithm 1) and Hopf–Poincaré (§1.3: the indices of a closed surface of genus g sum to
//! 2 − 2g). Not a step of the pipeline: it says how far a mesh's singular-triangle count can go
//! down, for comparison with the paper's "2 – 3% of the triangles" (§6).
//!
//! Around a triangle T = (v0, v1, v2) the matching compares each vertex's cross with its
//! neighbour's, carried along the edge by [`transport`]; the matched quarter turn leaves an angle
//! d_e ∈ [−π/4, π/4] per edge (the closest quarter turn). Carrying a tangent vector once around
//! T, v0 → v1 → v2 → v0, turns it by the holonomy Ω_T ∈ (−π, π]. The cross turns by Σ_e d_e
//! while the planes turn by Ω_T, so the field's index in T is a whole number q_T of quarter
//! turns with
//!
//! ```text
//! q_T · π/2 = Ω_T + Σ_e d_e,    |q_T| ≤ 3/2 + 2|Ω_T|/π.
//! ```
//!
//! The matched quarter turns fail to close around T exactly when q_T ≠ 0 (|q_T| ≤ 3 < 4), and
//! then T is open in Algorithm 1, a singular triangle of §3.2 ([`super::extraction`]; it can
//! also be open, or negative, for other reasons). On a closed connected component
//! every interior edge's d_e enters its two triangles with opposite signs, so Σ_T q_T =
//! (2/π) Σ_T Ω_T: the same for every field. (Ω_T is the area of T's image on the sphere of
//! normals, wrapped into (−π, π]; the areas sum to 2πχ, so Σ_T q_T = ±4χ unless an image is
//! larger than π: `closed_g0_cow` has 16 quarter turns and `closed_g0_man` 36 instead of 8.) The
//! open triangles must carry at least |Σ_T q_T| quarter turns, each at most its cap
//! ⌊3/2 + 2|Ω_T|/π⌋ (1 unless |Ω_T| ≥ π/4), so there are at least as many of them as it takes
//! to reach |Σ_T q_T| adding the largest caps first. Components with a boundary give no bound
//! (the boundary edges' d_e do not cancel), and neither do components with an edge between
//! opposite vertex normals (a zero-thickness wall; `closed_g133_cheese` has four), across which
//! the transport, hence the matching, is arbitrary.
//!
//! Cost: O(F log F).

use super::frames::{match_rotation, normalized, rotate_quarter, tangent_part, transport, wrap_angle};
use crate::geometry::{cross, dot, sub};
use crate::TriMesh;
use std::f64::consts::FRAC_PI_2;

/// Edges whose endpoint normals are this close to opposite (1 + n_a · n_b below it) have no
/// well-defined transport: the smallest rotation between opposite normals is not unique, and
/// near them rounding decides it.
pub const ANTIPODAL_TOLERANCE: f64 = 1e-9;

/// What [`forced_singular_triangles`] found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ForcedSingularities {
    /// Quarter turns the singular triangles must carry: |Σ_T q_T| summed over the closed
    /// components with no antipodal edge (4 |χ| per component where discrete Gauss–Bonnet holds).
    pub quarters: u64,
    /// The fewest triangles that can carry them: a lower bound on the open triangles, hence on
    /// the singular triangles, of every PGP parameterization with these normals.
    pub triangles: usize,
    /// Closed components left out because an edge joins vertices with opposite normals
    /// ([`ANTIPODAL_TOLERANCE`]): the matching across it is arbitrary, so nothing is forced.
    pub undetermined_components: usize,
}

/// The lower bound of the module comment, for the unit vertex `normals` the rotation matching
/// uses ([`super::PgpResult::normals`]).
pub fn forced_singular_triangles(mesh: &TriMesh, normals: &[[f64; 3]]) -> ForcedSingularities {
    let components = mesh.triangle_components();
    let count = components.iter().map(|&c| c as usize + 1).max().unwrap_or(0);
    let mut closed = vec![true; count];
    for loop_ in mesh.boundary_loops() {
        if let Some(t) = loop_.first().and_then(|&v| mesh.outgoing_halfedges(v).next()) {
            closed[components[(t / 3) as usize] as usize] = false;
        }
    }
    let mut determined = vec![true; count];
    let mut holonomy_sum = vec![0.0; count];
    let mut caps: Vec<Vec<u64>> = vec![Vec::new(); count];
    for (t, &c) in components.iter().enumerate() {
        let c = c as usize;
        determined[c] &= !has_antipodal_edge(mesh, normals, t);
        let omega = triangle_holonomy(mesh, normals, t);
        holonomy_sum[c] += omega;
        caps[c].push(quarter_capacity(omega));
    }
    let mut forced = ForcedSingularities::default();
    for c in (0..count).filter(|&c| closed[c]) {
        if !determined[c] {
            forced.undetermined_components += 1;
            continue;
        }
        let quarters = (holonomy_sum[c].abs() / FRAC_PI_2).round() as u64;
        forced.quarters += quarters;
        forced.triangles += fewest_carrying(&mut caps[c], quarters);
    }
    forced
}

/// Whether an edge of triangle `t` joins vertices with opposite normals ([`ANTIPODAL_TOLERANCE`]).
pub fn has_antipodal_edge(mesh: &TriMesh, normals: &[[f64; 3]], t: usize) -> bool {
    let tri = mesh.triangles()[t];
    (0..3).any(|k| 1.0 + dot(normals[tri[k] as usize], normals[tri[(k + 1) % 3] as usize]) < ANTIPODAL_TOLERANCE)
}

/// Ω_T: the angle by which a tangent vector at corner 0 turns when carried by [`transport`]
/// around the triangle, corner 0 → 1 → 2 → 0, counter-clockwise about corner 0's normal, in
/// (−π, π].
pub fn triangle_holonomy(mesh: &TriMesh, normals: &[[f64; 3]], t: usize) -> f64 {
    let tri = mesh.triangles()[t];
    let n = tri.map(|v| normals[v as usize]);
    let p = tri.map(|v| mesh.points()[v as usize]);
    let start = normalized(tangent_part(sub(p[1], p[0]), n[0]));
    let around = transport(transport(transport(start, n[0], n[1]), n[1], n[2]), n[2], n[0]);
    wrap_angle(dot(cross(start, around), n[0]).atan2(dot(start, around)))
}

/// q_T of the module comment for a cross field given by one vector per vertex (its tangent part):
/// the field carried around T by [`transport`] and re-matched at each corner by eq. 13's
/// closest quarter turn comes back turned by q_T quarter turns, q_T · π/2 = Ω_T + Σ_e d_e.
pub fn field_quarter_index(mesh: &TriMesh, normals: &[[f64; 3]], field: &[[f64; 3]], t: usize) -> i64 {
    let tri = mesh.triangles()[t];
    let tangent = |v: usize| normalized(tangent_part(field[v], normals[v]));
    let mut turn = triangle_holonomy(mesh, normals, t);
    let mut current = tangent(tri[0] as usize);
    for k in 0..3 {
        let (from, to) = (tri[k] as usize, tri[(k + 1) % 3] as usize);
        let carried = transport(current, normals[from], normals[to]);
        let k_to = tangent(to);
        let matched = rotate_quarter(normals[to], k_to, match_rotation(carried, normals[to], normals[to], k_to));
        turn += dot(cross(carried, matched), normals[to]).atan2(dot(carried, matched));
        current = matched;
    }
    (turn / FRAC_PI_2).round() as i64
}

/// The most quarter turns a triangle of holonomy `omega` can carry: ⌊3/2 + 2|Ω|/π⌋.
fn quarter_capacity(omega: f64) -> u64 {
    (1.5 + omega.abs() / FRAC_PI_2).floor() as u64
}

/// The fewest of `caps` whose sum reaches `quarters` (largest first); all of them if even that
/// does not reach it (which the index bound rules out on a closed component).
fn fewest_carrying(caps: &mut [u64], quarters: u64) -> usize {
    caps.sort_unstable_by(|a, b| b.cmp(a));
    let mut carried = 0;
    for (k, &cap) in caps.iter().enumerate() {
        if carried >= quarters {
            return k;
        }
        carried += cap;
    }
    caps.len()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn capacity_is_one_quarter_below_a_holonomy_of_45_degrees_and_grows_with_it() {
        assert_eq!(quarter_capacity(0.0), 1);
        assert_eq!(quarter_capacity(-0.7), 1);
        assert_eq!(quarter_capacity(PI / 4.0 + 1e-9), 2);
        assert_eq!(quarter_capacity(-3.0 * PI / 4.0 - 1e-9), 3);
        assert_eq!(quarter_capacity(PI), 3);
    }

    #[test]
    fn the_largest_capacities_are_used_first() {
        assert_eq!(fewest_carrying(&mut [1, 1, 3, 1, 2], 5), 2);
        assert_eq!(fewest_carrying(&mut [1, 1, 1], 0), 0);
        assert_eq!(fewest_carrying(&mut [1, 1], 3), 2);
    }

    #[test]
    fn an_octahedron_needs_eight_quarter_turns() {
        // The octahedron's vertex normals point at its vertices; each face's normals span an
        // octant of the sphere, whose area (π/2) is the holonomy: capacity 2 per face, so the
        // 8 quarter turns of a sphere (χ = 2) need at least 4 of its 8 faces.
        let p = [1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.0];
        let t = [0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5];
        let mesh = TriMesh::new(&p, &t).unwrap();
        let normals: Vec<[f64; 3]> = mesh.points().iter().map(|&x| normalized(x)).collect();
        for f in 0..8 {
            assert!((triangle_holonomy(&mesh, &normals, f).abs() - FRAC_PI_2).abs() < 1e-12);
        }
        let forced = forced_singular_triangles(&mesh, &normals);
        assert_eq!(forced, ForcedSingularities { quarters: 8, triangles: 4, undetermined_components: 0 });
    }
}
