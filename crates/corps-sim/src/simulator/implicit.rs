//! Linearly implicit Euler: one factorization per step, stable at a 1 ms step with contact
//! springs stiff enough for a rigid-contact torque controller.
//!
//! The contact spring–dampers and the joint servos are the stiff forces; they are linearized
//! about the start of the step, f(q + h v⁺, v⁺) ≈ f₀ − K h v⁺ − D (v⁺ − v), and the rest
//! (gravity, Coriolis, commanded torques, friction on the cone, pushes) is explicit:
//!
//! (M + h D_q + h² K_q) Δv = h (τ − h(q, v) + Σ_b J_bᵀ w_b) − h² K_q v,   v⁺ = v + Δv,
//! q⁺ = q ⊕ h v⁺,
//!
//! with D_q = Σ_b J_bᵀ D_b J_b + diag(k_d) and K_q likewise, D_b and K_b the 6×6 sums of the
//! touching points' matrices moved to the body (`Gᵀ K G`, `G = [I  −[p]×]` mapping a world
//! twist to the point's velocity). It is the scheme MuJoCo's `implicitfast` applies to
//! damping, here applied to the contact stiffness as well. Every added term lies inside the
//! branch sparsity of M (each body's Jacobian spans its chain of ancestors), so the sparse
//! LᵀDL factorization of M serves. Without contact and servo it is semi-implicit Euler. The
//! contact forces and servo torques recorded for the sensors are the linearized ones at the
//! end of the step, those that produced Δv (a lifting point's may be slightly adhesive for
//! that one step, as the linearization does not clamp).

use super::Simulator;
use crate::actuation::{first_actuated, Command};
use crate::contact::{split_times, Anchor};
use crate::contact_pass::{contact_pass, PointVisit};
use crate::error::Result;
use corps_model::spatial::{Force, Motion};
use corps_model::{
    compute_joint_jacobians, crba_at_jacobians, factorize_branch_sparse, integrate_to,
    nonlinear_effects_at_placements, solve_mass_matrix, world_motions_from_jacobians, Data, Model,
};
use nalgebra::{DVector, Matrix3, Matrix6, Matrix6xX, Vector3, Vector6};

/// A touching point's contribution, kept for the end-of-step force.
#[derive(Clone, Copy, Debug)]
struct ActivePoint {
    index: usize,
    joint: usize,
    position: Vector3<f64>,
    /// f₀ − h K v_p: the force if the point's velocity did not change.
    force: Vector3<f64>,
    /// Surface normal at the point.
    normal: Vector3<f64>,
    /// How the force falls with the change of the point's velocity, D + h K, along the
    /// normal and in the tangent plane.
    normal_gain: f64,
    tangential_gain: f64,
}

/// Work buffers of the implicit step, sized once.
#[derive(Clone, Debug)]
pub(super) struct ImplicitWork {
    rhs: DVector<f64>,
    zeros: DVector<f64>,
    servo_stiffness: Vec<f64>,
    servo_damping: Vec<f64>,
    body_gain: Vec<GainSums>,
    body_wrench: Vec<Force>,
    body_dtwist: Vec<Motion>,
    touched: Vec<bool>,
    active: Vec<ActivePoint>,
    chain: Vec<usize>,
    gain_cols: Matrix6xX<f64>,
    /// Next anchors and point positions of the prepared step, swapped in when it is taken.
    next_anchors: Vec<Anchor>,
    point_positions: Vec<Vector3<f64>>,
    /// The servo linearization the factorized A holds.
    factored_stiffness: Vec<f64>,
    factored_damping: Vec<f64>,
    /// Whether `data` holds the world Jacobians, placements and twists at the current state
    /// (left by the last step; cleared when the state is set).
    pub(super) terms_valid: bool,
    /// Whether the state-only part of the next step is done ([`Simulator::prepare_step`]).
    pub(super) prepared: bool,
}

impl ImplicitWork {
    pub(super) fn new(model: &Model, n_points: usize) -> Self {
        let (nv, n) = (model.nv, model.njoints());
        let na = nv - first_actuated(model);
        Self {
            rhs: DVector::zeros(nv),
            zeros: DVector::zeros(nv),
            servo_stiffness: vec![0.0; na],
            servo_damping: vec![0.0; na],
            body_gain: vec![GainSums::default(); n],
            body_wrench: vec![Force::zero(); n],
            body_dtwist: vec![Motion::zero(); n],
            touched: vec![false; n],
            active: Vec::with_capacity(n_points),
            chain: Vec::with_capacity(nv),
            gain_cols: Matrix6xX::zeros(nv),
            next_anchors: vec![Anchor::default(); n_points],
            point_positions: vec![Vector3::zeros(); n_points],
            factored_stiffness: vec![0.0; na],
            factored_damping: vec![0.0; na],
            terms_valid: false,
            prepared: false,
        }
    }

