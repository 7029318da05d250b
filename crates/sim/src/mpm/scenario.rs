//! The MPM scenario file (`engine = "mpm"`), parsed strictly (`deny_unknown_fields`
//! everywhere) and reported with one-line errors.

use grains_mpm::{Geometry, Material};
use serde::{Deserialize, Serialize};

/// A whole scenario file.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Engine tag: `"mpm"`.
    pub engine: String,
    /// Name of the run; the default output directory is `runs/<name>`.
    pub name: String,
    /// Free text shown by `grains check`.
    #[serde(default)]
    pub description: String,
    /// Gravitational acceleration (m/s²).
    #[serde(default)]
    pub gravity: [f64; 2],
    /// Background grid and point density.
    pub grid: GridSpec,
    /// Numerical method.
    #[serde(default)]
    pub method: MethodSpec,
    /// Which domain edges are walls.
    #[serde(default)]
    pub walls: WallsSpec,
    /// Materials, referred to by name.
    #[serde(rename = "material")]
    pub materials: Vec<Material>,
    /// Bodies.
    #[serde(rename = "body", default)]
    pub bodies: Vec<BodySpec>,
    /// Contact law between bodies.
    #[serde(default)]
    pub contact: ContactSpec,
    /// Time stepping.
    pub run: RunSpec,
    /// What is written and how often.
    #[serde(default)]
    pub output: crate::output::OutputSpec,
    /// Validation checks written into summary.json.
    #[serde(rename = "check", default)]
    pub checks: Vec<CheckSpec>,
}

/// `[grid]`: the domain, its cells and the material points per cell.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GridSpec {
    /// Lower-left corner of the domain (m).
    pub lo: [f64; 2],
    /// Upper-right corner (m); the domain must hold a whole number of cells.
    pub hi: [f64; 2],
    /// Cell size h (m).
    pub cell_size: f64,
    /// Material points per cell along each axis (2 → 4 points per cell).
    #[serde(default = "default_ppc")]
    pub particles_per_cell: u32,
}

fn default_ppc() -> u32 {
    2
}

/// `[method]`: shape function, stress update, transfer.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MethodSpec {
    /// `"linear"`, `"gimp"` or `"bspline2"`.
    #[serde(default = "default_shape")]
    pub shape: String,
    /// `"usf"`, `"usl"`, `"usavg"` or `"musl"`.
    #[serde(default = "default_update")]
    pub update: String,
    /// FLIP fraction of the particle velocity update (1 = pure FLIP, 0 = PIC).
    #[serde(default = "default_flip")]
    pub flip: f64,
    /// Whether the first contact correction also reaches the particle velocities.
    #[serde(default = "default_true")]
    pub pass1_to_particles: bool,
}

fn default_shape() -> String {
    "gimp".into()
}
fn default_update() -> String {
    "usavg".into()
}
fn default_flip() -> f64 {
    1.0
}
fn default_true() -> bool {
    true
}

impl Default for MethodSpec {
    fn default() -> Self {
        MethodSpec {
            shape: default_shape(),
            update: default_update(),
            flip: default_flip(),
            pass1_to_particles: true,
        }
    }
}

/// `[walls]`: each domain edge is a rigid wall (with friction μ) or open.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WallsSpec {
    /// x = lo.x.
    #[serde(default)]
    pub left: Option<WallSpec>,
    /// x = hi.x.
    #[serde(default)]
    pub right: Option<WallSpec>,
    /// y = lo.y.
    #[serde(default)]
    pub bottom: Option<WallSpec>,
    /// y = hi.y.
    #[serde(default)]
    pub top: Option<WallSpec>,
}

/// One wall.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WallSpec {
    /// Coulomb friction coefficient (0: free slip).
    #[serde(default)]
    pub mu: f64,
}

/// One `[[body]]`.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// Name (history columns `<name>_x`, ...).
    pub name: String,
    /// Material name.
    pub material: String,
    /// Initial region.
    pub geometry: Geometry,
    /// Initial velocity (m/s); for a rigid body, its prescribed velocity.
    #[serde(default)]
    pub velocity: [f64; 2],
    /// Rigid mover with prescribed velocity.
    #[serde(default)]
    pub rigid: bool,
}

/// A contact law's name.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LawName {
    /// Coulomb friction with `mu`.
    Coulomb,
    /// One shared velocity field.
    NoSlip,
}

/// `[contact]`: the law between any two bodies, and per-pair overrides.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    /// Default law.
    #[serde(default = "default_law")]
    pub law: LawName,
    /// Friction coefficient of the default Coulomb law.
    #[serde(default)]
    pub mu: Option<f64>,
    /// Correct only where two bodies touch, judged from where their material sits at
    /// each node (Nairn's position method), instead of wherever their grid supports
    /// overlap. (Walls always use approach with their exact normals.)
    #[serde(default = "default_true")]
    pub separation_test: bool,
    /// With the separation test: contact once the centroid separation is below this
    /// multiple of its value for touching bodies.
    #[serde(default = "default_separation_factor")]
    pub separation_factor: f64,
    /// Overrides.
    #[serde(default)]
    pub pair: Vec<PairSpec>,
}

