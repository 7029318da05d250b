//! The seams a distributed run plugs into: one interface for every global sum
//! ([`Reduce`]) and the communication stage of a step ([`Exchange`]). A serial run uses
//! [`Serial`], for which both are no-ops, so the engine stays free of any message
//! library (the MPI implementation lives outside it, behind the `mpi` feature of
//! `grains-sim`).
//!
//! Every global quantity of a step goes through [`Reduce`]: the rebuild test (largest
//! displacement, the frame's residuals and sums), the wall loads, the energies of
//! [`crate::diagnostics`], and the state hash, whose records are gathered from every rank
//! and ordered by particle id before they are hashed (so the hash does not depend on
//! which rank holds a particle). The sums are taken in rank order, so a run is
//! reproducible on a given number of ranks.

use crate::particles::Particles;
use crate::setup::Setup;
use crate::step::State;

/// Global reductions, in a fixed order (rank 0 first). Values are combined element-wise
/// and every rank receives the result.
pub trait Reduce {
    /// Number of ranks taking part.
    fn ranks(&self) -> usize {
        1
    }

    /// This rank, 0-based.
    fn rank(&self) -> usize {
        0
    }

    /// Element-wise sum over the ranks, in rank order.
    fn sum(&self, _values: &mut [f64]) {}

    /// Element-wise integer sum over the ranks.
    fn sum_u64(&self, _values: &mut [u64]) {}

    /// Element-wise maximum over the ranks.
    fn max(&self, _values: &mut [f64]) {}

    /// Every rank's words, concatenated in rank order (the serial run's own words).
    fn gather(&self, words: Vec<u64>) -> Vec<u64> {
        words
    }

    /// [`Reduce::sum_u64`] of the energy ledger's exact sums, apart so that a
    /// transport can count the ledger's cost apart from the rest.
    fn sum_ledger(&self, values: &mut [u64]) {
        self.sum_u64(values)
    }

    /// Element-wise minimum over the ranks.
    fn min(&self, values: &mut [f64]) {
        for v in values.iter_mut() {
            *v = -*v;
        }
        self.max(values);
        for v in values.iter_mut() {
            *v = -*v;
        }
    }

    /// Whether `flag` holds on any rank.
    fn any(&self, flag: bool) -> bool {
        let mut v = [flag as u64];
        self.sum_u64(&mut v);
        v[0] > 0
    }
}

/// The communication stage of a DEM step. A distributed run moves particles between
/// ranks at a rebuild (migration, then fresh ghost copies of the particles within
/// contact range plus skin of a neighbour's region) and refreshes the ghosts' motion
/// every step; the serial run does nothing.
pub trait Exchange: Reduce {
    /// At a rebuild, before the neighbour list is made: particles that left this rank's
    /// region go to their new rank with their wall and contact history, and the ghosts
    /// are made anew.
    fn migrate(&mut self, _setup: &Setup, _state: &mut State) {}

    /// Right after the list was rebuilt (and the particles re-sorted): the rank finds
    /// its particles and its ghosts in their new places.
    fn rebuilt(&mut self, _setup: &Setup, _state: &mut State) {}

    /// At the end of every step (and of the initial force evaluation): the ghosts take
    /// their owners' positions, velocities, spins, forces and torques, so the next
    /// step's kick and drift move each ghost exactly as its owner.
    fn refresh(&mut self, _setup: &Setup, _particles: &mut Particles) {}

    /// How many of the stored particles this rank owns (the rest are ghosts).
    fn owned(&self, particles: &Particles) -> usize {
        particles.len()
    }

    /// Whether stored particle `i` is this rank's own (else a ghost).
    fn owns(&self, _i: usize) -> bool {
        true
    }
}

/// Point-to-point messages between ranks (the neighbours of a decomposition): byte
/// buffers, delivered in the order they were sent between any two ranks.
pub trait Post {
    /// Sends each `(rank, bytes)` of `outgoing`, then returns one message from each rank
    /// of `from`, in that order. Sends never wait for the matching receive, so every
    /// rank may send before it receives.
    fn exchange(&self, outgoing: Vec<(usize, Vec<u8>)>, from: &[usize]) -> Vec<Vec<u8>>;
}

/// One process, one rank: every reduction returns its input, every exchange does
/// nothing.
#[derive(Clone, Copy, Debug, Default)]
pub struct Serial;

impl Reduce for Serial {}

impl Exchange for Serial {}

/// A rank has no neighbours to write to.
impl Post for Serial {
    fn exchange(&self, outgoing: Vec<(usize, Vec<u8>)>, from: &[usize]) -> Vec<Vec<u8>> {
        assert!(
            outgoing.is_empty() && from.is_empty(),
            "one rank has no neighbours"
        );
        Vec::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn serial_reductions_are_the_identity() {
        let s = Serial;
        let mut v = [1.5, -2.0];
        s.sum(&mut v);
        s.max(&mut v);
        s.min(&mut v);
        assert_eq!(v, [1.5, -2.0]);
        assert!(s.any(true) && !s.any(false));
        assert_eq!(s.gather(vec![3, 4]), vec![3, 4]);
        assert_eq!((s.rank(), s.ranks()), (0, 1));
    }
}
