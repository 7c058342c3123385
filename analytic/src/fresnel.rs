//! Fresnel reflectance of smooth interfaces, unpolarised light.
//!
//! η is always the *relative* index n_t / n_i (transmitted over incident side); a
//! negative `cos_theta` means the light arrives from the other side (η → 1/η).

/// Unpolarised reflectance of a smooth dielectric interface, with total internal
/// reflection.
///
/// **Formula.** sin²θₜ = (1 − cos²θᵢ)/η²; if sin²θₜ ≥ 1, F = 1 (TIR); otherwise
/// r_s = (cos θᵢ − η cos θₜ)/(cos θᵢ + η cos θₜ), r_p = (η cos θᵢ − cos θₜ)/(η cos θᵢ + cos θₜ),
/// F = (r_s² + r_p²)/2.
///
/// **Derivation.** Continuity of the tangential E and H fields at the interface for the
/// s and p polarisations; unpolarised light averages the two intensities.
///
/// **Near-matched indices** (|η − 1| < 1/2) the same r_s, r_p are evaluated without
/// cancellation: with d = (η − 1)(η + 1), η² cos²θₜ = η² − sin²θᵢ = d + cos²θᵢ, and
/// cos θᵢ − η cos θₜ = (cos²θᵢ − η² cos²θₜ)/(cos θᵢ + η cos θₜ) = −d/(cos θᵢ + η cos θₜ),
/// η cos θᵢ − cos θₜ = (η² cos²θᵢ − cos²θₜ)/(η cos θᵢ + cos θₜ)
/// = d((η² + 1) cos²θᵢ − 1)/(η² (η cos θᵢ + cos θₜ)): so r_s = −d/(cos θᵢ + η cos θₜ)²,
/// r_p = d((η² + 1) cos²θᵢ − 1)/(η (η cos θᵢ + cos θₜ))². The direct form loses
/// 1 − sin²θₜ to rounding (its relative error ~1e-16/(η² − 1 + cos²θᵢ), 5e-10 at
/// η = 1 + 10⁻⁷, cos θᵢ → 0), and with it the relative accuracy of a tiny F, which an
/// adaptive quadrature of F then cannot reach (the rough dielectric's albedo took
/// minutes). From inside (η → 1/η) d = −(η − 1)(η + 1)/η², from the given η. Elsewhere
/// the direct form is kept (d overflows for η > 10¹⁵⁴). The tests check 1e-12 relative
/// against 50-digit references at η = 1 + 10⁻⁷.
///
/// **Source.** Born & Wolf, *Principles of Optics*, §1.5.2; pbrt 4th ed. §9.3.
///
/// A NaN `cos_theta` or `eta` gives NaN.
pub fn dielectric(cos_theta: f64, eta: f64) -> f64 {
    let Some(Incidence {
        d,
        cos_i,
        eta,
        sin2_t,
    }) = Incidence::refracted(cos_theta, eta)
    else {
        return 1.0;
    };
    if (eta - 1.0).abs() < 0.5 {
        let c2 = cos_i * cos_i;
        let e_cos_t = (d + c2).max(0.0).sqrt();
        let cos_t = e_cos_t / eta;
        let s = cos_i + e_cos_t;
        let rs = -d / (s * s);
        let p = eta * (eta * cos_i + cos_t);
        let rp = d * ((eta * eta + 1.0) * c2 - 1.0) / (p * p);
        return 0.5 * (rs * rs + rp * rp);
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    0.5 * (rs * rs + rp * rp)
}

/// 1 − [`dielectric`]: the unpolarised transmittance of a smooth dielectric interface
/// (0 under total internal reflection), without the cancellation of 1 − F where F → 1
/// (near the critical angle and at grazing incidence).
///
/// **Formula.** 1 − r_s² = 4 cos θᵢ η cos θₜ/(cos θᵢ + η cos θₜ)²,
/// 1 − r_p² = 4 η cos θᵢ cos θₜ/(η cos θᵢ + cos θₜ)², T = (1 − r_s² + 1 − r_p²)/2, with
/// η cos θₜ = √((η − 1)(η + 1) + cos²θᵢ).
///
/// **Derivation.** (x + y)² − (x − y)² = 4xy applied to [`dielectric`]'s r_s and r_p.
///
/// **Source.** Born & Wolf, *Principles of Optics*, §1.5.3 (the transmissivity).
///
/// A NaN `cos_theta` or `eta` gives NaN.
pub fn dielectric_transmittance(cos_theta: f64, eta: f64) -> f64 {
    let Some(Incidence { d, cos_i, eta, .. }) = Incidence::refracted(cos_theta, eta) else {
        return 0.0;
    };
    let e_cos_t = (d + cos_i * cos_i).max(0.0).sqrt();
    let cos_t = e_cos_t / eta;
    let s = cos_i + e_cos_t;
    let p = eta * cos_i + cos_t;
    2.0 * cos_i * (e_cos_t / (s * s) + eta * cos_t / (p * p))
}

/// The incidence both dielectric forms start from: d = η′² − 1 ([`index_excess`]),
/// |cos θᵢ| (at most 1), the relative index η′ on the side of `cos_theta` (η, or 1/η
/// when negative) and sin²θₜ = (1 − cos²θᵢ)/η′².
struct Incidence {
    d: f64,
    cos_i: f64,
    eta: f64,
    sin2_t: f64,
}

impl Incidence {
    /// `None` under total internal reflection, sin²θₜ = (1 − cos²θᵢ)/η′² ≥ 1.
    fn refracted(cos_theta: f64, eta: f64) -> Option<Self> {
        let d = index_excess(cos_theta, eta);
        let (cos_i, eta) = if cos_theta < 0.0 {
            (-cos_theta, 1.0 / eta)
        } else {
            (cos_theta, eta)
        };
        // Not `min(1.0)`, which made a NaN cosine 1 (normal incidence: F = 0.04 at η = 1.5).
        let cos_i = if cos_i > 1.0 { 1.0 } else { cos_i };
        let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
        // `>=`: a NaN passes on to the formulas (never masked as total reflection).
        if sin2_t >= 1.0 {
            None
        } else {
            Some(Incidence {
                d,
                cos_i,
                eta,
                sin2_t,
            })
        }
    }
}

/// η′² − 1 for the relative index η′ seen from the side of `cos_theta` (η, or 1/η when
/// negative), as (η − 1)(η + 1), or −(η − 1)(η + 1)/η² from inside: from η itself, so
/// that 1/η's rounding (relative 1e-16, but 1e-9 of 1/η − 1 at η = 1 + 10⁻⁷) is not
/// magnified.
fn index_excess(cos_theta: f64, eta: f64) -> f64 {
    let d = (eta - 1.0) * (eta + 1.0);
    if cos_theta < 0.0 { -(d / eta) / eta } else { d }
}

/// A complex number, just enough for the conductor Fresnel equations.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Complex {
    re: f64,
    im: f64,
}

