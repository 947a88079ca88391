//! Which feet of a biped are on the ground.

/// Contact phase of a biped (seed 002 §4.11: `0` = double support, `1` = left-foot support,
/// `−1` = right-foot support, as sot-pattern-generator encodes it). Per-foot arrays index the
/// left foot 0 and the right foot 1.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ContactPhase {
    /// Both feet on the ground.
    #[default]
    Double,
    /// Single support on the left foot (the right foot swings).
    LeftSupport,
    /// Single support on the right foot (the left foot swings).
    RightSupport,
}

impl ContactPhase {
    /// Integer code of seed 002 §4.11: 0, 1, −1.
    pub fn code(self) -> i8 {
        match self {
            ContactPhase::Double => 0,
            ContactPhase::LeftSupport => 1,
            ContactPhase::RightSupport => -1,
        }
    }

    /// From the integer code of seed 002 §4.11.
    pub fn from_code(code: i32) -> Option<Self> {
        match code {
            0 => Some(Self::Double),
            1 => Some(Self::LeftSupport),
            -1 => Some(Self::RightSupport),
            _ => None,
        }
    }

    /// Whether foot `i` (0 = left, 1 = right) is in contact.
    pub fn in_contact(self, i: usize) -> bool {
        match self {
            Self::Double => true,
            Self::LeftSupport => i == 0,
            Self::RightSupport => i == 1,
        }
    }

    /// `true` when the left foot is in contact.
    pub fn left_in_contact(self) -> bool {
        self != ContactPhase::RightSupport
    }

    /// `true` when the right foot is in contact.
    pub fn right_in_contact(self) -> bool {
        self != ContactPhase::LeftSupport
    }
}
