//! Checks of raw caller data before any connectivity is built: array lengths, index range,
//! finite coordinates, repeated vertices, degenerate and duplicate triangles.

use crate::error::{Error, Result};

/// Triangles whose area is below this fraction of their longest edge squared are degenerate.
/// (A needle with a 1e-6 degree angle still passes; collinear points do not.)
pub const DEGENERATE_RELATIVE_AREA: f64 = 1e-12;

/// Splits flat arrays into points and triangles, checking lengths, indices and coordinates.
pub fn split_arrays(positions: &[f64], triangles: &[u32]) -> Result<(Vec<[f64; 3]>, Vec<[u32; 3]>)> {
    if positions.len() % 3 != 0 {
        return Err(Error::BadArrayLength { what: "positions", len: positions.len(), multiple_of: 3 });
    }
    if triangles.len() % 3 != 0 {
        return Err(Error::BadArrayLength { what: "triangles", len: triangles.len(), multiple_of: 3 });
    }
    if triangles.is_empty() {
        return Err(Error::EmptyMesh);
    }
    let points: Vec<[f64; 3]> = positions.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    let tris: Vec<[u32; 3]> = triangles.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    check_indices(&tris, points.len())?;
    check_finite(&points, &tris)?;
    Ok((points, tris))
}

fn check_indices(tris: &[[u32; 3]], vertex_count: usize) -> Result<()> {
    for (t, tri) in tris.iter().enumerate() {
        for &v in tri {
            if v as usize >= vertex_count {
                return Err(Error::IndexOutOfRange { triangle: t, vertex: v as u64, vertex_count });
            }
        }
        if tri[0] == tri[1] || tri[0] == tri[2] {
            return Err(Error::RepeatedVertex { triangle: t, vertex: tri[0] });
        }
        if tri[1] == tri[2] {
            return Err(Error::RepeatedVertex { triangle: t, vertex: tri[1] });
        }
    }
    Ok(())
}

/// Non-finite coordinates are an error only on vertices that a triangle uses; unreferenced
/// vertices are ignored by every method.
fn check_finite(points: &[[f64; 3]], tris: &[[u32; 3]]) -> Result<()> {
    let mut used = vec![false; points.len()];
    for tri in tris {
        for &v in tri {
            used[v as usize] = true;
        }
    }
    for (v, p) in points.iter().enumerate() {
        if !used[v] {
            continue;
        }
        if let Some(&value) = p.iter().find(|c| !c.is_finite()) {
            return Err(Error::NonFiniteCoordinate { vertex: v, value });
        }
    }
    Ok(())
}

/// Whether a triangle of this relative area is degenerate (NaN counts as degenerate).
pub fn is_degenerate(relative_area: f64) -> bool {
    relative_area.is_nan() || relative_area <= DEGENERATE_RELATIVE_AREA
}

/// Rejects two triangles over the same three vertices (in any order). Triangles are bucketed by
/// their lowest vertex (a counting sort) and compared within buckets; the pair reported is the
/// one with the smallest sorted vertex triple, and within it the two lowest triangle indices.
pub fn check_duplicates(tris: &[[u32; 3]]) -> Result<()> {
    let sorted = |tri: &[u32; 3]| {
        let mut s = *tri;
        s.sort_unstable();
        s
    };
    let vertex_count = tris.iter().flat_map(|t| t.iter()).max().map_or(0, |&v| v as usize + 1);
    let mut start = vec![0u32; vertex_count + 1];
    for tri in tris {
        start[tri[0].min(tri[1]).min(tri[2]) as usize + 1] += 1;
    }
    for v in 0..vertex_count {
        start[v + 1] += start[v];
    }
    let mut fill = start.clone();
    let mut entries = vec![(0u32, 0u32, 0u32); tris.len()];
    for (t, tri) in tris.iter().enumerate() {
        let s = sorted(tri);
        let slot = &mut fill[s[0] as usize];
        entries[*slot as usize] = (s[1], s[2], t as u32);
        *slot += 1;
    }
    for v in 0..vertex_count {
        let bucket = &mut entries[start[v] as usize..start[v + 1] as usize];
        bucket.sort_unstable();
        if let Some(w) = bucket.windows(2).find(|w| (w[0].0, w[0].1) == (w[1].0, w[1].1)) {
            return Err(Error::DuplicateTriangle { triangle: w[1].2 as usize, first: w[0].2 as usize });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_duplicate_reported_has_the_smallest_vertex_triple_then_the_lowest_indices() {
        let tris = [[5, 6, 7], [1, 2, 3], [7, 5, 6], [3, 1, 2], [2, 3, 1], [0, 8, 9]];
        match check_duplicates(&tris) {
            Err(Error::DuplicateTriangle { triangle, first }) => assert_eq!((triangle, first), (3, 1)),
            other => panic!("expected a duplicate, got {other:?}"),
        }
        assert!(check_duplicates(&[[0, 1, 2], [0, 2, 1 + 2]]).is_ok());
    }
}
