//! The simulator: floating-base forward dynamics with contact and push wrenches, integrated
//! on the configuration manifold with RK4 (default) or semi-implicit Euler (both on ABA), or
//! with linearly implicit Euler (`simulator/implicit.rs`, on CRBA and a sparse factorization).

use crate::actuation::{Actuators, Command, ServoGains};
use crate::contact::{Anchor, ContactParams};
use crate::contact_pass::{contact_pass, PointVisit};
use crate::contact_points::{sample_contact_points, ContactPoint, ShapeBound};
use crate::disturbance::{PlacedPush, Push};
use crate::drive::{Drives, FlexibleDrive};
use crate::error::{Result, SimError};
use crate::terrain::Terrain;
use corps_model::spatial::Force;
use corps_model::{aba_with_external_forces, integrate_to, Data, Model};
use nalgebra::{DVector, Vector3};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

mod implicit;

/// Time integration scheme.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Integrator {
    /// Classical 4th-order Runge–Kutta: 4 dynamics evaluations per step, stable for contact
    /// stiffness up to ω·dt ≈ 2.8 and energy-accurate (drift O(dt⁴)).
    Rk4,
    /// Semi-implicit (symplectic) Euler: one evaluation per step, needs smaller steps.
    SemiImplicitEuler,
    /// Linearly implicit Euler in the contact springs and joint servos (one factorization of
    /// M plus their stiffness and damping per step; `simulator/implicit.rs`): stable at 1 ms
    /// with the stiff contact a torque controller needs, first order, dissipative.
    ImplicitEuler,
}

/// Simulation settings.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SimSettings {
    /// Control period (s): one command per period.
    pub control_dt: f64,
    /// Physics steps per control period.
    pub substeps: usize,
    pub integrator: Integrator,
    pub contact: ContactParams,
    /// Gravity (m/s², world frame).
    pub gravity: [f64; 3],
    /// Stops at the joints' URDF position limits (absent: none, the joints pass them).
    pub joint_stops: Option<crate::actuation::JointStops>,
}

impl Default for SimSettings {
    fn default() -> Self {
        Self {
            control_dt: 1e-3,
            substeps: 1,
            integrator: Integrator::Rk4,
            contact: ContactParams::default(),
            gravity: [0.0, 0.0, -corps_model::STANDARD_GRAVITY],
            joint_stops: None,
        }
    }
}

impl SimSettings {
    /// Checks every setting.
    pub fn validate(&self) -> Result<()> {
        let bad = |name: &str, reason: String| {
            Err(SimError::Setting {
                name: name.into(),
                reason,
            })
        };
        if !(self.control_dt > 0.0 && self.control_dt <= 0.1) {
            return bad(
                "control_dt",
                format!("{} s is not in (0, 0.1]", self.control_dt),
            );
        }
        if self.substeps == 0 || self.substeps > 1000 {
            return bad("substeps", format!("{} is not in 1..=1000", self.substeps));
        }
        let c = &self.contact;
        for (n, x) in [
            ("contact.normal_stiffness", c.normal_stiffness),
            ("contact.normal_damping_time", c.normal_damping_time),
            ("contact.tangential_stiffness", c.tangential_stiffness),
            ("contact.tangential_damping_time", c.tangential_damping_time),
        ] {
            if !(x >= 0.0 && x.is_finite()) {
                return bad(n, format!("{x} must be finite and ≥ 0"));
            }
        }
        if !(c.point_spacing > 1e-4 && c.point_spacing.is_finite()) {
            return bad(
                "contact.point_spacing",
                format!("{} m is too small", c.point_spacing),
            );
        }
        if self.gravity.iter().any(|g| !g.is_finite()) {
            return bad("gravity", "non-finite".into());
        }
        Ok(())
    }

    /// Physics step (s).
    pub fn dt(&self) -> f64 {
        self.control_dt / self.substeps as f64
    }
}

