//! Configuration (view) factors between diffuse surfaces: the fraction of the power
//! leaving surface 1 (Lambertian) that arrives at surface 2,
//! F₁₂ = (1/A₁) ∫_{A₁}∫_{A₂} cos θ₁ cos θ₂ / (π s²) dA₂ dA₁.
//! A differential element's factor is its irradiance from a unit-radiance emitter / π.

use crate::irradiance::cap_projected_solid_angle;
use std::f64::consts::PI;

/// Differential element to a parallel coaxial disk of radius r at distance h.
///
/// **Formula.** F = r² / (r² + h²).
///
/// **Derivation.** F = (1/π)∫₀^r h²/(h²+ρ²)² 2πρ dρ = r²/(r²+h²).
///
/// **Source.** Howell, *A Catalog of Radiation Heat Transfer Configuration Factors*,
/// section B (plane element to parallel coaxial disk); Siegel & Howell App. C.
pub fn element_to_coaxial_disk(radius: f64, height: f64) -> f64 {
    // 1/(1 + (h/r)²): no r² to overflow (R = h = 10²⁰⁰ gave NaN); (h/r)² = ∞ gives 0.
    let q = height / radius;
    1.0 / (1.0 + q * q)
}

/// Disk of radius r₁ to a parallel coaxial disk of radius r₂ at distance h.
///
/// **Formula.** With R₁ = r₁/h, R₂ = r₂/h, X = 1 + (1 + R₂²)/R₁²:
/// F₁₂ = ½ [X − √(X² − 4 (R₂/R₁)²)], evaluated as 2(R₂/R₁)² / (X + √(X² − 4(R₂/R₁)²))
/// (no cancellation for small or distant disks). Multiplied through by r₁² and with
/// every length divided by m = max(r₁, r₂, h) (a = r₁/m, b = r₂/m, c = h/m ≤ 1):
/// F₁₂ = 2b²/(S + √(S² − 4a²b²)), S = a² + b² + c², and
/// S² − 4a²b² = ((a − b)² + c²)((a + b)² + c²), so the root is
/// hypot(a − b, c)·hypot(a + b, c): X² is never formed (it overflowed at r₁/h = 10⁻⁸⁰,
/// giving 0 for 0.5) and nothing cancels (h = 10⁻¹⁶⁰ gave NaN for ≈ 1).
///
/// **Derivation.** Average over disk 1 of the offset element-to-disk factor
/// ([`crate::irradiance::disk_parallel_offset`]):
/// F₁₂ = (2/r₁²)∫₀^{r₁} F(a) a da, elementary after the substitution u = a².
///
/// **Source.** Howell's catalog, case C-41 (parallel coaxial disks of unequal radii);
/// Siegel & Howell App. C.
pub fn disk_to_coaxial_disk(r1: f64, r2: f64, height: f64) -> f64 {
    let m = r1.max(r2).max(height);
    let (a, b, c) = (r1 / m, r2 / m, height / m);
    let s = a * a + b * b + c * c;
    2.0 * b * b / (s + (a - b).hypot(c) * (a + b).hypot(c))
}

/// ln(1 + x)/x, 1 at x = 0 (x > −1): the logarithms below multiplied out of their
/// arguments, so that no argument's underflow loses a leading term.
fn ln_1p_over(x: f64) -> f64 {
    if x == 0.0 { 1.0 } else { x.ln_1p() / x }
}

/// x ln y, 0 at x = 0 (its limit where y → 0 with x: p ln p and p ln s below).
fn times_ln(x: f64, y: f64) -> f64 {
    if x == 0.0 { 0.0 } else { x * y.ln() }
}

/// atan(x)/x, 1 at x = 0.
fn atan_over(x: f64) -> f64 {
    if x == 0.0 { 1.0 } else { x.atan() / x }
}

