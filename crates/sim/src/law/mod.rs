//! The scenario's `[contact]` table (LAMMPS's keywords, per material pair) turned into
//! the engine's laws, from one source for both dimensions: `spec.rs` (the table) and
//! `table.rs` (its validation, LAMMPS's mixing and the bad-input lines) are compiled once
//! on `grains-dem` ([`dim2`]) and once on `grains-dem3d` ([`dim3`]), as the engine itself
//! is, because the two engines' parameter types are distinct types of one source.

pub mod dim2;
pub mod dim3;
