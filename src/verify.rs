//! Cases and verdicts: load a case file, run each estimator × sampler it names, and
//! judge the estimates against the oracle's reference.
//!
//! A case file:
//! ```json
//! {
//!   "name": "disk light over a point, on axis",
//!   "teaches": "irradiance E = π L sin²θ from a uniform disk",
//!   "scene": { "shapes": [ { "geometry": { "type": "disk", "center": [0, 0, 2],
//!              "normal": [0, 0, -1], "radius": 1 }, "emission": { "radiance": 1 } } ] },
//!   "measure": { "irradiance": { "at": [0, 0, 0], "normal": [0, 0, 1] } },
//!   "reference": { "closed_form": "disk_irradiance_on_axis", "radius": 1, "height": 2, "radiance": 1 },
//!   "estimators": ["light", "bsdf", "mis"],
//!   "samplers": ["independent"],
//!   "samples": 262144
//! }
//! ```
//! The reference names a closed form of `lightproof-analytic` (the independent oracle)
//! with its parameters; a case without one is simply estimated.
//!
//! **Verdict** ([`verdict`]): a z or batch-means t test for estimates with variance, in
//! one Šidák family per run; an exact comparison within the stated f32 error bound for
//! estimates without variance, outside the family.

use crate::bsdf::Bsdf;
use crate::error::{InputError, check_direction, check_number, check_point, parse_json};
use crate::sampling::{SampleStream, SamplerKind};
use crate::scene::Scene;
use crate::scene::load::SceneDesc;
use crate::spectrum::Response;
use crate::stats::Verdict;
use crate::transport::effects::{Effects, analyze};
use crate::transport::engine::{BATCHES, Estimate, RunSpec, run};
use crate::transport::measure::Measure;
use crate::transport::path::Config;
use crate::transport::phase::Dimensions;
mod dimensions;
pub mod verdict;
use crate::transport::{Estimator, Heuristic};
use dimensions::dimensions;
use glam::DVec3;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
pub use verdict::{ErrorBar, judge};

/// Default samples per estimate.
pub const DEFAULT_SAMPLES: u64 = 1 << 18;

/// Fewest samples per estimate: two per batch (the batch-means error needs them).
pub const MIN_SAMPLES: u64 = 2 * BATCHES;

/// Most samples per estimate: 2⁴⁰ ≈ 1.1·10¹² (days of work; no count wraps below it).
pub const MAX_SAMPLES: u64 = 1 << 40;

/// Longest wavelength of a `spectral` section (nm): 1 cm. Far past the thermal
/// infrared, and λ + 1 nm is still a different `f32`.
pub const MAX_WAVELENGTH_NM: f64 = 1e7;

/// Narrowest band, relative to its longer end: (λ₂ − λ₁) ≥ 10⁻⁴·λ₂ (0.05 nm at
/// 500 nm), so that `f32` wavelengths resolve the band into ~10³ values or more.
pub const MIN_RELATIVE_BANDWIDTH: f64 = 1e-4;

/// A measurement as written in a case file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum MeasureDesc {
    /// Solid angle of a shape from a point.
    SolidAngle {
        /// Viewpoint.
        from: [f64; 3],
        /// Index of the shape in `scene.shapes`.
        shape: usize,
    },
    /// Projected solid angle of a shape for a receiver.
    ProjectedSolidAngle {
        /// Viewpoint.
        from: [f64; 3],
        /// Receiver normal.
        normal: [f64; 3],
        /// Index of the shape.
        shape: usize,
    },
    /// Irradiance at a point.
    Irradiance {
        /// Point.
        at: [f64; 3],
        /// Receiver normal.
        normal: [f64; 3],
    },
    /// Radiance seen from a point looking along a direction.
    Radiance {
        /// Eye.
        at: [f64; 3],
        /// Viewing direction.
        direction: [f64; 3],
    },
    /// Directional albedo of a BSDF.
    Albedo {
        /// The BSDF (same JSON as a material).
        bsdf: Bsdf,
        /// Polar angle of ωo in degrees.
        theta_degrees: f64,
        /// Azimuth of ωo in degrees.
        #[serde(default)]
        phi_degrees: f64,
    },
    /// Power of an emitter: an emitting shape (`shape`) or an entry of `scene.emitters`.
    Power {
        /// Emitting shape.
        #[serde(default)]
        shape: Option<usize>,
        /// Entry of `scene.emitters`.
        #[serde(default)]
        emitter: Option<usize>,
    },
    /// Intensity of an emitter towards a direction.
    Intensity {
        /// Emitting shape.
        #[serde(default)]
        shape: Option<usize>,
        /// Entry of `scene.emitters`.
        #[serde(default)]
        emitter: Option<usize>,
        /// Direction.
        direction: [f64; 3],
    },
    /// Mean free-flight length of a diffuse random walk inside a closed shape (Cauchy's
    /// 4V/S); divided by c it is the mean time of flight between bounces.
    MeanPathLength {
        /// The closed shape.
        shape: usize,
        /// Flights averaged per path (default 8).
        #[serde(default = "default_segments")]
        segments: u32,
    },
}