/// Contact forces at the end of the last step, for sensors, logs and tests. Under implicit
/// Euler the forces are the linearized ones that produced the step's velocity change, and
/// the positions those at the start of the step (a touching point moves ≪ 1 mm in a step);
/// neither the normal sign nor the friction cone is enforced on those recorded forces.
#[derive(Clone, Debug, Default)]
pub struct ContactState {
    /// World force on each contact point (zero when not touching).
    pub point_forces: Vec<Vector3<f64>>,
    /// World position of each contact point.
    pub point_positions: Vec<Vector3<f64>>,
    /// Net contact wrench on each joint's body, world frame, moment about the world origin.
    pub body_wrenches: Vec<Force>,
}

/// A simulation of one robot in one world.
pub struct Simulator {
    model: Arc<Model>,
    data: Data,
    settings: SimSettings,
    terrain: Terrain,
    points: Vec<ContactPoint>,
    bounds: Vec<ShapeBound>,
    anchors: Vec<Anchor>,
    actuators: Actuators,
    pushes: Vec<PlacedPush>,
    /// Surfaces to take out of the world: (time, index in `terrain.surfaces` now).
    removals: Vec<(f64, usize)>,
    q: DVector<f64>,
    v: DVector<f64>,
    t: f64,
    tau: DVector<f64>,
    contact: ContactState,
    acceleration: DVector<f64>,
    work: Rk4Work,
    implicit: implicit::ImplicitWork,
    /// The command of the last accepted step, and whether `acceleration` (evaluated at the
    /// end of that step) can serve as the first RK4 stage of the next one: it can when the
    /// command is unchanged and no contact anchor moved (first-same-as-last).
    last_cmd: Option<Command>,
    first_stage_valid: bool,
}

#[derive(Clone, Debug)]
struct Rk4Work {
    qs: DVector<f64>,
    vs: DVector<f64>,
    dq: DVector<f64>,
    ka: [DVector<f64>; 4],
    kv: [DVector<f64>; 4],
}

impl Simulator {
    /// A simulator starting at configuration `q0` at rest. `gains` are the joint servo gains
    /// used by position and velocity commands.
    pub fn new(
        model: Arc<Model>,
        terrain: Terrain,
        settings: SimSettings,
        q0: &[f64],
        gains: ServoGains,
    ) -> Result<Self> {
        settings.validate()?;
        model.check_configuration(q0)?;
        let na = model.nv - crate::actuation::first_actuated(&model);
        let integral_sizes_ok = gains.integral.as_ref().is_none_or(|i| {
            i.ki.len() == na && i.i_clamp.len() == na && i.torque_clamp.len() == na
        });
        if gains.kp.len() != na || gains.kd.len() != na || !integral_sizes_ok {
            return Err(SimError::Setting {
                name: "servo gains".into(),
                reason: format!("need {na} entries"),
            });
        }
        let (points, bounds) = sample_contact_points(&model, settings.contact.point_spacing);
        let nv = model.nv;
        // The run's gravity lives in its model; copy the model only when it differs.
        let gravity = Vector3::from(settings.gravity);
        let model = if gravity == model.gravity {
            model
        } else {
            let mut m = (*model).clone();
            m.gravity = gravity;
            Arc::new(m)
        };
        let n = model.njoints();
        let points_len = points.len();
        let mut sim = Self {
            data: Data::new(&model),
            actuators: Actuators::new(&model, gains),
            anchors: vec![Anchor::default(); points.len()],
            contact: ContactState {
                point_forces: vec![Vector3::zeros(); points.len()],
                point_positions: vec![Vector3::zeros(); points.len()],
                body_wrenches: vec![Force::zero(); n],
            },
            points,
            bounds,
            pushes: Vec::new(),
            removals: Vec::new(),
            q: DVector::from_column_slice(q0),
            v: DVector::zeros(nv),
            t: 0.0,
            tau: DVector::zeros(nv),
            acceleration: DVector::zeros(nv),
            work: Rk4Work {
                qs: DVector::zeros(model.nq),
                vs: DVector::zeros(nv),
                dq: DVector::zeros(nv),
                ka: std::array::from_fn(|_| DVector::zeros(nv)),
                kv: std::array::from_fn(|_| DVector::zeros(nv)),
            },
            last_cmd: None,
            first_stage_valid: false,
            implicit: implicit::ImplicitWork::new(&model, points_len),
            model,
            settings,
            terrain,
        };
        let stops = sim.settings.joint_stops;
        sim.actuators.set_stops(&sim.model, stops)?;
        // `data()` holds the kinematics of the current state from the start, as after a step.
        let (model, data) = (&*sim.model, &mut sim.data);
        let (v, a) = (sim.v.as_slice(), sim.acceleration.as_slice());
        corps_model::forward_kinematics(model, data, q0, v, a)?;
        Ok(sim)
    }

