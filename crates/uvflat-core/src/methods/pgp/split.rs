//! Splitting an N-sided chart into quads (Ray et al. 2006, §3.4, Fig. 6 C–D): "by inserting one
//! vertex at the center of the chart and one vertex at the middle of each side of the chart",
//! cutting the mesh along the lines joining them, and re-parameterizing each quad; "the
//! parameter domains on the created charts are adjusted to preserve C0 continuity".
//!
//! The paper joins the new vertices by geodesics on the surface; here they are joined by
//! straight lines in the chart's mean-value map onto a regular N-gon ([`super::charts`]),
//! which is one-to-one, so their pre-images are simple curves on the surface from the centre
//! to the middle of each side, and the quads — the pre-images of the kites (centre, middle of
//! side k − 1, corner k, middle of side k) — are disks. The middle of a side is its midpoint in
//! the side's (θ, φ) length, the measure the neighbouring chart uses.
//!
//! Each triangle of the chart is clipped against the kites (two half-planes through the centre
//! each, Sutherland–Hodgman); a new vertex on an edge is named by the edge and the line, so
//! the two triangles of an edge create it once, and the lines meet only at the centre. Pieces
//! are fanned from their centroid. Quad k is then mapped by mean-value coordinates onto the
//! rectangle [0, L_k / 2] × [0, L_{k−1} / 2] (L: side lengths in periods), its outer half-sides
//! keeping the parameter of the N-gon boundary, so they match the neighbouring charts exactly.

use super::mean_value_chart::mean_value_map;
use crate::geometry::cross2;
use std::collections::HashMap;

/// Quads cut out of one chart.
#[derive(Debug, Clone, Default)]
pub struct SplitQuads {
    /// Positions of the new vertices; a vertex id `base + i` in `triangles` is `points[i]`.
    pub points: Vec<[f64; 3]>,
    /// Triangles: ids below `base` are vertices of the input triangulation.
    pub triangles: Vec<[u32; 3]>,
    /// Input triangle (of the chart's triangulation) every triangle lies in.
    pub source: Vec<u32>,
    /// Quad of every triangle.
    pub quad: Vec<u32>,
    /// (u, v) at every corner, in periods, in its quad's rectangle.
    pub uv: Vec<[[f64; 2]; 3]>,
    /// Width and height of every quad's rectangle.
    pub sizes: Vec<[f64; 2]>,
}

/// One chart: its triangles (vertex ids below `base`), the 3D position and the N-gon position
/// of every vertex, the N-gon's corners and the side lengths (periods).
pub struct ChartDomain<'a> {
    /// Vertex ids of the triangulation are below this.
    pub base: u32,
    /// The chart's triangles, by input triangle id.
    pub members: &'a [u32],
    /// Corners of every input triangle.
    pub triangles: &'a [[u32; 3]],
    /// 3D positions of the input vertices.
    pub positions: &'a [[f64; 3]],
    /// Position in the N-gon of every vertex of the chart.
    pub domain: &'a HashMap<u32, [f64; 2]>,
    /// The N-gon's corners, counter-clockwise, centred at the origin.
    pub polygon: &'a [[f64; 2]],
    /// Side k runs from corner k to corner k + 1; its length in periods.
    pub sides: &'a [f64],
}

/// A vertex of a clipped piece: what it is and where it is in the N-gon.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Key {
    Old(u32),
    /// On the edge (a, b), a < b, where line `j` crosses it.
    OnEdge(u32, u32, u32),
    Centre,
}

/// Which line a piece's edge lies on.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Along {
    Edge(u32, u32),
    Line(u32),
}

