//! QuadCover's default frame field: a smooth cross field per triangle aligned with the principal
//! curvature directions where the surface is anisotropic. The course notes (§8.1, §8.4) take
//! "a user-given frame field, such as principal curvature directions" after smoothing; this
//! file smooths on the triangles themselves, where QuadCover's frames live, with one linear
//! solve in the representation of a cross by the 4th power of a unit complex number (the
//! representation of Knöppel, Crane, Pinkall & Schröder 2013, "Globally optimal direction
//! fields", §4–5, read for the formulation; no code of theirs is used):
//!
//! ```text
//! min_z  Σ_e w_e |z_g − r_e z_f|²  +  s Σ_f A_f |z_f − q_f|²
//! ```
//!
//! - z_f ∈ ℂ per triangle, in the triangle's basis (x = its first edge, y = n × x); the cross
//!   is arg(z_f)/4 + k·π/2;
//! - r_e = e^{4i(a_g − a_f)}, a_f and a_g the angles of the shared edge in the two bases (the
//!   unfolding transport of [`super::matching`]);
//! - w_e = |e| / |c_f − c_g| (the dual edge over the primal: the Dirichlet energy of a
//!   piecewise constant field, positive also on obtuse triangles);
//! - q_f = the mean over the corners of ŵ_v e^{4iψ_v}, ψ_v the angle of the vertex's maximum
//!   curvature direction in the triangle's plane and ŵ_v PGP's anisotropy weight
//!   ([`crate::fields::smoothing::anisotropy_weights`]) over its mean;
//! - s = α / h², h the grid spacing: the field follows curvature directions over features
//!   larger than about a grid cell and is smooth below (α = [`DEFAULT_ALIGNMENT`]).
//!
//! The normal equations are Hermitian positive definite whenever some q_f ≠ 0 (one sparse
//! Cholesky solve). Where the surface is umbilic everywhere (a plane, a sphere) q vanishes and
//! so does z; the caller's field is then required.

use crate::error::{Error, Result};
use crate::fields::curvature::PrincipalCurvatures;
use crate::fields::frames::{normalized, triangle_normal};
use crate::fields::smoothing::anisotropy_weights;
use crate::geometry::{cross, distance, dot, norm, sub};
use crate::mesh::NONE;
use crate::TriMesh;
use faer::{c64, Mat};
use uvflat_sparse::{CholeskySolver, TripletBuilder};

/// Default α of the alignment weight s = α / h².
pub const DEFAULT_ALIGNMENT: f64 = 1.0;

/// The basis (x, y) of triangle t's plane: x along its first edge.
pub(super) fn basis(mesh: &TriMesh, t: usize) -> ([f64; 3], [f64; 3]) {
    let tri = mesh.triangles()[t];
    let x = normalized(sub(mesh.points()[tri[1] as usize], mesh.points()[tri[0] as usize]));
    (x, cross(triangle_normal(mesh, t), x))
}

/// Angle of the tangent vector `v` in the basis `b`.
pub(super) fn angle_in(v: [f64; 3], b: ([f64; 3], [f64; 3])) -> f64 {
    dot(v, b.1).atan2(dot(v, b.0))
}

/// Centroid of triangle `t`.
pub(super) fn centroid(mesh: &TriMesh, t: usize) -> [f64; 3] {
    let p = mesh.triangles()[t].map(|v| mesh.points()[v as usize]);
    std::array::from_fn(|d| (p[0][d] + p[1][d] + p[2][d]) / 3.0)
}

