//! 3D DEM runs (`engine = "dem"` with `dim = 3`): spheres in [`grains_dem3d`], from the
//! scenario ([`scenario`], in the 2D scenario's style) through its assembly ([`crate::law`],
//! [`assemble`]) to the [`Dem3`] simulation, its checks ([`probes`]), frames and plots
//! ([`output`]) and its run ([`run`]). The driver, history, frame recorder, summary and
//! the run contract are the ones every engine uses.

pub mod assemble;
pub mod collapse;
pub mod deposit;
pub mod drum;
pub mod ledger;
pub mod output;
pub mod packing;
pub mod pour;
pub mod probes;
pub mod ranks;
pub mod run;
pub mod scenario;
pub mod silo;
pub mod walls;

use crate::driver::{Clock, FrameKind, ParticleView, Simulation};
use crate::forces::{Hook, Outside};
use crate::history::Recorded;
use crate::output::Capabilities;
use grains_core::input::InputError;
use grains_dem3d::diagnostics::{self, Diagnostics};
use grains_dem3d::{step, step_with, Particles, Reduce, Setup, State};
use std::borrow::Cow;

/// What a 3D DEM run writes, and its defaults.
pub const CAPABILITIES: Capabilities = Capabilities {
    engine: "dem",
    frames: 50,
    history: 2000,
    checkpoints: true,
    lammps_dump: true,
    grid: false,
};

/// A running 3D DEM simulation.
pub struct Dem3 {
    /// Engine configuration (read-only).
    pub setup: Setup,
    /// The evolving state.
    pub state: State,
    /// Time step (s).
    pub dt: f64,
    /// Also write a LAMMPS dump with every frame.
    pub lammps_dump: bool,
    /// Forces from outside the particle system (none in a scenario run).
    pub outside: Outside<Particles>,
    /// Spheres poured in after each step.
    pub pour: Option<pour::Pour>,
    /// Walls taken away during the run and when ([`walls::release`]).
    pub releases: Vec<(usize, f64)>,
    /// The energy ledger's start and what pours brought in ([`ledger`]).
    pub books: ledger::Books,
    /// The energy ledger's figures at the last sample (made only then: [`ledger`]).
    pub ledger: Option<grains_dem3d::EnergyLedger>,
    /// This rank's part of a run spread over ranks (`None`: the whole run is here).
    /// Then `state` is rank 0's view, whole at frames, checkpoints and the end.
    pub ranks: Option<Box<ranks::Part>>,
}

impl Dem3 {
    /// Starts a run, refusing spheres that overlap beyond the runaway limit at the start.
    pub fn new(setup: Setup, particles: Particles, dt: f64) -> Result<Self, InputError> {
        let state = State::new(&setup, particles);
        if let Some((i, j, ratio)) = diagnostics::deepest_overlap(&setup, &state) {
            let limit = crate::dem::RUNAWAY_OVERLAP;
            if ratio > limit {
                return Err(InputError::new(
                    format!("particles {i} and {j}"),
                    format!("overlap {ratio:.3} of the smaller radius at the start"),
                    format!("spheres may overlap by at most {limit} of the smaller radius (the run's runaway limit); separate them"),
                ));
            }
        }
        Ok(Self::resumed(setup, state, dt))
    }

    /// The spheres that `pick` names by id, in ascending id, whether the run is here or
    /// spread over ranks (then on every rank: every rank must ask at the same point with
    /// the same `pick`); what the probes read ([`ranks::watched`]).
    pub fn watched(&self, pick: impl Fn(u32) -> bool) -> Particles {
        ranks::watched(self.ranks.as_deref(), &self.state, pick)
    }

    /// The run's figures now, over every rank (on every rank: a collective), the serial
    /// ones bit for bit.
    pub fn measured(&self) -> Diagnostics {
        match &self.ranks {
            Some(part) => part.sample(&self.setup),
            None => diagnostics::measure(&self.setup, &self.state),
        }
    }

    /// Pours what is due after a step: the spheres near the pour's region, here or over
    /// every rank (in ascending id), decide where the new ones go, the same on every
    /// rank; a rank spread over ranks keeps those in its box.
    fn pour(&mut self) {
        let Some(pour) = self.pour.as_mut() else {
            return;
        };
        let (time, step) = (self.state.time, self.state.step);
        if !pour.due(time) {
            return;
        }
        let (setup, part) = (&self.setup, self.ranks.as_deref());
        let r_max = ranks::largest_radius(part, &self.state);
        let near = ranks::nearby(part, &self.state, |x, r| pour.near(setup, (x, r), r_max));
        let new = pour.draw(setup, &near, (step, time));
        let ledger = match part {
            Some(part) => part.local.ledger.is_some(),
            None => self.state.ledger.is_some(),
        };
        if ledger {
            self.books.poured += ledger::brought_in(setup, &new);
        }
        match self.ranks.as_mut() {
            Some(part) => part.insert(&self.setup, &new, &mut self.state),
            None => {
                grains_dem3d::insert::insert(&self.setup, &mut self.state, &new);
            }
        }
    }

