//! The passive inverse dynamics (seed 000 ch. 5) in closed loop with the corps simulator:
//! TALOS standing under Table 5.1–5.2 gains, taking a CoM reference step, with the energy
//! tank. At every tick the QP's power row holds, `Ḣ ≤ −q̇_jᵀτ` (Eq 5.3, 5.34), and the tank
//! stays within [0, E_max].

mod common;
use common::*;
use corps_control::formulation::{InverseDynamics, PassiveInverseDynamics, PassiveSignals};
use corps_control::passivity::{EnergyTank, TankParams};
use corps_control::tasks::ComTask;
use corps_control::RobotState;
use corps_sim::{Command, Simulator};
use nalgebra::DVector;

const DT: f64 = 1e-3;

struct Run {
    signals: Vec<PassiveSignals>,
    fallbacks: usize,
    first_fallback: Option<String>,
    min_base_z: f64,
    com_error_end: f64,
}

/// Stands `seconds` under the passive controller from a settled TALOS, the CoM reference
/// moved by `com_step` (m, world) at 0.5 s; the CoM task's Kp × `gain_factor`, Kd ×
/// √`gain_factor` (the same damping ratio).
fn run(seconds: f64, com_step: [f64; 3], gain_factor: f64, tank0: f64) -> Run {
    let (mut sim, q0): (Simulator, _) = settled_talos(implicit_settings());
    let model = sim.model().clone();
    let mut state = RobotState::new(&model);
    state
        .update(&model, sim.q().as_slice(), sim.v().as_slice())
        .unwrap();
    let mut id: InverseDynamics = standing_controller(&model, &state, &q0);
    let com0 = state.data.com;
    {
        let com = id.tasks.task_mut::<ComTask>("com").unwrap();
        com.kp *= gain_factor;
        com.kd *= gain_factor.sqrt();
    }
    let tank = EnergyTank::new(TankParams::default(), tank0).unwrap();
    let mut passive = PassiveInverseDynamics::new(&model, tank, DT).unwrap();
    let mut tau = DVector::zeros(model.nv - 6);
    let mut out = Run {
        signals: Vec::new(),
        fallbacks: 0,
        first_fallback: None,
        min_base_z: f64::INFINITY,
        com_error_end: 0.0,
    };
    let ticks = (seconds / DT).round() as usize;
    for k in 0..ticks {
        let t = k as f64 * DT;
        if (t - 0.5).abs() < DT / 2.0 {
            let com = id.tasks.task_mut::<ComTask>("com").unwrap();
            for i in 0..3 {
                com.reference.pos[i] = com0[i] + com_step[i];
            }
        }
        let (q, v) = (sim.q().clone_owned(), sim.v().clone_owned());
        let r = passive.tick(
            &mut id,
            &model,
            &mut state,
            t,
            q.as_slice(),
            v.as_slice(),
            5.0,
            &mut tau,
        );
        if let Some(reason) = &r {
            out.first_fallback
                .get_or_insert_with(|| format!("t = {t:.3} s: {reason}"));
        }
        out.fallbacks += usize::from(r.is_some());
        out.signals.push(passive.signals);
        sim.step(&Command::Torque(tau.clone())).unwrap();
        out.min_base_z = out.min_base_z.min(sim.q()[2]);
    }
    let com = id.tasks.task::<ComTask>("com").unwrap();
    out.com_error_end = (state.data.com
        - nalgebra::Vector3::from_column_slice(com.reference.pos.as_slice()))
    .norm();
    out
}

fn check_passive(r: &Run, e_max: f64) {
    assert_eq!(r.fallbacks, 0, "no tick fell back: {:?}", r.first_fallback);
    for (k, s) in r.signals.iter().enumerate() {
        assert!(
            s.h_dot <= s.passivity_bound + 1e-6,
            "tick {k}: Ḣ = {} W > −q̇ᵀτ = {} W",
            s.h_dot,
            s.passivity_bound
        );
        assert!(
            s.tank_energy >= 0.0 && s.tank_energy <= e_max + 1e-3,
            "tick {k}: tank {} J",
            s.tank_energy
        );
    }
}

