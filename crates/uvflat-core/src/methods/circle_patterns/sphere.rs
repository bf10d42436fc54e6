//! Circle patterns over the sphere for closed genus-0 meshes (Kharevych, Springborn & Schröder
//! 2006: "closed meshes of genus zero can be parameterized over the sphere"), built from the
//! planar method of [`super::circle_pattern_map`] and a Möbius argument:
//!
//! The intersection angles θ of a circle pattern are invariant under Möbius transformations,
//! and stereographic projection from a point of the pattern is one. Seen from a vertex s at the
//! projection's pole, every circle through s (those of the triangles around s) becomes a
//! straight line: the rest of the mesh, a disk whose boundary is the link of s, is a planar
//! pattern whose boundary edges lie on those lines, so its boundary is a polygon, and at a link
//! vertex a the two lines through it (the circles of the two triangles of the spoke s–a) meet
//! at the intersection angle of that spoke. So:
//!
//! 1. s = the vertex whose link makes the most regular polygon ([`pole_candidates`]; the next
//!    ones while the planar solve of step 3 fails numerically, [`POLE_TRIALS`] in all);
//! 2. the boundary of the disk gets the prescribed turning angle (paper §5; the planar
//!    boundary condition of [`super::CirclePatternOptions::boundary_curvature`])
//!    κ_a = π − θ_{sa} at every link vertex a, θ_{sa} = α_b + α_c the two 3D angles opposite
//!    the spoke (the intersection angle of the circumcircles of its two triangles, unfolded);
//!    the κ sum to the angle sum around s, 2π − K_s, and are scaled by 2π / (2π − K_s) so the
//!    polygon closes (the curvature of s is spread over its link, as the angle program spreads
//!    every vertex's);
//! 3. the planar circle pattern of the disk (intrinsic Delaunay flips, angle program, radii,
//!    layout) with that boundary;
//! 4. a similarity of the plane (the Möbius transformations fixing the pole), chosen so that
//!    the area-weighted centroid of the vertices on the sphere is its centre
//!    ([`balanced_projection`]), then inverse stereographic projection with s at the south pole.
//!
//! With every κ_a in (0, π) the polygon is convex and the star of s, projected, is a fan of
//! positively oriented triangles around the pole; the disk's triangles keep the planar
//! pattern's orientation under the (orientation-preserving, circle-preserving) projection
//! as long as no circumcircle's image covers more than a hemisphere. Flips are counted by the
//! caller ([`crate::methods::sphere`]; the shared spherical geometry is in `methods::sphere_geometry`).
//!
//! Cost: that of the planar pattern on V − 1 vertices plus O(V) per balancing iteration.

use super::{circle_pattern_map, CirclePatternOptions, CirclePatternReport};
use crate::error::{Error, Result};
use crate::mesh::TriMesh;
use crate::methods::sphere_geometry::{inverse_stereographic, without_triangles};
use crate::progress::Progress;
use std::f64::consts::{PI, TAU};

/// Balancing stops when the centroid is this close to the centre (unit sphere), or after
/// [`BALANCE_ITERATIONS`].
const BALANCE_TOLERANCE: f64 = 1e-12;
const BALANCE_ITERATIONS: usize = 500;

/// The circle-pattern map of a closed genus-0 mesh onto the unit sphere (module comment): one
/// position per vertex (NaN for unreferenced ones), not yet oriented outward, and the planar
/// pattern's report. When a pole's planar solve fails numerically and the next pole is tried
/// (4 poles at most), `progress` starts again from 0; the error of the first pole is returned
/// when all fail.
pub fn circle_pattern_sphere_map(
    mesh: &TriMesh,
    options: &CirclePatternOptions,
    progress: &mut Progress,
) -> Result<(Vec<[f64; 3]>, CirclePatternReport)> {
    let poles = pole_candidates(mesh)?;
    let mut first_error = None;
    for &s in poles.iter().take(POLE_TRIALS) {
        match map_from_pole(mesh, s, options, progress) {
            Err(e @ Error::Numerical(_)) => {
                first_error.get_or_insert(e);
            }
            done => return done,
        }
    }
    Err(first_error.expect("at least one pole was tried"))
}

