//! Bidirectional scattering distribution functions.
//!
//! A BSDF f(x, ωi → ωo) = dLo(ωo) / (Li(ωi) dσ⊥(ωi)) says how much of the radiance
//! arriving from ωi leaves towards ωo. All models here work in a local shading frame
//! with the normal along +z; both directions point away from the surface, `wo` towards
//! the viewer and `wi` towards the light.
//!
//! - `eval(wo, wi)` is f (zero for delta lobes),
//! - `sample(wo, u)` draws wi and returns the weight f·|cos θi|/pdf, the pdf (solid
//!   angle, or the discrete probability of a delta lobe) and the lobe it came from,
//! - `pdf(wo, wi)` is the density `sample` draws wi with.
//!
//! Hot paths use the closed enum [`Bsdf`]; [`BsdfModel`] is the public trait a user
//! implements to put their own BSDF through the same proof ([`contract`], run on every
//! built-in model by `tests/proof/bsdf_contract.rs` and `tests/proof/bsdf_stability.rs`).
//!
//! | model | JSON | file |
//! |---|---|---|
//! | Lambertian | `{"type": "lambertian", "albedo": 0.5}` | [`lambertian`] |
//! | Oren–Nayar (Fujii's improved form) | `{"type": "oren_nayar", "albedo": 0.8, "sigma": 0.5}` | [`oren_nayar`] |
//! | Oren–Nayar (classic, Oren & Nayar 1994 / pbrt-v3; σ in radians) | `{"type": "oren_nayar_classic", "albedo": 0.8, "sigma": 0.35}` | [`oren_nayar_classic`] |
//! | smooth conductor | `{"type": "conductor", "eta": 0.2, "k": 3.9}` | [`conductor`] |
//! | smooth dielectric | `{"type": "dielectric", "eta": 1.5}` | [`dielectric`] |
//! | rough conductor | `{"type": "rough_conductor", "alpha": 0.3, "eta": 0.2, "k": 3.9, "distribution": "ggx", "masking": "height_correlated"}`; F ≡ 1: `{"type": "rough_conductor", "alpha": 0.3, "fresnel": "none"}` | [`rough_conductor`] |
//! | rough dielectric | `{"type": "rough_dielectric", "alpha": 0.3, "eta": 1.5, "distribution": "beckmann"}` | [`rough_dielectric`] |
//! | two-layer plastic | `{"type": "plastic", "albedo": 0.5, "eta": 1.5}` | [`plastic`] |
//!
//! `distribution` (`ggx` | `beckmann`) and `masking` (`height_correlated` |
//! `uncorrelated`) are optional. Shared pieces: [`fresnel`] (dielectric and conductor
//! Fresnel, reflection, refraction) and [`microfacet`] (D, Λ, G1, G2, visible-normal
//! sampling). [`Bsdf::from_json`] parses and validates a model.
//!
//! **Indices of refraction.** A dielectric's `eta` is η_inside/η_outside with the inside
//! below the surface (−z); [`BsdfSample::eta`] is the relative index η_i/η_o crossed by
//! the sample (1 for reflection). **Radiance convention** (pbrt-v4 "radiance" mode):
//! transmitted radiance is scaled by (η_o/η_i)², so reciprocity reads
//! f(ωi→ωo)/η_o² = f(ωo→ωi)/η_i², and the energy carried by a sample is
//! weight·η′² (see [`dielectric`], [`rough_dielectric`]).
//!
//! Engine arithmetic is `f32`; `f64` appears where a formula cancels (the generalised
//! half vector and refraction Jacobian as η → 1, erf-based Beckmann terms, constants
//! computed once by quadrature), each place saying why.

pub mod conductor;
pub mod contract;
pub mod dielectric;
pub mod fresnel;
pub mod lambertian;
pub mod microfacet;
pub mod oren_nayar;
pub mod oren_nayar_classic;
pub mod plastic;
pub mod rough_conductor;
pub mod rough_dielectric;

pub use conductor::Conductor;
pub use dielectric::Dielectric;
pub use lambertian::Lambertian;
pub use microfacet::{Distribution, Masking, Microfacet};
pub use oren_nayar::OrenNayar;
pub use oren_nayar_classic::OrenNayarClassic;
pub use plastic::Plastic;
pub use rough_conductor::{FresnelMode, RoughConductor};
pub use rough_dielectric::RoughDielectric;

