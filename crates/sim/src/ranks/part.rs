// One rank's part of a DEM run spread over ranks, for both dimensions: compiled once
// per engine, as a child of `dem::ranks` (which names `grains_dem` its `engine`) and of
// `dem3d::ranks` (`grains_dem3d`), as the engine's own source is built twice.
//
// Each rank steps its box of the domain (the engine's `decomp`), every global figure
// is reduced over the ranks, and rank 0 holds the whole state, gathered, at frames,
// checkpoints and the end, for the observers that read every particle. The history
// rows need the samples (reduced on every rank) and the time, step, build count and wall
// loads (the same on every rank, copied into rank 0's view every step); the energy
// ledger's sums are combined over the ranks at samples and gathers only.

use super::engine::comm::Post;
use super::engine::decomp::traffic::Totals;
use super::engine::decomp::{Decomposed, GridError};
use super::engine::diagnostics::Diagnostics;
use super::engine::ledger_sums::{self, LedgerSums};
use super::engine::math::{Vector, DIM};
use super::engine::{
    step_on, EnergyLedger, Exchange, Hooks, NoHooks, Particles, Reduce, Setup, State,
};
use crate::ranks::comm::{Comm, PerStep};
use crate::ranks::Link;
use serde::{Deserialize, Serialize};

/// `[parallel]`: how a run under `mpirun` is spread over its ranks.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParallelSpec {
    /// Ranks along each axis; their product must be the number of ranks the run is
    /// started on (default: the grid with the shortest cuts for that number).
    #[serde(default)]
    pub ranks: Option<[usize; DIM]>,
    /// Load balancing: the most particles on a rank over the mean past which the cut
    /// planes between the ranks' boxes move (a number above 1, default
    /// [`crate::ranks::DEFAULT_BALANCE`]), or `"off"` for equal boxes throughout. Any
    /// value is read here and checked by [`crate::ranks::balance`], which names what is
    /// allowed.
    #[serde(default)]
    pub balance: Option<toml::Value>,
}

impl ParallelSpec {
    /// The balance threshold of `spec` (the default when there is no `[parallel]`).
    pub fn balance_of(spec: Option<&ParallelSpec>) -> Result<Option<f64>, String> {
        crate::ranks::balance(spec.and_then(|p| p.balance.as_ref()))
    }
}

/// The rank grid `[parallel] ranks` asks for on `ranks` ranks (`None`: chosen), or why
/// it cannot be, as one line naming the key, the value and what is allowed.
pub fn grid(spec: Option<&ParallelSpec>, ranks: usize) -> Result<Option<[usize; DIM]>, String> {
    let Some(dims) = spec.and_then(|p| p.ranks) else {
        return Ok(None);
    };
    let shown: Vec<String> = dims.iter().map(usize::to_string).collect();
    let shown = format!("[{}]", shown.join(", "));
    if dims.contains(&0) {
        return Err(format!("parallel.ranks = {shown}: each must be at least 1"));
    }
    let product: usize = dims.iter().product();
    if product != ranks {
        return Err(format!(
            "parallel.ranks = {shown} makes {product} ranks, but the run has {ranks}; allowed: a grid whose product is {ranks} (or no parallel.ranks)"
        ));
    }
    Ok(Some(dims))
}

/// What every engine's `open_on` settles before it assembles: the rank grid and the
/// balance `[parallel]` asks for on `link`'s ranks (one rank without a link), and, on
/// ranks, that the scenario may be spread at all (`unsupported` says why not).
pub fn layout(
    spec: Option<&ParallelSpec>,
    link: Option<&Link>,
    unsupported: impl FnOnce() -> Option<String>,
) -> Result<(Option<[usize; DIM]>, Option<f64>), String> {
    let dims = grid(spec, link.map_or(1, Reduce::ranks))?;
    let balance = ParallelSpec::balance_of(spec)?;
    match link.and_then(|_| unsupported()) {
        Some(why) => Err(why),
        None => Ok((dims, balance)),
    }
}

impl Reduce for Link {
    fn ranks(&self) -> usize {
        grains_dem::Reduce::ranks(&*self.0)
    }

    fn rank(&self) -> usize {
        grains_dem::Reduce::rank(&*self.0)
    }

    fn sum(&self, values: &mut [f64]) {
        grains_dem::Reduce::sum(&*self.0, values);
    }

    fn sum_u64(&self, values: &mut [u64]) {
        grains_dem::Reduce::sum_u64(&*self.0, values);
    }

    fn max(&self, values: &mut [f64]) {
        grains_dem::Reduce::max(&*self.0, values);
    }

    fn gather(&self, words: Vec<u64>) -> Vec<u64> {
        grains_dem::Reduce::gather(&*self.0, words)
    }
}

impl Post for Link {
    fn exchange(&self, outgoing: Vec<(usize, Vec<u8>)>, from: &[usize]) -> Vec<Vec<u8>> {
        grains_dem::comm::Post::exchange(&*self.0, outgoing, from)
    }
}

