//! Closed-loop tests of `corps_control::stabilizer` on a simulated position-controlled LIPM.
//!
//! The "robot" (TALOS numbers, seed 002 §2: m = 90.2722 kg, c_z = 0.876681 m, feet 0.162 m
//! apart, soles 0.20 × 0.12 m):
//! - the true CoM (x, y) obeys the LIPM `c̈ = ω²(c − p_r)` (seed 000 Eq 2.25);
//! - its whole-body controller tracks the stabilizer's CoM reference with the IK's CoM gain
//!   `Kp = 100 s⁻²` (seed 000 Table 4.3) and `Kd = 2√Kp`, i.e. asks for the ZMP
//!   `p_cmd = c − (c̈* + Kp(c* + d − c) + Kd(ċ* − ċ))/ω²`, where `d` is a static servo
//!   deflection (the CoM lands at `c* + d`);
//! - the body realizes `p_cmd` through a first-order lag of 30 ms, clipped to the support
//!   polygon (the ZMP cannot leave it);
//! - it splits that ZMP over the feet as the stabilizer's distribution asks (normal forces
//!   through the same 30 ms lag; each foot's CoP shifted by the same world offset, so the
//!   total ZMP is the body's), then each foot's CoP
//!   moves with its ankle tilt `θ` (the previous tick's ankle command, held by a stiff servo on
//!   a stiff floor: `Δτ = −k θ`, i.e. `Δcop = (k θ_pitch, −k θ_roll)/f_z`, `k = 10⁶ N·m/rad`,
//!   the stiffness implied by the report's unfiltered threshold, see `ankle_admittance.rs`), plus
//!   an optional disturbance (a stick under the left toe), and is clipped to its sole; the
//!   realized ZMP `p_r` is the ZMP of these foot wrenches and drives the CoM;
//! - the stabilizer measures the CoM, its velocity and the foot wrenches exactly, and the ZMP
//!   from the foot wrenches.

use corps_control::stabilizer::*;
use corps_testkit::{allocations_during, CountingAllocator};
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector2, Vector3};

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

const M: f64 = 90.2722;
const G: f64 = 9.81;
const ZC: f64 = 0.876681;
const DT: f64 = 1e-3;
const LAG: f64 = 0.03;
const KP_COM: f64 = 100.0;
const K_TILT: f64 = 1e6;

fn feet() -> [Isometry3<f64>; 2] {
    [
        Isometry3::from_parts(
            Translation3::new(0.0, 0.081, 0.0),
            UnitQuaternion::identity(),
        ),
        Isometry3::from_parts(
            Translation3::new(0.0, -0.081, 0.0),
            UnitQuaternion::identity(),
        ),
    ]
}

struct Sim {
    c: Vector2<f64>,
    cd: Vector2<f64>,
    body_zmp: Vector2<f64>,
    deflection: Vector2<f64>,
    /// CoP offset of the left foot from a stick under its toe (sole frame) [m].
    stick: Vector2<f64>,
    feet: [Isometry3<f64>; 2],
    wrenches: [Wrench; 2],
    zmp: Vector2<f64>,
    cops: [Vector2<f64>; 2],
    /// Realized normal forces: the requested split through the same 30 ms lag.
    fz: [f64; 2],
    body_clipped: usize,
}

impl Sim {
    fn new(c: Vector2<f64>, deflection: Vector2<f64>) -> Self {
        let f = feet();
        let half = Wrench::new(Vector3::new(0.0, 0.0, 0.5 * M * G), Vector3::zeros());
        let mut s = Self {
            c,
            cd: Vector2::zeros(),
            body_zmp: c,
            deflection,
            stick: Vector2::zeros(),
            feet: f,
            wrenches: [half; 2],
            zmp: c,
            cops: [Vector2::zeros(); 2],
            fz: [0.5 * M * G; 2],
            body_clipped: 0,
        };
        // Static start: both feet share the weight around ZMP = c.
        for i in 0..2 {
            let cop = c - s.feet[i].translation.vector.xy();
            s.wrenches[i].torque = Vector3::new(cop.y * half.force.z, -cop.x * half.force.z, 0.0);
        }
        s
    }

    fn omega() -> f64 {
        (G / ZC).sqrt()
    }

    fn input(&self, phase: ContactPhase) -> StabilizerInput {
        StabilizerInput {
            com_ref: Vector3::new(0.0, 0.0, ZC),
            com_vel_ref: Vector3::zeros(),
            com_acc_ref: Vector3::zeros(),
            zmp_ref: Vector2::zeros(),
            com: Vector3::new(self.c.x, self.c.y, ZC),
            com_vel: Vector3::new(self.cd.x, self.cd.y, 0.0),
            zmp: self.zmp,
            feet: self.feet,
            foot_wrenches: self.wrenches,
            phase,
        }
    }