use bitflags::bitflags;
use glam::Vec3;
use serde::{Deserialize, Serialize};

bitflags! {
    /// Which kind of lobe a sample came from, or a model has.
    #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
    pub struct LobeFlags: u8 {
        /// Scattering into the hemisphere of incidence.
        const REFLECTION = 1;
        /// Scattering through the surface.
        const TRANSMISSION = 2;
        /// A smooth (non-delta) lobe.
        const DIFFUSE = 4;
        /// A glossy (rough specular) lobe.
        const GLOSSY = 8;
        /// A Dirac delta lobe (perfect specular).
        const SPECULAR = 16;
    }
}

impl LobeFlags {
    /// Whether the lobe is a Dirac delta.
    pub fn is_delta(&self) -> bool {
        self.contains(LobeFlags::SPECULAR)
    }

    /// Whether some lobe has a density (a diffuse or glossy one): a model of Dirac delta
    /// lobes only has none anywhere (its `eval` and `pdf` are 0), so a chi-square test of
    /// its sampled directions has nothing to compare them with.
    pub fn has_density(&self) -> bool {
        self.intersects(LobeFlags::DIFFUSE | LobeFlags::GLOSSY)
    }
}

/// A direction drawn from a BSDF.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BsdfSample {
    /// The sampled incident direction (local frame).
    pub wi: Vec3,
    /// f·|cos θi| / pdf.
    pub weight: f32,
    /// Density of `wi` in solid angle (or the lobe's discrete probability if delta).
    pub pdf: f32,
    /// The lobe that produced the sample.
    pub lobe: LobeFlags,
    /// Relative index of refraction crossed (1 for reflection).
    pub eta: f32,
}

/// The contract every BSDF satisfies; implement it to verify your own model.
///
/// Conventions: local shading frame with the normal +z; `wo` (towards the viewer) and
/// `wi` (towards the light) both point away from the surface; `eval(wo, wi)` is
/// f(wi → wo), zero for delta lobes; `sample` returns the weight f·|cos θi|/pdf; `pdf`
/// is in solid angle (a delta lobe's `BsdfSample::pdf` is its discrete selection
/// probability). No method may return NaN, Inf or a negative value for any input.
///
/// # Verifying your own BSDF
///
/// The functions in [`contract`] are the proof the built-in models pass
/// (`tests/proof/bsdf_contract.rs`); run them on your model:
///
/// ```
/// use glam::Vec3;
/// use lightproof::bsdf::{contract, BsdfModel, BsdfSample, LobeFlags};
/// use lightproof::stats::{sidak_alpha, MeanTest};
///
/// /// A "uniform" diffuse reflector: f = ρ/π, sampled uniformly over the hemisphere.
/// struct UniformDiffuse { rho: f32 }
///
/// impl BsdfModel for UniformDiffuse {
///     fn eval(&self, wo: Vec3, wi: Vec3) -> f32 {
///         if wo.z * wi.z > 0.0 { self.rho / std::f32::consts::PI } else { 0.0 }
///     }
///     fn sample(&self, wo: Vec3, u: Vec3) -> Option<BsdfSample> {
///         if wo.z == 0.0 { return None; }
///         let z = u.x;
///         let r = (1.0 - z * z).max(0.0).sqrt();
///         let phi = 2.0 * std::f32::consts::PI * u.y;
///         let wi = Vec3::new(r * phi.cos(), r * phi.sin(), z.copysign(wo.z));
///         let pdf = 0.5 / std::f32::consts::PI;
///         Some(BsdfSample { wi, weight: self.eval(wo, wi) * z / pdf, pdf, lobe: LobeFlags::REFLECTION | LobeFlags::DIFFUSE, eta: 1.0 })
///     }
///     fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
///         if wo.z * wi.z > 0.0 { 0.5 / std::f32::consts::PI } else { 0.0 }
///     }
///     fn flags(&self) -> LobeFlags { LobeFlags::REFLECTION | LobeFlags::DIFFUSE }
/// }
///
/// let model = UniformDiffuse { rho: 0.8 };
/// let wo = contract::direction(0.7, 0.3); // θo = 0.7 rad, φo = 0.3 rad
/// let seed = 7;
/// // Three statistical tests below: Šidák-correct them together.
/// let alpha = sidak_alpha(1e-4, 3);
///
/// // 1. sample() draws from pdf() (chi-square over the sphere, normalisation included).
/// let chi2 = contract::chi2_bsdf(&model, "uniform-diffuse", wo, 100_000, seed, alpha);
/// assert!(chi2.passed, "{:?}", chi2.reason);
/// // 2. weight = eval·|cos|/pdf and the returned pdf = pdf(wo, wi), sample by sample.
/// assert!(contract::check_consistency(&model, wo, 10_000, seed).passed);
/// // 3. f(wi→wo) = f(wo→wi) (η inside = 1: no transmission).
/// assert!(contract::check_reciprocity(&model, 1.0, 10_000, seed).passed);
/// // 4. The directional albedo is at most 1, and equals the promised ρ.
/// let a = contract::albedo(&model, wo, 200_000, seed);
/// let test = MeanTest::new(1e-4, 3);
/// assert!(contract::judge_at_most(&test, &a.energy, 1.0).passed);
/// let v = contract::judge_equal(&test, &a.energy, 0.8);
/// assert!(v.passed && v.detectable_relative_bias < 0.01, "{v:?}");
/// ```
pub trait BsdfModel: Send + Sync {
    /// f(wi → wo).
    fn eval(&self, wo: Vec3, wi: Vec3) -> f32;
    /// Draw wi given wo and three uniform numbers.
    fn sample(&self, wo: Vec3, u: Vec3) -> Option<BsdfSample>;
    /// Density of `sample` drawing wi given wo.
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32;
    /// The lobes the model has.
    fn flags(&self) -> LobeFlags;
}

