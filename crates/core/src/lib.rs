//! Shared output layer of the grains simulation suite.
//!
//! Every solver in the workspace writes its results through this crate so
//! that all of them produce the same kinds of files:
//!
//! - [`vtk`]: ParaView-readable `.vtp`/`.vtu`/`.vts` frames (VTK XML, appended raw
//!   binary) and [`pvd`] time-series collections that index them;
//! - [`history`]: CSV time histories with full round-trip precision;
//! - [`plot`]: PNG line plots, particle maps and polar maps;
//! - [`checks`]: pass/fail verification records for `summary.json`, written
//!   with [`json`];
//! - [`input`]: the one error type for rejected input (key, value, allowed) and the
//!   one formatter for TOML errors;
//! - [`hash`]: FNV-1a fingerprints of states and checksums of checkpoints;
//! - [`rng`]: the one seeded random generator used everywhere, so runs are
//!   reproducible;
//! - [`lammps_data`]: reader for LAMMPS `atom_style sphere` data files, so
//!   beds built with LAMMPS can start a grains run;
//! - [`table`]: tables of values against time (temperature, velocity histories),
//!   validated and read linearly;
//! - [`snapshot`]: the tagged binary arrays engine checkpoints are written in;
//! - [`atomic`]: the write-then-rename primitive the writers above share, so
//!   an interrupted run never leaves a half-written file behind.
#![warn(missing_docs)]

pub mod atomic;
pub mod checks;
pub mod hash;
pub mod history;
pub mod input;
pub mod json;
pub mod lammps_data;
pub mod plot;
pub mod pvd;
pub mod rng;
pub mod snapshot;
pub mod table;
pub mod vtk;
mod xml;

pub use glam::{DVec2, DVec3};
