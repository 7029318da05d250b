//! Domain decomposition: each rank owns the particles in its box of a Cartesian
//! [`RankGrid`] and keeps copies (ghosts) of its neighbours' particles within the
//! contact range plus the skin (2 r_max + skin) of its box.
//!
//! [`Decomposed`] is the [`Exchange`] of such a run, over any transport that offers
//! [`Reduce`] and [`Post`] (in-process ranks: [`local`]; MPI: `grains-mpi`):
//!
//! - at a rebuild, particles whose centre left the box go to the neighbour that owns
//!   them now, with every field, their wall springs and their (partner id, spring)
//!   rows (under the granular law, whole histories); then each rank sends its
//!   neighbours fresh ghosts;
//! - at the end of every step, each ghost takes its owner's position, velocity, spin,
//!   force and torque, so the next kick and drift move it exactly as the owner;
//! - a pair across a boundary is listed and computed on both ranks (the law gives the
//!   two sides bitwise-opposite forces), so no force travels back; a ghost's own force
//!   and wall contacts are not computed (its walls are masked off, so wall loads count
//!   owned particles only).
//!
//! With a balance threshold ([`Decomposed::with_balance`]), the cut planes between
//! the boxes move at the start and at a rebuild when the ranks' particle counts are too
//! uneven ([`balance`]); the particles then go to their new owners, wherever they are.
//!
//! A rank grid of one rank exchanges nothing and is the serial run bit for bit.

pub mod balance;
mod gather;
pub mod grid;
mod insert;
pub mod local;
pub mod traffic;
pub mod words;

pub use gather::picked;
pub use grid::{GridError, RankGrid};

use crate::comm::{Exchange, Post, Reduce};
use crate::history::{GranularHistory, Histories, Narrow};
use crate::math::{self, Tangent, Vector, DIM};
use crate::neighbours::ContactList;
use crate::particles::Particles;
use crate::setup::Setup;
use crate::step::State;
use crate::CHUNK;
use std::collections::HashMap;
use traffic::{Counted, Stage, Totals, Traffic};
use words::{Carried, Reader};

/// One rank of a decomposed run.
pub struct Decomposed<C> {
    /// The transport, every message counted by stage.
    comm: Counted<C>,
    grid: RankGrid,
    /// Ghosts are the particles within this distance of a rank's box (m).
    halo: f64,
    neighbours: Vec<usize>,
    /// Whether each stored particle is this rank's (else a ghost).
    owned: Vec<bool>,
    /// Per neighbour (as `neighbours`): the ids this rank sends it as ghosts, and the
    /// ids of the ghosts it sends here, each in sending order; then their indices after
    /// the last rebuild.
    send_ids: Vec<Vec<u32>>,
    recv_ids: Vec<Vec<u32>>,
    send_at: Vec<Vec<u32>>,
    recv_at: Vec<Vec<u32>>,
    /// The most particles on a rank over the mean past which the cuts move (`None`:
    /// never).
    balance: Option<f64>,
    /// That ratio at the start or the last rebuild, after any move of the cuts.
    imbalance: f64,
    /// How many times the cuts moved.
    rebalances: u64,
}

impl<C: Reduce + Post> Decomposed<C> {
    /// The rank of `comm` in the grid `dims` (chosen by [`RankGrid::auto`] when `None`)
    /// over the set-up's domain, for particles up to `r_max` in radius (on any rank).
    pub fn new(
        comm: C,
        setup: &Setup,
        dims: Option<[usize; DIM]>,
        r_max: f64,
    ) -> Result<Self, GridError> {
        if crate::verlet::frame_centre(setup).is_some() {
            return Err(GridError::Unsupported("an expanding neighbour frame"));
        }
        let mut r = [r_max];
        comm.max(&mut r);
        let halo = 2.0 * r[0] + setup.skin;
        let ranks = comm.ranks();
        let grid = match dims {
            Some(d) => RankGrid::new(setup.domain, d, ranks, halo)?,
            None => RankGrid::auto(setup.domain, ranks, halo)?,
        };
        let neighbours = grid.neighbours(comm.rank());
        let none = vec![Vec::new(); neighbours.len()];
        Ok(Decomposed {
            comm: Counted::new(comm),
            grid,
            halo,
            neighbours,
            owned: Vec::new(),
            send_ids: none.clone(),
            recv_ids: none.clone(),
            send_at: none.clone(),
            recv_at: none,
            balance: None,
            imbalance: 1.0,
            rebalances: 0,
        })
    }

