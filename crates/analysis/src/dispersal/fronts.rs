//! Fronts of the dispersing ring over time (xue-2019 §5.1, Fig. 6a).
//!
//! Per frame ([`FrameFronts`]):
//!
//! * R_in, R_out: the 0.1 % and 99.9 % quantiles of |x − c| − r and |x − c| + r over the
//!   grains, so a few stray grains do not set them (as the ring measures of the run).
//! * R_p, the pressure front "delimiting the stressed and stress-free particles": in
//!   each sector, the outer edge of the outermost stressed bin (coarse-grained
//!   pressure above `stressed_pressure`) that is either the sector's first ring with
//!   material or has a stressed ring inside it — an isolated stressed bin out in the
//!   spall (two clusters colliding) is not the front. A sector with no stressed bin has
//!   its front at its inner surface. R_p is the mean over sectors with material;
//!   R_p(θ) is kept for the envelopes of Fig. 13.
//! * R_comp: the compact band's outer edge (φ ≈ 0.84), from [`BandMap`].
//!
//! Over time ([`front_history`]) the pressure front is read the way the paper reads
//! Fig. 6a: it runs out with the primary shock (PSF) until the shock reflects at the
//! outer surface (the first maximum of R_p), runs back in with the rarefaction (RW)
//! until the secondary shock arrests it (the following minimum), then runs out again
//! with the secondary shock (SSF) until it meets the band boundary R_comp. A maximum
//! or minimum counts once R_p has turned back by half a ring width.

use super::bands::BandMap;
use super::fields::PolarFields;
use super::input::{positive, InputError, ParticleSet};
use serde::{Deserialize, Serialize};

/// Settings of the pressure front.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FrontSpec {
    /// Coarse-grained pressure above which a bin is stressed (Pa).
    pub stressed_pressure: f64,
}

impl Default for FrontSpec {
    fn default() -> Self {
        // As the run's ring measures: stressed above 50 MPa.
        FrontSpec {
            stressed_pressure: 5.0e7,
        }
    }
}

impl FrontSpec {
    /// Checks the threshold; `key` names the section in messages.
    pub fn validate(&self, key: &str) -> Result<(), InputError> {
        positive(&format!("{key}.stressed_pressure"), self.stressed_pressure).map(|_| ())
    }
}

/// The fronts of one frame.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FrameFronts {
    /// Time (s).
    pub time: f64,
    /// Inner radius R_in (m).
    pub r_in: f64,
    /// Outer radius R_out (m).
    pub r_out: f64,
    /// Pressure front R_p (m), when the stress is known.
    pub pressure_front: Option<f64>,
    /// R_p(θ) per sector (m); NaN where a sector has no material, empty without stress.
    pub pressure_front_theta: Vec<f64>,
    /// Compact band boundary R_comp (m), when there is a band.
    pub band_outer: Option<f64>,
}

/// Measures the fronts of one frame at `time`.
pub fn frame_fronts(
    time: f64,
    fields: &PolarFields,
    particles: &ParticleSet,
    map: &BandMap,
    spec: &FrontSpec,
) -> FrameFronts {
    let c0 = fields.grid.centre();
    let rho: Vec<f64> = particles.pos.iter().map(|p| (*p - c0).length()).collect();
    let mut lo: Vec<f64> = rho
        .iter()
        .zip(particles.radius)
        .map(|(d, r)| d - r)
        .collect();
    let mut hi: Vec<f64> = rho
        .iter()
        .zip(particles.radius)
        .map(|(d, r)| d + r)
        .collect();
    let (pressure_front, theta) = match fields.pressure() {
        Some(p) => {
            let theta = pressure_front_theta(fields, map, p, spec.stressed_pressure);
            let known: Vec<f64> = theta.iter().copied().filter(|r| r.is_finite()).collect();
            let mean = (!known.is_empty()).then(|| known.iter().sum::<f64>() / known.len() as f64);
            (mean, theta)
        }
        None => (None, Vec::new()),
    };
    FrameFronts {
        time,
        r_in: quantile(&mut lo, 0.001),
        r_out: quantile(&mut hi, 0.999),
        pressure_front,
        pressure_front_theta: theta,
        band_outer: map.mean_outer_radius(),
    }
}

/// R_p(θ) per sector: see the module documentation.
fn pressure_front_theta(
    fields: &PolarFields,
    map: &BandMap,
    p: &[f64],
    threshold: f64,
) -> Vec<f64> {
    let g = &fields.grid;
    (0..g.n_theta())
        .map(|j| {
            let Some(i0) = map.inner_ring[j] else {
                return f64::NAN;
            };
            let stressed = |i: usize| p[g.index(i, j)] > threshold;
            let front = (i0..g.n_r())
                .rev()
                .find(|&i| stressed(i) && (i == i0 || stressed(i - 1)));
            match front {
                Some(i) => g.r_edge(i + 1),
                None => g.r_edge(i0),
            }
        })
        .collect()
}

