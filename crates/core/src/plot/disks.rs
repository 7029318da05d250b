//! Particle maps: disks at their true size, coloured by a per-particle value.

use std::path::Path;

use glam::DVec2;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::bar::draw_colour_bar;
use super::colormap::viridis;
use super::ticks::{axis_range, extent, format_linear, plottable};
use super::{PlotError, FONT};
use crate::atomic::write_atomic_via_path;

/// Largest image size; square-ish because packings usually are.
const SIZE: (u32, u32) = (1200, 1000);
/// The least image height, for flat content (a heap, a layer).
const MIN_HEIGHT: u32 = 520;
/// Height the title takes (its font at 28 px and padding).
const TITLE: u32 = 50;
/// Width reserved at the right for the colour bar.
const BAR_AREA: u32 = 190;
const MARGIN: u32 = 20;
const X_LABELS: u32 = 70;
const Y_LABELS: u32 = 120;

/// Geometry drawn over a particle map: a wall, a plate, the edge of a charge.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Outline {
    /// Points of the poly-line (m).
    pub points: Vec<DVec2>,
    /// Join the last point back to the first.
    pub closed: bool,
}

/// A map of disks (particles, material points) at their true size, coloured by a
/// value, with the geometry they live in drawn over them.
#[derive(Clone, Debug)]
pub struct ParticleMap<'a> {
    /// Caption; say what is shown and when (with the time's unit).
    pub title: &'a str,
    /// Disk centres (m).
    pub centres: &'a [DVec2],
    /// Disk radii (m).
    pub radii: &'a [f64],
    /// The value each disk is coloured by.
    pub values: &'a [f64],
    /// The colour bar's label, with the value's unit.
    pub value_label: &'a str,
    /// Walls, plates, a charge's edge: drawn as black lines.
    pub outlines: &'a [Outline],
}

/// A length unit for the axes: its name and its size in metres, chosen so that the
/// tick labels of an extent `span` (m) read as plain numbers.
pub fn length_unit(span: f64) -> (&'static str, f64) {
    if span >= 0.5 || !span.is_finite() {
        ("m", 1.0)
    } else if span >= 5e-4 {
        ("mm", 1e-3)
    } else {
        ("µm", 1e-6)
    }
}

impl ParticleMap<'_> {
    /// Draws the map with equal x/y scaling, axes labelled in a fitting length unit and
    /// a colour bar (viridis-like), written to `path` (PNG) atomically.
    ///
    /// Disks smaller than a pixel are drawn as single pixels so that dense, fine
    /// packings stay visible and fast (~100k disks). Disks with a non-finite centre or
    /// radius are skipped; a non-finite value is drawn grey. The axes span the disks;
    /// outlines are clipped to them.
    pub fn write_png(&self, path: &Path) -> Result<(), PlotError> {
        self.write_png_axes(path, ["x", "y"])
    }

    /// [`ParticleMap::write_png`] with the axes named `axes` (a projection of 3D
    /// particles onto x–z, say).
    pub fn write_png_axes(&self, path: &Path, axes: [&str; 2]) -> Result<(), PlotError> {
        let n = self.centres.len();
        if self.radii.len() != n || self.values.len() != n {
            return Err(PlotError::InvalidInput(format!(
                "{} centres, {} radii and {} values",
                n,
                self.radii.len(),
                self.values.len()
            )));
        }
        let disks: Vec<(DVec2, f64, f64)> = self
            .centres
            .iter()
            .zip(self.radii)
            .zip(self.values)
            .filter(|((c, r), _)| plottable(c.x) && plottable(c.y) && plottable(**r))
            .map(|((c, r), v)| (*c, r.abs(), *v))
            .collect();
        let span = extent(disks.iter().flat_map(|d| [d.0.x, d.0.y])).map_or(1.0, |(a, b)| b - a);
        let (unit, metres) = length_unit(span);
        // Everything in display units from here on.
        let disks: Vec<(DVec2, f64, f64)> = disks
            .into_iter()
            .map(|(c, r, v)| (c / metres, r / metres, v))
            .collect();
        let outlines: Vec<Vec<(f64, f64)>> = self
            .outlines
            .iter()
            .map(|o| {
                let mut pts: Vec<(f64, f64)> = o
                    .points
                    .iter()
                    .map(|p| (p.x / metres, p.y / metres))
                    .collect();
                if o.closed && !pts.is_empty() {
                    pts.push(pts[0]);
                }
                pts
            })
            .collect();
        write_atomic_via_path(path, |tmp| {
            super::register_font();
            let size = image_size(content_ranges(&disks, &outlines));
            let root = BitMapBackend::new(tmp, size).into_drawing_area();
            root.fill(&WHITE)?;
            let root = root.titled(self.title, (FONT, 28))?;
            let (w, _) = root.dim_in_pixel();
            let (map, bar) = root.split_horizontally(w.saturating_sub(BAR_AREA));
            let v_range = axis_range(extent(disks.iter().map(|d| d.2)), 0.0);
            draw_map(&map, &disks, &outlines, unit, axes, v_range)?;
            draw_colour_bar(
                &bar,
                v_range,
                self.value_label,
                (MARGIN, MARGIN + X_LABELS),
                viridis,
            )?;
            root.present()?;
            Ok(())
        })
    }
}

