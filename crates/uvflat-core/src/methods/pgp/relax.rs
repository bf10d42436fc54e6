//! Global phase relaxation of PGP's per-triangle parameterization with its integers fixed (not
//! in Ray et al. 2006; a step between Algorithm 1's extraction, §3.1, and the local
//! [`super::untangle`]).
//!
//! Algorithm 1 sets each corner from its vertex's phases, `c_T(v) = P^ρ (θ_v, φ_v) + 2π (s, t)`
//! ([`super::extraction`]). Turning every vertex's phases by Δ_v moves its corners by `P^ρ Δ_v`
//! and changes no integer, hence no transition (eq. 16) and no open triangle. The turns are the
//! least-squares fit of the (θ, φ) triangles to the field, the Dirichlet energy of the
//! difference between each triangle's map and eq. 13's expected increments, in cotangent form:
//!
//! ```text
//! min_Δ  Σ_T Σ_{(i,j) ⊂ T} (cot α_k / 2) ‖P^ρj Δ_j − P^ρi Δ_i + (c_T(j) − c_T(i) − δ_ij)‖²
//!        + λ Σ_v ‖Δ_v‖²
//! ```
//!
//! over the triangles that are not open (α_k the angle opposite edge (i, j), δ_ij eq. 13's
//! increment in T's frame). Each triangle's term is positive semidefinite (a linear map's
//! Dirichlet energy), even with the negative cotangents of obtuse triangles; λ (a small
//! fraction of the mean diagonal) keeps the vertices of open triangles only in place and
//! removes the null space. One sparse Cholesky solve with 2 unknowns per vertex.
//!
//! Why: the periodic solve's phases are poorly determined where ‖U‖ is small (near singular
//! points, §2.5), and a sliver's (θ, φ) triangle flips with any error across its thin side,
//! which the cotangent weights make the costliest (the weight of a sliver's short edge is the
//! cotangent of its tiny angle).
//!
//! The fit is a least-squares one and can also flip a triangle that was positive (on cow with
//! curl correction it left 9 more singular triangles), so [`relax_if_better`] keeps it only when,
//! after the untangling that follows, it leaves fewer singular triangles (§3.2: open or of
//! non-positive area) than the untangling alone, or as many.
//!
//! Measured (README, "Periodic Global Parameterization", `scripts/pgp_quality.sh`): singular
//! triangles PGP / ccPGP on the 15 closed meshes, before → with the relaxation (alone, without the
//! keep-if-better test): eight 2.05 / 1.89 → 1.26 / 1.26%, knight 3.00 / 2.80 → 2.90 / 2.80%, man
//! 0.82 / 0.87 → 0.71 / 0.85%, cheese 24.82 / 27.94 → 21.41 / 23.91%; armadillo, bunny,
//! nefertiti, triple torus, kitten and cow 0.01–0.03 points lower in one mode or both; higher
//! only with curl correction on cow (1.12 → 1.27%) and spot (0.39 → 0.40%), which the test
//! refuses; the others equal. On the 207k-face disk of `crates/uvflat-core/benches/pgp.rs` (with boundary) it is
//! refused too (518 against 506 singular triangles). Not kept: re-solving with the weights of
//! the triangles still negative multiplied by 10, three rounds (cheese 4198 → 5283 negative
//! triangles before the untangling, cow refused).
//!
//! Cost: O(F) assembly and one factorization of a 2V × 2V matrix.

use super::extraction::CornerParameterization;
use super::periodic::{corner_frames, expected_increments};
use super::singularities::singular_triangle_count;
use super::untangle::{apply_move, turn_phases, untangle, UntangleReport};
use crate::error::{Error, Result};
use crate::fields::frames::rotate_coords;
use crate::geometry::{cross, dot, norm, sub};
use crate::mesh::NONE;
use crate::TriMesh;
use faer::Mat;
use uvflat_sparse::{lower_from_entries, CholeskySolver};

/// λ over the mean diagonal entry of the fit.
pub const RELAX_REGULARIZATION: f64 = 1e-4;

