//! The MPM scenario file (`engine = "mpm"`), parsed strictly (`deny_unknown_fields`
//! everywhere) and reported with one-line errors.

use grains_mpm::{Geometry, Material, TemperatureHistory};
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
    /// Packing files whose disks become bodies.
    #[serde(rename = "packing", default)]
    pub packings: Vec<super::packing::PackingSpec>,
    /// Contact law between bodies.
    #[serde(default)]
    pub contact: ContactSpec,
    /// Time stepping.
    pub run: RunSpec,
    /// What is written and how often.
    #[serde(default)]
    pub output: crate::output::OutputSpec,
    /// A cell sheared between two rigid boundaries (stresses, strain, locking).
    #[serde(default)]
    pub shear: Option<ShearSpec>,
    /// Validation checks written into summary.json.
    #[serde(rename = "check", default)]
    pub checks: Vec<CheckSpec>,
}

/// `[shear]`: a cell sheared between two rigid boundaries moving along y, the left one at
/// x = lo.x and the right one at x = hi.x (the paper's Figs. 6–8). The force each
/// boundary exerts on the material is the sum of its bodies' contact reactions; over
/// the boundary's length (the grid's height) it is the shear stress σ_xy and the normal
/// stress σ_xx there. The shear strain is the boundaries' relative displacement over
/// the grid's width.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShearSpec {
    /// The rigid bodies that make up the left boundary.
    pub left: Vec<String>,
    /// The rigid bodies that make up the right boundary.
    pub right: Vec<String>,
    /// A locking event: the shear stresses on both boundaries above this (Pa), i.e. a
    /// chain of grains carrying the load across the cell; its peak (mean of the two) and
    /// strain are reported, and the points at the first event's peak are drawn (the force
    /// chains of Fig. 7).
    pub lock_threshold: f64,
    /// The binder, if any: the grains' debonded length is the length of its interface
    /// that has debonded.
    #[serde(default)]
    pub binder: Option<String>,
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
    /// Periodic along y with this period (m): the bottom and top edges are one line. It
    /// must be the domain's height `hi.y − lo.y`.
    #[serde(default)]
    pub periodic_y: Option<f64>,
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
    /// Initial velocity gradient L (1/s), rows `[[∂vx/∂x, ∂vx/∂y], [∂vy/∂x, ∂vy/∂y]]`:
    /// a point at x starts with `velocity + L·x` (e.g. a block already in simple shear).
    #[serde(default)]
    pub velocity_gradient: Option<[[f64; 2]; 2]>,
    /// Rigid mover with prescribed velocity.
    #[serde(default)]
    pub rigid: bool,
    /// A rigid body's velocity over time: rows `[t, vx, vy]`, times strictly increasing,
    /// linear in between, held before the first row and after the last.
    #[serde(default)]
    pub velocity_table: Option<Vec<[f64; 3]>>,
    /// Prescribed temperature of the body (its material's `expansion` turns changes
    /// into thermal strain): `{ history = "rate", initial, rate }` or
    /// `{ history = "table", points = [[t, T], ...] }`.
    #[serde(default)]
    pub temperature: Option<TemperatureHistory>,
    /// Fill `geometry` minus the shapes of these bodies (names; `"*"`: every other
    /// body), e.g. a binder around grains.
    #[serde(default)]
    pub minus: Vec<String>,
}

/// A contact law's name.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LawName {
    /// Coulomb friction with `mu`.
    Coulomb,
    /// One shared velocity field.
    NoSlip,
    /// Bonded up to a normal traction `strength` (Pa), then Coulomb with `mu` where the
    /// bond failed (Bardenhagen et al. 1998).
    Bonded,
}

