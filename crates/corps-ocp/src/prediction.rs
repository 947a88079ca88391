//! Predicting the rest of a person's walk to a known goal (seed 000 §3.17): the state is
//! estimated from the last samples (a sliding window), and the walking OCP
//! ([`crate::human_walk`]) is solved from there. Its horizon is the one the authors'
//! estimation code chooses (`optimizeT` of `estimation_oc.py`): the number of nodes that
//! minimises the optimum's cost per node (ten times it when DDP stopped unconverged before 50
//! iterations, 1e4 after), here by a golden-section search over the integers instead of
//! their Nelder–Mead on a real number rounded down.

use crate::ddp::{ActionModel, DdpSettings, DdpWorkspace};
use crate::error::OcpError;
use crate::human_walk::{HumanWalkEnd, HumanWalkStep, DT, NU, NX};
use nalgebra::Vector6;
use std::collections::BTreeMap;
use std::f64::consts::PI;

/// A predicted path.
#[derive(Clone, Debug, PartialEq)]
pub struct Prediction {
    /// Poses (x, y, θ) every [`DT`] from the last measured one.
    pub poses: Vec<[f64; 3]>,
    /// The horizon chosen (nodes) and the optimum's cost.
    pub nodes: usize,
    pub cost: f64,
    /// Whether DDP converged at that horizon.
    pub converged: bool,
    /// DDP solves the horizon search took.
    pub solves: usize,
}

/// Speed of the first horizon guess (m/s): an ordinary walking pace.
const GUESS_SPEED: f64 = 1.0;

/// The rest of the walk from `window` (the last measured poses, oldest first, `sample_dt`
/// apart; at least two) to `goal` (x, y, θ).
pub fn predict(
    window: &[[f64; 3]],
    sample_dt: f64,
    goal: [f64; 3],
) -> Result<Prediction, OcpError> {
    let n = window.len();
    if n < 2 || !(sample_dt > 0.0 && sample_dt.is_finite()) {
        return Err(OcpError::Invalid(format!(
            "a window of {n} poses {sample_dt} s apart: need two or more, a positive period"
        )));
    }
    if window.iter().flatten().chain(&goal).any(|v| !v.is_finite()) {
        return Err(OcpError::Invalid("non-finite pose or goal".into()));
    }
    // The recorded heading swings with the gait (the pelvis'): the state starts on the path
    // instead, heading along the window's displacement at its mean speed, with no sideways
    // speed and no turn rate. (A turn rate from the window's two halves is mostly the gait's
    // sway: on the shared walks it doubled the prediction's mean error, 0.334 against
    // 0.159 m at a quarter of the walk; from a 10-sample window it sent predictions 57 m off.)
    let (first, last) = (window[0], window[n - 1]);
    let span = (n - 1) as f64 * sample_dt;
    let speed = (last[0] - first[0]).hypot(last[1] - first[1]) / span;
    let heading = (last[1] - first[1]).atan2(last[0] - first[0]);
    // The source's heading term atan2(·) − θ is not wrapped: start with θ on the branch of
    // the direction to the goal, and give the poses back on the measured heading's.
    let to_goal = (goal[1] - last[1]).atan2(goal[0] - last[0]);
    let shift = 2.0 * PI * ((to_goal - heading) / (2.0 * PI)).round();
    let theta = heading + shift;
    let x0 = Vector6::new(last[0], last[1], theta, speed, 0.0, 0.0);
    let step = HumanWalkStep::new(goal);
    let end = HumanWalkEnd::new(goal);
    let settings = DdpSettings::default();
    // Each horizon's score, optimum and poses, solved once, all in one workspace.
    let mut workspace = DdpWorkspace::default();
    let mut running: Vec<&dyn ActionModel<NX, NU>> = Vec::new();
    let mut solved: BTreeMap<usize, Solved> = BTreeMap::new();
    let mut solve = |nodes: usize| -> Result<f64, OcpError> {
        if let Some(s) = solved.get(&nodes) {
            return Ok(s.score);
        }
        running.clear();
        running.resize(nodes, &step);
        let o = workspace.solve(&x0, &running, &end, None, &settings)?;
        // The authors' scores: the cost per node, ten times it when DDP stopped early
        // unconverged, 1e4 when it ran out of iterations.
        let per_node = o.cost / nodes as f64;
        let score = match (o.converged, o.iterations < 50) {
            (true, _) => per_node,
            (false, true) => 10.0 * per_node,
            (false, false) => 1e4,
        };
        let poses = workspace.xs().iter().map(|x| [x[0], x[1], x[2] - shift]);
        solved.insert(
            nodes,
            Solved {
                score,
                cost: o.cost,
                converged: o.converged,
                poses: poses.collect(),
            },
        );
        Ok(score)
    };
    let distance = (goal[0] - last[0]).hypot(goal[1] - last[1]);
    let guess = ((distance / GUESS_SPEED / DT).ceil() as usize).max(2);
    // Golden-section search of the cost per node over [guess/3, 3 guess].
    let (mut lo, mut hi) = ((guess / 3).max(2), 3 * guess);
    while hi - lo > 2 {
        let third = (hi - lo) as f64 * 0.381_966;
        let (a, b) = (lo + third.round() as usize, hi - third.round() as usize);
        let (a, b) = (a.min(b.saturating_sub(1)).max(lo), b.max(a + 1).min(hi));
        if solve(a)? <= solve(b)? {
            hi = b;
        } else {
            lo = a;
        }
    }
    let mut best = lo;
    for nodes in lo..=hi {
        if solve(nodes)? < solve(best)? {
            best = nodes;
        }
    }
    let solves = solved.len();
    let sol = solved
        .remove(&best)
        .ok_or_else(|| OcpError::Invalid("no horizon was solved".into()))?;
    Ok(Prediction {
        poses: sol.poses,
        nodes: best,
        cost: sol.cost,
        converged: sol.converged,
        solves,
    })
}

