//! Discrete algebraic Riccati equation (DARE)
//! `P = Q + AᵀPA − AᵀPB (R + BᵀPB)⁻¹ BᵀPA`, solved by the structure-preserving doubling
//! algorithm (SDA; Chu, Fan, Lin & Wang 2004): with `G₀ = B R⁻¹ Bᵀ`, `H₀ = Q`, `A₀ = A`,
//!
//! ```text
//! W = I + G_k H_k
//! A_{k+1} = A_k W⁻¹ A_k
//! G_{k+1} = G_k + A_k W⁻¹ G_k A_kᵀ
//! H_{k+1} = H_k + A_kᵀ H_k W⁻¹ A_k     → P
//! ```
//!
//! `H_k` equals the Riccati iterate after `2^k` steps, so convergence is quadratic. On the
//! augmented 4-state preview system (`R = 1e-6`, ill-conditioned `I + G H`) the doubling result
//! keeps a relative residual of ~6e-4, so it is then refined by the plain Riccati recursion
//! until the iterate stops changing (measured: the jrl-walkgen gains are reproduced only after
//! this refinement), and the result is accepted only if its relative residual is below 1e-9.
//! This is a setup-time routine (it allocates).

use crate::WalkError;
use nalgebra::DMatrix;

/// Stabilizing solution `P` of the DARE for `(A, B, Q, R)`; `R` must be invertible.
pub fn solve_dare(
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    q: &DMatrix<f64>,
    r: &DMatrix<f64>,
) -> Result<DMatrix<f64>, WalkError> {
    let n = a.nrows();
    let r_inv = r
        .clone()
        .try_inverse()
        .ok_or(WalkError::InvalidParameter("R must be invertible"))?;
    let mut ak = a.clone();
    let mut g = b * r_inv * b.transpose();
    let mut h = q.clone();
    let id = DMatrix::<f64>::identity(n, n);
    const MAX_STEPS: usize = 64;
    let mut doubled = None;
    for _ in 0..MAX_STEPS {
        let Some(w_inv) = (&id + &g * &h).try_inverse() else {
            break;
        };
        let a_next = &ak * &w_inv * &ak;
        let g_next = &g + &ak * &w_inv * &g * ak.transpose();
        let h_next = &h + ak.transpose() * &h * &w_inv * &ak;
        let change = (&h_next - &h).norm();
        let scale = h_next.norm();
        ak = a_next;
        g = 0.5 * (&g_next + g_next.transpose());
        h = 0.5 * (&h_next + h_next.transpose());
        if !scale.is_finite() {
            break;
        }
        if change <= 1e-15 * scale {
            doubled = Some(h.clone());
            break;
        }
    }
    // Fixed-point refinement P ← Q + AᵀPA − AᵀPB (R + BᵀPB)⁻¹ BᵀPA.
    let mut p = doubled.unwrap_or_else(|| q.clone());
    const MAX_REFINE: usize = 1_000_000;
    for _ in 0..MAX_REFINE {
        let Some(s) = (r + b.transpose() * &p * b).try_inverse() else {
            return Err(WalkError::RiccatiNotConverged(MAX_STEPS));
        };
        let pa = &p * a;
        let next = q + a.transpose() * &pa - pa.transpose() * b * s * b.transpose() * &pa;
        let next = 0.5 * (&next + next.transpose());
        let change = (&next - &p).amax();
        p = next;
        if !p.amax().is_finite() {
            break;
        }
        if change <= 1e-15 * p.amax() {
            break;
        }
    }
    if p.amax().is_finite() && dare_residual(a, b, q, r, &p) < 1e-9 {
        Ok(p)
    } else {
        Err(WalkError::RiccatiNotConverged(MAX_STEPS))
    }
}

/// Residual `‖Q + AᵀPA − AᵀPB (R + BᵀPB)⁻¹ BᵀPA − P‖ / ‖P‖` (for checks).
pub fn dare_residual(
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    q: &DMatrix<f64>,
    r: &DMatrix<f64>,
    p: &DMatrix<f64>,
) -> f64 {
    let Some(s) = (r + b.transpose() * p * b).try_inverse() else {
        return f64::INFINITY;
    };
    let res = q + a.transpose() * p * a - a.transpose() * p * b * s * b.transpose() * p * a - p;
    res.norm() / p.norm()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scalar_dare_closed_form() {
        // x⁺ = a x + b u: P = q + a²P − a²b²P²/(r + b²P); positive root of
        // b²P² + (r(1 − a²) − q b²) P − q r = 0.
        let (a, b, q, r) = (1.2, 0.5, 2.0, 0.3);
        let p = solve_dare(
            &DMatrix::from_element(1, 1, a),
            &DMatrix::from_element(1, 1, b),
            &DMatrix::from_element(1, 1, q),
            &DMatrix::from_element(1, 1, r),
        )
        .unwrap()[0];
        let (qa, qb, qc) = (b * b, r * (1.0 - a * a) - q * b * b, -q * r);
        let expected = (-qb + (qb * qb - 4.0 * qa * qc).sqrt()) / (2.0 * qa);
        assert!((p - expected).abs() < 1e-12 * expected);
    }
}
