//! The simulation box: bounds for the cell grid and periodicity per axis.

use glam::DVec2;
use serde::{Deserialize, Serialize};

/// Rectangular domain `[lo, hi]`. Along a periodic axis positions wrap and distances use
/// the minimum image; along a non-periodic axis particles may leave the box (they are then
/// binned into the edge cells, which stays correct, only slower).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Domain {
    /// Lower-left corner (m).
    pub lo: DVec2,
    /// Upper-right corner (m).
    pub hi: DVec2,
    /// Periodicity along x and y.
    pub periodic: [bool; 2],
}

impl Domain {
    /// Box lengths along x and y.
    pub fn length(&self) -> DVec2 {
        self.hi - self.lo
    }

    /// Minimum-image version of a separation vector. Neighbour separations never exceed
    /// half a period by much, so two comparisons replace a rounding call in the hot loop;
    /// a separation beyond 1.5 periods falls back to rounding.
    #[inline(always)]
    pub fn min_image(&self, mut d: DVec2) -> DVec2 {
        for a in 0..2 {
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
    pub fn wrap(&self, mut p: DVec2) -> DVec2 {
        for a in 0..2 {
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
/// the periodicity fixed at compile time so hot loops carry no per-axis branches on it.
#[derive(Clone, Copy, Debug)]
pub struct Image<const PX: bool, const PY: bool> {
    lo: DVec2,
    hi: DVec2,
    period: DVec2,
    half: DVec2,
}

impl<const PX: bool, const PY: bool> Image<PX, PY> {
    /// The image rule of `domain` (whose periodicity must be `[PX, PY]`).
    pub fn new(domain: &Domain) -> Self {
        debug_assert_eq!(domain.periodic, [PX, PY]);
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
    pub fn wrap(&self, mut p: DVec2) -> DVec2 {
        if PX {
            if p.x < self.lo.x {
                p.x += self.period.x;
            } else if p.x >= self.hi.x {
                p.x -= self.period.x;
            }
        }
        if PY {
            if p.y < self.lo.y {
                p.y += self.period.y;
            } else if p.y >= self.hi.y {
                p.y -= self.period.y;
            }
        }
        p
    }

    /// Nearest image of a separation between two points inside the box.
    #[inline(always)]
    pub fn apply(&self, mut d: DVec2) -> DVec2 {
        if PX {
            if d.x > self.half.x {
                d.x -= self.period.x;
            } else if d.x < -self.half.x {
                d.x += self.period.x;
            }
        }
        if PY {
            if d.y > self.half.y {
                d.y -= self.period.y;
            } else if d.y < -self.half.y {
                d.y += self.period.y;
            }
        }
        d
    }
}

/// Calls `$f::<PX, PY>($args)` with the domain's periodicity as const generics.
#[macro_export]
macro_rules! with_image {
    ($domain:expr, $f:ident $(::<$($g:ty),*>)?, ($($arg:expr),*)) => {
        match $domain.periodic {
            [false, false] => $f::<$($($g,)*)? false, false>($($arg),*),
            [true, false] => $f::<$($($g,)*)? true, false>($($arg),*),
            [false, true] => $f::<$($($g,)*)? false, true>($($arg),*),
            [true, true] => $f::<$($($g,)*)? true, true>($($arg),*),
        }
    };
}

#[cfg(test)]
mod tests {
    use super::*;

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