/// This rank's part of a run spread over ranks.
pub struct Part {
    /// Its particles, then its ghosts.
    pub local: State,
    /// The decomposition and its transport.
    pub dec: Decomposed<Link>,
    /// The state hash over every rank at the last gather.
    hash: u64,
    /// Every rank's messages until the last gather.
    comm: Comm,
}

impl Part {
    /// This rank's part of `whole` (the start every rank assembled) on the grid `dims`
    /// (chosen when `None`), its cuts moved when the ranks' particle counts are more
    /// uneven than `balance` ([`ParallelSpec::balance_of`]); one line naming what does
    /// not fit when it cannot be. `later` is the largest radius of the particles a pour
    /// will add (0 for none): the ghost layer must reach them too.
    pub fn new(
        link: Link,
        setup: &Setup,
        whole: &State,
        dims: Option<[usize; DIM]>,
        (balance, later): (Option<f64>, f64),
    ) -> Result<Part, String> {
        let r_max = whole.particles.radius.iter().fold(later, |a, &r| a.max(r));
        let n = link.ranks();
        let mut dec = Decomposed::new(link, setup, dims, r_max)
            .map_err(|e| match dims {
                Some(_) if !matches!(e, GridError::Unsupported(_)) => format!("parallel.{e}"),
                _ => format!("mpirun -np {n}: {e}"),
            })?
            .with_balance(balance);
        let local = dec.start(setup, whole);
        let hash = dec.state_hash(&local);
        let comm = comm_of(&dec.traffic_over_ranks(&local));
        Ok(Part {
            local,
            dec,
            hash,
            comm,
        })
    }

    /// This rank.
    pub fn rank(&self) -> usize {
        self.dec.rank()
    }

    /// Ranks the run is spread over.
    pub fn ranks(&self) -> usize {
        self.dec.ranks()
    }

    /// One step of this rank's part; `view` (rank 0's whole state between gathers)
    /// takes what every rank knows: time, step, build count, wall loads and poses (the
    /// energy ledger only when asked: [`Part::ledger_figures`]).
    pub fn advance(&mut self, setup: &Setup, dt: f64, view: &mut State) {
        self.advance_with(setup, dt, &mut NoHooks, view);
    }

    /// [`Part::advance`] with outside forces from `hooks` (a coupled charge's edge),
    /// which are handed the decomposition's reductions and ownership.
    pub fn advance_with<H: Hooks>(
        &mut self,
        setup: &Setup,
        dt: f64,
        hooks: &mut H,
        view: &mut State,
    ) {
        step_on(setup, &mut self.local, dt, hooks, &mut self.dec);
        let s = &self.local;
        view.time = s.time;
        view.step = s.step;
        view.contacts.builds = s.contacts.builds;
        view.wall_loads.clone_from(&s.wall_loads);
        view.walls.clone_from(&s.walls);
    }

    /// The energy ledger's figures over every rank (on every rank; each rank must ask
    /// at the same time): the exact sums of each rank's own particles' running ledgers,
    /// combined in a fixed number of words, so the serial run's figures bit for bit.
    pub fn ledger_figures(&self) -> Option<EnergyLedger> {
        let own = ledger_sums::sums(&self.local, |i| self.dec.owns(i))?;
        Some(own.total(&self.dec).figures())
    }

    /// What left the run on every rank, summed (collective; see
    /// [`super::engine::ledger_sums`]).
    fn departed(&self) -> Option<LedgerSums> {
        Some(self.local.ledger.as_ref()?.total(&self.dec))
    }

    /// The run's figures over every rank, the serial ones bit for bit (on every rank).
    pub fn sample(&self, setup: &Setup) -> Diagnostics {
        self.dec.measure(setup, &self.local)
    }

    /// The first of `test`'s findings on any rank, in rank order (on every rank).
    pub fn first(&self, test: impl Fn(&State) -> Option<String>) -> Option<String> {
        let mine = test(&self.local).unwrap_or_default();
        let mut words = vec![mine.len() as u64];
        words.extend(mine.bytes().map(u64::from));
        let all = self.dec.gather(words);
        let mut at = 0;
        while at < all.len() {
            let n = all[at] as usize;
            if n > 0 {
                let bytes: Vec<u8> = all[at + 1..at + 1 + n].iter().map(|&b| b as u8).collect();
                return Some(String::from_utf8_lossy(&bytes).into_owned());
            }
            at += 1 + n;
        }
        None
    }

    /// Gathers the whole state into rank 0's `view` (the other ranks' stays as it is)
    /// and takes the state hash over every rank.
    pub fn gather(&mut self, setup: &Setup, view: &mut State) {
        let ledger = self.departed();
        if let Some(whole) = self.dec.gather_whole(setup, &self.local) {
            *view = whole;
            view.ledger = ledger;
        }
        self.hash = self.dec.state_hash(&self.local);
        self.comm = comm_of(&self.dec.traffic_over_ranks(&self.local));
    }

    /// What every rank sent until the last gather (the end, at the end of a run).
    pub fn comm(&self) -> &Comm {
        &self.comm
    }

    /// The state hash over every rank at the last gather (the serial run's).
    pub fn hash(&self) -> u64 {
        self.hash
    }

