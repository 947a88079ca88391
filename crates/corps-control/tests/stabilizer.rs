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
//!   a floor of rotational stiffness `k`: `Δτ = −k θ`, i.e.
//!   `Δcop = (k_pitch θ_pitch, −k_roll θ_roll)/f_z`, see [`Floor`]), plus an optional
//!   disturbance (a stick under the left toe), and is clipped to its sole; the realized ZMP
//!   `p_r` is the ZMP of these foot wrenches and drives the CoM;
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

/// Rotational stiffness of the floor under one foot [N·m/rad].
#[derive(Clone, Copy, Debug)]
struct Floor {
    pitch: f64,
    roll: f64,
}

impl Floor {
    /// A penalty contact of `kn` N/m per m² over the whole sole (0.2 × 0.12 m):
    /// `k_pitch = kn · w l³/12`, `k_roll = kn · l w³/12`.
    fn penalty(kn: f64) -> Self {
        let s = Sole::new(0.10, 0.06, 0.107);
        let (l, w) = (2.0 * s.half_length, 2.0 * s.half_width);
        Self {
            pitch: kn * w * l.powi(3) / 12.0,
            roll: kn * l * w.powi(3) / 12.0,
        }
    }

    /// The corps simulator's default contact (`corps_sim::ContactParams`, 4·10⁷ N/m³):
    /// 3.2·10³ / 1.2·10³ N·m/rad.
    fn simulator() -> Self {
        Self::penalty(4e7)
    }

    /// Its 10× stiff contact (the `tsid_torque_*` walk scenarios, 4·10⁸ N/m³).
    fn simulator_stiff() -> Self {
        Self::penalty(4e8)
    }

    /// 10⁶ N·m/rad: the stiffness at which the report's unfiltered threshold `A ≈ 0.001` would
    /// be the Nyquist bound `A k dt = 2` (see `ankle_admittance.rs`) [derived].
    fn report() -> Self {
        Self {
            pitch: 1e6,
            roll: 1e6,
        }
    }
}

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
    floor: Floor,
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
            floor: Floor::report(),
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
        let sole = Sole::new(0.10, 0.06, 0.107);
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
            let k = self.floor;
            let mut cop =
                out.foot_cops[i] + shift_sole + Vector2::new(k.pitch * th.y, -k.roll * th.x) / fz;
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
    let mut st = Stabilizer::new(talos_settings()).unwrap();
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
    let mut st = Stabilizer::new(talos_settings()).unwrap();
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
    /// RMS above 5 Hz over the last 2 s of the left CoP (worse of x, y) [m] and of the left
    /// ankle rate (worse of roll, pitch) [rad/s].
    hf_cop: f64,
    hf_rate: f64,
    cop_err: f64,
    dcm_err: f64,
}

impl SweepResult {
    /// No sustained oscillation: 0.1 mm of CoP (below F/T CoP resolution) and 1 % of the
    /// 0.1 rad/s rate clamp.
    fn quiet(&self) -> bool {
        self.hf_cop < 1e-4 && self.hf_rate < 1e-3
    }
}

fn ankle_sweep_run(ankle: AnkleAdmittanceSettings, floor: Floor) -> SweepResult {
    let settings = StabilizerSettings {
        ankle,
        ..talos_settings()
    };
    let mut st = Stabilizer::new(settings).unwrap();
    let mut sim = Sim::new(Vector2::zeros(), Vector2::zeros());
    sim.floor = floor;
    let (n, tail) = (6000, 2000);
    let mut cop = [Vec::with_capacity(tail), Vec::with_capacity(tail)];
    let mut rate = [Vec::with_capacity(tail), Vec::with_capacity(tail)];
    let mut out = st.tick(&sim.input(ContactPhase::Double)).unwrap();
    for k in 0..n {
        if k == 1000 {
            // A 2 cm CoP shift under the left toe (seed 002 S10/S11: a stick under the toe).
            sim.stick = Vector2::new(0.02, 0.0);
        }
        out = st.tick(&sim.input(ContactPhase::Double)).unwrap();
        sim.step(&out, ContactPhase::Double);
        if k >= n - tail {
            for a in 0..2 {
                cop[a].push(sim.cops[LEFT][a]);
                rate[a].push(out.ankle[LEFT].velocity[a]);
            }
        }
    }
    SweepResult {
        hf_cop: rms_above(&cop[0], 5.0).max(rms_above(&cop[1], 5.0)),
        hf_rate: rms_above(&rate[0], 5.0).max(rms_above(&rate[1], 5.0)),
        cop_err: (sim.cops[LEFT] - out.foot_cops[LEFT]).norm(),
        dcm_err: dcm_of(&sim).norm(),
    }
}

