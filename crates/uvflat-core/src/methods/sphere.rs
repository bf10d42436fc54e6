//! Spherical parameterizations of closed genus-0 meshes (Hormann–Lévy–Sheffer course notes
//! 2008, §6.1): one unit-sphere position per vertex, and the number of flipped spherical
//! triangles.
//!
//! A spherical triangle (p0, p1, p2) is *flipped* when `det[p0, p1, p2] ≤ 0`: for a
//! counter-clockwise (outward-oriented) triangle smaller than a hemisphere the determinant is
//! positive. The overall orientation is normalised first (if the determinants sum to a negative
//! value — an inward-oriented input — the map is mirrored), so the count does not depend on
//! the input's orientation convention.
//!
//! Methods:
//! - [`SphereMethod::GaussSeidel`] — §6.1's iterative extension of barycentric maps (Alexa
//!   2000; Kobbelt et al. 1999): start from the centred, normalised input positions, then sweep
//!   the vertices moving each one to the (uniform) barycentre of its neighbours projected onto
//!   the sphere, re-centring after every sweep. No guarantee: Saba et al. 2005 prove the
//!   iteration eventually collapses; flips are reported.
//! - [`SphereMethod::Stereographic`] — Haker et al. 2000: remove one triangle, map the rest
//!   (a disk whose boundary is that triangle) to the plane by the cotangent-Laplacian
//!   (discrete harmonic, Haker's discretisation of the conformal map) with the triangle fixed
//!   on an equilateral triangle, then inverse stereographic projection
//!   `z ↦ (2x, 2y, 1 − |z|²) / (1 + |z|²)` after centring and scaling so that half the
//!   vertices fall in each hemisphere. Flips can occur (course notes §6.1: a straight planar
//!   triangle does not map to the spherical triangle on its vertices); they are reported.
//! - [`SphereMethod::TutteGnomonic`] — a provably flip-free embedding:
//!   1. remove the star of one vertex s; the rest is a disk whose boundary is the link of s;
//!   2. Tutte/Floater embedding with positive mean value weights (Floater 2003) and the link on
//!      a regular polygon centred at the origin, counter-clockwise: every planar triangle is
//!      positively oriented (Tutte–Floater theorem, course notes §2.2);
//!   3. gnomonic (central) lift `(u, v) ↦ (u, v, 1)/|(u, v, 1)|`: for points of the plane
//!      z = 1, `det[p0, p1, p2] = 2·area(q0, q1, q2) / (|p0||p1||p2|)`, so every lifted triangle
//!      keeps its positive orientation (central projection maps lines to great circles);
//!   4. s goes to the south pole (0, 0, −1): for consecutive link vertices l_i → l_{i+1}
//!      (counter-clockwise around the origin, less than π apart), the fan triangle
//!      (s, l_{i+1}, l_i) has `det = x_i·y_{i+1} − x_{i+1}·y_i > 0` (up to positive factors);
//!   5. flip-guarded relaxation (in the spirit of Praun & Hoppe 2003's guarded vertex
//!      relaxation): Gauss–Seidel sweeps moving each vertex towards the projected barycentre of
//!      its neighbours, a move being kept only if every triangle around the vertex stays
//!      positively oriented and not nearly degenerate (relative to its size; trying the full
//!      step, then halves). Along the straight segment
//!      between the old and new positions each determinant is linear, so positive at both ends
//!      means positive throughout: the map stays a valid embedding at every step (the local
//!      degree at each vertex cannot jump while no triangle degenerates).
//!      The result has zero flipped triangles by construction (the count is still measured).
//! - [`SphereMethod::CirclePatterns`] — the conformal map of Kharevych, Springborn & Schröder
//!   2006 over the sphere ([`crate::methods::circle_patterns::circle_pattern_sphere_map`]): the
//!   planar circle pattern of the mesh minus one vertex star, with the link on a convex polygon
//!   whose corners are the removed spokes' intersection angles, then a similarity balancing
//!   the vertex areas and inverse stereographic projection. Flips are reported.
//!
//! Cost: Gauss–Seidel O(sweeps · E); stereographic and Tutte–gnomonic one sparse solve plus
//! O(sweeps · E) for the relaxation.

use crate::boundary::{BoundaryShape, Distribution};
use crate::error::{Error, Result};
use crate::geometry::{norm, norm2, sub};
use crate::mesh::{TriMesh, NONE};
use crate::methods::barycentric::{fixed_boundary_map, FixedBoundaryOptions, Weights};
use crate::methods::circle_patterns::circle_pattern_sphere_map;
pub use crate::methods::sphere_geometry::count_spherical_flips;
use crate::methods::sphere_geometry::{det, inverse_stereographic, without_triangles};
use crate::progress::Progress;

