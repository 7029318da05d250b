//! A FEM–DEM run from its scenario to its summary; a run continued from a checkpoint
//! goes on exactly as if it had never stopped.

use super::assemble::{assemble, assemble_with, on_demand, Unmade};
use super::ranks::RingPart;
use super::scenario::Scenario;
use super::{ledger, models, plots, probes, Blast, BlastSample, CAPABILITIES};
use crate::checkpoint;
use crate::dem::ranks::Link;
use crate::dispersal::DispersalObserver;
use crate::driver::{
    agreed, discount, restore_observers, Observer, Outcome, Report, Status, Stepper,
};
use crate::frames::FrameRecorder;
use crate::frames::{Mapped, Snapshots};
use crate::history::{HistoryRecorder, Recorded};
use crate::packings::Cached;
use crate::ranks::not_on_ranks;
use crate::run::{finish, resume_hint, summary, Costs, Finished, Live, RunError, RunOptions};
use crate::source::Source;
use grains_core::history::History;
use grains_core::plot::{time_label, Outline, ParticleMap};
use grains_dem::Reduce;
use std::path::{Path, PathBuf};

impl Recorded for Blast {
    fn columns(&self) -> Vec<String> {
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
        if self.ring.is_some() {
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
            if self.ring.as_ref().is_some_and(|r| r.state.ledger.is_some()) {
                c.extend(LEDGER_COLUMNS);
            }
        }
        c.into_iter().map(String::from).collect()
    }

    fn integer_columns(&self) -> Vec<String> {
        ["step", "edge_contacts", "neighbour_builds"]
            .map(String::from)
            .to_vec()
    }

