//! The exponential barrier of seed 000 Eq 3.14 on a bounded quantity `c ∈ [c_min, c_max]`:
//! `max(c) = 1 − λ (c_max − c)`, `min(c) = 1 − λ (c − c_min)`,
//! `C_s(c) = exp(λ max(c)) + exp(λ min(c))`, `dC_s/dc = λ² (e^{λ max} − e^{λ min})`,
//! `d²C_s/dc² = λ⁴ C_s`. It equals `2 e^{λ}`-ish at a bound and vanishes exponentially inside.

/// A barrier on one quantity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Barrier {
    pub lambda: f64,
    pub lower: f64,
    pub upper: f64,
}

impl Barrier {
    /// `(C_s, dC_s/dc, d²C_s/dc²)` at `c`.
    pub fn eval(&self, c: f64) -> (f64, f64, f64) {
        let l = self.lambda;
        let e_max = (l * (1.0 - l * (self.upper - c))).exp();
        let e_min = (l * (1.0 - l * (c - self.lower))).exp();
        let value = e_max + e_min;
        (value, l * l * (e_max - e_min), l.powi(4) * value)
    }

    /// The cost `w C_s(c)²` with its first and second derivatives in `c`.
    pub fn squared_cost(&self, w: f64, c: f64) -> (f64, f64, f64) {
        let (v, d, dd) = self.eval(c);
        (w * v * v, 2.0 * w * v * d, 2.0 * w * (d * d + v * dd))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn derivatives_match_finite_differences() {
        let b = Barrier {
            lambda: 0.7,
            lower: -2.0,
            upper: 3.0,
        };
        for c in [-1.9, -0.5, 0.0, 1.3, 2.9] {
            let h = 1e-5;
            let (v, d, dd) = b.eval(c);
            let (vp, dp, _) = b.eval(c + h);
            let (vm, dm, _) = b.eval(c - h);
            assert!(((vp - vm) / (2.0 * h) - d).abs() < 1e-7 * (1.0 + d.abs()));
            assert!(((dp - dm) / (2.0 * h) - dd).abs() < 1e-6 * (1.0 + dd.abs()));
            let (cv, cd, cdd) = b.squared_cost(2.0, c);
            assert!((cv - 2.0 * v * v).abs() < 1e-12);
            let (cvp, cdp, _) = b.squared_cost(2.0, c + h);
            let (cvm, cdm, _) = b.squared_cost(2.0, c - h);
            assert!(((cvp - cvm) / (2.0 * h) - cd).abs() < 1e-6 * (1.0 + cd.abs()));
            assert!(((cdp - cdm) / (2.0 * h) - cdd).abs() < 1e-5 * (1.0 + cdd.abs()));
        }
    }

    #[test]
    fn the_barrier_rises_towards_either_bound() {
        let b = Barrier {
            lambda: 10.0,
            lower: -2.35,
            upper: 0.0,
        };
        let middle = b.eval(-1.2).0;
        assert!(middle < 1e-30);
        assert!(b.eval(-0.05).0 > 1e-3 && b.eval(-2.3).0 > 1e-3);
        assert!((b.eval(0.0).0 - 10f64.exp()).abs() < 1e-6 * 10f64.exp());
    }
}
