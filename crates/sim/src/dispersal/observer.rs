//! The dispersal analysis as an observer of a run: at frames (fields written), at the
//! chosen times (maps too) and every so often at samples (figures only); at the end the
//! figures go under `dispersal` in the report. On several ranks every rank keeps the
//! schedule and reads the frame (a collective), and rank 0 alone analyses and writes.

use super::analyst::{Analyst, Frame, Layout, Writes};
use super::settings::DispersalSettings;
use crate::driver::{Flow, FrameKind, Observer, Report, Simulation, Status};
use glam::DVec2;
use std::path::Path;

/// A simulation whose particles the dispersal analysis can read.
pub trait Dispersing: Simulation {
    /// The particles now, with each one's contact stress.
    fn dispersal_frame(&self) -> Frame;
}

/// Runs the dispersal analysis during a run.
pub struct DispersalObserver {
    /// `None` on ranks other than 0, which only take part in reading the frames.
    analyst: Option<Analyst>,
    every_frame: bool,
    times: Vec<f64>,
    next_time: usize,
    every: Option<f64>,
    next_every: f64,
    end: f64,
}

impl DispersalObserver {
    /// The analysis `settings` of a run named `name` lasting `duration`, about `centre`,
    /// writing under the run directory `out`.
    pub fn new(
        name: &str,
        settings: &DispersalSettings,
        centre: DVec2,
        duration: f64,
        out: &Path,
    ) -> Self {
        let analyst = Analyst::new(
            name,
            settings.spec(),
            centre,
            settings.trace_time(duration),
            Layout::under(out),
        );
        Self::with(Some(analyst), settings, duration)
    }

    /// The observer of a rank other than 0: it reads the frames at the times rank 0's
    /// analyses them (each read gathers from every rank), and analyses nothing.
    pub fn follower(settings: &DispersalSettings, duration: f64) -> Self {
        Self::with(None, settings, duration)
    }

    fn with(analyst: Option<Analyst>, settings: &DispersalSettings, duration: f64) -> Self {
        let mut times = settings.times.clone();
        times.sort_by(f64::total_cmp);
        DispersalObserver {
            analyst,
            every_frame: settings.every_frame(),
            times,
            next_time: 0,
            every: settings.every,
            next_every: settings.every.unwrap_or(f64::INFINITY),
            end: duration,
        }
    }

    /// Times analysed so far.
    pub fn analysed(&self) -> usize {
        self.analyst.as_ref().map_or(0, Analyst::analysed)
    }

    /// Wall-clock seconds spent analysing.
    pub fn seconds(&self) -> f64 {
        self.analyst.as_ref().map_or(0.0, Analyst::seconds)
    }

    /// Reads `sim`'s frame (on every rank) and analyses it (on rank 0).
    fn analyse<S: Dispersing>(&mut self, sim: &S, writes: Writes) -> anyhow::Result<()> {
        let frame = sim.dispersal_frame();
        match self.analyst.as_mut() {
            Some(a) => a.analyse(&frame, writes),
            None => Ok(()),
        }
    }
}

impl<S: Dispersing> Observer<S> for DispersalObserver {
    fn on_sample(&mut self, sim: &S, _sample: &S::Sample) -> anyhow::Result<Flow> {
        let (Some(dt), t) = (self.every, sim.clock().time) else {
            return Ok(Flow::Continue);
        };
        if t >= self.next_every {
            while self.next_every <= t {
                self.next_every += dt;
            }
            self.analyse(sim, Writes::default())?;
        }
        Ok(Flow::Continue)
    }

    fn on_frame(&mut self, sim: &S, kind: FrameKind) -> anyhow::Result<()> {
        let t = sim.clock().time;
        // The first frame at or past each chosen time (the plan writes one there).
        let mut chosen = false;
        while self.next_time < self.times.len() && t >= self.times[self.next_time] * (1.0 - 1e-9) {
            chosen = true;
            self.next_time += 1;
        }
        // Without chosen times, the maps of the run's end: its last regular frame when
        // one falls there, else the final one.
        let last = kind == FrameKind::Final || t >= self.end * (1.0 - 1e-9);
        let maps = chosen || (self.times.is_empty() && last);
        if self.every_frame || maps {
            self.analyse(sim, Writes { fields: true, maps })?;
        }
        Ok(())
    }

    fn on_end(&mut self, _sim: &S, _status: &Status, report: &mut Report) -> anyhow::Result<()> {
        if let Some(a) = self.analyst.as_mut() {
            report.figures.insert("dispersal".into(), a.finish()?);
        }
        Ok(())
    }
}
