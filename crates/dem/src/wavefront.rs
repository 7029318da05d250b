//! The pair pass and the gather in one sweep: each chunk's reactions, walls and kick
//! run as soon as the last pass that writes a reaction onto its particles (or reads
//! them) is done, while those reactions are still in cache, instead of after the
//! whole pass.
//!
//! A particle's force is its row's sum (ascending partner id), then its walls, then
//! its reactions (ascending owner id): each chunk does the same arithmetic in the same
//! order as the two-phase step, so every bit is the same; only the order of the
//! chunks' work changes. It applies where nothing comes between the pass and the
//! gather (no hook adds a force, no ledger) and on one thread (the chunks are taken
//! one after another); elsewhere the step keeps the two phases.

use crate::forces::pair_contacts_then;
use crate::integrate::{fit_wall_history, merge_loads, Gather, WallSum};
use crate::neighbours::ContactList;
use crate::particles::Particles;
use crate::setup::Setup;
use crate::CHUNK;

/// Whether the list carries the order the fused sweep needs (one entry per chunk of
/// `p`) and the pool runs on one thread.
pub fn applies(p: &Particles, list: &ContactList) -> bool {
    rayon::current_num_threads() == 1 && list.gather_after.len() == p.len().div_ceil(CHUNK)
}

/// The pair pass over `dt` and the closing half kick, fused; returns this rank's part
/// of the load on each wall, as [`crate::integrate::walls_gather_kick`] does.
pub fn pair_contacts_gather_kick(
    setup: &Setup,
    p: &mut Particles,
    list: &mut ContactList,
    dt: f64,
) -> Vec<WallSum> {
    let nw = setup.walls.len();
    let granular = setup.granular.is_some();
    fit_wall_history(setup, list, p.len());
    let after = std::mem::take(&mut list.gather_after);
    // The chunks by the pass they wait for; each waits for itself at least.
    let mut due: Vec<usize> = (0..after.len()).collect();
    due.sort_by_key(|&c| after[c]);
    let mut next = 0;
    let mut total = vec![WallSum::default(); nw];
    pair_contacts_then(setup, p, list, dt, &mut |k, p, list| {
        let (g, mut w) = Gather::split(setup, p, list, dt, 0.5 * dt);
        while let Some(&c) = due.get(next).filter(|&&c| after[c] as usize == k) {
            merge_loads(&mut total, &g.chunk(c, w.own(c, nw, granular)));
            next += 1;
        }
    });
    list.gather_after = after;
    total
}
