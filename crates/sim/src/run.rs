//! Running a scenario as the command line does, from any Rust program: parse,
//! validate, assemble, run with every observer, write the outputs and the summary.
//!
//! ```no_run
//! use grains_sim::{run, RunOptions, Source};
//! let src = Source::read("examples/dem/head_on.toml".as_ref()).unwrap();
//! let done = run::run(&src, RunOptions::new("runs/head_on")).unwrap();
//! assert!(done.checks.iter().all(|c| c.pass));
//! ```

use crate::driver::{self, Observer, Outcome, Progress, Silent, Simulation, Status};
use crate::scenario::{self, Scenario};
use crate::source::Source;
use crate::summary::Summary;
use crate::{blast, dem, dem3d, mpm};
use grains_core::atomic::write_atomic;
use grains_core::checks::Check;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

/// How a run is driven and where it writes.
pub struct RunOptions<'a> {
    /// Output directory.
    pub out: PathBuf,
    /// Worker threads in use (reported in the summary).
    pub threads: usize,
    /// Stop with a checkpoint once this step is reached (DEM and FEM–DEM).
    pub stop_at_step: Option<u64>,
    /// Set by a signal handler to stop (with a checkpoint where the engine has one).
    pub interrupt: Option<&'a AtomicBool>,
    /// Where progress goes.
    pub progress: Box<dyn Progress + 'a>,
}

impl RunOptions<'_> {
    /// Writes into `out`, on the current thread pool, silently.
    pub fn new(out: impl Into<PathBuf>) -> Self {
        RunOptions {
            out: out.into(),
            threads: rayon::current_num_threads(),
            stop_at_step: None,
            interrupt: None,
            progress: Box::new(Silent),
        }
    }
}

/// Why a run could not be done.
#[derive(Debug)]
pub enum RunError {
    /// The input was refused (nothing was written): one line naming the key, the value
    /// and what is allowed.
    Input(String),
    /// Writing the outputs failed.
    Output(anyhow::Error),
}

impl std::fmt::Display for RunError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RunError::Input(m) => write!(f, "{m}"),
            RunError::Output(e) => write!(f, "{e:#}"),
        }
    }
}

impl std::error::Error for RunError {}

impl From<anyhow::Error> for RunError {
    fn from(e: anyhow::Error) -> Self {
        RunError::Output(e)
    }
}

/// What a run left behind.
#[derive(Clone, Debug)]
pub struct Finished {
    /// How it ended (`summary.status`).
    pub status: Status,
    /// Its checks with their verdicts.
    pub checks: Vec<Check>,
    /// The summary as written.
    pub summary: Summary,
    /// Where the outputs are.
    pub out: PathBuf,
}

/// Runs the scenario `src` with `opts`: every output goes into `opts.out`.
pub fn run(src: &Source, mut opts: RunOptions) -> Result<Finished, RunError> {
    open(src, &mut opts)?.run_to_end(&mut opts, src)
}

/// Runs the scenario `src` as one rank of several (`mpirun -np N grains run`), `link`
/// carrying the messages: rank 0 writes every output, the others write only their
/// pieces of the frames. DEM scenarios, 2D and 3D (docs/parallel.md); anything else is
/// refused with one line, on every rank alike.
pub fn run_on(
    src: &Source,
    mut opts: RunOptions,
    link: dem::ranks::Link,
) -> Result<Finished, RunError> {
    let o = &mut opts;
    let mut live = match scenario::parse(src).map_err(RunError::Input)? {
        Scenario::Dem(s) => AnyRun::Dem(Box::new(dem::run::open_on(&s, src, o, None, Some(link))?)),
        Scenario::Dem3(s) => {
            AnyRun::Dem3(Box::new(dem3d::run::open_on(&s, src, o, None, Some(link))?))
        }
        Scenario::FemDem(s) => {
            AnyRun::FemDem(Box::new(blast::run::open_on(&s, src, o, None, Some(link))?))
        }
        other => {
            return Err(RunError::Input(format!(
                "{}: engine = \"{}\" is not supported on several ranks yet (docs/parallel.md); allowed: DEM scenarios (2D and 3D) and FEM–DEM rings, or 1 rank",
                src.origin,
                other.engine()
            )));
        }
    };
    live.run_to_end(&mut opts, src)
}

/// Continues the run in `dir` from its checkpoint.
pub fn resume(dir: &Path, mut opts: RunOptions) -> Result<Finished, RunError> {
    let (mut live, src) = open_resumed(dir, &mut opts)?;
    live.run_to_end(&mut opts, &src)
}

