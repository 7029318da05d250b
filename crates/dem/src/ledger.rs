//! Where the particle contacts' energy goes: the energy ledger the pair pass keeps when
//! asked to ([`State::ledger`](crate::State::ledger) is `Some`).
//!
//! Per touching pair and step Δt (v_n the approach speed, v_t the sliding speed, both at
//! the half step the forces are evaluated with):
//!
//! * **damping**: the dashpots' work, (F_n − K_n δ)·v_n Δt, plus c_t v_t² Δt while the
//!   contact sticks. The first term is c_n v_n² Δt, or with `limit_damping` what the
//!   clamp at zero withholds;
//! * **friction**: on a step where the trial force exceeds μF_n and the spring is reset
//!   to ξ (so that −F_t = K_t ξ + c_t v_t), the tangential work −F_t v_t Δt less the
//!   spring's change ½K_t(ξ² − ξ_old²): the Coulomb cap bounds the force, the tangential
//!   dashpot's share included; zero while the contact sticks;
//! * **springs released**: ½K_t ξ² of a tangential spring whose contact has opened (the
//!   contact law forgets its history, as LAMMPS's does), counted once when it goes: the
//!   tangential energy the touching pairs held after the last pass, less what the pairs
//!   touching now held before this one.
//!
//! It also keeps the energy stored in the touching pairs' springs after the pass
//! (½K_n δ² and ½K_t ξ² summed). Work in = kinetic change + stored change + the
//! dissipation, up to the integrator's error (first order in Δt for sliding, whose slip
//! is read at the half step). Wall contacts are not in the ledger. Started on a state
//! whose springs are not all zero, it takes them in with [`EnergyLedger::starting`].
//!
//! The pair pass computes the terms beside the forces, from the same values, in a
//! version of the pass compiled for it ([`Tally`]): without the ledger the pass is the
//! code it was, and with it the forces and the state are the same bit for bit.

use crate::granular::GranularParams;
use crate::law::{ContactLaw, LedgerTerms};
use crate::math::TangentOps;
use crate::setup::Setup;
use crate::step::State;
use std::ops::AddAssign;

/// A ledger asked of a law that does not split its dissipation (the granular law).
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "the energy ledger is kept under the linear contact law only: the granular law \
     (Hertz, Mindlin) does not split its dissipation"
)]
pub struct LedgerRefused;

/// Energy the pair contacts have dissipated since the ledger was started, and what their
/// springs hold now (J per unit thickness).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EnergyLedger {
    /// Work of the normal and tangential dashpots.
    pub damping: f64,
    /// Coulomb sliding.
    pub friction: f64,
    /// Tangential springs dropped as their contacts opened.
    pub springs_released: f64,
    /// ½K_n δ² of the touching pairs after the last pass.
    pub stored_normal: f64,
    /// ½K_t ξ² of the touching pairs after the last pass.
    pub stored_tangential: f64,
}

impl EnergyLedger {
    /// Everything dissipated.
    pub fn total(&self) -> f64 {
        self.damping + self.friction + self.springs_released
    }

    /// Energy stored in the pairs' springs.
    pub fn stored(&self) -> f64 {
        self.stored_normal + self.stored_tangential
    }

    /// A ledger started on `s`: nothing dissipated yet, its springs' energy stored;
    /// refused under a law that does not split its dissipation
    /// ([`ContactLaw::LEDGER`]).
    pub fn starting(setup: &Setup, s: &State) -> Result<Self, LedgerRefused> {
        if setup.granular.is_some() && !GranularParams::LEDGER {
            return Err(LedgerRefused);
        }
        let p = &s.particles;
        let list = &s.contacts;
        let mut l = EnergyLedger::default();
        for i in 0..p.len() {
            for e in list.row[i] as usize..list.row[i + 1] as usize {
                let j = list.nbr[e] as usize;
                let pp = setup
                    .pairs
                    .get(p.material[i] as usize, p.material[j] as usize);
                let dist = setup.domain.min_image(p.pos[j] - p.pos[i]).length();
                let overlap = p.radius[i] + p.radius[j] - dist;
                if overlap > 0.0 {
                    l.stored_normal += 0.5 * pp.kn * overlap * overlap;
                }
                l.stored_tangential += list.shear[e].quad(0.5 * pp.kt);
            }
        }
        Ok(l)
    }

