//! Bijective free-boundary SLIM by a scaffold: SCAF, the Simplicial Complex Augmentation
//! Framework of Jiang, Schaefer & Panozzo 2017 ("Simplicial Complex Augmentation Framework for
//! Bijective Maps", ACM TOG 36(6)).
//!
//! A locally injective map can still overlap itself where its free boundary runs into itself.
//! SCAF turns that global condition into a local one: the region between the chart's boundary
//! and a fixed frame around it (the holes included) is triangulated — the *scaffold* — and the
//! chart and the scaffold are optimized together with the flip-free line search. Every
//! triangle of the union keeps a positive area along every step, and the union's outer
//! boundary (the frame) does not move, so the union stays a triangulation of the frame's
//! rectangle (a locally injective, orientation-preserving map of a disk that is the identity on
//! its boundary is a bijection); the chart's boundary therefore can never cross itself (§3).
//!
//! The scaffold is only paid for where it is needed: plain SLIM ([`super::slim`]) runs first,
//! and every iterate it proposes is checked exactly for crossing boundary edges
//! ([`metrics::count_boundary_crossings`]); at the first iterate whose boundary would cross
//! itself, that step is refused and SCAF takes over from the last bijective iterate for the
//! iterations left. A map whose plain SLIM run never runs into itself is plain SLIM's, at plain
//! SLIM's cost plus one crossing test per iteration.
//!
//! Each SCAF iteration (§4, "Scaffold construction" and "Optimization"):
//! 1. The scaffold is rebuilt for the current map: the constrained Delaunay triangulation
//!    (`spade`) of the chart's boundary vertices and 4·`FRAME_POINTS_PER_SIDE` frame points,
//!    with every boundary edge a constraint; its triangles outside the chart's image are the
//!    scaffold (found by flooding from the boundary edges' outer sides). The frame is the
//!    boundary's bounding box enlarged `FRAME_SCALE` times about its centre.
//! 2. A scaffold triangle's rest shape is its current shape (so its Jacobian is the identity
//!    when it is built); one whose area is below a quarter of the shortest boundary edge
//!    squared gets an equilateral rest shape of that area instead (the paper's "degenerate
//!    scaffold triangles").
//! 3. The energy is `E = E_chart + Σ_s w E_SD(J_s)`: the chart's symmetric Dirichlet energy
//!    (area-weighted mean, as in [`super::slim`]) plus the scaffold triangles' symmetric
//!    Dirichlet energy with one weight `w = E_chart / (100 |S|)` each (§4: the scaffold's share
//!    is kept about a hundredth of the chart's, and shrinks with it), so the scaffold changes the
//!    chart's optimum little while its barrier keeps the boundary apart.
//! 4. The SLIM proxy of `E` (Rabinovich et al. 2017, eq. 8–9, [`super::slim::proxy_blocks`])
//!    is minimized with the frame points fixed (their terms move to the right-hand side), which
//!    gives the search direction of the chart's vertices; the flip-free Armijo search over the
//!    union's triangles takes the step.
//!
//! The elimination order of the chart's unknowns is computed once; the pattern (chart plus
//! the scaffold's couplings between boundary vertices) is analysed again each iteration, since
//! the scaffold changes.
//!
//! Guarantees: from a start with no flipped triangle and no crossing boundary edges, every
//! iterate has neither (a start that is not bijective fails with [`Error::InvalidArgument`]).
//! No flipped triangle and a boundary that does not cross itself make the map bijective: the
//! number of preimages of a point is the winding number of the boundary's image around it,
//! which for non-crossing, consistently oriented loops is 0 or 1. Cost per SCAF iteration: one
//! constrained Delaunay triangulation of the boundary (O(B log B)), one symbolic and one numeric
//! sparse Cholesky factorization of the 2n-unknown system.

use super::energy::{self, evaluate, vertex_gradient, Energy};
use super::jacobian::RestFrames;
use super::line_search;
use super::slim::{proxy_blocks, SlimSystem};
use super::{NonlinearOptions, Problem, Run};
use crate::error::{Error, Result};
use crate::metrics;
use crate::progress::Progress;
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};
use std::collections::HashMap;
use uvflat_sparse::{lower_from_entries, ordering};

