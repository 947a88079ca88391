//! A scenario run on a plant that only reports its state ([`ScenarioRun::with_plant`]): here
//! a second copy of corps' simulator behind the [`StatePlant`] seam, so that the run can be held
//! against the same scenario on the simulator itself. The sensors are read from the reported
//! state (ABA with the reported contact forces), not from the simulator's own buffers.

use corps_loop::{Command, PlantError};
use corps_scenario::run::{RunOptions, RunResult, ScenarioRun};
use corps_scenario::scenario::Scenario;
use corps_sim::{PlantState, Push, Simulator, StatePlant};
use std::path::Path;

const DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenarios/control");

fn scenario(name: &str, duration: f64) -> Scenario {
    let text = std::fs::read_to_string(Path::new(DIR).join(name)).expect("the scenario");
    Scenario::parse(&text)
        .and_then(|s| s.with_duration(duration))
        .expect("the scenario parses")
}

/// corps' simulator reporting its state, as another engine would.
struct Reporting {
    sim: Simulator,
    /// Plant time at the hand-over (the copy's own clock starts at 0).
    t0: f64,
}

impl StatePlant for Reporting {
    fn reset(&mut self, q: &[f64], v: &[f64], t: f64, dt: f64) -> Result<(), PlantError> {
        self.sim
            .set_state(q, v)
            .map_err(|e| PlantError::Failed(e.to_string()))?;
        self.t0 = t - self.sim.time();
        // One `Simulator::step` is one control period (its substeps inside).
        assert!((dt - self.sim.settings().control_dt).abs() < 1e-12);
        Ok(())
    }

    fn push(&mut self, push: &Push) -> Result<(), PlantError> {
        let mut shifted = push.clone();
        shifted.start -= self.t0;
        self.sim
            .add_push(shifted)
            .map_err(|e| PlantError::Failed(e.to_string()))
    }

    fn step(&mut self, command: &Command) -> Result<(), PlantError> {
        self.sim.step(command).map_err(|e| PlantError::Diverged {
            t: self.sim.time(),
            reason: e.to_string(),
        })
    }

    fn state(&mut self, out: &mut PlantState) -> Result<(), PlantError> {
        out.time = self.t0 + self.sim.time();
        out.q.copy_from(self.sim.q());
        out.v.copy_from(self.sim.v());
        out.applied_torques.copy_from(self.sim.applied_torques());
        corps_sim::touching_points(&self.sim, &mut out.contacts);
        Ok(())
    }
}

/// The scenario on the simulator, then on the reporting copy.
fn both(s: &Scenario) -> (RunResult, RunResult) {
    let dir = Path::new(DIR);
    let on_sim = ScenarioRun::new(s, "sim", dir, RunOptions::default())
        .and_then(|r| r.run(&mut []))
        .expect("the run on the simulator");
    let copy = corps_scenario::setup::build(s, dir)
        .expect("the scenario builds")
        .sim;
    let plant = Box::new(Reporting { sim: copy, t0: 0.0 });
    let on_plant = ScenarioRun::new(s, "reporting", dir, RunOptions::default())
        .and_then(|r| r.with_plant(plant))
        .and_then(|r| r.run(&mut []))
        .expect("the run on the reporting plant");
    (on_sim, on_plant)
}

fn column(r: &RunResult, name: &str) -> Vec<f64> {
    let k = r
        .columns
        .iter()
        .position(|c| c == name)
        .expect("the column");
    r.series.column(k).to_vec()
}

#[test]
fn a_reporting_plant_stands_as_the_simulator_does() {
    let (on_sim, on_plant) = both(&scenario("tsid_torque_stand.toml", 1.0));
    assert_eq!(on_plant.metrics.verdict.verdict.to_string(), "completed");
    // The feet carry the robot, as the F/T sensors read it from the reported contacts.
    let weight = 9.81 * 90.272192;
    let (left, right) = (
        column(&on_plant, "left_foot_fz"),
        column(&on_plant, "right_foot_fz"),
    );
    let support = left[left.len() - 1] + right[right.len() - 1];
    assert!((support - weight).abs() < 0.01 * weight, "{support} N");
    // The same robot, controller and physics: the CoM follows the same path to 0.5 mm.
    for axis in ["com_x", "com_y", "com_z"] {
        let (a, b) = (column(&on_sim, axis), column(&on_plant, axis));
        let gap = a
            .iter()
            .zip(&b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        assert!(gap < 5e-4, "{axis}: {gap} m apart");
    }
}

#[test]
fn a_reporting_plant_gets_the_scenarios_pushes() {
    let s = scenario("tsid_torque_push_front.toml", 2.0);
    let (on_sim, on_plant) = both(&s);
    let peak = |r: &RunResult| {
        let x = column(r, "base_x");
        x.iter().map(|v| (v - x[0]).abs()).fold(0.0, f64::max)
    };
    let (a, b) = (peak(&on_sim), peak(&on_plant));
    assert!(a > 0.01, "the push moves the base on the simulator: {a} m");
    assert!(
        (a - b).abs() < 0.1 * a,
        "{a} m on the simulator, {b} m on the plant"
    );
}
