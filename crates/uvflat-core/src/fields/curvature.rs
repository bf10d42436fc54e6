//! Principal curvature directions and values per vertex by the normal-cycle curvature tensor of
//! Cohen-Steiner & Morvan 2003 (*Restricted Delaunay triangulations and normal cycle*), the
//! input field PGP uses (Ray et al. 2006, §1.2 and §4.2: "an approximation of the principal
//! directions of curvature as defined in [Cohen-Steiner and Morvan 2003]").
//!
//! For a region B around vertex v, the tensor is
//!
//! ```text
//! T(B) = 1/|B| Σ_e β(e) |e ∩ B| ê êᵀ
//! ```
//!
//! over the edges e meeting B, with β(e) the signed dihedral angle at e (positive on convex
//! edges: the angle between the two triangle normals), |e ∩ B| the length of e inside B and ê
//! its unit direction. Projected on the tangent plane of v it is a
//! symmetric 2×2 matrix with eigenvalues λ1 ≥ λ2; as Cohen-Steiner and Morvan note, the
//! eigenvectors come swapped: the eigenvector of λ1 is the direction of the *other* principal
//! curvature. So `kmax = λ1` with direction ⊥ to λ1's eigenvector, `kmin = λ2` with direction ⊥
//! to λ2's eigenvector. Curvatures are signed: positive where the surface bends away from its
//! normal (a sphere with outward normals has κ = 1/r).
//!
//! The region B is the union of the triangles incident to a set S of vertices:
//! - [`Neighbourhood::Rings`]`(k)`: S = the vertices at most `k − 1` edges from v, so `k = 1` is
//!   the star of v, `k = 2` its two-ring;
//! - [`Neighbourhood::Radius`]`(r)`: S = the vertices within graph distance r of v (shortest
//!   paths along edges, an upper bound of the geodesic distance), always containing v.
//!
//! The tangent plane of v is normal to the area-weighted mean of B's triangle normals (the
//! normal averaged over the same region as the curvature). The normals are PGP's frames too:
//! the smoothing's connection (its holonomy is the area of the normals' spherical image) and
//! the periodic solve's tangent planes. With the one-ring normal instead, a coarse or noisy
//! mesh's normals turn by 20–35° between neighbours (cow, knight), their spherical image is
//! noise, and the fields get more singular points: measured with
//! `cargo bench --bench pgp_diagnostics`, the region normal lowers the singular triangles on
//! 13 of the 15 closed meshes (knight 25 → 14%, eight 12 → 8%, cow 15.5 → 13.7%, man
//! 11.7 → 10.2%, fertility 1.8 → 1.5%) and leaves spot unchanged.
//!
//! An edge inside B counts fully, an edge on the border of B (one of its triangles outside)
//! half, and |B| is the total area of B's triangles, so the estimate is exact for the
//! integrated normal cycle of a region bounded by edges. Boundary edges of the mesh have no
//! dihedral angle and count nothing.
//!
//! Cost: O(Σ_v |B(v)|) time (in parallel over vertices), O(V + F) memory.

use super::frames::{normalized, triangle_normal, vertex_normals};
use crate::error::{Error, Result};
use crate::geometry::{cross, dot, norm, sub};
use crate::mesh::NONE;
use crate::TriMesh;
use rayon::prelude::*;

/// The region the tensor is averaged over.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Neighbourhood {
    /// Triangles incident to the vertices at most `k − 1` edges away (k ≥ 1).
    Rings(u32),
    /// Triangles incident to the vertices within this graph distance (> 0).
    Radius(f64),
}

/// Options of [`principal_curvatures`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurvatureOptions {
    /// Averaging region (default: two rings).
    pub neighbourhood: Neighbourhood,
}

impl Default for CurvatureOptions {
    fn default() -> Self {
        CurvatureOptions { neighbourhood: Neighbourhood::Rings(2) }
    }
}

/// Principal curvatures per vertex (unreferenced vertices: zeros).
#[derive(Debug, Clone)]
pub struct PrincipalCurvatures {
    /// Unit direction of the minimum curvature, tangent at the vertex.
    pub kmin_direction: Vec<[f64; 3]>,
    /// Unit direction of the maximum curvature (= normal × `kmin_direction`).
    pub kmax_direction: Vec<[f64; 3]>,
    /// Minimum (signed) curvature.
    pub kmin: Vec<f64>,
    /// Maximum (signed) curvature, ≥ `kmin`.
    pub kmax: Vec<f64>,
    /// Unit normal of each vertex's tangent plane (the mean normal of its region, module comment).
    pub normal: Vec<[f64; 3]>,
}