/// One horizon of the search, solved.
struct Solved {
    score: f64,
    cost: f64,
    converged: bool,
    poses: Vec<[f64; 3]>,
}

/// Distance from `p` to the polyline `path` (x, y).
pub fn distance_to_path(p: [f64; 2], path: &[[f64; 3]]) -> f64 {
    let mut best = f64::INFINITY;
    for w in path.windows(2) {
        let (a, b) = ([w[0][0], w[0][1]], [w[1][0], w[1][1]]);
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let len2 = dx * dx + dy * dy;
        let t = if len2 > 0.0 {
            (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        best = best.min((p[0] - a[0] - t * dx).hypot(p[1] - a[1] - t * dy));
    }
    if path.len() == 1 {
        best = (p[0] - path[0][0]).hypot(p[1] - path[0][1]);
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A person walking straight at the goal keeps walking straight at it and reaches it.
    #[test]
    fn a_straight_walk_is_predicted_straight_to_the_goal() {
        let window: Vec<[f64; 3]> = (0..10)
            .map(|k| [-3.0 + 0.01 * k as f64, 0.0, 0.0])
            .collect();
        let p = predict(&window, 0.01, [0.0, 0.0, 0.0]).unwrap();
        assert!(p.converged);
        let end = p.poses.last().unwrap();
        assert!(end[0].hypot(end[1]) < 0.1, "ends at {end:?}");
        assert!(p.poses.iter().all(|q| q[1].abs() < 1e-6), "leaves the line");
        // About an ordinary pace: 3 m in 2 to 6 s.
        let t = p.nodes as f64 * DT;
        assert!((2.0..=6.0).contains(&t), "{t} s");
    }

    #[test]
    fn distances_to_a_polyline() {
        let path = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]];
        assert_eq!(distance_to_path([0.5, 0.3], &path), 0.3);
        assert_eq!(distance_to_path([2.0, 0.5], &path), 1.0);
        assert!((distance_to_path([-1.0, -1.0], &path) - 2f64.sqrt()).abs() < 1e-15);
    }

    #[test]
    fn bad_windows_are_errors() {
        assert!(predict(&[[0.0; 3]], 0.01, [1.0, 0.0, 0.0]).is_err());
        assert!(predict(&[[0.0; 3], [f64::NAN, 0.0, 0.0]], 0.01, [1.0, 0.0, 0.0]).is_err());
        assert!(predict(&[[0.0; 3], [0.1, 0.0, 0.0]], 0.0, [1.0, 0.0, 0.0]).is_err());
    }
}
