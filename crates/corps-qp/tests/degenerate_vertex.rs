//! Degenerate vertices: more active constraints than the free space can carry, with linearly
//! dependent active normals.
//!
//! `tests/data/ik_talos_degenerate.json` is the QP of level 3 (waist) of the TALOS velocity IK
//! on its first tick after a CoM step of (1, 2, −3) cm (`corps-control`'s
//! `ik_kinematic_loop_converges`): 38 variables, 15 equality rows holding the levels above
//! (feet, CoM), and joint-velocity bounds, many of which the upper levels already saturate.

mod common;

use common::{clarabel_solve, kkt, Reference};
use corps_qp::{HierarchicalQp, Level, QpProblem};
use nalgebra::{DMatrix, DVector};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn json() -> serde_json::Value {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/ik_talos_degenerate.json"
    );
    serde_json::from_str(&std::fs::read_to_string(path).expect("fixture")).unwrap()
}

fn matrix(v: &serde_json::Value, cols: usize) -> DMatrix<f64> {
    let rows = v.as_array().unwrap();
    DMatrix::from_fn(rows.len(), cols, |i, j| rows[i][j].as_f64().unwrap())
}

/// A vector whose `null` entries are `missing` (an infinite bound).
fn vector(v: &serde_json::Value, missing: f64) -> DVector<f64> {
    let a = v.as_array().unwrap();
    DVector::from_iterator(a.len(), a.iter().map(|e| e.as_f64().unwrap_or(missing)))
}

fn fixture_qp() -> QpProblem {
    let q = &json()["qp"];
    let h = matrix(&q["H"], q["H"].as_array().unwrap().len());
    let n = h.nrows();
    let a = matrix(&q["A"], n);
    let c = matrix(&q["C"], n);
    let mut p = QpProblem::new(n, a.nrows(), c.nrows());
    p.h = h;
    p.g = vector(&q["g"], f64::NAN);
    p.a = a;
    p.b = vector(&q["b"], f64::NAN);
    p.c = c;
    p.l = vector(&q["l"], f64::NEG_INFINITY);
    p.u = vector(&q["u"], f64::INFINITY);
    p.lx = vector(&q["lx"], f64::NEG_INFINITY);
    p.ux = vector(&q["ux"], f64::INFINITY);
    p
}

fn fixture_hierarchy() -> HierarchicalQp {
    let root = json();
    let h = &root["hierarchy"];
    let lx = vector(&h["lx"], f64::NEG_INFINITY);
    let n = lx.len();
    let levels = h["levels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| Level {
            a: matrix(&l["A"], n),
            b: vector(&l["b"], f64::NAN),
            eq_weights: vector(&l["eq_weights"], f64::NAN),
            c: matrix(&l["C"], n),
            l: vector(&l["l"], f64::NEG_INFINITY),
            u: vector(&l["u"], f64::INFINITY),
            in_weights: vector(&l["in_weights"], f64::NAN),
        })
        .collect();
    let mut hqp = HierarchicalQp::new(n, levels);
    hqp.lx = lx;
    hqp.ux = vector(&h["ux"], f64::INFINITY);
    hqp.regularization = root["regularization"].as_f64().unwrap();
    hqp
}

/// The fixture level is feasible (Clarabel solves it), and corps-qp finds the same optimum,
/// cold and with the portable kernels.
#[test]
fn ik_talos_level_matches_clarabel() {
    let p = fixture_qp();
    let (x_ref, obj_ref) = match clarabel_solve(&p) {
        Reference::Solved { x, objective } => (x, objective),
        other => panic!("Clarabel: {other:?}"),
    };
    for portable in [false, true] {
        let mut s = common::cold_solver(&p);
        if portable {
            s.force_portable_kernels();
        }
        let sol = s
            .solve(&p)
            .unwrap_or_else(|e| panic!("portable={portable}: {e}"));
        let dx = (&sol.x - &x_ref).amax();
        let dobj = (sol.objective - obj_ref).abs() / (1.0 + obj_ref.abs());
        let r = kkt(&p, sol);
        eprintln!(
            "portable={portable}: |x − x_clarabel| = {dx:e}, objective rel. diff {dobj:e}, \
             KKT {r:?}, {} active, {} iterations",
            sol.active_set.len(),
            sol.iterations
        );
        assert!(dx <= 1e-6, "|x − x_clarabel| = {dx:e}");
        assert!(dobj <= 1e-6, "objective {} vs {obj_ref}", sol.objective);
        assert!(r.max() <= 1e-8, "KKT residuals {r:?}");
    }
}

/// The whole IK hierarchy of that tick solves, and every level keeps what the levels above
/// achieved.
#[test]
fn ik_talos_hierarchy_solves() {
    let mut hqp = fixture_hierarchy();
    let levels = hqp.levels().to_vec();
    let x = hqp.solve().expect("hierarchy").clone();
    for (k, lv) in levels.iter().enumerate() {
        eprintln!("level {k}: cost {:e}", lv.cost(&x));
    }
    let bound_violation = (0..x.len())
        .map(|i| (hqp.lx[i] - x[i]).max(x[i] - hqp.ux[i]).max(0.0))
        .fold(0.0, f64::max);
    assert!(
        bound_violation <= 1e-9,
        "bounds violated by {bound_violation:e}"
    );
}

