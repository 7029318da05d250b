//! Coarse-grained polar fields of one frame (xue-2019 §4.2, Eqs. 5–8): bin averages
//! over the grains whose centres lie in each bin ([`Kernel::Bin`], the paper's plain
//! averages), or over the grains' shares under a smoothing kernel ([`Kernel::Hat`]).
//!
//! * Packing fraction φ: the disks' area over the bin's area.
//! * Velocity: the bin's momentum over its mass (for equal grains the plain mean of the
//!   grains' velocities), placed at the bin's mass centroid; radial and tangential
//!   components along and across the centroid's direction from the centre.
//! * ∇v, dilation rate, shear rate, vorticity: see [`super::gradient`].
//! * Stress and pressure (Eq. 6): see [`super::stress`].
//!
//! An empty bin has φ = 0, mass 0 and NaN velocity and rates (no material, no motion);
//! its stress is whatever contact branches cross it (usually zero).

use super::gradient::{rates, velocity_gradient};
use super::input::{ParticleSet, StressSource};
use super::kernel::{gather, sector_reach, spread, Kernel, Pieces, SectorIndex};
use super::polar::{Binning, PolarGrid, OUTSIDE};
use super::stress::{stress_field, StressField};
use glam::{DMat2, DVec2};
use rayon::prelude::*;
use std::f64::consts::PI;

/// The coarse-grained fields of one frame, one value per bin of `grid` (flat index,
/// ring index fastest).
#[derive(Clone, Debug)]
pub struct PolarFields {
    /// The grid.
    pub grid: PolarGrid,
    /// The kernel used.
    pub kernel: Kernel,
    /// Which bin each particle's centre is in.
    pub binning: Binning,
    /// Grains whose centre is in the bin (whatever the kernel).
    pub count: Vec<u32>,
    /// Mass per bin (kg/m).
    pub mass: Vec<f64>,
    /// Packing fraction.
    pub phi: Vec<f64>,
    /// Where the bin's values sit, relative to the centre (m): the mass centroid of its
    /// grains, or the bin's geometric centre when it is empty.
    pub position: Vec<DVec2>,
    /// Mass-averaged velocity (m/s), NaN when empty.
    pub velocity: Vec<DVec2>,
    /// Radial velocity (m/s).
    pub v_r: Vec<f64>,
    /// Tangential velocity, counter-clockwise positive (m/s).
    pub v_theta: Vec<f64>,
    /// Velocity gradient ∇v (1/s), `L · dx = dv`; NaN where undetermined.
    pub grad: Vec<DMat2>,
    /// Dilation rate D = ½ div v (1/s, Eq. 7).
    pub dilation: Vec<f64>,
    /// Shear rate γ̇ (1/s, Eq. 8).
    pub shear_rate: Vec<f64>,
    /// Vorticity (1/s).
    pub vorticity: Vec<f64>,
    /// Contact stress and pressure (Eq. 6), when contacts or particle stresses were given.
    pub stress: Option<StressField>,
}

/// Weighted sums over the grains of one bin.
#[derive(Clone, Copy, Default)]
struct BinSums {
    mass: f64,
    area: f64,
    moment: DVec2,
    momentum: DVec2,
}

impl BinSums {
    #[inline]
    fn add(&mut self, particles: &ParticleSet, c0: DVec2, p: usize, w: f64) {
        let m = w * particles.mass[p];
        let r = particles.radius[p];
        self.mass += m;
        self.area += w * PI * r * r;
        self.moment += m * (particles.pos[p] - c0);
        self.momentum += m * particles.vel[p];
    }
}

