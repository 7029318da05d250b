//! The contact law (one function for particle pairs and walls) and the pair pass.

use crate::contact::{PairParams, PairTable};
use crate::domain::Image;
use crate::law::{Contact, ContactLaw, LedgerTerms, Prior};
use crate::ledger::{Off, On, PassTally, Tally};
use crate::math::{self, AngVector, Components, Tangent, TangentOps, Vector, ANG, DIM, TAN};
use crate::neighbours::ContactList;
use crate::particles::Particles;
use crate::pass_fields::PassFields;
use crate::setup::Setup;
use crate::CHUNK;
use rayon::prelude::*;
use std::ops::Range;

/// Normal and tangential force of one contact, and its updated tangential spring.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactForce {
    /// Normal force (positive pushes the bodies apart).
    pub normal: f64,
    /// Tangential force on body i ([`crate::math::Tangent`]: along t = (−n_y, n_x) in
    /// 2D, a vector in the tangent plane in 3D).
    pub tangential: Tangent,
    /// The tangential spring ξ after this evaluation.
    pub shear: Tangent,
}

/// Linear spring-dashpot normal force and incremental tangential spring with a Coulomb
/// cap, for a contact with unit normal `n` from body i towards body j and overlap
/// `overlap` > 0.
///
/// `v` is v_i − v_j; `spin` is r_i ω_i + r_j ω_j (the rotational part of the contact
/// points' sliding velocity is spin × n; r_j ω_j = 0 for a wall); `shear` is the
/// contact's tangential spring before the step, carried to the current normal
/// ([`math::carry`]) and advanced by v_t·`dt` (`dt = 0` evaluates without advancing it).
/// Written without branches, so a loop over many contacts vectorises.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn contact_law(
    p: &PairParams,
    m_eff: f64,
    n: Vector,
    overlap: f64,
    v: Vector,
    spin: AngVector,
    shear: Tangent,
    dt: f64,
) -> ContactForce {
    let vn = v.dot(n); // > 0 while approaching
    let vt = math::tangential_velocity(v, n, spin);
    let fnorm = p.kn * overlap + p.normal_dashpot(m_eff) * vn;
    let fnorm = if fnorm < p.fn_floor {
        p.fn_floor
    } else {
        fnorm
    };
    let ct = p.gamma_t * m_eff;
    let xi = math::carry(shear, n) + vt * dt;
    let trial = -(xi * p.kt + vt * ct);
    let cap = p.mu * fnorm.abs();
    let slide = trial.norm() > cap;
    // Sliding: the force sits on the cap and the spring is reset so that spring +
    // dashpot give exactly that force (the LAMMPS convention).
    let ft = if slide { trial.with_norm(cap) } else { trial };
    let xi = if slide {
        -(ft + vt * ct) * p.inv_kt
    } else {
        xi
    };
    ContactForce {
        normal: fnorm,
        tangential: ft,
        shear: xi,
    }
}

/// [`contact_law`] with vector arguments, advancing `shear` in place.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn contact_force(
    p: &PairParams,
    m_eff: f64,
    n: Vector,
    overlap: f64,
    v_rel: Vector,
    spin: AngVector,
    shear: &mut Tangent,
    dt: f64,
) -> ContactForce {
    let f = contact_law(p, m_eff, n, overlap, v_rel, spin, *shear, dt);
    *shear = f.shear;
    f
}

/// Where the kernel finds a pair's law. One material (the common case) skips the table
/// lookup; the kernel is generic over both the lookup and the law, so each compiles to
/// its own loop.
pub trait PairLookup: Sync {
    /// The contact law: one whose history is the tangential spring alone, and which
    /// reads neither R_eff nor the relative spin (this pass gathers neither).
    type Law: ContactLaw<History = Tangent>;
    /// Whether every pair has the same parameters, `params(0, 0)`.
    const UNIFORM: bool;
    /// Parameters of materials (a, b).
    fn params(&self, a: u16, b: u16) -> &Self::Law;
}

/// Every pair has the same parameters.
pub struct Uniform<L = PairParams>(pub L);

