//! Vector field smoothing of PGP (Ray et al. 2006, §4.2, eqs. 21–22): fits a smooth direction
//! field to the principal curvature directions, extrapolating them from the anisotropic regions
//! into the isotropic ones where they are undefined, with equality modulo 2π, π or π/2.
//!
//! Per vertex i: a reference direction `H_i` (an edge from i projected on the tangent plane,
//! normalized) and the unknown `z_i = (cos α̃_i, sin α̃_i)`, where α_i is the angle from H_i to
//! the field (counter-clockwise about the normal N_i) and α̃ = kα for symmetry 2π/k (k = 1, 2,
//! 4: "dividing all the α's and β's by 2 (resp. 4)" in the paper's words, i.e. working on kα).
//! The energy (eq. 21) is
//!
//! ```text
//! R = (1 − ρ) Σ_i w_i ‖z_i − z_i⁰‖² + ρ Σ_T Σ_e λ_e^T ‖z_b − rot(−kβ_e) z_a‖²
//! ```
//!
//! with z⁰ the input directions, w_i the anisotropy weight (below), λ the triangle
//! weights of eq. 24 and β_e the angle from H_a to H_b (eq. 22; measured after parallel
//! transport, see [`reference_rotation`]). It is minimized by the machinery of §2.5 ([`super::block_newton`]):
//! the linear solve, then Newton with the unit-norm penalty. The result is
//! `K_i = cos α_i H_i + sin α_i (N_i × H_i)`, α_i = angle(z_i)/k.
//!
//! The fitting weight. Eq. 21 writes |kmax_i/kmin_i|, while the text calls the fitting
//! anisotropy-weighted and defines the anisotropy as |kmax/kmin| − 1, the indicator that
//! "vanishes when the vector field directions are ill-defined". We use the anisotropy
//! w_i = |kmax_i/kmin_i| − 1, which is what lets the directions of the anisotropic regions be
//! extrapolated into the isotropic ones (with |kmax/kmin| itself every umbilic region would
//! still be pulled towards its meaningless input directions with weight ≥ 1). The ratio is
//! computed as (|κ|max + η)/(|κ|min + η) with η = 10⁻² / (mean edge length), so that flat
//! regions (both curvatures ≈ 0) count as isotropic, and w is kept in
//! [[`MIN_FITTING_WEIGHT`], [`MAX_ANISOTROPY_WEIGHT`]] (a cylinder has kmin = 0; the floor keeps
//! the system definite on a flat mesh, whose connection has no curvature). Triangle forms made indefinite by an
//! obtuse corner are replaced by their semidefinite part, as in the periodic solve.
//!
//! Cost: one 2V × 2V factorization per Newton iteration.

use super::block_newton::{minimize, BlockSystem, NewtonOptions, SolveReport};
use super::curvature::tangent_basis;
use super::curvature::PrincipalCurvatures;
use super::frames::{
    edge_sum_form, match_rotation, normalized, project_semidefinite, rotate_quarter, tangent_part, transport,
    triangle_normal, triangle_weights, EdgeList,
};
use crate::error::{Error, Result};
use crate::geometry::{cross, dot, norm, sub};
use crate::progress::Progress;
use crate::TriMesh;
use faer::c64;

/// Default weight ε of the unit-norm penalty of the smoothing. The paper gives no value for
/// it (10⁻³ is its periodic solve's; ours is the same 0.1, [`super::block_newton::PERIODIC_EPSILON`]). Where the fitting weight is small (isotropic regions)
/// nothing else anchors the norms: with ε = 10⁻³ shrinking the unknowns towards zero is
/// cheaper than making them smooth, and the field collapses to |z| ≈ 0 (its directions are
/// then noise). With ε = 0.1 the penalty outweighs the smoothing term per vertex, |z| stays
/// near 1 away from singularities, and an icosphere gets the 2, 4 or 8 singularities of Fig. 9
/// (ε = 1 makes Newton stall in indefinite regions on fine meshes).
pub const SMOOTHING_EPSILON: f64 = 0.1;

