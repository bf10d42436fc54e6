//! uvflat against CGAL 5.5's Surface_mesh_parameterization on every disk mesh of the shared
//! collection with at most 100k faces.
//!
//! For each mesh, `crates/uvflat-test-support/cgal/cgal_reference.cpp` runs CGAL's method and uvflat runs its
//! counterpart on the same problem:
//! - fixed-border methods (dcp, dap, mvc, tutte): CGAL puts the border on a circle by arc
//!   length; uvflat is given exactly those boundary positions (`BoundaryShape::Given`), so
//!   both solve the same linear system up to the weights;
//! - lscm: CGAL pins the two boundary vertices farthest apart in 3D at (0, 0.5) and (1, 0.5);
//!   uvflat's natural conformal map is given the same two pins at the same positions.
//!   CGAL 5.5 writes one LSCM equation per triangle, (Z1−Z0)(U2−U0) = (Z2−Z0)(U1−U0), without
//!   the 1/sqrt(2·area) factor of Lévy et al. 2002 (LSCM_parameterizer_3.h,
//!   `setup_triangle_relations`, "no divide with this expression"), so it minimises
//!   Σ_T |r_T|² where LSCM and Desbrun et al. eq. 7 minimise Σ_T |r_T|²/A_T. Both have the same
//!   minimiser when the mesh is developable (energy 0). So on developable meshes the UVs must
//!   agree; on curved meshes each result must be optimal for its own energy: uvflat's Σ|r|²/A no larger
//!   than CGAL's, and CGAL's Σ|r|² no larger than uvflat's (relative slack `ENERGY_SLACK`).
//!
//!   `area_weighted_conformal_map` minimises CGAL's energy (Σ_T A_T·E_C,T = Σ|r|²/8); given the
//!   same pins it must agree with CGAL's LSCM on every mesh, curved or not.
//!
//! Every vertex's UV must agree to 1e-6 of the diagonal of CGAL's UV bounding box. A CGAL run
//! that fails (for example its iterative solver not converging) is reported, not hidden, and is
//! not counted as a disagreement; every method must still be compared on at least one mesh.
//! All runs happen once (two meshes at a time) and print one table; each method then has its
//! own test, so one method's disagreement does not hide the others' results.
//!
//! `UVFLAT_CGAL_DUMP_DIR=dir` writes both sides' UVs there (`<mesh>_<method>_{uvflat,cgal}.txt`).
//!
//! Needs libcgal-dev and libeigen3-dev: skipped without them, except under CI (`CI=true`),
//! where their absence fails the test.

use cgal::{DiskMesh, Method, Reference};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, OnceLock};
use std::time::Instant;
use uvflat_core::{
    area_weighted_conformal_map, fixed_boundary_map, natural_conformal_map, BoundaryShape, Distribution,
    FixedBoundaryOptions, TriMesh, Weights,
};
use uvflat_test_support::{cgal, meshes};

/// Largest mesh compared (faces).
const MAX_FACES: usize = 100_000;
/// Agreement required, relative to the diagonal of CGAL's UV bounding box.
const TOLERANCE: f64 = 1e-6;
const THREADS: usize = 2;
/// Relative slack when comparing the energies of two minimisers (direct solvers on both sides).
const ENERGY_SLACK: f64 = 1e-7;

enum Outcome {
    /// Largest distance between uvflat's and CGAL's UV of a vertex, relative to the UV
    /// bounding-box diagonal, and that vertex.
    Compared { deviation: f64, worst_vertex: usize },
    /// LSCM on a curved mesh: (uvflat, CGAL) values of the area-normalised LSCM energy
    /// Σ|r|²/A and of CGAL's unnormalised energy Σ|r|², with the UV deviation for reference.
    Energies { lscm: (f64, f64), cgal: (f64, f64), deviation: f64 },
    /// CGAL returned an error code (or the reference program failed otherwise).
    CgalFailed(String),
    /// CGAL succeeded but uvflat returned an error, or a result of the wrong size.
    UvflatFailed(String),
}

struct Row {
    mesh: String,
    faces: usize,
    method: Method,
    cgal_seconds: Option<f64>,
    uvflat_seconds: Option<f64>,
    outcome: Outcome,
    /// LSCM rows: deviation of `area_weighted_conformal_map` (CGAL's energy) from CGAL's UVs,
    /// relative to the UV diagonal, and the worst vertex; its error if it failed.
    weighted: Option<Result<(f64, usize), String>>,
}