/// What the relaxation did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct RelaxReport {
    /// Whether the relaxed phases were kept.
    pub kept: bool,
    /// Singular triangles (§3.2) after the untangling without the relaxation.
    pub singular_without: usize,
    /// The same with it (equal to `singular_without` when the relaxation did not run).
    pub singular_with: usize,
}

/// The untangling of `param` when `enabled`, else its report of no change.
pub(super) fn untangled(
    mesh: &TriMesh,
    param: &mut CornerParameterization,
    unknowns: &mut [[f64; 4]],
    field: &[[f64; 3]],
    omega: f64,
    enabled: bool,
) -> UntangleReport {
    if enabled {
        untangle(mesh, param, unknowns, field, omega)
    } else {
        UntangleReport::untouched(param)
    }
}

/// Untangles `param` (when `untangle` is set) with and without relaxing it first
/// ([`relax_phases`]) and keeps the one with fewer singular triangles, the relaxed one on a tie
/// (module comment). `param` and `unknowns` are replaced by the kept ones.
#[allow(clippy::too_many_arguments)]
pub fn relax_if_better(
    mesh: &TriMesh,
    normals: &[[f64; 3]],
    field: &[[f64; 3]],
    param: &mut CornerParameterization,
    unknowns: &mut [[f64; 4]],
    omega: f64,
    untangle: bool,
) -> Result<(UntangleReport, RelaxReport)> {
    let (mut relaxed, mut relaxed_unknowns) = (param.clone(), unknowns.to_vec());
    let plain = untangled(mesh, param, unknowns, field, omega, untangle);
    let without = singular_triangle_count(param);
    match relax_phases(mesh, normals, field, &mut relaxed, &mut relaxed_unknowns, omega) {
        Ok(_) => {}
        // A fit the factorization refuses (round-off on nearly degenerate triangles) is not
        // used: the untangled parameterization stands.
        Err(Error::Numerical(_)) => {
            return Ok((plain, RelaxReport { kept: false, singular_without: without, singular_with: without }))
        }
        Err(e) => return Err(e),
    }
    let report = untangled(mesh, &mut relaxed, &mut relaxed_unknowns, field, omega, untangle);
    let with = singular_triangle_count(&relaxed);
    let kept = with <= without;
    if kept {
        *param = relaxed;
        unknowns.copy_from_slice(&relaxed_unknowns);
    }
    let relax = RelaxReport { kept, singular_without: without, singular_with: with };
    Ok((if kept { report } else { plain }, relax))
}

/// Sine of an angle below which a triangle is left out of the fit (its cotangent weights would
/// exceed 10⁶ and swamp the others' round-off).
const DEGENERATE_SINE: f64 = 1e-6;

/// Cotangents of the three angles of a 3D triangle; `None` when an angle's sine is below
/// [`DEGENERATE_SINE`].
fn cotangents(p: &[[f64; 3]; 3]) -> Option<[f64; 3]> {
    let cot = |k: usize| {
        let (a, b) = (sub(p[(k + 1) % 3], p[k]), sub(p[(k + 2) % 3], p[k]));
        let s = norm(cross(a, b));
        (s > DEGENERATE_SINE * (dot(a, a) * dot(b, b)).sqrt()).then(|| dot(a, b) / s)
    };
    Some([cot(0)?, cot(1)?, cot(2)?])
}

/// The 2×2 matrix of the phase rotation `P^r`, by columns.
fn rotation_matrix(r: u8) -> [[f64; 2]; 2] {
    let c0 = rotate_coords(r, [1.0, 0.0]);
    let c1 = rotate_coords(r, [0.0, 1.0]);
    [[c0[0], c1[0]], [c0[1], c1[1]]]
}

/// The normal equations of the fit, 2 rows per block (referenced vertex).
struct Fit {
    diagonal: Vec<f64>,
    entries: Vec<(u32, u32, f64)>,
    rhs: Mat<f64>,
}