/// The refractive index a model carries, which a dispersive table
/// ([`crate::scene::dispersion`]) may vary per wavelength.
#[derive(Debug, PartialEq)]
pub enum Index<'a> {
    /// No index to vary (the diffuse models; the plastic's coat index is fixed).
    Fixed,
    /// A dielectric's relative index η.
    Dielectric(&'a mut f32),
    /// A conductor's complex index η + i k.
    Conductor(&'a mut f32, &'a mut f32),
}

/// Facts about a built-in model that planning and the contract read. Every model states
/// each one itself (there are no defaults), so a new model does not compile until it
/// has said what it is.
pub trait ModelFacts {
    /// The refractive index below the surface relative to above (1 for models that do
    /// not transmit): what the reciprocity rule of [`contract::check_reciprocity`] needs.
    fn eta_inside(&self) -> f32;
    /// Whether the model scatters no light at all (an absorber the effects analysis
    /// need not bounce off).
    fn is_black(&self) -> bool;
    /// Its refractive index, for dispersion to vary.
    fn index(&mut self) -> Index<'_>;
}

/// The closed set of built-in models (the engine's hot path dispatches on it).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum Bsdf {
    /// Ideal diffuse reflection: `{"type": "lambertian", "albedo": 0.5}`.
    Lambertian(Lambertian),
    /// Rough diffuse reflection: `{"type": "oren_nayar", "albedo": 0.8, "sigma": 0.35}`.
    OrenNayar(OrenNayar),
    /// Classic rough diffuse reflection (σ in radians):
    /// `{"type": "oren_nayar_classic", "albedo": 0.8, "sigma": 0.35}`.
    OrenNayarClassic(OrenNayarClassic),
    /// Smooth conductor: `{"type": "conductor", "eta": 0.2, "k": 3.9}`.
    Conductor(Conductor),
    /// Smooth dielectric: `{"type": "dielectric", "eta": 1.5}`.
    Dielectric(Dielectric),
    /// Microfacet conductor: `{"type": "rough_conductor", "alpha": 0.3, "eta": 0.2, "k": 3.9}`.
    RoughConductor(RoughConductor),
    /// Microfacet dielectric: `{"type": "rough_dielectric", "alpha": 0.3, "eta": 1.5}`.
    RoughDielectric(RoughDielectric),
    /// Diffuse base under a smooth coat: `{"type": "plastic", "albedo": 0.5, "eta": 1.5}`.
    Plastic(Plastic),
}

macro_rules! dispatch {
    ($self:ident, $b:ident => $e:expr) => {
        match $self {
            Bsdf::Lambertian($b) => $e,
            Bsdf::OrenNayar($b) => $e,
            Bsdf::OrenNayarClassic($b) => $e,
            Bsdf::Conductor($b) => $e,
            Bsdf::Dielectric($b) => $e,
            Bsdf::RoughConductor($b) => $e,
            Bsdf::RoughDielectric($b) => $e,
            Bsdf::Plastic($b) => $e,
        }
    };
}

