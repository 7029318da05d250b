//! The scenario file: what a user writes to describe a DEM run, parsed strictly
//! (`deny_unknown_fields` everywhere) and reported with one-line errors.

use grains_dem::{Material, WallShape};
use serde::{Deserialize, Serialize};

/// A whole scenario file.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Engine tag; `"dem"` (the default) for this scenario type.
    #[serde(default)]
    pub engine: Option<String>,
    /// `2` (the default; `dim = 3` is a [`crate::dem3d`] scenario).
    #[serde(default)]
    pub dim: Option<u32>,
    /// Name of the run; the default output directory is `runs/<name>`.
    pub name: String,
    /// Free text shown by `grains check`.
    #[serde(default)]
    pub description: String,
    /// Simulation box.
    pub domain: DomainSpec,
    /// Gravitational acceleration (m/s²).
    #[serde(default)]
    pub gravity: [f64; 2],
    /// The contact law of every pair, and the pairs that have their own (3D's keys but
    /// twisting; default: the material route, the law derived from the materials).
    #[serde(default = "crate::law::dim2::material_law")]
    pub contact: crate::law::dim2::LawSpec,
    /// Materials, referred to by name.
    #[serde(rename = "material")]
    pub materials: Vec<Material>,
    /// Groups of particles.
    #[serde(rename = "particles", default)]
    pub particles: Vec<ParticleSource>,
    /// Rigid walls.
    #[serde(rename = "wall", default)]
    pub walls: Vec<WallSpec>,
    /// Time stepping and stopping.
    pub run: RunSpec,
    /// What is written and how often.
    #[serde(default)]
    pub output: crate::output::OutputSpec,
    /// Validation checks written into summary.json.
    #[serde(rename = "check", default)]
    pub checks: Vec<CheckSpec>,
    /// Figures reported in summary.json (not checked).
    #[serde(rename = "figure", default)]
    pub figures: Vec<FigureSpec>,
    /// `[dispersal]`: the dispersal analysis about `centre` during the run (a ring of
    /// grains driven outward, as xue-2019's).
    #[serde(default)]
    pub dispersal: Option<Box<crate::dispersal::DispersalSettings>>,
    /// `[parallel]`: how a run under `mpirun` is spread over its ranks.
    #[serde(default)]
    pub parallel: Option<super::ranks::ParallelSpec>,
}

/// `[domain]`: box corners and periodicity.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DomainSpec {
    /// Lower-left corner (m).
    pub lo: [f64; 2],
    /// Upper-right corner (m).
    pub hi: [f64; 2],
    /// Periodicity along x and y.
    #[serde(default)]
    pub periodic: [bool; 2],
}

/// One `[[particles]]` group.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(tag = "source", rename_all = "snake_case", deny_unknown_fields)]
pub enum ParticleSource {
    /// Disks listed one by one.
    List {
        /// Material name.
        material: String,
        /// The disks.
        disks: Vec<DiskSpec>,
    },
    /// A rectangle filled row by row, bottom-up, with disks of random radii on a
    /// square lattice of pitch `spacing` × the largest diameter (so none overlap).
    Lattice {
        /// Material name.
        material: String,
        /// Region to fill.
        region: Rect,
        /// Number of disks.
        count: usize,
        /// Radius distribution.
        radius: RadiusSpec,
        /// Lattice pitch as a multiple of the largest diameter (≥ 1).
        #[serde(default = "default_spacing")]
        spacing: f64,
        /// Random initial speeds up to this value (m/s), in random directions.
        #[serde(default)]
        speed: f64,
        /// Random seed.
        #[serde(default)]
        seed: u64,
    },
    /// A LAMMPS data file (`atom_style sphere`, as `write_data` writes it): positions,
    /// diameters and, if present, velocities and angular velocities. Masses come from the
    /// material's density as disks (πr²ρ), not from the file's density column.
    LammpsData {
        /// Material name.
        material: String,
        /// Path, relative to the scenario file.
        path: String,
        /// Take velocities and angular velocities from the file (default true).
        #[serde(default = "default_true")]
        velocities: bool,
    },
    /// A packing file: one disk per line `x y r` (SI units), `#` comments.
    File {
        /// Material name.
        material: String,
        /// Path, relative to the scenario file.
        path: String,
    },
}

