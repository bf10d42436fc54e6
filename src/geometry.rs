//! Per-triangle geometric quantities computed once per mesh and shared by every method:
//! areas, corner angles and corner cotangents. Angles are in radians; corner `k` of triangle
//! `t` sits at vertex `triangles[t][k]`.

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

/// Corner angles, cotangents and area of every triangle.
#[derive(Debug, Clone)]
pub struct TriangleGeometry {
    /// Area of each triangle.
    pub area: Vec<f64>,
    /// Interior angle at each corner (radians).
    pub angle: Vec<[f64; 3]>,
    /// Cotangent of the angle at each corner.
    pub cot: Vec<[f64; 3]>,
}

/// Angle and cotangent at the corner `p` between the edges towards `q` and `r`.
#[inline]
pub fn corner_angle_cot(p: [f64; 3], q: [f64; 3], r: [f64; 3]) -> (f64, f64) {
    let (e1, e2) = (sub(q, p), sub(r, p));
    let (c, s) = (dot(e1, e2), norm(cross(e1, e2)));
    (s.atan2(c), c / s)
}

impl TriangleGeometry {
    /// Computes areas, angles and cotangents of all triangles.
    pub fn new(points: &[[f64; 3]], triangles: &[[u32; 3]]) -> Self {
        let mut g = TriangleGeometry {
            area: Vec::with_capacity(triangles.len()),
            angle: Vec::with_capacity(triangles.len()),
            cot: Vec::with_capacity(triangles.len()),
        };
        for tri in triangles {
            let p = tri.map(|v| points[v as usize]);
            g.area.push(0.5 * norm(cross(sub(p[1], p[0]), sub(p[2], p[0]))));
            let mut angle = [0.0; 3];
            let mut cot = [0.0; 3];
            for k in 0..3 {
                (angle[k], cot[k]) = corner_angle_cot(p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
            }
            g.angle.push(angle);
            g.cot.push(cot);
        }
        g
    }
}
