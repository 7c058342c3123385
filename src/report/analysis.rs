//! From batch accumulators to numbers a person reads: point statistics, the slope fits,
//! efficiency, the time to a relative error, and the best series of a case.
//!
//! Every function here is a pure function of its inputs, so a single run and a merge of
//! shards (which hand it the same accumulators in the same order) write identical
//! numbers.

use super::{
    BATCHES, Best, CaseInfo, CaseReport, Comparison, ErrorMeasure, FORMAT, Fit, HEADLINE, Kind,
    Point, RunInfo, Series, Settings, Status, TARGETS, TimeTo, finite,
};
use crate::sampling::SamplerKind;
use crate::stats::{Accumulator, BatchMeans, fit_cost, fit_slope};
use crate::transport::Estimator;

/// A series from its points, with its fits, efficiency and times filled in
/// ([`summarize`]).
pub fn summarized_series(
    (estimator, sampler, seed): (Estimator, SamplerKind, u64),
    status: Status,
    points: Vec<Point>,
    measure: ErrorMeasure,
    reference: Option<f64>,
) -> Series {
    let mut out = Series {
        estimator,
        sampler,
        seed,
        status,
        points,
        fit_cost: None,
        fit_samples: None,
        fit_seconds: None,
        efficiency: None,
        seconds_per_sample: None,
        time_to: vec![],
        bias_floor: None,
    };
    summarize(&mut out, measure, reference);
    out
}

/// The report of a case from its summarized series (the best series chosen here).
pub fn assemble_case_report(
    id: String,
    case: CaseInfo,
    settings: &Settings,
    measure: ErrorMeasure,
    run: &RunInfo,
    series: Vec<Series>,
) -> CaseReport {
    CaseReport {
        format: FORMAT.to_string(),
        kind: Kind::Case,
        id,
        case,
        settings: settings.clone(),
        error_measure: measure,
        run: run.clone(),
        best: best(&series),
        series,
        plot: None,
    }
}

/// |d|/σ̂ beyond which a point's distance d = x̄ − ref to the reference counts as a bias
/// in its RMS error: the two-sided normal quantile at α = 10⁻⁴, the catalog's family
/// level (per point, uncorrected; with σ̂ from 128 batch means, an unbiased point crosses
/// it about 1.6 times in 10⁴, by Student's t with 127 degrees of freedom).
pub const BIAS_Z: f64 = 3.890_591_886_413_094;

/// The family level of [`bias_floor`]: an unbiased series reports a bias about once in
/// 10⁴ (the catalog's family level).
pub const BIAS_FAMILY_ALPHA: f64 = 1e-4;

/// The least relative bias the points of a series establish, under the engine's model of
/// a bias that does not change with N: the least |β|/|ref| over the biases β every point
/// admits, |x̄ₖ − ref − β| ≤ z σ̂ₖ + γ|x̄ₖ| (z the two-sided quantile of Student's t with
/// B − 1 degrees of freedom, σ̂ from B batch means, at the Šidák level for
/// [`BIAS_FAMILY_ALPHA`] over the points; γ the `f32` rounding an exact verdict allows).
/// `None` where β = 0 is admitted, where no β is (the points disagree among themselves,
/// so the model does not describe them), or without a reference (or with a zero one).
///
/// A point whose samples agree to `f32` rounding (an exact verdict's test: their spread,
/// σ̂_plain·√N, at most γ|x̄|) says nothing about a rare region none of its samples
/// reached, so it takes part only where every point of the series is such (a
/// deterministic estimator): the first two points of a strip's view factor under BSDF
/// sampling with Sobol samples agreed exactly, 1.3% off, and alone "established" a 1.3%
/// bias for a series 0.045% off at 2¹⁶ samples (session 56's review).
///
/// The engine's biases do not fall with N, so an error never goes below a bias: a
/// series 0.2% off whose errors fell from 0.3% and flattened still fitted a negative
/// slope and was given 0.1% at 1.5·10⁵ samples (session 56's audit); [`time_to`] gives
/// no time for a target at or below this floor.
pub fn bias_floor(points: &[Point], reference: Option<f64>) -> Option<f64> {
    use statrs::distribution::{ContinuousCDF, StudentsT};
    // A zero or non-finite reference gives no floor through the last division.
    let r = reference?;
    let gamma = crate::stats::exact_relative_tolerance();
    // (x̄ − ref, σ̂, γ|x̄|, whether the samples agree to f32 rounding).
    let all: Vec<(f64, f64, f64, bool)> = points
        .iter()
        .filter_map(|p| {
            let (x, se, plain) = (p.estimate?, p.std_error?, p.plain_std_error?);
            let rounding = gamma * x.abs();
            let agree = plain * (p.samples as f64).sqrt() <= rounding;
            Some((x - r, se, rounding, agree))
        })
        .collect();
    let deterministic = all.iter().all(|p| p.3);
    let judged: Vec<_> = all.iter().filter(|p| deterministic || !p.3).collect();
    if judged.is_empty() {
        return None;
    }
    let alpha = crate::stats::sidak_alpha(BIAS_FAMILY_ALPHA, judged.len());
    let t = StudentsT::new(0.0, 1.0, (BATCHES - 1) as f64).ok()?;
    let z = t.inverse_cdf(1.0 - alpha / 2.0);
    let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
    for &&(d, se, rounding, _) in &judged {
        let w = z * se + rounding;
        lo = lo.max(d - w);
        hi = hi.min(d + w);
    }
    // The admitted β nearest 0: lo above 0, −hi below it; none where [lo, hi] holds 0
    // or is empty.
    let least = lo.max(-hi);
    (lo <= hi && least > 0.0)
        .then(|| crate::report::finite(least / r.abs()))
        .flatten()
}