/// Estimates the principal curvatures of every vertex (module comment). Errors: an invalid
/// neighbourhood (0 rings, a radius that is not finite and > 0).
pub fn principal_curvatures(mesh: &TriMesh, options: &CurvatureOptions) -> Result<PrincipalCurvatures> {
    check_neighbourhood(options.neighbourhood)?;
    let normals = vertex_normals(mesh);
    let dihedral = signed_dihedral_angles(mesh);
    let area_normals = triangle_area_normals(mesh);
    let per_vertex: Vec<Estimate> = (0..mesh.vertex_count() as u32)
        .into_par_iter()
        .with_min_len(256)
        .map(|v| {
            if !mesh.is_referenced(v) {
                return Estimate::default();
            }
            let region = region_triangles(mesh, v, options.neighbourhood);
            let tensor = normal_cycle_tensor(mesh, &dihedral, &region);
            principal_frame(tensor, region_normal(&area_normals, &region, normals[v as usize]))
        })
        .collect();
    Ok(PrincipalCurvatures {
        kmin_direction: per_vertex.iter().map(|e| e.kmin_direction).collect(),
        kmax_direction: per_vertex.iter().map(|e| e.kmax_direction).collect(),
        kmin: per_vertex.iter().map(|e| e.kmin).collect(),
        kmax: per_vertex.iter().map(|e| e.kmax).collect(),
        normal: per_vertex.iter().map(|e| e.normal).collect(),
    })
}

/// Twice the area times the unit normal of every triangle.
fn triangle_area_normals(mesh: &TriMesh) -> Vec<[f64; 3]> {
    mesh.triangles()
        .iter()
        .map(|tri| {
            let p = tri.map(|w| mesh.points()[w as usize]);
            cross(sub(p[1], p[0]), sub(p[2], p[0]))
        })
        .collect()
}

/// Unit area-weighted mean normal of the triangles of `region`; `fallback` (the one-ring
/// normal) when they cancel.
fn region_normal(area_normals: &[[f64; 3]], region: &[u32], fallback: [f64; 3]) -> [f64; 3] {
    let mut sum = [0.0; 3];
    for &t in region {
        let c = area_normals[t as usize];
        sum = std::array::from_fn(|a| sum[a] + c[a]);
    }
    let n = normalized(sum);
    if n == [0.0; 3] {
        fallback
    } else {
        n
    }
}

fn check_neighbourhood(n: Neighbourhood) -> Result<()> {
    match n {
        Neighbourhood::Rings(0) => {
            Err(Error::InvalidArgument("the curvature neighbourhood needs at least 1 ring".into()))
        }
        Neighbourhood::Radius(r) if !(r.is_finite() && r > 0.0) => {
            Err(Error::InvalidArgument(format!("the curvature radius must be finite and > 0 (got {r})")))
        }
        _ => Ok(()),
    }
}

#[derive(Debug, Clone, Copy, Default)]
struct Estimate {
    kmin_direction: [f64; 3],
    kmax_direction: [f64; 3],
    kmin: f64,
    kmax: f64,
    normal: [f64; 3],
}

/// Signed dihedral angle of every half-edge's edge (0 on the boundary): the angle between the
/// normals of the two triangles, positive where the edge is convex.
pub fn signed_dihedral_angles(mesh: &TriMesh) -> Vec<f64> {
    let twin = &mesh.connectivity().twin;
    let normals: Vec<[f64; 3]> = (0..mesh.triangle_count()).map(|t| triangle_normal(mesh, t)).collect();
    (0..twin.len())
        .into_par_iter()
        .with_min_len(4096)
        .map(|h| {
            let g = twin[h];
            if g == NONE {
                return 0.0;
            }
            let (n1, n2) = (normals[h / 3], normals[g as usize / 3]);
            let e = sub(mesh.points()[mesh.head(h as u32) as usize], mesh.points()[mesh.tail(h as u32) as usize]);
            let c = cross(n1, n2);
            let angle = norm(c).atan2(dot(n1, n2));
            // Convex when n1 × n2 points along the half-edge of the first triangle.
            if dot(c, e) >= 0.0 {
                angle
            } else {
                -angle
            }
        })
        .collect()
}

/// Triangles of the averaging region of vertex `v`, sorted.
fn region_triangles(mesh: &TriMesh, v: u32, neighbourhood: Neighbourhood) -> Vec<u32> {
    let centre = match neighbourhood {
        Neighbourhood::Rings(k) => ring_vertices(mesh, v, k),
        Neighbourhood::Radius(r) => vertices_within(mesh, v, r),
    };
    let mut tris: Vec<u32> = centre.iter().flat_map(|&u| mesh.outgoing_halfedges(u).map(|h| h / 3)).collect();
    tris.sort_unstable();
    tris.dedup();
    tris
}

/// Vertices at most `k − 1` edges from `v` (breadth-first).
fn ring_vertices(mesh: &TriMesh, v: u32, k: u32) -> Vec<u32> {
    let mut seen = std::collections::HashSet::from([v]);
    let mut found = vec![v];
    let mut frontier = vec![v];
    for _ in 1..k {
        let mut next = Vec::new();
        for &u in &frontier {
            for w in one_ring(mesh, u) {
                if seen.insert(w) {
                    found.push(w);
                    next.push(w);
                }
            }
        }
        if next.is_empty() {
            break;
        }
        frontier = next;
    }
    found
}