fn floors() -> [(&'static str, Floor); 3] {
    [
        ("simulator floor", Floor::simulator()),
        ("stiff simulator floor", Floor::simulator_stiff()),
        ("report-derived floor", Floor::report()),
    ]
}

#[test]
fn ankle_gain_sweep_has_no_high_frequency_oscillation() {
    // The design (10 Hz filter with a 5 % lead + 0.1 rad/s clamp, `ankle_admittance.rs`) at
    // the report's gains (seed 002 §4.10, §5 items 26–28), on the corps simulator's floors and
    // on the stiff floor derived from the report's threshold.
    for (name, floor) in floors() {
        for gain in [0.0, 0.001, 0.01] {
            let r = ankle_sweep_run(
                AnkleAdmittanceSettings {
                    gain,
                    ..Default::default()
                },
                floor,
            );
            println!(
                "{name} ({:.1e} / {:.1e} N·m/rad), ankle gain {gain}: last 2 s RMS above 5 Hz: left CoP {:.2e} m, rate {:.2e} rad/s; left CoP error {:.4} mm; DCM error {:.4} mm",
                floor.pitch, floor.roll, r.hf_cop, r.hf_rate, r.cop_err * 1e3, r.dcm_err * 1e3
            );
            assert!(r.quiet(), "{name}: gain {gain} oscillates");
            if gain > 0.0 {
                // The admittance brings the left CoP back to its desired value (the sign is
                // right).
                assert!(
                    r.cop_err < 1e-4,
                    "{name}: gain {gain}: CoP error {}",
                    r.cop_err
                );
            } else {
                // Without it the CoM loop restores the total ZMP by shifting both feet's CoPs
                // by −stick/2 (equal normal forces), so the left CoP stays 20 · 0.5 = 10 mm off.
                assert!((r.cop_err - 0.01).abs() < 1e-3, "CoP error {}", r.cop_err);
            }
        }
    }
}

/// What the lead is for: on the report-derived floor at A = 0.01, the 10 Hz filter alone
/// (ζ ≈ 0.04, `ankle_admittance.rs`) does not settle — the roll loop locks into a ≈ 100 Hz
/// limit cycle between the sole edges — and without any filter the loop chatters at the
/// sampling rate (the report's failure). Checks that the detector sees both.
#[test]
fn without_the_lead_or_the_filter_gain_0_01_oscillates_on_a_stiff_floor() {
    let filter_only = ankle_sweep_run(
        AnkleAdmittanceSettings {
            gain: 0.01,
            lead_fraction: 0.0,
            ..Default::default()
        },
        Floor::report(),
    );
    let unfiltered = ankle_sweep_run(
        AnkleAdmittanceSettings {
            gain: 0.01,
            filter_cutoff_hz: f64::INFINITY,
            ..Default::default()
        },
        Floor::report(),
    );
    for (name, r) in [("filter only", &filter_only), ("unfiltered", &unfiltered)] {
        println!(
            "ankle gain 0.01, report-derived floor, {name}: RMS above 5 Hz: left CoP {:.2e} m, rate {:.2e} rad/s; left CoP error {:.2} mm",
            r.hf_cop, r.hf_rate, r.cop_err * 1e3
        );
        assert!(!r.quiet() && r.cop_err > 1e-3, "{name} settled");
    }
}

/// The stable region of the design in the coupled loop, floor stiffness × gain (the stick
/// test above): it settles up to `A k dt = 10` and fails from `β A k dt = 1` (`A k dt = 20` at
/// `β = 0.05`), where the unfiltered part alone nears its Nyquist bound (2) and the sole-edge
/// saturation tips it into a limit cycle (`ankle_admittance.rs`).
#[test]
fn ankle_stability_region() {
    let beta = AnkleAdmittanceSettings::default().lead_fraction;
    for k in [1e3, 1e4, 1e5, 1e6, 2e6, 4e6, 1e7] {
        let mut line = format!("k = {k:.0e} N·m/rad:");
        for gain in [0.001, 0.003, 0.01, 0.03] {
            let r = ankle_sweep_run(
                AnkleAdmittanceSettings {
                    gain,
                    ..Default::default()
                },
                Floor { pitch: k, roll: k },
            );
            let settles = r.quiet() && r.cop_err < 1e-4;
            line += &format!(
                "  A {gain}: {} (hf CoP {:.1e} m, err {:.2} mm)",
                if settles { "settles" } else { "FAILS" },
                r.hf_cop,
                r.cop_err * 1e3
            );
            let akdt = gain * k * DT;
            if akdt <= 10.0 {
                assert!(settles, "A {gain}, k {k:e}: A k dt = {akdt} must settle");
            } else if beta * akdt >= 1.0 {
                assert!(!settles, "A {gain}, k {k:e}: A k dt = {akdt} settled");
            }
        }
        println!("{line}");
    }
}

#[test]
fn a_stabilizer_tick_does_not_allocate() {
    let mut st = Stabilizer::new(StabilizerSettings {
        ankle: AnkleAdmittanceSettings {
            gain: 0.01,
            ..Default::default()
        },
        ..talos_settings()
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
        ..talos_settings()
    })
    .is_err());
    let mut st = Stabilizer::new(talos_settings()).unwrap();
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
        ..talos_settings()
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
    let damped = sway_run(talos_settings().sway_damping, 10.0);
    println!(
        "flexible LIPM, 3 mm start: max |c| over the last second, g_d = 0 after 4 s: {:.2} mm; g_d = 0.1 s after 10 s: {:.4} mm",
        undamped * 1e3,
        damped * 1e3
    );
    assert!(undamped > 0.003 * 2f64.sqrt(), "{undamped}");
    assert!(damped < 1e-4, "{damped}");
}

/// TALOS' stabilizer settings: 90.2722 kg and the 0.20 × 0.12 m sole of seed 002 §2, ankle
/// 0.107 m above it (talos_data's `leg_*_sole_fix_joint`).
fn talos_settings() -> StabilizerSettings {
    StabilizerSettings::new(90.2722, Sole::new(0.10, 0.06, 0.107))
}
