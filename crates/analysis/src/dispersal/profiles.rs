//! Radial and azimuthal profiles of the coarse-grained fields.
//!
//! * Radial (xue-2019 Figs. 8c–d, 10a): per ring, φ averaged over the sectors (rings
//!   have equal bin areas), v_r averaged over mass, pressure, dilation and shear rate
//!   averaged over the bins that have them.
//! * Azimuthal (Figs. 10b, 12d–f): per sector, over the rings of the inner compact band
//!   only, φ averaged over area and v_r over mass, and the band's outer radius R_comp(θ);
//!   each with its Fourier [`Spectrum`]. Sectors without a band are NaN and filled by
//!   interpolation for the spectra.

use super::bands::BandMap;
use super::fields::PolarFields;
use super::spectra::{spectrum, Spectrum};
use serde::Serialize;

/// Profiles against radius at one time.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RadialProfile {
    /// Ring mid-radii (m).
    pub r: Vec<f64>,
    /// Packing fraction.
    pub phi: Vec<f64>,
    /// Mass-averaged radial velocity (m/s); NaN in empty rings.
    pub v_r: Vec<f64>,
    /// Mean pressure (Pa), if the stress was computed.
    pub pressure: Option<Vec<f64>>,
    /// Mean dilation rate (1/s).
    pub dilation: Vec<f64>,
    /// Mean shear rate (1/s).
    pub shear_rate: Vec<f64>,
}

/// Averages over the sectors of each ring.
pub fn radial_profile(fields: &PolarFields) -> RadialProfile {
    let g = &fields.grid;
    let nt = g.n_theta();
    let ring = |i: usize| (0..nt).map(move |j| g.index(i, j));
    let mean_finite = |v: &[f64], i: usize| {
        let (s, n) = ring(i)
            .map(|k| v[k])
            .filter(|x| x.is_finite())
            .fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
        if n > 0 {
            s / n as f64
        } else {
            f64::NAN
        }
    };
    let rings = 0..g.n_r();
    RadialProfile {
        r: rings.clone().map(|i| g.r_centre(i)).collect(),
        phi: rings
            .clone()
            .map(|i| ring(i).map(|k| fields.phi[k]).sum::<f64>() / nt as f64)
            .collect(),
        v_r: rings
            .clone()
            .map(|i| {
                let (mv, m) = ring(i)
                    .filter(|&k| fields.mass[k] > 0.0)
                    .fold((0.0, 0.0), |(mv, m), k| {
                        (mv + fields.mass[k] * fields.v_r[k], m + fields.mass[k])
                    });
                if m > 0.0 {
                    mv / m
                } else {
                    f64::NAN
                }
            })
            .collect(),
        pressure: fields
            .pressure()
            .map(|p| rings.clone().map(|i| mean_finite(p, i)).collect()),
        dilation: rings
            .clone()
            .map(|i| mean_finite(&fields.dilation, i))
            .collect(),
        shear_rate: rings.map(|i| mean_finite(&fields.shear_rate, i)).collect(),
    }
}

/// Band profiles against angle at one time.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct AzimuthalProfile {
    /// Sector mid-angles (rad, counter-clockwise from +x).
    pub theta: Vec<f64>,
    /// Radially averaged φ of the band.
    pub phi: Vec<f64>,
    /// Radially averaged (over mass) radial velocity of the band (m/s).
    pub v_r: Vec<f64>,
    /// Outer radius of the band R_comp(θ) (m).
    pub band_outer: Vec<f64>,
    /// Spectrum of `phi`.
    pub phi_spectrum: Spectrum,
    /// Spectrum of `v_r`.
    pub v_r_spectrum: Spectrum,
    /// Spectrum of `band_outer`.
    pub band_outer_spectrum: Spectrum,
}

