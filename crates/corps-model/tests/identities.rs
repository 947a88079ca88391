//! Identities every correct rigid-body implementation satisfies, checked on the robots of the
//! repository at random states: no reference implementation needed.

mod common;
use common::*;
use corps_model::*;
use nalgebra::{DMatrix, DVector, Matrix6xX};

const STATES: u64 = 6;

#[test]
fn crba_matches_rnea_column_by_column() {
    for (name, model) in robots() {
        let mut data = Data::new(&model);
        for s in 0..STATES {
            let (q, v, _, _) = random_state(&model, s);
            let m = crba(&model, &mut data, q.as_slice()).unwrap().clone();
            let g = generalized_gravity(&model, &mut data, q.as_slice())
                .unwrap()
                .clone();
            let zero = DVector::zeros(model.nv);
            for k in 0..model.nv {
                let mut e = DVector::zeros(model.nv);
                e[k] = 1.0;
                let col = rnea(
                    &model,
                    &mut data,
                    q.as_slice(),
                    zero.as_slice(),
                    e.as_slice(),
                )
                .unwrap()
                    - &g;
                assert_close(
                    &format!("{name} M column {k}"),
                    col.as_slice(),
                    m.column(k).as_slice(),
                    1e-10,
                );
            }
            assert_close(
                &format!("{name} M symmetric"),
                m.as_slice(),
                m.transpose().as_slice(),
                1e-12,
            );
            let _ = v;
        }
    }
}

#[test]
fn aba_inverts_rnea_and_agrees_with_crba_forward_dynamics() {
    for (name, model) in robots() {
        let mut data = Data::new(&model);
        for s in 0..STATES {
            let (q, v, a, tau) = random_state(&model, s);
            let t = rnea(&model, &mut data, q.as_slice(), v.as_slice(), a.as_slice())
                .unwrap()
                .clone();
            let a2 = aba(&model, &mut data, q.as_slice(), v.as_slice(), t.as_slice())
                .unwrap()
                .clone();
            assert_close(
                &format!("{name} ABA(RNEA(a))"),
                a2.as_slice(),
                a.as_slice(),
                1e-9,
            );
            let a3 = aba(
                &model,
                &mut data,
                q.as_slice(),
                v.as_slice(),
                tau.as_slice(),
            )
            .unwrap()
            .clone();
            let a4 = forward_dynamics_crba(
                &model,
                &mut data,
                q.as_slice(),
                v.as_slice(),
                tau.as_slice(),
            )
            .unwrap();
            assert_close(
                &format!("{name} ABA vs CRBA forward dynamics"),
                a3.as_slice(),
                a4.as_slice(),
                1e-9,
            );
        }
    }
}

#[test]
fn minverse_inverts_m_and_both_routes_agree() {
    for (name, model) in robots() {
        let mut data = Data::new(&model);
        for seed in [7, 8, 9] {
            let (q, ..) = random_state(&model, seed);
            let m = crba(&model, &mut data, q.as_slice()).unwrap().clone();
            let minv = compute_minverse(&model, &mut data, q.as_slice())
                .unwrap()
                .clone();
            let prod = &m * &minv;
            let id = DMatrix::<f64>::identity(model.nv, model.nv);
            assert_close(
                &format!("{name} M M⁻¹"),
                prod.as_slice(),
                id.as_slice(),
                1e-9,
            );
            let factorized = compute_minverse_factorized(&model, &mut data, q.as_slice())
                .unwrap()
                .clone();
            assert_close(
                &format!("{name} M⁻¹ by the recursion and by the factorization"),
                minv.as_slice(),
                factorized.as_slice(),
                1e-10,
            );
        }
    }
}

/// The configuration q ⊕ t v.
fn along(model: &Model, q: &DVector<f64>, v: &DVector<f64>, t: f64) -> DVector<f64> {
    integrate(model, q.as_slice(), (v * t).as_slice()).unwrap()
}

fn test_frames(model: &Model) -> Vec<usize> {
    // A few frames spread over the tree: the last frame of every fourth joint, and the last frame.
    let mut ids: Vec<usize> = (0..model.frames.len()).step_by(7).collect();
    ids.push(model.frames.len() - 1);
    ids
}

