//! Scenarios whose checks watch particles during the run (collisions after every step;
//! a drum's surface and torque, a silo's flow, a column's height at samples; every
//! particle at the end), on 1, 2 and 4 in-process ranks (the code path an `mpirun` run
//! takes): every rank ends with the serial run's state hash and its checks, measured
//! values bit for bit, and rank 0 with its figures.

#[path = "common/on_ranks.rs"]
mod on_ranks;

use grains_sim::run::{self, RunOptions};
use grains_sim::Source;
use on_ranks::{example_in, on_ranks, on_ranks_with};

/// `src` with each `(from, to)` replaced, every `from` present.
fn cut(mut src: Source, edits: &[(&str, &str)]) -> Source {
    for (from, to) in edits {
        assert!(src.text.contains(from), "{from} not in {}", src.origin);
        src.text = src.text.replace(from, to);
    }
    src
}

/// Runs `src` serially and on each of `ranks`: every rank has the serial state hash,
/// status and checks (as JSON: the measured values' every digit, NaN as null), rank 0
/// the serial figures.
fn checks_agree(src: &Source, ranks: &[usize]) {
    let dir = tempfile::tempdir().unwrap();
    let serial = run::run(src, RunOptions::new(dir.path().join("serial"))).unwrap();
    assert!(!serial.checks.is_empty(), "{}: no checks", src.origin);
    let want = serde_json::to_string(&serial.checks).unwrap();
    for &n in ranks {
        let out = dir.path().join(format!("ranks{n}"));
        for (r, done) in on_ranks(src, n, &out).into_iter().enumerate() {
            let what = format!("{}, {n} ranks, rank {r}", src.origin);
            let done = done.unwrap_or_else(|e| panic!("{what}: {e}"));
            assert_eq!(done.summary.state_hash, serial.summary.state_hash, "{what}");
            assert_eq!(done.status, serial.status, "{what}");
            assert_eq!(serde_json::to_string(&done.checks).unwrap(), want, "{what}");
            if r == 0 {
                assert_eq!(done.summary.figures, serial.summary.figures, "{what}");
            }
        }
    }
}

/// Chung & Ooi's test 1 in 3D: two spheres head on, watched after every step.
#[test]
fn a_3d_collision_is_watched_alike_on_1_2_and_4_ranks() {
    let src = example_in("dem3d", "chung_ooi_test1.toml");
    checks_agree(&src, &[1, 2, 4]);
}

/// The same test in 2D (the watch both dimensions share).
#[test]
fn a_2d_collision_is_watched_alike_on_2_and_4_ranks() {
    checks_agree(&example_in("dem", "chung_ooi_test1.toml"), &[2, 4]);
}

/// A head-on collision and an oblique impact on a wall under the linear law (the 2D
/// recorders of restitution, contact time and the impact's spin and slip).
#[test]
fn linear_2d_impacts_are_watched_alike_on_2_ranks() {
    checks_agree(&example_in("dem", "head_on.toml"), &[2]);
    checks_agree(&example_in("dem", "oblique_impact.toml"), &[2]);
}

/// The drum turned for 0.16 s, averaged from 0.08 s: the surface angle and the torque
/// over the weight's moment from every sphere at each sample.
#[test]
fn a_drum_is_judged_alike_on_1_2_and_4_ranks() {
    checks_agree(&short_drum(), &[1, 2, 4]);
}

fn short_drum() -> Source {
    cut(
        example_in("dem3d", "drum_small.toml"),
        &[
            ("duration = 1.6", "duration = 0.16"),
            ("after = 0.8", "after = 0.08"),
        ],
    )
}

/// The short drum stopped after its averaging began, on 4 ranks, and resumed on 2:
/// every rank ends with the straight serial run's hash and checks (the probes' running
/// means ride in the checkpoint, restored on every rank).
#[test]
fn a_drum_stopped_on_4_ranks_resumes_on_2_with_the_straight_runs_checks() {
    let src = short_drum();
    let dir = tempfile::tempdir().unwrap();
    let straight = run::run(&src, RunOptions::new(dir.path().join("straight"))).unwrap();
    let want = serde_json::to_string(&straight.checks).unwrap();
    let out = dir.path().join("four");
    let stop = straight.summary.steps * 3 / 4;
    let paused = on_ranks_with(4, |l| {
        let mut opts = RunOptions::new(&out);
        opts.stop_at_step = Some(stop);
        run::run_on(&src, opts, l)
    });
    for (r, d) in paused.into_iter().enumerate() {
        assert_eq!(d.unwrap().status.name(), "paused", "rank {r}");
    }
    let done = on_ranks_with(2, |l| run::resume_on(&out, RunOptions::new(&out), l));
    for (r, d) in done.into_iter().enumerate() {
        let d = d.unwrap_or_else(|e| panic!("rank {r}: {e}"));
        assert_eq!(
            d.summary.state_hash, straight.summary.state_hash,
            "rank {r}"
        );
        assert_eq!(serde_json::to_string(&d.checks).unwrap(), want, "rank {r}");
    }
}

/// The silo drained for 0.1 s, its flow through the slab under the orifice averaged
/// from 0.05 s.
#[test]
fn a_silo_is_judged_alike_on_1_2_and_4_ranks() {
    let src = cut(
        example_in("dem3d", "silo_small.toml"),
        &[
            ("duration = 1.0", "duration = 0.1"),
            ("after = 0.4", "after = 0.05"),
        ],
    );
    checks_agree(&src, &[1, 2, 4]);
}

/// The column's tube lifted at 0.02 s and the run-out read at 0.05 s.
#[test]
fn a_collapse_is_judged_alike_on_1_2_and_4_ranks() {
    let src = cut(
        example_in("dem3d", "collapse_small.toml"),
        &[
            ("release = 0.3", "release = 0.02"),
            ("duration = 0.8", "duration = 0.05"),
        ],
    );
    checks_agree(&src, &[1, 2, 4]);
}

/// The pour poured for 0.1 s (200 spheres, the first of them settled on the floor):
/// every rank draws the same spheres from those near the region, gathered by id, and
/// keeps those in its box; the ids, the state and the checks are the serial run's.
#[test]
fn a_pour_on_1_2_and_4_ranks_is_the_serial_pour() {
    let src = cut(
        example_in("dem3d", "pour_small.toml"),
        &[("duration = 1.0", "duration = 0.1")],
    );
    checks_agree(&src, &[1, 2, 4]);
}
