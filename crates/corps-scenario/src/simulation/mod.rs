//! An open-loop simulation of a scenario (`corps sim`): the robot under the scenario's
//! constant joint command, its pushes and terrain, for `duration`. Each tick's signals go to
//! the caller (the row of [`log::columns`] and the values the plots show); the run returns
//! how it ended and what the robot did. No file is written here.

pub mod log;

use crate::error::{Context, Result};
use crate::scenario::Scenario;
use crate::setup::{self, Setup};
use corps_loop::verdict::{TickSample, VerdictObserver, VerdictReport};
use corps_model::{center_of_mass, forward_kinematics_placements, frame_placement, Data};
use corps_sim::SimError;
use nalgebra::Vector3;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

/// The values of one tick that a summary or a plot shows.
pub struct Signals<'a> {
    pub t: f64,
    pub base_z: f64,
    pub com: [f64; 3],
    /// Vertical contact force on each foot (N, world z).
    pub feet_fz: &'a [f64],
    /// Force/torque reading of each foot's sensor [fx, fy, fz, tx, ty, tz] in its frame.
    pub feet_ft: &'a [[f64; 6]],
    pub total_fz: f64,
    pub tau: &'a [f64],
}

/// One simulated tick as the caller sees it.
pub struct SimTick<'a> {
    /// Tick index, from 0.
    pub index: usize,
    /// The log's row ([`log::columns`] order).
    pub row: &'a [f64],
    pub signals: Signals<'a>,
}

/// How a simulation ended and what the robot did.
pub struct SimulationOutcome {
    /// Simulated time reached (s) and ticks run.
    pub simulated: f64,
    pub ticks: usize,
    pub final_base: [f64; 3],
    /// Lowest base height (m).
    pub min_base_z: f64,
    pub verdict: VerdictReport,
    /// Simulated time when the interrupt stopped the run (s).
    pub interrupted_at: Option<f64>,
    /// Largest horizontal displacement of each foot from its start (label, m).
    pub slip: Vec<(String, f64)>,
}

/// A scenario built and ready to simulate.
pub struct Simulation {
    setup: Setup,
    gravity: [f64; 3],
    columns: Vec<String>,
}

impl Simulation {
    /// Builds the world of `scenario` (relative paths resolve from `base_dir`).
    pub fn new(scenario: &Scenario, base_dir: &Path) -> Result<Self> {
        if scenario.controller.is_some() {
            crate::error::bail!(
                "this scenario has a [controller]: run it closed-loop (`corps run`, ScenarioRun)"
            );
        }
        let setup = setup::build(scenario, base_dir)?;
        if setup.hidden.is_some() {
            crate::error::bail!(
                "robot: a robot with passive joints runs closed-loop only (`corps run`)"
            );
        }
        let ft_names: Vec<String> = (setup.sensors.force_torque_names())
            .map(String::from)
            .collect();
        let columns = log::columns(&setup.model, &ft_names, &setup.feet);
        Ok(Self {
            setup,
            gravity: scenario.sim.gravity,
            columns,
        })
    }

    /// The log's columns.
    pub fn columns(&self) -> &[String] {
        &self.columns
    }

    /// Ticks the run takes at most.
    pub fn ticks(&self) -> usize {
        self.setup.ticks
    }

    /// The feet's labels, in [`Signals`]' order.
    pub fn feet_labels(&self) -> Vec<String> {
        self.setup.feet.iter().map(|f| f.label.clone()).collect()
    }

    /// The actuated joints' names, in [`Signals::tau`]'s order.
    pub fn joint_names(&self) -> Vec<String> {
        (log::actuated_joints(&self.setup.model).into_iter())
            .map(|(n, _)| n)
            .collect()
    }

