//! The pair pass under the granular law ([`crate::granular`]): every listed pair that
//! touches is evaluated through [`ContactLaw::respond`] and its forces and torques applied, in the same
//! fixed chunks as the linear law's pass ([`crate::forces`]), so the sums are the same
//! for any thread count.
//!
//! As there, a row's forces go to its owner in row order and every touching pair
//! leaves the partner's share for `walls_gather_kick` (the order of ids:
//! [`ContactList`]), here beside its history in the chunk's pool
//! ([`crate::history::Pool::reaction`]) rather than in the list's per-entry `fpair` and
//! `ftan`, which this law leaves empty. Unlike the linear law, the two bodies' torques
//! differ by more than their radii (the arms are R − δ/2 and rolling and twisting add a
//! couple), so a pair leaves the partner's torque divided by its radius, which
//! `walls_gather_kick` multiplies back.

use crate::contact::PairTable;
use crate::domain::Image;
use crate::forces::{chunk_by_chunk, Then};
use crate::granular::{Contact, Damping, GranularParams, Normal, Tangential};
use crate::history::Pool;
use crate::law::{ContactLaw, Prior};
use crate::ledger::PassTally;
use crate::math::{self, AngVector, Components, Tangent, TangentOps, Vector, ANG, DIM, TAN};
use crate::neighbours::ContactList;
use crate::particles::Particles;
use crate::pass_fields::PassFields;
use crate::setup::Setup;
use crate::CHUNK;
use rayon::prelude::*;

/// The slices one task owns.
struct Chunk<'a> {
    range: std::ops::Range<usize>,
    /// The entries' slots in `pool`.
    slot: &'a mut [u32],
    pool: &'a mut Pool,
    /// How many entries touch (this law keeps no per-entry flags: an entry touches
    /// when it has a slot).
    touching: usize,
    force: &'a mut [Vector],
    torque: &'a mut [AngVector],
    /// With the ledger: each particle's row terms (empty without).
    terms: &'a mut [PassTally],
}

impl Chunk<'_> {
    /// Counts entry `k` as touching or not; one that does not touch has its history
    /// (and with it its reaction) released.
    #[inline(always)]
    fn touches(&mut self, k: usize, touching: bool) -> bool {
        self.touching += touching as usize;
        if !touching {
            self.pool.release(&mut self.slot[k]);
        }
        touching
    }
}

/// Evaluates every listed pair under `table`'s laws, advancing the histories by `dt`
/// (none when `dt` is 0: the evaluation of a set-up, as LAMMPS's). With `rows` (one per
/// particle), each particle's row of ledger terms ([`ContactLaw::ledger_terms`]) is
/// left there: the pass then takes every pair through the law one at a time (the
/// blocked loop gives the same bits, and is kept free of the ledger's work). With
/// `then` (and no `rows`), the chunks are taken one after another in order, `then`
/// called after each ([`crate::forces::pair_contacts_then`]).
pub fn pair_contacts(
    setup: &Setup,
    table: &PairTable<GranularParams>,
    p: &mut Particles,
    list: &mut ContactList,
    dt: f64,
    rows: Option<&mut [PassTally]>,
    then: Option<Then>,
) {
    crate::with_image!(setup.domain, run, (setup, table, p, list, dt, rows, then));
}

/// The pass's context, borrowing the particles' and the list's fields one by one so
/// that the chunks' own slices can be borrowed beside it.
macro_rules! pass_ctx {
    ($setup:expr, $table:expr, $p:expr, $list:expr, $dt:expr) => {
        Ctx {
            image: Image::<P>::new(&$setup.domain),
            f: crate::pass_fields::pass_fields!($p, $list),
            table: $table,
            dt: $dt,
        }
    };
}

