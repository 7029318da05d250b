//! The run loop of a blast scenario: step charge and ring together, record the history,
//! write frames and snapshots, stop on a breakdown, then write checks, plots and the
//! summary.

use super::analysis::{self, RingFigures};
use super::assemble::Assembled;
use super::coupling::Coupling;
use super::frames::FrameWriter;
use super::probes;
use super::scenario::Scenario;
use super::step::{coupled_step, RingRun};
use crate::progress::Progress;
use crate::summary;
use anyhow::Context;
use glam::DVec2;
use grains_core::atomic::write_atomic;
use grains_core::checks::Check;
use grains_core::history::History;
use grains_core::plot::scatter_disks_png;
use grains_dem::State;
use grains_fem::diagnostics::{energies, fronts};
use grains_fem::Charge;
use std::path::Path;
use std::time::Instant;

/// What the caller needs for the exit code.
pub struct Outcome {
    /// Why the run stopped early, if it did.
    pub unstable: Option<String>,
    /// Checks with their verdicts.
    pub checks: Vec<Check>,
}

/// Penetration of a particle into the charge, in radii, beyond which the contact has
/// failed (the particle is about to pass through the edge).
const RUNAWAY_PENETRATION: f64 = 0.9;

/// History columns; the ring's only when there is one.
fn columns(ring: bool) -> Vec<&'static str> {
    let mut c = vec![
        "time",
        "step",
        "dt",
        "charge_kinetic",
        "charge_internal",
        "charge_chemical",
        "charge_total",
        "work_on_charge",
        "charge_energy_error",
        "burnt_fraction",
        "max_pressure",
        "burn_front",
        "charge_radius",
        "charge_edge_speed",
    ];
    if ring {
        c.extend([
            "particle_kinetic",
            "coupling_energy",
            "edge_contacts",
            "max_penetration_ratio",
            "inner_radius",
            "outer_radius",
            "pressure_front",
            "band_outer",
            "band_velocity",
            "spall_velocity",
            "band_fraction",
            "mean_radial_velocity",
            "neighbour_builds",
        ]);
    }
    c
}