/// Poles tried, best first, while the planar pattern's solve fails numerically
/// ([`pole_candidates`]). On the plain 12-triangle cube the first pole's pattern has edges
/// of intersection angle π (each face one square, its diagonal between two triangles of one
/// circumcircle) where the radius energy has no curvature, and its Hessian is singular; the
/// next pole's is not.
const POLE_TRIALS: usize = 4;

/// Steps 2–4 of the module comment with `s` as the pole.
fn map_from_pole(
    mesh: &TriMesh,
    s: u32,
    options: &CirclePatternOptions,
    progress: &mut Progress,
) -> Result<(Vec<[f64; 3]>, CirclePatternReport)> {
    let disk = without_triangles(mesh, |t| mesh.triangles()[t].contains(&s))?;
    let mut curvature = vec![f64::NAN; mesh.vertex_count()];
    for (a, k) in link_turning_angles(mesh, s) {
        curvature[a as usize] = k;
    }
    let planar =
        CirclePatternOptions { boundary_curvature: Some(curvature), convex_boundary: false, ..options.clone() };
    let pattern = circle_pattern_map(&disk, &planar, progress)?;
    let weights = vertex_areas(mesh);
    let mut sphere = balanced_projection(&pattern.uv, &weights, s as usize);
    for (v, p) in sphere.iter_mut().enumerate() {
        if !mesh.is_referenced(v as u32) {
            *p = [f64::NAN; 3];
        }
    }
    Ok((sphere, pattern.report))
}

/// The turning angles κ_a of step 2 at the link vertices a of `s` (pairs (a, κ_a)).
fn link_turning_angles(mesh: &TriMesh, s: u32) -> Vec<(u32, f64)> {
    let mut kappa: Vec<(u32, f64)> = spoke_opposite_angles(mesh, s)
        .into_iter()
        .map(|(a, o)| (a, if (PI - o).abs() <= STRAIGHT_CORNER { 0.0 } else { PI - o }))
        .collect();
    let total: f64 = kappa.iter().map(|k| k.1).sum();
    for k in kappa.iter_mut() {
        k.1 *= TAU / total;
    }
    kappa
}

/// θ_{sa} = the sum of the two 3D angles opposite the spoke s–a, per link vertex a.
fn spoke_opposite_angles(mesh: &TriMesh, s: u32) -> Vec<(u32, f64)> {
    let angles = mesh.corner_angles();
    let mut opposite: Vec<(u32, f64)> = Vec::new();
    let mut add = |v: u32, angle: f64| match opposite.iter_mut().find(|o| o.0 == v) {
        Some(o) => o.1 += angle,
        None => opposite.push((v, angle)),
    };
    for h in mesh.outgoing_halfedges(s) {
        // Corners (s, x, y) counter-clockwise in triangle t: the angle at y is opposite the
        // spoke s–x and the angle at x opposite s–y.
        let (t, k) = ((h / 3) as usize, (h % 3) as usize);
        let tri = mesh.triangles()[t];
        add(tri[(k + 1) % 3], angles[t][(k + 2) % 3]);
        add(tri[(k + 2) % 3], angles[t][(k + 1) % 3]);
    }
    opposite
}

