//! Column collapse: the run-out (R∞ − R0)/R0 against the aspect ratio a = H0/R0 from the
//! CSV `bench/collapse_sweep.py` writes (columns count, aspect_ratio, h0_m, r0_m,
//! r_inf_m, edge_m, front_m, runout, runout_edge, lube, r0_over_d), beside Lube et al.'s
//! two laws (1.24 a below a = 1.7, 1.6 a^{1/2} above) and their ±15 % scatter: R∞ as the
//! radius holding 99 % of the grains (the check's, upright crosses, one series per
//! column width in grains) and, as a figure only, as the edge of the continuous deposit
//! at half coverage (diagonal crosses; a run whose edge was not measured has none); the
//! PNG is written beside the CSV. A second figure, `…_size.png` (its points and fits
//! also in `…_size.csv`), sets both measures over Lube's law against d/R0 for the
//! columns of a ≥ 2.5, with their least-squares lines carried to d/R0 = 0, the limit of
//! Lube's wide columns; it is left out where fewer than two column widths have an edge.
//!
//! `cargo run -p grains-sim --example collapse_runout -- docs/figures/collapse_runout.csv`

use grains_core::plot::{LinePlot, Series};
use grains_sim::dem3d::collapse::lube;
use std::path::PathBuf;

fn main() -> anyhow::Result<()> {
    let csv = PathBuf::from(
        std::env::args()
            .nth(1)
            .ok_or_else(|| anyhow::anyhow!("usage: collapse_runout SWEEP.csv"))?,
    );
    let (names, table) = grains_core::history::read_csv(&csv)?;
    let col = |name: &str| {
        names
            .iter()
            .position(|n| n == name)
            .ok_or_else(|| anyhow::anyhow!("{}: no column {name}", csv.display()))
    };
    let (ka, kr, kw) = (col("aspect_ratio")?, col("runout")?, col("r0_over_d")?);
    let ke = col("runout_edge")?;
    // (a, run-out, R0/d, run-out to the deposit's edge) of each run.
    let rows: Vec<[f64; 4]> = table.iter().map(|r| [r[ka], r[kr], r[kw], r[ke]]).collect();
    let top = rows.iter().map(|r| r[0]).fold(3.0, f64::max) * 1.1;
    let a: Vec<f64> = (0..=240).map(|k| top * k as f64 / 240.0).collect();
    let law: Vec<f64> = a.iter().map(|&a| lube(a)).collect();
    let above: Vec<f64> = law.iter().map(|l| 1.15 * l).collect();
    let below: Vec<f64> = law.iter().map(|l| 0.85 * l).collect();
    // The runs, one series per column width in grains, each run a cross (two strokes
    // broken by NaN: the plot joins points within a series, and markers would draw
    // Lube's curves as dots).
    let (dx, dy) = (0.025 * top, 0.06);
    let cross = |r: &[f64; 4]| -> ([f64; 6], [f64; 6]) {
        let (a, y) = (r[0], r[1]);
        (
            [a - dx, a + dx, f64::NAN, a, a, f64::NAN],
            [y, y, f64::NAN, y - dy, y + dy, f64::NAN],
        )
    };
    // The edge's run-outs as diagonal crosses, so the two measures stay apart where
    // they are close.
    let diagonal = |r: &[f64; 4]| -> ([f64; 6], [f64; 6]) {
        let (a, y) = (r[0], r[3]);
        let (dx, dy) = (0.7 * dx, 0.7 * dy);
        (
            [a - dx, a + dx, f64::NAN, a - dx, a + dx, f64::NAN],
            [y - dy, y + dy, f64::NAN, y + dy, y - dy, f64::NAN],
        )
    };
    let edges: (Vec<f64>, Vec<f64>) = (
        rows.iter().flat_map(|r| diagonal(r).0).collect(),
        rows.iter().flat_map(|r| diagonal(r).1).collect(),
    );
    let mut widths: Vec<f64> = rows.iter().map(|r| r[2]).collect();
    widths.sort_by(f64::total_cmp);
    widths.dedup();
    let runs: Vec<(String, Vec<f64>, Vec<f64>)> = widths
        .iter()
        .map(|&w| {
            let r: Vec<&[f64; 4]> = rows.iter().filter(|r| r[2] == w).collect();
            (
                format!("grains, 99 % radius (the check's R∞), R0/d = {w} (one run each)"),
                r.iter().flat_map(|r| cross(r).0).collect(),
                r.iter().flat_map(|r| cross(r).1).collect(),
            )
        })
        .collect();
    // The runs drawn in the palette's colours after the law's, the band after them.
    let mut series = vec![Series {
        name: "Lube et al. 2004: 1.24 a (a < 1.7), 1.6 a^1/2",
        x: &a,
        y: &law,
    }];
    series.extend(runs.iter().map(|(name, x, y)| Series { name, x, y }));
    series.push(Series {
        name: "grains, deposit edge at half coverage (a figure, not the check; all R0/d)",
        x: &edges.0,
        y: &edges.1,
    });
    series.push(Series {
        name: "Lube et al. + 15 %",
        x: &a,
        y: &above,
    });
    series.push(Series {
        name: "Lube et al. − 15 %",
        x: &a,
        y: &below,
    });
    let png = csv.with_extension("png");
    LinePlot {
        title: "Column collapse: run-out against aspect ratio",
        x_label: "aspect ratio a = H0/R0",
        y_label: "run-out (R∞ − R0)/R0",
        series,
        log_y: false,
        points: false,
    }
    .write_png(&png)?;
    println!("{}", png.display());
    let size = csv.with_file_name(format!(
        "{}_size.png",
        csv.file_stem()
            .map_or("collapse".into(), |s| s.to_string_lossy())
    ));
    match by_size(&rows, &size)? {
        true => println!("{}", size.display()),
        false => println!(
            "(no {}: fewer than two column widths of a ≥ 2.5 with an edge)",
            size.display()
        ),
    }
    Ok(())
}

