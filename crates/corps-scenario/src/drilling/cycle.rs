//! The drilling cycle of seed 000 Table 6.2 as a list of stations, and the phases the tool
//! goes through at each: move to the approach point above the station, descend until the
//! clamp load cell reads the touch force, raise the clamping force, hold it (a check of the
//! pre-hole, or a hole drilled against the drill's thrust), lower it, retreat.

use super::section::CycleSection;

/// One stop of the tool on the plate.
#[derive(Clone, Debug, PartialEq)]
pub struct Station {
    /// "R1 check", "hole 3", "R2 final", …
    pub name: String,
    /// Position on the plate (m, plate x and y).
    pub at: [f64; 2],
    /// How long the clamping force is held (s).
    pub hold: f64,
    /// Whether a hole is drilled (the thrust acts during the hold).
    pub drill: bool,
}

/// Table 6.2: clamp and check R1 (steps 0–1), then R2 (2–3), drill `holes` holes evenly
/// spaced strictly between them (4–5), drill R1 to its final diameter (6–7), then R2 (8).
pub fn stations(c: &CycleSection) -> Vec<Station> {
    let check = |name: &str, at| Station {
        name: name.into(),
        at,
        hold: c.check_time,
        drill: false,
    };
    let drill = |name: String, at| Station {
        name,
        at,
        hold: c.drill_time,
        drill: true,
    };
    let mut out = vec![check("R1 check", c.r1), check("R2 check", c.r2)];
    for k in 1..=c.holes {
        let s = k as f64 / (c.holes + 1) as f64;
        let at = [
            c.r1[0] + s * (c.r2[0] - c.r1[0]),
            c.r1[1] + s * (c.r2[1] - c.r1[1]),
        ];
        out.push(drill(format!("hole {k}"), at));
    }
    out.push(drill("R1 final".into(), c.r1));
    out.push(drill("R2 final".into(), c.r2));
    out
}

/// What the tool is doing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// Free motion to the approach point above the station.
    Move,
    /// Free motion down to the guard point, then the guarded approach through the surface,
    /// until the touch.
    Descend,
    /// In contact: the clamping force rises from the touch force to the clamp force.
    Clamp,
    /// The clamping force held (the drill's thrust on, for a hole).
    Hold,
    /// The clamping force lowered to zero; then the contact is released.
    Release,
    /// Free motion back to the approach point.
    Retreat,
    /// The cycle is over: the tool holds its last approach point.
    Done,
}

impl Phase {
    /// A number for the log.
    pub fn code(self) -> f64 {
        match self {
            Phase::Move => 0.0,
            Phase::Descend => 1.0,
            Phase::Clamp => 2.0,
            Phase::Hold => 3.0,
            Phase::Release => 4.0,
            Phase::Retreat => 5.0,
            Phase::Done => 6.0,
        }
    }

    /// Whether the clamping bounds of Eq 6.2 hold in this phase (the force held).
    pub fn clamped(self) -> bool {
        self == Phase::Hold
    }
}

/// How long the guarded approach takes from the guard point down to its lowest (s).
pub fn guarded_time(c: &CycleSection) -> f64 {
    (c.guard + c.descent_overshoot) / c.touch_speed
}

/// The longest the cycle can take (s): every phase's nominal duration, the descent's as if
/// the touch came at the end of the guarded approach, and half a second more per station.
pub fn nominal_length(c: &CycleSection) -> f64 {
    stations(c)
        .iter()
        .map(|s| {
            c.move_time
                + c.descent_time
                + guarded_time(c)
                + 2.0 * c.ramp_time
                + s.hold
                + c.retreat_time
                + 0.5
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_6_2_order_and_spacing() {
        let c = CycleSection {
            holes: 3,
            r1: [0.0, -0.2],
            r2: [0.0, 0.2],
            ..Default::default()
        };
        let s = stations(&c);
        let names: Vec<&str> = s.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(
            names,
            ["R1 check", "R2 check", "hole 1", "hole 2", "hole 3", "R1 final", "R2 final"]
        );
        assert_eq!(s[3].at, [0.0, 0.0]);
        assert!((s[2].at[1] + 0.1).abs() < 1e-12);
        assert!(!s[0].drill && s[2].drill && s[6].drill);
        assert_eq!(s[0].hold, c.check_time);
        assert_eq!(s[4].hold, c.drill_time);
    }
}