    /// The joint servos' gains (what position and velocity commands act through).
    pub fn servo_gains(&self) -> &ServoGains {
        &self.actuators.gains
    }

    /// The pushes added, in the order they were added, each with the joint it acts on.
    pub fn pushes(&self) -> &[PlacedPush] {
        &self.pushes
    }

    /// Adds a push on the body of frame `push.frame`.
    pub fn add_push(&mut self, push: Push) -> Result<()> {
        let fid = self.model.frame_id(&push.frame)?;
        let frame = &self.model.frames[fid];
        let Some(joint) = frame.parent_joint else {
            return Err(SimError::Setting {
                name: format!("push on '{}'", push.frame),
                reason: "the frame is fixed to the world".into(),
            });
        };
        if !(push.duration >= 0.0 && push.start.is_finite() && push.duration.is_finite())
            || push
                .force
                .iter()
                .chain(push.torque.iter())
                .any(|x| !x.is_finite())
        {
            return Err(SimError::Setting {
                name: format!("push on '{}'", push.frame),
                reason: "non-finite or negative timing/force".into(),
            });
        }
        self.pushes.push((push, joint, frame.placement));
        self.first_stage_valid = false;
        self.implicit.prepared = false;
        Ok(())
    }

    /// Takes terrain surface `index` out of the world at time `time` (s, simulated): from the
    /// first step that starts at or after it, nothing touches it (a block pulled away, a
    /// contact lost without warning). The other surfaces keep their anchors.
    pub fn remove_surface_at(&mut self, index: usize, time: f64) -> Result<()> {
        let pending = self.removals.iter().filter(|(_, k)| *k == index).count();
        if index >= self.terrain.surfaces.len() || pending > 0 {
            return Err(SimError::Setting {
                name: format!("removal of terrain surface {index}"),
                reason: format!(
                    "the world has surfaces 0..{}{}",
                    self.terrain.surfaces.len(),
                    if pending > 0 {
                        " and this one is already to be removed"
                    } else {
                        ""
                    }
                ),
            });
        }
        if !time.is_finite() {
            return Err(SimError::Setting {
                name: format!("removal of terrain surface {index}"),
                reason: format!("time {time} is not finite"),
            });
        }
        self.removals.push((time, index));
        Ok(())
    }

    /// Removes the surfaces due by the current time; the later removals' indices follow.
    fn remove_due_surfaces(&mut self) {
        while let Some(k) = self.removals.iter().position(|(t, _)| *t <= self.t) {
            let (_, index) = self.removals.swap_remove(k);
            self.terrain.surfaces.remove(index);
            for (_, later) in &mut self.removals {
                if *later > index {
                    *later -= 1;
                }
            }
            self.first_stage_valid = false;
            self.implicit.invalidate();
        }
    }

    /// Sets the state (q, v), e.g. to start with a velocity. Clears contact anchors.
    pub fn set_state(&mut self, q: &[f64], v: &[f64]) -> Result<()> {
        self.model.check_configuration(q)?;
        self.model.check_tangent("velocity v", v)?;
        self.q.copy_from_slice(q);
        self.v.copy_from_slice(v);
        self.anchors.iter_mut().for_each(|a| *a = Anchor::default());
        self.first_stage_valid = false;
        self.implicit.invalidate();
        self.actuators.restart_drives();
        Ok(())
    }

