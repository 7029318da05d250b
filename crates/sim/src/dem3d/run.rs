//! A 3D DEM run from its scenario to its summary, through the driver every engine uses,
//! and what `grains check` prints for it; a run continued from a checkpoint goes on
//! exactly as if it had never stopped.

use super::assemble::{assemble, Assembled};
use super::ledger::Books;
use super::probes::Probes;
use super::ranks::Part;
use super::scenario::{Scenario, SphereSource};
use super::{Dem3, CAPABILITIES};
use crate::check::{Derived, Line};
use crate::checkpoint;
use crate::dem::rest::RestDetector;
use crate::driver::{agreed, restore_observers, Every, Flow, Observer, Outcome, Status, Stepper};
use crate::estimate::{rate, Estimate};
use crate::frames::FrameRecorder;
use crate::history::HistoryRecorder;
use crate::ranks::Link;
use crate::run::{finish, resume_hint, summary, Costs, Finished, Live, RunError, RunOptions};
use crate::source::Source;
use grains_core::history::History;
use grains_dem3d::diagnostics::Diagnostics;
use grains_dem3d::State;
use std::path::{Path, PathBuf};

/// A checkpoint read back: the run loop's progress, the engine state and the energy
/// ledger's books.
pub type Resume = checkpoint::Resumed<(State, Books)>;

/// Reads `dir/checkpoint.bin` for the scenario copy in `dir`.
pub fn load_checkpoint(s: &Scenario, src: &Source, dir: &Path) -> Result<Resume, RunError> {
    // A `box` spec is six walls: the count is the assembled walls'.
    let walls = super::walls::walls(s).map_or(s.walls.len(), |w| w.len());
    checkpoint::load_dem(
        dir,
        &src.text,
        walls,
        |r| {
            let mut state = grains_dem3d::checkpoint::read(r, 1 << 31)?;
            let books = super::ledger::read_tail(r, &mut state)?;
            Ok((state, books))
        },
        |(state, _)| state.contacts.n_walls,
    )
    .map_err(RunError::Input)
}

/// Bytes per sphere: state (≈ 170 B), neighbour list with granular history (≈ 6
/// entries × 130 B), bookkeeping, and one wall spring and history per wall.
fn bytes_per_sphere(walls: usize) -> u64 {
    1000 + 100 * walls as u64
}

/// The spheres the scenario's sources hold, counted without building them.
pub fn count(s: &Scenario) -> u64 {
    s.particles
        .iter()
        .map(|p| match p {
            SphereSource::List { spheres, .. } => spheres.len() as u64,
            SphereSource::Lattice { count, .. } | SphereSource::Random { count, .. } => {
                *count as u64
            }
            // Counted when read: the estimate after assembly has them.
            SphereSource::File { .. } => 0,
        })
        .sum::<u64>()
        + s.pour.as_ref().and_then(|p| p.count).unwrap_or(0)
}

/// What a run of `n` spheres over `steps` steps costs (a sphere step costs about three
/// disk steps: a 27-cell stencil and three components).
pub fn cost(n: u64, walls: usize, steps: u64, threads: usize) -> Estimate {
    Estimate::new(
        n,
        steps,
        n * bytes_per_sphere(walls) + (1 << 20),
        rate::DEM / 3.0,
        threads,
    )
}

/// Refuses a run too large for memory before anything is built.
fn fits(s: &Scenario, src: &Source, threads: usize) -> Result<(), String> {
    cost(count(s), s.walls.len() * 6, 0, threads).fits_memory(&format!("{}: particles", src.origin))
}

/// What `grains check` prints for a 3D scenario.
pub fn derived(s: &Scenario, src: &Source, threads: usize) -> Result<Derived, String> {
    fits(s, src, threads)?;
    let a = assemble(s, &src.base).map_err(|e| format!("{}: {e}", src.origin))?;
    let n = a.particles.len() as u64 + a.pour.as_ref().map_or(0, |p| p.planned());
    let walls = a.setup.walls.len();
    let law = if a.setup.granular.is_some() {
        "granular"
    } else {
        "hooke_history"
    };
    let mut d = crate::dem::check::lines(
        (&s.name, &s.description),
        vec![
            Line::new("dimensions", 3, "3 (spheres)"),
            Line::new("contact_law", law, law),
        ],
        &[n, a.setup.materials.len() as u64, walls as u64],
        (a.dt, a.dt_critical, s.run.duration, a.steps),
        a.setup.skin,
    );
    d.cost(&cost(n, walls, a.steps, threads));
    Ok(d)
}

