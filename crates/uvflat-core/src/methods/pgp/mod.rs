//! Periodic Global Parameterization (Ray, Li, Lévy, Sheffer, Alliez 2006, ACM TOG 25(4)):
//! two periodic functions θ, φ whose gradients follow a pair of orthogonal fields (by default
//! the principal curvature directions), on meshes of any genus, with or without boundary,
//! without cutting. One file per step:
//!
//! - [`crate::fields::curvature`]: principal directions (Cohen-Steiner & Morvan 2003 normal-cycle tensor);
//! - [`crate::fields::smoothing`]: vector field smoothing modulo 2π, π or π/2 (§4.2, eqs. 21–22);
//! - [`crate::fields::pairs`]: ± quarter singularities of the smoothed field closer than half a period
//!   cancelled together (not in the paper; optional, on by default);
//! - [`curl`]: curl correction (§4.1, eqs. 17–20);
//! - [`density`]: the field scaled up on curved features narrower than a few periods (not in
//!   the paper; optional, on by default);
//! - [`periodic`]: the periodic energy (§2.3–2.4, eqs. 13–15, Appendix B eq. 24);
//! - [`crate::fields::block_newton`]: its minimization (§2.5: linear solve, then Newton on F** with the penalty);
//! - [`dislocations`]: open triangles of opposite winding where the field is regular annihilated
//!   in pairs, lone ones moved into a singular triangle of the field (not in the paper;
//!   optional, on by default);
//! - [`extraction`]: per-triangle (θ, φ) at the corners (§3.1, Algorithm 1);
//! - [`relax`]: every vertex's phases turned by the least-squares fit of the (θ, φ) triangles to
//!   the field with Algorithm 1's integers kept, where that leaves fewer singular triangles (not
//!   in the paper; optional, on by default);
//! - [`untangle`]: negative (θ, φ) triangles next to singular points made positive by moving
//!   vertex phases, every transition kept (not in the paper; optional, on by default);
//! - [`singularities`]: singular vertices, edges, triangles and indices (§3.2);
//! - [`quality`]: singular-triangle fraction, stretch, shear, alignment (Table I);
//! - [`forced`]: the fewest singular triangles any PGP parameterization of a mesh can have
//!   (Hopf–Poincaré and the rotation matching; a bound to compare the fraction with);
//! - [`isolines`]: the graph of iso-lines on the surface (§3.3 Algorithm 2, and §5's density);
//! - [`layout`]: the chart layout, chart boundaries along the iso-2kπ lines (§3.3);
//! - [`remesh`]: the quad-dominant remesh (§5);
//! - [`crate::fields::frames`]: tangent frames and rotation matching shared by the steps;
//! - [`refine`]: the chart boundaries inserted into the triangulation (§3.3);
//! - [`charts`]: the per-chart parameterization: charts assembled, singular ones
//!   re-parameterized by mean-value coordinates (§3.4);
//! - [`split`]: N-sided singular charts split into quads (§3.4).
//!
//! Pipeline of [`pgp`]: field (curvature directions or the caller's) → optional smoothing →
//! optional singularity-pair cancellation → optional curl correction → optional feature-adaptive density → periodic solve →
//! optional dislocation annihilation → per-corner (θ, φ) → optional relaxation → optional
//! untangling → singularities.

pub mod charts;
pub(crate) mod curl;
pub mod density;
pub mod dislocations;
pub mod extraction;
pub mod forced;
pub mod isolines;
pub(crate) mod layout;
mod mean_value_chart;
pub mod periodic;
pub mod quality;
pub(crate) mod refine;
pub(crate) mod relax;
pub(crate) mod remesh;
pub mod singularities;
pub(crate) mod split;
pub mod untangle;

use crate::error::{Error, Result};
use crate::fields::block_newton::{NewtonOptions, SolveReport};
use crate::fields::curvature::{principal_curvatures, CurvatureOptions};
use crate::fields::frames::{normalized, scale, tangent_part};
use crate::fields::smoothing::{mean_edge_length, smooth_field, SmoothingOptions};
use crate::progress::Progress;
use crate::TriMesh;
use extraction::{corner_parameterization, CornerParameterization};
use singularities::{find_singularities, Singularities};

/// Periods per chart edge used by [`default_omega`]: "we set ω to ten times the average edge
/// length" (§2.2), read as one 2π period per ten mean edge lengths.
pub const EDGES_PER_PERIOD: f64 = 10.0;

