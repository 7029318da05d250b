//! Neighbour search: spatial sort into a cell grid, a half Verlet list in CSR form with
//! the tangential history stored beside it, and the list of walls near each particle.
//!
//! At each rebuild the particles are re-sorted by cell (so a particle's neighbours sit
//! close to it in memory), the list is rebuilt with cutoff r_i + r_j + skin, and the
//! tangential springs of touching pairs are carried over by the particles' stable ids.
//! Between rebuilds the list stays valid while no particle has moved more than skin/2
//! (in a frame that expands with the particles, where the set-up names one:
//! [`crate::verlet`]).

use crate::math::{AngVector, Tangent, Vector, DIM, STENCIL};
use crate::particles::Particles;
use crate::setup::Setup;
use crate::verlet::{frame_centre, Comoving};
use crate::CHUNK;

pub use crate::history::GranularHistory;
use crate::history::{Histories, Narrow};
use rayon::prelude::*;

/// Half neighbour list (each pair once, in the row of its lower id, each row in
/// ascending partner id) with per-entry contact state, plus per-particle wall state.
///
/// The order is one of ids, not of storage, so that a particle's force is the same sum
/// in the same order whichever particles sit beside it in memory: on one rank or
/// several, in any chunking (docs/parallel.md, rule 1). The pair pass adds a row's
/// forces to its owner in row order (ascending partner id) and leaves every entry's
/// force in `fpair`; `walls_gather_kick` then subtracts the reactions in `rev_entry`
/// order (ascending owner id).
#[derive(Clone, Debug, Default)]
pub struct ContactList {
    /// Entries of particle i are `row[i]..row[i+1]` (length N + 1).
    pub row: Vec<u32>,
    /// Partner index j of each entry.
    pub nbr: Vec<u32>,
    /// Row owner i of each entry (made from `row`: [`ContactList::index_owners`]), so
    /// the pair pass walks the entries in one flat loop instead of a short loop per row,
    /// whose exit the processor cannot predict.
    pub owner: Vec<u32>,
    /// Tangential spring displacement ξ of each entry (m); zero when not touching. Empty
    /// under the granular law, whose histories hold its springs ([`ContactList::spring`]
    /// reads either).
    pub shear: Vec<Tangent>,
    /// Force on the row owner from this entry at the last evaluation (the partner gets
    /// the opposite); zero when the pair does not touch. Empty under the granular law,
    /// whose pools keep it for the touching pairs alone ([`ContactList::reaction`]
    /// reads either).
    pub fpair: Vec<Vector>,
    /// The partner's torque from this entry per unit of its radius (the linear law: n ×
    /// F_t, each side's torque being its radius times this). Empty as `fpair` is.
    pub ftan: Vec<AngVector>,
    /// 1 where the entry's pair touched at the last evaluation, else 0. The pass zeroes
    /// an entry's force only when it stops touching (a byte per entry read, where a
    /// force is three to six words written), and on a dilute bed the gather reads the
    /// forces of touching entries only. Not kept in checkpoints: a list read back
    /// starts with every flag set, so the first pass zeroes what does not touch. Empty
    /// under the granular law, whose entries touch where they have a history slot.
    pub touch: Vec<u8>,
    /// How many entries touched at the last evaluation (the gather's choice of loop).
    pub touching: usize,
    /// The energy ledger's terms per particle row, kept from pass to pass.
    pub(crate) ledger_rows: Vec<crate::ledger::PassTally>,
    /// The entries in which particle j is the partner are
    /// `rev_entry[rev_row[j]..rev_row[j+1]]`, in ascending id of their row owner.
    pub rev_row: Vec<u32>,
    /// Entry indices, grouped by partner.
    pub rev_entry: Vec<u32>,
    /// Per chunk of particles: the last chunk whose rows hold an entry with a partner
    /// in it (never less than the chunk itself). Once that chunk's pass is done, no
    /// later pass reads these particles or writes a reaction onto them, so their
    /// gather and kick may run while the reactions are still in cache
    /// ([`crate::wavefront`]).
    pub gather_after: Vec<u32>,
    /// Bit w is set when wall w may touch the particle before the next rebuild.
    pub wall_near: Vec<u64>,
    /// Tangential spring of each particle–wall pair, `[i * n_walls + w]`. Empty under
    /// the granular law, whose wall histories hold its springs (checkpoints still hold
    /// zeros there).
    pub wall_shear: Vec<Tangent>,
    /// Number of walls (stride of `wall_shear`).
    pub n_walls: usize,
    /// With the granular law ([`crate::granular`]): the contact history of each
    /// touching entry, in place of `shear` (empty with the linear law).
    pub history: Histories,
    /// With the granular law: each particle–wall pair's history, record `i * n_walls +
    /// w`, kept as wide as the law writes.
    pub wall_history: Narrow,
    /// Positions at the last rebuild, for the skin criterion.
    pub pos_at_build: Vec<Vector>,
    /// The expanding frame the list is judged in since the last rebuild, where the
    /// set-up has one ([`crate::verlet`]).
    pub frame: Option<Comoving>,
    /// With a frame: each particle's unit vector from its centre at the last rebuild.
    pub normal_at_build: Vec<Vector>,
    /// Number of rebuilds so far.
    pub builds: u64,
}

