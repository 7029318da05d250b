//! One coupled FEM–DEM step, both engines on the same velocity-Verlet clock:
//!
//! `fem kick_drift → fem stress_forces → dem step [rebuild in a box fitted to the ring →
//!  coarse detection → pair forces → penalty forces] → fem kick`
//!
//! The penalty forces enter the particles' force sums after the pair pass and before
//! the DEM step closes (its `post_force` hook), and the charge's external nodal forces
//! before its closing kick, so both sides see the same contact at the same time level.

use crate::penalty::Coupling;
use glam::DVec2;
use grains_dem::{step_on, Exchange, Hooks, ListChange, Particles, Serial, Setup, State};
use grains_fem::integrate as fem_int;
use grains_fem::stress::{stress_forces, Breakdown};
use grains_fem::{Charge, FemSetup};
use rayon::prelude::*;

/// The particle side of a coupled run.
#[derive(Clone, Debug)]
pub struct Ring {
    /// DEM configuration (read-only).
    pub setup: Setup,
    /// DEM state.
    pub state: State,
    /// Charge–particle contact.
    pub coupling: Coupling,
    /// The box the DEM cell grid spans: refitted to the particles at every rebuild,
    /// since the ring grows several-fold during a run.
    pub grid_box: (DVec2, DVec2),
}

impl Ring {
    /// The ring's particles in contact with the charge: initial forces of both sides.
    pub fn new(
        setup: Setup,
        particles: Particles,
        coupling: Coupling,
        charge: &mut Charge,
    ) -> Self {
        let state = State::new(&setup, particles);
        let mut ring = Ring {
            grid_box: (setup.domain.lo, setup.domain.hi),
            setup,
            state,
            coupling,
        };
        ring.coupling.rebuild(charge, &ring.state.particles);
        ring.coupling.forces(charge, &mut ring.state.particles);
        ring
    }
}

/// What rides on the DEM step of a coupled step: the charge's edge (its
/// [`Hooks`]: the grid box fitted to the particles, the candidates made again after a
/// rebuild, the penalty forces).
pub struct Edge<'a> {
    charge: &'a mut Charge,
    coupling: &'a mut Coupling,
    grid_box: &'a mut (DVec2, DVec2),
    outside: &'a mut dyn FnMut(&mut Particles),
}

impl Hooks for Edge<'_> {
    fn grid_box(&mut self, _setup: &Setup, p: &Particles) -> (DVec2, DVec2) {
        if let Some(fitted) = fitted_box(&p.pos) {
            *self.grid_box = fitted;
        }
        *self.grid_box
    }

    fn post_neighbour(&mut self, p: &Particles, change: ListChange, displacement: f64) {
        // The candidate list holds particle indices, so a re-sort invalidates it.
        if change == ListChange::Rebuilt || self.coupling.stale(self.charge, displacement) {
            self.coupling.rebuild_at(self.charge, p, displacement);
        }
    }

    fn post_force(&mut self, p: &mut Particles) {
        self.post_force_on(p, &Serial);
    }

    fn post_force_on(&mut self, p: &mut Particles, comm: &dyn Exchange) {
        self.coupling.forces_on(self.charge, p, comm);
        (self.outside)(p);
    }
}

/// Advances charge and ring by `dt`.
pub fn coupled_step(
    fem: &FemSetup,
    charge: &mut Charge,
    ring: &mut Ring,
    dt: f64,
) -> Result<(), Breakdown> {
    coupled_step_with(fem, charge, ring, dt, &mut |_| {})
}

/// Advances charge and ring by `dt`, `outside` adding forces of its own to the
/// particles' sums after the pair and penalty forces (a scripted field, a callback).
pub fn coupled_step_with(
    fem: &FemSetup,
    charge: &mut Charge,
    ring: &mut Ring,
    dt: f64,
    outside: &mut dyn FnMut(&mut Particles),
) -> Result<(), Breakdown> {
    let (coupling, grid_box) = (&mut ring.coupling, &mut ring.grid_box);
    let (setup, state) = (&ring.setup, &mut ring.state);
    coupled_step_by(fem, charge, coupling, grid_box, dt, outside, |edge| {
        step_on(setup, state, dt, edge, &mut Serial)
    })
}

/// [`coupled_step_with`] with the DEM step taken by `dem`, which steps the particles
/// (with the hooks it is handed, the charge's edge) however they are held: the whole
/// ring here, or on one rank of several its part, through the decomposition's
/// exchange. Every rank steps the whole charge alike: the penalty pass gives every
/// rank the same nodal forces ([`Coupling::forces_on`]).
pub fn coupled_step_by(
    fem: &FemSetup,
    charge: &mut Charge,
    coupling: &mut Coupling,
    grid_box: &mut (DVec2, DVec2),
    dt: f64,
    outside: &mut dyn FnMut(&mut Particles),
    dem: impl FnOnce(&mut Edge<'_>),
) -> Result<(), Breakdown> {
    fem_int::kick_drift(charge, dt);
    stress_forces(fem, charge, dt)?;
    let mut edge = Edge {
        charge,
        coupling,
        grid_box,
        outside,
    };
    dem(&mut edge);
    fem_int::kick(fem, charge, dt);
    Ok(())
}

/// The particles' bounding box with a margin of 10⁻³ of its size; `None` when a
/// position is not finite (the run is then about to stop as unstable).
fn fitted_box(pos: &[DVec2]) -> Option<(DVec2, DVec2)> {
    let (lo, hi) = pos
        .par_iter()
        .fold(
            || (DVec2::INFINITY, DVec2::NEG_INFINITY),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        )
        .reduce(
            || (DVec2::INFINITY, DVec2::NEG_INFINITY),
            |a, b| (a.0.min(b.0), a.1.max(b.1)),
        );
    (lo.is_finite() && hi.is_finite()).then(|| {
        let margin = DVec2::splat(1e-3 * (hi - lo).max_element() + 1e-9);
        (lo - margin, hi + margin)
    })
}
