//! Singularity-pair cancellation of PGP's cross field (not in Ray et al. 2006; a step between
//! its §4.2 smoothing and the periodic solve of §2): a +¼ and a −¼ singular triangle of the
//! smoothed field closer than a given distance are removed together, and the field is re-solved
//! around them with every other singularity kept.
//!
//! Why: each singular triangle of the field is a singular triangle of the parameterization (the
//! rotation matching of eq. 13 does not close around it, so Algorithm 1 gives an open path).
//! On coarse meshes the smoothing leaves ± pairs a few edges apart, where the curvature of a
//! handful of vertices turns the field by a quarter turn and back; a period (ten mean edge
//! lengths) cannot resolve them, so they only add singular triangles. Two opposite quarter
//! indices cancel: a field without either exists (Hopf–Poincaré only fixes the sum).
//!
//! How, in the angle form of the field. With H_v the reference direction of
//! [`super::smoothing`], β_v = 4 α_v the field's angle from H_v times 4, κ_e the angle of the
//! connection across e = (a, b) ([`reference_rotation`]) and p_e an integer, the matched
//! change of the field across e is `d_e = β_b − β_a + 4 κ_e + 2π p_e`, with p_e chosen so that
//! d_e ∈ (−π, π] (the quarter turn that eq. 13's matching picks). Around a triangle T the β's
//! cancel and
//!
//! ```text
//! q_T = (Σ_{e ∈ ∂T} ±d_e − 4 Ω_T) / 2π,   Ω_T = the holonomy Σ ±κ_e wrapped into (−π, π],
//! ```
//!
//! is an integer: the index of T in quarters (on a closed mesh Σ_T q_T = −(2/π) Σ_T Ω_T, which
//! is 4χ unless some Ω_T wrap around, see [`crate::methods::pgp::forced`]). Changing p_e by
//! ±1 moves a quarter from one triangle of e to the other, so changing it along a dual path
//! from a +¼ triangle to a −¼ one (shortest, by distances between centroids) cancels the pair
//! and keeps every other index. With the integers fixed, the field is the least-squares
//! solution (one sparse Cholesky solve, the p_e of the smoothed field changed on the paths)
//!
//! ```text
//! min_β  Σ_e w_e (β_b − β_a + 4 κ_e + 2π p_e)²  +  μ Σ_v A_v (β_v − β̂_v)²
//! ```
//!
//! with β̂ the smoothed field, A_v the vertex areas and μ = (ω / 2π)², so that the field
//! changes within about one period of the cancelled pairs and keeps the smoothing's alignment
//! elsewhere (the smoothness term alone is the angle form of eq. 22's). The weights w_e are 1:
//! the cotangent weights vanish or turn negative across the obtuse corners of coarse meshes
//! and leave those edges free, and the periodic solve's rotation matching then picks the old
//! quarter turn there again, restoring the pair. Measured with a first version of this step
//! (every pair of a round re-solved at once, no bisection), at one period: bob kept 8 field
//! singular triangles with cotangent weights clamped at 0 and 2 with unit weights, eight 16
//! and 8 (its genus's minimum); knight 34 and 40.
//!
//! The matrix does not depend on the integers, so it is factored once. Pairs are chosen
//! greedily, nearest first, each triangle's quarters used once, within a radius that grows to
//! the cancellation distance in [`RADIUS_STEPS`] steps. Since the periodic solve matches the
//! re-solved field again, a cancellation is kept only when the singular triangles counted from
//! the new field are fewer; a batch of pairs that is not is bisected (nearer half first) and a
//! single pair that is not is left alone. The count falls strictly at every kept step, so this
//! ends.
//!
//! Measured (README, "Singularity-pair cancellation"): bob 4.0 → 1.8%, eight 5.4 → 2.5%,
//! knight 5.9 → 3.6%, cow 2.5 → 1.2%, man 2.1 → 0.8% singular triangles.
//!
//! Measured and not kept (2026-12-04): re-weighting the edges whose change slips past the
//! matching's tie after a trial solve (×4 per round, 6 rounds, Woodbury updates of the factor),
//! so that the re-matching keeps the chosen integers: the slips moved to neighbouring edges,
//! and knight kept 30 field singular triangles instead of 28.
//!
//! Cost: a Dijkstra bounded by the radius per singular triangle, one V × V sparse Cholesky
//! factorization, and one solve per trial.

