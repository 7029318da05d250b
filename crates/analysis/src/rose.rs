//! The rose diagram: contact-normal density as a polar bar chart (xue-2019 Fig. 3d–e).

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::Path;

/// Why the rose diagram could not be drawn.
#[derive(Debug, thiserror::Error)]
#[error("rose diagram {path}: {message}")]
pub struct RoseError {
    path: String,
    message: String,
}

/// Draws `density` (one value per equal sector of [0, 2π), counter-clockwise from +x)
/// as a polar bar chart with a dashed circle at the isotropic density 1/(2π).
/// Written as PNG to a temporary name, then renamed into place.
pub fn rose_png(path: &Path, title: &str, density: &[f64]) -> Result<(), RoseError> {
    let err = |e: &dyn std::fmt::Display| RoseError {
        path: path.display().to_string(),
        message: e.to_string(),
    };
    let tmp = path.with_extension("tmp.png");
    draw(&tmp, title, density).map_err(|e| err(&e))?;
    std::fs::rename(&tmp, path).map_err(|e| err(&e))
}

fn draw(path: &Path, title: &str, density: &[f64]) -> Result<(), Box<dyn std::error::Error>> {
    use std::f64::consts::TAU;
    grains_core::plot::register_font();
    let root = BitMapBackend::new(path, (900, 960)).into_drawing_area();
    root.fill(&WHITE)?;
    let root = root.titled(title, (grains_core::plot::FONT, 28))?;
    let iso = 1.0 / TAU;
    let peak = density
        .iter()
        .cloned()
        .filter(|v| v.is_finite())
        .fold(iso, f64::max)
        * 1.2;
    let mut chart = ChartBuilder::on(&root)
        .margin(30)
        .build_cartesian_2d(-peak..peak, -peak..peak)?;
    let n = density.len().max(1);
    let width = TAU / n as f64;
    chart.draw_series(
        density
            .iter()
            .enumerate()
            .filter(|(_, v)| v.is_finite() && **v > 0.0)
            .map(|(k, &v)| {
                let steps = 8;
                let mut pts = vec![(0.0, 0.0)];
                for s in 0..=steps {
                    let a = width * (k as f64 + s as f64 / steps as f64);
                    pts.push((v * a.cos(), v * a.sin()));
                }
                Polygon::new(pts, RGBColor(0, 114, 178).mix(0.8).filled())
            }),
    )?;
    let circle = |r: f64| {
        (0..=180).map(move |s| {
            (
                r * (TAU * s as f64 / 180.0).cos(),
                r * (TAU * s as f64 / 180.0).sin(),
            )
        })
    };
    chart.draw_series(DashedLineSeries::new(
        circle(iso),
        6,
        4,
        BLACK.stroke_width(2),
    ))?;
    for k in 0..6 {
        let a = k as f64 * TAU / 12.0;
        chart.draw_series(LineSeries::new(
            [
                (-peak * a.cos(), -peak * a.sin()),
                (peak * a.cos(), peak * a.sin()),
            ],
            RGBColor(180, 180, 180),
        ))?;
    }
    // The angle of each spoke, in the ring left free beyond the longest bar.
    let label = TextStyle::from((grains_core::plot::FONT, 20).into_font())
        .pos(Pos::new(HPos::Center, VPos::Center));
    chart.draw_series((0..12).map(|k| {
        let a = k as f64 * TAU / 12.0;
        Text::new(
            format!("{}°", 30 * k),
            (0.93 * peak * a.cos(), 0.93 * peak * a.sin()),
            label.clone(),
        )
    }))?;
    chart.draw_series([Text::new(
        format!("dashed: isotropic 1/2π; outer edge {:.3} /rad", peak),
        (-0.98 * peak, -0.95 * peak),
        (grains_core::plot::FONT, 20),
    )])?;
    root.present()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_a_rose() {
        let dir = std::env::temp_dir().join(format!("grains-analysis-rose-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let d: Vec<f64> = (0..72)
            .map(|k| 0.16 + 0.05 * (6.0 * k as f64 * 0.0873).cos())
            .collect();
        let p = dir.join("rose.png");
        rose_png(&p, "rose", &d).unwrap();
        assert!(std::fs::read(&p).unwrap().starts_with(b"\x89PNG"));
        rose_png(&dir.join("empty.png"), "empty", &[]).unwrap();
    }
}
