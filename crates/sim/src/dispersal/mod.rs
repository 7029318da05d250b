//! The dispersal analysis of xue-2019 §§4.2–5 wired to runs: chosen in the scenario
//! (`[analysis.dispersal]` of a FEM–DEM ring, `[dispersal]` of a DEM run), run by an
//! [`observer::DispersalObserver`] at frames, at chosen times and every so often, and
//! afterwards on a finished run's frames by [`run_dir::analyze_run`]
//! (`grains analyze RUN_DIR`). Both feed the same [`analyst::Analyst`], which calls
//! `grains_analysis::dispersal`.
//!
//! Outputs: `frames/fields_NNNNN.vts` + `frames/fields.pvd` (the coarse-grained fields
//! per analysed frame), `plots/dispersal/` (R–t diagram, radial profiles, jets, and per
//! chosen time the polar maps and the band's azimuthal profiles with spectra), and the
//! figures under `dispersal` in `summary.json` (`analysis.json` for a finished run).

pub mod analyst;
pub mod observer;
pub mod run_dir;
pub mod settings;

pub use analyst::{Analyst, Frame, Layout, Writes};
pub use observer::{DispersalObserver, Dispersing};
pub use settings::DispersalSettings;
