//! Helpers shared by the integration tests and the benchmarks: random QP generators, the
//! Clarabel reference solve, KKT residuals and the TSID/TALOS data loader.
#![allow(dead_code)]

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};
use corps_qp::{ActiveSetSolver, QpProblem, Settings, Solution};
use nalgebra::{DMatrix, DVector};
use rand::Rng;

/// Random matrix with entries uniform in [−1, 1].
/// A solver sized for `p` that starts every solve cold (no warm start), as the reference
/// comparisons need.
pub fn cold_solver(p: &QpProblem) -> ActiveSetSolver {
    let (n, ne, ni) = p.dims();
    ActiveSetSolver::with_settings(
        n,
        ne,
        ni,
        Settings {
            warm_start: false,
            ..Settings::default()
        },
    )
}

pub fn rand_matrix(rng: &mut impl Rng, r: usize, c: usize) -> DMatrix<f64> {
    DMatrix::from_fn(r, c, |_, _| rng.gen_range(-1.0..1.0))
}

/// Random vector with entries uniform in [−1, 1].
pub fn rand_vector(rng: &mut impl Rng, n: usize) -> DVector<f64> {
    DVector::from_fn(n, |_, _| rng.gen_range(-1.0..1.0))
}

/// A strictly convex QP that is feasible by construction: a point `x0` satisfies every
/// constraint; `H = MᵀM/n + I/2` (condition number ≲ 10); inequality rows are two-sided or
/// one-sided at random, with bounds `C x0 ∓ margin` (margins in [0, 1]); the gradient is large
/// enough that about 40 % of the inequalities end up active.
pub fn random_feasible_qp(
    rng: &mut impl Rng,
    n: usize,
    ne: usize,
    ni: usize,
    bounds: bool,
) -> QpProblem {
    let m = rand_matrix(rng, n, n);
    let mut p = QpProblem::new(n, ne, ni);
    p.h = m.transpose() * &m / n as f64 + DMatrix::identity(n, n) * 0.5;
    p.g = rand_vector(rng, n) * 3.0;
    let x0 = rand_vector(rng, n);
    p.a = rand_matrix(rng, ne, n);
    p.b = &p.a * &x0;
    p.c = rand_matrix(rng, ni, n);
    let cx0 = &p.c * &x0;
    for i in 0..ni {
        let kind = rng.gen_range(0..10);
        let lo = cx0[i] - rng.gen_range(0.0..1.0);
        let hi = cx0[i] + rng.gen_range(0.0..1.0);
        p.l[i] = if kind == 0 { f64::NEG_INFINITY } else { lo };
        p.u[i] = if kind == 1 { f64::INFINITY } else { hi };
    }
    if bounds {
        for i in 0..n {
            if rng.gen_bool(0.5) {
                p.lx[i] = x0[i] - rng.gen_range(0.0..0.5);
            }
            if rng.gen_bool(0.5) {
                p.ux[i] = x0[i] + rng.gen_range(0.0..0.5);
            }
        }
    }
    p
}

/// Max-abs KKT residuals of a solution, in the crate's multiplier convention
/// `H x + g + Aᵀ y + Cᵀ z + z_box = 0`.
#[derive(Debug, Clone, Copy)]
pub struct Kkt {
    pub stationarity: f64,
    pub primal: f64,
    pub dual: f64,
    pub complementarity: f64,
}

impl Kkt {
    pub fn max(&self) -> f64 {
        self.stationarity
            .max(self.primal)
            .max(self.dual)
            .max(self.complementarity)
    }
}

fn side_residuals(z: f64, s: f64, lo: f64, hi: f64, inf: f64) -> (f64, f64, f64) {
    let (lo_f, hi_f) = (lo > -inf, hi < inf);
    let primal = (if lo_f { lo - s } else { 0.0 })
        .max(if hi_f { s - hi } else { 0.0 })
        .max(0.0);
    let dual = (if hi_f { 0.0 } else { z.max(0.0) }).max(if lo_f { 0.0 } else { (-z).max(0.0) });
    let comp = (if hi_f {
        z.max(0.0) * (hi - s).abs()
    } else {
        0.0
    })
    .max(if lo_f {
        (-z).max(0.0) * (s - lo).abs()
    } else {
        0.0
    });
    (primal, dual, comp)
}

