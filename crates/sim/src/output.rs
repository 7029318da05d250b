//! `[output]`: what a run writes and how often — one table for every engine, each
//! engine filling in its own defaults and refusing what it cannot write.

use crate::driver::{Every, Horizon, Plan};
use grains_core::input::{InputError, Shown};
use serde::{Deserialize, Serialize};

/// `[output]`.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Frames over the run, besides the first and the last (0: only those two).
    #[serde(default)]
    pub frames: Option<u64>,
    /// Rows of history.csv over the run.
    #[serde(default)]
    pub history: Option<u64>,
    /// Times (s) at which a frame and a PNG map of the particles are written.
    #[serde(default)]
    pub snapshots: Vec<f64>,
    /// Write `checkpoint.bin` every this many steps (also on Ctrl-C/SIGTERM and at
    /// `--stop-at-step`); `grains resume DIR` continues from it (DEM and FEM–DEM).
    #[serde(default)]
    pub checkpoint_every: Option<u64>,
    /// Also write each frame as a LAMMPS text dump (`frames/particles_NNNNN.dump`,
    /// columns `id type x y z radius vx vy vz omegaz fx fy fz` in 2D, `id type x y z vx
    /// vy vz omegax omegay omegaz radius fx fy fz` in 3D) for OVITO (DEM particles).
    #[serde(default)]
    pub lammps_dump: bool,
    /// Also write the grid (VTU) with every frame (MPM; default true).
    #[serde(default)]
    pub grid_frames: Option<bool>,
}

/// What an engine writes and its defaults.
#[derive(Clone, Copy, Debug)]
pub struct Capabilities {
    /// The engine's name in messages.
    pub engine: &'static str,
    /// Default frame count.
    pub frames: u64,
    /// Default history row count.
    pub history: u64,
    /// Whether runs can be checkpointed.
    pub checkpoints: bool,
    /// Whether frames can carry a LAMMPS dump.
    pub lammps_dump: bool,
    /// Whether a background grid can be written.
    pub grid: bool,
}

impl OutputSpec {
    /// Frames over the run.
    pub fn frames(&self, c: &Capabilities) -> u64 {
        self.frames.unwrap_or(c.frames)
    }

    /// History rows over the run.
    pub fn history(&self, c: &Capabilities) -> u64 {
        self.history.unwrap_or(c.history)
    }

    /// Refuses values out of range and keys the engine does not write; `duration` is
    /// the run's simulated time (snapshots must fall within it).
    pub fn validate(&self, c: &Capabilities, duration: f64) -> Result<(), InputError> {
        let only = |key: &str, value: &dyn Shown, what: &str| {
            InputError::new(
                key,
                value.shown(),
                format!("{what}; engine = \"{}\" does not write it", c.engine),
            )
        };
        if self.history == Some(0) {
            return Err(InputError::new(
                "output.history",
                0u64,
                "must be at least 1",
            ));
        }
        if let Some(k) = self.checkpoint_every {
            if !c.checkpoints {
                return Err(only(
                    "output.checkpoint_every",
                    &k,
                    "checkpoints are written by DEM and FEM–DEM runs only",
                ));
            }
            if k == 0 {
                return Err(InputError::new(
                    "output.checkpoint_every",
                    k,
                    "must be at least 1 step",
                ));
            }
        }
        if self.lammps_dump && !c.lammps_dump {
            return Err(only(
                "output.lammps_dump",
                &"true",
                "a dump of DEM particles",
            ));
        }
        if let (Some(g), false) = (self.grid_frames, c.grid) {
            return Err(only(
                "output.grid_frames",
                &g.to_string(),
                "the MPM background grid",
            ));
        }
        for (k, &t) in self.snapshots.iter().enumerate() {
            if !(t.is_finite() && t > 0.0 && t <= duration) {
                return Err(InputError::new(
                    format!("output.snapshots[{k}]"),
                    t,
                    format!("must be in (0, run.duration = {}] s", duration.shown()),
                ));
            }
        }
        Ok(())
    }

    /// The schedule of a run of `steps` fixed steps: samples and frames spread evenly
    /// over them.
    pub fn plan_by_steps(&self, c: &Capabilities, steps: u64) -> Plan {
        Plan {
            horizon: Horizon::Steps(steps),
            samples: Every::Steps((steps / self.history(c).max(1)).max(1)),
            frames: Every::Steps((steps / self.frames(c).max(1)).max(1)),
            snapshots: self.snapshot_times(),
            checkpoint_every: self.checkpoint_every,
        }
    }

    /// The schedule of a run of `duration` seconds in steps that adapt: samples and
    /// frames spread evenly over the time.
    pub fn plan_by_time(&self, c: &Capabilities, duration: f64) -> Plan {
        Plan {
            horizon: Horizon::Time(duration),
            samples: Every::Time(duration / self.history(c) as f64),
            frames: Every::Time(duration / self.frames(c).max(1) as f64),
            snapshots: self.snapshot_times(),
            checkpoint_every: self.checkpoint_every,
        }
    }

    /// The snapshot times, ascending.
    pub fn snapshot_times(&self) -> Vec<f64> {
        let mut t = self.snapshots.clone();
        t.sort_by(f64::total_cmp);
        t
    }
}