/// Default Newton iteration limit of the smoothing. Far from convergence the penalty's Hessian
/// is indefinite near the field's singularities and the steps are damped ([`super::block_newton`]),
/// while the singularities settle within the first few iterations; beyond 8 iterations the field
/// hardly changes on the meshes of `tests/data/meshes` (the periodic solve, not the smoothing,
/// is what the paper's 10⁻⁶ tolerance is for).
pub const SMOOTHING_ITERATIONS: usize = 8;

/// Smallest fitting weight (isotropic vertices).
pub const MIN_FITTING_WEIGHT: f64 = 1e-4;

/// Largest anisotropy weight |kmax/kmin| − 1 of the fitting term.
pub const MAX_ANISOTROPY_WEIGHT: f64 = 100.0;

/// The symmetry of the smoothed field: directions are equal modulo 2π, π or π/2.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Symmetry {
    /// Modulo 2π (vectors; singularities are poles of index 1).
    Vector,
    /// Modulo π (lines; half-poles).
    Line,
    /// Modulo π/2 (crosses; quarter-poles) — the symmetry PGP's rotation matching uses.
    Cross,
}

impl Symmetry {
    /// k such that the symmetry is 2π/k.
    pub fn order(self) -> u32 {
        match self {
            Symmetry::Vector => 1,
            Symmetry::Line => 2,
            Symmetry::Cross => 4,
        }
    }
}

/// Options of [`smooth_field`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SmoothingOptions {
    /// Equality modulo 2π/k.
    pub symmetry: Symmetry,
    /// Smoothing intensity ρ in [0, 1) (paper: 0.8).
    pub rho: f64,
    /// Solver (penalty ε, default [`SMOOTHING_EPSILON`]; gradient tolerance, default 10⁻⁵;
    /// iterations, default [`SMOOTHING_ITERATIONS`]).
    pub newton: NewtonOptions,
}

impl Default for SmoothingOptions {
    fn default() -> Self {
        SmoothingOptions {
            symmetry: Symmetry::Cross,
            rho: 0.8,
            newton: NewtonOptions {
                epsilon: SMOOTHING_EPSILON,
                gradient_tolerance: 1e-5,
                max_iterations: SMOOTHING_ITERATIONS,
            },
        }
    }
}

/// Smooths the direction field `field` (tangent vectors per vertex, e.g. the kmax directions)
/// with anisotropy weights from `curvatures` (module comment). Returns unit tangent vectors.
pub fn smooth_field(
    mesh: &TriMesh,
    curvatures: &PrincipalCurvatures,
    field: &[[f64; 3]],
    options: &SmoothingOptions,
    progress: &mut Progress,
    span: (f64, f64),
) -> Result<(Vec<[f64; 3]>, SolveReport)> {
    if !(options.rho.is_finite() && (0.0..1.0).contains(&options.rho)) {
        return Err(Error::InvalidArgument(format!("the smoothing rho must be in [0, 1) (got {})", options.rho)));
    }
    let normals = &curvatures.normal;
    let reference = reference_directions(mesh, normals);
    let k = options.symmetry.order() as f64;
    let weights = anisotropy_weights(mesh, curvatures);
    let edges = EdgeList::new(mesh);
    let mut system = BlockSystem::<2>::new(mesh, &edges);
    add_fitting_term(&mut system, normals, &reference, field, &weights, k, 1.0 - options.rho);
    add_smoothing_term(&mut system, mesh, &edges, normals, &reference, k, options.rho);
    let (z, report) = minimize(&system, &[], &options.newton, progress, span)?;
    let mut out = vec![[0.0; 3]; mesh.vertex_count()];
    for (b, &v) in system.vertex_of.iter().enumerate() {
        let alpha = z[b][1].atan2(z[b][0]) / k;
        let (h, n) = (reference[v as usize], normals[v as usize]);
        let nh = cross(n, h);
        out[v as usize] = normalized(std::array::from_fn(|a| alpha.cos() * h[a] + alpha.sin() * nh[a]));
    }
    Ok((out, report))
}

