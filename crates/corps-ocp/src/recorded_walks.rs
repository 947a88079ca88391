//! Recorded human walks in the format of Maroger et al.'s data set (`shared/data/human-walking`,
//! BSD-3-Clause): one file per starting position, 66 rows × 500 columns, i.e. six rows per
//! subject, each row resampled to 500 samples: row 6s is x, 6s+1 is y (m, goal at the
//! origin), 6s+5 the heading θ (rad); rows 6s+2 and 6s+3 are the horizontal velocity
//! components (m/s), 6s+4 another rate.
//!
//! The samples are normalised in time, not taken at a fixed rate. The time base used here:
//! a walk's duration is its path length over its median speed `median √(r₂² + r₃²)`, spread
//! evenly over the samples (on the 5.25 m walk N4040, subject 0: median 0.98 m/s, 5.35 s,
//! 10.7 ms a sample; the path's own increments over those rows give 10.2 ms).

use crate::error::OcpError;
use std::path::Path;

/// One subject's walk.
#[derive(Clone, Debug, PartialEq)]
pub struct RecordedWalk {
    /// Subject index in its file.
    pub subject: usize,
    /// Poses (x, y, θ), one per sample.
    pub poses: Vec<[f64; 3]>,
    /// Time between samples (s), from the time base above.
    pub dt: f64,
}

impl RecordedWalk {
    /// Path length (m).
    pub fn length(&self) -> f64 {
        self.poses
            .windows(2)
            .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
            .sum()
    }
}

/// The walks of one file, and the subjects left out because their heading row holds no
/// heading (every sample exactly 0, as some of the data set's rows do).
#[derive(Clone, Debug, PartialEq)]
pub struct RecordedFile {
    pub walks: Vec<RecordedWalk>,
    pub without_heading: Vec<usize>,
}

/// Reads one file of the data set; subjects whose heading row is all zero are left out
/// (listed in [`RecordedFile::without_heading`]).
pub fn read(path: &Path) -> Result<RecordedFile, OcpError> {
    parse(path, false)
}

/// Reads every subject's walk of one file; where the heading row is all zero, the heading is
/// the path's own direction (central differences of the positions).
pub fn read_paths(path: &Path) -> Result<Vec<RecordedWalk>, OcpError> {
    Ok(parse(path, true)?.walks)
}

fn parse(path: &Path, every_subject: bool) -> Result<RecordedFile, OcpError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| OcpError::Invalid(format!("{}: {e}", path.display())))?;
    let rows: Vec<Vec<f64>> = text
        .lines()
        .filter(|l| !l.trim().is_empty())
        .enumerate()
        .map(|(r, l)| {
            l.split_whitespace()
                .map(|v| {
                    v.parse::<f64>()
                        .ok()
                        .filter(|x| x.is_finite())
                        .ok_or_else(|| {
                            OcpError::Invalid(format!(
                                "{} row {}: '{v}' is not a finite number",
                                path.display(),
                                r + 1
                            ))
                        })
                })
                .collect::<Result<Vec<f64>, OcpError>>()
        })
        .collect::<Result<_, _>>()?;
    let columns = rows.first().map_or(0, Vec::len);
    if rows.is_empty() || !rows.len().is_multiple_of(6) || columns < 2 {
        return Err(OcpError::Invalid(format!(
            "{}: {} rows of {columns} samples; expected six rows per subject",
            path.display(),
            rows.len()
        )));
    }
    if let Some(r) = rows.iter().position(|r| r.len() != columns) {
        return Err(OcpError::Invalid(format!(
            "{} row {}: {} samples, the first row has {columns}",
            path.display(),
            r + 1,
            rows[r].len()
        )));
    }
    let mut file = RecordedFile {
        walks: Vec::new(),
        without_heading: Vec::new(),
    };
    for (subject, block) in rows.chunks_exact(6).enumerate() {
        let (x, y, vx, vy, theta) = (&block[0], &block[1], &block[2], &block[3], &block[5]);
        let headingless = theta.iter().all(|t| *t == 0.0);
        if headingless && !every_subject {
            file.without_heading.push(subject);
            continue;
        }
        let heading = |k: usize| {
            if !headingless {
                return theta[k];
            }
            let (a, b) = (k.saturating_sub(1), (k + 1).min(columns - 1));
            (y[b] - y[a]).atan2(x[b] - x[a])
        };
        let poses: Vec<[f64; 3]> = (0..columns).map(|k| [x[k], y[k], heading(k)]).collect();
        let mut speeds: Vec<f64> = vx.iter().zip(vy).map(|(a, b)| a.hypot(*b)).collect();
        speeds.sort_by(f64::total_cmp);
        let median = speeds[speeds.len() / 2];
        let mut walk = RecordedWalk {
            subject,
            poses,
            dt: 0.0,
        };
        let length = walk.length();
        if !(median > 0.0 && length > 0.0) {
            return Err(OcpError::Invalid(format!(
                "{} subject {subject}: no motion to derive a time base from",
                path.display()
            )));
        }
        walk.dt = length / median / (columns - 1) as f64;
        file.walks.push(walk);
    }
    Ok(file)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(name: &str, text: &str) -> std::path::PathBuf {
        let path = std::env::temp_dir().join(format!("corps-ocp-{}-{name}", std::process::id()));
        std::fs::write(&path, text).unwrap();
        path
    }

    /// One subject walking 1 m along x in 1 s at 1 m/s (velocity rows 1, 0).
    fn walk(theta: f64) -> String {
        let row = |f: &dyn Fn(f64) -> f64| {
            (0..11)
                .map(|k| f(k as f64 / 10.0).to_string())
                .collect::<Vec<_>>()
                .join(" ")
        };
        [
            row(&|s| s - 1.0),
            row(&|_| 0.0),
            row(&|_| 1.0),
            row(&|_| 0.0),
            row(&|_| 0.0),
            row(&|_| theta),
        ]
        .join("\n")
    }

    #[test]
    fn a_walk_reads_with_its_time_base() {
        let f = read(&write("ok", &walk(0.1))).unwrap();
        assert_eq!(f.walks.len(), 1);
        let w = &f.walks[0];
        assert!((w.length() - 1.0).abs() < 1e-12);
        assert!((w.dt - 0.1).abs() < 1e-12, "{}", w.dt);
        assert_eq!(w.poses[10], [0.0, 0.0, 0.1]);
        let f = read(&write("zero", &walk(0.0))).unwrap();
        assert!(f.walks.is_empty() && f.without_heading == vec![0]);
    }

    #[test]
    fn bad_files_are_clear_errors() {
        let e = read(&write("rows", "1 2\n3 4\n")).unwrap_err().to_string();
        assert!(e.contains("six rows per subject"), "{e}");
        let e = read(&write("nan", &walk(0.1).replace("0.1 ", "NaN "))).unwrap_err();
        assert!(e.to_string().contains("not a finite number"), "{e}");
        let ragged = walk(0.1) + " 7";
        let e = read(&write("ragged", &ragged)).unwrap_err().to_string();
        assert!(e.contains("samples"), "{e}");
        assert!(read(Path::new("/nonexistent/walk.dat")).is_err());
    }
}
