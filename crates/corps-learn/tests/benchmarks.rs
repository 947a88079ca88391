//! The (1+1)-CMA-ES with covariance constrained adaptation on standard problems, beside
//! pycma's CMA-ES on the same problems from the same start (tools/golden/cma_benchmarks.py,
//! tests/data/pycma_benchmarks.json): both reach each known optimum; the constrained search
//! never evaluates an infeasible point; a seed gives the same run to the bit.

use corps_learn::{OnePlusOne, Settings, StepOutcome};
use serde_json::Value;

type Fitness = fn(&[f64]) -> f64;
type Constraints = fn(&[f64], &mut [f64]);

fn sphere(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum()
}

fn rosenbrock(x: &[f64]) -> f64 {
    x.windows(2)
        .map(|w| 100.0 * (w[1] - w[0] * w[0]).powi(2) + (1.0 - w[0]).powi(2))
        .sum()
}

fn g06(x: &[f64]) -> f64 {
    (x[0] - 10.0).powi(3) + (x[1] - 20.0).powi(3)
}

fn none(_: &[f64], _: &mut [f64]) {}

fn linear(x: &[f64], g: &mut [f64]) {
    g[0] = 1.0 - x[0];
}

fn tr2(x: &[f64], g: &mut [f64]) {
    g[0] = 2.0 - x[0] - x[1];
}

fn g06_constraints(x: &[f64], g: &mut [f64]) {
    g[0] = 100.0 - (x[0] - 5.0).powi(2) - (x[1] - 5.0).powi(2);
    g[1] = (x[0] - 6.0).powi(2) + (x[1] - 5.0).powi(2) - 82.81;
    g[2] = 13.0 - x[0];
    g[3] = x[0] - 100.0;
    g[4] = -x[1];
    g[5] = x[1] - 100.0;
}

struct Problem {
    name: &'static str,
    f: Fitness,
    g: Constraints,
    constraints: usize,
    /// Reached when |f − optimum| ≤ tolerance.
    tolerance: f64,
}

const PROBLEMS: [Problem; 5] = [
    Problem {
        name: "sphere10",
        f: sphere,
        g: none,
        constraints: 0,
        tolerance: 1e-10,
    },
    Problem {
        name: "rosenbrock10",
        f: rosenbrock,
        g: none,
        constraints: 0,
        tolerance: 1e-10,
    },
    Problem {
        name: "sphere_linear10",
        f: sphere,
        g: linear,
        constraints: 1,
        tolerance: 1e-8,
    },
    Problem {
        name: "tr2",
        f: sphere,
        g: tr2,
        constraints: 1,
        tolerance: 1e-8,
    },
    Problem {
        name: "g06",
        f: g06,
        g: g06_constraints,
        constraints: 6,
        tolerance: 1e-4,
    },
];

fn golden() -> Value {
    let text = include_str!("data/pycma_benchmarks.json");
    serde_json::from_str(text).unwrap()
}

