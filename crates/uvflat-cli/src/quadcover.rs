//! `uvflat quadcover`: QuadCover's seamless grid parameterization and its quad mesh.

use std::path::PathBuf;
use std::time::Instant;

use crate::errors::{check_density, check_outputs, usage, Failure};
use crate::files::write_quad_mesh;
use uvflat_core::io::obj::{read_obj_geometry, write_obj_with_corner_uv};
use uvflat_core::io::svg::write_uv_svg;
use uvflat_core::methods::quadcover::{quad_mesh as quadcover_quad_mesh, quadcover, QuadCoverOptions};
use uvflat_core::progress::Progress;
use uvflat_core::TriMesh;

#[derive(clap::Args)]
pub(crate) struct QuadCoverArgs {
    /// Input mesh (OBJ), one connected component.
    pub(crate) input: PathBuf,
    /// Output OBJ with per-corner texture coordinates (u, v).
    #[arg(short = 'o', long = "output")]
    pub(crate) output: PathBuf,
    /// Surface length of one grid cell. Default: 3 mean edge lengths.
    #[arg(long = "grid-spacing")]
    pub(crate) grid_spacing: Option<f64>,
    /// Alignment of the frame field to the principal curvature directions (> 0).
    #[arg(long, default_value_t = uvflat_core::methods::quadcover::field::DEFAULT_ALIGNMENT)]
    pub(crate) alignment: f64,
    /// Keep the continuous solve: no rounding of gaps and cone positions (not seamless).
    #[arg(long = "no-round")]
    pub(crate) no_round: bool,
    /// Also put every cone on an integer point (irregular vertices of the grid); default: only
    /// the gaps are integers, as in the course notes (fewer folds).
    #[arg(long = "cones-on-grid")]
    pub(crate) cones_on_grid: bool,
    /// Cancel ± cone pairs of the field closer than this many grid cells, and move cones that
    /// close to the boundary onto it (0: keep the field's cones).
    #[arg(long = "pair-cells", default_value_t = uvflat_core::methods::quadcover::cone_pairs::DEFAULT_PAIR_CELLS)]
    pub(crate) pair_cells: f64,
    /// Keep the folds the rounding leaves: no untangling of the vertices near them.
    #[arg(long = "no-untangle")]
    pub(crate) no_untangle: bool,
    /// Also write an SVG picture of the (u, v) triangles.
    #[arg(long)]
    pub(crate) svg: Option<PathBuf>,
    /// Write the quad-dominant mesh of the integer iso-lines (non-quads split into quads and at
    /// most one triangle) to this OBJ.
    #[arg(long = "quad-mesh")]
    pub(crate) quad_mesh: Option<PathBuf>,
    /// Iso-lines per grid unit for --quad-mesh (a whole number >= 1; 1: one quad per grid
    /// cell).
    #[arg(long = "quad-density", default_value_t = 1.0)]
    pub(crate) quad_density: f64,
    /// Draw the quad mesh into this SVG file (needs --quad-mesh).
    #[arg(long = "quad-svg")]
    pub(crate) quad_svg: Option<PathBuf>,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub(crate) json: bool,
}

/// `uvflat quadcover`: per-corner (u, v) in grid units, written as `vt`.
pub(crate) fn quad_cover(args: &QuadCoverArgs) -> Result<(), Failure> {
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
