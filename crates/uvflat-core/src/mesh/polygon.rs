//! Triangulation of one polygon (a face of an OBJ file or of a polygon mesh given to the C
//! ABI): the fan from its first corner, unless a fan triangle would be flat or turn against the
//! polygon (a concave polygon seen from a corner that does not see all others, or collinear
//! corners), in which case the polygon is cut by ear clipping in the plane of its Newell normal
//! (Meisters 1975, "Polygons have ears": every simple polygon with more than three corners has
//! two non-overlapping ears). Cost: O(n) for a convex polygon, O(n³) worst case otherwise.

/// The triangles of the polygon `ring` as corner indices: the fan `(0, k, k + 1)` unless it folds,
/// then ear clipping; the fan when ear clipping finds no ear (a self-intersecting polygon).
pub fn triangulate(ring: &[[f64; 3]]) -> Vec<[usize; 3]> {
    ears_where_the_fan_folds(ring).unwrap_or_else(|| (1..ring.len().saturating_sub(1)).map(|k| [0, k, k + 1]).collect())
}

/// The ear-clipping triangles of `ring` when its fan would hold a flat triangle or one turned
/// against the polygon, None when the fan is fine or no ear is found.
pub(crate) fn ears_where_the_fan_folds(ring: &[[f64; 3]]) -> Option<Vec<[usize; 3]>> {
    if ring.len() < 4 {
        return None;
    }
    let normal = newell_normal(ring);
    if (1..ring.len() - 1).all(|k| turn(ring, normal, [0, k, k + 1]) > 0.0) {
        return None;
    }
    ear_clipping(ring, normal)
}

/// Twice the area of triangle `tri` of `ring` projected on the plane of `normal` (times
/// |normal|): positive when it turns the polygon's way.
fn turn(ring: &[[f64; 3]], normal: [f64; 3], tri: [usize; 3]) -> f64 {
    use crate::geometry::{cross, dot, sub};
    let [a, b, c] = tri.map(|k| ring[k]);
    dot(cross(sub(b, a), sub(c, a)), normal)
}

/// The polygon's Newell normal (twice its vector area).
fn newell_normal(ring: &[[f64; 3]]) -> [f64; 3] {
    let mut n = [0.0; 3];
    for k in 0..ring.len() {
        let (p, q) = (ring[k], ring[(k + 1) % ring.len()]);
        n[0] += (p[1] - q[1]) * (p[2] + q[2]);
        n[1] += (p[2] - q[2]) * (p[0] + q[0]);
        n[2] += (p[0] - q[0]) * (p[1] + q[1]);
    }
    n
}

/// Ear clipping of a simple polygon in the plane of its Newell `normal` (O(n²) per ear): an
/// ear is a corner that turns the polygon's way with no other corner inside or on its
/// triangle. None when some step finds no ear (a self-intersecting polygon, or all corners
/// collinear): the caller keeps the fan.
fn ear_clipping(ring: &[[f64; 3]], normal: [f64; 3]) -> Option<Vec<[usize; 3]>> {
    let mut left: Vec<usize> = (0..ring.len()).collect();
    let mut out = Vec::with_capacity(ring.len() - 2);
    while left.len() > 3 {
        let m = left.len();
        let ear = (0..m).find(|&i| {
            let tri = [left[(i + m - 1) % m], left[i], left[(i + 1) % m]];
            turn(ring, normal, tri) > 0.0
                && left.iter().filter(|v| !tri.contains(v)).all(|&v| !inside_or_on(ring, normal, tri, v))
        })?;
        out.push([left[(ear + m - 1) % m], left[ear], left[(ear + 1) % m]]);
        left.remove(ear);
    }
    let last = [left[0], left[1], left[2]];
    (turn(ring, normal, last) > 0.0).then(|| {
        out.push(last);
        out
    })
}

/// Whether corner `v` of `ring` lies inside or on triangle `tri` (in the plane of `normal`).
fn inside_or_on(ring: &[[f64; 3]], normal: [f64; 3], tri: [usize; 3], v: usize) -> bool {
    (0..3).all(|k| turn(ring, normal, [tri[k], tri[(k + 1) % 3], v]) >= 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area_2d(ring: &[[f64; 3]], tri: [usize; 3]) -> f64 {
        let [a, b, c] = tri.map(|k| ring[k]);
        0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]))
    }

    #[test]
    fn a_convex_polygon_keeps_its_fan() {
        let ring: Vec<[f64; 3]> = (0..6)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / 6.0;
                [a.cos(), a.sin(), 0.0]
            })
            .collect();
        assert_eq!(triangulate(&ring), vec![[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 5]]);
    }

    #[test]
    fn a_concave_polygon_is_cut_into_ears_that_tile_it() {
        // An L whose corner 0 does not see the corner (0, 1) past the reflex corner (1, 1): the
        // fan from corner 0 would fold.
        let ring =
            [[2.0, 2.0, 0.0], [1.0, 2.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
        let fan_folds = (1..ring.len() - 1).any(|k| area_2d(&ring, [0, k, k + 1]) <= 0.0);
        assert!(fan_folds, "the test polygon must be one whose fan folds");
        let tris = triangulate(&ring);
        assert_eq!(tris.len(), ring.len() - 2);
        assert!(tris.iter().all(|&t| area_2d(&ring, t) > 0.0), "{tris:?}");
        let total: f64 = tris.iter().map(|&t| area_2d(&ring, t)).sum();
        assert!((total - 3.0).abs() < 1e-12, "the ears cover the L's area 3, not {total}");
    }
}
