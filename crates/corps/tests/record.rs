//! `corps run --record`: the MCAP file reads back with Foxglove's own MCAP reader (the `mcap`
//! crate) and holds the robot, its motion and the log: the signals equal the CSV log row for
//! row, the markers' CoM is the logged CoM, every joint frame moves, and the robot's shapes
//! are there (its URDF meshes where the files are found).

use corps_mocap::skeleton::Units;
use corps_mocap::source::{ClipSource, MocapSource};
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::process::Command;

fn repo(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

/// Messages of each topic: (log time in ns, JSON).
fn read(path: &std::path::Path) -> BTreeMap<String, Vec<(u64, Value)>> {
    let bytes = std::fs::read(path).expect("the recording");
    let mut topics: BTreeMap<String, Vec<(u64, Value)>> = BTreeMap::new();
    for message in mcap::MessageStream::new(&bytes).expect("an MCAP file") {
        let message = message.expect("a well-formed message");
        assert_eq!(message.channel.message_encoding, "json");
        let schema = message.channel.schema.as_ref().expect("a schema");
        assert_eq!(schema.encoding, "jsonschema");
        let json: Value = serde_json::from_slice(&message.data).expect("JSON");
        topics
            .entry(message.channel.topic.clone())
            .or_default()
            .push((message.log_time, json));
    }
    topics
}

fn log(path: &std::path::Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).expect("the log");
    let mut lines = text.lines();
    let header = lines
        .next()
        .expect("a header")
        .split(',')
        .map(String::from)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(|x| x.parse().expect("a number")).collect())
        .collect();
    (header, rows)
}

