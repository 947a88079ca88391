//! The velocity walk planned as it is sampled ([`LiveWalk`]) against the one precomputed for
//! the whole run ([`WalkMotion::velocity`]): driven by the same schedule they give the same
//! targets at every tick (the online one runs the MPC the release time ahead with a ring of
//! samples), and sampling it allocates nothing.

use corps_model::spatial::Se3;
use corps_scenario::targets::Targets;
use corps_scenario::velocity_walk::{LiveVelocity, LiveWalk};
use corps_scenario::walk::{VelocitySection, WalkMotion};
use corps_walk::mpc::VelocityCommand;
use nalgebra::{Matrix3, Vector3};

#[global_allocator]
static GLOBAL: corps_testkit::CountingAllocator = corps_testkit::CountingAllocator;

const DT: f64 = 1e-3;

fn feet0() -> [Se3; 2] {
    let at = |y: f64| Se3::new(Matrix3::identity(), Vector3::new(0.02, y, 0.1));
    [at(0.085), at(-0.085)]
}

/// Forward, a quick turn to the side (within a step), backward with a turn, then stop.
fn schedule() -> VelocitySection {
    toml::from_str(
        "commands = [
            { t = 0.0, vx = 0.1 },
            { t = 3.3, vx = 0.0, vy = 0.15 },
            { t = 6.05, vx = -0.1, yaw_rate = 0.05 },
            { t = 9.0, vx = 0.0 },
        ]",
    )
    .unwrap()
}

#[test]
fn live_walk_on_a_schedule_equals_the_precomputed_walk() {
    let talos = corps_robot::Robot::built_in("talos").unwrap().unwrap();
    let v = schedule();
    let duration = 12.0;
    let com_height = 0.87;
    let planned = WalkMotion::velocity(&talos, &v, &feet0(), com_height, DT, duration).unwrap();
    let mut live =
        LiveWalk::new(&talos, Box::new(v.clone()), None, &feet0(), com_height, DT).unwrap();
    let com0 = Vector3::new(0.02, 0.0, 0.97);
    let (mut a, mut b) = (
        Targets::at_rest(&com0, &feet0()),
        Targets::at_rest(&com0, &feet0()),
    );
    // The precomputed walk clamps its look-ahead at the end: compare up to one release
    // (0.2 s) before it.
    let ticks = ((duration - 0.2) / DT) as usize;
    let mut lift_offs = 0;
    for k in 0..ticks {
        let t = k as f64 * DT;
        planned.sample(t, &mut a);
        live.sample(t, &mut b);
        assert_eq!(a, b, "t = {t:.3} s");
        lift_offs += usize::from(b.feet.iter().any(|f| !f.supporting));
    }
    assert!(
        lift_offs > 4000,
        "the walk steps ({lift_offs} ticks on one foot)"
    );
    assert_eq!(live.failures().0, 0);
}

#[test]
fn a_live_command_steers_the_walk_without_allocating() {
    let talos = corps_robot::Robot::built_in("talos").unwrap().unwrap();
    let input = LiveVelocity::new();
    let mut live =
        LiveWalk::new(&talos, Box::new(input.clone()), None, &feet0(), 0.87, DT).unwrap();
    let mut out = Targets::at_rest(&Vector3::new(0.02, 0.0, 0.97), &feet0());
    live.sample(0.0, &mut out);
    input.set(VelocityCommand::new(0.2, 0.0, 0.0));
    let ticks = (8.0 / DT) as usize;
    let allocations = corps_testkit::allocations_during(|| {
        for k in 1..ticks {
            live.sample(k as f64 * DT, &mut out);
        }
    });
    assert_eq!(allocations, 0);
    // 8 s at 0.2 m/s, after the 1.2 s start: both feet well ahead of where they started.
    for (f, f0) in out.feet.iter().zip(feet0()) {
        let dx = f.reference.placement.translation.x - f0.translation.x;
        assert!(dx > 0.6, "foot moved {dx:.3} m");
    }
}
