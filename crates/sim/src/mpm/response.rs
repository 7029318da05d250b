//! The material response a run is judged by: per sample, the mean shear stress and
//! shear strain of a body's points in a region (simple shear, relaxation) or the mean
//! in-plane stress of a disk's core (concentric cylinders); at the end, a heated body's
//! strain and stresses; over the run, the energy ledger. Each against its closed form
//! ([`super::reference`]).

use super::concentric::Concentric;
use super::plots::Curves;
use super::probes::Record;
use super::reference::{hardening_slope, line_fit, plane_strain_thermal, shear_yield, young};
use super::scenario::{CheckSpec, Region};
use super::Mpm;
use glam::DVec2;
use grains_core::checks::Check;
use grains_mpm::{Geometry, Material, State};

/// Which of a body's points a probe averages.
#[derive(Clone, Copy, Debug)]
enum Select {
    /// Those inside a rectangle.
    Region(Region),
    /// Those within `radius` of `centre`.
    Core { centre: DVec2, radius: f64 },
}

impl Select {
    fn keeps(&self, x: DVec2) -> bool {
        match *self {
            Select::Region(r) => r.contains(x),
            Select::Core { centre, radius } => (x - centre).length() < radius,
        }
    }
}

/// One sample of a probe.
#[derive(Clone, Copy, Debug, Default)]
pub struct Row {
    /// Time (s).
    pub t: f64,
    /// Mean σ_xy (Pa).
    pub shear: f64,
    /// Mean F_xy (the shear strain γ of simple shear).
    pub gamma: f64,
    /// Mean (σ_xx + σ_yy)/2 (Pa).
    pub mean: f64,
}

/// The points of one body a check follows, and what it saw.
#[derive(Clone, Debug)]
pub struct Probe {
    body: usize,
    select: Select,
    /// The concentric pair, for the interface stress.
    pair: Option<Concentric>,
    /// One row per sample.
    pub rows: Vec<Row>,
}

impl Probe {
    fn sample(&mut self, s: &State, range: (usize, usize)) {
        let p = &s.particles;
        let (mut n, mut row) = (0usize, Row::default());
        for i in range.0..range.1 {
            if self.select.keeps(p.pos[i]) {
                n += 1;
                row.shear += p.stress[i].xy;
                row.gamma += p.def[i].y_axis.x;
                row.mean += 0.5 * (p.stress[i].xx + p.stress[i].yy);
            }
        }
        let k = 1.0 / n.max(1) as f64;
        self.rows.push(Row {
            t: s.time,
            shear: row.shear * k,
            gamma: row.gamma * k,
            mean: if n == 0 { f64::NAN } else { row.mean * k },
        });
    }
}

/// The probes of a run's checks, by check index (`None` for checks without one).
#[derive(Clone, Debug, Default)]
pub struct Response {
    /// Per check.
    pub probes: Vec<Option<Probe>>,
}

impl Response {
    /// The probes `specs` need (body indices by name; `shapes`: the bodies' shapes).
    pub fn new(specs: &[CheckSpec], names: &[&str], shapes: &[Geometry]) -> Self {
        let index = |b: &str| names.iter().position(|n| *n == b).expect("validated");
        let probes = specs
            .iter()
            .map(|c| {
                let (body, select, pair) = match c {
                    CheckSpec::ShearStressPlateau { body, region, .. }
                    | CheckSpec::HardeningSlope { body, region, .. }
                    | CheckSpec::RelaxationTime { body, region, .. } => {
                        (index(body), Select::Region(*region), None)
                    }
                    CheckSpec::InterfaceRadialStress {
                        inner, outer, core, ..
                    } => {
                        let pair = Concentric::new(shapes, index(inner), index(outer)).ok()?;
                        let select = Select::Core {
                            centre: pair.centre,
                            radius: core * pair.a,
                        };
                        (pair.inner, select, Some(pair))
                    }
                    _ => return None,
                };
                Some(Probe {
                    body,
                    select,
                    pair,
                    rows: Vec::new(),
                })
            })
            .collect();
        Response { probes }
    }

    /// Takes a sample of every probe.
    pub fn sample(&mut self, s: &State, ranges: &[(usize, usize)]) {
        for p in self.probes.iter_mut().flatten() {
            p.sample(s, ranges[p.body]);
        }
    }

