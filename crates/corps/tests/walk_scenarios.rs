//! The walking scenarios (issue "Walking on TALOS", Deliver 4): each runs its scenario file
//! from `scenarios/walk/` as `corps run` does. Pass (issue): no fall — the base stays above
//! 0.6 m and nothing but the feet touches the ground — and the final base within 5 cm of the
//! plan. Where the thesis gives a figure, the metrics must match or beat it.

use corps::run::{run_file, Metrics, RunOptions};
use corps_loop::verdict::Verdict;
use std::path::PathBuf;

/// Runs `scenarios/walk/{name}.toml` with `options` and prints its metrics.
fn run_walk(name: &str, options: RunOptions) -> Metrics {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios/walk")
        .join(format!("{name}.toml"));
    let out = tempfile::tempdir().unwrap();
    let m = run_file(&path, Some(out.path()), None, options)
        .unwrap()
        .metrics;
    println!("{m}");
    m
}

fn walk(name: &str) -> Metrics {
    let m = run_walk(name, RunOptions::quiet());
    assert_eq!(m.verdict.verdict, Verdict::Completed, "{}", m.verdict);
    assert!(
        m.min_base_height > 0.6,
        "fell: base at {:.3} m",
        m.min_base_height
    );
    assert_eq!(
        m.other_contact_peak, 0.0,
        "a body other than the feet touched"
    );
    let w = m.walk.as_ref().expect("a walk");
    assert!(
        w.final_base_error < 0.05,
        "final base {:.1} mm from the plan",
        w.final_base_error * 1e3
    );
    assert_eq!(m.fallbacks, 0, "{:?}", m.first_fallback);
    m
}

/// The walk covered more than `at_least` m of its planned `planned` m.
fn assert_travelled(m: &Metrics, at_least: f64, planned: f64) {
    let d = m.walk.as_ref().expect("a walk").distance;
    assert!(d > at_least, "travelled {d:.3} m of {planned}");
}

/// Every figure of the thesis's tables that the scenario carries (seed 000 Tables 4.4–4.9:
/// CoM, ZMP and feet error averages and peaks, costs of transport) is compared with corps'
/// run, the controller seeing the sensors through the estimator. The figures where corps is
/// worse must be exactly `known`: RESULTS.md lists them with their measured causes. A new
/// shortfall fails, and so does a listed one that corps no longer has (strike it from the list
/// and from RESULTS.md). Both numbers are printed for every figure.
fn assert_shortfalls(m: &Metrics, known: &[&str]) {
    let rows = &m.against_thesis;
    assert!(!rows.is_empty(), "no thesis figures in the scenario");
    for c in rows {
        println!(
            "{:<28} corps {:>9.4}  thesis {:>9.4}{}",
            c.figure,
            c.corps,
            c.thesis,
            if c.worse { "  (worse)" } else { "" }
        );
    }
    let worse: Vec<&str> = rows
        .iter()
        .filter(|c| c.worse)
        .map(|c| c.figure.as_str())
        .collect();
    if let Some(c) = rows
        .iter()
        .find(|c| c.worse && !known.contains(&c.figure.as_str()))
    {
        panic!(
            "{}: corps {:.4} is worse than the thesis's {:.4}, and not a known shortfall",
            c.figure, c.corps, c.thesis
        );
    }
    for k in known {
        let c = rows.iter().find(|c| c.figure == *k);
        assert!(
            worse.contains(k),
            "{k} is no longer short of the thesis ({c:?}): strike it from the known shortfalls"
        );
    }
}

#[test]
fn tsid_torque_walks_six_20_cm_steps() {
    let m = walk("tsid_torque_20cm");
    assert_shortfalls(&m, &[]);
    // CoM and feet tracking error below 1 cm (seed 000 L4691).
    for s in m
        .com_error
        .iter()
        .chain(m.feet.iter().flat_map(|f| f.error.iter()))
    {
        assert!(s.peak < 1e-2, "tracking error peak {:.1} mm", s.peak * 1e3);
    }
}

#[test]
fn tsid_torque_walks_with_the_fast_timing() {
    walk("tsid_torque_20cm_fast");
}

