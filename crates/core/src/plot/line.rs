//! Line (or marker) plots of one or more `y(x)` series.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::ticks::{axis_range, extent, format_linear, format_pow10, plottable};
use super::{palette, PlotError, FONT};
use crate::atomic::write_atomic_via_path;

/// Image size in pixels: wide enough for long time axes, legible when
/// scaled down in a report.
pub(super) const SIZE: (u32, u32) = (1200, 750);

/// One named curve; `x` and `y` must have the same length.
#[derive(Clone, Copy, Debug)]
pub struct Series<'a> {
    /// Legend label (an empty name gets no legend entry).
    pub name: &'a str,
    /// Abscissae.
    pub x: &'a [f64],
    /// Ordinates.
    pub y: &'a [f64],
}

/// A line plot written as PNG.
#[derive(Clone, Debug)]
pub struct LinePlot<'a> {
    /// Caption above the plot.
    pub title: &'a str,
    /// X axis label.
    pub x_label: &'a str,
    /// Y axis label.
    pub y_label: &'a str,
    /// Curves, drawn in order with distinct colours.
    pub series: Vec<Series<'a>>,
    /// Logarithmic y axis; non-positive values are skipped.
    pub log_y: bool,
    /// Draw markers at the points instead of joining them with lines.
    pub points: bool,
}

