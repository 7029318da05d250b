//! The one run loop every engine uses.
//!
//! A [`Simulation`] advances itself one step at a time and measures itself on request;
//! [`Observer`]s watch it (history, frames, probes, snapshots, stop rules) and add their
//! figures and checks to the [`Report`] at the end. The [`Plan`] says when to sample,
//! when to write frames and checkpoints, and when the run is over; [`Control`] carries
//! what comes from outside (a pause step, an interrupt flag, a progress display).
//!
//! Per step: `advance → on_step`; at sample times: `sample → instability test →
//! on_sample` (an observer may stop the run, e.g. at rest); at frame and snapshot times:
//! `on_frame`; then progress, and pause/interrupt/checkpoint. At the end, a run that
//! finished gets its last frame, and every observer reports.

use crate::checkpoint::{self, Progress as SavedProgress};
use glam::DVec2;
use grains_core::checks::Check;
use serde::{Deserialize, Serialize};
use std::borrow::Cow;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// Where a run stands.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Clock {
    /// Simulated time (s).
    pub time: f64,
    /// Steps taken.
    pub step: u64,
}

/// The particles of a run, as any analysis reads them (SI units, per unit thickness).
/// Engines without a field of their own compute it on demand (`Cow::Owned`).
#[derive(Clone, Debug)]
pub struct ParticleView<'a> {
    /// Stable ids (creation order).
    pub id: &'a [u32],
    /// Positions (m).
    pub pos: &'a [DVec2],
    /// Velocities (m/s).
    pub vel: &'a [DVec2],
    /// Radii (m); for material points, the radius of a disk of the point's volume.
    pub radius: Cow<'a, [f64]>,
    /// Masses (kg/m).
    pub mass: Cow<'a, [f64]>,
}

/// A running simulation, stepped by [`run`] (on a worker of the thread pool, hence
/// `Send`).
pub trait Simulation: Send {
    /// What one sample measures (energies, contacts, ...), shared by every observer.
    type Sample;

    /// Time and step count.
    fn clock(&self) -> Clock;
    /// Advances one step; `Err` names what went wrong when the state broke down.
    fn advance(&mut self) -> Result<(), String>;
    /// Measures the present state (and updates whatever the measurement tracks from one
    /// sample to the next, such as an unwrapped rotation angle).
    fn sample(&mut self) -> Self::Sample;
    /// Why the sampled state counts as unstable, if it does.
    fn unstable(&self, sample: &Self::Sample) -> Option<String>;
    /// The particles as they are now.
    fn particles(&self) -> ParticleView<'_>;
    /// How many particles there are (a 3D run's are not in its 2D [`ParticleView`]).
    fn count(&self) -> usize {
        self.particles().id.len()
    }
    /// Fingerprint of the whole state: equal fingerprints mean bitwise-equal runs.
    fn state_hash(&self) -> u64;
    /// The engine state as checkpoint bytes, when the engine can be resumed.
    fn checkpoint(&self) -> Option<Vec<u8>> {
        None
    }
    /// Makes the whole state readable by the observers, before a frame, a checkpoint
    /// and at the end: a run spread over ranks gathers it on rank 0 there (so every rank
    /// calls this at the same steps), not at every step.
    fn gather(&mut self) {}
    /// Whether the observers of a frame of `kind` read the whole state, so that a run
    /// spread over ranks gathers it before that frame; not when its ranks write their
    /// own pieces of the frame.
    fn frame_reads_whole(&self, _kind: FrameKind) -> bool {
        true
    }
    /// Whether `flag` holds on any rank of a run spread over ranks (every rank calls
    /// this at the same steps); on one rank, `flag` itself.
    fn agree(&self, flag: bool) -> bool {
        flag
    }
    /// Ranks the run is spread over.
    fn ranks(&self) -> usize {
        1
    }
}

/// Steps between two readings of the interrupt flag on a run spread over ranks. A
/// signal reaches the ranks at different steps (or one rank only), so they read the
/// flag together, through one all-gather of a word at these steps, and all stop at the
/// same one. Beside the per-step exchange of ghosts the cost is nil; a run on one rank
/// reads its flag at every step.
pub const AGREE_EVERY: u64 = 16;

/// `r` as every rank of a run spread over ranks sees it. Rank 0 alone writes the
/// outputs, so its failure must stop every rank at the same point rather than leave
/// the others waiting for it: every rank calls this at the same steps, and where any
/// failed, all fail (the others with a line pointing at rank 0's message).
pub fn agreed<S: Simulation, T, E: From<anyhow::Error>>(sim: &S, r: Result<T, E>) -> Result<T, E> {
    if sim.agree(r.is_err()) && r.is_ok() {
        return Err(anyhow::anyhow!(
            "stopped with the other ranks: rank 0 could not write the run's outputs (its message says why)"
        )
        .into());
    }
    r
}

