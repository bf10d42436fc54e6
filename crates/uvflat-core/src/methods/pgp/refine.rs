//! The chart boundaries of a PGP parameterization inserted into the triangulation (Ray et al.
//! 2006, §3.3: "if needed, the chart boundaries can be inserted in the triangulation"), the
//! step §3.4's per-chart parameterization needs.
//!
//! Every input triangle is cut by the iso-2kπ chords built by Algorithm 2
//! ([`super::isolines`] at one line per period), including the dangling ones that were removed
//! afterwards: in a non-singular triangle the chords are straight lines of constant θ or φ of
//! an affine map, so the pieces are convex — the triangle intersected with one period cell.
//! The cut is combinatorial: the triangle's boundary (corners and every line crossing on its
//! three edges, from both sides of each edge so neighbours stay conforming) is split by the
//! θ-chords as whole paths, then by the φ-chords segment by segment (their crossings with the
//! θ-chords are already on the pieces' boundaries). A piece with more than three vertices is
//! fanned from its centroid (collinear crossings on its sides rule out a fan from a corner).
//! Singular triangles carry no chords; they are fanned the same way when their edges carry
//! crossings of their neighbours.
//!
//! Cost: O(F + output) time and memory.

use super::isolines::{ChordPath, IsoGraph, NodeLocation};
use crate::mesh::NONE;
use crate::TriMesh;
use rayon::prelude::*;
use std::collections::HashMap;

/// The input triangulation with the chart boundaries inserted.
#[derive(Debug, Clone)]
pub struct RefinedMesh {
    /// Positions: the input vertices, then one vertex per iso-graph node, then the piece
    /// centroids.
    pub positions: Vec<[f64; 3]>,
    /// Triangles, counter-clockwise like the input.
    pub triangles: Vec<[u32; 3]>,
    /// The input triangle every refined triangle lies in.
    pub origin: Vec<u32>,
    /// Barycentric coordinates of every refined corner in its origin triangle.
    pub bary: Vec<[[f64; 3]; 3]>,
    /// Refined vertex of iso-graph node 0 (nodes follow in order).
    pub first_node: u32,
    /// Refined vertex of every iso-graph node: `first_node + node`, except that nodes at the
    /// same place on a mesh edge (one line crossing a singular edge, seen from both sides) share
    /// the first one's.
    pub node_vertex: Vec<u32>,
    /// Chart-boundary edges: unordered pairs `(a, b)`, `a < b`, of refined vertices along a
    /// chord segment still in the graph.
    pub cuts: HashMap<(u32, u32), Cut>,
    /// Chord segments that could not be inserted (a degenerate crossing order); 0 in practice.
    pub skipped_segments: usize,
}

/// A chart-boundary edge: the chord's family in its triangle's chart, and the iso-graph arm
/// slot along the edge at its lower and at its higher refined vertex.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Cut {
    /// 0: θ-line, 1: φ-line.
    pub family: u8,
    /// Arm slots at `(a, b)`.
    pub slots: [u8; 2],
}

/// One triangle's pieces: polygons of refined vertex ids (centroids not yet numbered).
struct TrianglePieces {
    polygons: Vec<Vec<u32>>,
    skipped: usize,
}

