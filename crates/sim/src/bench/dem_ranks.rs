//! `mpirun -np N grains bench dem`: the 2D DEM bench spread over the ranks of a
//! decomposition (the automatic grid), each rank on its own thread pool. Every rank
//! builds the whole bed and its initial forces, keeps its box and the ghosts within
//! 2 r_max + skin of it, then all start the clock together; rank 0 reports, the rate
//! being every particle's steps over rank 0's wall time.

use super::dem::{build, Bed, DT};
use super::{peak_memory_mb, Report};
use crate::dem::ranks::{comm_of, Link};
use grains_dem::decomp::Decomposed;
use grains_dem::{step_on, Exchange, NoHooks, Reduce, State};

/// Times `steps` steps of `bed` over the ranks `link` joins: the report on rank 0,
/// `None` on the others.
pub fn run_on(bed: &Bed, steps: u64, link: Link) -> Result<Option<Report>, String> {
    let (setup, p) = build(bed, steps)?;
    let particles = p.len();
    let r_max = p.radius.iter().fold(0.0f64, |a, &r| a.max(r));
    let whole = State::new(&setup, p);
    let n = link.ranks();
    let mut d =
        Decomposed::new(link, &setup, None, r_max).map_err(|e| format!("mpirun -np {n}: {e}"))?;
    let mut s = d.start(&setup, &whole);
    drop(whole);
    // Every rank starts the clock together.
    d.any(false);
    let mut r = super::timed(particles, steps, || {
        step_on(&setup, &mut s, DT, &mut NoHooks, &mut d)
    });
    let mut held = [s.particles.len() as u64, d.owned(&s.particles) as u64];
    d.sum_u64(&mut held);
    let figures = d.measure(&setup, &s);
    let hash = d.state_hash(&s);
    let comm = comm_of(&d.traffic_over_ranks(&s));
    if d.rank() != 0 {
        return Ok(None);
    }
    let dims = d.grid().dims;
    r.line("ranks", format!("{n} (grid {} x {})", dims[0], dims[1]));
    r.line(
        "ghosts per owned particle",
        format!("{:.4}", (held[0] - held[1]) as f64 / held[1].max(1) as f64),
    );
    r.line("neighbour builds", s.contacts.builds);
    // What the steps sent (the bench keeps no energy ledger).
    r.lines.extend(comm.lines());
    r.line(
        "contacts per particle",
        format!("{:.3}", figures.mean_coordination(particles)),
    );
    r.line("state-hash", format!("{hash:016x}"));
    if let Some(mb) = peak_memory_mb() {
        r.line("peak memory (rank 0)", format!("{mb:.0} MB"));
    }
    Ok(Some(r))
}