/// The smoothed, curvature-aligned cross field (module comment): one unit tangent vector per
/// triangle. `alignment` is α, `spacing` the grid spacing h.
pub fn curvature_cross_field(
    mesh: &TriMesh,
    curvatures: &PrincipalCurvatures,
    spacing: f64,
    alignment: f64,
) -> Result<Vec<[f64; 3]>> {
    if !(alignment.is_finite() && alignment > 0.0) {
        return Err(Error::InvalidArgument(format!("the field alignment must be finite and > 0 (got {alignment})")));
    }
    let nt = mesh.triangle_count();
    let bases: Vec<_> = (0..nt).map(|t| basis(mesh, t)).collect();
    let targets = alignment_targets(mesh, curvatures, &bases);
    if targets.iter().all(|q| q.norm() < 1e-12) {
        return Err(Error::InvalidArgument(
            "the surface has no anisotropic curvature to align a frame field with; give a field".into(),
        ));
    }
    let s = alignment / (spacing * spacing);
    let mut builder = TripletBuilder::<c64>::with_capacity(nt, 4 * nt);
    let mut rhs = Mat::<c64>::zeros(nt, 1);
    let geometry = mesh.geometry();
    for f in 0..nt {
        let a = s * geometry.area[f];
        builder.add(f, f, c64::new(a, 0.0));
        rhs[(f, 0)] = targets[f] * a;
    }
    for e in interior_edges(mesh, &bases).0.iter().filter(|e| e.weight > 0.0) {
        let (f, t, w) = (e.f as usize, e.g as usize, e.weight);
        let r = c64::cis(-e.transport);
        builder.add(f, f, c64::new(w, 0.0));
        builder.add(t, t, c64::new(w, 0.0));
        // Entry (t, f) = −w r, entry (f, t) its conjugate; only the lower one is read.
        if t > f {
            builder.add(t, f, -r * w);
        } else {
            builder.add(f, t, -r.conj() * w);
        }
    }
    let solver = CholeskySolver::new(&builder.build()?, None)
        .map_err(|e| Error::Numerical(format!("QuadCover: the frame field system could not be factored: {e}")))?;
    solver.solve_in_place(&mut rhs)?;
    Ok((0..nt)
        .map(|f| {
            let z = rhs[(f, 0)];
            let theta = if z.norm() > 0.0 { z.arg() / 4.0 } else { 0.0 };
            let (x, y) = bases[f];
            std::array::from_fn(|d| theta.cos() * x[d] + theta.sin() * y[d])
        })
        .collect())
}

/// One interior edge: its key half-edge `key` (the one of the lower index, in triangle f; the
/// twin in g), the transport term c_e = −4 (a_g − a_f) (a_f, a_g the edge's angles in the two
/// bases; r_e = e^{−i c_e}) and the weight w_e = |e| / |c_f − c_g| (0 where not finite).
pub(super) struct InteriorEdge {
    pub key: u32,
    pub f: u32,
    pub g: u32,
    pub transport: f64,
    pub weight: f64,
}

/// Every interior edge once, and the edge index of every half-edge (NONE on the boundary).
pub(super) fn interior_edges(mesh: &TriMesh, bases: &[([f64; 3], [f64; 3])]) -> (Vec<InteriorEdge>, Vec<u32>) {
    let twin = &mesh.connectivity().twin;
    let mut edge_of = vec![NONE; twin.len()];
    let mut edges = Vec::new();
    for (h, &g) in twin.iter().enumerate() {
        if g == NONE || (g as usize) < h {
            continue;
        }
        let (f, t) = (h / 3, g as usize / 3);
        let e = sub(mesh.points()[mesh.head(h as u32) as usize], mesh.points()[mesh.tail(h as u32) as usize]);
        let weight = norm(e) / distance(centroid(mesh, f), centroid(mesh, t)).max(1e-300);
        let transport = -4.0 * (angle_in(e, bases[t]) - angle_in(e, bases[f]));
        edge_of[h] = edges.len() as u32;
        edge_of[g as usize] = edges.len() as u32;
        let weight = if weight.is_finite() { weight } else { 0.0 };
        edges.push(InteriorEdge { key: h as u32, f: f as u32, g: t as u32, transport, weight });
    }
    (edges, edge_of)
}

/// q_f (module comment).
fn alignment_targets(mesh: &TriMesh, c: &PrincipalCurvatures, bases: &[([f64; 3], [f64; 3])]) -> Vec<c64> {
    let weights = anisotropy_weights(mesh, c);
    let referenced: Vec<f64> =
        (0..mesh.vertex_count() as u32).filter(|&v| mesh.is_referenced(v)).map(|v| weights[v as usize]).collect();
    let mean = referenced.iter().sum::<f64>() / referenced.len().max(1) as f64;
    let scale = if mean > 0.0 { 1.0 / mean } else { 0.0 };
    (0..mesh.triangle_count())
        .map(|t| {
            mesh.triangles()[t].iter().fold(c64::new(0.0, 0.0), |acc, &v| {
                let psi = angle_in(c.kmax_direction[v as usize], bases[t]);
                acc + c64::cis(4.0 * psi) * (weights[v as usize] * scale / 3.0)
            })
        })
        .collect()
}
