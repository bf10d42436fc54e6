//! Cone-pair cancellation of QuadCover's frame field (not in Kälberer, Nieser & Polthier 2007 or
//! the course notes' ch. 8; the face-based counterpart of PGP's singularity-pair cancellation,
//! [`crate::fields::pairs`]): a +¼ and a −¼ cone closer than a few grid cells are
//! removed together, and a cone closer than that to the boundary is moved onto it, with the
//! field re-solved around them and every other cone kept.
//!
//! Why: QuadCover's gaps are integers (§8.3.1), so the grid cannot bend between two cones closer
//! than a cell or two, and the triangles between them fold after rounding (README, "QuadCover").
//! A smoothed curvature field leaves such ± pairs where a few vertices' curvature turns the
//! field by a quarter and back; two opposite quarters cancel (Hopf–Poincaré fixes only the
//! sum), and a boundary vertex has no index, so a cone moved onto the boundary vanishes.
//!
//! How, in the angle form of the field. β_f = 4θ_f is four times the field's angle in triangle
//! f's basis; across the interior edge e with key half-edge k in f and its twin in g,
//!
//! ```text
//! d_e = β_g − β_f + c_e + 2π p_e,   c_e = −4 (a_g − a_f),   p_e ∈ ℤ with d_e ∈ [−π, π],
//! ```
//!
//! a_f and a_g the angles of the shared edge in the two bases (the unfolding transport of
//! [`super::matching`]; the matching there is r_e ≡ −p_e mod 4). Counter-clockwise around an
//! interior vertex v the β's cancel and
//!
//! ```text
//! q_v = (4 K_v + Σ ±d_e) / 2π,   K_v = 2π − Σ corner angles,
//! ```
//!
//! is v's index in quarters (the reading of
//! [`crate::fields::indices::face_field_indices`] times 4). Raising p_e of an edge
//! u → w by one moves a quarter from u to w, so raising it along a path of interior edges from
//! a +¼ cone to a −¼ one cancels both and keeps every other index. With the integers changed
//! by Δp the field is corrected by the least-squares angles
//!
//! ```text
//! min_x  Σ_e w_e (x_g − x_f + 2π Δp_e)²  +  μ Σ_f A_f x_f²,   β ← β + x,
//! ```
//!
//! w_e = |e| / |c_f − c_g| (the Dirichlet weights of [`super::field`]) and μ = 1/L², L =
//! [`SCREENING_CELLS`] grid cells: x is the discrete angle function of the pair (a 2π jump
//! along the path, smooth elsewhere), screened so that the field changes within a few cells of
//! the pair and nowhere else. The matrix does not depend on Δp, so it is factored once.
//!
//! Pairs (and cone–boundary moves) closer than the cancellation distance are tried nearest
//! first, each cone's quarters used once, within a radius that grows to the distance in
//! [`RADIUS_STEPS`] steps (PGP's schedule). The field is matched again after the correction,
//! so a batch is kept only when the re-matched field has fewer cones; a batch that does not is
//! bisected (nearer half first) and a single move that does not is not tried again. The count falls at every
//! kept step, so this ends; at most √F trial solves are made. Keeping a batch only when it
//! removes every cone it was meant to (2 per pair, 1 per boundary move) was measured and not
//! kept: the bisection then spends the budget on batches where re-matching opened a cone
//! elsewhere, and man kept 325 cones and 651 folded triangles instead of 128 and 152.

use super::field::{angle_in, basis, centroid, interior_edges, InteriorEdge};
use crate::error::Result;
use crate::fields::frames::{normalized, wrap_angle};
use crate::fields::pairs::{trial_budget, Ordered, RADIUS_STEPS};
use crate::TriMesh;
use faer::Mat;
use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap, HashSet};
use std::f64::consts::TAU;
use uvflat_sparse::{lower_from_entries, require_finite, CholeskySolver};

