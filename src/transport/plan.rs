//! The plan of an estimate: which effects of light transport and which dimensions of a
//! sample (wavelength, time) a measurement in a scene calls for, decided together and
//! once, from the scene, the measurement and the case's `spectral` and `time` sections.
//!
//! Every consumer runs from a [`Plan`]: the path tracer's [`Config`] comes from
//! [`Config::for_estimator`] on the plan's effects, the sample's dimensions from the
//! plan's [`Dimensions`]; `render` uses the same plan as `estimate`. [`Plans::full`] is
//! the same measurement with every effect and dimension on, for the soundness proof
//! (`tests/proof/effects_soundness.rs`) that the pruned plan changes no expected value.

mod dimensions;

use crate::error::InputError;
use crate::scene::Scene;
use crate::spectrum::Response;
use crate::transport::Estimator;
use crate::transport::effects::{Effects, analyze};
use crate::transport::measure::Measure;
use crate::transport::path::Config;
use crate::transport::phase::Dimensions;
use serde::{Deserialize, Serialize};

/// How wavelengths are drawn over a band.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WavelengthSampling {
    /// Uniformly over the band.
    Uniform,
    /// Proportionally to the response times the emitters' (normalised) spectra.
    #[default]
    Emitter,
}

impl WavelengthSampling {
    /// How much more than R_max × S_max × band width (a uniform draw's largest weight,
    /// λ₂/(hc) aside) a sample's weight R(λ) Sₑ(λ)/p(λ) can be with `emitters` emitters:
    /// 1 for a uniform draw. The importance table's density is at least the defensive
    /// share δ of a uniform draw's, and at least (1 − δ) target(λ)/ΣT, with target =
    /// R Σₑ Sₑ/maxₑ (× λ/550 nm counting photons) bounded per cell
    /// ([`crate::spectrum::WavelengthSampler::importance_bounded`]) and ΣT ≤ width ×
    /// R_max × n: so the weight is at most min(1/δ, n/(1 − δ)) times a uniform draw's.
    pub fn weight_factor(&self, emitters: usize) -> f64 {
        let delta = crate::spectrum::DEFENSIVE;
        match self {
            WavelengthSampling::Uniform => 1.0,
            WavelengthSampling::Emitter => {
                (1.0 / delta).min(emitters.max(1) as f64 / (1.0 - delta))
            }
        }
    }
}

/// Wavelength of a measurement: a band with a response, or one wavelength.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpectralDesc {
    /// Band [λ₁, λ₂] in nm: the measurement is ∫ R(λ) M(λ) dλ over it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub band: Option<[f64; 2]>,
    /// One wavelength in nm: the measurement is spectral, M(λ) per nm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wavelength: Option<f64>,
    /// Response R(λ): "flat" (default), "photopic" or a sampled curve.
    #[serde(default = "flat")]
    pub response: Response,
    /// How wavelengths are drawn (default: by the emitters' spectra).
    #[serde(default)]
    pub sampling: WavelengthSampling,
    /// Four hero wavelengths per path (default true).
    #[serde(default = "yes")]
    pub hero: bool,
    /// Count photons: divide each wavelength's energy by hc/λ.
    #[serde(default)]
    pub photons: bool,
}

fn flat() -> Response {
    Response::Flat
}

fn yes() -> bool {
    true
}

/// Time of a measurement.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimeDesc {
    /// Shutter interval [t₀, t₁] in seconds: the measurement is the average over it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shutter: Option<[f64; 2]>,
    /// Arrival-time bin [t₁, t₂] in seconds: a time-resolved measurement (radiant
    /// exposure of light arriving in the bin).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bin: Option<[f64; 2]>,
    /// Arrival-time bin edges t₀ < … < t_K in seconds: a time-resolved histogram, one
    /// estimate per bin (see [`crate::case::bins`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bins: Option<Vec<f64>>,
}

/// What one estimate simulates.
#[derive(Clone, Debug)]
pub struct Plan {
    /// The effects simulated, each with its reason.
    pub effects: Effects,
    /// The dimensions sampled (wavelength, time) and the deterministic factor of those
    /// integrated out.
    pub dims: Dimensions,
}

/// A measurement's pruned plan and its fully simulated twin.
#[derive(Clone, Debug)]
pub struct Plans {
    /// Only what the scene can produce for the measurement.
    pub pruned: Plan,
    /// Every effect and dimension on (same expected value, by the soundness proof).
    pub full: Plan,
}

impl Plans {
    /// Decide both plans of `measure` in `scene` with the case's `spectral` and `time`
    /// sections; `file` names the case in errors (a spectral scene without a band, a
    /// time bin on a measurement without time of flight, ...).
    pub fn decide(
        file: &str,
        scene: &Scene,
        measure: &Measure,
        spectral: Option<&SpectralDesc>,
        time: Option<&TimeDesc>,
    ) -> Result<Plans, InputError> {
        let d = dimensions::dimensions(file, scene, measure, spectral, time)?;
        Ok(Plans {
            pruned: Plan {
                effects: analyze(scene, measure, d.wavelength, d.time),
                dims: d.pruned,
            },
            full: Plan {
                effects: Effects::everything(),
                dims: d.full,
            },
        })
    }
}

impl Plan {
    /// The path tracer's configuration for estimator `est` under this plan.
    pub fn config(&self, est: Estimator) -> Config {
        Config::for_estimator(est, &self.effects)
    }

    /// The same plan with paths cut after `bounces` scatterings (partial sums of the
    /// Neumann series: direct light only at 1, and so on).
    pub fn with_max_bounces(mut self, bounces: u32) -> Plan {
        self.effects.max_bounces =
            Some(self.effects.max_bounces.map_or(bounces, |b| b.min(bounces)));
        self
    }
}
