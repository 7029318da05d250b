//! A DEM run from its scenario to its summary; a run continued from a checkpoint goes
//! on exactly as if it had never stopped.

use super::assemble::{assemble, assemble_with, Assembled};
use super::probes::CheckObserver;
use super::ranks::{self, Link};
use super::records::figures;
use super::rest::RestDetector;
use super::scenario::Scenario;
use super::{plots, Dem, CAPABILITIES};
use crate::checkpoint;
use crate::dispersal::DispersalObserver;
use crate::driver::{agreed, restore_observers, Every, Observer, Outcome, Report, Status, Stepper};
use crate::frames::{FrameRecorder, Snapshots};
use crate::history::HistoryRecorder;
use crate::run::{finish, resume_hint, summary, Costs, Finished, Live, RunError, RunOptions};
use crate::source::Source;
use grains_core::history::History;
use grains_dem::State;
use std::path::{Path, PathBuf};

/// A checkpoint read back: the run loop's progress and the engine state.
pub type Resume = checkpoint::Resumed<State>;

/// Reads `dir/checkpoint.bin` for the scenario copy in `dir`.
pub fn load_checkpoint(s: &Scenario, src: &Source, dir: &Path) -> Result<Resume, RunError> {
    checkpoint::load_dem(
        dir,
        &src.text,
        s.walls.len(),
        |r| grains_dem::checkpoint::read(r, 1 << 31),
        |state| state.contacts.n_walls,
    )
    .map_err(RunError::Input)
}

/// A DEM run in progress: the simulation, the loop and every observer of `grains run`,
/// writing into its output directory as it goes.
pub struct DemRun {
    /// The simulation.
    pub sim: Dem,
    stepper: Stepper,
    watchers: Watchers,
    name: String,
    out: PathBuf,
    dt_critical: f64,
}

struct Watchers {
    /// The checks' probes, on every rank (they read particles through
    /// [`Dem::watched`], a collective on several ranks).
    checks: CheckObserver,
    history: HistoryRecorder,
    rest: Option<RestDetector>,
    /// The observers that write or read every particle: on rank 0 (or the only rank).
    writers: Option<Writers>,
    /// On the other ranks of a run spread over ranks: their pieces of each frame.
    pieces: Option<FrameRecorder>,
}

struct Writers {
    frames: FrameRecorder,
    snaps: Snapshots,
    ends: Figures,
    dispersal: Option<DispersalObserver>,
}