/// Default cancellation distance, in grid cells.
pub const DEFAULT_PAIR_CELLS: f64 = 2.0;

/// Screening length L of the correction, in grid cells (module comment).
pub const SCREENING_CELLS: f64 = 2.0;

/// What the cancellation did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ConePairReport {
    /// Cones of the field before.
    pub cones_before: usize,
    /// Cones of the returned field.
    pub cones_after: usize,
    /// ± pair moves made in the trials that were kept. A trial is kept when the re-matched
    /// field has fewer cones; re-matching can also open cones elsewhere, so `cones_before −
    /// cones_after` (the net change) may be less than 2 × `pairs` + `moved_to_boundary`.
    pub pairs: usize,
    /// Cone-to-boundary moves made in the trials that were kept.
    pub moved_to_boundary: usize,
    /// Trial solves made.
    pub trials: usize,
}

/// The field in angle form and the fixed parts of the indices.
struct AngleForm {
    bases: Vec<([f64; 3], [f64; 3])>,
    edges: Vec<InteriorEdge>,
    /// Interior edge of every half-edge (NONE on the boundary).
    edge_of: Vec<u32>,
    /// 4 K_v at interior vertices, NaN elsewhere (no index).
    defect: Vec<f64>,
}

/// The integers p_e and the quarter indices of one set of angles β.
struct Matched {
    beta: Vec<f64>,
    jumps: Vec<i64>,
    indices: Vec<i64>,
    cones: usize,
}

/// A quarter moved along a vertex path: from its first vertex to its last.
struct Move {
    path: Vec<u32>,
    to_boundary: bool,
}

/// Cancels the ± cone pairs of the frame field `directions` (one unit tangent per triangle)
/// closer than `distance`, and moves cones closer than it onto the boundary (module comment).
/// `spacing` is the grid cell. Returns the new field and the report.
pub fn cancel_cone_pairs(
    mesh: &TriMesh,
    directions: &[[f64; 3]],
    distance: f64,
    spacing: f64,
) -> Result<(Vec<[f64; 3]>, ConePairReport)> {
    let form = AngleForm::new(mesh);
    let beta: Vec<f64> = (0..mesh.triangle_count()).map(|t| 4.0 * angle_in(directions[t], form.bases[t])).collect();
    let mut current = form.matched(mesh, beta);
    let mut report = ConePairReport { cones_before: current.cones, cones_after: current.cones, ..Default::default() };
    if current.cones == 0 || !(distance > 0.0) {
        return Ok((directions.to_vec(), report));
    }
    let corrector = Corrector::new(mesh, &form, SCREENING_CELLS * spacing)?;
    let trial = Trial { mesh, form: &form, corrector: &corrector };
    let mut blocked = HashSet::new();
    let total = trial_budget(mesh);
    let mut budget = total;
    for step in 1..=RADIUS_STEPS {
        let radius = distance * step as f64 / RADIUS_STEPS as f64;
        while budget > 0 {
            let moves = candidate_moves(mesh, &current.indices, radius, &blocked);
            let (pairs, to_boundary) = trial.apply(&mut current, &moves, &mut blocked, &mut budget)?;
            if pairs + to_boundary == 0 {
                break;
            }
            report.pairs += pairs;
            report.moved_to_boundary += to_boundary;
        }
    }
    report.cones_after = current.cones;
    report.trials = total - budget;
    if report.pairs + report.moved_to_boundary == 0 {
        return Ok((directions.to_vec(), report));
    }
    let field = (0..mesh.triangle_count())
        .map(|t| {
            let (x, y) = form.bases[t];
            let theta = current.beta[t] / 4.0;
            normalized(std::array::from_fn(|d| theta.cos() * x[d] + theta.sin() * y[d]))
        })
        .collect();
    Ok((field, report))
}

