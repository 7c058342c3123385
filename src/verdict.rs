//! From an estimate to a verdict: which standard error a verdict uses, whether the
//! estimate is exact, the judgement itself, and the [`Outcome`] record that `verify`,
//! `estimate` and the proof print and judge as one family ([`judge_family`]).
//!
//! **Error bar.** With independent samples the plain standard error √(s²/N) is used,
//! unless the batch-means error exceeds it by half (heavy tails), when the batch-means
//! t test (B − 1 = 127 degrees of freedom) takes over; quasi-random samplers are always
//! judged by batch means, each batch being an independent randomisation. The error bar
//! is chosen from the estimate alone, never from the reference, so `estimate` prints
//! the same `std_error` with or without one.
//!
//! **Classes.** An estimate whose samples agree to f32 rounding is *exact*
//! ([`crate::stats::is_exact`]), and so is one judged by batch means whose batch means
//! are all equal (a σ̂ of 0 is no statistic): it is compared within the stated f32
//! error bound and
//! is not a member of the Šidák family. Every other estimate is *statistical*: a z (or
//! t) test at the family's per-test level, reporting the bias it detects with 99% power.

use crate::sampling::SamplerKind;
use crate::stats::{MeanTest, Verdict, is_exact};
use crate::transport::Estimator;
use crate::transport::effects::Effects;
use crate::transport::engine::Estimate;
use crate::transport::measure::Measure;
use crate::transport::plan::Plan;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The smallest relative bias every statistical verdict of the proof must be able to
/// see at 99% power, at its case's own sample count (the catalog's proof holds every
/// case to it, across seeds): a verdict that cannot see it fails there
/// ([`Outcome::require_power`]).
pub const DETECTABLE_BOUND: f64 = 0.005;

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
        let means = est.batches.of_means();
        let batch = means.std_error();
        if sampler != SamplerKind::Independent || batch > 1.5 * plain {
            // Identical batch means (a quasi-random sampler that stratifies the integrand
            // exactly) leave no variance to test either: σ̂ = 0 is no statistic.
            if means.count > 1 && means.non_finite == 0 && batch == 0.0 {
                return ErrorBar {
                    std_error: None,
                    dof: None,
                };
            }
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
/// `alpha` (an exact estimate is judged exactly, outside the family), against a reference
/// that moves by `input_rounding` when its inputs round to `f32`
/// ([`MeanTest::with_input_rounding`]).
#[allow(clippy::too_many_arguments)]
pub fn judge_parts(
    estimate: f64,
    bar: &ErrorBar,
    reference: f64,
    input_rounding: f64,
    non_finite: u64,
    count: u64,
    alpha: f64,
    tests: usize,
) -> Verdict {
    let t = MeanTest::new(alpha, tests).with_input_rounding(input_rounding);
    match bar.std_error {
        None => t.judge_exact(estimate, reference, non_finite, count),
        Some(se) => t.judge_parts(estimate, se, reference, bar.dof, non_finite, count),
    }
}

/// Judge an estimate against a reference within a family of `tests` statistical tests,
/// without input rounding (a caller's own reference; a case's outcome carries its ρ,
/// [`Outcome::verdict_against`]).
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
        0.0,
        total.non_finite,
        total.count,
        alpha,
        tests,
    )
}

impl Verdict {
    /// The detectable bias as shown: relative, a percentage; for a zero reference, which
    /// has no relative bias, the absolute one in the case's units, without a `%` that
    /// would read as relative (0.002 printed as "0.200%").
    pub fn detectable_bias_text(&self) -> String {
        if self.reference == 0.0 {
            format!("{:.2e}", self.detectable_bias)
        } else {
            format!("{:.3}%", 100.0 * self.detectable_relative_bias)
        }
    }

