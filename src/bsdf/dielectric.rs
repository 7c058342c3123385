//! Smooth dielectric interface: Fresnel-weighted mirror reflection and Snell
//! refraction, with total internal reflection (pbrt-v4 §9.5).
//!
//! **Conventions.** `eta` = η_inside/η_outside, the inside being below the surface
//! (−z). For ωo on side o and ωi on side i, η_o and η_i are the indices there
//! (1 outside, `eta` inside), and the *relative* index of a sample,
//! [`BsdfSample::eta`], is η_i/η_o (1 for reflection), as pbrt-v4's `etap`.
//!
//! **Radiance convention** (pbrt-v4 `TransportMode::Radiance`): radiance crossing into
//! a medium is scaled by (η_o/η_i)² (L/η² is invariant along a ray), so
//!
//! - reflection: f_r = R(cos θo) δ(ωi − M(ωo)) / |cos θi|,
//! - transmission: f_t = (1 − R) (η_o/η_i)² δ(ωi − T(ωo)) / |cos θi|,
//!
//! with R = [`fr_dielectric`] at the outgoing cosine. `sample` picks reflection with
//! probability R (pdf = R or 1 − R, the discrete lobe probability) and returns weight 1
//! for reflection and (η_o/η_i)² = 1/`eta`² for transmission. The *energy* weight
//! weight × (η_i/η_o)² is exactly 1 for both: R + T = 1, tested in
//! `tests/proof/bsdf_contract.rs` together with the reflection fraction against an
//! independent `f64` Fresnel.

use super::fresnel::{fr_dielectric, refract};
use super::{BsdfModel, BsdfSample, LobeFlags, ParamError, check_range};
use super::{Index, ModelFacts};
use glam::Vec3;
use serde::{Deserialize, Serialize};

/// A smooth dielectric boundary.
///
/// JSON: `{"type": "dielectric", "eta": 1.5}`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Dielectric {
    /// η_inside/η_outside (inside = −z).
    #[serde(deserialize_with = "crate::error::json_f32::scalar")]
    pub eta: f32,
}

/// Check a dielectric relative index (shared by the dielectric models).
pub(crate) fn validate_eta(eta: f32) -> Result<(), ParamError> {
    if !eta.is_finite() {
        return Err(ParamError::new(
            "eta",
            format!("must be a finite number, got {eta}"),
        ));
    }
    if eta <= 0.0 {
        return Err(ParamError::new(
            "eta",
            format!("must be positive (η_inside/η_outside), got {eta}"),
        ));
    }
    check_range("eta", eta, 0.01, 100.0)
}

impl Dielectric {
    /// A smooth dielectric of relative index η_inside/η_outside.
    pub fn new(eta: f32) -> Self {
        Dielectric { eta }
    }

    /// Parameter check: η ∈ [0.01, 100].
    pub fn validate(&self) -> Result<(), ParamError> {
        validate_eta(self.eta)
    }
}

impl BsdfModel for Dielectric {
    fn eval(&self, _wo: Vec3, _wi: Vec3) -> f32 {
        0.0
    }

    fn sample(&self, wo: Vec3, u: Vec3) -> Option<BsdfSample> {
        // Unit length, so that the mirrored or refracted direction is unit too.
        let wo = wo.normalize_or_zero();
        if !(wo.z != 0.0) || !wo.is_finite() {
            return None;
        }
        let r = fr_dielectric(wo.z, self.eta);
        let t = 1.0 - r;
        if u.z < r || !(t > 0.0) {
            let wi = Vec3::new(-wo.x, -wo.y, wo.z);
            return Some(BsdfSample {
                wi,
                weight: 1.0,
                pdf: r,
                lobe: LobeFlags::REFLECTION | LobeFlags::SPECULAR,
                eta: 1.0,
            });
        }
        // Relative index of the far side as seen from ωo's side.
        let (n, etap) = if wo.z > 0.0 {
            (Vec3::Z, self.eta)
        } else {
            (-Vec3::Z, 1.0 / self.eta)
        };
        let wi = refract(wo, n, etap)?;
        if !(wi.z * wo.z < 0.0) {
            return None;
        }
        let weight = 1.0 / (etap * etap);
        Some(BsdfSample {
            wi,
            weight,
            pdf: t,
            lobe: LobeFlags::TRANSMISSION | LobeFlags::SPECULAR,
            eta: etap,
        })
    }

    fn pdf(&self, _wo: Vec3, _wi: Vec3) -> f32 {
        0.0
    }

    fn flags(&self) -> LobeFlags {
        LobeFlags::REFLECTION | LobeFlags::TRANSMISSION | LobeFlags::SPECULAR
    }
}

/// Transmits into index η; never black (R + T = 1).
impl ModelFacts for Dielectric {
    fn eta_inside(&self) -> f32 {
        self.eta
    }
    fn is_black(&self) -> bool {
        false
    }
    fn index(&mut self) -> Index<'_> {
        Index::Dielectric(&mut self.eta)
    }
}
