//! `grains check --ranks N`: how a run would be spread over N ranks, without running it
//! and without MPI. The start is assembled and decomposed exactly as `mpirun -np N
//! grains run` decomposes it (each engine's `Part::new` over in-process ranks; a ring's
//! [`RingPart::new`]), and each rank's owned particles and ghosts are counted. 2D and 3D
//! DEM, and the FEM–DEM ring (its grains decomposed, the charge on every rank).

use super::{Held, Link};
use crate::blast::ranks::RingPart;
use crate::scenario::{self, Scenario};
use crate::source::Source;
use crate::{blast, dem, dem3d};
use grains_dem::decomp::local::run_ranks;
use serde_json::{json, Value};

/// One rank's share of the start.
#[derive(Clone, Debug, PartialEq)]
pub struct Share {
    /// Its box in the rank grid.
    pub cell: Vec<usize>,
    /// Particles it owns.
    pub owned: usize,
    /// Copies of its neighbours' particles within 2 r_max + skin of its box.
    pub ghosts: usize,
    /// What its part needs in memory (bytes), at `grains check`'s figure per particle
    /// (`dem::check::cost`, `dem3d::run::cost`, `blast::check::memory`) applied to owned
    /// + ghost particles, with what every rank holds whole (a ring's charge).
    pub memory_bytes: u64,
    /// Bytes it sends in each step's ghost refresh until the first rebuild (what a run
    /// books as `comm.per_rank_and_step.ghosts.bytes_sent`).
    pub ghost_bytes_per_step: u64,
}

/// A start spread over ranks.
#[derive(Clone, Debug, PartialEq)]
pub struct Spread {
    /// Ranks along each axis.
    pub grid: Vec<usize>,
    /// Whether `[parallel] ranks` gave the grid (else [`grains_dem::decomp::RankGrid::auto`]).
    pub given: bool,
    /// Each rank's share, in rank order.
    pub shares: Vec<Share>,
    /// What the whole run needs in memory on one rank (bytes): every rank holds the
    /// whole start for a moment before it takes its part (docs/parallel.md).
    pub whole_bytes: u64,
    /// What every rank holds whole besides its part, and its memory (bytes; counted in
    /// each share's): a ring's charge.
    pub replicated: Option<(String, u64)>,
}

impl Spread {
    /// Ghosts per owned particle over every rank (as `mpirun -np N grains bench dem`
    /// prints it).
    pub fn ghosts_per_owned(&self) -> f64 {
        let owned: usize = self.shares.iter().map(|s| s.owned).sum();
        let ghosts: usize = self.shares.iter().map(|s| s.ghosts).sum();
        ghosts as f64 / owned.max(1) as f64
    }

    /// Bytes a rank sends in a step's ghost refresh, mean over the ranks.
    pub fn ghost_bytes_per_step(&self) -> f64 {
        let sent: u64 = self.shares.iter().map(|s| s.ghost_bytes_per_step).sum();
        sent as f64 / self.shares.len().max(1) as f64
    }

    /// As aligned lines.
    pub fn text(&self) -> String {
        let how = if self.given {
            "[parallel] ranks"
        } else {
            "chosen: the shortest cuts"
        };
        let mut s = format!(
            "ranks        {} on a {} grid ({how})\n",
            self.shares.len(),
            by(&self.grid, " x ")
        );
        s.push_str(&format!(
            "ghosts       {:.4} per owned particle over every rank\n",
            self.ghosts_per_owned()
        ));
        s.push_str(&format!(
            "ghost bytes  {:.0} B sent per rank and step in the ghost refresh (mean), until the first rebuild\n",
            self.ghost_bytes_per_step()
        ));
        for (r, sh) in self.shares.iter().enumerate() {
            s.push_str(&format!(
                "rank {r:<7} box [{}]: {} owned, {} ghosts ({:.4} per owned), memory ≈ {}, ghost refresh {} B per step\n",
                by(&sh.cell, ", "),
                sh.owned,
                sh.ghosts,
                sh.ghosts as f64 / sh.owned.max(1) as f64,
                crate::estimate::bytes(sh.memory_bytes),
                sh.ghost_bytes_per_step
            ));
        }
        if let Some((what, bytes)) = &self.replicated {
            s.push_str(&format!(
                "replicated   {what} on every rank (≈ {}, in each rank's memory)\n",
                crate::estimate::bytes(*bytes)
            ));
        }
        s.push_str(&format!(
            "start        every rank holds the whole start (≈ {}) until it takes its part\n",
            crate::estimate::bytes(self.whole_bytes)
        ));
        s
    }