    /// Figures for `summary.json`: the elastic shear modulus seen by each shear probe.
    pub fn figures(
        &self,
        sim: &Mpm,
        specs: &[CheckSpec],
    ) -> serde_json::Map<String, serde_json::Value> {
        let mut f = serde_json::Map::new();
        for (spec, p) in specs.iter().zip(&self.probes) {
            let (
                Some(p),
                CheckSpec::ShearStressPlateau { name, .. } | CheckSpec::HardeningSlope { name, .. },
            ) = (p, spec)
            else {
                continue;
            };
            let m = &sim.setup.materials[sim.setup.bodies[p.body].material];
            if let Material::J2Plastic {
                shear,
                yield_stress,
                ..
            } = m
            {
                let elastic: Vec<&Row> = p
                    .rows
                    .iter()
                    .filter(|r| r.gamma < 0.5 * shear_yield(*yield_stress) / shear)
                    .collect();
                let (g, _) = fit(&elastic, |r| r.gamma, |r| r.shear);
                f.insert(format!("{name}_elastic_shear_modulus"), g.into());
                if let Some(last) = p.rows.last() {
                    f.insert(format!("{name}_final_shear_stress"), last.shear.into());
                    f.insert(format!("{name}_final_shear_strain"), last.gamma.into());
                }
            }
        }
        f
    }

    /// The check `spec` (number `k`) if it is one of the response's.
    pub fn check(&self, k: usize, spec: &CheckSpec, sim: &Mpm, rec: &Record) -> Option<Check> {
        let setup = &sim.setup;
        let material = |b: usize| &setup.materials[setup.bodies[b].material];
        let probe = self.probes[k].as_ref();
        Some(match (spec, probe) {
            (
                CheckSpec::ShearStressPlateau {
                    name, tolerance, ..
                },
                Some(p),
            ) => {
                let Material::J2Plastic { yield_stress, .. } = material(p.body) else {
                    return None;
                };
                let tau = p.rows.last().map_or(f64::NAN, |r| r.shear);
                let gamma = p.rows.last().map_or(f64::NAN, |r| r.gamma);
                Check::relative(name, tau, shear_yield(*yield_stress), *tolerance).with_note(&format!(
                    "mean σ_xy of the region's points at the end (γ = {gamma:.4}) vs k = σ_y/√3 (von Mises, perfectly plastic)"
                ))
            }
            (
                CheckSpec::HardeningSlope {
                    name, tolerance, ..
                },
                Some(p),
            ) => {
                let Material::J2Plastic {
                    shear,
                    yield_stress,
                    hardening,
                    ..
                } = material(p.body)
                else {
                    return None;
                };
                let from = 3.0 * shear_yield(*yield_stress) / shear;
                let plastic: Vec<&Row> = p.rows.iter().filter(|r| r.gamma > from).collect();
                let (slope, _) = fit(&plastic, |r| r.gamma, |r| r.shear);
                Check::relative(name, slope, hardening_slope(*shear, *hardening), *tolerance)
                    .with_note(&format!(
                        "least-squares dτ/dγ over {} samples with γ > 3k/G = {from:.4} (τ, γ = mean σ_xy, F_xy of the region's points) vs G H/(H + 3G)",
                        plastic.len()
                    ))
            }
            (
                CheckSpec::RelaxationTime {
                    name,
                    after,
                    tolerance,
                    ..
                },
                Some(p),
            ) => {
                let Material::Maxwell { prony, .. } = material(p.body) else {
                    return None;
                };
                let held: Vec<&Row> = p
                    .rows
                    .iter()
                    .filter(|r| r.t >= *after && r.shear > 0.0)
                    .collect();
                let (slope, _) = fit(&held, |r| r.t, |r| r.shear.ln());
                Check::relative(name, -1.0 / slope, prony[0].time, *tolerance).with_note(&format!(
                    "fit of ln τ(t) = c − t/τ_fit over {} samples from t = {after} s (τ = mean σ_xy of the region's points, shear held) vs η/G = τ₁ of the one-term Prony series",
                    held.len()
                ))
            }
            (
                CheckSpec::InterfaceRadialStress {
                    name,
                    after,
                    core,
                    tolerance,
                    ..
                },
                Some(p),
            ) => {
                let pair = p.pair?;
                let late: Vec<&Row> = p.rows.iter().filter(|r| r.t >= *after).collect();
                let mean = late.iter().map(|r| r.mean).sum::<f64>() / late.len() as f64;
                let expected = pair.static_stress(setup, sim.state.time);
                Check::relative(name, mean, expected, *tolerance).with_note(&format!(
                    "mean (σ_xx + σ_yy)/2 of the inner points with r < {core}·a, averaged over {} samples from t = {after} s, vs the static plane-strain σ_rr(a) = −(ε₁ − ε₂)/[1/(2L₁) + (a²/(2L₂) + b²/(2G₂))/(b² − a²)], ε = (1 + ν) α ΔT, L = K + G/3, a = {}, b = {} (for equal moduli −2LGε(1 − a²/b²)/(L + G); physics.md §3.2)",
                    late.len(), pair.a, pair.b
                ))
            }
            (
                CheckSpec::ThermalStrain { body, .. }
                | CheckSpec::InPlaneStress { body, .. }
                | CheckSpec::OutOfPlaneStress { body, .. },
                _,
            ) => return heated_check(spec, sim, sim.body(body)),
            (CheckSpec::EnergyBalance { name, max }, _) => {
                let s = &rec.samples;
                let b0 = s.first().map_or(f64::NAN, |x| x.balance);
                let drift = s.iter().map(|x| (x.balance - b0).abs()).fold(0.0, f64::max);
                let scale = s
                    .iter()
                    .map(|x| x.thermal_work.abs().max(x.dissipated))
                    .fold(s.first().map_or(0.0, |x| x.energy.abs()), f64::max);
                Check::at_most(name, drift / scale, *max).with_note(
                    "largest |B(t) − B(0)|, B = kinetic + strain + potential + dissipated − thermal work, over the largest of the initial energy, the dissipated energy and |thermal work|: constant without rigid movers or wall friction",
                )
            }
            (CheckSpec::ContactMomentumImbalance { name, max }, _) => {
                let x = &sim.exchange;
                Check::at_most(name, x.imbalance.length() / x.boundary_impulse, *max).with_note(
                    "|Σ over steps of the momentum the free bodies' fields gave one another| over Σ over steps of |the momentum the rigid bodies gave them|",
                )
            }
            (CheckSpec::EnergyLedger { name, max }, _) => {
                let s = &rec.samples;
                let l0 = s.first().map_or(f64::NAN, |x| x.ledger());
                let drift = s
                    .iter()
                    .map(|x| (x.ledger() - l0).abs())
                    .fold(0.0, f64::max);
                let scale = s
                    .iter()
                    .map(|x| {
                        x.work
                            .abs()
                            .max(x.dissipated + x.friction + x.bond + x.transfer)
                    })
                    .fold(s.first().map_or(0.0, |x| x.energy.abs()), f64::max);
                Check::at_most(name, drift / scale, *max).with_note(
                    "largest |L(t) − L(0)|, L = kinetic + strain + potential + plastic + viscous + friction + bond + transfer − thermal work − boundary work, over the largest of the boundary work, the energy taken out and the initial energy",
                )
            }
            _ => return None,
        })
    }
}

