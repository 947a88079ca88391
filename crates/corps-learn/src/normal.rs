//! Standard normal draws from a seeded generator (Box–Muller, both values used), so that a
//! run is reproducible to the bit from its seed on any machine.

use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// N(0, 1) draws.
#[derive(Clone, Debug)]
pub struct Normal {
    rng: ChaCha8Rng,
    spare: Option<f64>,
}

impl Normal {
    pub fn new(rng: ChaCha8Rng) -> Self {
        Self { rng, spare: None }
    }

    pub fn draw(&mut self) -> f64 {
        if let Some(z) = self.spare.take() {
            return z;
        }
        // u ∈ (0, 1]: ln u is finite.
        let u = 1.0 - self.rng.gen::<f64>();
        let v = self.rng.gen::<f64>();
        let r = (-2.0 * u.ln()).sqrt();
        let (s, c) = (std::f64::consts::TAU * v).sin_cos();
        self.spare = Some(r * s);
        r * c
    }
}
