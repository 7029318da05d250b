//! The random generator of the whole suite: xoshiro256++, seeded
//! explicitly, so every run is reproducible from its configuration.

use rand_xoshiro::rand_core::SeedableRng;

/// The generator type every crate uses.
pub type Rng = rand_xoshiro::Xoshiro256PlusPlus;

/// A generator for `seed` (expanded to the full 256-bit state with
/// SplitMix64, as `rand` does for `seed_from_u64`).
pub fn seeded(seed: u64) -> Rng {
    Rng::seed_from_u64(seed)
}

/// Generator number `stream` of a family identified by `seed`, e.g. one per
/// thread, per replica or per initial-condition sample.
///
/// Seed mixing rather than `jump()`: a jump costs 256 state steps, so
/// jumping `stream` times would be slow for large stream ids. The first two
/// state words are bijective scrambles of `seed` and `stream`, so distinct
/// `(seed, stream)` pairs always give distinct states; in a period of
/// 2^256 - 1, overlap between the sequences actually drawn is negligible.
pub fn stream(seed: u64, stream: u64) -> Rng {
    // Arbitrary odd constants that keep the words of one pair from
    // coinciding with those of another pair or of `seeded`.
    const A: u64 = 0x6a09_e667_f3bc_c909;
    const B: u64 = 0xbb67_ae85_84ca_a73b;
    let w0 = scramble(seed ^ A);
    let w1 = scramble(stream ^ B);
    let w2 = scramble(w0 ^ scramble(stream).rotate_left(21));
    let w3 = scramble(w1 ^ scramble(seed).rotate_left(43));
    let mut bytes = [0u8; 32];
    for (chunk, w) in bytes.chunks_exact_mut(8).zip([w0, w1, w2, w3]) {
        chunk.copy_from_slice(&w.to_le_bytes());
    }
    // An all-zero state is mapped to a valid one by `from_seed` itself.
    Rng::from_seed(bytes)
}

/// A bijective 64-bit avalanche mix (xor-shift/multiply rounds), so nearby
/// inputs such as consecutive stream ids give unrelated words.
fn scramble(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng as _, RngExt};

    #[test]
    fn seeded_is_deterministic() {
        let a: Vec<u64> = (0..5)
            .map({
                let mut r = seeded(42);
                move |_| r.next_u64()
            })
            .collect();
        let mut r = seeded(42);
        let b: Vec<u64> = (0..5).map(|_| r.next_u64()).collect();
        assert_eq!(a, b);
        assert_ne!(seeded(42).next_u64(), seeded(43).next_u64());
    }

    #[test]
    fn streams_are_deterministic_and_distinct() {
        assert_eq!(stream(1, 2).next_u64(), stream(1, 2).next_u64());
        let mut firsts: Vec<u64> = Vec::new();
        for s in 0..4 {
            for k in 0..256 {
                firsts.push(stream(s, k).next_u64());
            }
        }
        firsts.push(seeded(0).next_u64());
        let n = firsts.len();
        firsts.sort_unstable();
        firsts.dedup();
        assert_eq!(firsts.len(), n);
    }

    #[test]
    fn neighbouring_streams_look_independent() {
        // Consecutive ids must not give correlated sequences: the mean of
        // the product of centred uniforms should be ~0 (sd ~ 1/(12 sqrt n)).
        let mut a = stream(7, 0);
        let mut b = stream(7, 1);
        let n = 100_000;
        let mut sum = 0.0;
        let mut mean_a = 0.0;
        for _ in 0..n {
            let x: f64 = a.random::<f64>() - 0.5;
            let y: f64 = b.random::<f64>() - 0.5;
            sum += x * y;
            mean_a += x;
        }
        assert!((sum / n as f64).abs() < 0.002, "{}", sum / n as f64);
        assert!((mean_a / n as f64).abs() < 0.005);
    }

    #[test]
    fn scramble_is_injective_on_a_sample() {
        let mut v: Vec<u64> = (0..10_000u64).map(scramble).collect();
        v.sort_unstable();
        v.dedup();
        assert_eq!(v.len(), 10_000);
    }
}
