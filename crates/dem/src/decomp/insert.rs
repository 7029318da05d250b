//! Particles added between two steps of a decomposed run (pouring): every rank is handed
//! the same new particles, numbered from one past the largest id on any rank as a serial
//! insertion numbers them; each rank keeps those in its box, and the decomposition is
//! remade at once (migration, fresh ghosts, the list), as a serial insertion rebuilds
//! the list, so the next step's forces are the serial ones.

use super::traffic::Stage;
use super::Decomposed;
use crate::comm::{Post, Reduce};
use crate::particles::Particles;
use crate::setup::Setup;
use crate::step::State;
use std::ops::Range;

impl<C: Reduce + Post> Decomposed<C> {
    /// Inserts `new` (the same on every rank, its `id`s ignored, placed clear of every
    /// particle) into the run whose part here is `s`; returns the ids they were given,
    /// as [`crate::insert::insert`] gives them in a serial run. A collective: every
    /// rank calls it at the same point.
    pub fn insert(&mut self, setup: &Setup, s: &mut State, new: &Particles) -> Range<u32> {
        let mut top = [s.particles.id.iter().max().map_or(-1.0, |&m| f64::from(m))];
        self.during(Stage::Other, || self.comm.max(&mut top));
        let first = (top[0] + 1.0) as u32;
        let ids = first..first + new.len() as u32;
        if new.is_empty() {
            return ids;
        }
        let me = self.comm.rank();
        let mut mine = Particles::default();
        for k in 0..new.len() {
            if self.grid.owner(new.pos[k]) == me {
                super::words::copy_particle(new, k, &mut mine);
                *mine.id.last_mut().expect("just copied") = first + k as u32;
            }
        }
        mine.ledger.clear();
        crate::insert::append(setup, s, &mine);
        self.owned.resize(s.particles.len(), true);
        if !self.neighbours.is_empty() {
            let was = self.comm.enter(Stage::Rebuild);
            self.migrate_counted(setup, s);
            self.comm.enter(was);
        }
        s.contacts.rebuild(setup, &mut s.particles);
        crate::comm::Exchange::rebuilt(self, setup, s);
        ids
    }
}