    /// This rank with load balancing: at the start and at every rebuild, when the most
    /// particles on a rank over the mean passes `threshold`, the cuts move
    /// ([`balance`]); `None` keeps the equal boxes.
    pub fn with_balance(mut self, threshold: Option<f64>) -> Self {
        self.balance = threshold;
        self
    }

    /// The most particles owned by a rank over the mean, at the start or the last
    /// rebuild (after any move of the cuts then); 1 on one rank.
    pub fn imbalance(&self) -> f64 {
        self.imbalance
    }

    /// How many times the cuts have moved.
    pub fn rebalances(&self) -> u64 {
        self.rebalances
    }

    /// The transport, back.
    pub fn into_inner(self) -> C {
        self.comm.into_inner()
    }

    /// What this rank has sent and received so far, by stage ([`traffic`]).
    pub fn traffic(&self) -> Traffic {
        self.comm.traffic()
    }

    /// Neighbouring ranks (each sent ghosts every step).
    pub fn neighbours(&self) -> usize {
        self.neighbours.len()
    }

    /// Ghosts this rank holds since the last rebuild (copies of its neighbours'
    /// particles; one neighbour on both sides of a periodic axis sends each once).
    pub fn ghosts(&self) -> usize {
        self.recv_ids.iter().map(Vec::len).sum()
    }

    /// Bytes this rank sends in each step's ghost refresh until the next rebuild:
    /// [`words::MOTION_WORDS`] words for each particle a neighbour holds as a ghost.
    pub fn ghost_bytes_per_step(&self) -> u64 {
        let sent: usize = self.send_ids.iter().map(Vec::len).sum();
        (8 * words::MOTION_WORDS * sent) as u64
    }

    /// Every rank's traffic, particles and ghosts together, on every rank. A collective
    /// (every rank calls it at the same point), counted under [`Stage::Other`].
    pub fn traffic_over_ranks(&self, s: &State) -> Totals {
        self.during(Stage::Other, || {
            let mine = self.traffic();
            let mut w = mine.words();
            w.push(self.owned(&s.particles) as u64);
            w.push(self.ghosts() as u64);
            w.push(1);
            self.comm.sum_u64(&mut w);
            let step = mine.stepping();
            let mut most = [step.sent as f64, step.received as f64];
            self.comm.max(&mut most);
            let n = w.len();
            Totals {
                ranks: w[n - 1],
                sum: Traffic::from_words(&w[..n - 3]),
                owned: w[n - 3],
                ghosts: w[n - 2],
                most_sent: most[0] as u64,
                most_received: most[1] as u64,
            }
        })
    }

    /// `f` with every message counted under `stage`, then the stage as it was.
    fn during<R>(&self, stage: Stage, f: impl FnOnce() -> R) -> R {
        let was = self.comm.enter(stage);
        let r = f();
        self.comm.enter(was);
        r
    }

    /// The grid of ranks.
    pub fn grid(&self) -> &RankGrid {
        &self.grid
    }

    /// Whether stored particle `i` is this rank's own (else a ghost).
    pub fn owns(&self, i: usize) -> bool {
        self.owned.get(i).copied().unwrap_or(true)
    }

