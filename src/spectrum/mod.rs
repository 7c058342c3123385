//! Spectra as data: what varies with wavelength, and how wavelengths are drawn.
//!
//! | item | file | concept |
//! |---|---|---|
//! | [`SPEED_OF_LIGHT`], [`PLANCK`], [`BOLTZMANN`], [`photon_energy`] | `photon.rs` | exact SI constants; a photon's energy hc/λ |
//! | [`Band`], [`VISIBLE`] | `band.rs` | a wavelength interval [λ₁, λ₂] in nm |
//! | [`Spectrum`] | `spectrum.rs` | S(λ): constant, tabulated (linear, zero outside), Planck's blackbody |
//! | [`planck_radiance`], [`blackbody_band_radiance`] | `blackbody.rs` | Planck's law per nm and its exact band integral |
//! | [`Ior`], [`bk7`] | `ior.rs` | refractive index n(λ): constant, Cauchy, Sellmeier, tabulated |
//! | [`Response`], [`photopic`] | `response.rs` | a sensor's R(λ): flat, CIE 1931 ȳ (photopic), tabulated |
//! | [`cie`] | `cie.rs` | CIE 1931 x̄, ȳ, z̄ (analytic fit) and E-white tristimulus → linear sRGB, for rendering |
//! | [`WavelengthSampler`] | `wavelength.rs` | drawing λ over a band, uniformly or by importance; hero lanes |
//!
//! **Conventions.** Wavelengths are vacuum wavelengths in nanometres: `f32` in the engine,
//! `f64` inside closed forms and integrals. No public function here returns NaN, ±∞ or a
//! negative value, whatever its input (0, negative, NaN, ∞ or absurd parameters):
//! spectra and responses give 0 where they are undefined and clamp overflow to the
//! largest finite float; an index of refraction falls back to 1 (vacuum) where its formula
//! gives nothing physical; a sampler always returns a wavelength in its band with a
//! positive, finite density. Malformed data is caught by the `validate` methods, whose
//! messages name the entry and the value (`values[3] must be non-negative and finite,
//! got -1`), for the scene loader to turn into located input errors.
//!
//! **JSON.** A spectrum is a bare number (constant), `{"sampled": {"wavelengths": [..],
//! "values": [..]}}` or `{"blackbody": {"temperature": T, "scale": s}}`; an index is a
//! number, `{"cauchy": {..}}`, `{"sellmeier": {..}}` or `{"sampled": {..}}`; a response
//! is `"flat"`, `"photopic"` or `{"sampled": {..}}`; a band is `[λ₁, λ₂]`. Unknown keys
//! and variants are rejected with serde's message (and field path, through
//! [`crate::error::parse_json`]).

mod band;
mod blackbody;
pub mod cie;
mod ior;
mod json;
mod photon;
mod response;
#[allow(clippy::module_inception)]
mod spectrum;
mod table;
mod wavelength;

pub use band::{Band, VISIBLE};
pub use blackbody::{
    WIEN_DISPLACEMENT, blackbody_band_photon_radiance, blackbody_band_radiance,
    blackbody_total_radiance, planck_radiance, stefan_boltzmann, wien_peak,
};
pub use ior::{Ior, bk7};
pub use photon::{BOLTZMANN, PLANCK, SPEED_OF_LIGHT, photon_energy};
pub use response::{LUMINOUS_EFFICACY, Response, photopic};
pub use spectrum::Spectrum;
pub use wavelength::{DEFENSIVE, WavelengthSampler};

/// Narrowest interval of wavelengths, relative to its longer end: (λ₂ − λ₁) ≥ 10⁻⁴·λ₂
/// (0.05 nm at 500 nm), so that `f32` wavelengths resolve it into ~10³ values or more:
/// a case's band (`case::build`), a table's piece, and (as 10⁻⁴ of the time since a
/// pulse) a time bin.
pub const MIN_RELATIVE_BANDWIDTH: f64 = 1e-4;

/// A non-negative finite `f32` from an `f64`: NaN and negatives give 0, overflow gives
/// `f32::MAX`.
#[inline]
pub(crate) fn finite_f32(v: f64) -> f32 {
    if v > 0.0 {
        v.min(f32::MAX as f64) as f32
    } else {
        0.0
    }
}

/// A non-negative finite `f64`: NaN and negatives give 0, +∞ gives `f64::MAX`.
#[inline]
pub(crate) fn finite_f64(v: f64) -> f64 {
    if v > 0.0 { v.min(f64::MAX) } else { 0.0 }
}

/// ∫ f over [a, b] by `panels` composite 4-point Gauss–Legendre panels (exact for
/// polynomials of degree 7 on each panel; Abramowitz & Stegun 25.4.29).
pub(crate) fn gauss_legendre(a: f64, b: f64, panels: usize, f: impl Fn(f64) -> f64) -> f64 {
    crate::quadrature::GaussLegendre::new(4).composite(&mut |x| f(x), a, b, panels)
}
