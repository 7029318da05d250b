//! `grains check --ranks N` (`ranks::spread`) against what a run measures: a 3D column
//! and the FEM–DEM ring spread over 2 and 4 ranks, then run one step on as many
//! in-process ranks; the run's summary books the same particles owned, the same ghosts
//! and, for its one step, the ghost refresh the spread promised, to the byte.

#[path = "common/on_ranks.rs"]
mod on_ranks;

use grains_sim::ranks::spread::{spread, Spread};
use grains_sim::run::{self, RunOptions};
use grains_sim::Source;
use on_ranks::{example_in, on_ranks_with};

/// Checks `s` (`n` ranks) against a run of `src` stopped after its first step.
fn measured(src: &Source, n: usize, s: &Spread, what: &str) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    let done = on_ranks_with(n, |l| {
        let mut o = RunOptions::new(&out);
        o.stop_at_step = Some(1);
        run::run_on(src, o, l)
    });
    let leader = done.into_iter().next().unwrap().unwrap();
    let comm = &leader.summary.counts["comm"];
    let owned: usize = s.shares.iter().map(|r| r.owned).sum();
    let ghosts: usize = s.shares.iter().map(|r| r.ghosts).sum();
    assert_eq!(comm["steps"], 1, "{what}: {comm}");
    assert_eq!(
        comm["rebuilds"], 0,
        "{what}: a rebuild moved the ghosts: {comm}"
    );
    assert_eq!(comm["owned"], owned, "{what}: {comm}");
    assert_eq!(comm["ghosts"], ghosts, "{what}: {comm}");
    let sent = comm["per_rank_and_step"]["ghosts"]["bytes_sent"]
        .as_f64()
        .unwrap();
    assert_eq!(sent, s.ghost_bytes_per_step(), "{what}: {comm}");
    assert!(ghosts > 0, "{what}: no ghosts");
}

/// Memory per rank: the whole start's figure per particle on owned + ghosts, plus what
/// every rank holds whole (`charge`).
fn memory_is_per_particle(s: &Spread, particles: u64, charge: u64) {
    let base = (1u64 << 20) + charge;
    let per = |bytes: u64, k: u64| (bytes - base) as f64 / k as f64;
    let whole = per(s.whole_bytes, particles);
    for r in &s.shares {
        assert_eq!(per(r.memory_bytes, (r.owned + r.ghosts) as u64), whole);
    }
}

#[test]
fn a_3d_column_spread_is_what_its_run_holds() {
    let mut src = example_in("dem3d", "settling_column.toml");
    src.text = src.text.replace("duration = 1.5", "duration = 0.03");
    for n in [2, 4] {
        let s = spread(&src, n).unwrap();
        assert_eq!(s.grid.len(), 3);
        assert_eq!(s.grid.iter().product::<usize>(), n);
        assert!(s.replicated.is_none());
        let owned: usize = s.shares.iter().map(|r| r.owned).sum();
        memory_is_per_particle(&s, owned as u64, 0);
        if n == 2 {
            // One neighbour each: a rank sends the other's ghosts, 15 words each
            // (position, velocity, spin, force, torque; docs/parallel.md).
            let [a, b] = [&s.shares[0], &s.shares[1]];
            assert_eq!(a.ghost_bytes_per_step, 120 * b.ghosts as u64);
            assert_eq!(b.ghost_bytes_per_step, 120 * a.ghosts as u64);
        }
        measured(&src, n, &s, &format!("3D column, {n} ranks"));
    }
}

#[test]
fn a_ring_spread_is_what_its_run_holds_with_the_charge_on_every_rank() {
    let src = Source {
        text: include_str!("data/ring_tiny.toml").to_string(),
        origin: "t_ring.toml".into(),
        base: ".".into(),
    };
    for n in [2, 4] {
        let s = spread(&src, n).unwrap();
        assert_eq!(s.grid.len(), 2);
        let (what, charge) = s.replicated.clone().unwrap();
        assert_eq!(what, "the charge");
        let owned: usize = s.shares.iter().map(|r| r.owned).sum();
        memory_is_per_particle(&s, owned as u64, charge);
        measured(&src, n, &s, &format!("ring, {n} ranks"));
    }
    let text = spread(&src, 2).unwrap().text();
    assert!(text.contains("the charge on every rank"), "{text}");
}

#[test]
fn what_ranks_cannot_run_is_refused_by_the_spread_too() {
    let bare = example_in("xue2019", "charge_only.toml");
    let e = spread(&bare, 2).unwrap_err();
    assert!(
        e.contains("a charge without [ring]") && !e.contains('\n'),
        "{e}"
    );
    let one = spread(&bare, 1).unwrap();
    assert_eq!(one.shares[0].owned, 0);
    // Checks that watch the spheres during the run, and pours, are spread (they run on
    // ranks).
    let drum = example_in("dem3d", "drum_small.toml");
    assert!(spread(&drum, 2).is_ok());
    let pour = example_in("dem3d", "pour_small.toml");
    assert!(spread(&pour, 2).is_ok());
}