    /// What this rank holds: its box, its own particles and ghosts, and its ghost
    /// refresh per step (`grains check --ranks N`).
    pub fn held(&self) -> crate::ranks::Held {
        let held = self.local.particles.len();
        let owned = self.dec.owned(&self.local.particles);
        let grid = self.dec.grid();
        crate::ranks::Held {
            dims: grid.dims.to_vec(),
            cell: grid.coords(self.rank()).to_vec(),
            owned,
            ghosts: held - owned,
            ghost_bytes_per_step: self.dec.ghost_bytes_per_step(),
        }
    }

    /// Inserts `new` (the same on every rank; a collective), numbered as a serial
    /// insertion numbers them; each rank keeps those in its box. `view` (rank 0's whole
    /// state between gathers) takes the list's build count.
    pub fn insert(&mut self, setup: &Setup, new: &Particles, view: &mut State) {
        self.dec.insert(setup, &mut self.local, new);
        view.contacts.builds = self.local.contacts.builds;
    }

    /// This rank's own particles (not its ghosts), as indices into `local`.
    pub fn own(&self) -> Vec<usize> {
        (0..self.local.particles.len())
            .filter(|&i| self.dec.owns(i))
            .collect()
    }
}

/// What a probe watching particles during a run sees: those that `pick` names by id, in
/// ascending id, with every field, whether the whole run is here (`whole`, `part` is
/// `None`) or spread over ranks (`part`: then on every rank, a collective). The same
/// bits either way, so a probe's figures do not depend on the rank count, nor, in a
/// serial run, on the storage order.
pub fn watched(part: Option<&Part>, whole: &State, pick: impl Fn(u32) -> bool) -> Particles {
    seen(part, whole, |p, i| pick(p.id[i]))
}

/// The particles, in ascending id, whose centre and radius `near` accepts (as
/// [`watched`]: here or over every rank, then a collective).
pub fn nearby(part: Option<&Part>, whole: &State, near: impl Fn(Vector, f64) -> bool) -> Particles {
    seen(part, whole, |p, i| near(p.pos[i], p.radius[i]))
}

/// The largest radius of the run's particles (over every rank: a collective).
pub fn largest_radius(part: Option<&Part>, whole: &State) -> f64 {
    match part {
        Some(part) => {
            let mut r = [part.local.particles.max_radius()];
            part.dec.max(&mut r);
            r[0]
        }
        None => whole.particles.max_radius(),
    }
}

/// The particles `pick` accepts (by index into the particles it is handed), in
/// ascending id, here or over every rank.
fn seen(part: Option<&Part>, whole: &State, pick: impl Fn(&Particles, usize) -> bool) -> Particles {
    match part {
        Some(part) => {
            let p = &part.local.particles;
            part.dec.gather_picked(&part.local, |i| pick(p, i))
        }
        None => super::engine::decomp::picked(&whole.particles, |i| pick(&whole.particles, i)),
    }
}

/// `t` per rank and per step, as a user reads it.
pub fn comm_of(t: &Totals) -> Comm {
    let per = |bytes: u64| t.per_rank_step(bytes);
    let stage = |f: &super::engine::decomp::traffic::Flow| PerStep {
        messages: per(f.messages),
        collectives: per(f.collectives),
        sent: per(f.sent),
        received: per(f.received),
    };
    let s = &t.sum;
    let steps = t.steps().max(1) as f64;
    Comm {
        ranks: t.ranks,
        steps: t.steps(),
        rebuilds: s.rebuilds / t.ranks.max(1),
        owned: t.owned,
        ghosts: t.ghosts,
        stages: [s.ghosts, s.rebuild, s.reductions, s.ledger, s.other].map(|f| stage(&f)),
        busiest_sent: t.most_sent as f64 / steps,
        busiest_received: t.most_received as f64 / steps,
    }
}

/// The [`crate::driver::Simulation`] methods that a simulation spread over ranks answers
/// through its `ranks: Option<Box<Part>>` (`None`: the whole run is here, in `state`):
/// the state hash, the gather, which frames read the whole state, the agreement and
/// the rank count. Expanded inside the engine's `impl Simulation`, where
/// `diagnostics`, `FrameKind` and `Reduce` are in scope.
macro_rules! spread_methods {
    () => {
        fn state_hash(&self) -> u64 {
            match &self.ranks {
                Some(part) => part.hash(),
                None => diagnostics::state_hash(&self.state),
            }
        }

        fn gather(&mut self) {
            if let Some(part) = self.ranks.as_mut() {
                part.gather(&self.setup, &mut self.state);
            }
        }

        fn frame_reads_whole(&self, kind: FrameKind) -> bool {
            // Each rank writes its piece of a frame; the snapshot maps and a LAMMPS
            // dump are drawn from every particle on rank 0.
            self.ranks.is_none() || kind != FrameKind::Regular || self.lammps_dump
        }

        fn agree(&self, flag: bool) -> bool {
            match &self.ranks {
                Some(part) => part.dec.any(flag),
                None => flag,
            }
        }

        fn ranks(&self) -> usize {
            self.ranks.as_ref().map_or(1, |p| p.dec.ranks())
        }
    };
}

pub(crate) use spread_methods;
