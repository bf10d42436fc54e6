//! Circle-pattern conformal map (Kharevych, Springborn & Schröder 2006; partial implementation,
//! see the README) on the real disk meshes of `../shared/meshes` up to 10k faces, with and
//! without the intrinsic Delaunay flips: every circle closes and the report's flip count is
//! the mesh's; with the flips (the paper's method) the map is as conformal as the natural
//! conformal map; without them the pattern is laid out on the mesh's own triangles, so none
//! is flipped; a failure is a numerical-failure status, never a panic or a garbage map.
//! `--nocapture` prints the tables.

#[path = "common/cgal.rs"]
mod cgal;
#[path = "common/compiler.rs"]
mod compiler;

use cgal::{disk_meshes, read_plain_obj};
use uvflat::error::Error;
use uvflat::methods::circle_patterns::{circle_pattern_map, polygon_boundary_curvature, CirclePatternOptions};
use uvflat::metrics::distortion;
use uvflat::progress::Progress;
use uvflat::{natural_conformal_map, TriMesh};

/// Largest disk mesh tested; `UVFLAT_CIRCLE_MAX_FACES` raises it (the README's larger meshes).
fn max_faces() -> usize {
    std::env::var("UVFLAT_CIRCLE_MAX_FACES").ok().and_then(|v| v.parse().ok()).unwrap_or(10_000)
}

/// One row of the table: the map of one mesh with or without the intrinsic flips, checked.
struct Row {
    name: String,
    faces: usize,
    angle_distortion: f64,
    natural_distortion: f64,
    flipped: usize,
}

