//! Sparse linear algebra on top of `faer`: assembly of summed entries into compressed columns
//! (linear-time counting sort), sparse Cholesky (supernodal, with a geometric nested-dissection
//! ordering when unknowns have positions, AMD otherwise) for symmetric/Hermitian
//! positive-definite systems, and sparse LU for the others. A factorization is an object, so a
//! method that solves several times factors once.

pub mod ordering;

use crate::error::{Error, Result};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::solvers::Solve;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, LltRef, SymbolicCholesky, SymmetricOrdering};
use faer::sparse::linalg::solvers::Lu;
use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use faer::traits::ComplexField;
use faer::{Conj, Mat, Par, Side};

/// Accumulates matrix entries; repeated (row, col) entries are summed.
pub struct TripletBuilder<T> {
    n: usize,
    rows: Vec<u32>,
    cols: Vec<u32>,
    values: Vec<T>,
}

impl<T: ComplexField + Copy + std::ops::Add<Output = T>> TripletBuilder<T> {
    /// An empty `n × n` matrix with room for `capacity` entries.
    pub fn with_capacity(n: usize, capacity: usize) -> Self {
        TripletBuilder { n, rows: Vec::with_capacity(capacity), cols: Vec::with_capacity(capacity), values: Vec::with_capacity(capacity) }
    }
    /// Adds `value` at (`row`, `col`).
    #[inline]
    pub fn add(&mut self, row: usize, col: usize, value: T) {
        self.rows.push(row as u32);
        self.cols.push(col as u32);
        self.values.push(value);
    }
    /// Compressed-column matrix of the summed entries (rows sorted within each column).
    pub fn build(&self) -> Result<SparseColMat<usize, T>> {
        let n = self.n;
        let mut col_ptr = vec![0usize; n + 1];
        for &c in &self.cols {
            col_ptr[c as usize + 1] += 1;
        }
        for c in 0..n {
            col_ptr[c + 1] += col_ptr[c];
        }
        let mut fill = col_ptr.clone();
        let mut slots: Vec<(u32, T)> = vec![(0, T::zero_impl()); self.rows.len()];
        for k in 0..self.rows.len() {
            let c = self.cols[k] as usize;
            slots[fill[c]] = (self.rows[k], self.values[k]);
            fill[c] += 1;
        }
        let (mut out_ptr, mut row_idx, mut values) = (Vec::with_capacity(n + 1), Vec::new(), Vec::new());
        out_ptr.push(0);
        for c in 0..n {
            let column = &mut slots[col_ptr[c]..col_ptr[c + 1]];
            column.sort_unstable_by_key(|s| s.0);
            for &(r, v) in column.iter() {
                if row_idx.len() > out_ptr[c] && *row_idx.last().unwrap_or(&usize::MAX) == r as usize {
                    let last = values.len() - 1;
                    values[last] = values[last] + v;
                } else {
                    row_idx.push(r as usize);
                    values.push(v);
                }
            }
            out_ptr.push(row_idx.len());
        }
        let symbolic = SymbolicSparseColMat::new_checked(n, n, out_ptr, None, row_idx);
        Ok(SparseColMat::new(symbolic, values))
    }
}

/// Sparse Cholesky factorization `A = L Lᴴ` of a symmetric (Hermitian) positive-definite
/// matrix given by its lower triangle.
pub struct CholeskySolver<T> {
    symbolic: SymbolicCholesky<usize>,
    values: Vec<T>,
}

