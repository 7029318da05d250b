//! The collision watch on the 3D engine (spheres).

use grains_dem3d as engine;

// Both dimensions compile this file, each on its own engine's types.
#[allow(clippy::duplicate_mod)]
#[path = "watch.rs"]
mod watch;

pub use watch::{validate, Partner, Watch};