/// Uniform cell grid over the domain; cells are at least the largest cutoff wide.
#[derive(Clone, Copy, Debug)]
struct CellGrid {
    lo: Vector,
    inv_h: Vector,
    n: [usize; DIM],
    periodic: [bool; DIM],
}

impl CellGrid {
    fn new(setup: &Setup, bounds: (Vector, Vector), particles: &Particles) -> Self {
        let d = &setup.domain;
        // Periodic axes tile the domain exactly; non-periodic ones span `bounds`.
        let (mut lo, mut hi) = bounds;
        for a in 0..DIM {
            if d.periodic[a] {
                lo[a] = d.lo[a];
                hi[a] = d.hi[a];
            }
        }
        let len = hi - lo;
        let mut h = (2.0 * particles.max_radius() + setup.skin).max(f64::MIN_POSITIVE);
        // Bound the cell count (and memory) for sparse systems in large boxes.
        let max_cells = (4 * particles.len()).max(1024) as f64;
        let want = (1..DIM).fold((len[0] / h).ceil(), |w, a| w * (len[a] / h).ceil());
        if want > max_cells {
            h *= crate::math::cell_growth(want / max_cells);
        }
        let mut n = [1usize; DIM];
        let mut inv_h = Vector::ZERO;
        for a in 0..DIM {
            let l = len[a];
            if d.periodic[a] {
                // Cells must tile a periodic axis exactly, each at least h wide.
                n[a] = ((l / h).floor() as usize).max(1);
                inv_h[a] = n[a] as f64 / l;
            } else {
                n[a] = ((l / h).ceil() as usize).max(1);
                inv_h[a] = 1.0 / h;
            }
        }
        CellGrid {
            lo,
            inv_h,
            n,
            periodic: d.periodic,
        }
    }

    #[inline]
    fn coords(&self, p: Vector) -> [usize; DIM] {
        let c = (p - self.lo) * self.inv_h;
        let clamp = |v: f64, n: usize| (v.floor().max(0.0) as usize).min(n - 1);
        std::array::from_fn(|a| clamp(c[a], self.n[a]))
    }

    /// Cells are numbered with the first axis fastest.
    #[inline]
    fn index(&self, c: [usize; DIM]) -> usize {
        (0..DIM).rev().fold(0, |k, a| k * self.n[a] + c[a])
    }

    fn count(&self) -> usize {
        self.n.iter().product()
    }

    /// The distinct cells within one cell of `c` (wrapping periodic axes), the first
    /// axis's offset changing fastest.
    fn around(&self, c: [usize; DIM]) -> ([usize; STENCIL], usize) {
        let mut out = [0usize; STENCIL];
        let mut k = 0;
        'offsets: for o in 0..STENCIL {
            let mut at = [0usize; DIM];
            let mut digits = o;
            for a in 0..DIM {
                let Some(x) = self.step(c[a], (digits % 3) as i64 - 1, a) else {
                    continue 'offsets;
                };
                at[a] = x;
                digits /= 3;
            }
            let id = self.index(at);
            if !out[..k].contains(&id) {
                out[k] = id;
                k += 1;
            }
        }
        (out, k)
    }

    #[inline]
    fn step(&self, c: usize, d: i64, axis: usize) -> Option<usize> {
        let n = self.n[axis] as i64;
        let v = c as i64 + d;
        if self.periodic[axis] {
            Some(v.rem_euclid(n) as usize)
        } else if (0..n).contains(&v) {
            Some(v as usize)
        } else {
            None
        }
    }
}