    /// Puts flexible drives (seed 000 Eq 2.33, [`crate::drive`]) on the actuated joints given
    /// one; they act on torque commands.
    /// Under an explicit integrator the drive's spring acts on the link explicitly: a drive
    /// whose `√(K/m)` on the joint's apparent inertia `m = 1/(M⁻¹)_jj` (at the current
    /// configuration) exceeds the step's stability bound (RK4 2.8/h, semi-implicit Euler 2/h)
    /// is refused, with the substeps it would need.
    pub fn set_drives(&mut self, drives: Vec<Option<FlexibleDrive>>) -> Result<()> {
        let bound = match self.settings.integrator {
            Integrator::ImplicitEuler => None,
            Integrator::Rk4 => Some(2.8),
            Integrator::SemiImplicitEuler => Some(2.0),
        };
        if let Some(bound) = bound {
            let model = &*self.model;
            let first = crate::actuation::first_actuated(model);
            let mut data = Data::new(model);
            let minv =
                corps_model::compute_minverse_factorized(model, &mut data, self.q.as_slice())?;
            let h = self.settings.dt();
            for (k, drive) in drives.iter().enumerate() {
                let Some(d) = drive else { continue };
                let Some(&m_inv) = minv.get((first + k, first + k)) else {
                    continue;
                };
                let omega = (d.stiffness * m_inv).sqrt();
                if omega * h > bound {
                    let needed = (omega * self.settings.control_dt / bound).ceil();
                    let joint = &model.joints[model.dof_joint[first + k]].name;
                    return Err(SimError::Setting {
                        name: format!("drive of {joint}"),
                        reason: format!(
                            "its spring ({} N·m/rad on {:.2e} kg·m²) needs a step of at most \
                             {:.2e} s under {:?}: use integrator = \"implicit_euler\" or \
                             {needed} substeps",
                            d.stiffness,
                            1.0 / m_inv,
                            bound / omega,
                            self.settings.integrator
                        ),
                    });
                }
            }
        }
        self.actuators.set_drives(&self.model, drives)?;
        self.first_stage_valid = false;
        Ok(())
    }

    /// Makes `joints` (model joint index, stiffness N·m/rad, damping N·m·s/rad) passive
    /// spring-dampers: the command no longer moves them ([`Actuators::set_passive`]).
    pub fn set_passive_joints(&mut self, joints: &[(usize, f64, f64)]) -> Result<()> {
        self.actuators.set_passive(&self.model, joints)?;
        self.first_stage_valid = false;
        self.implicit.prepared = false;
        Ok(())
    }

    /// The flexible drives, if any.
    pub fn drives(&self) -> Option<&Drives> {
        self.actuators.drives()
    }

    pub fn model(&self) -> &Arc<Model> {
        &self.model
    }
    pub fn settings(&self) -> &SimSettings {
        &self.settings
    }
    pub fn terrain(&self) -> &Terrain {
        &self.terrain
    }
    /// Simulated time (s).
    pub fn time(&self) -> f64 {
        self.t
    }
    /// Configuration.
    pub fn q(&self) -> &DVector<f64> {
        &self.q
    }
    /// Velocity.
    pub fn v(&self) -> &DVector<f64> {
        &self.v
    }
    /// Joint torques applied in the last evaluation (size nv, zero on the base).
    pub fn applied_torques(&self) -> &DVector<f64> {
        &self.tau
    }
    /// Generalized acceleration at the current state under the last command (under implicit
    /// Euler, the mean over the last step, Δv / h).
    pub fn acceleration(&self) -> &DVector<f64> {
        &self.acceleration
    }
    /// Whether the next step can reuse the end-of-step evaluation as its first RK4 stage.
    pub fn reuses_first_stage(&self) -> bool {
        self.first_stage_valid
    }
    /// Contact forces at the current state.
    pub fn contact(&self) -> &ContactState {
        &self.contact
    }
    /// Rigid-body workspace holding placements and world velocities at the current state.
    pub fn data(&self) -> &Data {
        &self.data
    }
    /// The sampled contact points.
    pub fn contact_points(&self) -> &[ContactPoint] {
        &self.points
    }

    /// Total mechanical energy (kinetic + potential) at the current state.
    pub fn energy(&mut self) -> Result<f64> {
        self.implicit.invalidate();
        let ke = corps_model::kinetic_energy(
            &self.model,
            &mut self.data,
            self.q.as_slice(),
            self.v.as_slice(),
        )?;
        let pe = corps_model::potential_energy(&self.model, &mut self.data, self.q.as_slice())?;
        Ok(ke + pe)
    }

