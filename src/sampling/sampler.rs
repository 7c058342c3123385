//! Sample streams addressed by sample index.
//!
//! A [`Sampler`] hands out one [`SampleStream`] per sample index; the stream yields the
//! uniform numbers of that sample, dimension after dimension. Because a sample's
//! numbers depend only on (seed, index), any split of the indices over threads gives
//! bit-identical results.
//!
//! - **Independent**: PCG32 (O'Neill 2014) seeded by a SplitMix64 hash of (seed, index).
//! - **Stratified**: Latin hypercube within each batch of `batch` samples: in every
//!   dimension each of the strata [k/B, (k+1)/B) holds exactly one sample of the batch (a
//!   hashed permutation, Kensler 2013 "Correlated Multi-Jittered Sampling", picks
//!   which), jittered inside it and rounded to `f32` within it (for B up to 2²⁴, where
//!   the strata are no narrower than the `f32` spacing below 1).
//! - **Sobol**: Owen-scrambled Sobol (Burley 2020, "Practical Hash-based Owen
//!   Scrambling", via `sobol_burley`), 256 dimensions; each batch (at most 2¹⁶ samples)
//!   has its own scramble seed, and dimensions past 256 fall back to independent numbers.
//!
//! Batches are independent randomisations, so the spread of batch means gives an
//! honest standard error for the quasi-random samplers (randomised QMC; Owen 1997).

use crate::math::{ONE_MINUS_EPSILON, unit_float_from_bits};
use glam::Vec2;
use rand::Rng;
use rand_pcg::Pcg32;
use serde::{Deserialize, Serialize};

/// Which family of sample points to use.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum SamplerKind {
    /// Independent uniform numbers.
    #[default]
    Independent,
    /// Latin-hypercube stratification over the run's sample count.
    Stratified,
    /// Owen-scrambled Sobol.
    Sobol,
}

impl SamplerKind {
    /// All kinds, in report order.
    pub const ALL: [SamplerKind; 3] = [
        SamplerKind::Independent,
        SamplerKind::Stratified,
        SamplerKind::Sobol,
    ];

    /// Lower-case name.
    pub fn name(&self) -> &'static str {
        match self {
            SamplerKind::Independent => "independent",
            SamplerKind::Stratified => "stratified",
            SamplerKind::Sobol => "sobol",
        }
    }
}

/// SplitMix64 finaliser (Steele, Lea & Flood 2014): a bijective 64-bit hash.
#[inline]
pub fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// FNV-1a 64 of a byte stream (Fowler, Noll and Vo; offset basis 0xcbf29ce484222325,
/// prime 0x100000001b3): a hash of names that is stable across builds and platforms,
/// unlike `std`'s `DefaultHasher`.
pub fn fnv1a(bytes: impl IntoIterator<Item = u8>) -> u64 {
    bytes.into_iter().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
        (h ^ b as u64).wrapping_mul(0x100_0000_01b3)
    })
}

/// Hash of several words.
#[inline]
pub fn hash_words(words: &[u64]) -> u64 {
    let mut h = 0x9e37_79b9_7f4a_7c15u64;
    for &w in words {
        h = mix64(h ^ w.wrapping_add(0x9e37_79b9_7f4a_7c15));
    }
    h
}

/// A seeded pseudo-random permutation of `i` within [0, n), by cycle-walking a bijection
/// of [0, 2^k) (2^k the power of two at or above n), in the manner of Kensler's hashed
/// permutations (Kensler 2013, "Correlated multi-jittered sampling").
///
/// Each of four rounds applies bijections of [0, 2^k): XOR with a round key, an
/// odd multiply, an xorshift by ⌈k/2⌉ bits, and the addition of a second key, the keys
/// being hashes of (seed, round). Every step is invertible modulo 2^k, so the whole is a
/// permutation for every n, and the shift follows k so that small n mix too (a fixed
/// shift of 17 bits did nothing for n < 2¹⁷, which left n ≤ 8 with one or two orders for
/// every seed: sample 0 took the lowest stratum of every dimension).
fn permute(mut i: u64, n: u64, seed: u64) -> u64 {
    if n <= 1 {
        return 0;
    }
    let bits = 64 - (n - 1).leading_zeros();
    let w = if bits >= 64 {
        u64::MAX
    } else {
        (1u64 << bits) - 1
    };
    let shift = bits.div_ceil(2).max(1);
    let keys: [u64; 8] = std::array::from_fn(|r| hash_words(&[seed, r as u64]));
    loop {
        let mut x = i;
        for round in 0..4 {
            x = (x ^ keys[2 * round]) & w;
            x = x.wrapping_mul(0xe170_893d_6b5a_8a97 | 1) & w;
            x ^= x >> shift;
            x = x.wrapping_add(keys[2 * round + 1]) & w;
        }
        if x < n {
            return x;
        }
        i = x;
    }
}

