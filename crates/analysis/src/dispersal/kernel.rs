//! How a grain (or a point of a contact's branch vector) is shared among the bins.
//!
//! * [`Kernel::Bin`] — the paper's plain bin average: a grain counts whole in the bin
//!   holding its centre, and a contact's `l ⊗ f` is split among the bins its branch
//!   vector crosses by length.
//! * [`Kernel::Hat`] — the bin average of a field first smoothed with a kernel of
//!   half-width `w` (MercuryCG's coarse graining, dem.md §3.5): a point at polar
//!   position (r, θ) spreads its quantity as the product of two hat (triangle) kernels,
//!   one in r and one in arc length rθ, each of support ±w. The weights over the bins
//!   sum to one, so mass and momentum are kept exactly; the bin values no longer jump
//!   by a whole grain as grains cross bin edges, which for the paper's thin bins
//!   (5 d0 × 3–9 d0, a few dozen grains) is most of their noise.
//!
//! Both are deterministic: every bin sums its contributions in a fixed order (by
//! sector, then source index), whatever the number of threads.

use super::input::{positive, InputError};
use super::polar::PolarGrid;
use glam::DVec2;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::f64::consts::{PI, TAU};

/// The coarse-graining kernel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Kernel {
    /// Plain bin averages (xue-2019): whole grains by their centres.
    #[default]
    Bin,
    /// Hat kernel of half-width `half_width` (m) in r and in arc length.
    Hat {
        /// Half-width w (m); about one grain diameter is the usual choice.
        half_width: f64,
    },
}

impl Kernel {
    /// Checks the width; `key` names the setting in messages.
    pub fn validate(&self, key: &str) -> Result<(), InputError> {
        match *self {
            Kernel::Bin => Ok(()),
            Kernel::Hat { half_width } => {
                positive(&format!("{key}.half_width"), half_width).map(|_| ())
            }
        }
    }

    /// The half-width, zero for plain bins.
    pub fn half_width(&self) -> f64 {
        match *self {
            Kernel::Bin => 0.0,
            Kernel::Hat { half_width } => half_width,
        }
    }
}

/// Integral of the unit hat kernel (support ±1, peak 1) from −∞ to `u`.
#[inline]
fn hat_cdf(u: f64) -> f64 {
    if u <= -1.0 {
        0.0
    } else if u <= 0.0 {
        0.5 * (1.0 + u) * (1.0 + u)
    } else if u < 1.0 {
        1.0 - 0.5 * (1.0 - u) * (1.0 - u)
    } else {
        1.0
    }
}

/// Calls `f(ring, sector, weight)` for every bin that the hat kernel of half-width `w`
/// centred on `p` (relative to the grid centre) overlaps; the weights of the bins on
/// the grid sum to one (less whatever falls off the grid).
#[inline]
pub(crate) fn spread(grid: &PolarGrid, p: DVec2, w: f64, mut f: impl FnMut(usize, usize, f64)) {
    let r = p.length();
    let (r_lo, r_hi) = (grid.r_min(), grid.r_max());
    if r + w <= r_lo || r - w >= r_hi {
        return;
    }
    let i0 = (((r - w).max(r_lo) - r_lo) / grid.dr()) as usize;
    let i1 = ((((r + w).min(r_hi) - r_lo) / grid.dr()) as usize).min(grid.n_r() - 1);
    let theta = p.y.atan2(p.x).rem_euclid(TAU);
    let dt = grid.dtheta();
    let n = grid.n_theta() as i64;
    // Half-width in angle; near the centre the arc kernel would wrap the whole circle,
    // so there the point stays in its own sector.
    let alpha = if r > 0.0 { w / r } else { f64::INFINITY };
    for i in i0..=i1 {
        let fr = hat_cdf((grid.r_edge(i + 1) - r) / w) - hat_cdf((grid.r_edge(i) - r) / w);
        if fr <= 0.0 {
            continue;
        }
        if alpha >= PI {
            f(i, grid.sector_of(p), fr);
            continue;
        }
        let s0 = ((theta - alpha) / dt).floor() as i64;
        let s1 = ((theta + alpha) / dt).floor() as i64;
        for s in s0..=s1 {
            let ft = hat_cdf(((s + 1) as f64 * dt - theta) / alpha)
                - hat_cdf((s as f64 * dt - theta) / alpha);
            if ft > 0.0 {
                f(i, s.rem_euclid(n) as usize, fr * ft);
            }
        }
    }
}

