//! Dislocation-pair annihilation (not in Ray et al. 2006; a step between the periodic solve of
//! §2.5 and Algorithm 1's extraction, §3.1): two open triangles of opposite winding, where the
//! rotation matching closes but θ (or φ) turns by a whole period around a regular point of the
//! field, are removed together by turning the phases around them; a lone one is moved into a
//! nearby singular triangle of the field.
//!
//! Why: such a *dislocation* (an edge dislocation of the wave pattern: one more iso-line on one
//! side than on the other) is a singular triangle of §3.2 although the field has no
//! singularity there. On coarse meshes F*'s minimizer keeps ± pairs of them a period or less
//! apart where the field's curl is large (measured on the coarse knight: re-solving the phases
//! from scratch around each pair gives them back), so the periodic solve alone does not remove
//! them. A +1 and a −1 winding cancel: phases without either exist near them; and a singular
//! triangle of the field is open whatever the phases, so a winding moved into it costs nothing.
//!
//! How, in a region around the pair (the triangles within the pair's dual distance plus half a
//! period of the first one). Its vertices whose triangles all lie in the region are *free*; the
//! others keep their phases. With r_ab eq. 13's matching of edge (a, b) and P the quarter turn
//! (θ, φ) → (φ, −θ) that it applies to the phases, g_ab = wrap(P^{r_ab} (θ, φ)_b − (θ, φ)_a −
//! δ_ab) is the edge's wrapped residual against the expected increment δ_ab (eq. 13), in a's
//! frame; around a triangle whose matching closes, `w_T = Σ_{∂T} g / 2π` (carried to one
//! corner's frame) is its winding, a pair of integers. Adding 2π w to the target of every edge
//! crossed by a dual path from T1 (winding w) to T2 (winding −w, once carried along the path),
//! each edge taken as in the triangle the path leaves and w carried into its tail's frame,
//! moves T1's winding along the path onto T2, where it cancels. The phase change δ = (δθ, δφ)
//! per free vertex, in its own frame, is the least-squares fit (unit weights, δ = 0 on the
//! fixed vertices)
//!
//! ```text
//! min_δ  Σ_e ‖P^{r_ab} δ_b − δ_a − c_e‖²,   c_e = 2π w on the path's edges, 0 elsewhere,
//! ```
//!
//! whose residual is the discrete field of a vortex pair: it turns the edges' residuals around
//! T1 and T2 by ∓2π in total and decays away from them, so every other winding is kept (while
//! no edge's residual crosses ±π). One sparse Cholesky solve per trial; each vertex's unknowns
//! X_v are turned by its δ (norms kept). The path is the fewest-step one through triangles
//! whose matching closes, searched over (triangle, carried winding) states, so that it may go
//! round a singularity of the field when the winding must turn by a quarter to meet −w. A lone
//! dislocation is moved the same way into a singular triangle of the field (whose matching does
//! not close, so it is open whatever the phases).
//!
//! A change is kept only when the singular triangles of §3.2 (open, or of non-positive (θ, φ)
//! area) among the triangles it can touch fall by two (a pair) or one (a move into a field
//! singularity). Each round tries the pairs nearest first, then the moves nearest first, each
//! dislocation once; rounds repeat until one keeps nothing ([`DISLOCATION_ROUNDS`] at most).
//! Measured (README, "Dislocation annihilation"): the coarse knight 3.6 / 3.6% → 3.0 / 2.8%
//! singular triangles (PGP / ccPGP).
//!
//! Cost: O(F) per round to find the dislocations, a dual Dijkstra per dislocation, and per
//! trial a sparse Cholesky factorization of the region's connection Laplacian (2 unknowns per
//! free vertex, about a thousand vertices at the default distance). Trials whose regions share
//! no triangle run in parallel (a trial reads and writes only its region, so the result is
//! the one-at-a-time order's); the singular flags of all triangles are kept between trials,
//! and a trial stops recounting as soon as its touched triangles can no longer fall by enough
//! (most rejected trials add more than ten singular triangles). Measured on `closed_g0_man`
//! (457 trials, 9 kept): the step's share of a CLI run went from 6.9 to 4.4 s (medians of 3
//! interleaved runs with and without it, 2026-12-04), with the same phases.

