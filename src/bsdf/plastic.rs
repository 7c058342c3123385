//! Two-layer plastic: a Lambertian base of albedo ρ under a smooth dielectric coat of
//! relative index η (the "smooth plastic" of Weidlich & Wilkie 2007 and Mitsuba's
//! `plastic`, with the internal diffuse inter-reflection summed in closed form).
//!
//! Light reaching the base has crossed the coat with transmittance 1 − F(θi); the base
//! radiance bounces between the base and the coat's underside, which reflects a
//! fraction F_dr,int of diffuse light (the hemispherical average of the internal
//! Fresnel reflectance, [`fresnel_diffuse_reflectance`] at 1/η), giving the geometric
//! series 1/(1 − ρ F_dr,int); leaving, radiance is scaled by (1 − F(θo))/η². So
//!
//! - specular coat: f_s = F(θo) δ(ωi − M(ωo))/|cos θi|,
//! - diffuse: f_d = (1 − F(θi))(1 − F(θo)) ρ / (π η² (1 − ρ F_dr,int)).
//!
//! Using the étendue identity η²(1 − F_dr,int) = 1 − F_dr,ext, the directional albedo
//! is exactly **A(θo) = F(θo) + (1 − F(θo)) ρ (1 − F_dr,int)/(1 − ρ F_dr,int)** ≤ 1, the
//! reflectance this model promises ([`Plastic::albedo_at`]) and that the contract tests.
//!
//! Sampling picks the coat with probability P_s = F/(F + (1 − F) a),
//! a = ρ(1 − F_dr,int)/(1 − ρ F_dr,int) (the two lobes' albedos), else the base by the
//! cosine-weighted hemisphere. `pdf` is (1 − P_s) cos θi/π, the density of the
//! non-delta part. Two-sided (the coat faces the viewer); η ≥ 1 (a coat no denser than
//! the air above it has no meaning here).

use super::fresnel::{fr_dielectric, fresnel_diffuse_reflectance};
use super::{BsdfModel, BsdfSample, LobeFlags, ParamError, check_range};
use super::{Index, ModelFacts};
use super::{flip_z, to_upper};
use crate::math::{INV_PI, PI};
use crate::sampling::hemisphere::cosine_hemisphere;
use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};

/// The JSON form of [`Plastic`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlasticParams {
    /// Base albedo ρ ∈ [0, 1].
    #[serde(deserialize_with = "crate::error::json_f32::scalar")]
    pub albedo: f32,
    /// Coat index η ∈ [1, 10] relative to the outside.
    #[serde(deserialize_with = "crate::error::json_f32::scalar")]
    pub eta: f32,
}

/// A diffuse base under a smooth dielectric coat.
///
/// JSON: `{"type": "plastic", "albedo": 0.5, "eta": 1.5}`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(from = "PlasticParams", into = "PlasticParams")]
pub struct Plastic {
    /// Base albedo ρ.
    pub albedo: f32,
    /// Coat index η.
    pub eta: f32,
    /// F_dr,int: hemispherical internal reflectance of the coat (cached).
    fdr_int: f32,
}

impl From<PlasticParams> for Plastic {
    fn from(p: PlasticParams) -> Self {
        Plastic::new(p.albedo, p.eta)
    }
}

impl From<Plastic> for PlasticParams {
    fn from(p: Plastic) -> Self {
        PlasticParams {
            albedo: p.albedo,
            eta: p.eta,
        }
    }
}

impl Plastic {
    /// A plastic of base albedo ρ and coat index η (F_dr,int computed here, once).
    pub fn new(albedo: f32, eta: f32) -> Self {
        let fdr_int = if eta.is_finite() && (1.0..=10.0).contains(&eta) {
            fresnel_diffuse_reflectance(1.0 / eta as f64) as f32
        } else {
            0.0
        };
        Plastic {
            albedo,
            eta,
            fdr_int,
        }
    }

    /// Parameter check: ρ ∈ [0, 1], η ∈ [1, 10].
    pub fn validate(&self) -> Result<(), ParamError> {
        check_range("albedo", self.albedo, 0.0, 1.0)?;
        check_range("eta", self.eta, 1.0, 10.0)
    }

    /// F_dr,int of the coat.
    pub fn internal_diffuse_reflectance(&self) -> f32 {
        self.fdr_int
    }

    /// Albedo a = ρ(1 − F_dr,int)/(1 − ρ F_dr,int) of the base seen through the coat,
    /// per unit of light transmitted at the top.
    #[inline]
    fn base_albedo(&self) -> f32 {
        let rho = self.albedo.clamp(0.0, 1.0);
        let d = 1.0 - rho * self.fdr_int;
        if d > 0.0 {
            rho * (1.0 - self.fdr_int) / d
        } else {
            0.0
        }
    }