use super::frames::{normalized, wrap_angle, EdgeList};
use super::smoothing::{reference_directions, reference_rotation};
use crate::error::Result;
use crate::geometry::{cross, dot};
use crate::mesh::NONE;
use crate::TriMesh;
use faer::Mat;
use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap, HashSet};
use std::f64::consts::TAU;
use uvflat_sparse::{lower_from_entries, require_finite, CholeskySolver};

/// Trial solves per √(triangle count) ([`trial_budget`]).
pub const TRIALS_PER_SQRT_TRIANGLE: f64 = 1.0;

/// The pairing radius grows to the cancellation distance in this many steps.
pub const RADIUS_STEPS: usize = 4;

/// Default cancellation distance, in periods (2π/ω).
pub const DEFAULT_PAIR_PERIODS: f64 = 0.5;

/// What the cancellation did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PairReport {
    /// Singular triangles of the field before.
    pub singular_before: usize,
    /// Singular triangles of the returned field.
    pub singular_after: usize,
    /// Pairs cancelled (in the trials that were kept).
    pub pairs: usize,
    /// Trial solves made.
    pub trials: usize,
}

/// The cross field in angle form: per-vertex reference directions and 4α, per edge the
/// connection angle times 4.
struct AngleField {
    reference: Vec<[f64; 3]>,
    beta: Vec<f64>,
    connection: Vec<f64>,
}

/// The matching integers p and quarter indices of one set of angles β.
struct Matching {
    beta: Vec<f64>,
    jumps: Vec<i64>,
    indices: Vec<i64>,
    singular: usize,
}

/// Cancels the ± pairs of quarter singularities of the cross field `field` closer than
/// `distance` (module comment). Returns unit tangent vectors and the report.
pub fn cancel_singularity_pairs(
    mesh: &TriMesh,
    normals: &[[f64; 3]],
    field: &[[f64; 3]],
    distance: f64,
    omega: f64,
) -> Result<(Vec<[f64; 3]>, PairReport)> {
    let edges = EdgeList::new(mesh);
    let angles = angle_field(mesh, &edges, normals, field);
    let mut current = matching(mesh, &edges, &angles, angles.beta.clone());
    let before = current.singular;
    let mut report = PairReport { singular_before: before, singular_after: before, pairs: 0, trials: 0 };
    if before == 0 {
        return Ok((field.to_vec(), report));
    }
    let resolver = Resolver::new(mesh, &edges, &angles, omega)?;
    let mut blocked = HashSet::new();
    let trial = Trial { mesh, edges: &edges, angles: &angles, resolver: &resolver };
    let mut budget = trial_budget(mesh);
    let total = budget;
    for step in 1..=RADIUS_STEPS {
        let radius = distance * step as f64 / RADIUS_STEPS as f64;
        while budget > 0 {
            let paths = pair_paths(mesh, &current.indices, radius, &blocked);
            let cancelled = trial.cancel(&mut current, &paths, &mut blocked, &mut budget)?;
            if cancelled == 0 {
                break;
            }
            report.pairs += cancelled;
        }
    }
    report.singular_after = current.singular;
    report.trials = total - budget;
    if report.pairs == 0 {
        return Ok((field.to_vec(), report));
    }
    Ok((field_from_angles(normals, &angles.reference, &current.beta), report))
}

/// What a trial of cancellations needs.
struct Trial<'a> {
    mesh: &'a TriMesh,
    edges: &'a EdgeList,
    angles: &'a AngleField,
    resolver: &'a Resolver,
}

