//! The background grid: a uniform Cartesian mesh of square cells over the domain, with one
//! layer of ghost nodes outside it so that wide stencils (GIMP, B-splines) near a wall
//! never index out of range.

use glam::DVec2;

/// Ghost nodes kept outside each edge of the domain.
pub const GHOST: usize = 1;

/// Geometry of the background grid. Node `(i, j)` of the domain sits at
/// `lo + h·(i, j)`; it is *stored* at `(i + GHOST, j + GHOST)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    /// Lower-left corner of the domain (m).
    pub lo: DVec2,
    /// Cell size (m).
    pub h: f64,
    /// Cells along x and y.
    pub cells: [usize; 2],
}

impl Grid {
    /// Upper-right corner of the domain.
    pub fn hi(&self) -> DVec2 {
        self.lo + self.h * DVec2::new(self.cells[0] as f64, self.cells[1] as f64)
    }

    /// Stored nodes along x and y, ghosts included.
    pub fn stored(&self) -> [usize; 2] {
        [self.cells[0] + 1 + 2 * GHOST, self.cells[1] + 1 + 2 * GHOST]
    }

    /// Position of a stored node.
    pub fn node_pos(&self, stored: [usize; 2]) -> DVec2 {
        self.lo
            + self.h
                * DVec2::new(
                    stored[0] as f64 - GHOST as f64,
                    stored[1] as f64 - GHOST as f64,
                )
    }

    /// True if `x` lies inside the domain (edges included).
    pub fn contains(&self, x: DVec2) -> bool {
        let hi = self.hi();
        x.x >= self.lo.x && x.y >= self.lo.y && x.x <= hi.x && x.y <= hi.y
    }

    /// The cell holding `x` along each axis (domain cells from 0), clamped to the grid.
    pub fn cell_of(&self, x: DVec2) -> [usize; 2] {
        let r = (x - self.lo) / self.h;
        [
            (r.x.floor().max(0.0) as usize).min(self.cells[0] - 1),
            (r.y.floor().max(0.0) as usize).min(self.cells[1] - 1),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn node_positions_and_cells() {
        let g = Grid {
            lo: DVec2::new(-1.0, 2.0),
            h: 0.5,
            cells: [4, 2],
        };
        assert_eq!(g.hi(), DVec2::new(1.0, 3.0));
        assert_eq!(g.stored(), [7, 5]);
        assert_eq!(g.node_pos([GHOST, GHOST]), g.lo);
        assert_eq!(g.node_pos([0, 0]), g.lo - DVec2::splat(0.5));
        assert_eq!(g.cell_of(DVec2::new(0.9, 2.6)), [3, 1]);
        assert_eq!(g.cell_of(g.hi()), [3, 1]);
        assert!(g.contains(g.hi()) && !g.contains(DVec2::new(1.01, 2.5)));
    }
}