    fn step(&mut self, out: &StabilizerOutput, phase: ContactPhase) {
        let w2 = Self::omega().powi(2);
        let kd = 2.0 * KP_COM.sqrt();
        let acc_cmd = out.com.acc.xy()
            + (out.com.pos.xy() + self.deflection - self.c) * KP_COM
            + (out.com.vel.xy() - self.cd) * kd;
        let p_cmd = self.c - acc_cmd / w2;
        self.body_zmp += (p_cmd - self.body_zmp) * (DT / LAG);
        let clipped = out.support.closest_point(&self.body_zmp);
        if (clipped - self.body_zmp).norm() > 1e-12 {
            self.body_clipped += 1;
        }
        self.body_zmp = clipped;
        let sole = Sole::default();
        let (mut num, mut den) = (Vector2::zeros(), 0.0);
        let shift = self.body_zmp - out.zmp_distributed;
        for i in 0..2 {
            if !phase.in_contact(i) {
                self.wrenches[i] = Wrench::default();
                self.cops[i] = Vector2::zeros();
                continue;
            }
            self.fz[i] += (out.foot_wrenches[i].force.z - self.fz[i]) * (DT / LAG);
            let fz = self.fz[i];
            let rot = self.feet[i].rotation;
            let shift_sole = (rot.inverse() * Vector3::new(shift.x, shift.y, 0.0)).xy();
            let th = out.ankle[i].offset;
            let mut cop =
                out.foot_cops[i] + shift_sole + Vector2::new(K_TILT * th.y, -K_TILT * th.x) / fz;
            if i == LEFT {
                cop += self.stick;
            }
            let cop = sole.clamp_cop(&cop);
            self.cops[i] = cop;
            let world = self.feet[i] * nalgebra::Point3::new(cop.x, cop.y, 0.0);
            num += Vector2::new(world.x, world.y) * fz;
            den += fz;
            self.wrenches[i] = Wrench::new(
                Vector3::new(0.0, 0.0, fz),
                Vector3::new(cop.y * fz, -cop.x * fz, 0.0),
            );
        }
        let p_r = num / den;
        let acc = (self.c - p_r) * w2;
        // Horizontal forces shared in proportion to the normal forces.
        for i in 0..2 {
            let share = self.wrenches[i].force.z / den;
            self.wrenches[i].force.x = share * M * acc.x;
            self.wrenches[i].force.y = share * M * acc.y;
        }
        self.cd += acc * DT;
        self.c += self.cd * DT;
        self.zmp = zmp_from_feet(&self.feet, &self.wrenches, 0.0).unwrap();
    }
}

fn dcm_of(s: &Sim) -> Vector2<f64> {
    s.c + s.cd / Sim::omega()
}

#[test]
fn constant_com_deflection_is_removed() {
    let d = Vector2::new(0.005, 0.005);
    // Open loop reference: without the stabilizer the CoM sits at c_ref + d.
    let mut open = Sim::new(d, d);
    let mut st = Stabilizer::new(StabilizerSettings::default()).unwrap();
    let mut closed = Sim::new(d, d);
    let mut max_err = 0.0f64;
    for _ in 0..20_000 {
        let out = st.tick(&open.input(ContactPhase::Double)).unwrap();
        // Open loop: hand the robot the plain reference, keep the distribution's split.
        let mut plain = out;
        plain.com = ComReference {
            pos: Vector3::new(0.0, 0.0, ZC),
            ..Default::default()
        };
        plain.ankle = [AnkleCommand::default(); 2];
        open.step(&plain, ContactPhase::Double);
    }
    st.reset();
    for _ in 0..20_000 {
        let out = st.tick(&closed.input(ContactPhase::Double)).unwrap();
        closed.step(&out, ContactPhase::Double);
        max_err = max_err.max((closed.c - d).norm());
    }
    let open_err = open.c.norm();
    let com_err = closed.c.norm();
    let dcm_err = dcm_of(&closed).norm();
    println!(
        "deflection 5 mm (x, y): open-loop CoM error {:.3} mm; stabilized after 20 s: CoM error {:.4} mm, DCM error {:.4} mm, CoM offset ref {:?} mm, DCM integral {:?}",
        open_err * 1e3,
        com_err * 1e3,
        dcm_err * 1e3,
        st.com_offset() * 1e3,
        st.dcm_integral()
    );
    assert!(
        open_err > 0.0069,
        "the disturbance must be visible without the stabilizer"
    );
    assert!(com_err < 5e-4 && dcm_err < 5e-4);
    assert_eq!(closed.body_clipped, 0);
}