    /// A passed statistical verdict must be able to see a relative bias of
    /// [`DETECTABLE_BOUND`] (its `detectable_relative_bias`, at 99% power), or the pass
    /// proves nothing: an engine whose variance blew up (a dropped Jacobian that leaves
    /// rare huge samples) passes any z test. `inside` says whether the run met the
    /// proof's conditions (the case's own estimators and samplers at its own sample
    /// count or more, where the catalog's proof shows every verdict of a correct engine
    /// sees 0.5 %): there such a verdict fails; outside them it stays a pass marked
    /// [`Verdict::weak`]. This holds for any case file at its own count, a user's too: its
    /// `samples` is the count its author vouches for. A zero reference has no relative
    /// bias to see (`detectable_relative_bias` is then the absolute one, in the case's
    /// units), so such a pass is only marked weak. Failures are left as they are, and so
    /// are exact verdicts (their tolerance is the f32 bound) unless the reference's input
    /// rounding ([`Verdict::input_rounding`]) widens their allowance past the bound: such
    /// a verdict fails wherever it is (more samples change nothing; weak for a zero
    /// reference), and a statistical one that cannot see the bound says how much of it
    /// is input rounding.
    pub fn require_power(&mut self, inside: bool) {
        let sees = self.detectable_relative_bias <= DETECTABLE_BOUND;
        if !self.passed || sees {
            return;
        }
        // The part of the detectable bias no sample count removes: the input rounding |ρ|
        // (relative; the f32 bound's 7.6·10⁻⁶ beside it is left out of the advice).
        let fixed = if self.reference != 0.0 {
            self.input_rounding.abs() / self.reference.abs()
        } else {
            0.0
        };
        let rounding = format!(
            "its reference moves by {:.3}% when its inputs round to the engine's f32 values",
            100.0 * fixed
        );
        let exact = match self.class {
            crate::stats::VerdictClass::Exact => true,
            crate::stats::VerdictClass::Statistical => false,
        };
        if self.reference == 0.0 || (exact && self.input_rounding == 0.0) {
            // A zero reference has no relative bias to see; an exact verdict's tolerance
            // is the f32 bound, whatever it is.
            self.weak |= self.reference == 0.0;
            return;
        }
        if exact || fixed >= DETECTABLE_BOUND {
            // More samples change nothing: only the case's numbers can.
            self.passed = false;
            self.reason = Some(format!(
                "{rounding}, so this verdict cannot see a relative bias below {:.3}%, more than the {}% every verdict must see, whatever its sample count: {INPUT_ROUNDING_REMEDY}",
                100.0 * self.detectable_relative_bias,
                100.0 * DETECTABLE_BOUND
            ));
        } else if inside {
            self.passed = false;
            // The statistical part of the detectable bias falls as 1/√N: the samples that
            // would bring the whole to the bound.
            let rel = self.detectable_relative_bias;
            let (sees, more) = if rel.is_finite() {
                let more = ((rel - fixed) / (DETECTABLE_BOUND - fixed)).powi(2).ceil();
                (
                    format!(
                        "cannot see a relative bias below {:.3}% (99% power)",
                        100.0 * rel
                    ),
                    if more.is_finite() {
                        format!(" to about {more}× the samples this run drew")
                    } else {
                        String::new()
                    },
                )
            } else {
                ("has no finite detectable bias".to_string(), String::new())
            };
            let rounds = if self.input_rounding != 0.0 {
                format!(" ({rounding}: part of it)")
            } else {
                String::new()
            };
            self.reason = Some(format!(
                "{sees}{rounds}, where a verdict at its case's own sample count must see {}%, or its pass proves nothing: raise the case's `samples`{more} or find why the estimator's variance is this high",
                100.0 * DETECTABLE_BOUND
            ));
        } else {
            self.weak = true;
        }
    }
}

/// What a case whose reference is too sensitive to its inputs' `f32` rounding can do.
const INPUT_ROUNDING_REMEDY: &str = "write the case's numbers as f32 values, or choose inputs where its closed form is less sensitive to them";

/// The outcome of one estimator × sampler of a case.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Outcome {
    /// Case name.
    pub case: String,
    /// Case file.
    pub file: String,
    /// Measurement.
    pub measure: String,
    /// Estimator.
    pub estimator: Estimator,
    /// Sampler.
    pub sampler: SamplerKind,
    /// Samples drawn.
    pub samples: u64,
    /// Seed.
    pub seed: u64,
    /// Mean of the finite samples; NaN (`null` in JSON) where there is none, every
    /// sample non-finite (a mean of no samples is no estimate, never 0).
    pub estimate: f64,
    /// Standard error a verdict uses (plain or batch means, see [`ErrorBar`]); absent
    /// when the estimate is exact.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub std_error: Option<f64>,
    /// Degrees of freedom of the batch-means t test, when it decides.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dof: Option<u64>,
    /// Whether the samples have no variance (judged within the f32 error bound).
    pub exact: bool,
    /// Whether it is exact only because its batch means agree to the bit while its
    /// samples vary (a quasi-random sampler that stratifies the integrand exactly,
    /// [`ErrorBar::of`]): known to the run that drew it, not written to JSON (README
    /// "How a verdict is reached": no catalog verdict is such an estimate, which
    /// `tests/proof/catalog.rs` checks).
    #[serde(skip)]
    pub exact_by_batch_means: bool,
    /// Non-finite samples (any one fails the outcome, reference or not).
    pub non_finite: u64,
    /// Wall seconds.
    pub seconds: f64,
    /// What was simulated, and why.
    pub effects: Effects,
    /// Closed-form reference.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reference: Option<f64>,
    /// ρ = μ(f32 inputs) − μ, the reference's change when its inputs round to the `f32`
    /// values the engine's scene holds ([`crate::case::build::reference_rounding`]): the
    /// verdict accepts a mean between μ and μ + ρ ([`MeanTest::with_input_rounding`]).
    /// Absent when 0.
    #[serde(default, skip_serializing_if = "crate::stats::hypothesis::is_zero")]
    pub reference_rounding: f64,
    /// z score.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub z: Option<f64>,
    /// The verdict.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub verdict: Option<Verdict>,
    /// The arrival-time bin [t₁, t₂] (s) of one bin of a time-resolved histogram.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bin: Option<[f64; 2]>,
}