/// Draws disks (`centres`, `radii`) filled with the colour of `values`, with no
/// outlines: a [`ParticleMap`] in one call.
pub fn scatter_disks_png(
    path: &Path,
    title: &str,
    centres: &[DVec2],
    radii: &[f64],
    values: &[f64],
    value_label: &str,
) -> Result<(), PlotError> {
    ParticleMap {
        title,
        centres,
        radii,
        values,
        value_label,
        outlines: &[],
    }
    .write_png(path)
}

/// The ranges the disks and the outline points near them cover, before any widening.
/// The outline points that lie within twice the disks' span of them are covered too: a
/// box's walls are in view, a 'floor' a kilometre long is not.
fn content_ranges(
    disks: &[(DVec2, f64, f64)],
    outlines: &[Vec<(f64, f64)>],
) -> ((f64, f64), (f64, f64)) {
    let ex = extent(disks.iter().flat_map(|d| [d.0.x - d.1, d.0.x + d.1]));
    let ey = extent(disks.iter().flat_map(|d| [d.0.y - d.1, d.0.y + d.1]));
    let near: Vec<(f64, f64)> = match (ex, ey) {
        (Some((a, b)), Some((c, d))) => {
            let reach = 2.0 * (b - a).max(d - c);
            outlines
                .iter()
                .flatten()
                .copied()
                .filter(|p| {
                    p.0 > a - reach && p.0 < b + reach && p.1 > c - reach && p.1 < d + reach
                })
                .collect()
        }
        _ => Vec::new(),
    };
    let x = axis_range(
        extent(
            disks
                .iter()
                .flat_map(|d| [d.0.x - d.1, d.0.x + d.1])
                .chain(near.iter().map(|p| p.0)),
        ),
        0.02,
    );
    let y = axis_range(
        extent(
            disks
                .iter()
                .flat_map(|d| [d.0.y - d.1, d.0.y + d.1])
                .chain(near.iter().map(|p| p.1)),
        ),
        0.02,
    );
    (x, y)
}

/// The image size for content spanning `ranges` at equal scaling: the full width, and a
/// height that follows the content's aspect between [`MIN_HEIGHT`] and [`SIZE`]'s, so
/// that a flat heap or a thin layer is not drawn in a square of white.
fn image_size(((x0, x1), (y0, y1)): ((f64, f64), (f64, f64))) -> (u32, u32) {
    let map_w = (SIZE.0 - BAR_AREA - 2 * MARGIN - Y_LABELS) as f64;
    let frame = (TITLE + 2 * MARGIN + X_LABELS) as f64;
    let want = frame + map_w * (y1 - y0) / (x1 - x0);
    let h = if want.is_finite() {
        want.clamp(MIN_HEIGHT as f64, SIZE.1 as f64)
    } else {
        SIZE.1 as f64
    };
    (SIZE.0, h.round() as u32)
}