/// Coarse-grains `particles` on `grid` with `kernel`; the stress fields need `stress`.
pub fn coarse_grain(
    grid: &PolarGrid,
    particles: &ParticleSet,
    stress: Option<StressSource>,
    kernel: Kernel,
) -> PolarFields {
    let c0 = grid.centre();
    let binning = Binning::new(grid, particles.pos);
    let sums: Vec<BinSums> = match kernel {
        Kernel::Bin => (0..grid.len())
            .into_par_iter()
            .map(|k| {
                let mut s = BinSums::default();
                for &p in binning.bin(k) {
                    s.add(particles, c0, p as usize, 1.0);
                }
                s
            })
            .collect(),
        Kernel::Hat { half_width: w } => {
            let (index, reach) = sector_index(grid, particles, &binning, w);
            let pieces = Pieces::new(particles.len(), |p, f| {
                spread(grid, particles.pos[p as usize] - c0, w, f)
            });
            gather(
                grid,
                &index,
                reach,
                BinSums::default(),
                |p, f| pieces.visit(p, f),
                |acc, p, wt| acc.add(particles, c0, p as usize, wt),
            )
        }
    };

    let n = grid.len();
    let mut count = Vec::with_capacity(n);
    let mut mass = Vec::with_capacity(n);
    let mut phi = Vec::with_capacity(n);
    let mut position = Vec::with_capacity(n);
    let mut velocity = Vec::with_capacity(n);
    let mut v_r = Vec::with_capacity(n);
    let mut v_theta = Vec::with_capacity(n);
    for (k, s) in sums.iter().enumerate() {
        let (i, _) = grid.ring_sector(k);
        count.push(binning.bin(k).len() as u32);
        mass.push(s.mass);
        phi.push(s.area / grid.bin_area(i));
        // A bin of massless grains (not physical, but not excluded by the input type)
        // is treated as empty rather than dividing by zero.
        if s.mass > 0.0 {
            let x = s.moment / s.mass;
            let v = s.momentum / s.mass;
            let (er, et) = basis(x);
            position.push(x);
            velocity.push(v);
            v_r.push(v.dot(er));
            v_theta.push(v.dot(et));
        } else {
            position.push(grid.bin_centre(k));
            velocity.push(DVec2::NAN);
            v_r.push(f64::NAN);
            v_theta.push(f64::NAN);
        }
    }
    let valid: Vec<bool> = velocity.iter().map(|v| v.is_finite()).collect();
    let grad = velocity_gradient(grid, &position, &velocity, &valid);
    let r: Vec<_> = grad.iter().map(|l| rates(*l)).collect();
    let stress = stress.map(|s| stress_field(grid, particles, &binning, s, kernel));
    PolarFields {
        grid: *grid,
        kernel,
        binning,
        count,
        mass,
        phi,
        position,
        velocity,
        v_r,
        v_theta,
        dilation: r.iter().map(|x| x.dilation).collect(),
        shear_rate: r.iter().map(|x| x.shear_rate).collect(),
        vorticity: r.iter().map(|x| x.vorticity).collect(),
        grad,
        stress,
    }
}

/// The grains grouped by the sector of their centre, and how many sectors on either
/// side a kernel of half-width `w` reaches from the innermost grain.
pub(crate) fn sector_index(
    grid: &PolarGrid,
    particles: &ParticleSet,
    binning: &Binning,
    w: f64,
) -> (SectorIndex, usize) {
    let c0 = grid.centre();
    let sector: Vec<u32> = binning
        .bin_of
        .iter()
        .map(|&b| {
            if b == OUTSIDE {
                u32::MAX
            } else {
                grid.ring_sector(b as usize).1 as u32
            }
        })
        .collect();
    let r_inner = particles
        .pos
        .par_iter()
        .map(|p| (*p - c0).length())
        .reduce(|| f64::INFINITY, f64::min);
    (
        SectorIndex::new(grid.n_theta(), &sector),
        sector_reach(grid, w, 0.0, r_inner),
    )
}

/// Unit radial and tangential (counter-clockwise) vectors at `x` (relative to the
/// centre); +x and +y at the centre itself.
pub fn basis(x: DVec2) -> (DVec2, DVec2) {
    let er = x.try_normalize().unwrap_or(DVec2::X);
    (er, er.perp())
}

impl PolarFields {
    /// The symmetric part of tensor `m` in bin `k`'s polar basis: (rr, θθ, rθ).
    pub fn polar_components(&self, k: usize, m: DMat2) -> (f64, f64, f64) {
        let (er, et) = basis(self.position[k]);
        let s = 0.5 * (m + m.transpose());
        (er.dot(s * er), et.dot(s * et), er.dot(s * et))
    }

    /// Pressure per bin (Pa), if the stress was computed.
    pub fn pressure(&self) -> Option<&[f64]> {
        self.stress.as_ref().map(|s| s.pressure.as_slice())
    }