use super::extraction::{angles, corner_triangle_parameterization, triangle_parameterization};
use super::periodic::{corner_frames, expected_increments, rotate_unknowns};
use super::singularities::signed_area2;
use super::untangle::turn_phases;
use crate::error::Result;
use crate::fields::frames::{match_rotation, rotate_coords, wrap_angle};
use crate::fields::pairs::{dual_distances, dual_search};
use crate::mesh::NONE;
use crate::TriMesh;
use faer::Mat;
use rayon::prelude::*;
use std::collections::{HashMap, HashSet, VecDeque};
use std::f64::consts::{PI, TAU};
use uvflat_sparse::{lower_from_entries, CholeskySolver};

/// Default pairing distance, in periods (2π/ω).
pub const DEFAULT_DISLOCATION_PERIODS: f64 = 1.5;

/// Rounds of pairing at most (each tries every pair once).
pub const DISLOCATION_ROUNDS: usize = 4;

/// Trials per √(triangle count) in all ([`trial_budget`]).
pub const DISLOCATION_TRIALS_PER_SQRT_TRIANGLE: f64 = 4.0;

/// Field singular triangles a lone dislocation may be moved into: the nearest ones.
pub const ABSORPTION_CANDIDATES: usize = 4;

/// What the annihilation did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct DislocationReport {
    /// Dislocations (open triangles whose matching closes) before.
    pub before: usize,
    /// Pairs annihilated (changes kept).
    pub pairs: usize,
    /// Dislocations moved into a nearby singular triangle of the field (changes kept).
    pub absorbed: usize,
    /// Pairs and absorptions tried.
    pub trials: usize,
}

/// What every trial reads.
struct Context<'a> {
    mesh: &'a TriMesh,
    normals: &'a [[f64; 3]],
    field: &'a [[f64; 3]],
    omega: f64,
    /// Triangles around each vertex, counted.
    valence: Vec<u32>,
    /// Whether the rotation matching closes around each triangle.
    closing: Vec<bool>,
    /// Eq. 13's matching of each half-edge a → b: the quarter turn r with `P^r` taking (θ, φ)
    /// at b into a's frame; and of its reverse b → a.
    along: Vec<u8>,
    against: Vec<u8>,
}

/// Annihilates pairs of opposite dislocations closer than `distance` by turning the phases in
/// `unknowns` (module comment).
pub fn annihilate_dislocations(
    mesh: &TriMesh,
    normals: &[[f64; 3]],
    field: &[[f64; 3]],
    unknowns: &mut [[f64; 4]],
    omega: f64,
    distance: f64,
) -> Result<DislocationReport> {
    annihilate_in_batches(mesh, (normals, field), unknowns, omega, distance, BATCH)
}

/// [`annihilate_dislocations`] with at most `batch` trials at once.
fn annihilate_in_batches(
    mesh: &TriMesh,
    (normals, field): (&[[f64; 3]], &[[f64; 3]]),
    unknowns: &mut [[f64; 4]],
    omega: f64,
    distance: f64,
    batch: usize,
) -> Result<DislocationReport> {
    let closing: Vec<bool> =
        (0..mesh.triangle_count()).into_par_iter().map(|t| matching_closes(mesh, normals, field, t)).collect();
    let mut valence = vec![0u32; mesh.vertex_count()];
    for tri in mesh.triangles() {
        for &v in tri {
            valence[v as usize] += 1;
        }
    }
    let half_edge_matching = |h: usize, forward: bool| {
        let (a, b) = (mesh.tail(h as u32) as usize, mesh.head(h as u32) as usize);
        let (a, b) = if forward { (a, b) } else { (b, a) };
        match_rotation(field[a], normals[a], normals[b], field[b])
    };
    let along = (0..3 * mesh.triangle_count()).into_par_iter().map(|h| half_edge_matching(h, true)).collect();
    let against = (0..3 * mesh.triangle_count()).into_par_iter().map(|h| half_edge_matching(h, false)).collect();
    let ctx = Context { mesh, normals, field, omega, valence, closing, along, against };
    let singular = (0..mesh.triangle_count())
        .into_par_iter()
        .with_min_len(1024)
        .map(|t| is_singular(&ctx, mesh.triangles()[t].map(|v| unknowns[v as usize]), t))
        .collect();
    let mut phases = Phases { unknowns, singular };
    let mut report = DislocationReport { before: dislocations(&ctx, phases.unknowns).len(), ..Default::default() };
    let mut blocked = HashSet::new();
    let budget = trial_budget(mesh);
    for _ in 0..DISLOCATION_ROUNDS {
        let list = candidates(&ctx, phases.unknowns, distance, &blocked);
        let kept = run_round(&ctx, &mut phases, (&list, batch), &mut blocked, &mut report, budget)?;
        if kept == 0 || report.trials == budget {
            break;
        }
    }
    Ok(report)
}

