//! The rotating drum's dynamic angle of repose against sliding friction μ (at the
//! examples' μ_r) and against rolling friction μ_r (at their μ), side by side, one
//! series per sweep, from the CSVs `bench/drum_sweep.py` writes (columns mu, mu_r,
//! angle_deg, torque_ratio). Each argument is a CSV, optionally followed by `=` and the
//! sweep's name in the legend (default: the file's stem); the PNG is written beside
//! the first CSV.
//!
//! `cargo run -p grains-sim --example drum_repose -- "docs/figures/drum_repose.csv=small drum (drum_small, D/d 15)" "docs/figures/drum_repose_full.csv=drum (drum.toml, D/d 30)"`

use grains_core::plot::{write_grid_png, LinePlot, Series};
use std::path::{Path, PathBuf};

/// μ and μ_r of `examples/dem3d/drum_small.toml` and `drum.toml`, which each half of
/// a sweep holds.
const MU: f64 = 0.5;
const MU_R: f64 = 0.05;

/// A sweep's rows: μ, μ_r, angle (degrees).
fn read(csv: &Path) -> anyhow::Result<Vec<[f64; 3]>> {
    let text = std::fs::read_to_string(csv)?;
    text.lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let v: Vec<f64> = l.split(',').filter_map(|x| x.trim().parse().ok()).collect();
            anyhow::ensure!(v.len() >= 3, "{}: bad row {l}", csv.display());
            Ok([v[0], v[1], v[2]])
        })
        .collect()
}

/// One half of a sweep: the rows where column `fixed` holds `value`, sorted by the
/// other column, as (that column, angle).
fn half(rows: &[[f64; 3]], fixed: usize, value: f64) -> (Vec<f64>, Vec<f64>) {
    let mut r: Vec<&[f64; 3]> = rows
        .iter()
        .filter(|r| (r[fixed] - value).abs() < 1e-12)
        .collect();
    r.sort_by(|a, b| a[1 - fixed].total_cmp(&b[1 - fixed]));
    (
        r.iter().map(|r| r[1 - fixed]).collect(),
        r.iter().map(|r| r[2]).collect(),
    )
}

/// One series per sweep (`names`: their legend entries, empty for a single sweep).
fn series<'a>(halves: &'a [(Vec<f64>, Vec<f64>)], names: &[&'a str]) -> Vec<Series<'a>> {
    halves
        .iter()
        .zip(names)
        .map(|((x, y), name)| Series { name, x, y })
        .collect()
}

fn main() -> anyhow::Result<()> {
    let args: Vec<(PathBuf, String)> = std::env::args()
        .skip(1)
        .map(|a| match a.split_once('=') {
            Some((p, name)) => (PathBuf::from(p), name.to_string()),
            None => {
                let p = PathBuf::from(&a);
                let stem = p.file_stem().map(|s| s.to_string_lossy().into_owned());
                (p, stem.unwrap_or(a))
            }
        })
        .collect();
    anyhow::ensure!(
        !args.is_empty(),
        "usage: drum_repose SWEEP.csv[=NAME] [SWEEP.csv[=NAME] ...]"
    );
    let sweeps: Vec<Vec<[f64; 3]>> = args
        .iter()
        .map(|(p, _)| read(p))
        .collect::<anyhow::Result<_>>()?;
    let by_mu: Vec<_> = sweeps.iter().map(|r| half(r, 1, MU_R)).collect();
    let by_mu_r: Vec<_> = sweeps.iter().map(|r| half(r, 0, MU)).collect();
    let names: Vec<&str> = match args.len() {
        1 => vec![""],
        _ => args.iter().map(|(_, n)| n.as_str()).collect(),
    };
    let t1 = format!("Dynamic angle of repose against μ (μ_r = {MU_R})");
    let t2 = format!("Dynamic angle of repose against μ_r (μ = {MU})");
    let panels = [
        LinePlot {
            title: &t1,
            x_label: "sliding friction μ",
            y_label: "angle of repose (degrees)",
            series: series(&by_mu, &names),
            log_y: false,
            points: true,
        },
        LinePlot {
            title: &t2,
            x_label: "rolling friction μ_r",
            y_label: "angle of repose (degrees)",
            series: series(&by_mu_r, &names),
            log_y: false,
            points: true,
        },
    ];
    let png = args[0].0.with_extension("png");
    write_grid_png(&panels, 2, &png)?;
    println!("{}", png.display());
    Ok(())
}
