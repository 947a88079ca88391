//! After setup, solves do not touch the heap: a counting global allocator (counting only on
//! the thread that sets the flag) sees zero allocations during repeated solves, cold and
//! warm, on the fast path and through the active-set iterations, and on failures.

mod common;

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use corps_qp::{ActiveSetSolver, QpError, QpProblem, Settings};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

struct Counting;

thread_local! {
    static COUNTING: Cell<bool> = const { Cell::new(false) };
    /// Allocations made by this thread while it counts (per thread: the tests run in
    /// parallel, and one test's allocations must not land in another's count).
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

fn note_allocation() {
    if COUNTING.with(|c| c.get()) {
        ALLOCATIONS.with(|a| a.set(a.get() + 1));
    }
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        note_allocation();
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        note_allocation();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn count_allocations(f: impl FnOnce()) -> usize {
    let before = ALLOCATIONS.with(|a| a.get());
    COUNTING.with(|c| c.set(true));
    f();
    COUNTING.with(|c| c.set(false));
    ALLOCATIONS.with(|a| a.get()) - before
}

#[test]
fn repeated_solves_do_not_allocate() {
    // The counter works.
    assert!(count_allocations(|| drop(std::hint::black_box(vec![1.0f64; 10]))) >= 1);

    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let (n, ne, ni) = (40, 12, 50);
    let problems: Vec<QpProblem> = (0..10)
        .map(|_| common::random_feasible_qp(&mut rng, n, ne, ni, true))
        .collect();
    let mut infeasible = problems[0].clone();
    infeasible.l[0] = 1.0;
    infeasible.u[0] = 0.0;
    let mut nan = problems[0].clone();
    nan.g[0] = f64::NAN;
    // Equality-only problem: solved by the range-space fast path.
    let mut eq_only = problems[1].clone();
    eq_only.l.fill(f64::NEG_INFINITY);
    eq_only.u.fill(f64::INFINITY);
    eq_only.lx.fill(f64::NEG_INFINITY);
    eq_only.ux.fill(f64::INFINITY);

    let tsid = common::load_tsid();
    for warm in [true, false] {
        let settings = Settings {
            warm_start: warm,
            ..Settings::default()
        };
        let mut s = ActiveSetSolver::with_settings(n, ne, ni, settings);
        let mut t = ActiveSetSolver::with_settings(62, 18, 66, settings);
        let mut iterations = 0;
        let count = count_allocations(|| {
            for _ in 0..3 {
                for p in &problems {
                    iterations += s.solve(p).map(|sol| sol.iterations).unwrap_or(0);
                    // Same problem again: warm start from the final factorization.
                    iterations += s.solve(p).map(|sol| sol.iterations).unwrap_or(0);
                }
                assert!(s.solve(&infeasible).is_err());
                assert!(s.solve(&nan).is_err());
                assert!(s.solve(&eq_only).is_ok());
                for q in &tsid {
                    assert!(t.solve(&q.problem).is_ok());
                }
            }
        });
        assert!(iterations > 0, "the active-set iterations ran");
        assert_eq!(
            count, 0,
            "heap allocations during solves (warm_start = {warm})"
        );
    }
}

/// The fallbacks allocate nothing either: ill-conditioned, degenerate problems (cond(H) to
/// 1e12, near-copy rows) take the proximal iterations, the solve on their last active set and
/// the tightening of loose answers (the 300 first problems of `tests/ill_conditioned.rs`,
/// answered and refused alike).
#[test]
fn fallback_solves_do_not_allocate() {
    let mut rng = ChaCha8Rng::seed_from_u64(0x111c);
    let problems: Vec<QpProblem> = (0..300)
        .map(|_| common::ill_conditioned_qp(&mut rng))
        .collect();
    let mut solvers: Vec<ActiveSetSolver> = problems.iter().map(common::cold_solver).collect();
    let (mut solved, mut refused, mut failed) = (0, 0, 0);
    let count = count_allocations(|| {
        for (s, p) in solvers.iter_mut().zip(&problems) {
            match s.solve(p) {
                Ok(_) => solved += 1,
                // Refused: the fallback's last step (the solve on the active set) ran and
                // its answer missed the conditions.
                Err(QpError::Inaccurate) => refused += 1,
                Err(_) => failed += 1,
            }
        }
    });
    assert!(
        solved > 200 && refused > 0 && failed > 0,
        "{solved} solved, {refused} refused, {failed} not solved"
    );
    assert_eq!(count, 0, "heap allocations during the fallback solves");
}
