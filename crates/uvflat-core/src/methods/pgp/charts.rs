//! Per-chart parameterization of a PGP result (Ray et al. 2006, §3.3 last paragraph and
//! §3.4): the surface is cut along the chart boundaries (the iso-2kπ lines of θ and φ,
//! [`super::refine`] inserts them into the triangulation) and every chart gets its own
//! (u, v), in periods (one period = 1):
//!
//! - a chart with no singularity is **assembled** from its triangles' (θ, φ) ("assembling the
//!   triangles in 2D space"): the transition functions of eq. 16 across its regular edges
//!   bring every triangle into the chart of one seed triangle (a breadth-first walk, which for
//!   such a chart is path-independent — checked, not assumed);
//! - a chart with singularities (a singular triangle, a singular edge crossed, or transitions
//!   that do not agree around a vertex) is **re-parameterized by mean-value coordinates**
//!   (Floater 2003) with its boundary fixed: four corners with equal opposite sides on a
//!   rectangle; otherwise (N ≠ 4 corners, or opposite sides of different lengths) on a regular
//!   N-gon, then split into N quads ([`super::split`]), each mapped onto a rectangle.
//!   The boundary keeps the parameter the chart's neighbours see (C0 continuity, §3.4): along
//!   a side the position of a point is the fraction of the side's (θ, φ) length before it,
//!   measured triangle by triangle along the iso-line in each triangle's own chart, which is
//!   the same number from both sides of the side and equals the assembled chart's coordinate;
//! - a chart that is not a disk with at least three corners (possible when the iso-lines are
//!   removed around many singularities, or where a chart wraps a handle) has no quad to map
//!   to; it is flattened by the atlas segmentation instead ([`ChartKind::Atlas`]) — outside
//!   the paper, which assumes disks.
//!
//! Corners: an iso-graph node where the chart's boundary turns (a grid node whose two arms on
//! this chart are not opposite, or a boundary node where an iso-line meets the mesh boundary);
//! a T-junction is a corner of the two charts on its stem side only.
//!
//! Cost: O(F + output) for the cut and the assembly, one small sparse solve per singular chart
//! (in parallel).

use super::isolines::{iso_graph, IsoGraph, NodeKind};
use super::mean_value_chart::{local_mesh, mean_value_map};
use super::refine::{refine, RefinedMesh};
use super::singularities::transition;
use super::split::{split_into_quads, ChartDomain};
use super::PgpResult;
use crate::atlas::AtlasOptions;
use crate::error::Result;
use crate::fields::frames::rotate_coords;
use crate::geometry::{distance, dot, norm, sub};
use crate::mesh::connectivity::next;
use crate::mesh::{TriMesh, NONE};
use rayon::prelude::*;
use std::collections::HashMap;
use std::f64::consts::TAU;
use uvflat_sparse::union_find::{find, set_labels};

/// How a chart was parameterized.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ChartKind {
    /// No singularity: its triangles' (θ, φ) assembled.
    Assembled,
    /// Four corners with equal opposite sides, re-parameterized by mean-value coordinates onto
    /// a rectangle.
    MeanValue,
    /// One of the N quads a chart with N ≠ 4 corners (or unequal opposite sides) was split
    /// into ([`super::split`]), re-parameterized by mean-value coordinates onto a rectangle.
    SplitQuad,
    /// Part of a chart of the layout that is not a disk with at least three corners (it holds a
    /// handle, encloses another chart, or has one or two corners), flattened by the atlas
    /// segmentation ([`crate::atlas`]) at the chart's scale: no quad structure and not
    /// continuous with its neighbours, but not folded.
    Atlas,
    /// Left with the per-triangle (θ, φ), not continuous (the atlas failed on it).
    Unresolved,
}

