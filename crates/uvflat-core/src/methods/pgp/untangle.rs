//! Local untangling of PGP's per-triangle parameterization (an addition to Ray et al. 2006):
//! (θ, φ) triangles that came out negatively oriented or nearly flat next to singular points
//! are made positive by moving the (θ, φ) of their vertices, keeping every integer of
//! Algorithm 1 (§3.1), hence every transition function (eq. 16), as it is.
//!
//! Algorithm 1 sets each corner from its vertex's phases, `c_T(v) = P^ρ (θ_v, φ_v) + 2π (s, t)`
//! with integer ρ, s, t ([`super::extraction`]; P(θ, φ) = (φ, −θ)). Near a singular point the
//! phases are poorly determined (‖U‖ → 0, the paper's Fig. 5) and a triangle's three corners
//! can come out clockwise: §3.2 counts it as singular, although nothing topological forces it
//! (only the open triangles and the vertices whose corner angles cannot sum to 2π are). Moving
//! a vertex's phases by Δ moves each of its corners by `P^ρ Δ` and changes no integer. The
//! paper's §3.4 re-parameterizes such places chart by chart and notes that fixing singular
//! triangles locally is possible but delicate; this is that local fix, for the orientation.
//!
//! With `A*_T = 2 ω² ‖K‖²_T area(T)` the doubled (θ, φ) area T would have if (θ, φ) followed
//! the field exactly, ‖K‖²_T the mean over T's corners of min(‖K‖², 1) — 1 for the paper's unit
//! field; below 1 where curl correction shrinks the field, so that the thresholds follow it; but
//! never above 1 where curl correction or [`super::density`] enlarge it, since stricter
//! thresholds there left more triangles negative (measured: man 2.14 → 2.40%, cow 2.52 → 2.71%
//! with the density and the mean of ‖K‖² itself), a
//! triangle that is not open is *tangled* when its doubled (θ, φ) area is below
//! [`TANGLED_AREA`] · A*_T (negative, flat or nearly so). In sweeps over the vertices of the
//! tangled triangles, each vertex moves to the point of its *kernel* nearest to the mean of
//! the moves that would make each of its triangles similar to its 3D triangle (the other two
//! corners fixed). The kernel is the convex set of Δ, |Δ_θ|, |Δ_φ| ≤ π (half a period, so a
//! corner stays in its period), where every incident triangle that is not open has a doubled
//! area of at least [`REPAIRED_AREA`] · A*_T — or its present area, if that is smaller and the
//! triangle not tangled: one half-plane per triangle. A vertex whose kernel is empty stays.
//!
//! A move makes every incident tangled triangle untangled and leaves every other one untangled
//! (REPAIRED_AREA > TANGLED_AREA), so each move removes at least one tangled triangle: the
//! sweeps end, after at most as many moves as there were tangled triangles. Open triangles
//! stay singular whatever their orientation and constrain nothing.
//!
//! Measured on the 15 closed meshes, with and without curl correction (README, "Periodic
//! Global Parameterization"): 32–100% of the negative triangles repaired (median 75%), the
//! singular triangles 1.54 → 0.93% (armadillo) or 13.9 → 7.4% (knight). What stays are the
//! open triangles and groups of negative triangles where one of the two functions is a
//! standing rather than a travelling wave (‖V‖ ≈ 0.5, ∇φ small and reversed, where a feature is
//! narrower than a period; cow 686 → 467): no vertex of those can move alone.
//!
//! Cost: O(valence²) per move, on the few vertices next to tangled triangles.

use super::extraction::CornerParameterization;
use super::singularities::signed_area2;
use crate::fields::frames::rotate_coords as rotate;
use crate::geometry::cross2;
use crate::geometry::{cross, dot, norm, sub};
use crate::TriMesh;
use std::f64::consts::PI;

/// Doubled (θ, φ) area below which a triangle is tangled, over the expected one `2 ω² ‖K‖² area`.
pub const TANGLED_AREA: f64 = 0.05;

/// Doubled (θ, φ) area a move gives a tangled triangle, over the expected one.
pub const REPAIRED_AREA: f64 = 0.1;

