//! One DEM time step: `kick_drift → neighbours → pair_contacts → walls_gather_kick`.

use crate::forces::pair_contacts;
use crate::integrate::{kick_drift, walls_gather_kick, WallLoad};
use crate::neighbours::ContactList;
use crate::particles::Particles;
use crate::setup::Setup;

/// Everything that evolves during a run.
#[derive(Clone, Debug, Default)]
pub struct State {
    /// The disks.
    pub particles: Particles,
    /// Neighbour list and contact history.
    pub contacts: ContactList,
    /// Load on each wall at the last force evaluation.
    pub wall_loads: Vec<WallLoad>,
    /// Simulated time (s).
    pub time: f64,
    /// Steps taken.
    pub step: u64,
}

impl State {
    /// Wraps particles into a state and evaluates the initial forces (without advancing
    /// any tangential spring), so the first step starts from consistent forces.
    pub fn new(setup: &Setup, particles: Particles) -> Self {
        let mut s = State {
            particles,
            ..Default::default()
        };
        s.contacts.rebuild(setup, &mut s.particles);
        pair_contacts(setup, &mut s.particles, &mut s.contacts, 0.0);
        s.wall_loads = walls_gather_kick(setup, &mut s.particles, &mut s.contacts, 0.0, 0.0);
        s
    }
}

/// Advances the state by one time step `setup.dt`.
pub fn step(setup: &Setup, s: &mut State) {
    let dt = setup.dt;
    if kick_drift(setup, &mut s.particles, &s.contacts.pos_at_build) {
        s.contacts.rebuild(setup, &mut s.particles);
    }
    pair_contacts(setup, &mut s.particles, &mut s.contacts, dt);
    s.wall_loads = walls_gather_kick(setup, &mut s.particles, &mut s.contacts, dt, 0.5 * dt);
    s.time += dt;
    s.step += 1;
}