/// The statistics of one point from its per-batch accumulators, in batch order.
///
/// `rms_error² = Σ_b (m_b − ref)²/B²` over the B batches that hold a finite sample: the
/// squared standard error of the mean taken about the reference, plus d²/B for the
/// distance d = x̄ − ref. That form holds only 1/B of a bias β (the mean's squared error
/// is β² + σ²/N), so the part of |d| beyond what chance explains, e = max(0, |d| −
/// [`BIAS_Z`]·σ̂) with σ̂ the batch-means standard error, is added as (1 − 1/B)·e²: a bias
/// many standard errors wide (always, when the batches agree exactly and d ≠ 0) shows
/// nearly whole, never √B times smaller, and the error is continuous in d (a point of an
/// unbiased series just past the threshold by chance adds next to nothing).
pub fn point_from_batches(
    samples: u64,
    seed: u64,
    batches: &[Accumulator],
    seconds: f64,
    wall_seconds: Option<f64>,
    reference: Option<f64>,
) -> Point {
    let bm = BatchMeans::from_batches(batches.to_vec());
    let estimate = (bm.total.count > 0).then_some(bm.total.mean);
    let (abs_error, rel_error, rms_error) = match reference.zip(estimate) {
        None => (None, None, None),
        Some((r, estimate)) => {
            let abs = (estimate - r).abs();
            let means: Vec<f64> = bm
                .batches
                .iter()
                .filter(|b| b.count > 0)
                .map(|b| b.mean)
                .collect();
            let rms = if means.is_empty() {
                None
            } else {
                let b = means.len() as f64;
                let ms = means.iter().map(|m| (m - r) * (m - r)).sum::<f64>() / b;
                let beyond = ((estimate - r).abs() - BIAS_Z * bm.std_error()).max(0.0);
                finite((ms / b + beyond * beyond * (1.0 - 1.0 / b)).sqrt())
            };
            (finite(abs), finite(abs / r.abs()), rms)
        }
    };
    Point {
        samples,
        seed,
        estimate,
        std_error: finite(bm.std_error()),
        plain_std_error: finite(bm.total.std_error()),
        rms_error,
        abs_error,
        rel_error,
        non_finite: bm.total.non_finite,
        seconds,
        wall_seconds,
    }
}

/// The error e a report fits: the RMS error against the reference, or the standard error.
pub fn error_of(p: &Point, measure: ErrorMeasure) -> Option<f64> {
    match measure {
        ErrorMeasure::RmsError => p.rms_error,
        ErrorMeasure::StdError => p.std_error,
    }
}

/// The scale of relative errors: |reference|, else |estimate| at the largest point
/// (none where that point has no estimate).
pub(crate) fn scale(series: &Series, reference: Option<f64>) -> Option<f64> {
    let s = match reference {
        Some(r) => r.abs(),
        None => series.points.last()?.estimate?.abs(),
    };
    (s > 0.0 && s.is_finite()).then_some(s)
}

