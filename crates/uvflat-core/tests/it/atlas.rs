//! Atlas mode on every closed and multi-hole mesh of `tests/data/meshes` (`closed_*`, `holes_*`:
//! genus 0 to 133), and the default unwrap (`uvflat_core::unwrap`) on every manifold mesh there
//! (`disk_*` as well):
//! - zero flipped triangles: every UV triangle is counter-clockwise (the packer only rotates and
//!   translates charts, so one orientation holds across the whole atlas) and not degenerate;
//! - zero overlaps: no two UV triangles — of different charts, or of one chart — have
//!   intersecting interiors, checked by a separating-axis test on every pair of triangles whose
//!   bounding boxes share a cell of a uniform grid (this file's own geometry, not the library's);
//! - every UV inside the unit square, every chart within the stretch bound (the default unwrap's
//!   islands measured one by one with `metrics::distortion`), the reported atlas stretch equal
//!   to `metrics::distortion`'s; with the bound off, the default unwrap keeps every connected
//!   component one island;
//! - cut + flatten + unflatten: mapping each corner's UV vertex back to its input vertex gives
//!   the input triangle, so every original vertex is reproduced exactly once per corner, and
//!   corners of one input vertex share a UV vertex exactly when they are joined by an edge that
//!   is not a seam (also after an OBJ round trip, and on generated tori of several sizes).
//!
//! Run with `--nocapture` for the per-mesh table.

use std::time::Instant;
use uvflat_test_support::meshes;

use uvflat_core::atlas::{atlas, Atlas, AtlasOptions, ChartMethod};
use uvflat_core::io::obj::{read_obj, write_obj_with_corner_uv};
use uvflat_core::metrics::distortion;
use uvflat_core::unwrap::{unwrap, UnwrapOptions};
use uvflat_core::verify::check_layout;
use uvflat_core::TriMesh;

use meshes::{load, DIR as MESH_DIR};

fn closed_and_holes() -> Vec<String> {
    let names = meshes::with_prefix(&["closed_", "holes_"]);
    assert!(names.len() >= 20, "expected the closed_* and holes_* meshes in {MESH_DIR}");
    names
}

fn signed_area(q: [[f64; 2]; 3]) -> f64 {
    0.5 * ((q[1][0] - q[0][0]) * (q[2][1] - q[0][1]) - (q[1][1] - q[0][1]) * (q[2][0] - q[0][0]))
}

/// Whether the interiors of two counter-clockwise triangles intersect: no separating axis among
/// the six edge normals (for convex polygons with disjoint interiors one always exists; touching
/// along an edge or at a vertex counts as disjoint, up to `eps`).
fn interiors_intersect(a: [[f64; 2]; 3], b: [[f64; 2]; 3], eps: f64) -> bool {
    for (first, second) in [(a, b), (b, a)] {
        for k in 0..3 {
            let (p, q) = (first[k], first[(k + 1) % 3]);
            let n = [q[1] - p[1], p[0] - q[0]]; // outward normal of a counter-clockwise edge
            let proj = |r: [f64; 2]| n[0] * (r[0] - p[0]) + n[1] * (r[1] - p[1]);
            let first_max = first.iter().map(|&r| proj(r)).fold(f64::NEG_INFINITY, f64::max);
            let second_min = second.iter().map(|&r| proj(r)).fold(f64::INFINITY, f64::min);
            if second_min >= first_max - eps * (n[0].abs() + n[1].abs()) {
                return false;
            }
        }
    }
    true
}