/// A family of sample points for a run of `count` samples with a seed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sampler {
    /// Which family.
    pub kind: SamplerKind,
    /// The seed (recorded in every report).
    pub seed: u64,
    /// Samples per independent batch (stratification and scrambling work per batch).
    pub count: u64,
}

impl Sampler {
    /// A sampler of the given kind.
    pub fn new(kind: SamplerKind, seed: u64, count: u64) -> Self {
        Sampler {
            kind,
            seed,
            count: count.max(1),
        }
    }

    /// Independent samples with a seed.
    pub fn independent(seed: u64) -> Self {
        Sampler::new(SamplerKind::Independent, seed, 1)
    }

    /// The stream of sample `index`.
    #[inline]
    pub fn stream(&self, index: u64) -> SampleStream {
        let rng_seed = hash_words(&[self.seed, index]);
        // The Sobol scramble of the sample's block, hashed once per stream rather than
        // once per dimension (the same value either way).
        let scramble = match self.kind {
            SamplerKind::Sobol => hash_words(&[self.seed, index / self.count.min(1 << 16)]) as u32,
            SamplerKind::Independent | SamplerKind::Stratified => 0,
        };
        SampleStream {
            kind: self.kind,
            seed: self.seed,
            count: self.count,
            index,
            dim: 0,
            scramble,
            rng: Pcg32::new(rng_seed, hash_words(&[self.seed, 0x5eed]) | 1),
        }
    }
}

/// The uniform numbers of one sample, one dimension at a time.
#[derive(Clone, Debug)]
pub struct SampleStream {
    kind: SamplerKind,
    seed: u64,
    count: u64,
    index: u64,
    dim: u32,
    /// Owen scramble seed of the sample's Sobol block (0 for the other kinds).
    scramble: u32,
    rng: Pcg32,
}

impl SampleStream {
    /// The next uniform number in [0, 1).
    #[inline]
    pub fn next_1d(&mut self) -> f32 {
        // The independent stream inline (a few instructions, drawn several times per
        // path vertex); the quasi-random kinds out of line.
        match self.kind {
            SamplerKind::Independent => {
                self.dim += 1;
                unit_float_from_bits(self.rng.next_u32()).min(ONE_MINUS_EPSILON)
            }
            SamplerKind::Sobol | SamplerKind::Stratified => self.next_1d_quasi(),
        }
    }

    /// [`SampleStream::next_1d`] of the Sobol and stratified streams.
    #[inline(never)]
    fn next_1d_quasi(&mut self) -> f32 {
        let d = self.dim;
        self.dim += 1;
        let u = match self.kind {
            SamplerKind::Independent => unit_float_from_bits(self.rng.next_u32()),
            SamplerKind::Sobol if d < 256 => {
                let batch = self.count.min(1 << 16);
                sobol_burley::sample((self.index % batch) as u32, d, self.scramble)
            }
            SamplerKind::Sobol => unit_float_from_bits(self.rng.next_u32()),
            SamplerKind::Stratified => {
                let dim_seed = hash_words(&[self.seed, d as u64, self.index / self.count]);
                let stratum = permute(self.index % self.count, self.count, dim_seed);
                let jitter = unit_float_from_bits(self.rng.next_u32()) as f64;
                let count = self.count as f64;
                let x = (stratum as f64 + jitter) / count;
                // Rounded to f32 within the stratum: to nearest, a value just below
                // (k + 1)/B lands on it, in the next stratum (84 of 65 536 samples per
                // dimension at B = 2¹⁶), and where k/B is no f32 (B not a power of two) a
                // value just above it can round below, into the previous one.
                // v·B is exact in f64 for B ≤ 2²⁹ (24 + 29 bits), so one product decides
                // both edges without dividing.
                let v = x as f32;
                let scaled = v as f64 * count;
                if scaled >= (stratum + 1) as f64 {
                    v.next_down()
                } else if scaled < stratum as f64 {
                    v.next_up()
                } else {
                    v
                }
            }
        };
        u.min(ONE_MINUS_EPSILON)
    }

    /// The next two uniform numbers.
    #[inline]
    pub fn next_2d(&mut self) -> Vec2 {
        let a = self.next_1d();
        let b = self.next_1d();
        Vec2::new(a, b)
    }

