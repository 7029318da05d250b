//! Bonded interfaces as a run sees them fail: the first step a bond breaks (the onset),
//! the separate debonded arcs of the watched disk's rim at that moment (the initiation
//! sites), its debonded length at every step while the front runs, and the points
//! coloured by bond at four moments (the paper's Fig. 5). At the end, the onset against
//! the static prediction, the front speed over the Rayleigh speed and the unloading of a
//! body once debonded.

use super::concentric::Concentric;
use super::plots::{Curves, Snapshot};
use super::probes::Record;
use super::reference::{line_fit, rayleigh_speed};
use super::scenario::CheckSpec;
use super::Mpm;
use glam::DVec2;
use grains_core::checks::Check;
use grains_mpm::{bond, Geometry};

/// Fraction of the watched perimeter debonded at which the front counts as through.
const THROUGH: f64 = 0.95;

/// The record of the bonded interfaces.
#[derive(Clone, Debug, Default)]
pub struct Debond {
    /// The disk whose rim is watched (the inner body of the concentric checks): its index,
    /// centre and radius.
    watched: Option<(usize, DVec2, f64)>,
    /// First time a bond failed (s).
    pub onset: Option<f64>,
    /// Angles (degrees) of the centres of the debonded arcs of the watched rim at onset.
    pub sites: Vec<f64>,
    /// (t, debonded, surface) of the watched body at every step from onset until the
    /// front is through.
    pub front: Vec<[f64; 3]>,
    /// The points coloured by bond at the moments of Fig. 5: (file, caption, snapshot).
    pub snapshots: Vec<(String, String, Snapshot)>,
    /// The last sample before onset, kept as the first panel.
    before: Option<Snapshot>,
    /// Grid cell size (m), for clustering the rim.
    h: f64,
}

fn bond_snapshot(sim: &Mpm) -> Snapshot {
    let p = &sim.state.particles;
    Snapshot {
        t: sim.state.time,
        pos: p.pos.clone(),
        value: p.bond.clone(),
        strain: 0.0,
    }
}

impl Debond {
    /// The record for `sim`, watching the inner disk of the first concentric check (or
    /// the first bonded disk); `None` without bonds.
    pub fn new(sim: &Mpm, specs: &[CheckSpec], shapes: &[Geometry]) -> Option<Self> {
        let setup = &sim.setup;
        if !setup.bonds() {
            return None;
        }
        let index = |b: &str| setup.bodies.iter().position(|x| x.name == b);
        let named = specs.iter().find_map(|c| match c {
            CheckSpec::DebondOnsetTime { inner, outer, .. }
            | CheckSpec::DebondSpeedOverRayleigh { inner, outer, .. } => {
                Concentric::new(shapes, index(inner)?, index(outer)?).ok()
            }
            _ => None,
        });
        let watched = match named {
            Some(p) => Some((p.inner, p.centre, p.a)),
            None => (0..setup.bodies.len())
                .filter(|&b| setup.contact.bond_of(b) > 0.0)
                .find_map(|b| match shapes[b] {
                    Geometry::Disk { centre, radius } => Some((b, DVec2::from(centre), radius)),
                    _ => None,
                }),
        };
        Some(Debond {
            watched,
            h: setup.grid.h,
            ..Default::default()
        })
    }

    /// The watched body, if any.
    pub fn watched(&self) -> Option<usize> {
        self.watched.map(|w| w.0)
    }

    /// After every step: the onset, and the front while it runs.
    pub fn on_step(&mut self, sim: &Mpm) {
        let s = &sim.state;
        if self.onset.is_none() {
            if !s.touch.iter().any(|t| t.debonded > 0) {
                return;
            }
            self.onset = Some(s.time);
            self.sites = self.arcs(sim);
            if let Some(before) = self.before.take() {
                self.snapshots.push((
                    "bond_1_before_onset.png".into(),
                    "before the first debond".into(),
                    before,
                ));
            }
        }
        let Some((b, ..)) = self.watched else {
            return;
        };
        if self.front.last().is_some_and(|f| f[1] >= THROUGH * f[2]) {
            return;
        }
        let ranges = &sim.solver.layout().bodies;
        let l = bond::lengths(&sim.setup, &s.particles, ranges)[b];
        self.front.push([s.time, l.debonded, l.surface]);
        for (k, (file, caption)) in [
            (
                1.0 / 3.0,
                ("bond_2_one_third.png", "a third of the interface debonded"),
            ),
            (
                2.0 / 3.0,
                (
                    "bond_3_two_thirds.png",
                    "two thirds of the interface debonded",
                ),
            ),
        ] {
            let taken = self.snapshots.iter().any(|x| x.0 == file);
            if !taken && l.debonded >= k * l.surface {
                self.snapshots
                    .push((file.into(), caption.into(), bond_snapshot(sim)));
            }
        }
    }

