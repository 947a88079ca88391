//! The shared motion-capture clips (`../shared/data/mocap`: real people, read in place — their
//! license allows no modified copies) read and retargeted onto iCub and TALOS, the mapping's
//! signs checked by the robots' own kinematics: where the operator's hands go up, the robot's
//! go up; where the operator bows, the robot's chest goes forward.

use corps_mocap::bvh::Bvh;
use corps_mocap::replay::{retarget_clip, Retargeted};
use corps_mocap::retarget::Mapping;
use corps_mocap::skeleton::Skeleton;
use corps_robot::Robot;
use nalgebra::{DVector, Vector3};
use std::path::PathBuf;

fn repo(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

/// Every shared clip (any the folder holds).
fn clips() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(repo("../shared/data/mocap"))
        .expect("../shared/data/mocap")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "bvh"))
        .collect();
    v.sort();
    assert!(!v.is_empty());
    v
}

fn find(word: &str) -> PathBuf {
    clips()
        .into_iter()
        .find(|p| p.file_name().unwrap().to_string_lossy().contains(word))
        .unwrap_or_else(|| panic!("no shared clip named *{word}*"))
}

fn mapping(robot: &str) -> Mapping {
    Mapping::read(&repo(&format!("config/{robot}/retargeting.toml"))).unwrap()
}

/// The robot at its rest posture with the retargeted joints of frame `k` set.
fn robot_q(robot: &Robot, r: &Retargeted, k: usize) -> DVector<f64> {
    let mut q = robot.posture.clone();
    for (j, v) in r.joints.iter().zip(&r.clipped[k]) {
        q[j.q_index] = *v;
    }
    q
}

fn frame_position(robot: &Robot, q: &DVector<f64>, frame: usize) -> Vector3<f64> {
    let mut data = corps_model::Data::new(&robot.model);
    corps_model::forward_kinematics_placements(&robot.model, &mut data, q.as_slice()).unwrap();
    corps_model::update_frame_placements(&robot.model, &mut data);
    data.o_m_f[frame].translation
}

#[test]
fn every_shared_clip_reads_and_retargets_within_the_limits_on_both_robots() {
    for path in clips() {
        let bvh = Bvh::read(&path).unwrap();
        assert!(
            bvh.frames() > 1 && bvh.frame_time > 0.0,
            "{}",
            path.display()
        );
        for robot in ["icub", "talos"] {
            let m = mapping(robot);
            let r = retarget_clip(&m, &bvh).unwrap();
            let rest = m.spec.skeleton.rest_frame;
            let mut clippings = vec![0; r.joints.len()];
            for (k, (op, cl)) in r.operator.iter().zip(&r.clipped).enumerate() {
                for (i, j) in r.joints.iter().enumerate() {
                    assert!(
                        cl[i] >= j.lower && cl[i] <= j.upper,
                        "{robot} {} frame {k}",
                        j.name
                    );
                    assert_eq!(cl[i], op[i].clamp(j.lower, j.upper));
                    clippings[i] += usize::from(cl[i] != op[i]);
                    if k == rest {
                        // Eq 6.1–6.2 at the rest frame: Δs = 0.
                        assert!(
                            (op[i] - j.rest).abs() < 1e-9,
                            "{robot} {}: {}",
                            j.name,
                            op[i]
                        );
                    }
                }
            }
            assert_eq!(clippings, r.joint_clippings, "{robot}");
            // Eq 6.3–6.5 at the rest frame: the robot's own waist height.
            assert!((r.waist[rest] - r.waist_rest_robot).abs() < 1e-12);
        }
    }
}

