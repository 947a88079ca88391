//! Controller A of seed 000 chapter 4: Stack-of-Tasks style hierarchical inverse kinematics
//! at velocity level, for a position-controlled robot (seed 000 §3.7, thesis L4097–L4190,
//! Table 4.1; task formulation §3.6, Eq 2.42–2.47 and the lexicographic QP Eq 2.58–2.59).
//!
//! Every task `i` imposes `ė_i = −K_i e_i` on its error, i.e. the velocity rows
//! `J_i v = ẋ*_i + K_i (x*_i ⊖ x_i)` (Eq 4.1–4.2, with the sign that converges), and the
//! tasks are solved in strict priority (Eq 4.4):
//!
//! ```text
//! g_k* = min_v ‖J_k v − ẋ_k‖²   s.t.  J_j v − ẋ_j = achieved residual of j,  j < k,
//!                                     max(−v̇_max, (q_min − q)/dt) ≤ v_joint ≤ min(v_max, (q_max − q)/dt)
//! ```
//!
//! by [`corps_qp::HierarchicalQp`] (a cascade of QPs, each holding the upper levels' achieved
//! task values — the lexicographic QP of Eq 2.58; the recursive null-space form of Eq 4.5
//! is its equality-only special case). Joint position limits (one step ahead,
//! `q_min ≤ q + dt·v ≤ q_max`) and the URDF velocity limits are hard bounds on v at every
//! level (Eq 2.55). The output is `v*` (nv, free-flyer included) and the joint position
//! target `q_des = q ⊕ dt·v*`, integrated once as the thesis does (§3.7, L4538–L4550), from
//! a configuration the caller chooses (the previous `q_des` for a position-servoed robot).
//!
//! Tasks live in a [`TaskStack`] of velocity-level tasks with integer priorities (several
//! tasks may share a priority; their rows are then weighted inside the level, and a weight
//! may ramp at run time without rebuilding the levels). [`InverseKinematics::standing_stack`] builds the
//! hierarchy of Table 4.1 with the IK gains of Table 4.3: 0 both feet (6D contact, LOCAL),
//! 1 CoM height, 2 CoM x/y, 3 waist orientation, 4 posture.
//!
//! Allocation: the levels and the QP workspaces are built when the stack's structure changes
//! (a task added, removed or moved); a tick with an unchanged structure fills the preallocated
//! levels in place and calls `HierarchicalQp::solve`, which does not allocate.

use crate::error::{ControlError, Result};
use crate::robot_state::RobotState;
use crate::stack::TaskStack;
use crate::tasks::velocity::{ComVelocityTask, FrameVelocityTask, PostureVelocityTask};
use crate::tasks::{Reference, Se3Reference, Task, TaskLevel};
use corps_model::spatial::Motion;
use corps_model::{integrate_to, JointKind, Model};
use corps_qp::{HierarchicalQp, Level};
use nalgebra::{DMatrix, DVector, Vector3, Vector6};

/// The controller's answer at one tick.
#[derive(Clone, Debug, PartialEq)]
pub struct IkOutput {
    /// Joint velocities v* (nv, free-flyer included).
    pub v: DVector<f64>,
    /// Position target `q_from ⊕ dt·v*` (nq).
    pub q_des: DVector<f64>,
}

/// Gains of the standing stack (1/s). Defaults: the IK column of seed 000 Table 4.3
/// (L4598–L4632): Kp_contacts 1000, Kp_comH 100, Kp_com 100, Kp_waist 300, Kp_posture 100.
#[derive(Clone, Debug, PartialEq)]
pub struct IkGains {
    pub contacts: f64,
    pub com_height: f64,
    pub com: f64,
    pub waist: f64,
    pub posture: f64,
}

impl Default for IkGains {
    fn default() -> Self {
        Self {
            contacts: 1000.0,
            com_height: 100.0,
            com: 100.0,
            waist: 300.0,
            posture: 100.0,
        }
    }
}

/// Frame names of the standing stack.
#[derive(Clone, Debug, PartialEq)]
pub struct StackFrames<'a> {
    pub left_foot: &'a str,
    pub right_foot: &'a str,
    pub waist: &'a str,
}