/// What the trials change: the unknowns and whether each triangle is singular (§3.2).
struct Phases<'a> {
    unknowns: &'a mut [[f64; 4]],
    singular: Vec<bool>,
}

/// A kept trial: the new unknowns of its region's free vertices and the new singular flags of
/// the triangles it touches.
struct Change {
    unknowns: Vec<(usize, [f64; 4])>,
    singular: Vec<(usize, bool)>,
}

/// Trials run at once (in parallel); a batch looks for them among the [`LOOKAHEAD`] × `batch`
/// candidates from the first one still to run.
const BATCH: usize = 8;
const LOOKAHEAD: usize = 4;

/// One round: each candidate `(t1, t2, distance)` of `list` tried once, in order, while the
/// budget lasts. Trials run in batches (of `batch_size` at most) of candidates whose regions
/// share no triangle with one another nor with an earlier candidate still to run: a trial
/// reads and writes only its region, so the outcome is the one-at-a-time order's. Returns the
/// changes kept.
fn run_round(
    ctx: &Context,
    phases: &mut Phases,
    (list, batch_size): (&[(usize, usize, f64)], usize),
    blocked: &mut HashSet<(usize, usize)>,
    report: &mut DislocationReport,
    budget: usize,
) -> Result<usize> {
    let mut regions: Vec<Option<Region>> = (0..list.len()).map(|_| None).collect();
    let mut done = vec![false; list.len()];
    let mut used = HashSet::new();
    let mut claimed = vec![0u32; ctx.mesh.triangle_count()];
    let (mut first, mut stamp, mut kept) = (0, 0u32, 0);
    loop {
        while first < list.len() && done[first] {
            first += 1;
        }
        if first == list.len() || report.trials == budget {
            return Ok(kept);
        }
        stamp += 1;
        let mut batch = Vec::new();
        for i in first..list.len().min(first + LOOKAHEAD * batch_size) {
            let (t1, t2, d) = list[i];
            if done[i] {
                continue;
            }
            if used.contains(&t1) || (ctx.closing[t2] && used.contains(&t2)) {
                done[i] = true;
                continue;
            }
            let region = regions[i].get_or_insert_with(|| region(ctx, t1, d + PI / ctx.omega));
            let free = region.triangles.iter().all(|&u| claimed[u] != stamp);
            for &u in &region.triangles {
                claimed[u] = stamp;
            }
            if free {
                batch.push(i);
            }
            if batch.len() == batch_size || report.trials + batch.len() == budget {
                break;
            }
        }
        let outcomes: Vec<Result<Option<Change>>> = batch
            .par_iter()
            .map(|&i| {
                let region = regions[i].as_ref().expect("batched candidates have their region");
                try_pair(ctx, phases, list[i].0, list[i].1, region)
            })
            .collect();
        for (&i, outcome) in batch.iter().zip(outcomes) {
            let (t1, t2, _) = list[i];
            report.trials += 1;
            done[i] = true;
            regions[i] = None;
            match outcome? {
                Some(change) => {
                    apply(phases, change);
                    used.extend([t1, t2]);
                    if ctx.closing[t2] {
                        report.pairs += 1;
                    } else {
                        report.absorbed += 1;
                    }
                    kept += 1;
                }
                None => {
                    blocked.insert((t1, t2));
                }
            }
        }
    }
}

fn apply(phases: &mut Phases, change: Change) {
    for (v, x) in change.unknowns {
        phases.unknowns[v] = x;
    }
    for (t, s) in change.singular {
        phases.singular[t] = s;
    }
}

/// Trials allowed in all: [`DISLOCATION_TRIALS_PER_SQRT_TRIANGLE`] × √F, so that the work
/// grows more slowly than the mesh where dislocations are everywhere (the sliver-ridden cheese).
fn trial_budget(mesh: &TriMesh) -> usize {
    (DISLOCATION_TRIALS_PER_SQRT_TRIANGLE * (mesh.triangle_count() as f64).sqrt()).ceil() as usize
}