impl Complex {
    const fn new(re: f64, im: f64) -> Self {
        Self { re, im }
    }
    fn add(self, o: Self) -> Self {
        Self::new(self.re + o.re, self.im + o.im)
    }
    fn sub(self, o: Self) -> Self {
        Self::new(self.re - o.re, self.im - o.im)
    }
    fn mul(self, o: Self) -> Self {
        Self::new(
            self.re * o.re - self.im * o.im,
            self.re * o.im + self.im * o.re,
        )
    }
    /// Smith's (1962) division: scaled by the divisor's larger component, so that no
    /// |o|² is formed, which overflows for |o| > 10¹⁵⁴ (an index of 10²⁰⁰ gave NaN).
    fn div(self, o: Self) -> Self {
        if o.re.abs() >= o.im.abs() {
            let r = o.im / o.re;
            let d = o.re + o.im * r;
            Self::new((self.re + self.im * r) / d, (self.im - self.re * r) / d)
        } else {
            let r = o.re / o.im;
            let d = o.re * r + o.im;
            Self::new((self.re * r + self.im) / d, (self.im * r - self.re) / d)
        }
    }
    fn norm2(self) -> f64 {
        self.re * self.re + self.im * self.im
    }
    /// Principal square root.
    fn sqrt(self) -> Self {
        let m = self.re.hypot(self.im);
        let re = (0.5 * (m + self.re)).max(0.0).sqrt();
        let im = (0.5 * (m - self.re)).max(0.0).sqrt().copysign(self.im);
        Self::new(re, im)
    }
}

