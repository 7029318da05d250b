//! What gets analysed: disks read from a packing file (`x y r` lines, `#` header) or a
//! DEM particle frame (`.vtp` with a `radius` point array).

use crate::region::Region;
use glam::DVec2;
use std::path::Path;

/// Header key of the packing region, e.g. `# domain = annulus centre_x=0 ...`.
pub const DOMAIN_KEY: &str = "domain";
/// Header key of the number of boundary-layer disks, which come first in the file.
pub const LINING_KEY: &str = "lining";

/// Where the disks came from; it sets the contact criterion.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SampleKind {
    /// A generated packing: contacts are gaps up to 10⁻³ d0.
    Packing,
    /// A DEM frame: contacts are overlaps (positive elastic normal force).
    DemFrame,
}

/// A set of disks to analyse.
#[derive(Clone, Debug)]
pub struct Sample {
    /// Centres.
    pub pos: Vec<DVec2>,
    /// Radii.
    pub radius: Vec<f64>,
    /// The first `lining` disks are a boundary layer, left out of size statistics.
    pub lining: usize,
    /// The container, when the file says.
    pub region: Option<Region>,
    /// Packing or DEM frame.
    pub kind: SampleKind,
}

/// Why a file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The file could not be opened or read.
    #[error("{path}: cannot be read: {source}")]
    Io {
        /// File.
        path: String,
        /// Cause.
        source: std::io::Error,
    },
    /// The content is not what the format says.
    #[error("{path} line {line}: {message}")]
    Format {
        /// File.
        path: String,
        /// Line number (1-based; 0 for a whole-file problem).
        line: usize,
        /// What is wrong.
        message: String,
    },
}

/// Reads a packing file or, for a `.vtp` path, a DEM frame.
pub fn load(path: &Path) -> Result<Sample, LoadError> {
    let name = path.display().to_string();
    if path.extension().is_some_and(|e| e == "vtp") {
        return load_vtp(path, &name);
    }
    let text = std::fs::read_to_string(path).map_err(|source| LoadError::Io {
        path: name.clone(),
        source,
    })?;
    parse_packing(&text, &name)
}

/// Parses the text of a packing file.
pub fn parse_packing(text: &str, name: &str) -> Result<Sample, LoadError> {
    let bad = |line: usize, message: String| LoadError::Format {
        path: name.to_string(),
        line,
        message,
    };
    let mut s = Sample {
        pos: Vec::new(),
        radius: Vec::new(),
        lining: 0,
        region: None,
        kind: SampleKind::Packing,
    };
    for (ln, line) in text.lines().enumerate() {
        let line = line.trim();
        if let Some(h) = line.strip_prefix('#') {
            if let Some((k, v)) = h.split_once('=') {
                match k.trim() {
                    DOMAIN_KEY => {
                        s.region = Some(Region::parse(v.trim()).ok_or_else(|| {
                            bad(ln + 1, format!("domain = {}: not a valid region", v.trim()))
                        })?)
                    }
                    LINING_KEY => {
                        s.lining = v.trim().parse().map_err(|_| {
                            bad(ln + 1, format!("lining = {}: must be a count", v.trim()))
                        })?
                    }
                    _ => {}
                }
            }
            continue;
        }
        if line.is_empty() {
            continue;
        }
        let v: Vec<f64> = line
            .split_whitespace()
            .map(str::parse)
            .collect::<Result<_, _>>()
            .unwrap_or_default();
        if v.len() != 3 || !v.iter().all(|x| x.is_finite()) || v[2] <= 0.0 {
            return Err(bad(
                ln + 1,
                "each line must hold three numbers x y r with r > 0".into(),
            ));
        }
        s.pos.push(DVec2::new(v[0], v[1]));
        s.radius.push(v[2]);
    }
    if s.pos.is_empty() {
        return Err(bad(0, "no disks".into()));
    }
    if s.lining > s.pos.len() {
        return Err(bad(
            0,
            format!(
                "lining = {}: more than the {} disks in the file",
                s.lining,
                s.pos.len()
            ),
        ));
    }
    Ok(s)
}

fn load_vtp(path: &Path, name: &str) -> Result<Sample, LoadError> {
    use grains_core::vtk::{find_array, read_appended_arrays};
    let bad = |message: String| LoadError::Format {
        path: name.to_string(),
        line: 0,
        message,
    };
    let arrays = read_appended_arrays(path).map_err(|source| LoadError::Io {
        path: name.to_string(),
        source,
    })?;
    let points =
        find_array(&arrays, "Points", "Points").ok_or_else(|| bad("no Points array".into()))?;
    let radius = find_array(&arrays, "PointData", "radius")
        .ok_or_else(|| bad("no point array \"radius\"".into()))?;
    let n = radius.values.len();
    if points.components != 3 || points.values.len() != 3 * n || n == 0 {
        return Err(bad(format!(
            "{} points for {} radii",
            points.values.len() / 3,
            n
        )));
    }
    let pos = points
        .values
        .chunks_exact(3)
        .map(|p| DVec2::new(p[0], p[1]))
        .collect();
    if radius.values.iter().any(|r| !(r.is_finite() && *r > 0.0)) {
        return Err(bad("radius must be finite and positive".into()));
    }
    Ok(Sample {
        pos,
        radius: radius.values.clone(),
        lining: 0,
        region: None,
        kind: SampleKind::DemFrame,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_header_and_lines() {
        let text = "# grains pack\n# domain = disk centre_x=0 centre_y=0 radius=1\n# lining = 1\n0 0 0.1\n0.5 0 0.2\n";
        let s = parse_packing(text, "t").unwrap();
        assert_eq!(s.pos.len(), 2);
        assert_eq!(s.lining, 1);
        assert!(matches!(s.region, Some(Region::Disk { .. })));
        let e = parse_packing("0 0\n", "t").unwrap_err().to_string();
        assert!(e.contains("line 1"), "{e}");
        assert!(parse_packing("# only\n", "t").is_err());
    }
}