impl ContactList {
    /// Number of list entries.
    pub fn len(&self) -> usize {
        self.nbr.len()
    }

    /// True when the list has no entries.
    pub fn is_empty(&self) -> bool {
        self.nbr.is_empty()
    }

    /// The linear law's spring of entry `e` (zero where the list keeps none: under the
    /// granular law, and in a list read back before its first rebuild).
    #[inline]
    pub fn spring(&self, e: usize) -> Tangent {
        self.shear.get(e).copied().unwrap_or_default()
    }

    /// Entry `e`'s force on its row owner and its partner's torque per unit radius at
    /// the last evaluation: from the per-entry arrays where the list keeps them (the
    /// linear law, a list read back), else from the granular law's pools.
    pub fn reaction(&self, e: usize) -> (Vector, AngVector) {
        match (self.fpair.get(e), self.ftan.get(e)) {
            (Some(&f), Some(&t)) => (f, t),
            _ if self.history.kept(self.nbr.len()) => self.history.reaction(e, self.owner[e]),
            _ => (Vector::ZERO, AngVector::default()),
        }
    }

    /// The granular law's history of entry `e` (zero where the pair does not touch), or
    /// `None` when the list keeps none (the linear law).
    pub fn granular(&self, e: usize) -> Option<GranularHistory> {
        self.history
            .kept(self.nbr.len())
            .then(|| self.history.get(e, self.owner[e]))
    }

    /// Re-sorts the particles by cell, rebuilds the list and carries the tangential
    /// history of touching pairs (and walls) over to the new order. The cell grid spans
    /// the domain.
    pub fn rebuild(&mut self, setup: &Setup, particles: &mut Particles) {
        self.rebuild_within(setup, (setup.domain.lo, setup.domain.hi), particles);
    }

