//! Soft-disk energy minimisation (FIRE, Bitzek et al. 2006) of harmonic overlaps,
//! U = ½ Σ δ_ij² (+ the same for wall overlaps), in units where d0 = 1 and the
//! stiffness is 1.
//!
//! Deterministic for any thread count: forces are gathered per particle from a full
//! neighbour list (no scattered writes), and every global sum is taken over fixed
//! chunks whose partial results are added in chunk order.

use glam::DVec2;
use grains_analysis::grid::CellGrid;
use grains_analysis::region::Region;
use rayon::prelude::*;

/// Particles per parallel work item; fixed so that sums do not depend on threads.
const CHUNK: usize = 4096;
/// Verlet skin (in d0).
const SKIN: f64 = 0.3;

/// FIRE constants (Bitzek et al. 2006).
const DT_START: f64 = 0.05;
const DT_MAX: f64 = 0.2;
const N_MIN: u32 = 5;
const F_INC: f64 = 1.1;
const F_DEC: f64 = 0.5;
const ALPHA_START: f64 = 0.1;
const F_ALPHA: f64 = 0.99;

/// Soft disks being relaxed; the first `fixed` never move (the lining).
pub struct Soft {
    /// Centres (d0 units).
    pub pos: Vec<DVec2>,
    /// Radii (d0 units).
    pub rad: Vec<f64>,
    /// Number of leading immobile disks.
    pub fixed: usize,
    vel: Vec<DVec2>,
    force: Vec<DVec2>,
    start: Vec<u32>,
    list: Vec<u32>,
    built_pos: Vec<DVec2>,
    built_rad: Vec<f64>,
    /// Neighbour-list builds so far.
    pub builds: u64,
    /// Force evaluations so far.
    pub evaluations: u64,
}

/// How a minimisation ended.
#[derive(Clone, Copy, Debug, Default)]
pub struct MinResult {
    /// Iterations taken.
    pub iterations: u64,
    /// Largest force on a mobile disk at the end.
    pub max_force: f64,
    /// Largest pair or wall overlap at the end.
    pub max_overlap: f64,
    /// Energy per mobile disk.
    pub energy: f64,
}

/// Per-chunk partial sums.
#[derive(Clone, Copy, Default)]
struct Sums {
    power: f64,
    v2: f64,
    f2: f64,
    fmax: f64,
    energy: f64,
    overlap: f64,
}

impl Sums {
    fn add(self, o: Sums) -> Sums {
        Sums {
            power: self.power + o.power,
            v2: self.v2 + o.v2,
            f2: self.f2 + o.f2,
            fmax: self.fmax.max(o.fmax),
            energy: self.energy + o.energy,
            overlap: self.overlap.max(o.overlap),
        }
    }
}

impl Soft {
    /// Disks at rest.
    pub fn new(pos: Vec<DVec2>, rad: Vec<f64>, fixed: usize) -> Self {
        let n = pos.len();
        Soft {
            pos,
            rad,
            fixed,
            vel: vec![DVec2::ZERO; n],
            force: vec![DVec2::ZERO; n],
            start: Vec::new(),
            list: Vec::new(),
            built_pos: Vec::new(),
            built_rad: Vec::new(),
            builds: 0,
            evaluations: 0,
        }
    }

