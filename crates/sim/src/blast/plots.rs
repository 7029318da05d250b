//! PNG plots of a blast run, drawn from its history: the ring's radii (xue-2019 Fig. 6a),
//! the band and spall velocities and the band's share of particles (Fig. 14), the
//! energies, the burn, and for a bare charge the detonation-arrival profile.

use grains_core::history::History;
use grains_core::plot::{LinePlot, Series};
use grains_fem::diagnostics::ArrivalBin;
use std::path::Path;

/// The band's rule as a title says it: the packing-fraction threshold and the radial
/// bin, since the band fraction read under two rules differs by far more than the runs
/// compared (VALIDATION.md, "Band fraction of test 1").
pub fn band_rule(band_fraction: f64, radial_bin: f64) -> String {
    format!("φ ≥ {band_fraction:.2} on {radial_bin} d0 bins")
}

fn plot(
    dir: &Path,
    file: &str,
    title: &str,
    x: (&str, &[f64]),
    y_label: &str,
    series: &[(&str, Vec<f64>)],
    points: bool,
) -> anyhow::Result<()> {
    LinePlot {
        title,
        x_label: x.0,
        y_label,
        series: series
            .iter()
            .map(|(name, y)| Series { name, x: x.1, y })
            .collect(),
        log_y: false,
        points,
    }
    .write_png_and_csv(&dir.join(file))?;
    Ok(())
}

/// Writes every plot of the run into `dir`. `levels` are velocities drawn as flat
/// lines on the velocity plot (the paper's band velocity, the ring models), by legend;
/// `band_rule` says how the band was told apart (its [`band_rule`]), in the titles.
pub fn write_all(
    dir: &Path,
    h: &History,
    ring: bool,
    arrival: &[ArrivalBin],
    levels: &[(&str, f64)],
    band_rule: &str,
) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir)?;
    let col = |name: &str| h.column(name).unwrap_or_default();
    let t_us: Vec<f64> = col("time").iter().map(|t| t * 1e6).collect();
    let x = ("time (µs)", t_us.as_slice());
    let mut energies = vec![
        ("charge kinetic", col("charge_kinetic")),
        ("charge internal", col("charge_internal")),
        ("chemical (unreleased)", col("charge_chemical")),
    ];
    if ring {
        energies.push(("particles kinetic", col("particle_kinetic")));
    }
    plot(
        dir,
        "energies.png",
        "Energies (per unit thickness)",
        x,
        "energy (J/m)",
        &energies,
        false,
    )?;
    plot(
        dir,
        "burn.png",
        "Burn: mass fraction burnt",
        x,
        "burnt fraction",
        &[("burnt", col("burnt_fraction"))],
        false,
    )?;
    let mm = |name: &str| col(name).iter().map(|v| v * 1e3).collect::<Vec<f64>>();
    if ring {
        plot(
            dir,
            "radii.png",
            "Ring radii (cf. xue-2019 Fig. 6a)",
            x,
            "radius (mm)",
            &[
                ("inner radius", mm("inner_radius")),
                ("outer radius", mm("outer_radius")),
                ("pressure front", mm("pressure_front")),
                ("compact band outer edge", mm("band_outer")),
                ("charge edge", mm("charge_radius")),
            ],
            false,
        )?;
        let n = t_us.len();
        let mut v = vec![
            ("compact band", col("band_velocity")),
            ("spall layer", spall_only(&col)),
        ];
        v.extend(levels.iter().map(|&(name, l)| (name, vec![l; n])));
        plot(
            dir,
            "velocities.png",
            &format!("Mean radial velocity (cf. xue-2019 Fig. 14); band: {band_rule}"),
            x,
            "velocity (m/s)",
            &v,
            false,
        )?;
        plot(
            dir,
            "band_fraction.png",
            &format!("Particles in the compact band, {band_rule} (cf. xue-2019 Fig. 14)"),
            x,
            "N_band / N",
            &[("band fraction", col("band_fraction"))],
            false,
        )?;
    } else {
        plot(
            dir,
            "charge_radius.png",
            "Charge: mean boundary radius",
            x,
            "radius (mm)",
            &[("boundary", mm("charge_radius"))],
            false,
        )?;
    }
    if !arrival.is_empty() {
        let r: Vec<f64> = arrival.iter().map(|b| b.r * 1e3).collect();
        let t: Vec<f64> = arrival.iter().map(|b| b.t * 1e6).collect();
        let e: Vec<f64> = arrival.iter().map(|b| b.expected * 1e6).collect();
        plot(
            dir,
            "arrival.png",
            "Detonation front arrival (p ≥ P_CJ/2) vs r/D_CJ",
            ("radius (mm)", &r),
            "arrival time (µs)",
            &[("measured", t), ("r/D_CJ + t0", e)],
            true,
        )?;
    }
    Ok(())
}

/// The spall layer's velocity from when it can exist: before the pressure front reaches
/// the ring's outer edge, the disks beyond the band are the unshocked ring at rest, not a
/// spall, and drawing their 0 m/s would read as a measurement (left as a gap instead).
fn spall_only(col: &dyn Fn(&str) -> Vec<f64>) -> Vec<f64> {
    let (mut v, front, outer) = (
        col("spall_velocity"),
        col("pressure_front"),
        col("outer_radius"),
    );
    let reached = front.iter().zip(&outer).position(|(f, o)| *f >= 0.98 * *o);
    if let Some(k) = reached {
        let k = k.min(v.len());
        v[..k].fill(f64::NAN);
    }
    v
}
