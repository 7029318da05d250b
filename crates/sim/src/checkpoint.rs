//! Checkpoint files: the engine state (bytes the engine writes, bitwise) plus the run
//! loop's progress and its observers' records, in one file with a magic number, a
//! format version, the hash of the scenario it belongs to and a checksum, so that a
//! truncated, corrupted or foreign file is refused with a clear message instead of a
//! panic or a silently different run.

use crate::driver::Counters;
use grains_core::atomic::write_atomic_with;
use grains_core::hash::{fnv1a, Fnv1a};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The checkpoint's file name in a run directory.
pub const FILE: &str = "checkpoint.bin";

const MAGIC: &[u8; 8] = b"GRAINSCK";
const VERSION: u32 = 5;

/// The run loop's side of a checkpoint.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Progress {
    /// The loop's counters.
    pub counters: Counters,
    /// What each observer saved, by name.
    pub observers: toml::Table,
    /// The directory the scenario's relative paths were read from (absolute), so that
    /// a run resumed from the copy in its output directory finds the files the original
    /// names (a packing spec, a table); absent in older checkpoints.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base: Option<std::path::PathBuf>,
}

/// A checkpoint read back: the run loop's progress and the engine's state `S`.
pub struct Resumed<S> {
    /// The loop's counters, the observers' records, the scenario's directory.
    pub progress: Progress,
    /// The engine's state (or its bytes).
    pub state: S,
}

impl<S> Resumed<S> {
    /// Where the original scenario's relative paths started, if the checkpoint says.
    pub fn base(&self) -> Option<&Path> {
        self.progress.base.as_deref()
    }
}

/// Removes what a checkpoint write cut short left in `dir` (its temporary file, as
/// large as a checkpoint): a run killed while writing one leaves it behind.
pub fn remove_stale_temps(dir: &Path) {
    let prefix = format!(".{FILE}.tmp.");
    if let Ok(entries) = std::fs::read_dir(dir) {
        for e in entries.flatten() {
            if e.file_name().to_string_lossy().starts_with(&prefix) {
                let _ = std::fs::remove_file(e.path());
            }
        }
    }
}

/// Writes a checkpoint atomically, streaming the engine's bytes (as large as the state:
/// 0.44 GB for xue-2019 test 1) rather than copying them once more.
pub fn save(
    path: &Path,
    scenario_text: &str,
    state: &[u8],
    progress: &Progress,
) -> anyhow::Result<()> {
    // TOML rather than JSON: the recorders hold NaN and infinities, which TOML keeps.
    let meta = toml::to_string(progress)
        .map_err(|e| anyhow::anyhow!("cannot write {}: the run's progress: {e}", path.display()))?
        .into_bytes();
    let mut head = Vec::with_capacity(28 + meta.len());
    head.extend_from_slice(MAGIC);
    head.extend_from_slice(&VERSION.to_le_bytes());
    head.extend_from_slice(&fnv1a(scenario_text.as_bytes()).to_le_bytes());
    head.extend_from_slice(&(meta.len() as u64).to_le_bytes());
    head.extend_from_slice(&meta);
    let mut sum = Fnv1a::default();
    sum.bytes(&head);
    sum.bytes(state);
    write_atomic_with(path, |w| {
        w.write_all(&head)?;
        w.write_all(state)?;
        w.write_all(&sum.finish().to_le_bytes())
    })?;
    Ok(())
}

/// Reads a checkpoint written by [`save`] for `scenario_text`: the run's progress and
/// the engine's bytes.
pub fn load(path: &Path, scenario_text: &str) -> Result<(Progress, Vec<u8>), String> {
    let name = path.display();
    let bytes = std::fs::read(path).map_err(|e| format!("{name}: cannot read checkpoint: {e}"))?;
    if bytes.len() < 8 + 4 + 8 + 8 + 8 || &bytes[..8] != MAGIC {
        return Err(format!(
            "{name}: not a grains checkpoint (bad magic number or too short)"
        ));
    }
    let (body, tail) = bytes.split_at(bytes.len() - 8);
    if fnv1a(body).to_le_bytes() != tail {
        return Err(format!(
            "{name}: checkpoint is corrupted or truncated (checksum mismatch); use an earlier copy or rerun"
        ));
    }
    let word = |at: usize| -> [u8; 8] { body[at..at + 8].try_into().expect("8 bytes") };
    let version = u32::from_le_bytes(body[8..12].try_into().expect("4 bytes"));
    if version != VERSION {
        return Err(format!(
            "{name}: checkpoint format version {version}, this grains reads version {VERSION}"
        ));
    }
    if u64::from_le_bytes(word(12)) != fnv1a(scenario_text.as_bytes()) {
        return Err(format!(
            "{name}: checkpoint belongs to a different scenario.toml than the one beside it"
        ));
    }
    let meta_len = u64::from_le_bytes(word(20)) as usize;
    let meta = body
        .get(28..28usize.saturating_add(meta_len))
        .ok_or_else(|| format!("{name}: checkpoint header is inconsistent"))?;
    let progress: Progress = std::str::from_utf8(meta)
        .ok()
        .and_then(|t| toml::from_str(t).ok())
        .ok_or_else(|| format!("{name}: checkpoint run progress unreadable"))?;
    Ok((progress, body[28 + meta_len..].to_vec()))
}

/// Reads the DEM checkpoint in the run directory `dir` for `scenario_text`: the engine's
/// state through `read` (2D or 3D), whose wall count `n_walls` gives, refused unless it
/// has the scenario's `walls`.
pub fn load_dem<S>(
    dir: &Path,
    scenario_text: &str,
    walls: usize,
    read: impl FnOnce(&mut &[u8]) -> Result<S, grains_core::snapshot::SnapshotError>,
    n_walls: impl Fn(&S) -> usize,
) -> Result<Resumed<S>, String> {
    let file = dir.join(FILE);
    let (progress, bytes) = load(&file, scenario_text)?;
    let name = file.display();
    let state = read(&mut bytes.as_slice()).map_err(|e| format!("{name}: {e}"))?;
    if n_walls(&state) != walls {
        return Err(format!(
            "{name}: the checkpoint has {} walls, the scenario {walls}",
            n_walls(&state)
        ));
    }
    Ok(Resumed { progress, state })
}
