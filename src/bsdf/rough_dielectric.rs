//! Rough dielectric: microfacet reflection and refraction (Walter, Marschner, Li &
//! Torrance 2007, "Microfacet Models for Refraction through Rough Surfaces";
//! pbrt-v4 §9.7).
//!
//! Conventions as in [`super::dielectric`]: `eta` = η_inside/η_outside (inside = −z),
//! radiance transport (pbrt-v4 `TransportMode::Radiance`). For ωo on side o with
//! index η_o, ωi on side i, and the relative index η′ = η_i/η_o:
//!
//! - reflection (same side): f_r = D(h) G2 F(ωo·h) / (4 |cos θo cos θi|), h ∝ ωo + ωi;
//! - transmission: with the generalised half vector h ∝ −(η_i ωi + η_o ωo) turned to +z,
//!   f_t = D(h) G2 (1 − F(ωo·h)) |ωi·h| |ωo·h| / (|cos θi cos θo| (ωi·h + ωo·h/η′)² η′²)
//!   (Walter eq. 21 with its η_o² factor, which is the radiance convention's 1/η′²).
//!
//! **Reciprocity** in this convention is f(ωi → ωo)/η_o² = f(ωo → ωi)/η_i² (Veach 1997,
//! eq. 5.14), i.e. `eval(wo, wi)/η(wo)² = eval(wi, wo)/η(wi)²`: tested.
//!
//! **Sampling**: a visible normal m ~ D_ωo, then reflection with probability F(ωo·m),
//! else refraction. pdf = D_ωo(h)/(4|ωo·h|)·F for reflection and
//! D_ωo(h) |ωi·h|/(ωi·h + ωo·h/η′)² · (1 − F) for transmission; the weights simplify to
//! G2/G1(ωo) and G2/(G1(ωo) η′²), computed in that form. The energy weight
//! weight·η′² = G2/G1 ≤ 1.
//!
//! The generalised half vector ωo + η′ωi is formed in `f64`: as η′ → 1 it is a
//! difference of nearly opposite vectors and `f32` would lose ~4 digits at η′ = 1.0001,
//! breaking reciprocity (the two argument orders would round differently).
//!
//! The transmitted lobe's angular width scales with α|1 − 1/η′|; at η′ = 1.0001 it is
//! far below what a chi-square grid resolves (and approaches `f32` direction
//! resolution), so such configurations are tested by consistency, albedo and
//! stability only.

use super::dielectric::validate_eta;

/// η at least [`MIN_ETA_GAP`] from 1 (see there), else the reason.
pub fn check_eta_gap(eta: f32) -> Result<(), ParamError> {
    let gap = (eta - 1.0).abs();
    if resolves(gap as f64) {
        return Ok(());
    }
    Err(ParamError::new(
        "eta",
        format!(
            "must be at least {MIN_ETA_GAP:e} from 1 for a rough dielectric, got {eta} (|η − 1| = {gap:e}): the transmitted lobe, α|1 − 1/η| wide, is then below what f32 directions resolve (the albedo read up to 33% low, 0 at η = 1); use a smooth `dielectric`, or none"
        ),
    ))
}
use super::flip_z;
use super::fresnel::{fr_dielectric, reflect, refract, tr_dielectric};
use super::microfacet::{Distribution, MAX_ALPHA, MIN_ALPHA, Masking, Microfacet};
use super::{BsdfModel, BsdfSample, LobeFlags, ParamError, check_range};
use super::{Index, ModelFacts};
use glam::{DVec3, Vec2, Vec3};
use serde::{Deserialize, Serialize};

