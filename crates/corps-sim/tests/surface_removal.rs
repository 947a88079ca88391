//! A terrain surface taken out of the world at a given time: a box resting on a table stays
//! put until the table is removed, then falls freely (z drops by ½ g t² to within the
//! integrator's first-order error) onto the ground below; removing a surface that does not
//! exist, or twice, is an error.

mod common;

use corps_model::spatial::Se3;
use corps_sim::*;
use nalgebra::{Matrix3, Vector3};

fn world() -> Terrain {
    let mut t = Terrain::preset(TerrainPreset::Flat, 0.8);
    // A table whose top is at z = 0.5 m.
    t.surfaces.push(Surface::Box {
        pose: Se3::new(Matrix3::identity(), Vector3::new(0.0, 0.0, 0.25)),
        half_extents: Vector3::new(0.5, 0.5, 0.25),
        mu: 0.8,
    });
    t
}

#[test]
fn a_box_on_a_table_falls_when_the_table_is_removed() {
    let model = common::box_body(2.0, [0.1, 0.1, 0.1]);
    let mut q0 = corps_model::neutral(&model);
    q0[2] = 0.55;
    let settings = SimSettings {
        integrator: Integrator::ImplicitEuler,
        ..Default::default()
    };
    for integrator in [Integrator::ImplicitEuler, Integrator::Rk4] {
        let settings = SimSettings {
            integrator,
            ..settings.clone()
        };
        let gains = common::no_gains(&model);
        let mut sim =
            Simulator::new(model.clone(), world(), settings, q0.as_slice(), gains).unwrap();
        let removal = 0.3;
        sim.remove_surface_at(1, removal).unwrap();
        let cmd = common::zero_torque(&model);
        while sim.time() < removal - 1e-9 {
            sim.prepare_step();
            sim.step(&cmd).unwrap();
        }
        let z_on_table = sim.q()[2];
        assert!(
            (z_on_table - 0.55).abs() < 2e-3,
            "{integrator:?}: resting on the table at {z_on_table} m"
        );
        assert_eq!(
            sim.terrain().surfaces.len(),
            2,
            "not removed before its time"
        );
        let fall = 0.2;
        while sim.time() < removal + fall - 1e-9 {
            sim.step(&cmd).unwrap();
        }
        assert_eq!(sim.terrain().surfaces.len(), 1);
        let drop = z_on_table - sim.q()[2];
        let free_fall = 0.5 * 9.81 * fall * fall;
        assert!(
            (drop - free_fall).abs() < 0.02 * free_fall,
            "{integrator:?}: dropped {drop} m in {fall} s, free fall {free_fall} m"
        );
        // It lands on the ground.
        while sim.time() < removal + 1.5 {
            sim.step(&cmd).unwrap();
        }
        assert!(
            (sim.q()[2] - 0.05).abs() < 2e-3,
            "{integrator:?}: {}",
            sim.q()[2]
        );
    }
}

#[test]
fn removing_a_missing_surface_or_one_twice_is_an_error() {
    let model = common::box_body(1.0, [0.1, 0.1, 0.1]);
    let mut q0 = corps_model::neutral(&model);
    q0[2] = 0.55;
    let gains = common::no_gains(&model);
    let mut sim =
        Simulator::new(model, world(), SimSettings::default(), q0.as_slice(), gains).unwrap();
    assert!(sim.remove_surface_at(2, 1.0).is_err());
    assert!(sim.remove_surface_at(1, f64::NAN).is_err());
    sim.remove_surface_at(1, 1.0).unwrap();
    let e = sim.remove_surface_at(1, 2.0).unwrap_err().to_string();
    assert!(e.contains("already"), "{e}");
}