/// Inserts the chords of `graph` (built at one line per period) into `mesh`.
pub fn refine(mesh: &TriMesh, graph: &IsoGraph) -> RefinedMesh {
    let nv = mesh.vertex_count() as u32;
    let (on_edge, node_vertex) = edge_points(mesh, graph);
    let mut chords_of: Vec<Vec<usize>> = vec![Vec::new(); mesh.triangle_count()];
    for (i, c) in graph.chords.iter().enumerate() {
        chords_of[c.triangle as usize].push(i);
    }
    let pieces: Vec<TrianglePieces> = (0..mesh.triangle_count())
        .into_par_iter()
        .with_min_len(1024)
        .map(|t| {
            let chords: Vec<&ChordPath> = chords_of[t].iter().map(|&i| &graph.chords[i]).collect();
            triangle_pieces(mesh, &on_edge, &node_vertex, t, &chords)
        })
        .collect();
    let mut out = RefinedMesh {
        positions: mesh.points().to_vec(),
        triangles: Vec::new(),
        origin: Vec::new(),
        bary: Vec::new(),
        first_node: nv,
        node_vertex,
        cuts: HashMap::new(),
        skipped_segments: 0,
    };
    out.positions.extend_from_slice(&graph.position);
    for (t, p) in pieces.iter().enumerate() {
        out.skipped_segments += p.skipped;
        for poly in &p.polygons {
            out.add_polygon(mesh, graph, t, poly);
        }
    }
    for c in &graph.chords {
        for i in 0..c.nodes.len() - 1 {
            if graph.segment_present(c, i) {
                let (a, b) = (out.node_vertex[c.nodes[i].0 as usize], out.node_vertex[c.nodes[i + 1].0 as usize]);
                let (sa, sb) = (c.nodes[i].2, c.nodes[i + 1].1);
                let slots = if a < b { [sa, sb] } else { [sb, sa] };
                out.cuts.insert((a.min(b), a.max(b)), Cut { family: c.family, slots });
            }
        }
    }
    out
}

/// `(parameter, refined vertex)` along every undirected mesh edge, keyed by its smaller
/// half-edge.
type EdgePoints = HashMap<u32, Vec<(f64, u32)>>;

/// Refined vertices on every undirected mesh edge, keyed by its smaller half-edge, ordered
/// along it, and the refined vertex of every node.
fn edge_points(mesh: &TriMesh, graph: &IsoGraph) -> (EdgePoints, Vec<u32>) {
    let nv = mesh.vertex_count() as u32;
    let mut node_vertex: Vec<u32> = (0..graph.location.len() as u32).map(|n| nv + n).collect();
    let twin = &mesh.connectivity().twin;
    let mut map: HashMap<u32, Vec<(f64, u32)>> = HashMap::new();
    let mut side: HashMap<u32, bool> = HashMap::new();
    for (node, loc) in graph.location.iter().enumerate() {
        if let NodeLocation::Edge { half_edge: h, t } = *loc {
            let g = twin[h as usize];
            let (key, s) = if g != NONE && g < h { (g, 1.0 - t) } else { (h, t) };
            map.entry(key).or_default().push((s, node as u32));
            side.insert(node as u32, key == h);
        }
    }
    for list in map.values_mut() {
        list.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        // Only nodes made by the two sides separately (a line crossing a singular edge).
        list.dedup_by(|later, kept| {
            let same = later.0 - kept.0 <= 1e-12 && side[&later.1] != side[&kept.1];
            if same {
                node_vertex[later.1 as usize] = nv + kept.1;
            }
            same
        });
        list.iter_mut().for_each(|p| p.1 += nv);
    }
    (map, node_vertex)
}

/// Refined vertices on half-edge `h` from its tail to its head.
fn points_along(mesh: &TriMesh, on_edge: &EdgePoints, h: u32) -> Vec<u32> {
    let g = mesh.connectivity().twin[h as usize];
    let key = if g != NONE && g < h { g } else { h };
    let Some(list) = on_edge.get(&key) else { return Vec::new() };
    let ids = list.iter().map(|&(_, v)| v);
    if key == h {
        ids.collect()
    } else {
        ids.rev().collect()
    }
}

