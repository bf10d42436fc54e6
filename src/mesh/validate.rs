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

/// Area of a triangle divided by its longest edge squared (0 for collinear points).
pub fn relative_area(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    use crate::geometry::{cross, norm, norm2, sub};
    let (ab, ac, bc) = (sub(b, a), sub(c, a), sub(c, b));
    let longest = norm2(ab).max(norm2(ac)).max(norm2(bc));
    if longest == 0.0 {
        return 0.0;
    }
    0.5 * norm(cross(ab, ac)) / longest
}

/// Rejects triangles with (near-)zero area.
pub fn check_degenerate(points: &[[f64; 3]], tris: &[[u32; 3]]) -> Result<()> {
    for (t, tri) in tris.iter().enumerate() {
        let r = relative_area(points[tri[0] as usize], points[tri[1] as usize], points[tri[2] as usize]);
        if !(r > DEGENERATE_RELATIVE_AREA) {
            return Err(Error::DegenerateTriangle { triangle: t, relative_area: r });
        }
    }
    Ok(())
}

/// Rejects two triangles over the same three vertices (in any order).
pub fn check_duplicates(tris: &[[u32; 3]]) -> Result<()> {
    let mut keys: Vec<(u128, usize)> = tris
        .iter()
        .enumerate()
        .map(|(t, tri)| {
            let mut s = *tri;
            s.sort_unstable();
            (((s[0] as u128) << 64) | ((s[1] as u128) << 32) | s[2] as u128, t)
        })
        .collect();
    keys.sort_unstable();
    for w in keys.windows(2) {
        if w[0].0 == w[1].0 {
            return Err(Error::DuplicateTriangle { triangle: w[1].1, first: w[0].1 });
        }
    }
    Ok(())
}
