//! Seed 001 S2 (issue 18, Deliver 2–4): iCub stepping in place under the soft-tasks
//! controller #2 and FSM #2 (`scenarios/icub/fsm2_stepping.toml`), the controller reading the
//! sensors through the estimator. The test runs 60 s (4 strides); the thesis's 50 cycles run
//! from `corps run scenarios/icub/fsm2_stepping.toml --duration 720`, whose output RESULTS.md
//! records (52 strides). Every thesis figure the controller reports is printed beside corps';
//! those corps misses must be exactly the known ones, which RESULTS.md lists with their causes.

use corps::run::{run_file, Metrics, RunOptions};
use corps_loop::verdict::Verdict;
use std::path::{Path, PathBuf};

/// Runs the scenario at `path` for `duration` (None: its own) into a temporary directory and
/// prints its metrics.
fn run(path: &Path, duration: Option<f64>) -> Metrics {
    let out = tempfile::tempdir().unwrap();
    let m = run_file(path, Some(out.path()), duration, RunOptions::quiet())
        .unwrap_or_else(|e| panic!("{e:#}"))
        .metrics;
    println!("{m}");
    m
}

fn scenario(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios/icub")
        .join(name)
}

/// The report lines missed in a 60 s run: the cycle count (the test runs 4 of the thesis's
/// 50; the 720 s run of RESULTS.md makes 52).
const KNOWN: [&str; 1] = ["strides (two steps each)"];

#[test]
fn fsm2_steps_in_place_within_the_thesis_bounds() {
    let m = run(&scenario("fsm2_stepping.toml"), Some(60.0));
    assert_eq!(m.verdict.verdict, Verdict::Completed, "{}", m.verdict);
    assert_eq!(m.fallbacks, 0, "{:?}", m.first_fallback);
    let line = |name: &str| {
        (m.controller_report.iter())
            .find(|l| l.figure == name)
            .unwrap_or_else(|| panic!("no report line '{name}'"))
    };
    assert!(line("strides (two steps each)").value >= 4.0);
    // ≈ 14 s per stride (seed 001 L3132–L3136): within 20 %.
    let stride = line("stride duration").value;
    assert!((stride - 14.0).abs() < 0.2 * 14.0, "stride {stride:.2} s");
    for l in &m.controller_report {
        if let (Some(thesis), Some(met)) = (&l.thesis, l.met) {
            println!(
                "{:<58} corps {:>9.4} {:<2} thesis {thesis}{}",
                l.figure,
                l.value,
                l.unit,
                if met { "" } else { "  (missed)" }
            );
            assert_eq!(
                met,
                !KNOWN.contains(&l.figure.as_str()),
                "{}: corps {:.4} {} against the thesis's {thesis}: {}",
                l.figure,
                l.value,
                l.unit,
                if met {
                    "now met, strike it from the known shortfalls"
                } else {
                    "a new shortfall"
                }
            );
        }
    }
    // The true CoM (the simulator's) against the references, estimator drift included.
    for (axis, s) in ["x", "y"].iter().zip(&m.com_error) {
        println!("true CoM error {axis}: peak {:.1} mm", s.peak * 1e3);
        assert!(s.peak < 0.01);
    }
}

