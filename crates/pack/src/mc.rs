//! Hard-disk Monte Carlo with growth: a Lubachevsky–Stillinger-like compression.
//!
//! Each sweep every mobile disk tries one random displacement and one exchange of size
//! with another disk of its cell, then grows towards the common target scale (radii
//! grow by one factor, so the size distribution is kept) as far as its neighbours
//! allow. The growth rate per sweep is the protocol's rate: fast growth jams the
//! disks where they stand (amorphous); slow growth gives them time to find
//! close-packed arrangements, which narrow size distributions can form and broad
//! ones cannot. Size exchanges are an equilibrium move (Berthier et al.'s swap Monte
//! Carlo): they reach the slow-growth limit in far fewer sweeps, without changing the
//! set of sizes.
//!
//! Parallel and deterministic: each sweep sorts the disks into square cells (grid
//! shifted by a seeded offset) wider than any interaction plus a move, and visits
//! them in four colour classes of a 2 × 2 checkerboard. A disk only moves within its
//! cell, so cells of one colour are independent; rows of one colour are processed in
//! parallel, each cell with its own random stream keyed by (seed, sweep, cell). No
//! result depends on the thread count.

use glam::DVec2;
use grains_analysis::grid::CellGrid;
use grains_analysis::region::Region;
use grains_core::rng;
use rand::RngExt;
use rayon::prelude::*;

/// Target acceptance of trial displacements.
const ACCEPTANCE: f64 = 0.3;

/// One disk's state during a sweep.
#[derive(Clone, Copy, Debug, Default)]
struct Disk {
    pos: DVec2,
    /// Final radius.
    base: f64,
    /// Current radius over final radius.
    scale: f64,
    /// Index in the caller's arrays.
    id: u32,
    mobile: bool,
}

impl Disk {
    fn r(&self) -> f64 {
        self.base * self.scale
    }
}

/// Hard disks: the first `fixed` never move, grow or swap (the lining).
pub struct HardDisks {
    /// Centres (d0 units).
    pub pos: Vec<DVec2>,
    /// Final radii (d0 units).
    pub base: Vec<f64>,
    /// Current scale of each disk (radius = base · scale).
    pub scale: Vec<f64>,
    /// Leading immobile disks.
    pub fixed: usize,
    /// Largest trial displacement (d0 units), adapted towards 30 % acceptance.
    pub step: f64,
    /// Sweeps done.
    pub sweeps: u64,
    seed: u64,
}

/// Outcome of one sweep.
#[derive(Clone, Copy, Debug, Default)]
pub struct SweepStats {
    /// Accepted over tried displacements.
    pub acceptance: f64,
    /// Accepted over tried size exchanges.
    pub swap_acceptance: f64,
    /// Smallest scale of a mobile disk.
    pub min_scale: f64,
    /// Mean scale of the mobile disks.
    pub mean_scale: f64,
}

/// Per-cell tallies.
#[derive(Clone, Copy, Default)]
struct Tally {
    tried: u64,
    moved: u64,
    swaps_tried: u64,
    swapped: u64,
}

impl Tally {
    fn add(self, o: Tally) -> Tally {
        Tally {
            tried: self.tried + o.tried,
            moved: self.moved + o.moved,
            swaps_tried: self.swaps_tried + o.swaps_tried,
            swapped: self.swapped + o.swapped,
        }
    }
}

impl HardDisks {
    /// Disks at the given non-overlapping positions and scales.
    pub fn new(pos: Vec<DVec2>, base: Vec<f64>, scale: Vec<f64>, fixed: usize, seed: u64) -> Self {
        HardDisks {
            pos,
            base,
            scale,
            fixed,
            step: 0.1,
            sweeps: 0,
            seed,
        }
    }