/// Spherical parameterization method.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SphereMethod {
    /// Projected Gauss–Seidel barycentric iteration (no guarantee).
    GaussSeidel,
    /// Haker et al. 2000: planar harmonic map of the mesh minus one triangle, inverse
    /// stereographic projection (no guarantee).
    Stereographic,
    /// Tutte embedding of the mesh minus one vertex star, gnomonic lift, flip-guarded
    /// relaxation: never flips.
    TutteGnomonic,
    /// Kharevych, Springborn & Schröder 2006: the planar circle pattern of the mesh minus one
    /// vertex star, its boundary a convex polygon whose corners are the intersection angles of
    /// the removed spokes, balanced and projected stereographically (conformal; flips counted).
    CirclePatterns,
}

/// Options of [`spherical_map`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SphereOptions {
    /// The method.
    pub method: SphereMethod,
    /// Relaxation sweeps (Gauss–Seidel iterations; the Tutte–gnomonic relaxation); ignored by
    /// the stereographic method.
    pub sweeps: usize,
}

impl Default for SphereOptions {
    fn default() -> Self {
        SphereOptions { method: SphereMethod::TutteGnomonic, sweeps: 100 }
    }
}

/// A spherical parameterization.
#[derive(Debug, Clone)]
pub struct SphereMap {
    /// Unit-sphere position per vertex (NaN for unreferenced vertices).
    pub positions: Vec<[f64; 3]>,
    /// Triangles with `det[p0, p1, p2] ≤ 0`.
    pub flipped: usize,
}

/// Checks that the mesh is one closed genus-0 surface.
pub fn require_sphere(mesh: &TriMesh) -> Result<()> {
    let t = mesh.topology();
    if t.components != 1 {
        return Err(Error::MultipleComponents { components: t.components });
    }
    if t.boundary_loops != 0 || t.genus != 0 {
        return Err(Error::NotASphere { boundary_loops: t.boundary_loops, genus: t.genus });
    }
    Ok(())
}

/// Maps a closed genus-0 mesh onto the unit sphere.
pub fn spherical_map(mesh: &TriMesh, options: &SphereOptions) -> Result<SphereMap> {
    spherical_map_with_progress(mesh, options, &mut Progress::none())
}

/// [`spherical_map`] reporting progress (which can cancel): through the circle-pattern map's
/// stages, after every relaxation sweep, at the start and the end of the stereographic map.
pub fn spherical_map_with_progress(
    mesh: &TriMesh,
    options: &SphereOptions,
    progress: &mut Progress,
) -> Result<SphereMap> {
    require_sphere(mesh)?;
    progress.report(0.0)?;
    let mut positions = match options.method {
        SphereMethod::GaussSeidel => gauss_seidel(mesh, options.sweeps, progress)?,
        SphereMethod::Stereographic => stereographic(mesh)?,
        SphereMethod::TutteGnomonic => tutte_gnomonic(mesh, options.sweeps, progress)?,
        SphereMethod::CirclePatterns => {
            let options = crate::methods::circle_patterns::CirclePatternOptions::default();
            circle_pattern_sphere_map(mesh, &options, progress)?.0
        }
    };
    progress.report(1.0)?;
    orient_outward(mesh, &mut positions);
    let flipped = count_spherical_flips(&positions, mesh.triangles());
    Ok(SphereMap { positions, flipped })
}

/// Mirrors the map (z → −z) when the determinants sum to a negative value.
fn orient_outward(mesh: &TriMesh, positions: &mut [[f64; 3]]) {
    let total: f64 = mesh
        .triangles()
        .iter()
        .map(|t| det(positions[t[0] as usize], positions[t[1] as usize], positions[t[2] as usize]))
        .filter(|d| d.is_finite())
        .sum();
    if total < 0.0 {
        for p in positions.iter_mut() {
            p[2] = -p[2];
        }
    }
}

fn normalize(p: [f64; 3]) -> [f64; 3] {
    let l = norm(p);
    p.map(|x| x / l)
}

