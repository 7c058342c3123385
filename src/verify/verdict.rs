//! From an estimate to a verdict: which standard error a verdict uses, whether the
//! estimate is exact, and the judgement itself.
//!
//! **Error bar.** With independent samples the plain standard error √(s²/N) is used,
//! unless the batch-means error exceeds it by half (heavy tails), when the batch-means
//! t test (B − 1 = 127 degrees of freedom) takes over; quasi-random samplers are always
//! judged by batch means, each batch being an independent randomisation. The error bar
//! is chosen from the estimate alone, never from the reference, so `estimate` prints
//! the same `std_error` with or without one.
//!
//! **Classes.** An estimate whose samples agree to f32 rounding is *exact*
//! ([`crate::stats::is_exact`]): it is compared within the stated f32 error bound and
//! is not a member of the Šidák family. Every other estimate is *statistical*: a z (or
//! t) test at the family's per-test level, reporting the bias it detects with 99% power.

use crate::sampling::SamplerKind;
use crate::stats::{MeanTest, Verdict, is_exact};
use crate::transport::engine::Estimate;
use serde::{Deserialize, Serialize};

/// The standard error a verdict on an estimate uses.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ErrorBar {
    /// `None` for an exact estimate (no variance); otherwise the standard error.
    pub std_error: Option<f64>,
    /// Degrees of freedom of the batch-means t test, when it decides.
    pub dof: Option<u64>,
}

impl ErrorBar {
    /// The error bar of an estimate drawn with `sampler`.
    pub fn of(est: &Estimate, sampler: SamplerKind) -> ErrorBar {
        let total = &est.batches.total;
        if is_exact(total) {
            return ErrorBar {
                std_error: None,
                dof: None,
            };
        }
        let plain = total.std_error();
        let batch = est.batches.std_error();
        if sampler != SamplerKind::Independent || batch > 1.5 * plain {
            ErrorBar {
                std_error: Some(batch),
                dof: Some(est.batches.dof()),
            }
        } else {
            ErrorBar {
                std_error: Some(plain),
                dof: None,
            }
        }
    }

    /// Whether the estimate is exact.
    pub fn exact(&self) -> bool {
        self.std_error.is_none()
    }
}

/// Judge an estimate's parts within a family of `tests` statistical tests at level
/// `alpha` (an exact estimate is judged exactly, outside the family).
pub fn judge_parts(
    estimate: f64,
    bar: &ErrorBar,
    reference: f64,
    non_finite: u64,
    count: u64,
    alpha: f64,
    tests: usize,
) -> Verdict {
    let t = MeanTest::new(alpha, tests);
    match bar.std_error {
        None => t.judge_exact(estimate, reference, non_finite, count),
        Some(se) => t.judge_parts(estimate, se, reference, bar.dof, non_finite, count),
    }
}

/// Judge an estimate against a reference within a family of `tests` statistical tests.
pub fn judge(
    est: &Estimate,
    sampler: SamplerKind,
    reference: f64,
    alpha: f64,
    tests: usize,
) -> Verdict {
    let total = &est.batches.total;
    judge_parts(
        total.mean,
        &ErrorBar::of(est, sampler),
        reference,
        total.non_finite,
        total.count,
        alpha,
        tests,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::{Accumulator, BatchMeans, VerdictClass};

    fn estimate(batches: Vec<Accumulator>) -> Estimate {
        Estimate {
            batches: BatchMeans::from_batches(batches),
            seconds: 0.0,
        }
    }

    fn batch(xs: &[f64]) -> Accumulator {
        let mut a = Accumulator::new();
        xs.iter().for_each(|&x| a.push(x));
        a
    }

    #[test]
    fn error_bar_depends_on_the_sampler_and_the_tails_only() {
        // Batches that agree with the plain error: independent uses it, Sobol batch means.
        let even: Vec<_> = (0..16)
            .map(|i| batch(&[0.0, 1.0, (i % 2) as f64]))
            .collect();
        let e = estimate(even);
        let ind = ErrorBar::of(&e, SamplerKind::Independent);
        assert_eq!(ind.dof, None);
        assert!(!ind.exact());
        assert_eq!(ind.std_error, Some(e.batches.total.std_error()));
        let sob = ErrorBar::of(&e, SamplerKind::Sobol);
        assert_eq!(sob.dof, Some(15));
        assert_eq!(sob.std_error, Some(e.batches.std_error()));
        // Batch means far apart (correlated samples): independent switches to them.
        let lumpy: Vec<_> = (0..16).map(|i| batch(&[i as f64; 8])).collect();
        let l = estimate(lumpy);
        assert!(l.batches.std_error() > 1.5 * l.batches.total.std_error());
        assert_eq!(ErrorBar::of(&l, SamplerKind::Independent).dof, Some(15));
        // Identical samples: exact, no error bar at all.
        let flat = estimate((0..4).map(|_| batch(&[2.5, 2.5])).collect());
        let b = ErrorBar::of(&flat, SamplerKind::Stratified);
        assert!(b.exact() && b.dof.is_none());
        let v = judge(&flat, SamplerKind::Stratified, 2.5, 1e-4, 10);
        assert!(v.passed && v.class == VerdictClass::Exact);
        assert!(!judge(&flat, SamplerKind::Stratified, 2.6, 1e-4, 10).passed);
    }

    #[test]
    fn a_statistical_verdict_uses_the_family_size() {
        let xs: Vec<_> = (0..64)
            .map(|i| batch(&[(i % 7) as f64, (i % 3) as f64]))
            .collect();
        let e = estimate(xs);
        let one = judge(&e, SamplerKind::Independent, 1.0, 1e-4, 1);
        let many = judge(&e, SamplerKind::Independent, 1.0, 1e-4, 1000);
        assert!(many.critical > one.critical);
        assert_eq!(one.class, VerdictClass::Statistical);
    }
}