#[test]
fn frame_jacobians_match_finite_differences() {
    let h = 1e-6;
    for (name, model) in robots() {
        let mut data = Data::new(&model);
        let mut jac = Matrix6xX::zeros(model.nv);
        for s in 0..3 {
            let (q, v, ..) = random_state(&model, s);
            for fid in test_frames(&model) {
                compute_joint_jacobians(&model, &mut data, q.as_slice()).unwrap();
                frame_jacobian(&model, &data, fid, ReferenceFrame::Local, &mut jac).unwrap();
                let jv_local = &jac * &v;
                frame_jacobian(
                    &model,
                    &data,
                    fid,
                    ReferenceFrame::LocalWorldAligned,
                    &mut jac,
                )
                .unwrap();
                let jv_lwa = &jac * &v;
                frame_jacobian(&model, &data, fid, ReferenceFrame::World, &mut jac).unwrap();
                let jv_world = &jac * &v;
                let m0 = frame_placement(&model, &data, fid).unwrap();
                let place = |t: f64, data: &mut Data| {
                    forward_kinematics_placements(
                        &model,
                        data,
                        along(&model, &q, &v, t).as_slice(),
                    )
                    .unwrap();
                    frame_placement(&model, data, fid).unwrap()
                };
                let (mp, mm) = (place(h, &mut data), place(-h, &mut data));
                // LOCAL twist: log6(M0⁻¹ M(t)) / t, central.
                let fd = (spatial::log6(&(m0.inverse() * mp)).to_vector()
                    - spatial::log6(&(m0.inverse() * mm)).to_vector())
                    / (2.0 * h);
                let ctx = format!("{name} frame {}", model.frames[fid].name);
                assert_close(
                    &format!("{ctx} J_local v"),
                    jv_local.as_slice(),
                    fd.as_slice(),
                    1e-6,
                );
                // LWA: origin velocity in world axes, and world angular velocity.
                let dp = (mp.translation - mm.translation) / (2.0 * h);
                assert_close(
                    &format!("{ctx} J_lwa v (linear)"),
                    &jv_lwa.as_slice()[..3],
                    dp.as_slice(),
                    1e-6,
                );
                assert_close(
                    &format!("{ctx} J_lwa v (angular)"),
                    &jv_lwa.as_slice()[3..],
                    (m0.rotation * fd.fixed_rows::<3>(3)).as_slice(),
                    1e-6,
                );
                // WORLD: velocity of the point at the world origin.
                let w = m0.rotation * fd.fixed_rows::<3>(3);
                let v_origin = dp - w.cross(&m0.translation);
                assert_close(
                    &format!("{ctx} J_world v"),
                    &jv_world.as_slice()[..3],
                    v_origin.as_slice(),
                    1e-6,
                );
            }
        }
    }
}

#[test]
fn classical_acceleration_is_the_jacobian_drift() {
    let h = 1e-6;
    for (name, model) in robots() {
        let mut data = Data::new(&model);
        let mut jac = Matrix6xX::zeros(model.nv);
        let (q, v, a, _) = random_state(&model, 3);
        for fid in test_frames(&model) {
            let mut jv = |t: f64, data: &mut Data| {
                compute_joint_jacobians(&model, data, along(&model, &q, &v, t).as_slice()).unwrap();
                frame_jacobian(
                    &model,
                    data,
                    fid,
                    ReferenceFrame::LocalWorldAligned,
                    &mut jac,
                )
                .unwrap();
                (&jac * &v, jac.clone())
            };
            let (jp, _) = jv(h, &mut data);
            let (jm, _) = jv(-h, &mut data);
            let (_, j0) = jv(0.0, &mut data);
            let drift_fd = (jp - jm) / (2.0 * h);
            forward_kinematics(&model, &mut data, q.as_slice(), v.as_slice(), a.as_slice())
                .unwrap();
            let acc =
                frame_classical_acceleration(&model, &data, fid, ReferenceFrame::LocalWorldAligned)
                    .unwrap();
            let expected = drift_fd + j0 * &a;
            assert_close(
                &format!("{name} frame {} classical acc", model.frames[fid].name),
                acc.to_vector().as_slice(),
                expected.as_slice(),
                1e-6,
            );
        }
    }
}

