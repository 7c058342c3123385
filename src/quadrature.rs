//! The engine's own deterministic quadrature, in f64: Gauss–Legendre rules and an
//! adaptive bisection on them. The oracle (`lightproof-analytic`) has its own; the two
//! never share code, so a reference computed by one can judge a value computed by the
//! other (`oracle_and_engine_share_no_code` in `tests/proof/catalog.rs` enforces the direction).
//!
//! **Rule.** The n-point Gauss–Legendre rule integrates polynomials of degree 2n − 1
//! exactly on [−1, 1]; its nodes are the roots of Pₙ, found by Newton's method from
//! Tricomi's initial guess cos(π(i − ¼)/(n + ½)), with weights 2/((1 − x²) Pₙ′(x)²)
//! (Abramowitz & Stegun 25.4.29; Press et al., *Numerical Recipes*, §4.6).
//!
//! **Adaptive.** A panel is accepted when the n-point rule on it and the sum of the
//! rule on its two halves agree within the panel's share of the tolerance; otherwise
//! both halves are refined (depth-limited, so the cost is bounded for any integrand).

/// An n-point Gauss–Legendre rule on [−1, 1].
#[derive(Clone, Debug, PartialEq)]
pub struct GaussLegendre {
    nodes: Vec<f64>,
    weights: Vec<f64>,
}

impl GaussLegendre {
    /// The rule with `n` ≥ 1 points (`n` = 0 is taken as 1).
    pub fn new(n: usize) -> Self {
        let n = n.max(1);
        let mut nodes = vec![0.0; n];
        let mut weights = vec![0.0; n];
        let nf = n as f64;
        for i in 0..n.div_ceil(2) {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (nf + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                let (p, d) = legendre(n, x);
                dp = d;
                let dx = p / d;
                x -= dx;
                if dx.abs() < 1e-16 {
                    break;
                }
            }
            let (_, d) = legendre(n, x);
            dp = if d.is_finite() { d } else { dp };
            let w = 2.0 / ((1.0 - x * x) * dp * dp);
            nodes[i] = -x;
            nodes[n - 1 - i] = x;
            weights[i] = w;
            weights[n - 1 - i] = w;
        }
        GaussLegendre { nodes, weights }
    }

    /// Nodes on [−1, 1], increasing.
    pub fn nodes(&self) -> &[f64] {
        &self.nodes
    }

    /// Weights (summing to 2).
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// ∫ₐᵇ f by this rule on one panel.
    pub fn integrate(&self, f: &mut impl FnMut(f64) -> f64, a: f64, b: f64) -> f64 {
        let (m, h) = (0.5 * (a + b), 0.5 * (b - a));
        let s: f64 = self
            .nodes
            .iter()
            .zip(&self.weights)
            .map(|(x, w)| w * f(m + h * x))
            .sum();
        s * h
    }

    /// ∫ₐᵇ f by this rule on `panels` equal panels.
    pub fn composite(&self, f: &mut impl FnMut(f64) -> f64, a: f64, b: f64, panels: usize) -> f64 {
        let panels = panels.max(1);
        let h = (b - a) / panels as f64;
        (0..panels)
            .map(|i| self.integrate(f, a + i as f64 * h, a + (i + 1) as f64 * h))
            .sum()
    }
}

/// Pₙ(x) and Pₙ′(x) by the three-term recurrence.
fn legendre(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    for k in 2..=n {
        let kf = k as f64;
        let p2 = ((2.0 * kf - 1.0) * x * p1 - (kf - 1.0) * p0) / kf;
        p0 = p1;
        p1 = p2;
    }
    let p = if n == 0 { p0 } else { p1 };
    let dp = n as f64 * (x * p - p0) / (x * x - 1.0);
    (p, dp)
}

/// ∫ₐᵇ f to within max(`rel_tol`·|∫f|, `abs_tol`), by adaptive bisection on the
/// 10-point rule (at most 2²⁰ panels). `abs_tol` should reflect the integrand's own
/// accuracy: an integral of rounding noise (a reflectance of ~1e-16 at η = 1) cannot be
/// resolved relatively.
pub fn adaptive(mut f: impl FnMut(f64) -> f64, a: f64, b: f64, rel_tol: f64, abs_tol: f64) -> f64 {
    let rule = GaussLegendre::new(10);
    let whole = rule.integrate(&mut f, a, b);
    let tol = (rel_tol * whole.abs()).max(abs_tol).max(f64::MIN_POSITIVE);
    refine(&rule, &mut f, a, b, whole, tol, 0)
}