/// One chart.
#[derive(Debug, Clone, PartialEq)]
pub struct Chart {
    /// How it was parameterized.
    pub kind: ChartKind,
    /// Corners on its boundary (0 when it is not a disk).
    pub corners: u32,
    /// Whether it holds a singularity (a singular triangle or inconsistent transitions).
    pub singular: bool,
    /// Extent of its (u, v), in cells.
    pub size: [f64; 2],
    /// The chart of the layout (a face of the iso-2kπ lines) it is, or is a quad of.
    pub layout: u32,
    /// Length of every side between consecutive corners, in cells (along the iso-lines, in
    /// (θ, φ); mesh-boundary sides: ω × length × density / 2π). Empty when it is not a disk.
    pub sides: Vec<f64>,
}

/// The surface cut into charts, each with its own parameterization.
#[derive(Debug, Clone)]
pub struct ChartParameterization {
    /// Vertex positions of the cut triangulation (the input's vertices first; every position
    /// lies on the input surface).
    pub positions: Vec<[f64; 3]>,
    /// Triangles of the cut triangulation, counter-clockwise.
    pub triangles: Vec<[u32; 3]>,
    /// Input triangle every triangle lies in.
    pub origin: Vec<u32>,
    /// Chart of every triangle.
    pub chart: Vec<u32>,
    /// (u, v) at every corner of every triangle, in cells (a regular chart is a unit square).
    pub uv: Vec<[[f64; 2]; 3]>,
    /// The charts.
    pub charts: Vec<Chart>,
}

/// §3.3–3.4: cuts the surface along the chart boundaries — the iso-lines at `density` lines per
/// period, 1 for the paper's iso-2kπ lines — and parameterizes every chart, in cells (one cell
/// = 1/density period). Errors: density not a whole number ≥ 1.
pub fn chart_parameterization(mesh: &TriMesh, result: &PgpResult, density: f64) -> Result<ChartParameterization> {
    let graph = iso_graph(mesh, result, density)?;
    let mut refined = refine(mesh, &graph);
    let mut cut = TriMesh::from_checked(refined.positions.clone(), refined.triangles.clone())?;
    if refined.split_border_triangles(&cut.connectivity().twin) > 0 {
        cut = TriMesh::from_checked(refined.positions.clone(), refined.triangles.clone())?;
    }
    let (label, count) = regions(&cut, &refined);
    let mut members: Vec<Vec<u32>> = vec![Vec::new(); count];
    for (r, &l) in label.iter().enumerate() {
        members[l as usize].push(r as u32);
    }
    let context = Context { mesh, result, graph: &graph, refined: &refined, cut: &cut, density, scale: density / TAU };
    let outputs: Vec<ChartOutput> = members.par_iter().map(|m| context.chart(m)).collect();
    let mut out = ChartParameterization {
        positions: refined.positions.clone(),
        triangles: Vec::with_capacity(refined.triangles.len()),
        origin: Vec::with_capacity(refined.triangles.len()),
        chart: Vec::with_capacity(refined.triangles.len()),
        uv: Vec::with_capacity(refined.triangles.len()),
        charts: Vec::with_capacity(count),
    };
    let base = refined.positions.len() as u32;
    for (layout, mut o) in outputs.into_iter().enumerate() {
        o.charts.iter_mut().for_each(|c| c.layout = layout as u32);
        let (first_chart, first_point) = (out.charts.len() as u32, out.positions.len() as u32);
        let id = |v: u32| if v < base { v } else { v - base + first_point };
        out.triangles.extend(o.triangles.iter().map(|t| t.map(id)));
        out.origin.extend(o.source.iter().map(|&r| refined.origin[r as usize]));
        out.chart.extend(o.chart.iter().map(|&c| c + first_chart));
        out.uv.extend(o.uv);
        out.charts.extend(o.charts);
        out.positions.extend(o.points);
    }
    Ok(out)
}

/// What one chart of the layout gives: one chart, or several after a split, with its
/// triangles (vertex ids at or above the cut triangulation's count are `points`).
#[derive(Default)]
struct ChartOutput {
    charts: Vec<Chart>,
    triangles: Vec<[u32; 3]>,
    /// The cut triangle every triangle lies in.
    source: Vec<u32>,
    chart: Vec<u32>,
    uv: Vec<[[f64; 2]; 3]>,
    points: Vec<[f64; 3]>,
}

