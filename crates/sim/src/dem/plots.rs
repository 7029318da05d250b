//! PNG plots written at the end of a run from its history.

use grains_core::history::History;
use grains_core::plot::{scatter_disks_png, LinePlot, Series};
use grains_dem::{Setup, State};
use std::path::Path;

/// Writes `energies.png`, `kinetic_energy.png` (log scale), `contacts.png`, with walls
/// `wall_forces.png`, and a map of the final particles coloured by speed.
pub fn write_all(dir: &Path, h: &History, setup: &Setup, state: &State) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir)?;
    let col = |name: &str| h.column(name).unwrap_or_default();
    let t = col("time");
    let shift = |v: Vec<f64>| -> Vec<f64> {
        let v0 = v.first().copied().unwrap_or(0.0);
        v.into_iter().map(|x| x - v0).collect()
    };
    let kinetic = col("kinetic");
    let elastic = col("elastic");
    let potential = shift(col("potential"));
    let total = shift(col("total"));
    LinePlot {
        title: "Energies (per unit thickness)",
        x_label: "time (s)",
        y_label: "energy (J/m)",
        series: vec![
            Series {
                name: "kinetic",
                x: &t,
                y: &kinetic,
            },
            Series {
                name: "elastic (contacts)",
                x: &t,
                y: &elastic,
            },
            Series {
                name: "potential − initial",
                x: &t,
                y: &potential,
            },
            Series {
                name: "total − initial",
                x: &t,
                y: &total,
            },
        ],
        log_y: false,
        points: false,
    }
    .write_png(&dir.join("energies.png"))?;

    LinePlot {
        title: "Kinetic energy",
        x_label: "time (s)",
        y_label: "energy (J/m)",
        series: vec![Series {
            name: "kinetic",
            x: &t,
            y: &kinetic,
        }],
        log_y: true,
        points: false,
    }
    .write_png(&dir.join("kinetic_energy.png"))?;

    let p = &state.particles;
    let speed: Vec<f64> = p.vel.iter().map(|v| v.length()).collect();
    scatter_disks_png(
        &dir.join("particles_final.png"),
        &format!("Particles at t = {:.4e} s", state.time),
        &p.pos,
        &p.radius,
        &speed,
        "speed (m/s)",
    )?;

    let coordination = col("coordination");
    LinePlot {
        title: "Mean coordination number",
        x_label: "time (s)",
        y_label: "contacts per particle",
        series: vec![Series {
            name: "coordination",
            x: &t,
            y: &coordination,
        }],
        log_y: false,
        points: false,
    }
    .write_png(&dir.join("contacts.png"))?;

    if !setup.walls.is_empty() {
        let data: Vec<(String, Vec<f64>)> = setup
            .walls
            .iter()
            .flat_map(|w| {
                ["fx", "fy"].map(|c| {
                    let key = format!("{}_{c}", w.name);
                    let v = col(&key);
                    (key, v)
                })
            })
            .collect();
        LinePlot {
            title: "Force of the particles on each wall",
            x_label: "time (s)",
            y_label: "force (N/m)",
            series: data
                .iter()
                .map(|(k, v)| Series {
                    name: k,
                    x: &t,
                    y: v,
                })
                .collect(),
            log_y: false,
            points: false,
        }
        .write_png(&dir.join("wall_forces.png"))?;
    }
    Ok(())
}
