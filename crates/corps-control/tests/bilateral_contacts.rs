//! A bilateral contact (no friction pyramids) lets the model's ZMP leave the soles: a CoM
//! acceleration whose LIPM ZMP lies outside the feet is made by the contact wrench, where the
//! unilateral contacts cap the ZMP at the sole edge (the QP then makes up the rest with angular
//! momentum, as TSID in position mode did with its pelvis).

mod common;
use common::*;
use corps_control::tasks::ComTask;

/// ZMP (y) of the QP's contact forces with the CoM reference accelerating by `acc_y` sideways,
/// and the LIPM ZMP `c − c̈/ω²` that acceleration asks for.
fn zmp_y(bilateral: bool, acc_y: f64) -> (f64, f64) {
    let (model, _, state, mut id) = standing();
    for c in &mut id.contacts {
        c.bilateral = bilateral;
    }
    let com = id.tasks.task_mut::<ComTask>("com").unwrap();
    com.reference.acc[1] = acc_y;
    let soles: Vec<_> = id
        .contacts
        .iter()
        .map(|c| {
            (
                state.frame_placement(&model, c.frame).unwrap(),
                c.points().to_vec(),
            )
        })
        .collect();
    let out = id.compute(&model, &state).unwrap();
    let (mut fz, mut moment) = (0.0, 0.0);
    let mut k = 0;
    for (placement, points) in &soles {
        for p in points {
            let world = placement.translation + placement.rotation * p;
            let f = placement.rotation * out.forces.fixed_rows::<3>(3 * k).into_owned();
            fz += f.z;
            moment += world.y * f.z;
            k += 1;
        }
    }
    let c = state.data.com;
    let ground = soles[0].0.translation.z;
    let omega2 = 9.81 / (c.z - ground);
    (moment / fz, c.y - acc_y / omega2)
}

#[test]
fn bilateral_contacts_let_the_zmp_leave_the_soles() {
    // 2 m/s² sideways: the LIPM ZMP is ≈ 0.18 m from the CoM, past the soles' outer edges
    // (±0.085 ± 0.065 m); friction (μ 0.3) still holds the 180 N.
    let (unilateral, lipm) = zmp_y(false, 2.0);
    assert!(lipm < -0.16, "LIPM ZMP {lipm}");
    assert!(
        unilateral > -0.151,
        "unilateral contacts: ZMP {unilateral} off the soles"
    );
    let (bilateral, _) = zmp_y(true, 2.0);
    assert!(
        (bilateral - lipm).abs() < 0.02,
        "bilateral contacts: ZMP {bilateral} m, LIPM {lipm} m"
    );
}
