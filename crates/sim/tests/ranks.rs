//! `grains run` on several ranks, on in-process ranks (the code path an `mpirun` run
//! takes, with the messages over channels instead of MPI): rank 0 writes the outputs,
//! the others nothing, and the summary's state hash and the history's energies are the
//! serial run's bit for bit.

use grains_dem::decomp::local::run_ranks;
use grains_sim::dem::ranks::Link;
use grains_sim::run::{self, RunOptions};
use grains_sim::{Finished, Source};
use std::path::{Path, PathBuf};

fn example(name: &str) -> Source {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/dem")
        .join(name);
    Source::read(&path).unwrap()
}

/// Runs `src` on `n` in-process ranks (one thread each) into `out`.
fn on_ranks(src: &Source, n: usize, out: &Path) -> Vec<Result<Finished, String>> {
    run_ranks(n, |l| {
        // Each rank its own pool, as each MPI process has: a rank blocked on a message
        // must not hold a worker another rank needs.
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        pool.install(|| {
            run::run_on(src, RunOptions::new(out), Link(Box::new(l))).map_err(|e| e.to_string())
        })
    })
}

fn files(dir: &Path) -> Vec<PathBuf> {
    let mut all = Vec::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            all.extend(files(&p));
        } else {
            all.push(p.strip_prefix(dir).unwrap().to_path_buf());
        }
    }
    all.sort();
    all
}

/// The energy columns of a history (the wall loads are summed per rank, equal to
/// rounding only: docs/parallel.md).
fn energies(dir: &Path) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(dir.join("history.csv")).unwrap();
    let head: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    let keep: Vec<usize> = (0..head.len())
        .filter(|&k| !head[k].starts_with("floor"))
        .collect();
    text.lines()
        .map(|l| {
            let v: Vec<&str> = l.split(',').collect();
            keep.iter().map(|&k| v[k].to_string()).collect()
        })
        .collect()
}

#[test]
fn a_2d_dem_run_on_2_and_4_ranks_is_the_serial_run() {
    let src = example("ranks_column.toml");
    let dir = tempfile::tempdir().unwrap();
    let serial = run::run(&src, RunOptions::new(dir.path().join("serial"))).unwrap();
    assert_eq!(serial.status.name(), "completed");
    for n in [2, 4] {
        let out = dir.path().join(format!("ranks{n}"));
        let done = on_ranks(&src, n, &out);
        for (r, d) in done.iter().enumerate() {
            let d = d.as_ref().unwrap_or_else(|e| panic!("rank {r}: {e}"));
            assert_eq!(
                d.summary.state_hash, serial.summary.state_hash,
                "{n} ranks, rank {r}"
            );
            assert_eq!(d.status, serial.status);
        }
        let leader = done[0].as_ref().unwrap();
        assert_eq!(leader.summary.particles, serial.summary.particles);
        assert_eq!(leader.summary.frames, serial.summary.frames);
        assert_eq!(leader.summary.figures, serial.summary.figures, "{n} ranks");
        assert_eq!(files(&out), files(&dir.path().join("serial")), "{n} ranks");
        assert_eq!(
            energies(&out),
            energies(&dir.path().join("serial")),
            "{n} ranks"
        );
    }
}

/// Under several ranks, what the decomposition does not carry, and a grid that does not
/// match the rank count, are refused on every rank with one line, nothing written.
#[test]
fn what_ranks_cannot_run_is_refused_on_every_rank() {
    let dir = tempfile::tempdir().unwrap();
    let column = example("ranks_column.toml");
    let mut wrong = column.clone();
    wrong.text = wrong
        .text
        .replace("[run]", "[parallel]\nranks = [3, 1]\n\n[run]");
    let cases = [
        (
            wrong,
            "parallel.ranks = [3, 1] makes 3 ranks, but the run has 2",
        ),
        (
            example("head_on.toml"),
            "is not supported on several ranks yet",
        ),
    ];
    for (k, (src, want)) in cases.iter().enumerate() {
        let out = dir.path().join(format!("case{k}"));
        for (r, got) in on_ranks(src, 2, &out).into_iter().enumerate() {
            let e = got
                .err()
                .unwrap_or_else(|| panic!("case {k}, rank {r}: ran"));
            assert!(e.contains(want) && !e.contains('\n'), "rank {r}: {e}");
        }
        assert!(!out.exists(), "case {k}: nothing written");
    }
    // One rank is refused a grid of several, too.
    let mut two = column.clone();
    two.text = two
        .text
        .replace("[run]", "[parallel]\nranks = [1, 2]\n\n[run]");
    let e = run::run(&two, RunOptions::new(dir.path().join("one"))).unwrap_err();
    assert!(
        e.to_string().contains("makes 2 ranks, but the run has 1"),
        "{e}"
    );
}
