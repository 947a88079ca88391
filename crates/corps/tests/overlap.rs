//! `corps run` overlaps the simulator's next-step preparation with the controller on a second
//! thread; the run must be the serial run, bit for bit (every logged signal but the tick time).

use corps::run::{run_file, Overlap, RunOptions};
use std::path::{Path, PathBuf};

/// The log without its last column (`tick_us`, wall-clock time).
fn signals(dir: &Path) -> Vec<String> {
    let log = std::fs::read_to_string(dir.join("log.csv")).unwrap();
    let header = log.lines().next().unwrap();
    assert!(header.ends_with(",tick_us"), "tick_us is the last column");
    log.lines()
        .map(|l| l.rsplit_once(',').unwrap().0.to_string())
        .collect()
}

#[test]
fn overlapped_walk_is_the_serial_walk() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios/walk/tsid_torque_20cm.toml");
    let run = |overlap: Overlap| {
        let out = tempfile::tempdir().unwrap();
        let options = RunOptions {
            overlap,
            ..RunOptions::quiet()
        };
        let m = run_file(&path, Some(out.path()), Some(3.0), options)
            .unwrap()
            .metrics;
        (signals(out.path()), m)
    };
    let (serial, ms) = run(Overlap::Never);
    let w = |m: &corps::run::Metrics| m.walk.as_ref().map(|w| (w.distance, w.cost_of_transport));
    // Every tick overlapped, and the adaptive schedule, which switches between the two.
    for overlap in [Overlap::Always, Overlap::Adaptive] {
        let (overlapped, mo) = run(overlap);
        assert!(serial.len() > 100, "{} log rows", serial.len());
        assert_eq!(serial, overlapped, "{overlap:?}");
        assert_eq!(w(&ms), w(&mo), "{overlap:?}");
        if overlap == Overlap::Always {
            assert_eq!(mo.overlapped_ticks, 3000);
        } else {
            // The adaptive run switched: its probes run both modes.
            assert!(
                mo.overlapped_ticks > 0 && mo.overlapped_ticks < 3000,
                "{}",
                mo.overlapped_ticks
            );
        }
    }
    let d = ms.walk.as_ref().unwrap().distance;
    assert!(d > 0.05, "the robot walked {d:.3} m");
}