/// The least |η − 1| of a rough dielectric. Through an interface with η′ near 1 the
/// transmitted lobe is α|1 − 1/η′| wide around −ωo, and the generalised half vector
/// ωo + η′ωi is a difference of nearly opposite vectors that the `f32` rounding of ωi
/// (~6·10⁻⁸) turns by up to about 6·10⁻⁸/|η − 1| rad. Measured with the albedo test
/// (`bsdf` estimator, Sobol, 65 536 samples, GGX and Beckmann, α from 10⁻⁴ to 1, θo
/// from 30° to 150°, against the oracle's albedo at the same `f32` η): at η = 1 every
/// sample is lost (ωi = −ωo whatever the microfacet, a delta transmission) and the
/// albedo reads 0; at |η − 1| = 10⁻⁵ Beckmann at α = 10⁻⁴ loses every sample (its D
/// underflows at the noisy half vector) and GGX at α = 1 reads 0.1% low; at 10⁻⁶–10⁻⁷
/// GGX at α = 0.3–1 reads up to 33% low. At 10⁻⁴ the 240 configurations of that test
/// agreed with the oracle, but an audit at 2²² samples (session 52) found GGX at α = 1,
/// θo = 120° reading 1.4·10⁻⁴ low (z = −16 to −18; −7 to −9 at 45° and 85°, and at
/// α = 0.5; −1.4 to −2.7 at 3·10⁻⁴), about 2.7·10⁻⁴ of the samples being lost. At 10⁻³
/// (η = 1.001 and 0.999, GGX at α = 0.5 and 1, θo = 60°, 85° and 120°, two seeds of
/// 2²² samples) all 24 estimates agree with the oracle, |z| ≤ 1.7.
pub const MIN_ETA_GAP: f32 = 1e-3;

/// Whether an index `gap` = |η − 1| from 1 is at least [`MIN_ETA_GAP`], to the `f32`
/// rounding of η near 1 (one ulp of 1): 0.999 is 0.99998713·10⁻³ from 1 in `f32`, and
/// is taken, as 1.001 is.
pub fn resolves(gap: f64) -> bool {
    gap + f64::from(f32::EPSILON) >= f64::from(MIN_ETA_GAP)
}

/// A rough dielectric boundary.
///
/// JSON: `{"type": "rough_dielectric", "alpha": 0.3, "eta": 1.5, "distribution": "ggx",
/// "masking": "height_correlated"}` (the last two optional, defaults shown).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RoughDielectric {
    /// Roughness α ∈ [1e-4, 1].
    #[serde(deserialize_with = "crate::error::json_f32::scalar")]
    pub alpha: f32,
    /// η_inside/η_outside (inside = −z).
    #[serde(deserialize_with = "crate::error::json_f32::scalar")]
    pub eta: f32,
    /// Normal distribution.
    #[serde(default)]
    pub distribution: Distribution,
    /// Masking–shadowing form.
    #[serde(default)]
    pub masking: Masking,
}

/// The half vector of a configuration with ωo above (z > 0), where the indices on
/// ωo's and ωi's sides are `no` and `ni`: for reflection normalize(ωo + ωi), for
/// transmission normalize(no ωo + ni ωi) turned to +z (in `f64`, and symmetric in the
/// two arguments so that reciprocity holds to rounding). `None` when degenerate or when
/// the microfacet would be back-facing to either direction.
#[inline]
fn half_vector(wo: Vec3, wi: Vec3, no: f32, ni: f32) -> Option<Vec3> {
    let reflect = wi.z > 0.0;
    let h = if reflect {
        let h = wo + wi;
        if !(h.length_squared() > 0.0) {
            return None;
        }
        h.normalize()
    } else {
        // Unit-normalised in f64 first: as η → 1 the sum is short, and a direction's
        // length error (an ulp) would turn its direction by 1e-4 relative.
        let h = wo.as_dvec3().normalize() * no as f64 + wi.as_dvec3().normalize() * ni as f64;
        let l2 = h.length_squared();
        if !(l2 > 0.0) {
            return None;
        }
        let h: DVec3 = h / l2.sqrt();
        let h = if h.z < 0.0 { -h } else { h };
        h.as_vec3().normalize_or_zero()
    };
    if !(h.z > 0.0) || !(wo.dot(h) > 0.0) {
        return None;
    }
    let ci = wi.dot(h);
    if reflect && !(ci > 0.0) || !reflect && !(ci < 0.0) {
        return None;
    }
    Some(h)
}

#[inline]
fn dot64(a: Vec3, b: Vec3) -> f64 {
    a.as_dvec3().dot(b.as_dvec3())
}