fn map_and_check(disk: &cgal::DiskMesh, intrinsic: bool) -> Option<Row> {
    let (positions, triangles) = read_plain_obj(&disk.path).expect("read obj");
    let mesh = TriMesh::new(&positions, &triangles).expect("valid mesh");
    let options = CirclePatternOptions { intrinsic_delaunay: intrinsic, ..Default::default() };
    let start = std::time::Instant::now();
    let result = match circle_pattern_map(&mesh, &options, &mut Progress::none()) {
        Ok(r) => r,
        Err(Error::Numerical(why)) => {
            println!("| {} | {} | numerical failure: {why} |", disk.name, disk.faces);
            return None;
        }
        Err(e) => panic!("{}: {e}", disk.name),
    };
    let seconds = start.elapsed().as_secs_f64();
    let r = result.report;
    let m = distortion(mesh.points(), mesh.triangles(), &result.uv, mesh.triangles()).expect("metrics");
    let natural = natural_conformal_map(&mesh, None).expect("natural conformal map");
    let n = distortion(mesh.points(), mesh.triangles(), &natural, mesh.triangles()).expect("metrics");
    println!(
        "| {} | {} | {} | {} | {:.2} | {} | {} | {:.1e} | {} | {:.2} ({:.2}) | {:.2} |",
        disk.name,
        disk.faces,
        r.intrinsic_flips,
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
    assert_eq!(r.flipped_triangles as usize, m.flipped, "{}: the report's flip count", disk.name);
    assert_eq!(m.degenerate_uv, 0, "{}: degenerate uv triangles", disk.name);
    assert!(result.uv.iter().flatten().all(|x| x.is_finite()), "{}", disk.name);
    if !intrinsic {
        assert_eq!(r.intrinsic_flips, 0, "{}", disk.name);
    }
    Some(Row {
        name: disk.name.clone(),
        faces: disk.faces,
        angle_distortion: m.angle_mean.to_degrees(),
        natural_distortion: n.angle_mean.to_degrees(),
        flipped: m.flipped,
    })
}

fn print_header(title: &str) {
    println!("{title}");
    println!("| mesh | triangles | intrinsic flips | non-Delaunay edges | max |α − β| ° | angle steps | radius steps | closure | flipped | angle distortion ° (natural conformal) | s |");
    println!("|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|");
}

#[test]
fn with_intrinsic_flips_the_map_is_as_conformal_as_the_natural_conformal_map() {
    // The paper's point (§4): on the intrinsic Delaunay triangulation the intersection angles
    // are the 3D ones, so the pattern is a discrete conformal map of the surface; its mean angle
    // distortion is then within 0.2° of the natural conformal map's (LSCM) or below it
    // (the Delaunay margin of the program, 0.01 rad, moves the angles of co-circular edges).
    let meshes = disk_meshes(max_faces()).expect("read ../shared/meshes");
    assert!(meshes.len() >= 8, "disk meshes missing");
    print_header("with intrinsic Delaunay flips (default)");
    let rows: Vec<Row> = meshes.iter().filter_map(|d| map_and_check(d, true)).collect();
    assert_eq!(rows.len(), meshes.len(), "every disk mesh maps");
    for row in &rows {
        assert!(
            row.angle_distortion <= row.natural_distortion + 0.2,
            "{}: angle distortion {:.3}° against the natural conformal map's {:.3}°",
            row.name,
            row.angle_distortion,
            row.natural_distortion
        );
        // The mesh's own triangles take their vertices' uv from the flipped triangulation.
        assert!(row.flipped * 1000 <= row.faces, "{}: {} flipped triangles", row.name, row.flipped);
    }
}

#[test]
fn without_intrinsic_flips_the_map_never_flips() {
    let meshes = disk_meshes(max_faces()).expect("read ../shared/meshes");
    assert!(meshes.len() >= 8, "disk meshes missing");
    print_header("without intrinsic flips (Delaunay condition on the mesh's edges)");
    let rows: Vec<Row> = meshes.iter().filter_map(|d| map_and_check(d, false)).collect();
    println!("{} maps, {} numerical failures", rows.len(), meshes.len() - rows.len());
    assert!(rows.len() >= 7, "{} maps of {}", rows.len(), meshes.len());
    for row in &rows {
        assert_eq!(row.flipped, 0, "{}: flipped triangles", row.name);
    }
}

#[test]
fn the_angle_program_centres_on_camelhead_despite_rounding_noise() {
    // disk_camelhead (23k faces, many slivers) without the flips: the Newton decrement of the
    // barrier problem changes sign from step to step at ±4·10⁻³ at t = 10⁶ (rounding in
    // t·(α − β)/β²); a stopping floor that ignored this made the map fail with "no centred point".
    let disk = named_disk("disk_camelhead");
    let row = map_and_check(&disk, false).expect("camelhead maps");
    assert_eq!(row.flipped, 0);
}

#[test]
fn mannequin_devil_maps_on_its_intrinsic_delaunay_triangulation() {
    // Without the flips the program's Delaunay condition moves angles by up to 180° on this
    // mesh and the radius Hessian loses positive definiteness (a numerical-failure status);
    // on the intrinsic Delaunay triangulation the circles close.
    let disk = named_disk("disk_mannequin_devil");
    let row = map_and_check(&disk, true).expect("mannequin_devil maps with the flips");
    assert!(row.angle_distortion <= row.natural_distortion + 0.2, "{:.3}°", row.angle_distortion);
    assert!(row.flipped * 1000 <= row.faces, "{} flipped", row.flipped);
}

fn named_disk(name: &str) -> cgal::DiskMesh {
    let path = std::path::Path::new(cgal::MESH_DIR).join(format!("{name}.obj"));
    let faces = cgal::count_faces(&path).expect("read mesh");
    cgal::DiskMesh { name: name.into(), path, faces }
}

/// Turning angle of the uv boundary polygon at each vertex of `lp` (counter-clockwise loop).
fn uv_turning(lp: &[u32], uv: &[[f64; 2]]) -> Vec<f64> {
    let n = lp.len();
    (0..n)
        .map(|i| {
            let [a, v, b] = [lp[(i + n - 1) % n], lp[i], lp[(i + 1) % n]].map(|x| uv[x as usize]);
            let (d1, d2) = ([v[0] - a[0], v[1] - a[1]], [b[0] - v[0], b[1] - v[1]]);
            (d1[0] * d2[1] - d1[1] * d2[0]).atan2(d1[0] * d2[0] + d1[1] * d2[1])
        })
        .collect()
}

#[test]
fn four_corners_make_a_rectangle_with_straight_sides() {
    // Paper §5: prescribing the boundary curvature (turning π/2 at four corners spread along
    // the boundary, 0 elsewhere) maps the disk onto a rectangle: the uv boundary turns by
    // exactly the prescribed angles at every boundary vertex.
    println!("| mesh | triangles | corners | max turning error | flipped | angle distortion ° (free boundary) | s |");
    println!("|---|--:|--:|--:|--:|--:|--:|");
    let meshes = disk_meshes(max_faces()).expect("read ../shared/meshes");
    let mut mapped = 0;
    for disk in &meshes {
        let (positions, triangles) = read_plain_obj(&disk.path).expect("read obj");
        let mesh = TriMesh::new(&positions, &triangles).expect("valid mesh");
        let lp = mesh.boundary_loops()[mesh.longest_boundary_loop().unwrap()].clone();
        let corners: Vec<u32> = (0..4).map(|k| lp[k * lp.len() / 4]).collect();
        let curvature = match polygon_boundary_curvature(&mesh, &corners) {
            Ok(c) => c,
            Err(Error::InvalidArgument(why)) if why.contains("single triangle") => {
                println!("| {} | {} | refused: {why} |", disk.name, disk.faces);
                continue;
            }
            Err(e) => panic!("{}: {e}", disk.name),
        };
        let options = CirclePatternOptions { boundary_curvature: Some(curvature.clone()), ..Default::default() };
        let start = std::time::Instant::now();
        let result = match circle_pattern_map(&mesh, &options, &mut Progress::none()) {
            Ok(r) => r,
            Err(e @ (Error::InvalidArgument(_) | Error::Numerical(_))) => {
                println!("| {} | {} | refused: {e} |", disk.name, disk.faces);
                continue;
            }
            Err(e) => panic!("{}: {e}", disk.name),
        };
        let seconds = start.elapsed().as_secs_f64();
        mapped += 1;
        let turning = uv_turning(&lp, &result.uv);
        let worst = lp.iter().zip(&turning).map(|(v, t)| (t - curvature[*v as usize]).abs()).fold(0.0, f64::max);
        let m = distortion(mesh.points(), mesh.triangles(), &result.uv, mesh.triangles()).expect("metrics");
        let free =
            circle_pattern_map(&mesh, &CirclePatternOptions::default(), &mut Progress::none()).expect("free map");
        let f = distortion(mesh.points(), mesh.triangles(), &free.uv, mesh.triangles()).expect("metrics");
        println!(
            "| {} | {} | {} | {:.1e} | {} | {:.2} ({:.2}) | {:.2} |",
            disk.name,
            disk.faces,
            corners.len(),
            worst,
            m.flipped,
            m.angle_mean.to_degrees(),
            f.angle_mean.to_degrees(),
            seconds
        );
        assert!(worst < 1e-8, "{}: boundary turns {worst} away from the prescription", disk.name);
        assert_eq!(result.report.flipped_triangles as usize, m.flipped, "{}", disk.name);
        assert!(m.flipped * 1000 <= disk.faces, "{}: {} flipped", disk.name, m.flipped);
    }
    assert!(mapped >= 5, "{mapped} of {} meshes mapped onto a rectangle", meshes.len());
}