/// The backpacked iCub (a 1.8 kg pack on the chest, `robots/icub_description/icub_backpacked.toml`)
/// steps for 60 s under the same gains and state machine (RESULTS.md has its 720 s).
#[test]
fn the_backpacked_icub_steps_for_a_minute() {
    let text = std::fs::read_to_string(scenario("fsm2_stepping.toml")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("backpacked.toml");
    std::fs::write(
        &path,
        text.replace(
            "description = \"icub\"",
            "description = \"icub_backpacked\"",
        ),
    )
    .unwrap();
    let m = run(&path, Some(60.0));
    assert_eq!(m.verdict.verdict, Verdict::Completed, "{}", m.verdict);
    assert_eq!(m.fallbacks, 0, "{:?}", m.first_fallback);
    let strides = (m.controller_report.iter())
        .find(|l| l.figure == "strides (two steps each)")
        .unwrap();
    assert!(strides.value >= 4.0);
}

#[test]
fn a_state_machine_or_a_frame_that_cannot_be_is_refused_before_the_run() {
    let text = std::fs::read_to_string(scenario("fsm2_stepping.toml")).unwrap();
    for (set, expected) in [
        (
            r#"set = { neck = { frame = "no_such_frame", kp = 1.5 } }"#,
            "no_such_frame",
        ),
        (r#"set = { fsm = { t_smooth = -1.0 } }"#, "fsm.t_smooth"),
        (
            r#"set = { contacts = { fz_min = 10.0, fz_max = 5.0, mu = 1.0, mu_torsion = 0.01, vertices_per_quadrant = 4 } }"#,
            "fz_max",
        ),
        (r#"set = { torque_rate = -50.0 }"#, "torque_rate"),
        (
            r#"set = { posture_reference_deg = { r_elbow = 10.0 }, joint_limits = { law = "reparametrised", xi_max = 2.6, limits_deg = { r_elbow = [15.0, 106.0] } } }"#,
            "not inside its limits",
        ),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bad.toml");
        let text = text.replace("settle = 0.5", &format!("settle = 0.5\n{set}"));
        std::fs::write(&path, text).unwrap();
        let err = run_file(
            &path,
            Some(&dir.path().join("out")),
            Some(1.0),
            RunOptions::quiet(),
        )
        .err()
        .expect("refused");
        let msg = format!("{err:#}");
        println!("{msg}");
        assert!(msg.contains(expected), "{msg}");
        assert!(!dir.path().join("out").join("log.csv").exists());
    }
}

/// The smallest distance of the right elbow to its limit over a run of
/// `scenarios/icub/s7_elbow_{law}.toml`, and the verdict.
fn s7(law: &str) -> (f64, Verdict) {
    let m = run(&scenario(&format!("s7_elbow_{law}.toml")), None);
    let margin = (m.controller_report.iter())
        .find(|l| l.figure == "smallest distance to a joint limit (r_elbow)")
        .expect("the elbow's margin")
        .value;
    (margin, m.verdict.verdict)
}

/// Seed 001 S7 (issue 18, Deliver 5): stepping with the right elbow's reference at 22.5°, 7.5°
/// from its 15° limit, the right hand pushed as Table 3.2 says. The thesis: the classical PD
/// lets a push take the elbow past its limit, the re-parametrised law (Eq 3.27) never does, and
/// the robot recovers from every push. corps' robot falls after the first push (15 N forward
/// for 1 s at 5 s, on one foot) under both laws, the elbow passing its limit as it falls: a
/// shortfall in RESULTS.md with its measured cause. Both margins are printed; when the runs
/// complete, this test fails: then assert the thesis's claims.
#[test]
fn s7_falls_after_the_first_push_under_both_laws() {
    let (classical, classical_end) = s7("classical");
    let (reparametrised, reparametrised_end) = s7("reparametrised");
    println!(
        "elbow margin over the run: classical {classical:.2}°, re-parametrised \
         {reparametrised:.2}° (thesis: classical past the limit, re-parametrised never); \
         verdicts {classical_end:?}, {reparametrised_end:?} (thesis: both recover)"
    );
    for end in [classical_end, reparametrised_end] {
        assert_ne!(
            end,
            Verdict::Completed,
            "S7 now completes: strike the fall from RESULTS.md's shortfalls and assert the thesis's claims"
        );
    }
}

/// The FSM #1 scenario (`scenarios/icub/fsm1_stepping.toml`, seed 001 S1) with `set` replacing
/// its controller's, run for `duration`: its metrics and its log's (t, fsm_state, right foot z,
/// its reference) rows.
fn fsm1(set: &str, duration: f64) -> (Metrics, Vec<[f64; 4]>) {
    let text = std::fs::read_to_string(scenario("fsm1_stepping.toml")).unwrap();
    let shipped = "set = { torque_rate = 100.0 }";
    assert!(text.contains(shipped));
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("fsm1.toml");
    std::fs::write(&path, text.replace(shipped, set)).unwrap();
    let out = dir.path().join("out");
    let m = run_file(&path, Some(&out), Some(duration), RunOptions::quiet())
        .unwrap_or_else(|e| panic!("{e:#}"))
        .metrics;
    let log = std::fs::read_to_string(out.join("log.csv")).unwrap();
    let mut lines = log.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let cols = ["t", "fsm_state", "right_foot_z", "right_foot_z_ref"].map(col);
    let rows = lines
        .map(|l| {
            let v: Vec<f64> = l
                .split(',')
                .map(|x| x.parse().unwrap_or(f64::NAN))
                .collect();
            cols.map(|c| v[c])
        })
        .collect();
    (m, rows)
}

/// The states visited, in order (1-based, as seed 001 numbers them), with their entry times.
fn visited(rows: &[[f64; 4]]) -> Vec<(usize, f64)> {
    let mut out: Vec<(usize, f64)> = Vec::new();
    for r in rows {
        let s = r[1] as usize + 1;
        if out.last().is_none_or(|l| l.0 != s) {
            out.push((s, r[0]));
        }
    }
    out
}

/// The report lines FSM #1 misses in 45 s (RESULTS.md gives the causes): the stride count (the
/// long run of RESULTS.md makes the thesis's 75) and the feet error's peak (the swing foot's
/// sideways excursion after a release). The lateral CoM error's peak, 9.4 mm here, reaches
/// 10.7 mm in the long run (a shortfall RESULTS.md lists).
const FSM1_KNOWN: [&str; 2] = [
    "strides (two steps each)",
    "feet error (estimate − reference), peak of any axis",
];

/// Seed 001 S1 (issue 18): FSM #1 and controller #1 step in place, 45 s here (2 strides; the
/// thesis's 75 run from `corps run scenarios/icub/fsm1_stepping.toml --duration 1560`, whose
/// output RESULTS.md records). The states follow Fig 2.3's order, the right foot rises to its
/// 5 cm set-point and stays 5 s (t_balancing), and every thesis bound the controller reports
/// holds but the known ones ([`FSM1_KNOWN`]). Under Table A.3's torque-rate bound
/// (50 N·m/s; the scenario runs the real robot's 100) the robot falls at its first foot
/// release: a known shortfall, RESULTS.md.
#[test]
fn fsm1_steps_in_place_and_falls_under_the_simulations_torque_rate() {
    let (m, rows) = fsm1("set = { torque_rate = 100.0 }", 45.0);
    let states = visited(&rows);
    println!("{states:?}\n{m}");
    assert_eq!(m.verdict.verdict, Verdict::Completed, "{}", m.verdict);
    assert_eq!(m.fallbacks, 0, "{:?}", m.first_fallback);
    let order: Vec<usize> = states.iter().map(|s| s.0).collect();
    assert_eq!(order[..12], [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 2]);
    let (t3, t4) = (states[2].1, states[3].1);
    assert!(t4 - t3 >= 5.0, "t_balancing: {:.2} s", t4 - t3);
    let up = rows.iter().rfind(|r| r[0] < t4).unwrap();
    println!("right foot at {:.4} m, set-point {:.4} m", up[2], up[3]);
    assert!((up[2] - up[3]).abs() < 0.01 && up[3] > 0.045);
    for l in &m.controller_report {
        if let (Some(thesis), Some(met)) = (&l.thesis, l.met) {
            println!(
                "{:<58} corps {:>9.4} {:<2} thesis {thesis}",
                l.figure, l.value, l.unit
            );
            let known = FSM1_KNOWN.contains(&l.figure.as_str());
            assert_eq!(met, !known, "{}: {:.4} against {thesis}", l.figure, l.value);
        }
    }
    for (axis, s) in ["x", "y", "z"].iter().zip(&m.com_error) {
        println!("true CoM error {axis}: peak {:.1} mm", s.peak * 1e3);
    }
    let (m, rows) = fsm1("set = { torque_rate = 50.0 }", 8.0);
    let states = visited(&rows);
    println!("under Table A.3's 50 N·m/s: {states:?}, {}", m.verdict);
    assert_eq!(states.iter().map(|s| s.0).collect::<Vec<_>>(), [1, 2, 3]);
    assert_ne!(
        m.verdict.verdict,
        Verdict::Completed,
        "the fall under Table A.3's rate bound is fixed: update RESULTS.md, the scenario and this test"
    );
}