/// What an observer asks of the run after a sample.
#[derive(Clone, Debug, PartialEq)]
pub enum Flow {
    /// Go on.
    Continue,
    /// Stop now with this status.
    Stop(Status),
}

/// Why a frame is written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameKind {
    /// On the regular schedule.
    Regular,
    /// At one of the plan's snapshot times.
    Snapshot,
    /// The state at the end of a run that finished.
    Final,
}

/// Watches a run. Every method has a default that does nothing.
pub trait Observer<S: Simulation>: Send {
    /// After every step (cheap work only).
    fn on_step(&mut self, _sim: &S) {}
    /// At sample times, with the sample.
    fn on_sample(&mut self, _sim: &S, _sample: &S::Sample) -> anyhow::Result<Flow> {
        Ok(Flow::Continue)
    }
    /// At frame times.
    fn on_frame(&mut self, _sim: &S, _kind: FrameKind) -> anyhow::Result<()> {
        Ok(())
    }
    /// At the end: add figures and checks to the report. Called for every status.
    fn on_end(&mut self, _sim: &S, _status: &Status, _report: &mut Report) -> anyhow::Result<()> {
        Ok(())
    }
    /// Makes what this observer has written so far durable, just before a checkpoint
    /// that will count on it is written (a resumed run reads it back).
    fn persist(&mut self) -> anyhow::Result<()> {
        Ok(())
    }
    /// What this observer must carry across a checkpoint (name, state); `None` for none.
    fn save(&self) -> Option<(&'static str, toml::Value)> {
        None
    }
    /// Takes back what [`Observer::save`] gave, when a run resumes.
    fn restore(&mut self, _state: toml::Value) -> anyhow::Result<()> {
        Ok(())
    }
}

/// How a run ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Status {
    /// Ran to its end.
    Completed,
    /// Stopped early because it came to rest.
    AtRest,
    /// Stopped because the state broke down; the message says how and when.
    Unstable(String),
    /// Stopped at the requested step, with a checkpoint.
    Paused,
    /// Stopped by a signal, with a checkpoint (where the engine supports one).
    Interrupted,
}

impl Status {
    /// The value of `summary.status`.
    pub fn name(&self) -> &'static str {
        match self {
            Status::Completed => "completed",
            Status::AtRest => "at_rest",
            Status::Unstable(_) => "unstable",
            Status::Paused => "paused",
            Status::Interrupted => "interrupted",
        }
    }

    /// Whether the run reached an end of its own (its checks mean something).
    pub fn finished(&self) -> bool {
        matches!(self, Status::Completed | Status::AtRest)
    }
}

/// A recurring event: every so many steps, or every so much simulated time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Every {
    /// On steps that are multiples of this.
    Steps(u64),
    /// At the first step at or past each multiple of this time (s).
    Time(f64),
}

/// When a run ends.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Horizon {
    /// After this many steps.
    Steps(u64),
    /// Once the time reaches this (s).
    Time(f64),
}

impl Horizon {
    fn reached(&self, c: Clock) -> bool {
        match *self {
            Horizon::Steps(n) => c.step >= n,
            Horizon::Time(t) => c.time >= t * (1.0 - 1e-12),
        }
    }

    fn fraction(&self, c: Clock) -> f64 {
        match *self {
            Horizon::Steps(n) => c.step as f64 / n.max(1) as f64,
            Horizon::Time(t) => c.time / t,
        }
    }
}

/// The schedule of a run.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// When the run is over.
    pub horizon: Horizon,
    /// History samples (also where stability is judged).
    pub samples: Every,
    /// Regular frames.
    pub frames: Every,
    /// Extra frames at these times (s), ascending.
    pub snapshots: Vec<f64>,
    /// Checkpoints every so many steps.
    pub checkpoint_every: Option<u64>,
}

/// A progress display (the CLI's bar; nothing in a library call).
pub trait Progress: Send {
    /// A line about what is about to run (sizes, step, threads).
    fn announce(&mut self, _line: &str) {}
    /// How far the run has got (0 to 1) and where it stands.
    fn update(&mut self, done: f64, clock: Clock);
    /// How far a stage before the run (making its packing) has got, 0 to 1.
    fn stage(&mut self, _what: &str, _done: f64) {}
    /// The run is over.
    fn finish(&mut self) {}
}

/// No display.
pub struct Silent;

