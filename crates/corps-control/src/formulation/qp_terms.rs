//! The pieces every QP formulation assembles its problem from: weighted task rows into the
//! Hessian and gradient, a contact's wrench cost, block copies.

use crate::contacts::Contact;
use crate::error::{ControlError, Result};
use crate::robot_state::RobotState;
use crate::tasks::{ContactForceTask, TaskRows};
use crate::FallbackReason;
use corps_model::Model;
use corps_qp::QpProblem;
use nalgebra::{DMatrix, DVector};

/// One control tick of a formulation that outputs torques: checks (q, v), computes the
/// model terms, lets `solve` write the torques (na) to `tau`; when the state is not finite or
/// `solve` fails, `tau` gets the safe command ([`crate::safe_torques`], damping
/// `safe_damping`) and the reason is returned.
pub(crate) fn torque_tick(
    model: &Model,
    state: &mut RobotState,
    q: &[f64],
    v: &[f64],
    safe_damping: f64,
    tau: &mut DVector<f64>,
    solve: impl FnOnce(&RobotState, &mut DVector<f64>) -> Result<()>,
) -> Option<FallbackReason> {
    let reason = match (
        model.check_configuration(q),
        model.check_tangent("velocity v", v),
    ) {
        (Err(e), _) | (_, Err(e)) => Some(FallbackReason::BadState(e.to_string())),
        _ => (state.update(model, q, v).map_err(ControlError::from))
            .and_then(|_| solve(state, tau))
            .err()
            .map(FallbackReason::Controller),
    };
    if reason.is_some() {
        crate::safe_torques(model, &mut state.data, q, v, safe_damping, tau);
    }
    reason
}

/// A contact's force terms, its force variables starting at column `col`: the friction
/// pyramid and normal-force bounds from inequality row `row`, the force regularization and
/// the force tasks that name it, their wanted wrench scaled by `force_scale` (1 but under
/// an energy tank's valves, seed 000 Eq 5.24).
pub(crate) fn add_force_terms(
    p: &mut QpProblem,
    contact: &Contact,
    force_tasks: &[(ContactForceTask, f64)],
    row: usize,
    col: usize,
    force_scale: f64,
) {
    contact.force_constraints(&mut p.c, &mut p.l, &mut p.u, row, col);
    add_wrench_cost(
        &mut p.h,
        &mut p.g,
        col,
        &contact.t,
        &contact.force_reg_components,
        &contact.force_reference,
        contact.force_reg_weight,
    );
    for (task, w) in force_tasks {
        if task.contact == contact.name {
            let ones = nalgebra::Vector6::repeat(1.0);
            add_wrench_cost(
                &mut p.h,
                &mut p.g,
                col,
                &contact.t,
                &ones,
                &(task.desired * force_scale),
                *w,
            );
        }
    }
}

/// Actuation bounds of `na` entries each, or an error naming their sizes.
pub(crate) fn check_actuation(
    actuation: &Option<(DVector<f64>, DVector<f64>)>,
    na: usize,
) -> Result<()> {
    match actuation {
        Some((lower, upper)) if lower.len() != na || upper.len() != na => {
            Err(ControlError::Config {
                name: "actuation".into(),
                reason: format!(
                    "bounds of sizes {} and {}, the model has {na} actuated dofs",
                    lower.len(),
                    upper.len()
                ),
            })
        }
        _ => Ok(()),
    }
}

/// One task row gathered for [`add_least_squares`]: its values and its non-zero columns.
#[derive(Clone, Debug)]
pub(crate) struct RowScratch {
    values: Vec<f64>,
    nonzeros: Vec<usize>,
}

impl RowScratch {
    /// Scratch for rows of up to `n` columns.
    pub(crate) fn new(n: usize) -> Self {
        Self {
            values: vec![0.0; n],
            nonzeros: Vec::with_capacity(n),
        }
    }
}

/// `H += w AᵀA` and `g −= w β Aᵀ b` for a task's rows, whose right side `b` is scaled by
/// `beta` (1 but under an energy tank's valves, seed 000 Eq 5.24): on the diagonal for a
/// selection (a joint-space task), else by [`add_least_squares`].
pub(crate) fn add_task_cost(
    h: &mut DMatrix<f64>,
    g: &mut DVector<f64>,
    rows: &TaskRows,
    w: f64,
    beta: f64,
    scratch: &mut RowScratch,
) {
    match rows.selection {
        Some(first) => {
            for k in 0..rows.rows() {
                h[(first + k, first + k)] += w;
                g[first + k] -= w * beta * rows.b[k];
            }
        }
        None => add_least_squares(h, g, rows, w, beta, scratch),
    }
}