impl AngleForm {
    fn new(mesh: &TriMesh) -> Self {
        let bases: Vec<_> = (0..mesh.triangle_count()).map(|t| basis(mesh, t)).collect();
        let (edges, edge_of) = interior_edges(mesh, &bases);
        let angles = mesh.corner_angles();
        let defect = (0..mesh.vertex_count() as u32)
            .map(|v| {
                if !mesh.is_referenced(v) || mesh.is_boundary_vertex(v) {
                    return f64::NAN;
                }
                let sum: f64 = mesh.outgoing_halfedges(v).map(|h| angles[(h / 3) as usize][(h % 3) as usize]).sum();
                4.0 * (TAU - sum)
            })
            .collect();
        AngleForm { bases, edges, edge_of, defect }
    }

    /// The matching of `beta` (p_e wraps each d_e into [−π, π]) and its cones.
    fn matched(&self, mesh: &TriMesh, beta: Vec<f64>) -> Matched {
        let jumps: Vec<i64> = self
            .edges
            .iter()
            .map(|e| {
                let x = beta[e.g as usize] - beta[e.f as usize] + e.transport;
                ((wrap_angle(x) - x) / TAU).round() as i64
            })
            .collect();
        let indices = self.indices(mesh, &beta, &jumps);
        let cones = indices.iter().filter(|&&q| q != 0).count();
        Matched { beta, jumps, indices, cones }
    }

    /// d_e of interior edge `e`.
    fn change(&self, beta: &[f64], jumps: &[i64], e: usize) -> f64 {
        let edge = &self.edges[e];
        beta[edge.g as usize] - beta[edge.f as usize] + edge.transport + TAU * jumps[e] as f64
    }

    /// q_v in quarters at every interior vertex (0 elsewhere).
    fn indices(&self, mesh: &TriMesh, beta: &[f64], jumps: &[i64]) -> Vec<i64> {
        (0..mesh.vertex_count() as u32)
            .map(|v| {
                let defect = self.defect[v as usize];
                if defect.is_nan() {
                    return 0;
                }
                // Counter-clockwise around v, edge h (outgoing) is crossed from twin(h)'s
                // triangle into h's: the change d of twin(h), −d_e when h is the key.
                let total = mesh.outgoing_halfedges(v).fold(defect, |acc, h| {
                    let e = self.edge_of[h as usize] as usize;
                    let d = self.change(beta, jumps, e);
                    if self.edges[e].key == h {
                        acc - d
                    } else {
                        acc + d
                    }
                });
                (total / TAU).round() as i64
            })
            .collect()
    }

    /// Moves one quarter from the first vertex of `path` to its last (module comment).
    fn move_quarter(&self, mesh: &TriMesh, jumps: &mut [i64], path: &[u32]) {
        for step in path.windows(2) {
            let h = mesh.outgoing_halfedges(step[0]).find(|&h| mesh.head(h) == step[1]).expect("path edge");
            let e = self.edge_of[h as usize] as usize;
            jumps[e] += if self.edges[e].key == h { 1 } else { -1 };
        }
    }
}

/// What a trial of moves needs.
struct Trial<'a> {
    mesh: &'a TriMesh,
    form: &'a AngleForm,
    corrector: &'a Corrector,
}

