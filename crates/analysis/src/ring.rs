//! Measures of the dispersing ring (xue-2019 §5.1, Figs. 6a and 14): its inner and
//! outer radius, the pressure front, and the split into an inner compact band and an
//! outer spall layer.
//!
//! * Inner/outer radius: the 0.1 % and 99.9 % quantiles of |x − c| − r and |x − c| + r,
//!   so a few stray grains do not set them.
//! * Local packing fraction: polar bins as in the paper — `sectors` angular sectors and
//!   radial bins `radial_bin` mean diameters wide, starting in each sector at its inner
//!   envelope; disks are counted whole by their centres.
//! * Compact band: in each sector (packing fractions smoothed over it and its two
//!   neighbours), the bins from the inner envelope through the first run of bins at or
//!   above `band_fraction` — single-bin dips do not end it — whose outer edge is R_comp;
//!   the particles there form the band, the rest the spall layer.
//! * Pressure front R_p: per particle a mean contact stress p = Σ F_n / (2π r) (the
//!   trace of Love's average over the disk); in each sector the outer edge of the
//!   outermost bin where at least half the particles exceed `stressed_pressure`.
//!
//! Every figure is a mean over the sectors that hold particles.

// Per-particle passes index several per-field arrays with one particle index.
#![allow(clippy::needless_range_loop)]

use glam::DVec2;
use std::f64::consts::{PI, TAU};

/// The packing fraction at or above which a bin belongs to the inner compact band:
/// xue-2019's "inner compact band with packing fraction φ ≥ 0.84" (§5.1, Fig. 6b), about
/// the densest random packing, on its polar bins of dr = 5 d0 by dθ = π/90 (§4.2). The
/// run's band rule (`[analysis] band_fraction`) and the dispersal analysis
/// (`[analysis.dispersal.band]`) both default to it.
pub const BAND_PHI: f64 = 0.84;

/// How the ring's layers are told apart.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rule {
    /// Local packing fraction at or above which particles belong to the compact band.
    pub band_fraction: f64,
    /// Radial bin width in mean diameters.
    pub radial_bin: f64,
    /// Angular sectors; `None`: 180 (dθ = π/90), or fewer so that a sector's arc at the
    /// inner radius spans at least 4 mean diameters.
    pub sectors: Option<usize>,
    /// Mean contact stress (Pa) above which a particle counts as stressed.
    pub stressed_pressure: f64,
}

/// The particles of a ring (SI, per unit thickness).
#[derive(Clone, Copy, Debug)]
pub struct Disks<'a> {
    /// Centres.
    pub pos: &'a [DVec2],
    /// Velocities.
    pub vel: &'a [DVec2],
    /// Radii.
    pub radius: &'a [f64],
    /// Masses.
    pub mass: &'a [f64],
}

/// One measurement of the ring.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RingFigures {
    /// Inner radius (m).
    pub inner: f64,
    /// Outer radius (m).
    pub outer: f64,
    /// Pressure front (m).
    pub pressure_front: f64,
    /// Outer edge of the compact band, R_comp (m).
    pub band_outer: f64,
    /// Mean radial velocity of the band (m/s).
    pub band_velocity: f64,
    /// Mean radial velocity of the spall layer (m/s); NaN when it is empty.
    pub spall_velocity: f64,
    /// Number fraction of particles in the band.
    pub band_fraction: f64,
    /// Mean radial velocity of all particles (m/s).
    pub mean_velocity: f64,
    /// Kinetic energy of the particles (J/m).
    pub kinetic: f64,
}

/// The number of angular sectors: as given, else 180 or as many as keep each sector's
/// arc at the inner radius `r_in` at least 4 mean diameters long.
pub fn sectors(spec: &Rule, r_in: f64, mean_d: f64) -> usize {
    spec.sectors
        .unwrap_or_else(|| ((TAU * r_in / (4.0 * mean_d)).floor() as usize).clamp(8, 180))
}

