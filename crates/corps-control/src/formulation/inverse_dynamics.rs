//! TSID's acceleration–force inverse-dynamics formulation (`InverseDynamicsFormulationAccForce`
//! solved as one weighted QP): variables `x = [q̈; f₁; …; f_k]`;
//! - equalities: the floating-base rows of the dynamics `M_u q̈ − Jc_uᵀ f = −h_u`, each
//!   contact's motion task `J q̈ = a_des − J̇ v`, and the rows of the stack's priority-0 tasks
//!   `A q̈ = b` (an equality has no weight: it holds until the task leaves the stack);
//! - inequalities: each contact's friction pyramid and normal-force bounds, and the actuation
//!   bounds `τ_min − h_a ≤ M_a q̈ − Jc_aᵀ f ≤ τ_max − h_a`;
//! - cost: Σ w‖A_k x − b_k‖² over the stack's priority-1 tasks (any [`crate::Task`] of acceleration
//!   level: CoM, posture, angular momentum, frames, ...) and the contact force
//!   regularizations and force tasks, plus 1e-8‖x‖² (TSID's Hessian regularization).
//!
//! Torques follow from the actuated rows: `τ = M_a q̈ + h_a − Jc_aᵀ f`.

use super::qp_terms::{
    add_force_terms, add_task_cost, check_actuation, copy_block, copy_block_neg_transposed,
    torque_tick, RowScratch,
};
use crate::contacts::Contact;
use crate::error::{ControlError, Result};
use crate::robot_state::RobotState;
use crate::stack::TaskStack;
use crate::tasks::{ContactForceTask, JointBoundsTask, TaskLevel};
use corps_model::Model;
use corps_qp::{ActiveSetSolver, QpProblem};
use nalgebra::DVector;

/// TSID's `DEFAULT_HESSIAN_REGULARIZATION`.
pub const HESSIAN_REGULARIZATION: f64 = 1e-8;

/// Slack of the passivity row (W): at rest (q̇_j = 0) the row reads `0 ≤ −Ḣ`, which rounding
/// of Ḣ ≈ 0 must not make infeasible.
pub const PASSIVITY_SLACK: f64 = 1e-9;

/// The controller's answer at one tick.
#[derive(Clone, Debug, PartialEq)]
pub struct IdOutput {
    /// Joint accelerations q̈ (nv).
    pub dv: DVector<f64>,
    /// Contact forces, 3 per contact point, in contact order.
    pub forces: DVector<f64>,
    /// Actuated joint torques (na).
    pub tau: DVector<f64>,
}

/// A contact whose normal-force bound ramps over time, so that adding or removing it does not
/// make the force jump: removal lowers `fmax` linearly from the current normal force to 0,
/// then drops the contact; addition raises `fmax` from 0 to its nominal value.
#[derive(Clone, Debug, PartialEq)]
struct Transition {
    contact: String,
    t0: f64,
    duration: f64,
    from: f64,
    to: f64,
    /// The contact's minimum normal force, restored when an addition ends (it is 0 during
    /// the ramp: a minimum above the ramping maximum would make the QP infeasible).
    fmin_end: f64,
    remove_at_end: bool,
}

/// The weighted inverse-dynamics controller.
pub struct InverseDynamics {
    /// The motion tasks: priority 0 equalities, priority 1 weighted costs.
    pub tasks: TaskStack,
    pub contacts: Vec<Contact>,
    /// Actuation bounds (na each), a hard inequality when set.
    pub actuation: Option<(DVector<f64>, DVector<f64>)>,
    /// Joint position / velocity / acceleration bounds, as bounds on q̈ when set.
    pub joint_bounds: Option<JointBoundsTask>,
    /// Contact-force tasks in the cost, with weights (each names its contact).
    pub contact_forces: Vec<(ContactForceTask, f64)>,
    /// Scale of every motion task's right side, contact motion rows included, and of the
    /// force tasks' wanted wrenches (βγ of an energy tank; 1 otherwise).
    pub reference_scale: f64,
    /// `Some(Ḣ)`: the passivity row `Ḣ ≤ −q̇_jᵀτ + PASSIVITY_SLACK` (W).
    pub passivity: Option<f64>,
    /// Set when the tasks and contacts were computed at this tick's state already (the energy
    /// tank's stage 1 does): the next `build` reads their rows instead; it clears the flag.
    pub(crate) rows_current: bool,
    first: usize,
    pub problem: QpProblem,
    solver: ActiveSetSolver,
    pub output: IdOutput,
    transitions: Vec<Transition>,
    scratch: RowScratch,
}

