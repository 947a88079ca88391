//! Adding and removing a contact ramps its normal-force bound, so the force never jumps and the
//! QP stays feasible through the switch (a re-added contact's minimum force is held at 0 until
//! its ramp ends: a minimum above the ramping maximum would make the QP infeasible).

mod common;
use common::*;

#[test]
fn a_removed_then_re_added_contact_ramps_its_force_and_stays_feasible() {
    let (model, _, state, mut id) = standing();
    let right = "leg_right_sole_fix_joint";
    let template = id.contacts[id.contact_index(right).unwrap()].clone();
    assert_eq!(template.fmin, 1.0);

    id.update_transitions(0.0);
    id.compute(&model, &state).unwrap();
    let f0 = id.normal_force(id.contact_index(right).unwrap());
    id.remove_contact(right, 0.0, 0.1).unwrap();
    let mut previous = f0;
    for k in 1..=10 {
        let t = 0.01 * k as f64;
        id.update_transitions(t);
        if let Ok(i) = id.contact_index(right) {
            id.compute(&model, &state).unwrap();
            let f = id.normal_force(i);
            assert!(
                f <= f0 * (1.0 - t / 0.1) + 1e-6,
                "t = {t}: {f} N above the ramp"
            );
            assert!(f <= previous + 1e-6, "t = {t}: the force rose");
            previous = f;
        }
    }
    assert!(
        id.contact_index(right).is_err(),
        "the contact is gone after its ramp"
    );

    id.add_contact(template, 0.2, 0.1);
    for k in 0..=12 {
        let t = 0.2 + 0.01 * k as f64;
        id.update_transitions(t);
        let out = id.compute(&model, &state);
        assert!(out.is_ok(), "t = {t:.2}: {:?}", out.err());
        let i = id.contact_index(right).unwrap();
        let ramp = 1000.0 * ((t - 0.2) / 0.1).min(1.0);
        assert!(
            id.normal_force(i) <= ramp + 1e-6,
            "t = {t:.2}: above the ramp"
        );
    }
    let i = id.contact_index(right).unwrap();
    assert_eq!((id.contacts[i].fmin, id.contacts[i].fmax), (1.0, 1000.0));
}
