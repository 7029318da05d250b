//! Spiral shear bands at the inner perimeter of the compact band (xue-2019 §§5.2, 5.4,
//! 5.5, Figs. 7d, 11, 12): how many clockwise and anticlockwise bands, their angle to
//! the radius, and how they group.
//!
//! The paper traces the bands by eye in the shear-rate field: curves of high γ̇ that
//! leave the inner perimeter at about 45° to the radius, clockwise and anticlockwise,
//! crossing into a grid. A band at a constant angle α to the radius is a logarithmic
//! spiral, θ = θ0 ± tan α · ln(r/r0), a straight line in (ln r, θ). So:
//!
//! 1. **Annulus.** The rings from just inside the band's inner surface (the median
//!    first ring with material, plus `skip_rings` partly filled surface rings) out to
//!    `rows` rings, but not past the median band boundary. γ̇ of each ring is divided
//!    by the ring's mean, so the fall of γ̇ with radius does not weigh the rings; bins
//!    without a value count as the mean.
//! 2. **Spiral sums.** For each sense (clockwise: θ decreases outward; anticlockwise:
//!    increases) and each angle α on a grid (`min_angle`..`max_angle`, every
//!    `angle_step` degrees), S(θ0) is the mean of the normalised γ̇ along the spiral
//!    from θ0 on the first ring, read by linear interpolation between sectors. When α
//!    matches a family its bands add up along the path and S(θ0) peaks at each band's
//!    root; bands of the other sense are crossed and smear out. The ridge response
//!    R(θ0) = S(θ0) − ½[S(θ0 − δ) + S(θ0 + δ)], δ = `min_separation` sectors, keeps
//!    what is sharp in θ0 (bands of this sense) and cancels what is smooth (the
//!    crossings of the other family, broad variations of γ̇). The family's angle is the
//!    α whose R varies most (largest standard deviation).
//! 3. **Counting.** The bands of a family are the peaks of R at that angle: local
//!    maxima over ±`min_separation` sectors standing `ridge_threshold` times the noise
//!    above its mean. The noise is the standard deviation of R at the least varied
//!    (sense, angle) of the search, where no family lines up: a field of noise alone
//!    then yields next to no bands, whatever its amplitude. Their θ0 are the roots on
//!    the first ring.
//! 4. **Groups.** The paper's groups are the repeats of the band pattern round the
//!    inner perimeter: the bands of both senses gather between the "velocity petals"
//!    (§5.5, Fig. 12), six of them in an ordered ring's hexagonal band, dozens in an
//!    amorphous one's, where each band or pair is a group of its own. Their number is
//!    `dominant_mode`, the leading azimuthal Fourier mode (k ≥ 2) of the annulus' mean
//!    normalised γ̇ per sector: a group of crossing bands is one lobe of high γ̇. It does
//!    not rest on resolving every band: on a coarse ring (a sector ~1 d0 wide, the
//!    annulus 2–4 rings of 5 d0) the spiral sums miss bands, the spectrum does not.
//!
//! The angle is the one at the inner perimeter; the paper notes that it grows
//! outward. A family whose angle is an end of the search range is flagged
//! (`at_search_limit`): at the low end it is radial streaks, not spirals. Resolution: a band is found if it is at least a sector apart from its
//! neighbours of the same sense and the annulus spans a few rings.

use super::bands::BandMap;
use super::fields::PolarFields;
use super::input::{at_least, positive, InputError};
use super::spectra::spectrum;
use serde::{Deserialize, Serialize};

/// Settings of the shear-band detection.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ShearBandSpec {
    /// Rings of the annulus (at most; fewer if the band is thinner).
    pub rows: usize,
    /// Rings skipped at the inner surface (partly filled).
    pub skip_rings: usize,
    /// Smallest angle to the radius tried (degrees).
    pub min_angle: f64,
    /// Largest angle to the radius tried (degrees).
    pub max_angle: f64,
    /// Angle step (degrees).
    pub angle_step: f64,
    /// Peak height for a band, in units of the noise of the ridge response.
    pub ridge_threshold: f64,
    /// Closest two bands of one sense may be, in sectors.
    pub min_separation: usize,
}

