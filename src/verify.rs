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
//! **Verdict.** With independent samples the z test uses the plain standard error,
//! unless the batch-means error exceeds it by half (heavy tails), when the batch-means
//! t test (127 degrees of freedom) decides; quasi-random samplers are always judged by
//! batch means, each batch being an independent randomisation. A zero-variance
//! estimator is compared at the resolution of f32 evaluation (2e-6 relative).

use crate::bsdf::Bsdf;
use crate::error::{InputError, check_number, parse_json};
use crate::sampling::{SampleStream, SamplerKind};
use crate::scene::Scene;
use crate::scene::load::SceneDesc;
use crate::spectrum::Response;
use crate::stats::{MeanTest, Verdict};
use crate::transport::effects::{Effects, analyze};
use crate::transport::engine::{BATCHES, Estimate, RunSpec, run};
use crate::transport::measure::Measure;
use crate::transport::path::Config;
use crate::transport::phase::Dimensions;
mod dimensions;
use crate::transport::{Estimator, Heuristic};
use dimensions::dimensions;
use glam::{DVec3, Vec3};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Default samples per estimate.
pub const DEFAULT_SAMPLES: u64 = 1 << 18;

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

fn unit(file: &str, field: &str, a: [f64; 3]) -> Result<Vec3, InputError> {
    let v = DVec3::from_array(a);
    if !v.is_finite() || !(v.length() > 0.0) {
        return Err(InputError::new(
            file,
            field,
            format!("must be a finite non-zero vector, got {a:?}"),
        ));
    }
    Ok(v.normalize().as_vec3())
}

fn point(file: &str, field: &str, a: [f64; 3]) -> Result<DVec3, InputError> {
    let v = DVec3::from_array(a);
    if !v.is_finite() {
        return Err(InputError::new(
            file,
            field,
            format!("must be three finite numbers, got {a:?}"),
        ));
    }
    Ok(v)
}

