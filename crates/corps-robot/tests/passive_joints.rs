//! Passive joints: the simulator's variant of a description (seed 000 App. 4) has them, the
//! rigid model does not, and both are the same robot everywhere else.

use corps_model::{forward_kinematics_placements, Data};
use corps_robot::Robot;
use std::path::Path;

fn flexible() -> Robot {
    Robot::built_in("talos_flexible_hip").unwrap().unwrap()
}

#[test]
fn the_plant_model_has_four_more_joints_and_the_same_body() {
    let robot = flexible();
    let rigid = Robot::built_in("talos").unwrap().unwrap();
    assert_eq!(
        robot.model.nq, rigid.model.nq,
        "the controllers' model stays rigid"
    );
    let plant = robot.plant.as_ref().expect("a plant variant");
    assert_eq!(plant.model.nq, rigid.model.nq + 4);
    assert_eq!(plant.model.nv, rigid.model.nv + 4);
    assert!((plant.model.total_mass() - rigid.model.total_mass()).abs() < 1e-12);
    let names: Vec<&str> = plant.passive.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "leg_left_hip_flex_roll",
            "leg_left_hip_flex_pitch",
            "leg_right_hip_flex_roll",
            "leg_right_hip_flex_pitch"
        ]
    );
    assert_eq!(plant.passive[0].stiffness, 3000.0);
    assert_eq!(plant.passive[2].stiffness, 4750.0);
    let roll = plant.passive[0].compensated_by.unwrap();
    assert_eq!(robot.model.joints[roll].name, "leg_left_2_joint");

    // With the passive joints at zero, every frame sits where the rigid model puts it.
    let q_rigid = &rigid.posture;
    let mut q_plant = nalgebra::DVector::zeros(plant.model.nq);
    for (j, joint) in rigid.model.joints.iter().enumerate() {
        let pj = plant.model.joint_id(&joint.name).unwrap();
        let (a, b) = (joint.idx_q, plant.model.joints[pj].idx_q);
        for k in 0..joint.nq() {
            q_plant[b + k] = q_rigid[a + k];
        }
        assert_eq!(joint.nq(), plant.model.joints[pj].nq(), "joint {j}");
    }
    let mut d_rigid = Data::new(&rigid.model);
    let mut d_plant = Data::new(&plant.model);
    forward_kinematics_placements(&rigid.model, &mut d_rigid, q_rigid.as_slice()).unwrap();
    forward_kinematics_placements(&plant.model, &mut d_plant, q_plant.as_slice()).unwrap();
    for f in &robot.feet {
        let pf = plant.model.frame_id(&f.frame_name).unwrap();
        let a = rigid.model.frames[f.frame].parent_joint.unwrap();
        let b = plant.model.frames[pf].parent_joint.unwrap();
        let ta = (d_rigid.o_m_i[a] * rigid.model.frames[f.frame].placement).translation;
        let tb = (d_plant.o_m_i[b] * plant.model.frames[pf].placement).translation;
        assert!((ta - tb).norm() < 1e-12, "{}: {ta} vs {tb}", f.label);
    }
}

fn with_passive(entry: &str) -> Result<Robot, String> {
    let dir = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let talos = root.join("robots/talos_data");
    let abs = |p: &Path| p.canonicalize().unwrap().display().to_string();
    let text = std::fs::read_to_string(talos.join("talos.toml"))
        .unwrap()
        .replace("\"robots/", &format!("\"{}/", abs(&talos.join("robots"))))
        .replace("\"srdf/", &format!("\"{}/", abs(&talos.join("srdf"))))
        .replace(
            "\"../../config/",
            &format!("\"{}/", abs(&root.join("config"))),
        );
    let path = dir.path().join("x.toml");
    std::fs::write(&path, format!("{text}\n[[passive_joints]]\n{entry}\n")).unwrap();
    Robot::from_file(&path).map_err(|e| e.to_string())
}

#[test]
fn bad_passive_joints_are_refused_with_the_key() {
    let ok = "name = \"p\"\nbefore = \"leg_left_1_joint\"\naxis = [1.0, 0.0, 0.0]\nstiffness = 3000.0\ndamping = 50.0";
    assert!(with_passive(ok).is_ok(), "{:?}", with_passive(ok).err());
    for (entry, expected) in [
        (ok.replace("3000.0", "0.0"), "passive_joints[0].stiffness"),
        (ok.replace("3000.0", "-5.0"), "passive_joints[0].stiffness"),
        (ok.replace("3000.0", "nan"), "passive_joints[0].stiffness"),
        (ok.replace("3000.0", "inf"), "passive_joints[0].stiffness"),
        (
            ok.replace("damping = 50.0", "damping = -1.0"),
            "passive_joints[0].damping",
        ),
        (
            ok.replace("[1.0, 0.0, 0.0]", "[0.0, 0.0, 0.0]"),
            "passive_joints[0].axis",
        ),
        (
            ok.replace("leg_left_1_joint", "no_such_joint"),
            "passive_joints[0].before",
        ),
        (
            ok.replace("name = \"p\"", "name = \"leg_left_2_joint\""),
            "passive_joints[0].name",
        ),
        (
            format!("{ok}\ncompensated_by = \"nope\""),
            "passive_joints[0].compensated_by",
        ),
        (
            format!(
                "{ok}\ncompensated_by = \"leg_left_2_joint\"\n[[passive_joints]]\n{}\ncompensated_by = \"leg_left_2_joint\"",
                ok.replace("name = \"p\"", "name = \"q\"")
            ),
            "passive_joints[1].compensated_by",
        ),
    ] {
        let err = with_passive(&entry).expect_err(&entry);
        assert!(err.contains(expected), "{entry}: {err}");
    }
}
