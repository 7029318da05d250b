//! The Cartesian grid of ranks over the domain: which rank owns a position, which ranks
//! are a rank's neighbours, and how far a position is from a rank's region (periodic
//! axes wrap). Written over [`DIM`], so the same source serves 2D and 3D.

use crate::domain::Domain;
use crate::math::{Vector, DIM};

/// Ranks laid out as `dims[0] × dims[1] (× dims[2])` equal boxes over the domain, the
/// first axis's coordinate changing fastest in the rank number.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RankGrid {
    /// Ranks along each axis.
    pub dims: [usize; DIM],
    domain: Domain,
    width: Vector,
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
        let mut width = Vector::ZERO;
        for a in 0..DIM {
            width[a] = len[a] / dims[a] as f64;
            if dims[a] > 1 && width[a] < halo {
                return Err(GridError::Narrow {
                    dims: dims.to_vec(),
                    axis: a,
                    width: width[a],
                    halo,
                    most: ((len[a] / halo).floor() as usize).max(1),
                });
            }
        }
        Ok(RankGrid {
            dims,
            domain,
            width,
        })
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
        let c = std::array::from_fn(|a| {
            let x = ((p[a] - self.domain.lo[a]) / self.width[a]).floor();
            (x.max(0.0) as usize).min(self.dims[a] - 1)
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
            let lo = self.domain.lo[a] + c[a] as f64 * self.width[a];
            let hi = lo + self.width[a];
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
