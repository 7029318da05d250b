//! `grains analyze FILE`: microstructure of a packing file or a DEM frame, and the
//! figures, plots and frame that `grains pack` writes for every packing it makes.

use grains_analysis::sample::{Sample, SampleKind};
use grains_analysis::{sizes, Analysis};
use grains_core::plot::{LinePlot, ParticleMap, Series};
use grains_core::vtk::{DataArray, PolyData};
use serde_json::{json, Map, Value};
use std::path::Path;
use std::time::Instant;

/// Analyses `file` (a packing file or a DEM frame) into `out`: the frame, plots and
/// `analysis.json`; returns the figures.
pub fn analyze(file: &Path, out: &Path) -> Result<Map<String, Value>, String> {
    let started = Instant::now();
    let sample = grains_analysis::sample::load(file).map_err(|e| e.to_string())?;
    let stem = file
        .file_stem()
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or_else(|| "sample".into());
    let analysis = grains_analysis::analyze(&sample);
    let mut figures = figures(&sample, &analysis);
    write_outputs(out, &sample, &analysis, &stem).map_err(|e| format!("{e:#}"))?;
    figures.insert("wall_time_s".into(), json!(started.elapsed().as_secs_f64()));
    figures.insert("source".into(), json!(file.display().to_string()));
    grains_core::json::write_json_pretty(
        &out.join("analysis.json"),
        &Value::Object(figures.clone()),
    )
    .map_err(|e| e.to_string())?;
    Ok(figures)
}

/// The figures of an analysis, under the names summary.json uses.
pub fn figures(s: &Sample, a: &Analysis) -> Map<String, Value> {
    let mut m = Map::new();
    let num = |v: f64| if v.is_finite() { json!(v) } else { Value::Null };
    m.insert("particles".into(), json!(s.pos.len()));
    m.insert("lining_particles".into(), json!(s.lining));
    m.insert("interior_particles".into(), json!(a.order_interior.count));
    m.insert("mean_diameter".into(), num(a.sizes.mean));
    m.insert("polydispersity".into(), num(a.sizes.polydispersity));
    m.insert("min_diameter".into(), num(a.sizes.min));
    m.insert("max_diameter".into(), num(a.sizes.max));
    m.insert("packing_fraction_bulk".into(), num(a.packing_fraction_bulk));
    m.insert(
        "packing_fraction_total".into(),
        num(a.packing_fraction_total),
    );
    m.insert("psi6_local_mean_all".into(), num(a.order_all.local));
    m.insert(
        "psi6_local_mean_interior".into(),
        num(a.order_interior.local),
    );
    m.insert("psi6_global_all".into(), num(a.order_all.global));
    m.insert("psi6_global_interior".into(), num(a.order_interior.global));
    m.insert("contacts".into(), json!(a.contacts.pairs.len()));
    m.insert("contact_gap".into(), num(a.contact_gap));
    m.insert("mean_coordination".into(), num(a.mean_coordination));
    m.insert("rattler_fraction".into(), num(a.rattler_fraction));
    m.insert("fabric_anisotropy".into(), num(a.fabric.anisotropy()));
    m.insert(
        "fabric_major_angle_deg".into(),
        num(a.fabric.major_angle.to_degrees()),
    );
    m.insert("region".into(), json!(a.region.describe()));
    m.insert("region_from_file".into(), json!(a.region_from_file));
    m.insert(
        "sample_kind".into(),
        json!(match s.kind {
            SampleKind::Packing => "packing",
            SampleKind::DemFrame => "dem_frame",
        }),
    );
    m
}

/// The figures that say most about a packing, in print order (also the top-level keys
/// of `grains pack`'s summary.json).
pub const MAIN_FIGURES: [&str; 9] = [
    "particles",
    "mean_diameter",
    "polydispersity",
    "packing_fraction_bulk",
    "psi6_local_mean_all",
    "psi6_local_mean_interior",
    "psi6_global_interior",
    "mean_coordination",
    "fabric_anisotropy",
];

/// The main figures, one `key: value` line each.
pub fn main_figures(f: &Map<String, Value>) -> String {
    let mut s = String::new();
    for k in MAIN_FIGURES {
        if let Some(v) = f.get(k) {
            s.push_str(&format!("{k}: {v}\n"));
        }
    }
    s
}