/// A QP whose optimum is a degenerate vertex `x0`, by construction: `k` variables sit exactly
/// on a bound at `x0` with `n_eq + k > n` (more active constraints than variables), the
/// equality rows include linear combinations of other rows and of those bounds' normals
/// (dependent active normals, right-hand sides `A x0` rounded like any computed target), some
/// inequality rows pass through `x0` too, and `g = −H x0 − Aᵀ y − Cᵀ z − z_box` with
/// multipliers of the right signs (some zero: weakly active). `H` is well conditioned, or, with
/// `flat`, a rank-`r` task plus `1e-9 I` like a hierarchy level.
fn degenerate_vertex_qp(seed: u64, n: usize, flat: bool) -> (QpProblem, DVector<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let ne0 = rng.gen_range(1..=n / 2);
    let k = rng.gen_range(n - ne0 + 1..=n);
    let n_dep = rng.gen_range(1..=3);
    let ni = rng.gen_range(0..=n / 2);
    let ne = ne0 + n_dep;
    let x0 = common::rand_vector(&mut rng, n) * 2.0;
    let mut p = QpProblem::new(n, ne, ni);
    p.h = if flat {
        let r = rng.gen_range(1..=3);
        let b = common::rand_matrix(&mut rng, r, n);
        b.transpose() * &b + DMatrix::identity(n, n) * 1e-9
    } else {
        let m = common::rand_matrix(&mut rng, n, n);
        m.transpose() * &m / n as f64 + DMatrix::identity(n, n) * 0.5
    };
    // Bounds: the first k variables of a random order on a bound at x0 (side at random), the
    // others inside loose bounds or unbounded.
    let mut order: Vec<usize> = (0..n).collect();
    for i in (1..n).rev() {
        order.swap(i, rng.gen_range(0..=i));
    }
    let mut z_box = DVector::zeros(n);
    for (rank, &i) in order.iter().enumerate() {
        if rank < k {
            let weak = rng.gen_bool(0.2);
            let mag = if weak { 0.0 } else { rng.gen_range(0.1..2.0) };
            if rng.gen_bool(0.5) {
                p.lx[i] = x0[i];
                p.ux[i] = x0[i] + rng.gen_range(0.5..2.0);
                z_box[i] = -mag;
            } else {
                p.ux[i] = x0[i];
                p.lx[i] = x0[i] - rng.gen_range(0.5..2.0);
                z_box[i] = mag;
            }
        } else if rng.gen_bool(0.5) {
            p.lx[i] = x0[i] - rng.gen_range(0.1..1.0);
            p.ux[i] = x0[i] + rng.gen_range(0.1..1.0);
        }
    }
    // Equalities: independent rows, then combinations of them and of the active bounds.
    let a0 = common::rand_matrix(&mut rng, ne0, n);
    p.a.rows_mut(0, ne0).copy_from(&a0);
    for d in 0..n_dep {
        let mut row = a0.tr_mul(&common::rand_vector(&mut rng, ne0)).transpose();
        for &i in order.iter().take(k) {
            if rng.gen_bool(0.5) {
                row[i] += rng.gen_range(-1.0..1.0);
            }
        }
        p.a.set_row(ne0 + d, &row);
    }
    p.b = &p.a * &x0;
    // Inequalities: about half through x0 (active, multiplier of the right sign or zero),
    // the others inactive.
    p.c = common::rand_matrix(&mut rng, ni, n);
    let cx0 = &p.c * &x0;
    let mut z_in = DVector::zeros(ni);
    for i in 0..ni {
        let through = rng.gen_bool(0.5);
        let mag = if rng.gen_bool(0.2) {
            0.0
        } else {
            rng.gen_range(0.1..2.0)
        };
        if through && rng.gen_bool(0.5) {
            p.l[i] = cx0[i];
            p.u[i] = cx0[i] + rng.gen_range(0.1..1.0);
            z_in[i] = -mag;
        } else if through {
            p.u[i] = cx0[i];
            p.l[i] = f64::NEG_INFINITY;
            z_in[i] = mag;
        } else {
            p.l[i] = cx0[i] - rng.gen_range(0.1..1.0);
            p.u[i] = cx0[i] + rng.gen_range(0.1..1.0);
        }
    }
    let y = common::rand_vector(&mut rng, ne);
    p.g = -(&p.h * &x0) - p.a.tr_mul(&y) - p.c.tr_mul(&z_in) - &z_box;
    (p, x0)
}

