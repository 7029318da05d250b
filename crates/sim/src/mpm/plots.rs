//! PNG plots written at the end of a run: energies and momenta against time (the
//! paper's Figs. 2 and 4), body motion, and the points at each impact (Fig. 3).

use glam::DVec2;
use grains_core::history::History;
use grains_core::plot::{time_label, LinePlot, Outline, ParticleMap, Series};
use grains_mpm::Setup;
use std::path::Path;

/// The points at one moment, coloured by a value.
#[derive(Clone, Debug, Default)]
pub struct Snapshot {
    /// Time.
    pub t: f64,
    /// Positions.
    pub pos: Vec<DVec2>,
    /// Principal stress difference.
    pub value: Vec<f64>,
    /// Strain energy when taken (the snapshot of an impact keeps its maximum).
    pub strain: f64,
}

fn line(
    dir: &Path,
    file: &str,
    title: &str,
    y_label: &str,
    t: &[f64],
    series: &[(&str, Vec<f64>)],
) -> anyhow::Result<()> {
    LinePlot {
        title,
        x_label: "time (s)",
        y_label,
        series: series
            .iter()
            .map(|(n, y)| Series { name: n, x: t, y })
            .collect(),
        log_y: false,
        points: false,
    }
    .write_png(&dir.join(file))?;
    Ok(())
}

/// Writes every plot into `dir`.
pub fn write_all(
    dir: &Path,
    h: &History,
    setup: &Setup,
    snapshots: &[(String, Snapshot)],
    point_radius: f64,
) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir)?;
    let col = |name: &str| h.column(name).unwrap_or_default();
    let t = col("time");
    let mut energies = vec![("kinetic", col("kinetic")), ("strain", col("strain"))];
    if setup.gravity != DVec2::ZERO {
        energies.push(("potential", col("potential")));
    }
    energies.push(("total", col("total")));
    line(
        dir,
        "energies.png",
        "Energies (per unit thickness)",
        "energy (J/m)",
        &t,
        &energies,
    )?;
    let (px, py) = (col("momentum_x"), col("momentum_y"));
    let mag: Vec<f64> = px.iter().zip(&py).map(|(a, b)| a.hypot(*b)).collect();
    line(
        dir,
        "momenta.png",
        "Total momentum (per unit thickness)",
        "momentum per unit thickness (kg/s)",
        &t,
        &[("x", px.clone()), ("y", py.clone()), ("|p|", mag)],
    )?;
    for b in &setup.bodies {
        let n = &b.name;
        line(
            dir,
            &format!("{n}_motion.png"),
            &format!("Body \"{n}\": velocity and spin"),
            "m/s, rad/s",
            &t,
            &[
                ("vx", col(&format!("{n}_vx"))),
                ("vy", col(&format!("{n}_vy"))),
                ("omega", col(&format!("{n}_omega"))),
            ],
        )?;
        let deg: Vec<f64> = col(&format!("{n}_rotation"))
            .iter()
            .map(|a| a.to_degrees())
            .collect();
        line(
            dir,
            &format!("{n}_rotation.png"),
            &format!("Body \"{n}\": accumulated rotation"),
            "degrees",
            &t,
            &[("rotation", deg)],
        )?;
    }
    let walls = walls(setup);
    for (file, s) in snapshots {
        let radii = vec![point_radius; s.pos.len()];
        ParticleMap {
            title: &format!(
                "Material points at t = {}, coloured by principal stress difference",
                time_label(s.t)
            ),
            centres: &s.pos,
            radii: &radii,
            values: &s.value,
            value_label: "principal stress difference σ1 − σ2 (Pa)",
            outlines: &walls,
        }
        .write_png(&dir.join(file))?;
    }
    Ok(())
}

/// The grid edges that are walls, as lines.
fn walls(setup: &Setup) -> Vec<Outline> {
    let (lo, hi) = (setup.grid.lo, setup.grid.hi());
    let corners = [
        [DVec2::new(lo.x, lo.y), DVec2::new(lo.x, hi.y)],
        [DVec2::new(hi.x, lo.y), DVec2::new(hi.x, hi.y)],
        [DVec2::new(lo.x, lo.y), DVec2::new(hi.x, lo.y)],
        [DVec2::new(lo.x, hi.y), DVec2::new(hi.x, hi.y)],
    ];
    setup
        .walls
        .iter()
        .zip(corners)
        .filter(|(w, _)| w.is_some())
        .map(|(_, c)| Outline {
            points: c.to_vec(),
            closed: false,
        })
        .collect()
}
