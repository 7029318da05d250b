//! Polar maps: a field on polar bins (radial rings × angular sectors about a centre)
//! drawn as the bins themselves, with the charge, overlay curves and a colour bar, the
//! way xue-2019 shows its coarse-grained fields (Figs. 5, 7, 8, 11, 12).

use std::f64::consts::TAU;
use std::path::Path;

use glam::DVec2;
use plotters::coord::Shift;
use plotters::element::BitMapElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::bar::draw_colour_bar;
use super::colormap::{diverging, viridis};
use super::ticks::{axis_range, extent, format_linear, plottable};
use super::{PlotError, FONT};
use crate::atomic::write_atomic_via_path;

/// Image size in pixels: a square map plus the colour bar.
const SIZE: (u32, u32) = (1180, 1000);
/// Width reserved at the right for the colour bar.
const BAR_AREA: u32 = 200;
const MARGIN: u32 = 20;
const X_LABELS: u32 = 60;
const Y_LABELS: u32 = 80;
/// Lengths are drawn in millimetres: the rings of the suite are millimetre-sized.
const MM: f64 = 1e3;
/// Fraction of values left out at each end of an automatic colour range, so that a
/// few extreme bins (a shock front, a lone grain) do not wash out the map.
const ROBUST_TAIL: f64 = 0.01;

/// How values map to colours.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColourScale {
    /// Viridis-like ramp from the lowest to the highest value (magnitudes).
    Sequential,
    /// Blue–white–red centred on zero (signed fields such as a dilation rate); the
    /// automatic range is symmetric.
    Diverging,
}

/// A curve drawn over the map, in metres relative to the map's centre.
#[derive(Clone, Copy, Debug)]
pub struct Overlay<'a> {
    /// Vertices relative to the centre (m).
    pub points: &'a [DVec2],
    /// Join the last vertex back to the first.
    pub closed: bool,
    /// Line colour (RGB).
    pub colour: [u8; 3],
    /// Legend entry; empty for none.
    pub label: &'a str,
}

/// A field on polar bins, written as PNG by [`PolarMap::write_png`].
///
/// Bin `(i, j)` spans radii `r_edges[i]..r_edges[i + 1]` and angles
/// `j·2π/n_theta..(j + 1)·2π/n_theta` counter-clockwise from +x; its value is
/// `values[j * (r_edges.len() - 1) + i]` (radial index fastest). NaN values (no data)
/// are left white.
#[derive(Clone, Debug)]
pub struct PolarMap<'a> {
    /// Caption; say what and when (e.g. "pressure, t = 5.0 µs").
    pub title: &'a str,
    /// Colour-bar label, with units.
    pub value_label: &'a str,
    /// Radial bin edges (m), increasing.
    pub r_edges: &'a [f64],
    /// Angular sectors over the full circle.
    pub n_theta: usize,
    /// One value per bin, radial index fastest.
    pub values: &'a [f64],
    /// Colour scale.
    pub scale: ColourScale,
    /// Colour range; `None` takes the 1st–99th percentile of the finite values
    /// (symmetric about zero for [`ColourScale::Diverging`]).
    pub range: Option<(f64, f64)>,
    /// Half-width of the square view about the centre (m).
    pub view_radius: f64,
    /// Radius of the charge, drawn as a grey disk at the centre.
    pub charge_radius: Option<f64>,
    /// Curves drawn over the map.
    pub overlays: Vec<Overlay<'a>>,
}

