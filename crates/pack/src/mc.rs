//! Hard-disk Monte Carlo with growth: a Lubachevsky–Stillinger-like compression.
//!
//! Each sweep every mobile disk tries one random displacement and one exchange of size
//! with another disk of its cell, then grows towards the common target scale (radii
//! grow by one factor, so the size distribution is kept) as far as its neighbours
//! allow. The growth rate per sweep is the protocol's rate: it sets how long the disks
//! can rearrange before they jam. From a disordered start, fast growth jams them where
//! they stand (amorphous) and slow growth lets narrow size distributions find
//! close-packed arrangements. From a lattice, fast growth freezes the template and slow
//! growth lets broad distributions, which cannot hold a crystal, lose it. Size
//! exchanges are an equilibrium move (Berthier et al.'s swap Monte Carlo) that leaves
//! the set of sizes unchanged.
//!
//! Parallel and deterministic: each sweep sorts the disks into square cells (grid
//! shifted by a seeded offset) wider than any interaction plus a move, and visits
//! them in four colour classes of a 2 × 2 checkerboard. A disk only moves within its
//! cell, so cells of one colour are independent; rows of one colour are processed in
//! parallel, in place (the rows they read are of the other parity), each cell with its
//! own random stream keyed by (seed, sweep, cell). No result depends on the thread
//! count.
//!
//! Each disk first gathers the few neighbours that can touch it during its visit (those
//! within twice the largest radius plus a step), so its three tests run over about a
//! third of the 3 × 3 block.

