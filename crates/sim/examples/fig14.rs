//! xue-2019 Fig. 14 a–d from ring runs: for each run, the inner compact band's and the
//! spall layer's mean radial velocity (|v̄_r|_N) and the band's number fraction
//! (N_compt/N) against time, read from its `history.csv` (the run's own band rule,
//! `[analysis]`); the panels side by side in one PNG, every plotted series in a CSV
//! beside it (columns: run, time in µs, band and spall velocity in m/s, band fraction).
//!
//! `cargo run --release -p grains-sim --example fig14 -- OUT.png LABEL=RUN_DIR ...`
//!
//! VALIDATION.md, "Jetting mode", draws tests 1, 3, 5 and 6 this way.

use grains_core::history::read_csv;
use grains_core::plot::{write_grid_png, LinePlot, Series};
use std::fmt::Write as _;
use std::path::PathBuf;

/// One run's curves.
struct Curves {
    label: String,
    /// How the run told its band apart, as its plots' titles say it.
    rule: String,
    t_us: Vec<f64>,
    band: Vec<f64>,
    spall: Vec<f64>,
    fraction: Vec<f64>,
}

/// The band rule of the run whose scenario is `path` (its `[analysis]`, or the defaults).
fn rule_of(path: &std::path::Path) -> anyhow::Result<String> {
    let text =
        std::fs::read_to_string(path).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    let scn: grains_sim::blast::scenario::Scenario =
        toml::from_str(&text).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    let a = scn.analysis;
    Ok(grains_sim::blast::plots::band_rule(
        a.band_fraction,
        a.radial_bin,
    ))
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some((out, runs)) = args.split_first() else {
        anyhow::bail!("usage: fig14 OUT.png LABEL=RUN_DIR [LABEL=RUN_DIR ...]");
    };
    let mut all = Vec::new();
    for r in runs {
        let (label, dir) = r
            .split_once('=')
            .ok_or_else(|| anyhow::anyhow!("{r}: expected LABEL=RUN_DIR"))?;
        let path = PathBuf::from(dir).join("history.csv");
        let (names, rows) =
            read_csv(&path).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
        let col = |k: &str| -> anyhow::Result<Vec<f64>> {
            let j = names
                .iter()
                .position(|n| n == k)
                .ok_or_else(|| anyhow::anyhow!("{}: no column {k}", path.display()))?;
            Ok(rows.iter().map(|r| r[j]).collect())
        };
        all.push(Curves {
            rule: rule_of(&PathBuf::from(dir).join("scenario.toml"))?,
            label: label.to_string(),
            t_us: col("time")?.iter().map(|t| t * 1e6).collect(),
            band: col("band_velocity")?,
            spall: col("spall_velocity")?,
            fraction: col("band_fraction")?,
        });
    }
    let titles: Vec<(String, String)> = all
        .iter()
        .map(|c| {
            (
                format!("{}: band and spall velocity ({})", c.label, c.rule),
                format!("{}: band fraction ({})", c.label, c.rule),
            )
        })
        .collect();
    // Two runs a row, each run's velocities above its band fraction.
    let mut panels = Vec::new();
    for (pair, names) in all.chunks(2).zip(titles.chunks(2)) {
        for (c, (tv, _)) in pair.iter().zip(names) {
            panels.push(LinePlot {
                title: tv,
                x_label: "time (µs)",
                y_label: "mean radial velocity (m/s)",
                series: vec![
                    Series {
                        name: "compact band",
                        x: &c.t_us,
                        y: &c.band,
                    },
                    Series {
                        name: "spall layer",
                        x: &c.t_us,
                        y: &c.spall,
                    },
                ],
                log_y: false,
                points: false,
            });
        }
        for (c, (_, tf)) in pair.iter().zip(names) {
            panels.push(LinePlot {
                title: tf,
                x_label: "time (µs)",
                y_label: "band fraction N_compt/N",
                series: vec![Series {
                    name: "",
                    x: &c.t_us,
                    y: &c.fraction,
                }],
                log_y: false,
                points: false,
            });
        }
    }
    let png = PathBuf::from(out);
    write_grid_png(&panels, 2.min(all.len()), &png)?;
    let mut csv = String::from("run,time_us,band_velocity_m_s,spall_velocity_m_s,band_fraction\n");
    for c in &all {
        for k in 0..c.t_us.len() {
            writeln!(
                csv,
                "{},{},{},{},{}",
                c.label.replace(',', ";"),
                c.t_us[k],
                c.band[k],
                c.spall[k],
                c.fraction[k]
            )?;
        }
    }
    std::fs::write(png.with_extension("csv"), csv)?;
    println!(
        "{} and {}",
        png.display(),
        png.with_extension("csv").display()
    );
    Ok(())
}