/// `[contact]`: the law between any two bodies, and per-pair overrides.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    /// Default law.
    #[serde(default = "default_law")]
    pub law: LawName,
    /// Friction coefficient of the default Coulomb law (or of a bonded law once the
    /// bond failed).
    #[serde(default)]
    pub mu: Option<f64>,
    /// Bond strength (Pa) of the default law when it is `"bonded"`.
    #[serde(default)]
    pub strength: Option<f64>,
    /// Correct only where two bodies touch, judged from where their material sits at
    /// each node (Nairn's position method), instead of wherever their grid supports
    /// overlap. (Walls always use approach with their exact normals.)
    #[serde(default = "default_true")]
    pub separation_test: bool,
    /// With the separation test: contact once the centroid separation is below this
    /// multiple of its value for touching bodies.
    #[serde(default = "default_separation_factor")]
    pub separation_factor: f64,
    /// Where more than two bodies (or a rigid body and another) meet at a node:
    /// `"pairwise"` (each pair's changes equal and opposite; the default) or `"lumped"`
    /// (each body against the sum of the others, the earlier rule, kept to measure
    /// what it loses).
    #[serde(default)]
    pub multi_body: grains_mpm::Crowd,
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
            strength: None,
            separation_test: true,
            separation_factor: default_separation_factor(),
            multi_body: Default::default(),
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
    /// Friction coefficient for `coulomb` (and `bonded`, once debonded).
    #[serde(default)]
    pub mu: Option<f64>,
    /// Bond strength (Pa) for `bonded`.
    #[serde(default)]
    pub strength: Option<f64>,
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
    /// Fraction of the initial total energy lost (negative: gained), measured in the
    /// free flight after wall impact number `after_impact` (from 1) of `body`; passes
    /// when its magnitude is at most `max`.
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
    /// Largest change, over the body's wall impacts, of its momentum along the wall it
    /// hit (means over the free flights before and after), as a fraction of that
    /// momentum: a frictionless impact leaves it unchanged.
    TangentialMomentumChange {
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
    /// Energy change |ΔE|/E0 after impact `after_impact` no larger than that of a
    /// reference scenario (run first, without output).
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
    /// A J2 body in simple shear (perfectly plastic, `hardening = 0`): the mean shear
    /// stress σ_xy of its points in `region` at the end against k = σ_y/√3.
    ShearStressPlateau {
        /// Check name.
        name: String,
        /// The sheared J2 body.
        body: String,
        /// Where the stress is averaged (away from plates and free ends).
        region: Region,
        /// Relative tolerance.
        tolerance: f64,
    },
    /// A hardening J2 body in simple shear: the least-squares slope dτ/dγ of the mean
    /// shear stress against the mean shear strain F_xy in `region`, over γ > 3k/G,
    /// against G H/(H + 3G).
    HardeningSlope {
        /// Check name.
        name: String,
        /// The sheared J2 body (`hardening > 0`).
        body: String,
        /// Where stress and strain are averaged.
        region: Region,
        /// Relative tolerance.
        tolerance: f64,
    },
    /// A one-term Maxwell body (G∞ = 0) under held shear: the relaxation time of an
    /// exponential fitted to the mean shear stress in `region` from time `after` on,
    /// against τ₁ = η/G.
    RelaxationTime {
        /// Check name.
        name: String,
        /// The Maxwell body.
        body: String,
        /// Where the stress is averaged.
        region: Region,
        /// Start of the fit (s), once the shear is held.
        after: f64,
        /// Relative tolerance.
        tolerance: f64,
    },
    /// A free body heated uniformly: its mean in-plane strain ½ ln det F at the end
    /// against the plane-strain free strain (1 + ν) α ΔT.
    ThermalStrain {
        /// Check name.
        name: String,
        /// The heated body (with a `temperature` history).
        body: String,
        /// Relative tolerance.
        tolerance: f64,
    },
    /// A free body heated uniformly: the largest in-plane stress component of its points
    /// at the end, over K α |ΔT|.
    InPlaneStress {
        /// Check name.
        name: String,
        /// The heated body.
        body: String,
        /// Largest ratio allowed.
        max: f64,
    },
    /// A free body heated uniformly in plane strain: its mean σ_zz at the end against
    /// −E α ΔT (the confined out-of-plane direction).
    OutOfPlaneStress {
        /// Check name.
        name: String,
        /// The heated body.
        body: String,
        /// Relative tolerance.
        tolerance: f64,
    },
    /// The energy ledger: the largest drift of kinetic + strain + potential + dissipated
    /// − thermal work over the run, as a fraction of the largest energy that went
    /// through it (initial total, dissipated, thermal work).
    EnergyBalance {
        /// Check name.
        name: String,
        /// Largest fraction allowed.
        max: f64,
    },
    /// The whole energy ledger with contact and rigid movers: the largest drift of
    /// kinetic + strain + potential + plastic + viscous + friction + bond − thermal work −
    /// boundary work over the run, as a fraction of the largest energy that went through
    /// it (the boundary work, the energy taken out, the initial total).
    EnergyLedger {
        /// Check name.
        name: String,
        /// Largest fraction allowed.
        max: f64,
    },
    /// Where several bodies meet: |Σ over steps of the momentum the free bodies gave one
    /// another| over Σ over steps of |the momentum the rigid bodies gave them|: zero if
    /// every exchange is equal and opposite.
    ContactMomentumImbalance {
        /// Check name.
        name: String,
        /// Largest fraction allowed.
        max: f64,
    },
    /// A `[shear]` cell: the shear strain reached at the end.
    ShearStrainReached {
        /// Check name.
        name: String,
        /// Smallest strain accepted (1 = 100 %).
        min: f64,
    },
    /// Concentric cylinders: the mean in-plane stress of the inner disk's core (r <
    /// `core`·a), averaged over the samples from `after` on, against the static
    /// plane-strain solution σ_rr(a) for the temperature changes at the end.
    InterfaceRadialStress {
        /// Check name.
        name: String,
        /// The inner disk.
        inner: String,
        /// The annulus around it.
        outer: String,
        /// Start of the time average (s).
        after: f64,
        /// Radius of the sampled core as a fraction of the disk's.
        #[serde(default = "default_core")]
        core: f64,
        /// Relative tolerance.
        tolerance: f64,
    },
    /// Concentric cylinders with a finite bond: the first time a bond fails, against the
    /// time the static interface traction reaches the bond strength.
    DebondOnsetTime {
        /// Check name.
        name: String,
        /// The inner disk.
        inner: String,
        /// The bonded annulus.
        outer: String,
        /// Relative tolerance.
        tolerance: f64,
    },
    /// Concentric cylinders: the debonding front's speed along the interface over the
    /// plane-strain Rayleigh speed of the outer material. The speed is the slope of the
    /// inner disk's debonded length between 10 % and 90 % of its perimeter, divided by
    /// two fronts per initiation site.
    DebondSpeedOverRayleigh {
        /// Check name.
        name: String,
        /// The inner disk.
        inner: String,
        /// The bonded annulus.
        outer: String,
        /// The interval (lo, hi] the ratio must fall in.
        range: [f64; 2],
    },
    /// After the bond has failed: the time-averaged mean in-plane stress of `body` from
    /// `after` seconds past the onset to the end, as a fraction of its largest |·|
    /// before the onset (its bonded peak).
    StressFreeAfterDebond {
        /// Check name.
        name: String,
        /// The body that should unload.
        body: String,
        /// Delay after the onset before averaging (s).
        after: f64,
        /// Largest fraction allowed.
        max: f64,
    },
}