use glam::DVec2;
use grains_analysis::grid::CellLayout;
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
    /// The disks, in the cell order of the last sweep.
    disks: Vec<Disk>,
    /// Scratch for re-binning.
    spare: Vec<Disk>,
    keys: Vec<u32>,
    /// Leading immobile disks.
    pub fixed: usize,
    /// Largest trial displacement (d0 units), adapted towards 30 % acceptance.
    pub step: f64,
    /// Sweeps done.
    pub sweeps: u64,
    /// Whether disks try size exchanges (swap Monte Carlo).
    pub swaps: bool,
    seed: u64,
    r_max: f64,
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
    /// Disks at the given non-overlapping centres, final radii `base` and current
    /// scales (radius = base · scale).
    pub fn new(pos: Vec<DVec2>, base: Vec<f64>, scale: Vec<f64>, fixed: usize, seed: u64) -> Self {
        let disks: Vec<Disk> = (0..pos.len())
            .map(|i| Disk {
                pos: pos[i],
                base: base[i],
                scale: scale[i],
                id: i as u32,
                mobile: i >= fixed,
            })
            .collect();
        HardDisks {
            spare: disks.clone(),
            keys: vec![0; disks.len()],
            r_max: base.iter().cloned().fold(0.0, f64::max),
            disks,
            fixed,
            step: 0.1,
            sweeps: 0,
            swaps: true,
            seed,
        }
    }

    /// Centres, final radii and scales, in the order given to [`HardDisks::new`].
    pub fn state(&self) -> (Vec<DVec2>, Vec<f64>, Vec<f64>) {
        let n = self.disks.len();
        let (mut pos, mut base, mut scale) = (vec![DVec2::ZERO; n], vec![0.0; n], vec![0.0; n]);
        for d in &self.disks {
            let i = d.id as usize;
            pos[i] = d.pos;
            base[i] = d.base;
            scale[i] = d.scale;
        }
        (pos, base, scale)
    }

    /// One sweep; mobile disks grow towards `target` by at most the factor `1 + rate`.
    pub fn sweep(&mut self, region: &Region, rate: f64, target: f64) -> SweepStats {
        let r_max = self.r_max;
        let mut cell = 2.0 * r_max * target.max(1.0) + 2.0 * self.step + 1e-9;
        let mut srng = rng::stream(
            self.seed,
            self.sweeps.wrapping_mul(0x9e37_79b9_7f4a_7c15) ^ 0xa5a5,
        );
        let (mut lo, mut hi) = region.bounds();
        let nx = if let Some(l) = region.period_x() {
            // An even number of columns keeps the checkerboard consistent across the seam.
            let n = (((l / cell).floor() as usize) & !1).max(2);
            cell = l / n as f64;
            n
        } else {
            lo.x -= cell * (1.0 + srng.random::<f64>());
            hi.x += cell;
            (((hi.x - lo.x) / cell).ceil() as usize).max(1)
        };
        lo.y -= cell * (1.0 + srng.random::<f64>());
        hi.y += cell;
        let ny = (((hi.y - lo.y) / cell).ceil() as usize).max(1);
        // The sweep's square cells over the shifted box.
        let bins = CellLayout {
            lo,
            cell,
            nx,
            ny,
            periodic_x: region.period_x().is_some(),
        };
        // Re-bin: a stable counting sort of the disks by cell.
        self.disks
            .par_iter()
            .zip(self.keys.par_iter_mut())
            .with_min_len(4096)
            .for_each(|(d, k)| *k = bins.index(d.pos) as u32);
        let mut start = vec![0usize; nx * ny + 1];
        for &k in &self.keys {
            start[k as usize + 1] += 1;
        }
        for c in 0..nx * ny {
            start[c + 1] += start[c];
        }
        let mut fill = start.clone();
        for (d, &k) in self.disks.iter().zip(&self.keys) {
            self.spare[fill[k as usize]] = *d;
            fill[k as usize] += 1;
        }
        std::mem::swap(&mut self.disks, &mut self.spare);

        let mut tally = Tally::default();
        let ctx = Ctx {
            region,
            bins: &bins,
            start: &start,
            step: self.step,
            reach: 2.0 * r_max * target.max(1.0) + self.step + 1e-9,
            rate,
            target,
            swaps: self.swaps,
            seed: self.seed,
            sweep: self.sweeps,
        };
        for colour in 0..4usize {
            let (ox, oy) = (colour & 1, colour >> 1);
            // Rows of this colour's parity are written, the others only read: disjoint
            // slices of one array, so no copy of the state is needed.
            let mut written: Vec<(usize, &mut [Disk])> = Vec::with_capacity(ny / 2 + 1);
            let mut read: Vec<&[Disk]> = Vec::with_capacity(ny);
            let mut rest: &mut [Disk] = &mut self.disks;
            for cy in 0..ny {
                let len = start[(cy + 1) * nx] - start[cy * nx];
                let (row, tail) = rest.split_at_mut(len);
                rest = tail;
                if cy % 2 == oy {
                    written.push((cy, row));
                    read.push(&[]);
                } else {
                    read.push(row);
                }
            }
            let read = &read;
            let t = written
                .into_par_iter()
                .map(|(cy, row)| ctx.visit_row(read, row, cy, ox))
                .reduce(Tally::default, Tally::add);
            tally = tally.add(t);
        }
        let acc = if tally.tried > 0 {
            tally.moved as f64 / tally.tried as f64
        } else {
            0.0
        };
        self.step = (self.step * if acc > ACCEPTANCE { 1.05 } else { 0.95 }).clamp(1e-4, 0.25);
        self.sweeps += 1;
        // Sums over fixed chunks in a fixed order: the same on any thread count.
        let parts: Vec<(f64, f64, usize)> = self
            .disks
            .par_chunks(4096)
            .map(|c| {
                c.iter()
                    .filter(|d| d.mobile)
                    .fold((0.0, f64::INFINITY, 0), |(s, m, n), d| {
                        (s + d.scale, m.min(d.scale), n + 1)
                    })
            })
            .collect();
        let (sum, min, n) = parts
            .into_iter()
            .fold((0.0, f64::INFINITY, 0), |(s, m, n), (a, b, c)| {
                (s + a, m.min(b), n + c)
            });
        SweepStats {
            acceptance: acc,
            swap_acceptance: if tally.swaps_tried > 0 {
                tally.swapped as f64 / tally.swaps_tried as f64
            } else {
                0.0
            },
            min_scale: min,
            mean_scale: sum / n.max(1) as f64,
        }
    }
}

