//! The cost model of an estimator: t(N) = t₀ + c·N core-seconds for N samples.
//!
//! Each point of a convergence sweep is one short measurement: at small N its time is
//! dominated by start-up (building the integrand, waking threads, cache misses) and
//! scheduler noise, so raw times of neighbouring points can even run backwards. A line
//! fitted through all the points of a series separates the fixed cost t₀ from the cost
//! per sample c, and its predictions t₀ + c·N are what plots and times-to-accuracy use.
//!
//! **Fit.** Timing noise is roughly proportional to the time, so the fit minimises the
//! *relative* residuals: weighted least squares with weights wᵢ = 1/tᵢ², made robust by
//! iteratively reweighting with Huber's function (k = 1.345 times the residuals' MAD
//! scale; Huber 1964, Holland & Welsch 1977). The disturbance timing suffers is a point
//! made slower by another process taking the core: its relative weight and its Huber
//! weight both shrink, so it does not bend the line (a point measured too *fast* would
//! pull harder; clocks do not do that). Standard errors come from the weighted
//! normal equations, Cov = s²(XᵀWX)⁻¹ with s² = Σwᵢrᵢ²/(n − 2) (Draper & Smith §9.2).
//! A negative t₀ (possible with noise) is clamped to 0 and c refitted through the
//! origin; a non-positive c means the points do not describe a cost (None).

use serde::{Deserialize, Serialize};

/// A fitted cost line t = t₀ + c·N.
///
/// Unknown fields are refused, as `reports/schema.json` says (`additionalProperties:
/// false`) and every other part of a report does.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CostFit {
    /// Fixed cost t₀ in seconds (≥ 0).
    pub t0: f64,
    /// Standard error of t₀: null with fewer than three points; 0 where a negative
    /// intercept was clamped to 0 (the line then goes through the origin).
    pub t0_std_error: Option<f64>,
    /// Cost per sample c in seconds.
    pub per_sample: f64,
    /// Standard error of c: for the free line null with fewer than three points; where
    /// the line goes through the origin (one parameter, n − 1 degrees of freedom) null
    /// only with a single point.
    pub per_sample_std_error: Option<f64>,
    /// Points used.
    pub points: usize,
}

impl CostFit {
    /// The predicted cost of N samples.
    pub fn seconds(&self, n: f64) -> f64 {
        self.t0 + self.per_sample * n
    }
}

/// Huber's tuning constant: 95% efficiency at the normal distribution.
const HUBER_K: f64 = 1.345;
/// Reweighting rounds (the weights settle in a handful).
const ROUNDS: usize = 20;

/// Fit t = t₀ + c·N through the points (N, t) with N > 0 and t > 0 (others are skipped).
pub fn fit_cost(n: &[f64], t: &[f64]) -> Option<CostFit> {
    let pts: Vec<(f64, f64)> = n
        .iter()
        .zip(t)
        .map(|(&a, &b)| (a, b))
        .filter(|(a, b)| a.is_finite() && b.is_finite() && *a > 0.0 && *b > 0.0)
        .collect();
    if pts.len() < 2 {
        return None;
    }
    let base: Vec<f64> = pts.iter().map(|p| 1.0 / (p.1 * p.1)).collect();
    let mut robust = vec![1.0; pts.len()];
    let mut fit = weighted_line(&pts, &base)?;
    for _ in 0..ROUNDS {
        // Relative residuals and their robust scale (MAD / 0.6745).
        let rel: Vec<f64> = pts
            .iter()
            .map(|&(x, y)| (y - fit.0 - fit.1 * x) / y)
            .collect();
        let mut abs: Vec<f64> = rel.iter().map(|r| r.abs()).collect();
        abs.sort_by(f64::total_cmp);
        let scale = median(&abs) / 0.6745;
        if !(scale > 0.0) {
            break;
        }
        let next: Vec<f64> = rel
            .iter()
            .map(|r| {
                let u = r.abs() / (HUBER_K * scale);
                if u <= 1.0 { 1.0 } else { 1.0 / u }
            })
            .collect();
        let w: Vec<f64> = base.iter().zip(&next).map(|(b, r)| b * r).collect();
        let Some(f) = weighted_line(&pts, &w) else {
            break;
        };
        let settled = robust
            .iter()
            .zip(&next)
            .all(|(a, b): (&f64, &f64)| (a - b).abs() < 1e-9);
        robust = next;
        fit = f;
        if settled {
            break;
        }
    }
    let w: Vec<f64> = base.iter().zip(&robust).map(|(b, r)| b * r).collect();
    let (t0, c, se0, sec) = if fit.0 >= 0.0 {
        fit
    } else {
        through_origin(&pts, &w)?
    };
    if !(c > 0.0 && c.is_finite() && t0.is_finite()) {
        return None;
    }
    let finite = |v: f64| v.is_finite().then_some(v);
    Some(CostFit {
        t0,
        t0_std_error: se0.and_then(finite),
        per_sample: c,
        per_sample_std_error: sec.and_then(finite),
        points: pts.len(),
    })
}

