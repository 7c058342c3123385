//! Mean tests for samples with a known range, which need no central limit theorem.
//!
//! A z test's stated level holds only once the sample mean is near normal; a rare lobe
//! (a weight that is 0 once in 10⁴ draws) makes the samples so skewed that millions are
//! needed before the normal tail can be trusted at a Šidák level of 1e-7
//! ([`MeanTest::clt_samples`]). When every sample is known to lie in an interval of
//! width b — an energy weight G2/G1 ∈ [0, 1] — the empirical Bernstein bound (Maurer &
//! Pontil, "Empirical Bernstein Bounds and Sample Variance Penalization", COLT 2009,
//! Theorem 4) holds for every n ≥ 2 and every distribution on the interval:
//!
//! P( μ − x̄ > √(2 V ln(2/δ)/n) + 7 b ln(2/δ)/(3(n − 1)) ) ≤ δ,
//!
//! with V the unbiased sample variance; the same holds for x̄ − μ (apply it to b − x).
//! A two-sided test at level α₁ spends δ = α₁/2 on each side, so it rejects when
//! |x̄ − μ| − τ exceeds h = √(2 V L/n) + 7 b L/(3(n − 1)) with L = ln(4/α₁); the
//! one-sided test (mean ≤ bound) uses L = ln(2/α₁). τ is the f32 rounding allowance of
//! [`MeanTest::rounding_allowance`], as in every statistical verdict.
//!
//! The p value is the δ at which the bound would just reach the observed excess e:
//! with c = √(2V/n) and a = 7b/(3(n − 1)), √L = (√(c² + 4ae) − c)/(2a) and
//! p = 4e^{−L} (two-sided) or 2e^{−L} (one-sided), capped at 1. The verdict fails
//! exactly when p < α₁, i.e. when the excess exceeds h.
//!
//! **Power.** A bias δ is found with probability ≥ 99% once δ ≥ τ + h + q₀.₉₉·s,
//! s = √(V/n) (the estimate itself is near normal around μ + δ at the sample counts
//! used; the level does not depend on that): the reported detectable bias. For a
//! skewed, low-variance weight the range term 7bL/(3n) dominates and a few ten thousand
//! samples detect well under 1%, where the CLT guard asked for millions; for a
//! high-variance weight √(2L) ≈ 5.9 exceeds the normal critical value ≈ 5.3 and the
//! z test is the cheaper of the two (the caller picks before drawing the samples).
//!
//! **Range.** The caller states the interval [lo, lo + b] from the model's theory and
//! passes the smallest and largest sample seen: one sample outside fails the verdict
//! (the model broke the bound the test relies on).

use crate::stats::hypothesis::{non_finite_moments, non_finite_reason};
use crate::stats::{Accumulator, MeanTest, Verdict, is_exact_at};
use statrs::distribution::{ContinuousCDF, Normal};

/// Samples' promised interval and the extremes actually seen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Range {
    /// Promised lower end.
    pub lo: f64,
    /// Promised upper end.
    pub hi: f64,
    /// Smallest finite sample seen.
    pub min: f64,
    /// Largest finite sample seen.
    pub max: f64,
}

impl Range {
    /// Width b = hi − lo of the promised interval.
    pub fn width(&self) -> f64 {
        self.hi - self.lo
    }

    fn violation(&self) -> Option<String> {
        if !(self.lo <= self.hi) {
            Some(format!("empty range [{}, {}]", self.lo, self.hi))
        } else if self.min < self.lo || self.max > self.hi {
            Some(format!(
                "samples in [{:.9}, {:.9}], outside the promised range [{}, {}]",
                self.min, self.max, self.lo, self.hi
            ))
        } else {
            None
        }
    }
}

/// The Bernstein half-width h = c√L + aL and, for an excess e, the p value of the bound.
struct Bernstein {
    c: f64,
    a: f64,
}

impl Bernstein {
    fn new(acc: &Accumulator, width: f64) -> Bernstein {
        let n = acc.count as f64;
        Bernstein {
            c: (2.0 * acc.variance() / n).sqrt(),
            a: 7.0 * width / (3.0 * (n - 1.0)),
        }
    }

    fn half_width(&self, l: f64) -> f64 {
        self.c * l.sqrt() + self.a * l
    }