/// The q-quantile of `v` (reorders it); NaN for an empty slice.
fn quantile(v: &mut [f64], q: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    let k = ((v.len() - 1) as f64 * q).round() as usize;
    *v.select_nth_unstable_by(k, |a, b| a.total_cmp(b)).1
}

/// Which wave the pressure front follows at a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FrontPhase {
    /// Primary shock front, running out.
    PrimaryShock,
    /// Rarefaction wave, running in after the reflection at the outer surface.
    Rarefaction,
    /// Secondary shock front, running out after arresting the rarefaction.
    SecondaryShock,
    /// After the secondary shock has met the band boundary.
    Merged,
}

/// The fronts of a sequence of frames, with the phases of the pressure front.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FrontHistory {
    /// One entry per frame, in time order.
    pub frames: Vec<FrameFronts>,
    /// Phase of the pressure front per frame (None without stress).
    pub phase: Vec<Option<FrontPhase>>,
    /// Reflection of the primary shock at the outer surface (s): the first maximum
    /// of R_p.
    pub reflection: Option<f64>,
    /// Arrest of the rarefaction by the secondary shock (s): the next minimum.
    pub arrest: Option<f64>,
    /// The secondary shock meets the band boundary (s): R_p ≥ R_comp.
    pub meeting: Option<f64>,
}