    /// The promised directional albedo A(θo) = F + (1 − F) a.
    pub fn albedo_at(&self, cos_o: f32) -> f32 {
        let f = fr_dielectric(cos_o.abs(), self.eta);
        f + (1.0 - f) * self.base_albedo()
    }

    #[inline]
    fn specular_probability(&self, fo: f32) -> f32 {
        let s = fo + (1.0 - fo) * self.base_albedo();
        if s > 0.0 {
            (fo / s).clamp(0.0, 1.0)
        } else {
            0.0
        }
    }

    #[inline]
    fn diffuse(&self, co: f32, ci: f32) -> f32 {
        let fo = fr_dielectric(co, self.eta);
        let fi = fr_dielectric(ci, self.eta);
        let rho = self.albedo.clamp(0.0, 1.0);
        let d = PI * self.eta * self.eta * (1.0 - rho * self.fdr_int);
        let v = (1.0 - fi) * (1.0 - fo) * rho / d;
        if v.is_finite() && v > 0.0 { v } else { 0.0 }
    }
}

impl BsdfModel for Plastic {
    fn eval(&self, wo: Vec3, wi: Vec3) -> f32 {
        let (wo, wi) = to_upper(wo, wi);
        if !(wo.z > 0.0 && wi.z > 0.0) {
            return 0.0;
        }
        self.diffuse(wo.z, wi.z)
    }

    fn sample(&self, wo: Vec3, u: Vec3) -> Option<BsdfSample> {
        // Unit length, so that the mirrored or refracted direction is unit too.
        let wo = wo.normalize_or_zero();
        let flip = wo.z < 0.0;
        let wo = if flip { flip_z(wo) } else { wo };
        if !(wo.z > 0.0) || !wo.is_finite() {
            return None;
        }
        let fo = fr_dielectric(wo.z, self.eta);
        let ps = self.specular_probability(fo);
        let s = if u.z < ps {
            let wi = Vec3::new(-wo.x, -wo.y, wo.z);
            BsdfSample {
                wi,
                weight: fo / ps,
                pdf: ps,
                lobe: LobeFlags::REFLECTION | LobeFlags::SPECULAR,
                eta: 1.0,
            }
        } else {
            let wi = cosine_hemisphere(Vec2::new(u.x, u.y));
            let pd = 1.0 - ps;
            let pdf = pd * wi.z * INV_PI;
            if !(pdf > 0.0) {
                return None;
            }
            let weight = self.diffuse(wo.z, wi.z) * PI / pd;
            BsdfSample {
                wi,
                weight,
                pdf,
                lobe: LobeFlags::REFLECTION | LobeFlags::DIFFUSE,
                eta: 1.0,
            }
        };
        if !s.weight.is_finite() {
            return None;
        }
        Some(if flip {
            BsdfSample {
                wi: flip_z(s.wi),
                ..s
            }
        } else {
            s
        })
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let (wo, wi) = to_upper(wo, wi);
        if !(wo.z > 0.0 && wi.z > 0.0) {
            return 0.0;
        }
        let ps = self.specular_probability(fr_dielectric(wo.z, self.eta));
        (1.0 - ps) * wi.z * INV_PI
    }

    fn flags(&self) -> LobeFlags {
        LobeFlags::REFLECTION | LobeFlags::SPECULAR | LobeFlags::DIFFUSE
    }
}

/// Reflects only (the coat and base are one surface); its coat index is fixed. Black
/// exactly when ρ = 0 and η = 1: otherwise the coat reflects F > 0 even at ρ = 0, or the
/// base shows through; at η = 1 the coat's F is 0 exactly (cos θt = cos θi to the bit:
/// cos²θt = (0·sin²θi + cos²θi)/1, for cos θi ≥ 1.1·10⁻¹⁹, where cos²θi is a normal
/// `f32`; below, within 10⁻¹⁷° of grazing, cos²θi is subnormal and F rounds to up to 0.03,
/// and to 1 where it underflows to 0, cos θi < 2.7·10⁻²³: directions of less than
/// 10⁻³⁷ sr of projected solid angle (π cos²θi), which pruning the model ignores).
impl ModelFacts for Plastic {
    fn eta_inside(&self) -> f32 {
        1.0
    }
    fn is_black(&self) -> bool {
        self.albedo == 0.0 && self.eta == 1.0
    }
    fn index(&mut self) -> Index<'_> {
        Index::Fixed
    }
}
