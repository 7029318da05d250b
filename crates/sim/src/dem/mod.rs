//! DEM runs (`engine = "dem"`, the default): the scenario, its assembly into a
//! [`grains_dem`] set-up, the [`Dem`] simulation, its observers (probes, rest) and
//! outputs (history rows, frames, plots, figures).

pub mod assemble;
pub mod check;
pub mod frames;
pub mod plausible;
pub mod plots;
pub mod probes;
pub mod ranks;
pub mod records;
pub mod rest;
pub mod run;
pub mod scenario;

use crate::dispersal::{Dispersing, Frame};
use crate::driver::{Clock, FrameKind, ParticleView, Simulation};
use crate::forces::{Hook, Outside};
use crate::output::Capabilities;
use grains_core::input::InputError;
use grains_dem::diagnostics::{self, Diagnostics};
use grains_dem::{step, step_with, Particles, Reduce, Setup, State};
use std::borrow::Cow;

/// What a DEM run writes, and its defaults.
pub const CAPABILITIES: Capabilities = Capabilities {
    engine: "dem",
    frames: 50,
    history: 2000,
    checkpoints: true,
    lammps_dump: true,
    grid: false,
};

/// Overlap (relative to the smaller radius) beyond which a run is declared unstable;
/// a start beyond it is refused.
pub const RUNAWAY_OVERLAP: f64 = 0.5;

/// A running DEM simulation.
pub struct Dem {
    /// Engine configuration (read-only).
    pub setup: Setup,
    /// The evolving state.
    pub state: State,
    /// Time step (s).
    pub dt: f64,
    /// Also write a LAMMPS dump with every frame.
    pub lammps_dump: bool,
    /// Forces from outside the particle system (none in a scenario run).
    pub outside: Outside,
    /// This rank's part of a run spread over ranks (`None`: the whole run is here).
    /// Then `state` is rank 0's view, whole at frames and at the end.
    pub ranks: Option<Box<ranks::Part>>,
}

impl Dem {
    /// The particles that `pick` names by id, in ascending id, whether the run is here
    /// or spread over ranks (then on every rank: every rank must ask at the same point
    /// with the same `pick`); what the probes read ([`ranks::watched`]).
    pub fn watched(&self, pick: impl Fn(u32) -> bool) -> Particles {
        ranks::watched(self.ranks.as_deref(), &self.state, pick)
    }

    /// Starts a run: evaluates the initial forces, and refuses a start whose disks
    /// already overlap beyond the runaway limit (coincident or deeply overlapping
    /// disks blow up within a few steps).
    pub fn new(a: assemble::Assembled, lammps_dump: bool) -> Result<Self, InputError> {
        let state = State::new(&a.setup, a.particles);
        if let Some((i, j, ratio)) = diagnostics::deepest_overlap(&a.setup, &state) {
            if ratio > RUNAWAY_OVERLAP {
                return Err(InputError::new(
                    format!("particles {i} and {j}"),
                    format!("overlap {:.3} of the smaller radius at the start", ratio),
                    format!(
                        "disks may overlap by at most {RUNAWAY_OVERLAP} of the smaller radius (the run's runaway limit); separate them"
                    ),
                ));
            }
        }
        Ok(Dem {
            setup: a.setup,
            state,
            dt: a.dt,
            lammps_dump,
            outside: Outside::default(),
            ranks: None,
        })
    }

    /// Continues from a checkpointed state.
    pub fn resumed(setup: Setup, state: State, dt: f64, lammps_dump: bool) -> Self {
        Dem {
            setup,
            state,
            dt,
            lammps_dump,
            outside: Outside::default(),
            ranks: None,
        }
    }
}

impl Simulation for Dem {
    type Sample = Diagnostics;

    fn clock(&self) -> Clock {
        Clock {
            time: self.state.time,
            step: self.state.step,
        }
    }

    fn advance(&mut self) -> Result<(), String> {
        if let Some(part) = self.ranks.as_mut() {
            part.advance(&self.setup, self.dt, &mut self.state);
        } else if self.outside.is_empty() {
            step(&self.setup, &mut self.state, self.dt);
        } else {
            let mut hook = Hook {
                outside: &mut self.outside,
                time: self.state.time + self.dt,
            };
            step_with(&self.setup, &mut self.state, self.dt, &mut hook);
        }
        Ok(())
    }

    fn sample(&mut self) -> Diagnostics {
        match &self.ranks {
            Some(part) => part.sample(&self.setup),
            None => diagnostics::measure(&self.setup, &self.state),
        }
    }

    fn unstable(&self, d: &Diagnostics) -> Option<String> {
        if !d.finite {
            return Some("a position or velocity is not finite (NaN or infinity)".into());
        }
        if d.max_overlap_ratio > RUNAWAY_OVERLAP {
            return Some(format!(
                "runaway overlap: {:.3} of a radius (limit {RUNAWAY_OVERLAP}); the time step is too large or the contacts too soft for the load",
                d.max_overlap_ratio
            ));
        }
        match &self.ranks {
            Some(part) => part.first(|s| plausible::escaped(&self.setup, s, self.dt)),
            None => plausible::escaped(&self.setup, &self.state, self.dt),
        }
    }

    fn particles(&self) -> ParticleView<'_> {
        let p = &self.state.particles;
        ParticleView {
            id: &p.id,
            pos: &p.pos,
            vel: &p.vel,
            radius: Cow::Borrowed(&p.radius),
            mass: Cow::Owned((0..p.len()).map(|i| p.mass(i)).collect()),
        }
    }

    ranks::spread_methods!();

    fn checkpoint(&self) -> Option<Vec<u8>> {
        // On several ranks, rank 0 writes the whole state it has just gathered (in id
        // order, the list rebuilt over the whole domain), so the file is the same on any
        // rank count; the others write nothing.
        if self.ranks.as_ref().is_some_and(|p| p.rank() != 0) {
            return None;
        }
        let mut bytes = Vec::with_capacity(200 * self.state.particles.len());
        grains_dem::checkpoint::write(&self.state, &mut bytes).ok()?;
        Some(bytes)
    }
}

impl Dispersing for Dem {
    fn dispersal_frame(&self) -> Frame {
        let p = &self.state.particles;
        Frame {
            time: self.state.time,
            id: p.id.clone(),
            pos: p.pos.clone(),
            vel: p.vel.clone(),
            radius: p.radius.clone(),
            mass: (0..p.len()).map(|i| p.mass(i)).collect(),
            stress: Some(grains_dem::stress::particle_stress(
                &self.setup,
                &self.state,
            )),
            charge_radius: None,
        }
    }
}
