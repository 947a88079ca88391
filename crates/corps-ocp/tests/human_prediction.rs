//! The walking OCP predicting the rest of every recorded walk of the shared data set
//! (`shared/data/human-walking`, Maroger et al., read at run time): at 25, 50 and 75 % of each
//! subject's walk, from the last 50 samples (about half a second) and the walk's end as the
//! goal, facing along its last 50 samples. Printed per
//! instant: the mean over walks of the prediction's mean distance to the true remaining path,
//! and of its final point's distance to the true end; beside them, the same for a straight
//! line from the person to the goal.

use corps_ocp::prediction::{distance_to_path, predict};
use corps_ocp::recorded_walks;
use std::path::PathBuf;

const WINDOW: usize = 50;

fn data_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/human-walking")
}

#[derive(Default)]
struct Tally {
    walks: usize,
    converged: usize,
    mean_error: f64,
    final_error: f64,
    line_error: f64,
    worst_mean: f64,
    means: Vec<f64>,
}

#[test]
fn every_recorded_walk_is_predicted_and_the_errors_are_reported() {
    let mut files: Vec<PathBuf> = std::fs::read_dir(data_dir())
        .expect("shared/data/human-walking beside the repository")
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.extension().is_some_and(|e| e == "dat")
                && !p
                    .file_name()
                    .unwrap()
                    .to_string_lossy()
                    .starts_with("StartAndEnd")
        })
        .collect();
    files.sort();
    assert!(files.len() >= 30, "{} walk files", files.len());
    let fractions = [0.25, 0.5, 0.75];
    let mut tallies: [Tally; 3] = Default::default();
    let mut left_out = 0;
    let start = std::time::Instant::now();
    let mut solves = 0;
    for path in &files {
        let file = recorded_walks::read(path).unwrap();
        left_out += file.without_heading.len();
        for walk in &file.walks {
            let n = walk.poses.len();
            // The goal: the walk's end, facing along its last samples (the recorded heading
            // swings with the gait).
            let (end, before) = (walk.poses[n - 1], walk.poses[n - WINDOW]);
            let goal = [
                end[0],
                end[1],
                (end[1] - before[1]).atan2(end[0] - before[0]),
            ];
            for (tally, f) in tallies.iter_mut().zip(fractions) {
                let k = ((n - 1) as f64 * f).round() as usize;
                let window = &walk.poses[k + 1 - WINDOW..=k];
                let p = predict(window, walk.dt, goal)
                    .unwrap_or_else(|e| panic!("{} subject {}: {e}", path.display(), walk.subject));
                solves += p.solves;
                assert!(p.poses.iter().flatten().all(|v| v.is_finite()));
                let rest = &walk.poses[k..];
                let mean = p
                    .poses
                    .iter()
                    .map(|q| distance_to_path([q[0], q[1]], rest))
                    .sum::<f64>()
                    / p.poses.len() as f64;
                let end = p.poses.last().unwrap();
                let fin = (end[0] - goal[0]).hypot(end[1] - goal[1]);
                // The straight line from the person to the goal, sampled as finely.
                let here = walk.poses[k];
                let m = p.poses.len().max(2);
                let line = (0..m)
                    .map(|i| {
                        let t = i as f64 / (m - 1) as f64;
                        let q = [
                            here[0] + t * (goal[0] - here[0]),
                            here[1] + t * (goal[1] - here[1]),
                        ];
                        distance_to_path(q, rest)
                    })
                    .sum::<f64>()
                    / m as f64;
                tally.walks += 1;
                tally.converged += usize::from(p.converged);
                tally.mean_error += mean;
                tally.final_error += fin;
                tally.line_error += line;
                tally.worst_mean = tally.worst_mean.max(mean);
                tally.means.push(mean);
            }
        }
    }
    println!(
        "{} files, {} subjects' walks ({left_out} left out: no heading recorded), {solves} DDP \
         solves in {:.2} s",
        files.len(),
        tallies[0].walks,
        start.elapsed().as_secs_f64()
    );
    println!("| at | walks | DDP converged | mean distance to the true path (m) | median (m) | worst (m) | final point to the true end (m) | straight line: mean distance (m) |");
    println!("|---|---|---|---|---|---|---|---|");
    for (t, f) in tallies.iter_mut().zip(fractions) {
        let w = t.walks as f64;
        t.means.sort_by(f64::total_cmp);
        println!(
            "| {:.0} % | {} | {} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} |",
            f * 100.0,
            t.walks,
            t.converged,
            t.mean_error / w,
            t.means[t.means.len() / 2],
            t.worst_mean,
            t.final_error / w,
            t.line_error / w
        );
    }
    assert!(tallies[0].walks >= 200, "{} walks", tallies[0].walks);
    // Less of the walk left, less to get wrong: the errors shrink as the walk goes on.
    let mean = |t: &Tally| t.mean_error / t.walks as f64;
    assert!(mean(&tallies[0]) > mean(&tallies[1]) && mean(&tallies[1]) > mean(&tallies[2]));
}
