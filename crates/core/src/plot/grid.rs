//! Several line plots as the panels of one figure (xue-2019 Fig. 14 a–d draws four
//! tests side by side): each panel the size of a single plot, so its text stays legible.

use std::path::Path;

use plotters::prelude::*;

use super::line::{LinePlot, SIZE};
use super::PlotError;
use crate::atomic::write_atomic_via_path;

/// Writes `panels` row by row into a grid `columns` wide (as many rows as needed) as one
/// PNG at `path`, atomically. A panel is drawn exactly as [`LinePlot::write_png`] would.
pub fn write_grid_png(panels: &[LinePlot], columns: usize, path: &Path) -> Result<(), PlotError> {
    if panels.is_empty() || columns == 0 {
        return Err(PlotError::InvalidInput(format!(
            "a figure needs at least one panel and one column ({} panels, {columns} columns)",
            panels.len()
        )));
    }
    for p in panels {
        p.check()?;
    }
    let cols = columns.min(panels.len());
    let rows = panels.len().div_ceil(cols);
    write_atomic_via_path(path, |tmp| {
        super::register_font();
        let size = (SIZE.0 * cols as u32, SIZE.1 * rows as u32);
        let root = BitMapBackend::new(tmp, size).into_drawing_area();
        root.fill(&WHITE)?;
        for (p, area) in panels.iter().zip(root.split_evenly((rows, cols))) {
            p.draw_on(&area)?;
        }
        root.present()?;
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::super::{is_png, test_dir, Series};
    use super::*;

    #[test]
    fn panels_fill_a_grid_and_bad_input_is_refused() {
        let x: Vec<f64> = (0..50).map(|i| i as f64).collect();
        let y: Vec<f64> = x.iter().map(|v| v * v).collect();
        let panel = |title| LinePlot {
            title,
            x_label: "t (µs)",
            y_label: "v (m/s)",
            series: vec![Series {
                name: "band",
                x: &x,
                y: &y,
            }],
            log_y: false,
            points: false,
        };
        let p = test_dir().join("grid.png");
        write_grid_png(&[panel("a"), panel("b"), panel("c")], 2, &p).unwrap();
        assert!(is_png(&p));
        let b = std::fs::read(&p).unwrap();
        let dim = |k: usize| u32::from_be_bytes([b[k], b[k + 1], b[k + 2], b[k + 3]]);
        assert_eq!((dim(16), dim(20)), (2 * SIZE.0, 2 * SIZE.1));
        assert!(write_grid_png(&[], 2, &p).is_err());
        let mut bad = panel("d");
        bad.series[0].y = &y[1..];
        assert!(write_grid_png(&[bad], 1, &p).is_err());
    }
}
