//! Degenerate vertices: more active constraints than the free space can carry, with linearly
//! dependent active normals.
//!
//! `tests/data/ik_talos_degenerate.json` is the QP of level 3 (waist) of the TALOS velocity IK
//! on its first tick after a CoM step of (1, 2, −3) cm (`corps-control`'s
//! `ik_kinematic_loop_converges`): 38 variables, 15 equality rows holding the levels above
//! (feet, CoM), and joint-velocity bounds, many of which the upper levels already saturate.

mod common;

use common::{clarabel_solve, kkt, Reference};
use corps_qp::{ActiveSetSolver, HierarchicalQp, Level, QpProblem, Settings};
use nalgebra::{DMatrix, DVector};

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
    let (n, ne, ni) = p.dims();
    for portable in [false, true] {
        let mut s = ActiveSetSolver::with_settings(
            n,
            ne,
            ni,
            Settings {
                warm_start: false,
                ..Settings::default()
            },
        );
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
