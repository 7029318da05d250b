//! The Cartesian grid of ranks over the domain: which rank owns a position, which ranks
//! are a rank's neighbours, and how far a position is from a rank's region (periodic
//! axes wrap). Written over [`DIM`], so the same source serves 2D and 3D.
//!
//! Each axis is cut into slabs at a sorted list of cut positions, each slab of its own
//! width (equal at the start; load balancing moves them, `balance.rs`). A rank's box is
//! the product of one slab per axis, so the grid's topology, and with it every rank's
//! neighbours, never changes when cuts move. The rule that keeps ghosts one rank away:
//! *every slab of an axis cut into several is at least the ghost layer wide* (2 r_max +
//! skin), so a particle within the layer of a box lies in that box's slab or the next
//! one along each axis, that is in a neighbouring box.

use crate::domain::Domain;
use crate::math::{Vector, DIM};

/// Ranks laid out as `dims[0] × dims[1] (× dims[2])` boxes over the domain, the first
/// axis's coordinate changing fastest in the rank number.
#[derive(Clone, Debug, PartialEq)]
pub struct RankGrid {
    /// Ranks along each axis.
    pub dims: [usize; DIM],
    domain: Domain,
    /// The ghost layer's width (m): no slab of a cut axis is narrower.
    halo: f64,
    /// Per axis, the slabs' bounds: `dims[a] + 1` ascending positions from the domain's
    /// lower face to its upper one.
    cuts: [Vec<f64>; DIM],
}

/// Why a rank grid does not fit a run.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum GridError {
    /// The grid's rank count is not the run's.
    #[error("ranks = {dims:?} makes {product} ranks, but the run has {ranks}; allowed: a grid whose product is {ranks}")]
    Count {
        /// The grid asked for.
        dims: Vec<usize>,
        /// Its product.
        product: usize,
        /// The run's rank count.
        ranks: usize,
    },
    /// A rank's box is narrower than the ghost layer, so a particle could need copies
    /// two ranks away.
    #[error("ranks = {dims:?} cuts axis {axis} into boxes {width:.4e} m wide, under the contact range {halo:.4e} m (2 r_max + skin); allowed: at most {most} ranks along that axis")]
    Narrow {
        /// The grid asked for.
        dims: Vec<usize>,
        /// The axis cut too finely.
        axis: usize,
        /// Its boxes' width (m).
        width: f64,
        /// The ghost layer's width (m).
        halo: f64,
        /// The most ranks that axis takes.
        most: usize,
    },
    /// Cuts that do not run from the domain's lower face to its upper one, one more
    /// than the ranks along the axis.
    #[error("cuts along axis {axis} do not bound its slabs from the domain's lower face to its upper one")]
    Cuts {
        /// The axis.
        axis: usize,
    },
    /// Something the decomposition does not carry yet.
    #[error("{0} is not supported on several ranks yet (docs/parallel.md); allowed: 1 rank")]
    Unsupported(&'static str),
}

impl RankGrid {
    /// The grid `dims` over `domain`, for `ranks` ranks and a ghost layer `halo` wide.
    pub fn new(
        domain: Domain,
        dims: [usize; DIM],
        ranks: usize,
        halo: f64,
    ) -> Result<Self, GridError> {
        let product: usize = dims.iter().product();
        if product != ranks || dims.contains(&0) {
            return Err(GridError::Count {
                dims: dims.to_vec(),
                product,
                ranks,
            });
        }
        let len = domain.length();
        let cuts = std::array::from_fn(|a| {
            let width = len[a] / dims[a] as f64;
            (0..=dims[a])
                .map(|k| match k {
                    k if k == dims[a] => domain.hi[a],
                    k => domain.lo[a] + k as f64 * width,
                })
                .collect()
        });
        RankGrid {
            dims,
            domain,
            halo,
            cuts,
        }
        .checked()
    }

    /// This grid with the slabs' bounds `cuts` (per axis `dims[a] + 1` ascending
    /// positions from the domain's lower face to its upper one), refused when a slab of
    /// a cut axis is narrower than the ghost layer.
    pub fn with_cuts(&self, cuts: [Vec<f64>; DIM]) -> Result<Self, GridError> {
        for (a, c) in cuts.iter().enumerate() {
            let ends = (c.first(), c.last());
            if c.len() != self.dims[a] + 1
                || ends != (Some(&self.domain.lo[a]), Some(&self.domain.hi[a]))
            {
                return Err(GridError::Cuts { axis: a });
            }
        }
        RankGrid {
            cuts,
            ..self.clone()
        }
        .checked()
    }

