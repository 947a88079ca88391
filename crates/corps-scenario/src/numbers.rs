//! Numbers in messages.

/// `x` for a message: plain when moderate, in scientific notation when huge or tiny.
pub fn number(x: f64) -> String {
    if x == 0.0 || (1e-4..1e7).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}