#[test]
fn push_recovery_keeps_the_dcm_inside_the_support() {
    let mut st = Stabilizer::new(StabilizerSettings::default()).unwrap();
    let mut sim = Sim::new(Vector2::zeros(), Vector2::zeros());
    let omega = Sim::omega();
    let mut peak = Vector2::zeros();
    let mut out_of_polygon = 0;
    let mut settle_time = None;
    let push_tick = 1000;
    for k in 0..8000 {
        if k == push_tick {
            sim.cd.x += 0.1;
        }
        let out = st.tick(&sim.input(ContactPhase::Double)).unwrap();
        let xi = dcm_of(&sim);
        if !out.support.contains(&xi, 0.0) {
            out_of_polygon += 1;
        }
        if xi.x.abs() > peak.x {
            peak = xi;
        }
        if k > push_tick && xi.norm() > 1e-3 {
            settle_time = None;
        } else if k > push_tick && settle_time.is_none() {
            settle_time = Some((k - push_tick) as f64 * DT);
        }
        sim.step(&out, ContactPhase::Double);
    }
    let settle = settle_time.expect("the DCM must return within 1 mm");
    println!(
        "push 0.1 m/s: DCM jump {:.1} mm, peak DCM x {:.1} mm, back within 1 mm after {:.3} s, final DCM {:.2e} m, DCM outside polygon {} ticks, body ZMP clipped {} ticks",
        0.1 / omega * 1e3,
        peak.x * 1e3,
        settle,
        dcm_of(&sim).norm(),
        out_of_polygon,
        sim.body_clipped
    );
    // Capturability: a DCM beyond the sole edge (x = 0.10 m) cannot be brought back without a
    // step (ξ̇ = ω(ξ − p) with p inside the polygon).
    assert_eq!(out_of_polygon, 0);
    assert!(peak.x < 0.10);
    // Closed-loop DCM error dynamics ė = −K_P e (seed 000 Eq 2.29, K_P = 8 s⁻¹, τ = 0.125 s),
    // slowed by the 30 ms ZMP lag and the CoM servo: the slowest closed-loop mode of the
    // admittance/DCM pair (ω_n ≈ 3.9 s⁻¹, ζ ≈ 0.8 for K_adm = 15, module docs) settles 3 cm to
    // 1 mm in ≈ ln(30)/(ζ ω_n) ≈ 1.1 s; allow 2 s.
    assert!(settle < 2.0, "settled after {settle} s");
}

/// Energy of `x` (mean removed, linear trend removed) above `f_min` Hz, as an RMS value, by a
/// direct DFT.
fn rms_above(x: &[f64], f_min: f64) -> f64 {
    let n = x.len();
    let nf = n as f64;
    let tm = (nf - 1.0) / 2.0;
    let mean = x.iter().sum::<f64>() / nf;
    let slope = x
        .iter()
        .enumerate()
        .map(|(i, v)| (i as f64 - tm) * (v - mean))
        .sum::<f64>()
        / (0..n).map(|i| (i as f64 - tm).powi(2)).sum::<f64>();
    let y: Vec<f64> = x
        .iter()
        .enumerate()
        .map(|(i, v)| v - mean - slope * (i as f64 - tm))
        .collect();
    let k_min = (f_min * nf * DT).ceil() as usize;
    let mut energy = 0.0;
    for k in k_min.max(1)..=n / 2 {
        let (mut re, mut im) = (0.0, 0.0);
        for (i, v) in y.iter().enumerate() {
            let a = -2.0 * std::f64::consts::PI * (k * i) as f64 / nf;
            re += v * a.cos();
            im += v * a.sin();
        }
        let mult = if k == n / 2 { 1.0 } else { 2.0 };
        energy += mult * (re * re + im * im) / (nf * nf);
    }
    energy.sqrt()
}

struct SweepResult {
    hf_cop: f64,
    hf_rate: f64,
    cop_err: f64,
    dcm_err: f64,
}