/// Orders `frames` by time and reads the phases off R_p; `dr` is the ring width, half
/// of which R_p must turn back by for a maximum or minimum to count.
pub fn front_history(mut frames: Vec<FrameFronts>, dr: f64) -> FrontHistory {
    frames.sort_by(|a, b| a.time.total_cmp(&b.time));
    let n = frames.len();
    let tol = 0.5 * dr;
    let rp: Vec<Option<f64>> = frames.iter().map(|f| f.pressure_front).collect();
    let known: Vec<usize> = (0..n).filter(|&k| rp[k].is_some()).collect();
    let at = |k: usize| rp[k].unwrap_or(f64::NAN);
    let mut phase = vec![None; n];

    // First maximum, confirmed once R_p drops by `tol` below it.
    let mut k_max = None;
    let mut best: Option<usize> = None;
    for &k in &known {
        match best {
            Some(b) if at(k) < at(b) - tol => {
                k_max = Some(b);
                break;
            }
            Some(b) if at(k) <= at(b) => {}
            _ => best = Some(k),
        }
    }
    // Following minimum, confirmed once R_p rises by `tol` above it.
    let mut k_min = None;
    if let Some(m) = k_max {
        let mut low = m;
        for &k in known.iter().filter(|&&k| k > m) {
            if at(k) > at(low) + tol {
                k_min = Some(low);
                break;
            }
            if at(k) < at(low) {
                low = k;
            }
        }
    }
    // Meeting with the band boundary.
    let k_meet = k_min.and_then(|m| {
        known
            .iter()
            .copied()
            .find(|&k| k > m && frames[k].band_outer.is_some_and(|rc| at(k) >= rc - tol))
    });
    for &k in &known {
        phase[k] = Some(match (k_max, k_min, k_meet) {
            (Some(a), _, _) if k <= a => FrontPhase::PrimaryShock,
            (None, _, _) => FrontPhase::PrimaryShock,
            (Some(_), Some(b), _) if k <= b => FrontPhase::Rarefaction,
            (Some(_), None, _) => FrontPhase::Rarefaction,
            (_, Some(_), Some(c)) if k <= c => FrontPhase::SecondaryShock,
            (_, Some(_), None) => FrontPhase::SecondaryShock,
            _ => FrontPhase::Merged,
        });
    }
    let time = |k: Option<usize>| k.map(|k| frames[k].time);
    FrontHistory {
        reflection: time(k_max),
        arrest: time(k_min),
        meeting: time(k_meet),
        frames,
        phase,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A lattice ring 10–16 mm whose bonds inside 13 mm carry 200 MPa and outside
    /// nothing: the pressure front is at 13 mm, within a ring width.
    #[test]
    fn pressure_front_of_a_stressed_inner_layer() {
        use crate::dispersal::bands::BandSpec;
        use crate::dispersal::synthetic::LatticeRing;
        use crate::dispersal::{coarse_grain, Contacts, Kernel, PolarGrid, StressSource};
        use glam::DVec2;
        let ring = LatticeRing::new(DVec2::ZERO, 10e-3, 16e-3, 0.1e-3, 0.099e-3, 0.4, 0.0, 1);
        let (i, j, mut f) = ring.pressure_contacts(200e6);
        for k in 0..i.len() {
            if (0.5 * (ring.pos[i[k] as usize] + ring.pos[j[k] as usize])).length() > 13e-3 {
                f[k] = DVec2::ZERO;
            }
        }
        let v = vec![DVec2::ZERO; ring.pos.len()];
        let set = ParticleSet::new(&ring.pos, &v, &ring.radius, &ring.mass, &ring.id).unwrap();
        let c = Contacts::new(&i, &j, &f, set.len()).unwrap();
        let grid = PolarGrid::covering(DVec2::ZERO, 0.0, 0.5e-3, 180, &set).unwrap();
        let fields = coarse_grain(
            &grid,
            &set,
            Some(StressSource::Contacts(c)),
            Kernel::Hat { half_width: 0.1e-3 },
        );
        let map = BandMap::new(&fields, &BandSpec::default());
        let fr = frame_fronts(1e-6, &fields, &set, &map, &FrontSpec::default());
        let rp = fr.pressure_front.unwrap();
        assert!((rp - 13e-3).abs() <= 0.5e-3, "{rp}");
        assert!(fr
            .pressure_front_theta
            .iter()
            .all(|r| (r - 13e-3).abs() <= 0.5e-3));
        assert!(
            (fr.r_in - 10e-3).abs() < 0.1e-3 && (fr.r_out - 16e-3).abs() < 0.1e-3,
            "{fr:?}"
        );
        assert!((fr.band_outer.unwrap() - 16e-3).abs() < 0.6e-3, "{fr:?}");
    }

    fn frame(t: f64, rp: f64, rc: Option<f64>) -> FrameFronts {
        FrameFronts {
            time: t,
            r_in: 10e-3,
            r_out: 30e-3,
            pressure_front: Some(rp),
            pressure_front_theta: vec![],
            band_outer: rc,
        }
    }

    /// R_p of Fig. 6a in outline: out to the surface by 5 µs, back in to 9 µs, out
    /// again until it meets R_comp (shrinking from 29 mm).
    #[test]
    fn phases_of_fig_6a() {
        let dr = 0.5e-3;
        let mut frames = Vec::new();
        for k in 0..=25 {
            let t = k as f64 * 1e-6;
            let rp = if t <= 5e-6 {
                10e-3 + 4e-3 * k as f64
            } else if t <= 9e-6 {
                30e-3 - 2.5e-3 * (k - 5) as f64
            } else {
                20e-3 + 1.0e-3 * (k - 9) as f64
            };
            let rc = 29e-3 - 0.3e-3 * k as f64;
            frames.push(frame(t, rp, Some(rc)));
        }
        frames.reverse();
        let h = front_history(frames, dr);
        assert!((h.reflection.unwrap() - 5e-6).abs() < 1e-12);
        assert!((h.arrest.unwrap() - 9e-6).abs() < 1e-12);
        // R_p = 25 mm, R_comp = 24.8 mm at 14 µs (24 and 25.1 mm at 13 µs).
        assert!((h.meeting.unwrap() - 14e-6).abs() < 1e-12);
        assert_eq!(h.phase[3], Some(FrontPhase::PrimaryShock));
        assert_eq!(h.phase[7], Some(FrontPhase::Rarefaction));
        assert_eq!(h.phase[12], Some(FrontPhase::SecondaryShock));
        assert_eq!(h.phase[25], Some(FrontPhase::Merged));
        assert!(h.frames.windows(2).all(|w| w[0].time < w[1].time));
    }

    #[test]
    fn small_wiggles_are_not_events_and_missing_stress_is_none() {
        let dr = 0.5e-3;
        let frames: Vec<FrameFronts> = (0..10)
            .map(|k| {
                frame(
                    k as f64,
                    10e-3 + 1e-3 * k as f64 - if k == 4 { 1.2e-3 } else { 0.0 },
                    None,
                )
            })
            .collect();
        let h = front_history(frames, dr);
        // The dip at k = 4 is 0.2 mm below k = 3: less than half a ring, no reflection.
        assert_eq!(h.reflection, None);
        assert!(h.phase.iter().all(|p| *p == Some(FrontPhase::PrimaryShock)));
        let mut f = frame(0.0, 0.0, None);
        f.pressure_front = None;
        let h = front_history(vec![f], dr);
        assert_eq!(h.phase, vec![None]);
        assert!(quantile(&mut [], 0.5).is_nan());
    }
}
