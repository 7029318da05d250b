//! One call for a whole frame: the settings ([`DispersalSpec`], a scenario section)
//! and [`analyze_frame`], which runs fields, band split, fronts, profiles and shear
//! bands, and the [`FrameSummary`] for `summary.json`.

use super::bands::{band_split, BandMap, BandSpec, BandSplit};
use super::fields::{coarse_grain, PolarFields};
use super::fronts::{frame_fronts, FrameFronts, FrontSpec};
use super::input::{at_least, positive, InputError, ParticleSet, StressSource};
use super::jets::JetSpec;
use super::kernel::Kernel;
use super::output::MapOverlays;
use super::polar::{PolarGrid, PAPER_DR_D0, PAPER_SECTORS};
use super::profiles::{azimuthal_profile, radial_profile, AzimuthalProfile, RadialProfile};
use super::shear_bands::{shear_bands, ShearBandSpec, ShearBands};
use glam::DVec2;
use serde::{Deserialize, Serialize};

/// Settings of the dispersal analysis; every length in mean grain diameters d0.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DispersalSpec {
    /// Ring width dr of the bins (paper: 5, or 10).
    pub radial_bin: f64,
    /// Sectors (paper: 180, dθ = π/90).
    pub sectors: usize,
    /// Half-width of the hat kernel; 0 for the paper's plain bin averages (noisier:
    /// single bins of the paper's size are off by up to ~5 % in stress and φ).
    pub kernel_width: f64,
    /// Band and spall thresholds.
    pub band: BandSpec,
    /// Pressure front.
    pub fronts: FrontSpec,
    /// Shear-band detection.
    pub shear_bands: ShearBandSpec,
    /// Jet detection.
    pub jets: JetSpec,
}

impl Default for DispersalSpec {
    fn default() -> Self {
        DispersalSpec {
            radial_bin: PAPER_DR_D0,
            sectors: PAPER_SECTORS,
            kernel_width: 1.0,
            band: BandSpec::default(),
            fronts: FrontSpec::default(),
            shear_bands: ShearBandSpec::default(),
            jets: JetSpec::default(),
        }
    }
}

impl DispersalSpec {
    /// Checks every setting; `key` is the section's name in the scenario.
    pub fn validate(&self, key: &str) -> Result<(), InputError> {
        positive(&format!("{key}.radial_bin"), self.radial_bin)?;
        at_least(&format!("{key}.sectors"), self.sectors, 8)?;
        if !(self.kernel_width.is_finite() && self.kernel_width >= 0.0) {
            return Err(InputError::new(
                format!("{key}.kernel_width"),
                self.kernel_width,
                "must be a finite number ≥ 0 (0: plain bins)",
            ));
        }
        self.band.validate(&format!("{key}.band"))?;
        self.fronts.validate(&format!("{key}.fronts"))?;
        self.shear_bands.validate(&format!("{key}.shear_bands"))?;
        self.jets.validate(&format!("{key}.jets"))
    }

    /// The kernel for grains of mean diameter `d0`.
    pub fn kernel(&self, d0: f64) -> Kernel {
        if self.kernel_width > 0.0 {
            Kernel::Hat {
                half_width: self.kernel_width * d0,
            }
        } else {
            Kernel::Bin
        }
    }
}

/// Everything measured on one frame.
#[derive(Clone, Debug)]
pub struct FrameAnalysis {
    /// Time (s).
    pub time: f64,
    /// Coarse-grained fields.
    pub fields: PolarFields,
    /// Where the band is.
    pub band_map: BandMap,
    /// Band, transition and spall.
    pub split: BandSplit,
    /// Fronts.
    pub fronts: FrameFronts,
    /// Radial profiles.
    pub radial: RadialProfile,
    /// Azimuthal profiles of the band.
    pub azimuthal: AzimuthalProfile,
    /// Spiral shear bands, if the band is thick enough.
    pub shear_bands: Option<ShearBands>,
}

/// Analyses one frame at `time`: grains `particles` (mean diameter `d0`) about the
/// charge centre `centre`, with the stress from `stress` when given.
pub fn analyze_frame(
    spec: &DispersalSpec,
    centre: DVec2,
    d0: f64,
    time: f64,
    particles: &ParticleSet,
    stress: Option<StressSource>,
) -> Result<FrameAnalysis, InputError> {
    spec.validate("dispersal")?;
    positive("dispersal.d0", d0)?;
    if particles.is_empty() {
        return Err(InputError::new(
            "particles",
            "none",
            "the frame must hold grains",
        ));
    }
    let grid = PolarGrid::covering(centre, 0.0, spec.radial_bin * d0, spec.sectors, particles)?;
    let fields = coarse_grain(&grid, particles, stress, spec.kernel(d0));
    let band_map = BandMap::new(&fields, &spec.band);
    Ok(FrameAnalysis {
        time,
        split: band_split(&fields, particles, &band_map, &spec.band),
        fronts: frame_fronts(time, &fields, particles, &band_map, &spec.fronts),
        radial: radial_profile(&fields),
        azimuthal: azimuthal_profile(&fields, &band_map),
        shear_bands: shear_bands(&fields, &band_map, &spec.shear_bands),
        band_map,
        fields,
    })
}