fn ankle_sweep_run(gain: f64, cutoff_hz: f64) -> SweepResult {
    let mut settings = StabilizerSettings::default();
    settings.ankle.gain = gain;
    settings.ankle.filter_cutoff_hz = cutoff_hz;
    let mut st = Stabilizer::new(settings).unwrap();
    let mut sim = Sim::new(Vector2::zeros(), Vector2::zeros());
    let (n, tail) = (6000, 2000);
    let mut cop = Vec::with_capacity(tail);
    let mut rate = Vec::with_capacity(tail);
    let mut out = st.tick(&sim.input(ContactPhase::Double)).unwrap();
    for k in 0..n {
        if k == 1000 {
            // A 2 cm CoP shift under the left toe (seed 002 S10/S11: a stick under the toe).
            sim.stick = Vector2::new(0.02, 0.0);
        }
        out = st.tick(&sim.input(ContactPhase::Double)).unwrap();
        sim.step(&out, ContactPhase::Double);
        if k >= n - tail {
            cop.push(sim.cops[LEFT].x);
            rate.push(out.ankle[LEFT].velocity.y);
        }
    }
    SweepResult {
        hf_cop: rms_above(&cop, 5.0),
        hf_rate: rms_above(&rate, 5.0),
        cop_err: (sim.cops[LEFT] - out.foot_cops[LEFT]).norm(),
        dcm_err: dcm_of(&sim).norm(),
    }
}

#[test]
fn ankle_gain_sweep_has_no_high_frequency_oscillation() {
    // The design (10 Hz filter + 0.1 rad/s clamp) at the report's gains 0 and 0.001 (seed 002
    // §4.10, §5 items 26–28); 0.01 is the ignored test below.
    for gain in [0.0, 0.001] {
        let r = ankle_sweep_run(gain, AnkleAdmittanceSettings::default().filter_cutoff_hz);
        println!(
            "ankle gain {gain}: last 2 s RMS above 5 Hz: left CoP x {:.2e} m, pitch rate {:.2e} rad/s; left CoP error {:.3} mm; DCM error {:.4} mm",
            r.hf_cop, r.hf_rate, r.cop_err * 1e3, r.dcm_err * 1e3
        );
        // Sustained oscillation threshold: 0.1 mm of CoP (below F/T CoP resolution) and 1 % of
        // the 0.1 rad/s rate clamp.
        assert!(
            r.hf_cop < 1e-4 && r.hf_rate < 1e-3,
            "gain {gain} oscillates"
        );
        if gain > 0.0 {
            // The admittance brings the left CoP back to its desired value (the sign is right).
            assert!(r.cop_err < 1e-4, "gain {gain}: CoP error {}", r.cop_err);
        } else {
            // Without it the CoM loop restores the total ZMP by shifting both feet's CoPs by
            // −stick/2 (equal normal forces), so the left CoP stays 20 · 0.5 = 10 mm off.
            assert!((r.cop_err - 0.01).abs() < 1e-3, "CoP error {}", r.cop_err);
        }
    }
    // Without the filter, 0.01 reproduces the report's failure: an oscillation at the sampling
    // rate, bounded only by the clamp and the sole (checks that the detector sees one).
    let r = ankle_sweep_run(0.01, f64::INFINITY);
    println!(
        "ankle gain 0.01 unfiltered: RMS above 5 Hz: left CoP x {:.2e} m, pitch rate {:.2e} rad/s",
        r.hf_cop, r.hf_rate
    );
    assert!(r.hf_cop > 1e-3 && r.hf_rate > 1e-2);
}

/// Known failure: at A = 0.01 with the 10^6 N·m/rad floor the coupled loop (ankle admittance +
/// distribution + CoM/DCM feedback through the measured ZMP) does not settle — the left CoP
/// ends pinned near a sole edge with a residual high-frequency component — for any filter
/// cutoff from 5 to 100 Hz (scan in the report); A ≤ 0.003 settles.
#[test]
#[ignore = "known failure: ankle gain 0.01 does not settle in the coupled loop at k = 1e6 N·m/rad"]
fn ankle_gain_0_01_settles() {
    let r = ankle_sweep_run(0.01, AnkleAdmittanceSettings::default().filter_cutoff_hz);
    println!(
        "ankle gain 0.01: RMS above 5 Hz: left CoP x {:.2e} m, pitch rate {:.2e} rad/s; left CoP error {:.2} mm",
        r.hf_cop, r.hf_rate, r.cop_err * 1e3
    );
    assert!(r.hf_cop < 1e-4 && r.hf_rate < 1e-3 && r.cop_err < 1e-4);
}

