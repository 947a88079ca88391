//! Ill-conditioned and degenerate QPs that are feasible by construction, against Clarabel for
//! the status and the objective: H = BᵀB (rank r < n) + ε I with ε down to 1e-12 (cond(H) to
//! 1e12), duplicated and nearly parallel equality and inequality rows (consistent with one
//! point), redundant equalities and rank-deficient equality blocks.

mod common;

use common::{clarabel_solve, Reference};
use corps_qp::QpError;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// 1,000 problems of the family. The goal (every one solved, KKT ≤ 1e-9 scaled, the
/// objective Clarabel's) is far off, and this test holds the measured state as a ledger, so
/// that a change that makes it worse fails and one that makes it better is seen:
/// - returned as optimal with a scaled KKT residual over 1e-6 (a wrong answer): 0 (42 before
///   every answer was checked against the optimality conditions; 1 until the check included
///   the active sides' multiplier signs: an upper bound held with a multiplier of −2.3e-4);
/// - refused as inaccurate (`QpError::Inaccurate`: the answer missed the conditions and the
///   proximal fallback did not produce one that meets them): 32 (37 before the fallback ended
///   with the original problem solved on its last active set);
/// - reported infeasible (or at the iteration limit) although feasible: 80 (176 before the
///   proximal fallback of `ActiveSetSolver::solve_proximal`, 92 before its last step);
/// - answered with a scaled KKT residual between 1e-9 (the accuracy) and 1e-6: 40; so
///   152 of the 1,000 are not solved to the accuracy (held as a total: an answer that
///   replaces a failure may well land between 1e-9 and 1e-6).
///
/// Where both solve, the objectives are compared with Clarabel's and the disagreements
/// printed (at cond(H) ~ 1e12 Clarabel's own answer is often the wrong one: corps' KKT
/// residuals there are ~1e-14).
#[test]
fn ill_conditioned_degenerate_problems_ledger() {
    const KNOWN_FAILED: usize = 80;
    const KNOWN_INACCURATE: usize = 32;
    const KNOWN_SHORT_OF_1E9: usize = 152;
    let mut rng = ChaCha8Rng::seed_from_u64(0x111c);
    let (mut failed, mut inaccurate, mut wrong, mut both, mut differ) = (0, 0, 0, 0, 0);
    let mut loose = 0;
    for _ in 0..1000 {
        let p = common::ill_conditioned_qp(&mut rng);
        let mut s = common::cold_solver(&p);
        match s.solve(&p) {
            Err(QpError::Inaccurate) => inaccurate += 1,
            Err(_) => failed += 1,
            Ok(sol) => {
                let kkt = common::kkt_scaled(&p, sol);
                if kkt > 1e-6 {
                    wrong += 1;
                } else {
                    if kkt > 1e-9 {
                        loose += 1;
                    }
                    if let Reference::Solved { objective, .. } = clarabel_solve(&p) {
                        both += 1;
                        if (sol.objective - objective).abs() / (1.0 + objective.abs()) > 1e-6 {
                            differ += 1;
                        }
                    }
                }
            }
        }
    }
    println!(
        "of 1000 feasible problems: {failed} not solved, {inaccurate} refused as inaccurate, \
         {wrong} wrong answers, {loose} with a KKT residual over 1e-9; of {both} both solved \
         (corps' KKT ≤ 1e-6), objectives differ in {differ}"
    );
    assert!(
        failed <= KNOWN_FAILED,
        "{failed} not solved (known: {KNOWN_FAILED})"
    );
    assert!(
        inaccurate <= KNOWN_INACCURATE,
        "{inaccurate} refused as inaccurate (known: {KNOWN_INACCURATE})"
    );
    assert_eq!(
        wrong, 0,
        "wrong answers (returned as optimal, KKT over 1e-6)"
    );
    let short = failed + inaccurate + wrong + loose;
    assert!(
        short <= KNOWN_SHORT_OF_1E9,
        "{short} problems not solved to a KKT residual of 1e-9 (known: {KNOWN_SHORT_OF_1E9})"
    );
}
