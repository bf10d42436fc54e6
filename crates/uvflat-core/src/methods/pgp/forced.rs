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
//! larger than π: `closed_g0_cow` has 16 quarter turns and `closed_g0_man` 36 instead of 8.)
//! The open triangles must carry those |Σ_T q_T| quarter turns.
//!
//! Two things bound each q_T on its own: it is a whole number within 3/2 of 2Ω_T/π, so
//! `⌈2Ω_T/π − 3/2⌉ ≤ q_T ≤ ⌊2Ω_T/π + 3/2⌋` (at most one quarter either way unless |Ω_T| ≥ π/4),
//! and a triangle whose holonomy exceeds 3π/4 in magnitude is open whatever the field (no three
//! d_e of at most π/4 can close it). The bound is the fewest triangles with q_T ≠ 0 that fit
//! both: the forced ones, plus, if the sums they can reach miss the target, the free ones with
//! the most room towards it, largest first. It relaxes the coupling of the d_e between
//! neighbours, so it is a lower bound, not the minimum.
//!
//! The target is exact on a closed component. Elsewhere some d_e do not cancel: on a boundary
//! edge (one triangle), and on an edge shared with a triangle that has an edge between opposite
//! vertex normals (a zero-thickness wall; `closed_g133_cheese` has four), across which the
//! transport, hence Ω and the matching, is arbitrary. Such triangles are left out, and every
//! edge with one side left out or missing moves the sum of the others by up to |d_e| ≤ π/4, half
//! a quarter turn: the target becomes a range. So every component gives a bound.
//!
//! Cost: O(F log F).

use crate::fields::curvature::tangent_basis;
use crate::fields::frames::{match_rotation, normalized, rotate_quarter, tangent_part, transport, wrap_angle};
use crate::geometry::{cross, dot};
use crate::mesh::connectivity::NONE;
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
    /// The fewest open triangles, over every component: a lower bound on the open triangles,
    /// hence on the singular triangles, of every PGP parameterization with these normals.
    pub triangles: usize,
    /// Triangles open whatever the field, |Ω_T| > 3π/4 (counted in `triangles` too).
    pub holonomy_forced: usize,
    /// Closed components with an edge between opposite normals ([`ANTIPODAL_TOLERANCE`]): their
    /// index sum is known only within a range, so they add nothing to `quarters`, and to
    /// `triangles` what that range still forces.
    pub undetermined_components: usize,
}

/// The lower bound of the module comment, for the unit vertex `normals` the rotation matching
/// uses ([`super::PgpResult::normals`]).
pub fn forced_singular_triangles(mesh: &TriMesh, normals: &[[f64; 3]]) -> ForcedSingularities {
    let components = mesh.triangle_components();
    let count = components.iter().map(|&c| c as usize + 1).max().unwrap_or(0);
    let left_out: Vec<bool> = (0..mesh.triangle_count()).map(|t| has_antipodal_edge(mesh, normals, t)).collect();
    let mut parts = vec![ComponentIndices::default(); count];
    for (t, &c) in components.iter().enumerate() {
        let part = &mut parts[c as usize];
        if left_out[t] {
            continue;
        }
        part.add_triangle(triangle_holonomy(mesh, normals, t));
        let loose = (0..3).filter(|&k| mesh.connectivity().twin[3 * t + k] == NONE).count();
        part.boundary_edges += loose;
        part.loose_edges += loose;
        part.loose_edges += (0..3).filter(|&k| next_to_left_out(mesh, &left_out, 3 * t + k)).count();
    }
    let mut forced = ForcedSingularities::default();
    for part in &mut parts {
        if part.loose_edges == 0 {
            forced.quarters += part.quarters.round().abs() as u64;
        } else if part.boundary_edges == 0 {
            forced.undetermined_components += 1;
        }
        forced.holonomy_forced += part.forced.len();
        forced.triangles += part.fewest_open();
    }
    forced
}

/// Whether the twin of half-edge `h` lies in a triangle left out.
fn next_to_left_out(mesh: &TriMesh, left_out: &[bool], h: usize) -> bool {
    let twin = mesh.connectivity().twin[h];
    twin != NONE && left_out[(twin / 3) as usize]
}

/// One component's triangles as ranges of possible quarter indices.
#[derive(Debug, Clone, Default)]
struct ComponentIndices {
    /// Σ 2Ω_T/π over the triangles kept.
    quarters: f64,
    /// Edges of kept triangles whose d_e does not cancel: boundary edges and edges shared with
    /// a triangle left out.
    loose_edges: usize,
    /// The boundary edges among them.
    boundary_edges: usize,
    /// (lowest, highest) q_T of the triangles that cannot close.
    forced: Vec<(i64, i64)>,
    /// How far each of the other triangles can go up (positive q_T) and down.
    up: Vec<u64>,
    down: Vec<u64>,
}