/// The frame is the boundary's bounding box scaled by this factor about its centre (SCAF's
/// reference implementation uses 3).
const FRAME_SCALE: f64 = 3.0;
/// Frame points on each side of the frame rectangle.
const FRAME_POINTS_PER_SIDE: usize = 5;
/// The scaffold's total weight relative to the chart's energy (§4).
const SCAFFOLD_SHARE: f64 = 0.01;

/// The triangulated region between the chart's boundary and the frame.
pub(super) struct Scaffold {
    /// Frame points, numbered `n..n + frame.len()` after the chart's vertices.
    frame: Vec<[f64; 2]>,
    /// Scaffold triangles (counter-clockwise), in that numbering.
    pub(super) tris: Vec<[u32; 3]>,
    /// Rest shapes, with `area` holding each triangle's weight and `total_area` = 1.
    frames: RestFrames,
}

/// Directed boundary edges `a → b` of the chart (the chart on their left).
pub(super) fn boundary_edges(tris: &[[u32; 3]]) -> Vec<[u32; 2]> {
    let mut directed: HashMap<(u32, u32), usize> = HashMap::with_capacity(3 * tris.len());
    for t in tris {
        for k in 0..3 {
            *directed.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
        }
    }
    let mut edges: Vec<[u32; 2]> =
        directed.keys().filter(|&&(a, b)| !directed.contains_key(&(b, a))).map(|&(a, b)| [a, b]).collect();
    edges.sort_unstable();
    edges
}

/// Points on the rectangle `FRAME_SCALE` times the bounding box of `points`, counter-clockwise.
fn frame_points(points: impl Iterator<Item = [f64; 2]>) -> Vec<[f64; 2]> {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in points {
        for d in 0..2 {
            lo[d] = lo[d].min(p[d]);
            hi[d] = hi[d].max(p[d]);
        }
    }
    let half = 0.5 * FRAME_SCALE * (hi[0] - lo[0]).max(hi[1] - lo[1]);
    let centre = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
    let (a, b) = ([centre[0] - half, centre[1] - half], [centre[0] + half, centre[1] + half]);
    let corners = [a, [b[0], a[1]], b, [a[0], b[1]]];
    let m = FRAME_POINTS_PER_SIDE;
    (0..4)
        .flat_map(|side| {
            let (p, q) = (corners[side], corners[(side + 1) % 4]);
            (0..m).map(move |i| {
                let s = i as f64 / m as f64;
                [p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1])]
            })
        })
        .collect()
}

impl Scaffold {
    /// The scaffold of the map `x` (chart vertices `0..n`) with boundary edges `edges`, and
    /// the chart energy `chart_energy` setting the weights.
    pub(super) fn build(x: &[[f64; 2]], edges: &[[u32; 2]], chart_energy: f64) -> Result<Scaffold> {
        let n = x.len() as u32;
        let mut boundary: Vec<u32> = edges.iter().flatten().copied().collect();
        boundary.sort_unstable();
        boundary.dedup();
        let frame = frame_points(boundary.iter().map(|&v| x[v as usize]));
        // CDT vertices: the boundary vertices, then the frame points.
        let local: HashMap<u32, usize> = boundary.iter().enumerate().map(|(i, &v)| (v, i)).collect();
        let points: Vec<Point2<f64>> = boundary
            .iter()
            .map(|&v| x[v as usize])
            .chain(frame.iter().copied())
            .map(|p| Point2::new(p[0], p[1]))
            .collect();
        let constraints: Vec<[usize; 2]> = edges.iter().map(|e| [local[&e[0]], local[&e[1]]]).collect();
        let (mut conflicts, count) = (0usize, points.len());
        let cdt =
            ConstrainedDelaunayTriangulation::<Point2<f64>>::try_bulk_load_cdt(points, constraints, |_| conflicts += 1)
                .map_err(|e| Error::InvalidArgument(format!("the map's boundary cannot be triangulated: {e:?}")))?;
        // A duplicate point is merged by the triangulation: two boundary vertices coincide.
        if conflicts > 0 || cdt.num_vertices() != count {
            return Err(Error::InvalidArgument(
                "the map's boundary crosses or touches itself; a scaffold needs a bijective start".into(),
            ));
        }
        let global = |i: usize| if i < boundary.len() { boundary[i] } else { n + (i - boundary.len()) as u32 };
        let faces: Vec<[u32; 3]> = cdt
            .inner_faces()
            .map(|f| {
                let v = f.vertices();
                [0, 1, 2].map(|k| global(v[k].fix().index()))
            })
            .collect();
        let outside = outside_faces(&faces, edges)?;
        let tris: Vec<[u32; 3]> = faces.iter().zip(&outside).filter(|(_, &o)| o).map(|(t, _)| *t).collect();
        let mut all = x.to_vec();
        all.extend(&frame);
        let frames = rest_frames(&all, &tris, 0.25 * shortest_edge2(&all, edges), chart_energy);
        Ok(Scaffold { frame, tris, frames })
    }

