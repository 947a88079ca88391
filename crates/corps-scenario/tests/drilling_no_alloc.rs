//! A drilling run's ticks allocate nothing between the cycle's events (counting global
//! allocator, per thread): sensing, the cycle, the QP update when due, the local loop, the
//! figures, the row and the simulator's step. An event — a phase that begins: the contact
//! made or released, the force task in or out, the thrust's pushes added — and the
//! [`SETTLE`] after it may allocate (the contact's force bound ramps over 0.05 s, and the
//! first QP with a new contact set sizes its problem), as may the run's first [`SETTLE`];
//! every other tick of the cycle is counted.

use corps_scenario::drilling::{DrillingRun, DrillingScenario};
use corps_scenario::run::RowSink;
use corps_scenario::ScenarioError;
use corps_testkit::{allocations, CountingAllocator};
use std::path::PathBuf;

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

/// How long after an event (s) allocations are not counted.
const SETTLE: f64 = 0.1;

/// Counts the allocations between consecutive rows more than [`SETTLE`] after an event.
struct Counter {
    phase_column: usize,
    /// The last row's phase and the allocations then, and when the phase last changed.
    last: Option<(f64, usize)>,
    changed_at: f64,
    steady_ticks: usize,
    allocating_ticks: Vec<(usize, usize)>,
}

impl RowSink for Counter {
    fn row(&mut self, index: usize, row: &[f64]) -> Result<(), ScenarioError> {
        let now = allocations();
        let (t, phase) = (row[0], row[self.phase_column]);
        if self.last.is_some_and(|(last_phase, _)| last_phase != phase) {
            self.changed_at = t;
        }
        if let Some((_, before)) = self.last {
            if t > self.changed_at + SETTLE {
                self.steady_ticks += 1;
                if now > before {
                    self.allocating_ticks.push((index, now - before));
                }
            }
        }
        self.last = Some((phase, allocations()));
        Ok(())
    }
}

#[test]
fn drilling_ticks_do_not_allocate_between_events() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios/drilling/ur5_drilling.toml");
    let mut s = DrillingScenario::parse(&std::fs::read_to_string(&path).unwrap()).unwrap();
    s.cycle.holes = 1;
    let run = DrillingRun::new(&s, path.parent().unwrap()).unwrap();
    assert_eq!(run.columns()[0], "t");
    let phase_column = run.columns().iter().position(|c| c == "phase").unwrap();
    let mut counter = Counter {
        phase_column,
        last: None,
        changed_at: 0.0,
        steady_ticks: 0,
        allocating_ticks: Vec::new(),
    };
    let m = run.run(&mut [&mut counter], None).unwrap();
    assert_eq!(m.verdict, "ok");
    assert!(counter.steady_ticks > 10_000, "{}", counter.steady_ticks);
    assert!(
        counter.allocating_ticks.is_empty(),
        "{} of {} ticks allocated, first (tick, allocations): {:?}",
        counter.allocating_ticks.len(),
        counter.steady_ticks,
        &counter.allocating_ticks[..counter.allocating_ticks.len().min(5)]
    );
}
