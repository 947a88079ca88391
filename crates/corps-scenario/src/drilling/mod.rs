//! A fixed-base arm drilling a plate under the passive QP (seed 000 §3.19, ch. 6: the MSDR
//! proposal, Eq 6.1–6.2, Table 6.1, the cycle of Table 6.2, the loops of L6960–L6990).
//!
//! The world: the arm's URDF on a fixed base, a massless cylinder on its flange whose end is
//! the tip frame ([`controller`]), and a plate (a box) whose top face is drilled. Each local
//! tick (`[loops] local_rate_hz`) the sensors are read with their noise (encoders, joint
//! velocities, the clamp load cell: the plate's normal force on the tool); when the
//! high-level update is due (`qp_rate_hz`, best effort with jitter: [`local_loop`]) the QP
//! runs on those readings; the local loop (a PD around the QP's trajectory with its torques
//! as feed-forward) then commands the torques, and the simulator steps at `[sim] step`. The cycle ([`cycle`]) drives the end-effector reference, makes and releases the
//! tool's contact and schedules the clamping force and the drill's thrust (an external
//! force on the tip the controller does not model).
//!
//! The verdict ([`DrillingMetrics::judge`]): every station done; while the clamping force is
//! held, the true normal force inside `[F_min, F_max]` and each tangential component within
//! the slip ratio on every tick; from the touch to the release, the force never above
//! `F_max` and the tool sliding less than `slide_limit_mm`; the power row `Ḣ ≤ −q̇ᵀτ` in every
//! update's solution and the tank paying all the energy the QP's torques gave the arm; no
//! joint past its position or velocity limit; no QP fallback.

pub mod controller;
pub mod cycle;
pub mod local_loop;
pub mod metrics;
pub mod section;