impl Trial<'_> {
    /// Cancels all `paths` at once and re-solves, keeping the result when it has fewer singular
    /// triangles than `current`; otherwise tries the nearer half, then the farther one
    /// (bisection, each on top of what was kept), and blocks a single pair that fails. Each
    /// solve costs one unit of `budget`. Returns how many pairs were cancelled.
    fn cancel(
        &self,
        current: &mut Matching,
        paths: &[Vec<usize>],
        blocked: &mut HashSet<(usize, usize)>,
        budget: &mut usize,
    ) -> Result<usize> {
        if paths.is_empty() || *budget == 0 {
            return Ok(0);
        }
        *budget -= 1;
        let mut jumps = current.jumps.clone();
        for path in paths {
            move_quarter_along(self.mesh, self.edges, &mut jumps, path);
        }
        let beta = self.resolver.solve(&jumps)?;
        let next = matching(self.mesh, self.edges, self.angles, beta);
        if next.singular < current.singular {
            *current = next;
            return Ok(paths.len());
        }
        if paths.len() == 1 {
            blocked.insert((paths[0][0], *paths[0].last().unwrap()));
            return Ok(0);
        }
        let (near, far) = paths.split_at(paths.len() / 2);
        Ok(self.cancel(current, near, blocked, budget)? + self.cancel(current, far, blocked, budget)?)
    }
}

/// Solves allowed in all: [`TRIALS_PER_SQRT_TRIANGLE`] × √F, so that the number of solves
/// grows more slowly than the mesh (measured: cow 6, armadillo 5, man 115 of 187, cheese 133
/// of 133).
pub(crate) fn trial_budget(mesh: &TriMesh) -> usize {
    (TRIALS_PER_SQRT_TRIANGLE * (mesh.triangle_count() as f64).sqrt()).ceil() as usize
}

/// β and κ of `field`.
fn angle_field(mesh: &TriMesh, edges: &EdgeList, normals: &[[f64; 3]], field: &[[f64; 3]]) -> AngleField {
    let reference = reference_directions(mesh, normals);
    let beta: Vec<f64> = (0..mesh.vertex_count())
        .map(|v| {
            let (h, n, k) = (reference[v], normals[v], field[v]);
            4.0 * dot(cross(h, k), n).atan2(dot(h, k))
        })
        .collect();
    let connection: Vec<f64> = edges
        .edges
        .iter()
        .map(|&[a, b]| {
            let (a, b) = (a as usize, b as usize);
            4.0 * reference_rotation(reference[a], normals[a], reference[b], normals[b])
        })
        .collect();
    AngleField { reference, beta, connection }
}

/// The matching of the angles `beta`: p_e wraps each change into (−π, π].
fn matching(mesh: &TriMesh, edges: &EdgeList, angles: &AngleField, beta: Vec<f64>) -> Matching {
    let jumps: Vec<i64> = edges
        .edges
        .iter()
        .zip(&angles.connection)
        .map(|(&[a, b], &c)| {
            let x = beta[b as usize] - beta[a as usize] + c;
            ((wrap_angle(x) - x) / TAU).round() as i64
        })
        .collect();
    let indices = triangle_indices(mesh, edges, angles, &beta, &jumps);
    let singular = indices.iter().filter(|&&q| q.rem_euclid(4) != 0).count();
    Matching { beta, jumps, indices, singular }
}

/// +1 when half-edge `h` runs along its edge's stored direction, −1 otherwise.
fn orientation(mesh: &TriMesh, edges: &EdgeList, h: usize) -> f64 {
    if edges.edges[edges.edge_of[h] as usize][0] == mesh.tail(h as u32) {
        1.0
    } else {
        -1.0
    }
}

/// q_T per triangle, in quarters (module comment).
fn triangle_indices(mesh: &TriMesh, edges: &EdgeList, angles: &AngleField, beta: &[f64], jumps: &[i64]) -> Vec<i64> {
    (0..mesh.triangle_count())
        .map(|t| {
            let (mut change, mut holonomy) = (0.0, 0.0);
            for k in 0..3 {
                let h = 3 * t + k;
                let (e, s) = (edges.edge_of[h] as usize, orientation(mesh, edges, h));
                let [a, b] = edges.edges[e];
                let d = beta[b as usize] - beta[a as usize] + angles.connection[e] + TAU * jumps[e] as f64;
                change += s * d;
                holonomy += s * angles.connection[e] / 4.0;
            }
            ((change - 4.0 * wrap_angle(holonomy)) / TAU).round() as i64
        })
        .collect()
}

