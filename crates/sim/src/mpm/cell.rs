//! A cell sheared between two rigid boundaries (`[shear]`, the paper's Figs. 6–8): per
//! sample the shear strain, the shear and normal stresses on each boundary (its bodies'
//! contact reactions over its length), the grains' debonded length and the energy
//! ledger; at the end the locking events (both boundaries' shear stresses above a stated
//! threshold: a chain of grains spans the cell; with their peak and strain), the inertial
//! number, and the maps a reader of
//! the paper compares with its figures: the bodies at the start and the end (Fig. 6), the
//! principal stress difference at the first lock (Fig. 7), the bond early on and at the
//! end (Fig. 8).

use super::plots::{Curves, Snapshot};
use super::probes::Sample;
use super::scenario::ShearSpec;
use super::Mpm;
use glam::DVec2;
use grains_core::checks::Check;
use grains_mpm::{Geometry, Motion};

/// The shear strain at which the binder's bond is drawn "early on" (Fig. 8, left).
pub const EARLY_STRAIN: f64 = 0.2;

/// One sample of the cell.
#[derive(Clone, Copy, Debug, Default)]
pub struct Row {
    /// Time (s).
    pub t: f64,
    /// Shear strain: the boundaries' relative displacement along y over the width.
    pub gamma: f64,
    /// σ_xy on the left and right boundaries (Pa).
    pub tau: [f64; 2],
    /// σ_xx on the left and right boundaries (Pa, tension > 0).
    pub sigma: [f64; 2],
    /// Debonded length of the binder's interfaces (m).
    pub debonded: f64,
}

impl Row {
    /// Mean shear stress of the two boundaries.
    pub fn shear(&self) -> f64 {
        0.5 * (self.tau[0] + self.tau[1])
    }

    /// Mean compressive normal stress of the two boundaries (−σ_xx).
    pub fn pressure(&self) -> f64 {
        -0.5 * (self.sigma[0] + self.sigma[1])
    }

    /// The lesser of the two boundaries' shear stresses: high only while a chain of
    /// grains carries the load from one boundary to the other (a grain that merely hits
    /// one boundary loads that one alone).
    pub fn spanning(&self) -> f64 {
        self.tau[0].min(self.tau[1])
    }
}

/// A locking event: both boundaries' shear stresses above the threshold from `start`
/// to `end` ([`Row::spanning`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lock {
    /// Strain where the stress rose above the threshold.
    pub start: f64,
    /// Strain at the peak.
    pub peak_strain: f64,
    /// The peak mean shear stress of the two boundaries (Pa).
    pub peak: f64,
    /// Strain where it fell back (the last sample if it never did).
    pub end: f64,
    /// Mean compressive normal stress at the peak (Pa).
    pub pressure: f64,
}

/// The locking events of `rows`.
pub fn locks(rows: &[Row], threshold: f64) -> Vec<Lock> {
    let mut out: Vec<Lock> = Vec::new();
    let mut open = false;
    for r in rows {
        let tau = r.shear();
        if r.spanning() > threshold {
            if !open {
                out.push(Lock {
                    start: r.gamma,
                    peak_strain: r.gamma,
                    peak: tau,
                    end: r.gamma,
                    pressure: r.pressure(),
                });
                open = true;
            }
            let l = out.last_mut().expect("opened above");
            if tau > l.peak {
                (l.peak, l.peak_strain, l.pressure) = (tau, r.gamma, r.pressure());
            }
            l.end = r.gamma;
        } else if open {
            out.last_mut().expect("open").end = r.gamma;
            open = false;
        }
    }
    out
}

/// The `q` quantile of `v` (nearest rank; NaN if empty).
fn percentile(v: &[f64], q: f64) -> f64 {
    let mut s: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    if s.is_empty() {
        return f64::NAN;
    }
    s.sort_unstable_by(f64::total_cmp);
    s[((s.len() - 1) as f64 * q).round() as usize]
}

/// The record of the cell.
#[derive(Clone, Debug)]
pub struct Cell {
    left: Vec<usize>,
    right: Vec<usize>,
    binder: Option<usize>,
    threshold: f64,
    /// Boundary length (the grid's height) and width (m).
    length: f64,
    width: f64,
    /// Density and mean diameter of the free grains (for the inertial number).
    grain: (f64, f64),
    /// One row per sample.
    pub rows: Vec<Row>,
    /// The points at the first lock's peak so far, while it lasts.
    first_lock: Option<Snapshot>,
    first_over: bool,
    /// The maps: (file, caption, value label, snapshot).
    pub maps: Vec<(String, String, String, Snapshot)>,
}