    /// The grid, or why a slab is too narrow.
    fn checked(self) -> Result<Self, GridError> {
        let len = self.domain.length();
        for a in (0..DIM).filter(|&a| self.dims[a] > 1) {
            let c = &self.cuts[a];
            let width = (0..self.dims[a])
                .map(|k| c[k + 1] - c[k])
                .fold(f64::INFINITY, f64::min);
            if width.is_nan() || width < self.halo {
                return Err(GridError::Narrow {
                    dims: self.dims.to_vec(),
                    axis: a,
                    width,
                    halo: self.halo,
                    most: ((len[a] / self.halo).floor() as usize).max(1),
                });
            }
        }
        Ok(self)
    }

    /// The domain the grid covers.
    pub fn domain(&self) -> &Domain {
        &self.domain
    }

    /// The ghost layer's width (m), the narrowest a slab of a cut axis may be.
    pub fn halo(&self) -> f64 {
        self.halo
    }

    /// The bounds of the slabs along `axis`: `dims[axis] + 1` ascending positions.
    pub fn cuts(&self, axis: usize) -> &[f64] {
        &self.cuts[axis]
    }

    /// The lower and upper corners of `rank`'s box (the boxes at non-periodic faces
    /// also own what lies beyond them).
    pub fn bounds(&self, rank: usize) -> (Vector, Vector) {
        let c = self.coords(rank);
        let mut lo = Vector::ZERO;
        let mut hi = Vector::ZERO;
        for a in 0..DIM {
            lo[a] = self.cuts[a][c[a]];
            hi[a] = self.cuts[a][c[a] + 1];
        }
        (lo, hi)
    }

    /// The grid for `ranks` ranks whose cuts are shortest in total (ties: more ranks
    /// along the first axis).
    pub fn auto(domain: Domain, ranks: usize, halo: f64) -> Result<Self, GridError> {
        let len = domain.length();
        let mut best: Option<([usize; DIM], f64)> = None;
        for dims in factorisations(ranks) {
            // The area (length in 2D) of every cut plane.
            let cut: f64 = (0..DIM)
                .map(|a| {
                    let face: f64 = (0..DIM).filter(|&b| b != a).map(|b| len[b]).product();
                    (dims[a] - 1) as f64 * face
                })
                .sum();
            if best.is_none_or(|(_, c)| cut < c) {
                best = Some((dims, cut));
            }
        }
        Self::new(domain, best.map_or([1; DIM], |b| b.0), ranks, halo)
    }

    /// Number of ranks.
    pub fn ranks(&self) -> usize {
        self.dims.iter().product()
    }

    /// A rank's place in the grid.
    pub fn coords(&self, rank: usize) -> [usize; DIM] {
        let mut r = rank;
        std::array::from_fn(|a| {
            let c = r % self.dims[a];
            r /= self.dims[a];
            c
        })
    }

    /// The rank at a place in the grid.
    pub fn rank(&self, c: [usize; DIM]) -> usize {
        (0..DIM).rev().fold(0, |k, a| k * self.dims[a] + c[a])
    }

    /// The rank that owns a particle at `p`: beyond a non-periodic face of the domain,
    /// the rank at that face.
    pub fn owner(&self, p: Vector) -> usize {
        // The slab whose lower bound is the last inner cut at or below p (0 below the first).
        let c = std::array::from_fn(|a| {
            let inner = &self.cuts[a][1..self.dims[a]];
            inner.partition_point(|&cut| cut <= p[a])
        });
        self.rank(c)
    }

    /// The other ranks whose boxes touch `rank`'s, faces, edges and corners (wrapping
    /// periodic axes), each once, in increasing order.
    pub fn neighbours(&self, rank: usize) -> Vec<usize> {
        let c = self.coords(rank);
        let mut out = Vec::new();
        for o in 0..3usize.pow(DIM as u32) {
            let mut at = [0usize; DIM];
            let mut digits = o;
            let mut inside = true;
            for a in 0..DIM {
                let n = self.dims[a] as i64;
                let v = c[a] as i64 + (digits % 3) as i64 - 1;
                digits /= 3;
                if self.domain.periodic[a] {
                    at[a] = v.rem_euclid(n) as usize;
                } else if (0..n).contains(&v) {
                    at[a] = v as usize;
                } else {
                    inside = false;
                }
            }
            let q = self.rank(at);
            if inside && q != rank && !out.contains(&q) {
                out.push(q);
            }
        }
        out.sort_unstable();
        out
    }

    /// The distance from `p` to `rank`'s box (0 inside it), along periodic axes to the
    /// nearest image; the boxes at non-periodic faces reach to infinity.
    pub fn distance(&self, p: Vector, rank: usize) -> f64 {
        let c = self.coords(rank);
        let len = self.domain.length();
        let mut d2 = 0.0;
        for a in 0..DIM {
            let (lo, hi) = (self.cuts[a][c[a]], self.cuts[a][c[a] + 1]);
            let gap = |x: f64| {
                let below = c[a] > 0 || self.domain.periodic[a];
                let above = c[a] + 1 < self.dims[a] || self.domain.periodic[a];
                if x < lo && below {
                    lo - x
                } else if x > hi && above {
                    x - hi
                } else {
                    0.0
                }
            };
            let g = if self.domain.periodic[a] {
                [-len[a], 0.0, len[a]]
                    .into_iter()
                    .map(|s| gap(p[a] + s))
                    .fold(f64::INFINITY, f64::min)
            } else {
                gap(p[a])
            };
            d2 += g * g;
        }
        d2.sqrt()
    }
}

