//! Inverse dynamics on the torques and contact forces, u = [τ; f] (seed 001 §2.6, the
//! decision variable of its stack of tasks, Eq 2.40–2.45): the joint accelerations are a
//! function of u through the dynamics, ν̇(u) = M⁻¹(Sᵀτ + J_cᵀf − h) = G u + d, so that a task
//! `A ν̇ = b` becomes the rows `(A G) u = b − A d`:
//! - equalities: each contact's motion rows and the stack's priority-0 tasks (no weight: an
//!   equality holds until its task leaves the stack); a contact with a `soft` weight puts
//!   its motion rows in the cost instead (seed 001's stance-foot task);
//! - inequalities: each contact's friction pyramid and normal-force bounds; torque bounds as
//!   bounds on τ;
//! - cost: Σ w‖A G u − (b − A d)‖² over the priority-1 tasks, the contacts' force
//!   regularizations and force tasks, and w_τ‖τ‖² (seed 001's torque regularization, Table
//!   B.3 / soft-tasks #1: w_τ = 1e-4), plus 1e-8‖f‖².
//!
//! With the same tasks it has the optimum of [`super::InverseDynamics`] up to their
//! regularizations (`tests/torque_force.rs` compares them); it is the form seed 001's
//! controllers take, and the one where a torque cost or a torque-rate bound is a plain row.

use super::qp_terms::{
    add_force_terms, add_task_cost, check_actuation, copy_block, torque_tick, RowScratch,
};
use super::HESSIAN_REGULARIZATION;
use crate::contacts::Contact;
use crate::error::{ControlError, Result};
use crate::robot_state::RobotState;
use crate::stack::TaskStack;
use crate::tasks::{ContactForceTask, TaskLevel, TaskRows};
use crate::FallbackReason;
use corps_model::{compute_minverse, Data, Model};
use corps_qp::{ActiveSetSolver, QpProblem};
use nalgebra::{DMatrix, DVector};

/// The answer of one tick.
#[derive(Clone, Debug, PartialEq)]
pub struct TorqueForceOutput {
    /// Actuated joint torques (na).
    pub tau: DVector<f64>,
    /// Contact forces in contact order: 3 per contact point, or a contact's 6-D wrench.
    pub forces: DVector<f64>,
    /// The joint accelerations they give, ν̇ = G u + d (nv).
    pub dv: DVector<f64>,
}

/// The [τ; f] formulation (see the module docs).
pub struct TorqueForce {
    /// The motion tasks (acceleration level): priority 0 equalities, 1 costs.
    pub tasks: TaskStack,
    pub contacts: Vec<Contact>,
    /// Contact-force tasks in the cost, with weights (each names its contact).
    pub contact_forces: Vec<(ContactForceTask, f64)>,
    /// w_τ of the torque regularization w_τ‖τ‖².
    pub torque_weight: f64,
    /// τ_min ≤ τ ≤ τ_max (na each), when set.
    pub actuation: Option<(DVector<f64>, DVector<f64>)>,
    /// The torque-rate bound of seed 001's Eq 2.40d / 2.43c, `|τ − τ₋₁| ≤ τ̇_max t_s`: the
    /// largest change of each torque from the last tick's command (N·m), when set.
    pub torque_step: Option<f64>,
    /// The last tick's command, for the torque-rate bound (None before the first tick).
    last_tau: Option<DVector<f64>>,
    first: usize,
    /// Workspace of the M⁻¹ recursion.
    minv_data: Data,
    /// G = M⁻¹[Sᵀ J_cᵀ] (nv × n) and d = −M⁻¹h.
    map: DMatrix<f64>,
    drift: DVector<f64>,
    /// A task's rows mapped to u, one buffer per row count met so far.
    mapped: Vec<TaskRows>,
    /// The non-zero columns of a task's rows (nv entries).
    used: Vec<usize>,
    pub problem: QpProblem,
    solver: ActiveSetSolver,
    pub output: TorqueForceOutput,
    scratch: RowScratch,
}