use crate::error::{bail, invalid, Context, Result};
use crate::run::RowSink;
use crate::ScenarioError;
use controller::{at_rest, ArmController};
use corps_control::tasks::Se3Reference;
use corps_learn::normal::Normal;
use corps_model::min_jerk::min_jerk_between;
use corps_model::spatial::rotation::{exp3, log3, rpy_to_matrix};
use corps_model::spatial::{Motion, Se3};
use corps_model::{CollisionGeometry, Frame, FrameKind, JointKind, Model, RootJoint, Shape};
use corps_sim::{
    Command, ContactParams, Integrator, Push, ServoGains, SimSettings, Simulator, Surface, Terrain,
};
use cycle::{Phase, Station};
use local_loop::{LocalRegulation, UpdateClock};
pub use metrics::DrillingMetrics;
use nalgebra::{DVector, Matrix3, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
pub use section::DrillingScenario;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

/// Name of the tip frame added to the arm's model.
pub const TIP_FRAME: &str = "drill_tip";
/// Steps of the drill's thrust as it rises.
const THRUST_STEPS: usize = 10;
/// A tangential force is compared with the normal one above this normal force (N).
const RATIO_MIN_NORMAL: f64 = 1.0;

/// A drilling run, built and ready.
pub struct DrillingRun {
    s: DrillingScenario,
    model: Arc<Model>,
    sim: Simulator,
    controller: ArmController,
    local: LocalRegulation,
    clock: UpdateClock,
    /// The jitter's draws, and the sensors' noise (N(0, 1) draws).
    rng: ChaCha8Rng,
    noise: Normal,
    stations: Vec<Station>,
    /// The plate's top face: origin at its centre, z its outward normal.
    plate: Se3,
    /// The tip's orientation at every station: z along the plate's normal, turned about it
    /// as the tool starts (a drill is symmetric about its axis).
    tool_rotation: Matrix3<f64>,
    tool_joint: usize,
    tip_in_joint: Se3,
    start_tip: Se3,
    local_dt: f64,
    ticks: usize,
    columns: Vec<String>,
}

/// Where the cycle stands.
struct CycleState {
    station: usize,
    phase: Phase,
    since: f64,
    /// The pose reference's start and end over the current motion, and its duration.
    from: Se3,
    to: Se3,
    duration: f64,
    /// Where the tip touched the plate (true, world).
    touch: Option<Vector3<f64>>,
    /// When the current hole's thrust started.
    thrust_from: Option<f64>,
}

impl DrillingRun {
    /// Builds the run of `s`; relative paths resolve from `base_dir`.
    pub fn new(s: &DrillingScenario, base_dir: &Path) -> Result<Self> {
        s.check().map_err(ScenarioError::Invalid)?;
        let EquippedArm {
            model,
            tip,
            tool_joint,
            q0,
        } = EquippedArm::new(s, base_dir)?;
        let tip_in_joint = model.frames[tip].placement;
        let p = &s.plate;
        let [r, pi, y] = p.rpy_deg.map(f64::to_radians);
        let plate = Se3::new(rpy_to_matrix(r, pi, y), Vector3::from(p.centre));
        let slab = Surface::Box {
            pose: plate
                * Se3::new(
                    Matrix3::identity(),
                    Vector3::new(0.0, 0.0, -p.thickness / 2.0),
                ),
            half_extents: Vector3::new(p.size[0] / 2.0, p.size[1] / 2.0, p.thickness / 2.0),
            mu: p.mu,
        };
        let local_dt = 1.0 / s.loops.local_rate_hz;
        let settings = SimSettings {
            control_dt: local_dt,
            substeps: (local_dt / s.sim.step - 1e-9).ceil().max(1.0) as usize,
            integrator: Integrator::ImplicitEuler,
            contact: ContactParams {
                normal_stiffness: s.sim.normal_stiffness,
                tangential_stiffness: s.sim.tangential_stiffness,
                ..ContactParams::default()
            },
            ..SimSettings::default()
        };
        let na = model.na();
        let idle = ServoGains {
            kp: DVector::zeros(na),
            kd: DVector::zeros(na),
            integral: None,
        };
        let terrain = Terrain {
            surfaces: vec![slab],
        };
        let sim = Simulator::new(model.clone(), terrain, settings, q0.as_slice(), idle)?;
        let start_tip = tip_placement(&sim, tool_joint, &tip_in_joint);
        if slab_contains(&sim, &start_tip.translation) {
            bail!("arm.q0: the tool's tip starts inside the plate");
        }
        let x = plate.rotation.transpose() * start_tip.rotation.column(0);
        let yaw = if x.x.hypot(x.y) > 1e-6 {
            x.y.atan2(x.x)
        } else {
            0.0
        };
        let tool_rotation = plate.rotation * rpy_to_matrix(0.0, 0.0, yaw);
        let controller = ArmController::new(model.clone(), tip, &q0, s)?;
        let gains = ServoGains::from_bandwidth(&model, q0.as_slice(), s.loops.local_bandwidth_hz)?;
        let limit = model
            .effort_limit
            .rows(model.first_actuated(), na)
            .into_owned();
        let local = LocalRegulation::new(&model, gains.kp, gains.kd, limit);
        let period = 1.0 / s.loops.qp_rate_hz;
        let clock = UpdateClock::new(period, s.loops.jitter, local_dt);
        let stations = cycle::stations(&s.cycle);
        let duration = s
            .duration
            .unwrap_or_else(|| cycle::nominal_length(&s.cycle) + 1.0);
        let ticks = (duration / local_dt).round().max(1.0) as usize;
        let columns = log_columns(&model);
        Ok(Self {
            s: s.clone(),
            sim,
            controller,
            local,
            clock,
            rng: ChaCha8Rng::seed_from_u64(s.loops.seed),
            noise: Normal::new(ChaCha8Rng::seed_from_u64(s.loops.seed.wrapping_add(1))),
            stations,
            plate,
            tool_rotation,
            tool_joint,
            tip_in_joint,
            start_tip,
            local_dt,
            ticks,
            columns,
            model,
        })
    }

    /// The log's columns.
    pub fn columns(&self) -> &[String] {
        &self.columns
    }

    /// Local ticks of the run, and their period (s).
    pub fn ticks(&self) -> usize {
        self.ticks
    }
    pub fn dt(&self) -> f64 {
        self.local_dt
    }

    /// The stations of the cycle.
    pub fn stations(&self) -> &[Station] {
        &self.stations
    }

    /// The plate's outward normal (world).
    fn normal(&self) -> Vector3<f64> {
        self.plate.rotation.column(2).into_owned()
    }

    /// The tool's approach point above `station`.
    fn approach(&self, station: usize) -> Se3 {
        self.above(station, self.s.cycle.standoff)
    }

    /// The tip `height` above the surface at `station` (below it if negative), in the tool's
    /// orientation.
    fn above(&self, station: usize, height: f64) -> Se3 {
        let [x, y] = self.stations[station].at;
        let at = self.plate.act_point(&Vector3::new(x, y, height));
        Se3::new(self.tool_rotation, at)
    }

    /// Runs the cycle, each tick's row to `sinks`, until a second after the cycle ends or
    /// for the scenario's duration; stops early (an error) if `interrupt` is raised.
    pub fn run(
        mut self,
        sinks: &mut [&mut dyn RowSink],
        interrupt: Option<&AtomicBool>,
    ) -> Result<DrillingMetrics> {
        let wall = Instant::now();
        let model = self.model.clone();
        let (nq, nv) = (model.nq, model.nv);
        let normal = self.normal();
        let sd = self.s.sensors.clone();
        let mut m = DrillingMetrics {
            stations: self.stations.len(),
            f_min_n: self.s.clamp.f_min,
            f_max_n: self.s.clamp.f_max,
            slip_ratio_bound: self.s.clamp.slip_ratio,
            slide_limit_mm: self.s.clamp.slide_limit_mm,
            clamp_min_n: f64::INFINITY,
            clamp_max_n: f64::NEG_INFINITY,
            qp_interval_min_ms: f64::INFINITY,
            tank_min_j: f64::INFINITY,
            cycle_time_s: f64::NAN,
            ..Default::default()
        };
        let mut cyc = CycleState {
            station: 0,
            phase: Phase::Move,
            since: 0.0,
            from: self.start_tip,
            to: self.approach(0),
            duration: self.s.cycle.move_time,
            touch: None,
            thrust_from: None,
        };
        let mut q_m = DVector::zeros(nq);
        let mut v_m = DVector::zeros(nv);
        let mut dq = DVector::zeros(nv);
        // The local loop's accelerations after a fallback (the safe command holds no motion).
        let at_rest_acceleration = DVector::zeros(nv);
        let mut command = Command::Torque(DVector::zeros(model.na()));
        let mut row = Vec::with_capacity(self.columns.len());
        let mut interval_sum = 0.0;
        let mut qp_interval = 0.0;
        let mut reference = at_rest(self.start_tip);
        let mut ran = self.ticks;
        for k in 0..self.ticks {
            if m.cycle_time_s.is_finite() && k as f64 * self.local_dt > m.cycle_time_s + 1.0 {
                // The cycle ended a second ago: the run ends.
                ran = k;
                break;
            }
            if interrupt.is_some_and(|f| f.load(Ordering::Relaxed)) {
                return Err(ScenarioError::Interrupted {
                    t: k as f64 * self.local_dt,
                });
            }
            let t = k as f64 * self.local_dt;
            // Sensors.
            for x in dq.iter_mut() {
                *x = sd.encoder * self.noise.draw();
            }
            corps_model::integrate_to(
                &model,
                self.sim.q().as_slice(),
                dq.as_slice(),
                q_m.as_mut_slice(),
            )?;
            for (m, v) in v_m.iter_mut().zip(self.sim.v().iter()) {
                *m = v + sd.velocity * self.noise.draw();
            }
            let wrench = self.sim.contact().body_wrenches[self.tool_joint];
            let clamp = normal.dot(&wrench.linear);
            let tangential = (wrench.linear - normal * clamp).norm();
            let load = clamp + sd.load_cell * self.noise.draw();
            let tip = tip_placement(&self.sim, self.tool_joint, &self.tip_in_joint);

            // The cycle.
            let (force_ref, force_rate) = self.advance_cycle(t, load, &tip, &mut cyc, &mut m)?;
            if cyc.phase != Phase::Done || cyc.since == t {
                reference = self.pose_reference(t, &cyc);
                self.controller.set_pose_reference(&reference);
            }

            // The high-level update, when due.
            let update = self.clock.due(t, &mut self.rng);
            if let Some((dt, until_next)) = update {
                qp_interval = dt;
                let reason = self.controller.tick(
                    t,
                    dt,
                    until_next,
                    q_m.as_slice(),
                    v_m.as_slice(),
                    load,
                    force_ref,
                    force_rate,
                );
                let sig = &self.controller.passive.signals;
                if m.qp_updates > 0 {
                    interval_sum += dt;
                    m.qp_interval_min_ms = m.qp_interval_min_ms.min(dt * 1e3);
                    m.qp_interval_max_ms = m.qp_interval_max_ms.max(dt * 1e3);
                }
                m.qp_updates += 1;
                if sig.h_dot.is_finite() && sig.h_dot > sig.passivity_bound + 1e-6 {
                    m.passivity_violations += 1;
                }
                m.tank_unpaid_j += sig.unpaid;
                m.qp_energy_to_arm_j -= sig.port_energy;
                m.tank_min_j = m.tank_min_j.min(sig.tank_energy);
                match reason {
                    Some(r) => {
                        m.qp_fallbacks += 1;
                        if m.first_fallback.is_none() {
                            m.first_fallback = Some(format!("t = {t:.3} s: {r}"));
                        }
                        self.local.update(
                            q_m.as_slice(),
                            v_m.as_slice(),
                            &at_rest_acceleration,
                            &self.controller.tau,
                        );
                    }
                    None => self.local.update(
                        q_m.as_slice(),
                        v_m.as_slice(),
                        self.controller.acceleration(),
                        &self.controller.tau,
                    ),
                }
            }
            let Command::Torque(tau) = &mut command else {
                unreachable!("a torque command")
            };
            self.local
                .command(&model, q_m.as_slice(), v_m.as_slice(), self.local_dt, tau)?;
            m.local_loop_energy_j += self
                .local
                .feedback
                .iter()
                .zip(self.sim.v().iter())
                .map(|(f, v)| f * v)
                .sum::<f64>()
                * self.local_dt;

            // Figures of this tick: the tool on the plate from its touch to its release.
            let on_plate = matches!(cyc.phase, Phase::Clamp | Phase::Hold | Phase::Release);
            if on_plate {
                m.contact_peak_n = m.contact_peak_n.max(clamp);
                if let Some(at) = cyc.touch {
                    let slide = along_plate(&normal, tip.translation - at);
                    m.slide_max_mm = m.slide_max_mm.max(slide * 1e3);
                }
            }
            let held = cyc.phase.clamped();
            if held {
                m.clamped_ticks += 1;
                m.clamp_min_n = m.clamp_min_n.min(clamp);
                m.clamp_max_n = m.clamp_max_n.max(clamp);
                if clamp < self.s.clamp.f_min || clamp > self.s.clamp.f_max {
                    m.clamp_out_of_bounds_ticks += 1;
                }
                // In the tip's frame, the frame of the QP's slip pyramid.
                let f = wrench.linear;
                let r = tip.rotation;
                let normal_in_tip = f.dot(&r.column(2));
                if normal_in_tip > RATIO_MIN_NORMAL {
                    let along = f.dot(&r.column(0)).abs().max(f.dot(&r.column(1)).abs());
                    m.slip_ratio_max = m.slip_ratio_max.max(along / normal_in_tip);
                }
                let cos = tip.rotation.column(2).dot(&normal).clamp(-1.0, 1.0);
                m.normality_error_max_deg = m.normality_error_max_deg.max(cos.acos().to_degrees());
            }
            if beyond_limits(&model, self.sim.q(), self.sim.v()) {
                m.joint_limit_violations += 1;
            }
            for (k, x) in tau.iter().enumerate() {
                let l = model.effort_limit[model.first_actuated() + k];
                m.torque_ratio_max = m.torque_ratio_max.max(x.abs() / l);
            }
            let thrust = self.thrust_at(t, &cyc);
            let sig = &self.controller.passive.signals;
            row.clear();
            row.extend([
                t,
                cyc.station as f64,
                cyc.phase.code(),
                clamp,
                load,
                force_ref,
                self.controller.force_desired,
                self.controller.force_solved,
                if held { self.s.clamp.f_min } else { f64::NAN },
                if held { self.s.clamp.f_max } else { f64::NAN },
                tangential,
                thrust,
                tip.translation.x,
                tip.translation.y,
                tip.translation.z,
                reference.placement.translation.x,
                reference.placement.translation.y,
                reference.placement.translation.z,
                sig.tank_energy,
                sig.valves.alpha,
                sig.valves.beta,
                sig.valves.gamma,
                sig.h_dot,
                sig.passivity_bound,
                if update.is_some() { 1.0 } else { 0.0 },
                qp_interval * 1e3,
            ]);
            row.extend(tau.iter());
            row.extend(self.sim.q().iter());
            for sink in sinks.iter_mut() {
                sink.row(k, &row)?;
            }
            self.sim.step(&command)?;
        }
        let duration = ran as f64 * self.local_dt;
        m.duration_s = duration;
        if m.qp_updates > 1 {
            m.qp_interval_mean_ms = interval_sum / (m.qp_updates - 1) as f64 * 1e3;
        }
        m.tank_final_j = self.controller.passive.signals.tank_energy;
        if m.clamped_ticks == 0 {
            m.clamp_min_n = f64::NAN;
            m.clamp_max_n = f64::NAN;
        }
        m.wall_time_s = wall.elapsed().as_secs_f64();
        m.real_time_factor = duration / m.wall_time_s.max(1e-9);
        m.judge();
        Ok(m)
    }

    /// Advances the cycle at `t` on the load cell's reading and the tip's placement; returns
    /// the force reference and its rate.
    fn advance_cycle(
        &mut self,
        t: f64,
        load: f64,
        tip: &Se3,
        c: &mut CycleState,
        m: &mut DrillingMetrics,
    ) -> Result<(f64, f64)> {
        let cy = self.s.cycle.clone();
        let clamp = self.s.clamp.force;
        let elapsed = t - c.since;
        match c.phase {
            Phase::Move if elapsed >= c.duration => {
                c.phase = Phase::Descend;
                c.since = t;
                c.from = c.to;
                c.to = self.above(c.station, cy.guard);
                c.duration = cy.descent_time;
            }
            Phase::Descend if load >= cy.touch_force => {
                let placement = self
                    .controller
                    .state
                    .frame_placement(&self.model, self.controller.tip())?;
                self.controller.make_contact(t, placement);
                c.phase = Phase::Clamp;
                c.since = t;
                c.from = Se3::new(self.tool_rotation, tip.translation);
                c.touch = Some(tip.translation);
                let [x, y] = self.stations[c.station].at;
                let hole = self.plate.act_point(&Vector3::new(x, y, 0.0));
                let off = along_plate(&self.normal(), tip.translation - hole);
                m.hole_position_error_max_mm = m.hole_position_error_max_mm.max(off * 1e3);
            }
            Phase::Descend if elapsed >= cy.descent_time + cycle::guarded_time(&cy) + 1.0 => {
                // No touch: the station is skipped.
                c.phase = Phase::Retreat;
                c.since = t;
                c.from = *tip;
                c.to = self.approach(c.station);
                c.duration = cy.retreat_time;
                c.touch = None;
            }
            Phase::Clamp if elapsed >= cy.ramp_time => {
                self.controller.set_min_force(self.s.clamp.f_min);
                c.phase = Phase::Hold;
                c.since = t;
                if self.stations[c.station].drill
                    && cy.thrust > 0.0
                    && self.stations[c.station].hold > 0.0
                {
                    self.start_thrust(t, c)?;
                }
            }
            Phase::Hold if elapsed >= self.stations[c.station].hold => {
                self.controller.set_min_force(0.0);
                c.phase = Phase::Release;
                c.since = t;
                c.thrust_from = None;
            }
            Phase::Release if elapsed >= cy.ramp_time => {
                let here = at_rest(Se3::new(self.tool_rotation, tip.translation));
                self.controller.release(t, &here)?;
                c.phase = Phase::Retreat;
                c.since = t;
                c.from = here.placement;
                c.to = self.approach(c.station);
                c.duration = cy.retreat_time;
                m.stations_done += 1;
                if self.stations[c.station].drill {
                    m.holes_drilled += 1;
                }
            }
            Phase::Retreat if elapsed >= c.duration => {
                c.touch = None;
                c.since = t;
                if c.station + 1 < self.stations.len() {
                    c.station += 1;
                    c.phase = Phase::Move;
                    c.from = c.to;
                    c.to = self.approach(c.station);
                    c.duration = cy.move_time;
                } else {
                    c.phase = Phase::Done;
                    c.from = c.to;
                    m.cycle_time_s = t;
                }
            }
            _ => {}
        }
        let elapsed = t - c.since;
        let ramp = |a: f64, b: f64| {
            let [f, rate, _] = min_jerk_between(a, b, elapsed / cy.ramp_time, cy.ramp_time);
            (f, rate)
        };
        Ok(match c.phase {
            Phase::Clamp => ramp(cy.touch_force, clamp),
            Phase::Hold => (clamp, 0.0),
            Phase::Release => ramp(clamp, 0.0),
            _ => (0.0, 0.0),
        })
    }

    /// The drill's thrust on the tip: `THRUST_STEPS` pushes starting one after the other
    /// over the rise time, all ending with the hold.
    fn start_thrust(&mut self, t: f64, c: &mut CycleState) -> Result<()> {
        let cy = &self.s.cycle;
        let hold = self.stations[c.station].hold;
        let f = self.normal() * (cy.thrust / THRUST_STEPS as f64);
        for i in 0..THRUST_STEPS {
            let start = t + cy.thrust_rise * i as f64 / THRUST_STEPS as f64;
            self.sim.add_push(Push {
                frame: TIP_FRAME.into(),
                start,
                duration: t + hold - start,
                force: [f.x, f.y, f.z],
                torque: [0.0; 3],
            })?;
        }
        c.thrust_from = Some(t);
        Ok(())
    }

    /// The thrust acting at `t` (N).
    fn thrust_at(&self, t: f64, c: &CycleState) -> f64 {
        let Some(from) = c.thrust_from else {
            return 0.0;
        };
        let cy = &self.s.cycle;
        let steps = ((t - from) / cy.thrust_rise * THRUST_STEPS as f64).floor() + 1.0;
        cy.thrust * steps.clamp(0.0, THRUST_STEPS as f64) / THRUST_STEPS as f64
    }

    /// The end-effector reference at `t`: a minimum-jerk motion from `from` to `to`
    /// (positions, and the rotation along the geodesic), at rest outside it.
    fn pose_reference(&self, t: f64, c: &CycleState) -> Se3Reference {
        let elapsed = t - c.since;
        if c.phase == Phase::Descend && elapsed > c.duration {
            // The guarded approach: straight down the normal at the touch speed.
            let cy = &self.s.cycle;
            let normal = self.normal();
            let depth =
                (cy.touch_speed * (elapsed - c.duration)).min(cy.guard + cy.descent_overshoot);
            let moving = depth < cy.guard + cy.descent_overshoot;
            let speed = if moving { cy.touch_speed } else { 0.0 };
            return Se3Reference {
                placement: Se3::new(c.to.rotation, c.to.translation - normal * depth),
                velocity: Motion::new(-normal * speed, Vector3::zeros()),
                acceleration: Motion::zero(),
            };
        }
        match c.phase {
            Phase::Move | Phase::Descend | Phase::Retreat => {
                let tau = (elapsed / c.duration).clamp(0.0, 1.0);
                let [s, ds, dds] = corps_model::min_jerk::min_jerk(tau);
                let (ds, dds) = (ds / c.duration, dds / (c.duration * c.duration));
                let dp = c.to.translation - c.from.translation;
                let w = log3(&(c.from.rotation.transpose() * c.to.rotation));
                let w_world = c.from.rotation * w;
                Se3Reference {
                    placement: Se3::new(
                        c.from.rotation * exp3(&(w * s)),
                        c.from.translation + dp * s,
                    ),
                    velocity: Motion::new(dp * ds, w_world * ds),
                    acceleration: Motion::new(dp * dds, w_world * dds),
                }
            }
            _ => at_rest(c.from),
        }
    }
}

/// The scenario's arm with its tool: the URDF on a fixed base, the tool's cylinder on the
/// flange and the tip frame ([`TIP_FRAME`]) at its end, z pointing back along the tool.
pub struct EquippedArm {
    pub model: Arc<Model>,
    /// The tip frame and the joint that carries the tool.
    pub tip: usize,
    pub tool_joint: usize,
    /// The starting configuration (`[arm] q0`).
    pub q0: DVector<f64>,
}

impl EquippedArm {
    /// Loads and equips the arm of `s`; its URDF's path resolves from `base_dir`.
    pub fn new(s: &DrillingScenario, base_dir: &Path) -> Result<Self> {
        let urdf = base_dir.join(&s.arm.urdf);
        let mut model = corps_model::build_model_from_urdf_file(&urdf, RootJoint::Fixed)
            .with_context(|| format!("arm.urdf: loading {}", urdf.display()))?;
        let flange = model.frame_id(&s.arm.tool_frame).map_err(|_| {
            invalid!(
                "arm.tool_frame: no frame '{}' in {}",
                s.arm.tool_frame,
                urdf.display()
            )
        })?;
        let Some(tool_joint) = model.frames[flange].parent_joint else {
            bail!(
                "arm.tool_frame: '{}' is fixed to the world",
                s.arm.tool_frame
            );
        };
        if model.frame_id(TIP_FRAME).is_ok() {
            bail!("arm.urdf: the model already has a frame '{TIP_FRAME}'");
        }
        let q0 = start_configuration(&model, &s.arm.q0)?;
        let l = s.tool.length;
        let flange_in_joint = model.frames[flange].placement;
        let flip = rpy_to_matrix(std::f64::consts::PI, 0.0, 0.0);
        let tip_in_joint = flange_in_joint * Se3::new(flip, Vector3::new(0.0, 0.0, l));
        let centre = Se3::new(Matrix3::identity(), Vector3::new(0.0, 0.0, l / 2.0));
        model.collisions.push(CollisionGeometry {
            link: "drill_tool".into(),
            parent_joint: Some(tool_joint),
            placement: flange_in_joint * centre,
            shape: Shape::Cylinder {
                radius: s.tool.radius,
                length: l,
            },
        });
        model.frames.push(Frame {
            name: TIP_FRAME.into(),
            kind: FrameKind::FixedJoint,
            parent_joint: Some(tool_joint),
            placement: tip_in_joint,
        });
        let tip = model.frames.len() - 1;
        Ok(Self {
            model: Arc::new(model),
            tip,
            tool_joint,
            q0,
        })
    }
}

/// The tip's true placement in the simulator.
fn tip_placement(sim: &Simulator, joint: usize, tip_in_joint: &Se3) -> Se3 {
    sim.data().o_m_i[joint] * *tip_in_joint
}

/// The length of `d` along the plate (its part across `normal`).
fn along_plate(normal: &Vector3<f64>, d: Vector3<f64>) -> f64 {
    (d - normal * normal.dot(&d)).norm()
}

/// Whether `p` is inside a surface of the simulator's world.
fn slab_contains(sim: &Simulator, p: &Vector3<f64>) -> bool {
    sim.terrain()
        .surfaces
        .iter()
        .any(|s| s.penetration(p).is_some())
}

/// The starting configuration: `q0` on the one-dof joints in order (none: all zero), in
/// degrees for a revolute joint and metres for a prismatic one.
fn start_configuration(model: &Model, q0: &[f64]) -> Result<DVector<f64>> {
    let mut q = corps_model::neutral(model);
    let joints: Vec<_> = model.joints.iter().filter(|j| j.nv() == 1).collect();
    if !q0.is_empty() && q0.len() != joints.len() {
        bail!(
            "arm.q0: {} positions for the arm's {} joints",
            q0.len(),
            joints.len()
        );
    }
    for (j, x) in joints.iter().zip(q0) {
        let prismatic = matches!(j.kind, JointKind::Prismatic { .. });
        let (value, unit) = if prismatic {
            (*x, "m")
        } else {
            (x.to_radians(), "°")
        };
        let shown = |v: f64| if prismatic { v } else { v.to_degrees() };
        if j.nq() == 2 {
            q[j.idx_q] = value.cos();
            q[j.idx_q + 1] = value.sin();
            continue;
        }
        let (lo, hi) = (
            model.lower_position_limit[j.idx_q],
            model.upper_position_limit[j.idx_q],
        );
        if lo < hi && (value < lo || value > hi) {
            bail!(
                "arm.q0: {x} {unit} for joint '{}' is outside its limits [{:.3}, {:.3}] {unit}",
                j.name,
                shown(lo),
                shown(hi)
            );
        }
        q[j.idx_q] = value;
    }
    Ok(q)
}

/// Whether a joint is past its position limit or its velocity limit.
fn beyond_limits(model: &Model, q: &DVector<f64>, v: &DVector<f64>) -> bool {
    model.joints.iter().filter(|j| j.nv() == 1).any(|j| {
        let vl = model.velocity_limit[j.idx_v];
        let fast = vl > 0.0 && vl.is_finite() && v[j.idx_v].abs() > vl;
        let past = j.nq() == 1 && {
            let (lo, hi) = (
                model.lower_position_limit[j.idx_q],
                model.upper_position_limit[j.idx_q],
            );
            lo < hi && (q[j.idx_q] < lo || q[j.idx_q] > hi)
        };
        fast || past
    })
}

/// The log's columns: the cycle, the clamp, the tip, the tank, the loops, then each joint's
/// torque and angle.
pub fn log_columns(model: &Model) -> Vec<String> {
    let mut c: Vec<String> = [
        "t",
        "station",
        "phase",
        "clamp_N",
        "load_cell_N",
        "force_ref_N",
        "force_desired_N",
        "force_qp_N",
        "f_min_N",
        "f_max_N",
        "tangential_N",
        "thrust_N",
        "tip_x",
        "tip_y",
        "tip_z",
        "tip_ref_x",
        "tip_ref_y",
        "tip_ref_z",
        "tank_energy_J",
        "alpha",
        "beta",
        "gamma",
        "h_dot_W",
        "passivity_bound_W",
        "qp_update",
        "qp_interval_ms",
    ]
    .map(String::from)
    .to_vec();
    let names: Vec<&str> = model
        .joints
        .iter()
        .filter(|j| j.nv() == 1)
        .map(|j| j.name.as_str())
        .collect();
    c.extend(names.iter().map(|n| format!("tau_{n}")));
    for j in model.joints.iter().filter(|j| j.nv() == 1) {
        if j.nq() == 2 {
            c.push(format!("q_{}_cos", j.name));
            c.push(format!("q_{}_sin", j.name));
        } else {
            c.push(format!("q_{}", j.name));
        }
    }
    c
}