fn default_segments() -> u32 {
    8
}

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
}

/// A case file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaseDesc {
    /// Name.
    pub name: String,
    /// What it teaches, in one sentence.
    pub teaches: String,
    /// The scene.
    #[serde(default)]
    pub scene: SceneDesc,
    /// The measurement.
    pub measure: MeasureDesc,
    /// Wavelength: a band with a response, or one wavelength (default: grey).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spectral: Option<SpectralDesc>,
    /// Time: a shutter interval and/or an arrival-time bin (default: static).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<TimeDesc>,
    /// The closed form (`closed_form` plus its parameters).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reference: Option<serde_json::Map<String, serde_json::Value>>,
    /// Estimators to run.
    pub estimators: Vec<Estimator>,
    /// Samplers to run (default: independent).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub samplers: Vec<SamplerKind>,
    /// Samples per estimate (default 2¹⁸).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub samples: Option<u64>,
    /// Why every estimator of this case is exact (samples without variance), when they
    /// all are: a catalog case must have an estimator with variance or say why not.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub exact: Option<String>,
    /// A camera for `lightproof render` (see [`crate::render::CameraDesc`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub camera: Option<crate::render::CameraDesc>,
}

/// A loaded, validated case.
pub struct Case {
    /// Where it came from.
    pub file: PathBuf,
    /// Its description.
    pub desc: CaseDesc,
    /// The built scene.
    pub scene: Scene,
    /// The measurement in engine coordinates.
    pub measure: Measure,
    /// The reference value, if any.
    pub reference: Option<f64>,
    /// The effects analysis.
    pub effects: Effects,
    /// Wavelength and time as the effects analysis prunes them.
    pub dims: Dimensions,
    /// Wavelength and time all sampled (for the soundness proof).
    pub dims_full: Dimensions,
}