#[test]
fn coriolis_matrix_is_consistent_and_mdot_minus_2c_is_skew() {
    let h = 1e-6;
    for (name, model) in robots() {
        let mut data = Data::new(&model);
        for s in 0..3 {
            let (q, v, ..) = random_state(&model, s);
            let c = coriolis_matrix(&model, &mut data, q.as_slice(), v.as_slice())
                .unwrap()
                .clone();
            let nle = nonlinear_effects(&model, &mut data, q.as_slice(), v.as_slice())
                .unwrap()
                .clone();
            let g = generalized_gravity(&model, &mut data, q.as_slice())
                .unwrap()
                .clone();
            assert_close(
                &format!("{name} C v = h − g"),
                (&c * &v).as_slice(),
                (nle - g).as_slice(),
                1e-9,
            );
            let mp = crba(&model, &mut data, along(&model, &q, &v, h).as_slice())
                .unwrap()
                .clone();
            let mm = crba(&model, &mut data, along(&model, &q, &v, -h).as_slice())
                .unwrap()
                .clone();
            let mdot = (mp - mm) / (2.0 * h);
            let n = &mdot - &c * 2.0;
            let sym = &n + n.transpose();
            let zero = DMatrix::<f64>::zeros(model.nv, model.nv);
            let scale = mdot.amax().max(1.0);
            assert_close(
                &format!("{name} Ṁ − 2C skew"),
                (sym / scale).as_slice(),
                zero.as_slice(),
                1e-6,
            );
        }
    }
}

#[test]
fn power_balance_d_energy_dt_equals_tau_dot_v() {
    let h = 1e-6;
    for (name, model) in robots() {
        let mut data = Data::new(&model);
        for s in 0..3 {
            let (q, v, _, tau) = random_state(&model, s);
            let a = aba(
                &model,
                &mut data,
                q.as_slice(),
                v.as_slice(),
                tau.as_slice(),
            )
            .unwrap()
            .clone();
            let mut energy = |t: f64| {
                let qt = along(&model, &q, &v, t);
                let vt = &v + &a * t;
                kinetic_energy(&model, &mut data, qt.as_slice(), vt.as_slice()).unwrap()
                    + potential_energy(&model, &mut data, qt.as_slice()).unwrap()
            };
            let de = (energy(h) - energy(-h)) / (2.0 * h);
            let power = tau.dot(&v);
            assert!(
                (de - power).abs() <= 1e-6 * power.abs().max(1.0),
                "{name}: dE/dt = {de}, τᵀv = {power}"
            );
        }
    }
}

#[test]
fn centroidal_quantities_are_consistent() {
    let h = 1e-6;
    for (name, model) in robots() {
        let mut data = Data::new(&model);
        let mass = model.total_mass();
        for s in 0..3 {
            let (q, v, a, _) = random_state(&model, s);
            let hg =
                compute_centroidal_momentum(&model, &mut data, q.as_slice(), v.as_slice()).unwrap();
            let jcom = data.jcom.clone();
            let ag = data.ag.clone();
            let com_composite = data.com;
            center_of_mass(&model, &mut data, q.as_slice(), v.as_slice(), a.as_slice()).unwrap();
            let (vcom, acom) = (data.vcom, data.acom);
            // The CoM from the placements and world twists a kinematic pass leaves = the
            // composite-inertia CoM and Jcom v.
            for (i, (m, v)) in data.o_m_i.clone().iter().zip(data.v.clone()).enumerate() {
                data.ov[i] = m.act_motion(&v);
            }
            let (c, vc) = com_at_placements(&model, &data);
            let close = |what: &str, a: &[f64], b: &[f64]| {
                assert_close(&format!("{name} {what} from placements"), a, b, 1e-12)
            };
            close("CoM", c.as_slice(), com_composite.as_slice());
            close("CoM velocity", vc.as_slice(), vcom.as_slice());
            // Linear momentum = m ċ = m Jcom v.
            assert_close(
                &format!("{name} Jcom v"),
                (&jcom * &v).as_slice(),
                vcom.as_slice(),
                1e-10,
            );
            assert_close(
                &format!("{name} h_G linear"),
                hg.linear.as_slice(),
                (vcom * mass).as_slice(),
                1e-10,
            );
            // d/dt h_G = Ȧ_G v + A_G a, and its linear part = m c̈.
            let drift =
                centroidal_momentum_drift(&model, &mut data, q.as_slice(), v.as_slice()).unwrap();
            let rate = drift.to_vector() + &ag * &a;
            assert_close(
                &format!("{name} ḣ_G linear"),
                &rate.as_slice()[..3],
                (acom * mass).as_slice(),
                1e-9,
            );
            let mut hg_at = |t: f64| {
                let qt = along(&model, &q, &v, t);
                let vt = &v + &a * t;
                compute_centroidal_momentum(&model, &mut data, qt.as_slice(), vt.as_slice())
                    .unwrap()
                    .to_vector()
            };
            let fd = (hg_at(h) - hg_at(-h)) / (2.0 * h);
            assert_close(
                &format!("{name} ḣ_G by finite differences"),
                rate.as_slice(),
                fd.as_slice(),
                1e-6,
            );
        }
    }
}