#[test]
fn a_stabilizer_tick_does_not_allocate() {
    let mut st = Stabilizer::new(StabilizerSettings {
        ankle: AnkleAdmittanceSettings {
            gain: 0.01,
            ..Default::default()
        },
        ..Default::default()
    })
    .unwrap();
    let mut sim = Sim::new(Vector2::zeros(), Vector2::new(0.003, -0.002));
    let phases = [
        ContactPhase::Double,
        ContactPhase::LeftSupport,
        ContactPhase::Double,
        ContactPhase::RightSupport,
    ];
    // Warm-up tick in each phase.
    for p in phases {
        let _ = st.tick(&sim.input(p)).unwrap();
    }
    let mut ticks = 0;
    let n = allocations_during(|| {
        for k in 0..4000 {
            let phase = phases[(k / 500) % 4];
            if k == 700 {
                sim.cd.x += 0.05;
            }
            let mut input = sim.input(phase);
            input.zmp_ref.x = 0.01 * ((k as f64) * 0.002).sin();
            let out = st.tick(&input).unwrap();
            // Double support only for the sim (it models no swing); feed it the same output.
            if phase == ContactPhase::Double {
                sim.step(&out, phase);
            }
            ticks += 1;
        }
    });
    assert_eq!(ticks, 4000);
    assert_eq!(n, 0, "{n} allocations in 4000 ticks");
}

#[test]
fn non_finite_input_and_bad_settings_are_errors() {
    assert!(Stabilizer::new(StabilizerSettings {
        mass: -1.0,
        ..Default::default()
    })
    .is_err());
    let mut st = Stabilizer::new(StabilizerSettings::default()).unwrap();
    let sim = Sim::new(Vector2::zeros(), Vector2::zeros());
    let mut input = sim.input(ContactPhase::Double);
    input.com.x = f64::NAN;
    assert!(st.tick(&input).is_err());
}

/// The servo-held robot as an inverted pendulum on a spring (x and y alike, see "Sway damping"
/// in the `stabilizer` module docs): `c̈ = ω²c − K_s(c − u) − D ċ` with `K_s = 81 s⁻²`,
/// ζ = 0.013 (TALOS in the corps simulator: 1.33 Hz sway); `u` follows the stabilizer's CoM
/// reference through the IK (`u̇ = ċ* + 100 (c* − u)`); the feet share the weight, each CoP
/// at the ZMP `p = c − c̈/ω²`. Returns the largest |c| over the last second of `seconds`.
fn sway_run(sway_damping: f64, seconds: f64) -> f64 {
    let w2 = G / ZC;
    let ks = 81.0;
    let d = 2.0 * 0.013 * (ks - w2).sqrt();
    let mut st = Stabilizer::new(StabilizerSettings {
        sway_damping,
        ..Default::default()
    })
    .unwrap();
    let f = feet();
    let (mut c, mut cd) = (Vector2::new(0.003, 0.003), Vector2::zeros());
    let mut u = Vector2::zeros();
    let mut acc = (c - u) * -ks + c * w2 - cd * d;
    let n = (seconds / DT).round() as usize;
    let mut tail_max = 0.0f64;
    for k in 0..n {
        let p = c - acc / w2;
        let wrenches = [0, 1].map(|i| {
            let cop = p - f[i].translation.vector.xy();
            let fz = 0.5 * M * G;
            Wrench::new(
                Vector3::new(0.5 * M * acc.x, 0.5 * M * acc.y, fz),
                Vector3::new(cop.y * fz, -cop.x * fz, 0.0),
            )
        });
        let input = StabilizerInput {
            com_ref: Vector3::new(0.0, 0.0, ZC),
            com_vel_ref: Vector3::zeros(),
            com_acc_ref: Vector3::zeros(),
            zmp_ref: Vector2::zeros(),
            com: Vector3::new(c.x, c.y, ZC),
            com_vel: Vector3::new(cd.x, cd.y, 0.0),
            zmp: p,
            feet: f,
            foot_wrenches: wrenches,
            phase: ContactPhase::Double,
        };
        let out = st.tick(&input).unwrap();
        u += (out.com.vel.xy() + (out.com.pos.xy() - u) * KP_COM) * DT;
        acc = c * w2 - (c - u) * ks - cd * d;
        cd += acc * DT;
        c += cd * DT;
        if (k as f64) * DT >= seconds - 1.0 {
            tail_max = tail_max.max(c.norm());
        }
    }
    tail_max
}

#[test]
fn sway_damping_stabilizes_the_servo_held_pendulum() {
    // Eq 2.30–2.31 alone (g_d = 0): the 3 mm initial offset grows into the sway.
    let undamped = sway_run(0.0, 4.0);
    // Default g_d = 0.1 s: the offset is gone.
    let damped = sway_run(StabilizerSettings::default().sway_damping, 10.0);
    println!(
        "flexible LIPM, 3 mm start: max |c| over the last second, g_d = 0 after 4 s: {:.2} mm; g_d = 0.1 s after 10 s: {:.4} mm",
        undamped * 1e3,
        damped * 1e3
    );
    assert!(undamped > 0.003 * 2f64.sqrt(), "{undamped}");
    assert!(damped < 1e-4, "{damped}");
}
