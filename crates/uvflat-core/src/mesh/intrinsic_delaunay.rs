//! Intrinsic Delaunay triangulation by edge flips (Bobenko & Springborn 2007, "A discrete
//! Laplace–Beltrami operator for simplicial surfaces", DCG 38, §2–§3; Fisher, Springborn,
//! Bobenko & Schröder 2007, "An algorithm for the construction of intrinsic Delaunay
//! triangulations", §3), used by the circle patterns of Kharevych, Springborn & Schröder
//! 2006 (§4: their intersection angles are conformally invariant only on a Delaunay
//! triangulation).
//!
//! The surface is the mesh's piecewise flat metric, known by its edge lengths alone. An
//! interior edge is (locally) Delaunay when the two angles opposite it sum to at most π
//! (cot α + cot β ≥ 0). A non-Delaunay edge is flipped: its two triangles, unfolded into the
//! plane, form a convex quadrilateral (the two opposite angles sum to more than π), whose other
//! diagonal is a geodesic of the surface; its length is read off the unfolding. Flipping until
//! every edge is Delaunay terminates (Bobenko & Springborn, Prop. 10) and changes neither the
//! vertices nor the boundary nor the metric, only the triangulation.
//!
//! In general the flips may join two vertices by a second edge (the result is then a
//! Δ-complex, not a simplicial surface). This implementation keeps the triangulation simplicial,
//! so that the rest of the library's connectivity applies to it: a flip that would create an
//! edge between two vertices already joined is not made, and the edge is counted in
//! [`IntrinsicTriangulation::non_delaunay_edges`]. Callers may also keep given edges (a cut
//! graph) and boundary fans ([`FlipConstraints`]). The half-edge convention is the mesh's:
//! half-edge `3t + k` runs from corner `k` of triangle `t` to corner `k + 1`.

use super::connectivity::{next, prev, NONE};
use super::TriMesh;
use crate::geometry::distance;
use std::collections::HashSet;

/// Flips that are not worth making: cot α + cot β below −this counts as non-Delaunay (an edge
/// of four co-circular vertices is Delaunay both ways, and rounding must not flip it back and
/// forth).
const DELAUNAY_TOLERANCE: f64 = 1e-12;

/// The intrinsic Delaunay triangulation of a mesh: same vertices, new triangles, and the
/// length of every edge in the mesh's metric.
#[derive(Debug, Clone)]
pub struct IntrinsicTriangulation {
    /// Triangles, counter-clockwise as in the mesh.
    pub triangles: Vec<[u32; 3]>,
    /// `lengths[t][k]`: length of half-edge `3t + k` (corner k to corner k + 1).
    pub lengths: Vec<[f64; 3]>,
    /// Twin of each half-edge ([`NONE`] on the boundary).
    pub twin: Vec<u32>,
    /// Edge flips made.
    pub flips: u32,
    /// Interior edges left non-Delaunay: their flip would have joined two vertices twice, or
    /// is ruled out by the caller's [`FlipConstraints`] (a fixed edge, a boundary fan).
    pub non_delaunay_edges: u32,
}

impl IntrinsicTriangulation {
    /// Interior angles from the edge lengths, `[t][k]` at corner k.
    pub fn corner_angles(&self) -> Vec<[f64; 3]> {
        self.lengths.iter().map(|&l| angles_from_lengths(l)).collect()
    }
}

/// The interior angles of a triangle with half-edge lengths `l` (`l[k]` from corner k to
/// k + 1): the angle at corner k is opposite `l[k + 1]`, by the half-angle formula
/// tan(A/2) = √((s − b)(s − c) / (s (s − a))), accurate for small angles.
pub fn angles_from_lengths(l: [f64; 3]) -> [f64; 3] {
    let s = 0.5 * (l[0] + l[1] + l[2]);
    std::array::from_fn(|k| {
        let a = l[(k + 1) % 3];
        let (b, c) = (l[k], l[(k + 2) % 3]);
        let num = ((s - b) * (s - c)).max(0.0);
        let den = (s * (s - a)).max(0.0);
        2.0 * num.sqrt().atan2(den.sqrt())
    })
}

