//! A static cell list: particles counting-sorted into square cells (CSR layout), for
//! neighbour queries in O(1) per particle.

use glam::DVec2;

/// The geometry of a grid of `nx × ny` square cells of side `cell` over the box
/// `lo..lo + (nx, ny)·cell`; with `periodic_x` the columns wrap.
#[derive(Clone, Copy, Debug)]
pub struct CellLayout {
    /// Lower corner of the grid.
    pub lo: DVec2,
    /// Cell side.
    pub cell: f64,
    /// Columns.
    pub nx: usize,
    /// Rows.
    pub ny: usize,
    /// Whether the columns wrap in x.
    pub periodic_x: bool,
}

impl CellLayout {
    /// Column and row of a position, clamped into the grid (wrapped in periodic x).
    #[inline]
    pub fn coords(&self, p: DVec2) -> (i64, i64) {
        let fx = ((p.x - self.lo.x) / self.cell).floor() as i64;
        let fy = ((p.y - self.lo.y) / self.cell).floor() as i64;
        let cx = if self.periodic_x {
            fx.rem_euclid(self.nx as i64)
        } else {
            fx.clamp(0, self.nx as i64 - 1)
        };
        (cx, fy.clamp(0, self.ny as i64 - 1))
    }

    /// Row-major index of the cell holding a position.
    #[inline]
    pub fn index(&self, p: DVec2) -> usize {
        let (cx, cy) = self.coords(p);
        cy as usize * self.nx + cx as usize
    }
}

/// Particles binned into square cells of side `cell`, over the box `lo..lo + n·cell`.
///
/// With a periodic x direction the columns wrap, so a query near one side finds
/// particles near the other; the caller applies the minimum image to distances.
#[derive(Clone, Debug)]
pub struct CellGrid {
    layout: CellLayout,
    /// `start[c]..start[c + 1]` indexes `items` for cell `c`.
    start: Vec<u32>,
    items: Vec<u32>,
}

impl CellGrid {
    /// Bins `pos` into cells of side at least `cell` covering `lo..hi`. With `period_x`
    /// the x extent is divided into a whole number of cells of the period, at least three.
    pub fn build(pos: &[DVec2], lo: DVec2, hi: DVec2, cell: f64, period_x: Option<f64>) -> Self {
        let cell = cell.max(1e-300);
        let (nx, cell_x) = match period_x {
            Some(l) => {
                let n = ((l / cell).floor() as usize).max(1);
                (n, l / n as f64)
            }
            None => ((((hi.x - lo.x) / cell).ceil() as usize).max(1), cell),
        };
        // Square cells keep the query shape simple; the periodic width sets the side.
        let side = cell_x.max(cell);
        let nx = if period_x.is_some() {
            nx
        } else {
            (((hi.x - lo.x) / side).ceil() as usize).max(1)
        };
        let ny = (((hi.y - lo.y) / side).ceil() as usize).max(1);
        let mut g = CellGrid {
            layout: CellLayout {
                lo,
                cell: side,
                nx,
                ny,
                periodic_x: period_x.is_some(),
            },
            start: vec![0; nx * ny + 1],
            items: vec![0; pos.len()],
        };
        let cells: Vec<u32> = pos.iter().map(|p| g.layout.index(*p) as u32).collect();
        for &c in &cells {
            g.start[c as usize + 1] += 1;
        }
        for c in 0..nx * ny {
            g.start[c + 1] += g.start[c];
        }
        let mut fill = g.start.clone();
        for (i, &c) in cells.iter().enumerate() {
            g.items[fill[c as usize] as usize] = i as u32;
            fill[c as usize] += 1;
        }
        g
    }

    /// Cell side.
    pub fn cell(&self) -> f64 {
        self.layout.cell
    }

    /// Column and row of a position, clamped into the grid (wrapped in periodic x).
    #[inline]
    pub fn coords(&self, p: DVec2) -> (i64, i64) {
        self.layout.coords(p)
    }

    /// The particles of cell `(cx, cy)`; empty outside the grid. In periodic x the
    /// column wraps.
    #[inline]
    pub fn cell_items(&self, cx: i64, cy: i64) -> &[u32] {
        if cy < 0 || cy >= self.layout.ny as i64 {
            return &[];
        }
        let cx = if self.layout.periodic_x {
            cx.rem_euclid(self.layout.nx as i64)
        } else if cx < 0 || cx >= self.layout.nx as i64 {
            return &[];
        } else {
            cx
        };
        let c = cy as usize * self.layout.nx + cx as usize;
        &self.items[self.start[c] as usize..self.start[c + 1] as usize]
    }

    /// Calls `f(j)` for every particle in the cells within `reach` cells of `p`'s cell
    /// (a `(2 reach + 1)²` block), each once even when periodic columns wrap around.
    #[inline]
    pub fn for_each_near(&self, p: DVec2, reach: i64, mut f: impl FnMut(u32)) {
        let (cx, cy) = self.coords(p);
        let span = (2 * reach + 1).min(if self.layout.periodic_x {
            self.layout.nx as i64
        } else {
            i64::MAX
        });
        for dy in -reach..=reach {
            for k in 0..span {
                for &j in self.cell_items(cx - reach + k, cy + dy) {
                    f(j);
                }
            }
        }
    }

    /// Number of columns and rows.
    pub fn dims(&self) -> (usize, usize) {
        (self.layout.nx, self.layout.ny)
    }

    /// Particle indices in cell order (row by row): a spatially coherent ordering.
    pub fn order(&self) -> &[u32] {
        &self.items
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_all_neighbours_in_periodic_box() {
        let pos: Vec<DVec2> = (0..200)
            .map(|k| {
                DVec2::new(
                    (k as f64 * 0.618_034).fract() * 10.0,
                    (k as f64 * 0.414_21).fract() * 4.0,
                )
            })
            .collect();
        let g = CellGrid::build(&pos, DVec2::ZERO, DVec2::new(10.0, 4.0), 1.0, Some(10.0));
        let delta = |a: DVec2, b: DVec2| {
            let mut d = b - a;
            d.x -= 10.0 * (d.x / 10.0).round();
            d
        };
        for (i, p) in pos.iter().enumerate() {
            let mut found = Vec::new();
            g.for_each_near(*p, 1, |j| {
                if j as usize != i && delta(*p, pos[j as usize]).length() < 1.0 {
                    found.push(j)
                }
            });
            found.sort_unstable();
            let brute: Vec<u32> = (0..pos.len() as u32)
                .filter(|&j| j as usize != i && delta(*p, pos[j as usize]).length() < 1.0)
                .collect();
            assert_eq!(found, brute);
        }
    }
}
