//! A 2D DEM run spread over ranks (`mpirun -np N grains run`): each rank steps its box
//! of the domain ([`grains_dem::decomp`]), every global figure is reduced over the
//! ranks, and rank 0 holds the whole state, gathered, at frames and at the end, for the
//! observers that read every particle. The transport (MPI) comes from outside
//! (`grains-mpi`), so this crate needs nothing but cargo; its tests run on in-process
//! ranks.
//!
//! Which observer reads what: the history rows need the samples (reduced on every
//! rank) and the time, step, build count and wall loads (the same on every rank, copied
//! into rank 0's view every step); frames, plots and the end figures and checks read
//! every particle and spring, so those are gathered on rank 0 before each frame and at
//! the end (about 20 words per particle and 3 per spring, through every rank). The rest
//! detector needs the samples only, so every rank runs it and all stop together.

use super::scenario::{CheckSpec, Scenario};
use grains_dem::comm::Post;
use grains_dem::decomp::{Decomposed, GridError};
use grains_dem::diagnostics::Diagnostics;
use grains_dem::{step_on, NoHooks, Reduce, Setup, State};
use serde::{Deserialize, Serialize};

/// `[parallel]`: how a run under `mpirun` is spread over its ranks.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParallelSpec {
    /// Ranks along x and y; their product must be the number of ranks the run is
    /// started on (default: the grid with the shortest cuts for that number).
    #[serde(default)]
    pub ranks: Option<[usize; 2]>,
    /// Load balancing: the most particles on a rank over the mean past which the cut
    /// planes between the ranks' boxes move (a number above 1, default
    /// [`DEFAULT_BALANCE`]), or `"off"` for equal boxes throughout. Any value is read
    /// here and checked by [`balance`], which names what is allowed.
    #[serde(default)]
    pub balance: Option<toml::Value>,
}

/// The imbalance (most particles on a rank over the mean) past which the cuts move when
/// `[parallel] balance` is not given.
pub const DEFAULT_BALANCE: f64 = 1.2;

/// The balance threshold `[parallel] balance` asks for (`None`: off), or why it cannot
/// be, as one line naming the key, the value and what is allowed.
pub fn balance(s: &Scenario) -> Result<Option<f64>, String> {
    let Some(v) = s.parallel.as_ref().and_then(|p| p.balance.as_ref()) else {
        return Ok(Some(DEFAULT_BALANCE));
    };
    let number = v.as_float().or(v.as_integer().map(|i| i as f64));
    match (number, v.as_str()) {
        (Some(t), _) if t.is_finite() && t > 1.0 => Ok(Some(t)),
        (_, Some("off")) => Ok(None),
        _ => Err(format!(
            "parallel.balance = {v}: allowed: a number above 1 (the most particles on a rank over the mean past which the cuts between the ranks move; default {DEFAULT_BALANCE}) or \"off\""
        )),
    }
}

/// The rank grid `[parallel] ranks` asks for on `ranks` ranks (`None`: chosen), or why
/// it cannot be, as one line naming the key, the value and what is allowed.
pub fn grid(s: &Scenario, ranks: usize) -> Result<Option<[usize; 2]>, String> {
    let Some(dims) = s.parallel.as_ref().and_then(|p| p.ranks) else {
        return Ok(None);
    };
    let shown = format!("[{}, {}]", dims[0], dims[1]);
    if dims.contains(&0) {
        return Err(format!("parallel.ranks = {shown}: each must be at least 1"));
    }
    let product = dims[0] * dims[1];
    if product != ranks {
        return Err(format!(
            "parallel.ranks = {shown} makes {product} ranks, but the run has {ranks}; allowed: a grid whose product is {ranks} (or no parallel.ranks)"
        ));
    }
    Ok(Some(dims))
}

/// Why `s` cannot run on several ranks yet, as one line naming what is not supported;
/// `None` when it can. The engine's own refusal (an expanding neighbour frame) comes
/// from [`Decomposed::new`].
pub fn unsupported(s: &Scenario) -> Option<String> {
    let not = |what: String, allowed: &str| {
        Some(format!(
            "{what} is not supported on several ranks yet (docs/parallel.md); allowed: {allowed}"
        ))
    };
    if s.dispersal.is_some() {
        return not("[dispersal]".into(), "no [dispersal] table, or 1 rank");
    }
    for c in &s.checks {
        if !matches!(c, CheckSpec::WallForceOverWeight { .. }) {
            // Collision and impact probes watch particles at every step.
            return not(
                format!("check \"{}\" (a collision or impact probe)", c.name()),
                "kind = \"wall_force_over_weight\" checks, or 1 rank",
            );
        }
    }
    None
}

/// What carries a run's messages between ranks: MPI, or in-process ranks in tests.
pub trait Transport: Reduce + Post + Send {}

impl<T: Reduce + Post + Send> Transport for T {}

/// A transport chosen at run time.
pub struct Link(pub Box<dyn Transport>);

impl Reduce for Link {
    fn ranks(&self) -> usize {
        self.0.ranks()
    }

    fn rank(&self) -> usize {
        self.0.rank()
    }

    fn sum(&self, values: &mut [f64]) {
        self.0.sum(values);
    }

    fn sum_u64(&self, values: &mut [u64]) {
        self.0.sum_u64(values);
    }

    fn max(&self, values: &mut [f64]) {
        self.0.max(values);
    }

    fn gather(&self, words: Vec<u64>) -> Vec<u64> {
        self.0.gather(words)
    }
}

impl Post for Link {
    fn exchange(&self, outgoing: Vec<(usize, Vec<u8>)>, from: &[usize]) -> Vec<Vec<u8>> {
        self.0.exchange(outgoing, from)
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
}

impl Part {
    /// This rank's part of `whole` (the start every rank assembled) on the grid `dims`
    /// (chosen when `None`), its cuts moved when the ranks' particle counts are more
    /// uneven than `balance` ([`balance`]); one line naming what does not fit when it
    /// cannot be.
    pub fn new(
        link: Link,
        setup: &Setup,
        whole: &State,
        dims: Option<[usize; 2]>,
        balance: Option<f64>,
    ) -> Result<Part, String> {
        let r_max = whole.particles.radius.iter().fold(0.0f64, |a, &r| a.max(r));
        let n = link.ranks();
        let mut dec = Decomposed::new(link, setup, dims, r_max)
            .map_err(|e| match dims {
                Some(_) if !matches!(e, GridError::Unsupported(_)) => format!("parallel.{e}"),
                _ => format!("mpirun -np {n}: {e}"),
            })?
            .with_balance(balance);
        let local = dec.start(setup, whole);
        let hash = dec.state_hash(&local);
        Ok(Part { local, dec, hash })
    }

    /// This rank.
    pub fn rank(&self) -> usize {
        self.dec.rank()
    }

    /// One step of this rank's part; `view` (rank 0's whole state between gathers)
    /// takes what every rank knows: time, step, build count, wall loads and poses.
    pub fn advance(&mut self, setup: &Setup, dt: f64, view: &mut State) {
        step_on(setup, &mut self.local, dt, &mut NoHooks, &mut self.dec);
        let s = &self.local;
        view.time = s.time;
        view.step = s.step;
        view.contacts.builds = s.contacts.builds;
        view.wall_loads.clone_from(&s.wall_loads);
        view.walls.clone_from(&s.walls);
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
        if let Some(whole) = self.dec.gather_whole(setup, &self.local) {
            *view = whole;
        }
        self.hash = self.dec.state_hash(&self.local);
    }

    /// The state hash over every rank at the last gather (the serial run's).
    pub fn hash(&self) -> u64 {
        self.hash
    }
}
