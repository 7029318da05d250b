//! `grains run` of 3D DEM scenarios on several ranks, on in-process ranks (the code
//! path an `mpirun` run takes, with the messages over channels instead of MPI): every
//! rank ends with the serial run's state hash, rank 0 writes the outputs (frames as
//! per-rank pieces with a `.pvtp` index), a checkpoint written on 4 ranks resumes on 2
//! to the straight run's hash, and what the decomposition cannot carry is refused.

#[path = "common/on_ranks.rs"]
mod on_ranks;

use grains_sim::run::{self, RunOptions};
use grains_sim::Source;
use on_ranks::{
    as_pieces, columns_but, example_in, files, hashed, on_ranks, on_ranks_with, refused_everywhere,
};
use std::path::Path;

fn example(name: &str) -> Source {
    example_in("dem3d", name)
}

/// The settling column cut short (0.03 s of its fall, across every cut), with a rank
/// grid when `grid` is given.
fn short_column(grid: Option<&str>) -> Source {
    let mut src = example("settling_column.toml");
    src.text = src
        .text
        .replace("duration = 1.5", "duration = 0.03")
        .replace("frames = 20", "frames = 3")
        .replace("history = 400", "history = 30");
    if let Some(g) = grid {
        src.text = src
            .text
            .replace("[run]", &format!("[parallel]\nranks = {g}\n\n[run]"));
    }
    src
}

/// The history (wall loads included: added exactly, docs/parallel.md, rule 2) but, with
/// `builds`, the neighbour builds.
fn history_but_builds(dir: &Path, builds: bool) -> Vec<Vec<String>> {
    columns_but(dir, |c| builds && c == "neighbour_builds")
}

/// Runs `src` serially and on each rank count (and grid): every rank has the serial
/// state hash, rank 0 the serial figures, history (wall loads too) and files, each
/// frame as one `.pvtp` and a piece per rank.
fn is_the_serial_run(src: &Source, runs: &[(usize, Option<&str>)]) {
    let dir = tempfile::tempdir().unwrap();
    let serial_dir = dir.path().join("serial");
    let serial = run::run(src, RunOptions::new(&serial_dir)).unwrap();
    for (k, &(n, grid)) in runs.iter().enumerate() {
        let mut src = src.clone();
        if let Some(g) = grid {
            src.text = src
                .text
                .replace("[run]", &format!("[parallel]\nranks = {g}\n\n[run]"));
        }
        let what = format!("{n} ranks, grid {grid:?}");
        let out = dir.path().join(format!("run{k}"));
        let leader = hashed(on_ranks(&src, n, &out), &serial.summary.state_hash, &what);
        assert_eq!(leader.status, serial.status, "{what}");
        assert_eq!(leader.summary.frames, serial.summary.frames, "{what}");
        assert_eq!(leader.summary.figures, serial.summary.figures, "{what}");
        // The energy ledger's sums, when it is kept: nothing per step, one fixed sum of
        // 19 exact sums (71 words each) when a history sample or a gather asks for the
        // figures, whatever the sphere count; none on one rank (docs/parallel.md, "Past
        // this machine").
        let ledger = &leader.summary.counts["comm"]["per_rank_and_step"]["ledger"];
        let calls = ledger["collectives"].as_f64().unwrap();
        assert!(
            (n == 1 && calls == 0.0) || (n > 1 && calls <= 1.0),
            "{what}: {calls} ledger sums a step"
        );
        if calls > 0.0 {
            let per_call = ledger["bytes_sent"].as_f64().unwrap() / calls;
            let want = 8.0 * 19.0 * 71.0;
            assert!(
                (per_call - want).abs() <= 1e-6 * want,
                "{what}: {per_call} B a sum, not {want}"
            );
        }
        // One rank of `mpirun -np 1` writes its frames as pieces too.
        assert_eq!(files(&out), as_pieces(files(&serial_dir), n), "{what}");
        assert_eq!(
            history_but_builds(&out, false),
            history_but_builds(&serial_dir, false),
            "{what}"
        );
        let counts = &leader.summary.counts;
        let (Some(imbalance), Some(moves)) =
            (counts.get("rank_imbalance"), counts.get("rebalances"))
        else {
            assert_eq!(
                n, 1,
                "{what}: no rank_imbalance or rebalances in the summary"
            );
            continue;
        };
        eprintln!("{what}: max/mean {imbalance} at the end, {moves} rebalances");
        if grid == Some("[1, 1, 4]") {
            // Cut along the fall: the cuts follow the column down (balance = 1.2, the
            // default).
            assert!(imbalance.as_f64().unwrap() <= 1.2, "{what}: {imbalance}");
            assert!(moves.as_u64().unwrap() > 0, "{what}: {moves}");
        }
    }
}

