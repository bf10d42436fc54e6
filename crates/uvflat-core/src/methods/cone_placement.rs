//! Automatic placement of cone singularities for conformal maps (Ben-Chen, Gotsman & Bunin
//! 2008, "Conformal flattening by curvature prescription and metric scaling", §4–5: a cone
//! concentrates Gaussian curvature, and the log scale factor u of the flattening solves the
//! Poisson equation Δu = K − K̃; cones are added greedily where |u| is largest). Used with the
//! circle-pattern cone map (Kharevych, Springborn & Schröder 2006 §5, where the cones are the
//! user's), whose cut and layout then follow the cones placed here.
//!
//! With the cone set S (and the boundary, if any) held at u = 0, the flattening's log scale on
//! the other vertices solves the Dirichlet problem L u = −K there (L the positive semidefinite
//! cotangent Laplacian, K the angle defects), and each cone takes the curvature
//! κ_s = K_s + (L u)_s, so that L u = κ − K everywhere: Σ κ_s = Σ K = 2π χ on a closed mesh
//! (the rows of L sum to 0). The vertex with the largest |u| is the next cone. The same greedy
//! strategy is the default of the boundary-first-flattening reference implementation (Sawhney
//! & Crane 2017, its "CETM" cone placement). The first cone of a closed surface with χ ≠ 0 is
//! the vertex of largest angle defect (χ > 0) or smallest (χ < 0); a torus starts with none.
//!
//! L is the cotangent Laplacian of the intrinsic Delaunay triangulation of the mesh's metric
//! ([`crate::mesh::intrinsic_delaunay`]), whose weights are all ≥ 0, so each Dirichlet problem
//! is positive definite even where the mesh has obtuse triangles; the vertices and the angle
//! defects are the mesh's. Cost: one sparse Cholesky factorization per cone (the pattern is
//! analysed once; a cone's row and column are replaced by the identity).

use crate::error::{Error, Result};
use crate::mesh::intrinsic_delaunay::{angles_from_lengths, intrinsic_delaunay};
use crate::mesh::TriMesh;
use crate::progress::Progress;
use faer::Mat;
use std::f64::consts::PI;
use uvflat_sparse::{factor_reusing, lower_from_entries, CholeskyPattern};

/// Options of [`place_cones`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConePlacementOptions {
    /// Most cones placed (the first cone of a closed surface included).
    pub max_cones: u32,
    /// Stop once the flattening's log scale |u| is at most this everywhere (e^u is the length
    /// scale: 0.7 ≈ a factor of 2).
    pub max_log_scale: f64,
}

impl Default for ConePlacementOptions {
    fn default() -> Self {
        ConePlacementOptions { max_cones: 64, max_log_scale: 0.7 }
    }
}

/// The cones [`place_cones`] chose.
#[derive(Debug, Clone, PartialEq)]
pub struct ConePlacement {
    /// (interior vertex, curvature κ = 2π − cone angle in radians), in the order placed.
    pub cones: Vec<(u32, f64)>,
    /// Largest |u| of the flattening with these cones (the boundary, if any, at u = 0).
    pub max_log_scale: f64,
}

/// Greedy cone placement on a connected mesh (closed or with boundary): cones are added where
/// the conformal flattening's log scale is largest until it is at most
/// `options.max_log_scale` everywhere or `options.max_cones` are placed.
pub fn place_cones(mesh: &TriMesh, options: &ConePlacementOptions, progress: &mut Progress) -> Result<ConePlacement> {
    if !(options.max_log_scale.is_finite() && options.max_log_scale >= 0.0) {
        return Err(Error::InvalidArgument(format!(
            "max_log_scale must be finite and ≥ 0 (got {})",
            options.max_log_scale
        )));
    }
    let topology = mesh.topology();
    if topology.components != 1 {
        return Err(Error::MultipleComponents { components: topology.components });
    }
    let defects = angle_defects(mesh);
    let laplacian = Laplacian::intrinsic(mesh);
    let mut fixed: Vec<bool> =
        (0..mesh.vertex_count() as u32).map(|v| !mesh.is_referenced(v) || mesh.is_boundary_vertex(v)).collect();
    let mut cones = Vec::new();
    if let Some(first) = first_cone(mesh, &defects, topology.boundary_loops, topology.euler_characteristic) {
        if options.max_cones > 0 {
            fixed[first as usize] = true;
            cones.push(first);
        }
    }
    let degree = mesh.corner_counts();
    let mut pattern = None;
    loop {
        let u = laplacian.scale_factors(&defects, &fixed, &mut pattern)?;
        let worst = (0..u.len()).filter(|&v| !fixed[v]).max_by(|&a, &b| u[a].abs().total_cmp(&u[b].abs()));
        let largest = worst.map_or(0.0, |v| u[v].abs());
        let flux = laplacian.apply(&u);
        let placed: Vec<(u32, f64)> = cones.iter().map(|&s| (s, defects[s as usize] + flux[s as usize])).collect();
        let unrealizable = placed.iter().find(|&&(s, k)| !realizable(k, degree[s as usize]));
        let full = cones.len() >= options.max_cones as usize;
        if let (Some(&(s, k)), true) = (unrealizable, full) {
            return Err(too_few_cones(s, k, degree[s as usize], options.max_cones, topology.euler_characteristic));
        }
        match worst.filter(|_| !full && (largest > options.max_log_scale || unrealizable.is_some())) {
            Some(v) => {
                fixed[v] = true;
                cones.push(v as u32);
                progress.report(cones.len() as f64 / options.max_cones.max(1) as f64)?;
            }
            None => return Ok(ConePlacement { cones: placed, max_log_scale: largest }),
        }
    }
}

