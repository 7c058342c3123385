//! Mergeable accumulators of samples in `f64`.
//!
//! Welford's update keeps the mean and M₂ = Σ(xᵢ − x̄)² stable; two accumulators merge
//! with Chan et al.'s formula M₂ = M₂ₐ + M₂ᵦ + δ² nₐ nᵦ / n, δ = x̄ᵦ − x̄ₐ, so sample
//! blocks can be summed in any grouping (up to rounding) and, merged in index order,
//! bit-identically whatever the thread count. Non-finite samples are counted and never
//! enter the moments: a test that sees any of them fails.

use serde::{Deserialize, Serialize};

/// Count, mean and M₂ of a stream of samples, plus the count of non-finite ones.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Accumulator {
    /// Number of finite samples.
    pub count: u64,
    /// Their mean.
    pub mean: f64,
    /// Σ (x − mean)².
    pub m2: f64,
    /// Number of NaN or infinite samples seen (each one is a failure).
    pub non_finite: u64,
}

impl Accumulator {
    /// An empty accumulator.
    pub fn new() -> Self {
        Self::default()
    }

    /// Add one sample.
    #[inline]
    pub fn push(&mut self, x: f64) {
        if !x.is_finite() {
            self.non_finite += 1;
            return;
        }
        self.count += 1;
        let delta = x - self.mean;
        self.mean += delta / self.count as f64;
        self.m2 += delta * (x - self.mean);
    }

    /// Merge another accumulator into this one.
    pub fn merge(&mut self, other: &Accumulator) {
        self.non_finite += other.non_finite;
        if other.count == 0 {
            return;
        }
        if self.count == 0 {
            let nf = self.non_finite;
            *self = *other;
            self.non_finite = nf;
            return;
        }
        let n = self.count + other.count;
        let delta = other.mean - self.mean;
        let w = other.count as f64 / n as f64;
        self.mean += delta * w;
        self.m2 += other.m2 + delta * delta * self.count as f64 * w;
        self.count = n;
    }

    /// Merged copy.
    pub fn merged(mut self, other: &Accumulator) -> Self {
        self.merge(other);
        self
    }

    /// Unbiased sample variance.
    pub fn variance(&self) -> f64 {
        if self.count > 1 {
            self.m2 / (self.count - 1) as f64
        } else {
            0.0
        }
    }

    /// Standard error of the mean, √(s²/n).
    pub fn std_error(&self) -> f64 {
        if self.count > 1 {
            (self.variance() / self.count as f64).sqrt()
        } else {
            f64::INFINITY
        }
    }
}

impl FromIterator<f64> for Accumulator {
    /// The accumulator of a stream of samples, pushed in order.
    fn from_iter<I: IntoIterator<Item = f64>>(xs: I) -> Self {
        let mut a = Accumulator::new();
        xs.into_iter().for_each(|x| a.push(x));
        a
    }
}

/// Batch means: the run's samples are cut into equal consecutive batches and the
/// standard error is estimated from the spread of the batch means (Law & Kelton,
/// "Simulation Modeling and Analysis", §9.5.3). Robust when single samples are heavy
/// tailed or correlated (quasi-Monte Carlo), at the price of B − 1 degrees of freedom.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct BatchMeans {
    /// All samples.
    pub total: Accumulator,
    /// One accumulator per batch.
    pub batches: Vec<Accumulator>,
}

impl BatchMeans {
    /// From per-batch accumulators, merged in order.
    pub fn from_batches(batches: Vec<Accumulator>) -> Self {
        let mut total = Accumulator::new();
        for b in &batches {
            total.merge(b);
        }
        BatchMeans { total, batches }
    }

    /// Accumulator over the batch means.
    pub fn of_means(&self) -> Accumulator {
        let mut a = Accumulator::new();
        for b in self.batches.iter().filter(|b| b.count > 0) {
            a.push(b.mean);
        }
        a
    }

    /// Standard error of the grand mean from the batch means.
    pub fn std_error(&self) -> f64 {
        self.of_means().std_error()
    }

    /// Degrees of freedom of the batch-means t statistic.
    pub fn dof(&self) -> u64 {
        self.of_means().count.saturating_sub(1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #[test]
        fn merge_equals_accumulating_all(xs in prop::collection::vec(-1e3f64..1e3, 0..200), split in 0usize..200) {
            let split = split.min(xs.len());
            let mut all = Accumulator::new();
            xs.iter().for_each(|&x| all.push(x));
            let mut a = Accumulator::new();
            let mut b = Accumulator::new();
            xs[..split].iter().for_each(|&x| a.push(x));
            xs[split..].iter().for_each(|&x| b.push(x));
            let m = a.merged(&b);
            prop_assert_eq!(m.count, all.count);
            prop_assert!((m.mean - all.mean).abs() <= 1e-9 * (1.0 + all.mean.abs()));
            prop_assert!((m.m2 - all.m2).abs() <= 1e-9 * (1.0 + all.m2));
        }
    }

    #[test]
    fn non_finite_is_counted_not_dropped() {
        let mut a = Accumulator::new();
        a.push(1.0);
        a.push(f64::NAN);
        a.push(f64::INFINITY);
        assert_eq!(a.count, 1);
        assert_eq!(a.non_finite, 2);
        let b = Accumulator::new().merged(&a);
        assert_eq!(b.non_finite, 2);
    }

    #[test]
    fn batch_means_of_constant_batches() {
        let mk = |v: f64| {
            let mut a = Accumulator::new();
            (0..10).for_each(|_| a.push(v));
            a
        };
        let bm = BatchMeans::from_batches(vec![mk(1.0), mk(2.0), mk(3.0)]);
        assert_eq!(bm.total.count, 30);
        assert!((bm.total.mean - 2.0).abs() < 1e-12);
        assert!((bm.std_error() - (1.0f64 / 3.0).sqrt()).abs() < 1e-12);
        assert_eq!(bm.dof(), 2);
    }
}