impl<T: ComplexField> CholeskySolver<T> {
    /// Factors the matrix (entries with row ≥ col are read). With `coords` (one 3D position
    /// per unknown) the elimination order is geometric nested dissection, otherwise AMD.
    pub fn new(lower: &SparseColMat<usize, T>, coords: Option<&[[f64; 3]]>) -> Result<Self> {
        let n = lower.nrows();
        let (fwd, inv) = match coords {
            Some(c) => {
                let adj = ordering::Adjacency::from_lower(n, lower.col_ptr(), lower.row_idx());
                let fwd = ordering::nested_dissection(&adj, c);
                let mut inv = vec![0usize; n];
                for (k, &v) in fwd.iter().enumerate() {
                    inv[v] = k;
                }
                (fwd, inv)
            }
            None => (Vec::new(), Vec::new()),
        };
        let ord = if coords.is_some() {
            SymmetricOrdering::Custom(PermRef::new_checked(&fwd, &inv, n))
        } else {
            SymmetricOrdering::Amd
        };
        let symbolic = factorize_symbolic_cholesky(lower.symbolic(), Side::Lower, ord, Default::default())
            .map_err(|e| Error::Internal(format!("symbolic Cholesky failed: {e:?}")))?;
        let mut values = try_zeroed_vec::<T>(symbolic.len_val())?;
        let par = faer::get_global_parallelism();
        let mut mem = MemBuffer::try_new(symbolic.factorize_numeric_llt_scratch::<T>(par, Default::default()))
            .map_err(|_| Error::Internal("out of memory for the Cholesky workspace".into()))?;
        symbolic
            .factorize_numeric_llt(&mut values, lower.as_ref(), Side::Lower, Default::default(), par, MemStack::new(&mut mem), Default::default())
            .map_err(|e| Error::Numerical(format!("the system matrix is not positive definite ({e:?}); the mesh may have extremely bad triangles")))?;
        Ok(CholeskySolver { symbolic, values })
    }

    /// Solves for every column of `rhs` in place.
    pub fn solve_in_place(&self, rhs: &mut Mat<T>) -> Result<()> {
        let par = faer::get_global_parallelism();
        let mut mem = MemBuffer::try_new(self.symbolic.solve_in_place_scratch::<T>(rhs.ncols(), par))
            .map_err(|_| Error::Internal("out of memory for the solve workspace".into()))?;
        LltRef::new(&self.symbolic, &self.values).solve_in_place_with_conj(Conj::No, rhs.as_mut(), par, MemStack::new(&mut mem));
        Ok(())
    }
}

fn try_zeroed_vec<T: ComplexField>(len: usize) -> Result<Vec<T>> {
    let mut v = Vec::new();
    v.try_reserve_exact(len).map_err(|_| Error::Internal(format!("out of memory for a Cholesky factor of {len} entries")))?;
    v.resize(len, T::zero_impl());
    Ok(v)
}

/// Sparse LU factorization with partial pivoting, for non-symmetric systems.
pub struct LuSolver {
    lu: Lu<usize, f64>,
}

impl LuSolver {
    /// Factors a square matrix.
    pub fn new(matrix: &SparseColMat<usize, f64>) -> Result<Self> {
        let lu = matrix.sp_lu().map_err(|e| Error::Numerical(format!("the system matrix is singular ({e:?})")))?;
        Ok(LuSolver { lu })
    }
    /// Solves for every column of `rhs` in place.
    pub fn solve_in_place(&self, rhs: &mut Mat<f64>) {
        self.lu.solve_in_place(rhs.as_mut());
    }
}

/// Fails with a numerical error when a solution holds NaN or infinity.
pub fn require_finite(values: impl IntoIterator<Item = f64>, what: &str) -> Result<()> {
    if values.into_iter().all(f64::is_finite) {
        Ok(())
    } else {
        Err(Error::Numerical(format!("the {what} solve produced non-finite values")))
    }
}

/// Parallelism used by the factorizations (all cores, through rayon).
pub fn parallelism() -> Par {
    faer::get_global_parallelism()
}

/// Numbering of the free (unknown) vertices of a system: referenced vertices that are not
/// fixed get consecutive indices.
pub struct Unknowns {
    /// Row/column of each vertex, or `NONE` for fixed and unreferenced vertices.
    pub index: Vec<u32>,
    /// Vertex of each unknown.
    pub vertex: Vec<u32>,
}

impl Unknowns {
    /// Numbers the referenced vertices of `mesh` for which `is_fixed` is false.
    pub fn free_vertices(mesh: &crate::TriMesh, is_fixed: impl Fn(u32) -> bool) -> Self {
        let mut index = vec![crate::mesh::NONE; mesh.vertex_count()];
        let mut vertex = Vec::new();
        for v in 0..mesh.vertex_count() as u32 {
            if mesh.is_referenced(v) && !is_fixed(v) {
                index[v as usize] = vertex.len() as u32;
                vertex.push(v);
            }
        }
        Unknowns { index, vertex }
    }
    /// Number of unknowns.
    pub fn count(&self) -> usize {
        self.vertex.len()
    }
    /// 3D position of each unknown (for the nested-dissection ordering).
    pub fn positions(&self, mesh: &crate::TriMesh) -> Vec<[f64; 3]> {
        self.vertex.iter().map(|&v| mesh.points()[v as usize]).collect()
    }
}
