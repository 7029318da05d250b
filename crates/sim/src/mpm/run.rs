//! An MPM run from its scenario to its summary, and the silent run of a reference
//! scenario that a check compares with.

use super::assemble::{assemble, Assembled};
use super::scenario::{CheckSpec, Scenario};
use super::watch::Watch;
use super::{plots, Mpm, MpmSample, CAPABILITIES};
use crate::driver::{self, Counters, Observer, Plan, Silent};
use crate::frames::FrameRecorder;
use crate::history::{HistoryRecorder, Recorded};
use crate::run::{drive, finish, fresh_out, summary, Costs, Finished, RunError, RunOptions};
use crate::source::Source;
use std::path::Path;

impl Recorded for Mpm {
    fn columns(&self) -> Vec<String> {
        let mut c: Vec<String> = [
            "time",
            "step",
            "kinetic",
            "strain",
            "potential",
            "total",
            "momentum_x",
            "momentum_y",
            "max_speed",
        ]
        .map(String::from)
        .to_vec();
        for b in &self.setup.bodies {
            for s in [
                "x",
                "y",
                "vx",
                "vy",
                "omega",
                "rotation",
                "touch_wall",
                "touch_body",
            ] {
                c.push(format!("{}_{s}", b.name));
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
            d.momentum.x,
            d.momentum.y,
            d.max_speed,
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
                (t.walls != 0) as u8 as f64,
                (t.body_nodes > 0) as u8 as f64,
            ]);
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

/// Runs `s` (read from `src`) into `opts.out`.
pub fn run(s: &Scenario, src: &Source, mut opts: RunOptions) -> Result<Finished, RunError> {
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
    let e = super::check::cost(a.particles.len() as u64, nodes, a.steps, opts.threads);
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
    let outcome = {
        let mut observers: Vec<&mut dyn Observer<Mpm>> =
            vec![&mut history, &mut frames, &mut watch];
        drive(
            &mut sim,
            &mut observers,
            &plan,
            &mut opts,
            &src.text,
            Counters::fresh(&plan),
        )?
    };
    let pitch = sim.setup.grid.h * sim.setup.half_width;
    plots::write_all(
        &out.join("plots"),
        &history.history,
        &sim.setup,
        watch.snapshots.as_deref().unwrap_or_default(),
        pitch,
    )?;
    let mut counts = serde_json::Map::new();
    counts.insert("bodies".into(), sim.setup.bodies.len().into());
    let costs = Costs {
        dt: sim.dt,
        dt_critical: a.dt_critical,
        threads: opts.threads,
        frames: frames.count(),
    };
    let sum = summary(&s.name, "mpm", &sim, &outcome, costs, counts);
    finish(sum, outcome.status, &out)
}

/// A reference scenario's energy loss after impact `k` of body `body`, from a run
/// that writes nothing.
pub fn reference_loss(path: &Path, body: &str, k: usize) -> anyhow::Result<f64> {
    let src = Source::read(path).map_err(anyhow::Error::msg)?;
    let s: Scenario =
        grains_core::input::parse_toml(&src.text, &src.origin).map_err(anyhow::Error::msg)?;
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
