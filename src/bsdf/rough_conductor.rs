//! Rough conductor: the Cook–Torrance microfacet reflection model with a conductor
//! Fresnel factor (Cook & Torrance 1982; Walter et al. 2007, eq. 20; pbrt-v4 §9.6):
//!
//! f(ωi → ωo) = D(h) G2(ωo, ωi) F(ωo·h) / (4 cos θo cos θi),  h = (ωo + ωi)/‖ωo + ωi‖,
//!
//! with D, G2 from [`Microfacet`] (GGX or Beckmann; height-correlated or uncorrelated
//! Smith masking). Sampling draws a visible normal m ~ D_ωo (Heitz 2018 for GGX,
//! Heitz & d'Eon 2014 for Beckmann) and reflects ωo about it; the reflection Jacobian
//! |dωh/dωi| = 1/(4 ωo·h) gives pdf(ωi) = D_ωo(h)/(4 ωo·h), and the weight simplifies
//! to F(ωo·m) G2(ωo, ωi)/G1(ωo) ≤ 1 (computed in that form, not as eval·cos/pdf, so
//! the contract's consistency check compares two independent computations).
//! Two-sided: for ωo below the surface the model is mirrored through the tangent plane.

use super::conductor::validate_complex_ior;
use super::fresnel::{fr_conductor, reflect};
use super::microfacet::{Distribution, MAX_ALPHA, MIN_ALPHA, Masking, Microfacet};
use super::{BsdfModel, BsdfSample, LobeFlags, check_range, flip_z, to_upper};
use super::{Index, ModelFacts};
use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};

/// A rough conductor.
///
/// JSON: `{"type": "rough_conductor", "alpha": 0.3, "eta": 0.2, "k": 3.9,
/// "distribution": "ggx", "masking": "height_correlated"}` (`distribution`:
/// `ggx` | `beckmann`, default `ggx`; `masking`: `height_correlated` | `uncorrelated`,
/// default `height_correlated`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RoughConductor {
    /// Roughness α ∈ [1e-4, 1].
    pub alpha: f32,
    /// Real part η of the relative index (> 0).
    pub eta: f32,
    /// Extinction coefficient k (≥ 0).
    pub k: f32,
    /// Normal distribution.
    #[serde(default)]
    pub distribution: Distribution,
    /// Masking–shadowing form.
    #[serde(default)]
    pub masking: Masking,
}

impl RoughConductor {
    /// A GGX rough conductor with height-correlated masking.
    pub fn new(alpha: f32, eta: f32, k: f32) -> Self {
        RoughConductor {
            alpha,
            eta,
            k,
            distribution: Distribution::Ggx,
            masking: Masking::HeightCorrelated,
        }
    }

    /// Parameter check: α ∈ [1e-4, 1], η ∈ [1e-3, 100], k ∈ [0, 100].
    pub fn validate(&self) -> Result<(), String> {
        check_range("alpha", self.alpha, MIN_ALPHA, MAX_ALPHA)?;
        validate_complex_ior(self.eta, self.k)
    }

    /// The microfacet distribution.
    #[inline]
    pub fn microfacet(&self) -> Microfacet {
        Microfacet::new(self.distribution, self.alpha, self.masking)
    }
}

impl BsdfModel for RoughConductor {
    fn eval(&self, wo: Vec3, wi: Vec3) -> f32 {
        let (wo, wi) = to_upper(wo, wi);
        let (co, ci) = (wo.z, wi.z);
        if !(co > 0.0 && ci > 0.0) {
            return 0.0;
        }
        let h = wo + wi;
        if !(h.length_squared() > 0.0) {
            return 0.0;
        }
        let h = h.normalize();
        let mf = self.microfacet();
        // F at the symmetric mean of ωo·h and ωi·h (equal but for rounding): reciprocal to the bit.
        let c = 0.5 * (wo.dot(h) + wi.dot(h));
        let f = mf.d(h) * mf.g2(wo, wi) * fr_conductor(c, self.eta, self.k) / (4.0 * (co * ci));
        if f.is_finite() { f } else { 0.0 }
    }

    fn sample(&self, wo: Vec3, u: Vec3) -> Option<BsdfSample> {
        // Unit length, so that the mirrored or refracted direction is unit too.
        let wo = wo.normalize_or_zero();
        let flip = wo.z < 0.0;
        let wo = if flip { flip_z(wo) } else { wo };
        if !(wo.z > 0.0) || !wo.is_finite() {
            return None;
        }
        let mf = self.microfacet();
        let m = mf.sample_m(wo, Vec2::new(u.x, u.y));
        let c = wo.dot(m);
        if !(c > 0.0) {
            return None;
        }
        let wi = reflect(wo, m);
        if !(wi.z > 0.0) {
            return None;
        }
        let pdf = mf.pdf_m(wo, m) / (4.0 * c);
        if !(pdf > 0.0) || !pdf.is_finite() {
            return None;
        }
        let weight = fr_conductor(c, self.eta, self.k) * mf.g2(wo, wi) / mf.g1(wo);
        if !weight.is_finite() {
            return None;
        }
        let wi = if flip { flip_z(wi) } else { wi };
        Some(BsdfSample {
            wi,
            weight,
            pdf,
            lobe: LobeFlags::REFLECTION | LobeFlags::GLOSSY,
            eta: 1.0,
        })
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let (wo, wi) = to_upper(wo, wi);
        if !(wo.z > 0.0 && wi.z > 0.0) {
            return 0.0;
        }
        let h = wo + wi;
        if !(h.length_squared() > 0.0) {
            return 0.0;
        }
        let h = h.normalize();
        let p = self.microfacet().pdf_m(wo, h) / (4.0 * wo.dot(h));
        if p.is_finite() && p > 0.0 { p } else { 0.0 }
    }

    fn flags(&self) -> LobeFlags {
        LobeFlags::REFLECTION | LobeFlags::GLOSSY
    }
}

/// Reflects only; never black (F > 0).
impl ModelFacts for RoughConductor {
    fn eta_inside(&self) -> f32 {
        1.0
    }
    fn is_black(&self) -> bool {
        false
    }
    fn index(&mut self) -> Index<'_> {
        Index::Conductor(&mut self.eta, &mut self.k)
    }
}