impl Default for ShearBandSpec {
    fn default() -> Self {
        ShearBandSpec {
            rows: 6,
            skip_rings: 1,
            min_angle: 15.0,
            max_angle: 75.0,
            angle_step: 2.5,
            ridge_threshold: 3.0,
            min_separation: 2,
        }
    }
}

impl ShearBandSpec {
    /// Checks the settings; `key` names the section in messages.
    pub fn validate(&self, key: &str) -> Result<(), InputError> {
        let k = |f: &str| format!("{key}.{f}");
        at_least(&k("rows"), self.rows, 2)?;
        positive(&k("angle_step"), self.angle_step)?;
        positive(&k("ridge_threshold"), self.ridge_threshold)?;
        if !(self.min_angle >= 0.0 && self.min_angle < self.max_angle && self.max_angle < 90.0) {
            return Err(InputError::new(
                k("min_angle/max_angle"),
                format!("{}/{}", self.min_angle, self.max_angle),
                "must satisfy 0 ≤ min_angle < max_angle < 90",
            ));
        }
        at_least(&k("min_separation"), self.min_separation, 1).map(|_| ())
    }
}

/// The bands of one sense.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SpiralFamily {
    /// Number of bands.
    pub count: usize,
    /// Their angle to the radius at the inner perimeter (degrees).
    pub angle: f64,
    /// Angles of their roots on the first ring of the annulus (rad).
    pub roots: Vec<f64>,
    /// Standard deviation of the ridge response at that angle (how sharply the family
    /// stands out; about 0 for no bands).
    pub contrast: f64,
    /// The angle is an end of the search range: the bands may lie outside it (at the
    /// low end, nearly radial streaks rather than spirals).
    pub at_search_limit: bool,
}

/// The spiral shear bands of one frame.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ShearBands {
    /// Bands along which θ decreases outward.
    pub clockwise: SpiralFamily,
    /// Bands along which θ increases outward.
    pub anticlockwise: SpiralFamily,
    /// Groups of bands: the repeats of the band pattern round the inner perimeter,
    /// `dominant_mode` (0 for a flat field; see the module documentation).
    pub groups: usize,
    /// Leading azimuthal mode (k ≥ 2) of the shear rate in the annulus.
    pub dominant_mode: Option<usize>,
    /// Inner and outer radius of the annulus searched (m).
    pub annulus: (f64, f64),
}

/// Finds the spiral shear bands in `fields` at the inner perimeter of the band of
/// `map`; None when there is no band or it is less than two rings thick.
pub fn shear_bands(
    fields: &PolarFields,
    map: &BandMap,
    spec: &ShearBandSpec,
) -> Option<ShearBands> {
    let g = &fields.grid;
    let nt = g.n_theta();
    let median = |v: Vec<usize>| -> Option<usize> {
        let mut v = v;
        v.sort_unstable();
        v.get(v.len() / 2).copied()
    };
    let banded: Vec<usize> = (0..nt).filter(|&j| map.last_ring[j].is_some()).collect();
    let first =
        median(banded.iter().filter_map(|&j| map.inner_ring[j]).collect())? + spec.skip_rings;
    let last = median(banded.iter().filter_map(|&j| map.last_ring[j]).collect())?;
    let rows = (last + 1).saturating_sub(first).min(spec.rows);
    if rows < 2 {
        return None;
    }
    let radii: Vec<f64> = (first..first + rows).map(|i| g.r_centre(i)).collect();
    let mut values = Vec::with_capacity(rows * nt);
    for i in first..first + rows {
        let row: Vec<f64> = (0..nt).map(|j| fields.shear_rate[g.index(i, j)]).collect();
        let (s, n) = row
            .iter()
            .filter(|x| x.is_finite())
            .fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
        let mean = if n > 0 { s / n as f64 } else { 0.0 };
        values.extend(row.iter().map(|x| {
            if x.is_finite() && mean > 0.0 {
                x / mean
            } else {
                1.0
            }
        }));
    }
    let annulus = Annulus {
        radii,
        n_theta: nt,
        values,
    };
    Some(annulus.detect(spec, (g.r_edge(first), g.r_edge(first + rows))))
}