impl Watchers {
    /// The observers, the probes first, so that a failure of rank 0's writers cannot
    /// leave the other ranks waiting in their gathers.
    fn list(&mut self) -> Vec<&mut dyn Observer<Dem>> {
        let mut o: Vec<&mut dyn Observer<Dem>> = vec![&mut self.checks, &mut self.history];
        let Some(w) = self.writers.as_mut() else {
            o.extend(self.pieces.as_mut().map(|f| f as &mut dyn Observer<Dem>));
            o.extend(self.rest.as_mut().map(|r| r as &mut dyn Observer<Dem>));
            return o;
        };
        o.push(&mut w.frames);
        o.push(&mut w.snaps);
        if let Some(r) = self.rest.as_mut() {
            o.push(r);
        }
        o.push(&mut w.ends);
        if let Some(d) = w.dispersal.as_mut() {
            o.push(d);
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
) -> Result<DemRun, RunError> {
    open_on(s, src, opts, resume, None)
}

/// [`open`] on one of several ranks, `link` carrying the messages (`None`: one rank):
/// every rank assembles the start and takes its part of it; rank 0 writes every
/// output, the others step their part and write nothing.
pub fn open_on(
    s: &Scenario,
    src: &Source,
    opts: &mut RunOptions,
    resume: Option<Resume>,
    link: Option<Link>,
) -> Result<DemRun, RunError> {
    let input = |e: grains_core::input::InputError| RunError::Input(format!("{}: {e}", src.origin));
    let refused = |e: String| RunError::Input(format!("{}: {e}", src.origin));
    let out = opts.out.clone();
    super::check::fits(s, src, opts.threads).map_err(RunError::Input)?;
    let (dims, balance) =
        ranks::layout(s.parallel.as_ref(), link.as_ref(), || ranks::unsupported(s))
            .map_err(refused)?;
    let (mut sim, steps, dt_critical, implausible) = match &resume {
        None => {
            let a = assemble(s, &src.base).map_err(input)?;
            let (steps, dt_critical) = (a.steps, a.dt_critical);
            let implausible = super::plausible::warnings(s, &a);
            (
                Dem::new(a, s.output.lammps_dump).map_err(input)?,
                steps,
                dt_critical,
                implausible,
            )
        }
        Some(r) => {
            let a: Assembled =
                assemble_with(s, &src.base, Some(r.state.particles.clone())).map_err(input)?;
            let (steps, dt_critical) = (a.steps, a.dt_critical);
            let dem = Dem::resumed(a.setup, r.state.clone(), a.dt, s.output.lammps_dump);
            (dem, steps, dt_critical, Vec::new())
        }
    };
    if let Some(link) = link {
        let part = ranks::Part::new(link, &sim.setup, &sim.state, dims, (balance, 0.0))
            .map_err(refused)?;
        sim.ranks = Some(Box::new(part));
    }
    let leader = sim.ranks.as_ref().is_none_or(|p| p.rank() == 0);
    let sim_spread = sim.ranks.is_some();
    let mut plan = s.output.plan_by_steps(&CAPABILITIES, steps);
    opts.progress.announce(&format!(
        "{}{} (dem) — {} particles, dt = {:.3e} s, {} steps, {} threads → {}",
        if resume.is_some() { "resuming " } else { "" },
        s.name,
        sim.state.particles.len(),
        sim.dt,
        steps,
        opts.threads,
        out.display()
    ));
    let e = super::check::cost(
        sim.state.particles.len() as u64,
        sim.setup.walls.len(),
        steps,
        opts.threads,
    );
    for w in e.warning().into_iter().chain(implausible) {
        opts.progress.announce(&format!("warning: {w}"));
    }
    let every = match plan.samples {
        Every::Steps(k) => k,
        Every::Time(_) => 1,
    };
    let rest = s.run.stop_kinetic_ratio.map(|ratio| {
        let hold = s.run.stop_rest_time.unwrap_or(20.0 * every as f64 * sim.dt);
        RestDetector::new(&sim, ratio, hold)
    });
    let (history, frames, counters) = crate::ranks::recorders(
        &mut sim,
        (leader, sim_spread),
        (&out, &src.text),
        &plan,
        resume.as_ref().map(|r| &r.progress.counters),
    )?;
    // The law was resolved (and refused where bad) when the run was assembled, on every
    // rank alike: it cannot fail here on one rank alone.
    let restitution = crate::law::dim2::resolve(&s.contact, &s.materials).map_err(input)?;
    let checks = CheckObserver::new(&sim, &s.checks, restitution.restitution);
    let (frames, pieces) = match leader {
        true => (Some(frames), None),
        false => (None, Some(frames)),
    };
    let writers = if let Some(frames) = frames {
        // On a resumed run the analysis covers the new segment; `grains analyze RUN_DIR`
        // covers every frame.
        let dispersal = s.dispersal.as_ref().map(|d| {
            plan.snapshots.extend(&d.times);
            plan.snapshots.sort_by(f64::total_cmp);
            plan.snapshots.dedup();
            let centre = glam::DVec2::from(d.centre.unwrap_or_default());
            DispersalObserver::new(&s.name, d, centre, s.run.duration, &out)
        });
        Some(Writers {
            frames,
            snaps: Snapshots {
                dir: out.join("plots"),
            },
            ends: Figures {
                scenario: s.clone(),
            },
            dispersal,
        })
    } else {
        // Rank 0 holds the whole state; here it was needed only to take this part.
        sim.state = State {
            time: sim.state.time,
            step: sim.state.step,
            ..Default::default()
        };
        None
    };
    let mut watchers = Watchers {
        checks,
        history,
        rest,
        writers,
        pieces,
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
    Ok(DemRun {
        sim,
        stepper,
        watchers,
        name: s.name.clone(),
        out,
        dt_critical,
    })
}

impl Live for DemRun {
    type S = Dem;

    fn parts(&mut self) -> (&mut Dem, &mut Stepper, Vec<&mut dyn Observer<Dem>>) {
        (&mut self.sim, &mut self.stepper, self.watchers.list())
    }

    fn history(&self) -> &History {
        &self.watchers.history.history
    }

    fn conclude(&mut self, outcome: Outcome, threads: usize) -> Result<Finished, RunError> {
        let (sim, out) = (&self.sim, &self.out);
        let Some(writers) = &self.watchers.writers else {
            // Another rank than 0: its part is done, rank 0 writes.
            let costs = Costs {
                dt: sim.dt,
                dt_critical: self.dt_critical,
                threads,
                frames: 0,
            };
            let at = (self.name.as_str(), out.as_path());
            return Ok(crate::ranks::finished_elsewhere(at, sim, outcome, costs));
        };
        plots::write_all(
            &out.join("plots"),
            &self.watchers.history.history,
            &sim.setup,
            &sim.state,
        )?;
        let mut counts = serde_json::Map::new();
        counts.insert("neighbour_builds".into(), sim.state.contacts.builds.into());
        if let Some(part) = &sim.ranks {
            crate::ranks::count_balance(&mut counts, part.dec.imbalance(), part.dec.rebalances());
            part.comm().insert_into(&mut counts);
        }
        let costs = Costs {
            dt: sim.dt,
            dt_critical: self.dt_critical,
            threads,
            frames: writers.frames.count(),
        };
        let mut sum = summary(&self.name, "dem", sim, &outcome, costs, counts);
        if matches!(outcome.status, Status::Paused | Status::Interrupted) {
            sum.message = Some(resume_hint(outcome.clock.step, out));
        }
        finish(sum, outcome.status, out)
    }
}

/// The scenario's figures at the end of a run.
struct Figures {
    scenario: Scenario,
}

impl Observer<Dem> for Figures {
    fn on_end(&mut self, sim: &Dem, _status: &Status, report: &mut Report) -> anyhow::Result<()> {
        let d = grains_dem::diagnostics::measure(&sim.setup, &sim.state);
        report
            .figures
            .extend(figures(&self.scenario, &sim.setup, &sim.state, &d));
        Ok(())
    }
}
