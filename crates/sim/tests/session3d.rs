//! The library façade on 3D runs: stepped to its end through a [`Session`], a 3D
//! scenario ends with the command line's `state_hash`; spheres, contacts and outside
//! forces as 3-vectors; a checkpoint resumed bitwise.

use glam::DVec3;
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

#[test]
fn a_3d_session_ends_with_the_command_lines_state_hash_and_resumes_bitwise() {
    let dir = tempfile::tempdir().unwrap();
    let cli = run::run(&source("column3d_tiny.toml"), RunOptions::new(dir.path()))
        .unwrap()
        .summary
        .state_hash;
    let mut s = Session::open(source("column3d_tiny.toml"), None).unwrap();
    assert_eq!((s.engine(), s.dim()), ("dem", 3));
    s.step(400).unwrap();
    let p = s.particles3().unwrap();
    assert_eq!(p.id, (0..60).collect::<Vec<u32>>());
    assert!(s.particles().id.is_empty());
    s.checkpoint(&dir.path().join("ck")).unwrap();
    while !s.at_end() {
        s.step_while(7, true, |_, over| !over).unwrap();
    }
    assert_eq!(format!("{:016x}", s.state_hash()), cli);
    let c = s.contacts3().unwrap();
    assert!(!c.i.is_empty());
    for k in 0..c.i.len() {
        let (n, b) = (c.normal_force[k], c.branch[k]);
        assert!(n.cross(b).length() <= 1e-9 * n.length() * b.length());
        assert!(c.tangential_force[k].dot(b).abs() <= 1e-9 * n.length() * b.length());
    }
    let mut again = Session::resume(&dir.path().join("ck")).unwrap();
    assert_eq!(again.clock().step, 400);
    again.run(None).unwrap();
    assert_eq!(format!("{:016x}", again.state_hash()), cli);
}

/// A constant force and torque on every sphere.
struct Constant(DVec3, DVec3);

impl OutsideForce<grains_dem3d::Particles> for Constant {
    fn add(&mut self, _t: f64, p: &mut grains_dem3d::Particles) -> Result<(), ForceError> {
        for (f, t) in p.force.iter_mut().zip(&mut p.torque) {
            *f += self.0;
            *t += self.1;
        }
        Ok(())
    }
}

#[test]
fn a_constant_outside_force_moves_a_free_sphere_as_it_should() {
    let mut s = Session::open(source("free_sphere.toml"), None).unwrap();
    let p = s.particles3().unwrap();
    let (m, r) = (p.mass[0], p.radius[0]);
    let (f, t) = (DVec3::new(1e-3, -2e-3, 3e-3), DVec3::new(0.0, 4e-9, -1e-9));
    assert!(s.add_force(Box::new(Constant2)).is_err());
    s.add_force3(Box::new(Constant(f, t))).unwrap();
    s.set3("velocity", &[0], &[DVec3::new(0.1, 0.0, -0.05)])
        .unwrap();
    s.run(None).unwrap();
    let time = s.clock().time;
    let p = s.particles3().unwrap();
    let v0 = DVec3::new(0.1, 0.0, -0.05);
    let want = v0 * time + 0.5 * f / m * time * time;
    assert!(
        (p.pos[0] - want).length() <= 1e-12 * want.length(),
        "{:?}",
        p.pos[0]
    );
    let omega = t / (0.4 * m * r * r) * time;
    assert!((p.omega.unwrap()[0] - omega).length() <= 1e-12 * omega.length());
}

/// A 2D field, refused by a 3D run.
struct Constant2;

impl OutsideForce for Constant2 {
    fn add(&mut self, _t: f64, _p: &mut grains_dem::Particles) -> Result<(), ForceError> {
        Ok(())
    }
}
