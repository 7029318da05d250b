//! PNG plots written at the end of a run: energies and momenta against time (the
//! paper's Figs. 2 and 4), body motion, the points at each impact (Fig. 3), the
//! response the material checks probe against its closed form, and for bonded
//! interfaces the points coloured by bond (Fig. 5) and the debonded length.

use glam::DVec2;
use grains_core::history::History;
use grains_core::plot::{time_label, LinePlot, Outline, ParticleMap, Series};
use grains_mpm::{Geometry, Setup};
use std::path::Path;

/// Most bodies that get a motion and a rotation plot each.
pub const MOTION_PLOTS: usize = 24;

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
    .write_png_and_csv(&dir.join(file))?;
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
    let (dissipated, thermal) = (col("dissipated"), col("thermal_work"));
    if dissipated.iter().chain(&thermal).any(|x| *x != 0.0) {
        energies.push(("dissipated", dissipated));
        energies.push(("thermal work", thermal));
        energies.push(("total + dissipated − thermal work", col("balance")));
    }
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
    // One plot per body helps with a few bodies, not with a packing of hundreds.
    let few = setup.bodies.len() <= MOTION_PLOTS;
    for b in setup.bodies.iter().filter(|_| few) {
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

/// One line plot a record asks for.
pub struct Curves {
    /// File name.
    pub file: String,
    /// Caption.
    pub title: String,
    /// X axis label, with unit.
    pub x_label: String,
    /// Y axis label, with unit.
    pub y_label: String,
    /// (legend, x, y).
    pub series: Vec<(String, Vec<f64>, Vec<f64>)>,
    /// Logarithmic y axis.
    pub log_y: bool,
}

/// Writes each of `curves` into `dir`: the plot, and its series as a CSV of the same
/// name (`shear_stress.png` and `shear_stress.csv`), so that they can be re-plotted.
pub fn write_curves(dir: &Path, curves: &[Curves]) -> anyhow::Result<()> {
    for c in curves {
        LinePlot {
            title: &c.title,
            x_label: &c.x_label,
            y_label: &c.y_label,
            series: c
                .series
                .iter()
                .map(|(n, x, y)| Series { name: n, x, y })
                .collect(),
            log_y: c.log_y,
            points: false,
        }
        .write_png_and_csv(&dir.join(&c.file))?;
    }
    Ok(())
}

/// The points coloured by their bond strength, one map per moment (the paper's Fig. 5),
/// with the initial body outlines drawn.
pub fn bond_maps(
    dir: &Path,
    maps: &[(String, String, Snapshot)],
    shapes: &[Geometry],
    point_radius: f64,
) -> anyhow::Result<()> {
    let outlines: Vec<Outline> = shapes.iter().flat_map(outlines).collect();
    for (file, caption, s) in maps {
        let radii = vec![point_radius; s.pos.len()];
        ParticleMap {
            title: &format!(
                "Bond strength at t = {} ({caption}); lines: initial body outlines",
                time_label(s.t)
            ),
            centres: &s.pos,
            radii: &radii,
            values: &s.value,
            value_label: "bond strength (Pa); 0 = debonded",
            outlines: &outlines,
        }
        .write_png(&dir.join(file))?;
    }
    Ok(())
}

/// Point maps: (file, caption, colour-bar label, snapshot) each.
pub fn maps(
    dir: &Path,
    maps: &[(String, String, String, Snapshot)],
    point_radius: f64,
) -> anyhow::Result<()> {
    for (file, caption, label, s) in maps {
        let radii = vec![point_radius; s.pos.len()];
        ParticleMap {
            title: &format!("{caption}, t = {}", time_label(s.t)),
            centres: &s.pos,
            radii: &radii,
            values: &s.value,
            value_label: label,
            outlines: &[],
        }
        .write_png(&dir.join(file))?;
    }
    Ok(())
}

/// A body's initial outline: circles as 128-gons, rectangles, polygons, the parts of a
/// difference.
fn outlines(g: &Geometry) -> Vec<Outline> {
    let circle = |c: [f64; 2], r: f64| Outline {
        points: (0..128)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / 128.0;
                DVec2::from(c) + r * DVec2::new(a.cos(), a.sin())
            })
            .collect(),
        closed: true,
    };
    match g {
        Geometry::Disk { centre, radius } => vec![circle(*centre, *radius)],
        Geometry::Annulus {
            centre,
            inner,
            outer,
        } => vec![circle(*centre, *inner), circle(*centre, *outer)],
        Geometry::Rectangle { lo, hi } => vec![Outline {
            points: vec![
                DVec2::from(*lo),
                DVec2::new(hi[0], lo[1]),
                DVec2::from(*hi),
                DVec2::new(lo[0], hi[1]),
            ],
            closed: true,
        }],
        Geometry::Polygon { vertices } => vec![Outline {
            points: vertices.iter().map(|v| DVec2::from(*v)).collect(),
            closed: true,
        }],
        Geometry::Difference { base, minus } => outlines(base)
            .into_iter()
            .chain(minus.iter().flat_map(outlines))
            .collect(),
        Geometry::Union { parts } => parts.iter().flat_map(outlines).collect(),
    }
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
