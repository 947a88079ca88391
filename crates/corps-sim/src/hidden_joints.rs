//! A plant whose model has joints the controllers' model lacks (passive elastic joints, seed
//! 000 App. 4): commands are widened to the plant's model and readings and true state narrowed
//! to the controllers', by joint name. The hidden joints' positions never reach a reading, as
//! a real robot's unmeasured flexibility never reaches its encoders; the true state keeps the
//! bodies where the plant has them (every joint placement, the centre of mass).

use crate::error::{Result, SimError};
use corps_estimation::Readings;
use corps_loop::{Command, Plant, PlantError, Sensed, Truth};
use corps_model::Model;
use nalgebra::DVector;

/// Index maps between a rigid model and a plant model that adds joints to it.
#[derive(Clone, Debug, PartialEq)]
pub struct HiddenJoints {
    /// Rigid q index → plant q index.
    q_of: Vec<usize>,
    /// Rigid v index → plant v index.
    v_of: Vec<usize>,
    /// Rigid joint → plant joint.
    joint_of: Vec<usize>,
    /// Plant joint → the rigid joint of its nearest non-hidden ancestor (itself if it has one).
    rigid_joint: Vec<usize>,
    first: usize,
    plant_first: usize,
    plant_nq: usize,
    plant_nv: usize,
}

impl HiddenJoints {
    /// Matches every joint of `rigid` with the joint of the same name in `plant` (with as
    /// many q and v entries); the joints of `plant` left over are the hidden ones.
    pub fn new(rigid: &Model, plant: &Model) -> Result<Self> {
        let bad = |reason: String| SimError::Setting {
            name: "plant model".into(),
            reason,
        };
        if rigid.has_free_flyer() != plant.has_free_flyer() {
            return Err(bad("one model has a free-flyer, the other not".into()));
        }
        let mut q_of = vec![0; rigid.nq];
        let mut v_of = vec![0; rigid.nv];
        let mut joint_of = Vec::with_capacity(rigid.joints.len());
        for joint in &rigid.joints {
            let p = plant.joint_id(&joint.name).map_err(|_| {
                bad(format!(
                    "has no joint '{}' of the controllers' model",
                    joint.name
                ))
            })?;
            let pj = &plant.joints[p];
            if (pj.nq(), pj.nv()) != (joint.nq(), joint.nv()) {
                return Err(bad(format!("joint '{}' differs in size", joint.name)));
            }
            for k in 0..joint.nq() {
                q_of[joint.idx_q + k] = pj.idx_q + k;
            }
            for k in 0..joint.nv() {
                v_of[joint.idx_v + k] = pj.idx_v + k;
            }
            joint_of.push(p);
        }
        let mut rigid_joint = vec![0; plant.joints.len()];
        for (p, joint) in plant.joints.iter().enumerate() {
            rigid_joint[p] = match joint_of.iter().position(|&x| x == p) {
                Some(r) => r,
                None => joint.parent.map_or(0, |parent| rigid_joint[parent]),
            };
        }
        Ok(Self {
            q_of,
            v_of,
            joint_of,
            rigid_joint,
            first: rigid.first_actuated(),
            plant_first: plant.first_actuated(),
            plant_nq: plant.nq,
            plant_nv: plant.nv,
        })
    }

    /// The rigid model's nq.
    pub fn rigid_nq(&self) -> usize {
        self.q_of.len()
    }

    /// The plant configuration of rigid configuration `q`, the hidden joints at `hidden_q`'s
    /// values (a plant configuration, or None for zero).
    pub fn widen_q(&self, q: &[f64], hidden_q: Option<&[f64]>, out: &mut [f64]) {
        match hidden_q {
            Some(h) => out.copy_from_slice(h),
            None => out.iter_mut().for_each(|x| *x = 0.0),
        }
        for (i, &p) in self.q_of.iter().enumerate() {
            out[p] = q[i];
        }
    }

    /// The rigid configuration seen in plant configuration `q` (hidden joints dropped).
    pub fn narrow_q(&self, q: &[f64], out: &mut [f64]) {
        for (o, &p) in out.iter_mut().zip(&self.q_of) {
            *o = q[p];
        }
    }

    /// The rigid velocity seen in plant velocity `v`.
    pub fn narrow_v(&self, v: &[f64], out: &mut [f64]) {
        for (o, &p) in out.iter_mut().zip(&self.v_of) {
            *o = v[p];
        }
    }