    /// The L at which the half-width equals `excess` (0 for no excess).
    fn level(&self, excess: f64) -> f64 {
        if !(excess > 0.0) {
            return 0.0;
        }
        if self.a == 0.0 {
            return if self.c > 0.0 {
                (excess / self.c).powi(2)
            } else {
                f64::INFINITY
            };
        }
        let root = ((self.c * self.c + 4.0 * self.a * excess).sqrt() - self.c) / (2.0 * self.a);
        root * root
    }
}

impl MeanTest {
    /// Two-sided empirical Bernstein test that the mean of samples in `range` equals
    /// `reference` (see the module notes), or the exact comparison when the samples have
    /// no variance.
    pub fn judge_bounded(&self, acc: &Accumulator, range: Range, reference: f64) -> Verdict {
        self.bounded(acc, range, reference, true)
    }

    /// One-sided empirical Bernstein test that the mean of samples in `range` is not
    /// above `bound`.
    pub fn judge_bounded_at_most(&self, acc: &Accumulator, range: Range, bound: f64) -> Verdict {
        self.bounded(acc, range, bound, false)
    }

    /// The detectable bias of a bounded test of `n` samples of variance `variance` in an
    /// interval of width `width` around `reference` (for choosing n before sampling).
    pub fn bounded_detectable_bias(
        &self,
        n: u64,
        variance: f64,
        width: f64,
        reference: f64,
        two_sided: bool,
    ) -> f64 {
        let acc = Accumulator {
            count: n,
            mean: 0.0,
            m2: variance * n.saturating_sub(1) as f64,
            non_finite: 0,
        };
        let b = Bernstein::new(&acc, width);
        let l = self.bounded_level(two_sided);
        self.rounding_allowance(reference)
            + b.half_width(l)
            + Normal::standard().inverse_cdf(crate::stats::hypothesis::POWER) * acc.std_error()
    }

    fn bounded_level(&self, two_sided: bool) -> f64 {
        let sides = if two_sided { 4.0 } else { 2.0 };
        (sides / self.per_test_alpha()).ln()
    }

    fn bounded(&self, acc: &Accumulator, range: Range, reference: f64, two_sided: bool) -> Verdict {
        let mut v = if two_sided {
            if is_exact_at(acc, self.term_scale) {
                self.judge_exact(acc.mean, reference, acc.non_finite, acc.count)
            } else {
                self.bernstein(acc, range, reference, true)
            }
        } else if is_exact_at(acc, self.term_scale) {
            self.judge_at_most(acc, reference)
        } else {
            self.bernstein(acc, range, reference, false)
        };
        if v.passed
            && let Some(why) = range.violation()
        {
            v.passed = false;
            v.reason = Some(why);
        }
        v
    }

