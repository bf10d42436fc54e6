//! The periodic solve of PGP (Ray et al. 2006, §2.3–2.5, eqs. 13–15 and Appendix B eq. 24):
//! per vertex the unknowns `X_v = (cos θ, sin θ, cos φ, sin φ)` of two periodic functions whose
//! gradients follow ω K and ω K⊥.
//!
//! Per triangle T with corners 0, 1, 2 (vertices v_c):
//! - rotation matching (eq. 13): `r_c = argmax_r K_v0 · R^r K_vc` (r_0 = 0) and the rotated
//!   field `K'_c = R^{r_c} K_vc`, `K'⊥_c = N_vc × K'_c`;
//! - the same rotation applied to the unknowns: rotating the frame by π/2 turns (θ, φ) into
//!   (φ, −θ), i.e. `X' = M X` with `M (Ux, Uy, Vx, Vy) = (Vx, Vy, Ux, −Uy)` (the paper's M,
//!   eq. 14, with the signs that make it this rotation) and `X'_c = M^{r_c} X_vc`;
//! - per edge i (from corner a = i⊕1 to b = i⊕2, vector e_i) the expected increments
//!   `δ_i = ω/2 (K'_a + K'_b)·e_i`, `δ⊥_i = ω/2 (K'⊥_a + K'⊥_b)·e_i` and the edge energy of eq. 14,
//!   `‖U'_b − rot(δ_i) U'_a‖² + ‖V'_b − rot(δ⊥_i) V'_a‖²` (the first-order expansion of the
//!   periodic difference of eq. 11);
//! - the triangle energy (eq. 15) `F_T = Σ_i λ_i^T (F_T,i^θ + F_T,i^φ)` with the weights of
//!   eq. 24, which make it the integral of eq. 8 over T (see [`crate::fields::frames::triangle_weights`]).
//!   With an obtuse corner λ is negative and F_T can be indefinite; such forms are replaced by
//!   their positive-semidefinite part ([`crate::fields::frames::project_semidefinite`]).
//!
//! The field K may carry a per-vertex magnitude (the curl-correction scale v of §4.1); the
//! paper's field is unit-length. F* = Σ_T F_T is minimized with one vertex per connected
//! component locked at U = V = (1, 0), then F** = F* + ε Σ ((‖U‖² − 1)² + (‖V‖² − 1)²) by
//! Newton ([`crate::fields::block_newton`]).
//!
//! Cost: O(F) assembly, then the solver's factorizations of a 4V × 4V system, grouped in
//! 2V blocks of one (cosine, sine) pair each (`pair_system`).

use crate::error::Result;
use crate::fields::block_newton::{minimize, Block, BlockSystem, NewtonOptions, SolveReport};
use crate::fields::frames::{
    add, edge_sum_form, project_semidefinite, rotate_quarter, scale, triangle_weights, EdgeList, Hermitian3,
};
use crate::geometry::{cross, dot, sub};
use crate::progress::Progress;
use crate::TriMesh;
use faer::c64;

/// The unknown rotation `M^r` (frame rotated by r quarter turns) as a 4×4 matrix acting on
/// `(cos θ, sin θ, cos φ, sin φ)`.
pub fn unknown_rotation(r: u8) -> Block<4> {
    let m1: Block<4> = [[0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0], [1.0, 0.0, 0.0, 0.0], [0.0, -1.0, 0.0, 0.0]];
    let mut m = identity4();
    for _ in 0..(r % 4) {
        m = matmul4(&m1, &m);
    }
    m
}

/// `M^r X`.
pub fn rotate_unknowns(r: u8, x: [f64; 4]) -> [f64; 4] {
    let m = unknown_rotation(r);
    std::array::from_fn(|i| (0..4).map(|j| m[i][j] * x[j]).sum())
}

fn identity4() -> Block<4> {
    std::array::from_fn(|i| std::array::from_fn(|j| if i == j { 1.0 } else { 0.0 }))
}