fn default_true() -> bool {
    true
}

fn default_spacing() -> f64 {
    1.05
}

/// One disk of a `list` group.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DiskSpec {
    /// Centre (m).
    pub at: [f64; 2],
    /// Radius (m).
    pub radius: f64,
    /// Initial velocity (m/s).
    #[serde(default)]
    pub velocity: [f64; 2],
    /// Initial angular velocity (rad/s).
    #[serde(default)]
    pub omega: f64,
}

/// An axis-aligned rectangle.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Rect {
    /// Lower-left corner.
    pub lo: [f64; 2],
    /// Upper-right corner.
    pub hi: [f64; 2],
}

/// A radius distribution.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
#[serde(tag = "distribution", rename_all = "snake_case", deny_unknown_fields)]
pub enum RadiusSpec {
    /// Every disk the same.
    Constant {
        /// Radius (m).
        value: f64,
    },
    /// Uniform on [min, max].
    Uniform {
        /// Smallest radius (m).
        min: f64,
        /// Largest radius (m).
        max: f64,
    },
}

/// One `[[wall]]`: its shape (`shape = "segment" | "circle"`), name and material.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "snake_case", deny_unknown_fields)]
pub enum WallSpec {
    /// A straight segment from `a` to `b`.
    Segment {
        /// Name (history columns `<name>_fx`, ...).
        name: String,
        /// Material name; default: each particle's own material.
        #[serde(default)]
        material: Option<String>,
        /// First end point (m).
        a: [f64; 2],
        /// Second end point (m).
        b: [f64; 2],
    },
    /// A circle; `inside = true` keeps particles inside it.
    Circle {
        /// Name.
        name: String,
        /// Material name; default: each particle's own material.
        #[serde(default)]
        material: Option<String>,
        /// Centre (m).
        centre: [f64; 2],
        /// Radius (m).
        radius: f64,
        /// Particles live inside the circle.
        inside: bool,
    },
}

impl WallSpec {
    /// The wall's name.
    pub fn name(&self) -> &str {
        match self {
            WallSpec::Segment { name, .. } | WallSpec::Circle { name, .. } => name,
        }
    }

    /// The wall's material name, if given.
    pub fn material(&self) -> Option<&str> {
        match self {
            WallSpec::Segment { material, .. } | WallSpec::Circle { material, .. } => {
                material.as_deref()
            }
        }
    }

    /// The engine's geometry.
    pub fn shape(&self) -> WallShape {
        match *self {
            WallSpec::Segment { a, b, .. } => WallShape::Segment { a, b },
            WallSpec::Circle {
                centre,
                radius,
                inside,
                ..
            } => WallShape::Circle {
                centre,
                radius,
                inside,
            },
        }
    }
}

/// `[run]`: time stepping and stopping.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunSpec {
    /// Simulated time to run (s); with `stop_kinetic_ratio`, the longest.
    pub duration: f64,
    /// Time step (s); default `safety` × the critical step.
    #[serde(default)]
    pub dt: Option<f64>,
    /// Fraction of the critical time step used when `dt` is not given.
    #[serde(default = "default_safety")]
    pub safety: f64,
    /// Verlet skin (m); default 0.1 × the mean diameter.
    #[serde(default)]
    pub skin: Option<f64>,
    /// Stop once the kinetic energy falls below this fraction of Σ m|g|d̄ (the energy
    /// of lifting every particle by one mean diameter): the bed is then at rest.
    #[serde(default)]
    pub stop_kinetic_ratio: Option<f64>,
    /// How long (s) the kinetic energy must stay below that threshold before the run
    /// stops, so that a momentary minimum of a bouncing bed does not count as rest.
    /// Default: 20 history intervals.
    #[serde(default)]
    pub stop_rest_time: Option<f64>,
}

