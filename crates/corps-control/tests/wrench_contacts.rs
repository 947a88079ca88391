//! Seed 001's wrench contacts (§2.4) in the [τ; f] formulation, on TALOS standing with a
//! moving state:
//! - where no limit binds, a wrench contact and the four-corner contact of the same sole give
//!   the same torques and accelerations (both hold the same motion rows and reach the same
//!   wrenches; neither's force is regularized but by the formulation's 1e-8‖f‖², which
//!   weighs a wrench and four corner forces differently: that alone separates the answers,
//!   by 1.9e-2 N·m and 3.4e-5 rad/s² here);
//! - pushed by a CoM reference far aside, the answer's wrenches keep every limit: f_z ≥ f_min,
//!   friction inside the 12-edge polygon, |τ_z| ≤ μ_t f_z, the CoP inside the box; and the
//!   dynamics M ν̇ + h = Sᵀτ + Σ J_kᵀ w_k hold;
//! - a soft contact (its motion rows in the cost) tends to the hard one as its weight grows
//!   (up to 1e4: the gap falls as 1/w).

mod common;
use common::*;
use corps_control::contacts::{Contact, CopBox, WrenchLimits};
use corps_control::formulation::TorqueForce;
use corps_control::tasks::ComTask;
use corps_control::RobotState;
use corps_model::Model;
use nalgebra::{DVector, Vector3};

/// The standing controller's tasks in the [τ; f] formulation, its corner contacts replaced by
/// wrench contacts (`wrench`) of TALOS' sole box (±0.1 × ±0.065 m).
fn formulation(model: &Model, state: &RobotState, q: &DVector<f64>, wrench: bool) -> TorqueForce {
    let (mut tf, id) = standing_torque_force(model, state, q);
    for c in &id.contacts {
        let mut contact = if wrench {
            let limits = WrenchLimits {
                mu: 0.3,
                mu_torsion: 1.0 / 75.0,
                vertices_per_quadrant: 4,
                cop: CopBox {
                    x_min: -0.1,
                    x_max: 0.1,
                    y_min: -0.065,
                    y_max: 0.065,
                },
            };
            let m = &c.motion;
            Contact::with_wrench(
                model,
                &c.name,
                c.frame,
                limits,
                (10.0, 1000.0),
                m.kp,
                m.kd,
                m.reference.clone(),
            )
        } else {
            c.clone()
        };
        contact.force_reg_weight = 0.0;
        tf.contacts.push(contact);
    }
    tf.actuation = None;
    tf
}

fn set_com(tf: &mut TorqueForce, offset: Vector3<f64>) {
    let com = tf.tasks.task_mut::<ComTask>("com").unwrap();
    for k in 0..3 {
        com.reference.pos[k] += offset[k];
    }
}

#[test]
fn where_no_limit_binds_a_wrench_contact_moves_the_robot_as_four_corners_do() {
    let (model, q, _, _) = standing();
    let state = moving_state(&model, &q);
    let mut corners = formulation(&model, &state, &q, false);
    let mut wrench = formulation(&model, &state, &q, true);
    for tf in [&mut corners, &mut wrench] {
        set_com(tf, Vector3::new(0.005, -0.003, 0.0));
    }
    let a = corners.compute(&model, &state).unwrap().clone();
    let b = wrench.compute(&model, &state).unwrap().clone();
    let (dt, dv) = ((&a.tau - &b.tau).amax(), (&a.dv - &b.dv).amax());
    println!("torques differ by {dt:.2e} N·m, accelerations by {dv:.2e}");
    assert!(dt < 5e-2 && dv < 1e-4);
    // The same total wrench on each foot.
    let (mut oa, mut ob) = (0, 0);
    for (ca, cb) in corners.contacts.iter().zip(&wrench.contacts) {
        let wa = ca.wrench(&a.forces.as_slice()[oa..]);
        let wb = cb.wrench(&b.forces.as_slice()[ob..]);
        oa += ca.n_force();
        ob += cb.n_force();
        println!(
            "{}: corners {:.3?}, wrench {:.3?}",
            ca.name,
            wa.as_slice(),
            wb.as_slice()
        );
        assert!((wa - wb).amax() < 0.5, "the feet's wrenches differ");
    }
}

#[test]
fn pushed_far_aside_the_wrenches_keep_every_limit_and_the_dynamics_hold() {
    let (model, q, _, _) = standing();
    let state = moving_state(&model, &q);
    for offset in [
        Vector3::new(0.3, 0.0, 0.0),
        Vector3::new(0.0, -0.4, 0.0),
        Vector3::new(-0.2, 0.2, -0.1),
    ] {
        let mut tf = formulation(&model, &state, &q, true);
        set_com(&mut tf, offset);
        let out = tf.compute(&model, &state).unwrap().clone();
        let mut rhs = -state.data.nle.clone();
        for k in 0..out.tau.len() {
            rhs[6 + k] += out.tau[k];
        }
        let mut o = 0;
        let mut bound_hit = false;
        for c in &tf.contacts {
            let w = c.wrench(&out.forces.as_slice()[o..]);
            rhs += c.jc.transpose() * out.forces.rows(o, 6);
            o += 6;
            let (f, t) = (w.fixed_rows::<3>(0), w.fixed_rows::<3>(3));
            let tol = 1e-7;
            assert!(f.z >= 10.0 - tol, "f_z {}", f.z);
            let edge = 0.3 * (std::f64::consts::PI / 12.0).cos();
            assert!(
                f.xy().norm() <= 0.3 * f.z + tol,
                "outside the friction circle"
            );
            for k in 0..12 {
                let phi = (2 * k + 1) as f64 * std::f64::consts::PI / 12.0;
                assert!(phi.cos() * f.x + phi.sin() * f.y <= edge * f.z + tol);
            }
            assert!(t.z.abs() <= f.z / 75.0 + tol);
            let cop = (-t.y / f.z, t.x / f.z);
            assert!(
                cop.0.abs() <= 0.1 + 1e-9 && cop.1.abs() <= 0.065 + 1e-9,
                "CoP {cop:?}"
            );
            bound_hit |= cop.0.abs() > 0.0999 || cop.1.abs() > 0.0649 || f.z < 10.0 + 1e-6;
            println!(
                "offset {offset:?} {}: f {:.1?} CoP {cop:.4?}",
                c.name,
                f.as_slice()
            );
        }
        assert!(bound_hit, "the push should drive a wrench to a limit");
        let residual = (&state.data.m * &out.dv - rhs).amax();
        assert!(residual < 1e-8, "dynamics residual {residual}");
    }
}

#[test]
fn a_soft_contact_tends_to_the_hard_one_as_its_weight_grows() {
    let (model, q, _, _) = standing();
    let state = moving_state(&model, &q);
    let mut hard = formulation(&model, &state, &q, true);
    set_com(&mut hard, Vector3::new(0.01, 0.0, 0.0));
    let reference = hard.compute(&model, &state).unwrap().dv.clone();
    let mut previous = f64::INFINITY;
    for w in [1.0, 1e2, 1e4] {
        let mut soft = formulation(&model, &state, &q, true);
        set_com(&mut soft, Vector3::new(0.01, 0.0, 0.0));
        for c in &mut soft.contacts {
            c.soft = Some(w);
        }
        let dv = soft.compute(&model, &state).unwrap().dv.clone();
        let gap = (&dv - &reference).amax();
        println!("soft weight {w:e}: accelerations {gap:.3e} from the hard contacts'");
        assert!(gap < previous, "the gap grew at weight {w}");
        previous = gap;
    }
    assert!(previous < 1e-3);
}