/// The `spectral` and `time` sections as `f32` sees them: wavelengths in
/// (0, [`MAX_WAVELENGTH_NM`]], a band at least [`MIN_RELATIVE_BANDWIDTH`] wide, every
/// dispersive index valid over the band actually measured (a Sellmeier pole inside it is
/// refused, not only inside the visible range), and moving geometry staying within
/// range over the shutter.
fn check_spectral_and_time(f: &str, desc: &CaseDesc) -> Result<(), InputError> {
    use crate::spectrum::Band;
    let wl = |field: &str, l: f64| {
        check_number(
            f,
            field,
            l,
            |x| x > 0.0 && x <= MAX_WAVELENGTH_NM,
            "a wavelength in (0, 1e7] nm",
        )
    };
    let band = match desc.spectral.as_ref().map(|s| (s.band, s.wavelength)) {
        Some((Some([a, b]), None)) => {
            wl("spectral.band", a)?;
            wl("spectral.band", b)?;
            if !(b > a) {
                return Err(InputError::new(
                    f,
                    "spectral.band",
                    format!("must be [λ₁, λ₂] in nm with 0 < λ₁ < λ₂, got [{a}, {b}]"),
                ));
            }
            let (a32, b32) = (a as f32, b as f32);
            if !((b32 as f64 - a32 as f64) >= MIN_RELATIVE_BANDWIDTH * b) {
                return Err(InputError::new(
                    f,
                    "spectral.band",
                    format!(
                        "[{a}, {b}] nm is too narrow for f32 wavelengths: λ₂ − λ₁ must be at least {MIN_RELATIVE_BANDWIDTH}·λ₂ ({:.3e} nm here); for one wavelength use `spectral.wavelength`",
                        MIN_RELATIVE_BANDWIDTH * b
                    ),
                ));
            }
            Some(Band::new(a32, b32))
        }
        Some((None, Some(l))) => {
            wl("spectral.wavelength", l)?;
            Some(Band::new(l as f32, l as f32 + 1.0))
        }
        _ => None,
    };
    if let Some(band) = band {
        for (name, d) in &desc.scene.dispersion {
            if let Some(m) = desc.scene.materials.get(name) {
                d.validate(m, band)
                    .map_err(|r| InputError::new(f, format!("scene.dispersion.{name}"), r))?;
            }
        }
    }
    for (field, v) in [
        ("time.shutter", desc.time.as_ref().and_then(|t| t.shutter)),
        ("time.bin", desc.time.as_ref().and_then(|t| t.bin)),
    ] {
        for x in v.into_iter().flatten() {
            check_number(f, field, x, |_| true, "a time in seconds")?;
        }
    }
    if let Some([t0, t1]) = desc.time.as_ref().and_then(|t| t.shutter) {
        let t = t0.abs().max(t1.abs());
        let speeds = desc
            .scene
            .shapes
            .iter()
            .enumerate()
            .filter_map(|(i, s)| {
                s.velocity
                    .map(|v| (format!("scene.shapes[{i}].velocity"), v))
            })
            .chain(desc.scene.emitters.iter().enumerate().filter_map(|(i, e)| {
                use crate::scene::load::EmitterDesc;
                match e {
                    EmitterDesc::Point { velocity, .. } | EmitterDesc::Spot { velocity, .. } => {
                        velocity.map(|v| (format!("scene.emitters[{i}].velocity"), v))
                    }
                    _ => None,
                }
            }));
        for (field, v) in speeds {
            let travel = DVec3::from_array(v).length() * t;
            if travel.is_finite() && travel > crate::error::MAX_COORDINATE {
                return Err(InputError::new(
                    f,
                    field,
                    format!(
                        "moves {travel:e} over the shutter [{t0}, {t1}] s, out of range: positions must stay within ±{:e}",
                        crate::error::MAX_COORDINATE
                    ),
                ));
            }
        }
    }
    Ok(())
}

impl Case {
    /// Load and validate a case file.
    pub fn load(path: &Path) -> Result<Case, InputError> {
        let file = path.display().to_string();
        let text = crate::io::read_input(path, crate::io::MAX_JSON_BYTES)
            .map_err(|e| InputError::new(&file, "-", e))?;
        let desc: CaseDesc = parse_json(&file, &text)?;
        Case::from_desc(desc, path)
    }