impl Trial<'_> {
    /// Makes all `moves` at once and keeps the corrected field when it has fewer cones than
    /// `current`; otherwise tries the nearer half, then the farther one (each on top of what
    /// was kept), and blocks a single move that fails. Each solve costs one unit of `budget`.
    /// Returns the pairs cancelled and the cones moved onto the boundary.
    fn apply(
        &self,
        current: &mut Matched,
        moves: &[Move],
        blocked: &mut HashSet<(u32, u32)>,
        budget: &mut usize,
    ) -> Result<(usize, usize)> {
        if moves.is_empty() || *budget == 0 {
            return Ok((0, 0));
        }
        *budget -= 1;
        let mut jumps = current.jumps.clone();
        for m in moves {
            self.form.move_quarter(self.mesh, &mut jumps, &m.path);
        }
        let delta: Vec<i64> = jumps.iter().zip(&current.jumps).map(|(a, b)| a - b).collect();
        let correction = self.corrector.solve(self.form, &delta)?;
        let beta = current.beta.iter().zip(&correction).map(|(b, x)| b + x).collect();
        let next = self.form.matched(self.mesh, beta);
        if next.cones < current.cones {
            *current = next;
            let to_boundary = moves.iter().filter(|m| m.to_boundary).count();
            return Ok((moves.len() - to_boundary, to_boundary));
        }
        if moves.len() == 1 {
            blocked.insert((moves[0].path[0], *moves[0].path.last().unwrap()));
            return Ok((0, 0));
        }
        let (near, far) = moves.split_at(moves.len() / 2);
        let a = self.apply(current, near, blocked, budget)?;
        let b = self.apply(current, far, blocked, budget)?;
        Ok((a.0 + b.0, a.1 + b.1))
    }
}

/// Moves within `radius`, nearest first, each cone's quarters used once: from every +¼ cone to
/// a −¼ one (a pair), or between a cone and the nearest boundary vertex.
fn candidate_moves(mesh: &TriMesh, indices: &[i64], radius: f64, blocked: &HashSet<(u32, u32)>) -> Vec<Move> {
    let mut candidates = Vec::new();
    let mut searches = HashMap::new();
    for (v, &q) in indices.iter().enumerate() {
        if q == 0 {
            continue;
        }
        let search = vertex_search(mesh, v as u32, radius);
        let boundary = search
            .distance
            .iter()
            .filter(|(&w, _)| mesh.is_boundary_vertex(w))
            .min_by(|a, b| a.1.total_cmp(b.1).then(a.0.cmp(b.0)));
        if let Some((&w, &d)) = boundary {
            if !blocked.contains(&(v as u32, w)) {
                candidates.push((d, v as u32, w));
            }
        }
        if q > 0 {
            for (&w, &d) in &search.distance {
                if indices[w as usize] < 0 && !blocked.contains(&(v as u32, w)) {
                    candidates.push((d, v as u32, w));
                }
            }
        }
        searches.insert(v as u32, search);
    }
    candidates.sort_by(|x, y| x.0.total_cmp(&y.0).then((x.1, x.2).cmp(&(y.1, y.2))));
    let mut left: Vec<i64> = indices.to_vec();
    let mut moves = Vec::new();
    for (_, v, w) in candidates {
        let to_boundary = indices[w as usize] == 0;
        let (qv, qw) = (left[v as usize], left[w as usize]);
        if qv == 0 || !(to_boundary || (qv > 0 && qw < 0)) {
            continue;
        }
        let mut path = searches[&v].path_to(w);
        if qv > 0 {
            left[v as usize] -= 1;
            if !to_boundary {
                left[w as usize] += 1;
            }
        } else {
            // A negative cone receives a quarter from the boundary.
            left[v as usize] += 1;
            path.reverse();
        }
        moves.push(Move { path, to_boundary });
    }
    moves
}

/// Dijkstra over the edges from a vertex: distances and predecessors of the reached vertices.
/// Boundary vertices are reached but not passed through (every edge used is interior).
struct VertexSearch {
    distance: HashMap<u32, f64>,
    parent: HashMap<u32, u32>,
}

impl VertexSearch {
    /// The path from the source to `to` (both included).
    fn path_to(&self, to: u32) -> Vec<u32> {
        let mut path = vec![to];
        while let Some(&p) = self.parent.get(path.last().unwrap()) {
            path.push(p);
        }
        path.reverse();
        path
    }
}

