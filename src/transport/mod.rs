//! Light transport: the integrands lightproof estimates.
//!
//! Rendering is integration: a measurement is an integral of radiance against a
//! sensitivity, and radiance obeys the rendering equation
//! Lo(x, ωo) = Le(x, ωo) + ∫ f(x, ωi → ωo) Li(x, ωi) |cos θi| dωi with
//! Li(x, ωi) = Lo(x′, −ωi) for the first surface x′ seen along ωi (Kajiya 1986).
//!
//! - [`plan`]: what an estimate simulates — the effects a scene can produce for a
//!   measurement ([`effects`]) and the dimensions it samples, decided together;
//! - [`effects`]: the geometric rules of that decision;
//! - [`path`]: the path tracer (next-event estimation, BSDF sampling, MIS, Russian
//!   roulette) that estimates Li;
//! - [`measure`]: the measurements (solid angle, irradiance, radiance, albedo, power,
//!   intensity, image) as one-sample estimators over the sample streams;
//! - [`microfacet_integral`]: the microfacet distributions' own integrals
//!   (normalisation, projected area, visible normals) as a measurement;
//! - [`phase`]: wavelength and time as dimensions of a sample (hero wavelengths, time
//!   of flight, motion), sampled only where the effects analysis says they matter;
//! - [`engine`]: running N samples in parallel, deterministically, into accumulators.

pub mod effects;
pub mod engine;
pub mod measure;
pub mod microfacet_integral;
pub mod path;
pub mod phase;
pub mod plan;

use serde::{Deserialize, Serialize};

/// How a measurement's integral is sampled.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Estimator {
    /// Emitter sampling (next-event estimation) only.
    Light,
    /// BSDF (or cosine) sampling only.
    Bsdf,
    /// Both, combined by multiple importance sampling with the power heuristic (β = 2).
    Mis,
    /// Both, combined with the balance heuristic.
    MisBalance,
    /// Uniform directions (sphere or hemisphere).
    Uniform,
    /// Cosine-weighted directions.
    Cosine,
    /// Points sampled uniformly by area on the shape or emitter.
    Area,
}

impl Estimator {
    /// Lower-case name.
    pub fn name(&self) -> &'static str {
        match self {
            Estimator::Light => "light",
            Estimator::Bsdf => "bsdf",
            Estimator::Mis => "mis",
            Estimator::MisBalance => "mis_balance",
            Estimator::Uniform => "uniform",
            Estimator::Cosine => "cosine",
            Estimator::Area => "area",
        }
    }

    /// The path tracer's strategies for this estimator: (light sampling, BSDF sampling,
    /// the MIS heuristic when both are on). Geometric estimators (uniform, cosine) sample
    /// directions as BSDF sampling does; area sampling of an emitter is light sampling
    /// combined with the BSDF by MIS.
    pub fn strategies(&self) -> (bool, bool, Heuristic) {
        match self {
            Estimator::Light => (true, false, Heuristic::Power),
            Estimator::Bsdf | Estimator::Uniform | Estimator::Cosine => {
                (false, true, Heuristic::Power)
            }
            Estimator::MisBalance => (true, true, Heuristic::Balance),
            Estimator::Mis | Estimator::Area => (true, true, Heuristic::Power),
        }
    }
}

/// The multiple importance sampling heuristics of Veach & Guibas 1995.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Heuristic {
    /// w = p / (p + q).
    Balance,
    /// w = p² / (p² + q²).
    Power,
}

impl Heuristic {
    /// Weight of a sample drawn with density `p` when the other strategy has density `q`.
    #[inline]
    pub fn weight(&self, p: f32, q: f32) -> f32 {
        if p.is_infinite() {
            return 1.0;
        }
        let w = match self {
            Heuristic::Balance => p / (p + q),
            Heuristic::Power => (p * p) / (p * p + q * q),
        };
        if w.is_finite() { w } else { 0.0 }
    }
}
