//! Read-only measurements of a state: energies, momentum, contacts, overlaps.
//! Nothing here changes the run (contact history included).

use crate::comm::{Reduce, Serial};
use crate::exact::ExactSums;
use crate::law::ContactLaw;
use crate::math::{AngVector, Components, Tangent, TangentOps, Vector, DIM};
use crate::particles::Particles;
use crate::setup::Setup;
use crate::step::State;
use crate::CHUNK;
use rayon::prelude::*;

/// Global figures of one state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Diagnostics {
    /// Translational kinetic energy (J per unit thickness).
    pub kinetic_translational: f64,
    /// Rotational kinetic energy.
    pub kinetic_rotational: f64,
    /// Gravitational potential energy −m g·x (zero at the origin).
    pub potential: f64,
    /// Elastic energy stored in contact springs (normal and tangential, walls included).
    pub elastic: f64,
    /// Total linear momentum.
    pub momentum: Vector,
    /// Number of touching particle pairs.
    pub pair_contacts: usize,
    /// Number of touching particle–wall pairs.
    pub wall_contacts: usize,
    /// Largest overlap divided by the smaller radius of the pair.
    pub max_overlap_ratio: f64,
    /// Whether every position and velocity is finite.
    pub finite: bool,
}

impl Diagnostics {
    /// Kinetic energy, translational plus rotational.
    pub fn kinetic(&self) -> f64 {
        self.kinetic_translational + self.kinetic_rotational
    }

    /// Kinetic + potential + elastic.
    pub fn total(&self) -> f64 {
        self.kinetic() + self.potential + self.elastic
    }

    /// Mean number of contacts per particle (each pair counts for both, walls for one).
    pub fn mean_coordination(&self, n: usize) -> f64 {
        if n == 0 {
            return 0.0;
        }
        (2 * self.pair_contacts + self.wall_contacts) as f64 / n as f64
    }
}

/// Measures a state. Each particle's terms (its pairs with higher ids and its walls
/// counted with it) are added exactly and rounded once, so the figures depend neither
/// on the thread count nor on where the particles are stored, on one rank or several.
pub fn measure(setup: &Setup, s: &State) -> Diagnostics {
    measure_on(setup, s, &Serial)
}

/// [`measure`] of a state spread over ranks, every stored particle counted.
pub fn measure_on<R: Reduce + ?Sized>(setup: &Setup, s: &State, reduce: &R) -> Diagnostics {
    measure_where(setup, s, reduce, |_| true)
}

/// The summed terms of one particle: translational and rotational kinetic, potential
/// and elastic energy, then momentum.
const TERMS: usize = 4 + DIM;

/// [`measure_on`] of a rank that `owns` some of the particles it stores (by index; the
/// others are copies of another rank's, as in [`crate::decomp`]): its own particles'
/// terms and wall contacts, and each touching pair once, with the particle of the lower
/// id on the rank that owns it. The terms are added exactly ([`ExactSums`]) and rounded
/// once (docs/parallel.md, rule 2): the figures are the same bit for bit whatever the
/// storage order, thread count or rank count, and ranks exchange a fixed number of words
/// whatever their particle count.
pub fn measure_where<R: Reduce + ?Sized>(
    setup: &Setup,
    s: &State,
    reduce: &R,
    owns: impl Fn(usize) -> bool + Sync,
) -> Diagnostics {
    let (mut d, sums) = measure_here(setup, s, &owns);
    if reduce.ranks() > 1 {
        let mut counts = [
            d.pair_contacts as u64,
            d.wall_contacts as u64,
            !d.finite as u64,
        ];
        reduce.sum_u64(&mut counts);
        let mut worst = [d.max_overlap_ratio];
        reduce.max(&mut worst);
        d.pair_contacts = counts[0] as usize;
        d.wall_contacts = counts[1] as usize;
        d.finite = counts[2] == 0;
        d.max_overlap_ratio = worst[0];
    }
    let sum = sums.total(reduce);
    d.kinetic_translational = sum[0];
    d.kinetic_rotational = sum[1];
    d.potential = sum[2];
    d.elastic = sum[3];
    d.momentum = Vector::from_slice(&sum[4..]);
    d
}

