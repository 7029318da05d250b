//! The scenario file of an explosive-dispersal run (`engine = "fem_dem"`): a charge meshed
//! with finite elements, optionally surrounded by a ring of DEM particles, parsed strictly.

use grains_dem::{ContactModel, Material};
use grains_fem::{Burn, Explosive, MeshSpec, Strength, Viscosity};
use serde::{Deserialize, Serialize};

/// A whole scenario file.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Engine tag, `"fem_dem"`.
    pub engine: String,
    /// Name of the run; the default output directory is `runs/<name>`.
    pub name: String,
    /// Free text shown by `grains check`.
    #[serde(default)]
    pub description: String,
    /// The explosive charge.
    pub charge: ChargeSpec,
    /// The particle ring; none for a bare charge.
    #[serde(default)]
    pub ring: Option<RingSpec>,
    /// Particle materials (DEM), referred to by name.
    #[serde(rename = "material", default)]
    pub materials: Vec<Material>,
    /// Particle contact model (DEM).
    #[serde(default)]
    pub contact: ContactModel,
    /// Charge–particle contact.
    #[serde(default)]
    pub coupling: CouplingSpec,
    /// Time stepping.
    pub run: RunSpec,
    /// What is written and how often.
    #[serde(default)]
    pub output: crate::output::OutputSpec,
    /// How the ring is measured.
    #[serde(default)]
    pub analysis: AnalysisSpec,
    /// Checks written into summary.json.
    #[serde(rename = "check", default)]
    pub checks: Vec<CheckSpec>,
    /// `[parallel]`: how the ring is spread over the ranks of a run under `mpirun`
    /// (the charge is on every rank).
    #[serde(default)]
    pub parallel: Option<crate::dem::ranks::ParallelSpec>,
}

/// `[charge]`: a circular charge.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChargeSpec {
    /// A built-in explosive (`tnt`, `tnt_llnl1985`, `pe4`) or `custom`.
    pub explosive: String,
    /// The full parameter set when `explosive = "custom"`.
    #[serde(default)]
    pub custom: Option<Explosive>,
    /// Radius R_in (m).
    pub radius: f64,
    /// Centre (m).
    #[serde(default)]
    pub centre: [f64; 2],
    /// Mesh sizes.
    pub mesh: MeshSpec,
    /// Programmed burn.
    #[serde(default)]
    pub burn: Burn,
    /// Artificial bulk viscosity.
    #[serde(default)]
    pub viscosity: Viscosity,
    /// Deviatoric stress of the unreacted explosive (none by default).
    #[serde(default)]
    pub strength: Option<Strength>,
    /// Global non-viscous damping ratio α (Eq. A5), 0 = none.
    #[serde(default)]
    pub damping: f64,
}

/// `[ring]`: the particle ring around the charge.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RingSpec {
    /// Material name.
    pub material: String,
    /// Inner radius (m); at least the charge radius.
    pub inner_radius: f64,
    /// Outer radius R_out (m).
    pub outer_radius: f64,
    /// Where the disks come from.
    pub packing: PackingSpec,
}

/// `[ring.packing]`.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(tag = "source", rename_all = "snake_case", deny_unknown_fields)]
pub enum PackingSpec {
    /// A packing file (`x y r` per line, SI, `#` comments), e.g. from `grains pack`.
    File {
        /// Path, relative to the scenario file.
        path: String,
    },
    /// The packing a `grains pack` spec makes, made on the first run and cached under
    /// the spec's key (see [`crate::packings`]). The spec must pack the ring's annulus.
    Spec {
        /// Path of the packing spec, relative to the scenario file.
        spec: String,
    },
    /// A quick built-in ring: a triangular lattice of disks with diameters uniform in
    /// d0(1 ± spread), lined inside and outside by a chain of small disks tangent to the
    /// ring's circles, as the paper's packings are.
    Lattice {
        /// Mean diameter d0 (m).
        d0: f64,
        /// Relative half-width of the diameter distribution.
        #[serde(default = "default_spread")]
        spread: f64,
        /// Lining disk diameter over d0 (0: no lining).
        #[serde(default = "default_lining")]
        lining: f64,
        /// Random seed of the diameters.
        #[serde(default)]
        seed: u64,
    },
}

fn default_spread() -> f64 {
    0.03
}
fn default_lining() -> f64 {
    0.6
}

