//! What to do with the zero-area triangles of a modelled mesh so that it can be solved:
//! vertices snapped onto each other but not merged, and faces whose corners are collinear,
//! which `TriMesh::new` refuses (a zero-area triangle has no angles and no Jacobian).
//!
//! 1. **Weld.** In every degenerate triangle (relative area ≤ `DEGENERATE_RELATIVE_AREA`, or a
//!    corner repeated), the two ends of an edge shorter than `COINCIDENT_RELATIVE_LENGTH` times
//!    that triangle's longest edge are one point: they are welded into one solve vertex (a
//!    triangle whose three corners meet welds all three). Welding is transitive (union–find).
//! 2. **Leave out** every triangle that is still degenerate over the welded vertices: those that
//!    lost a corner to the weld, and collinear ones whose corners are apart (a slit of zero
//!    area, which becomes a free boundary of the solve).
//!
//! The caller solves the kept triangles over the welded vertices and gives every input vertex
//! the UV of its solve vertex; a left-out triangle then gets UVs of zero area, like its 3D
//! shape. A solve vertex that only left-out triangles use gets no UV from a solve; it is
//! counted (`unreferenced`) so that the caller can refuse or handle it.
//!
//! Cost: O(n + m) plus the union–find.

use super::validate::is_degenerate;
use crate::error::{Error, Result};
use crate::geometry::{distance, relative_area};
use uvflat_sparse::union_find::{set_labels, union};

/// An edge of a degenerate triangle shorter than this times the triangle's longest edge joins
/// two vertices that are one point (snapped together but not merged).
pub const COINCIDENT_RELATIVE_LENGTH: f64 = 1e-6;

/// The welds and left-out triangles of [`snapped_repair`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SnappedRepair {
    /// Solve vertex of every input vertex, numbered in order of their lowest input vertex (an
    /// input vertex welded to none is a solve vertex of its own).
    pub vertex: Vec<u32>,
    /// Number of solve vertices.
    pub vertex_count: usize,
    /// Per input triangle: kept for the solve (false: left out).
    pub keep: Vec<bool>,
    /// Input vertices welded onto another (input vertices − solve vertices).
    pub welded: usize,
    /// Triangles left out.
    pub left_out: usize,
    /// Solve vertices used by some triangle, but only by left-out ones.
    pub unreferenced: usize,
}

/// Finds the welds and the triangles to leave out (see the module docs). Errors for an index
/// out of range or a non-finite coordinate of a used vertex; a mesh without degenerate
/// triangles gives no welds and keeps everything.
pub fn snapped_repair(points: &[[f64; 3]], triangles: &[[u32; 3]]) -> Result<SnappedRepair> {
    check(points, triangles)?;
    let degenerate = |t: &[u32; 3], p: &dyn Fn(u32) -> [f64; 3]| {
        t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || is_degenerate(relative_area(p(t[0]), p(t[1]), p(t[2])))
    };
    let at = |v: u32| points[v as usize];
    let mut parent: Vec<u32> = (0..points.len() as u32).collect();
    for t in triangles.iter().filter(|t| degenerate(t, &at)) {
        let length = |k: usize| distance(at(t[k]), at(t[(k + 1) % 3]));
        let longest = length(0).max(length(1)).max(length(2));
        for k in 0..3 {
            if length(k) <= COINCIDENT_RELATIVE_LENGTH * longest {
                union(&mut parent, t[k], t[(k + 1) % 3]);
            }
        }
    }
    let (vertex, vertex_count) = set_labels(&mut parent);
    // A solve vertex sits where its lowest input vertex is (the labels follow the lowest members).
    let mut position = vec![[0.0; 3]; vertex_count];
    for v in (0..points.len()).rev() {
        position[vertex[v] as usize] = points[v];
    }
    let keep: Vec<bool> =
        triangles.iter().map(|t| !degenerate(&t.map(|v| vertex[v as usize]), &|w| position[w as usize])).collect();
    let mut used = vec![0u8; vertex_count];
    for (t, &k) in triangles.iter().zip(&keep) {
        for &v in t {
            let s = &mut used[vertex[v as usize] as usize];
            *s = (*s).max(if k { 2 } else { 1 });
        }
    }
    Ok(SnappedRepair {
        welded: points.len() - vertex_count,
        left_out: keep.iter().filter(|&&k| !k).count(),
        unreferenced: used.iter().filter(|&&u| u == 1).count(),
        vertex,
        vertex_count,
        keep,
    })
}