impl Fit {
    fn new(blocks: usize) -> Self {
        Fit { diagonal: vec![0.0; 2 * blocks], entries: Vec::new(), rhs: Mat::zeros(2 * blocks, 1) }
    }

    /// Adds `w ‖R_j Δ_j − R_i Δ_i + e‖²` for blocks i, j with rotations `R = P^r`: gradient
    /// `w R_jᵀ r` at j and `−w R_iᵀ r` at i, off-diagonal block `−w R_iᵀ R_j = −w P^(rj − ri)`.
    fn add_edge(&mut self, (bi, ri): (usize, u8), (bj, rj): (usize, u8), w: f64, e: [f64; 2]) {
        let (gi, gj) = (rotate_coords((4 - ri) % 4, e), rotate_coords((4 - rj) % 4, e));
        for l in 0..2 {
            self.diagonal[2 * bi + l] += w;
            self.diagonal[2 * bj + l] += w;
            self.rhs[(2 * bi + l, 0)] += w * gi[l];
            self.rhs[(2 * bj + l, 0)] -= w * gj[l];
        }
        for (l, row) in rotation_matrix((4 + rj - ri) % 4).iter().enumerate() {
            for (c, &x) in row.iter().enumerate().filter(|&(_, &x)| x != 0.0) {
                let (a, b) = (2 * bi + l, 2 * bj + c);
                self.entries.push((a.max(b) as u32, a.min(b) as u32, -w * x));
            }
        }
    }

    /// Adds the terms of triangle t's three edges (`block`: the block of each vertex).
    fn add_triangle(
        &mut self,
        ctx: (&TriMesh, &[[f64; 3]], &[[f64; 3]], f64),
        param: &CornerParameterization,
        block: &[u32],
        t: usize,
    ) {
        let (mesh, normals, field, omega) = ctx;
        let tri = mesh.triangles()[t];
        let p = tri.map(|v| mesh.points()[v as usize]);
        let Some(cot) = cotangents(&p) else { return };
        let frames = corner_frames(mesh, normals, field, t);
        let q = &param.coords[t];
        for (k, cot) in cot.into_iter().enumerate() {
            let (i, j) = ((k + 1) % 3, (k + 2) % 3);
            let (d, dp) = expected_increments(&p, &frames, omega, i, j);
            let e = [q[j][0] - q[i][0] - d, q[j][1] - q[i][1] - dp];
            let bi = (block[tri[i] as usize] as usize, param.rotation[t][i]);
            let bj = (block[tri[j] as usize] as usize, param.rotation[t][j]);
            self.add_edge(bi, bj, 0.5 * cot, e);
        }
    }

    /// Δ per block: the solution with λ = [`RELAX_REGULARIZATION`] times the mean diagonal.
    fn solve(mut self) -> Result<Vec<[f64; 2]>> {
        let n = self.diagonal.len() / 2;
        let mean = self.diagonal.iter().map(|x| x.abs()).sum::<f64>() / self.diagonal.len().max(1) as f64;
        let lambda = RELAX_REGULARIZATION * mean.max(f64::MIN_POSITIVE);
        self.diagonal.iter_mut().for_each(|x| *x += lambda);
        let lower = lower_from_entries(&self.diagonal, self.entries)?;
        CholeskySolver::new(&lower, None)?.solve_in_place(&mut self.rhs)?;
        Ok((0..n).map(|b| [self.rhs[(2 * b, 0)], self.rhs[(2 * b + 1, 0)]]).collect())
    }
}