/// Sources (grains, contacts) grouped by the sector of their anchor point, CSR.
pub(crate) struct SectorIndex {
    start: Vec<u32>,
    items: Vec<u32>,
}

impl SectorIndex {
    /// Groups sources by `sector[k]` (`u32::MAX` for none), keeping index order.
    pub(crate) fn new(n_theta: usize, sector: &[u32]) -> Self {
        let mut start = vec![0u32; n_theta + 1];
        for &s in sector {
            if s != u32::MAX {
                start[s as usize + 1] += 1;
            }
        }
        for j in 0..n_theta {
            start[j + 1] += start[j];
        }
        let mut fill = start.clone();
        let mut items = vec![0u32; start[n_theta] as usize];
        for (k, &s) in sector.iter().enumerate() {
            if s != u32::MAX {
                items[fill[s as usize] as usize] = k as u32;
                fill[s as usize] += 1;
            }
        }
        SectorIndex { start, items }
    }

    /// The sources of sector `j`.
    pub(crate) fn sector(&self, j: usize) -> &[u32] {
        &self.items[self.start[j] as usize..self.start[j + 1] as usize]
    }
}

/// Sectors on either side of its anchor's sector that a source can touch: the kernel
/// (half-width `w`) is spread from points up to `offset` (m) from anchors at radius
/// ≥ `r_inner`. Such a point is at most asin(offset/r_inner) from the anchor in angle
/// and its kernel spans ±w/(r_inner − offset); an anchor anywhere in its sector then
/// reaches ceil(that angle/dθ) sectors either side. Near the centre, every sector.
pub(crate) fn sector_reach(grid: &PolarGrid, w: f64, offset: f64, r_inner: f64) -> usize {
    let half = grid.n_theta() / 2;
    if r_inner <= offset + w {
        return half;
    }
    let a = (offset / r_inner).asin() + w / (r_inner - offset);
    ((a / grid.dtheta()).ceil() as usize).min(half)
}

/// Each source's shares of the bins, spread once (CSR by source): [`gather`] visits a
/// source from every sector its kernel can reach, and reading its shares back is much
/// cheaper than spreading it again.
pub(crate) struct Pieces {
    start: Vec<u32>,
    share: Vec<Share>,
}

/// One source's share of one bin: ring, sector, weight.
type Share = (u32, u32, f64);

/// Sources spread in fixed chunks, so the pieces are the same whatever the threads.
const PIECE_CHUNK: usize = 4096;

impl Pieces {
    /// Spreads sources `0..n` with `visit` (calling back `(ring, sector, weight)`).
    pub(crate) fn new<V>(n: usize, visit: V) -> Self
    where
        V: Fn(u32, &mut dyn FnMut(usize, usize, f64)) + Sync,
    {
        let parts: Vec<(Vec<u32>, Vec<Share>)> = (0..n.div_ceil(PIECE_CHUNK))
            .into_par_iter()
            .map(|c| {
                let range = c * PIECE_CHUNK..((c + 1) * PIECE_CHUNK).min(n);
                let mut count = Vec::with_capacity(range.len());
                let mut share = Vec::with_capacity(9 * range.len());
                for src in range {
                    let before = share.len();
                    visit(src as u32, &mut |i, j, w| {
                        share.push((i as u32, j as u32, w))
                    });
                    count.push((share.len() - before) as u32);
                }
                (count, share)
            })
            .collect();
        let mut start = Vec::with_capacity(n + 1);
        start.push(0u32);
        let mut all = Vec::with_capacity(parts.iter().map(|p| p.1.len()).sum());
        for (count, share) in parts {
            for c in count {
                start.push(start[start.len() - 1] + c);
            }
            all.extend(share);
        }
        Pieces { start, share: all }
    }

