//! Floater's shape-preserving weights (Floater 1997, "Parametrization and smooth approximation
//! of surface triangulations"; course notes §2.4).
//!
//! The 1-ring of an interior vertex is flattened by a geodesic polar map (edge lengths kept,
//! angles scaled to sum to 2π). For each neighbour p_m, the origin lies in a triangle
//! (p_m, p_l, p_{l+1}) formed with two consecutive other neighbours; its barycentric
//! coordinates there are averaged over all m. The weights are positive and reproduce a planar
//! 1-ring exactly. Cost: O(d²) per vertex of degree d.

use crate::geometry::distance;
use crate::mesh::{TriMesh, NONE};

/// `(i, j, λ_ij)` for every free vertex `i` (`unknown[i] != NONE`) and neighbour `j`.
pub fn floater_weights(mesh: &TriMesh, unknown: &[u32]) -> Vec<(u32, u32, f64)> {
    let mut out = Vec::with_capacity(6 * mesh.triangle_count());
    for v in 0..mesh.vertex_count() as u32 {
        if unknown[v as usize] == NONE {
            continue;
        }
        let (ring, flat) = polar_map(mesh, v);
        let weights = averaged_barycentric(&flat);
        out.extend(ring.iter().zip(weights).map(|(&j, w)| (v, j, w)));
    }
    out
}

/// Neighbours of an interior vertex in counter-clockwise order and their polar-map positions.
fn polar_map(mesh: &TriMesh, v: u32) -> (Vec<u32>, Vec<[f64; 2]>) {
    let corner_angles = mesh.corner_angles();
    let mut ring = Vec::new();
    let mut angles = Vec::new();
    for h in mesh.outgoing_halfedges(v) {
        ring.push(mesh.head(h));
        angles.push(corner_angles[(h / 3) as usize][(h % 3) as usize]);
    }
    let total: f64 = angles.iter().sum();
    let p = mesh.points()[v as usize];
    let mut phi = 0.0f64;
    let mut flat = Vec::with_capacity(ring.len());
    for (m, &j) in ring.iter().enumerate() {
        let r = distance(p, mesh.points()[j as usize]);
        flat.push([r * phi.cos(), r * phi.sin()]);
        phi += 2.0 * std::f64::consts::PI * angles[m] / total;
    }
    (ring, flat)
}

/// Barycentric coordinates of the origin in triangle (a, b, c), or None if degenerate.
fn barycentric_of_origin(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Option<[f64; 3]> {
    let area = |p: [f64; 2], q: [f64; 2], r: [f64; 2]| (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
    let o = [0.0, 0.0];
    let total = area(a, b, c);
    if total.abs() <= f64::MIN_POSITIVE {
        return None;
    }
    Some([area(o, b, c) / total, area(a, o, c) / total, area(a, b, o) / total])
}

/// For each neighbour m, the barycentric coordinates of the origin in the triangle
/// (p_m, p_l, p_{l+1}) that contains it (the one with the least negative coordinate, which is
/// non-negative whenever such a triangle exists), averaged over m.
fn averaged_barycentric(flat: &[[f64; 2]]) -> Vec<f64> {
    let d = flat.len();
    let mut w = vec![0.0; d];
    for m in 0..d {
        let mut best: Option<(f64, usize, [f64; 3])> = None;
        for l in 0..d {
            let l1 = (l + 1) % d;
            if l == m || l1 == m {
                continue;
            }
            if let Some(bc) = barycentric_of_origin(flat[m], flat[l], flat[l1]) {
                let worst = bc[0].min(bc[1]).min(bc[2]);
                if best.is_none_or(|(b, _, _)| worst > b) {
                    best = Some((worst, l, bc));
                }
            }
        }
        if let Some((_, l, bc)) = best {
            w[m] += bc[0];
            w[l] += bc[1];
            w[(l + 1) % d] += bc[2];
        }
    }
    let total: f64 = w.iter().sum();
    w.iter().map(|x| x / total).collect()
}