/// Whether a cone of curvature κ fits a vertex of `degree` triangles: its angle 2π − κ must
/// be positive (above 0.05) and at most 0.8 π per triangle, so that every corner can stay
/// below π with room for the circle pattern's Delaunay condition.
fn realizable(curvature: f64, degree: u32) -> bool {
    let angle = 2.0 * PI - curvature;
    angle > 0.05 && angle <= 0.8 * PI * degree as f64
}

/// The error for a cone that `max_cones` leave too much curvature to carry.
fn too_few_cones(vertex: u32, curvature: f64, degree: u32, max_cones: u32, chi: i64) -> Error {
    Error::InvalidArgument(format!(
        "{max_cones} cones are too few: the cone at vertex {vertex} would need an angle of {:.3} rad over its {degree} triangles; raise max_cones (Gauss–Bonnet puts 2π χ = {:.1} rad of curvature on the cones of a closed surface, and a cone of a vertex of 6 triangles carries at most about −2.8π)",
        2.0 * PI - curvature,
        2.0 * PI * chi as f64
    ))
}

/// 2π − Σ angles at every interior vertex (0 elsewhere).
fn angle_defects(mesh: &TriMesh) -> Vec<f64> {
    let mut sums = vec![0.0; mesh.vertex_count()];
    for (tri, angles) in mesh.triangles().iter().zip(mesh.corner_angles()) {
        for k in 0..3 {
            sums[tri[k] as usize] += angles[k];
        }
    }
    (0..mesh.vertex_count() as u32)
        .map(|v| if mesh.is_referenced(v) && !mesh.is_boundary_vertex(v) { 2.0 * PI - sums[v as usize] } else { 0.0 })
        .collect()
}

/// The first cone of a closed surface with χ ≠ 0: the vertex of largest angle defect when
/// χ > 0, of smallest when χ < 0 (as the boundary-first-flattening reference does); none with
/// a boundary (held at u = 0) or on a torus.
fn first_cone(mesh: &TriMesh, defects: &[f64], boundary_loops: usize, chi: i64) -> Option<u32> {
    if boundary_loops > 0 || chi == 0 {
        return None;
    }
    let sign = chi.signum() as f64;
    (0..mesh.vertex_count() as u32)
        .filter(|&v| mesh.is_referenced(v))
        .max_by(|&a, &b| (sign * defects[a as usize]).total_cmp(&(sign * defects[b as usize])))
}

/// The cotangent Laplacian L (positive semidefinite) as its diagonal and strictly lower
/// entries.
struct Laplacian {
    diagonal: Vec<f64>,
    lower: Vec<(u32, u32, f64)>,
    points: Vec<[f64; 3]>,
}

impl Laplacian {
    /// Of the intrinsic Delaunay triangulation of `mesh`: weight ½ cot of the angle opposite
    /// each half-edge, every one ≥ 0 up to rounding.
    fn intrinsic(mesh: &TriMesh) -> Self {
        let delaunay = intrinsic_delaunay(mesh);
        let mut diagonal = vec![0.0; mesh.vertex_count()];
        let mut lower = Vec::with_capacity(3 * delaunay.triangles.len());
        for (tri, lengths) in delaunay.triangles.iter().zip(&delaunay.lengths) {
            let angles = angles_from_lengths(*lengths);
            for k in 0..3 {
                // Half-edge k (corner k to k + 1) is opposite corner k + 2.
                let (i, j) = (tri[k], tri[(k + 1) % 3]);
                let w = 0.5 / angles[(k + 2) % 3].tan();
                diagonal[i as usize] += w;
                diagonal[j as usize] += w;
                lower.push((i.max(j), i.min(j), -w));
            }
        }
        Laplacian { diagonal, lower, points: mesh.points().to_vec() }
    }

    /// L u.
    fn apply(&self, u: &[f64]) -> Vec<f64> {
        let mut out: Vec<f64> = self.diagonal.iter().zip(u).map(|(d, x)| d * x).collect();
        for &(r, c, w) in &self.lower {
            out[r as usize] += w * u[c as usize];
            out[c as usize] += w * u[r as usize];
        }
        out
    }

