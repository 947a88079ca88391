//! Closed-loop preview-control walks on the LIPM (robot-free, as in CCC's
//! TestPreviewControlZmp; anchors §4.3 "Robot-free closed-loop tests").

mod common {
    pub mod talos;
}

use corps_walk::preview_walk::PreviewWalk;
use corps_walk::{ContactPhase, Foot, FootstepPlan, StepTiming};

/// Walks `plan` to the end plus 3 s; returns (max |ZMP − ZMP_ref|, max signed distance of the
/// ZMP to the support polygon, final CoM error to the middle of the feet, final CoM speed).
fn walk(plan: FootstepPlan) -> (f64, f64, f64, f64) {
    let params = common::talos::talos_preview();
    let mut g = PreviewWalk::new(plan.clone(), params).unwrap();
    let sole = common::talos::TALOS_SOLE;
    let (mut max_err, mut max_out) = (0.0f64, f64::NEG_INFINITY);
    let mut last = None;
    while g.plan_time(g.time()) < plan.duration() + 3.0 {
        let r = g.step().unwrap();
        let s = plan.sample(g.plan_time(r.time));
        max_err = max_err.max((r.zmp.xy() - s.zmp.xy()).norm());
        let poly = match r.phase {
            ContactPhase::Double => sole.double_support(&r.left_foot, &r.right_foot),
            ContactPhase::LeftSupport => sole.sole_polygon(&r.left_foot),
            ContactPhase::RightSupport => sole.sole_polygon(&r.right_foot),
        };
        max_out = max_out.max(poly.signed_distance(&r.zmp.xy()));
        // waist yaw is recomputed from the feet every tick (seed 002 §4.13)
        assert_eq!(
            r.waist_yaw,
            corps_walk::waist_yaw(r.left_foot.yaw, r.right_foot.yaw)
        );
        last = Some(r);
    }
    let r = last.unwrap();
    let (l, rf) = plan.final_feet();
    let mid = nalgebra::Vector2::new(0.5 * (l.x + rf.x), 0.5 * (l.y + rf.y));
    let com_err = (r.com.xy() - mid).norm();
    let speed = r.com_vel.xy().norm();
    (max_err, max_out, com_err, speed)
}

/// Seed 000 S5: six 20 cm steps plus a closing step, SS 0.9 s / DS 0.115 s, TALOS CoM height
/// and feet 0.162 m apart (seed 002 `:setDSFeetDistance`). Pass: ZMP tracking error < 0.1 m
/// (anchors §4.3 / CCC) and, stricter and physical, the ZMP never leaves the support polygon
/// of the TALOS sole; at the end CoM within 1 cm of the middle of the feet, speed < 1 cm/s
/// (CCC's convergence bounds).
#[test]
fn preview_control_walks_seed000_20cm_plan() {
    let plan =
        FootstepPlan::straight(6, 0.2, 0.162, Foot::Left, StepTiming::seed000_nominal()).unwrap();
    let (err, out, com, speed) = walk(plan);
    eprintln!("20 cm / 0.9–0.115: max ZMP error {err:.4} m, max signed distance {out:.4} m, final CoM error {com:.2e} m, speed {speed:.2e} m/s");
    assert!(err < 0.1);
    assert!(out <= 0.0);
    assert!(com < 1e-2 && speed < 1e-2);
}

/// Same with the faster seed 000 timing (SS 0.711 / DS 0.089) and the 60 cm steps (S6, S7).
#[test]
fn preview_control_walks_fast_and_long_plans() {
    for (len, timing) in [
        (0.2, StepTiming::seed000_fast()),
        (0.6, StepTiming::seed000_nominal()),
    ] {
        let plan = FootstepPlan::straight(6, len, 0.162, Foot::Right, timing).unwrap();
        let (err, out, com, speed) = walk(plan);
        eprintln!("{len} m steps, SS {}: max ZMP error {err:.4} m, max signed distance {out:.4} m, final CoM error {com:.2e}, speed {speed:.2e}", timing.single_support);
        assert!(err < 0.1);
        assert!(out <= 0.0);
        assert!(com < 1e-2 && speed < 1e-2);
    }
}