/// Identical, parallel, directly opposed rectangles a × b at separation c.
///
/// **Formula.** With X = a/c, Y = b/c:
/// F₁₂ = 2/(π X Y) { ½ ln[(1+X²)(1+Y²)/(1+X²+Y²)] + X√(1+Y²) atan(X/√(1+Y²))
///        + Y√(1+X²) atan(Y/√(1+X²)) − X atan X − Y atan Y }.
///
/// **Derivation.** Integrate the differential factor to a rectangle (itself from the
/// contour form) over the emitting rectangle; the four-fold integral is elementary.
///
/// **Source.** Howell's catalog, case C-11; Siegel & Howell App. C.
///
/// **Evaluation (an exact rearrangement, no cancellation).** Evaluated as written, the
/// braces hold O(1) terms that cancel to F·πXY/2 ~ X²Y² (distant plates) or ~X (a
/// strip, X ≪ 1 ≤ Y): about 2 log₁₀(c/min(a, b)) digits were lost (a = 10⁻⁹,
/// b = c = 1 gave 0 for 2.5e-10). Grouped instead as
/// ```text
/// braces = ½ ln(1 + X²Y²/(1+X²+Y²)) + P(X, Y) + P(Y, X),
/// P(x, y) = x [σ atan(x/σ) − atan x],  σ = √(1+y²),
/// ```
/// three terms that are each ≥ 0 (σ atan(x/σ) grows with σ, its σ-derivative being
/// atan t − t/(1+t²) > 0 at t = x/σ), so none cancels another. Inside P, with
/// δ = σ − 1 = y²/(σ+1) and atan(x/σ) − atan x = −atan(xδ/(σ + x²)) (both arguments
/// ≥ 0), σ atan(x/σ) − atan x = δ atan(x/σ) − atan(xδ/(σ + x²)): the two terms agree to
/// a relative O(x²) only for small x, where each is ≈ x²δ ≈ x²y²/2 and the logarithm
/// ≈ X²Y²/2 already dominates the braces (and for small x and large y P is O(x²) while
/// the braces are ≥ P(y, x) ~ x²y), so the error stays a few ulps of F. Divided through
/// by XY (no X²Y² to underflow, no X² to overflow):
/// ```text
/// πF/2 = ½ r ln(1 + z)/z + Q(X, Y) + Q(Y, X),   r = XY/(1+X²+Y²), z = rXY,
/// Q(x, y) = P(x, y)/(xy) = e [atan(x/σ) − m atan(g)/g],
///   e = y/(σ+1), m = x/(σ + x²), g = xδ/(σ + x²) = y e m.
/// ```
/// The limits where a ratio leaves f64: X = a/c = ∞ (so Y = ∞ too) is F = 1 to
/// O(1/X) = O(10⁻³⁰⁸); Y = ∞ with X finite is the expression's Y → ∞ limit (the
/// infinitely long plates' F = √(1 + 1/X²) − 1/X = X/(√(1+X²) + 1)), to O(1/Y); X = 0
/// means F < X < 2.3·10⁻³⁰⁸ (the three terms above are below X/4, X/2 and πX/4),
/// returned as 0. Against mpmath at 60+ digits of the formula as written (working
/// precision raised by 2 log₁₀ of every ratio, for its cancellation), over a grid of
/// a, b, c ∈ 10⁻³⁰⁰..10³⁰⁰ in every combination, 4000 log-uniform random points and all
/// combinations of subnormal, ordinary and near-f64::MAX lengths, the worst error was
/// 4.8·10⁻¹⁵ relative (1.7·10⁻¹⁵ of 2.2·10⁻³⁰⁸ absolute where F is subnormal).
///
/// A NaN length gives NaN (the final `min(1.0)` made it 1).
pub fn parallel_rectangles(a: f64, b: f64, c: f64) -> f64 {
    if a.is_nan() || b.is_nan() || c.is_nan() {
        return f64::NAN;
    }
    let (x, y) = (a / c, b / c);
    let (x, y) = if x <= y { (x, y) } else { (y, x) };
    if x.is_infinite() {
        return 1.0;
    }
    if y.is_infinite() {
        return x / (1f64.hypot(x) + 1.0);
    }
    if x == 0.0 {
        return 0.0;
    }
    // Q(u, v) = P(u, v)/(uv) above.
    let q = |u: f64, v: f64| {
        let sigma = 1f64.hypot(v);
        let e = v / (sigma + 1.0);
        let m = if u <= 1.0 {
            u / (sigma + u * u)
        } else {
            1.0 / (sigma / u + u)
        };
        e * ((u / sigma).atan() - m * atan_over(v * e * m))
    };
    // r = XY/(1 + X² + Y²). Y² overflows only for Y > 1.3·10¹⁵⁴, where r becomes 0 for
    // at most X/Y: the logarithm's share r ln(1 + z)/z ≤ X/Y of F is then below 10⁻¹⁵⁴ of
    // Q(Y, X) ≥ (π/4) min(X, 1)/2, far below an ulp (a scaled form here made no
    // difference over the 15 000 mpmath-checked points).
    let r = x * y / (1.0 + x * x + y * y);
    let z = r * x * y;
    // z = r X Y overflows only for X > 1.3·10¹⁵⁴ (r ≈ X/Y with X ≤ Y, so z ≈ X²), where the
    // logarithm's share ln(z)/(XY) < 10⁻³⁰⁵ of the Q terms is below an ulp of F ≈ 1.
    let log = if z.is_finite() {
        r * ln_1p_over(z)
    } else {
        0.0
    };
    // F < 1, but for c ≪ a, b the sum rounds to 1 + 2⁻⁵² at times.
    (2.0 / PI * (0.5 * log + q(x, y) + q(y, x))).min(1.0)
}

