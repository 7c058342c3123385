//! Oren–Nayar rough diffuse reflection in the **classic "qualitative" form** (Oren &
//! Nayar 1994, eq. 30; pbrt-v3 §8.4.2), the form most reference tables use:
//!
//! f = ρ/π (A + B max(0, cos(φi − φo)) sin α tan β),  α = max(θi, θo), β = min(θi, θo),
//! A = 1 − σ²/(2(σ² + 0.33)),  B = 0.45 σ²/(σ² + 0.09),
//!
//! with σ the standard deviation of the facet slope angle **in radians** (pbrt-v3's
//! scene files take degrees and convert). Since sin α tan β = sin θi sin θo /
//! max(cos θi, cos θo), the angular term is B·max(0, s)/max(cos θi, cos θo) with
//! s = ωi·ωo − cos θi cos θo (the tangential dot product): no trigonometry, symmetric in
//! (ωi, ωo), hence reciprocal. It is **not** energy conserving: with ρ = 1 its albedo
//! exceeds 1 at grazing for small σ (ρ(A + B/2) = 1.0078 at σ = 0.1); the closed-form
//! albedo is in the oracle crate's `oren_nayar` module (see [`super::oren_nayar`] for Fujii's
//! energy-conserving form, which this suite keeps as `oren_nayar`).
//!
//! Sampled by the cosine-weighted hemisphere: weight = π f ≤ ρ(A + B/cos θo). Two-sided
//! like [`super::Lambertian`].

use super::oren_nayar::{shaped_eval, shaped_pdf, shaped_sample};
use super::{BsdfModel, BsdfSample, LobeFlags, ParamError, check_range};
use super::{Index, ModelFacts};
use glam::Vec3;
use serde::{Deserialize, Serialize};
use std::f32::consts::FRAC_PI_2;

/// Classic Oren–Nayar reflector.
///
/// JSON: `{"type": "oren_nayar_classic", "albedo": 0.8, "sigma": 0.35}` (σ in radians,
/// in [0, π/2]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OrenNayarClassic {
    /// Albedo ρ ∈ [0, 1].
    #[serde(deserialize_with = "crate::error::json_f32::scalar")]
    pub albedo: f32,
    /// Slope-angle standard deviation σ ∈ [0, π/2] (radians).
    #[serde(deserialize_with = "crate::error::json_f32::scalar")]
    pub sigma: f32,
}

impl OrenNayarClassic {
    /// A classic Oren–Nayar reflector (σ in radians).
    pub fn new(albedo: f32, sigma: f32) -> Self {
        OrenNayarClassic { albedo, sigma }
    }

    /// Parameter check: ρ ∈ [0, 1], σ ∈ [0, π/2].
    pub fn validate(&self) -> Result<(), ParamError> {
        check_range("albedo", self.albedo, 0.0, 1.0)?;
        check_range("sigma", self.sigma, 0.0, FRAC_PI_2)
    }

    /// (A, B) at σ.
    #[inline]
    pub fn ab(&self) -> (f32, f32) {
        let s2 = self.sigma * self.sigma;
        (1.0 - s2 / (2.0 * (s2 + 0.33)), 0.45 * s2 / (s2 + 0.09))
    }

    /// π f / ρ = A + B max(0, s)/max(cos θi, cos θo) for two directions above the surface.
    #[inline]
    fn shape(&self, wo: Vec3, wi: Vec3) -> f32 {
        let (a, b) = self.ab();
        let s = wo.x * wi.x + wo.y * wi.y;
        if !(s > 0.0) {
            return a;
        }
        let v = a + b * s / wo.z.max(wi.z);
        if v.is_finite() { v } else { a }
    }
}

impl BsdfModel for OrenNayarClassic {
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

/// Reflects only; black at ρ = 0.
impl ModelFacts for OrenNayarClassic {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::INV_PI;

    /// pbrt-v3's formula with angles, against the trigonometry-free form.
    #[test]
    fn matches_the_angle_form() {
        let m = OrenNayarClassic::new(0.8, 0.4);
        let (a, b) = m.ab();
        let dir = |t: f32, p: f32| Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos());
        for (to, po, ti, pi) in [
            (0.3, 0.2, 1.1, 0.5),
            (1.2, 0.0, 0.4, 2.0),
            (0.7, 1.0, 0.7, 4.0),
            (1.5, 0.3, 0.2, 0.1),
        ] {
            let (wo, wi) = (dir(to, po), dir(ti, pi));
            let (al, be) = (ti.max(to), ti.min(to));
            let f = 0.8 * INV_PI * (a + b * (pi - po).cos().max(0.0) * al.sin() * be.tan());
            let g = m.eval(wo, wi);
            assert!((f - g).abs() <= 1e-5 * f, "{f} vs {g}");
            assert_eq!(m.eval(wo, wi), m.eval(wi, wo));
        }
        assert_eq!(OrenNayarClassic::new(0.5, 0.0).ab(), (1.0, 0.0));
        assert!(
            OrenNayarClassic::new(0.5, 1.6)
                .validate()
                .unwrap_err()
                .field
                == "sigma"
        );
        assert!(
            OrenNayarClassic::new(1.1, 0.1)
                .validate()
                .unwrap_err()
                .field
                == "albedo"
        );
    }
}