/// This rank's counts and extremes, and the exact sums of the terms of the particles
/// it owns. Each chunk adds its particles' terms as it makes them: no array of every
/// particle's terms is kept (56 bytes a sphere at the peak of a run), and as the sums
/// are exact, the order they are added in does not matter.
fn measure_here(
    setup: &Setup,
    s: &State,
    owns: &(impl Fn(usize) -> bool + Sync),
) -> (Diagnostics, ExactSums<TERMS>) {
    let p = &s.particles;
    let list = &s.contacts;
    let n = p.len();
    let parts: Vec<(Diagnostics, ExactSums<TERMS>)> = (0..n.div_ceil(CHUNK))
        .into_par_iter()
        .map(|c| {
            let mut d = Diagnostics {
                finite: true,
                ..Default::default()
            };
            let mut sum = ExactSums::<TERMS>::default();
            for i in c * CHUNK..((c + 1) * CHUNK).min(n) {
                let mut t = [0.0; TERMS];
                let mine = owns(i);
                // This particle's figures alone, then its pairs' and walls' energy.
                let mut e = Diagnostics::default();
                if mine {
                    let m = p.mass(i);
                    let v = p.vel[i];
                    e.kinetic_translational = 0.5 * m * v.length_squared();
                    e.kinetic_rotational =
                        0.5 * TangentOps::dot(p.omega[i], p.omega[i]) / p.inv_inertia[i];
                    e.potential = -m * setup.gravity.dot(p.pos[i]);
                    e.momentum = m * v;
                    d.finite &= p.pos[i].is_finite() && v.is_finite() && p.omega[i].finite();
                }
                let mi = p.material[i] as usize;
                for e_ in list.row[i] as usize..list.row[i + 1] as usize {
                    let j = list.nbr[e_] as usize;
                    // A pair across ranks is stored on both: its lower id's owner counts it.
                    if !owns(if p.id[i] < p.id[j] { i } else { j }) {
                        continue;
                    }
                    let dist = setup.domain.min_image(p.pos[j] - p.pos[i]).length();
                    let overlap = p.radius[i] + p.radius[j] - dist;
                    if overlap > 0.0 {
                        let mj = p.material[j] as usize;
                        let (ri, rj) = (p.radius[i], p.radius[j]);
                        let r_eff = ri * rj / (ri + rj);
                        e.elastic += match &setup.granular {
                            Some(t) => t.get(mi, mj).stored_energy(
                                overlap,
                                r_eff,
                                &list.granular(e_).unwrap_or_default(),
                            ),
                            None => setup.pairs.get(mi, mj).stored_energy(
                                overlap,
                                r_eff,
                                &list.shear[e_],
                            ),
                        };
                        d.pair_contacts += 1;
                        let rmin = p.radius[i].min(p.radius[j]);
                        d.max_overlap_ratio = d.max_overlap_ratio.max(overlap / rmin);
                    }
                }
                if mine {
                    wall_terms(setup, s, i, &mut e);
                    d.wall_contacts += e.wall_contacts;
                    d.max_overlap_ratio = d.max_overlap_ratio.max(e.max_overlap_ratio);
                }
                t[0] = e.kinetic_translational;
                t[1] = e.kinetic_rotational;
                t[2] = e.potential;
                t[3] = e.elastic;
                for a in 0..DIM {
                    t[4 + a] = e.momentum.get(a);
                }
                if mine {
                    sum.add(&t);
                }
            }
            (d, sum)
        })
        .collect();
    let mut total = Diagnostics {
        finite: true,
        ..Default::default()
    };
    let mut sums = ExactSums::<TERMS>::default();
    for (d, part) in parts {
        total.pair_contacts += d.pair_contacts;
        total.wall_contacts += d.wall_contacts;
        total.max_overlap_ratio = total.max_overlap_ratio.max(d.max_overlap_ratio);
        total.finite &= d.finite;
        sums.merge(&part);
    }
    (total, sums)
}

fn wall_terms(setup: &Setup, s: &State, i: usize, d: &mut Diagnostics) {
    let p = &s.particles;
    let nw = setup.walls.len();
    for (w, wall) in setup.walls.iter().enumerate() {
        let Some(t) = wall.shape.nearest(p.pos[i]) else {
            continue;
        };
        let overlap = p.radius[i] - t.distance;
        if overlap > 0.0 {
            let mi = p.material[i] as usize;
            let (c, k) = (&s.contacts, i * nw + w);
            let wm = wall.material.map_or(mi, |m| m as usize);
            // A wall is flat: R_eff is the particle's radius.
            let r = p.radius[i];
            d.elastic += match &setup.granular {
                Some(t) => {
                    let h = c.wall_history.try_get(k).unwrap_or_default();
                    t.get(mi, wm).stored_energy(overlap, r, &h)
                }
                None => {
                    let xi = c.wall_shear.get(k).copied().unwrap_or_default();
                    setup.pairs.get(mi, wm).stored_energy(overlap, r, &xi)
                }
            };
            d.wall_contacts += 1;
            d.max_overlap_ratio = d.max_overlap_ratio.max(overlap / p.radius[i]);
        }
    }
}

