//! TSID's acceleration–force inverse-dynamics formulation (`InverseDynamicsFormulationAccForce`
//! solved as one weighted QP): variables `x = [q̈; f₁; …; f_k]`;
//! - equalities: the floating-base rows of the dynamics `M_u q̈ − Jc_uᵀ f = −h_u`, and each
//!   contact's motion task `J q̈ = a_des − J̇ v`;
//! - inequalities: each contact's friction pyramid and normal-force bounds, and the actuation
//!   bounds `τ_min − h_a ≤ M_a q̈ − Jc_aᵀ f ≤ τ_max − h_a`;
//! - cost: Σ w‖A_k x − b_k‖² over the priority-1 tasks (contact force regularizations, CoM,
//!   posture, angular momentum, other frame tasks), plus 1e-8‖x‖² (TSID's Hessian
//!   regularization).
//!
//! Torques follow from the actuated rows: `τ = M_a q̈ + h_a − Jc_aᵀ f`.

use crate::contacts::{Contact6d, FORCE_ROWS, FORCE_VARS};
use crate::error::{ControlError, Result};
use crate::robot_state::RobotState;
use crate::tasks::{AngularMomentumTask, ComTask, PostureTask, Se3Task, TaskRows};
use corps_model::Model;
use corps_qp::{ActiveSetSolver, QpProblem};
use nalgebra::{DMatrix, DVector};

/// TSID's `DEFAULT_HESSIAN_REGULARIZATION`.
pub const HESSIAN_REGULARIZATION: f64 = 1e-8;

/// The controller's answer at one tick.
#[derive(Clone, Debug, PartialEq)]
pub struct IdOutput {
    /// Joint accelerations q̈ (nv).
    pub dv: DVector<f64>,
    /// Contact forces, 12 per contact, in contact order.
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
    pub com: Option<(ComTask, f64)>,
    pub posture: Option<(PostureTask, f64)>,
    pub angular_momentum: Option<(AngularMomentumTask, f64)>,
    /// Frame tasks in the cost (e.g. a swing foot), with weights.
    pub frames: Vec<(Se3Task, f64)>,
    pub contacts: Vec<Contact6d>,
    /// Actuation bounds (na each), a hard inequality when set.
    pub actuation: Option<(DVector<f64>, DVector<f64>)>,
    first: usize,
    pub problem: QpProblem,
    solver: ActiveSetSolver,
    pub output: IdOutput,
    transitions: Vec<Transition>,
    scratch: DVector<f64>,
}