    /// Rest shapes and weights reset for the map `x`, the triangulation kept.
    fn reset_rest_shapes(&mut self, x: &[[f64; 2]], edges: &[[u32; 2]], chart_energy: f64) {
        let all = self.extend(x);
        self.frames = rest_frames(&all, &self.tris, 0.25 * shortest_edge2(&all, edges), chart_energy);
    }

    /// The chart's map followed by the frame points.
    pub(super) fn extend(&self, x: &[[f64; 2]]) -> Vec<[f64; 2]> {
        let mut all = x.to_vec();
        all.extend(&self.frame);
        all
    }
}

/// Squared length of the shortest of `edges` under the map `all`.
fn shortest_edge2(all: &[[f64; 2]], edges: &[[u32; 2]]) -> f64 {
    edges
        .iter()
        .map(|e| {
            let (p, q) = (all[e[0] as usize], all[e[1] as usize]);
            (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)
        })
        .fold(f64::INFINITY, f64::min)
}

/// Which faces of the triangulation lie outside the chart: flooding across the edges that are
/// not chart boundary edges, seeded by the faces on either side of every boundary edge (a face
/// holding `b → a` for a boundary edge `a → b` is outside; one holding `a → b` is inside). A face
/// reached from both sides means the boundary is not a set of simple, disjoint curves.
fn outside_faces(faces: &[[u32; 3]], edges: &[[u32; 2]]) -> Result<Vec<bool>> {
    let constraint: std::collections::HashSet<(u32, u32)> =
        edges.iter().flat_map(|e| [(e[0], e[1]), (e[1], e[0])]).collect();
    let chart_side: std::collections::HashSet<(u32, u32)> = edges.iter().map(|e| (e[0], e[1])).collect();
    let mut face_of: HashMap<(u32, u32), usize> = HashMap::with_capacity(3 * faces.len());
    for (f, t) in faces.iter().enumerate() {
        for k in 0..3 {
            face_of.insert((t[k], t[(k + 1) % 3]), f);
        }
    }
    let mut label: Vec<Option<bool>> = vec![None; faces.len()];
    let mut stack = Vec::new();
    for (f, t) in faces.iter().enumerate() {
        for k in 0..3 {
            let e = (t[k], t[(k + 1) % 3]);
            if constraint.contains(&e) {
                let out = !chart_side.contains(&e);
                match label[f] {
                    Some(l) if l != out => {
                        return Err(Error::InvalidArgument("the map's boundary is not a set of simple curves".into()))
                    }
                    Some(_) => {}
                    None => {
                        label[f] = Some(out);
                        stack.push(f);
                    }
                }
            }
        }
    }
    while let Some(f) = stack.pop() {
        let t = faces[f];
        let l = label[f];
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if constraint.contains(&(a, b)) {
                continue;
            }
            let Some(&g) = face_of.get(&(b, a)) else { continue };
            match label[g] {
                None => {
                    label[g] = l;
                    stack.push(g);
                }
                Some(other) if Some(other) != l => {
                    return Err(Error::InvalidArgument("the map's boundary is not a set of simple curves".into()))
                }
                Some(_) => {}
            }
        }
    }
    // Faces no boundary edge reaches lie between the frame and nothing: outside.
    Ok(label.into_iter().map(|l| l.unwrap_or(true)).collect())
}