/// The settling column (Hertz–Mindlin with rolling and twisting resistance, the energy
/// ledger on) on 1, 2 and 4 ranks (the automatic grids), on a 2 × 2 × 1 grid, and on a
/// 1 × 1 × 4 grid cut along the fall, where the cut planes move with the spheres (load
/// balancing in 3D).
#[test]
fn the_3d_settling_column_on_1_2_and_4_ranks_is_the_serial_run() {
    is_the_serial_run(
        &short_column(None),
        &[
            (1, None),
            (2, None),
            (4, None),
            (4, Some("[2, 2, 1]")),
            (4, Some("[1, 1, 4]")),
        ],
    );
}

/// A sphere dropped on a moving belt (a wall with a surface velocity, on every rank)
/// rolls across a cut of 4 ranks along x (x = 0.0125 m; on 2 it stays on rank 0).
#[test]
fn the_belt_on_2_and_4_ranks_is_the_serial_run() {
    is_the_serial_run(
        &example("belt.toml"),
        &[(2, Some("[2, 1, 1]")), (4, Some("[4, 1, 1]"))],
    );
}

/// The short column stopped half-way on 4 ranks and resumed on 2 ends with the
/// straight serial run's state hash on every rank, its figures and history (but the
/// neighbour builds).
#[test]
fn a_3d_checkpoint_on_4_ranks_resumes_on_2_as_the_straight_run() {
    let src = short_column(None);
    let dir = tempfile::tempdir().unwrap();
    let at = |name: &str| dir.path().join(name);
    let straight = run::run(&src, RunOptions::new(at("straight"))).unwrap();
    let want = straight.summary.state_hash.clone();
    let stop = straight.summary.steps / 2 + 7;
    let out = at("four");
    let done = on_ranks_with(4, |l| {
        let mut opts = RunOptions::new(&out);
        opts.stop_at_step = Some(stop);
        run::run_on(&src, opts, l)
    });
    for (r, d) in done.into_iter().enumerate() {
        let d = d.unwrap_or_else(|e| panic!("rank {r}: {e}"));
        assert_eq!(d.status.name(), "paused", "rank {r}");
    }
    let done = on_ranks_with(2, |l| run::resume_on(&out, RunOptions::new(&out), l));
    let d = hashed(done, &want, "4 ranks, resumed on 2");
    assert_eq!(d.status, straight.status);
    assert_eq!(d.summary.figures, straight.summary.figures);
    assert_eq!(
        history_but_builds(&out, true),
        history_but_builds(&at("straight"), true)
    );
}

/// A grid that is not the rank count is refused on every rank with one line naming the
/// key, nothing written.
#[test]
fn what_3d_ranks_cannot_run_is_refused_on_every_rank() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (
            short_column(Some("[2, 2, 2]")),
            "parallel.ranks = [2, 2, 2] makes 8 ranks, but the run has 2",
        ),
        (
            short_column(Some("[1, 1, 9]")),
            "parallel.ranks = [1, 1, 9] makes 9 ranks",
        ),
    ];
    for (k, (src, want)) in cases.iter().enumerate() {
        refused_everywhere(src, 2, &dir.path().join(format!("case{k}")), want);
    }
    // More ranks along z than the column's height takes.
    let thin = short_column(Some("[1, 1, 40]"));
    refused_everywhere(&thin, 40, &dir.path().join("thin"), "parallel.");
}