fn check_degenerate_vertex(seed: u64, n: usize) -> Result<(), TestCaseError> {
    let (p, x0) = degenerate_vertex_qp(seed, n, false);
    let mut s = common::cold_solver(&p);
    let sol = s
        .solve(&p)
        .map_err(|e| TestCaseError::fail(format!("corps-qp: {e}")))?;
    let dx0 = (&sol.x - &x0).amax();
    prop_assert!(dx0 <= 1e-6, "|x − x0| = {dx0:e}");
    // The KKT residuals scaled by the problem's own magnitudes (ProxQP's and OSQP's
    // criterion) ≤ 1e-9; with a well-conditioned H also ≤ 1e-8 unscaled.
    let r = kkt(&p, sol);
    let scaled = common::kkt_scaled(&p, sol);
    prop_assert!(scaled <= 1e-9, "scaled KKT residual {scaled:e} ({r:?})");
    prop_assert!(r.max() <= 1e-8, "KKT residuals {r:?}");
    match clarabel_solve(&p) {
        Reference::Solved { x, objective } => {
            let dx = (&sol.x - &x).amax();
            prop_assert!(dx <= 1e-6, "|x − x_clarabel| = {dx:e}");
            let dobj = (sol.objective - objective).abs() / (1.0 + objective.abs());
            prop_assert!(dobj <= 1e-6, "objective {} vs {objective}", sol.objective);
        }
        other => prop_assert!(false, "Clarabel: {other:?}"),
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 64,
        // A fixed seed: CI runs the same cases every time (set another to explore);
        // no regression files are written during CI.
        rng_seed: proptest::test_runner::RngSeed::Fixed(0xde9e),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// Degenerate vertices with a well-conditioned H: corps-qp (cold) finds the constructed
    /// optimum x0 to 1e-6, agrees with Clarabel to 1e-6 in x and objective, and its KKT
    /// residuals are ≤ 1e-8.
    #[test]
    fn degenerate_vertices_match_clarabel(seed in any::<u64>(), n in 4usize..30) {
        check_degenerate_vertex(seed, n)?;
    }

}

/// The same with H = BᵀB + 1e-9 I (rank-1 to 3 task plus the hierarchy's regularization),
/// 1,000 seeded problems. Before the solver's proximal fallback
/// (`ActiveSetSolver::solve_proximal`) about one in five of these feasible problems was
/// reported infeasible (76 of 400). Now every one is solved with Clarabel's objective to 1e-6
/// (relative). Two bounds still fail in a few problems, counted here as known shortfalls:
/// the KKT residuals ≤ 1e-9 scaled (3 of 1000, worst 7.1e-8 when measured: rows
/// outside the final active set violated by up to 2.8e-7, which solving again on the active
/// set cannot reach; 4, worst 2.2e-7, before answers were tightened on their active set), and
/// x at the constructed optimum x0 to 1e-6 (1 of 1000, worst 1.0e-4: along directions where
/// H is 1e-9, the objective cannot tell them apart; 2 before). Fewer fails nothing; more
/// fails.
#[test]
fn degenerate_vertices_with_flat_hessian_are_solved() {
    const KNOWN_OVER: usize = 3;
    const KNOWN_FAR: usize = 1;
    let mut rng = ChaCha8Rng::seed_from_u64(0xf1a7);
    let (mut over, mut worst, mut far, mut worst_dx) = (0, 0.0f64, 0, 0.0f64);
    for case in 0..1000 {
        let seed: u64 = rng.gen();
        let n = rng.gen_range(4..30);
        let (p, x0) = degenerate_vertex_qp(seed, n, true);
        let mut s = common::cold_solver(&p);
        let sol = s
            .solve(&p)
            .unwrap_or_else(|e| panic!("case {case} (seed {seed}, n {n}): {e}"));
        let dx0 = (&sol.x - &x0).amax();
        worst_dx = worst_dx.max(dx0);
        if dx0 > 1e-6 {
            far += 1;
        }
        let scaled = common::kkt_scaled(&p, sol);
        worst = worst.max(scaled);
        if scaled > 1e-9 {
            over += 1;
        }
        match clarabel_solve(&p) {
            Reference::Solved { objective, .. } => {
                let dobj = (sol.objective - objective).abs() / (1.0 + objective.abs());
                assert!(
                    dobj <= 1e-6,
                    "case {case}: objective {} vs {objective}",
                    sol.objective
                );
            }
            other => panic!("case {case}: Clarabel: {other:?}"),
        }
    }
    println!("scaled KKT residual over 1e-9 in {over} of 1000 problems, worst {worst:e}");
    println!("|x − x0| over 1e-6 in {far} of 1000 problems, worst {worst_dx:e}");
    assert!(
        over <= KNOWN_OVER,
        "{over} problems over the scaled KKT bound of 1e-9 (known: {KNOWN_OVER}), worst {worst:e}"
    );
    assert!(
        far <= KNOWN_FAR,
        "{far} problems farther than 1e-6 from x0 (known: {KNOWN_FAR}), worst {worst_dx:e}"
    );
}
