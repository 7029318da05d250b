// The 2D test beds' parts: the one material, the linear law with history, and the peer
// benchmark's bed (disks of diameter 0.88..0.98 in rows `nx` wide, periodic along x,
// on a floor, under unit gravity).

use glam::DVec2;
use grains_dem::{ContactModel, Domain, Material, Particles, Setup, Wall, WallShape};

/// Density 1, disks (I = ½ m r²).
pub fn material() -> Material {
    Material {
        name: "m".into(),
        density: 1.0,
        youngs: None,
        poisson: None,
        restitution: None,
        friction: None,
        inertia_factor: 0.5,
    }
}

/// The linear law with history: k_t = 2/7 k_n, γ_t = γ_n / 2, μ = 0.3.
pub fn hooke(kn: f64, gamma_n: f64) -> ContactModel {
    ContactModel::hooke_history(kn, gamma_n, 0.3)
}

/// The floor y = 0.
pub fn floor() -> Wall {
    Wall::fixed(
        "floor",
        WallShape::Segment {
            a: [-1e9, 0.0],
            b: [1e9, 0.0],
        },
        None,
    )
}

/// `n` disks in rows `nx` wide, with a little sideways motion.
pub fn bed(n: usize, nx: usize) -> (Setup, Particles) {
    let domain = Domain {
        lo: DVec2::ZERO,
        hi: DVec2::new(nx as f64, (n / nx) as f64 + 2.0),
        periodic: [true, false],
    };
    let setup = Setup::new(
        domain,
        vec![material()],
        hooke(4000.0, 87.0),
        vec![floor()],
        DVec2::new(0.0, -1.0),
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

/// Moves `p`'s disks onto a triangular lattice squeezed to 0.95 of their spacing, rows
/// `nx` wide: most overlap several neighbours and the bed springs apart.
#[allow(dead_code)] // Not every test that loads this module squeezes.
pub fn squeeze(p: &mut Particles, nx: usize) {
    for (k, x) in p.pos.iter_mut().enumerate() {
        let (row, col) = ((k / nx) as f64, (k % nx) as f64);
        let shift = 0.5 * ((k / nx) % 2) as f64;
        *x = 0.95 * DVec2::new(col + 0.5 + shift, 0.866 * row + 0.6);
    }
}