/// Whether eq. 13's matching closes around triangle `t` (corner 1 → 2 agrees with 0 → 2).
fn matching_closes(mesh: &TriMesh, normals: &[[f64; 3]], field: &[[f64; 3]], t: usize) -> bool {
    let tri = mesh.triangles()[t];
    let frames = corner_frames(mesh, normals, field, t);
    let (v1, v2) = (tri[1] as usize, tri[2] as usize);
    match_rotation(frames[1].1, normals[v1], normals[v2], field[v2]) == frames[2].0
}

/// Triangles that are open although their matching closes.
fn dislocations(ctx: &Context, unknowns: &[[f64; 4]]) -> Vec<usize> {
    (0..ctx.mesh.triangle_count())
        .into_par_iter()
        .with_min_len(1024)
        .filter(|&t| {
            ctx.closing[t] && triangle_parameterization(ctx.mesh, ctx.normals, ctx.field, unknowns, ctx.omega, t).open
        })
        .collect()
}

/// Dislocation pairs within `distance` (dual distance between centroids), nearest first, then
/// (dislocation, field-singular triangle) pairs, nearest first.
fn candidates(
    ctx: &Context,
    unknowns: &[[f64; 4]],
    distance: f64,
    blocked: &HashSet<(usize, usize)>,
) -> Vec<(usize, usize, f64)> {
    let found = dislocations(ctx, unknowns);
    let is_dislocation: HashSet<usize> = found.iter().copied().collect();
    let nearby: Vec<Vec<(usize, f64)>> = found
        .par_iter()
        .map(|&t| {
            let mut near = dual_distances(ctx.mesh, t, distance);
            near.sort_by(|x, y| x.1.total_cmp(&y.1).then(x.0.cmp(&y.0)));
            near
        })
        .collect();
    let (mut pairs, mut absorptions) = (Vec::new(), Vec::new());
    for (&t, near) in found.iter().zip(nearby) {
        let mut singular = 0;
        for (u, d) in near {
            if blocked.contains(&(t, u)) {
                continue;
            }
            if !ctx.closing[u] && singular < ABSORPTION_CANDIDATES {
                absorptions.push((t, u, d));
                singular += 1;
            } else if u > t && is_dislocation.contains(&u) {
                pairs.push((t, u, d));
            }
        }
    }
    // Nearest first; ties (symmetric meshes) in triangle order, so that the result does not
    // depend on hash order.
    let nearest_first =
        |x: &(usize, usize, f64), y: &(usize, usize, f64)| x.2.total_cmp(&y.2).then((x.0, x.1).cmp(&(y.0, y.1)));
    pairs.sort_by(nearest_first);
    absorptions.sort_by(nearest_first);
    pairs.extend(absorptions);
    pairs
}

/// A search state of [`free_dual_path`]: a triangle and the winding carried into its corner
/// 0's frame.
type State = (usize, [i64; 2]);

/// The region of a trial: its triangles (nearest to its first triangle first) and its free
/// vertices (numbered).
struct Region {
    triangles: Vec<usize>,
    free: HashMap<usize, usize>,
}

/// Tries to annihilate `t1` and `t2` in `region` (the triangles within a radius of `t1`):
/// the change, when the singular triangles it touches fall by two (a pair) or one (a move into
/// a field singularity).
fn try_pair(ctx: &Context, phases: &Phases, t1: usize, t2: usize, region: &Region) -> Result<Option<Change>> {
    let unknowns = &*phases.unknowns;
    let w1 = triangle_winding(ctx, unknowns, t1);
    let w2 = if ctx.closing[t2] { Some(triangle_winding(ctx, unknowns, t2)) } else { None };
    if w1 == [0, 0] || w2 == Some([0, 0]) {
        return Ok(None);
    }
    let Some(path) = free_dual_path(ctx, region, (t1, w1), (t2, w2)) else { return Ok(None) };
    let delta = phase_change(ctx, region, &path, w1, ctx.mesh.triangles()[t1][0] as usize)?;
    let mut moved = vec![[0.0; 4]; region.free.len()];
    for (&v, &i) in &region.free {
        moved[i] = turn_phases(unknowns[v], delta[i]);
    }
    let corners = |t: usize| {
        ctx.mesh.triangles()[t].map(|v| region.free.get(&(v as usize)).map_or(unknowns[v as usize], |&i| moved[i]))
    };
    // A pair removes two singular triangles; an absorption one (t2 stays open).
    let gain = if w2.is_some() { 2 } else { 1 };
    let Some(singular) = fewer_singular(ctx, &phases.singular, &touched_triangles(ctx, region), corners, gain) else {
        return Ok(None);
    };
    let unknowns = region.free.iter().map(|(&v, &i)| (v, moved[i])).collect();
    Ok(Some(Change { unknowns, singular }))
}

