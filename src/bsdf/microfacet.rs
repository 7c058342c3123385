//! Isotropic microfacet distributions: normal distribution D, Smith masking G, and
//! visible-normal sampling.
//!
//! Directions are in the local frame (normal +z). With tan²θ = (x² + y²)/z² for a unit
//! vector (computed from x and y, which keeps precision near the pole where
//! 1 − z² rounds to zero in `f32`):
//!
//! - **GGX / Trowbridge–Reitz** (Trowbridge & Reitz 1975; Walter et al. 2007):
//!   D(m) = α² / (π (x² + y² + α² z²)²) for unit m with z > 0, and
//!   Λ(ω) = (√(1 + α² tan²θ) − 1)/2, written α² tan²θ / (2(1 + √(1 + α² tan²θ))) to avoid
//!   cancellation for small α tan θ.
//! - **Beckmann** (Beckmann & Spizzichino 1963): D(m) = exp(−tan²θ/α²)/(π α² cos⁴θ),
//!   Λ(ω) = (erf(a) − 1)/2 + exp(−a²)/(2a√π), a = 1/(α tan θ) (Heitz 2014, eq. 80);
//!   evaluated in `f64` with statrs's erf because the two terms cancel for large a.
//! - **Smith masking** G1(ω) = 1/(1 + Λ(ω)); masking–shadowing either
//!   **height-correlated** G2 = 1/(1 + Λ(ωo) + Λ(ωi)) (Heitz 2014, "Understanding the
//!   Masking-Shadowing Function", eq. 99; used for reflection and, as in pbrt-v4, for
//!   transmission) or **uncorrelated** G2 = G1(ωo) G1(ωi) (eq. 98).
//! - **Visible normals** D_ω(m) = G1(ω) ⟨ω, m⟩⁺ D(m) / cos θ (Heitz 2014, eq. 38).
//!   GGX samples them exactly with Heitz 2018, "Sampling the GGX Distribution of
//!   Visible Normals" (JCGT 7(4)); [`Microfacet::sample_vndf_spherical_cap`] is the
//!   equivalent spherical-cap construction of Dupuy & Benyoub 2023. Beckmann samples
//!   them with the stretch/sample/rotate/unstretch scheme of Heitz & d'Eon 2014
//!   ("Importance Sampling Microfacet-Based BSDFs using the Distribution of Visible
//!   Normals"), the 1-D slope inversion done by a safeguarded Newton iteration on the
//!   closed-form CDF F(x) ∝ 1 + erf(x) + tan θ e^{−x²}/√π (as in pbrt-v3), in `f64`
//!   so that its accuracy (1e-10 in the CDF) sits far below what a chi-square test sees.
//!
//! Identities proven in `tests/proof/bsdf_contract.rs`: ∫ D(m) cos θm dm = 1,
//! ∫ D_ω(m) dm = 1 and the weak white furnace ∫ G1(ω) D(m) ⟨ω, m⟩⁺ / cos θ dm = 1.
//! The unit tests below pin the same identities with the engine's quadrature, plus the
//! closed forms, the projected area ∫ ⟨ω, m⟩⁺ D dm = cos θ (1 + Λ(ω)) and each sampler,
//! in about a second: fast enough for `cargo mutants` with lib tests alone.

use crate::math::{PI, TWO_PI, safe_sqrt};
use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};

/// Which normal distribution.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Distribution {
    /// GGX / Trowbridge–Reitz.
    #[default]
    Ggx,
    /// Beckmann–Spizzichino.
    Beckmann,
}

/// Which masking–shadowing form.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Masking {
    /// 1/(1 + Λ(ωo) + Λ(ωi)).
    #[default]
    HeightCorrelated,
    /// G1(ωo) G1(ωi).
    Uncorrelated,
}

/// Smallest roughness a microfacet model accepts.
pub const MIN_ALPHA: f32 = 1e-4;
/// Largest roughness a microfacet model accepts.
pub const MAX_ALPHA: f32 = 1.0;

/// An isotropic microfacet distribution of roughness α.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Microfacet {
    /// D's family.
    pub distribution: Distribution,
    /// Roughness α (GGX: the Trowbridge–Reitz width; Beckmann: the RMS slope × √2).
    pub alpha: f32,
    /// G2's form.
    pub masking: Masking,
}

#[inline]
fn tan2_theta(w: Vec3) -> f32 {
    let s2 = w.x * w.x + w.y * w.y;
    let c2 = w.z * w.z;
    // `== 0`, not `!(> 0)`: a NaN direction passes on as NaN (never masked).
    if c2 == 0.0 { f32::INFINITY } else { s2 / c2 }
}