/// Unpolarised reflectance of a conductor of complex relative index η + iκ, incidence
/// cosine `cos_theta` ∈ [0, 1] from the dielectric side.
///
/// **Formula.** The dielectric expressions with η replaced by η̃ = η + iκ and
/// cos θₜ = √(1 − sin²θᵢ/η̃²) (principal complex root):
/// F = (|r_s|² + |r_p|²)/2.
///
/// **Derivation.** As [`dielectric`]: the boundary conditions hold for complex
/// permittivity; the refracted wave is inhomogeneous, which the complex cos θₜ encodes.
///
/// **Source.** Born & Wolf, *Principles of Optics*, §14.2 (metal optics); pbrt 4th ed.
/// §9.3.6 (`FrComplex`).
///
/// A subnormal κ is taken as 0: F moves by O(√κ) < 1.5·10⁻¹⁵⁴ (at the critical angle of
/// η < 1, O(κ) elsewhere), far below an ulp, while subnormal arithmetic made a rough
/// conductor's albedo quadrature 7× slower (κ = 5·10⁻³²⁴: 3.4 s against 0.5 s).
pub fn conductor(cos_theta: f64, eta: f64, k: f64) -> f64 {
    let k = if k.abs() < f64::MIN_POSITIVE { 0.0 } else { k };
    let cos_i = cos_theta.clamp(0.0, 1.0);
    let sin2_i = (1.0 - cos_i) * (1.0 + cos_i);
    let eta_c = Complex::new(eta, k);
    let ci = Complex::new(cos_i, 0.0);
    if (eta - 1.0).hypot(k) < 0.5 {
        // Near a matched index, [`dielectric`]'s cancellation-free form in complex
        // arithmetic: d = (η̃ − 1)(η̃ + 1), cos²θt = (d + cos²θi)/η̃²,
        // r_s = −d/(cos θi + η̃ cos θt)², r_p = d((η̃² + 1) cos²θi − 1)/(η̃ (η̃ cos θi + cos θt))².
        // The direct form's cos θi − η̃ cos θt cancels to ~|η̃ − 1|: at η = 1, κ = 10⁻¹²
        // F ~ 10⁻²⁵ came out with ~10⁻⁴ relative noise (a rough conductor's albedo
        // quadrature then ran for minutes).
        let one = Complex::new(1.0, 0.0);
        let d = eta_c.sub(one).mul(eta_c.add(one));
        let c2 = Complex::new(cos_i * cos_i, 0.0);
        let cos_t = d.add(c2).div(eta_c).div(eta_c).sqrt();
        let s = ci.add(eta_c.mul(cos_t));
        // |r_s| only: F reads |r_s|², so its sign (−d/s²) is dropped.
        let rs = d.div(s.mul(s));
        let p = eta_c.mul(eta_c.mul(ci).add(cos_t));
        let e2 = eta_c.mul(eta_c);
        let rp = d.mul(e2.add(one).mul(c2).sub(one)).div(p.mul(p));
        return 0.5 * (rs.norm2() + rp.norm2());
    }
    // sin²θt = sin²θi/η², divided twice: η² overflows for |η| > 10¹⁵⁴.
    let sin2_t = Complex::new(sin2_i, 0.0).div(eta_c).div(eta_c);
    let cos_t = Complex::new(1.0, 0.0).sub(sin2_t).sqrt();
    let ec = eta_c.mul(cos_t);
    let rs = ci.sub(ec).div(ci.add(ec));
    let ei = eta_c.mul(ci);
    let rp = ei.sub(cos_t).div(ei.add(cos_t));
    0.5 * (rs.norm2() + rp.norm2())
}

