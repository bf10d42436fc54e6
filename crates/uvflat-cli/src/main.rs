//! `uvflat`: the command-line tool. Unwraps an OBJ into an OBJ with UVs (and optionally an SVG
//! picture of the layout), measures the distortion of an OBJ's UVs, lists the methods, and
//! reports a mesh's topology. Every failure prints the library's message and exits with
//! status 1 (2 for a command-line usage error); nothing panics on bad input.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use clap::{Parser, Subcommand, ValueEnum};
use uvflat_core::atlas::{atlas, Atlas, AtlasOptions, ChartMethod};
use uvflat_core::io::obj::{read_obj, read_obj_geometry, write_obj_with_corner_uv, write_obj_with_uv, ObjMesh};
use uvflat_core::io::surface_svg::{write_periodic_svg, write_polygon_mesh_svg, PeriodicPicture};
use uvflat_core::io::svg::write_uv_svg;
use uvflat_core::mesh::cut::{cut_to_disk, total_edge_length, EdgeCost};
use uvflat_core::methods::abf::{abf, AbfOptions, AbfVariant};
use uvflat_core::methods::boundary_optimization::{boundary_optimized_map, BoundaryOptimizationOptions};
use uvflat_core::methods::circle_patterns::{
    circle_pattern_cone_map, circle_pattern_map, polygon_boundary_curvature, CirclePatternOptions,
};
use uvflat_core::methods::cone_placement::{place_cones, ConePlacementOptions};
use uvflat_core::methods::conformal::Pin;
use uvflat_core::methods::length_area_distortion::DistortionEnergy;
use uvflat_core::methods::near_optimal::{near_optimal_map, NearOptimalOptions};
use uvflat_core::methods::nonlinear::{nonlinear_map, NonlinearMethod, NonlinearOptions};
use uvflat_core::methods::pgp::charts::{chart_parameterization, ChartKind, ChartParameterization};
use uvflat_core::methods::pgp::forced::forced_singular_triangles;
use uvflat_core::methods::pgp::quality::quality;
use uvflat_core::methods::pgp::smoothing::{SmoothingOptions, Symmetry};
use uvflat_core::methods::pgp::{pgp, quad_dominant_remesh, PgpOptions, PolygonMesh};
use uvflat_core::methods::quadcover::{quad_mesh as quadcover_quad_mesh, quadcover, QuadCoverOptions};
use uvflat_core::methods::spectral_conformal::{spectral_conformal_map, SpectralOptions};
use uvflat_core::methods::sphere::{spherical_map, SphereMethod, SphereOptions};
use uvflat_core::metrics::{distortion, Metrics};
use uvflat_core::progress::Progress;
use uvflat_core::unwrap::{unwrap_with_progress, UnwrapOptions, UnwrapReport};
use uvflat_core::verify::check_layout;
use uvflat_core::{
    fixed_boundary_map, natural_conformal_map, BoundaryShape, Distribution, Error, FixedBoundaryOptions, TriMesh,
    Weights,
};

