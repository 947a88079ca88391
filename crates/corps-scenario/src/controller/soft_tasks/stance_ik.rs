//! A state's leg set-point by inverse kinematics of its Cartesian set-points: the base and
//! the legs' joints that put the stance sole where it stands, the swing sole at its
//! set-point, the CoM at its set-point and the orientation frame at its initial rotation, the
//! other joints held at the state's postural set-point. Seed 001's Table A.7 gives these leg
//! angles for the thesis's robot (straight, parallel legs at the start); computed here, they
//! agree with the Cartesian tasks of the robot that runs, so the posture does not pull
//! against them and FSM #1's leg-error conditions (e_leg) can be met.
//!
//! Gauss–Newton on the 18 × 18 system (6 + 6 + 3 + 3 rows; the base's 6 and the legs' 12
//! velocities), damped least squares with steps of at most 0.1, until the error is below
//! 1e-10. Where no configuration meets every set-point (a stance too wide to carry the CoM
//! over one sole at its height), the best of the iterations is the set-point if its error
//! is below [`COMPROMISE`].

use crate::error::{bail, Result};
use corps_model::spatial::rotation::log3;
use corps_model::spatial::Se3;
use corps_model::{
    compute_frame_jacobian, integrate, jacobian_center_of_mass, Data, JointKind, Model,
    ReferenceFrame,
};
use nalgebra::{DMatrix, DVector, Matrix6xX, Vector3};

/// What the legs must realise.
pub struct StanceGoal {
    /// The stance and swing soles' frames and placements.
    pub stance: (usize, Se3),
    pub swing: (usize, Se3),
    pub com: Vector3<f64>,
    /// The orientation frame and its rotation.
    pub orientation: (usize, nalgebra::Matrix3<f64>),
}

/// The joints on the chain from the floating base to frame `frame` (indices in the model's
/// joints, the free-flyer left out), frame first.
pub fn chain_to(model: &Model, frame: usize) -> Vec<usize> {
    let mut out = Vec::new();
    let mut joint = model.frames[frame].parent_joint;
    while let Some(j) = joint {
        if model.joints[j].kind != JointKind::FreeFlyer {
            out.push(j);
        }
        joint = model.joints[j].parent;
    }
    out
}

/// Solves for the base and the velocity indices `free` (the legs' joints) from `q` (the other
/// joints keep their values); returns the configuration.
pub fn solve(
    model: &Model,
    q: &DVector<f64>,
    free: &[usize],
    goal: &StanceGoal,
) -> Result<DVector<f64>> {
    let mut data = Data::new(model);
    let mut q = q.clone();
    let mut jac = Matrix6xX::zeros(model.nv);
    let cols: Vec<usize> = (0..6).chain(free.iter().copied()).collect();
    let rows = 18;
    let mut a = DMatrix::zeros(rows, cols.len());
    let mut e = DVector::zeros(rows);
    let mut best = (f64::INFINITY, q.clone());
    for _ in 0..ITERATIONS {
        let mut r = 0;
        for (frame, target) in [goal.stance, goal.swing] {
            let at = placed_jacobian(model, &mut data, &q, frame, &mut jac)?;
            let dp = target.translation - at.translation;
            let dr = log3(&(target.rotation * at.rotation.transpose()));
            for k in 0..3 {
                e[r + k] = dp[k];
                e[r + 3 + k] = dr[k];
            }
            for (c, &col) in cols.iter().enumerate() {
                for k in 0..6 {
                    a[(r + k, c)] = jac[(k, col)];
                }
            }
            r += 6;
        }
        let (frame, rotation) = goal.orientation;
        let at = placed_jacobian(model, &mut data, &q, frame, &mut jac)?;
        let dr = log3(&(rotation * at.rotation.transpose()));
        for k in 0..3 {
            e[r + k] = dr[k];
            for (c, &col) in cols.iter().enumerate() {
                a[(r + k, c)] = jac[(3 + k, col)];
            }
        }
        r += 3;
        jacobian_center_of_mass(model, &mut data, q.as_slice())?;
        let dc = goal.com - data.com;
        for k in 0..3 {
            e[r + k] = dc[k];
            for (c, &col) in cols.iter().enumerate() {
                a[(r + k, c)] = data.jcom[(k, col)];
            }
        }
        if e.norm() < 1e-10 {
            return Ok(q);
        }
        if e.norm() < best.0 {
            best = (e.norm(), q.clone());
        }
        // Damped least squares: (AᵀA + λI) dx = Aᵀe.
        let lambda = 1e-8;
        let normal = a.transpose() * &a + DMatrix::identity(cols.len(), cols.len()) * lambda;
        let Some(dx) = normal.cholesky().map(|c| c.solve(&(a.transpose() * &e))) else {
            bail!("stance inverse kinematics: singular system");
        };
        // Steps of at most 0.1 (rad or m) keep the linearisation honest.
        let scale = (0.1 / dx.amax()).min(1.0);
        let mut v = DVector::zeros(model.nv);
        for (c, &col) in cols.iter().enumerate() {
            v[col] = scale * dx[c];
        }
        q = integrate(model, q.as_slice(), v.as_slice())?;
    }
    if best.0 < COMPROMISE {
        return Ok(best.1);
    }
    bail!(
        "stance inverse kinematics: no configuration puts the soles, the CoM and the orientation within {COMPROMISE} of their set-points (error {:.2e} after {ITERATIONS} iterations)",
        best.0
    )
}