/// Writes `frames/<stem>.vtp` and the plots into `out`.
pub fn write_outputs(out: &Path, s: &Sample, a: &Analysis, stem: &str) -> anyhow::Result<()> {
    use anyhow::Context;
    let plots = out.join("plots");
    let frames = out.join("frames");
    std::fs::create_dir_all(&plots)
        .with_context(|| format!("cannot create {}", plots.display()))?;
    std::fs::create_dir_all(&frames)
        .with_context(|| format!("cannot create {}", frames.display()))?;
    let psi_abs: Vec<f64> = a.psi6.iter().map(|v| v.length()).collect();
    let mut poly = PolyData::from_points_2d(&s.pos);
    poly.point_data = vec![
        DataArray::scalar_f64("radius", s.radius.clone()),
        DataArray::scalar_f64("psi6", psi_abs.clone()),
        DataArray::scalar_f64(
            "psi6_phase",
            a.psi6.iter().map(|v| v.y.atan2(v.x)).collect(),
        ),
        DataArray::scalar_i32(
            "contacts",
            a.contacts.count.iter().map(|&c| c as i32).collect(),
        ),
        DataArray::scalar_u8("interior", a.interior.iter().map(|&b| b as u8).collect()),
        DataArray::scalar_u8(
            "lining",
            (0..s.pos.len()).map(|k| (k < s.lining) as u8).collect(),
        ),
    ];
    poly.write(&frames.join(format!("{stem}.vtp")))?;

    ParticleMap {
        title: "Local bond-orientational order |ψ6| per particle (6 nearest neighbours)",
        centres: &s.pos,
        radii: &s.radius,
        values: &psi_abs,
        value_label: "|ψ6| (dimensionless)",
        outlines: &a.region.outlines(),
    }
    .write_png(&plots.join("psi6_map.png"))?;
    let interior: Vec<f64> = psi_abs
        .iter()
        .zip(&a.interior)
        .filter(|(_, i)| **i)
        .map(|(v, _)| *v)
        .collect();
    let (xa, pa) = sizes::cdf(&psi_abs, 400);
    let (xi, pi) = sizes::cdf(&interior, 400);
    LinePlot {
        title: "Cumulative distribution of local |psi6|",
        x_label: "|psi6|",
        y_label: "P(|psi6| <= x)",
        series: vec![
            Series {
                name: "all",
                x: &xa,
                y: &pa,
            },
            Series {
                name: "interior",
                x: &xi,
                y: &pi,
            },
        ],
        log_y: false,
        points: false,
    }
    .write_png_and_csv(&plots.join("psi6_cdf.png"))?;

    let diam: Vec<f64> = s.radius[s.lining.min(s.radius.len())..]
        .iter()
        .map(|r| 2.0 * r)
        .collect();
    let title = format!(
        "d0 = {:.4e} m, delta = {:.4}",
        a.sizes.mean, a.sizes.polydispersity
    );
    let (xc, pc) = sizes::pdf(&diam, 40);
    LinePlot {
        title: &format!("Diameter PDF ({title})"),
        x_label: "diameter (m)",
        y_label: "P(d) (1/m)",
        series: vec![Series {
            name: "",
            x: &xc,
            y: &pc,
        }],
        log_y: false,
        points: false,
    }
    .write_png_and_csv(&plots.join("size_pdf.png"))?;
    let (xd, pd) = sizes::cdf(&diam, 400);
    LinePlot {
        title: &format!("Diameter CDF ({title})"),
        x_label: "diameter (m)",
        y_label: "P(diameter <= d)",
        series: vec![Series {
            name: "",
            x: &xd,
            y: &pd,
        }],
        log_y: false,
        points: false,
    }
    .write_png_and_csv(&plots.join("size_cdf.png"))?;
    grains_analysis::rose::rose_png(
        &plots.join("rose.png"),
        &format!(
            "Contact normals, a = F_I - F_II = {:.4}",
            a.fabric.anisotropy()
        ),
        &a.rose,
    )?;
    Ok(())
}
