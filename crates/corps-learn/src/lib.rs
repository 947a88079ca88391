//! Learning for corps. [`OnePlusOne`] is the (1+1)-CMA-ES with covariance constrained
//! adaptation of Arnold & Hansen (GECCO 2012) as seed 001 §5.1 states it (Eq 5.2–5.13, with
//! the printed typos fixed: the σ factor of 5.9 and the signs of the active update 5.13):
//! one candidate a step, infeasible candidates rejected before their fitness is computed and
//! used to shrink the search distribution away from the constraint, the step size adapted by
//! the success rule, the covariance's Cholesky factor by the success path and, after a
//! candidate worse than the fifth ancestor, by an active (negative) update.
//!
//! ```
//! use corps_learn::{OnePlusOne, Settings};
//! // Minimize |x|² subject to x₀ ≥ 1 (g(x) = 1 − x₀ ≤ 0), from (3, 3).
//! let g = |x: &[f64], out: &mut [f64]| out[0] = 1.0 - x[0];
//! let f = |x: &[f64]| x.iter().map(|v| v * v).sum::<f64>();
//! let mut es = OnePlusOne::new(&[3.0, 3.0], 1, Settings { sigma0: 1.0, seed: 7 }, g, f).unwrap();
//! for _ in 0..2000 {
//!     es.step(g, f);
//! }
//! assert!((es.best_fitness() - 1.0).abs() < 1e-6);
//! ```

mod cmaes;
mod error;
pub mod normal;

pub use cmaes::{Constants, OnePlusOne, Settings, StepOutcome};
pub use error::LearnError;
