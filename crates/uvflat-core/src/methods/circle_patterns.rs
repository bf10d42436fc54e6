//! Conformal parameterization by circle patterns (Kharevych, Springborn & Schröder 2006,
//! "Discrete conformal mappings via circle patterns", ACM TOG 25(2); course notes 2008 §4.4,
//! Figure 4.3), for disks (holes allowed) with a free or prescribed boundary
//! ([`polygon_boundary_curvature`]), with cone singularities on meshes of any genus
//! ([`circle_pattern_cone_map`]), and over the sphere for closed genus-0 meshes
//! ([`circle_pattern_sphere_map`], `sphere.rs`).
//!
//! One circle per triangle, the circumcircle; two circles meet at the two ends of their common
//! edge. For the triangle angles α (α_a at corner a, opposite the edge e(a)) the *intersection
//! angle* of edge e is θ_e = α_a + α_b (the two corners opposite e) for an interior edge and
//! θ_e = α_a on the boundary: in the kite (centre f, vertex i, centre g, vertex j) of an
//! interior edge the angles at the centres are φ_f + φ_g = θ_e and the angle at each vertex
//! is π − θ_e. Given θ, the pattern is determined by the log radii ρ_f (paper §3): the law of
//! sines in the kite, r_g / r_f = sin φ_f / sin φ_g, gives
//!
//! ```text
//! φ_f(x) = atan2(eˣ sin θ, 1 + eˣ cos θ),   x = ρ_g − ρ_f,   dφ_f/dx = sin θ / (2 (cosh x + cos θ)),
//! ```
//!
//! and the circle of f closes when Σ_{e ∈ f} φ_{e,f} = π (boundary edges: φ = θ_e). These are
//! the critical-point equations of the paper's convex energy E(ρ) (eq. 5, the sum of
//! Im Li₂ terms; its Hessian is the weighted dual Laplacian with weights dφ/dx > 0), so the
//! radii are its unique minimizer up to a common scale. The pattern's triangle angles are then
//! the φ (the inscribed angle opposite e is half the central angle 2 φ_{e,f}), they sum to 2π
//! around every interior vertex whenever the α do (Σ_e (π − θ_e) = Σ α at the vertex), and the
//! edge lengths 2 r_f sin φ_{e,f} agree from both sides: a planar triangulation with every
//! angle in (0, π) — a local immersion, no flipped triangle.
//!
//! The angles α come from the paper's quadratic program (§4, course notes §4.4): minimize
//! Σ (α_a − β_a)² / β_a² (β = the 3D angles) subject to the triangle sums π, the interior
//! vertex sums 2π, α > 0 and the local Delaunay condition α_a + α_b < π on every interior edge
//! (θ_e < π). The paper hands it to a QP solver; here a primal–dual interior-point method
//! solves it (`angle_ipm.rs`, 6–10 iterations), and where rounding stops that, a log-barrier
//! method: Newton steps on t·f(α) − Σ ln α_a − Σ_e ln(π − α_a − α_b) under the linear
//! equalities, t × 100 from 1 to 10⁸. Each corner is opposite one edge, so the Hessian of
//! either is diagonal with 2×2 blocks (the two corners of an interior edge), and each step
//! solves the Schur complement J H⁻¹ Jᵀ over triangles and constrained vertices by sparse
//! Cholesky.
//! As in the paper (§4), the edges are first flipped to an intrinsic Delaunay triangulation of
//! the mesh's metric ([`crate::mesh::intrinsic_delaunay`], on by default), so that the 3D
//! angles already meet the Delaunay condition and θ is a conformal invariant: the program then
//! only moves the angles to flatten the vertices. The pattern is that of the flipped
//! triangulation, whose vertices are the mesh's: the mesh's triangles take the uv of their
//! vertices, which is no longer guaranteed to be free of flips (the flipped edges are straight
//! in the plane, the mesh's own edges are not), so the report counts the mesh's flipped
//! triangles. Without the flips the Delaunay condition is enforced on the mesh as given, which
//! moves the angles of non-Delaunay edges away from their 3D values but never flips.
//!
//! The planar layout is the least-squares reconstruction from angles of ABF++
//! ([`super::angle_layout::reconstruct_uv`]), exact here because the angles are those of a planar
//! triangulation. Cost: 40–90 sparse Cholesky factorizations for the angles (order F + V), a
//! few Newton steps on the F radii, one factorization for the layout.

use super::angle_layout::reconstruct_uv;
use super::conformal::{resolve_pins, Pin};
use crate::error::{Error, Result};
use crate::mesh::connectivity::prev;
use crate::mesh::intrinsic_delaunay::{edge_lengths, intrinsic_delaunay_constrained, FlipConstraints};
use crate::mesh::{TriMesh, NONE};
use crate::progress::Progress;
use faer::Mat;
use std::f64::consts::PI;
use uvflat_sparse::{factor_reusing, lower_from_entries, CholeskyPattern, CholeskySolver};

mod angle_ipm;
mod angle_sums;
mod cones;
mod sphere;
pub use angle_sums::polygon_boundary_curvature;
pub use cones::{circle_pattern_cone_map, ConeMapResult};
pub use sphere::circle_pattern_sphere_map;

/// Smallest gap π − θ_e the angle program allows (radians): at θ = π the two circles
/// coincide and the kite's weight sin θ / (2 (cosh x + cos θ)) runs to 0 or ∞.
pub const DELAUNAY_MARGIN: f64 = 0.01;
/// Smallest planar angle the angle program allows (radians).
pub const MIN_ANGLE: f64 = 1e-4;

/// Options of [`circle_pattern_map`].
#[derive(Debug, Clone, PartialEq)]
pub struct CirclePatternOptions {
    /// Two boundary vertices and their uv; `None` pins the farthest boundary pair at (0, 0)
    /// and (d, 0), d their 3D distance (the map is only determined up to a similarity).
    pub pins: Option<[Pin; 2]>,
    /// Newton iterations allowed for the radii, for the primal–dual angle solve (at most 40) and
    /// for every centering of its log-barrier fallback.
    pub max_iterations: u32,
    /// Stop the radii when every circle closes to within this angle (radians), or below 10⁻⁸
    /// when a Newton step no longer halves the largest gap (rounding).
    pub tolerance: f64,
    /// Flip to the intrinsic Delaunay triangulation first (paper §4; default true). Off, the
    /// map never flips a triangle but the non-Delaunay edges' angles are distorted.
    pub intrinsic_delaunay: bool,
    /// Prescribed boundary curvature (paper §5): one value per vertex, the turning angle κ_v
    /// of the uv boundary at boundary vertex v (the uv angle sum there is π − κ_v; 0 keeps the
    /// boundary straight), NaN where the boundary is free; ignored at interior vertices.
    /// `None` (default): free boundary. [`polygon_boundary_curvature`] makes a convex polygon
    /// with given corners.
    pub boundary_curvature: Option<Vec<f64>>,
    /// Keep the uv boundary convex (the paper's inequality constraints on the boundary angles,
    /// course notes §4.4): at every boundary vertex whose curvature is not prescribed, the
    /// turning angle is at least 0 (the angle sum at most π). The pattern is then an embedding
    /// of the triangulation it is built on: a local immersion whose boundary is a closed convex
    /// polygon. Default false.
    pub convex_boundary: bool,
}