/// Runs until the optimum is within tolerance (or 100,000 iterations): evaluations used,
/// the best value, and whether an infeasible point was ever evaluated.
fn solve(p: &Problem, x0: &[f64], sigma0: f64, optimum: f64, seed: u64) -> (usize, f64, bool) {
    let infeasible = std::cell::Cell::new(false);
    let mut scratch = vec![0.0; p.constraints];
    let mut f = |x: &[f64]| {
        (p.g)(x, &mut scratch);
        if scratch.iter().any(|v| *v > 0.0) {
            infeasible.set(true);
        }
        (p.f)(x)
    };
    let mut es =
        OnePlusOne::new(x0, p.constraints, Settings { sigma0, seed }, p.g, &mut f).unwrap();
    while (es.best_fitness() - optimum).abs() > p.tolerance && es.iterations() < 100_000 {
        es.step(p.g, &mut f);
    }
    (es.evaluations(), es.best_fitness(), infeasible.get())
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

#[test]
fn every_problem_reaches_its_optimum_beside_pycma() {
    let golden = golden();
    for p in &PROBLEMS {
        let g = &golden["problems"][p.name];
        let optimum = g["optimum"].as_f64().unwrap();
        let x0: Vec<f64> = (g["x0"].as_array().unwrap().iter())
            .map(|v| v.as_f64().unwrap())
            .collect();
        let sigma0 = g["sigma0"].as_f64().unwrap();
        let mut evaluations = Vec::new();
        for seed in 1..=5 {
            let (evals, best, infeasible) = solve(p, &x0, sigma0, optimum, seed);
            assert!(
                (best - optimum).abs() <= p.tolerance,
                "{}: seed {seed}: {best} against {optimum}",
                p.name
            );
            assert!(!infeasible, "{}: an infeasible point was evaluated", p.name);
            evaluations.push(evals as f64);
        }
        let pycma: Vec<f64> = (g["runs"].as_array().unwrap().iter())
            .map(|r| r["evaluations"].as_f64().unwrap())
            .collect();
        for r in g["runs"].as_array().unwrap() {
            let best = r["best"].as_f64().unwrap();
            assert!(
                (best - optimum).abs() < 1e-6 * optimum.abs().max(1.0),
                "{}: pycma {best}",
                p.name
            );
        }
        println!(
            "{}: evaluations to |f − f*| ≤ {:e}: corps (1+1)-CMA-ES median {} (5 seeds); pycma {} median {} (to its tolfun 1e-12)",
            p.name,
            p.tolerance,
            median(evaluations),
            golden["pycma_version"].as_str().unwrap(),
            median(pycma)
        );
    }
}

#[test]
fn a_seed_gives_the_same_run_to_the_bit() {
    let run = |seed| {
        let mut es = OnePlusOne::new(
            &[15.05, 5.0],
            6,
            Settings { sigma0: 1.0, seed },
            g06_constraints,
            g06,
        )
        .unwrap();
        let outcomes: Vec<StepOutcome> = (0..500).map(|_| es.step(g06_constraints, g06)).collect();
        (es.best().to_vec(), es.best_fitness(), es.sigma(), outcomes)
    };
    let (a, b) = (run(3), run(3));
    assert_eq!(
        a.0.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
        b.0.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
    );
    assert_eq!(a.1.to_bits(), b.1.to_bits());
    assert_eq!(a.2.to_bits(), b.2.to_bits());
    assert_eq!(a.3, b.3);
    assert_ne!(run(4).1.to_bits(), a.1.to_bits());
    // The constrained search meets infeasible candidates, shrinks after bad ones and succeeds.
    let kinds = |k: fn(&StepOutcome) -> bool| a.3.iter().filter(|o| k(o)).count();
    assert!(kinds(|o| matches!(o, StepOutcome::Infeasible { .. })) > 0);
    assert!(kinds(|o| matches!(o, StepOutcome::Success)) > 0);
    assert!(kinds(|o| matches!(o, StepOutcome::Failure { active: true })) > 0);
}

#[test]
fn the_constants_are_seed_001s() {
    // Seed 001 §5.1 for nP = 5: β 0.0143, c 0.2857, c_c 0.1429, c⁺ 0.0645, d 3.5.
    let k = corps_learn::Constants::for_dimension(5);
    for (value, expected) in [
        (k.beta, 0.1 / 7.0),
        (k.c, 2.0 / 7.0),
        (k.c_c, 1.0 / 7.0),
        (k.c_cov_plus, 2.0 / 31.0),
        (k.d, 3.5),
        (k.p_target, 2.0 / 11.0),
        (k.c_p, 1.0 / 12.0),
    ] {
        assert!((value - expected).abs() < 1e-15);
    }
    assert!((k.c_cov_minus_cap - 0.4 / (5f64.powf(1.6) + 1.0)).abs() < 1e-15);
    assert!(k.c_cov_minus_cap <= 0.0283 + 5e-5);
}

#[test]
fn bad_settings_are_refused() {
    let ok = |sigma0: f64, x0: &[f64]| {
        OnePlusOne::new(x0, 1, Settings { sigma0, seed: 0 }, tr2, sphere).map(|_| ())
    };
    assert!(ok(1.0, &[3.0, 3.0]).is_ok());
    for (sigma0, x0, expected) in [
        (0.0, vec![3.0, 3.0], "σ0"),
        (-1.0, vec![3.0, 3.0], "σ0"),
        (f64::NAN, vec![3.0, 3.0], "σ0"),
        (1.0, vec![0.0, 0.0], "violates constraint 0"),
        (1.0, vec![f64::NAN, 3.0], "entry 0"),
        (1.0, vec![], "empty"),
    ] {
        let err = ok(sigma0, &x0).unwrap_err().to_string();
        assert!(err.contains(expected), "{sigma0} {x0:?}: {err}");
    }
    let err = OnePlusOne::new(
        &[1.0],
        0,
        Settings {
            sigma0: 1.0,
            seed: 0,
        },
        none,
        |_| f64::NAN,
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("fitness"), "{err}");
}