/// Overlapping triangle pairs `(between charts, within a chart)`.
fn overlapping_pairs(atlas: &Atlas) -> (usize, usize) {
    let tris = atlas.corner_uv();
    let n = tris.len();
    let boxes: Vec<([f64; 2], [f64; 2])> = tris
        .iter()
        .map(|t| {
            let lo = [
                t.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min),
                t.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min),
            ];
            let hi = [
                t.iter().map(|p| p[0]).fold(f64::NEG_INFINITY, f64::max),
                t.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max),
            ];
            (lo, hi)
        })
        .collect();
    // Grid over the unit square with about one triangle per cell; big triangles span many cells.
    let cells = ((n as f64).sqrt().ceil() as usize).clamp(1, 4096);
    let cell = |x: f64| ((x * cells as f64).floor().max(0.0) as usize).min(cells - 1);
    let mut grid: Vec<Vec<u32>> = vec![Vec::new(); cells * cells];
    for (t, (lo, hi)) in boxes.iter().enumerate() {
        for cy in cell(lo[1])..=cell(hi[1]) {
            for cx in cell(lo[0])..=cell(hi[0]) {
                grid[cy * cells + cx].push(t as u32);
            }
        }
    }
    let (mut between, mut within) = (0, 0);
    for (c, members) in grid.iter().enumerate() {
        let (cx, cy) = (c % cells, c / cells);
        for (i, &s) in members.iter().enumerate() {
            for &t in &members[i + 1..] {
                let (a, b) = (boxes[s as usize], boxes[t as usize]);
                // Count each pair once: in the cell of the lower-left corner of the boxes' overlap.
                let corner = [a.0[0].max(b.0[0]), a.0[1].max(b.0[1])];
                if corner[0] > a.1[0].min(b.1[0]) || corner[1] > a.1[1].min(b.1[1]) {
                    continue;
                }
                if cell(corner[0]) != cx || cell(corner[1]) != cy {
                    continue;
                }
                if interiors_intersect(tris[s as usize], tris[t as usize], 1e-12) {
                    if atlas.chart_of_triangle[s as usize] == atlas.chart_of_triangle[t as usize] {
                        within += 1;
                    } else {
                        between += 1;
                    }
                }
            }
        }
    }
    (between, within)
}

/// Flipped or degenerate UV triangles (all must be counter-clockwise).
fn flipped(atlas: &Atlas) -> usize {
    atlas
        .corner_uv()
        .iter()
        .filter(|q| {
            let longest = (0..3)
                .map(|k| {
                    let (p, r) = (q[k], q[(k + 1) % 3]);
                    (p[0] - r[0]).powi(2) + (p[1] - r[1]).powi(2)
                })
                .fold(0.0, f64::max);
            !(2.0 * signed_area(**q) > 1e-12 * longest)
        })
        .count()
}

/// Unflatten: every corner's atlas vertex maps back to the corner's input vertex, and two
/// corners of one input vertex joined across a shared edge of one chart share their atlas
/// vertex unless that edge is a seam (the edge then has different atlas vertices on its sides).
fn check_unflatten(file: &str, mesh: &TriMesh, atlas: &Atlas) {
    assert_eq!(atlas.triangles.len(), mesh.triangle_count(), "{file}");
    let mut corners_per_vertex = vec![0usize; mesh.vertex_count()];
    for (t, (tri, uv_tri)) in mesh.triangles().iter().zip(&atlas.triangles).enumerate() {
        for k in 0..3 {
            assert_eq!(atlas.original[uv_tri[k] as usize], tri[k], "{file}: triangle {t} corner {k} maps back wrongly");
            corners_per_vertex[tri[k] as usize] += 1;
        }
    }
    // Each input vertex is reproduced once per corner: as many corners as its triangle fan.
    let mut fan = vec![0usize; mesh.vertex_count()];
    for tri in mesh.triangles() {
        for &v in tri {
            fan[v as usize] += 1;
        }
    }
    assert_eq!(corners_per_vertex, fan, "{file}");
    // Across every interior edge: the two sides use the same atlas vertices, or the edge is a
    // seam with the chart boundary on both sides (different atlas vertices at both ends or
    // different charts).
    let twin = &mesh.connectivity().twin;
    for h in 0..twin.len() {
        let g = twin[h];
        if g == u32::MAX {
            continue;
        }
        let (th, tg) = (h / 3, g as usize / 3);
        let uv_tail_h = atlas.triangles[th][h % 3];
        let uv_head_g = atlas.triangles[tg][(g as usize + 1) % 3];
        // The same input vertex on both sides.
        assert_eq!(atlas.original[uv_tail_h as usize], atlas.original[uv_head_g as usize], "{file}");
        if atlas.chart_of_triangle[th] != atlas.chart_of_triangle[tg] {
            assert_ne!(uv_tail_h, uv_head_g, "{file}: two charts share an atlas vertex");
        }
    }
}