/// Weighted least squares y = a + b·x: (a, b, se(a), se(b)).
#[allow(clippy::type_complexity)]
fn weighted_line(pts: &[(f64, f64)], w: &[f64]) -> Option<(f64, f64, Option<f64>, Option<f64>)> {
    let sw: f64 = w.iter().sum();
    let mx = pts.iter().zip(w).map(|(p, w)| w * p.0).sum::<f64>() / sw;
    let my = pts.iter().zip(w).map(|(p, w)| w * p.1).sum::<f64>() / sw;
    let sxx: f64 = pts.iter().zip(w).map(|(p, w)| w * (p.0 - mx).powi(2)).sum();
    if !(sxx > 0.0) {
        return None;
    }
    let sxy: f64 = pts
        .iter()
        .zip(w)
        .map(|(p, w)| w * (p.0 - mx) * (p.1 - my))
        .sum();
    let b = sxy / sxx;
    let a = my - b * mx;
    let n = pts.len();
    let (sea, seb) = if n > 2 {
        let s2 = pts
            .iter()
            .zip(w)
            .map(|(p, w)| w * (p.1 - a - b * p.0).powi(2))
            .sum::<f64>()
            / (n - 2) as f64;
        (
            Some((s2 * (1.0 / sw + mx * mx / sxx)).sqrt()),
            Some((s2 / sxx).sqrt()),
        )
    } else {
        (None, None)
    };
    Some((a, b, sea, seb))
}

/// Weighted least squares y = b·x (t₀ clamped to 0): (0, b, se(t₀) = 0, se(b)).
#[allow(clippy::type_complexity)]
fn through_origin(pts: &[(f64, f64)], w: &[f64]) -> Option<(f64, f64, Option<f64>, Option<f64>)> {
    let sxx: f64 = pts.iter().zip(w).map(|(p, w)| w * p.0 * p.0).sum();
    if !(sxx > 0.0) {
        return None;
    }
    let b = pts.iter().zip(w).map(|(p, w)| w * p.0 * p.1).sum::<f64>() / sxx;
    let n = pts.len();
    let seb = (n > 1).then(|| {
        let s2 = pts
            .iter()
            .zip(w)
            .map(|(p, w)| w * (p.1 - b * p.0).powi(2))
            .sum::<f64>()
            / (n - 1) as f64;
        (s2 / sxx).sqrt()
    });
    Some((0.0, b, Some(0.0), seb))
}