const ITERATIONS: usize = 200;

/// Frame `frame`'s Jacobian at `q` (origin at the frame, world axes) into `jac`, and its
/// placement.
fn placed_jacobian(
    model: &Model,
    data: &mut Data,
    q: &DVector<f64>,
    frame: usize,
    jac: &mut Matrix6xX<f64>,
) -> Result<Se3> {
    let rf = ReferenceFrame::LocalWorldAligned;
    compute_frame_jacobian(model, data, q.as_slice(), frame, rf, jac)?;
    Ok(corps_model::frame_placement(model, data, frame)?)
}

/// The largest error (m and rad, stacked) of a least-squares compromise accepted where no
/// configuration meets every set-point.
const COMPROMISE: f64 = 0.05;

#[cfg(test)]
mod tests {
    use super::*;
    use corps_model::{forward_kinematics_placements, frame_placement};

    /// iCub with its legs parallel: the CoM 4 cm towards the left sole and the right sole
    /// 3 cm up, the base keeping its rotation; the solution puts every frame and the CoM on its
    /// goal (forward kinematics, an independent check of the iterations), and moves only the
    /// base and the legs.
    #[test]
    fn the_solution_meets_every_set_point_and_moves_only_the_legs() {
        let robot = corps_robot::Robot::built_in("icub_parallel_legs")
            .unwrap()
            .unwrap();
        let model = &robot.model;
        let q0 = robot.posture.clone();
        let mut data = Data::new(model);
        forward_kinematics_placements(model, &mut data, q0.as_slice()).unwrap();
        let (left, right, root) = (robot.feet[0].frame, robot.feet[1].frame, robot.base);
        let at = |d: &Data, f| frame_placement(model, d, f).unwrap();
        let (com0, _) = corps_model::com_at_placements(model, &data);
        let mut raised = at(&data, right);
        raised.translation.z += 0.03;
        let goal = StanceGoal {
            stance: (left, at(&data, left)),
            swing: (right, raised),
            com: com0 + Vector3::new(0.0, 0.04, 0.0),
            orientation: (root, at(&data, root).rotation),
        };
        let legs: Vec<usize> = [left, right]
            .iter()
            .flat_map(|f| chain_to(model, *f))
            .map(|j| model.joints[j].idx_v)
            .collect();
        assert_eq!(legs.len(), 12);
        let q = solve(model, &q0, &legs, &goal).unwrap();
        forward_kinematics_placements(model, &mut data, q.as_slice()).unwrap();
        let (com, _) = corps_model::com_at_placements(model, &data);
        assert!((com - goal.com).norm() < 1e-9, "{com:?}");
        for (f, target) in [goal.stance, goal.swing] {
            let p = at(&data, f);
            assert!((p.translation - target.translation).norm() < 1e-9);
            assert!(log3(&(target.rotation * p.rotation.transpose())).norm() < 1e-9);
        }
        assert!(log3(&(goal.orientation.1 * at(&data, root).rotation.transpose())).norm() < 1e-9);
        for j in (model.joints.iter()).filter(|j| j.kind != corps_model::JointKind::FreeFlyer) {
            if !legs.contains(&j.idx_v) {
                assert_eq!(q[j.idx_q], q0[j.idx_q], "{} moved", j.name);
            }
        }
    }
}
