//! The built-in descriptions load and agree with their models; every kind of bad description
//! is refused with one line naming its key.

use corps_robot::{Description, Robot, RobotError};
use std::path::{Path, PathBuf};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

#[test]
fn the_built_in_robots_load_with_their_feet_and_sensors() {
    for (name, mass, feet_gap) in [
        ("talos", 90.27, 0.17),
        ("icub", 28.35, 0.1),
        ("simple_humanoid", 0.0, 0.17),
    ] {
        let robot = Robot::built_in(name).unwrap().unwrap();
        let m = &robot.model;
        println!(
            "{name}: {:.3} kg, nv {}, feet {:?}, ankle heights {:?}",
            m.total_mass(),
            m.nv,
            robot.feet.iter().map(|f| &f.frame_name).collect::<Vec<_>>(),
            robot
                .feet
                .iter()
                .map(|f| f.ankle_height)
                .collect::<Vec<_>>()
        );
        if mass > 0.0 {
            assert!((m.total_mass() - mass).abs() < 0.05 * mass, "{name}");
        }
        assert_eq!(robot.feet.len(), 2, "{name}");
        assert!(
            robot.feet.iter().all(|f| f.force_torque.is_some()),
            "{name}"
        );
        assert!(robot.gains.contains_key("tsid_torque"), "{name}");
        // The feet are apart along y at the posture (left first).
        let mut data = corps_model::Data::new(m);
        corps_model::forward_kinematics_placements(m, &mut data, robot.posture.as_slice()).unwrap();
        let y = |k: usize| {
            corps_model::frame_placement(m, &data, robot.feet[k].frame)
                .unwrap()
                .translation
                .y
        };
        assert!(y(0) - y(1) > feet_gap * 0.5, "{name}: {} {}", y(0), y(1));
    }
}

#[test]
fn a_description_file_on_disk_resolves_its_paths_from_its_directory() {
    let path = repo().join("robots/talos_data/talos.toml");
    let robot = Robot::resolve(path.to_str().unwrap(), Path::new("/")).unwrap();
    assert_eq!(robot.name, "talos");
    assert_eq!(robot.feet[1].label, "right");
    assert!(robot.gains["tsid_position"]
        .shown
        .ends_with("tsid_position.toml"));
}

/// Writes TALOS' description with `edit` applied into a temporary directory beside copies of
/// its model files, and loads it.
fn talos_with(edit: impl Fn(&str) -> String) -> Result<Robot, RobotError> {
    let dir = tempfile::tempdir().unwrap();
    let src = repo().join("robots/talos_data");
    std::fs::create_dir_all(dir.path().join("robots")).unwrap();
    std::fs::create_dir_all(dir.path().join("srdf")).unwrap();
    for f in ["robots/talos_reduced_box.urdf", "srdf/talos.srdf"] {
        std::fs::copy(src.join(f), dir.path().join(f)).unwrap();
    }
    let text = std::fs::read_to_string(src.join("talos.toml")).unwrap();
    let text = text.replace("../../config", &repo().join("config").display().to_string());
    let path = dir.path().join("robot.toml");
    std::fs::write(&path, edit(&text)).unwrap();
    Robot::from_file(&path)
}

