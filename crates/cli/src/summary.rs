//! `summary.json`: the figures a run exists to produce, its checks and its cost.

use grains_core::atomic::write_atomic;
use grains_core::checks::Check;
use serde::Serialize;
use std::path::Path;

/// Everything summary.json holds.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    /// Scenario name.
    pub name: String,
    /// `completed`, `at_rest` or `unstable`.
    pub status: String,
    /// Diagnostic when the run stopped early for a bad state.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub message: Option<String>,
    /// Number of particles.
    pub particles: usize,
    /// Steps taken.
    pub steps: u64,
    /// Simulated time reached (s).
    pub time: f64,
    /// Time step (s).
    pub dt: f64,
    /// Largest stable time step (s).
    pub dt_critical: f64,
    /// Worker threads.
    pub threads: usize,
    /// Wall-clock time of the time loop (s).
    pub wall_time_s: f64,
    /// Particles × steps / wall time.
    pub particle_steps_per_s: f64,
    /// Neighbour-list rebuilds.
    pub neighbour_builds: u64,
    /// Frames written.
    pub frames: usize,
    /// Fingerprint of the final state, as hex (DEM: `grains_dem::diagnostics::state_hash`);
    /// equal fingerprints mean bitwise-equal runs.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub state_hash: Option<String>,
    /// Scenario-specific figures.
    pub figures: serde_json::Map<String, serde_json::Value>,
    /// Validation checks.
    pub checks: Vec<Check>,
}

/// Writes the summary atomically, pretty-printed.
pub fn write(path: &Path, s: &Summary) -> anyhow::Result<()> {
    let text = serde_json::to_string_pretty(s)?;
    write_atomic(path, text.as_bytes())?;
    Ok(())
}
