//! Second-order Butterworth low-pass filter per channel, the filter seed 002 §4.12 puts on the
//! F/T signals (order 2, Wn = 0.4 of the Nyquist frequency). Coefficients by the bilinear
//! transform with prewarping, as `scipy.signal.butter(2, Wn)`:
//! `K = tan(π Wn / 2)`, `b = [K², 2K², K²] / n`, `a = [1, 2(K² − 1) / n, (1 − √2 K + K²) / n]`,
//! `n = 1 + √2 K + K²`; `y_k = b₀x_k + b₁x_{k−1} + b₂x_{k−2} − a₁y_{k−1} − a₂y_{k−2}`.

use nalgebra::SVector;

/// The filter of `N` channels.
#[derive(Clone, Copy, Debug)]
pub struct Butterworth2<const N: usize> {
    b: [f64; 3],
    a: [f64; 2],
    x: [SVector<f64, N>; 2],
    y: [SVector<f64, N>; 2],
    started: bool,
}

impl<const N: usize> Butterworth2<N> {
    /// A filter with cutoff `wn` (fraction of the Nyquist frequency, in (0, 1)).
    pub fn new(wn: f64) -> Self {
        let k = (std::f64::consts::FRAC_PI_2 * wn).tan();
        let (k2, r2) = (k * k, std::f64::consts::SQRT_2 * k);
        let n = 1.0 + r2 + k2;
        Self {
            b: [k2 / n, 2.0 * k2 / n, k2 / n],
            a: [2.0 * (k2 - 1.0) / n, (1.0 - r2 + k2) / n],
            x: [SVector::zeros(); 2],
            y: [SVector::zeros(); 2],
            started: false,
        }
    }

    /// Numerator and denominator, scipy's `b` and `a[1..]`.
    pub fn coefficients(&self) -> ([f64; 3], [f64; 2]) {
        (self.b, self.a)
    }

    /// Filters one sample; the first one sets the filter at rest on it (no start-up step).
    pub fn filter(&mut self, x: &SVector<f64, N>) -> SVector<f64, N> {
        if !self.started {
            self.x = [*x; 2];
            self.y = [*x; 2];
            self.started = true;
        }
        let [b0, b1, b2] = self.b;
        let [a1, a2] = self.a;
        let y = x * b0 + self.x[0] * b1 + self.x[1] * b2 - self.y[0] * a1 - self.y[1] * a2;
        self.x = [*x, self.x[0]];
        self.y = [y, self.y[0]];
        y
    }

    /// Forgets the past samples (the next one sets the filter at rest again).
    pub fn reset(&mut self) {
        self.started = false;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector1;

    /// scipy.signal.butter(2, Wn) (`tools/golden/butterworth.py`).
    #[test]
    fn coefficients_match_scipy() {
        let golden = [
            (
                0.4,
                [
                    0.20657208382614792,
                    0.41314416765229584,
                    0.20657208382614792,
                ],
                [-0.3695273773512414, 0.19581571265583306],
            ),
            (
                0.1,
                [
                    0.020083365564211232,
                    0.040166731128422464,
                    0.020083365564211232,
                ],
                [-1.5610180758007182, 0.6413515380575631],
            ),
        ];
        for (wn, b, a) in golden {
            let (fb, fa) = Butterworth2::<1>::new(wn).coefficients();
            for (x, y) in fb.iter().chain(&fa).zip(b.iter().chain(&a)) {
                assert!((x - y).abs() < 1e-14, "Wn {wn}: {x} vs {y}");
            }
        }
    }

    /// Unit DC gain, and at the cutoff the response `|H(e^{jω})|` is 1/√2 (−3 dB).
    #[test]
    fn dc_passes_and_the_cutoff_is_minus_3_db() {
        let mut f = Butterworth2::<1>::new(0.4);
        f.filter(&Vector1::new(0.0));
        let mut y = 0.0;
        for _ in 0..200 {
            y = f.filter(&Vector1::new(2.0))[0];
        }
        assert!((y - 2.0).abs() < 1e-12, "{y}");
        let ([b0, b1, b2], [a1, a2]) = f.coefficients();
        let w = std::f64::consts::PI * 0.4;
        // Σ c_k e^{−jkω} as (re, im).
        let poly = |c: [f64; 3]| {
            (0..3).fold((0.0, 0.0), |(re, im), k| {
                let p = -(k as f64) * w;
                (re + c[k] * p.cos(), im + c[k] * p.sin())
            })
        };
        let (nr, ni) = poly([b0, b1, b2]);
        let (dr, di) = poly([1.0, a1, a2]);
        let gain = ((nr * nr + ni * ni) / (dr * dr + di * di)).sqrt();
        assert!((gain - 0.5f64.sqrt()).abs() < 1e-12, "{gain}");
    }
}