/// Taylor coefficients in δ = η − 1 of the non-logarithmic part S(δ) of
/// [`dielectric_average`] (computed symbolically; S(0) = 0, radius of convergence 1).
// Printed to 20 significant digits by the computer algebra; kept verbatim.
#[allow(clippy::excessive_precision)]
const SERIES: [f64; 28] = [
    0.0,
    0.333_333_333_333_333_33,
    0.791_666_666_666_666_67,
    -1.066_666_666_666_666_7,
    0.168_75,
    0.936_011_904_761_904_76,
    -1.240_997_023_809_523_8,
    0.606_299_603_174_603_18,
    0.342_640_128_968_253_97,
    -0.892_113_658_910_533_91,
    0.778_853_969_381_313_13,
    -0.243_268_146_783_771_78,
    -0.277_046_480_537_691_48,
    0.484_920_279_915_397_10,
    -0.361_180_455_693_395_15,
    0.084_357_007_993_410_796,
    0.140_967_317_935_252_94,
    -0.210_628_762_677_866_88,
    0.143_673_788_593_609_80,
    -0.026_572_241_695_307_845,
    -0.059_613_776_222_431_048,
    0.081_378_741_132_109_947,
    -0.052_510_496_183_616_070,
    0.008_150_656_826_055_328_5,
    0.022_425_348_616_864_397,
    -0.028_977_693_520_114_284,
    0.017_979_001_668_201_123,
    -0.002_364_294_902_008_443_3,
];

/// Hemispherical (cosine-weighted) average of [`dielectric`], the first Fresnel moment
/// F̄(η) = 2 ∫₀¹ F(μ, η) μ dμ, for light arriving from the side of index 1 into index
/// η > 0. For η < 1 (light inside the denser medium) it uses the relation of
/// [`dielectric_average_inside`].
///
/// **Formula** (η > 1).
/// F̄ = ½ + (η−1)(3η+1)/(6(η+1)²) + η²(η²−1)²/(η²+1)³ ln((η−1)/(η+1))
///     − 2η³(η²+2η−1)/((η²+1)(η⁴−1)) + 8η⁴(η⁴+1)/((η²+1)(η⁴−1)²) ln η.
/// The terms without ln((η−1)/(η+1)) cancel catastrophically as η → 1 (each ~1/(η−1)²
/// while F̄ ≈ (η−1)/3); for |η − 1| < 0.1 they are summed as their Taylor series in
/// η − 1 (28 terms, coefficients derived symbolically, truncation < 1e-28). For
/// η ≥ [`LARGE_ETA`] the formula's terms cancel towards 1 and its powers η⁴ and (η⁴−1)²
/// overflow (η = 10⁸⁰ gave NaN); there F̄ = 1 − [`transmitted_average_large`].
///
/// **Derivation.** Substituting the s and p reflectances and integrating each rational
/// function of μ and √(η²−1+μ²) in closed form (partial fractions, then t = √(η²−1+μ²)).
///
/// **Source.** Siegel & Howell, *Thermal Radiation Heat Transfer*, hemispherical
/// emissivity of a dielectric (after Dunkle); also in d'Eon & Irving, "A quantized-
/// diffusion model for rendering translucent materials", SIGGRAPH 2011 (C₁ moment).
pub fn dielectric_average(eta: f64) -> f64 {
    if eta == 1.0 {
        return 0.0;
    }
    if eta < 1.0 {
        return dielectric_average_inside(1.0 / eta);
    }
    if eta >= LARGE_ETA {
        return 1.0 - transmitted_average_large(eta);
    }
    let n = eta;
    let (n2, n4) = (n * n, n * n * n * n);
    let log_part =
        n2 * (n2 - 1.0) * (n2 - 1.0) / ((n2 + 1.0).powi(3)) * ((n - 1.0) / (n + 1.0)).ln();
    let d = n - 1.0;
    let rest = if d < 0.1 {
        SERIES.iter().rev().fold(0.0, |acc, c| acc * d + c)
    } else {
        0.5 + d * (3.0 * n + 1.0) / (6.0 * (n + 1.0) * (n + 1.0))
            - 2.0 * n * n2 * (n2 + 2.0 * n - 1.0) / ((n2 + 1.0) * (n4 - 1.0))
            + 8.0 * n4 * (n4 + 1.0) / ((n2 + 1.0) * (n4 - 1.0) * (n4 - 1.0)) * n.ln()
    };
    rest + log_part
}

/// Where [`dielectric_average`] switches to its expansion in 1/η.
const LARGE_ETA: f64 = 1e4;