#[derive(Parser)]
#[command(name = "uvflat", version, about = "Mesh parameterization (UV unwrapping)")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Computes UVs for IN.obj and writes OUT.obj (input vertices and faces, plus `vt` lines).
    Unwrap(UnwrapArgs),
    /// Distortion of the UVs stored in an OBJ file (`vt` lines).
    Metrics {
        input: PathBuf,
        /// Print one JSON object instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Lists the parameterization methods, one per line.
    Methods,
    /// Prints vertices, faces, components, boundary loops and genus of a mesh.
    Info {
        input: PathBuf,
        /// Print one JSON object instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Maps a closed genus-0 mesh onto the unit sphere and writes OUT.obj with the sphere
    /// positions as vertices (same faces).
    Sphere(SphereArgs),
    /// Periodic Global Parameterization (Ray et al. 2006) of a mesh of any genus, without
    /// cutting: writes OUT.obj with per-corner `vt` = (θ, φ)/2π, so a tiling texture repeats
    /// once per period along the principal curvature directions.
    Pgp(PgpArgs),
    /// QuadCover (Kälberer, Nieser & Polthier 2007) of a mesh of any genus: writes OUT.obj with
    /// per-corner `vt` = (u, v) in grid units, whose integer iso-lines close up over the whole
    /// surface (a texture that repeats once per unit shows a seamless grid).
    Quadcover(QuadCoverArgs),
}

#[derive(clap::Args)]
struct QuadCoverArgs {
    /// Input mesh (OBJ), one connected component.
    input: PathBuf,
    /// Output OBJ with per-corner texture coordinates (u, v).
    #[arg(short = 'o', long = "output")]
    output: PathBuf,
    /// Surface length of one grid cell. Default: 3 mean edge lengths.
    #[arg(long = "grid-spacing")]
    grid_spacing: Option<f64>,
    /// Alignment of the frame field to the principal curvature directions (> 0).
    #[arg(long, default_value_t = uvflat_core::methods::quadcover::field::DEFAULT_ALIGNMENT)]
    alignment: f64,
    /// Keep the continuous solve: no rounding of gaps and cone positions (not seamless).
    #[arg(long = "no-round")]
    no_round: bool,
    /// Also put every cone on an integer point (irregular vertices of the grid); default: only
    /// the gaps are integers, as in the course notes (fewer folds).
    #[arg(long = "cones-on-grid")]
    cones_on_grid: bool,
    /// Cancel ± cone pairs of the field closer than this many grid cells, and move cones that
    /// close to the boundary onto it (0: keep the field's cones).
    #[arg(long = "pair-cells", default_value_t = uvflat_core::methods::quadcover::cone_pairs::DEFAULT_PAIR_CELLS)]
    pair_cells: f64,
    /// Keep the folds the rounding leaves: no untangling of the vertices near them.
    #[arg(long = "no-untangle")]
    no_untangle: bool,
    /// Also write an SVG picture of the (u, v) triangles.
    #[arg(long)]
    svg: Option<PathBuf>,
    /// Write the quad-dominant mesh of the integer iso-lines (non-quads split into quads and at
    /// most one triangle) to this OBJ.
    #[arg(long = "quad-mesh")]
    quad_mesh: Option<PathBuf>,
    /// Iso-lines per grid unit for --quad-mesh (a whole number >= 1; 1: one quad per grid
    /// cell).
    #[arg(long = "quad-density", default_value_t = 1.0)]
    quad_density: f64,
    /// Draw the quad mesh into this SVG file (needs --quad-mesh).
    #[arg(long = "quad-svg")]
    quad_svg: Option<PathBuf>,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

#[derive(clap::Args)]
struct PgpArgs {
    /// Input mesh (OBJ).
    input: PathBuf,
    /// Output OBJ with per-corner texture coordinates (θ/2π, φ/2π).
    #[arg(short = 'o', long = "output")]
    output: PathBuf,
    /// ω (θ grows by ω per unit length; a period is 2π/ω long). Default: 2π / (10 × mean edge
    /// length).
    #[arg(long)]
    omega: Option<f64>,
    /// Rescale the field to reduce its curl (§4.1): fewer singularities, conformal instead of
    /// isometric.
    #[arg(long = "curl-correction")]
    curl_correction: bool,
    /// Keep Algorithm 1's per-corner (θ, φ) as it is: no untangling of the negative triangles
    /// next to singular points (the untangling moves vertex phases, keeping every transition;
    /// not in the paper, see docs/methods/pgp.md).
    #[arg(long = "no-untangle")]
    no_untangle: bool,
    /// No phase relaxation before the untangling (the relaxation turns every vertex's phases by
    /// the least-squares fit of the (theta, phi) triangles to the field, keeping every
    /// transition, and is used only where it leaves no more singular triangles; not in the
    /// paper, see docs/methods/pgp.md).
    #[arg(long = "no-relax")]
    no_relax: bool,
    /// Minimum number of periods around a curved feature: where a curvature radius r holds fewer
    /// than C periods (omega r < C), the frequency is raised there (at most 2.5x) so that legs,
    /// horns and fingers narrower than a period are not singular standing waves (not in the
    /// paper, see docs/methods/pgp.md). 0: the paper's single omega everywhere.
    #[arg(long = "feature-periods", default_value_t = uvflat_core::methods::pgp::density::DEFAULT_FEATURE_PERIODS)]
    feature_periods: f64,
    /// Cancel the +1/4 and -1/4 singularities of the smoothed cross field that lie closer than
    /// P periods (2pi/omega) to each other, re-solving the field around them (not in the paper,
    /// see docs/methods/pgp.md): on coarse meshes most such pairs only add singular triangles. 0: keep
    /// the smoothed field's singularities.
    #[arg(long = "pair-periods", default_value_t = uvflat_core::methods::pgp::pairs::DEFAULT_PAIR_PERIODS)]
    pair_periods: f64,
    /// Annihilate pairs of open triangles of opposite winding where the field is regular
    /// (dislocations of the wave pattern) closer than P periods, turning the phases around
    /// them (not in the paper, see docs/methods/pgp.md). 0: keep the periodic solve's phases.
    #[arg(long = "dislocation-periods", default_value_t = uvflat_core::methods::pgp::dislocations::DEFAULT_DISLOCATION_PERIODS)]
    dislocation_periods: f64,
    /// Field smoothing (§4.2): directions equal modulo 2pi, pi or pi/2, or none.
    #[arg(long, value_enum, default_value_t = SmoothName::HalfPi)]
    smooth: SmoothName,
    /// Newton iterations of the periodic solve (§2.5; stops earlier once the gradient norm is
    /// below 1e-6, within 3–78 iterations on the meshes measured but one: the mesh torus without
    /// curl correction reaches 100). 10 is about 3× faster with
    /// nearly the same singularities (see docs/methods/pgp.md).
    #[arg(long = "newton-iterations", default_value_t = uvflat_core::methods::pgp::solver::PERIODIC_ITERATIONS)]
    newton_iterations: usize,
    /// Write the quad-dominant remesh (§5: iso-lines of θ and φ, non-quads split) to this OBJ.
    #[arg(long = "quad-mesh")]
    quad_mesh: Option<PathBuf>,
    /// Iso-lines per period for --quad-mesh (a whole number >= 1; quad sides are about
    /// 2pi / (omega x density) long, 10 / density mean edge lengths with the default omega, and
    /// down to 2.5x shorter on curved features, see --feature-periods).
    #[arg(long = "quad-density", default_value_t = 8.0)]
    quad_density: f64,
    /// Draw the quad-dominant remesh into this SVG file (needs --quad-mesh).
    #[arg(long = "quad-svg")]
    quad_svg: Option<PathBuf>,
    /// Write the per-chart parameterization (§3.3–3.4: the surface cut along the chart
    /// boundaries, each chart with its own (u, v) in cells, a regular chart the unit square) to
    /// this OBJ, one group per chart.
    #[arg(long)]
    charts: Option<PathBuf>,
    /// Iso-lines per period bounding the charts of --charts (a whole number >= 1; 1: the
    /// paper's iso-2kpi lines).
    #[arg(long = "chart-density", default_value_t = 1.0)]
    chart_density: f64,
    /// Draw the iso-kπ lines and singularities on the surface into this SVG file.
    #[arg(long)]
    svg: Option<PathBuf>,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum SmoothName {
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

#[derive(clap::Args)]
struct SphereArgs {
    /// Input mesh (OBJ), closed genus 0.
    input: PathBuf,
    /// Output OBJ with unit-sphere vertex positions.
    #[arg(short = 'o', long = "output")]
    output: PathBuf,
    /// Spherical parameterization method.
    #[arg(long, value_enum, default_value_t = SphereMethodName::TutteGnomonic)]
    method: SphereMethodName,
    /// Relaxation sweeps (Gauss–Seidel iterations, guarded relaxation of tutte-gnomonic; the
    /// other methods have none); default 100.
    #[arg(long)]
    sweeps: Option<usize>,
    /// Print one JSON object instead of text.
    #[arg(long)]
    json: bool,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum SphereMethodName {
    /// Tutte embedding minus a vertex star, gnomonic lift, flip-guarded relaxation (never flips).
    TutteGnomonic,
    /// Projected Gauss–Seidel barycentric iteration (course notes §6.1; may flip).
    GaussSeidel,
    /// Haker et al. 2000: harmonic map minus one triangle, inverse stereographic (may flip).
    Stereographic,
    /// Kharevych et al. 2006: conformal circle pattern minus one vertex star, balanced,
    /// inverse stereographic (may flip).
    CirclePatterns,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum CutMode {
    /// Cut closed and higher-genus meshes into a disk (tree–cotree cut graph).
    Auto,
    /// Never cut (the method must accept the mesh as it is).
    None,
}

#[derive(clap::Args)]
struct UnwrapArgs {
    /// Input mesh (OBJ; polygons are fan-triangulated, or cut by ear clipping where the fan would
    /// fold).
    input: PathBuf,
    /// Output OBJ with one UV per vertex.
    #[arg(short = 'o', long = "output")]
    output: PathBuf,
    /// Parameterization method (see `uvflat methods`). Without it, the default unwrap: islands
    /// flattened by the natural conformal map, repaired by bijective SLIM where that flips or
    /// overlaps, split where over --max-stretch, packed into the unit square and verified (no
    /// flipped triangle, no overlap). A named method's own result is written as it is, with a
    /// warning when it flips, overlaps or stretches.
    #[arg(long, value_enum)]
    method: Option<MethodName>,
    /// Boundary of fixed-boundary methods: `circle`, `square`, or a file of lines
    /// `vertex_index u v` (0-based) fixing those boundary vertices.
    #[arg(long)]
    boundary: Option<String>,
    /// Spacing of boundary vertices along the circle or square.
    #[arg(long, value_enum)]
    distribution: Option<DistributionName>,
    /// λ of the intrinsic method (weight of the conformal part; may be negative); default 1.
    #[arg(long, allow_negative_numbers = true)]
    lambda: Option<f64>,
    /// μ of the intrinsic method (weight of the authalic part; may be negative); default 0.
    #[arg(long, allow_negative_numbers = true)]
    mu: Option<f64>,
    /// Vertex to pin, a 0-based index (the first `v` line is 0; natural-conformal; give exactly
    /// two). Default: the two boundary vertices farthest apart.
    #[arg(long = "pin")]
    pins: Vec<u32>,
    /// Iteration limit of the non-linear methods (slim, arap, mips, ...) and of the default
    /// unwrap's repair; default 100.
    #[arg(long)]
    iterations: Option<usize>,
    /// Non-linear methods: keep the whole map bijective (a scaffold around the free boundary, so
    /// the boundary cannot run into itself), not only free of flipped triangles.
    #[arg(long)]
    bijective: bool,
    /// θ of the degener method (weight of area against angle distortion); default 3.
    #[arg(long)]
    theta: Option<f64>,
    /// Distortion energy of intrinsic-optimal and boundary-optimized (Desbrun et al. 2002
    /// §5.1); default edge.
    #[arg(long, value_enum)]
    energy: Option<EnergyName>,
    /// circle-patterns: enforce the Delaunay condition on the mesh's own edges instead of
    /// flipping to the intrinsic Delaunay triangulation first (never flips, more distortion).
    #[arg(long = "no-intrinsic-delaunay")]
    no_intrinsic_delaunay: bool,
    /// circle-patterns: a vertex (0-based) that is a corner of a straight-sided convex polygon
    /// (give at least 3, on the longest boundary loop; 4 give a rectangle); default: free
    /// boundary.
    #[arg(long = "corner")]
    corners: Vec<u32>,
    /// circle-patterns: keep the UV boundary convex (every boundary vertex turns by at least 0),
    /// so the layout cannot overlap itself; with `--corner`, the polygon's own vertices keep
    /// their prescribed turning.
    #[arg(long = "convex-boundary")]
    convex_boundary: bool,
    /// circle-patterns: a cone singularity `V:DEGREES` at interior vertex V (0-based), its curvature in
    /// degrees (360 minus the cone angle: 90 for a cube corner); repeat. The mesh is then cut
    /// through the cones (any genus; on a closed mesh the curvatures must sum to 360·χ) and the
    /// UVs are per corner. Tori need none: give `--cone` with curvature 0 (e.g. `0:0`).
    #[arg(long = "cone")]
    cones: Vec<String>,
    /// circle-patterns: place the cones automatically (greedily where the conformal
    /// flattening's scale is largest, Ben-Chen et al. 2008) and cut through them; any genus,
    /// UVs per corner.
    #[arg(long = "auto-cones")]
    auto_cones: bool,
    /// With `--auto-cones`: most cones placed (default 64, or 4 per unit of −χ on a higher
    /// genus, which needs at least 2g − 2).
    #[arg(long = "max-cones", value_name = "N")]
    max_cones: Option<u32>,
    /// With `--auto-cones`: stop once the log scale is at most this everywhere (default 0.7,
    /// about a factor of 2 in length).
    #[arg(long = "max-log-scale", value_name = "S")]
    max_log_scale: Option<f64>,
    /// Also draw the UV layout into this SVG file.
    #[arg(long)]
    svg: Option<PathBuf>,
    /// Print one JSON object (method, seconds, metrics) instead of text.
    #[arg(long)]
    json: bool,
    /// With --method: cut the mesh into a disk first, `auto` (the default when the mesh is
    /// closed or has handles) or `none`; UVs are then per corner (`vt` indices differ from `v`
    /// indices). Without --method, `none` runs the plain natural conformal map (no cut, no
    /// repair, no packing).
    #[arg(long, value_enum)]
    cut: Option<CutMode>,
    /// Atlas mode: split into charts under a stretch bound, flatten each (natural-conformal by
    /// default; also mean-value, slim, stretch), pack them into the unit square.
    #[arg(long)]
    atlas: bool,
    /// Largest L2 stretch of an island: default unwrap 1.5, --atlas 1.004; `inf` turns the
    /// bound off (islands are split only where no valid layout is found).
    #[arg(long = "max-stretch")]
    max_stretch: Option<f64>,
    /// Default unwrap and --atlas: gap between packed islands in the unit square (default 0.005).
    #[arg(long)]
    margin: Option<f64>,
    /// Default unwrap and --atlas: do not rotate islands when packing.
    #[arg(long = "no-rotate")]
    no_rotate: bool,
    /// Atlas mode: L2-stretch polish iterations per chart (default 10; 0: none). Polishing
    /// lowers the L2 stretch and raises the angle error (charts are no longer conformal).
    #[arg(long)]
    polish: Option<usize>,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum MethodName {
    Tutte,
    Floater,
    Authalic,
    Conformal,
    MeanValue,
    Intrinsic,
    NaturalConformal,
    Slim,
    Arap,
    Mips,
    Stretch,
    GreenLagrange,
    Degener,
    Abf,
    #[value(name = "abf++")]
    AbfPlusPlus,
    SpectralConformal,
    CirclePatterns,
    IntrinsicOptimal,
    BoundaryOptimized,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum EnergyName {
    /// Edge-length distortion Σ (|u_i − u_j|²/|x_i − x_j|² − 1)².
    Edge,
    /// Area distortion Σ ((A_uv/A_3D)² − 1)².
    Area,
}

impl MethodName {
    /// The distortion-minimizing method, for the free-boundary non-linear methods.
    fn nonlinear(self) -> Option<NonlinearMethod> {
        Some(match self {
            MethodName::Slim => NonlinearMethod::Slim,
            MethodName::Arap => NonlinearMethod::Arap,
            MethodName::Mips => NonlinearMethod::Mips,
            MethodName::Stretch => NonlinearMethod::Stretch,
            MethodName::GreenLagrange => NonlinearMethod::GreenLagrange,
            MethodName::Degener => NonlinearMethod::Degener,
            _ => return None,
        })
    }
}

/// Each method's CLI name and one-line description, as `uvflat methods` prints them.
const METHODS: [(MethodName, &str, &str); 19] = [
    (MethodName::Tutte, "tutte", "fixed boundary, uniform weights (Tutte 1963); never flips with a convex boundary"),
    (MethodName::Floater, "floater", "fixed boundary, Floater's shape-preserving weights (1997); never flips"),
    (MethodName::Authalic, "authalic", "fixed boundary, discrete authalic = Wachspress (Desbrun et al. 2002 eq. 6)"),
    (MethodName::Conformal, "conformal", "fixed boundary, discrete conformal = harmonic (Desbrun et al. 2002 eq. 4)"),
    (MethodName::MeanValue, "mean-value", "fixed boundary, mean value weights (Floater 2003); never flips"),
    (MethodName::Intrinsic, "intrinsic", "fixed boundary, lambda*DCP + mu*DAP (Desbrun et al. 2002 §3.4)"),
    (
        MethodName::NaturalConformal,
        "natural-conformal",
        "free boundary, natural conformal map = LSCM (Desbrun et al. 2002 eq. 7); the default",
    ),
    (MethodName::Slim, "slim", "free boundary, symmetric Dirichlet by SLIM (Rabinovich et al. 2017); never flips"),
    (MethodName::Arap, "arap", "free boundary, as-rigid-as-possible local-global (Liu et al. 2008); never flips, no triangle below 1% of its share of the area"),
    (MethodName::Mips, "mips", "free boundary, MIPS conformal energy (Hormann & Greiner 2000); never flips"),
    (MethodName::Stretch, "stretch", "free boundary, L2 stretch (Sander et al. 2001); never flips"),
    (
        MethodName::GreenLagrange,
        "green-lagrange",
        "free boundary, Green-Lagrange tensor (Maillot et al. 1993); never flips, no triangle below 1% of its share of the area",
    ),
    (MethodName::Degener, "degener", "free boundary, Degener et al. 2003 angle x area^theta energy; never flips"),
    (MethodName::Abf, "abf", "free boundary, angle based flattening, full Newton (Sheffer & de Sturler 2001)"),
    (MethodName::AbfPlusPlus, "abf++", "free boundary, ABF++ Gauss-Newton + LSCM reconstruction (Sheffer et al. 2005)"),
    (
        MethodName::SpectralConformal,
        "spectral-conformal",
        "free boundary, conformal without pins: smallest generalized eigenvector (Mullen et al. 2008)",
    ),
    (
        MethodName::CirclePatterns,
        "circle-patterns",
        "conformal by circle patterns on the intrinsic Delaunay triangulation (Kharevych et al. 2006); free, polygon (--corner) or convex (--convex-boundary) boundary; cones (--cone, --auto-cones) on any genus",
    ),
    (
        MethodName::IntrinsicOptimal,
        "intrinsic-optimal",
        "fixed boundary, lambda*DCP map + (1-lambda)*DAP map of least --energy (Desbrun et al. 2002 §5.1)",
    ),
    (
        MethodName::BoundaryOptimized,
        "boundary-optimized",
        "intrinsic map whose boundary descends --energy, never flipping (Desbrun et al. 2002 §5.2)",
    ),
];

#[derive(Clone, Copy, ValueEnum)]
enum DistributionName {
    Uniform,
    Chord,
    Centripetal,
}

/// A failure to report: the message, and whether it was a usage error.
struct Failure {
    message: String,
    usage: bool,
}

impl From<Error> for Failure {
    fn from(e: Error) -> Self {
        let hint = match e {
            Error::MultipleComponents { .. } => " (`uvflat unwrap --atlas` unwraps every component)",
            _ => "",
        };
        Failure { message: format!("{e}{hint}"), usage: false }
    }
}

fn usage(message: impl Into<String>) -> Failure {
    Failure { message: message.into(), usage: true }
}

/// `uvflat ... | head` closes stdout early; `println!` then panics with "failed printing to
/// stdout: Broken pipe". Like a C tool killed by SIGPIPE, exit quietly with status 141
/// (128 + SIGPIPE) instead of printing a panic.
fn exit_quietly_on_broken_pipe() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let message = info.payload().downcast_ref::<String>().map_or("", String::as_str);
        if message.contains("Broken pipe") {
            std::process::exit(141);
        }
        // println! panics when stdout cannot be written (a full disk, /dev/full): an error,
        // not a crash.
        if message.starts_with("failed printing to stdout") {
            eprintln!("uvflat: {message}");
            std::process::exit(1);
        }
        default(info);
    }));
}

fn main() -> ExitCode {
    exit_quietly_on_broken_pipe();
    let cli = Cli::parse();
    let outcome = match cli.command {
        Command::Unwrap(args) => unwrap(&args),
        Command::Metrics { input, json } => print_metrics(&input, json),
        Command::Methods => {
            list_methods();
            Ok(())
        }
        Command::Info { input, json } => info(&input, json),
        Command::Sphere(args) => sphere(&args),
        Command::Pgp(args) => periodic(&args),
        Command::Quadcover(args) => quad_cover(&args),
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(f) => {
            eprintln!("uvflat: {}", f.message);
            ExitCode::from(if f.usage { 2 } else { 1 })
        }
    }
}

fn list_methods() {
    for (_, name, description) in METHODS {
        println!("{name:<18} {description}");
    }
}

fn method_label(method: MethodName) -> &'static str {
    METHODS.iter().find(|(m, _, _)| *m == method).map_or("?", |(_, name, _)| name)
}

fn load_mesh(path: &Path) -> Result<(ObjMesh, TriMesh), Failure> {
    let obj = read_obj_geometry(path)?;
    let mesh = TriMesh::new(&obj.positions, &obj.triangles)
        .map_err(|e| Failure { message: format!("{}: {e}", path.display()), usage: false })?;
    Ok((obj, mesh))
}

fn unwrap(args: &UnwrapArgs) -> Result<(), Failure> {
    check_option_combination(args)?;
    check_outputs(&[("-o", Some(&args.output)), ("--svg", args.svg.as_deref())])?;
    if args.atlas {
        return unwrap_atlas(args);
    }
    if args.polish.is_some() {
        return Err(usage("--polish applies to --atlas only"));
    }
    let obj = read_obj_geometry(&args.input)?;
    let start = Instant::now();
    let mesh = TriMesh::new(&obj.positions, &obj.triangles)
        .map_err(|e| Failure { message: format!("{}: {e}", args.input.display()), usage: false })?;
    if !args.cones.is_empty() || args.auto_cones {
        return unwrap_cone_map(args, &obj, &mesh, start);
    }
    if args.method.is_none() && args.cut != Some(CutMode::None) {
        return unwrap_default(args, &obj, &mesh, start);
    }
    if args.max_stretch.is_some() || args.no_rotate || args.margin.is_some() {
        return Err(usage("--max-stretch, --margin and --no-rotate apply to the default unwrap and --atlas only"));
    }
    let cut_mode =
        args.cut.unwrap_or(if mesh.require_disk_with_holes().is_ok() { CutMode::None } else { CutMode::Auto });
    let cut = match cut_mode {
        CutMode::None => None,
        CutMode::Auto => {
            if !args.pins.is_empty() || args.boundary.as_deref().is_some_and(|b| b != "circle" && b != "square") {
                return Err(usage(
                    "--pin and a boundary file name vertices of the input; they cannot be combined with a cut",
                ));
            }
            Some(cut_to_disk(&mesh, &EdgeCost::default())?)
        }
    };
    let work = cut.as_ref().map_or(&mesh, |c| &c.mesh);
    let (uv, extra) = run_method(work, args)?;
    let seconds = start.elapsed().as_secs_f64();
    let uv_triangles: Vec<[u32; 3]> = work.triangles().to_vec();
    match &cut {
        None => write_obj_with_uv(&args.output, &obj.positions, &obj.triangles, &uv)?,
        Some(_) => {
            let flat: Vec<u32> = uv_triangles.iter().flatten().copied().collect();
            write_obj_with_corner_uv(&args.output, &obj.positions, &obj.triangles, &uv, &flat)?
        }
    }
    if let Some(svg) = &args.svg {
        write_uv_svg(svg, &uv, &uv_triangles)?;
    }
    let metrics = distortion(mesh.points(), mesh.triangles(), &uv, &uv_triangles)?;
    let overlaps = overlaps_of(&uv, &uv_triangles);
    warn_if_unusable(method_label(args.method()), &metrics, overlaps);
    if args.json {
        let mut object = serde_json::json!({
            "method": method_label(args.method()),
            "seconds": seconds,
            "vertices": mesh.vertex_count(),
            "output": args.output.display().to_string(),
            "overlaps": overlaps,
        });
        if let Some(c) = &cut {
            let (seam, total) = (c.seam_length(&mesh), total_edge_length(&mesh));
            merge(
                &mut object,
                serde_json::json!({
                    "cut_edges": c.edges.len(),
                    "seam_length": seam,
                    "seam_ratio": seam / total,
                    "uv_vertices": c.original.len(),
                }),
            );
        }
        merge(&mut object, metrics_json(&metrics));
        merge(&mut object, extra);
        println!("{object}");
    } else {
        println!(
            "{}: {} vertices, {} triangles, {:.3} s -> {}",
            method_label(args.method()),
            mesh.vertex_count(),
            mesh.triangle_count(),
            seconds,
            args.output.display()
        );
        if let Some(c) = &cut {
            let (seam, total) = (c.seam_length(&mesh), total_edge_length(&mesh));
            println!("  cut edges               {} (seam {:.4} of total edge length)", c.edges.len(), seam / total);
        }
        print_metrics_text(&metrics);
    }
    Ok(())
}

/// Overlaps of a raw layout by the independent checker, mirrored first when it is clockwise as
/// a whole (a mirror image is not a map of flips).
fn overlaps_of(uv: &[[f64; 2]], uv_triangles: &[[u32; 3]]) -> usize {
    let mirrored: Vec<[f64; 2]>;
    let layout = if uvflat_core::metrics::majority_orientation(uv, uv_triangles) < 0.0 {
        mirrored = uv.iter().map(|p| [-p[0], p[1]]).collect();
        &mirrored
    } else {
        uv
    };
    check_layout(layout, uv_triangles).overlaps
}

/// L2 stretch above which a named method's result is reported as hard to texture (the default
/// unwrap's bound).
const WARN_STRETCH: f64 = 1.5;

/// A warning on stderr when a named method's layout flips, overlaps or stretches (the default
/// unwrap never does).
fn warn_if_unusable(method: &str, metrics: &Metrics, overlaps: usize) {
    let mut problems = Vec::new();
    if metrics.flipped + metrics.degenerate_uv > 0 {
        problems.push(format!("{} flipped or degenerate triangles", metrics.flipped + metrics.degenerate_uv));
    }
    if overlaps > 0 {
        problems.push(format!("{overlaps} overlapping boundary-edge pairs"));
    }
    if metrics.stretch_l2 > WARN_STRETCH {
        problems.push(format!("L2 stretch {:.3} (above {WARN_STRETCH})", metrics.stretch_l2));
    }
    if !problems.is_empty() {
        eprintln!(
            "warning: the {method} layout has {}; run without --method for a layout without flips or overlaps",
            problems.join(", ")
        );
    }
}

/// The default unwrap: the library's whole pipeline (valid by construction and verified).
fn unwrap_default(args: &UnwrapArgs, obj: &ObjMesh, mesh: &TriMesh, start: Instant) -> Result<(), Failure> {
    if !args.pins.is_empty() {
        return Err(usage("--pin applies to --method natural-conformal, abf and abf++ only"));
    }
    let defaults = UnwrapOptions::default();
    let options = UnwrapOptions {
        max_stretch: args.max_stretch.unwrap_or(defaults.max_stretch),
        margin: args.margin.unwrap_or(defaults.margin),
        iterations: args.iterations.unwrap_or(defaults.iterations),
        rotate: !args.no_rotate,
        ..defaults
    };
    let result = unwrap_with_progress(mesh, &options, &mut Progress::none())?;
    let seconds = start.elapsed().as_secs_f64();
    report_atlas(args, obj, mesh, &result.atlas, seconds, Some(&result.report))
}

/// `--cone V:DEGREES` values as (vertex, curvature in radians).
fn parse_cones(values: &[String]) -> Result<Vec<(u32, f64)>, Failure> {
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
fn circle_pattern_options(args: &UnwrapArgs, mesh: &TriMesh) -> Result<CirclePatternOptions, Failure> {
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
fn unwrap_cone_map(args: &UnwrapArgs, obj: &ObjMesh, mesh: &TriMesh, start: Instant) -> Result<(), Failure> {
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

impl UnwrapArgs {
    /// The chosen method (natural-conformal when none is given).
    fn method(&self) -> MethodName {
        self.method.unwrap_or(MethodName::NaturalConformal)
    }
}

/// `--atlas`: charts under the stretch bound, packed into the unit square.
fn unwrap_atlas(args: &UnwrapArgs) -> Result<(), Failure> {
    if args.cut == Some(CutMode::None) {
        return Err(usage("--atlas cuts the mesh into charts; it cannot be combined with --cut none"));
    }
    let inapplicable = [
        ("--boundary", args.boundary.is_some()),
        ("--distribution", args.distribution.is_some()),
        ("--pin", !args.pins.is_empty()),
        ("--lambda", args.lambda.is_some()),
        ("--mu", args.mu.is_some()),
        ("--theta", args.theta.is_some()),
        ("--energy", args.energy.is_some()),
        ("--no-intrinsic-delaunay", args.no_intrinsic_delaunay),
        ("--corner", !args.corners.is_empty()),
        ("--convex-boundary", args.convex_boundary),
        ("--cone", !args.cones.is_empty()),
        ("--auto-cones", args.auto_cones),
        ("--max-cones", args.max_cones.is_some()),
        ("--max-log-scale", args.max_log_scale.is_some()),
    ];
    let given: Vec<&str> = inapplicable.iter().filter(|(_, set)| *set).map(|(flag, _)| *flag).collect();
    if !given.is_empty() {
        return Err(usage(format!("{} do(es) not apply to --atlas", given.join(", "))));
    }
    let method = match args.method() {
        MethodName::NaturalConformal => ChartMethod::NaturalConformal,
        MethodName::MeanValue => ChartMethod::MeanValue,
        MethodName::Slim => ChartMethod::Slim,
        MethodName::Stretch => ChartMethod::Stretch,
        other => {
            return Err(usage(format!(
                "--atlas flattens charts with natural-conformal, mean-value, slim or stretch, not {}",
                method_label(other)
            )))
        }
    };
    let defaults = AtlasOptions::default();
    let options = AtlasOptions {
        max_stretch: args.max_stretch.unwrap_or(defaults.max_stretch),
        margin: args.margin.unwrap_or(defaults.margin),
        method,
        iterations: args.iterations.unwrap_or(defaults.iterations),
        rotate: !args.no_rotate,
        merge: defaults.merge,
        polish: args.polish.unwrap_or(defaults.polish),
        repair: defaults.repair,
    };
    let (obj, mesh) = load_mesh(&args.input)?;
    let start = Instant::now();
    let result = atlas(&mesh, &options)?;
    let seconds = start.elapsed().as_secs_f64();
    report_atlas(args, &obj, &mesh, &result, seconds, None)
}

/// Writes an atlas (per-corner UVs) and prints its figures: charts, utilization, seam ratio,
/// metrics; `unwrapped` holds the default unwrap's report (`None` for `--atlas`).
fn report_atlas(
    args: &UnwrapArgs,
    obj: &ObjMesh,
    mesh: &TriMesh,
    atlas: &Atlas,
    seconds: f64,
    unwrapped: Option<&UnwrapReport>,
) -> Result<(), Failure> {
    let flat: Vec<u32> = atlas.triangles.iter().flatten().copied().collect();
    write_obj_with_corner_uv(&args.output, &obj.positions, &obj.triangles, &atlas.uv, &flat)?;
    if let Some(svg) = &args.svg {
        write_uv_svg(svg, &atlas.uv, &atlas.triangles)?;
    }
    let metrics = distortion(mesh.points(), mesh.triangles(), &atlas.uv, &atlas.triangles)?;
    let (seam, total) = (atlas_seam_length(mesh, atlas), total_edge_length(mesh));
    let label = if unwrapped.is_some() { "default" } else { method_label(args.method()) };
    if args.json {
        let mut object = serde_json::json!({
            "method": label,
            "mode": if unwrapped.is_some() { "unwrap" } else { "atlas" },
            "seconds": seconds,
            "vertices": mesh.vertex_count(),
            "output": args.output.display().to_string(),
            "charts": atlas.charts.len(),
            "utilization": atlas.utilization,
            "seam_length": seam,
            "seam_ratio": seam / total,
            "uv_vertices": atlas.uv.len(),
        });
        if let Some(r) = unwrapped {
            merge(
                &mut object,
                serde_json::json!({
                    "islands": r.islands,
                    "repaired_islands": r.repaired_islands,
                    "seam_edges": r.seam_edges,
                    "overlaps": r.overlaps,
                    "max_island_stretch": r.max_island_stretch,
                }),
            );
        }
        merge(&mut object, metrics_json(&metrics));
        println!("{object}");
    } else {
        println!(
            "{label}{}: {} vertices, {} triangles, {:.3} s -> {}",
            if unwrapped.is_some() { " unwrap" } else { " (atlas)" },
            mesh.vertex_count(),
            mesh.triangle_count(),
            seconds,
            args.output.display()
        );
        if let Some(r) = unwrapped {
            println!(
                "  islands                 {} ({} laid out by bijective SLIM: the natural conformal map flipped or overlapped)",
                r.islands, r.repaired_islands
            );
            println!("  verified                {} flipped, {} overlaps", r.flipped, r.overlaps);
            println!("  largest island L2       {:.4}", r.max_island_stretch);
        } else {
            println!("  charts                  {}", atlas.charts.len());
        }
        println!("  utilization             {:.3}", atlas.utilization);
        println!("  seam                    {:.4} of total edge length", seam / total);
        print_metrics_text(&metrics);
    }
    Ok(())
}

/// Total 3D length of the input edges whose two sides have different UV vertices.
fn atlas_seam_length(mesh: &TriMesh, atlas: &Atlas) -> f64 {
    let twin = &mesh.connectivity().twin;
    let corner = |h: usize| atlas.triangles[h / 3][h % 3];
    (0..twin.len())
        .filter(|&h| twin[h] != u32::MAX && (twin[h] as usize) > h)
        .filter(|&h| {
            let g = twin[h] as usize;
            let (nh, ng) = (3 * (h / 3) + (h + 1) % 3, 3 * (g / 3) + (g + 1) % 3);
            corner(h) != corner(ng) || corner(nh) != corner(g)
        })
        .map(|h| {
            let (a, b) = (mesh.tail(h as u32), mesh.head(h as u32));
            let (p, q) = (mesh.points()[a as usize], mesh.points()[b as usize]);
            ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
        })
        .fold(0.0, |a, b| a + b) // not `sum`, whose empty sum is −0.0
}

fn sphere(args: &SphereArgs) -> Result<(), Failure> {
    check_outputs(&[("-o", Some(&args.output))])?;
    let relaxed = matches!(args.method, SphereMethodName::TutteGnomonic | SphereMethodName::GaussSeidel);
    if args.sweeps.is_some() && !relaxed {
        return Err(usage("--sweeps applies to --method tutte-gnomonic and gauss-seidel only"));
    }
    let (obj, mesh) = load_mesh(&args.input)?;
    let method = match args.method {
        SphereMethodName::TutteGnomonic => SphereMethod::TutteGnomonic,
        SphereMethodName::GaussSeidel => SphereMethod::GaussSeidel,
        SphereMethodName::Stereographic => SphereMethod::Stereographic,
        SphereMethodName::CirclePatterns => SphereMethod::CirclePatterns,
    };
    let start = Instant::now();
    let map = spherical_map(&mesh, &SphereOptions { method, sweeps: args.sweeps.unwrap_or(100) })?;
    let seconds = start.elapsed().as_secs_f64();
    write_sphere_obj(&args.output, &map.positions, &obj.triangles)?;
    let name = SphereMethodName::value_variants()
        .iter()
        .find(|m| **m == args.method)
        .and_then(|m| m.to_possible_value())
        .map_or("?".to_string(), |v| v.get_name().to_string());
    if args.json {
        println!(
            "{}",
            serde_json::json!({"method": name, "seconds": seconds, "vertices": mesh.vertex_count(), "triangles": mesh.triangle_count(), "flipped": map.flipped, "output": args.output.display().to_string()})
        );
    } else {
        println!(
            "{name}: {} vertices, {} triangles, {:.3} s, {} flipped -> {}",
            mesh.vertex_count(),
            mesh.triangle_count(),
            seconds,
            map.flipped,
            args.output.display()
        );
    }
    Ok(())
}

/// `uvflat quadcover`: per-corner (u, v) in grid units, written as `vt`.
fn quad_cover(args: &QuadCoverArgs) -> Result<(), Failure> {
    if args.quad_svg.is_some() && args.quad_mesh.is_none() {
        return Err(usage("--quad-svg needs --quad-mesh"));
    }
    check_density("--quad-density", args.quad_density)?;
    check_outputs(&[
        ("-o", Some(&args.output)),
        ("--svg", args.svg.as_deref()),
        ("--quad-mesh", args.quad_mesh.as_deref()),
        ("--quad-svg", args.quad_svg.as_deref()),
    ])?;
    let obj = read_obj_geometry(&args.input)?;
    let mesh = TriMesh::new(&obj.positions, &obj.triangles)?;
    let options = QuadCoverOptions {
        grid_spacing: args.grid_spacing,
        alignment: args.alignment,
        round: !args.no_round,
        cones_on_grid: args.cones_on_grid,
        pair_cells: args.pair_cells,
        untangle: !args.no_untangle,
        ..QuadCoverOptions::default()
    };
    let start = Instant::now();
    let result = quadcover(&mesh, &options, &mut Progress::none())?;
    let seconds = start.elapsed().as_secs_f64();
    let uv: Vec<[f64; 2]> = result.uv.iter().flatten().copied().collect();
    let uv_triangles: Vec<u32> = (0..uv.len() as u32).collect();
    write_obj_with_corner_uv(&args.output, &obj.positions, &obj.triangles, &uv, &uv_triangles)?;
    if let Some(svg) = &args.svg {
        let tris: Vec<[u32; 3]> = (0..result.uv.len() as u32).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect();
        write_uv_svg(svg, &uv, &tris)?;
    }
    let quads = match &args.quad_mesh {
        Some(path) => Some(write_quad_mesh(
            &quadcover_quad_mesh(&mesh, &result, args.quad_density)?,
            path,
            args.quad_svg.as_deref(),
        )?),
        None => None,
    };
    if args.json {
        println!(
            "{}",
            serde_json::json!({
                "method": "quadcover", "seconds": seconds, "vertices": mesh.vertex_count(),
                "triangles": mesh.triangle_count(), "genus": mesh.topology().genus,
                "grid_spacing": result.grid_spacing, "cones": result.cones.len(), "chains": result.chains,
                "cone_pairs": serde_json::json!({
                    "cones_before": result.cone_pairs.cones_before, "pairs": result.cone_pairs.pairs,
                    "moved_to_boundary": result.cone_pairs.moved_to_boundary, "trials": result.cone_pairs.trials,
                }),
                "untangled": serde_json::json!({
                    "folded_before": result.untangled.folded_before, "folded_after": result.untangled.folded_after,
                    "groups": result.untangled.groups, "groups_kept": result.untangled.groups_kept,
                    "forced_flat": result.untangled.forced_flat,
                }),
                "flipped": result.flipped, "rounding_offset": result.rounding_offset,
                "lattice_error": result.lattice_error, "energy_continuous": result.energy_continuous,
                "energy": result.energy, "output": args.output.display().to_string(),
                "quad_mesh": quads.map(|(faces, quads, vertices)| serde_json::json!({
                    "faces": faces, "quads": quads, "vertices": vertices, "density": args.quad_density,
                })),
            })
        );
    } else {
        println!(
            "quadcover: {} vertices, {} triangles, genus {}, grid spacing {:.4}, {:.3} s -> {}",
            mesh.vertex_count(),
            mesh.triangle_count(),
            mesh.topology().genus,
            result.grid_spacing,
            seconds,
            args.output.display()
        );
        println!("  cones / cutting paths       {} / {}", result.cones.len(), result.chains);
        let pairs = &result.cone_pairs;
        if pairs.pairs + pairs.moved_to_boundary > 0 {
            println!(
                "  cone-pair cancellation      {} -> {} cones ({} pair moves, {} cones moved onto the boundary)",
                pairs.cones_before, pairs.cones_after, pairs.pairs, pairs.moved_to_boundary
            );
        }
        println!(
            "  folded triangles            {} ({:.2}%)",
            result.flipped,
            100.0 * result.flipped as f64 / mesh.triangle_count().max(1) as f64
        );
        let u = &result.untangled;
        if u.folded_before > 0 {
            println!(
                "  untangling                  {} -> {} folded ({} of {} groups kept; {} flat whatever the vertices)",
                u.folded_before, u.folded_after, u.groups_kept, u.groups, u.forced_flat
            );
        }
        println!(
            "  field energy (eq. 8.6)      {:.4} continuous, {:.4} with integer gaps (largest gap offset {:.3})",
            result.energy_continuous, result.energy, result.rounding_offset
        );
        if let Some((faces, quad_count, vertices)) = quads {
            println!(
                "  quad mesh                   {faces} faces ({:.1}% quads), {vertices} vertices",
                100.0 * quad_count as f64 / faces.max(1) as f64
            );
            if faces == 0 {
                println!(
                    "  (no grid line survived: the lines stop at folded triangles and cones, which cover \
                     this surface; a smaller --grid-spacing folds less)"
                );
            }
        }
    }
    Ok(())
}

/// Lines per period or per grid unit: a whole number ≥ 1 (checked before any work).
fn check_density(flag: &str, value: f64) -> Result<(), Failure> {
    if value >= 1.0 && value.fract() == 0.0 {
        Ok(())
    } else {
        Err(usage(format!("{flag} must be a whole number >= 1 (got {value})")))
    }
}

/// Refuses, before any work, output files that could not all be written or would overwrite
/// one another: two options naming one file, a path that is a directory, a directory that does
/// not exist. (Writing the main OBJ and then failing on a side output left a partial result.)
fn check_outputs(outputs: &[(&str, Option<&Path>)]) -> Result<(), Failure> {
    let given: Vec<(&str, &Path)> = outputs.iter().filter_map(|&(flag, path)| path.map(|p| (flag, p))).collect();
    for (i, &(flag, path)) in given.iter().enumerate() {
        if path.is_dir() {
            return Err(usage(format!("{flag} {} is a directory", path.display())));
        }
        let parent = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
        if !parent.is_dir() {
            return Err(usage(format!("{flag} {}: the directory {} does not exist", path.display(), parent.display())));
        }
        if let Some(&(other, _)) = given[..i].iter().find(|&&(_, q)| same_file(path, q)) {
            return Err(usage(format!("{other} and {flag} name the same file {}", path.display())));
        }
    }
    Ok(())
}

/// Whether two output paths name the same file (their directories resolved).
fn same_file(a: &Path, b: &Path) -> bool {
    let resolved = |p: &Path| {
        let parent = p.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."));
        Some(parent.canonicalize().ok()?.join(p.file_name()?))
    };
    a == b || matches!((resolved(a), resolved(b)), (Some(x), Some(y)) if x == y)
}

/// Writes a polygon mesh to an OBJ (and its picture to an SVG); returns its face, quad and
/// vertex counts.
fn write_quad_mesh(remesh: &PolygonMesh, path: &Path, svg: Option<&Path>) -> Result<(usize, usize, usize), Failure> {
    write_polygon_obj(path, remesh)?;
    if let Some(svg) = svg {
        let faces: Vec<Vec<u32>> = remesh.faces().map(|f| f.to_vec()).collect();
        write_polygon_mesh_svg(svg, &remesh.positions, &faces)?;
    }
    Ok((remesh.face_sizes.len(), remesh.quad_count(), remesh.positions.len()))
}

fn periodic(args: &PgpArgs) -> Result<(), Failure> {
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
fn chart_counts(c: &ChartParameterization) -> [usize; 5] {
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
fn write_chart_obj(path: &Path, c: &ChartParameterization) -> Result<(), Failure> {
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

/// Writes a polygon mesh as `v` and `f` lines.
fn write_polygon_obj(path: &Path, mesh: &PolygonMesh) -> Result<(), Failure> {
    use std::io::Write;
    let fail = |e: std::io::Error| Failure { message: format!("cannot write {}: {e}", path.display()), usage: false };
    let mut out = std::io::BufWriter::new(std::fs::File::create(path).map_err(fail)?);
    for p in &mesh.positions {
        writeln!(out, "v {} {} {}", p[0], p[1], p[2]).map_err(fail)?;
    }
    for face in mesh.faces() {
        let line: Vec<String> = face.iter().map(|&v| (v + 1).to_string()).collect();
        writeln!(out, "f {}", line.join(" ")).map_err(fail)?;
    }
    out.flush().map_err(fail)
}

/// Writes `v` lines (NaN positions of unreferenced vertices as `v 0 0 0`) and `f` lines.
fn write_sphere_obj(path: &Path, positions: &[[f64; 3]], triangles: &[u32]) -> Result<(), Failure> {
    use std::io::Write;
    let fail = |e: std::io::Error| Failure { message: format!("cannot write {}: {e}", path.display()), usage: false };
    let mut out = std::io::BufWriter::new(std::fs::File::create(path).map_err(fail)?);
    for p in positions {
        let p = if p.iter().all(|x| x.is_finite()) { *p } else { [0.0; 3] };
        writeln!(out, "v {} {} {}", p[0], p[1], p[2]).map_err(fail)?;
    }
    for t in triangles.chunks_exact(3) {
        writeln!(out, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1).map_err(fail)?;
    }
    out.flush().map_err(fail)
}

/// Rejects options that do not apply to the chosen method, so nothing is silently ignored.
fn check_option_combination(args: &UnwrapArgs) -> Result<(), Failure> {
    if args.atlas {
        return Ok(()); // checked by `unwrap_atlas`
    }
    let method = args.method();
    let free = matches!(
        method,
        MethodName::NaturalConformal
            | MethodName::Abf
            | MethodName::AbfPlusPlus
            | MethodName::SpectralConformal
            | MethodName::CirclePatterns
    );
    let nonlinear = method.nonlinear().is_some();
    let optimizing = matches!(method, MethodName::IntrinsicOptimal | MethodName::BoundaryOptimized);
    if (free || nonlinear) && (args.boundary.is_some() || args.distribution.is_some()) {
        return Err(usage(format!(
            "--boundary and --distribution apply to fixed-boundary methods, not {}",
            method_label(method)
        )));
    }
    if args.method.is_some() && !(nonlinear || method == MethodName::BoundaryOptimized) && args.iterations.is_some() {
        return Err(usage(
            "--iterations applies to the non-linear methods (slim, arap, mips, stretch, green-lagrange, degener) and boundary-optimized",
        ));
    }
    if !nonlinear && args.bijective {
        return Err(usage(
            "--bijective applies to the non-linear methods (slim, arap, mips, stretch, green-lagrange, degener)",
        ));
    }
    if method != MethodName::Degener && args.theta.is_some() {
        return Err(usage("--theta applies to --method degener only"));
    }
    if !matches!(method, MethodName::NaturalConformal | MethodName::Abf | MethodName::AbfPlusPlus)
        && !args.pins.is_empty()
    {
        return Err(usage("--pin applies to --method natural-conformal, abf and abf++ only"));
    }
    if free && !args.pins.is_empty() && args.pins.len() != 2 {
        return Err(usage(format!("give --pin exactly twice (got {})", args.pins.len())));
    }
    if !matches!(method, MethodName::Intrinsic | MethodName::BoundaryOptimized)
        && (args.lambda.is_some() || args.mu.is_some())
    {
        return Err(usage("--lambda and --mu apply to --method intrinsic and boundary-optimized only"));
    }
    if !optimizing && args.energy.is_some() {
        return Err(usage("--energy applies to --method intrinsic-optimal and boundary-optimized only"));
    }
    if method != MethodName::CirclePatterns
        && (args.no_intrinsic_delaunay
            || !args.corners.is_empty()
            || !args.cones.is_empty()
            || args.convex_boundary
            || args.auto_cones)
    {
        return Err(usage(
            "--no-intrinsic-delaunay, --corner, --convex-boundary, --cone and --auto-cones apply to --method circle-patterns only",
        ));
    }
    if (!args.cones.is_empty() || args.auto_cones) && (args.cut.is_some() || !args.pins.is_empty()) {
        return Err(usage("--cone and --auto-cones cut the mesh through the cones: no --cut or --pin"));
    }
    if args.auto_cones && !args.cones.is_empty() {
        return Err(usage("give --cone or --auto-cones, not both"));
    }
    if !args.auto_cones && (args.max_cones.is_some() || args.max_log_scale.is_some()) {
        return Err(usage("--max-cones and --max-log-scale apply to --auto-cones only"));
    }
    Ok(())
}

/// The boundary shape and spacing of `--boundary` and `--distribution`.
fn boundary_of(args: &UnwrapArgs) -> Result<(BoundaryShape, Distribution), Failure> {
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

fn energy_of(args: &UnwrapArgs) -> (DistortionEnergy, &'static str) {
    match args.energy {
        None | Some(EnergyName::Edge) => (DistortionEnergy::EdgeLength, "edge"),
        Some(EnergyName::Area) => (DistortionEnergy::Area, "area"),
    }
}

/// No extra JSON fields.
fn plain(uv: Vec<[f64; 2]>) -> (Vec<[f64; 2]>, serde_json::Value) {
    (uv, serde_json::json!({}))
}

/// The UVs of the chosen method, and method-specific JSON fields.
fn run_method(mesh: &TriMesh, args: &UnwrapArgs) -> Result<(Vec<[f64; 2]>, serde_json::Value), Failure> {
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
fn cli_pins(mesh: &TriMesh, pins: &[u32]) -> Result<Option<[Pin; 2]>, Failure> {
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
fn read_boundary_file(path: &Path) -> Result<Vec<(u32, [f64; 2])>, Failure> {
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

fn print_metrics(path: &Path, json: bool) -> Result<(), Failure> {
    let obj = read_obj(path)?;
    if obj.uv.is_empty() {
        return Err(Failure {
            message: format!("{} has no texture coordinates (`vt` lines)", path.display()),
            usage: false,
        });
    }
    if obj.uv_triangles.len() != obj.triangles.len() {
        return Err(Failure {
            message: format!("{}: some faces have no texture coordinate indices (`f v/vt ...`)", path.display()),
            usage: false,
        });
    }
    let group3 = |flat: &[u32]| flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect::<Vec<_>>();
    let positions: Vec<[f64; 3]> = obj.positions.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    let uv: Vec<[f64; 2]> = obj.uv.chunks_exact(2).map(|c| [c[0], c[1]]).collect();
    let metrics = distortion(&positions, &group3(&obj.triangles), &uv, &group3(&obj.uv_triangles))?;
    if json {
        println!("{}", metrics_json(&metrics));
    } else {
        print_metrics_text(&metrics);
    }
    Ok(())
}

/// Area ratio (UV over 3D, both scaled to the same total) beyond which a triangle is reported as
/// collapsed or blown up: a map read from a file may press a triangle nearly flat without
/// flipping it (Green–Lagrange without its area floor did so on disk_cat_head: L2 stretch 3e5).
const EXTREME_AREA_RATIO: f64 = 1e4;

fn print_metrics_text(m: &Metrics) {
    if m.area_max > EXTREME_AREA_RATIO.ln() {
        eprintln!(
            "uvflat: warning: a triangle's UV area is {:.0e} times off its share of the surface's (|log| {:.1}); the \
             map is valid but nearly degenerate there",
            m.area_max.exp(),
            m.area_max
        );
    }
    println!("  triangles               {}", m.triangles);
    println!("  flipped                 {}", m.flipped);
    println!("  degenerate uv           {}", m.degenerate_uv);
    println!("  boundary intersections  {}", m.boundary_intersections);
    println!("  stretch L2 / Linf       {:.4} / {:.4}", m.stretch_l2, m.stretch_linf);
    println!("  conformal mean / max    {:.4} / {:.4}", m.conformal_mean, m.conformal_max);
    println!("  angle error mean / max  {:.3}° / {:.3}°", m.angle_mean.to_degrees(), m.angle_max.to_degrees());
    println!("  area |log| mean / max   {:.4} / {:.4}", m.area_mean, m.area_max);
}

fn info(path: &Path, json: bool) -> Result<(), Failure> {
    let (_, mesh) = load_mesh(path)?;
    let t = mesh.topology();
    if json {
        println!(
            "{}",
            serde_json::json!({
                "vertices": t.vertices,
                "referenced_vertices": t.referenced_vertices,
                "faces": t.triangles,
                "edges": t.edges,
                "components": t.components,
                "boundary_loops": t.boundary_loops,
                "euler_characteristic": t.euler_characteristic,
                "genus": t.genus,
            })
        );
    } else {
        println!("vertices        {} ({} referenced)", t.vertices, t.referenced_vertices);
        println!("faces           {}", t.triangles);
        println!("edges           {}", t.edges);
        println!("components      {}", t.components);
        println!("boundary loops  {}", t.boundary_loops);
        println!("euler           {}", t.euler_characteristic);
        println!("genus           {}", t.genus);
    }
    Ok(())
}

/// All fields of `metrics` as a JSON object (NaN becomes `null`).
fn metrics_json(metrics: &Metrics) -> serde_json::Value {
    serde_json::json!({
        "triangles": metrics.triangles,
        "flipped": metrics.flipped,
        "degenerate_uv": metrics.degenerate_uv,
        "stretch_l2": metrics.stretch_l2,
        "stretch_linf": metrics.stretch_linf,
        "conformal_mean": metrics.conformal_mean,
        "conformal_max": metrics.conformal_max,
        "angle_mean": metrics.angle_mean,
        "angle_max": metrics.angle_max,
        "area_mean": metrics.area_mean,
        "area_max": metrics.area_max,
        "boundary_intersections": metrics.boundary_intersections,
    })
}

/// Adds the fields of `extra` (a JSON object) to `object`.
fn merge(object: &mut serde_json::Value, extra: serde_json::Value) {
    if let (Some(o), serde_json::Value::Object(e)) = (object.as_object_mut(), extra) {
        o.extend(e);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `--json` reports every distortion field: an identity map of a 2 × 2 grid (8 triangles)
    /// has L2 stretch 1.
    #[test]
    fn metrics_json_has_every_field() {
        let positions: Vec<[f64; 3]> = (0..9).map(|i| [(i % 3) as f64, (i / 3) as f64, 0.0]).collect();
        let mut triangles = Vec::new();
        for (x, y) in [(0u32, 0u32), (1, 0), (0, 1), (1, 1)] {
            let v = y * 3 + x;
            triangles.push([v, v + 1, v + 4]);
            triangles.push([v, v + 4, v + 3]);
        }
        let uv: Vec<[f64; 2]> = positions.iter().map(|p| [p[0], p[1]]).collect();
        let metrics = uvflat_core::metrics::distortion(&positions, &triangles, &uv, &triangles).expect("metrics");
        let json = metrics_json(&metrics);
        assert_eq!(json["triangles"], 8);
        assert_eq!(json["flipped"], 0);
        assert_eq!(json.as_object().map(|o| o.len()), Some(12));
        assert!((json["stretch_l2"].as_f64().unwrap_or(0.0) - 1.0).abs() < 1e-12);
    }
}