impl PolarMap<'_> {
    /// Renders the map to `path` (PNG), atomically.
    pub fn write_png(&self, path: &Path) -> Result<(), PlotError> {
        let nr = self.r_edges.len().saturating_sub(1);
        if self.values.len() != nr * self.n_theta {
            return Err(PlotError::InvalidInput(format!(
                "{} values for {nr} radial bins x {} sectors",
                self.values.len(),
                self.n_theta
            )));
        }
        if self
            .r_edges
            .windows(2)
            .any(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
        {
            return Err(PlotError::InvalidInput(
                "radial bin edges must increase".into(),
            ));
        }
        if !(self.view_radius > 0.0 && self.view_radius.is_finite()) {
            return Err(PlotError::InvalidInput(format!(
                "view radius {} must be positive",
                self.view_radius
            )));
        }
        let range = self.colour_range();
        write_atomic_via_path(path, |tmp| {
            super::register_font();
            let root = BitMapBackend::new(tmp, SIZE).into_drawing_area();
            root.fill(&WHITE)?;
            let root = root.titled(self.title, (FONT, 30))?;
            let (w, _) = root.dim_in_pixel();
            let (map, bar) = root.split_horizontally(w.saturating_sub(BAR_AREA));
            self.draw_map(&map, range)?;
            let colour = |t: f64| self.colour(t);
            draw_colour_bar(
                &bar,
                range,
                self.value_label,
                (MARGIN, MARGIN + X_LABELS),
                colour,
            )?;
            root.present()?;
            Ok(())
        })
    }

    fn colour(&self, t: f64) -> RGBColor {
        match self.scale {
            ColourScale::Sequential => viridis(t),
            ColourScale::Diverging => diverging(t),
        }
    }

    /// The colour range: given, or robust percentiles of the data.
    fn colour_range(&self) -> (f64, f64) {
        if let Some((lo, hi)) = self.range {
            if plottable(lo) && plottable(hi) && hi > lo {
                return (lo, hi);
            }
        }
        let mut v: Vec<f64> = self
            .values
            .iter()
            .copied()
            .filter(|x| plottable(*x))
            .collect();
        if v.is_empty() {
            return (0.0, 1.0);
        }
        v.sort_by(f64::total_cmp);
        let at = |q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
        match self.scale {
            ColourScale::Sequential => {
                axis_range(Some((at(ROBUST_TAIL), at(1.0 - ROBUST_TAIL))), 0.0)
            }
            ColourScale::Diverging => {
                let a = at(ROBUST_TAIL).abs().max(at(1.0 - ROBUST_TAIL).abs());
                if a > 0.0 {
                    (-a, a)
                } else {
                    (-1.0, 1.0)
                }
            }
        }
    }

    /// The value of the bin holding the point `p` (m, relative to the centre).
    #[cfg(test)]
    fn value_at(&self, p: DVec2) -> f64 {
        self.bin_at(p, &Rings::of(self.r_edges))
            .map_or(f64::NAN, |k| self.values[k])
    }

    /// The bin holding the point `p` (m, relative to the centre), if any.
    #[inline]
    fn bin_at(&self, p: DVec2, rings: &Rings) -> Option<usize> {
        let r = p.length();
        let nr = self.r_edges.len().saturating_sub(1);
        if nr == 0 || self.n_theta == 0 || r < self.r_edges[0] || r >= self.r_edges[nr] {
            return None;
        }
        let i = match rings.uniform {
            // Equal rings (the dispersal grids): the ring is a division, not a search.
            Some((r0, inv_dr)) => ((r - r0) * inv_dr) as usize,
            None => self.r_edges.partition_point(|&e| e <= r) - 1,
        };
        // atan2 lies in [−π, π]: one add, not a floating-point remainder, per pixel.
        let a = p.y.atan2(p.x);
        let a = if a < 0.0 { a + TAU } else { a };
        let j = ((a / TAU * self.n_theta as f64) as usize).min(self.n_theta - 1);
        Some(j * nr + i.min(nr - 1))
    }

    fn draw_map(
        &self,
        area: &DrawingArea<BitMapBackend, Shift>,
        (v0, v1): (f64, f64),
    ) -> Result<(), PlotError> {
        let half = self.view_radius * MM;
        // Build once to learn the plotting area's size, then again with the shorter
        // direction widened so a millimetre is the same number of pixels both ways.
        let probe = ChartBuilder::on(area)
            .margin(MARGIN)
            .x_label_area_size(X_LABELS)
            .y_label_area_size(Y_LABELS)
            .build_cartesian_2d(-half..half, -half..half)?;
        let (pw, ph) = probe.plotting_area().dim_in_pixel();
        let upp = 2.0 * half / pw.min(ph).max(1) as f64;
        let (hx, hy) = (0.5 * upp * pw as f64, 0.5 * upp * ph as f64);
        let mut chart = ChartBuilder::on(area)
            .margin(MARGIN)
            .x_label_area_size(X_LABELS)
            .y_label_area_size(Y_LABELS)
            .build_cartesian_2d(-hx..hx, -hy..hy)?;
        let fx = |v: &f64| format_linear(*v, -hx, hx);
        let fy = |v: &f64| format_linear(*v, -hy, hy);
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("x (mm)")
            .y_desc("y (mm)")
            .x_label_formatter(&fx)
            .y_label_formatter(&fy)
            .label_style((FONT, 16))
            .axis_desc_style((FONT, 20))
            .draw()?;

        // Bins are painted pixel by pixel into one bitmap: exact bin shapes at any
        // resolution, and independent of the number of bins.
        let (pw, ph) = chart.plotting_area().dim_in_pixel();
        let mut buf = vec![255u8; (pw * ph * 3) as usize];
        let span = v1 - v0;
        // A colour per bin, then per pixel only the bin it falls in.
        let colours: Vec<Option<[u8; 3]>> = self
            .values
            .iter()
            .map(|v| {
                v.is_finite().then(|| {
                    let c = self.colour((v - v0) / span);
                    [c.0, c.1, c.2]
                })
            })
            .collect();
        let rings = Rings::of(self.r_edges);
        for py in 0..ph {
            let y = hy - (py as f64 + 0.5) / ph as f64 * 2.0 * hy;
            for px in 0..pw {
                let x = -hx + (px as f64 + 0.5) / pw as f64 * 2.0 * hx;
                let Some(c) = self
                    .bin_at(DVec2::new(x, y) / MM, &rings)
                    .and_then(|k| colours[k])
                else {
                    continue;
                };
                let k = ((py * pw + px) * 3) as usize;
                buf[k..k + 3].copy_from_slice(&c);
            }
        }
        if let Some(img) = BitMapElement::with_owned_buffer((-hx, hy), (pw, ph), buf) {
            chart.draw_series(std::iter::once(img))?;
        }

        if let Some(rc) = self.charge_radius.filter(|r| *r > 0.0 && r.is_finite()) {
            let circle = circle_points(rc * MM);
            chart.draw_series(std::iter::once(Polygon::new(
                circle.clone(),
                RGBColor(215, 215, 215).filled(),
            )))?;
            chart.draw_series(std::iter::once(PathElement::new(
                circle,
                RGBColor(90, 90, 90).stroke_width(2),
            )))?;
            chart.draw_series(std::iter::once(Text::new(
                "charge",
                (0.0, 0.0),
                (FONT, 18)
                    .into_font()
                    .color(&RGBColor(60, 60, 60))
                    .pos(Pos::new(HPos::Center, VPos::Center)),
            )))?;
        }

        let mut any_label = false;
        for o in &self.overlays {
            let mut pts: Vec<(f64, f64)> = o
                .points
                .iter()
                .filter(|p| plottable(p.x) && plottable(p.y))
                .map(|p| (p.x * MM, p.y * MM))
                .collect();
            if pts.is_empty() {
                continue;
            }
            if o.closed {
                pts.push(pts[0]);
            }
            let c = RGBColor(o.colour[0], o.colour[1], o.colour[2]);
            let s = chart.draw_series(std::iter::once(PathElement::new(pts, c.stroke_width(2))))?;
            if !o.label.is_empty() {
                any_label = true;
                s.label(o.label).legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(3))
                });
            }
        }
        if any_label {
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperRight)
                .background_style(RGBColor(200, 200, 200).mix(0.9))
                .border_style(BLACK)
                .label_font((FONT, 16))
                .draw()?;
        }
        if extent(self.values.iter().copied()).is_none() {
            chart.draw_series(std::iter::once(Text::new(
                "no data",
                (-0.1 * hx, 0.5 * hy),
                (FONT, 24).into_font().color(&RGBColor(150, 150, 150)),
            )))?;
        }
        Ok(())
    }
}

