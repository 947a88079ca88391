//! The minimum-jerk profile every smooth transition uses (task references, swing heights,
//! CoM height changes): s(λ) = 10λ³ − 15λ⁴ + 6λ⁵ on λ ∈ [0, 1], zero velocity and
//! acceleration at both ends (Flash & Hogan 1985).

/// [s, ds/dλ, d²s/dλ²] at `lambda`, clamped to [0, 1].
pub fn min_jerk(lambda: f64) -> [f64; 3] {
    let l = lambda.clamp(0.0, 1.0);
    [
        l * l * l * (10.0 - 15.0 * l + 6.0 * l * l),
        30.0 * l * l * (1.0 - l) * (1.0 - l),
        60.0 * l * (1.0 - l) * (1.0 - 2.0 * l),
    ]
}

/// `a → b` over a transition of `duration` s, at the fraction `lambda` of it (clamped):
/// value, rate and acceleration.
pub fn min_jerk_between(a: f64, b: f64, lambda: f64, duration: f64) -> [f64; 3] {
    let [s, ds, dds] = min_jerk(lambda);
    let d = b - a;
    [
        a + d * s,
        d * ds / duration,
        d * dds / (duration * duration),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_derivatives_match_finite_differences_and_vanish_at_the_ends() {
        let h = 1e-6;
        for k in 1..20 {
            let l = k as f64 / 20.0;
            let [_, ds, dds] = min_jerk(l);
            let fd = (min_jerk(l + h)[0] - min_jerk(l - h)[0]) / (2.0 * h);
            let fdd = (min_jerk(l + h)[1] - min_jerk(l - h)[1]) / (2.0 * h);
            assert!(
                (ds - fd).abs() < 1e-8 && (dds - fdd).abs() < 1e-6,
                "λ = {l}"
            );
        }
        assert_eq!(min_jerk(0.0), [0.0, 0.0, 0.0]);
        assert_eq!(min_jerk(1.0), [1.0, 0.0, 0.0]);
        assert_eq!(min_jerk(-1.0), [0.0, 0.0, 0.0]);
        assert_eq!(min_jerk(2.0), [1.0, 0.0, 0.0]);
        let [x, v, a] = min_jerk_between(1.0, 3.0, 0.5, 2.0);
        assert!((x - 2.0).abs() < 1e-15 && (v - 1.875).abs() < 1e-12 && a.abs() < 1e-12);
    }
}
