//! The polar grid of xue-2019 §4.2: rings of width dr (5 or 10 d0) by sectors of dθ
//! (π/90) about the charge centre, and the particles sorted into its bins.
//!
//! Bin `(i, j)` is ring `i` (radii `r_min + i·dr .. r_min + (i + 1)·dr`) and sector `j`
//! (angles `j·dθ .. (j + 1)·dθ`, counter-clockwise from +x); its flat index is
//! `j·n_r + i`, ring index fastest — the order of the `.vts` cells and of
//! [`grains_core::plot::PolarMap`] values.

use super::input::{positive, InputError, ParticleSet};
use glam::DVec2;
use rayon::prelude::*;
use std::f64::consts::TAU;

/// The paper's radial bin width, in mean diameters.
pub const PAPER_DR_D0: f64 = 5.0;
/// The paper's number of sectors (dθ = π/90).
pub const PAPER_SECTORS: usize = 180;
/// Largest grid accepted, in bins: far beyond any useful resolution, and small enough
/// that a mistaken argument fails cleanly instead of exhausting memory.
const MAX_BINS: usize = 50_000_000;

/// A polar grid about `centre`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PolarGrid {
    centre: DVec2,
    r_min: f64,
    dr: f64,
    n_r: usize,
    n_theta: usize,
}

impl PolarGrid {
    /// Rings of width `dr` from `r_min` out to at least `r_max`, and `n_theta` sectors.
    pub fn new(
        centre: DVec2,
        r_min: f64,
        r_max: f64,
        dr: f64,
        n_theta: usize,
    ) -> Result<Self, InputError> {
        if !(centre.is_finite()) {
            return Err(InputError::new("grid.centre", centre, "must be finite"));
        }
        if !(r_min.is_finite() && r_min >= 0.0) {
            return Err(InputError::new(
                "grid.r_min",
                r_min,
                "must be finite and ≥ 0",
            ));
        }
        positive("grid.dr", dr)?;
        if !(r_max.is_finite() && r_max > r_min) {
            return Err(InputError::new(
                "grid.r_max",
                r_max,
                format!("must be finite and > r_min = {r_min}"),
            ));
        }
        if n_theta < 4 {
            return Err(InputError::new(
                "grid.n_theta",
                n_theta,
                "must be at least 4",
            ));
        }
        let n_r = ((r_max - r_min) / dr).ceil().max(1.0);
        if n_r * n_theta as f64 > MAX_BINS as f64 {
            return Err(InputError::new(
                "grid.dr",
                dr,
                format!("gives {n_r} rings × {n_theta} sectors, more than {MAX_BINS} bins"),
            ));
        }
        Ok(PolarGrid {
            centre,
            r_min,
            dr,
            n_r: n_r as usize,
            n_theta,
        })
    }

    /// Rings of width `dr` (the paper's 5 d0 or 10 d0) and `n_theta` sectors (180 in
    /// the paper) from `r_min` out one ring beyond the farthest centre in `particles`,
    /// so that every particle is binned.
    pub fn covering(
        centre: DVec2,
        r_min: f64,
        dr: f64,
        n_theta: usize,
        particles: &ParticleSet,
    ) -> Result<Self, InputError> {
        let far = particles
            .pos
            .par_iter()
            .map(|p| (*p - centre).length())
            .reduce(|| 0.0, f64::max);
        // One ring beyond the farthest centre, so that it lies strictly inside.
        PolarGrid::new(centre, r_min, far.max(r_min) + dr, dr, n_theta)
    }

    /// Centre (m).
    pub fn centre(&self) -> DVec2 {
        self.centre
    }

    /// Inner radius of the first ring (m).
    pub fn r_min(&self) -> f64 {
        self.r_min
    }

    /// Outer radius of the last ring (m).
    pub fn r_max(&self) -> f64 {
        self.r_min + self.n_r as f64 * self.dr
    }

    /// Ring width (m).
    pub fn dr(&self) -> f64 {
        self.dr
    }

    /// Sector angle (rad).
    pub fn dtheta(&self) -> f64 {
        TAU / self.n_theta as f64
    }

    /// Number of rings.
    pub fn n_r(&self) -> usize {
        self.n_r
    }

    /// Number of sectors.
    pub fn n_theta(&self) -> usize {
        self.n_theta
    }

