//! `uvflat unwrap --method NAME`: the options of each method family built from the command line,
//! and the call of the chosen method.

use std::path::Path;
use std::time::Instant;

use crate::errors::{usage, Failure};
use crate::methods::{method_label, DistributionName, EnergyName, MethodName};
use crate::metrics::{merge, metrics_json, print_metrics_text};
use crate::unwrap_args::UnwrapArgs;
use uvflat_core::io::obj::{write_obj_with_corner_uv, ObjMesh};
use uvflat_core::io::svg::write_uv_svg;
use uvflat_core::methods::abf::{abf, AbfOptions, AbfVariant};
use uvflat_core::methods::boundary_optimization::{boundary_optimized_map, BoundaryOptimizationOptions};
use uvflat_core::methods::circle_patterns::{
    circle_pattern_cone_map, circle_pattern_map, polygon_boundary_curvature, CirclePatternOptions,
};
use uvflat_core::methods::cone_placement::{place_cones, ConePlacementOptions};
use uvflat_core::methods::conformal::Pin;
use uvflat_core::methods::length_area_distortion::DistortionEnergy;
use uvflat_core::methods::near_optimal::{near_optimal_map, NearOptimalOptions};
use uvflat_core::methods::nonlinear::{nonlinear_map, NonlinearOptions};
use uvflat_core::methods::spectral_conformal::{spectral_conformal_map, SpectralOptions};
use uvflat_core::metrics::distortion;
use uvflat_core::progress::Progress;
use uvflat_core::{
    fixed_boundary_map, natural_conformal_map, BoundaryShape, Distribution, FixedBoundaryOptions, TriMesh, Weights,
};

/// `--cone V:DEGREES` values as (vertex, curvature in radians).
pub(crate) fn parse_cones(values: &[String]) -> Result<Vec<(u32, f64)>, Failure> {
    values
        .iter()
        .map(|text| {
            let parsed =
                text.split_once(':').and_then(|(v, k)| Some((v.trim().parse().ok()?, k.trim().parse::<f64>().ok()?)));
            parsed
                .map(|(v, k)| (v, k.to_radians()))
                .ok_or_else(|| usage(format!("--cone takes VERTEX:DEGREES, not {text:?}")))
        })
        .collect()
}

/// The circle-pattern options of `--no-intrinsic-delaunay`, `--corner` and `--convex-boundary`.
pub(crate) fn circle_pattern_options(args: &UnwrapArgs, mesh: &TriMesh) -> Result<CirclePatternOptions, Failure> {
    let boundary_curvature =
        if args.corners.is_empty() { None } else { Some(polygon_boundary_curvature(mesh, &args.corners)?) };
    Ok(CirclePatternOptions {
        intrinsic_delaunay: !args.no_intrinsic_delaunay,
        boundary_curvature,
        convex_boundary: args.convex_boundary,
        ..CirclePatternOptions::default()
    })
}

/// `--method circle-patterns --cone ...`: the cone map, cut through its cones, per-corner UVs.
pub(crate) fn unwrap_cone_map(args: &UnwrapArgs, obj: &ObjMesh, mesh: &TriMesh, start: Instant) -> Result<(), Failure> {
    let (cones, max_log_scale) = if args.auto_cones {
        let defaults = ConePlacementOptions::default();
        let options = ConePlacementOptions {
            max_cones: args.max_cones.unwrap_or_else(|| {
                let chi = mesh.topology().euler_characteristic;
                defaults.max_cones.max(4 * (-chi).clamp(0, u32::MAX as i64 / 4) as u32)
            }),
            max_log_scale: args.max_log_scale.unwrap_or(defaults.max_log_scale),
        };
        let placement = place_cones(mesh, &options, &mut Progress::none())?;
        (placement.cones, Some(placement.max_log_scale))
    } else {
        (parse_cones(&args.cones)?, None)
    };
    let result = circle_pattern_cone_map(mesh, &cones, &circle_pattern_options(args, mesh)?, &mut Progress::none())?;
    let seconds = start.elapsed().as_secs_f64();
    let uv: Vec<[f64; 2]> = result.corner_uv.iter().flatten().copied().collect();
    let uv_triangles: Vec<[u32; 3]> =
        (0..mesh.triangle_count() as u32).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect();
    let flat: Vec<u32> = uv_triangles.iter().flatten().copied().collect();
    write_obj_with_corner_uv(&args.output, &obj.positions, &obj.triangles, &uv, &flat)?;
    if let Some(svg) = &args.svg {
        write_uv_svg(svg, &uv, &uv_triangles)?;
    }
    let metrics = distortion(mesh.points(), mesh.triangles(), &uv, &uv_triangles)?;
    let r = result.report;
    if args.json {
        let mut object = serde_json::json!({
            "method": "circle-patterns", "seconds": seconds, "vertices": mesh.vertex_count(),
            "output": args.output.display().to_string(), "cones": cones.len(), "seam_edges": result.seams.len(),
            "intrinsic_flips": r.intrinsic_flips, "closure_error": r.closure_error, "flipped_triangles": r.flipped_triangles,
            "radius_span": r.radius_span,
        });
        if let Some(scale) = max_log_scale {
            object["cone_vertices"] = cones.iter().map(|c| c.0).collect();
            object["cone_curvatures"] = cones.iter().map(|c| c.1).collect();
            object["max_log_scale"] = scale.into();
        }
        merge(&mut object, metrics_json(&metrics));
        println!("{object}");
    } else {
        println!(
            "circle-patterns with {} cones: {} seam edges, {} intrinsic flips, circles closed to {:.1e}, {:.3} s -> {}",
            cones.len(),
            result.seams.len(),
            r.intrinsic_flips,
            r.closure_error,
            seconds,
            args.output.display()
        );
        print_metrics_text(&metrics);
    }
    Ok(())
}

