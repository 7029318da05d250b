//! The library façade: one handle on a run of any engine, stepped by its caller.
//!
//! A [`Session`] is what `grains run` does, taken apart: it is opened from a scenario
//! (a file, TOML text or a parsed table) through the same validation, assembly and
//! observers as the command line ([`crate::run::open`]), stepped a few steps at a time
//! through the same loop ([`crate::driver::Stepper`]), and concluded into the same
//! outputs. It writes them into a working directory as it goes (a temporary one unless
//! given), which [`Session::write`] copies out. A scenario stepped to its end through a
//! session ends with the command line's `state_hash`.
//!
//! ```no_run
//! use grains_sim::session::Session;
//! let mut sim = Session::from_file("examples/dem/settling_column.toml".as_ref()).unwrap();
//! sim.run(None).unwrap();
//! println!("{:016x}", sim.state_hash());
//! sim.write("runs/settling".as_ref()).unwrap();
//! ```

pub mod data;
mod files;

use crate::driver::{Clock, Status};
use crate::forces::{ForceError, OutsideForce};
use crate::run::{self, AnyRun, Finished, Live, RunError, RunOptions};
use crate::source::Source;
use crate::Simulation;
use data::{ChargeData, Contacts, Field, ParticleData, ParticleData3, Points};
use glam::{DVec2, DVec3};
use grains_core::history::History;
use std::path::{Path, PathBuf};

/// Why a session call failed.
#[derive(Debug)]
pub enum Error {
    /// The scenario (or a checkpoint) was refused: one line naming the key, the value
    /// and what is allowed, as the command line says it.
    Input(String),
    /// A call's arguments do not fit this run (a field it has not, an unknown id, a
    /// wrong length).
    Argument(String),
    /// An outside force failed (the step it failed in went on without it).
    Force(ForceError),
    /// The run has been concluded (its outputs written); it cannot step any more.
    Ended,
    /// Writing or reading files failed.
    Output(anyhow::Error),
}

impl std::fmt::Display for Error {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Error::Input(m) | Error::Argument(m) => write!(f, "{m}"),
            Error::Force(e) => write!(f, "outside force: {e}"),
            Error::Ended => write!(
                f,
                "the run has ended (its outputs are written); open it again to go on"
            ),
            Error::Output(e) => write!(f, "{e:#}"),
        }
    }
}

impl std::error::Error for Error {}

impl From<RunError> for Error {
    fn from(e: RunError) -> Self {
        match e {
            RunError::Input(m) => Error::Input(m),
            RunError::Output(e) => Error::Output(e),
        }
    }
}

impl From<anyhow::Error> for Error {
    fn from(e: anyhow::Error) -> Self {
        Error::Output(e)
    }
}

/// A run of any engine, stepped by its caller.
pub struct Session {
    live: AnyRun,
    src: Source,
    opts: RunOptions<'static>,
    work: files::WorkDir,
    /// The status the run's own rules gave (unstable, at rest), if any.
    stopped: Option<Status>,
    finished: Option<Finished>,
}

impl Session {
    /// Opens the scenario file `path`.
    pub fn from_file(path: &Path) -> Result<Self, Error> {
        Self::open(Source::read(path).map_err(Error::Input)?, None)
    }

    /// Opens a scenario given as TOML text; its relative paths start at `base`.
    pub fn from_toml(text: &str, base: &Path) -> Result<Self, Error> {
        Self::open(
            Source {
                text: text.to_string(),
                origin: "<scenario>".into(),
                base: base.to_path_buf(),
            },
            None,
        )
    }

    /// Opens a scenario given as a parsed table; its relative paths start at `base`.
    pub fn from_table(table: &toml::Table, base: &Path) -> Result<Self, Error> {
        let text = toml::to_string(table)
            .map_err(|e| Error::Input(format!("<scenario>: cannot be written as TOML: {e}")))?;
        Self::from_toml(&text, base)
    }

