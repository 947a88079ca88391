//! Butterworth low-pass filters as second-order sections (bilinear transform with the cut-off
//! pre-warped), applied forward and backward for zero phase, and decimation — the
//! pre-processing of seed 000 §6 step 4 (order 5, 5 Hz, zero phase, then decimation).

use std::f64::consts::PI;

/// One section `H(z) = (b0 + b1 z⁻¹ + b2 z⁻²) / (1 + a1 z⁻¹ + a2 z⁻²)`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Section {
    b: [f64; 3],
    a: [f64; 2],
}

/// A digital Butterworth low-pass filter.
#[derive(Clone, Debug, PartialEq)]
pub struct Butterworth {
    sections: Vec<Section>,
}

impl Butterworth {
    /// Order `order` (≥ 1), cut-off `cutoff_hz` (−3 dB) at sampling rate `sample_hz`; None
    /// when the cut-off is not inside (0, Nyquist).
    pub fn low_pass(order: usize, cutoff_hz: f64, sample_hz: f64) -> Option<Self> {
        if order == 0 || !(cutoff_hz > 0.0 && cutoff_hz < 0.5 * sample_hz) {
            return None;
        }
        let fs2 = 2.0 * sample_hz;
        let warped = fs2 * (PI * cutoff_hz / sample_hz).tan();
        let mut sections = Vec::new();
        // Analog poles Ω_c e^{iπ(2k + n + 1)/(2n)}, k = 0 … n−1; one of each conjugate pair.
        for k in 0..order / 2 {
            let theta = PI * (2 * k + order + 1) as f64 / (2 * order) as f64;
            let (re, im) = (warped * theta.cos(), warped * theta.sin());
            // z = (1 + s/2fs) / (1 − s/2fs).
            let (nr, ni) = (1.0 + re / fs2, im / fs2);
            let (dr, di) = (1.0 - re / fs2, -im / fs2);
            let den = dr * dr + di * di;
            let zr = (nr * dr + ni * di) / den;
            let zi = (ni * dr - nr * di) / den;
            let (a1, a2) = (-2.0 * zr, zr * zr + zi * zi);
            let gain = (1.0 + a1 + a2) / 4.0;
            sections.push(Section {
                b: [gain, 2.0 * gain, gain],
                a: [a1, a2],
            });
        }
        if order % 2 == 1 {
            let z = (1.0 - warped / fs2) / (1.0 + warped / fs2);
            let gain = (1.0 - z) / 2.0;
            sections.push(Section {
                b: [gain, gain, 0.0],
                a: [-z, 0.0],
            });
        }
        Some(Self { sections })
    }

    /// The magnitude of the frequency response at `f_hz`.
    pub fn gain(&self, f_hz: f64, sample_hz: f64) -> f64 {
        let w = 2.0 * PI * f_hz / sample_hz;
        let z1 = (w.cos(), -w.sin());
        let z2 = ((2.0 * w).cos(), -(2.0 * w).sin());
        self.sections.iter().fold(1.0, |g, s| {
            let num = (
                s.b[0] + s.b[1] * z1.0 + s.b[2] * z2.0,
                s.b[1] * z1.1 + s.b[2] * z2.1,
            );
            let den = (
                1.0 + s.a[0] * z1.0 + s.a[1] * z2.0,
                s.a[0] * z1.1 + s.a[1] * z2.1,
            );
            g * (num.0.hypot(num.1) / den.0.hypot(den.1))
        })
    }

    /// Causal filtering, each section started at rest at the first sample's steady state.
    fn forward(&self, x: &mut [f64]) {
        for s in &self.sections {
            let Some(&first) = x.first() else { return };
            // Transposed direct form II, steady state for a constant input `first`
            // (every section has unit DC gain).
            let mut z2 = s.b[2] * first - s.a[1] * first;
            let mut z1 = first - s.b[0] * first;
            for v in x.iter_mut() {
                let input = *v;
                let y = s.b[0] * input + z1;
                z1 = s.b[1] * input - s.a[0] * y + z2;
                z2 = s.b[2] * input - s.a[1] * y;
                *v = y;
            }
        }
    }

    /// Zero-phase filtering (forward then backward) of `x`, padded at both ends by `pad`
    /// samples of its odd reflection about the end sample (`2x₀ − x_k`) to settle the
    /// transients. Noise on an end sample offsets the reflection: the result near either end
    /// (a few periods of the cut-off) is only as good as that sample.
    pub fn filtfilt(&self, x: &[f64], pad: usize) -> Vec<f64> {
        let n = x.len();
        if n == 0 {
            return Vec::new();
        }
        let pad = pad.min(n - 1);
        let mut y = Vec::with_capacity(n + 2 * pad);
        y.extend((1..=pad).rev().map(|k| 2.0 * x[0] - x[k]));
        y.extend_from_slice(x);
        y.extend((1..=pad).map(|k| 2.0 * x[n - 1] - x[n - 1 - k]));
        self.forward(&mut y);
        y.reverse();
        self.forward(&mut y);
        y.reverse();
        y[pad..pad + n].to_vec()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_response_is_butterworth() {
        let fs = 2000.0;
        let f = Butterworth::low_pass(5, 5.0, fs).unwrap();
        assert!((f.gain(0.0, fs) - 1.0).abs() < 1e-12);
        assert!((f.gain(5.0, fs) - 0.5f64.sqrt()).abs() < 1e-9);
        // The bilinear transform maps f to the analog tan(πf/fs): |H|² = 1/(1 + r¹⁰) with
        // r = tan(πf/fs)/tan(πf_c/fs), exactly.
        for f_hz in [2.5, 10.0, 20.0, 200.0] {
            let r = (PI * f_hz / fs).tan() / (PI * 5.0 / fs).tan();
            let expected = 1.0 / (1.0 + r.powi(10)).sqrt();
            let g = f.gain(f_hz, fs);
            assert!(
                (g / expected - 1.0).abs() < 1e-8,
                "{f_hz}: {g} vs {expected}"
            );
        }
        assert!(Butterworth::low_pass(5, 1000.0, fs).is_none());
    }

    #[test]
    fn zero_phase_filtering_keeps_a_slow_sine_in_place_and_removes_a_fast_one() {
        let fs = 2000.0;
        let f = Butterworth::low_pass(5, 5.0, fs).unwrap();
        let x: Vec<f64> = (0..8000)
            .map(|k| {
                let t = k as f64 / fs;
                (2.0 * PI * 0.5 * t).sin() + 0.3 * (2.0 * PI * 60.0 * t).sin()
            })
            .collect();
        let y = f.filtfilt(&x, 2000);
        // Gain |H(0.5 Hz)|² = 1 − 1e-10: no lag, no attenuation, once a second away from
        // the ends (the last sample carries the 60 Hz ripple into the reflection).
        for (k, yk) in y.iter().enumerate().take(6000).skip(2000) {
            let slow = (2.0 * PI * 0.5 * k as f64 / fs).sin();
            assert!((yk - slow).abs() < 1e-6, "{k}: {yk} vs {slow}");
        }
    }
}
