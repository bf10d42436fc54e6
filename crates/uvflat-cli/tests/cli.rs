//! The `uvflat` command line as a user runs it: unwrap an OBJ into an OBJ with UVs and an SVG,
//! measure it, list methods, report topology; bad meshes and bad options give a message and a
//! non-zero exit, never a panic.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const SAMPLE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/nefertiti.obj");
const MESHES: &str = uvflat_test_support::meshes::DIR;

fn uvflat(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_uvflat")).args(args).output().expect("run uvflat")
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("uvflat-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir.join(name)
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn json(o: &Output) -> serde_json::Value {
    assert!(o.status.success(), "uvflat failed: {}", stderr(o));
    serde_json::from_str(stdout(o).trim()).unwrap_or_else(|e| panic!("not JSON ({e}): {}", stdout(o)))
}

fn count_lines(path: &Path, prefix: &str) -> usize {
    std::fs::read_to_string(path).expect("read output").lines().filter(|l| l.starts_with(prefix)).count()
}

#[test]
fn unwrap_writes_obj_with_one_uv_per_vertex_and_an_svg() {
    let (out, svg) = (scratch("n.obj"), scratch("n.svg"));
    let o = uvflat(&[
        "unwrap",
        SAMPLE,
        "-o",
        out.to_str().unwrap(),
        "--method",
        "natural-conformal",
        "--svg",
        svg.to_str().unwrap(),
        "--json",
    ]);
    let report = json(&o);
    assert_eq!(report["method"], "natural-conformal");
    assert_eq!(report["flipped"], 0);
    assert!(report["seconds"].as_f64().is_some_and(|s| s >= 0.0));
    assert!(report["conformal_mean"].as_f64().is_some_and(|c| (1.0..1.2).contains(&c)), "{report}");
    assert_eq!(count_lines(&out, "v "), 299);
    assert_eq!(count_lines(&out, "vt "), 299);
    assert_eq!(count_lines(&out, "f "), 562);
    let text = std::fs::read_to_string(&out).unwrap();
    let face = text.lines().find(|l| l.starts_with("f ")).unwrap();
    assert!(face.split_whitespace().skip(1).all(|c| c.split_once('/').is_some_and(|(a, b)| a == b)), "{face}");
    let picture = std::fs::read_to_string(&svg).expect("svg written");
    assert!(picture.starts_with("<svg") || picture.starts_with("<?xml"), "not an SVG");

    // `metrics` on the written file reproduces what `unwrap --json` reported.
    let measured = json(&uvflat(&["metrics", out.to_str().unwrap(), "--json"]));
    for key in ["flipped", "triangles", "boundary_intersections"] {
        assert_eq!(measured[key], report[key], "{key}");
    }
    for key in ["stretch_l2", "conformal_mean", "angle_mean", "area_mean"] {
        let (a, b) = (measured[key].as_f64().unwrap(), report[key].as_f64().unwrap());
        assert!((a - b).abs() <= 1e-9 * b.abs().max(1.0), "{key}: {a} vs {b}");
    }
}

#[test]
fn every_listed_method_unwraps_the_sample() {
    let o = uvflat(&["methods"]);
    assert!(o.status.success());
    let names: Vec<String> =
        stdout(&o).lines().filter_map(|l| l.split_whitespace().next().map(str::to_string)).collect();
    assert!(names.len() >= 7, "{names:?}");
    for name in names {
        let out = scratch(&format!("{name}.obj"));
        let report = json(&uvflat(&["unwrap", SAMPLE, "-o", out.to_str().unwrap(), "--method", &name, "--json"]));
        assert_eq!(report["method"], name.as_str());
        assert_eq!(report["triangles"], 562, "{name}");
        if ["tutte", "floater", "mean-value", "slim", "arap", "mips", "stretch", "green-lagrange", "degener"]
            .contains(&name.as_str())
        {
            assert_eq!(report["flipped"], 0, "{name} flipped a triangle with a convex boundary");
        }
    }
}

#[test]
fn fixed_boundary_options_change_the_result() {
    let square = json(&uvflat(&[
        "unwrap",
        SAMPLE,
        "-o",
        scratch("sq.obj").to_str().unwrap(),
        "--method",
        "mean-value",
        "--boundary",
        "square",
        "--distribution",
        "uniform",
        "--json",
    ]));
    let circle = json(&uvflat(&[
        "unwrap",
        SAMPLE,
        "-o",
        scratch("ci.obj").to_str().unwrap(),
        "--method",
        "mean-value",
        "--json",
    ]));
    assert_ne!(square["stretch_l2"], circle["stretch_l2"]);
    let intrinsic = json(&uvflat(&[
        "unwrap",
        SAMPLE,
        "-o",
        scratch("in.obj").to_str().unwrap(),
        "--method",
        "intrinsic",
        "--lambda",
        "0.5",
        "--mu",
        "0.5",
        "--json",
    ]));
    assert_eq!(intrinsic["method"], "intrinsic");
}

#[test]
fn boundary_file_fixes_the_given_vertices() {
    // Take the boundary of a square unwrap and feed it back as a FILE: same result.
    let first = scratch("first.obj");
    json(&uvflat(&[
        "unwrap",
        SAMPLE,
        "-o",
        first.to_str().unwrap(),
        "--method",
        "conformal",
        "--boundary",
        "square",
        "--json",
    ]));
    let mesh = uvflat_core::io::obj::read_obj(&first).unwrap();
    let tris: Vec<[u32; 3]> = mesh.triangles.chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
    let mut edges = std::collections::HashMap::new();
    for t in &tris {
        for k in 0..3 {
            let (a, b) = (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]));
            *edges.entry((a, b)).or_insert(0) += 1;
        }
    }
    let mut boundary: Vec<u32> = edges.iter().filter(|(_, &n)| n == 1).flat_map(|(&(a, b), _)| [a, b]).collect();
    boundary.sort_unstable();
    boundary.dedup();
    let file = scratch("boundary.txt");
    let lines: String = boundary
        .iter()
        .map(|&v| format!("{v} {} {}\n", mesh.uv[2 * v as usize], mesh.uv[2 * v as usize + 1]))
        .collect();
    std::fs::write(&file, format!("# vertex u v\n{lines}")).unwrap();
    let second = scratch("second.obj");
    json(&uvflat(&[
        "unwrap",
        SAMPLE,
        "-o",
        second.to_str().unwrap(),
        "--method",
        "conformal",
        "--boundary",
        file.to_str().unwrap(),
        "--json",
    ]));
    let again = uvflat_core::io::obj::read_obj(&second).unwrap();
    let worst = mesh.uv.iter().zip(&again.uv).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    assert!(worst < 1e-12, "given boundary changed the map by {worst}");
}