/// `[coupling]`: the normal penalty contact between particles and the charge's edge.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CouplingSpec {
    /// Penalty stiffness K_pe (N/m per unit thickness); default `stiffness_ratio` × the
    /// particles' normal contact stiffness.
    #[serde(default)]
    pub stiffness: Option<f64>,
    /// K_pe over the particle–particle K_n when `stiffness` is not given. The default 4
    /// keeps grains within ~¼ of a radius of the edge at the detonation's breakout (where
    /// the load peaks; a few % afterwards) while the penalty contact's stable step stays
    /// within a factor ~1.5 of the DEM's own (both measured on ring_small; the overlap
    /// scales as 1/K_pe, the step as 1/√K_pe).
    #[serde(default = "default_stiffness_ratio")]
    pub stiffness_ratio: f64,
}

fn default_stiffness_ratio() -> f64 {
    4.0
}

impl Default for CouplingSpec {
    fn default() -> Self {
        CouplingSpec {
            stiffness: None,
            stiffness_ratio: default_stiffness_ratio(),
        }
    }
}

/// `[run]`: time stepping.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunSpec {
    /// Simulated time (s).
    pub duration: f64,
    /// Fraction of the charge's stable (CFL) step.
    #[serde(default = "default_safety")]
    pub safety: f64,
    /// Fraction of the particles' stable step: their damped contacts need about ten
    /// steps per oscillation to resolve a collision's restitution.
    #[serde(default = "default_dem_safety")]
    pub dem_safety: f64,
    /// Fraction of the penalty contact's stable step. The charge–particle spring is
    /// undamped and serves only to keep the bodies apart, so it needs stability, not
    /// resolution.
    #[serde(default = "default_coupling_safety")]
    pub coupling_safety: f64,
    /// Verlet skin (m); default half the mean particle diameter (the ring moves fast
    /// as a whole, so a wide skin saves rebuilds at little cost in pairs).
    #[serde(default)]
    pub skin: Option<f64>,
    /// The run stops, as LS-DYNA's DTMIN does, once its step falls below this fraction
    /// of the step it started with: a step that collapses means a crushed element or a
    /// runaway contact, and the bound makes the step count `grains check` prints an
    /// upper bound (the small rings' steps fall to 0.76 of the initial one).
    #[serde(default = "default_min_dt_ratio")]
    pub min_dt_ratio: f64,
}

fn default_safety() -> f64 {
    0.5
}
fn default_min_dt_ratio() -> f64 {
    0.2
}
fn default_dem_safety() -> f64 {
    0.3
}
fn default_coupling_safety() -> f64 {
    0.5
}

/// `[analysis]`: how the ring's layers are told apart.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnalysisSpec {
    /// Local packing fraction at or above which particles belong to the compact band
    /// (default the paper's 0.84, as the dispersal analysis's; 0.8 until issue 28).
    #[serde(default = "default_band_fraction")]
    pub band_fraction: f64,
    /// Radial bin width in mean diameters (the paper's 5 d0).
    #[serde(default = "default_radial_bin")]
    pub radial_bin: f64,
    /// Angular sectors; default the paper's 180 (dθ = π/90), or fewer so that a
    /// sector's arc at the ring's inner radius spans at least 4 mean diameters.
    #[serde(default)]
    pub sectors: Option<usize>,
    /// Mean contact stress (Pa) above which a particle counts as stressed, for the
    /// pressure front.
    #[serde(default = "default_stressed")]
    pub stressed_pressure: f64,
    /// Fraction of the run at its end over which the band velocity is averaged to give
    /// the terminal velocity.
    #[serde(default = "default_terminal_window")]
    pub terminal_window: f64,
    /// Keep the grains' energy ledger (contact damping, friction, stored contact
    /// energy; history columns and `figures.energy_ledger`). Default on: it changes
    /// nothing in the run and costs a few per cent of the particles' step.
    #[serde(default = "default_true")]
    pub energy_ledger: bool,
    /// `[analysis.dispersal]`: the dispersal analysis of xue-2019 §§4.2–5 during the
    /// run (fields, fronts, profiles, band and spall, shear bands, jets).
    #[serde(default)]
    pub dispersal: Option<crate::dispersal::DispersalSettings>,
}

fn default_true() -> bool {
    true
}

fn default_band_fraction() -> f64 {
    grains_analysis::ring::BAND_PHI
}
fn default_radial_bin() -> f64 {
    5.0
}
fn default_stressed() -> f64 {
    5.0e7
}
fn default_terminal_window() -> f64 {
    0.1
}

impl Default for AnalysisSpec {
    fn default() -> Self {
        AnalysisSpec {
            band_fraction: default_band_fraction(),
            radial_bin: default_radial_bin(),
            sectors: None,
            stressed_pressure: default_stressed(),
            terminal_window: default_terminal_window(),
            energy_ledger: true,
            dispersal: None,
        }
    }
}