/// 1 − F̄(η) for large η: the asymptotic expansion of [`dielectric_average`] in x = 1/η,
/// with L = ln η,
///
///   1 − F̄ = 16x/3 − 2x²(4L − 1) − 32x³/3 − (2/3)x⁴(11 − 12L) + 496x⁵/15 + O(x⁶ L).
///
/// **Derivation.** The series of the closed form at x = 0 (computer algebra: sympy's
/// `series` of the formula with η = 1/x; the first neglected term is −32x⁶ ln x). At
/// η = 10⁴ the truncation is 5.5·10⁻¹⁹ of 1 − F̄ (against the closed form in 60-digit
/// arithmetic, mpmath), below the closed form's own cancellation there (~10⁻¹² of
/// 1 − F̄ in `f64`); from η ≈ 5·10³⁸ the terms beyond the first underflow harmlessly.
/// An infinite η (the reciprocal of an index below 1/f64::MAX) transmits nothing.
fn transmitted_average_large(eta: f64) -> f64 {
    if eta == f64::INFINITY {
        return 0.0;
    }
    let (x, l) = (1.0 / eta, eta.ln());
    x * (16.0 / 3.0
        - x * (2.0 * (4.0 * l - 1.0)
            + x * (32.0 / 3.0 + x * (2.0 / 3.0 * (11.0 - 12.0 * l) - x * (496.0 / 15.0)))))
}

/// Hemispherical average of the dielectric reflectance for light *inside* a medium of
/// relative index η > 1 (η = n_inside / n_outside), including total internal reflection.
///
/// **Formula.** F̄_in(η) = 1 − (1 − F̄_out(η)) / η², evaluated as
/// ((η − 1)(η + 1) + F̄_out(η)) / η² below η = 2: near a matched index 1 − 1/η² cancels (it lost
/// log₁₀(1/(η − 1)) digits, 3.5·10⁻¹⁰ relative at η = 1 + 10⁻⁷ and 1.6·10⁻⁵ at
/// η = 1 + 10⁻¹², against a 40-digit mpmath quadrature of 2∫F μ dμ from inside), while
/// η − 1 is exact there.
///
/// **Derivation.** Reciprocity of transmission: radiance crossing the interface scales
/// by η², and the étendue of the cone of transmitted directions inside is the outside
/// hemisphere's divided by η², so the cosine-weighted transmittance from inside is
/// (1 − F̄_out)/η²; everything outside that cone is totally reflected.
///
/// **Source.** Walter et al. 2007 / d'Eon & Irving 2011 (internal diffuse reflectance);
/// Siegel & Howell, interface reciprocity.
pub fn dielectric_average_inside(eta: f64) -> f64 {
    if eta < 2.0 {
        ((eta - 1.0) * (eta + 1.0) + dielectric_average(eta)) / (eta * eta)
    } else {
        // No cancellation here, and η² may overflow (the transmitted part → 0).
        1.0 - (1.0 - dielectric_average(eta)) / (eta * eta)
    }
}