#[test]
fn bad_descriptions_are_refused_with_one_line_naming_the_key() {
    let cases: [(&str, &str, &str); 13] = [
        ("delay_periods = 1", "delay_periods = 1\nideal = [\"head_9_joint\"]", "drives.ideal: the model has no joint 'head_9_joint'"),
        ("stiffness = 1.5e4", "stiffnes = 1.5e4", "unknown field `stiffnes`"),
        ("frame = \"leg_left_sole_fix_joint\"", "frame = \"left_sole_nowhere\"", "feet[0].frame: no frame named 'left_sole_nowhere'"),
        ("ankle = [\"leg_left_5_joint\"", "ankle = [\"leg_left_9_joint\"", "feet[0].ankle: no joint named 'leg_left_9_joint'"),
        ("sole = { front = 0.1, back = 0.1, left = 0.065, right = 0.065 }\nforce_torque = \"left_ankle\"", "sole = { front = 0.1, back = 0.1, left = 0.0, right = 0.0 }\nforce_torque = \"left_ankle\"", "feet[0].sole: the rectangle has zero area"),
        ("base = \"base_link\"", "base = \"pelvis\"", "base: no frame named 'pelvis'"),
        ("posture = \"half_sitting\"", "posture = \"crouch\"", "posture:"),
        ("force_torque = \"left_ankle\"\nankle", "force_torque = \"left_heel\"\nankle", "feet[0].force_torque: 'left_heel'"),
        ("name = \"talos\"", "name = \"talos\"\nmass = 90.0", "unknown field `mass`"),
        ("[gains]", "[limits.effort]\nleg_left_1_joint = -1.0\n[gains]", "limits.effort.leg_left_1_joint: must be a finite number > 0"),
        ("tsid_torque = \"", "tsid_torque = \"missing/", "gains.tsid_torque: cannot read"),
        ("ankle = [\"leg_left_5_joint\"", "ankle = [\"root_joint\"", "feet[0].ankle: must name two one-axis joints"),
        ("sole = { front = 0.1, back = 0.1, left = 0.065, right = 0.065 }\nforce_torque = \"left_ankle\"", "sole = { front = 0.1, back = -0.05, left = 0.065, right = 0.065 }\nforce_torque = \"left_ankle\"", "feet[0].sole: front, back, left and right are distances"),
    ];
    for (from, to, expected) in cases {
        let e = talos_with(|t| {
            assert!(t.contains(from), "{from}");
            t.replacen(from, to, 1)
        })
        .unwrap_err()
        .to_string();
        assert!(e.contains(expected), "{to}: {e}");
        assert!(!e.contains('\n'), "{e}");
    }
}

#[test]
fn feet_without_a_primitive_cannot_touch_the_ground_unless_the_sole_is_simulated() {
    // TALOS' original URDF has mesh feet.
    let dir = tempfile::tempdir().unwrap();
    let src = repo().join("robots/talos_data");
    std::fs::create_dir_all(dir.path().join("robots")).unwrap();
    std::fs::create_dir_all(dir.path().join("srdf")).unwrap();
    std::fs::copy(
        src.join("robots/talos_reduced.urdf"),
        dir.path().join("robots/talos_reduced_box.urdf"),
    )
    .unwrap();
    std::fs::copy(
        src.join("srdf/talos.srdf"),
        dir.path().join("srdf/talos.srdf"),
    )
    .unwrap();
    let text = std::fs::read_to_string(src.join("talos.toml")).unwrap();
    let text = text.split("[gains]").next().unwrap().to_string();
    let path = dir.path().join("robot.toml");
    std::fs::write(&path, &text).unwrap();
    let e = Robot::from_file(&path).unwrap_err().to_string();
    assert!(
        e.contains("feet[0].contact") && e.contains("cannot touch the ground"),
        "{e}"
    );
    let text = text.replace(
        "ankle = [\"leg_left_5",
        "contact = \"sole_box\"\nankle = [\"leg_left_5",
    );
    let text = text.replace(
        "ankle = [\"leg_right_5",
        "contact = \"sole_box\"\nankle = [\"leg_right_5",
    );
    std::fs::write(&path, &text).unwrap();
    let robot = Robot::from_file(&path).unwrap();
    assert!(robot
        .model
        .collisions
        .iter()
        .any(|c| c.link == "left_sole_box"));
}

#[test]
fn a_drafted_description_parses_and_finds_the_feet() {
    for (name, urdf) in [
        ("talos", "robots/talos_data/robots/talos_reduced_box.urdf"),
        ("icub", "robots/icub_description/robots/icub.urdf"),
        (
            "simple_humanoid",
            "robots/simple_humanoid_description/urdf/simple_humanoid.urdf",
        ),
    ] {
        let robot = Robot::built_in(name).unwrap().unwrap();
        let text = corps_robot::init::draft(&robot.model, urdf, Some("robot.srdf"));
        let d: Description =
            corps_robot::toml_text::parse(&text).unwrap_or_else(|e| panic!("{name}: {e}\n{text}"));
        assert_eq!(d.feet.len(), 2, "{name}:\n{text}");
        assert!(text.contains("CHECK"), "{name}");
        if name == "talos" {
            assert!(text.contains("parent = \"leg_left_6_link\""), "{text}");
        }
    }
}
