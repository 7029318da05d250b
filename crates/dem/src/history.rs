//! The granular law's contact histories, kept only for the pairs that touch, and each
//! only as wide as the law writes.
//!
//! A list entry holds a slot number (4 bytes) instead of a whole history: most entries
//! of a list with a skin do not touch, and their 64-byte records were both memory and
//! the bulk of what the pair pass read for them. The histories themselves live in one
//! pool per fixed chunk of particles ([`crate::CHUNK`]), so a pass over a chunk takes
//! and frees slots without touching another task's pool, and which slot a contact gets
//! depends on the chunk's entry order alone, not on the thread count.
//!
//! A history's numbers past what its law writes stay zero (Mindlin without rescale,
//! rolling or twisting writes the tangential spring alone: 3 of 8 numbers in 3D), so
//! records are kept in [`Narrow`] rows, as wide as the widest history they have held;
//! the zeros past the width are implied. A row that is handed a wider history widens
//! first, so no number is ever lost and the bits are those of full-width records.

use crate::granular::WIDTH;
use crate::math::{AngVector, Vector, TAN};
use crate::CHUNK;

/// One contact's history under the granular law.
pub type GranularHistory = [f64; WIDTH];

/// The slot of an entry without a history (its pair does not touch).
pub const NONE: u32 = u32::MAX;

/// How many leading numbers of `h` are needed to hold it: up to its last non-zero
/// number, and never fewer than the tangential spring's.
#[inline]
pub fn width_of(h: &GranularHistory) -> usize {
    h.iter()
        .rposition(|&x| x != 0.0)
        .map_or(0, |k| k + 1)
        .max(TAN)
}

/// Granular histories in rows of `width` numbers each (the rest of each history zero).
#[derive(Clone, Debug)]
pub struct Narrow {
    width: usize,
    data: Vec<f64>,
}

impl Default for Narrow {
    fn default() -> Self {
        Narrow::new(TAN)
    }
}

impl Narrow {
    /// No records, each to be `width` numbers wide (at least the tangential spring's).
    pub fn new(width: usize) -> Self {
        Narrow {
            width: width.clamp(TAN, WIDTH),
            data: Vec::new(),
        }
    }

    /// The records `h`, as wide as the widest of them.
    pub fn from_records(h: &[GranularHistory]) -> Self {
        let mut out = Narrow::new(h.iter().map(width_of).max().unwrap_or(TAN));
        out.data.reserve_exact(h.len() * out.width);
        for r in h {
            out.data.extend_from_slice(&r[..out.width]);
        }
        out
    }

    /// How many numbers each record keeps.
    #[inline]
    pub fn width(&self) -> usize {
        self.width
    }

    /// Number of records.
    #[inline]
    pub fn len(&self) -> usize {
        self.data.len() / self.width
    }

    /// True when there are no records.
    pub fn is_empty(&self) -> bool {
        self.data.is_empty()
    }

    /// Record `k`, zeros past the width.
    #[inline]
    pub fn get(&self, k: usize) -> GranularHistory {
        read(&self.data[k * self.width..(k + 1) * self.width])
    }

    /// Record `k`, or `None` past the last.
    #[inline]
    pub fn try_get(&self, k: usize) -> Option<GranularHistory> {
        (k < self.len()).then(|| self.get(k))
    }

    /// The kept numbers of record `k`.
    #[inline]
    pub fn row(&self, k: usize) -> &[f64] {
        &self.data[k * self.width..(k + 1) * self.width]
    }

    /// Mutable [`Narrow::row`].
    #[inline]
    pub fn row_mut(&mut self, k: usize) -> &mut [f64] {
        &mut self.data[k * self.width..(k + 1) * self.width]
    }

    /// Stores `h` as record `k`, widening every record first if `h` needs more numbers.
    #[inline]
    pub fn set(&mut self, k: usize, h: &GranularHistory) {
        let need = width_of(h);
        if need > self.width {
            self.widen(need);
        }
        let w = self.width;
        self.data[k * w..(k + 1) * w].copy_from_slice(&h[..w]);
    }

