//! Right-preconditioned GMRES without restarts (Saad 2003, "Iterative Methods for Sparse Linear
//! Systems", 2nd ed., Algorithm 9.5): Arnoldi with modified Gram–Schmidt on `K P⁻¹`, the
//! Hessenberg matrix reduced by Givens rotations as it grows, so the residual norm of every
//! step is known without forming x. The operator and the preconditioner are closures, so the
//! matrix can be applied without being stored (ABF++'s Newton correction).
//!
//! Cost: k operator applications and preconditioner solves for k steps, O(k²n) for the
//! orthogonalization, O(kn) memory.

/// Right-preconditioned GMRES (no restarts) on `K x = b`: at most `max_inner` Krylov steps of
/// `K P⁻¹`, stopping once ‖b − K x‖ ≤ `relative`·‖b‖ (Saad 2003, Alg. 9.5). Returns x.
pub fn preconditioned_gmres<E>(
    apply: impl Fn(&[f64]) -> Vec<f64>,
    precondition: impl Fn(&[f64]) -> std::result::Result<Vec<f64>, E>,
    b: &[f64],
    relative: f64,
    max_inner: usize,
) -> std::result::Result<Vec<f64>, E> {
    let dot = |u: &[f64], v: &[f64]| u.iter().zip(v).map(|(a, b)| a * b).sum::<f64>();
    let beta = dot(b, b).sqrt();
    let n = b.len();
    if beta == 0.0 {
        return Ok(vec![0.0; n]);
    }
    let mut basis: Vec<Vec<f64>> = vec![b.iter().map(|x| x / beta).collect()];
    let mut preconditioned: Vec<Vec<f64>> = Vec::new();
    // Hessenberg columns rotated to upper triangular form by Givens rotations.
    let mut r_cols: Vec<Vec<f64>> = Vec::new();
    let mut rotations: Vec<(f64, f64)> = Vec::new();
    let mut g = vec![beta];
    for j in 0..max_inner {
        let z = precondition(&basis[j])?;
        let mut w = apply(&z);
        preconditioned.push(z);
        let mut h = Vec::with_capacity(j + 2);
        for v in &basis {
            let hij = dot(&w, v);
            for (wk, vk) in w.iter_mut().zip(v) {
                *wk -= hij * vk;
            }
            h.push(hij);
        }
        let norm_w = dot(&w, &w).sqrt();
        h.push(norm_w);
        for (i, &(cs, sn)) in rotations.iter().enumerate() {
            let (a, b) = (h[i], h[i + 1]);
            h[i] = cs * a + sn * b;
            h[i + 1] = -sn * a + cs * b;
        }
        let (a, b) = (h[j], h[j + 1]);
        let rho = a.hypot(b);
        let (cs, sn) = if rho == 0.0 { (1.0, 0.0) } else { (a / rho, b / rho) };
        h[j] = rho;
        h[j + 1] = 0.0;
        rotations.push((cs, sn));
        g.push(-sn * g[j]);
        g[j] *= cs;
        h.truncate(j + 1);
        r_cols.push(h);
        let converged = g[j + 1].abs() <= relative * beta;
        if converged || norm_w == 0.0 || j + 1 == max_inner {
            break;
        }
        basis.push(w.iter().map(|x| x / norm_w).collect());
    }
    // Back substitution R y = g, then x = Σ y_j P⁻¹ v_j.
    let k = r_cols.len();
    let mut y = vec![0.0; k];
    for i in (0..k).rev() {
        let mut sum = g[i];
        for j in i + 1..k {
            sum -= r_cols[j][i] * y[j];
        }
        y[i] = if r_cols[i][i] != 0.0 { sum / r_cols[i][i] } else { 0.0 };
    }
    let mut x = vec![0.0; n];
    for (yj, z) in y.iter().zip(&preconditioned) {
        for (xi, zi) in x.iter_mut().zip(z) {
            *xi += yj * zi;
        }
    }
    Ok(x)
}
