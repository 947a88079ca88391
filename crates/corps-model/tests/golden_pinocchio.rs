//! Every algorithm against Pinocchio 4.1 (golden values made by
//! tools/golden/gen_model_golden.py, committed under tests/golden/): within 1e-9, relative
//! to the largest entry of each quantity (or 1).

mod common;
use common::*;
use corps_model::*;
use nalgebra::{DMatrix, Matrix6xX};
use serde_json::Value;

const TOL: f64 = 1e-9;

fn flat(v: &Value) -> Vec<f64> {
    match v {
        Value::Array(a) => a.iter().flat_map(flat).collect(),
        Value::Number(n) => vec![n.as_f64().unwrap()],
        other => panic!("unexpected JSON {other}"),
    }
}

fn rows<'a>(m: impl Iterator<Item = nalgebra::RowDVector<f64>> + 'a) -> Vec<f64> {
    m.flat_map(|r| r.iter().copied().collect::<Vec<_>>())
        .collect()
}

fn mat_rows(m: &DMatrix<f64>) -> Vec<f64> {
    rows(m.row_iter().map(|r| r.into_owned()))
}

fn mat6_rows(m: &Matrix6xX<f64>) -> Vec<f64> {
    (0..6)
        .flat_map(|r| m.row(r).iter().copied().collect::<Vec<_>>())
        .collect()
}