/// Measures the ring about `centre` with `ns` sectors; `pressure` is each particle's
/// contact stress.
pub fn measure(
    spec: &Rule,
    ns: usize,
    p: Disks,
    centre: DVec2,
    mean_d: f64,
    pressure: &[f64],
) -> RingFigures {
    let n = p.pos.len();
    if n == 0 {
        return RingFigures::default();
    }
    let rho: Vec<f64> = p.pos.iter().map(|x| (*x - centre).length()).collect();
    let ur: Vec<f64> = (0..n)
        .map(|i| {
            let d = p.pos[i] - centre;
            if rho[i] > 0.0 {
                p.vel[i].dot(d) / rho[i]
            } else {
                0.0
            }
        })
        .collect();
    let mut lo: Vec<f64> = (0..n).map(|i| rho[i] - p.radius[i]).collect();
    let mut hi: Vec<f64> = (0..n).map(|i| rho[i] + p.radius[i]).collect();
    let inner = quantile(&mut lo, 0.001);
    let outer = quantile(&mut hi, 0.999);

    let sector: Vec<usize> = p
        .pos
        .iter()
        .map(|x| {
            let d = *x - centre;
            let a = d.y.atan2(d.x).rem_euclid(TAU);
            ((a / TAU * ns as f64) as usize).min(ns - 1)
        })
        .collect();
    let mut envelope = vec![f64::INFINITY; ns];
    for i in 0..n {
        envelope[sector[i]] = envelope[sector[i]].min(rho[i] - p.radius[i]);
    }
    let dr = spec.radial_bin * mean_d;
    let bin_of = |i: usize| ((rho[i] - envelope[sector[i]]).max(0.0) / dr) as usize;
    let nbins = (0..n).map(bin_of).max().unwrap_or(0) + 1;
    let mut area = vec![0.0; ns * nbins];
    let mut count = vec![0u32; ns * nbins];
    let mut stressed = vec![0u32; ns * nbins];
    for i in 0..n {
        let k = sector[i] * nbins + bin_of(i);
        area[k] += PI * p.radius[i] * p.radius[i];
        count[k] += 1;
        if pressure.get(i).is_some_and(|&s| s > spec.stressed_pressure) {
            stressed[k] += 1;
        }
    }
    let dtheta = TAU / ns as f64;
    let mut band_bins = vec![0usize; ns];
    let (mut r_comp, mut r_p, mut occupied) = (0.0, 0.0, 0usize);
    for s in 0..ns {
        if !envelope[s].is_finite() {
            continue;
        }
        occupied += 1;
        let r0 = envelope[s];
        // Packing fraction of bin b, smoothed over this sector and its two neighbours
        // (each with its own inner envelope), so that a bin of a few dozen grains does
        // not flicker across the threshold.
        let phi = |b: usize| {
            let (mut a_disks, mut a_bins) = (0.0, 0.0);
            for t in [(s + ns - 1) % ns, s, (s + 1) % ns] {
                if !envelope[t].is_finite() {
                    continue;
                }
                let (lo, hi) = (
                    envelope[t] + b as f64 * dr,
                    envelope[t] + (b + 1) as f64 * dr,
                );
                a_disks += area[t * nbins + b];
                a_bins += 0.5 * dtheta * (hi * hi - lo * lo);
            }
            a_disks / a_bins
        };
        // Band: from the inner surface through the first run of dense bins; a looser
        // first bin (a lined inner surface) and single-bin dips belong to it.
        let mut k_band = 0;
        let mut k_press = 0;
        let mut b = 0;
        while b < nbins {
            if phi(b) >= spec.band_fraction {
                k_band = b + 1;
            } else if k_band > 0 && !(b + 1 < nbins && phi(b + 1) >= spec.band_fraction) {
                break;
            }
            b += 1;
        }
        for b in 0..nbins {
            let c = count[s * nbins + b];
            if c > 0 && 2 * stressed[s * nbins + b] >= c {
                k_press = b + 1;
            }
        }
        band_bins[s] = k_band;
        r_comp += r0 + k_band as f64 * dr;
        r_p += if k_press > 0 {
            r0 + k_press as f64 * dr
        } else {
            r0
        };
    }
    let occ = occupied.max(1) as f64;
    let (mut vb, mut nb, mut vs, mut nsp, mut vall, mut ke) = (0.0, 0usize, 0.0, 0usize, 0.0, 0.0);
    for i in 0..n {
        vall += ur[i];
        ke += 0.5 * p.mass[i] * p.vel[i].length_squared();
        if bin_of(i) < band_bins[sector[i]] {
            vb += ur[i];
            nb += 1;
        } else {
            vs += ur[i];
            nsp += 1;
        }
    }
    RingFigures {
        inner,
        outer,
        pressure_front: r_p / occ,
        band_outer: r_comp / occ,
        band_velocity: if nb > 0 { vb / nb as f64 } else { f64::NAN },
        spall_velocity: if nsp > 0 { vs / nsp as f64 } else { f64::NAN },
        band_fraction: nb as f64 / n as f64,
        mean_velocity: vall / n as f64,
        kinetic: ke,
    }
}

