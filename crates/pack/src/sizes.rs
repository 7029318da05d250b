//! Drawing diameters from the spec's distribution.

use crate::spec::SizeSpec;
use grains_core::rng::Rng;
use rand::RngExt;

/// A distribution ready to sample, with its nominal mean.
#[derive(Clone, Copy, Debug)]
pub enum Distribution {
    /// Normal(mean, sd), redrawn at or below zero.
    Gaussian {
        /// Mean.
        mean: f64,
        /// Standard deviation.
        sd: f64,
    },
    /// Uniform on [lo, hi].
    Uniform {
        /// Lower end.
        lo: f64,
        /// Upper end.
        hi: f64,
    },
    /// `large` with probability `p_large`, else `small`.
    Bidisperse {
        /// Small diameter.
        small: f64,
        /// Large diameter.
        large: f64,
        /// Probability of a large disk.
        p_large: f64,
    },
    /// exp(Normal(mu, s)).
    Lognormal {
        /// Mean of ln d.
        mu: f64,
        /// Standard deviation of ln d.
        s: f64,
    },
}

impl Distribution {
    /// The distribution a spec describes (validated beforehand).
    pub fn from_spec(spec: &SizeSpec) -> Self {
        match *spec {
            SizeSpec::Gaussian { d0, delta } => Distribution::Gaussian {
                mean: d0,
                sd: delta * d0,
            },
            SizeSpec::Uniform { d0, delta } => {
                let a = 3f64.sqrt() * delta * d0;
                Distribution::Uniform {
                    lo: d0 - a,
                    hi: d0 + a,
                }
            }
            SizeSpec::Bidisperse {
                d_small,
                d_large,
                fraction_large,
            } => Distribution::Bidisperse {
                small: d_small,
                large: d_large,
                p_large: fraction_large,
            },
            SizeSpec::Lognormal { d0, delta } => {
                let s2 = (1.0 + delta * delta).ln();
                Distribution::Lognormal {
                    mu: d0.ln() - 0.5 * s2,
                    s: s2.sqrt(),
                }
            }
        }
    }

    /// Nominal mean diameter (before truncation).
    pub fn mean(&self) -> f64 {
        match *self {
            Distribution::Gaussian { mean, .. } => mean,
            Distribution::Uniform { lo, hi } => 0.5 * (lo + hi),
            Distribution::Bidisperse {
                small,
                large,
                p_large,
            } => small + p_large * (large - small),
            Distribution::Lognormal { mu, s } => (mu + 0.5 * s * s).exp(),
        }
    }

    /// Nominal mean of d² (sets how many disks fill an area).
    pub fn mean_square(&self) -> f64 {
        match *self {
            Distribution::Gaussian { mean, sd } => mean * mean + sd * sd,
            Distribution::Uniform { lo, hi } => (lo * lo + lo * hi + hi * hi) / 3.0,
            Distribution::Bidisperse {
                small,
                large,
                p_large,
            } => small * small + p_large * (large * large - small * small),
            Distribution::Lognormal { mu, s } => (2.0 * mu + 2.0 * s * s).exp(),
        }
    }

    /// Probability mass the Gaussian loses at d ≤ 0 (0 for the others).
    pub fn truncated_mass(&self) -> f64 {
        match *self {
            Distribution::Gaussian { mean, sd } if sd > 0.0 => {
                0.5 * erfc(mean / (sd * std::f64::consts::SQRT_2))
            }
            _ => 0.0,
        }
    }

    /// One diameter.
    pub fn sample(&self, rng: &mut Rng) -> f64 {
        match *self {
            Distribution::Gaussian { mean, sd } => loop {
                let d = mean + sd * normal(rng);
                if d > 0.0 {
                    return d;
                }
            },
            Distribution::Uniform { lo, hi } => lo + (hi - lo) * rng.random::<f64>(),
            Distribution::Bidisperse {
                small,
                large,
                p_large,
            } => {
                if rng.random::<f64>() < p_large {
                    large
                } else {
                    small
                }
            }
            Distribution::Lognormal { mu, s } => (mu + s * normal(rng)).exp(),
        }
    }
}

/// A standard normal variate (Box–Muller, one of the pair).
fn normal(rng: &mut Rng) -> f64 {
    let u1: f64 = 1.0 - rng.random::<f64>(); // (0, 1]: ln stays finite
    let u2: f64 = rng.random::<f64>();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// Complementary error function (Numerical Recipes' erfcc, relative error < 1.2e-7).
fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let r = t
        * (-z * z - 1.265_512_23
            + t * (1.000_023_68
                + t * (0.374_091_96
                    + t * (0.096_784_18
                        + t * (-0.186_288_06
                            + t * (0.278_868_07
                                + t * (-1.135_203_98
                                    + t * (1.488_515_87
                                        + t * (-0.822_152_23 + t * 0.170_872_77)))))))))
            .exp();
    if x >= 0.0 {
        r
    } else {
        2.0 - r
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use grains_analysis::sizes::stats;

    fn realised(spec: SizeSpec) -> (f64, f64) {
        let d = Distribution::from_spec(&spec);
        let mut rng = grains_core::rng::seeded(3);
        let v: Vec<f64> = (0..200_000).map(|_| d.sample(&mut rng)).collect();
        let s = stats(&v);
        (s.mean, s.polydispersity)
    }

    #[test]
    fn polydispersity_matches_delta() {
        for spec in [
            SizeSpec::Gaussian {
                d0: 1.0,
                delta: 0.113,
            },
            SizeSpec::Uniform {
                d0: 1.0,
                delta: 0.177,
            },
            SizeSpec::Lognormal {
                d0: 1.0,
                delta: 0.2,
            },
        ] {
            let (m, p) = realised(spec.clone());
            let want = match spec {
                SizeSpec::Gaussian { delta, .. }
                | SizeSpec::Uniform { delta, .. }
                | SizeSpec::Lognormal { delta, .. } => delta,
                _ => unreachable!(),
            };
            assert!((m - 1.0).abs() < 3e-3, "{spec:?}: mean {m}");
            assert!((p - want).abs() < 3e-3, "{spec:?}: delta {p}");
        }
        let (m, _) = realised(SizeSpec::Bidisperse {
            d_small: 1.0,
            d_large: 1.4,
            fraction_large: 0.5,
        });
        assert!((m - 1.2).abs() < 3e-3);
    }

    #[test]
    fn truncation_mass() {
        let d = Distribution::Gaussian { mean: 1.0, sd: 0.5 };
        assert!((d.truncated_mass() - 0.022_750).abs() < 1e-5);
        assert!(
            Distribution::Gaussian {
                mean: 1.0,
                sd: 0.113
            }
            .truncated_mass()
                < 1e-15
        );
    }
}
