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
    if c2 > 0.0 { s2 / c2 } else { f32::INFINITY }
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
        if !(m.z > 0.0) {
            return 0.0;
        }
        let a = self.alpha;
        let a2 = a * a;
        match self.distribution {
            Distribution::Ggx => {
                let den = m.x * m.x + m.y * m.y + a2 * m.z * m.z;
                let v = a2 / (PI * den * den);
                if v.is_finite() { v } else { 0.0 }
            }
            Distribution::Beckmann => {
                let e = tan2_theta(m) / a2;
                if !(e < 80.0) {
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
        let t2 = tan2_theta(w);
        if !t2.is_finite() {
            return f32::INFINITY;
        }
        match self.distribution {
            Distribution::Ggx => {
                let x = self.alpha * self.alpha * t2;
                if !x.is_finite() {
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
                l.max(0.0) as f32
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
        if !(w.z > 0.0) || !(c > 0.0) {
            return 0.0;
        }
        let v = self.g1(w) * c * self.d(m) / w.z;
        if v.is_finite() { v } else { 0.0 }
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
}
