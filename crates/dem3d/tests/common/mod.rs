//! What the 3D physics tests share: a glass material, a box set-up, a floor, a jittered
//! cloud of spheres and the bed made of it, and a run on a thread pool of a given size.
// Each test binary uses a part of this module.
#![allow(dead_code)]

use glam::DVec3;
use grains_dem3d::{
    step, ContactModel, Domain, Material, Particles, Setup, State, Wall, WallShape,
};

/// Density of the glass spheres (kg/m³).
pub const RHO: f64 = 2500.0;

/// Glass of density [`RHO`], spheres' inertia factor 2/5.
pub fn glass() -> Material {
    Material {
        name: "glass".into(),
        density: RHO,
        youngs: None,
        poisson: None,
        restitution: None,
        friction: None,
        inertia_factor: 0.4,
    }
}

/// A 0.1 m box with `walls`, `gravity`, periodic where asked, glass alone, skin 1 mm.
pub fn setup(model: ContactModel, walls: Vec<Wall>, gravity: DVec3, periodic: [bool; 3]) -> Setup {
    let domain = Domain {
        lo: DVec3::ZERO,
        hi: DVec3::splat(0.1),
        periodic,
    };
    Setup::new(domain, vec![glass()], model, walls, gravity, 1e-3).unwrap()
}

/// The plane z = 0, facing up.
pub fn floor() -> Wall {
    Wall {
        name: "floor".into(),
        shape: WallShape::Plane {
            point: [0.0, 0.0, 0.0],
            normal: [0.0, 0.0, 1.0],
        },
        material: None,
        motion: Default::default(),
    }
}

/// `n_side`³ spheres of radius about `r` on a loose lattice, with random velocities and
/// spins drawn from `jitter`.
pub fn cloud(n_side: usize, r: f64, jitter: u64) -> Particles {
    let mut p = Particles::default();
    let mut seed = jitter;
    let mut next = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let gap = 2.05 * r;
    for k in 0..n_side {
        for j in 0..n_side {
            for i in 0..n_side {
                let x = DVec3::new(
                    0.01 + i as f64 * gap,
                    0.01 + j as f64 * gap,
                    r * 1.1 + k as f64 * gap,
                );
                let v = DVec3::new(next(), next(), next());
                let w = 10.0 * DVec3::new(next(), next(), next());
                let rr = r * (1.0 + 0.1 * next());
                p.push(x, rr, RHO, 0.4, 0, v, w);
            }
        }
    }
    p
}

/// A bed of 14³ spheres over a floor, periodic in x and y, under the linear law.
pub fn bed() -> (Setup, Particles) {
    let g = DVec3::new(0.0, 0.0, -9.81);
    let mut s = setup(
        ContactModel::hooke_history(2e4, 200.0, 0.5),
        vec![floor()],
        g,
        [true, true, false],
    );
    s.domain.hi = DVec3::new(0.05, 0.05, 0.1);
    // More particles than one chunk, so the chunk borders and the reverse pass count.
    (s, cloud(14, 0.0015, 11))
}

/// `steps` steps of `dt` from `p` on a pool of `threads` threads.
pub fn run_on(s: &Setup, p: Particles, threads: usize, steps: usize, dt: f64) -> State {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let mut st = State::new(s, p);
        for _ in 0..steps {
            step(s, &mut st, dt);
        }
        st
    })
}
