//! The current-limiting iLQR in closed loop (seed 000 §3.13, §4.1 Fig 3.7–3.10): the MPC
//! solves the problem of [`crate::current_ocp`] at every control period from the measured
//! state, warm-started from the previous solution shifted by one node, and applies the first
//! current. The plant is the joint in corps-sim behind a flexible drive (current loop, one
//! period of delay, [`crate::simulated_joint`]), or the MPC's own model integrated by RK4
//! with ten sub-steps per control period and the current held. The payload hangs on the link from
//! the start; the reference swings the joint between `q_start` and `q_target` (beyond the
//! position limit, so that the barrier decides where the arm stops).

use crate::current_ocp::CurrentLimitingOcp;
use crate::description::ActuatorDescription;
use crate::elbow::Payload;
use crate::error::ActuatorError;
use crate::ilqr::{Ilqr, IlqrSettings};
use nalgebra::Vector2;

/// The longest closed loop a run keeps in memory, s (600 000 ticks at 1 kHz).
pub const MAX_DURATION_S: f64 = 600.0;

/// The closed-loop experiment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MpcScenario {
    /// Payload mass, kg, and its distance from the joint along the link, m.
    pub payload_kg: f64,
    pub distance_m: f64,
    /// Reference `q*(t) = c + a cos(2πt/T)` from `q_start` to `q_target` and back, rad.
    pub q_start: f64,
    pub q_target: f64,
    pub period_s: f64,
    pub duration_s: f64,
    /// Control period = node duration, s, and horizon length (nodes).
    pub dt: f64,
    pub horizon: usize,
    /// iLQR iterations per control period (upstream: 10).
    pub iterations_per_tick: usize,
    /// With the exponential barriers (false: the comparison without them).
    pub barrier: bool,
    /// What the MPC controls.
    pub plant: MpcPlant,
}

/// The plant of the closed loop.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MpcPlant {
    /// The MPC's own model (smoothed friction), RK4 at a tenth of the control period.
    Model,
    /// The joint in corps-sim behind a flexible drive with current loop and one period of
    /// delay ([`crate::simulated_joint`]).
    Simulator,
}

impl Default for MpcScenario {
    /// 30 kg at 5 cm (seed 000 §4.1), a 100-node 1 ms horizon (the thesis's laptop setting:
    /// 100 ms preview), from −0.2 rad to −2.5 rad (beyond the −2.35 rad limit) every 1.2 s.
    /// The thesis does not give its reference; this swing is fast enough that tracking it
    /// needs more than the 6 A limit with the drive gain of the description (without the
    /// barriers the command peaks near −6.2 A), as the thesis's 30 kg run did.
    fn default() -> Self {
        Self {
            payload_kg: 30.0,
            distance_m: 0.05,
            q_start: -0.2,
            q_target: -2.5,
            period_s: 1.2,
            duration_s: 3.6,
            dt: 0.001,
            horizon: 100,
            iterations_per_tick: 10,
            barrier: true,
            plant: MpcPlant::Simulator,
        }
    }
}

/// The closed-loop series, one sample per control period.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MpcSeries {
    pub t: Vec<f64>,
    pub q: Vec<f64>,
    pub q_ref: Vec<f64>,
    pub current: Vec<f64>,
    /// iLQR iterations of each solve.
    pub iterations: Vec<usize>,
}

impl MpcScenario {
    fn check(&self) -> Result<(), ActuatorError> {
        let bad = |what: &str| Err(ActuatorError::Ilqr(format!("scenario: {what}")));
        if !(self.payload_kg >= 0.0 && self.payload_kg.is_finite()) {
            return bad("the payload mass must be ≥ 0");
        }
        if !(self.distance_m.is_finite() && self.distance_m >= 0.0) {
            return bad("the payload distance must be ≥ 0");
        }
        if !(self.dt > 0.0 && self.period_s > 0.0 && self.duration_s > 0.0) {
            return bad("dt, period and duration must be positive");
        }
        if self.duration_s > MAX_DURATION_S {
            return bad(&format!(
                "duration {} s is beyond the {MAX_DURATION_S} s a run keeps in memory",
                self.duration_s
            ));
        }
        if self.period_s < 2.0 * self.dt {
            return bad(&format!(
                "the swing's period {} s is shorter than two control periods",
                self.period_s
            ));
        }
        if self.horizon == 0 || self.iterations_per_tick == 0 {
            return bad("the horizon and the iterations per tick must be positive");
        }
        if !(self.q_start.is_finite() && self.q_target.is_finite()) {
            return bad("the reference positions must be finite");
        }
        Ok(())
    }

