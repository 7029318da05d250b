//! Synthetic rings with known answers, for the unit tests and the speed benchmark: a
//! triangular lattice of disks clipped to an annulus, optionally jittered, with the
//! contact forces of a uniform pressure.
//!
//! For equal disks on a triangular lattice of spacing l, each bond carrying a normal
//! compressive force f, Love's formula over a unit cell (area √3/2 l², three bonds at
//! 60°) gives σ = −(3 f l / 2)/(√3/2 l²)·I, i.e. the pressure P = √3 f / l. The
//! lattice's packing fraction is π a²/(√3/2 l²) for disks of radius a.

use glam::DVec2;
use grains_core::rng::seeded;
use rand::RngExt;

/// Grain density used for the masses (quartz, xue-2019 Table 1), kg/m³.
pub const DENSITY: f64 = 2560.0;

/// A synthetic ring: per-particle fields plus the lattice contacts.
#[derive(Clone, Debug)]
pub struct LatticeRing {
    /// Centre of the ring (m).
    pub centre: DVec2,
    /// Inner and outer radius of the clipping annulus (m).
    pub r_in: f64,
    /// Outer radius (m).
    pub r_out: f64,
    /// Mean grain diameter (m).
    pub d0: f64,
    /// Packing fraction of the lattice (before clipping).
    pub phi: f64,
    /// Centres (m).
    pub pos: Vec<DVec2>,
    /// Radii (m).
    pub radius: Vec<f64>,
    /// Masses per unit thickness (kg/m).
    pub mass: Vec<f64>,
    /// Identities 0..N.
    pub id: Vec<u32>,
    /// Lattice neighbour pairs (i < j).
    pub pairs: Vec<(u32, u32)>,
}

impl LatticeRing {
    /// A lattice of spacing `spacing` between `r_in` and `r_out` about `centre`, disks
    /// of diameter `d0` (overlapping when `d0 > spacing`), rotated by `angle`. With
    /// `jitter > 0` every centre moves by up to `jitter·spacing` and every diameter is
    /// scaled by up to ±`jitter` (seeded by `seed`); the pairs stay the lattice bonds.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        centre: DVec2,
        r_in: f64,
        r_out: f64,
        d0: f64,
        spacing: f64,
        angle: f64,
        jitter: f64,
        seed: u64,
    ) -> Self {
        let (a1, a2) = (
            spacing * DVec2::from_angle(angle),
            spacing * DVec2::from_angle(angle + std::f64::consts::FRAC_PI_3),
        );
        let m = (r_out / (0.5 * spacing)).ceil() as i64 + 2;
        let side = (2 * m + 1) as usize;
        let mut site = vec![u32::MAX; side * side];
        let mut rng = seeded(seed);
        let mut ring = LatticeRing {
            centre,
            r_in,
            r_out,
            d0,
            phi: std::f64::consts::PI * 0.25 * d0 * d0 / (0.75f64.sqrt() * spacing * spacing),
            pos: Vec::new(),
            radius: Vec::new(),
            mass: Vec::new(),
            id: Vec::new(),
            pairs: Vec::new(),
        };
        for b in -m..=m {
            for a in -m..=m {
                let x = a as f64 * a1 + b as f64 * a2;
                let r = x.length();
                if r < r_in || r > r_out {
                    continue;
                }
                let mut u = || 2.0 * rng.random::<f64>() - 1.0;
                let shift = jitter * spacing * DVec2::new(u(), u());
                let rad = 0.5 * d0 * (1.0 + jitter * u());
                let k = ring.pos.len() as u32;
                site[((b + m) as usize) * side + (a + m) as usize] = k;
                ring.pos.push(centre + x + shift);
                ring.radius.push(rad);
                ring.mass.push(DENSITY * std::f64::consts::PI * rad * rad);
                ring.id.push(k);
            }
        }
        for b in -m..=m {
            for a in -m..=m {
                let k = site[((b + m) as usize) * side + (a + m) as usize];
                if k == u32::MAX {
                    continue;
                }
                for (da, db) in [(1, 0), (0, 1), (-1, 1)] {
                    let (na, nb) = (a + da, b + db);
                    if na.abs() > m || nb.abs() > m {
                        continue;
                    }
                    let n = site[((nb + m) as usize) * side + (na + m) as usize];
                    if n != u32::MAX {
                        ring.pairs.push((k.min(n), k.max(n)));
                    }
                }
            }
        }
        ring
    }

    /// Contact lists (i, j, force on i from j) for a uniform pressure `p` (Pa): every
    /// bond carries the normal force f = p·l/√3, pushing the disks apart.
    pub fn pressure_contacts(&self, p: f64) -> (Vec<u32>, Vec<u32>, Vec<DVec2>) {
        let (mut i, mut j, mut f) = (Vec::new(), Vec::new(), Vec::new());
        for &(a, b) in &self.pairs {
            let d = self.pos[b as usize] - self.pos[a as usize];
            let mag = p * d.length() / 3f64.sqrt();
            i.push(a);
            j.push(b);
            f.push(-mag * d.normalize());
        }
        (i, j, f)
    }
}

#[cfg(test)]
pub(crate) use test_rings::*;

#[cfg(test)]
mod test_rings {
    use super::*;

    /// A jittered ring for the field tests: about 50 000 grains of 0.1 mm between 10
    /// and 16 mm, off-centre, polydisperse by ±10 %.
    pub(crate) fn jittered_ring(seed: u64) -> LatticeRing {
        LatticeRing::new(
            DVec2::new(1e-3, -2e-3),
            10e-3,
            16e-3,
            0.1e-3,
            0.1e-3,
            0.3,
            0.1,
            seed,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lattice_bonds_and_forces() {
        let r = LatticeRing::new(DVec2::ZERO, 1e-3, 2e-3, 0.1e-3, 0.098e-3, 0.0, 0.0, 1);
        // Interior sites have six bonds.
        let mut deg = vec![0; r.pos.len()];
        for &(a, b) in &r.pairs {
            deg[a as usize] += 1;
            deg[b as usize] += 1;
            let d = (r.pos[a as usize] - r.pos[b as usize]).length();
            assert!((d - 0.098e-3).abs() < 1e-12);
        }
        assert_eq!(*deg.iter().max().unwrap(), 6);
        let (i, j, f) = r.pressure_contacts(1e6);
        for k in 0..i.len() {
            let d = r.pos[j[k] as usize] - r.pos[i[k] as usize];
            assert!(f[k].dot(d) < 0.0);
        }
        assert!(
            (r.phi - std::f64::consts::PI / 12f64.sqrt() * (0.1f64 / 0.098).powi(2)).abs() < 1e-12
        );
    }
}
