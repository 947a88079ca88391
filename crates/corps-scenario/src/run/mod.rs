//! A scenario's closed-loop run. [`ScenarioRun::new`] builds the robot, the simulated plant,
//! the estimator, the controller and the motion from a parsed [`Scenario`] and lets the robot
//! settle under the joint PD hold; [`ScenarioRun::run`] then closes the loop
//! ([`corps_loop::ClosedLoop`]) and returns the metrics, the verdict and a bounded copy of the
//! time series in memory. Rows go to any [`RowSink`] the caller adds (a CSV file, a live plot)
//! as the run goes; this crate writes no file.

mod columns;
mod contacts;
mod plant;
mod recorder;

pub use columns::log_columns;

use crate::conav::CoNavigation;
use crate::controller::{
    self, behind_stabilizer, ControllerKind, IkController, ScenarioController,
};
use crate::controller::{SoftTasksConfig, SoftTasksController, TsidController, TsidMode};
use crate::error::{bail, invalid, Context, Result};
use crate::estimation;
use crate::gains;
use crate::metrics::{DynamicFilterMetrics, FootMetrics, Metrics, WalkMetrics, WalkingErrors};
use crate::mocap::MocapSourceKind;
use crate::motion::{self, MotionPlan, MotionSection};
use crate::scenario::Scenario;
use crate::series::PlotBuffer;
use crate::setup::{self, Setup};
use crate::velocity_walk::VelocitySource;
use crate::{dynamic_filter, ScenarioError};
use corps_estimation::KinematicEstimator;
use corps_loop::verdict::VerdictObserver;
use corps_loop::{ClosedLoop, LoopEnd, LoopSettings, Truth};
use corps_model::STANDARD_GRAVITY as GRAVITY;
use corps_model::{com_at_placements, frame_placement};
use corps_sim::WithHiddenJoints;
use corps_sim::{ExternalPlant, Overlap, SimulatedRobot, StatePlant};
use nalgebra::Vector3;
use plant::RunPlant;
use recorder::{Recorder, RecorderSetup};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

/// Receives every row of the time series as the run goes ([`log_columns`] order).
pub trait RowSink: Send {
    /// Row `index` (one per control tick). An error stops the run and is returned by it.
    fn row(&mut self, index: usize, row: &[f64]) -> Result<(), ScenarioError>;
    /// The plant's true state at the same tick (a viewer's recording draws the robot from
    /// it); called right after [`RowSink::row`]. Nothing by default.
    fn state(&mut self, _index: usize, _truth: &Truth) -> Result<(), ScenarioError> {
        Ok(())
    }
}

/// How a run executes.
#[derive(Clone, Copy, Debug)]
pub struct RunOptions {
    /// Whether the simulator prepares its next step on a second thread while the controller
    /// computes (bit-identical to the serial run).
    pub overlap: Overlap,
    /// Raised to stop the run at the next tick: it then returns what it has, marked
    /// interrupted.
    pub interrupt: Option<&'static AtomicBool>,
    /// Ends the run this long (s) after its first failure (a fall, a controller failure)
    /// instead of running on to the scenario's end: a teleoperated robot that fell. None
    /// runs on, so that the log shows what followed.
    pub stop_after_failure: Option<f64>,
}

impl Default for RunOptions {
    /// One thread, no interrupt, run to the end: for tests and for rollouts run side by side.
    fn default() -> Self {
        Self {
            overlap: Overlap::Never,
            interrupt: None,
            stop_after_failure: None,
        }
    }
}

/// What a run returns.
pub struct RunResult {
    pub metrics: Metrics,
    /// The time series' columns, and a bounded, decimated copy of its rows.
    pub columns: Vec<String>,
    pub series: PlotBuffer,
}

