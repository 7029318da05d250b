//! `grains check --ranks N`: a start (2D or 3D DEM, a FEM–DEM ring) spread over N ranks
//! as a run under mpirun spreads it, without MPI: each rank's particles, ghosts and
//! memory; bad input, and what mpirun would refuse, refused with one line naming the
//! value.

mod common;
use common::*;

/// `grains check --ranks N --json` on `file`: the `ranks` object.
fn spread(file: &std::path::Path, n: usize) -> serde_json::Value {
    let o = grains(&[
        "check",
        file.to_str().unwrap(),
        "--ranks",
        &n.to_string(),
        "--json",
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let v: serde_json::Value = serde_json::from_str(&o.stdout).unwrap();
    v["ranks"].clone()
}

#[test]
fn the_column_spread_over_1_2_and_4_ranks() {
    let column = example("dem/ranks_column.toml");
    for n in [1, 2, 4] {
        let s = spread(&column, n);
        let grid: Vec<u64> = s["grid"]
            .as_array()
            .unwrap()
            .iter()
            .map(|d| d.as_u64().unwrap())
            .collect();
        assert_eq!(grid.iter().product::<u64>(), n as u64, "{s}");
        let ranks = s["per_rank"].as_array().unwrap();
        assert_eq!(ranks.len(), n);
        let count = |k: &str| ranks.iter().map(|r| r[k].as_u64().unwrap()).sum::<u64>();
        assert_eq!(count("owned"), 400, "{n} ranks: every disk owned once");
        let ghosts = count("ghosts");
        assert_eq!(ghosts == 0, n == 1, "{n} ranks: {ghosts} ghosts");
        let fraction = s["ghosts_per_owned"].as_f64().unwrap();
        assert_eq!(fraction, ghosts as f64 / 400.0);
        // Memory: the run's figure per particle, on owned + ghost particles.
        let per = |bytes: u64, k: u64| (bytes - (1 << 20)) as f64 / k as f64;
        let whole = per(s["start_memory_bytes"].as_u64().unwrap(), 400);
        for r in ranks {
            let held = r["owned"].as_u64().unwrap() + r["ghosts"].as_u64().unwrap();
            let m = r["memory_bytes_estimate"].as_u64().unwrap();
            assert_eq!(per(m, held), whole, "{r}");
        }
        if n == 2 {
            // One neighbour each (a 1 x 2 grid, y not periodic): what a rank sends per
            // step is the other's ghosts, 8 words each (docs/parallel.md).
            for (r, q) in [(0, 1), (1, 0)] {
                let sent = ranks[r]["ghost_bytes_per_step"].as_u64().unwrap();
                assert_eq!(sent, 64 * ranks[q]["ghosts"].as_u64().unwrap(), "{s}");
            }
        }
    }
    let o = grains(&["check", column.to_str().unwrap(), "--ranks", "2"]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    for want in [
        "on a 1 x 2 grid",
        "rank 1",
        "per owned",
        "memory ≈",
        "ghost refresh",
    ] {
        assert!(o.stdout.contains(want), "{want}: {}", o.stdout);
    }
}

#[test]
fn a_rank_count_the_scenario_cannot_take_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let column = std::fs::read_to_string(example("dem/ranks_column.toml")).unwrap();
    let grid = column.replace("[run]", "[parallel]\nranks = [3, 1]\n\n[run]");
    let balance = |v: &str| column.replace("[run]", &format!("[parallel]\nbalance = {v}\n\n[run]"));
    let (low, word) = (balance("1.0"), balance("\"sometimes\""));
    let cases: [(&str, &str, &str, &[&str]); 5] = [
        ("zero.toml", &column, "0", &["--ranks = 0", "at least 1"]),
        (
            "grid.toml",
            &grid,
            "2",
            &["parallel.ranks = [3, 1]", "makes 3 ranks"],
        ),
        (
            "narrow.toml",
            &column,
            "29",
            &["under the contact range", "at most"],
        ),
        (
            "low.toml",
            &low,
            "2",
            &["parallel.balance = 1.0", "a number above 1", "\"off\""],
        ),
        (
            "word.toml",
            &word,
            "1",
            &["parallel.balance = \"sometimes\"", "\"off\""],
        ),
    ];
    for (name, text, n, want) in cases {
        std::fs::write(dir.path().join(name), text).unwrap();
        let o = grains_in(Some(dir.path()), &["check", name, "--ranks", n]);
        assert_refused(&o, dir.path(), want);
    }
    let mpm = example("mpm/j2_simple_shear.toml");
    let o = grains(&["check", mpm.to_str().unwrap(), "--ranks", "2"]);
    assert_refused(&o, dir.path(), &["engine = \"mpm\"", "FEM–DEM ring"]);
    // What `mpirun grains run` refuses: a bare charge (3D checks and pours run on ranks).
    let bare = example("xue2019/charge_only.toml");
    let o = grains(&["check", bare.to_str().unwrap(), "--ranks", "2"]);
    assert_refused(&o, dir.path(), &["a charge without [ring]", "1 rank"]);
    let pour = example("dem3d/pour_small.toml");
    let o = grains(&["check", pour.to_str().unwrap(), "--ranks", "2"]);
    assert_eq!(o.code, 0, "{}", o.stderr);
}

#[test]
fn a_3d_column_and_a_ring_spread_over_2_ranks() {
    let column = example("dem3d/settling_column.toml");
    let s = spread(&column, 2);
    assert_eq!(s["grid"].as_array().unwrap().len(), 3, "{s}");
    assert!(s["replicated"].is_null(), "{s}");
    let o = grains(&["check", column.to_str().unwrap(), "--ranks", "2"]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    for want in ["rank 1", "ghost refresh"] {
        assert!(o.stdout.contains(want), "{want}: {}", o.stdout);
    }
    let grid = o.stdout.lines().find(|l| l.contains(" grid ")).unwrap();
    assert_eq!(grid.matches(" x ").count(), 2, "{grid}");
    // The ring with its dispersal analysis, which runs on ranks.
    let ring = example("xue2019/ring_small.toml");
    let s = spread(&ring, 2);
    let per = s["per_rank"].as_array().unwrap();
    let owned: u64 = per.iter().map(|r| r["owned"].as_u64().unwrap()).sum();
    assert!(owned > 15_000, "{s}");
    let charge = s["replicated"]["memory_bytes_estimate"].as_u64().unwrap();
    for r in per {
        assert!(r["memory_bytes_estimate"].as_u64().unwrap() > charge, "{s}");
    }
    let o = grains(&["check", ring.to_str().unwrap(), "--ranks", "2"]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(
        o.stdout.contains("the charge on every rank"),
        "{}",
        o.stdout
    );
}
