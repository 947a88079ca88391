//! The (1+1)-CMA-ES with covariance constrained adaptation (Arnold & Hansen 2012; seed 001
//! §5.1, Eq 5.2–5.13), minimizing `f(x)` subject to `g_j(x) ≤ 0`. An equality constraint is
//! two inequalities with a tolerance.

use crate::error::LearnError;
use crate::normal::Normal;
use nalgebra::{DMatrix, DVector};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::collections::VecDeque;

/// How many ancestors back the active update compares with: the parent's fifth, w₋₅ in seed
/// 001's notation (L5744–L5760; Arnold & Hansen count from the offspring, one fewer).
const ANCESTORS: usize = 5;

/// The strategy's constants for dimension n (seed 001 Eq 5.2a–h).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Constants {
    /// β = 0.1/(n+2): the constraint vectors' pull on the Cholesky factor.
    pub beta: f64,
    /// c = 2/(n+2): the success path's learning rate.
    pub c: f64,
    /// c_c = 1/(n+2): the constraint vectors' learning rate.
    pub c_c: f64,
    /// c⁺_cov = 2/(n²+6).
    pub c_cov_plus: f64,
    /// 0.4/(n^1.6+1), c⁻_cov's cap (c⁻_cov = min(cap, 1/(2|z|²−1))).
    pub c_cov_minus_cap: f64,
    /// c_P = 1/12.
    pub c_p: f64,
    /// d = 1 + n/2, the step size's damping.
    pub d: f64,
    /// P_succ^target = 2/11.
    pub p_target: f64,
}

impl Constants {
    pub fn for_dimension(n: usize) -> Self {
        let n = n as f64;
        Self {
            beta: 0.1 / (n + 2.0),
            c: 2.0 / (n + 2.0),
            c_c: 1.0 / (n + 2.0),
            c_cov_plus: 2.0 / (n * n + 6.0),
            c_cov_minus_cap: 0.4 / (n.powf(1.6) + 1.0),
            c_p: 1.0 / 12.0,
            d: 1.0 + n / 2.0,
            p_target: 2.0 / 11.0,
        }
    }
}

/// The initial step size and the generator's seed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// σ₀ > 0 (seed 001 Eq 5.3: 0.1 for the task weights).
    pub sigma0: f64,
    pub seed: u64,
}

/// What one step did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StepOutcome {
    /// The candidate violated `violated` constraints: rejected unevaluated, the distribution
    /// turned away from them (Eq 5.4–5.6).
    Infeasible { violated: usize },
    /// The candidate was at least as good as the parent and replaced it (Eq 5.10–5.12).
    Success,
    /// The candidate was worse; `active` when it was worse than the fifth ancestor too and
    /// the distribution shrank along it (Eq 5.13).
    Failure { active: bool },
}

/// The optimizer's state (seed 001 Eq 5.3).
#[derive(Clone, Debug)]
pub struct OnePlusOne {
    k: Constants,
    x: DVector<f64>,
    fx: f64,
    sigma: f64,
    /// Cholesky factor A of the covariance, C = A Aᵀ.
    a: DMatrix<f64>,
    /// Success path p_c.
    pc: DVector<f64>,
    p_succ: f64,
    /// One vector per constraint, v_j.
    v: Vec<DVector<f64>>,
    /// The fitness of the last parents, oldest first.
    ancestors: VecDeque<f64>,
    normal: Normal,
    g: Vec<f64>,
    evaluations: usize,
    iterations: usize,
}

fn setting(name: &'static str, reason: String) -> LearnError {
    LearnError::Setting { name, reason }
}

impl OnePlusOne {
    /// Starts from `x0`, which must satisfy the `constraints` inequalities (`g(x, out)` writes
    /// the `constraints` values, feasible where all are ≤ 0) and have a finite fitness `f`.
    pub fn new(
        x0: &[f64],
        constraints: usize,
        settings: Settings,
        mut g: impl FnMut(&[f64], &mut [f64]),
        mut f: impl FnMut(&[f64]) -> f64,
    ) -> Result<Self, LearnError> {
        let n = x0.len();
        if n == 0 {
            return Err(setting("start point", "empty".into()));
        }
        if let Some(i) = x0.iter().position(|v| !v.is_finite()) {
            return Err(setting("start point", format!("entry {i} is {}", x0[i])));
        }
        if !(settings.sigma0.is_finite() && settings.sigma0 > 0.0) {
            return Err(setting("σ0", format!("{} (must be > 0)", settings.sigma0)));
        }
        let mut values = vec![0.0; constraints];
        g(x0, &mut values);
        if let Some(j) = values.iter().position(|v| v.is_nan() || *v > 0.0) {
            return Err(setting(
                "start point",
                format!("violates constraint {j} (g = {})", values[j]),
            ));
        }
        let fx = f(x0);
        if !fx.is_finite() {
            return Err(setting("start point", format!("its fitness is {fx}")));
        }
        let k = Constants::for_dimension(n);
        Ok(Self {
            k,
            x: DVector::from_column_slice(x0),
            fx,
            sigma: settings.sigma0,
            a: DMatrix::identity(n, n),
            pc: DVector::zeros(n),
            p_succ: k.p_target,
            v: vec![DVector::zeros(n); constraints],
            ancestors: VecDeque::with_capacity(ANCESTORS + 1),
            normal: Normal::new(ChaCha8Rng::seed_from_u64(settings.seed)),
            g: values,
            evaluations: 1,
            iterations: 0,
        })
    }

