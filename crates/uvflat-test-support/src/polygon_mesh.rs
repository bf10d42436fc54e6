//! Checks of a polygon mesh produced from a triangle mesh (PGP's and QuadCover's quad-dominant
//! remeshes): manifoldness, and how much of the surface it covers and how closely.

use uvflat_core::geometry::{cross, dot, norm, sub};
use uvflat_core::methods::pgp::PolygonMesh;
use uvflat_core::TriMesh;

/// What [`check_remesh`] measured.
#[derive(Debug)]
pub struct RemeshReport {
    pub quad_fraction: f64,
    /// Output area over input area (fan-triangulated polygons).
    pub area_ratio: f64,
    /// Largest distance from an output vertex to the input surface, over the bounding-box
    /// diagonal.
    pub max_distance: f64,
    /// Mean |corner angle − 90°| of the quads (degrees).
    pub quad_angle_error: f64,
}

/// Asserts that `remesh` is an oriented manifold polygon mesh (every edge in at most two
/// faces, once each way, and in two when the input is closed; one fan of faces around every
/// vertex; no repeated corner; no doublet vertex) and measures it.
pub fn check_remesh(file: &str, mesh: &TriMesh, remesh: &PolygonMesh) -> RemeshReport {
    let closed = mesh.boundary_loops().is_empty();
    let n = remesh.positions.len();
    assert!(!remesh.face_sizes.is_empty(), "{file}: empty remesh");
    let mut directed = std::collections::HashSet::new();
    let mut wedges: Vec<Vec<(u32, u32)>> = vec![Vec::new(); n];
    for face in remesh.faces() {
        assert!(face.len() >= 3, "{file}: face {face:?}");
        let distinct: std::collections::HashSet<u32> = face.iter().copied().collect();
        assert_eq!(distinct.len(), face.len(), "{file}: repeated corner in {face:?}");
        for i in 0..face.len() {
            let (a, b) = (face[i], face[(i + 1) % face.len()]);
            assert!((a as usize) < n && (b as usize) < n, "{file}: index out of range in {face:?}");
            assert!(directed.insert((a, b)), "{file}: edge {a} -> {b} in two faces");
            wedges[b as usize].push((a, face[(i + 2) % face.len()]));
        }
    }
    for &(a, b) in &directed {
        assert!(!closed || directed.contains(&(b, a)), "{file}: edge {a} -> {b} has no opposite (open surface)");
    }
    for (v, w) in wedges.iter().enumerate() {
        assert!(!w.is_empty(), "{file}: vertex {v} in no face");
        assert_eq!(fans(w), 1, "{file}: vertex {v} has {} fans (non-manifold)", fans(w));
        // A doublet: two faces sharing both edges of a vertex fold onto each other there, and
        // fan-triangulating readers (uvflat's own) get one triangle twice.
        let doublet = w.len() == 2 && w[0] == (w[1].1, w[1].0);
        assert!(!doublet, "{file}: vertex {v} is a doublet (two faces sharing both its edges)");
    }
    RemeshReport {
        quad_fraction: remesh.quad_count() as f64 / remesh.face_sizes.len() as f64,
        area_ratio: polygon_area(remesh) / surface_area(mesh),
        max_distance: max_distance_to_surface(mesh, &remesh.positions) / bbox_diagonal(mesh.points()),
        quad_angle_error: quad_angle_error(remesh),
    }
}

/// Number of fans (open chains or cycles) formed by a vertex's corners `(previous, next)`: a
/// corner continues into the one whose previous neighbour is its next.
fn fans(wedges: &[(u32, u32)]) -> usize {
    let by_previous: std::collections::HashMap<u32, usize> = wedges.iter().enumerate().map(|(i, w)| (w.0, i)).collect();
    assert_eq!(by_previous.len(), wedges.len(), "two corners share an edge on the same side");
    let nexts: std::collections::HashSet<u32> = wedges.iter().map(|w| w.1).collect();
    let mut seen = vec![false; wedges.len()];
    let mut count = 0;
    // Chains start where no corner continues in; then what is left are cycles.
    let chain_starts = (0..wedges.len()).filter(|&i| !nexts.contains(&wedges[i].0));
    for start in chain_starts.chain(0..wedges.len()) {
        if seen[start] {
            continue;
        }
        count += 1;
        let mut i = Some(start);
        while let Some(k) = i.filter(|&k| !seen[k]) {
            seen[k] = true;
            i = by_previous.get(&wedges[k].1).copied();
        }
    }
    count
}

fn triangle_area(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    0.5 * norm(cross(sub(b, a), sub(c, a)))
}