    /// Does ahead the part of the next step that depends on the state alone (implicit Euler:
    /// h(q, v), the contact pass and the factorization; other integrators: nothing), so a
    /// caller can run it while its controller computes the command. [`Simulator::step`] does
    /// it itself when it was not done; either way the step is bit-identical. Changes none of
    /// the state, contact or sensor readings.
    pub fn prepare_step(&mut self) {
        self.remove_due_surfaces();
        if self.settings.integrator == Integrator::ImplicitEuler && !self.implicit.prepared {
            self.prepare_implicit(self.settings.dt());
        }
    }

    /// Advances one control period under `cmd`.
    pub fn step(&mut self, cmd: &Command) -> Result<()> {
        self.actuators.check(&self.model, cmd)?;
        if !store_command(&mut self.last_cmd, cmd) {
            self.first_stage_valid = false;
        }
        let period = self.settings.control_dt;
        if self
            .actuators
            .integrate(&self.model, cmd, self.q.as_slice(), period)
        {
            self.first_stage_valid = false;
        }
        let drives = self.actuators.has_drives();
        if drives {
            self.actuators
                .begin_period(cmd, self.q.as_slice(), self.v.as_slice());
            self.first_stage_valid = false;
        }
        let h = self.settings.dt();
        for _ in 0..self.settings.substeps {
            self.remove_due_surfaces();
            match self.settings.integrator {
                Integrator::Rk4 => self.rk4(cmd, h),
                Integrator::SemiImplicitEuler => self.euler(cmd, h),
                Integrator::ImplicitEuler => {
                    self.implicit_euler(cmd, h)?;
                    self.t += h;
                    self.advance_drives(cmd, h);
                    continue;
                }
            }
            self.t += h;
            self.finish_step(cmd)?;
            self.advance_drives(cmd, h);
        }
        Ok(())
    }

    /// Advances the flexible drives' motors over a step of `h` with the links at the new
    /// state (the link step held them); the end-of-step evaluation no longer holds.
    fn advance_drives(&mut self, cmd: &Command, h: f64) {
        if self.actuators.has_drives() {
            self.actuators
                .advance_drives(cmd, h, self.q.as_slice(), self.v.as_slice());
            self.first_stage_valid = false;
        }
    }

    fn rk4(&mut self, cmd: &Command, h: f64) {
        let mut w = self.begin_step();
        let fractions = [0.5, 0.5, 1.0];
        for stage in 0..4 {
            w.kv[stage].copy_from(&w.vs);
            // The end-of-step evaluation already gave stage 1 when nothing changed since.
            if stage > 0 || !self.first_stage_valid {
                self.evaluate(
                    cmd,
                    w.qs.as_slice(),
                    w.vs.as_slice(),
                    self.t + h * [0.0, 0.5, 0.5, 1.0][stage],
                    false,
                );
            }
            w.ka[stage].copy_from(&self.acceleration);
            if stage < 3 {
                let c = h * fractions[stage];
                for k in 0..w.dq.len() {
                    w.dq[k] = c * w.kv[stage][k];
                    w.vs[k] = self.v[k] + c * w.ka[stage][k];
                }
                let _ = integrate_to(
                    &self.model,
                    self.q.as_slice(),
                    w.dq.as_slice(),
                    w.qs.as_mut_slice(),
                );
            }
        }
        for k in 0..w.dq.len() {
            w.dq[k] = h / 6.0 * (w.kv[0][k] + 2.0 * w.kv[1][k] + 2.0 * w.kv[2][k] + w.kv[3][k]);
            self.v[k] += h / 6.0 * (w.ka[0][k] + 2.0 * w.ka[1][k] + 2.0 * w.ka[2][k] + w.ka[3][k]);
        }
        self.end_step(w);
    }

    fn euler(&mut self, cmd: &Command, h: f64) {
        let mut w = self.begin_step();
        self.evaluate(cmd, w.qs.as_slice(), w.vs.as_slice(), self.t, false);
        for k in 0..w.dq.len() {
            self.v[k] += h * self.acceleration[k];
            w.dq[k] = h * self.v[k];
        }
        self.end_step(w);
    }

    /// The work buffers, with `qs`, `vs` holding the current state (no allocation).
    fn begin_step(&mut self) -> Rk4Work {
        let mut w = std::mem::replace(&mut self.work, Rk4Work::empty());
        w.qs.copy_from(&self.q);
        w.vs.copy_from(&self.v);
        w
    }