    /// Opens the scenario `src`, writing into `out` as it runs (a temporary directory,
    /// removed when the session is dropped, when `None`).
    pub fn open(src: Source, out: Option<PathBuf>) -> Result<Self, Error> {
        Self::start(files::WorkDir::new(out)?, |opts| {
            Ok((run::open(&src, opts)?, src.clone()))
        })
    }

    /// A session over the run `open` prepares in `work`.
    fn start(
        work: files::WorkDir,
        open: impl FnOnce(&mut RunOptions<'static>) -> Result<(AnyRun, Source), RunError>,
    ) -> Result<Self, Error> {
        let mut opts = RunOptions::new(work.path());
        let (live, src) = open(&mut opts)?;
        Ok(Session {
            live,
            src,
            opts,
            work,
            stopped: None,
            finished: None,
        })
    }

    /// Continues the run checkpointed in the run directory `dir` (written by
    /// [`Session::checkpoint`] or by `grains run`), in a working copy of it.
    pub fn resume(dir: &Path) -> Result<Self, Error> {
        if !dir.join(crate::checkpoint::FILE).is_file() {
            return Err(Error::Input(format!(
                "{}: no {} there (is it a grains run directory with a checkpoint?)",
                dir.display(),
                crate::checkpoint::FILE
            )));
        }
        let work = files::WorkDir::new(None)?;
        files::copy_tree(dir, work.path())?;
        let path = work.path().to_path_buf();
        Self::start(work, |opts| run::open_resumed(&path, opts))
    }

    /// The engine: `"dem"`, `"mpm"` or `"fem_dem"`.
    pub fn engine(&self) -> &'static str {
        match self.live {
            AnyRun::Dem(_) | AnyRun::Dem3(_) => "dem",
            AnyRun::Mpm(_) => "mpm",
            AnyRun::FemDem(_) => "fem_dem",
        }
    }

    /// Spatial dimensions.
    pub fn dim(&self) -> usize {
        match self.live {
            AnyRun::Dem3(_) => 3,
            _ => 2,
        }
    }

    /// Time and steps taken.
    pub fn clock(&self) -> Clock {
        match &self.live {
            AnyRun::Dem(l) => l.sim.clock(),
            AnyRun::Dem3(l) => l.sim.clock(),
            AnyRun::Mpm(l) => l.sim.clock(),
            AnyRun::FemDem(l) => l.sim.clock(),
        }
    }

    /// The time step (FEM–DEM: the last one taken; it adapts).
    pub fn dt(&self) -> f64 {
        match &self.live {
            AnyRun::Dem(l) => l.sim.dt,
            AnyRun::Dem3(l) => l.sim.dt,
            AnyRun::Mpm(l) => l.sim.dt,
            AnyRun::FemDem(l) => l.sim.dt,
        }
    }

    /// The fingerprint of the whole state, as `summary.json`'s `state_hash` writes it.
    pub fn state_hash(&self) -> u64 {
        match &self.live {
            AnyRun::Dem(l) => l.sim.state_hash(),
            AnyRun::Dem3(l) => l.sim.state_hash(),
            AnyRun::Mpm(l) => l.sim.state_hash(),
            AnyRun::FemDem(l) => l.sim.state_hash(),
        }
    }

    /// Whether the scenario's end (its duration or step count) is reached.
    pub fn at_end(&mut self) -> bool {
        match &mut self.live {
            AnyRun::Dem(l) => over(l.as_mut()),
            AnyRun::Dem3(l) => over(l.as_mut()),
            AnyRun::Mpm(l) => over(l.as_mut()),
            AnyRun::FemDem(l) => over(l.as_mut()),
        }
    }

    /// The status the run's own rules gave so far (unstable, at rest), if any.
    pub fn stopped(&self) -> Option<&Status> {
        self.stopped.as_ref()
    }

    /// Takes `n` steps, feeding every observer as `grains run` does. Stops early only
    /// when the state breaks down ([`Status::Unstable`], returned); a rule that would
    /// end a command-line run (at rest) is recorded and returned, and stepping goes on.
    pub fn step(&mut self, n: u64) -> Result<Option<Status>, Error> {
        self.step_while(n, false, |_, _| true)
    }