impl InverseDynamics {
    /// An empty formulation for `model` (add tasks and contacts, then call `compute`).
    pub fn new(model: &Model) -> Self {
        let first = if model.has_free_flyer() { 6 } else { 0 };
        let na = model.nv - first;
        Self {
            tasks: TaskStack::with_max_priority(TaskLevel::Acceleration, 1),
            contacts: Vec::new(),
            actuation: None,
            joint_bounds: None,
            contact_forces: Vec::new(),
            reference_scale: 1.0,
            passivity: None,
            rows_current: false,
            first,
            problem: QpProblem::new(model.nv, first, 0),
            solver: ActiveSetSolver::new(model.nv, first, 0),
            output: IdOutput {
                dv: DVector::zeros(model.nv),
                forces: DVector::zeros(0),
                tau: DVector::zeros(na),
            },
            transitions: Vec::new(),
            scratch: RowScratch::new(model.nv),
        }
    }

    /// Index of the contact named `name`.
    pub fn contact_index(&self, name: &str) -> Result<usize> {
        self.contacts
            .iter()
            .position(|c| c.name == name)
            .ok_or_else(|| ControlError::Config {
                name: format!("contact '{name}'"),
                reason: "no such active contact".into(),
            })
    }

    /// Offset of contact `k`'s force variables in `output.forces`.
    fn force_offset(&self, k: usize) -> usize {
        self.contacts[..k].iter().map(Contact::n_force).sum()
    }

    /// Total normal force of contact `k` in the last solution (N).
    pub fn normal_force(&self, k: usize) -> f64 {
        let c = &self.contacts[k];
        let (o, n) = (self.force_offset(k), c.n_force());
        match self.output.forces.as_slice().get(o..o + n) {
            Some(f) => c.normal_force(f),
            None => 0.0,
        }
    }

    /// Wrench of contact `k` in the last solution ([force; torque] about its frame origin,
    /// contact frame).
    pub fn contact_wrench(&self, k: usize) -> nalgebra::Vector6<f64> {
        let c = &self.contacts[k];
        let (o, n) = (self.force_offset(k), c.n_force());
        match self.output.forces.as_slice().get(o..o + n) {
            Some(f) => c.wrench(f),
            None => nalgebra::Vector6::zeros(),
        }
    }

    /// Starts removing contact `name` at time `t`: its force goes to zero over `duration` s,
    /// then the contact is dropped (TSID `removeRigidContact(name, transition)`).
    pub fn remove_contact(&mut self, name: &str, t: f64, duration: f64) -> Result<()> {
        let k = self.contact_index(name)?;
        let from = self.normal_force(k).max(self.contacts[k].fmin);
        self.contacts[k].fmin = 0.0;
        self.transitions.retain(|tr| tr.contact != name);
        self.transitions.push(Transition {
            contact: name.into(),
            t0: t,
            duration,
            from,
            to: 0.0,
            fmin_end: 0.0,
            remove_at_end: true,
        });
        Ok(())
    }

    /// Adds `contact` at time `t` with its normal-force bound raised from 0 to its `fmax`
    /// over `duration` s.
    pub fn add_contact(&mut self, mut contact: Contact, t: f64, duration: f64) {
        let to = contact.fmax;
        let fmin_end = contact.fmin;
        contact.fmax = 0.0;
        contact.fmin = 0.0;
        let name = contact.name.clone();
        self.contacts.push(contact);
        self.transitions.retain(|tr| tr.contact != name);
        self.transitions.push(Transition {
            contact: name,
            t0: t,
            duration,
            from: 0.0,
            to,
            fmin_end,
            remove_at_end: false,
        });
    }

    /// Advances contact transitions and task weight ramps to time `t` (call once per tick
    /// before `compute`).
    pub fn update_transitions(&mut self, t: f64) {
        self.tasks.update(t);
        let mut k_done = Vec::new();
        for (i, tr) in self.transitions.iter().enumerate() {
            let Some(k) = self.contacts.iter().position(|c| c.name == tr.contact) else {
                k_done.push(i);
                continue;
            };
            let s = if tr.duration > 0.0 {
                ((t - tr.t0) / tr.duration).clamp(0.0, 1.0)
            } else {
                1.0
            };
            self.contacts[k].fmax = tr.from + (tr.to - tr.from) * s;
            if s >= 1.0 {
                if tr.remove_at_end {
                    self.contacts.remove(k);
                } else {
                    self.contacts[k].fmin = tr.fmin_end;
                }
                k_done.push(i);
            }
        }
        for i in k_done.into_iter().rev() {
            self.transitions.remove(i);
        }
    }

