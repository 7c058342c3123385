//! One-sample test of a Monte Carlo estimate against a reference value.
//!
//! With estimate x̄, standard error s and reference μ, the statistic is z = (x̄ − μ)/s,
//! referred to the standard normal (or to Student's t with ν degrees of freedom for
//! batch means). A suite of k tests at family-wise level α uses the Šidák per-test level
//! α₁ = 1 − (1 − α)^{1/k} (Šidák 1967), exact for independent tests.
//!
//! **Power.** The smallest bias δ that the two-sided test at level α₁ detects with
//! probability 1 − β is δ = (q₁₋α₁/₂ + q₁₋β)·s; with β = 0.01 this is the test's
//! "detectable bias", reported relative to |μ|. A test whose detectable bias is larger
//! than the error you care about proves nothing about that error.
//!
//! **Non-finite samples** make the verdict fail regardless of the statistic.

use crate::stats::Accumulator;
use serde::{Deserialize, Serialize};
use statrs::distribution::{ContinuousCDF, Normal, StudentsT};

/// Šidák-corrected per-test significance for `k` tests at family-wise level `alpha`.
pub fn sidak_alpha(alpha: f64, k: usize) -> f64 {
    let k = k.max(1) as f64;
    // 1 − (1 − α)^{1/k} computed without cancellation.
    -((-alpha).ln_1p() / k).exp_m1()
}

/// The power the detectable bias is quoted at.
pub const POWER: f64 = 0.99;

/// Configuration of a (family of) mean test(s).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct MeanTest {
    /// Family-wise significance level.
    pub alpha: f64,
    /// Number of tests in the family (Šidák).
    pub tests: usize,
}

impl Default for MeanTest {
    fn default() -> Self {
        MeanTest {
            alpha: 1e-4,
            tests: 1,
        }
    }
}

/// Outcome of a mean test.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Verdict {
    /// The estimate x̄.
    pub estimate: f64,
    /// Its standard error.
    pub std_error: f64,
    /// The reference μ.
    pub reference: f64,
    /// (x̄ − μ)/s.
    pub z: f64,
    /// Two-sided p value (one-sided where the test is one-sided).
    pub p_value: f64,
    /// Per-test significance after the Šidák correction.
    pub alpha: f64,
    /// Critical |z|.
    pub critical: f64,
    /// Smallest absolute bias detected with 99% power.
    pub detectable_bias: f64,
    /// `detectable_bias / |μ|`.
    pub detectable_relative_bias: f64,
    /// Degrees of freedom when a t distribution is used.
    pub dof: Option<u64>,
    /// Number of non-finite samples seen.
    pub non_finite: u64,
    /// The verdict.
    pub passed: bool,
    /// Why it failed, if it did.
    pub reason: Option<String>,
}

fn quantile(p: f64, dof: Option<u64>) -> f64 {
    match dof {
        Some(n) if n > 0 => StudentsT::new(0.0, 1.0, n as f64)
            .map(|t| t.inverse_cdf(p))
            .unwrap_or(f64::INFINITY),
        _ => Normal::standard().inverse_cdf(p),
    }
}

fn upper_tail(z: f64, dof: Option<u64>) -> f64 {
    match dof {
        Some(n) if n > 0 => StudentsT::new(0.0, 1.0, n as f64)
            .map(|t| t.sf(z))
            .unwrap_or(0.0),
        _ => Normal::standard().sf(z),
    }
}

impl MeanTest {
    /// A family of `tests` tests at family-wise level `alpha`.
    pub fn new(alpha: f64, tests: usize) -> Self {
        MeanTest { alpha, tests }
    }

    /// The per-test level.
    pub fn per_test_alpha(&self) -> f64 {
        sidak_alpha(self.alpha, self.tests)
    }

    /// Two-sided test of an accumulator's mean against `reference` (z test).
    pub fn judge(&self, acc: &Accumulator, reference: f64) -> Verdict {
        self.judge_parts(
            acc.mean,
            acc.std_error(),
            reference,
            None,
            acc.non_finite,
            acc.count,
        )
    }