    /// Steps to the scenario's end, or to time `until` (s) if given, or until the run's
    /// own rules stop it (at rest, unstable); returns how it stopped.
    pub fn run(&mut self, until: Option<f64>) -> Result<Status, Error> {
        let stop = self.step_while(u64::MAX, true, |c, over| wanted(c, over, until))?;
        Ok(stop.unwrap_or(if self.at_end() {
            Status::Completed
        } else {
            Status::Paused
        }))
    }

    /// Takes up to `n` steps while `go(clock, at_end)` holds before each; returns a
    /// stop status: at once when `stop_at_rule` and the run's own rules say stop (as
    /// [`Session::run`] does), else only when the state breaks down.
    pub fn step_while(
        &mut self,
        n: u64,
        stop_at_rule: bool,
        mut go: impl FnMut(Clock, bool) -> bool + Send,
    ) -> Result<Option<Status>, Error> {
        if self.finished.is_some() {
            return Err(Error::Ended);
        }
        let mut control = run::control(&mut self.opts, &self.src);
        let r = match &mut self.live {
            AnyRun::Dem(l) => steps(l.as_mut(), n, stop_at_rule, &mut control, &mut go, |s| {
                s.outside.error.take()
            }),
            AnyRun::Mpm(l) => steps(l.as_mut(), n, stop_at_rule, &mut control, &mut go, |_| None),
            AnyRun::Dem3(l) => steps(l.as_mut(), n, stop_at_rule, &mut control, &mut go, |s| {
                s.outside.error.take()
            }),
            AnyRun::FemDem(l) => steps(l.as_mut(), n, stop_at_rule, &mut control, &mut go, |s| {
                s.outside.error.take()
            }),
        }?;
        if let Some(s) = &r {
            if self.stopped.is_none() || matches!(s, Status::Unstable(_)) {
                self.stopped = Some(s.clone());
            }
        }
        Ok(r)
    }

    /// The particles in id order (copies): DEM particles, a FEM–DEM run's ring, an MPM
    /// run's material points; none for a 3D run ([`Session::particles3`]).
    pub fn particles(&self) -> ParticleData {
        match &self.live {
            AnyRun::Dem(l) => ParticleData::of_dem(&l.sim.state.particles),
            AnyRun::Mpm(l) => ParticleData::of_view(&l.sim.particles()),
            AnyRun::Dem3(_) => ParticleData::default(),
            AnyRun::FemDem(l) => match &l.sim.ring {
                Some(r) => ParticleData::of_dem(&r.state.particles),
                None => ParticleData::default(),
            },
        }
    }

    /// A 3D run's spheres in id order (copies); `None` for a 2D run.
    pub fn particles3(&self) -> Option<ParticleData3> {
        match &self.live {
            AnyRun::Dem3(l) => Some(ParticleData3::of_dem3(&l.sim.state.particles)),
            _ => None,
        }
    }

