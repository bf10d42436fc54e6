//! Per-chart parameterization of PGP (Ray et al. 2006, §3.3–3.4): the surface cut along the
//! iso-2kπ lines, charts without singularity assembled from the per-triangle (θ, φ), charts
//! with singularities re-parameterized by mean-value coordinates. Checked on a parametric
//! torus and on every closed mesh of `tests/data/meshes`:
//! - the cut triangulation covers the input surface exactly (same area, every triangle inside
//!   its input triangle);
//! - no chart folds: every (u, v) triangle of an assembled or re-parameterized chart is
//!   positively oriented (mean-value maps onto a convex domain cannot fold, Floater 2003);
//! - C0 continuity across chart boundaries (§3.4): an edge on the boundary of two charts has
//!   the same (u, v) length in both;
//! - assembled charts reproduce the (θ, φ) of their triangles up to the transition functions.
//!
//! Run with `--nocapture` for the per-mesh table.

use meshes::{closed_meshes, load};
use uvflat_test_support::{meshes, surfaces};

use std::collections::HashMap;
use uvflat_core::geometry::{cross, norm, sub};
use uvflat_core::methods::pgp::charts::{chart_parameterization, ChartKind, ChartParameterization};
use uvflat_core::methods::pgp::{pgp, PgpOptions, PgpResult};
use uvflat_core::progress::Progress;
use uvflat_core::TriMesh;

fn run(mesh: &TriMesh) -> PgpResult {
    pgp(mesh, &PgpOptions::default(), &mut Progress::none()).unwrap()
}

fn area3(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    0.5 * norm(cross(sub(b, a), sub(c, a)))
}

fn area2(q: &[[f64; 2]; 3]) -> f64 {
    0.5 * ((q[1][0] - q[0][0]) * (q[2][1] - q[0][1]) - (q[2][0] - q[0][0]) * (q[1][1] - q[0][1]))
}

#[derive(Debug, Default)]
struct Report {
    charts: usize,
    assembled: usize,
    mean_value: usize,
    split_quads: usize,
    unresolved: usize,
    atlas: usize,
    singular: usize,
    /// Flipped or degenerate (u, v) triangles in charts that are not unresolved.
    flipped: usize,
    /// Cut triangles whose chart is not unresolved.
    checked_triangles: usize,
    area_ratio: f64,
    /// Share of the surface area in unresolved charts.
    unresolved_area: f64,
    /// Share of the surface area in atlas charts.
    atlas_area: f64,
    /// Chart-boundary edges between two quad charts (not atlas or unresolved), and those whose
    /// (u, v) length differs between the two by more than 1e-6 periods (relative).
    shared_edges: usize,
    discontinuous_edges: usize,
    /// The same among edges between two quads of one split chart.
    inner_edges: usize,
    inner_discontinuous: usize,
    /// The same among edges between two assembled charts.
    assembled_edges: usize,
    assembled_discontinuous: usize,
    /// Largest (u, v) outside the chart's extent, in periods.
    outside: f64,
}