    /// Forgets the terms left by the last step and any prepared step (the state or `data`
    /// changed under them).
    pub(super) fn invalidate(&mut self) {
        self.terms_valid = false;
        self.prepared = false;
    }
}

/// Calls `f(b, chain)` for every body `b` with `touched[b]`, `chain` being the dofs that move
/// it (its own and its ancestors', deepest first), gathered in the `scratch` buffer.
fn for_each_touched(
    model: &Model,
    touched: &[bool],
    scratch: &mut Vec<usize>,
    mut f: impl FnMut(usize, &[usize]),
) {
    for (b, j) in model.joints.iter().enumerate() {
        if !touched[b] {
            continue;
        }
        scratch.clear();
        if j.nv() > 0 {
            let last = j.idx_v + j.nv() - 1;
            scratch.push(last);
            scratch.extend_from_slice(model.dof_ancestors(last));
        }
        f(b, scratch);
    }
}

/// Column `k` of a 6×n matrix as a 6-vector.
fn col6(m: &Matrix6xX<f64>, k: usize) -> Vector6<f64> {
    m.fixed_view::<6, 1>(0, k).into_owned()
}

/// The sums over one body's touching points from which `Σ Gᵀ C G` is assembled, for
/// `G = [I  −[p]×]` (a world twist to the velocity of point `p`) and
/// `C = a nnᵀ + b (I − nnᵀ)`. With `P = [p]×`, `c = a − b` and `m = p × n = P n`, a point's
/// blocks are: top-left `b I + c nnᵀ`; top-right `−C P = −b P + c n mᵀ` (as `nᵀ P = −mᵀ`);
/// bottom-left its transpose; bottom-right `−P C P = b (|p|² I − ppᵀ) + c m mᵀ`. Each is
/// linear in the per-point terms, so a body sums them and builds its 6×6 once.
#[derive(Clone, Copy, Debug, Default)]
struct GainSums {
    b: f64,
    b_p: Vector3<f64>,
    c_nn: Matrix3<f64>,
    c_nm: Matrix3<f64>,
    angular: Matrix3<f64>,
}

impl GainSums {
    fn add(&mut self, n: &Vector3<f64>, a: f64, b: f64, p: &Vector3<f64>) {
        let c = a - b;
        let m = p.cross(n);
        let cn = n * c;
        self.b += b;
        self.b_p += p * b;
        self.c_nn += cn * n.transpose();
        self.c_nm += cn * m.transpose();
        let pp = p.norm_squared();
        self.angular += Matrix3::from_diagonal_element(b * pp) - (p * b) * p.transpose()
            + (m * c) * m.transpose();
    }

    fn matrix(&self) -> Matrix6<f64> {
        let top_right = self.c_nm - self.b_p.cross_matrix();
        let mut g = Matrix6::zeros();
        g.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&(Matrix3::from_diagonal_element(self.b) + self.c_nn));
        g.fixed_view_mut::<3, 3>(0, 3).copy_from(&top_right);
        g.fixed_view_mut::<3, 3>(3, 0)
            .copy_from(&top_right.transpose());
        g.fixed_view_mut::<3, 3>(3, 3).copy_from(&self.angular);
        g
    }
}

/// `A = M + h D_q + h² K_q` into `data.ltdl`, factorized, for the servo linearization in
/// `w.factored_stiffness`, `w.factored_damping` and the contact gains of the touched bodies.
fn assemble_and_factor(model: &Model, data: &mut Data, w: &mut ImplicitWork, h: f64) {
    let first = first_actuated(model);
    data.ltdl.copy_from(&data.m);
    let a = &mut data.ltdl;
    let servos = w.factored_stiffness.iter().zip(&w.factored_damping);
    for (k, (kp, kd)) in (first..model.nv).zip(servos) {
        a[(k, k)] += h * kd + h * h * kp;
    }
    let (body_gain, gain_cols, j) = (&w.body_gain, &mut w.gain_cols, &data.j);
    for_each_touched(model, &w.touched, &mut w.chain, |b, chain| {
        let gain = body_gain[b].matrix();
        for &c in chain {
            gain_cols.set_column(c, &(gain * col6(j, c)));
        }
        for &r in chain {
            let jr = col6(j, r);
            for &c in chain {
                a[(r, c)] += jr.dot(&gain_cols.column(c));
            }
        }
    });
    let _ = factorize_branch_sparse(model, a); // data.ltdl is nv × nv
}