impl ChartOutput {
    /// The chart's own triangles with one (u, v) per corner.
    fn whole(cut: &TriMesh, members: &[u32], chart: Chart, uv: Vec<[[f64; 2]; 3]>) -> Self {
        ChartOutput {
            charts: vec![chart],
            triangles: members.iter().map(|&r| cut.triangles()[r as usize]).collect(),
            source: members.to_vec(),
            chart: vec![0; members.len()],
            uv,
            points: Vec::new(),
        }
    }
}

/// A chart flattened by the atlas (no corners, no quad structure) of the given extent.
fn atlas_chart(size: [f64; 2]) -> Chart {
    Chart { kind: ChartKind::Atlas, corners: 0, singular: true, size, sides: Vec::new(), layout: 0 }
}

/// Charts as connected sets of cut triangles: union over every edge that is not a chart
/// boundary. Returns the label of every triangle and the count.
fn regions(cut: &TriMesh, refined: &RefinedMesh) -> (Vec<u32>, usize) {
    let twin = &cut.connectivity().twin;
    let mut parent: Vec<u32> = (0..cut.triangle_count() as u32).collect();
    for (h, &g) in twin.iter().enumerate() {
        if g == NONE || (g as usize) < h || refined.cut(cut.tail(h as u32), cut.head(h as u32)).is_some() {
            continue;
        }
        let (a, b) = (find(&mut parent, (h / 3) as u32), find(&mut parent, g / 3));
        if a != b {
            parent[a.max(b) as usize] = a.min(b);
        }
    }
    set_labels(&mut parent)
}

/// A transition of eq. 16: `x ↦ P^rot x + 2π shift`, P(θ, φ) = (φ, −θ).
type Frame = (u8, [i64; 2]);

fn rotate_int(r: u8, x: [i64; 2]) -> [i64; 2] {
    (0..r % 4).fold(x, |x, _| [x[1], -x[0]])
}

/// `F ∘ τ⁻¹`: the frame of the next triangle when `τ` maps this triangle's chart to it.
fn compose_inverse(f: Frame, tau: Frame) -> Frame {
    let rot = (4 + f.0 - tau.0) % 4;
    let moved = rotate_int(rot, tau.1);
    (rot, [f.1[0] - moved[0], f.1[1] - moved[1]])
}

struct Context<'a> {
    mesh: &'a TriMesh,
    result: &'a PgpResult,
    graph: &'a IsoGraph,
    refined: &'a RefinedMesh,
    cut: &'a TriMesh,
    /// Lines per period.
    density: f64,
    /// Cells per radian of θ or φ: density / 2π.
    scale: f64,
}

