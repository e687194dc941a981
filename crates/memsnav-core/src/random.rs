//! Seeded random streams. Every draw in memsnav comes from an [`Rng`] built
//! here, so a result depends only on the seeds the user passes.
//!
//! ## One seed, many independent draws
//!
//! A ChaCha8 key (the seed) has 2⁶⁴ independent streams; memsnav gives
//! each use of a seed its own range of them, so no two draws share numbers
//! and no seed's draws are another seed's:
//!
//! | stream of `seed` | drawn from it |
//! |---|---|
//! | 0 | a single draw from a user seed (`seed=` of the Python functions) |
//! | i < 2⁶² | Monte Carlo run i ([`crate::montecarlo`]) |
//! | 2⁶² + h(purpose) | [`derive_seed`]: the seed of a named independent draw |
//! | 2⁶² + h(purpose, stream, position) | [`side_stream`]: the key of a named draw made alongside a generator |
//! | 2⁶³ + s | parameter set s of the calibration experiment ([`parameter_set_stream`]) |
//!
//! When one user seed must feed several functions that each take a seed
//! (a trajectory, the IMU's errors, its noise, the GNSS: `memsnav
//! simulate`), each gets `derive_seed(seed, "its name")`, not `seed + 1`,
//! `seed + 2`, ...: those would make seed 0's second draw seed 1's first.
//! A derived seed is the first output of its own stream, so it is as
//! unrelated to small user seeds as two random 64-bit numbers.

use rand::{Rng as _, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The generator used everywhere: ChaCha8, fast and with 2⁶⁴ independent streams.
pub type Rng = ChaCha8Rng;

/// First stream of the derived seeds (module docs).
const DERIVED_STREAMS: u64 = 1 << 62;
/// First stream of the parameter sets (module docs).
const PARAMETER_SET_STREAMS: u64 = 1 << 63;

/// The stream `stream` of base seed `seed`. Monte Carlo run i draws from
/// `stream(seed, i)`, so its numbers do not depend on which thread runs it,
/// in which order, or how many runs there are.
pub fn stream(seed: u64, stream: u64) -> Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(stream);
    rng
}

/// The seed wherever none is given. `seed=None` has one meaning
/// everywhere in memsnav: this seed, so that a result never depends on the
/// operating system's entropy and a rerun reproduces it. Independent draws
/// need different seeds (or [`derive_seed`]).
pub const DEFAULT_SEED: u64 = 0;

/// A generator from an optional user seed (its stream 0); `None` is
/// [`DEFAULT_SEED`].
pub fn from_optional_seed(seed: Option<u64>) -> Rng {
    stream(seed.unwrap_or(DEFAULT_SEED), 0)
}

/// The seed of the independent draw named `purpose` made from user seed
/// `seed` (module docs): the first output of stream 2⁶² + h, h the 64-bit
/// FNV-1a hash of `purpose` reduced below 2⁶², so the name, not a position
/// in a list, fixes the draw.
pub fn derive_seed(seed: u64, purpose: &str) -> u64 {
    let hash = fnv1a(purpose.bytes());
    stream(seed, DERIVED_STREAMS + hash % DERIVED_STREAMS).random()
}

/// A generator for the draws named `purpose` made alongside `rng`, which
/// it leaves untouched: draws added to a computation (the simulator's
/// carrier phases) come from it, so the draws `rng` already fed (the
/// pseudoranges) stay the same. Its key is the first 32 bytes of stream
/// 2⁶² + h of `rng`'s key, h hashing `purpose` with `rng`'s stream and
/// position: Monte Carlo run i gets its own side stream, and so does each
/// of several computations fed in turn from one generator.
pub fn side_stream(rng: &Rng, purpose: &str) -> Rng {
    let hash = fnv1a(
        purpose
            .bytes()
            .chain(rng.get_stream().to_le_bytes())
            .chain(rng.get_word_pos().to_le_bytes()),
    );
    let mut keyed = ChaCha8Rng::from_seed(rng.get_seed());
    keyed.set_stream(DERIVED_STREAMS + hash % DERIVED_STREAMS);
    ChaCha8Rng::from_seed(keyed.random())
}

/// The 64-bit FNV-1a hash of `bytes`.
fn fnv1a(bytes: impl Iterator<Item = u8>) -> u64 {
    bytes.fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// Stream of parameter set `s` of a Monte Carlo whose runs use streams
/// 0, 1, ...: far above any run index (module docs).
pub fn parameter_set_stream(s: usize) -> u64 {
    PARAMETER_SET_STREAMS + s as u64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_are_reproducible_and_distinct() {
        let a: f64 = stream(7, 3).random();
        let b: f64 = stream(7, 3).random();
        let c: f64 = stream(7, 4).random();
        let d: f64 = stream(8, 3).random();
        assert_eq!(a, b);
        assert_ne!(a, c);
        assert_ne!(a, d);
        let e: f64 = from_optional_seed(Some(7)).random();
        let f: f64 = stream(7, 0).random();
        assert_eq!(e, f);
    }

    /// Derived seeds depend on the name and the seed, and never reproduce
    /// the `seed + 1` overlap: seed 0's derived draws differ from seed 1's
    /// plain stream.
    #[test]
    fn derived_seeds_are_distinct_and_unrelated_to_small_seeds() {
        let names = ["trajectory", "imu errors", "imu noise", "gnss"];
        let mut seen = std::collections::HashSet::new();
        for seed in 0..50u64 {
            for name in names {
                let d = derive_seed(seed, name);
                assert!(d >= 1 << 16, "{seed} {name}: {d}");
                assert!(seen.insert(d), "{seed} {name} repeats");
            }
        }
        assert_eq!(derive_seed(3, "gnss"), derive_seed(3, "gnss"));
        // FNV-1a of the empty name is its offset basis.
        assert_eq!(
            derive_seed(0, ""),
            stream(0, DERIVED_STREAMS + 0xcbf2_9ce4_8422_2325 % DERIVED_STREAMS).random::<u64>()
        );
    }

    /// A side stream leaves its generator as it was, is reproducible, and
    /// differs by name, by the generator's stream and by its position.
    #[test]
    fn side_streams_leave_the_generator_untouched() {
        let rng = stream(7, 3);
        let a: f64 = side_stream(&rng, "carrier").random();
        assert_eq!(a, side_stream(&stream(7, 3), "carrier").random::<f64>());
        assert_eq!(rng, stream(7, 3));
        assert_ne!(a, side_stream(&rng, "slips").random::<f64>());
        assert_ne!(a, side_stream(&stream(7, 4), "carrier").random::<f64>());
        let mut moved = stream(7, 3);
        let _: f64 = moved.random();
        assert_ne!(a, side_stream(&moved, "carrier").random::<f64>());
        // Not the generator's own numbers either.
        assert_ne!(a, stream(7, 3).random::<f64>());
    }
}
