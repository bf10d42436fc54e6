//! QuadCover, step 4 (an addition to the course notes' §8.3): untangling the folds that the
//! rounding and the stiffening leave, with every lattice unknown kept — so the transition
//! functions `J^r z + t`, the integer gaps and the cones' grid points do not change, only the
//! positions of regular vertices near folds move.
//!
//! The energy is the untangling energy of Garanzha, Kaporin, Kudryavtseva, Protais, Ray &
//! Sokolov 2021 ("Foldover-free maps in 50 lines of code", ACM TOG 40(4), §3–4, read for the
//! idea): per triangle, with J the Jacobian of the map in an orthonormal frame of the
//! triangle's plane divided by the grid scale (so that the field's ideal map has J = I),
//! D = det J and the regularized determinant χ(D, ε) = (D + √(ε² + D²)) / 2 > 0,
//!
//! ```text
//! E_ε = Σ_T A_T [ (1 − λ) |J|²_F / χ(D, ε) + λ (D² + 1) / χ(D, ε) ]
//! ```
//!
//! (a shape term, the conformal distortion, and an area term, both minimal at J = I). E_ε is
//! finite for folded triangles, so minimization can start from a folded map; as ε → 0 the
//! terms become barriers against D ≤ 0. The outer loop lowers ε so that the smallest
//! regularized determinant shrinks by the factor (1 − σ), σ the energy's last relative decrease
//! (at least 1/10): with μ = (1 − σ) χ(D_min, ε), the next ε solves χ(D_min, ε) = μ, i.e.
//! ε² = 4 μ (μ − D_min), and once D_min ≥ μ the barrier is used (ε = 10⁻⁸). The inner loop is
//! Newton's method on per-triangle Hessians projected onto the positive semidefinite cone, with
//! Armijo backtracking.
//!
//! The free unknowns are the real unknowns of the vertices within a few rings of the folded
//! triangles, in groups that share no triangle (solved in parallel); a group's new positions
//! are kept only when its triangles fold less than before. Groups still folded are tried again
//! with wider rings ([`RINGS`]).

use super::covering::Covering;
use super::guards::is_fixed;
use super::integration::{corner_uv, evaluate};
use crate::error::Result;
use crate::geometry::{cross, dot, norm, sub};
use crate::mesh::cut::Cut;
use crate::metrics::signed_uv_area;
use crate::TriMesh;
use faer::{Mat, Side};
use rayon::prelude::*;
use std::collections::HashMap;
use uvflat_sparse::union_find::{find, union};
use uvflat_sparse::{CholeskySolver, TripletBuilder};

/// Ring widths of the successive attempts around the folds.
const RINGS: [usize; 2] = [2, 6];

/// Weight λ of the area term.
const AREA_WEIGHT: f64 = 0.5;

/// Outer (ε) iterations and Newton iterations per ε at most.
const OUTER_ITERATIONS: usize = 40;
const NEWTON_ITERATIONS: usize = 8;

/// What the untangling did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct UntangleReport {
    /// Folded triangles before and after.
    pub folded_before: usize,
    pub folded_after: usize,
    /// Groups of free vertices optimized, and how many of them were kept.
    pub groups: usize,
    pub groups_kept: usize,
    /// Folded triangles that no untangling can open: two of their corners are fixed at the same
    /// point by the lattice unknowns (e.g. two cones rounded onto one grid point).
    pub forced_flat: usize,
}

/// One triangle of a group's energy: area, hat-function gradients in its frame divided by the
/// grid scale, and per corner and component the constant part and the free terms.
struct Term {
    area: f64,
    grads: [[f64; 2]; 3],
    constant: [[f64; 2]; 3],
    free: [[Vec<(usize, f64)>; 2]; 3],
}

/// A group: the global indices of its free unknowns and its energy terms.
struct Group {
    unknowns: Vec<u32>,
    terms: Vec<Term>,
}

