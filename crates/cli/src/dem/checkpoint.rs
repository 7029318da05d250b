//! Checkpoint files of a DEM run: the engine state (bitwise) plus the run loop's own
//! progress, in one file with a magic number, a format version, the hash of the scenario
//! it belongs to and a checksum, so a truncated, corrupted or foreign file is refused
//! with a clear message instead of a panic or a silently different run.

use super::probes::Probes;
use grains_core::atomic::write_atomic;
use grains_dem::State;
use serde::{Deserialize, Serialize};
use std::path::Path;

const MAGIC: &[u8; 8] = b"GRAINSCK";
const VERSION: u32 = 1;

/// The run loop's progress, saved beside the engine state.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct RunProgress {
    /// Frames written so far.
    pub frames: usize,
    /// Step of the last frame.
    pub last_frame_step: u64,
    /// Since when the kinetic energy has been below the rest threshold.
    pub rest_since: Option<f64>,
    /// Check recorders.
    pub probes: Probes,
    /// Wall-clock seconds spent in earlier segments of the run.
    pub wall_time: f64,
    /// Steps run in earlier segments.
    pub steps_before: u64,
}

/// FNV-1a, 64 bit: small, dependency-free, and enough to catch corruption.
pub fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf29ce484222325;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x100000001b3);
    }
    h
}

/// Writes `DIR/checkpoint.bin` atomically.
pub fn save(
    path: &Path,
    scenario_text: &str,
    state: &State,
    progress: &RunProgress,
) -> anyhow::Result<()> {
    let mut bytes = Vec::with_capacity(64 + 200 * state.particles.len());
    bytes.extend_from_slice(MAGIC);
    bytes.extend_from_slice(&VERSION.to_le_bytes());
    bytes.extend_from_slice(&fnv1a(scenario_text.as_bytes()).to_le_bytes());
    // TOML rather than JSON: the recorders hold NaN and infinities, which TOML keeps.
    let meta = toml::to_string(progress)?.into_bytes();
    bytes.extend_from_slice(&(meta.len() as u64).to_le_bytes());
    bytes.extend_from_slice(&meta);
    grains_dem::checkpoint::write(state, &mut bytes)?;
    let sum = fnv1a(&bytes);
    bytes.extend_from_slice(&sum.to_le_bytes());
    write_atomic(path, &bytes)?;
    Ok(())
}

/// Reads a checkpoint written by [`save`] for `scenario_text`.
pub fn load(
    path: &Path,
    scenario_text: &str,
    max_particles: usize,
) -> Result<(State, RunProgress), String> {
    let name = path.display();
    let bytes = std::fs::read(path).map_err(|e| format!("{name}: cannot read checkpoint: {e}"))?;
    if bytes.len() < 8 + 4 + 8 + 8 + 8 || &bytes[..8] != MAGIC {
        return Err(format!(
            "{name}: not a grains checkpoint (bad magic number or too short)"
        ));
    }
    let (body, tail) = bytes.split_at(bytes.len() - 8);
    if fnv1a(body) != u64::from_le_bytes(tail.try_into().unwrap()) {
        return Err(format!("{name}: checkpoint is corrupted or truncated (checksum mismatch); use an earlier copy or rerun"));
    }
    let version = u32::from_le_bytes(body[8..12].try_into().unwrap());
    if version != VERSION {
        return Err(format!(
            "{name}: checkpoint format version {version}, this grains reads version {VERSION}"
        ));
    }
    let scenario_hash = u64::from_le_bytes(body[12..20].try_into().unwrap());
    if scenario_hash != fnv1a(scenario_text.as_bytes()) {
        return Err(format!(
            "{name}: checkpoint belongs to a different scenario.toml than the one beside it"
        ));
    }
    let meta_len = u64::from_le_bytes(body[20..28].try_into().unwrap()) as usize;
    let meta = body
        .get(28..28usize.saturating_add(meta_len))
        .ok_or_else(|| format!("{name}: checkpoint header is inconsistent"))?;
    let progress: RunProgress = std::str::from_utf8(meta)
        .ok()
        .and_then(|t| toml::from_str(t).ok())
        .ok_or_else(|| format!("{name}: checkpoint run progress unreadable"))?;
    let mut rest = &body[28 + meta_len..];
    let state = grains_dem::checkpoint::read(&mut rest, max_particles)
        .map_err(|e| format!("{name}: {e}"))?;
    if !rest.is_empty() {
        return Err(format!(
            "{name}: {} unexpected bytes after the state",
            rest.len()
        ));
    }
    Ok((state, progress))
}
