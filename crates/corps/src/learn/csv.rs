//! `evaluations.csv` and `learned.csv`: one row per evaluation (`iteration`, `repeat`,
//! `fitness`, `feasible`, one column per weight, then the constraints, the failed rollouts,
//! the best fitness so far and the first rollout error), read back to resume.

use anyhow::{bail, Context, Result};
use corps_scenario::learning::campaign::{Evaluation, RepeatResult};
use std::collections::BTreeMap;
use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::Path;

const TAIL: [&str; 5] = [
    "joint_limit_over_tolerance_rad",
    "torque_over_limit_nm",
    "failed_rollouts",
    "best_fitness",
    "error",
];

fn header(names: &[String]) -> String {
    let mut cols = vec!["iteration", "repeat", "fitness", "feasible"];
    cols.extend(names.iter().map(String::as_str));
    cols.extend(TAIL);
    cols.join(",")
}

fn num(x: f64) -> String {
    format!("{x:.17e}")
}

/// One evaluation as a row.
pub fn row(e: &Evaluation) -> String {
    let mut cells = vec![
        e.iteration.to_string(),
        e.repeat.to_string(),
        e.fitness.map_or(String::new(), num),
        e.feasible.to_string(),
    ];
    cells.extend(e.weights.iter().map(|w| num(*w)));
    let [g0, g1] = e
        .constraints
        .map_or([String::new(), String::new()], |g| g.map(num));
    cells.extend([g0, g1, e.failed_rollouts.to_string(), num(e.best_fitness)]);
    let error = e
        .error
        .as_deref()
        .unwrap_or("")
        .replace([',', '\n', '"'], ";");
    cells.push(error);
    cells.join(",")
}

/// The evaluations of an earlier run, by repeat and iteration; none if the file is absent.
/// A last line cut short (the run killed while writing it) is ignored.
pub fn read(path: &Path, names: &[String]) -> Result<BTreeMap<usize, BTreeMap<usize, Evaluation>>> {
    let mut out: BTreeMap<usize, BTreeMap<usize, Evaluation>> = BTreeMap::new();
    let Ok(text) = std::fs::read_to_string(path) else {
        return Ok(out);
    };
    let mut lines = text.lines();
    match lines.next() {
        None => return Ok(out),
        Some(h) if h == header(names) => {}
        Some(_) => bail!(
            "{}: its columns are not this campaign's (another campaign's directory?); choose another -o",
            path.display()
        ),
    }
    let n = names.len();
    let all: Vec<&str> = lines.collect();
    let complete = text.ends_with('\n');
    // A last line without its newline was cut while written: dropped whatever it holds (the
    // evaluation is run again).
    let all = if complete {
        &all[..]
    } else {
        &all[..all.len().saturating_sub(1)]
    };
    for (k, line) in all.iter().enumerate() {
        let cells: Vec<&str> = line.split(',').collect();
        let parsed = (|| -> Option<Evaluation> {
            if cells.len() != 4 + n + TAIL.len() {
                return None;
            }
            let f = |s: &str| s.parse::<f64>().ok();
            let opt = |s: &str| {
                if s.is_empty() {
                    Some(None)
                } else {
                    f(s).map(Some)
                }
            };
            let weights: Option<Vec<f64>> = cells[4..4 + n].iter().map(|s| f(s)).collect();
            let g = (opt(cells[4 + n])?, opt(cells[5 + n])?);
            Some(Evaluation {
                iteration: cells[0].parse().ok()?,
                repeat: cells[1].parse().ok()?,
                fitness: opt(cells[2])?,
                feasible: cells[3].parse().ok()?,
                weights: weights?,
                constraints: match g {
                    (Some(a), Some(b)) => Some([a, b]),
                    _ => None,
                },
                failed_rollouts: cells[6 + n].parse().ok()?,
                best_fitness: f(cells[7 + n])?,
                error: (!cells[8 + n].is_empty()).then(|| cells[8 + n].to_string()),
            })
        })();
        match parsed {
            Some(e) => {
                out.entry(e.repeat).or_default().insert(e.iteration, e);
            }
            None => bail!("{}: line {} is not an evaluation", path.display(), k + 2),
        }
    }
    Ok(out)
}

/// The file to append rows to (its header written if it is new; a cut last line ended).
pub fn open_for_append(path: &Path, names: &[String]) -> Result<File> {
    let exists = path.exists()
        && std::fs::metadata(path)
            .map(|m| m.len() > 0)
            .unwrap_or(false);
    if exists {
        let text = std::fs::read_to_string(path)?;
        if !text.ends_with('\n') {
            // Drop the cut line so that appended rows start on their own line.
            let keep = text.rfind('\n').map_or(0, |i| i + 1);
            std::fs::write(path, &text[..keep])
                .with_context(|| format!("repairing {}", path.display()))?;
        }
    }
    let mut f = OpenOptions::new()
        .create(true)
        .append(true)
        .open(path)
        .with_context(|| format!("opening {}", path.display()))?;
    if !exists {
        writeln!(f, "{}", header(names))?;
    }
    Ok(f)
}

/// `learned.csv`: each repeat's best weights and fitness.
pub fn write_learned(path: &Path, names: &[String], learned: &[RepeatResult]) -> Result<()> {
    let mut text = format!("repeat,best_fitness,{}\n", names.join(","));
    let mut sorted: Vec<&RepeatResult> = learned.iter().collect();
    sorted.sort_by_key(|r| r.repeat);
    for r in sorted {
        let w: Vec<String> = r.best_weights.iter().map(|w| format!("{w:.17e}")).collect();
        text += &format!("{},{:.17e},{}\n", r.repeat, r.best_fitness, w.join(","));
    }
    let dir = path.parent().unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or("learned.csv");
    crate::output::write_atomic(dir, name, text.as_bytes())?;
    Ok(())
}
