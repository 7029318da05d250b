//! Started by `mpirun -np 4` (as the launcher's variables say), a grains that cannot run
//! on several ranks refuses on every rank: exit 1, one line naming the rank count,
//! nothing written (not four runs writing into one directory).

mod common;
use common::*;
use std::process::Command;

#[test]
fn several_ranks_are_refused_on_each() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.toml"), ONE_DISK).unwrap();
    for (size_var, rank_var) in [
        ("OMPI_COMM_WORLD_SIZE", "OMPI_COMM_WORLD_RANK"),
        ("PMI_SIZE", "PMI_RANK"),
    ] {
        for rank in 0..4 {
            let o = Command::new(env!("CARGO_BIN_EXE_grains"))
                .current_dir(dir.path())
                .args(["run", "s.toml", "--out", "out"])
                .env(size_var, "4")
                .env(rank_var, rank.to_string())
                .output()
                .unwrap();
            let out = Out {
                code: o.status.code().unwrap_or(-1),
                stdout: String::from_utf8_lossy(&o.stdout).into_owned(),
                stderr: String::from_utf8_lossy(&o.stderr).into_owned(),
            };
            let who = format!("rank {rank} of 4");
            assert_refused(&out, dir.path(), &[&who, "ranks = 4"]);
        }
    }
    // One rank is an ordinary run.
    let o = Command::new(env!("CARGO_BIN_EXE_grains"))
        .current_dir(dir.path())
        .args(["run", "s.toml", "--out", "out"])
        .env("OMPI_COMM_WORLD_SIZE", "1")
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}
