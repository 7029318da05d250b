//! The 3D scenario's checks: collisions (the watch both dimensions share,
//! [`crate::collision`]), the load on a wall, drums, silos, pours and collapses.
//!
//! Every probe reads the spheres through [`Dem3::watched`], in ascending id: the few
//! a collision watches after every step, every sphere at the samples a drum, a silo
//! or a column takes and at the end. So a probe's figures are the same bits on any
//! rank count, and on several ranks every rank keeps the probes (they see the same
//! spheres) and reaches the same checks.

use super::collapse::{lube, Deposit, RunoutWatch};
use super::deposit;
use super::drum::DrumWatch;
use super::scenario::CheckSpec;
use super::silo::{beverloo, orifice, DischargeWatch};
use super::Dem3;
use crate::collision::dim3::Watch;
use crate::driver::{Flow, Observer, Report, Status};
use glam::DVec3;
use grains_core::checks::Check;
use grains_dem3d::diagnostics::index_of;
use grains_dem3d::diagnostics::Diagnostics;
use grains_dem3d::{PairTable, Particles};
use serde::{Deserialize, Serialize};

/// What a checkpoint keeps of the probes, one list per check (empty for none).
#[derive(Serialize, Deserialize)]
struct Saved<I, D, S, C> {
    impacts: Vec<Vec<I>>,
    drums: Vec<Vec<D>>,
    silos: Vec<Vec<S>>,
    /// Absent from checkpoints written before columns were watched.
    #[serde(default = "Vec::new")]
    columns: Vec<Vec<C>>,
}

/// Watches the scenario's checks.
pub struct Probes {
    specs: Vec<CheckSpec>,
    impacts: Vec<Option<Watch>>,
    drums: Vec<Option<DrumWatch>>,
    silos: Vec<Option<DischargeWatch>>,
    columns: Vec<Option<RunoutWatch>>,
    restitution: PairTable<Option<f64>>,
}

impl Probes {
    /// The probes of `specs` (validated) in `sim`, with the restitution of each pair.
    pub fn new(sim: &Dem3, specs: &[CheckSpec], restitution: PairTable<Option<f64>>) -> Self {
        let impacts = specs
            .iter()
            .map(|c| match c {
                CheckSpec::Collision {
                    particle,
                    partner,
                    wall,
                    ..
                } => {
                    let at = (&sim.state.particles, sim.state.time);
                    Watch::of(&sim.setup, at, *particle, *partner, wall.as_deref())
                }
                _ => None,
            })
            .collect();
        let wall = |name: &str| sim.setup.walls.iter().position(|w| w.name == name);
        let drums = specs
            .iter()
            .map(|c| match c {
                CheckSpec::ReposeAngle { wall: w, after, .. }
                | CheckSpec::DrumTorque { wall: w, after, .. } => {
                    Some(DrumWatch::new(wall(w)?, *after))
                }
                _ => None,
            })
            .collect();
        let silos = specs
            .iter()
            .map(|c| match c {
                CheckSpec::Beverloo { wall: w, after, .. } => {
                    Some(DischargeWatch::new(wall(w)?, *after))
                }
                _ => None,
            })
            .collect();
        let columns = specs
            .iter()
            .map(|c| match c {
                CheckSpec::Runout { wall: w, .. } => {
                    let w = wall(w)?;
                    let (_, at) = sim.releases.iter().find(|(r, _)| *r == w)?;
                    Some(RunoutWatch::new(sim, w, *at))
                }
                _ => None,
            })
            .collect();
        Probes {
            specs: specs.to_vec(),
            impacts,
            drums,
            silos,
            columns,
            restitution,
        }
    }
}

/// The force of wall `wall` along gravity over the weight of the spheres `p`.
fn load_over_weight(sim: &Dem3, p: &Particles, wall: &str) -> f64 {
    let walls = &sim.setup.walls;
    let g = sim.setup.gravity;
    let mass: f64 = (0..p.len()).map(|i| p.mass(i)).sum();
    walls
        .iter()
        .zip(&sim.state.wall_loads)
        .find(|(w, _)| w.name == wall)
        .map_or(f64::NAN, |(_, load)| {
            load.force.dot(g) / (g.length_squared() * mass)
        })
}

