//! The run loop: step the engine, watch impacts every step, record history and frames,
//! stop on instability, then write checks, figures, plots and the summary.

use super::assemble::{self, Assembled};
use super::frames::FrameWriter;
use super::plots::{self, Snapshot};
use super::probes::{self, BodySample, Context, Record, Sample};
use super::scenario::{CheckSpec, Scenario};
use crate::progress::Progress;
use anyhow::Context as _;
use glam::DVec2;
use grains_core::atomic::write_atomic;
use grains_core::checks::Check;
use grains_core::history::History;
use grains_mpm::diagnostics::{measure, Diagnostics};
use grains_mpm::{step, Motion, Setup, Solver, State};
use serde::Serialize;
use std::path::Path;
use std::time::Instant;

/// What the caller needs to decide the exit code.
pub struct Outcome {
    /// The diagnostic, when the run stopped on a bad state.
    pub unstable: Option<String>,
    /// Checks with their verdicts.
    pub checks: Vec<Check>,
}

/// Everything summary.json holds.
#[derive(Serialize)]
struct Summary {
    name: String,
    engine: &'static str,
    status: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    message: Option<String>,
    particles: usize,
    bodies: usize,
    steps: u64,
    time: f64,
    dt: f64,
    dt_critical: f64,
    threads: usize,
    wall_time_s: f64,
    particle_steps_per_s: f64,
    frames: usize,
    figures: serde_json::Map<String, serde_json::Value>,
    checks: Vec<Check>,
}

/// Outputs a full run writes; a reference run has none.
struct Sink {
    history: History,
    frames: FrameWriter,
    snapshots: Vec<(String, Snapshot)>,
    frame_every: u64,
    last_frame: u64,
}

/// What a simulation leaves behind.
pub struct Simulated {
    /// Impacts and samples.
    pub record: Record,
    /// Final state.
    pub state: State,
    /// Why it stopped early, if it did.
    pub unstable: Option<String>,
    /// Wall-clock seconds of the time loop.
    pub seconds: f64,
    /// Measured energy and momentum at t = 0.
    pub initial: (f64, DVec2),
}