    /// The ledger of a run under a law that keeps none: every figure NaN.
    pub fn refused() -> Self {
        EnergyLedger {
            damping: f64::NAN,
            friction: f64::NAN,
            springs_released: f64::NAN,
            stored_normal: f64::NAN,
            stored_tangential: f64::NAN,
        }
    }

    /// Takes in one pair pass.
    pub(crate) fn record(&mut self, pass: &PassTally) {
        self.damping += pass.damping;
        self.friction += pass.friction;
        self.springs_released += self.stored_tangential - pass.tangential_before;
        self.stored_normal = pass.normal;
        self.stored_tangential = pass.tangential;
    }
}

/// What one pair pass adds up, the law's [`LedgerTerms`] summed per particle (its row),
/// then over the particles in ascending id ([`in_id_order`]).
pub(crate) type PassTally = LedgerTerms;

/// The pass's total from each stored particle's row terms `rows` (its pairs with higher
/// ids): the rows of the particles this rank `owns`, gathered from every rank through
/// `reduce` and added in ascending id, so that each pair counts once (on the rank that
/// owns its lower id) and the sum is the same bit for bit on any rank count. On one rank
/// the particles are taken in the order `by_id` (indices in ascending id, made when it
/// is empty or of another length: a rebuild, which re-sorts the particles, clears it),
/// with nothing gathered.
pub(crate) fn in_id_order<R: crate::comm::Reduce + ?Sized>(
    rows: &[PassTally],
    id: &[u32],
    owns: impl Fn(usize) -> bool,
    reduce: &R,
    by_id: &mut Vec<u32>,
) -> PassTally {
    let mut total = PassTally::default();
    if reduce.ranks() == 1 {
        if by_id.len() != id.len() {
            *by_id = (0..id.len() as u32).collect();
            by_id.sort_unstable_by_key(|&i| id[i as usize]);
        }
        for &i in by_id.iter() {
            total += rows[i as usize];
        }
        return total;
    }
    let mut words = Vec::with_capacity(6 * rows.len());
    for (i, r) in rows.iter().enumerate().filter(|&(i, _)| owns(i)) {
        words.push(id[i] as u64);
        let terms = [
            r.damping,
            r.friction,
            r.normal,
            r.tangential,
            r.tangential_before,
        ];
        words.extend(terms.map(f64::to_bits));
    }
    let words = reduce.gather(words);
    let mut records: Vec<&[u64]> = words.chunks_exact(6).collect();
    records.sort_unstable_by_key(|r| r[0]);
    for r in records {
        let t = |k: usize| f64::from_bits(r[k]);
        total += PassTally {
            damping: t(1),
            friction: t(2),
            normal: t(3),
            tangential: t(4),
            tangential_before: t(5),
        };
    }
    total
}

impl AddAssign for PassTally {
    fn add_assign(&mut self, o: Self) {
        self.damping += o.damping;
        self.friction += o.friction;
        self.normal += o.normal;
        self.tangential += o.tangential;
        self.tangential_before += o.tangential_before;
    }
}

/// Whether a pair pass keeps the ledger, decided at compile time so that the pass
/// without it does no ledger work at all.
pub(crate) trait Tally: Sync {
    /// Keep it.
    const ON: bool;
}

/// The pass without the ledger.
pub(crate) struct Off;

impl Tally for Off {
    const ON: bool = false;
}

/// The pass with the ledger.
pub(crate) struct On;

impl Tally for On {
    const ON: bool = true;
}
