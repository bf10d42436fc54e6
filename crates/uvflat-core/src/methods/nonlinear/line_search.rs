//! A line search that never lets a triangle flip (Smith & Schaefer 2015, §4 "Line search":
//! bounding the step by the first time any triangle's signed area reaches zero), followed by
//! Armijo backtracking (Nocedal & Wright, Alg. 3.1).
//!
//! Moving every UV along a direction `d`, the doubled signed area of a triangle is a quadratic
//! in the step `t`: `2A(t) = (e1 + t f1) × (e2 + t f2) = c + b t + a t²` with `e_i` the current
//! edge vectors and `f_i` their change. With `c > 0` (the triangle is positively oriented now),
//! the smallest positive root over all triangles is the largest step keeping every triangle
//! positively oriented. The search starts at `min(1, 0.8 · t_max)` and halves until the energy
//! decreases enough; since every energy evaluates a flipped triangle to +∞, an accepted step is
//! flip-free by construction as well. A bijective (locally injective) start therefore stays
//! locally injective, and the energy decreases monotonically.

use crate::geometry::cross2;
use rayon::prelude::*;

/// Armijo sufficient-decrease constant.
const ARMIJO_C1: f64 = 1e-4;
/// Fraction of the maximal flip-free step tried first (Smith & Schaefer 2015).
pub const MAX_STEP_FRACTION: f64 = 0.8;
/// Halvings before the search gives up.
const MAX_HALVINGS: usize = 60;

/// Smallest positive root of `a t² + b t + c` for `c > 0`, or +∞.
fn first_positive_root(a: f64, b: f64, c: f64) -> f64 {
    let scale = a.abs().max(b.abs()).max(c.abs());
    if scale == 0.0 {
        return f64::INFINITY;
    }
    if a.abs() <= 1e-14 * scale {
        return if b < 0.0 { -c / b } else { f64::INFINITY };
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return f64::INFINITY;
    }
    // Stable roots: q = −(b + sign(b)√disc)/2, roots q/a and c/q.
    let q = -0.5 * (b + b.signum() * disc.sqrt());
    let mut best = f64::INFINITY;
    for r in [q / a, if q != 0.0 { c / q } else { f64::INFINITY }] {
        if r > 0.0 && r < best {
            best = r;
        }
    }
    best
}

/// Largest `t` such that every triangle of `uv + s·d` keeps a positive signed area for all
/// `s < t` (+∞ when no triangle ever degenerates along `d`).
pub fn max_flip_free_step(tris: &[[u32; 3]], uv: &[[f64; 2]], d: &[[f64; 2]]) -> f64 {
    max_step_above(tris, uv, d, None)
}

/// Largest `t` such that every triangle `i` of `uv + s·d` keeps its doubled signed area above
/// `floor[i]` (≥ 0; 0 for every triangle without `floor`) for all `s < t`: the same quadratic
/// as [`max_flip_free_step`] with its constant term lowered by the floor.
pub fn max_step_above(tris: &[[u32; 3]], uv: &[[f64; 2]], d: &[[f64; 2]], floor: Option<&[f64]>) -> f64 {
    tris.par_iter()
        .enumerate()
        .with_min_len(4096)
        .map(|(index, t)| {
            let [i, j, k] = t.map(|v| v as usize);
            let e1 = [uv[j][0] - uv[i][0], uv[j][1] - uv[i][1]];
            let e2 = [uv[k][0] - uv[i][0], uv[k][1] - uv[i][1]];
            let f1 = [d[j][0] - d[i][0], d[j][1] - d[i][1]];
            let f2 = [d[k][0] - d[i][0], d[k][1] - d[i][1]];
            let c = cross2(e1, e2) - floor.map_or(0.0, |f| f[index]);
            if !(c > 0.0) {
                return 0.0;
            }
            first_positive_root(cross2(f1, f2), cross2(e1, f2) + cross2(f1, e2), c)
        })
        .reduce(|| f64::INFINITY, f64::min)
}

/// `x + t·d`.
pub fn step(x: &[[f64; 2]], d: &[[f64; 2]], t: f64) -> Vec<[f64; 2]> {
    x.par_iter().zip(d.par_iter()).with_min_len(4096).map(|(a, b)| [a[0] + t * b[0], a[1] + t * b[1]]).collect()
}

/// Directional derivative `∇E · d`.
pub fn slope(grad: &[[f64; 2]], d: &[[f64; 2]]) -> f64 {
    grad.iter().zip(d).map(|(g, d)| g[0] * d[0] + g[1] * d[1]).sum()
}

