//! The passive controller's scenarios (issue "Passive whole-body controller with a global
//! energy tank", Deliver 2, 3 and 4), run from `scenarios/passive/` as `corps run` runs them with
//! every tick logged: at every tick where the controller's QP answered, the power row holds,
//! `Ḣ ≤ −q̇_jᵀτ + 1e-6 W` (log columns `h_dot_W`, `passivity_bound_W`), and the tank stays
//! within `0 ≤ E_tank ≤ E_max + 1e-6 J` (`tank_energy_J`); and the controller never gives the
//! robot more energy than its storage lost.

use corps::run::{run_file, Metrics, RunOptions};
use corps_loop::verdict::Verdict;
use corps_scenario::controller::{HAND_CHANNELS, TANK_CHANNELS};
use std::collections::HashMap;
use std::path::PathBuf;

/// E_max of config/talos/passive_torque*.toml (seed 000 L6396).
const E_MAX: f64 = 5.0;

struct Logged {
    metrics: Metrics,
    rows: Vec<HashMap<String, f64>>,
}

/// The log columns the checks read besides the controller's own (the others are not kept).
const KEPT: [&str; 3] = ["t", "base_z", "joint_power_W"];

/// Whether the checks keep column `name`: [`KEPT`], the energy tank's and the hand's.
fn kept(name: &str) -> bool {
    KEPT.iter()
        .chain(&TANK_CHANNELS)
        .chain(&HAND_CHANNELS)
        .any(|c| *c == name)
}

/// Runs `scenarios/passive/{name}.toml` with every tick logged.
fn run(name: &str) -> Logged {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios/passive")
        .join(format!("{name}.toml"));
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(
        text.contains("log_every = 10"),
        "the scenario logs every 10th tick"
    );
    let dir = tempfile::tempdir().unwrap();
    let every_tick = dir.path().join(format!("{name}.toml"));
    std::fs::write(&every_tick, text.replace("log_every = 10", "log_every = 1")).unwrap();
    let out = dir.path().join("out");
    let metrics = run_file(&every_tick, Some(&out), None, RunOptions::quiet())
        .unwrap()
        .metrics;
    println!("{metrics}");
    let log = std::fs::read_to_string(out.join("log.csv")).unwrap();
    let mut lines = log.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| {
            header
                .iter()
                .zip(l.split(','))
                .filter(|(h, _)| kept(h))
                .map(|(h, x)| (h.clone(), x.parse::<f64>().unwrap_or(f64::NAN)))
                .collect()
        })
        .collect();
    Logged { metrics, rows }
}

/// The power row and the tank's bounds at every tick the QP answered; returns how many ticks
/// fell back (`h_dot_W` is NaN there). The energy the controller gave the robot (Σ τᵀΔq_j
/// over the steps, `port_energy_J`) never exceeds what its storage `H = βγ S + E_tank` lost
/// plus what the empty tank could not pay of its bookings (`unpaid_J`, printed), fallbacks
/// included (the tank books a safe command's step too).
fn assert_passive(l: &Logged) -> usize {
    let mut fallbacks = 0;
    // A tick that fell back (h_dot_W NaN) holds no task spring.
    let storage = |r: &HashMap<String, f64>| match r["h_dot_W"].is_nan() {
        true => r["tank_energy_J"],
        false => {
            r["beta"] * r["gamma"] * r["task_energy_J"] + r["tank_energy_J"] - r["spring_payment_J"]
        }
    };
    let h0 = storage(&l.rows[0]);
    let (mut given, mut unpaid, mut unpaid_before_fallback) = (0.0, 0.0, None);
    for r in &l.rows {
        given -= r["port_energy_J"];
        unpaid += r["unpaid_J"];
        if r["h_dot_W"].is_nan() && unpaid_before_fallback.is_none() {
            unpaid_before_fallback = Some(unpaid);
        }
        let lost = h0 - storage(r);
        assert!(
            given <= lost + unpaid + 1e-6,
            "t = {:.3} s: gave {given} J, the storage lost {lost} J, {unpaid} J unpaid",
            r["t"]
        );
        let (t, h_dot, bound, e) = (
            r["t"],
            r["h_dot_W"],
            r["passivity_bound_W"],
            r["tank_energy_J"],
        );
        assert!(
            (0.0..=E_MAX + 1e-6).contains(&e),
            "t = {t:.3} s: tank {e} J outside [0, {E_MAX}]"
        );
        if h_dot.is_nan() {
            fallbacks += 1;
            continue;
        }
        assert!(
            h_dot <= bound + 1e-6,
            "t = {t:.3} s: Ḣ = {h_dot} W above −q̇ᵀτ = {bound} W"
        );
    }
    println!(
        "the robot received {:.3} J beyond the storage's loss before the first fallback \
         ({unpaid:.3} J in all): sampled power the empty tank could not pay",
        unpaid_before_fallback.unwrap_or(unpaid)
    );
    fallbacks
}