/// The new singular flags of `touched` (their unknowns given by `corners`) when at least `gain`
/// fewer of them are singular than `singular` says; `None` as soon as that cannot happen (the
/// triangles singular before are the only ones that can still improve).
fn fewer_singular(
    ctx: &Context,
    singular: &[bool],
    touched: &[usize],
    corners: impl Fn(usize) -> [[f64; 4]; 3],
    gain: i64,
) -> Option<Vec<(usize, bool)>> {
    let mut improvable = touched.iter().filter(|&&t| singular[t]).count() as i64;
    let mut change = 0i64;
    let mut flags = Vec::with_capacity(touched.len());
    for &t in touched {
        let now = is_singular(ctx, corners(t), t);
        improvable -= singular[t] as i64;
        change += now as i64 - singular[t] as i64;
        if change - improvable > -gain {
            return None;
        }
        flags.push((t, now));
    }
    Some(flags)
}

/// Triangles within `radius` of `t` (dual distance) and the vertices all of whose triangles
/// are among them.
fn region(ctx: &Context, t: usize, radius: f64) -> Region {
    let mut near: Vec<(usize, f64)> = dual_search(ctx.mesh, t, radius).0.into_iter().collect();
    near.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
    let triangles: Vec<usize> = near.into_iter().map(|(u, _)| u).collect();
    let mut inside: HashMap<usize, u32> = HashMap::new();
    for &u in &triangles {
        for &v in &ctx.mesh.triangles()[u] {
            *inside.entry(v as usize).or_default() += 1;
        }
    }
    let mut free: Vec<usize> = inside.iter().filter(|&(&v, &n)| n == ctx.valence[v]).map(|(&v, _)| v).collect();
    free.sort_unstable();
    Region { triangles, free: free.into_iter().enumerate().map(|(i, v)| (v, i)).collect() }
}

/// An integer (θ, φ) vector in the frame of `from` expressed in the frame of `to`, both
/// vertices of triangle `t` (the same one or an edge's two ends).
fn carry(ctx: &Context, t: usize, from: usize, to: usize, w: [i64; 2]) -> [i64; 2] {
    if from == to {
        return w;
    }
    let tri = ctx.mesh.triangles()[t];
    let corner = |v: usize| tri.iter().position(|&x| x as usize == v).expect("a vertex of the triangle");
    let (i, j) = (corner(from), corner(to));
    // Half-edge 3t + k runs from corner k to corner k + 1.
    let m = if j == (i + 1) % 3 { ctx.along[3 * t + i] } else { ctx.against[3 * t + j] };
    rotate_coords((4 - m) % 4, w.map(|x| x as f64)).map(|x| x.round() as i64)
}

/// Winding (θ, φ) of triangle `t` in its corner 0's frame: the wrapped residuals of eq. 13's
/// increments summed around it, in periods.
fn triangle_winding(ctx: &Context, unknowns: &[[f64; 4]], t: usize) -> [i64; 2] {
    let tri = ctx.mesh.triangles()[t];
    let frames = corner_frames(ctx.mesh, ctx.normals, ctx.field, t);
    let p = tri.map(|v| ctx.mesh.points()[v as usize]);
    let base: [[f64; 2]; 3] = std::array::from_fn(|c| angles(rotate_unknowns(frames[c].0, unknowns[tri[c] as usize])));
    let mut sum = [0.0; 2];
    for c in 0..3 {
        let n = (c + 1) % 3;
        let (d, dp) = expected_increments(&p, &frames, ctx.omega, c, n);
        sum[0] += wrap_angle(base[n][0] - base[c][0] - d);
        sum[1] += wrap_angle(base[n][1] - base[c][1] - dp);
    }
    sum.map(|s| (s / TAU).round() as i64)
}

