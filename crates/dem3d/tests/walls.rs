//! A moving wall's pose is engine state: advanced with each step, kept by the
//! checkpoint and placed back on resume, with the straight run's bits.

use glam::DVec3;
use grains_dem3d::diagnostics::state_hash;
use grains_dem3d::walls::{advance_walls, place_walls, Motion};
use grains_dem3d::{
    step, ContactModel, Domain, Material, Particles, Setup, State, Wall, WallShape,
};

fn setup() -> Setup {
    let domain = Domain {
        lo: DVec3::splat(-0.1),
        hi: DVec3::splat(0.1),
        periodic: [false; 3],
    };
    let glass = Material {
        name: "glass".into(),
        density: 2500.0,
        youngs: None,
        poisson: None,
        restitution: None,
        friction: None,
        inertia_factor: 0.4,
    };
    let model = ContactModel::HookeHistory {
        kn: 1e4,
        kt: 2e3,
        gamma_n: 10.0,
        gamma_t: 5.0,
        mu: 0.5,
        limit_damping: false,
    };
    let mut floor = Wall::fixed(
        "floor",
        WallShape::Plane {
            point: [0.0, 0.0, -0.05],
            normal: [0.0, 0.0, 1.0],
        },
        None,
    );
    floor.motion = Motion {
        velocity: DVec3::new(0.0, 0.0, 0.03),
        omega: DVec3::ZERO,
    };
    let mut drum = Wall::fixed(
        "drum",
        WallShape::Cylinder {
            point: [0.0, 0.0, 0.0],
            axis: [1.0, 0.0, 0.0],
            radius: 0.08,
            inside: true,
        },
        None,
    );
    drum.motion.omega = DVec3::new(2.0, 0.0, 0.0);
    let g = DVec3::new(0.0, 0.0, -9.81);
    Setup::new(domain, vec![glass], model, vec![floor, drum], g, 1e-3).unwrap()
}

fn go(setup: &mut Setup, state: &mut State, steps: usize, dt: f64) {
    for _ in 0..steps {
        advance_walls(setup, state, dt);
        step(setup, state, dt);
    }
}

#[test]
fn a_wall_pose_survives_a_checkpoint_bitwise() {
    let dt = 1e-5;
    let mut a = setup();
    let mut p = Particles::default();
    p.push(
        DVec3::new(0.0, 0.0, -0.04),
        0.01,
        2500.0,
        0.4,
        0,
        DVec3::ZERO,
        DVec3::ZERO,
    );
    p.push(
        DVec3::new(0.0, 0.01, -0.015),
        0.01,
        2500.0,
        0.4,
        0,
        DVec3::ZERO,
        DVec3::ZERO,
    );
    let mut st = State::new(&a, p);
    go(&mut a, &mut st, 1000, dt);
    let mut bytes = Vec::new();
    grains_dem3d::checkpoint::write(&st, &mut bytes).unwrap();
    // A fresh set-up, with the walls where the scenario put them.
    let mut b = setup();
    let mut back = grains_dem3d::checkpoint::read(&mut bytes.as_slice(), 1 << 20).unwrap();
    grains_dem3d::checkpoint::fits(&back, &b).unwrap();
    place_walls(&mut b, &back);
    assert_eq!(back.walls, st.walls);
    assert_eq!(b.walls, a.walls);
    let (rise, turn) = (st.walls[0].at.z + 0.05, st.walls[1].angle.x);
    assert!(
        (rise - 0.03 * 1000.0 * dt).abs() < 1e-12,
        "floor rose {rise}"
    );
    assert!(
        (turn - 2.0 * 1000.0 * dt).abs() < 1e-12,
        "drum turned {turn}"
    );
    go(&mut a, &mut st, 1000, dt);
    go(&mut b, &mut back, 1000, dt);
    assert_eq!(state_hash(&st), state_hash(&back));
    assert_eq!(b.walls, a.walls);
    assert!(
        st.wall_loads[0].contacts > 0,
        "the floor carries the sphere"
    );
}