/// 3D length of every half-edge, `[t][k]` for half-edge 3t + k.
pub fn edge_lengths(mesh: &TriMesh) -> Vec<[f64; 3]> {
    let p = mesh.points();
    mesh.triangles()
        .iter()
        .map(|t| std::array::from_fn(|k| distance(p[t[k] as usize], p[t[(k + 1) % 3] as usize])))
        .collect()
}

/// cot of the angle at the corner opposite half-edge `h`.
fn opposite_cot(lengths: &[[f64; 3]], h: u32) -> f64 {
    let (t, k) = ((h / 3) as usize, (h % 3) as usize);
    let l = lengths[t];
    let (a, b, c) = (l[k], l[(k + 1) % 3], l[(k + 2) % 3]);
    let s = 0.5 * (a + b + c);
    let area = (s * (s - a) * (s - b) * (s - c)).max(0.0).sqrt();
    (b * b + c * c - a * a) / (4.0 * area)
}

/// Flips the interior edges of `mesh` until every one is Delaunay in the mesh's metric (or
/// would join two already joined vertices). O(E) flips in practice; each pops one edge and
/// pushes the four around it.
pub fn intrinsic_delaunay(mesh: &TriMesh) -> IntrinsicTriangulation {
    intrinsic_delaunay_constrained(mesh, &FlipConstraints::default())
}

/// Edges [`intrinsic_delaunay_constrained`] must not flip.
#[derive(Debug, Clone, Copy, Default)]
pub struct FlipConstraints<'a> {
    /// No flip leaves a boundary vertex in a single triangle (whose angle there would then
    /// have to be the whole boundary angle, near π on a smooth boundary): for callers that
    /// prescribe the boundary angles.
    pub keep_boundary_fans: bool,
    /// Edges (vertex pairs, either order) kept as they are, e.g. a cut graph the caller will
    /// open the result along.
    pub fixed_edges: &'a [[u32; 2]],
}

/// [`intrinsic_delaunay`] under `constraints`; the edges left non-Delaunay because of them
/// are counted in [`IntrinsicTriangulation::non_delaunay_edges`].
pub fn intrinsic_delaunay_constrained(mesh: &TriMesh, constraints: &FlipConstraints) -> IntrinsicTriangulation {
    let keep_boundary_fans = constraints.keep_boundary_fans;
    let fixed: HashSet<[u32; 2]> = constraints.fixed_edges.iter().map(|&[a, b]| edge_key(a, b)).collect();
    let triangles = mesh.triangles().to_vec();
    let mut fan_size = mesh.corner_counts();
    let thin_fan =
        |v: u32, fan_size: &[u32]| keep_boundary_fans && mesh.is_boundary_vertex(v) && fan_size[v as usize] <= 2;
    let lengths = edge_lengths(mesh);
    let twin = mesh.connectivity().twin.clone();
    let mut tri = IntrinsicTriangulation { triangles, lengths, twin, flips: 0, non_delaunay_edges: 0 };
    let mut edges: HashSet<[u32; 2]> = HashSet::new();
    for (h, &o) in tri.twin.iter().enumerate() {
        if o == NONE || (h as u32) < o {
            edges.insert(edge_key(tri.tail(h as u32), tri.tail(next(h as u32))));
        }
    }
    let mut stack: Vec<u32> = (0..tri.twin.len() as u32).filter(|&h| tri.twin[h as usize] > h).collect();
    while let Some(h) = stack.pop() {
        if tri.is_delaunay(h) {
            continue;
        }
        let (k, l) = (tri.tail(prev(h)), tri.tail(prev(tri.twin[h as usize])));
        let (i, j) = (tri.tail(h), tri.tail(next(h)));
        let blocked = fixed.contains(&edge_key(i, j)) || thin_fan(i, &fan_size) || thin_fan(j, &fan_size);
        if k == l || edges.contains(&edge_key(k, l)) || blocked {
            continue;
        }
        edges.remove(&edge_key(i, j));
        edges.insert(edge_key(k, l));
        fan_size[i as usize] -= 1;
        fan_size[j as usize] -= 1;
        fan_size[k as usize] += 1;
        fan_size[l as usize] += 1;
        stack.extend(tri.flip(h));
    }
    tri.non_delaunay_edges =
        (0..tri.twin.len() as u32).filter(|&h| tri.twin[h as usize] > h && !tri.is_delaunay(h)).count() as u32;
    tri
}