impl Context<'_> {
    /// (θ, φ) at corner `k` of cut triangle `r`, in its input triangle's chart.
    fn corner_coords(&self, r: usize, k: usize) -> [f64; 2] {
        let t = self.refined.origin[r] as usize;
        let b = self.refined.bary[r][k];
        let c = &self.result.param.coords[t];
        std::array::from_fn(|f| b[0] * c[0][f] + b[1] * c[1][f] + b[2] * c[2][f])
    }

    /// The chart of cut triangles `members`, parameterized (module comment).
    fn chart(&self, members: &[u32]) -> ChartOutput {
        let singular_triangle = members.iter().any(|&r| self.is_singular(self.refined.origin[r as usize]));
        let boundary = self.boundary_loop(members);
        let sides = boundary.as_ref().map_or(Vec::new(), |(lp, c)| self.side_lengths(lp, c));
        let corners = boundary.as_ref().map_or(0, |(_, c)| c.len() as u32);
        if !singular_triangle {
            if let Some(uv) = self.assemble(members) {
                let (uv, size) = to_origin(uv);
                let chart = Chart { kind: ChartKind::Assembled, corners, singular: false, size, sides, layout: 0 };
                return ChartOutput::whole(self.cut, members, chart, uv);
            }
        }
        if let Some(out) = boundary.as_ref().and_then(|(lp, c)| self.reparameterize(members, lp, c)) {
            return out;
        }
        if let Some(out) = self.flatten_by_atlas(members) {
            return out;
        }
        let uv = members
            .iter()
            .map(|&r| std::array::from_fn(|k| self.corner_coords(r as usize, k).map(|x| x * self.scale)))
            .collect();
        let (uv, size) = to_origin(uv);
        let chart = Chart { kind: ChartKind::Unresolved, corners, singular: true, size, sides, layout: 0 };
        ChartOutput::whole(self.cut, members, chart, uv)
    }

    /// The chart cut and flattened by [`crate::atlas::atlas`], scaled to cells (ω × density / 2π
    /// cells per unit length); `None` when the atlas fails. Zero-area cut triangles (a line
    /// through a vertex: no flattening of them is valid, and the atlas refuses them) are left
    /// out of the atlas and laid out on their own, on a segment, one chart each.
    fn flatten_by_atlas(&self, members: &[u32]) -> Option<ChartOutput> {
        let (degenerate, flat): (Vec<u32>, Vec<u32>) = members.iter().partition(|&&r| {
            let [a, b, c] = self.cut.triangles()[r as usize].map(|v| self.cut.points()[v as usize]);
            crate::mesh::validate::is_degenerate(crate::geometry::relative_area(a, b, c))
        });
        let mut out = if flat.is_empty() { ChartOutput::default() } else { self.atlas_charts(&flat)? };
        let k = self.scale * self.result.omega;
        for r in degenerate {
            let [a, b, c] = self.cut.triangles()[r as usize].map(|v| self.cut.points()[v as usize]);
            let (e, f) = (sub(b, a), sub(c, a));
            let length = norm(e);
            let along = if length > 0.0 { dot(e, f) / length } else { norm(f) };
            let (uv, size) = to_origin(vec![[[0.0, 0.0], [k * length, 0.0], [k * along, 0.0]]]);
            out.chart.push(out.charts.len() as u32);
            out.charts.push(atlas_chart(size));
            out.triangles.push(self.cut.triangles()[r as usize]);
            out.source.push(r);
            out.uv.extend(uv);
        }
        Some(out)
    }

    /// [`Self::flatten_by_atlas`] on non-degenerate triangles.
    fn atlas_charts(&self, members: &[u32]) -> Option<ChartOutput> {
        let tris: Vec<[u32; 3]> = members.iter().map(|&r| self.cut.triangles()[r as usize]).collect();
        let (local_mesh, _) = local_mesh(&tris, &|v| self.cut.points()[v as usize])?;
        // A sliver of the cut (a line through a vertex) cannot meet the default stretch bound
        // on its own; then only folds and overlaps split charts.
        let atlas = crate::atlas::atlas(&local_mesh, &AtlasOptions::default())
            .or_else(|_| {
                let unbounded = AtlasOptions { max_stretch: f64::INFINITY, ..AtlasOptions::default() };
                crate::atlas::atlas(&local_mesh, &unbounded)
            })
            .ok()?;
        let uv_area: f64 =
            0.5 * atlas.triangles.iter().map(|t| area2(t.map(|v| atlas.uv[v as usize])).abs()).sum::<f64>();
        let area: f64 = local_mesh.geometry().area.iter().sum();
        if !(uv_area > 0.0 && area > 0.0) {
            return None;
        }
        let k = self.scale * self.result.omega * (area / uv_area).sqrt();
        let mut out = ChartOutput::default();
        let mut of_chart: Vec<Vec<usize>> = vec![Vec::new(); atlas.charts.len()];
        for (i, &c) in atlas.chart_of_triangle.iter().enumerate() {
            of_chart[c as usize].push(i);
        }
        for (c, mine) in of_chart.iter().enumerate() {
            let uv: Vec<[[f64; 2]; 3]> =
                mine.iter().map(|&i| atlas.triangles[i].map(|v| atlas.uv[v as usize].map(|x| x * k))).collect();
            let (uv, size) = to_origin(uv);
            out.charts.push(atlas_chart(size));
            for (&i, q) in mine.iter().zip(uv) {
                out.triangles.push(tris[i]);
                out.source.push(members[i]);
                out.chart.push(c as u32);
                out.uv.push(q);
            }
        }
        Some(out)
    }

    fn is_singular(&self, t: u32) -> bool {
        self.result.singularities.triangles.binary_search(&t).is_ok()
    }

    /// Assembly by a breadth-first walk; `None` when the transitions disagree (a singular edge
    /// or vertex inside the chart).
    fn assemble(&self, members: &[u32]) -> Option<Vec<[[f64; 2]; 3]>> {
        let mut frame: std::collections::HashMap<u32, Frame> = std::collections::HashMap::new();
        frame.insert(members[0], (0, [0, 0]));
        let mut queue = std::collections::VecDeque::from([members[0]]);
        let twin = &self.cut.connectivity().twin;
        while let Some(r) = queue.pop_front() {
            let f = frame[&r];
            for k in 0..3 {
                let h = 3 * r + k;
                let g = twin[h as usize];
                if g == NONE || self.refined.cut(self.cut.tail(h), self.cut.head(h)).is_some() {
                    continue;
                }
                let s = g / 3;
                let fs = match self.transition_between(self.refined.origin[r as usize], self.refined.origin[s as usize])
                {
                    Some(tau) => compose_inverse(f, tau),
                    None => return None,
                };
                match frame.get(&s) {
                    Some(&old) if old != fs => return None,
                    Some(_) => {}
                    None => {
                        frame.insert(s, fs);
                        queue.push_back(s);
                    }
                }
            }
        }
        Some(
            members
                .iter()
                .map(|&r| {
                    let (rot, d) = frame[&r];
                    std::array::from_fn(|k| {
                        let x = rotate_coords(rot, self.corner_coords(r as usize, k));
                        [x[0] * self.scale + self.density * d[0] as f64, x[1] * self.scale + self.density * d[1] as f64]
                    })
                })
                .collect(),
        )
    }

    /// The transition from input triangle `t1`'s chart to adjacent `t2`'s (identity for the
    /// same triangle); `None` across a singular edge.
    fn transition_between(&self, t1: u32, t2: u32) -> Option<Frame> {
        if t1 == t2 {
            return Some((0, [0, 0]));
        }
        let twin = &self.mesh.connectivity().twin;
        let k1 = (0..3).find(|&k| twin[3 * t1 as usize + k] != NONE && twin[3 * t1 as usize + k] / 3 == t2)?;
        let g = twin[3 * t1 as usize + k1] as usize;
        let (t1, t2, k2) = (t1 as usize, t2 as usize, g % 3);
        let at_tail = transition(&self.result.param, (t1, k1), (t2, (k2 + 1) % 3));
        let at_head = transition(&self.result.param, (t1, (k1 + 1) % 3), (t2, k2));
        // eq. 16 with τ_s, τ_t = s^{T2} − P^ρ s^{T1}, as `transition` returns.
        (at_tail == at_head).then_some(at_tail)
    }

    /// The chart's boundary as one loop of cut half-edges and the positions of its corners in
    /// the loop; `None` unless the chart is a disk (one loop, Euler characteristic 1).
    fn boundary_loop(&self, members: &[u32]) -> Option<(Vec<u32>, Vec<usize>)> {
        let twin = &self.cut.connectivity().twin;
        let is_border =
            |h: u32| twin[h as usize] == NONE || self.refined.cut(self.cut.tail(h), self.cut.head(h)).is_some();
        let borders: Vec<u32> =
            members.iter().flat_map(|&r| (0..3).map(move |k| 3 * r + k)).filter(|&h| is_border(h)).collect();
        let start = *borders.first()?;
        let mut lp = vec![start];
        let mut h = start;
        loop {
            // The next border half-edge leaving head(h), turning inside the chart.
            let mut c = next(h);
            let mut guard = 0;
            while !is_border(c) {
                c = next(twin[c as usize]);
                guard += 1;
                if guard > borders.len() + 3 * members.len() {
                    return None;
                }
            }
            if c == start {
                break;
            }
            if lp.len() > borders.len() {
                return None;
            }
            lp.push(c);
            h = c;
        }
        let mut vertices: Vec<u32> = members.iter().flat_map(|&r| self.cut.triangles()[r as usize]).collect();
        vertices.sort_unstable();
        vertices.dedup();
        let edges = (3 * members.len() + borders.len()) / 2;
        let euler = vertices.len() as i64 - edges as i64 + members.len() as i64;
        if lp.len() != borders.len() || euler != 1 {
            return None;
        }
        let corners = (0..lp.len()).filter(|&i| self.is_corner(lp[(i + lp.len() - 1) % lp.len()], lp[i])).collect();
        Some((lp, corners))
    }

    /// Whether the chart's boundary turns at the vertex between border half-edges `h_in` and
    /// `h_out`.
    fn is_corner(&self, h_in: u32, h_out: u32) -> bool {
        let v = self.cut.tail(h_out);
        let Some(node) = v.checked_sub(self.refined.first_node).filter(|&n| (n as usize) < self.graph.kind.len())
        else {
            return false;
        };
        let slot = |h: u32, other: u32, on_boundary: u8| {
            if self.cut.connectivity().twin[h as usize] == NONE {
                Some(on_boundary)
            } else {
                self.refined.slot_at(v, other)
            }
        };
        let (Some(s_in), Some(s_out)) = (slot(h_in, self.cut.tail(h_in), 2), slot(h_out, self.cut.head(h_out), 0))
        else {
            return false;
        };
        match self.graph.kind[node as usize] {
            NodeKind::Grid => (s_in + 2) % 4 != s_out,
            NodeKind::Boundary => (s_in == 1) != (s_out == 1),
            NodeKind::Crossing => false,
        }
    }

    /// Length of border half-edge `h` along its side, in cells: θ or φ × density / 2π
    /// (mesh-boundary edges: ω × their length × density / 2π).
    fn side_length(&self, h: u32) -> f64 {
        let (a, b) = (self.cut.tail(h), self.cut.head(h));
        let (r, k) = ((h / 3) as usize, (h % 3) as usize);
        match self.refined.cut(a, b) {
            Some(cut) => {
                let f = 1 - cut.family as usize;
                self.scale * (self.corner_coords(r, (k + 1) % 3)[f] - self.corner_coords(r, k)[f]).abs()
            }
            None => {
                self.scale * self.result.omega * distance(self.cut.points()[a as usize], self.cut.points()[b as usize])
            }
        }
    }

    /// Length of every side, in periods.
    fn side_lengths(&self, lp: &[u32], corners: &[usize]) -> Vec<f64> {
        let lengths: Vec<f64> = lp.iter().map(|&h| self.side_length(h)).collect();
        sides(&lengths, corners)
    }

    /// Mean-value re-parameterization with the boundary on a rectangle (four corners, equal
    /// opposite sides) or on a regular N-gon split into quads; `None` with fewer than three
    /// corners or when a solve fails.
    fn reparameterize(&self, members: &[u32], lp: &[u32], corners: &[usize]) -> Option<ChartOutput> {
        let n = corners.len();
        if n < 3 {
            return None;
        }
        let lengths: Vec<f64> = lp.iter().map(|&h| self.side_length(h)).collect();
        let side = sides(&lengths, corners);
        let rectangle = n == 4 && same_length(side[0], side[2]) && same_length(side[1], side[3]);
        let polygon = domain_polygon(&side, rectangle);
        let mut boundary = HashMap::with_capacity(lp.len());
        for (s, &c0) in corners.iter().enumerate() {
            let c1 = corners[(s + 1) % n];
            let steps: Vec<usize> =
                (0..((c1 + lp.len() - c0 - 1) % lp.len() + 1)).map(|i| (c0 + i) % lp.len()).collect();
            let total: f64 = steps.iter().map(|&i| lengths[i]).sum();
            let (p, q) = (polygon[s], polygon[(s + 1) % n]);
            let mut run = 0.0;
            for (j, &i) in steps.iter().enumerate() {
                let frac = if total > 0.0 { run / total } else { j as f64 / steps.len() as f64 };
                boundary.insert(self.cut.tail(lp[i]), [p[0] + frac * (q[0] - p[0]), p[1] + frac * (q[1] - p[1])]);
                run += lengths[i];
            }
        }
        let tris: Vec<[u32; 3]> = members.iter().map(|&r| self.cut.triangles()[r as usize]).collect();
        let point = |v: u32| self.cut.points()[v as usize];
        let uv = mean_value_map(&tris, &point, &|v| boundary.get(&v).copied())?;
        if rectangle {
            let (uv, size) = to_origin(uv);
            let chart = Chart { kind: ChartKind::MeanValue, corners: 4, singular: true, size, sides: side, layout: 0 };
            return Some(ChartOutput::whole(self.cut, members, chart, uv));
        }
        let mut domain = HashMap::new();
        for (t, q) in tris.iter().zip(&uv) {
            for k in 0..3 {
                domain.insert(t[k], q[k]);
            }
        }
        let chart = ChartDomain {
            base: self.cut.vertex_count() as u32,
            members,
            triangles: self.cut.triangles(),
            positions: self.cut.points(),
            domain: &domain,
            polygon: &polygon,
            sides: &side,
        };
        let quads = split_into_quads(&chart)?;
        let charts = quads
            .sizes
            .iter()
            .map(|&[w, h]| Chart {
                kind: ChartKind::SplitQuad,
                corners: 4,
                singular: true,
                size: [w, h],
                sides: vec![w, h, w, h],
                layout: 0,
            })
            .collect();
        Some(ChartOutput {
            charts,
            triangles: quads.triangles,
            source: quads.source,
            chart: quads.quad,
            uv: quads.uv,
            points: quads.points,
        })
    }
}

