//! The energy ledger as a run keeps it: each particle's own running ledger, summed
//! exactly into the figures ([`EnergyLedger`]) only when they are asked for.
//!
//! Each particle carries a row of [`LEDGER_WORDS`] numbers
//! ([`Particles::ledger`](crate::Particles::ledger), in the order of
//! [`EnergyLedger::to_words`]): what its row's terms (its pairs with higher ids, and its
//! wall contacts) have dissipated and worked so far, added pass after pass in plain
//! `f64`, and what the springs of its row held after the last pair pass and the last
//! wall pass. A particle's row terms are the same bits on any rank and thread count
//! (docs/parallel.md, rule 1), and it adds them in step order, so its running ledger is
//! too; it moves with the particle (re-sorts, migration, gathers, checkpoints). The
//! springs a particle's row released are its last pass's stored less this pass's
//! `_before` energies, which summed over the particles is the ledger's rule
//! (`crate::ledger`). The figures are the exact sums ([`ExactSum`]) of the rows of the
//! particles each rank owns, plus what left the run ([`crate::State::ledger`]),
//! combined over the ranks in a fixed number of words and rounded once: the same bits
//! on any rank count, a few additions per particle and step, nothing sent per step.

use crate::exact::ExactSums;
use crate::ledger::{EnergyLedger, PassTally, LEDGER_WORDS};
use crate::step::State;

/// One particle's running ledger (the words of an [`EnergyLedger`]).
pub type LedgerRow = [f64; LEDGER_WORDS];

// Slots, in the order of `EnergyLedger::to_words`.
const DAMPING: usize = 0;
const FRICTION: usize = 1;
const RELEASED: usize = 2;
const PAIR_SPRINGS: [usize; 4] = [3, 4, 12, 13];
const DAMPING_TANGENTIAL: usize = 5;
const ROLLING_DAMPING: usize = 6;
const ROLLING_FRICTION: usize = 7;
const TWISTING_DAMPING: usize = 8;
const TWISTING_FRICTION: usize = 9;
const SOFTENING: usize = 10;
const LEVER: usize = 11;
const WALL_SPRINGS: [usize; 4] = [14, 15, 16, 17];
const WALL_WORK: usize = 18;

/// Exact sums of ledger rows: a rank's own particles' at a sample, or what particles
/// that left the run took with them ([`crate::State::ledger`]).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LedgerSums(ExactSums<LEDGER_WORDS>);

impl LedgerSums {
    /// Words in [`LedgerSums::to_words`].
    pub const WORDS: usize = ExactSums::<LEDGER_WORDS>::WORDS;

    /// Adds one row exactly.
    pub fn add(&mut self, row: &LedgerRow) {
        self.0.add(row);
    }

    /// The figures of these sums, each rounded once.
    pub fn figures(&self) -> EnergyLedger {
        EnergyLedger::from_words(&self.0.values())
    }

    /// The sums of every rank of `reduce` (one integer sum of [`LedgerSums::WORDS`]
    /// words, on every rank).
    pub fn total<R: crate::comm::Reduce + ?Sized>(&self, reduce: &R) -> LedgerSums {
        if reduce.ranks() == 1 {
            return self.clone();
        }
        let mut words = self.to_words();
        reduce.sum_ledger(&mut words);
        LedgerSums(ExactSums::from_words(&words))
    }

    /// Its words, for a checkpoint or a reduction: exact, so sums read back go on
    /// as if never written.
    pub fn to_words(&self) -> Vec<u64> {
        self.0.to_words()
    }

    /// The sums of [`LedgerSums::to_words`]; `None` if `w` is not
    /// [`LedgerSums::WORDS`] long.
    pub fn from_words(w: &[u64]) -> Option<LedgerSums> {
        (w.len() == Self::WORDS).then(|| LedgerSums(ExactSums::from_words(w)))
    }
}

/// Starts the ledger on `s`: each particle's row holds its springs' energy
/// ([`EnergyLedger::starting_rows`]), nothing has left; refused under a law that does
/// not split its dissipation.
pub fn start(setup: &crate::Setup, s: &mut State) -> Result<(), crate::ledger::LedgerRefused> {
    s.particles.ledger = EnergyLedger::starting_rows(setup, s)?;
    s.ledger = Some(LedgerSums::default());
    Ok(())
}

/// The exact sums of the rows of the particles of `s` this rank `owns`, and of what
/// left the run here (`None` without a ledger).
pub fn sums(s: &State, owns: impl Fn(usize) -> bool) -> Option<LedgerSums> {
    let mut out = s.ledger.clone()?;
    for (_, row) in s
        .particles
        .ledger
        .iter()
        .enumerate()
        .filter(|&(i, _)| owns(i))
    {
        out.add(row);
    }
    Some(out)
}

/// The ledger's figures of a whole state (`None` without a ledger).
pub fn figures(s: &State) -> Option<EnergyLedger> {
    sums(s, |_| true).map(|l| l.figures())
}

