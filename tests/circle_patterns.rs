//! Circle-pattern conformal map (Kharevych, Springborn & Schröder 2006; partial implementation,
//! see the README) on the real disk meshes of `../shared/meshes` up to 10k faces: where it
//! returns a map, the pattern's angles make a planar triangulation, so no triangle is flipped or
//! degenerate and every circle closes; where it does not, the error is a numerical-failure
//! status, never a panic or a garbage map. `--nocapture` prints the table.

#[path = "common/cgal.rs"]
mod cgal;
#[path = "common/compiler.rs"]
mod compiler;

use cgal::{disk_meshes, read_plain_obj};
use uvflat::error::Error;
use uvflat::methods::circle_patterns::{circle_pattern_map, CirclePatternOptions};
use uvflat::metrics::distortion;
use uvflat::progress::Progress;
use uvflat::{natural_conformal_map, TriMesh};

/// Largest disk mesh tested; `UVFLAT_CIRCLE_MAX_FACES` raises it (the README's larger meshes).
fn max_faces() -> usize {
    std::env::var("UVFLAT_CIRCLE_MAX_FACES").ok().and_then(|v| v.parse().ok()).unwrap_or(10_000)
}

#[test]
fn circle_pattern_map_never_flips_and_keeps_every_circle_closed_on_the_disk_meshes() {
    let meshes = disk_meshes(max_faces()).expect("read ../shared/meshes");
    assert!(meshes.len() >= 8, "disk meshes missing");
    println!("| mesh | triangles | non-Delaunay edges | max |α − β| ° | angle steps | radius steps | closure | flipped | angle distortion ° (natural conformal) | s |");
    println!("|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|");
    let (mut successes, mut failures) = (0, 0);
    for disk in meshes {
        let (positions, triangles) = read_plain_obj(&disk.path).expect("read obj");
        let mesh = TriMesh::new(&positions, &triangles).expect("valid mesh");
        let start = std::time::Instant::now();
        let result = match circle_pattern_map(&mesh, &CirclePatternOptions::default(), &mut Progress::none()) {
            Ok(r) => r,
            Err(Error::Numerical(why)) => {
                println!("| {} | {} | numerical failure: {why} |", disk.name, disk.faces);
                failures += 1;
                continue;
            }
            Err(e) => panic!("{}: {e}", disk.name),
        };
        successes += 1;
        let seconds = start.elapsed().as_secs_f64();
        let r = result.report;
        let m = distortion(mesh.points(), mesh.triangles(), &result.uv, mesh.triangles()).expect("metrics");
        let natural = natural_conformal_map(&mesh, None).expect("natural conformal map");
        let n = distortion(mesh.points(), mesh.triangles(), &natural, mesh.triangles()).expect("metrics");
        println!(
            "| {} | {} | {} | {:.2} | {} | {} | {:.1e} | {} | {:.2} ({:.2}) | {:.2} |",
            disk.name,
            disk.faces,
            r.non_delaunay_edges,
            r.max_angle_change.to_degrees(),
            r.angle_iterations,
            r.radius_iterations,
            r.closure_error,
            m.flipped,
            m.angle_mean.to_degrees(),
            n.angle_mean.to_degrees(),
            seconds
        );
        assert!(r.closure_error < 1e-9, "{}: {r:?}", disk.name);
        assert_eq!(m.flipped, 0, "{}: flipped triangles", disk.name);
        assert_eq!(m.degenerate_uv, 0, "{}: degenerate uv triangles", disk.name);
        assert!(result.uv.iter().flatten().all(|x| x.is_finite()), "{}", disk.name);
    }
    println!("{successes} maps, {failures} numerical failures");
    assert!(successes >= 7, "{successes} maps, {failures} numerical failures");
}

#[test]
fn the_angle_program_centres_on_camelhead_despite_rounding_noise() {
    // disk_camelhead (23k faces, many slivers): the Newton decrement of the barrier problem
    // changes sign from step to step at ±4·10⁻³ at t = 10⁶ (rounding in t·(α − β)/β²); a
    // stopping floor that ignored this made the map fail with "no centred point".
    let path = std::path::Path::new(cgal::MESH_DIR).join("disk_camelhead.obj");
    let (positions, triangles) = read_plain_obj(&path).expect("read camelhead");
    let mesh = TriMesh::new(&positions, &triangles).expect("valid mesh");
    let result = circle_pattern_map(&mesh, &CirclePatternOptions::default(), &mut Progress::none())
        .unwrap_or_else(|e| panic!("camelhead: {e}"));
    let m = distortion(mesh.points(), mesh.triangles(), &result.uv, mesh.triangles()).expect("metrics");
    assert!(result.report.closure_error < 1e-9, "{:?}", result.report);
    assert_eq!((m.flipped, m.degenerate_uv), (0, 0));
}