/// A run of any engine in progress.
pub enum AnyRun {
    /// `engine = "dem"`.
    Dem(Box<dem::run::DemRun>),
    /// `engine = "dem"`, `dim = 3`.
    Dem3(Box<dem3d::run::Dem3Run>),
    /// `engine = "mpm"`.
    Mpm(Box<mpm::run::MpmRun>),
    /// `engine = "fem_dem"`.
    FemDem(Box<blast::run::BlastRun>),
}

impl AnyRun {
    /// Steps the run to the end of its plan (or until it stops) and concludes it.
    pub fn run_to_end(
        &mut self,
        opts: &mut RunOptions,
        src: &Source,
    ) -> Result<Finished, RunError> {
        match self {
            AnyRun::Dem(l) => run_live(l.as_mut(), opts, src),
            AnyRun::Dem3(l) => run_live(l.as_mut(), opts, src),
            AnyRun::Mpm(l) => run_live(l.as_mut(), opts, src),
            AnyRun::FemDem(l) => run_live(l.as_mut(), opts, src),
        }
    }
}

/// Prepares the run of the scenario `src` into `opts.out` (validated, assembled, its
/// output directory started).
pub fn open(src: &Source, opts: &mut RunOptions) -> Result<AnyRun, RunError> {
    Ok(match scenario::parse(src).map_err(RunError::Input)? {
        Scenario::Dem(s) => AnyRun::Dem(Box::new(dem::run::open(&s, src, opts, None)?)),
        Scenario::Dem3(s) => AnyRun::Dem3(Box::new(dem3d::run::open(&s, src, opts, None)?)),
        Scenario::Mpm(s) => AnyRun::Mpm(Box::new(mpm::run::open(&s, src, opts)?)),
        Scenario::FemDem(s) => AnyRun::FemDem(Box::new(blast::run::open(&s, src, opts, None)?)),
    })
}

/// Prepares the continuation of the run in `dir` from its checkpoint (`opts.out`
/// becomes `dir`); also returns the scenario as the run reads it.
pub fn open_resumed(dir: &Path, opts: &mut RunOptions) -> Result<(AnyRun, Source), RunError> {
    let (scn, src) = resumable(dir, opts, true)?;
    match scn {
        Scenario::Dem(s) => {
            let saved = dem::run::load_checkpoint(&s, &src, dir)?;
            let src = from_base(src, saved.base());
            let live = dem::run::open(&s, &src, opts, Some(saved))?;
            Ok((AnyRun::Dem(Box::new(live)), src))
        }
        Scenario::FemDem(s) => {
            let saved = blast::run::load_checkpoint(&src, dir)?;
            let src = from_base(src, saved.base());
            let live = blast::run::open(&s, &src, opts, Some(saved))?;
            Ok((AnyRun::FemDem(Box::new(live)), src))
        }
        Scenario::Dem3(s) => {
            let saved = dem3d::run::load_checkpoint(&s, &src, dir)?;
            let src = from_base(src, saved.base());
            let live = dem3d::run::open(&s, &src, opts, Some(saved))?;
            Ok((AnyRun::Dem3(Box::new(live)), src))
        }
        other => Err(RunError::Input(format!(
            "{}: resume is supported for engine = \"dem\" and \"fem_dem\" runs, this one is engine = \"{}\"",
            dir.display(),
            other.engine()
        ))),
    }
}

/// Continues the run in `dir` from its checkpoint as one rank of several (`mpirun -np
/// N grains resume`), `link` carrying the messages: every rank reads the checkpoint
/// (written by any number of ranks) and takes its box of it; rank 0 writes every
/// output. DEM runs (2D and 3D); anything else is refused with one line, on every rank.
pub fn resume_on(
    dir: &Path,
    mut opts: RunOptions,
    link: dem::ranks::Link,
) -> Result<Finished, RunError> {
    use grains_dem::Reduce;
    // One rank clears what an earlier write left: the others must not race it.
    let (scn, src) = resumable(dir, &mut opts, link.rank() == 0)?;
    let o = &mut opts;
    let (mut live, src) = match scn {
        Scenario::Dem(s) => {
            let saved = dem::run::load_checkpoint(&s, &src, dir)?;
            let src = from_base(src, saved.base());
            let live = dem::run::open_on(&s, &src, o, Some(saved), Some(link))?;
            (AnyRun::Dem(Box::new(live)), src)
        }
        Scenario::Dem3(s) => {
            let saved = dem3d::run::load_checkpoint(&s, &src, dir)?;
            let src = from_base(src, saved.base());
            let live = dem3d::run::open_on(&s, &src, o, Some(saved), Some(link))?;
            (AnyRun::Dem3(Box::new(live)), src)
        }
        Scenario::FemDem(s) => {
            let saved = blast::run::load_checkpoint(&src, dir)?;
            let src = from_base(src, saved.base());
            let live = blast::run::open_on(&s, &src, o, Some(saved), Some(link))?;
            (AnyRun::FemDem(Box::new(live)), src)
        }
        other => {
            return Err(RunError::Input(format!(
                "{}: resume on several ranks is supported for DEM runs (2D and 3D) and FEM–DEM rings, this one is engine = \"{}\"; allowed: 1 rank",
                dir.display(),
                other.engine()
            )));
        }
    };
    live.run_to_end(&mut opts, &src)
}