fn matmul4(a: &Block<4>, b: &Block<4>) -> Block<4> {
    std::array::from_fn(|i| std::array::from_fn(|j| (0..4).map(|k| a[i][k] * b[k][j]).sum()))
}

fn transpose4(a: &Block<4>) -> Block<4> {
    std::array::from_fn(|i| std::array::from_fn(|j| a[j][i]))
}

/// The rotation and rotated field of each corner of triangle `t` relative to its corner 0
/// (eq. 13): `(r_c, K'_c, K'⊥_c)`.
pub fn corner_frames(
    mesh: &TriMesh,
    normals: &[[f64; 3]],
    field: &[[f64; 3]],
    t: usize,
) -> [(u8, [f64; 3], [f64; 3]); 3] {
    let tri = mesh.triangles()[t];
    let (k0, n0) = (field[tri[0] as usize], normals[tri[0] as usize]);
    std::array::from_fn(|c| {
        let v = tri[c] as usize;
        let r = if c == 0 { 0 } else { crate::fields::frames::match_rotation(k0, n0, normals[v], field[v]) };
        let k = rotate_quarter(normals[v], field[v], r);
        (r, k, cross(normals[v], k))
    })
}

/// Expected increments of θ and φ from corner `a` to corner `b`: `ω/2 (K'_a + K'_b)·(p_b − p_a)`
/// and the same with K'⊥.
pub fn expected_increments(
    p: &[[f64; 3]; 3],
    frames: &[(u8, [f64; 3], [f64; 3]); 3],
    omega: f64,
    a: usize,
    b: usize,
) -> (f64, f64) {
    let e = sub(p[b], p[a]);
    let k = scale(add(frames[a].1, frames[b].1), 0.5 * omega);
    let kp = scale(add(frames[a].2, frames[b].2), 0.5 * omega);
    (dot(k, e), dot(kp, e))
}

/// Minimizes F** for the field `field` (K per vertex, tangent, with its magnitude) at
/// frequency `omega`; returns X per vertex (zeros for unreferenced vertices).
pub fn periodic_solve(
    mesh: &TriMesh,
    normals: &[[f64; 3]],
    field: &[[f64; 3]],
    omega: f64,
    options: &NewtonOptions,
    progress: &mut Progress,
    span: (f64, f64),
) -> Result<(Vec<[f64; 4]>, SolveReport)> {
    let edges = EdgeList::new(mesh);
    let system = assemble(mesh, &edges, normals, field, omega);
    let locked: Vec<(u32, [f64; 2])> = locked_vertices(mesh, &system)
        .into_iter()
        .flat_map(|(b, x)| [(2 * b, [x[0], x[1]]), (2 * b + 1, [x[2], x[3]])])
        .collect();
    let (x, report) = minimize(&pair_system(&system), &locked, options, progress, span)?;
    let mut out = vec![[0.0; 4]; mesh.vertex_count()];
    for (b, &v) in system.vertex_of.iter().enumerate() {
        let (u, w) = (x[2 * b], x[2 * b + 1]);
        out[v as usize] = [u[0], u[1], w[0], w[1]];
    }
    Ok((out, report))
}