impl Case {
    /// Load and validate a case file.
    pub fn load(path: &Path) -> Result<Case, InputError> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path)
            .map_err(|e| InputError::new(&file, "-", format!("cannot read the file: {e}")))?;
        let desc: CaseDesc = parse_json(&file, &text)?;
        Case::from_desc(desc, path)
    }

    /// Validate a parsed description (`path` names it and anchors relative paths).
    pub fn from_desc(desc: CaseDesc, path: &Path) -> Result<Case, InputError> {
        let file = path.display().to_string();
        let f = file.as_str();
        let origin = match &desc.measure {
            MeasureDesc::SolidAngle { from, .. }
            | MeasureDesc::ProjectedSolidAngle { from, .. } => point(f, "measure.from", *from)?,
            MeasureDesc::Irradiance { at, .. } | MeasureDesc::Radiance { at, .. } => {
                point(f, "measure.at", *at)?
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
                from: rebased(point(f, "measure.from", *from)?),
                shape: shape_index("measure.shape", *shape)?,
            },
            MeasureDesc::ProjectedSolidAngle {
                from,
                normal,
                shape,
            } => Measure::ProjectedSolidAngle {
                from: rebased(point(f, "measure.from", *from)?),
                normal: unit(f, "measure.normal", *normal)?,
                shape: shape_index("measure.shape", *shape)?,
            },
            MeasureDesc::Irradiance { at, normal } => Measure::Irradiance {
                at: rebased(point(f, "measure.at", *at)?),
                normal: unit(f, "measure.normal", *normal)?,
            },
            MeasureDesc::Radiance { at, direction } => Measure::Radiance {
                at: rebased(point(f, "measure.at", *at)?),
                direction: unit(f, "measure.direction", *direction)?,
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
                direction: unit(f, "measure.direction", *direction)?,
            },
            MeasureDesc::MeanPathLength { shape, segments } => Measure::MeanPathLength {
                shape: shape_index("measure.shape", *shape)?,
                segments: (*segments).clamp(1, 1 << 16),
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
            && n < 2 * BATCHES
        {
            return Err(InputError::new(
                f,
                "samples",
                format!("must be at least {} (two per batch), got {n}", 2 * BATCHES),
            ));
        }
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

/// Judge an estimate against a reference within a family of `tests` tests at level `alpha`.
pub fn judge(
    est: &Estimate,
    sampler: SamplerKind,
    reference: f64,
    alpha: f64,
    tests: usize,
) -> Verdict {
    let t = MeanTest::new(alpha, tests);
    let total = &est.batches.total;
    let plain = total.std_error();
    let batch = est.batches.std_error();
    let use_batches = sampler != SamplerKind::Independent || batch > 1.5 * plain;
    let (se, dof) = if use_batches {
        (batch, Some(est.batches.dof()))
    } else {
        (plain, None)
    };
    let floor = 2e-6 * total.mean.abs();
    t.judge_parts(
        total.mean,
        se.max(floor),
        reference,
        dof,
        total.non_finite,
        total.count,
    )
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
    /// Standard error used by the verdict (plain or batch means).
    pub std_error: f64,
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
    /// Whether it passed (a case without reference passes unless a sample was non-finite).
    pub fn passed(&self) -> bool {
        self.verdict.as_ref().is_none_or(|v| v.passed)
    }
}

/// Per-test seed: the base seed mixed with the case, estimator and sampler, so tests are
/// independent (Šidák is exact) and reproducible.
pub fn seed_for(base: u64, case: &str, est: Estimator, sampler: SamplerKind) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    for b in case
        .bytes()
        .chain(est.name().bytes())
        .chain(sampler.name().bytes())
    {
        h = (h ^ b as u64).wrapping_mul(0x100_0000_01b3);
    }
    crate::sampling::sampler::hash_words(&[base, h])
}

/// Run every estimator × sampler of a case and judge them in a family of `tests` tests.
pub fn run_case(
    case: &Case,
    base_seed: u64,
    samples: Option<u64>,
    scale: u64,
    alpha: f64,
    tests: usize,
) -> Vec<Outcome> {
    let mut out = Vec::new();
    for sampler in case.samplers() {
        for &est in &case.desc.estimators {
            let n = samples.or(case.desc.samples).unwrap_or(DEFAULT_SAMPLES) * scale.max(1);
            let seed = seed_for(base_seed, &case.desc.name, est, sampler);
            let spec = RunSpec {
                samples: n,
                sampler,
                seed,
            };
            let e = case.estimate(est, &spec, false);
            let verdict = case.reference.map(|r| judge(&e, sampler, r, alpha, tests));
            out.push(Outcome {
                case: case.desc.name.clone(),
                file: case.file.display().to_string(),
                measure: case.measure.name().to_string(),
                estimator: est,
                sampler,
                samples: e.batches.total.count + e.batches.total.non_finite,
                seed,
                estimate: e.batches.total.mean,
                std_error: verdict
                    .as_ref()
                    .map_or(e.batches.total.std_error(), |v| v.std_error),
                seconds: e.seconds,
                effects: case.effects.clone(),
                reference: case.reference,
                z: verdict.as_ref().map(|v| v.z),
                verdict,
            });
        }
    }
    out
}

/// Every `.json` case file under the given files or folders, sorted.
pub fn collect_cases(paths: &[PathBuf]) -> Result<Vec<PathBuf>, InputError> {
    let mut out = Vec::new();
    for p in paths {
        if p.is_dir() {
            let mut stack = vec![p.clone()];
            while let Some(d) = stack.pop() {
                let rd = std::fs::read_dir(&d).map_err(|e| {
                    InputError::new(
                        d.display().to_string(),
                        "-",
                        format!("cannot read folder: {e}"),
                    )
                })?;
                for entry in rd.flatten() {
                    let q = entry.path();
                    if q.is_dir() {
                        stack.push(q);
                    } else if q.extension().is_some_and(|x| x == "json") {
                        out.push(q);
                    }
                }
            }
        } else if p.exists() {
            out.push(p.clone());
        } else {
            return Err(InputError::new(
                p.display().to_string(),
                "-",
                "no such file or folder",
            ));
        }
    }
    out.sort();
    Ok(out)
}

/// Number of verdicts a list of cases will produce (for the Šidák correction).
pub fn count_tests(cases: &[Case]) -> usize {
    cases
        .iter()
        .filter(|c| c.reference.is_some())
        .map(|c| c.desc.estimators.len() * c.samplers().len())
        .sum()
}