/// Options of [`pgp`].
#[derive(Debug, Clone, PartialEq)]
pub struct PgpOptions {
    /// ω, the frequency: θ grows by ω per unit length along K, so a chart (one 2π period) is
    /// 2π/ω long. `None`: [`default_omega`].
    pub omega: Option<f64>,
    /// The field K per vertex (3 coordinates, projected on the tangent plane, only its
    /// direction is used). `None`: the maximum principal curvature direction.
    pub field: Option<Vec<[f64; 3]>>,
    /// Curvature estimation (also used for the smoothing's anisotropy weights).
    pub curvature: CurvatureOptions,
    /// Field smoothing (§4.2); `None` skips it. Default: modulo π/2, ρ = 0.8.
    pub smoothing: Option<SmoothingOptions>,
    /// Curl correction (§4.1).
    pub curl_correction: bool,
    /// Minimum number of periods around a curved feature ([`density`], not in the paper): the
    /// field is scaled by up to [`density::MAX_DENSITY`] where a curvature radius r gives fewer
    /// than `feature_periods` periods ω r. Default [`density::DEFAULT_FEATURE_PERIODS`] = 3;
    /// 0 keeps the paper's single ω everywhere.
    pub feature_periods: f64,
    /// Singularity-pair cancellation ([`pairs`], not in the paper): ± quarter singularities of
    /// the smoothed field closer than `pair_periods` periods (2π/ω) are removed together.
    /// Default [`crate::fields::pairs::DEFAULT_PAIR_PERIODS`]; 0 keeps the smoothed field's singularities.
    pub pair_periods: f64,
    /// Untangle the per-corner (θ, φ) after Algorithm 1 ([`untangle`], not in the paper):
    /// negative triangles next to singular points made positive without changing any
    /// transition. Default true; false gives Algorithm 1's output as it is.
    pub untangle: bool,
    /// Global phase relaxation before the untangling ([`relax`], not in the paper): every
    /// vertex's phases turned by the least-squares fit of the (θ, φ) triangles to the field with
    /// every integer of Algorithm 1 kept, used only when it leaves no more singular triangles.
    /// Default true.
    pub relax: bool,
    /// Dislocation-pair annihilation ([`dislocations`], not in the paper): open triangles of
    /// opposite winding where the field is regular, closer than `dislocation_periods` periods,
    /// removed together by turning the phases around them, and lone ones moved into a nearby
    /// singular triangle of the field. Default
    /// [`dislocations::DEFAULT_DISLOCATION_PERIODS`]; 0 keeps the periodic solve's phases.
    pub dislocation_periods: f64,
    /// Periodic solve: ε (default [`crate::fields::block_newton::PERIODIC_EPSILON`] = 0.1; paper 10⁻³), gradient
    /// tolerance (10⁻⁶), iterations ([`crate::fields::block_newton::PERIODIC_ITERATIONS`] = 100).
    pub newton: NewtonOptions,
}

impl Default for PgpOptions {
    fn default() -> Self {
        PgpOptions {
            omega: None,
            field: None,
            curvature: CurvatureOptions::default(),
            smoothing: Some(SmoothingOptions::default()),
            curl_correction: false,
            feature_periods: density::DEFAULT_FEATURE_PERIODS,
            pair_periods: crate::fields::pairs::DEFAULT_PAIR_PERIODS,
            untangle: true,
            relax: true,
            dislocation_periods: dislocations::DEFAULT_DISLOCATION_PERIODS,
            newton: NewtonOptions::default(),
        }
    }
}

/// Everything PGP computes.
#[derive(Debug, Clone)]
pub struct PgpResult {
    /// (θ, φ) at the corners of every triangle and the integer data behind them.
    pub param: CornerParameterization,
    /// Singular elements and indices.
    pub singularities: Singularities,
    /// The field K used by the periodic solve, per vertex (after smoothing; times the
    /// curl-correction scale when enabled and the feature-adaptive density factor).
    pub field: Vec<[f64; 3]>,
    /// Unit vertex normals.
    pub normals: Vec<[f64; 3]>,
    /// The frequency used.
    pub omega: f64,
    /// X = (cos θ, sin θ, cos φ, sin φ) per vertex, from the periodic solve (with the untangling
    /// its phases are turned so that they still give `param` through Algorithm 1's integers).
    pub unknowns: Vec<[f64; 4]>,
    /// The periodic solve's report.
    pub solve: SolveReport,
    /// The smoothing solve's report, when smoothing ran.
    pub smoothing: Option<SolveReport>,
    /// What the untangling of the per-corner (θ, φ) did ([`untangle`]).
    pub untangled: untangle::UntangleReport,
    /// What the phase relaxation did ([`relax`]; all zero when it was off).
    pub relaxed: relax::RelaxReport,
    /// What the singularity-pair cancellation did ([`pairs`]).
    pub pairs: crate::fields::pairs::PairReport,
    /// What the dislocation-pair annihilation did ([`dislocations`]).
    pub dislocations: dislocations::DislocationReport,
}

/// ω = 2π / (10 × mean edge length) (see [`EDGES_PER_PERIOD`]).
pub fn default_omega(mesh: &TriMesh) -> f64 {
    std::f64::consts::TAU / (EDGES_PER_PERIOD * mean_edge_length(mesh))
}

