//! Discrete element method (DEM) after xue-2019 Appendix B, in two dimensions (disks,
//! built as `grains-dem`) and in three (spheres, built from this same source as
//! `grains-dem3d`); the dimension lives in [`math`] alone.
//!
//! Particles interact through a linear spring-dashpot normal force and an incremental
//! tangential spring capped by Coulomb friction, whose history lives as long as the
//! contact does (in 3D it is kept in the tangent plane as the contact turns). Walls
//! (segments and circles in 2D; planes, spheres and cylinders in 3D) use the same law
//! with an infinitely heavy, non-rotating partner.
//!
//! One time step is a short, fixed sequence of named stages (see [`step::step`]):
//! `kick_drift → neighbours → pair_contacts → walls_gather_kick`, with outside forces
//! entering through [`Hooks`]. State is passed explicitly: [`Particles`] (per-field
//! storage), [`ContactList`] (neighbour list with tangential history) and a read-only
//! [`Setup`] (domain, walls, contact table, skin); the time step is an argument.
#![warn(missing_docs)]
// SoA kernels index several arrays with one particle or entry index; iterator zips over
// five or more fields would hide that, not clarify it.
#![allow(clippy::needless_range_loop)]

pub mod checkpoint;
pub mod comm;
pub mod contact;
pub mod decomp;
pub mod diagnostics;
pub mod domain;
pub mod exact;
pub mod forces;
pub mod granular;
pub mod granular_ledger;
pub mod granular_pass;
pub mod history;
pub mod insert;
pub mod integrate;
pub mod law;
pub mod ledger;
pub mod ledger_sums;
pub mod material;
pub mod math;
pub mod neighbours;
pub mod particles;
mod pass_fields;
pub mod restitution;
pub mod setup;
pub mod step;
pub mod stress;
pub mod timestep;
pub mod verlet;
pub mod walls;
pub mod wavefront;

pub use comm::{Exchange, Reduce, Serial};
pub use contact::{ContactModel, PairParams, PairTable};
pub use domain::Domain;
pub use law::ContactLaw;
pub use ledger::EnergyLedger;
pub use ledger_sums::LedgerSums;
pub use material::Material;
pub use neighbours::ContactList;
pub use particles::Particles;
pub use setup::Setup;
pub use step::{step, step_on, step_with, Hooks, ListChange, NoHooks, State};
pub use walls::{Wall, WallShape};

/// Work is split into fixed-size chunks of particles so that every reduction and every
/// parallel pass sees the same partition whatever the thread count: results are then
/// bitwise identical for 1, 2 or N threads.
pub const CHUNK: usize = 2048;