impl Simulator {
    /// The part of an implicit step of length `h` that depends on the state alone: h(q, v),
    /// the contact pass (explicit wrenches f₀ − h K v_p and implicit gains h (D + h K) per
    /// body) and the factorization of A, with the servo linearization of the last step (the
    /// step redoes A if the command's differs). Writes only work buffers and `data`'s terms;
    /// the contact state and the anchors change when the step is taken.
    pub(super) fn prepare_implicit(&mut self, h: f64) {
        let model = &*self.model;
        let (q, v) = (self.q.as_slice(), self.v.as_slice());
        let w = &mut self.implicit;
        // Checked sizes: none of these calls can fail. The world Jacobians, placements and
        // twists at (q, v) are left by the previous step unless the state was set since; M
        // and h reuse them.
        if !w.terms_valid {
            let _ = compute_joint_jacobians(model, &mut self.data, q);
            let _ = world_motions_from_jacobians(model, &mut self.data, v, w.zeros.as_slice());
            w.terms_valid = true;
        }
        crba_at_jacobians(model, &mut self.data);
        let _ = nonlinear_effects_at_placements(model, &mut self.data, v);

        w.body_gain
            .iter_mut()
            .for_each(|g| *g = GainSums::default());
        w.body_wrench.iter_mut().for_each(|f| *f = Force::zero());
        w.touched.iter_mut().for_each(|t| *t = false);
        w.active.clear();
        let (params, points, ov) = (&self.settings.contact, &self.points, &self.data.ov);
        let (positions, next_anchors) = (&mut w.point_positions, &mut w.next_anchors);
        let (body_gain, body_wrench) = (&mut w.body_gain, &mut w.body_wrench);
        let (touched, active) = (&mut w.touched, &mut w.active);
        let visit = |pt: PointVisit| {
            let k = pt.index;
            positions[k] = pt.position;
            let Some(pf) = pt.force else {
                next_anchors[k] = Anchor::default();
                return;
            };
            next_anchors[k] = pf.next_anchor;
            if pf.normal_force <= 0.0 {
                return;
            }
            let lin = pf.linearization(params, points[k].weight);
            let p = pt.position;
            let force = pf.force - lin.stiffness_times(&pf.velocity) * h;
            let normal_gain = lin.normal_damping + h * lin.normal_stiffness;
            let tangential_gain = lin.tangential_damping + h * lin.tangential_stiffness;
            body_gain[pt.joint].add(&lin.normal, h * normal_gain, h * tangential_gain, &p);
            body_wrench[pt.joint] += Force::new(force, p.cross(&force));
            touched[pt.joint] = true;
            active.push(ActivePoint {
                index: k,
                joint: pt.joint,
                position: p,
                force,
                normal: lin.normal,
                normal_gain,
                tangential_gain,
            });
        };
        contact_pass(
            &self.terrain,
            params,
            points,
            &self.bounds,
            &mut self.anchors,
            &self.data.o_m_i,
            ov,
            true,
            visit,
        );
        for (push, joint, placement) in &self.pushes {
            if push.active(self.t) {
                w.body_wrench[*joint] += push.world_wrench(&self.data.o_m_i[*joint], placement);
                w.touched[*joint] = true;
            }
        }
        assemble_and_factor(model, &mut self.data, w, h);
        w.prepared = true;
    }

