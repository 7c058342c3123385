//! Running an estimator: N samples cut into B equal batches, batches spread over rayon's
//! threads, each batch accumulated in index order, batches merged in batch order. A
//! sample's random numbers depend only on (seed, sample index), so the result is
//! bit-identical for any number of threads. Any subset of batches can run on its own
//! (shards on several machines) and merge into exactly the single-run accumulators.

use crate::sampling::{SampleStream, Sampler, SamplerKind};
use crate::stats::{Accumulator, BatchMeans};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Number of batches of every run (the batch-means t test has B − 1 degrees of freedom).
pub const BATCHES: u64 = 128;

/// How many samples, drawn how.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct RunSpec {
    /// Requested sample count (rounded up to B × batch size).
    pub samples: u64,
    /// Sample family.
    pub sampler: SamplerKind,
    /// Seed.
    pub seed: u64,
}

impl RunSpec {
    /// Samples per batch: ⌈N/B⌉, a power of two for the quasi-random samplers.
    pub fn batch_size(&self) -> u64 {
        let b = self.samples.div_ceil(BATCHES).max(1);
        match self.sampler {
            SamplerKind::Independent => b,
            SamplerKind::Stratified | SamplerKind::Sobol => b.next_power_of_two(),
        }
    }

    /// Samples actually drawn.
    pub fn total(&self) -> u64 {
        self.batch_size() * BATCHES
    }

    /// The sampler of this run.
    pub fn sampler(&self) -> Sampler {
        Sampler::new(self.sampler, self.seed, self.batch_size())
    }
}

/// A finished run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Estimate {
    /// Per-batch accumulators and their merge.
    pub batches: BatchMeans,
    /// Wall-clock seconds.
    pub seconds: f64,
}

/// Run batches `range` of `spec` with the one-sample estimator `f`.
pub fn run_batches<F>(spec: &RunSpec, range: std::ops::Range<u64>, f: F) -> Vec<Accumulator>
where
    F: Fn(&mut SampleStream) -> f32 + Sync,
{
    let sampler = spec.sampler();
    let bs = spec.batch_size();
    range
        .into_par_iter()
        .map(|b| {
            let mut acc = Accumulator::new();
            for i in b * bs..(b + 1) * bs {
                let mut s = sampler.stream(i);
                acc.push(f(&mut s) as f64);
            }
            acc
        })
        .collect()
}

/// Run all batches.
pub fn run<F>(spec: &RunSpec, f: F) -> Estimate
where
    F: Fn(&mut SampleStream) -> f32 + Sync,
{
    let t0 = Instant::now();
    let batches = run_batches(spec, 0..BATCHES, f);
    Estimate {
        batches: BatchMeans::from_batches(batches),
        seconds: t0.elapsed().as_secs_f64(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The README's rounding: a request rounds up to a multiple of the 128 batches, and
    /// for the quasi-random samplers to 128 × a power of two (so that each batch is a
    /// whole power-of-two block of the sequence).
    #[test]
    fn sample_counts_round_up_to_whole_batches() {
        let spec = |samples, sampler| RunSpec {
            samples,
            sampler,
            seed: 1,
        };
        for (n, independent, quasi) in [
            (256, 256, 256),
            (300, 384, 512),
            (1000, 1024, 1024),
            (1025, 1152, 2048),
            (4096, 4096, 4096),
            (1 << 40, 1 << 40, 1 << 40),
            ((1 << 40) + 1, (1 << 40) + 128, 1 << 41),
        ] {
            assert_eq!(
                spec(n, SamplerKind::Independent).total(),
                independent,
                "{n}"
            );
            for s in [SamplerKind::Stratified, SamplerKind::Sobol] {
                let r = spec(n, s);
                assert_eq!(r.total(), quasi, "{n} {s:?}");
                assert!(r.batch_size().is_power_of_two());
            }
        }
    }
}