/// A scenario ready to run: built, checked and settled.
pub struct ScenarioRun {
    closed_loop: ClosedLoop<RunPlant, KinematicEstimator, ScenarioController, MotionPlan>,
    settings: LoopSettings,
    recorder: RecorderSetup,
    metrics: Metrics,
    verdict: VerdictObserver,
    columns: Vec<String>,
    handover: f64,
    feet0: [corps_model::spatial::Se3; 2],
    mass: f64,
    /// The dynamic filter's figures, for a filtered walk.
    dynamic_filter: Option<DynamicFilterMetrics>,
    interrupt: Option<&'static AtomicBool>,
    /// Each foot's sole frame and rectangle corners (left, right), for viewers.
    soles: [(usize, [Vector3<f64>; 4]); 2],
    /// The clip a teleoperation run follows and its units, for viewers.
    operator_clip: Option<(corps_mocap::bvh::Bvh, corps_mocap::skeleton::Units)>,
}

impl ScenarioRun {
    /// Builds `scenario` (named `name`; relative paths resolve from `base_dir`) and lets the
    /// robot settle for `[controller] settle`. Every error of the input comes from here,
    /// before a tick runs.
    pub fn new(
        scenario: &Scenario,
        name: &str,
        base_dir: &Path,
        options: RunOptions,
    ) -> Result<Self> {
        Self::build(scenario, name, base_dir, options, None)
    }

    /// As [`ScenarioRun::new`], the scenario's velocity walk (`[motion] kind = "velocity"`,
    /// no `commands`) taking its command from `steering` as the run goes: an operator's
    /// keyboard or joystick setting a [`crate::velocity_walk::LiveVelocity`] from another
    /// thread ([`crate::teleop`]), or any other source.
    pub fn steered(
        scenario: &Scenario,
        name: &str,
        base_dir: &Path,
        options: RunOptions,
        steering: Box<dyn VelocitySource>,
    ) -> Result<Self> {
        if scenario.human.is_some() {
            bail!("human: a walk with a person takes its commands from them, not from steering");
        }
        Self::build(scenario, name, base_dir, options, Some(steering))
    }