    /// As JSON.
    pub fn json(&self) -> Value {
        json!({
            "grid": self.grid,
            "grid_given": self.given,
            "ghosts_per_owned": self.ghosts_per_owned(),
            "ghost_bytes_per_step": self.ghost_bytes_per_step(),
            "start_memory_bytes": self.whole_bytes,
            "replicated": self.replicated.as_ref().map(|(what, bytes)| json!({
                "what": what,
                "memory_bytes_estimate": bytes,
            })),
            "per_rank": self.shares.iter().map(|s| json!({
                "box": s.cell,
                "owned": s.owned,
                "ghosts": s.ghosts,
                "memory_bytes_estimate": s.memory_bytes,
                "ghost_bytes_per_step": s.ghost_bytes_per_step,
            })).collect::<Vec<_>>(),
        })
    }
}

/// `v` joined by `sep`.
fn by(v: &[usize], sep: &str) -> String {
    v.iter().map(usize::to_string).collect::<Vec<_>>().join(sep)
}

/// The start of the scenario `src` spread over `n` ranks as a run would spread it, or
/// why it cannot be (what `mpirun -np N grains run` refuses too), as one line naming
/// the value.
pub fn spread(src: &Source, n: usize) -> Result<Spread, String> {
    if n == 0 {
        return Err("--ranks = 0: must be at least 1".into());
    }
    let refused = |e: String| format!("{}: {e}", src.origin);
    match scenario::parse(src)? {
        Scenario::Dem(s) => flat(&s, src, n).map_err(refused),
        Scenario::Dem3(s) => solid(&s, src, n).map_err(refused),
        Scenario::FemDem(s) => ring(&s, src, n).map_err(refused),
        Scenario::Mpm(_) => Err(refused(
            "--ranks: engine = \"mpm\" does not run on several ranks yet (docs/parallel.md); allowed: DEM (2D, 3D) and FEM–DEM ring scenarios".into(),
        )),
    }
}

/// A DEM start spread as `mpirun` spreads it: `$sim` is the run's module over the
/// engine `$engine` (2D or 3D, one source as `ranks/part.rs` is), `$cost` its figure,
/// `$later` the largest radius a pour of the assembled run adds.
macro_rules! dem_spread {
    ($name:ident, $sim:ident, $engine:ident, $cost:path, $later:expr, $doc:literal) => {
        #[doc = $doc]
        fn $name(s: &$sim::scenario::Scenario, src: &Source, n: usize) -> Result<Spread, String> {
            let dims = $sim::ranks::grid(s.parallel.as_ref(), n)?;
            let balance = $sim::ranks::ParallelSpec::balance_of(s.parallel.as_ref())?;
            refuse(n, || $sim::ranks::unsupported(s))?;
            let a = $sim::assemble::assemble(s, &src.base).map_err(|e| e.to_string())?;
            let walls = a.setup.walls.len();
            let later: f64 = $later(&a);
            let whole = $engine::State::new(&a.setup, a.particles);
            let setup = &a.setup;
            let held = shares(n, |l| {
                $sim::ranks::Part::new(l, setup, &whole, dims, (balance, later)).map(|p| p.held())
            })?;
            let memory = |k: usize| $cost(k as u64, walls, 0, 1).memory_bytes;
            let given = dims.is_some();
            Ok(Spread::of(held, given, whole.particles.len(), memory, None))
        }
    };
}