pub fn kkt(p: &QpProblem, s: &Solution) -> Kkt {
    let inf = 1e10;
    let x = &s.x;
    let st = &p.h * x + &p.g + p.a.transpose() * &s.y_eq + p.c.transpose() * &s.z_in + &s.z_box;
    let mut r = Kkt {
        stationarity: st.amax(),
        primal: if p.a.nrows() > 0 {
            (&p.a * x - &p.b).amax()
        } else {
            0.0
        },
        dual: 0.0,
        complementarity: 0.0,
    };
    let cx = &p.c * x;
    for i in 0..p.c.nrows() {
        let (a, b, c) = side_residuals(s.z_in[i], cx[i], p.l[i], p.u[i], inf);
        r.primal = r.primal.max(a);
        r.dual = r.dual.max(b);
        r.complementarity = r.complementarity.max(c);
    }
    for i in 0..x.len() {
        let (a, b, c) = side_residuals(s.z_box[i], x[i], p.lx[i], p.ux[i], inf);
        r.primal = r.primal.max(a);
        r.dual = r.dual.max(b);
        r.complementarity = r.complementarity.max(c);
    }
    r
}

/// The largest KKT residual scaled as ProxQP and OSQP scale theirs: stationarity over
/// `1 + max(‖Hx‖∞, ‖g‖∞, ‖Aᵀy‖∞, ‖Cᵀz‖∞, ‖z_box‖∞)`, the primal residual over
/// `1 + max(‖Ax‖∞, ‖b‖∞, ‖Cx‖∞)`, complementarity (a multiplier times a constraint's slack)
/// over the product of the two.
pub fn kkt_scaled(p: &QpProblem, s: &Solution) -> f64 {
    let r = kkt(p, s);
    let x = &s.x;
    let dual_scale = 1.0
        + [
            (&p.h * x).amax(),
            p.g.amax(),
            (p.a.transpose() * &s.y_eq).amax(),
            (p.c.transpose() * &s.z_in).amax(),
            s.z_box.amax(),
        ]
        .into_iter()
        .fold(0.0, f64::max);
    let primal_scale = 1.0
        + [
            if p.a.nrows() > 0 {
                (&p.a * x).amax()
            } else {
                0.0
            },
            if p.b.is_empty() { 0.0 } else { p.b.amax() },
            if p.c.nrows() > 0 {
                (&p.c * x).amax()
            } else {
                0.0
            },
        ]
        .into_iter()
        .fold(0.0, f64::max);
    (r.stationarity / dual_scale)
        .max(r.primal / primal_scale)
        .max(r.dual / dual_scale)
        .max(r.complementarity / (primal_scale * dual_scale))
}

/// Outcome of the Clarabel reference solve.
#[derive(Debug, Clone)]
pub enum Reference {
    Solved { x: DVector<f64>, objective: f64 },
    Infeasible,
    Other(String),
}

/// Clarabel's data for `p`: `P` (upper triangle), `q`, `A`, `b`, cones (equalities, then
/// `C x ≤ u`, `−C x ≤ −l`, `x ≤ ux`, `−x ≤ −lx` for finite sides; |v| ≥ 1e10 is infinite).
pub struct ClarabelData {
    pub p: CscMatrix<f64>,
    pub q: Vec<f64>,
    pub a: CscMatrix<f64>,
    pub b: Vec<f64>,
    pub cones: Vec<SupportedConeT<f64>>,
}

pub fn clarabel_data(p: &QpProblem) -> ClarabelData {
    let (n, ne, ni) = p.dims();
    let inf = 1e10;
    let (mut pi, mut pj, mut pv) = (vec![], vec![], vec![]);
    for j in 0..n {
        for i in 0..=j {
            let v = 0.5 * (p.h[(i, j)] + p.h[(j, i)]);
            if v != 0.0 {
                pi.push(i);
                pj.push(j);
                pv.push(v);
            }
        }
    }
    let (mut ai, mut aj, mut av, mut b) = (vec![], vec![], vec![], vec![]);
    let mut row = 0;
    let mut push_row =
        |coefs: &mut dyn Iterator<Item = (usize, f64)>, rhs: f64, b: &mut Vec<f64>| {
            for (j, v) in coefs {
                if v != 0.0 {
                    ai.push(row);
                    aj.push(j);
                    av.push(v);
                }
            }
            b.push(rhs);
            row += 1;
        };
    for i in 0..ne {
        push_row(&mut (0..n).map(|j| (j, p.a[(i, j)])), p.b[i], &mut b);
    }
    for i in 0..ni {
        if p.u[i] < inf {
            push_row(&mut (0..n).map(|j| (j, p.c[(i, j)])), p.u[i], &mut b);
        }
        if p.l[i] > -inf {
            push_row(&mut (0..n).map(|j| (j, -p.c[(i, j)])), -p.l[i], &mut b);
        }
    }
    for i in 0..n {
        if p.ux[i] < inf {
            push_row(&mut std::iter::once((i, 1.0)), p.ux[i], &mut b);
        }
        if p.lx[i] > -inf {
            push_row(&mut std::iter::once((i, -1.0)), -p.lx[i], &mut b);
        }
    }
    let m = b.len();
    let mut cones = vec![];
    if ne > 0 {
        cones.push(SupportedConeT::ZeroConeT(ne));
    }
    if m > ne {
        cones.push(SupportedConeT::NonnegativeConeT(m - ne));
    }
    ClarabelData {
        p: CscMatrix::new_from_triplets(n, n, pi, pj, pv),
        q: p.g.as_slice().to_vec(),
        a: CscMatrix::new_from_triplets(m, n, ai, aj, av),
        b,
        cones,
    }
}

