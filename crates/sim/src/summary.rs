//! `summary.json`: the figures a run exists to produce, its checks and its cost.

use grains_core::checks::Check;
use serde::Serialize;
use std::path::Path;

/// Everything summary.json holds.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    /// Scenario name.
    pub name: String,
    /// `dem`, `mpm` or `fem_dem`.
    pub engine: &'static str,
    /// `completed`, `at_rest`, `unstable`, `paused` or `interrupted`.
    pub status: String,
    /// Why the run stopped early, if it did.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub message: Option<String>,
    /// Number of particles (material points for MPM).
    pub particles: usize,
    /// Steps taken.
    pub steps: u64,
    /// Simulated time reached (s).
    pub time: f64,
    /// Time step (s); the last one where it adapts.
    pub dt: f64,
    /// Largest stable time step (s).
    pub dt_critical: f64,
    /// Worker threads.
    pub threads: usize,
    /// Wall-clock time of the time loop (s).
    pub wall_time_s: f64,
    /// Particles × steps / wall time.
    pub particle_steps_per_s: f64,
    /// Frames written.
    pub frames: usize,
    /// Fingerprint of the final state, as hex: equal fingerprints mean bitwise-equal
    /// runs.
    pub state_hash: String,
    /// Engine-specific counts (neighbour-list rebuilds, bodies).
    #[serde(flatten)]
    pub counts: serde_json::Map<String, serde_json::Value>,
    /// Scenario-specific figures.
    pub figures: serde_json::Map<String, serde_json::Value>,
    /// Validation checks.
    pub checks: Vec<Check>,
}

impl Summary {
    /// Writes the summary atomically, pretty-printed.
    pub fn write(&self, path: &Path) -> anyhow::Result<()> {
        grains_core::json::write_json_pretty(path, &serde_json::to_value(self)?)?;
        Ok(())
    }
}
