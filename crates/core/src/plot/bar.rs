//! The colour bar beside a map: the value range drawn as bands of the map's colours,
//! with a labelled axis.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::ticks::format_linear;
use super::{PlotError, FONT};

/// Colour-bar resolution; more bands than visible colour steps.
const BAR_BANDS: usize = 128;

/// Draws a vertical colour bar for values `v0..v1` in `area`, whose colour at a
/// fraction `t` of the range is `colour(t)`; `label` (with units) names the axis.
/// `top`/`bottom` margins line the bar up with the map beside it.
pub(crate) fn draw_colour_bar(
    area: &DrawingArea<BitMapBackend, Shift>,
    (v0, v1): (f64, f64),
    label: &str,
    (top, bottom): (u32, u32),
    colour: impl Fn(f64) -> RGBColor,
) -> Result<(), PlotError> {
    let mut chart = ChartBuilder::on(area)
        .margin_top(top)
        .margin_bottom(bottom)
        .margin_left(20)
        .margin_right(10)
        .right_y_label_area_size(120)
        .build_cartesian_2d(0.0..1.0, v0..v1)?;
    // Two spaces keep the first digit clear of the tick marks, which otherwise cover
    // it ("0.8" read as ".8").
    let fy = |v: &f64| format!("  {}", format_linear(*v, v0, v1));
    // The bands fill the left of the bar's cell and go first, so that the tick labels
    // (which the compiled-in font's layout places partly over the cell) stay readable.
    let dv = (v1 - v0) / BAR_BANDS as f64;
    chart.draw_series((0..BAR_BANDS).map(|k| {
        let lo = v0 + k as f64 * dv;
        let t = (k as f64 + 0.5) / BAR_BANDS as f64;
        Rectangle::new([(0.0, lo), (0.4, lo + dv)], colour(t).filled())
    }))?;
    chart
        .configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_desc(label)
        .y_label_formatter(&fy)
        .label_style((FONT, 16))
        .axis_desc_style((FONT, 20))
        .draw()?;
    Ok(())
}