    /// A field of the particles as the engine stores it (storage order), for a
    /// zero-copy view; valid while [`Session::layout`] is unchanged.
    pub fn field(&self, name: &str) -> Option<Field<'_>> {
        match &self.live {
            AnyRun::Dem(l) => data::dem_field(&l.sim.state.particles, name),
            AnyRun::FemDem(l) => data::dem_field(&l.sim.ring.as_ref()?.state.particles, name),
            AnyRun::Dem3(l) => data::dem3_field(&l.sim.state.particles, name),
            AnyRun::Mpm(l) => {
                let p = &l.sim.state.particles;
                match name {
                    "id" => Some(Field::Ids(&p.id)),
                    "position" => Some(Field::Vector(&p.pos)),
                    "velocity" => Some(Field::Vector(&p.vel)),
                    "mass" => Some(Field::Scalar(&p.mass)),
                    _ => None,
                }
            }
        }
    }

    /// A counter that changes whenever the engine reorders or reallocates its particle
    /// storage (DEM: at each neighbour-list rebuild, which re-sorts the particles).
    pub fn layout(&self) -> u64 {
        match &self.live {
            AnyRun::Dem(l) => l.sim.state.contacts.builds,
            AnyRun::Dem3(l) => l.sim.state.contacts.builds,
            AnyRun::FemDem(l) => l.sim.ring.as_ref().map_or(0, |r| r.state.contacts.builds),
            AnyRun::Mpm(_) => 0,
        }
    }

    /// Sets `"position"` or `"velocity"` of the particles `ids` to `values` (2D runs;
    /// 3D runs take [`Session::set3`]).
    pub fn set(&mut self, name: &str, ids: &[u32], values: &[DVec2]) -> Result<(), Error> {
        let (id, pos, vel) = match &mut self.live {
            AnyRun::Dem(l) => {
                let p = &mut l.sim.state.particles;
                (&p.id, &mut p.pos, &mut p.vel)
            }
            AnyRun::Mpm(l) => {
                let p = &mut l.sim.state.particles;
                (&p.id, &mut p.pos, &mut p.vel)
            }
            AnyRun::FemDem(l) => match l.sim.ring.as_mut() {
                Some(r) => {
                    let p = &mut r.state.particles;
                    (&p.id, &mut p.pos, &mut p.vel)
                }
                None => return Err(Error::Argument("this run has no particles".into())),
            },
            AnyRun::Dem3(_) => return Err(Error::Argument(other_dim("set", 3, "set3"))),
        };
        assign(name, id, pos, vel, ids, values)
    }

    /// Sets `"position"` or `"velocity"` of the spheres `ids` of a 3D run to `values`.
    pub fn set3(&mut self, name: &str, ids: &[u32], values: &[DVec3]) -> Result<(), Error> {
        let AnyRun::Dem3(l) = &mut self.live else {
            return Err(Error::Argument(other_dim("set3", 2, "set")));
        };
        let p = &mut l.sim.state.particles;
        assign(name, &p.id, &mut p.pos, &mut p.vel, ids, values)
    }

    /// Adds an outside force (DEM and FEM–DEM runs), applied in every later step after
    /// the contact forces are summed. It is also applied once now, to the forces of the
    /// present state, so that the next step's first half-kick includes it as velocity
    /// Verlet needs.
    pub fn add_force(&mut self, mut f: Box<dyn OutsideForce>) -> Result<(), Error> {
        let (outside, p, time) =
            match &mut self.live {
                AnyRun::Dem(l) => (
                    &mut l.sim.outside,
                    &mut l.sim.state.particles,
                    l.sim.state.time,
                ),
                AnyRun::FemDem(l) => match l.sim.ring.as_mut() {
                    Some(r) => (&mut l.sim.outside, &mut r.state.particles, r.state.time),
                    None => return Err(Error::Argument("this run has no particles".into())),
                },
                AnyRun::Mpm(_) => return Err(Error::Argument(
                    "outside forces apply to DEM and FEM–DEM runs; this one is engine = \"mpm\""
                        .into(),
                )),
                AnyRun::Dem3(_) => {
                    return Err(Error::Argument(other_dim("add_force", 3, "add_force3")))
                }
            };
        f.add(time, p).map_err(Error::Force)?;
        outside.fields.push(f);
        Ok(())
    }

    /// Adds an outside force to a 3D run, as [`Session::add_force`] does to a 2D one.
    pub fn add_force3(
        &mut self,
        mut f: Box<dyn OutsideForce<grains_dem3d::Particles>>,
    ) -> Result<(), Error> {
        let AnyRun::Dem3(l) = &mut self.live else {
            return Err(Error::Argument(other_dim("add_force3", 2, "add_force")));
        };
        let sim = &mut l.sim;
        f.add(sim.state.time, &mut sim.state.particles)
            .map_err(Error::Force)?;
        sim.outside.fields.push(f);
        Ok(())
    }

    /// The touching particle pairs of a 3D run.
    pub fn contacts3(&self) -> Option<Contacts<DVec3>> {
        match &self.live {
            AnyRun::Dem3(l) => Some(Contacts::of3(&l.sim.setup, &l.sim.state)),
            _ => None,
        }
    }

    /// The touching particle pairs (DEM and FEM–DEM runs).
    pub fn contacts(&self) -> Option<Contacts> {
        match &self.live {
            AnyRun::Dem(l) => Some(Contacts::of(&l.sim.setup, &l.sim.state)),
            AnyRun::FemDem(l) => l
                .sim
                .ring
                .as_ref()
                .map(|r| Contacts::of(&r.setup, &r.state)),
            AnyRun::Mpm(_) | AnyRun::Dem3(_) => None,
        }
    }

    /// An MPM run's material points.
    pub fn points(&self) -> Option<Points> {
        match &self.live {
            AnyRun::Mpm(l) => Some(Points::of(&l.sim.state.particles)),
            _ => None,
        }
    }

    /// A FEM–DEM run's charge.
    pub fn charge(&self) -> Option<ChargeData> {
        match &self.live {
            AnyRun::FemDem(l) => Some(ChargeData::of(&l.sim.charge)),
            _ => None,
        }
    }

    /// The history so far (the rows of `history.csv`).
    pub fn history(&self) -> &History {
        match &self.live {
            AnyRun::Dem(l) => l.history(),
            AnyRun::Dem3(l) => l.history(),
            AnyRun::Mpm(l) => l.history(),
            AnyRun::FemDem(l) => l.history(),
        }
    }

    /// Concludes the run as `grains run` does at its end (last frame, plots, figures,
    /// checks, `summary.json` in the working directory) and returns it; later calls
    /// return the same. A run stopped before its end is concluded as paused. The session
    /// cannot step afterwards.
    pub fn finish(&mut self) -> Result<&Finished, Error> {
        if self.finished.is_none() {
            let status = match self.stopped.clone() {
                Some(s) => s,
                None if self.at_end() => Status::Completed,
                None => Status::Paused,
            };
            let threads = self.opts.threads;
            let mut control = run::control(&mut self.opts, &self.src);
            let done = match &mut self.live {
                AnyRun::Dem(l) => conclude(l.as_mut(), status, &mut control, threads),
                AnyRun::Dem3(l) => conclude(l.as_mut(), status, &mut control, threads),
                AnyRun::Mpm(l) => conclude(l.as_mut(), status, &mut control, threads),
                AnyRun::FemDem(l) => conclude(l.as_mut(), status, &mut control, threads),
            }?;
            self.finished = Some(done);
        }
        Ok(self.finished.as_ref().expect("just concluded"))
    }

    /// Concludes the run ([`Session::finish`]) and copies its outputs (what `grains run`
    /// writes) into `out`.
    pub fn write(&mut self, out: &Path) -> Result<Finished, Error> {
        let mut done = self.finish()?.clone();
        files::copy_tree(self.work.path(), out)?;
        done.out = out.to_path_buf();
        Ok(done)
    }

    /// Writes a checkpoint of the run as it stands and copies the run directory into
    /// `dir`, which [`Session::resume`] and `grains resume` continue from (DEM runs of
    /// either dimension and FEM–DEM runs). The session goes on unchanged.
    pub fn checkpoint(&mut self, dir: &Path) -> Result<(), Error> {
        if self.finished.is_some() {
            return Err(Error::Ended);
        }
        let control = run::control(&mut self.opts, &self.src);
        let written = match &mut self.live {
            AnyRun::Dem(l) => save(l.as_mut(), &control),
            AnyRun::Dem3(l) => save(l.as_mut(), &control),
            AnyRun::FemDem(l) => save(l.as_mut(), &control),
            AnyRun::Mpm(_) => Ok(false),
        }?;
        if !written {
            return Err(Error::Argument(format!(
                "checkpoints are written by DEM and FEM–DEM runs; this one is engine = \"{}\"",
                self.engine()
            )));
        }
        files::copy_tree(self.work.path(), dir)?;
        Ok(())
    }

    /// Where the run writes as it goes.
    pub fn work_dir(&self) -> &Path {
        self.work.path()
    }
}

