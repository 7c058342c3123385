//! Numerical quadrature: the *independent* side of every closed-form test.
//!
//! - [`GaussLegendre`]: n-point Gauss–Legendre rules with nodes found by Newton's method
//!   on the Legendre recurrence (Golub & Welsch would also do; see Press et al.,
//!   *Numerical Recipes* 3rd ed. §4.6). No tabulated constants to mistype.
//! - [`adaptive`]: globally-toleranced adaptive bisection, comparing one 12-point rule on
//!   an interval against the same rule on its two halves. Integrable endpoint
//!   singularities (log, inverse square root) are handled by the bisection depth.
//! - [`adaptive_2d`]: nested adaptive integration over a region
//!   `a ≤ x ≤ b, lo(x) ≤ y ≤ hi(x)`.
//!
//! Smooth integrands converge geometrically, so tolerances of 1e-12 relative are cheap;
//! the closed-form tests then ask for agreement ~1e-9 or better, leaving a margin of
//! several orders of magnitude over the quadrature's own error estimate.

use std::cell::Cell;
use std::f64::consts::PI;
use std::sync::OnceLock;

thread_local! {
    static EVALUATIONS: Cell<u64> = const { Cell::new(0) };
}

/// The number of integrand evaluations made by [`GaussLegendre::integrate`] (and so by
/// [`adaptive`] and [`adaptive_2d`]) on the calling thread so far: the tests bound the
/// cost of a quadrature by the difference of two readings, which, unlike a clock, does
/// not depend on the machine or its load.
pub fn evaluations() -> u64 {
    EVALUATIONS.with(Cell::get)
}

/// An n-point Gauss–Legendre rule on [-1, 1].
#[derive(Debug, Clone)]
pub struct GaussLegendre {
    nodes: Vec<f64>,
    weights: Vec<f64>,
}

impl GaussLegendre {
    /// Builds the n-point rule (n ≥ 1). Exact for polynomials of degree ≤ 2n − 1.
    pub fn new(n: usize) -> Self {
        assert!(n >= 1, "a Gauss–Legendre rule needs at least one node");
        let mut nodes = vec![0.0; n];
        let mut weights = vec![0.0; n];
        let nf = n as f64;
        for i in 0..n.div_ceil(2) {
            // Tricomi's initial guess, then Newton on P_n.
            let mut x = (PI * (i as f64 + 0.75) / (nf + 0.5)).cos();
            let mut dp = 0.0;
            for _ in 0..100 {
                let (p, d) = legendre_and_derivative(n, x);
                dp = d;
                let dx = p / d;
                x -= dx;
                if dx.abs() < 1e-16 {
                    let (_, d) = legendre_and_derivative(n, x);
                    dp = d;
                    break;
                }
            }
            let w = 2.0 / ((1.0 - x * x) * dp * dp);
            nodes[i] = -x;
            nodes[n - 1 - i] = x;
            weights[i] = w;
            weights[n - 1 - i] = w;
        }
        Self { nodes, weights }
    }

    /// The rule's nodes on [-1, 1], ascending.
    pub fn nodes(&self) -> &[f64] {
        &self.nodes
    }

    /// The rule's weights (sum to 2).
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// ∫_a^b f(x) dx by this rule.
    pub fn integrate(&self, f: &mut impl FnMut(f64) -> f64, a: f64, b: f64) -> f64 {
        let h = 0.5 * (b - a);
        let m = 0.5 * (a + b);
        let mut s = 0.0;
        for (x, w) in self.nodes.iter().zip(&self.weights) {
            s += w * f(m + h * x);
        }
        EVALUATIONS.with(|c| c.set(c.get() + self.nodes.len() as u64));
        s * h
    }
}

/// P_n(x) and P_n'(x) by the three-term recurrence.
fn legendre_and_derivative(n: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    for k in 2..=n {
        let kf = k as f64;
        let p2 = ((2.0 * kf - 1.0) * x * p1 - (kf - 1.0) * p0) / kf;
        p0 = p1;
        p1 = p2;
    }
    let p = if n == 0 { 1.0 } else { p1 };
    let pm1 = if n == 0 { 0.0 } else { p0 };
    let d = n as f64 * (x * p - pm1) / (x * x - 1.0);
    (p, d)
}