    /// This rank's part of `whole`, a state every rank holds in full (made with
    /// [`State::new`], or read back): its particles and ghosts with every field as they
    /// are, its particles' springs, the list rebuilt.
    pub fn start(&mut self, setup: &Setup, whole: &State) -> State {
        // Whatever the start sends is the start's; the steps follow.
        self.comm.enter(Stage::Step);
        if self.neighbours.is_empty() {
            // One rank: the serial state as it is.
            self.owned = vec![true; whole.particles.len()];
            return whole.clone();
        }
        let p = &whole.particles;
        self.rebalance(&p.pos, true);
        let me = self.comm.rank();
        let owner: Vec<usize> = p.pos.iter().map(|&x| self.grid.owner(x)).collect();
        let mine: Vec<bool> = owner.iter().map(|&o| o == me).collect();
        let mut rows = carried_of(setup, &whole.contacts, p, &mine);
        let mut local = Particles::default();
        let mut hist = Vec::new();
        for i in (0..p.len()).filter(|&i| mine[i]) {
            words::copy_particle(p, i, &mut local);
            hist.push(std::mem::take(&mut rows[i]));
        }
        for (k, &q) in self.neighbours.iter().enumerate() {
            let near_me = |i: usize| owner[i] == q && self.grid.distance(p.pos[i], me) <= self.halo;
            self.recv_ids[k] = (0..p.len())
                .filter(|&i| near_me(i))
                .map(|i| p.id[i])
                .collect();
            for i in (0..p.len()).filter(|&i| near_me(i)) {
                words::copy_particle(p, i, &mut local);
            }
            let near_q = |i: usize| mine[i] && self.grid.distance(p.pos[i], q) <= self.halo;
            self.send_ids[k] = (0..p.len())
                .filter(|&i| near_q(i))
                .map(|i| p.id[i])
                .collect();
        }
        let mut s = State {
            wall_loads: whole.wall_loads.clone(),
            // The walls' poses, which a checkpoint (written from the gathered state) holds.
            walls: whole.walls.clone(),
            // The whole run's sums on one rank: the ranks' sums add up to them.
            ledger: whole.ledger.as_ref().map(|l| {
                if me == 0 {
                    l.clone()
                } else {
                    Default::default()
                }
            }),
            time: whole.time,
            step: whole.step,
            ..Default::default()
        };
        s.contacts.builds = whole.contacts.builds;
        install(setup, &mut s, local, hist);
        let bounds = (setup.domain.lo, setup.domain.hi);
        s.contacts.rebuild_within(setup, bounds, &mut s.particles);
        s.contacts.builds = whole.contacts.builds;
        self.rebuilt(setup, &mut s);
        s
    }

    /// The state hash of the run over every rank ([`crate::diagnostics::state_hash`]).
    pub fn state_hash(&self, s: &State) -> u64 {
        self.during(Stage::Other, || {
            crate::diagnostics::state_hash_on(s, self, |i| self.owns(i))
        })
    }

    /// The run's figures over every rank ([`crate::diagnostics::measure`]): each rank's
    /// own particles, each pair once.
    pub fn measure(&self, setup: &Setup, s: &State) -> crate::diagnostics::Diagnostics {
        // The flags, not `self`: the transport need not be shared between threads.
        let owned = &self.owned;
        self.during(Stage::Other, || {
            crate::diagnostics::measure_where(setup, s, self, |i| {
                owned.get(i).copied().unwrap_or(true)
            })
        })
    }

    /// Sends each rank of `to` its part of `out` (aligned with `to`) and returns what
    /// each sent here, as words.
    fn swap(&self, to: &[usize], out: Vec<Vec<u64>>) -> Vec<Vec<u64>> {
        let outgoing = to
            .iter()
            .zip(out)
            .map(|(&q, w)| (q, words::bytes_of(&w)))
            .collect();
        let got = self.comm.exchange(outgoing, to);
        got.iter().map(|b| words::words_of(b)).collect()
    }

    /// The migration of a rebuild ([`Exchange::migrate`]), counted under its stage.
    fn migrate_counted(&mut self, setup: &Setup, s: &mut State) {
        let me = self.comm.rank();
        let nw = setup.walls.len();
        let p = &s.particles;
        let mut rows = carried_of(setup, &s.contacts, p, &self.owned);
        let own: Vec<Vector> = (0..p.len())
            .filter(|&i| self.owned[i])
            .map(|i| p.pos[i])
            .collect();
        // Moved cuts may hand a particle to any rank; else it stays within reach.
        let to: Vec<usize> = if self.rebalance(&own, false) {
            (0..self.comm.ranks()).filter(|&q| q != me).collect()
        } else {
            self.neighbours.clone()
        };
        // Round 1: particles that left the box, with their history.
        let mut out = vec![vec![0u64]; to.len()];
        let mut local = Particles::default();
        let mut hist = Vec::new();
        for i in (0..p.len()).filter(|&i| self.owned[i]) {
            let owner = self.grid.owner(p.pos[i]);
            if owner == me {
                words::copy_particle(p, i, &mut local);
                hist.push(std::mem::take(&mut rows[i]));
                continue;
            }
            let w = &mut out[slot(&to, owner, me)];
            w[0] += 1;
            words::put_particle(w, p, i, true);
            words::put_history(w, &rows[i]);
        }
        for got in self.swap(&to, out) {
            let mut r = Reader::new(&got);
            for _ in 0..r.word() {
                words::get_particle(&mut r, &mut local);
                hist.push(words::get_history(&mut r, nw));
            }
        }
        // Round 2: fresh ghosts of the particles now owned.
        let mut out = vec![Vec::new(); self.neighbours.len()];
        for (k, &q) in self.neighbours.iter().enumerate() {
            let near: Vec<usize> = (0..local.len())
                .filter(|&i| self.grid.distance(local.pos[i], q) <= self.halo)
                .collect();
            self.send_ids[k] = near.iter().map(|&i| local.id[i]).collect();
            for i in near {
                words::put_particle(&mut out[k], &local, i, false);
            }
        }
        for (k, got) in self.swap(&self.neighbours, out).into_iter().enumerate() {
            let mut r = Reader::new(&got);
            let from = local.len();
            while !r.done() {
                words::get_particle(&mut r, &mut local);
            }
            self.recv_ids[k] = local.id[from..].to_vec();
        }
        install(setup, s, local, hist);
    }
}