    /// Dimensions consumed so far.
    pub fn dimension(&self) -> u32 {
        self.dim
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// FNV-1a 64 reference values (the empty string is the offset basis; "a" from the
    /// FNV authors' test vectors).
    #[test]
    fn fnv1a_matches_reference_vectors() {
        assert_eq!(fnv1a(*b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a(*b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a(*b"foobar"), 0x8594_4171_f739_67e8);
    }

    /// SplitMix64 seeded with 0 (Vigna's reference `splitmix64.c`): its k-th output is
    /// mix64(k · 0x9e3779b97f4a7c15).
    const GOLDEN: u64 = 0x9e37_79b9_7f4a_7c15;
    const SPLITMIX_FROM_ZERO: [u64; 4] = [
        0xe220_a839_7b1d_cdaf,
        0x6e78_9e6a_a1b9_65f4,
        0x06c4_5d18_8009_454f,
        0xf88b_b8a8_724c_81ec,
    ];

    #[test]
    fn mix64_is_the_splitmix64_finaliser() {
        for (k, want) in SPLITMIX_FROM_ZERO.iter().enumerate() {
            assert_eq!(
                mix64(GOLDEN.wrapping_mul(k as u64 + 1)),
                *want,
                "output {k}"
            );
        }
        assert_eq!(mix64(0), 0);
    }

    /// hash_words starts from the golden ratio and folds each word w as
    /// h ← mix64(h ⊕ (w + golden)): words chosen so that h ⊕ (w + golden) is k · golden
    /// land on SplitMix64's reference outputs.
    #[test]
    fn hash_words_chains_mix64_from_the_golden_ratio() {
        assert_eq!(hash_words(&[]), GOLDEN);
        // golden ⊕ (0 + golden) = 0, and mix64(0) = 0.
        assert_eq!(hash_words(&[0]), 0);
        // w = −golden: golden ⊕ 0 = golden.
        let w1 = GOLDEN.wrapping_neg();
        assert_eq!(hash_words(&[w1]), SPLITMIX_FROM_ZERO[0]);
        assert_eq!(hash_words(&[0, 0]), SPLITMIX_FROM_ZERO[0]);
        let w2 = (SPLITMIX_FROM_ZERO[0] ^ GOLDEN.wrapping_mul(2)).wrapping_sub(GOLDEN);
        assert_eq!(hash_words(&[w1, w2]), SPLITMIX_FROM_ZERO[1]);
    }

    #[test]
    fn names_are_the_json_spellings() {
        for kind in SamplerKind::ALL {
            let json = serde_json::to_string(&kind).unwrap();
            assert_eq!(json, format!("\"{}\"", kind.name()));
        }
        assert_eq!(SamplerKind::default(), SamplerKind::Independent);
    }

    #[test]
    fn permutation_of_zero_or_one_place_is_zero_and_the_widest_stays_in_range() {
        assert_eq!(permute(5, 0, 9), 0);
        assert_eq!(permute(0, 1, 9), 0);
        // n = 2⁶⁴ − 1: the mask is every bit (no 1 << 64 overflow).
        for i in [0u64, 1, 1 << 40, u64::MAX - 1] {
            assert!(permute(i, u64::MAX, 3) < u64::MAX);
        }
    }

    #[test]
    fn streams_count_their_dimensions_and_sobol_falls_back_past_256() {
        for kind in SamplerKind::ALL {
            let mut st = Sampler::new(kind, 1, 64).stream(5);
            st.next_2d();
            st.next_1d();
            assert_eq!(st.dimension(), 3);
            for _ in 3..300 {
                let u = st.next_1d();
                assert!((0.0..1.0).contains(&u), "{kind:?}: {u}");
            }
            assert_eq!(st.dimension(), 300);
        }
    }

    /// Each Sobol batch starts the sequence afresh: the first four samples of every batch
    /// (here batches of 5, so not aligned with the sequence's blocks of four) are the
    /// sequence's first four points, which fall in four different quarters of every
    /// dimension.
    #[test]
    fn every_sobol_batch_starts_at_the_first_point() {
        for seed in 0..8u64 {
            let s = Sampler::new(SamplerKind::Sobol, seed, 5);
            for batch in 0..3u64 {
                let mut streams: Vec<SampleStream> =
                    (0..4).map(|i| s.stream(5 * batch + i)).collect();
                for dim in 0..8 {
                    let mut quarters: Vec<usize> = streams
                        .iter_mut()
                        .map(|st| (st.next_1d() * 4.0) as usize)
                        .collect();
                    quarters.sort_unstable();
                    assert_eq!(
                        quarters,
                        [0, 1, 2, 3],
                        "seed {seed} batch {batch} dim {dim}"
                    );
                }
            }
        }
    }

    /// Each batch of a quasi-random run is its own randomisation (what its batch-means
    /// error bar assumes): the same point of two batches differs, in every one of the
    /// first 16 dimensions for Sobol (another Owen scramble) and in most for stratified
    /// (another permutation of the strata, another jitter).
    #[test]
    fn every_batch_is_another_randomisation() {
        for kind in [SamplerKind::Sobol, SamplerKind::Stratified] {
            for seed in 0..4u64 {
                let s = Sampler::new(kind, seed, 64);
                for i in [0u64, 5, 63] {
                    let (mut a, mut b, mut c) = (s.stream(i), s.stream(64 + i), s.stream(128 + i));
                    let differ = (0..16)
                        .filter(|_| {
                            let (x, y, z) = (a.next_1d(), b.next_1d(), c.next_1d());
                            x != y && y != z && x != z
                        })
                        .count();
                    assert_eq!(differ, 16, "{kind:?} seed {seed} point {i}");
                }
            }
        }
    }

    #[test]
    fn small_permutations_depend_on_the_seed() {
        for n in 2..=16u64 {
            let mut orders = std::collections::HashSet::new();
            let mut first = std::collections::HashSet::new();
            for seed in 0..256u64 {
                let p: Vec<u64> = (0..n).map(|i| permute(i, n, seed)).collect();
                let mut q = p.clone();
                q.sort_unstable();
                assert_eq!(q, (0..n).collect::<Vec<_>>(), "not a permutation");
                first.insert(p[0]);
                orders.insert(p);
            }
            // Distinct orders expected from 256 uniformly random permutations of n!:
            // n!(1 − (1 − 1/n!)^256); demand 80% of it.
            let factorial: f64 = (1..=n).map(|k| k as f64).product();
            let expected = factorial * (1.0 - (1.0 - 1.0 / factorial).powi(256));
            assert!(
                orders.len() as f64 >= 0.8 * expected,
                "n = {n}: only {} orders over 256 seeds (uniform: {expected:.0})",
                orders.len()
            );
            assert_eq!(
                first.len() as u64,
                n,
                "n = {n}: element 0 does not reach every place"
            );
        }
    }

    #[test]
    fn permutation_is_a_bijection() {
        for n in [1u64, 2, 7, 64, 1000] {
            let mut seen = vec![false; n as usize];
            for i in 0..n {
                let p = permute(i, n, 12345) as usize;
                assert!(!seen[p]);
                seen[p] = true;
            }
        }
    }

    #[test]
    fn stratified_fills_every_stratum_in_every_dimension() {
        // 1000 per batch over 200 seeds and 2¹⁶ over one: at 2¹⁶ the f32 rounding to
        // nearest put 84 samples per dimension into the next stratum, and at 1000 (k/B no
        // f32) about 5·10⁻⁶ of them into the previous one, before each was rounded within
        // its own.
        let runs = (0..200u64)
            .map(|seed| (1000u64, seed))
            .chain([(1 << 16, 7)]);
        for (n, seed) in runs {
            let s = Sampler::new(SamplerKind::Stratified, seed, n);
            for dim in 0..4 {
                let mut seen = vec![false; n as usize];
                for i in 0..n {
                    let mut st = s.stream(i);
                    let mut u = 0.0;
                    for _ in 0..=dim {
                        u = st.next_1d();
                    }
                    let k = (u as f64 * n as f64) as usize;
                    assert!(
                        !seen[k],
                        "n = {n}, seed {seed}: stratum {k} twice in dim {dim}"
                    );
                    seen[k] = true;
                }
            }
        }
    }

    #[test]
    fn sobol_is_stratified_in_2d() {
        // The first 2^k points of a (0,2)-sequence put one point in each of the 2^k
        // elementary intervals of every shape (here 16 x 16 for 256 points).
        let s = Sampler::new(SamplerKind::Sobol, 3, 256);
        let mut seen = [[false; 16]; 16];
        for i in 0..256 {
            let u = s.stream(i).next_2d();
            let (a, b) = ((u.x * 16.0) as usize, (u.y * 16.0) as usize);
            assert!(!seen[a][b]);
            seen[a][b] = true;
        }
    }

    #[test]
    fn streams_depend_only_on_seed_and_index() {
        for kind in SamplerKind::ALL {
            let s = Sampler::new(kind, 42, 100);
            let a: Vec<f32> = (0..5)
                .map(|_| 0.0)
                .scan(s.stream(17), |st, _| Some(st.next_1d()))
                .collect();
            let b: Vec<f32> = (0..5)
                .map(|_| 0.0)
                .scan(s.stream(17), |st, _| Some(st.next_1d()))
                .collect();
            assert_eq!(a, b);
            assert!(a.iter().all(|u| (0.0..1.0).contains(u)));
        }
    }
}
