//! Load balancing: the cut planes of the [`RankGrid`] move so that the ranks own about
//! as many particles each, when the imbalance (most particles on a rank over the mean)
//! passes a threshold.
//!
//! *Particles, not contacts*: the count is exact and known at every rebuild without a
//! force pass; in a bed the work per particle is close to uniform (a few contacts each),
//! and in a gas the list and the integration are per particle. A contact count changes
//! every step and weights a dense lump over the gas around it only by a small factor.
//!
//! *The same decision on every rank*: the counts per rank and the histograms are
//! integers summed over the ranks ([`Reduce::sum_u64`], exact), and the new cuts are
//! bin edges computed from them by integer arithmetic, so every rank computes the same
//! grid bit for bit. The cuts of an axis are its histogram's quantiles (each slab holds
//! about as many particles as the next), held at least a ghost layer apart; new cuts
//! are taken only when the counts under them (summed again) are better balanced, so a
//! distribution the grid cannot balance (a product of slabs balances each axis, not
//! every box: a ring on 3 × 3 ranks leaves the centre box empty) does not move the cuts
//! at every rebuild.

use super::grid::RankGrid;
use super::Decomposed;
use crate::comm::{Post, Reduce};
use crate::math::{Vector, DIM};

/// Bins of the histograms per ghost-layer width: a cut's resolution.
const PER_HALO: f64 = 8.0;

/// The particles at `pos` each rank owns under `grid`, by rank.
fn counts(grid: &RankGrid, pos: &[Vector]) -> Vec<u64> {
    let mut n = vec![0u64; grid.ranks()];
    for &x in pos {
        n[grid.owner(x)] += 1;
    }
    n
}

/// The most particles on a rank over the mean (1 when there are none).
pub fn imbalance(counts: &[u64]) -> f64 {
    let total: u64 = counts.iter().sum();
    let most = counts.iter().copied().max().unwrap_or(0);
    if total == 0 {
        return 1.0;
    }
    most as f64 * counts.len() as f64 / total as f64
}

/// The histograms' bins along each axis (none along an axis that is not cut).
fn bins(grid: &RankGrid) -> [usize; DIM] {
    let len = grid.domain().length();
    std::array::from_fn(|a| match grid.dims[a] {
        1 => 0,
        _ => ((len[a] / grid.halo() * PER_HALO).floor() as usize).max(1),
    })
}

/// The particles at `pos` in each bin of each cut axis, the axes one after the other;
/// beyond a non-periodic face, in the bin at that face (as [`RankGrid::owner`] does).
fn histogram(grid: &RankGrid, pos: &[Vector]) -> Vec<u64> {
    let b = bins(grid);
    let (lo, len) = (grid.domain().lo, grid.domain().length());
    let mut h = vec![0u64; b.iter().sum()];
    for &x in pos {
        let mut at = 0;
        for a in (0..DIM).filter(|&a| b[a] > 0) {
            let k = ((x[a] - lo[a]) / len[a] * b[a] as f64).floor();
            h[at + (k.max(0.0) as usize).min(b[a] - 1)] += 1;
            at += b[a];
        }
    }
    h
}

/// The bin edges of `n` slabs over the histogram `h`, each slab at least `m` bins wide:
/// edge k is the edge nearest the k/n quantile, or `None` when `n` slabs of `m` bins do
/// not fit.
fn edges(h: &[u64], n: usize, m: usize) -> Option<Vec<usize>> {
    let b = h.len();
    if n * m > b {
        return None;
    }
    let mut cum = vec![0u128; b + 1];
    for (k, &c) in h.iter().enumerate() {
        cum[k + 1] = cum[k] + c as u128;
    }
    let (total, slabs) = (cum[b], n as u128);
    let mut e = vec![0usize; n + 1];
    e[n] = b;
    for k in 1..n {
        // Compared times n, in integers: cum(e) / total against k / n.
        let target = k as u128 * total;
        let first = cum.partition_point(|&c| c * slabs < target);
        let nearer_below =
            first > 0 && target - cum[first - 1] * slabs < cum[first] * slabs - target;
        let pick = if nearer_below { first - 1 } else { first };
        e[k] = pick.max(e[k - 1] + m).min(b - (n - k) * m);
    }
    Some(e)
}

/// `grid` with the cuts of every cut axis at the quantiles of the histogram `hist`
/// (made by [`histogram`] and summed over the ranks); an axis whose slabs cannot move
/// keeps its cuts. `None` when a slab would be narrower than the ghost layer.
fn recut(grid: &RankGrid, hist: &[u64]) -> Option<RankGrid> {
    let b = bins(grid);
    let d = grid.domain();
    let len = d.length();
    let mut cuts: [Vec<f64>; DIM] = std::array::from_fn(|a| grid.cuts(a).to_vec());
    let mut at = 0;
    for a in (0..DIM).filter(|&a| b[a] > 0) {
        let h = &hist[at..at + b[a]];
        at += b[a];
        let w = len[a] / b[a] as f64;
        // More bins than the layer takes, so rounding cannot make a slab narrower.
        let m = (grid.halo() / w).floor() as usize + 1;
        if let Some(e) = edges(h, grid.dims[a], m) {
            cuts[a] = e
                .iter()
                .map(|&k| match k {
                    0 => d.lo[a],
                    k if k == b[a] => d.hi[a],
                    k => d.lo[a] + k as f64 * w,
                })
                .collect();
        }
    }
    grid.with_cuts(cuts).ok()
}

impl<C: Reduce + Post> Decomposed<C> {
    /// Measures the imbalance of the particles at `pos` (this rank's own, summed over
    /// the ranks; with `whole`, every particle, which every rank holds) and, when it
    /// passes the threshold, moves the cuts to where it is lower. Returns whether the
    /// cuts moved (then particles may go to any rank, not only to neighbours). Every rank
    /// must call it at the same point, and every rank decides the same.
    pub(super) fn rebalance(&mut self, pos: &[Vector], whole: bool) -> bool {
        let total = |mut v: Vec<u64>| {
            if !whole {
                self.comm.sum_u64(&mut v);
            }
            v
        };
        let now = imbalance(&total(counts(&self.grid, pos)));
        self.imbalance = now;
        match self.balance {
            Some(t) if now > t => {}
            _ => return false,
        }
        let Some(grid) = recut(&self.grid, &total(histogram(&self.grid, pos))) else {
            return false;
        };
        if grid == self.grid {
            return false;
        }
        let then = imbalance(&total(counts(&grid, pos)));
        if then >= now {
            return false;
        }
        self.grid = grid;
        self.imbalance = then;
        self.rebalances += 1;
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edges_sit_at_the_quantiles_and_keep_slabs_wide_enough() {
        // Everything in the first eight bins of 64: four slabs of at least 4 bins.
        let mut h = vec![0u64; 64];
        for c in h.iter_mut().take(8) {
            *c = 10;
        }
        assert_eq!(edges(&h, 4, 2), Some(vec![0, 2, 4, 6, 64]));
        assert_eq!(edges(&h, 4, 4), Some(vec![0, 4, 8, 12, 64]));
        // Uniform: equal slabs.
        assert_eq!(edges(&[3; 12], 3, 1), Some(vec![0, 4, 8, 12]));
        // Four slabs of 20 bins do not fit in 64.
        assert_eq!(edges(&h, 4, 20), None);
        assert_eq!(imbalance(&[4, 0, 0, 0]), 4.0);
        assert_eq!(imbalance(&[0, 0]), 1.0);
    }
}
