//! Point and line constraints with Lagrange multipliers (Desbrun–Meyer–Alliez 2002, §4.1).
//!
//! A constraint fixes a point of the surface — triangle `t` and barycentric coordinates
//! `(β0, β1, β2)` — to a UV position: `Σ_k β_k u_{t_k} = target`, one linear row `C` per
//! constraint. A constrained line is a sequence of such points ([`line_constraints`]).
//!
//! - Fixed-boundary maps (every weight family of [`super::barycentric`], including the
//!   intrinsic `λ·DCP + μ·DAP`): `A u = b` becomes `[A Cᵀ; C 0] [u; λ] = [b; d]`, solved with
//!   the factor of `A` and a Schur complement on the constraints
//!   ([`uvflat_sparse::lagrange`]): k extra solves for k constraints. When the constraints are
//!   already satisfied by the unconstrained map, `λ = 0` and the map is unchanged.
//! - Natural conformal map (free boundary, §4.2 eq. 7): the pins of the unconstrained map are
//!   replaced by the constraints (any number ≥ 2 of points with distinct targets). The
//!   conformal energy `E_C = ½ z* H z` (see [`super::conformal`]) vanishes on constants, so
//!   `H` is singular; one vertex p is split off as a free translation `t`: `z = t·1 + w` with
//!   `w_p = 0`. Since barycentric rows sum to one, `C z = C' w + t·1`, and the KKT conditions
//!   of `min ½ w* H_ff w` s.t. `C' w + t·1 = d` are `w = −H_ff⁻¹ C'ᵀ λ`,
//!   `[−S 1; 1ᵀ 0][λ; t] = [d; 0]` with `S = C' H_ff⁻¹ C'ᵀ` — one complex Cholesky of
//!   `H_ff` and k solves. With two vertex constraints this is exactly the 2-pin natural
//!   conformal map.
//!
//! Conflicts: a linearly dependent constraint set (two constraints on one point, a point of a
//! triangle whose vertices are all on the fixed boundary, …) is reduced to an independent
//! subset; a dropped constraint that the solution does not satisfy is reported
//! ([`crate::Error::InvalidArgument`] naming the constraint) — never NaNs.
//!
//! Cost: the factorization of the unconstrained map plus k solves and O(k³) dense work.

use super::barycentric::FixedBoundaryOptions;
use super::conformal::{default_pins, ConformalSystem, Pin};
use super::fixed_system::FixedSystem;
use crate::boundary::fixed_boundary;
use crate::error::{Error, Result};
use crate::geometry::distance;
use crate::mesh::{fill::fill_holes, TriMesh, NONE};
use crate::progress::Progress;
use faer::{c64, Mat};
use uvflat_sparse::lagrange::{check_dropped, dense_solve, independent_rows, rows_times, solve_constrained, SparseRow};
use uvflat_sparse::{require_finite, CholeskySolver};

/// A point of the surface (triangle and barycentric coordinates) and the UV it must map to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointConstraint {
    /// Triangle index.
    pub triangle: u32,
    /// Barycentric coordinates with respect to the triangle's corners, in order; they are
    /// normalized to sum to one (they must not sum to zero).
    pub barycentric: [f64; 3],
    /// Target UV.
    pub uv: [f64; 2],
}

/// A constraint on a vertex (a pin): barycentric coordinates (1, 0, 0) of one of its
/// triangles. `None` when the vertex is in no triangle.
pub fn vertex_constraint(mesh: &TriMesh, vertex: u32, uv: [f64; 2]) -> Option<PointConstraint> {
    if vertex as usize >= mesh.vertex_count() {
        return None;
    }
    let h = mesh.outgoing_halfedges(vertex).next()?;
    let t = h / 3;
    let corner = mesh.triangles()[t as usize].iter().position(|&v| v == vertex)?;
    let mut barycentric = [0.0; 3];
    barycentric[corner] = 1.0;
    Some(PointConstraint { triangle: t, barycentric, uv })
}

