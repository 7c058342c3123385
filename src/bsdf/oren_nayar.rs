//! Oren–Nayar rough diffuse reflection, the **qualitative model** of Oren & Nayar 1994
//! ("Generalization of Lambert's Reflectance Model", eq. 30, without the
//! inter-reflection term), as in pbrt-v3 §8.4.2, with σ in radians:
//!
//! f = ρ/π (A + B max(0, cos(φi − φo)) sin α tan β),
//! A = 1 − σ²/(2(σ² + 0.33)), B = 0.45 σ²/(σ² + 0.09), α = max(θi, θo), β = min(θi, θo).
//!
//! σ = 0 is Lambertian. The model is symmetric in (ωi, ωo), hence reciprocal; it does
//! not promise an albedo (it loses some energy and, being an approximation, the
//! contract checks only albedo ≤ 1). Sampled by the cosine-weighted hemisphere:
//! weight = π f = ρ (A + B …), bounded by ρ (A + B tan θo). Two-sided like
//! [`super::Lambertian`].

use super::rough_conductor::flip_z;
use super::{BsdfModel, BsdfSample, LobeFlags, check_range};
use crate::math::INV_PI;
use std::f32::consts::FRAC_PI_2;
use crate::sampling::hemisphere::cosine_hemisphere;
use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};

/// Oren–Nayar reflector.
///
/// JSON: `{"type": "oren_nayar", "albedo": 0.8, "sigma": 0.35}`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OrenNayar {
    /// Albedo ρ ∈ [0, 1].
    pub albedo: f32,
    /// Standard deviation σ of the facet slope angle, radians, ∈ [0, π/2].
    pub sigma: f32,
}

impl OrenNayar {
    /// An Oren–Nayar reflector.
    pub fn new(albedo: f32, sigma: f32) -> Self {
        OrenNayar { albedo, sigma }
    }

    /// Parameter check.
    pub fn validate(&self) -> Result<(), String> {
        check_range("albedo", self.albedo, 0.0, 1.0)?;
        check_range("sigma", self.sigma, 0.0, FRAC_PI_2)
    }

    #[inline]
    fn ab(&self) -> (f32, f32) {
        let s2 = self.sigma * self.sigma;
        (1.0 - s2 / (2.0 * (s2 + 0.33)), 0.45 * s2 / (s2 + 0.09))
    }

    /// π f / ρ for two directions above the surface.
    #[inline]
    fn shape(&self, wo: Vec3, wi: Vec3) -> f32 {
        let (a, b) = self.ab();
        let so = (wo.x * wo.x + wo.y * wo.y).sqrt();
        let si = (wi.x * wi.x + wi.y * wi.y).sqrt();
        if !(so > 1e-7 && si > 1e-7) {
            return a;
        }
        let cos_dphi = ((wo.x * wi.x + wo.y * wi.y) / (so * si)).clamp(-1.0, 1.0).max(0.0);
        // α = max θ, β = min θ: sin α tan β.
        let (sin_alpha, tan_beta) = if wi.z.abs() > wo.z.abs() { (so, si / wi.z.abs()) } else { (si, so / wo.z.abs()) };
        let v = a + b * cos_dphi * sin_alpha * tan_beta;
        if v.is_finite() { v } else { a }
    }
}

impl BsdfModel for OrenNayar {
    fn eval(&self, wo: Vec3, wi: Vec3) -> f32 {
        let (wo, wi) = if wo.z < 0.0 { (flip_z(wo), flip_z(wi)) } else { (wo, wi) };
        if !(wo.z > 0.0 && wi.z > 0.0) {
            return 0.0;
        }
        self.albedo * INV_PI * self.shape(wo, wi)
    }

    fn sample(&self, wo: Vec3, u: Vec3) -> Option<BsdfSample> {
        let flip = wo.z < 0.0;
        let wo = if flip { flip_z(wo) } else { wo };
        if !(wo.z > 0.0) || !wo.is_finite() {
            return None;
        }
        let wi = cosine_hemisphere(Vec2::new(u.x, u.y));
        let pdf = wi.z * INV_PI;
        if !(pdf > 0.0) {
            return None;
        }
        let weight = self.albedo * self.shape(wo, wi);
        let wi = if flip { flip_z(wi) } else { wi };
        Some(BsdfSample { wi, weight, pdf, lobe: LobeFlags::REFLECTION | LobeFlags::DIFFUSE, eta: 1.0 })
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let (wo, wi) = if wo.z < 0.0 { (flip_z(wo), flip_z(wi)) } else { (wo, wi) };
        if !(wo.z > 0.0 && wi.z > 0.0) {
            return 0.0;
        }
        wi.z * INV_PI
    }

    fn flags(&self) -> LobeFlags {
        LobeFlags::REFLECTION | LobeFlags::DIFFUSE
    }
}