fn snapshot(sim: &Mpm, strain: f64, value: impl Fn(usize) -> f64) -> Snapshot {
    let p = &sim.state.particles;
    Snapshot {
        t: sim.state.time,
        pos: p.pos.clone(),
        value: (0..p.len()).map(value).collect(),
        strain,
    }
}

impl Cell {
    /// The record of `sim`'s `[shear]` cell (names validated); `shapes` are the bodies'
    /// shapes as filled.
    pub fn new(sim: &Mpm, spec: &ShearSpec, shapes: &[Geometry]) -> Self {
        let setup = &sim.setup;
        let index = |n: &String| sim.body(n);
        let binder = spec.binder.as_ref().map(index);
        let grains: Vec<usize> = (0..setup.bodies.len())
            .filter(|&b| setup.bodies[b].motion == Motion::Free && Some(b) != binder)
            .collect();
        let diameter = grains
            .iter()
            .map(|&b| 2.0 * (shapes[b].area() / std::f64::consts::PI).sqrt())
            .sum::<f64>()
            / grains.len().max(1) as f64;
        let density = grains.first().map_or(f64::NAN, |&b| {
            setup.materials[setup.bodies[b].material].density()
        });
        let (lo, hi) = (setup.grid.lo, setup.grid.hi());
        let mut cell = Cell {
            left: spec.left.iter().map(index).collect(),
            right: spec.right.iter().map(index).collect(),
            binder,
            threshold: spec.lock_threshold,
            length: hi.y - lo.y,
            width: hi.x - lo.x,
            grain: (density, diameter),
            rows: Vec::new(),
            first_lock: None,
            first_over: false,
            maps: Vec::new(),
        };
        cell.maps
            .push(cell.bodies_map(sim, "cell_initial.png", "start"));
        cell
    }

    fn bodies_map(&self, sim: &Mpm, file: &str, when: &str) -> (String, String, String, Snapshot) {
        let body = &sim.state.particles.body;
        (
            file.into(),
            format!("Bodies at the {when} (γ = {:.2})", self.strain()),
            "shade (tells bodies apart)".into(),
            // Consecutive bodies (neighbours in a packing or a list) would get nearly
            // the same colour from their index; the golden-ratio step spreads them.
            snapshot(sim, self.strain(), |i| {
                (f64::from(body[i]) * 0.618_033_988_75).fract()
            }),
        )
    }

    /// The binder's points coloured by their bond (the paper's Fig. 8), the grains grey.
    fn bond_map(
        &self,
        sim: &Mpm,
        file: &str,
        when: &str,
        gamma: f64,
    ) -> (String, String, String, Snapshot) {
        let p = &sim.state.particles;
        let binder = self.binder.map(|b| b as u16);
        (
            file.into(),
            format!("Binder's bond {when} (γ = {gamma:.2}); 0 = debonded, grains grey"),
            "bond strength (Pa)".into(),
            snapshot(sim, gamma, |i| {
                if Some(p.body[i]) == binder {
                    p.bond[i]
                } else {
                    f64::NAN
                }
            }),
        )
    }

    fn strain(&self) -> f64 {
        self.rows.last().map_or(0.0, |r| r.gamma)
    }

    /// Adds a sample.
    pub fn on_sample(&mut self, sim: &Mpm, s: &Sample) {
        let sum = |list: &[usize], f: fn(&super::probes::BodySample) -> DVec2| {
            list.iter().map(|&b| f(&s.bodies[b])).sum::<DVec2>()
        };
        let (fl, fr) = (sum(&self.left, |b| b.force), sum(&self.right, |b| b.force));
        let (dl, dr) = (
            s.bodies[self.left[0]].displacement,
            s.bodies[self.right[0]].displacement,
        );
        let row = Row {
            t: s.t,
            gamma: (dr.y - dl.y) / self.width,
            // The material's stress where it meets each boundary: σ·n = force per length,
            // with n = −x on the left and +x on the right.
            tau: [-fl.y / self.length, fr.y / self.length],
            sigma: [-fl.x / self.length, fr.x / self.length],
            debonded: self.binder.map_or(0.0, |b| s.bodies[b].debonded),
        };
        let early =
            self.rows.last().is_some_and(|r| r.gamma < EARLY_STRAIN) && row.gamma >= EARLY_STRAIN;
        self.rows.push(row);
        if early && self.binder.is_some() {
            self.maps
                .push(self.bond_map(sim, "bond_early.png", "early on", row.gamma));
        }
        // The first lock: keep the points at its highest stress until it is over.
        if self.first_over {
            return;
        }
        let tau = row.shear();
        if row.spanning() > self.threshold {
            let higher = self.first_lock.as_ref().is_none_or(|f| tau > f.strain);
            if higher {
                let st = &sim.state.particles.stress;
                let mut snap = snapshot(sim, row.gamma, |i| st[i].principal_difference());
                snap.strain = tau;
                self.first_lock = Some(snap);
            }
        } else if self.first_lock.is_some() {
            self.first_over = true;
        }
    }