fn run<const P: u8>(
    setup: &Setup,
    table: &PairTable<GranularParams>,
    p: &mut Particles,
    list: &mut ContactList,
    dt: f64,
    rows: Option<&mut [PassTally]>,
    then: Option<Then>,
) {
    let book = rows.is_some();
    let mut terms = rows.unwrap_or_default().chunks_mut(CHUNK);
    // Particles of one material (the common case; walls may differ): the law is read
    // once, not per contact.
    let m0 = p.material.first().map_or(0, |&m| m as usize);
    let one = table.len() == 1 || p.material.iter().all(|&m| m as usize == m0);
    let uniform = (one && m0 < table.len()).then(|| *table.get(m0, m0));
    let n = p.len();
    list.history
        .fit(list.nbr.len(), n.div_ceil(CHUNK), table.history_width());
    // The slots say which entries touch: no flags are kept.
    list.touch = Vec::new();
    // A list read back from a checkpoint holds its reactions per entry: the pass makes
    // them anew in the pools.
    list.fpair = Vec::new();
    list.ftan = Vec::new();
    let plain = uniform.and_then(|law| Plain::of(&law));
    if let Some(then) = then.filter(|_| !book) {
        list.touching = chunk_by_chunk(p, list, then, |c, e, p, list| {
            let mut job = Chunk {
                range: c.clone(),
                slot: &mut list.history.slot[e],
                pool: &mut list.history.pools[c.start / CHUNK],
                touching: 0,
                force: &mut p.force[c.clone()],
                torque: &mut p.torque[c],
                terms: &mut [],
            };
            let ctx = pass_ctx!(setup, table, p, list, dt);
            match &plain {
                Some(plain) => ctx.blocked(plain, &mut job),
                None => ctx.scalar::<false>(uniform.as_ref(), &mut job),
            }
        });
        return;
    }
    let row = &list.row;
    let mut jobs = Vec::with_capacity(n.div_ceil(CHUNK));
    let mut pools = list.history.pools.iter_mut();
    let mut slot = &mut list.history.slot[..];
    let mut force = p.force.chunks_mut(CHUNK);
    let mut torque = p.torque.chunks_mut(CHUNK);
    for c in 0..n.div_ceil(CHUNK) {
        let range = c * CHUNK..((c + 1) * CHUNK).min(n);
        let len = (row[range.end] - row[range.start]) as usize;
        let (h, h_rest) = slot.split_at_mut(len);
        jobs.push(Chunk {
            range,
            slot: h,
            pool: pools.next().expect("a pool per chunk"),
            touching: 0,
            force: force.next().unwrap_or_default(),
            torque: torque.next().unwrap_or_default(),
            terms: terms.next().unwrap_or_default(),
        });
        slot = h_rest;
    }
    let ctx = pass_ctx!(setup, table, p, list, dt);
    list.touching = match plain {
        _ if book => jobs
            .into_par_iter()
            .map(|mut c| ctx.scalar::<true>(uniform.as_ref(), &mut c))
            .sum(),
        Some(plain) => jobs
            .into_par_iter()
            .map(|mut c| ctx.blocked(&plain, &mut c))
            .sum(),
        None => jobs
            .into_par_iter()
            .map(|mut c| ctx.scalar::<false>(uniform.as_ref(), &mut c))
            .sum(),
    };
}

/// Everything the pass reads.
struct Ctx<'a, const P: u8> {
    image: Image<P>,
    /// The particles' and the list's fields the pass reads.
    f: PassFields<'a>,
    table: &'a PairTable<GranularParams>,
    dt: f64,
}