dem_spread!(
    flat,
    dem,
    grains_dem,
    dem::check::cost,
    |_: &dem::assemble::Assembled| 0.0,
    "A 2D DEM start."
);
dem_spread!(
    solid,
    dem3d,
    grains_dem3d,
    dem3d::run::cost,
    |a: &dem3d::assemble::Assembled| a.pour.as_ref().map_or(0.0, |p| p.largest()),
    "A 3D DEM start."
);

/// What `mpirun` refuses on `n` ranks (nothing on one: that is a serial run).
fn refuse(n: usize, why: impl FnOnce() -> Option<String>) -> Result<(), String> {
    match why().filter(|_| n > 1) {
        Some(why) => Err(why),
        None => Ok(()),
    }
}

/// A FEM–DEM start: the ring's grains decomposed as a run decomposes them, the charge
/// on every rank.
fn ring(s: &blast::scenario::Scenario, src: &Source, n: usize) -> Result<Spread, String> {
    let dims = dem::ranks::grid(s.parallel.as_ref(), n)?;
    let balance = dem::ranks::ParallelSpec::balance_of(s.parallel.as_ref())?;
    refuse(n, || blast::run::unsupported(s))?;
    let a = blast::assemble::assemble(s, &src.base)?;
    let elements = a.mesh.tris.len() as u64;
    let charge = blast::check::memory(0, elements) - blast::check::memory(0, 0);
    let memory = |k: usize| blast::check::memory(k as u64, elements);
    let sim = blast::Blast::new(s, a);
    let replicated = Some(("the charge".to_string(), charge));
    let Some(r) = sim.ring.as_ref() else {
        // One rank, nothing to spread (more are refused above).
        let alone = Held {
            dims: vec![1, 1],
            cell: vec![0, 0],
            owned: 0,
            ghosts: 0,
            ghost_bytes_per_step: 0,
        };
        return Ok(Spread::of(
            vec![alone],
            dims.is_some(),
            0,
            memory,
            replicated,
        ));
    };
    let c = &sim.charge;
    let held = shares(n, |l| {
        RingPart::new(l, (r, c), dims, balance).map(|p| p.part.held())
    })?;
    let grains = r.state.particles.len();
    Ok(Spread::of(held, dims.is_some(), grains, memory, replicated))
}

/// What each of `n` in-process ranks holds of its part, made by `part` from its link;
/// the first rank's refusal when one refuses.
fn shares(
    n: usize,
    part: impl Fn(Link) -> Result<Held, String> + Sync,
) -> Result<Vec<Held>, String> {
    run_ranks(n, |l| {
        // Each rank its own pool, as each MPI process has: a rank waiting for a
        // message must not hold a worker another rank needs.
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .map_err(|e| e.to_string())?;
        pool.install(|| part(Link(Box::new(l))))
    })
    .into_iter()
    .collect()
}

impl Spread {
    /// The spread of `held` (in rank order) of a start of `particles`, whose memory for
    /// `k` particles is `memory(k)`.
    fn of(
        held: Vec<Held>,
        given: bool,
        particles: usize,
        memory: impl Fn(usize) -> u64,
        replicated: Option<(String, u64)>,
    ) -> Spread {
        Spread {
            grid: held.first().map_or_else(Vec::new, |h| h.dims.clone()),
            given,
            shares: held
                .into_iter()
                .map(|h| Share {
                    memory_bytes: memory(h.owned + h.ghosts),
                    cell: h.cell,
                    owned: h.owned,
                    ghosts: h.ghosts,
                    ghost_bytes_per_step: h.ghost_bytes_per_step,
                })
                .collect(),
            whole_bytes: memory(particles),
            replicated,
        }
    }
}