/// The field per triangle, for singularity indices: the corners' vectors matched to corner 0
/// modulo 2π/k (k = 4: rotation matching, eq. 13; k = 2: sign; k = 1: as they are), averaged
/// and projected on the triangle's plane.
pub fn face_directions(mesh: &TriMesh, normals: &[[f64; 3]], field: &[[f64; 3]], symmetry: Symmetry) -> Vec<[f64; 3]> {
    (0..mesh.triangle_count())
        .map(|t| {
            let tri = mesh.triangles()[t];
            let (k0, n0) = (field[tri[0] as usize], normals[tri[0] as usize]);
            let mut sum = k0;
            for &v in &tri[1..] {
                let (n, k) = (normals[v as usize], field[v as usize]);
                let matched = match symmetry {
                    Symmetry::Vector => k,
                    Symmetry::Line => {
                        if dot(k, k0) < 0.0 {
                            k.map(|x| -x)
                        } else {
                            k
                        }
                    }
                    Symmetry::Cross => rotate_quarter(n, k, match_rotation(k0, n0, n, k)),
                };
                sum = std::array::from_fn(|a| sum[a] + matched[a]);
            }
            normalized(tangent_part(sum, triangle_normal(mesh, t)))
        })
        .collect()
}

/// H_i: the first outgoing edge of each vertex, projected on its tangent plane and normalized,
/// unless that edge runs along the normal (its tangent part under [`MIN_TANGENT_PART`] of its
/// length, mostly rounding); then the outgoing edge that lies the most in the tangent plane, and
/// any tangent direction where no edge has a tangent part. (The smoothed field is the same for
/// every choice, up to rounding and the solver's tolerance; the first edge alone can run along
/// the normal: on the tetrahedron (0,0,0), (2,0,0), (0,2,0), (0,0,2) the vertex normal at
/// (0,2,0) is (0,1,0) and so is its first edge, and the smoothed field came out zero there;
/// among the shared closed meshes only `closed_g133_cheese`, whose cube faces are axis-aligned,
/// has such vertices: its results alone changed with this choice.)
pub fn reference_directions(mesh: &TriMesh, normals: &[[f64; 3]]) -> Vec<[f64; 3]> {
    (0..mesh.vertex_count() as u32).map(|v| reference_direction(mesh, normals[v as usize], v)).collect()
}

/// Smallest tangent part of the first outgoing edge, relative to its length, kept as H_i.
const MIN_TANGENT_PART: f64 = 1e-6;

fn reference_direction(mesh: &TriMesh, n: [f64; 3], v: u32) -> [f64; 3] {
    let p = mesh.points()[v as usize];
    let mut tangents = mesh.outgoing_halfedges(v).map(|h| {
        let e = sub(mesh.points()[mesh.head(h) as usize], p);
        (tangent_part(e, n), norm(e))
    });
    let Some((first, length)) = tangents.next() else { return [0.0; 3] };
    if norm(first) >= MIN_TANGENT_PART * length {
        return normalized(first);
    }
    let share = |(t, l): (_, f64)| if l > 0.0 { norm(t) / l } else { 0.0 };
    let best = tangents.fold((first, length), |best, e| if share(e) > share(best) { e } else { best }).0;
    if norm(best) > 0.0 {
        normalized(best)
    } else if norm(n) > 0.0 {
        tangent_basis(n).0
    } else {
        [0.0; 3]
    }
}

/// Angle from `h` to `k` counter-clockwise about `n`.
fn angle_from(h: [f64; 3], k: [f64; 3], n: [f64; 3]) -> f64 {
    dot(cross(h, k), n).atan2(dot(h, k))
}

