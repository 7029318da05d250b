//! A 3D DEM run spread over ranks (`mpirun -np N grains run`): the part each rank steps
//! is [`Part`], the 2D run's source (`ranks/part.rs`) compiled over [`grains_dem3d`];
//! what a 3D scenario cannot do on several ranks is [`unsupported`].

use super::scenario::Scenario;
use crate::ranks::not_on_ranks;
use grains_dem3d as engine;

// Loaded once per engine on purpose: the same source over each engine's types.
#[allow(clippy::duplicate_mod)]
#[path = "../ranks/part.rs"]
mod part;

pub(crate) use part::spread_methods;
pub use part::{grid, watched, ParallelSpec, Part};

/// Why `s` cannot run on several ranks yet, as one line naming what is not supported;
/// `None` when it can. The checks run on ranks: their probes read the spheres through
/// [`watched`]. The engine's own refusal (an expanding neighbour frame) comes from
/// [`grains_dem3d::decomp::Decomposed::new`].
pub fn unsupported(s: &Scenario) -> Option<String> {
    // A pour inserts spheres into the whole state after each step.
    s.pour
        .as_ref()
        .map(|_| not_on_ranks("[pour]", "no [pour] table, or 1 rank"))
}
