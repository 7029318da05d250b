//! The run loop: step the engine, record history, write frames and checkpoints, stop at
//! rest, on instability, on request or on a signal, then write checks, figures, plots and
//! the summary. A run continued from a checkpoint goes on exactly as if never stopped.

use super::assemble::Assembled;
use super::checkpoint::{self, RunProgress};
use super::frames::FrameWriter;
use super::plots;
use super::probes::Probes;
use super::records::{figures, history_columns, history_row};
use super::scenario::Scenario;
use crate::progress::Progress;
use crate::{interrupt, summary};
use anyhow::Context;
use grains_core::atomic::write_atomic;
use grains_core::checks::Check;
use grains_core::history::{read_csv, History};
use grains_dem::diagnostics::{self, Diagnostics};
use grains_dem::{step, State};
use std::path::Path;
use std::time::Instant;

/// How a run ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Status {
    /// Ran for the whole duration.
    Completed,
    /// Stopped early because the kinetic energy fell below the threshold.
    AtRest,
    /// Stopped because the state went bad; the message says how.
    Unstable(String),
    /// Stopped at the requested step, with a checkpoint.
    Paused,
    /// Stopped by a signal (Ctrl-C, SIGTERM), with a checkpoint.
    Interrupted,
}

/// How the caller wants the run driven.
pub struct RunOptions {
    /// Worker threads in use (reported).
    pub threads: usize,
    /// Stop with a checkpoint once this step is reached.
    pub stop_at_step: Option<u64>,
    /// Continue from this checkpointed state instead of starting afresh.
    pub resume: Option<(State, RunProgress)>,
}

/// What the caller needs to decide the exit code.
pub struct Outcome {
    /// How it ended.
    pub status: Status,
    /// Checks with their verdicts (none for a paused or interrupted run).
    pub checks: Vec<Check>,
}

/// Overlap (relative to the smaller radius) beyond which a run is declared unstable.
const RUNAWAY_OVERLAP: f64 = 0.5;