#[test]
fn compute_all_terms_agrees_with_the_single_algorithms() {
    for (name, model) in robots() {
        let mut data = Data::new(&model);
        let mut d2 = Data::new(&model);
        let (q, v, ..) = random_state(&model, 11);
        compute_all_terms(&model, &mut data, q.as_slice(), v.as_slice()).unwrap();
        crba(&model, &mut d2, q.as_slice()).unwrap();
        nonlinear_effects(&model, &mut d2, q.as_slice(), v.as_slice()).unwrap();
        kinetic_energy(&model, &mut d2, q.as_slice(), v.as_slice()).unwrap();
        potential_energy(&model, &mut d2, q.as_slice()).unwrap();
        compute_centroidal_momentum(&model, &mut d2, q.as_slice(), v.as_slice()).unwrap();
        assert_close(
            &format!("{name} M"),
            data.m.as_slice(),
            d2.m.as_slice(),
            1e-12,
        );
        assert_close(
            &format!("{name} nle"),
            data.nle.as_slice(),
            d2.nle.as_slice(),
            1e-12,
        );
        assert_close(
            &format!("{name} Ag"),
            data.ag.as_slice(),
            d2.ag.as_slice(),
            1e-12,
        );
        assert_close(
            &format!("{name} hg"),
            data.hg.to_vector().as_slice(),
            d2.hg.to_vector().as_slice(),
            1e-12,
        );
        assert!((data.kinetic_energy - d2.kinetic_energy).abs() < 1e-9);
        assert!((data.potential_energy - d2.potential_energy).abs() < 1e-9);
    }
}

#[test]
fn configuration_space_operations_are_consistent() {
    for (name, model) in robots() {
        for s in 0..4 {
            let (q0, ..) = random_state(&model, s);
            let (q1, v, ..) = random_state(&model, s + 100);
            let d = difference(&model, q0.as_slice(), q1.as_slice()).unwrap();
            let q1b = integrate(&model, q0.as_slice(), d.as_slice()).unwrap();
            let back = difference(&model, q1.as_slice(), q1b.as_slice()).unwrap();
            assert_close(
                &format!("{name} q0 ⊕ (q1 ⊖ q0) = q1"),
                back.as_slice(),
                &vec![0.0; model.nv],
                1e-9,
            );
            let qv = integrate(&model, q0.as_slice(), v.as_slice()).unwrap();
            let v2 = difference(&model, q0.as_slice(), qv.as_slice()).unwrap();
            assert_close(
                &format!("{name} (q ⊕ v) ⊖ q = v"),
                v2.as_slice(),
                v.as_slice(),
                1e-9,
            );
            let q_half = interpolate(&model, q0.as_slice(), q1.as_slice(), 0.5).unwrap();
            let d0 = difference(&model, q0.as_slice(), q_half.as_slice()).unwrap();
            assert_close(
                &format!("{name} interpolate halfway"),
                d0.as_slice(),
                (&d * 0.5).as_slice(),
                1e-9,
            );
            let mut qn = q0.clone() * 1.0;
            if model.has_free_flyer() {
                for k in 3..7 {
                    qn[k] *= 3.0;
                }
            }
            normalize(&model, qn.as_mut_slice());
            assert_close(
                &format!("{name} normalize"),
                qn.as_slice(),
                q0.as_slice(),
                1e-12,
            );
        }
    }
}

