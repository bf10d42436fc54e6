//! The default unwrap of a mesh given as flat arrays that may hold zero-area triangles
//! (vertices snapped together but not merged, collinear corners), which `TriMesh::new` refuses:
//! the welds and left-out triangles of `mesh::snapped` make a mesh that is solved by
//! [`super::unwrap_with_progress`], and the result is expressed back over the input.
//!
//! Over the input, every kept triangle has the corners the unwrap gave it; a left-out triangle
//! takes for each corner a UV vertex of its solve vertex, in one island where its vertices share
//! one (so a triangle whose corners were welded gets a UV triangle of zero area, like its 3D
//! shape). Left-out triangles are outside the solve and the verification: the report's flip
//! and overlap counts are those of the kept triangles, and it counts the left-out ones (the
//! islands' triangle counts are those of the solve too).
//!
//! A group of welded input vertices is named by its lowest vertex in the result's `original`
//! (the input vertex of every UV vertex) and `seams` (vertex pairs).

use super::{unwrap_with_progress, UnwrapOptions, Unwrapped};
use crate::error::{Error, Result};
use crate::mesh::snapped::{snapped_repair, SnappedRepair};
use crate::mesh::TriMesh;
use crate::progress::Progress;
use std::collections::HashMap;

/// [`super::unwrap_with_progress`] on flat arrays (3 coordinates per vertex, 3 indices per
/// triangle): a mesh `TriMesh::new` accepts is unwrapped as it is; one it refuses only for
/// zero-area triangles is welded and unwrapped without them (see the module docs); any other
/// problem is the mesh's own error.
pub fn unwrap_arrays(
    positions: &[f64],
    triangles: &[u32],
    options: &UnwrapOptions,
    progress: &mut Progress,
) -> Result<Unwrapped> {
    let refusal = match TriMesh::new(positions, triangles) {
        Ok(mesh) => return unwrap_with_progress(&mesh, options, progress),
        Err(e @ (Error::DegenerateTriangle { .. } | Error::RepeatedVertex { .. })) => e,
        Err(e) => return Err(e),
    };
    // (The lengths are whole triples: `TriMesh::new` checks them before the triangles.)
    let points: Vec<[f64; 3]> = positions.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    let tris: Vec<[u32; 3]> = triangles.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    let repair = snapped_repair(&points, &tris)?;
    let Some(solve) = solve_mesh(&points, &tris, &repair) else {
        return Err(refusal);
    };
    let mut result = unwrap_with_progress(&solve, options, progress)?;
    over_the_input(&mut result, &tris, &repair);
    Ok(result)
}

/// The welded mesh of the kept triangles, or None when it is not a valid mesh, or a vertex
/// would be left without a UV.
fn solve_mesh(points: &[[f64; 3]], tris: &[[u32; 3]], repair: &SnappedRepair) -> Option<TriMesh> {
    if repair.unreferenced > 0 || repair.left_out == tris.len() {
        return None;
    }
    let mut position = vec![0.0; 3 * repair.vertex_count];
    for v in (0..points.len()).rev() {
        let s = repair.vertex[v] as usize;
        position[3 * s..3 * s + 3].copy_from_slice(&points[v]);
    }
    let kept: Vec<u32> = tris
        .iter()
        .zip(&repair.keep)
        .filter(|(_, &k)| k)
        .flat_map(|(t, _)| t.map(|v| repair.vertex[v as usize]))
        .collect();
    TriMesh::new(&position, &kept).ok()
}

/// Rewrites the unwrap of the solve mesh over the input's vertices and triangles.
fn over_the_input(result: &mut Unwrapped, tris: &[[u32; 3]], repair: &SnappedRepair) {
    let atlas = &mut result.atlas;
    // The lowest input vertex of every solve vertex.
    let mut first = vec![u32::MAX; repair.vertex_count];
    for (v, &s) in repair.vertex.iter().enumerate().rev() {
        first[s as usize] = v as u32;
    }
    // A UV vertex of every (solve vertex, island), one of every solve vertex, and the islands of
    // every solve vertex.
    let mut in_island: HashMap<(u32, u32), u32> = HashMap::new();
    let mut islands_of: Vec<Vec<u32>> = vec![Vec::new(); repair.vertex_count];
    let mut any = vec![u32::MAX; repair.vertex_count];
    let mut chart_of_uv = vec![0u32; atlas.uv.len()];
    for (corners, &chart) in atlas.triangles.iter().zip(&atlas.chart_of_triangle) {
        for &uv in corners {
            chart_of_uv[uv as usize] = chart;
            let s = atlas.original[uv as usize];
            if let std::collections::hash_map::Entry::Vacant(e) = in_island.entry((s, chart)) {
                e.insert(uv);
                islands_of[s as usize].push(chart);
            }
            if any[s as usize] == u32::MAX {
                any[s as usize] = uv;
            }
        }
    }
    let (mut triangles, mut charts) = (Vec::with_capacity(tris.len()), Vec::with_capacity(tris.len()));
    let mut kept = atlas.triangles.iter().zip(&atlas.chart_of_triangle);
    for (t, &keep) in tris.iter().zip(&repair.keep) {
        if keep {
            let (corners, &chart) = kept.next().expect("one solve triangle per kept triangle");
            triangles.push(*corners);
            charts.push(chart);
            continue;
        }
        let s = t.map(|v| repair.vertex[v as usize]);
        // An island holding all three corners where there is one (a seam vertex has several).
        let chart = islands_of[s[0] as usize]
            .iter()
            .copied()
            .find(|&c| in_island.contains_key(&(s[1], c)) && in_island.contains_key(&(s[2], c)))
            .unwrap_or(chart_of_uv[any[s[0] as usize] as usize]);
        triangles.push(s.map(|w| *in_island.get(&(w, chart)).unwrap_or(&any[w as usize])));
        charts.push(chart);
    }
    atlas.triangles = triangles;
    atlas.chart_of_triangle = charts;
    for o in &mut atlas.original {
        *o = first[*o as usize];
    }
    for seam in &mut result.seams {
        let [a, b] = seam.map(|s| first[s as usize]);
        *seam = [a.min(b), a.max(b)];
    }
    result.seams.sort_unstable();
    result.report.welded_vertices = repair.welded;
    result.report.left_out_triangles = repair.left_out;
}