/// Where one entry's rows sit in the hierarchy.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Slot {
    level: usize,
    row: usize,
    dim: usize,
}

/// Hierarchical velocity-level inverse kinematics (see the module docs).
pub struct InverseKinematics {
    /// Control period (s): the integration step of `q_des` and the look-ahead of the
    /// position limits.
    pub dt: f64,
    /// Enforce the joint position and velocity limits as hard bounds.
    pub enforce_limits: bool,
    /// µ of the position bounds `µ(q_min − q)/dt ≤ v ≤ µ(q_max − q)/dt`: the share of the
    /// distance to a limit one tick may close (1: reach it in one tick; seed 001 Eq 6.15's
    /// OpenSoT bound scaling, below 1, approaches it geometrically).
    pub limit_scaling: f64,
    /// The velocity-level tasks.
    pub tasks: TaskStack,
    hqp: Option<HierarchicalQp>,
    slots: Vec<Slot>,
    /// The stack's structure the levels were built for.
    built_for: Option<u64>,
    /// For each velocity index: its configuration index when the joint has position limits.
    q_index: Vec<Option<usize>>,
    q_lo: DVector<f64>,
    q_hi: DVector<f64>,
    v_max: DVector<f64>,
    nv: usize,
    output: IkOutput,
}

impl InverseKinematics {
    /// An empty stack for `model` with control period `dt`.
    pub fn new(model: &Model, dt: f64) -> Result<Self> {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(ControlError::Config {
                name: "IK dt".into(),
                reason: format!("{dt} s is not positive and finite"),
            });
        }
        let mut q_index = vec![None; model.nv];
        for j in &model.joints {
            if matches!(
                j.kind,
                JointKind::Revolute { .. } | JointKind::Prismatic { .. }
            ) {
                q_index[j.idx_v] = Some(j.idx_q);
            }
        }
        let v_max = DVector::from_fn(model.nv, |k, _| {
            let l = model.velocity_limit[k];
            // A zero or missing URDF limit means "unlimited".
            if l > 0.0 && l.is_finite() {
                l
            } else {
                f64::INFINITY
            }
        });
        Ok(Self {
            dt,
            enforce_limits: true,
            limit_scaling: 1.0,
            tasks: TaskStack::new(TaskLevel::Velocity),
            hqp: None,
            slots: Vec::new(),
            built_for: None,
            q_index,
            q_lo: model.lower_position_limit.clone(),
            q_hi: model.upper_position_limit.clone(),
            v_max,
            nv: model.nv,
            output: IkOutput {
                v: DVector::zeros(model.nv),
                q_des: DVector::zeros(model.nq),
            },
        })
    }

    /// Seed 000 Table 4.1's hierarchy with references taken at `state`: 0 both feet
    /// ("contact_left", "contact_right", 6D LOCAL), 1 "com_height", 2 "com_xy",
    /// 3 "waist" (orientation), 4 "posture" (towards `q_posture`).
    pub fn standing_stack(
        model: &Model,
        state: &RobotState,
        dt: f64,
        frames: &StackFrames,
        gains: &IkGains,
        q_posture: &DVector<f64>,
    ) -> Result<Self> {
        let mut ik = Self::new(model, dt)?;
        let nv = model.nv;
        let frame_ref = |name: &str| -> Result<(usize, Se3Reference)> {
            let id = model.frame_id(name)?;
            Ok((
                id,
                Se3Reference {
                    placement: state.frame_placement(model, id)?,
                    velocity: Motion::zero(),
                    acceleration: Motion::zero(),
                },
            ))
        };
        for (name, frame) in [
            ("contact_left", frames.left_foot),
            ("contact_right", frames.right_foot),
        ] {
            let (id, reference) = frame_ref(frame)?;
            let task = FrameVelocityTask::new(
                model,
                id,
                Vector6::repeat(gains.contacts),
                [true; 6],
                reference,
            )?;
            ik.add_task(name, 0, 1.0, task)?;
        }
        let com = Reference::constant(DVector::from_column_slice(state.data.com.as_slice()));
        let height = ComVelocityTask::new(
            nv,
            Vector3::repeat(gains.com_height),
            [false, false, true],
            com.clone(),
        )?;
        ik.add_task("com_height", 1, 1.0, height)?;
        let xy = ComVelocityTask::new(nv, Vector3::repeat(gains.com), [true, true, false], com)?;
        ik.add_task("com_xy", 2, 1.0, xy)?;
        let (id, reference) = frame_ref(frames.waist)?;
        let waist = FrameVelocityTask::new(
            model,
            id,
            Vector6::repeat(gains.waist),
            [false, false, false, true, true, true],
            reference,
        )?;
        ik.add_task("waist", 3, 1.0, waist)?;
        let na = nv - if model.has_free_flyer() { 6 } else { 0 };
        let posture =
            PostureVelocityTask::new(model, DVector::repeat(na, gains.posture), q_posture.clone())?;
        ik.add_task("posture", 4, 1.0, posture)?;
        Ok(ik)
    }

    /// Keeps the position bounds `margin` (rad or m) inside every joint's limits (a joint
    /// servo's own error then stays within the limits); a joint whose range is narrower than
    /// twice the margin keeps its middle.
    pub fn set_limit_margin(&mut self, model: &Model, margin: f64) {
        let margin = if margin.is_finite() {
            margin.max(0.0)
        } else {
            0.0
        };
        for k in 0..self.q_lo.len() {
            let (lo, hi) = (model.lower_position_limit[k], model.upper_position_limit[k]);
            let m = margin.min(((hi - lo) * 0.5).max(0.0));
            self.q_lo[k] = lo + m;
            self.q_hi[k] = hi - m;
        }
    }

    /// Adds a task (the hierarchy is rebuilt at the next `compute`).
    pub fn add_task(
        &mut self,
        name: &str,
        priority: usize,
        weight: f64,
        task: impl Task,
    ) -> Result<()> {
        check_weight(name, weight)?;
        self.tasks.add(name, task, priority, weight)
    }

    /// Removes a task and returns it.
    pub fn remove_task(&mut self, name: &str) -> Result<Box<dyn Task>> {
        self.tasks.remove(name)
    }

    /// Moves a task to another priority (the hierarchy is rebuilt at the next `compute`).
    pub fn set_priority(&mut self, name: &str, priority: usize) -> Result<()> {
        self.tasks.set_priority(name, priority)
    }

    /// The task called `name` as its type `T`, to change its reference or gains.
    pub fn task_mut<T: Task>(&mut self, name: &str) -> Result<&mut T> {
        self.tasks
            .task_mut(name)
            .ok_or_else(|| ControlError::Config {
                name: format!("IK task {name}"),
                reason: format!("no task of type {} so named", std::any::type_name::<T>()),
            })
    }

    /// Number of priority levels of the current structure.
    pub fn levels(&self) -> usize {
        let mut p: Vec<usize> = self.tasks.entries().iter().map(|e| e.priority).collect();
        p.sort_unstable();
        p.dedup();
        p.len()
    }

    /// The output of the last successful `compute`.
    pub fn output(&self) -> &IkOutput {
        &self.output
    }

    fn structure_changed(&self) -> bool {
        self.hqp.is_none()
            || self.built_for != Some(self.tasks.structure())
            || self.slots.len() != self.tasks.entries().len()
            || (self.slots.iter().zip(self.tasks.entries())).any(|(s, e)| s.dim != e.task.dim())
    }

    /// Builds the levels and the QP workspaces for the current stack (allocates).
    fn rebuild(&mut self) -> Result<()> {
        let entries = self.tasks.entries();
        let mut priorities: Vec<usize> = entries.iter().map(|e| e.priority).collect();
        priorities.sort_unstable();
        priorities.dedup();
        let n = self.nv;
        let mut levels: Vec<Level> = priorities.iter().map(|_| Level::new(n)).collect();
        let mut rows = vec![0usize; priorities.len()];
        self.slots.clear();
        for e in entries {
            // The priorities were collected from the entries: the search succeeds.
            let level = priorities.partition_point(|p| *p < e.priority);
            let dim = e.task.dim();
            let lv = std::mem::replace(&mut levels[level], Level::new(n));
            levels[level] =
                lv.with_equality(&DMatrix::zeros(dim, n), &DVector::zeros(dim), e.weight);
            self.slots.push(Slot {
                level,
                row: rows[level],
                dim,
            });
            rows[level] += dim;
        }
        self.hqp = Some(HierarchicalQp::new(n, levels));
        self.built_for = Some(self.tasks.structure());
        Ok(())
    }

    /// Advances the stack's weight ramps to time `t` (call once per tick before `compute`).
    pub fn update_transitions(&mut self, t: f64) {
        self.tasks.update(t);
    }

    /// Solves the stack at `state` (the measured or estimated robot state, whose
    /// `RobotState::update` has run) and integrates `q_des = q_from ⊕ dt·v*`.
    /// The position limits are applied to `q_from + dt·v`.
    pub fn compute(
        &mut self,
        model: &Model,
        state: &RobotState,
        q_from: &[f64],
    ) -> Result<&IkOutput> {
        model.check_configuration(q_from)?;
        if q_from.iter().any(|x| !x.is_finite()) {
            return Err(ControlError::NonFinite("IK integration configuration"));
        }
        if state.q.iter().chain(state.v.iter()).any(|x| !x.is_finite()) {
            return Err(ControlError::NonFinite("robot state"));
        }
        if self.tasks.entries().is_empty() {
            return Err(ControlError::Config {
                name: "IK stack".into(),
                reason: "no task".into(),
            });
        }
        if self.structure_changed() {
            self.rebuild()?;
        }
        let Some(hqp) = self.hqp.as_mut() else {
            return Err(ControlError::Config {
                name: "IK stack".into(),
                reason: "not built".into(),
            });
        };
        for (e, slot) in self.tasks.entries_mut().iter_mut().zip(&self.slots) {
            let weight = e.weight;
            let rows = e.task.compute(model, state)?;
            if rows.a.ncols() != self.nv {
                return Err(ControlError::Config {
                    name: format!("IK task {}", e.name),
                    reason: format!(
                        "rows of {} columns, the model has nv = {}",
                        rows.a.ncols(),
                        self.nv
                    ),
                });
            }
            let lv = &mut hqp.levels_mut()[slot.level];
            lv.a.rows_mut(slot.row, slot.dim).copy_from(&rows.a);
            lv.b.rows_mut(slot.row, slot.dim).copy_from(&rows.b);
            lv.eq_weights.rows_mut(slot.row, slot.dim).fill(weight);
        }
        let dt = self.dt;
        for k in 0..self.nv {
            let (mut lo, mut hi) = if self.enforce_limits {
                (-self.v_max[k], self.v_max[k])
            } else {
                (f64::NEG_INFINITY, f64::INFINITY)
            };
            if let (true, Some(iq)) = (self.enforce_limits, self.q_index[k]) {
                let mu = self.limit_scaling;
                lo = lo.max(mu * (self.q_lo[iq] - q_from[iq]) / dt);
                hi = hi.min(mu * (self.q_hi[iq] - q_from[iq]) / dt);
                // Beyond a limit by more than one step at full speed: head back at full speed.
                if lo > hi {
                    if hi < 0.0 {
                        hi = lo;
                    } else {
                        lo = hi;
                    }
                }
            }
            hqp.lx[k] = lo;
            hqp.ux[k] = hi;
        }
        let v = hqp.solve().map_err(ControlError::Hqp)?;
        if v.iter().any(|x| !x.is_finite()) {
            return Err(ControlError::NonFinite("IK solution"));
        }
        self.output.v.copy_from(v);
        self.output.v.scale_mut(dt);
        integrate_to(
            model,
            q_from,
            self.output.v.as_slice(),
            self.output.q_des.as_mut_slice(),
        )?;
        self.output.v.copy_from(v);
        Ok(&self.output)
    }
}

fn check_weight(name: &str, w: f64) -> Result<()> {
    if w > 0.0 && w.is_finite() {
        Ok(())
    } else {
        Err(ControlError::Config {
            name: format!("IK task {name}"),
            reason: format!("weight {w} is not positive and finite"),
        })
    }
}