#[test]
fn raised_hands_go_up_on_both_robots() {
    let bvh = Bvh::read(&find("raise-up-both-hands")).unwrap();
    for robot_name in ["icub", "talos"] {
        let m = mapping(robot_name);
        let robot = m.robot().unwrap();
        let r = retarget_clip(&m, &bvh).unwrap();
        // The operator's highest-hands frame.
        let skeleton = Skeleton::new(&bvh, m.units());
        let hands = ["Hand_L", "Hand_R"].map(|n| skeleton.joint(n).unwrap());
        let height = |k: usize| {
            let p = skeleton.pose(bvh.frame(k), 0.0);
            hands.map(|h| p.world[h].translation.vector.z)
        };
        let top = (0..bvh.frames())
            .max_by(|a, b| height(*a)[0].total_cmp(&height(*b)[0]))
            .unwrap();
        let lift = height(top);
        let rest = height(0);
        println!(
            "{robot_name}: operator hands up {:.2} / {:.2} m at frame {top}",
            lift[0] - rest[0],
            lift[1] - rest[1]
        );
        assert!(lift[0] - rest[0] > 0.3 && lift[1] - rest[1] > 0.3);
        for hand in &robot.hands {
            let up = frame_position(&robot, &robot_q(&robot, &r, top), hand.frame).z
                - frame_position(&robot, &robot.posture, hand.frame).z;
            println!("  {robot_name} {} hand up {up:.3} m", hand.label);
            // At least half the operator's rise scaled by the waist heights' ratio (Eq 6.4's
            // size ratio): the arms raise, not just twitch.
            let k = if hand.label == "left" { 0 } else { 1 };
            let scaled = (lift[k] - rest[k]) * r.waist_rest_robot / r.waist_rest_human;
            assert!(
                up > 0.5 * scaled,
                "{robot_name} {} hand: {up:.3} m of {scaled:.3}",
                hand.label
            );
        }
    }
}

#[test]
fn a_bow_bends_the_robots_forward() {
    let bvh = Bvh::read(&find("bow")).unwrap();
    // A frame above the torso joints, at the neck.
    for (robot_name, torso) in [("icub", "neck_1"), ("talos", "head_1_link")] {
        let m = mapping(robot_name);
        let robot = m.robot().unwrap();
        let r = retarget_clip(&m, &bvh).unwrap();
        let frame = robot.model.frame_id(torso).unwrap();
        let neck = |k: usize| frame_position(&robot, &robot_q(&robot, &r, k), frame);
        // The deepest bow: the operator's head furthest forward in body coordinates.
        let skeleton = Skeleton::new(&bvh, m.units());
        let h = skeleton.joint("Head").unwrap();
        let rest = skeleton.pose(bvh.frame(0), 0.0);
        let forward = |k: usize| {
            let p = skeleton.pose(bvh.frame(k), 0.0);
            let d = p.world[h].translation.vector - rest.world[h].translation.vector;
            let mut left = rest.world[skeleton.joint("UpperLeg_L").unwrap()]
                .translation
                .vector
                - rest.world[skeleton.joint("UpperLeg_R").unwrap()]
                    .translation
                    .vector;
            left.z = 0.0;
            d.dot(&left.normalize().cross(&Vector3::z()))
        };
        let deepest = (0..bvh.frames())
            .max_by(|a, b| forward(*a).total_cmp(&forward(*b)))
            .unwrap();
        let moved = neck(deepest) - neck(0);
        println!(
            "{robot_name}: operator head forward {:.2} m; robot {torso} moves {:.3?}",
            forward(deepest),
            moved.as_slice()
        );
        assert!(forward(deepest) > 0.2);
        // The robots face +x in corps' world: the neck goes forward by at least a third of
        // the operator's head, scaled by the waist heights' ratio (the neck sits below the
        // head on the same chain).
        let scaled = forward(deepest) * r.waist_rest_robot / r.waist_rest_human;
        assert!(
            moved.x > scaled / 3.0,
            "{robot_name}: {torso} {moved:?}, {scaled:.3}"
        );
    }
}

#[test]
fn a_walk_gives_alternating_steps_normalised_into_the_robots_range() {
    let bvh = Bvh::read(&find("walk_normal")).unwrap();
    for robot in ["icub", "talos"] {
        let m = mapping(robot);
        let s = &m.spec.steps;
        let r = retarget_clip(&m, &bvh).unwrap();
        println!("{robot}: {} steps", r.steps.len());
        assert!(r.steps.len() >= 6, "{robot}: {} steps", r.steps.len());
        for w in r.steps.windows(2) {
            assert_ne!(w[0].foot, w[1].foot, "{robot}: steps alternate feet");
        }
        for st in &r.steps {
            // Eq 6.6–6.7, recomputed.
            let o = (st.human_travel.norm() - s.human_length[0])
                / (s.human_length[1] - s.human_length[0]);
            let expect = (o * (s.robot_length[1] - s.robot_length[0]) + s.robot_length[0])
                .clamp(s.robot_length[0], s.robot_length[1]);
            assert!((st.robot_travel.norm() - expect).abs() < 1e-12);
            assert!(st.robot_height <= s.robot_height[1] && st.robot_height >= s.robot_height[0]);
            // Forward, as the operator walked.
            assert!(st.robot_travel.x > 0.0);
        }
    }
}