impl Progress for Silent {
    fn update(&mut self, _done: f64, _clock: Clock) {}
}

/// What reaches the loop from outside.
pub struct Control<'a> {
    /// Stop with a checkpoint once this step is reached.
    pub stop_at_step: Option<u64>,
    /// Set (by a signal handler) to stop with a checkpoint.
    pub interrupt: Option<&'a AtomicBool>,
    /// Where progress goes.
    pub progress: &'a mut dyn Progress,
    /// Where checkpoints are written (the run directory); none: no checkpoints.
    pub checkpoint_dir: Option<PathBuf>,
    /// The scenario text the checkpoints belong to.
    pub scenario_text: &'a str,
    /// The directory its relative paths start at (absolute), kept in checkpoints.
    pub scenario_base: Option<PathBuf>,
}

/// Figures and checks of a run, filled by the observers at the end.
#[derive(Clone, Debug, Default)]
pub struct Report {
    /// Named figures for `summary.json`.
    pub figures: serde_json::Map<String, serde_json::Value>,
    /// Checks, in the scenario's order.
    pub checks: Vec<Check>,
}

/// What a run did.
#[derive(Clone, Debug)]
pub struct Outcome {
    /// How it ended.
    pub status: Status,
    /// Where it ended.
    pub clock: Clock,
    /// Steps taken in this and earlier segments of the run.
    pub steps_run: u64,
    /// Wall-clock seconds of the time loop, earlier segments included.
    pub wall_time_s: f64,
    /// Figures and checks.
    pub report: Report,
}

/// Counters that survive a checkpoint.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Counters {
    /// Frames written so far.
    pub frames: usize,
    /// Step of the last frame.
    pub last_frame_step: Option<u64>,
    /// Next sample time (time-based plans).
    pub next_sample: f64,
    /// Next frame time (time-based plans).
    pub next_frame: f64,
    /// Snapshots taken.
    pub snapshots_done: usize,
    /// Wall-clock seconds spent in earlier segments.
    pub wall_time: f64,
    /// Steps run in earlier segments.
    pub steps_before: u64,
}

impl Counters {
    /// The counters of a run that has not started: the first time-based sample and
    /// frame one interval in.
    pub fn fresh(plan: &Plan) -> Self {
        let first = |e: Every| match e {
            Every::Time(dt) => dt,
            Every::Steps(_) => 0.0,
        };
        Counters {
            next_sample: first(plan.samples),
            next_frame: first(plan.frames),
            ..Default::default()
        }
    }
}

/// Whether a recurring event is due at `c` (and, for time-based events, moves `next`
/// past it).
fn due(every: Every, c: Clock, next: &mut f64) -> bool {
    match every {
        Every::Steps(k) => c.step.is_multiple_of(k.max(1)),
        Every::Time(dt) => {
            if c.time >= *next {
                while *next <= c.time {
                    *next += dt;
                }
                true
            } else {
                false
            }
        }
    }
}

/// Runs `sim` to the end of `plan`, feeding `observers`. `counters` are
/// [`Counters::fresh`] for a new run and the checkpoint's for a resumed one. Observer and checkpoint I/O errors are
/// returned; a breakdown of the state is a [`Status::Unstable`] outcome.
pub fn run<S: Simulation>(
    sim: &mut S,
    observers: &mut [&mut dyn Observer<S>],
    plan: &Plan,
    control: &mut Control,
    counters: Counters,
) -> anyhow::Result<Outcome> {
    let mut stepper = Stepper::start(sim, observers, plan.clone(), counters)?;
    let mut status = Status::Completed;
    // Stepping from inside the pool keeps each parallel pass from waking it from outside.
    rayon::scope(|_| -> anyhow::Result<()> {
        while !stepper.over(sim) {
            if let Some(s) = stepper.step(sim, observers, control)? {
                status = s;
                break;
            }
        }
        Ok(())
    })?;
    stepper.finish(sim, observers, status, control)
}

/// The run loop taken apart, so that a caller can step a run a few steps at a time
/// (the library façade, [`crate::session`]) and still feed every observer exactly as
/// [`run`] does: [`Stepper::start`], then [`Stepper::step`] until it says stop or the
/// plan is over, then [`Stepper::finish`].
pub struct Stepper {
    /// The schedule.
    pub plan: Plan,
    /// The loop's counters (frames, next sample and frame times, earlier segments).
    pub counters: Counters,
    first_step: u64,
    /// Wall-clock seconds spent stepping in this segment.
    stepping: f64,
}

