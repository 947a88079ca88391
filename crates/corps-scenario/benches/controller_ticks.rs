//! The controller's tick in closed loop against an anchor in the same run: TSID's torque
//! controller on TALOS walking 20 cm steps (`scenarios/walk/tsid_torque_20cm.toml`). Two
//! controllers are measured against it: seed 001's soft-tasks controller #2 on iCub stepping
//! in place (`scenarios/icub/fsm2_stepping.toml`, 23 torque-controlled joints + 9 held; issue
//! 18, goal ≤ 0.7) and the two-layer velocity HQP of teleoperation on iCub replaying a clip
//! of a person (`scenarios/teleop/icub_bye.toml`, 29 joints; issue 24, goal ≤ 0.5). Each
//! round runs the three in memory, alternating, and reads the median of the wall-clock time
//! around each controller tick (the run's own timer: state update, references, QP assembly
//! and solve); the ratios to TALOS's are the figures.
//!
//! `cargo bench -p corps-scenario --bench controller_ticks` (`cargo test --benches` runs a
//! short smoke).

use corps_scenario::run::{RunOptions, ScenarioRun};
use corps_scenario::scenario::Scenario;
use std::path::{Path, PathBuf};

fn scenario(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios")
        .join(rel)
}

/// Median controller tick (µs) of `rel` run for `seconds`.
fn median_tick(rel: &str, seconds: f64) -> f64 {
    let path = scenario(rel);
    let text = std::fs::read_to_string(&path).expect("the scenario");
    let s = Scenario::parse(&text)
        .and_then(|s| s.with_duration(seconds))
        .expect("the scenario parses");
    let dir = path.parent().expect("its directory");
    let run = ScenarioRun::new(&s, "bench", dir, RunOptions::default()).expect("it builds");
    let m = run.run(&mut []).expect("it runs").metrics;
    assert_eq!(m.fallbacks, 0, "{:?}", m.first_fallback);
    m.tick_time.median_us
}

/// Median time (µs) of one retargeting of a pose (`Retargeter::joints_into` and the waist
/// height) over the teleoperation scenario's clip: the part of the teleop tick that is not
/// the HQP.
fn median_retarget() -> f64 {
    let path = scenario("teleop/icub_bye.toml");
    let text = std::fs::read_to_string(&path).expect("the scenario");
    let s = Scenario::parse(&text).expect("the scenario parses");
    let mocap = s.mocap.expect("a [mocap] section");
    let op = mocap
        .open(path.parent().expect("its directory"))
        .expect("the clip");
    let robot = op.mapping.robot().expect("the robot");
    let units = op.mapping.units();
    let skeleton = corps_mocap::skeleton::Skeleton::new(&op.clip, units);
    let rest = op
        .mapping
        .rest_pose(&skeleton, &op.clip)
        .expect("the rest pose");
    let mut r = corps_mocap::retarget::Retargeter::new(&op.mapping, &robot, &skeleton, &rest)
        .expect("the retargeting");
    let poses: Vec<_> = (0..op.clip.frames())
        .map(|k| skeleton.pose(op.clip.frame(k), 0.0))
        .collect();
    let n = r.joints.len();
    let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
    let mut times: Vec<f64> = poses
        .iter()
        .map(|p| {
            let t0 = std::time::Instant::now();
            r.joints_into(p, &mut a, &mut b);
            std::hint::black_box(r.waist_height(p));
            t0.elapsed().as_secs_f64() * 1e6
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

fn main() {
    let bench = std::env::args().any(|a| a == "--bench");
    let (rounds, icub_s, teleop_s, talos_s) = if bench {
        (5, 60.0, 5.0, 11.0)
    } else {
        (1, 2.0, 1.0, 1.0)
    };
    let mut ratios = [Vec::new(), Vec::new()];
    println!("round  iCub soft-tasks #2  iCub teleop HQP  TALOS TSID torque  ratios (medians, µs)");
    for round in 1..=rounds {
        let icub = median_tick("icub/fsm2_stepping.toml", icub_s);
        let teleop = median_tick("teleop/icub_bye.toml", teleop_s);
        let talos = median_tick("walk/tsid_torque_20cm.toml", talos_s);
        ratios[0].push(icub / talos);
        ratios[1].push(teleop / talos);
        println!(
            "{round:>5}  {icub:>18.1}  {teleop:>15.1}  {talos:>17.1}  {:.2} {:.2}",
            icub / talos,
            teleop / talos
        );
    }
    for r in &mut ratios {
        r.sort_by(f64::total_cmp);
    }
    println!(
        "median ratio iCub soft-tasks / TALOS: {:.2} (goal ≤ 0.7)",
        ratios[0][ratios[0].len() / 2]
    );
    println!(
        "median ratio iCub teleop HQP / TALOS: {:.2} (goal ≤ 0.5)",
        ratios[1][ratios[1].len() / 2]
    );
    println!(
        "of the teleop tick, the retargeting of one pose: median {:.1} µs",
        median_retarget()
    );
}
