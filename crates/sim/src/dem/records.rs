//! What a DEM run records besides frames: history rows and end-of-run figures.

use super::scenario::{FigureSpec, Scenario};
use super::Dem;
use crate::history::Recorded;
use grains_dem::diagnostics::Diagnostics;
use grains_dem::{Setup, State};

impl Recorded for Dem {
    fn columns(&self) -> Vec<String> {
        history_columns(&self.setup)
    }

    fn integer_columns(&self) -> Vec<String> {
        ["step", "pair_contacts", "wall_contacts", "neighbour_builds"]
            .map(String::from)
            .to_vec()
    }

    fn row(&self, d: &Diagnostics) -> Vec<f64> {
        history_row(&self.setup, &self.state, d)
    }
}

/// Names of the history.csv columns.
pub fn history_columns(setup: &Setup) -> Vec<String> {
    let mut c: Vec<String> = [
        "time",
        "step",
        "kinetic",
        "kinetic_rotational",
        "potential",
        "elastic",
        "total",
        "momentum_x",
        "momentum_y",
        "pair_contacts",
        "wall_contacts",
        "coordination",
        "max_overlap_ratio",
        "neighbour_builds",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    for w in &setup.walls {
        for suffix in ["fx", "fy", "torque"] {
            c.push(format!("{}_{suffix}", w.name));
        }
    }
    c
}

/// One history row for the state and its diagnostics.
pub fn history_row(setup: &Setup, s: &State, d: &Diagnostics) -> Vec<f64> {
    let n = s.particles.len();
    let mut row = vec![
        s.time,
        s.step as f64,
        d.kinetic(),
        d.kinetic_rotational,
        d.potential,
        d.elastic,
        d.total(),
        d.momentum.x,
        d.momentum.y,
        d.pair_contacts as f64,
        d.wall_contacts as f64,
        d.mean_coordination(n),
        d.max_overlap_ratio,
        s.contacts.builds as f64,
    ];
    for load in s.wall_loads.iter().take(setup.walls.len()) {
        row.extend([load.force.x, load.force.y, load.torque]);
    }
    row
}

/// The scenario's figures at the end of the run.
pub fn figures(
    scenario: &Scenario,
    setup: &Setup,
    s: &State,
    d: &Diagnostics,
) -> serde_json::Map<String, serde_json::Value> {
    let p = &s.particles;
    let n = p.len();
    let mut out = serde_json::Map::new();
    out.insert("kinetic_energy_final".into(), d.kinetic().into());
    out.insert(
        "mean_coordination_final".into(),
        d.mean_coordination(n).into(),
    );
    for f in &scenario.figures {
        match f {
            FigureSpec::MeanCoordination { name } => {
                out.insert(name.clone(), d.mean_coordination(n).into());
            }
            FigureSpec::PackingFraction {
                name,
                region,
                margin,
            } => {
                let mean_d = 2.0 * p.radius.iter().sum::<f64>() / n as f64;
                let (lo, hi) = match region {
                    Some(r) => (glam::DVec2::from(r.lo), glam::DVec2::from(r.hi)),
                    None => {
                        let mut lo = p
                            .pos
                            .iter()
                            .copied()
                            .fold(glam::DVec2::INFINITY, glam::DVec2::min);
                        let mut hi = p
                            .pos
                            .iter()
                            .copied()
                            .fold(glam::DVec2::NEG_INFINITY, glam::DVec2::max);
                        for a in 0..2 {
                            if setup.domain.periodic[a] {
                                lo[a] = setup.domain.lo[a];
                                hi[a] = setup.domain.hi[a];
                            } else {
                                lo[a] += margin * mean_d;
                                hi[a] -= margin * mean_d;
                            }
                        }
                        (lo, hi)
                    }
                };
                // Disks are counted whole by their centres: the bias at the region's
                // edges averages out for regions many diameters across.
                let area: f64 = (0..n)
                    .filter(|&i| p.pos[i].cmpge(lo).all() && p.pos[i].cmplt(hi).all())
                    .map(|i| std::f64::consts::PI * p.radius[i].powi(2))
                    .sum();
                let region_area = (hi - lo).x.max(0.0) * (hi - lo).y.max(0.0);
                let phi = if region_area > 0.0 {
                    area / region_area
                } else {
                    f64::NAN
                };
                out.insert(name.clone(), phi.into());
            }
        }
    }
    out
}