    fn row(&self, s: &BlastSample) -> Vec<f64> {
        let (e, f) = (&s.energies, &s.fronts);
        let mut row = vec![
            self.charge.time,
            self.charge.step as f64,
            self.dt,
            e.kinetic,
            e.internal,
            e.chemical,
            e.total(),
            e.work_external,
            e.balance(self.e0) / self.e0,
            f.burnt,
            f.max_pressure,
            f.burn_front,
            f.boundary_radius,
            f.boundary_speed,
        ];
        if let (Some(r), Some(c), Some(g)) = (&self.ring, self.coupling(), &s.ring) {
            row.extend([
                g.kinetic,
                c.energy,
                c.contacts as f64,
                c.max_penetration_ratio,
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
            if let (Some(l), Some(rot)) = (&s.ledger, s.rotational) {
                row.extend([rot, l.stored(), l.damping, l.friction, l.springs_released]);
            }
        }
        row
    }
}

/// History columns of the energy ledger (J/m): the grains' rotational kinetic energy,
/// the energy stored in their contacts, and what damping, sliding and dropped
/// tangential springs have dissipated so far.
pub const LEDGER_COLUMNS: [&str; 5] = [
    "particle_rotational",
    "contact_stored",
    "contact_damping",
    "contact_friction",
    "springs_released",
];

/// A checkpoint read back: the run loop's progress and the run's state bytes.
pub type Resume = checkpoint::Resumed<Vec<u8>>;

/// Reads `dir/checkpoint.bin` for the scenario copy in `dir` (its bytes are checked
/// against the scenario when the run is rebuilt).
pub fn load_checkpoint(src: &Source, dir: &Path) -> Result<Resume, RunError> {
    let (progress, state) =
        checkpoint::load(&dir.join(checkpoint::FILE), &src.text).map_err(RunError::Input)?;
    Ok(Resume { progress, state })
}

/// A FEM–DEM run in progress: the simulation, the loop and every observer of
/// `grains run`, writing into its output directory as it goes.
pub struct BlastRun {
    /// The simulation.
    pub sim: Blast,
    stepper: Stepper,
    watchers: Watchers,
    scenario: Box<Scenario>,
    charge_mass: f64,
    out: PathBuf,
}

struct Watchers {
    history: HistoryRecorder,
    frames: FrameRecorder,
    /// The maps, on rank 0 (or the only rank).
    maps: Option<(Snapshots, FinalMap)>,
    dispersal: Option<DispersalObserver>,
}

impl Watchers {
    fn list(&mut self) -> Vec<&mut dyn Observer<Blast>> {
        let mut o: Vec<&mut dyn Observer<Blast>> = Vec::new();
        // First: on ranks it reads its frames from every rank, so every rank must reach
        // it, whichever observer after it fails on one rank (the failure is shared
        // after the observers ran).
        if let Some(d) = self.dispersal.as_mut() {
            o.push(d);
        }
        o.push(&mut self.history);
        o.push(&mut self.frames);
        if let Some((snaps, last)) = self.maps.as_mut() {
            o.push(snaps);
            o.push(last);
        }
        o
    }
}

/// Prepares the run of `s` (read from `src`) into `opts.out`, or its continuation from
/// `resume`: assembled, its output directory started, its first frame written.
pub fn open(
    s: &Scenario,
    src: &Source,
    opts: &mut RunOptions,
    resume: Option<Resume>,
) -> Result<BlastRun, RunError> {
    open_on(s, src, opts, resume, None)
}

/// Why `s` cannot run on several ranks yet, as one line naming what and what is
/// allowed; `None` when it can.
pub fn unsupported(s: &Scenario) -> Option<String> {
    // The charge alone is a few thousand elements with nothing to spread: every rank
    // would step the same charge.
    s.ring.is_none().then(|| {
        not_on_ranks(
            "a charge without [ring] (nothing to spread over ranks)",
            "run it on 1 rank (grains run, without mpirun), or add a [ring]",
        )
    })
}

/// [`open`] on one of several ranks, `link` carrying the messages (`None`: one rank):
/// every rank assembles the start and steps the whole charge and its box of the ring;
/// rank 0 writes every output but the other ranks' pieces of the frames.
pub fn open_on(
    s: &Scenario,
    src: &Source,
    opts: &mut RunOptions,
    resume: Option<Resume>,
    link: Option<Link>,
) -> Result<BlastRun, RunError> {
    super::check::fits(s, src, opts.threads).map_err(RunError::Input)?;
    let input = |e: String| RunError::Input(format!("{}: {e}", src.origin));
    let ranks = link.as_ref().map_or(1, |l| l.ranks());
    let (dims, balance) =
        crate::dem::ranks::layout(s.parallel.as_ref(), link.as_ref(), || unsupported(s))
            .map_err(input)?;
    let leader = link.as_ref().is_none_or(|l| l.rank() == 0);
    let made = match on_demand(s, &src.base).map_err(input)? {
        // One rank makes a packing the others then read.
        Some(od) if od.state() != Cached::Ready && leader => {
            // Every other key is checked before the packing is made, which may take
            // minutes: with the disks the spec will make standing in.
            assemble_with(s, &src.base, Unmade::Preview)
                .map_err(input)
                .and_then(|_| od.ensure(&mut *opts.progress).map(drop).map_err(input))
        }
        _ => Ok(()),
    };
    if let Some(l) = &link {
        if l.any(made.is_err()) {
            return Err(made
                .err()
                .unwrap_or_else(|| input("rank 0 could not make the ring's packing".to_string())));
        }
    }
    made?;
    let a = assemble(s, &src.base).map_err(input)?;
    let charge_mass = a.charge_mass;
    let out = opts.out.clone();
    opts.progress.announce(&format!(
        "{}{} (fem_dem) — charge {} ({} elements), {} particles, dt ≈ {:.3e} s, {} threads{} → {}",
        if resume.is_some() { "resuming " } else { "" },
        s.name,
        a.fem.explosive.name,
        a.mesh.tris.len(),
        a.ring.as_ref().map_or(0, |r| r.particles.len()),
        super::check::dt_initial(s, &a),
        opts.threads,
        if ranks > 1 {
            format!(" on {ranks} ranks")
        } else {
            String::new()
        },
        out.display()
    ));
    let steps = (s.run.duration / super::check::dt_initial(s, &a)).ceil() as u64;
    let n = a.ring.as_ref().map_or(0, |r| r.particles.len()) as u64;
    let e = super::check::cost(n, a.mesh.tris.len() as u64, steps, opts.threads);
    if let Some(w) = e.warning() {
        opts.progress.announce(&format!("warning: {w}"));
    }
    let mut sim = Blast::new(s, a);
    if let Some(r) = &resume {
        sim.restore(&r.state).map_err(|e| {
            RunError::Input(format!("{}: {e}", out.join(checkpoint::FILE).display()))
        })?;
    }
    if let (Some(link), Some(ring)) = (link, sim.ring.as_ref()) {
        let part = RingPart::new(link, (ring, &sim.charge), dims, balance).map_err(input)?;
        sim.ranks = Some(Box::new(part));
    }
    let spread = sim.ranks.is_some();
    let mut plan = s.output.plan_by_time(&CAPABILITIES, s.run.duration);
    // On a resumed run the analysis covers the new segment; `grains analyze RUN_DIR`
    // covers every frame.
    let dispersal = s.analysis.dispersal.as_ref().filter(|_| sim.ring.is_some());
    if let Some(d) = dispersal {
        // A frame at each chosen time, so that the maps there can be made again from
        // the frames.
        plan.snapshots.extend(&d.times);
        plan.snapshots.sort_by(f64::total_cmp);
        plan.snapshots.dedup();
    }
    let (history, frames, counters) = crate::ranks::recorders(
        &mut sim,
        (leader, spread),
        (&out, &src.text),
        &plan,
        resume.as_ref().map(|r| &r.progress.counters),
    )?;
    let maps = if leader {
        let snaps = Snapshots {
            dir: out.join("plots"),
        };
        let last = FinalMap {
            dir: out.join("plots"),
        };
        let made = std::fs::create_dir_all(&snaps.dir)
            .map_err(|e| anyhow::anyhow!("cannot create {}: {e}", snaps.dir.display()));
        agreed(&sim, made)?;
        Some((snaps, last))
    } else {
        agreed(&sim, Ok::<(), anyhow::Error>(()))?;
        None
    };
    let dispersal = dispersal.map(|d| {
        let centre = d.centre.map_or(sim.centre, glam::DVec2::from);
        if leader {
            DispersalObserver::new(&s.name, d, centre, s.run.duration, &out)
        } else {
            DispersalObserver::follower(d, s.run.duration)
        }
    });
    let mut watchers = Watchers {
        history,
        frames,
        maps,
        dispersal,
    };
    let mut observers = watchers.list();
    if let Some(r) = &resume {
        agreed(
            &sim,
            restore_observers(&mut observers, &r.progress.observers),
        )?;
    }
    let stepper = Stepper::start(&sim, &mut observers, plan, counters)?;
    drop(observers);
    Ok(BlastRun {
        sim,
        stepper,
        watchers,
        scenario: Box::new(s.clone()),
        charge_mass,
        out,
    })
}

impl Live for BlastRun {
    type S = Blast;

    fn parts(&mut self) -> (&mut Blast, &mut Stepper, Vec<&mut dyn Observer<Blast>>) {
        (&mut self.sim, &mut self.stepper, self.watchers.list())
    }

    fn history(&self) -> &History {
        &self.watchers.history.history
    }

    fn conclude(&mut self, outcome: Outcome, threads: usize) -> Result<Finished, RunError> {
        let (sim, s, out) = (&self.sim, &*self.scenario, &self.out);
        let dt_critical = match &sim.ring {
            Some(_) => sim.dt_particles,
            None => sim.charge.dt_stable,
        };
        if self.watchers.maps.is_none() {
            // Another rank than 0: its part is done, rank 0 writes.
            let costs = Costs {
                dt: sim.dt,
                dt_critical,
                threads,
                frames: 0,
            };
            let at = (s.name.as_str(), out.as_path());
            return Ok(crate::ranks::finished_elsewhere(at, sim, outcome, costs));
        }
        let history = &self.watchers.history;
        let dispersal = &self.watchers.dispersal;
        let charge_mass = self.charge_mass;
        // Added in ascending id: the same whatever order the ring is held in.
        let ring_mass: Option<f64> = sim.ring.as_ref().map(|r| {
            let p = &r.state.particles;
            let mut by_id: Vec<(u32, f64)> = (0..p.len()).map(|i| (p.id[i], p.mass(i))).collect();
            by_id.sort_unstable_by_key(|&(id, _)| id);
            by_id.into_iter().map(|(_, m)| m).sum()
        });
        let ring_models = ring_mass.and_then(|mass| models::figures(s, mass, sim.charge.time));
        let ctx = probes::Context {
            scn: s,
            fem: &sim.fem,
            charge: &sim.charge,
            e0: sim.e0,
            history: &history.history,
            charge_mass,
            ring_mass,
            dispersal: outcome.report.figures.get("dispersal"),
            models: ring_models.as_ref(),
        };
        let (checks, mut figures, arrival) = probes::evaluate(&ctx);
        figures.insert("max_penetration_ratio".into(), sim.max_penetration.into());
        figures.insert("dt_min".into(), sim.dt_range.0.into());
        figures.insert("dt_max".into(), sim.dt_range.1.into());
        figures.insert("charge_elements".into(), sim.charge.n_elems().into());
        if let Some(r) = &sim.ring {
            figures.insert("coupling_stiffness".into(), r.coupling.stiffness.into());
            figures.insert("coupling_builds".into(), r.coupling.builds.into());
        }
        if let Some(m) = ring_models {
            figures.insert("models".into(), m);
        }
        if let Some(l) = ledger::figures(&history.history) {
            figures.insert("energy_ledger".into(), l);
        }
        if let Some(d) = &dispersal {
            figures.insert("dispersal_analysed".into(), d.analysed().into());
            figures.insert("dispersal_wall_time_s".into(), d.seconds().into());
        }
        let mut outcome = outcome;
        outcome.report = merge(outcome.report, figures, checks, &outcome.status);
        let figure = |v: Option<&serde_json::Value>| v.and_then(|v| v.as_f64());
        let fig = &outcome.report.figures;
        let levels: Vec<(&str, f64)> = [
            ("paper, FEM-DEM", probes::band_reference(s)),
            ("classic Gurney", figure(fig.get("gurney_velocity"))),
            (
                "Milne porous Gurney (reconstructed)",
                figure(
                    fig.get("models")
                        .map(|m| &m["milne_porous_gurney"]["velocity"]),
                ),
            ),
        ]
        .into_iter()
        .filter_map(|(name, v)| Some((name, v?)))
        .collect();
        plots::write_all(
            &out.join("plots"),
            &history.history,
            sim.ring.is_some(),
            &arrival,
            &levels,
            &plots::band_rule(s.analysis.band_fraction, s.analysis.radial_bin),
        )?;
        ledger::plot(&out.join("plots"), &history.history)?;
        let mut counts = serde_json::Map::new();
        counts.insert(
            "neighbour_builds".into(),
            sim.ring
                .as_ref()
                .map_or(0, |r| r.state.contacts.builds)
                .into(),
        );
        if let Some(rp) = &sim.ranks {
            // Of this segment of the run (a resumed run counts afresh).
            let dec = &rp.part.dec;
            crate::ranks::count_balance(&mut counts, dec.imbalance(), dec.rebalances());
            rp.part.comm().insert_into(&mut counts);
        }
        if let Some(r) = &sim.ring {
            // The particles' own fingerprint, comparable with a DEM run's.
            counts.insert(
                "ring_state_hash".into(),
                format!("{:016x}", sim.ring_hash(r)).into(),
            );
        }
        let costs = Costs {
            dt: sim.dt,
            dt_critical,
            threads,
            frames: self.watchers.frames.count(),
        };
        let mut sum = summary(&s.name, "fem_dem", sim, &outcome, costs, counts);
        if matches!(outcome.status, Status::Paused | Status::Interrupted) {
            sum.message = Some(resume_hint(outcome.clock.step, out));
        }
        finish(sum, outcome.status, out)
    }
}

/// The end-of-run checks and figures, after the loop's own.
fn merge(
    mut report: Report,
    figures: serde_json::Map<String, serde_json::Value>,
    checks: Vec<grains_core::checks::Check>,
    status: &Status,
) -> Report {
    report.figures.extend(figures);
    let mut more = Report {
        figures: Default::default(),
        checks,
    };
    discount(&mut more, status);
    report.checks.extend(more.checks);
    report
}

/// The map of the particles at the end of a run that finished.
struct FinalMap {
    dir: PathBuf,
}

impl Observer<Blast> for FinalMap {
    fn on_end(&mut self, sim: &Blast, status: &Status, _report: &mut Report) -> anyhow::Result<()> {
        if sim.ring.is_some() && status.finished() {
            sim.draw_map(&self.dir.join(sim.map_name()))?;
        }
        Ok(())
    }
}

impl Mapped for Blast {
    fn map_name(&self) -> String {
        format!("particles_{:07.2}us.png", self.charge.time * 1e6)
    }

    /// The particles coloured by speed, with the charge's edge (xue-2019 Fig. 5a).
    fn draw_map(&self, path: &Path) -> anyhow::Result<()> {
        let Some(r) = &self.ring else {
            return Ok(());
        };
        let p = &r.state.particles;
        let speed: Vec<f64> = p.vel.iter().map(|v| v.length()).collect();
        let c = &self.charge;
        let edge = Outline {
            points: c
                .boundary
                .iter()
                .map(|e| c.nodes.pos[e[0] as usize])
                .collect(),
            closed: true,
        };
        ParticleMap {
            title: &format!(
                "Particles at t = {}, coloured by speed; the charge's edge in black",
                time_label(c.time)
            ),
            centres: &p.pos,
            radii: &p.radius,
            values: &speed,
            value_label: "speed (m/s)",
            outlines: &[edge],
        }
        .write_png(path)?;
        Ok(())
    }
}
