//! The hierarchical QP on degenerate and ill-conditioned hierarchies of 2–5 levels, against a
//! cascade of Clarabel solves: each level's optimal cost with every upper level held at the
//! residuals it achieved (equality tasks: the fitted values A_j x, which are unique; inequality
//! tasks: their achieved violation), which is the lexicographic optimum. Families: duplicated
//! and nearly parallel task rows (1e-10 apart), rank-deficient task matrices, rows scaled from
//! 1e-3 to 1e3 (task Hessians with condition numbers to 1e12), weights from 1e-3 to 1e3, and
//! hard bounds that saturate. Both sides solve the same levels (the regularization rule
//! included), so the comparison is of the solvers.

mod common;

use common::{clarabel_solve, Reference};
use corps_qp::{HierarchicalQp, Level, QpProblem};
use nalgebra::{DMatrix, DVector};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A task matrix of `rows × n` whose rows are random, duplicated, nearly parallel or
/// combinations of the others, each scaled by 10^[−3, 3] at random.
fn task_rows(rng: &mut ChaCha8Rng, rows: usize, n: usize) -> DMatrix<f64> {
    let mut m = common::rand_matrix(rng, rows, n);
    for r in 1..rows {
        let src = rng.gen_range(0..r);
        match rng.gen_range(0..5) {
            0 => {
                let row = m.row(src).clone_owned();
                m.set_row(r, &row);
            }
            1 => {
                let row = m.row(src) + common::rand_matrix(rng, 1, n) * 1e-10;
                m.set_row(r, &row);
            }
            2 if r >= 2 => {
                let row = m.row(src) * rng.gen_range(-1.0..1.0) + m.row(r - 1);
                m.set_row(r, &row);
            }
            _ => {}
        }
    }
    for r in 0..rows {
        let scale = 10f64.powf(rng.gen_range(-3.0..3.0));
        m.row_mut(r).scale_mut(scale);
    }
    m
}

fn random_hierarchy(seed: u64) -> (Vec<Level>, DVector<f64>, DVector<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let n = rng.gen_range(4..14);
    let levels = rng.gen_range(2..=5);
    let weight = |rng: &mut ChaCha8Rng| 10f64.powf(rng.gen_range(-3.0..3.0));
    let mut out = Vec::new();
    for _ in 0..levels {
        let mut level = Level::new(n);
        let re = rng.gen_range(1..=n);
        let a = task_rows(&mut rng, re, n);
        let b = &a * common::rand_vector(&mut rng, n) * 2.0;
        let w = weight(&mut rng);
        level = level.with_equality(&a, &b, w);
        if rng.gen_bool(0.5) {
            let ri = rng.gen_range(1..=n / 2 + 1);
            let c = task_rows(&mut rng, ri, n);
            let centre = &c * common::rand_vector(&mut rng, n) * 2.0;
            let half = DVector::from_fn(ri, |_, _| rng.gen_range(0.0..0.5));
            let (l, u) = (&centre - &half, &centre + &half);
            let w = weight(&mut rng);
            level = level.with_inequality(&c, &l, &u, w);
        }
        out.push(level);
    }
    let lx = DVector::from_fn(n, |_, _| -rng.gen_range(0.5..3.0));
    let ux = DVector::from_fn(n, |_, _| rng.gen_range(0.5..3.0));
    (out, lx, ux)
}

/// Level k's QP with every upper level held at what `x_prev` achieves (the formulation of
/// `HierarchicalQp`'s docs, held rows δ = 1e-9 (1 + |target|) wide), variables (x, v).
fn level_problem(
    levels: &[Level],
    k: usize,
    x_prev: &DVector<f64>,
    lx: &DVector<f64>,
    ux: &DVector<f64>,
    eps: f64,
) -> QpProblem {
    let n = lx.len();
    let lv = &levels[k];
    let ri = lv.n_in();
    let held_in: usize = levels[..k].iter().map(Level::n_in).sum();
    let held_eq: usize = levels[..k].iter().map(Level::n_eq).sum();
    let mut p = QpProblem::new(n + ri, 0, ri + held_in + held_eq);
    let w = DMatrix::from_diagonal(&lv.eq_weights);
    let h = lv.a.transpose() * &w * &lv.a;
    // The regularization rule of `HierarchicalQp`: ε, at least 1e-12 of the largest diagonal.
    let eps = eps.max(1e-12 * h.diagonal().max());
    let h = h + DMatrix::identity(n, n) * eps;
    p.h.view_mut((0, 0), (n, n)).copy_from(&h);
    for r in 0..ri {
        p.h[(n + r, n + r)] = lv.in_weights[r];
    }
    let g = -(lv.a.transpose() * (&w * &lv.b));
    p.g.rows_mut(0, n).copy_from(&g);
    let mut row = 0;
    for r in 0..ri {
        p.c.view_mut((row, 0), (1, n)).copy_from(&lv.c.row(r));
        p.c[(row, n + r)] = -1.0;
        (p.l[row], p.u[row]) = (lv.l[r], lv.u[r]);
        row += 1;
    }
    for up in &levels[..k] {
        let cx = &up.c * x_prev;
        for r in 0..up.n_in() {
            p.c.view_mut((row, 0), (1, n)).copy_from(&up.c.row(r));
            (p.l[row], p.u[row]) = (up.l[r].min(cx[r]), up.u[r].max(cx[r]));
            row += 1;
        }
    }
    for up in &levels[..k] {
        let ax = &up.a * x_prev;
        for r in 0..up.n_eq() {
            p.c.view_mut((row, 0), (1, n)).copy_from(&up.a.row(r));
            let delta = 1e-9 * (1.0 + ax[r].abs());
            (p.l[row], p.u[row]) = (ax[r] - delta, ax[r] + delta);
            row += 1;
        }
    }
    p.lx.rows_mut(0, n).copy_from(lx);
    p.ux.rows_mut(0, n).copy_from(ux);
    p
}