/// Untangles `values` in place (module comment).
pub fn untangle(
    mesh: &TriMesh,
    cut: &Cut,
    scale: f64,
    covering: &Covering,
    values: &mut [f64],
) -> Result<UntangleReport> {
    let folded = |values: &[f64]| -> Vec<usize> {
        corner_uv(cut, covering, values)
            .iter()
            .enumerate()
            .filter(|(_, q)| signed_uv_area(**q) <= 0.0)
            .map(|(t, _)| t)
            .collect()
    };
    let mut report = UntangleReport { folded_before: folded(values).len(), ..Default::default() };
    let geometry = TriangleFrames::new(mesh, scale);
    for rings in RINGS {
        let flips = folded(values);
        if flips.is_empty() {
            break;
        }
        let groups = groups_around(mesh, cut, covering, &geometry, values, &flips, rings);
        report.groups += groups.len();
        let solved: Vec<Option<Vec<f64>>> = groups.par_iter().map(|g| solve_group(g, values)).collect::<Result<_>>()?;
        for (group, x) in groups.iter().zip(solved) {
            if let Some(x) = x {
                report.groups_kept += 1;
                for (&k, &value) in group.unknowns.iter().zip(&x) {
                    values[k as usize] = value;
                }
            }
        }
    }
    report.folded_after = folded(values).len();
    report.forced_flat = forced_flat_triangles(cut, covering, values);
    Ok(report)
}

/// Per triangle: area and the hat-function gradients in an orthonormal frame of its plane,
/// divided by the grid scale (zero area for a degenerate triangle).
struct TriangleFrames {
    area: Vec<f64>,
    grads: Vec<[[f64; 2]; 3]>,
}

impl TriangleFrames {
    fn new(mesh: &TriMesh, scale: f64) -> Self {
        let (area, grads) = (0..mesh.triangle_count())
            .map(|t| {
                let p = mesh.triangles()[t].map(|v| mesh.points()[v as usize]);
                let nn = cross(sub(p[1], p[0]), sub(p[2], p[0]));
                let twice = norm(nn);
                let e1 = sub(p[1], p[0]);
                let l1 = norm(e1);
                if !(twice > f64::MIN_POSITIVE && l1 > 0.0) {
                    return (0.0, [[0.0; 2]; 3]);
                }
                let n = nn.map(|x| x / twice);
                let e1 = e1.map(|x| x / l1);
                let e2 = cross(n, e1);
                let grads = std::array::from_fn(|i| {
                    let g = cross(n, sub(p[(i + 2) % 3], p[(i + 1) % 3])).map(|x| x / twice);
                    [dot(g, e1) / scale, dot(g, e2) / scale]
                });
                (0.5 * twice, grads)
            })
            .unzip();
        TriangleFrames { area, grads }
    }
}