impl<L: ContactLaw<History = Tangent>> PairLookup for Uniform<L> {
    type Law = L;
    const UNIFORM: bool = true;
    #[inline(always)]
    fn params(&self, _: u16, _: u16) -> &L {
        &self.0
    }
}

impl<L: ContactLaw<History = Tangent>> PairLookup for PairTable<L> {
    type Law = L;
    const UNIFORM: bool = false;
    #[inline(always)]
    fn params(&self, a: u16, b: u16) -> &L {
        self.get(a as usize, b as usize)
    }
}

/// Evaluates every listed pair and advances the tangential springs by `dt` (0 to only
/// evaluate). Each particle's force and torque are set to the sum of its own row's
/// contacts, in row order (ascending partner id); every entry keeps its force (`fpair`,
/// `ftan`; zero unless it touches, flagged in `touch`) for `walls_gather_kick` to
/// subtract from the partner in ascending owner id.
/// A particle's force is so summed in an order of ids, the same for any thread count,
/// rank count or storage order ([`ContactList`]).
/// With the `ledger`, the energy the contacts dissipate in this pass is added to each
/// particle's running ledger (see [`crate::ledger_sums`]); the forces are the same
/// either way.
pub fn pair_contacts(
    setup: &Setup,
    p: &mut Particles,
    list: &mut ContactList,
    dt: f64,
    ledger: bool,
) {
    let granular = setup.granular.as_ref();
    if !ledger {
        match granular {
            Some(table) => {
                crate::granular_pass::pair_contacts(setup, table, p, list, dt, None, None)
            }
            None => dispatch::<Off>(setup, p, list, dt, &mut [], None),
        }
        return;
    }
    let mut rows = std::mem::take(&mut list.ledger_rows);
    rows.resize(p.len(), PassTally::default());
    match granular {
        Some(table) => {
            crate::granular_pass::pair_contacts(setup, table, p, list, dt, Some(&mut rows), None)
        }
        None => dispatch::<On>(setup, p, list, dt, &mut rows, None),
    }
    crate::ledger_sums::pair_pass(&mut p.ledger, &rows);
    list.ledger_rows = rows;
}

/// What runs after each chunk's pass when the pass takes the chunks one after another
/// in order ([`crate::wavefront`]): the chunk's index, the particles and the list.
pub type Then<'t> = &'t mut dyn FnMut(usize, &mut Particles, &mut ContactList);

/// Runs `pass` over each chunk in turn (given its particles and its entries, returning
/// how many of them touch), `then` after each; returns how many entries touch.
pub(crate) fn chunk_by_chunk(
    p: &mut Particles,
    list: &mut ContactList,
    then: Then,
    mut pass: impl FnMut(Range<usize>, Range<usize>, &mut Particles, &mut ContactList) -> usize,
) -> usize {
    let n = p.len();
    let mut touching = 0;
    for c in 0..n.div_ceil(CHUNK) {
        let range = c * CHUNK..((c + 1) * CHUNK).min(n);
        let entries = list.row[range.start] as usize..list.row[range.end] as usize;
        touching += pass(range, entries, p, list);
        then(c, p, list);
    }
    touching
}

/// [`pair_contacts`] without the ledger, the chunks taken one after another in order,
/// `then` called after each.
pub fn pair_contacts_then(
    setup: &Setup,
    p: &mut Particles,
    list: &mut ContactList,
    dt: f64,
    then: Then,
) {
    match setup.granular.as_ref() {
        Some(table) => {
            crate::granular_pass::pair_contacts(setup, table, p, list, dt, None, Some(then))
        }
        None => dispatch::<Off>(setup, p, list, dt, &mut [], Some(then)),
    }
}

