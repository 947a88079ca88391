//! What a teleoperation tick asks of motion capture — the source's pose, its retargeting, the
//! waist height, the step detection — allocates nothing once set up: counting global
//! allocator, per thread. On a shared clip (read in place) onto both robots.

use corps_mocap::bvh::Bvh;
use corps_mocap::retarget::{Mapping, Retargeter};
use corps_mocap::skeleton::Skeleton;
use corps_mocap::source::{ClipSource, MocapSource};
use corps_mocap::steps::StepDetector;
use corps_testkit::{allocations, CountingAllocator};
use std::path::PathBuf;

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

fn repo(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

#[test]
fn a_tick_of_retargeting_does_not_allocate() {
    let dir = repo("../shared/data/mocap");
    let mut clips: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.to_string_lossy().contains("walk"))
        .collect();
    clips.sort();
    let bvh = Bvh::read(&clips[0]).unwrap();
    for robot in ["icub", "talos"] {
        let m = Mapping::read(&repo(&format!("config/{robot}/retargeting.toml"))).unwrap();
        let model = m.robot().unwrap();
        let skeleton = Skeleton::new(&bvh, m.units());
        let rest = skeleton.pose(bvh.frame(0), 0.0);
        let mut r = Retargeter::new(&m, &model, &skeleton, &rest).unwrap();
        let mut steps = StepDetector::new(&m.spec.steps, r.feet(&rest));
        let mut source = ClipSource::new(bvh.clone(), m.units());
        let n = r.joints.len();
        let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
        let (pose, _) = source.poll(0.0);
        r.joints_into(pose, &mut a, &mut b);
        let before = allocations();
        let mut waist = 0.0;
        for k in 0..(bvh.frames() * 3) {
            let t = k as f64 * bvh.frame_time / 3.0;
            let (pose, _) = source.poll(t);
            r.joints_into(pose, &mut a, &mut b);
            waist += r.waist_height(pose);
            steps.update(t, r.feet(pose));
        }
        let count = allocations() - before;
        assert!(waist.is_finite());
        assert_eq!(count, 0, "{robot}: {count} heap allocations");
        assert!(steps.count > 0);
    }
}