#[test]
fn external_wrenches_act_through_the_jacobian_transpose() {
    for (name, model) in robots() {
        let mut data = Data::new(&model);
        let (q, v, _, tau) = random_state(&model, 21);
        // World wrenches (moment about the world origin) on every third body.
        let wrench = |i: usize| {
            let s = i as f64;
            spatial::Force::new(
                nalgebra::Vector3::new(10.0 + s, -3.0 * s, 2.0),
                nalgebra::Vector3::new(0.5, s.sin(), -1.0),
            )
        };
        let a_ext = aba_with_external_forces(
            &model,
            &mut data,
            q.as_slice(),
            v.as_slice(),
            tau.as_slice(),
            |_, _, f| {
                for (i, fi) in f.iter_mut().enumerate().step_by(3) {
                    *fi = wrench(i);
                }
            },
        )
        .unwrap()
        .clone();
        compute_joint_jacobians(&model, &mut data, q.as_slice()).unwrap();
        let mut tau_total = tau.clone();
        for i in (0..model.njoints()).step_by(3) {
            let f = wrench(i).to_vector();
            let mut j = Some(i);
            while let Some(k) = j {
                let jk = &model.joints[k];
                for d in jk.idx_v..jk.idx_v + jk.nv() {
                    tau_total[d] += data.j.column(d).dot(&f);
                }
                j = jk.parent;
            }
        }
        let a_ref = forward_dynamics_crba(
            &model,
            &mut data,
            q.as_slice(),
            v.as_slice(),
            tau_total.as_slice(),
        )
        .unwrap();
        assert_close(
            &format!("{name} ABA with external wrenches"),
            a_ext.as_slice(),
            a_ref.as_slice(),
            1e-9,
        );
    }
}

#[test]
fn rotation_conversions_round_trip_at_every_angle() {
    use corps_model::spatial::rotation::{exp3, log3, matrix_to_quat, quat_to_matrix};
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
    for k in 0..2000 {
        let axis = nalgebra::Vector3::new(
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
            rng.gen_range(-1.0..1.0),
        )
        .normalize();
        // Angles across (0, π), with extra samples near 0 and near π.
        let angle = match k % 4 {
            0 => rng.gen_range(0.0..1e-6),
            1 => std::f64::consts::PI - rng.gen_range(0.0..1e-6),
            _ => rng.gen_range(0.0..std::f64::consts::PI),
        };
        let w = axis * angle;
        let r = exp3(&w);
        let [x, y, z, qw] = matrix_to_quat(&r);
        assert_close(
            "quaternion round trip",
            quat_to_matrix(x, y, z, qw).as_slice(),
            r.as_slice(),
            1e-12,
        );
        let back = exp3(&log3(&r));
        assert_close("exp3(log3(R))", back.as_slice(), r.as_slice(), 1e-10);
        if angle < std::f64::consts::PI - 1e-3 {
            assert_close("log3(exp3(w))", log3(&r).as_slice(), w.as_slice(), 1e-9);
        }
    }
}

