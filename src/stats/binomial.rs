//! Exact binomial tests: the tails of K ~ Binomial(n, q) and the two-sided test of a
//! count against a probability, for the chi-square judge's normalisation (lost draws
//! against 1 − ∫ pdf) and the BSDF suite's reflection fractions (reflected draws against
//! the Fresnel reflectance).
//!
//! **Tails.** P(K ≤ k) and P(K ≥ k) are summed term by term, starting at k on the far
//! side of the mode m = ⌊(n + 1) q⌋, where the terms only fall: P(K = k) from log-gamma (statrs's `ln_gamma`),
//! then the ratios P(K = j − 1)/P(K = j) = j (1 − q)/((n − j + 1) q) downwards and
//! P(K = j + 1)/P(K = j) = (n − j) q/((j + 1)(1 − q)) upwards (Johnson, Kemp & Kotz,
//! "Univariate Discrete Distributions", 3rd ed., §3.2), until a term adds less than
//! 10⁻¹⁷ of the sum. A tail that holds the mode is 1 minus the other one. The relative
//! error is that of ln P(K = k), whose log-gamma terms of size n ln n cancel: measured
//! against mpmath, 10⁻¹⁰ at n = 3.2·10⁴ and 10⁻⁸ at n = 10⁷ and 10⁸, far below what a
//! p value compared with α needs. The work is some ten standard deviations
//! √(n q (1 − q)) of terms. statrs's `Binomial::cdf` and `sf` are
//! not used: they evaluate the incomplete beta function by a continued fraction stopped
//! after 140 iterations, which has not converged near the mean of a large n (at
//! n = 10⁷, q = ½ it gives P(K ≤ n/2) = 0.365 for 0.5001; at n = 10⁸, q = 0.3, −0.27).
//!
//! **Two-sided test.** p = min(1, 2 min(P(K ≤ k), P(K ≥ k))): twice the smaller tail, the
//! rule of the BSDF suite since session 32 (conservative: a discrete p value is never
//! below α with probability above α). At k = n q (a mean that is a count) both tails are
//! at least ½, so p = 1.

use crate::stats::{MeanTest, Verdict, VerdictClass};
use statrs::distribution::{ContinuousCDF, Normal};

/// ln P(K = k) for K ~ Binomial(n, q), 0 < q < 1, k ≤ n.
fn ln_pmf(k: u64, n: u64, q: f64) -> f64 {
    use statrs::function::gamma::ln_gamma;
    let (k, n) = (k as f64, n as f64);
    ln_gamma(n + 1.0) - ln_gamma(k + 1.0) - ln_gamma(n - k + 1.0)
        + k * q.ln()
        + (n - k) * (-q).ln_1p()
}

/// The mode ⌊(n + 1) q⌋ of Binomial(n, q), at most n.
fn mode(n: u64, q: f64) -> u64 {
    (((n as f64 + 1.0) * q).floor() as u64).min(n)
}

/// Σ P(K = j) over j from `k` away from the mode (`down`: j ≤ k, else j ≥ k), for k on
/// the side of the mode where the terms fall, 0 < q < 1.
fn sum_from(k: u64, n: u64, q: f64, down: bool) -> f64 {
    let odds = q / (1.0 - q);
    let mut term = ln_pmf(k, n, q).exp();
    let mut sum = term;
    let mut j = k;
    loop {
        if down {
            if j == 0 {
                break;
            }
            term *= j as f64 / ((n - j + 1) as f64 * odds);
            j -= 1;
        } else {
            if j == n {
                break;
            }
            term *= (n - j) as f64 * odds / (j + 1) as f64;
            j += 1;
        }
        sum += term;
        if term <= 1e-17 * sum {
            break;
        }
    }
    sum
}

/// P(K ≤ k) for K ~ Binomial(n, q) (NaN for a NaN q; q ≤ 0 is K = 0, q ≥ 1 is K = n).
pub fn lower_tail(k: u64, n: u64, q: f64) -> f64 {
    if q.is_nan() {
        f64::NAN
    } else if k >= n || q <= 0.0 {
        1.0
    } else if q >= 1.0 {
        0.0
    } else if k < mode(n, q) {
        sum_from(k, n, q, true)
    } else {
        (1.0 - sum_from(k + 1, n, q, false)).max(0.0)
    }
}

/// P(K ≥ k) for K ~ Binomial(n, q) (NaN for a NaN q; q ≤ 0 is K = 0, q ≥ 1 is K = n).
pub fn upper_tail(k: u64, n: u64, q: f64) -> f64 {
    if q.is_nan() {
        f64::NAN
    } else if k == 0 {
        1.0
    } else if k > n || q <= 0.0 {
        0.0
    } else if q >= 1.0 {
        1.0
    } else if k > mode(n, q) {
        sum_from(k, n, q, false)
    } else {
        (1.0 - sum_from(k - 1, n, q, true)).max(0.0)
    }
}

