//! The mesh of one PGP chart and its mean-value map (Ray et al. 2006, §3.4: a chart with
//! singularities is re-parameterized with its boundary fixed; Floater 2003, mean value
//! coordinates, used through [`crate::methods::barycentric::fixed_boundary_map`]). Shared by the
//! chart parameterization ([`super::charts`]) and the split of an N-gon chart into quads
//! ([`super::split`]).
//!
//! Cost: O(T) to renumber T triangles (corners joined by union-find across shared edges), one
//! sparse solve for the map.

use crate::boundary::{BoundaryShape, Distribution};
use crate::mesh::TriMesh;
use crate::methods::barycentric::{fixed_boundary_map, FixedBoundaryOptions, Weights};
use std::collections::HashMap;
use uvflat_sparse::union_find::find;

/// Floater's mean value map of triangles `tris` (vertex ids mapped to positions by `point`)
/// with every boundary vertex fixed at `boundary(v)`, per corner; `None` when a boundary
/// vertex has no position, the triangles are not a disk, or the result is not finite.
pub(super) fn mean_value_map(
    tris: &[[u32; 3]],
    point: &dyn Fn(u32) -> [f64; 3],
    boundary: &dyn Fn(u32) -> Option<[f64; 2]>,
) -> Option<Vec<[[f64; 2]; 3]>> {
    let (chart, global) = local_mesh(tris, point)?;
    let mut given = Vec::new();
    for lp in chart.boundary_loops() {
        for &v in lp {
            given.push((v, boundary(global[v as usize])?));
        }
    }
    let options = FixedBoundaryOptions {
        weights: Weights::MeanValue,
        shape: BoundaryShape::Given(given),
        distribution: Distribution::ChordLength,
    };
    let uv = fixed_boundary_map(&chart, &options).ok()?;
    if uv.iter().any(|p| !p[0].is_finite() || !p[1].is_finite()) {
        return None;
    }
    Some(chart.triangles().iter().map(|t| t.map(|v| uv[v as usize])).collect())
}

/// The triangles `tris` renumbered as a mesh of their own, with the original id of every local
/// vertex; a vertex where the triangles meet in several fans (a pinch) gets one local vertex
/// per fan. `None` when they are still not a manifold.
pub(super) fn local_mesh(tris: &[[u32; 3]], point: &dyn Fn(u32) -> [f64; 3]) -> Option<(TriMesh, Vec<u32>)> {
    // Corners 3i + k; corners at one vertex are joined across every edge two triangles share.
    let mut parent: Vec<u32> = (0..3 * tris.len() as u32).collect();
    let mut edge: HashMap<(u32, u32), u32> = HashMap::with_capacity(3 * tris.len());
    for (i, t) in tris.iter().enumerate() {
        for k in 0..3 {
            edge.insert((t[k], t[(k + 1) % 3]), (3 * i + k) as u32);
        }
    }
    for (i, t) in tris.iter().enumerate() {
        for k in 0..3 {
            let Some(&c) = edge.get(&(t[(k + 1) % 3], t[k])) else { continue };
            let (j, l) = (c / 3, c % 3);
            // Edge a → b here, b → a in triangle j (corner l at b, l + 1 at a).
            for (x, y) in [((3 * i + k) as u32, 3 * j + (l + 1) % 3), ((3 * i + (k + 1) % 3) as u32, c)] {
                let (rx, ry) = (find(&mut parent, x), find(&mut parent, y));
                if rx != ry {
                    parent[rx.max(ry) as usize] = rx.min(ry);
                }
            }
        }
    }
    let mut local: HashMap<u32, u32> = HashMap::new();
    let mut global = Vec::new();
    let mut local_tris = vec![[0u32; 3]; tris.len()];
    for (i, t) in tris.iter().enumerate() {
        for k in 0..3 {
            let root = find(&mut parent, (3 * i + k) as u32);
            local_tris[i][k] = *local.entry(root).or_insert_with(|| {
                global.push(t[k]);
                (global.len() - 1) as u32
            });
        }
    }
    let points = global.iter().map(|&v| point(v)).collect();
    Some((TriMesh::from_checked(points, local_tris).ok()?, global))
}