impl<const P: u8> Ctx<'_, P> {
    /// Any law, one entry at a time through [`ContactLaw::respond`]; `BOOK`: each
    /// row's ledger terms summed into `c.terms` in entry order. Returns how many entries
    /// touch.
    fn scalar<const BOOK: bool>(&self, uniform: Option<&GranularParams>, c: &mut Chunk) -> usize {
        let first = c.range.start;
        let base = self.f.row[first] as usize;
        let (pos, vel, omega, radius, inv_mass) = (
            self.f.pos,
            self.f.vel,
            self.f.omega,
            self.f.radius,
            self.f.inv_mass,
        );
        let dt = self.dt;
        c.force.fill(Vector::ZERO);
        c.torque.fill(AngVector::default());
        c.terms.fill(PassTally::default());
        for k in 0..c.slot.len() {
            let (i, j) = (
                self.f.owner[base + k] as usize,
                self.f.nbr[base + k] as usize,
            );
            let d = self.image.apply(pos[j] - pos[i]);
            let (ri, rj) = (radius[i], radius[j]);
            let rsum = ri + rj;
            let dist2 = d.length_squared();
            if !c.touches(k, dist2 < rsum * rsum && dist2 > 0.0) {
                continue;
            }
            let dist = dist2.sqrt();
            let contact = Contact {
                n: d / dist,
                overlap: rsum - dist,
                r_eff: ri * rj / rsum,
                m_eff: 1.0 / (inv_mass[i] + inv_mass[j]),
                v: vel[i] - vel[j],
                spin: ri * omega[i] + rj * omega[j],
                w_rel: omega[i] - omega[j],
            };
            let law = match uniform {
                Some(law) => law,
                None => self
                    .table
                    .get(self.f.material[i] as usize, self.f.material[j] as usize),
            };
            let s = c.pool.take(&mut c.slot[k]);
            let mut h = c.pool.at(s);
            let before = h;
            let r = law.respond(&contact, &mut h, dt);
            c.pool.put(s, &h);
            if BOOK {
                let prior = Prior {
                    overlap: rsum - (d + dt * contact.v).length(),
                    omega_sum: omega[i] + omega[j],
                };
                c.terms[i - first] += law.ledger_terms(&contact, &before, &h, &r, dt, &prior);
            }
            let half = 0.5 * contact.overlap;
            c.force[i - first] += r.force;
            c.torque[i - first] += (ri - half) * r.moment + r.couple;
            let tj = (rj - half) * r.moment - r.couple;
            c.pool.set_reaction(s, r.force, tj * (1.0 / rj));
        }
        c.touching
    }

    /// One law without rolling, twisting or rescaling for every pair: the touching
    /// entries are gathered into blocks and the law runs over each block's arrays
    /// ([`Plain::respond`]), the same operations as [`crate::granular::respond`], so the same bits.
    /// Returns how many entries touch.
    fn blocked(&self, law: &Plain, c: &mut Chunk) -> usize {
        let base = self.f.row[c.range.start] as usize;
        c.force.fill(Vector::ZERO);
        c.torque.fill(AngVector::default());
        let mut b = Block::new();
        let mut len = 0usize;
        for k in 0..c.slot.len() {
            let (i, j) = (
                self.f.owner[base + k] as usize,
                self.f.nbr[base + k] as usize,
            );
            let d = self.image.apply(self.f.pos[j] - self.f.pos[i]);
            let rsum = self.f.radius[i] + self.f.radius[j];
            let dist2 = d.length_squared();
            if !c.touches(k, dist2 < rsum * rsum && dist2 > 0.0) {
                continue;
            }
            c.pool.take(&mut c.slot[k]);
            let t = len & (BLOCK - 1);
            b.entry[t] = k as u32;
            b.i[t] = i as u32;
            b.j[t] = j as u32;
            d.write(&mut b.d, t);
            b.rsum[t] = rsum;
            len += 1;
            if len == BLOCK {
                self.flush(law, &mut b, len, c);
                len = 0;
            }
        }
        self.flush(law, &mut b, len, c);
        c.touching
    }

    /// Runs the law over the first `len` pairs of the block and adds their forces in
    /// entry order.
    fn flush(&self, law: &Plain, b: &mut Block, len: usize, c: &mut Chunk) {
        let n = len.min(BLOCK);
        for t in 0..n {
            let (i, j, k) = (b.i[t] as usize, b.j[t] as usize, b.entry[t] as usize);
            let (ri, rj) = (self.f.radius[i], self.f.radius[j]);
            (self.f.vel[i] - self.f.vel[j]).write(&mut b.v, t);
            (ri * self.f.omega[i] + rj * self.f.omega[j]).write(&mut b.spin, t);
            b.ri[t] = ri;
            b.rj[t] = rj;
            b.inv_msum[t] = self.f.inv_mass[i] + self.f.inv_mass[j];
            Tangent::from_slice(c.pool.spring(c.slot[k])).write(&mut b.xi, t);
        }
        // The deck's law (Hertz, Tsuji, Mindlin) and the step's update are fixed at
        // compile time: the loop then has no branch left and vectorises.
        let hmt = law.hertz
            && matches!(law.damping, Damping::Tsuji | Damping::Restitution)
            && law.mindlin
            && !law.limit_damping;
        match (hmt, self.dt > 0.0) {
            (true, true) => law_loop::<true, true>(law, b, n, self.dt),
            (true, false) => law_loop::<true, false>(law, b, n, self.dt),
            (false, true) => law_loop::<false, true>(law, b, n, self.dt),
            (false, false) => law_loop::<false, false>(law, b, n, self.dt),
        }
        let first = c.range.start;
        for t in 0..n {
            let (i, k) = (b.i[t] as usize, b.entry[t] as usize);
            let f = Vector::read(&b.f, t);
            let tj = AngVector::read(&b.tj, t);
            let xi = Tangent::read(&b.xi, t);
            let s = c.slot[k];
            let h = c.pool.spring_mut(s);
            for a in 0..TAN {
                h[a] = xi.get(a);
            }
            c.force[i - first] += f;
            c.torque[i - first] += AngVector::read(&b.ti, t);
            c.pool.set_reaction(s, f, tj * (1.0 / b.rj[t]));
        }
    }
}

