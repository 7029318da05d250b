//! Silo discharge against Beverloo's law: the mass flow rate W measured against the
//! orifice's diameter D for each sweep `bench/silo_sweep.py` wrote (its CSV: columns
//! D_over_d, orifice_m, rate_kg_s, c_at_k1.5, packing_measured, c_at_k1.5_measured, and
//! a last comment line with the fit, the mean diameter d and the bulk density ρ_b the
//! fit used), each run a cross, beside W = C ρ_b √g (D − k d)^{5/2} at each sweep's
//! fitted (C, k) and at the literature's C = 0.58, k = 1.5. The PNG is written
//! beside the first CSV, its name ending `_plot.png`. Each argument is a CSV, optionally
//! followed by `=` and the sweep's name in the legend (default: the file's stem).
//!
//! `cargo run -p grains-sim --example silo_beverloo --
//! "docs/figures/silo_beverloo_full.csv=40 mm silo (silo.toml)" "docs/figures/silo_beverloo.csv=25 mm silo (silo_small widened)"`

use grains_core::plot::{LinePlot, Series};
use std::path::{Path, PathBuf};

/// Beverloo's constants as the issue quotes the literature.
const C_LIT: f64 = 0.58;
const K_LIT: f64 = 1.5;
const G: f64 = 9.81;

/// One sweep: (D m, W kg/s) rows, the fit (C, k), d (m) and ρ_b (kg/m³).
struct Sweep {
    rows: Vec<(f64, f64)>,
    fit: (f64, f64),
    d: f64,
    rho_b: f64,
}

/// The number after `key` in `line` (`key` ends with `=` or `= `).
fn after(line: &str, key: &str) -> Option<f64> {
    let rest = &line[line.find(key)? + key.len()..];
    let end = rest
        .find(|c: char| !(c.is_ascii_digit() || ".-+e".contains(c)))
        .unwrap_or(rest.len());
    rest[..end].parse().ok()
}

fn read(csv: &Path) -> anyhow::Result<Sweep> {
    let text = std::fs::read_to_string(csv)?;
    let mut rows = Vec::new();
    let mut fit = None;
    for l in text.lines().skip(1).filter(|l| !l.trim().is_empty()) {
        if l.starts_with('#') {
            let f =
                |k| after(l, k).ok_or_else(|| anyhow::anyhow!("{}: no {k} in {l}", csv.display()));
            fit = Some((f("C = ")?, f("k = ")?, f("d = ")?, f("rho_b = ")?));
            continue;
        }
        let v: Vec<f64> = l.split(',').filter_map(|x| x.trim().parse().ok()).collect();
        anyhow::ensure!(v.len() >= 3, "{}: bad row {l}", csv.display());
        rows.push((v[1], v[2]));
    }
    let (c, k, d, rho_b) = fit.ok_or_else(|| anyhow::anyhow!("{}: no fit line", csv.display()))?;
    rows.sort_by(|a, b| a.0.total_cmp(&b.0));
    Ok(Sweep {
        rows,
        fit: (c, k),
        d,
        rho_b,
    })
}

/// Beverloo's W (g/s) at the orifice diameters `ds` (m).
fn beverloo(ds: &[f64], (c, k): (f64, f64), d: f64, rho_b: f64) -> Vec<f64> {
    ds.iter()
        .map(|&dd| 1e3 * c * rho_b * G.sqrt() * (dd - k * d).max(0.0).powf(2.5))
        .collect()
}

fn main() -> anyhow::Result<()> {
    let args: Vec<(PathBuf, Option<String>)> = std::env::args()
        .skip(1)
        .map(|a| match a.split_once('=') {
            Some((p, name)) => (PathBuf::from(p), Some(name.to_string())),
            None => (PathBuf::from(a), None),
        })
        .collect();
    anyhow::ensure!(
        !args.is_empty(),
        "usage: silo_beverloo SWEEP.csv[=NAME] [SWEEP.csv[=NAME] ...]"
    );
    let csvs: Vec<PathBuf> = args.iter().map(|a| a.0.clone()).collect();
    let sweeps: Vec<Sweep> = csvs
        .iter()
        .map(|c| read(c))
        .collect::<anyhow::Result<_>>()?;
    let (lo, hi) = sweeps
        .iter()
        .flat_map(|s| s.rows.iter().map(|r| r.0))
        .fold((f64::INFINITY, 0.0f64), |(a, b), x| (a.min(x), b.max(x)));
    let curve_d: Vec<f64> = (0..=60).map(|i| lo + (hi - lo) * i as f64 / 60.0).collect();
    let mm = |v: &[f64]| v.iter().map(|x| 1e3 * x).collect::<Vec<f64>>();
    let curve_mm = mm(&curve_d);
    let mut data = Vec::new();
    for (s, (csv, name)) in sweeps.iter().zip(&args) {
        let stem = name
            .as_deref()
            .or_else(|| csv.file_stem().and_then(|s| s.to_str()))
            .unwrap_or("sweep");
        // Each run a cross (two strokes broken by NaN: a series' points are joined).
        let (dx, dy) = (0.01 * 1e3 * (hi - lo), 2.5);
        let d: Vec<f64> = s
            .rows
            .iter()
            .flat_map(|r| {
                [
                    1e3 * r.0 - dx,
                    1e3 * r.0 + dx,
                    f64::NAN,
                    1e3 * r.0,
                    1e3 * r.0,
                    f64::NAN,
                ]
            })
            .collect();
        let w: Vec<f64> = s
            .rows
            .iter()
            .flat_map(|r| {
                [
                    1e3 * r.1,
                    1e3 * r.1,
                    f64::NAN,
                    1e3 * r.1 - dy,
                    1e3 * r.1 + dy,
                    f64::NAN,
                ]
            })
            .collect();
        data.push((
            format!("measured, {stem}"),
            d,
            w,
            format!(
                "Beverloo fitted to {stem}: C = {:.2}, k = {:.2}",
                s.fit.0, s.fit.1
            ),
            beverloo(&curve_d, s.fit, s.d, s.rho_b),
        ));
    }
    let first = &sweeps[0];
    let lit = beverloo(&curve_d, (C_LIT, K_LIT), first.d, first.rho_b);
    let lit_name = format!(
        "Beverloo, C = {C_LIT}, k = {K_LIT} (literature), ρ_b = {:.0} kg/m³ as the first sweep's",
        first.rho_b
    );
    let mut series = Vec::new();
    for (name, d, w, fit_name, fit) in &data {
        series.push(Series { name, x: d, y: w });
        series.push(Series {
            name: fit_name,
            x: &curve_mm,
            y: fit,
        });
    }
    series.push(Series {
        name: &lit_name,
        x: &curve_mm,
        y: &lit,
    });
    let plot = LinePlot {
        title: "Silo discharge: mass flow rate against orifice diameter",
        x_label: "orifice diameter D (mm)",
        y_label: "mass flow rate W (g/s)",
        series,
        log_y: false,
        points: false,
    };
    let png = csvs[0].with_file_name(format!(
        "{}_plot.png",
        csvs[0]
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("silo")
    ));
    plot.write_png(&png)?;
    println!("{}", png.display());
    Ok(())
}