/// Whether half-edge `h` has a free endpoint.
fn crossable(ctx: &Context, region: &Region, h: usize) -> bool {
    let (a, b) = (ctx.mesh.tail(h as u32) as usize, ctx.mesh.head(h as u32) as usize);
    region.free.contains_key(&a) || region.free.contains_key(&b)
}

/// Fewest-step dual path from `t1` to `t2` inside the region, through triangles whose matching
/// closes and across edges with a free endpoint, along which `w1` (t1's winding) arrives as
/// −`w2` (t2's): as the half-edges crossed (each in the triangle the path leaves). The search
/// runs over (triangle, winding carried into its corner 0's frame) pairs, so that a path may go
/// round a field singularity to turn the winding by a quarter.
fn free_dual_path(
    ctx: &Context,
    region: &Region,
    (t1, w1): (usize, [i64; 2]),
    (t2, w2): (usize, Option<[i64; 2]>),
) -> Option<Vec<usize>> {
    let twin = &ctx.mesh.connectivity().twin;
    let corner0 = |t: usize| ctx.mesh.triangles()[t][0] as usize;
    let inside: HashSet<usize> = region.triangles.iter().copied().collect();
    let mut goal = w2.map(|w| (t2, w.map(|x| -x)));
    let mut via: HashMap<State, (State, usize)> = HashMap::new();
    let mut seen = HashSet::from([(t1, w1)]);
    let mut queue = VecDeque::from([(t1, w1)]);
    while let Some((t, w)) = queue.pop_front() {
        if t == t2 && goal.is_none_or(|g| g == (t, w)) {
            goal = Some((t, w));
            break;
        }
        for h in 3 * t..3 * t + 3 {
            let g = twin[h];
            if g == NONE || !crossable(ctx, region, h) {
                continue;
            }
            let u = g as usize / 3;
            if !inside.contains(&u) || !(ctx.closing[u] || u == t2) {
                continue;
            }
            let a = ctx.mesh.tail(h as u32) as usize;
            let next = (u, carry(ctx, u, a, corner0(u), carry(ctx, t, corner0(t), a, w)));
            if seen.insert(next) {
                via.insert(next, ((t, w), h));
                queue.push_back(next);
            }
        }
    }
    let mut path = Vec::new();
    let mut state = goal?;
    while state != (t1, w1) {
        let &(previous, h) = via.get(&state)?;
        path.push(h);
        state = previous;
    }
    path.reverse();
    Some(path)
}

/// (δθ, δφ) per free vertex, each in its vertex's frame: the least-squares fit of the module
/// comment, `Σ_e ‖P^{r_ab} δ_b − δ_a − c_ab‖²` over the region's edges (a < b, r_ab eq. 13's
/// matching), with c = 2π w (carried from `start`'s frame) on the half-edges of `path`.
fn phase_change(ctx: &Context, region: &Region, path: &[usize], w: [i64; 2], start: usize) -> Result<Vec<[f64; 2]>> {
    let mut target: HashMap<(usize, usize), [f64; 2]> = HashMap::new();
    let mut current = (start, w);
    for &h in path {
        let (a, b) = (ctx.mesh.tail(h as u32) as usize, ctx.mesh.head(h as u32) as usize);
        current = (a, carry(ctx, h / 3, current.0, a, current.1));
        let c = current.1.map(|x| TAU * x as f64);
        // c is given on a → b in a's frame; the term of (min, max) is in min's frame.
        let c = if a < b { c } else { rotate_coords(ctx.against[h], c).map(|x| -x) };
        let e = target.entry((a.min(b), a.max(b))).or_default();
        *e = [e[0] + c[0], e[1] + c[1]];
    }
    let n = region.free.len();
    let mut diagonal = vec![0.0; 2 * n];
    let mut entries = Vec::new();
    let mut rhs = Mat::<f64>::zeros(2 * n, 1);
    for (a, b, r) in region_edges(ctx, region) {
        let c = target.get(&(a, b)).copied().unwrap_or([0.0; 2]);
        let (fa, fb) = (region.free.get(&a).copied(), region.free.get(&b).copied());
        if let Some(i) = fa {
            add_edge_rows(&mut diagonal, &mut rhs, i, c.map(|x| -x));
        }
        if let Some(j) = fb {
            // Qᵀ c with Q = P^r: P^{−r}.
            add_edge_rows(&mut diagonal, &mut rhs, j, rotate_coords((4 - r) % 4, c));
        }
        if let (Some(i), Some(j)) = (fa, fb) {
            for k in 0..2 {
                let column = rotate_coords(r, [(k == 0) as u8 as f64, (k == 1) as u8 as f64]);
                for (l, &q) in column.iter().enumerate() {
                    if q != 0.0 {
                        // Block (a, b) = −Q: row 2i + l, column 2j + k.
                        let (row, col) = (2 * i + l, 2 * j + k);
                        entries.push((row.max(col) as u32, row.min(col) as u32, -q));
                    }
                }
            }
        }
    }
    let lower = lower_from_entries(&diagonal, entries)?;
    CholeskySolver::new(&lower, None)?.solve_in_place(&mut rhs)?;
    Ok((0..n).map(|i| [rhs[(2 * i, 0)], rhs[(2 * i + 1, 0)]]).collect())
}

