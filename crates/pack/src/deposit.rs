//! Deposition under gravity (−y): disks arrive one at a time and come to rest in the
//! lowest free pocket of the whole surface, resting on two disks below with its centre
//! between theirs (the infinitely slow pouring limit). A pocket takes the first of the
//! next few drawn disks that fits it, as fine grains percolate into holes. This gives
//! a dense, overlap-free, uniformly filled start for the Monte Carlo growth.
//!
//! Sequential by nature; every choice follows from the seeded size sequence, so the
//! result does not depend on the thread count.

use glam::DVec2;
use grains_analysis::region::Region;
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// Upcoming disks a pocket may choose from: a tight pocket takes a smaller disk, as
/// fine grains percolate into holes when poured.
const LOOKAHEAD: usize = 32;
/// Relative slack for "not overlapping" (rounding in the pocket geometry).
const TOUCH: f64 = 1e-9;

/// Disks in a linked-cell grid that grows as disks are placed.
struct Bed {
    pos: Vec<DVec2>,
    rad: Vec<f64>,
    head: Vec<u32>,
    next: Vec<u32>,
    lo: DVec2,
    cell: f64,
    nx: i64,
    ny: i64,
    period: Option<f64>,
}

const NONE: u32 = u32::MAX;

impl Bed {
    fn new(region: &Region, cell: f64) -> Self {
        let (lo, hi) = region.bounds();
        let period = region.period_x();
        let nx = match period {
            Some(l) => ((l / cell).floor() as i64).max(1),
            None => ((hi.x - lo.x) / cell).ceil() as i64 + 1,
        };
        let cell = match period {
            Some(l) => l / nx as f64,
            None => cell,
        }
        .max(cell);
        let ny = ((hi.y - lo.y) / cell).ceil() as i64 + 1;
        Bed {
            pos: Vec::new(),
            rad: Vec::new(),
            head: vec![NONE; (nx * ny) as usize],
            next: Vec::new(),
            lo,
            cell,
            nx,
            ny,
            period,
        }
    }

    fn coords(&self, p: DVec2) -> (i64, i64) {
        let cx = ((p.x - self.lo.x) / self.cell).floor() as i64;
        let cy = ((p.y - self.lo.y) / self.cell).floor() as i64;
        let cx = if self.period.is_some() {
            cx.rem_euclid(self.nx)
        } else {
            cx.clamp(0, self.nx - 1)
        };
        (cx, cy.clamp(0, self.ny - 1))
    }

    fn delta(&self, a: DVec2, b: DVec2) -> DVec2 {
        let mut d = b - a;
        if let Some(l) = self.period {
            d.x -= l * (d.x / l).round();
        }
        d
    }

    fn push(&mut self, p: DVec2, r: f64) -> u32 {
        let k = self.pos.len() as u32;
        let (cx, cy) = self.coords(p);
        let c = (cy * self.nx + cx) as usize;
        self.pos.push(p);
        self.rad.push(r);
        self.next.push(self.head[c]);
        self.head[c] = k;
        k
    }

    /// Calls `f(j)` for every disk in the `(2 reach + 1)²` cells around `p`.
    fn near(&self, p: DVec2, reach: i64, mut f: impl FnMut(u32)) {
        let (cx, cy) = self.coords(p);
        let span = if self.period.is_some() {
            (2 * reach + 1).min(self.nx)
        } else {
            2 * reach + 1
        };
        for y in (cy - reach)..=(cy + reach) {
            if y < 0 || y >= self.ny {
                continue;
            }
            for k in 0..span {
                let mut x = cx - reach + k;
                if self.period.is_some() {
                    x = x.rem_euclid(self.nx);
                } else if x < 0 || x >= self.nx {
                    continue;
                }
                let mut j = self.head[(y * self.nx + x) as usize];
                while j != NONE {
                    f(j);
                    j = self.next[j as usize];
                }
            }
        }
    }

    /// The upper pocket for a disk of radius `r` resting on disks `i` and `j`, if it
    /// exists and is stable (its centre lies horizontally between theirs).
    fn pocket(&self, i: u32, j: u32, r: f64) -> Option<DVec2> {
        let ci = self.pos[i as usize];
        let dij = self.delta(ci, self.pos[j as usize]);
        let (ri, rj) = (self.rad[i as usize] + r, self.rad[j as usize] + r);
        let d = dij.length();
        if d > ri + rj || d < (ri - rj).abs() || d == 0.0 {
            return None;
        }
        let u = dij / d;
        let a = (ri * ri - rj * rj + d * d) / (2.0 * d);
        let h = (ri * ri - a * a).max(0.0).sqrt();
        let perp = DVec2::new(-u.y, u.x);
        let base = a * u;
        let p = if perp.y >= 0.0 {
            base + h * perp
        } else {
            base - h * perp
        };
        let (x0, x1) = if dij.x >= 0.0 {
            (0.0, dij.x)
        } else {
            (dij.x, 0.0)
        };
        (p.x > x0 && p.x < x1).then_some(ci + p)
    }

