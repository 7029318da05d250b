//! An MPM run from its scenario to its summary, and the silent run of a reference
//! scenario that a check compares with.

use super::assemble::{assemble, Assembled};
use super::scenario::{CheckSpec, Scenario};
use super::watch::Watch;
use super::{plots, Mpm, MpmSample, CAPABILITIES};
use crate::driver::{self, Counters, Observer, Outcome, Plan, Silent, Stepper};
use crate::frames::FrameRecorder;
use crate::history::{HistoryRecorder, Recorded};
use crate::run::{finish, fresh_out, summary, Costs, Finished, Live, RunError, RunOptions};
use crate::source::Source;
use grains_core::history::History;
use grains_mpm::{Material, Setup};
use std::path::{Path, PathBuf};

/// A per-body history column beyond the kinematics, written only where it means
/// something.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Extra {
    /// The body's prescribed temperature.
    Temperature,
    /// Largest equivalent plastic strain (J2 bodies).
    PlasticMax,
    /// Energy dissipated (J2 and Maxwell bodies).
    Dissipated,
    /// Debonded length of its interfaces (bonded bodies).
    DebondedLength,
    /// Its perimeter as the grid sees it (bonded bodies).
    SurfaceLength,
    /// Mean force it exerted on the material since the last row, x and y (rigid bodies).
    ForceX,
    /// The y component.
    ForceY,
    /// Work it did on the material so far (rigid bodies).
    Work,
}

