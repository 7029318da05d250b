//! The run loop: step the engine, record history, write frames, stop at rest or on
//! instability, then write checks, figures, plots and the summary.

use super::assemble::Assembled;
use super::frames::FrameWriter;
use super::probes::Probes;
use crate::progress::Progress;
use super::scenario::{FigureSpec, Scenario};
use super::plots;
use crate::summary;
use anyhow::Context;
use grains_core::atomic::write_atomic;
use grains_core::checks::Check;
use grains_core::history::History;
use grains_dem::diagnostics::{self, Diagnostics};
use grains_dem::{step, Setup, State};
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
}

/// What the caller needs to decide the exit code.
pub struct Outcome {
    /// The diagnostic, when the run stopped on a bad state.
    pub unstable: Option<String>,
    /// Checks with their verdicts.
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
    threads: usize,
) -> anyhow::Result<Outcome> {
    std::fs::create_dir_all(out)
        .with_context(|| format!("cannot create output directory {}", out.display()))?;
    write_atomic(&out.join("scenario.toml"), text.as_bytes())?;
    let Assembled {
        setup,
        particles,
        dt_critical,
        steps,
    } = asm;
    let n = particles.len();
    let mut state = State::new(&setup, particles);
    let mut probes = Probes::new(&setup, &scenario.checks);
    probes.observe(&setup, &state);

    let columns = history_columns(&setup);
    let cols: Vec<&str> = columns.iter().map(String::as_str).collect();
    let mut history = History::create(&out.join("history.csv"), &cols)?;
    let mut frames = FrameWriter::create(out, &setup)?;
    let history_every = (steps / scenario.output.history.max(1)).max(1);
    let frame_every = (steps / scenario.output.frames.max(1)).max(1);
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
    let mut rest_since: Option<f64> = None;
    let first = diagnostics::measure(&setup, &state);
    history.push(&history_row(&setup, &state, &first))?;
    frames.write(&setup, &state)?;
    let mut progress = Progress::new(steps);
    let started = Instant::now();
    let mut status = Status::Completed;
    let mut last_frame_step = 0;
    while state.step < steps {
        step(&setup, &mut state);
        probes.observe(&setup, &state);
        if state.step.is_multiple_of(history_every) || state.step == steps {
            let d = diagnostics::measure(&setup, &state);
            if let Some(why) = instability(&d) {
                status = Status::Unstable(format!(
                    "step {} (t = {:.6e} s): {why}",
                    state.step, state.time
                ));
                break;
            }
            history.push(&history_row(&setup, &state, &d))?;
            if rest_energy.is_some_and(|limit| d.kinetic() < limit) {
                let since = *rest_since.get_or_insert(state.time);
                if state.time - since >= rest_time {
                    status = Status::AtRest;
                    break;
                }
            } else {
                rest_since = None;
            }
        }
        if state.step.is_multiple_of(frame_every) {
            frames.write(&setup, &state)?;
            last_frame_step = state.step;
        }
        progress.tick(state.step);
    }
    let loop_seconds = started.elapsed().as_secs_f64();
    progress.finish();
    history.flush()?;
    if !matches!(status, Status::Unstable(_)) && last_frame_step != state.step {
        frames.write(&setup, &state)?;
    }

    let checks = probes.checks(&setup, &state, &scenario.checks);
    let final_diag = diagnostics::measure(&setup, &state);
    let figures = figures(scenario, &setup, &state, &final_diag);
    plots::write_all(&out.join("plots"), &history, &setup, &state)?;
    let sum = summary::Summary {
        name: scenario.name.clone(),
        status: match &status {
            Status::Completed => "completed".into(),
            Status::AtRest => "at_rest".into(),
            Status::Unstable(_) => "unstable".into(),
        },
        message: match &status {
            Status::Unstable(m) => Some(m.clone()),
            _ => None,
        },
        particles: n,
        steps: state.step,
        time: state.time,
        dt: setup.dt,
        dt_critical,
        threads,
        wall_time_s: loop_seconds,
        particle_steps_per_s: n as f64 * state.step as f64 / loop_seconds.max(1e-12),
        neighbour_builds: state.contacts.builds,
        frames: frames.count(),
        figures,
        checks: checks.clone(),
    };
    summary::write(&out.join("summary.json"), &sum)?;
    let unstable = match status {
        Status::Unstable(m) => Some(m),
        _ => None,
    };
    Ok(Outcome { unstable, checks })
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

fn history_columns(setup: &Setup) -> Vec<String> {
    let mut c: Vec<String> = [
        "time",
        "step",
        "kinetic",
        "kinetic_rotational",
        "potential",
        "elastic",
        "total",
        "momentum_x",
        "momentum_y",
        "pair_contacts",
        "wall_contacts",
        "coordination",
        "max_overlap_ratio",
        "neighbour_builds",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    for w in &setup.walls {
        for suffix in ["fx", "fy", "torque"] {
            c.push(format!("{}_{suffix}", w.name));
        }
    }
    c
}

fn history_row(setup: &Setup, s: &State, d: &Diagnostics) -> Vec<f64> {
    let n = s.particles.len();
    let mut row = vec![
        s.time,
        s.step as f64,
        d.kinetic(),
        d.kinetic_rotational,
        d.potential,
        d.elastic,
        d.total(),
        d.momentum.x,
        d.momentum.y,
        d.pair_contacts as f64,
        d.wall_contacts as f64,
        d.mean_coordination(n),
        d.max_overlap_ratio,
        s.contacts.builds as f64,
    ];
    for load in s.wall_loads.iter().take(setup.walls.len()) {
        row.extend([load.force.x, load.force.y, load.torque]);
    }
    row
}

fn figures(
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