    fn bernstein(
        &self,
        acc: &Accumulator,
        range: Range,
        reference: f64,
        two_sided: bool,
    ) -> Verdict {
        let alpha = self.per_test_alpha();
        let b = Bernstein::new(acc, range.width());
        let sides = if two_sided { 4.0 } else { 2.0 };
        let l = self.bounded_level(two_sided);
        let h = b.half_width(l);
        let s = acc.std_error();
        let diff = acc.mean - reference;
        let tau = self.rounding_allowance(reference);
        let excess = if two_sided { diff.abs() } else { diff } - tau;
        let p_value = (sides * (-b.level(excess)).exp()).min(1.0);
        let detectable_bias =
            tau + h + Normal::standard().inverse_cdf(crate::stats::hypothesis::POWER) * s;
        let reason = if acc.non_finite > 0 {
            Some(non_finite_reason(acc.non_finite))
        } else if acc.count < 2 {
            Some("fewer than two finite samples".into())
        } else if !reference.is_finite() {
            Some("reference is not finite".into())
        } else if let Some(why) = non_finite_moments(acc.mean, s) {
            Some(why)
        } else if excess > h {
            // (p < α is the same event: the p value is α exactly at an excess of h.)
            Some(format!(
                "mean {:.6} is {:.3e} from {reference}, beyond the empirical Bernstein bound {h:.3e} (p = {p_value:.2e} < α = {alpha:.2e})",
                acc.mean,
                diff.abs()
            ))
        } else {
            None
        };
        // The z test's record of the estimate, with the Bernstein statistic in place of
        // the normal one.
        let z_test = self.judge_parts(acc.mean, s, reference, None, acc.non_finite, acc.count);
        Verdict {
            p_value,
            critical: if s > 0.0 { h / s } else { f64::INFINITY },
            detectable_bias,
            detectable_relative_bias: detectable_bias / reference.abs().max(f64::MIN_POSITIVE),
            passed: reason.is_none(),
            reason,
            ..z_test
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::VerdictClass;

    fn acc_of(xs: impl IntoIterator<Item = f64>) -> Accumulator {
        xs.into_iter().collect()
    }

    /// [0, 1], every sample inside.
    fn unit(_acc: &Accumulator) -> Range {
        Range {
            lo: 0.0,
            hi: 1.0,
            min: 0.0,
            max: 1.0,
        }
    }

    /// A rare-loss weight: 1 except a 0 every 1000th sample (mean 0.999, skewness −31.6).
    fn rare_loss(n: usize) -> Accumulator {
        acc_of((0..n).map(|i| if i % 1000 == 999 { 0.0 } else { 1.0 }))
    }

    #[test]
    fn half_width_and_p_value_follow_maurer_pontil() {
        let t = MeanTest::new(1e-4, 1);
        let acc = rare_loss(20_000);
        let (n, var) = (20_000.0, acc.variance());
        let l = (4.0f64 / 1e-4).ln();
        let h = (2.0 * var * l / n).sqrt() + 7.0 * l / (3.0 * (n - 1.0));
        // Just inside and just outside h (τ = γ₁₂₈ |μ| added to the excess).
        let tau = t.rounding_allowance(0.999);
        let inside = t.judge_bounded(&acc, unit(&acc), acc.mean + 0.99 * h - tau);
        let outside = t.judge_bounded(&acc, unit(&acc), acc.mean - 1.01 * h - tau);
        assert!(inside.passed, "{inside:?}");
        assert!(!outside.passed, "{outside:?}");
        // Two samples are enough to judge (the bound is then wide: h ≈ 25 for [0, 1]).
        let two = acc_of([0.4, 0.6]);
        let v2 = t.judge_bounded(&two, unit(&two), 0.5);
        assert!(v2.passed, "{v2:?}");
        // Its own reason, not the z test's it is built on.
        let why = outside.reason.clone().unwrap_or_default();
        assert!(
            why.contains("beyond the empirical Bernstein bound"),
            "{why}"
        );
        // At excess h the p value is the level itself.
        let at = t.judge_bounded(
            &acc,
            unit(&acc),
            acc.mean + h + t.rounding_allowance(acc.mean + h),
        );
        assert!((at.p_value / 1e-4 - 1.0).abs() < 1e-3, "{}", at.p_value);
        assert!((inside.critical - h / acc.std_error()).abs() < 1e-9 * inside.critical);
        // Detectable bias τ + h + q₀.₉₉ s.
        let q99 = 2.326_347_874_040_841;
        let det = t.rounding_allowance(acc.mean) + h + q99 * acc.std_error();
        let v = t.judge_bounded(&acc, unit(&acc), acc.mean);
        assert!(
            (v.detectable_bias - det).abs() < 1e-12,
            "{} {det}",
            v.detectable_bias
        );
        assert_eq!(v.p_value, 1.0);
        assert!(v.passed && v.class == VerdictClass::Statistical && v.dof.is_none());
        assert!((v.z - 0.0).abs() < 1e-12 && (v.std_error - acc.std_error()).abs() < 1e-15);
        assert!((outside.z - (acc.mean - outside.reference) / acc.std_error()).abs() < 1e-9);
        assert!(
            (t.bounded_detectable_bias(20_000, acc.variance(), 1.0, acc.mean, true) - det).abs()
                < 1e-9,
            "the planning formula is the verdict's"
        );
        // Relative to the reference, from the Bernstein bias (not the z test's).
        assert!(
            (v.detectable_relative_bias - v.detectable_bias / acc.mean).abs() < 1e-15,
            "{v:?}"
        );
        // The rare-loss weight at 20 000 samples sees a bias of 0.3%.
        assert!(
            v.detectable_relative_bias < 0.003,
            "{}",
            v.detectable_relative_bias
        );
    }

    #[test]
    fn one_sided_uses_half_the_sides_and_only_the_upper_excess() {
        let t = MeanTest::new(1e-4, 1);
        let acc = rare_loss(20_000);
        let range = unit(&acc);
        let (n, v) = (20_000.0, acc.variance());
        let l = (2.0f64 / 1e-4).ln();
        let h = (2.0 * v * l / n).sqrt() + 7.0 * l / (3.0 * (n - 1.0));
        let tau = t.rounding_allowance(acc.mean);
        assert!(
            t.judge_bounded_at_most(&acc, range, acc.mean - 0.99 * h + tau)
                .passed
        );
        assert!(
            !t.judge_bounded_at_most(&acc, range, acc.mean - 1.01 * h + tau)
                .passed
        );
        // Far below the bound: passes (the mean may be as low as it likes).
        assert!(t.judge_bounded_at_most(&acc, range, 10.0).passed);
        let below = t.judge_bounded_at_most(&acc, range, acc.mean + 0.5);
        assert_eq!(below.p_value, 1.0);
    }

    #[test]
    fn out_of_range_non_finite_and_tiny_samples_fail() {
        let t = MeanTest::new(1e-4, 1);
        let acc = rare_loss(20_000);
        let over = Range {
            lo: 0.0,
            hi: 1.0,
            min: 0.0,
            max: 1.02,
        };
        let v = t.judge_bounded(&acc, over, acc.mean);
        assert!(!v.passed && v.reason.unwrap().contains("outside"));
        let under = Range { min: -0.1, ..over };
        assert!(
            !t.judge_bounded_at_most(&acc, Range { max: 1.0, ..under }, 1.0)
                .passed
        );
        let empty = Range {
            lo: 1.0,
            hi: 0.0,
            min: 0.5,
            max: 0.5,
        };
        assert!(!t.judge_bounded(&acc, empty, acc.mean).passed);
        let mut nan = acc;
        nan.push(f64::NAN);
        assert!(!t.judge_bounded(&nan, unit(&acc), acc.mean).passed);
        assert!(!t.judge_bounded(&acc, unit(&acc), f64::NAN).passed);
        // Samples without variance are judged exactly, within the f32 bound.
        let flat = acc_of([1.0; 100]);
        let e = t.judge_bounded(&flat, unit(&flat), 1.0);
        assert!(e.passed && e.class == VerdictClass::Exact);
        assert!(!t.judge_bounded(&flat, unit(&flat), 0.99).passed);
        assert!(t.judge_bounded_at_most(&flat, unit(&flat), 1.0).passed);
    }

    #[test]
    fn a_one_percent_bias_in_a_rare_loss_weight_is_found() {
        // 0 every 1000th sample, or every 90th: means 0.999 and 0.98889 (1% apart).
        let t = MeanTest::new(1e-4, 900);
        let acc = rare_loss(40_000);
        assert!(t.judge_bounded(&acc, unit(&acc), 0.999).passed);
        assert!(!t.judge_bounded(&acc, unit(&acc), 0.999 * 0.99).passed);
        let v = t.judge_bounded(&acc, unit(&acc), 0.999);
        assert!(
            v.detectable_relative_bias < 0.0075,
            "{}",
            v.detectable_relative_bias
        );
    }

    /// Finite samples whose mean overflowed to NaN in a range as wide as f64 allows: the
    /// Bernstein statistic of a NaN excess reads as no excess, which must not pass.
    #[test]
    fn a_non_finite_mean_of_finite_samples_fails() {
        let t = MeanTest::new(1e-4, 1);
        let acc = acc_of([1e308, -1e308, 1e308]);
        assert!(acc.mean.is_nan() && acc.non_finite == 0);
        let wide = Range {
            lo: -f64::MAX,
            hi: f64::MAX,
            min: -1e308,
            max: 1e308,
        };
        let v = t.judge_bounded(&acc, wide, 1.0);
        assert!(!v.passed, "{v:?}");
        assert!(!t.judge_bounded_at_most(&acc, wide, 1.0).passed);
    }
}