    /// Whether a disk (`p`, `r`) fits: inside the region and clear of every disk.
    fn fits(&self, region: &Region, p: DVec2, r: f64) -> bool {
        if region.boundary_distance(p) < r * (1.0 - TOUCH) {
            return false;
        }
        let mut ok = true;
        self.near(p, 1, |m| {
            if ok {
                let d = self.delta(p, self.pos[m as usize]).length();
                ok = d >= (r + self.rad[m as usize]) * (1.0 - TOUCH);
            }
        });
        ok
    }
}

/// A candidate pocket: height (at the reference radius) and its two supports.
type Candidate = Reverse<(Key, u32, u32)>;

/// f64 ordered by `total_cmp`, for the heap.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Key(f64);
impl Eq for Key {}
impl PartialOrd for Key {
    fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Key {
    fn cmp(&self, o: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&o.0)
    }
}

/// What deposition produced.
pub struct Deposit {
    /// Bulk disk centres, in placement order.
    pub pos: Vec<DVec2>,
    /// Their radii.
    pub radius: Vec<f64>,
}

/// Deposits disks of radii `radii` (in about that order, until they run out or no
/// pocket is left) onto the fixed `support` disks (the lining) inside `region`.
pub fn deposit(region: &Region, support: &[(DVec2, f64)], radii: &[f64]) -> Deposit {
    let r_max = radii
        .iter()
        .cloned()
        .fold(0.0, f64::max)
        .max(support.iter().map(|s| s.1).fold(0.0, f64::max));
    let r_ref = radii.iter().sum::<f64>() / radii.len().max(1) as f64;
    let mut bed = Bed::new(region, 2.0 * r_max * (1.0 + 1e-6));
    for &(c, r) in support {
        bed.push(c, r);
    }
    let mut heap: BinaryHeap<Candidate> = BinaryHeap::new();
    let candidates = |bed: &Bed, k: u32, heap: &mut BinaryHeap<Candidate>| {
        let ck = bed.pos[k as usize];
        bed.near(ck, 2, |m| {
            if m == k {
                return;
            }
            let reach = bed.rad[k as usize] + bed.rad[m as usize];
            let d = bed.delta(ck, bed.pos[m as usize]).length();
            if d > reach + 2.0 * r_max {
                return;
            }
            // The pocket at the reference size, or at the smallest size that spans the gap.
            let r = r_ref.max(0.5 * (d - reach) * (1.0 + 1e-9));
            if let Some(p) = bed.pocket(k, m, r) {
                heap.push(Reverse((Key(p.y), k.min(m), k.max(m))));
            }
        });
    };
    for k in 0..support.len() as u32 {
        candidates(&bed, k, &mut heap);
    }
    let first_bulk = support.len();
    // The upcoming disks, in drawing order; the lowest pocket takes the first that fits.
    let mut window: Vec<f64> = Vec::with_capacity(LOOKAHEAD);
    let mut drawn = 0usize;
    loop {
        while window.len() < LOOKAHEAD && drawn < radii.len() {
            window.push(radii[drawn]);
            drawn += 1;
        }
        if window.is_empty() {
            break;
        }
        let Some(Reverse((_, i, j))) = heap.pop() else {
            break;
        };
        let Some(w) = take(&bed, region, i, j, &window) else {
            continue;
        };
        let r = window.remove(w);
        let p = bed.pocket(i, j, r).expect("checked by take");
        let k = bed.push(wrap(region, p), r);
        candidates(&bed, k, &mut heap);
    }
    Deposit {
        pos: bed.pos[first_bulk..].to_vec(),
        radius: bed.rad[first_bulk..].to_vec(),
    }
}

/// Index in `window` of the first disk that rests stably in pocket `(i, j)` without
/// overlapping anything.
fn take(bed: &Bed, region: &Region, i: u32, j: u32, window: &[f64]) -> Option<usize> {
    window
        .iter()
        .position(|&r| bed.pocket(i, j, r).is_some_and(|p| bed.fits(region, p, r)))
}

fn wrap(region: &Region, mut p: DVec2) -> DVec2 {
    if let (Some(l), Region::Rectangle { lo, .. }) = (region.period_x(), region) {
        p.x = lo.x + (p.x - lo.x).rem_euclid(l);
    }
    p
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_disks_on_a_flat_floor_stack_in_rows() {
        let region = Region::Rectangle {
            lo: DVec2::ZERO,
            hi: DVec2::new(20.0, 8.0),
            periodic_x: true,
        };
        let floor: Vec<(DVec2, f64)> = (0..20)
            .map(|k| (DVec2::new(k as f64 + 0.5, 0.5), 0.5))
            .collect();
        let radii = vec![0.5; 200];
        let d = deposit(&region, &floor, &radii);
        // A close-packed stack: rows √3/2 apart, 20 per row, nothing overlapping.
        assert!(d.pos.len() >= 120, "{}", d.pos.len());
        let row_h = 3f64.sqrt() / 2.0;
        for p in &d.pos {
            let rows = (p.y - 0.5) / row_h;
            assert!((rows - rows.round()).abs() < 1e-6, "{p}");
        }
    }
}