/// A 3D run in progress.
pub struct Dem3Run {
    /// The simulation.
    pub sim: Dem3,
    stepper: Stepper,
    history: HistoryRecorder,
    /// Rank 0's (or the only rank's) series; on the other ranks, their pieces.
    frames: FrameRecorder,
    /// The checks' probes, on every rank (they read the spheres through
    /// [`Dem3::watched`], a collective on several ranks).
    probes: Probes,
    /// Rank 0, or the only rank: it writes.
    leader: bool,
    rest: Option<RestDetector>,
    name: String,
    out: PathBuf,
    dt_critical: f64,
}

/// Prepares the run of `s` (read from `src`) into `opts.out`, or its continuation from
/// `resume`.
pub fn open(
    s: &Scenario,
    src: &Source,
    opts: &mut RunOptions,
    resume: Option<Resume>,
) -> Result<Dem3Run, RunError> {
    open_on(s, src, opts, resume, None)
}

/// [`open`] on one of several ranks, `link` carrying the messages (`None`: one rank):
/// every rank assembles the start and takes its part of it; rank 0 writes every
/// output, the others step their part and write their pieces of the frames.
pub fn open_on(
    s: &Scenario,
    src: &Source,
    opts: &mut RunOptions,
    resume: Option<Resume>,
    link: Option<Link>,
) -> Result<Dem3Run, RunError> {
    let input = |e: grains_core::input::InputError| RunError::Input(format!("{}: {e}", src.origin));
    let refused = |e: String| RunError::Input(format!("{}: {e}", src.origin));
    fits(s, src, opts.threads).map_err(RunError::Input)?;
    let (dims, balance) = super::ranks::layout(s.parallel.as_ref(), link.as_ref(), || {
        super::ranks::unsupported(s)
    })
    .map_err(refused)?;
    let Assembled {
        setup,
        particles,
        dt,
        dt_critical,
        steps,
        restitution,
        pour,
    } = assemble(s, &src.base).map_err(input)?;
    let mut sim = match &resume {
        None => Dem3::new(setup, particles, dt).map_err(input)?,
        Some(r) => {
            grains_dem3d::checkpoint::fits(&r.state.0, &setup)
                .map_err(|e| RunError::Input(format!("{}: checkpoint: {e}", opts.out.display())))?;
            let mut sim = Dem3::resumed(setup, r.state.0.clone(), dt);
            sim.books = r.state.1;
            sim
        }
    };
    if resume.is_none() && s.analysis.energy_ledger {
        // Both laws split their dissipation: a refusal leaves the ledger off.
        if grains_dem3d::ledger_sums::start(&sim.setup, &mut sim.state).is_ok() {
            let d = grains_dem3d::diagnostics::measure(&sim.setup, &sim.state);
            super::ledger::open(&mut sim, &d);
        }
    }
    sim.lammps_dump = s.output.lammps_dump;
    sim.releases = super::walls::releases(s, &sim.setup.walls);
    super::walls::release(&mut sim.setup.walls, &sim.releases, sim.state.time);
    sim.pour = pour.map(|p| p.resumed(&sim.state));
    let plan = s.output.plan_by_steps(&CAPABILITIES, steps);
    let out = opts.out.clone();
    opts.progress.announce(&format!(
        "{}{} (dem, 3D) — {} spheres, dt = {:.3e} s, {} steps, {} threads → {}",
        if resume.is_some() { "resuming " } else { "" },
        s.name,
        sim.state.particles.len(),
        dt,
        steps,
        opts.threads,
        out.display()
    ));
    let e = cost(
        sim.state.particles.len() as u64,
        sim.setup.walls.len(),
        steps,
        opts.threads,
    );
    if let Some(w) = e.warning() {
        opts.progress.announce(&format!("warning: {w}"));
    }
    if let Some(link) = link {
        let later = sim.pour.as_ref().map_or(0.0, |p| p.largest());
        let at = (&sim.setup, &sim.state);
        let part = Part::new(link, at.0, at.1, dims, (balance, later)).map_err(refused)?;
        sim.ranks = Some(Box::new(part));
    }
    let leader = sim.ranks.as_ref().is_none_or(|p| p.rank() == 0);
    let spread = sim.ranks.is_some();
    let (mut history, mut frames, counters) = crate::ranks::recorders(
        &mut sim,
        (leader, spread),
        (&out, &src.text),
        &plan,
        resume.as_ref().map(|r| &r.progress.counters),
    )?;
    let mut probes = Probes::new(&sim, &s.checks, restitution);
    let mut rest = s.run.stop_kinetic_ratio.map(|ratio| {
        let p = &sim.state.particles;
        let n = p.len();
        let mean_d = 2.0 * p.radius.iter().sum::<f64>() / n as f64;
        let weight: f64 = (0..n).map(|i| p.mass(i)).sum::<f64>() * sim.setup.gravity.length();
        let every = match plan.samples {
            Every::Steps(k) => k,
            Every::Time(_) => 1,
        };
        let hold = s.run.stop_rest_time.unwrap_or(20.0 * every as f64 * dt);
        RestDetector::with_limit(ratio * weight * mean_d, hold)
    });
    if !leader {
        // Rank 0 holds the whole state; here it was needed only to take this part.
        sim.state = State {
            time: sim.state.time,
            step: sim.state.step,
            ..Default::default()
        };
    }
    let stepper = {
        let mut observers = watchers(&mut history, &mut frames, &mut probes, &mut rest);
        if let Some(r) = &resume {
            agreed(
                &sim,
                restore_observers(&mut observers, &r.progress.observers),
            )?;
        }
        Stepper::start(&sim, &mut observers, plan, counters)?
    };
    Ok(Dem3Run {
        sim,
        stepper,
        history,
        frames,
        probes,
        leader,
        rest,
        name: s.name.clone(),
        out,
        dt_critical,
    })
}

