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

    /// Minimum-image version of a separation vector.
    #[inline(always)]
    pub fn min_image(&self, mut d: DVec2) -> DVec2 {
        if self.periodic[0] {
            let l = self.hi.x - self.lo.x;
            d.x -= l * (d.x / l).round();
        }
        if self.periodic[1] {
            let l = self.hi.y - self.lo.y;
            d.y -= l * (d.y / l).round();
        }
        d
    }

    /// Maps a position back into the box along periodic axes.
    #[inline(always)]
    pub fn wrap(&self, mut p: DVec2) -> DVec2 {
        if self.periodic[0] {
            let l = self.hi.x - self.lo.x;
            if p.x < self.lo.x || p.x >= self.hi.x {
                p.x -= l * ((p.x - self.lo.x) / l).floor();
                // floor can land exactly on hi for values just below lo.
                if p.x >= self.hi.x {
                    p.x = self.lo.x;
                }
            }
        }
        if self.periodic[1] {
            let l = self.hi.y - self.lo.y;
            if p.y < self.lo.y || p.y >= self.hi.y {
                p.y -= l * ((p.y - self.lo.y) / l).floor();
                if p.y >= self.hi.y {
                    p.y = self.lo.y;
                }
            }
        }
        p
    }
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
    }
}