    /// `q ← q ⊕ w.dq` (checked sizes: cannot fail), and the work buffers go back.
    fn end_step(&mut self, mut w: Rk4Work) {
        let _ = integrate_to(
            &self.model,
            self.q.as_slice(),
            w.dq.as_slice(),
            w.qs.as_mut_slice(),
        );
        self.q.copy_from(&w.qs);
        self.work = w;
    }

    /// Re-evaluates at the new state: accepts the anchors, records contact forces and the
    /// acceleration (for the IMU), and checks for divergence.
    fn finish_step(&mut self, cmd: &Command) -> Result<()> {
        corps_model::normalize(&self.model, self.q.as_mut_slice());
        self.check_state(self.t)?;
        let w = self.begin_step();
        self.first_stage_valid =
            !self.evaluate(cmd, w.qs.as_slice(), w.vs.as_slice(), self.t, true);
        self.work = w;
        Ok(())
    }

    /// A divergence error at time `t` if the state is non-finite or exploding.
    fn check_state(&self, t: f64) -> Result<()> {
        let bad = self.q.iter().chain(self.v.iter()).any(|x| !x.is_finite()) || self.v.amax() > 1e4;
        if bad {
            return Err(SimError::Diverged {
                t,
                reason: "non-finite or exploding state".into(),
            });
        }
        Ok(())
    }

    /// Generalized acceleration at (q, v, t) under `cmd`, into `self.acceleration`. With
    /// `record`, also stores contact forces and moves the anchors; returns whether any anchor
    /// changed.
    fn evaluate(&mut self, cmd: &Command, q: &[f64], v: &[f64], t: f64, record: bool) -> bool {
        let mut changed = false;
        let model = &*self.model;
        self.actuators.set_drive_lead(t - self.t);
        self.actuators
            .torques(model, cmd, q, v, self.tau.as_mut_slice());
        let (terrain, params) = (&self.terrain, &self.settings.contact);
        let (points, bounds, anchors) = (&self.points, &self.bounds, &mut self.anchors);
        let (pushes, contact) = (&self.pushes, &mut self.contact);
        let result = aba_with_external_forces(
            model,
            &mut self.data,
            q,
            v,
            self.tau.as_slice(),
            |o_m_i, ov, fext| {
                if record {
                    contact
                        .body_wrenches
                        .iter_mut()
                        .for_each(|f| *f = Force::zero());
                }
                let visit = |pt: PointVisit| {
                    let f = pt.force.as_ref().map_or(Vector3::zeros(), |x| x.force);
                    let p = pt.position;
                    let wrench = Force::new(f, p.cross(&f));
                    fext[pt.joint] += wrench;
                    if record {
                        contact.point_forces[pt.index] = f;
                        contact.point_positions[pt.index] = p;
                        contact.body_wrenches[pt.joint] += wrench;
                        let next = pt.force.map_or(Anchor::default(), |x| x.next_anchor);
                        changed |= next != *pt.anchor;
                        *pt.anchor = next;
                    }
                };
                contact_pass(
                    terrain, params, points, bounds, anchors, o_m_i, ov, record, visit,
                );
                for (push, joint, placement) in pushes {
                    if push.active(t) {
                        fext[*joint] += push.world_wrench(&o_m_i[*joint], placement);
                    }
                }
            },
        );
        match result {
            Ok(a) => self.acceleration.copy_from(a),
            Err(_) => self.acceleration.fill(f64::NAN),
        }
        changed
    }
}

/// Keeps a copy of `cmd` in `slot` (without allocating when its kind and sizes are
/// unchanged); returns whether the stored command was already equal to `cmd`.
fn store_command(slot: &mut Option<Command>, cmd: &Command) -> bool {
    match slot {
        Some(last) => {
            let same = last == cmd;
            last.copy_from(cmd);
            same
        }
        None => {
            *slot = Some(cmd.clone());
            false
        }
    }
}

impl Rk4Work {
    fn empty() -> Self {
        let z = || DVector::zeros(0);
        Self {
            qs: z(),
            vs: z(),
            dq: z(),
            ka: std::array::from_fn(|_| z()),
            kv: std::array::from_fn(|_| z()),
        }
    }
}