pub fn surface_area(mesh: &TriMesh) -> f64 {
    let p = mesh.points();
    mesh.triangles().iter().map(|t| triangle_area(p[t[0] as usize], p[t[1] as usize], p[t[2] as usize])).sum()
}

fn polygon_area(remesh: &PolygonMesh) -> f64 {
    let p = &remesh.positions;
    remesh
        .faces()
        .map(|f| {
            (1..f.len() - 1)
                .map(|i| triangle_area(p[f[0] as usize], p[f[i] as usize], p[f[i + 1] as usize]))
                .sum::<f64>()
        })
        .sum()
}

fn quad_angle_error(remesh: &PolygonMesh) -> f64 {
    let p = &remesh.positions;
    let (mut sum, mut count) = (0.0, 0usize);
    for f in remesh.faces().filter(|f| f.len() == 4) {
        for i in 0..4 {
            let (a, b) =
                (sub(p[f[(i + 3) % 4] as usize], p[f[i] as usize]), sub(p[f[(i + 1) % 4] as usize], p[f[i] as usize]));
            let angle = (dot(a, b) / (norm(a) * norm(b))).clamp(-1.0, 1.0).acos().to_degrees();
            sum += (angle - 90.0).abs();
            count += 1;
        }
    }
    sum / count.max(1) as f64
}

pub fn bbox_diagonal(points: &[[f64; 3]]) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    norm(sub(hi, lo))
}

/// Largest distance from `queries` to the triangles of `mesh`, with the triangles bucketed in
/// a uniform grid (cells about the mean edge length; rings searched until the nearest found
/// distance is below the searched radius).
pub fn max_distance_to_surface(mesh: &TriMesh, queries: &[[f64; 3]]) -> f64 {
    let p = mesh.points();
    let tris = mesh.triangles();
    let cell = (surface_area(mesh) / tris.len() as f64).sqrt() * 2.0;
    let key = |x: [f64; 3]| [(x[0] / cell).floor() as i64, (x[1] / cell).floor() as i64, (x[2] / cell).floor() as i64];
    let mut grid: std::collections::HashMap<[i64; 3], Vec<usize>> = std::collections::HashMap::new();
    for (t, tri) in tris.iter().enumerate() {
        let q = tri.map(|v| p[v as usize]);
        let lo = key(std::array::from_fn(|k| q[0][k].min(q[1][k]).min(q[2][k])));
        let hi = key(std::array::from_fn(|k| q[0][k].max(q[1][k]).max(q[2][k])));
        for i in lo[0]..=hi[0] {
            for j in lo[1]..=hi[1] {
                for k in lo[2]..=hi[2] {
                    grid.entry([i, j, k]).or_default().push(t);
                }
            }
        }
    }
    let nearest = |x: [f64; 3]| {
        let c = key(x);
        let mut best = f64::INFINITY;
        for ring in 0..64i64 {
            for i in -ring..=ring {
                for j in -ring..=ring {
                    for k in -ring..=ring {
                        if i.abs().max(j.abs()).max(k.abs()) != ring {
                            continue;
                        }
                        for &t in grid.get(&[c[0] + i, c[1] + j, c[2] + k]).into_iter().flatten() {
                            let q = tris[t].map(|v| p[v as usize]);
                            best = best.min(point_triangle_distance(x, q));
                        }
                    }
                }
            }
            if best <= ring as f64 * cell {
                break;
            }
        }
        best
    };
    queries.iter().map(|&x| nearest(x)).fold(0.0, f64::max)
}

/// Distance from `x` to triangle `q` (closest point by regions: vertices, edges, interior).
fn point_triangle_distance(x: [f64; 3], q: [[f64; 3]; 3]) -> f64 {
    let n = cross(sub(q[1], q[0]), sub(q[2], q[0]));
    let inside = (0..3).all(|i| dot(cross(sub(q[(i + 1) % 3], q[i]), sub(x, q[i])), n) >= 0.0);
    if inside && norm(n) > 0.0 {
        return (dot(sub(x, q[0]), n) / norm(n)).abs();
    }
    (0..3)
        .map(|i| {
            let (a, b) = (q[i], q[(i + 1) % 3]);
            let e = sub(b, a);
            let s = if dot(e, e) > 0.0 { (dot(sub(x, a), e) / dot(e, e)).clamp(0.0, 1.0) } else { 0.0 };
            norm(sub(x, [a[0] + s * e[0], a[1] + s * e[1], a[2] + s * e[2]]))
        })
        .fold(f64::INFINITY, f64::min)
}