/// The scenario of the run directory `dir`, parsed, unless the run there already
/// finished; `opts.out` becomes `dir`, and with `clean` what a checkpoint write cut
/// short left there is removed.
fn resumable(
    dir: &Path,
    opts: &mut RunOptions,
    clean: bool,
) -> Result<(Scenario, Source), RunError> {
    let src = Source::read(&dir.join("scenario.toml")).map_err(|e| {
        RunError::Input(format!(
            "{e} (is {} a grains run directory?)",
            dir.display()
        ))
    })?;
    if let Ok(text) = std::fs::read_to_string(dir.join("summary.json")) {
        let status = serde_json::from_str::<serde_json::Value>(&text)
            .ok()
            .and_then(|v| v["status"].as_str().map(String::from));
        if let Some(s @ ("completed" | "at_rest")) = status.as_deref() {
            return Err(RunError::Input(format!(
                "{}: this run already finished (summary.status = \"{s}\"); there is nothing to resume. Run it again with `grains run` to start over",
                dir.display()
            )));
        }
    }
    opts.out = dir.to_path_buf();
    if clean {
        crate::checkpoint::remove_stale_temps(dir);
    }
    let scn = scenario::parse(&src).map_err(RunError::Input)?;
    Ok((scn, src))
}

/// The scenario copy of a run directory, its relative paths read from where the
/// original's were (as the checkpoint recorded it), when that directory still exists.
fn from_base(mut src: Source, base: Option<&Path>) -> Source {
    if let Some(b) = base.filter(|b| b.is_dir()) {
        src.base = b.to_path_buf();
    }
    src
}

/// Prepares a fresh output directory: creates it, copies the scenario into it and
/// removes what an earlier run there left that this one would not overwrite.
pub fn fresh_out(out: &Path, text: &str) -> anyhow::Result<()> {
    use anyhow::Context;
    std::fs::create_dir_all(out)
        .with_context(|| format!("cannot create output directory {}", out.display()))?;
    write_atomic(&out.join("scenario.toml"), text.as_bytes())?;
    crate::checkpoint::remove_stale_temps(out);
    let stale = out.join(crate::checkpoint::FILE);
    if stale.exists() {
        std::fs::remove_file(&stale)
            .with_context(|| format!("cannot remove the stale {}", stale.display()))?;
    }
    let plots = out.join("plots");
    if plots.exists() {
        std::fs::remove_dir_all(&plots)
            .with_context(|| format!("cannot clear {}", plots.display()))?;
    }
    Ok(())
}

/// The history and frame recorders of a run and the loop's counters: started in a fresh
/// output directory `out` (the scenario `text` copied in), or reopened where the
/// checkpoint whose counters are `resumed` left them.
pub fn recorders<S: crate::history::Recorded + crate::frames::Framed>(
    out: &Path,
    text: &str,
    sim: &mut S,
    plan: &driver::Plan,
    resumed: Option<&driver::Counters>,
) -> Result<
    (
        crate::history::HistoryRecorder,
        crate::frames::FrameRecorder,
        driver::Counters,
    ),
    RunError,
> {
    use crate::frames::FrameRecorder;
    use crate::history::HistoryRecorder;
    Ok(match resumed {
        None => {
            fresh_out(out, text)?;
            let history = HistoryRecorder::create(out, sim)?;
            let frames = FrameRecorder::create(out, sim).map_err(anyhow::Error::from)?;
            (history, frames, driver::Counters::fresh(plan))
        }
        Some(c) => {
            let clock = sim.clock();
            let history = HistoryRecorder::reopen(out, sim, clock.step)?;
            let frames = FrameRecorder::resume(out, sim, clock.time, c.frames)
                .map_err(anyhow::Error::from)?;
            (history, frames, c.clone())
        }
    })
}