/// The exact two-sided p value of `k` successes in `n` draws of probability `q`:
/// min(1, 2 min(P(K ≤ k), P(K ≥ k))) (module notes; NaN for a NaN q).
pub fn two_sided_p(k: u64, n: u64, q: f64) -> f64 {
    if q.is_nan() {
        // f64::min would drop the NaN and answer 1.
        return f64::NAN;
    }
    (2.0 * lower_tail(k, n, q).min(upper_tail(k, n, q))).min(1.0)
}

impl MeanTest {
    /// Exact two-sided binomial test of `k` successes in `n` draws against probability
    /// `r` ([`two_sided_p`]), for counts where the normal approximation is meaningless
    /// (n r (1 − r) small: a reflectance of 10⁻⁸, or 1 under total internal reflection).
    /// Rejects when p < α₁, the family's per-test level. Its power is stated as the
    /// verdict's `detectable_bias`: the smallest |r′ − r| at which a true probability r′
    /// lands in the rejection region {K ≥ k_hi} or {K ≤ k_lo} (each tail ≤ α₁/2 under r)
    /// with probability ≥ 0.99, by bisection on r′; `std_error` is the null
    /// √(r(1 − r)/n) and `z` the plain (k/n − r)/SE. The rejection region is found by
    /// stepping from n r, a few standard deviations: meant for small n r (1 − r).
    pub fn judge_binomial(&self, k: u64, n: u64, r: f64, non_finite: u64) -> Verdict {
        let r = r.clamp(0.0, 1.0);
        let p_two = two_sided_p(k, n, r);
        let alpha1 = self.per_test_alpha();
        // Rejection region under r: K ≥ k_hi (None: unreachable) or K ≤ k_lo.
        let mean = (n as f64 * r).floor() as u64;
        let mut k_hi = Some(mean);
        while let Some(j) = k_hi {
            if upper_tail(j, n, r) <= alpha1 / 2.0 {
                break;
            }
            k_hi = (j < n).then_some(j + 1);
        }
        let mut k_lo = Some(mean.min(n));
        while let Some(j) = k_lo {
            if lower_tail(j, n, r) <= alpha1 / 2.0 {
                break;
            }
            k_lo = j.checked_sub(1);
        }
        // The shift of r that reaches 99% power on one side, by bisection between r and
        // the end `towards` (1 or 0), where a region that exists is met surely: K ≥ k_hi
        // with k_hi ≤ n at r′ = 1, K ≤ k_lo at r′ = 0 (a side without a region: ∞).
        let shift = |power: &dyn Fn(f64) -> f64, towards: f64| {
            let (mut near, mut far) = (r, towards);
            for _ in 0..100 {
                let mid = 0.5 * (near + far);
                if power(mid) >= 0.99 {
                    far = mid;
                } else {
                    near = mid;
                }
            }
            (far - r).abs()
        };
        let up = k_hi.map_or(f64::INFINITY, |j| shift(&|p| upper_tail(j, n, p), 1.0));
        let down = k_lo.map_or(f64::INFINITY, |j| shift(&|p| lower_tail(j, n, p), 0.0));
        let detectable_bias = up.min(down);
        let se = (r * (1.0 - r) / n as f64).sqrt();
        let diff = k as f64 / n as f64 - r;
        let reason = if non_finite > 0 {
            Some(crate::stats::hypothesis::non_finite_reason(non_finite))
        } else if !(p_two >= alpha1) {
            Some(format!(
                "{k} of {n} draws against probability {r:.3e}: exact binomial p = {p_two:.2e} < α = {alpha1:.2e}"
            ))
        } else {
            None
        };
        Verdict {
            class: VerdictClass::Statistical,
            estimate: k as f64 / n as f64,
            std_error: se,
            reference: r,
            z: if se > 0.0 {
                diff / se
            } else if diff == 0.0 {
                0.0
            } else {
                f64::INFINITY.copysign(diff)
            },
            p_value: p_two,
            alpha: alpha1,
            critical: Normal::standard().inverse_cdf(1.0 - alpha1 / 2.0),
            detectable_bias,
            detectable_relative_bias: if r > 0.0 {
                detectable_bias / r
            } else {
                detectable_bias
            },
            dof: None,
            non_finite,
            passed: reason.is_none(),
            reason,
            weak: false,
            input_rounding: self.input_rounding,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Tails against their definition Σ C(n, j) qʲ (1 − q)ⁿ⁻ʲ, summed in mpmath at 40
    /// digits over every term that matters (references not from this code): small and
    /// large n, near the mean and far in a tail, q near 0 and near 1.
    #[test]
    fn tails_match_their_definition() {
        let q = 20.0 / 32_000.0;
        let cases: [(f64, f64, f64); 10] = [
            (lower_tail(10, 32_000, q), 0.010_793_549_118_661_757, 1e-9),
            (lower_tail(9, 32_000, q), 0.004_985_420_625_146_068, 1e-9),
            (lower_tail(8, 32_000, q), 0.002_082_354_931_316_057_5, 1e-9),
            (upper_tail(33, 32_000, q), 0.004_714_817_016_727_36, 1e-9),
            (upper_tail(34, 32_000, q), 0.002_680_161_464_998_375, 1e-9),
            // Far in the upper tail (not 1 minus a sum near 1).
            (upper_tail(60, 32_000, q), 4.130_040_084_587_611e-13, 1e-9),
            // n = 10⁷, q = ½: 6.3 σ below the mean, and at the mean (½ + P(K = n/2)/2).
            (
                lower_tail(4_990_000, 10_000_000, 0.5),
                1.272_400_245_577_586_5e-10,
                1e-7,
            ),
            (
                lower_tail(5_000_000, 10_000_000, 0.5),
                0.500_126_156_622_947_1,
                1e-7,
            ),
            // n = 10⁸, q = 0.3 at the mean (statrs's continued fraction: −0.27).
            (
                lower_tail(30_000_000, 100_000_000, 0.3),
                0.500_049_331_927_352_3,
                1e-7,
            ),
            (
                lower_tail(900, 1_000_000, 1e-3),
                6.940_154_622_868_569e-4,
                1e-8,
            ),
        ];
        for (i, (got, want, tol)) in cases.into_iter().enumerate() {
            assert!((got / want - 1.0).abs() < tol, "{i}: {got} vs {want}");
        }
        // The same tail seen from the other side: n − K ~ Binomial(n, 1 − q).
        let mirrored = upper_tail(999_100, 1_000_000, 1.0 - 1e-3);
        assert!(
            (mirrored / 6.940_154_622_868_569e-4 - 1.0).abs() < 1e-8,
            "{mirrored}"
        );
        // The two tails overlap in P(K = k): they sum to 1 + P(K = k).
        let pmf10 = lower_tail(10, 32_000, q) - lower_tail(9, 32_000, q);
        let sum = lower_tail(10, 32_000, q) + upper_tail(10, 32_000, q);
        assert!((sum - 1.0 - pmf10).abs() < 1e-14, "{sum}");
    }

    /// The ends: q = 0 puts K at 0, q = 1 at n; k beyond n; NaN stays NaN.
    #[test]
    fn tails_at_the_ends() {
        assert_eq!((lower_tail(0, 10, 0.0), upper_tail(1, 10, 0.0)), (1.0, 0.0));
        assert_eq!(upper_tail(0, 10, 0.0), 1.0);
        assert_eq!(
            (lower_tail(9, 10, 1.0), lower_tail(10, 10, 1.0)),
            (0.0, 1.0)
        );
        assert_eq!(
            (upper_tail(10, 10, 1.0), upper_tail(11, 10, 0.5)),
            (1.0, 0.0)
        );
        assert_eq!(
            (lower_tail(12, 10, 0.5), upper_tail(0, 10, 0.5)),
            (1.0, 1.0)
        );
        // One draw: P(K ≤ 0) = 1 − q, P(K ≥ 1) = q.
        assert!((lower_tail(0, 1, 0.3) - 0.7).abs() < 1e-15);
        assert!((upper_tail(1, 1, 0.3) - 0.3).abs() < 1e-15);
        assert!((upper_tail(1, 1, 0.7) - 0.7).abs() < 1e-15);
        assert!((lower_tail(0, 1, 0.7) - 0.3).abs() < 1e-15);
        assert!(lower_tail(3, 10, f64::NAN).is_nan() && upper_tail(3, 10, f64::NAN).is_nan());
        assert!(two_sided_p(3, 10, f64::NAN).is_nan());
    }

    /// Twice the smaller tail, at most 1; 1 where the count is the mean.
    #[test]
    fn two_sided_p_is_twice_the_smaller_tail() {
        let q = 20.0 / 32_000.0;
        assert!(
            (two_sided_p(10, 32_000, q) / (2.0 * 0.010_793_549_118_661_757) - 1.0).abs() < 1e-9
        );
        assert!((two_sided_p(33, 32_000, q) / (2.0 * 0.004_714_817_016_727_36) - 1.0).abs() < 1e-9);
        assert_eq!(two_sided_p(20, 32_000, q), 1.0);
        assert_eq!(two_sided_p(5_000_000, 10_000_000, 0.5), 1.0);
        assert_eq!(two_sided_p(7, 32_000, 0.0), 0.0);
        assert_eq!(two_sided_p(0, 32_000, 0.0), 1.0);
    }

    /// The exact binomial verdict can fail, on either side, and states the power it has
    /// (the BSDF suite's reflection fractions, at its family of 900 tests at α = 10⁻⁴).
    #[test]
    fn exact_binomial_verdict_can_fail_and_states_its_power() {
        let test = MeanTest::new(1e-4, 900);
        // R ≈ 2.5e-9 (η = 1.0001) at 20 000 draws: none reflected passes, 5 fail.
        let r = 2.5e-9;
        let ok = test.judge_binomial(0, 20_000, r, 0);
        assert!(ok.passed && ok.p_value == 1.0, "{ok:?}");
        let five = test.judge_binomial(5, 20_000, r, 0);
        assert!(!five.passed && five.reason.as_deref().unwrap().contains("5 of 20000"));
        // The power: under a true R′ = R + detectable, K reaches the rejection region
        // K ≥ k_hi (k_hi = 2: P(K ≥ 2) ≈ (nR)²/2 = 1.3e-9 ≤ α₁/2) with probability 0.99.
        let alpha1 = test.per_test_alpha();
        let k_hi = (0..=20_000u64)
            .find(|&j| upper_tail(j, 20_000, r) <= alpha1 / 2.0)
            .unwrap();
        assert_eq!(k_hi, 2);
        let seen = upper_tail(k_hi, 20_000, r + ok.detectable_bias);
        assert!((seen - 0.99).abs() < 1e-6, "k_hi {k_hi}: {seen}");
        assert!(
            ok.detectable_bias > 0.0 && ok.detectable_bias < 1e-3,
            "{ok:?}"
        );
        assert!(
            (ok.detectable_relative_bias - ok.detectable_bias / r).abs()
                < 1e-6 * ok.detectable_relative_bias
        );
        // Total internal reflection (R = 1): one transmitted draw fails.
        let tir = test.judge_binomial(20_000, 20_000, 1.0, 0);
        assert!(tir.passed && tir.z == 0.0, "{tir:?}");
        // Its power: K ≤ n − 1 (one draw transmitted) with probability 1 − r′ⁿ ≥ 0.99,
        // r′ ≤ 0.01^{1/n}: |Δr| = 1 − 0.01^{1/20 000} = 2.3023·10⁻⁴ (mpmath).
        assert!(
            (tir.detectable_bias - 2.302_320_018_434_136_5e-4).abs() < 1e-12,
            "{tir:?}"
        );
        let lost = test.judge_binomial(19_999, 20_000, 1.0, 0);
        assert!(!lost.passed && lost.z == f64::NEG_INFINITY, "{lost:?}");
        // Non-finite samples fail whatever the count.
        assert!(!test.judge_binomial(0, 20_000, r, 1).passed);
        // The normal parts: SE √(r(1 − r)/n), z, α₁ and its critical value.
        let v = test.judge_binomial(5_100, 10_000, 0.5, 0);
        assert_eq!(v.estimate, 0.51);
        assert!(
            (v.std_error - 0.005).abs() < 1e-15 && (v.z - 2.0).abs() < 1e-9,
            "{v:?}"
        );
        assert_eq!(v.alpha, alpha1);
        assert!((v.critical - Normal::standard().inverse_cdf(1.0 - alpha1 / 2.0)).abs() < 1e-15);
        assert!(v.passed && (v.p_value - two_sided_p(5_100, 10_000, 0.5)).abs() < 1e-15);
        // Both rejection regions at r = ½ (symmetric: k_lo = n − k_hi), and the shift
        // that reaches each with probability 0.99.
        let k_hi = (5_000..=10_000u64)
            .find(|&j| upper_tail(j, 10_000, 0.5) <= alpha1 / 2.0)
            .unwrap();
        let k_lo = (0..=5_000u64)
            .rev()
            .find(|&j| lower_tail(j, 10_000, 0.5) <= alpha1 / 2.0)
            .unwrap();
        assert_eq!(k_lo, 10_000 - k_hi);
        let d = v.detectable_bias;
        assert!(
            (upper_tail(k_hi, 10_000, 0.5 + d) - 0.99).abs() < 1e-9,
            "{d}"
        );
        assert!(
            (lower_tail(k_lo, 10_000, 0.5 - d) - 0.99).abs() < 1e-9,
            "{d}"
        );
        assert!((v.detectable_relative_bias - 2.0 * d).abs() < 1e-15);
        // A probability of 0: the detectable bias is absolute, as the relative one.
        let zero = test.judge_binomial(0, 20_000, 0.0, 0);
        assert!(zero.passed && zero.p_value == 1.0, "{zero:?}");
        assert_eq!(zero.detectable_relative_bias, zero.detectable_bias);
        assert!(!test.judge_binomial(1, 20_000, 0.0, 0).passed);
    }
}