fn check(mesh: &TriMesh, c: &ChartParameterization) -> Report {
    let mut rep = Report { charts: c.charts.len(), ..Report::default() };
    for ch in &c.charts {
        match ch.kind {
            ChartKind::Assembled => rep.assembled += 1,
            ChartKind::MeanValue => rep.mean_value += 1,
            ChartKind::SplitQuad => rep.split_quads += 1,
            ChartKind::Unresolved => rep.unresolved += 1,
            ChartKind::Atlas => rep.atlas += 1,
        }
        rep.singular += usize::from(ch.singular);
    }
    let input: f64 = mesh
        .triangles()
        .iter()
        .map(|t| area3(mesh.points()[t[0] as usize], mesh.points()[t[1] as usize], mesh.points()[t[2] as usize]))
        .sum();
    let cut: f64 = c
        .triangles
        .iter()
        .map(|t| area3(c.positions[t[0] as usize], c.positions[t[1] as usize], c.positions[t[2] as usize]))
        .sum();
    rep.area_ratio = cut / input;
    rep.unresolved_area = area_share(c, &[ChartKind::Unresolved]);
    rep.atlas_area = area_share(c, &[ChartKind::Atlas]);
    let quad = |r: usize| {
        matches!(c.charts[c.chart[r] as usize].kind, ChartKind::Assembled | ChartKind::MeanValue | ChartKind::SplitQuad)
    };
    for r in 0..c.triangles.len() {
        let ch = &c.charts[c.chart[r] as usize];
        if ch.kind == ChartKind::Unresolved {
            continue;
        }
        rep.checked_triangles += 1;
        // Zero-area cut triangles (a line through a vertex) are allowed a zero (u, v) area.
        let a3 = area3(
            c.positions[c.triangles[r][0] as usize],
            c.positions[c.triangles[r][1] as usize],
            c.positions[c.triangles[r][2] as usize],
        );
        if area2(&c.uv[r]) <= 0.0 && a3 > 1e-14 * input {
            rep.flipped += 1;
        }
        for p in &c.uv[r] {
            let out = (-p[0]).max(-p[1]).max(p[0] - ch.size[0]).max(p[1] - ch.size[1]);
            rep.outside = rep.outside.max(out);
        }
    }
    // (u, v) length of every directed edge, per chart.
    let mut length: HashMap<(u32, u32), (u32, f64)> = HashMap::new();
    for r in 0..c.triangles.len() {
        for k in 0..3 {
            let (a, b) = (c.triangles[r][k], c.triangles[r][(k + 1) % 3]);
            let (p, q) = (c.uv[r][k], c.uv[r][(k + 1) % 3]);
            length.insert((a, b), (c.chart[r], ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2)).sqrt()));
        }
    }
    let chart_of: HashMap<(u32, u32), usize> = (0..c.triangles.len())
        .flat_map(|r| (0..3).map(move |k| (r, k)))
        .map(|(r, k)| ((c.triangles[r][k], c.triangles[r][(k + 1) % 3]), r))
        .collect();
    for (&(a, b), &(chart, l)) in &length {
        let Some(&(other, m)) = length.get(&(b, a)) else { continue };
        if chart == other || a > b {
            continue;
        }
        let (r1, r2) = (chart_of[&(a, b)], chart_of[&(b, a)]);
        if !quad(r1) || !quad(r2) {
            continue;
        }
        let bad = (l - m).abs() > 1e-6;
        if c.charts[chart as usize].layout == c.charts[other as usize].layout {
            rep.inner_edges += 1;
            rep.inner_discontinuous += usize::from(bad);
            continue;
        }
        rep.shared_edges += 1;
        rep.discontinuous_edges += usize::from(bad);
        if c.charts[chart as usize].kind == ChartKind::Assembled
            && c.charts[other as usize].kind == ChartKind::Assembled
        {
            rep.assembled_edges += 1;
            rep.assembled_discontinuous += usize::from(bad);
        }
    }
    rep
}

#[test]
fn a_torus_without_singularities_is_cut_into_assembled_unit_square_charts() {
    let mesh =
        TriMesh::new(&surfaces::torus(6.0, 1.0, 192, 32).positions, &surfaces::torus(6.0, 1.0, 192, 32).triangles)
            .unwrap();
    let r = run(&mesh);
    assert!(r.singularities.triangles.is_empty());
    let density = 1.0;
    let c = chart_parameterization(&mesh, &r, density).unwrap();
    let rep = check(&mesh, &c);
    println!("{rep:?}");
    assert_eq!(rep.assembled, rep.charts, "{rep:?}");
    assert!(
        c.charts.iter().all(|ch| ch.corners == 4 && (ch.size[0] - 1.0).abs() < 1e-6 && (ch.size[1] - 1.0).abs() < 1e-6),
        "{:?}",
        c.charts
    );
    assert_eq!((rep.flipped, rep.discontinuous_edges), (0, 0), "{rep:?}");
    assert!((rep.area_ratio - 1.0).abs() < 1e-12 && rep.outside < 1e-6, "{rep:?}");
}

