//! The min-jerk blend every smooth transition of a walk uses (CoM height over a step, the
//! swing's height, the start of a walk off the middle of the feet).

/// `a → b` by the min-jerk polynomial `s(λ) = 10λ³ − 15λ⁴ + 6λ⁵` at `λ ∈ [0, 1]` (clamped) of
/// a transition of `duration` s: value, rate, acceleration.
pub(crate) fn min_jerk(a: f64, b: f64, lam: f64, duration: f64) -> [f64; 3] {
    let l = lam.clamp(0.0, 1.0);
    let d = b - a;
    let s = l * l * l * (10.0 - 15.0 * l + 6.0 * l * l);
    let ds = 30.0 * l * l * (1.0 - l) * (1.0 - l);
    let dds = 60.0 * l * (1.0 - l) * (1.0 - 2.0 * l);
    [
        a + d * s,
        d * ds / duration,
        d * dds / (duration * duration),
    ]
}
