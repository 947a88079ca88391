//! Per-tick latency of the inverse-dynamics controller on TSID's TALOS anchor problem: 20 000
//! ticks, each on the next of the 25 states TSID recorded (state update + QP assembly + solve),
//! timed one by one; prints the median, p99 and peak. Criterion reports means of batches, so
//! it cannot give the p99 the issue asks for. Run with TSID's harness around it for the ratio:
//! `bash tools/bench/run_tsid_bench.sh; cargo bench -p corps-control --bench tick_latency`.

#[path = "../tests/common/tsid.rs"]
mod tsid;
use corps_control::RobotState;
use std::hint::black_box;
use std::time::Instant;
use tsid::*;

fn main() {
    // `cargo bench` passes `--bench`; `cargo test --benches` passes nothing: run a short smoke.
    let ticks_to_time = if std::env::args().any(|a| a == "--bench") {
        20_000
    } else {
        200
    };
    let (model, mut id, states) = anchor_problem();
    let mut state = RobotState::new(&model);
    let mut tick = |k: usize| {
        let (q, v) = &states[k % states.len()];
        state.update(&model, q, v).expect("state");
        black_box(id.compute(&model, &state).map(|o| o.tau[0])).expect("tick");
    };
    for k in 0..1000 {
        tick(k);
    }
    let mut us: Vec<f64> = (0..ticks_to_time)
        .map(|k| {
            let start = Instant::now();
            tick(k);
            start.elapsed().as_secs_f64() * 1e6
        })
        .collect();
    us.sort_by(f64::total_cmp);
    let q = |p: f64| us[((us.len() as f64 * p).ceil() as usize).clamp(1, us.len()) - 1];
    println!(
        "talos_id_tick latency over {} ticks: median {:.1} µs, p99 {:.1} µs, p99.9 {:.1} µs, peak {:.1} µs",
        us.len(),
        q(0.5),
        q(0.99),
        q(0.999),
        us[us.len() - 1]
    );
}