fn check_atlas(
    file: &str,
    mesh: &TriMesh,
    atlas: &Atlas,
    max_stretch: f64,
    failures: &mut Vec<String>,
) -> (usize, usize, usize) {
    check_unflatten(file, mesh, atlas);
    assert!(
        atlas.uv.iter().all(|p| (0.0..=1.0).contains(&p[0]) && (0.0..=1.0).contains(&p[1])),
        "{file}: UV outside [0,1]²"
    );
    for (c, info) in atlas.charts.iter().enumerate() {
        assert!(info.stretch_l2 <= max_stretch, "{file}: chart {c} stretch {} over {max_stretch}", info.stretch_l2);
    }
    let m = distortion(mesh.points(), mesh.triangles(), &atlas.uv, &atlas.triangles).expect("metrics");
    let relative = (m.stretch_l2 - atlas.stretch_l2).abs() / m.stretch_l2;
    assert!(
        relative < 1e-6 || !atlas.stretch_l2.is_finite(),
        "{file}: reported stretch {} vs metrics {}",
        atlas.stretch_l2,
        m.stretch_l2
    );
    let flips = flipped(atlas);
    let (between, within) = overlapping_pairs(atlas);
    if flips + between + within > 0 {
        failures.push(format!("{file}: {flips} flipped, {between} overlapping pairs between charts, {within} within"));
    }
    (flips, between, within)
}

#[test]
fn every_closed_and_multi_hole_mesh_gets_an_atlas_without_flips_or_overlaps() {
    let options = AtlasOptions::default();
    println!("{:<32} {:>7} {:>8} {:>7} {:>6} {:>7}", "mesh", "faces", "charts", "L2", "util", "s");
    let mut failures = Vec::new();
    for file in closed_and_holes() {
        let mesh = load(&file);
        let start = Instant::now();
        let a = atlas(&mesh, &options).unwrap_or_else(|e| panic!("{file}: atlas failed: {e}"));
        let seconds = start.elapsed().as_secs_f64();
        check_atlas(&file, &mesh, &a, options.max_stretch, &mut failures);
        println!(
            "{file:<32} {:>7} {:>8} {:>7.4} {:>6.3} {:>7.2}",
            mesh.triangle_count(),
            a.charts.len(),
            a.stretch_l2,
            a.utilization,
            seconds
        );
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// L2 stretch of each island, measured on its own triangles by `metrics::distortion`.
fn island_stretches(mesh: &TriMesh, atlas: &Atlas) -> Vec<f64> {
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); atlas.charts.len()];
    for (t, &c) in atlas.chart_of_triangle.iter().enumerate() {
        members[c as usize].push(t);
    }
    members
        .iter()
        .map(|faces| {
            let tris: Vec<[u32; 3]> = faces.iter().map(|&t| mesh.triangles()[t]).collect();
            let uv_tris: Vec<[u32; 3]> = faces.iter().map(|&t| atlas.triangles[t]).collect();
            distortion(mesh.points(), &tris, &atlas.uv, &uv_tris).expect("island metrics").stretch_l2
        })
        .collect()
}