/// [`Plain::respond`] over the first `n` pairs of a block; `HMT`: the law is Hertz with
/// Tsuji's damping and Mindlin's spring (and no limit on damping); `UPDATE`: the springs
/// advance (dt > 0).
#[inline(never)]
fn law_loop<const HMT: bool, const UPDATE: bool>(law: &Plain, b: &mut Block, n: usize, dt: f64) {
    let n = n.min(BLOCK);
    for t in 0..n {
        let d = Vector::read(&b.d, t);
        let dist = d.length_squared().sqrt();
        let (ri, rj, rsum) = (b.ri[t], b.rj[t], b.rsum[t]);
        let overlap = rsum - dist;
        let (force, moment, xi) = law.respond::<HMT, UPDATE>(
            d / dist,
            overlap,
            ri * rj / rsum,
            1.0 / b.inv_msum[t],
            Vector::read(&b.v, t),
            AngVector::read(&b.spin, t),
            Tangent::read(&b.xi, t),
            dt,
        );
        // As the scalar pass: no couple without rolling or twisting.
        let half = 0.5 * overlap;
        let none = AngVector::default();
        force.write(&mut b.f, t);
        ((ri - half) * moment + none).write(&mut b.ti, t);
        ((rj - half) * moment - none).write(&mut b.tj, t);
        xi.write(&mut b.xi, t);
    }
}

/// [`math::carry_keeping_length`] with a select in place of its branches (the same
/// operations on the path taken).
#[cfg(feature = "dim3")]
#[inline(always)]
fn carry(xi: Tangent, n: Vector, stiffness: f64, limit: f64) -> Tangent {
    let along = xi.dot(n);
    let tilted = along.abs() * stiffness > 1e-10 * limit;
    let before = xi.length();
    let p = xi - along * n;
    let after = p.length();
    let scale = if after > 0.0 { before / after } else { 0.0 };
    pick(tilted, p * scale, xi)
}

/// In 2D the spring is a component along t and is carried as it is.
#[cfg(not(feature = "dim3"))]
#[inline(always)]
fn carry(xi: Tangent, n: Vector, stiffness: f64, limit: f64) -> Tangent {
    math::carry_keeping_length(xi, n, stiffness, limit)
}

/// Touching pairs per block.
const BLOCK: usize = 64;
const _: () = assert!(BLOCK.is_power_of_two());

/// The touching pairs of one block, one array per quantity and component.
struct Block {
    entry: [u32; BLOCK],
    i: [u32; BLOCK],
    j: [u32; BLOCK],
    /// x_j − x_i (nearest image).
    d: [[f64; BLOCK]; DIM],
    rsum: [f64; BLOCK],
    ri: [f64; BLOCK],
    rj: [f64; BLOCK],
    inv_msum: [f64; BLOCK],
    /// v_i − v_j.
    v: [[f64; BLOCK]; DIM],
    /// r_i ω_i + r_j ω_j.
    spin: [[f64; BLOCK]; ANG],
    /// The tangential spring: before the law, then after it.
    xi: [[f64; BLOCK]; TAN],
    /// Force on i.
    f: [[f64; BLOCK]; DIM],
    /// Torque on i and on j.
    ti: [[f64; BLOCK]; ANG],
    tj: [[f64; BLOCK]; ANG],
}