/// Centroid of triangle `t`.
fn centroid(mesh: &TriMesh, t: usize) -> [f64; 3] {
    let p = mesh.triangles()[t].map(|v| mesh.points()[v as usize]);
    std::array::from_fn(|a| (p[0][a] + p[1][a] + p[2][a]) / 3.0)
}

/// Dual paths (triangle sequences) from +¼ to −¼ triangles, nearest pairs first, each quarter
/// used once, no longer than `distance`.
fn pair_paths(mesh: &TriMesh, indices: &[i64], distance: f64, blocked: &HashSet<(usize, usize)>) -> Vec<Vec<usize>> {
    let mut candidates = Vec::new();
    for (t, &q) in indices.iter().enumerate() {
        if q > 0 {
            for (u, d) in dual_distances(mesh, t, distance) {
                if indices[u] < 0 && !blocked.contains(&(t, u)) {
                    candidates.push((d, t, u));
                }
            }
        }
    }
    candidates.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut left: Vec<i64> = indices.to_vec();
    let mut paths = Vec::new();
    for (_, t, u) in candidates {
        if left[t] > 0 && left[u] < 0 {
            left[t] -= 1;
            left[u] += 1;
            paths.push(dual_path(mesh, t, u, distance));
        }
    }
    paths
}

/// Dijkstra over the dual graph from triangle `source`, up to `limit`: distance per reached
/// triangle, and each triangle's predecessor.
pub(crate) fn dual_search(mesh: &TriMesh, source: usize, limit: f64) -> (HashMap<usize, f64>, HashMap<usize, usize>) {
    let twin = &mesh.connectivity().twin;
    let mut dist = HashMap::from([(source, 0.0)]);
    let mut parent = HashMap::new();
    let mut heap = BinaryHeap::from([(Reverse(Ordered(0.0)), source)]);
    while let Some((Reverse(Ordered(d)), t)) = heap.pop() {
        if d > dist[&t] {
            continue;
        }
        let c = centroid(mesh, t);
        for k in 0..3 {
            let h = twin[3 * t + k];
            if h == NONE {
                continue;
            }
            let u = h as usize / 3;
            let nd = d + crate::geometry::norm(crate::geometry::sub(centroid(mesh, u), c));
            if nd <= limit && dist.get(&u).is_none_or(|&old| nd < old) {
                dist.insert(u, nd);
                parent.insert(u, t);
                heap.push((Reverse(Ordered(nd)), u));
            }
        }
    }
    (dist, parent)
}

/// Triangles within `limit` of `source` and their dual distances.
pub(crate) fn dual_distances(mesh: &TriMesh, source: usize, limit: f64) -> Vec<(usize, f64)> {
    dual_search(mesh, source, limit).0.into_iter().collect()
}

/// The shortest dual path from `from` to `to` (both included).
fn dual_path(mesh: &TriMesh, from: usize, to: usize, limit: f64) -> Vec<usize> {
    let parent = dual_search(mesh, from, limit).1;
    let mut path = vec![to];
    while let Some(&p) = parent.get(path.last().unwrap()) {
        path.push(p);
    }
    path.reverse();
    path
}

/// Changes the jumps on the edges crossed by `path` so that one quarter moves from its first
/// triangle to its last.
fn move_quarter_along(mesh: &TriMesh, edges: &EdgeList, jumps: &mut [i64], path: &[usize]) {
    let twin = &mesh.connectivity().twin;
    for step in path.windows(2) {
        let (t, u) = (step[0], step[1]);
        let h = (0..3).map(|k| 3 * t + k).find(|&h| twin[h] != NONE && twin[h] as usize / 3 == u).unwrap();
        // In t the edge adds orientation × p to Σ ±d; lowering t's sum by 2π raises u's.
        jumps[edges.edge_of[h] as usize] -= orientation(mesh, edges, h) as i64;
    }
}

/// The least-squares angles for given jumps (module comment): the matrix does not depend on
/// the jumps, so it is factored once.
struct Resolver {
    solver: CholeskySolver<f64>,
    anchor: Vec<f64>,
    weights: Vec<f64>,
    edges: Vec<[u32; 2]>,
    connection: Vec<f64>,
}