/// Runs an assembled scenario, writing every output into `out`.
pub fn run(
    scenario: &Scenario,
    text: &str,
    asm: Assembled,
    out: &Path,
    opts: RunOptions,
) -> anyhow::Result<Outcome> {
    let Assembled {
        setup,
        particles,
        dt_critical,
        steps,
    } = asm;
    let columns = history_columns(&setup);
    let cols: Vec<&str> = columns.iter().map(String::as_str).collect();
    let history_every = (steps / scenario.output.history.max(1)).max(1);
    let frame_every = (steps / scenario.output.frames.max(1)).max(1);
    let checkpoint_every = scenario.output.checkpoint_every;
    let resumed = opts.resume.is_some();
    let (mut state, mut run) = match opts.resume {
        Some(v) => v,
        None => {
            std::fs::create_dir_all(out)
                .with_context(|| format!("cannot create output directory {}", out.display()))?;
            write_atomic(&out.join("scenario.toml"), text.as_bytes())?;
            let state = State::new(&setup, particles);
            let mut probes = Probes::new(&setup, &scenario.checks);
            probes.observe(&setup, &state);
            (
                state,
                RunProgress {
                    probes,
                    ..Default::default()
                },
            )
        }
    };
    let n = state.particles.len();
    let (mut history, mut frames) = if resumed {
        (
            reopen_history(out, &cols, state.step)?,
            FrameWriter::resume(
                out,
                &setup,
                state.time,
                run.frames,
                scenario.output.lammps_dump,
            )?,
        )
    } else {
        let mut h = History::create(&out.join("history.csv"), &cols)?;
        h.push(&history_row(
            &setup,
            &state,
            &diagnostics::measure(&setup, &state),
        ))?;
        let mut f = FrameWriter::create(out, &setup, scenario.output.lammps_dump)?;
        f.write(&setup, &state)?;
        run.frames = f.count();
        (h, f)
    };
    let rest_energy = scenario.run.stop_kinetic_ratio.map(|ratio| {
        let p = &state.particles;
        let mean_d = 2.0 * p.radius.iter().sum::<f64>() / n as f64;
        let weight: f64 = (0..n).map(|i| p.mass(i)).sum::<f64>() * setup.gravity.length();
        ratio * weight * mean_d
    });
    let rest_time = scenario
        .run
        .stop_rest_time
        .unwrap_or(20.0 * history_every as f64 * setup.dt);

    let mut progress = Progress::new(steps);
    let started = Instant::now();
    let first_step = state.step;
    let mut status = Status::Completed;
    // Stepping from inside the pool keeps each parallel pass from waking it from outside.
    rayon::scope(|_| -> anyhow::Result<()> {
        while state.step < steps {
            step(&setup, &mut state);
            run.probes.observe(&setup, &state);
            if state.step.is_multiple_of(history_every) || state.step == steps {
                let d = diagnostics::measure(&setup, &state);
                if let Some(why) = instability(&d) {
                    status = Status::Unstable(format!(
                        "step {} (t = {:.6e} s): {why}",
                        state.step, state.time
                    ));
                    return Ok(());
                }
                history.push(&history_row(&setup, &state, &d))?;
                if rest_energy.is_some_and(|limit| d.kinetic() < limit) {
                    let since = *run.rest_since.get_or_insert(state.time);
                    if state.time - since >= rest_time {
                        status = Status::AtRest;
                        return Ok(());
                    }
                } else {
                    run.rest_since = None;
                }
            }
            if state.step.is_multiple_of(frame_every) {
                frames.write(&setup, &state)?;
                run.last_frame_step = state.step;
                run.frames = frames.count();
            }
            progress.tick(state.step);
            let pause = opts.stop_at_step.is_some_and(|s| state.step >= s);
            let signal = interrupt::requested();
            if pause || signal || checkpoint_every.is_some_and(|k| state.step.is_multiple_of(k)) {
                history.flush()?;
                let mut saved = run.clone();
                saved.wall_time += started.elapsed().as_secs_f64();
                saved.steps_before += state.step - first_step;
                checkpoint::save(&out.join("checkpoint.bin"), text, &state, &saved)?;
                if pause || signal {
                    status = if signal {
                        Status::Interrupted
                    } else {
                        Status::Paused
                    };
                    return Ok(());
                }
            }
        }
        Ok(())
    })?;
    let wall = run.wall_time + started.elapsed().as_secs_f64();
    let stepped = run.steps_before + state.step - first_step;
    progress.finish();
    history.flush()?;
    let finished = matches!(status, Status::Completed | Status::AtRest);
    if finished && run.last_frame_step != state.step {
        frames.write(&setup, &state)?;
    }
    let checks = if finished {
        run.probes.checks(&setup, &state, &scenario.checks)
    } else {
        Vec::new()
    };
    let final_diag = diagnostics::measure(&setup, &state);
    plots::write_all(&out.join("plots"), &history, &setup, &state)?;
    let sum = summary::Summary {
        name: scenario.name.clone(),
        status: match &status {
            Status::Completed => "completed",
            Status::AtRest => "at_rest",
            Status::Unstable(_) => "unstable",
            Status::Paused => "paused",
            Status::Interrupted => "interrupted",
        }
        .into(),
        message: match &status {
            Status::Unstable(m) => Some(m.clone()),
            Status::Paused | Status::Interrupted => Some(format!(
                "stopped at step {} with a checkpoint; continue with `grains resume {}`",
                state.step,
                out.display()
            )),
            _ => None,
        },
        particles: n,
        steps: state.step,
        time: state.time,
        dt: setup.dt,
        dt_critical,
        threads: opts.threads,
        wall_time_s: wall,
        particle_steps_per_s: n as f64 * stepped as f64 / wall.max(1e-12),
        neighbour_builds: state.contacts.builds,
        frames: frames.count(),
        state_hash: Some(format!("{:016x}", diagnostics::state_hash(&state))),
        figures: figures(scenario, &setup, &state, &final_diag),
        checks: checks.clone(),
    };
    summary::write(&out.join("summary.json"), &sum)?;
    Ok(Outcome { status, checks })
}

/// Reopens history.csv for a resumed run, keeping the rows up to the checkpoint's step
/// (a run may have gone on past its last checkpoint before it stopped).
fn reopen_history(out: &Path, cols: &[&str], step: u64) -> anyhow::Result<History> {
    let path = out.join("history.csv");
    let (names, rows) =
        read_csv(&path).with_context(|| format!("cannot read {}", path.display()))?;
    if names != cols {
        anyhow::bail!("{}: columns differ from this scenario's", path.display());
    }
    let mut h = History::create(&path, cols)?;
    for row in rows.iter().filter(|r| r[1] <= step as f64) {
        h.push(row)?;
    }
    Ok(h)
}

fn instability(d: &Diagnostics) -> Option<String> {
    if !d.finite {
        return Some("a position or velocity is not finite (NaN or infinity)".into());
    }
    if d.max_overlap_ratio > RUNAWAY_OVERLAP {
        return Some(format!(
            "runaway overlap: {:.3} of a radius (limit {RUNAWAY_OVERLAP}); the time step is too large or the contacts too soft for the load",
            d.max_overlap_ratio
        ));
    }
    None
}
