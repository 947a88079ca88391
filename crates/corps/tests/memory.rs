//! A run's memory does not grow with its length: the log streams to disk, the metrics are
//! online and the plots keep a bounded decimated copy (issue "corps under load"). Measured
//! on the heap (every byte allocated and alive at once, all threads), so the figure is exact
//! and independent of the machine.

use corps::run::{run_text, RunOptions};
use std::path::PathBuf;

#[global_allocator]
static GLOBAL: corps_testkit::PeakAllocator = corps_testkit::PeakAllocator;

#[test]
fn a_longer_run_peaks_at_the_same_heap() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios/control/tsid_torque_push_front.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let no_plots = text.replacen("[output]\n", "[output]\nplots = false\n", 1);
    assert!(no_plots.contains("plots = false"));
    let peak = |seconds: f64, text: &str| {
        let out = tempfile::tempdir().unwrap();
        let (report, peak) = corps_testkit::peak_heap_during(|| {
            run_text(
                text,
                &path,
                Some(out.path()),
                Some(seconds),
                RunOptions::quiet(),
            )
            .unwrap()
        });
        assert_eq!(report.metrics.fallbacks, 0);
        peak
    };
    let short = peak(2.0, &no_plots);
    let long = peak(12.0, &no_plots);
    eprintln!(
        "peak heap: 2 s {:.2} MB, 12 s {:.2} MB",
        short as f64 / 1e6,
        long as f64 / 1e6
    );
    // Growth of 0.18 MB per simulated second (before the log streamed) would add 1.8 MB.
    assert!(
        long as f64 <= short as f64 * 1.02 + 64e3,
        "the heap grew from {short} to {long} bytes"
    );
    // With plots on, the peak also holds the figures being drawn, on several threads at
    // once, so it varies from run to run by the interleaving; their data come from a buffer
    // of at most 8,192 points per signal (`plot_buffer`'s test), and the soak benchmark
    // measures the whole process's RSS with plots (BENCHMARKS.md).
}
