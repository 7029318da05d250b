// Runs on in-process ranks and what they leave, for the rank tests of both
// dimensions (`ranks.rs`, `ranks3d.rs`).

#![allow(dead_code)]

use grains_dem::decomp::local::run_ranks;
use grains_sim::dem::ranks::Link;
use grains_sim::run::{self, RunOptions};
use grains_sim::{Finished, Source};
use std::path::{Path, PathBuf};

/// The example `name` of `examples/<dir>`.
pub fn example_in(dir: &str, name: &str) -> Source {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples")
        .join(dir)
        .join(name);
    Source::read(&path).unwrap()
}

/// Runs `src` on `n` in-process ranks (one thread each) into `out`.
pub fn on_ranks(src: &Source, n: usize, out: &Path) -> Vec<Result<Finished, String>> {
    on_ranks_with(n, |l| run::run_on(src, RunOptions::new(out), l))
}

/// `go` on `n` in-process ranks (one thread each), each with its link.
pub fn on_ranks_with(
    n: usize,
    go: impl Fn(Link) -> Result<Finished, run::RunError> + Sync,
) -> Vec<Result<Finished, String>> {
    run_ranks(n, |l| {
        // Each rank its own pool, as each MPI process has: a rank blocked on a message
        // must not hold a worker another rank needs.
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap();
        pool.install(|| go(Link(Box::new(l))).map_err(|e| e.to_string()))
    })
}

/// Every file under `dir`, by its path from `dir`.
pub fn files(dir: &Path) -> Vec<PathBuf> {
    fn walk(top: &Path, dir: &Path, all: &mut Vec<PathBuf>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                walk(top, &p, all);
            } else {
                all.push(p.strip_prefix(top).unwrap().to_path_buf());
            }
        }
    }
    let mut all = Vec::new();
    walk(dir, dir, &mut all);
    all.sort();
    all
}

/// The history's columns but those `skip` names, as written.
pub fn columns_but(dir: &Path, skip: impl Fn(&str) -> bool) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(dir.join("history.csv")).unwrap();
    let head: Vec<&str> = text.lines().next().unwrap().split(',').collect();
    let keep: Vec<usize> = (0..head.len()).filter(|&k| !skip(head[k])).collect();
    text.lines()
        .map(|l| {
            let v: Vec<&str> = l.split(',').collect();
            keep.iter().map(|&k| v[k].to_string()).collect()
        })
        .collect()
}

/// The files of a serial run as a run on `n` ranks writes them: each particle frame
/// `frames/particles_K.vtp` as the index `particles_K.pvtp` and one piece per rank.
pub fn as_pieces(serial: Vec<PathBuf>, n: usize) -> Vec<PathBuf> {
    let mut all = Vec::new();
    for f in serial {
        let name = f.file_name().unwrap().to_str().unwrap();
        match name
            .strip_prefix("particles_")
            .and_then(|k| k.strip_suffix(".vtp"))
        {
            Some(k) => {
                all.push(f.with_file_name(format!("particles_{k}.pvtp")));
                for r in 0..n {
                    all.push(f.with_file_name(format!("particles_{k}_r{r:03}.vtp")));
                }
            }
            None => all.push(f),
        }
    }
    all.sort();
    all
}

/// Every rank's result, unwrapped; all with the state hash `want`.
pub fn hashed(done: Vec<Result<Finished, String>>, want: &str, what: &str) -> Finished {
    let mut all = done.into_iter().enumerate().map(|(r, d)| {
        let d = d.unwrap_or_else(|e| panic!("{what}, rank {r}: {e}"));
        assert_eq!(d.summary.state_hash, want, "{what}, rank {r}");
        d
    });
    let leader = all.next().unwrap();
    all.for_each(drop);
    leader
}

pub fn copy_dir(from: &Path, to: &Path) {
    for f in files(from) {
        std::fs::create_dir_all(to.join(&f).parent().unwrap()).unwrap();
        std::fs::copy(from.join(&f), to.join(&f)).unwrap();
    }
}

/// Runs `src` on `n` in-process ranks into `out` and checks that every rank refused it
/// with one line containing `want`, and that nothing was written.
pub fn refused_everywhere(src: &Source, n: usize, out: &Path, want: &str) {
    for (r, got) in on_ranks(src, n, out).into_iter().enumerate() {
        let e = got.err().unwrap_or_else(|| panic!("{want}: rank {r} ran"));
        assert!(e.contains(want) && !e.contains('\n'), "rank {r}: {e}");
    }
    assert!(!out.exists(), "{want}: nothing written");
}