fn rule12() -> &'static GaussLegendre {
    static RULE: OnceLock<GaussLegendre> = OnceLock::new();
    RULE.get_or_init(|| GaussLegendre::new(12))
}

const MAX_DEPTH: u32 = 48;

/// ∫_a^b f(x) dx to a *relative* tolerance `rel_tol` of the integral's magnitude (with an
/// absolute floor of `rel_tol·1e-300`), by adaptive bisection of a 12-point
/// Gauss–Legendre rule.
///
/// A non-finite integrand (NaN or ±∞ somewhere, e.g. parameters whose arithmetic
/// overflows; or values near f64::MAX whose sums overflow, where the coarse sum is
/// returned unrefined) cannot converge: its value is returned as soon as it shows, so that the
/// caller's finiteness check reports it, instead of bisecting to the evaluation cap,
/// which a nested rule ([`adaptive_2d`]) multiplies into hours (a rough-conductor albedo
/// with η = 10³⁰⁸ took over ten minutes before it failed). A NaN `rel_tol` gives NaN.
pub fn adaptive(f: impl FnMut(f64) -> f64, a: f64, b: f64, rel_tol: f64) -> f64 {
    adaptive_abs(f, a, b, rel_tol, 0.0)
}

/// [`adaptive`] to the looser of the relative tolerance `rel_tol` and the *absolute*
/// tolerance `abs_tol`: for a part of a larger sum known to be small beside it, whose own
/// relative accuracy matters little and may be unattainable (a tiny integrand whose
/// rounding noise is a large fraction of it). `abs_tol` = 0 is [`adaptive`] exactly.
///
/// A NaN tolerance gives NaN: `max` took it for the other or the 1e-300 floor, and a
/// finite integral came back.
pub fn adaptive_abs(
    mut f: impl FnMut(f64) -> f64,
    a: f64,
    b: f64,
    rel_tol: f64,
    abs_tol: f64,
) -> f64 {
    if rel_tol.is_nan() || abs_tol.is_nan() {
        return f64::NAN;
    }
    if a == b {
        return 0.0;
    }
    let rule = rule12();
    // A first coarse pass over 8 pieces sets the scale of the absolute tolerance.
    const PIECES: usize = 8;
    let edge = |i: usize| a + (b - a) * i as f64 / PIECES as f64;
    let coarse: Vec<f64> = (0..PIECES)
        .map(|i| rule.integrate(&mut f, edge(i), edge(i + 1)))
        .collect();
    let scale: f64 = coarse.iter().map(|v| v.abs()).sum();
    if !scale.is_finite() {
        return coarse.iter().sum();
    }
    let tol = (rel_tol * scale).max(abs_tol).max(1e-300);
    let mut evals = 0usize;
    (0..PIECES)
        .map(|i| {
            let ctx = Ctx {
                rule,
                tol_floor: 4.0 * f64::EPSILON * scale,
            };
            recurse(
                &mut f,
                &ctx,
                edge(i),
                edge(i + 1),
                coarse[i],
                tol / PIECES as f64,
                0,
                &mut evals,
            )
        })
        .sum()
}

/// Hard cap on the rule applications (12 integrand evaluations each) of one call of
/// [`adaptive`], shared by all its 8 top-level pieces (one counter), so an unattainable
/// tolerance degrades accuracy instead of running away: once it is spent, every pending
/// sub-interval returns after one more bisection, so a call makes at most about
/// 2.4·10⁵ evaluations (241 056 measured on a noisy integrand).
const MAX_EVALS: usize = 20_000;

struct Ctx<'r> {
    rule: &'r GaussLegendre,
    /// Below this the difference between the two estimates is rounding noise.
    tol_floor: f64,
}