    /// u = 0 on `fixed`, L u = −K elsewhere. With nothing fixed (a torus before its first
    /// cone) u is determined up to a constant: one vertex is held, then the mean removed.
    fn scale_factors(
        &self,
        defects: &[f64],
        fixed: &[bool],
        pattern: &mut Option<CholeskyPattern>,
    ) -> Result<Vec<f64>> {
        let n = self.diagonal.len();
        let surface = |v: usize| self.diagonal[v] > 0.0;
        let anchor = (!(0..n).any(|v| fixed[v] && surface(v))).then(|| (0..n).find(|&v| surface(v))).flatten();
        let held = |v: usize| fixed[v] || Some(v) == anchor;
        let diagonal: Vec<f64> = (0..n).map(|v| if held(v) { 1.0 } else { self.diagonal[v] }).collect();
        let entries = self
            .lower
            .iter()
            .map(|&(r, c, w)| (r, c, if held(r as usize) || held(c as usize) { 0.0 } else { w }))
            .collect();
        let lower = lower_from_entries(&diagonal, entries)?;
        let solver = factor_reusing(pattern, &lower, &self.points)?;
        let mut u = Mat::from_fn(n, 1, |v, _| if held(v) { 0.0 } else { -defects[v] });
        solver.solve_in_place(&mut u)?;
        let mut u: Vec<f64> = (0..n).map(|v| u[(v, 0)]).collect();
        if anchor.is_some() {
            let free: Vec<usize> = (0..n).filter(|&v| surface(v)).collect();
            let mean = free.iter().map(|&v| u[v]).sum::<f64>() / free.len() as f64;
            free.iter().for_each(|&v| u[v] -= mean);
        }
        Ok(u)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The surface of the cube [0, n]³, each face an n × n grid of squares split into two
    /// triangles, outward-facing.
    fn cube(n: usize) -> TriMesh {
        let mut positions: Vec<[f64; 3]> = Vec::new();
        let mut index = std::collections::HashMap::new();
        let mut triangles = Vec::new();
        let mut id = |p: [i64; 3], positions: &mut Vec<[f64; 3]>| -> u32 {
            *index.entry(p).or_insert_with(|| {
                positions.push(p.map(|x| x as f64));
                (positions.len() - 1) as u32
            })
        };
        let n = n as i64;
        for axis in 0..3 {
            for side in [0, n] {
                let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
                for i in 0..n {
                    for j in 0..n {
                        let point = |di: i64, dj: i64| {
                            let mut p = [0i64; 3];
                            p[axis] = side;
                            p[a] = i + di;
                            p[b] = j + dj;
                            p
                        };
                        let mut quad =
                            [point(0, 0), point(1, 0), point(1, 1), point(0, 1)].map(|p| id(p, &mut positions));
                        if side == 0 {
                            quad.reverse();
                        }
                        triangles.extend([quad[0], quad[1], quad[2], quad[0], quad[2], quad[3]]);
                    }
                }
            }
        }
        let flat: Vec<f64> = positions.iter().flatten().copied().collect();
        TriMesh::new(&flat, &triangles).unwrap()
    }

    #[test]
    fn the_cones_of_a_cube_are_its_corners() {
        // All of a cube's curvature sits at its 8 corners (π/2 each); its faces and edges are
        // flat. With cones there the flattening is exact (u = 0), so the greedy placement must
        // find exactly those, with their own curvature.
        let mesh = cube(4);
        let placement = place_cones(&mesh, &ConePlacementOptions::default(), &mut Progress::none()).unwrap();
        assert_eq!(placement.cones.len(), 8, "{placement:?}");
        for &(v, k) in &placement.cones {
            let p = mesh.points()[v as usize];
            assert!(p.iter().all(|&x| x == 0.0 || x == 4.0), "cone {v} at {p:?} is not a corner");
            assert!((k - PI / 2.0).abs() < 1e-9, "cone {v}: curvature {k}");
        }
        assert!(placement.max_log_scale < 1e-9, "{placement:?}");
        // A limit on the count stops early, with the curvature still summing to 4π.
        let three = ConePlacementOptions { max_cones: 3, ..Default::default() };
        let placement = place_cones(&mesh, &three, &mut Progress::none()).unwrap();
        assert_eq!(placement.cones.len(), 3);
        let total: f64 = placement.cones.iter().map(|c| c.1).sum();
        assert!((total - 4.0 * PI).abs() < 1e-9, "{total}");
        assert!(placement.max_log_scale > 0.1);
    }

    #[test]
    fn a_flat_disk_needs_no_cone_and_bad_options_are_refused() {
        let positions: Vec<f64> = (0..25).flat_map(|k| [(k % 5) as f64, (k / 5) as f64 * 1.1, 0.0]).collect();
        let triangles: Vec<u32> = (0..16u32)
            .flat_map(|q| {
                let (i, j) = (q % 4, q / 4);
                let v = j * 5 + i;
                [v, v + 1, v + 6, v, v + 6, v + 5]
            })
            .collect();
        let mesh = TriMesh::new(&positions, &triangles).unwrap();
        let placement = place_cones(&mesh, &ConePlacementOptions::default(), &mut Progress::none()).unwrap();
        assert!(placement.cones.is_empty() && placement.max_log_scale < 1e-12, "{placement:?}");
        for bad in [f64::NAN, -1.0, f64::INFINITY] {
            let options = ConePlacementOptions { max_log_scale: bad, ..Default::default() };
            assert!(matches!(place_cones(&mesh, &options, &mut Progress::none()), Err(Error::InvalidArgument(_))));
        }
    }
}