/// The groups of free unknowns around `flips`: the vertices within `rings` rings of a folded
/// triangle, their real unknowns free, split into groups no triangle couples.
fn groups_around(
    mesh: &TriMesh,
    cut: &Cut,
    covering: &Covering,
    geometry: &TriangleFrames,
    values: &[f64],
    flips: &[usize],
    rings: usize,
) -> Vec<Group> {
    let nv = covering.vertex_unknowns;
    let mut inside = vec![false; mesh.vertex_count()];
    for &t in flips {
        for v in mesh.triangles()[t] {
            inside[v as usize] = true;
        }
    }
    for _ in 0..rings {
        let touching: Vec<usize> =
            (0..mesh.triangle_count()).filter(|&t| mesh.triangles()[t].iter().any(|&v| inside[v as usize])).collect();
        for t in touching {
            for v in mesh.triangles()[t] {
                inside[v as usize] = true;
            }
        }
    }
    // Free unknowns: the real unknowns of the corners of inside vertices.
    let mut free = vec![false; nv];
    for (c, rows) in covering.rows.iter().enumerate() {
        if inside[cut.original[c] as usize] {
            for &(k, _) in rows.iter().flatten() {
                if (k as usize) < nv {
                    free[k as usize] = true;
                }
            }
        }
    }
    // Triangles that see a free unknown, and the groups they couple (union–find).
    let mut parent: Vec<u32> = (0..nv as u32).collect();
    let mut terms_of: Vec<usize> = Vec::new();
    for t in 0..mesh.triangle_count() {
        let ks: Vec<u32> =
            triangle_unknowns(cut, covering, t).filter(|&k| (k as usize) < nv && free[k as usize]).collect();
        if ks.is_empty() || geometry.area[t] <= 0.0 {
            continue;
        }
        terms_of.push(t);
        for &k in &ks[1..] {
            union(&mut parent, ks[0], k);
        }
    }
    let mut group_of: HashMap<u32, usize> = HashMap::new();
    let mut groups: Vec<(Vec<u32>, Vec<usize>)> = Vec::new();
    for k in (0..nv as u32).filter(|&k| free[k as usize]) {
        let root = find(&mut parent, k);
        let g = *group_of.entry(root).or_insert_with(|| {
            groups.push((Vec::new(), Vec::new()));
            groups.len() - 1
        });
        groups[g].0.push(k);
    }
    for t in terms_of {
        let k = triangle_unknowns(cut, covering, t).find(|&k| (k as usize) < nv && free[k as usize]).unwrap();
        let g = group_of[&find(&mut parent, k)];
        groups[g].1.push(t);
    }
    groups
        .into_iter()
        .map(|(unknowns, triangles)| {
            let local: HashMap<u32, usize> = unknowns.iter().enumerate().map(|(i, &k)| (k, i)).collect();
            let terms = triangles
                .iter()
                .map(|&t| term(cut, covering, geometry, values, &local, t))
                .filter(|term| !term.is_forced_flat())
                .collect();
            Group { unknowns, terms }
        })
        .collect()
}

/// Whether two corners that no real unknown moves (`Some` position) are at the same point — two
/// cones rounded onto one grid point, or a cone and its neighbour's fixed copy: no untangling
/// can open such a triangle.
fn two_fixed_corners_coincide(fixed: [Option<[f64; 2]>; 3]) -> bool {
    (0..3).any(|i| {
        let (Some(p), Some(q)) = (fixed[i], fixed[(i + 1) % 3]) else { return false };
        super::guards::same_point(p, q)
    })
}

/// Triangles of the map that are flat whatever its real unknowns
/// ([`two_fixed_corners_coincide`]).
fn forced_flat_triangles(cut: &Cut, covering: &Covering, values: &[f64]) -> usize {
    let fixed_position = |c: u32| -> Option<[f64; 2]> {
        is_fixed(covering, c).then(|| covering.rows[c as usize].each_ref().map(|r| evaluate(r, values)))
    };
    cut.triangles.iter().filter(|tri| two_fixed_corners_coincide(tri.map(fixed_position))).count()
}

/// Every unknown referenced by the corners of triangle `t`.
fn triangle_unknowns<'a>(cut: &'a Cut, covering: &'a Covering, t: usize) -> impl Iterator<Item = u32> + 'a {
    cut.triangles[t].into_iter().flat_map(move |c| covering.rows[c as usize].iter().flatten().map(|&(k, _)| k))
}

/// The energy term of triangle `t`, its free unknowns numbered by `local`.
fn term(
    cut: &Cut,
    covering: &Covering,
    geometry: &TriangleFrames,
    values: &[f64],
    local: &HashMap<u32, usize>,
    t: usize,
) -> Term {
    let mut constant = [[0.0; 2]; 3];
    let mut free: [[Vec<(usize, f64)>; 2]; 3] = Default::default();
    for (i, &c) in cut.triangles[t].iter().enumerate() {
        for comp in 0..2 {
            for &(k, x) in &covering.rows[c as usize][comp] {
                match local.get(&k) {
                    Some(&j) => free[i][comp].push((j, x)),
                    None => constant[i][comp] += x * values[k as usize],
                }
            }
        }
    }
    Term { area: geometry.area[t], grads: geometry.grads[t], constant, free }
}

