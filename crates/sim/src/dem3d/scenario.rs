//! The 3D DEM scenario (`engine = "dem"`, `dim = 3`): spheres, walls and contact laws
//! per material pair, in the 2D scenario's style (its `[run]`, `[output]`, radius
//! distributions and materials are the same tables), parsed strictly.

pub use crate::collision::Measure;
use crate::dem::scenario::{RadiusSpec, RunSpec};
pub use crate::law::dim3::{LawModel, LawSpec, NormalSpec};
use grains_dem3d::Material;
use serde::{Deserialize, Serialize};

/// A whole 3D scenario file.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// `"dem"`.
    #[serde(default)]
    pub engine: Option<String>,
    /// 3.
    pub dim: u32,
    /// Name of the run; the default output directory is `runs/<name>`.
    pub name: String,
    /// Free text shown by `grains check`.
    #[serde(default)]
    pub description: String,
    /// Simulation box.
    pub domain: DomainSpec,
    /// Gravitational acceleration (m/s²), three components.
    #[serde(default)]
    pub gravity: [f64; 3],
    /// The contact law of every pair, and the pairs that have their own.
    pub contact: LawSpec,
    /// Materials, referred to by name.
    #[serde(rename = "material")]
    pub materials: Vec<Material>,
    /// Groups of spheres.
    #[serde(rename = "particles", default)]
    pub particles: Vec<SphereSource>,
    /// Spheres poured in during the run.
    #[serde(default)]
    pub pour: Option<super::pour::PourSpec>,
    /// Rigid walls.
    #[serde(rename = "wall", default)]
    pub walls: Vec<WallSpec>,
    /// Time stepping and stopping (as in 2D).
    pub run: RunSpec,
    /// What is written and how often.
    #[serde(default)]
    pub output: crate::output::OutputSpec,
    /// What the run analyses beside its history.
    #[serde(default)]
    pub analysis: AnalysisSpec,
    /// Validation checks written into summary.json.
    #[serde(rename = "check", default)]
    pub checks: Vec<CheckSpec>,
    /// `[parallel]`: how a run under `mpirun` is spread over its ranks.
    #[serde(default)]
    pub parallel: Option<super::ranks::ParallelSpec>,
}

/// `[analysis]`: what the run analyses beside its history.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnalysisSpec {
    /// Keep the grains' energy ledger (stored contact energy, dissipation by kind, the
    /// law's changes without work, the walls' and pours' work in; history columns,
    /// `plots/energy_ledger.png`, `figures.energy_ledger`), as the FEM–DEM ring's
    /// `[analysis] energy_ledger`. Default on: it changes nothing in the run.
    #[serde(default = "default_true")]
    pub energy_ledger: bool,
}

impl Default for AnalysisSpec {
    fn default() -> Self {
        AnalysisSpec {
            energy_ledger: true,
        }
    }
}

fn default_true() -> bool {
    true
}

/// `[domain]`: box corners and periodicity along x, y, z.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DomainSpec {
    /// Lower corner (m).
    pub lo: [f64; 3],
    /// Upper corner (m).
    pub hi: [f64; 3],
    /// Periodicity along x, y and z.
    #[serde(default)]
    pub periodic: [bool; 3],
}

/// A region spheres are placed in.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "snake_case", deny_unknown_fields)]
pub enum RegionSpec {
    /// An axis-aligned box.
    Box {
        /// Lower corner (m).
        lo: [f64; 3],
        /// Upper corner (m).
        hi: [f64; 3],
    },
    /// A vertical cylinder (axis along z) standing on `base`.
    Cylinder {
        /// Centre of its bottom face (m).
        base: [f64; 3],
        /// Radius (m).
        radius: f64,
        /// Height (m).
        height: f64,
    },
}

/// One `[[particles]]` group of spheres.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(tag = "source", rename_all = "snake_case", deny_unknown_fields)]
pub enum SphereSource {
    /// Spheres listed one by one.
    List {
        /// Material name.
        material: String,
        /// The spheres.
        spheres: Vec<SphereSpec>,
    },
    /// A region filled layer by layer from the bottom (z) on a cubic lattice of pitch
    /// `spacing` × the largest diameter.
    Lattice {
        /// Material name.
        material: String,
        /// Region to fill.
        region: RegionSpec,
        /// Number of spheres.
        count: usize,
        /// Radius distribution.
        radius: RadiusSpec,
        /// Lattice pitch over the largest diameter (≥ 1).
        #[serde(default = "default_spacing")]
        spacing: f64,
        /// Random initial speeds up to this value (m/s).
        #[serde(default)]
        speed: f64,
        /// Random seed.
        #[serde(default)]
        seed: u64,
    },
    /// Spheres at random places in a region, none overlapping another or the region's
    /// edge.
    Random {
        /// Material name.
        material: String,
        /// Region to fill.
        region: RegionSpec,
        /// Number of spheres.
        count: usize,
        /// Radius distribution.
        radius: RadiusSpec,
        /// Random seed.
        #[serde(default)]
        seed: u64,
    },
    /// The spheres of a packing file (`x y z r` per line, `#` lines skipped), as
    /// `grains pack` writes for a spec with `dim = 3`, moved by `offset`.
    File {
        /// Material name.
        material: String,
        /// Path, relative to the scenario file.
        path: String,
        /// Added to every centre (m).
        #[serde(default)]
        offset: [f64; 3],
    },
}