/// Runs PGP (module comment). Errors: bad options or field (naming the vertex), numerical
/// failures, cancellation.
pub fn pgp(mesh: &TriMesh, options: &PgpOptions, progress: &mut Progress) -> Result<PgpResult> {
    let omega = match options.omega {
        None => default_omega(mesh),
        Some(w) if w.is_finite() && w > 0.0 => w,
        Some(w) => return Err(Error::InvalidArgument(format!("omega must be finite and > 0 (got {w})"))),
    };
    if !(options.feature_periods.is_finite() && options.feature_periods >= 0.0) {
        return Err(Error::InvalidArgument(format!(
            "feature_periods must be finite and >= 0 (got {})",
            options.feature_periods
        )));
    }
    if !(options.dislocation_periods.is_finite() && options.dislocation_periods >= 0.0) {
        return Err(Error::InvalidArgument(format!(
            "dislocation_periods must be finite and >= 0 (got {})",
            options.dislocation_periods
        )));
    }
    if !(options.pair_periods.is_finite() && options.pair_periods >= 0.0) {
        return Err(Error::InvalidArgument(format!(
            "pair_periods must be finite and >= 0 (got {})",
            options.pair_periods
        )));
    }
    progress.report(0.0)?;
    let curvatures = principal_curvatures(mesh, &options.curvature)?;
    let normals = curvatures.normal.clone();
    let mut field = match &options.field {
        Some(f) => tangent_field(mesh, &normals, f)?,
        None => curvatures.kmax_direction.clone(),
    };
    progress.report(0.1)?;
    let smoothing = match &options.smoothing {
        Some(s) => {
            let (smoothed, report) = smooth_field(mesh, &curvatures, &field, s, progress, (0.1, 0.3))?;
            field = smoothed;
            Some(report)
        }
        None => None,
    };
    let pairs = if options.pair_periods > 0.0 {
        let distance = options.pair_periods * std::f64::consts::TAU / omega;
        let (cancelled, report) =
            crate::fields::pairs::cancel_singularity_pairs(mesh, &normals, &field, distance, omega)?;
        field = cancelled;
        report
    } else {
        crate::fields::pairs::PairReport::default()
    };
    if options.curl_correction {
        let v = curl::curl_correction_scale(mesh, &normals, &field)?;
        field = scaled_field(&field, &v);
    }
    if options.feature_periods > 0.0 {
        let s = density::density_scale(mesh, &curvatures.kmin, &curvatures.kmax, omega, options.feature_periods);
        field = scaled_field(&field, &s);
    }
    progress.report(0.35)?;
    let (mut unknowns, solve) =
        periodic::periodic_solve(mesh, &normals, &field, omega, &options.newton, progress, (0.35, 0.95))?;
    let dislocations = if options.dislocation_periods > 0.0 {
        let distance = options.dislocation_periods * std::f64::consts::TAU / omega;
        dislocations::annihilate_dislocations(mesh, &normals, &field, &mut unknowns, omega, distance)?
    } else {
        dislocations::DislocationReport::default()
    };
    let mut param = corner_parameterization(mesh, &normals, &field, &unknowns, omega);
    let (untangled, relaxed) = if options.relax {
        relax::relax_if_better(mesh, &normals, &field, &mut param, &mut unknowns, omega, options.untangle)?
    } else {
        let report = relax::untangled(mesh, &mut param, &mut unknowns, &field, omega, options.untangle);
        (report, relax::RelaxReport::default())
    };
    let singularities = find_singularities(mesh, &param);
    progress.report(1.0)?;
    Ok(PgpResult {
        param,
        singularities,
        field,
        normals,
        omega,
        unknowns,
        solve,
        smoothing,
        untangled,
        relaxed,
        pairs,
        dislocations,
    })
}

/// `field` with each vertex's vector times its factor in `factors`.
fn scaled_field(field: &[[f64; 3]], factors: &[f64]) -> Vec<[f64; 3]> {
    field.iter().zip(factors).map(|(&k, &s)| scale(k, s)).collect()
}

/// The caller's field projected on the tangent planes and normalized; errors name the first
/// referenced vertex whose vector is not finite or has no tangent part.
fn tangent_field(mesh: &TriMesh, normals: &[[f64; 3]], field: &[[f64; 3]]) -> Result<Vec<[f64; 3]>> {
    if field.len() != mesh.vertex_count() {
        return Err(Error::InvalidArgument(format!(
            "the field has {} vectors but the mesh has {} vertices",
            field.len(),
            mesh.vertex_count()
        )));
    }
    let mut out = vec![[0.0; 3]; field.len()];
    for v in 0..field.len() {
        if !mesh.is_referenced(v as u32) {
            continue;
        }
        let k = field[v];
        if !k.iter().all(|c| c.is_finite()) {
            return Err(Error::InvalidArgument(format!("field vector of vertex {v} is not finite: {k:?}")));
        }
        let t = tangent_part(k, normals[v]);
        let len = crate::geometry::norm(t);
        if len <= 1e-9 * crate::geometry::norm(k) || len == 0.0 {
            return Err(Error::InvalidArgument(format!(
                "field vector of vertex {v} ({k:?}) has no component tangent to the surface"
            )));
        }
        out[v] = normalized(t);
    }
    Ok(out)
}

pub use isolines::PeriodicMap;
pub use layout::{chart_layout, ChartLayout};
pub use remesh::{quad_dominant_remesh, quad_dominant_remesh_of, PolygonMesh};