/// The storage index of an id.
fn index_of_ids(ids: &[u32]) -> impl Fn(u32) -> Option<usize> + '_ {
    let order = data::id_order(ids);
    move |id| {
        let k = order.partition_point(|&i| ids[i] < id);
        order.get(k).copied().filter(|&i| ids[i] == id)
    }
}

fn over<L: Live>(l: &mut L) -> bool {
    let (sim, stepper, _) = l.parts();
    stepper.over(sim)
}

/// Whether a run that should go on to `until` (or to its end) wants another step.
pub fn wanted(c: Clock, over: bool, until: Option<f64>) -> bool {
    match until {
        Some(t) => c.time < t * (1.0 - 1e-12),
        None => !over,
    }
}

fn steps<L: Live>(
    l: &mut L,
    n: u64,
    stop_at_rule: bool,
    control: &mut crate::driver::Control,
    go: &mut (impl FnMut(Clock, bool) -> bool + Send),
    failed: impl Fn(&mut L::S) -> Option<ForceError> + Sync,
) -> Result<Option<Status>, Error> {
    let (sim, stepper, mut observers) = l.parts();
    // Stepping from inside the pool, as the command line's loop does.
    rayon::scope(|_| {
        let mut seen = None;
        for _ in 0..n {
            if !go(sim.clock(), stepper.over(sim)) {
                break;
            }
            let stop = stepper.step(sim, &mut observers, control)?;
            if let Some(e) = failed(sim) {
                return Err(Error::Force(e));
            }
            match stop {
                Some(s @ Status::Unstable(_)) => return Ok(Some(s)),
                Some(s) if stop_at_rule => return Ok(Some(s)),
                Some(s) => {
                    seen.get_or_insert(s);
                }
                None => {}
            }
        }
        Ok(seen)
    })
}

