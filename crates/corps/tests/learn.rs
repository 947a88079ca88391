//! `corps learn` (seed 001 ch. 5): a shortened campaign improves the fitness and never takes
//! the fitness of an infeasible candidate; an interrupted campaign resumes to the same result
//! as an uninterrupted one; the thread count changes no number; bad campaigns stop before any
//! rollout with one line.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn repo(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

fn learn(args: &[&str], threads: Option<usize>) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_corps"));
    cmd.current_dir(repo("")).arg("learn").args(args);
    if let Some(n) = threads {
        cmd.env("RAYON_NUM_THREADS", n.to_string());
    }
    cmd.output().expect("corps runs")
}

fn ok(out: &Output) -> String {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Rows of a CSV file as maps from column to cell.
fn rows(path: &Path) -> Vec<std::collections::BTreeMap<String, String>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    lines
        .map(|l| {
            header
                .iter()
                .cloned()
                .zip(l.split(',').map(String::from))
                .collect()
        })
        .collect()
}

#[test]
fn a_short_campaign_improves_and_never_takes_an_infeasible_fitness() {
    let dir = tempfile::tempdir().unwrap();
    let o = dir.path().join("pr");
    let text = ok(&learn(
        &[
            "campaigns/icub/phi_pr.toml",
            "--iterations",
            "12",
            "--repeats",
            "2",
            "-o",
            o.to_str().unwrap(),
        ],
        None,
    ));
    println!("{text}");
    let rows = rows(&o.join("evaluations.csv"));
    assert_eq!(rows.len(), 2 * 13);
    let mut improved = false;
    for repeat in ["0", "1"] {
        let mine: Vec<_> = rows.iter().filter(|r| r["repeat"] == repeat).collect();
        let start: f64 = mine.iter().find(|r| r["iteration"] == "0").unwrap()["fitness"]
            .parse()
            .unwrap();
        let mut best = f64::NEG_INFINITY;
        let mut sorted = mine.clone();
        sorted.sort_by_key(|r| r["iteration"].parse::<usize>().unwrap());
        for r in sorted {
            let feasible = r["feasible"] == "true";
            // An infeasible candidate's fitness is never computed.
            assert_eq!(r["fitness"].is_empty(), !feasible, "{r:?}");
            let b: f64 = r["best_fitness"].parse().unwrap();
            assert!(b >= best, "the best fitness never decreases");
            best = b;
        }
        improved |= best > start;
    }
    assert!(improved, "no repeat improved on its start in 12 iterations");
    for f in ["learned.csv", "fitness.png", "tests.csv"] {
        assert!(o.join(f).exists(), "{f}");
    }
}

#[test]
fn a_resumed_campaign_ends_as_an_uninterrupted_one_on_any_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    // Randomized: the start's several draws are replayed too.
    let campaign = "campaigns/icub/phi_pr.toml";
    let (a, b, c) = (
        dir.path().join("a"),
        dir.path().join("b"),
        dir.path().join("c"),
    );
    let args = |o: &Path, it: &str| -> Vec<String> {
        [
            campaign,
            "--iterations",
            it,
            "--repeats",
            "2",
            "-o",
            o.to_str().unwrap(),
        ]
        .map(String::from)
        .to_vec()
    };
    ok(&learn(&strs(&args(&a, "6")), Some(2)));
    // The campaign "interrupted" after 3 iterations, its last row written but not its newline
    // (that row is run again).
    ok(&learn(&strs(&args(&b, "3")), Some(1)));
    let mut text = std::fs::read_to_string(b.join("evaluations.csv")).unwrap();
    let last = text.lines().last().unwrap().to_string();
    text.truncate(text.len() - last.len() - 1);
    let cut = text.clone() + &last;
    std::fs::write(b.join("evaluations.csv"), cut).unwrap();
    let resumed = ok(&learn(&strs(&args(&b, "6")), Some(2)));
    assert!(resumed.contains("7 evaluations replayed"), "{resumed}");
    // Another campaign into the same directory is refused.
    let other = learn(
        &[
            "campaigns/icub/phi_r.toml",
            "--iterations",
            "6",
            "--repeats",
            "2",
            "-o",
            b.to_str().unwrap(),
        ],
        None,
    );
    assert!(!other.status.success());
    assert!(String::from_utf8_lossy(&other.stderr).contains("another campaign"));
    ok(&learn(&strs(&args(&c, "6")), Some(1)));
    let learned = |d: &Path| std::fs::read_to_string(d.join("learned.csv")).unwrap();
    assert_eq!(learned(&a), learned(&b), "resumed against uninterrupted");
    assert_eq!(learned(&a), learned(&c), "1 thread against 2");
    let sorted = |d: &Path| {
        let mut r: Vec<String> = std::fs::read_to_string(d.join("evaluations.csv"))
            .unwrap()
            .lines()
            .map(String::from)
            .collect();
        r.sort();
        r
    };
    assert_eq!(sorted(&a), sorted(&b));
    assert_eq!(sorted(&a), sorted(&c));
}

#[test]
fn bad_campaigns_stop_before_any_rollout() {
    let dir = tempfile::tempdir().unwrap();
    let base = std::fs::read_to_string(repo("campaigns/icub/phi_pr.toml"))
        .unwrap()
        .replace(
            "../../scenarios/",
            &format!("{}/", repo("scenarios").display()),
        );
    for (from, to, expected) in [
        (
            "lower = 1e-4\nupper = 10.0\nstart = 1.0",
            "lower = 10.0\nupper = 1e-4\nstart = 1.0",
            "lower 10 > upper 0.0001",
        ),
        (
            "lower = 1e-4\nupper = 10.0\nstart = 1.0",
            "lower = 1e-4\nupper = 10.0\nstart = 20.0",
            "outside",
        ),
        ("sigma0 = 0.1", "sigma0 = 0.0", "sigma0"),
        (
            "push_duration = 1.0",
            "push_duration = 0.0",
            "randomization.push_duration",
        ),
        (
            "conditions = 1",
            "conditions = 0",
            "conditions: must be at least 1",
        ),
        (
            "fsm2_one_step.toml\"",
            "no_such_file.toml\"",
            "no such scenario file",
        ),
        (
            "key = \"weights.stance\"",
            "key = \"weights..stance\"",
            "dotted path",
        ),
    ] {
        assert!(base.contains(from), "{from}");
        let path = dir.path().join("bad.toml");
        std::fs::write(&path, base.replacen(from, to, 1)).unwrap();
        let o = dir.path().join("out");
        let out = learn(
            &[
                path.to_str().unwrap(),
                "--iterations",
                "1",
                "--repeats",
                "1",
                "-o",
                o.to_str().unwrap(),
            ],
            None,
        );
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{to}");
        assert!(err.contains(expected), "{to}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(
            !o.join("evaluations.csv").exists(),
            "{to}: a file was written"
        );
    }
}

fn strs(v: &[String]) -> Vec<&str> {
    v.iter().map(String::as_str).collect()
}
