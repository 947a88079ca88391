//! A description that extends another and adds a rigid body (the backpacked iCub of seed 001
//! ch. 5): the added body's mass and first moment appear in the model exactly (total mass,
//! CoM at the posture against the weighted mean of the two), the rest of the base description
//! is inherited, and bad added bodies or extension chains are refused with one line.

use corps_model::{com_at_placements, forward_kinematics_placements, frame_placement, Data};
use corps_robot::Robot;
use nalgebra::Vector3;
use std::path::Path;

fn repo_icub_dir() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../robots/icub_description")
}

#[test]
fn the_backpacked_icub_is_the_icub_plus_its_pack() {
    let plain = Robot::built_in("icub").unwrap().unwrap();
    let packed = Robot::built_in("icub_backpacked").unwrap().unwrap();
    assert_eq!(packed.name, "icub_backpacked");
    assert_eq!(packed.model.nv, plain.model.nv);
    assert_eq!(packed.feet.len(), 2);
    assert_eq!(
        packed.gains.keys().collect::<Vec<_>>(),
        plain.gains.keys().collect::<Vec<_>>()
    );
    let dm = packed.model.total_mass() - plain.model.total_mass();
    assert!((dm - 1.8).abs() < 1e-12, "added {dm} kg");
    // CoM at the posture: (m c + m_p p) / (m + m_p), p the pack's centre in the world.
    let q = &plain.posture;
    let mut data = Data::new(&plain.model);
    forward_kinematics_placements(&plain.model, &mut data, q.as_slice()).unwrap();
    let (c_plain, _) = com_at_placements(&plain.model, &data);
    let m_plain = plain.model.total_mass();
    let chest = plain.model.frame_id("chest").unwrap();
    let p = frame_placement(&plain.model, &data, chest)
        .unwrap()
        .act_point(&Vector3::new(-0.12, 0.12, 0.0));
    let mut data_p = Data::new(&packed.model);
    forward_kinematics_placements(&packed.model, &mut data_p, q.as_slice()).unwrap();
    let (c_packed, _) = com_at_placements(&packed.model, &data_p);
    let expected = (c_plain * m_plain + p * 1.8) / (m_plain + 1.8);
    println!("CoM {c_plain:?} → {c_packed:?}, pack at {p:?}");
    assert!((c_packed - expected).norm() < 1e-12);
    // The pack is behind the robot (it faces +x): the CoM moves back.
    assert!(c_packed.x < c_plain.x);
}

fn write(dir: &Path, name: &str, text: &str) {
    std::fs::write(dir.join(name), text).unwrap();
}

#[test]
fn bad_added_bodies_and_extension_chains_are_refused_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    // A copy of the iCub's directory, so that paths resolve (its gains files read from the
    // repository).
    let config = repo_icub_dir()
        .join("../../config/")
        .canonicalize()
        .unwrap();
    let icub = std::fs::read_to_string(repo_icub_dir().join("icub.toml")).unwrap();
    let icub = icub.replace("\"../../config/", &format!("\"{}/", config.display()));
    write(dir.path(), "icub.toml", &icub);
    std::fs::create_dir_all(dir.path().join("robots")).unwrap();
    std::fs::create_dir_all(dir.path().join("srdf")).unwrap();
    std::fs::copy(
        repo_icub_dir().join("robots/icub.urdf"),
        dir.path().join("robots/icub.urdf"),
    )
    .unwrap();
    std::fs::copy(
        repo_icub_dir().join("srdf/icub.srdf"),
        dir.path().join("srdf/icub.srdf"),
    )
    .unwrap();
    let body = |edit: &str| {
        format!(
            "extends = \"icub.toml\"\nname = \"x\"\n[[added_bodies]]\nname = \"pack\"\nlink = \"chest\"\nmass = 1.0\ncom = [0.0, 0.0, 0.0]\ninertia = [0.01, 0.01, 0.01, 0.0, 0.0, 0.0]\n{edit}"
        )
    };
    for (text, expected) in [
        (
            body("").replace("link = \"chest\"", "link = \"nowhere\""),
            "no link named 'nowhere'",
        ),
        (
            body("").replace("mass = 1.0", "mass = -1.0"),
            "mass must be",
        ),
        (
            body("").replace(
                "[0.01, 0.01, 0.01, 0.0, 0.0, 0.0]",
                "[0.01, 0.01, 0.1, 0.0, 0.0, 0.0]",
            ),
            "triangle inequality",
        ),
        (
            body("").replace(
                "[0.01, 0.01, 0.01, 0.0, 0.0, 0.0]",
                "[0.01, 0.01, -0.01, 0.0, 0.0, 0.0]",
            ),
            "positive definite",
        ),
        (
            body("").replace("extends = \"icub.toml\"", "extends = \"../icub.toml\""),
            "same directory",
        ),
        (
            body("").replace("extends = \"icub.toml\"", "extends = \"missing.toml\""),
            "extends",
        ),
        (
            body("").replace("extends = \"icub.toml\"", "extends = \"x.toml\""),
            "deep",
        ),
    ] {
        write(dir.path(), "x.toml", &text);
        let err = Robot::from_file(&dir.path().join("x.toml"))
            .unwrap_err()
            .to_string();
        println!("{err}");
        assert!(err.contains(expected), "{err}");
        assert_eq!(err.lines().count(), 1, "{err}");
    }
    // The good one loads and keeps the base's feet and gains.
    write(dir.path(), "x.toml", &body(""));
    let robot = Robot::from_file(&dir.path().join("x.toml")).unwrap();
    assert_eq!(robot.name, "x");
    assert!(robot.gains.contains_key("soft_tasks"));
}