/// One edge's identity block and right-hand side on the rows of free vertex `i`.
fn add_edge_rows(diagonal: &mut [f64], rhs: &mut Mat<f64>, i: usize, value: [f64; 2]) {
    for (k, v) in value.into_iter().enumerate() {
        diagonal[2 * i + k] += 1.0;
        rhs[(2 * i + k, 0)] += v;
    }
}

/// Edges (a < b) of the region's triangles with a free endpoint, and eq. 13's matching from a
/// to b.
fn region_edges(ctx: &Context, region: &Region) -> Vec<(usize, usize, u8)> {
    let mut edges = HashMap::new();
    for &u in &region.triangles {
        let tri = ctx.mesh.triangles()[u];
        for k in 0..3 {
            let (a, b) = (tri[k] as usize, tri[(k + 1) % 3] as usize);
            if region.free.contains_key(&a) || region.free.contains_key(&b) {
                let h = 3 * u + k;
                edges.entry((a.min(b), a.max(b))).or_insert(if a < b { ctx.along[h] } else { ctx.against[h] });
            }
        }
    }
    let mut edges: Vec<_> = edges.into_iter().map(|((a, b), r)| (a, b, r)).collect();
    edges.sort_unstable();
    edges
}

/// Region triangles with a free vertex (the ones a phase change can alter), in the region's
/// order.
fn touched_triangles(ctx: &Context, region: &Region) -> Vec<usize> {
    region
        .triangles
        .iter()
        .copied()
        .filter(|&u| ctx.mesh.triangles()[u].iter().any(|&v| region.free.contains_key(&(v as usize))))
        .collect()
}

