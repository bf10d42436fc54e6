//! Real polynomials in one variable: arithmetic on coefficient vectors, every real root that
//! changes sign, and the exact minimum on an interval. Used where an energy restricted to a line
//! is a polynomial in the line parameter (Desbrun–Meyer–Alliez 2002 §5.1: the near-optimal λ is
//! a root of dE/dλ; the exact line search of the boundary optimization, §5.2).
//!
//! Roots are isolated by recursion on the derivative (the roots of p′ split the line into
//! intervals on which p is monotone, so each holds at most one root; Cauchy's bound
//! `1 + max |c_i / c_d|` closes the outer intervals), then found by bisection safeguarded with
//! Newton steps, to a bracket of a few ulps. Multiple roots that do not change sign (p touches
//! zero) are not reported: a minimizer of a smooth function is always a sign change of its
//! derivative, which is all the callers need. Cost: O(d²) evaluations per root for degree d.

/// Coefficients `c[0] + c[1] x + c[2] x² + …`.
#[derive(Debug, Clone, PartialEq)]
pub struct Polynomial {
    coefficients: Vec<f64>,
}

/// Bisection / Newton steps before a bracket is accepted as converged.
const MAX_STEPS: usize = 200;

impl Polynomial {
    /// The polynomial with these coefficients (lowest degree first).
    pub fn new(coefficients: Vec<f64>) -> Self {
        let mut p = Polynomial { coefficients };
        p.trim();
        p
    }

    /// The zero polynomial.
    pub fn zero() -> Self {
        Polynomial { coefficients: Vec::new() }
    }

    fn trim(&mut self) {
        while self.coefficients.last() == Some(&0.0) {
            self.coefficients.pop();
        }
    }

    /// Coefficients, lowest degree first, without trailing zeros.
    pub fn coefficients(&self) -> &[f64] {
        &self.coefficients
    }

    /// Degree (0 for constants, including the zero polynomial).
    pub fn degree(&self) -> usize {
        self.coefficients.len().saturating_sub(1)
    }

    /// Value at `x` (Horner).
    pub fn eval(&self, x: f64) -> f64 {
        self.coefficients.iter().rev().fold(0.0, |acc, &c| acc * x + c)
    }

    /// The derivative.
    pub fn derivative(&self) -> Self {
        Polynomial::new(self.coefficients.iter().enumerate().skip(1).map(|(k, &c)| k as f64 * c).collect())
    }

    /// The product `self · other`.
    pub fn mul(&self, other: &Polynomial) -> Self {
        if self.coefficients.is_empty() || other.coefficients.is_empty() {
            return Polynomial::zero();
        }
        let mut out = vec![0.0; self.coefficients.len() + other.coefficients.len() - 1];
        for (i, &a) in self.coefficients.iter().enumerate() {
            for (j, &b) in other.coefficients.iter().enumerate() {
                out[i + j] += a * b;
            }
        }
        Polynomial::new(out)
    }

    /// `self += scale · other`.
    pub fn add_scaled(&mut self, scale: f64, other: &Polynomial) {
        if self.coefficients.len() < other.coefficients.len() {
            self.coefficients.resize(other.coefficients.len(), 0.0);
        }
        for (a, &b) in self.coefficients.iter_mut().zip(&other.coefficients) {
            *a += scale * b;
        }
        self.trim();
    }

    /// Cauchy's bound: every real root lies in `[−R, R]`.
    fn root_bound(&self) -> f64 {
        let lead = self.coefficients[self.degree()].abs();
        1.0 + self.coefficients[..self.degree()].iter().map(|c| c.abs() / lead).fold(0.0, f64::max)
    }

    /// The real roots at which the polynomial changes sign, in increasing order. Empty for
    /// constants (also for the zero polynomial). Non-finite coefficients give no roots.
    pub fn sign_changing_roots(&self) -> Vec<f64> {
        if self.degree() == 0 || self.coefficients.iter().any(|c| !c.is_finite()) {
            return Vec::new();
        }
        if self.degree() == 1 {
            return vec![-self.coefficients[0] / self.coefficients[1]];
        }
        let bound = self.root_bound();
        if !bound.is_finite() {
            return Vec::new();
        }
        let mut ends = vec![-bound];
        ends.extend(self.derivative().sign_changing_roots().into_iter().filter(|x| x.abs() < bound));
        ends.push(bound);
        let mut roots = Vec::new();
        for pair in ends.windows(2) {
            if let Some(r) = self.monotone_root(pair[0], pair[1]) {
                if roots.last().is_none_or(|&last| r > last) {
                    roots.push(r);
                }
            }
        }
        roots
    }

