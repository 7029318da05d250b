//! A 3D DEM run spread over ranks (`mpirun -np N grains run`): the part each rank steps
//! is [`Part`], the 2D run's source (`ranks/part.rs`) compiled over [`grains_dem3d`];
//! what a 3D scenario cannot do on several ranks is [`unsupported`].

use super::scenario::Scenario;
use grains_dem3d as engine;

// Loaded once per engine on purpose: the same source over each engine's types.
#[allow(clippy::duplicate_mod)]
#[path = "../ranks/part.rs"]
mod part;

pub(crate) use part::spread_methods;
pub use part::{grid, largest_radius, layout, nearby, watched, ParallelSpec, Part};

/// Why `s` cannot run on several ranks yet, as one line naming what is not supported;
/// `None` when it can: every 3D scenario the engine's decomposition carries (its own
/// refusal, an expanding neighbour frame, comes from
/// [`grains_dem3d::decomp::Decomposed::new`]). The checks' probes read the spheres
/// through [`watched`]; a pour draws its spheres from those [`nearby`] its region.
pub fn unsupported(_s: &Scenario) -> Option<String> {
    None
}
