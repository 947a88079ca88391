//! Identification records: simulated from the drive model with sensor noise, or read from a
//! CSV file.
//!
//! The CSV format: a header naming the columns `t_s`, `q_rad`, `current_A`,
//! `torque_sensor_Nm` and `payload` (0 without the payload, 1 with it), in any order, then one
//! sample per line. Experiments are the runs of equal `payload`; time increases within each
//! and may restart where `payload` changes.

use crate::description::ActuatorDescription;
use crate::elbow::Payload;
use crate::error::ActuatorError;
use crate::excitation::Excitation;
use crate::identification::{IdentificationData, Segment};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

/// The simulated experiments: sampling, sensor noise and payload.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RecordSimulation {
    /// EtherCAT rate, Hz (seed 000 §6 step 2: ~2 kHz).
    pub sample_hz: f64,
    /// Encoder resolution, bits per turn (the thesis: 19).
    pub encoder_bits: u32,
    /// Standard deviation of the current measurement, A.
    pub current_noise_a: f64,
    /// Standard deviation of the torque sensor, N·m.
    pub torque_noise_nm: f64,
    /// The known payload: mass (kg) at a distance (m) along the link.
    pub payload_kg: f64,
    pub payload_distance_m: f64,
    /// Margin kept from the position limits, rad; fraction of the velocity limit reached.
    pub range_margin: f64,
    pub velocity_fraction: f64,
    pub seed: u64,
}

impl Default for RecordSimulation {
    /// Current noise 0.055 A: `R K_m σ_i` ≈ 0.58 N·m, the thesis's fit RMSD (0.6 N·m, §4.1),
    /// as the noise floor of a model without error; torque sensor 0.3 N·m; a 2 kg payload at
    /// 0.3 m (its `L_Y` = 0.6 kg·m is the known parameter).
    fn default() -> Self {
        Self {
            sample_hz: 2000.0,
            encoder_bits: 19,
            current_noise_a: 0.055,
            torque_noise_nm: 0.3,
            payload_kg: 2.0,
            payload_distance_m: 0.3,
            range_margin: 0.05,
            velocity_fraction: 1.0,
            seed: 1,
        }
    }
}

impl RecordSimulation {
    /// The payload as the model sees it.
    pub fn payload(&self) -> Payload {
        Payload::point_mass(self.payload_kg, self.payload_distance_m)
    }

    /// Two experiments (without, then with the payload) on the exciting trajectory over the
    /// joint's range, tracked exactly (current from the inverse model), measured through a
    /// quantised encoder and noisy current and torque sensors.
    pub fn run(&self, actuator: &ActuatorDescription) -> IdentificationData {
        let [lo, hi] = actuator.limits.position;
        let excitation = Excitation::thesis(
            [lo + self.range_margin, hi - self.range_margin],
            self.velocity_fraction * actuator.limits.velocity[1].min(-actuator.limits.velocity[0]),
        );
        let motion = excitation.sample(self.sample_hz);
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
        let current_noise = Normal::new(0.0, self.current_noise_a.max(0.0)).unwrap();
        let torque_noise = Normal::new(0.0, self.torque_noise_nm.max(0.0)).unwrap();
        let tick = 2.0 * std::f64::consts::PI / f64::powi(2.0, self.encoder_bits as i32);
        let m = &actuator.model;
        let segments = [false, true]
            .into_iter()
            .map(|with| {
                let payload = if with {
                    self.payload()
                } else {
                    Payload::default()
                };
                let mut s = Segment {
                    payload: with,
                    ..Segment::default()
                };
                for k in 0..motion.t.len() {
                    let (q, v, a) = (motion.q[k], motion.v[k], motion.a[k]);
                    let sign = if v == 0.0 { 0.0 } else { v.signum() };
                    let motor = m.motor_torque(q, v, a, sign, &payload);
                    let joint = m.joint_torque(q, v, a, sign, &payload);
                    s.t.push(motion.t[k]);
                    s.q.push((q / tick).round() * tick);
                    s.current
                        .push(motor / m.drive_gain + current_noise.sample(&mut rng));
                    s.torque_sensor
                        .push(joint / m.torque_sensor_gain + torque_noise.sample(&mut rng));
                }
                s
            })
            .collect();
        IdentificationData {
            segments,
            payload_moment: self.payload().l_y,
        }
    }
}

/// The true value of each identified parameter (in the order of
/// [`crate::identification::PARAMETER_NAMES`]) for a simulated record.
pub fn truth(actuator: &ActuatorDescription, payload: &Payload) -> Vec<f64> {
    let m = &actuator.model;
    vec![
        m.m_x,
        m.m_y,
        m.i_m,
        m.f_vm,
        m.f_sm,
        m.off_m,
        m.i_j,
        m.f_vj,
        m.f_sj,
        m.off_j,
        m.drive_gain,
        m.torque_sensor_gain,
        payload.inertia,
        payload.l_x,
        payload.l_y,
    ]
}

/// The CSV columns, in the order written.
pub const CSV_COLUMNS: [&str; 5] = ["t_s", "q_rad", "current_A", "torque_sensor_Nm", "payload"];

/// Reads a record in the CSV format of the module's documentation; `payload_moment` is the
/// known payload's `L_Y`, kg·m.
pub fn read_csv(text: &str, payload_moment: f64) -> Result<IdentificationData, ActuatorError> {
    let mut segments: Vec<Segment> = Vec::new();
    crate::csv_rows::read_rows(text, CSV_COLUMNS, |line, v| {
        let payload = match v[4] {
            0.0 => false,
            1.0 => true,
            x => {
                return Err(ActuatorError::Data(format!(
                    "line {}: payload must be 0 or 1, not {x}",
                    line
                )))
            }
        };
        if segments.last().is_none_or(|s| s.payload != payload) {
            segments.push(Segment {
                payload,
                ..Segment::default()
            });
        }
        let s = segments.last_mut().expect("pushed above");
        if v[..4].iter().any(|x: &f64| !x.is_finite()) {
            return Err(ActuatorError::Data(format!(
                "line {}: a non-finite value",
                line
            )));
        }
        if let Some(&last) = s.t.last() {
            if v[0] <= last {
                return Err(ActuatorError::Data(format!(
                    "line {}: time {} s does not increase (previous {} s)",
                    line, v[0], last
                )));
            }
        }
        s.t.push(v[0]);
        s.q.push(v[1]);
        s.current.push(v[2]);
        s.torque_sensor.push(v[3]);
        Ok(())
    })?;
    Ok(IdentificationData {
        segments,
        payload_moment,
    })
}

/// Writes `data` in the CSV format.
pub fn write_csv(data: &IdentificationData) -> String {
    let mut out = CSV_COLUMNS.join(",");
    out.push('\n');
    for s in &data.segments {
        for k in 0..s.t.len() {
            out.push_str(&format!(
                "{},{},{},{},{}\n",
                s.t[k],
                s.q[k],
                s.current[k],
                s.torque_sensor[k],
                u8::from(s.payload)
            ));
        }
    }
    out
}