/// The particles' running ledgers of `s` in ascending id, as numbers (for a
/// checkpoint: [`read_rows`] puts them back whatever order the state is read in).
pub fn rows_by_id(s: &State) -> Vec<f64> {
    let p = &s.particles;
    let mut order: Vec<usize> = (0..p.ledger.len()).collect();
    order.sort_unstable_by_key(|&i| p.id[i]);
    order.iter().flat_map(|&i| p.ledger[i]).collect()
}

/// Puts the running ledgers [`rows_by_id`] wrote back on the particles of `s`; refused
/// (with what was found) unless there is one per particle.
pub fn read_rows(s: &mut State, numbers: &[f64]) -> Result<(), String> {
    let p = &mut s.particles;
    if numbers.len() != LEDGER_WORDS * p.len() {
        return Err(format!(
            "the energy ledger has {} numbers for {} particles, not {} per particle",
            numbers.len(),
            p.len(),
            LEDGER_WORDS
        ));
    }
    let mut order: Vec<usize> = (0..p.len()).collect();
    order.sort_unstable_by_key(|&i| p.id[i]);
    p.ledger = vec![[0.0; LEDGER_WORDS]; p.len()];
    for (row, &i) in numbers.chunks_exact(LEDGER_WORDS).zip(&order) {
        p.ledger[i].copy_from_slice(row);
    }
    Ok(())
}

/// Takes one pair pass's row terms `terms` (one per particle) into the particles'
/// running ledgers `rows`.
pub(crate) fn pair_pass(rows: &mut Vec<LedgerRow>, terms: &[PassTally]) {
    pass(rows, terms, PAIR_SPRINGS, false);
}

/// Takes one wall pass's row terms in: its dissipation as a pair pass's, its springs
/// apart, the walls' work.
pub(crate) fn wall_pass(rows: &mut Vec<LedgerRow>, terms: &[PassTally]) {
    pass(rows, terms, WALL_SPRINGS, true);
}

