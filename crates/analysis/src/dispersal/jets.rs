//! Jets: spikes on the outer envelope of the ring at a late time, each traced back by
//! grain identity to the cluster it came from at an earlier time (xue-2019 §5.3,
//! Fig. 9: the agglomerates of the spall layer at 20 µs become the jets at 100 µs).
//!
//! 1. **Envelope.** The circle is cut into `sectors`; a sector's envelope radius is the
//!    outer extent |x − c| + r of its `tip_grains`-th farthest grain, so a lone grain
//!    does not make a spike.
//! 2. **Baseline.** The running median of the envelope over `baseline_window` degrees:
//!    the ring's overall (possibly hexagonal) outline without its spikes.
//! 3. **Spikes.** Local maxima of envelope − baseline over ±`min_separation` sectors
//!    standing higher than both `min_height` grain diameters and `noise_factor` times
//!    the residual's robust noise (1.4826 × its median absolute deviation). A spike's
//!    width spans the sectors around it where the residual stays above half its height.
//! 4. **Grains.** A jet's grains are those in its sectors reaching beyond the
//!    baseline plus half the spike's height: the jet itself, not the ring under it.
//! 5. **Origin.** [`trace_jets`] finds those grains by id in an earlier frame and
//!    reports where they were: their centroid (radius and angle), radial and angular
//!    spread, and, given that frame's layers, how many were in the band, in transition
//!    or in the spall.

use super::bands::Layer;
use super::input::{at_least, positive, InputError, ParticleSet};
use glam::DVec2;
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

/// Settings of the jet detection.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct JetSpec {
    /// Sectors of the envelope.
    pub sectors: usize,
    /// The envelope follows this many of a sector's farthest grains.
    pub tip_grains: usize,
    /// Width of the running-median baseline (degrees).
    pub baseline_window: f64,
    /// Least spike height, in mean grain diameters.
    pub min_height: f64,
    /// Least spike height, in units of the residual's robust noise.
    pub noise_factor: f64,
    /// Closest two spikes may be, in sectors.
    pub min_separation: usize,
}

impl Default for JetSpec {
    fn default() -> Self {
        JetSpec {
            sectors: 720,
            tip_grains: 3,
            baseline_window: 15.0,
            min_height: 5.0,
            noise_factor: 3.0,
            min_separation: 2,
        }
    }
}

impl JetSpec {
    /// Checks the settings; `key` names the section in messages.
    pub fn validate(&self, key: &str) -> Result<(), InputError> {
        let k = |f: &str| format!("{key}.{f}");
        if self.sectors < 16 {
            return Err(InputError::new(
                k("sectors"),
                self.sectors,
                "must be at least 16",
            ));
        }
        if self.tip_grains == 0 {
            return Err(InputError::new(k("tip_grains"), 0, "must be at least 1"));
        }
        if !(self.baseline_window > 0.0 && self.baseline_window <= 180.0) {
            return Err(InputError::new(
                k("baseline_window"),
                self.baseline_window,
                "must lie in (0, 180] degrees",
            ));
        }
        positive(&k("min_height"), self.min_height)?;
        positive(&k("noise_factor"), self.noise_factor)?;
        at_least(&k("min_separation"), self.min_separation, 1).map(|_| ())
    }
}

/// One spike of the envelope.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Jet {
    /// Angle of its tip (rad, counter-clockwise from +x).
    pub theta: f64,
    /// Envelope radius at the tip (m).
    pub tip_radius: f64,
    /// Height above the baseline (m).
    pub height: f64,
    /// Angular width at half height (rad).
    pub width: f64,
    /// Ids of its grains.
    pub grains: Vec<u32>,
}

/// The jets of one frame.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Jets {
    /// The spikes, by angle.
    pub jets: Vec<Jet>,
    /// Envelope radius per sector (m); NaN for an empty sector.
    pub envelope: Vec<f64>,
    /// Baseline per sector (m).
    pub baseline: Vec<f64>,
    /// Height a spike had to exceed (m).
    pub threshold: f64,
}

