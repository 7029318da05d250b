//! The rotating drum's dynamic angle of repose against sliding friction μ (at the
//! example's μ_r) and against rolling friction μ_r (at its μ), side by side, from the
//! CSV `bench/drum_sweep.py` writes (columns mu, mu_r, angle_deg, torque_ratio); the
//! PNG is written beside the CSV.
//!
//! `cargo run -p grains-sim --example drum_repose -- docs/figures/drum_repose.csv`

use grains_core::plot::{write_grid_png, LinePlot, Series};
use std::path::PathBuf;

/// μ and μ_r of `examples/dem3d/drum_small.toml`, which each half of the sweep holds.
const MU: f64 = 0.5;
const MU_R: f64 = 0.05;

fn main() -> anyhow::Result<()> {
    let csv = PathBuf::from(
        std::env::args()
            .nth(1)
            .ok_or_else(|| anyhow::anyhow!("usage: drum_repose SWEEP.csv"))?,
    );
    let text = std::fs::read_to_string(&csv)?;
    let rows: Vec<[f64; 3]> = text
        .lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let v: Vec<f64> = l.split(',').filter_map(|x| x.trim().parse().ok()).collect();
            anyhow::ensure!(v.len() >= 3, "{}: bad row {l}", csv.display());
            Ok([v[0], v[1], v[2]])
        })
        .collect::<anyhow::Result<_>>()?;
    // One half of the sweep: the rows where `fixed` holds its value, sorted by the other.
    let half = |fixed: usize, value: f64| -> (Vec<f64>, Vec<f64>) {
        let mut r: Vec<&[f64; 3]> = rows
            .iter()
            .filter(|r| (r[fixed] - value).abs() < 1e-12)
            .collect();
        r.sort_by(|a, b| a[1 - fixed].total_cmp(&b[1 - fixed]));
        (
            r.iter().map(|r| r[1 - fixed]).collect(),
            r.iter().map(|r| r[2]).collect(),
        )
    };
    let (mu, by_mu) = half(1, MU_R);
    let (mu_r, by_mu_r) = half(0, MU);
    let t1 = format!("Dynamic angle of repose against μ (μ_r = {MU_R})");
    let t2 = format!("Dynamic angle of repose against μ_r (μ = {MU})");
    let panels = [
        LinePlot {
            title: &t1,
            x_label: "sliding friction μ",
            y_label: "angle of repose (degrees)",
            series: vec![Series {
                name: "",
                x: &mu,
                y: &by_mu,
            }],
            log_y: false,
            points: true,
        },
        LinePlot {
            title: &t2,
            x_label: "rolling friction μ_r",
            y_label: "angle of repose (degrees)",
            series: vec![Series {
                name: "",
                x: &mu_r,
                y: &by_mu_r,
            }],
            log_y: false,
            points: true,
        },
    ];
    let png = csv.with_extension("png");
    write_grid_png(&panels, 2, &png)?;
    println!("{}", png.display());
    Ok(())
}