impl LinePlot<'_> {
    /// Renders the plot to `path` (PNG), atomically.
    ///
    /// Non-finite points (and non-positive ones with `log_y`) are skipped,
    /// and lines are broken there rather than bridging the gap.
    pub fn write_png(&self, path: &Path) -> Result<(), PlotError> {
        self.check()?;
        write_atomic_via_path(path, |tmp| {
            super::register_font();
            let root = BitMapBackend::new(tmp, SIZE).into_drawing_area();
            self.draw_on(&root)?;
            root.present()?;
            Ok(())
        })
    }

    /// Refuses series whose x and y differ in length.
    pub(super) fn check(&self) -> Result<(), PlotError> {
        for s in &self.series {
            if s.x.len() != s.y.len() {
                return Err(PlotError::InvalidInput(format!(
                    "series {:?} has {} x values and {} y values",
                    s.name,
                    s.x.len(),
                    s.y.len()
                )));
            }
        }
        Ok(())
    }

    /// Draws the plot on `area`: the whole image, or one panel of a figure.
    pub(super) fn draw_on(
        &self,
        area: &DrawingArea<BitMapBackend, Shift>,
    ) -> Result<(), PlotError> {
        let segments: Vec<Vec<Vec<(f64, f64)>>> =
            self.series.iter().map(|s| self.segments(s)).collect();
        self.draw(area, &segments)
    }

    /// Where the legend goes so that it covers no data: the corner whose box holds
    /// the fewest points, or, when every corner holds some, the upper right with the
    /// y axis raised to leave the legend a band above the data. Returns the corner and
    /// the (possibly raised) top of the y axis.
    fn legend_place(
        &self,
        segments: &[Vec<Vec<(f64, f64)>>],
        (x0, x1): (f64, f64),
        (y0, y1): (f64, f64),
    ) -> (SeriesLabelPosition, f64) {
        let named: Vec<&str> = self
            .series
            .iter()
            .map(|s| s.name)
            .filter(|n| !n.is_empty())
            .collect();
        if named.is_empty() || !(x1 > x0 && y1 > y0) {
            return (SeriesLabelPosition::UpperRight, y1);
        }
        // The legend's size as a fraction of the plotting area (about 1050 × 590 px):
        // 9 px a character and 50 px of key and padding across, 27 px a row down.
        let longest = named.iter().map(|n| n.chars().count()).max().unwrap_or(0);
        let fw = ((9 * longest + 70) as f64 / 1050.0).min(0.95);
        let fh = ((27 * named.len() + 25) as f64 / 590.0).min(0.9);
        let corners = [
            (SeriesLabelPosition::UpperRight, true, true),
            (SeriesLabelPosition::UpperLeft, false, true),
            (SeriesLabelPosition::LowerRight, true, false),
            (SeriesLabelPosition::LowerLeft, false, false),
        ];
        let inside = |right: bool, upper: bool, (x, y): (f64, f64)| {
            let u = (x - x0) / (x1 - x0);
            let v = (y - y0) / (y1 - y0);
            (if right { u > 1.0 - fw } else { u < fw })
                && (if upper { v > 1.0 - fh } else { v < fh })
        };
        let count = |right: bool, upper: bool| {
            segments
                .iter()
                .flatten()
                .flatten()
                .filter(|p| inside(right, upper, **p))
                .count()
        };
        let best = corners
            .into_iter()
            .map(|(pos, right, upper)| (count(right, upper), pos))
            .min_by_key(|(n, _)| *n);
        match best {
            Some((0, pos)) => (pos, y1),
            _ => (
                SeriesLabelPosition::UpperRight,
                y1 + (y1 - y0) * fh / (1.0 - fh),
            ),
        }
    }

    /// Splits a series into runs of drawable points, in plot coordinates
    /// (`log10 y` when `log_y`, since the axis is drawn in exponent space).
    fn segments(&self, s: &Series) -> Vec<Vec<(f64, f64)>> {
        let mut out: Vec<Vec<(f64, f64)>> = Vec::new();
        let mut current = Vec::new();
        for (&x, &y) in s.x.iter().zip(s.y) {
            let y = if self.log_y {
                if y > 0.0 {
                    y.log10()
                } else {
                    f64::NAN
                }
            } else {
                y
            };
            if plottable(x) && plottable(y) {
                current.push((x, y));
            } else if !current.is_empty() {
                out.push(std::mem::take(&mut current));
            }
        }
        if !current.is_empty() {
            out.push(current);
        }
        out
    }

    fn draw(
        &self,
        root: &DrawingArea<BitMapBackend, Shift>,
        segments: &[Vec<Vec<(f64, f64)>>],
    ) -> Result<(), PlotError> {
        root.fill(&WHITE)?;
        let all = || segments.iter().flatten().flatten();
        let x_extent = extent(all().map(|p| p.0));
        let y_extent = extent(all().map(|p| p.1));
        let (x0, x1) = axis_range(x_extent, 0.0);
        let (y0, y1) = match y_extent {
            // Exponent space: pad a flat curve by half a decade either way
            // rather than by a fraction of its (meaningless) exponent.
            Some((lo, hi)) if self.log_y && hi - lo < 1e-9 => (lo - 0.5, hi + 0.5),
            _ => axis_range(y_extent, 0.05),
        };
        let (corner, y1) = self.legend_place(segments, (x0, x1), (y0, y1));

        let y_desc = if self.log_y {
            format!("{} (log scale)", self.y_label)
        } else {
            self.y_label.to_string()
        };
        let mut chart = ChartBuilder::on(root)
            .caption(self.title, (FONT, 30))
            .margin(20)
            .x_label_area_size(70)
            .y_label_area_size(110)
            .build_cartesian_2d(x0..x1, y0..y1)?;

        let fx = |v: &f64| format_linear(*v, x0, x1);
        let log_y = self.log_y;
        let fy = |v: &f64| {
            if log_y {
                format_pow10(*v)
            } else {
                format_linear(*v, y0, y1)
            }
        };
        chart
            .configure_mesh()
            .x_desc(self.x_label)
            .y_desc(y_desc)
            .x_label_formatter(&fx)
            .y_label_formatter(&fy)
            .label_style((FONT, 18))
            .axis_desc_style((FONT, 22))
            .light_line_style(RGBColor(235, 235, 235))
            .draw()?;

        let mut any_label = false;
        let n = self.series.len();
        for (i, (s, segs)) in self.series.iter().zip(segments).enumerate() {
            let color = palette(i, n);
            if self.points {
                let markers = segs
                    .iter()
                    .flatten()
                    .map(|&p| Circle::new(p, 3, color.filled()));
                chart.draw_series(markers)?;
            } else {
                for seg in segs {
                    chart
                        .draw_series(LineSeries::new(seg.iter().copied(), color.stroke_width(2)))?;
                }
            }
            if !s.name.is_empty() {
                any_label = true;
                // The legend entry hangs off an empty series so that a
                // curve with no drawable points still appears in it.
                let anchor = chart.draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())?;
                anchor.label(s.name);
                if self.points {
                    anchor.legend(move |(x, y)| Circle::new((x + 10, y), 4, color.filled()));
                } else {
                    anchor.legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(3))
                    });
                }
            }
        }
        if any_label {
            chart
                .configure_series_labels()
                .position(corner)
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .label_font((FONT, 18))
                .draw()?;
        }
        if x_extent.is_none() {
            let (w, h) = root.dim_in_pixel();
            root.draw(&Text::new(
                "no plottable data",
                (w as i32 / 2 - 80, h as i32 / 2),
                (FONT, 24).into_font().color(&RGBColor(150, 150, 150)),
            ))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::{is_png, test_dir};
    use super::*;

    fn plot<'a>(series: Vec<Series<'a>>, log_y: bool, points: bool) -> LinePlot<'a> {
        LinePlot {
            title: "test",
            x_label: "t (s)",
            y_label: "E (J)",
            series,
            log_y,
            points,
        }
    }

    /// Levels across the top and a curve rising from the lower left leave the lower
    /// right free: the legend goes there, not over the levels.
    #[test]
    fn the_legend_takes_the_emptiest_corner() {
        let x: Vec<f64> = (0..400).map(|i| i as f64 * 0.1).collect();
        let rise: Vec<f64> = x.iter().map(|t| 600.0 * (t / 40.0).sqrt()).collect();
        let (g, m) = (vec![880.0; x.len()], vec![770.0; x.len()]);
        let s = |name, y| Series { name, x: &x, y };
        let p = plot(
            vec![s("band", &rise), s("Gurney", &g), s("Milne", &m)],
            false,
            false,
        );
        let segs: Vec<_> = p.series.iter().map(|s| p.segments(s)).collect();
        let (corner, _) = p.legend_place(&segs, (0.0, 40.0), (0.0, 900.0));
        assert_eq!(corner, SeriesLabelPosition::LowerRight);
        // Nothing drawn: upper right, as before.
        let empty = plot(
            vec![Series {
                name: "a",
                x: &[],
                y: &[],
            }],
            false,
            false,
        );
        assert_eq!(
            empty.legend_place(&[vec![]], (0.0, 1.0), (0.0, 1.0)).0,
            SeriesLabelPosition::UpperRight
        );
    }

    #[test]
    fn normal_plot_with_legend() {
        let x: Vec<f64> = (0..200).map(|i| i as f64 * 1e-7).collect();
        let a: Vec<f64> = x.iter().map(|t| (t * 1e7).sin()).collect();
        let b: Vec<f64> = x.iter().map(|t| (t * 1e7).cos() * 0.5).collect();
        let p = test_dir().join("normal.png");
        plot(
            vec![
                Series {
                    name: "sin",
                    x: &x,
                    y: &a,
                },
                Series {
                    name: "cos",
                    x: &x,
                    y: &b,
                },
            ],
            false,
            false,
        )
        .write_png(&p)
        .unwrap();
        assert!(is_png(&p));
    }

    #[test]
    fn degenerate_inputs_do_not_panic() {
        let dir = test_dir();
        let nan = [f64::NAN, 1.0, f64::INFINITY, 2.0, f64::NEG_INFINITY];
        let xs = [0.0, 1.0, 2.0, 3.0, 4.0];
        let cases: Vec<(&str, Vec<Series>, bool)> = vec![
            ("none", vec![], false),
            (
                "empty",
                vec![Series {
                    name: "e",
                    x: &[],
                    y: &[],
                }],
                false,
            ),
            (
                "single",
                vec![Series {
                    name: "s",
                    x: &[1.0],
                    y: &[2.0],
                }],
                false,
            ),
            (
                "const",
                vec![Series {
                    name: "c",
                    x: &xs,
                    y: &[3.0; 5],
                }],
                false,
            ),
            (
                "zeros",
                vec![Series {
                    name: "",
                    x: &xs,
                    y: &[0.0; 5],
                }],
                false,
            ),
            (
                "nan",
                vec![Series {
                    name: "n",
                    x: &xs,
                    y: &nan,
                }],
                false,
            ),
            (
                "allnan",
                vec![Series {
                    name: "n",
                    x: &xs,
                    y: &[f64::NAN; 5],
                }],
                true,
            ),
            (
                "lognonpos",
                vec![Series {
                    name: "l",
                    x: &xs,
                    y: &[0.0, -1.0, 1e-20, 1e-5, 1.0],
                }],
                true,
            ),
            (
                "logconst",
                vec![Series {
                    name: "l",
                    x: &xs,
                    y: &[1e-7; 5],
                }],
                true,
            ),
            (
                "huge",
                vec![Series {
                    name: "h",
                    x: &xs,
                    y: &[1e308, -1e308, 1.0, 2.0, 3.0],
                }],
                false,
            ),
        ];
        for (name, series, log_y) in cases {
            for points in [false, true] {
                let p = dir.join(format!("{name}-{points}.png"));
                plot(series.clone(), log_y, points)
                    .write_png(&p)
                    .unwrap_or_else(|e| panic!("{name}: {e}"));
                assert!(is_png(&p), "{name}");
            }
        }
    }

    #[test]
    fn many_series_and_mismatched_lengths() {
        let x: Vec<f64> = (0..50).map(f64::from).collect();
        let ys: Vec<Vec<f64>> = (0..10)
            .map(|k| x.iter().map(|v| v * k as f64).collect())
            .collect();
        let names: Vec<String> = (0..10).map(|k| format!("k={k}")).collect();
        let series = ys
            .iter()
            .zip(&names)
            .map(|(y, n)| Series { name: n, x: &x, y })
            .collect();
        let p = test_dir().join("many.png");
        plot(series, false, false).write_png(&p).unwrap();

        let bad = plot(
            vec![Series {
                name: "b",
                x: &x,
                y: &x[..3],
            }],
            false,
            false,
        );
        let q = test_dir().join("bad.png");
        assert!(matches!(bad.write_png(&q), Err(PlotError::InvalidInput(_))));
        assert!(!q.exists());
    }

    #[test]
    fn unwritable_path_is_an_error() {
        let p = test_dir().join("no/such/dir/x.png");
        let r = plot(vec![], false, false).write_png(&p);
        assert!(r.is_err());
    }
}
