//! Runs spread over ranks (`mpirun -np N grains run`), for both DEM builds: the
//! transport ([`Link`]), the refusal's wording and the frame pieces here; the part a
//! rank steps is one source, `ranks/part.rs`, compiled once per engine as the engine
//! itself is (`dem::ranks` over `grains_dem`, `dem3d::ranks` over `grains_dem3d`).

pub mod comm;
pub mod spread;

use crate::driver::{agreed, Counters, Outcome, Plan, Simulation};
use crate::frames::{FrameRecorder, Framed};
use crate::history::{HistoryRecorder, Recorded};
use crate::run::{fresh_out, summary, Costs, Finished, RunError};
use anyhow::Context;
use grains_core::vtk::PolyData;
use grains_dem::comm::Post;
use grains_dem::Reduce;
use std::io;
use std::path::Path;

/// What carries a run's messages between ranks: MPI, or in-process ranks in tests. The
/// 2D engine's seams; the 3D engine's are implemented over them (`ranks/part.rs`), so
/// one MPI world serves both.
pub trait Transport: Reduce + Post + Send {}

impl<T: Reduce + Post + Send> Transport for T {}

/// A transport chosen at run time.
pub struct Link(pub Box<dyn Transport>);

/// What one rank holds of a decomposed start ([`spread`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Held {
    /// Ranks along each axis.
    pub dims: Vec<usize>,
    /// The rank's box in the grid.
    pub cell: Vec<usize>,
    /// Particles it owns.
    pub owned: usize,
    /// Copies of its neighbours' particles within 2 r_max + skin of its box.
    pub ghosts: usize,
    /// Bytes it sends in each step's ghost refresh until the first rebuild.
    pub ghost_bytes_per_step: u64,
}

/// The imbalance (most particles on a rank over the mean) past which the cuts move when
/// `[parallel] balance` is not given.
pub const DEFAULT_BALANCE: f64 = 1.2;

/// The balance threshold `[parallel] balance` (the value `v`, when given) asks for
/// (`None`: off), or why it cannot be, as one line naming the key, the value and what is
/// allowed.
pub fn balance(v: Option<&toml::Value>) -> Result<Option<f64>, String> {
    let Some(v) = v else {
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

/// Why something in a scenario cannot run on several ranks, as one line naming it and
/// what is allowed.
pub fn not_on_ranks(what: &str, allowed: &str) -> String {
    format!("{what} is not supported on several ranks yet (docs/parallel.md); allowed: {allowed}")
}

/// Writes rank `rank`'s piece of frame `k`, `poly` (its own particles), as
/// `particles_<k>_r<rank>.vtp`; on rank 0 also the index `particles_<k>.pvtp` over the
/// `ranks` pieces, whose name it returns. Every rank writes a piece, an empty one too,
/// so the index names them without asking the others.
pub fn write_piece(
    poly: &PolyData,
    dir: &Path,
    k: usize,
    (rank, ranks): (usize, usize),
) -> io::Result<Option<String>> {
    poly.write(&dir.join(piece_name(k, rank)))?;
    if rank != 0 {
        return Ok(None);
    }
    let pieces: Vec<String> = (0..ranks).map(|r| piece_name(k, r)).collect();
    let name = format!("particles_{k:05}.pvtp");
    poly.write_pvtp(&dir.join(&name), &pieces)?;
    Ok(Some(name))
}

/// Rank `rank`'s piece of frame `k`.
pub fn piece_name(k: usize, rank: usize) -> String {
    format!("particles_{k:05}_r{rank:03}.vtp")
}

/// The history and frame recorders of a run and the loop's counters, on any rank: rank
/// 0 (`leader`, or the only rank) starts the output directory (the scenario `text`
/// copied in) or reopens it where the checkpoint whose counters are `resumed` left it,
/// as [`crate::run::recorders`]; the other ranks of a run spread over ranks keep a
/// history written nowhere and write their pieces of each frame. A failure on rank 0
/// stops every rank at the same point.
pub fn recorders<S: Simulation + Recorded + Framed>(
    sim: &mut S,
    (leader, spread): (bool, bool),
    (out, text): (&Path, &str),
    plan: &Plan,
    resumed: Option<&Counters>,
) -> Result<(HistoryRecorder, FrameRecorder, Counters), RunError> {
    if spread && resumed.is_none() {
        // Both branches below sample a fresh start, together, so what could fail before
        // that sample is tried first, by itself.
        let ready = match leader {
            true => fresh_out(out, text).and_then(|()| {
                let path = out.join("history.csv");
                std::fs::File::create(&path)
                    .map(drop)
                    .with_context(|| format!("cannot create {}", path.display()))
            }),
            false => Ok(()),
        };
        agreed(sim, ready)?;
    }
    let started = if leader {
        crate::run::recorders(out, text, sim, plan, resumed)
    } else {
        // Every rank keeps the loop's counters: they say when all gather together.
        let counters = resumed.cloned().unwrap_or_else(|| Counters::fresh(plan));
        HistoryRecorder::discarding(sim, resumed.is_none())
            .map(|history| {
                let pieces = FrameRecorder::pieces(out, counters.frames);
                (history, pieces, counters)
            })
            .map_err(RunError::from)
    };
    agreed(sim, started)
}

/// How a run ended on a rank other than 0, which writes nothing: its summary as rank 0
/// would make it (the state hash is the run's over every rank).
pub fn finished_elsewhere<S: Simulation>(
    (name, out): (&str, &Path),
    sim: &S,
    outcome: Outcome,
    costs: Costs,
) -> Finished {
    let sum = summary(name, "dem", sim, &outcome, costs, Default::default());
    Finished {
        status: outcome.status,
        checks: sum.checks.clone(),
        summary: sum,
        out: out.to_path_buf(),
    }
}

/// Puts a run's load balance into its summary's counts: the most particles on a rank
/// over the mean at the end, and how many times the cut planes moved, both of this
/// segment of the run (a resumed run counts afresh).
pub fn count_balance(
    counts: &mut serde_json::Map<String, serde_json::Value>,
    imbalance: f64,
    rebalances: u64,
) {
    counts.insert("rank_imbalance".into(), imbalance.into());
    counts.insert("rebalances".into(), rebalances.into());
}