/// The least-squares line y = c0 + c1 x through the points.
fn fit(x: &[f64], y: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    let c1 = sxy / sxx;
    (my - c1 * mx, c1)
}

/// The standard error of the intercept of [`fit`]'s line through the points (NaN with
/// two points or fewer: no residual freedom).
fn intercept_error(x: &[f64], y: &[f64], (c0, c1): (f64, f64)) -> f64 {
    let n = x.len() as f64;
    let mx = x.iter().sum::<f64>() / n;
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    let ssr: f64 = x
        .iter()
        .zip(y)
        .map(|(a, b)| (b - c0 - c1 * a).powi(2))
        .sum();
    (ssr / (n - 2.0) * (1.0 / n + mx * mx / sxx)).sqrt()
}

/// Both measures over Lube's law against d/R0 for the tall columns (a ≥ 2.5) of
/// `rows` ([a, run-out, R0/d, edge run-out]), each with its fitted line from d/R0 = 0;
/// false (nothing written) where fewer than two column widths have an edge.
fn by_size(rows: &[[f64; 4]], png: &std::path::Path) -> anyhow::Result<bool> {
    let tall: Vec<&[f64; 4]> = rows
        .iter()
        .filter(|r| r[0] >= 2.5 && r[3].is_finite())
        .collect();
    let mut widths: Vec<f64> = tall.iter().map(|r| r[2]).collect();
    widths.sort_by(f64::total_cmp);
    widths.dedup();
    if widths.len() < 2 {
        return Ok(false);
    }
    let x: Vec<f64> = tall.iter().map(|r| 1.0 / r[2]).collect();
    let q99: Vec<f64> = tall.iter().map(|r| r[1] / lube(r[0])).collect();
    let edge: Vec<f64> = tall.iter().map(|r| r[3] / lube(r[0])).collect();
    let right = x.iter().copied().fold(0.0, f64::max) * 1.1;
    // Each measure one series: a cross per column, then (after a NaN, which breaks the
    // line) its fitted line from d/R0 = 0, so that both take the same colour.
    let (dx, dy) = (0.012 * right, 0.012);
    let measure = |y: &[f64]| -> (Vec<f64>, Vec<f64>, f64) {
        let (c0, c1) = fit(&x, y);
        let mut px: Vec<f64> = x
            .iter()
            .flat_map(|&a| [a - dx, a + dx, f64::NAN, a, a, f64::NAN])
            .collect();
        let mut py: Vec<f64> = y
            .iter()
            .flat_map(|&b| [b, b, f64::NAN, b - dy, b + dy, f64::NAN])
            .collect();
        px.extend([0.0, right]);
        py.extend([c0, c0 + c1 * right]);
        (px, py, c0)
    };
    let (q, e) = (measure(&q99), measure(&edge));
    let names = [
        format!(
            "99 % radius (the check's) and its fit: {:.2} at d/R0 = 0",
            q.2
        ),
        format!(
            "deposit edge at half coverage and its fit: {:.2} at d/R0 = 0",
            e.2
        ),
    ];
    let line_x = [0.0, right];
    let ones = [1.0, 1.0];
    let band_x = [0.0, right, f64::NAN, 0.0, right];
    let band_y = [1.15, 1.15, f64::NAN, 0.85, 0.85];
    LinePlot {
        title: "Column collapse, a = 2.5–2.8: run-out over Lube et al.'s against grain size",
        x_label: "d/R0 (grain diameter over column radius)",
        y_label: "run-out over Lube et al.'s 1.6 a^1/2",
        series: vec![
            Series {
                name: "Lube et al. 2004 (experiments: R0/d ≫ 10)",
                x: &line_x,
                y: &ones,
            },
            Series {
                name: &names[0],
                x: &q.0,
                y: &q.1,
            },
            Series {
                name: &names[1],
                x: &e.0,
                y: &e.1,
            },
            Series {
                name: "Lube et al. ± 15 %",
                x: &band_x,
                y: &band_y,
            },
        ],
        log_y: false,
        points: false,
    }
    .write_png(png)?;
    // The data, not the drawing: one row per column, then the fits.
    let mut csv =
        String::from("r0_over_d,d_over_r0,aspect_ratio,runout_over_lube,edge_runout_over_lube\n");
    for (r, ((x, q), e)) in tall.iter().zip(x.iter().zip(&q99).zip(&edge)) {
        csv += &format!("{},{x:.6},{},{q:.6},{e:.6}\n", r[2], r[0]);
    }
    let (q, e) = (fit(&x, &q99), fit(&x, &edge));
    let (sq, se) = (intercept_error(&x, &q99, q), intercept_error(&x, &edge, e));
    csv += &format!(
        "# least squares over {} columns: runout_over_lube = {:.4} + {:.4} d/R0 \
         (intercept's standard error {sq:.4}); edge_runout_over_lube = {:.4} + {:.4} d/R0 \
         (intercept's standard error {se:.4})\n",
        x.len(),
        q.0,
        q.1,
        e.0,
        e.1
    );
    std::fs::write(png.with_extension("csv"), csv)?;
    Ok(true)
}
