//! Size sorting on the lattice start: exchanges the drawn sizes between lattice sites
//! so that large disks sit beside small ones, before any disk moves.
//!
//! Disks of random sizes on one lattice overlap wherever two large ones are neighbours;
//! pushing them apart distorts the lattice, and the denser the start the more it
//! distorts (a Gaussian of δ = 0.113 at φ = 0.846 loses local ψ6 from 1 to about 0.76).
//! A polydisperse crystal avoids this by arranging its sizes (fractionation); the
//! exchange does it directly. A swap of two sites' sizes is kept when it lowers the
//! summed squared overlap of their lattice bonds at the start's scale (zero
//! temperature), so the sizes stay the drawn ones and only their places change.

use glam::DVec2;
use grains_analysis::grid::CellGrid;
use grains_analysis::region::Region;
use grains_core::rng;
use rand::RngExt;

/// What the sorting did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SortStats {
    /// Summed squared bond overlap (d0² units) before and after.
    pub energy_before: f64,
    /// See `energy_before`.
    pub energy_after: f64,
    /// Share of lattice bonds that overlap, before and after.
    pub overlapping_before: f64,
    /// See `overlapping_before`.
    pub overlapping_after: f64,
    /// Exchanges tried and kept.
    pub tried: u64,
    /// See `tried`.
    pub kept: u64,
}

/// Sorts `radius` among the lattice sites `sites` (nearest-neighbour spacing
/// `spacing`), minimising Σ max(0, scale·(r_i + r_j) − spacing)² over the
/// lattice bonds, in `sweeps` sweeps of one exchange attempt per site, partners drawn
/// anywhere in the region. Deterministic for a seed.
pub fn sort_sizes(
    region: &Region,
    sites: &[DVec2],
    r: &mut [f64],
    spacing: f64,
    scale: f64,
    sweeps: u64,
    seed: u64,
) -> SortStats {
    let n = sites.len();
    let bonds = lattice_bonds(region, sites, spacing);
    let over = |a: f64, b: f64| (scale * (a + b) - spacing).max(0.0);
    let energy = |r: &[f64]| -> (f64, f64) {
        let (mut e, mut count, mut all) = (0.0, 0usize, 0usize);
        for i in 0..n {
            for &j in bonds.of(i) {
                if (j as usize) > i {
                    let o = over(r[i], r[j as usize]);
                    e += o * o;
                    count += (o > 0.0) as usize;
                    all += 1;
                }
            }
        }
        (e, count as f64 / all.max(1) as f64)
    };
    let (e0, f0) = energy(r);
    let mut stats = SortStats {
        energy_before: e0,
        overlapping_before: f0,
        ..Default::default()
    };
    if n < 2 {
        return SortStats {
            energy_after: e0,
            overlapping_after: f0,
            ..stats
        };
    }
    let mut rng = rng::stream(seed, 3);
    // The bond energy of site i if it held radius `ri`, leaving out its bond to `skip`
    // (a bond between the two exchanged sites keeps its sum).
    let site_energy = |r: &[f64], i: usize, ri: f64, skip: usize| -> f64 {
        bonds
            .of(i)
            .iter()
            .filter(|&&k| k as usize != skip)
            .map(|&k| {
                let o = over(ri, r[k as usize]);
                o * o
            })
            .sum()
    };
    for _ in 0..sweeps {
        for _ in 0..n {
            let i = rng.random_range(0..n);
            let j = rng.random_range(0..n);
            if i == j || r[i] == r[j] {
                continue;
            }
            stats.tried += 1;
            let before = site_energy(r, i, r[i], j) + site_energy(r, j, r[j], i);
            let after = site_energy(r, i, r[j], j) + site_energy(r, j, r[i], i);
            if after < before {
                r.swap(i, j);
                stats.kept += 1;
            }
        }
    }
    let (e1, f1) = energy(r);
    stats.energy_after = e1;
    stats.overlapping_after = f1;
    stats
}

/// Each site's lattice neighbours (sites within 1.05 spacings), in CSR form.
struct Bonds {
    start: Vec<u32>,
    list: Vec<u32>,
}

impl Bonds {
    fn of(&self, i: usize) -> &[u32] {
        &self.list[self.start[i] as usize..self.start[i + 1] as usize]
    }
}

fn lattice_bonds(region: &Region, sites: &[DVec2], spacing: f64) -> Bonds {
    let (lo, hi) = region.bounds();
    let grid = CellGrid::build(sites, lo, hi, 1.05 * spacing, region.period_x());
    let reach2 = (1.05 * spacing).powi(2);
    let mut start = Vec::with_capacity(sites.len() + 1);
    let mut list = Vec::with_capacity(sites.len() * 6);
    start.push(0);
    for (i, &p) in sites.iter().enumerate() {
        grid.for_each_near(p, 1, |j| {
            if j as usize != i && region.delta(p, sites[j as usize]).length_squared() < reach2 {
                list.push(j);
            }
        });
        start.push(list.len() as u32);
    }
    Bonds { start, list }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lattice::sites;

    #[test]
    fn sorting_keeps_the_sizes_and_lowers_the_overlap() {
        let region = Region::Rectangle {
            lo: DVec2::ZERO,
            hi: DVec2::new(30.0, 30.0),
            periodic_x: false,
        };
        let pos = sites(&region, 1.0, 0.5, DVec2::ZERO);
        let mut draw = rng::stream(7, 0);
        let mut radius: Vec<f64> = (0..pos.len())
            .map(|_| 0.5 * (1.0 + 0.113 * (draw.random::<f64>() * 2.0 - 1.0) * 3f64.sqrt()))
            .collect();
        let drawn = radius.clone();
        let s = sort_sizes(&region, &pos, &mut radius, 1.0, 0.97, 10, 1);
        // Many small overlaps replace a few large ones: the energy falls by two thirds
        // while the share of overlapping bonds barely moves.
        assert!(s.energy_after < 0.5 * s.energy_before, "{s:?}");
        let mut after = radius.clone();
        let mut before = drawn.clone();
        before.sort_by(f64::total_cmp);
        after.sort_by(f64::total_cmp);
        assert_eq!(before, after);
        // The same seed gives the same arrangement.
        let mut again = drawn;
        sort_sizes(&region, &pos, &mut again, 1.0, 0.97, 10, 1);
        assert_eq!(again, radius);
    }
}