    /// Two-sided test from a mean, standard error and optional t degrees of freedom.
    pub fn judge_parts(
        &self,
        estimate: f64,
        std_error: f64,
        reference: f64,
        dof: Option<u64>,
        non_finite: u64,
        count: u64,
    ) -> Verdict {
        let alpha = self.per_test_alpha();
        let critical = quantile(1.0 - alpha / 2.0, dof);
        let power_q = quantile(POWER, dof);
        let diff = estimate - reference;
        let (z, p_value) = if std_error > 0.0 && std_error.is_finite() {
            let z = diff / std_error;
            (z, (2.0 * upper_tail(z.abs(), dof)).min(1.0))
        } else if diff == 0.0 {
            (0.0, 1.0)
        } else {
            (f64::INFINITY.copysign(diff), 0.0)
        };
        let detectable_bias = (critical + power_q) * std_error;
        let detectable_relative_bias = if reference != 0.0 {
            detectable_bias / reference.abs()
        } else {
            detectable_bias
        };
        let mut reason = None;
        if non_finite > 0 {
            reason = Some(format!("{non_finite} non-finite samples (NaN or Inf)"));
        } else if count < 2 {
            reason = Some("fewer than two finite samples".into());
        } else if !reference.is_finite() {
            reason = Some("reference is not finite".into());
        } else if p_value < alpha || !estimate.is_finite() {
            reason = Some(format!(
                "|z| = {:.2} exceeds the critical value {critical:.2} (p = {p_value:.2e} < α = {alpha:.2e})",
                z.abs()
            ));
        }
        Verdict {
            estimate,
            std_error,
            reference,
            z,
            p_value,
            alpha,
            critical,
            detectable_bias,
            detectable_relative_bias,
            dof,
            non_finite,
            passed: reason.is_none(),
            reason,
        }
    }

    /// One-sided test that the mean is not above `bound` (e.g. albedo ≤ 1): fails
    /// when (x̄ − bound)/s exceeds the one-sided critical value.
    pub fn judge_at_most(&self, acc: &Accumulator, bound: f64) -> Verdict {
        let alpha = self.per_test_alpha();
        let critical = quantile(1.0 - alpha, None);
        let power_q = quantile(POWER, None);
        let s = acc.std_error();
        let diff = acc.mean - bound;
        let z = if s > 0.0 && s.is_finite() {
            diff / s
        } else if diff > 0.0 {
            f64::INFINITY
        } else {
            f64::NEG_INFINITY
        };
        let p_value = upper_tail(z, None);
        let detectable_bias = (critical + power_q) * s;
        let mut reason = None;
        if acc.non_finite > 0 {
            reason = Some(format!(
                "{} non-finite samples (NaN or Inf)",
                acc.non_finite
            ));
        } else if p_value < alpha {
            reason = Some(format!(
                "mean {:.6} exceeds the bound {bound} by z = {z:.2} (p = {p_value:.2e})",
                acc.mean
            ));
        }
        Verdict {
            estimate: acc.mean,
            std_error: s,
            reference: bound,
            z,
            p_value,
            alpha,
            critical,
            detectable_bias,
            detectable_relative_bias: detectable_bias / bound.abs().max(f64::MIN_POSITIVE),
            dof: None,
            non_finite: acc.non_finite,
            passed: reason.is_none(),
            reason,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sidak_matches_definition() {
        let a = sidak_alpha(0.01, 10);
        assert!((a - (1.0 - 0.99f64.powf(0.1))).abs() < 1e-15);
        assert!((sidak_alpha(1e-4, 1) - 1e-4).abs() < 1e-18);
    }

    #[test]
    fn detects_a_shift_and_accepts_truth() {
        let mut acc = Accumulator::new();
        for i in 0..10_000 {
            acc.push(((i * 7919) % 1000) as f64 / 1000.0);
        }
        let t = MeanTest::new(1e-4, 1);
        assert!(t.judge(&acc, acc.mean).passed);
        let shifted = acc.mean + 10.0 * acc.std_error();
        let v = t.judge(&acc, shifted);
        assert!(!v.passed && v.p_value < 1e-10);
        // Detectable bias: (3.89 + 2.33) s.
        assert!((v.detectable_bias / acc.std_error() - 6.22).abs() < 0.02);
    }

    #[test]
    fn nan_fails() {
        let mut acc = Accumulator::new();
        (0..100).for_each(|i| acc.push(i as f64));
        acc.push(f64::NAN);
        let v = MeanTest::default().judge(&acc, acc.mean);
        assert!(!v.passed);
        assert!(v.reason.unwrap().contains("non-finite"));
    }

    #[test]
    fn one_sided_bound() {
        let mut acc = Accumulator::new();
        (0..1000).for_each(|i| acc.push(0.9 + 0.2 * ((i % 10) as f64 / 10.0)));
        assert!(!MeanTest::default().judge_at_most(&acc, 0.95).passed);
        assert!(MeanTest::default().judge_at_most(&acc, 1.0).passed);
    }
}