    /// A plant configuration and velocity (as vectors) of a rigid state, hidden joints at rest.
    pub fn widen_state(&self, q: &[f64], v: &[f64]) -> (DVector<f64>, DVector<f64>) {
        let mut pq = DVector::zeros(self.plant_nq);
        let mut pv = DVector::zeros(self.plant_nv);
        self.widen_q(q, None, pq.as_mut_slice());
        self.widen_actuated(v, pv.as_mut_slice(), 0);
        (pq, pv)
    }

    /// Writes the actuated-sized (`offset` = first actuated index) or full-sized vector `x`
    /// of the rigid model into the plant-sized `out` (hidden entries zero).
    fn widen_actuated(&self, x: &[f64], out: &mut [f64], offset: usize) {
        out.iter_mut().for_each(|o| *o = 0.0);
        let plant_offset = if offset == 0 { 0 } else { self.plant_first };
        for (i, &p) in self.v_of.iter().enumerate().skip(offset) {
            out[p - plant_offset] = x[i - offset];
        }
    }

    /// An actuated-sized vector of the plant narrowed to the rigid model's.
    fn narrow_actuated(&self, x: &[f64], out: &mut [f64]) {
        for (i, &p) in self.v_of.iter().enumerate().skip(self.first) {
            out[i - self.first] = x[p - self.plant_first];
        }
    }

    /// The rigid model's servo gains for the plant (zero on the hidden joints, which their
    /// spring-dampers drive instead).
    pub fn widen_gains(&self, gains: &crate::ServoGains) -> crate::ServoGains {
        let widen = |x: &DVector<f64>| {
            let mut out = DVector::zeros(self.plant_nv - self.plant_first);
            self.widen_actuated(x.as_slice(), out.as_mut_slice(), self.first);
            out
        };
        crate::ServoGains {
            kp: widen(&gains.kp),
            kd: widen(&gains.kd),
            integral: gains.integral.as_ref().map(|i| crate::IntegralTerm {
                ki: widen(&i.ki),
                i_clamp: widen(&i.i_clamp),
                torque_clamp: widen(&i.torque_clamp),
            }),
        }
    }

    /// A command for the plant's sizes, empty of values (as [`Self::widen_command`] fills).
    pub fn plant_command(&self, like: &Command) -> Command {
        let na = self.plant_nv - self.plant_first;
        match like {
            Command::Torque(_) => Command::Torque(DVector::zeros(na)),
            Command::Velocity(_) => Command::Velocity(DVector::zeros(na)),
            Command::Position { .. } => Command::Position {
                q_ref: DVector::zeros(self.plant_nq),
                v_ref: DVector::zeros(na),
            },
        }
    }

    /// Writes the rigid model's command `cmd` into `out` (of [`Self::plant_command`]'s shape;
    /// re-shaped, allocating, if `cmd` is of another kind): hidden joints get zero, which
    /// their passive spring-dampers ignore.
    pub fn widen_command(&self, cmd: &Command, out: &mut Command) {
        let na = self.plant_nv - self.plant_first;
        let fits = match out {
            Command::Torque(x) | Command::Velocity(x) => x.len() == na,
            Command::Position { q_ref, v_ref } => q_ref.len() == self.plant_nq && v_ref.len() == na,
        };
        if !fits || std::mem::discriminant(cmd) != std::mem::discriminant(out) {
            *out = self.plant_command(cmd);
        }
        match (cmd, out) {
            (Command::Torque(a), Command::Torque(b))
            | (Command::Velocity(a), Command::Velocity(b)) => {
                self.widen_actuated(a.as_slice(), b.as_mut_slice(), self.first)
            }
            (
                Command::Position { q_ref, v_ref },
                Command::Position {
                    q_ref: pq,
                    v_ref: pv,
                },
            ) => {
                self.widen_q(q_ref.as_slice(), None, pq.as_mut_slice());
                self.widen_actuated(v_ref.as_slice(), pv.as_mut_slice(), self.first);
            }
            _ => {}
        }
    }

    /// Readings of the rigid model's sizes (as [`Self::narrow_readings`] fills).
    pub fn rigid_readings(&self, plant: &Readings) -> Readings {
        let na = self.v_of.len() - self.first;
        Readings {
            joint_positions: DVector::zeros(na),
            joint_velocities: DVector::zeros(na),
            joint_torques: DVector::zeros(na),
            contact_wrenches: vec![[0.0; 6]; self.joint_of.len()],
            ..plant.clone()
        }
    }