fn edge_key(a: u32, b: u32) -> [u32; 2] {
    [a.min(b), a.max(b)]
}

impl IntrinsicTriangulation {
    fn tail(&self, h: u32) -> u32 {
        self.triangles[(h / 3) as usize][(h % 3) as usize]
    }

    fn length(&self, h: u32) -> f64 {
        self.lengths[(h / 3) as usize][(h % 3) as usize]
    }

    /// Boundary edges, and interior edges whose opposite angles sum to at most π.
    fn is_delaunay(&self, h: u32) -> bool {
        let o = self.twin[h as usize];
        o == NONE || opposite_cot(&self.lengths, h) + opposite_cot(&self.lengths, o) >= -DELAUNAY_TOLERANCE
    }

    /// Length of the other diagonal of the quadrilateral of interior half-edge h (from i to j,
    /// corner k opposite on its side, l on the twin's), from the two triangles unfolded with
    /// i at the origin and j on the positive x axis.
    fn flipped_length(&self, h: u32) -> f64 {
        let o = self.twin[h as usize];
        let ij = self.length(h);
        let (jk, ki) = (self.length(next(h)), self.length(prev(h)));
        let (il, lj) = (self.length(next(o)), self.length(prev(o)));
        let apex = |to_i: f64, to_j: f64| {
            let x = (ij * ij + to_i * to_i - to_j * to_j) / (2.0 * ij);
            (x, (to_i * to_i - x * x).max(0.0).sqrt())
        };
        let (xk, yk) = apex(ki, jk);
        let (xl, yl) = apex(il, lj);
        ((xk - xl).powi(2) + (yk + yl).powi(2)).sqrt()
    }

