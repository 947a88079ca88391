//! One prediction of a person's path (issue 25, Deliver 4), beside Crocoddyl's `SolverDDP` on
//! the same OCP (`tools/anchors/human_walk_croc_bench.cpp`; both sides, interleaved:
//! `bash tools/anchors/run_human_walk_bench.sh`).
//!
//! - `ddp/*`: one DDP solve as the online predictor runs it (`prediction::predict`): zero
//!   controls from the start state, `DdpSettings::default()` (Σ‖Q_u‖² < 1e-9, at most 200
//!   iterations). Problems: golden problem 0 of `tests/data/human_walk_crocoddyl.json`
//!   (50 nodes), and the horizon the predictor chooses on the co-navigation scenario's walk
//!   (`shared/data/human-walking/E1540.dat`, subject 0, a quarter of the way, from the last
//!   50 samples, as `tests/human_prediction.rs`).
//! - `predict/*`: the whole prediction on that walk, `predict(window, dt, goal)`: the state
//!   estimate and the horizon search (one DDP solve per horizon tried).
//!
//! The problems (start state, goal, horizon) and corps' results are written to
//! `$HUMAN_WALK_PROBLEMS` (else `target/tmp/human_walk_problems.txt`), which the C++ harness
//! reads, one problem a line:
//! `ddp <name> <nodes> <x0: 6> <goal: 3> <iterations> <cost>` and
//! `predict <name> <x0: 6> <goal: 3> <nodes> <cost> <solves> <horizons solved, in order>`.

use corps_ocp::human_walk::{HumanWalkEnd, HumanWalkStep, DT, NU, NX};
use corps_ocp::prediction::predict;
use corps_ocp::recorded_walks;
use corps_ocp::{ActionModel, Ddp, DdpSettings, DdpSolution};
use criterion::{criterion_group, criterion_main, Criterion};
use nalgebra::Vector6;
use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::fmt::Write as _;
use std::path::PathBuf;

/// The predictor's window (samples), as the prediction test and the co-navigation default.
const WINDOW: usize = 50;

fn solve(x0: &[f64; 6], goal: [f64; 3], nodes: usize) -> DdpSolution<NX, NU> {
    let step = HumanWalkStep::new(goal);
    let end = HumanWalkEnd::new(goal);
    let running: Vec<&dyn ActionModel<NX, NU>> = vec![&step; nodes];
    let x0 = Vector6::from_column_slice(x0);
    Ddp::solve(&x0, &running, &end, None, &DdpSettings::default()).unwrap()
}

/// The start state `predict` solves from (its state estimate, repeated here so that the C++
/// harness gets it; checked below against `predict`'s own cost).
fn start_state(window: &[[f64; 3]], dt: f64, goal: [f64; 3]) -> [f64; 6] {
    let (first, last) = (window[0], window[window.len() - 1]);
    let span = (window.len() - 1) as f64 * dt;
    let speed = (last[0] - first[0]).hypot(last[1] - first[1]) / span;
    let heading = (last[1] - first[1]).atan2(last[0] - first[0]);
    let to_goal = (goal[1] - last[1]).atan2(goal[0] - last[0]);
    let shift = 2.0 * PI * ((to_goal - heading) / (2.0 * PI)).round();
    [last[0], last[1], heading + shift, speed, 0.0, 0.0]
}

/// The co-navigation scenario's walk (E1540, subject 0) a quarter of the way: window, period
/// and goal, as `corps-scenario`'s `conav.rs` and the prediction test build them.
fn shared_walk() -> (Vec<[f64; 3]>, f64, [f64; 3]) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/data/human-walking/E1540.dat");
    let walks = recorded_walks::read_paths(&path).expect("shared/data/human-walking/E1540.dat");
    let walk = walks.into_iter().find(|w| w.subject == 0).unwrap();
    let n = walk.poses.len();
    let (end, before) = (walk.poses[n - 1], walk.poses[n - WINDOW]);
    let goal = [
        end[0],
        end[1],
        (end[1] - before[1]).atan2(end[0] - before[0]),
    ];
    let k = ((n - 1) as f64 * 0.25).round() as usize;
    (walk.poses[k + 1 - WINDOW..=k].to_vec(), walk.dt, goal)
}

