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
//!
//! **Fresnel off** (`"fresnel": "none"`, Mitsuba's `material = "none"`): F ≡ 1, a
//! perfectly reflecting microsurface, so the albedo is the single-scattering
//! masking–shadowing loss alone (the "weak white furnace", Heitz 2014 §6; references in
//! the oracle crate's `microfacet` module). Then `eta` and `k` are not given.

use super::conductor::validate_complex_ior;
use super::fresnel::{fr_conductor_cs, reflect};
use super::microfacet::{Distribution, MAX_ALPHA, MIN_ALPHA, Masking, Microfacet};
use super::{BsdfModel, BsdfSample, LobeFlags, ParamError, check_range, flip_z, to_upper};
use super::{Index, ModelFacts};
use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};

/// The Fresnel factor of a rough conductor (JSON `"conductor"` or `"none"`; any other
/// value is an error naming the `fresnel` field).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FresnelMode {
    /// The conductor Fresnel reflectance of η + ik (`eta` and `k` required).
    #[default]
    Conductor,
    /// F ≡ 1: a perfect reflector (`eta` and `k` must be absent).
    None,
}

impl<'de> Deserialize<'de> for FresnelMode {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let v = serde_json::Value::deserialize(d)?;
        match v.as_str() {
            Some("conductor") => Ok(FresnelMode::Conductor),
            Some("none") => Ok(FresnelMode::None),
            _ => Err(serde::de::Error::custom(format!(
                "`fresnel` must be \"conductor\" or \"none\" (F ≡ 1), got {v}"
            ))),
        }
    }
}