/// What the untangling did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct UntangleReport {
    /// Triangles with a non-positive (θ, φ) area that are not open, before.
    pub negative_before: usize,
    /// The same after.
    pub negative_after: usize,
    /// Vertices whose phases moved.
    pub moved_vertices: usize,
}

impl UntangleReport {
    /// The report of no untangling: the negative triangles of `param`, none moved.
    pub fn untouched(param: &CornerParameterization) -> Self {
        let n = negative_count(param);
        UntangleReport { negative_before: n, negative_after: n, moved_vertices: 0 }
    }
}

/// Untangles `param` in place (module comment) and turns the phases of `unknowns` by the same
/// amounts (norms kept), so that `param`'s corners are still `P^ρ (θ_v, φ_v) + 2π (s, t)` with
/// the same integers. `field` is the field K of the periodic solve (only its norms are used).
pub fn untangle(
    mesh: &TriMesh,
    param: &mut CornerParameterization,
    unknowns: &mut [[f64; 4]],
    field: &[[f64; 3]],
    omega: f64,
) -> UntangleReport {
    let expected = expected_areas(mesh, field, omega);
    let negative_before = negative_count(param);
    let mut moves = vec![[0.0f64; 2]; mesh.vertex_count()];
    let bound = tangled_triangles(param, &expected).len();
    for _ in 0..bound {
        let mut changed = false;
        for v in tangled_vertices(mesh, param, &expected) {
            if let Some(d) = kernel_move(mesh, param, &expected, v) {
                apply_move(mesh, param, v, d);
                moves[v as usize] = [moves[v as usize][0] + d[0], moves[v as usize][1] + d[1]];
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    for (x, m) in unknowns.iter_mut().zip(&moves) {
        *x = turn_phases(*x, *m);
    }
    UntangleReport {
        negative_before,
        negative_after: negative_count(param),
        moved_vertices: moves.iter().filter(|m| m[0] != 0.0 || m[1] != 0.0).count(),
    }
}

/// Triangles that are not open with a non-positive (θ, φ) area.
fn negative_count(param: &CornerParameterization) -> usize {
    (0..param.coords.len()).filter(|&t| !param.open[t] && signed_area2(&param.coords[t]) <= 0.0).count()
}

/// `2 ω² ‖K‖²_T area(T)` per triangle, ‖K‖²_T the mean of min(‖K‖², 1) over its corners
/// (module comment).
fn expected_areas(mesh: &TriMesh, field: &[[f64; 3]], omega: f64) -> Vec<f64> {
    let squared = |v: u32| dot(field[v as usize], field[v as usize]).min(1.0);
    mesh.triangles()
        .iter()
        .zip(&mesh.geometry().area)
        .map(|(t, a)| 2.0 * omega * omega * a * t.iter().map(|&v| squared(v)).sum::<f64>() / 3.0)
        .collect()
}

fn is_tangled(param: &CornerParameterization, expected: &[f64], t: usize) -> bool {
    !param.open[t] && signed_area2(&param.coords[t]) <= TANGLED_AREA * expected[t]
}

fn tangled_triangles(param: &CornerParameterization, expected: &[f64]) -> Vec<usize> {
    (0..param.coords.len()).filter(|&t| is_tangled(param, expected, t)).collect()
}

/// The vertices of the tangled triangles, ascending, without repeats.
fn tangled_vertices(mesh: &TriMesh, param: &CornerParameterization, expected: &[f64]) -> Vec<u32> {
    let mut v: Vec<u32> = tangled_triangles(param, expected).iter().flat_map(|&t| mesh.triangles()[t]).collect();
    v.sort_unstable();
    v.dedup();
    v
}

/// `P^-r d`.
fn rotate_back(r: u8, d: [f64; 2]) -> [f64; 2] {
    rotate((4 - r % 4) % 4, d)
}

/// Corners (t, k) at vertex v.
fn corners_at(mesh: &TriMesh, v: u32) -> impl Iterator<Item = (usize, usize)> + '_ {
    mesh.outgoing_halfedges(v).map(|h| ((h / 3) as usize, (h % 3) as usize))
}

/// Half-plane `g · Δ ≥ h` in the move Δ of corner (t, k)'s vertex that keeps triangle t's
/// doubled area at the required value (module comment); `None` when t is open or its side
/// opposite the corner has no length.
fn area_constraint(param: &CornerParameterization, expected: &[f64], t: usize, k: usize) -> Option<([f64; 2], f64)> {
    if param.open[t] {
        return None;
    }
    let q = &param.coords[t];
    let (c, a, b) = (q[k], q[(k + 1) % 3], q[(k + 2) % 3]);
    let n = [b[0] - a[0], b[1] - a[1]];
    if n == [0.0, 0.0] {
        return None;
    }
    // 2·area = n × (c + P^ρ Δ − a), linear in Δ.
    let r = param.rotation[t][k];
    let g = [cross2(n, rotate(r, [1.0, 0.0])), cross2(n, rotate(r, [0.0, 1.0]))];
    let now = cross2(n, [c[0] - a[0], c[1] - a[1]]);
    let repaired = REPAIRED_AREA * expected[t];
    let wanted = if is_tangled(param, expected, t) { repaired } else { now.min(repaired) };
    Some((g, wanted - now))
}

/// The move of v into its kernel (module comment), when v has a violated constraint and the
/// kernel is not empty.
fn kernel_move(mesh: &TriMesh, param: &CornerParameterization, expected: &[f64], v: u32) -> Option<[f64; 2]> {
    let constraints: Vec<([f64; 2], f64)> =
        corners_at(mesh, v).filter_map(|(t, k)| area_constraint(param, expected, t, k)).collect();
    if constraints.iter().all(|&(_, h)| h <= 0.0) {
        return None;
    }
    let mut polygon = vec![[-PI, -PI], [PI, -PI], [PI, PI], [-PI, PI]];
    for &(g, h) in &constraints {
        polygon = clip(&polygon, g, h);
        if polygon.len() < 3 {
            return None;
        }
    }
    Some(nearest_point(&polygon, similarity_target(mesh, param, v)))
}

/// The part of convex `polygon` where `g · x ≥ h` (Sutherland–Hodgman with one line).
fn clip(polygon: &[[f64; 2]], g: [f64; 2], h: f64) -> Vec<[f64; 2]> {
    let side = |p: [f64; 2]| g[0] * p[0] + g[1] * p[1] - h;
    let mut out = Vec::with_capacity(polygon.len() + 1);
    for i in 0..polygon.len() {
        let (p, q) = (polygon[i], polygon[(i + 1) % polygon.len()]);
        let (sp, sq) = (side(p), side(q));
        if sp >= 0.0 {
            out.push(p);
        }
        if (sp >= 0.0) != (sq >= 0.0) {
            let s = sp / (sp - sq);
            out.push([p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1])]);
        }
    }
    out
}