/// Normalised γ̇ on `radii.len()` rings × `n_theta` sectors, ring by ring.
struct Annulus {
    radii: Vec<f64>,
    n_theta: usize,
    values: Vec<f64>,
}

impl Annulus {
    /// Value of ring `k` at fractional sector `s` (periodic, linear).
    fn at(&self, k: usize, s: f64) -> f64 {
        let n = self.n_theta;
        let s = s.rem_euclid(n as f64);
        let j0 = (s.floor() as usize).min(n - 1);
        let t = s - j0 as f64;
        let row = &self.values[k * n..(k + 1) * n];
        (1.0 - t) * row[j0] + t * row[(j0 + 1) % n]
    }

    /// The spiral sum S(θ0) for `sense` (−1 clockwise, +1 anticlockwise) at angle
    /// `alpha` (rad) from every sector's centre on the first ring.
    fn spiral_sum(&self, sense: f64, alpha: f64) -> Vec<f64> {
        let n = self.n_theta;
        let per_rad = n as f64 / std::f64::consts::TAU;
        let shifts: Vec<f64> = self
            .radii
            .iter()
            .map(|r| sense * alpha.tan() * (r / self.radii[0]).ln() * per_rad)
            .collect();
        (0..n)
            .map(|j| {
                shifts
                    .iter()
                    .enumerate()
                    .map(|(k, sh)| self.at(k, j as f64 + sh))
                    .sum::<f64>()
                    / shifts.len() as f64
            })
            .collect()
    }

    /// The ridge response of the spiral sum: S(θ0) less the mean of S a lateral
    /// `sep` sectors either side. Bands of the same sense are sharp in θ0 and stand
    /// out; the crossings of the other family, and broad variations of γ̇, are smooth
    /// in θ0 and cancel.
    fn ridge(&self, sense: f64, alpha: f64, sep: usize) -> Vec<f64> {
        let s = self.spiral_sum(sense, alpha);
        let n = s.len();
        (0..n)
            .map(|j| s[j] - 0.5 * (s[(j + sep) % n] + s[(j + n - sep % n) % n]))
            .collect()
    }

    /// The ridge response of every angle of the grid for `sense`.
    fn responses(&self, sense: f64, spec: &ShearBandSpec) -> Vec<(f64, Vec<f64>, f64)> {
        (0..=last_step(spec))
            .map(|s| {
                let deg = spec.min_angle + s as f64 * spec.angle_step;
                let r = self.ridge(sense, deg.to_radians(), spec.min_separation);
                let sd = mean_sd(&r).1;
                (deg, r, sd)
            })
            .collect()
    }

    /// The family of the angle with the most varied response; peaks count above
    /// `ridge_threshold` × `noise`.
    fn family(
        responses: Vec<(f64, Vec<f64>, f64)>,
        noise: f64,
        spec: &ShearBandSpec,
    ) -> SpiralFamily {
        let n = responses.first().map_or(0, |r| r.1.len());
        let Some((angle, best, sd)) = responses.into_iter().max_by(|a, b| a.2.total_cmp(&b.2))
        else {
            return SpiralFamily {
                count: 0,
                angle: f64::NAN,
                roots: Vec::new(),
                contrast: 0.0,
                at_search_limit: false,
            };
        };
        let peaks = peaks(&best, spec.ridge_threshold * noise, spec.min_separation);
        let dt = std::f64::consts::TAU / n.max(1) as f64;
        let last = spec.min_angle + last_step(spec) as f64 * spec.angle_step;
        SpiralFamily {
            count: peaks.len(),
            angle,
            roots: peaks.iter().map(|&j| (j as f64 + 0.5) * dt).collect(),
            contrast: sd,
            at_search_limit: angle <= spec.min_angle || angle >= last,
        }
    }