impl Microfacet {
    /// A distribution; α is clamped into [`MIN_ALPHA`], [`MAX_ALPHA`] so that no
    /// formula divides by zero.
    pub fn new(distribution: Distribution, alpha: f32, masking: Masking) -> Self {
        let alpha = if alpha.is_finite() {
            alpha.clamp(MIN_ALPHA, MAX_ALPHA)
        } else {
            MAX_ALPHA
        };
        Microfacet {
            distribution,
            alpha,
            masking,
        }
    }

    /// D(m) for a unit microfacet normal (0 below the horizon).
    #[inline]
    pub fn d(&self, m: Vec3) -> f32 {
        // `<=`, not `!(>)`: a NaN m passes on as NaN (never masked).
        if m.z <= 0.0 {
            return 0.0;
        }
        let a = self.alpha;
        let a2 = a * a;
        match self.distribution {
            Distribution::Ggx => {
                // Finite for every unit m at α ≥ MIN_ALPHA (den ≥ α²: D ≤ 1/(πα²) ≈ 3.2·10⁷);
                // a NaN component of m gives NaN, passed on (never masked).
                let den = m.x * m.x + m.y * m.y + a2 * m.z * m.z;
                a2 / (PI * den * den)
            }
            Distribution::Beckmann => {
                let e = tan2_theta(m) / a2;
                // `>=`, not `!(<)`: a NaN m passes on as NaN (never masked).
                if e >= 80.0 {
                    return 0.0;
                }
                let c2 = m.z * m.z;
                (-e).exp() / (PI * a2 * c2 * c2)
            }
        }
    }

    /// Smith's Λ(ω) (symmetric in the sign of ω.z); +∞ at exactly grazing ω.
    #[inline]
    pub fn lambda(&self, w: Vec3) -> f32 {
        // `== ∞`, not `!is_finite`, here and below: a NaN direction passes on as NaN.
        let t2 = tan2_theta(w);
        if t2 == f32::INFINITY {
            return f32::INFINITY;
        }
        match self.distribution {
            Distribution::Ggx => {
                let x = self.alpha * self.alpha * t2;
                if x == f32::INFINITY {
                    return f32::INFINITY;
                }
                x / (2.0 * (1.0 + (1.0 + x).sqrt()))
            }
            Distribution::Beckmann => {
                let at = self.alpha as f64 * (t2 as f64).sqrt();
                if at <= 0.0 {
                    return 0.0;
                }
                let a = 1.0 / at;
                if a > 6.0 {
                    // Λ < 1e-17 here.
                    return 0.0;
                }
                let l = 0.5
                    * ((-a * a).exp() / (a * std::f64::consts::PI.sqrt())
                        - statrs::function::erf::erfc(a));
                // Not `max`, which would turn a NaN into 0.
                (if l < 0.0 { 0.0 } else { l }) as f32
            }
        }
    }

