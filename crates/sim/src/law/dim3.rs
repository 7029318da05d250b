//! The contact-law table on the 3D engine (spheres).

use grains_dem3d as engine;

// Both dimensions compile these files, each on its own engine's types.
#[allow(clippy::duplicate_mod)]
#[path = "spec.rs"]
mod spec;
#[allow(clippy::duplicate_mod)]
#[path = "table.rs"]
mod table;

pub use spec::{material_law, LawModel, LawSpec, NormalSpec};
pub use table::{resolve, Laws};