/// The scalar results of a frame, for `summary.json`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FrameSummary {
    /// Time (s).
    pub time: f64,
    /// R_in (m).
    pub r_in: f64,
    /// R_out (m).
    pub r_out: f64,
    /// Pressure front R_p (m).
    pub pressure_front: Option<f64>,
    /// Band, transition and spall.
    pub split: BandSplit,
    /// Leading azimuthal modes (k ≥ 2) of the band's φ, v_r and outer radius.
    pub band_modes: [Option<usize>; 3],
    /// Shear bands: clockwise and anticlockwise counts and angles, groups.
    pub shear_bands: Option<ShearBandSummary>,
}

/// The scalar part of [`ShearBands`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ShearBandSummary {
    /// Clockwise bands.
    pub clockwise: usize,
    /// Anticlockwise bands.
    pub anticlockwise: usize,
    /// Angle of the clockwise bands to the radius (degrees).
    pub clockwise_angle: f64,
    /// Angle of the anticlockwise bands to the radius (degrees).
    pub anticlockwise_angle: f64,
    /// Groups.
    pub groups: usize,
    /// Leading azimuthal mode of γ̇ at the inner perimeter.
    pub dominant_mode: Option<usize>,
    /// Either angle is an end of the search range (not clearly spiral).
    pub at_search_limit: bool,
}

impl FrameAnalysis {
    /// What the maps draw over the fields: R_comp(θ), R_p(θ) and the shear bands.
    pub fn overlays(&self) -> MapOverlays<'_> {
        MapOverlays {
            band: Some(&self.band_map),
            pressure_front: (!self.fronts.pressure_front_theta.is_empty())
                .then_some(self.fronts.pressure_front_theta.as_slice()),
            shear_bands: self.shear_bands.as_ref(),
        }
    }

    /// The scalar results.
    pub fn summary(&self) -> FrameSummary {
        FrameSummary {
            time: self.time,
            r_in: self.fronts.r_in,
            r_out: self.fronts.r_out,
            pressure_front: self.fronts.pressure_front,
            split: self.split.clone(),
            band_modes: [
                self.azimuthal.phi_spectrum.dominant_mode,
                self.azimuthal.v_r_spectrum.dominant_mode,
                self.azimuthal.band_outer_spectrum.dominant_mode,
            ],
            shear_bands: self.shear_bands.as_ref().map(|b| ShearBandSummary {
                clockwise: b.clockwise.count,
                anticlockwise: b.anticlockwise.count,
                clockwise_angle: b.clockwise.angle,
                anticlockwise_angle: b.anticlockwise.angle,
                groups: b.groups,
                dominant_mode: b.dominant_mode,
                at_search_limit: b.clockwise.at_search_limit || b.anticlockwise.at_search_limit,
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dispersal::output::{
        fields_grid, plot_azimuthal, plot_fronts, plot_radial_profiles, write_maps,
    };
    use crate::dispersal::synthetic::LatticeRing;
    use crate::dispersal::{front_history, Contacts};

    fn scratch() -> std::path::PathBuf {
        let d = std::env::temp_dir().join(format!("grains-dispersal-{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    /// A whole frame of a lattice ring expanding at v = a r, its inner half under
    /// 100 MPa: every output is produced and readable.
    #[test]
    fn a_frame_end_to_end() {
        let d0 = 0.1e-3;
        let ring = LatticeRing::new(DVec2::ZERO, 10e-3, 14e-3, d0, 0.098e-3, 0.1, 0.02, 3);
        let vel: Vec<DVec2> = ring.pos.iter().map(|x| 2e4 * *x).collect();
        let (i, j, mut f) = ring.pressure_contacts(100e6);
        for k in 0..i.len() {
            if ring.pos[i[k] as usize].length() > 12e-3 {
                f[k] = DVec2::ZERO;
            }
        }
        let set = ParticleSet::new(&ring.pos, &vel, &ring.radius, &ring.mass, &ring.id).unwrap();
        let c = Contacts::new(&i, &j, &f, set.len()).unwrap();
        let spec = DispersalSpec::default();
        let a = analyze_frame(
            &spec,
            DVec2::ZERO,
            d0,
            5e-6,
            &set,
            Some(StressSource::Contacts(c)),
        )
        .unwrap();
        let s = a.summary();
        assert!((s.pressure_front.unwrap() - 12e-3).abs() <= 0.5e-3, "{s:?}");
        assert!(s.split.band.number_fraction > 0.9, "{s:?}");
        let json = serde_json::to_string(&s).unwrap();
        assert!(
            json.contains("\"band\"") && json.contains("\"status\":\"measured\""),
            "{json}"
        );

        let dir = scratch();
        let vts = dir.join("fields.vts");
        fields_grid(&a.fields).write(&vts).unwrap();
        let arrays = grains_core::vtk::read_appended_arrays(&vts).unwrap();
        let p = grains_core::vtk::find_array(&arrays, "CellData", "pressure").unwrap();
        assert_eq!(p.values.len(), a.fields.grid.len());
        let maps =
            write_maps(&dir, "frame", &a.fields, a.time, Some(10e-3), &a.overlays()).unwrap();
        assert_eq!(maps.len(), 6);
        let h = front_history(vec![a.fronts.clone()], a.fields.grid.dr());
        plot_fronts(&dir.join("fronts.png"), "ring", &h).unwrap();
        plot_radial_profiles(&dir, "radial", &[(a.time, &a.radial)]).unwrap();
        plot_azimuthal(&dir, "azimuthal", a.time, &a.azimuthal).unwrap();

        let bad = DispersalSpec {
            sectors: 3,
            ..DispersalSpec::default()
        };
        let e = analyze_frame(&bad, DVec2::ZERO, d0, 0.0, &set, None).unwrap_err();
        assert_eq!(e.key, "dispersal.sectors");
    }
}
