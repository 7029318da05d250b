//! The whole state of a decomposed run gathered on rank 0 (what `grains run` under
//! `mpirun` writes its frames, plots and end figures from) is the serial state: the
//! same particles, fields and springs, so the same hash and figures.

use grains_dem::decomp::local::run_ranks;
use grains_dem::decomp::Decomposed;
use grains_dem::diagnostics::{measure, state_hash};
use grains_dem::{step, step_on, NoHooks, State};

#[path = "common/peer.rs"]
mod peer;

#[test]
fn the_state_gathered_on_rank_0_is_the_serial_state() {
    let nx = 20;
    let (set, p) = peer::bed(8 * nx, nx);
    let dt = 5e-4;
    let start = State::new(&set, p);
    let mut serial = start.clone();
    for _ in 0..1500 {
        step(&set, &mut serial, dt);
    }
    let out = run_ranks(4, |l| {
        let mut d = Decomposed::new(l, &set, Some([2, 2]), 0.5).unwrap();
        let mut s = d.start(&set, &start);
        for _ in 0..1500 {
            step_on(&set, &mut s, dt, &mut NoHooks, &mut d);
        }
        d.gather_whole(&set, &s)
    });
    assert!(out[1..].iter().all(Option::is_none), "only rank 0 holds it");
    let whole = out[0].as_ref().expect("rank 0 holds the whole state");
    assert_eq!(whole.particles.len(), serial.particles.len());
    assert_eq!(state_hash(whole), state_hash(&serial));
    let (got, want) = (measure(&set, whole), measure(&set, &serial));
    assert!(want.elastic > 0.0 && want.pair_contacts > 60, "{want:?}");
    assert_eq!(got, want);
    assert_eq!((whole.time, whole.step), (serial.time, serial.step));
}