    /// Continues from a checkpointed state.
    pub fn resumed(mut setup: Setup, state: State, dt: f64) -> Self {
        // The walls where the state has them (its poses: the straight run's bits).
        grains_dem3d::walls::place_walls(&mut setup, &state);
        Dem3 {
            setup,
            state,
            dt,
            lammps_dump: false,
            outside: Outside::default(),
            pour: None,
            releases: Vec::new(),
            books: ledger::Books::default(),
            ledger: None,
            ranks: None,
        }
    }
}

impl Simulation for Dem3 {
    type Sample = Diagnostics;

    fn clock(&self) -> Clock {
        Clock {
            time: self.state.time,
            step: self.state.step,
        }
    }

    fn advance(&mut self) -> Result<(), String> {
        walls::release(&mut self.setup.walls, &self.releases, self.state.time);
        if let Some(part) = self.ranks.as_mut() {
            // Every rank moves every wall the same way: walls are on every rank.
            grains_dem3d::walls::advance_walls(&mut self.setup, &mut part.local, self.dt);
            part.advance(&self.setup, self.dt, &mut self.state);
            self.pour();
            return Ok(());
        }
        // The walls first: the step's forces are those at its end, t + dt.
        grains_dem3d::walls::advance_walls(&mut self.setup, &mut self.state, self.dt);
        if self.outside.is_empty() {
            step(&self.setup, &mut self.state, self.dt);
        } else {
            let mut hook = Hook {
                outside: &mut self.outside,
                time: self.state.time + self.dt,
            };
            step_with(&self.setup, &mut self.state, self.dt, &mut hook);
        }
        self.pour();
        Ok(())
    }

    fn sample(&mut self) -> Diagnostics {
        self.ledger = match &self.ranks {
            Some(part) => part.ledger_figures(),
            None => grains_dem3d::ledger_sums::figures(&self.state),
        };
        self.measured()
    }

    fn unstable(&self, d: &Diagnostics) -> Option<String> {
        if !d.finite {
            return Some("a position or velocity is not finite (NaN or infinity)".into());
        }
        let limit = crate::dem::RUNAWAY_OVERLAP;
        (d.max_overlap_ratio > limit).then(|| {
            format!(
                "runaway overlap: {:.3} of a radius (limit {limit}); the time step is too large or the contacts too soft for the load",
                d.max_overlap_ratio
            )
        })
    }

    /// The view is of 2D points, which a 3D run has not: it shows none (the run's
    /// particles are in its frames and in [`Simulation::count`]).
    fn particles(&self) -> ParticleView<'_> {
        ParticleView {
            id: &[],
            pos: &[],
            vel: &[],
            radius: Cow::Borrowed(&[]),
            mass: Cow::Borrowed(&[]),
        }
    }

    fn count(&self) -> usize {
        self.state.particles.len()
    }

    ranks::spread_methods!();

    fn checkpoint(&self) -> Option<Vec<u8>> {
        // On several ranks rank 0 writes the whole state it has just gathered (in id
        // order, the list rebuilt over the whole domain); the others write nothing.
        if self.ranks.as_ref().is_some_and(|p| p.rank() != 0) {
            return None;
        }
        let mut bytes = Vec::with_capacity(400 * self.state.particles.len());
        grains_dem3d::checkpoint::write(&self.state, &mut bytes).ok()?;
        ledger::write_tail(self, &mut bytes).ok()?;
        Some(bytes)
    }
}

impl Recorded for Dem3 {
    fn columns(&self) -> Vec<String> {
        let walls: Vec<&str> = self.setup.walls.iter().map(|w| w.name.as_str()).collect();
        let mut c = crate::dem::records::columns(
            &["x", "y", "z"],
            &walls,
            &["fx", "fy", "fz", "tx", "ty", "tz"],
        );
        for (w, axis) in walls::spin_axes(&self.setup.walls).iter().enumerate() {
            if axis.is_some() {
                c.push(format!("{}_torque_axis", walls[w]));
            }
        }
        if self.state.ledger.is_some() {
            c.extend(ledger::COLUMNS.map(String::from));
        }
        c
    }

    fn integer_columns(&self) -> Vec<String> {
        crate::dem::records::INTEGER_COLUMNS
            .map(String::from)
            .to_vec()
    }

    fn row(&self, d: &Diagnostics) -> Vec<f64> {
        let s = &self.state;
        let mut row = crate::dem::records::state_row!(s, d);
        for load in s.wall_loads.iter().take(self.setup.walls.len()) {
            row.extend(load.force.to_array());
            row.extend(load.torque.to_array());
        }
        for (load, axis) in s.wall_loads.iter().zip(walls::spin_axes(&self.setup.walls)) {
            if let Some(u) = axis {
                row.push(load.torque.dot(u));
            }
        }
        row.extend(ledger::row(self, d).unwrap_or_default());
        row
    }
}