    /// Appends a zero record and returns its index.
    #[inline]
    pub fn push_zero(&mut self) -> usize {
        self.data.resize(self.data.len() + self.width, 0.0);
        self.len() - 1
    }

    /// Sets every number of record `k` to zero.
    #[inline]
    pub fn clear(&mut self, k: usize) {
        self.row_mut(k).fill(0.0);
    }

    /// Keeps `width` numbers of each record from now on (never fewer than now).
    pub fn widen(&mut self, width: usize) {
        let width = width.min(WIDTH);
        if width <= self.width {
            return;
        }
        let old = std::mem::take(&mut self.data);
        self.data.reserve_exact(old.len() / self.width * width);
        for r in old.chunks_exact(self.width) {
            self.data.extend_from_slice(r);
            self.data.resize(self.data.len() + width - self.width, 0.0);
        }
        self.width = width;
    }

    /// `records` records, the new ones zero.
    pub fn resize(&mut self, records: usize) {
        self.data.resize(records * self.width, 0.0);
    }

    /// Every record at full width, one after another (the checkpoint's layout).
    pub fn full(&self) -> Vec<f64> {
        (0..self.len()).flat_map(|k| self.get(k)).collect()
    }

    /// The records in groups of `group` (a particle's walls), group `g` of the result
    /// being group `perm[g]` of these.
    pub fn permuted(&self, perm: &[u32], group: usize) -> Self {
        let stride = group * self.width;
        let mut data = Vec::with_capacity(perm.len() * stride);
        for &p in perm {
            data.extend_from_slice(&self.data[p as usize * stride..(p as usize + 1) * stride]);
        }
        Narrow {
            width: self.width,
            data,
        }
    }

    /// Records `range` as a run one task owns.
    pub fn slice_mut(&mut self, range: std::ops::Range<usize>) -> NarrowMut<'_> {
        let width = self.width;
        NarrowMut {
            width,
            data: &mut self.data[range.start * width..range.end * width],
        }
    }

    /// The records split into runs of `records` records each, in order.
    pub fn chunks_mut(&mut self, records: usize) -> Vec<NarrowMut<'_>> {
        let width = self.width;
        self.data
            .chunks_mut((records * width).max(1))
            .map(|data| NarrowMut { width, data })
            .collect()
    }
}

/// A run of [`Narrow`]'s records that one task owns; its width is fixed.
#[derive(Debug, Default)]
pub struct NarrowMut<'a> {
    width: usize,
    data: &'a mut [f64],
}

impl NarrowMut<'_> {
    /// Record `k`, zeros past the width.
    #[inline]
    pub fn get(&self, k: usize) -> GranularHistory {
        read(&self.data[k * self.width..(k + 1) * self.width])
    }

    /// Stores `h` as record `k`; `h` must fit the width (the run was widened for its
    /// law before it was split).
    #[inline]
    pub fn set(&mut self, k: usize, h: &GranularHistory) {
        debug_assert!(width_of(h) <= self.width, "a history wider than its rows");
        let w = self.width;
        self.data[k * w..(k + 1) * w].copy_from_slice(&h[..w]);
    }

    /// Sets record `k` to zero, where there are records.
    #[inline]
    pub fn clear(&mut self, k: usize) {
        let w = self.width;
        if let Some(r) = self.data.get_mut(k * w..(k + 1) * w) {
            r.fill(0.0);
        }
    }

    /// True when the run holds no records (the linear law's).
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.data.is_empty()
    }
}

#[inline]
fn read(row: &[f64]) -> GranularHistory {
    let mut h = [0.0; WIDTH];
    h[..row.len()].copy_from_slice(row);
    h
}

