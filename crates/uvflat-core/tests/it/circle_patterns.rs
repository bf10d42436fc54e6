//! Circle-pattern conformal map (Kharevych, Springborn & Schröder 2006; partial implementation,
//! see docs/methods/circle_patterns.md) on the real disk meshes of `tests/data/meshes` up to 10k faces, with and
//! without the intrinsic Delaunay flips: every circle closes and the report's flip count is
//! the mesh's; with the flips (the paper's method) the map is as conformal as the natural
//! conformal map; without them the pattern is laid out on the mesh's own triangles, so none
//! is flipped; a failure is a numerical-failure status, never a panic or a garbage map.
//! `--nocapture` prints the tables.

use cgal::{disk_meshes, read_plain_obj};
use uvflat_core::error::Error;
use uvflat_core::methods::circle_patterns::{
    circle_pattern_cone_map, circle_pattern_map, polygon_boundary_curvature, CirclePatternOptions, ConeMapResult,
};
use uvflat_core::methods::cone_placement::{place_cones, ConePlacementOptions};
use uvflat_core::metrics::{distortion, Metrics};
use uvflat_core::progress::Progress;
use uvflat_core::{fixed_boundary_map, natural_conformal_map, FixedBoundaryOptions, TriMesh};
use uvflat_test_support::{cgal, meshes};

/// Largest disk mesh tested; `UVFLAT_CIRCLE_MAX_FACES` raises it (the larger meshes of docs/methods/circle_patterns.md).
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
    let meshes = disk_meshes(max_faces());
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
    let meshes = disk_meshes(max_faces());
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
    cgal::DiskMesh::named(name)
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
    let meshes = disk_meshes(max_faces());
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

#[test]
fn a_convex_boundary_embeds_the_map_with_less_distortion_than_a_mean_value_map() {
    // The paper's inequality constraints on the boundary angles (course notes §4.4): with every
    // boundary vertex's angle sum at most π, the uv boundary turns by at least 0 everywhere and by
    // 2π in all, so it is a convex polygon, and the pattern — a local immersion — embeds the
    // triangulation. Checked on every disk mesh whose pattern's radii span fewer than 12
    // decades: no vertex turns backwards, the boundary does not cross itself (the free map's
    // may), and the angle distortion lies between the free map's (to 0.01°) and that of
    // Floater's mean-value map onto a circle (convex too, bijective by Tutte–Floater, but with
    // the boundary fixed in advance). Where the boundary is a long winding strip (disk_maze,
    // disk_hilbert) or a cut ends in a vertex of angle 2π (disk_cow_cut), the conformal map onto
    // a convex domain shrinks parts of it by more than double precision can hold; the report
    // says so (radius span ≥ 12 decades), and those must be among the named ones.
    println!("| mesh | triangles | radius span (decades) free / convex | most negative turning | flipped | boundary crossings free / convex | angle distortion ° free / convex / mean value on a circle | s |");
    println!("|---|--:|--:|--:|--:|--:|--:|--:|");
    let meshes = disk_meshes(max_faces());
    assert!(meshes.len() >= 8, "disk meshes missing");
    let mut embedded = 0;
    for disk in &meshes {
        let (positions, triangles) = read_plain_obj(&disk.path).expect("read obj");
        let mesh = TriMesh::new(&positions, &triangles).expect("valid mesh");
        let lp = mesh.boundary_loops()[mesh.longest_boundary_loop().unwrap()].clone();
        let options = CirclePatternOptions { convex_boundary: true, ..Default::default() };
        let start = std::time::Instant::now();
        let convex =
            circle_pattern_map(&mesh, &options, &mut Progress::none()).unwrap_or_else(|e| panic!("{}: {e}", disk.name));
        let seconds = start.elapsed().as_secs_f64();
        let free = circle_pattern_map(&mesh, &CirclePatternOptions::default(), &mut Progress::none())
            .unwrap_or_else(|e| panic!("{}: {e}", disk.name));
        let mean_value = fixed_boundary_map(&mesh, &FixedBoundaryOptions::default()).expect("mean value map");
        let metrics =
            |uv: &[[f64; 2]]| distortion(mesh.points(), mesh.triangles(), uv, mesh.triangles()).expect("metrics");
        let (m, f) = (metrics(&convex.uv), metrics(&free.uv));
        let turning = uv_turning(&lp, &convex.uv);
        let most_negative = turning.iter().copied().fold(f64::INFINITY, f64::min);
        let (a_free, a_convex) = (f.angle_mean.to_degrees(), m.angle_mean.to_degrees());
        let a_mean_value = metrics(&mean_value).angle_mean.to_degrees();
        let span = convex.report.radius_span;
        println!(
            "| {} | {} | {:.1} / {:.1} | {:.1e} | {} | {} / {} | {:.2} / {:.2} / {:.2} | {:.2} |",
            disk.name,
            disk.faces,
            free.report.radius_span,
            span,
            most_negative,
            m.flipped,
            f.boundary_intersections,
            m.boundary_intersections,
            a_free,
            a_convex,
            a_mean_value,
            seconds
        );
        assert!(convex.report.closure_error < 1e-9, "{}: {:?}", disk.name, convex.report);
        if span >= 12.0 {
            assert!(
                ["disk_maze", "disk_hilbert", "disk_cow_cut"].contains(&disk.name.as_str()),
                "{}: span {span}",
                disk.name
            );
            continue;
        }
        embedded += 1;
        assert_eq!(convex.report.flipped_triangles as usize, m.flipped, "{}", disk.name);
        assert!(most_negative > -1e-9, "{}: a boundary vertex turns by {most_negative}", disk.name);
        let total = turning.iter().sum::<f64>();
        assert!((total - std::f64::consts::TAU).abs() < 1e-8, "{}: the boundary turns by {total}", disk.name);
        assert_eq!(m.boundary_intersections, 0, "{}", disk.name);
        assert!(m.flipped * 1000 <= disk.faces, "{}: {} flipped", disk.name, m.flipped);
        // The program minimizes the relative angle change, not this mean, so "at least the free
        // map's" holds only up to the two programs' different optima.
        assert!(a_convex >= a_free - 0.01, "{}: {a_convex} below the free map's {a_free}", disk.name);
        assert!(a_convex <= a_mean_value, "{}: {a_convex} above the mean-value map's {a_mean_value}", disk.name);
    }
    assert!(embedded + 3 >= meshes.len(), "{embedded} of {} meshes embedded", meshes.len());
}