    fn build(
        scenario: &Scenario,
        name: &str,
        base_dir: &Path,
        options: RunOptions,
        mut steering: Option<Box<dyn VelocitySource>>,
    ) -> Result<Self> {
        let Some(section) = &scenario.controller else {
            bail!("no [controller] section: this is a `corps sim` scenario");
        };
        if steering.is_some() || scenario.human.is_some() {
            scenario.motion.check_steerable()?;
        }
        // The person's walk, read and checked before the robot moves.
        let person = (scenario.human.as_ref())
            .map(|h| CoNavigation::new(h, base_dir))
            .transpose()?;
        let Setup {
            robot,
            criteria,
            model,
            mut sim,
            sensors,
            command: hold,
            q0,
            feet: foot_sensors,
            imu_frame,
            press,
            hidden,
            ..
        } = setup::build(scenario, base_dir)?;
        let Some(robot) = robot else {
            bail!(
                "robot: corps run needs a robot description (robot.description), not a bare URDF"
            );
        };
        let source = gains::GainsSource::resolve(
            section.gains.as_deref(),
            section.kind.name(),
            &robot,
            base_dir,
        )
        .context("controller.gains")?;
        let soles = controller::two_feet(&robot)?;
        let sole_rectangles = soles.map(|f| (f.frame, f.corners));
        let dt = scenario.sim.control_dt;
        let settle_ticks = (section.settle / dt).round() as usize;
        for _ in 0..settle_ticks {
            if options.interrupt.is_some_and(|f| f.load(Ordering::Relaxed)) {
                return Err(ScenarioError::Interrupted { t: 0.0 });
            }
            sim.step(&hold)?;
        }
        let handover = sim.time();
        // Pushes count from the handover (the setup added none).
        let pushes = crate::pushes::schedule(
            &scenario.pushes,
            sim.time(),
            scenario.duration,
            Some(model.total_mass()),
        )
        .map_err(|e| invalid!("{e}"))?;
        for push in pushes {
            sim.add_push(push)?;
        }
        if let Some(p) = &press {
            if let Some(at) = p.section.block.removed_at {
                sim.remove_surface_at(p.block_surface, handover + at)?;
            }
        }
        // The state the controllers start from: what the rigid model sees of the plant's.
        let (q, v) = match &hidden {
            Some(map) => {
                let mut q = nalgebra::DVector::zeros(model.nq);
                let mut v = nalgebra::DVector::zeros(model.nv);
                map.narrow_q(sim.q().as_slice(), q.as_mut_slice());
                map.narrow_v(sim.v().as_slice(), v.as_mut_slice());
                (q, v)
            }
            None => (sim.q().clone_owned(), sim.v().clone_owned()),
        };
        let mass = model.total_mass();
        if scenario.footsteps.is_some() && section.kind != ControllerKind::TeleopVelocity {
            bail!(
                "footsteps: scripted footsteps are walked by the teleop_velocity controller, not '{}'",
                section.kind.name()
            );
        }
        if scenario.mocap.is_some() && section.kind != ControllerKind::TeleopVelocity {
            bail!(
                "mocap: an operator is followed by the teleop_velocity controller, not '{}'",
                section.kind.name()
            );
        }
        let mut operator_clip = None;
        let (inner, stabilized) = match section.kind {
            ControllerKind::TsidTorque
            | ControllerKind::TsidPosition
            | ControllerKind::PassiveTorque => {
                let mode = if section.kind == ControllerKind::TsidPosition {
                    TsidMode::Position
                } else {
                    TsidMode::Torque
                };
                let g: gains::TsidGains =
                    gains::load(&source, &section.set).context("controller.gains")?;
                match (section.kind == ControllerKind::PassiveTorque, g.tank.is_some()) {
                    (true, false) => bail!(
                        "controller.gains: the passive_torque controller needs a [tank] section"
                    ),
                    (false, true) => bail!(
                        "controller.gains: [tank] is the passive controller's (kind = \"passive_torque\")"
                    ),
                    _ => {}
                }
                let stabilizer = g.stabilizer.clone();
                let mut inner =
                    TsidController::new(&robot, mode, g, dt, &q, &v, &q0).context("controller")?;
                if let Some(p) = &press {
                    inner = inner.with_press(p.tip_frame, &p.section)?;
                }
                if matches!(scenario.motion, MotionSection::PostureSinusoid { .. }) {
                    inner = inner.with_posture_channels();
                }
                if mode == TsidMode::Torque && stabilizer.is_some() {
                    bail!("controller.gains: [stabilizer] is for the position-mode controllers")
                }
                let ctrl = behind_stabilizer(inner, stabilizer.as_ref(), soles[0], mass, dt)
                    .context("controller.gains.stabilizer")?;
                (ctrl, stabilizer.is_some())
            }
            ControllerKind::IkPosition => {
                let g: gains::IkGainsFile =
                    gains::load(&source, &section.set).context("controller.gains")?;
                let stabilizer = g.stabilizer.clone();
                if press.is_some() {
                    bail!("press: the force task needs a torque-mode TSID controller, not the IK");
                }
                let inner = IkController::new(&robot, g, dt, &q, &q0).context("controller")?;
                let ctrl = behind_stabilizer(inner, stabilizer.as_ref(), soles[0], mass, dt)
                    .context("controller.gains.stabilizer")?;
                (ctrl, stabilizer.is_some())
            }
            ControllerKind::TeleopVelocity => {
                let g: controller::teleop_velocity::TeleopVelocityConfig =
                    gains::load(&source, &section.set).context("controller.gains")?;
                let footsteps = match &scenario.footsteps {
                    Some(f) => f.steps()?,
                    None => Vec::new(),
                };
                if scenario.mocap.is_none() && footsteps.is_empty() {
                    bail!("mocap: the teleop_velocity controller follows an operator or walks footsteps: add a [mocap] or a [footsteps] section");
                }
                if press.is_some() {
                    bail!("press: the teleoperation controller has no force task");
                }
                let operator = match &scenario.mocap {
                    Some(mocap) => Some(mocap.open(base_dir)?),
                    None => None,
                };
                let from_clip =
                    (scenario.mocap.as_ref()).is_some_and(|m| m.source == MocapSourceKind::Bvh);
                operator_clip = (operator.as_ref())
                    .filter(|_| from_clip)
                    .map(|o| (o.clip.clone(), o.mapping.units()));
                let inner = controller::teleop_velocity::TeleopVelocityController::new(
                    &robot, g, dt, &q, operator, &footsteps,
                )
                .context("controller")?;
                (
                    Box::new(inner) as Box<dyn controller::WholeBodyController>,
                    false,
                )
            }
            ControllerKind::SoftTasks => {
                let g: SoftTasksConfig =
                    gains::load(&source, &section.set).context("controller.gains")?;
                if press.is_some() {
                    bail!("press: the soft-tasks controller has no force task");
                }
                let inner =
                    SoftTasksController::new(&robot, g, dt, &q, &v).context("controller")?;
                (
                    Box::new(inner) as Box<dyn controller::WholeBodyController>,
                    false,
                )
            }
        };
        let ankles = soles.map(|f| {
            f.ankle
                .map(|j| model.joints[j].idx_v - model.first_actuated())
        });
        let soles = soles.map(|f| f.frame);
        let tool_joint = (press.as_ref()).and_then(|p| model.frames[p.tip_frame].parent_joint);
        let foot_joints = soles.map(|f| model.frames[f].parent_joint.unwrap_or(usize::MAX));
        let mut estimator = estimation::build(
            &scenario.estimator,
            &model,
            &foot_sensors,
            soles,
            imu_frame,
            scenario.sim.gravity,
            scenario.force_torque_model == corps_sim::ForceTorqueModel::Transmitted,
        )?;
        if let Some(p) = &press {
            let hand = corps_estimation::FootSensor {
                sensor: p.hand_sensor,
                sensor_frame: p.sensor_frame,
                sole_frame: p.tip_frame,
            };
            estimator = estimator.with_hands(&[hand])?;
        }
        corps_estimation::Estimator::reset(&mut estimator, q.as_slice(), v.as_slice())?;
        // The handover as the controllers' model sees it (with hidden joints, the rigid
        // model at the encoders' angles).
        let mut rigid_data = None;
        let (model_ref, data) = match &hidden {
            Some(_) => {
                let mut d = corps_model::Data::new(&model);
                corps_model::forward_kinematics_placements(&model, &mut d, q.as_slice())?;
                (&model, &*rigid_data.insert(d))
            }
            None => (sim.model(), sim.data()),
        };
        let (com0, _) = com_at_placements(model_ref, data);
        let feet0 = [
            frame_placement(model_ref, data, soles[0])?,
            frame_placement(model_ref, data, soles[1])?,
        ];
        let ticks = (scenario.duration / dt).round() as usize;
        let following = person.is_some();
        if let Some(person) = person {
            let mid = (feet0[0].translation + feet0[1].translation) / 2.0;
            steering = Some(Box::new(person.placed_at([mid.x, mid.y])));
        }
        let mut plan = MotionPlan::new(
            &robot,
            scenario.motion.clone(),
            motion::Handover {
                com: com0,
                feet: feet0,
            },
            motion::Timeline {
                dt,
                duration: scenario.duration,
            },
            base_dir,
            sim.terrain(),
            steering,
        )?;
        let dynamic_filter = match &scenario.motion {
            MotionSection::Walk(w) if w.dynamic_filter => Some(
                dynamic_filter::filter_walk(&robot, &q, &q0, &mut plan, ticks)
                    .context("motion.dynamic_filter")?,
            ),
            _ => None,
        };
        let walking_window = plan.walk().and_then(|w| w.walking_window());
        let metrics = Metrics {
            scenario: name.to_string(),
            controller: section.kind.label().to_string(),
            duration: ticks as f64 * dt,
            feet: ["left", "right"]
                .map(|label| FootMetrics {
                    label: label.into(),
                    ..Default::default()
                })
                .to_vec(),
            min_base_height: f64::INFINITY,
            while_walking: walking_window.map(|(start, end)| WalkingErrors {
                start,
                end,
                ..Default::default()
            }),
            estimator: scenario.estimator.kind,
            sensor_noise: if scenario.noise == corps_sim::SensorNoise::default() {
                "noiseless".into()
            } else {
                "the scenario's [noise]".into()
            },
            thesis: scenario.thesis.clone(),
            ..Default::default()
        };
        let verdict =
            VerdictObserver::new(criteria, mass * GRAVITY, com0.z - recorder::support(&feet0))
                .context("verdict")?;
        let mut columns = log_columns(stabilized);
        if following {
            columns.extend(columns::FOLLOW_COLUMNS.map(String::from));
        }
        columns.extend(inner.channels().iter().map(|c| c.to_string()));
        let base0 = Vector3::new(q[0], q[1], q[2]);
        let current = plan.initial_targets();
        Ok(Self {
            closed_loop: ClosedLoop {
                plant: {
                    let robot = SimulatedRobot::new(sim, sensors, options.overlap);
                    match hidden {
                        Some(map) => RunPlant::Hidden(WithHiddenJoints::new(robot, map)),
                        None => RunPlant::Simulated(robot),
                    }
                },
                estimator,
                controller: match &section.flexibility {
                    Some(fx) => {
                        if !matches!(
                            section.kind,
                            ControllerKind::IkPosition
                                | ControllerKind::TsidPosition
                                | ControllerKind::TeleopVelocity
                        ) {
                            bail!("controller.flexibility: compensates position commands; kind '{}' sends torques", section.kind.name());
                        }
                        let g = Vector3::from(scenario.sim.gravity).norm();
                        let comp = fx.build(&robot, q0.as_slice(), g)?;
                        ScenarioController::new(inner).with_compensation(
                            comp,
                            fx.wrenches,
                            model.clone(),
                            g,
                            dt,
                        )
                    }
                    None => ScenarioController::new(inner),
                },
                references: plan,
                current,
            },
            settings: LoopSettings {
                dt,
                ticks,
                feed: estimation::feed(scenario.estimator.kind),
            },
            recorder: RecorderSetup {
                model,
                soles,
                foot_joints,
                tool_joint,
                ankles,
                base0,
                walking_window,
                stabilized,
                dt,
                columns: columns.len(),
                stop_after_failure: options.stop_after_failure,
                following,
            },
            metrics,
            verdict,
            columns,
            handover,
            feet0,
            mass,
            dynamic_filter,
            interrupt: options.interrupt,
            soles: sole_rectangles,
            operator_clip,
        })
    }