impl Term {
    /// Whether the triangle is flat whatever the free unknowns ([`two_fixed_corners_coincide`]);
    /// its energy would only pull its free corner onto the other two, so it is left out.
    fn is_forced_flat(&self) -> bool {
        two_fixed_corners_coincide(std::array::from_fn(|i| {
            self.free[i].iter().all(|c| c.is_empty()).then_some(self.constant[i])
        }))
    }

    /// Corner (u, v) for the free values `x`.
    fn corners(&self, x: &[f64]) -> [[f64; 2]; 3] {
        std::array::from_fn(|i| {
            std::array::from_fn(|comp| {
                self.constant[i][comp] + self.free[i][comp].iter().map(|&(j, a)| a * x[j]).sum::<f64>()
            })
        })
    }

    /// J = Σ_i q_i ⊗ g_i (rows u, v; columns the frame's axes).
    fn jacobian(&self, q: &[[f64; 2]; 3]) -> [[f64; 2]; 2] {
        std::array::from_fn(|r| std::array::from_fn(|c| (0..3).map(|i| q[i][r] * self.grads[i][c]).sum()))
    }
}

/// χ(D, ε) and dχ/dD.
fn chi(d: f64, eps: f64) -> (f64, f64) {
    let root = (eps * eps + d * d).sqrt();
    (0.5 * (d + root), 0.5 * (1.0 + d / root))
}

/// E_ε of one triangle per unit area and its derivative with respect to J.
fn local_energy(j: &[[f64; 2]; 2], eps: f64) -> (f64, [[f64; 2]; 2]) {
    let f = j[0][0] * j[0][0] + j[0][1] * j[0][1] + j[1][0] * j[1][0] + j[1][1] * j[1][1];
    let d = j[0][0] * j[1][1] - j[0][1] * j[1][0];
    let (c, dc) = chi(d, eps);
    let lambda = AREA_WEIGHT;
    let e = ((1.0 - lambda) * f + lambda * (d * d + 1.0)) / c;
    // ∂/∂D of the numerators over χ, then through D's cofactor; the shape term also through |J|².
    let de_dd = (lambda * 2.0 * d) / c - e * dc / c;
    let cof = [[j[1][1], -j[1][0]], [-j[0][1], j[0][0]]];
    let g = std::array::from_fn(|r| std::array::from_fn(|s| (1.0 - lambda) * 2.0 * j[r][s] / c + de_dd * cof[r][s]));
    (e, g)
}

/// Energy, gradient and smallest determinant of a group at `x`.
fn group_energy(group: &Group, x: &[f64], eps: f64, gradient: Option<&mut [f64]>) -> (f64, f64) {
    let mut energy = 0.0;
    let mut d_min = f64::INFINITY;
    let mut grad = gradient;
    if let Some(g) = grad.as_deref_mut() {
        g.iter_mut().for_each(|v| *v = 0.0);
    }
    for term in &group.terms {
        let q = term.corners(x);
        let j = term.jacobian(&q);
        d_min = d_min.min(j[0][0] * j[1][1] - j[0][1] * j[1][0]);
        let (e, de) = local_energy(&j, eps);
        energy += term.area * e;
        if let Some(g) = grad.as_deref_mut() {
            for (i, free) in term.free.iter().enumerate() {
                for (row, terms) in de.iter().zip(free) {
                    let dq = term.area * (row[0] * term.grads[i][0] + row[1] * term.grads[i][1]);
                    for &(k, a) in terms {
                        g[k] += a * dq;
                    }
                }
            }
        }
    }
    (energy, d_min)
}

/// Folded triangles of a group at `x`.
fn group_folds(group: &Group, x: &[f64]) -> usize {
    group.terms.iter().filter(|t| signed_uv_area(t.corners(x)) <= 0.0).count()
}