/// Perpendicular rectangles sharing an edge of length l: from A₁ = l × w to A₂ = l × h.
///
/// **Formula.** With H = h/l, W = w/l:
/// ```text
/// F₁₂ = 1/(πW) { W atan(1/W) + H atan(1/H) − √(H²+W²) atan(1/√(H²+W²))
///   + ¼ ln( (1+W²)(1+H²)/(1+W²+H²) · [W²(1+W²+H²)/((1+W²)(W²+H²))]^{W²}
///                                 · [H²(1+H²+W²)/((1+H²)(H²+W²))]^{H²} ) }.
/// ```
///
/// **Derivation.** Contour-integral (Stokes) reduction of the double area integral; the
/// resulting line integrals along the edges are elementary.
///
/// **Source.** Howell's catalog, case C-14; Siegel & Howell App. C.
///
/// **Evaluation (an exact rearrangement, no cancellation).** Evaluated as written, the
/// braces N = πW F₁₂, which are O(W) for a narrow emitter (F₁₂ → ½ as W → 0), are formed
/// from O(1) terms, losing log₁₀(1/W) digits, and W² or H² under/overflowed (ln 0 = −∞
/// times 0 gave NaN at a side ratio of 10⁻²⁰⁰). Collecting the logarithms, with
/// a = W², b = H²:
/// ```text
/// N = Λ(a) + Λ(b) − Λ(a+b),
/// Λ(t) = √t atan(1/√t) + ¼[(1−t) ln(1+t) + t ln t] = √t atan(1/√t) + ¼ ln(1+t) − ¼ t ln(1+1/t),
/// ```
/// Λ(0) = 0 and Λ''(t) = −atan(1/√t)/(4t^{3/2}) < 0 (sympy), so
/// N = ¼∫₀^a∫₀^b atan(1/√(u+v)) (u+v)^{−3/2} du dv > 0, symmetric in W and H
/// (reciprocity). With p = min(W, H), q = max(W, H), ρ = p/q, s = √(p²+q²) = q√(1+ρ²):
/// N = Λ(p²) − Δ, Δ = Λ(s²) − Λ(q²) ≤ Λ(p²) (concavity), and Δ splits, with
/// d = s − q = p²/(s+q) and atan(1/s) − atan(1/q) = −atan(d/(1+qs)), into
/// ```text
/// Δ = [d atan(1/s) − q atan(d/(1+qs))] + ¼ ln(1 + p²/(1+q²))
///     − ¼ [p² ln(1 + 1/s²) + q² ln(1 − p²/((1+q²)s²))],
/// ```
/// where Δ and each of its five terms stay below N/√2 (mpmath over p, q ∈ 10⁻¹⁵..10¹⁵;
/// the bound is approached as p = q → 0, where N → (π/2)(2 − √2)p and Δ → (π/2)(√2 − 1)p),
/// so Λ(p²) ≤ (1 + 1/√2) N: nothing cancels by more than that factor. Everything
/// is divided by p before it is formed (N/p, with d/p = ρ/(1 + √(1+ρ²)) and each square
/// scaled so that none overflows and an underflowing one only drops a term below an ulp
/// of the result), and F₁₂ = (N/p)(p/W)/π.
///
/// For p > 10⁸ (a regime that takes in every p or q overflowing f64: l = 3.3·10⁻³⁰⁰,
/// w = 3.7·10⁹, h = 3.3·10¹⁰ is F₁₂ = 1.01·10⁻³⁰⁷) the asymptotic form is used: Λ(t) = ¾ + ¼ ln t + R(t) (sympy:
/// R = 1/(24t) − 1/(120t²) + …) with R'' = [1/√t − atan(1/√t)]/(4t^{3/2}) ∈ [0, 1/(12t³)]
/// and R(∞) = R'(∞) = 0, so 0 ≤ R(t) ≤ 1/(24t), and
/// N = ¾ + ½ ln p − ¼ ln(1 + ρ²) + E, |E| ≤ 1/(12p²) ≤ 10⁻¹⁷ (relative ≤ 10⁻¹⁸, N ≥ 9.7).
/// ln p is taken as ln(min(w, h)) − ln l when p overflows (then ln p ≥ 709 and each
/// logarithm is at most 745 in size, so that difference loses about a factor 2).
///
/// Against mpmath at 60+ digits of the formula as written (working precision raised by
/// 2 log₁₀ of every ratio, for its cancellation), over a grid of l, w, h ∈
/// 10⁻³⁰⁰..10³⁰⁰ in every combination, 4000 log-uniform random points and all
/// combinations of subnormal, ordinary and near-f64::MAX lengths, the worst error was
/// 5.2·10⁻¹⁵ relative (1.9·10⁻¹⁵ of 2.2·10⁻³⁰⁸ absolute where F₁₂ is subnormal).
///
/// A NaN length gives NaN (`min` and `max` took a NaN w or h for the other: w = h).
pub fn perpendicular_rectangles(l: f64, w: f64, h: f64) -> f64 {
    if l.is_nan() || w.is_nan() || h.is_nan() {
        return f64::NAN;
    }
    let (p_len, q_len) = (w.min(h), w.max(h));
    let rho = p_len / q_len;
    let (p, q) = (p_len / l, q_len / l);
    if p > 1e8 {
        let ln_p = if p.is_finite() {
            p.ln()
        } else {
            p_len.ln() - l.ln()
        };
        let n = 0.75 + 0.5 * ln_p - 0.25 * (rho * rho).ln_1p();
        // F₁₂ = N/(πW): as (N/p)(p/W)/π while p is finite (N/p ≥ 5·10⁻³⁰⁸ is normal), else
        // as N (l/w)/π with l/w scaled by 2⁶⁰⁰ (exact; l < 1 here), so that a subnormal
        // l/w does not drop bits of a normal F₁₂ (up to 6·10⁻³⁰⁷ at p = ∞).
        return if p.is_finite() {
            let n_p = n / p;
            if w <= h { n_p / PI } else { n_p * rho / PI }
        } else {
            let scale = 2f64.powi(600);
            n * (l * scale / w) / PI / scale
        };
    }
    // Λ(p²)/p, the p → 0 limit π/2 reached continuously (p ln p = 0 at p = 0).
    let lambda = if p < 1.0 {
        (1.0 / p).atan() + 0.25 * p * ln_1p_over(p * p) + 0.5 * times_ln(p, p)
            - 0.25 * p * (p * p).ln_1p()
    } else {
        let ip = 1.0 / p;
        ip.atan() + 0.25 * ip * (2.0 * p.ln() + (ip * ip).ln_1p()) - 0.25 * ip * ln_1p_over(ip * ip)
    };
    // N/p; Δ/p = t1 + t2 − t3 − t4 in the order of the doc's terms.
    let n = if q.is_infinite() {
        lambda // Δ ≤ p²/(4q²) → 0 (Λ'(t) ≤ 1/(4t) for large t)
    } else {
        let root = 1f64.hypot(rho);
        let s = q * root;
        let d_p = rho / (1.0 + root);
        let inv_q = 1.0 / q; // ∞ at q = 0: the terms below reach their limits
        let q_iq = q + inv_q; // (1 + q²)/q
        let t1 = d_p * ((1.0 / s).atan() - atan_over(p * d_p / (1.0 + q * s)) / (s + inv_q));
        let x2 = p * rho / q_iq; // p²/(1 + q²)
        let t2 = 0.25 * ln_1p_over(x2) * rho / q_iq;
        let t3 = if s < 1.0 {
            0.25 * (p * (s * s).ln_1p() - 2.0 * times_ln(p, s))
        } else {
            let is = 1.0 / s;
            0.25 * (rho / root) * is * ln_1p_over(is * is)
        };
        let inv_1q2 = if q <= 1.0 {
            1.0 / (1.0 + q * q)
        } else {
            inv_q * inv_q / (1.0 + inv_q * inv_q)
        };
        let y = rho * rho / (1.0 + rho * rho) * inv_1q2; // p²/((1+q²)s²)
        let t4 = -0.25 * ln_1p_over(-y) * (rho / q_iq) / (1.0 + rho * rho);
        lambda - t1 - t2 + t3 + t4
    };
    if w <= h { n / PI } else { n * rho / PI }
}