impl TorqueForce {
    /// An empty formulation for `model` (add tasks and contacts, then call `compute`).
    pub fn new(model: &Model) -> Self {
        let first = model.first_actuated();
        let na = model.nv - first;
        Self {
            tasks: TaskStack::with_max_priority(TaskLevel::Acceleration, 1),
            contacts: Vec::new(),
            contact_forces: Vec::new(),
            torque_weight: 1e-4,
            actuation: None,
            torque_step: None,
            last_tau: None,
            first,
            minv_data: Data::new(model),
            map: DMatrix::zeros(model.nv, na),
            drift: DVector::zeros(model.nv),
            mapped: Vec::new(),
            used: vec![0; model.nv],
            problem: QpProblem::new(na, 0, 0),
            solver: ActiveSetSolver::new(na, 0, 0),
            output: TorqueForceOutput {
                tau: DVector::zeros(na),
                forces: DVector::zeros(0),
                dv: DVector::zeros(model.nv),
            },
            scratch: RowScratch::new(na),
        }
    }

    /// Problem sizes (variables, equalities, inequalities).
    pub fn dims(&self, model: &Model) -> (usize, usize, usize) {
        let na = model.nv - self.first;
        let c = &self.contacts;
        let n_force: usize = c.iter().map(Contact::n_force).sum();
        let n_motion: usize = (c.iter().filter(|c| c.soft.is_none()))
            .map(Contact::n_motion)
            .sum();
        let n_rows: usize = c.iter().map(Contact::n_rows).sum();
        let n_task_eq: usize = (self.tasks.entries().iter())
            .filter(|e| e.priority == 0)
            .map(|e| e.task.dim())
            .sum();
        (na + n_force, n_motion + n_task_eq, n_rows)
    }