    /// Number of bins.
    pub fn len(&self) -> usize {
        self.n_r * self.n_theta
    }

    /// True if the grid has no bins (never, for a grid built by [`PolarGrid::new`]).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Flat index of ring `i`, sector `j`.
    #[inline]
    pub fn index(&self, i: usize, j: usize) -> usize {
        j * self.n_r + i
    }

    /// Ring and sector of a flat index.
    #[inline]
    pub fn ring_sector(&self, k: usize) -> (usize, usize) {
        (k % self.n_r, k / self.n_r)
    }

    /// Inner radius of ring `i` (`i = n_r` gives the outer edge of the grid).
    #[inline]
    pub fn r_edge(&self, i: usize) -> f64 {
        self.r_min + i as f64 * self.dr
    }

    /// All ring edges, `n_r + 1` radii.
    pub fn r_edges(&self) -> Vec<f64> {
        (0..=self.n_r).map(|i| self.r_edge(i)).collect()
    }

    /// Mid-radius of ring `i`.
    #[inline]
    pub fn r_centre(&self, i: usize) -> f64 {
        self.r_min + (i as f64 + 0.5) * self.dr
    }

    /// Mid-angle of sector `j`.
    #[inline]
    pub fn theta_centre(&self, j: usize) -> f64 {
        (j as f64 + 0.5) * self.dtheta()
    }

    /// Area of a bin of ring `i` (m²).
    #[inline]
    pub fn bin_area(&self, i: usize) -> f64 {
        let (a, b) = (self.r_edge(i), self.r_edge(i + 1));
        0.5 * self.dtheta() * (b * b - a * a)
    }

    /// Geometric centre of bin `k` relative to the grid centre.
    pub fn bin_centre(&self, k: usize) -> DVec2 {
        let (i, j) = self.ring_sector(k);
        self.r_centre(i) * DVec2::from_angle(self.theta_centre(j))
    }

    /// Sector holding the direction of `d` (relative to the centre).
    #[inline]
    pub fn sector_of(&self, d: DVec2) -> usize {
        let a = d.y.atan2(d.x).rem_euclid(TAU);
        ((a / TAU * self.n_theta as f64) as usize).min(self.n_theta - 1)
    }

    /// Ring of radius `r`, or `None` outside the grid.
    #[inline]
    pub fn ring_of(&self, r: f64) -> Option<usize> {
        if r.is_nan() || r < self.r_min {
            return None;
        }
        let i = ((r - self.r_min) / self.dr) as usize;
        (i < self.n_r).then_some(i)
    }

    /// Flat index of the bin holding `d` (relative to the centre), or `None` outside.
    #[inline]
    pub fn locate_rel(&self, d: DVec2) -> Option<usize> {
        let i = self.ring_of(d.length())?;
        Some(self.index(i, self.sector_of(d)))
    }

    /// Flat index of the bin holding the absolute position `p`, or `None` outside.
    #[inline]
    pub fn locate(&self, p: DVec2) -> Option<usize> {
        self.locate_rel(p - self.centre)
    }
}

/// Marks a particle outside the grid in [`Binning::bin_of`].
pub const OUTSIDE: u32 = u32::MAX;

/// Particles sorted into the bins of a grid by their centres (CSR layout): the
/// particles of bin `k` are `items[start[k]..start[k + 1]]`, in increasing index, so
/// every per-bin sum runs in the same order whatever the number of threads.
#[derive(Clone, Debug, PartialEq)]
pub struct Binning {
    /// Bin of each particle, [`OUTSIDE`] if its centre is off the grid.
    pub bin_of: Vec<u32>,
    /// Offsets into `items`, one more than the number of bins.
    pub start: Vec<u32>,
    /// Particle indices, bin by bin.
    pub items: Vec<u32>,
}

impl Binning {
    /// Sorts the centres `pos` into `grid`.
    pub fn new(grid: &PolarGrid, pos: &[DVec2]) -> Self {
        let bin_of: Vec<u32> = pos
            .par_iter()
            .map(|p| grid.locate(*p).map_or(OUTSIDE, |k| k as u32))
            .collect();
        let mut start = vec![0u32; grid.len() + 1];
        for &b in &bin_of {
            if b != OUTSIDE {
                start[b as usize + 1] += 1;
            }
        }
        for k in 0..grid.len() {
            start[k + 1] += start[k];
        }
        let mut fill = start.clone();
        let mut items = vec![0u32; start[grid.len()] as usize];
        for (p, &b) in bin_of.iter().enumerate() {
            if b != OUTSIDE {
                items[fill[b as usize] as usize] = p as u32;
                fill[b as usize] += 1;
            }
        }
        Binning {
            bin_of,
            start,
            items,
        }
    }

