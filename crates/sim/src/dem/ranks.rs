//! A 2D DEM run spread over ranks (`mpirun -np N grains run`): the part each rank steps
//! is [`Part`] (one source for both dimensions, `ranks/part.rs`, here over
//! [`grains_dem`]); what a 2D scenario cannot do on several ranks is [`unsupported`].
//! The transport (MPI) comes from outside (`grains-mpi`), so this crate needs nothing
//! but cargo; its tests run on in-process ranks.

use super::scenario::Scenario;
use crate::ranks::not_on_ranks;
use grains_dem as engine;

// Loaded once per engine on purpose: the same source over each engine's types.
#[allow(clippy::duplicate_mod)]
#[path = "../ranks/part.rs"]
mod part;

pub use crate::ranks::{Link, Transport};
pub(crate) use part::spread_methods;
pub use part::{comm_of, grid, largest_radius, layout, nearby, watched, ParallelSpec, Part};

/// Why `s` cannot run on several ranks yet, as one line naming what is not supported;
/// `None` when it can. The checks run on ranks: their probes read the particles through
/// [`watched`]. The engine's own refusal (an expanding neighbour frame) comes from
/// [`grains_dem::decomp::Decomposed::new`].
pub fn unsupported(s: &Scenario) -> Option<String> {
    s.dispersal
        .as_ref()
        .map(|_| not_on_ranks("[dispersal]", "no [dispersal] table, or 1 rank"))
}
