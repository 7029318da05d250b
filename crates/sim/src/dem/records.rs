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
        INTEGER_COLUMNS.map(String::from).to_vec()
    }

    fn row(&self, d: &Diagnostics) -> Vec<f64> {
        history_row(&self.setup, &self.state, d)
    }
}

/// The history's integer columns, in 2D and 3D.
pub const INTEGER_COLUMNS: [&str; 4] =
    ["step", "pair_contacts", "wall_contacts", "neighbour_builds"];

/// History columns of a DEM run in `axes` (momentum components) with `walls`, each
/// with the load columns `loads`: the same names in 2D and 3D.
pub fn columns(axes: &[&str], walls: &[&str], loads: &[&str]) -> Vec<String> {
    let mut c: Vec<String> = [
        "time",
        "step",
        "kinetic",
        "kinetic_rotational",
        "potential",
        "elastic",
        "total",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    c.extend(axes.iter().map(|a| format!("momentum_{a}")));
    for name in [
        "pair_contacts",
        "wall_contacts",
        "coordination",
        "max_overlap_ratio",
        "neighbour_builds",
    ] {
        c.push(name.into());
    }
    for w in walls {
        for suffix in loads {
            c.push(format!("{w}_{suffix}"));
        }
    }
    c
}

/// The row of a DEM state `$s` and its diagnostics `$d` before the walls' loads: the
/// same fields in 2D and 3D, from the two builds' own types.
macro_rules! state_row {
    ($s:expr, $d:expr) => {{
        let (s, d) = ($s, $d);
        let mut row = vec![
            s.time,
            s.step as f64,
            d.kinetic(),
            d.kinetic_rotational,
            d.potential,
            d.elastic,
            d.total(),
        ];
        row.extend(d.momentum.to_array());
        row.extend([
            d.pair_contacts as f64,
            d.wall_contacts as f64,
            d.mean_coordination(s.particles.len()),
            d.max_overlap_ratio,
            s.contacts.builds as f64,
        ]);
        row
    }};
}
pub(crate) use state_row;

/// Names of the history.csv columns.
pub fn history_columns(setup: &Setup) -> Vec<String> {
    let walls: Vec<&str> = setup.walls.iter().map(|w| w.name.as_str()).collect();
    columns(&["x", "y"], &walls, &["fx", "fy", "torque"])
}

/// One history row for the state and its diagnostics.
pub fn history_row(setup: &Setup, s: &State, d: &Diagnostics) -> Vec<f64> {
    let mut row = state_row!(s, d);
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
