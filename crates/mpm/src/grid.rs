//! The background grid: a uniform Cartesian mesh of square cells over the domain, with one
//! layer of ghost nodes outside it so that wide stencils (GIMP, B-splines) near a wall
//! never index out of range.
//!
//! The grid may be periodic along y (the top and bottom edges are one line, as in the
//! paper's shear cell). Points are then kept inside `[lo.y, hi.y)`; the stored rows
//! outside the domain's first `ny` node rows are *images* of rows inside it (stored row
//! 0 is domain row ny − 1, stored rows ny + 1 and ny + 2 are domain rows 0 and 1), and
//! whatever a scatter puts on an image is added to its canonical row
//! ([`crate::nodes::Patch::fold`]).

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
    /// Periodic along y with period `cells[1] · h` (no walls at the bottom and top).
    pub periodic_y: bool,
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

    /// The period along y, if the grid is periodic.
    pub fn period_y(&self) -> Option<f64> {
        self.periodic_y.then(|| self.h * self.cells[1] as f64)
    }

    /// `x` moved by whole periods into `[lo.y, hi.y)` along a periodic y (unchanged
    /// otherwise). A point moves less than a cell per step, so one period is enough.
    #[inline(always)]
    pub fn wrap(&self, mut x: DVec2) -> DVec2 {
        if self.periodic_y {
            let l = self.h * self.cells[1] as f64;
            if x.y >= self.lo.y + l {
                x.y -= l;
            } else if x.y < self.lo.y {
                x.y += l;
            }
        }
        x
    }

    /// The stored rows of the domain's node rows along a periodic y, `[GHOST, GHOST + ny)`
    /// (every stored row is one of them or an image); `None` if y is not periodic.
    pub fn canonical_rows(&self) -> Option<Rows> {
        self.periodic_y.then_some(Rows { ny: self.cells[1] })
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

/// Row arithmetic of a periodic y: which canonical stored row a stored row stands for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rows {
    /// Cells (and distinct node rows) along y.
    pub ny: usize,
}

impl Rows {
    /// The canonical stored row of stored row `r`.
    #[inline(always)]
    pub fn canonical(self, r: usize) -> usize {
        // Stored rows run from 0 to ny + 2: one ghost below, two image rows above.
        if r < GHOST {
            r + self.ny
        } else if r >= GHOST + self.ny {
            r - self.ny
        } else {
            r
        }
    }

    /// How far (in rows, ±ny or 0) the canonical row of `r` lies from `r`: a position
    /// summed at the image moves by this many cells along y at the canonical row.
    #[inline(always)]
    pub fn shift(self, r: usize) -> f64 {
        self.canonical(r) as f64 - r as f64
    }

    /// The canonical row `d` rows from canonical row `r` (wrapping).
    #[inline(always)]
    pub fn offset(self, r: usize, d: isize) -> usize {
        let k = (r - GHOST) as isize + d;
        k.rem_euclid(self.ny as isize) as usize + GHOST
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
            periodic_y: false,
        };
        assert_eq!(g.hi(), DVec2::new(1.0, 3.0));
        assert_eq!(g.stored(), [7, 5]);
        assert_eq!(g.node_pos([GHOST, GHOST]), g.lo);
        assert_eq!(g.node_pos([0, 0]), g.lo - DVec2::splat(0.5));
        assert_eq!(g.cell_of(DVec2::new(0.9, 2.6)), [3, 1]);
        assert_eq!(g.cell_of(g.hi()), [3, 1]);
        assert!(g.contains(g.hi()) && !g.contains(DVec2::new(1.01, 2.5)));
        assert_eq!(g.wrap(DVec2::new(0.0, 3.2)), DVec2::new(0.0, 3.2));
    }

    #[test]
    fn periodic_rows_and_wrapping() {
        let g = Grid {
            lo: DVec2::new(0.0, -1.0),
            h: 0.25,
            cells: [4, 8],
            periodic_y: true,
        };
        assert_eq!(g.period_y(), Some(2.0));
        assert_eq!(g.wrap(DVec2::new(0.5, 1.0)), DVec2::new(0.5, -1.0));
        assert_eq!(g.wrap(DVec2::new(0.5, -1.25)), DVec2::new(0.5, 0.75));
        let rows = g.canonical_rows().unwrap();
        // Stored 0 is domain row −1 = ny − 1; stored ny + 1, ny + 2 are rows 0 and 1.
        assert_eq!(rows.canonical(0), 8);
        assert_eq!(rows.canonical(9), 1);
        assert_eq!(rows.canonical(10), 2);
        assert_eq!(rows.canonical(5), 5);
        assert_eq!(rows.shift(9), -8.0);
        assert_eq!(rows.offset(1, -1), 8);
        assert_eq!(rows.offset(8, 3), 3);
        // Every stored row's node sits a whole number of periods from its canonical one.
        for r in 0..g.stored()[1] {
            let (a, b) = (g.node_pos([0, r]), g.node_pos([0, rows.canonical(r)]));
            assert_eq!(b.y - a.y, rows.shift(r) * g.h);
        }
    }
}