    /// One control tick in torque mode: computes the model terms at (q, v), solves, and
    /// writes the joint torques (na) to `tau`. When the state is not finite or the QP fails,
    /// `tau` gets the safe command ([`crate::safe_torques`], damping `safe_damping`) and the
    /// reason is returned; the controller keeps running at the next tick.
    #[allow(clippy::too_many_arguments)]
    pub fn tick(
        &mut self,
        model: &Model,
        state: &mut RobotState,
        t: f64,
        q: &[f64],
        v: &[f64],
        safe_damping: f64,
        tau: &mut DVector<f64>,
    ) -> Option<crate::FallbackReason> {
        torque_tick(model, state, q, v, safe_damping, tau, |state, tau| {
            self.update_transitions(t);
            tau.copy_from(&self.compute(model, state)?.tau);
            Ok(())
        })
    }

    /// Problem sizes (variables, equalities, inequalities) for the current contacts.
    pub fn dims(&self, model: &Model) -> (usize, usize, usize) {
        let na = model.nv - self.first;
        let c = &self.contacts;
        let n_force: usize = c.iter().map(Contact::n_force).sum();
        let n_motion: usize = c.iter().map(Contact::n_motion).sum();
        let n_rows: usize = c.iter().map(Contact::n_rows).sum();
        let n_in = n_rows
            + if self.actuation.is_some() { na } else { 0 }
            + usize::from(self.passivity.is_some());
        let n_task_eq: usize = (self.tasks.entries().iter())
            .filter(|e| e.priority == 0)
            .map(|e| e.task.dim())
            .sum();
        (model.nv + n_force, self.first + n_motion + n_task_eq, n_in)
    }

    /// Builds the QP at state `s` into `self.problem` (resizing only when contacts or the
    /// stack's equalities change).
    pub fn build(&mut self, model: &Model, s: &RobotState) -> Result<()> {
        if let Some(e) = self.tasks.entries().iter().find(|e| e.priority > 1) {
            return Err(ControlError::Config {
                name: format!("task '{}'", e.name),
                reason: format!(
                    "priority {}: the weighted inverse dynamics has two levels, 0 \
                     (equalities) and 1 (costs)",
                    e.priority
                ),
            });
        }
        if let Some(c) = self.contacts.iter().find(|c| c.soft.is_some()) {
            return Err(ControlError::Config {
                name: format!("contact '{}'", c.name),
                reason: "a soft contact (motion rows in the cost) needs the [τ; f] formulation;                          TSID's inverse dynamics holds contacts as equalities"
                    .into(),
            });
        }
        let na = model.nv - self.first;
        check_actuation(&self.actuation, na)?;
        let (n, n_eq, n_in) = self.dims(model);
        if self.problem.dims() != (n, n_eq, n_in) {
            self.problem = QpProblem::new(n, n_eq, n_in);
            self.solver.resize(n, n_eq, n_in);
            self.output.forces = DVector::zeros(n - model.nv);
        }
        let nv = model.nv;
        let first = self.first;
        let p = &mut self.problem;
        // Contiguous fills (DMatrix::fill walks nalgebra's strided iterator, 10× slower here).
        for buf in [
            p.h.as_mut_slice(),
            p.g.as_mut_slice(),
            p.a.as_mut_slice(),
            p.b.as_mut_slice(),
            p.c.as_mut_slice(),
        ] {
            buf.fill(0.0);
        }
        let m = &s.data.m;
        let h = &s.data.nle;
        // Contacts first: their Jacobians enter the dynamics rows.
        let reuse = std::mem::take(&mut self.rows_current);
        if !reuse {
            for contact in &mut self.contacts {
                contact.compute(model, s)?;
            }
        }
        // Floating-base dynamics rows: [M_u  −Jc_uᵀ] x = −h_u.
        copy_block(&mut p.a, (0, 0), m, (0, 0), (first, nv));
        let mut col = nv;
        for contact in &self.contacts {
            let nf = contact.n_force();
            copy_block_neg_transposed(&mut p.a, (0, col), &contact.jc, (0, 0), (first, nf));
            col += nf;
        }
        for r in 0..first {
            p.b[r] = -h[r];
        }
        // Contact motion rows, friction rows and force regularization.
        let (mut col, mut r_eq, mut r_in) = (nv, first, 0);
        for contact in &self.contacts {
            let rows = &contact.motion_rows();
            let nm = contact.n_motion();
            copy_block(&mut p.a, (r_eq, 0), &rows.a, (0, 0), (nm, nv));
            p.b.rows_mut(r_eq, nm).copy_from(&rows.b.rows(0, nm));
            if self.reference_scale != 1.0 {
                p.b.rows_mut(r_eq, nm).scale_mut(self.reference_scale);
            }
            let scale = self.reference_scale;
            add_force_terms(p, contact, &self.contact_forces, r_in, col, scale);
            col += contact.n_force();
            r_eq += nm;
            r_in += contact.n_rows();
        }
        // The stack's equalities.
        for e in self.tasks.entries_mut() {
            if e.priority != 0 {
                continue;
            }
            let rows = match reuse {
                true if e.task.last_rows().is_some() => e.task.last_rows(),
                _ => None,
            };
            let rows = match rows {
                Some(rows) => rows,
                None => e.task.compute(model, s)?,
            };
            let m = rows.rows();
            copy_block(&mut p.a, (r_eq, 0), &rows.a, (0, 0), (m, nv));
            p.b.rows_mut(r_eq, m).copy_from(&rows.b);
            if self.reference_scale != 1.0 {
                p.b.rows_mut(r_eq, m).scale_mut(self.reference_scale);
            }
            r_eq += m;
        }
        // Actuation bounds.
        if let Some((lower, upper)) = &self.actuation {
            let r0 = r_in;
            let na = nv - first;
            // [M_a  −Jc_aᵀ] x within [τ_min − h_a, τ_max − h_a].
            copy_block(&mut p.c, (r0, 0), m, (first, 0), (na, nv));
            let mut col = nv;
            for contact in &self.contacts {
                let nf = contact.n_force();
                copy_block_neg_transposed(&mut p.c, (r0, col), &contact.jc, (0, first), (na, nf));
                col += nf;
            }
            for k in 0..na {
                p.l[r0 + k] = lower[k] - h[first + k];
                p.u[r0 + k] = upper[k] - h[first + k];
            }
            r_in += na;
        }
        // Passivity: q̇_jᵀ [M_a q̈ − Jc_aᵀ f] ≤ −Ḣ − q̇_jᵀ h_a.
        if let Some(h_dot) = self.passivity {
            let v = &s.v;
            let mut bound = -h_dot + PASSIVITY_SLACK;
            for k in first..nv {
                bound -= v[k] * h[k];
            }
            for c in 0..nv {
                let column = &m.as_slice()[c * nv..(c + 1) * nv];
                p.c[(r_in, c)] = (first..nv).map(|k| v[k] * column[k]).sum();
            }
            let mut col = nv;
            for contact in &self.contacts {
                for j in 0..contact.n_force() {
                    p.c[(r_in, col + j)] =
                        -(first..nv).map(|k| v[k] * contact.jc[(j, k)]).sum::<f64>();
                }
                col += contact.n_force();
            }
            p.l[r_in] = f64::NEG_INFINITY;
            p.u[r_in] = bound;
        }
        // Joint bounds on q̈ (the free-flyer and the forces stay free).
        p.lx.fill(f64::NEG_INFINITY);
        p.ux.fill(f64::INFINITY);
        if let Some(bounds) = &mut self.joint_bounds {
            bounds.compute(s);
            for k in 0..bounds.lower.len() {
                p.lx[first + k] = bounds.lower[k];
                p.ux[first + k] = bounds.upper[k];
            }
        }
        // Cost terms on q̈, in the stack's order.
        let row = &mut self.scratch;
        for e in self.tasks.entries_mut() {
            if e.priority == 1 {
                let rows = match reuse {
                    true if e.task.last_rows().is_some() => e.task.last_rows(),
                    _ => None,
                };
                let rows = match rows {
                    Some(rows) => rows,
                    None => e.task.compute(model, s)?,
                };
                add_task_cost(
                    &mut p.h,
                    &mut p.g,
                    rows,
                    e.weight,
                    self.reference_scale,
                    row,
                );
            }
        }
        for i in 0..n {
            p.h[(i, i)] += HESSIAN_REGULARIZATION;
        }
        Ok(())
    }