/// The same quadratic form with one block per (cosine, sine) pair: block 2b is U of vertex
/// block b, block 2b + 1 its V, and a 2×2 block joins two pairs only where the 4×4 form couples
/// them.
///
/// Why: the rotation matching (eq. 13) maps θ to θ and φ to φ across an edge whose rotation r
/// is even, and θ to φ only where r is odd (the matching's cut lines between singularities).
/// So the 4V unknowns form two copies of the vertex graph glued along those lines, which the
/// fill-reducing ordering sees when the pairs are separate nodes; with the vertex's 4 unknowns
/// kept together every front of the factorization is twice as wide. Where the two triangles of
/// an edge match it differently (next to singular triangles) both kinds of 2×2 block appear;
/// every non-zero one is kept, so the form is exactly the 4×4 one. Measured on the 207k-face
/// disk (`cargo bench --bench pgp`): the factor goes from 72.3M to 47.9M entries and the whole
/// pipeline from 94.7 / 93.1 s to 69.8 / 65.1 s (interleaved single runs, same 62 Newton
/// iterations and the same result counts). Which quarter turn represents the field at a vertex
/// does not matter here: changing it swaps that vertex's U and V nodes, the same graph. Combing
/// the field along a breadth-first tree (measured) cut the θ–φ couplings from 315k to 12.8k on
/// that disk and gave a factor of 49.4M entries, no smaller.
fn pair_system(system: &BlockSystem<4>) -> BlockSystem<2> {
    let n = system.blocks();
    let sub = |m: &Block<4>, i: usize, j: usize| -> Block<2> {
        std::array::from_fn(|r| std::array::from_fn(|c| m[2 * i + r][2 * j + c]))
    };
    let nonzero = |m: &Block<2>| m.iter().flatten().any(|&x| x != 0.0);
    let mut edge_blocks = Vec::new();
    let mut off = Vec::new();
    let mut diag = Vec::with_capacity(2 * n);
    for (b, d) in system.diag.iter().enumerate() {
        diag.push(sub(d, 0, 0));
        diag.push(sub(d, 1, 1));
        let cross = sub(d, 1, 0);
        if nonzero(&cross) {
            edge_blocks.push([2 * b as u32 + 1, 2 * b as u32]);
            off.push(cross);
        }
    }
    for (&[hi, lo], o) in system.edge_blocks.iter().zip(&system.off) {
        for i in 0..2 {
            for j in 0..2 {
                let q = sub(o, i, j);
                if nonzero(&q) {
                    edge_blocks.push([2 * hi + i as u32, 2 * lo + j as u32]);
                    off.push(q);
                }
            }
        }
    }
    BlockSystem {
        block_of: Vec::new(),
        vertex_of: system.vertex_of.iter().flat_map(|&v| [v, v]).collect(),
        edge_blocks,
        diag,
        off,
        rhs: system.rhs.iter().flat_map(|r| [[r[0], r[1]], [r[2], r[3]]]).collect(),
        constant: system.constant,
    }
}

/// One locked block per connected component (corner 0 of its lowest triangle), at U = V = (1, 0).
fn locked_vertices(mesh: &TriMesh, system: &BlockSystem<4>) -> Vec<(u32, [f64; 4])> {
    let mut seen = std::collections::HashSet::new();
    let mut locked = Vec::new();
    for (t, &c) in mesh.triangle_components().iter().enumerate() {
        if seen.insert(c) {
            let v = mesh.triangles()[t][0];
            locked.push((system.block_of[v as usize], [1.0, 0.0, 1.0, 0.0]));
        }
    }
    locked
}

/// F* (eq. 15) as a block system over the vertices.
pub fn assemble(
    mesh: &TriMesh,
    edges: &EdgeList,
    normals: &[[f64; 3]],
    field: &[[f64; 3]],
    omega: f64,
) -> BlockSystem<4> {
    use rayon::prelude::*;
    let mut system = BlockSystem::<4>::new(mesh, edges);
    let forms: Vec<([Hermitian3; 2], [u8; 3])> = (0..mesh.triangle_count())
        .into_par_iter()
        .with_min_len(1024)
        .map(|t| triangle_forms(mesh, normals, field, omega, t))
        .collect();
    for (t, (forms, rotations)) in forms.iter().enumerate() {
        scatter_triangle(&mut system, mesh, edges, t, forms, rotations);
    }
    system
}

/// The θ and φ forms of triangle `t` in its corner-0 frame, and the corner rotations.
fn triangle_forms(
    mesh: &TriMesh,
    normals: &[[f64; 3]],
    field: &[[f64; 3]],
    omega: f64,
    t: usize,
) -> ([Hermitian3; 2], [u8; 3]) {
    let p = mesh.triangles()[t].map(|v| mesh.points()[v as usize]);
    let frames = corner_frames(mesh, normals, field, t);
    let weights = triangle_weights(mesh, t);
    let mut rot_theta = [c64::new(1.0, 0.0); 3];
    let mut rot_phi = [c64::new(1.0, 0.0); 3];
    for i in 0..3 {
        let (d, dp) = expected_increments(&p, &frames, omega, (i + 1) % 3, (i + 2) % 3);
        rot_theta[i] = c64::new(d.cos(), d.sin());
        rot_phi[i] = c64::new(dp.cos(), dp.sin());
    }
    let mut h = [edge_sum_form(weights, rot_theta), edge_sum_form(weights, rot_phi)];
    if weights.iter().any(|&w| w < 0.0) {
        h = h.map(project_semidefinite);
    }
    (h, frames.map(|f| f.0))
}

