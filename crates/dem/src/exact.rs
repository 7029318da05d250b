//! Sums of floating-point numbers that do not depend on the order of their terms.
//!
//! A global sum over particles spread over threads and ranks must come out the same bit
//! for bit however they are spread (docs/parallel.md, rule 2). Adding in ascending id
//! does it, but needs every term gathered in one place: a word per particle per sum,
//! which on many ranks costs more than the step. An [`ExactSum`] instead holds the
//! exact value of the terms so far as a wide fixed-point integer, so any grouping of
//! the terms gives the same integer; the sum is rounded to `f64` once, at the end, and
//! ranks exchange a fixed [`ExactSum::WORDS`] words whatever their particle count.
//! The rounding is to nearest (ties to even) except for results below the smallest
//! normal `f64`, which may be off by an ulp of a subnormal (still the same bits on any
//! grouping).

/// Bits per limb; limbs are kept in `i64` so that 2³¹ terms can be added before any
/// carry is propagated.
const LIMB_BITS: u32 = 32;
/// Limbs covering the `f64` range: bit 0 is 2⁻¹⁰⁷⁴ (the smallest subnormal), the
/// largest finite value's top bit is bit 2097, and two limbs of headroom take the carries
/// of up to 2⁶³ such values.
const LIMBS: usize = 68;
/// Terms added between carry propagations (each adds under 2³² to a limb).
const CARRY_EVERY: u32 = 1 << 30;

/// The exact sum of the finite terms added so far, and what non-finite terms there were.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ExactSum {
    limbs: [i64; LIMBS],
    /// Terms added since the last carry propagation.
    pending: u32,
    /// Counts of +∞, −∞ and NaN terms (their effect does not depend on order either).
    special: [u64; 3],
}

impl Default for ExactSum {
    fn default() -> Self {
        ExactSum {
            limbs: [0; LIMBS],
            pending: 0,
            special: [0; 3],
        }
    }
}

impl ExactSum {
    /// Words in [`ExactSum::to_words`].
    pub const WORDS: usize = LIMBS + 3;

    /// An empty sum (zero).
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds `x` exactly.
    #[inline]
    pub fn add(&mut self, x: f64) {
        let bits = x.to_bits();
        // Most terms of a ledger row are zero (a law without rolling, a particle
        // without contacts): leave them first.
        if bits << 1 == 0 {
            return;
        }
        let exp = ((bits >> 52) & 0x7ff) as u32;
        let frac = bits & ((1u64 << 52) - 1);
        if exp == 0x7ff {
            let k = if frac != 0 {
                2
            } else if x > 0.0 {
                0
            } else {
                1
            };
            self.special[k] += 1;
            return;
        }
        // x = ±m · 2^(p − 1074), with p the position of m's lowest bit above 2⁻¹⁰⁷⁴.
        let (m, p) = if exp == 0 {
            (frac, 0)
        } else {
            (frac | (1u64 << 52), exp - 1)
        };
        let k = (p / LIMB_BITS) as usize;
        let shifted = (m as u128) << (p % LIMB_BITS);
        let mask = (1u128 << LIMB_BITS) - 1;
        let parts = [
            (shifted & mask) as i64,
            ((shifted >> LIMB_BITS) & mask) as i64,
            (shifted >> (2 * LIMB_BITS)) as i64,
        ];
        if x < 0.0 {
            for (l, v) in self.limbs[k..k + 3].iter_mut().zip(parts) {
                *l -= v;
            }
        } else {
            for (l, v) in self.limbs[k..k + 3].iter_mut().zip(parts) {
                *l += v;
            }
        }
        self.pending += 1;
        if self.pending >= CARRY_EVERY {
            self.carry();
        }
    }

    /// Adds another sum's terms exactly.
    pub fn merge(&mut self, other: &ExactSum) {
        let mut other = other.clone();
        other.carry();
        self.carry();
        for (a, b) in self.limbs.iter_mut().zip(other.limbs) {
            *a += b;
        }
        for (a, b) in self.special.iter_mut().zip(other.special) {
            *a += b;
        }
        // Each limb is now under 2³³ in magnitude: room for 2³⁰ more terms is left.
        self.pending = CARRY_EVERY / 2;
    }

    /// Propagates the carries, so every limb but the top lies in [0, 2³²): the one
    /// representation of the integer, whatever the terms' order.
    fn carry(&mut self) {
        for k in 0..LIMBS - 1 {
            let c = self.limbs[k] >> LIMB_BITS;
            self.limbs[k] -= c << LIMB_BITS;
            self.limbs[k + 1] += c;
        }
        self.pending = 0;
    }