/// `count` vertices spread over the mesh by farthest-point sampling (3D distance), from vertex 0.
fn spread_vertices(mesh: &TriMesh, count: usize) -> Vec<u32> {
    let p = mesh.points();
    let d = |a: u32, b: u32| {
        let (x, y) = (p[a as usize], p[b as usize]);
        ((x[0] - y[0]).powi(2) + (x[1] - y[1]).powi(2) + (x[2] - y[2]).powi(2)).sqrt()
    };
    let interior: Vec<u32> =
        (0..mesh.vertex_count() as u32).filter(|&v| mesh.is_referenced(v) && !mesh.is_boundary_vertex(v)).collect();
    let mut chosen = vec![interior[0]];
    while chosen.len() < count {
        let next = *interior
            .iter()
            .max_by(|&&a, &&b| {
                let da = chosen.iter().map(|&c| d(a, c)).fold(f64::INFINITY, f64::min);
                let db = chosen.iter().map(|&c| d(b, c)).fold(f64::INFINITY, f64::min);
                da.total_cmp(&db)
            })
            .unwrap();
        chosen.push(next);
    }
    chosen
}

/// Checks a cone map: circles closed, (almost) no flipped triangle, both sides of every seam edge
/// congruent (the same uv length), and the uv angles around each cone summing to its cone
/// angle 2π − κ. Returns the largest seam length mismatch and cone angle error.
fn check_cone_map(name: &str, mesh: &TriMesh, cones: &[(u32, f64)], result: &ConeMapResult) -> (f64, f64) {
    check_cone_map_flipping(name, mesh, cones, result, 1)
}