/// |dωm/dωi| of refraction, η_i² |ωi·m| / (η_i ωi·m + η_o ωo·m)² (Walter eq. 17), in
/// `f64` because the denominator cancels as η → 1.
#[inline]
fn transmission_jacobian(wo: Vec3, wi: Vec3, m: Vec3, no: f32, ni: f32) -> f64 {
    let m = m.as_dvec3().normalize();
    let (oh, ih) = (
        wo.as_dvec3().normalize().dot(m),
        wi.as_dvec3().normalize().dot(m),
    );
    let (no, ni) = (no as f64, ni as f64);
    let denom = ni * ih + no * oh;
    ni * ni * ih.abs() / (denom * denom)
}

/// Fresnel transmittance through a microfacet, evaluated from the side of the rarer
/// medium (cosine `oh` on ωo's side of index `no`, `ih` on ωi's side of index `ni`).
/// Physically T is the same from both sides; numerically the dense side's cosine near
/// the critical angle cancels, so always using the rare side makes the two argument
/// orders of a reciprocity check compute the same expression.
#[inline]
fn transmittance(oh: f64, ih: f64, no: f32, ni: f32) -> f32 {
    if ni >= no {
        tr_dielectric(oh.abs() as f32, ni / no)
    } else {
        tr_dielectric(ih.abs() as f32, no / ni)
    }
}

impl RoughDielectric {
    /// A GGX rough dielectric with height-correlated masking.
    pub fn new(alpha: f32, eta: f32) -> Self {
        RoughDielectric {
            alpha,
            eta,
            distribution: Distribution::Ggx,
            masking: Masking::HeightCorrelated,
        }
    }

    /// Parameter check: α ∈ [1e-4, 1], η ∈ [0.01, 100] with |η − 1| ≥ [`MIN_ETA_GAP`]
    /// (an interface the model resolves; η = 1 is no interface at all).
    pub fn validate(&self) -> Result<(), ParamError> {
        check_range("alpha", self.alpha, MIN_ALPHA, MAX_ALPHA)?;
        validate_eta(self.eta)?;
        check_eta_gap(self.eta)
    }

    /// The microfacet distribution.
    #[inline]
    pub fn microfacet(&self) -> Microfacet {
        Microfacet::new(self.distribution, self.alpha, self.masking)
    }

    /// ωo mirrored above the surface, the other direction with it, the indices
    /// (η_o, η_i′) of ωo's side and of the far side, and η′ = η_far/η_o.
    #[inline]
    fn canonical(&self, wo: Vec3, wi: Vec3) -> (Vec3, Vec3, f32, f32, f32) {
        if wo.z < 0.0 {
            (flip_z(wo), flip_z(wi), self.eta, 1.0, 1.0 / self.eta)
        } else {
            (wo, wi, 1.0, self.eta, self.eta)
        }
    }
}

impl BsdfModel for RoughDielectric {
    fn eval(&self, wo: Vec3, wi: Vec3) -> f32 {
        let (wo, wi, no, nf, etap) = self.canonical(wo, wi);
        let (co, ci) = (wo.z, wi.z);
        if !(co > 0.0) || !(ci != 0.0) {
            return 0.0;
        }
        let ni = if wi.z > 0.0 { no } else { nf };
        let Some(h) = half_vector(wo, wi, no, ni) else {
            return 0.0;
        };
        let mf = self.microfacet();
        let v = if ci > 0.0 {
            // F at the symmetric mean of ωo·h and ωi·h (equal but for rounding), so that
            // both argument orders compute the same value (reciprocity to the bit).
            let c = (0.5 * (dot64(wo, h) + dot64(wi, h))) as f32;
            mf.d(h) * mf.g2(wo, wi) * fr_dielectric(c, etap) / (4.0 * (co * ci))
        } else {
            // Walter eq. 21 in f64: η_o² |ωi·h||ωo·h| / (η_i ωi·h + η_o ωo·h)², whose
            // denominator cancels as η → 1.
            // With ωo, ωi unit in f64: a length error of one ulp would move the
            // cancelling denominator by 1e-3 relative at η = 1.0001.
            let hd = h.as_dvec3().normalize();
            let (oh, ih) = (
                wo.as_dvec3().normalize().dot(hd),
                wi.as_dvec3().normalize().dot(hd),
            );
            let (no, ni) = (no as f64, nf as f64);
            let denom = ni * ih + no * oh;
            let jac = no * no * (ih * oh).abs() / ((ci as f64 * co as f64).abs() * denom * denom);
            (mf.d(h) as f64
                * mf.g2(wo, wi) as f64
                * transmittance(oh, ih, no as f32, ni as f32) as f64
                * jac) as f32
        };
        if v.is_finite() && v > 0.0 { v } else { 0.0 }
    }