/// Contacts per particle (pairs and walls), in the current particle order.
pub fn contact_counts(setup: &Setup, s: &State) -> Vec<u32> {
    let p: &Particles = &s.particles;
    let list = &s.contacts;
    let mut count = vec![0u32; p.len()];
    for i in 0..p.len() {
        for e in list.row[i] as usize..list.row[i + 1] as usize {
            let j = list.nbr[e] as usize;
            let dist = setup.domain.min_image(p.pos[j] - p.pos[i]).length();
            if p.radius[i] + p.radius[j] > dist {
                count[i] += 1;
                count[j] += 1;
            }
        }
        for wall in &setup.walls {
            if wall
                .shape
                .nearest(p.pos[i])
                .is_some_and(|t| t.distance < p.radius[i])
            {
                count[i] += 1;
            }
        }
    }
    count
}

/// The most overlapping pair of listed particles: (id, id, overlap over the smaller
/// radius), or `None` when no two touch. Coincident centres give an infinite ratio.
pub fn deepest_overlap(setup: &Setup, s: &State) -> Option<(u32, u32, f64)> {
    let p = &s.particles;
    let list = &s.contacts;
    let mut worst: Option<(u32, u32, f64)> = None;
    for i in 0..p.len() {
        for e in list.row[i] as usize..list.row[i + 1] as usize {
            let j = list.nbr[e] as usize;
            let dist = setup.domain.min_image(p.pos[j] - p.pos[i]).length();
            let overlap = p.radius[i] + p.radius[j] - dist;
            let ratio = if dist == 0.0 {
                f64::INFINITY
            } else {
                overlap / p.radius[i].min(p.radius[j])
            };
            if overlap > 0.0 && worst.is_none_or(|w| ratio > w.2) {
                worst = Some((p.id[i], p.id[j], ratio));
            }
        }
    }
    worst
}

/// Mean contact stress of each particle (Pa per unit thickness): the elastic normal
/// forces K_n·overlap of its pair contacts (through the neighbour list), plus `extra`
/// (outside pushes, N/m), over its perimeter 2πr — the trace of Love's average over
/// the disk. Each particle's forces are added in the order of its partners' ids (its
/// row, then the reverse index: rule 1 of docs/parallel.md), so a particle's pressure
/// is the same whatever the storage order, and on a rank of several for every
/// particle it owns.
pub fn contact_pressure(setup: &Setup, s: &State, extra: &[f64]) -> Vec<f64> {
    let p = &s.particles;
    let list = &s.contacts;
    let n = p.len();
    let mut sum: Vec<f64> = extra.to_vec();
    sum.resize(n, 0.0);
    let force = |e: usize| {
        let (i, j) = (list.owner[e] as usize, list.nbr[e] as usize);
        let dist = setup.domain.min_image(p.pos[j] - p.pos[i]).length();
        let overlap = p.radius[i] + p.radius[j] - dist;
        (overlap > 0.0).then(|| {
            setup
                .pairs
                .get(p.material[i] as usize, p.material[j] as usize)
                .kn
                * overlap
        })
    };
    let indexed = list.row.len() == n + 1
        && list.rev_row.len() == n + 1
        && list.owner.len() == list.nbr.len();
    if indexed {
        for (i, total) in sum.iter_mut().enumerate() {
            let row = list.row[i] as usize..list.row[i + 1] as usize;
            let rev = &list.rev_entry[list.rev_row[i] as usize..list.rev_row[i + 1] as usize];
            for e in row.chain(rev.iter().map(|&e| e as usize)) {
                if let Some(f) = force(e) {
                    *total += f;
                }
            }
        }
    }
    (0..n)
        .map(|i| sum[i] / crate::math::surface(p.radius[i]))
        .collect()
}

/// Overlap of particle `i` with wall `w` (negative: a gap), if the wall has a normal there.
pub fn wall_overlap(setup: &Setup, p: &Particles, i: usize, w: usize) -> Option<f64> {
    setup.walls[w]
        .shape
        .nearest(p.pos[i])
        .map(|t| p.radius[i] - t.distance)
}

/// Convenience: position of the particle with stable id `id`, if present.
pub fn index_of(p: &Particles, id: u32) -> Option<usize> {
    p.id.iter().position(|&k| k == id)
}

/// A fingerprint of the state: FNV-1a over every particle's position, velocity and
/// angular velocity (in id order) and every touching pair's tangential spring (keyed by
/// ids). Equal hashes mean bitwise-equal runs, whatever the thread count or restarts.
pub fn state_hash(s: &State) -> u64 {
    state_hash_on(s, &Serial, |_| true)
}

