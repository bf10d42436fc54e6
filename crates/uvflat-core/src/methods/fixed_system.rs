//! The factored linear system of a fixed-boundary barycentric map (course notes ch. 2;
//! Desbrun–Meyer–Alliez 2002 eq. 4, 6 and §3.4), kept as an object so it can be solved again:
//! for new boundary positions (the boundary editor, Desbrun §4.2), for many right-hand sides
//! (the Green-function basis), or with Lagrange point constraints (§4.1).
//!
//! Rows are the free vertices i: `Σ_j w_ij (u_i − u_j) = 0`, i.e. `A u_f = K u_b` with `A` the
//! weighted Laplacian restricted to the free vertices and `K` (the coupling) holding `w_ij` for
//! every fixed neighbour j. `A` is factored once: Cholesky when the weights are symmetric
//! (uniform, DCP, intrinsic with μ = 0), sparse LU otherwise. Solving is `&self` and
//! allocation-local, so one system serves concurrent solves from several threads.

use super::barycentric::{vertex_weights, Weights};
use crate::error::Result;
use crate::mesh::Unknowns;
use crate::mesh::{TriMesh, NONE};
use faer::Mat;
use rayon::prelude::*;
use uvflat_sparse::{require_finite, CholeskySolver, LuSolver, TripletBuilder};

/// Reusable buffers of [`FixedSystem::solve_permuted_rows`].
#[derive(Default)]
pub struct RowScratch {
    buffer: Vec<[f64; 2]>,
    rhs: Vec<[f64; 2]>,
}

/// The factorization of `A`.
enum Factor {
    Cholesky(CholeskySolver<f64>),
    Lu(LuSolver),
}

/// A factored fixed-boundary system over the free vertices of a mesh.
pub struct FixedSystem {
    /// Numbering of the free vertices (rows and columns of `A`).
    pub unknowns: Unknowns,
    /// `(row, fixed vertex, w)`: the right-hand side of `row` gets `w · uv[fixed vertex]`.
    coupling: Vec<(u32, u32, f64)>,
    factor: Factor,
}

impl FixedSystem {
    /// Assembles and factors the system of `mesh` (a disk: holes already filled) with the
    /// vertices for which `is_fixed` holds fixed.
    pub fn new(mesh: &TriMesh, weights: Weights, is_fixed: impl Fn(u32) -> bool) -> Result<Self> {
        let unknowns = Unknowns::free_vertices(mesh, is_fixed);
        let entries = vertex_weights(mesh, weights, &unknowns.index);
        let symmetric = weights.is_symmetric() || matches!(weights, Weights::Intrinsic { mu, .. } if mu == 0.0);
        let mut a = TripletBuilder::with_capacity(unknowns.count(), 2 * entries.len());
        let mut coupling = Vec::new();
        for &(i, j, w) in &entries {
            let r = unknowns.index[i as usize] as usize;
            a.add(r, r, w);
            match unknowns.index[j as usize] {
                NONE => coupling.push((r as u32, j, w)),
                c if !symmetric || r >= c as usize => a.add(r, c as usize, -w),
                _ => {}
            }
        }
        let matrix = a.build()?;
        let coords = unknowns.positions(mesh);
        let factor = if symmetric {
            Factor::Cholesky(CholeskySolver::new(&matrix, Some(&coords))?)
        } else {
            Factor::Lu(LuSolver::with_coords(&matrix, Some(&coords))?)
        };
        Ok(FixedSystem { unknowns, coupling, factor })
    }

    /// Values stored by the factorization (L, or L and U).
    pub fn factor_len(&self) -> usize {
        match &self.factor {
            Factor::Cholesky(c) => c.factor_len(),
            Factor::Lu(lu) => lu.frontal().map_or(0, |f| f.factor_len()),
        }
    }

    /// Number of free vertices.
    pub fn count(&self) -> usize {
        self.unknowns.count()
    }

    /// The right-hand side `K u_b` (n × 2) for fixed positions `fixed_uv` (indexed by vertex;
    /// only the fixed vertices are read).
    pub fn rhs(&self, fixed_uv: &[[f64; 2]]) -> Mat<f64> {
        let mut rhs = Mat::<f64>::zeros(self.count(), 2);
        for &(r, j, w) in &self.coupling {
            rhs[(r as usize, 0)] += w * fixed_uv[j as usize][0];
            rhs[(r as usize, 1)] += w * fixed_uv[j as usize][1];
        }
        rhs
    }