/// Differential element to a sphere of radius R whose centre is at distance d, the
/// element's normal pointing at the centre.
///
/// **Formula.** F = (R/d)².
///
/// **Derivation.** The sphere is a cap of sin σ = R/d around the normal; the projected
/// solid angle of a cap centred on the normal is π sin²σ.
///
/// **Source.** Howell's catalog, section B (element to sphere); Siegel & Howell App. C.
pub fn element_to_sphere(distance: f64, radius: f64) -> f64 {
    (radius / distance) * (radius / distance)
}

/// Differential element to a sphere, the element's normal at angle `tilt` (radians) from
/// the direction to the centre, including the partly-below-the-horizon range.
///
/// **Formula.** F = Ω⊥/π with Ω⊥ the horizon-clipped projected solid angle of a cap,
/// [`crate::irradiance::sphere`] (Snyder 1996): F = (R/d)² cos tilt while
/// cos tilt ≥ R/d, zero once cos tilt ≤ −R/d, and the clipped expression between.
///
/// **Source.** Howell's catalog, section B (element to sphere, tilted; element plane
/// intersecting the sphere); Snyder 1996. A NaN input gives NaN
/// ([`crate::irradiance::cap_projected_solid_angle`]).
pub fn element_to_sphere_tilted(distance: f64, radius: f64, tilt: f64) -> f64 {
    let s = radius / distance;
    cap_projected_solid_angle(tilt.cos(), s * s) / PI
}

