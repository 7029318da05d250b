//! Velocity-Verlet integration, fused with gravity, walls and the gathering of pair
//! forces, so each stage is one sweep over the particles.

use crate::comm::Reduce;
use crate::domain::Image;
use crate::exact::ExactSums;
use crate::forces::contact_force;
use crate::history::NarrowMut;
use crate::law::{ContactLaw, Prior, Response};
use crate::ledger::PassTally;
use crate::math::{self, AngVector, Components, Vector, DIM};
use crate::neighbours::ContactList;
use crate::particles::Particles;
use crate::setup::Setup;
use crate::verlet::{Comoving, Sums};
use crate::CHUNK;
use rayon::prelude::*;

/// Resultant load that the particles exert on one wall.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WallLoad {
    /// Force on the wall (N; per unit thickness in 2D).
    pub force: Vector,
    /// Torque on the wall about its reference point (`WallShape::reference`).
    pub torque: AngVector,
    /// Number of particles touching it.
    pub contacts: u32,
}

/// Components of a wall's load: force, then torque.
const LOAD: usize = DIM + math::ANG;

/// One rank's part of a wall's load, added exactly ([`ExactSums`]), so that the loads
/// are the same bit for bit on any thread and rank count (docs/parallel.md, rule 2).
#[derive(Clone, Debug, Default)]
pub struct WallSum {
    /// Force components, then torque components.
    sums: ExactSums<LOAD>,
    /// Particles touching the wall.
    contacts: u64,
}

impl WallSum {
    fn add(&mut self, force: Vector, torque: AngVector) {
        let mut t = [0.0; LOAD];
        for (a, x) in t.iter_mut().enumerate().take(DIM) {
            *x = force.get(a);
        }
        for a in 0..math::ANG {
            t[DIM + a] = torque.get(a);
        }
        self.sums.add(&t);
        self.contacts += 1;
    }

    fn merge(&mut self, other: &WallSum) {
        self.sums.merge(&other.sums);
        self.contacts += other.contacts;
    }
}

/// Adds one chunk's `loads` to the `total` of each wall (exactly: in any order).
pub(crate) fn merge_loads(total: &mut [WallSum], loads: &[WallSum]) {
    for (t, l) in total.iter_mut().zip(loads) {
        t.merge(l);
    }
}

/// The walls' loads from every rank's parts, through `reduce` (one integer sum).
pub fn wall_loads<R: Reduce + ?Sized>(parts: &[WallSum], reduce: &R) -> Vec<WallLoad> {
    let mut n: Vec<u64> = parts.iter().map(|w| w.contacts).collect();
    let mut words: Vec<u64> = parts.iter().flat_map(|w| w.sums.to_words()).collect();
    if reduce.ranks() > 1 {
        reduce.sum_u64(&mut n);
        reduce.sum_u64(&mut words);
    }
    words
        .chunks_exact(ExactSums::<LOAD>::WORDS)
        .zip(n)
        .map(|(w, n)| {
            let t = ExactSums::<LOAD>::from_words(w).values();
            WallLoad {
                force: Vector::from_slice(&t[..DIM]),
                torque: AngVector::from_slice(&t[DIM..]),
                contacts: n as u32,
            }
        })
        .collect()
}

/// How far the particles went in a [`kick_drift`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Drift {
    /// Some particle is now more than skin/2 from `pos_at_build` (or the list does not
    /// fit the particles): the classic rule would rebuild.
    pub moved: bool,
    /// The largest distance of a particle from `pos_at_build` (m; infinite when the
    /// list does not fit the particles).
    pub displacement: f64,
    /// With a frame: no two particles have strayed, together, more than the skin from
    /// where the frame carries their build positions (the list is still valid;
    /// [`crate::verlet`]).
    pub in_frame: bool,
    /// With a frame: the two largest squared residuals, largest first (the test of
    /// `in_frame` over several ranks takes the two largest of all).
    pub residuals: [f64; 2],
    /// With a frame: the sums the next frame is estimated from.
    pub sums: Sums,
}

