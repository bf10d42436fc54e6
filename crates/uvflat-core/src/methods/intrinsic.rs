//! Real-time boundary manipulation (Desbrun–Meyer–Alliez 2002, §4.2 "impulse response"): the
//! intrinsic map `λ·DCP + μ·DAP` (§3.4) with its boundary fixed is linear in the boundary
//! positions, `U_int = A⁻¹ K U_b`, so the system `A` is factored once and every new boundary
//! costs one sparse product and one pair of triangular solves ([`BoundaryEditor::solve`]).
//!
//! Equivalently `U = Σ_i u_i b^i` where the Green function (impulse response) `b^i` of
//! boundary vertex i is the map obtained with boundary vertex i at 1 and every other at 0 — the
//! paper's "basis functions". [`BoundaryEditor::green_basis`] computes them explicitly: b solves
//! with b right-hand sides, memory n × b doubles (n vertices, b boundary vertices; 8·n·b
//! bytes), refused above a caller-given cap.
//!
//! The boundary is the outer (longest) loop, in the order of [`TriMesh::boundary_loops`]
//! (counter-clockwise, surface on the left); other loops are holes, filled by cones as in the
//! fixed-boundary maps. Cost: one factorization (Cholesky when μ = 0, LU otherwise); a solve is
//! one pass over the coupling `K`, one forward and one backward substitution with u and v
//! together (row-interleaved, [`uvflat_sparse::supernodal_solve`]) and one pass writing the
//! UVs, with buffers taken from a pool so a re-solve allocates nothing. `solve` takes `&self`:
//! concurrent solves on one editor are safe (each takes its own buffers).
//!
//! [`BoundaryEditor::boundary_gradient`] is the adjoint of the map: given ∂E/∂u for every vertex
//! it returns ∂E/∂u_b for every boundary vertex, `g_b + Kᵀ A⁻ᵀ g_f` — the impulse responses
//! `∂u_i/∂u_p = b^p(i)` summed against the gradient without forming them (one transposed solve),
//! which is what the boundary optimization (§5.2) descends on.

use super::barycentric::Weights;
use super::fixed_system::FixedSystem;
use super::fixed_system::RowScratch;
use crate::error::{Error, Result};
use crate::mesh::{fill::fill_holes, TriMesh, NONE};
use crate::progress::Progress;
use faer::Mat;
use rayon::prelude::*;
use std::sync::Mutex;

/// A factored intrinsic map whose boundary can be moved and re-solved quickly.
pub struct BoundaryEditor {
    /// Vertices of the outer boundary loop, in the order the boundary positions are given.
    boundary: Vec<u32>,
    /// Vertex count of the caller's mesh (the filled mesh may have more).
    vertex_count: usize,
    /// Vertex count of the filled mesh (the system's numbering).
    work_vertex_count: usize,
    referenced: Vec<bool>,
    system: FixedSystem,
    /// `(permuted row, boundary index, w)`: the coupling `K` in the factor's elimination order.
    coupling_rows: Vec<(u32, u32, f64)>,
    /// Vertex (of the filled mesh) of each permuted row.
    row_vertex: Vec<u32>,
    /// Permuted row of each free unknown (inverse of the elimination order).
    inverse_order: Vec<usize>,
    /// Supernodes reached by right-hand sides `K u_b` (nonzero only next to the boundary).
    active: Option<Vec<bool>>,
    /// Buffers of finished solves, reused by the next ones.
    pool: Mutex<Vec<Workspace>>,
}

/// Buffers of one solve.
#[derive(Default)]
struct Workspace {
    rows: Vec<[f64; 2]>,
    scratch: RowScratch,
}

/// The Green-function basis: `values[i * vertex_count + v]` is `b^i(v)`, the weight of
/// boundary vertex i in the UV of vertex v (NaN for unreferenced vertices).
pub struct GreenBasis {
    /// Number of vertices of the mesh.
    pub vertex_count: usize,
    /// Boundary vertices, in basis order.
    pub boundary: Vec<u32>,
    /// `boundary.len() × vertex_count` values, one column per boundary vertex.
    pub values: Vec<f64>,
}

impl GreenBasis {
    /// `U = Σ_i u_i b^i` for boundary positions `boundary_uv` (one per boundary vertex).
    pub fn evaluate(&self, boundary_uv: &[[f64; 2]]) -> Vec<[f64; 2]> {
        let n = self.vertex_count;
        let mut uv = vec![[0.0; 2]; n];
        uv.par_iter_mut().enumerate().with_min_len(1024).for_each(|(v, p)| {
            for (i, b) in boundary_uv.iter().enumerate() {
                let w = self.values[i * n + v];
                p[0] += w * b[0];
                p[1] += w * b[1];
            }
        });
        uv
    }
}

