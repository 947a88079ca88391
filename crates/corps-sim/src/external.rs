//! A plant outside corps-sim (another physics engine, a plant written in Python) that reports
//! only its true state; corps reads its sensors from that state with the same sensor model
//! and noise as the simulator's, so that the controller and the estimator see the same kind
//! of readings whatever computes the physics.
//!
//! The sensors need the bodies' accelerations (the IMU, an F/T sensor's inertial part): they
//! come from ABA at the reported state with the reported contact forces and the pushes
//! active, `q̈ = ABA(q, v, τ, f_c + f_push)`, which is what the plant's own physics integrates
//! up to its contact model.

use crate::{PlacedPush, Push, Sensors, ServoGains};
use corps_loop::{Command, ContactForce, Plant, PlantError, Sensed, Truth};
use corps_model::spatial::Force;
use corps_model::{aba_with_external_forces, com_at_placements, Data, Model};
use nalgebra::{DVector, Vector3};
use std::sync::Arc;

/// How far from 1 a reported quaternion's norm may be.
const UNIT_QUATERNION: f64 = 1e-6;

/// Contact points reserved in the truth (more are accepted, at the cost of an allocation).
const CONTACT_CAPACITY: usize = 256;

/// The true state a [`StatePlant`] reports.
#[derive(Clone, Debug, PartialEq)]
pub struct PlantState {
    /// Plant time (s).
    pub time: f64,
    /// Configuration (size nq, Pinocchio's convention).
    pub q: DVector<f64>,
    /// Velocity (size nv).
    pub v: DVector<f64>,
    /// Joint torques applied over the last period (size nv; the free-flyer's entries zero).
    pub applied_torques: DVector<f64>,
    /// Contact forces at points, world frame, each on the body of a joint of the model.
    pub contacts: Vec<ContactForce>,
}

impl PlantState {
    /// A zero state sized for `model`.
    pub fn zeros(model: &Model) -> Self {
        Self {
            time: 0.0,
            q: corps_model::neutral(model),
            v: DVector::zeros(model.nv),
            applied_torques: DVector::zeros(model.nv),
            contacts: Vec::new(),
        }
    }
}

/// A plant that computes its own physics and reports its true state.
pub trait StatePlant: Send {
    /// Starts from configuration `q` and velocity `v` at time `t`; each [`StatePlant::step`]
    /// lasts `dt` seconds.
    fn reset(&mut self, q: &[f64], v: &[f64], t: f64, dt: f64) -> Result<(), PlantError>;
    /// Applies `command` for one control period.
    fn step(&mut self, command: &Command) -> Result<(), PlantError>;
    /// Writes the current true state into `out` (sized by [`PlantState::zeros`]).
    fn state(&mut self, out: &mut PlantState) -> Result<(), PlantError>;
    /// The joint servo gains position and velocity commands act through (corps' simulator's
    /// PD law, τ = kp (q_ref − q) + kd (v_ref − v), clamped at the effort limits). Given once,
    /// after [`StatePlant::reset`]; a plant that takes torque commands only may ignore them.
    fn servo_gains(&mut self, _gains: &ServoGains) -> Result<(), PlantError> {
        Ok(())
    }
    /// Schedules `push` (times on the plant's clock). A plant that cannot push the robot
    /// refuses it, and a scenario with pushes does not run on it.
    fn push(&mut self, push: &Push) -> Result<(), PlantError> {
        Err(PlantError::Failed(format!(
            "the scenario pushes '{}' and this plant takes no pushes",
            push.frame
        )))
    }
}

impl<P: StatePlant + ?Sized> StatePlant for Box<P> {
    fn reset(&mut self, q: &[f64], v: &[f64], t: f64, dt: f64) -> Result<(), PlantError> {
        (**self).reset(q, v, t, dt)
    }
    fn step(&mut self, command: &Command) -> Result<(), PlantError> {
        (**self).step(command)
    }
    fn state(&mut self, out: &mut PlantState) -> Result<(), PlantError> {
        (**self).state(out)
    }
    fn push(&mut self, push: &Push) -> Result<(), PlantError> {
        (**self).push(push)
    }
    fn servo_gains(&mut self, gains: &ServoGains) -> Result<(), PlantError> {
        (**self).servo_gains(gains)
    }
}

/// A [`StatePlant`] with corps' sensors on it: a loop [`Plant`].
pub struct ExternalPlant<P: StatePlant> {
    plant: P,
    model: Arc<Model>,
    data: Data,
    sensors: Sensors,
    state: PlantState,
    /// Contact wrench on each joint's body (world, about the origin): what F/T sensors read.
    wrenches: Vec<Force>,
    /// The pushes given to the plant, with the joint and placement of their frame: they act
    /// in the accelerations the IMU and the F/T sensors' inertial part read.
    pushes: Vec<PlacedPush>,
    /// The state and the sensors are read since the last step.
    fresh: bool,
    /// Plant time of the last state read: a plant's clock never goes back.
    last_time: f64,
}

