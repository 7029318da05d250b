//! The whole state of a decomposed run on rank 0, for the outputs that read every
//! particle (frames, plots, the end-of-run figures and checks): each rank sends its own
//! particles with their wall springs and (partner id, spring) rows; rank 0 puts them in
//! id order and rebuilds the list over the whole domain, which carries the springs over
//! as a serial rebuild does. A few particles (or all of them) without their springs,
//! for what watches them during a run, go to every rank the same way ([`picked`]).

use super::traffic::Stage;
use super::words::{self, Reader};
use super::{carried_of, install, Decomposed};
use crate::comm::{Post, Reduce};
use crate::particles::Particles;
use crate::setup::Setup;
use crate::step::State;

impl<C: Reduce + Post> Decomposed<C> {
    /// The whole state on rank 0 (`None` on the others), from this rank's part `s`:
    /// every particle with every field, every spring, and `s`'s time, step, walls,
    /// wall loads and build count. Every rank must call it at the same point: it is a
    /// collective (each rank's particles are gathered, about 20 words per particle
    /// plus 3 per spring).
    pub fn gather_whole(&self, setup: &Setup, s: &State) -> Option<State> {
        let p = &s.particles;
        let nw = setup.walls.len();
        let owned: Vec<bool> = (0..p.len()).map(|i| self.owns(i)).collect();
        let rows = carried_of(setup, &s.contacts, p, &owned);
        let mut out = Vec::new();
        for i in (0..p.len()).filter(|&i| owned[i]) {
            words::put_particle(&mut out, p, i, true);
            words::put_history(&mut out, &rows[i]);
        }
        let all = self.during(Stage::Other, || self.comm.gather(out));
        if self.comm.rank() != 0 {
            return None;
        }
        let mut r = Reader::new(&all);
        let mut got = Particles::default();
        let mut histories = Vec::new();
        while !r.done() {
            words::get_particle(&mut r, &mut got);
            histories.push(words::get_history(&mut r, nw));
        }
        // Id order, as a serial run starts: the rebuild then sorts them as it would.
        let mut order: Vec<usize> = (0..got.len()).collect();
        order.sort_unstable_by_key(|&k| got.id[k]);
        let mut local = Particles::default();
        let mut hist = Vec::new();
        for k in order {
            words::copy_particle(&got, k, &mut local);
            hist.push(std::mem::take(&mut histories[k]));
        }
        let mut whole = State {
            wall_loads: s.wall_loads.clone(),
            time: s.time,
            step: s.step,
            walls: s.walls.clone(),
            ..Default::default()
        };
        install(setup, &mut whole, local, hist);
        let bounds = (setup.domain.lo, setup.domain.hi);
        whole
            .contacts
            .rebuild_within(setup, bounds, &mut whole.particles);
        whole.contacts.builds = s.contacts.builds;
        Some(whole)
    }

    /// The particles of `s` that `pick` names (by their index in `s`), of every rank,
    /// on every rank, in ascending id: every field but the running ledger, the same bits
    /// as the serial run's [`picked`]. Every rank must call it at the same point with
    /// the same rule: it is a collective (each rank's own picked particles, about 20
    /// words each).
    pub fn gather_picked(&self, s: &State, pick: impl Fn(usize) -> bool) -> Particles {
        let p = &s.particles;
        let mut out = Vec::new();
        for i in (0..p.len()).filter(|&i| self.owns(i) && pick(i)) {
            words::put_particle(&mut out, p, i, false);
        }
        let all = self.during(Stage::Other, || self.comm.gather(out));
        let mut r = Reader::new(&all);
        let mut got = Particles::default();
        while !r.done() {
            words::get_particle(&mut r, &mut got);
        }
        got.ledger.clear();
        picked(&got, |_| true)
    }
}

/// The particles of `p` that `pick` names (by index), in ascending id, every field but
/// the running ledger: a view that does not depend on the storage order (nor, through
/// [`Decomposed::gather_picked`], on the rank count).
pub fn picked(p: &Particles, pick: impl Fn(usize) -> bool) -> Particles {
    let mut order: Vec<usize> = (0..p.len()).filter(|&i| pick(i)).collect();
    order.sort_unstable_by_key(|&i| p.id[i]);
    let mut out = Particles::default();
    for i in order {
        words::copy_particle(p, i, &mut out);
    }
    out.ledger.clear();
    out
}