    /// The root in `[a, b]`, on which the polynomial is monotone, when it changes sign there.
    fn monotone_root(&self, a: f64, b: f64) -> Option<f64> {
        let (fa, fb) = (self.eval(a), self.eval(b));
        if fa == 0.0 {
            return Some(a);
        }
        if fb == 0.0 {
            return Some(b);
        }
        if fa.signum() == fb.signum() {
            return None;
        }
        let derivative = self.derivative();
        let (mut lo, mut hi) = if fa < 0.0 { (a, b) } else { (b, a) }; // p(lo) < 0 < p(hi)
        let mut x = 0.5 * (a + b);
        for _ in 0..MAX_STEPS {
            let fx = self.eval(x);
            if fx == 0.0 {
                return Some(x);
            }
            if fx < 0.0 {
                lo = x;
            } else {
                hi = x;
            }
            let mid = 0.5 * (lo + hi);
            if mid == lo || mid == hi {
                break;
            }
            let newton = x - fx / derivative.eval(x);
            let inside = newton.is_finite() && (newton - lo) * (newton - hi) < 0.0;
            x = if inside { newton } else { mid };
        }
        let (flo, fhi) = (self.eval(lo).abs(), self.eval(hi).abs());
        Some(if flo <= fhi { lo } else { hi })
    }

    /// The minimum of the polynomial on `[lo, hi]` (either end may be infinite): `(x, p(x))`,
    /// comparing the finite ends and every sign-changing root of the derivative inside. `None`
    /// when the polynomial is unbounded below on the interval or the interval is empty.
    pub fn minimum_on(&self, lo: f64, hi: f64) -> Option<(f64, f64)> {
        if lo.is_nan() || hi.is_nan() || lo > hi {
            return None;
        }
        let d = self.degree();
        let lead = self.coefficients.get(d).copied().unwrap_or(0.0);
        // Unbounded below towards an infinite end?
        if d > 0 {
            let down_right = lead < 0.0;
            let down_left = if d % 2 == 0 { lead < 0.0 } else { lead > 0.0 };
            if (hi == f64::INFINITY && down_right) || (lo == f64::NEG_INFINITY && down_left) {
                return None;
            }
        }
        let mut candidates: Vec<f64> = [lo, hi].into_iter().filter(|x| x.is_finite()).collect();
        candidates.extend(self.derivative().sign_changing_roots().into_iter().filter(|&x| x > lo && x < hi));
        if candidates.is_empty() {
            // A constant on the whole line.
            return Some((0.0, self.eval(0.0)));
        }
        candidates.into_iter().map(|x| (x, self.eval(x))).min_by(|a, b| a.1.total_cmp(&b.1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The monic polynomial with the given roots.
    fn from_roots(roots: &[f64]) -> Polynomial {
        roots.iter().fold(Polynomial::new(vec![1.0]), |p, &r| p.mul(&Polynomial::new(vec![-r, 1.0])))
    }

    #[test]
    fn finds_every_simple_root_of_a_degree_seven_polynomial() {
        let roots = [-3.5, -1.0, -0.25, 0.1, 0.7, 2.0, 9.0];
        let p = from_roots(&roots);
        let found = p.sign_changing_roots();
        assert_eq!(found.len(), roots.len(), "{found:?}");
        for (a, b) in found.iter().zip(&roots) {
            assert!((a - b).abs() < 1e-12 * (1.0 + b.abs()), "{a} vs {b}");
        }
    }

    #[test]
    fn roots_of_close_pairs_and_touching_roots() {
        // Two roots 1e-6 apart, and a double root at 3 (rounding decides whether p dips below
        // zero there: found at most as a pair right at 3).
        let p = from_roots(&[1.0, 1.000001, 3.0, 3.0, -2.0]);
        let found = p.sign_changing_roots();
        assert!(found.len() >= 3, "{found:?}");
        assert!((found[0] + 2.0).abs() < 1e-12);
        assert!((found[1] - 1.0).abs() < 1e-9 && (found[2] - 1.000001).abs() < 1e-9, "{found:?}");
        assert!(found[3..].iter().all(|r| (r - 3.0).abs() < 1e-6), "{found:?}");
        // No real roots at all.
        assert!(Polynomial::new(vec![1.0, 0.0, 1.0]).sign_changing_roots().is_empty());
    }

    #[test]
    fn minimum_of_a_quartic_is_at_a_root_of_its_derivative_or_an_end() {
        // (x² − 1)² + 0.3 x: two wells, the left one lower.
        let p = Polynomial::new(vec![1.0, 0.3, -2.0, 0.0, 1.0]);
        let (x, v) = p.minimum_on(f64::NEG_INFINITY, f64::INFINITY).expect("bounded");
        let scan = (0..=400_000).map(|k| -2.0 + k as f64 * 1e-5).map(|x| p.eval(x)).fold(f64::INFINITY, f64::min);
        assert!(x < 0.0 && v <= scan + 1e-12, "x = {x}, v = {v}, scan = {scan}");
        assert!(p.derivative().eval(x).abs() < 1e-12);
        // On [0, 0.5] the minimum is at the end 0.5 (the function decreases towards the right well).
        let (x, _) = p.minimum_on(0.0, 0.5).expect("bounded");
        assert_eq!(x, 0.5);
        // Unbounded below.
        assert!(Polynomial::new(vec![0.0, 0.0, 0.0, 1.0]).minimum_on(f64::NEG_INFINITY, 0.0).is_none());
        assert!(Polynomial::new(vec![0.0, 0.0, -1.0]).minimum_on(0.0, f64::INFINITY).is_none());
        // Constants.
        assert_eq!(Polynomial::new(vec![2.0]).minimum_on(f64::NEG_INFINITY, f64::INFINITY), Some((0.0, 2.0)));
    }
}