    /// One linearly implicit Euler step of length `h` under `cmd`; records the contact
    /// forces and leaves placements, twists and accelerations of the new state in `data`.
    pub(super) fn implicit_euler(&mut self, cmd: &Command, h: f64) -> Result<()> {
        if !self.implicit.prepared {
            self.prepare_implicit(h);
        }
        let model = &*self.model;
        let (q, v) = (self.q.as_slice(), self.v.as_slice());
        let w = &mut self.implicit;
        let first = first_actuated(model);
        // A drive's torque at the step's end, its motor solved with the link.
        self.actuators.set_implicit_step(h);
        self.actuators
            .torques(model, cmd, q, v, self.tau.as_mut_slice());
        self.actuators.linearization(
            model,
            cmd,
            self.tau.as_slice(),
            &mut w.servo_stiffness,
            &mut w.servo_damping,
        );
        let data = &mut self.data;
        if w.servo_stiffness != w.factored_stiffness || w.servo_damping != w.factored_damping {
            w.factored_stiffness.copy_from_slice(&w.servo_stiffness);
            w.factored_damping.copy_from_slice(&w.servo_damping);
            assemble_and_factor(model, data, w, h);
        }

        // rhs = h (τ − h(q, v) + Σ Jᵀ w) − h² K_servo v.
        for k in 0..model.nv {
            w.rhs[k] = h * (self.tau[k] - data.nle[k]);
        }
        for ((vk, kp), k) in v[first..].iter().zip(&w.servo_stiffness).zip(first..) {
            w.rhs[k] -= h * h * kp * vk;
        }
        let (body_wrench, rhs) = (&w.body_wrench, &mut w.rhs);
        for_each_touched(model, &w.touched, &mut w.chain, |b, chain| {
            let wrench = body_wrench[b].to_vector();
            for &c in chain {
                rhs[c] += h * col6(&data.j, c).dot(&wrench);
            }
        });
        solve_mass_matrix(model, &data.ltdl, w.rhs.as_mut_slice());
        let dv = &w.rhs;

        // The step is taken: the anchors move, and the contact forces are those that
        // produced Δv: f = f₀ − h K v_p − (D + h K) Δv_p.
        std::mem::swap(&mut self.anchors, &mut w.next_anchors);
        let contact = &mut self.contact;
        std::mem::swap(&mut contact.point_positions, &mut w.point_positions);
        contact.point_forces.fill(Vector3::zeros());
        contact.body_wrenches.fill(Force::zero());
        let body_dtwist = &mut w.body_dtwist;
        for_each_touched(model, &w.touched, &mut w.chain, |b, chain| {
            let mut twist = Vector6::zeros();
            for &c in chain {
                twist += col6(&data.j, c) * dv[c];
            }
            body_dtwist[b] = Motion::from_vector(&twist);
        });
        for a in &w.active {
            let dv_p = w.body_dtwist[a.joint].point_velocity(&a.position);
            let f = a.force - split_times(&a.normal, a.normal_gain, a.tangential_gain, &dv_p);
            contact.point_forces[a.index] = f;
            contact.body_wrenches[a.joint] += Force::new(f, a.position.cross(&f));
        }

        // v⁺, q⁺ = q ⊕ h v⁺, and the new state's kinematics for the sensors.
        let scratch = &mut self.work;
        for k in 0..model.nv {
            self.acceleration[k] = dv[k] / h;
            self.v[k] += dv[k];
            scratch.dq[k] = h * self.v[k];
        }
        // The servo torques that produced Δv, τ₀ − k_p h v⁺ − k_d Δv, as the applied torques
        // (the sensors and the work read them), within the effort limits.
        let servos = w.servo_stiffness.iter().zip(&w.servo_damping);
        for (k, (kp, kd)) in (first..model.nv).zip(servos) {
            let lim = model.effort_limit[k];
            let t = self.tau[k] - kp * h * self.v[k] - kd * dv[k];
            self.tau[k] = t.clamp(-lim, lim);
        }
        let _ = integrate_to(
            model,
            self.q.as_slice(),
            scratch.dq.as_slice(),
            scratch.qs.as_mut_slice(),
        );
        self.q.copy_from(&scratch.qs);
        corps_model::normalize(model, self.q.as_mut_slice());
        let _ = compute_joint_jacobians(model, data, self.q.as_slice());
        let _ = world_motions_from_jacobians(
            model,
            data,
            self.v.as_slice(),
            self.acceleration.as_slice(),
        );
        w.terms_valid = true;
        w.prepared = false;
        self.first_stage_valid = false;
        self.check_state(self.t + h)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::split_matrix;
    use nalgebra::Matrix3x6;

    #[test]
    fn summed_point_gains_are_the_sum_of_g_transpose_c_g() {
        let points = [
            (
                Vector3::new(0.1, -0.2, 0.97),
                Vector3::new(0.4, -0.3, 0.05),
                3.0,
                1.7,
            ),
            (
                Vector3::new(0.0, 0.0, 1.0),
                Vector3::new(-0.2, 0.1, 0.0),
                2.0,
                0.0,
            ),
            (
                Vector3::new(-0.3, 0.1, 0.9),
                Vector3::new(0.05, 0.6, -0.1),
                0.5,
                0.9,
            ),
        ];
        let mut expected = Matrix6::zeros();
        let mut sums = GainSums::default();
        for (n, p, a, b) in points {
            let n = n.normalize();
            let mut g = Matrix3x6::zeros();
            g.fixed_view_mut::<3, 3>(0, 0)
                .copy_from(&Matrix3::identity());
            g.fixed_view_mut::<3, 3>(0, 3)
                .copy_from(&(-p.cross_matrix()));
            expected += g.transpose() * split_matrix(&n, a, b) * g;
            sums.add(&n, a, b, &p);
        }
        assert!((sums.matrix() - expected).norm() < 1e-12 * expected.norm());
    }
}