/// The horizons `predict` solves from `x0`, in its order, and the one it keeps: its search
/// (golden section over [guess/3, 3 guess], then a scan) repeated so that the C++ harness can
/// solve the same horizons (checked below against `predict`'s choice and count).
fn horizons(x0: &[f64; 6], goal: [f64; 3]) -> (Vec<usize>, usize, usize) {
    let mut order = Vec::new();
    let mut iterations = 0;
    let mut scores: BTreeMap<usize, f64> = BTreeMap::new();
    let mut score = |nodes: usize| {
        *scores.entry(nodes).or_insert_with(|| {
            order.push(nodes);
            let s = solve(x0, goal, nodes);
            iterations += s.iterations;
            let per_node = s.cost / nodes as f64;
            match (s.converged, s.iterations < 50) {
                (true, _) => per_node,
                (false, true) => 10.0 * per_node,
                (false, false) => 1e4,
            }
        })
    };
    let distance = (goal[0] - x0[0]).hypot(goal[1] - x0[1]);
    let guess = ((distance / 1.0 / DT).ceil() as usize).max(2);
    let (mut lo, mut hi) = ((guess / 3).max(2), 3 * guess);
    while hi - lo > 2 {
        let third = (hi - lo) as f64 * 0.381_966;
        let (a, b) = (lo + third.round() as usize, hi - third.round() as usize);
        let (a, b) = (a.min(b.saturating_sub(1)).max(lo), b.max(a + 1).min(hi));
        if score(a) <= score(b) {
            hi = b;
        } else {
            lo = a;
        }
    }
    let mut best = lo;
    for nodes in lo..=hi {
        if score(nodes) < score(best) {
            best = nodes;
        }
    }
    (order, best, iterations)
}

fn numbers(v: &[f64]) -> String {
    v.iter()
        .map(|x| format!("{x:e}"))
        .collect::<Vec<_>>()
        .join(" ")
}

fn bench(c: &mut Criterion) {
    let mut problems = String::new();
    let (window, dt, goal) = shared_walk();
    let p = predict(&window, dt, goal).unwrap();
    let x0 = start_state(&window, dt, goal);
    let at_horizon = solve(&x0, goal, p.nodes);
    assert_eq!(at_horizon.cost, p.cost, "the start state is not predict's");
    let (searched, best, iterations) = horizons(&x0, goal);
    assert_eq!(
        (best, searched.len()),
        (p.nodes, p.solves),
        "not predict's search"
    );
    let golden = ([-1.0, -4.0, 1.2, 0.0, 0.0, 0.0], [0.0, 0.0, PI / 2.0], 50);
    let walk_name = "E1540_s0_quarter";
    let mut group = c.benchmark_group("human_walk");
    for (name, x0, goal, nodes) in [
        ("golden0_n50", golden.0, golden.1, golden.2),
        (walk_name, x0, goal, p.nodes),
    ] {
        let s = solve(&x0, goal, nodes);
        println!(
            "ddp {name}: {nodes} nodes, {} iterations, cost {:.12}, converged {} (stop {:e})",
            s.iterations, s.cost, s.converged, s.stop
        );
        writeln!(
            problems,
            "ddp {name} {nodes} {} {} {} {:e}",
            numbers(&x0),
            numbers(&goal),
            s.iterations,
            s.cost
        )
        .unwrap();
        group.bench_function(format!("ddp/{name}"), |b| {
            b.iter(|| solve(&x0, goal, nodes))
        });
    }
    let searched: Vec<String> = searched.iter().map(usize::to_string).collect();
    println!(
        "predict {walk_name}: {} nodes, cost {:.12}, converged {}; {} DDP solves (horizons {}), \
         {iterations} iterations in all",
        p.nodes,
        p.cost,
        p.converged,
        p.solves,
        searched.join(" ")
    );
    writeln!(
        problems,
        "predict {walk_name} {} {} {} {:e} {} {}",
        numbers(&x0),
        numbers(&goal),
        p.nodes,
        p.cost,
        p.solves,
        searched.join(" ")
    )
    .unwrap();
    group.bench_function(format!("predict/{walk_name}"), |b| {
        b.iter(|| predict(&window, dt, goal).unwrap())
    });
    group.finish();
    let out = std::env::var_os("HUMAN_WALK_PROBLEMS")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("human_walk_problems.txt")
        });
    std::fs::write(&out, problems).unwrap();
    println!("problems written to {}", out.display());
}

criterion_group!(benches, bench);
criterion_main!(benches);