impl Block {
    fn new() -> Box<Self> {
        Box::new(Block {
            entry: [0; BLOCK],
            i: [0; BLOCK],
            j: [0; BLOCK],
            d: [[0.0; BLOCK]; DIM],
            rsum: [0.0; BLOCK],
            ri: [0.0; BLOCK],
            rj: [0.0; BLOCK],
            inv_msum: [0.0; BLOCK],
            v: [[0.0; BLOCK]; DIM],
            spin: [[0.0; BLOCK]; ANG],
            xi: [[0.0; BLOCK]; TAN],
            f: [[0.0; BLOCK]; DIM],
            ti: [[0.0; BLOCK]; ANG],
            tj: [[0.0; BLOCK]; ANG],
        })
    }
}

/// A law with a tangential spring and nothing after it (no rolling, no twisting, no
/// `mindlin_rescale`): what [`crate::granular::respond`] does for it, written with selects in place of
/// branches so that a loop over contacts vectorises, in the same operations.
#[derive(Clone, Copy, Debug)]
struct Plain {
    hertz: bool,
    kn: f64,
    damping: Damping,
    damp: f64,
    mindlin: bool,
    kt: f64,
    x_gamma_t: f64,
    mu: f64,
    limit_damping: bool,
}

impl Plain {
    fn of(p: &GranularParams) -> Option<Self> {
        let plain =
            p.rolling.is_none() && !p.twisting && p.tangential != Tangential::MindlinRescale;
        plain.then_some(Plain {
            hertz: p.normal == Normal::HertzMaterial,
            kn: p.kn,
            damping: p.damping,
            damp: p.damp,
            mindlin: p.tangential == Tangential::Mindlin,
            kt: p.kt,
            x_gamma_t: p.x_gamma_t,
            mu: p.mu,
            limit_damping: p.limit_damping,
        })
    }

    /// The force on i, n × F_t and the new spring, for unit normal `n` (i towards j),
    /// overlap, R_eff, m_eff, v_i − v_j, R_i ω_i + R_j ω_j and the spring before.
    /// `HMT` and `UPDATE` as [`law_loop`]'s.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn respond<const HMT: bool, const UPDATE: bool>(
        &self,
        n: Vector,
        overlap: f64,
        r_eff: f64,
        m_eff: f64,
        v: Vector,
        spin: AngVector,
        xi: Tangent,
        dt: f64,
    ) -> (Vector, AngVector, Tangent) {
        let vnn = -v.dot(n);
        let a = (overlap * r_eff).sqrt();
        let (fne, knfac) = if HMT || self.hertz {
            (self.kn * overlap * a, self.kn * a)
        } else {
            (self.kn * overlap, self.kn)
        };
        let damp_normal = if HMT {
            (m_eff * knfac).sqrt()
        } else {
            match self.damping {
                Damping::Velocity => 1.0,
                Damping::MassVelocity => m_eff,
                Damping::Viscoelastic => a * m_eff,
                Damping::Tsuji | Damping::Restitution => (m_eff * knfac).sqrt(),
            }
        };
        let eta_n = self.damp * damp_normal;
        let fn_total = fne - eta_n * vnn;
        let fn_total = if !HMT && self.limit_damping && fn_total < 0.0 {
            0.0
        } else {
            fn_total
        };
        let fn_crit = fn_total.abs();
        let vtr = math::tangential_velocity(v, n, spin);
        let f_scrit = self.mu * fn_crit;
        let kt = if HMT || self.mindlin {
            self.kt * a
        } else {
            self.kt
        };
        let eta_t = self.x_gamma_t * eta_n;
        let xi = if UPDATE {
            carry(xi, n, kt, f_scrit) + vtr * dt
        } else {
            xi
        };
        let ft = -(xi * kt) - vtr * eta_t;
        let fs = ft.norm();
        let slide = fs > f_scrit;
        let moving = xi.norm() != 0.0;
        let ratio = f_scrit / fs;
        let xi_cap = -(ft * ratio + vtr * eta_t) * (1.0 / kt);
        let ft_cap = if moving {
            ft * ratio
        } else {
            Tangent::default()
        };
        let xi = pick(slide & moving, xi_cap, xi);
        let ft = pick(slide, ft_cap, ft);
        (
            -fn_total * n + math::tangent_vector(ft, n),
            math::moment(ft, n),
            xi,
        )
    }
}