/// First half of velocity Verlet over a step `dt`: half kick with the last forces and
/// gravity, then drift, and wrap positions on periodic axes. Measures, in the same sweep
/// (no extra pass over memory), whether any particle has now moved more than skin/2 from
/// `pos_at_build`, and, given an expanding `frame` with each particle's unit vector from
/// its centre at the build, whether the two largest residuals from where the frame
/// carries the particles add up to at most the skin.
pub fn kick_drift(
    setup: &Setup,
    p: &mut Particles,
    pos_at_build: &[Vector],
    frame: Option<(&Comoving, &[Vector])>,
    dt: f64,
) -> Drift {
    let stale =
        pos_at_build.len() != p.len() || frame.is_some_and(|(_, normals)| normals.len() != p.len());
    let (frame, normals) = match frame {
        Some((f, normals)) if !stale => (Some(f), normals),
        _ => (None, &[][..]),
    };
    let d = crate::with_image!(
        setup.domain,
        kick_drift_chunks,
        (setup, p, pos_at_build, stale, frame, normals, dt)
    );
    // Two particles come closer by at most the sum of their residuals, so the two
    // largest residuals bound every pair: one fast grain alone does not force a rebuild.
    let [a, b] = d.residuals;
    let limit2 = (0.5 * setup.skin).powi(2);
    Drift {
        moved: d.d2 > limit2 || stale,
        displacement: if stale { f64::INFINITY } else { d.d2.sqrt() },
        in_frame: !stale && frame.is_some() && a.sqrt() + b.sqrt() <= setup.skin,
        residuals: d.residuals,
        sums: d.sums,
    }
}

/// What one chunk of a [`kick_drift`] measured.
#[derive(Clone, Copy, Debug, Default)]
struct ChunkDrift {
    /// The largest squared distance from the build position.
    d2: f64,
    /// The two largest squared residuals in the frame, largest first.
    residuals: [f64; 2],
    sums: Sums,
}

/// The two largest of two pairs, largest first.
#[inline]
fn top_two(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    if a[0] >= b[0] {
        [a[0], a[1].max(b[0])]
    } else {
        [b[0], b[1].max(a[0])]
    }
}