/// Axis ranges covering `content`, widened along the shorter direction so one data
/// unit is the same number of pixels on both axes.
fn equal_ranges(
    ((x0, x1), (y0, y1)): ((f64, f64), (f64, f64)),
    plot_px: (u32, u32),
) -> ((f64, f64), (f64, f64)) {
    let (pw, ph) = (plot_px.0.max(1) as f64, plot_px.1.max(1) as f64);
    // Units per pixel each axis would need; the larger one wins.
    let upp = ((x1 - x0) / pw).max((y1 - y0) / ph);
    let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    let (hx, hy) = (0.5 * upp * pw, 0.5 * upp * ph);
    ((cx - hx, cx + hx), (cy - hy, cy + hy))
}

fn draw_map(
    area: &DrawingArea<BitMapBackend, Shift>,
    disks: &[(DVec2, f64, f64)],
    outlines: &[Vec<(f64, f64)>],
    unit: &str,
    axes: [&str; 2],
    (v0, v1): (f64, f64),
) -> Result<(), PlotError> {
    let (w, h) = area.dim_in_pixel();
    let plot_px = (
        w.saturating_sub(2 * MARGIN + Y_LABELS),
        h.saturating_sub(2 * MARGIN + X_LABELS),
    );
    let ((x0, x1), (y0, y1)) = equal_ranges(content_ranges(disks, outlines), plot_px);
    let mut chart = ChartBuilder::on(area)
        .margin(MARGIN)
        .x_label_area_size(X_LABELS)
        .y_label_area_size(Y_LABELS)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    let fx = |v: &f64| format_linear(*v, x0, x1);
    let fy = |v: &f64| format_linear(*v, y0, y1);
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(format!("{} ({unit})", axes[0]))
        .y_desc(format!("{} ({unit})", axes[1]))
        .x_label_formatter(&fx)
        .y_label_formatter(&fy)
        .label_style((FONT, 16))
        .axis_desc_style((FONT, 20))
        .draw()?;

    // Pixels per data unit, measured on the chart actually built, so disk
    // sizes stay true even if the layout differs from the estimate above.
    let (pw, _) = chart.plotting_area().dim_in_pixel();
    let scale = pw as f64 / (x1 - x0);
    let colour = |v: f64| viridis((v - v0) / (v1 - v0));
    // Plotters draws each element clipped to the plotting area, so disks
    // straddling the border are cut, not spilled over the labels.
    let (big, small): (Vec<_>, Vec<_>) = disks.iter().partition(|d| d.1 * scale >= 1.0);
    chart.draw_series(big.iter().map(|&&(c, r, v)| {
        Circle::new((c.x, c.y), (r * scale).round() as i32, colour(v).filled())
    }))?;
    chart.draw_series(
        small
            .iter()
            .map(|&&(c, _, v)| Pixel::new((c.x, c.y), colour(v))),
    )?;
    // Plotters pins points outside the range to its edge, which would draw a distant
    // wall along the frame: clip each segment to the range first.
    let view = ((x0, y0), (x1, y1));
    for o in outlines {
        for w in o.windows(2) {
            if let Some((a, b)) = clip(w[0], w[1], view) {
                chart.draw_series(LineSeries::new([a, b], BLACK.stroke_width(3)))?;
            }
        }
    }
    Ok(())
}

/// The part of the segment a–b inside the box `view` (Liang–Barsky), if any.
fn clip(
    a: (f64, f64),
    b: (f64, f64),
    ((x0, y0), (x1, y1)): ((f64, f64), (f64, f64)),
) -> Option<((f64, f64), (f64, f64))> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-dx, a.0 - x0),
        (dx, x1 - a.0),
        (-dy, a.1 - y0),
        (dy, y1 - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    (t0 <= t1).then_some((
        (a.0 + t0 * dx, a.1 + t0 * dy),
        (a.0 + t1 * dx, a.1 + t1 * dy),
    ))
}

#[cfg(test)]
mod tests {
    use super::super::{is_png, test_dir};
    use super::*;