/// A pass whose stored springs go to the slots `springs` (normal, tangential,
/// rolling, twisting). Particles without a row yet (just inserted) start from zero.
fn pass(rows: &mut Vec<LedgerRow>, terms: &[PassTally], springs: [usize; 4], walls: bool) {
    rows.resize(terms.len(), [0.0; LEDGER_WORDS]);
    let [n, t, r, w] = springs;
    for (l, x) in rows.iter_mut().zip(terms) {
        l[RELEASED] +=
            (l[t] - x.tangential_before) + (l[r] - x.rolling_before) + (l[w] - x.twisting_before);
        l[n] = x.normal;
        l[t] = x.tangential;
        l[r] = x.rolling;
        l[w] = x.twisting;
        l[DAMPING] += x.damping;
        l[FRICTION] += x.friction;
        l[DAMPING_TANGENTIAL] += x.damping_tangential;
        l[ROLLING_DAMPING] += x.rolling_damping;
        l[ROLLING_FRICTION] += x.rolling_friction;
        l[TWISTING_DAMPING] += x.twisting_damping;
        l[TWISTING_FRICTION] += x.twisting_friction;
        l[SOFTENING] += x.softening;
        l[LEVER] += x.lever;
        if walls {
            l[WALL_WORK] += x.work;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::ContactModel;
    use crate::domain::Domain;
    use crate::forces::pair_contacts;
    use crate::material::Material;
    use crate::math::{self, AngVector, Components, Vector};
    use crate::particles::Particles;
    use crate::setup::Setup;
    use crate::step::{step, State};

    /// The ledger's figures as they were kept before the exact sums: each pass's rows
    /// added in ascending id, then taken in by the ledger's formulas (`record`).
    #[derive(Default)]
    struct InIdOrder(EnergyLedger);

    impl InIdOrder {
        fn pair_pass(&mut self, rows: &[PassTally], id: &[u32]) {
            let mut order: Vec<usize> = (0..id.len()).collect();
            order.sort_unstable_by_key(|&i| id[i]);
            let mut t = PassTally::default();
            for i in order {
                t += rows[i];
            }
            let l = &mut self.0;
            l.springs_released += (l.stored_tangential - t.tangential_before)
                + (l.stored_rolling - t.rolling_before)
                + (l.stored_twisting - t.twisting_before);
            l.stored_normal = t.normal;
            l.stored_tangential = t.tangential;
            l.stored_rolling = t.rolling;
            l.stored_twisting = t.twisting;
            l.damping += t.damping;
            l.friction += t.friction;
            l.damping_tangential += t.damping_tangential;
            l.rolling_damping += t.rolling_damping;
            l.rolling_friction += t.rolling_friction;
            l.twisting_damping += t.twisting_damping;
            l.twisting_friction += t.twisting_friction;
            l.softening += t.softening;
            l.lever += t.lever;
        }
    }

    /// Grains squeezed together in a periodic box, flying apart: contacts that stick,
    /// slide and open.
    fn squeezed() -> (Setup, State) {
        let mut hi = Vector::ZERO;
        for a in 0..math::DIM {
            hi[a] = 6.0;
        }
        let domain = Domain {
            lo: Vector::ZERO,
            hi,
            periodic: [true; math::DIM],
        };
        let model = ContactModel::HookeHistory {
            kn: 2e5,
            kt: 1e5,
            gamma_n: 50.0,
            gamma_t: 25.0,
            mu: 0.3,
            limit_damping: false,
        };
        let material = Material {
            name: "grain".into(),
            density: 1000.0,
            youngs: None,
            poisson: None,
            restitution: None,
            friction: None,
            inertia_factor: 0.4,
        };
        let setup = Setup::new(domain, vec![material], model, vec![], Vector::ZERO, 0.1)
            .expect("a valid set-up");
        let mut p = Particles::default();
        let mut k = 7u64;
        let mut noise = || {
            k = k
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (k >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let per: usize = 6;
        for c in 0..per.pow(math::DIM as u32) {
            let (mut at, mut v, mut idx) = (Vector::ZERO, Vector::ZERO, c);
            for a in 0..math::DIM {
                at[a] = ((idx % per) as f64 + 0.5) * 6.0 / per as f64 + 0.05 * noise();
                v[a] = noise();
                idx /= per;
            }
            let w = AngVector::from_slice(&[noise(), noise(), noise()][..AngVector::N]);
            p.push(at, 0.54 + 0.04 * noise(), 1000.0, 0.4, 0, v, w);
        }
        let s = State::new(&setup, p);
        (setup, s)
    }

    /// Each state's particle rows indexed by id (the fixture's ids are 0..n).
    fn by_id<T: Copy>(rows: &[T], id: &[u32]) -> Vec<T> {
        let mut out = rows.to_vec();
        for (i, &k) in id.iter().enumerate() {
            out[k as usize] = rows[i];
        }
        out
    }

    /// The running ledgers' figures are the figures the ledger kept before them (each
    /// pass's rows added in ascending id, then taken in by the global formulas) up to
    /// rounding: fed the same passes' rows, the two agree to 1e-12 of the ledger's
    /// scale, springs released included.
    #[test]
    fn the_figures_are_the_id_ordered_sums_up_to_rounding() {
        let (setup, mut s) = squeezed();
        let start = EnergyLedger::starting_rows(&setup, &s).expect("the linear law");
        let mut rows = by_id(&start, &s.particles.id);
        let mut old = InIdOrder(EnergyLedger::starting(&setup, &s).expect("the linear law"));
        let dt = 2e-4;
        for _ in 0..400 {
            step(&setup, &mut s, dt);
            // A pass of the state as it is, with the ledger: its rows, as the step's.
            let mut c = s.clone();
            pair_contacts(&setup, &mut c.particles, &mut c.contacts, dt, true);
            let (terms, id) = (&c.contacts.ledger_rows, &c.particles.id);
            pair_pass(&mut rows, &by_id(terms, id));
            old.pair_pass(terms, id);
        }
        let mut sums = LedgerSums::default();
        rows.iter().for_each(|r| sums.add(r));
        let (a, b) = (sums.figures(), old.0);
        // (Passes repeated on the stepped state: friction and releases of either sign.)
        assert!(a.friction != 0.0 && a.springs_released != 0.0, "{a:?}");
        assert!(a.damping > 0.0 && a.stored_normal > 0.0 && a.stored_tangential > 0.0);
        let scale: f64 = a.to_words().iter().map(|x| x.abs()).sum();
        for (x, y) in a.to_words().into_iter().zip(b.to_words()) {
            assert!((x - y).abs() <= 1e-12 * scale, "{a:?}\n{b:?}");
        }
    }

    /// The rows follow their particles (a re-sort, a checkpoint's numbers read back in
    /// another order) and the figures do not depend on the storage order; a particle
    /// inserted into a running state starts with an empty row, so the figures are
    /// unchanged until its contacts book something.
    #[test]
    fn rows_follow_their_particles_and_new_ones_start_empty() {
        let (setup, mut s) = squeezed();
        start(&setup, &mut s).expect("the linear law");
        let dt = 1e-3;
        for _ in 0..100 {
            step(&setup, &mut s, dt);
        }
        let before = figures(&s).unwrap();
        // Far from everything: a particle in no contact adds nothing.
        let mut new = Particles::default();
        let mut at = Vector::ZERO;
        at[0] = 1e-3;
        new.push(at, 1e-4, 1000.0, 0.4, 0, Vector::ZERO, AngVector::default());
        crate::insert::insert(&setup, &mut s, &new);
        assert_eq!(s.particles.ledger.len(), s.particles.len());
        assert_eq!(figures(&s).unwrap(), before);
        // Reversed storage: the same figures, bit for bit.
        let mut r = s.clone();
        let perm: Vec<u32> = (0..r.particles.len() as u32).rev().collect();
        r.particles.permute(&perm);
        assert_eq!(figures(&r).unwrap(), before);
        // Through a checkpoint's numbers, in another order.
        let numbers = rows_by_id(&s);
        r.particles.ledger.clear();
        read_rows(&mut r, &numbers).unwrap();
        assert_eq!(r.particles.ledger.len(), r.particles.len());
        assert_eq!(figures(&r).unwrap(), before);
        assert!(read_rows(&mut r, &numbers[1..]).is_err());
        for _ in 0..100 {
            step(&setup, &mut s, dt);
        }
        assert!(figures(&s).unwrap().damping > before.damping);
    }
}