/// The convex pieces of triangle `t` cut by its chords.
fn triangle_pieces(
    mesh: &TriMesh,
    on_edge: &EdgePoints,
    node_vertex: &[u32],
    t: usize,
    chords: &[&ChordPath],
) -> TrianglePieces {
    let tri = mesh.triangles()[t];
    let mut boundary = Vec::new();
    for (k, &corner) in tri.iter().enumerate() {
        boundary.push(corner);
        boundary.extend(points_along(mesh, on_edge, (3 * t + k) as u32));
    }
    let mut polygons = vec![boundary];
    let mut skipped = 0;
    for family in 0..2u8 {
        for c in chords.iter().filter(|c| c.family == family) {
            let ids: Vec<u32> = c.nodes.iter().map(|&(n, _, _)| node_vertex[n as usize]).collect();
            if family == 0 {
                skipped += usize::from(!split_by_path(&mut polygons, &ids));
            } else {
                for w in ids.windows(2) {
                    skipped += usize::from(!split_by_path(&mut polygons, w));
                }
            }
        }
    }
    TrianglePieces { polygons, skipped }
}

/// Splits the polygon holding both ends of `path` (not adjacent in it) along the path, whose
/// inner nodes are new; false when there is none.
fn split_by_path(polygons: &mut Vec<Vec<u32>>, path: &[u32]) -> bool {
    let (a, b) = (path[0], path[path.len() - 1]);
    for p in 0..polygons.len() {
        let poly = &polygons[p];
        let (Some(i), Some(j)) = (poly.iter().position(|&v| v == a), poly.iter().position(|&v| v == b)) else {
            continue;
        };
        let n = poly.len();
        if path.len() == 2 && ((i + 1) % n == j || (j + 1) % n == i) {
            return true; // already an edge
        }
        let inner = &path[1..path.len() - 1];
        // From a to b along the polygon, back along the path; from b to a, then along the path.
        let mut first: Vec<u32> = (0..).map(|k| poly[(i + k) % n]).take((j + n - i) % n + 1).collect();
        first.extend(inner.iter().rev());
        let mut second: Vec<u32> = (0..).map(|k| poly[(j + k) % n]).take((i + n - j) % n + 1).collect();
        second.extend(inner.iter());
        polygons[p] = first;
        polygons.push(second);
        return true;
    }
    false
}

impl RefinedMesh {
    /// Adds polygon `poly` of input triangle `t` as one triangle or a fan around its centroid.
    fn add_polygon(&mut self, mesh: &TriMesh, graph: &IsoGraph, t: usize, poly: &[u32]) {
        let bary: Vec<[f64; 3]> = poly.iter().map(|&v| self.vertex_bary(mesh, graph, t, v)).collect();
        if poly.len() == 3 {
            self.push(t, [poly[0], poly[1], poly[2]], [bary[0], bary[1], bary[2]]);
            return;
        }
        let n = poly.len() as f64;
        let centre: [f64; 3] = std::array::from_fn(|k| bary.iter().map(|b| b[k]).sum::<f64>() / n);
        let corners = mesh.triangles()[t].map(|v| mesh.points()[v as usize]);
        self.positions.push(std::array::from_fn(|k| (0..3).map(|c| centre[c] * corners[c][k]).sum()));
        let c = (self.positions.len() - 1) as u32;
        for i in 0..poly.len() {
            let j = (i + 1) % poly.len();
            self.push(t, [c, poly[i], poly[j]], [centre, bary[i], bary[j]]);
        }
    }

    fn push(&mut self, t: usize, tri: [u32; 3], bary: [[f64; 3]; 3]) {
        self.triangles.push(tri);
        self.origin.push(t as u32);
        self.bary.push(bary);
    }

    /// Barycentric coordinates of refined vertex `v` (an input corner or a node) in `t`.
    fn vertex_bary(&self, mesh: &TriMesh, graph: &IsoGraph, t: usize, v: u32) -> [f64; 3] {
        let tri = mesh.triangles()[t];
        if v < self.first_node {
            return std::array::from_fn(|k| if tri[k] == v { 1.0 } else { 0.0 });
        }
        match graph.location[(v - self.first_node) as usize] {
            NodeLocation::Inside { bary, .. } => bary,
            NodeLocation::Edge { half_edge: h, t: s } => {
                let (h, s) = if h as usize / 3 == t { (h, s) } else { (mesh.connectivity().twin[h as usize], 1.0 - s) };
                let k = (h % 3) as usize;
                let mut b = [0.0; 3];
                b[k] = 1.0 - s;
                b[(k + 1) % 3] = s;
                b
            }
        }
    }
}