/// Splits the chart into quads and parameterizes them; `None` when a solve fails.
pub fn split_into_quads(chart: &ChartDomain) -> Option<SplitQuads> {
    let n = chart.polygon.len();
    let mid: Vec<[f64; 2]> = (0..n).map(|k| midpoint(chart.polygon[k], chart.polygon[(k + 1) % n])).collect();
    let mut out = SplitQuads::default();
    let mut ids: HashMap<(u32, u32, u32), u32> = HashMap::new();
    let mut centre = None;
    let mut pieces: Vec<Vec<[u32; 3]>> = vec![Vec::new(); n];
    let mut piece_source: Vec<Vec<u32>> = vec![Vec::new(); n];
    let mut plane: HashMap<u32, [f64; 2]> = HashMap::new();
    for &r in chart.members {
        let tri = chart.triangles[r as usize];
        for k in 0..n {
            let mut poly: Vec<(Key, [f64; 2], Along)> = (0..3)
                .map(|c| {
                    let (a, b) = (tri[c], tri[(c + 1) % 3]);
                    (Key::Old(a), chart.domain[&a], Along::Edge(a.min(b), a.max(b)))
                })
                .collect();
            // Sector k: left of the line through the middle of side k − 1, right of side k's.
            poly = clip(&poly, mid[(k + n - 1) % n], (k + n - 1) as u32 % n as u32, 1.0, chart);
            poly = clip(&poly, mid[k], k as u32, -1.0, chart);
            poly.dedup_by(|x, y| x.0 == y.0);
            if poly.len() > 1 && poly[0].0 == poly[poly.len() - 1].0 {
                poly.pop();
            }
            // Degenerate pieces (coincident vertices, zero area) are kept: dropping them would
            // open a slit in the quad.
            if poly.len() < 3 {
                continue;
            }
            let verts: Vec<u32> = poly
                .iter()
                .map(|&(key, d, _)| {
                    let id = out.vertex(chart, r, key, d, &mut ids, &mut centre);
                    plane.insert(id, d);
                    id
                })
                .collect();
            for t in fan(&mut out, chart, r, &verts, &mut plane) {
                pieces[k].push(t);
                piece_source[k].push(r);
            }
        }
    }
    for k in 0..n {
        let (w, h) = (0.5 * chart.sides[k], 0.5 * chart.sides[(k + n - 1) % n]);
        let kite = [[0.0, 0.0], mid[(k + n - 1) % n], chart.polygon[k], mid[k]];
        let rect = [[0.0, 0.0], [w, 0.0], [w, h], [0.0, h]];
        let point =
            |v: u32| if v < chart.base { chart.positions[v as usize] } else { out.points[(v - chart.base) as usize] };
        let boundary = |v: u32| Some(kite_to_rectangle(plane[&v], &kite, &rect));
        let uv = mean_value_map(&pieces[k], &point, &boundary)?;
        out.triangles.extend_from_slice(&pieces[k]);
        out.source.extend_from_slice(&piece_source[k]);
        out.quad.extend(std::iter::repeat_n(k as u32, uv.len()));
        out.uv.extend(uv);
        out.sizes.push([w, h]);
    }
    Some(out)
}

fn midpoint(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])]
}

/// Side of `x` relative to the line from the origin through `m`, zero within rounding.
fn side(m: [f64; 2], x: [f64; 2]) -> f64 {
    let s = cross2(m, x);
    let scale = (m[0].abs() + m[1].abs()) * (x[0].abs() + x[1].abs());
    if s.abs() <= 1e-12 * scale {
        0.0
    } else {
        s
    }
}

/// Sutherland–Hodgman: the part of `poly` where `sign · side(m, x) ≥ 0`.
fn clip(
    poly: &[(Key, [f64; 2], Along)],
    m: [f64; 2],
    line: u32,
    sign: f64,
    chart: &ChartDomain,
) -> Vec<(Key, [f64; 2], Along)> {
    let mut out: Vec<(Key, [f64; 2], Along)> = Vec::new();
    for i in 0..poly.len() {
        let (p, q) = (poly[i], poly[(i + 1) % poly.len()]);
        let (sp, sq) = (sign * side(m, p.1), sign * side(m, q.1));
        if sp >= 0.0 {
            out.push(p);
        }
        if (sp > 0.0 && sq < 0.0) || (sp < 0.0 && sq > 0.0) {
            let (key, at) = crossing(p.2, m, line, chart);
            if sp > 0.0 {
                out.push((key, at, Along::Line(line)));
            } else {
                out.push((key, at, p.2));
            }
        } else if sp == 0.0 && sq < 0.0 {
            if let Some(last) = out.last_mut() {
                last.2 = Along::Line(line);
            }
        }
    }
    out
}

/// Where line `line` (through the origin and `m`) crosses the piece edge lying along `along`.
fn crossing(along: Along, m: [f64; 2], line: u32, chart: &ChartDomain) -> (Key, [f64; 2]) {
    match along {
        Along::Edge(a, b) => {
            let (pa, pb) = (chart.domain[&a], chart.domain[&b]);
            let (sa, sb) = (cross2(m, pa), cross2(m, pb));
            let t = (sa / (sa - sb)).clamp(0.0, 1.0);
            (Key::OnEdge(a, b, line), [pa[0] + t * (pb[0] - pa[0]), pa[1] + t * (pb[1] - pa[1])])
        }
        Along::Line(_) => (Key::Centre, [0.0, 0.0]),
    }
}