    /// G1(ω) = 1/(1 + Λ(ω)).
    #[inline]
    pub fn g1(&self, w: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(w))
    }

    /// G2(ωo, ωi) in the configured form.
    #[inline]
    pub fn g2(&self, wo: Vec3, wi: Vec3) -> f32 {
        match self.masking {
            // Λo + Λi first: commutative, so G2(ωo, ωi) = G2(ωi, ωo) bit for bit.
            Masking::HeightCorrelated => 1.0 / (1.0 + (self.lambda(wo) + self.lambda(wi))),
            Masking::Uncorrelated => self.g1(wo) * self.g1(wi),
        }
    }

    /// Visible-normal density D_ω(m) = G1(ω) ⟨ω, m⟩⁺ D(m) / cos θ for ω with z > 0.
    #[inline]
    pub fn d_visible(&self, w: Vec3, m: Vec3) -> f32 {
        // ⟨ω, m⟩ in f64: at grazing ω it is a sum of nearly cancelling products.
        let c = w.as_dvec3().dot(m.as_dvec3()) as f32;
        // `<=`, not `!(>)`: a NaN ω or m passes on as NaN (never masked).
        if w.z <= 0.0 || c <= 0.0 {
            return 0.0;
        }
        // Finite: G1(ω)·c·D(m) ≤ 3.2·10⁷ overflows only for cos θ < 10⁻³¹, where Λ's
        // tan²θ is already +∞ and G1 = 0. A NaN is passed on (never masked).
        self.g1(w) * c * self.d(m) / w.z
    }

    /// Density of [`Microfacet::sample_m`] (solid angle of m): D_ω(m) for both families.
    #[inline]
    pub fn pdf_m(&self, w: Vec3, m: Vec3) -> f32 {
        self.d_visible(w, m)
    }

    /// Draw a visible microfacet normal for ω with z > 0.
    #[inline]
    pub fn sample_m(&self, w: Vec3, u: Vec2) -> Vec3 {
        match self.distribution {
            Distribution::Ggx => self.sample_vndf_heitz(w, u),
            Distribution::Beckmann => self.sample_vndf_beckmann(w, u),
        }
    }

    /// GGX visible normals, Heitz 2018 (listing 1), for ω with z > 0.
    pub fn sample_vndf_heitz(&self, w: Vec3, u: Vec2) -> Vec3 {
        let a = self.alpha;
        let vh = Vec3::new(a * w.x, a * w.y, w.z).normalize_or(Vec3::Z);
        let lensq = vh.x * vh.x + vh.y * vh.y;
        let t1 = if lensq > 0.0 {
            Vec3::new(-vh.y, vh.x, 0.0) / lensq.sqrt()
        } else {
            Vec3::X
        };
        let t2 = vh.cross(t1);
        let r = safe_sqrt(u.x);
        let phi = TWO_PI * u.y;
        let p1 = r * phi.cos();
        let mut p2 = r * phi.sin();
        let s = 0.5 * (1.0 + vh.z);
        p2 = (1.0 - s) * safe_sqrt(1.0 - p1 * p1) + s * p2;
        let nh = p1 * t1 + p2 * t2 + safe_sqrt(1.0 - p1 * p1 - p2 * p2) * vh;
        Vec3::new(a * nh.x, a * nh.y, nh.z.max(0.0)).normalize_or(Vec3::Z)
    }

    /// GGX visible normals by the spherical cap (Dupuy & Benyoub 2023, listing 3):
    /// the same density as [`Microfacet::sample_vndf_heitz`], fewer operations.
    pub fn sample_vndf_spherical_cap(&self, w: Vec3, u: Vec2) -> Vec3 {
        let a = self.alpha;
        let ws = Vec3::new(a * w.x, a * w.y, w.z).normalize_or(Vec3::Z);
        let phi = TWO_PI * u.x;
        let z = (1.0 - u.y) * (1.0 + ws.z) - ws.z;
        let st = safe_sqrt(1.0 - z * z);
        let c = Vec3::new(st * phi.cos(), st * phi.sin(), z);
        let h = c + ws;
        Vec3::new(a * h.x, a * h.y, h.z.max(0.0)).normalize_or(Vec3::Z)
    }

    /// Beckmann visible normals (Heitz & d'Eon 2014; pbrt-v3 `BeckmannSample`).
    pub fn sample_vndf_beckmann(&self, w: Vec3, u: Vec2) -> Vec3 {
        let a = self.alpha;
        let ws = Vec3::new(a * w.x, a * w.y, w.z).normalize_or(Vec3::Z);
        let (sx, sy) = beckmann_sample11(ws.z as f64, u.x as f64, u.y as f64);
        let r = (ws.x * ws.x + ws.y * ws.y).sqrt();
        let (cos_phi, sin_phi) = if r > 0.0 {
            (ws.x / r, ws.y / r)
        } else {
            (1.0, 0.0)
        };
        let (sx, sy) = (sx as f32, sy as f32);
        let tx = cos_phi * sx - sin_phi * sy;
        let ty = sin_phi * sx + cos_phi * sy;
        Vec3::new(-a * tx, -a * ty, 1.0).normalize_or(Vec3::Z)
    }
}

