//! Triangle meshes sampled from parametric surfaces with known differential geometry, for the
//! PGP and QuadCover tests: cylinder, torus, icosphere. Every mesh is counter-clockwise
//! around its outward normal.

use std::f64::consts::TAU;

/// Flat positions and triangles.
pub struct Sampled {
    pub positions: Vec<f64>,
    pub triangles: Vec<u32>,
    /// Parameter values (u, v) of each vertex (empty for the icosphere).
    pub params: Vec<[f64; 2]>,
}

/// Quads of a `nu × nv` grid split along alternating diagonals; `wrap_u`/`wrap_v` close the
/// grid in that direction. Vertex (i, j) has index `j * cols + i`.
pub fn grid_triangles(nu: usize, nv: usize, wrap_u: bool, wrap_v: bool) -> Vec<u32> {
    let cols = if wrap_u { nu } else { nu + 1 };
    let rows = if wrap_v { nv } else { nv + 1 };
    let id = |i: usize, j: usize| ((j % rows) * cols + (i % cols)) as u32;
    let mut t = Vec::new();
    for j in 0..nv {
        for i in 0..nu {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if (i + j) % 2 == 0 {
                t.extend([a, b, c, a, c, d]);
            } else {
                t.extend([a, b, d, b, c, d]);
            }
        }
    }
    t
}

/// Open cylinder of radius `r` and height `h` around the z axis: u around (nu samples), v
/// along the axis (nv quads). Outward normals.
pub fn cylinder(r: f64, h: f64, nu: usize, nv: usize) -> Sampled {
    let mut positions = Vec::new();
    let mut params = Vec::new();
    for j in 0..=nv {
        for i in 0..nu {
            let (u, v) = (TAU * i as f64 / nu as f64, h * j as f64 / nv as f64);
            positions.extend([r * u.cos(), r * u.sin(), v]);
            params.push([u, v]);
        }
    }
    Sampled { positions, triangles: grid_triangles(nu, nv, true, false), params }
}

/// Torus `((R + r cos v) cos u, (R + r cos v) sin u, r sin v)`, `nu × nv` samples. Outward
/// normals (∂p/∂u × ∂p/∂v points away from the tube's centre line).
pub fn torus(big_r: f64, r: f64, nu: usize, nv: usize) -> Sampled {
    let mut positions = Vec::new();
    let mut params = Vec::new();
    for j in 0..nv {
        for i in 0..nu {
            let (u, v) = (TAU * i as f64 / nu as f64, TAU * j as f64 / nv as f64);
            let rho = big_r + r * v.cos();
            positions.extend([rho * u.cos(), rho * u.sin(), r * v.sin()]);
            params.push([u, v]);
        }
    }
    Sampled { positions, triangles: grid_triangles(nu, nv, true, true), params }
}

/// Icosahedron subdivided `levels` times (each triangle into four), projected on the sphere of
/// radius `r`.
pub fn icosphere(r: f64, levels: usize) -> Sampled {
    let g = (1.0 + 5f64.sqrt()) / 2.0;
    let mut points: Vec<[f64; 3]> = vec![
        [-1.0, g, 0.0],
        [1.0, g, 0.0],
        [-1.0, -g, 0.0],
        [1.0, -g, 0.0],
        [0.0, -1.0, g],
        [0.0, 1.0, g],
        [0.0, -1.0, -g],
        [0.0, 1.0, -g],
        [g, 0.0, -1.0],
        [g, 0.0, 1.0],
        [-g, 0.0, -1.0],
        [-g, 0.0, 1.0],
    ];
    let mut tris: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut midpoint = std::collections::HashMap::new();
        let mut mid = |a: u32, b: u32, points: &mut Vec<[f64; 3]>| -> u32 {
            *midpoint.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (p, q) = (points[a as usize], points[b as usize]);
                points.push([(p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0, (p[2] + q[2]) / 2.0]);
                (points.len() - 1) as u32
            })
        };
        let mut next = Vec::new();
        for [a, b, c] in tris {
            let (ab, bc, ca) = (mid(a, b, &mut points), mid(b, c, &mut points), mid(c, a, &mut points));
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        tris = next;
    }
    let positions = points
        .iter()
        .flat_map(|p| {
            let l = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            [r * p[0] / l, r * p[1] / l, r * p[2] / l]
        })
        .collect();
    Sampled { positions, triangles: tris.into_iter().flatten().collect(), params: Vec::new() }
}