fn vertex_search(mesh: &TriMesh, source: u32, limit: f64) -> VertexSearch {
    let mut distance = HashMap::from([(source, 0.0)]);
    let mut parent = HashMap::new();
    let mut heap = BinaryHeap::from([(Reverse(Ordered(0.0)), source)]);
    while let Some((Reverse(Ordered(d)), v)) = heap.pop() {
        if d > distance[&v] || mesh.is_boundary_vertex(v) {
            continue;
        }
        let p = mesh.points()[v as usize];
        for h in mesh.outgoing_halfedges(v) {
            let w = mesh.head(h);
            let nd = d + crate::geometry::distance(p, mesh.points()[w as usize]);
            if nd <= limit && distance.get(&w).is_none_or(|&old| nd < old) {
                distance.insert(w, nd);
                parent.insert(w, v);
                heap.push((Reverse(Ordered(nd)), w));
            }
        }
    }
    VertexSearch { distance, parent }
}

/// The screened least-squares correction for integer changes Δp (module comment), factored
/// once.
struct Corrector {
    solver: CholeskySolver<f64>,
}

impl Corrector {
    fn new(mesh: &TriMesh, form: &AngleForm, screening: f64) -> Result<Self> {
        let mu = 1.0 / (screening * screening);
        let mut diagonal: Vec<f64> = mesh.geometry().area.iter().map(|a| mu * a).collect();
        let mut entries = Vec::with_capacity(form.edges.len());
        for e in &form.edges {
            diagonal[e.f as usize] += e.weight;
            diagonal[e.g as usize] += e.weight;
            entries.push((e.f.max(e.g), e.f.min(e.g), -e.weight));
        }
        for d in diagonal.iter_mut().filter(|d| !(**d > 0.0)) {
            *d = 1.0; // a zero-area triangle with no weighted edge: x = 0
        }
        let lower = lower_from_entries(&diagonal, entries)?;
        let centroids: Vec<[f64; 3]> = (0..mesh.triangle_count()).map(|t| centroid(mesh, t)).collect();
        Ok(Corrector { solver: CholeskySolver::new(&lower, Some(&centroids))? })
    }