/// Rest frames of the scaffold triangles at their current shape (an equilateral triangle of
/// area `min_area` for smaller ones), each weighted `SCAFFOLD_SHARE × chart_energy / |S|`.
fn rest_frames(all: &[[f64; 2]], tris: &[[u32; 3]], min_area: f64, chart_energy: f64) -> RestFrames {
    let points: Vec<[f64; 3]> = all.iter().map(|p| [p[0], p[1], 0.0]).collect();
    let mut frames = RestFrames::new(&points, tris);
    let side = (4.0 * min_area / 3f64.sqrt()).sqrt();
    let equilateral = [[0.0, 0.0, 0.0], [side, 0.0, 0.0], [0.5 * side, 0.5 * 3f64.sqrt() * side, 0.0]];
    let regular = RestFrames::new(&equilateral, &[[0, 1, 2]]).grad[0];
    for (t, area) in frames.area.iter().enumerate() {
        if !(*area >= min_area) || frames.grad[t].iter().flatten().any(|g| !g.is_finite()) {
            frames.grad[t] = regular;
        }
    }
    let weight = SCAFFOLD_SHARE * chart_energy / tris.len().max(1) as f64;
    frames.area = vec![weight; tris.len()];
    frames.total_area = 1.0;
    frames
}

/// Chart plus scaffold energy of the extended map `all`.
fn total_energy(problem: &Problem, scaffold: &Scaffold, all: &[[f64; 2]]) -> f64 {
    let chart = energy::energy(Energy::SymmetricDirichlet, &problem.frames, &problem.tris, all);
    chart + energy::energy(Energy::SymmetricDirichlet, &scaffold.frames, &scaffold.tris, all)
}

/// Gradient of the total energy in the chart's unknowns.
fn total_gradient(problem: &Problem, scaffold: &Scaffold, all: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let m = all.len();
    let (_, dj) = evaluate(Energy::SymmetricDirichlet, &problem.frames, &problem.tris, all, true);
    let mut g = vertex_gradient(&problem.frames, &problem.tris, &dj, m);
    let (_, dj) = evaluate(Energy::SymmetricDirichlet, &scaffold.frames, &scaffold.tris, all, true);
    for (a, b) in g.iter_mut().zip(vertex_gradient(&scaffold.frames, &scaffold.tris, &dj, m)) {
        a[0] += b[0];
        a[1] += b[1];
    }
    g
}

/// Elimination order of the union's free unknowns (the chart's vertices): nested dissection of
/// the union's vertex graph, split by planes in the UV plane (the union is a planar
/// triangulation there), u and v of each vertex consecutively. Ordering the chart's graph
/// alone leaves the scaffold's couplings across narrow gaps of the boundary out of account;
/// measured on disk_hilbert (18k vertices, a boundary of long channels) that ordering's
/// numeric factorization took 0.03–0.04 s against SLIM's 0.011 s.
fn union_order(n: usize, union: &[[u32; 3]], all: &[[f64; 2]]) -> Result<Vec<usize>> {
    let mut entries = Vec::with_capacity(3 * union.len());
    for t in union {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if (a as usize) < n && (b as usize) < n && a != b {
                entries.push((a.max(b), a.min(b), 0.0));
            }
        }
    }
    let graph = lower_from_entries(&vec![0.0; n], entries)?;
    let adjacency = ordering::Adjacency::from_lower(n, graph.symbolic().col_ptr(), graph.symbolic().row_idx());
    let coords: Vec<[f64; 3]> = all[..n].iter().map(|p| [p[0], p[1], 0.0]).collect();
    Ok(ordering::nested_dissection_with(&adjacency, Some(&coords), &ordering::Options::thorough())
        .iter()
        .flat_map(|&v| [2 * v, 2 * v + 1])
        .collect())
}

/// A scaffold and the SLIM system of the union of chart and scaffold, kept while the scaffold's
/// triangulation is kept.
struct Augmented {
    scaffold: Scaffold,
    union: Vec<[u32; 3]>,
    system: SlimSystem,
}

