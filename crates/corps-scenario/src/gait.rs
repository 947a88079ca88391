//! The passivity gait measure of seed 000 Eq 4.17–4.18, per gait phase:
//! `PGM = 1 − RMS(τ_sa) / RMS(τ_tot)`, `RMS(τ) = √((1/T) ∫ Σ_i τ_i² dt)`, with τ_sa the ankle
//! torques that matter in the phase and τ_tot all joint torques: both ankles in double
//! support, the stance ankle in single support, the swing ankle for the flying foot. Near 1,
//! the ankles barely work (a passive, human-like gait); the thesis reports 0.93 / 0.87 / 1.0
//! for TSID torque on the 20 cm walk (Table 4.9).

/// Sums of squared torques per phase: double support, stance ankle, flying ankle.
#[derive(Clone, Debug, Default)]
pub struct PassivityGaitMeasure {
    /// Per phase: (Σ τ_sa², Σ τ_tot²).
    sums: [(f64, f64); 3],
}

impl PassivityGaitMeasure {
    /// Adds one tick: all actuated torques `tau`, each foot's ankle joints (indices into
    /// `tau`), and which feet are in contact.
    pub fn push(&mut self, tau: &[f64], ankles: &[[usize; 2]; 2], in_contact: [bool; 2]) {
        let all: f64 = tau.iter().map(|t| t * t).sum();
        let ankle = |f: usize| -> f64 { ankles[f].iter().map(|&j| tau[j] * tau[j]).sum() };
        match in_contact {
            [true, true] => {
                self.sums[0].0 += ankle(0) + ankle(1);
                self.sums[0].1 += all;
            }
            [true, false] | [false, true] => {
                let stance = if in_contact[0] { 0 } else { 1 };
                self.sums[1].0 += ankle(stance);
                self.sums[1].1 += all;
                self.sums[2].0 += ankle(1 - stance);
                self.sums[2].1 += all;
            }
            [false, false] => {}
        }
    }

    /// PGM in double support, single support (stance ankle) and for the flying foot; None for
    /// a phase that never occurred.
    pub fn values(&self) -> [Option<f64>; 3] {
        self.sums
            .map(|(sa, tot)| (tot > 0.0).then(|| 1.0 - (sa / tot).sqrt()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pgm_is_one_without_ankle_torque_and_zero_when_only_ankles_work() {
        let ankles = [[0, 1], [2, 3]];
        let mut p = PassivityGaitMeasure::default();
        p.push(&[0.0, 0.0, 0.0, 0.0, 5.0], &ankles, [true, true]);
        p.push(&[3.0, 4.0, 0.0, 0.0, 0.0], &ankles, [true, false]);
        let [ds, ss, fly] = p.values();
        assert_eq!(ds, Some(1.0));
        assert_eq!(ss, Some(0.0)); // the stance (left) ankle does all the work
        assert_eq!(fly, Some(1.0)); // the flying (right) ankle does none
                                    // RMS ratio: ankle 3 of total 5 → 1 − 3/5.
        let mut q = PassivityGaitMeasure::default();
        q.push(&[3.0, 0.0, 0.0, 0.0, 4.0], &ankles, [true, false]);
        assert!((q.values()[1].unwrap() - 0.4).abs() < 1e-12);
    }
}