/// Finds the spikes on the outer envelope of `particles` about `centre`; `d0` is the
/// mean grain diameter.
pub fn jets(centre: DVec2, particles: &ParticleSet, d0: f64, spec: &JetSpec) -> Jets {
    let n = spec.sectors;
    let sector = |x: DVec2| {
        let d = x - centre;
        ((d.y.atan2(d.x).rem_euclid(TAU) / TAU * n as f64) as usize).min(n - 1)
    };
    let sec: Vec<usize> = particles.pos.iter().map(|x| sector(*x)).collect();
    let ext: Vec<f64> = (0..particles.len())
        .map(|p| (particles.pos[p] - centre).length() + particles.radius[p])
        .collect();
    // The tip_grains farthest extents of each sector, kept sorted (small k).
    let k = spec.tip_grains;
    let mut tips: Vec<Vec<f64>> = vec![Vec::with_capacity(k + 1); n];
    for p in 0..particles.len() {
        let t = &mut tips[sec[p]];
        let e = ext[p];
        if t.len() < k || e > t[t.len() - 1] {
            let at = t.partition_point(|&x| x >= e);
            t.insert(at, e);
            t.truncate(k);
        }
    }
    let envelope: Vec<f64> = tips
        .iter()
        .map(|t| t.last().copied().unwrap_or(f64::NAN))
        .collect();
    let half = ((spec.baseline_window / 360.0 * n as f64 / 2.0).round() as usize).clamp(1, n / 2);
    let baseline: Vec<f64> = (0..n)
        .map(|j| {
            let mut w: Vec<f64> = (0..=2 * half)
                .map(|d| envelope[(j + n + d - half) % n])
                .filter(|x| x.is_finite())
                .collect();
            median(&mut w)
        })
        .collect();
    let residual: Vec<f64> = envelope
        .iter()
        .zip(&baseline)
        .map(|(e, b)| if e.is_finite() { e - b } else { f64::NAN })
        .collect();
    let mut r: Vec<f64> = residual.iter().copied().filter(|x| x.is_finite()).collect();
    let m = median(&mut r);
    let mut dev: Vec<f64> = r.iter().map(|x| (x - m).abs()).collect();
    let noise = 1.4826 * median(&mut dev);
    let threshold = (spec.min_height * d0).max(spec.noise_factor * noise);
    let sep = spec.min_separation.min(n / 2);
    let res = |j: usize| residual[j % n];
    let dt = TAU / n as f64;
    let mut out = Vec::new();
    for j in 0..n {
        let h = res(j);
        if h.is_nan() || h < threshold {
            continue;
        }
        let is_peak = (1..=sep).all(|d| {
            let (a, b) = (res(j + d), res(j + n - d));
            (a.is_nan() || a < h) && (b.is_nan() || h >= b)
        });
        if !is_peak {
            continue;
        }
        let mut lo = 0;
        while lo + 1 < n / 2 && res(j + n - lo - 1) > 0.5 * h {
            lo += 1;
        }
        let mut hi = 0;
        while hi + 1 < n / 2 && res(j + hi + 1) > 0.5 * h {
            hi += 1;
        }
        let in_jet = |s: usize| {
            let off = (s + n - j) % n;
            off <= hi || n - off <= lo
        };
        let grains = (0..particles.len())
            .filter(|&p| in_jet(sec[p]) && ext[p] > baseline[sec[p]] + 0.5 * h)
            .map(|p| particles.id[p])
            .collect();
        out.push(Jet {
            theta: (j as f64 + 0.5) * dt,
            tip_radius: envelope[j],
            height: h,
            width: (lo + hi + 1) as f64 * dt,
            grains,
        });
    }
    Jets {
        jets: out,
        envelope,
        baseline,
        threshold,
    }
}

/// Where a jet's grains were at an earlier time.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct JetOrigin {
    /// Grains of the jet found in the earlier frame.
    pub found: usize,
    /// Distance of their centroid from the centre (m).
    pub radius: f64,
    /// Angle of their centroid (rad), a circular mean.
    pub theta: f64,
    /// Standard deviation of their distances from the centre (m).
    pub radial_spread: f64,
    /// Circular standard deviation of their angles (rad).
    pub angular_spread: f64,
    /// How many were in the band, in transition and in the spall, when the earlier
    /// frame's layers are given.
    pub layers: Option<[usize; 3]>,
}

/// Traces each jet of `jets` back to `earlier` (a frame of the same grains) by id;
/// `layers` are the earlier frame's grain layers, if known.
pub fn trace_jets(
    jets: &Jets,
    centre: DVec2,
    earlier: &ParticleSet,
    layers: Option<&[Layer]>,
) -> Vec<JetOrigin> {
    let mut by_id: Vec<(u32, u32)> = earlier
        .id
        .iter()
        .enumerate()
        .map(|(p, &id)| (id, p as u32))
        .collect();
    by_id.sort_unstable();
    jets.jets
        .iter()
        .map(|jet| {
            let found: Vec<usize> = jet
                .grains
                .iter()
                .filter_map(|id| {
                    by_id
                        .binary_search_by_key(id, |e| e.0)
                        .ok()
                        .map(|k| by_id[k].1 as usize)
                })
                .collect();
            let n = found.len().max(1) as f64;
            let rel: Vec<DVec2> = found.iter().map(|&p| earlier.pos[p] - centre).collect();
            let rs: Vec<f64> = rel.iter().map(|d| d.length()).collect();
            let unit: DVec2 = rel
                .iter()
                .map(|d| d.try_normalize().unwrap_or(DVec2::ZERO))
                .sum::<DVec2>()
                / n;
            let r_mean = rs.iter().sum::<f64>() / n;
            let r_var = rs.iter().map(|r| (r - r_mean).powi(2)).sum::<f64>() / n;
            let resultant = unit.length().clamp(1e-300, 1.0);
            JetOrigin {
                found: found.len(),
                radius: r_mean,
                theta: unit.y.atan2(unit.x).rem_euclid(TAU),
                radial_spread: r_var.sqrt(),
                angular_spread: (-2.0 * resultant.ln()).sqrt(),
                layers: layers.map(|l| {
                    let mut c = [0usize; 3];
                    for &p in &found {
                        match l.get(p) {
                            Some(Layer::Band) => c[0] += 1,
                            Some(Layer::Transition) => c[1] += 1,
                            Some(Layer::Spall) => c[2] += 1,
                            _ => {}
                        }
                    }
                    c
                }),
            }
        })
        .collect()
}