fn refine(
    rule: &GaussLegendre,
    f: &mut impl FnMut(f64) -> f64,
    a: f64,
    b: f64,
    whole: f64,
    tol: f64,
    depth: u32,
) -> f64 {
    let m = 0.5 * (a + b);
    let (l, r) = (rule.integrate(f, a, m), rule.integrate(f, m, b));
    // Converged, or the difference is down to the rounding of the panel sums (a tighter
    // tolerance than f64 can hold would otherwise refine to the depth limit).
    let err = (l + r - whole).abs();
    if depth >= 20 || err <= tol || err <= 16.0 * f64::EPSILON * (l.abs() + r.abs()) {
        return l + r;
    }
    refine(rule, f, a, m, l, 0.5 * tol, depth + 1) + refine(rule, f, m, b, r, 0.5 * tol, depth + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rules_are_exact_for_their_degree() {
        for n in [1, 2, 3, 4, 5, 8, 10, 16, 33] {
            let g = GaussLegendre::new(n);
            assert!(
                (g.weights().iter().sum::<f64>() - 2.0).abs() < 1e-13,
                "n = {n}"
            );
            assert!(g.nodes().windows(2).all(|w| w[0] < w[1]), "n = {n}");
            // ∫₀¹ x^k = 1/(k + 1) for k ≤ 2n − 1.
            for k in 0..2 * n {
                let v = g.integrate(&mut |x| x.powi(k as i32), 0.0, 1.0);
                assert!(
                    (v - 1.0 / (k as f64 + 1.0)).abs() < 1e-12,
                    "n = {n}, k = {k}: {v}"
                );
            }
        }
        // The 4-point nodes and weights (A&S table 25.4).
        let g = GaussLegendre::new(4);
        assert!((g.nodes()[3] - 0.861_136_311_594_052_6).abs() < 1e-15);
        assert!((g.weights()[2] - 0.652_145_154_862_546_1).abs() < 1e-15);
        assert_eq!(GaussLegendre::new(0), GaussLegendre::new(1));
    }

    #[test]
    fn adaptive_handles_kinks_and_peaks() {
        // ∫₀¹ √x = 2/3 (singular derivative), ∫ |x − 0.3| over [0, 1] = 0.29 (kink).
        assert!((adaptive(f64::sqrt, 0.0, 1.0, 1e-12, 0.0) - 2.0 / 3.0).abs() < 1e-11);
        assert!((adaptive(|x: f64| (x - 0.3).abs(), 0.0, 1.0, 1e-12, 0.0) - 0.29).abs() < 1e-12);
        // A narrow Lorentzian: ∫ ε/(x² + ε²) over [−1, 1] = 2 atan(1/ε).
        let e: f64 = 1e-4;
        let want = 2.0 * (1.0 / e).atan();
        let got = adaptive(|x| e / (x * x + e * e), -1.0, 1.0, 1e-10, 0.0);
        assert!((got - want).abs() < 1e-8 * want, "{got} {want}");
        // A tolerance below f64's resolution stops at the rounding floor, not 2²⁰ panels.
        let mut calls = 0u64;
        let tiny = adaptive(
            |x: f64| {
                calls += 1;
                1e-10 * (1.0 + x)
            },
            0.0,
            1.0,
            1e-30,
            0.0,
        );
        assert!(
            (tiny - 1.5e-10).abs() < 1e-24 && calls < 1000,
            "{tiny} after {calls} calls"
        );
        // Noise of 1e-16 (a reflectance at η = 1) stops at the absolute tolerance.
        let mut k = 0u64;
        let noise = adaptive(
            |x: f64| {
                k += 1;
                1e-16 * (1e4 * x).sin().abs()
            },
            0.0,
            1.0,
            1e-12,
            1e-15,
        );
        assert!(noise < 1e-15 && k < 1000, "{noise} after {k} calls");
        let c = GaussLegendre::new(4).composite(&mut |x: f64| x.exp(), 0.0, 2.0, 8);
        assert!((c - (2f64.exp() - 1.0)).abs() < 1e-13);
    }
}
