//! A packing file as a 3D scenario's spheres (`source = "file"`): the `x y z r` lines
//! `grains pack` writes for a spec with `dim = 3`, `#` lines skipped.

use grains_core::input::InputError;
use std::path::Path;

/// The spheres of the packing file `full` (centre, radius), read for `key`.
pub fn read(key: &str, full: &Path) -> Result<Vec<([f64; 3], f64)>, InputError> {
    let text = std::fs::read_to_string(full).map_err(|e| {
        InputError::new(
            format!("{key}.path"),
            format!("\"{}\"", full.display()),
            format!("cannot be read: {e}"),
        )
    })?;
    let mut out = Vec::new();
    for (ln, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let v: Option<Vec<f64>> = line.split_whitespace().map(|x| x.parse().ok()).collect();
        match v.as_deref() {
            Some(&[x, y, z, r]) => out.push(([x, y, z], r)),
            _ => {
                return Err(InputError::new(
                    format!("{key}.path"),
                    format!("\"{}\" line {}", full.display(), ln + 1),
                    "each line must hold four numbers: x y z r (a 3D packing)",
                ))
            }
        }
    }
    Ok(out)
}
