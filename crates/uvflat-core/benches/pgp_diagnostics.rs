//! Diagnostics of PGP's singularities on one mesh (Ray et al. 2006 §3.2, §4.2): how many
//! singularities the raw and the smoothed cross fields have (± counts of the quarter indices),
//! how many singular points and triangles the parameterization has and of which kind (open
//! path, negative area, tiny negative area), the norms ‖U‖ after the Newton refinement, the
//! share of the L2 stretch carried by the worst triangles, and the quality columns of the
//! table of docs/methods/pgp.md. It produced the figures of that page's "Why the rate is high" bullets.
//!
//!     cargo bench --bench pgp_diagnostics -- tests/data/meshes/closed_g0_cow.obj.gz
//!
//! Environment (all optional): CC=1 curl correction; RHO=r smoothing ρ (default 0.8);
//! RINGS=k or RADIUS=f (× mean edge length) curvature neighbourhood; NOSMOOTH=1 no smoothing;
//! EPS / IT penalty ε and iterations of the periodic Newton solve; SEPS / SIT the same for the
//! smoothing; FIELDW=uniform|paper|CAP fitting weights (uniform, eq. 21's |kmax/kmin|, or the
//! default anisotropy capped at CAP); PTS=1 local edge length and normal deviation at the
//! singular points; OUT=1 the worst regular triangles by stretch; PERIOD=p sets ω to one period
//! per p mean edge lengths (default 10); NOUNTANGLE=1 keeps Algorithm 1's corners (no
//! untangling); FEATURE_PERIODS=c the feature-adaptive density (default 3, 0 = the paper's single
//! ω). It also prints what the untangling did, the sizes of the edge-connected
//! groups of negative triangles left, and the triangles around which the rotation
//! matching of eq. 13 does not close (the field's singular triangles as the periodic solve
//! sees them) and where the negative (θ, φ) triangles lie (needles, next to singular points).
//! A measuring tool, not part of the library: it panics with a message on bad arguments.
use std::path::Path;
use uvflat_core::fields::curvature::{principal_curvatures, CurvatureOptions, Neighbourhood};
use uvflat_core::fields::indices::face_field_indices;
use uvflat_core::fields::smoothing::{face_directions, mean_edge_length, Symmetry};
use uvflat_core::methods::pgp::quality::quality;
use uvflat_core::methods::pgp::singularities::signed_area2;
use uvflat_core::methods::pgp::{pgp, PgpOptions};
use uvflat_core::progress::Progress;
use uvflat_core::TriMesh;

fn count(ix: &[f64]) -> (usize, usize) {
    let pos = ix.iter().filter(|&&i| (4.0 * i).round() > 0.0).count();
    let neg = ix.iter().filter(|&&i| (4.0 * i).round() < 0.0).count();
    (pos, neg)
}

