//! BVH input written here (two joints, six and three channels): read right, and every fault
//! the reader must catch named with its file and line before any frame is used.

use corps_mocap::bvh::Bvh;
use corps_mocap::retarget::Mapping;
use corps_mocap::skeleton::{Skeleton, Units};

const GOOD: &str = "HIERARCHY
ROOT Hips
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT Arm
  {
    OFFSET 10 0 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    End Site
    {
      OFFSET 20 0 0
    }
  }
}
MOTION
Frames: 2
Frame Time: 0.04
0 90 0 0 0 0 0 0 0
0 90 0 0 0 0 90 0 0
";

fn error(text: &str) -> String {
    Bvh::parse(text, "clip.bvh").unwrap_err().to_string()
}

#[test]
fn a_small_file_reads_and_poses_in_corps_world() {
    let bvh = Bvh::parse(GOOD, "clip.bvh").unwrap();
    assert_eq!((bvh.joints.len(), bvh.channels, bvh.frames()), (2, 9, 2));
    assert_eq!(bvh.joints[1].first_channel, 6);
    let skeleton = Skeleton::new(&bvh, Units::default());
    // Frame 0: hips 0.9 m up (file y → corps z); the arm 0.1 m along file x → corps y.
    let p = skeleton.pose(bvh.frame(0), 0.0);
    let arm = p.world[1].translation.vector;
    assert!(
        (arm - nalgebra::Vector3::new(0.0, 0.1, 0.9)).norm() < 1e-12,
        "{arm:?}"
    );
    // Frame 1: the arm turned 90° about file z; its end site would point along file y, up.
    let p = skeleton.pose(bvh.frame(1), 0.04);
    let tip = p.world[1] * nalgebra::Point3::new(20.0 * 0.01, 0.0, 0.0);
    assert!(
        (tip.coords - nalgebra::Vector3::new(0.0, 0.1, 1.1)).norm() < 1e-12,
        "{tip:?}"
    );
}

#[test]
fn a_byte_order_mark_is_read_past() {
    let bvh = Bvh::parse(&format!("\u{feff}{GOOD}"), "clip.bvh").unwrap();
    assert_eq!(bvh.frames(), 2);
}

#[test]
fn every_fault_is_one_line_naming_the_file_and_the_line() {
    // Cut while writing the last frame.
    let cut = &GOOD[..GOOD.len() - 8];
    let cases: Vec<(String, &str)> = vec![
        (
            cut.to_string(),
            "line 20: frame 1 has 6 values where the hierarchy has 9 channels",
        ),
        (
            GOOD.replace("Frames: 2", "Frames: 3"),
            "line 20: the file ends after 2 of the 3 frames",
        ),
        (
            GOOD.replace("0 90 0 0 0 0 90 0 0", "0 90 0 0 nan 0 90 0 0"),
            "line 20: frame 1: 'nan' is not a finite number",
        ),
        (
            GOOD.replace("0 90 0 0 0 0 90 0 0", "0 90 0 0 inf 0 90 0 0"),
            "'inf' is not a finite number",
        ),
        (
            GOOD.replace("Frame Time: 0.04", "Frame Time: 0"),
            "line 18: Frame Time 0 s: must be > 0",
        ),
        (
            GOOD.replace("Frame Time: 0.04", "Frame Time: -0.1"),
            "must be > 0",
        ),
        (
            GOOD.replace("0 90 0 0 0 0 90 0 0", "0 90 0 0 0 0 90 0"),
            "frame 1 has 8 values where the hierarchy has 9 channels",
        ),
        (
            GOOD.replace("CHANNELS 3 Zrotation", "CHANNELS 3 Wrotation"),
            "'Wrotation' is not a channel",
        ),
        (GOOD[..200].to_string(), "the file ends where"),
        (GOOD.replace("Frames: 2", "Frames: 0"), "no frame"),
        (String::new(), "the file ends where HIERARCHY was expected"),
        (
            GOOD.replace("Frames: 2", "Frames: 1000000000000"),
            "line 20: the file ends after 2 of the 1000000000000 frames",
        ),
        (
            GOOD.replace("Frame Time: 0.04", "Frame Time: 0.04 0 90"),
            "line 18: '0' after the frame time",
        ),
        (
            GOOD.replace(
                "CHANNELS 3 Zrotation Xrotation Yrotation",
                "CHANNELS 3 Zrotation Xrotation Yrotation\n    CHANNELS 1 Xposition",
            ),
            "joint 'Arm': CHANNELS given twice",
        ),
    ];
    for (text, words) in cases {
        let e = error(&text);
        assert!(e.starts_with("clip.bvh: line "), "{e}");
        assert!(e.contains(words), "expected '{words}' in: {e}");
        assert_eq!(e.lines().count(), 1, "{e}");
    }
}

#[test]
fn a_mapping_naming_a_joint_the_robot_or_the_skeleton_lacks_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let repo = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let text = std::fs::read_to_string(repo.join("config/icub/retargeting.toml")).unwrap();
    let text = text.replace(
        "robot = \"../../robots/icub_description/icub_teleop.toml\"",
        &format!(
            "robot = \"{}\"",
            repo.join("robots/icub_description/icub_teleop.toml")
                .display()
        ),
    );
    // A shared clip's skeleton (any of them: the 21-joint layout the mapping names).
    let shared = std::fs::read_dir(repo.join("../shared/data/mocap"))
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .find(|p| p.extension().is_some_and(|e| e == "bvh"))
        .unwrap();
    let bvh = Bvh::read(&shared).unwrap();
    for (from, to, words) in [
        ("\"l_elbow\"", "\"l_elbw\"", "has no joint 'l_elbw'"),
        (
            "waist = \"Hips\"",
            "waist = \"Pelvis\"",
            "skeleton.waist: the skeleton has no joint 'Pelvis'",
        ),
        (
            "lift = 0.05",
            "lift = 0.01",
            "steps.land: must be below steps.lift",
        ),
    ] {
        let path = dir.path().join("m.toml");
        std::fs::write(&path, text.replace(from, to)).unwrap();
        let e = match Mapping::read(&path) {
            Err(e) => e.to_string(),
            Ok(m) => corps_mocap::replay::retarget_clip(&m, &bvh)
                .unwrap_err()
                .to_string(),
        };
        assert!(e.contains("m.toml") && e.contains(words), "{e}");
    }
}
