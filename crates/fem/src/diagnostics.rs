//! Read-only measurements of a charge: the energy ledger, burn progress, fronts, and the
//! detonation-arrival profile the `charge_only` check compares with r/D_CJ.

use crate::setup::FemSetup;
use crate::state::Charge;
use glam::DVec2;

/// The charge's energies per unit thickness (J/m).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Energies {
    /// Kinetic energy of the nodes.
    pub kinetic: f64,
    /// Internal energy Σ m(e + λQ): mechanical plus the chemical energy released.
    pub internal: f64,
    /// Chemical energy not yet released, Σ m(1 − λ)Q.
    pub chemical: f64,
    /// Work done by external (coupling) forces so far.
    pub work_external: f64,
    /// Work done by damping so far (≤ 0).
    pub work_damping: f64,
}

impl Energies {
    /// Kinetic + internal + chemical.
    pub fn total(&self) -> f64 {
        self.kinetic + self.internal + self.chemical
    }

    /// What the total should be: the initial total plus the work done on the charge.
    pub fn balance(&self, initial_total: f64) -> f64 {
        self.total() - initial_total - self.work_external - self.work_damping
    }
}

/// Measures the energies.
pub fn energies(setup: &FemSetup, c: &Charge) -> Energies {
    let q = setup.explosive.specific_energy();
    let n = &c.nodes;
    let kinetic = n
        .mass
        .iter()
        .zip(&n.vel)
        .map(|(m, v)| 0.5 * m * v.length_squared())
        .sum();
    let el = &c.elems;
    let mut internal = 0.0;
    let mut chemical = 0.0;
    for e in 0..el.mass.len() {
        internal += el.mass[e] * (el.energy[e] + el.lambda[e] * q);
        chemical += el.mass[e] * (1.0 - el.lambda[e]) * q;
    }
    Energies {
        kinetic,
        internal,
        chemical,
        work_external: c.work_external,
        work_damping: c.work_damping,
    }
}

/// Burn progress and front positions.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Fronts {
    /// Mass fraction burnt, Σ mλ / Σ m.
    pub burnt: f64,
    /// Largest EOS pressure (Pa).
    pub max_pressure: f64,
    /// Largest initial distance from the detonation point of an element that is at
    /// least half burnt (m): the burn front.
    pub burn_front: f64,
    /// Mean distance of the boundary nodes from the charge's centre of mass (m).
    pub boundary_radius: f64,
    /// Mean outward speed of the boundary nodes (m/s).
    pub boundary_speed: f64,
    /// Smallest relative volume of any element.
    pub min_rel_volume: f64,
}

/// Measures the fronts.
pub fn fronts(c: &Charge) -> Fronts {
    let el = &c.elems;
    let total: f64 = el.mass.iter().sum();
    let burnt = el
        .mass
        .iter()
        .zip(&el.lambda)
        .map(|(m, l)| m * l)
        .sum::<f64>()
        / total;
    let max_pressure = el
        .pressure
        .iter()
        .copied()
        .fold(f64::NEG_INFINITY, f64::max);
    let burn_front = el
        .lambda
        .iter()
        .zip(&el.r_light)
        .filter(|(l, _)| **l >= 0.5)
        .map(|(_, r)| *r)
        .fold(0.0, f64::max);
    let min_rel_volume = el
        .area
        .iter()
        .zip(&el.area_ref)
        .map(|(a, a0)| a / a0)
        .fold(f64::INFINITY, f64::min);
    let n = &c.nodes;
    let mtot: f64 = n.mass.iter().sum();
    let centre = n
        .pos
        .iter()
        .zip(&n.mass)
        .map(|(x, m)| *x * *m)
        .sum::<DVec2>()
        / mtot;
    let (mut r, mut s) = (0.0, 0.0);
    for e in &c.boundary {
        let i = e[0] as usize;
        let d = n.pos[i] - centre;
        let len = d.length();
        r += len;
        if len > 0.0 {
            s += n.vel[i].dot(d / len);
        }
    }
    let nb = c.boundary.len().max(1) as f64;
    Fronts {
        burnt,
        max_pressure,
        burn_front,
        boundary_radius: r / nb,
        boundary_speed: s / nb,
        min_rel_volume,
    }
}