/// The point of convex `polygon` (counter-clockwise, as [`clip`] keeps it) nearest to `x`.
fn nearest_point(polygon: &[[f64; 2]], x: [f64; 2]) -> [f64; 2] {
    let n = polygon.len();
    let edge = |i: usize| (polygon[i], polygon[(i + 1) % n]);
    let inside = (0..n).all(|i| {
        let (p, q) = edge(i);
        cross2([q[0] - p[0], q[1] - p[1]], [x[0] - p[0], x[1] - p[1]]) >= 0.0
    });
    if inside {
        return x;
    }
    let dist2 = |a: [f64; 2]| (a[0] - x[0]).powi(2) + (a[1] - x[1]).powi(2);
    (0..n)
        .map(|i| {
            let (p, q) = edge(i);
            nearest_on_segment(p, q, x)
        })
        .min_by(|a, b| dist2(*a).total_cmp(&dist2(*b)))
        .unwrap_or(x)
}

fn nearest_on_segment(p: [f64; 2], q: [f64; 2], x: [f64; 2]) -> [f64; 2] {
    let d = [q[0] - p[0], q[1] - p[1]];
    let len2 = d[0] * d[0] + d[1] * d[1];
    let s = if len2 > 0.0 { (((x[0] - p[0]) * d[0] + (x[1] - p[1]) * d[1]) / len2).clamp(0.0, 1.0) } else { 0.0 };
    [p[0] + s * d[0], p[1] + s * d[1]]
}

