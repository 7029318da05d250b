//! When the neighbour list must be rebuilt: the classic rule, or the same rule read in a
//! frame that expands radially with the particles.
//!
//! The classic rule rebuilds once any particle has moved more than skin/2 from where it
//! was at the last rebuild. A ring thrown outward by an explosion moves at hundreds of
//! metres per second while its grains barely move with respect to each other, so that
//! rule rebuilds every ten steps or so (test 2 of xue-2019: 4,087 builds in 45,709
//! steps) for lists that are still valid.
//!
//! Write each particle's displacement since the build as Δ_i = s + u·n_i + e_i, with
//! n_i the unit vector from a centre C to its position at the build X_i, a shift s and a
//! radial displacement u ≥ 0 common to all particles. The map F(X) = X + s + u·n(X)
//! never brings two points closer: with X − C = r₁e₁ and r₂e₂ (r₁, r₂ > 0),
//! |F(X₁) − F(X₂)|² − |X₁ − X₂|² = 2u (r₁ + r₂ + u)(1 − e₁·e₂) ≥ 0; and with n(C) = 0,
//! |F(X) − F(C)| = r + u ≥ r. So a pair now is at
//! least |X_i − X_j| − |e_i| − |e_j| apart, and a pair left out of the list (at least
//! r_i + r_j + skin apart at the build) cannot touch while the two largest |e_i| add up
//! to at most the skin: the classic rule with e in place of Δ (and its two largest
//! values in place of twice the largest, so that one grain flying off alone does not
//! force a rebuild). Any s and any u ≥ 0 will do at any step, so they are
//! estimated from the previous step's displacements (u as the mean radial displacement,
//! s as the mean of the rest), which costs a few sums in the sweep that already measures
//! the displacements; with u = 0 and s = 0 the rule is the classic one.
//!
//! The rule is used where it holds as derived: no walls (whose lists are kept by
//! absolute positions) and no periodic axis. Lists kept by absolute positions outside
//! the DEM (a coupled solid's contacts) are given the largest displacement since the
//! build ([`crate::step::Hooks::post_neighbour`]) to judge themselves by.

use crate::math::Vector;
use crate::setup::Setup;

/// The expanding frame the list is judged in: centre C, shift s and radial displacement u.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Comoving {
    /// The centre C the frame expands from (m).
    pub centre: Vector,
    /// The common shift s since the build (m).
    pub shift: Vector,
    /// The common radial displacement u ≥ 0 since the build (m).
    pub radial: f64,
}

/// What one sweep measures of the particles' displacements, from which the next frame
/// is estimated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sums {
    /// The smallest and largest radial displacement Δ_i · n_i (m).
    pub radial: [f64; 2],
    /// Σ Δ_i (m).
    pub displacement: Vector,
    /// Σ n_i.
    pub normal: Vector,
}

impl Default for Sums {
    fn default() -> Self {
        Sums {
            radial: [f64::INFINITY, f64::NEG_INFINITY],
            displacement: Vector::ZERO,
            normal: Vector::ZERO,
        }
    }
}

impl Sums {
    /// The measures of two parts of the particles together.
    pub fn join(self, o: Sums) -> Sums {
        Sums {
            radial: [
                self.radial[0].min(o.radial[0]),
                self.radial[1].max(o.radial[1]),
            ],
            displacement: self.displacement + o.displacement,
            normal: self.normal + o.normal,
        }
    }
}

impl Comoving {
    /// The frame at a build: nothing has moved yet.
    pub fn at_build(centre: Vector) -> Self {
        Comoving {
            centre,
            ..Default::default()
        }
    }

    /// The frame that follows `n` particles whose displacements gave `sums`: u midway
    /// between the smallest and largest radial displacement (which makes the largest
    /// radial residual smallest; never negative), s the mean of what u leaves.
    pub fn estimate(&self, sums: &Sums, n: usize) -> Self {
        if n == 0 {
            return *self;
        }
        let inv = 1.0 / n as f64;
        let radial = (0.5 * (sums.radial[0] + sums.radial[1])).max(0.0);
        let shift = (sums.displacement - radial * sums.normal) * inv;
        if !(radial.is_finite() && shift.is_finite()) {
            return Comoving::at_build(self.centre);
        }
        Comoving {
            centre: self.centre,
            shift,
            radial,
        }
    }

    /// The unit vector from the centre to `x` (zero at the centre, which F only shifts,
    /// and which it still brings no closer to any point).
    #[inline(always)]
    pub fn normal(&self, x: Vector) -> Vector {
        let r = x - self.centre;
        let l2 = r.length_squared();
        if l2 > 0.0 {
            r / l2.sqrt()
        } else {
            Vector::ZERO
        }
    }
}

/// The centre of the expanding frame the list of `setup` may be judged in, if the rule
/// holds there (see the module's notes).
pub fn frame_centre(setup: &Setup) -> Option<Vector> {
    let centre = setup.expanding_from?;
    (setup.walls.is_empty() && !setup.domain.periodic.contains(&true)).then_some(centre)
}

#[cfg(all(test, feature = "dim2"))]
mod tests {
    use super::*;
    use glam::DVec2;

    #[test]
    fn the_expanding_map_brings_no_two_points_closer() {
        let f = Comoving {
            centre: DVec2::new(0.3, -0.2),
            shift: DVec2::new(0.05, 0.01),
            radial: 0.4,
        };
        let map = |x: DVec2| x + f.shift + f.radial * f.normal(x);
        let mut rng = 12345u64;
        let mut next = || {
            rng = rng
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (rng >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for _ in 0..10_000 {
            let a = DVec2::new(next(), next());
            let b = DVec2::new(next(), next());
            assert!((map(a) - map(b)).length() >= (a - b).length() * (1.0 - 1e-12));
        }
        // The centre itself stays put and moves nothing closer.
        let c = f.centre;
        assert!((map(c) - map(c + DVec2::X)).length() >= 1.0);
    }

    #[test]
    fn the_estimate_follows_a_uniform_expansion_and_never_contracts() {
        let f = Comoving::at_build(DVec2::ZERO);
        let xs = [DVec2::X, DVec2::Y, -DVec2::X, -DVec2::Y];
        let mut s = Sums::default();
        for x in xs {
            let n = f.normal(x);
            let d = 0.1 * n + DVec2::new(0.02, 0.0);
            s = s.join(Sums {
                radial: [d.dot(n); 2],
                displacement: d,
                normal: n,
            });
        }
        let e = f.estimate(&s, xs.len());
        assert!((e.radial - 0.1).abs() < 1e-12);
        assert!((e.shift - DVec2::new(0.02, 0.0)).length() < 1e-12);
        let inward = Sums {
            radial: [-1.0, -0.5],
            ..Default::default()
        };
        assert_eq!(f.estimate(&inward, 4).radial, 0.0);
    }
}