/// Where rank `q` is in `to`, the ranks rank `me` sends particles to.
fn slot(to: &[usize], q: usize, me: usize) -> usize {
    to.iter().position(|&n| n == q).unwrap_or_else(|| {
        panic!("a particle moved past the neighbours of rank {me} in one list's life")
    })
}

/// Installs `local` (owned particles first, then ghosts) into `s` with a list that
/// holds nothing but the owned particles' springs (or granular histories), in the form
/// the rebuild carries over (rows by particle index, partner by index, each entry's
/// history as seen from its row's particle).
fn install(setup: &Setup, s: &mut State, local: Particles, hist: Vec<Carried>) {
    let n = local.len();
    let nw = setup.walls.len();
    let at: HashMap<u32, u32> = local
        .id
        .iter()
        .enumerate()
        .map(|(k, &id)| (id, k as u32))
        .collect();
    let list = &mut s.contacts;
    list.row = vec![0];
    list.nbr.clear();
    list.shear.clear();
    let mut granular = Vec::new();
    // A pair of two owned particles is in both rows: listed once.
    let partner = |i: usize, j: u32| {
        at.get(&j)
            .copied()
            .filter(|&j| j as usize >= hist.len() || i < j as usize)
    };
    for (i, c) in hist.iter().enumerate() {
        for &(j, xi) in &c.rows {
            if let Some(j) = partner(i, j) {
                list.nbr.push(j);
                list.shear.push(xi);
                granular.push(None);
            }
        }
        for &(j, h) in &c.granular_rows {
            if let Some(j) = partner(i, j) {
                list.nbr.push(j);
                list.shear.push(Tangent::default());
                granular.push(Some(h));
            }
        }
        list.row.push(list.nbr.len() as u32);
    }
    list.row.resize(n + 1, list.nbr.len() as u32);
    list.index_owners();
    list.history = match setup.granular {
        Some(_) => Histories::from_entries(&list.owner, n.div_ceil(CHUNK), |e| granular[e]),
        None => Default::default(),
    };
    list.wall_shear = hist.iter().flat_map(|c| c.walls.iter().copied()).collect();
    list.wall_shear.resize(n * nw, Tangent::default());
    list.wall_history = match setup.granular {
        Some(_) => {
            let w: Vec<GranularHistory> = hist
                .iter()
                .flat_map(|c| c.granular_walls.iter().copied())
                .collect();
            let mut w = Narrow::from_records(&w);
            w.resize(n * nw);
            w
        }
        None => Narrow::default(),
    };
    s.particles = local;
}

