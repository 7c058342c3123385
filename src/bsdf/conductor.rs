//! Smooth conductor: a perfect mirror whose reflectance is the conductor Fresnel
//! factor F(cos θo; η + ik) ([`fr_conductor`], Born & Wolf §14.2; pbrt-v4 §9.4).
//!
//! f(ωi → ωo) = F(cos θo) δ(ωi − R(ωo)) / |cos θi| with R the mirror direction about
//! the normal, so `sample` returns the mirror direction with pdf 1 (the discrete
//! probability of the single delta lobe) and weight F(cos θo); `eval` and `pdf` are 0.
//! Two-sided: a viewer below the surface sees the same mirror. The directional
//! albedo is exactly F(cos θo) (tested against an independent `f64` complex-number
//! Fresnel in `tests/proof/bsdf_contract.rs`).

use super::fresnel::{fr_conductor, fr_conductor_cs};
use super::{BsdfModel, BsdfSample, LobeFlags, ParamError, check_range};
use super::{Index, ModelFacts};
use glam::Vec3;
use serde::{Deserialize, Serialize};

/// A smooth conductor of complex relative index η + ik.
///
/// JSON: `{"type": "conductor", "eta": 0.2, "k": 3.9}`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Conductor {
    /// Real part η of the relative index (> 0).
    #[serde(deserialize_with = "crate::error::json_f32::scalar")]
    pub eta: f32,
    /// Extinction coefficient k (≥ 0).
    #[serde(deserialize_with = "crate::error::json_f32::scalar")]
    pub k: f32,
}

/// Check a complex index of refraction (shared by the conductor models).
pub(crate) fn validate_complex_ior(eta: f32, k: f32) -> Result<(), ParamError> {
    check_range("eta", eta, 1e-3, 100.0)?;
    check_range("k", k, 0.0, 100.0)
}

impl Conductor {
    /// A smooth conductor.
    pub fn new(eta: f32, k: f32) -> Self {
        Conductor { eta, k }
    }

    /// Parameter check: η ∈ [1e-3, 100], k ∈ [0, 100].
    pub fn validate(&self) -> Result<(), ParamError> {
        validate_complex_ior(self.eta, self.k)
    }

    /// The promised reflectance F(cos θo).
    pub fn reflectance(&self, cos_o: f32) -> f32 {
        fr_conductor(cos_o, self.eta, self.k)
    }
}

impl BsdfModel for Conductor {
    fn eval(&self, _wo: Vec3, _wi: Vec3) -> f32 {
        0.0
    }

    fn sample(&self, wo: Vec3, _u: Vec3) -> Option<BsdfSample> {
        // Unit length, so that the mirrored or refracted direction is unit too.
        let wo = wo.normalize_or_zero();
        if !(wo.z != 0.0) || !wo.is_finite() {
            return None;
        }
        let wi = Vec3::new(-wo.x, -wo.y, wo.z);
        // sin²θo from the tangent components: 1 − cos² of an `f32` cosine near 1 keeps
        // only its absolute error (~10⁻⁷), which the reflectance of η = 0.001, climbing
        // to 1 by sin θ = η, reads (`RoughConductor::fresnel_at`;
        // `tests::the_mirror_takes_sin_squared_from_the_direction`).
        let s2 = wo.x * wo.x + wo.y * wo.y;
        let weight = fr_conductor_cs(wo.z.abs().min(1.0), s2, self.eta, self.k);
        Some(BsdfSample {
            wi,
            weight,
            pdf: 1.0,
            lobe: LobeFlags::REFLECTION | LobeFlags::SPECULAR,
            eta: 1.0,
        })
    }

    fn pdf(&self, _wo: Vec3, _wi: Vec3) -> f32 {
        0.0
    }

    fn flags(&self) -> LobeFlags {
        LobeFlags::REFLECTION | LobeFlags::SPECULAR
    }
}

/// Reflects only; never called black. F > 0 for every index the model accepts but the
/// matched one, η = 1 and k = 0, where [`fr_conductor`] gives F = 0 exactly at every angle
/// (`fresnel::tests::conductor_reflects_nothing_at_the_matched_index`); not called black
/// there either: dispersion may move the index away from 1 at other wavelengths, and a
/// black claim would let the effects analysis prune light that scatters (this costs the
/// pruning some work and no expected value).
impl ModelFacts for Conductor {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The mirror's weight F(θo) for ωo from 0.02° to 0.2° off the normal, against the
    /// `f64` Fresnel equations at the `f32` direction's exact angle, for η = 2⁻⁹, k = 0
    /// (total reflection beyond sin θ = η, where F climbs steeply) and a gold-like index: within
    /// 10⁻⁶ relative. With sin²θ = 1 − cos²θ of the `f32` cosine it was off by 7·10⁻⁴.
    #[test]
    fn the_mirror_takes_sin_squared_from_the_direction() {
        for (eta, k) in [(2f32.powi(-9), 0.0f32), (0.2, 3.9)] {
            let mirror = Conductor::new(eta, k);
            for deg in [0.02f64, 0.05, 0.1, 0.11, 0.2] {
                for phi in [0.0f64, 0.7, 2.0] {
                    let (s, c) = deg.to_radians().sin_cos();
                    let wo = Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, c as f32);
                    let got = f64::from(mirror.sample(wo, Vec3::ZERO).unwrap().weight);
                    let w = wo.as_dvec3().normalize();
                    let want = crate::bsdf::fresnel::tests::conductor_f64(
                        w.z,
                        f64::from(eta),
                        f64::from(k),
                    );
                    assert!(
                        (got - want).abs() <= 1e-6 * want,
                        "η = {eta}, k = {k}, θo = {deg}°: F = {got}, not {want}"
                    );
                }
            }
        }
    }
}