#[test]
fn tsid_torque_climbs_six_stairs() {
    let m = walk("tsid_torque_stairs");
    assert_travelled(&m, 1.7, 1.8);
    assert_shortfalls(
        &m,
        &[
            "ZMP x average",
            "ZMP x peak",
            "ZMP x average while walking",
            "ZMP x peak while walking",
        ],
    );
}

#[test]
fn ik_position_climbs_six_stairs() {
    // Table 4.3's stairs gains for the IK, the dynamic filter, and the CoM height spread over
    // each step period (`FootstepPlan::com_ground`; with the height changed within the double
    // support alone the IK's QP turned infeasible at 3.7 s and TALOS fell).
    let m = walk("ik_position_stairs");
    assert_travelled(&m, 1.7, 1.8);
    assert_shortfalls(
        &m,
        &[
            "ZMP y average",
            "ZMP x average while walking",
            "ZMP y average while walking",
        ],
    );
    assert_dynamic_filter_helped(&m);
}

#[test]
fn tsid_torque_walks_over_the_tilted_platforms() {
    // Seed 000 §4.2 (Table 4.6): 6 steps of 25 cm plus a closing step, three of them on the
    // two platforms rolled ±10°, two of them with both feet on opposite platforms.
    let m = walk("tsid_torque_platforms");
    assert_travelled(&m, 1.45, 1.5);
    assert_shortfalls(&m, &["ZMP y peak", "ZMP y peak while walking"]);
}

#[test]
fn ik_position_walks_over_the_tilted_platforms() {
    let m = walk("ik_position_platforms");
    assert_travelled(&m, 1.45, 1.5);
    assert_shortfalls(&m, &["ZMP y peak", "ZMP y peak while walking"]);
    assert_dynamic_filter_helped(&m);
}

#[test]
// Walks since the integrated model's contacts dropped their friction pyramids
// (`contacts.bilateral`, crates/corps/src/run/controller/tsid.rs "Position mode's contacts").
fn tsid_position_walks_over_the_tilted_platforms() {
    let m = walk("tsid_position_platforms");
    assert_dynamic_filter_helped(&m);
    assert_shortfalls(
        &m,
        &[
            "ZMP x average",
            "ZMP x peak",
            "ZMP y peak",
            "ZMP x average while walking",
            "ZMP x peak while walking",
            "ZMP y average while walking",
            "ZMP y peak while walking",
        ],
    );
}

#[test]
fn tsid_torque_walks_six_60_cm_steps() {
    let m = walk("tsid_torque_60cm");
    assert_shortfalls(&m, &[]);
    // CoM and feet tracking error peaks at most the thesis's (seed 000 Table 4.5).
    let t = m.thesis.as_ref().unwrap();
    let pairs = [
        (&m.com_error[0], t.com_x),
        (&m.com_error[1], t.com_y),
        (&m.feet[0].error[0], t.left_foot_x),
        (&m.feet[0].error[1], t.left_foot_y),
        (&m.feet[1].error[0], t.right_foot_x),
        (&m.feet[1].error[1], t.right_foot_y),
    ];
    for (ours, thesis) in pairs {
        let [_, _, peak] = thesis.unwrap();
        assert!(
            ours.peak <= peak,
            "{:.1} mm > thesis {:.1} mm",
            ours.peak * 1e3,
            peak * 1e3
        );
    }
}

#[test]
fn tsid_torque_walks_by_velocity_commands_forward_sideways_backward() {
    walk("tsid_torque_velocity");
}

#[test]
fn tsid_torque_walks_while_turning() {
    walk("tsid_torque_turning");
}

/// The dynamic filter's pass brought the plan's multibody ZMP (kinematic IK replay) closer to
/// the plan's ZMP on both axes, RMS and peak (seed 002 §4.5).
fn assert_dynamic_filter_helped(m: &Metrics) {
    let d = m.walk.as_ref().and_then(|w| w.dynamic_filter.as_ref());
    let d = d.expect("the scenario runs the dynamic filter");
    for k in 0..2 {
        let ((rms0, peak0), (rms1, peak1)) = (d.before[k], d.after[k]);
        assert!(
            rms1 < rms0 && peak1 < peak0,
            "axis {k}: RMS {rms0:.4} -> {rms1:.4} m, peak {peak0:.4} -> {peak1:.4} m"
        );
    }
}

#[test]
fn ik_position_walks_six_20_cm_steps() {
    let m = walk("ik_position_20cm");
    assert_shortfalls(&m, &[]);
    assert_dynamic_filter_helped(&m);
}

