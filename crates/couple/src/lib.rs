//! FEM–DEM coupling after xue-2019 Appendix C: a charge meshed with finite elements
//! (grains-fem) and a ring of disks (grains-dem) in penalty contact at the charge's
//! edge, advanced together on one velocity-Verlet clock.
//!
//! The engines never import each other; this crate is where they meet. The DEM step
//! takes the penalty forces through its [`grains_dem::Hooks`], so the coupled step
//! ([`step::coupled_step`]) adds stages around the engines' own steps instead of
//! copying them.
#![warn(missing_docs)]

pub mod checkpoint;
pub mod hits;
pub mod penalty;
pub mod step;

pub use penalty::Coupling;
pub use step::{coupled_step, coupled_step_by, coupled_step_with, Ring};