/// Vertices within graph distance `r` of `v` (Dijkstra along edges).
fn vertices_within(mesh: &TriMesh, v: u32, r: f64) -> Vec<u32> {
    use std::cmp::Reverse;
    use std::collections::{BinaryHeap, HashMap};
    // Distances are non-negative, so their bit patterns order like the values.
    let mut best: HashMap<u32, f64> = HashMap::from([(v, 0.0)]);
    let mut heap = BinaryHeap::from([Reverse((0u64, v))]);
    let mut found = Vec::new();
    while let Some(Reverse((bits, u))) = heap.pop() {
        let d = f64::from_bits(bits);
        if d > best[&u] {
            continue;
        }
        found.push(u);
        let pu = mesh.points()[u as usize];
        for w in one_ring(mesh, u) {
            let dw = d + norm(sub(mesh.points()[w as usize], pu));
            if dw <= r && best.get(&w).is_none_or(|&old| dw < old) {
                best.insert(w, dw);
                heap.push(Reverse((dw.to_bits(), w)));
            }
        }
    }
    found
}

/// Neighbours of `u` (heads of its outgoing half-edges, plus the tail of the last incoming
/// boundary half-edge).
fn one_ring(mesh: &TriMesh, u: u32) -> impl Iterator<Item = u32> + '_ {
    mesh.outgoing_halfedges(u).flat_map(move |h| {
        let head = mesh.head(h);
        let prev = crate::mesh::prev(h);
        // The last outgoing half-edge of a boundary fan misses the neighbour across prev(h).
        let extra = if mesh.connectivity().twin[prev as usize] == NONE { Some(mesh.tail(prev)) } else { None };
        std::iter::once(head).chain(extra)
    })
}

/// `1/|B| Σ_e w_e β_e |e| ê êᵀ` over the edges of the region's triangles (w = 1 inside, ½ on
/// its border).
fn normal_cycle_tensor(mesh: &TriMesh, dihedral: &[f64], region: &[u32]) -> [[f64; 3]; 3] {
    let twin = &mesh.connectivity().twin;
    let mut t = [[0.0; 3]; 3];
    let mut area = 0.0;
    for &tri in region {
        area += mesh.geometry().area[tri as usize];
        for k in 0..3 {
            let h = 3 * tri + k;
            let g = twin[h as usize];
            if g == NONE {
                continue;
            }
            let inside = region.binary_search(&(g / 3)).is_ok();
            if inside && g < h {
                continue; // counted from the twin
            }
            let weight = if inside { 1.0 } else { 0.5 };
            let e = sub(mesh.points()[mesh.head(h) as usize], mesh.points()[mesh.tail(h) as usize]);
            let len = norm(e);
            let coefficient = weight * dihedral[h as usize] / len; // β |e| ê êᵀ = β e eᵀ / |e|
            for a in 0..3 {
                for b in 0..3 {
                    t[a][b] += coefficient * e[a] * e[b];
                }
            }
        }
    }
    if area > 0.0 {
        t.iter_mut().flatten().for_each(|x| *x /= area);
    }
    t
}

/// Principal directions and curvatures from the tensor projected on the tangent plane of `n`.
fn principal_frame(t: [[f64; 3]; 3], n: [f64; 3]) -> Estimate {
    let (t1, t2) = tangent_basis(n);
    let apply = |v: [f64; 3]| -> [f64; 3] { std::array::from_fn(|a| (0..3).map(|b| t[a][b] * v[b]).sum()) };
    let (a, b, d) = (dot(t1, apply(t1)), dot(t1, apply(t2)), dot(t2, apply(t2)));
    let mean = 0.5 * (a + d);
    let radius = (0.5 * (a - d)).hypot(b);
    let (lambda1, lambda2) = (mean + radius, mean - radius);
    let psi = 0.5 * (2.0 * b).atan2(a - d);
    // e1: eigenvector of λ1 (the minimum curvature direction, swapped as explained above).
    let e1 = normalized([0, 1, 2].map(|k| psi.cos() * t1[k] + psi.sin() * t2[k]));
    let e2 = cross(n, e1);
    Estimate { kmin_direction: e1, kmax_direction: e2, kmin: lambda2, kmax: lambda1, normal: n }
}

/// An orthonormal basis of the plane orthogonal to the unit vector `n`.
pub fn tangent_basis(n: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let helper = if n[0].abs() < 0.6 { [1.0, 0.0, 0.0] } else { [0.0, 1.0, 0.0] };
    let t1 = normalized(cross(helper, n));
    (t1, cross(n, t1))
}
