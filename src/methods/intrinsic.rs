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
//! O(nnz(L)) and allocation of two n-vectors. `solve` takes `&self`: concurrent solves on one
//! editor are safe.

use super::barycentric::Weights;
use super::fixed_system::FixedSystem;
use crate::error::{Error, Result};
use crate::mesh::{fill::fill_holes, TriMesh, NONE};
use crate::progress::Progress;
use faer::Mat;
use rayon::prelude::*;

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
        Ok(BoundaryEditor {
            boundary,
            vertex_count: mesh.vertex_count(),
            work_vertex_count: work.vertex_count(),
            referenced,
            system,
        })
    }

    /// The outer boundary loop's vertices, in the order [`Self::solve`] expects their UVs.
    pub fn boundary_vertices(&self) -> &[u32] {
        &self.boundary
    }

    /// Number of vertices of the mesh (length of a solution).
    pub fn vertex_count(&self) -> usize {
        self.vertex_count
    }

    fn fixed_uv(&self, boundary_uv: &[[f64; 2]]) -> Result<Vec<[f64; 2]>> {
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
        let mut fixed = vec![[f64::NAN; 2]; self.work_vertex_count];
        for (&v, &p) in self.boundary.iter().zip(boundary_uv) {
            fixed[v as usize] = p;
        }
        Ok(fixed)
    }

    /// The map for new boundary positions (one per boundary vertex, in
    /// [`Self::boundary_vertices`] order): one UV per mesh vertex, NaN for unreferenced ones.
    pub fn solve(&self, boundary_uv: &[[f64; 2]]) -> Result<Vec<[f64; 2]>> {
        let fixed = self.fixed_uv(boundary_uv)?;
        let mut uv = self.system.solve(&fixed)?;
        uv.truncate(self.vertex_count);
        Ok(uv)
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