/// The lexicographic optimum by Clarabel, level by level: `Some(x)`, or `None` if Clarabel
/// fails on a level.
fn clarabel_cascade(
    levels: &[Level],
    lx: &DVector<f64>,
    ux: &DVector<f64>,
) -> Option<DVector<f64>> {
    let n = lx.len();
    let mut x = DVector::zeros(n);
    for k in 0..levels.len() {
        match clarabel_solve(&level_problem(levels, k, &x, lx, ux, 1e-9)) {
            Reference::Solved { x: sol, .. } => {
                x = DVector::from_fn(n, |i, _| sol[i].max(lx[i]).min(ux[i]));
            }
            _ => return None,
        }
    }
    Some(x)
}

/// 300 hierarchies, compared lexicographically: at the first level whose costs differ by more
/// than 1e-6 (relative to 1 + the cost), a lower cost for corps means Clarabel's interior
/// point stopped short on that ill-scaled level (corps is better), a higher one that corps is
/// worse. Held as a ledger (the counts printed): corps' failures and its worse answers may
/// shrink, not grow.
#[test]
fn hierarchies_of_2_to_5_levels_match_a_clarabel_cascade() {
    let (mut compared, mut failed_ours, mut failed_reference) = (0, 0, 0);
    let (mut worse, mut better) = (Vec::new(), 0);
    for seed in 0..300u64 {
        let (levels, lx, ux) = random_hierarchy(seed);
        let n = lx.len();
        let mut hqp = HierarchicalQp::new(n, levels.clone());
        hqp.lx = lx.clone();
        hqp.ux = ux.clone();
        let ours = match hqp.solve() {
            Ok(x) => x.clone(),
            Err(e) => {
                println!("seed {seed}: corps: {e}");
                failed_ours += 1;
                continue;
            }
        };
        let Some(reference) = clarabel_cascade(&levels, &lx, &ux) else {
            failed_reference += 1;
            continue;
        };
        compared += 1;
        for (k, level) in levels.iter().enumerate() {
            let (c_ours, c_ref) = (level.cost(&ours), level.cost(&reference));
            if (c_ours - c_ref).abs() > 1e-6 * (1.0 + c_ref) {
                if c_ours < c_ref {
                    better += 1;
                } else {
                    worse.push((seed, k, c_ours, c_ref));
                }
                break;
            }
        }
    }
    for (seed, k, ours, reference) in &worse {
        println!("seed {seed}: level {k} cost {ours:.9e}, Clarabel's cascade {reference:.9e}");
    }
    println!(
        "{compared} hierarchies compared: corps worse in {}, better in {better}; corps \
         failed on {failed_ours}, Clarabel on {failed_reference}",
        worse.len()
    );
    assert_eq!(failed_ours, 0, "hierarchies corps failed on");
    assert!(
        worse.len() <= LEDGER_WORSE,
        "hierarchies where corps is worse: {}",
        worse.len()
    );
}

/// The measured state (2026-11-27), short of the goal (every hierarchy solved with the
/// reference's costs): of the 267 both solve, corps is worse in 23 and better in 111 (Clarabel
/// fails 33); corps solves all 300 (3 were spurious infeasibilities before a level reported
/// infeasible was retried with wider held rows). A "worse" at level k may come from an upper
/// level whose costs agreed only to the 1e-6 tolerance (costs reach 1e8 here, so the two
/// answers may differ along directions the upper level barely weighs): an upper bound on
/// corps' defects. corps must solve every hierarchy.
const LEDGER_WORSE: usize = 23;