/// Normal-incidence reflectance of a dielectric, R₀ = ((η − 1)/(η + 1))².
pub fn normal_reflectance(eta: f64) -> f64 {
    let r = (eta - 1.0) / (eta + 1.0);
    r * r
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quadrature::adaptive;

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs().max(1e-300)
    }

    /// 2∫ F μ dμ by adaptive quadrature, split at the critical angle (from inside) or at
    /// the scale √(η²−1) of the grazing feature (from outside), in log μ near 0.
    fn average_by_quadrature(eta: f64) -> f64 {
        let f = |mu: f64| 2.0 * dielectric(mu, eta) * mu;
        let feature = (eta * eta - 1.0).abs().sqrt().min(0.5);
        let mut pts = vec![0.0, feature * 1e-3, feature, (2.0 * feature).min(1.0), 1.0];
        pts.dedup();
        let lo = pts[1];
        // Below `lo` the integrand is ~2μF(0) (F → 1): integrate in log μ.
        let mut total = adaptive(
            |x: f64| f(x.exp()) * x.exp(),
            (lo * 1e-12).ln(),
            lo.ln(),
            1e-14,
        );
        for w in pts[1..].windows(2) {
            if w[1] > w[0] {
                total += adaptive(f, w[0], w[1], 1e-14);
            }
        }
        total
    }

    /// A NaN cosine or index gives NaN, never a reflectance: the cosine was capped at 1
    /// by `min`, which made NaN normal incidence (F = 0.04, T = 0.96 at η = 1.5), also
    /// where a finite cosine is totally reflected or grazing.
    #[test]
    fn nan_cosine_or_index_gives_nan() {
        // A cosine past 1 (rounding) is normal incidence, as the cap that replaced `min`
        // keeps it.
        for c in [1.0 + f64::EPSILON, 2.0, f64::INFINITY] {
            assert_eq!(dielectric(c, 1.5), dielectric(1.0, 1.5), "{c}");
            assert_eq!(dielectric(-c, 1.5), dielectric(-1.0, 1.5), "{c}");
        }
        let nan = f64::NAN;
        for (c, eta) in [
            (0.5, 1.5),
            (-0.5, 1.5),
            (-0.1, 1.5),
            (0.5, 1.000_000_1),
            (1.0, 1.5),
            (0.0, 1.5),
            (2.0, 1.5),
        ] {
            for (what, c, eta) in [("cos θ", nan, eta), ("η", c, nan)] {
                let (f, t) = (dielectric(c, eta), dielectric_transmittance(c, eta));
                assert!(
                    f.is_nan() && t.is_nan(),
                    "{what} NaN, η {eta}: F {f}, T {t}"
                );
            }
        }
    }

    #[test]
    fn dielectric_basics() {
        assert!(rel(dielectric(1.0, 1.5), 0.04) < 1e-14);
        assert!(rel(dielectric(-1.0, 1.5), 0.04) < 1e-14);
        assert_eq!(dielectric(0.0, 1.5), 1.0);
        // TIR beyond the critical angle from inside glass.
        let crit = (1.0f64 - 1.0 / 2.25).sqrt();
        assert_eq!(dielectric(-(crit * 0.999), 1.5), 1.0);
        assert!(dielectric(-(crit * 1.001), 1.5) < 1.0);
        // Brewster: r_p = 0 at tan θ = η.
        let tb = 1.5f64.atan();
        let cos_b = tb.cos();
        let sin_t2 = (1.0 - cos_b * cos_b) / 2.25;
        let cos_t = (1.0 - sin_t2).sqrt();
        let rs = (cos_b - 1.5 * cos_t) / (cos_b + 1.5 * cos_t);
        assert!(rel(dielectric(cos_b, 1.5), 0.5 * rs * rs) < 1e-12);
    }

    /// pbrt-v3's real-arithmetic conductor formula (an independent derivation, after
    /// Born & Wolf's a² ± b² parameterisation).
    fn conductor_pbrt_v3(cos_i: f64, eta: f64, k: f64) -> f64 {
        let c2 = cos_i * cos_i;
        let s2 = 1.0 - c2;
        let t0 = eta * eta - k * k - s2;
        let a2b2 = (t0 * t0 + 4.0 * eta * eta * k * k).sqrt();
        let t1 = a2b2 + c2;
        let a = (0.5 * (a2b2 + t0)).sqrt();
        let t2 = 2.0 * cos_i * a;
        let rs = (t1 - t2) / (t1 + t2);
        let t3 = c2 * a2b2 + s2 * s2;
        let t4 = t2 * s2;
        let rp = rs * (t3 - t4) / (t3 + t4);
        0.5 * (rs + rp)
    }

    #[test]
    fn conductor_cross_checks() {
        for (eta, k) in [
            (0.2, 3.0),
            (1.5, 0.0),
            (2.9, 3.0),
            (0.05, 1e-3),
            (1.0001, 1e-4),
        ] {
            let r0 = ((eta - 1.0) * (eta - 1.0) + k * k) / ((eta + 1.0) * (eta + 1.0) + k * k);
            assert!(rel(conductor(1.0, eta, k), r0) < 1e-12);
            for c in [1.0, 0.8, 0.3, 0.05, 1e-4] {
                let want = conductor_pbrt_v3(c, eta, k);
                // pbrt-v3's form cancels (t₁ − t₂) near η̃ = 1: allow its rounding.
                assert!(
                    (conductor(c, eta, k) - want).abs() < 1e-9 * want + 1e-15,
                    "{eta} {k} {c}"
                );
                if k == 0.0 && eta > 1.0 {
                    assert!(rel(conductor(c, eta, k), dielectric(c, eta)) < 1e-12);
                }
            }
            assert!((conductor(0.0, eta, k) - 1.0).abs() < 1e-12);
        }
    }

    /// Indices far beyond any metal (10¹⁰⁰ to 10³⁰⁸, where |η̃|² overflows; |η̃| itself
    /// must stay below f64::MAX/2, the sums of the formula) reflect
    /// almost everything: F = 1 − O(cos θ/|η̃|), finite and within [0, 1], not NaN. Where
    /// the square still fits (10¹⁰⁰), also the normal-incidence closed form.
    #[test]
    fn huge_indices_reflect_everything() {
        for (eta, k) in [
            (1e100, 0.0),
            (1e200, 0.5),
            (1e308, 0.5),
            (1.5, 1e200),
            (1.5, 1e308),
            (1e307, 1e307),
        ] {
            for c in [1.0, 0.3, 1e-3, 0.0] {
                let f = conductor(c, eta, k);
                assert!(
                    (0.0..=1.0).contains(&f) && f >= 1.0 - 1e-90,
                    "η = {eta}, k = {k}, cos θ = {c}: F = {f}"
                );
            }
        }
        let (eta, k) = (1e100, 3.0);
        let r0 = ((eta - 1.0) * (eta - 1.0) + k * k) / ((eta + 1.0) * (eta + 1.0) + k * k);
        assert!(rel(conductor(1.0, eta, k), r0) < 1e-12);
    }

    /// Near a matched index from inside, F̄_in ≈ 1 − 1/η² is small and 1 − (1 − F̄)/η²
    /// cancelled: 3.5·10⁻¹⁰ relative at η = 1 + 10⁻⁷, 1.6·10⁻⁵ at 1 + 10⁻¹². References:
    /// 2∫₀¹ F(μ; 1/η) μ dμ split at the critical μ, in 40-digit mpmath (session 40).
    #[test]
    fn average_inside_near_a_matched_index_does_not_cancel() {
        for (eta, want) in [
            (1.0000001, 2.333_332_206_633_736e-7),
            (1.0001, 2.332_550_778_980_566e-4),
            (1.01, 2.278_825_868_282_86e-2),
            (1.000000000001, 2.333_540_768_008_422e-12),
        ] {
            let got = dielectric_average_inside(eta);
            assert!(rel(got, want) < 1e-13, "η = {eta}: {got:e} vs {want:e}");
            assert!(
                rel(dielectric_average(1.0 / eta), want) < 1e-12,
                "1/η = {}",
                1.0 / eta
            );
        }
        assert_eq!(dielectric_average_inside(1.0), 0.0);
        assert_eq!(dielectric_average_inside(1e300), 1.0);
    }

    #[test]
    fn hemispherical_average_matches_quadrature() {
        for eta in [1.0001, 1.01, 1.0999, 1.1001, 1.33, 1.5, 2.4, 4.0, 10.0] {
            let q = average_by_quadrature(eta);
            let got = dielectric_average(eta);
            assert!(rel(got, q) < 1e-9, "eta={eta}: {got} vs {q}");
            // From inside (TIR): direct quadrature with the relative index 1/η.
            let qi = average_by_quadrature(1.0 / eta);
            assert!(
                rel(dielectric_average_inside(eta), qi) < 1e-9,
                "inside eta={eta}: {qi}"
            );
            assert!(rel(dielectric_average(1.0 / eta), qi) < 1e-9);
        }
        // Known value: F̄(1.5) ≈ 0.0918 (e.g. tables of hemispherical reflectance).
        assert!((dielectric_average(1.5) - 0.091_777_959_342_351_21).abs() < 1e-15);
        assert_eq!(dielectric_average(1.0), 0.0);
    }

    /// Large indices take the expansion in 1/η: against the closed form in 60-digit
    /// arithmetic (mpmath, `F(mpf(n))` of the formula in the doc, which a quadrature of
    /// 2∫F μ dμ matches to 25 digits at η = 10⁴), on both sides of the switch, and finite
    /// up to f64::MAX (η = 10⁸⁰ gave NaN: η⁴ and (η⁴ − 1)² overflowed).
    #[test]
    // References printed to 20 significant digits by mpmath; kept verbatim.
    #[allow(clippy::excessive_precision)]
    fn large_indices_take_the_expansion() {
        for (eta, one_minus) in [
            (1e4, 5.326_164_954_435_438_413_9e-4),
            (3.7e5, 1.441_367_978_990_670_735_5e-5),
            (1e9, 5.333_333_169_547_206_627_1e-9),
            (1e20, 5.333_333_333_333_333_329_7e-20),
        ] {
            assert!(
                rel(transmitted_average_large(eta), one_minus) < 1e-15,
                "{eta}"
            );
            // F̄ itself to an ulp of 1.
            let f = dielectric_average(eta);
            assert!((f - (1.0 - one_minus)).abs() <= f64::EPSILON, "{eta}: {f}");
        }
        // Every term counts: at η = 10³ (below the switch, where the truncation is
        // 4·10⁻¹⁴ of 1 − F̄) the x⁵ term is 6·10⁻¹² of it.
        let at_1e3 = transmitted_average_large(1e3);
        assert!(
            rel(at_1e3, 5.280_060_672_396_367_375_1e-3) < 1e-13,
            "{at_1e3}"
        );
        // Just below the switch the closed form, just above it the series: they agree.
        let (below, above) = (
            dielectric_average(1e4f64.next_down()),
            dielectric_average(1e4),
        );
        assert!(rel(below, above) < 1e-15, "{below} {above}");
        // Inside, 1 − (1 − F̄)/η²: 0.999 473 671 259 191 217 22 at η = 20 (closed form).
        assert!(
            rel(
                dielectric_average_inside(20.0),
                0.999_473_671_259_191_217_22
            ) < 1e-15
        );
        for eta in [1e80, 1e200, f64::MAX, f64::INFINITY] {
            for v in [
                dielectric_average(eta),
                dielectric_average(1.0 / eta),
                dielectric_average_inside(eta),
            ] {
                assert!(v.is_finite() && v <= 1.0 && v > 0.999_999, "η = {eta}: {v}");
            }
        }
    }

    /// Near matched indices the cancellation-free forms keep F's relative accuracy where
    /// the direct form lost it (1 − sin²θₜ rounded), and the transmittance 1 − F near the
    /// critical angle: against Born & Wolf's expressions in 50-digit arithmetic (mpmath).
    #[test]
    // References printed to 20 significant digits by mpmath; kept verbatim.
    #[allow(clippy::excessive_precision)]
    fn near_matched_indices_keep_relative_accuracy() {
        let e = 1.000_000_1;
        for (c, want) in [
            (1e-3, 2.074_693_373_084_809_376e-3),
            (0.5, 2.499_997_952_920_768_543_3e-14),
            (1.0, 2.499_999_752_919_354_197_1e-15),
            (-0.5, 2.500_001_552_920_234_850_5e-14),
        ] {
            let f = dielectric(c, e);
            assert!(rel(f, want) < 1e-12, "F({c}; {e}) = {f} vs {want}");
        }
        // 1 − F from inside, just above the critical cosine 4.4721356e-4 (η′ = 1/e).
        for (c, eta, want) in [
            (-4.5e-4, e, 0.360_001_750_066_390_560_02),
            (-4.4722e-4, e, 0.021_234_263_924_314_119_721),
            (-1e-3, e, 0.996_894_386_577_955_762_5),
        ] {
            let t = dielectric_transmittance(c, eta);
            assert!(rel(t, want) < 1e-11, "T({c}; {eta}) = {t} vs {want}");
        }
        assert_eq!(dielectric_transmittance(-0.4e-3, e), 0.0);
        for (c, eta) in [(0.3, 1.5), (0.9, 2.4), (-0.9, 1.33), (0.7, 0.8)] {
            let t = dielectric_transmittance(c, eta);
            assert!((t - (1.0 - dielectric(c, eta))).abs() < 1e-15, "{c} {eta}");
        }
        // The conductor at 1 + 10⁻¹² i (F ~ 10⁻²⁵) and two other indices within 1/2 of 1.
        for (c, eta, k, want) in [
            (1e-3, 1.0, 1e-12, 2.499_995_000_001_249_698_8e-13),
            (0.5, 1.0, 1e-12, 2.499_999_999_999_999_899_4e-24),
            (1.0, 1.0, 1e-12, 2.499_999_999_999_999_899_4e-25),
            (0.5, 0.9, 0.1, 0.083_392_729_924_655_190_497),
            (0.3, 0.7, 1e-3, 0.996_782_894_421_151_158_79),
        ] {
            let f = conductor(c, eta, k);
            assert!(rel(f, want) < 1e-12, "F({c}; {eta} + {k}i) = {f} vs {want}");
        }
    }
}