/// Neighbours of every vertex in compressed rows (each undirected edge seen from both ends).
fn neighbours(mesh: &TriMesh) -> (Vec<usize>, Vec<u32>) {
    let n = mesh.vertex_count();
    let mut start = vec![0usize; n + 1];
    // On a closed mesh every edge is an outgoing half-edge of each of its ends.
    for tri in mesh.triangles() {
        for &v in tri {
            start[v as usize + 1] += 1;
        }
    }
    for v in 0..n {
        start[v + 1] += start[v];
    }
    let mut list = vec![0u32; start[n]];
    let mut fill = start.clone();
    for (t, tri) in mesh.triangles().iter().enumerate() {
        for k in 0..3 {
            let v = tri[k] as usize;
            list[fill[v]] = mesh.head((3 * t + k) as u32);
            fill[v] += 1;
        }
    }
    (start, list)
}

/// Centroid of the referenced vertices.
fn centroid(mesh: &TriMesh, points: &[[f64; 3]]) -> [f64; 3] {
    let mut c = [0.0; 3];
    let mut count = 0.0f64;
    for (v, p) in points.iter().enumerate() {
        if mesh.is_referenced(v as u32) {
            for d in 0..3 {
                c[d] += p[d];
            }
            count += 1.0;
        }
    }
    c.map(|x| x / count.max(1.0))
}

fn unreferenced_to_nan(mesh: &TriMesh, points: &mut [[f64; 3]]) {
    for (v, p) in points.iter_mut().enumerate() {
        if !mesh.is_referenced(v as u32) {
            *p = [f64::NAN; 3];
        }
    }
}

/// Projected Gauss–Seidel barycentric iteration with re-centring.
fn gauss_seidel(mesh: &TriMesh, sweeps: usize, progress: &mut Progress) -> Result<Vec<[f64; 3]>> {
    let c = centroid(mesh, mesh.points());
    let mut x: Vec<[f64; 3]> =
        mesh.points().iter().map(|p| normalize([p[0] - c[0], p[1] - c[1], p[2] - c[2]])).collect();
    let (start, list) = neighbours(mesh);
    for sweep in 0..sweeps {
        progress.report(sweep as f64 / sweeps as f64)?;
        for v in 0..mesh.vertex_count() {
            let row = &list[start[v]..start[v + 1]];
            if row.is_empty() {
                continue;
            }
            let mut s = [0.0; 3];
            for &w in row {
                for d in 0..3 {
                    s[d] += x[w as usize][d];
                }
            }
            if norm(s) > 0.0 {
                x[v] = normalize(s);
            }
        }
        let c = centroid(mesh, &x);
        for p in x.iter_mut() {
            *p = normalize([p[0] - c[0], p[1] - c[1], p[2] - c[2]]);
        }
    }
    unreferenced_to_nan(mesh, &mut x);
    Ok(x)
}

/// Vertex of highest degree (a large link gives a rounder polygon and a smaller pole cap).
fn highest_degree_vertex(mesh: &TriMesh) -> u32 {
    let mut degree = vec![0u32; mesh.vertex_count()];
    for tri in mesh.triangles() {
        for &v in tri {
            degree[v as usize] += 1;
        }
    }
    (0..mesh.vertex_count() as u32).max_by_key(|&v| (degree[v as usize], std::cmp::Reverse(v))).unwrap_or(0)
}

/// Haker et al. 2000: harmonic map of the mesh minus one triangle, then inverse stereographic
/// projection.
fn stereographic(mesh: &TriMesh) -> Result<Vec<[f64; 3]>> {
    // The removed triangle: one around the highest-degree vertex (any choice is valid).
    let s = highest_degree_vertex(mesh);
    let removed = mesh.triangles().iter().position(|t| t.contains(&s)).unwrap_or(0);
    let disk = without_triangles(mesh, |t| t == removed)?;
    let lp = disk.boundary_loops()[0].clone();
    let given: Vec<(u32, [f64; 2])> = lp
        .iter()
        .enumerate()
        .map(|(k, &v)| {
            let a = std::f64::consts::TAU * k as f64 / lp.len() as f64;
            (v, [a.cos(), a.sin()])
        })
        .collect();
    let uv = fixed_boundary_map(
        &disk,
        &FixedBoundaryOptions {
            weights: Weights::Conformal,
            shape: BoundaryShape::Given(given),
            distribution: Distribution::Uniform,
        },
    )?;
    // Centre on the mean, scale so that the median radius is 1 (half the vertices per hemisphere).
    let referenced: Vec<usize> = (0..mesh.vertex_count()).filter(|&v| mesh.is_referenced(v as u32)).collect();
    let n = referenced.len() as f64;
    let (mut cu, mut cv) = (0.0, 0.0);
    for &v in &referenced {
        cu += uv[v][0] / n;
        cv += uv[v][1] / n;
    }
    let mut radii: Vec<f64> = referenced.iter().map(|&v| (uv[v][0] - cu).hypot(uv[v][1] - cv)).collect();
    radii.sort_unstable_by(|a, b| a.total_cmp(b));
    let median = radii[radii.len() / 2];
    let scale = if median > 0.0 { 1.0 / median } else { 1.0 };
    let mut x: Vec<[f64; 3]> =
        uv.iter().map(|p| inverse_stereographic((p[0] - cu) * scale, (p[1] - cv) * scale)).collect();
    unreferenced_to_nan(mesh, &mut x);
    Ok(x)
}

