//! `frames/`: numbered ParaView files of the particles (and whatever else an engine
//! writes beside them), grouped per time in `frames/series.pvd`. On a run spread over
//! ranks every rank writes its piece of each frame; rank 0 keeps the series.

use crate::driver::{FrameKind, Observer, Simulation};
use grains_core::pvd::PvdSeries;
use std::io;
use std::path::{Path, PathBuf};

/// A simulation that writes frames.
pub trait Framed: Simulation {
    /// Files written once, at the start (e.g. fixed walls): (part name, file name).
    fn static_parts(&self, _dir: &Path) -> io::Result<Vec<(&'static str, String)>> {
        Ok(Vec::new())
    }
    /// Writes frame number `k` into `dir`: its (part name, file name) pairs.
    fn write_frame(&self, dir: &Path, k: usize) -> io::Result<Vec<(&'static str, String)>>;
}

/// Writes numbered frames into `frames/` and keeps `frames/series.pvd` current.
pub struct FrameRecorder {
    dir: PathBuf,
    /// `None` on a rank other than 0, which writes its pieces only.
    series: Option<PvdSeries>,
    statics: Vec<(&'static str, String)>,
    count: usize,
}

impl FrameRecorder {
    /// Creates (and empties) `out/frames` and writes the static parts.
    pub fn create<S: Framed>(out: &Path, sim: &S) -> io::Result<Self> {
        let dir = out.join("frames");
        if dir.exists() {
            std::fs::remove_dir_all(&dir)?;
        }
        std::fs::create_dir_all(&dir)?;
        let statics = sim.static_parts(&dir)?;
        Ok(FrameRecorder {
            series: Some(PvdSeries::new(&dir.join("series.pvd"))),
            dir,
            statics,
            count: 0,
        })
    }

    /// Reopens the frames of a run continued from a checkpoint at `time`, which had
    /// written `count` frames by then: later entries of the series are dropped.
    pub fn resume<S: Framed>(out: &Path, sim: &S, time: f64, count: usize) -> io::Result<Self> {
        let dir = out.join("frames");
        let mut series = PvdSeries::load(&dir.join("series.pvd"))?;
        series.truncate_after(time)?;
        let statics = sim.static_parts(&dir)?;
        Ok(FrameRecorder {
            series: Some(series),
            dir,
            statics,
            count,
        })
    }

    /// The recorder of a rank other than 0 of a run spread over ranks, `count` frames
    /// into the run: it writes the rank's piece of each frame into `out/frames` (which
    /// rank 0 made before any rank writes) and leaves the series and static parts to
    /// rank 0.
    pub fn pieces(out: &Path, count: usize) -> Self {
        FrameRecorder {
            dir: out.join("frames"),
            series: None,
            statics: Vec::new(),
            count,
        }
    }

    /// Frames written.
    pub fn count(&self) -> usize {
        self.count
    }
}

impl<S: Framed> Observer<S> for FrameRecorder {
    fn on_frame(&mut self, sim: &S, _kind: FrameKind) -> anyhow::Result<()> {
        let mut parts = sim.write_frame(&self.dir, self.count)?;
        self.count += 1;
        let Some(series) = self.series.as_mut() else {
            return Ok(());
        };
        parts.extend(self.statics.iter().cloned());
        let t = sim.clock().time;
        match parts.as_slice() {
            [(_, only)] => series.push(t, only)?,
            _ => {
                let refs: Vec<(&str, &str)> = parts.iter().map(|(n, f)| (*n, f.as_str())).collect();
                series.push_group(t, &refs)?;
            }
        }
        Ok(())
    }
}

/// A simulation that can draw its particles as a PNG map.
pub trait Mapped: Simulation {
    /// The map's file name at the present time.
    fn map_name(&self) -> String;
    /// Draws the map into `path`.
    fn draw_map(&self, path: &Path) -> anyhow::Result<()>;
}

/// PNG maps of the particles at the plan's snapshot times (with their frames).
pub struct Snapshots {
    /// Where the maps go (the run's `plots/`).
    pub dir: PathBuf,
}

impl<S: Mapped> Observer<S> for Snapshots {
    fn on_frame(&mut self, sim: &S, kind: FrameKind) -> anyhow::Result<()> {
        if kind == FrameKind::Snapshot {
            std::fs::create_dir_all(&self.dir)?;
            sim.draw_map(&self.dir.join(sim.map_name()))?;
        }
        Ok(())
    }
}
