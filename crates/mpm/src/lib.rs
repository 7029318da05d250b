//! Two-dimensional, plane-strain, explicit material point method (MPM) with
//! multi-velocity-field frictional contact between bodies, after Bardenhagen, Brackbill &
//! Sulsky (1998, 2000) and Bardenhagen et al. (2001).
//!
//! Bodies are sets of material points carrying mass, volume, position, velocity,
//! deformation gradient, stress and the internal state of their material (equivalent
//! plastic strain, Maxwell branch stresses, bond strength, dissipated energy, thermal
//! work). Materials ([`Material`]) are elastic, Neo-Hookean, J2 elastic-plastic or
//! generalized Maxwell; the rate models take a thermal strain from their body's
//! prescribed temperature ([`TemperatureHistory`]). Each body has its own velocity field on
//! the background grid; where fields meet, the Coulomb contact law moves them toward the
//! centre-of-mass field, once after the particle-to-grid transfer and once after
//! integration (the second correction reaches the particles as a force); where more than
//! two bodies (or a rigid body and another) meet, pair by pair ([`crowd`]). Bonded pairs
//! move as one until the bond fails, then slide ([`bond`]). The domain's edges are walls
//! with exact normals and Coulomb friction, or the grid is periodic along y ([`grid`]);
//! bodies with a prescribed velocity are rigid movers, whose contact reactions and work
//! are counted ([`Touch`]).
//!
//! One time step is a short fixed sequence of named stages (see [`step::step`]). State is
//! passed explicitly: [`Particles`] (per-field storage) in a [`State`], a read-only
//! [`Setup`], and a [`Solver`] holding only scratch space. Grid scatters are coloured by
//! strips of columns and every reduction runs in a fixed order, so results are bitwise
//! identical for any number of threads.
#![warn(missing_docs)]
// SoA kernels index several arrays with one particle or node index; iterator zips over
// five or more fields would hide that, not clarify it.
#![allow(clippy::needless_range_loop)]

pub mod bond;
pub mod contact;
pub mod crowd;
pub mod diagnostics;
pub mod geometry;
pub mod grid;
pub mod material;
pub mod models;
pub mod nodes;
pub mod particles;
pub mod setup;
pub mod shape;
mod simd;
pub mod step;
mod tasks;
pub mod thermal;
pub mod timestep;
pub mod transfer;

pub use contact::{Crowd, Touch};
pub use geometry::Geometry;
pub use grid::Grid;
pub use material::{Material, PronyTerm, Stress};
pub use models::PointState;
pub use particles::Particles;
pub use setup::{Body, ContactLaw, ContactTable, Motion, Setup, UpdateScheme};
pub use shape::ShapeFunction;
pub use step::{step, Solver, State, Unstable};
pub use thermal::{TemperatureHistory, Thermal};

/// Points per chunk of every reduction, fixed so sums do not depend on the thread count.
pub const CHUNK: usize = 4096;