/// Solve `p` with Clarabel at tight tolerances (gap 1e-13, feasibility 1e-12; on degenerate
/// problems an interior point's x error scales like the square root of the gap).
pub fn clarabel_solve(p: &QpProblem) -> Reference {
    let d = clarabel_data(p);
    let settings = DefaultSettingsBuilder::default()
        .verbose(false)
        .tol_gap_abs(1e-13)
        .tol_gap_rel(1e-13)
        .tol_feas(1e-12)
        .max_iter(200)
        .build()
        .unwrap();
    let mut solver = match DefaultSolver::new(&d.p, &d.q, &d.a, &d.b, &d.cones, settings) {
        Ok(s) => s,
        Err(e) => return Reference::Other(format!("{e:?}")),
    };
    solver.solve();
    match solver.solution.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => {
            let x = DVector::from_vec(solver.solution.x.clone());
            let objective = p.objective(&x);
            Reference::Solved { x, objective }
        }
        SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => {
            Reference::Infeasible
        }
        s => Reference::Other(format!("{s:?}")),
    }
}

/// One TSID/eiquadprog QP of the TALOS data set.
pub struct TsidQp {
    pub tick: u64,
    pub problem: QpProblem,
    pub x: DVector<f64>,
    pub objective: f64,
    pub eiquadprog_us: f64,
    pub contact_points: [[f64; 3]; 4],
}

fn matrix(v: &serde_json::Value, r: usize, c: usize) -> DMatrix<f64> {
    let rows = v.as_array().unwrap();
    assert_eq!(rows.len(), r);
    DMatrix::from_fn(r, c, |i, j| rows[i][j].as_f64().unwrap())
}

fn vector(v: &serde_json::Value) -> DVector<f64> {
    DVector::from_vec(
        v.as_array()
            .unwrap()
            .iter()
            .map(|e| e.as_f64().unwrap())
            .collect(),
    )
}

/// Load `tests/data/tsid_talos_double.json` (converted by `tools/convert_tsid_qps.py`).
pub fn load_tsid() -> Vec<TsidQp> {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/tsid_talos_double.json"
    );
    let text = std::fs::read_to_string(path).expect("TSID data file");
    let root: serde_json::Value = serde_json::from_str(&text).unwrap();
    root["qps"]
        .as_array()
        .unwrap()
        .iter()
        .map(|q| {
            let n = q["nVar"].as_u64().unwrap() as usize;
            let ne = q["nEq"].as_u64().unwrap() as usize;
            let ni = q["nIn"].as_u64().unwrap() as usize;
            let mut p = QpProblem::new(n, ne, ni);
            p.h = matrix(&q["H"], n, n);
            p.g = vector(&q["g"]);
            p.a = matrix(&q["A"], ne, n);
            p.b = vector(&q["b"]);
            p.c = matrix(&q["C"], ni, n);
            p.l = vector(&q["l"]);
            p.u = vector(&q["u"]);
            let cp = &q["contact_points"];
            let mut contact_points = [[0.0; 3]; 4];
            for (k, pt) in contact_points.iter_mut().enumerate() {
                for (a, v) in pt.iter_mut().enumerate() {
                    *v = cp[k][a].as_f64().unwrap();
                }
            }
            TsidQp {
                tick: q["tick"].as_u64().unwrap(),
                problem: p,
                x: vector(&q["x"]),
                objective: q["objective"].as_f64().unwrap(),
                eiquadprog_us: q["eiquadprog_us"].as_f64().unwrap(),
                contact_points,
            }
        })
        .collect()
}

/// Sole wrench `Σₖ [fₖ; pₖ × fₖ]` of the 4 corner forces `f` (12 values, corner-major).
pub fn sole_wrench(f: &[f64], points: &[[f64; 3]; 4]) -> [f64; 6] {
    let mut w = [0.0; 6];
    for (k, p) in points.iter().enumerate() {
        let fk = [f[3 * k], f[3 * k + 1], f[3 * k + 2]];
        w[0] += fk[0];
        w[1] += fk[1];
        w[2] += fk[2];
        w[3] += p[1] * fk[2] - p[2] * fk[1];
        w[4] += p[2] * fk[0] - p[0] * fk[2];
        w[5] += p[0] * fk[1] - p[1] * fk[0];
    }
    w
}