    /// At the end: the final maps.
    pub fn on_end(&mut self, sim: &Mpm) {
        let end = self.bodies_map(sim, "cell_final.png", "end");
        self.maps.push(end);
        if self.binder.is_some() {
            let map = self.bond_map(sim, "bond_final.png", "at the end", self.strain());
            self.maps.push(map);
        }
        if let Some(mut f) = self.first_lock.take() {
            let l = locks(&self.rows, self.threshold);
            let at = l.first().map_or(f64::NAN, |l| l.peak_strain);
            // A few points at the contacts carry several times the rest: the colours
            // stop at the 99th percentile so that the chains between them show.
            let top = percentile(&f.value, 0.99);
            f.value.iter_mut().for_each(|v| *v = v.min(top));
            self.maps.push((
                "lock_first.png".into(),
                format!(
                    "First lock (γ = {at:.3}, τ = {:.3e} Pa): σ1 − σ2, colours capped at its 99th percentile",
                    f.strain
                ),
                "principal stress difference σ1 − σ2 (Pa)".into(),
                f,
            ));
        }
    }

    /// The mean shear rate after the first half of the run (1/s).
    fn rate(&self) -> f64 {
        let n = self.rows.len();
        if n < 3 {
            return f64::NAN;
        }
        let (a, b) = (&self.rows[n / 2], &self.rows[n - 1]);
        (b.gamma - a.gamma) / (b.t - a.t)
    }

    /// The inertial number γ̇ d / √(p/ρ) at compressive normal stress `p`.
    fn inertial(&self, p: f64) -> f64 {
        let (rho, d) = self.grain;
        self.rate() * d / (p / rho).sqrt()
    }

    /// The figures of summary.json.
    pub fn figures(&self) -> serde_json::Map<String, serde_json::Value> {
        let mut f = serde_json::Map::new();
        let events = locks(&self.rows, self.threshold);
        let last = self.rows.last().copied().unwrap_or_default();
        f.insert("shear_strain_final".into(), last.gamma.into());
        f.insert("shear_rate".into(), self.rate().into());
        f.insert("lock_threshold".into(), self.threshold.into());
        f.insert("locking_events".into(), events.len().into());
        let list: Vec<serde_json::Value> = events
            .iter()
            .map(|l| {
                serde_json::json!({
                    "start_strain": l.start,
                    "peak_strain": l.peak_strain,
                    "peak_shear_stress": l.peak,
                    "end_strain": l.end,
                    "pressure_at_peak": l.pressure,
                    "inertial_number_at_peak": self.inertial(l.pressure),
                })
            })
            .collect();
        f.insert("locks".into(), list.into());
        if let Some(l) = events.first() {
            f.insert("first_lock_strain".into(), l.peak_strain.into());
        }
        let max = |g: fn(&Row) -> f64| self.rows.iter().map(g).fold(f64::NAN, f64::max);
        f.insert("shear_stress_max".into(), max(|r| r.shear()).into());
        f.insert("pressure_max".into(), max(|r| r.pressure()).into());
        let loaded: Vec<f64> = self.rows.iter().map(|r| r.pressure().max(0.0)).collect();
        let mean = loaded.iter().sum::<f64>() / loaded.len().max(1) as f64;
        f.insert("pressure_mean".into(), mean.into());
        f.insert("inertial_number_mean".into(), self.inertial(mean).into());
        f.insert("grain_diameter_mean".into(), self.grain.1.into());
        if self.binder.is_some() {
            f.insert("debonded_length_final".into(), last.debonded.into());
        }
        f
    }