/// Relaxes `param` and `unknowns` in place (module comment); returns the number of vertices
/// whose phases moved.
pub fn relax_phases(
    mesh: &TriMesh,
    normals: &[[f64; 3]],
    field: &[[f64; 3]],
    param: &mut CornerParameterization,
    unknowns: &mut [[f64; 4]],
    omega: f64,
) -> Result<usize> {
    let vertex_of: Vec<u32> = (0..mesh.vertex_count() as u32).filter(|&v| mesh.is_referenced(v)).collect();
    if vertex_of.is_empty() {
        return Ok(0);
    }
    let mut block = vec![NONE; mesh.vertex_count()];
    for (b, &v) in vertex_of.iter().enumerate() {
        block[v as usize] = b as u32;
    }
    let mut fit = Fit::new(vertex_of.len());
    for t in (0..mesh.triangle_count()).filter(|&t| !param.open[t]) {
        fit.add_triangle((mesh, normals, field, omega), param, &block, t);
    }
    let mut moved = 0;
    for (&v, d) in vertex_of.iter().zip(fit.solve()?) {
        if d != [0.0, 0.0] {
            apply_move(mesh, param, v, d);
            unknowns[v as usize] = turn_phases(unknowns[v as usize], d);
            moved += 1;
        }
    }
    Ok(moved)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::methods::pgp::extraction::angles;
    use crate::methods::pgp::singularities::signed_area2;
    // An n × n grid of unit squares, the isometric parameterization (θ, φ) = (x, y) at ω = 1
    // (for the field (1, 0, 0)), vertex v's corners with rotation r.
    use crate::methods::pgp::untangle::tests::grid;

    #[test]
    fn phases_pushed_across_their_neighbours_are_relaxed_back_to_the_isometric_map() {
        for r in 0..4u8 {
            let (n, v, w) = (6, 24, 17); // the middle vertex (3, 3) and its neighbour (3, 2)
            let (mesh, mut param, mut unknowns) = grid(n, v, r);
            let (normals, field) = (vec![[0.0, 0.0, 1.0]; 49], vec![[1.0, 0.0, 0.0]; 49]);
            for (u, d) in [(v, [1.6, 1.4]), (w, [-1.2, 0.9])] {
                apply_move(&mesh, &mut param, u, d);
                unknowns[u as usize] = turn_phases(unknowns[u as usize], d);
            }
            assert!(param.coords.iter().filter(|q| signed_area2(q) <= 0.0).count() >= 2, "r = {r}");
            let before = param.clone();
            let moved = relax_phases(&mesh, &normals, &field, &mut param, &mut unknowns, 1.0).unwrap();
            assert_eq!(moved, 49, "r = {r}");
            assert_eq!((&param.rotation, &param.shift, &param.open), (&before.rotation, &before.shift, &before.open));
            // Every triangle is the isometric one again, up to a common translation.
            let offset = [param.coords[0][0][0], param.coords[0][0][1]];
            for (t, tri) in mesh.triangles().iter().enumerate() {
                for (k, &u) in tri.iter().enumerate() {
                    let p = mesh.points()[u as usize];
                    let got = param.coords[t][k];
                    let err = (got[0] - offset[0] - p[0]).abs().max((got[1] - offset[1] - p[1]).abs());
                    assert!(err < 1e-3, "r = {r}: corner {t}/{k} at {got:?}, vertex at {p:?}");
                    // Still its vertex's rotated phases plus whole periods.
                    let want = rotate_coords(param.rotation[t][k], angles(unknowns[u as usize]));
                    for (g, w) in got.iter().zip(want) {
                        let turns = (g - w) / std::f64::consts::TAU;
                        assert!((turns - turns.round()).abs() < 1e-9, "r = {r}: corner {t}/{k}");
                    }
                }
            }
        }
    }

    #[test]
    fn cotangents_are_those_of_the_angles_and_slivers_below_the_threshold_are_left_out() {
        let right = cotangents(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]).unwrap();
        assert!(right[0].abs() < 1e-15 && (right[1] - 1.0).abs() < 1e-15 && (right[2] - 1.0).abs() < 1e-15);
        // A needle with a 0.2° angle (cheese's smallest) stays; one of 10⁻⁷ rad does not.
        let needle = |h: f64| [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, h, 0.0]];
        let kept = cotangents(&needle(0.2f64.to_radians().tan())).unwrap();
        assert!((kept[0] - 1.0 / 0.2f64.to_radians().tan()).abs() < 1e-9, "{kept:?}");
        assert_eq!(cotangents(&needle(1e-7)), None);
    }
}