    /// `[q*, q̇*]` at `t`.
    pub fn reference(&self, t: f64) -> Vector2<f64> {
        let c = 0.5 * (self.q_start + self.q_target);
        let a = 0.5 * (self.q_start - self.q_target);
        let w = 2.0 * std::f64::consts::PI / self.period_s;
        Vector2::new(c + a * (w * t).cos(), -a * w * (w * t).sin())
    }

    /// The problem the MPC solves.
    pub fn ocp(&self, actuator: &ActuatorDescription) -> CurrentLimitingOcp {
        CurrentLimitingOcp::new(
            actuator.model,
            Payload::point_mass(self.payload_kg, self.distance_m),
            &actuator.limits,
            self.dt,
            self.barrier,
        )
    }

    /// Runs the closed loop from rest at `q_start`.
    pub fn run(&self, actuator: &ActuatorDescription) -> Result<MpcSeries, ActuatorError> {
        self.run_timed(actuator, |_| {})
    }

    /// [`MpcScenario::run`], calling `on_solve` with each solve's wall time.
    pub fn run_timed(
        &self,
        actuator: &ActuatorDescription,
        mut on_solve: impl FnMut(std::time::Duration),
    ) -> Result<MpcSeries, ActuatorError> {
        let mut mpc = Mpc::new(self, actuator)?;
        let mut model_plant = mpc.ocp;
        model_plant.dt = self.dt / 10.0;
        let mut sim_plant = match self.plant {
            MpcPlant::Simulator => Some(crate::simulated_joint::SimulatedJoint::new(
                actuator,
                self.payload_kg,
                self.distance_m,
                self.q_start,
            )?),
            MpcPlant::Model => None,
        };
        let ticks = (self.duration_s / self.dt).round() as usize;
        let mut x = Vector2::new(self.q_start, 0.0);
        let mut out = MpcSeries::default();
        for tick in 0..ticks {
            let t = tick as f64 * self.dt;
            let start = std::time::Instant::now();
            let (u, iterations) = mpc.command(t, &x)?;
            on_solve(start.elapsed());
            out.t.push(t);
            out.q.push(x[0]);
            out.q_ref.push(self.reference(t)[0]);
            out.current.push(u);
            out.iterations.push(iterations);
            match &mut sim_plant {
                Some(joint) => {
                    joint.step(u)?;
                    let [q, v] = joint.state();
                    x = Vector2::new(q, v);
                }
                None => {
                    for _ in 0..10 {
                        x = model_plant.step(&x, u);
                    }
                }
            }
            if !(x[0].is_finite() && x[1].is_finite()) {
                return Err(ActuatorError::Ilqr(format!(
                    "the plant diverged at t = {t:.3} s"
                )));
            }
        }
        Ok(out)
    }
}

/// The controller: the problem, the solver warm-started from its last solution, and the
/// reference window.
#[derive(Clone, Debug)]
pub struct Mpc {
    pub ocp: CurrentLimitingOcp,
    scenario: MpcScenario,
    solver: Ilqr,
    reference: Vec<Vector2<f64>>,
}

impl Mpc {
    /// The controller of `scenario`, its controls initialised to the current that holds the
    /// start against gravity and the offset.
    pub fn new(
        scenario: &MpcScenario,
        actuator: &ActuatorDescription,
    ) -> Result<Self, ActuatorError> {
        scenario.check()?;
        let ocp = scenario.ocp(actuator);
        let settings = IlqrSettings {
            max_iterations: scenario.iterations_per_tick,
            ..IlqrSettings::default()
        };
        let mut solver = Ilqr::new(scenario.horizon, settings);
        let (_, _, off) = actuator.model.friction();
        let hold =
            (ocp.joint.gravity(scenario.q_start, &ocp.payload) + off) / actuator.model.drive_gain;
        solver.us_mut().fill(hold);
        Ok(Self {
            ocp,
            scenario: *scenario,
            solver,
            reference: vec![Vector2::zeros(); scenario.horizon + 1],
        })
    }

    /// The current to apply at time `t` in state `x`, and the iterations the solve took.
    pub fn command(&mut self, t: f64, x: &Vector2<f64>) -> Result<(f64, usize), ActuatorError> {
        for (k, r) in self.reference.iter_mut().enumerate() {
            *r = self.scenario.reference(t + k as f64 * self.scenario.dt);
        }
        let report = self.solver.solve(&self.ocp, x, &self.reference)?;
        let u = self.solver.us()[0];
        self.solver.shift();
        Ok((u, report.iterations))
    }
}
