//! The FEM–DEM ring through the library: bitwise the same on 1, 2 and 3 threads (the
//! fingerprint covers the charge's nodes and elements and the particles), and a loop
//! written against the library ends where `run` ends.

use grains_sim::blast::{assemble::assemble, Blast};
use grains_sim::scenario::{self, Scenario};
use grains_sim::{run, RunOptions, Simulation, Source};

/// A 2 mm PE4 charge in a ring of 0.1 mm disks, 3 µs.
const RING: &str = include_str!("data/ring_tiny.toml");

fn source() -> Source {
    Source {
        text: RING.into(),
        origin: "t_ring.toml".into(),
        base: ".".into(),
    }
}

/// Steps the ring to its end on `threads` threads; its fingerprint and the bits of its
/// mean radial velocity.
fn ring_on(threads: usize) -> (u64, u64) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let src = source();
        let Scenario::FemDem(s) = scenario::parse(&src).unwrap() else {
            panic!("not fem_dem")
        };
        let mut sim = Blast::new(&s, assemble(&s, &src.base).unwrap());
        while sim.clock().time < s.run.duration * (1.0 - 1e-12) {
            sim.advance().unwrap();
        }
        let v = sim.ring_figures().unwrap().mean_velocity;
        (sim.state_hash(), v.to_bits())
    })
}

#[test]
fn the_coupled_ring_is_bitwise_the_same_on_1_2_and_3_threads() {
    let one = ring_on(1);
    assert_eq!(one, ring_on(2), "2 threads differ from 1");
    assert_eq!(one, ring_on(3), "3 threads differ from 1");
}

#[test]
fn a_library_loop_ends_where_run_ends() {
    let (hash, v) = ring_on(2);
    let dir = tempfile::tempdir().unwrap();
    let done = run::run(&source(), RunOptions::new(dir.path().join("out"))).unwrap();
    assert_eq!(done.summary.state_hash, format!("{hash:016x}"));
    let (names, rows) =
        grains_core::history::read_csv(&dir.path().join("out/history.csv")).unwrap();
    let k = names
        .iter()
        .position(|n| n == "mean_radial_velocity")
        .unwrap();
    assert_eq!(rows.last().unwrap()[k].to_bits(), v);
}