/// Every way to write `n` as a product of DIM factors, the first factor first.
fn factorisations(n: usize) -> Vec<[usize; DIM]> {
    fn go(n: usize, a: usize, at: &mut [usize; DIM], out: &mut Vec<[usize; DIM]>) {
        if a == DIM - 1 {
            at[a] = n;
            out.push(*at);
            return;
        }
        for f in (1..=n).rev().filter(|&f| n.is_multiple_of(f)) {
            at[a] = f;
            go(n / f, a + 1, at, out);
        }
    }
    let mut out = Vec::new();
    go(n.max(1), 0, &mut [1; DIM], &mut out);
    out
}

#[cfg(all(test, feature = "dim2"))]
mod tests {
    use super::*;
    use glam::DVec2;

    fn unit(periodic: [bool; 2]) -> Domain {
        Domain {
            lo: DVec2::ZERO,
            hi: DVec2::new(2.0, 1.0),
            periodic,
        }
    }

    #[test]
    fn owners_neighbours_and_distances() {
        let g = RankGrid::new(unit([true, false]), [2, 2], 4, 0.1).unwrap();
        assert_eq!(g.owner(DVec2::new(0.5, 0.2)), 0);
        assert_eq!(g.owner(DVec2::new(1.5, 0.2)), 1);
        assert_eq!(g.owner(DVec2::new(0.5, 0.7)), 2);
        // Beyond the open top: the top row.
        assert_eq!(g.owner(DVec2::new(1.5, 3.0)), 3);
        assert_eq!(g.neighbours(0), vec![1, 2, 3]);
        // Periodic along x: 1.9 is 0.1 from rank 0's box through the wrap.
        assert!((g.distance(DVec2::new(1.9, 0.2), 0) - 0.1).abs() < 1e-12);
        assert_eq!(g.distance(DVec2::new(0.3, -5.0), 0), 0.0);
        assert!((g.distance(DVec2::new(0.3, 0.2), 2) - 0.3).abs() < 1e-12);
    }

    #[test]
    fn moved_cuts_own_measure_and_refuse_slabs_under_the_ghost_layer() {
        let g = RankGrid::new(unit([true, false]), [4, 1], 4, 0.1).unwrap();
        let g = g
            .with_cuts([vec![0.0, 0.1, 0.3, 1.9, 2.0], vec![0.0, 1.0]])
            .unwrap();
        assert_eq!(g.owner(DVec2::new(0.05, 0.5)), 0);
        assert_eq!(g.owner(DVec2::new(0.1, 0.5)), 1);
        assert_eq!(g.owner(DVec2::new(1.0, 0.5)), 2);
        assert_eq!(g.owner(DVec2::new(5.0, 0.5)), 3);
        assert_eq!(g.bounds(2), (DVec2::new(0.3, 0.0), DVec2::new(1.9, 1.0)));
        // The neighbours are the grid's, wherever the cuts are.
        assert_eq!(g.neighbours(0), vec![1, 3]);
        // Through the periodic wrap, 0.15 from rank 1's box [0.1, 0.3].
        assert!((g.distance(DVec2::new(1.95, 0.5), 1) - 0.15).abs() < 1e-12);
        let narrow = g
            .with_cuts([vec![0.0, 0.1, 0.15, 1.9, 2.0], vec![0.0, 1.0]])
            .unwrap_err();
        assert!(
            matches!(narrow, GridError::Narrow { axis: 0, .. }),
            "{narrow}"
        );
        let short = g.with_cuts([vec![0.0, 1.0, 2.0], vec![0.0, 1.0]]);
        assert!(matches!(short, Err(GridError::Cuts { axis: 0 })));
    }

    #[test]
    fn bad_grids_are_refused_and_auto_cuts_the_long_side() {
        assert!(matches!(
            RankGrid::new(unit([false; 2]), [2, 2], 3, 0.1),
            Err(GridError::Count { product: 4, .. })
        ));
        let narrow = RankGrid::new(unit([false; 2]), [1, 20], 20, 0.1).unwrap_err();
        assert!(narrow.to_string().contains("axis 1"), "{narrow}");
        assert_eq!(
            RankGrid::auto(unit([false; 2]), 2, 0.1).unwrap().dims,
            [2, 1]
        );
        assert_eq!(
            RankGrid::auto(unit([false; 2]), 4, 0.1).unwrap().dims,
            [4, 1]
        );
    }
}