/// The promise of the default unwrap, on every manifold mesh: no flipped triangle, no
/// overlap (this file's triangle-pair test and the library's exact checker agree), every
/// island's L2 stretch at most 1.5 by an independent measurement; with the bound off, one island
/// per connected component and still no flip or overlap.
#[test]
fn the_default_unwrap_is_valid_on_every_manifold_mesh() {
    let names: Vec<String> = meshes::with_prefix(&["disk_", "holes_", "closed_"])
        .into_iter()
        .filter(|n| !n.contains("_loop")) // the subdivided scaling meshes belong to the benches
        .collect();
    assert!(names.len() >= 40, "expected the disk_*, holes_* and closed_* meshes in {MESH_DIR}");
    println!(
        "{:<36} {:>7} | {:>7} {:>8} {:>7} {:>7} {:>6} | {:>9} {:>8} {:>6}",
        "mesh", "faces", "islands", "repaired", "max L2", "angle°", "s", "∞:islands", "repaired", "s"
    );
    let mut failures = Vec::new();
    let bounded = UnwrapOptions::default();
    let free = UnwrapOptions { max_stretch: f64::INFINITY, ..UnwrapOptions::default() };
    for file in names {
        let mesh = load(&file);
        let mut row = Vec::new();
        for options in [&bounded, &free] {
            let start = Instant::now();
            let result = unwrap(&mesh, options).unwrap_or_else(|e| panic!("{file}: unwrap failed: {e}"));
            let seconds = start.elapsed().as_secs_f64();
            let a = &result.atlas;
            check_atlas(&file, &mesh, a, options.max_stretch, &mut failures);
            let exact = check_layout(&a.uv, &a.triangles);
            if !exact.is_valid() {
                failures.push(format!("{file}: exact checker: {exact:?}"));
            }
            let worst = island_stretches(&mesh, a).into_iter().fold(0.0, f64::max);
            if options.max_stretch.is_finite() && !(worst <= options.max_stretch * (1.0 + 1e-9)) {
                failures.push(format!("{file}: an island has L2 stretch {worst} > {}", options.max_stretch));
            }
            if options.max_stretch.is_infinite() && a.charts.len() != mesh.topology().components {
                failures.push(format!(
                    "{file}: {} islands without a bound, {} components",
                    a.charts.len(),
                    mesh.topology().components
                ));
            }
            let angle = distortion(mesh.points(), mesh.triangles(), &a.uv, &a.triangles).expect("metrics").angle_mean;
            row.push((a.charts.len(), result.report.repaired_islands, worst, angle.to_degrees(), seconds));
        }
        let (b, f) = (row[0], row[1]);
        println!(
            "{file:<36} {:>7} | {:>7} {:>8} {:>7.3} {:>7.3} {:>6.2} | {:>9} {:>8} {:>6.2}",
            mesh.triangle_count(),
            b.0,
            b.1,
            b.2,
            b.3,
            b.4,
            f.0,
            f.1,
            f.4
        );
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// A torus of `n × m` quads split into triangles, radii perturbed deterministically.
fn torus(n: u32, m: u32, seed: u64) -> TriMesh {
    let mut state = seed;
    let mut noise = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((state >> 33) as f64 / (1u64 << 31) as f64) - 0.5
    };
    let mut positions = Vec::new();
    for i in 0..n {
        for j in 0..m {
            let (u, v) = (i as f64 / n as f64 * std::f64::consts::TAU, j as f64 / m as f64 * std::f64::consts::TAU);
            let r = 2.0 + (1.0 + 0.2 * noise()) * v.cos();
            positions.extend([r * u.cos(), r * u.sin(), (1.0 + 0.2 * noise()) * v.sin()]);
        }
    }
    let id = |i: u32, j: u32| (i % n) * m + (j % m);
    let mut tris = Vec::new();
    for i in 0..n {
        for j in 0..m {
            tris.extend([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    TriMesh::new(&positions, &tris).expect("torus")
}

#[test]
fn cut_flatten_unflatten_reproduces_every_vertex_once_per_corner() {
    let mut failures = Vec::new();
    let dir = std::env::temp_dir().join(format!("uvflat-atlas-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    for (case, (n, m)) in [(3u32, 3u32), (4, 7), (9, 5), (16, 12), (30, 10)].into_iter().enumerate() {
        let mesh = torus(n, m, case as u64 + 1);
        let name = format!("torus {n}x{m}");
        let unwrapped = unwrap(&mesh, &UnwrapOptions { margin: 0.01, ..UnwrapOptions::default() }).map(|r| r.atlas);
        for result in [unwrapped, atlas(&mesh, &AtlasOptions::default())] {
            let a = result.unwrap_or_else(|e| panic!("{name}: {e}"));
            check_atlas(&name, &mesh, &a, f64::INFINITY, &mut failures);
            // Through an OBJ file and back: the same corners, the same UVs.
            let path = dir.join(format!("t{case}.obj"));
            let positions: Vec<f64> = mesh.points().iter().flatten().copied().collect();
            let triangles: Vec<u32> = mesh.triangles().iter().flatten().copied().collect();
            let uv_index: Vec<u32> = a.triangles.iter().flatten().copied().collect();
            write_obj_with_corner_uv(&path, &positions, &triangles, &a.uv, &uv_index).expect("write");
            let back = read_obj(&path).expect("read");
            assert_eq!(back.triangles, triangles, "{name}");
            for (t, tri) in back.uv_triangles.chunks_exact(3).enumerate() {
                for k in 0..3 {
                    let (u, w) = (tri[k] as usize, a.triangles[t][k] as usize);
                    assert_eq!([back.uv[2 * u], back.uv[2 * u + 1]], a.uv[w], "{name}: corner UV changed");
                }
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    assert!(failures.is_empty(), "{failures:#?}");
}

#[test]
fn the_stretch_bound_is_met_and_looser_bounds_give_fewer_charts() {
    let mesh = load("closed_g0_bunny.obj");
    let mut previous = usize::MAX;
    for bound in [1.01, 1.05, 1.2] {
        let options = AtlasOptions { max_stretch: bound, ..AtlasOptions::default() };
        let a = atlas(&mesh, &options).expect("atlas");
        assert!(a.charts.iter().all(|c| c.stretch_l2 <= bound));
        let m = distortion(mesh.points(), mesh.triangles(), &a.uv, &a.triangles).expect("metrics");
        assert!(m.stretch_l2 <= bound * (1.0 + 1e-9), "bound {bound}: atlas stretch {}", m.stretch_l2);
        assert!(a.charts.len() <= previous, "bound {bound}: {} charts, more than with a tighter bound", a.charts.len());
        previous = a.charts.len();
    }
}

/// Polishing (L2-stretch minimization per chart) is kept only where it lowers a chart's
/// stretch, and lets charts slightly over the bound be accepted: with it the atlas has no more
/// charts and lower stretch (measured independently by `metrics::distortion`) than without.
#[test]
fn polishing_lowers_the_stretch_without_adding_charts() {
    for file in ["closed_g0_bunny.obj", "closed_g0_cow.obj", "holes_lion.obj"] {
        let mesh = load(file);
        let stretch = |a: &Atlas| distortion(mesh.points(), mesh.triangles(), &a.uv, &a.triangles).unwrap().stretch_l2;
        let plain = atlas(&mesh, &AtlasOptions { polish: 0, ..AtlasOptions::default() }).expect("atlas");
        let polished = atlas(&mesh, &AtlasOptions::default()).expect("atlas");
        assert!(
            polished.charts.len() <= plain.charts.len(),
            "{file}: {} > {} charts",
            polished.charts.len(),
            plain.charts.len()
        );
        assert!(stretch(&polished) < stretch(&plain), "{file}: {} ≥ {}", stretch(&polished), stretch(&plain));
    }
}

#[test]
fn options_out_of_range_are_refused() {
    let mesh = torus(6, 4, 7);
    for options in [
        AtlasOptions { max_stretch: 0.5, ..AtlasOptions::default() },
        AtlasOptions { max_stretch: f64::NAN, ..AtlasOptions::default() },
        AtlasOptions { margin: 0.5, ..AtlasOptions::default() },
        AtlasOptions { margin: -0.1, ..AtlasOptions::default() },
    ] {
        assert!(matches!(atlas(&mesh, &options), Err(uvflat_core::Error::InvalidArgument(_))), "{options:?}");
    }
}

#[test]
fn a_margin_the_charts_cannot_all_have_is_refused_before_packing() {
    // 422 charts at margin 0.05 used to come back at a utilization of 1e-6 (charts shrunk to
    // nothing), and margin 0.3 on the knight ran for minutes in the raster packing.
    let mesh = load("closed_g0_decimated_knight.obj");
    let charts = atlas(&mesh, &AtlasOptions::default()).unwrap().charts.len();
    let margin = 0.6 / (charts as f64).sqrt();
    match atlas(&mesh, &AtlasOptions { margin, ..AtlasOptions::default() }) {
        Err(uvflat_core::Error::InvalidArgument(m)) => assert!(m.contains("too large"), "{m}"),
        other => panic!("margin {margin} for {charts} charts: {:?}", other.map(|a| a.charts.len())),
    }
}

#[test]
fn every_chart_method_and_the_isometric_bound_give_an_atlas() {
    // A triangle alone always has an isometric layout: a method that puts its corners
    // elsewhere (mean value: on a circle) or rounds a few ulps over max_stretch = 1 no longer
    // fails the whole atlas.
    let mesh = load("closed_g0_decimated_knight.obj");
    for options in [
        AtlasOptions { method: ChartMethod::MeanValue, ..AtlasOptions::default() },
        AtlasOptions { max_stretch: 1.0, ..AtlasOptions::default() },
    ] {
        let result = atlas(&mesh, &options).unwrap_or_else(|e| panic!("{options:?}: {e}"));
        assert_eq!(flipped(&result), 0, "{options:?}");
        assert!(result.charts.iter().all(|c| c.stretch_l2 <= options.max_stretch * (1.0 + 1e-9)), "{options:?}");
    }
}

/// Vertices snapped onto a neighbour but not merged (what a modeller's snap leaves), which
/// `TriMesh::new` refuses: `unwrap_arrays` welds each pair, leaves out exactly the triangles
/// holding both ends of a pair (found here from the input), and the rest of the layout is
/// valid by this file's own checks; every corner's UV vertex maps back to its input vertex or
/// to the vertex it was snapped onto.
#[test]
fn snapped_vertices_are_welded_and_the_rest_of_the_unwrap_is_valid() {
    for file in ["disk_cat_head.obj", "closed_g1_bob.obj"] {
        let mesh = load(file);
        let mut positions: Vec<f64> = mesh.points().iter().flatten().copied().collect();
        let triangles: Vec<u32> = mesh.triangles().iter().flatten().copied().collect();
        let mut pairs: Vec<(u32, u32)> = Vec::new();
        let step = (mesh.triangle_count() / 7).max(1);
        for t in mesh.triangles().iter().step_by(step) {
            let (a, b) = (t[0].min(t[1]), t[0].max(t[1]));
            if pairs.len() < 5 && pairs.iter().all(|&(x, y)| ![x, y].contains(&a) && ![x, y].contains(&b)) {
                pairs.push((a, b));
            }
        }
        for &(a, b) in &pairs {
            for k in 0..3 {
                positions[3 * b as usize + k] = positions[3 * a as usize + k];
            }
        }
        assert!(TriMesh::new(&positions, &triangles).is_err(), "{file}: snapping must make degenerate triangles");
        let result = uvflat_core::unwrap::unwrap_arrays(
            &positions,
            &triangles,
            &UnwrapOptions::default(),
            &mut uvflat_core::progress::Progress::none(),
        )
        .unwrap_or_else(|e| panic!("{file}: {e}"));
        let holds_pair: Vec<bool> =
            mesh.triangles().iter().map(|t| pairs.iter().any(|&(a, b)| t.contains(&a) && t.contains(&b))).collect();
        let report = &result.report;
        assert_eq!(report.welded_vertices, pairs.len(), "{file}");
        assert_eq!(report.left_out_triangles, holds_pair.iter().filter(|&&h| h).count(), "{file}");
        let a = &result.atlas;
        assert_eq!(a.triangles.len(), mesh.triangle_count());
        let snapped_onto = |v: u32| pairs.iter().find(|p| p.1 == v).map_or(v, |p| p.0);
        for (t, corners) in mesh.triangles().iter().zip(&a.triangles) {
            for (&v, &uv) in t.iter().zip(corners) {
                assert_eq!(a.original[uv as usize], snapped_onto(v), "{file}: corner of vertex {v}");
            }
        }
        let kept: Vec<usize> = (0..holds_pair.len()).filter(|&t| !holds_pair[t]).collect();
        let solved = Atlas {
            triangles: kept.iter().map(|&t| a.triangles[t]).collect(),
            chart_of_triangle: kept.iter().map(|&t| a.chart_of_triangle[t]).collect(),
            ..a.clone()
        };
        assert_eq!(flipped(&solved), 0, "{file}");
        assert_eq!(overlapping_pairs(&solved), (0, 0), "{file}");
        assert!(a.uv.iter().flatten().all(|x| (0.0..=1.0).contains(x)), "{file}");
        // A left-out triangle's two welded corners share one UV vertex.
        for (t, corners) in mesh
            .triangles()
            .iter()
            .zip(&a.triangles)
            .filter(|(t, _)| pairs.iter().any(|&(x, y)| t.contains(&x) && t.contains(&y)))
        {
            let &(x, y) = pairs.iter().find(|&&(x, y)| t.contains(&x) && t.contains(&y)).unwrap();
            let at = |v: u32| corners[t.iter().position(|&w| w == v).unwrap()];
            assert_eq!(at(x), at(y), "{file}: {t:?}");
        }
    }
}
