//! Test matrices shared by the unit tests of the factorizations.

use faer::c64;

/// Entries (row, column, value) of a lower triangle.
pub(crate) type Lower = Vec<(u32, u32, c64)>;

/// Hermitian positive-definite matrix on a `k × k` grid graph: a shifted Laplacian plus
/// an antisymmetric imaginary part on the edges of the first row. Returns the diagonal, the
/// entries below it and the grid coordinates of the vertices.
pub(crate) fn grid_matrix(k: u32) -> (Vec<c64>, Lower, Vec<[f64; 3]>) {
    let id = |i: u32, j: u32| j * k + i;
    let n = (k * k) as usize;
    let mut diagonal = vec![c64::new(0.1, 0.0); n];
    let mut lower = Vec::new();
    let mut coords = vec![[0.0; 3]; n];
    for j in 0..k {
        for i in 0..k {
            coords[id(i, j) as usize] = [i as f64, j as f64, 0.0];
            for (a, b) in [(id(i, j), id(i + 1, j)), (id(i, j), id(i, j + 1)), (id(i, j), id(i + 1, j + 1))] {
                if i + 1 >= k && b == id(i + 1, j)
                    || j + 1 >= k && b != id(i + 1, j)
                    || i + 1 >= k && b == id(i + 1, j + 1)
                {
                    continue;
                }
                let w = 1.0 + 0.1 * ((a * 7 + b * 3) % 5) as f64;
                diagonal[a as usize].re += w;
                diagonal[b as usize].re += w;
                let imag = if j == 0 && b == id(i + 1, j) { 0.5 } else { 0.0 };
                lower.push((b, a, c64::new(-w, -imag)));
            }
        }
    }
    (diagonal, lower, coords)
}