/// The admissible poles, best first: a pole s is admissible when every link vertex gets a
/// turning angle in [0, π) (step 2), so that the link polygon is convex; the best has the
/// smallest maximum turning angle, so that the polygon is as regular (and as far from a reflex
/// corner) as possible, the lowest index on ties. A link vertex may turn by 0 (a straight
/// corner: its spoke's two triangles are cocircular, as every diagonal of a grid of squares),
/// but a pole whose link turns strictly at every vertex is preferred. Errors when no vertex is
/// admissible.
fn pole_candidates(mesh: &TriMesh) -> Result<Vec<u32>> {
    let mut candidates: Vec<((bool, f64), u32)> = Vec::new();
    for v in (0..mesh.vertex_count() as u32).filter(|&v| mesh.is_referenced(v)) {
        let kappa = link_turning_angles(mesh, v);
        let (lo, hi) = kappa.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), k| (lo.min(k.1), hi.max(k.1)));
        if lo >= -STRAIGHT_CORNER && hi < PI {
            candidates.push(((lo <= STRAIGHT_CORNER, hi), v));
        }
    }
    if candidates.is_empty() {
        return Err(Error::Numerical(
            "circle patterns on the sphere: no vertex's link can be laid out as a convex polygon (every vertex has a spoke whose opposite angles sum to more than π)".into(),
        ));
    }
    // Stable: equal keys keep the lowest index first.
    candidates.sort_by(|a, b| a.0 .0.cmp(&b.0 .0).then(a.0 .1.total_cmp(&b.0 .1)));
    Ok(candidates.into_iter().map(|c| c.1).collect())
}

/// Turning angles within this of 0 (radians) count as a straight corner: the rounding of two
/// 3D angles that sum to π.
const STRAIGHT_CORNER: f64 = 1e-9;

/// A third of the 3D area of the triangles around every vertex.
fn vertex_areas(mesh: &TriMesh) -> Vec<f64> {
    let mut area = vec![0.0; mesh.vertex_count()];
    for (t, tri) in mesh.triangles().iter().enumerate() {
        for &v in tri {
            area[v as usize] += mesh.geometry().area[t] / 3.0;
        }
    }
    area
}