/// One `[[check]]`.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum CheckSpec {
    /// Largest relative deviation of the half-CJ-pressure front's arrival from r/D_CJ
    /// (radial bins from a quarter of the radius out), at most `tolerance`.
    DetonationArrival {
        /// Relative tolerance.
        #[serde(default = "two_percent")]
        tolerance: f64,
    },
    /// |internal + kinetic − (initial chemical + internal)| / the latter at the end,
    /// at most `tolerance` (needs no damping and no ring).
    EnergyConservation {
        /// Relative tolerance.
        #[serde(default = "two_percent")]
        tolerance: f64,
    },
    /// Terminal band velocity against the paper's simulated value.
    BandVelocity {
        /// Expected velocity (m/s).
        expected: f64,
        /// Relative tolerance.
        #[serde(default = "fifteen_percent")]
        tolerance: f64,
    },
    /// Terminal band velocity between the run's compaction (snowplough) estimate and its
    /// lossless JWL-expansion ceiling (`figures.models`), for the tests whose paper
    /// values exceed what the cited JWL sets can deliver (xue-2019 tests 3, 5, 6); the
    /// paper's value and the classic Gurney velocity are reported beside it.
    BandVelocityBracket {
        /// The paper's simulated terminal band velocity (m/s), reported, not checked.
        paper: f64,
    },
    /// |1 − ring kinetic energy / work the charge did on the ring| at the end, at most
    /// `tolerance`: the coupling's energy bookkeeping, meaningful for elastic
    /// (restitution 1), frictionless grains, which cannot dissipate.
    RingEnergyTransfer {
        /// Relative tolerance.
        #[serde(default = "two_percent")]
        tolerance: f64,
    },
    /// Ring mass over charge mass against the paper's F/B (also evaluated by `check`).
    FillToBurster {
        /// Expected F/B.
        expected: f64,
        /// Relative tolerance.
        #[serde(default = "five_percent")]
        tolerance: f64,
        /// A value the paper lists beside the expected one, reported, not checked
        /// (xue-2019's Table 2 F/B, which its Table 1 packing fraction and grain
        /// density do not give: VALIDATION.md).
        #[serde(default)]
        paper: Option<f64>,
    },
    /// The share of the times analysed in [`from`, `to`] at which the shear rate at the
    /// compact band's inner perimeter has its leading azimuthal mode equal to `mode`
    /// (xue-2019 §§5.4–5.5: an ordered packing's band is hexagonal, its spiral shear
    /// bands gather in six groups between the corners; an amorphous one's are spread
    /// evenly). Exactly one of `at_least` and `at_most`. Needs `[analysis.dispersal]`.
    ShearBandMode {
        /// The mode (lobes round the ring).
        mode: usize,
        /// Start of the window (s).
        from: f64,
        /// End of the window (s).
        to: f64,
        /// Least share.
        #[serde(default)]
        at_least: Option<f64>,
        /// Largest share.
        #[serde(default)]
        at_most: Option<f64>,
    },
    /// The median over the times analysed in [`from`, `to`] (with a band) of the number
    /// of groups of spiral shear bands at the compact band's inner perimeter (xue-2019
    /// §§5.4–5.5, Fig. 11: six in an ordered packing, tens in an amorphous one).
    /// Exactly one of `at_least` and `at_most`. Needs `[analysis.dispersal]`.
    ShearBandCount {
        /// Start of the window (s).
        from: f64,
        /// End of the window (s).
        to: f64,
        /// Least median.
        #[serde(default)]
        at_least: Option<f64>,
        /// Largest median.
        #[serde(default)]
        at_most: Option<f64>,
    },
}

fn two_percent() -> f64 {
    0.02
}
fn five_percent() -> f64 {
    0.05
}
fn fifteen_percent() -> f64 {
    0.15
}

impl CheckSpec {
    /// The relative tolerance; for `shear_band_mode` its bound on the share, for
    /// `shear_band_count` its bound on the median; NaN for `band_velocity_bracket`.
    pub fn tolerance(&self) -> f64 {
        match self {
            CheckSpec::DetonationArrival { tolerance }
            | CheckSpec::EnergyConservation { tolerance }
            | CheckSpec::RingEnergyTransfer { tolerance }
            | CheckSpec::BandVelocity { tolerance, .. }
            | CheckSpec::FillToBurster { tolerance, .. } => *tolerance,
            // The bracket comes from the run's models; nothing to tolerate.
            CheckSpec::BandVelocityBracket { .. } => f64::NAN,
            CheckSpec::ShearBandMode {
                at_least, at_most, ..
            }
            | CheckSpec::ShearBandCount {
                at_least, at_most, ..
            } => at_least.or(*at_most).unwrap_or(f64::NAN),
        }
    }
}