    fn sample(&self, wo: Vec3, u: Vec3) -> Option<BsdfSample> {
        // Unit length, so that the mirrored or refracted direction is unit too.
        let wo_in = wo;
        let wo = wo.normalize_or_zero();
        let flip = wo.z < 0.0;
        let (wo, _, _, _, etap) = self.canonical(wo, Vec3::ZERO);
        if !(wo.z > 0.0) || !wo.is_finite() {
            return None;
        }
        let mf = self.microfacet();
        let m = mf.sample_m(wo, Vec2::new(u.x, u.y));
        let c = dot64(wo, m) as f32;
        if !(c > 0.0) {
            return None;
        }
        let f = fr_dielectric(c, etap);
        let g1 = mf.g1(wo);
        let (wi, weight, lobe, eta) = if u.z < f {
            let wi = reflect(wo, m);
            if !(wi.z > 0.0) {
                return None;
            }
            (
                wi,
                mf.g2(wo, wi) / g1,
                LobeFlags::REFLECTION | LobeFlags::GLOSSY,
                1.0,
            )
        } else {
            let wi = refract(wo, m, etap)?;
            if !(wi.z < 0.0) {
                return None;
            }
            (
                wi,
                mf.g2(wo, wi) / (g1 * etap * etap),
                LobeFlags::TRANSMISSION | LobeFlags::GLOSSY,
                etap,
            )
        };
        if !weight.is_finite() {
            return None;
        }
        let wi = if flip { flip_z(wi) } else { wi };
        // The density MIS sees is `pdf` at the given ωo and the returned f32 direction
        // (whose generalised half vector differs from m by rounding), the function
        // next-event estimation evaluates, so that the two strategies' weights sum to 1.
        let pdf = self.pdf(wo_in, wi);
        if !(pdf > 0.0) || !pdf.is_finite() {
            return None;
        }
        Some(BsdfSample {
            wi,
            weight,
            pdf,
            lobe,
            eta,
        })
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let (wo, wi, no, nf, etap) = self.canonical(wo, wi);
        if !(wo.z > 0.0) || !(wi.z != 0.0) {
            return 0.0;
        }
        let ni = if wi.z > 0.0 { no } else { nf };
        let Some(h) = half_vector(wo, wi, no, ni) else {
            return 0.0;
        };
        let mf = self.microfacet();
        let oh = dot64(wo, h) as f32;
        let pm = mf.pdf_m(wo, h);
        let p = if wi.z > 0.0 {
            pm / (4.0 * oh) * fr_dielectric((0.5 * (dot64(wo, h) + dot64(wi, h))) as f32, etap)
        } else {
            let t = transmittance(dot64(wo, h), dot64(wi, h), no, nf);
            (pm as f64 * transmission_jacobian(wo, wi, h, no, nf) * t as f64) as f32
        };
        if p.is_finite() && p > 0.0 { p } else { 0.0 }
    }

    fn flags(&self) -> LobeFlags {
        LobeFlags::REFLECTION | LobeFlags::TRANSMISSION | LobeFlags::GLOSSY
    }
}