impl Response {
    /// Plots of what each probe saw, with the closed form it is checked against.
    pub fn curves(&self, sim: &Mpm, specs: &[CheckSpec]) -> Vec<Curves> {
        let setup = &sim.setup;
        let mut out = Vec::new();
        for (spec, p) in specs.iter().zip(&self.probes) {
            let Some(p) = p else { continue };
            let body = &setup.bodies[p.body];
            let col = |f: fn(&Row) -> f64| p.rows.iter().map(f).collect::<Vec<f64>>();
            let (t, tau, gamma) = (col(|r| r.t), col(|r| r.shear), col(|r| r.gamma));
            match (spec, &setup.materials[body.material]) {
                (
                    CheckSpec::ShearStressPlateau { name, .. }
                    | CheckSpec::HardeningSlope { name, .. },
                    Material::J2Plastic {
                        shear,
                        yield_stress,
                        hardening,
                        ..
                    },
                ) => {
                    let k = shear_yield(*yield_stress);
                    let slope = hardening_slope(*shear, *hardening);
                    let bilinear: Vec<f64> = gamma
                        .iter()
                        .map(|g| (shear * g).min(k + slope * (g - k / shear)))
                        .collect();
                    out.push(Curves {
                        file: format!("{name}.png"),
                        title: format!("Simple shear of \"{}\": mean stress against strain in the probed region", body.name),
                        x_label: "shear strain γ = F_xy (−)".into(),
                        y_label: "shear stress σ_xy (Pa)".into(),
                        series: vec![
                            ("MPM".into(), gamma.clone(), tau),
                            ("G γ, then k + G H/(H + 3G)(γ − k/G), k = σ_y/√3".into(), gamma, bilinear),
                        ],
                        log_y: false,
                    });
                }
                (
                    CheckSpec::RelaxationTime { name, after, .. },
                    Material::Maxwell { prony, .. },
                ) => {
                    let Some(start) = p.rows.iter().find(|r| r.t >= *after) else {
                        continue;
                    };
                    let (late_t, exact): (Vec<f64>, Vec<f64>) = p
                        .rows
                        .iter()
                        .filter(|r| r.t >= *after)
                        .map(|r| (r.t, start.shear * (-(r.t - start.t) / prony[0].time).exp()))
                        .collect();
                    // From where the stress is a hundredth of its peak: the log axis
                    // would otherwise spend most of its decades on the loading's start.
                    let peak = tau.iter().copied().fold(0.0, f64::max);
                    let (t, tau): (Vec<f64>, Vec<f64>) = t
                        .iter()
                        .zip(&tau)
                        .filter(|(_, s)| **s > 1e-2 * peak)
                        .map(|(t, s)| (*t, *s))
                        .unzip();
                    out.push(Curves {
                        file: format!("{name}.png"),
                        title: format!("Stress relaxation of \"{}\" under held shear", body.name),
                        x_label: "time (s)".into(),
                        y_label: "shear stress σ_xy (Pa), log scale".into(),
                        series: vec![
                            ("MPM".into(), t, tau),
                            (
                                format!(
                                    "τ(t₀) exp(−(t − t₀)/τ₁), t₀ = {:.3} s, τ₁ = η/G = {} s",
                                    start.t, prony[0].time
                                ),
                                late_t,
                                exact,
                            ),
                        ],
                        log_y: true,
                    });
                }
                (CheckSpec::InterfaceRadialStress { name, core, .. }, _) => {
                    let Some(pair) = p.pair else { continue };
                    let exact: Vec<f64> = t.iter().map(|t| pair.static_stress(setup, *t)).collect();
                    out.push(Curves {
                        file: format!("{name}.png"),
                        title: "Concentric cylinders: stress in the inner disk against the static solution".into(),
                        x_label: "time (s)".into(),
                        y_label: "stress (Pa)".into(),
                        series: vec![
                            (format!("MPM: mean (σ_xx + σ_yy)/2, r < {core} a"), t.clone(), col(|r| r.mean)),
                            ("static σ_rr(a) at the current temperatures".into(), t, exact),
                        ],
                        log_y: false,
                    });
                }
                _ => {}
            }
        }
        out
    }
}