#[test]
fn pins_are_placed_where_documented() {
    let out = scratch("pinned.obj");
    let out_s = out.to_str().unwrap();
    json(&uvflat(&[
        "unwrap",
        SAMPLE,
        "-o",
        out_s,
        "--method",
        "natural-conformal",
        "--pin",
        "3",
        "--pin",
        "17",
        "--json",
    ]));
    let mesh = uvflat_core::io::obj::read_obj(&out).unwrap();
    assert_eq!([mesh.uv[6], mesh.uv[7]], [0.0, 0.0]);
    assert_eq!(mesh.uv[35], 0.0);
    assert!(mesh.uv[34] > 0.0);
}

#[test]
fn info_reports_topology() {
    let t = json(&uvflat(&["info", &format!("{MESHES}/holes_lion.obj.gz"), "--json"]));
    assert_eq!((t["vertices"].as_u64(), t["faces"].as_u64()), (Some(7529), Some(14859)));
    assert_eq!(
        (t["components"].as_u64(), t["boundary_loops"].as_u64(), t["genus"].as_u64()),
        (Some(1), Some(5), Some(0))
    );
    let text = stdout(&uvflat(&["info", SAMPLE]));
    assert!(text.contains("boundary loops  1") && text.contains("genus           0"), "{text}");
}