/// Minimizes the group's energy (module comment); the free values if the group folds less.
fn solve_group(group: &Group, values: &[f64]) -> Result<Option<Vec<f64>>> {
    let x0: Vec<f64> = group.unknowns.iter().map(|&k| values[k as usize]).collect();
    let before = group_folds(group, &x0);
    if before == 0 {
        return Ok(None);
    }
    let (mut best, mut best_folds) = (x0.clone(), before);
    let mut x = x0;
    let (_, mut d_min) = group_energy(group, &x, 1e-8, None);
    let mut eps = next_epsilon(d_min, 0.1, 1e-8);
    let mut energy = group_energy(group, &x, eps, None).0;
    for _ in 0..OUTER_ITERATIONS {
        let barrier = eps <= 1e-8;
        let new_energy = newton(group, &mut x, eps)?;
        d_min = group_energy(group, &x, eps, None).1;
        let folds = group_folds(group, &x);
        if folds < best_folds {
            (best, best_folds) = (x.clone(), folds);
        }
        if barrier && d_min > 0.0 {
            break;
        }
        let sigma = (1.0 - new_energy / energy).max(0.1);
        let mu = (1.0 - sigma) * chi(d_min, eps).0;
        eps = next_epsilon(d_min, mu, 1e-8);
        energy = group_energy(group, &x, eps, None).0;
    }
    // The iterate with the fewest folds (the barrier phase never adds any, but the
    // regularized phase may).
    let after = group_folds(group, &x);
    if best_folds < after {
        x = best;
    }
    let after = after.min(best_folds);
    Ok((x.iter().all(|v| v.is_finite()) && after < before).then_some(x))
}

/// The ε with χ(D_min, ε) = μ, or `floor` once D_min ≥ μ.
fn next_epsilon(d_min: f64, mu: f64, floor: f64) -> f64 {
    if d_min < mu {
        (4.0 * mu * (mu - d_min)).sqrt().max(floor)
    } else {
        floor
    }
}

/// Newton's method with Armijo backtracking on the group's E_ε from `x` (in place): each
/// triangle's Hessian in J is projected onto the positive semidefinite cone
/// ([`local_hessian`]), so every step is a descent direction. Returns the energy.
fn newton(group: &Group, x: &mut [f64], eps: f64) -> Result<f64> {
    let n = x.len();
    let mut g = vec![0.0; n];
    let (mut e, _) = group_energy(group, x, eps, Some(&mut g));
    let mut trial = vec![0.0; n];
    for _ in 0..NEWTON_ITERATIONS {
        let Some(d) = newton_direction(group, x, eps, &g)? else { break };
        let slope = vec_dot(&g, &d);
        if !(slope < 0.0) {
            break;
        }
        let mut t = 1.0;
        let mut accepted = false;
        for _ in 0..40 {
            trial.iter_mut().zip(x.iter().zip(&d)).for_each(|(y, (a, b))| *y = a + t * b);
            let e_new = group_energy(group, &trial, eps, None).0;
            if e_new.is_finite() && e_new <= e + 1e-4 * t * slope {
                x.copy_from_slice(&trial);
                let decrease = e - e_new;
                e = group_energy(group, x, eps, Some(&mut g)).0;
                accepted = true;
                if decrease <= 1e-10 * e.abs() {
                    return Ok(e);
                }
                break;
            }
            t *= 0.5;
        }
        if !accepted {
            break;
        }
    }
    Ok(e)
}