impl<P: StatePlant> ExternalPlant<P> {
    /// `plant` read through `sensors`, started at (`q`, `v`, `t`) with control period `dt`,
    /// and given the servo `gains` and `pushes` (as [`crate::Simulator::pushes`] holds them).
    pub fn new(
        mut plant: P,
        model: Arc<Model>,
        sensors: Sensors,
        (q, v, t): (&[f64], &[f64], f64),
        dt: f64,
        gains: &ServoGains,
        pushes: &[PlacedPush],
    ) -> Result<Self, PlantError> {
        plant.reset(q, v, t, dt)?;
        plant.servo_gains(gains)?;
        for (push, _, _) in pushes {
            plant.push(push)?;
        }
        Ok(Self {
            pushes: pushes.to_vec(),
            data: Data::new(&model),
            state: PlantState::zeros(&model),
            wrenches: vec![Force::zero(); model.njoints()],
            fresh: false,
            last_time: f64::NEG_INFINITY,
            plant,
            model,
            sensors,
        })
    }

    /// The state last reported (after the last step, once a step succeeded).
    pub fn last_state(&self) -> &PlantState {
        &self.state
    }

    /// Reads the plant's state, checks it and updates the sensors.
    fn read(&mut self) -> Result<(), PlantError> {
        self.plant.state(&mut self.state)?;
        let (model, s) = (&*self.model, &self.state);
        let bad = |what: &str| PlantError::Failed(format!("the plant's state: {what}"));
        if s.q.len() != model.nq || s.v.len() != model.nv || s.applied_torques.len() != model.nv {
            return Err(bad(&format!(
                "q, v, torques of sizes {}, {}, {} (the model has nq = {}, nv = {})",
                s.q.len(),
                s.v.len(),
                s.applied_torques.len(),
                model.nq,
                model.nv
            )));
        }
        let finite = |x: &DVector<f64>| x.iter().all(|y| y.is_finite());
        let contacts_finite = (s.contacts.iter()).all(|c| {
            c.force
                .iter()
                .chain(c.position.iter())
                .all(|x| x.is_finite())
        });
        if !(s.time.is_finite() && finite(&s.q) && finite(&s.v) && contacts_finite) {
            return Err(PlantError::Diverged {
                t: s.time,
                reason: "the plant reported a non-finite state".into(),
            });
        }
        if s.time < self.last_time {
            return Err(bad(&format!(
                "time went back from {:.4} s to {:.4} s",
                self.last_time, s.time
            )));
        }
        for j in &model.joints {
            if j.kind == corps_model::JointKind::FreeFlyer {
                let norm = s.q.rows(j.idx_q + 3, 4).norm();
                if (norm - 1.0).abs() > UNIT_QUATERNION {
                    return Err(bad(&format!(
                        "the base quaternion has norm {norm:.9} (a unit quaternion is needed)"
                    )));
                }
            }
        }
        self.wrenches.fill(Force::zero());
        for c in &s.contacts {
            let Some(w) = self.wrenches.get_mut(c.joint) else {
                return Err(bad(&format!(
                    "a contact on joint {} (the model has {})",
                    c.joint,
                    model.njoints()
                )));
            };
            *w += Force::new(c.force, c.position.cross(&c.force));
        }
        let (wrenches, pushes, time) = (&self.wrenches, &self.pushes, s.time);
        let (q, v, tau) = (s.q.as_slice(), s.v.as_slice(), s.applied_torques.as_slice());
        aba_with_external_forces(model, &mut self.data, q, v, tau, |o_m_i, _, f| {
            f.copy_from_slice(wrenches);
            for (push, joint, placement) in pushes {
                if push.active(time) {
                    f[*joint] += push.world_wrench(&o_m_i[*joint], placement);
                }
            }
        })
        .map_err(|e| bad(&e.to_string()))?;
        let input = crate::SensorInput {
            time: s.time,
            q,
            v,
            applied_torques: tau,
            data: &self.data,
            body_wrenches: wrenches,
        };
        self.sensors.update_from(model, &input);
        self.fresh = true;
        self.last_time = s.time;
        Ok(())
    }
}

impl<P: StatePlant> Plant for ExternalPlant<P> {
    fn sensed(&self) -> Sensed {
        let readings = self.sensors.measured().clone();
        let model = &*self.model;
        Sensed {
            time: self.state.time,
            truth: Some(Truth {
                q: corps_model::neutral(model),
                v: DVector::zeros(model.nv),
                applied_torques: DVector::zeros(model.nv),
                com: Vector3::zeros(),
                com_velocity: Vector3::zeros(),
                joint_placements: self.data.o_m_i.clone(),
                contacts: Vec::with_capacity(CONTACT_CAPACITY),
                readings: readings.clone(),
            }),
            readings,
        }
    }

    fn sense(&mut self, out: &mut Sensed) -> Result<(), PlantError> {
        if !self.fresh {
            self.read()?;
        }
        let s = &self.state;
        out.time = s.time;
        out.readings.copy_from(self.sensors.measured());
        if let Some(truth) = &mut out.truth {
            truth.readings.copy_from(self.sensors.truth());
            truth.q.copy_from(&s.q);
            truth.v.copy_from(&s.v);
            truth.applied_torques.copy_from(&s.applied_torques);
            (truth.com, truth.com_velocity) = com_at_placements(&self.model, &self.data);
            truth.joint_placements.copy_from_slice(&self.data.o_m_i);
            truth.contacts.clear();
            truth.contacts.extend_from_slice(&s.contacts);
        }
        Ok(())
    }

    /// Steps the plant and reads its new state at once, so that a state that blew up ends
    /// the run as diverged.
    fn step(&mut self, command: &Command) -> Result<(), PlantError> {
        self.fresh = false;
        self.plant.step(command)?;
        self.read()
    }
}
