//! The contact-law table on the 2D engine (disks): every key of 3D's but twisting, and
//! the material route (xue-2019 App. B) that 2D scenarios take by default.

use grains_dem as engine;

// Both dimensions compile these files, each on its own engine's types.
#[allow(clippy::duplicate_mod)]
#[path = "spec.rs"]
mod spec;
#[allow(clippy::duplicate_mod)]
#[path = "table.rs"]
mod table;

pub use spec::{material_law, LawModel, LawSpec, NormalSpec};
pub use table::{resolve, Laws};