/// w_i = |kmax/kmin| − 1, the anisotropy (module comment for the regularization).
pub fn anisotropy_weights(mesh: &TriMesh, c: &PrincipalCurvatures) -> Vec<f64> {
    let eta = 1e-2 / mean_edge_length(mesh).max(f64::MIN_POSITIVE);
    (0..mesh.vertex_count())
        .map(|v| {
            let (a, b) = (c.kmax[v].abs(), c.kmin[v].abs());
            ((a.max(b) + eta) / (a.min(b) + eta) - 1.0).clamp(MIN_FITTING_WEIGHT, MAX_ANISOTROPY_WEIGHT)
        })
        .collect()
}

/// Mean length of the mesh's edges.
pub fn mean_edge_length(mesh: &TriMesh) -> f64 {
    let edges = EdgeList::new(mesh);
    let total: f64 =
        edges.edges.iter().map(|&[a, b]| norm(sub(mesh.points()[a as usize], mesh.points()[b as usize]))).sum();
    total / edges.edges.len().max(1) as f64
}

/// `scale Σ_i w_i ‖z_i − z_i⁰‖²`.
fn add_fitting_term(
    system: &mut BlockSystem<2>,
    normals: &[[f64; 3]],
    reference: &[[f64; 3]],
    field: &[[f64; 3]],
    weights: &[f64],
    k: f64,
    scale: f64,
) {
    for b in 0..system.blocks() {
        let v = system.vertex_of[b] as usize;
        let alpha0 = k * angle_from(reference[v], tangent_part(field[v], normals[v]), normals[v]);
        let w = scale * weights[v];
        system.diag[b][0][0] += w;
        system.diag[b][1][1] += w;
        system.rhs[b] = [w * alpha0.cos(), w * alpha0.sin()];
        system.constant += w;
    }
}

/// β: the angle from H_a to H_b. Eq. 22 measures it between the 3D vectors about the
/// triangle normal; we first carry H_a to b's tangent plane by the smallest rotation taking N_a
/// to N_b ([`transport`]) and measure about N_b. This discrete Levi-Civita connection has the
/// holonomy of the Gauss image around each triangle, so its curvature sums to 2πχ and the
/// smoothed fields get the singularities the surface demands; with the projected angle the
/// errors, multiplied by k, add spurious singularities to line and cross fields.
pub fn reference_rotation(ha: [f64; 3], na: [f64; 3], hb: [f64; 3], nb: [f64; 3]) -> f64 {
    let t = transport(ha, na, nb);
    dot(cross(t, hb), nb).atan2(dot(t, hb))
}

/// `scale Σ_T Σ_e λ_e ‖z_b − rot(−kβ_e) z_a‖²` (eq. 22).
fn add_smoothing_term(
    system: &mut BlockSystem<2>,
    mesh: &TriMesh,
    edges: &EdgeList,
    normals: &[[f64; 3]],
    reference: &[[f64; 3]],
    k: f64,
    scale: f64,
) {
    for t in 0..mesh.triangle_count() {
        let tri = mesh.triangles()[t];
        let weights = triangle_weights(mesh, t).map(|w| w * scale);
        let rotations: [c64; 3] = std::array::from_fn(|i| {
            let (a, b) = (tri[(i + 1) % 3] as usize, tri[(i + 2) % 3] as usize);
            let beta = reference_rotation(reference[a], normals[a], reference[b], normals[b]);
            c64::new((-k * beta).cos(), (-k * beta).sin())
        });
        let mut h = edge_sum_form(weights, rotations);
        if weights.iter().any(|&w| w < 0.0) {
            h = project_semidefinite(h);
        }
        for c in 0..3 {
            for d in c..3 {
                let z = h[c][d];
                let q = [[z.re, -z.im], [z.im, z.re]];
                if c == d {
                    system.add_diagonal(tri[c], &q);
                } else {
                    let e = if d == (c + 1) % 3 { 3 * t + c } else { 3 * t + d };
                    system.add_pair(edges.edge_of[e], tri[c], tri[d], &q);
                }
            }
        }
    }
}