fn default_separation_factor() -> f64 {
    1.05
}

fn default_law() -> LawName {
    LawName::Coulomb
}

impl Default for ContactSpec {
    fn default() -> Self {
        ContactSpec {
            law: LawName::Coulomb,
            mu: None,
            separation_test: true,
            separation_factor: default_separation_factor(),
            pair: Vec::new(),
        }
    }
}

/// One `[[contact.pair]]`.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PairSpec {
    /// The two body names.
    pub bodies: [String; 2],
    /// Law.
    pub law: LawName,
    /// Friction coefficient for `coulomb`.
    #[serde(default)]
    pub mu: Option<f64>,
}

/// `[run]`.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunSpec {
    /// Simulated time (s).
    pub duration: f64,
    /// Time step (s); refused above the stable limit. Default: `safety` × the limit.
    #[serde(default)]
    pub dt: Option<f64>,
    /// Fraction of the stable limit used when `dt` is not given.
    #[serde(default = "default_safety")]
    pub safety: f64,
}

fn default_safety() -> f64 {
    0.2
}

/// Which way a body on an incline is expected to move.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum InclineMotion {
    /// A block sliding: a = g(sin θ − μ cos θ).
    Slide,
    /// A cylinder: a = (2/3) g sin θ if μ ≥ tan θ / 3, else it slips as a block.
    Roll,
}

/// One `[[check]]`.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum CheckSpec {
    /// Total energy at t = 0 against Σ ½ ρ A |v|² of the free bodies' exact shapes.
    InitialEnergy {
        /// Check name.
        name: String,
        /// Relative tolerance.
        tolerance: f64,
    },
    /// One component of the total momentum at t = 0 against Σ ρ A v.
    InitialMomentum {
        /// Check name.
        name: String,
        /// `"x"` or `"y"`.
        component: String,
        /// Relative tolerance.
        tolerance: f64,
    },
    /// Fraction of the initial total energy lost, measured in the free flight after
    /// wall impact number `after_impact` (from 1) of `body`.
    EnergyLoss {
        /// Check name.
        name: String,
        /// Body whose impacts count.
        body: String,
        /// Impact number.
        after_impact: usize,
        /// Largest fraction allowed.
        max: f64,
    },
    /// Largest deviation of |Σ m v| from its initial value in free flight (between
    /// impacts), as a fraction.
    MomentumBetweenImpacts {
        /// Check name.
        name: String,
        /// Body whose impacts count.
        body: String,
        /// Largest fraction allowed.
        max: f64,
    },
    /// Total accumulated rotation of a body (degrees, absolute value).
    Rotation {
        /// Check name.
        name: String,
        /// Body.
        body: String,
        /// Largest angle allowed (degrees).
        max_deg: f64,
    },
    /// Tangential velocity after wall impact number `impact`, against rigid-disk impulse
    /// theory with the wall's μ.
    ImpactTangentialVelocity {
        /// Check name.
        name: String,
        /// Body (a disk).
        body: String,
        /// Impact number (from 1).
        impact: usize,
        /// Relative tolerance.
        tolerance: f64,
    },
    /// Spin after wall impact number `impact`, against rigid-disk impulse theory.
    ImpactSpin {
        /// Check name.
        name: String,
        /// Body (a disk).
        body: String,
        /// Impact number (from 1).
        impact: usize,
        /// Relative tolerance.
        tolerance: f64,
    },
    /// Acceleration of a body down an incline (least-squares fit of its centre's
    /// position along the slope from time `after` on) against rigid-body theory.
    Acceleration {
        /// Check name.
        name: String,
        /// The moving body.
        body: String,
        /// The body it rests on (its contact law gives μ).
        on: String,
        /// Outward normal of the incline's surface.
        #[serde(default = "default_normal")]
        normal: [f64; 2],
        /// Sliding block or rolling cylinder.
        motion: InclineMotion,
        /// Start of the fit (s).
        #[serde(default)]
        after: f64,
        /// Relative tolerance.
        tolerance: f64,
    },
    /// Energy loss after impact `after_impact` no larger than that of a reference
    /// scenario (run first, without output).
    EnergyLossBelowReference {
        /// Check name.
        name: String,
        /// Body whose impacts count (same name in both).
        body: String,
        /// Impact number.
        after_impact: usize,
        /// The reference scenario, relative to this file.
        reference: String,
    },
}

fn default_normal() -> [f64; 2] {
    [0.0, 1.0]
}

impl CheckSpec {
    /// The body the check watches, if any.
    pub fn body(&self) -> Option<&str> {
        match self {
            CheckSpec::InitialEnergy { .. } | CheckSpec::InitialMomentum { .. } => None,
            CheckSpec::EnergyLoss { body, .. }
            | CheckSpec::MomentumBetweenImpacts { body, .. }
            | CheckSpec::Rotation { body, .. }
            | CheckSpec::ImpactTangentialVelocity { body, .. }
            | CheckSpec::ImpactSpin { body, .. }
            | CheckSpec::Acceleration { body, .. }
            | CheckSpec::EnergyLossBelowReference { body, .. } => Some(body),
        }
    }
}