/// The pass; with the ledger (`T`), each particle's row terms are left in `rows`; with
/// `then`, the chunks one after another ([`pair_contacts_then`]).
fn dispatch<T: Tally>(
    setup: &Setup,
    p: &mut Particles,
    list: &mut ContactList,
    dt: f64,
    rows: &mut [PassTally],
    then: Option<Then>,
) {
    if setup.pairs.len() == 1 {
        let uniform = Uniform(*setup.pairs.get(0, 0));
        crate::with_image!(
            setup.domain,
            run::<Uniform, T>,
            (setup, &uniform, p, list, dt, rows, then)
        )
    } else {
        crate::with_image!(
            setup.domain,
            run::<PairTable, T>,
            (setup, &setup.pairs, p, list, dt, rows, then)
        )
    }
}

/// The pass's context, borrowing the particles' and the list's fields one by one so
/// that the chunks' own slices can be borrowed beside it.
macro_rules! pass_ctx {
    ($setup:expr, $lookup:expr, $p:expr, $list:expr, $dt:expr) => {
        Ctx {
            image: Image::<P>::new(&$setup.domain),
            lookup: $lookup,
            f: crate::pass_fields::pass_fields!($p, $list),
            dt: $dt,
            tally: std::marker::PhantomData::<T>,
        }
    };
}

fn run<L: PairLookup, T: Tally, const P: u8>(
    setup: &Setup,
    lookup: &L,
    p: &mut Particles,
    list: &mut ContactList,
    dt: f64,
    rows: &mut [PassTally],
    then: Option<Then>,
) {
    let n = p.len();
    list.fit_touch();
    if let Some(then) = then {
        list.touching = chunk_by_chunk(p, list, then, |c, e, p, list| {
            let mut job = Chunk {
                range: c.clone(),
                shear: &mut list.shear[e.clone()],
                fpair: &mut list.fpair[e.clone()],
                ftan: &mut list.ftan[e.clone()],
                touch: &mut list.touch[e],
                force: &mut p.force[c.clone()],
                torque: &mut p.torque[c],
                terms: &mut [],
            };
            pass_ctx!(setup, lookup, p, list, dt).chunk(&mut job)
        });
        return;
    }
    // Split entry and particle arrays at chunk boundaries so each task owns its slices.
    let mut jobs = Vec::with_capacity(n.div_ceil(CHUNK));
    let (mut shear, mut fpair, mut ftan, mut touch) = (
        &mut list.shear[..],
        &mut list.fpair[..],
        &mut list.ftan[..],
        &mut list.touch[..],
    );
    let mut force = p.force.chunks_mut(CHUNK);
    let mut torque = p.torque.chunks_mut(CHUNK);
    let mut terms = rows.chunks_mut(CHUNK);
    let mut done = 0usize;
    for c in 0..n.div_ceil(CHUNK) {
        let range = c * CHUNK..((c + 1) * CHUNK).min(n);
        let len = list.row[range.end] as usize - done;
        let (s, s_rest) = shear.split_at_mut(len);
        let (f, f_rest) = fpair.split_at_mut(len);
        let (t, t_rest) = ftan.split_at_mut(len);
        let (h, h_rest) = touch.split_at_mut(len);
        jobs.push(Chunk {
            range,
            shear: s,
            fpair: f,
            ftan: t,
            touch: h,
            force: force.next().unwrap_or_default(),
            torque: torque.next().unwrap_or_default(),
            terms: terms.next().unwrap_or_default(),
        });
        shear = s_rest;
        fpair = f_rest;
        ftan = t_rest;
        touch = h_rest;
        done += len;
    }
    let ctx = pass_ctx!(setup, lookup, p, list, dt);
    list.touching = jobs
        .into_par_iter()
        .map(|mut job| ctx.chunk(&mut job))
        .sum();
}

/// Touching pairs are processed in blocks of this many: first their geometry and inputs
/// are gathered (one distance test per entry), then the contact law runs over the whole
/// block as a loop over plain arrays, which the compiler vectorises, then the forces are
/// scattered onto the particles in entry order.
const BLOCK: usize = 64;
const _: () = assert!(BLOCK.is_power_of_two());

/// Everything the pair pass reads.
struct Ctx<'a, L, T, const P: u8> {
    image: Image<P>,
    lookup: &'a L,
    /// The particles' and the list's fields the pass reads.
    f: PassFields<'a>,
    dt: f64,
    tally: std::marker::PhantomData<T>,
}