fn columns(setup: &Setup) -> Vec<String> {
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
    for b in &setup.bodies {
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

/// Unwraps each body's rotation against the previous sample.
fn sample(d: &Diagnostics, t: f64, prev: Option<&Sample>) -> Sample {
    let bodies = d
        .bodies
        .iter()
        .enumerate()
        .map(|(b, x)| {
            let angle = match prev {
                Some(p) => {
                    let last = p.bodies[b].angle;
                    let mut da = x.angle - last.rem_euclid(std::f64::consts::TAU);
                    da -= (da / std::f64::consts::TAU).round() * std::f64::consts::TAU;
                    last + da
                }
                None => x.angle,
            };
            BodySample {
                centre: x.centre,
                velocity: x.velocity,
                omega: x.omega,
                angle,
            }
        })
        .collect();
    Sample {
        t,
        energy: d.total(),
        momentum: d.momentum,
        bodies,
    }
}

fn row(s: &State, d: &Diagnostics, smp: &Sample) -> Vec<f64> {
    let mut r = vec![
        s.time,
        s.step as f64,
        d.kinetic,
        d.strain,
        d.potential,
        d.total(),
        d.momentum.x,
        d.momentum.y,
        d.max_speed,
    ];
    for (b, x) in smp.bodies.iter().enumerate() {
        let t = s.touch[b];
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

fn instability(setup: &Setup, d: &Diagnostics) -> Option<String> {
    if !d.finite {
        return Some("a position, velocity or stress is not finite (NaN or infinity)".into());
    }
    let c = setup
        .bodies
        .iter()
        .filter(|b| b.motion == Motion::Free)
        .map(|b| setup.materials[b.material].wave_speed())
        .fold(0.0, f64::max);
    let cfl = (c + d.max_speed) * setup.dt / setup.grid.h;
    (cfl > 1.0).then(|| {
        format!(
            "CFL breach: (c + |v|max)·Δt/h = {cfl:.3} > 1 with |v|max = {:.4e} m/s; lower run.dt or run.safety",
            d.max_speed
        )
    })
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

/// Runs `steps` steps, feeding `sink` if given.
fn simulate(
    asm: &Assembled,
    history_rows: u64,
    mut sink: Option<&mut Sink>,
) -> anyhow::Result<Simulated> {
    let setup = &asm.setup;
    let mut state = State {
        particles: asm.particles.clone(),
        ..Default::default()
    };
    let mut solver = Solver::new(setup, &mut state);
    let mut rec = Record::new(setup.bodies.len());
    let every = (asm.steps / history_rows.max(1)).max(1);
    let d0 = measure(setup, &state.particles, &solver.layout().bodies);
    let initial = (d0.kinetic + d0.strain, d0.momentum);
    let s0 = sample(&d0, 0.0, None);
    if let Some(k) = sink.as_deref_mut() {
        k.history.push(&row(&state, &d0, &s0))?;
        k.frames.write(setup, &state, &solver)?;
        k.snapshots
            .push(("points_initial.png".into(), snapshot(&state, 0.0, 0.0)));
    }
    rec.samples.push(s0);
    let mut progress = sink.is_some().then(|| Progress::new(asm.steps));
    let started = Instant::now();
    let mut unstable = None;
    // The loop runs on a pool worker, so each stage's parallel passes start without
    // waking the pool from outside.
    rayon::scope(|_| -> anyhow::Result<()> {
        while state.step < asm.steps {
            if let Err(e) = step(setup, &mut state, &mut solver) {
                unstable = Some(format!(
                    "step {} (t = {:.6e} s): {e}",
                    state.step, state.time
                ));
                break;
            }
            rec.step(state.step, state.time, state.touch.iter().map(|t| t.walls));
            if state.step.is_multiple_of(every) || state.step == asm.steps {
                let d = measure(setup, &state.particles, &solver.layout().bodies);
                if let Some(why) = instability(setup, &d) {
                    unstable = Some(format!(
                        "step {} (t = {:.6e} s): {why}",
                        state.step, state.time
                    ));
                    break;
                }
                let smp = sample(&d, state.time, rec.samples.last());
                if let Some(k) = sink.as_deref_mut() {
                    k.history.push(&row(&state, &d, &smp))?;
                    // The moment of largest stored energy: where load paths show (Fig. 7).
                    let file = "points_peak_strain.png";
                    match k.snapshots.iter_mut().find(|(f, _)| f == file) {
                        Some((_, snap)) if snap.strain >= d.strain => {}
                        Some((_, snap)) => *snap = snapshot(&state, state.time, d.strain),
                        None => k
                            .snapshots
                            .push((file.into(), snapshot(&state, state.time, d.strain))),
                    }
                    for b in 0..setup.bodies.len() {
                        if !rec.in_impact(b) {
                            continue;
                        }
                        let file = format!(
                            "impact_{}_{}.png",
                            setup.bodies[b].name,
                            rec.impacts[b].len()
                        );
                        let strain = d.bodies[b].strain;
                        match k.snapshots.iter_mut().find(|(f, _)| *f == file) {
                            Some((_, snap)) if snap.strain >= strain => {}
                            Some((_, snap)) => *snap = snapshot(&state, state.time, strain),
                            None => k
                                .snapshots
                                .push((file, snapshot(&state, state.time, strain))),
                        }
                    }
                }
                rec.samples.push(smp);
            }
            if let Some(k) = sink.as_deref_mut() {
                if state.step.is_multiple_of(k.frame_every) {
                    k.frames.write(setup, &state, &solver)?;
                    k.last_frame = state.step;
                }
            }
            if let Some(p) = progress.as_mut() {
                p.tick(state.step);
            }
        }
        Ok(())
    })?;
    let seconds = started.elapsed().as_secs_f64();
    if let Some(p) = progress {
        p.finish();
    }
    if let Some(k) = sink {
        k.history.flush()?;
        if unstable.is_none() && k.last_frame != state.step {
            k.frames.write(setup, &state, &solver)?;
        }
        k.snapshots
            .push(("points_final.png".into(), snapshot(&state, state.time, 0.0)));
    }
    Ok(Simulated {
        record: rec,
        state,
        unstable,
        seconds,
        initial,
    })
}

/// A reference scenario's energy loss after impact `k` of body `body`.
pub fn reference_loss(path: &Path, body: &str, k: usize) -> anyhow::Result<f64> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("cannot read reference {}", path.display()))?;
    let scn =
        super::scenario::parse(&text, &path.display().to_string()).map_err(anyhow::Error::msg)?;
    let asm = assemble::assemble(&scn).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    let b = asm
        .setup
        .bodies
        .iter()
        .position(|x| x.name == body)
        .ok_or_else(|| anyhow::anyhow!("{}: no body \"{body}\"", path.display()))?;
    let sim = simulate(&asm, scn.output.history, None)?;
    Ok(sim.record.energy_loss(b, k))
}

/// Runs an assembled scenario, writing every output into `out`.
pub fn run(
    scenario: &Scenario,
    text: &str,
    base: &Path,
    asm: Assembled,
    out: &Path,
    threads: usize,
) -> anyhow::Result<Outcome> {
    std::fs::create_dir_all(out)
        .with_context(|| format!("cannot create output directory {}", out.display()))?;
    write_atomic(&out.join("scenario.toml"), text.as_bytes())?;
    let setup = &asm.setup;
    let cols = columns(setup);
    let cols: Vec<&str> = cols.iter().map(String::as_str).collect();
    let mut sink = Sink {
        history: History::create(&out.join("history.csv"), &cols)?,
        frames: FrameWriter::create(out, scenario.output.grid_frames)?,
        snapshots: Vec::new(),
        frame_every: (asm.steps / scenario.output.frames.max(1)).max(1),
        last_frame: 0,
    };
    let sim = simulate(&asm, scenario.output.history, Some(&mut sink))?;
    let rec = &sim.record;

    let exact = asm
        .areas
        .iter()
        .zip(&asm.velocities)
        .zip(&setup.bodies)
        .filter(|(_, b)| b.motion == Motion::Free)
        .fold((0.0, DVec2::ZERO), |(e, p), ((a, v), b)| {
            let m = setup.materials[b.material].density() * a;
            (e + 0.5 * m * v.length_squared(), p + m * *v)
        });
    let cx = Context {
        setup,
        geometry: scenario.bodies.iter().map(|b| &b.geometry).collect(),
        exact,
        initial: sim.initial,
    };
    let mut checks = Vec::new();
    for (spec, c) in scenario
        .checks
        .iter()
        .zip(probes::checks(rec, &cx, &scenario.checks))
    {
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
                let b = setup
                    .bodies
                    .iter()
                    .position(|x| &x.name == body)
                    .expect("validated");
                let mine = rec.energy_loss(b, *after_impact);
                let theirs = reference_loss(&base.join(reference), body, *after_impact)?;
                checks.push(Check::at_most(name, mine, theirs).with_note(&format!(
                    "energy loss after impact {after_impact} here vs in {reference} (expected = the reference's loss)"
                )));
            }
            _ => {}
        }
    }

    let mut figures = serde_json::Map::new();
    for (b, body) in setup.bodies.iter().enumerate() {
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
                    "walls": (0..4).filter(|s| i.walls >> s & 1 == 1).map(|s| grains_mpm::setup::SIDES[s]).collect::<Vec<_>>(),
                    "start": i.start,
                    "end": i.end,
                    "energy_loss_after": rec.energy_loss(b, k + 1),
                    "momentum_after": rec.momentum_after(k + 1),
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
    if let Some(last) = rec.samples.last() {
        figures.insert("total_energy_final".into(), last.energy.into());
        for (b, body) in setup.bodies.iter().enumerate() {
            figures.insert(
                format!("{}_rotation_deg_total", body.name),
                last.bodies[b].angle.to_degrees().into(),
            );
        }
    }
    let pitch = setup.grid.h * setup.half_width;
    plots::write_all(
        &out.join("plots"),
        &sink.history,
        setup,
        rec,
        &sink.snapshots,
        pitch,
    )?;
    let n = sim.state.particles.len();
    let sum = Summary {
        name: scenario.name.clone(),
        engine: "mpm",
        status: if sim.unstable.is_some() {
            "unstable"
        } else {
            "completed"
        }
        .into(),
        message: sim.unstable.clone(),
        particles: n,
        bodies: setup.bodies.len(),
        steps: sim.state.step,
        time: sim.state.time,
        dt: setup.dt,
        dt_critical: asm.dt_critical,
        threads,
        wall_time_s: sim.seconds,
        particle_steps_per_s: n as f64 * sim.state.step as f64 / sim.seconds.max(1e-12),
        frames: sink.frames.count(),
        figures,
        checks: checks.clone(),
    };
    write_atomic(
        &out.join("summary.json"),
        serde_json::to_string_pretty(&sum)?.as_bytes(),
    )?;
    Ok(Outcome {
        unstable: sim.unstable,
        checks,
    })
}