/// Mean arrival time of the half-CJ-pressure front in one radial bin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArrivalBin {
    /// Mean initial distance from the detonation point (m).
    pub r: f64,
    /// Mean arrival time (s).
    pub t: f64,
    /// Arrival expected from the lighting law, r/D_CJ + t0 (s).
    pub expected: f64,
    /// Elements in the bin that the front reached.
    pub reached: usize,
    /// Elements in the bin.
    pub elements: usize,
}

/// Bins the elements whose initial centroid lies between `r_lo` and `r_hi` from the
/// detonation point into `bins` rings and averages their arrival times.
pub fn arrival_profile(
    setup: &FemSetup,
    c: &Charge,
    r_lo: f64,
    r_hi: f64,
    bins: usize,
) -> Vec<ArrivalBin> {
    let d = setup.explosive.detonation_velocity;
    let width = (r_hi - r_lo) / bins as f64;
    let mut acc = vec![(0.0, 0.0, 0usize, 0usize); bins];
    let el = &c.elems;
    for e in 0..el.mass.len() {
        let r = el.r_light[e];
        if r < r_lo || r >= r_hi {
            continue;
        }
        let b = (((r - r_lo) / width) as usize).min(bins - 1);
        acc[b].3 += 1;
        if el.arrival[e].is_finite() {
            acc[b].0 += r;
            acc[b].1 += el.arrival[e];
            acc[b].2 += 1;
        }
    }
    acc.into_iter()
        .filter(|a| a.3 > 0)
        .map(|(rs, ts, n, all)| {
            let k = n.max(1) as f64;
            let r = if n > 0 { rs / k } else { f64::NAN };
            ArrivalBin {
                r,
                t: if n > 0 { ts / k } else { f64::NAN },
                expected: r / d + setup.burn.time,
                reached: n,
                elements: all,
            }
        })
        .collect()
}

/// Largest relative deviation |t − t_expected| / (t_expected − t0) over the bins, and the
/// front speed from a least-squares fit of r against t. NaN when a bin was not reached.
pub fn arrival_error(setup: &FemSetup, bins: &[ArrivalBin]) -> (f64, f64) {
    let mut worst: f64 = 0.0;
    let (mut st, mut sr, mut stt, mut str_, mut n) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for b in bins {
        if b.reached < b.elements {
            return (f64::NAN, f64::NAN);
        }
        let travel = b.expected - setup.burn.time;
        worst = worst.max((b.t - b.expected).abs() / travel);
        st += b.t;
        sr += b.r;
        stt += b.t * b.t;
        str_ += b.t * b.r;
        n += 1.0;
    }
    let speed = (n * str_ - st * sr) / (n * stt - st * st);
    (worst, speed)
}

/// A fingerprint of the charge: FNV-1a over every node's position and velocity and
/// every element's mass, specific energy, burn fraction, pressure, viscous pressure
/// and deviatoric stress. Equal hashes mean bitwise-equal runs, whatever the thread count.
pub fn state_hash(c: &Charge) -> u64 {
    let mut h = grains_core::hash::Fnv1a::default();
    for (x, v) in c.nodes.pos.iter().zip(&c.nodes.vel) {
        for w in [x.x, x.y, v.x, v.y] {
            h.f64(w);
        }
    }
    let e = &c.elems;
    for k in 0..e.mass.len() {
        for w in [e.mass[k], e.energy[k], e.lambda[k], e.pressure[k], e.q[k]] {
            h.f64(w);
        }
        for w in e.dev[k] {
            h.f64(w);
        }
    }
    h.finish()
}
