//! What an MPM run watches to judge itself: each body's wall impacts (from the contact
//! flags of every step), the sampled energies and body motion, the material response
//! its checks probe, its bonded interfaces, snapshots of the points at the moments that
//! tell (largest stored energy, each impact's deepest moment), and at the end the checks
//! and figures computed from them.

use super::debond::Debond;
use super::plots::Snapshot;
use super::probes::{self, Context, Record};
use super::response::Response;
use super::scenario::{CheckSpec, Scenario};
use super::{Mpm, MpmSample};
use crate::driver::{Flow, FrameKind, Observer, Report, Status};
use glam::DVec2;
use grains_core::checks::Check;
use grains_mpm::setup::SIDES;
use grains_mpm::{Geometry, Motion, State};
use std::path::PathBuf;

/// The body watch.
pub struct Watch {
    /// Impacts and samples.
    pub record: Record,
    /// Point snapshots for the plots, by file name (none for a reference run).
    pub snapshots: Option<Vec<(String, Snapshot)>>,
    /// The probes of the material checks.
    pub response: Response,
    /// The bonded interfaces (runs with bonds).
    pub debond: Option<Debond>,
    /// The sheared cell (`[shear]`).
    pub cell: Option<super::cell::Cell>,
    /// The bodies' shapes as filled.
    shapes: Vec<Geometry>,
    /// The scenario (its checks and shapes).
    scenario: Scenario,
    /// Where reference scenarios are read from.
    base: PathBuf,
    /// Exact initial energy and momentum of the free bodies' shapes.
    exact: (f64, DVec2),
    /// Measured initial (kinetic + strain) energy and momentum.
    initial: (f64, DVec2),
}

fn snapshot(s: &State, t: f64, strain: f64) -> Snapshot {
    let p = &s.particles;
    Snapshot {
        t,
        pos: p.pos.clone(),
        value: p.stress.iter().map(|x| x.principal_difference()).collect(),
        strain,
    }
}

/// Keeps in `list` the snapshot named `file` taken at the largest `strain` so far.
fn keep_peak(list: &mut Vec<(String, Snapshot)>, file: String, s: &State, strain: f64) {
    match list.iter_mut().find(|(f, _)| *f == file) {
        Some((_, snap)) if snap.strain >= strain => {}
        Some((_, snap)) => *snap = snapshot(s, s.time, strain),
        None => list.push((file, snapshot(s, s.time, strain))),
    }
}

impl Watch {
    /// The watch of `sim` for `scenario` (relative paths from `base`); `snapshots`: keep
    /// point snapshots for plots. `first` is the run's first sample.
    pub fn new(
        sim: &Mpm,
        a: &super::assemble::Assembled,
        scenario: &Scenario,
        base: PathBuf,
        first: &MpmSample,
        snapshots: bool,
    ) -> Self {
        let setup = &sim.setup;
        let exact = a
            .areas
            .iter()
            .zip(&a.velocities)
            .zip(&setup.bodies)
            .filter(|(_, b)| b.motion == Motion::Free)
            .fold((0.0, DVec2::ZERO), |(e, p), ((area, v), b)| {
                let m = setup.materials[b.material].density() * area;
                (e + 0.5 * m * v.length_squared(), p + m * *v)
            });
        let mut record = Record::new(setup.bodies.len());
        record.samples.push(first.sample.clone());
        let names: Vec<&str> = setup.bodies.iter().map(|b| b.name.as_str()).collect();
        let mut response = Response::new(&scenario.checks, &names, &a.geometry);
        response.sample(&sim.state, &sim.solver.layout().bodies);
        Watch {
            record,
            response,
            // A sheared cell reports its own debonding (against strain).
            debond: if scenario.shear.is_some() {
                None
            } else {
                Debond::new(sim, &scenario.checks, &a.geometry)
            },
            cell: scenario
                .shear
                .as_ref()
                .map(|spec| super::cell::Cell::new(sim, spec, &a.geometry)),
            shapes: a.geometry.clone(),
            snapshots: snapshots
                .then(|| vec![("points_initial.png".into(), snapshot(&sim.state, 0.0, 0.0))]),
            scenario: scenario.clone(),
            base,
            exact,
            initial: (
                first.diagnostics.kinetic + first.diagnostics.strain,
                first.diagnostics.momentum,
            ),
        }
    }

    fn figures(&self, sim: &Mpm) -> serde_json::Map<String, serde_json::Value> {
        let rec = &self.record;
        let mut figures = serde_json::Map::new();
        for (b, body) in sim.setup.bodies.iter().enumerate() {
            let list = &rec.impacts[b];
            if list.is_empty() {
                continue;
            }
            let impacts: Vec<serde_json::Value> = list
                .iter()
                .enumerate()
                .map(|(k, i)| {
                    serde_json::json!({
                        "number": k + 1,
                        "walls": (0..4).filter(|s| i.walls >> s & 1 == 1).map(|s| SIDES[s]).collect::<Vec<_>>(),
                        "start": i.start,
                        "end": i.end,
                        "energy_loss_after": rec.energy_loss(b, k + 1),
                        "momentum_after": rec.momentum_after(k + 1),
                        "normal_restitution": rec.bounce(b, k + 1).map(|x| x.restitution),
                        "tangential_momentum_change": rec.bounce(b, k + 1).map(|x| x.tangential_change),
                    })
                })
                .collect();
            figures.insert(format!("{}_impacts", body.name), impacts.into());
            figures.insert(
                format!("{}_rotation_deg_between_impacts", body.name),
                rec.rotation_per_window(b).into(),
            );
            let in_contact: f64 = list
                .iter()
                .map(|i| i.end.unwrap_or(sim.state.time) - i.start)
                .sum();
            figures.insert(
                format!("{}_wall_contact_fraction", body.name),
                (in_contact / sim.state.time.max(1e-300)).into(),
            );
        }
        figures.extend(self.response.figures(sim, &self.scenario.checks));
        if let Some(d) = &self.debond {
            figures.extend(d.figures());
        }
        if let Some(c) = &self.cell {
            figures.extend(c.figures());
        }
        let x = &sim.exchange;
        if sim.setup.multi_body() {
            figures.insert("contact_imbalance".into(), x.imbalance.length().into());
            figures.insert("contact_imbalance_steps".into(), x.imbalance_abs.into());
            figures.insert("boundary_impulse".into(), x.boundary_impulse.into());
        }
        if let Some(last) = rec.samples.last() {
            figures.insert("total_energy_final".into(), last.energy.into());
            if last.dissipated != 0.0 || last.thermal_work != 0.0 {
                figures.insert("dissipated_final".into(), last.dissipated.into());
                figures.insert("thermal_work_final".into(), last.thermal_work.into());
                let b0 = rec.samples[0].balance;
                figures.insert("energy_balance_drift".into(), (last.balance - b0).into());
            }
            for (b, body) in sim.setup.bodies.iter().enumerate() {
                figures.insert(
                    format!("{}_rotation_deg_total", body.name),
                    last.bodies[b].angle.to_degrees().into(),
                );
            }
        }
        figures
    }

