//! The simulation box: bounds for the cell grid and periodicity per axis.

use crate::math::{Vector, DIM};
use serde::{Deserialize, Serialize};

/// Box-shaped domain `[lo, hi]`. Along a periodic axis positions wrap and distances use
/// the minimum image; along a non-periodic axis particles may leave the box (they are then
/// binned into the edge cells, which stays correct, only slower).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Domain {
    /// Lower corner (m).
    pub lo: Vector,
    /// Upper corner (m).
    pub hi: Vector,
    /// Periodicity per axis.
    pub periodic: [bool; DIM],
}

impl Domain {
    /// Box lengths per axis.
    pub fn length(&self) -> Vector {
        self.hi - self.lo
    }

    /// Minimum-image version of a separation vector. Neighbour separations never exceed
    /// half a period by much, so two comparisons replace a rounding call in the hot loop;
    /// a separation beyond 1.5 periods falls back to rounding.
    #[inline(always)]
    pub fn min_image(&self, mut d: Vector) -> Vector {
        for a in 0..DIM {
            if self.periodic[a] {
                let l = self.hi[a] - self.lo[a];
                let h = 0.5 * l;
                if d[a] > h {
                    d[a] -= l;
                } else if d[a] < -h {
                    d[a] += l;
                }
                if d[a].abs() > h {
                    d[a] -= l * (d[a] / l).round();
                }
            }
        }
        d
    }

    /// Maps a position back into the box along periodic axes.
    #[inline(always)]
    pub fn wrap(&self, mut p: Vector) -> Vector {
        for a in 0..DIM {
            if self.periodic[a] {
                let (lo, hi) = (self.lo[a], self.hi[a]);
                let l = hi - lo;
                if p[a] < lo {
                    p[a] += l;
                } else if p[a] >= hi {
                    p[a] -= l;
                }
                if p[a] < lo || p[a] >= hi {
                    // More than a period away (only at set-up): fold it in fully.
                    p[a] -= l * ((p[a] - lo) / l).floor();
                    if p[a] >= hi {
                        p[a] = lo;
                    }
                }
            }
        }
        p
    }
}

/// Minimum image for separations of two points inside the box (|d| < one period), with
/// the periodic axes fixed at compile time as the bit mask `P` (bit a: axis a periodic,
/// see [`crate::with_image`]), so hot loops carry no per-axis branches on them.
#[derive(Clone, Copy, Debug)]
pub struct Image<const P: u8> {
    lo: Vector,
    hi: Vector,
    period: Vector,
    half: Vector,
}

impl<const P: u8> Image<P> {
    /// The image rule of `domain` (whose periodic axes must be those of `P`).
    pub fn new(domain: &Domain) -> Self {
        debug_assert!((0..DIM).all(|a| domain.periodic[a] == (P >> a & 1 == 1)));
        let period = domain.length();
        Image {
            lo: domain.lo,
            hi: domain.hi,
            period,
            half: 0.5 * period,
        }
    }

    /// Brings back into the box a position that left it by less than one period (as a
    /// particle does in one stable step).
    #[inline(always)]
    pub fn wrap(&self, mut p: Vector) -> Vector {
        for a in 0..DIM {
            if P >> a & 1 == 1 {
                if p[a] < self.lo[a] {
                    p[a] += self.period[a];
                } else if p[a] >= self.hi[a] {
                    p[a] -= self.period[a];
                }
            }
        }
        p
    }

    /// Nearest image of a separation between two points inside the box.
    #[inline(always)]
    pub fn apply(&self, mut d: Vector) -> Vector {
        for a in 0..DIM {
            if P >> a & 1 == 1 {
                if d[a] > self.half[a] {
                    d[a] -= self.period[a];
                } else if d[a] < -self.half[a] {
                    d[a] += self.period[a];
                }
            }
        }
        d
    }
}

#[cfg(all(test, feature = "dim2"))]
mod tests {
    use super::*;
    use glam::DVec2;

    #[test]
    fn min_image_and_wrap() {
        let d = Domain {
            lo: DVec2::ZERO,
            hi: DVec2::new(10.0, 5.0),
            periodic: [true, false],
        };
        assert_eq!(d.min_image(DVec2::new(9.0, 4.0)), DVec2::new(-1.0, 4.0));
        assert_eq!(d.wrap(DVec2::new(-0.5, 7.0)), DVec2::new(9.5, 7.0));
        assert_eq!(d.wrap(DVec2::new(10.0, 1.0)), DVec2::new(0.0, 1.0));
        assert_eq!(d.wrap(DVec2::new(-25.5, 1.0)), DVec2::new(4.5, 1.0));
        assert_eq!(d.min_image(DVec2::new(-26.0, 0.0)), DVec2::new(4.0, 0.0));
    }
}