fn kick_drift_chunks<const P: u8>(
    setup: &Setup,
    p: &mut Particles,
    built: &[Vector],
    stale: bool,
    frame: Option<&Comoving>,
    normals: &[Vector],
    dt: f64,
) -> ChunkDrift {
    let image = Image::<P>::new(&setup.domain);
    let (h, g) = (0.5 * dt, setup.gravity);
    p.pos
        .par_chunks_mut(CHUNK)
        .zip(p.vel.par_chunks_mut(CHUNK))
        .zip(p.omega.par_chunks_mut(CHUNK))
        .zip(p.force.par_chunks(CHUNK))
        .zip(p.torque.par_chunks(CHUNK))
        .zip(p.inv_mass.par_chunks(CHUNK))
        .zip(p.inv_inertia.par_chunks(CHUNK))
        .enumerate()
        .map(|(c, ((((((x, v), w), f), t), im), ii))| {
            let n = x.len();
            let (v, w, f, t, im, ii) = (
                &mut v[..n],
                &mut w[..n],
                &f[..n],
                &t[..n],
                &im[..n],
                &ii[..n],
            );
            for k in 0..n {
                v[k] += h * (im[k] * f[k] + g);
                w[k] += h * ii[k] * t[k];
                x[k] = image.wrap(x[k] + dt * v[k]);
            }
            let mut d = ChunkDrift::default();
            if stale {
                return d;
            }
            let b = &built[c * CHUNK..c * CHUNK + n];
            match frame {
                None => {
                    for k in 0..n {
                        d.d2 = d.d2.max(image.apply(x[k] - b[k]).length_squared());
                    }
                }
                Some(fr) => {
                    // Frames are only used without periodic axes: no image to apply.
                    let nb = &normals[c * CHUNK..c * CHUNK + n];
                    let (mut d2, mut top) = (0.0f64, [0.0f64; 2]);
                    let mut radial = [f64::INFINITY, f64::NEG_INFINITY];
                    let (mut sum_d, mut sum_n) = (Vector::ZERO, Vector::ZERO);
                    for k in 0..n {
                        let delta = x[k] - b[k];
                        let e = delta - fr.shift - fr.radial * nb[k];
                        d2 = d2.max(delta.length_squared());
                        let e2 = e.length_squared();
                        // A residual that is not a number must fail the test, not pass it.
                        let e2 = if e2.is_nan() { f64::INFINITY } else { e2 };
                        if e2 > top[1] {
                            top = if e2 > top[0] {
                                [e2, top[0]]
                            } else {
                                [top[0], e2]
                            };
                        }
                        let along = delta.dot(nb[k]);
                        radial = [radial[0].min(along), radial[1].max(along)];
                        sum_d += delta;
                        sum_n += nb[k];
                    }
                    d.d2 = d2;
                    d.residuals = top;
                    d.sums = Sums {
                        radial,
                        displacement: sum_d,
                        normal: sum_n,
                    };
                }
            }
            d
        })
        // Collected, then joined in chunk order: the frame's sums are floating-point
        // additions, which must not depend on how the pool split the work.
        .collect::<Vec<ChunkDrift>>()
        .into_iter()
        .fold(ChunkDrift::default(), |a, b| ChunkDrift {
            d2: a.d2.max(b.d2),
            residuals: top_two(a.residuals, b.residuals),
            sums: a.sums.join(b.sums),
        })
}

/// Adds to each particle's own-entry sums (left in `force`/`torque` by the pair pass) the
/// reactions of the entries where it is the partner, gravity and wall contacts (advancing wall springs by `dt_shear`), stores the
/// total force and torque, and applies a kick of `kick` × acceleration to the velocities
/// (½Δt to close a Verlet step; 0 for the initial evaluation).
///
/// Returns this rank's part of the load on each wall, added exactly so that it is
/// bitwise the same whatever the thread count ([`wall_loads`] rounds it). With `rows` (one per particle), each
/// particle's wall contacts' ledger terms are left there ([`crate::ledger`]); the
/// forces are the same either way.
pub fn walls_gather_kick(
    setup: &Setup,
    p: &mut Particles,
    list: &mut ContactList,
    dt_shear: f64,
    kick: f64,
    rows: Option<&mut [PassTally]>,
) -> Vec<WallSum> {
    let (nw, granular) = (setup.walls.len(), setup.granular.is_some());
    fit_wall_history(setup, list, p.len());
    let (g, w) = Gather::split(setup, p, list, dt_shear, kick);
    let partial: Vec<Vec<WallSum>> = w
        .into_chunks(nw, granular, rows)
        .into_par_iter()
        .enumerate()
        .map(|(c, own)| g.chunk(c, own))
        .collect();
    let mut total = vec![WallSum::default(); nw];
    for loads in partial {
        merge_loads(&mut total, &loads);
    }
    total
}

/// Sizes the walls' granular histories for the law before they are split by chunk:
/// each chunk writes its own run of records.
pub(crate) fn fit_wall_history(setup: &Setup, list: &mut ContactList, n: usize) {
    if let Some(table) = setup.granular.as_ref() {
        list.wall_history.widen(table.history_width());
        list.wall_history.resize(n * setup.walls.len());
    }
}