    /// The sum rounded to the nearest `f64`; NaN if a term was NaN or there were both
    /// infinities, ±∞ if there was one kind of infinity or the sum overflows.
    pub fn value(&self) -> f64 {
        let [pos, neg, nan] = self.special;
        if nan > 0 || (pos > 0 && neg > 0) {
            return f64::NAN;
        }
        if pos > 0 {
            return f64::INFINITY;
        }
        if neg > 0 {
            return f64::NEG_INFINITY;
        }
        let mut s = self.clone();
        s.carry();
        let negative = s.limbs[LIMBS - 1] < 0;
        if negative {
            for l in s.limbs.iter_mut() {
                *l = -*l;
            }
            s.carry();
        }
        let Some(top) = s.limbs.iter().rposition(|&l| l != 0) else {
            return 0.0;
        };
        // The top three limbs hold at least 65 significant bits; a set bit below them
        // is folded into the lowest (sticky), which rounds exactly as the full value.
        let lo = top.saturating_sub(2);
        let mut m: u128 = 0;
        for k in (lo..=top).rev() {
            m = (m << LIMB_BITS) | s.limbs[k] as u128;
        }
        if s.limbs[..lo].iter().any(|&l| l != 0) {
            m |= 1;
        }
        let shift = (lo as i32) * LIMB_BITS as i32 - 1074;
        let v = scale(m as f64, shift);
        if negative {
            -v
        } else {
            v
        }
    }

    /// The sum as words: the limbs after carrying (two's complement) and the three
    /// special counts. Words of several ranks add element-wise (wrapping) into the
    /// words of their sums' sum ([`ExactSum::from_words`] carries again).
    pub fn to_words(&self) -> [u64; Self::WORDS] {
        let mut s = self.clone();
        s.carry();
        let mut w = [0u64; Self::WORDS];
        for (a, b) in w.iter_mut().zip(s.limbs) {
            *a = b as u64;
        }
        w[LIMBS..].copy_from_slice(&s.special);
        w
    }

    /// A sum from [`ExactSum::to_words`], or from the element-wise wrapping sum of
    /// several ranks' words (up to 2³⁰ ranks).
    pub fn from_words(w: &[u64]) -> Self {
        let mut s = ExactSum::default();
        for (a, b) in s.limbs.iter_mut().zip(w) {
            *a = *b as i64;
        }
        s.special.copy_from_slice(&w[LIMBS..Self::WORDS]);
        s.carry();
        s
    }
}

/// `x · 2^e`, exact unless the result is subnormal or overflows.
fn scale(x: f64, e: i32) -> f64 {
    let pow = |e: i32| f64::from_bits(((e + 1023) as u64) << 52);
    let mut x = x;
    let mut e = e;
    while e > 1000 {
        x *= pow(1000);
        e -= 1000;
    }
    while e < -1000 {
        x *= pow(-1000);
        e += 1000;
    }
    x * pow(e)
}

/// Exact sums of `N` quantities at once (the terms of one particle added together).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ExactSums<const N: usize>(pub [ExactSum; N]);

impl<const N: usize> Default for ExactSums<N> {
    fn default() -> Self {
        ExactSums(std::array::from_fn(|_| ExactSum::default()))
    }
}

impl<const N: usize> ExactSums<N> {
    /// Adds one term to each quantity.
    #[inline]
    pub fn add(&mut self, terms: &[f64; N]) {
        for (s, &t) in self.0.iter_mut().zip(terms) {
            s.add(t);
        }
    }

    /// Adds another set of sums.
    pub fn merge(&mut self, other: &Self) {
        for (a, b) in self.0.iter_mut().zip(&other.0) {
            a.merge(b);
        }
    }

    /// Words in [`ExactSums::to_words`].
    pub const WORDS: usize = N * ExactSum::WORDS;

    /// Every quantity's words ([`ExactSum::to_words`]), one after the other.
    pub fn to_words(&self) -> Vec<u64> {
        self.0.iter().flat_map(|s| s.to_words()).collect()
    }

    /// Sums from [`ExactSums::to_words`] (or the wrapping sum of several ranks').
    pub fn from_words(w: &[u64]) -> Self {
        ExactSums(std::array::from_fn(|k| {
            ExactSum::from_words(&w[k * ExactSum::WORDS..(k + 1) * ExactSum::WORDS])
        }))
    }

    /// Every quantity's sum, rounded.
    pub fn values(&self) -> [f64; N] {
        std::array::from_fn(|k| self.0[k].value())
    }