/// The largest excess over the run of the energy the controller gave the robot, Σ τᵀΔq_j
/// over the steps (the torques are held over each), over what its storage
/// `H = βγ S + E_tank` lost since the start, less what the empty tank could not pay of its
/// bookings (J): ≤ 0 when every gap is the sampled power's, which the tank books.
fn injected_beyond_storage(r: &Run) -> f64 {
    // H after the tick's payment u to the spring: βγ S + (E_tank − u).
    let storage =
        |s: &PassiveSignals| s.valves.scale() * s.task.storage + s.tank_energy - s.spring_payment;
    let h0 = storage(&r.signals[0]);
    let (mut injected, mut unpaid) = (0.0, 0.0);
    let mut worst = f64::NEG_INFINITY;
    for s in &r.signals {
        // The energy the robot received over the last step (−τᵀΔq_j, booked at this tick),
        // against the storage after this tick's booking.
        injected -= s.port_energy;
        unpaid += s.unpaid;
        worst = worst.max(injected - (h0 - storage(s)) - unpaid);
    }
    worst
}

fn summary(r: &Run) {
    let last = r.signals.last().expect("ticks");
    let lowest = r
        .signals
        .iter()
        .map(|s| s.tank_energy)
        .fold(f64::INFINITY, f64::min);
    let bound_active = (r.signals.iter())
        .filter(|s| (s.h_dot - s.passivity_bound).abs() < 1e-6)
        .count();
    let unpaid: f64 = r.signals.iter().map(|s| s.unpaid).sum();
    println!(
        "tank {:.3} J at the end, lowest {:.3} J; power row binding on {} of {} ticks; \
         lowest base {:.4} m; CoM error at the end {:.4} m; the robot received {unpaid:.3} J \
         beyond the storage's loss (sampled power the empty tank could not pay)",
        last.tank_energy,
        lowest,
        bound_active,
        r.signals.len(),
        r.min_base_z,
        r.com_error_end
    );
}

/// A 5 cm lateral CoM step from a 3 J tank: every tick keeps the power bound and the tank
/// within [0, E_max]; the controller gives the robot no more than its storage `βγ S + E_tank`
/// lost plus what the empty tank could not pay of the sampled power (printed: 1.29 J);
/// without the tank's payment for the spring energy the step creates it gave 5.96 J more.
/// The robot stands and the CoM reaches its reference.
#[test]
fn a_com_step_under_the_tank_keeps_the_power_bound_at_every_tick() {
    let r = run(3.0, [0.0, 0.05, 0.0], 1.0, 3.0);
    summary(&r);
    check_passive(&r, 5.0);
    let excess = injected_beyond_storage(&r);
    assert!(
        excess <= 1e-6,
        "the controller gave {excess} J more than its storage lost and its unpaid bookings"
    );
    assert!(
        r.min_base_z > 0.9,
        "the robot stands: base {:.3} m",
        r.min_base_z
    );
    assert!(
        r.com_error_end < 5e-3,
        "CoM error {:.4} m at the end",
        r.com_error_end
    );
}

/// The CoM task's gains ×10 over Table 5.2 (Kp 500, Kd 5√10) under a 2 cm step: every tick
/// keeps the power bound and the tank within [0, E_max] (it empties: the stiffer spring holds
/// more than 3 J); the same energy account holds (unpaid sampled power printed: 7.89 J;
/// 9.60 J more without the spring payment).
#[test]
fn ten_times_the_com_gains_keep_the_power_bound() {
    let r = run(3.0, [0.0, 0.02, 0.0], 10.0, 3.0);
    summary(&r);
    check_passive(&r, 5.0);
    let excess = injected_beyond_storage(&r);
    assert!(
        excess <= 1e-6,
        "the controller gave {excess} J more than its storage lost and its unpaid bookings"
    );
    assert!(
        r.min_base_z > 0.9,
        "the robot stands: base {:.3} m",
        r.min_base_z
    );
}

/// Without a posture task the stacked Jacobian has not full column rank (Λ is undefined): the
/// tick gives the safe command and a reason that names what is missing.
#[test]
fn a_stack_without_posture_gives_the_safe_command_and_says_why() {
    let (model, q, mut state, mut id) = standing();
    id.tasks.remove("posture").unwrap();
    let tank = EnergyTank::new(TankParams::default(), 3.0).unwrap();
    let mut passive = PassiveInverseDynamics::new(&model, tank, DT).unwrap();
    let mut tau = DVector::zeros(model.nv - 6);
    let v = DVector::zeros(model.nv);
    let r = passive.tick(
        &mut id,
        &model,
        &mut state,
        0.0,
        q.as_slice(),
        v.as_slice(),
        5.0,
        &mut tau,
    );
    let reason = r.expect("a fallback").to_string();
    assert!(reason.contains("posture task"), "{reason}");
    assert!(tau.iter().all(|t| t.is_finite()));
    assert_eq!(
        passive.tank.energy(),
        3.0,
        "the tank holds on a failed tick"
    );
}
