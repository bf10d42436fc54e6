//! Geometric bisection (the coordinate bisection of George 1973; Miller–Teng–Thurston–Vavasis
//! 1997 in its simplest form): unknowns with 3D positions are split at the median of their
//! longest bounding-box axis. On the nearly flat pieces of surface that the small subproblems
//! of a mesh are, the plane cuts about as few edges as a graph bisection would, for the price
//! of one selection. Cost: O(n).

/// Reorders `set` so that the vertices below the median plane of its longest axis come first;
/// returns the number of them (half the set).
pub fn median_split(set: &mut [u32], points: &[[f64; 3]]) -> usize {
    let axis = longest_axis(set.iter().map(|&v| points[v as usize]));
    let mid = set.len() / 2;
    set.select_nth_unstable_by(mid, |&a, &b| points[a as usize][axis].total_cmp(&points[b as usize][axis]));
    mid
}

/// Axis (0, 1, 2) along which the points spread the most.
fn longest_axis(points: impl Iterator<Item = [f64; 3]>) -> usize {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for d in 0..3 {
            lo[d] = lo[d].min(p[d]);
            hi[d] = hi[d].max(p[d]);
        }
    }
    (0..3).max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b]))).unwrap_or(0)
}