impl RefinedMesh {
    /// Splits an interior edge of every triangle whose three vertices lie on chart boundaries
    /// (cut edges or the mesh boundary) at its midpoint, so that a chart mapped onto a convex
    /// domain with straight sides never has a triangle with its three corners on one side,
    /// which a fixed-boundary map flattens to zero area (Floater 2003's embedding theorem
    /// excludes such triangles). Returns the number of edges split. `twin`: the half-edge
    /// twins of the refined triangulation.
    pub fn split_border_triangles(&mut self, twin: &[u32]) -> usize {
        let mut on_border = vec![false; self.positions.len()];
        let mut triangle_of: HashMap<(u32, u32), usize> = HashMap::with_capacity(3 * self.triangles.len());
        for (r, t) in self.triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                triangle_of.insert((a, b), r);
                if twin[3 * r + k] == NONE || self.cut(a, b).is_some() {
                    on_border[a as usize] = true;
                    on_border[b as usize] = true;
                }
            }
        }
        let ears: Vec<usize> =
            (0..self.triangles.len()).filter(|&r| self.triangles[r].iter().all(|&v| on_border[v as usize])).collect();
        let mut split = 0;
        for r in ears {
            let t = self.triangles[r];
            if !t.iter().all(|&v| on_border.get(v as usize).copied().unwrap_or(false)) {
                continue; // already split through a neighbour
            }
            let interior = (0..3)
                .map(|k| (t[k], t[(k + 1) % 3]))
                .find(|&(a, b)| triangle_of.contains_key(&(b, a)) && self.cut(a, b).is_none());
            if let Some((a, b)) = interior {
                self.split_edge(a, b, &mut triangle_of);
                split += 1;
            }
        }
        split
    }

    /// Splits interior edge a–b at its midpoint, and both its triangles.
    fn split_edge(&mut self, a: u32, b: u32, triangle_of: &mut HashMap<(u32, u32), usize>) {
        let (pa, pb) = (self.positions[a as usize], self.positions[b as usize]);
        self.positions.push(std::array::from_fn(|k| 0.5 * (pa[k] + pb[k])));
        let e = (self.positions.len() - 1) as u32;
        for (p, q) in [(a, b), (b, a)] {
            let r = triangle_of.remove(&(p, q)).expect("interior edge");
            let k = (0..3).find(|&k| self.triangles[r][k] == p).expect("edge of its triangle");
            let x = self.triangles[r][(k + 2) % 3];
            let bary = self.bary[r];
            let (bp, bq, bx) = (bary[k], bary[(k + 1) % 3], bary[(k + 2) % 3]);
            let be: [f64; 3] = std::array::from_fn(|i| 0.5 * (bp[i] + bq[i]));
            self.triangles[r] = [p, e, x];
            self.bary[r] = [bp, be, bx];
            let n = self.triangles.len();
            self.push(self.origin[r] as usize, [e, q, x], [be, bq, bx]);
            triangle_of.insert((p, e), r);
            triangle_of.insert((e, x), r);
            triangle_of.insert((e, q), n);
            triangle_of.insert((q, x), n);
            triangle_of.insert((x, e), n);
        }
    }

    /// The chart-boundary edge between refined vertices `a` and `b`, if it is one.
    pub fn cut(&self, a: u32, b: u32) -> Option<Cut> {
        self.cuts.get(&(a.min(b), a.max(b))).copied()
    }

    /// The iso-graph arm slot at `a` along the chart-boundary edge `a`–`b`.
    pub fn slot_at(&self, a: u32, b: u32) -> Option<u8> {
        self.cut(a, b).map(|c| c.slots[usize::from(a > b)])
    }
}
