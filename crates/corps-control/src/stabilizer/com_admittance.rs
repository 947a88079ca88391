//! CoM admittance (seed 000 Eq 2.31; seed 002 §4.8, acceleration level):
//!
//! `c̈* = c̈_ref + K_adm (p − p*)`   (x, y; p = measured ZMP, p* = desired ZMP),
//!
//! integrated into a CoM reference `(c*, ċ*)` for the whole-body controller's CoM task. The
//! state is the offset `δ = c* − c_ref` with `δ̈ = K_adm (p − p*)`, so the reference's own
//! position, velocity and acceleration pass through unchanged; `|δ|` is saturated per axis
//! (and the outward offset velocity zeroed at the bound).

use nalgebra::{Vector2, Vector3};

/// Settings of [`ComAdmittance`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ComAdmittanceSettings {
    /// `K_adm` [s⁻²] on x and y. Default 15 (seed 000 Table 4.3, IK 20 cm walk; seed 002 §4.8
    /// reference script). TSID-position uses 12, the IK on stairs 45.
    pub gain: f64,
    /// Bound on each horizontal component of `c* − c_ref` [m]. Our choice: half the sole's
    /// half-length, which [`super::StabilizerSettings::new`] sets from the robot's sole (TALOS:
    /// 0.05 m of 0.10 m, seed 002 §2; the admittance moves the CoM reference by 2–5 mm on flat
    /// ground, seed 002 §5 item 9, and by a few cm after a push). Default 0.05 m.
    pub max_offset: f64,
}

impl Default for ComAdmittanceSettings {
    fn default() -> Self {
        Self {
            gain: 15.0,
            max_offset: 0.05,
        }
    }
}

/// CoM reference handed to the whole-body controller's CoM task.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ComReference {
    pub pos: Vector3<f64>,
    pub vel: Vector3<f64>,
    pub acc: Vector3<f64>,
}

/// CoM admittance integrator.
#[derive(Clone, Debug)]
pub struct ComAdmittance {
    pub settings: ComAdmittanceSettings,
    offset: Vector2<f64>,
    offset_vel: Vector2<f64>,
}

impl ComAdmittance {
    pub fn new(settings: ComAdmittanceSettings) -> Self {
        Self {
            settings,
            offset: Vector2::zeros(),
            offset_vel: Vector2::zeros(),
        }
    }

    /// Zero the offset and its velocity (seed 002 §4.8: `setState(comDes, 0)`).
    pub fn reset(&mut self) {
        self.offset = Vector2::zeros();
        self.offset_vel = Vector2::zeros();
    }

    /// Current offset `c* − c_ref` (x, y) [m].
    pub fn offset(&self) -> Vector2<f64> {
        self.offset
    }

    /// One tick: returns `(c*, ċ*, c̈*)`. `zmp` = measured p, `zmp_des` = p*.
    pub fn update(
        &mut self,
        com_ref: &Vector3<f64>,
        com_vel_ref: &Vector3<f64>,
        com_acc_ref: &Vector3<f64>,
        zmp: &Vector2<f64>,
        zmp_des: &Vector2<f64>,
        dt: f64,
    ) -> ComReference {
        let s = &self.settings;
        let acc = (zmp - zmp_des) * s.gain;
        // Exact integration over the tick for constant acceleration.
        for k in 0..2 {
            let mut x = self.offset[k] + self.offset_vel[k] * dt + 0.5 * acc[k] * dt * dt;
            let mut v = self.offset_vel[k] + acc[k] * dt;
            if x.abs() > s.max_offset {
                x = x.clamp(-s.max_offset, s.max_offset);
                if v * x > 0.0 {
                    v = 0.0;
                }
            }
            self.offset[k] = x;
            self.offset_vel[k] = v;
        }
        let mut out = ComReference {
            pos: *com_ref,
            vel: *com_vel_ref,
            acc: *com_acc_ref,
        };
        for k in 0..2 {
            out.pos[k] += self.offset[k];
            out.vel[k] += self.offset_vel[k];
            out.acc[k] += acc[k];
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zmp_error_accelerates_the_reference_and_the_offset_saturates() {
        let mut a = ComAdmittance::new(ComAdmittanceSettings::default());
        let z = Vector3::zeros();
        // Measured ZMP 1 cm ahead of the desired one: c̈* = 15 · 0.01 = 0.15 m/s² forward.
        let r = a.update(
            &z,
            &z,
            &z,
            &Vector2::new(0.01, 0.0),
            &Vector2::zeros(),
            0.01,
        );
        assert!((r.acc.x - 0.15).abs() < 1e-15 && r.acc.y == 0.0);
        assert!((r.vel.x - 0.0015).abs() < 1e-15);
        assert!((r.pos.x - 0.5 * 0.15 * 1e-4).abs() < 1e-15);
        for _ in 0..1000 {
            a.update(
                &z,
                &z,
                &z,
                &Vector2::new(0.01, 0.0),
                &Vector2::zeros(),
                0.01,
            );
        }
        assert_eq!(a.offset().x, 0.05);
        let r = a.update(
            &z,
            &z,
            &z,
            &Vector2::new(0.01, 0.0),
            &Vector2::zeros(),
            0.01,
        );
        assert_eq!(r.vel.x, 0.0);
    }
}
