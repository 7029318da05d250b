//! The inner compact band and the outer spall layer (xue-2019 §§5.1, 5.6, Figs. 6b
//! and 14), with the paper's thresholds: band φ ≥ 0.84 (about the densest random
//! packing), spall φ < 0.6.
//!
//! In each sector, on φ averaged over the sector and `smoothing_sectors` neighbours on
//! either side (a bin of the paper's size holds a few dozen grains):
//!
//! * the inner surface is the first ring with φ ≥ [`OCCUPIED_PHI`];
//! * the band runs from the inner surface through the first run of rings with
//!   φ ≥ `band_fraction`; looser rings before it (a partly filled surface ring) and
//!   single-ring dips inside it belong to it. Its outer edge is R_comp(θ), the compact
//!   band boundary of Fig. 6a. A sector with no such ring has no band;
//! * outside the band a grain is spall where φ < `spall_fraction`, otherwise it is in
//!   transition (loosening, not yet spall).
//!
//! Grains count by the bin of their centre. Velocities are radial (about the grid
//! centre), averaged per grain (Fig. 14's |v̄_r|_N) and per mass. A layer with fewer
//! than `min_grains` grains gets no velocity but an explicit
//! [`LayerVelocity::TooFewGrains`].

use super::fields::PolarFields;
use super::input::{at_least, positive, InputError, ParticleSet};
use super::polar::OUTSIDE;
use serde::{Deserialize, Serialize};

/// Packing fraction above which a bin counts as holding material (the inner surface).
pub const OCCUPIED_PHI: f64 = 0.1;

/// Thresholds of the band/spall split.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BandSpec {
    /// φ at or above which a bin is compact (paper: 0.84).
    pub band_fraction: f64,
    /// φ below which a bin outside the band is spall (paper: 0.6).
    pub spall_fraction: f64,
    /// Sectors on either side averaged with each sector's φ.
    pub smoothing_sectors: usize,
    /// Fewest grains for a layer's velocity to be reported.
    pub min_grains: usize,
}

impl Default for BandSpec {
    fn default() -> Self {
        BandSpec {
            band_fraction: crate::ring::BAND_PHI,
            spall_fraction: 0.6,
            smoothing_sectors: 1,
            min_grains: 100,
        }
    }
}

impl BandSpec {
    /// Checks the thresholds; `key` names the section in messages.
    pub fn validate(&self, key: &str) -> Result<(), InputError> {
        positive(&format!("{key}.spall_fraction"), self.spall_fraction)?;
        if !(self.band_fraction > self.spall_fraction && self.band_fraction < 1.0) {
            return Err(InputError::new(
                format!("{key}.band_fraction"),
                self.band_fraction,
                format!("must lie in (spall_fraction = {}, 1)", self.spall_fraction),
            ));
        }
        at_least(&format!("{key}.min_grains"), self.min_grains, 1).map(|_| ())
    }
}

/// Where the band is, sector by sector.
#[derive(Clone, Debug, PartialEq)]
pub struct BandMap {
    /// φ smoothed over neighbouring sectors, per bin.
    pub phi: Vec<f64>,
    /// First ring with material in each sector.
    pub inner_ring: Vec<Option<usize>>,
    /// Last ring of the band in each sector.
    pub last_ring: Vec<Option<usize>>,
    /// R_comp(θ): outer radius of the band per sector (m).
    pub outer_radius: Vec<Option<f64>>,
}

impl BandMap {
    /// Finds the band in `fields`.
    pub fn new(fields: &PolarFields, spec: &BandSpec) -> Self {
        let g = &fields.grid;
        let (nr, nt) = (g.n_r(), g.n_theta());
        let s = spec.smoothing_sectors.min((nt - 1) / 2);
        let mut phi = vec![0.0; g.len()];
        for j in 0..nt {
            for i in 0..nr {
                // Rings have equal bin areas, so the plain mean is the area average.
                let sum: f64 = (0..=2 * s)
                    .map(|d| fields.phi[g.index(i, (j + nt + d - s) % nt)])
                    .sum();
                phi[g.index(i, j)] = sum / (2 * s + 1) as f64;
            }
        }
        let mut inner_ring = vec![None; nt];
        let mut last_ring = vec![None; nt];
        for j in 0..nt {
            let at = |i: usize| phi[g.index(i, j)];
            let Some(i0) = (0..nr).find(|&i| at(i) >= OCCUPIED_PHI) else {
                continue;
            };
            inner_ring[j] = Some(i0);
            let mut last = None;
            for i in i0..nr {
                if at(i) >= spec.band_fraction {
                    last = Some(i);
                } else if last.is_some() && !(i + 1 < nr && at(i + 1) >= spec.band_fraction) {
                    break;
                }
            }
            last_ring[j] = last;
        }
        let outer_radius = last_ring
            .iter()
            .map(|l| l.map(|i| g.r_edge(i + 1)))
            .collect();
        BandMap {
            phi,
            inner_ring,
            last_ring,
            outer_radius,
        }
    }

