//! The packing spec: what a user writes to describe a packing, parsed strictly and
//! validated with one-line errors naming the key, the value and what is allowed.

use serde::{Deserialize, Serialize};

/// A whole packing spec file.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PackSpec {
    /// Name; the default output directory is `runs/<name>`.
    pub name: String,
    /// Free text.
    #[serde(default)]
    pub description: String,
    /// Seed of every random draw (sizes, deposition choices).
    #[serde(default = "default_seed")]
    pub seed: u64,
    /// The container.
    pub domain: DomainSpec,
    /// The size distribution of the bulk disks.
    pub sizes: SizeSpec,
    /// The boundary layer of small disks on walls.
    #[serde(default)]
    pub lining: LiningSpec,
    /// Deposition and densification parameters.
    #[serde(default)]
    pub protocol: ProtocolSpec,
    /// Checks of summary figures, written into summary.json (exit 2 when one fails).
    #[serde(rename = "check", default)]
    pub checks: Vec<CheckSpec>,
}

/// `[[check]]`: a bound on one figure of summary.json.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CheckSpec {
    /// Figure name, e.g. `psi6_local_mean_interior`.
    pub figure: String,
    /// Lower bound.
    #[serde(default)]
    pub at_least: Option<f64>,
    /// Upper bound.
    #[serde(default)]
    pub at_most: Option<f64>,
    /// Why the bound is what it is (reference value).
    #[serde(default)]
    pub note: String,
}

fn default_seed() -> u64 {
    1
}

/// `[domain]`: the container's shape (SI lengths).
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "snake_case", deny_unknown_fields)]
pub enum DomainSpec {
    /// A ring between two circles.
    Annulus {
        /// Inner radius (m).
        r_in: f64,
        /// Outer radius (m).
        r_out: f64,
        /// Centre (m).
        #[serde(default)]
        centre: [f64; 2],
    },
    /// A circular container.
    Disk {
        /// Radius (m).
        radius: f64,
        /// Centre (m).
        #[serde(default)]
        centre: [f64; 2],
    },
    /// A box `[0, width] × [0, height]`, walled, or periodic in x (walls at top and bottom).
    Rectangle {
        /// Width (m).
        width: f64,
        /// Height (m).
        height: f64,
        /// Periodic in x instead of side walls.
        #[serde(default)]
        periodic_x: bool,
    },
}

/// `[sizes]`: the diameter distribution of the bulk disks.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(tag = "distribution", rename_all = "snake_case", deny_unknown_fields)]
pub enum SizeSpec {
    /// Normal with mean `d0` and standard deviation `delta · d0`, redrawn below
    /// `d_min_ratio · d0` (the truncation is reported).
    Gaussian {
        /// Mean diameter (m).
        d0: f64,
        /// Polydispersity σ/d0.
        delta: f64,
    },
    /// Uniform on `[d0 − a, d0 + a]` with `a = √3 · delta · d0`.
    Uniform {
        /// Mean diameter (m).
        d0: f64,
        /// Polydispersity.
        delta: f64,
    },
    /// Two sizes; `fraction_large` is the number fraction of large disks.
    Bidisperse {
        /// Small diameter (m).
        d_small: f64,
        /// Large diameter (m).
        d_large: f64,
        /// Number fraction of large disks.
        fraction_large: f64,
    },
    /// Log-normal with mean `d0` and polydispersity `delta`.
    Lognormal {
        /// Mean diameter (m).
        d0: f64,
        /// Polydispersity.
        delta: f64,
    },
}

/// `[lining]`: small disks tangent to every wall, as in xue-2019 §4.1.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LiningSpec {
    /// Lining diameter over the nominal d0.
    #[serde(default = "default_lining_ratio")]
    pub diameter_ratio: f64,
}

fn default_lining_ratio() -> f64 {
    0.6
}

impl Default for LiningSpec {
    fn default() -> Self {
        LiningSpec {
            diameter_ratio: default_lining_ratio(),
        }
    }
}

/// `protocol.start`: the configuration the Monte Carlo growth starts from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StartSpec {
    /// One triangular lattice over the whole region: a single crystal orientation,
    /// which a narrow size distribution keeps and a broad one loses.
    #[default]
    Lattice,
    /// Gravity deposition: a dense, disordered bed.
    Deposit,
}

/// `protocol.finish`: where the growth ends.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FinishSpec {
    /// Grow until jammed, then swell and minimise until the disks press on each other.
    #[default]
    Jammed,
    /// Grow until the disks have the size at which the start's bulk disks fill
    /// `target_fraction` (or until jammed, if that comes first; a growth that jams
    /// short of the target is swelled up to it, not past it): the sizes, and so the
    /// ring's mass, are known from the spec.
    Target,
}