/// Transmits into index η; never black.
impl ModelFacts for RoughDielectric {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// An interface within [`MIN_ETA_GAP`] of η = 1 is refused, naming `eta`, for either
    /// distribution (η = 1 itself, 1 ± 5·10⁻⁵, 1 ± 10⁻⁴ (taken until session 52),
    /// 1 ± 5·10⁻⁴, the `f32` neighbours of 1), and one at 1.001 or 0.999 is taken; a
    /// dispersive index reaching that close to 1 anywhere in the band is refused too
    /// (`scene::dispersion`).
    #[test]
    fn an_interface_too_weak_to_resolve_is_refused() {
        for d in [Distribution::Ggx, Distribution::Beckmann] {
            let b = |eta: f32| RoughDielectric {
                distribution: d,
                ..RoughDielectric::new(0.3, eta)
            };
            for eta in [
                1.0,
                1.00005,
                0.99995,
                1.0001,
                0.9999,
                1.0005,
                0.9995,
                1.0f32.next_up(),
                1.0f32.next_down(),
            ] {
                let e = b(eta).validate().unwrap_err();
                assert!(
                    e.field == "eta" && e.reason.contains("from 1"),
                    "{eta}: {e}"
                );
            }
            for eta in [1.001, 0.999, 1.5, 1.0 / 1.5] {
                assert!(b(eta).validate().is_ok(), "{eta}");
            }
        }
        let cauchy = |a: f64| -> crate::scene::SpectralIor {
            serde_json::from_value(serde_json::json!({ "eta": { "cauchy": { "a": a, "b": 0.0 } } }))
                .unwrap()
        };
        let bsdf = super::super::Bsdf::RoughDielectric(RoughDielectric::new(0.3, 1.5));
        let visible = crate::spectrum::VISIBLE;
        let (at, e) = cauchy(1.0005).validate(&bsdf, visible).unwrap_err();
        assert!(at == ".eta" && e.contains("within 1e-3 of 1"), "{at}: {e}");
        assert!(cauchy(1.002).validate(&bsdf, visible).is_ok());
        // The band's ends exactly MIN_ETA_GAP from 1 (in f32) are taken, as the
        // constant index is by `validate`.
        for a in [1.0 + MIN_ETA_GAP, 1.0 - MIN_ETA_GAP] {
            assert!(check_eta_gap(a).is_ok(), "{a}");
            assert!(cauchy(a as f64).validate(&bsdf, visible).is_ok(), "{a}");
        }
        let smooth = super::super::Bsdf::Dielectric(super::super::Dielectric::new(1.5));
        assert!(cauchy(1.00005).validate(&smooth, visible).is_ok());
    }

    /// Straight through, ωo = +z and ωi = −z: the half vector (η_o ωo + η_i ωi, turned
    /// to +z) is the normal itself, a configuration sampling reaches with probability 0
    /// and that only a direct evaluation checks. Walter et al. 2007 eq. 21 there, with
    /// ωo·h = 1, ωi·h = −1, G₂ = 1 and D(n) = 1/(πα²) (GGX): from outside (η_o = 1,
    /// η_i = η) f = (1 − F₀)/(πα² (η − 1)²), and from inside η² times that (the η² rule
    /// of transmitted radiance), F₀ = ((η − 1)/(η + 1))².
    #[test]
    fn straight_through_transmission_has_walters_value() {
        for (alpha, eta) in [(0.3f32, 1.5f32), (0.05, 1.33), (1.0, 2.4), (0.3, 1.0 / 1.5)] {
            let b = RoughDielectric::new(alpha, eta);
            let (a, e) = (alpha as f64, eta as f64);
            let f0 = ((e - 1.0) / (e + 1.0)).powi(2);
            let outside = (1.0 - f0) / (std::f64::consts::PI * a * a * (e - 1.0).powi(2));
            for (wo, wi, want) in [
                (Vec3::Z, -Vec3::Z, outside),
                (-Vec3::Z, Vec3::Z, e * e * outside),
            ] {
                let got = b.eval(wo, wi) as f64;
                assert!(
                    (got / want - 1.0).abs() < 1e-5,
                    "α = {alpha}, η = {eta}, ωo = {wo}: f = {got}, Walter: {want}"
                );
                assert!(b.pdf(wo, wi) > 0.0, "α = {alpha}, η = {eta}, ωo = {wo}");
            }
        }
    }
}