impl BoundaryEditor {
    /// Factors the intrinsic map `λ·DCP + μ·DAP` of a disk (possibly with holes) with its outer
    /// boundary fixed.
    pub fn new(mesh: &TriMesh, lambda: f64, mu: f64, progress: &mut Progress) -> Result<Self> {
        if !(lambda.is_finite() && mu.is_finite()) || (lambda == 0.0 && mu == 0.0) {
            return Err(Error::InvalidArgument(format!(
                "intrinsic weights need finite λ, μ not both zero (got λ = {lambda}, μ = {mu})"
            )));
        }
        mesh.require_disk_with_holes()?;
        let outer =
            mesh.longest_boundary_loop().ok_or(Error::NotADisk { components: 1, boundary_loops: 0, genus: 0 })?;
        let boundary = mesh.boundary_loops()[outer].clone();
        progress.report(0.05)?;
        let keep: Vec<bool> = (0..mesh.boundary_loops().len()).map(|i| i == outer).collect();
        let filled;
        let work = if keep.iter().all(|&k| k) {
            mesh
        } else {
            filled = fill_holes(mesh, &keep)?;
            &filled.mesh
        };
        let mut is_fixed = vec![false; work.vertex_count()];
        for &v in &boundary {
            is_fixed[v as usize] = true;
        }
        let system = FixedSystem::new(work, Weights::Intrinsic { lambda, mu }, |v| is_fixed[v as usize])?;
        progress.report(1.0)?;
        let referenced = (0..mesh.vertex_count() as u32).map(|v| mesh.is_referenced(v)).collect();
        let order = system.elimination_order();
        let mut inverse_order = vec![0usize; order.len()];
        for (k, &r) in order.iter().enumerate() {
            inverse_order[r] = k;
        }
        let row_vertex = order.iter().map(|&r| system.unknowns.vertex[r]).collect();
        let mut boundary_index = vec![NONE; work.vertex_count()];
        for (i, &v) in boundary.iter().enumerate() {
            boundary_index[v as usize] = i as u32;
        }
        let coupling_rows: Vec<(u32, u32, f64)> = system
            .coupling()
            .iter()
            .map(|&(r, j, w)| (inverse_order[r as usize] as u32, boundary_index[j as usize], w))
            .collect();
        let active = system.active_supernodes(coupling_rows.iter().map(|c| c.0 as usize));
        Ok(BoundaryEditor {
            boundary,
            vertex_count: mesh.vertex_count(),
            work_vertex_count: work.vertex_count(),
            referenced,
            system,
            coupling_rows,
            row_vertex,
            inverse_order,
            active,
            pool: Mutex::new(Vec::new()),
        })
    }

    /// The outer boundary loop's vertices, in the order [`Self::solve`] expects their UVs.
    pub fn boundary_vertices(&self) -> &[u32] {
        &self.boundary
    }

    /// Values stored by the editor's factorization (L for Cholesky, L and U for LU): a re-solve
    /// reads each of them twice at most.
    pub fn factor_len(&self) -> usize {
        self.system.factor_len()
    }

    /// Number of vertices of the mesh (length of a solution).
    pub fn vertex_count(&self) -> usize {
        self.vertex_count
    }

    fn check_boundary(&self, boundary_uv: &[[f64; 2]]) -> Result<()> {
        if boundary_uv.len() != self.boundary.len() {
            return Err(Error::InvalidArgument(format!(
                "{} boundary positions given for a boundary of {} vertices",
                boundary_uv.len(),
                self.boundary.len()
            )));
        }
        if let Some(i) = boundary_uv.iter().position(|p| !(p[0].is_finite() && p[1].is_finite())) {
            return Err(Error::InvalidArgument(format!("boundary position {i} is not finite")));
        }
        Ok(())
    }

    fn take_workspace(&self) -> Workspace {
        let mut ws = self.pool.lock().unwrap_or_else(|e| e.into_inner()).pop().unwrap_or_default();
        ws.rows.clear();
        ws.rows.resize(self.row_vertex.len(), [0.0; 2]);
        ws
    }

    fn give_workspace(&self, ws: Workspace) {
        self.pool.lock().unwrap_or_else(|e| e.into_inner()).push(ws);
    }

    /// The map for new boundary positions (one per boundary vertex, in
    /// [`Self::boundary_vertices`] order): one UV per mesh vertex, NaN for unreferenced ones.
    pub fn solve(&self, boundary_uv: &[[f64; 2]]) -> Result<Vec<[f64; 2]>> {
        let mut uv = vec![[0.0; 2]; self.vertex_count];
        self.solve_into(boundary_uv, &mut uv)?;
        Ok(uv)
    }

    /// [`Self::solve`] into a caller-owned array of [`Self::vertex_count`] UVs (left unchanged
    /// on failure). Allocation-free after the first solves.
    pub fn solve_into(&self, boundary_uv: &[[f64; 2]], uv: &mut [[f64; 2]]) -> Result<()> {
        self.check_boundary(boundary_uv)?;
        if uv.len() != self.vertex_count {
            return Err(Error::InvalidArgument(format!(
                "output holds {} UVs for a mesh of {} vertices",
                uv.len(),
                self.vertex_count
            )));
        }
        let mut ws = self.take_workspace();
        for &(r, i, w) in &self.coupling_rows {
            let (p, x) = (boundary_uv[i as usize], &mut ws.rows[r as usize]);
            x[0] += w * p[0];
            x[1] += w * p[1];
        }
        let solved = self.system.solve_permuted_rows(
            &mut ws.rows,
            false,
            &self.inverse_order,
            &mut ws.scratch,
            self.active.as_deref(),
        );
        if solved.is_ok() {
            for (p, &referenced) in uv.iter_mut().zip(&self.referenced) {
                if !referenced {
                    *p = [f64::NAN; 2];
                }
            }
            for (&v, &x) in self.row_vertex.iter().zip(&ws.rows) {
                if (v as usize) < self.vertex_count {
                    uv[v as usize] = x;
                }
            }
            for (&v, &p) in self.boundary.iter().zip(boundary_uv) {
                uv[v as usize] = p;
            }
        }
        self.give_workspace(ws);
        solved
    }