#[test]
fn ik_position_walks_with_the_fast_timing() {
    assert_dynamic_filter_helped(&walk("ik_position_20cm_fast"));
}

#[test]
// Walks since the integrated model's contacts dropped their friction pyramids
// (`contacts.bilateral`, crates/corps/src/run/controller/tsid.rs "Position mode's contacts"):
// before, the stabilizer's CoM acceleration pushed the model's ZMP off its sole and the QP
// rolled the pelvis instead (simulation diverged at 6.1 s; 7.6 s with the dynamic filter).
fn tsid_position_walks_six_20_cm_steps() {
    let m = walk("tsid_position_20cm");
    assert_dynamic_filter_helped(&m);
    assert_shortfalls(&m, &["ZMP y average while walking"]);
}

#[test]
// Walks since the walks run on the stiff contact (implicit Euler): on the default compliant
// contact (0.4 mm sinking under the robot's weight) its pelvis roll and pitch grew over the
// steps and it fell at 7.79 s after the handover.
fn tsid_position_walks_with_the_fast_timing() {
    assert_dynamic_filter_helped(&walk("tsid_position_20cm_fast"));
}

#[test]
fn tsid_torque_steps_on_the_stick() {
    walk("tsid_torque_stick");
}

#[test]
fn ik_position_steps_on_the_stick() {
    walk("ik_position_stick");
}

#[test]
fn ik_position_steps_on_the_stick_with_the_ankle_admittance() {
    // Seed 002's working ankle gain 0.001. Its target (S11): better ZMP tracking than the
    // CoM strategy alone, so the average ZMP error must not exceed the run without it.
    let with = walk("ik_position_stick_ankle");
    let without = walk("ik_position_stick");
    for k in 0..2 {
        assert!(
            with.zmp_error[k].avg <= without.zmp_error[k].avg,
            "ZMP {} error avg {:.2} mm with the ankle admittance, {:.2} mm without",
            ["x", "y"][k],
            with.zmp_error[k].avg * 1e3,
            without.zmp_error[k].avg * 1e3
        );
    }
}

/// Seed 002's failing gain (S11). It fell while the wrapper dropped a released foot's ankle
/// offset in one tick (see `run::controller::stabilized`); the offset now leaks out.
#[test]
fn ik_position_steps_on_the_stick_with_the_ankle_gain_that_failed_in_seed_002() {
    walk("ik_position_stick_ankle_0_01");
}

/// The IK's 20 cm walk on PID joint servos with the gains of PAL Robotics' TALOS simulation
/// (config/talos/gazebo_pid.toml), as the thesis's Gazebo ran position control. Seed 000
/// Table 4.8 has position control spend about four times the torque controller's energy
/// (C_et IK 1.68, TSID torque 0.44); corps' figures stay near the torque controller's, which is
/// not a shortfall against the thesis's bound (lower is better) but is no reproduction of its
/// result either: RESULTS.md gives both and the measured cause.
#[test]
fn ik_position_walks_on_gazebo_pid_servos() {
    let m = walk("ik_position_20cm_gazebo_pid");
    assert_shortfalls(&m, &["ZMP x peak"]);
    let w = m.walk.as_ref().unwrap();
    println!(
        "C_et {:.2} (thesis 1.68), C_mt {:.2} (thesis 1.15)",
        w.cost_of_transport, w.mechanical_cost_of_transport
    );
}

/// TSID in position mode on the same PID servos falls with the estimator (a shortfall listed
/// in RESULTS.md; the thesis walked it in Gazebo) and walks on the simulator's exact state.
/// When it no longer falls, this test fails: move it to `walk` with its shortfalls.
#[test]
fn tsid_position_on_gazebo_pid_servos_falls_with_the_estimator_only() {
    let name = "tsid_position_20cm_gazebo_pid";
    let m = run_walk(name, RunOptions::quiet());
    assert_eq!(m.verdict.verdict, Verdict::Fell, "{}", m.verdict);
    let truth = RunOptions {
        estimator: Some(corps::run::EstimatorKind::GroundTruth),
        ..RunOptions::quiet()
    };
    let m = run_walk(name, truth);
    assert_eq!(m.verdict.verdict, Verdict::Completed, "{}", m.verdict);
}
