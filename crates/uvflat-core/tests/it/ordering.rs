//! Fill-reducing orders (`uvflat_sparse::ordering`) on a real mesh of `tests/data/meshes`: both
//! presets give permutations, and the thorough one (multilevel bisection at every level, used
//! where one pattern is factored many times) gives a smaller Cholesky factor than the default's
//! plane splits on a curved 207k-face scan, as measured when it was introduced (99M → 72M
//! entries for PGP's 4 unknowns per vertex; METIS 5: 65M).

use faer::sparse::SymbolicSparseColMat;
use uvflat_core::TriMesh;
use uvflat_sparse::ordering::{nested_dissection_with, Adjacency, Options};
use uvflat_sparse::CholeskyPattern;
use uvflat_test_support::meshes;

/// Lower-triangular pattern (diagonal included) of the vertex graph of `mesh`.
fn vertex_graph_pattern(mesh: &TriMesh) -> SymbolicSparseColMat<usize> {
    let n = mesh.vertex_count();
    let mut below: Vec<Vec<usize>> = (0..n).map(|c| vec![c]).collect();
    for t in mesh.triangles() {
        for k in 0..3 {
            let (a, b) = (t[k] as usize, t[(k + 1) % 3] as usize);
            below[a.min(b)].push(a.max(b));
        }
    }
    let (mut col_ptr, mut row_idx) = (vec![0], Vec::new());
    for mut rows in below {
        rows.sort_unstable();
        rows.dedup();
        row_idx.extend(rows);
        col_ptr.push(row_idx.len());
    }
    SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx)
}

fn is_permutation(order: &[usize], n: usize) -> bool {
    let mut seen = vec![false; n];
    order.len() == n && order.iter().all(|&v| v < n && !std::mem::replace(&mut seen[v], true))
}

#[test]
fn thorough_nested_dissection_shrinks_the_factor_of_a_curved_scan() {
    let mesh = meshes::load("disk_face_libigl_loop1.obj");
    let lower = vertex_graph_pattern(&mesh);
    let n = mesh.vertex_count();
    let adjacency = Adjacency::from_lower(n, lower.col_ptr(), lower.row_idx());
    let factor_len = |options: &Options| {
        let order = nested_dissection_with(&adjacency, Some(mesh.points()), options);
        assert!(is_permutation(&order, n));
        CholeskyPattern::with_order(lower.as_ref(), Some(order)).unwrap().factor_len()
    };
    let (default, thorough) = (factor_len(&Options::default()), factor_len(&Options::thorough()));
    println!("factor entries: default {default}, thorough {thorough}");
    assert!((thorough as f64) < 0.85 * default as f64, "thorough {thorough} vs default {default} factor entries");
}