    /// Every quantity's sum over the ranks of `reduce` (one integer sum of
    /// [`ExactSums::WORDS`] words), rounded.
    pub fn total<R: crate::comm::Reduce + ?Sized>(&self, reduce: &R) -> [f64; N] {
        if reduce.ranks() == 1 {
            return self.values();
        }
        let mut words = self.to_words();
        reduce.sum_u64(&mut words);
        Self::from_words(&words).values()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn exact(xs: &[f64]) -> f64 {
        let mut s = ExactSum::new();
        xs.iter().for_each(|&x| s.add(x));
        s.value()
    }

    /// A small deterministic generator (no dependency).
    fn numbers(n: usize, seed: u64) -> Vec<f64> {
        let mut state = seed;
        (0..n)
            .map(|_| {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let u = (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
                let e = ((state >> 3) % 60) as i32 - 30;
                u * 2f64.powi(e)
            })
            .collect()
    }

    #[test]
    fn the_order_of_the_terms_does_not_change_a_bit() {
        let xs = numbers(10_000, 7);
        let forward = exact(&xs);
        let mut rev = xs.clone();
        rev.reverse();
        assert_eq!(forward.to_bits(), exact(&rev).to_bits());
        // Split among "ranks" and merged, in either order, through words.
        let mut a = ExactSum::new();
        let mut b = ExactSum::new();
        for (i, &x) in xs.iter().enumerate() {
            if i % 3 == 0 { &mut a } else { &mut b }.add(x);
        }
        let mut w = a.to_words();
        for (x, y) in w.iter_mut().zip(b.to_words()) {
            *x = x.wrapping_add(y);
        }
        assert_eq!(
            ExactSum::from_words(&w).value().to_bits(),
            forward.to_bits()
        );
        b.merge(&a);
        assert_eq!(b.value().to_bits(), forward.to_bits());
    }

    #[test]
    fn sums_are_correctly_rounded() {
        // 1 + 2⁻⁵³ + 2⁻⁵³: plain left-to-right addition gives 1, the exact sum is
        // 1 + 2⁻⁵², representable.
        let tiny = 2f64.powi(-53);
        assert_eq!(exact(&[1.0, tiny, tiny]), 1.0 + 2.0 * tiny);
        // Cancellation: nothing of the large terms is left but the small one.
        assert_eq!(exact(&[1e300, 3.5, -1e300]), 3.5);
        // 0.1 + 0.2 − 0.3 as doubles is exactly 2⁻⁵⁵ (their representation errors);
        // left-to-right addition gives 2⁻⁵⁴.
        assert_eq!(exact(&[0.1, 0.2, -0.3]), 2f64.powi(-55));
        assert_eq!(exact(&[]), 0.0);
        assert_eq!(exact(&[-2.5]), -2.5);
        assert_eq!(exact(&[f64::MAX, -f64::MAX, 1.0]), 1.0);
        let sub = f64::from_bits(1);
        assert_eq!(exact(&[sub, sub, sub]), 3.0 * sub);
        // Against a wide reference: integers sum exactly in i128.
        let ints: Vec<f64> = (0..1000)
            .map(|i| ((i * 7919) % 2001) as f64 - 1000.0)
            .collect();
        let want: i128 = ints.iter().map(|&x| x as i128).sum();
        assert_eq!(exact(&ints), want as f64);
    }

    #[test]
    fn two_terms_round_as_ieee_addition_does() {
        // IEEE addition of two doubles is their exact sum correctly rounded, so it is
        // the reference for every pair, cancellations and ties included.
        let xs = numbers(20_000, 11);
        for w in xs.windows(2) {
            let (x, y) = (w[0], w[1]);
            assert_eq!(exact(&[x, y]).to_bits(), (x + y).to_bits(), "{x:e} + {y:e}");
            let y2 = -x * (1.0 + f64::EPSILON);
            assert_eq!(
                exact(&[x, y2]).to_bits(),
                (x + y2).to_bits(),
                "{x:e} + {y2:e}"
            );
        }
    }

    #[test]
    fn non_finite_terms_give_what_ieee_addition_gives() {
        assert!(exact(&[1.0, f64::NAN]).is_nan());
        assert!(exact(&[f64::INFINITY, f64::NEG_INFINITY]).is_nan());
        assert_eq!(exact(&[f64::INFINITY, 1.0, f64::INFINITY]), f64::INFINITY);
        assert_eq!(exact(&[-1.0, f64::NEG_INFINITY]), f64::NEG_INFINITY);
    }
}