impl Row {
    fn disagrees(&self) -> bool {
        match self.outcome {
            Outcome::Compared { deviation, .. } => !(deviation <= TOLERANCE),
            Outcome::Energies { lscm, cgal, .. } => {
                !(lscm.0 <= lscm.1 * (1.0 + ENERGY_SLACK) && cgal.1 <= cgal.0 * (1.0 + ENERGY_SLACK))
            }
            Outcome::UvflatFailed(_) => true,
            Outcome::CgalFailed(_) => false,
        }
    }
}

/// Largest per-vertex distance between `ours` and `reference`, relative to the diagonal of
/// the reference's bounding box; NaN anywhere counts as infinitely far.
fn max_relative_deviation(ours: &[[f64; 2]], reference: &[[f64; 2]]) -> (f64, usize) {
    let diagonal = cgal::bbox_diagonal(reference);
    let mut worst = (0.0f64, 0usize);
    for (i, (a, b)) in ours.iter().zip(reference).enumerate() {
        let d = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt() / diagonal;
        let d = if d.is_nan() { f64::INFINITY } else { d };
        if d > worst.0 {
            worst = (d, i);
        }
    }
    worst
}

/// Per-triangle LSCM residual r = (Z1−Z0)(U2−U0) − (Z2−Z0)(U1−U0) in the triangle's own
/// orthonormal frame (Z) and the UV plane (U), and the triangle's area.
fn lscm_residual(p: [[f64; 3]; 3], q: [[f64; 2]; 3]) -> (f64, f64) {
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let (e1, e2) = (sub(p[1], p[0]), sub(p[2], p[0]));
    let l1 = dot(e1, e1).sqrt();
    let x = [e1[0] / l1, e1[1] / l1, e1[2] / l1];
    let (z1, z2) = ((l1, 0.0), (dot(e2, x), 0.0));
    let y = sub(e2, [x[0] * z2.0, x[1] * z2.0, x[2] * z2.0]);
    let z2 = (z2.0, dot(y, y).sqrt());
    let (u1, u2) = ((q[1][0] - q[0][0], q[1][1] - q[0][1]), (q[2][0] - q[0][0], q[2][1] - q[0][1]));
    let mul = |a: (f64, f64), b: (f64, f64)| (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0);
    let (a, b) = (mul(z1, u2), mul(z2, u1));
    let r2 = (a.0 - b.0).powi(2) + (a.1 - b.1).powi(2);
    (r2, 0.5 * z1.0 * z2.1)
}

/// (Σ|r|²/A, Σ|r|²) over the mesh for the UVs `uv`.
fn lscm_energies(mesh: &TriMesh, uv: &[[f64; 2]]) -> (f64, f64) {
    let (mut normalised, mut plain) = (0.0, 0.0);
    for t in mesh.triangles() {
        let p = t.map(|v| mesh.points()[v as usize]);
        let q = t.map(|v| uv[v as usize]);
        let (r2, area) = lscm_residual(p, q);
        normalised += r2 / area;
        plain += r2;
    }
    (normalised, plain)
}

/// True when the mesh is intrinsically flat (developable): the corner angles around every
/// interior vertex sum to 2π within 1e-3 (OBJ files round coordinates to ~6 digits, which
/// perturbs the angles of short edges by ~1e-4), so a map with zero LSCM residual exists and both
/// energies have the same minimiser. (disk_maze and disk_hilbert are bent but developable.)
fn is_developable(mesh: &TriMesh, boundary: &[u32]) -> bool {
    let pts = mesh.points();
    let mut angle_sum = vec![0.0f64; pts.len()];
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    for t in mesh.triangles() {
        for k in 0..3 {
            let (o, a, b) = (pts[t[k] as usize], pts[t[(k + 1) % 3] as usize], pts[t[(k + 2) % 3] as usize]);
            let (e1, e2) = (sub(a, o), sub(b, o));
            angle_sum[t[k] as usize] += (dot(e1, e2) / (dot(e1, e1) * dot(e2, e2)).sqrt()).clamp(-1.0, 1.0).acos();
        }
    }
    for &v in boundary {
        angle_sum[v as usize] = std::f64::consts::TAU;
    }
    angle_sum.iter().all(|s| (s - std::f64::consts::TAU).abs() <= 1e-3)
}