impl ComponentIndices {
    fn add_triangle(&mut self, omega: f64) {
        self.quarters += omega / FRAC_PI_2;
        let (lo, hi) = quarter_range(omega);
        if lo > 0 || hi < 0 {
            self.forced.push((lo, hi));
        } else {
            self.up.push(hi as u64);
            self.down.push(lo.unsigned_abs());
        }
    }

    /// The fewest triangles with q_T ≠ 0 whose indices can sum into the target range.
    fn fewest_open(&mut self) -> usize {
        let slack = self.loose_edges as f64 / 2.0 + SUM_TOLERANCE;
        let (low, high) = ((self.quarters - slack).ceil() as i64, (self.quarters + slack).floor() as i64);
        let reach_low: i64 = self.forced.iter().map(|r| r.0).sum();
        let reach_high: i64 = self.forced.iter().map(|r| r.1).sum();
        let extra = if reach_high < low {
            fewest_carrying(&mut self.up, (low - reach_high) as u64)
        } else if reach_low > high {
            fewest_carrying(&mut self.down, (reach_low - high) as u64)
        } else {
            0
        };
        self.forced.len() + extra
    }
}

/// Rounding allowed on holonomies and their sums before another quarter turn counts.
const SUM_TOLERANCE: f64 = 1e-6;

/// The whole numbers q with |q π/2 − Ω| ≤ 3π/4, widened by rounding so that no possible index
/// is left out.
fn quarter_range(omega: f64) -> (i64, i64) {
    let x = omega / FRAC_PI_2;
    ((x - 1.5 - SUM_TOLERANCE).ceil() as i64, (x + 1.5 + SUM_TOLERANCE).floor() as i64)
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
    // Any tangent vector at corner 0 turns by the same angle (the loop of transports is a
    // rotation about n0); the edge to corner 1 can run along n0 and have none.
    let start = tangent_basis(n[0]).0;
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
    fn a_triangle_carries_one_quarter_either_way_below_45_degrees_and_is_forced_open_above_135() {
        assert_eq!(quarter_range(0.0), (-1, 1));
        assert_eq!(quarter_range(-0.7), (-1, 1));
        assert_eq!(quarter_range(PI / 4.0 - 1e-3), (-1, 1));
        assert_eq!(quarter_range(PI / 4.0 + 1e-3), (0, 2));
        assert_eq!(quarter_range(3.0 * PI / 4.0 - 1e-3), (0, 2));
        assert_eq!(quarter_range(3.0 * PI / 4.0 + 1e-3), (1, 3));
        assert_eq!(quarter_range(-PI), (-3, -1));
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
        assert_eq!(
            forced,
            ForcedSingularities { quarters: 8, triangles: 4, holonomy_forced: 0, undetermined_components: 0 }
        );
    }

    #[test]
    fn a_triangle_whose_normals_turn_by_more_than_135_degrees_is_open_for_every_field() {
        // A flat triangle whose vertex normals lean outwards by 70°: their spherical triangle
        // has an area between 3π/4 and π, so no matching closes it.
        let p = [1.0, 0.0, 0.0, -0.5, 0.866, 0.0, -0.5, -0.866, 0.0];
        let mesh = TriMesh::new(&p, &[0, 1, 2]).unwrap();
        let lean = 70f64.to_radians();
        let normals: Vec<[f64; 3]> =
            mesh.points().iter().map(|x| [lean.sin() * x[0], lean.sin() * x[1], lean.cos()]).collect();
        let omega = triangle_holonomy(&mesh, &normals, 0).abs();
        assert!(omega > 3.0 * PI / 4.0 && omega < PI, "{omega}");
        for turn in 0..24 {
            let a = turn as f64 * 0.37;
            let field: Vec<[f64; 3]> =
                (0..3).map(|v| [(a * (v + 1) as f64).cos(), (a * (v + 2) as f64).sin(), 0.3]).collect();
            assert_ne!(field_quarter_index(&mesh, &normals, &field, 0), 0, "field {turn}");
        }
        let forced = forced_singular_triangles(&mesh, &normals);
        assert_eq!(
            forced,
            ForcedSingularities { quarters: 0, triangles: 1, holonomy_forced: 1, undetermined_components: 0 }
        );
    }
}