fn check_case(case: &str) {
    let path = repo_path(&format!("crates/corps-model/tests/golden/{case}.json"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let g: Value = serde_json::from_str(&text).unwrap();
    let root = if g["root"] == "fixed" {
        RootJoint::Fixed
    } else {
        RootJoint::FreeFlyer
    };
    let model = load(g["urdf"].as_str().unwrap(), root);
    assert_eq!(model.nq as u64, g["nq"].as_u64().unwrap(), "{case} nq");
    assert_eq!(model.nv as u64, g["nv"].as_u64().unwrap(), "{case} nv");
    let names: Vec<&str> = g["joint_names"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n.as_str().unwrap())
        .collect();
    let ours: Vec<&str> = model.joints.iter().map(|j| j.name.as_str()).collect();
    assert_eq!(ours, names, "{case}: joint order differs from Pinocchio's");
    assert!(
        (model.total_mass() - g["mass"].as_f64().unwrap()).abs() < 1e-12,
        "{case} mass"
    );
    for (k, j) in model.joints.iter().enumerate() {
        assert_eq!(
            j.idx_q as u64,
            g["joint_idx_q"][k].as_u64().unwrap(),
            "{case} idx_q of {}",
            j.name
        );
        assert_eq!(
            j.idx_v as u64,
            g["joint_idx_v"][k].as_u64().unwrap(),
            "{case} idx_v of {}",
            j.name
        );
        let m = g["body_masses"][k].as_f64().unwrap();
        assert!(
            (model.inertias[k].mass - m).abs() < 1e-12,
            "{case} body mass of {}",
            j.name
        );
        assert_close(
            &format!("{case} body lever of {}", j.name),
            model.inertias[k].lever.as_slice(),
            &flat(&g["body_levers"][k]),
            TOL,
        );
    }
    let frames: Vec<(String, usize)> = g["frames"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| {
            let n = n.as_str().unwrap().to_string();
            let id = model.frame_id(&n).unwrap_or_else(|e| panic!("{case}: {e}"));
            (n, id)
        })
        .collect();
    let mut data = Data::new(&model);
    let mut jac = Matrix6xX::zeros(model.nv);
    let states = g["states"].as_array().unwrap();
    assert!(
        states.len() >= 10,
        "{case}: only {} golden states",
        states.len()
    );
    for (s, st) in states.iter().enumerate() {
        let ctx = |what: &str| format!("{case} state {s} {what}");
        let (q, v, a, tau) = (
            flat(&st["q"]),
            flat(&st["v"]),
            flat(&st["a"]),
            flat(&st["tau"]),
        );
        let (q, v, a, tau) = (q.as_slice(), v.as_slice(), a.as_slice(), tau.as_slice());
        let chk = |what: &str, ours: &[f64], key: &str| {
            assert_close(&ctx(what), ours, &flat(&st[key]), TOL)
        };

        chk("M", &mat_rows(crba(&model, &mut data, q).unwrap()), "M");
        chk(
            "Minv",
            &mat_rows(compute_minverse(&model, &mut data, q).unwrap()),
            "Minv",
        );
        chk(
            "nle",
            nonlinear_effects(&model, &mut data, q, v)
                .unwrap()
                .as_slice(),
            "nle",
        );
        chk(
            "g",
            generalized_gravity(&model, &mut data, q)
                .unwrap()
                .as_slice(),
            "g",
        );
        chk(
            "rnea",
            rnea(&model, &mut data, q, v, a).unwrap().as_slice(),
            "rnea",
        );
        chk(
            "aba",
            aba(&model, &mut data, q, v, tau).unwrap().as_slice(),
            "aba",
        );
        chk(
            "C",
            &mat_rows(coriolis_matrix(&model, &mut data, q, v).unwrap()),
            "C",
        );
        center_of_mass(&model, &mut data, q, v, a).unwrap();
        chk("com", data.com.as_slice(), "com");
        chk("vcom", data.vcom.as_slice(), "vcom");
        chk("acom", data.acom.as_slice(), "acom");
        let jcom = jacobian_center_of_mass(&model, &mut data, q).unwrap();
        chk(
            "Jcom",
            &(0..3)
                .flat_map(|r| jcom.row(r).iter().copied().collect::<Vec<_>>())
                .collect::<Vec<_>>(),
            "Jcom",
        );
        let hg = compute_centroidal_momentum(&model, &mut data, q, v).unwrap();
        chk("Ag", &mat6_rows(&data.ag), "Ag");
        chk("hg", hg.to_vector().as_slice(), "hg");
        let drift = centroidal_momentum_drift(&model, &mut data, q, v).unwrap();
        chk("dAg v", drift.to_vector().as_slice(), "dAg_v");
        let dhg = drift.to_vector() + &data.ag * nalgebra::DVector::from_column_slice(a);
        chk("dhg", dhg.as_slice(), "dhg");
        chk(
            "kinetic",
            &[kinetic_energy(&model, &mut data, q, v).unwrap()],
            "kinetic",
        );
        chk(
            "potential",
            &[potential_energy(&model, &mut data, q).unwrap()],
            "potential",
        );

        forward_kinematics(&model, &mut data, q, v, a).unwrap();
        for (k, jg) in st["joints"].as_array().unwrap().iter().enumerate() {
            let w = format!("joint {}", model.joints[k].name);
            assert_close(
                &ctx(&format!("{w} translation")),
                data.o_m_i[k].translation.as_slice(),
                &flat(&jg["translation"]),
                TOL,
            );
            assert_close(
                &ctx(&format!("{w} rotation")),
                data.o_m_i[k].rotation.transpose().as_slice(),
                &flat(&jg["rotation"]),
                TOL,
            );
            assert_close(
                &ctx(&format!("{w} v")),
                data.v[k].to_vector().as_slice(),
                &flat(&jg["v_local"]),
                TOL,
            );
            assert_close(
                &ctx(&format!("{w} a")),
                data.a[k].to_vector().as_slice(),
                &flat(&jg["a_local"]),
                TOL,
            );
        }
        compute_joint_jacobians(&model, &mut data, q).unwrap();
        chk("J (world)", &mat6_rows(&data.j), "J_world");
        for (name, fid) in &frames {
            let fg = &st["frames"][name.as_str()];
            let w = |x: &str| ctx(&format!("frame {name} {x}"));
            let m = frame_placement(&model, &data, *fid).unwrap();
            assert_close(
                &w("translation"),
                m.translation.as_slice(),
                &flat(&fg["translation"]),
                TOL,
            );
            assert_close(
                &w("rotation"),
                m.rotation.transpose().as_slice(),
                &flat(&fg["rotation"]),
                TOL,
            );
            for (rf, key) in [
                (ReferenceFrame::Local, "J_local"),
                (ReferenceFrame::World, "J_world"),
                (ReferenceFrame::LocalWorldAligned, "J_lwa"),
            ] {
                frame_jacobian(&model, &data, *fid, rf, &mut jac).unwrap();
                assert_close(&w(key), &mat6_rows(&jac), &flat(&fg[key]), TOL);
            }
            let acc = frame_classical_acceleration(
                &model,
                &data,
                *fid,
                ReferenceFrame::LocalWorldAligned,
            )
            .unwrap();
            assert_close(
                &w("classical acc"),
                acc.to_vector().as_slice(),
                &flat(&fg["classical_acc_lwa"]),
                TOL,
            );
            let sacc = frame_acceleration(&model, &data, *fid, ReferenceFrame::Local).unwrap();
            assert_close(
                &w("spatial acc"),
                sacc.to_vector().as_slice(),
                &flat(&fg["spatial_acc_local"]),
                TOL,
            );
            let vel = frame_velocity(&model, &data, *fid, ReferenceFrame::Local).unwrap();
            assert_close(
                &w("velocity"),
                vel.to_vector().as_slice(),
                &flat(&fg["velocity_local"]),
                TOL,
            );
            if !fg["Lambda_lwa"].is_null() {
                let l = frame_operational_space_inertia(
                    &model,
                    &mut data,
                    q,
                    *fid,
                    ReferenceFrame::LocalWorldAligned,
                )
                .unwrap_or_else(|e| panic!("{}: {e}", w("Lambda")));
                assert_close(
                    &w("Lambda"),
                    l.transpose().as_slice(),
                    &flat(&fg["Lambda_lwa"]),
                    TOL,
                );
                forward_kinematics(&model, &mut data, q, v, a).unwrap();
                compute_joint_jacobians(&model, &mut data, q).unwrap();
            }
        }
    }
}

#[test]
fn talos_matches_pinocchio() {
    check_case("talos");
}

#[test]
fn icub_matches_pinocchio() {
    check_case("icub");
}

#[test]
fn simple_humanoid_matches_pinocchio() {
    check_case("simple_humanoid");
}

#[test]
fn simple_humanoid_fixed_base_matches_pinocchio() {
    check_case("simple_humanoid_fixed");
}

#[test]
fn mixed_joint_types_match_pinocchio() {
    check_case("mixed_joints");
}