/// Fill the fits, efficiency and times to accuracy of a series from its points.
///
/// - `fit_cost`: t = t₀ + c·N through every point's core-seconds ([`fit_cost`]: relative,
///   robust); the predicted time t̂(N) = t₀ + c·N is what the rest uses, so one noisy
///   short measurement neither makes a curve run backwards nor decides a time to
///   accuracy (measured times are used only when no cost line fits).
/// - `fit_samples`: ln e = a + b ln N; `fit_seconds`: ln e = a′ + b′ ln t̂, over the points
///   with e > 0 (a zero-variance estimator has no slope).
/// - `efficiency = 1/(σ̂² t̂)` at the largest point; `seconds_per_sample = c`.
/// - `bias_floor`: [`bias_floor`].
/// - `time_to[ε]`: none where ε ≤ `bias_floor`; else along the fits,
///   N* = exp((ln(ε·scale) − a)/b) when b is below 0 by more than twice its standard
///   error and t* = t̂(N*), `extrapolated` when N* lies beyond the largest point; without
///   such a fit (zero variance, a flat error, two points), the cheapest point with
///   e/scale ≤ ε.
pub fn summarize(series: &mut Series, measure: ErrorMeasure, reference: Option<f64>) {
    let ns: Vec<f64> = series.points.iter().map(|p| p.samples as f64).collect();
    let ts: Vec<f64> = series.points.iter().map(|p| p.seconds).collect();
    series.fit_cost = fit_cost(&ns, &ts);
    let cost = series.fit_cost;
    let t_hat = |p: &Point| cost.map_or(p.seconds, |c| c.seconds(p.samples as f64));
    let pts: Vec<(f64, f64, f64)> = series
        .points
        .iter()
        .filter_map(|p| {
            let e = error_of(p, measure)?;
            let t = t_hat(p);
            (e > 0.0 && t > 0.0).then(|| ((p.samples as f64).ln(), t.ln(), e.ln()))
        })
        .collect();
    let xs: Vec<f64> = pts.iter().map(|p| p.0).collect();
    let lts: Vec<f64> = pts.iter().map(|p| p.1).collect();
    let ys: Vec<f64> = pts.iter().map(|p| p.2).collect();
    series.fit_samples = fit_slope(&xs, &ys).map(Fit::from);
    series.fit_seconds = fit_slope(&lts, &ys).map(Fit::from);
    let last = series.points.last();
    series.efficiency = last.and_then(|p| {
        let se = p.std_error?;
        let t = t_hat(p);
        (se > 0.0 && t > 0.0).then(|| 1.0 / (se * se * t))
    });
    series.seconds_per_sample = match cost {
        Some(c) => Some(c.per_sample),
        None => last.and_then(|p| finite(p.seconds / p.samples as f64)),
    };
    series.bias_floor = bias_floor(&series.points, reference);
    let scale = scale(series, reference);
    series.time_to = TARGETS
        .iter()
        .map(|&eps| time_to(series, measure, scale, eps))
        .collect();
}

fn time_to(series: &Series, measure: ErrorMeasure, scale: Option<f64>, eps: f64) -> TimeTo {
    let none = TimeTo {
        rel_error: eps,
        samples: None,
        seconds: None,
        extrapolated: false,
    };
    let Some(scale) = scale else {
        return none;
    };
    // Below a bias the points establish, no sample count reaches ε.
    if series.bias_floor.is_some_and(|b| b >= eps) {
        return none;
    }
    let largest = series.points.last().map_or(0.0, |p| p.samples as f64);
    let smallest = series.points.first().map_or(0.0, |p| p.samples as f64);
    match (
        series.fit_samples,
        series.fit_cost,
        series.seconds_per_sample,
    ) {
        (Some(f), cost, Some(sps)) if decreasing(&f) => {
            let n = ((eps * scale).ln() - f.intercept) / f.slope;
            // Not before the sweep's first point: a fit says nothing about fewer samples
            // than were measured.
            let n = finite(n.exp()).map(|n| n.max(smallest));
            let t = |n: f64| cost.map_or(n * sps, |c| c.seconds(n));
            TimeTo {
                samples: n,
                seconds: n.and_then(|n| finite(t(n))),
                extrapolated: n.is_some_and(|n| n > largest),
                ..none
            }
        }
        _ => match series
            .points
            .iter()
            .find(|p| error_of(p, measure).is_some_and(|e| e / scale <= eps))
        {
            Some(p) => TimeTo {
                samples: Some(p.samples as f64),
                seconds: Some(
                    series
                        .fit_cost
                        .map_or(p.seconds, |c| c.seconds(p.samples as f64)),
                ),
                ..none
            },
            None => none,
        },
    }
}

/// Whether an error fit may be extrapolated: its slope is negative by more than twice its
/// standard error. An error that does not fall (a bias's floor, or a zero-variance
/// estimator) predicts nothing: a slope of −2·10⁻⁶ ± 0.4 put 0.1% at 0 samples and
/// 0.01% at none. A fit of two points has no standard error, so it is not extrapolated
/// either (its sign alone, −0.35 from two noisy points, once gave a time to 0.1% ten
/// times the sweep's largest); such a series takes the cheapest point that reached ε.
fn decreasing(f: &Fit) -> bool {
    f.slope_std_error.is_some_and(|se| f.slope + 2.0 * se < 0.0)
}

/// Index of [`HEADLINE`] in [`TARGETS`].
fn headline_slot() -> usize {
    TARGETS.iter().position(|&t| t == HEADLINE).unwrap_or(0)
}

/// The time of a series to [`HEADLINE`].
pub fn headline_time(s: &Series) -> Option<&TimeTo> {
    s.time_to
        .get(headline_slot())
        .filter(|t| t.seconds.is_some())
}