/// Slopes (x, y) of a visible Beckmann (α = 1) microfacet for a direction with
/// cos θ = `cos_theta` and azimuth 0: x from the CDF
/// F(x) = (1 + erf x + tan θ e^{−x²}/√π)/(1 + erf(cot θ) + tan θ e^{−cot²θ}/√π) on
/// x < cot θ, inverted in b = erf x by Newton steps kept inside a bisection bracket;
/// y = erf⁻¹(2u₂ − 1).
fn beckmann_sample11(cos_theta: f64, u1: f64, u2: f64) -> (f64, f64) {
    use statrs::function::erf::{erf, erf_inv};
    const B_MIN: f64 = -1.0 + 1e-15;
    let c = cos_theta.clamp(1e-12, 1.0);
    let s = (1.0 - c * c).max(0.0).sqrt();
    let tan_t = s / c;
    let inv_sqrt_pi = 1.0 / std::f64::consts::PI.sqrt();
    let y = erf_inv((2.0 * u2 - 1.0).clamp(B_MIN, -B_MIN));
    let u = u1.clamp(1e-12, 1.0 - 1e-12);
    if tan_t < 1e-8 {
        return (erf_inv((2.0 * u - 1.0).clamp(B_MIN, -B_MIN)), y);
    }
    let cot = 1.0 / tan_t;
    let hi0 = erf(cot);
    let norm = 1.0 / (1.0 + hi0 + inv_sqrt_pi * tan_t * (-cot * cot).exp());
    let (mut lo, mut hi) = (-1.0f64, hi0);
    // Initial guess from pbrt-v3's fit.
    let theta = c.acos();
    let fit = 1.0 + theta * (-0.876 + theta * (0.4265 - 0.0594 * theta));
    let mut b = hi0 - (1.0 + hi0) * (1.0 - u).powf(fit);
    for _ in 0..60 {
        if !(b > lo && b < hi) {
            b = 0.5 * (lo + hi);
        }
        let x = erf_inv(b.max(B_MIN));
        let value = norm * (1.0 + b + inv_sqrt_pi * tan_t * (-x * x).exp()) - u;
        if value.abs() < 1e-12 {
            break;
        }
        if value > 0.0 {
            hi = b;
        } else {
            lo = b;
        }
        let deriv = norm * (1.0 - x * tan_t);
        b -= value / deriv;
        if hi - lo < 1e-15 {
            break;
        }
    }
    let x = erf_inv(b.clamp(B_MIN, hi0.max(B_MIN)));
    (x, y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grazing_and_pole_are_finite() {
        for dist in [Distribution::Ggx, Distribution::Beckmann] {
            for alpha in [1e-4, 0.01, 0.5, 1.0] {
                let mf = Microfacet::new(dist, alpha, Masking::HeightCorrelated);
                assert!(mf.d(Vec3::Z).is_finite());
                assert_eq!(mf.g1(Vec3::X), 0.0);
                assert_eq!(mf.lambda(Vec3::Z), 0.0);
                for w in [
                    Vec3::Z,
                    Vec3::new(1.0, 0.0, 1e-6).normalize(),
                    Vec3::new(0.3, 0.4, 0.2).normalize(),
                ] {
                    for u in [
                        Vec2::ZERO,
                        Vec2::splat(0.5),
                        Vec2::splat(crate::math::ONE_MINUS_EPSILON),
                    ] {
                        let m = mf.sample_m(w, u);
                        assert!(m.is_finite() && m.z >= 0.0, "{dist:?} {alpha} {w} {u} {m}");
                    }
                }
            }
        }
    }

    /// D and D_ω at the edges of their domain: D = 0 for m at or below the horizon, D_ω =
    /// 0 for an exactly grazing ω (where G1 = 0 and cos θ = 0 would make 0/0) and for m
    /// facing away from ω; a NaN m passes on as NaN (never zeroed).
    #[test]
    fn densities_at_their_domain_edges() {
        for dist in [Distribution::Ggx, Distribution::Beckmann] {
            for alpha in [1e-4, 0.3, 1.0] {
                let mf = Microfacet::new(dist, alpha, Masking::HeightCorrelated);
                assert_eq!(mf.d(Vec3::X), 0.0);
                assert_eq!(mf.d(-Vec3::Z), 0.0);
                assert_eq!(mf.d_visible(Vec3::X, Vec3::Z), 0.0, "{dist:?} {alpha}");
                assert_eq!(mf.d_visible(Vec3::new(0.6, 0.0, 0.0), Vec3::X), 0.0);
                let w = Vec3::new(0.6, 0.0, 0.8);
                assert_eq!(mf.d_visible(w, Vec3::new(-0.8, 0.0, 0.6)), 0.0);
                assert!(mf.d_visible(w, Vec3::Z) > 0.0);
                let nan = Vec3::new(f32::NAN, 0.0, 1.0);
                assert!(mf.d(nan).is_nan(), "{dist:?} {alpha}");
                assert!(mf.d(Vec3::new(0.0, 0.0, f32::NAN)).is_nan());
                assert!(
                    mf.d_visible(Vec3::new(0.0, 0.0, f32::NAN), Vec3::Z)
                        .is_nan()
                );
                assert!(mf.lambda(Vec3::new(0.0, f32::NAN, 1.0)).is_nan());
                if dist == Distribution::Beckmann {
                    // a = 1/(α tan θ) just past 6: Λ < 1e-17 is returned as 0 exactly (the
                    // formula would give ~1e-19 there).
                    let w = Vec3::new(1.0 / (6.01 * mf.alpha), 0.0, 1.0).normalize();
                    assert_eq!(mf.lambda(w), 0.0, "{alpha}");
                }
                assert!(mf.g1(Vec3::new(0.0, 0.0, f32::NAN)).is_nan());
                assert!(
                    mf.d_visible(Vec3::Z, Vec3::new(0.0, f32::NAN, 1.0))
                        .is_nan()
                );
            }
        }
    }

    use crate::quadrature::adaptive;
    use statrs::function::erf::{erf, erf_inv};
    use std::f64::consts::{FRAC_PI_2, PI as PI64};

    /// The unit vector at polar angle θ and azimuth φ (f64 in, f32 out).
    fn dir(theta: f64, phi: f64) -> Vec3 {
        let (s, c) = theta.sin_cos();
        Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, c as f32)
    }

    fn ggx(alpha: f32) -> Microfacet {
        Microfacet::new(Distribution::Ggx, alpha, Masking::HeightCorrelated)
    }

    fn beckmann(alpha: f32) -> Microfacet {
        Microfacet::new(Distribution::Beckmann, alpha, Masking::HeightCorrelated)
    }

    /// The closed forms of the module notes, written out by hand in f64 from θ:
    /// GGX D = 1/(π α² cos⁴θ (1 + tan²θ/α²)²), Λ = (√(1 + α² tan²θ) − 1)/2;
    /// Beckmann D = e^{−tan²θ/α²}/(π α² cos⁴θ), Λ = (erf a − 1)/2 + e^{−a²}/(2a√π),
    /// a = 1/(α tan θ).
    fn d_hand(dist: Distribution, alpha: f64, theta: f64) -> f64 {
        let (t2, c4) = (theta.tan().powi(2), theta.cos().powi(4));
        let a2 = alpha * alpha;
        match dist {
            Distribution::Ggx => 1.0 / (PI64 * a2 * c4 * (1.0 + t2 / a2).powi(2)),
            Distribution::Beckmann => (-t2 / a2).exp() / (PI64 * a2 * c4),
        }
    }

    fn lambda_hand(dist: Distribution, alpha: f64, theta: f64) -> f64 {
        let t = theta.tan();
        match dist {
            Distribution::Ggx => ((1.0 + alpha * alpha * t * t).sqrt() - 1.0) / 2.0,
            Distribution::Beckmann => {
                let a = 1.0 / (alpha * t);
                (erf(a) - 1.0) / 2.0 + (-a * a).exp() / (2.0 * a * PI64.sqrt())
            }
        }
    }

    /// |x − y| within `rel` of |y| (the f32 evaluation: a few ulps times the formula's
    /// condition, 2e-5 covers every angle below).
    fn close(x: f32, y: f64, rel: f64) -> bool {
        (x as f64 - y).abs() <= rel * y.abs().max(1e-30)
    }

    const DISTS: [Distribution; 2] = [Distribution::Ggx, Distribution::Beckmann];

    #[test]
    fn d_lambda_g1_g2_match_their_closed_forms() {
        for dist in DISTS {
            for alpha in [0.3f32, 0.7, 1.0] {
                let a = alpha as f64;
                let mf = Microfacet::new(dist, alpha, Masking::HeightCorrelated);
                let un = Microfacet::new(dist, alpha, Masking::Uncorrelated);
                for deg in [0.0f64, 20.0, 45.0, 60.0, 75.0, 85.0] {
                    let th = deg.to_radians();
                    let m = dir(th, 1.1);
                    let d = d_hand(dist, a, th);
                    assert!(
                        close(mf.d(m), d, 2e-5),
                        "{dist:?} α {a} θ {deg}: D {}",
                        mf.d(m)
                    );
                    // D vanishes below the horizon.
                    assert_eq!(mf.d(Vec3::new(m.x, m.y, -m.z)), 0.0);
                    if deg == 0.0 {
                        continue;
                    }
                    let l = lambda_hand(dist, a, th);
                    let w = dir(th, -2.3);
                    assert!(
                        (mf.lambda(w) as f64 - l).abs() <= 2e-5 * l + 1e-7,
                        "{dist:?} α {a} θ {deg}: Λ {} vs {l}",
                        mf.lambda(w)
                    );
                    // Λ is even in cos θ.
                    assert_eq!(mf.lambda(w), mf.lambda(Vec3::new(w.x, w.y, -w.z)));
                    assert!(close(mf.g1(w), 1.0 / (1.0 + l), 2e-5));
                    // G2 against a second direction, in both forms and both orders.
                    let th2 = 70f64.to_radians();
                    let wi = dir(th2, 0.4);
                    let l2 = lambda_hand(dist, a, th2);
                    let hc = 1.0 / (1.0 + l + l2);
                    let uc = 1.0 / ((1.0 + l) * (1.0 + l2));
                    assert!(close(mf.g2(w, wi), hc, 2e-5), "{dist:?} {a} {deg}");
                    assert!(close(un.g2(w, wi), uc, 2e-5), "{dist:?} {a} {deg}");
                    assert_eq!(mf.g2(w, wi), mf.g2(wi, w));
                }
            }
        }
        // Hand values at α = 1, θ = 45° (tan θ = 1): GGX Λ = (√2 − 1)/2; Beckmann a = 1,
        // Λ = (erf 1 − 1)/2 + e⁻¹/(2√π) with erf 1 = 0.8427007929497149.
        let w = dir(std::f64::consts::FRAC_PI_4, 0.0);
        assert!(close(ggx(1.0).lambda(w), (2f64.sqrt() - 1.0) / 2.0, 2e-5));
        let beck = (0.842_700_792_949_714_9 - 1.0) / 2.0 + (-1f64).exp() / (2.0 * PI64.sqrt());
        assert!(close(beckmann(1.0).lambda(w), beck, 2e-5));
        // GGX D at the pole is 1/(π α²).
        assert!(close(ggx(0.5).d(Vec3::Z), 4.0 / PI64, 1e-6));
        // Beckmann Λ is below 1e-17 for a = 1/(α tan θ) > 6: exactly 0 here (a ≈ 38).
        assert_eq!(beckmann(0.3).lambda(dir(5f64.to_radians(), 0.0)), 0.0);
    }

    #[test]
    fn beckmann_d_vanishes_from_its_cutoff() {
        // D is 0 once tan²θ/α² ≥ 80 (e⁻⁸⁰ ≈ 1.8e-35; beyond, exp and cos⁴θ underflow
        // and 0/0 would follow). At m = (4, 2, 1), α = ½, tan²θ/α² = 20/¼ = 80 exactly
        // in f32; at (4, 1.9, 1) it is 78.44 and D is positive.
        let b = beckmann(0.5);
        assert_eq!(b.d(Vec3::new(4.0, 2.0, 1.0)), 0.0);
        assert!(b.d(Vec3::new(4.0, 1.9, 1.0)) > 0.0);
    }

    #[test]
    fn roughness_is_clamped_into_its_range() {
        let a = |x: f32| ggx(x).alpha;
        assert_eq!(a(0.0), MIN_ALPHA);
        assert_eq!(a(2.0), MAX_ALPHA);
        assert_eq!(a(f32::NAN), MAX_ALPHA);
        assert_eq!(a(f32::INFINITY), MAX_ALPHA);
        assert_eq!(a(0.25), 0.25);
        let mf = Microfacet::new(Distribution::Beckmann, 0.25, Masking::Uncorrelated);
        assert_eq!(mf.distribution, Distribution::Beckmann);
        assert_eq!(mf.masking, Masking::Uncorrelated);
    }

    /// ∫ f over the upper hemisphere (dm = sin θ dθ dφ) by the engine's adaptive
    /// Gauss–Legendre rule, nested; adaptive in φ because D_ω has a kink at ⟨ω, m⟩ = 0.
    /// Tolerance 1e-6 relative: the f32 integrand's rounding (~1e-7) must sit below it,
    /// or the bisection refines rounding noise to its depth limit.
    fn hemisphere(f: impl Fn(Vec3) -> f64) -> f64 {
        adaptive(
            |th| {
                let inner = adaptive(|ph| f(dir(th, ph)), 0.0, 2.0 * PI64, 1e-6, 1e-9);
                inner * th.sin()
            },
            0.0,
            FRAC_PI_2,
            1e-6,
            1e-9,
        )
    }

    #[test]
    fn d_is_normalised_and_lambda_is_its_projected_area() {
        for dist in DISTS {
            for alpha in [0.3f32, 0.8] {
                let mf = Microfacet::new(dist, alpha, Masking::HeightCorrelated);
                // ∫ D(m) cos θm dm = 1 (isotropic: one azimuth suffices for the θ integral).
                let n = 2.0
                    * PI64
                    * adaptive(
                        |th| mf.d(dir(th, 0.9)) as f64 * th.cos() * th.sin(),
                        0.0,
                        FRAC_PI_2,
                        1e-6,
                        1e-9,
                    );
                assert!((n - 1.0).abs() < 1e-4, "{dist:?} α {alpha}: ∫D cos = {n}");
                for w in [dir(1.0, 0.6), dir(1.4, -2.0)] {
                    // ∫ ⟨ω, m⟩⁺ D(m) dm = cos θ (1 + Λ(ω)) (Heitz 2014, eq. 12 and 21).
                    let proj = hemisphere(|m| (w.dot(m).max(0.0) * mf.d(m)) as f64);
                    let want = w.z as f64 * (1.0 + mf.lambda(w) as f64);
                    assert!(
                        (proj - want).abs() < 1e-4 * want,
                        "{dist:?} α {alpha} {w}: {proj} vs {want}"
                    );
                    // Hence ∫ D_ω(m) dm = 1, and pdf_m is that density.
                    let vis = hemisphere(|m| mf.d_visible(w, m) as f64);
                    assert!((vis - 1.0).abs() < 1e-4, "{dist:?} α {alpha} {w}: {vis}");
                    let m = dir(0.5, 0.2);
                    assert_eq!(mf.pdf_m(w, m), mf.d_visible(w, m));
                }
            }
        }
    }

    #[test]
    fn d_visible_matches_its_definition_and_vanishes_where_it_must() {
        let a = 0.4;
        for dist in DISTS {
            let mf = Microfacet::new(dist, a as f32, Masking::Uncorrelated);
            let (tw, tm) = (1.1f64, 0.5f64);
            let (w, m) = (dir(tw, 0.3), dir(tm, -0.4));
            let cos_wm = w.as_dvec3().dot(m.as_dvec3());
            let want = cos_wm * d_hand(dist, a, tm) / ((1.0 + lambda_hand(dist, a, tw)) * tw.cos());
            assert!(close(mf.d_visible(w, m), want, 3e-5), "{dist:?}");
            // Back-facing m, ω below the horizon, m below the horizon: 0.
            assert_eq!(mf.d_visible(w, dir(1.2, 0.3 + PI64)), 0.0);
            assert_eq!(mf.d_visible(Vec3::new(w.x, w.y, -w.z), m), 0.0);
            assert_eq!(mf.d_visible(w, Vec3::new(m.x, m.y, -m.z)), 0.0);
        }
    }

    /// Each of a pair of uniform numbers in (0, 1), away from the clamps.
    const US: [f32; 4] = [0.1, 0.37, 0.62, 0.8];

    fn close_vec(a: Vec3, b: Vec3) -> bool {
        (a - b).abs().max_element() < 2e-6
    }

    #[test]
    fn samplers_at_normal_incidence_have_closed_forms() {
        // At ω = +z each construction reduces by hand: Heitz 2018 to Malley's disk
        // projection (s = 1, t1 = x, t2 = y), the spherical cap to the half-vector of
        // z and a uniform sphere point, ∝ (√u₂ cos 2πu₁, √u₂ sin 2πu₁, √(1 − u₂)), and
        // Beckmann to independent Gaussian slopes −α erf⁻¹(2u − 1); each stretched by α.
        for alpha in [0.35f32, 1.0] {
            let a = alpha as f64;
            let g = ggx(alpha);
            let b = beckmann(alpha);
            for u1 in US {
                for u2 in US {
                    let (x1, x2) = (u1 as f64, u2 as f64);
                    let malley = |r2: f64, phi: f64| {
                        glam::DVec3::new(
                            a * r2.sqrt() * (2.0 * PI64 * phi).cos(),
                            a * r2.sqrt() * (2.0 * PI64 * phi).sin(),
                            (1.0 - r2).sqrt(),
                        )
                        .normalize()
                        .as_vec3()
                    };
                    let u = Vec2::new(u1, u2);
                    let h = g.sample_vndf_heitz(Vec3::Z, u);
                    assert!(close_vec(h, malley(x1, x2)), "heitz {u}: {h}");
                    assert_eq!(g.sample_m(Vec3::Z, u), h);
                    let c = g.sample_vndf_spherical_cap(Vec3::Z, u);
                    assert!(close_vec(c, malley(x2, x1)), "cap {u}: {c}");
                    let slopes = glam::DVec3::new(
                        -a * erf_inv(2.0 * x1 - 1.0),
                        -a * erf_inv(2.0 * x2 - 1.0),
                        1.0,
                    );
                    let s = b.sample_vndf_beckmann(Vec3::Z, u);
                    assert!(
                        close_vec(s, slopes.normalize().as_vec3()),
                        "beckmann {u}: {s}"
                    );
                    assert_eq!(b.sample_m(Vec3::Z, u), s);
                }
            }
        }
    }

    #[test]
    fn heitz_and_beckmann_samplers_turn_with_the_direction() {
        // Both build their frame from ω's azimuth: rotating ω about z rotates every
        // sample (same u) by the same angle.
        let rot = glam::Quat::from_rotation_z(1.3);
        for mf in [ggx(0.45), beckmann(0.45)] {
            for th in [0.4f64, 1.2] {
                let w = dir(th, 0.0);
                let wr = dir(th, 1.3);
                for u1 in US {
                    for u2 in US {
                        let u = Vec2::new(u1, u2);
                        let (m, mr) = (mf.sample_m(w, u), mf.sample_m(wr, u));
                        assert!(
                            (rot * m - mr).abs().max_element() < 1e-5,
                            "{:?} θ {th} {u}: {m} {mr}",
                            mf.distribution
                        );
                        // A sampled normal is visible and has positive density.
                        assert!(w.dot(m) > 0.0 && mf.pdf_m(w, m) > 0.0);
                    }
                }
            }
        }
    }

    #[test]
    fn beckmann_slopes_invert_the_visible_slope_cdf() {
        // The x slope of a visible Beckmann (α = 1) normal for cos θ has density
        // ∝ (1 − x tan θ)⁺ e^{−x²} (Heitz & d'Eon 2014, eq. 17): its CDF by quadrature
        // at the sampled slope must return u (the inversion promises 1e-10 in the CDF).
        for cos in [0.95f64, 0.6, 0.2, 0.02] {
            let tan = (1.0 - cos * cos).sqrt() / cos;
            let density = |x: f64| (1.0 - x * tan).max(0.0) * (-x * x).exp();
            let cut = 1.0 / tan;
            let total = adaptive(density, -9.0, cut, 1e-14, 1e-17);
            for u in [0.001f64, 0.03, 0.3, 0.5, 0.77, 0.97, 0.999] {
                let (x, y) = beckmann_sample11(cos, u, 0.8);
                let cdf = adaptive(density, -9.0, x, 1e-14, 1e-17) / total;
                assert!((cdf - u).abs() < 1e-10, "cos {cos} u {u}: F(x) = {cdf}");
                assert!((y - erf_inv(0.6)).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn sampled_normals_have_the_moments_of_their_density() {
        // Mean of m.x, m.y, m.z over N samples of each sampler vs its quadrature
        // ∫ m D_ω(m) dm, as z tests: 3 samplers × 2 directions × 3 components = 18
        // tests at family-wise α = 1e-4 (Šidák, |z| ≤ 4.54), seed LIGHTPROOF_SEED.
        use crate::sampling::Sampler;
        use crate::stats::{Accumulator, MeanTest};
        let seed = crate::case::env_count("LIGHTPROOF_SEED", 0)
            .unwrap_or_else(|e| panic!("{e}"))
            .unwrap_or(13);
        let n = 1u64 << 15;
        let test = MeanTest::new(1e-4, 18);
        type Draw = fn(&Microfacet, Vec3, Vec2) -> Vec3;
        let samplers: [(Microfacet, Draw); 3] = [
            (ggx(0.5), Microfacet::sample_vndf_heitz),
            (ggx(0.5), Microfacet::sample_vndf_spherical_cap),
            (beckmann(0.5), Microfacet::sample_vndf_beckmann),
        ];
        for (k, (mf, sample)) in samplers.iter().enumerate() {
            for w in [dir(0.9, 0.6), dir(1.35, -2.0)] {
                let stream = Sampler::independent(seed ^ k as u64);
                let mut acc = [Accumulator::new(), Accumulator::new(), Accumulator::new()];
                for i in 0..n {
                    let m = sample(mf, w, stream.stream(i).next_2d());
                    for (c, a) in acc.iter_mut().enumerate() {
                        a.push(m[c] as f64);
                    }
                }
                for (c, a) in acc.iter().enumerate() {
                    let mu = hemisphere(|m| (m[c] * mf.d_visible(w, m)) as f64);
                    let v = test.judge(a, mu);
                    assert!(v.passed, "sampler {k} ω {w} component {c}: {v:?}");
                    // The test sees a bias of 0.02 in a mean of a unit vector's component.
                    assert!(v.detectable_bias < 0.02, "{}", v.detectable_bias);
                }
            }
        }
    }
}
