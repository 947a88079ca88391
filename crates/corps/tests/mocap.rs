//! `corps mocap retarget`: a shared clip (read in place) onto iCub and TALOS writes its
//! files with the columns the issue names and a summary; a bad clip or mapping is one line
//! and a non-zero exit, with nothing written. `corps mocap send` plays a clip to a receiver on
//! the loopback.

use std::path::PathBuf;
use std::process::{Command, Output};

fn repo(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

fn corps(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_corps"))
        .current_dir(repo(""))
        .arg("mocap")
        .args(args)
        .output()
        .expect("corps runs")
}

fn walk_clip() -> String {
    let dir = repo("../shared/data/mocap");
    let mut clips: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.to_string_lossy().contains("walk"))
        .collect();
    clips.sort();
    clips[0].display().to_string()
}

#[test]
fn a_walk_retargets_onto_both_robots_with_its_steps() {
    let dir = tempfile::tempdir().unwrap();
    for robot in ["icub", "talos"] {
        let out = dir.path().join(robot);
        let o = corps(&[
            "retarget",
            &walk_clip(),
            "--mapping",
            &format!("config/{robot}/retargeting.toml"),
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let text = String::from_utf8_lossy(&o.stdout);
        println!("{text}");
        assert!(text.contains("operator steps: "), "{text}");
        for f in ["joints.csv", "steps.csv", "joints.png", "steps.png"] {
            assert!(out.join(f).exists(), "{f}");
        }
        let joints = std::fs::read_to_string(out.join("joints.csv")).unwrap();
        assert!(joints.starts_with("time,operator_"));
        assert!(joints.lines().next().unwrap().ends_with(",waist_height"));
        let steps = std::fs::read_to_string(out.join("steps.csv")).unwrap();
        assert!(steps.lines().count() > 4, "{steps}");
    }
}

#[test]
fn a_bad_clip_or_mapping_is_one_line_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.bvh");
    std::fs::write(&bad, "HIERARCHY\nROOT Hips\n{\n OFFSET 0 0 0\n CHANNELS 3 Zrotation Xrotation Yrotation\n}\nMOTION\nFrames: 2\nFrame Time: 0.0\n0 0 0\n0 0 0\n").unwrap();
    let out = dir.path().join("out");
    for (args, words) in [
        (
            vec!["retarget", bad.to_str().unwrap()],
            "bad.bvh: line 9: Frame Time 0 s: must be > 0",
        ),
        (
            vec![
                "retarget",
                &walk_clip(),
                "--mapping",
                "config/icub/nothing.toml",
            ],
            "config/icub/nothing.toml",
        ),
    ] {
        let mut args = args.clone();
        args.extend(["-o", out.to_str().unwrap()]);
        let o = corps(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success());
        assert!(err.contains(words), "{err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(!out.exists());
    }
}

#[test]
fn send_plays_a_clip_to_a_receiver_on_the_loopback() {
    let receiver = std::net::UdpSocket::bind("127.0.0.1:0").unwrap();
    receiver
        .set_read_timeout(Some(std::time::Duration::from_secs(5)))
        .unwrap();
    let address = receiver.local_addr().unwrap().to_string();
    let clip = walk_clip();
    let child =
        std::thread::spawn(move || corps(&["send", &clip, "--to", &address, "--speed", "20"]));
    let mut buf = vec![0u8; 65536];
    let n = receiver.recv(&mut buf).unwrap();
    let first = String::from_utf8_lossy(&buf[..n]).to_string();
    let o = child.join().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stdout).starts_with("sent "));
    // TIME, then one value per channel of the clip.
    let words: Vec<&str> = first.split_whitespace().collect();
    assert_eq!(words[0].parse::<f64>().ok(), Some(0.0));
    assert!(words.len() > 1 && words[1..].iter().all(|w| w.parse::<f64>().is_ok()));
}