#[test]
fn aba_world_accelerations_match_forward_kinematics() {
    // After ABA, data.oa holds each body's world spatial acceleration offset by −g (the
    // gravity trick); forward kinematics with q̈ = ABA(...) must give the same motion, and so
    // must the Jacobian form an integrator without ABA uses (world_motions_from_jacobians).
    for (name, model) in robots() {
        let mut data = Data::new(&model);
        let mut fk = Data::new(&model);
        let mut from_jacobians = Data::new(&model);
        let (q, v, _, tau) = random_state(&model, 4);
        let ddq = aba_with_external_forces(
            &model,
            &mut data,
            q.as_slice(),
            v.as_slice(),
            tau.as_slice(),
            |_, _, _| {},
        )
        .unwrap()
        .clone();
        forward_kinematics(&model, &mut fk, q.as_slice(), v.as_slice(), ddq.as_slice()).unwrap();
        let mut plain = Data::new(&model);
        aba(
            &model,
            &mut plain,
            q.as_slice(),
            v.as_slice(),
            tau.as_slice(),
        )
        .unwrap();
        compute_joint_jacobians(&model, &mut from_jacobians, q.as_slice()).unwrap();
        world_motions_from_jacobians(&model, &mut from_jacobians, v.as_slice(), ddq.as_slice())
            .unwrap();
        let g = spatial::Motion::new(-model.gravity, nalgebra::Vector3::zeros());
        for i in 0..model.njoints() {
            for (what, got, expected) in [
                ("velocity", from_jacobians.ov[i], data.ov[i]),
                ("acceleration", from_jacobians.oa[i], data.oa[i]),
            ] {
                assert_close(
                    &format!("{name} joint {i} world {what} from the Jacobians"),
                    got.to_vector().as_slice(),
                    expected.to_vector().as_slice(),
                    1e-9,
                );
            }
            let expected = fk.o_m_i[i].act_motion(&fk.a[i]) + g;
            assert_close(
                &format!("{name} joint {i} world acceleration"),
                data.oa[i].to_vector().as_slice(),
                expected.to_vector().as_slice(),
                1e-9,
            );
            let local_g = fk.o_m_i[i].act_inv_motion(&g);
            assert_close(
                &format!("{name} joint {i} local acceleration"),
                plain.a[i].to_vector().as_slice(),
                (fk.a[i] + local_g).to_vector().as_slice(),
                1e-9,
            );
            assert_close(
                &format!("{name} joint {i} local velocity"),
                plain.v[i].to_vector().as_slice(),
                fk.v[i].to_vector().as_slice(),
                1e-12,
            );
            let ov = fk.o_m_i[i].act_motion(&fk.v[i]);
            assert_close(
                &format!("{name} joint {i} world velocity"),
                data.ov[i].to_vector().as_slice(),
                ov.to_vector().as_slice(),
                1e-12,
            );
        }
    }
}

/// h from the placements a CRBA pass left equals h computed from q, bit for bit (the same
/// placements enter the same recursion).
#[test]
fn nonlinear_effects_at_placements_match_the_full_pass() {
    for (name, model) in robots() {
        let (mut a, mut b) = (Data::new(&model), Data::new(&model));
        for s in 0..3 {
            let (q, v, ..) = random_state(&model, 20 + s);
            let full = nonlinear_effects(&model, &mut a, q.as_slice(), v.as_slice())
                .unwrap()
                .clone();
            crba(&model, &mut b, q.as_slice()).unwrap();
            let reused = nonlinear_effects_at_placements(&model, &mut b, v.as_slice()).unwrap();
            assert_eq!(&full, reused, "{name}, state {s}");
        }
    }
}

/// M from the Jacobians of a kinematic pass equals CRBA's, bit for bit (CRBA is that pass and
/// the same composite recursion).
#[test]
fn mass_matrix_at_jacobians_matches_crba() {
    for (name, model) in robots() {
        let (mut a, mut b) = (Data::new(&model), Data::new(&model));
        for s in 0..3 {
            let (q, ..) = random_state(&model, 40 + s);
            let full = crba(&model, &mut a, q.as_slice()).unwrap().clone();
            compute_joint_jacobians(&model, &mut b, q.as_slice()).unwrap();
            assert_eq!(
                &full,
                crba_at_jacobians(&model, &mut b),
                "{name}, state {s}"
            );
        }
    }
}

#[test]
fn one_pass_drifts_match_the_separate_algorithms() {
    for (name, model) in robots() {
        let mut a = Data::new(&model);
        let mut b = Data::new(&model);
        let (q, v, ..) = random_state(&model, 9);
        let zero = DVector::zeros(model.nv);
        compute_all_terms(&model, &mut a, q.as_slice(), v.as_slice()).unwrap();
        let (acom, dag) =
            com_and_momentum_drifts(&model, &mut a, q.as_slice(), v.as_slice()).unwrap();
        let dag_ref =
            centroidal_momentum_drift(&model, &mut b, q.as_slice(), v.as_slice()).unwrap();
        center_of_mass(&model, &mut b, q.as_slice(), v.as_slice(), zero.as_slice()).unwrap();
        assert_close(
            &format!("{name} J̇com v"),
            acom.as_slice(),
            b.acom.as_slice(),
            1e-12,
        );
        assert_close(
            &format!("{name} Ȧ_G v"),
            dag.to_vector().as_slice(),
            dag_ref.to_vector().as_slice(),
            1e-12,
        );
    }
}