    /// Builds and solves the QP; on success fills `self.output` (q̈, forces, τ).
    pub fn compute(&mut self, model: &Model, s: &RobotState) -> Result<&IdOutput> {
        self.build(model, s)?;
        let sol = self.solver.solve(&self.problem).map_err(ControlError::Qp)?;
        let nv = model.nv;
        self.output.dv.copy_from(&sol.x.rows(0, nv));
        let nf = self.output.forces.len();
        self.output.forces.copy_from(&sol.x.rows(nv, nf));
        // τ = M_a q̈ + h_a − Jc_aᵀ f; M_a q̈ column by column (contiguous in M).
        let (m, h) = (&s.data.m, &s.data.nle);
        let first = self.first;
        let tau = self.output.tau.as_mut_slice();
        tau.copy_from_slice(&h.as_slice()[first..nv]);
        for (column, &dv) in m.as_slice().chunks_exact(nv).zip(self.output.dv.iter()) {
            for (t, mc) in tau.iter_mut().zip(&column[first..]) {
                *t += mc * dv;
            }
        }
        for k in 0..nv - self.first {
            let r = self.first + k;
            let mut t = self.output.tau[k];
            let mut o = 0;
            for contact in &self.contacts {
                for j in 0..contact.n_force() {
                    t -= contact.jc[(j, r)] * self.output.forces[o + j];
                }
                o += contact.n_force();
            }
            self.output.tau[k] = t;
        }
        Ok(&self.output)
    }
}