    /// One iteration (seed 001 (a)–(e)): samples a candidate, checks the constraints `g`
    /// first (a non-finite value counts as violated) and calls `f` only on a feasible one.
    pub fn step(
        &mut self,
        mut g: impl FnMut(&[f64], &mut [f64]),
        mut f: impl FnMut(&[f64]) -> f64,
    ) -> StepOutcome {
        self.iterations += 1;
        let n = self.x.len();
        let k = self.k;
        // (a) z ~ N(0, I), y = x + σ A z.
        let z = DVector::from_fn(n, |_, _| self.normal.draw());
        let az = &self.a * &z;
        let y = &self.x + &az * self.sigma;
        // (b) The violated constraints' vectors, and A pulled away from them (5.4–5.6).
        g(y.as_slice(), &mut self.g);
        let violated: Vec<usize> = (0..self.g.len())
            .filter(|&j| self.g[j].is_nan() || self.g[j] > 0.0)
            .collect();
        if !violated.is_empty() {
            for &j in &violated {
                self.v[j] = &self.v[j] * (1.0 - k.c_c) + &az * k.c_c;
            }
            let lu = self.a.clone().lu();
            let mut pull = DMatrix::zeros(n, n);
            for &j in &violated {
                if let Some(w) = lu.solve(&self.v[j]) {
                    let ww = w.dot(&w);
                    if ww > 0.0 {
                        pull += &self.v[j] * w.transpose() / ww;
                    }
                }
            }
            self.a -= pull * (k.beta / violated.len() as f64);
            return StepOutcome::Infeasible {
                violated: violated.len(),
            };
        }
        // (c) The fitness, the success probability and the step size (5.7–5.9).
        let fy = f(y.as_slice());
        self.evaluations += 1;
        let success = fy <= self.fx;
        self.p_succ = (1.0 - k.c_p) * self.p_succ + k.c_p * if success { 1.0 } else { 0.0 };
        self.sigma *= ((self.p_succ - k.p_target) / ((1.0 - k.p_target) * k.d)).exp();
        if success {
            // (d) The parent replaced, the success path and A's rank-one update (5.10–5.12).
            self.ancestors.push_back(self.fx);
            if self.ancestors.len() > ANCESTORS {
                self.ancestors.pop_front();
            }
            self.x = y;
            self.fx = fy;
            self.pc = &self.pc * (1.0 - k.c) + &az * (k.c * (2.0 - k.c)).sqrt();
            if let Some(w) = self.a.clone().lu().solve(&self.pc) {
                let ww = w.dot(&w);
                if ww > 0.0 {
                    let s = (1.0 - k.c_cov_plus).sqrt();
                    let r =
                        s / ww * ((1.0 + k.c_cov_plus * ww / (1.0 - k.c_cov_plus)).sqrt() - 1.0);
                    self.a = &self.a * s + &self.pc * w.transpose() * r;
                }
            }
            return StepOutcome::Success;
        }
        // Worse than the fifth ancestor: A shrinks along A z (5.13, Arnold & Hansen's signs).
        let fifth = (self.ancestors.len() == ANCESTORS).then(|| self.ancestors[0]);
        let active = fifth.is_some_and(|f5| fy.is_nan() || fy > f5);
        if active {
            let zz = z.dot(&z);
            let c = if 2.0 * zz - 1.0 > 0.0 {
                k.c_cov_minus_cap.min(1.0 / (2.0 * zz - 1.0))
            } else {
                k.c_cov_minus_cap
            };
            let root = 1.0 - c * zz / (1.0 + c);
            if zz > 0.0 && root > 0.0 {
                let s = (1.0 + c).sqrt();
                let r = s / zz * (root.sqrt() - 1.0);
                self.a = &self.a * s + &az * z.transpose() * r;
            }
        }
        StepOutcome::Failure { active }
    }

    /// The parent: the best feasible point so far.
    pub fn best(&self) -> &[f64] {
        self.x.as_slice()
    }

    pub fn best_fitness(&self) -> f64 {
        self.fx
    }

    pub fn sigma(&self) -> f64 {
        self.sigma
    }

    /// Fitness evaluations so far (the start point's included).
    pub fn evaluations(&self) -> usize {
        self.evaluations
    }

    pub fn iterations(&self) -> usize {
        self.iterations
    }

    /// The covariance's Cholesky factor A.
    pub fn cholesky(&self) -> &DMatrix<f64> {
        &self.a
    }

    pub fn constants(&self) -> &Constants {
        &self.k
    }
}