    /// Flips interior half-edge h: triangles (i, j, k) and (j, i, l) become (k, i, l) and
    /// (l, j, k), in the same two slots, the new edge l→k / k→l as their half-edges 2.
    /// Returns the four outer half-edges, to be checked again.
    fn flip(&mut self, h: u32) -> [u32; 4] {
        let o = self.twin[h as usize];
        let (t1, t2) = (h / 3, o / 3);
        let (i, j, k, l) = (self.tail(h), self.tail(o), self.tail(prev(h)), self.tail(prev(o)));
        let diagonal = self.flipped_length(h);
        // Outer half-edges with their twins and lengths: k→i, i→l, l→j, j→k.
        let outer = [prev(h), next(o), prev(o), next(h)];
        let saved: Vec<(u32, f64)> = outer.iter().map(|&e| (self.twin[e as usize], self.length(e))).collect();
        self.triangles[t1 as usize] = [k, i, l];
        self.triangles[t2 as usize] = [l, j, k];
        let slots = [3 * t1, 3 * t1 + 1, 3 * t2, 3 * t2 + 1];
        for (&slot, &(twin, length)) in slots.iter().zip(&saved) {
            self.twin[slot as usize] = twin;
            if twin != NONE {
                self.twin[twin as usize] = slot;
            }
            self.lengths[(slot / 3) as usize][(slot % 3) as usize] = length;
        }
        let (n1, n2) = (3 * t1 + 2, 3 * t2 + 2);
        self.twin[n1 as usize] = n2;
        self.twin[n2 as usize] = n1;
        self.lengths[t1 as usize][2] = diagonal;
        self.lengths[t2 as usize][2] = diagonal;
        self.flips += 1;
        slots
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mesh(positions: &[f64], triangles: &[u32]) -> TriMesh {
        TriMesh::new(positions, triangles).unwrap()
    }

    #[test]
    fn angles_from_lengths_of_a_right_triangle() {
        let a = angles_from_lengths([3.0, 5.0, 4.0]);
        // Corner 0 is opposite l[1] = 5: the right angle.
        assert!((a[0] - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        assert!((a[1] - (4.0f64 / 5.0).asin()).abs() < 1e-15);
        assert!((a.iter().sum::<f64>() - std::f64::consts::PI).abs() < 1e-15);
    }

    #[test]
    fn flat_non_delaunay_quad_is_flipped_to_the_planar_delaunay_diagonal() {
        // A flat rhombus split along its long diagonal (0–2): angles at 1 and 3 are obtuse.
        let positions = [0.0, 0.0, 0.0, 2.0, -0.5, 0.0, 4.0, 0.0, 0.0, 2.0, 0.5, 0.0];
        let m = mesh(&positions, &[0, 1, 2, 0, 2, 3]);
        let t = intrinsic_delaunay(&m);
        assert_eq!(t.flips, 1);
        assert_eq!(t.non_delaunay_edges, 0);
        let h = (0..6).find(|&h| t.twin[h] != NONE).unwrap();
        let (a, b) = (t.triangles[h / 3][h % 3], t.triangles[h / 3][(h + 1) % 3]);
        assert_eq!(edge_key(a, b), [1, 3]);
        assert!((t.lengths[h / 3][h % 3] - 1.0).abs() < 1e-14);
        // The metric is unchanged: every triangle's lengths are the 3D distances of its corners.
        for (tri, len) in t.triangles.iter().zip(&t.lengths) {
            for k in 0..3 {
                let d = distance(m.points()[tri[k] as usize], m.points()[tri[(k + 1) % 3] as usize]);
                assert!((len[k] - d).abs() < 1e-14);
            }
        }
    }

    #[test]
    fn folded_quad_gets_the_geodesic_diagonal() {
        // Two triangles folded by 90° along 0–2; their unfolding is the rhombus above, so the
        // new diagonal is 1 long although the 3D distance of 1 and 3 is not.
        let positions = [0.0, 0.0, 0.0, 2.0, -0.5, 0.0, 4.0, 0.0, 0.0, 2.0, 0.0, 0.5];
        let t = intrinsic_delaunay(&mesh(&positions, &[0, 1, 2, 0, 2, 3]));
        assert_eq!(t.flips, 1);
        let h = (0..6).find(|&h| t.twin[h] != NONE).unwrap();
        assert!((t.lengths[h / 3][h % 3] - 1.0).abs() < 1e-14);
        let sum: f64 = t.corner_angles().iter().flatten().sum();
        assert!((sum - 2.0 * std::f64::consts::PI).abs() < 1e-13);
    }

    #[test]
    fn flip_that_would_duplicate_an_edge_is_not_made() {
        // A fan of three triangles around vertex 3, which lies beyond vertex 1 (x > 1) and
        // above: the angles at 1 and 2 opposite the spoke 0–3 are both obtuse, but flipping it
        // would join 1 and 2, which the boundary already joins (so would any spoke's flip).
        let positions = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.5, 0.9, 0.0, 1.5, 0.5, 0.5];
        let m = mesh(&positions, &[0, 1, 3, 1, 2, 3, 2, 0, 3]);
        let t = intrinsic_delaunay(&m);
        assert_eq!(t.flips, 0);
        assert!(t.non_delaunay_edges >= 1);
        assert_eq!(t.triangles, m.triangles());
    }

    #[test]
    fn fixed_edges_and_boundary_fans_are_kept() {
        // The flat rhombus of the first test: its diagonal 0–2 is non-Delaunay, but fixed.
        let positions = [0.0, 0.0, 0.0, 2.0, -0.5, 0.0, 4.0, 0.0, 0.0, 2.0, 0.5, 0.0];
        let m = mesh(&positions, &[0, 1, 2, 0, 2, 3]);
        let fixed =
            intrinsic_delaunay_constrained(&m, &FlipConstraints { keep_boundary_fans: false, fixed_edges: &[[2, 0]] });
        assert_eq!((fixed.flips, fixed.non_delaunay_edges), (0, 1));
        // Every vertex is a boundary vertex in two triangles or fewer: flipping 0–2 would leave
        // 0 and 2 in one triangle each.
        let fans = intrinsic_delaunay_constrained(&m, &FlipConstraints { keep_boundary_fans: true, fixed_edges: &[] });
        assert_eq!((fans.flips, fans.non_delaunay_edges), (0, 1));
        assert_eq!(intrinsic_delaunay(&m).flips, 1);
    }
}