impl Outcome {
    /// The unjudged outcome of estimate `e` of estimator `est` × `sampler` of the case
    /// named `case` (from `file`), measuring `measure` under `plan`.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        case: &str,
        file: &Path,
        measure: &Measure,
        plan: &Plan,
        reference: Option<f64>,
        est: Estimator,
        sampler: SamplerKind,
        seed: u64,
        e: &Estimate,
    ) -> Outcome {
        let total = &e.batches.total;
        let bar = ErrorBar::of(e, sampler);
        Outcome {
            case: case.to_string(),
            file: file.display().to_string(),
            measure: measure.name().to_string(),
            estimator: est,
            sampler,
            samples: total.count + total.non_finite,
            seed,
            estimate: if total.count == 0 {
                f64::NAN
            } else {
                total.mean
            },
            std_error: bar.std_error,
            dof: bar.dof,
            exact: bar.exact(),
            exact_by_batch_means: bar.exact() && !is_exact(total),
            non_finite: total.non_finite,
            seconds: e.seconds,
            effects: plan.effects.clone(),
            reference,
            reference_rounding: 0.0,
            z: None,
            verdict: None,
            bin: None,
        }
    }

    /// What names one bin of a time-resolved histogram after its case's id, e.g.
    /// ` t∈[3.669, 4.336] ns`; empty for any other outcome.
    pub fn bin_suffix(&self) -> String {
        match self.bin {
            Some([a, b]) => format!(" t∈[{:.4}, {:.4}] ns", a * 1e9, b * 1e9),
            None => String::new(),
        }
    }

    /// The samples a run asked for `n` draws with this outcome's sampler.
    fn drawn(&self, n: u64) -> u64 {
        crate::transport::engine::RunSpec {
            samples: n,
            sampler: self.sampler,
            seed: 0,
        }
        .total()
    }

    /// Whether a run asked for `ran` samples drew fewer than its case's own count `own`
    /// would have (both as the engine rounds them for this outcome's sampler).
    pub fn drew_fewer(&self, ran: u64, own: u64) -> bool {
        self.drawn(ran) < self.drawn(own)
    }

    /// A failed verdict of an estimate asked for `ran` samples where its case's own count
    /// is `own` says so in its reason when it drew fewer samples than the case's own count
    /// would have ([`Outcome::drew_fewer`]): the
    /// false-alarm rate α is established at each case's own count and above (the proof
    /// runs there, across seeds), and with fewer samples an integrand whose variance sits
    /// in rare events (a near-delta lobe at grazing incidence, a thin strip of a view
    /// factor) can hide it from the standard error, so a failure there may be a false alarm
    /// (`verify --samples 256 --no-chi2` failed 3–7 of the 282 verdicts of a correct
    /// engine across the default seed and the seven after it, measured in session 36).
    /// Passed verdicts, and failures that are never chance (non-finite samples or
    /// reference), are left as they are.
    /// Returns whether it added the note.
    pub fn note_fewer_samples(&mut self, ran: u64, own: u64) -> bool {
        if !self.drew_fewer(ran, own) {
            return false;
        }
        let (ran, own) = (self.drawn(ran), self.drawn(own));
        self.note_outside_the_proof(
            &format!("drew {ran} samples, fewer than the case's own {own}"),
            "rerun at the case's own count to tell",
        )
    }

    /// This outcome's verdict, if any, held to the proof's power
    /// ([`Verdict::require_power`]); `inside`: whether the run met the proof's conditions
    /// (its case's own estimators and samplers at its own sample count or more).
    pub fn require_power(&mut self, inside: bool) {
        if let Some(v) = self.verdict.as_mut() {
            v.require_power(inside);
        }
    }

    /// A failed verdict of a run the catalog's proof does not cover (`what`: fewer samples
    /// than the case's own, an estimator or sampler the case does not list) says so in its
    /// reason, with the `remedy`: the false-alarm rate α is established for each case's own
    /// estimators × samplers at its own count, and elsewhere an integrand whose variance
    /// sits in rare events (a tiny or huge light sampled by the wrong strategy, a delta or
    /// near-delta lobe sampled uniformly) can hide it from the standard error. Passed
    /// verdicts and failures that are never chance (non-finite samples or reference) are
    /// left as they are. Returns whether it added the note.
    pub fn note_outside_the_proof(&mut self, what: &str, remedy: &str) -> bool {
        let chance = |v: &Verdict| !v.passed && v.non_finite == 0 && v.reference.is_finite();
        let Some(v) = self.verdict.as_mut().filter(|v| chance(v)) else {
            return false;
        };
        let why = format!(
            "{what}, where its false-alarm rate is not established (rare events may go unseen, and the standard error with them): {remedy}"
        );
        v.reason = Some(match v.reason.take() {
            Some(r) => format!("{r}; {why}"),
            None => why,
        });
        true
    }

    /// Whether it passed weakly ([`Verdict::weak`]).
    pub fn is_weak(&self) -> bool {
        self.verdict.as_ref().is_some_and(|v| v.weak)
    }

    /// Whether the outcome will be a member of the statistical (Šidák) family.
    pub fn is_statistical(&self) -> bool {
        self.reference.is_some() && !self.exact
    }

    /// Judge against the reference (if any) in a family of `tests` statistical tests.
    pub fn judge(&mut self, alpha: f64, tests: usize) {
        if let Some(r) = self.reference {
            let v = self.verdict_against(r, alpha, tests);
            self.z = Some(v.z);
            self.verdict = Some(v);
        }
    }

    /// The verdict of this outcome against `reference` (which need not be the case's),
    /// in a family of `tests` statistical tests at level `alpha`, with this outcome's
    /// [`Outcome::reference_rounding`] in the allowance.
    pub fn verdict_against(&self, reference: f64, alpha: f64, tests: usize) -> Verdict {
        let bar = ErrorBar {
            std_error: self.std_error,
            dof: self.dof,
        };
        let count = self.samples - self.non_finite;
        judge_parts(
            self.estimate,
            &bar,
            reference,
            self.reference_rounding,
            self.non_finite,
            count,
            alpha,
            tests,
        )
    }

    /// Whether it passed. Without a reference there is nothing to compare, but a
    /// non-finite sample still fails.
    pub fn passed(&self) -> bool {
        match &self.verdict {
            Some(v) => v.passed,
            None => self.non_finite == 0 && self.samples > 0,
        }
    }
}

