//! A foot of a run: the force/torque sensor under it and the body carrying it.

/// A foot: a force/torque sensor under it and the body carrying it.
#[derive(Clone, Debug)]
pub struct Foot {
    /// Label used in column and plot names ("left").
    pub label: String,
    /// Index of its force/torque sensor in the readings.
    pub sensor: usize,
    /// Frame of that sensor (TALOS: the sole frame).
    pub frame: usize,
    /// Joint whose body carries the sensor.
    pub joint: usize,
}
