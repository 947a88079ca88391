//! corps' DDP on the human walking OCP against Crocoddyl's `SolverDDP` on the same problems
//! (`tools/golden/human_walk_crocoddyl.py` wrote the optima, Crocoddyl 3.2.1 converged to its
//! criterion 1e-18; corps to Σ‖Q_u‖² < 1e-18): the same optimum, cost to 1e-9 relative and
//! every state and control to 1e-6, from the same start (zero controls). Measured: states
//! within 6e-10, controls within 6e-9 (the orthogonal acceleration, weight 1e-6, is the
//! least determined).

use corps_ocp::human_walk::{
    HumanWalkEnd, HumanWalkStep, DT, NU, NX, RUNNING_WEIGHTS, TERMINAL_WEIGHTS,
};
use corps_ocp::{ActionModel, Ddp, DdpSettings};
use nalgebra::{DVector, Vector6};
use serde_json::Value;

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

#[test]
fn the_optima_are_crocoddyls() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/human_walk_crocoddyl.json"
    );
    let golden: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    assert_eq!(golden["dt"].as_f64().unwrap(), DT);
    assert_eq!(floats(&golden["running_weights"]), RUNNING_WEIGHTS.to_vec());
    assert_eq!(
        floats(&golden["terminal_weights"]),
        TERMINAL_WEIGHTS.to_vec()
    );
    let settings = DdpSettings {
        stop: 1e-18,
        max_iterations: 500,
        ..DdpSettings::default()
    };
    let problems = golden["problems"].as_array().unwrap();
    assert!(problems.len() >= 4);
    for p in problems {
        assert!(p["converged"].as_bool().unwrap());
        let start = floats(&p["start"]);
        let g = floats(&p["goal"]);
        let goal = [g[0], g[1], g[2]];
        let nodes = p["nodes"].as_u64().unwrap() as usize;
        let step = HumanWalkStep::new(goal);
        let end = HumanWalkEnd::new(goal);
        let running: Vec<&dyn ActionModel<NX, NU>> = vec![&step; nodes];
        let x0 = Vector6::new(start[0], start[1], start[2], 0.0, 0.0, 0.0);
        let s = Ddp::solve(&x0, &running, &end, None, &settings).unwrap();
        let cost = p["cost"].as_f64().unwrap();
        println!(
            "start {start:?}: corps {} iterations, cost {:.12}; Crocoddyl {} iterations, cost {cost:.12}",
            s.iterations,
            s.cost,
            p["iterations"]
        );
        assert!(s.converged, "Σ‖Q_u‖² = {}", s.stop);
        assert!(
            ((s.cost - cost) / cost).abs() < 1e-9,
            "{} vs {cost}",
            s.cost
        );
        let worst = |ours: &[Vector6<f64>], theirs: &Value| {
            ours.iter()
                .zip(theirs.as_array().unwrap())
                .map(|(a, b)| {
                    (DVector::from_column_slice(a.as_slice()) - DVector::from_vec(floats(b))).amax()
                })
                .fold(0.0, f64::max)
        };
        let dx = worst(&s.xs, &p["xs"]);
        let mut du = [0.0f64; 3];
        for (a, b) in s.us.iter().zip(p["us"].as_array().unwrap()) {
            let b = floats(b);
            for i in 0..3 {
                du[i] = du[i].max((a[i] - b[i]).abs());
            }
        }
        println!(
            "  largest differences: states {dx:.1e}, controls (u_f, u_ω, u_o) {:.1e} {:.1e} {:.1e}",
            du[0], du[1], du[2]
        );
        assert!(dx < 1e-6, "states differ by {dx}");
        assert!(du.iter().all(|d| *d < 1e-6), "controls differ by {du:?}");
    }
}