/// CGAL's two LSCM pins with the positions CGAL gave them.
fn cgal_pins(reference: &Reference) -> Result<[uvflat_core::methods::conformal::Pin; 2], String> {
    let (a, b) = reference.pins.ok_or("CGAL's LSCM output names no pins")?;
    Ok([(a, reference.uv[a as usize]), (b, reference.uv[b as usize])])
}

/// `area_weighted_conformal_map` with CGAL's pins, against CGAL's LSCM UVs.
fn weighted_deviation(mesh: &TriMesh, reference: &Reference) -> Result<(f64, usize), String> {
    let uv = area_weighted_conformal_map(mesh, Some(cgal_pins(reference)?)).map_err(|e| e.to_string())?;
    Ok(max_relative_deviation(&uv, &reference.uv))
}

/// uvflat's counterpart of `method`, set up with CGAL's boundary or pins from `reference`.
fn run_uvflat(
    mesh: &TriMesh,
    boundary: &[u32],
    method: Method,
    reference: &Reference,
) -> Result<Vec<[f64; 2]>, String> {
    let weights = match method {
        Method::Dcp => Weights::Conformal,
        Method::Dap => Weights::Authalic,
        Method::Mvc => Weights::MeanValue,
        Method::Tutte => Weights::Uniform,
        Method::Lscm => return natural_conformal_map(mesh, Some(cgal_pins(reference)?)).map_err(|e| e.to_string()),
    };
    let given = boundary.iter().map(|&v| (v, reference.uv[v as usize])).collect();
    let options =
        FixedBoundaryOptions { weights, shape: BoundaryShape::Given(given), distribution: Distribution::ChordLength };
    fixed_boundary_map(mesh, &options).map_err(|e| e.to_string())
}

/// Runs every method on one mesh, CGAL first, then uvflat.
fn check_mesh(exe: &Path, disk: &DiskMesh) -> Vec<Row> {
    let row = |method, cgal_seconds, uvflat_seconds, outcome| Row {
        mesh: disk.name.clone(),
        faces: disk.faces,
        method,
        cgal_seconds,
        uvflat_seconds,
        outcome,
        weighted: None,
    };
    let loaded = cgal::read_plain_obj(&disk.path).and_then(|(positions, triangles)| {
        let mesh = TriMesh::new(&positions, &triangles).map_err(|e| format!("TriMesh::new: {e}"))?;
        Ok((mesh, cgal::boundary_vertices(&triangles), positions.len() / 3))
    });
    let (mesh, boundary, vertex_count) = match loaded {
        Ok(loaded) => loaded,
        Err(e) => return Method::ALL.iter().map(|&m| row(m, None, None, Outcome::UvflatFailed(e.clone()))).collect(),
    };

    let mut rows = Vec::new();
    for method in Method::ALL {
        let reference = match cgal::run_reference(exe, method, &disk.path, None) {
            Ok(reference) => reference,
            Err(message) => {
                rows.push(row(method, None, None, Outcome::CgalFailed(message)));
                continue;
            }
        };
        if reference.uv.len() != vertex_count {
            let message = format!("CGAL wrote {} UVs for {vertex_count} vertices", reference.uv.len());
            rows.push(row(method, Some(reference.seconds), None, Outcome::CgalFailed(message)));
            continue;
        }
        let start = Instant::now();
        let result = run_uvflat(&mesh, &boundary, method, &reference);
        let seconds = start.elapsed().as_secs_f64();
        if let (Some(dir), Ok(uv)) = (std::env::var_os("UVFLAT_CGAL_DUMP_DIR"), &result) {
            dump_uv(Path::new(&dir), &disk.name, method, uv, &reference.uv);
        }
        let outcome = match result {
            Ok(uv) if uv.len() == vertex_count => {
                let (deviation, worst_vertex) = max_relative_deviation(&uv, &reference.uv);
                if method == Method::Lscm && !is_developable(&mesh, &boundary) {
                    let (ours, theirs) = (lscm_energies(&mesh, &uv), lscm_energies(&mesh, &reference.uv));
                    Outcome::Energies { lscm: (ours.0, theirs.0), cgal: (ours.1, theirs.1), deviation }
                } else {
                    Outcome::Compared { deviation, worst_vertex }
                }
            }
            Ok(uv) => Outcome::UvflatFailed(format!("{} UVs for {vertex_count} vertices", uv.len())),
            Err(e) => Outcome::UvflatFailed(e),
        };
        let mut done = row(method, Some(reference.seconds), Some(seconds), outcome);
        if method == Method::Lscm {
            done.weighted = Some(weighted_deviation(&mesh, &reference));
        }
        rows.push(done);
    }
    rows
}

