//! Two-dimensional explicit Lagrangian finite elements for an explosive charge and its
//! detonation products, after xue-2019 Appendix A.
//!
//! A circular charge is meshed with triangles refined toward its edge ([`mesh`]). Nodes
//! carry lumped masses and are integrated explicitly ([`integrate`]); each element's
//! stress comes from the equation of state of its burning mixture — a shock
//! Mie–Grüneisen reactant and JWL products mixed by the burn fraction λ ([`eos`],
//! [`explosive`]) — plus linear + quadratic artificial bulk viscosity and, optionally, a
//! deviatoric part ([`stress`]). λ follows a programmed burn: each element is lit when
//! the detonation front, spreading at D_CJ from the detonation point, reaches its
//! centroid, and burns over a few element sizes, or sooner when compressed.
//!
//! One step is `kick_drift → stress_forces → kick` ([`step::step`]). State is passed
//! explicitly: a [`Charge`] (per-field nodes and elements) and a read-only [`FemSetup`].
//! Plane strain, per unit thickness, SI units.
#![warn(missing_docs)]
// Element and node kernels index several per-field arrays with one index.
#![allow(clippy::needless_range_loop)]

pub mod checkpoint;
pub mod diagnostics;
pub mod eos;
pub mod explosive;
pub mod integrate;
pub mod mesh;
pub mod setup;
pub mod shell;
pub mod state;
pub mod step;
pub mod stress;

pub use explosive::Explosive;
pub use mesh::{Mesh, MeshSpec};
pub use setup::{Burn, FemSetup, Strength, Viscosity};
pub use state::Charge;
pub use step::step;
pub use stress::Breakdown;