    /// `(row, fixed vertex, w)` entries of the coupling `K`.
    pub fn coupling(&self) -> &[(u32, u32, f64)] {
        &self.coupling
    }

    /// Replaces `rhs` (any number of columns) by `A⁻¹ rhs`.
    pub fn solve_in_place(&self, rhs: &mut Mat<f64>) -> Result<()> {
        match &self.factor {
            Factor::Cholesky(c) => c.solve_in_place(rhs)?,
            Factor::Lu(lu) => lu.solve_in_place(rhs)?,
        }
        Ok(())
    }

    /// The elimination order of the factor: `order[k]` is the free unknown (row of `A`) held
    /// by row k of the permuted solves.
    pub fn elimination_order(&self) -> Vec<usize> {
        match &self.factor {
            Factor::Cholesky(c) => c.elimination_order().map_or_else(|| (0..self.count()).collect(), |o| o.to_vec()),
            Factor::Lu(lu) => match lu.frontal() {
                Some(f) => f.elimination_order().to_vec(),
                None => (0..self.count()).collect(),
            },
        }
    }

    /// The supernodes the forward substitution must visit for right-hand sides nonzero only in
    /// the permuted rows `rows` (`None` when the factor has no supernodal structure).
    pub fn active_supernodes(&self, rows: impl IntoIterator<Item = usize>) -> Option<Vec<bool>> {
        match &self.factor {
            Factor::Cholesky(c) => c.active_supernodes(rows),
            Factor::Lu(lu) => lu.frontal().and_then(|f| f.active_supernodes(rows)),
        }
    }

    /// Solves `A X = B` (`Aᵀ X = B` when `transpose`) for two row-interleaved columns in place,
    /// rows in [`Self::elimination_order`] (`inverse` is that order's inverse). No allocation
    /// once `scratch` has grown, except for the LU's rare pivoted fallback. `active` (from
    /// [`Self::active_supernodes`]) restricts the forward substitution to a sparse right-hand
    /// side's reach.
    pub fn solve_permuted_rows(
        &self,
        x: &mut [[f64; 2]],
        transpose: bool,
        inverse: &[usize],
        scratch: &mut RowScratch,
        active: Option<&[bool]>,
    ) -> Result<()> {
        match &self.factor {
            Factor::Cholesky(c) => c.solve_permuted_rows(x, &mut scratch.buffer, active)?,
            Factor::Lu(lu) => {
                let accepted = match lu.frontal() {
                    Some(f) => {
                        scratch.rhs.clear();
                        scratch.rhs.extend_from_slice(x);
                        f.solve_permuted_rows(x, transpose, &mut scratch.buffer, active)?;
                        lu.accepts_rows(x, &scratch.rhs, transpose, Some(inverse))
                    }
                    None => {
                        scratch.rhs.clear();
                        scratch.rhs.extend_from_slice(x);
                        false
                    }
                };
                if !accepted {
                    // Unstable unpivoted factors: faer's pivoted LU in the original numbering.
                    let mut m = Mat::<f64>::from_fn(self.count(), 2, |i, c| scratch.rhs[inverse[i]][c]);
                    lu.solve_pivoted_in_place(&mut m, transpose)?;
                    for (i, &k) in inverse.iter().enumerate() {
                        x[k] = [m[(i, 0)], m[(i, 1)]];
                    }
                }
            }
        }
        Ok(require_finite(x.iter().flatten().copied(), "fixed-boundary")?)
    }

    /// One UV per vertex from a solution `x` of the free vertices and the fixed positions.
    pub fn scatter(&self, x: &Mat<f64>, fixed_uv: &[[f64; 2]]) -> Result<Vec<[f64; 2]>> {
        require_finite(x.col_as_slice(0).iter().chain(x.col_as_slice(1)).copied(), "fixed-boundary")?;
        let mut uv = fixed_uv.to_vec();
        uv.par_iter_mut().enumerate().with_min_len(4096).for_each(|(v, p)| {
            let r = self.unknowns.index[v];
            if r != NONE {
                *p = [x[(r as usize, 0)], x[(r as usize, 1)]];
            }
        });
        Ok(uv)
    }
}