/// One chunk's own slices of what the gather writes.
pub(crate) struct Own<'a> {
    vel: &'a mut [Vector],
    omega: &'a mut [AngVector],
    /// In: the row sums the pass left; out: the particles' total forces.
    force: &'a mut [Vector],
    /// As `force`, for the torques.
    torque: &'a mut [AngVector],
    /// The chunk's wall springs (linear law), `[k * n_walls + w]`.
    ws: &'a mut [math::Tangent],
    /// The chunk's wall histories (granular law).
    wh: NarrowMut<'a>,
    /// With the ledger: the chunk's rows of wall terms (empty without).
    book: &'a mut [PassTally],
}

/// Everything the gather reads, shared by its chunks.
pub(crate) struct Gather<'a> {
    setup: &'a Setup,
    pos: &'a [Vector],
    radius: &'a [f64],
    inv_mass: &'a [f64],
    inv_inertia: &'a [f64],
    material: &'a [u16],
    fpair: &'a [Vector],
    ftan: &'a [AngVector],
    touch: &'a [u8],
    slot: &'a [u32],
    pools: &'a [crate::history::Pool],
    owner: &'a [u32],
    rev_row: &'a [u32],
    rev_entry: &'a [u32],
    wall_near: &'a [u64],
    /// The granular law keeps its reactions beside the touching pairs' histories: an
    /// entry with a slot touches, and its reaction is in its row owner's pool.
    pooled: bool,
    /// Most entries of a dilute bed do not touch: reading a flag and skipping them
    /// beats reading every force; where most touch, the flag's branch would mispredict.
    sparse: bool,
    dt_shear: f64,
    kick: f64,
}

/// What the gather writes, split from what it reads ([`Gather::split`]).
pub(crate) struct Written<'a> {
    vel: &'a mut [Vector],
    omega: &'a mut [AngVector],
    force: &'a mut [Vector],
    torque: &'a mut [AngVector],
    wall_shear: &'a mut [math::Tangent],
    wall_history: &'a mut crate::history::Narrow,
}

impl<'a> Written<'a> {
    /// Every chunk's slices, in order, with the ledger's `rows` (one per particle) split
    /// beside them; `granular`: the walls' histories are the law's.
    fn into_chunks(
        self,
        nw: usize,
        granular: bool,
        rows: Option<&'a mut [PassTally]>,
    ) -> Vec<Own<'a>> {
        let nchunks = self.vel.len().div_ceil(CHUNK);
        let mut ws = self.wall_shear.chunks_mut((CHUNK * nw).max(1));
        let mut wh = match granular && nw > 0 {
            true => self.wall_history.chunks_mut(CHUNK * nw),
            false => Vec::new(),
        }
        .into_iter();
        let mut book = rows.unwrap_or_default().chunks_mut(CHUNK);
        self.vel
            .chunks_mut(CHUNK)
            .zip(self.omega.chunks_mut(CHUNK))
            .zip(self.force.chunks_mut(CHUNK))
            .zip(self.torque.chunks_mut(CHUNK))
            .map(|(((vel, omega), force), torque)| Own {
                vel,
                omega,
                force,
                torque,
                ws: ws.next().unwrap_or_default(),
                wh: wh.next().unwrap_or_default(),
                book: book.next().unwrap_or_default(),
            })
            .take(nchunks)
            .collect()
    }

    /// Chunk `c`'s slices, without the ledger's rows; `granular`: the walls' histories
    /// are the law's.
    pub(crate) fn own(&mut self, c: usize, nw: usize, granular: bool) -> Own<'_> {
        let range = c * CHUNK..((c + 1) * CHUNK).min(self.vel.len());
        let walls = range.start * nw..range.end * nw;
        Own {
            vel: &mut self.vel[range.clone()],
            omega: &mut self.omega[range.clone()],
            force: &mut self.force[range.clone()],
            torque: &mut self.torque[range],
            // Empty under the granular law, which keeps no linear wall springs.
            ws: self.wall_shear.get_mut(walls.clone()).unwrap_or_default(),
            wh: match granular && nw > 0 {
                true => self.wall_history.slice_mut(walls),
                false => NarrowMut::default(),
            },
            book: &mut [],
        }
    }
}