    #[test]
    fn draws_a_packing() {
        let mut c = Vec::new();
        let mut r = Vec::new();
        let mut v = Vec::new();
        for i in 0..40 {
            for j in 0..20 {
                c.push(DVec2::new(i as f64 * 2e-3, j as f64 * 2e-3));
                r.push(if (i + j) % 2 == 0 { 1e-3 } else { 0.7e-3 });
                v.push(j as f64 * 1e-7);
            }
        }
        let p = test_dir().join("disks.png");
        scatter_disks_png(&p, "packing", &c, &r, &v, "speed (m/s)").unwrap();
        assert!(is_png(&p));
    }

    #[test]
    fn segments_are_clipped_to_the_view() {
        let view = ((0.0, 0.0), (1.0, 1.0));
        assert_eq!(
            clip((-1.0, 0.5), (2.0, 0.5), view),
            Some(((0.0, 0.5), (1.0, 0.5)))
        );
        assert_eq!(clip((0.0, -1.0), (1.0, -1.0), view), None);
        assert_eq!(
            clip((0.2, 0.2), (0.8, 0.8), view),
            Some(((0.2, 0.2), (0.8, 0.8)))
        );
    }

    #[test]
    fn equal_scaling() {
        let disks = [(DVec2::ZERO, 1.0, 0.0), (DVec2::new(10.0, 0.0), 1.0, 0.0)];
        let ((x0, x1), (y0, y1)) = equal_ranges(content_ranges(&disks, &[]), (800, 400));
        let ux = (x1 - x0) / 800.0;
        let uy = (y1 - y0) / 400.0;
        assert!((ux - uy).abs() < 1e-12 * ux);
        assert!(x0 <= -1.0 && x1 >= 11.0 && y0 <= -1.0 && y1 >= 1.0);
    }

    #[test]
    fn a_flat_heap_gets_a_low_image_and_a_tall_column_the_full_one() {
        let flat = ((-90.0, 90.0), (0.0, 16.0));
        assert_eq!(image_size(flat), (SIZE.0, MIN_HEIGHT));
        let tall = ((-10.0, 10.0), (0.0, 100.0));
        assert_eq!(image_size(tall), SIZE);
        let between = ((0.0, 100.0), (0.0, 60.0));
        let h = image_size(between).1;
        assert!(h > MIN_HEIGHT && h < SIZE.1, "{h}");
    }

    #[test]
    fn degenerate_inputs_do_not_panic() {
        let dir = test_dir();
        let one = [DVec2::new(1.0, 1.0)];
        scatter_disks_png(&dir.join("d0.png"), "empty", &[], &[], &[], "v").unwrap();
        scatter_disks_png(&dir.join("d1.png"), "one", &one, &[0.0], &[1.0], "v").unwrap();
        let c = [
            DVec2::new(f64::NAN, 0.0),
            DVec2::ZERO,
            DVec2::new(1e-9, 0.0),
        ];
        let r = [1.0, f64::INFINITY, 1e-12];
        let v = [f64::NAN, 1.0, f64::NAN];
        scatter_disks_png(&dir.join("d2.png"), "nan", &c, &r, &v, "v").unwrap();
        let e = scatter_disks_png(&dir.join("d3.png"), "bad", &one, &[], &[1.0], "v");
        assert!(matches!(e, Err(PlotError::InvalidInput(_))));
    }

    #[test]
    fn hundred_thousand_disks() {
        let n = 100_000;
        let side = (n as f64).sqrt() as usize;
        let c: Vec<DVec2> = (0..n)
            .map(|k| DVec2::new((k % side) as f64, (k / side) as f64))
            .collect();
        let r: Vec<f64> = (0..n).map(|k| 0.3 + 0.2 * ((k % 7) as f64 / 7.0)).collect();
        let v: Vec<f64> = c.iter().map(|p| p.x + p.y).collect();
        let p = test_dir().join("many_disks.png");
        let t = std::time::Instant::now();
        scatter_disks_png(&p, "100k", &c, &r, &v, "x+y").unwrap();
        eprintln!("100k disks: {:?}", t.elapsed());
        assert!(is_png(&p));
    }
}
