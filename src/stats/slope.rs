//! Ordinary least squares y = a + b·x with the standard error of the slope,
//! s_b = √(Σr²/(n − 2) / Σ(x − x̄)²) (any regression text, e.g. Draper & Smith §1.4).
//! Applied to (log N, log error) it measures a convergence rate: −½ for Monte Carlo.

use serde::{Deserialize, Serialize};

/// A fitted line.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SlopeFit {
    /// b.
    pub slope: f64,
    /// a.
    pub intercept: f64,
    /// Standard error of b (infinite with fewer than three points).
    pub slope_std_error: f64,
    /// Number of points used.
    pub points: usize,
}

/// Least-squares fit through the finite points.
pub fn fit_slope(x: &[f64], y: &[f64]) -> Option<SlopeFit> {
    let pts: Vec<(f64, f64)> = x
        .iter()
        .zip(y)
        .map(|(&a, &b)| (a, b))
        .filter(|(a, b)| a.is_finite() && b.is_finite())
        .collect();
    let n = pts.len();
    if n < 2 {
        return None;
    }
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n as f64;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n as f64;
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let slope = sxy / sxx;
    let intercept = my - slope * mx;
    let ssr: f64 = pts
        .iter()
        .map(|p| (p.1 - intercept - slope * p.0).powi(2))
        .sum();
    let slope_std_error = if n > 2 {
        (ssr / (n - 2) as f64 / sxx).sqrt()
    } else {
        f64::INFINITY
    };
    Some(SlopeFit {
        slope,
        intercept,
        slope_std_error,
        points: n,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_line() {
        let x = [1.0, 2.0, 3.0, 4.0];
        let y = [3.0, 5.0, 7.0, 9.0];
        let f = fit_slope(&x, &y).unwrap();
        assert!((f.slope - 2.0).abs() < 1e-12 && (f.intercept - 1.0).abs() < 1e-12);
        assert!(f.slope_std_error < 1e-12);
    }

    #[test]
    fn too_few_points() {
        assert!(fit_slope(&[1.0], &[1.0]).is_none());
        assert!(fit_slope(&[1.0, 1.0], &[1.0, 2.0]).is_none());
        // Two points fix the line and leave no degree of freedom: no error bar.
        let two = fit_slope(&[1.0, 2.0], &[1.0, 3.0]).unwrap();
        assert_eq!((two.slope, two.points), (2.0, 2), "{two:?}");
        assert_eq!(two.slope_std_error, f64::INFINITY, "{two:?}");
    }
}