    fn checks(&self, sim: &Mpm) -> anyhow::Result<Vec<Check>> {
        let rec = &self.record;
        let cx = Context {
            setup: &sim.setup,
            geometry: self.scenario.bodies.iter().map(|b| &b.geometry).collect(),
            exact: self.exact,
            initial: self.initial,
        };
        let mut checks = Vec::new();
        let specs = &self.scenario.checks;
        for (k, (spec, c)) in specs
            .iter()
            .zip(probes::checks(rec, &cx, specs))
            .enumerate()
        {
            let c = c
                .or_else(|| self.response.check(k, spec, sim, rec))
                .or_else(|| match (spec, &self.cell) {
                    (CheckSpec::ShearStrainReached { name, min }, Some(c)) => {
                        Some(c.strain_check(name, *min))
                    }
                    _ => None,
                })
                .or_else(|| {
                    let d = self.debond.as_ref()?;
                    d.check(spec, sim, &self.shapes, rec)
                });
            match (spec, c) {
                (_, Some(c)) => checks.push(c),
                (
                    CheckSpec::EnergyLossBelowReference {
                        name,
                        body,
                        after_impact,
                        reference,
                    },
                    None,
                ) => {
                    let b = sim
                        .setup
                        .bodies
                        .iter()
                        .position(|x| &x.name == body)
                        .expect("validated");
                    let mine = rec.energy_loss(b, *after_impact).abs();
                    let theirs = super::run::reference_loss(
                        &self.base.join(reference),
                        body,
                        *after_impact,
                    )?
                    .abs();
                    checks.push(Check::at_most(name, mine, theirs).with_note(&format!(
                        "|ΔE|/E0 after impact {after_impact} here vs in {reference} (expected = the reference's)"
                    )));
                }
                (spec, None) => {
                    checks.push(Check::at_most(spec.name(), f64::NAN, f64::NAN).with_note(
                        "nothing to measure: the run never reached what this check needs",
                    ))
                }
            }
        }
        Ok(checks)
    }
}

impl Observer<Mpm> for Watch {
    fn on_step(&mut self, sim: &Mpm) {
        self.record.step(
            sim.state.step,
            sim.state.time,
            sim.state.touch.iter().map(|t| t.walls),
        );
        if let Some(d) = self.debond.as_mut() {
            d.on_step(sim);
        }
    }

    fn on_sample(&mut self, sim: &Mpm, s: &MpmSample) -> anyhow::Result<Flow> {
        if let Some(list) = self.snapshots.as_mut() {
            let d = &s.diagnostics;
            // The moment of largest stored energy: where load paths show (Fig. 7).
            keep_peak(list, "points_peak_strain.png".into(), &sim.state, d.strain);
            for b in 0..sim.setup.bodies.len() {
                if self.record.in_impact(b) {
                    let file = format!(
                        "impact_{}_{}.png",
                        sim.setup.bodies[b].name,
                        self.record.impacts[b].len()
                    );
                    keep_peak(list, file, &sim.state, d.bodies[b].strain);
                }
            }
        }
        self.record.samples.push(s.sample.clone());
        if let Some(c) = self.cell.as_mut() {
            c.on_sample(sim, &s.sample);
        }
        self.response
            .sample(&sim.state, &sim.solver.layout().bodies);
        if let Some(d) = self.debond.as_mut() {
            d.on_sample(sim);
        }
        Ok(Flow::Continue)
    }

    fn on_frame(&mut self, sim: &Mpm, kind: FrameKind) -> anyhow::Result<()> {
        if let (Some(list), FrameKind::Snapshot) = (self.snapshots.as_mut(), kind) {
            let file = format!("points_{:.6e}s.png", sim.state.time);
            list.push((file, snapshot(&sim.state, sim.state.time, 0.0)));
        }
        Ok(())
    }

    fn on_end(&mut self, sim: &Mpm, _status: &Status, report: &mut Report) -> anyhow::Result<()> {
        if let Some(list) = self.snapshots.as_mut() {
            list.push((
                "points_final.png".into(),
                snapshot(&sim.state, sim.state.time, 0.0),
            ));
        }
        if let Some(d) = self.debond.as_mut() {
            d.on_end(sim);
        }
        if let Some(c) = self.cell.as_mut() {
            c.on_end(sim);
        }
        report.figures.extend(self.figures(sim));
        report.checks.extend(self.checks(sim)?);
        Ok(())
    }
}