impl Augmented {
    /// The scaffold of `x` and its system, eliminated in `order` (computed for this union when
    /// `None`, and stored there).
    fn build(
        problem: &Problem,
        x: &[[f64; 2]],
        edges: &[[u32; 2]],
        chart_energy: f64,
        order: &mut Option<Vec<usize>>,
    ) -> Result<Self> {
        let scaffold = Scaffold::build(x, edges, chart_energy)?;
        let union: Vec<[u32; 3]> = problem.tris.iter().chain(&scaffold.tris).copied().collect();
        if order.is_none() {
            *order = Some(union_order(problem.n(), &union, &scaffold.extend(x))?);
        }
        let system = SlimSystem::new(problem.n(), &union, order.clone().unwrap_or_default())?;
        Ok(Augmented { scaffold, union, system })
    }

    /// The proxy's minimizer as a direction for every point of `all` (zero for the frame).
    fn direction(&self, problem: &Problem, all: &[[f64; 2]]) -> Result<Vec<[f64; 2]>> {
        let mut blocks = proxy_blocks(&problem.frames, &problem.tris, all, 1.0 / problem.frames.total_area);
        blocks.extend(proxy_blocks(&self.scaffold.frames, &self.scaffold.tris, all, 1.0));
        let mut d = self.system.direction(&self.union, &blocks, all)?;
        d.resize(all.len(), [0.0; 2]);
        Ok(d)
    }
}

/// Runs bijective SLIM from `x0`, which must have no flipped triangle and a boundary that does
/// not cross itself.
pub(crate) fn minimize(
    problem: &Problem,
    x0: Vec<[f64; 2]>,
    options: &NonlinearOptions,
    progress: &mut Progress,
) -> Result<Run> {
    let n = problem.n();
    let edges = boundary_edges(&problem.tris);
    if edges.is_empty() {
        return Err(Error::InvalidArgument("a bijective map needs a boundary".into()));
    }
    let chart_energy = |x: &[[f64; 2]]| energy::energy(Energy::SymmetricDirichlet, &problem.frames, &problem.tris, x);
    if !chart_energy(&x0).is_finite() {
        return Err(Error::InvalidArgument("the starting map has a flipped or degenerate triangle".into()));
    }
    if metrics::count_boundary_crossings(&x0, &edges) > 0 {
        return Err(Error::InvalidArgument("the starting map's boundary crosses itself: it is not bijective".into()));
    }
    // Plain SLIM while its iterates stay bijective (checked exactly), SCAF from the last
    // bijective one for the iterations left.
    let plain = NonlinearOptions { bijective: false, ..options.clone() };
    let keep = |x: &[[f64; 2]]| metrics::count_boundary_crossings(x, &edges) == 0;
    let (mut run, crossed) = super::slim::minimize_while(problem, x0, &plain, progress, keep)?;
    if !crossed {
        return Ok(run);
    }
    let mut e = *run.energy.last().expect("the start's energy");
    let mut augmented: Option<Augmented> = None;
    // The first union's elimination order serves every later scaffold: the chart's vertices do
    // not change, and the scaffold's couplings change little from one triangulation to the next.
    let mut order = None;
    for it in run.iterations..options.iterations {
        progress.report(0.02 + 0.97 * it as f64 / options.iterations as f64)?;
        let (current, rebuilt) = match augmented.take() {
            Some(mut a) => {
                // Same triangulation, rest shapes reset to the current shapes.
                a.scaffold.reset_rest_shapes(&run.x, &edges, e);
                (a, false)
            }
            None => (Augmented::build(problem, &run.x, &edges, e, &mut order)?, true),
        };
        let all = current.scaffold.extend(&run.x);
        let e_total = total_energy(problem, &current.scaffold, &all);
        let grad = total_gradient(problem, &current.scaffold, &all);
        let d = current.direction(problem, &all)?;
        let slope = line_search::slope(&grad, &d);
        let step = line_search::flip_free_armijo(&current.union, &all, &d, e_total, slope, |y| {
            total_energy(problem, &current.scaffold, y)
        });
        let Some(step) = step else {
            if !rebuilt {
                continue; // a kept scaffold may block the step: retriangulate before stopping
            }
            run.converged = true;
            break;
        };
        // Keep the triangulation unless the scaffold, not the chart, kept the step below 1.
        let scaffold_bound = line_search::max_flip_free_step(&current.scaffold.tris, &all, &d);
        let limited_by_scaffold = line_search::MAX_STEP_FRACTION * scaffold_bound < 1.0
            && scaffold_bound < line_search::max_flip_free_step(&problem.tris, &all, &d);
        if !limited_by_scaffold {
            augmented = Some(current);
        }
        let mut x = step.uv;
        x.truncate(n);
        let e_new = chart_energy(&x);
        let decrease = e - e_new;
        run.x = x;
        e = e_new;
        run.energy.push(e);
        run.iterations += 1;
        if decrease.abs() <= options.tolerance * e.abs() {
            run.converged = true;
            break;
        }
    }
    Ok(run)
}