    /// Steps until the scenario's end, a fall, a divergence or `interrupt`; hands every tick
    /// to `on_tick` (an error there stops the run and is returned).
    pub fn run(
        self,
        on_tick: &mut dyn FnMut(&SimTick<'_>) -> Result<()>,
        interrupt: Option<&AtomicBool>,
    ) -> Result<SimulationOutcome> {
        let Setup {
            model,
            mut sim,
            mut sensors,
            command,
            feet,
            ticks,
            q0,
            criteria,
            ..
        } = self.setup;
        let mut data = Data::new(&model);
        forward_kinematics_placements(&model, &mut data, q0.as_slice())?;
        let feet_start = (feet.iter())
            .map(|f| Ok(frame_placement(&model, &data, f.frame)?.translation))
            .collect::<Result<Vec<_>>>()?;
        // The verdict: the CoM height above the lowest sole (the ground when no foot is
        // named), the contact on bodies other than the feet (not judged when no foot is
        // named). Forces are judged in body weights; without gravity, in weights under
        // standard gravity.
        let g = Vector3::from(self.gravity).norm();
        let weight = model.total_mass()
            * if g > 0.0 {
                g
            } else {
                corps_model::STANDARD_GRAVITY
            };
        let support =
            |feet: &[Vector3<f64>]| feet.iter().map(|p| p.z).fold(f64::INFINITY, f64::min);
        let ground = if feet.is_empty() {
            0.0
        } else {
            support(&feet_start)
        };
        let zeros = vec![0.0; model.nv];
        let com0 = center_of_mass(&model, &mut data, q0.as_slice(), &zeros, &zeros)?;
        let mut verdict =
            VerdictObserver::new(criteria, weight, com0.z - ground).context("verdict")?;
        let foot_joints: Vec<usize> = feet.iter().map(|f| f.joint).collect();
        let mut min_base_z = f64::INFINITY;
        let mut max_slip = vec![0.0f64; feet.len()];
        let mut row = Vec::with_capacity(self.columns.len());
        let mut feet_fz = vec![0.0; feet.len()];
        let mut feet_ft = vec![[0.0; 6]; feet.len()];
        let mut feet_pos = vec![Vector3::zeros(); feet.len()];
        let (mut ticks_run, mut interrupted_at) = (0, None);
        for tick in 0..ticks {
            if interrupt.is_some_and(|f| f.load(Ordering::Relaxed)) {
                interrupted_at = Some(sim.time());
                break;
            }
            match sim.step(&command) {
                Ok(()) => {}
                Err(SimError::Diverged { t, reason }) => {
                    verdict.diverged(t, format!("the simulation: {reason}"));
                    break;
                }
                Err(other) => return Err(other.into()),
            }
            ticks_run = tick + 1;
            sensors.update(&sim);
            let (truth, measured) = (sensors.truth(), sensors.measured());
            let (q, v) = (sim.q().as_slice(), sim.v().as_slice());
            let com = center_of_mass(&model, &mut data, q, v, &zeros)?;
            let com_velocity = data.vcom;
            for (k, f) in feet.iter().enumerate() {
                feet_fz[k] = truth.contact_wrenches[f.joint][2];
                feet_ft[k] = measured.force_torque[f.sensor];
                feet_pos[k] = frame_placement(&model, sim.data(), f.frame)?.translation;
            }
            let total_fz = truth.contact_wrenches.iter().map(|w| w[2]).sum();
            log::fill_row(
                &mut row,
                truth,
                measured,
                &log::Extra {
                    com: &com,
                    com_velocity: &com_velocity,
                    feet_fz: &feet_fz,
                    total_fz,
                },
            );
            on_tick(&SimTick {
                index: tick,
                row: &row,
                signals: Signals {
                    t: truth.time,
                    base_z: q[2],
                    com: com.into(),
                    feet_fz: &feet_fz,
                    feet_ft: &feet_ft,
                    total_fz,
                    tau: truth.joint_torques.as_slice(),
                },
            })?;
            min_base_z = min_base_z.min(q[2]);
            for ((max, start), now) in max_slip.iter_mut().zip(&feet_start).zip(&feet_pos) {
                *max = max.max((now - start).xy().norm());
            }
            let total = (truth.contact_wrenches.iter())
                .fold(Vector3::zeros(), |s, w| s + Vector3::new(w[0], w[1], w[2]));
            let other = if feet.is_empty() {
                0.0
            } else {
                (truth.contact_wrenches.iter().enumerate())
                    .filter(|(j, _)| !foot_joints.contains(j))
                    .fold(Vector3::zeros(), |s, (_, w)| {
                        s + Vector3::new(w[0], w[1], w[2])
                    })
                    .norm()
            };
            let stop = verdict.observe(&TickSample {
                t: truth.time,
                com_height: com.z
                    - if feet.is_empty() {
                        ground
                    } else {
                        support(&feet_pos)
                    },
                base_speed: Vector3::new(v[0], v[1], v[2]).norm(),
                total_contact_force: total.norm(),
                other_contact_force: other,
                state_finite: q.iter().chain(v).all(|x| x.is_finite()),
                safe_command: false,
            });
            if stop.is_some() {
                break;
            }
        }
        let q = sim.q();
        Ok(SimulationOutcome {
            simulated: sim.time(),
            ticks: ticks_run,
            final_base: [q[0], q[1], q[2]],
            min_base_z,
            verdict: verdict.finish(sim.time()),
            interrupted_at,
            slip: (feet.iter().map(|f| f.label.clone()))
                .zip(max_slip)
                .collect(),
        })
    }
}