    /// Calls `f(ring, sector, weight)` for each share of source `src`.
    #[inline]
    pub(crate) fn visit(&self, src: u32, f: &mut dyn FnMut(usize, usize, f64)) {
        let k = src as usize;
        for &(i, j, w) in &self.share[self.start[k] as usize..self.start[k + 1] as usize] {
            f(i as usize, j as usize, w);
        }
    }
}

/// Per-bin accumulators gathered sector by sector: for each sector `j`, every source
/// anchored within `reach` sectors of it is spread with `visit` and the parts that land
/// in sector `j` are added with `add`. The result is in flat bin order.
pub(crate) fn gather<A, V, F>(
    grid: &PolarGrid,
    index: &SectorIndex,
    reach: usize,
    zero: A,
    visit: V,
    add: F,
) -> Vec<A>
where
    A: Clone + Send + Sync,
    V: Fn(u32, &mut dyn FnMut(usize, usize, f64)) + Sync,
    F: Fn(&mut A, u32, f64) + Sync,
{
    let n = grid.n_theta();
    let nr = grid.n_r();
    // Each sector visits its neighbours' sources once, in a fixed order; a reach that
    // covers the circle visits every sector once.
    let span = (2 * reach + 1).min(n);
    (0..n)
        .into_par_iter()
        .flat_map_iter(|j| {
            let mut local = vec![zero.clone(); nr];
            for d in 0..span {
                let jj = (j + n + d - reach.min(n / 2)) % n;
                for &src in index.sector(jj) {
                    visit(src, &mut |i, s, w| {
                        if s == j {
                            add(&mut local[i], src, w);
                        }
                    });
                }
            }
            local
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hat_weights_sum_to_one_and_are_local() {
        let g = PolarGrid::new(DVec2::ZERO, 1.0, 3.0, 0.25, 36).unwrap();
        for (p, w) in [
            (DVec2::new(2.0, 0.3), 0.1),
            (DVec2::new(-1.6, -0.02), 0.3),
            (DVec2::new(1.25, 1e-9), 0.2),
            (DVec2::new(2.0, -2.0), 0.05),
        ] {
            let mut sum = 0.0;
            let mut moment = DVec2::ZERO;
            spread(&g, p, w, |i, s, wt| {
                sum += wt;
                let c = g.bin_centre(g.index(i, s));
                assert!((c - p).length() < w + 0.3, "{p} {c}");
                moment += wt * c;
            });
            assert!((sum - 1.0).abs() < 1e-12, "{p}: {sum}");
            assert!((moment - p).length() < 0.3);
        }
        // Off the grid, the missing share is lost.
        let mut sum = 0.0;
        spread(&g, DVec2::new(2.99, 0.0), 0.1, |_, _, w| sum += w);
        assert!(sum < 0.99 && sum > 0.5);
        assert_eq!(hat_cdf(0.0), 0.5);
        assert_eq!(hat_cdf(-2.0) + hat_cdf(2.0), 1.0);
    }

    #[test]
    fn gather_matches_direct_accumulation() {
        let g = PolarGrid::new(DVec2::ZERO, 1.0, 3.0, 0.25, 36).unwrap();
        let pts: Vec<DVec2> = (0..400)
            .map(|k| (1.1 + 1.8 * (k as f64 * 0.618).fract()) * DVec2::from_angle(k as f64 * 0.7))
            .collect();
        let w = 0.15;
        let mut direct = vec![0.0; g.len()];
        for p in &pts {
            spread(&g, *p, w, |i, s, wt| direct[g.index(i, s)] += wt);
        }
        let sector: Vec<u32> = pts.iter().map(|p| g.sector_of(*p) as u32).collect();
        let idx = SectorIndex::new(36, &sector);
        let reach = sector_reach(&g, w, 0.0, 1.1);
        let got = gather(
            &g,
            &idx,
            reach,
            0.0,
            |k, f| spread(&g, pts[k as usize], w, f),
            |a: &mut f64, _, wt| *a += wt,
        );
        for k in 0..g.len() {
            assert!((got[k] - direct[k]).abs() < 1e-12, "{k}");
        }
        assert_eq!(sector_reach(&g, 0.5, 0.5, 1.0), 18);
        assert_eq!(sector_reach(&g, 0.1, 0.0, 2.0), 1);
    }
}