    /// Runs on `plant` instead of corps' simulator: the plant starts from the settled state
    /// (the simulator's, after `[controller] settle`) and is read through the scenario's
    /// sensors, with their noise, and is given the scenario's pushes
    /// ([`StatePlant::push`]). Terrain changes and the simulator's settings are the
    /// simulator's own and do not carry over.
    pub fn with_plant(mut self, plant: Box<dyn StatePlant>) -> Result<Self> {
        let ClosedLoop {
            plant: current_plant,
            estimator,
            controller,
            references,
            current,
        } = self.closed_loop;
        let sim = match current_plant {
            RunPlant::Simulated(sim) => sim,
            RunPlant::Hidden(_) => {
                bail!("robot: another plant cannot take a robot with passive joints")
            }
            RunPlant::External(_) => bail!("the run already has its own plant"),
        };
        let (sim, sensors) = sim.into_parts()?;
        let model = sim.model().clone();
        let start = (sim.q().as_slice(), sim.v().as_slice(), sim.time());
        let external = ExternalPlant::new(
            plant,
            model,
            sensors,
            start,
            self.settings.dt,
            sim.servo_gains(),
            sim.pushes(),
        )?;
        self.closed_loop = ClosedLoop {
            plant: RunPlant::External(external),
            estimator,
            controller,
            references,
            current,
        };
        Ok(self)
    }

