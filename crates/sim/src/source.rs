//! Where a scenario comes from: its text, a name for messages, and the directory its
//! relative paths start at.

use std::path::{Path, PathBuf};

/// The built-in demo: disks pouring through a hopper onto a floor.
const DEMO: &str = include_str!("../../../examples/dem/demo_hopper.toml");

/// A scenario file's text and origin.
#[derive(Clone, Debug)]
pub struct Source {
    /// The TOML text.
    pub text: String,
    /// The file's path as given, for messages.
    pub origin: String,
    /// The directory relative paths in the file start at.
    pub base: PathBuf,
}

impl Source {
    /// Reads a scenario file.
    pub fn read(path: &Path) -> Result<Self, String> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("{}: cannot read scenario: {e}", path.display()))?;
        Ok(Source {
            text,
            origin: path.display().to_string(),
            base: path.parent().map(Path::to_path_buf).unwrap_or_default(),
        })
    }

    /// The built-in demo (`examples/dem/demo_hopper.toml`).
    pub fn demo() -> Self {
        Source {
            text: DEMO.to_string(),
            origin: "demo_hopper.toml".into(),
            base: PathBuf::from("."),
        }
    }
}