impl Stepper {
    /// Starts (or resumes) a run: a run that has not started yet writes its first
    /// frame, the initial state.
    pub fn start<S: Simulation>(
        sim: &S,
        observers: &mut [&mut dyn Observer<S>],
        plan: Plan,
        mut counters: Counters,
    ) -> anyhow::Result<Self> {
        if counters.last_frame_step.is_none() {
            agreed(
                sim,
                frame(sim, observers, FrameKind::Regular, &mut counters),
            )?;
        }
        Ok(Stepper {
            plan,
            counters,
            first_step: sim.clock().step,
            stepping: 0.0,
        })
    }

    /// Whether the plan's end is reached.
    pub fn over<S: Simulation>(&self, sim: &S) -> bool {
        self.plan.horizon.reached(sim.clock())
    }

    /// How far the plan has got, 0 to 1.
    pub fn fraction(&self, c: Clock) -> f64 {
        self.plan.horizon.fraction(c)
    }

    /// One step with everything the plan wants at it (samples, frames, checkpoints);
    /// `Some` when the run must stop there, with why.
    pub fn step<S: Simulation>(
        &mut self,
        sim: &mut S,
        observers: &mut [&mut dyn Observer<S>],
        control: &mut Control,
    ) -> anyhow::Result<Option<Status>> {
        let started = Instant::now();
        let r = self.step_timed(sim, observers, control);
        self.stepping += started.elapsed().as_secs_f64();
        r
    }

    fn step_timed<S: Simulation>(
        &mut self,
        sim: &mut S,
        observers: &mut [&mut dyn Observer<S>],
        control: &mut Control,
    ) -> anyhow::Result<Option<Status>> {
        let plan = &self.plan;
        let counters = &mut self.counters;
        if let Err(why) = sim.advance() {
            return Ok(Some(unstable_at(sim.clock(), &why)));
        }
        for o in observers.iter_mut() {
            o.on_step(sim);
        }
        let c = sim.clock();
        let end = plan.horizon.reached(c);
        if due(plan.samples, c, &mut counters.next_sample) || end {
            let sample = sim.sample();
            if let Some(why) = sim.unstable(&sample) {
                return Ok(Some(unstable_at(c, &why)));
            }
            let mut status = Status::Completed;
            let watched = observers.iter_mut().try_for_each(|o| {
                if let Flow::Stop(s) = o.on_sample(sim, &sample)? {
                    status = s;
                }
                anyhow::Ok(())
            });
            agreed(sim, watched)?;
            if status != Status::Completed {
                return Ok(Some(status));
            }
        }
        let regular = due(plan.frames, c, &mut counters.next_frame);
        let mut snapped = false;
        while counters.snapshots_done < plan.snapshots.len()
            && c.time >= plan.snapshots[counters.snapshots_done] * (1.0 - 1e-9)
        {
            counters.snapshots_done += 1;
            snapped = true;
        }
        let kind = match (snapped, regular) {
            (true, _) => Some(FrameKind::Snapshot),
            (false, true) => Some(FrameKind::Regular),
            (false, false) => None,
        };
        let gathered = kind.is_some_and(|k| sim.frame_reads_whole(k));
        if gathered {
            sim.gather();
        }
        // A snapshot on a step the schedule also wants is one frame, not the same
        // state twice in the series.
        if let Some(kind) = kind {
            agreed(sim, frame(sim, observers, kind, counters))?;
        }
        control.progress.update(plan.horizon.fraction(c), c);
        let pause = control.stop_at_step.is_some_and(|s| c.step >= s);
        let raised = || control.interrupt.is_some_and(|f| f.load(Ordering::Relaxed));
        let signal = if sim.ranks() == 1 {
            raised()
        } else {
            c.step.is_multiple_of(AGREE_EVERY) && sim.agree(raised())
        };
        let periodic = plan
            .checkpoint_every
            .is_some_and(|k| c.step.is_multiple_of(k.max(1)));
        if pause || signal || periodic {
            // A checkpoint holds the whole state, which a run spread over ranks has
            // only once gathered (every rank stops here at the same step).
            if !gathered {
                sim.gather();
            }
            agreed(sim, self.checkpoint(sim, observers, control))?;
            if signal {
                return Ok(Some(Status::Interrupted));
            }
            if pause {
                return Ok(Some(Status::Paused));
            }
        }
        Ok(None)
    }

    /// Writes a checkpoint of the run as it stands into `control.checkpoint_dir`
    /// (nothing when the engine has none); `true` when one was written.
    pub fn checkpoint<S: Simulation>(
        &self,
        sim: &S,
        observers: &mut [&mut dyn Observer<S>],
        control: &Control,
    ) -> anyhow::Result<bool> {
        let mut saved = self.counters.clone();
        saved.wall_time += self.stepping;
        saved.steps_before += sim.clock().step - self.first_step;
        save_checkpoint(sim, observers, control, &saved)
    }

