//! 2D scenarios under LAMMPS's granular law (the `[contact]` table the 3D scenarios take):
//! the run, the session, checkpoints, the run on in-process ranks and the bad-input
//! lines.

use grains_sim::session::Session;
use grains_sim::{run, RunOptions, Source};
use std::path::Path;

fn text() -> String {
    std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/column_granular_tiny.toml"),
    )
    .unwrap()
}

fn source(text: &str) -> Source {
    Source {
        text: text.to_string(),
        origin: "column_granular_tiny.toml".into(),
        base: Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data"),
    }
}

#[test]
fn a_2d_granular_run_settles_and_resumes_bitwise() {
    let dir = tempfile::tempdir().unwrap();
    let done = run::run(&source(&text()), RunOptions::new(dir.path())).unwrap();
    assert_eq!(done.summary.status, "completed");
    for f in ["history.csv", "summary.json", "frames/series.pvd"] {
        assert!(dir.path().join(f).is_file(), "{f}");
    }
    let mut s = Session::open(source(&text()), None).unwrap();
    s.step(300).unwrap();
    s.checkpoint(&dir.path().join("ck")).unwrap();
    s.run(None).unwrap();
    let end = format!("{:016x}", s.state_hash());
    assert_eq!(end, done.summary.state_hash);
    let mut r = Session::resume(&dir.path().join("ck")).unwrap();
    r.run(None).unwrap();
    assert_eq!(format!("{:016x}", r.state_hash()), end);
}

#[path = "common/on_ranks.rs"]
mod on_ranks;

/// The granular law's pair histories (sliding and rolling springs) migrate with their
/// particles and the pairs across a cut are computed on both sides: on 2 and 4
/// in-process ranks (the code path of `mpirun`) the run ends with the serial hash,
/// figures and history, every column.
#[test]
fn a_2d_granular_run_on_2_and_4_ranks_is_the_serial_run() {
    let dir = tempfile::tempdir().unwrap();
    let serial = run::run(&source(&text()), RunOptions::new(dir.path().join("serial"))).unwrap();
    for n in [2, 4] {
        let out = dir.path().join(format!("ranks{n}"));
        let done = on_ranks::on_ranks(&source(&text()), n, &out);
        let leader = on_ranks::hashed(done, &serial.summary.state_hash, &format!("{n} ranks"));
        assert_eq!(leader.summary.figures, serial.summary.figures, "{n} ranks");
        assert_eq!(
            on_ranks::columns_but(&out, |_| false),
            on_ranks::columns_but(&dir.path().join("serial"), |_| false),
            "{n} ranks"
        );
    }
}

/// The first line of the input error `edit` gives.
fn refused(edit: impl Fn(String) -> String) -> String {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let e = match run::run(&source(&edit(text())), RunOptions::new(&out)) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("accepted"),
    };
    assert!(!out.exists(), "nothing written: {e}");
    assert_eq!(e.trim().lines().count(), 1, "{e}");
    e
}

#[test]
fn what_a_disk_cannot_have_is_refused_in_one_line() {
    let e = refused(|t| t.replace("mu_r = 0.1", "mu_r = 0.1\ntwisting = \"marshall\""));
    assert!(e.contains("contact.twisting") && e.contains("2D"), "{e}");
    let e = refused(|t| t.replace("poisson = 0.27", "poisson = 0.6"));
    assert!(e.contains("poisson"), "{e}");
    let e = refused(|t| t.replace("model = \"granular\"", "model = \"material\""));
    assert!(e.contains("contact.kr"), "{e}");
    let e = refused(|t| {
        t + "\n[[check]]\nkind = \"restitution\"\nname = \"e\"\nparticles = [0, 1]\ntolerance = 0.02\n"
    });
    assert!(e.contains("check[0]") && e.contains("linear law"), "{e}");
}