    /// The particles of bin `k`.
    #[inline]
    pub fn bin(&self, k: usize) -> &[u32] {
        &self.items[self.start[k] as usize..self.start[k + 1] as usize]
    }

    /// Number of particles off the grid.
    pub fn outside(&self) -> usize {
        self.bin_of.len() - self.items.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn geometry_and_lookup() {
        let g = PolarGrid::new(DVec2::new(1.0, 2.0), 0.01, 0.0305, 1e-3, 180).unwrap();
        assert_eq!(g.n_r(), 21);
        assert!((g.r_max() - 0.031).abs() < 1e-15);
        let p = g.centre() + 0.0155 * DVec2::from_angle(0.5);
        let k = g.locate(p).unwrap();
        let (i, j) = g.ring_sector(k);
        assert_eq!(i, 5);
        assert_eq!(j, (0.5 / g.dtheta()) as usize);
        assert_eq!(g.index(i, j), k);
        assert!(g.locate(g.centre() + DVec2::new(0.005, 0.0)).is_none());
        assert!(g.locate(g.centre() + DVec2::new(0.0, 0.04)).is_none());
        assert_eq!(g.sector_of(DVec2::new(1.0, -1e-12)), 179);
        // Bin areas tile the annulus.
        let total: f64 = (0..g.n_r()).map(|i| g.bin_area(i)).sum::<f64>() * 180.0;
        let annulus = std::f64::consts::PI * (g.r_max().powi(2) - 0.01f64.powi(2));
        assert!((total - annulus).abs() < 1e-12 * annulus);
        assert_eq!(g.r_edges().len(), 22);
        assert!(
            (g.bin_centre(k) - (g.r_centre(i) * DVec2::from_angle(g.theta_centre(j)))).length()
                < 1e-15
        );
    }

    #[test]
    fn bad_arguments_name_themselves() {
        let c = DVec2::ZERO;
        assert_eq!(
            PolarGrid::new(c, -1.0, 1.0, 0.1, 8).unwrap_err().key,
            "grid.r_min"
        );
        assert_eq!(
            PolarGrid::new(c, 0.0, 1.0, 0.0, 8).unwrap_err().key,
            "grid.dr"
        );
        assert_eq!(
            PolarGrid::new(c, 0.5, 0.5, 0.1, 8).unwrap_err().key,
            "grid.r_max"
        );
        assert_eq!(
            PolarGrid::new(c, 0.0, 1.0, 0.1, 2).unwrap_err().key,
            "grid.n_theta"
        );
        assert_eq!(
            PolarGrid::new(c, 0.0, 1.0, 1e-9, 180).unwrap_err().key,
            "grid.dr"
        );
        let nan = DVec2::new(f64::NAN, 0.0);
        assert_eq!(
            PolarGrid::new(nan, 0.0, 1.0, 0.1, 8).unwrap_err().key,
            "grid.centre"
        );
    }

    #[test]
    fn binning_is_a_partition() {
        let g = PolarGrid::new(DVec2::ZERO, 1.0, 3.0, 0.5, 12).unwrap();
        let pos: Vec<DVec2> = (0..500)
            .map(|k| (0.5 + 3.0 * (k as f64 * 0.618).fract()) * DVec2::from_angle(k as f64))
            .collect();
        let b = Binning::new(&g, &pos);
        let mut seen = vec![false; pos.len()];
        for k in 0..g.len() {
            for &p in b.bin(k) {
                assert_eq!(g.locate(pos[p as usize]), Some(k));
                assert!(!seen[p as usize]);
                seen[p as usize] = true;
            }
        }
        let outside = pos.iter().filter(|p| g.locate(**p).is_none()).count();
        assert_eq!(b.outside(), outside);
        assert_eq!(seen.iter().filter(|s| **s).count() + outside, pos.len());
    }
}
