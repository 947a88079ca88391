//! The current-limiting iLQR (seed 000 §3.13): its derivatives against finite differences,
//! its backward pass's value gradient against the optimal cost's finite difference, its
//! optimum against corps-ocp's generic DDP and against Crocoddyl's SolverDDP
//! (tools/golden/elbow_ilqr_crocoddyl.py), and an infeasible start.

mod common;

use corps_actuator::current_ocp::CurrentLimitingOcp;
use corps_actuator::elbow::Payload;
use corps_actuator::ilqr::{Ilqr, IlqrSettings};
use corps_ocp::{ActionDerivatives, ActionModel, Ddp, DdpSettings, TerminalCost};
use nalgebra::{Matrix2, Vector1, Vector2};

fn ocp(payload_kg: f64, barrier: bool) -> CurrentLimitingOcp {
    let d = common::elbow();
    CurrentLimitingOcp::new(
        d.model,
        Payload::point_mass(payload_kg, 0.05),
        &d.limits,
        0.001,
        barrier,
    )
}

#[test]
fn the_node_derivatives_match_finite_differences() {
    let p = ocp(30.0, true);
    let xr = Vector2::new(-2.0, -1.0);
    for (x, u) in [
        (Vector2::new(-1.0, -1.5), -3.0),
        (Vector2::new(-2.3, 0.3), -5.5),
        (Vector2::new(-0.1, 4.3), 5.8),
    ] {
        let d = p.running_diff(&x, u, &xr);
        let h = 1e-6;
        for j in 0..2 {
            let mut xp = x;
            let mut xm = x;
            xp[j] += h;
            xm[j] -= h;
            let (cp, np) = p.running(&xp, u, &xr);
            let (cm, nm) = p.running(&xm, u, &xr);
            let fx = (np - nm) / (2.0 * h);
            for i in 0..2 {
                assert!(
                    (fx[i] - d.fx[(i, j)]).abs() < 1e-6 * (1.0 + fx[i].abs()),
                    "fx {i}{j}"
                );
            }
            let lx = (cp - cm) / (2.0 * h);
            assert!(
                (lx - d.lx[j]).abs() < 1e-5 * (1.0 + lx.abs()),
                "lx {j}: {lx} vs {}",
                d.lx[j]
            );
            let gp = p.running_diff(&xp, u, &xr).lx;
            let gm = p.running_diff(&xm, u, &xr).lx;
            let lxx = (gp[j] - gm[j]) / (2.0 * h);
            assert!(
                (lxx - d.lxx[(j, j)]).abs() < 1e-4 * (1.0 + lxx.abs()),
                "lxx {j}"
            );
        }
        let (cp, np) = p.running(&x, u + h, &xr);
        let (cm, nm) = p.running(&x, u - h, &xr);
        let fu = (np - nm) / (2.0 * h);
        assert!((fu - d.fu).norm() < 1e-6 * (1.0 + fu.norm()), "fu");
        let lu = (cp - cm) / (2.0 * h);
        assert!(
            (lu - d.lu).abs() < 1e-5 * (1.0 + lu.abs()),
            "lu {lu} vs {}",
            d.lu
        );
        let lup = p.running_diff(&x, u + h, &xr).lu;
        let lum = p.running_diff(&x, u - h, &xr).lu;
        assert!(
            ((lup - lum) / (2.0 * h) - d.luu).abs() < 1e-4 * (1.0 + d.luu.abs()),
            "luu"
        );
    }
}

fn reference(target: [f64; 2], n: usize) -> Vec<Vector2<f64>> {
    vec![Vector2::new(target[0], target[1]); n + 1]
}

fn solve(p: &CurrentLimitingOcp, x0: Vector2<f64>, target: [f64; 2], u0: f64) -> Ilqr {
    let mut s = Ilqr::new(
        100,
        IlqrSettings {
            max_iterations: 500,
            stop: 1e-18,
            ..IlqrSettings::default()
        },
    );
    s.us_mut().fill(u0);
    s.solve(p, &x0, &reference(target, 100)).unwrap();
    s
}

#[test]
fn the_value_gradient_is_the_optimal_costs_derivative() {
    let p = ocp(30.0, true);
    let target = [-2.0, -4.0];
    let cost = |x0: Vector2<f64>| {
        let mut s = Ilqr::new(
            100,
            IlqrSettings {
                max_iterations: 500,
                stop: 1e-20,
                ..IlqrSettings::default()
            },
        );
        s.us_mut().fill(-2.0);
        let r = s.solve(&p, &x0, &reference(target, 100)).unwrap();
        (r.cost, s)
    };
    let x0 = Vector2::new(-1.0, -1.0);
    let (_, s) = cost(x0);
    // Re-run the backward pass at the optimum: V_x(x0) = ∂J*/∂x0 (envelope theorem).
    let vx = s.value_gradient();
    for j in 0..2 {
        let h = 1e-5;
        let mut xp = x0;
        let mut xm = x0;
        xp[j] += h;
        xm[j] -= h;
        let fd = (cost(xp).0 - cost(xm).0) / (2.0 * h);
        println!(
            "∂J*/∂x0[{j}]: backward pass {:.8}, finite difference {fd:.8}",
            vx[j]
        );
        assert!(
            (fd - vx[j]).abs() < 1e-5 * (1.0 + fd.abs()),
            "{j}: {fd} vs {}",
            vx[j]
        );
    }
}

/// The same problem as a corps-ocp action model, solved by the generic DDP.
struct Generic<'a> {
    p: &'a CurrentLimitingOcp,
    xr: Vector2<f64>,
}