#[allow(clippy::too_many_arguments)]
fn recurse(
    f: &mut impl FnMut(f64) -> f64,
    ctx: &Ctx<'_>,
    a: f64,
    b: f64,
    whole: f64,
    tol: f64,
    depth: u32,
    evals: &mut usize,
) -> f64 {
    let m = 0.5 * (a + b);
    let left = ctx.rule.integrate(f, a, m);
    let right = ctx.rule.integrate(f, m, b);
    *evals += 2;
    let sum = left + right;
    let err = (sum - whole).abs();
    if !err.is_finite() {
        return sum;
    }
    if err <= tol.max(ctx.tol_floor) || depth >= MAX_DEPTH || *evals > MAX_EVALS || m <= a || m >= b
    {
        return sum;
    }
    recurse(f, ctx, a, m, left, 0.5 * tol, depth + 1, evals)
        + recurse(f, ctx, m, b, right, 0.5 * tol, depth + 1, evals)
}

/// ∫_a^b ∫_{lo(x)}^{hi(x)} f(x, y) dy dx, nested [`adaptive`] with relative tolerance
/// `rel_tol` on both levels. A NaN `rel_tol` gives NaN.
pub fn adaptive_2d(
    f: impl FnMut(f64, f64) -> f64,
    a: f64,
    b: f64,
    lo: impl Fn(f64) -> f64,
    hi: impl Fn(f64) -> f64,
    rel_tol: f64,
) -> f64 {
    adaptive_2d_abs(f, a, b, lo, hi, rel_tol, 0.0)
}