/// The boundary shape and spacing of `--boundary` and `--distribution`.
pub(crate) fn boundary_of(args: &UnwrapArgs) -> Result<(BoundaryShape, Distribution), Failure> {
    let shape = match args.boundary.as_deref() {
        None | Some("circle") => BoundaryShape::Circle,
        Some("square") => BoundaryShape::Square,
        Some(file) => BoundaryShape::Given(read_boundary_file(Path::new(file))?),
    };
    let distribution = match args.distribution {
        None | Some(DistributionName::Chord) => Distribution::ChordLength,
        Some(DistributionName::Uniform) => Distribution::Uniform,
        Some(DistributionName::Centripetal) => Distribution::Centripetal,
    };
    Ok((shape, distribution))
}

pub(crate) fn energy_of(args: &UnwrapArgs) -> (DistortionEnergy, &'static str) {
    match args.energy {
        None | Some(EnergyName::Edge) => (DistortionEnergy::EdgeLength, "edge"),
        Some(EnergyName::Area) => (DistortionEnergy::Area, "area"),
    }
}

/// No extra JSON fields.
pub(crate) fn plain(uv: Vec<[f64; 2]>) -> (Vec<[f64; 2]>, serde_json::Value) {
    (uv, serde_json::json!({}))
}

/// The UVs of the chosen method, and method-specific JSON fields.
pub(crate) fn run_method(mesh: &TriMesh, args: &UnwrapArgs) -> Result<(Vec<[f64; 2]>, serde_json::Value), Failure> {
    let method = args.method();
    if let Some(method) = method.nonlinear() {
        let mut options = NonlinearOptions::new(method);
        options.iterations = args.iterations.unwrap_or(options.iterations);
        options.theta = args.theta.unwrap_or(options.theta);
        options.bijective = args.bijective;
        return Ok(plain(nonlinear_map(mesh, &options)?.uv));
    }
    let weights = match method {
        MethodName::NaturalConformal => return Ok(plain(natural_conformal_map(mesh, cli_pins(mesh, &args.pins)?)?)),
        MethodName::Abf | MethodName::AbfPlusPlus => {
            let variant = if method == MethodName::Abf { AbfVariant::Abf } else { AbfVariant::AbfPlusPlus };
            let options = AbfOptions { variant, pins: cli_pins(mesh, &args.pins)?, ..AbfOptions::default() };
            let result = abf(mesh, &options)?;
            if !args.json {
                let r = result.report;
                println!(
                    "{}: {} iterations, gradient norm {:.2e}{}",
                    method_label(method),
                    r.iterations,
                    r.gradient_norm,
                    if r.converged { "" } else { " (not converged)" }
                );
            }
            return Ok(plain(result.uv));
        }
        MethodName::SpectralConformal => {
            let r = spectral_conformal_map(mesh, &SpectralOptions::default(), &mut Progress::none())?;
            if !args.json {
                println!(
                    "spectral-conformal: eigenvalue {:.4e}, residual {:.1e} after {} iterations{}",
                    r.eigenvalue,
                    r.residual,
                    r.iterations,
                    if r.converged { "" } else { " (not converged)" }
                );
            }
            let extra = serde_json::json!({"eigenvalue": r.eigenvalue, "residual": r.residual, "iterations": r.iterations, "converged": r.converged});
            return Ok((r.uv, extra));
        }
        MethodName::CirclePatterns => {
            let r = circle_pattern_map(mesh, &circle_pattern_options(args, mesh)?, &mut Progress::none())?;
            let p = r.report;
            if !args.json {
                println!(
                    "circle-patterns: {} intrinsic flips, {} angle and {} radius Newton steps, circles closed to {:.1e}, {} non-Delaunay edges, largest angle change {:.2} deg, {} flipped triangles, radii span {:.1} decades",
                    p.intrinsic_flips,
                    p.angle_iterations,
                    p.radius_iterations,
                    p.closure_error,
                    p.non_delaunay_edges,
                    p.max_angle_change.to_degrees(),
                    p.flipped_triangles,
                    p.radius_span
                );
            }
            let extra = serde_json::json!({"angle_iterations": p.angle_iterations, "radius_iterations": p.radius_iterations, "closure_error": p.closure_error, "non_delaunay_edges": p.non_delaunay_edges, "max_angle_change": p.max_angle_change, "intrinsic_flips": p.intrinsic_flips, "flipped_triangles": p.flipped_triangles, "radius_span": p.radius_span});
            return Ok((r.uv, extra));
        }
        MethodName::IntrinsicOptimal => {
            let (shape, distribution) = boundary_of(args)?;
            let (energy, name) = energy_of(args);
            let options = NearOptimalOptions { energy, shape, distribution, ..NearOptimalOptions::default() };
            let r = near_optimal_map(mesh, &options, &mut Progress::none())?;
            if !args.json {
                println!(
                    "intrinsic-optimal ({name}): lambda {:.6}, energy {:.6e} (DCP {:.6e}, DAP {:.6e})",
                    r.lambda, r.energy, r.energy_conformal, r.energy_authalic
                );
            }
            let extra = serde_json::json!({
                "energy_name": name, "lambda": r.lambda, "energy": r.energy,
                "energy_dcp": r.energy_conformal, "energy_dap": r.energy_authalic, "boundary_scale": r.boundary_scale,
            });
            return Ok((r.uv, extra));
        }
        MethodName::BoundaryOptimized => {
            let (shape, distribution) = boundary_of(args)?;
            let (energy, name) = energy_of(args);
            let defaults = BoundaryOptimizationOptions::default();
            let options = BoundaryOptimizationOptions {
                energy,
                shape,
                distribution,
                lambda: args.lambda.unwrap_or(defaults.lambda),
                mu: args.mu.unwrap_or(defaults.mu),
                iterations: args.iterations.unwrap_or(defaults.iterations),
                ..defaults
            };
            let r = boundary_optimized_map(mesh, &options, &mut Progress::none())?;
            let (first, last) = (r.history[0], *r.history.last().unwrap_or(&r.history[0]));
            if !args.json {
                println!(
                    "boundary-optimized ({name}): energy {first:.6e} -> {last:.6e} in {} iterations{}",
                    r.iterations,
                    if r.converged { "" } else { " (iteration limit)" }
                );
            }
            let extra = serde_json::json!({
                "energy_name": name, "initial_energy": first, "final_energy": last, "iterations": r.iterations,
                "converged": r.converged, "energy_history": r.history, "boundary_scale": r.boundary_scale,
            });
            return Ok((r.uv, extra));
        }
        MethodName::Slim
        | MethodName::Arap
        | MethodName::Mips
        | MethodName::Stretch
        | MethodName::GreenLagrange
        | MethodName::Degener => {
            return Err(Failure { message: "internal: non-linear method not dispatched".into(), usage: false })
        }
        MethodName::Tutte => Weights::Uniform,
        MethodName::Floater => Weights::Floater,
        MethodName::Authalic => Weights::Authalic,
        MethodName::Conformal => Weights::Conformal,
        MethodName::MeanValue => Weights::MeanValue,
        MethodName::Intrinsic => Weights::Intrinsic { lambda: args.lambda.unwrap_or(1.0), mu: args.mu.unwrap_or(0.0) },
    };
    let (shape, distribution) = boundary_of(args)?;
    Ok(plain(fixed_boundary_map(mesh, &FixedBoundaryOptions { weights, shape, distribution })?))
}