/// Tutte embedding of the mesh minus a vertex star, gnomonic lift, pole, guarded relaxation.
fn tutte_gnomonic(mesh: &TriMesh, sweeps: usize, progress: &mut Progress) -> Result<Vec<[f64; 3]>> {
    let s = highest_degree_vertex(mesh);
    let disk = without_triangles(mesh, |t| mesh.triangles()[t].contains(&s))?;
    let lp = disk.boundary_loops()[0].clone();
    let given: Vec<(u32, [f64; 2])> = lp
        .iter()
        .enumerate()
        .map(|(k, &v)| {
            let a = std::f64::consts::TAU * k as f64 / lp.len() as f64;
            (v, [a.cos(), a.sin()])
        })
        .collect();
    let uv = fixed_boundary_map(
        &disk,
        &FixedBoundaryOptions {
            weights: Weights::MeanValue,
            shape: BoundaryShape::Given(given),
            distribution: Distribution::Uniform,
        },
    )?;
    let mut x: Vec<[f64; 3]> = uv.iter().map(|p| normalize([p[0], p[1], 1.0])).collect();
    x[s as usize] = [0.0, 0.0, -1.0];
    for (v, p) in x.iter_mut().enumerate() {
        if !mesh.is_referenced(v as u32) {
            *p = [0.0, 0.0, 1.0];
        }
    }
    guarded_relaxation(mesh, &mut x, sweeps, progress)?;
    unreferenced_to_nan(mesh, &mut x);
    Ok(x)
}

/// Smallest determinant accepted by the relaxation, relative to the triangle's longest edge
/// squared (`det[p, a, b]` is twice the area of the flat triangle times its distance to the
/// centre, so this is a relative height): a move that makes a triangle nearly degenerate is
/// refused. An absolute threshold is not enough — on the octahedron the barycentre of a vertex's
/// neighbours is exactly another vertex, and a move onto it leaves determinants of rounding
/// size (1e-17) that pass any absolute margin and then let later moves fold the map.
const MIN_RELATIVE_DET: f64 = 1e-9;