    fn detect(&self, spec: &ShearBandSpec, annulus: (f64, f64)) -> ShearBands {
        let cw = self.responses(-1.0, spec);
        let acw = self.responses(1.0, spec);
        // The noise level: the least varied response over both senses and all angles,
        // where no family lines up and only the field's noise (and smeared bands) is
        // left.
        let noise = cw
            .iter()
            .chain(&acw)
            .map(|r| r.2)
            .fold(f64::INFINITY, f64::min);
        let clockwise = Self::family(cw, noise, spec);
        let anticlockwise = Self::family(acw, noise, spec);
        let n = self.n_theta;
        let rows = self.radii.len();
        let mean_per_sector: Vec<f64> = (0..n)
            .map(|j| (0..rows).map(|k| self.values[k * n + j]).sum::<f64>() / rows as f64)
            .collect();
        let dominant_mode = spectrum(&mean_per_sector).dominant_mode;
        ShearBands {
            groups: dominant_mode.unwrap_or(0),
            dominant_mode,
            clockwise,
            anticlockwise,
            annulus,
        }
    }
}

/// Index of the last angle of the search grid.
fn last_step(spec: &ShearBandSpec) -> usize {
    ((spec.max_angle - spec.min_angle) / spec.angle_step).floor() as usize
}

fn mean_sd(v: &[f64]) -> (f64, f64) {
    let n = v.len().max(1) as f64;
    let m = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / n;
    (m, var.sqrt())
}