impl Default for CirclePatternOptions {
    fn default() -> Self {
        CirclePatternOptions {
            pins: None,
            max_iterations: 100,
            tolerance: 1e-11,
            intrinsic_delaunay: true,
            boundary_curvature: None,
            convex_boundary: false,
        }
    }
}

/// What [`circle_pattern_map`] reports.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CirclePatternReport {
    /// Iterations of the angle program: primal–dual steps, plus the log-barrier Newton steps
    /// where it fell back.
    pub angle_iterations: u32,
    /// Newton steps of the radii.
    pub radius_iterations: u32,
    /// Largest |Σ φ − π| over the circles at the end.
    pub closure_error: f64,
    /// Interior edges of the triangulation used (after the flips, if any) whose angles in the
    /// mesh's metric violate the Delaunay condition (β_a + β_b ≥ π − [`DELAUNAY_MARGIN`]).
    pub non_delaunay_edges: u32,
    /// Largest |α − β| of the planar angles (radians).
    pub max_angle_change: f64,
    /// Intrinsic edge flips made before the program.
    pub intrinsic_flips: u32,
    /// Triangles of the mesh whose uv area is not positive (0 without intrinsic flips).
    pub flipped_triangles: u32,
    /// log₁₀ of the ratio of the largest to the smallest circle radius: how many orders of
    /// magnitude the map's scale spans (3–4 on the free maps of the disk meshes). Beyond about
    /// 12 the layout, in double precision, loses the smallest triangles to rounding (flipped
    /// or degenerate): e.g. a convex boundary forced on a long winding strip, whose conformal
    /// map onto a convex domain shrinks it exponentially along its length.
    pub radius_span: f64,
}

/// Circle-pattern parameterization: one uv per vertex (NaN for unreferenced vertices).
#[derive(Debug, Clone)]
pub struct CirclePatternResult {
    pub uv: Vec<[f64; 2]>,
    pub report: CirclePatternReport,
}

/// The circle-pattern conformal map of a disk (possibly with holes, which are filled for the
/// pattern and the layout: see `fill_holes_for_pattern`), its outer boundary free or shaped by
/// `options.boundary_curvature`.
pub fn circle_pattern_map(
    mesh: &TriMesh,
    options: &CirclePatternOptions,
    progress: &mut Progress,
) -> Result<CirclePatternResult> {
    let mut pins = resolve_pins(mesh, options.pins)?;
    check_tolerance(options)?;
    let (filled, options) = fill_holes_for_pattern(mesh, options)?;
    let disk = filled.as_ref().unwrap_or(mesh);
    if options.pins.is_none() && filled.is_some() {
        // Automatic pins on the filled disk's one loop: the input's farthest boundary pair may
        // sit on a hole, whose vertices are now interior. Measured on holes_chinese_dragon
        // (two 3-vertex loops at the two ends of a long body), without intrinsic flips: the
        // layout folded 10,817 of its triangles with one pin on the filled hole, none with
        // both on the outer loop (the pattern's angles were the same; presumably rounding in
        // the least-squares layout across the body's wide range of scales).
        pins = resolve_pins(disk, None)?;
    }
    let surface = Triangulation::of(disk, &options, &[])?;
    let sums = angle_sums::vertex_sums(&surface.mesh, options.boundary_curvature.as_deref(), &[])?;
    let (angles, mut report) = solve_pattern(&surface, &sums, &options, progress)?;
    let mut uv = reconstruct_uv(&surface.mesh, &angles, pins)?;
    uv.truncate(mesh.vertex_count());
    progress.report(1.0)?;
    report.flipped_triangles = flipped_triangles(mesh, &uv);
    Ok(CirclePatternResult { uv, report })
}

/// A mesh with holes as the disk the pattern is solved on: every loop but the longest closed
/// by a cone of triangles around a virtual vertex ([`crate::mesh::fill::fill_holes`]), and the
/// options with the boundary curvature extended to the virtual vertices. `None` for a disk.
///
/// Why: a planar domain with holes has a layout only if, around each hole, the pattern's
/// developing map closes up — a rotation of −2π in all and no translation. The angle program
/// fixes only the total turning of all the loops (Gauss–Bonnet), and nothing in the radii
/// fixes the translations, so with free holes the pattern generally has no planar layout (on
/// holes_pig the least-squares layout of such a pattern folded 226 triangles). Filled, the
/// holes' vertices are interior and flat, and the layout is exact.
fn fill_holes_for_pattern(
    mesh: &TriMesh,
    options: &CirclePatternOptions,
) -> Result<(Option<TriMesh>, CirclePatternOptions)> {
    let loops = mesh.boundary_loops();
    let Some(outer) = mesh.longest_boundary_loop().filter(|_| loops.len() > 1) else {
        return Ok((None, options.clone()));
    };
    if let Some(curvature) = &options.boundary_curvature {
        let on_hole = loops.iter().enumerate().filter(|(i, _)| *i != outer).flat_map(|(_, lp)| lp);
        if let Some(v) = on_hole.copied().find(|&v| curvature.get(v as usize).is_some_and(|k| !k.is_nan())) {
            return Err(Error::InvalidArgument(format!(
                "boundary curvature is prescribed at vertex {v} of a hole; only the longest loop can be shaped (holes are filled for the layout)"
            )));
        }
    }
    let keep: Vec<bool> = (0..loops.len()).map(|i| i == outer).collect();
    let filled = crate::mesh::fill::fill_holes(mesh, &keep)?;
    let mut options = options.clone();
    if let Some(curvature) = options.boundary_curvature.as_mut() {
        curvature.resize(filled.mesh.vertex_count(), f64::NAN);
    }
    Ok((Some(filled.mesh), options))
}

fn check_tolerance(options: &CirclePatternOptions) -> Result<()> {
    if !(options.tolerance.is_finite() && options.tolerance > 0.0) {
        return Err(Error::InvalidArgument(format!(
            "circle pattern tolerance must be finite and > 0 (got {})",
            options.tolerance
        )));
    }
    Ok(())
}