    /// One sweep; mobile disks grow towards `target` by at most the factor `1 + rate`.
    pub fn sweep(&mut self, region: &Region, rate: f64, target: f64) -> SweepStats {
        let r_max = self.base.iter().cloned().fold(0.0, f64::max);
        let mut cell = 2.0 * r_max * target.max(1.0) + 2.0 * self.step + 1e-9;
        let mut srng = rng::stream(
            self.seed,
            self.sweeps.wrapping_mul(0x9e37_79b9_7f4a_7c15) ^ 0xa5a5,
        );
        let (mut lo, mut hi) = region.bounds();
        if let Some(l) = region.period_x() {
            // An even number of columns keeps the checkerboard consistent across the seam.
            let n = (((l / cell).floor() as usize) & !1).max(2);
            cell = l / n as f64 * (1.0 - 1e-12);
        } else {
            lo.x -= cell * (1.0 + srng.random::<f64>());
            hi.x += cell;
        }
        lo.y -= cell * (1.0 + srng.random::<f64>());
        hi.y += cell;
        let grid = CellGrid::build(&self.pos, lo, hi, cell, region.period_x());
        let (nx, ny) = grid.dims();
        // Disks in cell order; `start[c]..start[c + 1]` are cell c's.
        let mut start = Vec::with_capacity(nx * ny + 1);
        let mut disks: Vec<Disk> = Vec::with_capacity(self.pos.len());
        for cy in 0..ny as i64 {
            for cx in 0..nx as i64 {
                start.push(disks.len());
                for &i in grid.cell_items(cx, cy) {
                    let i = i as usize;
                    disks.push(Disk {
                        pos: self.pos[i],
                        base: self.base[i],
                        scale: self.scale[i],
                        id: i as u32,
                        mobile: i >= self.fixed,
                    });
                }
            }
        }
        start.push(disks.len());
        let mut next = disks.clone();
        let mut tally = Tally::default();
        let ctx = Ctx {
            region,
            grid: &grid,
            start: &start,
            step: self.step,
            rate,
            target,
            seed: self.seed,
            sweep: self.sweeps,
        };
        for colour in 0..4usize {
            let (ox, oy) = ((colour & 1) as i64, (colour >> 1) as i64);
            // Disjoint mutable row slices of the rows of this colour.
            let mut rows: Vec<(i64, &mut [Disk])> = Vec::new();
            let mut rest: &mut [Disk] = &mut next;
            let mut offset = 0usize;
            for cy in (oy..ny as i64).step_by(2) {
                let a = start[cy as usize * nx];
                let b = start[(cy as usize + 1) * nx];
                let (_, tail) = rest.split_at_mut(a - offset);
                let (row, tail) = tail.split_at_mut(b - a);
                rows.push((cy, row));
                rest = tail;
                offset = b;
            }
            let read = &disks;
            let t = rows
                .into_par_iter()
                .map(|(cy, row)| ctx.visit_row(read, row, cy, ox))
                .reduce(Tally::default, Tally::add);
            tally = tally.add(t);
            disks.copy_from_slice(&next);
        }
        for d in &disks {
            let i = d.id as usize;
            self.pos[i] = d.pos;
            self.base[i] = d.base;
            self.scale[i] = d.scale;
        }
        let acc = if tally.tried > 0 {
            tally.moved as f64 / tally.tried as f64
        } else {
            0.0
        };
        self.step = (self.step * if acc > ACCEPTANCE { 1.05 } else { 0.95 }).clamp(1e-4, 0.25);
        self.sweeps += 1;
        let mobile = &self.scale[self.fixed..];
        SweepStats {
            acceptance: acc,
            swap_acceptance: if tally.swaps_tried > 0 {
                tally.swapped as f64 / tally.swaps_tried as f64
            } else {
                0.0
            },
            min_scale: mobile.iter().cloned().fold(f64::INFINITY, f64::min),
            mean_scale: mobile.iter().sum::<f64>() / mobile.len().max(1) as f64,
        }
    }
}

/// What every cell visit of one sweep shares.
struct Ctx<'a> {
    region: &'a Region,
    grid: &'a CellGrid,
    start: &'a [usize],
    step: f64,
    rate: f64,
    target: f64,
    seed: u64,
    sweep: u64,
}