impl Observer<Dem3> for Probes {
    fn on_step(&mut self, sim: &Dem3) {
        let ids: Vec<u32> = self.impacts.iter().flatten().flat_map(Watch::ids).collect();
        if ids.is_empty() {
            return;
        }
        let p = sim.watched(|id| ids.contains(&id));
        for w in self.impacts.iter_mut().flatten() {
            w.step(&sim.setup, &p, sim.state.time);
        }
    }

    fn on_sample(&mut self, sim: &Dem3, _d: &Diagnostics) -> anyhow::Result<Flow> {
        let t = sim.state.time;
        let wanted = self.drums.iter().flatten().any(|d| d.wants(t))
            || self.silos.iter().flatten().any(|d| d.wants(t))
            || self.columns.iter().flatten().any(|c| c.wants(t));
        if !wanted {
            return Ok(Flow::Continue);
        }
        let p = sim.watched(|_| true);
        for d in self.drums.iter_mut().flatten() {
            d.sample(sim, &p);
        }
        for d in self.silos.iter_mut().flatten() {
            d.sample(sim, &p);
        }
        for c in self.columns.iter_mut().flatten() {
            c.sample(sim, &p);
        }
        Ok(Flow::Continue)
    }

    /// The collisions, drums and silos watched so far (a checkpoint's TOML has no null:
    /// a slot without one is an empty list).
    fn save(&self) -> Option<(&'static str, toml::Value)> {
        fn slots<T>(v: &[Option<T>]) -> Vec<Vec<&T>> {
            v.iter().map(|s| s.iter().collect()).collect()
        }
        let saved = Saved {
            impacts: slots(&self.impacts),
            drums: slots(&self.drums),
            silos: slots(&self.silos),
            columns: slots(&self.columns),
        };
        toml::Value::try_from(saved).ok().map(|v| ("probes", v))
    }

    fn restore(&mut self, state: toml::Value) -> anyhow::Result<()> {
        let saved: Saved<Watch, DrumWatch, DischargeWatch, RunoutWatch> = state.try_into()?;
        fn slots<T>(
            what: &str,
            saved: Vec<Vec<T>>,
            now: &mut Vec<Option<T>>,
        ) -> anyhow::Result<()> {
            anyhow::ensure!(
                saved.len() == now.len(),
                "{} {what} checks saved, the scenario has {}",
                saved.len(),
                now.len()
            );
            *now = saved.into_iter().map(|s| s.into_iter().next()).collect();
            Ok(())
        }
        slots("collision", saved.impacts, &mut self.impacts)?;
        slots("drum", saved.drums, &mut self.drums)?;
        if !saved.columns.is_empty() {
            slots("runout", saved.columns, &mut self.columns)?;
        }
        slots("silo", saved.silos, &mut self.silos)
    }