    /// Ends the run with `status`: a run that finished gets its last frame, and every
    /// observer reports.
    pub fn finish<S: Simulation>(
        &mut self,
        sim: &mut S,
        observers: &mut [&mut dyn Observer<S>],
        status: Status,
        control: &mut Control,
    ) -> anyhow::Result<Outcome> {
        control.progress.finish();
        sim.gather();
        let clock = sim.clock();
        let wall_time_s = self.counters.wall_time + self.stepping;
        let steps_run = self.counters.steps_before + clock.step - self.first_step;
        let mut report = Report::default();
        let ended = (|| {
            if status.finished() && self.counters.last_frame_step != Some(clock.step) {
                frame(sim, observers, FrameKind::Final, &mut self.counters)?;
            }
            observers
                .iter_mut()
                .try_for_each(|o| o.on_end(sim, &status, &mut report))
        })();
        agreed(sim, ended)?;
        discount(&mut report, &status);
        Ok(Outcome {
            status,
            clock,
            steps_run,
            wall_time_s,
            report,
        })
    }
}

/// A run that did not finish has not earned its checks: an unstable run's fail, with a
/// note saying why; a paused or interrupted run (it will go on) reports none yet.
pub fn discount(report: &mut Report, status: &Status) {
    match status {
        Status::Completed | Status::AtRest => {}
        Status::Paused | Status::Interrupted => report.checks.clear(),
        Status::Unstable(_) => {
            for c in &mut report.checks {
                c.pass = false;
                let why = format!("the run did not finish (status {})", status.name());
                c.note = Some(match c.note.take() {
                    Some(n) => format!("{why}; {n}"),
                    None => why,
                });
            }
        }
    }
}

fn unstable_at(c: Clock, why: &str) -> Status {
    Status::Unstable(format!("step {} (t = {:.6e} s): {why}", c.step, c.time))
}

fn frame<S: Simulation>(
    sim: &S,
    observers: &mut [&mut dyn Observer<S>],
    kind: FrameKind,
    counters: &mut Counters,
) -> anyhow::Result<()> {
    for o in observers.iter_mut() {
        o.on_frame(sim, kind)?;
    }
    counters.frames += 1;
    counters.last_frame_step = Some(sim.clock().step);
    Ok(())
}

fn save_checkpoint<S: Simulation>(
    sim: &S,
    observers: &mut [&mut dyn Observer<S>],
    control: &Control,
    counters: &Counters,
) -> anyhow::Result<bool> {
    let (Some(dir), Some(state)) = (&control.checkpoint_dir, sim.checkpoint()) else {
        return Ok(false);
    };
    for o in observers.iter_mut() {
        o.persist()?;
    }
    let mut saved = SavedProgress {
        counters: counters.clone(),
        observers: toml::Table::new(),
        base: control.scenario_base.clone(),
    };
    for o in observers.iter() {
        if let Some((name, v)) = o.save() {
            saved.observers.insert(name.to_string(), v);
        }
    }
    let path = dir.join(checkpoint::FILE);
    // Its errors name the path.
    checkpoint::save(&path, control.scenario_text, &state, &saved)?;
    Ok(true)
}

/// Hands each observer what it saved in a checkpoint.
pub fn restore_observers<S: Simulation>(
    observers: &mut [&mut dyn Observer<S>],
    saved: &toml::Table,
) -> anyhow::Result<()> {
    for o in observers.iter_mut() {
        if let Some((name, _)) = o.save() {
            if let Some(v) = saved.get(name) {
                o.restore(v.clone())?;
            }
        }
    }
    Ok(())
}

/// The directory a run writes into by default: `runs/<name>`.
pub fn default_out(name: &str) -> PathBuf {
    Path::new("runs").join(name)
}

/// Refuses an output directory that could not be written, before anything is computed:
/// a file where the directory should be, or a nearest existing ancestor that is not a
/// directory or cannot be written in. Leaves nothing behind.
pub fn writable_out(out: &Path) -> Result<(), String> {
    let shown = out.display();
    let mut at = out;
    while !at.exists() {
        at = match at.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
    }
    if !at.is_dir() {
        return Err(format!(
            "output directory {shown}: {} is a file, not a directory",
            at.display()
        ));
    }
    let probe = at.join(format!(".grains-write-probe.{}", std::process::id()));
    match std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
    {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(e) => Err(format!(
            "output directory {shown}: cannot write in {}: {e}",
            at.display()
        )),
    }
}