/// Whether triangle `t`, with `corners` the unknowns of its vertices, is singular (§3.2: open,
/// or of non-positive (θ, φ) area).
fn is_singular(ctx: &Context, corners: [[f64; 4]; 3], t: usize) -> bool {
    let p = corner_triangle_parameterization(ctx.mesh, ctx.normals, ctx.field, corners, ctx.omega, t);
    p.open || signed_area2(&p.coords) <= 0.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::methods::pgp::extraction::corner_parameterization;

    /// An n × n grid of unit squares (each split along a diagonal) in the plane.
    fn grid(n: u32) -> TriMesh {
        let id = |i: u32, j: u32| j * (n + 1) + i;
        let mut positions = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                positions.extend([i as f64, j as f64, 0.0]);
            }
        }
        let mut tris = Vec::new();
        for j in 0..n {
            for i in 0..n {
                tris.extend([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        TriMesh::new(&positions, &tris).unwrap()
    }

    /// The 20 × 20 grid, one period per ten edges, flat normals and the field along x.
    fn plane() -> (TriMesh, f64, Vec<[f64; 3]>, Vec<[f64; 3]>) {
        plane_of(20)
    }

    fn plane_of(n: u32) -> (TriMesh, f64, Vec<[f64; 3]>, Vec<[f64; 3]>) {
        let mesh = grid(n);
        let n = mesh.vertex_count();
        (mesh, TAU / 10.0, vec![[0.0, 0.0, 1.0]; n], vec![[1.0, 0.0, 0.0]; n])
    }

    /// Plane waves θ = ω x, φ = ω y with vortices of θ of the given signs at the given points.
    fn waves(mesh: &TriMesh, omega: f64, vortices: &[([f64; 2], f64)]) -> Vec<[f64; 4]> {
        mesh.points()
            .iter()
            .map(|p| {
                let turn: f64 = vortices.iter().map(|&(c, s)| s * (p[1] - c[1]).atan2(p[0] - c[0])).sum();
                let (theta, phi) = (omega * p[0] + turn, omega * p[1]);
                [theta.cos(), theta.sin(), phi.cos(), phi.sin()]
            })
            .collect()
    }

    fn singular(mesh: &TriMesh, field: &[[f64; 3]], unknowns: &[[f64; 4]], omega: f64) -> usize {
        let normals = vec![[0.0, 0.0, 1.0]; mesh.vertex_count()];
        let param = corner_parameterization(mesh, &normals, field, unknowns, omega);
        (0..mesh.triangle_count()).filter(|&t| param.open[t] || signed_area2(&param.coords[t]) <= 0.0).count()
    }

    /// Centroid of the lower triangle of square (i, j).
    fn core(i: f64, j: f64) -> [f64; 2] {
        [i + 2.0 / 3.0, j + 1.0 / 3.0]
    }

    #[test]
    fn an_opposite_pair_of_dislocations_is_annihilated_and_nothing_else_opens() {
        let (mesh, omega, normals, field) = plane();
        let mut unknowns = waves(&mesh, omega, &[(core(7.0, 10.0), 1.0), (core(12.0, 10.0), -1.0)]);
        // Two open triangles, and negative ones near the cores (the vortex turns θ faster than ω
        // within 1/ω of them).
        assert!(singular(&mesh, &field, &unknowns, omega) > 2);
        let report = annihilate_dislocations(&mesh, &normals, &field, &mut unknowns, omega, TAU / omega).unwrap();
        assert_eq!((report.before, report.pairs), (2, 1));
        assert_eq!(singular(&mesh, &field, &unknowns, omega), 0);
        // Far from the pair the phases are untouched.
        let far = 20 * 21; // vertex (0, 20)
        assert_eq!(unknowns[far], waves(&mesh, omega, &[(core(7.0, 10.0), 1.0), (core(12.0, 10.0), -1.0)])[far]);
    }

    #[test]
    fn trials_run_in_batches_give_the_one_at_a_time_result() {
        // Four pairs near the corners, whose regions (a period and a half across) do not
        // overlap, and a fifth in the middle whose region overlaps theirs: a batch runs the
        // first two pairs together and must leave the later ones for after the middle one.
        let (mesh, omega, normals, field) = plane_of(40);
        let vortices = [
            (core(3.0, 3.0), 1.0),
            (core(6.0, 3.0), -1.0),
            (core(22.0, 3.0), 1.0),
            (core(25.0, 3.0), -1.0),
            (core(12.0, 14.0), -1.0),
            (core(15.0, 14.0), 1.0),
            (core(3.0, 25.0), 1.0),
            (core(6.0, 25.0), -1.0),
            (core(22.0, 25.0), -1.0),
            (core(25.0, 25.0), 1.0),
        ];
        let original = waves(&mesh, omega, &vortices);
        let run = |batch| {
            let mut unknowns = original.clone();
            let report =
                annihilate_in_batches(&mesh, (&normals, &field), &mut unknowns, omega, 0.6 * TAU / omega, batch)
                    .unwrap();
            (unknowns, report)
        };
        let (one, report) = run(1);
        assert!(report.pairs >= 4, "{report:?}");
        assert_eq!(run(BATCH), (one, report));
    }

    #[test]
    fn dislocations_of_one_sign_or_farther_than_the_distance_are_kept() {
        let (mesh, omega, normals, field) = plane();
        for (signs, distance) in [([1.0, 1.0], TAU / omega), ([1.0, -1.0], 3.0)] {
            let original = waves(&mesh, omega, &[(core(7.0, 10.0), signs[0]), (core(12.0, 10.0), signs[1])]);
            let mut unknowns = original.clone();
            let report = annihilate_dislocations(&mesh, &normals, &field, &mut unknowns, omega, distance).unwrap();
            assert_eq!((report.before, report.pairs), (2, 0), "signs {signs:?}, distance {distance}");
            assert_eq!(unknowns, original);
        }
    }
}