/// The Newton direction −H⁺⁻¹ g (H⁺ the sum of the projected triangle Hessians plus a small
/// multiple of its mean diagonal); `None` when the system cannot be factored.
fn newton_direction(group: &Group, x: &[f64], eps: f64, g: &[f64]) -> Result<Option<Vec<f64>>> {
    let n = x.len();
    let mut h = TripletBuilder::with_capacity(n, 40 * group.terms.len());
    let mut diagonal = vec![0.0; n];
    for term in &group.terms {
        let q = term.corners(x);
        let hj = local_hessian(&term.jacobian(&q), eps);
        // d j[2r + s] / d x_k = Σ_i a_{i,r,k} g_i[s]: the columns of G per free unknown.
        let mut columns: Vec<(usize, [f64; 4])> = Vec::with_capacity(6);
        for i in 0..3 {
            for comp in 0..2 {
                for &(k, a) in &term.free[i][comp] {
                    let mut col = [0.0; 4];
                    col[2 * comp] = a * term.grads[i][0];
                    col[2 * comp + 1] = a * term.grads[i][1];
                    match columns.iter_mut().find(|(kk, _)| *kk == k) {
                        Some((_, c)) => (0..4).for_each(|m| c[m] += col[m]),
                        None => columns.push((k, col)),
                    }
                }
            }
        }
        for (a, ca) in &columns {
            let hca: [f64; 4] = std::array::from_fn(|r| (0..4).map(|c| hj[r][c] * ca[c]).sum());
            for (b, cb) in &columns {
                if b <= a {
                    let value = term.area * (0..4).map(|r| cb[r] * hca[r]).sum::<f64>();
                    h.add(*a, *b, value);
                    if a == b {
                        diagonal[*a] += value;
                    }
                }
            }
        }
    }
    let shift = 1e-9 * diagonal.iter().sum::<f64>() / n as f64 + f64::MIN_POSITIVE;
    for k in 0..n {
        h.add(k, k, shift);
    }
    let Ok(solver) = CholeskySolver::new(&h.build()?, None) else { return Ok(None) };
    let mut rhs = Mat::<f64>::from_fn(n, 1, |k, _| -g[k]);
    solver.solve_in_place(&mut rhs)?;
    let d: Vec<f64> = (0..n).map(|k| rhs[(k, 0)]).collect();
    Ok(d.iter().all(|v| v.is_finite()).then_some(d))
}

/// The Hessian of [`local_energy`] with respect to j = (J₀₀, J₀₁, J₁₀, J₁₁), projected onto
/// the positive semidefinite cone (negative eigenvalues set to zero). With N the numerator,
/// c = χ(D, ε): ∇²(N/c) = ∇²N/c − (c′/c²)(∇N ∇Dᵀ + ∇D ∇Nᵀ) − (N/c²)(c″ ∇D∇Dᵀ + c′ ∇²D)
/// + (2 N c′²/c³) ∇D∇Dᵀ.
fn local_hessian(j: &[[f64; 2]; 2], eps: f64) -> [[f64; 4]; 4] {
    let m = exact_local_hessian(j, eps);
    let mut out = [[0.0; 4]; 4];
    let Ok(eig) = m.self_adjoint_eigen(Side::Lower) else { return out };
    let (u, s) = (eig.U(), eig.S());
    for k in 0..4 {
        let l = s[k].max(0.0);
        if l > 0.0 {
            for r in 0..4 {
                for q in 0..4 {
                    out[r][q] += l * u[(r, k)] * u[(q, k)];
                }
            }
        }
    }
    out
}