/// Adds the triangle's form, rotated back to each vertex's own frame, to the system.
fn scatter_triangle(
    system: &mut BlockSystem<4>,
    mesh: &TriMesh,
    edges: &EdgeList,
    t: usize,
    forms: &[Hermitian3; 2],
    rotations: &[u8; 3],
) {
    let tri = mesh.triangles()[t];
    let m = rotations.map(unknown_rotation);
    for c in 0..3 {
        for d in c..3 {
            let local = local_block(forms, c, d);
            let global = matmul4(&transpose4(&m[c]), &matmul4(&local, &m[d]));
            if c == d {
                system.add_diagonal(tri[c], &global);
            } else {
                let h = if d == (c + 1) % 3 { 3 * t + c } else { 3 * t + d };
                system.add_pair(edges.edge_of[h], tri[c], tri[d], &global);
            }
        }
    }
}

/// The real 4×4 block (corner c, corner d) of the local form: `diag(B_θ, B_φ)` with
/// `B = [[Re h, −Im h], [Im h, Re h]]`, so that `conj(u_c) h u_d` summed over (c, d) is the
/// real form `U_cᵀ B U_d`.
fn local_block(forms: &[Hermitian3; 2], c: usize, d: usize) -> Block<4> {
    let mut q = [[0.0; 4]; 4];
    for (k, form) in forms.iter().enumerate() {
        let h = form[c][d];
        let o = 2 * k;
        q[o][o] = h.re;
        q[o][o + 1] = -h.im;
        q[o + 1][o] = h.im;
        q[o + 1][o + 1] = h.re;
    }
    q
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_quarter_turn_of_the_frame_maps_theta_phi_to_phi_minus_theta() {
        let (th, ph) = (0.7f64, -1.9f64);
        let x = [th.cos(), th.sin(), ph.cos(), ph.sin()];
        let y = rotate_unknowns(1, x);
        assert!((y[0] - ph.cos()).abs() < 1e-15 && (y[1] - ph.sin()).abs() < 1e-15);
        assert!((y[2] - (-th).cos()).abs() < 1e-15 && (y[3] - (-th).sin()).abs() < 1e-15);
        let z = rotate_unknowns(4, x);
        assert_eq!(z, x);
    }

    /// A small, slightly bumpy equilateral grid (all corners acute, so no projection), its
    /// normals and a field with arbitrary quarter-turn representatives per vertex (odd and even
    /// rotations between neighbours).
    fn bumpy_grid() -> (TriMesh, Vec<[f64; 3]>, Vec<[f64; 3]>) {
        let (w, h) = (4u32, 4u32);
        let mut positions = Vec::new();
        for j in 0..=h {
            for i in 0..=w {
                let (x, y) = (i as f64 + 0.5 * (j % 2) as f64, j as f64 * 0.75f64.sqrt());
                positions.extend([x, y, 0.05 * (x * 0.7).sin() * (y * 0.9).cos()]);
            }
        }
        let id = |i: u32, j: u32| j * (w + 1) + i;
        let mut tris = Vec::new();
        for j in 0..h {
            for i in 0..w {
                if j % 2 == 0 {
                    tris.extend([id(i, j), id(i + 1, j), id(i, j + 1), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
                } else {
                    tris.extend([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
                }
            }
        }
        let mesh = TriMesh::new(&positions, &tris).unwrap();
        let normals = crate::fields::frames::vertex_normals(&mesh);
        let field: Vec<[f64; 3]> = (0..mesh.vertex_count())
            .map(|v| {
                let n = normals[v];
                let k = crate::fields::frames::normalized(crate::fields::frames::tangent_part([1.0, 0.3, 0.0], n));
                rotate_quarter(n, k, (v * 7 % 4) as u8)
            })
            .collect();
        (mesh, normals, field)
    }

    fn unknowns(n: usize) -> Vec<[f64; 4]> {
        (0..n).map(|v| std::array::from_fn(|k| ((v * 4 + k) as f64 * 0.37).sin())).collect()
    }

    /// The pair system is the same quadratic form, and it joins a U pair to a V pair exactly
    /// where the 4×4 form does (odd rotations): the grid's field has both kinds of edges.
    #[test]
    fn the_pair_system_has_the_same_energy_and_joins_theta_to_phi_only_across_odd_rotations() {
        let (mesh, normals, field) = bumpy_grid();
        let edges = EdgeList::new(&mesh);
        let system = assemble(&mesh, &edges, &normals, &field, 1.3);
        let pairs = pair_system(&system);
        assert_eq!(pairs.blocks(), 2 * system.blocks());
        let x = unknowns(mesh.vertex_count());
        let xp: Vec<[f64; 2]> = x.iter().flat_map(|v| [[v[0], v[1]], [v[2], v[3]]]).collect();
        let (e4, e2) = (system.quadratic_energy(&x), pairs.quadratic_energy(&xp));
        assert!((e4 - e2).abs() < 1e-12 * e4.abs().max(1.0), "{e4} vs {e2}");
        let crossing = pairs.edge_blocks.iter().filter(|&&[hi, lo]| hi % 2 != lo % 2).count();
        let parallel = pairs.edge_blocks.len() - crossing;
        assert!(crossing > 0 && parallel > 0, "{crossing} θ–φ and {parallel} θ–θ/φ–φ couplings");
        // Fewer couplings than the 4 pair blocks of every 4×4 edge block.
        assert!(pairs.edge_blocks.len() < 4 * system.edge_blocks.len());
    }

    /// The assembled quadratic form equals the sum of the edge energies of eq. 14 weighted as in
    /// eq. 15, evaluated directly from the definitions on random unknowns.
    #[test]
    fn assembled_energy_is_the_weighted_sum_of_edge_energies() {
        let (mesh, normals, field) = bumpy_grid();
        let omega = 1.3;
        let edges = EdgeList::new(&mesh);
        let system = assemble(&mesh, &edges, &normals, &field, omega);
        let x = unknowns(mesh.vertex_count());
        let mut direct = 0.0;
        for t in 0..mesh.triangle_count() {
            let tri = mesh.triangles()[t];
            let p = tri.map(|v| mesh.points()[v as usize]);
            let frames = corner_frames(&mesh, &normals, &field, t);
            let weights = triangle_weights(&mesh, t);
            assert!(weights.iter().all(|&l| l > 0.0));
            let xr: Vec<[f64; 4]> = (0..3).map(|c| rotate_unknowns(frames[c].0, x[tri[c] as usize])).collect();
            for i in 0..3 {
                let (a, b) = ((i + 1) % 3, (i + 2) % 3);
                let (d, dp) = expected_increments(&p, &frames, omega, a, b);
                let rot =
                    |v: [f64; 2], ang: f64| [ang.cos() * v[0] - ang.sin() * v[1], ang.sin() * v[0] + ang.cos() * v[1]];
                let u = rot([xr[a][0], xr[a][1]], d);
                let vv = rot([xr[a][2], xr[a][3]], dp);
                let e = (xr[b][0] - u[0]).powi(2)
                    + (xr[b][1] - u[1]).powi(2)
                    + (xr[b][2] - vv[0]).powi(2)
                    + (xr[b][3] - vv[1]).powi(2);
                direct += weights[i] * e;
            }
        }
        let assembled = system.quadratic_energy(&x);
        assert!((assembled - direct).abs() < 1e-10 * direct.abs().max(1.0), "{assembled} vs {direct}");
    }
}