/// An axis-aligned rectangle of the domain (m).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Region {
    /// Lower-left corner.
    pub lo: [f64; 2],
    /// Upper-right corner.
    pub hi: [f64; 2],
}

impl Region {
    /// True if `x` lies inside.
    pub fn contains(&self, x: glam::DVec2) -> bool {
        x.x > self.lo[0] && x.x < self.hi[0] && x.y > self.lo[1] && x.y < self.hi[1]
    }
}

fn default_core() -> f64 {
    0.8
}

fn default_normal() -> [f64; 2] {
    [0.0, 1.0]
}

impl CheckSpec {
    /// The bodies the check names, with their keys.
    pub fn bodies(&self) -> Vec<(&'static str, &str)> {
        match self {
            CheckSpec::InitialEnergy { .. }
            | CheckSpec::InitialMomentum { .. }
            | CheckSpec::EnergyBalance { .. }
            | CheckSpec::EnergyLedger { .. }
            | CheckSpec::ContactMomentumImbalance { .. }
            | CheckSpec::ShearStrainReached { .. } => vec![],
            CheckSpec::EnergyLoss { body, .. }
            | CheckSpec::TangentialMomentumChange { body, .. }
            | CheckSpec::Rotation { body, .. }
            | CheckSpec::ImpactTangentialVelocity { body, .. }
            | CheckSpec::ImpactSpin { body, .. }
            | CheckSpec::EnergyLossBelowReference { body, .. }
            | CheckSpec::ShearStressPlateau { body, .. }
            | CheckSpec::HardeningSlope { body, .. }
            | CheckSpec::RelaxationTime { body, .. }
            | CheckSpec::ThermalStrain { body, .. }
            | CheckSpec::InPlaneStress { body, .. }
            | CheckSpec::OutOfPlaneStress { body, .. }
            | CheckSpec::StressFreeAfterDebond { body, .. } => vec![("body", body)],
            CheckSpec::Acceleration { body, on, .. } => vec![("body", body), ("on", on)],
            CheckSpec::InterfaceRadialStress { inner, outer, .. }
            | CheckSpec::DebondOnsetTime { inner, outer, .. }
            | CheckSpec::DebondSpeedOverRayleigh { inner, outer, .. } => {
                vec![("inner", inner), ("outer", outer)]
            }
        }
    }

    /// The check's name.
    pub fn name(&self) -> &str {
        match self {
            CheckSpec::InitialEnergy { name, .. }
            | CheckSpec::InitialMomentum { name, .. }
            | CheckSpec::EnergyLoss { name, .. }
            | CheckSpec::TangentialMomentumChange { name, .. }
            | CheckSpec::Rotation { name, .. }
            | CheckSpec::ImpactTangentialVelocity { name, .. }
            | CheckSpec::ImpactSpin { name, .. }
            | CheckSpec::Acceleration { name, .. }
            | CheckSpec::EnergyLossBelowReference { name, .. }
            | CheckSpec::ShearStressPlateau { name, .. }
            | CheckSpec::HardeningSlope { name, .. }
            | CheckSpec::RelaxationTime { name, .. }
            | CheckSpec::ThermalStrain { name, .. }
            | CheckSpec::InPlaneStress { name, .. }
            | CheckSpec::OutOfPlaneStress { name, .. }
            | CheckSpec::EnergyBalance { name, .. }
            | CheckSpec::EnergyLedger { name, .. }
            | CheckSpec::ContactMomentumImbalance { name, .. }
            | CheckSpec::ShearStrainReached { name, .. }
            | CheckSpec::InterfaceRadialStress { name, .. }
            | CheckSpec::DebondOnsetTime { name, .. }
            | CheckSpec::DebondSpeedOverRayleigh { name, .. }
            | CheckSpec::StressFreeAfterDebond { name, .. } => name,
        }
    }
}
