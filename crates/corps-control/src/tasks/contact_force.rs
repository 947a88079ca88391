//! Contact-force task (seed 000 §3.9, Eq 4.12; TSID `TaskContactForceEquality`): the wrench of
//! a named contact tracks `f_ref = F* + Kp∘(F* − F) + Kd∘(Ḟ* − Ḟ) + Ki∘I`, a PI with
//! feed-forward ("PI+") on the measured wrench `F`, whose integral leaks for anti-windup:
//! `I ← I + (e − leak·I) dt`, `e = F* − F`, leak rate 0.05 (seed 000 §3.9). In the
//! inverse-dynamics cost it weighs `‖T f − f_ref‖²` over the contact's force variables.

use nalgebra::Vector6;

#[derive(Clone, Debug)]
pub struct ContactForceTask {
    /// Name of the contact whose wrench is controlled.
    pub contact: String,
    pub kp: Vector6<f64>,
    pub kd: Vector6<f64>,
    pub ki: Vector6<f64>,
    /// Leak rate of the integral (1/s). Default 0.05 (seed 000 §3.9).
    pub leak: f64,
    /// Desired wrench `F*` and its derivative, contact frame, about the frame origin.
    pub reference: Vector6<f64>,
    pub reference_derivative: Vector6<f64>,
    integral: Vector6<f64>,
    /// The wrench the QP is asked for, from the last `update`.
    pub desired: Vector6<f64>,
}

impl ContactForceTask {
    /// Gains of seed 000 Table 5.2 are Kp = 10, Ki = 0.5 Kp.
    pub fn new(contact: &str, kp: Vector6<f64>, kd: Vector6<f64>, ki: Vector6<f64>) -> Self {
        Self {
            contact: contact.to_string(),
            kp,
            kd,
            ki,
            leak: 0.05,
            reference: Vector6::zeros(),
            reference_derivative: Vector6::zeros(),
            integral: Vector6::zeros(),
            desired: Vector6::zeros(),
        }
    }

    /// The integral state `I`.
    pub fn integral(&self) -> &Vector6<f64> {
        &self.integral
    }

    /// Updates `desired` from the measured wrench and its derivative over one period `dt`.
    pub fn update(&mut self, measured: &Vector6<f64>, measured_derivative: &Vector6<f64>, dt: f64) {
        let e = self.reference - measured;
        self.integral += (e - self.integral * self.leak) * dt;
        let de = self.reference_derivative - measured_derivative;
        self.desired = self.reference
            + self.kp.component_mul(&e)
            + self.kd.component_mul(&de)
            + self.ki.component_mul(&self.integral);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_leaky_integral_settles_at_error_over_leak_and_the_output_follows_the_law() {
        let one = Vector6::repeat(1.0);
        let mut t = ContactForceTask::new("c", one * 10.0, one * 0.0, one * 5.0);
        t.reference = Vector6::new(0.0, 0.0, 600.0, 0.0, 0.0, 0.0);
        let measured = Vector6::new(0.0, 0.0, 590.0, 0.0, 0.0, 0.0);
        for _ in 0..200_000 {
            t.update(&measured, &Vector6::zeros(), 1e-3);
        }
        // dI/dt = e − leak I = 0 at I = e / leak = 10 / 0.05 = 200 (after 200 s ≈ 10 time
        // constants of 1/leak = 20 s).
        assert!((t.integral()[2] - 200.0).abs() < 200.0 * 1e-4);
        let expected = 600.0 + 10.0 * 10.0 + 5.0 * t.integral()[2];
        assert!((t.desired[2] - expected).abs() < 1e-9);
        assert_eq!(t.desired[0], 0.0);
    }
}