impl ActionModel<2, 1> for Generic<'_> {
    fn calc(&self, x: &Vector2<f64>, u: &Vector1<f64>, next: &mut Vector2<f64>) -> f64 {
        let (c, n) = self.p.running(x, u[0], &self.xr);
        *next = n;
        c
    }
    fn calc_diff(&self, x: &Vector2<f64>, u: &Vector1<f64>, d: &mut ActionDerivatives<2, 1>) {
        let n = self.p.running_diff(x, u[0], &self.xr);
        d.fx = n.fx;
        d.fu = n.fu;
        d.lx = n.lx;
        d.lxx = n.lxx;
        d.lu = Vector1::new(n.lu);
        d.luu = Vector1::new(n.luu);
        d.lxu = Vector2::zeros();
    }
}

impl TerminalCost<2> for Generic<'_> {
    fn cost(&self, x: &Vector2<f64>) -> f64 {
        self.p.terminal(x, &self.xr)
    }
    fn diff(&self, x: &Vector2<f64>, lx: &mut Vector2<f64>, lxx: &mut Matrix2<f64>) {
        let (g, h) = self.p.terminal_diff(x, &self.xr);
        *lx = g;
        *lxx = h;
    }
}

#[test]
fn the_optimum_is_the_generic_ddps() {
    let p = ocp(30.0, true);
    let target = [-2.0, -4.0];
    let x0 = Vector2::new(-1.0, -1.0);
    let ours = solve(&p, x0, target, -2.0);
    let node = Generic {
        p: &p,
        xr: Vector2::new(target[0], target[1]),
    };
    let running: Vec<&dyn ActionModel<2, 1>> = vec![&node; 100];
    let us0 = vec![Vector1::new(-2.0); 100];
    let settings = DdpSettings {
        max_iterations: 500,
        stop: 1e-18,
        ..DdpSettings::default()
    };
    let generic = Ddp::solve(&x0, &running, &node, Some(&us0), &settings).unwrap();
    let worst = (0..100)
        .map(|k| (ours.us()[k] - generic.us[k][0]).abs())
        .fold(0.0, f64::max);
    println!("largest current difference {worst:.2e} A");
    assert!(worst < 1e-8, "{worst}");
}

#[derive(serde::Deserialize)]
struct Golden {
    source: String,
    problems: Vec<Problem>,
}

#[derive(serde::Deserialize)]
struct Problem {
    x0: [f64; 2],
    payload_kg: f64,
    distance_m: f64,
    target: [f64; 2],
    barrier: bool,
    initial_current: f64,
    converged: bool,
    stop: f64,
    cost: f64,
    xs: Vec<[f64; 2]>,
    us: Vec<f64>,
}

#[test]
fn the_optimum_is_crocoddyls() {
    let golden: Golden =
        serde_json::from_str(include_str!("data/elbow_ilqr_crocoddyl.json")).unwrap();
    println!("reference: {}", golden.source);
    let d = common::elbow();
    for g in &golden.problems {
        let p = CurrentLimitingOcp::new(
            d.model,
            Payload::point_mass(g.payload_kg, g.distance_m),
            &d.limits,
            0.001,
            g.barrier,
        );
        let x0 = Vector2::new(g.x0[0], g.x0[1]);
        let ours = solve(&p, x0, g.target, g.initial_current);
        let mut xs = vec![Vector2::zeros(); 101];
        let cost =
            corps_actuator::ilqr::rollout(&p, &x0, &reference(g.target, 100), ours.us(), &mut xs);
        let du = (0..100)
            .map(|k| (ours.us()[k] - g.us[k]).abs())
            .fold(0.0, f64::max);
        let dx = (0..=100)
            .map(|k| (xs[k] - Vector2::new(g.xs[k][0], g.xs[k][1])).abs().max())
            .fold(0.0, f64::max);
        let dc = (cost - g.cost) / g.cost;
        println!(
            "x0 {:?} → {:?}, barrier {}: Crocoddyl cost {:.10} (converged {}, Σ‖Q_u‖² {:.1e}), \
             ours {:.10}; largest differences {du:.1e} A, {dx:.1e} in x",
            g.x0, g.target, g.barrier, g.cost, g.converged, g.stop, cost
        );
        if g.converged {
            assert!(du < 1e-7 && dx < 1e-9 && dc.abs() < 1e-10, "{du} {dx} {dc}");
        } else {
            // Crocoddyl stopped short of stationarity: ours must be at least as good and close.
            assert!(dc < 1e-9, "ours is worse: {dc}");
            assert!(du < 1e-2 && dx < 1e-4, "{du} {dx}");
        }
    }
}

#[test]
fn a_start_beyond_the_position_limit_is_an_error() {
    let p = ocp(0.0, true);
    let mut s = Ilqr::new(10, IlqrSettings::default());
    let e = s
        .solve(&p, &Vector2::new(-2.5, 0.0), &reference([-1.0, 0.0], 10))
        .unwrap_err();
    assert!(e.to_string().contains("infeasible start"), "{e}");
    let e = s
        .solve(
            &p,
            &Vector2::new(f64::NAN, 0.0),
            &reference([-1.0, 0.0], 10),
        )
        .unwrap_err();
    assert!(e.to_string().contains("not finite"), "{e}");
    let e = s
        .solve(&p, &Vector2::new(-1.0, 0.0), &reference([-1.0, 0.0], 3))
        .unwrap_err();
    assert!(e.to_string().contains("reference states"), "{e}");
}