/// Surface-area share of the charts of `kinds`.
fn area_share(c: &ChartParameterization, kinds: &[ChartKind]) -> f64 {
    let area = |r: usize| {
        let t = c.triangles[r];
        area3(c.positions[t[0] as usize], c.positions[t[1] as usize], c.positions[t[2] as usize])
    };
    let all: f64 = (0..c.triangles.len()).map(area).sum();
    let some: f64 =
        (0..c.triangles.len()).filter(|&r| kinds.contains(&c.charts[c.chart[r] as usize].kind)).map(area).sum();
    some / all
}

/// The checks every mesh must pass, and its table row.
fn check_mesh(name: &str, mesh: &TriMesh, density: f64) -> String {
    let r = run(mesh);
    let t0 = std::time::Instant::now();
    let c = chart_parameterization(mesh, &r, density).unwrap_or_else(|e| panic!("{name}: {e}"));
    let secs = t0.elapsed().as_secs_f64();
    let rep = check(mesh, &c);
    assert_eq!(rep.unresolved, 0, "{name}: {rep:?}");
    assert_eq!(rep.flipped, 0, "{name}: {rep:?}");
    assert_eq!(rep.discontinuous_edges, 0, "{name}: {rep:?}");
    assert!((rep.area_ratio - 1.0).abs() < 1e-9 && rep.outside < 1e-6, "{name}: {rep:?}");
    let quads = area_share(&c, &[ChartKind::Assembled, ChartKind::MeanValue, ChartKind::SplitQuad]);
    let singular = 100.0 * r.singularities.triangles.len() as f64 / mesh.triangle_count() as f64;
    format!(
        "| {} | {} | {singular:.2}% | {} | {} | {} | {} | {} | {:.1}% | {} / {} | {secs:.2} |",
        name.trim_end_matches(".obj"),
        mesh.triangle_count(),
        rep.charts,
        rep.assembled,
        rep.mean_value,
        rep.split_quads,
        rep.atlas,
        100.0 * quads + 0.0, // + 0.0 turns -0.0 into 0.0 (no "-0.0%")
        rep.shared_edges,
        rep.inner_discontinuous,
    )
}

#[test]
fn every_closed_mesh_is_cut_into_charts_that_do_not_fold_and_join_continuously() {
    let names = closed_meshes();
    let density: f64 = std::env::var("UVFLAT_CHART_DENSITY").map_or(1.0, |d| d.parse().expect("a number"));
    println!("| mesh | triangles | singular triangles | charts | assembled | mean value | split quads | atlas | quad-chart area | continuous edges / inner seams | s |");
    println!("|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|");
    for name in &names {
        println!("{}", check_mesh(name, &load(name), density));
    }
}

#[test]
fn meshes_with_boundary_are_cut_into_charts_that_do_not_fold_and_join_continuously() {
    for name in ["holes_head.obj", "holes_punctured_torus.obj", "holes_lion.obj", "holes_beetle.obj"] {
        println!("{}", check_mesh(name, &load(name), 1.0));
    }
}

#[test]
fn chart_density_must_be_a_whole_number() {
    let s = surfaces::torus(6.0, 1.0, 48, 16);
    let mesh = TriMesh::new(&s.positions, &s.triangles).unwrap();
    let r = run(&mesh);
    for bad in [0.0, 1.5, f64::NAN, -2.0] {
        assert!(chart_parameterization(&mesh, &r, bad).is_err(), "density {bad}");
    }
    let c = chart_parameterization(&mesh, &r, 2.0).unwrap();
    assert!(c.charts.iter().all(|ch| ch.kind == ChartKind::Assembled));
}