/// Whether the spherical triangle (p, a, b) is positively oriented and not nearly degenerate.
fn well_oriented(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> bool {
    let longest = norm2(sub(a, p)).max(norm2(sub(b, p))).max(norm2(sub(b, a)));
    det(p, a, b) > MIN_RELATIVE_DET * longest
}

/// Gauss–Seidel sweeps moving each vertex towards the projected barycentre of its neighbours,
/// keeping a move only when every triangle around the vertex stays positively oriented.
fn guarded_relaxation(mesh: &TriMesh, x: &mut [[f64; 3]], sweeps: usize, progress: &mut Progress) -> Result<()> {
    let (start, list) = neighbours(mesh);
    // Triangles around each vertex (as the two other corners in counter-clockwise order).
    let n = mesh.vertex_count();
    let mut fan_start = vec![0usize; n + 1];
    for tri in mesh.triangles() {
        for &v in tri {
            fan_start[v as usize + 1] += 1;
        }
    }
    for v in 0..n {
        fan_start[v + 1] += fan_start[v];
    }
    let mut fan = vec![[0u32; 2]; fan_start[n]];
    let mut fill = fan_start.clone();
    for tri in mesh.triangles() {
        for k in 0..3 {
            let v = tri[k] as usize;
            fan[fill[v]] = [tri[(k + 1) % 3], tri[(k + 2) % 3]];
            fill[v] += 1;
        }
    }
    let all_positive = |x: &[[f64; 3]], v: usize, p: [f64; 3]| {
        fan[fan_start[v]..fan_start[v + 1]].iter().all(|&[a, b]| well_oriented(p, x[a as usize], x[b as usize]))
    };
    for sweep in 0..sweeps {
        progress.report(sweep as f64 / sweeps as f64)?;
        for v in 0..n {
            let row = &list[start[v]..start[v + 1]];
            if row.is_empty() || mesh.connectivity().vertex_halfedge[v] == NONE {
                continue;
            }
            let mut target = [0.0; 3];
            for &w in row {
                for d in 0..3 {
                    target[d] += x[w as usize][d];
                }
            }
            if !(norm(target) > 0.0) {
                continue;
            }
            let target = normalize(target);
            let old = x[v];
            let mut step = 1.0;
            for _ in 0..4 {
                let p = [
                    old[0] + step * (target[0] - old[0]),
                    old[1] + step * (target[1] - old[1]),
                    old[2] + step * (target[2] - old[2]),
                ];
                if norm(p) > 0.0 {
                    let p = normalize(p);
                    if all_positive(x, v, p) {
                        x[v] = p;
                        break;
                    }
                }
                step *= 0.5;
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An icosphere-like mesh: the octahedron subdivided `levels` times, pushed onto an
    /// ellipsoid.
    fn ellipsoid(levels: usize, axes: [f64; 3]) -> TriMesh {
        let mut p: Vec<[f64; 3]> = vec![
            [1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
        ];
        let mut t: Vec<[u32; 3]> =
            vec![[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]];
        for _ in 0..levels {
            let mut mid = std::collections::HashMap::new();
            let mut next_t = Vec::new();
            let mut midpoint = |a: u32, b: u32, p: &mut Vec<[f64; 3]>| -> u32 {
                *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                    let (x, y) = (p[a as usize], p[b as usize]);
                    p.push(normalize([x[0] + y[0], x[1] + y[1], x[2] + y[2]]));
                    (p.len() - 1) as u32
                })
            };
            for &[a, b, c] in &t {
                let (ab, bc, ca) = (midpoint(a, b, &mut p), midpoint(b, c, &mut p), midpoint(c, a, &mut p));
                next_t.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
            }
            t = next_t;
        }
        let positions: Vec<f64> = p.iter().flat_map(|q| [axes[0] * q[0], axes[1] * q[1], axes[2] * q[2]]).collect();
        let tris: Vec<u32> = t.iter().flatten().copied().collect();
        TriMesh::new(&positions, &tris).expect("ellipsoid")
    }

    #[test]
    fn the_relaxation_sweeps_report_progress_and_stop_when_asked() {
        let mesh = ellipsoid(2, [3.0, 1.0, 0.5]);
        for method in [SphereMethod::GaussSeidel, SphereMethod::TutteGnomonic] {
            let mut calls = 0;
            let mut stop_at_third = |_: f64| {
                calls += 1;
                calls < 3
            };
            // Sweeps enough for hours; the callback stops it at its third call.
            let options = SphereOptions { method, sweeps: usize::MAX };
            let result = spherical_map_with_progress(&mesh, &options, &mut Progress::new(&mut stop_at_third));
            assert!(matches!(result, Err(crate::error::Error::Cancelled)), "{method:?}");
            assert_eq!(calls, 3, "{method:?}");
        }
    }

    #[test]
    fn tutte_gnomonic_never_flips_and_stays_on_the_sphere() {
        let mesh = ellipsoid(3, [3.0, 1.0, 0.5]);
        let map =
            spherical_map(&mesh, &SphereOptions { method: SphereMethod::TutteGnomonic, sweeps: 50 }).expect("map");
        assert_eq!(map.flipped, 0);
        assert!(map.positions.iter().all(|p| (norm(*p) - 1.0).abs() < 1e-12));
        // Before any relaxation, the construction alone is flip-free.
        let map0 =
            spherical_map(&mesh, &SphereOptions { method: SphereMethod::TutteGnomonic, sweeps: 0 }).expect("map");
        assert_eq!(map0.flipped, 0);
    }

    #[test]
    fn a_sphere_mesh_maps_without_flips_by_every_method() {
        // A convex mesh: its normalised positions are already an embedding.
        let mesh = ellipsoid(2, [1.0, 1.0, 1.0]);
        for method in [SphereMethod::GaussSeidel, SphereMethod::Stereographic] {
            let map = spherical_map(&mesh, &SphereOptions { method, sweeps: 10 }).expect("map");
            assert_eq!(map.flipped, 0, "{method:?}");
        }
    }

    #[test]
    fn flip_count_sees_a_reflected_triangle() {
        let p = vec![[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        assert_eq!(count_spherical_flips(&p, &[[0, 1, 2]]), 0);
        assert_eq!(count_spherical_flips(&p, &[[0, 2, 1]]), 1);
    }
}