    /// Total mass on the grid (kg/m).
    pub fn total_mass(&self) -> f64 {
        self.mass.iter().sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dispersal::synthetic::{jittered_ring, LatticeRing as Ring};

    /// The two kernels every field test runs with: the paper's bins and a hat of one
    /// grain diameter.
    fn kernels(ring: &Ring) -> [Kernel; 2] {
        [
            Kernel::Bin,
            Kernel::Hat {
                half_width: ring.d0,
            },
        ]
    }

    fn fields_of(ring: &Ring, kernel: Kernel, vel: impl Fn(DVec2) -> DVec2) -> PolarFields {
        let v: Vec<DVec2> = ring.pos.iter().map(|x| vel(*x - ring.centre)).collect();
        let set = ParticleSet::new(&ring.pos, &v, &ring.radius, &ring.mass, &ring.id).unwrap();
        let grid = PolarGrid::covering(ring.centre, 0.0, 5.0 * ring.d0, 180, &set).unwrap();
        coarse_grain(&grid, &set, None, kernel)
    }

    /// Every occupied bin of `f` whose neighbours are all occupied (the interior).
    fn interior(f: &PolarFields) -> Vec<usize> {
        let g = &f.grid;
        (0..g.len())
            .filter(|&k| {
                let (i, j) = g.ring_sector(k);
                i > 0
                    && i + 1 < g.n_r()
                    && [
                        (i - 1, j),
                        (i + 1, j),
                        (i, (j + 1) % 180),
                        (i, (j + 179) % 180),
                    ]
                    .iter()
                    .all(|&(a, b)| f.count[g.index(a, b)] > 0 && f.phi[g.index(a, b)] > 0.5)
                    && f.count[k] > 0
            })
            .collect()
    }

    #[test]
    fn uniform_expansion_in_every_bin() {
        let ring = jittered_ring(1);
        let a = 2.0e4;
        for kernel in kernels(&ring) {
            let f = fields_of(&ring, kernel, |x| a * x);
            let mut occupied = 0;
            for k in 0..f.grid.len() {
                if f.mass[k] == 0.0 {
                    assert!(f.v_r[k].is_nan());
                    continue;
                }
                occupied += 1;
                let r = f.position[k].length();
                assert!((f.v_r[k] - a * r).abs() < 1e-9 * a * r, "bin {k}");
                assert!(f.v_theta[k].abs() < 1e-9 * a * r, "bin {k}");
                if f.grad[k].is_finite() {
                    assert!(
                        (f.dilation[k] - a).abs() < 1e-9 * a,
                        "bin {k}: {}",
                        f.dilation[k]
                    );
                    assert!(f.shear_rate[k].abs() < 1e-9 * a, "bin {k}");
                    assert!(f.vorticity[k].abs() < 1e-9 * a, "bin {k}");
                }
            }
            let inner = interior(&f);
            assert!(inner.len() > 1000 && occupied > inner.len());
            assert!(inner.iter().all(|&k| f.grad[k].is_finite()));
        }
    }

    #[test]
    fn rigid_rotation_in_every_bin() {
        let ring = jittered_ring(2);
        let w = 3.0e4;
        for kernel in kernels(&ring) {
            let f = fields_of(&ring, kernel, |x| w * x.perp());
            for k in 0..f.grid.len() {
                if f.mass[k] == 0.0 {
                    continue;
                }
                let r = f.position[k].length();
                assert!(f.v_r[k].abs() < 1e-9 * w * r, "bin {k}");
                assert!((f.v_theta[k] - w * r).abs() < 1e-9 * w * r, "bin {k}");
                if f.grad[k].is_finite() {
                    assert!(f.dilation[k].abs() < 1e-9 * w);
                    assert!(f.shear_rate[k].abs() < 1e-9 * w);
                    assert!((f.vorticity[k] - 2.0 * w).abs() < 1e-9 * w);
                }
            }
            assert!(interior(&f).iter().all(|&k| f.grad[k].is_finite()));
        }
    }

    /// A non-linear field checks the polar geometry of the differences: the source
    /// flow v = A x/|x|² has D = 0 and γ̇ = A/r² (∂v_r/∂r = −A/r², v_r/r = A/r²).
    #[test]
    fn source_flow_has_no_dilation_and_the_right_shear() {
        let ring = jittered_ring(3);
        let amp = 1.0;
        for kernel in kernels(&ring) {
            let f = fields_of(&ring, kernel, |x| amp * x / x.length_squared());
            let inner = interior(&f);
            for &k in &inner {
                let r = f.position[k].length();
                let want = amp / (r * r);
                assert!(
                    f.dilation[k].abs() < 0.03 * want,
                    "bin {k}: D {}",
                    f.dilation[k]
                );
                assert!(
                    (f.shear_rate[k] - want).abs() < 0.03 * want,
                    "bin {k}: γ̇ {} vs {want}",
                    f.shear_rate[k]
                );
            }
        }
    }

    #[test]
    fn binned_mass_is_the_total_mass() {
        let ring = jittered_ring(4);
        for kernel in kernels(&ring) {
            let f = fields_of(&ring, kernel, |x| x);
            let total: f64 = ring.mass.iter().sum();
            assert_eq!(f.binning.outside(), 0);
            assert!((f.total_mass() - total).abs() <= 1e-12 * total);
            assert_eq!(
                f.count.iter().map(|c| *c as usize).sum::<usize>(),
                ring.pos.len()
            );
            // φ averaged over the ring's full rings matches the packing's.
            let g = &f.grid;
            let i = g.ring_of(0.5 * (ring.r_in + ring.r_out)).unwrap();
            let mean: f64 = (0..180).map(|j| f.phi[g.index(i, j)]).sum::<f64>() / 180.0;
            assert!((mean - ring.phi).abs() < 0.01, "{mean} vs {}", ring.phi);
        }
    }

    #[test]
    fn polar_components_of_a_radial_tensor() {
        let ring = jittered_ring(5);
        let f = fields_of(&ring, Kernel::Bin, |x| x);
        let k = (0..f.grid.len()).find(|&k| f.count[k] > 0).unwrap();
        let (er, _) = basis(f.position[k]);
        let m = super::super::gradient::outer(er, er) * 7.0;
        let (rr, tt, rt) = f.polar_components(k, m);
        assert!((rr - 7.0).abs() < 1e-12 && tt.abs() < 1e-12 && rt.abs() < 1e-12);
    }
}