    /// The plant's readings as the rigid robot's sensors give them: the hidden joints have no
    /// encoder, and their bodies' contact wrenches are dropped (a passive joint's link is
    /// massless and has no shape to touch anything with).
    pub fn narrow_readings(&self, plant: &Readings, out: &mut Readings) {
        out.time = plant.time;
        self.narrow_actuated(
            plant.joint_positions.as_slice(),
            out.joint_positions.as_mut_slice(),
        );
        self.narrow_actuated(
            plant.joint_velocities.as_slice(),
            out.joint_velocities.as_mut_slice(),
        );
        self.narrow_actuated(
            plant.joint_torques.as_slice(),
            out.joint_torques.as_mut_slice(),
        );
        out.force_torque.copy_from_slice(&plant.force_torque);
        out.imu = plant.imu;
        out.base_pose = plant.base_pose;
        out.base_twist = plant.base_twist;
        for (r, &p) in self.joint_of.iter().enumerate() {
            out.contact_wrenches[r] = plant.contact_wrenches[p];
        }
    }

    /// The plant's true state for the rigid model's metrics.
    pub fn narrow_truth(&self, plant: &Truth, out: &mut Truth) {
        self.narrow_q(plant.q.as_slice(), out.q.as_mut_slice());
        self.narrow_v(plant.v.as_slice(), out.v.as_mut_slice());
        self.narrow_v(
            plant.applied_torques.as_slice(),
            out.applied_torques.as_mut_slice(),
        );
        out.com = plant.com;
        out.com_velocity = plant.com_velocity;
        for (r, &p) in self.joint_of.iter().enumerate() {
            out.joint_placements[r] = plant.joint_placements[p];
        }
        out.contacts.clear();
        for c in &plant.contacts {
            if out.contacts.len() < out.contacts.capacity() {
                let mut c = *c;
                c.joint = self.rigid_joint[c.joint];
                out.contacts.push(c);
            }
        }
        self.narrow_readings(&plant.readings, &mut out.readings);
    }
}

/// A plant with hidden joints seen through the rigid model: [`HiddenJoints`] around it.
pub struct WithHiddenJoints<P> {
    inner: P,
    map: HiddenJoints,
    sensed: Sensed,
    command: Command,
}

impl<P: Plant> WithHiddenJoints<P> {
    pub fn new(inner: P, map: HiddenJoints) -> Self {
        let sensed = inner.sensed();
        let command = Command::Torque(DVector::zeros(0));
        Self {
            inner,
            map,
            sensed,
            command,
        }
    }

    /// The plant inside.
    pub fn inner(&self) -> &P {
        &self.inner
    }

    pub fn into_inner(self) -> P {
        self.inner
    }

    pub fn map(&self) -> &HiddenJoints {
        &self.map
    }
}

impl<P: Plant> Plant for WithHiddenJoints<P> {
    fn sensed(&self) -> Sensed {
        let plant = self.inner.sensed();
        let readings = self.map.rigid_readings(&plant.readings);
        let truth = plant.truth.as_ref().map(|t| Truth {
            q: DVector::zeros(self.map.q_of.len()),
            v: DVector::zeros(self.map.v_of.len()),
            applied_torques: DVector::zeros(self.map.v_of.len()),
            com: t.com,
            com_velocity: t.com_velocity,
            joint_placements: vec![Default::default(); self.map.joint_of.len()],
            contacts: Vec::with_capacity(t.contacts.capacity()),
            readings: self.map.rigid_readings(&t.readings),
        });
        Sensed {
            time: plant.time,
            readings,
            truth,
        }
    }

    fn sense(&mut self, out: &mut Sensed) -> std::result::Result<(), PlantError> {
        self.inner.sense(&mut self.sensed)?;
        out.time = self.sensed.time;
        self.map
            .narrow_readings(&self.sensed.readings, &mut out.readings);
        Ok(())
    }

    fn complete(&mut self, out: &mut Sensed) -> std::result::Result<(), PlantError> {
        self.inner.complete(&mut self.sensed)?;
        if let (Some(plant), Some(rigid)) = (&self.sensed.truth, &mut out.truth) {
            self.map.narrow_truth(plant, rigid);
        }
        Ok(())
    }

    fn prepare(&mut self) {
        self.inner.prepare()
    }

    fn step(&mut self, command: &Command) -> std::result::Result<(), PlantError> {
        self.map.widen_command(command, &mut self.command);
        self.inner.step(&self.command)
    }
}
