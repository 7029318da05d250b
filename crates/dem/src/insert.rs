//! Adding particles to a running state between two steps (pouring): the new particles
//! take global ids past every id in the state, start with no contacts and no wall
//! history, and the neighbour list is rebuilt at once (the particles re-sorted), so the
//! next step sees them like any other.
//!
//! The caller places them clear of the others: no contact history is invented for an
//! overlap. Identity stays the global id, so a checkpoint of a state after an insertion
//! resumes bitwise like any other. The energy ledger, if kept, does not book the energy
//! the new particles bring.

use crate::particles::Particles;
use crate::setup::Setup;
use crate::step::State;
use std::ops::Range;

/// Appends `new` (its `id`s are ignored) to `s` and rebuilds the neighbour list; returns
/// the ids the new particles were given, consecutive from one past the largest id in
/// the state (from 0 in an empty state).
pub fn insert(setup: &Setup, s: &mut State, new: &Particles) -> Range<u32> {
    let first = s.particles.id.iter().max().map_or(0, |&m| m + 1);
    let ids = first..first + new.len() as u32;
    if new.is_empty() {
        return ids;
    }
    let mut named = new.clone();
    named.id = ids.clone().collect();
    append(setup, s, &named);
    s.contacts.rebuild(setup, &mut s.particles);
    ids
}

/// Appends `new` with its own ids to `s`, the list extended as if they had been there
/// at its build with no neighbours: the next rebuild (which must come before the next
/// force pass) carries every existing contact's history over. [`insert`] in a serial
/// run; a decomposed run's insertion (`decomp`) appends each rank's share.
pub fn append(setup: &Setup, s: &mut State, new: &Particles) {
    let n_old = s.particles.len();
    let p = &mut s.particles;
    p.id.extend_from_slice(&new.id);
    p.pos.extend_from_slice(&new.pos);
    p.vel.extend_from_slice(&new.vel);
    p.omega.extend_from_slice(&new.omega);
    p.radius.extend_from_slice(&new.radius);
    p.inv_mass.extend_from_slice(&new.inv_mass);
    p.inv_inertia.extend_from_slice(&new.inv_inertia);
    p.material.extend_from_slice(&new.material);
    // No contact force yet: they were placed clear of every other particle.
    p.force.resize(p.pos.len(), Default::default());
    p.torque.resize(p.pos.len(), Default::default());
    if s.ledger.is_some() {
        // Their running ledgers start empty: what they bring in is the caller's to book.
        p.ledger.resize(p.pos.len(), Default::default());
    }
    let c = &mut s.contacts;
    let n = s.particles.len();
    if c.row.len() == n_old + 1 {
        let last = *c.row.last().unwrap_or(&0);
        c.row.resize(n + 1, last);
    }
    let nw = setup.walls.len();
    if c.wall_shear.len() == n_old * nw {
        c.wall_shear.resize(n * nw, Default::default());
    }
    if c.wall_history.len() == n_old * nw && setup.granular.is_some() {
        c.wall_history.resize(n * nw);
    }
}