    /// Validate a parsed description (`path` names it and anchors relative paths).
    pub fn from_desc(desc: CaseDesc, path: &Path) -> Result<Case, InputError> {
        let file = path.display().to_string();
        let f = file.as_str();
        let origin = match &desc.measure {
            MeasureDesc::SolidAngle { from, .. }
            | MeasureDesc::ProjectedSolidAngle { from, .. } => {
                check_point(f, "measure.from", *from)?
            }
            MeasureDesc::Irradiance { at, .. } | MeasureDesc::Radiance { at, .. } => {
                check_point(f, "measure.at", *at)?
            }
            _ => desc.scene.any_point(),
        };
        let base = path.parent().unwrap_or(Path::new("."));
        let scene = desc.scene.build(f, "scene", base, origin)?;
        let shape_index = |field: &str, i: usize| -> Result<usize, InputError> {
            if i < scene.shapes.len() {
                Ok(i)
            } else {
                Err(InputError::new(
                    f,
                    field,
                    format!(
                        "shape {i} does not exist (the scene has {} shapes)",
                        scene.shapes.len()
                    ),
                ))
            }
        };
        let emitter_index =
            |shape: Option<usize>, emitter: Option<usize>| -> Result<usize, InputError> {
                let n_area = scene.shapes.iter().filter(|s| s.emitter.is_some()).count();
                let idx = match (shape, emitter) {
                    (Some(s), None) => scene.shapes[shape_index("measure.shape", s)?]
                        .emitter
                        .ok_or_else(|| {
                            InputError::new(f, "measure.shape", format!("shape {s} does not emit"))
                        })?,
                    (None, Some(e)) if e < scene.emitters.len() - n_area => n_area + e,
                    (None, Some(e)) => {
                        return Err(InputError::new(
                            f,
                            "measure.emitter",
                            format!("emitter {e} does not exist"),
                        ));
                    }
                    _ => {
                        return Err(InputError::new(
                            f,
                            "measure",
                            "give exactly one of `shape` or `emitter`",
                        ));
                    }
                };
                if scene.emitters[idx].is_infinite() {
                    return Err(InputError::new(
                        f,
                        "measure",
                        "power and intensity are not defined for emitters at infinity",
                    ));
                }
                Ok(idx)
            };
        let rebased = |p: DVec3| (p - origin).as_vec3();
        let measure = match &desc.measure {
            MeasureDesc::SolidAngle { from, shape } => Measure::SolidAngle {
                from: rebased(check_point(f, "measure.from", *from)?),
                shape: shape_index("measure.shape", *shape)?,
            },
            MeasureDesc::ProjectedSolidAngle {
                from,
                normal,
                shape,
            } => Measure::ProjectedSolidAngle {
                from: rebased(check_point(f, "measure.from", *from)?),
                normal: check_direction(f, "measure.normal", *normal)?.as_vec3(),
                shape: shape_index("measure.shape", *shape)?,
            },
            MeasureDesc::Irradiance { at, normal } => Measure::Irradiance {
                at: rebased(check_point(f, "measure.at", *at)?),
                normal: check_direction(f, "measure.normal", *normal)?.as_vec3(),
            },
            MeasureDesc::Radiance { at, direction } => Measure::Radiance {
                at: rebased(check_point(f, "measure.at", *at)?),
                direction: check_direction(f, "measure.direction", *direction)?.as_vec3(),
            },
            MeasureDesc::Albedo {
                bsdf,
                theta_degrees,
                phi_degrees,
            } => {
                bsdf.validate()
                    .map_err(|r| InputError::new(f, "measure.albedo.bsdf", r))?;
                check_number(
                    f,
                    "measure.albedo.theta_degrees",
                    *theta_degrees,
                    |t| (0.0..=180.0).contains(&t),
                    "in [0, 180]",
                )?;
                check_number(
                    f,
                    "measure.albedo.phi_degrees",
                    *phi_degrees,
                    |_| true,
                    "finite",
                )?;
                let (t, p) = (theta_degrees.to_radians(), phi_degrees.to_radians());
                let wo = DVec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos()).as_vec3();
                Measure::Albedo {
                    bsdf: Box::new(bsdf.clone()),
                    wo,
                }
            }
            MeasureDesc::Power { shape, emitter } => Measure::Power {
                emitter: emitter_index(*shape, *emitter)?,
            },
            MeasureDesc::Intensity {
                shape,
                emitter,
                direction,
            } => Measure::Intensity {
                emitter: emitter_index(*shape, *emitter)?,
                direction: check_direction(f, "measure.direction", *direction)?.as_vec3(),
            },
            MeasureDesc::MeanPathLength { shape, segments } => Measure::MeanPathLength {
                shape: shape_index("measure.shape", *shape)?,
                segments: {
                    if !(1..=1 << 16).contains(segments) {
                        return Err(InputError::new(
                            f,
                            "measure.mean_path_length.segments",
                            format!("must be 1 to 65536 flights per path, got {segments}"),
                        ));
                    }
                    *segments
                },
            },
        };
        if desc.estimators.is_empty() {
            return Err(InputError::new(
                f,
                "estimators",
                "name at least one estimator",
            ));
        }
        for (i, e) in desc.estimators.iter().enumerate() {
            if !measure.estimators().contains(e) {
                let ok: Vec<&str> = measure.estimators().iter().map(|e| e.name()).collect();
                return Err(InputError::new(
                    f,
                    format!("estimators[{i}]"),
                    format!(
                        "`{}` cannot estimate {}; use one of {}",
                        e.name(),
                        measure.name(),
                        ok.join(", ")
                    ),
                ));
            }
        }
        if let Some(n) = desc.samples
            && !(MIN_SAMPLES..=MAX_SAMPLES).contains(&n)
        {
            return Err(InputError::new(
                f,
                "samples",
                format!(
                    "must be {MIN_SAMPLES} to 2^40 = {MAX_SAMPLES} (at least two per batch of {BATCHES}; rounded up to a multiple of {BATCHES}), got {n}"
                ),
            ));
        }
        check_spectral_and_time(f, &desc)?;
        let reference = match &desc.reference {
            None => None,
            Some(map) => {
                let name = map
                    .get("closed_form")
                    .and_then(|v| v.as_str())
                    .ok_or_else(|| {
                        InputError::new(
                            f,
                            "reference.closed_form",
                            "must name a closed form of lightproof-analytic",
                        )
                    })?;
                let mut params = map.clone();
                params.remove("closed_form");
                // A unit conversion of the closed form's value (e.g. 1e-9 from per metre
                // to per nanometre of wavelength).
                let scale = match params.remove("scale") {
                    None => 1.0,
                    Some(v) => v
                        .as_f64()
                        .filter(|x| x.is_finite() && *x > 0.0)
                        .ok_or_else(|| {
                            InputError::new(
                                f,
                                "reference.scale",
                                "must be a positive finite number",
                            )
                        })?,
                };
                let v = lightproof_analytic::catalog::evaluate(name, &params)
                    .map_err(|e| InputError::new(f, "reference", e.to_string()))?;
                if !(v * scale).is_finite() {
                    return Err(InputError::new(
                        f,
                        "reference",
                        format!(
                            "the closed form `{name}` evaluates to {} with these parameters: give parameters where it is finite",
                            v * scale
                        ),
                    ));
                }
                Some(v * scale)
            }
        };
        let mut effects = analyze(&scene, &measure);
        let (dims, dims_full, wavelength, time) = dimensions(
            f,
            &scene,
            &measure,
            desc.spectral.as_ref(),
            desc.time.as_ref(),
        )?;
        effects.wavelength = wavelength;
        effects.time = time;
        Ok(Case {
            file: path.to_path_buf(),
            desc,
            scene,
            measure,
            reference,
            effects,
            dims,
            dims_full,
        })
    }

    /// Samplers to run.
    pub fn samplers(&self) -> Vec<SamplerKind> {
        if self.desc.samplers.is_empty() {
            vec![SamplerKind::Independent]
        } else {
            self.desc.samplers.clone()
        }
    }

    /// Path-tracer configuration for an estimator: pruned by the effects analysis, or
    /// with every effect on (`full`) for the soundness proof.
    pub fn config(&self, est: Estimator, full: bool) -> Config {
        let (light, bsdf, heuristic) = match est {
            Estimator::Light => (true, false, Heuristic::Power),
            Estimator::Bsdf | Estimator::Uniform | Estimator::Cosine => {
                (false, true, Heuristic::Power)
            }
            Estimator::MisBalance => (true, true, Heuristic::Balance),
            Estimator::Mis | Estimator::Area => (true, true, Heuristic::Power),
        };
        if full {
            return Config::full(light, bsdf, heuristic);
        }
        Config {
            light,
            bsdf,
            heuristic,
            max_bounces: self.effects.max_bounces.unwrap_or(u32::MAX),
            shadow_rays: self.effects.occlusion.simulated,
            rr_depth: 3,
        }
    }

    /// One sample of estimator `est` (pruned, or with every effect and dimension on).
    pub fn sample(&self, est: Estimator, cfg: &Config, full: bool, s: &mut SampleStream) -> f32 {
        let dims = if full { &self.dims_full } else { &self.dims };
        self.measure.sample_with(&self.scene, est, cfg, dims, s)
    }

    /// Run one estimator with one sampler.
    pub fn estimate(&self, est: Estimator, spec: &RunSpec, full: bool) -> Estimate {
        let cfg = self.config(est, full);
        run(spec, |s| self.sample(est, &cfg, full, s))
    }
}