/// Runs `corps run SCENARIO EXTRA… --record -o DIR` into a new directory, which it returns.
fn record(scenario: &str, extra: &[&str]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().expect("a directory");
    let out = Command::new(env!("CARGO_BIN_EXE_corps"))
        .current_dir(repo(""))
        .args(["run", scenario])
        .args(extra)
        .args(["--record", "-o"])
        .arg(dir.path())
        .output()
        .expect("runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    dir
}

#[test]
fn a_recorded_walk_reads_back() {
    let dir = record("scenarios/walk/tsid_torque_20cm.toml", &["--duration", "6"]);
    assert!(!dir.path().join("run.mcap.partial").exists());
    let topics = read(&dir.path().join("run.mcap"));
    let (header, rows) = log(&dir.path().join("log.csv"));

    // The signals are the log, value for value (to the last bits serde_json's reader keeps:
    // both files hold the shortest round-trip decimal of the same double).
    let same = |a: Option<f64>, b: f64| a.is_some_and(|a| (a - b).abs() <= 4e-16 * b.abs());
    let signals = &topics["/signals"];
    assert_eq!(signals.len(), rows.len());
    for ((_, s), row) in signals.iter().zip(&rows) {
        for (name, value) in header.iter().zip(row) {
            if name != "tick_us" {
                assert!(
                    same(s[name].as_f64(), *value),
                    "{name}: {} vs {value}",
                    s[name]
                );
            }
        }
    }

    // The robot: one scene of shapes locked to joint frames, meshes where found.
    let robot = &topics["/robot"];
    assert_eq!(robot.len(), 1);
    let entities = robot[0].1["entities"].as_array().expect("entities");
    assert!(entities.len() > 20);
    let meshes = entities
        .iter()
        .filter(|e| e.get("models").is_some())
        .count();
    if repo("../shared/robots/example-robot-data/talos_data/meshes").is_dir() {
        assert!(meshes > 20, "{meshes} meshes");
    }
    for e in entities {
        assert_eq!(e["frame_locked"], Value::Bool(true));
        assert!(e["frame_id"]
            .as_str()
            .expect("a frame")
            .starts_with("joint/"));
    }

    // Transforms: every joint frame at 50 Hz, and the feet move.
    let tf = &topics["/tf"];
    assert_eq!(tf.len(), 300);
    let transforms = |k: usize| {
        tf[k].1["transforms"]
            .as_array()
            .expect("transforms")
            .clone()
    };
    assert_eq!(transforms(0).len(), 33);
    let foot = |k: usize| {
        transforms(k)
            .into_iter()
            .find(|t| t["child_frame_id"] == "joint/leg_left_6_joint")
            .expect("the left ankle")["translation"]["x"]
            .as_f64()
            .expect("x")
    };
    assert!(foot(299) - foot(0) > 0.1, "the left foot walked");

    // Markers: the CoM sphere where the log puts the CoM, footprints where feet landed.
    let by_time: BTreeMap<u64, &Value> = signals.iter().map(|(t, v)| (*t, v)).collect();
    for (t, m) in &topics["/markers"] {
        let Some(s) = by_time.get(t) else { continue };
        let points = &m["entities"][0]["spheres"][0]["pose"]["position"];
        assert_eq!(points["x"], s["com_x"]);
        assert_eq!(points["z"], s["com_z"]);
    }
    let last = &topics["/markers"].last().expect("markers").1;
    let lines = last["entities"][1]["lines"]
        .as_array()
        .expect("lines")
        .len();
    assert!(
        lines >= 3,
        "{lines} lines: the CoM's drop line, a sole, the support hull"
    );
    let prints: usize = (topics["/markers"].iter())
        .map(|(_, m)| {
            let entities = m["entities"].as_array().expect("entities");
            (entities.iter())
                .filter(|e| {
                    e["id"]
                        .as_str()
                        .is_some_and(|id| id.starts_with("footprint/"))
                })
                .count()
        })
        .sum();
    assert!(
        prints >= 4,
        "{prints} footprints: both feet at the start, then each landing"
    );
    // One arrow a foot on the ground, at its centre of pressure.
    for (_, m) in &topics["/markers"] {
        let arrows = m["entities"][2]["arrows"].as_array().expect("arrows").len();
        assert!((1..=2).contains(&arrows), "{arrows} contact forces");
    }
    let first = &topics["/markers"][0].1["entities"][2]["arrows"];
    assert_eq!(
        first.as_array().expect("arrows").len(),
        2,
        "standing on both feet"
    );
}

/// A teleoperation run from a clip records the operator's skeleton beside the robot: every
/// joint of the clip at each view, standing on the ground about `BESIDE` to the robot's left
/// at the start, the hands rising with the clip's raised hands; a run without an operator
/// writes no `/operator` message.
#[test]
fn a_teleoperation_recording_shows_the_operator() {
    let dir = record("scenarios/teleop/talos_raise_hands.toml", &[]);
    let topics = read(&dir.path().join("run.mcap"));
    let clip = corps_mocap::bvh::Bvh::read(&repo(
        "../shared/data/mocap/dataset-2_raise-up-both-hands_normal_001.bvh",
    ))
    .expect("the clip");
    let operator = &topics["/operator"];
    assert_eq!(operator.len(), topics["/tf"].len(), "one skeleton per view");
    let joints = |k: usize| -> Vec<[f64; 3]> {
        let e = &operator[k].1["entities"][0];
        assert_eq!(e["frame_id"], "world");
        (e["spheres"].as_array().expect("joints").iter())
            .map(|s| {
                let p = &s["pose"]["position"];
                ["x", "y", "z"].map(|a| p[a].as_f64().expect("a number"))
            })
            .collect()
    };
    let (first, last) = (joints(0), joints(operator.len() - 1));
    assert_eq!(first.len(), clip.joints.len());
    let bones = operator[0].1["entities"][0]["lines"][0]["points"]
        .as_array()
        .expect("bones")
        .len();
    assert_eq!(bones, 2 * (clip.joints.len() - 1), "a segment per bone");
    let lowest = first.iter().map(|j| j[2]).fold(f64::INFINITY, f64::min);
    assert!(lowest.abs() < 1e-9, "lowest joint at {lowest} m");
    let signals = &topics["/signals"];
    let com_y = signals[0].1["com_y"].as_f64().expect("com_y");
    assert!((first[0][1] - com_y - 1.0).abs() < 1e-9, "beside the robot");
    // The views follow the clip as the controller reads it (`ClipSource::poll` at the view's
    // time): every joint where the clip puts it, moved by one constant shift.
    let mut source = ClipSource::new(clip.clone(), Units::default());
    let mut shift = None;
    for (k, (t_ns, _)) in operator.iter().enumerate() {
        let t = *t_ns as f64 * 1e-9;
        let (pose, _) = source.poll(t);
        let drawn = joints(k);
        for (j, at) in pose.world.iter().enumerate() {
            let p = at.translation.vector;
            let d = [drawn[j][0] - p.x, drawn[j][1] - p.y, drawn[j][2] - p.z];
            let s = *shift.get_or_insert(d);
            let off = (0..3).map(|a| (d[a] - s[a]).abs()).fold(0.0, f64::max);
            assert!(off < 1e-9, "{t} s, joint {j}: {off} m off the clip's pose");
        }
    }
    let hand = clip.joint("Hand_L").expect("Hand_L");
    let highest = (0..operator.len())
        .map(|k| joints(k)[hand][2])
        .fold(f64::NEG_INFINITY, f64::max);
    println!(
        "left hand: {:.3} m at the start, {highest:.3} m at most, {:.3} m at the end",
        first[hand][2], last[hand][2]
    );
    assert!(
        highest - first[hand][2] > 0.3,
        "the hands go up in this clip"
    );

    let dir = record(
        "scenarios/walk/tsid_torque_20cm.toml",
        &["--duration", "0.5"],
    );
    assert!(!read(&dir.path().join("run.mcap")).contains_key("/operator"));
}