/// The most efficient series: the least time to [`HEADLINE`] relative error, else (no
/// series has one) the highest efficiency among those whose [`Series::bias_floor`] is
/// below the headline; with each other series' ratios. None where no series qualifies.
pub fn best(series: &[Series]) -> Option<Best> {
    let by_time = series
        .iter()
        .enumerate()
        .filter_map(|(i, s)| Some((i, headline_time(s)?.seconds?)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(i, _)| i);
    // By efficiency only among series that may reach the headline: a biased one is
    // efficient at being wrong.
    let by_eff = || {
        series
            .iter()
            .enumerate()
            .filter(|(_, s)| s.bias_floor.is_none_or(|b| b < HEADLINE))
            .filter_map(|(i, s)| Some((i, s.efficiency?)))
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(i, _)| i)
    };
    let i = by_time.or_else(by_eff)?;
    let b = &series[i];
    let t_best = headline_time(b).and_then(|t| t.seconds);
    let others = series
        .iter()
        .enumerate()
        .filter(|(j, _)| *j != i)
        .map(|(_, s)| Comparison {
            estimator: s.estimator,
            sampler: s.sampler,
            time_ratio: match (headline_time(s).and_then(|t| t.seconds), t_best) {
                (Some(t), Some(tb)) if tb > 0.0 => finite(t / tb),
                _ => None,
            },
            efficiency_ratio: match (b.efficiency, s.efficiency) {
                (Some(eb), Some(e)) if e > 0.0 => finite(eb / e),
                _ => None,
            },
        })
        .collect();
    Some(Best {
        estimator: b.estimator,
        sampler: b.sampler,
        rel_error: HEADLINE,
        seconds: t_best,
        extrapolated: headline_time(b).is_some_and(|t| t.extrapolated),
        others,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::Status;
    use crate::sampling::SamplerKind;
    use crate::transport::Estimator;

    fn series(errors: &[(u64, f64, f64)]) -> Series {
        Series {
            estimator: Estimator::Light,
            sampler: SamplerKind::Independent,
            seed: 1,
            status: Status::Complete,
            points: errors
                .iter()
                // No estimate: these series are given their errors directly, which no
                // estimate and reference would all agree with (no bias floor).
                .map(|&(n, e, t)| Point {
                    samples: n,
                    seed: 0,
                    estimate: None,
                    std_error: Some(e),
                    plain_std_error: Some(e),
                    rms_error: Some(e),
                    abs_error: Some(e),
                    rel_error: Some(e),
                    non_finite: 0,
                    seconds: t,
                    wall_seconds: None,
                })
                .collect(),
            fit_cost: None,
            fit_samples: None,
            fit_seconds: None,
            efficiency: None,
            seconds_per_sample: None,
            time_to: vec![],
            bias_floor: None,
        }
    }

    #[test]
    fn exact_half_rate_gives_exact_slope_and_extrapolation() {
        // e = N^-1/2 exactly, t = 1e-6 N.
        let pts: Vec<(u64, f64, f64)> = (8..=14)
            .map(|k| {
                let n = 1u64 << k;
                (n, (n as f64).powf(-0.5), 1e-6 * n as f64)
            })
            .collect();
        let mut s = series(&pts);
        summarize(&mut s, ErrorMeasure::RmsError, Some(1.0));
        let f = s.fit_samples.unwrap();
        assert!((f.slope + 0.5).abs() < 1e-12);
        assert!((s.fit_seconds.unwrap().slope + 0.5).abs() < 1e-12);
        // The cost line is t = 1e-6 N exactly.
        let c = s.fit_cost.unwrap();
        assert!(c.t0.abs() < 1e-12 && (c.per_sample / 1e-6 - 1.0).abs() < 1e-9);
        // 1% needs N = 1e4, inside the sweep (up to 2^14): along the fits, not extrapolated.
        assert!(!s.time_to[0].extrapolated);
        assert!((s.time_to[0].samples.unwrap() / 1e4 - 1.0).abs() < 1e-9);
        assert!((s.time_to[0].seconds.unwrap() / 1e-2 - 1.0).abs() < 1e-9);
        // 0.1% needs N = 1e6, extrapolated: t = 1 s.
        let t = s.time_to[1];
        assert!(t.extrapolated);
        assert!((t.samples.unwrap() / 1e6 - 1.0).abs() < 1e-9);
        assert!((t.seconds.unwrap() - 1.0).abs() < 1e-9);
        // Efficiency 1/(σ² t) at N = 2^14: 1/(2^-14 · 2^14 · 1e-6) = 1e6.
        assert!((s.efficiency.unwrap() / 1e6 - 1.0).abs() < 1e-9);
    }

    #[test]
    fn best_is_the_fastest_to_the_headline() {
        let mk = |c: f64, sampler| {
            let pts: Vec<(u64, f64, f64)> = (8..=12)
                .map(|k| {
                    let n = 1u64 << k;
                    (n, c * (n as f64).powf(-0.5), 1e-6 * n as f64)
                })
                .collect();
            let mut s = series(&pts);
            s.sampler = sampler;
            summarize(&mut s, ErrorMeasure::RmsError, Some(1.0));
            s
        };
        let all = [
            mk(2.0, SamplerKind::Independent),
            mk(1.0, SamplerKind::Sobol),
        ];
        let b = best(&all).unwrap();
        assert_eq!(b.sampler, SamplerKind::Sobol);
        // Twice the error at every N: four times the samples, four times the time.
        let r = b.others[0].time_ratio.unwrap();
        assert!((r - 4.0).abs() < 1e-9, "{r}");
        assert!((b.others[0].efficiency_ratio.unwrap() - 4.0).abs() < 1e-9);
    }

    #[test]
    fn zero_variance_has_no_slope_and_reaches_every_target_at_once() {
        let mut s = series(&[(256, 0.0, 1e-5), (512, 0.0, 2e-5), (1024, 0.0, 4e-5)]);
        summarize(&mut s, ErrorMeasure::RmsError, Some(1.0));
        assert!(s.fit_samples.is_none());
        assert!(s.efficiency.is_none());
        assert!(
            s.time_to
                .iter()
                .all(|t| t.samples == Some(256.0) && !t.extrapolated)
        );
    }

    /// An error that does not fall is not extrapolated: a bias floor of 2·10⁻⁴ (relative)
    /// with noise reaches 1% and 0.1% at the first point measured and 0.01% never (the
    /// fit's slope, within twice its error of 0, once put 0.1% at 0 samples); a falling
    /// error whose fit reaches a target before the first point is given that point.
    #[test]
    fn flat_errors_are_not_extrapolated_and_nothing_precedes_the_sweep() {
        let floor: Vec<(u64, f64, f64)> = [1.0, 0.999_999, 1.000_001, 0.999_998, 1.000_002]
            .iter()
            .enumerate()
            .map(|(k, &w)| (256u64 << k, 2e-4 * w, 1e-6 * (256u64 << k) as f64))
            .collect();
        let mut s = series(&floor);
        summarize(&mut s, ErrorMeasure::RmsError, Some(1.0));
        let f = s.fit_samples.unwrap();
        assert!(f.slope.abs() < 1e-5 && !decreasing(&f), "{f:?}");
        assert_eq!(s.time_to[0].samples, Some(256.0));
        assert_eq!(s.time_to[1].samples, Some(256.0));
        assert_eq!(s.time_to[2].samples, None);
        // e = 10⁻³ N^-½ from N = 256: 1% "at" N = 0.01 by the fit, given as 256.
        let fast: Vec<(u64, f64, f64)> = (8..=12)
            .map(|k| {
                let n = 1u64 << k;
                (n, 1e-3 * (n as f64).powf(-0.5), 1e-6 * n as f64)
            })
            .collect();
        let mut s = series(&fast);
        summarize(&mut s, ErrorMeasure::RmsError, Some(1.0));
        assert!(decreasing(&s.fit_samples.unwrap()));
        assert_eq!(s.time_to[0].samples, Some(256.0));
        assert!(!s.time_to[0].extrapolated);
        // 0.01% at N = 100 by the fit: 256 as well; the fit's own answers stand beyond.
        assert_eq!(s.time_to[2].samples, Some(256.0));
        // Without a standard error (two points) nothing is extrapolated, whatever the sign.
        let two = Fit {
            slope: -0.5,
            slope_std_error: None,
            intercept: 0.0,
            points: 2,
        };
        assert!(!decreasing(&two) && !decreasing(&Fit { slope: 0.0, ..two }));
        assert!(!decreasing(&Fit {
            slope: -0.5,
            slope_std_error: Some(0.3),
            ..two
        }));
        assert!(decreasing(&Fit {
            slope: -0.5,
            slope_std_error: Some(0.2),
            ..two
        }));
    }

    /// Relative targets scale by |reference|: e = 4 N^-½ against a reference of 4 (or −4)
    /// reaches 1% at N = 10⁴; a flat error of 0.02 against 4 (0.5%) reaches 1% at the first
    /// point, at that point's fitted time, and 0.1% never; without a cost line the time is
    /// N times the seconds per sample.
    #[test]
    fn time_to_scales_by_the_reference_and_reads_costs() {
        let pts: Vec<(u64, f64, f64)> = (8..=14)
            .map(|k| {
                let n = 1u64 << k;
                (n, 4.0 * (n as f64).powf(-0.5), 1e-6 * n as f64)
            })
            .collect();
        for r in [4.0, -4.0] {
            let mut s = series(&pts);
            summarize(&mut s, ErrorMeasure::RmsError, Some(r));
            assert!(
                (s.time_to[0].samples.unwrap() / 1e4 - 1.0).abs() < 1e-9,
                "{:?}",
                s.time_to
            );
            assert!(!s.time_to[0].extrapolated && s.time_to[1].extrapolated);
            // Without a cost line: t = N · seconds per sample.
            s.fit_cost = None;
            s.seconds_per_sample = Some(2e-6);
            let t = time_to(&s, ErrorMeasure::RmsError, Some(4.0), 0.01);
            assert!((t.seconds.unwrap() / 2e-2 - 1.0).abs() < 1e-9, "{t:?}");
        }
        let mut flat = series(&[(256, 0.02, 1e-4), (512, 0.02, 2e-4), (1024, 0.02, 4e-4)]);
        summarize(&mut flat, ErrorMeasure::RmsError, Some(4.0));
        assert_eq!(flat.time_to[0].samples, Some(256.0));
        let t = flat.time_to[0].seconds.unwrap();
        assert!((t / 1e-4 - 1.0).abs() < 1e-6, "{t}");
        assert_eq!(flat.time_to[1].samples, None);
    }

    #[test]
    fn rms_error_of_batches() {
        let mk = |v: f64| {
            let mut a = Accumulator::new();
            a.push(v);
            a.push(v);
            a
        };
        // Batch means 1 and 3 against 2: √((1 + 1)/2)/√2 = 1/√2; an empty batch (no
        // finite sample) is not a batch mean.
        let p = point_from_batches(4, 0, &[mk(1.0), mk(3.0)], 1.0, None, Some(2.0));
        assert!((p.rms_error.unwrap() - 0.5f64.sqrt()).abs() < 1e-15);
        let e = point_from_batches(
            4,
            0,
            &[mk(1.0), Accumulator::new(), mk(3.0)],
            1.0,
            None,
            Some(2.0),
        );
        assert_eq!(e.rms_error, p.rms_error);
        assert_eq!(p.abs_error, Some(0.0));
        assert_eq!(p.estimate, Some(2.0));
    }

    /// A point whose every sample is non-finite has no mean: its estimate and its errors
    /// against the reference are null (the estimate read 0.0 and the error |reference|,
    /// numbers no run computed), and with no reference the series has no scale.
    #[test]
    fn a_point_without_a_finite_sample_has_no_estimate() {
        let nan = |n: usize| {
            let mut a = Accumulator::new();
            (0..n).for_each(|_| a.push(f64::NAN));
            a
        };
        for reference in [Some(2.0), None] {
            let p = point_from_batches(4, 0, &[nan(2), nan(2)], 1.0, None, reference);
            assert_eq!(p.estimate, None);
            assert_eq!((p.abs_error, p.rel_error, p.rms_error), (None, None, None));
            assert_eq!(p.non_finite, 4);
            let mut s = series(&[(256, 0.02, 1e-4)]);
            s.points = vec![p];
            assert_eq!(scale(&s, reference), reference);
        }
    }

    /// A bias counts beyond what chance explains: batches that agree exactly (no
    /// variance) off the reference by d give rms_error = |d|, not |d|/√B; batches whose
    /// spread covers d keep the batch form; between, the excess |d| − z σ̂ is added, so the
    /// error is continuous in d; the threshold z is the normal quantile at 10⁻⁴.
    #[test]
    fn a_significant_bias_counts_in_full_in_the_rms_error() {
        use statrs::distribution::{ContinuousCDF, Normal};
        let z = Normal::standard().inverse_cdf(1.0 - 0.5e-4);
        assert!((BIAS_Z - z).abs() < 1e-12, "{z}");
        let batch = |v: f64| {
            let mut a = Accumulator::new();
            a.push(v);
            a.push(v);
            a
        };
        // 128 identical batches at π against 3.140965.
        let flat: Vec<Accumulator> = (0..128).map(|_| batch(std::f64::consts::PI)).collect();
        let p = point_from_batches(256, 0, &flat, 1.0, None, Some(3.140965));
        let d = std::f64::consts::PI - 3.140965;
        assert!(
            (p.rms_error.unwrap() / d - 1.0).abs() < 1e-12,
            "{:?}",
            p.rms_error
        );
        assert!((p.rel_error.unwrap() / (d / 3.140965) - 1.0).abs() < 1e-12);
        let neg = point_from_batches(256, 0, &flat, 1.0, None, Some(-3.140965));
        let want = (std::f64::consts::PI + 3.140965) / 3.140965;
        assert!((neg.rel_error.unwrap() / want - 1.0).abs() < 1e-12);
        // Batch means ±1 about 0.01 (σ̂ = 1/√128 ≈ 0.088): d = 0.01 is not significant,
        // the batch form stays, √(1 + 10⁻⁴)/√128.
        let spread: Vec<Accumulator> = (0..128)
            .map(|i| batch(0.01 + if i % 2 == 0 { 1.0 } else { -1.0 }))
            .collect();
        let p = point_from_batches(256, 0, &spread, 1.0, None, Some(0.0));
        let want = ((1.0 + 1e-4) / 128.0f64).sqrt();
        assert!(
            (p.rms_error.unwrap() / want - 1.0).abs() < 1e-12,
            "{:?}",
            p.rms_error
        );
        // The same spread 0.5 off (σ̂ = 1/√127, the batch means' sample deviation over
        // √128; d/σ̂ ≈ 5.6): the excess e = d − z σ̂ counts, √((1 + d²)/128 + e²(1 − 1/128)).
        let off: Vec<Accumulator> = (0..128)
            .map(|i| batch(0.5 + if i % 2 == 0 { 1.0 } else { -1.0 }))
            .collect();
        let p = point_from_batches(256, 0, &off, 1.0, None, Some(0.0));
        let e = 0.5 - BIAS_Z / 127f64.sqrt();
        let want = ((1.0f64 + 0.25) / 128.0 + e * e * (1.0 - 1.0 / 128.0)).sqrt();
        assert!(
            (p.rms_error.unwrap() / want - 1.0).abs() < 1e-12,
            "{:?}",
            p.rms_error
        );
        // Continuous at the threshold: just below and just above it differ by next to
        // nothing (they jumped from ≈1.05 σ̂ to ≈4 σ̂ with the whole d² added at once).
        let at = |k: f64| {
            let d = k * BIAS_Z / 127f64.sqrt();
            let b: Vec<Accumulator> = (0..128)
                .map(|i| batch(d + if i % 2 == 0 { 1.0 } else { -1.0 }))
                .collect();
            point_from_batches(256, 0, &b, 1.0, None, Some(0.0))
                .rms_error
                .unwrap()
        };
        assert!((at(1.000_001) / at(0.999_999) - 1.0).abs() < 1e-5);
    }

    /// A series 0.3% off its reference whose error fell from the noise and flattened
    /// (session 56's audit: its fit, slope −0.24 ± 0.06, gave 0.1% at 1.5·10⁵ samples):
    /// its points establish a bias of at least |d| − z σ̂ at the largest, so 0.1% and
    /// 0.01% get no time, 1% keeps the fit's; an unbiased series (|d| = σ̂) has no floor.
    #[test]
    fn a_bias_the_points_establish_blocks_the_targets_below_it() {
        use statrs::distribution::{ContinuousCDF, StudentsT};
        let point = |k: usize, d: f64, se: f64| Point {
            samples: 256 << k,
            seed: 0,
            estimate: Some(1.0 + d),
            std_error: Some(se),
            plain_std_error: Some(se),
            rms_error: Some((d * d + se * se).sqrt()),
            abs_error: Some(d),
            rel_error: Some(d),
            non_finite: 0,
            seconds: 1e-6 * (256 << k) as f64,
            wall_seconds: None,
        };
        let se = |k: usize| 0.01 * (2f64).powf(-(k as f64) / 2.0);
        let mut s = series(&[]);
        s.points = (0..12).map(|k| point(k, 3e-3, se(k))).collect();
        summarize(&mut s, ErrorMeasure::RmsError, Some(1.0));
        let f = s.fit_samples.unwrap();
        assert!(decreasing(&f), "{f:?}");
        let t = StudentsT::new(0.0, 1.0, 127.0).unwrap();
        let z = t.inverse_cdf(1.0 - crate::stats::sidak_alpha(1e-4, 12) / 2.0);
        let gamma = crate::stats::exact_relative_tolerance();
        let want = 3e-3 - z * se(11) - gamma * 1.003;
        let floor = s.bias_floor.unwrap();
        assert!((floor / want - 1.0).abs() < 1e-12, "{floor} against {want}");
        assert!(s.time_to[0].samples.is_some(), "{:?}", s.time_to[0]);
        assert_eq!((s.time_to[1].samples, s.time_to[1].seconds), (None, None));
        assert_eq!((s.time_to[2].samples, s.time_to[2].seconds), (None, None));
        // A target just above the floor keeps its time (the floor blocks at or below it).
        let just_above = time_to(&s, ErrorMeasure::RmsError, Some(1.0), floor * 1.000_001);
        assert!(just_above.samples.is_some());
        assert!(
            time_to(&s, ErrorMeasure::RmsError, Some(1.0), floor)
                .samples
                .is_none()
        );
        // The same distances one z σ̂ inside chance at every point: no floor.
        s.points = (0..12)
            .map(|k| point(k, 0.999 * z * se(k), se(k)))
            .collect();
        summarize(&mut s, ErrorMeasure::RmsError, Some(1.0));
        assert_eq!(s.bias_floor, None);
        // A deterministic series (samples that agree) off by 2 at 3: relative to |ref|,
        // less the f32 rounding γ|x̄| an exact verdict allows, on either side of the
        // reference; none without a reference or with a zero one.
        let exact = |x: f64| Point {
            estimate: Some(x),
            std_error: Some(0.0),
            plain_std_error: Some(0.0),
            ..point(0, 0.0, 0.0)
        };
        let near = |a: f64, b: f64| (a / b - 1.0).abs() < 1e-12;
        assert!(near(
            bias_floor(&[exact(3.0)], Some(1.0)).unwrap(),
            2.0 - 3.0 * gamma
        ));
        assert!(near(
            bias_floor(&[exact(3.0)], Some(5.0)).unwrap(),
            (2.0 - 3.0 * gamma) / 5.0
        ));
        assert!(near(
            bias_floor(&[exact(3.0)], Some(-4.0)).unwrap(),
            (7.0 - 3.0 * gamma) / 4.0
        ));
        assert_eq!(bias_floor(&[exact(3.0)], None), None);
        assert_eq!(bias_floor(&[exact(3.0)], Some(0.0)), None);
        // Within the f32 rounding: no floor (a point light read 1.6·10⁻⁷ off).
        assert_eq!(bias_floor(&[exact(1.0 + 0.9 * gamma)], Some(1.0)), None);
    }

    /// A point whose samples agree to f32 rounding establishes nothing beside points
    /// that vary (session 56's review: a view factor's first two points under BSDF
    /// sampling with Sobol samples agreed exactly, 1.3% off, and alone gave a series
    /// 0.045% off at 2¹⁶ samples a 1.3% floor); points that disagree among themselves
    /// admit no common bias and establish none; points consistent with a bias of 1%
    /// establish it.
    #[test]
    fn a_floor_needs_every_point_to_admit_it() {
        let pt = |n: u64, x: f64, se: f64| Point {
            samples: n,
            seed: 0,
            estimate: Some(x),
            std_error: Some(se),
            plain_std_error: Some(se),
            rms_error: None,
            abs_error: None,
            rel_error: None,
            non_finite: 0,
            seconds: 1e-3,
            wall_seconds: None,
        };
        let strip = [
            pt(256, 1.013, 0.0),
            pt(512, 1.013, 0.0),
            pt(1024, 1.0065, 6e-3),
            pt(65536, 0.99955, 4.4e-4),
        ];
        assert_eq!(bias_floor(&strip, Some(1.0)), None);
        // Beside points that vary and admit 0 (and 1.3% too), the points that agree do
        // not decide: counted, they would make a floor of 1.3% alone.
        let wide = [
            pt(256, 1.013, 0.0),
            pt(4096, 1.01, 0.01),
            pt(16384, 1.0, 0.005),
        ];
        assert_eq!(bias_floor(&wide, Some(1.0)), None);
        assert!(bias_floor(&wide[..1], Some(1.0)).unwrap() > 0.0129);
        // Without the point that admits 0, the varying points admit no common bias.
        assert_eq!(
            bias_floor(&[pt(1024, 1.05, 1e-3), pt(4096, 0.95, 1e-3)], Some(1.0)),
            None
        );
        // Each consistent with 1%: the floor is the largest lower end, 1% − z σ̂ − γ|x̄|.
        let biased = [pt(1024, 1.012, 2e-3), pt(4096, 1.0101, 1e-4)];
        let floor = bias_floor(&biased, Some(1.0)).unwrap();
        assert!(floor > 0.0095 && floor < 0.0101, "{floor}");
        // And below the reference, the same.
        let below = [pt(1024, 0.988, 2e-3), pt(4096, 0.9899, 1e-4)];
        let f = bias_floor(&below, Some(1.0)).unwrap();
        assert!((f - floor).abs() < 1e-3, "{f} {floor}");
    }

    /// A biased series is not the best by efficiency: where no series has a time to the
    /// headline, the most efficient one among those without a floor at or above it is
    /// chosen, and none where every series has one.
    #[test]
    fn a_biased_series_is_never_best_by_efficiency() {
        let mut good = series(&[(256, 0.3, 1e-5), (512, 0.3, 2e-5), (1024, 0.3, 4e-5)]);
        summarize(&mut good, ErrorMeasure::RmsError, Some(1.0));
        let mut bad = good.clone();
        bad.sampler = SamplerKind::Sobol;
        bad.efficiency = Some(good.efficiency.unwrap() * 100.0);
        bad.bias_floor = Some(HEADLINE);
        assert!(good.time_to[1].seconds.is_none() && good.efficiency.is_some());
        let b = best(&[bad.clone(), good.clone()]).unwrap();
        assert_eq!(b.sampler, SamplerKind::Independent);
        bad.bias_floor = Some(HEADLINE * 0.999);
        assert_eq!(
            best(&[bad.clone(), good]).unwrap().sampler,
            SamplerKind::Sobol
        );
        bad.bias_floor = Some(HEADLINE);
        assert!(best(&[bad]).is_none());
    }
}