    fn build(&mut self, region: &Region) {
        let r_max = self.rad.iter().cloned().fold(0.0, f64::max);
        let (mut lo, mut hi) = region.bounds();
        for p in &self.pos {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        let grid = CellGrid::build(&self.pos, lo, hi, 2.0 * r_max + SKIN, region.period_x());
        let (pos, rad) = (&self.pos, &self.rad);
        let lists: Vec<Vec<u32>> = (0..pos.len())
            .into_par_iter()
            .with_min_len(CHUNK)
            .map(|i| {
                let mut v = Vec::with_capacity(12);
                grid.for_each_near(pos[i], 1, |j| {
                    if j as usize != i
                        && region.delta(pos[i], pos[j as usize]).length()
                            < rad[i] + rad[j as usize] + SKIN
                    {
                        v.push(j);
                    }
                });
                v.sort_unstable();
                v
            })
            .collect();
        self.start.clear();
        self.list.clear();
        self.start.push(0);
        for v in lists {
            self.list.extend_from_slice(&v);
            self.start.push(self.list.len() as u32);
        }
        self.built_pos = self.pos.clone();
        self.built_rad = self.rad.clone();
        self.builds += 1;
    }

    /// Whether motion or growth since the last build could bring an unlisted pair into contact.
    fn stale(&self) -> bool {
        if self.built_pos.len() != self.pos.len() {
            return true;
        }
        let (moved, grew) = self
            .pos
            .par_chunks(CHUNK)
            .zip(self.built_pos.par_chunks(CHUNK))
            .zip(
                self.rad
                    .par_chunks(CHUNK)
                    .zip(self.built_rad.par_chunks(CHUNK)),
            )
            .map(|((p, b), (r, rb))| {
                let m = p
                    .iter()
                    .zip(b)
                    .map(|(x, y)| (*x - *y).length_squared())
                    .fold(0.0, f64::max);
                let g = r.iter().zip(rb).map(|(x, y)| x - y).fold(0.0, f64::max);
                (m, g)
            })
            .reduce(|| (0.0, 0.0), |a, b| (a.0.max(b.0), a.1.max(b.1)));
        2.0 * moved.sqrt() + 2.0 * grew > SKIN
    }

    /// Forces into `self.force`, with per-chunk sums (power and norms use `vel`).
    fn forces(&mut self, region: &Region) -> Sums {
        if self.stale() {
            self.build(region);
        }
        self.evaluations += 1;
        let (pos, rad, start, list, vel, fixed) = (
            &self.pos,
            &self.rad,
            &self.start,
            &self.list,
            &self.vel,
            self.fixed,
        );
        let parts: Vec<Sums> = self
            .force
            .par_chunks_mut(CHUNK)
            .enumerate()
            .map(|(c, out)| {
                let mut s = Sums::default();
                for (k, f_out) in out.iter_mut().enumerate() {
                    let i = c * CHUNK + k;
                    let (pi, ri) = (pos[i], rad[i]);
                    let mut f = DVec2::ZERO;
                    for &j in &list[start[i] as usize..start[i + 1] as usize] {
                        let d = region.delta(pi, pos[j as usize]);
                        let reach = ri + rad[j as usize];
                        // Most listed pairs are apart: test before the square root.
                        let d2 = d.length_squared();
                        if d2 >= reach * reach {
                            continue;
                        }
                        let dist = d2.sqrt();
                        let ov = reach - dist;
                        if ov > 0.0 && dist > 0.0 {
                            f -= d * (ov / dist);
                            s.energy += 0.25 * ov * ov;
                            s.overlap = s.overlap.max(ov);
                        }
                    }
                    let (ov, normal) = wall(region, pi, ri);
                    if ov > 0.0 {
                        f += ov * normal;
                        s.energy += 0.5 * ov * ov;
                        s.overlap = s.overlap.max(ov);
                    }
                    if i < fixed {
                        f = DVec2::ZERO;
                    }
                    *f_out = f;
                    s.power += f.dot(vel[i]);
                    s.v2 += vel[i].length_squared();
                    s.f2 += f.length_squared();
                    s.fmax = s.fmax.max(f.length_squared());
                }
                s
            })
            .collect();
        let mut total = parts.into_iter().fold(Sums::default(), Sums::add);
        total.fmax = total.fmax.sqrt();
        total
    }

    /// Minimises until the largest force is below `ftol` or `max_iter` iterations.
    pub fn minimise(&mut self, region: &Region, ftol: f64, max_iter: u64) -> MinResult {
        self.vel.iter_mut().for_each(|v| *v = DVec2::ZERO);
        let (mut dt, mut alpha, mut positive) = (DT_START, ALPHA_START, 0u32);
        let mut sums = self.forces(region);
        let mut it = 0;
        while it < max_iter && sums.fmax > ftol {
            it += 1;
            if sums.power > 0.0 {
                let scale = if sums.f2 > 0.0 {
                    alpha * (sums.v2 / sums.f2).sqrt()
                } else {
                    0.0
                };
                mix(&mut self.vel, &self.force, 1.0 - alpha, scale);
                positive += 1;
                if positive > N_MIN {
                    dt = (dt * F_INC).min(DT_MAX);
                    alpha *= F_ALPHA;
                }
            } else {
                positive = 0;
                dt *= F_DEC;
                alpha = ALPHA_START;
                self.vel.par_iter_mut().for_each(|v| *v = DVec2::ZERO);
            }
            // Semi-implicit Euler with unit masses.
            let (force, fixed) = (&self.force, self.fixed);
            self.vel
                .par_chunks_mut(CHUNK)
                .zip(self.pos.par_chunks_mut(CHUNK))
                .enumerate()
                .for_each(|(c, (v, p))| {
                    for k in 0..v.len() {
                        let i = c * CHUNK + k;
                        if i >= fixed {
                            v[k] += dt * force[i];
                            p[k] += dt * v[k];
                        }
                    }
                });
            sums = self.forces(region);
        }
        let mobile = (self.pos.len() - self.fixed).max(1) as f64;
        MinResult {
            iterations: it,
            max_force: sums.fmax,
            max_overlap: sums.overlap,
            energy: sums.energy / mobile,
        }
    }
}

fn mix(vel: &mut [DVec2], force: &[DVec2], keep: f64, scale: f64) {
    vel.par_chunks_mut(CHUNK)
        .zip(force.par_chunks(CHUNK))
        .for_each(|(v, f)| {
            for (v, f) in v.iter_mut().zip(f) {
                *v = keep * *v + scale * *f;
            }
        });
}

/// Overlap of a disk with the nearest wall and the wall's inward normal.
fn wall(region: &Region, p: DVec2, r: f64) -> (f64, DVec2) {
    match *region {
        Region::Annulus {
            centre,
            r_in,
            r_out,
        } => {
            let d = p - centre;
            let len = d.length().max(1e-300);
            let radial = d / len;
            if len - r_in < r_out - len {
                (r - (len - r_in), radial)
            } else {
                (r - (r_out - len), -radial)
            }
        }
        Region::Disk { centre, radius } => {
            let d = p - centre;
            let len = d.length().max(1e-300);
            (r - (radius - len), -d / len)
        }
        Region::Rectangle { lo, hi, periodic_x } => {
            let mut best = (p.y - lo.y, DVec2::Y);
            if hi.y - p.y < best.0 {
                best = (hi.y - p.y, -DVec2::Y);
            }
            if !periodic_x {
                if p.x - lo.x < best.0 {
                    best = (p.x - lo.x, DVec2::X);
                }
                if hi.x - p.x < best.0 {
                    best = (hi.x - p.x, -DVec2::X);
                }
            }
            (r - best.0, best.1)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pushes_overlapping_pair_apart() {
        let region = Region::Rectangle {
            lo: DVec2::ZERO,
            hi: DVec2::new(10.0, 10.0),
            periodic_x: false,
        };
        let mut s = Soft::new(
            vec![DVec2::new(5.0, 5.0), DVec2::new(5.6, 5.0)],
            vec![0.5, 0.5],
            0,
        );
        let r = s.minimise(&region, 1e-10, 10_000);
        assert!(r.max_force <= 1e-10, "{r:?}");
        assert!((s.pos[1] - s.pos[0]).length() >= 1.0 - 1e-9);
    }
}
