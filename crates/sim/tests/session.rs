//! The library façade: a scenario of each engine stepped to its end through a
//! [`Session`] ends with the `state_hash` `grains run` writes; outputs, checkpoints and
//! outside forces.

use glam::DVec2;
use grains_sim::forces::{ForceError, OutsideForce};
use grains_sim::session::Session;
use grains_sim::{run, RunOptions, Source};
use std::path::Path;

fn source(file: &str) -> Source {
    Source::read(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data")
            .join(file),
    )
    .unwrap()
}

/// The `state_hash` of the command line's run of `file`.
fn cli_hash(file: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    run::run(&source(file), RunOptions::new(dir.path()))
        .unwrap()
        .summary
        .state_hash
}

/// Steps `file` to its end through a session, a few steps at a time.
fn session_hash(file: &str) -> String {
    let mut s = Session::open(source(file), None).unwrap();
    while !s.at_end() {
        s.step_while(7, true, |_, over| !over).unwrap();
    }
    let hash = format!("{:016x}", s.state_hash());
    let done = s.finish().unwrap();
    assert_eq!(done.summary.state_hash, hash);
    assert_eq!(done.summary.status, "completed");
    hash
}

#[test]
fn each_engine_stepped_through_a_session_ends_with_the_command_lines_state_hash() {
    for file in ["column_tiny.toml", "mpm_tiny.toml", "ring_tiny.toml"] {
        assert_eq!(session_hash(file), cli_hash(file), "{file}");
    }
}

#[test]
fn a_session_writes_what_grains_run_writes_and_resumes_bitwise() {
    let dir = tempfile::tempdir().unwrap();
    let mut s = Session::open(source("column_tiny.toml"), None).unwrap();
    assert_eq!((s.engine(), s.dim()), ("dem", 2));
    s.step(300).unwrap();
    s.checkpoint(&dir.path().join("ck")).unwrap();
    s.run(None).unwrap();
    let end = s.state_hash();
    s.write(&dir.path().join("out")).unwrap();
    for f in [
        "scenario.toml",
        "history.csv",
        "summary.json",
        "frames/series.pvd",
    ] {
        assert!(dir.path().join("out").join(f).is_file(), "{f}");
    }
    assert!(s.step(1).is_err(), "a concluded run cannot step");
    let mut r = Session::resume(&dir.path().join("ck")).unwrap();
    assert_eq!(r.clock().step, 300);
    r.run(None).unwrap();
    assert_eq!(r.state_hash(), end);
}

/// A constant force on every particle, applied per id.
struct Constant(DVec2);

impl OutsideForce for Constant {
    fn add(&mut self, _t: f64, p: &mut grains_dem::Particles) -> Result<(), ForceError> {
        for f in &mut p.force {
            *f += self.0;
        }
        Ok(())
    }
}

#[test]
fn a_constant_outside_force_gives_a_free_particles_parabola() {
    let mut s = Session::open(source("free_disk.toml"), None).unwrap();
    let m = s.particles().mass[0];
    let f = DVec2::new(0.0, 2.0e-3);
    s.add_force(Box::new(Constant(f))).unwrap();
    s.run(None).unwrap();
    let t = s.clock().time;
    let p = s.particles();
    let want = DVec2::new(0.1 * t, 0.5 * f.y / m * t * t);
    assert!(
        (p.pos[0] - want).length() < 1e-12 * (1.0 + want.length()),
        "{:?} vs {want:?}",
        p.pos[0]
    );
    assert!((p.vel[0].y - f.y / m * t).abs() < 1e-12);
}