/// From any part of a sphere's inner wall to a spherical cap of polar half-angle θ on
/// the same sphere (both facing inwards).
///
/// **Formula.** F = A_cap / (4π R²) = (1 − cos θ)/2 = sin²(θ/2), whatever the emitting
/// part.
///
/// **Derivation.** For two points of a sphere's inner wall at chord s, both polar angles
/// satisfy cos θ₁ = cos θ₂ = s/(2R), so the kernel cos θ₁ cos θ₂/(π s²) = 1/(4π R²) is a
/// constant: every element sees each region in proportion to its area.
///
/// **Source.** Siegel & Howell ch. 6 (the sphere's "area-fraction" view factors);
/// Goebel, Appl. Opt. 6(1), 1967.
pub fn sphere_wall_to_cap(theta: f64) -> f64 {
    let s = (0.5 * theta).sin();
    s * s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::{Vec3, assert_nan_in_each};
    use crate::irradiance::{disk_parallel_offset, polygon_projected_solid_angle, sphere};
    use crate::quadrature::{adaptive, adaptive_2d};

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs().max(1e-300)
    }

    /// Extreme aspect ratios: r₁/h = 10⁻¹⁰⁰ is the element-to-disk limit r₂²/(r₂² + h²);
    /// h/r = 10⁻¹⁰⁰ the touching limit min(1, (r₂/r₁)²); r₁/h = 10¹⁰⁰ with r₂ = h the
    /// reciprocal (r₂/r₁)² F₂₁, F₂₁ → 1. X² overflowed at the first (0 for 0.5) and
    /// cancelled to NaN at h = 10⁻¹⁶⁰.
    #[test]
    fn coaxial_disks_at_extreme_ratios() {
        for (r1, r2, h, want) in [
            (1e-100, 1.0, 1.0, 0.5),
            (1e-80, 1.0, 1.0, 0.5),
            (1e-100, 2.0, 1.0, 0.8),
            (1.0, 1.0, 1e-100, 1.0),
            (1.0, 1.0, 1e-160, 1.0),
            (1.0, 0.5, 1e-100, 0.25),
            (0.5, 1.0, 1e-100, 1.0),
            (1e100, 1.0, 1.0, 1e-200),
            (1e200, 1e200, 1e200, 0.5 * (3.0 - 5f64.sqrt())),
        ] {
            let f = disk_to_coaxial_disk(r1, r2, h);
            assert!(rel(f, want) < 1e-14, "r1 {r1} r2 {r2} h {h}: {f} vs {want}");
        }
        // R = h = 10²⁰⁰ and beyond: 1/2, no overflow.
        assert_eq!(element_to_coaxial_disk(1e200, 1e200), 0.5);
        assert_eq!(element_to_coaxial_disk(1e-200, 1e200), 0.0);
        assert!(rel(element_to_coaxial_disk(3.0, 4.0), 9.0 / 25.0) < 1e-15);
    }

    /// Checks `f` against mpmath references; a reference below the normal range
    /// (2.2·10⁻³⁰⁸) is met to that absolute error.
    fn check_references(name: &str, f: fn(f64, f64, f64) -> f64, cases: &[(f64, f64, f64, f64)]) {
        for &(x, y, z, want) in cases {
            let got = f(x, y, z);
            let err = if want.abs() < f64::MIN_POSITIVE {
                (got - want).abs() / f64::MIN_POSITIVE
            } else {
                rel(got, want)
            };
            assert!(
                err < 1e-13,
                "{name}({x:e}, {y:e}, {z:e}) = {got:e}, mpmath {want:e}"
            );
        }
    }

    /// C-11 at extreme ratios: thin strips, distant and touching plates, every length at
    /// 10⁻³⁰⁰..10³⁰⁰ and subnormal, where Howell's expression as written lost
    /// 2 log₁₀(c/min(a, b)) digits (a = 10⁻⁹, b = c = 1 gave 0) or overflowed. The
    /// references are Howell's expression as written, evaluated by mpmath with
    /// mp.dps = 80 + 2 max|log₁₀ X|, |log₁₀ Y| + 2|log₁₀ X| + 2|log₁₀ Y| (at least 50
    /// digits survive its cancellation), X = a/c, Y = b/c exact from the f64 inputs:
    /// `python3 -c 'from mpmath import *; mp.dps=<as above>; a,b,c=mpf(A),mpf(B),mpf(C);
    /// X,Y=a/c,b/c; sx,sy=sqrt(1+X*X),sqrt(1+Y*Y); print(nstr(2/(pi*X*Y)*(log((1+X*X)*
    /// (1+Y*Y)/(1+X*X+Y*Y))/2+X*sy*atan(X/sy)+Y*sx*atan(Y/sx)-X*atan(X)-Y*atan(Y)),20))'`.
    /// Measured worst error over a 10⁻³⁰⁰..10³⁰⁰ grid: 4.8·10⁻¹⁵ relative.
    #[test]
    // References printed to 20 significant digits by mpmath; kept verbatim.
    #[allow(clippy::excessive_precision)]
    fn parallel_rectangles_at_extreme_ratios() {
        check_references(
            "parallel_rectangles",
            parallel_rectangles,
            &[
                (1e-9, 1.0, 1.0, 2.5000000000000001549e-10),
                (1e-4, 1.0, 1.0, 2.4999999924237089692e-5),
                (1e-3, 1e-3, 10.0, 3.1830988406172479494e-9),
                (1.0, 1.0, 1e4, 3.1830988406172478168e-9),
                (0.5, 2.0, 3000.0, 3.5367759564385557165e-8),
                (1.0, 1.0, 1e150, 3.1830988618379068374e-301),
                (1e-150, 1e-150, 1.0, 3.1830988618379067555e-301),
                (1e-200, 1.0, 1.0, 2.4999999999999999553e-201),
                (1e-200, 1e200, 1.0, 4.9999999999999999105e-201),
                (1.0, 2.0, 1e-300, 1.0),
                (1e300, 1e-300, 1.0, 5.0000000000000001253e-301),
                (3.0, 7.0, 1e-200, 1.0),
                (1e-300, 1e-300, 1e-300, 0.19982489569838738304),
                (1e-300, 1e300, 1e300, 2.4999999999999999314e-601),
                (1e300, 1e300, 1e-300, 1.0),
                (1.7e308, 1.0, 1e-300, 1.0),
                (2.5e-7, 4e5, 0.3, 4.1666646772291546046e-7),
                (5e-324, 5e-324, 5e-324, 0.19982489569838738304),
                // One ratio overflowing and the other not: the long plates' limit
                // X/(√(1 + X²) + 1) of the finite one, X = 10¹⁰ and 1 (√2 − 1).
                (1e300, 1.0, 1e-10, 0.9999999999),
                (1e-300, 1e10, 1e-300, 0.4142135623730950488),
                // A tiny X beside a large Y (Q's m and r each in their other form lost
                // 10⁻³ and 5% here; found by mutation testing).
                (3.3e-300, 3.7e9, 3.3e6, 4.9971610206868119795e-307),
                (3.3e6, 7.9e-300, 3.7e-301, 0.9542607355205908724),
            ],
        );
    }

    /// C-14 at extreme ratios: a side of 10⁻²⁰⁰ or 10²⁰⁰ relative to the others
    /// (W² or H² under/overflowed, 0·ln 0 = NaN), narrow emitters (W → 0: F₁₂ → ½,
    /// formerly O(1) terms cancelling to O(W)), both plates narrow (l → ∞: the
    /// infinitely long plates' ½(1 + H/W − √(1 + H²/W²)) = ½(4 − √10) for H = 3W, also
    /// with W and H underflowing to 0), both wide (ratios overflowing), and both sides of
    /// the asymptotic regime's switch at min(w, h)/l = 10⁸. The references are Howell's
    /// expression as written, evaluated by mpmath with
    /// mp.dps = 2(80 + 2 max|log₁₀ W|, |log₁₀ H|, |log₁₀ (w/h)|):
    /// `python3 -c 'from mpmath import *; mp.dps=<as above>; l,w,h=mpf(L),mpf(W),mpf(H);
    /// W,H=w/l,h/l; a,b=W*W,H*H; s=sqrt(a+b); g=log((1+a)*(1+b)/(1+a+b))+a*log(a*(1+a+b)/
    /// ((1+a)*(a+b)))+b*log(b*(1+a+b)/((1+b)*(a+b))); print(nstr((W*atan(1/W)+H*atan(1/H)
    /// -s*atan(1/s)+g/4)/(pi*W),20))'`.
    /// Measured worst error over a 10⁻³⁰⁰..10³⁰⁰ grid: 5.2·10⁻¹⁵ relative.
    #[test]
    // References printed to 20 significant digits by mpmath; kept verbatim.
    #[allow(clippy::excessive_precision)]
    fn perpendicular_rectangles_at_extreme_ratios() {
        check_references(
            "perpendicular_rectangles",
            perpendicular_rectangles,
            &[
                (1.0, 1e-200, 1.0, 0.5),
                (1.0, 1.0, 1e-200, 4.9999999999999999105e-201),
                (1e-200, 1.0, 1.0, 7.3477133402542452880e-199),
                (1e200, 1.0, 1.0, 0.29289321881345247560),
                (1.0, 1e-300, 1e300, 0.5),
                (1.0, 1e300, 1e-300, 4.9999999999999998628e-601),
                (3.3e-300, 3.7e9, 3.3e10, 1.0122482188820601821e-307),
                (1e-100, 1.0, 3.0, 3.6877128035172403735e-99),
                (1e-5, 1.0, 1.0, 2.0159125118002390462e-5),
                (1e-8, 1.0, 2.0, 3.1527176105501857910e-8),
                (9.999e-9, 1.0, 2.0, 3.1524182534876388751e-8),
                (1e150, 1e-150, 3e-150, 0.41886116991581033748),
                (1e300, 1e-300, 3e-300, 0.41886116991581033825),
                (1.0, 1e-10, 1e-2, 0.49999999719886827854),
                (1.0, 1e-2, 1e-10, 4.9999999719886828635e-9),
                (2.0, 1.0, 0.01, 0.0049346840641041705796),
                (1.0, 1.0, 1.0, 0.20004377607540315424),
            ],
        );
    }

    /// Reciprocity A₁F₁₂ = A₂F₂₁ for C-14 (w F(l, w, h) = h F(l, h, w)), and finite
    /// values in [0, 1] for both rectangle cases over every combination of extreme and
    /// ordinary lengths, subnormal and f64::MAX included.
    #[test]
    fn rectangles_reciprocity_and_range_at_extremes() {
        let lengths = [
            5e-324,
            1e-310,
            f64::MIN_POSITIVE,
            1e-200,
            1e-9,
            0.3,
            1.0,
            7.0,
            1e12,
            1e200,
            f64::MAX,
        ];
        for &l in &lengths {
            for &w in &lengths {
                for &h in &lengths {
                    let (f12, f21) = (
                        perpendicular_rectangles(l, w, h),
                        perpendicular_rectangles(l, h, w),
                    );
                    let par = parallel_rectangles(l, w, h);
                    for f in [f12, f21, par] {
                        assert!((0.0..=1.0).contains(&f), "{l:e} {w:e} {h:e}: {f}");
                    }
                    // Reciprocity where both factors are normal numbers.
                    let (lhs, rhs) = (w / h * f12, f21);
                    if f12 >= 1e-300 && f21 >= 1e-300 && lhs.is_finite() {
                        assert!(rel(lhs, rhs) < 1e-14, "{l:e} {w:e} {h:e}: {lhs} vs {rhs}");
                    }
                }
            }
        }
        // Reciprocity at ordinary and moderately extreme shapes, to rounding.
        for (l, w, h) in [
            (1.0, 0.3, 2.0),
            (1.0, 1e-7, 1e3),
            (1e-6, 1.0, 5.0),
            (1e6, 1.0, 1e-3),
        ] {
            let (f12, f21) = (
                perpendicular_rectangles(l, w, h),
                perpendicular_rectangles(l, h, w),
            );
            assert!(rel(w * f12, h * f21) < 1e-14, "{l} {w} {h}");
        }
    }

    /// A NaN length or tilt gives NaN, also at the limits (a zero or infinite side, the
    /// asymptotic form, a sphere below the horizon): the parallel plates' final `min(1.0)`
    /// made NaN 1, the perpendicular ones' `min`/`max` of w and h took a NaN for the
    /// other, and the tilted sphere's cap made NaN 0.
    #[test]
    fn rectangles_and_tilted_sphere_propagate_nan() {
        let inf = f64::INFINITY;
        let bases: [&[f64]; 5] = [
            &[1.0, 2.0, 1.0],
            &[0.0, 1.0, 1.0],
            &[1.0, inf, 1.0],
            &[1e-9, 1.0, 1.0],
            &[1.0, 1.0, 1e-20],
        ];
        assert_nan_in_each("parallel rectangles", &bases, |x| {
            parallel_rectangles(x[0], x[1], x[2])
        });
        let bases: [&[f64]; 4] = [
            &[1.0, 2.0, 3.0],
            &[1.0, 3.0, 2.0],
            &[1.0, 1e9, 1e10],
            &[1.0, 0.0, 1.0],
        ];
        assert_nan_in_each("perpendicular rectangles", &bases, |x| {
            perpendicular_rectangles(x[0], x[1], x[2])
        });
        let bases: [&[f64]; 3] = [&[3.0, 1.0, 0.3], &[3.0, 1.0, 3.0], &[3.0, 1.0, 1.5]];
        assert_nan_in_each("tilted element to sphere", &bases, |x| {
            element_to_sphere_tilted(x[0], x[1], x[2])
        });
    }

    #[test]
    fn element_to_disk_by_area() {
        for (r, h) in [(1.0, 2.0), (1e-3, 10.0), (10.0, 1e-2)] {
            let q = adaptive(
                |rho| h * h / (h * h + rho * rho).powi(2) * 2.0 * rho,
                0.0,
                r,
                1e-14,
            );
            assert!(rel(element_to_coaxial_disk(r, h), q) < 1e-11);
        }
    }

    #[test]
    fn disk_to_disk_by_averaging_offset_factor() {
        for (r1, r2, h) in [
            (1.0, 1.0, 1.0),
            (0.5, 2.0, 1.0),
            (2.0, 0.1, 3.0),
            (1e-2, 1e-2, 10.0),
        ] {
            let q = 2.0 / (r1 * r1)
                * adaptive(
                    |a| disk_parallel_offset(r2, h, a, 1.0) / PI * a,
                    0.0,
                    r1,
                    1e-13,
                );
            assert!(
                rel(disk_to_coaxial_disk(r1, r2, h), q) < 1e-9,
                "{r1} {r2} {h}"
            );
        }
        // Reciprocity A1 F12 = A2 F21.
        let (r1, r2, h) = (0.5, 2.0, 1.3);
        assert!(
            rel(
                r1 * r1 * disk_to_coaxial_disk(r1, r2, h),
                r2 * r2 * disk_to_coaxial_disk(r2, r1, h)
            ) < 1e-13
        );
    }

    /// Area average over A₁ of Lambert's point-to-polygon factor.
    fn average_over(
        origin: Vec3,
        u: Vec3,
        v: Vec3,
        normal: Vec3,
        target: &[Vec3],
        tol: f64,
    ) -> f64 {
        adaptive_2d(
            |s, t| polygon_projected_solid_angle(origin + u * s + v * t, normal, target) / PI,
            0.0,
            1.0,
            |_| 0.0,
            |_| 1.0,
            tol,
        )
    }

    /// C-11 by quadrature: an a × b rectangle at z = 0 facing +z, the same rectangle
    /// at height c above it.
    fn parallel_by_averaging(a: f64, b: f64, c: f64, tol: f64) -> f64 {
        let target = [
            Vec3::new(0.0, 0.0, c),
            Vec3::new(a, 0.0, c),
            Vec3::new(a, b, c),
            Vec3::new(0.0, b, c),
        ];
        average_over(
            Vec3::default(),
            Vec3::new(a, 0.0, 0.0),
            Vec3::new(0.0, b, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
            &target,
            tol,
        )
    }

    #[test]
    fn parallel_rectangles_by_averaging_lambert() {
        for (a, b, c) in [(1.0, 1.0, 1.0), (2.0, 0.5, 0.3), (1.0, 3.0, 5.0)] {
            let q = parallel_by_averaging(a, b, c, 1e-11);
            assert!(rel(parallel_rectangles(a, b, c), q) < 1e-9, "{a} {b} {c}");
        }
    }

    #[test]
    fn perpendicular_rectangles_by_averaging_lambert() {
        // Common edge along x (length l); A1 in the z = 0 plane spanning y ∈ [0, w];
        // A2 in the y = 0 plane spanning z ∈ [0, h].
        for (l, w, h) in [(1.0, 1.0, 1.0), (2.0, 0.5, 1.5), (0.5, 2.0, 0.2)] {
            let target = [
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(l, 0.0, 0.0),
                Vec3::new(l, 0.0, h),
                Vec3::new(0.0, 0.0, h),
            ];
            let q = average_over(
                Vec3::default(),
                Vec3::new(l, 0.0, 0.0),
                Vec3::new(0.0, w, 0.0),
                Vec3::new(0.0, 0.0, 1.0),
                &target,
                1e-11,
            );
            assert!(
                rel(perpendicular_rectangles(l, w, h), q) < 1e-8,
                "{l} {w} {h}: {q}"
            );
        }
    }

    /// The catalog's near-touching and very distant configurations, each against the
    /// same independent quadratures as above (the cases under
    /// `analytic/cases/view_factor` use exactly these parameters).
    #[test]
    fn catalog_extremes_by_quadrature() {
        // C-11: separations 1e-3 (width 1, length 2) and 100 (width 2, length 1).
        for (a, b, c, tol) in [(1.0, 2.0, 1e-3, 1e-7), (2.0, 1.0, 100.0, 1e-8)] {
            let q = parallel_by_averaging(a, b, c, 1e-10);
            let f = parallel_rectangles(a, b, c);
            assert!(rel(f, q) < tol, "{a} {b} {c}: {f} vs {q}");
        }
        // C-14: a receiver strip 0.01 high on a 2 × 1 emitter's edge, by reciprocity
        // F₁₂ A₁ = F₂₁ A₂ averaged over the strip (the smooth side).
        let (l, w, h) = (2.0, 1.0, 0.01);
        let emitter = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(l, 0.0, 0.0),
            Vec3::new(l, w, 0.0),
            Vec3::new(0.0, w, 0.0),
        ];
        let f21 = average_over(
            Vec3::default(),
            Vec3::new(l, 0.0, 0.0),
            Vec3::new(0.0, 0.0, h),
            Vec3::new(0.0, 1.0, 0.0),
            &emitter,
            1e-10,
        );
        let f12 = perpendicular_rectangles(l, w, h);
        assert!(
            rel(f12 * l * w, f21 * l * h) < 1e-7,
            "{f12} vs {}",
            f21 * h / w
        );
        // C-41: coaxial unit disks 1e-2 and 100 apart.
        for (h, tol) in [(1e-2, 1e-7), (100.0, 1e-9)] {
            let q = 2.0
                * adaptive(
                    |a| disk_parallel_offset(1.0, h, a, 1.0) / PI * a,
                    0.0,
                    1.0,
                    1e-13,
                );
            assert!(rel(disk_to_coaxial_disk(1.0, 1.0, h), q) < tol, "{h}: {q}");
        }
    }

    #[test]
    fn sphere_wall_to_cap_by_quadrature() {
        // From a cap of half-angle 60° about +z to the cap of half-angle 120° about −z:
        // the four-fold integral by averaging, over the emitter, the kernel integrated
        // over the receiver (each by 2-D quadrature in polar coordinates).
        let (t1, t2) = (60f64.to_radians(), 120f64.to_radians());
        let point = |axis: f64, t: f64, p: f64| {
            Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), axis * t.cos())
        };
        let from = |x: Vec3| {
            adaptive_2d(
                |t, p| {
                    let q = point(-1.0, t, p);
                    let d = q - x;
                    let s2 = d.length_squared();
                    let s = s2.sqrt();
                    // Inward normals −x and −q.
                    let c1 = (-x).dot(d) / s;
                    let c2 = q.dot(d) / s;
                    c1 * c2 / (PI * s2) * t.sin()
                },
                0.0,
                t2,
                |_| 0.0,
                |_| 2.0 * PI,
                1e-9,
            )
        };
        // The emitter is rotationally symmetric: average over its polar angle only.
        let area1 = 2.0 * PI * (1.0 - t1.cos());
        let f = adaptive(
            |t| from(point(1.0, t, 0.0)) * 2.0 * PI * t.sin(),
            0.0,
            t1,
            1e-8,
        ) / area1;
        assert!(rel(f, sphere_wall_to_cap(t2)) < 1e-6, "{f}");
    }

    #[test]
    fn element_to_sphere_matches_irradiance_and_quadrature() {
        for (d, r) in [(2.0f64, 1.0f64), (1e3, 1.0), (1.0 + 1e-6, 1.0)] {
            // Facing: independent area quadrature over the visible sphere surface,
            // zones parameterised by distance s: cos θ₁ cos θ₂/(π s²) dA.
            let (s0, s1) = (d - r, ((d - r) * (d + r)).sqrt());
            let q = adaptive(
                |x: f64| {
                    let s = x.exp();
                    // cos θ₁ = (d² + s² − R²)/(2ds), cos θ₂ = (d² − R² − s²)/(2Rs),
                    // dA = 2π R s ds / d (zone area), and ds = s dx.
                    let c1 = (d * d + s * s - r * r) / (2.0 * d * s);
                    let c2 = ((d - r) * (d + r) - s * s) / (2.0 * r * s);
                    c1 * c2 / (PI * s * s) * 2.0 * PI * r * s / d * s
                },
                s0.ln(),
                s1.ln(),
                1e-14,
            );
            assert!(rel(element_to_sphere(d, r), q) < 1e-9, "{d} {r}: {q}");
            for tilt in [0.0f64, 0.7, 1.5, 1.6, 2.0] {
                let n = Vec3::new(tilt.sin(), 0.0, tilt.cos());
                let e = sphere(Vec3::default(), n, Vec3::new(0.0, 0.0, d), r, 1.0) / PI;
                assert!((element_to_sphere_tilted(d, r, tilt) - e).abs() <= 1e-14 * e.max(1e-300));
            }
        }
    }
}