impl InverseDynamics {
    /// An empty formulation for `model` (add tasks and contacts, then call `compute`).
    pub fn new(model: &Model) -> Self {
        let first = if model.has_free_flyer() { 6 } else { 0 };
        let na = model.nv - first;
        Self {
            com: None,
            posture: None,
            angular_momentum: None,
            frames: Vec::new(),
            contacts: Vec::new(),
            actuation: None,
            first,
            problem: QpProblem::new(model.nv, first, 0),
            solver: ActiveSetSolver::new(model.nv, first, 0),
            output: IdOutput {
                dv: DVector::zeros(model.nv),
                forces: DVector::zeros(0),
                tau: DVector::zeros(na),
            },
            transitions: Vec::new(),
            scratch: DVector::zeros(model.nv),
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

    /// Total normal force of contact `k` in the last solution (N).
    pub fn normal_force(&self, k: usize) -> f64 {
        let c = &self.contacts[k];
        let f = &self.output.forces;
        if f.len() < FORCE_VARS * (k + 1) {
            return 0.0;
        }
        (0..4)
            .map(|i| c.normal.dot(&f.fixed_rows::<3>(FORCE_VARS * k + 3 * i)))
            .sum()
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
    pub fn add_contact(&mut self, mut contact: Contact6d, t: f64, duration: f64) {
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

    /// Advances contact transitions to time `t` (call once per tick before `compute`).
    pub fn update_transitions(&mut self, t: f64) {
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
        use crate::FallbackReason;
        let reason = match (
            model.check_configuration(q),
            model.check_tangent("velocity v", v),
        ) {
            (Err(e), _) | (_, Err(e)) => Some(FallbackReason::BadState(e.to_string())),
            _ => {
                self.update_transitions(t);
                let solved = state
                    .update(model, q, v)
                    .map_err(ControlError::from)
                    .and_then(|_| self.compute(model, state).map(|_| ()));
                solved.err().map(FallbackReason::Controller)
            }
        };
        match reason {
            None => tau.copy_from(&self.output.tau),
            Some(_) => crate::safe_torques(model, &mut state.data, q, v, safe_damping, tau),
        }
        reason
    }

    /// Problem sizes (variables, equalities, inequalities) for the current contacts.
    pub fn dims(&self, model: &Model) -> (usize, usize, usize) {
        let nc = self.contacts.len();
        let na = model.nv - self.first;
        let n_in = FORCE_ROWS * nc + if self.actuation.is_some() { na } else { 0 };
        (model.nv + FORCE_VARS * nc, self.first + 6 * nc, n_in)
    }

    /// Builds the QP at state `s` into `self.problem` (resizing only when contacts change).
    pub fn build(&mut self, model: &Model, s: &RobotState) -> Result<()> {
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
        for contact in &mut self.contacts {
            contact.compute(model, s)?;
        }
        // Floating-base dynamics rows: [M_u  −Jc_uᵀ] x = −h_u.
        copy_block(&mut p.a, (0, 0), m, (0, 0), (first, nv));
        for (k, contact) in self.contacts.iter().enumerate() {
            copy_block_neg_transposed(
                &mut p.a,
                (0, nv + FORCE_VARS * k),
                &contact.jc,
                (0, 0),
                (first, FORCE_VARS),
            );
        }
        for r in 0..first {
            p.b[r] = -h[r];
        }
        // Contact motion rows, friction rows and force regularization.
        for (k, contact) in self.contacts.iter().enumerate() {
            let rows = &contact.motion_rows();
            let r0 = first + 6 * k;
            copy_block(&mut p.a, (r0, 0), &rows.a, (0, 0), (6, nv));
            p.b.rows_mut(r0, 6).copy_from(&rows.b);
            let col = nv + FORCE_VARS * k;
            contact.force_constraints(&mut p.c, &mut p.l, &mut p.u, FORCE_ROWS * k, col);
            let t = &contact.t;
            let w = contact.force_reg_weight;
            let cw = &contact.force_reg_components;
            // ‖diag(cw) (T f − f_ref)‖² weighted by w.
            for i in 0..FORCE_VARS {
                for j in 0..FORCE_VARS {
                    let mut acc = 0.0;
                    for r in 0..6 {
                        acc += cw[r] * cw[r] * t[(r, i)] * t[(r, j)];
                    }
                    p.h[(col + i, col + j)] += w * acc;
                }
                let mut acc = 0.0;
                for r in 0..6 {
                    acc += cw[r] * cw[r] * t[(r, i)] * contact.force_reference[r];
                }
                p.g[col + i] -= w * acc;
            }
        }
        // Actuation bounds.
        if let Some((lower, upper)) = &self.actuation {
            let r0 = FORCE_ROWS * self.contacts.len();
            let na = nv - first;
            // [M_a  −Jc_aᵀ] x within [τ_min − h_a, τ_max − h_a].
            copy_block(&mut p.c, (r0, 0), m, (first, 0), (na, nv));
            for (ci, contact) in self.contacts.iter().enumerate() {
                copy_block_neg_transposed(
                    &mut p.c,
                    (r0, nv + FORCE_VARS * ci),
                    &contact.jc,
                    (0, first),
                    (na, FORCE_VARS),
                );
            }
            for k in 0..na {
                p.l[r0 + k] = lower[k] - h[first + k];
                p.u[r0 + k] = upper[k] - h[first + k];
            }
        }
        // Cost terms on q̈.
        let row = self.scratch.as_mut_slice();
        if let Some((task, w)) = &mut self.com {
            add_least_squares(&mut p.h, &mut p.g, task.compute(s), *w, row);
        }
        if let Some((task, w)) = &mut self.posture {
            let rows = task.compute(model, s);
            for k in 0..rows.rows() {
                p.h[(first + k, first + k)] += *w;
                p.g[first + k] -= *w * rows.b[k];
            }
        }
        if let Some((task, w)) = &mut self.angular_momentum {
            add_least_squares(&mut p.h, &mut p.g, task.compute(s), *w, row);
        }
        for (task, w) in &mut self.frames {
            add_least_squares(&mut p.h, &mut p.g, task.compute(model, s)?, *w, row);
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
        // τ = M_a q̈ + h_a − Jc_aᵀ f.
        let (m, h) = (&s.data.m, &s.data.nle);
        for k in 0..nv - self.first {
            let r = self.first + k;
            let mut t = h[r];
            for c in 0..nv {
                t += m[(r, c)] * self.output.dv[c];
            }
            for (ci, contact) in self.contacts.iter().enumerate() {
                for j in 0..FORCE_VARS {
                    t -= contact.jc[(j, r)] * self.output.forces[FORCE_VARS * ci + j];
                }
            }
            self.output.tau[k] = t;
        }
        Ok(&self.output)
    }
}

/// `H += w AᵀA` and `g −= w Aᵀ b` over the first `A.ncols()` variables, as one rank-1 update
/// `w a_r a_rᵀ` per task row (contiguous inner loops over H's columns); `row` is scratch of at
/// least `A.ncols()` entries.
fn add_least_squares(
    h: &mut DMatrix<f64>,
    g: &mut DVector<f64>,
    rows: &TaskRows,
    w: f64,
    row: &mut [f64],
) {
    let (m, n) = (rows.a.nrows(), rows.a.ncols());
    let nh = h.nrows();
    let a = rows.a.as_slice();
    let hs = h.as_mut_slice();
    let row = &mut row[..n];
    for r in 0..m {
        for (i, x) in row.iter_mut().enumerate() {
            *x = a[i * m + r];
        }
        let br = w * rows.b[r];
        for (j, aj) in row.iter().enumerate() {
            g[j] -= br * aj;
            if *aj == 0.0 {
                continue;
            }
            let s = w * aj;
            for (hij, ai) in hs[j * nh..j * nh + n].iter_mut().zip(row.iter()) {
                *hij += s * ai;
            }
        }
    }
}

/// `dst[dr.., dc..] = src[sr.., sc..]` over a `rows × cols` block, column by column.
fn copy_block(
    dst: &mut DMatrix<f64>,
    (dr, dc): (usize, usize),
    src: &DMatrix<f64>,
    (sr, sc): (usize, usize),
    (rows, cols): (usize, usize),
) {
    let (nd, ns) = (dst.nrows(), src.nrows());
    let (d, s) = (dst.as_mut_slice(), src.as_slice());
    for c in 0..cols {
        let from = (sc + c) * ns + sr;
        let to = (dc + c) * nd + dr;
        d[to..to + rows].copy_from_slice(&s[from..from + rows]);
    }
}

/// `dst[dr + r, dc + c] = −src[sr + c, sc + r]`: a negated transposed block (`−Jcᵀ`).
fn copy_block_neg_transposed(
    dst: &mut DMatrix<f64>,
    (dr, dc): (usize, usize),
    src: &DMatrix<f64>,
    (sr, sc): (usize, usize),
    (rows, cols): (usize, usize),
) {
    let (nd, ns) = (dst.nrows(), src.nrows());
    let (d, s) = (dst.as_mut_slice(), src.as_slice());
    for c in 0..cols {
        let to = (dc + c) * nd + dr;
        for (r, x) in d[to..to + rows].iter_mut().enumerate() {
            *x = -s[(sc + r) * ns + sr + c];
        }
    }
}