impl Resolver {
    fn new(mesh: &TriMesh, edges: &EdgeList, angles: &AngleField, omega: f64) -> Result<Self> {
        let n = mesh.vertex_count();
        let mu = (omega / TAU).powi(2);
        let mut diagonal = vec![0.0; n];
        let mut anchor = vec![0.0; n];
        for (t, tri) in mesh.triangles().iter().enumerate() {
            for &v in tri {
                let m = mu * mesh.geometry().area[t] / 3.0;
                diagonal[v as usize] += m;
                anchor[v as usize] += m * angles.beta[v as usize];
            }
        }
        let weights = vec![1.0; edges.edges.len()];
        let mut entries = Vec::with_capacity(edges.edges.len());
        for (e, &[a, b]) in edges.edges.iter().enumerate() {
            diagonal[a as usize] += weights[e];
            diagonal[b as usize] += weights[e];
            entries.push((a.max(b), a.min(b), -weights[e]));
        }
        for d in diagonal.iter_mut().filter(|d| **d == 0.0) {
            *d = 1.0; // unreferenced vertex: β = 0
        }
        let lower = lower_from_entries(&diagonal, entries)?;
        let solver = CholeskySolver::new(&lower, Some(mesh.points()))?;
        Ok(Resolver { solver, anchor, weights, edges: edges.edges.clone(), connection: angles.connection.clone() })
    }

    /// β minimizing the energy of the module comment for the integers `jumps`.
    fn solve(&self, jumps: &[i64]) -> Result<Vec<f64>> {
        let n = self.anchor.len();
        let mut rhs = Mat::<f64>::from_fn(n, 1, |i, _| self.anchor[i]);
        for (e, &[a, b]) in self.edges.iter().enumerate() {
            let wc = self.weights[e] * (self.connection[e] + TAU * jumps[e] as f64);
            rhs[(a as usize, 0)] += wc;
            rhs[(b as usize, 0)] -= wc;
        }
        self.solver.solve_in_place(&mut rhs)?;
        require_finite((0..n).map(|i| rhs[(i, 0)]), "singularity-pair cancellation")?;
        Ok((0..n).map(|i| rhs[(i, 0)]).collect())
    }
}

/// Unit tangent vectors at angle β/4 from the reference directions.
fn field_from_angles(normals: &[[f64; 3]], reference: &[[f64; 3]], beta: &[f64]) -> Vec<[f64; 3]> {
    (0..beta.len())
        .map(|v| {
            let (h, alpha) = (reference[v], beta[v] / 4.0);
            let nh = cross(normals[v], h);
            normalized(std::array::from_fn(|a| alpha.cos() * h[a] + alpha.sin() * nh[a]))
        })
        .collect()
}

/// f64 ordered by `total_cmp`, for the heap (also of [`crate::methods::quadcover::cone_pairs`]).
#[derive(PartialEq)]
pub(crate) struct Ordered(pub(crate) f64);

impl Eq for Ordered {}

impl PartialOrd for Ordered {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Ordered {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An n × n grid of unit squares in the plane z = 0, normals +z.
    fn grid(n: u32) -> (TriMesh, Vec<[f64; 3]>) {
        let mut p = Vec::new();
        for y in 0..=n {
            for x in 0..=n {
                p.extend_from_slice(&[x as f64, y as f64, 0.0]);
            }
        }
        let mut t = Vec::new();
        for y in 0..n {
            for x in 0..n {
                let v = y * (n + 1) + x;
                t.extend_from_slice(&[v, v + 1, v + n + 2, v, v + n + 2, v + n + 1]);
            }
        }
        let mesh = TriMesh::new(&p, &t).unwrap();
        let normals = vec![[0.0, 0.0, 1.0]; mesh.vertex_count()];
        (mesh, normals)
    }