/// Writes both results as `u v` lines (for investigating a disagreement; set
/// `UVFLAT_CGAL_DUMP_DIR`).
fn dump_uv(dir: &Path, mesh: &str, method: Method, ours: &[[f64; 2]], reference: &[[f64; 2]]) {
    let write = |side: &str, uv: &[[f64; 2]]| {
        let text: String = uv.iter().map(|p| format!("{:.17e} {:.17e}\n", p[0], p[1])).collect();
        let path = dir.join(format!("{mesh}_{}_{side}.txt", method.name()));
        if let Err(e) = std::fs::write(&path, text) {
            eprintln!("cannot write {}: {e}", path.display());
        }
    };
    write("uvflat", ours);
    write("cgal", reference);
}

fn print_table(rows: &[Row]) {
    println!("| mesh | faces | method | max deviation / UV diagonal | worst vertex | CGAL s | uvflat s | result |");
    println!("|---|---:|---|---:|---:|---:|---:|---|");
    let seconds = |s: Option<f64>| s.map_or("-".to_string(), |s| format!("{s:.4}"));
    for r in rows {
        let (deviation, vertex, result) = match &r.outcome {
            Outcome::Compared { deviation, worst_vertex } => (
                format!("{deviation:.2e}"),
                worst_vertex.to_string(),
                if r.disagrees() { "DISAGREES".to_string() } else { "ok".to_string() },
            ),
            Outcome::Energies { lscm, cgal, deviation } => (
                format!("{deviation:.2e}"),
                "-".into(),
                format!(
                    "{}: Σ|r|²/A uvflat {:.6e} ≤ CGAL {:.6e}; Σ|r|² CGAL {:.6e} ≤ uvflat {:.6e}",
                    if r.disagrees() { "DISAGREES" } else { "ok (curved: energies)" },
                    lscm.0,
                    lscm.1,
                    cgal.1,
                    cgal.0
                ),
            ),
            Outcome::CgalFailed(m) => ("-".into(), "-".into(), format!("CGAL FAILED: {m}")),
            Outcome::UvflatFailed(m) => ("-".into(), "-".into(), format!("UVFLAT FAILED: {m}")),
        };
        println!(
            "| {} | {} | {} | {} | {} | {} | {} | {} |",
            r.mesh,
            r.faces,
            r.method.name(),
            deviation,
            vertex,
            seconds(r.cgal_seconds),
            seconds(r.uvflat_seconds),
            result
        );
    }
}

/// Runs CGAL and uvflat on every mesh and method once, for all the tests below; prints the
/// table. `None` when CGAL is not installed (and this is not CI).
fn results() -> Option<&'static [Row]> {
    static RESULTS: OnceLock<Option<Vec<Row>>> = OnceLock::new();
    RESULTS.get_or_init(compare_all).as_deref()
}

fn compare_all() -> Option<Vec<Row>> {
    if !cgal::require_headers_or_skip() {
        return None;
    }
    let compile_start = Instant::now();
    let exe = cgal::reference_executable().unwrap_or_else(|e| panic!("{e}"));
    println!(
        "CGAL reference program: {} ({:.1} s to compile or find in the cache)",
        exe.display(),
        compile_start.elapsed().as_secs_f64()
    );

    let mut meshes = cgal::disk_meshes(MAX_FACES);
    assert!(!meshes.is_empty(), "no disk_*.obj with at most {MAX_FACES} faces in {}", meshes::DIR);
    meshes.reverse(); // largest first, so the two threads finish together

    let run_start = Instant::now();
    let meshes = Arc::new(meshes);
    let next = Arc::new(AtomicUsize::new(0));
    let workers: Vec<_> = (0..THREADS)
        .map(|_| {
            let (meshes, next, exe) = (Arc::clone(&meshes), Arc::clone(&next), exe.clone());
            std::thread::spawn(move || {
                let mut rows = Vec::new();
                loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    let Some(disk) = meshes.get(i) else { break };
                    rows.extend(check_mesh(&exe, disk));
                }
                rows
            })
        })
        .collect();
    let mut rows: Vec<Row> = workers.into_iter().flat_map(|w| w.join().expect("worker panicked")).collect();
    rows.sort_by(|a, b| (a.method as usize, a.faces, &a.mesh).cmp(&(b.method as usize, b.faces, &b.mesh)));

    print_table(&rows);
    println!("{} meshes x {} methods in {:.1} s", meshes.len(), Method::ALL.len(), run_start.elapsed().as_secs_f64());
    let cgal_failures: Vec<&Row> = rows.iter().filter(|r| matches!(r.outcome, Outcome::CgalFailed(_))).collect();
    if !cgal_failures.is_empty() {
        println!("CGAL failed on {} runs (reported, not counted as disagreements):", cgal_failures.len());
        for r in &cgal_failures {
            if let Outcome::CgalFailed(m) = &r.outcome {
                println!("  {} {}: {m}", r.mesh, r.method.name());
            }
        }
    }
    Some(rows)
}