/// Constraints mapping a polyline of surface points (triangle, barycentric) onto the segment
/// from `from` to `to`, spaced by 3D chord length (the first point to `from`, the last to `to`).
pub fn line_constraints(
    mesh: &TriMesh,
    points: &[(u32, [f64; 3])],
    from: [f64; 2],
    to: [f64; 2],
) -> Result<Vec<PointConstraint>> {
    let position = |&(t, b): &(u32, [f64; 3])| -> Result<[f64; 3]> {
        let tri = mesh.triangles().get(t as usize).ok_or_else(|| {
            Error::InvalidArgument(format!(
                "line point on triangle {t}, but the mesh has {} triangles",
                mesh.triangle_count()
            ))
        })?;
        let s = b[0] + b[1] + b[2];
        let mut p = [0.0; 3];
        for k in 0..3 {
            let x = mesh.points()[tri[k] as usize];
            for (d, pd) in p.iter_mut().enumerate() {
                *pd += b[k] / s * x[d];
            }
        }
        Ok(p)
    };
    let xyz = points.iter().map(position).collect::<Result<Vec<_>>>()?;
    let mut arc = vec![0.0];
    for w in xyz.windows(2) {
        arc.push(arc.last().copied().unwrap_or(0.0) + distance(w[0], w[1]));
    }
    let total = arc.last().copied().unwrap_or(0.0);
    Ok(points
        .iter()
        .zip(&arc)
        .enumerate()
        .map(|(i, (&(triangle, barycentric), &s))| {
            let f = if total > 0.0 {
                s / total
            } else if points.len() > 1 {
                i as f64 / (points.len() - 1) as f64
            } else {
                0.0
            };
            PointConstraint {
                triangle,
                barycentric,
                uv: [from[0] + f * (to[0] - from[0]), from[1] + f * (to[1] - from[1])],
            }
        })
        .collect())
}

/// Checks a constraint against the mesh and returns its `(vertex, weight)` terms (normalized
/// barycentric coordinates; zero weights dropped).
fn constraint_terms(mesh: &TriMesh, i: usize, c: &PointConstraint) -> Result<Vec<(u32, f64)>> {
    let tri = mesh.triangles().get(c.triangle as usize).ok_or_else(|| {
        Error::InvalidArgument(format!(
            "constraint {i} is on triangle {}, but the mesh has {} triangles",
            c.triangle,
            mesh.triangle_count()
        ))
    })?;
    let b = c.barycentric;
    let sum = b[0] + b[1] + b[2];
    if !(b.iter().all(|x| x.is_finite()) && c.uv.iter().all(|x| x.is_finite())) {
        return Err(Error::InvalidArgument(format!(
            "constraint {i} has a non-finite barycentric coordinate or target"
        )));
    }
    if !(sum.abs() > 1e-12 * (b[0].abs() + b[1].abs() + b[2].abs())) || sum == 0.0 {
        return Err(Error::InvalidArgument(format!("constraint {i}: barycentric coordinates {b:?} sum to zero")));
    }
    Ok((0..3).filter(|&k| b[k] != 0.0).map(|k| (tri[k], b[k] / sum)).collect())
}

fn check_not_empty(constraints: &[PointConstraint], at_least: usize) -> Result<()> {
    if constraints.len() < at_least {
        return Err(Error::InvalidArgument(format!(
            "at least {at_least} constraint(s) needed, {} given",
            constraints.len()
        )));
    }
    Ok(())
}