#[test]
fn bad_meshes_print_the_library_message_and_exit_1() {
    let cases = [
        ("bad_nan_coordinate.obj", "non-finite"),
        ("bad_duplicate_faces.obj", "same three vertices"),
        ("bad_nonmanifold_edge.obj", "non-manifold"),
        ("bad_nonmanifold_vertex.obj", "separate fans"),
        ("bad_inconsistent_orientation.obj", "inconsistently oriented"),
        ("bad_empty_no_faces.obj", "no triangles"),
    ];
    for (file, expected) in cases {
        let o = uvflat(&["unwrap", &format!("{MESHES}/{file}.gz"), "-o", scratch("bad.obj").to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(1), "{file}: {}", stderr(&o));
        assert!(stderr(&o).contains(expected), "{file}: {}", stderr(&o));
        assert!(!stderr(&o).contains("panicked"), "{file}");
    }
    let o = uvflat(&["unwrap", "/nonexistent/mesh.obj", "-o", scratch("x.obj").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("/nonexistent/mesh.obj"), "{}", stderr(&o));
}

/// `bad_degenerate_faces.obj` (a face with a repeated corner, zero-area faces): the default
/// unwrap welds and leaves them out and says so; a named method still refuses the mesh.
#[test]
fn the_default_unwrap_leaves_zero_area_faces_out_and_a_named_method_refuses_them() {
    let input = format!("{MESHES}/bad_degenerate_faces.obj.gz");
    let out = scratch("degenerate.obj");
    let report = json(&uvflat(&["unwrap", &input, "-o", out.to_str().unwrap(), "--json"]));
    let left_out = report["left_out_triangles"].as_u64().unwrap();
    assert!(left_out >= 1, "{report}");
    assert_eq!(report["flipped"].as_u64(), Some(0), "{report}");
    assert_eq!(report["overlaps"].as_u64(), Some(0), "{report}");
    // The only zero-area UV triangles are the left-out ones (a welded corner pair shares a UV).
    assert!(report["degenerate_uv"].as_u64().unwrap() <= left_out, "{report}");
    assert_eq!(report["triangles"].as_u64(), Some(131), "every input face written");
    let text = uvflat(&["unwrap", &input, "-o", out.to_str().unwrap()]);
    assert!(stdout(&text).contains("left out of the solve"), "{}", stdout(&text));
    let named = uvflat(&["unwrap", &input, "-o", out.to_str().unwrap(), "--method", "natural-conformal"]);
    assert_eq!(named.status.code(), Some(1));
    assert!(stderr(&named).contains("more than once"), "{}", stderr(&named));
}

#[test]
fn circle_patterns_flip_to_intrinsic_delaunay_unless_told_not_to() {
    let out = scratch("cp.obj");
    let run = |extra: &[&str]| {
        let mut args = vec!["unwrap", SAMPLE, "-o", out.to_str().unwrap(), "--method", "circle-patterns", "--json"];
        args.extend_from_slice(extra);
        json(&uvflat(&args))
    };
    let flipped = run(&[]);
    let plain = run(&["--no-intrinsic-delaunay"]);
    assert!(flipped["intrinsic_flips"].as_u64().is_some_and(|n| n > 0), "{flipped}");
    assert_eq!(flipped["flipped"], flipped["flipped_triangles"], "{flipped}");
    assert_eq!(plain["intrinsic_flips"], 0, "{plain}");
    assert_eq!(plain["flipped"], 0, "{plain}");
    // On the intrinsic Delaunay triangulation the 3D angles need not be moved to meet the
    // Delaunay condition, so the planar angles stay closer to them.
    let change = |r: &serde_json::Value| r["max_angle_change"].as_f64().unwrap();
    assert!(change(&flipped) < change(&plain), "{flipped} {plain}");

    // `--corner` four times: the written uv boundary is a rectangle (straight between corners).
    let obj = uvflat_core::io::obj::read_obj(Path::new(SAMPLE)).unwrap();
    let mesh = uvflat_core::TriMesh::new(&obj.positions, &obj.triangles).unwrap();
    let lp = mesh.boundary_loops()[mesh.longest_boundary_loop().unwrap()].clone();
    let corners: Vec<String> = (0..4).map(|k| lp[k * lp.len() / 4].to_string()).collect();
    let mut args: Vec<&str> = Vec::new();
    for c in &corners {
        args.extend(["--corner", c.as_str()]);
    }
    let rectangle = run(&args);
    assert_eq!(rectangle["method"], "circle-patterns", "{rectangle}");
    let written = uvflat_core::io::obj::read_obj(&out).unwrap();
    let uv = |v: u32| [written.uv[2 * v as usize], written.uv[2 * v as usize + 1]];
    let (a, b, c) = (uv(lp[0]), uv(lp[1]), uv(lp[lp.len() / 4]));
    let cross = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    let side = ((c[0] - a[0]).powi(2) + (c[1] - a[1]).powi(2)).sqrt();
    // OBJ text keeps about 9 significant digits.
    assert!(cross.abs() < 1e-6 * side * side, "vertex {} is off the side: {cross}", lp[1]);
    // `--convex-boundary`: the written uv boundary turns left or goes straight at every vertex.
    let convex = run(&["--convex-boundary"]);
    assert_eq!(convex["boundary_intersections"], 0, "{convex}");
    assert!(convex["radius_span"].as_f64().is_some_and(|s| s > 0.0 && s < 12.0), "{convex}");
    let written = uvflat_core::io::obj::read_obj(&out).unwrap();
    let uv = |v: u32| [written.uv[2 * v as usize], written.uv[2 * v as usize + 1]];
    for i in 0..lp.len() {
        let [a, b, c] = [lp[i], lp[(i + 1) % lp.len()], lp[(i + 2) % lp.len()]].map(uv);
        let cross = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
        let scale = (b[0] - a[0]).hypot(b[1] - a[1]) * (c[0] - b[0]).hypot(c[1] - b[1]);
        assert!(cross > -1e-6 * scale, "the boundary turns right at vertex {}: {cross}", lp[(i + 1) % lp.len()]);
    }
    let interior = (0..mesh.vertex_count() as u32).find(|&v| !mesh.is_boundary_vertex(v)).unwrap().to_string();
    let mut bad = vec!["unwrap", SAMPLE, "-o", out.to_str().unwrap(), "--method", "circle-patterns"];
    bad.extend(["--corner", &corners[0], "--corner", &corners[1], "--corner", &interior]);
    let o = uvflat(&bad);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("not a vertex of the longest boundary loop"), "{}", stderr(&o));
}

#[test]
fn circle_patterns_with_cones_write_per_corner_uvs() {
    // A torus needs no cone (χ = 0): a zero-curvature cone only asks for the cone map.
    let torus = format!("{MESHES}/closed_g1_torus.obj.gz");
    let out = scratch("torus_cones.obj");
    let o = uvflat(&[
        "unwrap",
        &torus,
        "-o",
        out.to_str().unwrap(),
        "--method",
        "circle-patterns",
        "--cone",
        "0:0",
        "--json",
    ]);
    let report = json(&o);
    assert_eq!(report["flipped"], 0, "{report}");
    assert!(report["seam_edges"].as_u64().is_some_and(|n| n > 0), "{report}");
    assert!(report["closure_error"].as_f64().is_some_and(|c| c < 1e-9), "{report}");
    let triangles = count_lines(&out, "f ");
    assert_eq!(count_lines(&out, "vt "), 3 * triangles);
    // A sphere with one cone breaks Gauss–Bonnet: an input error, not a crash.
    let o = uvflat(&[
        "unwrap",
        &format!("{MESHES}/closed_g0_bunny.obj.gz"),
        "-o",
        out.to_str().unwrap(),
        "--method",
        "circle-patterns",
        "--cone",
        "0:90",
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("Gauss"), "{}", stderr(&o));
    // `--auto-cones`: placed where the flattening's scale is largest, reported in the JSON.
    let bunny = format!("{MESHES}/closed_g0_bunny.obj.gz");
    let o = uvflat(&[
        "unwrap",
        &bunny,
        "-o",
        out.to_str().unwrap(),
        "--method",
        "circle-patterns",
        "--auto-cones",
        "--json",
    ]);
    let report = json(&o);
    let cones = report["cone_vertices"].as_array().map(|a| a.len()).unwrap_or(0);
    assert!(cones > 0 && report["cones"] == cones, "{report}");
    assert!(report["max_log_scale"].as_f64().is_some_and(|s| s <= 0.7), "{report}");
    let total: f64 = report["cone_curvatures"].as_array().unwrap().iter().map(|k| k.as_f64().unwrap()).sum();
    assert!((total - 4.0 * std::f64::consts::PI).abs() < 1e-8, "{report}");
    for bad in [
        vec!["--cone", "zero:90"],
        vec!["--cone", "0:90", "--cut", "auto"],
        vec!["--cone", "0:0", "--auto-cones"],
        vec!["--max-cones", "4"],
    ] {
        let mut args = vec!["unwrap", torus.as_str(), "-o", out.to_str().unwrap(), "--method", "circle-patterns"];
        args.extend(bad);
        assert_eq!(uvflat(&args).status.code(), Some(2), "{args:?}");
    }
}

#[test]
fn options_that_do_not_apply_are_usage_errors() {
    let out = scratch("u.obj");
    let out = out.to_str().unwrap();
    for args in [
        vec!["unwrap", SAMPLE, "-o", out, "--boundary", "square"],
        vec!["unwrap", SAMPLE, "-o", out, "--method", "tutte", "--pin", "1", "--pin", "2"],
        vec!["unwrap", SAMPLE, "-o", out, "--pin", "1"],
        vec!["unwrap", SAMPLE, "-o", out, "--method", "tutte", "--lambda", "2"],
        vec!["unwrap", SAMPLE, "-o", out, "--method", "nonsense"],
        vec!["unwrap", SAMPLE, "-o", out, "--method", "abf", "--no-intrinsic-delaunay"],
        vec!["unwrap", SAMPLE, "-o", out, "--corner", "1", "--corner", "2", "--corner", "3"],
        vec!["unwrap", SAMPLE, "-o", out, "--method", "natural-conformal", "--convex-boundary"],
    ] {
        let o = uvflat(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
    }
    let o = uvflat(&["unwrap", SAMPLE, "-o", out, "--method", "natural-conformal", "--pin", "1", "--pin", "100000"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("100000"), "{}", stderr(&o));
    let o = uvflat(&["metrics", SAMPLE]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("no texture coordinates"), "{}", stderr(&o));
}

#[test]
fn unwrap_cuts_closed_meshes_and_writes_per_corner_uvs() {
    let out = scratch("torus.obj");
    let input = format!("{MESHES}/closed_g1_torus.obj.gz");
    let report = json(&uvflat(&["unwrap", &input, "-o", out.to_str().unwrap(), "--method", "mean-value", "--json"]));
    assert_eq!(report["flipped"], 0, "{report}");
    assert!(report["cut_edges"].as_u64().is_some_and(|e| e > 0), "{report}");
    assert!(report["seam_ratio"].as_f64().is_some_and(|r| r > 0.0 && r < 0.1), "{report}");
    let uv_vertices = report["uv_vertices"].as_u64().unwrap() as usize;
    assert_eq!(count_lines(&out, "v "), 2304);
    assert_eq!(count_lines(&out, "vt "), uv_vertices);
    assert!(uv_vertices > 2304, "seam vertices are duplicated in the uv set");
    let measured = json(&uvflat(&["metrics", out.to_str().unwrap(), "--json"]));
    assert_eq!(measured["flipped"], 0);
    // Without a cut the disk methods refuse the torus.
    let o = uvflat(&["unwrap", &input, "-o", out.to_str().unwrap(), "--cut", "none"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    // Atlas mode: charts under the stretch bound, packed into the unit square, no flips.
    let report = json(&uvflat(&[
        "unwrap",
        &input,
        "-o",
        out.to_str().unwrap(),
        "--atlas",
        "--max-stretch",
        "1.05",
        "--margin",
        "0.01",
        "--json",
    ]));
    assert_eq!(report["flipped"], 0, "{report}");
    assert_eq!(report["boundary_intersections"], 0, "{report}");
    assert!(report["charts"].as_u64().is_some_and(|c| c >= 1), "{report}");
    assert!(report["stretch_l2"].as_f64().is_some_and(|s| s <= 1.05), "{report}");
    assert!(report["utilization"].as_f64().is_some_and(|u| u > 0.1 && u < 1.0), "{report}");
    let measured = json(&uvflat(&["metrics", out.to_str().unwrap(), "--json"]));
    assert_eq!(measured["flipped"], 0);
    let o = uvflat(&["unwrap", &input, "-o", out.to_str().unwrap(), "--atlas", "--max-stretch", "0.5"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("max_stretch"), "{}", stderr(&o));
    let o = uvflat(&["unwrap", &input, "-o", out.to_str().unwrap(), "--atlas", "--method", "tutte"]);
    assert_eq!(o.status.code(), Some(2));
    // The default method on a cut mesh is flip-free (split into charts only when needed).
    let report =
        json(&uvflat(&["unwrap", &format!("{MESHES}/closed_g0_cow.obj.gz"), "-o", out.to_str().unwrap(), "--json"]));
    assert_eq!(report["flipped"], 0, "{report}");
    assert_eq!(report["mode"], "unwrap", "{report}");
}

#[test]
fn the_default_unwrap_is_verified_and_a_folding_method_is_warned_about() {
    let out = scratch("peaks.obj");
    let input = format!("{MESHES}/disk_three_peaks.obj.gz");
    // The natural conformal map flips 30 triangles here: the default repairs the island.
    let report = json(&uvflat(&["unwrap", &input, "-o", out.to_str().unwrap(), "--json"]));
    assert_eq!((report["method"].as_str(), report["mode"].as_str()), (Some("default"), Some("unwrap")), "{report}");
    assert_eq!((report["flipped"].as_u64(), report["overlaps"].as_u64()), (Some(0), Some(0)), "{report}");
    assert_eq!((report["islands"].as_u64(), report["repaired_islands"].as_u64()), (Some(1), Some(1)), "{report}");
    assert!(report["max_island_stretch"].as_f64().is_some_and(|s| s <= 1.5), "{report}");
    let measured = json(&uvflat(&["metrics", out.to_str().unwrap(), "--json"]));
    assert_eq!((measured["flipped"].as_u64(), measured["boundary_intersections"].as_u64()), (Some(0), Some(0)));
    // Named, the method's own result is kept, and stderr says what is wrong with it.
    let o = uvflat(&["unwrap", &input, "-o", out.to_str().unwrap(), "--method", "natural-conformal", "--json"]);
    let raw = json(&o);
    assert_eq!(raw["flipped"], 30, "{raw}");
    assert!(stderr(&o).contains("warning: the natural-conformal layout has 30 flipped"), "{}", stderr(&o));
    // Without a stretch bound the island is never split.
    let o = uvflat(&[
        "unwrap",
        &format!("{MESHES}/closed_g0_cow.obj.gz"),
        "-o",
        out.to_str().unwrap(),
        "--max-stretch",
        "inf",
        "--json",
    ]);
    let free = json(&o);
    assert_eq!(
        (free["islands"].as_u64(), free["flipped"].as_u64(), free["overlaps"].as_u64()),
        (Some(1), Some(0), Some(0))
    );
    // Options of the default unwrap are refused where they do not apply.
    for args in [
        vec!["unwrap", input.as_str(), "-o", out.to_str().unwrap(), "--method", "tutte", "--max-stretch", "2"],
        vec!["unwrap", input.as_str(), "-o", out.to_str().unwrap(), "--polish", "3"],
        vec!["unwrap", input.as_str(), "-o", out.to_str().unwrap(), "--method", "tutte", "--bijective"],
    ] {
        assert_eq!(uvflat(&args).status.code(), Some(2), "{args:?}");
    }
}

#[test]
fn sphere_writes_unit_sphere_vertices_without_flips() {
    let out = scratch("bunny_sphere.obj");
    let input = format!("{MESHES}/closed_g0_bunny.obj.gz");
    let report = json(&uvflat(&["sphere", &input, "-o", out.to_str().unwrap(), "--json"]));
    assert_eq!(report["flipped"], 0, "{report}");
    assert_eq!(report["method"], "tutte-gnomonic");
    let text = std::fs::read_to_string(&out).unwrap();
    let radii: Vec<f64> = text
        .lines()
        .filter(|l| l.starts_with("v "))
        .map(|l| l.split_whitespace().skip(1).map(|x| x.parse::<f64>().unwrap().powi(2)).sum::<f64>().sqrt())
        .collect();
    assert_eq!(radii.len(), 3301);
    assert!(radii.iter().all(|r| (r - 1.0).abs() < 1e-9));
    // The conformal circle-pattern map: no flip on the bunny either.
    let report =
        json(&uvflat(&["sphere", &input, "-o", out.to_str().unwrap(), "--method", "circle-patterns", "--json"]));
    assert_eq!((report["flipped"].as_u64(), report["method"].as_str()), (Some(0), Some("circle-patterns")), "{report}");
    let o = uvflat(&["sphere", &format!("{MESHES}/closed_g1_torus.obj.gz"), "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("genus"), "{}", stderr(&o));
}

/// `uvflat methods | head -0`: stdout closed before anything is written. The tool must exit
/// like a C tool on SIGPIPE (status 141), without a panic message. The read end is dropped
/// right after the spawn, so on a loaded machine the child may already have written its few
/// lines into the pipe's buffer and exit 0, which is also right; the test tries until a run
/// meets the closed pipe (a clean CI run once saw the race).
#[test]
fn a_closed_stdout_is_not_a_panic() {
    use std::process::Stdio;
    let mut statuses = Vec::new();
    for _ in 0..20 {
        let mut child = Command::new(env!("CARGO_BIN_EXE_uvflat"))
            .arg("methods")
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("run uvflat");
        drop(child.stdout.take());
        let output = child.wait_with_output().expect("wait for uvflat");
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(!stderr.contains("panicked"), "{stderr}");
        let code = output.status.code();
        assert!(matches!(code, Some(0) | Some(141)), "status {code:?}: {stderr}");
        statuses.push(code);
        if code == Some(141) {
            return;
        }
    }
    panic!("the closed pipe was never met in 20 runs: {statuses:?}");
}

#[test]
fn pgp_writes_per_corner_phases_a_quad_mesh_and_its_figures() {
    let (out, quads) = (scratch("knight_pgp.obj"), scratch("knight_quads.obj"));
    let mesh = format!("{MESHES}/closed_g0_decimated_knight.obj.gz");
    let o = uvflat(&["pgp", &mesh, "-o", out.to_str().unwrap(), "--quad-mesh", quads.to_str().unwrap(), "--json"]);
    let report = json(&o);
    assert_eq!(report["method"], "pgp");
    assert_eq!(report["triangles"], 1000);
    // Hopf–Poincaré on a sphere: the indices sum to 2.
    assert!((report["index_sum"].as_f64().unwrap() - 2.0).abs() < 1e-9, "{report}");
    // The lower bound of forced.rs: 8 quarter turns (χ = 2), at most 2 in a triangle here.
    let (forced, singular) =
        (report["forced_singular_triangles"].as_u64().unwrap(), report["singular_triangles"].as_u64().unwrap());
    assert_eq!(report["forced_quarter_turns"], 8);
    assert!((4..=8).contains(&forced) && forced <= singular, "{report}");
    assert!(report["converged"].as_bool().unwrap(), "{report}");
    // One (θ/2π, φ/2π) per corner, and the remesh the report counts.
    assert_eq!(count_lines(&out, "vt "), 3000);
    assert_eq!(count_lines(&out, "f "), 1000);
    assert_eq!(count_lines(&quads, "f ") as u64, report["quad_mesh"]["faces"].as_u64().unwrap());
    assert!(report["quad_mesh"]["quads"].as_u64().unwrap() * 10 >= report["quad_mesh"]["faces"].as_u64().unwrap() * 9);
}

#[test]
fn quadcover_writes_per_corner_grid_coordinates_and_its_figures() {
    let (out, svg) = (scratch("torus_quadcover.obj"), scratch("torus_quadcover.svg"));
    let mesh = format!("{MESHES}/closed_g1_torus.obj.gz");
    let o = uvflat(&["quadcover", &mesh, "-o", out.to_str().unwrap(), "--svg", svg.to_str().unwrap(), "--json"]);
    let report = json(&o);
    assert_eq!(report["method"], "quadcover");
    assert_eq!(report["triangles"], 4608);
    // A torus of revolution: a smooth field without cones, integer gaps, no fold.
    assert_eq!(report["cones"], 0, "{report}");
    assert_eq!(report["flipped"], 0, "{report}");
    assert!(report["lattice_error"].as_f64().unwrap() < 1e-9, "{report}");
    assert_eq!(count_lines(&out, "vt "), 3 * 4608);
    assert_eq!(count_lines(&out, "f "), 4608);
    assert!(std::fs::read_to_string(&svg).expect("svg").contains("<svg"));
    let bad = uvflat(&["quadcover", &mesh, "-o", out.to_str().unwrap(), "--grid-spacing=-2"]);
    assert_eq!(bad.status.code(), Some(1), "{}", stderr(&bad));
    assert!(stderr(&bad).contains("grid_spacing"), "{}", stderr(&bad));
    // The integer grid lines as a quad mesh: no cone, no fold, so every face a quad.
    let (quads, quad_svg) = (scratch("torus_quadcover_quads.obj"), scratch("torus_quadcover_quads.svg"));
    let with_quads = ["quadcover", &mesh, "-o", out.to_str().unwrap(), "--quad-mesh", quads.to_str().unwrap()];
    let o = uvflat(&[&with_quads[..], &["--quad-svg", quad_svg.to_str().unwrap(), "--json"]].concat());
    let q = &json(&o)["quad_mesh"];
    let faces = q["faces"].as_u64().unwrap();
    assert!(faces > 100 && q["quads"] == q["faces"], "{q}");
    assert_eq!(count_lines(&quads, "f "), faces as usize);
    assert_eq!(count_lines(&quads, "v "), q["vertices"].as_u64().unwrap() as usize);
    assert!(std::fs::read_to_string(&quad_svg).expect("svg").contains("<svg"));
    let bad = uvflat(&["quadcover", &mesh, "-o", out.to_str().unwrap(), "--quad-svg", quad_svg.to_str().unwrap()]);
    assert_eq!(bad.status.code(), Some(2), "{}", stderr(&bad));
    // Checked up front, as pgp does, before any output is written.
    let bad = uvflat(&[&with_quads[..], &["--quad-density", "1.5"]].concat());
    assert_eq!(bad.status.code(), Some(2), "{}", stderr(&bad));
    assert!(stderr(&bad).contains("density"), "{}", stderr(&bad));
    // bob folds after rounding; the untangling (default) opens every fold, --no-untangle keeps them.
    let bob = format!("{MESHES}/closed_g1_bob.obj.gz");
    let on = json(&uvflat(&["quadcover", &bob, "-o", out.to_str().unwrap(), "--json"]));
    let off = json(&uvflat(&["quadcover", &bob, "-o", out.to_str().unwrap(), "--json", "--no-untangle"]));
    assert!(off["flipped"].as_u64().unwrap() > 0 && off["untangled"]["groups"] == 0, "{off}");
    assert_eq!(on["untangled"]["folded_before"], off["flipped"], "{on}");
    assert!(on["flipped"].as_u64().unwrap() < off["flipped"].as_u64().unwrap(), "{on}");
    assert_eq!(on["untangled"]["folded_after"], on["flipped"], "{on}");
}

#[test]
fn outputs_that_cannot_all_be_written_are_refused_before_any_file_is() {
    let out = scratch("refused.obj");
    std::fs::remove_file(&out).ok();
    let missing_dir = scratch("no-such-dir").join("x.svg");
    let bob = format!("{MESHES}/closed_g1_bob.obj.gz");
    let cases: Vec<(Vec<String>, &str)> = vec![
        (vec!["unwrap".into(), SAMPLE.into(), "--svg".into(), out.display().to_string()], "name the same file"),
        (vec!["unwrap".into(), SAMPLE.into(), "--svg".into(), missing_dir.display().to_string()], "does not exist"),
        (vec!["unwrap".into(), SAMPLE.into(), "--svg".into(), scratch("").display().to_string()], "is a directory"),
        (
            vec![
                "quadcover".into(),
                bob.clone(),
                "--quad-mesh".into(),
                scratch("q.obj").display().to_string(),
                "--quad-density".into(),
                "0".into(),
            ],
            "--quad-density",
        ),
        (vec!["pgp".into(), bob, "--quad-mesh".into(), missing_dir.display().to_string()], "does not exist"),
    ];
    for (mut args, expected) in cases {
        args.splice(2..2, ["-o".to_string(), out.display().to_string()]);
        let o = uvflat(&args.iter().map(String::as_str).collect::<Vec<_>>());
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(expected), "{args:?}: {}", stderr(&o));
        assert!(!out.exists(), "{args:?} wrote {}", out.display());
    }
}

#[test]
fn options_that_do_not_apply_to_the_atlas_are_refused() {
    for extra in [["--cone", "0:0"], ["--mu", "0.5"], ["--energy", "edge"]] {
        let out = scratch("atlas-refused.obj");
        let o = uvflat(&["unwrap", SAMPLE, "-o", out.to_str().unwrap(), "--atlas", extra[0], extra[1]]);
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(extra[0]) && stderr(&o).contains("--atlas"), "{}", stderr(&o));
    }
}

#[test]
fn a_full_standard_output_is_an_error_not_a_panic() {
    let Ok(full) = std::fs::OpenOptions::new().write(true).open("/dev/full") else { return };
    let o = Command::new(env!("CARGO_BIN_EXE_uvflat")).arg("methods").stdout(full).output().expect("run uvflat");
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("failed printing to stdout") && !stderr(&o).contains("panicked"), "{}", stderr(&o));
}

#[test]
fn old_texture_coordinates_do_not_stop_a_new_unwrap() {
    // One face with `vt` indices and one without: `metrics` refuses it (it reads those UVs),
    // `unwrap` computes new ones and ignores them.
    let input = scratch("partial-vt.obj");
    std::fs::write(&input, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0.2\nvt 0 0\nf 1/1 2/1 3/1\nf 2 4 3\n").unwrap();
    let out = scratch("partial-vt-out.obj");
    let o = uvflat(&["unwrap", input.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(count_lines(&out, "vt "), 4);
    let o = uvflat(&["metrics", input.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
}

#[test]
fn negative_weights_parse_and_options_a_method_ignores_are_refused() {
    let out = scratch("negative-lambda.obj");
    // (Whether a negative λ makes a valid map is the library's call; the parser must pass it.)
    let o = uvflat(&[
        "unwrap",
        SAMPLE,
        "-o",
        out.to_str().unwrap(),
        "--method",
        "intrinsic",
        "--lambda",
        "-0.5",
        "--mu",
        "1",
    ]);
    assert_ne!(o.status.code(), Some(2), "{}", stderr(&o));
    let torus = format!("{MESHES}/closed_g0_bunny.obj.gz");
    let o = uvflat(&["sphere", &torus, "-o", out.to_str().unwrap(), "--method", "stereographic", "--sweeps", "5"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("--sweeps"), "{}", stderr(&o));
}

#[test]
fn a_nearly_collapsed_uv_triangle_is_warned_about() {
    // Two unit right triangles; the second's UV triangle has 1e-6 of the first's area.
    let input = scratch("collapsed.obj");
    std::fs::write(
        &input,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 0.5 0.500001\nf 1/1 2/2 3/3\nf 2/2 4/4 3/3\n",
    )
    .unwrap();
    let o = uvflat(&["metrics", input.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("nearly degenerate"), "{}", stderr(&o));
    std::fs::write(&input, "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n").unwrap();
    let fine = uvflat(&["metrics", input.to_str().unwrap()]);
    assert!(fine.status.success() && !stderr(&fine).contains("warning"), "{}", stderr(&fine));
}