    /// Mean of R_comp over the sectors that have a band (m).
    pub fn mean_outer_radius(&self) -> Option<f64> {
        let r: Vec<f64> = self.outer_radius.iter().flatten().copied().collect();
        (!r.is_empty()).then(|| r.iter().sum::<f64>() / r.len() as f64)
    }

    /// Sectors with a band.
    pub fn sectors_with_band(&self) -> usize {
        self.last_ring.iter().flatten().count()
    }
}

/// Which layer a grain belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Layer {
    /// Inner compact band.
    Band,
    /// Outside the band, not yet dilute.
    Transition,
    /// Outer dilute spall layer.
    Spall,
    /// Off the grid.
    Outside,
}

/// The layer of every grain.
pub fn classify(fields: &PolarFields, map: &BandMap, spec: &BandSpec) -> Vec<Layer> {
    let g = &fields.grid;
    fields
        .binning
        .bin_of
        .iter()
        .map(|&b| {
            if b == OUTSIDE {
                return Layer::Outside;
            }
            let (i, j) = g.ring_sector(b as usize);
            match map.last_ring[j] {
                Some(last) if i <= last => Layer::Band,
                _ if map.phi[b as usize] < spec.spall_fraction => Layer::Spall,
                _ => Layer::Transition,
            }
        })
        .collect()
}

/// A layer's mean radial velocity, or why there is none.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "status", rename_all = "snake_case")]
pub enum LayerVelocity {
    /// Enough grains: both means (m/s).
    Measured {
        /// Mean over grains.
        number_weighted: f64,
        /// Mean over mass.
        mass_weighted: f64,
    },
    /// Too few grains for a meaningful mean.
    TooFewGrains {
        /// Grains in the layer.
        grains: usize,
        /// Grains required ([`BandSpec::min_grains`]).
        needed: usize,
    },
}

impl LayerVelocity {
    /// The number-weighted mean, if measured.
    pub fn number_weighted(&self) -> Option<f64> {
        match self {
            LayerVelocity::Measured {
                number_weighted, ..
            } => Some(*number_weighted),
            LayerVelocity::TooFewGrains { .. } => None,
        }
    }
}

/// Size and velocity of one layer.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LayerFigures {
    /// Grains in the layer.
    pub grains: usize,
    /// Their share of all grains (N_compt/N for the band).
    pub number_fraction: f64,
    /// Their share of the mass.
    pub mass_fraction: f64,
    /// Mean radial velocity.
    pub velocity: LayerVelocity,
}

/// The band/spall split of one frame.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BandSplit {
    /// Inner compact band.
    pub band: LayerFigures,
    /// Between band and spall.
    pub transition: LayerFigures,
    /// Outer spall layer.
    pub spall: LayerFigures,
    /// Mean R_comp over sectors with a band (m).
    pub band_outer_radius: Option<f64>,
    /// Sectors with a band, of all sectors.
    pub sectors_with_band: usize,
}

