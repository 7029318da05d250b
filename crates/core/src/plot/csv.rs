//! A line plot's series as CSV beside its PNG (the run contract: every plotted series
//! is also written as data a user can re-plot).

use std::path::Path;

use super::line::LinePlot;
use super::PlotError;
use crate::history::History;

impl LinePlot<'_> {
    /// Writes the plot to `png` and its series to the same name with `.csv`.
    pub fn write_png_and_csv(&self, png: &Path) -> Result<(), PlotError> {
        self.write_png(png)?;
        self.write_csv(&png.with_extension("csv"))
    }

    /// Writes the series to `path`: one x column (named by the x label) and a column
    /// per series (named by its legend) when they share their x values, else an x and
    /// a y column per series, the shorter ones padded with NaN. Commas, quotes and line
    /// breaks in the names become `;`, repeated names are numbered, so the file needs
    /// no quoting; values are written as in `history.csv`.
    pub fn write_csv(&self, path: &Path) -> Result<(), PlotError> {
        let clean = |s: &str| s.replace([',', '"', '\n', '\r'], ";");
        let first = self.series.first().map(|s| s.x);
        let shared = self.series.iter().all(|s| Some(s.x) == first);
        let mut names: Vec<String> = Vec::new();
        let mut cols: Vec<&[f64]> = Vec::new();
        for (k, s) in self.series.iter().enumerate() {
            let name = if s.name.trim().is_empty() {
                format!("series {}", k + 1)
            } else {
                clean(s.name)
            };
            if !shared || k == 0 {
                names.push(if shared {
                    clean(self.x_label)
                } else {
                    format!("{name}: {}", clean(self.x_label))
                });
                cols.push(s.x);
            }
            names.push(name);
            cols.push(s.y);
        }
        for k in 1..names.len() {
            let base = names[k].clone();
            let mut n = 2;
            while names[..k].contains(&names[k]) {
                names[k] = format!("{base} ({n})");
                n += 1;
            }
        }
        if names.is_empty() {
            names.push(clean(self.x_label));
        }
        let refs: Vec<&str> = names.iter().map(String::as_str).collect();
        let mut csv = History::create(path, &refs)?;
        let rows = cols.iter().map(|c| c.len()).max().unwrap_or(0);
        for i in 0..rows {
            let row: Vec<f64> = cols
                .iter()
                .map(|c| c.get(i).copied().unwrap_or(f64::NAN))
                .collect();
            csv.push(&row)?;
        }
        csv.flush()?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::Series;
    use super::*;
    use crate::history::read_csv;

    fn scratch(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("grains-core-csv-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    fn plot<'a>(series: Vec<Series<'a>>) -> LinePlot<'a> {
        LinePlot {
            title: "t",
            x_label: "shear strain γ",
            y_label: "stress (Pa)",
            series,
            log_y: false,
            points: false,
        }
    }

    #[test]
    fn series_on_one_x_share_a_column() {
        let g = [0.0, 0.5, 1.0];
        let (a, b) = ([1.0, 2.0, 3.0], [4.0, 5.0, 6.0]);
        let s = |name, y| Series { name, x: &g, y };
        let p = scratch("shared.png");
        plot(vec![
            s("left, boundary", &a),
            s("left, boundary", &b),
            s("", &a),
        ])
        .write_png_and_csv(&p)
        .unwrap();
        assert!(p.exists());
        let (names, rows) = read_csv(&p.with_extension("csv")).unwrap();
        assert_eq!(
            names,
            [
                "shear strain γ",
                "left; boundary",
                "left; boundary (2)",
                "series 3"
            ]
        );
        assert_eq!(rows[1], [0.5, 2.0, 5.0, 2.0]);
        assert_eq!(rows.len(), 3);
    }

    #[test]
    fn series_on_their_own_x_get_a_pair_of_columns() {
        let (g, y) = ([0.0, 0.5, 1.0], [1.0, 2.0, 3.0]);
        let (fx, fy) = ([0.0, 1.0], [1.5, 2.5]);
        let p = scratch("mixed.csv");
        plot(vec![
            Series {
                name: "MPM",
                x: &g,
                y: &y,
            },
            Series {
                name: "fit",
                x: &fx,
                y: &fy,
            },
        ])
        .write_csv(&p)
        .unwrap();
        let (names, rows) = read_csv(&p).unwrap();
        assert_eq!(
            names,
            ["MPM: shear strain γ", "MPM", "fit: shear strain γ", "fit"]
        );
        assert_eq!(rows[1], [0.5, 2.0, 1.0, 2.5]);
        assert!(rows[2][2].is_nan() && rows[2][3].is_nan());
    }
}