/// The slices one task owns: its particles' rows, entries, forces and torques.
struct Chunk<'a> {
    range: std::ops::Range<usize>,
    shear: &'a mut [Tangent],
    fpair: &'a mut [Vector],
    ftan: &'a mut [AngVector],
    touch: &'a mut [u8],
    force: &'a mut [Vector],
    torque: &'a mut [AngVector],
    /// With the ledger: each particle's row terms (empty without).
    terms: &'a mut [PassTally],
}

/// The touching pairs of one block, one array per quantity and component; `W` the law.
struct Block<W> {
    len: usize,
    entry: [u32; BLOCK],
    i: [u32; BLOCK],
    j: [u32; BLOCK],
    params: [W; BLOCK],
    /// Separation x_j − x_i (nearest image).
    d: [[f64; BLOCK]; DIM],
    rsum: [f64; BLOCK],
    inv_msum: [f64; BLOCK],
    /// v_i − v_j.
    v: [[f64; BLOCK]; DIM],
    /// r_i ω_i + r_j ω_j.
    spin: [[f64; BLOCK]; ANG],
    /// The tangential spring: before the law, then after it.
    xi: [[f64; BLOCK]; TAN],
    /// Force on i.
    f: [[f64; BLOCK]; DIM],
    /// n × F_t, the torque on i and on j per unit radius.
    ft: [[f64; BLOCK]; ANG],
    /// The row being summed: its owner (`usize::MAX`: none), force and torque per unit
    /// radius so far.
    row: (usize, Vector, AngVector),
    /// With the ledger: the row's terms so far.
    row_terms: PassTally,
}

/// The ledger's terms per pair of a block (with the ledger only: the pass without it
/// keeps the block as it was).
struct Tallies {
    terms: [LedgerTerms; BLOCK],
}

impl<W: Copy> Block<W> {
    /// A block whose parameter slots start as `seed`.
    fn new(seed: W) -> Box<Self> {
        Box::new(Block {
            len: 0,
            entry: [0; BLOCK],
            i: [0; BLOCK],
            j: [0; BLOCK],
            params: [seed; BLOCK],
            d: [[0.0; BLOCK]; DIM],
            rsum: [0.0; BLOCK],
            inv_msum: [0.0; BLOCK],
            v: [[0.0; BLOCK]; DIM],
            spin: [[0.0; BLOCK]; ANG],
            xi: [[0.0; BLOCK]; TAN],
            f: [[0.0; BLOCK]; DIM],
            ft: [[0.0; BLOCK]; ANG],
            row: (usize::MAX, Vector::ZERO, AngVector::default()),
            row_terms: PassTally::default(),
        })
    }
}