/// [`adaptive_2d`] with an absolute floor `abs_tol` on the whole integral
/// ([`adaptive_abs`]); each inner integral gets 0.1·`abs_tol`/|b − a|, so that the inner
/// errors integrate to at most a tenth of it. `abs_tol` = 0 is [`adaptive_2d`] exactly.
/// A NaN tolerance gives NaN ([`adaptive_abs`]).
pub fn adaptive_2d_abs(
    mut f: impl FnMut(f64, f64) -> f64,
    a: f64,
    b: f64,
    lo: impl Fn(f64) -> f64,
    hi: impl Fn(f64) -> f64,
    rel_tol: f64,
    abs_tol: f64,
) -> f64 {
    let inner_abs = if a == b {
        0.0
    } else {
        0.1 * abs_tol / (b - a).abs()
    };
    adaptive_abs(
        |x| adaptive_abs(|y| f(x, y), lo(x), hi(x), rel_tol * 0.1, inner_abs),
        a,
        b,
        rel_tol,
        abs_tol,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_is_exact_on_polynomials() {
        for n in [1, 2, 5, 12, 20] {
            let r = GaussLegendre::new(n);
            assert!((r.weights().iter().sum::<f64>() - 2.0).abs() < 1e-14);
            for k in 0..(2 * n) {
                let exact = if k % 2 == 1 {
                    0.0
                } else {
                    2.0 / (k as f64 + 1.0)
                };
                let got = r.integrate(&mut |x: f64| x.powi(k as i32), -1.0, 1.0);
                assert!((got - exact).abs() < 1e-13, "n={n} k={k} got={got}");
            }
        }
    }

    #[test]
    fn adaptive_handles_endpoint_singularities() {
        // ∫_0^1 ln x dx = -1; ∫_0^1 x^{-1/2} dx = 2; ∫_0^π sin = 2.
        let v = adaptive(|x: f64| x.ln(), 0.0, 1.0, 1e-13);
        assert!((v + 1.0).abs() < 1e-11, "{v}");
        let v = adaptive(|x: f64| 1.0 / x.sqrt(), 0.0, 1.0, 1e-13);
        assert!((v - 2.0).abs() < 1e-7, "{v}");
        let v = adaptive(f64::sin, 0.0, PI, 1e-14);
        assert!((v - 2.0).abs() < 1e-14);
    }

    #[test]
    fn adaptive_2d_area_of_unit_disk() {
        let v = adaptive_2d(
            |_, _| 1.0,
            -1.0,
            1.0,
            |x| -(1.0 - x * x).max(0.0).sqrt(),
            |x| (1.0 - x * x).max(0.0).sqrt(),
            1e-12,
        );
        assert!((v - PI).abs() < 1e-9, "{v}");
    }

    /// A non-finite integrand is returned at once: NaN on a sliver of the interval (seen
    /// only once the rule bisects towards it), NaN and +∞ everywhere, in one and two
    /// dimensions, each within a few hundred evaluations per level (the cap would allow
    /// ~2.4·10⁵ per level, 5.8·10¹⁰ nested).
    /// The evaluation cap ([`MAX_EVALS`]) holds for an integrand whose relative
    /// tolerance is unattainable (noise of 1e-6 on 1, asked for 1e-12): one call of [`adaptive`]
    /// stops near 20 000 rule applications, all 8 pieces together, and
    /// [`evaluations`] counts every integrand evaluation.
    #[test]
    fn the_evaluation_cap_is_shared_by_the_pieces() {
        let noise = |x: f64| {
            let b = x.to_bits().wrapping_mul(0x9E37_79B9_7F4A_7C15);
            1.0 + (b >> 11) as f64 * 1e-6 / (1u64 << 53) as f64
        };
        let n = std::cell::Cell::new(0u64);
        let e0 = evaluations();
        let v = adaptive(
            |x| {
                n.set(n.get() + 1);
                noise(x)
            },
            0.0,
            1.0,
            1e-12,
        );
        assert_eq!(evaluations() - e0, n.get());
        assert!((v - 1.0).abs() < 1e-6, "{v}");
        let cap = 12 * MAX_EVALS as u64;
        assert!(
            n.get() > cap && n.get() < cap + 12 * 1000,
            "{} evaluations against a cap of {cap}",
            n.get()
        );
    }

    /// A NaN tolerance gives NaN, also over an empty range: `max` took it for the other
    /// tolerance or the 1e-300 floor, and a finite integral came back.
    #[test]
    fn a_nan_tolerance_gives_nan() {
        let nan = f64::NAN;
        for (a, b) in [(0.0, 1.0), (1.0, 1.0)] {
            for (rel, abs) in [(nan, 0.0), (1e-12, nan), (nan, 1e-14)] {
                let sq = |x: f64| x * x;
                let v = [
                    adaptive_abs(sq, a, b, rel, abs),
                    adaptive_2d_abs(|x, y| x * y, a, b, |_| 0.0, |_| 1.0, rel, abs),
                ];
                assert!(
                    v.iter().all(|v| v.is_nan()),
                    "[{a}, {b}], {rel}, {abs}: {v:?}"
                );
            }
            assert!(adaptive(|x| x, a, b, nan).is_nan());
            assert!(adaptive_2d(|x, y| x * y, a, b, |_| 0.0, |_| 1.0, nan).is_nan());
        }
    }

    #[test]
    fn a_non_finite_integrand_returns_at_once() {
        let sliver: fn(f64) -> f64 = |x| if x > 0.999 { f64::NAN } else { x };
        let nan: fn(f64) -> f64 = |_| f64::NAN;
        let inf: fn(f64) -> f64 = |_| f64::INFINITY;
        for (name, bad) in [
            ("NaN on a sliver", sliver),
            ("NaN everywhere", nan),
            ("+∞ everywhere", inf),
        ] {
            let n = std::cell::Cell::new(0u64);
            let v = adaptive(
                |x| {
                    n.set(n.get() + 1);
                    bad(x)
                },
                0.0,
                1.0,
                1e-12,
            );
            assert!(
                !v.is_finite() && n.get() < 2_000,
                "{name}: {v} after {}",
                n.get()
            );
            n.set(0);
            let v = adaptive_2d(
                |_, y| {
                    n.set(n.get() + 1);
                    bad(y)
                },
                0.0,
                1.0,
                |_| 0.0,
                |_| 1.0,
                1e-9,
            );
            assert!(
                !v.is_finite() && n.get() < 2_000_000,
                "{name} (2-D): {v} after {}",
                n.get()
            );
        }
    }
}