/// The checks of a body heated uniformly (number `b`): its strain, its in-plane stress
/// and its σ_zz at the end.
fn heated_check(spec: &CheckSpec, sim: &Mpm, b: usize) -> Option<Check> {
    let (bulk, shear, alpha_dt) = heated(sim, b);
    let p = &sim.state.particles;
    Some(match spec {
        CheckSpec::ThermalStrain {
            name, tolerance, ..
        } => {
            let strain = body_mean(sim, b, |i| 0.5 * p.def[i].determinant().ln());
            let nu = super::reference::poisson(bulk, shear);
            let free = plane_strain_thermal(bulk, shear, alpha_dt);
            Check::relative(name, strain, free, *tolerance).with_note(&format!(
                "mean ½ ln det F of the body's points at the end vs the plane-strain free strain (1 + ν) α ΔT (ν = {nu:.4}, α ΔT = {alpha_dt:.4e}): confined along z, the body expands in plane by (1 + ν) α ΔT, not α ΔT (the 3D or plane-stress value), and carries σ_zz = −E α ΔT"
            ))
        }
        CheckSpec::InPlaneStress { name, max, .. } => {
            let (start, end) = sim.solver.layout().bodies[b];
            let worst = (start..end)
                .map(|i| {
                    let s = p.stress[i];
                    s.xx.abs().max(s.yy.abs()).max(s.xy.abs())
                })
                .fold(0.0, f64::max);
            Check::at_most(name, worst / (bulk * alpha_dt.abs()), *max).with_note(
                "largest |σ_xx|, |σ_yy|, |σ_xy| of the body's points at the end over K α |ΔT|: a free body heated uniformly carries no in-plane stress",
            )
        }
        CheckSpec::OutOfPlaneStress {
            name, tolerance, ..
        } => {
            let zz = body_mean(sim, b, |i| p.stress[i].zz);
            Check::relative(name, zz, -young(bulk, shear) * alpha_dt, *tolerance).with_note(
                "mean σ_zz of the body's points at the end vs −E α ΔT (plane strain: the z direction is held)",
            )
        }
        _ => return None,
    })
}

/// (K, G, α ΔT over the run) of a heated body.
fn heated(sim: &Mpm, b: usize) -> (f64, f64, f64) {
    let body = &sim.setup.bodies[b];
    let m = &sim.setup.materials[body.material];
    let (bulk, shear) = m.moduli();
    let change = body
        .temperature
        .as_ref()
        .map_or(0.0, |h| h.at(sim.state.time) - h.at(0.0));
    (bulk, shear, m.expansion() * change)
}

/// Mean of `f` over body `b`'s points.
fn body_mean(sim: &Mpm, b: usize, f: impl Fn(usize) -> f64) -> f64 {
    let (start, end) = sim.solver.layout().bodies[b];
    (start..end).map(f).sum::<f64>() / (end - start).max(1) as f64
}

fn fit(rows: &[&Row], x: impl Fn(&Row) -> f64, y: impl Fn(&Row) -> f64) -> (f64, f64) {
    let xs: Vec<f64> = rows.iter().map(|r| x(r)).collect();
    let ys: Vec<f64> = rows.iter().map(|r| y(r)).collect();
    line_fit(&xs, &ys)
}