/// Fixed-boundary map (any weights, any boundary of [`FixedBoundaryOptions`]) with point
/// constraints added by Lagrange multipliers. One UV per vertex (NaN for unreferenced ones).
pub fn constrained_fixed_boundary_map(
    mesh: &TriMesh,
    options: &FixedBoundaryOptions,
    constraints: &[PointConstraint],
    progress: &mut Progress,
) -> Result<Vec<[f64; 2]>> {
    if let super::barycentric::Weights::Intrinsic { lambda, mu } = options.weights {
        if !(lambda.is_finite() && mu.is_finite()) || (lambda == 0.0 && mu == 0.0) {
            return Err(Error::InvalidArgument(format!(
                "intrinsic weights need finite λ, μ not both zero (got λ = {lambda}, μ = {mu})"
            )));
        }
    }
    mesh.require_disk_with_holes()?;
    let terms =
        constraints.iter().enumerate().map(|(i, c)| constraint_terms(mesh, i, c)).collect::<Result<Vec<_>>>()?;
    let boundary = fixed_boundary(mesh, &options.shape, options.distribution)?;
    progress.report(0.05)?;
    let filled;
    let work = if boundary.loop_fixed.iter().all(|&f| f) {
        mesh
    } else {
        filled = fill_holes(mesh, &boundary.loop_fixed)?;
        &filled.mesh
    };
    let mut fixed_uv = vec![[f64::NAN; 2]; work.vertex_count()];
    for &(v, p) in &boundary.fixed {
        fixed_uv[v as usize] = p;
    }
    let system = FixedSystem::new(work, options.weights, |v| !fixed_uv[v as usize][0].is_nan())?;
    progress.report(0.6)?;
    // Rows over the free vertices; fixed vertices move to the target side.
    let k = constraints.len();
    let mut rows: Vec<SparseRow> = Vec::with_capacity(k);
    let mut fixed_part = Mat::<f64>::zeros(k, 2);
    let mut targets = Mat::<f64>::zeros(k, 2);
    for (i, t) in terms.iter().enumerate() {
        let mut row = Vec::new();
        for &(v, w) in t {
            match system.unknowns.index[v as usize] {
                NONE => {
                    fixed_part[(i, 0)] += w * fixed_uv[v as usize][0];
                    fixed_part[(i, 1)] += w * fixed_uv[v as usize][1];
                }
                r => row.push((r as usize, w)),
            }
        }
        rows.push(row);
        targets[(i, 0)] = constraints[i].uv[0];
        targets[(i, 1)] = constraints[i].uv[1];
    }
    let kept = independent_rows(&rows);
    let d = &targets - &fixed_part;
    let x = solve_constrained(|m: &mut Mat<f64>| system.solve_in_place(m), system.rhs(&fixed_uv), &rows, &d, &kept)?;
    progress.report(0.95)?;
    let scale = 1.0
        + fixed_uv
            .iter()
            .chain(constraints.iter().map(|c| &c.uv))
            .filter(|p| p[0].is_finite())
            .fold(0.0f64, |m, p| m.max(p[0].abs()).max(p[1].abs()));
    check_dropped(&rows, &targets, &fixed_part, &kept, &x, 1e-9 * scale)?;
    let mut uv = system.scatter(&x, &fixed_uv)?;
    uv.truncate(mesh.vertex_count());
    progress.report(1.0)?;
    Ok(uv)
}

