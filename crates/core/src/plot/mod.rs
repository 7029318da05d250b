//! PNG plots: line plots of histories, particle maps and polar maps of binned fields.
//!
//! Plots are diagnostics, so they must never take a run down: empty series,
//! single points, constant data and non-finite values all produce a valid
//! (if uninformative) image, and every failure is a [`PlotError`], not a
//! panic. Files are written to a temporary name and renamed into place.

mod bar;
mod colormap;
mod disks;
mod line;
mod polar;
mod ticks;

pub use colormap::{diverging, viridis};
pub use disks::scatter_disks_png;
pub use line::{LinePlot, Series};
pub use polar::{ColourScale, Overlay, PolarMap};

use plotters::prelude::*;

/// Why a plot could not be written.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// Creating or renaming the file failed.
    #[error("plot file: {0}")]
    Io(#[from] std::io::Error),
    /// The drawing backend failed (font lookup, encoding, ...).
    #[error("drawing plot: {0}")]
    Draw(String),
    /// The caller's data is inconsistent (e.g. x and y of different length).
    #[error("invalid plot input: {0}")]
    InvalidInput(String),
}

impl<E: std::error::Error + Send + Sync> From<DrawingAreaErrorKind<E>> for PlotError {
    fn from(e: DrawingAreaErrorKind<E>) -> Self {
        PlotError::Draw(e.to_string())
    }
}

/// Font family for all text; resolved through fontconfig, so it works with
/// whatever sans-serif font the system has.
const FONT: &str = "sans-serif";

/// Distinct, colour-blind-friendly series colours (Okabe–Ito order, black
/// last), cycled if there are more series.
const PALETTE: [RGBColor; 8] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(120, 120, 120),
    RGBColor(0, 0, 0),
];

fn palette(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// True if the file exists and starts with the PNG signature.
#[cfg(test)]
pub(crate) fn is_png(path: &std::path::Path) -> bool {
    std::fs::read(path)
        .map(|b| b.starts_with(b"\x89PNG"))
        .unwrap_or(false)
}

#[cfg(test)]
pub(crate) fn test_dir() -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("grains-core-plot-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn palette_cycles_and_is_distinct() {
        assert_eq!(palette(0), palette(8));
        for i in 0..8 {
            for j in 0..i {
                assert_ne!(palette(i), palette(j));
            }
        }
    }
}