/// The weak passes of a run, by cause: (drawn with fewer samples than their case's own
/// count, at that count with a zero reference). `counts` holds each outcome's (samples
/// asked for, its case's own count); at its own count a statistical pass that cannot see
/// the bound fails unless its reference is 0 ([`Verdict::require_power`]), so a weak pass
/// that drew enough has a zero reference.
pub fn weak_counts(outcomes: &[Outcome], counts: &[(u64, u64)]) -> (usize, usize) {
    let (mut fewer, mut zero) = (0, 0);
    for (o, &(ran, own)) in outcomes.iter().zip(counts) {
        if o.is_weak() {
            if o.drew_fewer(ran, own) {
                fewer += 1;
            } else {
                zero += 1;
            }
        }
    }
    (fewer, zero)
}

/// Judge every outcome of a run as one family: the statistical ones (and `others`
/// further statistical tests of the same run, e.g. chi-square suites) share the Šidák
/// correction at family-wise level `alpha`; exact ones are judged outside it. Returns
/// the family size k.
pub fn judge_family(outcomes: &mut [Outcome], others: usize, alpha: f64) -> usize {
    let k = outcomes.iter().filter(|o| o.is_statistical()).count() + others;
    for o in outcomes.iter_mut() {
        o.judge(alpha, k);
    }
    k
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

    /// A failure below the case's own sample count says so; a pass, a run at or above the
    /// count and an unjudged outcome are left as they are.
    #[test]
    fn failures_below_the_case_count_are_named() {
        let failed = || {
            let mut o = outcome(1.6, Some(0.1), Some(1.0), 256, 0);
            o.judge(1e-4, 1);
            assert!(!o.passed());
            o
        };
        let mut o = failed();
        let before = o.verdict.as_ref().unwrap().reason.clone().unwrap();
        o.note_fewer_samples(256, 65536);
        let after = o.verdict.as_ref().unwrap().reason.clone().unwrap();
        assert!(
            after.starts_with(&before)
                && after.contains("drew 256 samples, fewer than the case's own 65536"),
            "{after}"
        );
        // Counts compare as drawn: 65 500 and 65 536 both draw 128 × 512 = 65 536.
        for (ran, own) in [(65536, 65536), (1 << 20, 65536), (65_500, 65536)] {
            let mut o = failed();
            o.note_fewer_samples(ran, own);
            assert_eq!(o.verdict.unwrap().reason.unwrap(), before);
        }
        let mut ok = outcome(1.0, Some(0.1), Some(1.0), 256, 0);
        ok.judge(1e-4, 1);
        ok.note_fewer_samples(256, 65536);
        assert!(ok.passed() && ok.verdict.unwrap().reason.is_none());
        let mut unjudged = outcome(1.0, Some(0.1), None, 256, 0);
        unjudged.note_fewer_samples(256, 65536);
        assert!(unjudged.verdict.is_none());
        // A non-finite sample fails at any count: no note.
        let mut nf = outcome(1.0, Some(0.1), Some(1.0), 256, 1);
        nf.judge(1e-4, 1);
        let why = nf.verdict.as_ref().unwrap().reason.clone();
        nf.note_fewer_samples(256, 65536);
        assert!(!nf.passed() && nf.verdict.unwrap().reason == why);
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
        // Every quasi-random sampler is judged by batch means, even where they agree
        // with the plain error (the README: "always judged by batch means").
        for kind in SamplerKind::ALL {
            let quasi = match kind {
                SamplerKind::Independent => false,
                SamplerKind::Stratified | SamplerKind::Sobol => true,
            };
            let bar = ErrorBar::of(&e, kind);
            if quasi {
                assert_eq!(bar.dof, Some(15), "{kind:?}");
                assert_eq!(bar.std_error, Some(e.batches.std_error()), "{kind:?}");
                assert_ne!(bar.std_error, Some(e.batches.total.std_error()), "{kind:?}");
            } else {
                assert_eq!(bar, ind);
            }
        }
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

    /// A quasi-random sampler can stratify a step integrand exactly: every batch of
    /// [0, 1, 0, 1] has the mean ½ to the bit, so the batch-means standard error is 0
    /// though the samples vary. That estimate has no variance to test: it is exact (judged
    /// within the f32 bound, outside the Šidák family), not a z test with σ̂ = 0.
    #[test]
    fn batch_means_without_variance_are_exact() {
        let e = estimate((0..16).map(|_| batch(&[0.0, 1.0, 0.0, 1.0])).collect());
        assert!(!is_exact(&e.batches.total));
        assert_eq!(e.batches.std_error(), 0.0);
        let bar = ErrorBar::of(&e, SamplerKind::Sobol);
        assert!(bar.exact() && bar.dof.is_none(), "{bar:?}");
        let v = judge(&e, SamplerKind::Sobol, 0.5, 1e-4, 10);
        assert!(v.passed && v.class == VerdictClass::Exact, "{v:?}");
        let off = judge(&e, SamplerKind::Sobol, 0.5 * (1.0 + 1e-3), 1e-4, 10);
        assert!(!off.passed && off.class == VerdictClass::Exact, "{off:?}");
        // Batch means that differ beyond rounding keep the t test.
        let mut varied: Vec<_> = (0..16).map(|_| batch(&[0.0, 1.0, 0.0, 1.0])).collect();
        varied[3] = batch(&[0.0, 1.0, 1.0, 1.0]);
        let e = estimate(varied);
        let bar = ErrorBar::of(&e, SamplerKind::Sobol);
        assert_eq!(
            (bar.std_error, bar.dof),
            (Some(e.batches.std_error()), Some(15))
        );
    }

    /// The same estimate through an outcome: `Outcome::new` records it as exact, it is
    /// not a member of the Šidák family (`is_statistical`), `judge_family` counts only
    /// the statistical outcome beside it and judges the exact one within the f32 bound.
    #[test]
    fn batch_means_without_variance_stay_outside_the_family() {
        use crate::transport::phase::Dimensions;
        let e = estimate((0..16).map(|_| batch(&[0.0, 1.0, 0.0, 1.0])).collect());
        let plan = Plan {
            effects: Effects::everything(),
            dims: Dimensions::none(),
        };
        let measure = Measure::SolidAngle {
            from: glam::Vec3::ZERO,
            shape: 0,
        };
        let step = |reference: f64| {
            Outcome::new(
                "step",
                Path::new("step.json"),
                &measure,
                &plan,
                Some(reference),
                Estimator::Light,
                SamplerKind::Sobol,
                1,
                &e,
            )
        };
        // Every sample non-finite: no estimate (NaN, `null` in JSON), never a mean of 0.
        let lost = estimate((0..16).map(|_| batch(&[f64::NAN, f64::INFINITY])).collect());
        let mut o = Outcome::new(
            "lost",
            Path::new("lost.json"),
            &measure,
            &plan,
            Some(0.0),
            Estimator::Light,
            SamplerKind::Sobol,
            1,
            &lost,
        );
        assert!(o.estimate.is_nan() && o.non_finite == 32, "{o:?}");
        assert!(
            serde_json::to_string(&o)
                .unwrap()
                .contains(r#""estimate":null"#)
        );
        o.judge(1e-4, 1);
        assert!(!o.verdict.as_ref().unwrap().passed);
        let o = step(0.5);
        assert!(o.exact && o.std_error.is_none() && o.dof.is_none(), "{o:?}");
        // Exact by its batch means, its samples varying; samples that agree are not.
        assert!(o.exact_by_batch_means);
        let flat = estimate((0..16).map(|_| batch(&[0.5, 0.5])).collect());
        let flat = Outcome::new(
            "flat",
            Path::new("flat.json"),
            &measure,
            &plan,
            Some(0.5),
            Estimator::Light,
            SamplerKind::Sobol,
            1,
            &flat,
        );
        assert!(flat.exact && !flat.exact_by_batch_means, "{flat:?}");
        assert_eq!((o.samples, o.estimate), (64, 0.5));
        assert!(!o.is_statistical());
        let mut run = vec![o, outcome(1.0, Some(0.1), Some(1.0), 100, 0), step(0.6)];
        assert_eq!(judge_family(&mut run, 0, 1e-4), 1);
        let v = run[0].verdict.as_ref().unwrap();
        assert!(
            v.passed && v.class == VerdictClass::Exact && v.alpha == 0.0,
            "{v:?}"
        );
        let off = run[2].verdict.as_ref().unwrap();
        assert!(!off.passed && off.class == VerdictClass::Exact, "{off:?}");
        // The statistical outcome is a family of one: its α₁ is α itself.
        let stat = run[1].verdict.as_ref().unwrap();
        assert_eq!(stat.alpha, crate::stats::sidak_alpha(1e-4, 1));
        assert_eq!(stat.class, VerdictClass::Statistical);
    }

    #[test]
    fn independent_samples_switch_to_batch_means_above_one_and_a_half() {
        // 16 batches of four pairs [m − 1, m + 1] with m = ±a alternating: the batch
        // means spread with a, the plain error less (ratio ≈ a√8/√(a² + 1)). Just below and just above the README's
        // "more than half" again, 1.5× the plain error.
        let lumpy = |a: f64| {
            estimate(
                (0..16)
                    .map(|i| {
                        let m = if i % 2 == 0 { a } else { -a };
                        batch(&[m - 1.0, m + 1.0].repeat(4))
                    })
                    .collect(),
            )
        };
        let ratio = |e: &Estimate| e.batches.std_error() / e.batches.total.std_error();
        let (below, above) = (lumpy(0.6), lumpy(0.65));
        assert!((1.4..1.5).contains(&ratio(&below)), "{}", ratio(&below));
        assert!((1.5..1.6).contains(&ratio(&above)), "{}", ratio(&above));
        assert_eq!(ErrorBar::of(&below, SamplerKind::Independent).dof, None);
        assert_eq!(ErrorBar::of(&above, SamplerKind::Independent).dof, Some(15));
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

    /// An unjudged outcome: mean `estimate` of `samples` samples (`non_finite` of them
    /// not finite) with error bar `std_error` (`None`: exact), against `reference`.
    fn outcome(
        estimate: f64,
        std_error: Option<f64>,
        reference: Option<f64>,
        samples: u64,
        non_finite: u64,
    ) -> Outcome {
        Outcome {
            case: "unit".into(),
            file: "unit.json".into(),
            measure: "irradiance".into(),
            estimator: Estimator::Light,
            sampler: SamplerKind::Independent,
            samples,
            seed: 1,
            estimate,
            std_error,
            dof: None,
            exact: std_error.is_none(),
            exact_by_batch_means: false,
            non_finite,
            seconds: 0.0,
            effects: Effects::everything(),
            reference,
            reference_rounding: 0.0,
            z: None,
            verdict: None,
            bin: None,
        }
    }

    /// ρ is written to JSON where it is not 0 (the outcome's `reference_rounding`, the
    /// verdict's `input_rounding`) and left out where it is, and it reads back.
    #[test]
    fn input_rounding_is_in_the_json_only_where_it_is_not_zero() {
        for rho in [0.0, -3e-7] {
            let mut o = outcome(1.0, Some(0.1), Some(1.0), 1000, 0);
            o.reference_rounding = rho;
            o.judge(1e-4, 1);
            let v = serde_json::to_value(&o).unwrap();
            let written = rho != 0.0;
            assert_eq!(v.get("reference_rounding").is_some(), written, "{v}");
            assert_eq!(v["verdict"].get("input_rounding").is_some(), written, "{v}");
            let back: Outcome = serde_json::from_value(v).unwrap();
            assert_eq!(back.reference_rounding, rho);
            assert_eq!(back.verdict.unwrap().input_rounding, rho);
        }
    }

    /// A pass that cannot see a 0.5 % bias fails inside the proof's conditions and is
    /// marked weak outside them; a pass that can, an exact verdict, a failure and an
    /// unjudged outcome are left as they are.
    #[test]
    fn a_pass_without_power_fails_inside_the_proof_and_is_weak_outside() {
        let judged = |se: f64| {
            let mut o = outcome(1.0, Some(se), Some(1.0), 1 << 16, 0);
            o.judge(1e-4, 1);
            assert!(o.passed());
            o
        };
        // se 1e-4: detects ~5e-4 relative; se 0.1: ~0.5, a hundred times the bound.
        for inside in [true, false] {
            let mut strong = judged(1e-4);
            let before = strong.verdict.clone();
            strong.require_power(inside);
            assert_eq!(strong.verdict, before);
            assert_eq!(strong.verdict.as_ref().unwrap().label(), "pass");
        }
        let mut blind = judged(0.1);
        assert!(
            blind.verdict.as_ref().unwrap().detectable_relative_bias > 100.0 * DETECTABLE_BOUND
        );
        blind.require_power(true);
        let v = blind.verdict.as_ref().unwrap();
        assert!(!blind.passed() && !v.weak && v.label() == "FAIL");
        let why = v.reason.as_deref().unwrap();
        assert!(
            why.contains("cannot see a relative bias below") && why.contains("0.5%"),
            "{why}"
        );
        let mut outside = judged(0.1);
        outside.require_power(false);
        let v = outside.verdict.as_ref().unwrap();
        assert!(outside.passed() && v.weak && v.reason.is_none() && v.label() == "weak");
        // `verify`'s summary counts it as drawn with fewer samples (2¹⁶ of a case's 2²⁰),
        // and a zero-reference weak pass at its own count apart; a plain pass in neither.
        let mut zero_ref = outcome(1e-3, Some(1e-3), Some(0.0), 1 << 16, 0);
        zero_ref.judge(1e-4, 1);
        zero_ref.require_power(true);
        let run = [outside.clone(), zero_ref, judged(1e-4)];
        let counts = [(1 << 16, 1 << 20), (1 << 16, 1 << 16), (1 << 16, 1 << 16)];
        assert_eq!(weak_counts(&run, &counts), (1, 1));
        // At the bound exactly it sees the bias; NaN (a non-finite error bar) sees nothing.
        for (det, passes) in [(DETECTABLE_BOUND, true), (f64::NAN, false)] {
            let mut o = judged(1e-4);
            o.verdict.as_mut().unwrap().detectable_relative_bias = det;
            o.require_power(true);
            assert_eq!(o.passed(), passes, "{det}");
            let why = o.verdict.unwrap().reason.unwrap_or_default();
            assert!(!why.contains("NaN"), "{why}");
        }
        // The samples that would reach the bound: (2.5 % / 0.5 %)² = 25×.
        let mut o = judged(1e-4);
        o.verdict.as_mut().unwrap().detectable_relative_bias = 5.0 * DETECTABLE_BOUND;
        o.require_power(true);
        let why = o.verdict.unwrap().reason.unwrap();
        assert!(
            why.contains("below 2.500%") && why.contains("about 25×"),
            "{why}"
        );
        // An exact verdict's tolerance is the f32 bound, whatever it is: never judged here.
        let mut exact = outcome(1.0, None, Some(1.0), 64, 0);
        exact.judge(1e-4, 1);
        exact.verdict.as_mut().unwrap().detectable_relative_bias = 1.0;
        exact.require_power(true);
        assert!(exact.passed() && !exact.verdict.unwrap().weak);
        // … unless the reference's input rounding widened it past the bound: it fails
        // inside the proof and out, saying why (weak for a zero reference); within the
        // bound it stays a pass.
        for (rho, reference, inside) in [
            (0.012, 2.0, true),
            (-0.012, 2.0, false),
            (0.008, 2.0, true),
            (0.006, 0.0, true),
        ] {
            let mut o = outcome(reference, None, Some(reference), 64, 0);
            o.reference_rounding = rho;
            o.judge(1e-4, 1);
            o.require_power(inside);
            let v = o.verdict.unwrap();
            assert_eq!(v.input_rounding, rho);
            let (fails, weak) = (
                rho.abs() > DETECTABLE_BOUND * reference && reference != 0.0,
                reference == 0.0,
            );
            assert!(
                v.passed != fails && v.weak == weak,
                "{rho} {reference}: {v:?}"
            );
            if fails {
                let why = v.reason.unwrap();
                assert!(
                    why.contains("moves by 0.600%") && why.contains("whatever its sample count"),
                    "{why}"
                );
            }
        }
        // A statistical verdict whose input rounding alone passes the bound fails the same
        // way; one where it is only part of the detectable bias is told how many samples
        // would reach the bound, counting only the part that falls as 1/√N:
        // ((0.9% − 0.3%)/(0.5% − 0.3%))² = 9.
        let stat = |rho: f64, det: f64| {
            let mut o = outcome(2.0, Some(1e-4), Some(2.0), 1 << 16, 0);
            o.reference_rounding = rho;
            o.judge(1e-4, 1);
            o.verdict.as_mut().unwrap().detectable_relative_bias = det;
            o.require_power(true);
            o.verdict.unwrap().reason.unwrap()
        };
        let why = stat(0.012, 0.0065);
        assert!(
            why.contains("whatever its sample count") && !why.contains("raise"),
            "{why}"
        );
        let why = stat(-0.006, 0.009);
        assert!(
            why.contains("moves by 0.300%") && why.contains("about 9×"),
            "{why}"
        );
        // A zero reference: the detectable bias is absolute, no relative power to require.
        let mut zero = outcome(1e-3, Some(1e-3), Some(0.0), 1 << 16, 0);
        zero.judge(1e-4, 1);
        assert!(zero.passed(), "{:?}", zero.verdict);
        zero.require_power(true);
        let v = zero.verdict.as_ref().unwrap();
        assert!(zero.passed() && v.weak && v.reason.is_none(), "{v:?}");
        // … and one whose absolute detectable bias is within the bound (0.005 in the
        // case's units) sees enough: a plain pass, not weak.
        let mut small = outcome(1e-6, Some(1e-6), Some(0.0), 1 << 16, 0);
        small.judge(1e-4, 1);
        let before = small.verdict.clone();
        small.require_power(true);
        let v = small.verdict.as_ref().unwrap();
        assert!(v.detectable_relative_bias < DETECTABLE_BOUND, "{v:?}");
        assert!(
            small.passed() && !v.weak && small.verdict == before,
            "{v:?}"
        );
        // A failure keeps its own reason; an unjudged outcome stays unjudged.
        let mut failed = outcome(2.0, Some(0.1), Some(1.0), 1 << 16, 0);
        failed.judge(1e-4, 1);
        let before = failed.verdict.clone();
        failed.require_power(true);
        assert!(!failed.passed() && failed.verdict == before);
        let mut unjudged = outcome(1.0, Some(0.1), None, 64, 0);
        unjudged.require_power(true);
        assert!(unjudged.verdict.is_none());
    }

    /// Counts compare as the sampler draws them.
    #[test]
    fn fewer_samples_compare_as_drawn() {
        let o = outcome(1.0, Some(0.1), Some(1.0), 256, 0);
        assert!(o.drew_fewer(256, 65536));
        assert!(!o.drew_fewer(65536, 65536));
        assert!(!o.drew_fewer(1 << 20, 65536));
        assert!(!o.drew_fewer(65_500, 65536));
    }

    #[test]
    fn only_a_statistical_outcome_with_a_reference_joins_the_family() {
        assert!(outcome(1.0, Some(0.1), Some(1.0), 100, 0).is_statistical());
        // No reference: nothing to test, even with an error bar.
        assert!(!outcome(1.0, Some(0.1), None, 100, 0).is_statistical());
        // Exact: judged outside the family.
        assert!(!outcome(1.0, None, Some(1.0), 100, 0).is_statistical());
        assert!(!outcome(1.0, None, None, 100, 0).is_statistical());
    }

    #[test]
    fn judging_records_the_verdict_and_its_z_against_the_reference_only() {
        // z = (1.3 − 1)/0.1 = 3 exactly in the test's own terms.
        let mut o = outcome(1.3, Some(0.1), Some(1.0), 1000, 0);
        o.judge(1e-4, 1);
        let v = o.verdict.clone().expect("judged");
        assert_eq!(o.z, Some(v.z));
        assert!((v.z - 3.0).abs() < 1e-9, "z = {}", v.z);
        assert_eq!(v.reference, 1.0);
        assert_eq!(v.std_error, 0.1);
        // |z| = 3 < q(1 − 0.5e-4) ≈ 3.89: passes alone.
        assert!(v.passed && o.passed());
        // The same estimate against another reference 5σ away fails, and the outcome's
        // own verdict is untouched by asking.
        let far = o.verdict_against(0.8, 1e-4, 1);
        assert!(!far.passed);
        assert!((far.z - 5.0).abs() < 1e-9);
        assert_eq!(o.verdict.as_ref().map(|v| v.passed), Some(true));
        // Without a reference, judging leaves the outcome unjudged.
        let mut free = outcome(1.3, Some(0.1), None, 1000, 0);
        free.judge(1e-4, 1);
        assert!(free.verdict.is_none() && free.z.is_none());
    }

    #[test]
    fn an_outcome_verdict_counts_only_finite_samples() {
        // One non-finite sample among 1000: fails whatever the statistic.
        let v = outcome(1.0, Some(0.1), Some(1.0), 1000, 1).verdict_against(1.0, 1e-4, 1);
        assert!(!v.passed);
        assert_eq!(v.non_finite, 1);
        // One finite sample and no non-finite one: too few to judge.
        let one = outcome(1.0, Some(0.1), Some(1.0), 1, 0).verdict_against(1.0, 1e-4, 1);
        assert!(!one.passed);
        assert_eq!(one.reason.as_deref(), Some("fewer than two finite samples"));
        // An exact outcome is judged exactly.
        let exact = outcome(2.0, None, Some(2.0), 10, 0).verdict_against(2.0, 1e-4, 1);
        assert!(exact.passed && exact.class == VerdictClass::Exact);
        let off = outcome(2.0, None, Some(2.0), 10, 0).verdict_against(2.001, 1e-4, 1);
        assert!(!off.passed && off.class == VerdictClass::Exact);
    }

    #[test]
    fn an_unreferenced_outcome_passes_only_with_finite_samples() {
        assert!(outcome(1.0, Some(0.1), None, 10, 0).passed());
        assert!(!outcome(1.0, Some(0.1), None, 10, 1).passed());
        assert!(!outcome(1.0, Some(0.1), None, 0, 0).passed());
        // A judged outcome passes exactly when its verdict does, finite or not.
        let mut o = outcome(2.0, Some(0.1), Some(1.0), 10, 0);
        o.judge(1e-4, 1);
        assert!(!o.passed());
    }

    #[test]
    fn the_family_is_the_statistical_outcomes_plus_the_others() {
        let mut all = vec![
            outcome(1.0, Some(0.1), Some(1.0), 100, 0),
            outcome(1.0, Some(0.1), Some(1.1), 100, 0),
            outcome(3.0, None, Some(3.0), 100, 0),
            outcome(1.0, Some(0.1), None, 100, 0),
        ];
        let k = judge_family(&mut all, 5, 1e-3);
        assert_eq!(k, 7);
        let per_test = crate::stats::sidak_alpha(1e-3, 7);
        for o in &all[..2] {
            let v = o.verdict.as_ref().expect("statistical outcomes are judged");
            assert_eq!(v.class, VerdictClass::Statistical);
            assert_eq!(v.alpha, per_test);
        }
        let exact = all[2].verdict.as_ref().expect("exact outcomes are judged");
        assert!(exact.passed && exact.class == VerdictClass::Exact);
        assert!(all[3].verdict.is_none());
        // No statistical outcome: the family is the others alone.
        let mut none = vec![outcome(3.0, None, Some(3.0), 100, 0)];
        assert_eq!(judge_family(&mut none, 2, 1e-3), 2);
        assert_eq!(judge_family(&mut [], 0, 1e-3), 0);
    }
}