/// iCub's description locks its neck and wrists at half-sitting: 9 fewer dofs, the same mass,
/// and at half-sitting the same CoM and the same sole position, in the root link's frame, as
/// the full URDF model's (the description's inertia floor only lifts moments, not masses or
/// centres). Locking a joint the URDF lacks, or a fixed one, is refused.
#[test]
fn locked_joints_keep_the_robot_where_it_was() {
    let locked = Robot::built_in("icub").unwrap().unwrap();
    let dir = repo_icub_dir();
    let urdf = std::fs::read_to_string(dir.join("robots/icub.urdf")).unwrap();
    let srdf = std::fs::read_to_string(dir.join("srdf/icub.srdf")).unwrap();
    let mut full =
        corps_model::build_model_from_urdf_str(&urdf, corps_model::RootJoint::FreeFlyer).unwrap();
    corps_model::parse::load_reference_configurations_str(&mut full, &srdf).unwrap();
    let m = &locked.model;
    assert_eq!(full.nv - m.nv, 9);
    let com = |model: &corps_model::Model| {
        let q = model
            .reference_configuration("half_sitting")
            .unwrap()
            .clone();
        let mut data = Data::new(model);
        forward_kinematics_placements(model, &mut data, q.as_slice()).unwrap();
        // In the root link's frame: the description turns the posture's base to level the soles.
        let base = frame_placement(model, &data, model.frame_id("root_link").unwrap()).unwrap();
        let sole = frame_placement(model, &data, model.frame_id("l_sole").unwrap()).unwrap();
        let c = com_at_placements(model, &data).0;
        let local = |p: Vector3<f64>| base.rotation.transpose() * (p - base.translation);
        (local(c), local(sole.translation))
    };
    let (c_full, sole_full) = com(&full);
    let (c_locked, sole_locked) = com(m);
    println!(
        "mass {} / {}, CoM {c_full:?} / {c_locked:?}",
        full.total_mass(),
        m.total_mass()
    );
    assert!((full.total_mass() - m.total_mass()).abs() < 1e-9);
    assert!((c_full - c_locked).norm() < 1e-12);
    assert!((sole_full - sole_locked).norm() < 1e-12);
    let err = corps_model::build_model_from_urdf_str_locked(
        &urdf,
        corps_model::RootJoint::FreeFlyer,
        &[("no_such_joint".to_string(), 0.0)],
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("no_such_joint"), "{err}");
    let err = corps_model::build_model_from_urdf_str_locked(
        &urdf,
        corps_model::RootJoint::FreeFlyer,
        &[("l_sole_fixed_joint".to_string(), 0.0)],
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("one-dof"), "{err}");
}