/// [`state_hash`] of a state spread over ranks, where this rank `owns` some of the
/// particles it stores (by index; the others are copies of another rank's): its
/// records (its particles, then the springs and granular histories of the pairs whose
/// lower id it owns, each keyed by ids) are gathered through `reduce` and hashed in key
/// order, so the hash does not depend on which rank holds what.
pub fn state_hash_on<R: Reduce + ?Sized>(
    s: &State,
    reduce: &R,
    owns: impl Fn(usize) -> bool,
) -> u64 {
    let p = &s.particles;
    // A pair is counted by the rank that owns its lower id.
    let counts = |i: usize, j: usize| owns(if p.id[i] < p.id[j] { i } else { j });
    let list = &s.contacts;
    let mut h = grains_core::hash::Fnv1a::default();
    // Each group is keyed, sorted and hashed before the next is made: at the end of a run
    // the hash's own records were the peak of the whole run's memory.
    let bodies: Vec<u32> = (0..p.len())
        .filter(|&i| owns(i))
        .map(|i| i as u32)
        .collect();
    hash_records(
        &mut h,
        reduce,
        (bodies, |i| p.id[i] as u64),
        (1 + 2 * Vector::N + AngVector::N, false),
        |i, put| {
            let (x, v, w) = (p.pos[i], p.vel[i], p.omega[i]);
            (0..Vector::N).for_each(|a| put(x.get(a).to_bits()));
            (0..Vector::N).for_each(|a| put(v.get(a).to_bits()));
            (0..AngVector::N).for_each(|a| put(w.get(a).to_bits()));
        },
    );
    let pair_key = |i: usize, j: usize| {
        let (a, b) = (p.id[i], p.id[j]);
        (a.min(b) as u64) << 32 | a.max(b) as u64
    };
    let mut springs = Vec::new();
    for i in 0..p.len() {
        for e in list.row[i] as usize..list.row[i + 1] as usize {
            let j = list.nbr[e] as usize;
            if list.spring(e) != Tangent::default() && counts(i, j) {
                springs.push(e as u32);
            }
        }
    }
    let entry_key = |e: usize| pair_key(list.owner[e] as usize, list.nbr[e] as usize);
    hash_records(
        &mut h,
        reduce,
        (springs, entry_key),
        (1 + Tangent::N, true),
        |e, put| {
            let xi = list.spring(e);
            (0..Tangent::N).for_each(|a| put(xi.get(a).to_bits()));
        },
    );
    // The granular law's histories, as seen from the lower id (none under the linear law).
    let kept = list.history.kept(list.len());
    let granular: Vec<u32> = (0..list.len())
        .filter(|&e| kept && list.history.slot[e] != crate::history::NONE)
        .filter(|&e| {
            let g = list.history.get(e, list.owner[e]);
            g.iter().any(|&x| x != 0.0) && counts(list.owner[e] as usize, list.nbr[e] as usize)
        })
        .map(|e| e as u32)
        .collect();
    hash_records(
        &mut h,
        reduce,
        (granular, entry_key),
        (1 + crate::granular::WIDTH, true),
        |e, put| {
            let g = list.history.get(e, list.owner[e]);
            let (a, b) = (p.id[list.owner[e] as usize], p.id[list.nbr[e] as usize]);
            let g = if a > b {
                crate::granular::swapped(&g)
            } else {
                g
            };
            g.iter().for_each(|x| put(x.to_bits()));
        },
    );
    h.finish()
}

/// Hashes one group of records, each the words `words` gives for an index (`stride`
/// words in all with its key, `key` of the index), in ascending key (the key itself too
/// where `keyed`); no two records share a key. On one rank the records are never written
/// out: only their indices are sorted, by key, 4 bytes a record. Over ranks the words are
/// made and gathered, and hashed in the same order, so both give one hash.
fn hash_records<R: Reduce + ?Sized>(
    h: &mut grains_core::hash::Fnv1a,
    reduce: &R,
    (mut items, key): (Vec<u32>, impl Fn(usize) -> u64),
    (stride, keyed): (usize, bool),
    words: impl Fn(usize, &mut dyn FnMut(u64)),
) {
    if reduce.ranks() == 1 {
        items.sort_unstable_by_key(|&at| key(at as usize));
        for at in items {
            if keyed {
                h.word(key(at as usize));
            }
            words(at as usize, &mut |w| h.word(w));
        }
        return;
    }
    let mut flat = Vec::with_capacity(items.len() * stride);
    for &at in &items {
        flat.push(key(at as usize));
        words(at as usize, &mut |w| flat.push(w));
    }
    drop(items);
    let flat = reduce.gather(flat);
    let mut records: Vec<&[u64]> = flat.chunks_exact(stride).collect();
    records.sort_unstable_by_key(|r| r[0]);
    for r in records {
        if keyed {
            h.word(r[0]);
        }
        for &x in &r[1..] {
            h.word(x);
        }
    }
}
