//! Oren–Nayar rough diffuse reflection in **Fujii's improved form** ("FON": Y. Fujii,
//! "A tiny improvement of Oren-Nayar reflectance model", 2012; the base of the EON
//! model of Portsmouth, Kutz & Hill 2024 used by OpenPBR):
//!
//! f = ρ/π (A + B s/t),  A = 1/(1 + (π/2 − 2/3) σ),  B = σ A,
//! s = ωi·ωo − cos θi cos θo,  t = 1 if s ≤ 0 else max(cos θi, cos θo),
//!
//! with the roughness σ ∈ [0, 1] (σ = 0 is Lambertian). Symmetric in (ωi, ωo), hence
//! reciprocal; its directional albedo is below ρ (it loses energy, 6–35% at σ = 0.1–1)
//! and has a closed form, ρ[A + (2B/π) sin θo (K(cos θo) − 1/3)] (the oracle crate's
//! `oren_nayar` module), which the contract suite and the catalog check.
//!
//! The classic "qualitative" model (Oren & Nayar 1994, eq. 30; pbrt-v3 §8.4.2) is
//! [`super::oren_nayar_classic`]: with ρ = 1 its albedo exceeds 1 at grazing incidence
//! for small σ (ρ(A + B/2) = 1.0078 at σ = 0.1), and its sampling weight grows like
//! tan β. FON's weight ρ(A + B s/t) stays bounded by ρ(A + B/cos θo).
//!
//! Sampled by the cosine-weighted hemisphere: weight = π f. Two-sided like
//! [`super::Lambertian`].

use super::{BsdfModel, BsdfSample, LobeFlags, ParamError, check_range};
use super::{Index, ModelFacts};
use super::{flip_z, to_upper};
use crate::math::INV_PI;
use crate::sampling::hemisphere::cosine_hemisphere;
use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};
use std::f32::consts::FRAC_PI_2;

/// Oren–Nayar reflector.
///
/// JSON: `{"type": "oren_nayar", "albedo": 0.8, "sigma": 0.35}`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OrenNayar {
    /// Albedo ρ ∈ [0, 1].
    #[serde(deserialize_with = "crate::error::json_f32::scalar")]
    pub albedo: f32,
    /// Fujii's roughness σ ∈ [0, 1].
    #[serde(deserialize_with = "crate::error::json_f32::scalar")]
    pub sigma: f32,
}

impl OrenNayar {
    /// An Oren–Nayar reflector.
    pub fn new(albedo: f32, sigma: f32) -> Self {
        OrenNayar { albedo, sigma }
    }

    /// Parameter check.
    pub fn validate(&self) -> Result<(), ParamError> {
        check_range("albedo", self.albedo, 0.0, 1.0)?;
        check_range("sigma", self.sigma, 0.0, 1.0)
    }

    #[inline]
    fn ab(&self) -> (f32, f32) {
        let a = 1.0 / (1.0 + (FRAC_PI_2 - 2.0 / 3.0) * self.sigma);
        (a, self.sigma * a)
    }

    /// π f / ρ = A + B s/t for two directions above the surface.
    #[inline]
    fn shape(&self, wo: Vec3, wi: Vec3) -> f32 {
        let (a, b) = self.ab();
        // s = ωi·ωo − cos θi cos θo: the tangential part of the dot product.
        let s = wo.x * wi.x + wo.y * wi.y;
        let v = if s <= 0.0 {
            a + b * s
        } else {
            a + b * s / wo.z.max(wi.z)
        };
        if v.is_finite() { v.max(0.0) } else { a }
    }
}

impl BsdfModel for OrenNayar {
    fn eval(&self, wo: Vec3, wi: Vec3) -> f32 {
        shaped_eval(self.albedo, wo, wi, |o, i| self.shape(o, i))
    }

    fn sample(&self, wo: Vec3, u: Vec3) -> Option<BsdfSample> {
        shaped_sample(self.albedo, wo, u, |o, i| self.shape(o, i))
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        shaped_pdf(wo, wi)
    }

    fn flags(&self) -> LobeFlags {
        LobeFlags::REFLECTION | LobeFlags::DIFFUSE
    }
}

/// f = (ρ/π)·s(ωo, ωi) of a reflective lobe with shape factor `shape`, evaluated in the
/// upper hemisphere (both Oren–Nayar forms share everything but s).
pub(super) fn shaped_eval(
    albedo: f32,
    wo: Vec3,
    wi: Vec3,
    shape: impl Fn(Vec3, Vec3) -> f32,
) -> f32 {
    let (wo, wi) = to_upper(wo, wi);
    if !(wo.z > 0.0 && wi.z > 0.0) {
        return 0.0;
    }
    albedo * INV_PI * shape(wo, wi)
}

/// Cosine sampling of that lobe: weight f·cos θi/pdf = ρ·s(ωo, ωi).
pub(super) fn shaped_sample(
    albedo: f32,
    wo: Vec3,
    u: Vec3,
    shape: impl Fn(Vec3, Vec3) -> f32,
) -> Option<BsdfSample> {
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
    let weight = albedo * shape(wo, wi);
    let wi = if flip { flip_z(wi) } else { wi };
    Some(BsdfSample {
        wi,
        weight,
        pdf,
        lobe: LobeFlags::REFLECTION | LobeFlags::DIFFUSE,
        eta: 1.0,
    })
}

/// The cosine density of that lobe (upper hemisphere of ωo).
pub(super) fn shaped_pdf(wo: Vec3, wi: Vec3) -> f32 {
    let (wo, wi) = to_upper(wo, wi);
    if !(wo.z > 0.0 && wi.z > 0.0) {
        return 0.0;
    }
    wi.z * INV_PI
}

/// Reflects only; black at ρ = 0.
impl ModelFacts for OrenNayar {
    fn eta_inside(&self) -> f32 {
        1.0
    }
    fn is_black(&self) -> bool {
        self.albedo <= 0.0
    }
    fn index(&mut self) -> Index<'_> {
        Index::Fixed
    }
}
