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

/// A coupled run's checkpoint bytes read back into a fresh run give the same state; cut
/// short or with any byte changed, they are refused or read, but never panic.
#[test]
fn damaged_checkpoint_bytes_are_refused_never_a_panic() {
    let src = source();
    let Scenario::FemDem(s) = scenario::parse(&src).unwrap() else {
        panic!("not fem_dem")
    };
    let fresh = || Blast::new(&s, assemble(&s, &src.base).unwrap());
    let mut sim = fresh();
    for _ in 0..200 {
        sim.advance().unwrap();
    }
    let bytes = sim.snapshot();
    let mut back = fresh();
    back.restore(&bytes).unwrap();
    assert_eq!(back.state_hash(), sim.state_hash());
    for cut in (0..bytes.len()).step_by(bytes.len() / 97 + 1) {
        assert!(
            fresh().restore(&bytes[..cut]).is_err(),
            "cut at {cut} was read"
        );
    }
    // Some 300 positions spread through the whole file, each changed in turn: lengths,
    // indices and values alike.
    let mut read = 0;
    for at in (0..bytes.len()).step_by(bytes.len() / 301 + 1) {
        let mut bad = bytes.clone();
        bad[at] ^= 0x5a;
        let ok = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            fresh().restore(&bad).is_ok()
        }));
        assert!(ok.is_ok(), "a change at byte {at} made the reader panic");
        read += ok.unwrap() as usize;
    }
    assert!(read > 0, "no changed value was read at all");
}