/// A disk that may touch the one being visited: its centre and radius, and its index
/// in the cell when it is a cell-mate (whose size a swap can change).
#[derive(Clone, Copy, Debug, Default)]
struct Cand {
    pos: DVec2,
    r: f64,
    own: u32,
}

const NOT_OWN: u32 = u32::MAX;

/// A uniform random point in the unit disk (rejection from the square: no sin/cos).
#[inline]
fn unit_disk(rng: &mut grains_core::rng::Rng) -> DVec2 {
    loop {
        let p = DVec2::new(
            2.0 * rng.random::<f64>() - 1.0,
            2.0 * rng.random::<f64>() - 1.0,
        );
        if p.length_squared() <= 1.0 {
            return p;
        }
    }
}

/// What every cell visit of one sweep shares.
struct Ctx<'a> {
    region: &'a Region,
    bins: &'a CellLayout,
    start: &'a [usize],
    step: f64,
    /// Largest centre distance at which two disks can touch during one visit.
    reach: f64,
    rate: f64,
    target: f64,
    swaps: bool,
    seed: u64,
    sweep: u64,
}

impl Ctx<'_> {
    /// Visits the cells of row `cy` whose column has parity `ox`, writing into `row`
    /// (the row's disks in cell order) and reading the rows above and below from `read`.
    fn visit_row(&self, read: &[&[Disk]], row: &mut [Disk], cy: usize, ox: usize) -> Tally {
        let (nx, ny) = (self.bins.nx, self.bins.ny);
        let row_start = self.start[cy * nx];
        let mut near: Vec<Disk> = Vec::with_capacity(64);
        let mut cand: Vec<Cand> = Vec::with_capacity(64);
        let mut tally = Tally::default();
        for cx in (ox..nx).step_by(2) {
            let c = cy * nx + cx;
            let (a, b) = (self.start[c], self.start[c + 1]);
            if a == b {
                continue;
            }
            // Neighbours: the 3 × 3 block minus the cell itself (other colours: fixed now).
            near.clear();
            for dy in -1..=1i64 {
                let y = cy as i64 + dy;
                if y < 0 || y >= ny as i64 {
                    continue;
                }
                let y = y as usize;
                let (src, base): (&[Disk], usize) = if y == cy {
                    (row, row_start)
                } else {
                    (read[y], self.start[y * nx])
                };
                for dx in -1..=1i64 {
                    if dx == 0 && dy == 0 {
                        continue;
                    }
                    let x = cx as i64 + dx;
                    let x = if self.bins.periodic_x {
                        x.rem_euclid(nx as i64)
                    } else if x < 0 || x >= nx as i64 {
                        continue;
                    } else {
                        x
                    } as usize;
                    let n = y * nx + x;
                    near.extend_from_slice(&src[self.start[n] - base..self.start[n + 1] - base]);
                }
            }
            let own = &mut row[a - row_start..b - row_start];
            let key = (self.sweep << 32) ^ c as u64;
            let mut rng = rng::stream(self.seed ^ 0x5eed_5eed, key);
            tally =
                tally.add(self.visit_cell(own, &near, cx as i64, cy as i64, &mut rng, &mut cand));
        }
        tally
    }

    fn visit_cell(
        &self,
        own: &mut [Disk],
        near: &[Disk],
        cx: i64,
        cy: i64,
        rng: &mut grains_core::rng::Rng,
        cand_buf: &mut Vec<Cand>,
    ) -> Tally {
        let mut t = Tally::default();
        let reach2 = self.reach * self.reach;
        for k in 0..own.len() {
            if !own[k].mobile {
                continue;
            }
            let d = own[k];
            // Every disk that can touch disk k during its visit, whatever its size or
            // trial position: a third of the block, so each test below is cheap.
            // Filled branch-free: a slot is written for every disk and kept when near.
            let total = own.len() + near.len();
            if cand_buf.len() < total {
                cand_buf.resize(total, Cand::default());
            }
            let mut n = 0;
            for (m, o) in own.iter().enumerate() {
                cand_buf[n] = Cand {
                    pos: o.pos,
                    r: o.r(),
                    own: m as u32,
                };
                let l2 = self.region.delta(d.pos, o.pos).length_squared();
                n += (m != k && l2 < reach2) as usize;
            }
            for o in near {
                cand_buf[n] = Cand {
                    pos: o.pos,
                    r: o.r(),
                    own: NOT_OWN,
                };
                n += (self.region.delta(d.pos, o.pos).length_squared() < reach2) as usize;
            }
            let cand = &mut cand_buf[..n];
            let q = d.pos + self.step * unit_disk(rng);
            t.tried += 1;
            if self.bins.coords(q) == (cx, cy) && self.clear_of(cand, q, d.r()) {
                own[k].pos = q;
                t.moved += 1;
            }
            // Size exchange with another mobile disk of the cell: only the disk that
            // becomes larger can collide, so only it is tested.
            if self.swaps && own.len() > 1 {
                let m = (k + 1 + rng.random_range(0..own.len() - 1)) % own.len();
                if own[m].mobile && own[m].base != own[k].base {
                    t.swaps_tried += 1;
                    let (bk, sk, bm, sm) = (own[k].base, own[k].scale, own[m].base, own[m].scale);
                    let ok = if bm * sm > bk * sk {
                        // Disk k takes m's larger size; m is in k's list only if near.
                        cand.iter().all(|c| {
                            if c.own == m as u32 {
                                let s = bk * sk + bm * sm;
                                self.region.delta(own[k].pos, c.pos).length_squared() >= s * s
                            } else {
                                let s = bm * sm + c.r;
                                self.region.delta(own[k].pos, c.pos).length_squared() >= s * s
                            }
                        }) && self.region.boundary_distance(own[k].pos) >= bm * sm
                    } else {
                        // Disk m takes k's larger size (and k shrinks): test m.
                        own[k].base = bm;
                        own[k].scale = sm;
                        own[m].base = bk;
                        own[m].scale = sk;
                        let fit = self.fits(own, near, m, own[m].pos, bk * sk);
                        own[k].base = bk;
                        own[k].scale = sk;
                        own[m].base = bm;
                        own[m].scale = sm;
                        fit
                    };
                    if ok {
                        t.swapped += 1;
                        own[k].base = bm;
                        own[k].scale = sm;
                        own[m].base = bk;
                        own[m].scale = sk;
                        if let Some(c) = cand.iter_mut().find(|c| c.own == m as u32) {
                            c.r = bk * sk;
                        }
                    }
                }
            }
            // Growth towards the target as far as the nearest surface allows.
            let d = own[k];
            let want = (d.scale * (1.0 + self.rate)).min(self.target);
            if want > d.scale {
                let r_want = d.base * want;
                let mut room = self.region.boundary_distance(d.pos);
                for c in cand.iter() {
                    let s = r_want + c.r;
                    let l2 = self.region.delta(d.pos, c.pos).length_squared();
                    if l2 < s * s {
                        room = room.min(l2.sqrt() - c.r);
                    }
                }
                own[k].scale = want.min(room / d.base).max(d.scale);
            }
        }
        t
    }

    /// Whether a disk of radius `r` at `q` clears the walls and the candidates.
    #[inline]
    fn clear_of(&self, cand: &[Cand], q: DVec2, r: f64) -> bool {
        self.region.boundary_distance(q) >= r
            && cand.iter().all(|c| {
                let s = r + c.r;
                self.region.delta(q, c.pos).length_squared() >= s * s
            })
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
        let (pos, base, scale) = hd.state();
        for i in 0..100 {
            for j in 0..i {
                let d = region.delta(pos[i], pos[j]).length();
                assert!(d >= base[i] * scale[i] + base[j] * scale[j] - 1e-12);
            }
        }
        let mut after = base.clone();
        sorted.sort_by(f64::total_cmp);
        after.sort_by(f64::total_cmp);
        assert_eq!(sorted, after);
        assert!(scale.iter().all(|&s| s > 0.9));
    }
}