impl Ctx<'_> {
    /// Visits the cells of row `cy` whose column has parity `ox`, writing into `row`
    /// (the row's disks in cell order) and reading neighbours from `read`.
    fn visit_row(&self, read: &[Disk], row: &mut [Disk], cy: i64, ox: i64) -> Tally {
        let (nx, _) = self.grid.dims();
        let row_start = self.start[cy as usize * nx];
        let mut near: Vec<Disk> = Vec::with_capacity(64);
        let mut tally = Tally::default();
        for cx in (ox..nx as i64).step_by(2) {
            let c = cy as usize * nx + cx as usize;
            let (a, b) = (self.start[c], self.start[c + 1]);
            if a == b {
                continue;
            }
            // Neighbours: the 3 × 3 block minus the cell itself (other colours: fixed now).
            near.clear();
            for dy in -1..=1i64 {
                for dx in -1..=1i64 {
                    if dx == 0 && dy == 0 {
                        continue;
                    }
                    if let Some((s, e)) = self.cell_range(cx + dx, cy + dy) {
                        near.extend_from_slice(&read[s..e]);
                    }
                }
            }
            let own = &mut row[a - row_start..b - row_start];
            let key = (self.sweep << 32) ^ c as u64;
            let mut rng = rng::stream(self.seed ^ 0x5eed_5eed, key);
            tally = tally.add(self.visit_cell(own, &near, cx, cy, &mut rng));
        }
        tally
    }

    fn cell_range(&self, cx: i64, cy: i64) -> Option<(usize, usize)> {
        let (nx, ny) = self.grid.dims();
        if cy < 0 || cy >= ny as i64 {
            return None;
        }
        let cx = if self.region.period_x().is_some() {
            cx.rem_euclid(nx as i64)
        } else if cx < 0 || cx >= nx as i64 {
            return None;
        } else {
            cx
        };
        let c = cy as usize * nx + cx as usize;
        Some((self.start[c], self.start[c + 1]))
    }

    fn visit_cell(
        &self,
        own: &mut [Disk],
        near: &[Disk],
        cx: i64,
        cy: i64,
        rng: &mut grains_core::rng::Rng,
    ) -> Tally {
        let mut t = Tally::default();
        for k in 0..own.len() {
            if !own[k].mobile {
                continue;
            }
            let d = own[k];
            let a = std::f64::consts::TAU * rng.random::<f64>();
            let q = d.pos + self.step * rng.random::<f64>().sqrt() * DVec2::from_angle(a);
            t.tried += 1;
            if self.grid.coords(q) == (cx, cy) && self.fits(own, near, k, q, d.r()) {
                own[k].pos = q;
                t.moved += 1;
            }
            // Size exchange with another mobile disk of the cell: only the disk that
            // becomes larger can collide, so only it is tested.
            if own.len() > 1 {
                let m = (k + 1 + rng.random_range(0..own.len() - 1)) % own.len();
                if own[m].mobile && own[m].base != own[k].base {
                    t.swaps_tried += 1;
                    let (bk, sk, bm, sm) = (own[k].base, own[k].scale, own[m].base, own[m].scale);
                    own[k].base = bm;
                    own[k].scale = sm;
                    own[m].base = bk;
                    own[m].scale = sk;
                    let grown = if bm * sm > bk * sk { k } else { m };
                    if self.fits(own, near, grown, own[grown].pos, own[grown].r()) {
                        t.swapped += 1;
                    } else {
                        own[k].base = bk;
                        own[k].scale = sk;
                        own[m].base = bm;
                        own[m].scale = sm;
                    }
                }
            }
            // Growth towards the target as far as the nearest surface allows.
            let d = own[k];
            let want = (d.scale * (1.0 + self.rate)).min(self.target);
            if want > d.scale {
                if self.fits(own, near, k, d.pos, d.base * want) {
                    own[k].scale = want;
                } else {
                    let room = self.room(own, near, k, d.pos) / d.base;
                    own[k].scale = want.min(room).max(d.scale);
                }
            }
        }
        t
    }

    /// Whether a disk of radius `r` at `q` clears the walls, the other disks of its
    /// cell (`own`, except `k`) and the neighbours.
    #[inline]
    fn fits(&self, own: &[Disk], near: &[Disk], k: usize, q: DVec2, r: f64) -> bool {
        if self.region.boundary_distance(q) < r {
            return false;
        }
        let clear = |o: &Disk| {
            let s = r + o.r();
            self.region.delta(q, o.pos).length_squared() >= s * s
        };
        own.iter().enumerate().all(|(m, o)| m == k || clear(o)) && near.iter().all(clear)
    }

    /// The largest radius a disk at `q` could have, given the walls, the other disks of
    /// its cell (`own`, except `k`) and the neighbours.
    fn room(&self, own: &[Disk], near: &[Disk], k: usize, q: DVec2) -> f64 {
        let mut room = self.region.boundary_distance(q);
        for (m, o) in own.iter().enumerate() {
            if m != k {
                room = room.min(self.region.delta(q, o.pos).length() - o.r());
            }
        }
        for o in near {
            room = room.min(self.region.delta(q, o.pos).length() - o.r());
        }
        room
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grows_without_overlap_and_keeps_sizes() {
        let region = Region::Rectangle {
            lo: DVec2::ZERO,
            hi: DVec2::new(12.0, 12.0),
            periodic_x: true,
        };
        let mut pos = Vec::new();
        let mut base = Vec::new();
        for j in 0..10 {
            for i in 0..10 {
                pos.push(DVec2::new(0.6 + 1.2 * i as f64, 0.6 + 1.2 * j as f64));
                base.push(0.45 + 0.01 * ((i * 7 + j * 3) % 10) as f64);
            }
        }
        let mut sorted = base.clone();
        let mut hd = HardDisks::new(pos, base, vec![0.9; 100], 0, 5);
        for _ in 0..200 {
            hd.sweep(&region, 1e-3, 1.0);
        }
        for i in 0..100 {
            for j in 0..i {
                let d = region.delta(hd.pos[i], hd.pos[j]).length();
                assert!(d >= hd.base[i] * hd.scale[i] + hd.base[j] * hd.scale[j] - 1e-12);
            }
        }
        let mut after = hd.base.clone();
        sorted.sort_by(f64::total_cmp);
        after.sort_by(f64::total_cmp);
        assert_eq!(sorted, after);
        assert!(hd.scale.iter().all(|&s| s > 0.9));
    }
}