/// The outcome of one estimator × sampler of a case.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Outcome {
    /// Case name.
    pub case: String,
    /// Case file.
    pub file: String,
    /// Measurement.
    pub measure: String,
    /// Estimator.
    pub estimator: Estimator,
    /// Sampler.
    pub sampler: SamplerKind,
    /// Samples drawn.
    pub samples: u64,
    /// Seed.
    pub seed: u64,
    /// Mean.
    pub estimate: f64,
    /// Standard error a verdict uses (plain or batch means, see [`verdict`]); absent
    /// when the estimate is exact.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub std_error: Option<f64>,
    /// Degrees of freedom of the batch-means t test, when it decides.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dof: Option<u64>,
    /// Whether the samples have no variance (judged within the f32 error bound).
    pub exact: bool,
    /// Non-finite samples (any one fails the outcome, reference or not).
    pub non_finite: u64,
    /// Wall seconds.
    pub seconds: f64,
    /// What was simulated, and why.
    pub effects: Effects,
    /// Closed-form reference.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reference: Option<f64>,
    /// z score.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub z: Option<f64>,
    /// The verdict.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub verdict: Option<Verdict>,
}

impl Outcome {
    /// An unjudged outcome of estimate `e` of estimator `est` × `sampler` on `case`.
    pub fn new(
        case: &Case,
        est: Estimator,
        sampler: SamplerKind,
        seed: u64,
        e: &Estimate,
    ) -> Outcome {
        let total = &e.batches.total;
        let bar = ErrorBar::of(e, sampler);
        Outcome {
            case: case.desc.name.clone(),
            file: case.file.display().to_string(),
            measure: case.measure.name().to_string(),
            estimator: est,
            sampler,
            samples: total.count + total.non_finite,
            seed,
            estimate: total.mean,
            std_error: bar.std_error,
            dof: bar.dof,
            exact: bar.exact(),
            non_finite: total.non_finite,
            seconds: e.seconds,
            effects: case.effects.clone(),
            reference: case.reference,
            z: None,
            verdict: None,
        }
    }