/// Runs an assembled scenario, writing every output into `out`.
pub fn run(
    scn: &Scenario,
    text: &str,
    asm: Assembled,
    out: &Path,
    threads: usize,
) -> anyhow::Result<Outcome> {
    std::fs::create_dir_all(out)
        .with_context(|| format!("cannot create output directory {}", out.display()))?;
    write_atomic(&out.join("scenario.toml"), text.as_bytes())?;
    let fem = &asm.fem;
    let centre = DVec2::from(scn.charge.centre);
    let mut charge = Charge::new(fem, &asm.mesh);
    let e0 = energies(fem, &charge).total();
    let coupling_safety = scn.run.coupling_safety;
    let (mut ring, dt_particles, mean_d, n) = match asm.ring {
        Some(rp) => {
            let dt_p = rp.dt(coupling_safety);
            let mean_d = rp.mean_diameter;
            let n = rp.particles.len();
            let mut coupling = Coupling::new(rp.stiffness, rp.setup.skin);
            let mut state = State::new(&rp.setup, rp.particles);
            coupling.rebuild(&charge, &state.particles);
            coupling.forces(&mut charge, &mut state.particles);
            (
                Some(RingRun {
                    setup: rp.setup,
                    state,
                    coupling,
                }),
                dt_p,
                mean_d,
                n,
            )
        }
        None => (None, f64::INFINITY, 0.0, 0),
    };

    let r_in = scn.ring.as_ref().map_or(0.0, |r| r.inner_radius);
    let n_sectors = analysis::sectors(&scn.analysis, r_in, mean_d);
    let cols = columns(ring.is_some());
    let mut history = History::create(&out.join("history.csv"), &cols)?;
    let mut frames = FrameWriter::create(out)?;
    let duration = asm.duration;
    let history_dt = duration / scn.output.history as f64;
    let frame_dt = duration / scn.output.frames.max(1) as f64;
    let mut snapshots: Vec<f64> = scn.output.snapshots.clone();
    snapshots.sort_by(f64::total_cmp);
    let mut next_snapshot = 0;
    let plots_dir = out.join("plots");
    std::fs::create_dir_all(&plots_dir)?;
    // Snapshots of an earlier run into the same directory would be mistaken for this one's.
    for entry in std::fs::read_dir(&plots_dir)?.flatten() {
        let name = entry.file_name().to_string_lossy().to_string();
        if name.starts_with("particles_") && name.ends_with("us.png") {
            std::fs::remove_file(entry.path())?;
        }
    }

    let mut max_penetration: f64 = 0.0;
    let record = |charge: &Charge,
                  ring: &Option<RingRun>,
                  dt: f64,
                  history: &mut History|
     -> anyhow::Result<Option<RingFigures>> {
        let e = energies(fem, charge);
        let f = fronts(charge);
        let mut row = vec![
            charge.time,
            charge.step as f64,
            dt,
            e.kinetic,
            e.internal,
            e.chemical,
            e.total(),
            e.work_external,
            e.balance(e0) / e0,
            f.burnt,
            f.max_pressure,
            f.burn_front,
            f.boundary_radius,
            f.boundary_speed,
        ];
        let mut figures = None;
        if let Some(r) = ring {
            let p = &r.state.particles;
            let pressure = analysis::contact_pressure(&r.setup, p, &r.state.contacts, &[]);
            let g = analysis::measure(&scn.analysis, n_sectors, p, centre, mean_d, &pressure);
            row.extend([
                g.kinetic,
                r.coupling.energy,
                r.coupling.contacts as f64,
                r.coupling.max_penetration_ratio,
                g.inner,
                g.outer,
                g.pressure_front,
                g.band_outer,
                g.band_velocity,
                g.spall_velocity,
                g.band_fraction,
                g.mean_velocity,
                r.state.contacts.builds as f64,
            ]);
            figures = Some(g);
        }
        history.push(&row)?;
        Ok(figures)
    };

    let mut dt = (fem.safety * charge.dt_stable).min(dt_particles);
    record(&charge, &ring, dt, &mut history)?;
    frames.write(0.0, &charge, ring.as_ref().map(|r| (&r.setup, &r.state)))?;
    let (mut next_history, mut next_frame) = (history_dt, frame_dt);
    let total_est = (duration / dt).ceil().max(1.0) as u64;
    let mut progress = Progress::new(total_est);
    let started = Instant::now();
    let (mut dt_min, mut dt_max) = (f64::INFINITY, 0.0f64);
    let mut unstable: Option<String> = None;
    while charge.time < duration * (1.0 - 1e-12) {
        dt = (fem.safety * charge.dt_stable).min(dt_particles);
        if let Some(r) = &ring {
            dt = dt.min(coupling_safety * r.coupling.stable_dt());
        }
        dt_min = dt_min.min(dt);
        dt_max = dt_max.max(dt);
        if let Err(b) = coupled_step(fem, &mut charge, ring.as_mut(), dt) {
            unstable = Some(format!("step {}: {b}", charge.step));
            break;
        }
        if let Some(r) = &ring {
            max_penetration = max_penetration.max(r.coupling.max_penetration_ratio);
            if r.coupling.max_penetration_ratio > RUNAWAY_PENETRATION {
                unstable = Some(format!(
                    "step {} (t = {:.6e} s): a particle penetrated the charge's edge by {:.3} of its radius \
                     (limit {RUNAWAY_PENETRATION}); raise coupling.stiffness_ratio or lower run.coupling_safety",
                    charge.step, charge.time, r.coupling.max_penetration_ratio
                ));
                break;
            }
        }
        let t = charge.time;
        if t >= next_history || t >= duration * (1.0 - 1e-12) {
            record(&charge, &ring, dt, &mut history)?;
            if let Some(r) = &ring {
                let d = grains_dem::diagnostics::measure(&r.setup, &r.state);
                if !d.finite {
                    unstable = Some(format!(
                        "step {} (t = {t:.6e} s): a particle position or velocity is not finite",
                        charge.step
                    ));
                    break;
                }
            }
            while next_history <= t {
                next_history += history_dt;
            }
        }
        if t >= next_frame {
            frames.write(t, &charge, ring.as_ref().map(|r| (&r.setup, &r.state)))?;
            while next_frame <= t {
                next_frame += frame_dt;
            }
        }
        if next_snapshot < snapshots.len() && t >= snapshots[next_snapshot] * (1.0 - 1e-9) {
            frames.write(t, &charge, ring.as_ref().map(|r| (&r.setup, &r.state)))?;
            if let Some(r) = &ring {
                snapshot(&plots_dir, t, &r.state)?;
            }
            while next_snapshot < snapshots.len() && t >= snapshots[next_snapshot] * (1.0 - 1e-9) {
                next_snapshot += 1;
            }
        }
        progress.tick(((t / duration) * total_est as f64) as u64);
    }
    let loop_seconds = started.elapsed().as_secs_f64();
    progress.finish();
    history.flush()?;
    if unstable.is_none() {
        frames.write(
            charge.time,
            &charge,
            ring.as_ref().map(|r| (&r.setup, &r.state)),
        )?;
        if let Some(r) = &ring {
            snapshot(&plots_dir, charge.time, &r.state)?;
        }
    }

    let ctx = probes::Context {
        scn,
        fem,
        charge: &charge,
        e0,
        history: &history,
        charge_mass: asm.charge_mass,
        ring_mass: ring
            .as_ref()
            .map(|r| (0..n).map(|i| r.state.particles.mass(i)).sum()),
    };
    let (checks, mut figures, arrival) = probes::evaluate(&ctx);
    figures.insert("max_penetration_ratio".into(), max_penetration.into());
    figures.insert("dt_min".into(), dt_min.into());
    figures.insert("dt_max".into(), dt_max.into());
    figures.insert("charge_elements".into(), charge.n_elems().into());
    if let Some(r) = &ring {
        figures.insert("coupling_stiffness".into(), r.coupling.stiffness.into());
        figures.insert("coupling_builds".into(), r.coupling.builds.into());
    }
    let reference = probes::band_reference(scn);
    let gurney = figures.get("gurney_velocity").and_then(|v| v.as_f64());
    super::plots::write_all(
        &plots_dir,
        &history,
        ring.is_some(),
        &arrival,
        reference,
        gurney,
    )?;
    let steps = charge.step;
    let sum = summary::Summary {
        name: scn.name.clone(),
        status: if unstable.is_some() {
            "unstable".into()
        } else {
            "completed".into()
        },
        message: unstable.clone(),
        particles: n,
        steps,
        time: charge.time,
        dt,
        dt_critical: if ring.is_some() {
            dt_particles
        } else {
            charge.dt_stable
        },
        threads,
        wall_time_s: loop_seconds,
        particle_steps_per_s: n as f64 * steps as f64 / loop_seconds.max(1e-12),
        neighbour_builds: ring.as_ref().map_or(0, |r| r.state.contacts.builds),
        frames: frames.count(),
        state_hash: ring
            .as_ref()
            .map(|r| format!("{:016x}", grains_dem::diagnostics::state_hash(&r.state))),
        figures,
        checks: checks.clone(),
    };
    summary::write(&out.join("summary.json"), &sum)?;
    Ok(Outcome { unstable, checks })
}

/// A PNG of the particles coloured by speed (xue-2019 Fig. 5a).
fn snapshot(dir: &Path, t: f64, s: &State) -> anyhow::Result<()> {
    let p = &s.particles;
    let speed: Vec<f64> = p.vel.iter().map(|v| v.length()).collect();
    scatter_disks_png(
        &dir.join(format!("particles_{:07.2}us.png", t * 1e6)),
        &format!("Particles at t = {:.2} µs, coloured by speed", t * 1e6),
        &p.pos,
        &p.radius,
        &speed,
        "speed (m/s)",
    )?;
    Ok(())
}