/// The pattern on `surface` with the angle sums `sums` (NaN: free): the program's angles, the
/// intersection angles, the radii; returns each triangle's pattern angles (corner order) and
/// the report (without the flipped triangles, which depend on the layout).
fn solve_pattern(
    surface: &Triangulation,
    sums: &[f64],
    options: &CirclePatternOptions,
    progress: &mut Progress,
) -> Result<(Vec<[f64; 3]>, CirclePatternReport)> {
    let work = &surface.mesh;
    let beta: Vec<f64> = surface.angles.iter().flatten().copied().collect();
    let bounds = angle_sums::convex_bounds(work, sums, options.convex_boundary)?;
    let program = AngleProgram::new(work, &beta, sums, &bounds);
    // The primal–dual method (6–10 iterations where it converges); the log-barrier path when
    // rounding stops it (active Delaunay constraints by the thousand, see angle_ipm.rs).
    let (mut alpha, angle_iterations) = match program.solve_primal_dual(options.max_iterations, progress)? {
        (Some(alpha), iterations) => (alpha, iterations),
        (None, tried) => {
            let (alpha, iterations) = program.solve(options.max_iterations, progress)?;
            (alpha, tried + iterations)
        }
    };
    alpha.truncate(beta.len());
    progress.report(0.6)?;
    let theta = intersection_angles(work, &alpha);
    let mut rho = circumradius_logs(&surface.lengths, &surface.angles);
    let radius_iterations = solve_radii(work, &theta, &mut rho, options, progress)?;
    let (smallest, largest) = rho.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), r| (a.min(*r), b.max(*r)));
    let phi = kite_angles(work, &theta, &rho);
    let closure_error = phi.iter().map(|p| (p.iter().sum::<f64>() - PI).abs()).fold(0.0, f64::max);
    let angles: Vec<[f64; 3]> = phi.iter().map(|p| [p[1], p[2], p[0]]).collect();
    let report = CirclePatternReport {
        angle_iterations,
        radius_iterations,
        closure_error,
        non_delaunay_edges: program.non_delaunay_edges(&beta),
        max_angle_change: alpha.iter().zip(&beta).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max),
        intrinsic_flips: surface.flips,
        flipped_triangles: 0,
        radius_span: (largest - smallest) / std::f64::consts::LN_10,
    };
    Ok((angles, report))
}

/// The triangulation the pattern is built on, with its edge lengths and angles in the mesh's
/// metric: the mesh itself, or its intrinsic Delaunay triangulation (same vertices).
struct Triangulation {
    mesh: TriMesh,
    /// `lengths[t][k]`: half-edge 3t + k.
    lengths: Vec<[f64; 3]>,
    angles: Vec<[f64; 3]>,
    flips: u32,
}

impl Triangulation {
    /// With `options.intrinsic_delaunay`, the flips keep the `fixed` edges (a cut) and, when
    /// the boundary angle sums are prescribed, leave no boundary vertex in one triangle (its one
    /// angle would have to be the whole sum).
    fn of(mesh: &TriMesh, options: &CirclePatternOptions, fixed: &[[u32; 2]]) -> Result<Self> {
        if !options.intrinsic_delaunay {
            let lengths = edge_lengths(mesh);
            let angles = mesh.corner_angles().to_vec();
            return Ok(Triangulation { mesh: mesh.clone(), lengths, angles, flips: 0 });
        }
        let constraints =
            FlipConstraints { keep_boundary_fans: options.boundary_curvature.is_some(), fixed_edges: fixed };
        let flipped = intrinsic_delaunay_constrained(mesh, &constraints);
        let angles = flipped.corner_angles();
        // Same vertices, a simplicial manifold triangulation of the same surface: the
        // connectivity checks pass; the 3D positions only order the sparse systems.
        let work = TriMesh::from_checked(mesh.points().to_vec(), flipped.triangles)?;
        Ok(Triangulation { mesh: work, lengths: flipped.lengths, angles, flips: flipped.flips })
    }
}

/// Triangles of `mesh` whose uv signed area is not positive.
fn flipped_triangles(mesh: &TriMesh, uv: &[[f64; 2]]) -> u32 {
    let corners: Vec<[[f64; 2]; 3]> = mesh.triangles().iter().map(|t| t.map(|v| uv[v as usize])).collect();
    flipped_triangles_of_corners(&corners)
}

