//! `grains check --ranks N`: how a 2D DEM run would be spread over N ranks, without
//! running it and without MPI. The start is assembled and decomposed exactly as
//! `mpirun -np N grains run` decomposes it ([`ranks::Part::new`] over in-process
//! ranks), and each rank's owned particles and ghosts are counted.

use super::assemble::assemble;
use super::ranks::{self, Link, Part};
use crate::scenario::{self, Scenario};
use crate::source::Source;
use grains_dem::decomp::local::run_ranks;
use grains_dem::{Exchange, State};
use serde_json::{json, Value};

/// One rank's share of the start.
#[derive(Clone, Debug, PartialEq)]
pub struct Share {
    /// Its box in the rank grid.
    pub cell: [usize; 2],
    /// Particles it owns.
    pub owned: usize,
    /// Copies of its neighbours' particles within 2 r_max + skin of its box.
    pub ghosts: usize,
    /// What its part needs in memory (bytes), at `grains check`'s figure per particle
    /// (`dem::check::cost`) applied to owned + ghost particles.
    pub memory_bytes: u64,
    /// Bytes it sends in each step's ghost refresh until the first rebuild (what a run
    /// books as `comm.per_rank_and_step.ghosts.bytes_sent`).
    pub ghost_bytes_per_step: u64,
}

/// A 2D DEM start spread over ranks.
#[derive(Clone, Debug, PartialEq)]
pub struct Spread {
    /// Ranks along x and y.
    pub grid: [usize; 2],
    /// Whether `[parallel] ranks` gave the grid (else [`grains_dem::decomp::RankGrid::auto`]).
    pub given: bool,
    /// Each rank's share, in rank order.
    pub shares: Vec<Share>,
    /// What the whole run needs in memory on one rank (bytes): every rank holds the
    /// whole start for a moment before it takes its part (docs/parallel.md).
    pub whole_bytes: u64,
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
        let [nx, ny] = self.grid;
        let how = if self.given {
            "[parallel] ranks"
        } else {
            "chosen: the shortest cuts"
        };
        let mut s = format!(
            "ranks        {} on a {nx} x {ny} grid ({how})\n",
            self.shares.len()
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
                "rank {r:<7} box [{}, {}]: {} owned, {} ghosts ({:.4} per owned), memory ≈ {}, ghost refresh {} B per step\n",
                sh.cell[0],
                sh.cell[1],
                sh.owned,
                sh.ghosts,
                sh.ghosts as f64 / sh.owned.max(1) as f64,
                crate::estimate::bytes(sh.memory_bytes),
                sh.ghost_bytes_per_step
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

/// The start of the scenario `src` spread over `n` ranks as a run would spread it, or
/// why it cannot be, as one line naming the value.
pub fn spread(src: &Source, n: usize) -> Result<Spread, String> {
    if n == 0 {
        return Err("--ranks = 0: must be at least 1".into());
    }
    let s = match scenario::parse(src)? {
        Scenario::Dem(s) => s,
        other => {
            return Err(format!(
                "{}: --ranks: {} (docs/parallel.md); allowed: 2D DEM scenarios",
                src.origin,
                match other {
                    // `mpirun` runs them; this report of the spread is not written yet.
                    Scenario::Dem3(_) => "dim = 3 is not spread by `grains check` yet".to_string(),
                    _ => format!(
                        "engine = \"{}\" does not run on several ranks yet",
                        other.engine()
                    ),
                }
            ));
        }
    };
    let refused = |e: String| format!("{}: {e}", src.origin);
    let dims = ranks::grid(s.parallel.as_ref(), n).map_err(refused)?;
    let balance = ranks::ParallelSpec::balance_of(s.parallel.as_ref()).map_err(refused)?;
    if n > 1 {
        if let Some(why) = ranks::unsupported(&s) {
            return Err(refused(why));
        }
    }
    super::check::fits(&s, src, 1)?;
    let a = assemble(&s, &src.base).map_err(|e| format!("{}: {e}", src.origin))?;
    let walls = a.setup.walls.len();
    let memory = |k: usize| super::check::cost(k as u64, walls, 0, 1).memory_bytes;
    let whole = State::new(&a.setup, a.particles);
    let setup = &a.setup;
    let parts = run_ranks(n, |l| {
        // Each rank its own pool, as each MPI process has: a rank waiting for a
        // message must not hold a worker another rank needs.
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .map_err(|e| e.to_string())?;
        pool.install(|| {
            let part = Part::new(Link(Box::new(l)), setup, &whole, dims, balance)?;
            let held = part.local.particles.len();
            let owned = part.dec.owned(&part.local.particles);
            let grid = part.dec.grid();
            let sent = part.dec.ghost_bytes_per_step();
            Ok((
                grid.dims,
                grid.coords(part.rank()),
                owned,
                held - owned,
                sent,
            ))
        })
    });
    let mut shares = Vec::with_capacity(n);
    let mut grid = [1, 1];
    for p in parts {
        let (dims, cell, owned, ghosts, ghost_bytes_per_step) = p.map_err(refused)?;
        grid = dims;
        shares.push(Share {
            cell,
            owned,
            ghosts,
            memory_bytes: memory(owned + ghosts),
            ghost_bytes_per_step,
        });
    }
    Ok(Spread {
        grid,
        given: dims.is_some(),
        shares,
        whole_bytes: memory(whole.particles.len()),
    })
}