#[test]
fn the_passive_stand_keeps_the_power_bound_at_every_tick() {
    let l = run("stand");
    assert_completed(&l);
    assert_eq!(assert_passive(&l), 0, "no tick fell back");
    assert!(
        l.metrics.base_drift < 1e-3,
        "base drift {} m",
        l.metrics.base_drift
    );
}

/// Seed 000 §4.5's 1 m walk: the thesis's robot completes it, β falling to 0 around 10 s and
/// γ staying above 0.5 afterwards. corps' does not complete it (a shortfall in RESULTS.md with
/// its measured cause: the tank empties by the first step). Passivity holds at every tick
/// the QP answered. When the walk completes, this test fails: assert the thesis's events
/// instead.
#[test]
fn the_passive_1m_walk_keeps_the_power_bound_and_falls_short_of_the_thesis() {
    let l = run("walk_1m");
    let fallbacks = assert_passive(&l);
    let beta_closed = l.rows.iter().find(|r| r["beta"] < 0.5).map(|r| r["t"]);
    let gamma_low = l.rows.iter().find(|r| r["gamma"] < 0.5).map(|r| r["t"]);
    println!(
        "β < 0.5 first at {beta_closed:?} s after the handover (thesis: β → 0 around 10 s); \
         γ < 0.5 first at {gamma_low:?} s (thesis: γ > 0.5 after β's fall); \
         {fallbacks} ticks fell back; verdict {}",
        l.metrics.verdict
    );
    assert_ne!(
        l.metrics.verdict.verdict,
        Verdict::Completed,
        "the walk now completes: move it to the thesis's checks"
    );
}

/// The run ended `completed`.
fn assert_completed(l: &Logged) {
    assert_eq!(
        l.metrics.verdict.verdict,
        Verdict::Completed,
        "{}",
        l.metrics.verdict
    );
}

/// The tank's row at `t` (the first logged at or after it).
fn at(l: &Logged, t: f64) -> &HashMap<String, f64> {
    l.rows
        .iter()
        .find(|r| r["t"] >= t - 1e-9)
        .unwrap_or_else(|| panic!("no row at {t} s"))
}