    /// At every sample: keeps the latest state before the onset.
    pub fn on_sample(&mut self, sim: &Mpm) {
        if self.onset.is_none() {
            self.before = Some(bond_snapshot(sim));
        }
    }

    /// At the end: the last panel.
    pub fn on_end(&mut self, sim: &Mpm) {
        if let Some(before) = self.before.take() {
            self.snapshots.push((
                "bond_1_before_onset.png".into(),
                "no bond has failed".into(),
                before,
            ));
        }
        self.snapshots.push((
            "bond_4_final.png".into(),
            "end of the run".into(),
            bond_snapshot(sim),
        ));
    }

    /// Separate debonded arcs of the watched rim (points within a cell of it whose bond is
    /// 0), split where consecutive ones are more than two cells of arc apart: the angles
    /// (degrees) of their middles.
    fn arcs(&self, sim: &Mpm) -> Vec<f64> {
        let Some((b, centre, radius)) = self.watched else {
            return Vec::new();
        };
        let p = &sim.state.particles;
        let (start, end) = sim.solver.layout().bodies[b];
        let mut angles: Vec<f64> = (start..end)
            .filter(|&i| (p.pos[i] - centre).length() > radius - self.h && p.bond[i] == 0.0)
            .map(|i| {
                let d = p.pos[i] - centre;
                d.y.atan2(d.x)
            })
            .collect();
        angles.sort_by(|a, b| a.total_cmp(b));
        let n = angles.len();
        if n == 0 {
            return Vec::new();
        }
        let gap = 2.0 * self.h / radius;
        let tau = std::f64::consts::TAU;
        let next = |k: usize| {
            if k + 1 < n {
                angles[k + 1]
            } else {
                angles[0] + tau
            }
        };
        // Start after a gap so no arc straddles the cut at ±π.
        let Some(first) = (0..n).find(|&k| next(k) - angles[k] > gap) else {
            return vec![0.0]; // one arc all the way round
        };
        let mut sites = Vec::new();
        let mut arc_start = next(first);
        let mut k = (first + 1) % n;
        loop {
            if next(k) - angles[k] > gap {
                let mut end = angles[k];
                while end < arc_start {
                    end += tau;
                }
                let mid = 0.5 * (arc_start + end);
                let mid = (mid + std::f64::consts::PI).rem_euclid(tau) - std::f64::consts::PI;
                sites.push(mid.to_degrees());
                arc_start = next(k);
            }
            if k == first {
                break;
            }
            k = (k + 1) % n;
        }
        sites.sort_by(|a, b| a.total_cmp(b));
        sites
    }

    /// Front speed (m/s): the slope of the debonded length between 10 % and 90 % of the
    /// perimeter, over two fronts per site; with the number of steps fitted.
    pub fn front_speed(&self) -> (f64, usize) {
        let Some(surface) = self.front.last().map(|f| f[2]) else {
            return (f64::NAN, 0);
        };
        let run: Vec<&[f64; 3]> = self
            .front
            .iter()
            .filter(|f| f[1] > 0.1 * surface && f[1] < 0.9 * surface)
            .collect();
        let t: Vec<f64> = run.iter().map(|f| f[0]).collect();
        let l: Vec<f64> = run.iter().map(|f| f[1]).collect();
        let (slope, _) = line_fit(&t, &l);
        (slope / (2 * self.sites.len().max(1)) as f64, run.len())
    }

    /// The debonded lengths over the run (from the samples) and the front while it runs
    /// (every step), with the onset and the 10–90 % fit marked.
    pub fn curves(&self, sim: &Mpm, rec: &Record) -> Vec<Curves> {
        let setup = &sim.setup;
        let t: Vec<f64> = rec.samples.iter().map(|s| s.t).collect();
        let mut series = Vec::new();
        for (b, body) in setup.bodies.iter().enumerate() {
            if setup.contact.bond_of(b) > 0.0 {
                let l: Vec<f64> = rec.samples.iter().map(|s| s.bodies[b].debonded).collect();
                series.push((format!("{} debonded", body.name), t.clone(), l));
            }
        }
        let top = series
            .iter()
            .flat_map(|s| s.2.iter().copied())
            .fold(0.0, f64::max);
        if let Some(onset) = self.onset {
            series.push(("onset".into(), vec![onset, onset], vec![0.0, top]));
        }
        let mut out = vec![Curves {
            file: "debonded_length.png".into(),
            title: "Debonded length of each bonded body".into(),
            x_label: "time (s)".into(),
            y_label: "debonded length (m per unit thickness)".into(),
            series,
            log_y: false,
        }];
        if let (Some((b, ..)), false) = (self.watched, self.front.is_empty()) {
            let name = &setup.bodies[b].name;
            let col = |k: usize| self.front.iter().map(|f| f[k]).collect::<Vec<f64>>();
            let (ft, surface) = (col(0), col(2));
            let mut series = vec![
                (format!("{name} debonded"), ft.clone(), col(1)),
                (format!("{name} perimeter"), ft.clone(), surface.clone()),
            ];
            let s = surface.last().copied().unwrap_or(f64::NAN);
            let run: Vec<&[f64; 3]> = self
                .front
                .iter()
                .filter(|f| f[1] > 0.1 * s && f[1] < 0.9 * s)
                .collect();
            let (tr, lr): (Vec<f64>, Vec<f64>) = run.iter().map(|f| (f[0], f[1])).unzip();
            let (slope, c) = line_fit(&tr, &lr);
            if let (Some(a), Some(z)) = (tr.first(), tr.last()) {
                let fronts = 2 * self.sites.len().max(1);
                series.push((
                    format!(
                        "fit over 10–90 %: dL/dt = {slope:.3} m/s = {fronts} fronts × {:.4} m/s",
                        slope / fronts as f64
                    ),
                    vec![*a, *z],
                    vec![c + slope * a, c + slope * z],
                ));
            }
            out.push(Curves {
                file: "debond_front.png".into(),
                title: format!("Debonding of \"{name}\" from the onset, every step"),
                x_label: "time (s)".into(),
                y_label: "length (m per unit thickness)".into(),
                series,
                log_y: false,
            });
        }
        out
    }