/// Median of `v` (reorders it); NaN when empty.
fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    let k = v.len() / 2;
    *v.select_nth_unstable_by(k, |a, b| a.total_cmp(b)).1
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dispersal::synthetic::LatticeRing;

    /// A ring 40–42 mm with 12 radial spikes of grains 3 mm long at known angles; the
    /// earlier frame has every grain at half its radius and the same angle.
    #[test]
    fn spikes_are_found_and_traced_back() {
        let d0 = 0.1e-3;
        let c = DVec2::new(2e-3, -1e-3);
        let ring = LatticeRing::new(c, 40e-3, 42e-3, d0, d0, 0.0, 0.05, 4);
        let mut pos = ring.pos.clone();
        let mut radius = ring.radius.clone();
        let angles: Vec<f64> = (0..12)
            .map(|k| 0.2 + TAU * k as f64 / 12.0 + 0.05 * (k % 3) as f64)
            .collect();
        for &a in &angles {
            for s in 0..30 {
                pos.push(c + (42e-3 + (s as f64 + 0.5) * d0) * DVec2::from_angle(a));
                radius.push(0.5 * d0);
            }
        }
        let n = pos.len();
        let mass = vec![1e-8; n];
        let vel = vec![DVec2::ZERO; n];
        let id: Vec<u32> = (0..n as u32).rev().collect();
        let late = ParticleSet::new(&pos, &vel, &radius, &mass, &id).unwrap();
        let j = jets(c, &late, d0, &JetSpec::default());
        assert_eq!(
            j.jets.len(),
            12,
            "{:?}",
            j.jets.iter().map(|x| x.theta).collect::<Vec<_>>()
        );
        for (jet, a) in j.jets.iter().zip(&angles) {
            assert!(
                (jet.theta - a).abs() < 2.0 * TAU / 720.0,
                "{} vs {a}",
                jet.theta
            );
            assert!((jet.height - 3e-3).abs() < 0.3e-3, "{}", jet.height);
            assert!(
                jet.grains.len() >= 14 && jet.grains.len() <= 20,
                "{}",
                jet.grains.len()
            );
        }
        // Earlier: same ids, half the distance from the centre, reversed order.
        let early_pos: Vec<DVec2> = pos.iter().rev().map(|x| c + 0.5 * (*x - c)).collect();
        let early_id: Vec<u32> = id.iter().rev().copied().collect();
        let early = ParticleSet::new(&early_pos, &vel, &radius, &mass, &early_id).unwrap();
        let layers = vec![Layer::Spall; n];
        let o = trace_jets(&j, c, &early, Some(&layers));
        for ((origin, jet), a) in o.iter().zip(&j.jets).zip(&angles) {
            assert_eq!(origin.found, jet.grains.len());
            assert!((origin.theta - a).abs() < 1e-9, "{} vs {a}", origin.theta);
            assert!(
                origin.radius > 21.0e-3 && origin.radius < 22.5e-3,
                "{}",
                origin.radius
            );
            assert!(origin.angular_spread < 1e-6);
            assert_eq!(origin.layers, Some([0, 0, origin.found]));
        }
    }

    #[test]
    fn a_smooth_ring_has_no_jets() {
        let ring = LatticeRing::new(DVec2::ZERO, 40e-3, 42e-3, 0.1e-3, 0.1e-3, 0.0, 0.1, 5);
        let vel = vec![DVec2::ZERO; ring.pos.len()];
        let set = ParticleSet::new(&ring.pos, &vel, &ring.radius, &ring.mass, &ring.id).unwrap();
        let j = jets(DVec2::ZERO, &set, 0.1e-3, &JetSpec::default());
        assert!(j.jets.is_empty(), "{:?}", j.jets);
        assert!(j.envelope.iter().all(|e| (e - 42e-3).abs() < 0.2e-3));
        assert!(JetSpec::default().validate("jets").is_ok());
        let bad = JetSpec {
            sectors: 4,
            ..JetSpec::default()
        };
        assert_eq!(bad.validate("jets").unwrap_err().key, "jets.sectors");
    }
}
