//! The FEM–DEM ring of `examples/xue2019/ring_small.toml` run through the library, with
//! no command line: assemble the scenario, step it, and every microsecond read the
//! particles and print the ring's mean radial velocity and its compact band's velocity.
//!
//! `cargo run --release -p grains-sim --example ring [SCENARIO]`
//!
//! The last line equals the last row of the `history.csv` that
//! `grains run examples/xue2019/ring_small.toml` writes: the same steps give bitwise the
//! same state.

use grains_sim::blast::{assemble::assemble, Blast};
use grains_sim::scenario::{self, Scenario};
use grains_sim::{Simulation, Source};

fn main() -> anyhow::Result<()> {
    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "examples/xue2019/ring_small.toml".into());
    let src = Source::read(path.as_ref()).map_err(anyhow::Error::msg)?;
    let Scenario::FemDem(s) = scenario::parse(&src).map_err(anyhow::Error::msg)? else {
        anyhow::bail!("{path}: not a FEM-DEM scenario");
    };
    let a = assemble(&s, &src.base).map_err(anyhow::Error::msg)?;
    let mut sim = Blast::new(&s, a);
    let centre = sim.centre;
    let end = s.run.duration;
    println!("time (µs)  mean radial velocity (m/s)  band velocity (m/s)");
    let mut next = 0.0;
    loop {
        let t = sim.clock().time;
        let done = t >= end * (1.0 - 1e-12);
        if t >= next || done {
            // Any analysis can read the particles as they are now.
            let p = sim.particles();
            let radial: f64 = p
                .pos
                .iter()
                .zip(p.vel)
                .map(|(x, v)| v.dot((*x - centre).normalize_or_zero()))
                .sum::<f64>()
                / p.pos.len().max(1) as f64;
            let band = sim.ring_figures().map_or(f64::NAN, |f| f.band_velocity);
            println!("{:9.3}  {radial:26.3}  {band:19.6}", t * 1e6);
            while next <= t {
                next += 1e-6;
            }
        }
        if done {
            break;
        }
        sim.advance().map_err(anyhow::Error::msg)?;
    }
    println!(
        "band velocity at t = {:.3} µs: {:.12e} m/s (state hash {:016x})",
        sim.clock().time * 1e6,
        sim.ring_figures().map_or(f64::NAN, |f| f.band_velocity),
        sim.state_hash()
    );
    Ok(())
}