/// `H += w AᵀA` and `g −= w β Aᵀ b` over the first `A.ncols()` variables, as one rank-1 update
/// `w a_r a_rᵀ` per task row. A frame task's rows are zero outside the frame's chain (a
/// foot's: 12 of TALOS' 38 columns), so a sparse row updates only its non-zero block; a
/// dense one (CoM, momentum) runs contiguous inner loops over H's columns.
pub(crate) fn add_least_squares(
    h: &mut DMatrix<f64>,
    g: &mut DVector<f64>,
    rows: &TaskRows,
    w: f64,
    beta: f64,
    scratch: &mut RowScratch,
) {
    let (m, n) = (rows.a.nrows(), rows.a.ncols());
    let nh = h.nrows();
    let a = rows.a.as_slice();
    let hs = h.as_mut_slice();
    let row = &mut scratch.values[..n];
    let nonzeros = &mut scratch.nonzeros;
    for r in 0..m {
        nonzeros.clear();
        for (i, x) in row.iter_mut().enumerate() {
            *x = a[i * m + r];
            if *x != 0.0 {
                nonzeros.push(i);
            }
        }
        let br = w * beta * rows.b[r];
        let sparse = 2 * nonzeros.len() < n;
        for &j in nonzeros.iter() {
            let aj = row[j];
            g[j] -= br * aj;
            let s = w * aj;
            let column = &mut hs[j * nh..j * nh + n];
            if sparse {
                for &i in nonzeros.iter() {
                    column[i] += s * row[i];
                }
            } else {
                for (hij, ai) in column.iter_mut().zip(row.iter()) {
                    *hij += s * ai;
                }
            }
        }
    }
}

/// Adds `w ‖diag(cw) (T f − f_ref)‖²` over the force variables starting at `col` (`T`: the
/// contact's 6 × n_f wrench generator): a contact's force regularization or force task.
pub(crate) fn add_wrench_cost(
    h: &mut DMatrix<f64>,
    g: &mut DVector<f64>,
    col: usize,
    t: &DMatrix<f64>,
    cw: &nalgebra::Vector6<f64>,
    f_ref: &nalgebra::Vector6<f64>,
    w: f64,
) {
    let nf = t.ncols();
    debug_assert_eq!(t.nrows(), 6, "a wrench generator has six rows");
    let nh = h.nrows();
    let (hs, ts) = (h.as_mut_slice(), t.as_slice());
    // Column i of T is ts[6 i..6 i + 6]; u = diag(cw²) T column i, in the same order of
    // operations as Σ_r cw_r cw_r T_ri T_rj.
    let cw2 = cw.map(|c| c * c);
    for i in 0..nf {
        let ti = &ts[6 * i..6 * i + 6];
        let u: [f64; 6] = std::array::from_fn(|r| cw2[r] * ti[r]);
        for j in 0..nf {
            let tj = &ts[6 * j..6 * j + 6];
            let mut acc = 0.0;
            for r in 0..6 {
                acc += u[r] * tj[r];
            }
            hs[(col + j) * nh + col + i] += w * acc;
        }
        let mut acc = 0.0;
        for r in 0..6 {
            acc += u[r] * f_ref[r];
        }
        g[col + i] -= w * acc;
    }
}

/// `dst[dr.., dc..] = src[sr.., sc..]` over a `rows × cols` block, column by column.
pub(crate) fn copy_block(
    dst: &mut DMatrix<f64>,
    (dr, dc): (usize, usize),
    src: &DMatrix<f64>,
    (sr, sc): (usize, usize),
    (rows, cols): (usize, usize),
) {
    let (nd, ns) = (dst.nrows(), src.nrows());
    let (d, s) = (dst.as_mut_slice(), src.as_slice());
    for c in 0..cols {
        let from = (sc + c) * ns + sr;
        let to = (dc + c) * nd + dr;
        d[to..to + rows].copy_from_slice(&s[from..from + rows]);
    }
}

/// `dst[dr + r, dc + c] = −src[sr + c, sc + r]`: a negated transposed block (`−Jcᵀ`).
pub(crate) fn copy_block_neg_transposed(
    dst: &mut DMatrix<f64>,
    (dr, dc): (usize, usize),
    src: &DMatrix<f64>,
    (sr, sc): (usize, usize),
    (rows, cols): (usize, usize),
) {
    let (nd, ns) = (dst.nrows(), src.nrows());
    let (d, s) = (dst.as_mut_slice(), src.as_slice());
    for c in 0..cols {
        let to = (dc + c) * nd + dr;
        for (r, x) in d[to..to + rows].iter_mut().enumerate() {
            *x = -s[(sc + r) * ns + sr + c];
        }
    }
}
