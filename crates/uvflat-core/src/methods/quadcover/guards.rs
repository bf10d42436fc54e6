//! QuadCover, rounding guards (not in the course notes): triangles that the integer unknowns
//! alone can flatten or fold.
//!
//! A corner of the cut mesh is *fixed* when its (u, v) row holds lattice scalars only: a cone
//! (its position is a function of the gaps, §8.3.1, or an integer unknown itself with the cones
//! on the grid) or the vertex the gauge puts at the origin. Where two fixed corners share a
//! triangle, the rounding alone decides whether they land on the same grid point — then the
//! triangle is flat whatever the real unknowns do, and neither stiffening nor the untangling
//! can open it (two cones rounded onto one point were 150 of the 189 folds left over the 15
//! meshes of the table in docs/methods/quadcover.md). With three fixed corners it decides the orientation too.
//!
//! The greedy rounding ([`super::integration`], the order of Bommes, Zimmer & Kobbelt 2009 §4)
//! consults the guards: when the unknowns it rounds complete a guard's dependencies and the
//! nearest integers would flatten or fold that triangle, the one of them whose other integer
//! raises the reduced energy least is rounded the other way (only while that lowers the number
//! of violated guards). Forcing two cones a cell apart distorts the map around them, so the
//! guarded rounding is kept only when it is expected to fold less after the untangling than
//! the plain one. Over the 15 meshes: 189 → 104 folds left, 150 → 26 flat whatever the
//! vertices. Merging the coinciding cones into one cone of the summed index instead (the
//! field's quarters moved onto one vertex as in [`super::cone_pairs`], everything solved again)
//! was measured and not kept: over cow, knight, eight and fertility it left more folds (76
//! against 58 with an earlier form of the guards), and new coincidences appeared after the
//! second solve.

use super::covering::Covering;
use crate::mesh::cut::Cut;

/// A fixed corner: its u and v rows over the free lattice scalars.
pub type FixedCorner = [Vec<(u32, f64)>; 2];

/// A triangle's fixed corners as rows over the free lattice scalars.
pub struct Guard {
    /// The fixed corners in the triangle's order.
    corners: Vec<FixedCorner>,
    /// The free lattice scalars the fixed corners depend on.
    pub depends: Vec<u32>,
}

/// The guards of every triangle with at least two fixed corners whose positions depend on
/// integer unknowns only (a real free unknown is re-optimized continuously and never lands
/// exactly on another corner).
pub fn rounding_guards(cut: &Cut, covering: &Covering) -> Vec<Guard> {
    cut.triangles
        .iter()
        .filter_map(|tri| {
            let corners: Vec<FixedCorner> = tri
                .iter()
                .filter(|&&c| is_fixed(covering, c))
                .map(|&c| covering.rows[c as usize].each_ref().map(|row| over_free_lattice(covering, row)))
                .collect();
            (corners.len() >= 2).then(|| Guard::new(corners))
        })
        .filter(|guard| guard.depends.iter().all(|&j| covering.free_integer[j as usize]))
        .collect()
}

/// Whether the cut-mesh vertex `c` is fixed: its (u, v) rows hold lattice scalars only.
pub fn is_fixed(covering: &Covering, c: u32) -> bool {
    let nv = covering.vertex_unknowns as u32;
    covering.rows[c as usize].iter().flatten().all(|&(k, _)| k >= nv)
}

/// A row over the real unknowns and lattice scalars (lattice scalars only) rewritten over the
/// free lattice scalars.
fn over_free_lattice(covering: &Covering, row: &[(u32, f64)]) -> Vec<(u32, f64)> {
    let nv = covering.vertex_unknowns;
    let mut out: Vec<(u32, f64)> = Vec::new();
    for &(k, x) in row {
        for &(j, y) in &covering.lattice[k as usize - nv] {
            match out.iter_mut().find(|(i, _)| *i == j) {
                Some(entry) => entry.1 += x * y,
                None => out.push((j, x * y)),
            }
        }
    }
    out.retain(|&(_, x)| x != 0.0);
    out
}

impl Guard {
    /// A guard over the fixed `corners` of a triangle, in its order.
    pub fn new(corners: Vec<FixedCorner>) -> Guard {
        let mut depends: Vec<u32> = corners.iter().flat_map(|rows| rows.iter().flatten().map(|&(j, _)| j)).collect();
        depends.sort_unstable();
        depends.dedup();
        Guard { corners, depends }
    }

    /// Whether the free lattice scalars `w` (integers wherever the guard depends) flatten the
    /// triangle (two fixed corners on one point) or, with three fixed corners, fold it.
    pub fn violated(&self, w: impl Fn(u32) -> f64) -> bool {
        let points: Vec<[f64; 2]> = self
            .corners
            .iter()
            .map(|rows| rows.each_ref().map(|row| row.iter().map(|&(j, x)| x * w(j)).sum()))
            .collect();
        let n = points.len();
        if (0..n).any(|i| (i + 1..n).any(|j| same_point(points[i], points[j]))) {
            return true;
        }
        n == 3 && {
            let [a, b, c] = [points[0], points[1], points[2]];
            (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) <= 0.0
        }
    }
}

/// Whether two (u, v) points that the lattice places are the same point (up to round-off).
pub fn same_point(p: [f64; 2], q: [f64; 2]) -> bool {
    (p[0] - q[0]).abs() + (p[1] - q[1]).abs() <= 1e-9 * (1.0 + p[0].abs() + p[1].abs())
}

/// The other integer next to `x`: the second nearest.
pub fn other_integer(x: f64) -> f64 {
    let r = x.round();
    if x >= r {
        r + 1.0
    } else {
        r - 1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coincident_fixed_corners_violate_and_distinct_ones_do_not() {
        // Corner 0 at (w0, w1), corner 1 at (w2, w3).
        let g = Guard::new(vec![[vec![(0, 1.0)], vec![(1, 1.0)]], [vec![(2, 1.0)], vec![(3, 1.0)]]]);
        assert!(g.violated(|j| [1.0, 2.0, 1.0, 2.0][j as usize]));
        assert!(!g.violated(|j| [1.0, 2.0, 1.0, 3.0][j as usize]));
    }

    #[test]
    fn three_fixed_corners_clockwise_violate() {
        let g = Guard::new(vec![[vec![], vec![]], [vec![(0, 1.0)], vec![(1, 1.0)]], [vec![(2, 1.0)], vec![(3, 1.0)]]]);
        assert!(!g.violated(|j| [1.0, 0.0, 0.0, 1.0][j as usize]));
        assert!(g.violated(|j| [0.0, 1.0, 1.0, 0.0][j as usize]));
    }

    #[test]
    fn the_other_integer_is_the_second_nearest() {
        assert_eq!(other_integer(2.3), 3.0);
        assert_eq!(other_integer(2.7), 2.0);
        assert_eq!(other_integer(-0.2), -1.0);
        assert_eq!(other_integer(4.0), 5.0);
    }
}
