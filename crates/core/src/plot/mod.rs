//! PNG plots: line plots of histories, particle maps and polar maps of binned fields.
//!
//! Plots are diagnostics, so they must never take a run down: empty series,
//! single points, constant data and non-finite values all produce a valid
//! (if uninformative) image, and every failure is a [`PlotError`], not a
//! panic. Files are written to a temporary name and renamed into place.

mod bar;
mod colormap;
mod csv;
mod disks;
mod grid;
mod line;
mod polar;
mod ticks;

pub use colormap::{diverging, viridis};
pub use disks::{length_unit, scatter_disks_png, Outline, ParticleMap};
pub use grid::write_grid_png;
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

/// Font family for all text: DejaVu Sans, compiled into the binary, so plots need no
/// system fonts or font libraries (a bare HPC node draws the same PNGs).
pub const FONT: &str = "sans-serif";

/// The font's bytes (DejaVu Sans 2.37; its licence is `fonts/DejaVuSans-LICENSE.txt`).
const FONT_BYTES: &[u8] = include_bytes!("../../fonts/DejaVuSans.ttf");

/// Registers the compiled-in font under [`FONT`] (once per process); every plot calls
/// it before drawing text.
pub fn register_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        if plotters::style::register_font(FONT, FontStyle::Normal, FONT_BYTES).is_err() {
            // The bytes are ours and tested; a failure leaves plots without text rather
            // than taking a run down.
            eprintln!("grains: the compiled-in plot font could not be loaded");
        }
    });
}

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

/// A time as people read it on a plot: seconds, milliseconds or microseconds with
/// four significant digits (`t = 40.00 µs`).
pub fn time_label(t: f64) -> String {
    let a = t.abs();
    let (v, unit) = if a == 0.0 || !a.is_finite() {
        return format!("{t} s");
    } else if a >= 1.0 {
        (t, "s")
    } else if a >= 1e-3 {
        (t * 1e3, "ms")
    } else {
        (t * 1e6, "µs")
    };
    let decimals = (3 - v.abs().log10().floor() as i32).max(0) as usize;
    format!("{v:.decimals$} {unit}")
}

/// The colour of series `i` of `n`: the palette for up to 8 series, else `n` hues
/// evenly around the colour wheel at alternating lightness, so no two series share a
/// colour however many there are.
fn palette(i: usize, n: usize) -> RGBColor {
    if n <= PALETTE.len() {
        return PALETTE[i];
    }
    let hue = i as f64 / n as f64;
    let light = if i.is_multiple_of(2) { 0.38 } else { 0.55 };
    let (r, g, b) = hsl(hue, 0.75, light);
    RGBColor(r, g, b)
}

/// HSL (all in [0, 1]) to 8-bit RGB.
fn hsl(h: f64, s: f64, l: f64) -> (u8, u8, u8) {
    let c = (1.0 - (2.0 * l - 1.0).abs()) * s;
    let hp = h * 6.0;
    let x = c * (1.0 - (hp % 2.0 - 1.0).abs());
    let (r, g, b) = match hp as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let m = l - c / 2.0;
    let to = |v: f64| ((v + m) * 255.0).round().clamp(0.0, 255.0) as u8;
    (to(r), to(g), to(b))
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
    fn times_read_in_their_unit() {
        assert_eq!(time_label(0.7), "700.0 ms");
        assert_eq!(time_label(4.0004e-5), "40.00 µs");
        assert_eq!(time_label(14.0), "14.00 s");
        assert_eq!(time_label(0.0), "0 s");
    }

    #[test]
    fn no_two_series_share_a_colour() {
        for n in [1, 5, 8, 9, 12, 30] {
            for i in 0..n {
                for j in 0..i {
                    assert_ne!(palette(i, n), palette(j, n), "{i} and {j} of {n}");
                }
            }
        }
    }
}