/// The contact history of each particle `keep` names, by its index, from the list: its
/// wall springs (or granular wall histories) and its pair springs (or granular
/// histories) as seen from it.
fn carried_of(setup: &Setup, list: &ContactList, p: &Particles, keep: &[bool]) -> Vec<Carried> {
    let nw = setup.walls.len();
    let mut rows = vec![Carried::default(); p.len()];
    for (i, c) in rows.iter_mut().enumerate().filter(|(i, _)| keep[*i]) {
        c.walls = list
            .wall_shear
            .get(i * nw..(i + 1) * nw)
            .map_or_else(|| vec![Tangent::default(); nw], <[Tangent]>::to_vec);
        if setup.granular.is_some() {
            c.granular_walls = (i * nw..(i + 1) * nw)
                .map(|k| list.wall_history.try_get(k).unwrap_or_default())
                .collect();
        }
    }
    if list.owner.len() != list.nbr.len() {
        return rows;
    }
    let kept = list.history.kept(list.nbr.len());
    for e in 0..list.nbr.len() {
        let (i, j, xi) = (list.owner[e] as usize, list.nbr[e] as usize, list.spring(e));
        if xi != Tangent::default() {
            if keep[i] {
                rows[i].rows.push((p.id[j], xi));
            }
            if keep[j] {
                rows[j].rows.push((p.id[i], math::swapped(xi)));
            }
        }
        if !kept || list.history.slot[e] == crate::history::NONE {
            continue;
        }
        let h = list.history.get(e, list.owner[e]);
        if h.iter().any(|&x| x != 0.0) {
            if keep[i] {
                rows[i].granular_rows.push((p.id[j], h));
            }
            if keep[j] {
                rows[j]
                    .granular_rows
                    .push((p.id[i], crate::granular::swapped(&h)));
            }
        }
    }
    rows
}

impl<C: Reduce> Reduce for Decomposed<C> {
    fn ranks(&self) -> usize {
        self.comm.ranks()
    }

    fn rank(&self) -> usize {
        self.comm.rank()
    }

    fn sum(&self, values: &mut [f64]) {
        self.comm.sum(values);
    }

    fn sum_u64(&self, values: &mut [u64]) {
        self.comm.sum_u64(values);
    }

    fn max(&self, values: &mut [f64]) {
        self.comm.max(values);
    }

    fn gather(&self, words: Vec<u64>) -> Vec<u64> {
        self.comm.gather(words)
    }

    fn sum_ledger(&self, values: &mut [u64]) {
        self.comm.sum_ledger(values)
    }
}

impl<C: Reduce + Post> Exchange for Decomposed<C> {
    fn migrate(&mut self, setup: &Setup, s: &mut State) {
        self.comm.tick(true);
        if self.neighbours.is_empty() {
            return;
        }
        let was = self.comm.enter(Stage::Rebuild);
        self.migrate_counted(setup, s);
        self.comm.enter(was);
    }

    fn rebuilt(&mut self, _setup: &Setup, s: &mut State) {
        let me = self.comm.rank();
        let p = &s.particles;
        self.owned = p.pos.iter().map(|&x| self.grid.owner(x) == me).collect();
        // A ghost's wall contacts are its owner's to compute (and to load the wall with).
        for (near, &own) in s.contacts.wall_near.iter_mut().zip(&self.owned) {
            if !own {
                *near = 0;
            }
        }
        let at: HashMap<u32, u32> =
            p.id.iter()
                .enumerate()
                .map(|(k, &id)| (id, k as u32))
                .collect();
        let find = |ids: &Vec<Vec<u32>>| -> Vec<Vec<u32>> {
            ids.iter()
                .map(|v| v.iter().map(|id| at[id]).collect())
                .collect()
        };
        self.send_at = find(&self.send_ids);
        self.recv_at = find(&self.recv_ids);
    }

    fn refresh(&mut self, _setup: &Setup, p: &mut Particles) {
        self.comm.tick(false);
        if self.neighbours.is_empty() {
            return;
        }
        self.comm.enter(Stage::Ghosts);
        let out = self
            .send_at
            .iter()
            .map(|idx| {
                let mut w = Vec::new();
                for &i in idx {
                    words::put_motion(&mut w, p, i as usize);
                }
                w
            })
            .collect();
        for (k, got) in self.swap(&self.neighbours, out).into_iter().enumerate() {
            let mut r = Reader::new(&got);
            for &i in &self.recv_at[k] {
                words::get_motion(&mut r, p, i as usize);
            }
        }
        // What follows, until the next refresh, is the next step's.
        self.comm.enter(Stage::Step);
    }

    fn owns(&self, i: usize) -> bool {
        // The inherent method, of the same meaning.
        Decomposed::owns(self, i)
    }

    fn owned(&self, particles: &Particles) -> usize {
        if self.owned.len() == particles.len() {
            self.owned.iter().filter(|&&o| o).count()
        } else {
            particles.len()
        }
    }
}
