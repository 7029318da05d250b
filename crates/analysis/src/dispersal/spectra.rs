//! Fourier spectra of periodic azimuthal series (φ(θ), v(θ), the band's outer radius
//! against θ; xue-2019 Figs. 10b, 12d–f): which mode number dominates the pattern.

use serde::Serialize;
use std::f64::consts::TAU;

/// Amplitude spectrum of a series sampled at n equal steps around the circle.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Spectrum {
    /// Amplitude of mode k = 0..=n/2: the mean for k = 0, otherwise the amplitude `a`
    /// of `a·cos(kθ + φ)`.
    pub amplitude: Vec<f64>,
    /// The mode k ≥ 2 of largest amplitude: the number of lobes of the pattern (k = 1
    /// is a shift of the whole ring against the centre, not a pattern). None when the
    /// series is flat or too short.
    pub dominant_mode: Option<usize>,
    /// Samples that were missing (non-finite) and filled by linear interpolation
    /// between their finite neighbours around the circle.
    pub filled: usize,
}

/// The spectrum of `values` (periodic). Missing values are filled first; with no
/// finite value at all every amplitude is zero.
pub fn spectrum(values: &[f64]) -> Spectrum {
    let n = values.len();
    let (x, filled) = fill_periodic(values);
    let mut amplitude = Vec::with_capacity(n / 2 + 1);
    for k in 0..=n / 2 {
        let (mut re, mut im) = (0.0, 0.0);
        for (j, v) in x.iter().enumerate() {
            // (k·j) mod n keeps the angle small, so the phase stays exact for large k.
            let a = TAU * ((k * j) % n) as f64 / n as f64;
            re += v * a.cos();
            im -= v * a.sin();
        }
        let scale = if k == 0 || 2 * k == n { 1.0 } else { 2.0 };
        amplitude.push(scale * (re * re + im * im).sqrt() / n.max(1) as f64);
    }
    let dominant_mode = (2..amplitude.len())
        .filter(|&k| amplitude[k] > 1e-12 * amplitude[0].abs().max(f64::MIN_POSITIVE))
        .max_by(|&a, &b| amplitude[a].total_cmp(&amplitude[b]).then(b.cmp(&a)));
    Spectrum {
        amplitude,
        dominant_mode,
        filled,
    }
}

/// Fills non-finite entries by linear interpolation between the nearest finite ones
/// around the circle; all zeros if none is finite. Returns the count filled.
pub(crate) fn fill_periodic(values: &[f64]) -> (Vec<f64>, usize) {
    let n = values.len();
    let known: Vec<usize> = (0..n).filter(|&j| values[j].is_finite()).collect();
    if known.is_empty() {
        return (vec![0.0; n], n);
    }
    let mut out = values.to_vec();
    for (a, &k0) in known.iter().enumerate() {
        let k1 = known[(a + 1) % known.len()];
        let gap = (k1 + n - k0) % n;
        let gap = if gap == 0 { n } else { gap };
        for s in 1..gap {
            let t = s as f64 / gap as f64;
            out[(k0 + s) % n] = (1.0 - t) * values[k0] + t * values[k1];
        }
    }
    (out, n - known.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_hexagonal_pattern_is_mode_six() {
        let n = 180;
        let v: Vec<f64> = (0..n)
            .map(|j| {
                let t = TAU * j as f64 / n as f64;
                10.0 + 2.0 * (6.0 * t + 0.3).cos() + 0.5 * (17.0 * t).sin() + 0.7 * t.cos()
            })
            .collect();
        let s = spectrum(&v);
        assert_eq!(s.dominant_mode, Some(6));
        assert!((s.amplitude[0] - 10.0).abs() < 1e-12);
        assert!((s.amplitude[6] - 2.0).abs() < 1e-12);
        assert!((s.amplitude[17] - 0.5).abs() < 1e-12);
        assert!((s.amplitude[1] - 0.7).abs() < 1e-12);
        assert_eq!(s.amplitude.len(), 91);
        assert_eq!(s.filled, 0);
    }

    #[test]
    fn gaps_are_filled_around_the_circle() {
        let (x, k) = fill_periodic(&[f64::NAN, 1.0, f64::NAN, 3.0, f64::NAN]);
        assert_eq!(k, 3);
        assert_eq!(&x[1..4], &[1.0, 2.0, 3.0]);
        // 3 → (4, 0) → 1 wraps: thirds.
        assert!(
            (x[4] - (3.0 - 2.0 / 3.0)).abs() < 1e-12 && (x[0] - (1.0 + 2.0 / 3.0)).abs() < 1e-12
        );
        assert_eq!(fill_periodic(&[f64::NAN; 3]), (vec![0.0; 3], 3));
        assert_eq!(spectrum(&[2.0; 8]).dominant_mode, None);
        assert_eq!(spectrum(&[]).amplitude, vec![0.0]);
    }
}