    /// Figures for `summary.json`.
    pub fn figures(&self) -> serde_json::Map<String, serde_json::Value> {
        let mut f = serde_json::Map::new();
        f.insert("debond_onset_time".into(), self.onset.into());
        if self.watched.is_some() && self.onset.is_some() {
            f.insert("initiation_sites".into(), self.sites.len().into());
            f.insert("initiation_angles_deg".into(), self.sites.clone().into());
            let (speed, n) = self.front_speed();
            f.insert("debond_front_speed".into(), speed.into());
            f.insert("debond_front_steps_fitted".into(), n.into());
            if let Some(last) = self.front.last() {
                f.insert("debond_front_through_time".into(), last[0].into());
            }
        }
        f
    }

    /// The check `spec` if it is one of the debond checks.
    pub fn check(
        &self,
        spec: &CheckSpec,
        sim: &Mpm,
        shapes: &[Geometry],
        rec: &Record,
    ) -> Option<Check> {
        let setup = &sim.setup;
        let index = |b: &str| sim.body(b);
        let onset = self.onset.unwrap_or(f64::NAN);
        Some(match spec {
            CheckSpec::DebondOnsetTime {
                name,
                inner,
                outer,
                tolerance,
            } => {
                let pair = Concentric::new(shapes, index(inner), index(outer)).ok()?;
                let expected = pair.predicted_onset(setup, sim.state.time);
                Check::relative(name, onset, expected, *tolerance).with_note(&format!(
                    "first step with a failed bond vs the time the static interface tension σ_rr(a) (plane strain, the temperatures at that time) reaches the bond strength {:.4e} Pa",
                    pair.bond(setup).unwrap_or(f64::NAN)
                ))
            }
            CheckSpec::DebondSpeedOverRayleigh {
                name, outer, range, ..
            } => {
                let m = &setup.materials[setup.bodies[index(outer)].material];
                let (bulk, shear) = m.moduli();
                let c_r = rayleigh_speed(bulk, shear, m.density());
                let (speed, n) = self.front_speed();
                let (lo, hi) = (range[0], range[1]);
                Check::absolute(name, speed / c_r, 0.5 * (lo + hi), 0.5 * (hi - lo)).with_note(&format!(
                    "front speed = slope of the inner disk's debonded length between 10 % and 90 % of its perimeter ({n} steps) / (2 fronts × {} initiation sites) over the outer material's plane-strain Rayleigh speed c_R = {c_r:.4} m/s; must lie in ({lo}, {hi}] (an interface crack runs below c_R; the paper reports 0.84)",
                    self.sites.len()
                ))
            }
            CheckSpec::StressFreeAfterDebond {
                name,
                body,
                after,
                max,
            } => {
                let b = index(body);
                let peak = rec
                    .samples
                    .iter()
                    .filter(|s| s.t < onset)
                    .map(|s| s.bodies[b].mean_stress.abs())
                    .fold(0.0, f64::max);
                let late: Vec<f64> = rec
                    .samples
                    .iter()
                    .filter(|s| s.t > onset + after)
                    .map(|s| s.bodies[b].mean_stress)
                    .collect();
                let mean = late.iter().sum::<f64>() / late.len() as f64;
                let span = rec.samples.last().map_or(0.0, |s| s.t) - onset - after;
                Check::at_most(name, (mean / peak).abs(), *max).with_note(&format!(
                    "|mean over {} samples from t = onset + {after} s to the end ({span:.1} s) of the body's mean (σ_xx + σ_yy)/2| over its largest |·| before the onset ({peak:.4e} Pa): once debonded nothing loads it, but it rings undamped about zero, so the average needs many periods",
                    late.len()
                ))
            }
            _ => return None,
        })
    }
}