    /// Like [`ContactList::rebuild`], with the cell grid spanning `bounds` (lower and
    /// upper corner) along the non-periodic axes: a run whose particles spread far beyond
    /// their starting box (an explosive ring) keeps its cells fitted to them.
    pub fn rebuild_within(
        &mut self,
        setup: &Setup,
        bounds: (Vector, Vector),
        particles: &mut Particles,
    ) {
        let n = particles.len();
        let nw = setup.walls.len();
        // The reactions of the last pass are not carried (the next pass makes them
        // anew): freed before the histories are filed by id, they leave room for the
        // copy, which would otherwise be the peak of a run's memory.
        self.fpair = Vec::new();
        self.ftan = Vec::new();
        self.touch = Vec::new();
        self.history.drop_reactions();
        let old = self.history_by_id(particles);
        let granular = setup.granular.is_some();
        let old_granular = granular.then(|| self.granular_by_id(particles));
        // The old list is carried by `old` and `old_granular` now: freed before the new
        // one is built, the peak memory holds one list, not two.
        self.nbr = Vec::new();
        self.shear = Vec::new();
        self.owner = Vec::new();
        self.rev_entry = Vec::new();
        self.history = Histories::default();
        // The granular law's wall histories hold its springs: no linear ones beside them.
        let springs = if granular { 0 } else { n * nw };
        if self.wall_shear.len() != springs {
            self.wall_shear = vec![Tangent::default(); springs];
        }
        if let Some(table) = setup.granular.as_ref() {
            if self.wall_history.len() != n * nw {
                self.wall_history = Narrow::new(table.history_width());
                self.wall_history.resize(n * nw);
            }
        }
        self.n_walls = nw;

        let grid = CellGrid::new(setup, bounds, particles);
        let (perm, cell_start) = sort_by_cell(&grid, particles);
        particles.permute(&perm);
        if nw > 0 && !granular {
            let old_ws = std::mem::take(&mut self.wall_shear);
            self.wall_shear = perm
                .iter()
                .flat_map(|&p| {
                    old_ws[p as usize * nw..(p as usize + 1) * nw]
                        .iter()
                        .copied()
                })
                .collect();
        }
        if nw > 0 && granular {
            self.wall_history = self.wall_history.permuted(&perm, nw);
        }

        // Rows, built per fixed chunk and concatenated in order (deterministic).
        let parts: Vec<(Vec<u32>, Vec<u32>, Vec<Tangent>)> = (0..n.div_ceil(CHUNK))
            .into_par_iter()
            .map(|c| {
                let range = c * CHUNK..((c + 1) * CHUNK).min(n);
                let springs = (!granular).then_some((&old.0, &old.1[..]));
                build_rows(setup, &grid, &cell_start, particles, range, springs, &perm)
            })
            .collect();
        let m: usize = parts.iter().map(|part| part.1.len()).sum();
        self.row.clear();
        self.row.reserve_exact(n + 1);
        self.row.push(0);
        self.nbr.reserve_exact(m);
        if !granular {
            self.shear.reserve_exact(m);
        }
        for (lens, nbr, shear) in parts {
            for l in lens {
                let last = *self.row.last().unwrap();
                self.row.push(last + l);
            }
            self.nbr.extend_from_slice(&nbr);
            self.shear.extend_from_slice(&shear);
        }
        if !granular {
            self.fpair.resize(m, Vector::ZERO);
            self.ftan.resize(m, AngVector::default());
        }
        if !granular {
            // The granular law's slots say which entries touch.
            self.touch.resize(m, 0);
        }
        self.touching = 0;
        self.index_reverse(&particles.id);
        self.history = match old_granular {
            Some((old, value)) => Histories::from_entries(&self.owner, n.div_ceil(CHUNK), |e| {
                let (i, j) = (self.owner[e] as usize, self.nbr[e] as usize);
                let (a, b) = (particles.id[i], particles.id[j]);
                // Filed under the lower id's index before the re-sort.
                let h = value.get(match a < b {
                    true => old.find(perm[i], b)?,
                    false => old.find(perm[j], a)?,
                });
                Some(if a > b {
                    crate::granular::swapped(&h)
                } else {
                    h
                })
            }),
            None => Histories::default(),
        };
        self.find_walls(setup, particles);
        // A wall out of reach starts afresh.
        let kept = !self.wall_shear.is_empty();
        for (i, mask) in self.wall_near.iter().enumerate() {
            for w in (0..nw).filter(|w| mask >> w & 1 == 0) {
                if kept {
                    self.wall_shear[i * nw + w] = Tangent::default();
                }
                if granular {
                    self.wall_history.clear(i * nw + w);
                }
            }
        }
        self.pos_at_build.clone_from(&particles.pos);
        self.frame = frame_centre(setup).map(Comoving::at_build);
        self.normal_at_build = match &self.frame {
            Some(f) => particles.pos.par_iter().map(|&x| f.normal(x)).collect(),
            None => Vec::new(),
        };
        self.builds += 1;
    }

    /// The granular law's history of each contact, as seen from its lower id, filed
    /// under that particle's current index and looked up by the other's id (each
    /// contact once: half the memory of filing it under both, and no hash table), as
    /// wide as the widest pool.
    fn granular_by_id(&self, particles: &Particles) -> (ById, Narrow) {
        let n = particles.len();
        let kept = self.history.kept(self.nbr.len()) && self.owner.len() == self.nbr.len();
        let id = &particles.id;
        let width = self.history.width();
        let filed = |total| {
            let mut v = Narrow::new(width);
            v.resize(total);
            v
        };
        let file = |v: &mut Narrow, k, h: GranularHistory| v.set(k, &h);
        ById::collect(n, filed, file, |put| {
            if !kept {
                return;
            }
            for (e, (&i, &j)) in self.owner.iter().zip(&self.nbr).enumerate() {
                if self.history.slot[e] == crate::history::NONE {
                    continue;
                }
                let h = self.history.get(e, i);
                if h.iter().all(|&x| x == 0.0) {
                    continue;
                }
                let (i, j) = (i as usize, j as usize);
                if id[i] < id[j] {
                    put(i, id[j], h);
                } else {
                    put(j, id[i], crate::granular::swapped(&h));
                }
            }
        })
    }

    /// Each particle's touching pairs as (partner id, ξ as seen from the particle), by
    /// the particle's current index: the history travels with the particle, whatever
    /// its index or rank after the rebuild, and ids need not be 0..N.
    fn history_by_id(&self, particles: &Particles) -> (ById, Vec<Tangent>) {
        let n = particles.len();
        let kept = self.row.len() == n + 1 && self.shear.len() == self.nbr.len();
        let filed = |total| vec![Tangent::default(); total];
        let file = |v: &mut Vec<Tangent>, k, xi| v[k] = xi;
        ById::collect(n, filed, file, |put| {
            if !kept {
                return;
            }
            for i in 0..n {
                for e in self.row[i] as usize..self.row[i + 1] as usize {
                    let xi = self.shear[e];
                    if xi != Tangent::default() {
                        let j = self.nbr[e] as usize;
                        put(i, particles.id[j], xi);
                        put(j, particles.id[i], crate::math::swapped(xi));
                    }
                }
            }
        })
    }

