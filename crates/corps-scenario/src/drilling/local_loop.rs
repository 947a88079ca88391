//! The two loops of seed 000 L6960–L6990: the high-level QP updates at a nominal rate, best
//! effort, each update `U(−jitter, jitter)` off its nominal time ([`UpdateClock`]); between
//! updates a local regulation ([`LocalRegulation`], the thesis's "PD+": a PD around the QP's
//! trajectory with the QP's torques as feed-forward) runs at its own faster rate:
//! `τ = τ* + K_p (q_ref ⊖ q) + K_d (v_ref − v)`, where `(q_ref, v_ref)` start at the state the
//! QP saw and follow its accelerations q̈*.

use corps_model::{difference_to, integrate_to, Model};
use nalgebra::DVector;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// When the high-level QP updates: nominal period `period`, each update off by a uniform
/// jitter, on the local loop's ticks (every `tick` seconds), never closer than one tick to
/// the last.
pub struct UpdateClock {
    period: f64,
    jitter: f64,
    tick: f64,
    /// Updates so far: the next one's nominal time is `updates × period` (a product, not a
    /// running sum, so that a long run's nominal times do not drift by rounding).
    updates: u64,
    next: f64,
    last: Option<f64>,
}

impl UpdateClock {
    pub fn new(period: f64, jitter: f64, tick: f64) -> Self {
        Self {
            period,
            jitter,
            tick,
            updates: 0,
            next: 0.0,
            last: None,
        }
    }

    /// Whether an update is due at time `t` (a local tick); if so, the interval since the
    /// last update (the nominal period for the first) and the one to the next, drawn now
    /// and rounded to the nearest local tick (at least one tick ahead). A jitter smaller than
    /// half a tick is rounded away.
    pub fn due(&mut self, t: f64, rng: &mut ChaCha8Rng) -> Option<(f64, f64)> {
        if t + 1e-6 * self.tick < self.next {
            return None;
        }
        let since = self.last.map_or(self.period, |last| t - last);
        self.last = Some(t);
        self.updates += 1;
        let nominal = self.updates as f64 * self.period;
        let off = if self.jitter > 0.0 {
            rng.gen_range(-self.jitter..=self.jitter)
        } else {
            0.0
        };
        let on_grid = ((nominal + off) / self.tick).round() * self.tick;
        self.next = on_grid.max(t + self.tick);
        Some((since, self.next - t))
    }
}

/// The local PD+ regulation around the last QP update.
pub struct LocalRegulation {
    kp: DVector<f64>,
    kd: DVector<f64>,
    limit: DVector<f64>,
    q_ref: DVector<f64>,
    v_ref: DVector<f64>,
    a_ref: DVector<f64>,
    tau_ff: DVector<f64>,
    error: DVector<f64>,
    step: DVector<f64>,
    next_q: DVector<f64>,
    /// The PD part of the last command (na).
    pub feedback: DVector<f64>,
}

impl LocalRegulation {
    /// PD gains per joint (na each) and the effort limits the command is clamped to.
    pub fn new(model: &Model, kp: DVector<f64>, kd: DVector<f64>, limit: DVector<f64>) -> Self {
        let (nq, nv) = (model.nq, model.nv);
        Self {
            kp,
            kd,
            limit,
            q_ref: DVector::zeros(nq),
            v_ref: DVector::zeros(nv),
            a_ref: DVector::zeros(nv),
            tau_ff: DVector::zeros(nv),
            error: DVector::zeros(nv),
            step: DVector::zeros(nv),
            next_q: DVector::zeros(nq),
            feedback: DVector::zeros(nv),
        }
    }

    /// A new update: the QP saw (q, v) and asked for accelerations `a` and torques `tau`.
    pub fn update(&mut self, q: &[f64], v: &[f64], a: &DVector<f64>, tau: &DVector<f64>) {
        self.q_ref.copy_from_slice(q);
        self.v_ref.copy_from_slice(v);
        self.a_ref.copy_from(a);
        self.tau_ff.copy_from(tau);
    }

    /// The command at the measured state (q, v) into `tau` (clamped to the effort limits),
    /// then the reference advanced by `dt` at the QP's accelerations.
    pub fn command(
        &mut self,
        model: &Model,
        q: &[f64],
        v: &[f64],
        dt: f64,
        tau: &mut DVector<f64>,
    ) -> corps_model::Result<()> {
        difference_to(model, q, self.q_ref.as_slice(), self.error.as_mut_slice())?;
        for k in 0..tau.len() {
            let fb = self.kp[k] * self.error[k] + self.kd[k] * (self.v_ref[k] - v[k]);
            let l = self.limit[k];
            tau[k] = (self.tau_ff[k] + fb).clamp(-l, l);
            self.feedback[k] = tau[k] - self.tau_ff[k];
        }
        self.step.copy_from(&self.v_ref);
        self.step.axpy(0.5 * dt * dt, &self.a_ref, dt);
        integrate_to(
            model,
            self.q_ref.as_slice(),
            self.step.as_slice(),
            self.next_q.as_mut_slice(),
        )?;
        self.q_ref.copy_from(&self.next_q);
        self.v_ref.axpy(dt, &self.a_ref, 1.0);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn updates_come_at_the_nominal_rate_within_the_jitter() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut clock = UpdateClock::new(0.004, 0.002, 0.002);
        let mut times: Vec<f64> = Vec::new();
        let mut announced: Option<f64> = None;
        for k in 0..50_000 {
            let t = k as f64 * 0.002;
            if let Some((since, until)) = clock.due(t, &mut rng) {
                if let Some(last) = times.last() {
                    assert!((since - (t - last)).abs() < 1e-12);
                }
                // The update comes when the last one said it would.
                if let Some(at) = announced {
                    assert!((t - at).abs() < 1e-9, "{t} against {at}");
                }
                announced = Some(t + until);
                // The next update lands on a local tick.
                let ticks = until / 0.002;
                assert!((ticks - ticks.round()).abs() < 1e-6 && ticks >= 1.0 - 1e-9);
                times.push(t);
            }
        }
        let rate = (times.len() - 1) as f64 / (times.last().unwrap() - times[0]);
        assert!((rate - 250.0).abs() < 2.0, "{rate} Hz");
        let gaps: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
        let (lo, hi) = gaps
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), g| (a.min(*g), b.max(*g)));
        assert!(lo >= 0.002 - 1e-9 && hi <= 0.008 + 1e-9, "{lo} {hi}");
        assert!(hi > lo + 1e-3, "no jitter: {lo} {hi}");
    }

    #[test]
    fn without_jitter_every_second_local_tick_for_an_hour() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut clock = UpdateClock::new(0.004, 0.0, 0.002);
        // Over an hour of 2 ms ticks: every second one, no drift.
        for k in 0..1_800_000u64 {
            let due = clock.due(k as f64 * 0.002, &mut rng);
            assert_eq!(due.is_some(), k % 2 == 0, "tick {k}");
            if let Some((since, until)) = due {
                assert!((until - 0.004).abs() < 1e-9, "tick {k}: {until}");
                assert!(k == 0 || (since - 0.004).abs() < 1e-9, "tick {k}: {since}");
            }
        }
    }
}