/// The histories of one chunk's touching pairs, with the slots freed since the last
/// rebuild kept for reuse, and beside each history its pair's reaction at the last pass.
///
/// The reaction (the force on the row owner, the partner's torque per unit of its
/// radius) is kept per touching pair rather than per list entry: an entry apart has no
/// reaction to keep, and about half the entries of a dense bed are apart. Its arrays
/// grow when the pass first writes a reaction, not when a slot is taken: a rebuild,
/// which fills new pools while the old histories are still held, then holds histories
/// alone.
///
/// The force and the torque of a pair sit side by side in one record ([`Reaction`]):
/// the gather, which reads them in the order of the partners' entries, then meets one
/// line of memory a pair where two arrays cost it two.
#[derive(Clone, Debug, Default)]
pub struct Pool {
    data: Narrow,
    reactions: Vec<Reaction>,
    free: Vec<u32>,
}

/// A touching pair's reaction: the force on the row owner and the partner's torque per
/// unit of its radius.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Reaction {
    /// Force on the row owner.
    pub force: Vector,
    /// The partner's torque per unit of its radius.
    pub moment: AngVector,
}

impl Pool {
    /// Gives the entry a fresh (zero) history if it has none; returns its slot.
    #[inline]
    pub fn take(&mut self, slot: &mut u32) -> u32 {
        if *slot == NONE {
            *slot = match self.free.pop() {
                Some(s) => {
                    self.data.clear(s as usize);
                    s
                }
                None => self.data.push_zero() as u32,
            };
        }
        *slot
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
    pub fn at(&self, slot: u32) -> GranularHistory {
        self.data.get(slot as usize)
    }

    /// Stores `h` in `slot` (the pool widens if `h` needs it).
    #[inline]
    pub fn put(&mut self, slot: u32, h: &GranularHistory) {
        self.data.set(slot as usize, h);
    }

    /// The reaction of the pair in `slot` at the last pass: the force on the row owner
    /// and the partner's torque per unit of its radius.
    #[inline]
    pub fn reaction(&self, slot: u32) -> (Vector, AngVector) {
        let r = reaction_in(&self.reactions, slot);
        (r.force, r.moment)
    }

    /// Every slot's reaction so far (slots past the end have none yet): what the
    /// gather reads through [`reaction_in`].
    #[inline]
    pub fn reactions(&self) -> &[Reaction] {
        &self.reactions
    }

    /// Keeps the reaction of the pair in `slot` ([`Pool::reaction`]).
    #[inline(always)]
    pub fn set_reaction(&mut self, slot: u32, force: Vector, moment: AngVector) {
        let s = slot as usize;
        if s >= self.reactions.len() {
            self.grow_reactions();
        }
        self.reactions[s] = Reaction { force, moment };
    }

    /// Sizes the reactions to the histories (the first reaction written since the
    /// pool grew).
    #[cold]
    #[inline(never)]
    fn grow_reactions(&mut self) {
        self.reactions.resize(self.data.len(), Reaction::default());
    }

    /// The tangential spring in `slot` (the first numbers of its history).
    #[inline]
    pub fn spring(&self, slot: u32) -> &[f64] {
        &self.data.row(slot as usize)[..TAN]
    }

    /// Mutable [`Pool::spring`].
    #[inline]
    pub fn spring_mut(&mut self, slot: u32) -> &mut [f64] {
        &mut self.data.row_mut(slot as usize)[..TAN]
    }

    /// Keeps at least `width` numbers of each history from now on.
    pub fn widen(&mut self, width: usize) {
        self.data.widen(width);
    }

    /// How many numbers each history keeps.
    pub fn width(&self) -> usize {
        self.data.width()
    }
}

/// The reaction in `slot` of a pool's [`Pool::reactions`], zero where it has none.
#[inline(always)]
pub fn reaction_in(reactions: &[Reaction], slot: u32) -> Reaction {
    reactions.get(slot as usize).copied().unwrap_or_default()
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
                let pool = &mut h.pools[i as usize / CHUNK];
                let s = pool.take(&mut h.slot[e]);
                pool.put(s, &v);
            }
        }
        h
    }

    /// True when the list keeps granular histories (one slot per entry).
    pub fn kept(&self, entries: usize) -> bool {
        self.slot.len() == entries && entries > 0
    }

    /// Sizes the slots and pools for a list of `entries` entries over `chunks` chunks,
    /// keeping what is there, each pool at least `width` numbers wide.
    pub fn fit(&mut self, entries: usize, chunks: usize, width: usize) {
        self.slot.resize(entries, NONE);
        self.pools.resize(chunks, Pool::default());
        for p in &mut self.pools {
            p.widen(width);
        }
    }

    /// Frees every pool's reactions (a rebuild, which does not carry them: the next
    /// pass writes them anew).
    pub fn drop_reactions(&mut self) {
        for p in &mut self.pools {
            p.reactions = Vec::new();
        }
    }

    /// The widest pool's width.
    pub fn width(&self) -> usize {
        self.pools.iter().map(Pool::width).max().unwrap_or(TAN)
    }

    /// The reaction of entry `e`, whose row owner is `owner` (zero when its pair did not
    /// touch at the last pass).
    #[inline]
    pub fn reaction(&self, e: usize, owner: u32) -> (Vector, AngVector) {
        match self.slot[e] {
            NONE => (Vector::ZERO, AngVector::default()),
            s => self.pools[owner as usize / CHUNK].reaction(s),
        }
    }

    /// The history of entry `e`, whose row owner is `owner` (zero when it has none).
    #[inline]
    pub fn get(&self, e: usize, owner: u32) -> GranularHistory {
        match self.slot[e] {
            NONE => [0.0; WIDTH],
            s => self.pools[owner as usize / CHUNK].at(s),
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
        let sa = p.take(&mut a);
        p.spring_mut(sa)[0] = 1.0;
        let sb = p.take(&mut b);
        p.spring_mut(sb)[0] = 2.0;
        assert_eq!((a, b), (0, 1));
        let s = p.take(&mut a);
        assert_eq!(p.at(s)[0], 1.0);
        p.release(&mut a);
        assert_eq!(a, NONE);
        let s = p.take(&mut a);
        assert_eq!(p.at(s)[0], 0.0);
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

    #[test]
    fn a_reaction_is_read_through_its_entry_slot() {
        let owner = [0u32, (CHUNK + 2) as u32];
        let mut h = Histories::from_entries(&owner, 2, |_| Some([1.0; WIDTH]));
        let f = Vector::splat(2.5);
        h.pools[1].set_reaction(h.slot[1], f, AngVector::default());
        assert_eq!(h.reaction(1, owner[1]).0, f);
        assert_eq!(h.reaction(0, owner[0]).0, Vector::ZERO);
        h.pools[1].release(&mut h.slot[1]);
        assert_eq!(h.reaction(1, owner[1]).0, Vector::ZERO);
    }

    #[test]
    fn a_wider_history_widens_the_rows_and_keeps_every_number() {
        let mut n = Narrow::default();
        assert_eq!(n.width(), TAN);
        n.resize(3);
        let mut first = [0.0; WIDTH];
        first[0] = 1.5;
        n.set(0, &first);
        let mut wide = [0.0; WIDTH];
        wide[0] = -2.0;
        wide[WIDTH - 1] = 0.25;
        n.set(2, &wide);
        assert_eq!(n.width(), WIDTH);
        assert_eq!((n.get(0), n.get(1), n.get(2)), (first, [0.0; WIDTH], wide));
        assert_eq!(Narrow::from_records(&[first, wide]).width(), WIDTH);
        assert_eq!(Narrow::from_records(&[first]).width(), TAN);
        assert_eq!(n.full().len(), 3 * WIDTH);
    }
}