/// Outcome of an accepted step.
pub struct Accepted {
    /// The new map.
    pub uv: Vec<[f64; 2]>,
    /// Its energy.
    pub energy: f64,
}

/// Flip-free Armijo line search along `d` from `x` (energy `e0`, directional derivative
/// `slope`, negative for a descent direction). `energy` must return +∞ for a map with a flipped
/// triangle. Returns `None` when no step decreases the energy (the method has converged to
/// rounding).
pub fn flip_free_armijo(
    tris: &[[u32; 3]],
    x: &[[f64; 2]],
    d: &[[f64; 2]],
    e0: f64,
    slope: f64,
    energy: impl Fn(&[[f64; 2]]) -> f64,
) -> Option<Accepted> {
    armijo_above(tris, &Search { x, d, e0, slope }, None, energy)
}

/// Where a line search starts: the map `x`, the direction `d`, the energy `e0` at `x` and the
/// directional derivative `slope` (negative for a descent direction).
pub struct Search<'a> {
    pub x: &'a [[f64; 2]],
    pub d: &'a [[f64; 2]],
    pub e0: f64,
    pub slope: f64,
}

/// [`flip_free_armijo`] whose steps also keep every triangle's doubled signed area above
/// `floor` (see [`max_step_above`]).
pub fn armijo_above(
    tris: &[[u32; 3]],
    search: &Search,
    floor: Option<&[f64]>,
    energy: impl Fn(&[[f64; 2]]) -> f64,
) -> Option<Accepted> {
    let &Search { x, d, e0, slope } = search;
    let t_max = max_step_above(tris, x, d, floor);
    let mut t = (MAX_STEP_FRACTION * t_max).min(1.0);
    if !(t > 0.0) {
        return None;
    }
    for _ in 0..MAX_HALVINGS {
        let uv = step(x, d, t);
        let e = energy(&uv);
        let enough = if slope < 0.0 { e <= e0 + ARMIJO_C1 * t * slope } else { e < e0 };
        if e.is_finite() && enough && e < e0 {
            return Some(Accepted { uv, energy: e });
        }
        t *= 0.5;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn max_step_is_where_the_triangle_degenerates() {
        let tris = [[0, 1, 2]];
        let uv = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        // Moving the apex straight down: the area vanishes at t = 1/2.
        let d = [[0.0, 0.0], [0.0, 0.0], [0.0, -2.0]];
        assert!((max_flip_free_step(&tris, &uv, &d) - 0.5).abs() < 1e-15);
        // Moving it sideways never degenerates.
        let d = [[0.0, 0.0], [0.0, 0.0], [5.0, 0.0]];
        assert_eq!(max_flip_free_step(&tris, &uv, &d), f64::INFINITY);
        // A quadratic case: swapping two corners passes through zero area first at t = 1/2.
        let d = [[0.0, 0.0], [-1.0, 1.0], [1.0, -1.0]];
        assert!((max_flip_free_step(&tris, &uv, &d) - 0.5).abs() < 1e-15);
    }

    #[test]
    fn a_floor_stops_the_step_where_the_area_reaches_it() {
        let tris = [[0, 1, 2]];
        let uv = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        // Doubled area 1 − 2t along d; a floor of 0.5 is reached at t = 1/4.
        let d = [[0.0, 0.0], [0.0, 0.0], [0.0, -2.0]];
        assert!((max_step_above(&tris, &uv, &d, Some(&[0.5])) - 0.25).abs() < 1e-15);
        assert!((max_step_above(&tris, &uv, &d, Some(&[0.0])) - 0.5).abs() < 1e-15);
        // Already at the floor: no step at all.
        assert_eq!(max_step_above(&tris, &uv, &d, Some(&[1.0])), 0.0);
    }

    #[test]
    fn armijo_never_accepts_a_flip() {
        let tris = [[0, 1, 2]];
        let uv = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        let d = [[0.0, 0.0], [0.0, 0.0], [0.0, -4.0]];
        // An "energy" that rewards moving down (so Armijo alone would cross zero area).
        let energy = |x: &[[f64; 2]]| {
            let a = (x[1][0] - x[0][0]) * (x[2][1] - x[0][1]) - (x[1][1] - x[0][1]) * (x[2][0] - x[0][0]);
            if a > 0.0 {
                x[2][1]
            } else {
                f64::INFINITY
            }
        };
        let out = flip_free_armijo(&tris, &uv, &d, 1.0, -4.0, energy).expect("a step");
        // The step length, read from the moved vertex (uv₂ = (0, 1 − 4t)).
        let t = (1.0 - out.uv[2][1]) / 4.0;
        assert!(t <= 0.8 * 0.25 + 1e-15 && out.uv[2][1] > 0.0);
    }
}