impl<'a> Gather<'a> {
    /// The gather over `p` and `list` after their pair pass, beside the fields it
    /// writes.
    pub(crate) fn split(
        setup: &'a Setup,
        p: &'a mut Particles,
        list: &'a mut ContactList,
        dt_shear: f64,
        kick: f64,
    ) -> (Self, Written<'a>) {
        let pooled = setup.granular.is_some() && list.history.kept(list.nbr.len());
        let sparse = 2 * list.touching < list.nbr.len();
        let g = Gather {
            setup,
            pos: &p.pos,
            radius: &p.radius,
            inv_mass: &p.inv_mass,
            inv_inertia: &p.inv_inertia,
            material: &p.material,
            fpair: &list.fpair,
            ftan: &list.ftan,
            touch: &list.touch,
            slot: &list.history.slot,
            pools: &list.history.pools,
            owner: &list.owner,
            rev_row: &list.rev_row,
            rev_entry: &list.rev_entry,
            wall_near: &list.wall_near,
            pooled,
            sparse,
            dt_shear,
            kick,
        };
        let w = Written {
            vel: &mut p.vel,
            omega: &mut p.omega,
            force: &mut p.force,
            torque: &mut p.torque,
            wall_shear: &mut list.wall_shear,
            wall_history: &mut list.wall_history,
        };
        (g, w)
    }