/// Barycentric coordinates of `x` in the N-gon image of triangle `r`.
fn barycentric(chart: &ChartDomain, r: u32, x: [f64; 2]) -> [f64; 3] {
    let tri = chart.triangles[r as usize].map(|v| chart.domain[&v]);
    let d = |a: [f64; 2], b: [f64; 2]| [b[0] - a[0], b[1] - a[1]];
    let total = cross2(d(tri[0], tri[1]), d(tri[0], tri[2]));
    let l1 = cross2(d(tri[0], x), d(tri[0], tri[2])) / total;
    let l2 = cross2(d(tri[0], tri[1]), d(tri[0], x)) / total;
    [1.0 - l1 - l2, l1, l2]
}

impl SplitQuads {
    /// The vertex id of a piece vertex, creating new vertices once.
    fn vertex(
        &mut self,
        chart: &ChartDomain,
        r: u32,
        key: Key,
        d: [f64; 2],
        ids: &mut HashMap<(u32, u32, u32), u32>,
        centre: &mut Option<u32>,
    ) -> u32 {
        match key {
            Key::Old(v) => v,
            Key::OnEdge(a, b, j) => {
                if let Some(&id) = ids.get(&(a, b, j)) {
                    return id;
                }
                let (pa, pb) = (chart.domain[&a], chart.domain[&b]);
                let len = ((pb[0] - pa[0]).powi(2) + (pb[1] - pa[1]).powi(2)).sqrt();
                let t = if len > 0.0 { ((d[0] - pa[0]).powi(2) + (d[1] - pa[1]).powi(2)).sqrt() / len } else { 0.0 };
                let (xa, xb) = (chart.positions[a as usize], chart.positions[b as usize]);
                let id = self.push_point(chart, std::array::from_fn(|k| xa[k] + t * (xb[k] - xa[k])));
                ids.insert((a, b, j), id);
                id
            }
            Key::Centre => *centre.get_or_insert_with(|| {
                let b = barycentric(chart, r, d);
                let p = chart.triangles[r as usize].map(|v| chart.positions[v as usize]);
                self.push_point(chart, std::array::from_fn(|k| b[0] * p[0][k] + b[1] * p[1][k] + b[2] * p[2][k]))
            }),
        }
    }

    fn push_point(&mut self, chart: &ChartDomain, p: [f64; 3]) -> u32 {
        self.points.push(p);
        chart.base + (self.points.len() - 1) as u32
    }
}

/// Triangles of a convex piece of triangle `r`: itself, or a fan around its centroid.
fn fan(
    out: &mut SplitQuads,
    chart: &ChartDomain,
    r: u32,
    verts: &[u32],
    plane: &mut HashMap<u32, [f64; 2]>,
) -> Vec<[u32; 3]> {
    if verts.len() == 3 {
        return vec![[verts[0], verts[1], verts[2]]];
    }
    let n = verts.len() as f64;
    let c2: [f64; 2] = std::array::from_fn(|k| verts.iter().map(|v| plane[v][k]).sum::<f64>() / n);
    let b = barycentric(chart, r, c2);
    let p = chart.triangles[r as usize].map(|v| chart.positions[v as usize]);
    let c = out.push_point(chart, std::array::from_fn(|k| b[0] * p[0][k] + b[1] * p[1][k] + b[2] * p[2][k]));
    plane.insert(c, c2);
    (0..verts.len()).map(|i| [c, verts[i], verts[(i + 1) % verts.len()]]).collect()
}

/// The point of the rectangle matching `x` on the kite's boundary: each kite side maps
/// linearly onto the rectangle's side (the nearest kite side is taken).
fn kite_to_rectangle(x: [f64; 2], kite: &[[f64; 2]; 4], rect: &[[f64; 2]; 4]) -> [f64; 2] {
    let mut best = (f64::INFINITY, [0.0; 2]);
    for s in 0..4 {
        let (a, b) = (kite[s], kite[(s + 1) % 4]);
        let ab = [b[0] - a[0], b[1] - a[1]];
        let len2 = ab[0] * ab[0] + ab[1] * ab[1];
        let t = if len2 > 0.0 { (((x[0] - a[0]) * ab[0] + (x[1] - a[1]) * ab[1]) / len2).clamp(0.0, 1.0) } else { 0.0 };
        let dist = (x[0] - a[0] - t * ab[0]).hypot(x[1] - a[1] - t * ab[1]);
        if dist < best.0 {
            let (p, q) = (rect[s], rect[(s + 1) % 4]);
            best = (dist, [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
        }
    }
    best.1
}