fn default_spacing() -> f64 {
    1.05
}

/// One sphere of a `list` group.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SphereSpec {
    /// Centre (m).
    pub at: [f64; 3],
    /// Radius (m).
    pub radius: f64,
    /// Initial velocity (m/s).
    #[serde(default)]
    pub velocity: [f64; 3],
    /// Initial angular velocity (rad/s).
    #[serde(default)]
    pub omega: [f64; 3],
}

/// One `[[wall]]`.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "snake_case", deny_unknown_fields)]
pub enum WallSpec {
    /// The infinite plane through `point` with normal `normal`.
    Plane {
        /// Name (history columns `<name>_fx`, ...).
        name: String,
        /// Material name; default: each particle's own.
        #[serde(default)]
        material: Option<String>,
        /// A point of the plane (m).
        point: [f64; 3],
        /// Its normal.
        normal: [f64; 3],
        /// Velocity of translation (m/s); default at rest.
        #[serde(default)]
        velocity: Option<[f64; 3]>,
        /// Angular velocity about the normal through `point` (rad/s); default none.
        #[serde(default)]
        omega: Option<[f64; 3]>,
    },
    /// A flat ring: the plane through `centre` with normal `normal` between the radii
    /// `hole` (default 0: no hole) and `radius` (default: unbounded); a silo's floor
    /// with its orifice. Spheres touch its faces and its rims.
    Disk {
        /// Name.
        name: String,
        /// Material name.
        #[serde(default)]
        material: Option<String>,
        /// Centre (m).
        centre: [f64; 3],
        /// Its normal.
        normal: [f64; 3],
        /// Outer radius (m).
        #[serde(default)]
        radius: Option<f64>,
        /// Radius of the hole (m).
        #[serde(default)]
        hole: Option<f64>,
        /// Velocity of translation (m/s); default at rest.
        #[serde(default)]
        velocity: Option<[f64; 3]>,
        /// Angular velocity about the normal through `centre` (rad/s); default none.
        #[serde(default)]
        omega: Option<[f64; 3]>,
    },
    /// A rectangle about `centre` in the plane with normal `normal`: `size[0]` along
    /// `edge`, `size[1]` across. It may translate, not turn.
    Rectangle {
        /// Name.
        name: String,
        /// Material name.
        #[serde(default)]
        material: Option<String>,
        /// Centre (m).
        centre: [f64; 3],
        /// Its normal.
        normal: [f64; 3],
        /// Direction of the first side.
        edge: [f64; 3],
        /// Side lengths (m).
        size: [f64; 2],
        /// Velocity of translation (m/s); default at rest.
        #[serde(default)]
        velocity: Option<[f64; 3]>,
    },
    /// The six faces of an axis-aligned box, particles inside: walls `<name>_xlo`,
    /// `<name>_xhi`, ..., `<name>_zhi`.
    Box {
        /// Name prefix.
        name: String,
        /// Material name.
        #[serde(default)]
        material: Option<String>,
        /// Lower corner (m).
        lo: [f64; 3],
        /// Upper corner (m).
        hi: [f64; 3],
    },
    /// An infinite cylinder; `inside = true` keeps particles inside.
    Cylinder {
        /// Name.
        name: String,
        /// Material name.
        #[serde(default)]
        material: Option<String>,
        /// A point on the axis (m).
        point: [f64; 3],
        /// Axis direction.
        axis: [f64; 3],
        /// Radius (m).
        radius: f64,
        /// Particles live inside.
        inside: bool,
        /// Velocity of translation (m/s); default at rest.
        #[serde(default)]
        velocity: Option<[f64; 3]>,
        /// Angular velocity about the axis (a drum) (rad/s); default none.
        #[serde(default)]
        omega: Option<[f64; 3]>,
        /// Time (s) from which the wall no longer acts: a column's confining tube taken
        /// away at once. Default: never.
        #[serde(default)]
        release: Option<f64>,
    },
    /// A sphere; `inside = true` keeps particles inside.
    Sphere {
        /// Name.
        name: String,
        /// Material name.
        #[serde(default)]
        material: Option<String>,
        /// Centre (m).
        centre: [f64; 3],
        /// Radius (m).
        radius: f64,
        /// Particles live inside.
        inside: bool,
    },
}