/// The ancestor runs, expanded, are the ancestor chain, in order.
#[test]
fn ancestor_runs_expand_to_the_chain() {
    for (name, model) in robots() {
        for k in 0..model.nv {
            let expanded: Vec<usize> = model
                .dof_ancestor_runs(k)
                .iter()
                .flat_map(|&(lo, hi)| (lo..=hi).rev())
                .collect();
            assert_eq!(expanded, model.dof_ancestors(k), "{name}, dof {k}");
        }
    }
}

#[test]
fn sparse_factorization_solves_a_70_link_chain() {
    // A 70-link serial arm: every dof's ancestor chain is long (TALOS' longest is 15).
    let n = 70;
    let mut urdf = String::from("<robot name=\"snake\"><link name=\"l0\"/>");
    for i in 1..=n {
        urdf += &format!(
            "<link name=\"l{i}\"><inertial><origin xyz=\"0 0 -0.05\"/><mass value=\"0.3\"/>\
             <inertia ixx=\"0.001\" iyy=\"0.001\" izz=\"0.0005\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/>\
             </inertial></link><joint name=\"j{i}\" type=\"revolute\"><parent link=\"l{}\"/>\
             <child link=\"l{i}\"/><origin xyz=\"0 0 -0.1\"/><axis xyz=\"{} 1 0\"/>\
             <limit lower=\"-3\" upper=\"3\" effort=\"10\" velocity=\"5\"/></joint>",
            i - 1,
            i % 2
        );
    }
    urdf += "</robot>";
    let model = build_model_from_urdf_str(&urdf, RootJoint::Fixed).unwrap();
    assert_eq!(model.nv, n);
    let mut data = Data::new(&model);
    let q = DVector::from_fn(n, |i, _| 0.3 * (i as f64).sin());
    let m = crba(&model, &mut data, q.as_slice()).unwrap().clone();
    factorize_mass_matrix(&model, &mut data);
    let b = DVector::from_fn(n, |i, _| 1.0 + (i as f64 * 0.7).cos());
    let mut x = b.clone();
    solve_mass_matrix(&model, &data.ltdl, x.as_mut_slice());
    let residual = (&m * &x - &b).norm() / b.norm();
    assert!(residual < 1e-9, "relative residual {residual:.3e}");
}

#[test]
fn a_subtree_is_the_range_of_joints_its_root_supports() {
    for (name, model) in robots() {
        for j in 0..model.njoints() {
            let supported: Vec<usize> = (0..model.njoints())
                .filter(|&k| model.supports(j, k))
                .collect();
            let range: Vec<usize> = model.subtree_joints(j).collect();
            assert_eq!(range, supported, "{name}, joint {j}");
        }
    }
}

#[test]
fn one_frame_jacobian_equals_the_full_pass() {
    for (name, model) in robots() {
        let (mut full, mut one) = (Data::new(&model), Data::new(&model));
        let (mut expected, mut got) = (Matrix6xX::zeros(model.nv), Matrix6xX::zeros(model.nv));
        for s in 0..STATES {
            let (q, _, _, _) = random_state(&model, s);
            compute_joint_jacobians(&model, &mut full, q.as_slice()).unwrap();
            for f in test_frames(&model) {
                for rf in [
                    ReferenceFrame::Local,
                    ReferenceFrame::World,
                    ReferenceFrame::LocalWorldAligned,
                ] {
                    frame_jacobian(&model, &full, f, rf, &mut expected).unwrap();
                    compute_frame_jacobian(&model, &mut one, q.as_slice(), f, rf, &mut got)
                        .unwrap();
                    assert_eq!(expected, got, "{name} frame {f} {rf:?}");
                }
            }
        }
    }
}