/// `[protocol]`: the start (lattice or deposition), Lubachevsky–Stillinger-like Monte Carlo growth, then
/// swell-and-minimise.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProtocolSpec {
    /// How the bulk disks are placed before the Monte Carlo growth.
    #[serde(default)]
    pub start: StartSpec,
    /// Bulk packing fraction the packing must reach (a check), and with
    /// `finish = "target"` where the growth ends.
    #[serde(default = "default_target")]
    pub target_fraction: f64,
    /// Where the growth ends: at jamming (default) or at `target_fraction`.
    #[serde(default)]
    pub finish: FinishSpec,
    /// Whether the Monte Carlo tries size exchanges between neighbours (swap Monte
    /// Carlo, default): they let the sizes arrange themselves, which packs denser.
    #[serde(default = "default_swaps")]
    pub swaps: bool,
    /// Growth rate: relative radius increase per Monte Carlo sweep, i.e. how long the
    /// disks may rearrange before they jam (see docs/packing.md for what it steers).
    #[serde(default = "default_rate")]
    pub rate: f64,
    /// Bulk packing fraction at which the Monte Carlo growth starts.
    #[serde(default = "default_start")]
    pub start_fraction: f64,
    /// Monte Carlo sweeps at `start_fraction`, with no growth, before the growth: time
    /// for a size distribution that cannot hold the template to lose it.
    #[serde(default)]
    pub anneal_sweeps: u64,
    /// Lattice start only: sweeps of size exchanges between lattice sites before any
    /// disk moves, so that large disks sit beside small ones and the lattice survives
    /// a dense start (see [`crate::sort`]); 0 (default) leaves the drawn order. Left out
    /// of the spec's key when 0, so older specs keep their keys.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub sort_sweeps: u64,
    /// Most Monte Carlo sweeps of the growth.
    #[serde(default = "default_max_sweeps")]
    pub max_sweeps: u64,
    /// Relative growth of the radii per swell cycle of the final minimisation.
    #[serde(default = "default_swell_step")]
    pub swell_step: f64,
    /// Largest radius scale reached by growth, relative to the drawn sizes.
    #[serde(default = "default_max_swell")]
    pub max_swell: f64,
    /// Scale of the deposited disks relative to their drawn size (sets how many fit;
    /// deposition start only).
    #[serde(default = "default_deposit_scale")]
    pub deposit_scale: f64,
}

fn is_zero(v: &u64) -> bool {
    *v == 0
}
fn default_swaps() -> bool {
    true
}
fn default_target() -> f64 {
    0.83
}
fn default_rate() -> f64 {
    1e-5
}
fn default_start() -> f64 {
    0.75
}
fn default_max_sweeps() -> u64 {
    100_000
}
fn default_swell_step() -> f64 {
    1e-3
}
fn default_max_swell() -> f64 {
    0.05
}
fn default_deposit_scale() -> f64 {
    0.99
}

impl Default for ProtocolSpec {
    fn default() -> Self {
        ProtocolSpec {
            start: StartSpec::default(),
            target_fraction: default_target(),
            finish: FinishSpec::default(),
            swaps: default_swaps(),
            rate: default_rate(),
            start_fraction: default_start(),
            anneal_sweeps: 0,
            sort_sweeps: 0,
            max_sweeps: default_max_sweeps(),
            swell_step: default_swell_step(),
            max_swell: default_max_swell(),
            deposit_scale: default_deposit_scale(),
        }
    }
}

/// Parses a spec, with the TOML error's line and column on failure.
pub fn parse(text: &str, origin: &str) -> Result<PackSpec, String> {
    grains_core::input::parse_toml(text, origin)
}

/// Version of the packing protocol: part of every spec's key, so that packings cached
/// by an older protocol are rebuilt. Raise it whenever a spec's packing changes.
pub const PROTOCOL_VERSION: u32 = 2;

/// What makes a packing: everything in a spec but its name, description and checks.
#[derive(Serialize)]
struct Recipe<'a> {
    protocol_version: u32,
    seed: u64,
    domain: &'a DomainSpec,
    sizes: &'a SizeSpec,
    lining: &'a LiningSpec,
    protocol: &'a ProtocolSpec,
}

impl PackSpec {
    /// The key of the packing this spec makes: a hash of every value that shapes it
    /// (not the name, description or checks) and of [`PROTOCOL_VERSION`]. Two specs
    /// with the same key make the same file.
    pub fn key(&self) -> u64 {
        let recipe = Recipe {
            protocol_version: PROTOCOL_VERSION,
            seed: self.seed,
            domain: &self.domain,
            sizes: &self.sizes,
            lining: &self.lining,
            protocol: &self.protocol,
        };
        let text = toml::to_string(&recipe).unwrap_or_default();
        grains_core::hash::fnv1a(text.as_bytes())
    }
}
