//! One coupled FEM–DEM step, both engines on the same velocity-Verlet clock:
//!
//! `dem kick_drift → fem kick_drift → (dem rebuild) → (coarse detection) → dem pair_contacts
//!  → fem stress_forces → coupling forces → dem walls_gather_kick → fem kick`
//!
//! The coupling's penalty forces enter the particles' force sums between the pair pass
//! and the gather that closes the DEM step, and the charge's external nodal forces
//! before its closing kick, so both sides see the same contact at the same time level.

use super::coupling::Coupling;
use glam::DVec2;
use grains_dem::integrate::{kick_drift, walls_gather_kick};
use grains_dem::{forces::pair_contacts, Setup, State};
use grains_fem::integrate as fem_int;
use grains_fem::stress::{stress_forces, Breakdown};
use grains_fem::{Charge, FemSetup};
use rayon::prelude::*;

/// The particle side of a coupled run.
pub struct RingRun {
    /// DEM configuration; its `dt` and `domain` are updated by the step.
    pub setup: Setup,
    /// DEM state.
    pub state: State,
    /// Charge–particle contact.
    pub coupling: Coupling,
}

/// Advances charge and ring (if any) by `dt`.
pub fn coupled_step(
    fem: &FemSetup,
    charge: &mut Charge,
    ring: Option<&mut RingRun>,
    dt: f64,
) -> Result<(), Breakdown> {
    let Some(r) = ring else {
        return grains_fem::step(fem, charge, dt);
    };
    r.setup.dt = dt;
    let moved = kick_drift(
        &r.setup,
        &mut r.state.particles,
        &r.state.contacts.pos_at_build,
    );
    fem_int::kick_drift(charge, dt);
    if moved {
        fit_domain(&mut r.setup, &r.state.particles.pos);
        r.state.contacts.rebuild(&r.setup, &mut r.state.particles);
    }
    if moved || r.coupling.stale(charge) {
        r.coupling.rebuild(charge, &r.state.particles);
    }
    pair_contacts(&r.setup, &mut r.state.particles, &mut r.state.contacts, dt);
    stress_forces(fem, charge, dt)?;
    r.coupling.forces(charge, &mut r.state.particles);
    r.state.wall_loads = walls_gather_kick(
        &r.setup,
        &mut r.state.particles,
        &mut r.state.contacts,
        dt,
        0.5 * dt,
    );
    r.state.time += dt;
    r.state.step += 1;
    fem_int::kick(fem, charge, dt);
    Ok(())
}

/// Fits the DEM's (non-periodic) box to the particles before a rebuild: the cell grid
/// spans the box, and the ring grows several-fold during a run.
pub fn fit_domain(setup: &mut Setup, pos: &[DVec2]) {
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
    if lo.is_finite() && hi.is_finite() {
        let margin = DVec2::splat(1e-3 * (hi - lo).max_element() + 1e-9);
        setup.domain.lo = lo - margin;
        setup.domain.hi = hi + margin;
    }
}