/// The planar points (NaN where unreferenced), moved by the similarity z ↦ λ (z − c) that puts
/// the `weights`-weighted centroid of their lifts, the pole vertex at the south pole included,
/// at the centre of the sphere, and lifted. Fixed-point iteration: a centroid above the equator
/// means the points crowd the north, so λ grows (pushing them south); a centroid off the axis
/// moves c towards it.
fn balanced_projection(uv: &[[f64; 2]], weights: &[f64], pole: usize) -> Vec<[f64; 3]> {
    let points: Vec<(usize, [f64; 2])> = uv
        .iter()
        .enumerate()
        .filter(|&(v, p)| v != pole && p[0].is_finite() && p[1].is_finite())
        .map(|(v, p)| (v, *p))
        .collect();
    let total: f64 = points.iter().map(|&(v, _)| weights[v]).sum::<f64>() + weights[pole];
    let mut c = points.iter().fold([0.0; 2], |a, &(v, p)| [a[0] + weights[v] * p[0], a[1] + weights[v] * p[1]]);
    c = c.map(|x| x / (total - weights[pole]).max(f64::MIN_POSITIVE));
    let mut radii: Vec<f64> = points.iter().map(|(_, p)| (p[0] - c[0]).hypot(p[1] - c[1])).collect();
    radii.sort_unstable_by(|a, b| a.total_cmp(b));
    let median = radii.get(radii.len() / 2).copied().unwrap_or(1.0);
    let mut lambda = if median > 0.0 { 1.0 / median } else { 1.0 };
    for _ in 0..BALANCE_ITERATIONS {
        let mut centroid = [0.0, 0.0, -weights[pole]];
        for &(v, p) in &points {
            let q = inverse_stereographic(lambda * (p[0] - c[0]), lambda * (p[1] - c[1]));
            for d in 0..3 {
                centroid[d] += weights[v] * q[d];
            }
        }
        let centroid = centroid.map(|x| x / total);
        if centroid.iter().map(|x| x * x).sum::<f64>() < BALANCE_TOLERANCE * BALANCE_TOLERANCE {
            break;
        }
        lambda *= centroid[2].clamp(-1.0, 1.0).exp();
        c = [c[0] + centroid[0] / lambda, c[1] + centroid[1] / lambda];
    }
    let mut out: Vec<[f64; 3]> =
        uv.iter().map(|p| inverse_stereographic(lambda * (p[0] - c[0]), lambda * (p[1] - c[1]))).collect();
    out[pole] = [0.0, 0.0, -1.0];
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{cross, dot, sub};

    /// The convex hull of points on a sphere whose faces are the triples of mutually nearest
    /// neighbours (edge length `edge`), oriented outward.
    fn regular_polyhedron(points: &[[f64; 3]], edge: f64) -> TriMesh {
        let n = points.len();
        let near = |a: usize, b: usize| (crate::geometry::distance(points[a], points[b]) - edge).abs() < 1e-9;
        let mut triangles = Vec::new();
        for a in 0..n {
            for b in a + 1..n {
                for c in b + 1..n {
                    if near(a, b) && near(b, c) && near(a, c) {
                        let outward = dot(points[a], cross(sub(points[b], points[a]), sub(points[c], points[a]))) > 0.0;
                        let tri = if outward { [a, b, c] } else { [a, c, b] };
                        triangles.extend(tri.map(|v| v as u32));
                    }
                }
            }
        }
        let flat: Vec<f64> = points.iter().flatten().copied().collect();
        TriMesh::new(&flat, &triangles).unwrap()
    }

    fn sphere_of(mesh: &TriMesh) -> Vec<[f64; 3]> {
        circle_pattern_sphere_map(mesh, &CirclePatternOptions::default(), &mut Progress::none()).unwrap().0
    }

    #[test]
    fn the_octahedron_maps_onto_a_regular_octahedron() {
        let p =
            [[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, -1.0]];
        let mesh = regular_polyhedron(&p, 2f64.sqrt());
        assert_eq!(mesh.triangle_count(), 8);
        let s = sphere_of(&mesh);
        // Every pair of vertices is either neighbours (orthogonal) or antipodal, as in the input.
        for a in 0..6 {
            for b in 0..6 {
                let expected = dot(p[a], p[b]);
                assert!((dot(s[a], s[b]) - expected).abs() < 1e-9, "{a} {b}: {} against {expected}", dot(s[a], s[b]));
            }
        }
    }

    #[test]
    fn the_icosahedron_keeps_its_symmetry_about_the_pole() {
        // Vertex 0 is the pole (every link is a regular pentagon; the lowest index wins). The
        // map keeps the five-fold symmetry about it: its antipode goes to the antipodal point,
        // its five neighbours to one latitude, equally spaced, and the next five to another.
        // It is not the regular icosahedron itself: the planar angle program pulls the angles
        // towards the 3D ones (60°), where the stereographic image of the icosahedron has
        // others (neighbours 0.563 apart in cosine instead of 1/√5 = 0.447).
        let g = (1.0 + 5f64.sqrt()) / 2.0;
        let mut p = Vec::new();
        for (x, y) in [(1.0, g), (1.0, -g), (-1.0, g), (-1.0, -g)] {
            p.extend([[0.0, x, y], [x, y, 0.0], [y, 0.0, x]]);
        }
        let mesh = regular_polyhedron(&p, 2.0);
        assert_eq!(mesh.triangle_count(), 20);
        assert_eq!(pole_candidates(&mesh).unwrap()[0], 0);
        let s = sphere_of(&mesh);
        let p = &p;
        let ring = |d: f64| (1..12).filter(move |&v| (dot(p[0], p[v]) - d).abs() < 1e-9).collect::<Vec<_>>();
        let r2 = 1.0 + g * g;
        let (near, far, antipode) = (ring(r2 / 5f64.sqrt()), ring(-r2 / 5f64.sqrt()), ring(-r2));
        assert_eq!((near.len(), far.len(), antipode.len()), (5, 5, 1));
        assert!((dot(s[0], s[antipode[0]]) + 1.0).abs() < 1e-9);
        for ring in [&near, &far] {
            let latitude = dot(s[0], s[ring[0]]);
            assert!(ring.iter().all(|&v| (dot(s[0], s[v]) - latitude).abs() < 1e-9), "{ring:?}");
            // Equally spaced: each vertex's nearest ring neighbour at the same distance.
            let spacing: Vec<f64> = ring
                .iter()
                .map(|&a| ring.iter().filter(|&&b| b != a).map(|&b| dot(s[a], s[b])).fold(f64::MIN, f64::max))
                .collect();
            assert!(spacing.iter().all(|x| (x - spacing[0]).abs() < 1e-9), "{spacing:?}");
        }
    }

    /// A cube whose faces are `n` × `n` grids of squares, each split along the same diagonal,
    /// oriented outward: every diagonal's two triangles are cocircular (opposite angles 90° +
    /// 90°), so every link has a straight corner.
    fn grid_cube(n: usize) -> TriMesh {
        let mut index = std::collections::HashMap::new();
        let (mut points, mut triangles) = (Vec::<[f64; 3]>::new(), Vec::new());
        let mut vertex = |p: [f64; 3]| -> u32 {
            let key = p.map(|x| (x * 1e6).round() as i64);
            *index.entry(key).or_insert_with(|| {
                points.push(p);
                points.len() as u32 - 1
            })
        };
        for axis in 0..3 {
            for sign in [-1.0, 1.0] {
                let at = |a: usize, b: usize| {
                    let mut p = [0.0; 3];
                    p[axis] = sign;
                    p[(axis + 1) % 3] = -1.0 + 2.0 * a as f64 / n as f64;
                    p[(axis + 2) % 3] = -1.0 + 2.0 * b as f64 / n as f64;
                    p
                };
                for i in 0..n {
                    for j in 0..n {
                        let q = [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)].map(&mut vertex);
                        let quad = if sign > 0.0 {
                            [q[0], q[1], q[2], q[0], q[2], q[3]]
                        } else {
                            [q[0], q[2], q[1], q[0], q[3], q[2]]
                        };
                        triangles.extend(quad);
                    }
                }
            }
        }
        let flat: Vec<f64> = points.iter().flatten().copied().collect();
        TriMesh::new(&flat, &triangles).unwrap()
    }

    #[test]
    fn a_subdivided_cube_whose_links_all_have_straight_corners_maps_without_flips() {
        // Before straight corners were allowed, no pole qualified ("no vertex's link can be laid
        // out as a convex polygon") although the grid is the intrinsic Delaunay triangulation.
        // n = 1, the plain 12-triangle cube: the best pole's pattern solve fails ("not positive
        // definite": every face is one square whose diagonal has intersection angle π, where the
        // radius energy has no curvature); the next pole's succeeds.
        for n in [1, 2, 3, 4, 9] {
            let mesh = grid_cube(n);
            assert_eq!(mesh.vertex_count(), 6 * n * n + 2);
            let s = sphere_of(&mesh);
            assert!(s.iter().all(|p| (crate::geometry::norm(*p) - 1.0).abs() < 1e-9), "n = {n}");
            let flipped = crate::methods::sphere_geometry::count_spherical_flips(&s, mesh.triangles());
            // Not yet oriented outward: all triangles one way.
            assert!(flipped == 0 || flipped == mesh.triangle_count(), "n = {n}: {flipped} flipped");
        }
    }

    #[test]
    fn the_link_turning_angles_close_the_polygon() {
        // A vertex of the octahedron: four spokes, each with opposite angles 60° + 60°, angle
        // sum 240°: the turning angles 60° each are scaled to a square's 90°.
        let p =
            [[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, -1.0]];
        let mesh = regular_polyhedron(&p, 2f64.sqrt());
        let kappa = link_turning_angles(&mesh, 4);
        assert_eq!(kappa.len(), 4);
        assert!(kappa.iter().all(|k| (k.1 - PI / 2.0).abs() < 1e-12), "{kappa:?}");
    }
}
