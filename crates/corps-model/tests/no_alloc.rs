//! Real-time discipline: once `Data` exists, no algorithm allocates on the heap. A counting
//! global allocator (per thread, so parallel tests do not interfere) proves it.

mod common;
use common::*;
use corps_model::*;
use corps_testkit::{allocations_during, CountingAllocator};
use nalgebra::{DVector, Matrix6xX};

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

#[test]
fn no_algorithm_allocates_once_data_exists() {
    for (name, model) in robots() {
        let mut data = Data::new(&model);
        let (q, v, a, tau) = random_state(&model, 1);
        let (q, v, a, tau) = (q.as_slice(), v.as_slice(), a.as_slice(), tau.as_slice());
        let mut jac = Matrix6xX::zeros(model.nv);
        let mut q_next = DVector::zeros(model.nq);
        let mut dq = DVector::zeros(model.nv);
        let fid = model.frames.len() - 1;
        let n = allocations_during(|| {
            for _ in 0..3 {
                rnea(&model, &mut data, q, v, a).unwrap();
                nonlinear_effects(&model, &mut data, q, v).unwrap();
                generalized_gravity(&model, &mut data, q).unwrap();
                crba(&model, &mut data, q).unwrap();
                aba(&model, &mut data, q, v, tau).unwrap();
                compute_minverse(&model, &mut data, q).unwrap();
                forward_dynamics_crba(&model, &mut data, q, v, tau).unwrap();
                forward_kinematics(&model, &mut data, q, v, a).unwrap();
                update_frame_placements(&model, &mut data);
                frame_velocity(&model, &data, fid, ReferenceFrame::Local).unwrap();
                frame_classical_acceleration(&model, &data, fid, ReferenceFrame::LocalWorldAligned)
                    .unwrap();
                compute_joint_jacobians(&model, &mut data, q).unwrap();
                frame_jacobian(
                    &model,
                    &data,
                    fid,
                    ReferenceFrame::LocalWorldAligned,
                    &mut jac,
                )
                .unwrap();
                center_of_mass(&model, &mut data, q, v, a).unwrap();
                jacobian_center_of_mass(&model, &mut data, q).unwrap();
                compute_centroidal_momentum(&model, &mut data, q, v).unwrap();
                centroidal_momentum_drift(&model, &mut data, q, v).unwrap();
                coriolis_matrix(&model, &mut data, q, v).unwrap();
                kinetic_energy(&model, &mut data, q, v).unwrap();
                potential_energy(&model, &mut data, q).unwrap();
                compute_all_terms(&model, &mut data, q, v).unwrap();
                integrate_to(&model, q, v, q_next.as_mut_slice()).unwrap();
                difference_to(&model, q, q_next.as_slice(), dq.as_mut_slice()).unwrap();
            }
        });
        assert_eq!(n, 0, "{name}: {n} heap allocations in the algorithms");
        // The operational-space inertia is checked on a frame with six independent directions.
        if model.has_free_flyer() {
            let n = allocations_during(|| {
                frame_operational_space_inertia(&model, &mut data, q, fid, ReferenceFrame::Local)
                    .unwrap();
            });
            assert_eq!(
                n, 0,
                "{name}: operational-space inertia allocated {n} times"
            );
        }
    }
}

#[test]
fn the_counter_sees_allocations() {
    let n = allocations_during(|| {
        let v = vec![1.0f64; 100];
        std::hint::black_box(v);
    });
    assert!(n >= 1);
}
