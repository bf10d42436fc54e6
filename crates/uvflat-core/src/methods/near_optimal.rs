//! Near-optimal maps (Desbrun–Meyer–Alliez 2002 §5.1, eq. 8): the map of least edge-length or
//! area distortion ([`super::length_area_distortion`]) among
//! `U(λ) = λ·U^A + (1 − λ)·U^χ`, the line through the discrete conformal map U^A (DCP, eq. 4)
//! and the discrete authalic map U^χ (DAP, eq. 6) with the same fixed boundary.
//!
//! On that line the energy is an exact polynomial in λ (degree 4 for edge lengths, 8 for areas),
//! so its minimum over the allowed λ range is found by root finding on dE/dλ and comparing the
//! roots with the range's ends ([`uvflat_sparse::polynomial::Polynomial::minimum_on`]); the
//! energies of λ = 0 (DAP) and λ = 1 (DCP), evaluated directly, are also compared, so the result
//! is never worse than either base map when they are in the range.
//!
//! Both energies compare UV lengths or areas with 3D ones, so the boundary must be at the
//! surface's scale: a circle or square boundary is scaled so that the DCP map's UV area equals
//! the surface area (caller-given boundary positions are used as they are). Cost: two
//! fixed-boundary maps (one Cholesky, one LU factorization) and O(edges) for the polynomial.

use super::barycentric::{fixed_boundary_map_with_progress, FixedBoundaryOptions, Weights};
use super::length_area_distortion::{DistortionEnergy, DistortionTerms};
use crate::boundary::{BoundaryShape, Distribution};
use crate::error::{Error, Result};
use crate::mesh::TriMesh;
use crate::metrics::{signed_uv_area, triangle_is_degenerate_2d};
use crate::progress::Progress;

/// Options of [`near_optimal_map`].
#[derive(Debug, Clone, PartialEq)]
pub struct NearOptimalOptions {
    /// The energy to minimize.
    pub energy: DistortionEnergy,
    /// Boundary of both base maps (circle and square are scaled to the surface area).
    pub shape: BoundaryShape,
    /// Spacing of the boundary vertices along a circle or square.
    pub distribution: Distribution,
    /// Smallest λ allowed (may be −∞).
    pub lambda_min: f64,
    /// Largest λ allowed (may be +∞).
    pub lambda_max: f64,
}

impl Default for NearOptimalOptions {
    fn default() -> Self {
        NearOptimalOptions {
            energy: DistortionEnergy::EdgeLength,
            shape: BoundaryShape::Circle,
            distribution: Distribution::ChordLength,
            lambda_min: f64::NEG_INFINITY,
            lambda_max: f64::INFINITY,
        }
    }
}

/// The chosen map and its energy.
#[derive(Debug, Clone)]
pub struct NearOptimalMap {
    /// `λ·U^A + (1 − λ)·U^χ`, one UV per vertex (NaN for unreferenced vertices).
    pub uv: Vec<[f64; 2]>,
    /// The minimizing λ.
    pub lambda: f64,
    /// The energy at λ.
    pub energy: f64,
    /// The energy of the DCP map (λ = 1).
    pub energy_conformal: f64,
    /// The energy of the DAP map (λ = 0).
    pub energy_authalic: f64,
    /// Factor applied to the circle or square boundary (1 for given positions).
    pub boundary_scale: f64,
    /// Triangles of the result that are clockwise or degenerate in UV (λ outside [0, 1]
    /// extrapolates and can fold; restrict the λ range to avoid that).
    pub flipped: usize,
    /// `λ ↦ E(U(λ))`, exactly.
    pub energy_polynomial: uvflat_sparse::polynomial::Polynomial,
}

/// The near-optimal map of `mesh` (a disk, possibly with holes).
pub fn near_optimal_map(
    mesh: &TriMesh,
    options: &NearOptimalOptions,
    progress: &mut Progress,
) -> Result<NearOptimalMap> {
    let (lo, hi) = (options.lambda_min, options.lambda_max);
    if lo.is_nan() || hi.is_nan() || lo > hi || lo == f64::INFINITY || hi == f64::NEG_INFINITY {
        return Err(Error::InvalidArgument(format!("the λ range [{lo}, {hi}] is empty or not a number")));
    }
    let base =
        |weights| FixedBoundaryOptions { weights, shape: options.shape.clone(), distribution: options.distribution };
    let mut conformal = fixed_boundary_map_with_progress(mesh, &base(Weights::Conformal), progress)?;
    let mut authalic = fixed_boundary_map_with_progress(mesh, &base(Weights::Authalic), progress)?;
    let boundary_scale = match options.shape {
        BoundaryShape::Given(_) => 1.0,
        BoundaryShape::Circle | BoundaryShape::Square => area_matching_scale(mesh, &conformal)?,
    };
    for p in conformal.iter_mut().chain(authalic.iter_mut()) {
        p[0] *= boundary_scale;
        p[1] *= boundary_scale;
    }
    let terms = DistortionTerms::new(mesh);
    let direction: Vec<[f64; 2]> = conformal.iter().zip(&authalic).map(|(a, x)| [a[0] - x[0], a[1] - x[1]]).collect();
    let polynomial = terms.along_line(options.energy, &authalic, &direction);
    let at = |lambda: f64| -> Vec<[f64; 2]> {
        authalic.iter().zip(&direction).map(|(x, d)| [x[0] + lambda * d[0], x[1] + lambda * d[1]]).collect()
    };
    let (root, _) = polynomial.minimum_on(lo, hi).ok_or_else(|| {
        Error::Numerical("the distortion energy is not bounded below on the λ range (non-finite UVs?)".into())
    })?;
    let energy_conformal = terms.energy(options.energy, &conformal);
    let energy_authalic = terms.energy(options.energy, &authalic);
    // The polynomial's minimum, checked against the two base maps evaluated directly.
    let mut best = (root, terms.energy(options.energy, &at(root)));
    for (lambda, e) in [(1.0, energy_conformal), (0.0, energy_authalic)] {
        if lambda >= lo && lambda <= hi && e < best.1 {
            best = (lambda, e);
        }
    }
    if !best.1.is_finite() {
        return Err(Error::Numerical(format!("the near-optimal map's energy is {}", best.1)));
    }
    progress.report(1.0)?;
    let uv = at(best.0);
    let flipped = mesh
        .triangles()
        .iter()
        .filter(|t| {
            let q = t.map(|v| uv[v as usize]);
            triangle_is_degenerate_2d(q) || signed_uv_area(q) < 0.0
        })
        .count();
    Ok(NearOptimalMap {
        uv,
        flipped,
        lambda: best.0,
        energy: best.1,
        energy_conformal,
        energy_authalic,
        boundary_scale,
        energy_polynomial: polynomial,
    })
}

/// The factor making the UV area of `uv` (summed signed areas of the mesh's triangles) equal to
/// the surface area.
pub fn area_matching_scale(mesh: &TriMesh, uv: &[[f64; 2]]) -> Result<f64> {
    let uv_area: f64 = mesh
        .triangles()
        .iter()
        .map(|t| signed_uv_area([uv[t[0] as usize], uv[t[1] as usize], uv[t[2] as usize]]))
        .sum();
    let surface: f64 = mesh.geometry().area.iter().sum();
    let scale = (surface / uv_area).sqrt();
    if uv_area > 0.0 && scale.is_finite() && scale > 0.0 {
        Ok(scale)
    } else {
        Err(Error::Numerical(format!(
            "the boundary encloses a UV area of {uv_area}; it cannot be scaled to the surface"
        )))
    }
}