/// `a` where `c`, else `b`, component by component (a select, not a branch).
#[inline(always)]
fn pick<T: Components>(c: bool, a: T, b: T) -> T {
    let mut out = [0.0; 3];
    for k in 0..T::N {
        out[k] = if c { a.get(k) } else { b.get(k) };
    }
    T::from_slice(&out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::granular::Damping;
    use crate::{ContactModel, Domain, Material, State};

    /// A heap of grains in a periodic box with a floor, under `table`.
    fn heap(materials: usize, table: PairTable<GranularParams>) -> (Setup, State) {
        let material = Material {
            name: "m".into(),
            density: 1.9,
            youngs: None,
            poisson: None,
            restitution: None,
            friction: None,
            inertia_factor: 0.4,
        };
        let model = ContactModel::unused();
        let mut lo = Vector::ZERO;
        let mut hi = Vector::ZERO;
        let mut periodic = [true; math::DIM];
        for a in 0..math::DIM {
            hi[a] = 6.0;
        }
        lo[math::DIM - 1] = -1.0;
        hi[math::DIM - 1] = 60.0;
        periodic[math::DIM - 1] = false;
        let domain = Domain { lo, hi, periodic };
        let mut setup = Setup::new(
            domain,
            vec![material; materials],
            model,
            vec![],
            -Vector::from_slice(&[0.0, 0.0, 1.0][3 - math::DIM..]),
            0.2,
        )
        .unwrap();
        setup.granular = Some(table);
        let mut p = Particles::default();
        let mut k = 0u64;
        let mut noise = || {
            k = k
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (k >> 11) as f64 / (1u64 << 53) as f64
        };
        for c in 0..300 {
            let mut at = Vector::ZERO;
            let mut v = Vector::ZERO;
            let mut idx = c;
            for a in 0..math::DIM {
                let m = if a + 1 == math::DIM { 1000 } else { 6 };
                at[a] = (idx % m) as f64 * 0.93 + 0.5 + 0.05 * noise();
                v[a] = noise() - 0.5;
                idx /= m;
            }
            let w = AngVector::from_slice(&[noise() - 0.5, noise() - 0.5, noise() - 0.5]);
            p.push(
                at,
                0.42 + 0.08 * noise(),
                1.9,
                0.4,
                (c % materials) as u16,
                v,
                w,
            );
        }
        let state = State::new(&setup, p);
        (setup, state)
    }

    #[test]
    fn blocks_give_the_scalar_bits() {
        let law = GranularParams::lammps(
            Normal::HertzMaterial,
            1e5,
            Damping::Tsuji,
            0.5,
            0.3,
            Tangential::Mindlin,
            None,
            1.0,
            0.4,
        );
        assert!(Plain::of(&law).is_some());
        // One material takes the blocked pass, two (the same law) the scalar one.
        let (s1, mut a) = heap(1, PairTable::from_fn(1, |_, _| law));
        let (s2, mut b) = heap(2, PairTable::from_fn(2, |_, _| law));
        for _ in 0..400 {
            crate::step(&s1, &mut a, 5e-4);
            crate::step(&s2, &mut b, 5e-4);
        }
        assert!((0..a.contacts.len()).any(|e| a.contacts.granular(e).unwrap()[0] != 0.0));
        assert_eq!(
            crate::diagnostics::state_hash(&a),
            crate::diagnostics::state_hash(&b)
        );
    }
}
