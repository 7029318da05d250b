//! Bond-orientational order ψ6 from each particle's six nearest neighbours.
//!
//! ψ6(k) = (1/6) Σ_j exp(6 i θ_kj), with j running over the 6 particles whose centres
//! are nearest to k's (self excluded, no distance cut-off, ties broken by index),
//! θ_kj the angle of the vector from k to j (minimum image in a periodic direction).
//! This is freud's `Hexatic(k=6)` with `{'mode': 'nearest', 'num_neighbors': 6}`.
//! With fewer than 6 other particles, all of them are used.

use crate::grid::CellGrid;
use crate::region::Region;
use glam::DVec2;
use rayon::prelude::*;

/// Number of neighbours in the definition.
pub const NEIGHBOURS: usize = 6;

/// ψ6 of every particle as `(re, im)`; NaN for a particle with no other particle.
pub fn psi6(pos: &[DVec2], region: &Region, grid: &CellGrid) -> Vec<DVec2> {
    pos.par_iter()
        .enumerate()
        .with_min_len(1024)
        .map(|(i, &p)| {
            let nn = nearest(pos, region, grid, i, NEIGHBOURS);
            if nn.is_empty() {
                return DVec2::splat(f64::NAN);
            }
            let mut s = DVec2::ZERO;
            for &(_, j) in &nn {
                let d = region.delta(p, pos[j as usize]);
                let t = 6.0 * d.y.atan2(d.x);
                s += DVec2::new(t.cos(), t.sin());
            }
            s / nn.len() as f64
        })
        .collect()
}

/// The `k` nearest other particles of particle `i` as `(distance², index)`, nearest
/// first. The cell search widens ring by ring until no unseen cell can hold a nearer one.
pub fn nearest(
    pos: &[DVec2],
    region: &Region,
    grid: &CellGrid,
    i: usize,
    k: usize,
) -> Vec<(f64, u32)> {
    let p = pos[i];
    let (cx, cy) = grid.coords(p);
    let (nx, ny) = grid.dims();
    let max_reach = nx.max(ny) as i64;
    let mut best: Vec<(f64, u32)> = Vec::with_capacity(k + 1);
    let consider = |j: u32, best: &mut Vec<(f64, u32)>| {
        if j as usize == i || best.iter().any(|e| e.1 == j) {
            return;
        }
        let d2 = region.delta(p, pos[j as usize]).length_squared();
        let key = (d2, j);
        if best.len() == k && key >= best[k - 1] {
            return;
        }
        let at = best.partition_point(|e| *e < key);
        best.insert(at, key);
        best.truncate(k);
    };
    // Within ring `reach` every point closer than `reach · cell` (from anywhere in the
    // home cell) has been seen.
    let mut reach = 0i64;
    loop {
        if reach == 0 {
            for &j in grid.cell_items(cx, cy) {
                consider(j, &mut best);
            }
        } else {
            for d in -reach..=reach {
                for &(x, y) in &[(cx + d, cy - reach), (cx + d, cy + reach)] {
                    for &j in grid.cell_items(x, y) {
                        consider(j, &mut best);
                    }
                }
                if d != -reach && d != reach {
                    for &(x, y) in &[(cx - reach, cy + d), (cx + reach, cy + d)] {
                        for &j in grid.cell_items(x, y) {
                            consider(j, &mut best);
                        }
                    }
                }
            }
        }
        let covered = reach as f64 * grid.cell();
        if (best.len() == k && best[k - 1].0 <= covered * covered) || reach > max_reach {
            break;
        }
        reach += 1;
    }
    best
}

/// The order figures of a set of particles.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct OrderFigures {
    /// Local order ⟨|ψ6(k)|⟩.
    pub local: f64,
    /// Global order |⟨ψ6(k)⟩| (phases cancel between differently oriented grains).
    pub global: f64,
    /// Particles counted.
    pub count: usize,
}

/// Local and global order over the particles where `mask` is true (NaN values skipped).
pub fn order(psi: &[DVec2], mask: impl Fn(usize) -> bool) -> OrderFigures {
    let (mut sum_abs, mut sum, mut n) = (0.0, DVec2::ZERO, 0usize);
    for (k, v) in psi.iter().enumerate() {
        if mask(k) && v.x.is_finite() {
            sum_abs += v.length();
            sum += *v;
            n += 1;
        }
    }
    if n == 0 {
        return OrderFigures {
            local: f64::NAN,
            global: f64::NAN,
            count: 0,
        };
    }
    OrderFigures {
        local: sum_abs / n as f64,
        global: (sum / n as f64).length(),
        count: n,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lattice(n: usize, a: f64, angle: f64) -> Vec<DVec2> {
        let (s, c) = angle.sin_cos();
        let mut v = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let p = DVec2::new(
                    a * (i as f64 + 0.5 * (j % 2) as f64),
                    a * j as f64 * 3f64.sqrt() / 2.0,
                );
                v.push(DVec2::new(c * p.x - s * p.y, s * p.x + c * p.y));
            }
        }
        v
    }

    #[test]
    fn perfect_lattice_interior_is_one_and_phase_follows_rotation() {
        let pos = lattice(20, 1.0, 0.1);
        let region = Region::bounding_box(&pos, &vec![0.5; pos.len()]);
        let (lo, hi) = region.bounds();
        let g = CellGrid::build(&pos, lo, hi, 1.0, None);
        let psi = psi6(&pos, &region, &g);
        let interior = |k: usize| region.boundary_distance(pos[k]) > 3.0;
        let f = order(&psi, interior);
        assert!(
            (f.local - 1.0).abs() < 1e-9 && (f.global - 1.0).abs() < 1e-9,
            "{f:?}"
        );
        let k = pos
            .iter()
            .position(|p| region.boundary_distance(*p) > 5.0)
            .unwrap();
        let phase = psi[k].y.atan2(psi[k].x);
        assert!((phase - 0.6).abs() < 1e-9, "{phase}");
    }

    #[test]
    fn nearest_matches_brute_force() {
        let pos: Vec<DVec2> = (0..500)
            .map(|k| {
                DVec2::new(
                    (k as f64 * 0.754_877).fract() * 7.0,
                    (k as f64 * 0.569_84).fract() * 3.0,
                )
            })
            .collect();
        for region in [
            Region::Rectangle {
                lo: DVec2::ZERO,
                hi: DVec2::new(7.0, 3.0),
                periodic_x: false,
            },
            Region::Rectangle {
                lo: DVec2::ZERO,
                hi: DVec2::new(7.0, 3.0),
                periodic_x: true,
            },
        ] {
            let (lo, hi) = region.bounds();
            let g = CellGrid::build(&pos, lo, hi, 0.3, region.period_x());
            for i in (0..pos.len()).step_by(7) {
                let got = nearest(&pos, &region, &g, i, 6);
                let mut all: Vec<(f64, u32)> = (0..pos.len() as u32)
                    .filter(|&j| j as usize != i)
                    .map(|j| (region.delta(pos[i], pos[j as usize]).length_squared(), j))
                    .collect();
                all.sort_by(|a, b| a.partial_cmp(b).unwrap());
                assert_eq!(got, all[..6].to_vec());
            }
        }
    }
}