    /// Whether the outcome will be a member of the statistical (Šidák) family.
    pub fn is_statistical(&self) -> bool {
        self.reference.is_some() && !self.exact
    }

    /// Judge against the reference (if any) in a family of `tests` statistical tests.
    pub fn judge(&mut self, alpha: f64, tests: usize) {
        if let Some(r) = self.reference {
            let bar = ErrorBar {
                std_error: self.std_error,
                dof: self.dof,
            };
            let count = self.samples - self.non_finite;
            let v =
                verdict::judge_parts(self.estimate, &bar, r, self.non_finite, count, alpha, tests);
            self.z = Some(v.z);
            self.verdict = Some(v);
        }
    }

    /// Whether it passed. Without a reference there is nothing to compare, but a
    /// non-finite sample still fails.
    pub fn passed(&self) -> bool {
        match &self.verdict {
            Some(v) => v.passed,
            None => self.non_finite == 0 && self.samples > 0,
        }
    }
}

/// Per-test seed: the base seed mixed with the case, estimator and sampler, so tests are
/// independent (Šidák is exact) and reproducible.
pub fn seed_for(base: u64, case: &str, est: Estimator, sampler: SamplerKind) -> u64 {
    use crate::sampling::sampler::{fnv1a, hash_words};
    let names = case
        .bytes()
        .chain(est.name().bytes())
        .chain(sampler.name().bytes());
    hash_words(&[base, fnv1a(names)])
}

/// Run every estimator × sampler of a case; the outcomes are not yet judged (see
/// [`judge_family`]).
pub fn run_case(case: &Case, base_seed: u64, samples: Option<u64>, scale: u64) -> Vec<Outcome> {
    let mut out = Vec::new();
    for sampler in case.samplers() {
        for &est in &case.desc.estimators {
            let n = samples
                .or(case.desc.samples)
                .unwrap_or(DEFAULT_SAMPLES)
                .saturating_mul(scale.max(1));
            let seed = seed_for(base_seed, &case.desc.name, est, sampler);
            let spec = RunSpec {
                samples: n,
                sampler,
                seed,
            };
            let e = case.estimate(est, &spec, false);
            out.push(Outcome::new(case, est, sampler, seed, &e));
        }
    }
    out
}

/// Judge every outcome of a run as one family: the statistical ones (and `others`
/// further statistical tests of the same run, e.g. chi-square suites) share the Šidák
/// correction at family-wise level `alpha`; exact ones are judged outside it. Returns
/// the family size k.
pub fn judge_family(outcomes: &mut [Outcome], others: usize, alpha: f64) -> usize {
    let k = outcomes.iter().filter(|o| o.is_statistical()).count() + others;
    for o in outcomes.iter_mut() {
        o.judge(alpha, k);
    }
    k
}

/// Every `.json` case file under the given files or folders (recursively), sorted.
pub fn collect_cases(paths: &[PathBuf]) -> Result<Vec<PathBuf>, InputError> {
    crate::io::collect_files(paths, true, |q| q.extension().is_some_and(|x| x == "json"))
}