    /// Makes `owner` from `row`, then indexes every entry by partner, each partner's
    /// entries in ascending id of their owner (`id`: the particles' ids). Also what a
    /// list read back from an older checkpoint, whose index held cross-chunk entries
    /// only, is given before its first pass.
    pub fn index_reverse(&mut self, id: &[u32]) {
        self.index_owners();
        let n = self.row.len().saturating_sub(1);
        let mut count = vec![0u32; n + 1];
        for &j in &self.nbr {
            count[j as usize + 1] += 1;
        }
        for k in 0..n {
            count[k + 1] += count[k];
        }
        self.rev_row.clone_from(&count);
        self.rev_entry.clear();
        self.rev_entry.resize(self.nbr.len(), 0);
        let mut fill = count;
        for (e, &j) in self.nbr.iter().enumerate() {
            let slot = &mut fill[j as usize];
            self.rev_entry[*slot as usize] = e as u32;
            *slot += 1;
        }
        let (owner, rev_row) = (&self.owner, &self.rev_row);
        let mut rest = &mut self.rev_entry[..];
        for j in 0..n {
            let (group, tail) = rest.split_at_mut((rev_row[j + 1] - rev_row[j]) as usize);
            group.sort_unstable_by_key(|&e| id[owner[e as usize] as usize]);
            rest = tail;
        }
        self.gather_after = (0..n.div_ceil(CHUNK))
            .map(|c| {
                let rev = rev_row[c * CHUNK] as usize..rev_row[((c + 1) * CHUNK).min(n)] as usize;
                let last = self.rev_entry[rev].iter().map(|&e| owner[e as usize]).max();
                last.map_or(c, |i| (i as usize / CHUNK).max(c)) as u32
            })
            .collect();
    }

    /// Sizes `touch` to the list: a list read back from a checkpoint has no flags, and
    /// gets every flag set, so that the first pass zeroes the forces of entries that
    /// do not touch.
    pub fn fit_touch(&mut self) {
        if self.touch.len() != self.nbr.len() {
            self.touch = vec![1; self.nbr.len()];
        }
    }

    /// Makes `owner` from `row` (after a rebuild, or a list read back from a checkpoint).
    pub fn index_owners(&mut self) {
        self.owner.clear();
        self.owner.resize(self.nbr.len(), 0);
        for i in 0..self.row.len().saturating_sub(1) {
            self.owner[self.row[i] as usize..self.row[i + 1] as usize].fill(i as u32);
        }
    }

    fn find_walls(&mut self, setup: &Setup, particles: &Particles) {
        let nw = setup.walls.len();
        self.wall_near.clear();
        self.wall_near.resize(particles.len(), 0);
        if nw == 0 {
            return;
        }
        let skin = setup.skin;
        self.wall_near
            .par_chunks_mut(CHUNK)
            .enumerate()
            .for_each(|(c, near)| {
                for (k, mask) in near.iter_mut().enumerate() {
                    let i = c * CHUNK + k;
                    let p = particles.pos[i];
                    let r = particles.radius[i];
                    for (w, wall) in setup.walls.iter().enumerate() {
                        let close = wall.translates()
                            || wall.shape.nearest(p).is_none_or(|t| t.distance < r + skin);
                        if close {
                            *mask |= 1 << w;
                        }
                    }
                }
            });
    }
}

/// Stable counting sort of particles by cell: returns the permutation and the CSR start
/// of each cell in the new order.
fn sort_by_cell(grid: &CellGrid, particles: &Particles) -> (Vec<u32>, Vec<u32>) {
    let cells: Vec<u32> = particles
        .pos
        .par_iter()
        .map(|&p| grid.index(grid.coords(p)) as u32)
        .collect();
    let mut start = vec![0u32; grid.count() + 1];
    for &c in &cells {
        start[c as usize + 1] += 1;
    }
    for k in 0..grid.count() {
        start[k + 1] += start[k];
    }
    let mut fill = start.clone();
    let mut perm = vec![0u32; cells.len()];
    for (i, &c) in cells.iter().enumerate() {
        perm[fill[c as usize] as usize] = i as u32;
        fill[c as usize] += 1;
    }
    (perm, start)
}