/// Stairs (seed 000 S9: 6 × 10 cm rise, 30 cm tread): the CoM height follows the support.
#[test]
fn preview_control_climbs_stairs() {
    let plan = FootstepPlan::stairs(
        6,
        0.1,
        0.3,
        0.162,
        Foot::Left,
        StepTiming::seed000_nominal(),
    )
    .unwrap();
    let mut g = PreviewWalk::new(plan.clone(), common::talos::talos_preview()).unwrap();
    let mut r = g.step().unwrap();
    while g.plan_time(g.time()) < plan.duration() + 3.0 {
        r = g.step().unwrap();
    }
    assert!((r.com.z - (0.6 + common::talos::talos_preview().lipm.com_height)).abs() < 1e-12);
    let (err, out, _, _) = walk(plan);
    assert!(err < 0.1 && out <= 0.0);
}

/// The generator slides its preview window by one sample per tick; preview control on a
/// window sampled afresh from the plan every tick must give the same CoM (to rounding: the
/// sample times are summed in a different order).
#[test]
fn sliding_preview_window_matches_a_fresh_window_every_tick() {
    use corps_walk::preview_control::{PreviewAxis, PreviewController};
    let plan =
        FootstepPlan::straight(6, 0.2, 0.162, Foot::Right, StepTiming::seed000_nominal()).unwrap();
    let params = common::talos::talos_preview();
    let mut g = PreviewWalk::new(plan.clone(), params).unwrap();
    let ctrl = PreviewController::with_integral(&params).unwrap();
    let start = plan.sample(0.0).zmp;
    let (mut x, mut y) = (PreviewAxis::at_rest(start.x), PreviewAxis::at_rest(start.y));
    let n = ctrl.horizon() + 1;
    let (mut wx, mut wy) = (vec![0.0; n], vec![0.0; n]);
    let mut worst = 0.0f64;
    while g.plan_time(g.time()) < plan.duration() + 1.0 {
        let tp = g.plan_time(g.time());
        for j in 0..n {
            let z = plan.sample(tp + j as f64 * params.period).zmp;
            (wx[j], wy[j]) = (z.x, z.y);
        }
        let r = g.step().unwrap();
        worst = worst.max((r.com.x - x.x[0]).abs().max((r.com.y - y.x[0]).abs()));
        ctrl.step(&mut x, &wx).unwrap();
        ctrl.step(&mut y, &wy).unwrap();
    }
    assert!(worst < 1e-9, "CoM differs by {worst} m");
}

/// A robot that stands with its CoM 27 mm ahead of the middle of its feet (TALOS' settled
/// half-sitting): the reference starts there, its ZMP changes during the standing window by
/// less per tick than the walk's own steps change it, and the walk then tracks the plan.
#[test]
fn a_walk_starting_off_centre_starts_where_the_robot_stands() {
    let plan =
        FootstepPlan::straight(6, 0.2, 0.162, Foot::Right, StepTiming::seed000_nominal()).unwrap();
    let mut g = PreviewWalk::new(plan.clone(), common::talos::talos_preview())
        .unwrap()
        .starting_at(0.027, -0.004);
    let first = g.step().unwrap();
    let start = nalgebra::Vector2::new(0.027, -0.004);
    assert!((first.com.xy() - start).norm() < 1e-12);
    assert!((first.zmp.xy() - start).norm() < 1e-12);
    let mut prev = first.zmp.xy();
    let (mut standing_jump, mut walking_jump, mut off_plan) = (0.0f64, 0.0f64, 0.0f64);
    while g.plan_time(g.time()) < plan.duration() {
        let r = g.step().unwrap();
        let jump = (r.zmp.xy() - prev).norm();
        let tp = g.plan_time(r.time);
        if tp < 0.0 {
            standing_jump = standing_jump.max(jump);
        } else {
            walking_jump = walking_jump.max(jump);
            off_plan = off_plan.max((r.zmp.xy() - plan.sample(tp).zmp.xy()).norm());
        }
        prev = r.zmp.xy();
    }
    assert!(
        standing_jump < walking_jump,
        "ZMP reference moved {standing_jump} m in one tick while standing, {walking_jump} m walking"
    );
    assert!(off_plan < 0.1, "ZMP off the plan by {off_plan} m");
}