/// The mean, over v's triangles that are not open, of the move making the (θ, φ) triangle
/// similar to the 3D one with its other two corners fixed.
fn similarity_target(mesh: &TriMesh, param: &CornerParameterization, v: u32) -> [f64; 2] {
    let (mut sum, mut count) = ([0.0, 0.0], 0.0);
    for (t, k) in corners_at(mesh, v).filter(|&(t, _)| !param.open[t]) {
        let q = &param.coords[t];
        let (c, a, b) = (q[k], q[(k + 1) % 3], q[(k + 2) % 3]);
        let z = shape_ratio(mesh, t, k);
        let ab = [b[0] - a[0], b[1] - a[1]];
        let similar = [a[0] + ab[0] * z[0] - ab[1] * z[1], a[1] + ab[0] * z[1] + ab[1] * z[0]];
        let d = rotate_back(param.rotation[t][k], [similar[0] - c[0], similar[1] - c[1]]);
        sum = [sum[0] + d[0], sum[1] + d[1]];
        count += 1.0;
    }
    if count == 0.0 {
        return [0.0, 0.0];
    }
    [sum[0] / count, sum[1] / count]
}

/// `(p_k − p_a) / (p_b − p_a)` as a complex number in the plane of triangle t (a, b its next
/// corners), with a non-negative imaginary part.
fn shape_ratio(mesh: &TriMesh, t: usize, k: usize) -> [f64; 2] {
    let tri = mesh.triangles()[t];
    let p = |i: usize| mesh.points()[tri[i % 3] as usize];
    let (c, a, b) = (p(k), p(k + 1), p(k + 2));
    let (ab, ac) = (sub(b, a), sub(c, a));
    let l2 = dot(ab, ab);
    [dot(ac, ab) / l2, norm(cross(ab, ac)) / l2]
}

/// Moves v's corners by `P^ρ d`.
pub(super) fn apply_move(mesh: &TriMesh, param: &mut CornerParameterization, v: u32, d: [f64; 2]) {
    let corners: Vec<(usize, usize)> = corners_at(mesh, v).collect();
    for (t, k) in corners {
        let m = rotate(param.rotation[t][k], d);
        param.coords[t][k] = [param.coords[t][k][0] + m[0], param.coords[t][k][1] + m[1]];
    }
}

