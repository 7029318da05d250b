//! Results must not depend on the number of threads.

use glam::DVec2;
use grains_dem::{step, ContactModel, Domain, Material, Particles, Setup, State, Wall, WallShape};

fn bed(n: usize) -> (Setup, Particles) {
    let nx = 60;
    let material = Material {
        name: "m".into(),
        density: 1.0,
        youngs: None,
        poisson: None,
        restitution: None,
        friction: None,
        inertia_factor: 0.5,
    };
    let model = ContactModel::HookeHistory {
        kn: 4000.0,
        kt: 4000.0 * 2.0 / 7.0,
        gamma_n: 87.0,
        gamma_t: 43.5,
        mu: 0.3,
        limit_damping: false,
    };
    let domain = Domain {
        lo: DVec2::ZERO,
        hi: DVec2::new(nx as f64, (n / nx) as f64 + 2.0),
        periodic: [true, false],
    };
    let floor = Wall {
        name: "floor".into(),
        shape: WallShape::Segment {
            a: [-1e9, 0.0],
            b: [1e9, 0.0],
        },
        material: None,
    };
    let setup = Setup::new(
        domain,
        vec![material],
        model,
        vec![floor],
        DVec2::new(0.0, -1.0),
        5e-4,
        0.1,
    )
    .unwrap();
    let mut p = Particles::default();
    let mut x: u64 = 12345;
    for k in 0..n {
        x = x
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let d = 0.88 + 0.1 * ((x >> 11) as f64 / (1u64 << 53) as f64);
        let at = DVec2::new((k % nx) as f64 + 0.5, (k / nx) as f64 * 0.97 + 0.5);
        p.push(
            at,
            0.5 * d,
            1.0,
            0.5,
            0,
            DVec2::new(0.01 * ((k % 7) as f64 - 3.0), 0.0),
            0.0,
        );
    }
    (setup, p)
}

fn run(threads: usize) -> State {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let (setup, p) = bed(6000);
        let mut s = State::new(&setup, p);
        for _ in 0..300 {
            step(&setup, &mut s);
        }
        s
    })
}

#[test]
fn bitwise_identical_for_1_2_3_threads() {
    let a = run(1);
    assert!(
        a.contacts.builds > 1,
        "the run must rebuild its neighbour list"
    );
    for t in [2, 3] {
        let b = run(t);
        let (pa, pb) = (&a.particles, &b.particles);
        assert_eq!(pa.id, pb.id, "{t} threads: order");
        for i in 0..pa.len() {
            assert_eq!(
                pa.pos[i].to_array().map(f64::to_bits),
                pb.pos[i].to_array().map(f64::to_bits)
            );
            assert_eq!(
                pa.vel[i].to_array().map(f64::to_bits),
                pb.vel[i].to_array().map(f64::to_bits)
            );
            assert_eq!(pa.omega[i].to_bits(), pb.omega[i].to_bits());
            assert_eq!(
                pa.force[i].to_array().map(f64::to_bits),
                pb.force[i].to_array().map(f64::to_bits)
            );
        }
        assert_eq!(a.contacts.nbr, b.contacts.nbr);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&a.contacts.shear), bits(&b.contacts.shear));
        assert_eq!(bits(&a.contacts.wall_shear), bits(&b.contacts.wall_shear));
        assert_eq!(a.wall_loads, b.wall_loads);
    }
}