/// The bijective guard of the other methods (ARAP, MIPS, stretch, Green–Lagrange, Degener):
/// their own search direction, with the step bounded by the first collapse of any triangle of
/// the chart *or of the scaffold* around it (rebuilt for the current map at every step, the
/// frame fixed). A boundary vertex cannot reach another part of the boundary without
/// collapsing a scaffold triangle first, so, as for SCAF, every iterate stays bijective; unlike
/// SCAF's SLIM, the direction does not see the scaffold (these methods have no proxy that can
/// include its energy), so a boundary that runs against itself stops the step there instead of
/// being pushed away. Returns the step, or `None` when no step lowers `energy`.
pub(super) fn guarded_step(
    tris: &[[u32; 3]],
    edges: &[[u32; 2]],
    search: &line_search::Search,
    floor: Option<&[f64]>,
    energy: impl Fn(&[[f64; 2]]) -> f64,
) -> Result<Option<line_search::Accepted>> {
    let (x, d) = (search.x, search.d);
    let n = x.len();
    let scaffold = Scaffold::build(x, edges, search.e0)?;
    let all = scaffold.extend(x);
    let union: Vec<[u32; 3]> = tris.iter().chain(&scaffold.tris).copied().collect();
    let mut d_all = d.to_vec();
    d_all.resize(all.len(), [0.0; 2]);
    let floor_all: Option<Vec<f64>> = floor.map(|f| {
        let mut v = f.to_vec();
        v.resize(union.len(), 0.0);
        v
    });
    let on_union = line_search::Search { x: &all, d: &d_all, e0: search.e0, slope: search.slope };
    let step = line_search::armijo_above(&union, &on_union, floor_all.as_deref(), |y| energy(&y[..n]));
    Ok(step.map(|mut s| {
        s.uv.truncate(n);
        s
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn boundary_edges_of_a_square_run_counter_clockwise() {
        let tris = [[0, 1, 2], [0, 2, 3]];
        assert_eq!(boundary_edges(&tris), vec![[0, 1], [1, 2], [2, 3], [3, 0]]);
    }

    #[test]
    fn the_scaffold_covers_the_frame_minus_the_chart() {
        // A unit square of two triangles: the scaffold and the chart tile the frame.
        let x = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let tris = [[0, 1, 2], [0, 2, 3]];
        let s = Scaffold::build(&x, &boundary_edges(&tris), 4.0).unwrap();
        let all = s.extend(&x);
        let area = |t: &[u32; 3]| {
            let [a, b, c] = t.map(|v| all[v as usize]);
            0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
        };
        assert!(s.tris.iter().all(|t| area(t) > 0.0));
        let scaffold_area: f64 = s.tris.iter().map(area).sum();
        assert!((scaffold_area + 1.0 - 9.0).abs() < 1e-12, "{scaffold_area}");
    }

    #[test]
    fn a_boundary_that_crosses_itself_has_no_scaffold() {
        // A bow tie: two triangles whose boundaries cross.
        let x = [[0.0, 0.0], [2.0, 0.0], [0.0, 2.0], [2.0, 2.0], [1.0, -1.0], [1.0, 3.0]];
        let tris = [[0, 4, 3], [1, 5, 2]];
        assert!(Scaffold::build(&x, &boundary_edges(&tris), 4.0).is_err());
    }
}