impl<L: PairLookup, T: Tally, const P: u8> Ctx<'_, L, T, P> {
    /// The rows of one chunk. Forces of pairs inside the chunk go straight onto both
    /// particles; pairs reaching into a later chunk leave their force in the entry.
    /// With the ledger, each row's terms go to `terms`. Returns how many of the chunk's
    /// entries touch.
    fn chunk(&self, c: &mut Chunk) -> usize {
        let base = self.f.row[c.range.start] as usize;
        c.force.fill(Vector::ZERO);
        c.torque.fill(AngVector::default());
        c.terms.fill(PassTally::default());
        let mut b = Block::new(*self.lookup.params(0, 0));
        // The fill count lives in a register: kept in the block it would go through
        // memory on every entry, in one long dependent chain.
        let mut len = 0usize;
        let mut touched = 0usize;
        let mut tally = T::ON.then(|| {
            Box::new(Tallies {
                terms: [LedgerTerms::default(); BLOCK],
            })
        });
        // One flat loop over the chunk's entries: a loop per row (two to five entries)
        // ends at a place the branch predictor cannot know.
        let entries = base..self.f.row[c.range.end] as usize;
        let (owner, nbr) = (&self.f.owner[entries.clone()], &self.f.nbr[entries]);
        for (k, (&i, &j)) in owner.iter().zip(nbr).enumerate() {
            let (i, j) = (i as usize, j as usize);
            let (pi, ri) = (self.f.pos[i], self.f.radius[i]);
            let d = self.image.apply(self.f.pos[j] - pi);
            let rj = self.f.radius[j];
            let rsum = ri + rj;
            let dist2 = d.length_squared();
            // Every entry is written into the block's next slot, and the slot is kept
            // only if the pair touches: no unpredictable branch per entry. Entries
            // start cleared; the scatter writes back those that touch.
            let touching = (dist2 < rsum * rsum) & (dist2 > 0.0);
            // Always < BLOCK (the block is flushed when full); the mask lets the
            // compiler see it and drop thirteen index checks per entry.
            let t = len & (BLOCK - 1);
            b.entry[t] = k as u32;
            b.i[t] = i as u32;
            b.j[t] = j as u32;
            d.write(&mut b.d, t);
            b.rsum[t] = rsum;
            c.shear[k].write(&mut b.xi, t);
            c.shear[k] = Tangent::default();
            // The scatter writes the forces of touching entries; one that stops
            // touching is zeroed here, once (rare: the branch is predictable).
            let was = std::mem::replace(&mut c.touch[k], touching as u8);
            if was > touching as u8 {
                c.fpair[k] = Vector::ZERO;
                c.ftan[k] = AngVector::default();
            }
            touched += touching as usize;
            len += touching as usize;
            if len == BLOCK {
                b.len = len;
                self.flush(&mut b, c, tally.as_deref_mut());
                len = 0;
            }
        }
        b.len = len;
        self.flush(&mut b, c, tally.as_deref_mut());
        self.settle(&mut b, c);
        touched
    }

    /// Runs the contact law over the block and scatters its forces.
    fn flush(&self, b: &mut Block<L::Law>, c: &mut Chunk, mut tally: Option<&mut Tallies>) {
        self.gather(b);
        if L::UNIFORM {
            let p = *self.lookup.params(0, 0);
            self.law(b, |_| p, tally.as_deref_mut());
        } else {
            let params = b.params;
            self.law(b, |t| params[t], tally.as_deref_mut());
        }
        self.scatter(b, c, tally.as_deref());
    }

    /// Reads the kinematics of the block's touching pairs. Done here rather than per
    /// listed entry: most entries of a Verlet list do not touch, and their velocities,
    /// spins and masses would be fetched (from arrays other than the positions) for
    /// nothing.
    #[inline(always)]
    fn gather(&self, b: &mut Block<L::Law>) {
        let n = b.len.min(BLOCK);
        for t in 0..n {
            let (i, j) = (b.i[t] as usize, b.j[t] as usize);
            let (vi, vj) = (self.f.vel[i], self.f.vel[j]);
            let (wi, wj) = (self.f.omega[i], self.f.omega[j]);
            let (ri, rj) = (self.f.radius[i], self.f.radius[j]);
            let (mi, mj) = (self.f.inv_mass[i], self.f.inv_mass[j]);
            (vi - vj).write(&mut b.v, t);
            (ri * wi + rj * wj).write(&mut b.spin, t);
            b.inv_msum[t] = mi + mj;
            if !L::UNIFORM {
                b.params[t] = *self.lookup.params(self.f.material[i], self.f.material[j]);
            }
        }
    }

    /// The contact law over the block's arrays: no branches and no indirection, so the
    /// loop vectorises.
    #[inline(always)]
    fn law(
        &self,
        b: &mut Block<L::Law>,
        params: impl Fn(usize) -> L::Law,
        mut tally: Option<&mut Tallies>,
    ) {
        // The bound lets the compiler drop index checks, which would stop vectorisation.
        let n = b.len.min(BLOCK);
        for t in 0..n {
            // Recomputed rather than stored: cheaper than a store and a load per entry, and
            // the same operations give the same value as the touching test.
            let d = Vector::read(&b.d, t);
            let dist = d.length_squared().sqrt();
            // One division serves both 1/dist and m_eff = 1/(1/m_i + 1/m_j).
            let q = 1.0 / (dist * b.inv_msum[t]);
            let inv_dist = q * b.inv_msum[t];
            let n = d * inv_dist;
            let pp = params(t);
            let xi0 = Tangent::read(&b.xi, t);
            // The law reads neither R_eff nor the relative spin (`PairLookup::Law`).
            let contact = Contact {
                n,
                overlap: b.rsum[t] - dist,
                r_eff: 0.0,
                m_eff: q * dist,
                v: Vector::read(&b.v, t),
                spin: AngVector::read(&b.spin, t),
                w_rel: AngVector::default(),
            };
            let mut xi = xi0;
            let r = pp.respond(&contact, &mut xi, self.dt);
            if let (true, Some(tl)) = (T::ON, tally.as_deref_mut()) {
                let (i, j) = (b.i[t] as usize, b.j[t] as usize);
                let prior = Prior {
                    overlap: b.rsum[t] - (d + self.dt * contact.v).length(),
                    omega_sum: self.f.omega[i] + self.f.omega[j],
                };
                tl.terms[t] = pp.ledger_terms(&contact, &xi0, &xi, &r, self.dt, &prior);
            }
            r.force.write(&mut b.f, t);
            r.moment.write(&mut b.ft, t);
            xi.write(&mut b.xi, t);
        }
    }

    /// Adds the block's forces (and ledger terms) to their row owners in entry order and
    /// leaves each force in its entry for the partner.
    fn scatter(&self, b: &mut Block<L::Law>, c: &mut Chunk, tally: Option<&Tallies>) {
        let n = b.len.min(BLOCK);
        // A block holds rows in order, so the row owner's sums stay in registers until
        // the owner changes, and are carried into the next block: a row is summed entry
        // by entry wherever a block ends.
        let (mut owner, mut f_own, mut t_own) = b.row;
        for t in 0..n {
            let (i, k) = (b.i[t] as usize, b.entry[t] as usize);
            if i != owner {
                b.row = (owner, f_own, t_own);
                self.settle(b, c);
                (owner, f_own, t_own) = (i, Vector::ZERO, AngVector::default());
            }
            let fv = Vector::read(&b.f, t);
            let ft = AngVector::read(&b.ft, t);
            c.shear[k] = Tangent::read(&b.xi, t);
            f_own += fv;
            t_own += ft;
            c.fpair[k] = fv;
            c.ftan[k] = ft;
            if let (true, Some(tl)) = (T::ON, tally) {
                b.row_terms += tl.terms[t];
            }
        }
        b.row = (owner, f_own, t_own);
        b.len = 0;
    }

    /// Writes the sums of the row in progress to its owner.
    #[inline(always)]
    fn settle(&self, b: &mut Block<L::Law>, c: &mut Chunk) {
        let (owner, f_own, t_own) = b.row;
        if owner != usize::MAX {
            c.force[owner - c.range.start] = f_own;
            c.torque[owner - c.range.start] = self.f.radius[owner] * t_own;
            if T::ON {
                c.terms[owner - c.range.start] = b.row_terms;
            }
        }
        b.row = (usize::MAX, Vector::ZERO, AngVector::default());
        b.row_terms = PassTally::default();
    }
}

#[cfg(all(test, feature = "dim2"))]
mod tests {
    use super::*;
    use glam::DVec2;

    #[test]
    fn coulomb_cap_holds_and_history_matches_force() {
        let p = PairParams::lammps(1e4, 5e3, 0.0, 0.0, 0.3, false);
        let mut xi = 0.0;
        let f = contact_force(
            &p,
            1.0,
            DVec2::X,
            1e-3,
            DVec2::new(0.0, 1.0),
            0.0,
            &mut xi,
            1e-2,
        );
        assert!((f.normal - 10.0).abs() < 1e-12);
        assert!((f.tangential.abs() - 3.0).abs() < 1e-12);
        assert!((p.kt * xi + f.tangential).abs() < 1e-12);
    }
}