/// Seed 000 §5.4.1 (Figs 5.4–5.6): the tool in the left hand tracks 10 N then 30 N on the
/// block; when the block is pulled away at 32.3 s, γ closes at once (the force task and every
/// reference are held back), the hand comes down slowly, the emergency action removes the
/// contact and the task, and the robot does not fall; passivity holds at every tick. The
/// event times are printed beside the thesis's (consumption peak 34.4 s, filling 20–30 s).
#[test]
fn the_passive_force_scenario_survives_the_block_removal() {
    let l = run("force_contact");
    assert_completed(&l);
    assert_eq!(assert_passive(&l), 0, "no tick fell back");
    // The force task tracks its plateaus (the schedule reaches 10 N at 5 s, 30 N at 20 s).
    for (t, f) in [(14.0, 10.0), (31.0, 30.0)] {
        let r = at(&l, t);
        let (reference, measured) = (r["hand_force_ref_N"], r["hand_force_N"]);
        assert!(reference == f, "reference {reference} N at {t} s");
        assert!(
            (measured - f).abs() < 0.05 * f,
            "t = {t} s: measured {measured} N against {f} N"
        );
    }
    const REMOVAL: f64 = 32.3;
    let after = |pred: &dyn Fn(&HashMap<String, f64>) -> bool| {
        l.rows
            .iter()
            .find(|r| r["t"] >= REMOVAL && pred(r))
            .map(|r| r["t"])
    };
    let gamma_closed = after(&|r| r["gamma"] < 0.5).expect("γ closes");
    let released = after(&|r| r["hand_contact"] == 0.0).expect("the contact is removed");
    let drop_at = |t: f64| at(&l, t)["tool_drop_m"];
    let lost = after(&|r| r["tool_drop_m"] > 0.02).expect("the tip drops 2 cm");
    let holding = l
        .rows
        .iter()
        .filter(|r| r["t"] >= REMOVAL && r["t"] < released);
    let (lowest, highest) = holding.fold((f64::NEG_INFINITY, f64::INFINITY), |(lo, hi), r| {
        (lo.max(r["tool_drop_m"]), hi.min(r["tool_drop_m"]))
    });
    // Consumption peak: the steepest fall of E_tank after the removal.
    let mut peak = (0.0, f64::INFINITY);
    for w in l.rows.windows(2).filter(|w| w[0]["t"] >= REMOVAL) {
        let rate = (w[1]["tank_energy_J"] - w[0]["tank_energy_J"]) / (w[1]["t"] - w[0]["t"]);
        if rate < peak.1 {
            peak = (w[0]["t"], rate);
        }
    }
    let filling = at(&l, 30.0)["tank_energy_J"] - at(&l, 20.0)["tank_energy_J"];
    println!(
        "block removed at {REMOVAL} s: γ < 0.5 at {gamma_closed:.3} s; the tool tip {:.1} mm \
         below its contact 0.1 s later, 2 cm below at {lost:.3} s; while the contact is held \
         the tip goes down to {:.1} mm below and up to {:.1} mm above it; contact and task \
         removed at {released:.3} s (thesis 34.4 s); steepest tank consumption {:.1} W at \
         {:.3} s (thesis: peak at 34.4 s); tank change over 20–30 s {filling:+.3} J (thesis: \
         a steady rise); lowest base {:.3} m",
        drop_at(REMOVAL + 0.1) * 1e3,
        lowest * 1e3,
        -highest * 1e3,
        peak.1,
        peak.0,
        l.rows
            .iter()
            .map(|r| r["base_z"])
            .fold(f64::INFINITY, f64::min),
    );
    assert!(
        gamma_closed < REMOVAL + 0.1,
        "γ closes within 0.1 s of the block's removal"
    );
}

/// The same without the tank (plain TSID, same tasks and emergency action): the thesis's
/// robot "quickly falls and cannot react in time" (L6440–L6445); corps' falls too, before its
/// emergency action fires.
#[test]
fn the_force_scenario_without_the_tank_falls() {
    let l = run("force_contact_no_tank");
    assert_eq!(
        l.metrics.verdict.verdict,
        Verdict::Fell,
        "{}",
        l.metrics.verdict
    );
    let fell = l.metrics.verdict.t.expect("a time");
    let released = l
        .rows
        .iter()
        .find(|r| r["hand_contact"] == 0.0)
        .map(|r| r["t"]);
    println!("fell at {fell:.3} s; hand contact removed at {released:?} s");
    assert!(
        released.is_none_or(|t| t > fell),
        "it falls before its emergency action"
    );
}