/// Fails when uvflat disagrees with CGAL for `method` on any mesh CGAL solved, when uvflat
/// fails where CGAL succeeded, or when CGAL solved no mesh at all.
fn assert_matches_cgal(method: Method) {
    let Some(rows) = results() else { return };
    let rows: Vec<&Row> = rows.iter().filter(|r| r.method == method).collect();
    assert!(
        rows.iter().any(|r| matches!(r.outcome, Outcome::Compared { .. })),
        // For LSCM this requires a developable mesh, where the UVs themselves are compared.
        "{}: nothing was compared (CGAL failed on every mesh)",
        method.name()
    );
    let disagreements: Vec<String> = rows
        .iter()
        .filter(|r| r.disagrees())
        .map(|r| match &r.outcome {
            Outcome::Compared { deviation, worst_vertex } => {
                format!("  {}: deviation {deviation:.3e} at vertex {worst_vertex}", r.mesh)
            }
            Outcome::Energies { lscm, cgal, .. } => format!(
                "  {}: not each optimal for its energy: Σ|r|²/A uvflat {:.9e} vs CGAL {:.9e}; Σ|r|² uvflat {:.9e} vs CGAL {:.9e}",
                r.mesh, lscm.0, lscm.1, cgal.0, cgal.1
            ),
            Outcome::UvflatFailed(m) => format!("  {}: uvflat failed: {m}", r.mesh),
            Outcome::CgalFailed(_) => unreachable!("CGAL failures are not disagreements"),
        })
        .collect();
    assert!(
        disagreements.is_empty(),
        "{}: {} of {} meshes disagree with CGAL beyond {TOLERANCE:e} of the UV diagonal:\n{}",
        method.name(),
        disagreements.len(),
        rows.len(),
        disagreements.join("\n")
    );
}

#[test]
fn dcp_matches_cgal_discrete_conformal_map() {
    assert_matches_cgal(Method::Dcp);
}

#[test]
fn dap_matches_cgal_discrete_authalic() {
    assert_matches_cgal(Method::Dap);
}

#[test]
fn mean_value_map_matches_cgal_mean_value_coordinates() {
    assert_matches_cgal(Method::Mvc);
}

#[test]
fn tutte_map_matches_cgal_barycentric_mapping() {
    assert_matches_cgal(Method::Tutte);
}

#[test]
fn natural_conformal_map_matches_cgal_lscm() {
    assert_matches_cgal(Method::Lscm);
}

#[test]
fn area_weighted_conformal_map_matches_cgal_lscm_on_every_mesh() {
    let Some(rows) = results() else { return };
    let compared: Vec<(&Row, &Result<(f64, usize), String>)> =
        rows.iter().filter_map(|r| r.weighted.as_ref().map(|w| (r, w))).collect();
    assert!(!compared.is_empty(), "CGAL's LSCM failed on every mesh");
    for (r, weighted) in &compared {
        match weighted {
            Ok((deviation, vertex)) => {
                println!("{}: area-weighted map vs CGAL LSCM {deviation:.2e} (vertex {vertex})", r.mesh)
            }
            Err(e) => println!("{}: area-weighted map failed: {e}", r.mesh),
        }
    }
    let bad: Vec<String> = compared
        .iter()
        .filter(|(_, w)| !matches!(w, Ok((d, _)) if *d <= TOLERANCE))
        .map(|(r, w)| format!("  {}: {w:?}", r.mesh))
        .collect();
    assert!(bad.is_empty(), "{} of {} meshes beyond {TOLERANCE:e}:\n{}", bad.len(), compared.len(), bad.join("\n"));
}