/// Natural conformal map (free boundary) with point constraints instead of two pins: any
/// number ≥ 2 of constraints, not all with the same target.
pub fn constrained_natural_conformal_map(
    mesh: &TriMesh,
    constraints: &[PointConstraint],
    progress: &mut Progress,
) -> Result<Vec<[f64; 2]>> {
    mesh.require_disk_with_holes()?;
    check_not_empty(constraints, 2)?;
    let terms =
        constraints.iter().enumerate().map(|(i, c)| constraint_terms(mesh, i, c)).collect::<Result<Vec<_>>>()?;
    let first_target = constraints[0].uv;
    if constraints.iter().all(|c| c.uv == first_target) {
        return Err(Error::InvalidArgument(
            "all constraints have the same target: the map would collapse to a point".into(),
        ));
    }
    // Rows over all vertices decide independence.
    let full: Vec<SparseRow> = terms.iter().map(|t| t.iter().map(|&(v, w)| (v as usize, w)).collect()).collect();
    let kept = independent_rows(&full);
    if kept.len() < 2 {
        return Err(Error::InvalidArgument("the constraints fix fewer than two independent points".into()));
    }
    progress.report(0.05)?;
    // Two split-off vertices (the default pins' vertices): with them removed H_ff is positive
    // definite even on a developable mesh (whose H also vanishes on the flat embedding).
    let split = default_pins(mesh).map(|(v, _)| v);
    let system = ConformalSystem::with_pins(mesh, &[(split[0], [0.0, 0.0]), (split[1], [0.0, 0.0])])?;
    let factor = CholeskySolver::new(&system.matrix, Some(&system.unknowns.positions(mesh)))?;
    progress.report(0.6)?;
    let n = system.unknowns.count();
    let m = kept.len();
    // C = [C_f C_p]: constraint rows over the free unknowns and over the two split vertices.
    let mut reduced: Vec<SparseRow> = Vec::with_capacity(m);
    let mut c_p = Mat::<c64>::zeros(m, 2);
    for (r, &i) in kept.iter().enumerate() {
        let mut row = Vec::new();
        for &(v, w) in &terms[i] {
            match (system.unknowns.index[v as usize], split.iter().position(|&s| s == v)) {
                (_, Some(a)) => c_p[(r, a)] += c64::new(w, 0.0),
                (NONE, None) => {}
                (x, None) => row.push((x as usize, w)),
            }
        }
        reduced.push(row);
    }
    // H_pf (rows of the split vertices over the free unknowns) and H_pp.
    let mut h_pp = Mat::<c64>::zeros(2, 2);
    let mut h_pf: [Vec<(usize, c64)>; 2] = [Vec::new(), Vec::new()];
    for a in 0..2 {
        let (diagonal, neighbours) = conformal_row(mesh, split[a]);
        h_pp[(a, a)] = c64::new(diagonal, 0.0);
        for (j, h) in neighbours {
            match (system.unknowns.index[j as usize], split.iter().position(|&s| s == j)) {
                (_, Some(b)) => h_pp[(a, b)] += h,
                (NONE, None) => {}
                (x, None) => h_pf[a].push((x as usize, h)),
            }
        }
    }
    // [G Y] = H_ff⁻¹ [H_fp  C_fᵀ] in one multi-column solve.
    let mut gy = Mat::<c64>::zeros(n, 2 + m);
    for a in 0..2 {
        for &(x, h) in &h_pf[a] {
            gy[(x, a)] += h.conj();
        }
    }
    for (r, row) in reduced.iter().enumerate() {
        for &(x, w) in row {
            gy[(x, 2 + r)] += c64::new(w, 0.0);
        }
    }
    factor.solve_in_place(&mut gy)?;
    let h_pf_times = |col: usize| -> [c64; 2] {
        let mut out = [c64::new(0.0, 0.0); 2];
        for a in 0..2 {
            for &(x, h) in &h_pf[a] {
                out[a] += h * gy[(x, col)];
            }
        }
        out
    };
    let c_f_gy = rows_times(&reduced, &gy); // m × (2 + m): [C_f G, C_f Y]
                                            // KKT in (z_p, λ): [P Q; R −S] [z_p; λ] = [0; d].
    let size = 2 + m;
    let mut kkt = Mat::<c64>::zeros(size, size);
    for col in 0..size {
        let hp = h_pf_times(col);
        for a in 0..2 {
            let base = if col < 2 { h_pp[(a, col)] } else { c_p[(col - 2, a)] };
            kkt[(a, col)] = base - hp[a];
        }
        for r in 0..m {
            kkt[(2 + r, col)] = if col < 2 { c_p[(r, col)] - c_f_gy[(r, col)] } else { -c_f_gy[(r, col)] };
        }
    }
    let rhs = Mat::<c64>::from_fn(size, 1, |r, _| {
        if r < 2 {
            c64::new(0.0, 0.0)
        } else {
            c64::new(constraints[kept[r - 2]].uv[0], constraints[kept[r - 2]].uv[1])
        }
    });
    let mut solution = dense_solve(&kkt, &rhs)?;
    let residual = &kkt * &solution - &rhs;
    solution -= dense_solve(&kkt, &residual)?;
    // w = −G z_p − Y λ.
    let w = -(&gy * &solution);
    progress.report(0.9)?;
    require_finite(w.col_as_slice(0).iter().flat_map(|z| [z.re, z.im]), "constrained natural conformal")?;
    let uv: Vec<[f64; 2]> = (0..mesh.vertex_count())
        .map(|v| match (split.iter().position(|&s| s as usize == v), system.unknowns.index[v]) {
            (Some(a), _) => [solution[(a, 0)].re, solution[(a, 0)].im],
            (None, NONE) => [f64::NAN; 2],
            (None, r) => [w[(r as usize, 0)].re, w[(r as usize, 0)].im],
        })
        .collect();
    // Constraints left out as dependent must hold.
    let x = Mat::<f64>::from_fn(mesh.vertex_count(), 2, |v, c| if uv[v][c].is_finite() { uv[v][c] } else { 0.0 });
    let targets = Mat::<f64>::from_fn(constraints.len(), 2, |i, c| constraints[i].uv[c]);
    let scale = 1.0 + constraints.iter().fold(0.0f64, |a, c| a.max(c.uv[0].abs()).max(c.uv[1].abs()));
    check_dropped(&full, &targets, &Mat::zeros(constraints.len(), 2), &kept, &x, 1e-9 * scale)?;
    progress.report(1.0)?;
    Ok(uv)
}