fn conclude<L: Live>(
    l: &mut L,
    status: Status,
    control: &mut crate::driver::Control,
    threads: usize,
) -> Result<Finished, Error> {
    let (sim, stepper, mut observers) = l.parts();
    let outcome = stepper.finish(sim, &mut observers, status, control)?;
    drop(observers);
    Ok(l.conclude(outcome, threads)?)
}

fn save<L: Live>(l: &mut L, control: &crate::driver::Control) -> Result<bool, Error> {
    let (sim, stepper, mut observers) = l.parts();
    Ok(stepper.checkpoint(sim, &mut observers, control)?)
}

/// Why a call for one dimension is refused on a run of the other.
fn other_dim(call: &str, dim: usize, instead: &str) -> String {
    format!("{call}: this run has dim = {dim}; use {instead}")
}

/// Sets `"position"` or `"velocity"` of the particles `ids` (their storage ids `id`) to
/// `values`.
fn assign<V: Copy>(
    name: &str,
    id: &[u32],
    pos: &mut [V],
    vel: &mut [V],
    ids: &[u32],
    values: &[V],
) -> Result<(), Error> {
    if ids.len() != values.len() {
        return Err(Error::Argument(format!(
            "set({name}): {} ids but {} values",
            ids.len(),
            values.len()
        )));
    }
    let target = match name {
        "position" => pos,
        "velocity" => vel,
        other => {
            return Err(Error::Argument(format!(
                "set: name = \"{other}\": must be \"position\" or \"velocity\""
            )))
        }
    };
    let index = index_of_ids(id);
    for (&k, v) in ids.iter().zip(values) {
        let i = index(k)
            .ok_or_else(|| Error::Argument(format!("set({name}): no particle with id {k}")))?;
        target[i] = *v;
    }
    Ok(())
}