fn median(sorted: &[f64]) -> f64 {
    let n = sorted.len();
    if n % 2 == 1 {
        sorted[n / 2]
    } else {
        0.5 * (sorted[n / 2 - 1] + sorted[n / 2])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ns() -> Vec<f64> {
        (8..=20).map(|k| (1u64 << k) as f64).collect()
    }

    #[test]
    fn recovers_an_exact_line() {
        let n = ns();
        let t: Vec<f64> = n.iter().map(|n| 2e-3 + 5e-7 * n).collect();
        let f = fit_cost(&n, &t).unwrap();
        assert!((f.t0 - 2e-3).abs() < 1e-12, "{f:?}");
        assert!((f.per_sample - 5e-7).abs() < 1e-15, "{f:?}");
        assert!(f.t0_std_error.unwrap() < 1e-12 && f.per_sample_std_error.unwrap() < 1e-15);
        assert_eq!(f.points, n.len());
        assert!((f.seconds(1e6) - (2e-3 + 0.5)).abs() < 1e-9);
    }

    #[test]
    fn one_disturbed_point_does_not_bend_the_line() {
        let n = ns();
        let mut t: Vec<f64> = n.iter().map(|n| 1e-3 + 1e-6 * n).collect();
        // Small relative noise everywhere, one small point 20× too slow and the largest
        // 1.5× too slow (another process took the core).
        for (i, x) in t.iter_mut().enumerate() {
            *x *= 1.0 + 0.01 * ((i * 7 % 5) as f64 - 2.0) / 2.0;
        }
        t[3] *= 20.0;
        t[12] *= 1.5;
        let f = fit_cost(&n, &t).unwrap();
        assert!((f.per_sample / 1e-6 - 1.0).abs() < 0.02, "{f:?}");
        assert!((f.t0 / 1e-3 - 1.0).abs() < 0.2, "{f:?}");
        // Ordinary least squares is pulled far off by them.
        let w = vec![1.0; t.len()];
        let pts: Vec<(f64, f64)> = n.iter().copied().zip(t.iter().copied()).collect();
        let plain = weighted_line(&pts, &w).unwrap();
        assert!((plain.0 / 1e-3 - 1.0).abs() > 0.2, "{plain:?}");
    }

    #[test]
    fn standard_errors_are_the_weighted_normal_equations() {
        // Points off a line with weights: the covariance s²(XᵀWX)⁻¹ written out as a 2×2
        // inverse, s² = Σw r²/(n − 2) (Draper & Smith §9.2).
        let pts = [
            (1.0, 2.9),
            (2.0, 5.2),
            (4.0, 8.8),
            (8.0, 17.3),
            (16.0, 33.1),
        ];
        let w = [1.0, 0.5, 2.0, 0.25, 0.125];
        let (a, b, sea, seb) = weighted_line(&pts, &w).unwrap();
        let (s0, s1, s2): (f64, f64, f64) = pts
            .iter()
            .zip(&w)
            .fold((0.0, 0.0, 0.0), |(s0, s1, s2), (p, w)| {
                (s0 + w, s1 + w * p.0, s2 + w * p.0 * p.0)
            });
        let det = s0 * s2 - s1 * s1;
        let rss: f64 = pts
            .iter()
            .zip(&w)
            .map(|(p, w)| w * (p.1 - a - b * p.0).powi(2))
            .sum();
        let s2r = rss / 3.0;
        assert!((sea.unwrap() / (s2r * s2 / det).sqrt() - 1.0).abs() < 1e-12);
        assert!((seb.unwrap() / (s2r * s0 / det).sqrt() - 1.0).abs() < 1e-12);
        // Through the origin: one parameter, n − 1 degrees of freedom.
        let (t0, c, se0, sec) = through_origin(&pts, &w).unwrap();
        assert_eq!((t0, se0), (0.0, Some(0.0)));
        let rss: f64 = pts
            .iter()
            .zip(&w)
            .map(|(p, w)| w * (p.1 - c * p.0).powi(2))
            .sum();
        assert!((sec.unwrap() / (rss / 4.0 / s2).sqrt() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn a_negative_fixed_cost_is_clamped_and_bad_points_skipped() {
        let n = [256.0, 512.0, 1024.0, 2048.0, f64::NAN, -4.0];
        let t = [2.4e-4, 5.2e-4, 1.0e-3, 2.0e-3, 1.0, 1.0];
        let f = fit_cost(&n, &t).unwrap();
        assert_eq!(f.t0, 0.0);
        assert_eq!(f.points, 4);
        assert!((f.per_sample / 9.9e-7 - 1.0).abs() < 0.05, "{f:?}");
        // Falling times describe no cost; too few points none either.
        assert!(fit_cost(&[1.0, 2.0, 3.0], &[3.0, 2.0, 1.0]).is_none());
        assert!(fit_cost(&[1.0], &[1.0]).is_none());
        assert!(fit_cost(&[4.0, 4.0], &[1.0, 2.0]).is_none());
        // Two points: the free line has no degrees of freedom left (no errors), the one
        // through the origin (a negative intercept clamped) has one: t₀'s error is 0 and
        // c's that of a one-parameter fit.
        let free = fit_cost(&[1.0, 2.0], &[2.0, 3.0]).unwrap();
        assert!(
            free.t0 > 0.0 && free.t0_std_error.is_none() && free.per_sample_std_error.is_none(),
            "{free:?}"
        );
        let clamped = fit_cost(&[1.0, 2.0], &[1.0, 3.0]).unwrap();
        assert_eq!(
            (clamped.t0, clamped.t0_std_error),
            (0.0, Some(0.0)),
            "{clamped:?}"
        );
        assert!(
            clamped.per_sample_std_error.is_some_and(|e| e > 0.0),
            "{clamped:?}"
        );
    }
}
