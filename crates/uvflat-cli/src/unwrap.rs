//! `uvflat unwrap`: the default unwrap (the library's valid-by-construction pipeline), a named
//! method or an atlas, and the warnings for a named method's unusable layout.

use std::time::Instant;

use crate::atlas_output::{report_atlas, unwrap_atlas};
use crate::errors::{check_outputs, usage, Failure};
use crate::methods::method_label;
use crate::metrics::{merge, metrics_json, print_metrics_text};
use crate::named_method::{run_method, unwrap_cone_map};
use crate::unwrap_args::{check_option_combination, CutMode, UnwrapArgs};
use uvflat_core::error::Error;
use uvflat_core::io::obj::{read_obj_geometry, write_obj_with_corner_uv, write_obj_with_uv, ObjMesh};
use uvflat_core::io::svg::write_uv_svg;
use uvflat_core::mesh::cut::{cut_to_disk, total_edge_length, EdgeCost};
use uvflat_core::metrics::{distortion, Metrics};
use uvflat_core::progress::Progress;
use uvflat_core::unwrap::{unwrap_arrays, unwrap_with_progress, UnwrapOptions};
use uvflat_core::verify::check_layout;
use uvflat_core::TriMesh;

pub(crate) fn unwrap(args: &UnwrapArgs) -> Result<(), Failure> {
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
    let default_unwrap =
        args.cones.is_empty() && !args.auto_cones && args.method.is_none() && args.cut != Some(CutMode::None);
    let mesh = match TriMesh::new(&obj.positions, &obj.triangles) {
        Ok(mesh) => mesh,
        // Zero-area triangles (snapped vertices): the default unwrap welds them for the solve.
        Err(Error::DegenerateTriangle { .. } | Error::RepeatedVertex { .. }) if default_unwrap => {
            return unwrap_default_snapped(args, &obj, start);
        }
        Err(e) => return Err(Failure { message: format!("{}: {e}", args.input.display()), usage: false }),
    };
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
pub(crate) fn overlaps_of(uv: &[[f64; 2]], uv_triangles: &[[u32; 3]]) -> usize {
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
pub(crate) const WARN_STRETCH: f64 = 1.5;

/// A warning on stderr when a named method's layout flips, overlaps or stretches (the default
/// unwrap never does).
pub(crate) fn warn_if_unusable(method: &str, metrics: &Metrics, overlaps: usize) {
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
pub(crate) fn unwrap_default(args: &UnwrapArgs, obj: &ObjMesh, mesh: &TriMesh, start: Instant) -> Result<(), Failure> {
    let options = default_options(args)?;
    let result = unwrap_with_progress(mesh, &options, &mut Progress::none())?;
    let seconds = start.elapsed().as_secs_f64();
    report_atlas(args, obj, Some(mesh), &result.atlas, seconds, Some(&result.report))
}

/// The default unwrap's options from the command line.
fn default_options(args: &UnwrapArgs) -> Result<UnwrapOptions, Failure> {
    if !args.pins.is_empty() {
        return Err(usage("--pin applies to --method natural-conformal, abf and abf++ only"));
    }
    let defaults = UnwrapOptions::default();
    Ok(UnwrapOptions {
        max_stretch: args.max_stretch.unwrap_or(defaults.max_stretch),
        margin: args.margin.unwrap_or(defaults.margin),
        iterations: args.iterations.unwrap_or(defaults.iterations),
        rotate: !args.no_rotate,
        ..defaults
    })
}

/// The default unwrap of a mesh with zero-area triangles, which `TriMesh` refuses: snapped
/// vertices welded and zero-area triangles left out of the solve (`unwrap_arrays`).
fn unwrap_default_snapped(args: &UnwrapArgs, obj: &ObjMesh, start: Instant) -> Result<(), Failure> {
    let options = default_options(args)?;
    let result = unwrap_arrays(&obj.positions, &obj.triangles, &options, &mut Progress::none())
        .map_err(|e| Failure { message: format!("{}: {e}", args.input.display()), usage: false })?;
    let seconds = start.elapsed().as_secs_f64();
    report_atlas(args, obj, None, &result.atlas, seconds, Some(&result.report))
}