/// Row `p` of the conformal matrix `H` (see [`super::conformal`]): its real diagonal
/// `Σ_j w_pj` and `(j, H_pj)` for each neighbour j, with `w = ½(cot α + cot β)` and `± i/2` on
/// boundary edges (`H_ab = −w + i/2` for a boundary half-edge a→b).
fn conformal_row(mesh: &TriMesh, p: u32) -> (f64, Vec<(u32, c64)>) {
    use crate::mesh::connectivity::prev;
    let cot = &mesh.geometry().cot;
    let twin = &mesh.connectivity().twin;
    let half_cot = |h: u32| 0.5 * cot[(h / 3) as usize][((h % 3 + 2) % 3) as usize];
    let (mut diagonal, mut row) = (0.0, Vec::new());
    for h in mesh.outgoing_halfedges(p) {
        // Edge p→j (interior, or boundary with the surface on its left).
        let t = twin[h as usize];
        let w = half_cot(h) + if t == NONE { 0.0 } else { half_cot(t) };
        diagonal += w;
        row.push((mesh.head(h), c64::new(-w, if t == NONE { 0.5 } else { 0.0 })));
        // The incoming boundary edge k→p appears only as prev of an outgoing half-edge.
        let g = prev(h);
        if twin[g as usize] == NONE {
            let w = half_cot(g);
            diagonal += w;
            row.push((mesh.tail(g), c64::new(-w, -0.5)));
        }
    }
    (diagonal, row)
}

/// Natural conformal map with any number ≥ 2 of pinned vertices (each pin is a vertex
/// constraint; with exactly two this is the 2-pin natural conformal map).
pub fn pinned_natural_conformal_map(mesh: &TriMesh, pins: &[Pin], progress: &mut Progress) -> Result<Vec<[f64; 2]>> {
    let constraints = pins
        .iter()
        .map(|&(v, uv)| {
            if v as usize >= mesh.vertex_count() || !mesh.is_referenced(v) {
                return Err(Error::InvalidArgument(format!(
                    "pinned vertex {v} is not a vertex of the mesh's triangles"
                )));
            }
            vertex_constraint(mesh, v, uv)
                .ok_or_else(|| Error::InvalidArgument(format!("pinned vertex {v} is in no triangle")))
        })
        .collect::<Result<Vec<_>>>()?;
    constrained_natural_conformal_map(mesh, &constraints, progress)
}
