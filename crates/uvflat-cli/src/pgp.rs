//! `uvflat pgp`: the Periodic Global Parameterization, its charts and its quad-dominant mesh.

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::errors::{check_density, check_outputs, usage, Failure};
use crate::files::{load_mesh, write_quad_mesh};
use clap::ValueEnum;
use uvflat_core::fields::smoothing::{SmoothingOptions, Symmetry};
use uvflat_core::io::obj::write_obj_with_corner_uv;
use uvflat_core::io::surface_svg::{write_periodic_svg, PeriodicPicture};
use uvflat_core::methods::pgp::charts::{chart_parameterization, ChartKind, ChartParameterization};
use uvflat_core::methods::pgp::forced::forced_singular_triangles;
use uvflat_core::methods::pgp::quality::quality;
use uvflat_core::methods::pgp::{pgp, quad_dominant_remesh, PgpOptions};
use uvflat_core::progress::Progress;

#[derive(clap::Args)]
pub(crate) struct PgpArgs {
    /// Input mesh (OBJ).
    pub(crate) input: PathBuf,
    /// Output OBJ with per-corner texture coordinates (θ/2π, φ/2π).
    #[arg(short = 'o', long = "output")]
    pub(crate) output: PathBuf,
    /// ω (θ grows by ω per unit length; a period is 2π/ω long). Default: 2π / (10 × mean edge
    /// length).
    #[arg(long)]
    pub(crate) omega: Option<f64>,
    /// Rescale the field to reduce its curl (§4.1): fewer singularities, conformal instead of
    /// isometric.
    #[arg(long = "curl-correction")]
    pub(crate) curl_correction: bool,
    /// Keep Algorithm 1's per-corner (θ, φ) as it is: no untangling of the negative triangles
    /// next to singular points (the untangling moves vertex phases, keeping every transition;
    /// not in the paper, see docs/methods/pgp.md).
    #[arg(long = "no-untangle")]
    pub(crate) no_untangle: bool,
    /// No phase relaxation before the untangling (the relaxation turns every vertex's phases by
    /// the least-squares fit of the (theta, phi) triangles to the field, keeping every
    /// transition, and is used only where it leaves no more singular triangles; not in the
    /// paper, see docs/methods/pgp.md).
    #[arg(long = "no-relax")]
    pub(crate) no_relax: bool,
    /// Minimum number of periods around a curved feature: where a curvature radius r holds fewer
    /// than C periods (omega r < C), the frequency is raised there (at most 2.5x) so that legs,
    /// horns and fingers narrower than a period are not singular standing waves (not in the
    /// paper, see docs/methods/pgp.md). 0: the paper's single omega everywhere.
    #[arg(long = "feature-periods", default_value_t = uvflat_core::methods::pgp::density::DEFAULT_FEATURE_PERIODS)]
    pub(crate) feature_periods: f64,
    /// Cancel the +1/4 and -1/4 singularities of the smoothed cross field that lie closer than
    /// P periods (2pi/omega) to each other, re-solving the field around them (not in the paper,
    /// see docs/methods/pgp.md): on coarse meshes most such pairs only add singular triangles. 0: keep
    /// the smoothed field's singularities.
    #[arg(long = "pair-periods", default_value_t = uvflat_core::fields::pairs::DEFAULT_PAIR_PERIODS)]
    pub(crate) pair_periods: f64,
    /// Annihilate pairs of open triangles of opposite winding where the field is regular
    /// (dislocations of the wave pattern) closer than P periods, turning the phases around
    /// them (not in the paper, see docs/methods/pgp.md). 0: keep the periodic solve's phases.
    #[arg(long = "dislocation-periods", default_value_t = uvflat_core::methods::pgp::dislocations::DEFAULT_DISLOCATION_PERIODS)]
    pub(crate) dislocation_periods: f64,
    /// Field smoothing (§4.2): directions equal modulo 2pi, pi or pi/2, or none.
    #[arg(long, value_enum, default_value_t = SmoothName::HalfPi)]
    pub(crate) smooth: SmoothName,
    /// Newton iterations of the periodic solve (§2.5; stops earlier once the gradient norm is
    /// below 1e-6, within 3–78 iterations on the meshes measured but one: the mesh torus without
    /// curl correction reaches 100). 10 is about 3× faster with
    /// nearly the same singularities (see docs/methods/pgp.md).
    #[arg(long = "newton-iterations", default_value_t = uvflat_core::fields::block_newton::PERIODIC_ITERATIONS)]
    pub(crate) newton_iterations: usize,
    /// Write the quad-dominant remesh (§5: iso-lines of θ and φ, non-quads split) to this OBJ.
    #[arg(long = "quad-mesh")]
    pub(crate) quad_mesh: Option<PathBuf>,
    /// Iso-lines per period for --quad-mesh (a whole number >= 1; quad sides are about
    /// 2pi / (omega x density) long, 10 / density mean edge lengths with the default omega, and
    /// down to 2.5x shorter on curved features, see --feature-periods).
    #[arg(long = "quad-density", default_value_t = 8.0)]
    pub(crate) quad_density: f64,
    /// Draw the quad-dominant remesh into this SVG file (needs --quad-mesh).
    #[arg(long = "quad-svg")]
    pub(crate) quad_svg: Option<PathBuf>,
    /// Write the per-chart parameterization (§3.3–3.4: the surface cut along the chart
    /// boundaries, each chart with its own (u, v) in cells, a regular chart the unit square) to
    /// this OBJ, one group per chart.
    #[arg(long)]
    pub(crate) charts: Option<PathBuf>,
    /// Iso-lines per period bounding the charts of --charts (a whole number >= 1; 1: the
    /// paper's iso-2kpi lines).
    #[arg(long = "chart-density", default_value_t = 1.0)]
    pub(crate) chart_density: f64,
    /// Draw the iso-kπ lines and singularities on the surface into this SVG file.
    #[arg(long)]
    pub(crate) svg: Option<PathBuf>,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub(crate) json: bool,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum SmoothName {
    /// No smoothing: the raw principal directions.
    None,
    /// Modulo 2π (poles).
    #[value(name = "2pi")]
    TwoPi,
    /// Modulo π (half-poles).
    #[value(name = "pi")]
    Pi,
    /// Modulo π/2 (quarter-poles; the default).
    #[value(name = "pi/2")]
    HalfPi,
}

pub(crate) fn periodic(args: &PgpArgs) -> Result<(), Failure> {
    let (obj, mesh) = load_mesh(&args.input)?;
    if let Some(w) = args.omega {
        if !(w.is_finite() && w > 0.0) {
            return Err(usage(format!("--omega must be a finite number > 0 (got {w})")));
        }
    }
    if !(args.feature_periods.is_finite() && args.feature_periods >= 0.0) {
        return Err(usage(format!("--feature-periods must be a finite number >= 0 (got {})", args.feature_periods)));
    }
    if !(args.pair_periods.is_finite() && args.pair_periods >= 0.0) {
        return Err(usage(format!("--pair-periods must be a finite number >= 0 (got {})", args.pair_periods)));
    }
    if !(args.dislocation_periods.is_finite() && args.dislocation_periods >= 0.0) {
        return Err(usage(format!(
            "--dislocation-periods must be a finite number >= 0 (got {})",
            args.dislocation_periods
        )));
    }
    if args.quad_svg.is_some() && args.quad_mesh.is_none() {
        return Err(usage("--quad-svg needs --quad-mesh"));
    }
    check_density("--quad-density", args.quad_density)?;
    check_density("--chart-density", args.chart_density)?;
    check_outputs(&[
        ("-o", Some(&args.output)),
        ("--svg", args.svg.as_deref()),
        ("--quad-mesh", args.quad_mesh.as_deref()),
        ("--quad-svg", args.quad_svg.as_deref()),
        ("--charts", args.charts.as_deref()),
    ])?;
    let symmetry = match args.smooth {
        SmoothName::None => None,
        SmoothName::TwoPi => Some(Symmetry::Vector),
        SmoothName::Pi => Some(Symmetry::Line),
        SmoothName::HalfPi => Some(Symmetry::Cross),
    };
    let mut options = PgpOptions {
        omega: args.omega,
        curl_correction: args.curl_correction,
        untangle: !args.no_untangle,
        relax: !args.no_relax,
        feature_periods: args.feature_periods,
        pair_periods: args.pair_periods,
        dislocation_periods: args.dislocation_periods,
        smoothing: symmetry.map(|symmetry| SmoothingOptions { symmetry, ..SmoothingOptions::default() }),
        ..PgpOptions::default()
    };
    options.newton.max_iterations = args.newton_iterations;
    let start = Instant::now();
    let result = pgp(&mesh, &options, &mut Progress::none())?;
    let seconds = start.elapsed().as_secs_f64();
    let q = quality(&mesh, &result.param, &result.singularities, &result.normals, &result.field, result.omega)?;
    let uv: Vec<[f64; 2]> = result
        .param
        .coords
        .iter()
        .flat_map(|c| c.map(|x| [x[0] / std::f64::consts::TAU, x[1] / std::f64::consts::TAU]))
        .collect();
    let uv_triangles: Vec<u32> = (0..uv.len() as u32).collect();
    write_obj_with_corner_uv(&args.output, &obj.positions, &obj.triangles, &uv, &uv_triangles)?;
    let points = result.singularities.singular_points();
    if let Some(svg) = &args.svg {
        let picture = PeriodicPicture {
            points: mesh.points(),
            triangles: mesh.triangles(),
            coords: &result.param.coords,
            singular_triangles: &result.singularities.triangles,
            singular_points: &points,
        };
        write_periodic_svg(svg, &picture)?;
    }
    let quads = match &args.quad_mesh {
        Some(path) => Some(write_quad_mesh(
            &quad_dominant_remesh(&mesh, &result, args.quad_density)?,
            path,
            args.quad_svg.as_deref(),
        )?),
        None => None,
    };
    let charts = match &args.charts {
        Some(path) => {
            let c = chart_parameterization(&mesh, &result, args.chart_density)?;
            write_chart_obj(path, &c)?;
            Some(chart_counts(&c))
        }
        None => None,
    };
    let s = &result.singularities;
    let genus = mesh.topology().genus;
    let forced = forced_singular_triangles(&mesh, &result.normals);
    if args.json {
        println!(
            "{}",
            serde_json::json!({
                "method": "pgp", "seconds": seconds, "vertices": mesh.vertex_count(), "triangles": mesh.triangle_count(),
                "genus": genus, "omega": result.omega, "curl_correction": args.curl_correction,
                "feature_periods": args.feature_periods, "pair_periods": args.pair_periods,
                "pairs": serde_json::json!({
                    "field_singular_before": result.pairs.singular_before,
                    "field_singular_after": result.pairs.singular_after,
                    "cancelled": result.pairs.pairs, "trials": result.pairs.trials,
                }),
                "dislocation_periods": args.dislocation_periods,
                "dislocations": serde_json::json!({
                    "before": result.dislocations.before, "annihilated_pairs": result.dislocations.pairs,
                    "absorbed": result.dislocations.absorbed,
                    "trials": result.dislocations.trials,
                }),
                "singular_vertices": s.vertices.len(), "singular_edges": s.edges.len(),
                "singular_triangles": s.triangles.len(), "singular_triangle_fraction": q.singular_triangle_fraction,
                "forced_singular_triangles": forced.triangles, "forced_quarter_turns": forced.quarters,
                "holonomy_forced_triangles": forced.holonomy_forced,
                "singular_points": points.len(), "index_sum": s.index_sum(),
                "newton_iterations": result.solve.iterations, "converged": result.solve.converged,
                "final_gradient": result.solve.final_gradient,
                "untangled": serde_json::json!({
                    "negative_before": result.untangled.negative_before,
                    "negative_after": result.untangled.negative_after,
                    "moved_vertices": result.untangled.moved_vertices,
                }),
                "relaxed": serde_json::json!({
                    "kept": result.relaxed.kept,
                    "singular_without": result.relaxed.singular_without,
                    "singular_with": result.relaxed.singular_with,
                }),
                "stretch": q.stretch, "shear": q.shear, "alignment_degrees": q.alignment_degrees,
                "output": args.output.display().to_string(),
                "quad_mesh": quads.map(|(faces, quads, vertices)| serde_json::json!({
                    "faces": faces, "quads": quads, "vertices": vertices,
                    "density": args.quad_density,
                })),
                "charts": charts.map(|k| serde_json::json!({
                    "assembled": k[0], "mean_value": k[1], "split_quads": k[2], "atlas": k[3], "unresolved": k[4],
                    "density": args.chart_density,
                })),
            })
        );
    } else {
        println!(
            "pgp: {} vertices, {} triangles, genus {genus}, omega {:.4}, {:.3} s -> {}",
            mesh.vertex_count(),
            mesh.triangle_count(),
            result.omega,
            seconds,
            args.output.display()
        );
        println!(
            "  singular vertices / edges / triangles  {} / {} / {} ({:.2}% of the triangles)",
            s.vertices.len(),
            s.edges.len(),
            s.triangles.len(),
            100.0 * q.singular_triangle_fraction
        );
        println!(
            "  fewest singular triangles possible     {} ({:.2}%, {} quarter turns to carry, {} open whatever the field)",
            forced.triangles,
            100.0 * forced.triangles as f64 / mesh.triangle_count() as f64,
            forced.quarters,
            forced.holonomy_forced
        );
        println!("  singular points                        {} (index sum {:.2})", points.len(), s.index_sum());
        println!(
            "  Newton iterations                      {}{} (|grad F**| {:.1e})",
            result.solve.iterations,
            if result.solve.converged { "" } else { ", not converged" },
            result.solve.final_gradient
        );
        println!(
            "  stretch / shear / alignment            {:.4} / {:.4} / {:.2}°",
            q.stretch, q.shear, q.alignment_degrees
        );
        if let (Some((faces, quad_count, vertices)), Some(path)) = (quads, &args.quad_mesh) {
            println!(
                "  quad-dominant remesh                   {vertices} vertices, {faces} faces, {:.1}% quads -> {}",
                100.0 * quad_count as f64 / faces.max(1) as f64,
                path.display()
            );
        }
        if let (Some(k), Some(path)) = (charts, &args.charts) {
            println!(
                "  charts (assembled / mean value / split quads / atlas / unresolved)  {} / {} / {} / {} / {} -> {}",
                k[0],
                k[1],
                k[2],
                k[3],
                k[4],
                path.display()
            );
        }
    }
    Ok(())
}

/// Charts of each kind: assembled, mean value, split quads, atlas, unresolved.
pub(crate) fn chart_counts(c: &ChartParameterization) -> [usize; 5] {
    let mut counts = [0; 5];
    for ch in &c.charts {
        counts[match ch.kind {
            ChartKind::Assembled => 0,
            ChartKind::MeanValue => 1,
            ChartKind::SplitQuad => 2,
            ChartKind::Atlas => 3,
            ChartKind::Unresolved => 4,
        }] += 1;
    }
    counts
}

/// Writes the cut triangulation with per-corner `vt`, one `g chartN` group per chart.
pub(crate) fn write_chart_obj(path: &Path, c: &ChartParameterization) -> Result<(), Failure> {
    use std::io::Write;
    let fail = |e: std::io::Error| Failure { message: format!("cannot write {}: {e}", path.display()), usage: false };
    let mut out = std::io::BufWriter::new(std::fs::File::create(path).map_err(fail)?);
    for p in &c.positions {
        writeln!(out, "v {} {} {}", p[0], p[1], p[2]).map_err(fail)?;
    }
    for q in c.uv.iter().flatten() {
        writeln!(out, "vt {} {}", q[0], q[1]).map_err(fail)?;
    }
    let mut current = u32::MAX;
    for (r, t) in c.triangles.iter().enumerate() {
        if c.chart[r] != current {
            current = c.chart[r];
            writeln!(out, "g chart{current}").map_err(fail)?;
        }
        let corner = |k: usize| format!("{}/{}", t[k] + 1, 3 * r + k + 1);
        writeln!(out, "f {} {} {}", corner(0), corner(1), corner(2)).map_err(fail)?;
    }
    out.flush().map_err(fail)
}