/// The parts of a summary every engine fills the same way.
pub struct Costs {
    /// Time step (s).
    pub dt: f64,
    /// Largest stable step (s).
    pub dt_critical: f64,
    /// Threads in use.
    pub threads: usize,
    /// Frames written.
    pub frames: usize,
}

/// The summary of an outcome.
pub fn summary<S: Simulation>(
    name: &str,
    engine: &'static str,
    sim: &S,
    o: &Outcome,
    costs: Costs,
    counts: serde_json::Map<String, serde_json::Value>,
) -> Summary {
    let n = sim.count();
    Summary {
        name: name.to_string(),
        engine,
        status: o.status.name().into(),
        message: match &o.status {
            Status::Unstable(m) => Some(m.clone()),
            _ => None,
        },
        particles: n,
        steps: o.clock.step,
        time: o.clock.time,
        dt: costs.dt,
        dt_critical: costs.dt_critical,
        threads: costs.threads,
        wall_time_s: o.wall_time_s,
        particle_steps_per_s: n as f64 * o.steps_run as f64 / o.wall_time_s.max(1e-12),
        frames: costs.frames,
        state_hash: format!("{:016x}", sim.state_hash()),
        counts,
        figures: o.report.figures.clone(),
        checks: o.report.checks.clone(),
    }
}

/// Writes the summary and returns what the caller needs.
pub fn finish(summary: Summary, status: Status, out: &Path) -> Result<Finished, RunError> {
    summary.write(&out.join("summary.json"))?;
    Ok(Finished {
        checks: summary.checks.clone(),
        status,
        summary,
        out: out.to_path_buf(),
    })
}

/// The message of a run stopped with a checkpoint.
pub fn resume_hint(step: u64, out: &Path) -> String {
    format!(
        "stopped at step {step} with a checkpoint; continue with `grains resume {}`",
        out.display()
    )
}

/// An engine's run in progress, as `grains run` drives it: prepared (output directory
/// started, first frame written) by the engine's `open`, stepped through
/// [`driver::Stepper`] with every observer, and concluded into its plots and summary.
/// The command line ([`run_live`]) and the library façade ([`crate::session`]) both go
/// through it.
pub trait Live: Send {
    /// The engine's simulation.
    type S: Simulation;
    /// The simulation, the loop and the observers, to step them together.
    fn parts(
        &mut self,
    ) -> (
        &mut Self::S,
        &mut driver::Stepper,
        Vec<&mut dyn Observer<Self::S>>,
    );
    /// The history so far.
    fn history(&self) -> &grains_core::history::History;
    /// Writes the end-of-run outputs (plots, figures, summary) for `outcome`.
    fn conclude(&mut self, outcome: Outcome, threads: usize) -> Result<Finished, RunError>;
}

/// The loop's controls from the options of a run of `src`.
pub fn control<'a>(opts: &'a mut RunOptions, src: &'a Source) -> driver::Control<'a> {
    let base = if src.base.as_os_str().is_empty() {
        Path::new(".")
    } else {
        src.base.as_path()
    };
    driver::Control {
        stop_at_step: opts.stop_at_step,
        interrupt: opts.interrupt,
        progress: opts.progress.as_mut(),
        checkpoint_dir: Some(opts.out.clone()),
        scenario_text: &src.text,
        scenario_base: std::fs::canonicalize(base).ok(),
    }
}

/// Steps `live` to the end of its plan (or until it stops) and concludes it.
pub fn run_live<L: Live>(
    live: &mut L,
    opts: &mut RunOptions,
    src: &Source,
) -> Result<Finished, RunError> {
    let threads = opts.threads;
    let mut control = control(opts, src);
    let (sim, stepper, mut observers) = live.parts();
    let mut status = Status::Completed;
    // Stepping from inside the pool keeps each parallel pass from waking it from outside.
    rayon::scope(|_| -> anyhow::Result<()> {
        while !stepper.over(sim) {
            if let Some(s) = stepper.step(sim, &mut observers, &mut control)? {
                status = s;
                break;
            }
        }
        Ok(())
    })?;
    let outcome = stepper.finish(sim, &mut observers, status, &mut control)?;
    drop(observers);
    let done = live.conclude(outcome, threads);
    // Rank 0 wrote the plots and the summary: every rank ends as it did.
    driver::agreed(live.parts().0, done)
}