/// A closed circle of radius `r` as a polyline.
fn circle_points(r: f64) -> Vec<(f64, f64)> {
    (0..=180)
        .map(|k| {
            let a = TAU * k as f64 / 180.0;
            (r * a.cos(), r * a.sin())
        })
        .collect()
}

/// How to find a ring from a radius: equal rings by division, others by search.
struct Rings {
    /// Inner radius and 1/width, when every ring has the same width.
    uniform: Option<(f64, f64)>,
}

impl Rings {
    fn of(edges: &[f64]) -> Self {
        let n = edges.len();
        let uniform = (n >= 2).then(|| (edges[n - 1] - edges[0]) / (n - 1) as f64);
        let uniform = uniform.filter(|dr| {
            *dr > 0.0
                && edges
                    .iter()
                    .enumerate()
                    .all(|(k, e)| (e - (edges[0] + k as f64 * dr)).abs() <= 1e-9 * dr)
        });
        Rings {
            uniform: uniform.map(|dr| (edges[0], 1.0 / dr)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::{is_png, test_dir};
    use super::*;

    fn map<'a>(edges: &'a [f64], values: &'a [f64], nt: usize) -> PolarMap<'a> {
        PolarMap {
            title: "test, t = 1.0 µs",
            value_label: "p (MPa)",
            r_edges: edges,
            n_theta: nt,
            values,
            scale: ColourScale::Sequential,
            range: None,
            view_radius: 0.03,
            charge_radius: Some(0.01),
            overlays: vec![],
        }
    }

    #[test]
    fn bins_are_looked_up_by_radius_and_angle() {
        let edges = [0.01, 0.02, 0.03];
        let values = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0];
        let m = map(&edges, &values, 4);
        assert_eq!(m.value_at(DVec2::new(0.015, 0.001)), 0.0);
        assert_eq!(m.value_at(DVec2::new(0.025, 0.001)), 1.0);
        assert_eq!(m.value_at(DVec2::new(-0.001, 0.015)), 2.0);
        assert_eq!(m.value_at(DVec2::new(0.001, -0.025)), 7.0);
        assert!(m.value_at(DVec2::new(0.005, 0.0)).is_nan());
        assert!(m.value_at(DVec2::new(0.031, 0.0)).is_nan());
    }

    #[test]
    fn draws_a_ring_with_overlays() {
        let nr = 20;
        let nt = 180;
        let edges: Vec<f64> = (0..=nr).map(|i| 0.01 + i as f64 * 1e-3).collect();
        let values: Vec<f64> = (0..nt * nr)
            .map(|k| {
                let (i, j) = (k % nr, k / nr);
                if i > 15 {
                    f64::NAN
                } else {
                    (6.0 * TAU * j as f64 / nt as f64).sin() * (i as f64 - 7.0)
                }
            })
            .collect();
        let hexagon: Vec<DVec2> = (0..6)
            .map(|k| 0.02 * DVec2::from_angle(TAU * k as f64 / 6.0))
            .collect();
        let mut m = map(&edges, &values, nt);
        m.scale = ColourScale::Diverging;
        m.overlays.push(Overlay {
            points: &hexagon,
            closed: true,
            colour: [0, 0, 0],
            label: "front",
        });
        let p = test_dir().join("polar.png");
        m.write_png(&p).unwrap();
        assert!(is_png(&p));
        assert_eq!(m.colour_range().0, -m.colour_range().1);
    }

    #[test]
    fn degenerate_inputs_do_not_panic() {
        let dir = test_dir();
        let edges = [0.01, 0.02];
        map(&edges, &[f64::NAN; 3], 3)
            .write_png(&dir.join("p0.png"))
            .unwrap();
        map(&edges, &[5.0; 3], 3)
            .write_png(&dir.join("p1.png"))
            .unwrap();
        map(&[], &[], 0).write_png(&dir.join("p2.png")).unwrap();
        let bad = map(&edges, &[1.0; 2], 3);
        assert!(matches!(
            bad.write_png(&dir.join("p3.png")),
            Err(PlotError::InvalidInput(_))
        ));
        let bad = map(&[0.02, 0.01], &[1.0; 3], 3);
        assert!(bad.write_png(&dir.join("p4.png")).is_err());
        let mut bad = map(&edges, &[1.0; 3], 3);
        bad.view_radius = 0.0;
        assert!(bad.write_png(&dir.join("p5.png")).is_err());
    }
}