/// A rough conductor.
///
/// JSON: `{"type": "rough_conductor", "alpha": 0.3, "eta": 0.2, "k": 3.9,
/// "distribution": "ggx", "masking": "height_correlated"}` (`distribution`:
/// `ggx` | `beckmann`, default `ggx`; `masking`: `height_correlated` | `uncorrelated`,
/// default `height_correlated`), or with F ≡ 1:
/// `{"type": "rough_conductor", "alpha": 0.3, "fresnel": "none"}`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RoughConductor {
    /// Roughness α ∈ [1e-4, 1].
    #[serde(deserialize_with = "crate::error::json_f32::scalar")]
    pub alpha: f32,
    /// Real part η of the relative index (> 0); required unless `fresnel` is `none`.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "crate::error::json_f32::optional"
    )]
    pub eta: Option<f32>,
    /// Extinction coefficient k (≥ 0); required unless `fresnel` is `none`.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "crate::error::json_f32::optional"
    )]
    pub k: Option<f32>,
    /// The Fresnel factor (default `conductor`).
    #[serde(default)]
    pub fresnel: FresnelMode,
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
            eta: Some(eta),
            k: Some(k),
            fresnel: FresnelMode::Conductor,
            distribution: Distribution::Ggx,
            masking: Masking::HeightCorrelated,
        }
    }

    /// A GGX height-correlated rough mirror with F ≡ 1 (`"fresnel": "none"`).
    pub fn white(alpha: f32) -> Self {
        RoughConductor {
            eta: None,
            k: None,
            fresnel: FresnelMode::None,
            ..RoughConductor::new(alpha, 1.0, 0.0)
        }
    }

    /// Parameter check: α ∈ [1e-4, 1]; with the conductor Fresnel η ∈ [1e-3, 100] and
    /// k ∈ [0, 100] both given; with `fresnel: none` neither.
    pub fn validate(&self) -> Result<(), ParamError> {
        check_range("alpha", self.alpha, MIN_ALPHA, MAX_ALPHA)?;
        match (self.fresnel, self.eta, self.k) {
            (FresnelMode::Conductor, Some(eta), Some(k)) => validate_complex_ior(eta, k),
            (FresnelMode::Conductor, None, _) => Err(ParamError::new(
                "eta",
                "is required (or `\"fresnel\": \"none\"` for F ≡ 1)",
            )),
            (FresnelMode::Conductor, Some(_), None) => Err(ParamError::new(
                "k",
                "is required (or `\"fresnel\": \"none\"` for F ≡ 1)",
            )),
            (FresnelMode::None, None, None) => Ok(()),
            (FresnelMode::None, Some(_), _) => Err(ParamError::new(
                "eta",
                "must be absent with `\"fresnel\": \"none\"` (F ≡ 1)",
            )),
            (FresnelMode::None, None, Some(_)) => Err(ParamError::new(
                "k",
                "must be absent with `\"fresnel\": \"none\"` (F ≡ 1)",
            )),
        }
    }

    /// F(cos θ) at a microfacet: the conductor's, or 1 with `fresnel: none` (also for an
    /// unvalidated conductor lacking η or k, which `validate` rejects).
    #[inline]
    pub fn fresnel(&self, cos_theta: f32) -> f32 {
        let c = cos_theta.abs().min(1.0);
        self.fresnel_cs(c, (1.0 - c) * (1.0 + c))
    }

    /// [`Self::fresnel`] at cos θ = `c` ∈ [0, 1] and sin²θ = `s2` ([`fr_conductor_cs`]).
    #[inline]
    pub fn fresnel_cs(&self, c: f32, s2: f32) -> f32 {
        match (self.fresnel, self.eta, self.k) {
            (FresnelMode::Conductor, Some(eta), Some(k)) => fr_conductor_cs(c, s2, eta, k),
            (FresnelMode::Conductor, _, _) | (FresnelMode::None, _, _) => 1.0,
        }
    }

    /// F at the microfacet `m` that mirrors `wo` into `wi` (unit vectors, all on m's
    /// side): cos θ and sin²θ are the symmetric means of ⟨ωo, m⟩, ⟨ωi, m⟩ and of |ωo × m|²,
    /// |ωi × m|² (equal but for rounding, so F is reciprocal to the bit). sin²θ is the
    /// cross product's, not 1 − cos²θ: near normal incidence 1 − c² of an `f32` cosine
    /// keeps only its absolute error, ~10⁻⁷. At η = 0.001, k = 0, whose reflectance
    /// climbs to 1 by sin θ = η (total reflection), a lobe of α = 10⁻³ read its albedo
    /// 4·10⁻⁵ off the oracle that way (z = +41 at normal incidence, −86 at 0.1°; session 52's
    /// audit; `fresnel_near_the_normal_takes_the_cross_product_sine`).
    #[inline]
    pub fn fresnel_at(&self, wo: Vec3, wi: Vec3, m: Vec3) -> f32 {
        let c = (0.5 * (wo.dot(m) + wi.dot(m))).clamp(0.0, 1.0);
        let s2 = 0.5 * (wo.cross(m).length_squared() + wi.cross(m).length_squared());
        self.fresnel_cs(c, s2)
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
        let f = mf.d(h) * mf.g2(wo, wi) * self.fresnel_at(wo, wi, h) / (4.0 * (co * ci));
        if f.is_finite() { f } else { 0.0 }
    }

    fn sample(&self, wo: Vec3, u: Vec3) -> Option<BsdfSample> {
        let wo_in = wo;
        // Unit length, so that the mirrored or refracted direction is unit too (and finite:
        // a non-finite or zero ωo becomes 0, which the side test below rejects).
        let wo = wo.normalize_or_zero();
        let flip = wo.z < 0.0;
        let wo = if flip { flip_z(wo) } else { wo };
        if !(wo.z > 0.0) {
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
        let weight = self.fresnel_at(wo, wi, m) * mf.g2(wo, wi) / mf.g1(wo);
        if !weight.is_finite() {
            return None;
        }
        // The density MIS sees is `pdf` at the given ωo and the returned f32 direction,
        // whose half vector differs from m by rounding (at α = 10⁻⁴ one ulp moves D by up
        // to 87% near grazing): next-event estimation evaluates that same function, so
        // the two strategies' weights sum to 1.
        let wi = if flip { flip_z(wi) } else { wi };
        let pdf = self.pdf(wo_in, wi);
        if !(pdf > 0.0) || !pdf.is_finite() {
            return None;
        }
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

/// Reflects only; never called black (F > 0, but F = 0 exactly at the matched index
/// η = 1, k = 0, which is not called black for the reason given at
/// [`super::Conductor`]); with `fresnel: none` it has no index to vary.
impl ModelFacts for RoughConductor {
    fn eta_inside(&self) -> f32 {
        1.0
    }
    fn is_black(&self) -> bool {
        false
    }
    fn index(&mut self) -> Index<'_> {
        match (self.fresnel, &mut self.eta, &mut self.k) {
            (FresnelMode::Conductor, Some(eta), Some(k)) => Index::Conductor(eta, k),
            (FresnelMode::Conductor, _, _) | (FresnelMode::None, _, _) => Index::Fixed,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lobe's F at microfacets within 2·10⁻³ of the normal, for ωo from normal
    /// incidence to 0.1°, against the `f64` Fresnel equations at the exact angle between
    /// the `f32` vectors ωo and m, for η = 0.001, k = 0 (total reflection beyond sin θ =
    /// 0.001, where F is steepest; the angles keep 10⁻⁵ rad from it, where F's slope in
    /// sin²θ is infinite) and a gold-like index: within 10⁻⁶ relative. With sin²θ =
    /// 1 − cos²θ of the `f32` cosine it was off by up to 1.8·10⁻².
    #[test]
    fn fresnel_near_the_normal_takes_the_cross_product_sine() {
        let unit = |theta: f64, phi: f64| {
            let (s, c) = theta.sin_cos();
            glam::DVec3::new(s * phi.cos(), s * phi.sin(), c)
        };
        for (eta, k) in [(0.001f32, 0.0f32), (0.2, 3.9)] {
            let lobe = RoughConductor {
                eta: Some(eta),
                k: Some(k),
                fresnel: FresnelMode::Conductor,
                ..RoughConductor::white(1e-3)
            };
            let mut worst = 0.0f64;
            for theta_o in [0.0, 0.02, 0.05, 0.1] {
                let wo = unit(f64::to_radians(theta_o), 0.3).as_vec3();
                for i in 1..=40 {
                    for phi in [0.0, 1.1, 2.5, 4.0] {
                        let m = unit((i as f64 + 0.37) * 5e-5, phi).as_vec3();
                        let wi = reflect(wo, m);
                        let got = f64::from(lobe.fresnel_at(wo, wi, m));
                        let (o, n) = (wo.as_dvec3().normalize(), m.as_dvec3().normalize());
                        let want = crate::bsdf::fresnel::tests::conductor_f64(
                            o.dot(n),
                            f64::from(eta),
                            f64::from(k),
                        );
                        worst = worst.max((got - want).abs() / want);
                    }
                }
            }
            assert!(worst < 1e-6, "η = {eta}, k = {k}: relative error {worst:e}");
        }
    }

    #[test]
    fn fresnel_none_is_a_perfect_reflector_and_validated() {
        let w = RoughConductor::white(0.3);
        assert_eq!(w.validate(), Ok(()));
        assert_eq!(w.fresnel(0.2), 1.0);
        let c = RoughConductor::new(0.3, 0.2, 3.9);
        assert!(c.fresnel(0.2) < 1.0);
        let json = |s: &str| {
            serde_json::from_str::<RoughConductor>(s)
                .unwrap()
                .validate()
        };
        assert_eq!(json(r#"{"alpha": 0.3, "fresnel": "none"}"#), Ok(()));
        for (text, field) in [
            (r#"{"alpha": 0.3, "eta": 1.5, "fresnel": "none"}"#, "eta"),
            (r#"{"alpha": 0.3, "k": 1, "fresnel": "none"}"#, "k"),
            (r#"{"alpha": 0.3, "k": 1}"#, "eta"),
            (r#"{"alpha": 0.3, "eta": 1}"#, "k"),
        ] {
            let e = json(text).unwrap_err();
            assert_eq!(e.field, field, "{text}: {e}");
        }
        let e = serde_json::from_str::<RoughConductor>(r#"{"alpha": 0.3, "fresnel": "off"}"#);
        assert!(e.unwrap_err().to_string().contains("`fresnel`"));
        let back: RoughConductor =
            serde_json::from_str(&serde_json::to_string(&w).unwrap()).unwrap();
        assert_eq!(back, w);
        let mut w = w;
        assert_eq!(w.index(), Index::Fixed);
        let mut c = c;
        assert!(matches!(c.index(), Index::Conductor(..)));
    }
}