    /// Builds the QP at state `s` into `self.problem`.
    pub fn build(&mut self, model: &Model, s: &RobotState) -> Result<()> {
        if let Some(e) = self.tasks.entries().iter().find(|e| e.priority > 1) {
            return Err(ControlError::Config {
                name: format!("task '{}'", e.name),
                reason: format!(
                    "priority {}: the [τ; f] formulation has two levels, 0 (equalities) and 1 \
                     (costs)",
                    e.priority
                ),
            });
        }
        if !(self.torque_weight >= 0.0 && self.torque_weight.is_finite()) {
            return Err(ControlError::Config {
                name: "torque_weight".into(),
                reason: format!("must be finite and ≥ 0, got {}", self.torque_weight),
            });
        }
        if let Some(c) = (self.contacts.iter()).find(|c| c.soft.is_some() && c.n_motion() < 6) {
            return Err(ControlError::Config {
                name: format!("contact '{}'", c.name),
                reason: "a point contact cannot be soft (its rows would hold its orientation)"
                    .into(),
            });
        }
        let (n, n_eq, n_in) = self.dims(model);
        let (nv, first) = (model.nv, self.first);
        let na = nv - first;
        check_actuation(&self.actuation, na)?;
        if self.problem.dims() != (n, n_eq, n_in) {
            self.problem = QpProblem::new(n, n_eq, n_in);
            self.solver.resize(n, n_eq, n_in);
            self.output.forces = DVector::zeros(n - na);
            self.map = DMatrix::zeros(nv, n);
            self.scratch = RowScratch::new(n);
            self.mapped.clear();
        }
        for contact in &mut self.contacts {
            contact.compute(model, s)?;
        }
        // G = M⁻¹[Sᵀ J_cᵀ], d = −M⁻¹h, with M⁻¹ by the O(n²) recursion: the torque columns
        // are columns of M⁻¹, the force columns M⁻¹ J_cᵀ.
        let minv = compute_minverse(model, &mut self.minv_data, s.q.as_slice())?;
        let (mv, nvs) = (minv.as_slice(), nv);
        for c in 0..na {
            let src = &mv[(first + c) * nvs..(first + c + 1) * nvs];
            self.map.column_mut(c).copy_from_slice(src);
        }
        let mut c = na;
        let map = self.map.as_mut_slice();
        for contact in &self.contacts {
            for j in 0..contact.n_force() {
                let out = &mut map[c * nvs..(c + 1) * nvs];
                out.fill(0.0);
                for i in 0..nvs {
                    let w = contact.jc[(j, i)];
                    if w != 0.0 {
                        let col = &mv[i * nvs..(i + 1) * nvs];
                        for (o, m) in out.iter_mut().zip(col) {
                            *o += w * m;
                        }
                    }
                }
                c += 1;
            }
        }
        self.drift.gemv(-1.0, minv, &s.data.nle, 0.0);

        for buf in [
            self.problem.h.as_mut_slice(),
            self.problem.g.as_mut_slice(),
            self.problem.a.as_mut_slice(),
            self.problem.b.as_mut_slice(),
            self.problem.c.as_mut_slice(),
        ] {
            buf.fill(0.0);
        }
        // Contacts: motion rows (equalities), friction rows, force costs.
        let (mut col, mut r_eq, mut r_in) = (na, 0, 0);
        for contact in &self.contacts {
            let m = contact.n_motion();
            let i = map_rows(
                &self.map,
                &self.drift,
                &mut self.mapped,
                contact.motion_rows(),
                &mut self.used,
            );
            let p = &mut self.problem;
            if let Some(weight) = contact.soft {
                let rows = &self.mapped[i];
                add_task_cost(&mut p.h, &mut p.g, rows, weight, 1.0, &mut self.scratch);
            } else {
                copy_block(&mut p.a, (r_eq, 0), &self.mapped[i].a, (0, 0), (m, n));
                p.b.rows_mut(r_eq, m)
                    .copy_from(&self.mapped[i].b.rows(0, m));
                r_eq += m;
            }
            add_force_terms(p, contact, &self.contact_forces, r_in, col, 1.0);
            col += contact.n_force();
            r_in += contact.n_rows();
        }
        // The stack: equalities, then costs, in its order.
        for entry in self.tasks.entries_mut() {
            let (priority, weight) = (entry.priority, entry.weight);
            let rows = entry.task.compute(model, s)?;
            let i = map_rows(
                &self.map,
                &self.drift,
                &mut self.mapped,
                rows,
                &mut self.used,
            );
            let (mapped, p) = (&self.mapped[i], &mut self.problem);
            if priority == 0 {
                let m = mapped.rows();
                copy_block(&mut p.a, (r_eq, 0), &mapped.a, (0, 0), (m, n));
                p.b.rows_mut(r_eq, m).copy_from(&mapped.b);
                r_eq += m;
            } else {
                add_task_cost(&mut p.h, &mut p.g, mapped, weight, 1.0, &mut self.scratch);
            }
        }
        let p = &mut self.problem;
        for k in 0..na {
            p.h[(k, k)] += self.torque_weight;
        }
        for k in na..n {
            p.h[(k, k)] += HESSIAN_REGULARIZATION;
        }
        p.lx.fill(f64::NEG_INFINITY);
        p.ux.fill(f64::INFINITY);
        if let Some((lower, upper)) = &self.actuation {
            p.lx.rows_mut(0, na).copy_from(lower);
            p.ux.rows_mut(0, na).copy_from(upper);
        }
        if let (Some(step), Some(last)) = (self.torque_step, &self.last_tau) {
            if !(step > 0.0 && step.is_finite()) {
                return Err(ControlError::Config {
                    name: "torque_step".into(),
                    reason: format!("must be positive and finite, got {step}"),
                });
            }
            for k in 0..na {
                // Within the rate bound and the actuation bounds; a last command outside the
                // latter (a safe command) is moved towards them at the rate.
                let (a, b) = (last[k] - step, last[k] + step);
                let (mut lo, mut hi) = (a.max(p.lx[k]), b.min(p.ux[k]));
                if lo > hi {
                    (lo, hi) = if a > p.ux[k] { (a, a) } else { (b, b) };
                }
                p.lx[k] = lo;
                p.ux[k] = hi;
            }
        }
        Ok(())
    }