    /// Chunk `c`: its particles' reactions, walls and kick; returns its part of each
    /// wall's load.
    pub(crate) fn chunk(&self, c: usize, own: Own) -> Vec<WallSum> {
        let Own {
            vel,
            omega,
            force,
            torque,
            ws,
            mut wh,
            book,
        } = own;
        let (setup, pos, radius, inv_mass, inv_inertia, material) = (
            self.setup,
            self.pos,
            self.radius,
            self.inv_mass,
            self.inv_inertia,
            self.material,
        );
        let (fpair, ftan, touch, slot, pools, owner) = (
            self.fpair, self.ftan, self.touch, self.slot, self.pools, self.owner,
        );
        let (rev_row, rev_entry, wall_near) = (self.rev_row, self.rev_entry, self.wall_near);
        let (pooled, sparse, dt_shear, kick) = (self.pooled, self.sparse, self.dt_shear, self.kick);
        let gravity = setup.gravity;
        let nw = setup.walls.len();
        let granular = setup.granular.as_ref();
        let mut loads = vec![WallSum::default(); nw];
        for k in 0..vel.len() {
            let i = c * CHUNK + k;
            let mut terms = PassTally::default();
            let r = radius[i];
            let mut f = force[k];
            let mut t_rev = AngVector::default();
            let rev = &rev_entry[rev_row[i] as usize..rev_row[i + 1] as usize];
            if pooled {
                // As the sparse loop below: entries apart are skipped.
                for &e in rev {
                    let e = e as usize;
                    if slot[e] != crate::history::NONE {
                        let (fp, tp) = pools[owner[e] as usize / CHUNK].reaction(slot[e]);
                        f -= fp;
                        t_rev += tp;
                    }
                }
            } else if sparse {
                // The force of an entry that does not touch is +0, and x − (+0) is
                // x; a torque sum left at −0 by the skip cannot show either, as the
                // own-row sum it is added to is never −0 (a sum that starts at +0).
                for &e in rev {
                    let e = e as usize;
                    if touch[e] != 0 {
                        f -= fpair[e];
                        t_rev += ftan[e];
                    }
                }
            } else {
                for &e in rev {
                    f -= fpair[e as usize];
                    t_rev += ftan[e as usize];
                }
            }
            let mut tq = torque[k] + r * t_rev;
            let mut mask = wall_near[i];
            while mask != 0 {
                let w = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                // The granular law keeps no linear wall springs: its histories are in `wh`.
                let mut unkept = math::Tangent::default();
                let shear = ws.get_mut(k * nw + w).unwrap_or(&mut unkept);
                let Some(touch) = setup.walls[w].shape.nearest(pos[i]) else {
                    continue;
                };
                if touch.distance >= r {
                    *shear = crate::math::Tangent::default();
                    wh.clear(k * nw + w);
                    continue;
                }
                let m = 1.0 / inv_mass[i];
                let at = pos[i] + touch.normal * touch.distance;
                let v_wall = setup.walls[w].surface_velocity(at);
                let v = vel[k] - v_wall;
                let prior = || Prior {
                    overlap: prior_overlap(setup, w, pos[i], r, vel[k], dt_shear),
                    omega_sum: omega[k],
                };
                // A wall is a body of infinite mass and radius that does not turn.
                let contact = crate::law::Contact {
                    n: touch.normal,
                    overlap: r - touch.distance,
                    r_eff: r,
                    m_eff: m,
                    v,
                    spin: r * omega[k],
                    w_rel: omega[k],
                };
                let (fw, tw) = match granular {
                    Some(table) => {
                        let wm = setup.walls[w].material.map_or(material[i], |m| m);
                        let law = table.get(material[i] as usize, wm as usize);
                        let mut h = wh.get(k * nw + w);
                        let before = h;
                        let resp = law.respond(&contact, &mut h, dt_shear);
                        wh.set(k * nw + w, &h);
                        if !book.is_empty() {
                            terms +=
                                law.ledger_terms(&contact, &before, &h, &resp, dt_shear, &prior());
                        }
                        let arm = r - 0.5 * contact.overlap;
                        (resp.force, arm * resp.moment + resp.couple)
                    }
                    None => {
                        let params = setup.wall_pair(w, material[i] as usize);
                        let before = *shear;
                        let cf = contact_force(
                            params,
                            m,
                            touch.normal,
                            r - touch.distance,
                            v,
                            r * omega[k],
                            shear,
                            dt_shear,
                        );
                        let fw = -cf.normal * touch.normal
                            + math::tangent_vector(cf.tangential, touch.normal);
                        let moment = math::moment(cf.tangential, touch.normal);
                        if !book.is_empty() {
                            let resp = Response {
                                force: fw,
                                moment,
                                couple: AngVector::default(),
                                normal: cf.normal,
                            };
                            terms += params.ledger_terms(
                                &contact,
                                &before,
                                shear,
                                &resp,
                                dt_shear,
                                &prior(),
                            );
                        }
                        (fw, r * moment)
                    }
                };
                if !book.is_empty() {
                    // The grain receives F·v_i = F·(v_i − v_w) + F·v_w: the law books
                    // the first, the wall's motion supplies the second.
                    terms.work += fw.dot(v_wall) * dt_shear;
                }
                f += fw;
                tq += tw;
                let arm = at - setup.walls[w].shape.reference();
                loads[w].add(-fw, -math::cross(arm, fw));
            }
            if let Some(b) = book.get_mut(k) {
                *b = terms;
            }
            force[k] = f;
            torque[k] = tq;
            vel[k] += kick * (inv_mass[i] * f + gravity);
            omega[k] += kick * inv_inertia[i] * tq;
        }
        loads
    }
}

/// The overlap of a particle (at `x`, radius `r`, drifting at `v`) with wall `w` before
/// the step's drift: the particle carried back by its drift relative to the wall (a
/// translating wall drifted too; a turning one keeps its shape). Negative where it did
/// not touch.
fn prior_overlap(setup: &Setup, w: usize, x: Vector, r: f64, v: Vector, dt: f64) -> f64 {
    let wall = &setup.walls[w];
    let back = x - dt * (v - wall.motion.velocity);
    wall.shape.nearest(back).map_or(-1.0, |t| r - t.distance)
}