/// [`check_cone_map`] with at most `per_mille` flipped triangles per 1000.
fn check_cone_map_flipping(
    name: &str,
    mesh: &TriMesh,
    cones: &[(u32, f64)],
    result: &ConeMapResult,
    per_mille: usize,
) -> (f64, f64) {
    let r = result.report;
    assert!(r.closure_error < 1e-9, "{name}: {r:?}");
    // The input's triangles take the uv of the flipped triangulation's vertices (see the disk
    // tests): only a few may flip.
    assert!(r.flipped_triangles as usize * 1000 <= per_mille * mesh.triangle_count(), "{name}: {r:?}");
    let mut lengths: std::collections::HashMap<[u32; 2], Vec<f64>> = Default::default();
    let seams: std::collections::HashSet<[u32; 2]> = result.seams.iter().copied().collect();
    let mut cone_sum = vec![0.0; mesh.vertex_count()];
    for (tri, uv) in mesh.triangles().iter().zip(&result.corner_uv) {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            let key = [a.min(b), a.max(b)];
            let (p, q, o) = (uv[k], uv[(k + 1) % 3], uv[(k + 2) % 3]);
            if seams.contains(&key) {
                lengths.entry(key).or_default().push(((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt());
            }
            let (e1, e2) = ([q[0] - p[0], q[1] - p[1]], [o[0] - p[0], o[1] - p[1]]);
            cone_sum[a as usize] += (e1[0] * e2[1] - e1[1] * e2[0]).atan2(e1[0] * e2[0] + e1[1] * e2[1]);
        }
    }
    let seam_error = lengths.values().map(|l| (l[0] - l[1]).abs() / l[0].max(l[1])).fold(0.0, f64::max);
    assert_eq!(lengths.len(), result.seams.len(), "{name}");
    let cone_error =
        cones.iter().map(|&(v, k)| (cone_sum[v as usize] - (2.0 * std::f64::consts::PI - k)).abs()).fold(0.0, f64::max);
    (seam_error, cone_error)
}

#[test]
fn cone_maps_of_closed_meshes_have_congruent_seams_and_the_prescribed_cone_angles() {
    // Sphere-like meshes with 8 cones of π/2 (Gauss–Bonnet: 8 · π/2 = 4π, a cube's corners)
    // and the tori with none (Σ κ = 2π χ = 0): a flat metric with cones, cut open through them.
    // The properties checked are those of a cone metric laid out after cutting: both sides of
    // every seam have the same length, and the angles around each cone add up to its angle.
    use std::f64::consts::PI;
    println!("| mesh | triangles | cones | seam edges | seam length mismatch | cone angle error | flipped | angle distortion ° | s |");
    println!("|---|--:|--:|--:|--:|--:|--:|--:|--:|");
    // Also a disk with two cones (free boundary) and a genus-3 surface with four saddles of
    // −2π each (Σ κ = 2π χ = −8π; cone angle 4π).
    let cases = [
        ("closed_g0_spot", 8, PI / 2.0),
        ("closed_g0_bunny", 8, PI / 2.0),
        ("closed_g1_torus", 0, 0.0),
        ("closed_g1_knot", 0, 0.0),
        ("disk_mushroom", 2, PI / 2.0),
        ("closed_g3_triple_torus", 4, -2.0 * PI),
    ];
    for (name, cone_count, curvature) in cases {
        let path = meshes::unpacked(&format!("{name}.obj"));
        let (positions, triangles) = read_plain_obj(&path).expect("read mesh");
        let mesh = TriMesh::new(&positions, &triangles).expect("valid mesh");
        let cones: Vec<(u32, f64)> =
            spread_vertices(&mesh, cone_count.max(1)).into_iter().take(cone_count).map(|v| (v, curvature)).collect();
        let start = std::time::Instant::now();
        let result = circle_pattern_cone_map(&mesh, &cones, &CirclePatternOptions::default(), &mut Progress::none())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let seconds = start.elapsed().as_secs_f64();
        let (seam_error, cone_error) = check_cone_map(name, &mesh, &cones, &result);
        let m = corner_metrics(&mesh, &result);
        println!(
            "| {name} | {} | {} | {} | {:.1e} | {:.1e} | {} | {:.2} | {:.2} |",
            mesh.triangle_count(),
            cones.len(),
            result.seams.len(),
            seam_error,
            cone_error,
            result.report.flipped_triangles,
            m.angle_mean.to_degrees(),
            seconds
        );
        assert!(seam_error < 1e-9, "{name}: seam sides differ by {seam_error}");
        assert!(cone_error < 1e-8, "{name}: cone angles off by {cone_error}");
    }
}

/// Distortion of a per-corner cone map.
fn corner_metrics(mesh: &TriMesh, result: &ConeMapResult) -> Metrics {
    let uv: Vec<[f64; 2]> = result.corner_uv.iter().flatten().copied().collect();
    let corner_tris: Vec<[u32; 3]> = (0..mesh.triangle_count() as u32).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect();
    distortion(mesh.points(), mesh.triangles(), &uv, &corner_tris).expect("metrics")
}

#[test]
fn automatic_cones_flatten_closed_meshes_with_little_area_distortion() {
    // Greedy cone placement (Ben-Chen et al. 2008; `methods::cone_placement`) on every closed
    // mesh up to 25k triangles, then the circle-pattern cone map through those cones. Checked:
    // the curvatures sum to 2π χ; the placement stops at |u| ≤ 0.7 or at the 64-cone limit; the
    // map is a valid cone map (seams congruent, cone angles as placed); and on the genus-0
    // meshes, 8 greedy cones give less area distortion than 8 cube-corner cones (π/2 each) at
    // farthest-point-sampled vertices — the placement the cone test above uses.
    use std::f64::consts::PI;
    println!("| mesh | triangles | genus | cones | max log scale | radius span | area |log| mean / max | angle distortion ° | flipped | boundary crossings | s ; 8 cones: area |log| mean greedy / farthest |");
    println!("|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|");
    let mut tested = 0;
    for file in meshes::with_prefix(&["closed_"]) {
        let path = meshes::unpacked(&file);
        let (positions, triangles) = read_plain_obj(&path).expect("read mesh");
        let mesh = TriMesh::new(&positions, &triangles).expect("valid mesh");
        if mesh.triangle_count() > max_faces().max(25_000) {
            continue;
        }
        let name = file.trim_end_matches(".obj");
        let topology = mesh.topology();
        let start = std::time::Instant::now();
        // 64 cones, or 4 per unit of −χ on a higher genus (Gauss–Bonnet puts 2π χ on the cones;
        // a saddle cone of −2π carries one unit of −χ, and a vertex of 6 triangles no more).
        let max_cones = 64.max(4 * (-topology.euler_characteristic).max(0) as u32);
        let options = ConePlacementOptions { max_cones, ..Default::default() };
        let placement = place_cones(&mesh, &options, &mut Progress::none()).unwrap_or_else(|e| panic!("{name}: {e}"));
        let result =
            circle_pattern_cone_map(&mesh, &placement.cones, &CirclePatternOptions::default(), &mut Progress::none())
                .unwrap_or_else(|e| panic!("{name}: {e}"));
        let seconds = start.elapsed().as_secs_f64();
        // The needle-ridden cheese (43% needle triangles, genus 133, 576 cones) is mapped but not
        // held to the checks: 60 of its 17,786 triangles flip where the input's triangles take the
        // intrinsic triangulation's vertex uv, and its layout spans scales (area |log| up to 21)
        // at which the seams agree to 10⁻⁵ only.
        let strict = name != "closed_g133_cheese";
        let (seam_error, cone_error) =
            check_cone_map_flipping(name, &mesh, &placement.cones, &result, if strict { 1 } else { 4 });
        let m = corner_metrics(&mesh, &result);
        let total: f64 = placement.cones.iter().map(|c| c.1).sum();
        let mut comparison = String::new();
        if topology.genus == 0 {
            // (Where 8 cones cannot carry the curvature the placement says so: no comparison.)
            let greedy = ConePlacementOptions { max_cones: 8, max_log_scale: 0.0 };
            if let Ok(eight) = place_cones(&mesh, &greedy, &mut Progress::none()) {
                let farthest: Vec<(u32, f64)> = spread_vertices(&mesh, 8).into_iter().map(|v| (v, PI / 2.0)).collect();
                let run = |cones: &[(u32, f64)]| {
                    let r =
                        circle_pattern_cone_map(&mesh, cones, &CirclePatternOptions::default(), &mut Progress::none())
                            .unwrap_or_else(|e| panic!("{name}: {e}"));
                    corner_metrics(&mesh, &r).area_mean
                };
                let (a_greedy, a_farthest) = (run(&eight.cones), run(&farthest));
                comparison = format!("{a_greedy:.3} / {a_farthest:.3}");
                assert!(a_greedy < a_farthest, "{name}: 8 greedy cones {a_greedy} against farthest {a_farthest}");
            } else {
                comparison = "8 too few".into();
            }
        }
        println!(
            "| {name} | {} | {} | {} | {:.2} | {:.2} | {:.3} / {:.3} | {:.2} | {} | {} | {:.2} ; {comparison} |",
            mesh.triangle_count(),
            topology.genus,
            placement.cones.len(),
            placement.max_log_scale,
            result.report.radius_span,
            m.area_mean,
            m.area_max,
            m.angle_mean.to_degrees(),
            result.report.flipped_triangles,
            m.boundary_intersections,
            seconds
        );
        let chi = topology.euler_characteristic as f64;
        assert!((total - 2.0 * PI * chi).abs() < 1e-8, "{name}: Σ κ = {total}");
        assert!(placement.max_log_scale <= 0.7 || placement.cones.len() == max_cones as usize, "{name}: {placement:?}");
        // Seams: relative length difference, rounding of the layout over up to 64 cones' cuts.
        assert!(!strict || (seam_error < 1e-8 && cone_error < 1e-8), "{name}: seams {seam_error}, cones {cone_error}");
        tested += 1;
    }
    assert!(tested >= 10, "{tested} closed meshes");
}

#[test]
fn holes_are_filled_so_that_each_hole_turns_once_the_other_way() {
    // A planar layout of a domain with holes needs every hole's developing map to close up
    // (turning −2π, no translation), which nothing in the pattern's free-boundary program
    // enforces: the holes are filled by virtual cones for the layout. Checked: the outer loop's
    // uv turning is +2π and each hole's −2π, circles closed, (nearly) no flips, and the angle
    // distortion is at most the natural conformal map's + 0.5° (LSCM folds on several of these).
    println!("| mesh | triangles | loops | worst loop turning error | flipped | angle distortion ° (natural conformal; its flips) |");
    println!("|---|--:|--:|--:|--:|--:|");
    let mut tested = 0;
    for file in meshes::with_prefix(&["holes_"]) {
        let name = file.trim_end_matches(".obj").to_string();
        let (positions, triangles) = read_plain_obj(&meshes::unpacked(&file)).expect("read obj");
        let mesh = TriMesh::new(&positions, &triangles).expect("valid mesh");
        let topology = mesh.topology();
        if topology.genus != 0 || topology.components != 1 || mesh.triangle_count() > max_faces().max(20_000) {
            continue;
        }
        let result = circle_pattern_map(&mesh, &CirclePatternOptions::default(), &mut Progress::none())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let outer = mesh.longest_boundary_loop().unwrap();
        let worst = mesh
            .boundary_loops()
            .iter()
            .enumerate()
            .map(|(i, lp)| {
                let turns = uv_turning(lp, &result.uv).iter().sum::<f64>() / std::f64::consts::TAU;
                (turns - if i == outer { 1.0 } else { -1.0 }).abs()
            })
            .fold(0.0, f64::max);
        let m = distortion(mesh.points(), mesh.triangles(), &result.uv, mesh.triangles()).expect("metrics");
        let natural = natural_conformal_map(&mesh, None).expect("natural conformal map");
        let n = distortion(mesh.points(), mesh.triangles(), &natural, mesh.triangles()).expect("metrics");
        println!(
            "| {name} | {} | {} | {:.1e} | {} | {:.2} ({:.2}; {}) |",
            mesh.triangle_count(),
            topology.boundary_loops,
            worst,
            m.flipped,
            m.angle_mean.to_degrees(),
            n.angle_mean.to_degrees(),
            n.flipped
        );
        assert!(result.report.closure_error < 1e-9, "{name}: {:?}", result.report);
        assert!(worst < 1e-6, "{name}: a loop turns {worst} turns away from ±1");
        assert!(m.flipped * 100 <= mesh.triangle_count(), "{name}: {} flipped", m.flipped);
        assert!(m.angle_mean <= n.angle_mean + 0.5f64.to_radians(), "{name}");
        tested += 1;
    }
    assert!(tested >= 8, "{tested} meshes with holes");
}

#[test]
fn a_cone_curvature_that_is_not_finite_is_refused() {
    // An octahedron: the NaN would otherwise read as "no cone here" and the map would go on.
    let p = [1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -1.0];
    let t = [0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5];
    let mesh = TriMesh::new(&p, &t).unwrap();
    for bad in [f64::NAN, f64::INFINITY] {
        let cones = [(0, bad), (1, std::f64::consts::PI)];
        match circle_pattern_cone_map(&mesh, &cones, &CirclePatternOptions::default(), &mut Progress::none()) {
            Err(Error::InvalidArgument(m)) => assert!(m.contains("not finite"), "{m}"),
            Err(e) => panic!("{bad}: expected InvalidArgument, got {e}"),
            Ok(_) => panic!("{bad}: a non-finite cone was accepted"),
        }
    }
}