impl Live for Dem3Run {
    type S = Dem3;

    fn parts(&mut self) -> (&mut Dem3, &mut Stepper, Vec<&mut dyn Observer<Dem3>>) {
        let o = watchers(
            &mut self.history,
            &mut self.frames,
            &mut self.probes,
            &mut self.rest,
        );
        (&mut self.sim, &mut self.stepper, o)
    }

    fn history(&self) -> &History {
        &self.history.history
    }

    fn conclude(&mut self, outcome: Outcome, threads: usize) -> Result<Finished, RunError> {
        let (sim, out) = (&self.sim, &self.out);
        let h = &self.history.history;
        if !self.leader {
            // Another rank than 0: its part is done, rank 0 writes.
            let costs = Costs {
                dt: sim.dt,
                dt_critical: self.dt_critical,
                threads,
                frames: 0,
            };
            let at = (self.name.as_str(), out.as_path());
            return Ok(crate::ranks::finished_elsewhere(at, sim, outcome, costs));
        }
        super::output::write_plots(&out.join("plots"), h, &sim.setup, &sim.state)?;
        super::ledger::plot(&out.join("plots"), h)?;
        let mut outcome = outcome;
        if let Some(l) = super::ledger::figures(h) {
            outcome.report.figures.insert("energy_ledger".into(), l);
        }
        let mut counts = serde_json::Map::new();
        counts.insert("dimensions".into(), 3.into());
        counts.insert("neighbour_builds".into(), sim.state.contacts.builds.into());
        if let Some(part) = &sim.ranks {
            // Of this segment of the run, as in 2D.
            crate::ranks::count_balance(&mut counts, part.dec.imbalance(), part.dec.rebalances());
            part.comm().insert_into(&mut counts);
        }
        if let Some(p) = &sim.pour {
            counts.insert("poured".into(), p.inserted().into());
            counts.insert("poured_mass_kg".into(), p.inserted_mass().into());
        }
        let costs = Costs {
            dt: sim.dt,
            dt_critical: self.dt_critical,
            threads,
            frames: self.frames.count(),
        };
        let mut sum = summary(&self.name, "dem", sim, &outcome, costs, counts);
        if matches!(outcome.status, Status::Paused | Status::Interrupted) {
            sum.message = Some(resume_hint(outcome.clock.step, out));
        }
        finish(sum, outcome.status, out)
    }
}

/// The observers of a run, in the order they see each step: the probes first, so that
/// a failure of rank 0's writers cannot leave the other ranks waiting in their gathers.
fn watchers<'a>(
    history: &'a mut HistoryRecorder,
    frames: &'a mut FrameRecorder,
    probes: &'a mut Probes,
    rest: &'a mut Option<RestDetector>,
) -> Vec<&'a mut dyn Observer<Dem3>> {
    let mut o: Vec<&mut dyn Observer<Dem3>> = vec![probes, history, frames];
    o.extend(rest.as_mut().map(|r| r as &mut dyn Observer<Dem3>));
    o
}

impl Observer<Dem3> for RestDetector {
    fn on_sample(&mut self, sim: &Dem3, d: &Diagnostics) -> anyhow::Result<Flow> {
        Ok(self.judge(sim.state.time, d.kinetic()))
    }

    fn save(&self) -> Option<(&'static str, toml::Value)> {
        toml::Value::try_from(self).ok().map(|v| ("rest", v))
    }

    fn restore(&mut self, state: toml::Value) -> anyhow::Result<()> {
        *self = state.try_into()?;
        Ok(())
    }
}