/// Triangles whose corner uv have a signed area that is not positive.
fn flipped_triangles_of_corners(corners: &[[[f64; 2]; 3]]) -> u32 {
    let area = |[a, b, c]: &[[f64; 2]; 3]| (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    corners.iter().filter(|t| !(area(t) > 0.0)).count() as u32
}

/// θ per half-edge (both half-edges of an interior edge get the same value): the sum of the
/// angles opposite the edge, or the one angle on the boundary. The corner opposite half-edge h
/// is `prev(h)` (half-edge h = 3t + k runs from corner k to corner k + 1).
fn intersection_angles(mesh: &TriMesh, alpha: &[f64]) -> Vec<f64> {
    let twin = &mesh.connectivity().twin;
    (0..twin.len() as u32)
        .map(|h| {
            let own = alpha[prev(h) as usize];
            match twin[h as usize] {
                NONE => own,
                t => own + alpha[prev(t) as usize],
            }
        })
        .collect()
}

/// ln of the circumradius of every triangle in the mesh's metric (law of sines on the edge
/// opposite corner 0, half-edge 1): the starting radii (exact for a flat Delaunay mesh).
fn circumradius_logs(lengths: &[[f64; 3]], angles: &[[f64; 3]]) -> Vec<f64> {
    lengths.iter().zip(angles).map(|(l, a)| (l[1] / (2.0 * a[0].sin())).ln()).collect()
}

/// φ_f(x) = atan2(eˣ sin θ, 1 + eˣ cos θ) without overflow, and dφ_f/dx.
fn kite_angle(theta: f64, x: f64) -> (f64, f64) {
    let (s, c) = theta.sin_cos();
    let phi = if x > 0.0 { s.atan2((-x).exp() + c) } else { (x.exp() * s).atan2(1.0 + x.exp() * c) };
    let slope = if x.abs() > 700.0 { 0.0 } else { s / (2.0 * (x.cosh() + c)) };
    (phi, slope)
}

/// The angle φ at the centre of triangle t in the kite of each of its half-edges, `[t][k]`
/// for half-edge 3t + k.
fn kite_angles(mesh: &TriMesh, theta: &[f64], rho: &[f64]) -> Vec<[f64; 3]> {
    let twin = &mesh.connectivity().twin;
    (0..rho.len())
        .map(|t| {
            std::array::from_fn(|k| {
                let h = 3 * t + k;
                match twin[h] {
                    NONE => theta[h],
                    o => kite_angle(theta[h], rho[o as usize / 3] - rho[t]).0,
                }
            })
        })
        .collect()
}

/// Gradient of the circle-pattern energy (halved): π − Σ φ per circle (Σ φ falls as the
/// circle grows).
fn closure_residual(mesh: &TriMesh, theta: &[f64], rho: &[f64]) -> Vec<f64> {
    kite_angles(mesh, theta, rho).iter().map(|p| PI - p.iter().sum::<f64>()).collect()
}

/// Newton on the convex energy of the log radii (circle 0 keeps its radius: the energy is
/// invariant under a common scale), with an exact line search on the monotone directional
/// derivative.
fn solve_radii(
    mesh: &TriMesh,
    theta: &[f64],
    rho: &mut [f64],
    options: &CirclePatternOptions,
    progress: &mut Progress,
) -> Result<u32> {
    let n = rho.len();
    if n <= 1 {
        return Ok(0);
    }
    let twin = &mesh.connectivity().twin;
    let centroids = triangle_centroids(mesh);
    let mut pattern: Option<CholeskyPattern> = None;
    let mut previous = f64::INFINITY;
    for iteration in 0..=options.max_iterations {
        let residual = closure_residual(mesh, theta, rho);
        let worst = residual.iter().map(|r| r.abs()).fold(0.0, f64::max);
        if !worst.is_finite() {
            return Err(Error::Numerical("circle pattern radii diverged".into()));
        }
        // Below 10⁻⁸ a Newton step that no longer halves the residual has met rounding.
        if worst <= options.tolerance || (worst < 1e-8 && worst > 0.5 * previous) {
            return Ok(iteration);
        }
        previous = worst;
        if iteration == options.max_iterations {
            break;
        }
        let (diag, entries) = radius_hessian(twin, theta, rho);
        let lower = lower_from_entries(&diag[1..], entries)?;
        let solver = factor_reusing(&mut pattern, &lower, &centroids[1..])?;
        let mut step = Mat::from_fn(n - 1, 1, |i, _| residual[i + 1]);
        solver.solve_in_place(&mut step)?;
        let mut direction = vec![0.0; n];
        for i in 1..n {
            direction[i] = -step[(i - 1, 0)];
        }
        let s = line_search(mesh, theta, rho, &direction);
        for (r, d) in rho.iter_mut().zip(&direction) {
            *r += s * d;
        }
        progress.report(0.6 + 0.3 * (iteration as f64 + 1.0) / (options.max_iterations as f64 + 1.0))?;
    }
    Err(Error::Numerical(format!(
        "circle pattern radii did not converge in {} Newton iterations (the intersection angles may admit no pattern)",
        options.max_iterations
    )))
}

/// The Hessian of the energy over circles 1.. (circle 0 fixed): diagonal and strictly lower
/// entries, weights dφ/dx on the dual edges.
fn radius_hessian(twin: &[u32], theta: &[f64], rho: &[f64]) -> (Vec<f64>, Vec<(u32, u32, f64)>) {
    let mut diag = vec![0.0; rho.len()];
    let mut entries = Vec::new();
    for (h, &o) in twin.iter().enumerate() {
        if o == NONE {
            continue;
        }
        let (f, g) = (h / 3, o as usize / 3);
        let (_, w) = kite_angle(theta[h], rho[g] - rho[f]);
        diag[f] += w;
        if f > g && g > 0 {
            entries.push(((f - 1) as u32, (g - 1) as u32, -w));
        }
    }
    (diag, entries)
}

/// Step length along `direction`: 1 when the energy still decreases there, else the zero of
/// the directional derivative in (0, 1) by bisection (it increases: the energy is convex).
fn line_search(mesh: &TriMesh, theta: &[f64], rho: &[f64], direction: &[f64]) -> f64 {
    // dE/ds = Σ residual · direction (the residual π − Σ φ is ∇E, halved).
    let slope = |s: f64| -> f64 {
        let moved: Vec<f64> = rho.iter().zip(direction).map(|(r, d)| r + s * d).collect();
        closure_residual(mesh, theta, &moved).iter().zip(direction).map(|(r, d)| r * d).sum::<f64>()
    };
    if slope(1.0) <= 0.0 {
        return 1.0;
    }
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if slope(mid) <= 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo.max(1e-12)
}

fn triangle_centroids(mesh: &TriMesh) -> Vec<[f64; 3]> {
    let p = mesh.points();
    mesh.triangles()
        .iter()
        .map(|t| std::array::from_fn(|i| t.iter().map(|&v| p[v as usize][i]).sum::<f64>() / 3.0))
        .collect()
}

/// The quadratic program for the planar angles (see the module comment): the log-barrier
/// solve here, the primal–dual one in `angle_ipm.rs`.
struct AngleProgram {
    /// Number of corners (3 per triangle): the first variables, the angles α.
    corners: usize,
    /// Per variable, the value it is kept above: [`MIN_ANGLE`] for an angle, 0 for a slack.
    lower: Vec<f64>,
    /// 3D angles, one per corner (3t + k), then 0 for every slack variable.
    beta: Vec<f64>,
    /// Objective weights 1 / β², then 0 for every slack variable.
    weight: Vec<f64>,
    /// Per slack variable (after the corners), its vertex row: an inequality Σ α ≤ bound at a
    /// boundary vertex (the turning there ≥ π − bound) is the row Σ α + σ = bound, σ ≥ 0.
    slack_row: Vec<u32>,
    /// The two corners opposite each interior edge.
    pairs: Vec<[u32; 2]>,
    /// For each variable, its pair, or NONE (a corner opposite a boundary edge, a slack).
    pair_of: Vec<u32>,
    /// Constraint row of each corner's vertex (after the triangle rows): interior vertices and
    /// boundary vertices with a prescribed curvature; NONE for the others.
    vertex_row: Vec<u32>,
    /// Number of constraint rows (triangles, then constrained vertices).
    rows: usize,
    /// Right-hand side of each row of J α = c: π per triangle, 2π per interior vertex,
    /// π − κ_v per boundary vertex with a prescribed curvature κ_v.
    targets: Vec<f64>,
    /// 3D position of each constraint row (triangle centroid, vertex), for the ordering.
    row_points: Vec<[f64; 3]>,
}

/// π − margin − α_a − α_b: positive where the edge is strictly locally Delaunay.
fn delaunay_slack(a: f64, b: f64) -> f64 {
    PI - DELAUNAY_MARGIN - a - b
}

impl AngleProgram {
    /// `sums`: per vertex, the angle sum to prescribe (NaN: free; see `angle_sums`);
    /// `bounds`: per vertex whose sum is free, an upper bound on it (NaN: none).
    fn new(mesh: &TriMesh, beta: &[f64], sums: &[f64], bounds: &[f64]) -> Self {
        let twin = &mesh.connectivity().twin;
        let corners = beta.len();
        let mut pairs = Vec::new();
        let mut pair_of = vec![NONE; corners];
        for (h, &o) in twin.iter().enumerate() {
            if o != NONE && (h as u32) < o {
                let (a, b) = (prev(h as u32), prev(o));
                pair_of[a as usize] = pairs.len() as u32;
                pair_of[b as usize] = pairs.len() as u32;
                pairs.push([a, b]);
            }
        }
        let triangles = mesh.triangle_count();
        let mut row_points = triangle_centroids(mesh);
        let mut targets = vec![PI; triangles];
        let mut row_of_vertex = vec![NONE; mesh.vertex_count()];
        // With every vertex prescribed, the vertex rows add up to the triangle rows (each
        // corner is in one of each): one row is implied (by Gauss–Bonnet, checked by
        // `angle_sums::vertex_sums`) and left out, or J H⁻¹ Jᵀ would be singular.
        let referenced = || (0..mesh.vertex_count() as u32).filter(|&v| mesh.is_referenced(v));
        let implied = referenced().all(|v| !sums[v as usize].is_nan());
        let skip = referenced().next().filter(|_| implied);
        for v in referenced().filter(|&v| !sums[v as usize].is_nan() && Some(v) != skip) {
            row_of_vertex[v as usize] = row_points.len() as u32;
            row_points.push(mesh.points()[v as usize]);
            targets.push(sums[v as usize]);
        }
        let mut slack_row = Vec::new();
        for v in referenced().filter(|&v| sums[v as usize].is_nan() && !bounds[v as usize].is_nan()) {
            row_of_vertex[v as usize] = row_points.len() as u32;
            slack_row.push(row_points.len() as u32);
            row_points.push(mesh.points()[v as usize]);
            targets.push(bounds[v as usize]);
        }
        let vertex_row = mesh.triangles().iter().flat_map(|t| t.map(|v| row_of_vertex[v as usize])).collect::<Vec<_>>();
        let mut weight: Vec<f64> = beta.iter().map(|b| 1.0 / b.max(1e-6).powi(2)).collect();
        debug_assert_eq!(beta.len(), 3 * triangles);
        let variables = corners + slack_row.len();
        let mut lower = vec![MIN_ANGLE; corners];
        lower.resize(variables, 0.0);
        let mut beta = beta.to_vec();
        beta.resize(variables, 0.0);
        weight.resize(variables, 0.0);
        pair_of.resize(variables, NONE);
        AngleProgram {
            corners,
            lower,
            beta,
            weight,
            slack_row,
            pairs,
            pair_of,
            vertex_row,
            rows: row_points.len(),
            targets,
            row_points,
        }
    }

    fn non_delaunay_edges(&self, beta: &[f64]) -> u32 {
        self.pairs.iter().filter(|[a, b]| beta[*a as usize] + beta[*b as usize] >= PI).count() as u32
    }

    /// Slack of every inequality: the angles, then π − α_a − α_b per pair.
    fn slacks_positive(&self, alpha: &[f64]) -> bool {
        alpha.iter().zip(&self.lower).all(|(a, l)| a > l)
            && self.pairs.iter().all(|[a, b]| delaunay_slack(alpha[*a as usize], alpha[*b as usize]) > 0.0)
    }

    /// A start strictly inside the inequalities, with exact triangle sums: the 3D angles
    /// blended towards π/3 as little as needed, and every slack what its row leaves, at least
    /// 0.1 (the equalities need not hold at the start).
    fn start(&self) -> Vec<f64> {
        let corners = &self.beta[..self.corners];
        let blend = |keep: f64| -> Vec<f64> { corners.iter().map(|b| keep * b + (1.0 - keep) * PI / 3.0).collect() };
        let inside = |alpha: &[f64]| {
            self.pairs.iter().all(|[a, b]| delaunay_slack(alpha[*a as usize], alpha[*b as usize]) > 1e-3)
                && alpha.iter().all(|&a| a > MIN_ANGLE + 1e-6)
        };
        let mut alpha = [1.0, 0.9, 0.5, 0.0]
            .into_iter()
            .map(blend)
            .find(|a| inside(a))
            .unwrap_or_else(|| vec![PI / 3.0; self.corners]);
        alpha.resize(self.beta.len(), 0.0);
        let sums = self.apply_j(&alpha);
        for (k, &row) in self.slack_row.iter().enumerate() {
            alpha[self.corners + k] = (self.targets[row as usize] - sums[row as usize]).max(0.1);
        }
        alpha
    }

    /// Gradient of t·f − Σ ln slack at α.
    fn gradient(&self, t: f64, alpha: &[f64]) -> Vec<f64> {
        let mut g: Vec<f64> = (0..alpha.len())
            .map(|a| t * self.weight[a] * (alpha[a] - self.beta[a]) - 1.0 / (alpha[a] - self.lower[a]))
            .collect();
        for [a, b] in &self.pairs {
            let s = delaunay_slack(alpha[*a as usize], alpha[*b as usize]);
            g[*a as usize] += 1.0 / s;
            g[*b as usize] += 1.0 / s;
        }
        g
    }

    /// The inverse Hessian blocks: per pair the 2×2 inverse [[p, q], [q, r]], per lone corner
    /// 1 / h (stored as p with q = r = 0 for its own index).
    fn inverse_blocks(&self, t: f64, alpha: &[f64]) -> Vec<[f64; 3]> {
        let own: Vec<f64> =
            (0..alpha.len()).map(|a| t * self.weight[a] + (alpha[a] - self.lower[a]).powi(-2)).collect();
        let coupling: Vec<f64> =
            self.pairs.iter().map(|[a, b]| delaunay_slack(alpha[*a as usize], alpha[*b as usize]).powi(-2)).collect();
        self.blocks_inverse(&own, &coupling)
    }

    /// The inverse blocks of H = diag(own) + Σ_pairs c_e (e_a + e_b)(e_a + e_b)ᵀ.
    fn blocks_inverse(&self, own: &[f64], coupling: &[f64]) -> Vec<[f64; 3]> {
        let mut inv: Vec<[f64; 3]> = own.iter().map(|h| [1.0 / h, 0.0, 0.0]).collect();
        for ([a, b], &c) in self.pairs.iter().zip(coupling) {
            let (a, b) = (*a as usize, *b as usize);
            let (x, y) = (own[a] + c, own[b] + c);
            // x y − c² without the cancellation of large c (an active Delaunay constraint).
            let det = own[a] * own[b] + c * (own[a] + own[b]);
            // inverse of [[x, c], [c, y]]: [[y, −c], [−c, x]] / det, stored at both corners.
            inv[a] = [y / det, -c / det, x / det];
            inv[b] = [x / det, -c / det, y / det];
        }
        inv
    }

    /// H⁻¹ v (block-diagonal H).
    fn apply_inverse(&self, inv: &[[f64; 3]], v: &[f64]) -> Vec<f64> {
        (0..v.len())
            .map(|a| match self.pair_of[a] {
                NONE => inv[a][0] * v[a],
                p => {
                    let [x, y] = self.pairs[p as usize];
                    let other = if x as usize == a { y } else { x } as usize;
                    inv[a][0] * v[a] + inv[a][1] * v[other]
                }
            })
            .collect()
    }

    /// The constraint rows touched by variable a: a corner's triangle and vertex rows, a
    /// slack's vertex row.
    fn rows_of(&self, a: usize) -> impl Iterator<Item = usize> + '_ {
        let (first, second) = if a < self.corners {
            (a / 3, self.vertex_row[a])
        } else {
            (self.slack_row[a - self.corners] as usize, NONE)
        };
        std::iter::once(first).chain((second != NONE).then_some(second as usize))
    }

    fn apply_j(&self, v: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.rows];
        for (a, x) in v.iter().enumerate() {
            for r in self.rows_of(a) {
                out[r] += x;
            }
        }
        out
    }

    fn apply_jt(&self, nu: &[f64]) -> Vec<f64> {
        (0..self.beta.len()).map(|a| self.rows_of(a).map(|r| nu[r]).sum()).collect()
    }

    /// The Schur complement J H⁻¹ Jᵀ (diagonal, strictly lower entries).
    fn schur(&self, inv: &[[f64; 3]]) -> (Vec<f64>, Vec<(u32, u32, f64)>) {
        let mut diag = vec![0.0; self.rows];
        let mut entries = Vec::new();
        let mut add = |i: usize, j: usize, v: f64, diag: &mut Vec<f64>| match i.cmp(&j) {
            std::cmp::Ordering::Equal => diag[i] += v,
            std::cmp::Ordering::Greater => entries.push((i as u32, j as u32, v)),
            std::cmp::Ordering::Less => {}
        };
        for (a, block) in inv.iter().enumerate() {
            let partner = (self.pair_of[a] != NONE).then(|| {
                let p = self.pairs[self.pair_of[a] as usize];
                (if p[0] as usize == a { p[1] } else { p[0] }) as usize
            });
            for i in self.rows_of(a) {
                for j in self.rows_of(a) {
                    add(i, j, block[0], &mut diag);
                }
                for j in partner.into_iter().flat_map(|b| self.rows_of(b)) {
                    add(i, j, block[1], &mut diag);
                }
            }
        }
        (diag, entries)
    }

    /// Newton step Δα on the barrier problem at weight t from α (infeasible start: the step
    /// also removes the equality residual) and −gᵀΔα, the Newton decrement once the equalities
    /// hold.
    fn newton_step(&self, t: f64, alpha: &[f64], pattern: &mut Option<CholeskyPattern>) -> Result<(Vec<f64>, f64)> {
        let g = self.gradient(t, alpha);
        let inv = self.inverse_blocks(t, alpha);
        let solver = self.factor_schur(&inv, pattern)?;
        let (step, _) = self.kkt_step(&solver, &inv, &g, &self.equality_residual(alpha))?;
        let decrement = -g.iter().zip(&step).map(|(a, b)| a * b).sum::<f64>();
        Ok((step, decrement))
    }

    /// J α − c.
    fn equality_residual(&self, alpha: &[f64]) -> Vec<f64> {
        self.apply_j(alpha).iter().zip(&self.targets).map(|(x, c)| x - c).collect()
    }

    /// The factored Schur complement J H⁻¹ Jᵀ of the blocks `inv` = H⁻¹.
    fn factor_schur(&self, inv: &[[f64; 3]], pattern: &mut Option<CholeskyPattern>) -> Result<CholeskySolver<f64>> {
        let (diag, entries) = self.schur(inv);
        let lower = lower_from_entries(&diag, entries)?;
        Ok(factor_reusing(pattern, &lower, &self.row_points)?)
    }

    /// The solution (Δα, Δν) of [H Jᵀ; J 0] (Δα, Δν) = −(g, r) by the Schur complement:
    /// (J H⁻¹ Jᵀ) Δν = r − J H⁻¹ g, Δα = −H⁻¹ (g + Jᵀ Δν).
    fn kkt_step(
        &self,
        schur: &CholeskySolver<f64>,
        inv: &[[f64; 3]],
        g: &[f64],
        r: &[f64],
    ) -> Result<(Vec<f64>, Vec<f64>)> {
        let jhg = self.apply_j(&self.apply_inverse(inv, g));
        let mut nu = Mat::from_fn(self.rows, 1, |i, _| r[i] - jhg[i]);
        schur.solve_in_place(&mut nu)?;
        let nu: Vec<f64> = (0..self.rows).map(|i| nu[(i, 0)]).collect();
        let rhs: Vec<f64> = g.iter().zip(self.apply_jt(&nu)).map(|(a, b)| a + b).collect();
        let step = self.apply_inverse(inv, &rhs).iter().map(|x| -x).collect();
        Ok((step, nu))
    }

    /// Largest s ≤ 1 keeping every slack positive (99% of the way to the boundary).
    fn max_step(&self, alpha: &[f64], step: &[f64]) -> f64 {
        let mut s: f64 = 1.0;
        for ((a, d), l) in alpha.iter().zip(step).zip(&self.lower) {
            if *d < 0.0 {
                s = s.min(-0.99 * (a - l) / d);
            }
        }
        for [a, b] in &self.pairs {
            let (a, b) = (*a as usize, *b as usize);
            let d = step[a] + step[b];
            if d > 0.0 {
                s = s.min(0.99 * delaunay_slack(alpha[a], alpha[b]) / d);
            }
        }
        s
    }

    /// The barrier path t = 1, 10², …, 10⁸ (the barrier moves an angle by about β / t);
    /// returns the angles and the Newton step count.
    fn solve(&self, max_iterations: u32, progress: &mut Progress) -> Result<(Vec<f64>, u32)> {
        let mut alpha = self.start();
        let mut pattern = None;
        let mut iterations = 0u32;
        let mut feasible = false;
        let stages = 5;
        for stage in 0..stages {
            let t = 100f64.powi(stage);
            let mut centred = false;
            for _ in 0..max_iterations.max(1) {
                let (step, decrement) = self.newton_step(t, &alpha, &mut pattern)?;
                iterations += 1;
                if !decrement.is_finite() {
                    return Err(Error::Numerical("circle pattern angles: the barrier Newton step diverged".into()));
                }
                let s = self.max_step(&alpha, &step);
                let s = self.backtrack(t, &alpha, &step, s);
                for (a, d) in alpha.iter_mut().zip(&step) {
                    *a += s * d;
                }
                // A full step solves the (linear) equalities; later steps keep them.
                feasible |= s == 1.0;
                // The decrement's rounding floor grows in proportion to t (the gradient holds
                // t·w·(α − β), w = 1/β² large at slivers): on disk_camelhead it changes sign
                // from step to step at ±10⁻⁷ at t = 100, ±3·10⁻⁵ at t = 10⁴ and ±4·10⁻³ at
                // t = 10⁶, about 4·10⁻⁹·t (a floor of 10⁻¹²·t failed there at t = 10⁶). A
                // decrement λ² leaves the barrier problem λ²/2 above its minimum, i.e. f (which
                // it scales by t) λ²/2t above: 10⁻⁷·t costs f at most 5·10⁻⁸.
                if feasible && decrement.abs() < 1e-6 + 1e-7 * t {
                    centred = true;
                    break;
                }
            }
            if !centred {
                return Err(Error::Numerical(format!(
                    "circle pattern angles: no centred point after {max_iterations} Newton steps at t = {t:e} (the angle constraints may be infeasible)"
                )));
            }
            progress.report(0.6 * (stage + 1) as f64 / stages as f64)?;
        }
        if !self.slacks_positive(&alpha) {
            return Err(Error::Numerical("circle pattern angles left the feasible region".into()));
        }
        let residual = self.apply_j(&alpha).iter().zip(&self.targets).map(|(x, c)| (x - c).abs()).fold(0.0, f64::max);
        if !(residual < 1e-9) {
            return Err(Error::Numerical(format!(
                "circle pattern angles miss their sums by {residual:.1e} rad (the prescribed boundary curvature may be infeasible)"
            )));
        }
        Ok((alpha, iterations))
    }

    /// Backtracking on the barrier value once the equalities hold (their residual is linear:
    /// a full step removes it; before that any step that keeps the slacks positive is taken).
    fn backtrack(&self, t: f64, alpha: &[f64], step: &[f64], mut s: f64) -> f64 {
        let value = |x: &[f64]| -> f64 {
            let mut v: f64 = (0..x.len())
                .map(|a| 0.5 * t * self.weight[a] * (x[a] - self.beta[a]).powi(2) - (x[a] - self.lower[a]).ln())
                .sum();
            for [a, b] in &self.pairs {
                v -= delaunay_slack(x[*a as usize], x[*b as usize]).ln();
            }
            v
        };
        let g = self.gradient(t, alpha);
        let slope: f64 = g.iter().zip(step).map(|(a, b)| a * b).sum();
        let v0 = value(alpha);
        for _ in 0..60 {
            let moved: Vec<f64> = alpha.iter().zip(step).map(|(a, d)| a + s * d).collect();
            if self.slacks_positive(&moved) && (slope >= 0.0 || value(&moved) <= v0 + 1e-4 * s * slope) {
                return s;
            }
            s *= 0.5;
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kite_angle_splits_theta_by_the_law_of_sines() {
        for &theta in &[0.3, 1.5, 2.9] {
            for &x in &[-3.0, -0.2, 0.0, 0.7, 5.0] {
                let (phi, slope) = kite_angle(theta, x);
                // sin φ_f / sin φ_g = r_g / r_f = eˣ with φ_f + φ_g = θ
                assert!((phi.sin() / (theta - phi).sin() - f64::exp(x)).abs() < 1e-9 * f64::exp(x).max(1.0));
                let h = 1e-6;
                let numeric = (kite_angle(theta, x + h).0 - kite_angle(theta, x - h).0) / (2.0 * h);
                assert!((slope - numeric).abs() < 1e-6, "θ {theta} x {x}: {slope} vs {numeric}");
            }
        }
        assert!((kite_angle(1.0, 0.0).0 - 0.5).abs() < 1e-15);
        assert!(kite_angle(1.0, 800.0).0 <= 1.0 && kite_angle(1.0, -800.0).0 >= 0.0);
    }

    /// A parallelogram of jittered equilateral triangles (every edge locally Delaunay) in
    /// the plane z = 0.
    fn jittered_lattice(n: usize, jitter: f64) -> (Vec<f64>, Vec<u32>) {
        lattice(n, jitter, false)
    }

    /// A jittered triangular lattice (nearly equilateral triangles); with `long_diagonals` each
    /// rhombus is split along its long diagonal instead, whose opposite angles are ≈ 120°.
    fn lattice(n: usize, jitter: f64, long_diagonals: bool) -> (Vec<f64>, Vec<u32>) {
        let mut positions = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let wiggle = |k: usize| jitter * (((i * 7 + j * 13 + k * 5) % 11) as f64 / 5.0 - 1.0);
                positions.extend([i as f64 + 0.5 * j as f64 + wiggle(0), j as f64 * 0.75f64.sqrt() + wiggle(1), 0.0]);
            }
        }
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        let mut triangles = Vec::new();
        for j in 0..n {
            for i in 0..n {
                if long_diagonals {
                    triangles.extend([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                    triangles.extend([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
                } else {
                    triangles.extend([id(i, j), id(i + 1, j), id(i, j + 1)]);
                    triangles.extend([id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
                }
            }
        }
        (positions, triangles)
    }

    /// Largest distance between uv and the best similarity image of the mesh's (x, y), over
    /// the diameter of (x, y).
    fn similarity_error(xy: &[[f64; 2]], uv: &[[f64; 2]]) -> f64 {
        use faer::c64;
        let z: Vec<c64> = xy.iter().map(|p| c64::new(p[0], p[1])).collect();
        let w: Vec<c64> = uv.iter().map(|p| c64::new(p[0], p[1])).collect();
        let n = z.len() as f64;
        let zm = z.iter().fold(c64::new(0.0, 0.0), |a, b| a + *b) * (1.0 / n);
        let wm = w.iter().fold(c64::new(0.0, 0.0), |a, b| a + *b) * (1.0 / n);
        let (mut num, mut den) = (c64::new(0.0, 0.0), 0.0);
        for (a, b) in z.iter().zip(&w) {
            let dz = *a - zm;
            num += (*b - wm) * dz.conj();
            den += dz.norm_sqr();
        }
        let scale = num * (1.0 / den);
        let diameter = z.iter().map(|a| (*a - zm).norm()).fold(0.0, f64::max) * 2.0;
        z.iter().zip(&w).map(|(a, b)| ((*a - zm) * scale + wm - *b).norm()).fold(0.0, f64::max)
            / (diameter * scale.norm())
    }

    #[test]
    fn newton_recovers_the_circumradii_from_perturbed_radii() {
        let (positions, triangles) = jittered_lattice(10, 0.08);
        let mesh = TriMesh::new(&positions, &triangles).unwrap();
        let beta: Vec<f64> = mesh.corner_angles().iter().flatten().copied().collect();
        let theta = intersection_angles(&mesh, &beta);
        let exact = circumradius_logs(&edge_lengths(&mesh), mesh.corner_angles());
        let mut rho: Vec<f64> =
            exact.iter().enumerate().map(|(f, r)| r + 0.7 * ((f * 37 % 17) as f64 / 8.0 - 1.0)).collect();
        let iterations =
            solve_radii(&mesh, &theta, &mut rho, &CirclePatternOptions::default(), &mut Progress::none()).unwrap();
        assert!(iterations >= 3, "{iterations} iterations");
        let shift = rho[0] - exact[0];
        let worst = rho.iter().zip(&exact).map(|(r, e)| (r - e - shift).abs()).fold(0.0, f64::max);
        assert!(worst < 1e-10, "log radii off by {worst}");
    }

    #[test]
    fn flat_delaunay_mesh_is_its_own_parameterization() {
        let (positions, triangles) = jittered_lattice(12, 0.06);
        let mesh = TriMesh::new(&positions, &triangles).unwrap();
        let result = circle_pattern_map(&mesh, &CirclePatternOptions::default(), &mut Progress::none()).unwrap();
        let xy: Vec<[f64; 2]> = positions.chunks(3).map(|p| [p[0], p[1]]).collect();
        let error = similarity_error(&xy, &result.uv);
        let r = result.report;
        assert_eq!(r.non_delaunay_edges, 0);
        assert!(r.max_angle_change < 1e-6, "{r:?}");
        assert!(r.closure_error < 1e-10, "{r:?}");
        assert!(error < 1e-6, "similarity error {error}, {r:?}");
    }

    #[test]
    fn flat_non_delaunay_mesh_is_its_own_parameterization_after_intrinsic_flips() {
        // Every rhombus split along its long diagonal: the intrinsic Delaunay triangulation of a
        // flat mesh is the planar Delaunay one (all n² diagonals flipped), whose angles are
        // planar and Delaunay already, so the pattern is the mesh itself up to a similarity.
        let n = 10;
        let (positions, triangles) = lattice(n, 0.04, true);
        let mesh = TriMesh::new(&positions, &triangles).unwrap();
        let xy: Vec<[f64; 2]> = positions.chunks(3).map(|p| [p[0], p[1]]).collect();
        let result = circle_pattern_map(&mesh, &CirclePatternOptions::default(), &mut Progress::none()).unwrap();
        let r = result.report;
        assert_eq!((r.intrinsic_flips, r.non_delaunay_edges, r.flipped_triangles), ((n * n) as u32, 0, 0), "{r:?}");
        assert!(r.max_angle_change < 1e-6, "{r:?}");
        let error = similarity_error(&xy, &result.uv);
        assert!(error < 1e-6, "similarity error {error}, {r:?}");
        // Without the flips the program must move the ≈ 120° angles below the Delaunay bound.
        let options = CirclePatternOptions { intrinsic_delaunay: false, ..Default::default() };
        let plain = circle_pattern_map(&mesh, &options, &mut Progress::none()).unwrap();
        assert_eq!(plain.report.non_delaunay_edges, (n * n) as u32);
        assert!(similarity_error(&xy, &plain.uv) > 1e-3);
    }

    /// Turning angle of the closed polygon `lp` of `xy` at each of its vertices.
    fn turning(lp: &[u32], xy: &[[f64; 2]]) -> Vec<f64> {
        let n = lp.len();
        (0..n)
            .map(|i| {
                let [a, v, b] = [lp[(i + n - 1) % n], lp[i], lp[(i + 1) % n]].map(|x| xy[x as usize]);
                let (d1, d2) = ([v[0] - a[0], v[1] - a[1]], [b[0] - v[0], b[1] - v[1]]);
                (d1[0] * d2[1] - d1[1] * d2[0]).atan2(d1[0] * d2[0] + d1[1] * d2[1])
            })
            .collect()
    }

    #[test]
    fn prescribing_a_flat_meshs_own_boundary_curvature_gives_the_mesh_back() {
        let (positions, triangles) = jittered_lattice(10, 0.06);
        let mesh = TriMesh::new(&positions, &triangles).unwrap();
        let xy: Vec<[f64; 2]> = positions.chunks(3).map(|p| [p[0], p[1]]).collect();
        let lp = &mesh.boundary_loops()[0];
        let mut curvature = vec![f64::NAN; mesh.vertex_count()];
        for (v, k) in lp.iter().zip(turning(lp, &xy)) {
            curvature[*v as usize] = k;
        }
        let options = CirclePatternOptions { boundary_curvature: Some(curvature.clone()), ..Default::default() };
        let result = circle_pattern_map(&mesh, &options, &mut Progress::none()).unwrap();
        assert!(similarity_error(&xy, &result.uv) < 1e-6, "{:?}", result.report);
        // Straight sides and four right angles instead: a rectangle, exactly.
        let corners: Vec<u32> = (0..4).map(|k| lp[k * lp.len() / 4]).collect();
        let square = polygon_boundary_curvature(&mesh, &corners).unwrap();
        let options = CirclePatternOptions { boundary_curvature: Some(square.clone()), ..Default::default() };
        let result = circle_pattern_map(&mesh, &options, &mut Progress::none()).unwrap();
        for (v, k) in lp.iter().zip(turning(lp, &result.uv)) {
            assert!((k - square[*v as usize]).abs() < 1e-9, "vertex {v} turns by {k}");
        }
    }

    #[test]
    fn infeasible_boundary_curvature_is_refused() {
        let (positions, triangles) = jittered_lattice(6, 0.06);
        let mesh = TriMesh::new(&positions, &triangles).unwrap();
        let lp = mesh.boundary_loops()[0].clone();
        let run = |curvature: Vec<f64>| {
            let options = CirclePatternOptions { boundary_curvature: Some(curvature), ..Default::default() };
            circle_pattern_map(&mesh, &options, &mut Progress::none())
        };
        let invalid = |r: Result<CirclePatternResult>| matches!(r, Err(Error::InvalidArgument(_)));
        // Gauss–Bonnet: a fully prescribed disk boundary must turn by 2π in all.
        let mut curvature = vec![f64::NAN; mesh.vertex_count()];
        for &v in &lp {
            curvature[v as usize] = 2.0 * PI / lp.len() as f64 * 1.01;
        }
        assert!(invalid(run(curvature.clone())));
        // An angle sum of π − κ ≤ 0 at a vertex.
        curvature.iter_mut().for_each(|k| *k = f64::NAN);
        curvature[lp[0] as usize] = 4.0;
        assert!(invalid(run(curvature.clone())));
        curvature[lp[0] as usize] = f64::INFINITY;
        assert!(invalid(run(curvature)));
        assert!(invalid(run(vec![0.0; 3])));
        // Polygons: at least 3 corners, each once, on the boundary.
        assert!(matches!(polygon_boundary_curvature(&mesh, &lp[..2]), Err(Error::InvalidArgument(_))));
        assert!(matches!(polygon_boundary_curvature(&mesh, &[lp[0], lp[1], lp[0]]), Err(Error::InvalidArgument(_))));
        let interior = (0..mesh.vertex_count() as u32).find(|&v| !mesh.is_boundary_vertex(v)).unwrap();
        assert!(matches!(polygon_boundary_curvature(&mesh, &[lp[0], lp[3], interior]), Err(Error::InvalidArgument(_))));
        assert!(matches!(polygon_boundary_curvature(&mesh, &[lp[0], lp[3], 10_000]), Err(Error::InvalidArgument(_))));
    }
}
