//! PNG plots written at the end of a run from its history.

use super::Dem;
use crate::frames::Mapped;
use grains_core::history::History;
use grains_core::plot::{time_label, LinePlot, Outline, ParticleMap, Series};
use grains_dem::{Setup, State};
use std::path::Path;

/// The units a DEM run's plots are labelled in: per unit thickness in 2D, whole in 3D.
pub struct Units {
    /// Energy (J/m or J).
    pub energy: &'static str,
    /// Force (N/m or N).
    pub force: &'static str,
    /// What the values are per, for the titles (" (per unit thickness)" or "").
    pub per: &'static str,
}

/// The 2D units.
pub const PLANAR: Units = Units {
    energy: "J/m",
    force: "N/m",
    per: " (per unit thickness)",
};

/// Writes `energies.png`, `kinetic_energy.png` (log scale), `contacts.png`, with walls
/// `wall_forces_x.png` and `wall_forces_y.png`, and a map of the final particles coloured by speed.
pub fn write_all(dir: &Path, h: &History, setup: &Setup, state: &State) -> anyhow::Result<()> {
    let walls: Vec<&str> = setup.walls.iter().map(|w| w.name.as_str()).collect();
    history_plots(dir, h, &walls, &["x", "y"], &PLANAR)?;
    particle_map(&dir.join("particles_final.png"), setup, state)
}

/// The plots of a DEM history (2D or 3D): energies, kinetic energy, coordination and,
/// with walls, each wall's force along each of `axes`.
pub fn history_plots(
    dir: &Path,
    h: &History,
    walls: &[&str],
    axes: &[&str],
    units: &Units,
) -> anyhow::Result<()> {
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
        title: &format!("Energies{}", units.per),
        x_label: "time (s)",
        y_label: &format!("energy ({})", units.energy),
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
    .write_png_and_csv(&dir.join("energies.png"))?;

    LinePlot {
        title: &format!("Kinetic energy{}", units.per),
        x_label: "time (s)",
        y_label: &format!("energy ({})", units.energy),
        series: vec![Series {
            name: "kinetic",
            x: &t,
            y: &kinetic,
        }],
        log_y: true,
        points: false,
    }
    .write_png_and_csv(&dir.join("kinetic_energy.png"))?;

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
    .write_png_and_csv(&dir.join("contacts.png"))?;

    for axis in axes {
        if walls.is_empty() {
            break;
        }
        let (data, idle) = loaded_walls(walls, |w| col(&format!("{w}_f{axis}")));
        // Each sample is one instant of impacts; a running mean shows each wall's load
        // instead of six sets of spikes over one another (history.csv keeps the samples).
        let window = (t.len() / 50).max(1);
        let data: Vec<(&str, Vec<f64>)> = data
            .into_iter()
            .map(|(k, v)| (k, running_mean(&v, window)))
            .collect();
        let span = t.last().copied().unwrap_or(0.0) - t.first().copied().unwrap_or(0.0);
        let mean_over = span * window as f64 / t.len().max(1) as f64;
        let idle_note = if idle.is_empty() {
            String::new()
        } else {
            format!("; zero throughout: {}", idle.join(", "))
        };
        let title = format!(
            "Force of the particles on each wall along {axis}, mean over {mean_over:.2e} s{idle_note}"
        );
        LinePlot {
            title: &title,
            x_label: "time (s)",
            y_label: &format!("force along {axis}{} ({})", units.per, units.force),
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
        .write_png_and_csv(&dir.join(format!("wall_forces_{axis}.png")))?;
    }
    Ok(())
}

/// The centred running mean of `v` over `window` samples (fewer at the ends), skipping
/// non-finite samples.
fn running_mean(v: &[f64], window: usize) -> Vec<f64> {
    let half = window / 2;
    // Prefix sums of the finite samples and of their count: O(n) for any window.
    let mut sum = vec![0.0; v.len() + 1];
    let mut count = vec![0usize; v.len() + 1];
    for (i, x) in v.iter().enumerate() {
        let ok = x.is_finite();
        sum[i + 1] = sum[i] + if ok { *x } else { 0.0 };
        count[i + 1] = count[i] + usize::from(ok);
    }
    (0..v.len())
        .map(|i| {
            let (a, b) = (i.saturating_sub(half), (i + half + 1).min(v.len()));
            let n = count[b] - count[a];
            if n > 0 {
                (sum[b] - sum[a]) / n as f64
            } else {
                f64::NAN
            }
        })
        .collect()
}

/// The walls' force series worth drawing, the smallest mean load first so that the
/// largest (a floor's, which carries the bed) is drawn last, on top of the others' spikes;
/// and the names of the walls whose force is zero throughout, which are left out.
fn loaded_walls<'a>(
    walls: &[&'a str],
    force: impl Fn(&str) -> Vec<f64>,
) -> (Vec<(&'a str, Vec<f64>)>, Vec<&'a str>) {
    let peak = |v: &[f64]| {
        v.iter()
            .filter(|x| x.is_finite())
            .fold(0.0f64, |m, x| m.max(x.abs()))
    };
    let (mut drawn, idle): (Vec<_>, Vec<_>) = walls
        .iter()
        .map(|w| (*w, force(w)))
        .partition(|(_, v)| peak(v) > 0.0);
    let mean = |v: &[f64]| {
        let f: Vec<f64> = v
            .iter()
            .filter(|x| x.is_finite())
            .map(|x| x.abs())
            .collect();
        f.iter().sum::<f64>() / f.len().max(1) as f64
    };
    drawn.sort_by(|a, b| mean(&a.1).total_cmp(&mean(&b.1)));
    (drawn, idle.into_iter().map(|(n, _)| n).collect())
}

/// The particles coloured by speed, with the walls drawn.
pub fn particle_map(path: &Path, setup: &Setup, state: &State) -> anyhow::Result<()> {
    let p = &state.particles;
    let speed: Vec<f64> = p.vel.iter().map(|v| v.length()).collect();
    let walls: Vec<Outline> = setup
        .walls
        .iter()
        .map(|w| Outline {
            points: w.shape.outline(),
            closed: false,
        })
        .collect();
    ParticleMap {
        title: &format!(
            "Particles at t = {}, coloured by speed",
            time_label(state.time)
        ),
        centres: &p.pos,
        radii: &p.radius,
        values: &speed,
        value_label: "speed (m/s)",
        outlines: &walls,
    }
    .write_png(path)?;
    Ok(())
}

impl Mapped for Dem {
    fn map_name(&self) -> String {
        format!("particles_{:.6e}s.png", self.state.time)
    }

    fn draw_map(&self, path: &Path) -> anyhow::Result<()> {
        particle_map(path, &self.setup, &self.state)
    }
}
