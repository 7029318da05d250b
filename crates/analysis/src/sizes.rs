//! Size statistics: mean diameter d0, polydispersity δ = √⟨Δd²⟩ / ⟨d⟩ (xue-2019 Eq. 1),
//! and the empirical PDF and CDF of diameters.

/// Mean diameter and polydispersity of a set of diameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SizeStats {
    /// ⟨d⟩.
    pub mean: f64,
    /// √⟨(d − ⟨d⟩)²⟩ / ⟨d⟩ (population standard deviation).
    pub polydispersity: f64,
    /// Smallest diameter.
    pub min: f64,
    /// Largest diameter.
    pub max: f64,
    /// Number of diameters.
    pub count: usize,
}

/// Statistics of `diameters` (NaN fields when empty). Sums run in input order, so
/// the figures are reproducible.
pub fn stats(diameters: &[f64]) -> SizeStats {
    let n = diameters.len();
    if n == 0 {
        return SizeStats {
            mean: f64::NAN,
            polydispersity: f64::NAN,
            min: f64::NAN,
            max: f64::NAN,
            count: 0,
        };
    }
    let mean = diameters.iter().sum::<f64>() / n as f64;
    let var = diameters
        .iter()
        .map(|d| (d - mean) * (d - mean))
        .sum::<f64>()
        / n as f64;
    SizeStats {
        mean,
        polydispersity: var.sqrt() / mean,
        min: diameters.iter().cloned().fold(f64::INFINITY, f64::min),
        max: diameters.iter().cloned().fold(f64::NEG_INFINITY, f64::max),
        count: n,
    }
}

/// A histogram density of `values` over `bins` equal bins spanning their range:
/// bin centres and densities (integrating to 1).
pub fn pdf(values: &[f64], bins: usize) -> (Vec<f64>, Vec<f64>) {
    let bins = bins.max(1);
    let lo = values.iter().cloned().fold(f64::INFINITY, f64::min);
    let hi = values.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    if values.is_empty() || hi.partial_cmp(&lo) != Some(std::cmp::Ordering::Greater) {
        return (
            values.first().map(|v| vec![*v]).unwrap_or_default(),
            vec![f64::NAN; values.len().min(1)],
        );
    }
    let w = (hi - lo) / bins as f64;
    let mut h = vec![0.0; bins];
    for v in values {
        h[(((v - lo) / w) as usize).min(bins - 1)] += 1.0;
    }
    let centres = (0..bins).map(|k| lo + (k as f64 + 0.5) * w).collect();
    let norm = 1.0 / (values.len() as f64 * w);
    (centres, h.into_iter().map(|c| c * norm).collect())
}

/// The empirical CDF of `values`, thinned to at most `points` points: sorted values and
/// the fraction of values at or below each.
pub fn cdf(values: &[f64], points: usize) -> (Vec<f64>, Vec<f64>) {
    let mut v: Vec<f64> = values.iter().cloned().filter(|x| x.is_finite()).collect();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    let stride = n.div_ceil(points.max(2)).max(1);
    let mut xs = Vec::new();
    let mut ps = Vec::new();
    for k in (0..n).step_by(stride).chain(n.checked_sub(1)) {
        xs.push(v[k]);
        ps.push((k + 1) as f64 / n as f64);
    }
    (xs, ps)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polydispersity_of_two_sizes() {
        let s = stats(&[1.0, 3.0]);
        assert_eq!(s.mean, 2.0);
        assert!((s.polydispersity - 0.5).abs() < 1e-15);
        let (x, p) = pdf(&[1.0, 2.0, 2.0, 3.0], 2);
        assert_eq!(x, vec![1.5, 2.5]);
        assert!((p.iter().sum::<f64>() * 1.0 - 1.0).abs() < 1e-12);
        let (x, p) = cdf(&[3.0, 1.0, 2.0], 10);
        assert_eq!(x.first(), Some(&1.0));
        assert_eq!(p.last(), Some(&1.0));
        assert!(stats(&[]).mean.is_nan());
    }
}
