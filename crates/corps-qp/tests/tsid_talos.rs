//! The 25 TALOS whole-body QPs that TSID 1.10 built and eiquadprog 1.3.2 solved
//! (`tests/data/tsid_talos_double.json`, converted from `shared/data/qp/tsid-talos-double`).
//! corps-qp must reproduce eiquadprog's joint accelerations and sole wrenches.

mod common;

use corps_qp::{ActiveSetSolver, Settings};

fn check_against_eiquadprog(warm_start: bool, portable: bool) {
    let qps = common::load_tsid();
    assert_eq!(qps.len(), 25);
    let settings = Settings {
        warm_start,
        ..Settings::default()
    };
    let mut solver = ActiveSetSolver::with_settings(62, 18, 66, settings);
    if portable {
        solver.force_portable_kernels();
    }
    let (mut worst_dv, mut worst_w) = (0.0f64, 0.0f64);
    for q in &qps {
        let sol = solver
            .solve(&q.problem)
            .unwrap_or_else(|e| panic!("tick {}: {e}", q.tick));
        let dv_err = (0..38)
            .map(|i| (sol.x[i] - q.x[i]).abs())
            .fold(0.0, f64::max);
        assert!(
            dv_err <= 1e-6,
            "tick {}: |dv − dv_eiquadprog| = {dv_err:e}",
            q.tick
        );
        for range in [38..50, 50..62] {
            let w = common::sole_wrench(&sol.x.as_slice()[range.clone()], &q.contact_points);
            let w_ref = common::sole_wrench(&q.x.as_slice()[range], &q.contact_points);
            let err = w
                .iter()
                .zip(&w_ref)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            assert!(err <= 1e-3, "tick {}: sole wrench error {err:e}", q.tick);
            worst_w = worst_w.max(err);
        }
        let rel_obj = (sol.objective - q.objective).abs() / q.objective.abs().max(1e-12);
        assert!(
            rel_obj <= 1e-9,
            "tick {}: objective {} vs {}",
            q.tick,
            sol.objective,
            q.objective
        );
        // eiquadprog's file states no inequality is active on these ticks.
        assert_eq!(sol.active_set.len(), 18, "tick {}", q.tick);
        let kkt = common::kkt(&q.problem, sol);
        assert!(kkt.primal <= 1e-8, "tick {}: {kkt:?}", q.tick);
        worst_dv = worst_dv.max(dv_err);
    }
    eprintln!(
        "warm_start={warm_start}: max |dv err| = {worst_dv:e}, max sole wrench err = {worst_w:e}"
    );
}

#[test]
fn matches_eiquadprog_cold() {
    check_against_eiquadprog(false, false);
}

#[test]
fn matches_eiquadprog_warm_sequence() {
    check_against_eiquadprog(true, false);
}

#[test]
fn matches_eiquadprog_with_portable_kernels() {
    check_against_eiquadprog(true, true);
}