    /// Builds and solves; on success fills `self.output`.
    pub fn compute(&mut self, model: &Model, s: &RobotState) -> Result<&TorqueForceOutput> {
        self.build(model, s)?;
        let sol = self.solver.solve(&self.problem).map_err(ControlError::Qp)?;
        let na = model.nv - self.first;
        self.output.tau.copy_from(&sol.x.rows(0, na));
        let nf = self.output.forces.len();
        self.output.forces.copy_from(&sol.x.rows(na, nf));
        self.output.dv.copy_from(&self.drift);
        self.output.dv.gemv(1.0, &self.map, &sol.x, 1.0);
        Ok(&self.output)
    }

    /// One control tick: the model terms at (q, v), the QP, the torques into `tau` (na); the
    /// safe command ([`crate::safe_torques`]) and the reason when the state is not finite or
    /// the QP fails.
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
    ) -> Option<FallbackReason> {
        self.tick_with(model, state, t, (q, v), safe_damping, tau, |_, _| Ok(()))
    }

    /// [`Self::tick`] with `adjust` called between the model terms' update and the QP, to set
    /// references that depend on them (a posture reference made consistent with the
    /// Cartesian tasks, say); its error gives the safe command like the QP's.
    #[allow(clippy::too_many_arguments)]
    pub fn tick_with(
        &mut self,
        model: &Model,
        state: &mut RobotState,
        t: f64,
        (q, v): (&[f64], &[f64]),
        safe_damping: f64,
        tau: &mut DVector<f64>,
        adjust: impl FnOnce(&mut Self, &RobotState) -> Result<()>,
    ) -> Option<FallbackReason> {
        let reason = torque_tick(model, state, q, v, safe_damping, tau, |state, tau| {
            self.tasks.update(t);
            adjust(self, state)?;
            tau.copy_from(&self.compute(model, state)?.tau);
            Ok(())
        });
        if self.torque_step.is_some() {
            match &mut self.last_tau {
                Some(last) => last.copy_from(tau),
                None => self.last_tau = Some(tau.clone()),
            }
        }
        reason
    }
}

/// `rows` (in ν̇) mapped to u = [τ; f] through ν̇ = G u + d: `(A G) u = b − A d`, written to
/// a buffer of `mapped` with as many rows (added the first time that size is met); returns
/// its index. Rows that select dofs (a posture's) copy rows of G; otherwise only the columns
/// of A with a non-zero entry (a foot's chain) enter the product, listed
/// in `used` (nv entries, preallocated).
fn map_rows(
    map: &DMatrix<f64>,
    drift: &DVector<f64>,
    mapped: &mut Vec<TaskRows>,
    rows: &TaskRows,
    used: &mut [usize],
) -> usize {
    let (m, n, nv) = (rows.rows(), map.ncols(), map.nrows());
    let k = match mapped
        .iter()
        .position(|r| r.rows() == m && r.a.ncols() == n)
    {
        Some(k) => k,
        None => {
            mapped.push(TaskRows::new(m, n));
            mapped.len() - 1
        }
    };
    let out = &mut mapped[k];
    let (a, g) = (rows.a.as_slice(), map.as_slice());
    if let Some(first) = rows.selection {
        for r in 0..m {
            for c in 0..n {
                out.a[(r, c)] = map[(first + r, c)];
            }
            out.b[r] = rows.b[r] - drift[first + r];
        }
        return k;
    }
    let mut count = 0;
    for i in 0..nv {
        if a[i * m..(i + 1) * m].iter().any(|x| *x != 0.0) {
            used[count] = i;
            count += 1;
        }
    }
    let used = &used[..count];
    for c in 0..n {
        let gc = &g[c * nv..(c + 1) * nv];
        for r in 0..m {
            let mut acc = 0.0;
            for &i in used {
                acc += a[i * m + r] * gc[i];
            }
            out.a[(r, c)] = acc;
        }
    }
    for r in 0..m {
        let mut acc = rows.b[r];
        for &i in used {
            acc -= a[i * m + r] * drift[i];
        }
        out.b[r] = acc;
    }
    k
}
