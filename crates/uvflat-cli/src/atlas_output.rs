//! `uvflat unwrap --atlas` and the report of a multi-island result: charts, utilization, seam
//! length, metrics.

use std::time::Instant;

use crate::errors::{usage, Failure};
use crate::files::load_mesh;
use crate::methods::{method_label, MethodName};
use crate::metrics::{merge, metrics_json, print_metrics_text};
use crate::unwrap_args::{CutMode, UnwrapArgs};
use uvflat_core::atlas::{atlas, Atlas, AtlasOptions, ChartMethod};
use uvflat_core::io::obj::{write_obj_with_corner_uv, ObjMesh};
use uvflat_core::io::svg::write_uv_svg;
use uvflat_core::mesh::cut::total_edge_length;
use uvflat_core::metrics::distortion;
use uvflat_core::unwrap::UnwrapReport;
use uvflat_core::TriMesh;

/// `--atlas`: charts under the stretch bound, packed into the unit square.
pub(crate) fn unwrap_atlas(args: &UnwrapArgs) -> Result<(), Failure> {
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
    report_atlas(args, &obj, Some(&mesh), &result, seconds, None)
}

/// Writes an atlas (per-corner UVs) and prints its figures: charts, utilization, seam ratio,
/// metrics; `unwrapped` holds the default unwrap's report (`None` for `--atlas`).
pub(crate) fn report_atlas(
    args: &UnwrapArgs,
    obj: &ObjMesh,
    mesh: Option<&TriMesh>,
    atlas: &Atlas,
    seconds: f64,
    unwrapped: Option<&UnwrapReport>,
) -> Result<(), Failure> {
    let flat: Vec<u32> = atlas.triangles.iter().flatten().copied().collect();
    write_obj_with_corner_uv(&args.output, &obj.positions, &obj.triangles, &atlas.uv, &flat)?;
    if let Some(svg) = &args.svg {
        write_uv_svg(svg, &atlas.uv, &atlas.triangles)?;
    }
    // Without a mesh (zero-area triangles welded for the solve), the input's own arrays.
    let (seam, total) = match mesh {
        Some(mesh) => (atlas_seam_length(mesh, atlas), total_edge_length(mesh)),
        None => seam_and_total_length(&obj.positions, &obj.triangles, atlas),
    };
    let points: Vec<[f64; 3]> = obj.positions.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    let triangles: Vec<[u32; 3]> = obj.triangles.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    let metrics = match mesh {
        Some(mesh) => distortion(mesh.points(), mesh.triangles(), &atlas.uv, &atlas.triangles)?,
        None => distortion(&points, &triangles, &atlas.uv, &atlas.triangles)?,
    };
    let (vertex_count, triangle_count) = (points.len(), triangles.len());
    let label = if unwrapped.is_some() { "default" } else { method_label(args.method()) };
    if args.json {
        let mut object = serde_json::json!({
            "method": label,
            "mode": if unwrapped.is_some() { "unwrap" } else { "atlas" },
            "seconds": seconds,
            "vertices": vertex_count,
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
                    "welded_vertices": r.welded_vertices,
                    "left_out_triangles": r.left_out_triangles,
                }),
            );
        }
        merge(&mut object, metrics_json(&metrics));
        println!("{object}");
    } else {
        println!(
            "{label}{}: {} vertices, {} triangles, {:.3} s -> {}",
            if unwrapped.is_some() { " unwrap" } else { " (atlas)" },
            vertex_count,
            triangle_count,
            seconds,
            args.output.display()
        );
        if let Some(r) = unwrapped {
            println!(
                "  islands                 {} ({} laid out by bijective SLIM: the natural conformal map flipped or overlapped)",
                r.islands, r.repaired_islands
            );
            println!("  verified                {} flipped, {} overlaps", r.flipped, r.overlaps);
            if r.left_out_triangles > 0 {
                println!(
                    "  zero-area triangles     {} left out of the solve ({} snapped vertices welded)",
                    r.left_out_triangles, r.welded_vertices
                );
            }
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

/// (Seam length, total edge length) from flat arrays: edges (vertex pairs) whose uses do not all
/// have the same two UV vertices, and all edges; for meshes `TriMesh` refuses.
fn seam_and_total_length(positions: &[f64], triangles: &[u32], atlas: &Atlas) -> (f64, f64) {
    let mut uses: std::collections::HashMap<[u32; 2], Vec<[u32; 2]>> = std::collections::HashMap::new();
    for (t, corners) in triangles.chunks_exact(3).zip(&atlas.triangles) {
        for k in 0..3 {
            let (a, b, ua, ub) = (t[k], t[(k + 1) % 3], corners[k], corners[(k + 1) % 3]);
            let (key, uv) = if a < b { ([a, b], [ua, ub]) } else { ([b, a], [ub, ua]) };
            uses.entry(key).or_default().push(uv);
        }
    }
    let length = |[a, b]: [u32; 2]| {
        let (p, q) = (&positions[3 * a as usize..3 * a as usize + 3], &positions[3 * b as usize..3 * b as usize + 3]);
        ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
    };
    let mut edges: Vec<_> = uses.into_iter().collect();
    edges.sort_unstable_by_key(|e| e.0);
    let seam =
        edges.iter().filter(|(_, uv)| uv.iter().any(|x| x != &uv[0])).map(|e| length(e.0)).fold(0.0, |a, b| a + b);
    let total = edges.iter().map(|e| length(e.0)).fold(0.0, |a, b| a + b);
    (seam, total)
}

/// Total 3D length of the input edges whose two sides have different UV vertices.
pub(crate) fn atlas_seam_length(mesh: &TriMesh, atlas: &Atlas) -> f64 {
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
