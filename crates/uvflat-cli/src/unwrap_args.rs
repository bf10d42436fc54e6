//! The options of `uvflat unwrap`, and the check that every option given applies to the chosen
//! method (nothing is silently ignored).

use std::path::PathBuf;

use crate::errors::{usage, Failure};
use crate::methods::{method_label, DistributionName, EnergyName, MethodName};
use clap::ValueEnum;

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum CutMode {
    /// Cut closed and higher-genus meshes into a disk (tree–cotree cut graph).
    Auto,
    /// Never cut (the method must accept the mesh as it is).
    None,
}

#[derive(clap::Args)]
pub(crate) struct UnwrapArgs {
    /// Input mesh (OBJ; polygons are fan-triangulated, or cut by ear clipping where the fan would
    /// fold).
    pub(crate) input: PathBuf,
    /// Output OBJ with one UV per vertex.
    #[arg(short = 'o', long = "output")]
    pub(crate) output: PathBuf,
    /// Parameterization method (see `uvflat methods`). Without it, the default unwrap: islands
    /// flattened by the natural conformal map, repaired by bijective SLIM where that flips or
    /// overlaps, split where over --max-stretch, packed into the unit square and verified (no
    /// flipped triangle, no overlap). A named method's own result is written as it is, with a
    /// warning when it flips, overlaps or stretches.
    #[arg(long, value_enum)]
    pub(crate) method: Option<MethodName>,
    /// Boundary of fixed-boundary methods: `circle`, `square`, or a file of lines
    /// `vertex_index u v` (0-based) fixing those boundary vertices.
    #[arg(long)]
    pub(crate) boundary: Option<String>,
    /// Spacing of boundary vertices along the circle or square.
    #[arg(long, value_enum)]
    pub(crate) distribution: Option<DistributionName>,
    /// λ of the intrinsic method (weight of the conformal part; may be negative); default 1.
    #[arg(long, allow_negative_numbers = true)]
    pub(crate) lambda: Option<f64>,
    /// μ of the intrinsic method (weight of the authalic part; may be negative); default 0.
    #[arg(long, allow_negative_numbers = true)]
    pub(crate) mu: Option<f64>,
    /// Vertex to pin, a 0-based index (the first `v` line is 0; natural-conformal; give exactly
    /// two). Default: the two boundary vertices farthest apart.
    #[arg(long = "pin")]
    pub(crate) pins: Vec<u32>,
    /// Iteration limit of the non-linear methods (slim, arap, mips, ...) and of the default
    /// unwrap's repair; default 100.
    #[arg(long)]
    pub(crate) iterations: Option<usize>,
    /// Non-linear methods: keep the whole map bijective (a scaffold around the free boundary, so
    /// the boundary cannot run into itself), not only free of flipped triangles.
    #[arg(long)]
    pub(crate) bijective: bool,
    /// θ of the degener method (weight of area against angle distortion); default 3.
    #[arg(long)]
    pub(crate) theta: Option<f64>,
    /// Distortion energy of intrinsic-optimal and boundary-optimized (Desbrun et al. 2002
    /// §5.1); default edge.
    #[arg(long, value_enum)]
    pub(crate) energy: Option<EnergyName>,
    /// circle-patterns: enforce the Delaunay condition on the mesh's own edges instead of
    /// flipping to the intrinsic Delaunay triangulation first (never flips, more distortion).
    #[arg(long = "no-intrinsic-delaunay")]
    pub(crate) no_intrinsic_delaunay: bool,
    /// circle-patterns: a vertex (0-based) that is a corner of a straight-sided convex polygon
    /// (give at least 3, on the longest boundary loop; 4 give a rectangle); default: free
    /// boundary.
    #[arg(long = "corner")]
    pub(crate) corners: Vec<u32>,
    /// circle-patterns: keep the UV boundary convex (every boundary vertex turns by at least 0),
    /// so the layout cannot overlap itself; with `--corner`, the polygon's own vertices keep
    /// their prescribed turning.
    #[arg(long = "convex-boundary")]
    pub(crate) convex_boundary: bool,
    /// circle-patterns: a cone singularity `V:DEGREES` at interior vertex V (0-based), its curvature in
    /// degrees (360 minus the cone angle: 90 for a cube corner); repeat. The mesh is then cut
    /// through the cones (any genus; on a closed mesh the curvatures must sum to 360·χ) and the
    /// UVs are per corner. Tori need none: give `--cone` with curvature 0 (e.g. `0:0`).
    #[arg(long = "cone")]
    pub(crate) cones: Vec<String>,
    /// circle-patterns: place the cones automatically (greedily where the conformal
    /// flattening's scale is largest, Ben-Chen et al. 2008) and cut through them; any genus,
    /// UVs per corner.
    #[arg(long = "auto-cones")]
    pub(crate) auto_cones: bool,
    /// With `--auto-cones`: most cones placed (default 64, or 4 per unit of −χ on a higher
    /// genus, which needs at least 2g − 2).
    #[arg(long = "max-cones", value_name = "N")]
    pub(crate) max_cones: Option<u32>,
    /// With `--auto-cones`: stop once the log scale is at most this everywhere (default 0.7,
    /// about a factor of 2 in length).
    #[arg(long = "max-log-scale", value_name = "S")]
    pub(crate) max_log_scale: Option<f64>,
    /// Also draw the UV layout into this SVG file.
    #[arg(long)]
    pub(crate) svg: Option<PathBuf>,
    /// Print one JSON object (method, seconds, metrics) instead of text.
    #[arg(long)]
    pub(crate) json: bool,
    /// With --method: cut the mesh into a disk first, `auto` (the default when the mesh is
    /// closed or has handles) or `none`; UVs are then per corner (`vt` indices differ from `v`
    /// indices). Without --method, `none` runs the plain natural conformal map (no cut, no
    /// repair, no packing).
    #[arg(long, value_enum)]
    pub(crate) cut: Option<CutMode>,
    /// Atlas mode: split into charts under a stretch bound, flatten each (natural-conformal by
    /// default; also mean-value, slim, stretch), pack them into the unit square.
    #[arg(long)]
    pub(crate) atlas: bool,
    /// Largest L2 stretch of an island: default unwrap 1.5, --atlas 1.004; `inf` turns the
    /// bound off (islands are split only where no valid layout is found).
    #[arg(long = "max-stretch")]
    pub(crate) max_stretch: Option<f64>,
    /// Default unwrap and --atlas: gap between packed islands in the unit square (default 0.005).
    #[arg(long)]
    pub(crate) margin: Option<f64>,
    /// Default unwrap and --atlas: do not rotate islands when packing.
    #[arg(long = "no-rotate")]
    pub(crate) no_rotate: bool,
    /// Atlas mode: L2-stretch polish iterations per chart (default 10; 0: none). Polishing
    /// lowers the L2 stretch and raises the angle error (charts are no longer conformal).
    #[arg(long)]
    pub(crate) polish: Option<usize>,
}

impl UnwrapArgs {
    /// The chosen method (natural-conformal when none is given).
    pub(crate) fn method(&self) -> MethodName {
        self.method.unwrap_or(MethodName::NaturalConformal)
    }
}

/// Rejects options that do not apply to the chosen method, so nothing is silently ignored.
pub(crate) fn check_option_combination(args: &UnwrapArgs) -> Result<(), Failure> {
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