/// Indices of the local maxima of the periodic `s` over ±`sep` that stand at least
/// `height` above its mean (ties: the first index). A flat `s` has none.
fn peaks(s: &[f64], height: f64, sep: usize) -> Vec<usize> {
    let n = s.len();
    let (m, sd) = mean_sd(s);
    if n == 0 || sd <= 1e-12 * m.abs().max(1.0) {
        return Vec::new();
    }
    let sep = sep.min(n / 2);
    (0..n)
        .filter(|&j| {
            s[j] - m >= height
                && (1..=sep).all(|d| {
                    let (a, b) = (s[(j + d) % n], s[(j + n - d) % n]);
                    s[j] > a && s[j] >= b
                })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    /// Uniform noise in [−1, 1] from a hash of (a, b): deterministic and uncorrelated.
    fn hash_noise(a: u64, b: u64) -> f64 {
        let mut x = a.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ b.wrapping_mul(0xC2B2_AE3D_27D4_EB4F);
        x ^= x >> 31;
        x = x.wrapping_mul(0xBF58_476D_1CE4_E5B9);
        x ^= x >> 29;
        (x >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }

    /// An annulus of 6 rings from 12 mm with log-spiral ridges of γ̇ (height 2): for
    /// each (sense, θ0) a Gaussian ridge of width `w` (rad) at angle `alpha` to the
    /// radius, on 1 ± `noise` white noise.
    fn synthetic(bands: &[(f64, f64)], alpha_deg: f64, w: f64, noise: f64) -> Annulus {
        let (n, rows, r0, dr) = (180, 6, 12e-3, 0.48e-3);
        let radii: Vec<f64> = (0..rows).map(|k| r0 + (k as f64 + 0.5) * dr).collect();
        let tan = alpha_deg.to_radians().tan();
        let mut values = Vec::new();
        for r in &radii {
            for j in 0..n {
                let th = (j as f64 + 0.5) * TAU / n as f64;
                let mut v = 1.0 + noise * hash_noise(j as u64, r.to_bits());
                for &(sense, t0) in bands {
                    let c = t0 + sense * tan * (r / radii[0]).ln();
                    let d = (th - c + 0.5 * TAU).rem_euclid(TAU) - 0.5 * TAU;
                    v += 2.0 * (-0.5 * d * d / (w * w)).exp();
                }
                values.push(v);
            }
        }
        Annulus {
            radii,
            n_theta: n,
            values,
        }
    }

    #[test]
    fn six_groups_of_crossing_bands() {
        // Six groups (one per hexagon edge), each with two clockwise and two
        // anticlockwise bands 4° apart; 45° to the radius.
        let mut bands = Vec::new();
        for g in 0..6 {
            let c = TAU * g as f64 / 6.0 + 0.5;
            for (k, off) in [-6.0f64, -2.0, 2.0, 6.0].iter().enumerate() {
                let sense = if k % 2 == 0 { -1.0 } else { 1.0 };
                bands.push((sense, c + off.to_radians()));
            }
        }
        let a = synthetic(&bands, 45.0, 0.012, 0.3);
        let b = a.detect(&ShearBandSpec::default(), (0.0, 1.0));
        assert_eq!(b.clockwise.count, 12, "{b:?}");
        assert_eq!(b.anticlockwise.count, 12, "{b:?}");
        assert!((b.clockwise.angle - 45.0).abs() <= 5.0, "{b:?}");
        assert!((b.anticlockwise.angle - 45.0).abs() <= 5.0, "{b:?}");
        assert!(!b.clockwise.at_search_limit && !b.anticlockwise.at_search_limit);
        assert_eq!(b.groups, 6, "{b:?}");
        assert_eq!(b.dominant_mode, Some(6), "{b:?}");
    }

    #[test]
    fn evenly_spread_bands_are_many_groups() {
        // 20 clockwise and 20 anticlockwise bands evenly around, 40° to the radius, in
        // noise of ±0.6 against band peaks of 2 (with ±1 about a fifth are missed).
        let mut bands = Vec::new();
        for k in 0..20 {
            let t = TAU * k as f64 / 20.0;
            bands.push((-1.0, t));
            bands.push((1.0, t + TAU / 40.0));
        }
        let a = synthetic(&bands, 40.0, 0.012, 0.6);
        let b = a.detect(&ShearBandSpec::default(), (0.0, 1.0));
        assert_eq!(b.clockwise.count, 20, "{b:?}");
        assert_eq!(b.anticlockwise.count, 20, "{b:?}");
        assert!((b.clockwise.angle - 40.0).abs() <= 5.0);
        assert!(b.groups >= 20, "{b:?}");
    }

    /// Through the public API: grains on a lattice ring (10–15 mm, d0 0.1 mm, bins of
    /// 0.5 mm × 2°) whose radial speed has narrow ridges (σ = 1.2°) along log spirals at
    /// 45° to the radius, one per (sense, root angle) of `bands` (velocity petals,
    /// Fig. 12): γ̇ is high along the ridges.
    fn bands_in_a_particle_velocity_field(bands: &[(f64, f64)]) -> ShearBands {
        use crate::dispersal::bands::BandSpec;
        use crate::dispersal::synthetic::LatticeRing;
        use crate::dispersal::{coarse_grain, BandMap, Kernel, ParticleSet, PolarGrid};
        use glam::DVec2;
        let ring = LatticeRing::new(DVec2::ZERO, 10e-3, 15e-3, 0.1e-3, 0.097e-3, 0.3, 0.02, 9);
        let sigma = 1.2f64.to_radians();
        let vel: Vec<DVec2> = ring
            .pos
            .iter()
            .map(|x| {
                let (r, th) = (x.length(), x.y.atan2(x.x));
                let mut v = 300.0;
                for &(sense, t0) in bands {
                    let c = t0 + sense * (r / 10e-3).ln();
                    let d = (th - c + 0.5 * TAU).rem_euclid(TAU) - 0.5 * TAU;
                    v += 40.0 * (-0.5 * d * d / (sigma * sigma)).exp();
                }
                v * x.normalize()
            })
            .collect();
        let set = ParticleSet::new(&ring.pos, &vel, &ring.radius, &ring.mass, &ring.id).unwrap();
        let grid = PolarGrid::covering(DVec2::ZERO, 0.0, 0.5e-3, 180, &set).unwrap();
        let f = coarse_grain(&grid, &set, None, Kernel::Hat { half_width: 0.1e-3 });
        let map = BandMap::new(&f, &BandSpec::default());
        shear_bands(&f, &map, &ShearBandSpec::default()).unwrap()
    }

    /// Ten clockwise and ten anticlockwise bands evenly round (an amorphous ring's
    /// pattern): all found, at 45°, and each pair its own group.
    #[test]
    fn bands_from_a_particle_velocity_field() {
        let bands: Vec<(f64, f64)> = (0..10)
            .flat_map(|b| {
                [
                    (-1.0, TAU * b as f64 / 10.0),
                    (1.0, TAU * (b as f64 + 0.5) / 10.0),
                ]
            })
            .collect();
        let b = bands_in_a_particle_velocity_field(&bands);
        assert_eq!(
            (b.clockwise.count, b.anticlockwise.count),
            (10, 10),
            "{b:?}"
        );
        assert!((b.clockwise.angle - 45.0).abs() <= 5.0, "{b:?}");
        assert!((b.anticlockwise.angle - 45.0).abs() <= 5.0, "{b:?}");
        assert!(
            b.annulus.0 >= 10e-3 && b.annulus.1 > b.annulus.0 + 1e-3,
            "{b:?}"
        );
        assert!(b.groups >= 10, "{b:?}");
    }

    /// Six groups of two clockwise and two anticlockwise bands 5° apart, one group per
    /// edge of a hexagon (an ordered ring's pattern, Fig. 11a): six groups.
    #[test]
    fn six_groups_from_a_particle_velocity_field() {
        let bands: Vec<(f64, f64)> = (0..6)
            .flat_map(|g| {
                let c = TAU * g as f64 / 6.0 + 0.2;
                [(-1.0, -7.5), (1.0, -2.5), (-1.0, 2.5), (1.0, 7.5)]
                    .map(|(sense, off): (f64, f64)| (sense, c + off.to_radians()))
            })
            .collect();
        let b = bands_in_a_particle_velocity_field(&bands);
        assert_eq!(b.groups, 6, "{b:?}");
        assert_eq!(b.dominant_mode, Some(6), "{b:?}");
        assert!(
            b.clockwise.count >= 6 && b.anticlockwise.count >= 6,
            "{b:?}"
        );
    }

    /// Radial streaks (γ̇ varying with θ only) are not spirals: they come out at the
    /// low end of the search, flagged.
    #[test]
    fn radial_streaks_are_flagged() {
        let mut a = synthetic(&[], 45.0, 0.01, 0.0);
        let n = a.n_theta;
        for (k, v) in a.values.iter_mut().enumerate() {
            *v = 1.0 + (6.0 * TAU * (k % n) as f64 / n as f64).sin().abs();
        }
        let b = a.detect(&ShearBandSpec::default(), (0.0, 1.0));
        assert!(
            b.clockwise.at_search_limit && b.clockwise.angle == 15.0,
            "{b:?}"
        );
    }

    #[test]
    fn one_sense_only() {
        let bands: Vec<(f64, f64)> = (0..8).map(|k| (-1.0, TAU * k as f64 / 8.0)).collect();
        let b = synthetic(&bands, 60.0, 0.015, 0.3).detect(&ShearBandSpec::default(), (0.0, 1.0));
        assert_eq!(b.clockwise.count, 8, "{b:?}");
        assert!((b.clockwise.angle - 60.0).abs() <= 5.0, "{b:?}");
        assert!(
            b.anticlockwise.contrast < 0.6 * b.clockwise.contrast,
            "{b:?}"
        );
    }

    #[test]
    fn no_bands_in_a_flat_field_and_settings_are_checked() {
        // Noise alone: (almost) no bands.
        let a = synthetic(&[], 45.0, 0.01, 0.5);
        let b = a.detect(&ShearBandSpec::default(), (0.0, 1.0));
        assert!(b.clockwise.count + b.anticlockwise.count <= 2, "{b:?}");
        let mut flat = a;
        flat.values.iter_mut().for_each(|v| *v = 1.0);
        let b = flat.detect(&ShearBandSpec::default(), (0.0, 1.0));
        assert_eq!(
            (b.clockwise.count, b.anticlockwise.count, b.groups),
            (0, 0, 0)
        );
        assert!(ShearBandSpec::default().validate("s").is_ok());
        let bad = ShearBandSpec {
            max_angle: 95.0,
            ..ShearBandSpec::default()
        };
        assert!(bad.validate("s").is_err());
    }
}