/// Per-pair records before a rebuild, filed by particle (its index before the rebuild's
/// re-sort): the records of particle `i` are `start[i]..start[i + 1]`, each as (partner
/// id, the record's place in a store of values beside it), so a lookup reads a row of a
/// few entries and the ids themselves may be anything (global ids of a distributed run).
struct ById {
    start: Vec<u32>,
    partner: Vec<u32>,
}

impl ById {
    /// The records `each` puts as (particle index, partner id, value), filed by a
    /// counting sort: `each` runs twice, once to count and once to file (`file` stores
    /// a value at its place in the store `filed` makes for the total), so nothing is
    /// sorted by comparison and nothing is kept twice.
    fn collect<T, S>(
        n: usize,
        filed: impl FnOnce(usize) -> S,
        file: impl Fn(&mut S, usize, T),
        each: impl Fn(&mut dyn FnMut(usize, u32, T)),
    ) -> (Self, S) {
        let mut start = vec![0u32; n + 2];
        each(&mut |i, _, _| start[i + 2] += 1);
        for k in 2..n + 2 {
            start[k] += start[k - 1];
        }
        let total = start[n + 1] as usize;
        let (mut partner, mut value) = (vec![0; total], filed(total));
        each(&mut |i, id, v| {
            let k = start[i + 1] as usize;
            partner[k] = id;
            file(&mut value, k, v);
            start[i + 1] += 1;
        });
        (ById { start, partner }, value)
    }

    /// The place of particle `i`'s record (index before the re-sort) with the particle
    /// of id `partner`, if there is one.
    #[inline]
    fn find(&self, i: u32, partner: u32) -> Option<usize> {
        let i = i as usize;
        let (&from, &to) = (self.start.get(i)?, self.start.get(i + 1)?);
        (from as usize..to as usize).find(|&k| self.partner[k] == partner)
    }
}

#[allow(clippy::too_many_arguments)]
fn build_rows(
    setup: &Setup,
    grid: &CellGrid,
    cell_start: &[u32],
    p: &Particles,
    range: std::ops::Range<usize>,
    springs: Option<(&ById, &[Tangent])>,
    perm: &[u32],
) -> (Vec<u32>, Vec<u32>, Vec<Tangent>) {
    let mut lens = Vec::with_capacity(range.len());
    let mut nbr = Vec::with_capacity(range.len() * 4);
    // Under the granular law the list keeps no linear springs: 24 bytes an entry in 3D.
    let mut shear = Vec::with_capacity(if springs.is_some() {
        range.len() * 4
    } else {
        0
    });
    // Each row scans the whole stencil and keeps the partners of higher id, so a pair
    // is listed by its lower id wherever the two are stored; consecutive rows share a
    // cell, so the stencil is found once per cell.
    let mut cell = usize::MAX;
    let mut around = ([0usize; STENCIL], 0usize);
    let mut row: Vec<(u32, u32, Tangent)> = Vec::with_capacity(16);
    for i in range {
        let at = grid.coords(p.pos[i]);
        let c = grid.index(at);
        if c != cell {
            cell = c;
            around = grid.around(at);
        }
        let me = p.id[i];
        row.clear();
        for &a in &around.0[..around.1] {
            for j in cell_start[a] as usize..cell_start[a + 1] as usize {
                if p.id[j] <= me {
                    continue;
                }
                let cut = p.radius[i] + p.radius[j] + setup.skin;
                let d = setup.domain.min_image(p.pos[j] - p.pos[i]);
                if d.length_squared() < cut * cut {
                    let xi = springs
                        .and_then(|(old, xi)| Some(xi[old.find(perm[i], p.id[j])?]))
                        .unwrap_or_default();
                    row.push((p.id[j], j as u32, xi));
                }
            }
        }
        row.sort_unstable_by_key(|e| e.0);
        nbr.extend(row.iter().map(|e| e.1));
        if springs.is_some() {
            shear.extend(row.iter().map(|e| e.2));
        }
        lens.push(row.len() as u32);
    }
    (lens, nbr, shear)
}