    fn on_end(&mut self, sim: &Dem3, _status: &Status, report: &mut Report) -> anyhow::Result<()> {
        let d = sim.measured();
        let setup = &sim.setup;
        let whole = sim.watched(|_| true);
        let p = &whole;
        for (k, (spec, slot)) in self.specs.iter().zip(&self.impacts).enumerate() {
            let (name, tol) = (spec.name(), spec.tolerance().unwrap_or(0.0));
            let check = match (spec, slot) {
                (CheckSpec::Collision { measure, .. }, Some(w)) => {
                    w.check(name, *measure, tol, setup, p, &self.restitution)
                }
                (CheckSpec::WallForceOverWeight { wall, .. }, _) => {
                    Check::relative(name, load_over_weight(sim, p, wall), 1.0, tol)
                }
                (
                    CheckSpec::FinalVelocity {
                        particle,
                        direction,
                        expected,
                        ..
                    },
                    _,
                ) => {
                    let i = index_of(p, *particle).expect("ids stay");
                    let u = DVec3::from(*direction).normalize();
                    Check::relative(name, p.vel[i].dot(u), *expected, tol)
                }
                (CheckSpec::ReposeAngle { lo, hi, .. }, _) => {
                    let a = self.drums[k].as_ref().map_or(f64::NAN, |d| d.angle());
                    Check::absolute(name, a, 0.5 * (lo + hi), 0.5 * (hi - lo))
                }
                (CheckSpec::Beverloo { wall, packing, .. }, _) => {
                    let w = self.silos[k].as_ref();
                    let rate = w.map_or(f64::NAN, |w| w.rate());
                    let hole = setup.walls.iter().position(|x| &x.name == wall);
                    let d_hole = hole.and_then(|h| orifice(sim, h)).map_or(f64::NAN, |o| o.2);
                    let n = p.len().max(1) as f64;
                    let d = 2.0 * p.radius.iter().sum::<f64>() / n;
                    let volume: f64 = p
                        .radius
                        .iter()
                        .map(|&r| grains_dem3d::math::measure(r))
                        .sum();
                    let mass: f64 = (0..p.len()).map(|i| p.mass(i)).sum();
                    let rho_b = packing * mass / volume;
                    let g = setup.gravity.length();
                    let (lo, hi) = (
                        beverloo(0.55, 2.9, rho_b, g, d_hole, d),
                        beverloo(0.65, 1.3, rho_b, g, d_hole, d),
                    );
                    let c_fit = rate / beverloo(1.0, 1.5, rho_b, g, d_hole, d);
                    // Beside the check, which keeps the scenario's `packing`: the bed's
                    // measured packing and C at k = 1.5 with the bulk density it gives.
                    let measured = w.map_or(f64::NAN, DischargeWatch::packing);
                    let rho_measured = measured * mass / volume;
                    let c_measured = rate / beverloo(1.0, 1.5, rho_measured, g, d_hole, d);
                    for (key, v) in [
                        ("rate_kg_s", rate),
                        ("orifice_m", d_hole),
                        ("mean_diameter_m", d),
                        ("bulk_density", rho_b),
                        ("c_at_k1.5", c_fit),
                        ("packing_measured", measured),
                        ("bulk_density_measured", rho_measured),
                        ("c_at_k1.5_measured", c_measured),
                    ] {
                        report.figures.insert(format!("{name}_{key}"), v.into());
                    }
                    Check::absolute(name, rate, 0.5 * (lo + hi), 0.5 * (hi - lo))
                }
                (CheckSpec::PouredMass { region, .. }, _) => {
                    let inside: f64 = (0..p.len())
                        .filter(|&i| super::assemble::fits(region, p.pos[i], 0.0))
                        .map(|i| p.mass(i))
                        .sum();
                    let total: f64 = (0..p.len()).map(|i| p.mass(i)).sum();
                    if let Some(pour) = &sim.pour {
                        report
                            .figures
                            .insert(format!("{name}_poured"), pour.inserted().into());
                        report.figures.insert(
                            format!("{name}_poured_mass_kg"),
                            pour.inserted_mass().into(),
                        );
                    }
                    report
                        .figures
                        .insert(format!("{name}_inside_kg"), inside.into());
                    Check::relative(name, inside, total, tol)
                }
                (CheckSpec::Runout { .. }, _) => {
                    let (r0, h0, d) = match &self.columns[k] {
                        Some(c) => (c.r0, c.h0, c.deposit(sim, p)),
                        None => (f64::NAN, f64::NAN, Deposit::NAN),
                    };
                    let a = h0 / r0;
                    for (key, v) in [
                        ("r0_m", r0),
                        ("h0_m", h0),
                        ("aspect_ratio", a),
                        ("r_inf_m", d.r99),
                        ("front_m", d.front),
                        ("lube", lube(a)),
                        // The deposit's edge beside the check, not in it (collapse.rs
                        // says why), with the coverage that sets it.
                        ("edge_m", d.edge),
                        ("edge_coverage", deposit::COVERED),
                        ("runout_edge", (d.edge - r0) / r0),
                    ] {
                        report.figures.insert(format!("{name}_{key}"), v.into());
                    }
                    Check::relative(name, (d.r99 - r0) / r0, lube(a), tol)
                }
                (CheckSpec::DrumTorque { .. }, _) => {
                    let r = self.drums[k]
                        .as_ref()
                        .map_or(f64::NAN, |d| d.torque_over_moment());
                    Check::relative(name, r, 1.0, tol)
                }
                (CheckSpec::EnergyClosure { max, .. }, _) => {
                    super::ledger::check(name, sim, &d, *max)
                }
                (CheckSpec::Collision { .. }, None) => Check::relative(name, f64::NAN, 1.0, tol)
                    .with_note("the particle has no partner"),
            };
            report.checks.push(check);
        }
        Ok(())
    }
}