/// The q-quantile of `v` (reorders it).
fn quantile(v: &mut [f64], q: f64) -> f64 {
    let k = ((v.len() - 1) as f64 * q).round() as usize;
    *v.select_nth_unstable_by(k, |a, b| a.total_cmp(b)).1
}

#[cfg(test)]
mod tests {
    use super::*;

    const RULE: Rule = Rule {
        band_fraction: 0.8,
        radial_bin: 5.0,
        sectors: None,
        stressed_pressure: 5.0e7,
    };

    /// A dense ring of near-equal disks on a triangular lattice between 2 and 3 mm.
    fn ring() -> (Vec<DVec2>, Vec<f64>, f64) {
        let d = 50e-6;
        let (mut pos, mut radius) = (Vec::new(), Vec::new());
        let row = d * 0.5 * 3f64.sqrt();
        let n = (3e-3 / row) as i64 + 1;
        for j in -n..=n {
            let shift = if j.rem_euclid(2) == 1 { 0.5 * d } else { 0.0 };
            for i in -n..=n {
                let x = DVec2::new(i as f64 * d + shift, j as f64 * row);
                let r = 0.5 * d * (0.97 + 0.03 * ((i * 7 + j * 13).rem_euclid(5) as f64 / 5.0));
                if x.length() - r >= 2e-3 && x.length() + r <= 3e-3 {
                    pos.push(x);
                    radius.push(r);
                }
            }
        }
        let mean_d = 2.0 * radius.iter().sum::<f64>() / radius.len() as f64;
        (pos, radius, mean_d)
    }

    fn masses(radius: &[f64]) -> Vec<f64> {
        radius.iter().map(|r| 2560.0 * PI * r * r).collect()
    }

    #[test]
    fn a_dense_ring_is_all_band() {
        let (pos, radius, d) = ring();
        let vel: Vec<DVec2> = pos.iter().map(|x| 100.0 * x.normalize()).collect();
        let mass = masses(&radius);
        let ns = sectors(&RULE, 2e-3, d);
        assert_eq!(ns, (TAU * 2e-3 / (4.0 * d)) as usize);
        let disks = Disks {
            pos: &pos,
            vel: &vel,
            radius: &radius,
            mass: &mass,
        };
        let f = measure(&RULE, ns, disks, DVec2::ZERO, d, &vec![0.0; pos.len()]);
        assert!((f.inner - 2e-3).abs() < 0.03e-3, "{f:?}");
        assert!((f.outer - 3e-3).abs() < 0.03e-3, "{f:?}");
        // All but the outermost, partly filled bin (the outer surface cuts it).
        assert!(f.band_fraction > 0.85, "{f:?}");
        assert!((f.band_velocity - 100.0).abs() < 1e-9);
        assert!((f.band_outer - 3e-3).abs() < 0.15e-3, "{f:?}");
        // Nothing stressed: the front sits at the inner envelope.
        assert!((f.pressure_front - f.inner).abs() < 0.03e-3, "{f:?}");
    }

    #[test]
    fn a_loose_outer_layer_is_spall() {
        let (mut pos, radius, d) = ring();
        let mut vel = vec![DVec2::ZERO; pos.len()];
        // Spread the outer third radially by 2: its packing fraction drops below 0.5.
        for (x, v) in pos.iter_mut().zip(&mut vel) {
            let r = x.length();
            if r > 2.75e-3 {
                let nr = 2.75e-3 + 2.0 * (r - 2.75e-3);
                *x *= nr / r;
                *v = 50.0 * x.normalize();
            } else {
                *v = 200.0 * x.normalize();
            }
        }
        let mass = masses(&radius);
        let ns = sectors(&RULE, 2e-3, d);
        let disks = Disks {
            pos: &pos,
            vel: &vel,
            radius: &radius,
            mass: &mass,
        };
        let f = measure(&RULE, ns, disks, DVec2::ZERO, d, &vec![0.0; pos.len()]);
        assert!(f.band_fraction > 0.5 && f.band_fraction < 0.8, "{f:?}");
        assert!(f.band_velocity > 150.0 && f.spall_velocity < 100.0, "{f:?}");
        assert!(f.band_outer > 2.4e-3 && f.band_outer < 2.9e-3, "{f:?}");
    }
}
