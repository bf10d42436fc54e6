//! Per-triangle geometric quantities computed once per mesh and shared by every method:
//! areas, corner cotangents and (on demand) corner angles. Angles are in radians; corner `k` of triangle
//! `t` sits at vertex `triangles[t][k]`.

use rayon::prelude::*;

/// Difference `a − b`.
#[inline]
pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
/// Dot product.
#[inline]
pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
/// Cross product.
#[inline]
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// The z component of the cross product of two plane vectors (twice the signed area of the
/// triangle they span; positive when `b` is counter-clockwise from `a`).
#[inline]
pub fn cross2(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}
/// Squared length.
#[inline]
pub fn norm2(a: [f64; 3]) -> f64 {
    dot(a, a)
}
/// Length.
#[inline]
pub fn norm(a: [f64; 3]) -> f64 {
    norm2(a).sqrt()
}
/// Distance between two points.
#[inline]
pub fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    norm(sub(a, b))
}

/// Cotangents and area of every triangle. (Corner angles, an `atan2` each, which only some
/// methods need, are computed on demand by [`corner_angles`]; `TriMesh` caches them.)
#[derive(Debug, Clone)]
pub struct TriangleGeometry {
    /// Area of each triangle.
    pub area: Vec<f64>,
    /// Cotangent of the angle at each corner.
    pub cot: Vec<[f64; 3]>,
}

/// Interior angle (radians) at every corner of every triangle, in parallel.
pub fn corner_angles(points: &[[f64; 3]], triangles: &[[u32; 3]]) -> Vec<[f64; 3]> {
    crate::parallel::map_range(triangles.len(), |t| {
        let p = triangles[t].map(|v| points[v as usize]);
        std::array::from_fn(|k| corner_angle_cot(p[k], p[(k + 1) % 3], p[(k + 2) % 3]).0)
    })
}

/// Angle and cotangent at the corner `p` between the edges towards `q` and `r`.
#[inline]
pub fn corner_angle_cot(p: [f64; 3], q: [f64; 3], r: [f64; 3]) -> (f64, f64) {
    let (e1, e2) = (sub(q, p), sub(r, p));
    let (c, s) = (dot(e1, e2), norm(cross(e1, e2)));
    (s.atan2(c), c / s)
}

/// Cotangent at the corner `p` between the edges towards `q` and `r` (as [`corner_angle_cot`]).
#[inline]
pub fn corner_cot(p: [f64; 3], q: [f64; 3], r: [f64; 3]) -> f64 {
    let (e1, e2) = (sub(q, p), sub(r, p));
    dot(e1, e2) / norm(cross(e1, e2))
}

impl TriangleGeometry {
    /// Computes areas, angles and cotangents of all triangles (in parallel).
    pub fn new(points: &[[f64; 3]], triangles: &[[u32; 3]]) -> Self {
        Self::new_rejecting(points, triangles, |_| false).0
    }

    /// [`TriangleGeometry::new`], also returning the first triangle (in triangle order) whose
    /// relative area ([`relative_area`]) `reject` refuses, with that
    /// relative area: one pass over the vertices serves validation and geometry.
    pub fn new_rejecting(
        points: &[[f64; 3]],
        triangles: &[[u32; 3]],
        reject: impl Fn(f64) -> bool + Sync,
    ) -> (Self, Option<(usize, f64)>) {
        let m = triangles.len();
        let mut g = TriangleGeometry { area: vec![0.0; m], cot: vec![[0.0; 3]; m] };
        let fill = |(t, ((area, cot), tri)): (usize, ((&mut f64, &mut [f64; 3]), &[u32; 3]))| {
            let p = tri.map(|v| points[v as usize]);
            *area = 0.5 * norm(cross(sub(p[1], p[0]), sub(p[2], p[0])));
            for k in 0..3 {
                cot[k] = corner_cot(p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
            }
            let relative = relative_area(p[0], p[1], p[2]);
            reject(relative).then_some((t, relative))
        };
        // (On the calling thread for small meshes: see `crate::parallel`.)
        let rejected = if m < crate::parallel::SEQUENTIAL_BELOW {
            g.area
                .iter_mut()
                .zip(g.cot.iter_mut())
                .zip(triangles.iter())
                .enumerate()
                .filter_map(fill)
                .min_by_key(|&(t, _)| t)
        } else {
            (g.area.par_iter_mut().zip(g.cot.par_iter_mut()).zip(triangles.par_iter()))
                .with_min_len(crate::parallel::SEQUENTIAL_BELOW)
                .enumerate()
                .filter_map(fill)
                .min_by_key(|&(t, _)| t)
        };
        (g, rejected)
    }
}

/// Area of a triangle divided by its longest edge squared (0 for collinear points).
pub fn relative_area(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    let (ab, ac, bc) = (sub(b, a), sub(c, a), sub(c, b));
    let longest = norm2(ab).max(norm2(ac)).max(norm2(bc));
    if longest == 0.0 {
        return 0.0;
    }
    0.5 * norm(cross(ab, ac)) / longest
}