/// The Hessian of [`local_energy`] with respect to j (formula at [`local_hessian`]).
fn exact_local_hessian(j: &[[f64; 2]; 2], eps: f64) -> Mat<f64> {
    let v = [j[0][0], j[0][1], j[1][0], j[1][1]];
    let d = v[0] * v[3] - v[1] * v[2];
    let f: f64 = v.iter().map(|x| x * x).sum();
    let lambda = AREA_WEIGHT;
    let root = (eps * eps + d * d).sqrt();
    let (c, dc, ddc) = (0.5 * (d + root), 0.5 * (1.0 + d / root), 0.5 * eps * eps / (root * root * root));
    let numerator = (1.0 - lambda) * f + lambda * (d * d + 1.0);
    let grad_d = [v[3], -v[2], -v[1], v[0]];
    let hess_d = |r: usize, s: usize| match (r, s) {
        (0, 3) | (3, 0) => 1.0,
        (1, 2) | (2, 1) => -1.0,
        _ => 0.0,
    };
    let grad_n: [f64; 4] = std::array::from_fn(|r| 2.0 * (1.0 - lambda) * v[r] + 2.0 * lambda * d * grad_d[r]);
    Mat::<f64>::from_fn(4, 4, |r, s| {
        let hess_n = 2.0 * (1.0 - lambda) * f64::from(u8::from(r == s))
            + 2.0 * lambda * (grad_d[r] * grad_d[s] + d * hess_d(r, s));
        hess_n / c
            - dc / (c * c) * (grad_n[r] * grad_d[s] + grad_d[r] * grad_n[s])
            - numerator / (c * c) * (ddc * grad_d[r] * grad_d[s] + dc * hess_d(r, s))
            + 2.0 * numerator * dc * dc / (c * c * c) * grad_d[r] * grad_d[s]
    })
}

fn vec_dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn energy_gradient_matches_finite_differences() {
        for (j, eps) in [([[1.1, 0.2], [-0.1, 0.9]], 1e-8), ([[0.7, -0.4], [0.3, -0.2]], 0.3)] {
            let (_, g) = local_energy(&j, eps);
            for r in 0..2 {
                for s in 0..2 {
                    let h = 1e-6;
                    let mut a = j;
                    let mut b = j;
                    a[r][s] += h;
                    b[r][s] -= h;
                    let fd = (local_energy(&a, eps).0 - local_energy(&b, eps).0) / (2.0 * h);
                    assert!((fd - g[r][s]).abs() < 1e-5 * (1.0 + fd.abs()), "eps {eps} ({r},{s}): {fd} vs {}", g[r][s]);
                }
            }
        }
    }

    #[test]
    fn hessian_matches_finite_differences() {
        for (j, eps) in [([[1.1, 0.2], [-0.1, 0.9]], 1e-8), ([[0.7, -0.4], [0.3, -0.2]], 0.3)] {
            let h = exact_local_hessian(&j, eps);
            let h = |r: usize, c: usize| h[(r, c)];
            let flat = |v: [f64; 4]| [[v[0], v[1]], [v[2], v[3]]];
            let base = [j[0][0], j[0][1], j[1][0], j[1][1]];
            for a in 0..4 {
                let step = 1e-6;
                let (mut p, mut m) = (base, base);
                p[a] += step;
                m[a] -= step;
                let (gp, gm) = (local_energy(&flat(p), eps).1, local_energy(&flat(m), eps).1);
                for b in 0..4 {
                    let fd = (gp[b / 2][b % 2] - gm[b / 2][b % 2]) / (2.0 * step);
                    assert!((fd - h(b, a)).abs() < 1e-6 * (1.0 + fd.abs()), "eps {eps} ({a},{b}): {fd} vs {}", h(b, a));
                }
            }
        }
    }

    #[test]
    fn the_projected_hessian_of_a_folded_triangle_is_semidefinite() {
        let h = local_hessian(&[[0.5, 0.3], [0.8, -0.4]], 0.01);
        let m = Mat::<f64>::from_fn(4, 4, |r, s| h[r][s]);
        let smallest = m.self_adjoint_eigenvalues(Side::Lower).unwrap().into_iter().fold(f64::INFINITY, f64::min);
        assert!(smallest > -1e-9 * h.iter().flatten().fold(0.0f64, |a, b| a.max(b.abs())), "{smallest}");
    }

    #[test]
    fn identity_is_the_minimum_of_the_barrier() {
        let (e, g) = local_energy(&[[1.0, 0.0], [0.0, 1.0]], 0.0);
        assert!((e - 2.0).abs() < 1e-12);
        assert!(g.iter().flatten().all(|v| v.abs() < 1e-12), "{g:?}");
    }
}