/// The two `--pin` vertices placed at (0, 0) and (d, 0), d their 3D distance (as the automatic
/// pins are), or `None` for the automatic choice. Index checks are the library's.
pub(crate) fn cli_pins(mesh: &TriMesh, pins: &[u32]) -> Result<Option<[Pin; 2]>, Failure> {
    let [a, b] = match pins {
        [] => return Ok(None),
        [a, b] => [*a, *b],
        _ => return Err(usage("give --pin exactly twice")),
    };
    let point = |v: u32| mesh.points().get(v as usize).copied().unwrap_or([f64::NAN; 3]);
    let (p, q) = (point(a), point(b));
    let d = ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt();
    let d = if d.is_finite() && d > 0.0 { d } else { 1.0 };
    Ok(Some([(a, [0.0, 0.0]), (b, [d, 0.0])]))
}

/// Reads `vertex_index u v` lines (0-based; blank lines and `#` comments allowed).
pub(crate) fn read_boundary_file(path: &Path) -> Result<Vec<(u32, [f64; 2])>, Failure> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| Failure { message: format!("cannot read boundary file {}: {e}", path.display()), usage: false })?;
    let mut given = Vec::new();
    for (number, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let bad = || Failure {
            message: format!("{}:{}: expected `vertex_index u v`, found `{line}`", path.display(), number + 1),
            usage: false,
        };
        let fields: Vec<&str> = line.split_whitespace().collect();
        let [v, u, w] = fields[..] else { return Err(bad()) };
        let vertex = v.parse::<u32>().map_err(|_| bad())?;
        let (u, w) = (u.parse::<f64>().map_err(|_| bad())?, w.parse::<f64>().map_err(|_| bad())?);
        given.push((vertex, [u, w]));
    }
    if given.is_empty() {
        return Err(Failure { message: format!("boundary file {} fixes no vertex", path.display()), usage: false });
    }
    Ok(given)
}
