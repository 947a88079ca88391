//! What a controller sends a plant for one control period.

use nalgebra::DVector;

/// A command for one control period, over the actuated joints (every dof but the free-flyer's).
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// Joint torques (size na).
    Torque(DVector<f64>),
    /// Joint position targets as a full configuration (size nq; the base part is ignored) and
    /// joint velocity targets (size na).
    Position {
        q_ref: DVector<f64>,
        v_ref: DVector<f64>,
    },
    /// Joint velocity targets (size na).
    Velocity(DVector<f64>),
}

impl Command {
    /// Copies `other` into `self`: in place, without allocating, when both are the same kind
    /// of command with the same sizes (a control loop's case), else by a clone.
    pub fn copy_from(&mut self, other: &Command) {
        match (&mut *self, other) {
            (Command::Torque(a), Command::Torque(b))
            | (Command::Velocity(a), Command::Velocity(b))
                if a.len() == b.len() =>
            {
                a.copy_from(b)
            }
            (
                Command::Position {
                    q_ref: qa,
                    v_ref: va,
                },
                Command::Position {
                    q_ref: qb,
                    v_ref: vb,
                },
            ) if qa.len() == qb.len() && va.len() == vb.len() => {
                qa.copy_from(qb);
                va.copy_from(vb);
            }
            _ => *self = other.clone(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_command_of_the_same_kind_and_sizes_is_copied_in_place_and_any_other_cloned() {
        let mut a = Command::Torque(DVector::zeros(3));
        let buffer = |c: &Command| match c {
            Command::Torque(t) => t.as_ptr(),
            _ => std::ptr::null(),
        };
        let before = buffer(&a);
        let b = Command::Torque(DVector::from_element(3, 2.0));
        a.copy_from(&b);
        assert_eq!(a, b);
        assert_eq!(buffer(&a), before, "the same buffer");
        for other in [
            Command::Torque(DVector::from_element(2, 1.0)),
            Command::Velocity(DVector::from_element(2, 1.0)),
            Command::Position {
                q_ref: DVector::from_element(4, 0.5),
                v_ref: DVector::zeros(2),
            },
        ] {
            a.copy_from(&other);
            assert_eq!(a, other);
        }
    }
}