    /// The cross field at angle α(p) = (arg(p − a) − arg(p − b)) / 4: a +¼ singularity at a and
    /// a −¼ one at b.
    fn pair_field(mesh: &TriMesh, a: [f64; 2], b: [f64; 2]) -> Vec<[f64; 3]> {
        mesh.points()
            .iter()
            .map(|p| {
                let alpha = ((p[1] - a[1]).atan2(p[0] - a[0]) - (p[1] - b[1]).atan2(p[0] - b[0])) / 4.0;
                [alpha.cos(), alpha.sin(), 0.0]
            })
            .collect()
    }

    fn indices_of(mesh: &TriMesh, normals: &[[f64; 3]], field: &[[f64; 3]]) -> Vec<i64> {
        let edges = EdgeList::new(mesh);
        let angles = angle_field(mesh, &edges, normals, field);
        matching(mesh, &edges, &angles, angles.beta.clone()).indices
    }

    #[test]
    fn a_constructed_pair_has_one_plus_and_one_minus_quarter() {
        let (mesh, normals) = grid(20);
        let q = indices_of(&mesh, &normals, &pair_field(&mesh, [8.3, 10.4], [11.6, 10.3]));
        assert_eq!(q.iter().filter(|&&x| x == 1).count(), 1, "{q:?}");
        assert_eq!(q.iter().filter(|&&x| x == -1).count(), 1);
        assert_eq!(q.iter().filter(|&&x| x != 0).count(), 2);
    }

    #[test]
    fn a_pair_closer_than_the_distance_is_cancelled_and_the_far_field_kept() {
        let (mesh, normals) = grid(20);
        let field = pair_field(&mesh, [8.3, 10.4], [11.6, 10.3]);
        let omega = TAU / 10.0;
        let (out, report) = cancel_singularity_pairs(&mesh, &normals, &field, 5.0, omega).unwrap();
        assert_eq!((report.singular_before, report.singular_after, report.pairs), (2, 0, 1));
        assert!(indices_of(&mesh, &normals, &out).iter().all(|&q| q == 0));
        // Unit vectors; at the corners, far from the pair, the cross barely turns.
        assert!(out.iter().all(|k| (crate::geometry::norm(*k) - 1.0).abs() < 1e-12));
        for v in [0usize, 20, 420, 440] {
            let (a, b) = (field[v], out[v]);
            let turn = 4.0 * (a[0] * b[1] - a[1] * b[0]).atan2(a[0] * b[0] + a[1] * b[1]);
            assert!(wrap_angle(turn).abs() < 0.6, "vertex {v} turned {turn} (4α)");
        }
    }

    #[test]
    fn a_pair_farther_than_the_distance_is_kept_unchanged() {
        let (mesh, normals) = grid(20);
        let field = pair_field(&mesh, [8.3, 10.4], [11.6, 10.3]);
        let (out, report) = cancel_singularity_pairs(&mesh, &normals, &field, 2.0, TAU / 10.0).unwrap();
        assert_eq!((report.singular_before, report.singular_after, report.pairs), (2, 2, 0));
        assert_eq!(out, field);
    }

    #[test]
    fn a_field_without_singularities_is_returned_as_it_is() {
        let (mesh, normals) = grid(6);
        let field = vec![[0.6, 0.8, 0.0]; mesh.vertex_count()];
        let (out, report) = cancel_singularity_pairs(&mesh, &normals, &field, 100.0, 1.0).unwrap();
        assert_eq!(report, PairReport::default());
        assert_eq!(out, field);
    }

    #[test]
    fn the_quarter_indices_of_a_closed_mesh_sum_to_four_chi() {
        // An octahedron (χ = 2) with an arbitrary tangent field: Σ q_T = 8.
        let p = [1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.0];
        let t = [0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5];
        let mesh = TriMesh::new(&p, &t).unwrap();
        let normals: Vec<[f64; 3]> = mesh.points().to_vec();
        let field: Vec<[f64; 3]> = normals
            .iter()
            .map(|n| {
                normalized(crate::geometry::sub(
                    [0.3, 0.5, 0.7],
                    super::super::frames::scale(*n, dot([0.3, 0.5, 0.7], *n)),
                ))
            })
            .collect();
        assert_eq!(indices_of(&mesh, &normals, &field).iter().sum::<i64>(), 8);
    }
}