    /// The check a `[shear]` cell answers.
    pub fn strain_check(&self, name: &str, min: f64) -> Check {
        Check::at_least(name, self.strain(), min)
            .with_note("shear strain: the boundaries' relative displacement over the cell's width")
    }

    /// Stress, ledger and debonding against strain.
    pub fn curves(&self, record: &[Sample]) -> Vec<Curves> {
        let g: Vec<f64> = self.rows.iter().map(|r| r.gamma).collect();
        let col = |f: &dyn Fn(&Row) -> f64| self.rows.iter().map(f).collect::<Vec<f64>>();
        let line = |v: f64| vec![v; g.len()];
        let mut out = vec![
            Curves {
                file: "shear_stress.png".into(),
                title: "Shear stress on the boundaries against shear strain".into(),
                x_label: "shear strain γ".into(),
                y_label: "shear stress σ_xy (Pa)".into(),
                series: vec![
                    ("left boundary".into(), g.clone(), col(&|r| r.tau[0])),
                    ("right boundary".into(), g.clone(), col(&|r| r.tau[1])),
                    ("mean".into(), g.clone(), col(&|r| r.shear())),
                    (
                        "lock threshold (both boundaries above it)".into(),
                        g.clone(),
                        line(self.threshold),
                    ),
                ],
                log_y: false,
            },
            Curves {
                file: "normal_stress.png".into(),
                title: "Normal stress on the boundaries against shear strain".into(),
                x_label: "shear strain γ".into(),
                y_label: "compressive normal stress −σ_xx (Pa)".into(),
                series: vec![
                    ("left boundary".into(), g.clone(), col(&|r| -r.sigma[0])),
                    ("right boundary".into(), g.clone(), col(&|r| -r.sigma[1])),
                ],
                log_y: false,
            },
        ];
        // The record also holds the first sample, taken before the cell's rows began.
        let record = &record[record.len().saturating_sub(self.rows.len())..];
        if record.len() == self.rows.len() {
            let e = |f: fn(&Sample) -> f64| record.iter().map(f).collect::<Vec<f64>>();
            let l0 = record.first().map_or(0.0, Sample::ledger);
            out.push(Curves {
                file: "energy_ledger.png".into(),
                title: "Energy ledger against shear strain (per unit thickness)".into(),
                x_label: "shear strain γ".into(),
                y_label: "energy (J/m)".into(),
                series: vec![
                    ("boundary work".into(), g.clone(), e(|s| s.work)),
                    ("kinetic + elastic".into(), g.clone(), e(|s| s.energy)),
                    ("plastic".into(), g.clone(), e(|s| s.plastic)),
                    ("viscous".into(), g.clone(), e(|s| s.viscous)),
                    ("friction".into(), g.clone(), e(|s| s.friction)),
                    ("bonds (debonding)".into(), g.clone(), e(|s| s.bond)),
                    (
                        "grid-to-point transfer".into(),
                        g.clone(),
                        e(|s| s.transfer),
                    ),
                    (
                        "unaccounted (ledger drift)".into(),
                        g.clone(),
                        record.iter().map(|s| s.ledger() - l0).collect(),
                    ),
                ],
                log_y: false,
            });
        }
        if self.binder.is_some() {
            out.push(Curves {
                file: "debonded_length.png".into(),
                title: "Debonded length of the binder's interfaces against shear strain".into(),
                x_label: "shear strain γ".into(),
                y_label: "debonded length (m per unit thickness)".into(),
                series: vec![("debonded".into(), g.clone(), col(&|r| r.debonded))],
                log_y: false,
            });
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn locks_are_excursions_above_the_threshold() {
        let mut rows: Vec<Row> = [0.0, 2.0, 5.0, 3.0, 0.5, 4.0, 6.0]
            .iter()
            .enumerate()
            .map(|(k, &tau)| Row {
                gamma: 0.1 * k as f64,
                tau: [tau, tau],
                sigma: [-1.0, -3.0],
                ..Default::default()
            })
            .collect();
        // A grain hitting one boundary alone is no lock.
        rows[4].tau = [9.0, 0.5];
        let l = locks(&rows, 1.0);
        assert_eq!(l.len(), 2);
        assert_eq!((l[0].start, l[0].peak, l[0].end), (0.1, 5.0, 0.4));
        assert!((l[0].peak_strain - 0.2).abs() < 1e-12);
        assert_eq!(l[0].pressure, 2.0);
        assert_eq!((l[1].peak, l[1].end), (6.0, 0.6000000000000001));
    }
}