/// One `[[check]]`.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum CheckSpec {
    /// The first collision of `particle` with `partner` (another particle) or `wall`.
    Collision {
        /// Check name.
        name: String,
        /// What is measured.
        measure: Measure,
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
    /// Force on a wall against gravity at the end, over the total weight (expected 1).
    WallForceOverWeight {
        /// Check name.
        name: String,
        /// Wall name.
        wall: String,
        /// Relative tolerance.
        tolerance: f64,
    },
    /// A particle's velocity along `direction` at the end, against `expected` (a value
    /// the scenario derives and states, e.g. 2/7 of a belt's speed for a sphere it
    /// brings to rolling).
    FinalVelocity {
        /// Check name.
        name: String,
        /// The particle (creation order, from 0).
        particle: u32,
        /// The direction measured along (need not be unit).
        direction: [f64; 3],
        /// The expected velocity (m/s).
        expected: f64,
        /// Relative tolerance.
        tolerance: f64,
    },
    /// The dynamic angle of repose in the rotating drum `wall` (a cylinder), averaged
    /// over history samples from `after` on, within [`lo`, `hi`] degrees.
    ReposeAngle {
        /// Check name.
        name: String,
        /// The drum's wall name.
        wall: String,
        /// Start of the averaging (s): after spin-up.
        after: f64,
        /// Lowest angle allowed (degrees).
        lo: f64,
        /// Highest angle allowed (degrees).
        hi: f64,
    },
    /// The steady discharge rate W through the hole of the floor `wall` (a disk):
    /// the slope of the mass below the floor against time from `after` on, within
    /// Beverloo's W = C ρ_b √g (D − k d)^{5/2} over the literature's spread, C 0.55–0.65
    /// and k 1.3–2.9, with ρ_b = `packing` × the grains' density.
    Beverloo {
        /// Check name.
        name: String,
        /// The floor's wall name.
        wall: String,
        /// Start of the steady window (s).
        after: f64,
        /// Solid fraction of the flowing bed, for its bulk density.
        packing: f64,
    },
    /// The mass of the spheres whose centres lie in `region` at the end over the mass
    /// the run holds, poured and initial (expected 1: none escaped the container).
    PouredMass {
        /// Check name.
        name: String,
        /// The container's inside.
        region: RegionSpec,
        /// Relative tolerance.
        tolerance: f64,
    },
    /// A granular column's run-out once the cylinder `wall` (with a `release` time) that
    /// held it is gone: (R∞ − R0)/R0 at the end against Lube et al.'s law for the
    /// column's aspect ratio H0/R0 ([`super::collapse`]).
    Runout {
        /// Check name.
        name: String,
        /// The confining cylinder's wall name.
        wall: String,
        /// Relative tolerance.
        tolerance: f64,
    },
    /// The energy ledger's closure at the end: |kinetic + potential + stored + booked −
    /// work in − initial| over the energy booked through the ledger, at most `max`
    /// (`super::ledger`).
    EnergyClosure {
        /// Check name.
        name: String,
        /// The largest closure allowed.
        max: f64,
    },
    /// The mean torque of the grains on the drum `wall` about its axis over the mean
    /// moment of their weight about it, from `after` on (expected 1).
    DrumTorque {
        /// Check name.
        name: String,
        /// The drum's wall name.
        wall: String,
        /// Start of the averaging (s).
        after: f64,
        /// Relative tolerance.
        tolerance: f64,
    },
}

impl CheckSpec {
    /// The check's name.
    pub fn name(&self) -> &str {
        match self {
            CheckSpec::Collision { name, .. }
            | CheckSpec::WallForceOverWeight { name, .. }
            | CheckSpec::FinalVelocity { name, .. }
            | CheckSpec::ReposeAngle { name, .. }
            | CheckSpec::Beverloo { name, .. }
            | CheckSpec::DrumTorque { name, .. }
            | CheckSpec::Runout { name, .. }
            | CheckSpec::EnergyClosure { name, .. }
            | CheckSpec::PouredMass { name, .. } => name,
        }
    }

    /// The relative tolerance (None for a range).
    pub fn tolerance(&self) -> Option<f64> {
        match self {
            CheckSpec::Collision { tolerance, .. }
            | CheckSpec::WallForceOverWeight { tolerance, .. }
            | CheckSpec::FinalVelocity { tolerance, .. }
            | CheckSpec::DrumTorque { tolerance, .. }
            | CheckSpec::Runout { tolerance, .. }
            | CheckSpec::PouredMass { tolerance, .. } => Some(*tolerance),
            CheckSpec::ReposeAngle { .. }
            | CheckSpec::Beverloo { .. }
            | CheckSpec::EnergyClosure { .. } => None,
        }
    }
}
