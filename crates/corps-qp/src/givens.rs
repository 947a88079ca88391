//! Givens plane rotations.
//!
//! A rotation `(c, s)` maps a pair `(a, b)` to `(c a + s b, c b − s a)`; [`Givens::zeroing`]
//! picks it so that the second entry becomes zero.

use crate::linalg::rot;

/// A plane rotation `[c s; −s c]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Givens {
    /// Cosine.
    pub c: f64,
    /// Sine.
    pub s: f64,
}

impl Givens {
    /// The rotation that maps `(a, b)` to `(h, 0)` with `h = ‖(a, b)‖`, and `h`.
    /// Returns `None` when `b` is already zero (identity rotation).
    #[inline(always)]
    pub fn zeroing(a: f64, b: f64) -> Option<(Self, f64)> {
        if b == 0.0 {
            return None;
        }
        let mut h = (a * a + b * b).sqrt();
        if !(h.is_finite() && h > 0.0) {
            // Over- or underflow of the squares: take the careful (slow) path.
            h = a.hypot(b);
        }
        Some((Self { c: a / h, s: b / h }, h))
    }

    /// Rotate two slices (e.g. two columns of J) over their common prefix:
    /// `x ← c x + s y`, `y ← c y − s x`.
    #[inline(always)]
    pub fn apply<const F: bool>(self, x: &mut [f64], y: &mut [f64]) {
        rot::<F>(self.c, self.s, x, y);
    }

    /// Rotate a pair of scalars.
    #[inline(always)]
    pub fn apply_pair(self, a: f64, b: f64) -> (f64, f64) {
        (self.c * a + self.s * b, self.c * b - self.s * a)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zeroing_rotation_zeroes_second_entry() {
        let (gr, h) = Givens::zeroing(3.0, 4.0).unwrap();
        let (a, b) = gr.apply_pair(3.0, 4.0);
        assert!((a - 5.0).abs() < 1e-15 && b.abs() < 1e-15 && (h - 5.0).abs() < 1e-15);
        let mut x = [3.0, 1.0];
        let mut y = [4.0, 2.0];
        gr.apply::<false>(&mut x, &mut y);
        assert!((x[0] - 5.0).abs() < 1e-15 && y[0].abs() < 1e-15);
        // Rotations preserve norms.
        assert!((x[1] * x[1] + y[1] * y[1] - 5.0).abs() < 1e-14);
        assert!(Givens::zeroing(1.0, 0.0).is_none());
        // Huge entries take the overflow-safe path.
        let (_, h) = Givens::zeroing(3e200, 4e200).unwrap();
        assert!((h / 5e200 - 1.0).abs() < 1e-15);
    }
}