/// Splits the grains of `particles` (those `fields` was built from) into layers.
pub fn band_split(
    fields: &PolarFields,
    particles: &ParticleSet,
    map: &BandMap,
    spec: &BandSpec,
) -> BandSplit {
    let layer = classify(fields, map, spec);
    let c0 = fields.grid.centre();
    let n = particles.len().max(1) as f64;
    let m_all = particles.total_mass();
    let figures = |which: Layer| {
        let (mut k, mut m, mut sv, mut smv) = (0usize, 0.0, 0.0, 0.0);
        for (p, l) in layer.iter().enumerate() {
            if *l != which {
                continue;
            }
            let d = particles.pos[p] - c0;
            let vr = particles.vel[p].dot(d.try_normalize().unwrap_or(glam::DVec2::ZERO));
            k += 1;
            m += particles.mass[p];
            sv += vr;
            smv += particles.mass[p] * vr;
        }
        LayerFigures {
            grains: k,
            number_fraction: k as f64 / n,
            mass_fraction: if m_all > 0.0 { m / m_all } else { 0.0 },
            velocity: if k >= spec.min_grains && m > 0.0 {
                LayerVelocity::Measured {
                    number_weighted: sv / k as f64,
                    mass_weighted: smv / m,
                }
            } else {
                LayerVelocity::TooFewGrains {
                    grains: k,
                    needed: spec.min_grains,
                }
            },
        }
    };
    BandSplit {
        band: figures(Layer::Band),
        transition: figures(Layer::Transition),
        spall: figures(Layer::Spall),
        band_outer_radius: map.mean_outer_radius(),
        sectors_with_band: map.sectors_with_band(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dispersal::synthetic::LatticeRing;
    use crate::dispersal::{coarse_grain, Kernel, PolarGrid};
    use glam::DVec2;

    /// A dense ring (φ ≈ 0.88) whose outer part from 13 mm is spread radially by 2
    /// (φ ≈ 0.44): band out to about 13 mm at 200 m/s, spall beyond at 50 m/s.
    fn split(kernel: Kernel, min_grains: usize) -> (BandMap, BandSplit, Vec<Layer>) {
        let mut ring =
            LatticeRing::new(DVec2::ZERO, 10e-3, 14.5e-3, 0.1e-3, 0.097e-3, 0.2, 0.02, 7);
        let mut vel = vec![DVec2::ZERO; ring.pos.len()];
        for (p, v) in ring.pos.iter_mut().zip(&mut vel) {
            let r = p.length();
            if r > 13e-3 {
                *p *= (13e-3 + 2.0 * (r - 13e-3)) / r;
                *v = 50.0 * p.normalize();
            } else {
                *v = 200.0 * p.normalize();
            }
        }
        let set = ParticleSet::new(&ring.pos, &vel, &ring.radius, &ring.mass, &ring.id).unwrap();
        let grid = PolarGrid::covering(DVec2::ZERO, 0.0, 5.0 * ring.d0, 180, &set).unwrap();
        let f = coarse_grain(&grid, &set, None, kernel);
        let spec = BandSpec {
            min_grains,
            ..BandSpec::default()
        };
        let map = BandMap::new(&f, &spec);
        let layers = classify(&f, &map, &spec);
        (map.clone(), band_split(&f, &set, &map, &spec), layers)
    }

    #[test]
    fn dense_core_is_band_and_loose_shell_is_spall() {
        for kernel in [Kernel::Bin, Kernel::Hat { half_width: 0.1e-3 }] {
            let (map, s, _) = split(kernel, 100);
            assert_eq!(s.sectors_with_band, 180, "{kernel:?}");
            let r = s.band_outer_radius.unwrap();
            assert!((r - 13e-3).abs() < 0.5e-3, "{kernel:?}: R_comp {r}");
            // Grains inside 13 mm: (13² − 10²)/(14.5² − 10²) of them.
            let want = (169.0 - 100.0) / (210.25 - 100.0);
            assert!(
                (s.band.number_fraction - want).abs() < 0.05,
                "{kernel:?} {s:?}"
            );
            let LayerVelocity::Measured {
                number_weighted,
                mass_weighted,
            } = s.band.velocity
            else {
                panic!("{s:?}")
            };
            assert!(number_weighted > 180.0 && mass_weighted > 180.0, "{s:?}");
            let v = s.spall.velocity.number_weighted().unwrap();
            assert!((v - 50.0).abs() < 10.0, "{s:?}");
            let total = s.band.grains + s.transition.grains + s.spall.grains;
            assert!(
                (s.band.mass_fraction + s.transition.mass_fraction + s.spall.mass_fraction - 1.0)
                    .abs()
                    < 1e-12
            );
            assert!(total > 0);
            assert!(map.inner_ring.iter().all(|i| i.is_some()));
        }
    }

    #[test]
    fn a_thin_layer_is_flagged_not_averaged() {
        let (_, s, _) = split(Kernel::Bin, 1_000_000);
        assert_eq!(
            s.band.velocity,
            LayerVelocity::TooFewGrains {
                grains: s.band.grains,
                needed: 1_000_000
            }
        );
        let json = serde_json::to_string(&s.band.velocity).unwrap();
        assert!(json.contains("\"status\":\"too_few_grains\""), "{json}");
        assert!(s.band.velocity.number_weighted().is_none());
    }

    #[test]
    fn thresholds_are_checked() {
        assert!(BandSpec::default().validate("band").is_ok());
        let bad = BandSpec {
            band_fraction: 0.5,
            ..BandSpec::default()
        };
        assert_eq!(bad.validate("band").unwrap_err().key, "band.band_fraction");
        let bad = BandSpec {
            min_grains: 0,
            ..BandSpec::default()
        };
        assert!(bad.validate("band").is_err());
    }
}