/// Averages over the band's rings in each sector.
pub fn azimuthal_profile(fields: &PolarFields, map: &BandMap) -> AzimuthalProfile {
    let g = &fields.grid;
    let nt = g.n_theta();
    let mut phi = vec![f64::NAN; nt];
    let mut v_r = vec![f64::NAN; nt];
    for j in 0..nt {
        let (Some(i0), Some(i1)) = (map.inner_ring[j], map.last_ring[j]) else {
            continue;
        };
        let (mut pa, mut a, mut mv, mut m) = (0.0, 0.0, 0.0, 0.0);
        for i in i0..=i1 {
            let k = g.index(i, j);
            pa += fields.phi[k] * g.bin_area(i);
            a += g.bin_area(i);
            if fields.mass[k] > 0.0 {
                mv += fields.mass[k] * fields.v_r[k];
                m += fields.mass[k];
            }
        }
        phi[j] = pa / a;
        if m > 0.0 {
            v_r[j] = mv / m;
        }
    }
    let band_outer: Vec<f64> = map
        .outer_radius
        .iter()
        .map(|r| r.unwrap_or(f64::NAN))
        .collect();
    AzimuthalProfile {
        theta: (0..nt).map(|j| g.theta_centre(j)).collect(),
        phi_spectrum: spectrum(&phi),
        v_r_spectrum: spectrum(&v_r),
        band_outer_spectrum: spectrum(&band_outer),
        phi,
        v_r,
        band_outer,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dispersal::bands::BandSpec;
    use crate::dispersal::synthetic::LatticeRing;
    use crate::dispersal::{coarse_grain, Kernel, ParticleSet, PolarGrid};
    use glam::DVec2;
    use std::f64::consts::TAU;

    #[test]
    fn profiles_of_a_hexagonal_band() {
        // A ring whose outer edge is a six-lobed curve and whose speed varies with 6θ.
        let ring = LatticeRing::new(DVec2::ZERO, 10e-3, 15e-3, 0.1e-3, 0.097e-3, 0.0, 0.02, 3);
        let keep: Vec<usize> = (0..ring.pos.len())
            .filter(|&p| {
                let x = ring.pos[p];
                x.length() < 13e-3 + 1.5e-3 * (6.0 * x.y.atan2(x.x)).cos()
            })
            .collect();
        let pick = |v: &[f64]| keep.iter().map(|&p| v[p]).collect::<Vec<f64>>();
        let pos: Vec<DVec2> = keep.iter().map(|&p| ring.pos[p]).collect();
        let vel: Vec<DVec2> = pos
            .iter()
            .map(|x| (300.0 + 40.0 * (6.0 * x.y.atan2(x.x)).cos()) * x.normalize())
            .collect();
        let (radius, mass) = (pick(&ring.radius), pick(&ring.mass));
        let id: Vec<u32> = (0..pos.len() as u32).collect();
        let set = ParticleSet::new(&pos, &vel, &radius, &mass, &id).unwrap();
        let grid = PolarGrid::covering(DVec2::ZERO, 0.0, 0.5e-3, 180, &set).unwrap();
        let f = coarse_grain(&grid, &set, None, Kernel::Hat { half_width: 0.1e-3 });
        let map = BandMap::new(&f, &BandSpec::default());
        let a = azimuthal_profile(&f, &map);
        assert_eq!(a.band_outer_spectrum.dominant_mode, Some(6));
        assert_eq!(a.v_r_spectrum.dominant_mode, Some(6));
        let amp = a.band_outer_spectrum.amplitude[6];
        assert!((amp - 1.5e-3).abs() < 0.3e-3, "{amp}");
        assert!(
            (a.v_r_spectrum.amplitude[6] - 40.0).abs() < 8.0,
            "{}",
            a.v_r_spectrum.amplitude[6]
        );
        assert!(a.phi.iter().all(|p| *p > 0.8), "{:?}", a.phi);
        assert!((a.theta[1] - a.theta[0] - TAU / 180.0).abs() < 1e-12);

        let r = radial_profile(&f);
        let i = grid.ring_of(11e-3).unwrap();
        assert!((r.phi[i] - ring.phi).abs() < 0.02, "{}", r.phi[i]);
        assert!((r.v_r[i] - 300.0).abs() < 2.0, "{}", r.v_r[i]);
        assert!(r.pressure.is_none());
        assert!(r.phi[grid.n_r() - 1] < 0.05);
    }
}
