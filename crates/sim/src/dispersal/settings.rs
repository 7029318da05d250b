//! `[analysis.dispersal]` (FEM–DEM) and `[dispersal]` (DEM): when the dispersal
//! analysis runs during a run and with which settings.

use grains_analysis::dispersal::{BandSpec, DispersalSpec, FrontSpec, JetSpec, ShearBandSpec};
use grains_core::input::{shown, InputError};
use serde::{Deserialize, Serialize};

/// The scenario's dispersal table. Every analysed time gets its figures in
/// `summary.json`; frames also get their fields as `.vts`; the chosen `times` also get
/// the polar maps and the band's azimuthal profiles.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DispersalSettings {
    /// Centre of the polar grid (m); default the charge's centre (required for DEM).
    #[serde(default)]
    pub centre: Option<[f64; 2]>,
    /// Times (s) of the polar maps and azimuthal profiles (the paper's figures); a
    /// frame is written at each. None: the last analysed frame.
    #[serde(default)]
    pub times: Vec<f64>,
    /// Analyse every frame, writing its fields (default true).
    #[serde(default)]
    pub frames: Option<bool>,
    /// Also analyse this often (s), figures only (no files): the fronts of Fig. 6a need
    /// finer steps than frames are worth writing at.
    #[serde(default)]
    pub every: Option<f64>,
    /// Jets found at the last analysed time are traced back to the analysed time
    /// nearest this (s); default a fifth of the run (the paper: 20 µs of 100).
    #[serde(default)]
    pub trace_from: Option<f64>,
    /// Ring width of the bins in mean grain diameters (paper: 5).
    #[serde(default)]
    pub radial_bin: Option<f64>,
    /// Sectors (paper: 180).
    #[serde(default)]
    pub sectors: Option<usize>,
    /// Half-width of the smoothing kernel in mean diameters; 0 for plain bins.
    #[serde(default)]
    pub kernel_width: Option<f64>,
    /// Band and spall thresholds.
    #[serde(default)]
    pub band: BandSpec,
    /// Pressure front.
    #[serde(default)]
    pub fronts: FrontSpec,
    /// Shear-band detection.
    #[serde(default)]
    pub shear_bands: ShearBandSpec,
    /// Jet detection.
    #[serde(default)]
    pub jets: JetSpec,
}

impl DispersalSettings {
    /// The analysis settings.
    pub fn spec(&self) -> DispersalSpec {
        let d = DispersalSpec::default();
        DispersalSpec {
            radial_bin: self.radial_bin.unwrap_or(d.radial_bin),
            sectors: self.sectors.unwrap_or(d.sectors),
            kernel_width: self.kernel_width.unwrap_or(d.kernel_width),
            band: self.band,
            fronts: self.fronts,
            shear_bands: self.shear_bands,
            jets: self.jets,
        }
    }

    /// Whether every frame is analysed.
    pub fn every_frame(&self) -> bool {
        self.frames.unwrap_or(true)
    }

    /// The time jets are traced back to, for a run of `duration`.
    pub fn trace_time(&self, duration: f64) -> f64 {
        self.trace_from.unwrap_or(0.2 * duration)
    }

    /// Checks every setting against a run of `duration` (s); `key` is the table's name.
    pub fn validate(&self, key: &str, duration: f64) -> Result<(), InputError> {
        self.spec().validate(key)?;
        for (k, &t) in self.times.iter().enumerate() {
            if !(t.is_finite() && t >= 0.0 && t <= duration) {
                return Err(InputError::new(
                    format!("{key}.times[{k}]"),
                    shown(t),
                    format!(
                        "must lie in [0, {}] s (the run's duration)",
                        shown(duration)
                    ),
                ));
            }
        }
        if let Some(e) = self.every {
            if !(e.is_finite() && e > 0.0 && e >= duration * 1e-5) {
                return Err(InputError::new(
                    format!("{key}.every"),
                    shown(e),
                    format!(
                        "must be a time > 0 s and at least 1e-5 of the run ({} s)",
                        shown(duration * 1e-5)
                    ),
                ));
            }
        }
        if let Some(t) = self.trace_from {
            if !(t.is_finite() && t >= 0.0 && t <= duration) {
                return Err(InputError::new(
                    format!("{key}.trace_from"),
                    shown(t),
                    format!("must lie in [0, {}] s", shown(duration)),
                ));
            }
        }
        if let Some(c) = self.centre {
            if !c.iter().all(|v| v.is_finite()) {
                return Err(InputError::new(
                    format!("{key}.centre"),
                    format!("{c:?}"),
                    "must be two finite coordinates (m)",
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_the_papers_and_bad_values_are_named() {
        let s: DispersalSettings = toml::from_str("").unwrap();
        assert_eq!(s.spec(), DispersalSpec::default());
        assert!(s.every_frame());
        assert!((s.trace_time(100e-6) - 20e-6).abs() < 1e-18);
        let s: DispersalSettings =
            toml::from_str("times = [1e-6, 9e-6]\nsectors = 4\n[band]\nmin_grains = 10").unwrap();
        assert_eq!(
            s.validate("analysis.dispersal", 1e-5).unwrap_err().key,
            "analysis.dispersal.sectors"
        );
        let s: DispersalSettings = toml::from_str("times = [2e-5]").unwrap();
        let e = s.validate("analysis.dispersal", 1e-5).unwrap_err();
        assert_eq!(e.key, "analysis.dispersal.times[0]");
        let s: DispersalSettings = toml::from_str("every = 0.0").unwrap();
        assert!(s.validate("d", 1e-5).is_err());
        assert!(toml::from_str::<DispersalSettings>("bogus = 1").is_err());
    }
}