impl RunSpec {
    /// Checks the values (2D and 3D alike) and returns the skin, its default 0.1 × the
    /// mean diameter `mean_d`.
    pub fn validate(&self, mean_d: f64) -> Result<f64, grains_core::input::InputError> {
        use grains_core::input::{positive, InputError};
        let skin = self.skin.unwrap_or(0.1 * mean_d);
        positive("run.skin", skin)?;
        positive("run.duration", self.duration)?;
        if !(self.safety > 0.0 && self.safety <= 1.0) {
            return Err(InputError::new(
                "run.safety",
                self.safety,
                "must be in (0, 1]",
            ));
        }
        if let Some(r) = self.stop_kinetic_ratio {
            positive("run.stop_kinetic_ratio", r)?;
        }
        if let Some(t) = self.stop_rest_time {
            positive("run.stop_rest_time", t)?;
        }
        Ok(skin)
    }
}

fn default_safety() -> f64 {
    0.1
}

/// One `[[check]]`: a measured figure compared with its expected value.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum CheckSpec {
    /// Restitution of a binary collision, −v_n(after)/v_n(before), against the pair's e.
    Restitution {
        /// Check name.
        name: String,
        /// The two particles (creation order, from 0).
        particles: [u32; 2],
        /// Relative tolerance.
        tolerance: f64,
    },
    /// Duration of a binary collision against π/ω_d of the damped oscillator.
    ContactTime {
        /// Check name.
        name: String,
        /// The two particles.
        particles: [u32; 2],
        /// Relative tolerance.
        tolerance: f64,
    },
    /// Tangential velocity after a wall impact, against rigid-body impulse theory.
    ImpactTangentialVelocity {
        /// Check name.
        name: String,
        /// The particle.
        particle: u32,
        /// Wall name.
        wall: String,
        /// Relative tolerance.
        tolerance: f64,
    },
    /// Angular velocity after a wall impact, against rigid-body impulse theory.
    ImpactAngularVelocity {
        /// Check name.
        name: String,
        /// The particle.
        particle: u32,
        /// Wall name.
        wall: String,
        /// Relative tolerance.
        tolerance: f64,
    },
    /// Force on a wall along gravity at the end, over the total weight (expected 1).
    WallForceOverWeight {
        /// Check name.
        name: String,
        /// Wall name.
        wall: String,
        /// Relative tolerance.
        tolerance: f64,
    },
    /// The first collision of `particle` with `partner` (another particle) or `wall`
    /// under the granular law, as in 3D ([`crate::collision`]).
    Collision {
        /// Check name.
        name: String,
        /// What is measured.
        measure: crate::collision::Measure,
        /// The particle (creation order, from 0).
        particle: u32,
        /// The other particle.
        #[serde(default)]
        partner: Option<u32>,
        /// Or the wall.
        #[serde(default)]
        wall: Option<String>,
        /// Relative tolerance.
        tolerance: f64,
    },
}

impl CheckSpec {
    /// The check's name.
    pub fn name(&self) -> &str {
        match self {
            CheckSpec::Restitution { name, .. }
            | CheckSpec::ContactTime { name, .. }
            | CheckSpec::ImpactTangentialVelocity { name, .. }
            | CheckSpec::ImpactAngularVelocity { name, .. }
            | CheckSpec::WallForceOverWeight { name, .. }
            | CheckSpec::Collision { name, .. } => name,
        }
    }

    /// The check's relative tolerance.
    pub fn tolerance(&self) -> f64 {
        match self {
            CheckSpec::Restitution { tolerance, .. }
            | CheckSpec::ContactTime { tolerance, .. }
            | CheckSpec::ImpactTangentialVelocity { tolerance, .. }
            | CheckSpec::ImpactAngularVelocity { tolerance, .. }
            | CheckSpec::WallForceOverWeight { tolerance, .. }
            | CheckSpec::Collision { tolerance, .. } => *tolerance,
        }
    }
}

/// One `[[figure]]`: a figure computed at the end and reported in summary.json.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum FigureSpec {
    /// Area fraction of disks whose centres lie in `region` (default: the particles'
    /// bounding box less `margin` mean diameters on each non-periodic side).
    PackingFraction {
        /// Name in summary.json.
        name: String,
        /// Region to measure in.
        #[serde(default)]
        region: Option<Rect>,
        /// Margin in mean diameters when no region is given.
        #[serde(default = "default_margin")]
        margin: f64,
    },
    /// Mean number of contacts per particle (walls count).
    MeanCoordination {
        /// Name in summary.json.
        name: String,
    },
}

fn default_margin() -> f64 {
    3.0
}