impl Extra {
    const ALL: [(Extra, &'static str); 8] = [
        (Extra::Temperature, "temperature"),
        (Extra::PlasticMax, "plastic_max"),
        (Extra::Dissipated, "dissipated"),
        (Extra::DebondedLength, "debonded_length"),
        (Extra::SurfaceLength, "surface_length"),
        (Extra::ForceX, "force_x"),
        (Extra::ForceY, "force_y"),
        (Extra::Work, "work"),
    ];

    fn applies(self, setup: &Setup, b: usize) -> bool {
        let body = &setup.bodies[b];
        let m = &setup.materials[body.material];
        match self {
            Extra::Temperature => body.temperature.is_some(),
            Extra::PlasticMax => matches!(m, Material::J2Plastic { .. }),
            Extra::Dissipated => matches!(m, Material::J2Plastic { .. } | Material::Maxwell { .. }),
            Extra::DebondedLength | Extra::SurfaceLength => setup.contact.bond_of(b) > 0.0,
            Extra::ForceX | Extra::ForceY | Extra::Work => {
                body.motion != grains_mpm::Motion::Free && setup.multi_body()
            }
        }
    }

    /// The extras of body `b`, with their column suffixes.
    fn of(setup: &Setup, b: usize) -> impl Iterator<Item = (Extra, &'static str)> + '_ {
        Self::ALL
            .into_iter()
            .filter(move |(e, _)| e.applies(setup, b))
    }
}

impl Recorded for Mpm {
    fn columns(&self) -> Vec<String> {
        let mut c: Vec<String> = [
            "time",
            "step",
            "kinetic",
            "strain",
            "potential",
            "total",
            "dissipated",
            "thermal_work",
            "balance",
            "momentum_x",
            "momentum_y",
            "max_speed",
            "plastic",
            "viscous",
            "friction",
            "bond_loss",
            "transfer_loss",
            "boundary_work",
            "ledger",
            "imbalance_x",
            "imbalance_y",
            "boundary_impulse",
        ]
        .map(String::from)
        .to_vec();
        for (b, body) in self.setup.bodies.iter().enumerate() {
            for s in [
                "x",
                "y",
                "vx",
                "vy",
                "omega",
                "rotation",
                "mean_stress",
                "touch_wall",
                "touch_body",
            ] {
                c.push(format!("{}_{s}", body.name));
            }
            for (_, s) in Extra::of(&self.setup, b) {
                c.push(format!("{}_{s}", body.name));
            }
        }
        c
    }

    fn integer_columns(&self) -> Vec<String> {
        let mut c = vec!["step".to_string()];
        for b in &self.setup.bodies {
            c.push(format!("{}_touch_wall", b.name));
            c.push(format!("{}_touch_body", b.name));
        }
        c
    }

    fn row(&self, s: &MpmSample) -> Vec<f64> {
        let d = &s.diagnostics;
        let mut r = vec![
            self.state.time,
            self.state.step as f64,
            d.kinetic,
            d.strain,
            d.potential,
            d.total(),
            d.dissipated,
            d.thermal_work,
            d.balance(),
            d.momentum.x,
            d.momentum.y,
            d.max_speed,
            s.sample.plastic,
            s.sample.viscous,
            s.sample.friction,
            s.sample.bond,
            s.sample.transfer,
            s.sample.work,
            s.sample.ledger(),
            self.exchange.imbalance.x,
            self.exchange.imbalance.y,
            self.exchange.boundary_impulse,
        ];
        for (b, x) in s.sample.bodies.iter().enumerate() {
            let t = self.state.touch.get(b).copied().unwrap_or_default();
            r.extend([
                x.centre.x,
                x.centre.y,
                x.velocity.x,
                x.velocity.y,
                x.omega,
                x.angle,
                x.mean_stress,
                (t.walls != 0) as u8 as f64,
                (t.body_nodes > 0) as u8 as f64,
            ]);
            let body = &self.setup.bodies[b];
            for (e, _) in Extra::of(&self.setup, b) {
                r.push(match e {
                    Extra::Temperature => body
                        .temperature
                        .as_ref()
                        .map_or(f64::NAN, |h| h.at(self.state.time)),
                    Extra::PlasticMax => d.bodies[b].plastic_max,
                    Extra::Dissipated => d.bodies[b].dissipated,
                    Extra::DebondedLength => d.bodies[b].lengths.debonded,
                    Extra::SurfaceLength => d.bodies[b].lengths.surface,
                    Extra::ForceX => x.force.x,
                    Extra::ForceY => x.force.y,
                    Extra::Work => self.exchange.work_by[b],
                });
            }
        }
        r
    }
}

/// Parses, validates (including any reference scenario a check names) and assembles.
pub fn prepare(s: &Scenario, src: &Source) -> Result<Assembled, String> {
    let a = assemble(s).map_err(|e| format!("{}: {e}", src.origin))?;
    for (k, c) in s.checks.iter().enumerate() {
        if let CheckSpec::EnergyLossBelowReference {
            reference, body, ..
        } = c
        {
            let path = src.base.join(reference);
            let r = Source::read(&path).map_err(|e| {
                format!(
                    "{}: check[{k}].reference = \"{reference}\": cannot be read: {e}",
                    src.origin
                )
            })?;
            let rs: Scenario = grains_core::input::parse_toml(&r.text, &r.origin)?;
            let rs = super::packing::expanded(&rs, &r)?;
            let ra = assemble(&rs).map_err(|e| format!("{}: {e}", r.origin))?;
            if !ra.setup.bodies.iter().any(|b| &b.name == body) {
                return Err(format!(
                    "{}: check[{k}].body = \"{body}\": the reference has no such body",
                    src.origin
                ));
            }
        }
    }
    Ok(a)
}

/// An MPM run in progress: the simulation, the loop and every observer of `grains run`,
/// writing into its output directory as it goes.
pub struct MpmRun {
    /// The simulation.
    pub sim: Mpm,
    stepper: Stepper,
    history: HistoryRecorder,
    frames: FrameRecorder,
    watch: Watch,
    scenario: Scenario,
    geometry: Vec<grains_mpm::Geometry>,
    dt_critical: f64,
    out: PathBuf,
}

/// Prepares the run of `s` (read from `src`) into `opts.out`: assembled, its output
/// directory started, its first frame written.
pub fn open(s: &Scenario, src: &Source, opts: &mut RunOptions) -> Result<MpmRun, RunError> {
    let s = &super::packing::expanded(s, src).map_err(RunError::Input)?;
    super::check::fits(s, src, opts.threads).map_err(RunError::Input)?;
    let a = prepare(s, src).map_err(RunError::Input)?;
    let out = opts.out.clone();
    opts.progress.announce(&format!(
        "{} (mpm) — {} points in {} bodies, {}×{} cells, dt = {:.3e} s, {} steps, {} threads → {}",
        s.name,
        a.particles.len(),
        a.setup.bodies.len(),
        a.setup.grid.cells[0],
        a.setup.grid.cells[1],
        a.dt,
        a.steps,
        opts.threads,
        out.display()
    ));
    let nodes = (a.setup.grid.stored()[0] * a.setup.grid.stored()[1]) as u64;
    let branches = a.setup.branch_width() as u64;
    let e = super::check::cost(
        a.particles.len() as u64,
        nodes,
        branches,
        a.steps,
        opts.threads,
    );
    if let Some(w) = e.warning() {
        opts.progress.announce(&format!("warning: {w}"));
    }
    fresh_out(&out, &src.text)?;
    let mut sim = Mpm::new(&a, s.output.grid_frames.unwrap_or(true));
    let mut history = HistoryRecorder::create(&out, &mut sim)?;
    let first = sim
        .last_sample()
        .expect("the history took the first sample");
    let mut frames = FrameRecorder::create(&out, &sim).map_err(anyhow::Error::from)?;
    let mut watch = Watch::new(&sim, &a, s, src.base.clone(), &first, true);
    let plan = s.output.plan_by_steps(&CAPABILITIES, a.steps);
    let stepper = {
        let mut observers: Vec<&mut dyn Observer<Mpm>> =
            vec![&mut history, &mut frames, &mut watch];
        Stepper::start(&sim, &mut observers, plan.clone(), Counters::fresh(&plan))?
    };
    Ok(MpmRun {
        sim,
        stepper,
        history,
        frames,
        watch,
        scenario: s.clone(),
        geometry: a.geometry.clone(),
        dt_critical: a.dt_critical,
        out,
    })
}

impl Live for MpmRun {
    type S = Mpm;

    fn parts(&mut self) -> (&mut Mpm, &mut Stepper, Vec<&mut dyn Observer<Mpm>>) {
        (
            &mut self.sim,
            &mut self.stepper,
            vec![&mut self.history, &mut self.frames, &mut self.watch],
        )
    }

    fn history(&self) -> &History {
        &self.history.history
    }

    fn conclude(&mut self, outcome: Outcome, threads: usize) -> Result<Finished, RunError> {
        let (sim, s, watch, out) = (&self.sim, &self.scenario, &self.watch, &self.out);
        let pitch = sim.setup.grid.h * sim.setup.half_width;
        let dir = out.join("plots");
        plots::write_all(
            &dir,
            &self.history.history,
            &sim.setup,
            watch.snapshots.as_deref().unwrap_or_default(),
            pitch,
        )?;
        plots::write_curves(&dir, &watch.response.curves(sim, &s.checks))?;
        if let Some(d) = &watch.debond {
            plots::write_curves(&dir, &d.curves(sim, &watch.record))?;
            plots::bond_maps(&dir, &d.snapshots, &self.geometry, pitch)?;
        }
        if let Some(c) = &watch.cell {
            plots::write_curves(&dir, &c.curves(&watch.record.samples))?;
            plots::maps(&dir, &c.maps, pitch)?;
        }
        let mut counts = serde_json::Map::new();
        counts.insert("bodies".into(), sim.setup.bodies.len().into());
        let costs = Costs {
            dt: sim.dt,
            dt_critical: self.dt_critical,
            threads,
            frames: self.frames.count(),
        };
        let sum = summary(&s.name, "mpm", sim, &outcome, costs, counts);
        finish(sum, outcome.status, out)
    }
}

/// A reference scenario's energy loss after impact `k` of body `body`, from a run
/// that writes nothing.
pub fn reference_loss(path: &Path, body: &str, k: usize) -> anyhow::Result<f64> {
    let src = Source::read(path).map_err(anyhow::Error::msg)?;
    let s: Scenario =
        grains_core::input::parse_toml(&src.text, &src.origin).map_err(anyhow::Error::msg)?;
    let s = super::packing::expanded(&s, &src).map_err(anyhow::Error::msg)?;
    let a = assemble(&s).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    let b = a
        .setup
        .bodies
        .iter()
        .position(|x| x.name == body)
        .ok_or_else(|| anyhow::anyhow!("{}: no body \"{body}\"", path.display()))?;
    let mut sim = Mpm::new(&a, false);
    let first = driver::Simulation::sample(&mut sim);
    let mut watch = Watch::new(&sim, &a, &s, src.base.clone(), &first, false);
    let plan = Plan {
        snapshots: Vec::new(),
        ..s.output.plan_by_steps(&CAPABILITIES, a.steps)
    };
    let mut control = driver::Control {
        stop_at_step: None,
        interrupt: None,
        progress: &mut Silent,
        checkpoint_dir: None,
        scenario_text: &src.text,
        scenario_base: None,
    };
    let mut observers: Vec<&mut dyn Observer<Mpm>> = vec![&mut watch];
    driver::run(
        &mut sim,
        &mut observers,
        &plan,
        &mut control,
        Counters::fresh(&plan),
    )?;
    Ok(watch.record.energy_loss(b, k))
}