fn check(points: &[[f64; 3]], triangles: &[[u32; 3]]) -> Result<()> {
    if triangles.is_empty() {
        return Err(Error::EmptyMesh);
    }
    for (t, tri) in triangles.iter().enumerate() {
        for &v in tri {
            let Some(p) = points.get(v as usize) else {
                return Err(Error::IndexOutOfRange { triangle: t, vertex: v as u64, vertex_count: points.len() });
            };
            if let Some(&value) = p.iter().find(|x| !x.is_finite()) {
                return Err(Error::NonFiniteCoordinate { vertex: v as usize, value });
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3 × 3 grid of vertices (two triangles per square), vertex 4 (the centre) at `centre`.
    fn grid(centre: [f64; 3]) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
        let mut p: Vec<[f64; 3]> = (0..9).map(|k| [(k % 3) as f64, (k / 3) as f64, 0.0]).collect();
        p[4] = centre;
        let mut t = Vec::new();
        for j in 0..2u32 {
            for i in 0..2u32 {
                let a = 3 * j + i;
                t.push([a, a + 1, a + 4]);
                t.push([a, a + 4, a + 3]);
            }
        }
        (p, t)
    }

    #[test]
    fn a_proper_mesh_is_kept_whole() {
        let (p, t) = grid([1.0, 1.0, 0.3]);
        let r = snapped_repair(&p, &t).unwrap();
        assert_eq!((r.welded, r.left_out, r.unreferenced, r.vertex_count), (0, 0, 0, 9));
        assert_eq!(r.vertex, (0..9).collect::<Vec<u32>>());
    }

    #[test]
    fn a_vertex_snapped_onto_its_neighbour_is_welded_and_its_flat_triangles_left_out() {
        // The centre moved onto vertex 5 (2, 1): the two triangles holding both 4 and 5 have
        // zero area, and 4 and 5 become one solve vertex.
        let (p, t) = grid([2.0, 1.0, 0.0]);
        let r = snapped_repair(&p, &t).unwrap();
        assert_eq!((r.welded, r.vertex_count), (1, 8));
        assert_eq!(r.vertex[4], r.vertex[5]);
        for (tri, &k) in t.iter().zip(&r.keep) {
            assert_eq!(k, !(tri.contains(&4) && tri.contains(&5)), "{tri:?}");
        }
        assert_eq!((r.left_out, r.unreferenced), (2, 0));
    }

    #[test]
    fn collinear_corners_apart_are_left_out_without_a_weld() {
        // The centre at (0.5, 0, 0), halfway between vertices 0 and 1: triangle (0, 1, 4) is a
        // zero-area slit with no short edge.
        let (p, t) = grid([0.5, 0.0, 0.0]);
        let r = snapped_repair(&p, &t).unwrap();
        assert_eq!((r.welded, r.left_out, r.unreferenced), (0, 1, 0));
        assert!(!r.keep[0] && r.keep[1..].iter().all(|&k| k));
    }

    #[test]
    fn a_vertex_only_left_out_triangles_use_is_counted() {
        // One extra triangle (2, 9, 10): 9 on vertex 2, 10 a nanometre above it, which at the
        // triangle's own scale is not one point with 2 (its edges are all ≤ 1e-9 long).
        let (mut p, mut t) = grid([1.0, 1.0, 0.2]);
        p.push(p[2]);
        p.push([2.0, 0.0, 1e-9]);
        t.push([2, 9, 10]);
        let r = snapped_repair(&p, &t).unwrap();
        assert_eq!((r.welded, r.left_out), (1, 1));
        assert_eq!(r.vertex[9], r.vertex[2]);
        assert_eq!(r.unreferenced, 1, "vertex 10 is only in the left-out triangle");
        let lone = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
        let r = snapped_repair(&lone, &[[0, 1, 2]]).unwrap();
        assert_eq!((r.left_out, r.unreferenced), (1, 3));
    }

    #[test]
    fn bad_input_is_refused() {
        let (mut p, t) = grid([1.0, 1.0, 0.0]);
        assert!(matches!(snapped_repair(&p[..5], &t), Err(Error::IndexOutOfRange { .. })));
        p[4][2] = f64::NAN;
        assert!(matches!(snapped_repair(&p, &t), Err(Error::NonFiniteCoordinate { vertex: 4, .. })));
        assert!(matches!(snapped_repair(&p, &[]), Err(Error::EmptyMesh)));
    }
}