    /// The adjoint of [`Self::solve`]: for `uv_gradient` = ∂E/∂u at every mesh vertex (entries
    /// of unreferenced vertices are ignored), the gradient of E with respect to the boundary
    /// positions, `g_b + Kᵀ A⁻ᵀ g_f` (Desbrun et al. 2002 §5.2: the impulse responses
    /// `∂u_i/∂u_p^boundary` applied to the gradient by one transposed solve).
    pub fn boundary_gradient(&self, uv_gradient: &[[f64; 2]]) -> Result<Vec<[f64; 2]>> {
        if uv_gradient.len() != self.vertex_count {
            return Err(Error::InvalidArgument(format!(
                "{} gradient entries for a mesh of {} vertices",
                uv_gradient.len(),
                self.vertex_count
            )));
        }
        let mut ws = self.take_workspace();
        for (x, &v) in ws.rows.iter_mut().zip(&self.row_vertex) {
            *x = if (v as usize) < self.vertex_count { uv_gradient[v as usize] } else { [0.0; 2] };
        }
        let solved = self.system.solve_permuted_rows(&mut ws.rows, true, &self.inverse_order, &mut ws.scratch, None);
        let gradient = solved.map(|()| {
            let mut g: Vec<[f64; 2]> = self.boundary.iter().map(|&v| uv_gradient[v as usize]).collect();
            for &(r, i, w) in &self.coupling_rows {
                let y = ws.rows[r as usize];
                g[i as usize][0] += w * y[0];
                g[i as usize][1] += w * y[1];
            }
            g
        });
        self.give_workspace(ws);
        gradient
    }

    /// Bytes the explicit Green-function basis takes: 8 · vertices · boundary vertices.
    pub fn green_basis_bytes(&self) -> Option<usize> {
        self.vertex_count.checked_mul(self.boundary.len())?.checked_mul(8)
    }

    /// The explicit Green-function basis (impulse responses) `b^i`, refused with
    /// [`Error::InvalidArgument`] when it would take more than `max_bytes`.
    pub fn green_basis(&self, max_bytes: usize, progress: &mut Progress) -> Result<GreenBasis> {
        let bytes = self.green_basis_bytes().filter(|&b| b <= max_bytes).ok_or_else(|| {
            Error::InvalidArgument(format!(
                "the Green-function basis needs {} × {} doubles ({} bytes), above the memory cap of {max_bytes} bytes",
                self.vertex_count,
                self.boundary.len(),
                self.green_basis_bytes().map_or("more than usize::MAX".into(), |b| b.to_string())
            ))
        })?;
        let n = self.vertex_count;
        let b = self.boundary.len();
        let mut values = Vec::new();
        values
            .try_reserve_exact(bytes / 8)
            .map_err(|_| Error::Internal(format!("out of memory for {bytes} bytes of Green basis")))?;
        values.resize(n * b, 0.0);
        // Column of each boundary vertex.
        let mut column = vec![NONE; self.work_vertex_count];
        for (i, &v) in self.boundary.iter().enumerate() {
            column[v as usize] = i as u32;
        }
        const CHUNK: usize = 32;
        let chunks = b.div_ceil(CHUNK);
        for (k, out) in values.chunks_mut(CHUNK * n).enumerate() {
            let first = k * CHUNK;
            let width = out.len() / n;
            let mut rhs = Mat::<f64>::zeros(self.system.count(), width);
            for &(r, j, w) in self.system.coupling() {
                let c = column[j as usize] as usize;
                if c >= first && c < first + width {
                    rhs[(r as usize, c - first)] += w;
                }
            }
            self.system.solve_in_place(&mut rhs)?;
            out.par_chunks_mut(n).enumerate().for_each(|(c, col)| {
                for (v, x) in col.iter_mut().enumerate() {
                    *x = if !self.referenced[v] {
                        f64::NAN
                    } else {
                        match self.system.unknowns.index[v] {
                            NONE => f64::from(u8::from(column[v] as usize == first + c)),
                            r => rhs[(r as usize, c)],
                        }
                    };
                }
            });
            progress.report((k + 1) as f64 / chunks as f64)?;
        }
        if values.iter().any(|x| x.is_infinite()) {
            return Err(Error::Numerical("the Green-function basis has infinite values".into()));
        }
        Ok(GreenBasis { vertex_count: n, boundary: self.boundary.clone(), values })
    }
}