    /// x for the changes `delta` of the integers.
    fn solve(&self, form: &AngleForm, delta: &[i64]) -> Result<Vec<f64>> {
        let n = self.solver.dim();
        let mut rhs = Mat::<f64>::zeros(n, 1);
        for (e, &dp) in form.edges.iter().zip(delta) {
            if dp != 0 {
                let wc = e.weight * TAU * dp as f64;
                rhs[(e.f as usize, 0)] += wc;
                rhs[(e.g as usize, 0)] -= wc;
            }
        }
        self.solver.solve_in_place(&mut rhs)?;
        require_finite((0..n).map(|i| rhs[(i, 0)]), "cone-pair cancellation")?;
        Ok((0..n).map(|i| rhs[(i, 0)]).collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fields::frames::triangle_normal;
    use crate::fields::indices::face_field_indices;
    use crate::geometry::{dot, norm, sub};

    /// An n × n grid of unit squares in the plane z = 0.
    fn grid(n: u32) -> TriMesh {
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
        TriMesh::new(&p, &t).unwrap()
    }

    /// One vector per triangle at angle Σ_k s_k arg(c − p_k) / 4 (c the centroid): a cone of
    /// index s_k/4 at every vertex p_k.
    fn cone_field(mesh: &TriMesh, cones: &[([f64; 2], f64)]) -> Vec<[f64; 3]> {
        (0..mesh.triangle_count())
            .map(|t| {
                let c = centroid(mesh, t);
                let alpha: f64 = cones.iter().map(|(p, s)| s * (c[1] - p[1]).atan2(c[0] - p[0])).sum::<f64>() / 4.0;
                [alpha.cos(), alpha.sin(), 0.0]
            })
            .collect()
    }

    fn quarter_indices(mesh: &TriMesh, field: &[[f64; 3]]) -> Vec<i64> {
        let form = AngleForm::new(mesh);
        let beta = (0..mesh.triangle_count()).map(|t| 4.0 * angle_in(field[t], form.bases[t])).collect();
        form.matched(mesh, beta).indices
    }

    #[test]
    fn the_angle_form_reads_the_indices_of_face_field_indices() {
        let mesh = grid(12);
        let field = cone_field(&mesh, &[([4.0, 6.0], 1.0), ([8.0, 5.0], -1.0), ([6.0, 9.0], 2.0)]);
        let q = quarter_indices(&mesh, &field);
        let reference = face_field_indices(&mesh, &field, 4);
        for v in 0..mesh.vertex_count() {
            assert_eq!(q[v] as f64, (4.0 * reference[v]).round(), "vertex {v}");
        }
        assert_eq!((q[6 * 13 + 4], q[5 * 13 + 8], q[9 * 13 + 6]), (1, -1, 2));
        assert_eq!(q.iter().filter(|&&x| x != 0).count(), 3);
        // A closed mesh: the quarters sum to 4χ = 8 on an octahedron, whatever the field.
        let p = [1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.0];
        let t = [0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5];
        let octahedron = TriMesh::new(&p, &t).unwrap();
        let field: Vec<[f64; 3]> = (0..8)
            .map(|t| {
                let n = triangle_normal(&octahedron, t);
                normalized(sub([0.3, 0.5, 0.7], crate::fields::frames::scale(n, dot([0.3, 0.5, 0.7], n))))
            })
            .collect();
        assert_eq!(quarter_indices(&octahedron, &field).iter().sum::<i64>(), 8);
    }

    #[test]
    fn a_pair_closer_than_the_distance_is_cancelled_and_the_far_field_kept() {
        let mesh = grid(20);
        let field = cone_field(&mesh, &[([8.0, 10.0], 1.0), ([11.0, 10.0], -1.0)]);
        let (out, report) = cancel_cone_pairs(&mesh, &field, 5.0, 1.0).unwrap();
        assert_eq!((report.cones_before, report.cones_after, report.pairs, report.moved_to_boundary), (2, 0, 1, 0));
        assert!(quarter_indices(&mesh, &out).iter().all(|&q| q == 0));
        assert!(out.iter().all(|k| (norm(*k) - 1.0).abs() < 1e-12 && k[2] == 0.0));
        // Far from the pair (the four corner triangles) the cross barely turns.
        for t in [0, 39, 760, 799] {
            let (a, b) = (field[t], out[t]);
            let turn = 4.0 * (a[0] * b[1] - a[1] * b[0]).atan2(dot(a, b));
            assert!(wrap_angle(turn).abs() < 0.3, "triangle {t} turned {turn} (4θ)");
        }
    }

    #[test]
    fn a_pair_farther_than_the_distance_or_no_distance_keeps_the_field() {
        let mesh = grid(20);
        let field = cone_field(&mesh, &[([5.0, 10.0], 1.0), ([15.0, 10.0], -1.0)]);
        for distance in [4.0, 0.0] {
            let (out, report) = cancel_cone_pairs(&mesh, &field, distance, 1.0).unwrap();
            assert_eq!((report.cones_before, report.cones_after, report.pairs), (2, 2, 0));
            assert_eq!(out, field);
        }
    }

    #[test]
    fn a_cone_near_the_boundary_is_moved_onto_it() {
        let mesh = grid(16);
        for sign in [1.0, -1.0] {
            let field = cone_field(&mesh, &[([2.0, 8.0], sign), ([12.0, 8.0], 2.0 * sign)]);
            let (out, report) = cancel_cone_pairs(&mesh, &field, 3.0, 1.0).unwrap();
            assert_eq!((report.cones_before, report.cones_after, report.moved_to_boundary), (2, 1, 1), "sign {sign}");
            let q = quarter_indices(&mesh, &out);
            assert_eq!(q[8 * 17 + 12], 2 * sign as i64, "the far cone is kept");
            assert_eq!(q.iter().filter(|&&x| x != 0).count(), 1);
        }
    }
}