/// The problem restricted to the constraints of an infeasibility certificate: the same
/// objective, the listed equality rows, each listed side of an inequality row (the other side
/// open) and each listed side of a variable bound; every other constraint dropped.
pub fn restricted_to(p: &QpProblem, certificate: &[corps_qp::ActiveConstraint]) -> QpProblem {
    use corps_qp::ActiveConstraint::*;
    let (n, _, _) = p.dims();
    let eq: Vec<usize> = certificate
        .iter()
        .filter_map(|c| match c {
            Equality(i) => Some(*i),
            _ => None,
        })
        .collect();
    let mut rows: Vec<usize> = certificate
        .iter()
        .filter_map(|c| match c {
            Lower(i) | Upper(i) => Some(*i),
            _ => None,
        })
        .collect();
    rows.sort_unstable();
    rows.dedup();
    let mut r = QpProblem::new(n, eq.len(), rows.len());
    r.h = p.h.clone();
    r.g = p.g.clone();
    for (k, &i) in eq.iter().enumerate() {
        r.a.set_row(k, &p.a.row(i));
        r.b[k] = p.b[i];
    }
    for (k, &i) in rows.iter().enumerate() {
        r.c.set_row(k, &p.c.row(i));
        r.l[k] = if certificate.contains(&Lower(i)) {
            p.l[i]
        } else {
            f64::NEG_INFINITY
        };
        r.u[k] = if certificate.contains(&Upper(i)) {
            p.u[i]
        } else {
            f64::INFINITY
        };
    }
    for i in 0..n {
        r.lx[i] = if certificate.contains(&LowerBound(i)) {
            p.lx[i]
        } else {
            f64::NEG_INFINITY
        };
        r.ux[i] = if certificate.contains(&UpperBound(i)) {
            p.ux[i]
        } else {
            f64::INFINITY
        };
    }
    r
}

/// One feasible problem of `tests/ill_conditioned.rs`' family: H = BᵀB (rank r < n) + ε I with
/// ε down to 1e-12, duplicated and nearly parallel rows (1e-10 apart) consistent with one
/// point x0, redundant equalities and rank-deficient equality blocks.
pub fn ill_conditioned_qp(rng: &mut impl Rng) -> QpProblem {
    let n = rng.gen_range(5..30);
    let r = rng.gen_range(1..n);
    let eps = [1e-3, 1e-6, 1e-9, 1e-12][rng.gen_range(0..4)];
    let b = rand_matrix(rng, r, n);
    let x0 = rand_vector(rng, n);
    // Equalities: independent rows, then copies, near copies (1e-10 apart) and combinations.
    let ne0 = rng.gen_range(0..n / 2 + 1);
    let extra = if ne0 > 0 { rng.gen_range(0..4) } else { 0 };
    let ni0 = rng.gen_range(1..n + 1);
    let ni_extra = rng.gen_range(0..4);
    let mut p = QpProblem::new(n, ne0 + extra, ni0 + ni_extra);
    p.h = b.transpose() * &b + DMatrix::identity(n, n) * eps;
    p.g = rand_vector(rng, n) * rng.gen_range(0.1..10.0);
    let a0 = rand_matrix(rng, ne0, n);
    p.a.rows_mut(0, ne0).copy_from(&a0);
    for d in 0..extra {
        let src = rng.gen_range(0..ne0);
        let row = match rng.gen_range(0..3) {
            0 => a0.row(src).clone_owned(),
            1 => a0.row(src) + rand_matrix(rng, 1, n) * 1e-10,
            _ => a0.tr_mul(&rand_vector(rng, ne0)).transpose(),
        };
        p.a.set_row(ne0 + d, &row);
    }
    p.b = &p.a * &x0;
    // Inequalities through or around x0, some duplicated or nearly parallel.
    let c0 = rand_matrix(rng, ni0, n);
    p.c.rows_mut(0, ni0).copy_from(&c0);
    for d in 0..ni_extra {
        let src = rng.gen_range(0..ni0);
        let row = if rng.gen_bool(0.5) {
            c0.row(src).clone_owned()
        } else {
            c0.row(src) + rand_matrix(rng, 1, n) * 1e-10
        };
        p.c.set_row(ni0 + d, &row);
    }
    let cx0 = &p.c * &x0;
    for i in 0..p.c.nrows() {
        let (lo, hi) = (
            cx0[i] - rng.gen_range(0.0..0.5),
            cx0[i] + rng.gen_range(0.0..0.5),
        );
        match rng.gen_range(0..3) {
            0 => (p.l[i], p.u[i]) = (lo, hi),
            1 => (p.l[i], p.u[i]) = (f64::NEG_INFINITY, hi),
            _ => (p.l[i], p.u[i]) = (lo, f64::INFINITY),
        }
    }
    if rng.gen_bool(0.5) {
        p.lx = DVector::from_fn(n, |i, _| x0[i] - rng.gen_range(0.0..1.0));
        p.ux = DVector::from_fn(n, |i, _| x0[i] + rng.gen_range(0.0..1.0));
    }
    p
}