/// X with θ turned by m[0] and φ by m[1], norms kept.
pub(super) fn turn_phases(x: [f64; 4], m: [f64; 2]) -> [f64; 4] {
    let turn = |c: f64, s: f64, a: f64| (c * a.cos() - s * a.sin(), c * a.sin() + s * a.cos());
    let (u0, u1) = turn(x[0], x[1], m[0]);
    let (v0, v1) = turn(x[2], x[3], m[1]);
    [u0, u1, v0, v1]
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// An n × n grid of unit squares in the plane, split along one diagonal, with the
    /// isometric parameterization (θ, φ) = (x, y) at ω = 1 and vertex `v` given rotation `r`.
    pub(in crate::methods::pgp) fn grid(n: u32, v: u32, r: u8) -> (TriMesh, CornerParameterization, Vec<[f64; 4]>) {
        let id = |i: u32, j: u32| j * (n + 1) + i;
        let mut positions = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                positions.extend([i as f64, j as f64, 0.0]);
            }
        }
        let mut tris = Vec::new();
        for j in 0..n {
            for i in 0..n {
                tris.extend([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        let mesh = TriMesh::new(&positions, &tris).unwrap();
        let xy = |w: u32| [mesh.points()[w as usize][0], mesh.points()[w as usize][1]];
        let rotation: Vec<[u8; 3]> = mesh.triangles().iter().map(|t| t.map(|w| if w == v { r } else { 0 })).collect();
        let coords = mesh.triangles().iter().map(|t| t.map(xy)).collect();
        let count = mesh.triangle_count();
        let param =
            CornerParameterization { coords, rotation, shift: vec![[[0; 2]; 3]; count], open: vec![false; count] };
        // Phases whose rotated angles are the corners: P^r p = (x, y).
        let unknowns = (0..mesh.vertex_count() as u32)
            .map(|w| {
                let p = if w == v { rotate_back(r, xy(w)) } else { xy(w) };
                [p[0].cos(), p[0].sin(), p[1].cos(), p[1].sin()]
            })
            .collect();
        (mesh, param, unknowns)
    }

    #[test]
    fn a_vertex_pushed_across_its_neighbours_is_moved_back_into_its_kernel() {
        for r in 0..4u8 {
            let (n, v) = (4, 12); // the middle vertex (2, 2)
            let (mesh, mut param, mut unknowns) = grid(n, v, r);
            // Push v's phases by d (in its own frame): its corners move by P^r d, over its ring.
            let d = [1.6, 1.4];
            apply_move(&mesh, &mut param, v, d);
            unknowns[v as usize] = turn_phases(unknowns[v as usize], d);
            let before = param.clone();
            let report = untangle(&mesh, &mut param, &mut unknowns, &unit_field(&mesh), 1.0);
            assert!(report.negative_before >= 2 && report.negative_after == 0, "r = {r}: {report:?}");
            assert!(report.moved_vertices >= 1, "r = {r}");
            assert_eq!((param.rotation.clone(), param.shift.clone()), (before.rotation, before.shift));
            // Every triangle is positive with at least REPAIRED_AREA of its isometric area (2·½).
            assert!(param.coords.iter().all(|q| signed_area2(q) >= REPAIRED_AREA - 1e-12), "r = {r}");
            // Every corner is still its vertex's rotated phases (plus whole periods).
            for (t, tri) in mesh.triangles().iter().enumerate() {
                for (k, &w) in tri.iter().enumerate() {
                    let x = unknowns[w as usize];
                    let want = rotate(param.rotation[t][k], [x[1].atan2(x[0]), x[3].atan2(x[2])]);
                    for (got, want) in param.coords[t][k].iter().zip(want) {
                        let turns = (got - want) / std::f64::consts::TAU;
                        assert!((turns - turns.round()).abs() < 1e-12, "r = {r}: corner {t}/{k}");
                    }
                }
            }
        }
    }

    fn unit_field(mesh: &TriMesh) -> Vec<[f64; 3]> {
        vec![[1.0, 0.0, 0.0]; mesh.vertex_count()]
    }

    #[test]
    fn the_expected_area_follows_the_field_norm_and_omega() {
        let (mesh, _, _) = grid(2, 0, 0);
        let unit = expected_areas(&mesh, &unit_field(&mesh), 1.0);
        // A unit field: 2 ω² area = 2 · ½ for every half unit square.
        assert!(unit.iter().all(|&a| (a - 1.0).abs() < 1e-12), "{unit:?}");
        // K of norm ½ at vertex 0: (¼ + 1 + 1) / 3 = ¾ of the area; of norm 2 at vertex 8: capped at 1.
        let mut field = unit_field(&mesh);
        field[0] = [0.0, 0.5, 0.0];
        field[8] = [0.0, 2.0, 0.0];
        let scaled = expected_areas(&mesh, &field, 3.0);
        for (t, tri) in mesh.triangles().iter().enumerate() {
            let want = if tri.contains(&0) { 9.0 * 0.75 } else { 9.0 };
            assert!((scaled[t] - want).abs() < 1e-12, "triangle {t}: {} != {want}", scaled[t]);
        }
    }

    #[test]
    fn open_triangles_and_untangled_ones_are_left_alone() {
        let (mesh, mut param, mut unknowns) = grid(3, 5, 0);
        let before = param.clone();
        let report = untangle(&mesh, &mut param, &mut unknowns, &unit_field(&mesh), 1.0);
        assert_eq!(report, UntangleReport::default());
        assert_eq!(param, before);
        // A flipped triangle that is open is singular whatever its orientation: not repaired.
        param.coords[0].swap(1, 2);
        param.open[0] = true;
        let report = untangle(&mesh, &mut param, &mut unknowns, &unit_field(&mesh), 1.0);
        assert_eq!(report.moved_vertices, 0);
        assert!(signed_area2(&param.coords[0]) < 0.0);
    }
}
