//! Lambertian (ideal diffuse) reflection: f = ρ/π for wo and wi on the same side,
//! sampled by the cosine-weighted hemisphere so the weight is exactly ρ
//! (Lambert 1760; pbrt-v4 §9.2). Directional albedo ∫ f cos θi dωi = ρ for every wo.

use super::{BsdfModel, BsdfSample, LobeFlags, ParamError, check_range, same_hemisphere};
use super::{Index, ModelFacts};
use crate::math::INV_PI;
use crate::sampling::hemisphere::{cosine_hemisphere, cosine_hemisphere_pdf};
use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};

/// Ideal diffuse reflector of albedo ρ ∈ [0, 1].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Lambertian {
    /// Albedo ρ.
    #[serde(deserialize_with = "crate::error::json_f32::scalar")]
    pub albedo: f32,
}

impl Lambertian {
    /// A Lambertian reflector of albedo ρ.
    pub fn new(albedo: f32) -> Self {
        Lambertian { albedo }
    }

    /// Parameter check.
    pub fn validate(&self) -> Result<(), ParamError> {
        check_range("albedo", self.albedo, 0.0, 1.0)
    }
}

impl BsdfModel for Lambertian {
    fn eval(&self, wo: Vec3, wi: Vec3) -> f32 {
        if same_hemisphere(wo, wi) {
            self.albedo * INV_PI
        } else {
            0.0
        }
    }

    fn sample(&self, wo: Vec3, u: Vec3) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let mut wi = cosine_hemisphere(Vec2::new(u.x, u.y));
        if wo.z < 0.0 {
            wi.z = -wi.z;
        }
        let pdf = cosine_hemisphere_pdf(Vec3::new(wi.x, wi.y, wi.z.abs()));
        if pdf <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi,
            weight: self.albedo,
            pdf,
            lobe: LobeFlags::REFLECTION | LobeFlags::DIFFUSE,
            eta: 1.0,
        })
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if same_hemisphere(wo, wi) {
            wi.z.abs() * INV_PI
        } else {
            0.0
        }
    }

    fn flags(&self) -> LobeFlags {
        LobeFlags::REFLECTION | LobeFlags::DIFFUSE
    }
}

/// Reflects only; black at ρ = 0.
impl ModelFacts for Lambertian {
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