/// Whether two side lengths (periods) are equal: they are whole numbers up to rounding.
fn same_length(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-6 * a.max(b).max(1.0)
}

/// Corners of the parameter domain, in periods: the rectangle of the sides' lengths, or the
/// regular polygon with the mean side length, centred at the origin.
fn domain_polygon(side: &[f64], rectangle: bool) -> Vec<[f64; 2]> {
    let n = side.len();
    if rectangle {
        return vec![[0.0, 0.0], [side[0], 0.0], [side[0], side[1]], [0.0, side[1]]];
    }
    let mean = side.iter().sum::<f64>() / n as f64;
    let radius = mean / (2.0 * (std::f64::consts::PI / n as f64).sin());
    (0..n)
        .map(|i| {
            let a = TAU * i as f64 / n as f64;
            [radius * a.cos(), radius * a.sin()]
        })
        .collect()
}

/// Side lengths from the loop's edge lengths and corner positions.
fn sides(lengths: &[f64], corners: &[usize]) -> Vec<f64> {
    let (n, count) = (corners.len(), lengths.len());
    (0..n)
        .map(|s| {
            let (c0, c1) = (corners[s], corners[(s + 1) % n]);
            let steps = (c1 + count - c0 - 1) % count + 1;
            (0..steps).map(|i| lengths[(c0 + i) % count]).sum::<f64>()
        })
        .collect()
}