    /// The robot's model (the one the run simulates and controls).
    pub fn model(&self) -> &std::sync::Arc<corps_model::Model> {
        &self.recorder.model
    }

    /// Each foot's sole frame and its rectangle's corners in that frame (left, right).
    pub fn soles(&self) -> &[(usize, [Vector3<f64>; 4]); 2] {
        &self.soles
    }

    /// The recorded clip a teleoperation run follows and its units (None for a live stream
    /// or another controller).
    pub fn operator_clip(&self) -> Option<&(corps_mocap::bvh::Bvh, corps_mocap::skeleton::Units)> {
        self.operator_clip.as_ref()
    }

    /// The time series' columns.
    pub fn columns(&self) -> &[String] {
        &self.columns
    }

    /// Control ticks the run will take at most.
    pub fn ticks(&self) -> usize {
        self.settings.ticks
    }

    /// Control period (s).
    pub fn dt(&self) -> f64 {
        self.settings.dt
    }

    /// Closes the loop until the scenario's end, a fall, a divergence or the interrupt; feeds
    /// every row to `sinks`.
    pub fn run(self, sinks: &mut [&mut dyn RowSink]) -> Result<RunResult> {
        let Self {
            mut closed_loop,
            settings,
            recorder,
            metrics,
            verdict,
            columns,
            handover,
            feet0,
            mass,
            dynamic_filter,
            interrupt,
            soles: _,
            operator_clip: _,
        } = self;
        let dt = settings.dt;
        let base0 = recorder.base0;
        let mut rec = Recorder::new(recorder, metrics, verdict, sinks);
        let outcome = closed_loop.run(&settings, &mut [&mut rec], interrupt)?;
        if let Some(e) = rec.sink_error.take() {
            return Err(e);
        }
        let mut m = std::mem::take(&mut rec.metrics);
        m.duration = outcome.ticks_run as f64 * dt;
        match outcome.end {
            LoopEnd::Interrupted => m.interrupted_at = Some(m.duration),
            LoopEnd::Diverged { t, reason } => rec
                .verdict
                .diverged(t - handover, format!("the simulation: {reason}")),
            LoopEnd::Completed | LoopEnd::Stopped => {}
        }
        m.tick_time = rec.tick_time.summary();
        m.verdict = rec.verdict.finish(m.duration);
        m.overlapped_ticks = closed_loop.plant.overlapped_ticks();
        m.estimator_errors = rec.estimator_errors;
        m.first_estimator_error = rec.first_estimator_error.take();
        let q = closed_loop.plant.final_configuration()?;
        if let Some(walk) = closed_loop.references.walk() {
            // Where the plan puts the base: its final feet midpoint plus the base's starting
            // offset from the feet midpoint.
            let r = walk.final_reference();
            let mid = walk.world(Vector3::new(
                (r.left_foot.x + r.right_foot.x) / 2.0,
                (r.left_foot.y + r.right_foot.y) / 2.0,
                0.0,
            ));
            let mid0 = (feet0[0].translation + feet0[1].translation) / 2.0;
            let planned = mid + (base0 - mid0);
            let base = Vector3::new(q[0], q[1], q[2]);
            let distance = (base - base0).xy().norm();
            let weight = mass * GRAVITY * distance.max(1e-9);
            m.walk = Some(WalkMetrics {
                distance,
                final_base_error: (base - planned).xy().norm(),
                cost_of_transport: m.work / weight,
                mechanical_cost_of_transport: m.positive_work / weight,
                passivity_gait_measure: rec.pgm.values(),
                dynamic_filter,
            });
        }
        for (foot, sum) in m.feet.iter_mut().zip(rec.force_sum) {
            foot.force_mean = sum / outcome.ticks_run.max(1) as f64;
        }
        m.against_thesis = m.thesis_comparison();
        m.controller_report = closed_loop.controller.report();
        m.teleop = closed_loop.controller.teleop_metrics();
        if let Some((failures, first)) = closed_loop.references.live_failures() {
            m.controller_report.push(crate::metrics::ReportLine {
                figure: format!(
                    "walking MPC failures (the reference held its last sample){}",
                    first.map(|f| format!(", first {f}")).unwrap_or_default()
                ),
                value: failures as f64,
                unit: "control periods".into(),
                thesis: None,
                met: None,
            });
        }
        Ok(RunResult {
            metrics: m,
            columns,
            series: std::mem::replace(&mut rec.series, PlotBuffer::new(0)),
        })
    }
}