impl Bsdf {
    /// Check parameters: a message naming the field and the reason.
    pub fn validate(&self) -> Result<(), ParamError> {
        dispatch!(self, b => b.validate())
    }

    /// Short model name.
    pub fn name(&self) -> &'static str {
        match self {
            Bsdf::Lambertian(_) => "lambertian",
            Bsdf::OrenNayar(_) => "oren_nayar",
            Bsdf::OrenNayarClassic(_) => "oren_nayar_classic",
            Bsdf::Conductor(_) => "conductor",
            Bsdf::Dielectric(_) => "dielectric",
            Bsdf::RoughConductor(_) => "rough_conductor",
            Bsdf::RoughDielectric(_) => "rough_dielectric",
            Bsdf::Plastic(_) => "plastic",
        }
    }

    /// Parse a model from its JSON text and validate it; the error names the problem
    /// (a JSON syntax error with its line and column, an unknown `type` or field, a
    /// number that does not fit `f32` with its field, or the parameter `validate`
    /// rejects).
    pub fn from_json(text: &str) -> Result<Bsdf, String> {
        let b: Bsdf = crate::error::parse_json("<bsdf>", text)
            .map_err(|e| format!("invalid BSDF JSON: {}", e.without_file()))?;
        b.validate()
            .map_err(|e| format!("invalid {} BSDF: {e}", b.name()))?;
        Ok(b)
    }
}

impl ModelFacts for Bsdf {
    fn eta_inside(&self) -> f32 {
        dispatch!(self, b => b.eta_inside())
    }
    fn is_black(&self) -> bool {
        dispatch!(self, b => b.is_black())
    }
    fn index(&mut self) -> Index<'_> {
        dispatch!(self, b => b.index())
    }
}

impl BsdfModel for Bsdf {
    #[inline]
    fn eval(&self, wo: Vec3, wi: Vec3) -> f32 {
        dispatch!(self, b => b.eval(wo, wi))
    }
    #[inline]
    fn sample(&self, wo: Vec3, u: Vec3) -> Option<BsdfSample> {
        dispatch!(self, b => b.sample(wo, u))
    }
    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        dispatch!(self, b => b.pdf(wo, wi))
    }
    #[inline]
    fn flags(&self) -> LobeFlags {
        dispatch!(self, b => b.flags())
    }
}

/// A model parameter rejected by `validate`: the field (as the JSON names it) and why.
/// Shown as `` `field` reason ``; a case file's error names the field in its path
/// (`scene.materials.glass.eta`).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("`{field}` {reason}")]
pub struct ParamError {
    /// The JSON field at fault.
    pub field: &'static str,
    /// Why it is rejected (`must lie in [0, 1], got -1`).
    pub reason: String,
}

impl ParamError {
    /// Field `field` rejected for `reason`.
    pub fn new(field: &'static str, reason: impl Into<String>) -> Self {
        ParamError {
            field,
            reason: reason.into(),
        }
    }
}

/// Check that a parameter is finite and within `[lo, hi]`.
pub fn check_range(field: &'static str, value: f32, lo: f32, hi: f32) -> Result<(), ParamError> {
    if !value.is_finite() {
        return Err(ParamError::new(
            field,
            format!("must be a finite number, got {value}"),
        ));
    }
    if value < lo || value > hi {
        return Err(ParamError::new(
            field,
            format!("must lie in [{lo}, {hi}], got {value}"),
        ));
    }
    Ok(())
}

/// cos θ of a local direction.
#[inline]
pub fn cos_theta(w: Vec3) -> f32 {
    w.z
}

/// Mirror a local direction through the tangent plane.
#[inline]
pub(crate) fn flip_z(w: Vec3) -> Vec3 {
    Vec3::new(w.x, w.y, -w.z)
}

/// Mirror a pair of local directions so that `wo` lies in the upper hemisphere (models
/// that reflect alike from both sides evaluate there).
#[inline]
pub(crate) fn to_upper(wo: Vec3, wi: Vec3) -> (Vec3, Vec3) {
    if wo.z < 0.0 {
        (flip_z(wo), flip_z(wi))
    } else {
        (wo, wi)
    }
}

/// Whether two local directions lie in the same hemisphere.
#[inline]
pub fn same_hemisphere(a: Vec3, b: Vec3) -> bool {
    a.z * b.z > 0.0
}