/// Twice the signed area of a (u, v) triangle.
fn area2(q: [[f64; 2]; 3]) -> f64 {
    (q[1][0] - q[0][0]) * (q[2][1] - q[0][1]) - (q[2][0] - q[0][0]) * (q[1][1] - q[0][1])
}

/// Translates (u, v) so the chart starts at whole periods just below its minimum; returns it
/// with its extent.
fn to_origin(mut uv: Vec<[[f64; 2]; 3]>) -> (Vec<[[f64; 2]; 3]>, [f64; 2]) {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in uv.iter().flatten() {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let shift = lo.map(|x| (x + 1e-6).floor());
    for p in uv.iter_mut().flatten() {
        p[0] -= shift[0];
        p[1] -= shift[1];
    }
    (uv, [hi[0] - shift[0], hi[1] - shift[1]])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::methods::pgp::{pgp, PgpOptions};
    use crate::progress::Progress;

    /// A flat 4 × 4 grid of unit squares, for a small [`PgpResult`] to build a [`Context`] from.
    fn grid_result() -> (TriMesh, PgpResult) {
        let n = 4u32;
        let positions: Vec<f64> = (0..=n).flat_map(|j| (0..=n).flat_map(move |i| [i as f64, j as f64, 0.0])).collect();
        let id = |i: u32, j: u32| j * (n + 1) + i;
        let tris: Vec<u32> = (0..n)
            .flat_map(|j| {
                (0..n).flat_map(move |i| {
                    [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j), id(i + 1, j + 1), id(i, j + 1)]
                })
            })
            .collect();
        let mesh = TriMesh::new(&positions, &tris).unwrap();
        let result = pgp(&mesh, &PgpOptions::default(), &mut Progress::none()).unwrap();
        (mesh, result)
    }

    /// A cut whose chart holds a zero-area triangle (an iso-line through a vertex splits a
    /// triangle into a line, 43e9845): the atlas refuses such a triangle, so it goes on a
    /// segment of its own (its (u, v) edge lengths are its 3D ones in cells) and the rest of
    /// the chart is flattened without a fold.
    #[test]
    fn a_zero_area_cut_triangle_is_laid_out_on_a_segment_beside_the_atlas_charts() {
        let (mesh, result) = grid_result();
        let graph = iso_graph(&mesh, &result, 1.0).unwrap();
        let refined = refine(&mesh, &graph);
        // The unit square (two triangles) and, under its bottom edge, the line 0 – 4 – 1.
        let points = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0], [0.25, 0.0, 0.0]];
        let cut = TriMesh::from_checked(points, vec![[0, 1, 2], [0, 2, 3], [0, 4, 1]]).unwrap();
        let context = Context {
            mesh: &mesh,
            result: &result,
            graph: &graph,
            refined: &refined,
            cut: &cut,
            density: 1.0,
            scale: 1.0 / TAU,
        };
        let out = context.flatten_by_atlas(&[0, 1, 2]).expect("the atlas flattens the square");

        let mut sources = out.source.clone();
        sources.sort_unstable();
        assert_eq!(sources, [0, 1, 2], "every cut triangle is laid out once");
        let line = out.source.iter().position(|&r| r == 2).unwrap();
        let line_chart = out.chart[line];
        assert_eq!(out.chart.iter().filter(|&&c| c == line_chart).count(), 1, "the line is a chart of its own");
        assert_eq!(out.charts[line_chart as usize].kind, ChartKind::Atlas);
        assert_eq!(area2(out.uv[line]), 0.0);
        let k = result.omega / TAU;
        let uv = out.uv[line];
        let length = |a: [f64; 2], b: [f64; 2]| (b[0] - a[0]).hypot(b[1] - a[1]);
        assert!((length(uv[0], uv[1]) - 0.25 * k).abs() < 1e-12 * k, "{uv:?}");
        assert!((length(uv[1], uv[2]) - 0.75 * k).abs() < 1e-12 * k, "{uv:?}");
        assert!((length(uv[0], uv[2]) - k).abs() < 1e-12 * k, "{uv:?}");
        for (r, q) in out.uv.iter().enumerate() {
            if r != line {
                assert!(area2(*q) > 0.0, "square triangle {} folds: {q:?}", out.source[r]);
                assert_ne!(out.chart[r], line_chart);
            }
        }
    }
}
