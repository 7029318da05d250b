//! The granular law's contact histories, kept only for the pairs that touch.
//!
//! A list entry holds a slot number (4 bytes) instead of a whole history: most entries
//! of a list with a skin do not touch, and their 64-byte records were both memory and
//! the bulk of what the pair pass read for them. The histories themselves live in one
//! pool per fixed chunk of particles ([`crate::CHUNK`]), so a pass over a chunk takes
//! and frees slots without touching another task's pool, and which slot a contact gets
//! depends on the chunk's entry order alone, not on the thread count.

use crate::granular::WIDTH;
use crate::CHUNK;

/// One contact's history under the granular law.
pub type GranularHistory = [f64; WIDTH];

/// The slot of an entry without a history (its pair does not touch).
pub const NONE: u32 = u32::MAX;

/// The histories of one chunk's touching pairs, with the slots freed since the last
/// rebuild kept for reuse.
#[derive(Clone, Debug, Default)]
pub struct Pool {
    data: Vec<GranularHistory>,
    free: Vec<u32>,
}

impl Pool {
    /// The history in `slot`, giving the entry a fresh (zero) one if it has none.
    #[inline]
    pub fn take(&mut self, slot: &mut u32) -> &mut GranularHistory {
        if *slot == NONE {
            *slot = match self.free.pop() {
                Some(s) => {
                    self.data[s as usize] = [0.0; WIDTH];
                    s
                }
                None => {
                    self.data.push([0.0; WIDTH]);
                    (self.data.len() - 1) as u32
                }
            };
        }
        &mut self.data[*slot as usize]
    }

    /// Forgets the history in `slot` (the pair no longer touches), if there is one.
    #[inline]
    pub fn release(&mut self, slot: &mut u32) {
        if *slot != NONE {
            self.free.push(*slot);
            *slot = NONE;
        }
    }

    /// The history in `slot`, which the entry has.
    #[inline]
    pub fn at(&self, slot: u32) -> &GranularHistory {
        &self.data[slot as usize]
    }

    /// Mutable [`Pool::at`].
    #[inline]
    pub fn at_mut(&mut self, slot: u32) -> &mut GranularHistory {
        &mut self.data[slot as usize]
    }
}

/// Every entry's slot and every chunk's pool; empty under the linear law.
#[derive(Clone, Debug, Default)]
pub struct Histories {
    /// Each list entry's slot in its chunk's pool, or [`NONE`].
    pub slot: Vec<u32>,
    /// One pool per chunk of row owners.
    pub pools: Vec<Pool>,
}

impl Histories {
    /// The histories of entries owned by `owner`, each `Some` where it holds anything
    /// (an all-zero history is the same as none).
    pub fn from_entries(
        owner: &[u32],
        chunks: usize,
        mut history: impl FnMut(usize) -> Option<GranularHistory>,
    ) -> Self {
        let mut h = Histories {
            slot: vec![NONE; owner.len()],
            pools: vec![Pool::default(); chunks],
        };
        for (e, &i) in owner.iter().enumerate() {
            if let Some(v) = history(e).filter(|v| v.iter().any(|&x| x != 0.0)) {
                *h.pools[i as usize / CHUNK].take(&mut h.slot[e]) = v;
            }
        }
        h
    }

    /// True when the list keeps granular histories (one slot per entry).
    pub fn kept(&self, entries: usize) -> bool {
        self.slot.len() == entries && entries > 0
    }

    /// Sizes the slots and pools for a list of `entries` entries over `chunks` chunks,
    /// keeping what is there.
    pub fn fit(&mut self, entries: usize, chunks: usize) {
        self.slot.resize(entries, NONE);
        self.pools.resize(chunks, Pool::default());
    }

    /// The history of entry `e`, whose row owner is `owner` (zero when it has none).
    #[inline]
    pub fn get(&self, e: usize, owner: u32) -> GranularHistory {
        match self.slot[e] {
            NONE => [0.0; WIDTH],
            s => *self.pools[owner as usize / CHUNK].at(s),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slots_are_reused_and_start_at_zero() {
        let mut p = Pool::default();
        let (mut a, mut b) = (NONE, NONE);
        p.take(&mut a)[0] = 1.0;
        p.take(&mut b)[0] = 2.0;
        assert_eq!((a, b), (0, 1));
        assert_eq!(p.take(&mut a)[0], 1.0);
        p.release(&mut a);
        assert_eq!(a, NONE);
        assert_eq!(p.take(&mut a)[0], 0.0);
        assert_eq!(a, 0);
    }

    #[test]
    fn zero_histories_take_no_slot() {
        let owner = [0u32, 0, 1, (CHUNK + 1) as u32];
        let h = Histories::from_entries(&owner, 2, |e| Some([e as f64; WIDTH]));
        assert_eq!(h.slot, vec![NONE, 0, 1, 0]);
        assert_eq!(h.get(3, owner[3])[0], 3.0);
        assert_eq!(h.get(0, owner[0]), [0.0; WIDTH]);
    }
}