/// Minimum, quartiles and maximum of `values`, printed with `digits` decimals.
fn quartiles(mut values: Vec<f64>, digits: usize) -> String {
    values.sort_by(f64::total_cmp);
    (0..5).map(|f| format!("{:.digits$}", values[(f * (values.len() - 1)) / 4])).collect::<Vec<_>>().join(" ")
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let file = args.iter().skip(1).find(|a| !a.starts_with("--")).expect("usage: pgp_diagnostics MESH.obj");
    let cc = std::env::var("CC").is_ok();
    let rings: u32 = std::env::var("RINGS").ok().and_then(|s| s.parse().ok()).unwrap_or(2);
    let rho: f64 = std::env::var("RHO").ok().and_then(|s| s.parse().ok()).unwrap_or(0.8);
    let nosmooth = std::env::var("NOSMOOTH").is_ok();
    let obj = uvflat_core::io::obj::read_obj(Path::new(file)).expect("readable OBJ");
    let mesh = TriMesh::new(&obj.positions, &obj.triangles).expect("valid mesh");
    let l = mean_edge_length(&mesh);
    let mut opts = PgpOptions { curl_correction: cc, ..PgpOptions::default() };
    if let Ok(c) = std::env::var("FEATURE_PERIODS") {
        opts.feature_periods = c.parse().expect("FEATURE_PERIODS is a number");
    }
    if let Ok(c) = std::env::var("PAIRS") {
        opts.pair_periods = c.parse().expect("PAIRS is a number");
    }
    opts.curvature = CurvatureOptions { neighbourhood: Neighbourhood::Rings(rings) };
    if let Ok(f) = std::env::var("RADIUS") {
        opts.curvature = CurvatureOptions { neighbourhood: Neighbourhood::Radius(f.parse::<f64>().unwrap() * l) };
    }
    if let Some(s) = opts.smoothing.as_mut() {
        s.rho = rho;
    }
    if nosmooth {
        opts.smoothing = None;
    }
    if let Ok(e) = std::env::var("EPS") {
        opts.newton.epsilon = e.parse().unwrap();
    }
    if let Ok(e) = std::env::var("SEPS") {
        opts.smoothing.as_mut().unwrap().newton.epsilon = e.parse().unwrap();
    }
    if let Ok(e) = std::env::var("SIT") {
        opts.smoothing.as_mut().unwrap().newton.max_iterations = e.parse().unwrap();
    }
    if let Ok(e) = std::env::var("IT") {
        opts.newton.max_iterations = e.parse().unwrap();
    }
    if let Ok(d) = std::env::var("DISLOC") {
        opts.dislocation_periods = d.parse().unwrap();
    }
    if std::env::var("NOUNTANGLE").is_ok() {
        opts.untangle = false;
    }
    if let Ok(e) = std::env::var("PERIOD") {
        opts.omega = Some(std::f64::consts::TAU / (e.parse::<f64>().unwrap() * l));
    }
    let start = std::time::Instant::now();
    let curv = principal_curvatures(&mesh, &opts.curvature).unwrap();
    let raw =
        face_field_indices(&mesh, &face_directions(&mesh, &curv.normal, &curv.kmax_direction, Symmetry::Cross), 4);
    if let Ok(mode) = std::env::var("FIELDW") {
        // Smooth here with modified anisotropy weights, then run PGP on the smoothed field.
        use uvflat_core::fields::smoothing::{anisotropy_weights, smooth_field};
        let w = anisotropy_weights(&mesh, &curv);
        let eta = 1e-2 / l;
        let target: Vec<f64> = (0..mesh.vertex_count())
            .map(|v| {
                let (a, b) = (curv.kmax[v].abs(), curv.kmin[v].abs());
                match mode.as_str() {
                    "uniform" => 1.0,
                    "paper" => (a.max(b) + eta) / (a.min(b) + eta),
                    m => w[v].min(m.parse::<f64>().unwrap()),
                }
            })
            .collect();
        // kmin = 1, kmax = target + 1 (+ eta correction) gives (kmax+η)/(kmin+η) − 1 = target.
        let mut c2 = curv.clone();
        for v in 0..mesh.vertex_count() {
            c2.kmin[v] = 1.0;
            c2.kmax[v] = (target[v] + 1.0) * (1.0 + eta) - eta;
        }
        let sopts = opts.smoothing.clone().unwrap();
        let (f, _) = smooth_field(&mesh, &c2, &curv.kmax_direction, &sopts, &mut Progress::none(), (0.0, 1.0)).unwrap();
        opts.field = Some(f);
        opts.smoothing = None;
    }
    if let Ok(fr) = std::env::var("FIELD_RINGS") {
        // The field smoothed on curvatures of FIELD_RINGS rings; normals and density from RINGS.
        use uvflat_core::fields::smoothing::smooth_field;
        let copts = CurvatureOptions { neighbourhood: Neighbourhood::Rings(fr.parse().unwrap()) };
        let c2 = principal_curvatures(&mesh, &copts).unwrap();
        let sopts = opts.smoothing.clone().unwrap();
        let (f, _) = smooth_field(&mesh, &c2, &c2.kmax_direction, &sopts, &mut Progress::none(), (0.0, 1.0)).unwrap();
        opts.field = Some(f);
        opts.smoothing = None;
    }
    if std::env::var("HOLONOMY").is_ok() {
        // Triangles whose holonomy alone forces an open triangle (|Ω_T| > 3π/4), by |Ω_T| bins.
        use uvflat_core::methods::pgp::forced::{has_antipodal_edge, triangle_holonomy};
        let normals = principal_curvatures(&mesh, &opts.curvature).unwrap().normal;
        let mut bins = [0usize; 5];
        let mut antipodal = 0;
        for t in 0..mesh.triangle_count() {
            if has_antipodal_edge(&mesh, &normals, t) {
                antipodal += 1;
                continue;
            }
            let o = triangle_holonomy(&mesh, &normals, t).abs().to_degrees();
            bins[[45.0, 90.0, 135.0, 180.1].iter().position(|&b| o < b).unwrap_or(4)] += 1;
        }
        println!("  |holonomy| bins <45 <90 <135 >=135: {:?} antipodal {antipodal}", &bins[..4]);
    }
    let r = pgp(&mesh, &opts, &mut Progress::none()).unwrap();
    let secs = start.elapsed().as_secs_f64();
    println!("  untangled: {:?}", r.untangled);
    println!("  pairs: {:?}", r.pairs);
    println!("  dislocations: {:?}", r.dislocations);
    let smooth = face_field_indices(&mesh, &face_directions(&mesh, &r.normals, &r.field, Symmetry::Cross), 4);
    let q = quality(&mesh, &r.param, &r.singularities, &r.normals, &r.field, r.omega).unwrap();
    let s = &r.singularities;
    let pts = s.singular_points();
    let ppos = pts.iter().filter(|p| p.1 > 0.0).count();
    let (mut open, mut neg, mut both, mut tiny) = (0, 0, 0, 0);
    for &t in &s.triangles {
        let t = t as usize;
        let a = signed_area2(&r.param.coords[t]);
        let o = r.param.open[t];
        let expected = 2.0 * mesh.geometry().area[t] * r.omega * r.omega;
        if o && a <= 0.0 {
            both += 1
        } else if o {
            open += 1
        } else {
            neg += 1;
            if a.abs() < 1e-3 * expected {
                tiny += 1
            }
        }
    }
    let small_u = r
        .unknowns
        .iter()
        .filter(|x| (x[0] * x[0] + x[1] * x[1]).sqrt() < 0.5 || (x[2] * x[2] + x[3] * x[3]).sqrt() < 0.5)
        .count();
    // Edge-length distribution: fraction of edges longer than 2.5 mean lengths (quarter period).
    let mut lens: Vec<f64> = Vec::new();
    for t in mesh.triangles() {
        for k in 0..3 {
            let (a, b) = (mesh.points()[t[k] as usize], mesh.points()[t[(k + 1) % 3] as usize]);
            lens.push(uvflat_core::geometry::norm(uvflat_core::geometry::sub(a, b)) / l);
        }
    }
    let long = lens.iter().filter(|&&x| x > 2.5).count() as f64 / lens.len() as f64;
    // Stretch outliers over the triangles quality() calls regular.
    let mut touched = vec![false; mesh.vertex_count()];
    for &v in s.vertices.iter().chain(s.edges.iter().flatten()) {
        touched[v as usize] = true;
    }
    let mut sing = vec![false; mesh.triangle_count()];
    for &t in &s.triangles {
        sing[t as usize] = true;
    }
    // (triangle, σ1, σ2) of (θ, φ)/ω → surface on the triangles quality() measures.
    let measured: Vec<(usize, f64, f64)> = (0..mesh.triangle_count())
        .filter(|&t| !sing[t] && !mesh.triangles()[t].iter().any(|&v| touched[v as usize]))
        .filter_map(|t| {
            let p = mesh.triangles()[t].map(|v| mesh.points()[v as usize]);
            let qq = r.param.coords[t].map(|c| [c[0] / r.omega, c[1] / r.omega]);
            uvflat_core::metrics::per_triangle_singular_values(p, qq).map(|(s1, s2)| (t, s1, s2))
        })
        .collect();
    let stretch_term = |&(t, s1, s2): &(usize, f64, f64)| mesh.geometry().area[t] * 0.5 * (s1 * s1 + s2 * s2);
    // (A σ² term, area, uv area)
    let per: Vec<(f64, f64, f64)> = measured
        .iter()
        .map(|m| (stretch_term(m), mesh.geometry().area[m.0], mesh.geometry().area[m.0] / (m.1 * m.2)))
        .collect();
    let mut nu: Vec<f64> = r.unknowns.iter().map(|x| (x[0] * x[0] + x[1] * x[1]).sqrt()).collect();
    nu.sort_by(|a, b| a.partial_cmp(b).unwrap());
    println!(
        "  |U| quantiles: {:.3e} {:.3e} {:.3e} {:.3e} {:.3e}",
        nu[0],
        nu[nu.len() / 10],
        nu[nu.len() / 2],
        nu[9 * nu.len() / 10],
        nu[nu.len() - 1]
    );
    // Singular triangles by 3D shape and edge length.
    let mut long_sing = 0;
    for &t in &s.triangles {
        let tri = mesh.triangles()[t as usize];
        let mx = (0..3)
            .map(|k| {
                uvflat_core::geometry::norm(uvflat_core::geometry::sub(
                    mesh.points()[tri[k] as usize],
                    mesh.points()[tri[(k + 1) % 3] as usize],
                ))
            })
            .fold(0.0, f64::max);
        if mx > 2.5 * l {
            long_sing += 1;
        }
    }
    println!("  singular triangles with an edge > 2.5 l: {long_sing}");
    if std::env::var("PTS").is_ok() {
        // Local mean edge length / l and max angle between vertex normal and ring face normals, at singular points vs all.
        let stat = |v: u32| -> (f64, f64) {
            let mut le = 0.0;
            let mut n = 0.0;
            let mut dev: f64 = 0.0;
            for h in mesh.outgoing_halfedges(v) {
                le += uvflat_core::geometry::norm(uvflat_core::geometry::sub(
                    mesh.points()[mesh.head(h) as usize],
                    mesh.points()[v as usize],
                ));
                n += 1.0;
                let fnrm = uvflat_core::fields::frames::triangle_normal(&mesh, (h / 3) as usize);
                dev = dev
                    .max(uvflat_core::geometry::dot(fnrm, r.normals[v as usize]).clamp(-1.0, 1.0).acos().to_degrees());
            }
            (le / n / l, dev)
        };
        let sp: Vec<(f64, f64)> = pts.iter().map(|p| stat(p.0)).collect();
        let all: Vec<(f64, f64)> = (0..mesh.vertex_count() as u32).map(stat).collect();
        let edge = |v: &[(f64, f64)]| quartiles(v.iter().map(|x| x.0).collect(), 2);
        println!("  local edge/l quartiles: singular {}  all {}", edge(&sp), edge(&all));
        let normal = |v: &[(f64, f64)]| quartiles(v.iter().map(|x| x.1).collect(), 1);
        println!("  normal dev deg quartiles: singular {}  all {}", normal(&sp), normal(&all));
    }
    if std::env::var("OUT").is_ok() {
        // The 10 worst regular triangles: σ1, σ2, uv area / expected, whether a vertex is shared with a singular triangle.
        let mut near_t = vec![false; mesh.vertex_count()];
        for &t in &s.triangles {
            for v in mesh.triangles()[t as usize] {
                near_t[v as usize] = true;
            }
        }
        let mut worst: Vec<(f64, usize, f64, f64)> =
            measured.iter().map(|m| (stretch_term(m), m.0, m.1, m.2)).collect();
        worst.sort_by(|a, b| b.0.partial_cmp(&a.0).unwrap());
        let mut nadj = 0;
        for w in worst.iter().take(worst.len() / 1000 + 1) {
            if mesh.triangles()[w.1].iter().any(|&v| near_t[v as usize]) {
                nadj += 1;
            }
        }
        for w in worst.iter().take(5) {
            let adj = mesh.triangles()[w.1].iter().any(|&v| near_t[v as usize]);
            println!(
                "  worst t {} term {:.3e} s1 {:.2} s2 {:.2} adjacent_to_singular_triangle {}",
                w.1, w.0, w.2, w.3, adj
            );
        }
        println!("  of the top 0.1%: {} of {} share a vertex with a singular triangle", nadj, worst.len() / 1000 + 1);
    }
    let tot: f64 = per.iter().map(|x| x.0).sum();
    let a3: f64 = per.iter().map(|x| x.1).sum();
    let auv: f64 = per.iter().map(|x| x.2).sum();
    let mut terms: Vec<f64> = per.iter().map(|x| x.0).collect();
    terms.sort_by(|a, b| b.partial_cmp(a).unwrap());
    let top = terms.iter().take((terms.len() / 1000).max(1)).sum::<f64>() / tot;
    let k = (terms.len() / 100).max(1);
    let trimmed = ((tot - terms.iter().take(k).sum::<f64>()) / a3).sqrt() / (a3 / auv).sqrt();
    println!("  stretch: top0.1% share {:.3} ; without top1% {:.3}; auv/a3 {:.3}", top, trimmed, auv / a3);
    // Triangles around which the rotation matching of eq. 13 does not close (the field's
    // singular triangles in the periodic solve's own terms).
    use uvflat_core::fields::frames::match_rotation;
    let unclosed = (0..mesh.triangle_count())
        .filter(|&t| {
            let tri = mesh.triangles()[t].map(|v| v as usize);
            let m = |a: usize, b: usize| {
                match_rotation(r.field[tri[a]], r.normals[tri[a]], r.normals[tri[b]], r.field[tri[b]]) as u32
            };
            (m(0, 1) + m(1, 2) + m(2, 0)) % 4 != 0
        })
        .count();
    println!("  matching-singular triangles: {unclosed}");
    {
        // Negative triangles: needle (< 5°), touching a singular point, any corner |U| or |V| < 0.5, within 2 rings of a singular point.
        let mut sp = vec![0u8; mesh.vertex_count()];
        for p in s.singular_points() {
            sp[p.0 as usize] = 1;
        }
        for _ in 0..2 {
            let prev = sp.clone();
            for t in mesh.triangles() {
                if t.iter().any(|&v| prev[v as usize] > 0) {
                    for &v in t {
                        if sp[v as usize] == 0 {
                            sp[v as usize] = 2;
                        }
                    }
                }
            }
        }
        let angles = mesh.corner_angles();
        let (mut n, mut needle, mut touch, mut small, mut near) = (0, 0, 0, 0, 0);
        for &t in &s.triangles {
            let t = t as usize;
            if r.param.open[t] || signed_area2(&r.param.coords[t]) > 0.0 {
                continue;
            }
            n += 1;
            let tri = mesh.triangles()[t];
            if angles[t].iter().any(|&a| a < 5f64.to_radians()) {
                needle += 1;
            }
            if tri.iter().any(|&v| sp[v as usize] == 1) {
                touch += 1;
            }
            if tri.iter().any(|&v| sp[v as usize] > 0) {
                near += 1;
            }
            if tri.iter().any(|&v| {
                let x = r.unknowns[v as usize];
                (x[0] * x[0] + x[1] * x[1]).sqrt() < 0.5 || (x[2] * x[2] + x[3] * x[3]).sqrt() < 0.5
            }) {
                small += 1;
            }
        }
        // Connected groups of negative triangles (sharing an edge) and their sizes.
        let negative: Vec<bool> =
            (0..mesh.triangle_count()).map(|t| !r.param.open[t] && signed_area2(&r.param.coords[t]) <= 0.0).collect();
        let twin = &mesh.connectivity().twin;
        let mut seen = vec![false; mesh.triangle_count()];
        let mut sizes: Vec<usize> = Vec::new();
        for t0 in 0..mesh.triangle_count() {
            if !negative[t0] || seen[t0] {
                continue;
            }
            let (mut stack, mut size) = (vec![t0], 0);
            seen[t0] = true;
            while let Some(t) = stack.pop() {
                size += 1;
                for k in 0..3 {
                    let h = twin[3 * t + k];
                    if h != u32::MAX && negative[(h / 3) as usize] && !seen[(h / 3) as usize] {
                        seen[(h / 3) as usize] = true;
                        stack.push((h / 3) as usize);
                    }
                }
            }
            sizes.push(size);
        }
        let hist: Vec<usize> = [1, 2, 3, 4, 6, 10, usize::MAX]
            .windows(2)
            .map(|w| sizes.iter().filter(|&&z| z >= w[0] && z < w[1]).count())
            .collect();
        println!("  negative groups {} sizes [1,2,3,4-5,6-9,10+] {:?}", sizes.len(), hist);
        println!("  negative triangles {n}: needle {needle} touch-singular-point {touch} within-2-rings {near} small-U {small}");
    }
    let (rp, rn) = count(&raw);
    let (sp, sn) = count(&smooth);
    println!(
        "{:<34} F={:>6} rawfield +{}/-{} smoothfield +{}/-{} param_pts {} (+{}/-{}) singT {:.2}% [open {} neg {} both {} tinyneg {}] |X|<.5 {} long>2.5l {:.4} stretch {:.3} shear {:.3} align {:.1} solve it {} clamped {} conv {} g {:.1e} smooth it {:?} conv {:?} {:.1}s",
        Path::new(file).file_name().unwrap().to_string_lossy(),
        mesh.triangle_count(),
        rp, rn, sp, sn,
        pts.len(), ppos, pts.len() - ppos,
        100.0 * q.singular_triangle_fraction,
        open, neg, both, tiny, small_u, long,
        q.stretch, q.shear, q.alignment_degrees,
        r.solve.iterations, r.solve.clamped_iterations, r.solve.converged, r.solve.final_gradient,
        r.smoothing.map(|s| s.iterations), r.smoothing.map(|s| s.converged),
        secs
    );
}
