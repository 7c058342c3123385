//! Building a case from its description, in small steps each named after what it checks:
//! the origin the scene is rebased on, the measurement, the estimators, the sample count,
//! the `spectral` and `time` sections, the reference. Every step names the file and the
//! field it rejects.

use super::schema::{CaseDesc, MeasureDesc};
use super::{BATCHES, MAX_SAMPLES, MIN_SAMPLES};
use crate::bsdf::microfacet::{Distribution, MAX_ALPHA, Masking, Microfacet};
use crate::error::{InputError, check_direction, check_number, check_point};
use crate::scene::Scene;
use crate::transport::measure::Measure;
use crate::transport::microfacet_integral::MicrofacetIntegral;
use crate::transport::path::MAX_PATH_BOUNCES;
use glam::DVec3;

/// Longest wavelength of a `spectral` section (nm): 1 cm. Far past the thermal
/// infrared, and λ + 1 nm is still a different `f32`.
pub const MAX_WAVELENGTH_NM: f64 = 1e7;

pub use crate::spectrum::MIN_RELATIVE_BANDWIDTH;

/// The point the scene is rebased on (in f64, before it becomes f32): the measurement's
/// viewpoint where it has one, so precision is best where it is measured.
pub fn origin(f: &str, desc: &CaseDesc) -> Result<DVec3, InputError> {
    Ok(match &desc.measure {
        MeasureDesc::SolidAngle { from, .. } | MeasureDesc::ProjectedSolidAngle { from, .. } => {
            check_point(f, &desc.measure.field("from"), *from)?
        }
        MeasureDesc::Irradiance { at, .. } | MeasureDesc::Radiance { at, .. } => {
            check_point(f, &desc.measure.field("at"), *at)?
        }
        // The receiver's own point: precision is best where the flux arrives.
        MeasureDesc::Flux { shape, .. } => desc.scene.shape_point(*shape),
        // No viewpoint: a property of one object, rebased on any point of the scene.
        MeasureDesc::Albedo { .. }
        | MeasureDesc::Microfacet { .. }
        | MeasureDesc::Power { .. }
        | MeasureDesc::Intensity { .. }
        | MeasureDesc::MeanPathLength { .. } => desc.scene.any_point(),
    })
}

/// The instant that becomes the scene's time 0 (s): the shutter's start t₀ where the case
/// gives a finite one, else 0. Moving objects are placed where they are at t₀ (in f64)
/// and time is sampled as τ = t − t₀ ∈ [0, t₁ − t₀] in f32, so a shutter far from t = 0
/// keeps its resolution (at t = 10⁶ s, f32 seconds step by 1/16 s).
pub fn epoch(desc: &CaseDesc) -> f64 {
    match desc.time.as_ref().and_then(|t| t.shutter) {
        Some([t0, _]) if t0.is_finite() => t0,
        _ => 0.0,
    }
}

/// Shape `i` of the scene, or an error naming `field`.
fn shape_index(f: &str, scene: &Scene, field: &str, i: usize) -> Result<usize, InputError> {
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
}

/// The emitter a power or intensity measurement names by `shape` or by `emitter` (an
/// entry of `scene.emitters`, after the area lights): exactly one of them, and finite.
fn emitter_index(
    f: &str,
    scene: &Scene,
    measure: &MeasureDesc,
    shape: Option<usize>,
    emitter: Option<usize>,
) -> Result<usize, InputError> {
    let field = |name: &str| measure.field(name);
    let n_area = scene.shapes.iter().filter(|s| s.emitter.is_some()).count();
    let idx = match (shape, emitter) {
        (Some(s), None) => scene.shapes[shape_index(f, scene, &field("shape"), s)?]
            .emitter
            .ok_or_else(|| {
                InputError::new(f, field("shape"), format!("shape {s} does not emit"))
            })?,
        (None, Some(e)) if e < scene.emitters.len() - n_area => n_area + e,
        (None, Some(e)) => {
            return Err(InputError::new(
                f,
                field("emitter"),
                format!("emitter {e} does not exist"),
            ));
        }
        _ => {
            return Err(InputError::new(
                f,
                format!("measure.{}", measure.key()),
                "give exactly one of `shape` or `emitter`",
            ));
        }
    };
    if scene.emitters[idx].kind.is_infinite() {
        return Err(InputError::new(
            f,
            format!("measure.{}", measure.key()),
            "power and intensity are not defined for emitters at infinity",
        ));
    }
    Ok(idx)
}

/// The flux measurement onto receiver `shape`: its anchor (the centre of its bounds, so
/// a sphere's centre) and its factor, 1, or 1/(π L A) of the scene's one emitter for a
/// view factor (one-sided, grey, steady, still, and not the receiver itself).
fn flux(f: &str, scene: &Scene, shape: usize, view_factor: bool) -> Result<Measure, InputError> {
    let field = "measure.flux.shape";
    let shape = shape_index(f, scene, field, shape)?;
    let s = &scene.shapes[shape];
    if s.velocity != glam::Vec3::ZERO {
        return Err(InputError::new(
            f,
            field,
            "a moving receiver is not supported: give it no velocity",
        ));
    }
    let (lo, hi) = scene.prims()[s.prims.clone()]
        .iter()
        .map(|p| p.bounds())
        .fold((glam::Vec3::INFINITY, glam::Vec3::NEG_INFINITY), |a, b| {
            (a.0.min(b.0), a.1.max(b.1))
        });
    let anchor = (lo + hi) * 0.5;
    let mut factor = 1.0f32;
    if view_factor {
        use crate::scene::emitter::EmitterKind;
        let vf = "measure.flux.view_factor";
        let [e] = scene.emitters.as_slice() else {
            let shapes = scene.shapes.iter().filter(|s| s.emitter.is_some()).count();
            return Err(InputError::new(
                f,
                vf,
                format!(
                    "a view factor needs exactly one emitter, a shape with `emission`, and no other light; the scene has shapes with `emission`: {shapes}, other lights: {}",
                    scene.emitters.len().saturating_sub(shapes)
                ),
            ));
        };
        let EmitterKind::Area {
            shape: from,
            radiance,
            two_sided,
        } = e.kind
        else {
            return Err(InputError::new(
                f,
                vf,
                "a view factor is between two shapes: the emitter must be a shape with `emission`",
            ));
        };
        let grey_steady = e.props.spectrum.is_none()
            && e.props.pulse.is_none()
            && e.props.velocity == glam::Vec3::ZERO;
        let why = if from == shape {
            Some("the receiver is the emitter: name another shape")
        } else if two_sided {
            Some("the emitter is two-sided: a view factor is from one side")
        } else if !grey_steady {
            Some("the emitter must be grey, steady and still (no spectrum, pulse or velocity)")
        } else if !(radiance > 0.0) {
            Some("the emitter's radiance must be positive")
        } else {
            None
        };
        if let Some(why) = why {
            return Err(InputError::new(f, vf, why));
        }
        let norm = std::f64::consts::PI * radiance as f64 * scene.shapes[from].area as f64;
        factor = (1.0 / norm) as f32;
        if !(factor.is_finite() && factor > 0.0) {
            return Err(InputError::new(
                f,
                vf,
                format!("π L A of the emitter = {norm:e} does not give a finite f32 factor"),
            ));
        }
    }
    Ok(Measure::Flux {
        shape,
        anchor,
        factor,
    })
}

/// A view factor is geometry: the flux the receiver gets straight from a grey, steady
/// emitter, over π L A. A case that measures something else under that name is refused,
/// naming `measure.flux.view_factor`: a `spectral` section (a band integrated F over its
/// width: 60 for F = 0.2 over 300 nm), a time `bin` or `bins` (F times the bin's width),
/// or a scene whose light can scatter before it arrives (a material that is not black,
/// without `max_depth` 1: C-14's rectangles of albedo 0.9 read 0.216 for F = 0.200).
pub fn check_view_factor(f: &str, desc: &CaseDesc, scene: &Scene) -> Result<(), InputError> {
    let MeasureDesc::Flux {
        view_factor: true, ..
    } = desc.measure
    else {
        return Ok(());
    };
    let timed = desc
        .time
        .as_ref()
        .is_some_and(|t| t.bin.is_some() || t.bins.is_some());
    let scatters = scene.shapes.iter().any(|s| {
        s.material
            .is_some_and(|m| !crate::bsdf::ModelFacts::is_black(&scene.materials[m].bsdf))
    });
    let why = if desc.spectral.is_some() {
        Some("a view factor is not spectral: leave out the `spectral` section")
    } else if timed {
        Some("a view factor is not time resolved: leave out `time.bin` and `time.bins`")
    } else if scatters && desc.max_depth != Some(1) {
        Some(
            "a material here scatters light, which would add interreflections to the view factor: make every material black, or give `max_depth` 1 (direct light only)",
        )
    } else {
        None
    };
    why.map_or(Ok(()), |w| {
        Err(InputError::new(f, "measure.flux.view_factor", w))
    })
}

/// An irradiance receiver off the surface of a sphere, spherical-cap, disk or annulus
/// light (a moving one in its rest frame over the shutter of length `shutter`,
/// `scene::emitter::within_surface_band_moving`) yet within that surface's `f32` error
/// band, and near it: there it cannot
/// be told from a point of the surface, which light sampling treats it as (by area over
/// the whole surface, where the receiver sees a patch of relative area ~gap/size), so
/// `light` read 0 for ≈ πL (just outside a sphere at a gap of 9.5·10⁻⁷ r; 10⁻⁷ inside a
/// unit sphere light and 5·10⁻⁷ inside a 60° cap, facing the wall; 10⁻⁶ above a tilted
/// unit disk, and 2·10⁻⁶ beyond its rim for E ≈ 0.17) while `bsdf` and `mis` were right.
/// Refused, naming `measure.irradiance.at`, the light and the least gap
/// (`scene::emitter::within_surface_band`). A receiver exactly on the sphere or plane is
/// the surface's own point and is kept.
pub fn check_receiver_clear_of_light_surfaces(
    f: &str,
    measure: &Measure,
    scene: &Scene,
    shutter: f64,
) -> Result<(), InputError> {
    let Measure::Irradiance { at, .. } = *measure else {
        return Ok(());
    };
    for (k, s) in scene.shapes.iter().enumerate() {
        if s.emitter.is_none() {
            continue;
        }
        for prim in &scene.prims()[s.prims.clone()] {
            if let Some(band) =
                crate::scene::emitter::within_surface_band_moving(prim, at, s.velocity, shutter)
            {
                return Err(InputError::new(
                    f,
                    "measure.irradiance.at",
                    format!(
                        "lies within {band:e} of the surface of light scene.shapes[{k}] ({}), the f32 error bound of a point on it, and near it: indistinguishable from a point of that surface, which light sampling treats it as; place the receiver at least {band:e} away, or on the surface",
                        prim.kind_name()
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// The length of the case's shutter (s; 0 without one): moving shapes sit at `velocity ·
/// τ` from their rest positions for τ in [0, this] ([`epoch`]).
pub fn shutter_length(desc: &CaseDesc) -> f64 {
    match desc.time.as_ref().and_then(|t| t.shutter) {
        Some([t0, t1]) if t1 - t0 > 0.0 => t1 - t0,
        _ => 0.0,
    }
}

/// The measurement in engine coordinates (rebased on `origin`).
pub fn measure(
    f: &str,
    measure: &MeasureDesc,
    scene: &Scene,
    origin: DVec3,
) -> Result<Measure, InputError> {
    let rebased = |p: DVec3| (p - origin).as_vec3();
    let field = |name: &str| measure.field(name);
    let shape_index = |i: usize| shape_index(f, scene, &field("shape"), i);
    Ok(match measure {
        MeasureDesc::SolidAngle { from, shape } => Measure::SolidAngle {
            from: rebased(check_point(f, &field("from"), *from)?),
            shape: shape_index(*shape)?,
        },
        MeasureDesc::ProjectedSolidAngle {
            from,
            normal,
            shape,
        } => Measure::ProjectedSolidAngle {
            from: rebased(check_point(f, &field("from"), *from)?),
            normal: check_direction(f, &field("normal"), *normal)?.as_vec3(),
            shape: shape_index(*shape)?,
        },
        MeasureDesc::Irradiance { at, normal } => Measure::Irradiance {
            at: rebased(check_point(f, &field("at"), *at)?),
            normal: check_direction(f, &field("normal"), *normal)?.as_vec3(),
        },
        MeasureDesc::Radiance { at, direction } => Measure::Radiance {
            at: rebased(check_point(f, &field("at"), *at)?),
            direction: check_direction(f, &field("direction"), *direction)?.as_vec3(),
        },
        MeasureDesc::Albedo {
            bsdf,
            theta_degrees,
            phi_degrees,
        } => {
            bsdf.validate().map_err(|r| {
                InputError::new(f, format!("measure.albedo.bsdf.{}", r.field), r.reason)
            })?;
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
        MeasureDesc::Microfacet {
            distribution,
            alpha,
            theta_degrees,
            integral,
        } => microfacet_measure(f, *distribution, *alpha, *theta_degrees, *integral)?,
        MeasureDesc::Power { shape, emitter } => Measure::Power {
            emitter: emitter_index(f, scene, measure, *shape, *emitter)?,
        },
        MeasureDesc::Intensity {
            shape,
            emitter,
            direction,
        } => Measure::Intensity {
            emitter: emitter_index(f, scene, measure, *shape, *emitter)?,
            direction: check_direction(f, &field("direction"), *direction)?.as_vec3(),
        },
        MeasureDesc::Flux { shape, view_factor } => flux(f, scene, *shape, *view_factor)?,
        MeasureDesc::MeanPathLength { shape, segments } => Measure::MeanPathLength {
            shape: shape_index(*shape)?,
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
    })
}

/// The smallest α the `microfacet` measurement accepts: its estimators draw normals
/// that know nothing of D, and a lobe of width α catches a fraction ~α² of them (at
/// α = 0.01 and 2²⁰ samples 50 to 100 of them; at 10⁻³ about one, where the case passes with a
/// detectable bias of 285%; at 10⁻⁴ none, where it fails a correct engine).
const MICROFACET_MEASURE_MIN_ALPHA: f64 = 0.01;

/// A microfacet-integral measurement: α in [[`MICROFACET_MEASURE_MIN_ALPHA`], 1], θo in
/// [0, 90] (below 90 for the visible normals, which divide by cos θo), given exactly for
/// the integrals that depend on ωo.
fn microfacet_measure(
    f: &str,
    distribution: Distribution,
    alpha: f64,
    theta_degrees: Option<f64>,
    integral: MicrofacetIntegral,
) -> Result<Measure, InputError> {
    check_number(
        f,
        "measure.microfacet.alpha",
        alpha,
        |a| (MICROFACET_MEASURE_MIN_ALPHA..=MAX_ALPHA as f64).contains(&a),
        "in [0.01, 1] (normals drawn uniformly or by cosine land in a lobe of width α a \
         fraction ~α² of the time: below 0.01 the estimate cannot resolve D; the BSDF \
         suite's near-delta chi-square proves narrower lobes)",
    )?;
    let field = "measure.microfacet.theta_degrees";
    let theta_degrees = match (integral.depends_on_wo(), theta_degrees) {
        (true, Some(t)) => t,
        (true, None) => {
            return Err(InputError::new(
                f,
                field,
                "missing: this integral depends on ωo's polar angle",
            ));
        }
        (false, None) => 0.0,
        (false, Some(_)) => {
            return Err(InputError::new(
                f,
                field,
                "the normalisation ∫ D cos θm dm does not depend on ωo: leave it out",
            ));
        }
    };
    let (ok, what): (fn(f64) -> bool, _) = if integral.needs_wo_above() {
        (
            |t| (0.0..90.0).contains(&t),
            "in [0, 90) (D_ωo divides by cos θo)",
        )
    } else {
        (|t| (0.0..=90.0).contains(&t), "in [0, 90]")
    };
    check_number(
        f,
        "measure.microfacet.theta_degrees",
        theta_degrees,
        ok,
        what,
    )?;
    let t = theta_degrees.to_radians();
    Ok(Measure::Microfacet {
        microfacet: Microfacet::new(distribution, alpha as f32, Masking::HeightCorrelated),
        wo: DVec3::new(t.sin(), 0.0, t.cos()).as_vec3(),
        integral,
    })
}

/// At least one estimator, each one the measurement can use, at least one sampler if
/// the field is there, and no estimator or sampler listed twice.
pub fn check_estimators(f: &str, desc: &CaseDesc, measure: &Measure) -> Result<(), InputError> {
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
        if desc.estimators[..i].contains(e) {
            return Err(twice(f, format!("estimators[{i}]"), e.name()));
        }
    }
    let samplers = desc.samplers.as_deref().unwrap_or_default();
    if desc.samplers.is_some() && samplers.is_empty() {
        return Err(InputError::new(
            f,
            "samplers",
            "name at least one sampler (or leave the field out for `independent`)",
        ));
    }
    for (i, s) in samplers.iter().enumerate() {
        if samplers[..i].contains(s) {
            return Err(twice(f, format!("samplers[{i}]"), s.name()));
        }
    }
    Ok(())
}

/// An estimator or sampler listed twice: it would run the same series twice (same
/// seed), counting one test as two in the verdict's Šidák correction.
fn twice(f: &str, field: String, name: &str) -> InputError {
    InputError::new(f, field, format!("`{name}` is listed twice"))
}

/// The case's `max_depth` as the path tracer's bound on scatterings (`None`: unbounded):
/// 1 to [`MAX_PATH_BOUNCES`], on a measurement made of light paths
/// ([`Measure::bounces_for_depth`]).
pub fn max_bounces(f: &str, desc: &CaseDesc, measure: &Measure) -> Result<Option<u32>, InputError> {
    let Some(depth) = desc.max_depth else {
        return Ok(None);
    };
    if !(1..=MAX_PATH_BOUNCES).contains(&depth) {
        return Err(InputError::new(
            f,
            "max_depth",
            format!("must be 1 (direct light only) to {MAX_PATH_BOUNCES} scatterings, got {depth}"),
        ));
    }
    measure.bounces_for_depth(depth).map(Some).ok_or_else(|| {
        InputError::new(
            f,
            "max_depth",
            format!(
                "applies to measurements of light paths (irradiance, radiance, flux), not to {}",
                measure.name()
            ),
        )
    })
}

/// A sample count within [`MIN_SAMPLES`, `MAX_SAMPLES`].
pub fn check_samples(f: &str, desc: &CaseDesc) -> Result<(), InputError> {
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
    Ok(())
}

/// The wavelengths a case measures (nm), after [`check_spectral_and_time`]: its
/// `spectral.band`, [λ, λ + 1] for one `spectral.wavelength` (as that check reads it),
/// else the visible range. A dispersive index is checked over this band only.
pub fn measured_band(desc: &CaseDesc) -> crate::spectrum::Band {
    use crate::spectrum::Band;
    match desc.spectral.as_ref().map(|s| (s.band, s.wavelength)) {
        Some((Some([a, b]), None)) => Band::new(a as f32, b as f32),
        Some((None, Some(l))) => Band::new(l as f32, l as f32 + 1.0),
        _ => crate::spectrum::VISIBLE,
    }
}

/// The `spectral` and `time` sections as `f32` sees them: wavelengths in
/// (0, [`MAX_WAVELENGTH_NM`]], a band at least [`MIN_RELATIVE_BANDWIDTH`] wide, every
/// dispersive index valid over the band actually measured (a Sellmeier pole inside it is
/// refused, not only inside the visible range), and moving geometry staying within
/// range over the shutter.
pub fn check_spectral_and_time(f: &str, desc: &CaseDesc) -> Result<(), InputError> {
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
                d.validate(m, band).map_err(|(path, r)| {
                    InputError::new(f, format!("scene.dispersion.{name}{path}"), r)
                })?;
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
                e.velocity()
                    .map(|v| (format!("scene.emitters[{i}].velocity"), v))
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

/// The reference: the named closed form of `lightproof-analytic` (the independent
/// oracle) at the given parameters, times an optional unit `scale`; finite or refused.
pub fn reference(f: &str, desc: &CaseDesc) -> Result<Option<f64>, InputError> {
    Ok(match &desc.reference {
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
                        InputError::new(f, "reference.scale", "must be a positive finite number")
                    })?,
            };
            let v = lightproof_analytic::catalog::evaluate(name, &params)
                .map_err(|e| InputError::new(f, reference_field(&e), e.to_string()))?;
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
    })
}

/// How far the reference `value` moves when the closed form is evaluated on the numbers
/// the engine's `f32` scene holds ([`as_engine_sees`]) rather than the case's own:
/// ρ = μ(f32 inputs) − μ (signed), scaled as the reference is. Every verdict accepts a
/// mean between μ and μ + ρ, each widened by its f32 bound
/// ([`crate::stats::MeanTest::with_input_rounding`]): an index η = 1.0001, which `f32`
/// holds as 1.00010001659, moves a conductor's ((η − 1)/(η + 1))² by 3.3·10⁻⁴ relative,
/// where a correct engine's exact verdict would otherwise fail by 40 times its f32 bound.
/// 0 where the rounded numbers leave the closed form's domain or give a non-finite value
/// (the strict test: the allowance never grows without a measured ρ).
pub fn reference_rounding(desc: &CaseDesc, origin: DVec3, value: f64) -> f64 {
    let Some(map) = &desc.reference else {
        return 0.0;
    };
    let Some(name) = map.get("closed_form").and_then(|v| v.as_str()) else {
        return 0.0;
    };
    let scale = map.get("scale").and_then(|v| v.as_f64()).unwrap_or(1.0);
    let mut params = map.clone();
    params.remove("closed_form");
    params.remove("scale");
    for (key, v) in params.iter_mut() {
        if engine_holds_as_given(name, key) {
            as_engine_sees(v, key, origin.to_array());
        }
    }
    match lightproof_analytic::catalog::evaluate(name, &params) {
        Ok(r) if (r * scale).is_finite() => r * scale - value,
        Ok(_) | Err(_) => 0.0,
    }
}

/// Whether the engine holds reference parameter `key` of closed form `name` as the `f32`
/// of the number the case gives: a point, an edge, a normal, a length, a radiance or a
/// material constant. Only these are rounded for ρ. A parameter the engine holds in
/// another form (an angle it turns into a direction or a cone's cosine, `theta`, `tilt`,
/// `half_angle`, `theta_max_degrees`; a time bin's edges, kept in `f64`; an area it
/// computes from the shape) is left as given, and so are wavelengths and temperatures,
/// which some paths keep in `f64` and others round: rounding the
/// angle θ near 90° moved a Lambertian intensity by 0.3% where the engine's direction
/// vector moved it by 2.5·10⁻⁸, and a wrong reference passed. Leaving a parameter out
/// makes ρ smaller, the strict side. A spot light keeps its axis and cone in `f64`.
fn engine_holds_as_given(name: &str, key: &str) -> bool {
    if name.starts_with("spot") && key == "axis" {
        return false;
    }
    is_point(key)
        || matches!(
            key,
            "edge_u"
                | "edge_v"
                | "normal"
                | "axis"
                | "radius"
                | "radius1"
                | "radius2"
                | "inner_radius"
                | "outer_radius"
                | "height"
                | "offset"
                | "distance"
                | "separation"
                | "length"
                | "width"
                | "common_edge"
                | "x0"
                | "radiance"
                | "emitted_radiance"
                | "intensity"
                | "albedo"
                | "eta"
                | "k"
                | "index_at_receiver"
                | "alpha"
                | "sigma"
                | "a"
                | "b"
                | "c"
                | "cos_theta"
        )
}

/// Whether reference parameter `key` names a point (or a list of points) of the scene,
/// which the loader rebases about the case's origin.
fn is_point(key: &str) -> bool {
    matches!(key, "center" | "corner" | "light" | "point" | "vertices")
}

/// What the engine's scene holds of the numbers of reference parameter `key`: points
/// (`center`, `corner`, `light`, `point`, `vertices`) as `o + f32(p − o)` about the
/// case's origin `o` (the loader rebases the scene there, [`origin`]), every other number
/// as its nearest `f32` (an integer too: 16 777 217 is no `f32`); nested arrays and
/// objects are walked. A model of the loader, not the loader: a length between two
/// points is rounded as a number. [`reference_rounding`] applies it to the parameters
/// the engine holds as given ([`engine_holds_as_given`]).
pub fn as_engine_sees(v: &mut serde_json::Value, key: &str, o: [f64; 3]) {
    let point = is_point(key);
    match v {
        serde_json::Value::Array(a) if point && a.len() == 3 && a.iter().all(|x| x.is_number()) => {
            for (i, x) in a.iter_mut().enumerate() {
                let p = x.as_f64().unwrap_or(f64::NAN);
                *x = serde_json::json!(o[i] + f64::from((p - o[i]) as f32));
            }
        }
        serde_json::Value::Number(n) => {
            if let Some(x) = n.as_f64() {
                *v = serde_json::json!(f64::from(x as f32));
            }
        }
        serde_json::Value::Array(a) => a.iter_mut().for_each(|x| as_engine_sees(x, key, o)),
        serde_json::Value::Object(m) => m.iter_mut().for_each(|(k, x)| as_engine_sees(x, k, o)),
        serde_json::Value::Null | serde_json::Value::Bool(_) | serde_json::Value::String(_) => {}
    }
}

/// The field of a closed form's refusal: `reference.PARAM` for a parameter that is
/// missing, unknown or invalid, `reference.closed_form` for an unknown name, `reference`
/// for parameters that are valid one by one but not together.
fn reference_field(e: &lightproof_analytic::catalog::CatalogError) -> String {
    use lightproof_analytic::catalog::CatalogError;
    match e {
        CatalogError::UnknownClosedForm { .. } => "reference.closed_form".to_string(),
        CatalogError::MissingParameter { param, .. }
        | CatalogError::InvalidParameter { param, .. } => format!("reference.{param}"),
        CatalogError::UnknownParameter { param, .. } => format!("reference.{param}"),
        CatalogError::Domain { .. } => "reference".to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    /// A case description with `extra` fields over a minimal microfacet case.
    fn desc(extra: serde_json::Value) -> CaseDesc {
        let mut v = json!({
            "name": "t",
            "teaches": "t",
            "measure": {"microfacet": {"distribution": "ggx", "alpha": 0.5,
                                       "integral": "normalisation"}},
            "estimators": ["uniform"]
        });
        for (k, x) in extra.as_object().unwrap() {
            v[k] = x.clone();
        }
        serde_json::from_value(v).unwrap()
    }

    fn mf(alpha: f64, theta: f64, integral: MicrofacetIntegral) -> Result<Measure, InputError> {
        let theta = integral.depends_on_wo().then_some(theta);
        microfacet_measure("c.json", Distribution::Beckmann, alpha, theta, integral)
    }

    #[test]
    fn microfacet_ranges_are_inclusive_except_the_visible_horizon() {
        use MicrofacetIntegral::{Normalisation, ProjectedArea, Visible};
        for (alpha, ok) in [
            (0.01, true),
            (1.0, true),
            (0.0099, false),
            (1e-4, false),
            (1.01, false),
        ] {
            let r = mf(alpha, 30.0, Normalisation);
            assert_eq!(r.is_ok(), ok, "α {alpha}");
            if let Err(e) = r {
                assert_eq!(e.field, "measure.microfacet.alpha");
            }
        }
        for (theta, integral, ok) in [
            (0.0, Visible, true),
            (89.9, Visible, true),
            (90.0, Visible, false),
            (90.0, ProjectedArea, true),
            (90.1, ProjectedArea, false),
            (-0.1, ProjectedArea, false),
        ] {
            let r = mf(0.5, theta, integral);
            assert_eq!(r.is_ok(), ok, "θ {theta} {integral:?}");
            if let Err(e) = r {
                assert_eq!(e.field, "measure.microfacet.theta_degrees");
            }
        }
        // θo is required where the integral depends on it and refused where it does not.
        let theta_of = |theta: Option<f64>, integral| {
            microfacet_measure("c.json", Distribution::Ggx, 0.5, theta, integral)
        };
        for integral in [ProjectedArea, Visible] {
            let e = theta_of(None, integral).expect_err("θo missing");
            assert_eq!(e.field, "measure.microfacet.theta_degrees");
            assert!(e.reason.contains("missing"), "{}", e.reason);
        }
        let e = theta_of(Some(0.0), Normalisation).expect_err("θo refused");
        assert_eq!(e.field, "measure.microfacet.theta_degrees");
        assert!(e.reason.contains("does not depend on ωo"), "{}", e.reason);
        assert!(theta_of(None, Normalisation).is_ok());
        // θo = 60° in the xz plane; the model is the named one at that α.
        let Ok(Measure::Microfacet { microfacet, wo, .. }) = mf(0.25, 60.0, Visible) else {
            panic!("a microfacet measure")
        };
        assert!((wo - glam::Vec3::new(0.75f32.sqrt(), 0.0, 0.5)).length() < 1e-6);
        assert_eq!(microfacet.alpha, 0.25);
        assert_eq!(microfacet.distribution, Distribution::Beckmann);
    }

    #[test]
    fn samples_lie_within_their_inclusive_range() {
        for (n, ok) in [
            (MIN_SAMPLES, true),
            (MAX_SAMPLES, true),
            (MIN_SAMPLES - 1, false),
            (MAX_SAMPLES + 1, false),
        ] {
            let r = check_samples("c.json", &desc(json!({ "samples": n })));
            assert_eq!(r.is_ok(), ok, "{n}");
        }
        assert!(check_samples("c.json", &desc(json!({}))).is_ok());
    }

    #[test]
    fn max_depth_applies_to_light_paths_within_its_range() {
        let irr = Measure::Irradiance {
            at: glam::Vec3::ZERO,
            normal: glam::Vec3::Z,
        };
        let d = |k: u32| desc(json!({ "max_depth": k }));
        assert_eq!(max_bounces("c.json", &desc(json!({})), &irr).unwrap(), None);
        // The receiver is the first scattering: depth k is k − 1 bounces.
        assert_eq!(max_bounces("c.json", &d(1), &irr).unwrap(), Some(0));
        assert_eq!(
            max_bounces("c.json", &d(MAX_PATH_BOUNCES), &irr).unwrap(),
            Some(MAX_PATH_BOUNCES - 1)
        );
        for bad in [0, MAX_PATH_BOUNCES + 1] {
            let e = max_bounces("c.json", &d(bad), &irr).unwrap_err();
            assert_eq!(e.field, "max_depth");
        }
        let m = mf(0.5, 0.0, MicrofacetIntegral::Normalisation).unwrap();
        let e = max_bounces("c.json", &d(2), &m).unwrap_err();
        assert!(e.reason.contains("light paths"), "{e}");
    }

    #[test]
    fn estimators_are_named_and_fit_the_measurement() {
        let m = mf(0.5, 0.0, MicrofacetIntegral::Normalisation).unwrap();
        assert!(check_estimators("c.json", &desc(json!({})), &m).is_ok());
        let e = check_estimators("c.json", &desc(json!({ "estimators": [] })), &m).unwrap_err();
        assert_eq!(e.field, "estimators");
        // An empty sampler list is refused as an empty estimator list is (it ran the
        // default `independent` silently); a list left out is that default.
        let e = check_estimators("c.json", &desc(json!({ "samplers": [] })), &m).unwrap_err();
        assert_eq!(e.field, "samplers");
        assert!(e.reason.contains("at least one sampler"), "{e}");
        let two = desc(json!({ "estimators": ["cosine", "light"] }));
        let e = check_estimators("c.json", &two, &m).unwrap_err();
        assert_eq!(e.field, "estimators[1]");
        // Listed twice: the second is at fault, for estimators and samplers alike.
        for (extra, field, reason) in [
            (
                json!({ "estimators": ["cosine", "uniform", "cosine"] }),
                "estimators[2]",
                "`cosine` is listed twice",
            ),
            (
                json!({ "samplers": ["sobol", "independent", "sobol"] }),
                "samplers[2]",
                "`sobol` is listed twice",
            ),
        ] {
            let e = check_estimators("c.json", &desc(extra), &m).unwrap_err();
            assert_eq!((e.field.as_str(), e.reason.as_str()), (field, reason));
        }
        assert!(
            check_estimators(
                "c.json",
                &desc(json!({ "samplers": ["sobol", "independent"] })),
                &m
            )
            .is_ok()
        );
    }

    #[test]
    fn wavelengths_and_bands_as_f32_sees_them() {
        let check = |s: serde_json::Value| check_spectral_and_time("c.json", &desc(s));
        let one = |l: f64| check(json!({ "spectral": { "wavelength": l } }));
        assert!(one(MAX_WAVELENGTH_NM).is_ok());
        assert!(one(0.5).is_ok());
        for bad in [0.0, MAX_WAVELENGTH_NM * 1.000_001] {
            assert_eq!(one(bad).unwrap_err().field, "spectral.wavelength");
        }
        let band = |a: f64, b: f64| check(json!({ "spectral": { "band": [a, b] } }));
        assert!(band(400.0, 700.0).is_ok());
        // 1e-4 of 500 nm is 0.05 nm: 0.06 passes, 0.04 is refused.
        assert!(band(500.0, 500.06).is_ok());
        for (a, b) in [
            (500.0, 500.04),
            (500.0, 500.0),
            (600.0, 500.0),
            (0.0, 500.0),
        ] {
            assert_eq!(band(a, b).unwrap_err().field, "spectral.band", "[{a}, {b}]");
        }
        assert!(band(400.0, MAX_WAVELENGTH_NM * 1.000_001).is_err());
        // An empty band is refused as an order error, before its width is looked at.
        let e = band(500.0, 500.0).unwrap_err();
        assert!(e.reason.contains("0 < λ₁ < λ₂"), "{e}");
    }

    #[test]
    fn moving_lights_stay_in_range_over_the_shutter() {
        // A point light at speed v over the shutter [t0, t1] travels v·max(|t0|, |t1|).
        let moving = |v: f64, t0: f64, t1: f64| {
            check_spectral_and_time(
                "c.json",
                &desc(json!({
                    "scene": { "emitters": [{ "type": "point", "position": [0, 0, 2],
                                               "intensity": 1, "velocity": [0, v, 0] }] },
                    "time": { "shutter": [t0, t1] }
                })),
            )
        };
        let lim = crate::error::MAX_COORDINATE;
        assert!(moving(1.5, -0.5, 2.0).is_ok());
        // Exactly at the limit is in range; twice it (from t1 = 2 or t0 = −2) is not.
        assert!(moving(lim, 0.0, 1.0).is_ok());
        for (t0, t1) in [(-0.5, 2.0), (-2.0, 0.5)] {
            let e = moving(lim, t0, t1).unwrap_err();
            assert_eq!(e.field, "scene.emitters[0].velocity", "[{t0}, {t1}]");
        }
    }

    #[test]
    fn the_reference_is_the_oracles_value_times_its_scale() {
        let r = |m: serde_json::Value| reference("c.json", &desc(json!({ "reference": m })));
        assert_eq!(reference("c.json", &desc(json!({}))).unwrap(), None);
        // ∫ D cos θ dm = 1 for every α: the oracle's value is 1.
        let norm = json!({"closed_form": "microfacet_normalisation",
                          "distribution": "ggx", "alpha": 0.3});
        let one = r(norm.clone()).unwrap().unwrap();
        assert!((one - 1.0).abs() < 1e-9, "{one}");
        let mut scaled = norm.clone();
        scaled["scale"] = json!(2.5);
        assert!((r(scaled.clone()).unwrap().unwrap() - 2.5).abs() < 1e-8);
        for bad in [json!(0.0), json!(-1.0), json!("two")] {
            scaled["scale"] = bad;
            assert_eq!(r(scaled.clone()).unwrap_err().field, "reference.scale");
        }
        // The mean chord of a sphere is 4r/3 (Cauchy): 40/3 for r = 10, which a scale
        // of 1e308 takes past f64's range: refused.
        let chord = r(json!({"closed_form": "mean_chord_sphere", "radius": 10})).unwrap();
        assert!((chord.unwrap() - 40.0 / 3.0).abs() < 1e-9);
        let e = r(json!({"closed_form": "mean_chord_sphere", "radius": 10, "scale": 1e308}))
            .unwrap_err();
        assert_eq!(e.field, "reference");
        assert!(
            e.reason.contains("give parameters where it is finite"),
            "{e}"
        );
        let e = r(json!({"distribution": "ggx"})).unwrap_err();
        assert_eq!(e.field, "reference.closed_form");
        let e = r(json!({"closed_form": "no_such_form"})).unwrap_err();
        assert_eq!(e.field, "reference.closed_form");
        // A parameter at fault is named by its path: invalid, missing or unknown.
        for (m, field) in [
            (
                json!({"closed_form": "mean_chord_sphere", "radius": -1}),
                "reference.radius",
            ),
            (
                json!({"closed_form": "mean_chord_sphere"}),
                "reference.radius",
            ),
            (
                json!({"closed_form": "mean_chord_sphere", "radius": 1, "colour": 1}),
                "reference.colour",
            ),
        ] {
            assert_eq!(r(m).unwrap_err().field, field);
        }
        // Parameters valid one by one whose value is not finite: the reference as a whole.
        let e = r(
            json!({"closed_form": "disk_irradiance_on_axis", "radius": 1, "height": 2,
                         "radiance": 1e308}),
        )
        .unwrap_err();
        assert_eq!(e.field, "reference", "{e}");
    }
    /// Two disks facing each other a unit apart: shape 0 (radius 1, at z = 1, facing
    /// down) emits L = 1 one-sided, shape 1 (radius ½, at the origin) does not; `extra`
    /// emitters follow the area light.
    /// The scene's time 0 is a finite shutter start; without one (or with one that is
    /// not finite, refused later by `check_spectral_and_time`), t = 0.
    #[test]
    fn the_epoch_is_the_shutters_start() {
        assert_eq!(
            epoch(&desc(json!({ "time": { "shutter": [1e6, 2e6] } }))),
            1e6
        );
        assert_eq!(
            epoch(&desc(json!({ "time": { "shutter": [-2.5, 1] } }))),
            -2.5
        );
        assert_eq!(epoch(&desc(json!({ "time": { "bin": [1, 2] } }))), 0.0);
        assert_eq!(epoch(&desc(json!({}))), 0.0);
        let mut d = desc(json!({ "time": { "shutter": [0, 1] } }));
        for t0 in [f64::NAN, f64::INFINITY] {
            d.time.as_mut().unwrap().shutter = Some([t0, 1.0]);
            assert_eq!(epoch(&d), 0.0, "{t0}");
        }
    }

    fn two_disks(measure: serde_json::Value, extra: serde_json::Value) -> CaseDesc {
        desc(json!({
            "scene": {
                "shapes": [
                    {"geometry": {"type": "disk", "center": [0, 0, 1], "normal": [0, 0, -1],
                                  "radius": 1}, "emission": {"radiance": 1}},
                    {"geometry": {"type": "disk", "center": [0, 0, 0], "normal": [0, 0, 1],
                                  "radius": 0.5}}
                ],
                "emitters": extra
            },
            "measure": measure
        }))
    }

    /// A time bin whose width is not a normal f32 (here 1e-45 s, subnormal, with normal
    /// edges) is refused naming `time.bin` (a steady emitter weighs paths by the width
    /// in f32); a width of f32::MIN_POSITIVE is accepted. Before the check,
    /// [2e-38, 2.0000001e-38] gave an estimate weighted by a subnormal width.
    #[test]
    fn a_time_bin_narrower_than_a_normal_f32_is_refused() {
        let case = |bin: [f64; 2]| {
            let mut d = two_disks(
                json!({"irradiance": {"at": [0, 0, 0], "normal": [0, 0, 1]}}),
                json!([]),
            );
            d.time = Some(serde_json::from_value(json!({ "bin": bin })).unwrap());
            crate::case::Case::from_desc(d, std::path::Path::new("c.json"))
        };
        for bin in [[2e-38, 2.0000001e-38], [1e-30, 1e-30 + 1e-39]] {
            let err = case(bin).err().unwrap();
            assert_eq!(err.field, "time.bin", "{bin:?}: {err}");
        }
        let min = f32::MIN_POSITIVE as f64;
        assert!(case([2e-38, 2e-38 + min]).is_ok());
        assert!(case([0.0, 1e-9]).is_ok());
        // An empty bin is refused for its order, before its width is looked at.
        let err = case([1.0, 1.0]).err().unwrap();
        assert!(err.to_string().contains("t₁ < t₂"), "{err}");
        // A shutter is sampled from its start (time τ = t − t₀): 10 ms at t = 10⁶ s is
        // resolved (f32 seconds there step by 1/16 s); a length below the smallest
        // normal f32 is refused, and so is one above f32::MAX.
        let shutter = |t: [f64; 2]| {
            let mut d = two_disks(
                json!({"irradiance": {"at": [0, 0, 0], "normal": [0, 0, 1]}}),
                json!([]),
            );
            d.time = Some(serde_json::from_value(json!({ "shutter": t })).unwrap());
            crate::case::Case::from_desc(d, std::path::Path::new("c.json"))
        };
        assert!(shutter([1e6, 1e6 + 0.01]).is_ok());
        assert!(shutter([1e-30, 1e-30 + min]).is_ok());
        for t in [[1e-30, 1e-30 + 1e-39], [-3e38, 3e38]] {
            let err = shutter(t).err().unwrap();
            assert!(
                err.field == "time.shutter" && err.to_string().contains("not a normal f32"),
                "{t:?}: {err}"
            );
        }
    }

    /// A pulse's arrivals are binned by the f32 path length ℓ (a step of 2⁻²³·ℓ, 0.4 fs
    /// of light at 1 m): a bin narrower than 10⁻⁴ of the time since the pulse is refused
    /// naming `time.bin` (`time.bins` for a histogram). The audit's 10 fs bins after the
    /// first arrival at 1 m read z = +9 … +13 and −9; 10⁻⁴·3.34 ns = 0.33 ps passes.
    #[test]
    fn a_time_bin_too_narrow_for_f32_path_lengths_is_refused() {
        let h = 1.0 / crate::spectrum::SPEED_OF_LIGHT;
        let pulsed = |time: serde_json::Value, pulse_at: f64| {
            let mut d = two_disks(
                json!({"irradiance": {"at": [0, 0, 0], "normal": [0, 0, 1]}}),
                json!([]),
            );
            let mut v = serde_json::to_value(&d.scene).unwrap();
            v["shapes"][0]["emission"]["pulse_at"] = json!(pulse_at);
            d.scene = serde_json::from_value(v).unwrap();
            d.time = Some(serde_json::from_value(time).unwrap());
            crate::case::Case::from_desc(d, std::path::Path::new("c.json"))
        };
        let err = pulsed(json!({"bin": [h, h + 1e-14]}), 0.0).err().unwrap();
        assert_eq!(err.field, "time.bin", "{err}");
        assert!(
            err.reason.contains("too narrow for f32 path lengths"),
            "{err}"
        );
        let edges: Vec<f64> = (0..4).map(|k| h + k as f64 * 1e-14).collect();
        let err = pulsed(json!({ "bins": edges }), 0.0).err().unwrap();
        assert_eq!(err.field, "time.bins", "{err}");
        assert!(pulsed(json!({"bin": [h, h + 3.4e-13]}), 0.0).is_ok());
        // Measured from the pulse: the same bin 10⁶ s after t = 0 passes for a pulse at
        // 10⁶ s, and is refused for one at 0 (a path 10⁶ light-seconds long).
        let far = [1e6 + h, 1e6 + h + 1e-9];
        assert!(pulsed(json!({ "bin": far }), 1e6).is_ok());
        assert_eq!(
            pulsed(json!({ "bin": far }), 0.0).err().unwrap().field,
            "time.bin"
        );
        // A pulse after the bin sends nothing into it, and a steady emitter none of ℓ.
        assert!(pulsed(json!({"bin": [h, h + 1e-14]}), 1.0).is_ok());
        let mut d = two_disks(
            json!({"irradiance": {"at": [0, 0, 0], "normal": [0, 0, 1]}}),
            json!([]),
        );
        d.time = Some(serde_json::from_value(json!({"bin": [h, h + 1e-14]})).unwrap());
        assert!(crate::case::Case::from_desc(d, std::path::Path::new("c.json")).is_ok());
    }

    /// The measurement as the case builds it (origin, scene, then the measure step).
    fn built(d: &CaseDesc) -> Result<Measure, InputError> {
        let origin = origin("c.json", d)?;
        let scene = d.scene.build(
            "c.json",
            "scene",
            std::path::Path::new("."),
            origin,
            epoch(d),
        )?;
        let m = measure("c.json", &d.measure, &scene, origin)?;
        check_view_factor("c.json", d, &scene)?;
        check_receiver_clear_of_light_surfaces("c.json", &m, &scene, shutter_length(d))?;
        Ok(m)
    }

    fn field(m: serde_json::Value, extra: serde_json::Value) -> String {
        built(&two_disks(m, extra)).unwrap_err().field
    }

    #[test]
    fn shapes_are_named_by_an_index_that_exists() {
        use glam::Vec3;
        for i in [0usize, 1] {
            let m = built(&two_disks(
                json!({"solid_angle": {"from": [3, 2, 5], "shape": i}}),
                json!([]),
            ));
            let Ok(Measure::SolidAngle { from, shape }) = m else {
                panic!("shape {i}: {m:?}")
            };
            assert_eq!(shape, i);
            // The scene is rebased on the viewpoint: it sits at the origin.
            assert_eq!(from, Vec3::ZERO);
        }
        let e = built(&two_disks(
            json!({"solid_angle": {"from": [3, 2, 5], "shape": 2}}),
            json!([]),
        ))
        .unwrap_err();
        assert_eq!(e.field, "measure.solid_angle.shape");
        assert!(e.reason.contains("the scene has 2 shapes"), "{e}");
    }

    #[test]
    fn power_names_one_finite_emitter() {
        let point = json!([{"type": "point", "position": [0, 0, 3], "intensity": 2}]);
        let emitter =
            |m: serde_json::Value, extra: serde_json::Value| match built(&two_disks(m, extra)) {
                Ok(Measure::Power { emitter }) => emitter,
                other => panic!("{other:?}"),
            };
        assert_eq!(emitter(json!({"power": {"shape": 0}}), point.clone()), 0);
        // Entries of `scene.emitters` come after the area lights.
        assert_eq!(emitter(json!({"power": {"emitter": 0}}), point.clone()), 1);
        let two = json!([{"type": "point", "position": [0, 0, 3], "intensity": 2},
                         {"type": "point", "position": [0, 1, 3], "intensity": 1}]);
        assert_eq!(emitter(json!({"power": {"emitter": 1}}), two), 2);
        assert_eq!(
            field(json!({"power": {"emitter": 1}}), point.clone()),
            "measure.power.emitter"
        );
        assert_eq!(
            field(json!({"power": {"shape": 1}}), point.clone()),
            "measure.power.shape"
        );
        assert_eq!(
            field(json!({"power": {"shape": 2}}), point.clone()),
            "measure.power.shape"
        );
        assert_eq!(
            field(json!({"power": {"shape": 0, "emitter": 0}}), point),
            "measure.power"
        );
        let sun = json!([{"type": "directional", "direction": [0, 0, -1], "irradiance": 1}]);
        assert_eq!(
            field(json!({"power": {"emitter": 0}}), sun),
            "measure.power"
        );
    }

    #[test]
    fn view_factors_divide_by_pi_l_a_of_the_one_emitter() {
        use glam::Vec3;
        // Receiver: shape 1, anchored at the centre of its bounds (the scene is rebased
        // on that point); factor 1/(π L A) = 1/(π · 1 · π).
        let m = built(&two_disks(
            json!({"flux": {"shape": 1, "view_factor": true}}),
            json!([]),
        ));
        let Ok(Measure::Flux {
            shape,
            anchor,
            factor,
        }) = m
        else {
            panic!("{m:?}")
        };
        assert_eq!(shape, 1);
        assert!(anchor.length() < 1e-6, "{anchor}");
        let want = 1.0 / (std::f64::consts::PI * std::f64::consts::PI);
        assert!((factor as f64 / want - 1.0).abs() < 1e-6, "{factor}");
        // Without a view factor the flux is plain.
        let Ok(Measure::Flux { factor, anchor, .. }) =
            built(&two_disks(json!({"flux": {"shape": 0}}), json!([])))
        else {
            panic!()
        };
        assert_eq!(factor, 1.0);
        assert_eq!(anchor, Vec3::ZERO);
        // A rectangle's anchor is the centre of its bounds, half its edges from the
        // corner the scene is rebased on.
        let rect = built(&desc(json!({
            "scene": {"shapes": [{"geometry": {"type": "rectangle", "corner": [3, 1, 0],
                                               "edge_u": [1, 0, 0], "edge_v": [0, 2, 0]}}]},
            "measure": {"flux": {"shape": 0}}
        })));
        let Ok(Measure::Flux { anchor, .. }) = rect else {
            panic!("{rect:?}")
        };
        assert!(
            (anchor - Vec3::new(0.5, 1.0, 0.0)).length() < 1e-6,
            "{anchor}"
        );
        let vf = "measure.flux.view_factor";
        // The receiver is the emitter; a second emitter; an emitter that is not a shape.
        assert_eq!(
            field(
                json!({"flux": {"shape": 0, "view_factor": true}}),
                json!([])
            ),
            vf
        );
        let point = json!([{"type": "point", "position": [0, 0, 3], "intensity": 2}]);
        assert_eq!(
            field(json!({"flux": {"shape": 1, "view_factor": true}}), point),
            vf
        );
        assert_eq!(
            field(json!({"flux": {"shape": 2}}), json!([])),
            "measure.flux.shape"
        );
    }

    #[test]
    fn mean_path_length_segments_and_albedo_angles_have_inclusive_ranges() {
        let segments = |n: u32| {
            built(&two_disks(
                json!({"mean_path_length": {"shape": 1, "segments": n}}),
                json!([]),
            ))
        };
        for (n, ok) in [
            (1, true),
            (1 << 16, true),
            (0, false),
            ((1 << 16) + 1, false),
        ] {
            assert_eq!(segments(n).is_ok(), ok, "{n}");
        }
        let Ok(Measure::MeanPathLength { segments: got, .. }) = segments(7) else {
            panic!()
        };
        assert_eq!(got, 7);
        let albedo = |theta: f64, phi: f64| {
            built(&two_disks(
                json!({"albedo": {"bsdf": {"type": "lambertian", "albedo": 0.5},
                              "theta_degrees": theta, "phi_degrees": phi}}),
                json!([]),
            ))
        };
        assert!(albedo(180.0, 0.0).is_ok() && albedo(0.0, 0.0).is_ok());
        assert!(albedo(180.1, 0.0).is_err() && albedo(-0.1, 0.0).is_err());
        // θ = 90°, φ = 90°: ωo = +y.
        let Ok(Measure::Albedo { wo, .. }) = albedo(90.0, 90.0) else {
            panic!()
        };
        assert!((wo - glam::Vec3::Y).length() < 1e-6, "{wo}");
        // θ = 60°, φ = 30°: ωo = (sin 60° cos 30°, sin 60° sin 30°, cos 60°).
        let Ok(Measure::Albedo { wo, .. }) = albedo(60.0, 30.0) else {
            panic!()
        };
        let want = glam::Vec3::new(0.75, 0.75f32.sqrt() * 0.5, 0.5);
        assert!((wo - want).length() < 1e-6, "{wo}");
    }
    /// The coaxial disks with the emitter's `emission` and the receiver's extra fields
    /// replaced, measured as a view factor onto shape 1.
    fn view_factor(
        emission: serde_json::Value,
        receiver: serde_json::Value,
    ) -> Result<Measure, InputError> {
        let mut d = json!({
            "shapes": [
                {"geometry": {"type": "disk", "center": [0, 0, 1], "normal": [0, 0, -1],
                              "radius": 1}, "emission": emission},
                {"geometry": {"type": "disk", "center": [0, 0, 0], "normal": [0, 0, 1],
                              "radius": 0.5}}
            ]
        });
        for (k, x) in receiver.as_object().unwrap() {
            d["shapes"][1][k] = x.clone();
        }
        built(&desc(json!({
            "scene": d,
            "measure": {"flux": {"shape": 1, "view_factor": true}}
        })))
    }

    /// The shutter's length: t₁ − t₀, 0 without a shutter (or one not open).
    #[test]
    fn the_shutter_length_is_its_span() {
        let with = |shutter: serde_json::Value| {
            shutter_length(&desc(json!({ "time": { "shutter": shutter } })))
        };
        assert_eq!(with(json!([2.0, 5.5])), 3.5);
        assert_eq!(with(json!([5.0, 2.0])), 0.0);
        assert_eq!(shutter_length(&desc(json!({}))), 0.0);
    }

    /// A receiver 4 ulps (4.8·10⁻⁷) above a sphere light of radius 0.5 lies within the
    /// band of its surface's error bound (7.2·10⁻⁷ here) and is refused, naming
    /// `measure.irradiance.at`; 8 ulps above, on the sphere, inside it, beside a sphere
    /// that does not emit, or measuring radiance there, it is taken; a moving light is
    /// checked in its rest frame over the shutter.
    #[test]
    fn a_receiver_within_a_light_surfaces_error_bound_is_refused() {
        let case = |z: f64, emits: bool, measure: &str| {
            let mut sphere = json!({"geometry": {"type": "sphere", "center": [0.25, -0.125, 0.5], "radius": 0.5}});
            if emits {
                sphere["emission"] = json!({"radiance": 1});
            }
            let dir = if measure == "irradiance" {
                "normal"
            } else {
                "direction"
            };
            built(&desc(json!({
                "scene": {"shapes": [sphere, {"geometry": {"type": "disk", "center": [9, 9, 9], "normal": [0, 0, 1], "radius": 1},
                          "emission": {"radiance": 1}}]},
                "measure": { measure: {"at": [0.25, -0.125, z], dir: [0, 0, -1]} }
            })))
        };
        let ulp = 2f64.powi(-23);
        let e = case(1.0 + 4.0 * ulp, true, "irradiance").unwrap_err();
        assert_eq!(e.field, "measure.irradiance.at");
        assert!(e.reason.contains("scene.shapes[0]"), "{e}");
        assert!(e.reason.contains("(sphere)"), "{e}");
        assert!(case(1.0 + ulp, true, "irradiance").is_err());
        // Inside, as outside (the cap's and disk's bands: `emitter::tests`, the corpus).
        for z in [1.0 - ulp, 1.0 - 4.0 * ulp] {
            assert_eq!(
                case(z, true, "irradiance").unwrap_err().field,
                "measure.irradiance.at"
            );
        }
        // A moving light in its rest frame: the receiver at the shutter's ends and where
        // it passes closest to the centre (a tilted disk moving in its own plane over a
        // receiver 1e-6 above its centre at mid-shutter); one that stays far is kept.
        let moving = |at: [f64; 3]| {
            built(&desc(json!({
                "scene": {"shapes": [{"geometry": {"type": "disk", "center": [-3, 0, 0], "normal": [0, 0.6, 0.8], "radius": 1},
                                      "emission": {"radiance": 1}, "velocity": [6, 0, 0]}]},
                "measure": {"irradiance": {"at": at, "normal": [0, -0.6, -0.8]}},
                "time": {"shutter": [0, 1]}
            })))
        };
        let e = moving([0.0, 6e-7, 8e-7]).unwrap_err();
        assert_eq!(e.field, "measure.irradiance.at");
        assert!(e.reason.contains("(disk)"), "{e}");
        assert!(moving([0.0, 6e-3, 8e-3]).is_ok());
        for ok in [
            case(1.0 + 8.0 * ulp, true, "irradiance"),
            case(1.0 - 8.0 * ulp, true, "irradiance"),
            case(1.0, true, "irradiance"),
            case(0.9, true, "irradiance"),
            case(1.0 + 4.0 * ulp, false, "irradiance"),
            case(1.0 + 4.0 * ulp, true, "radiance"),
        ] {
            assert!(ok.is_ok(), "{ok:?}");
        }
    }

    #[test]
    fn view_factors_need_a_one_sided_grey_steady_bright_emitter_and_a_still_receiver() {
        assert!(view_factor(json!({"radiance": 2}), json!({})).is_ok());
        let why = |emission: serde_json::Value| {
            let e = view_factor(emission, json!({})).unwrap_err();
            assert_eq!(e.field, "measure.flux.view_factor");
            e.reason
        };
        assert!(why(json!({"radiance": 1, "two_sided": true})).contains("two-sided"));
        assert!(why(json!({"radiance": 1, "pulse_at": 1e-9})).contains("grey, steady"));
        assert!(why(json!({"radiance": 0})).contains("must be positive"));
        // A faint, tiny emitter: π L A ≈ 1.2e-43 is fine as a power, but its inverse
        // overflows f32.
        let faint = built(&desc(json!({
            "scene": {"shapes": [
                {"geometry": {"type": "disk", "center": [0, 0, 1], "normal": [0, 0, -1],
                              "radius": 1e-3}, "emission": {"radiance": 1.2e-38}},
                {"geometry": {"type": "disk", "center": [0, 0, 0], "normal": [0, 0, 1],
                              "radius": 0.5}}
            ]},
            "measure": {"flux": {"shape": 1, "view_factor": true}}
        })))
        .unwrap_err();
        assert_eq!(faint.field, "measure.flux.view_factor");
        assert!(faint.reason.contains("finite f32 factor"), "{faint}");
        let e = view_factor(json!({"radiance": 1}), json!({"velocity": [0, 0, 1]})).unwrap_err();
        assert_eq!(e.field, "measure.flux.shape");
        assert!(e.reason.contains("moving receiver"), "{e}");
        // Geometry only: no spectral section, no time bin, no light scattered on the way
        // unless `max_depth` is 1 (a black material or a shutter changes nothing).
        let case = |scene_extra: serde_json::Value, extra: serde_json::Value| {
            let mut d = json!({
                "scene": {"shapes": [
                    {"geometry": {"type": "disk", "center": [0, 0, 1], "normal": [0, 0, -1],
                                  "radius": 1}, "emission": {"radiance": 1}},
                    {"geometry": {"type": "disk", "center": [0, 0, 0], "normal": [0, 0, 1],
                                  "radius": 0.5}, "material": "m"}],
                    "materials": {"m": {"type": "lambertian", "albedo": 0}}},
                "measure": {"flux": {"shape": 1, "view_factor": true}}
            });
            for (k, x) in scene_extra.as_object().unwrap() {
                d["scene"]["materials"]["m"][k] = x.clone();
            }
            for (k, x) in extra.as_object().unwrap() {
                d[k] = x.clone();
            }
            built(&desc(d)).map(|_| ()).map_err(|e| {
                assert_eq!(e.field, "measure.flux.view_factor");
                e.reason
            })
        };
        assert!(case(json!({}), json!({})).is_ok());
        assert!(case(json!({}), json!({"time": {"shutter": [0, 1]}})).is_ok());
        let grey = json!({"albedo": 0.9});
        assert!(case(grey.clone(), json!({"max_depth": 1})).is_ok());
        assert!(
            case(grey.clone(), json!({}))
                .unwrap_err()
                .contains("scatters")
        );
        assert!(
            case(grey, json!({"max_depth": 2}))
                .unwrap_err()
                .contains("scatters")
        );
        let spectral = json!({"spectral": {"band": [400, 700]}});
        assert!(
            case(json!({}), spectral)
                .unwrap_err()
                .contains("not spectral")
        );
        for time in [json!({"bin": [0, 1e-9]}), json!({"bins": [0, 1e-9, 2e-9]})] {
            let e = case(json!({}), json!({ "time": time })).unwrap_err();
            assert!(e.contains("not time resolved"), "{e}");
        }
    }
    #[test]
    fn one_wavelength_is_checked_as_the_nanometre_above_it() {
        // A weak Sellmeier pole at √0.25 µm = 500 nm (b = 0.001: n² stays positive up to
        // 0.5 nm below it): λ = 499.5 nm measures [499.5, 500.5] nm, which holds the pole;
        // λ = 501 nm measures [501, 502] nm, which does not.
        let at = |l: f64| {
            check_spectral_and_time(
                "c.json",
                &desc(json!({
                    "scene": {
                        "materials": {"glass": {"type": "dielectric", "eta": 1.5}},
                        "dispersion": {"glass": {"eta": {"sellmeier": {
                            "b": [0.001, 0.0, 0.0], "c": [0.25, 0.0, 0.0]}}}}
                    },
                    "spectral": {"wavelength": l}
                })),
            )
        };
        assert!(at(501.0).is_ok());
        let e = at(499.5).unwrap_err();
        assert_eq!(e.field, "scene.dispersion.glass.eta.sellmeier.c");
        assert!(e.reason.contains("pole"), "{e}");
    }

    /// A Sellmeier pole is checked against the wavelengths the case measures, through
    /// the whole build (the scene's own check once used [360, 830] nm whatever the
    /// case's band: a pole at 600 nm refused [400, 500] nm and λ = 500 nm). A pole inside
    /// the measured band is still refused, naming the dispersion entry.
    #[test]
    fn a_sellmeier_pole_is_checked_over_the_band_measured() {
        let case = |spectral: serde_json::Value| {
            let d = desc(json!({
                "scene": {
                    "materials": {"glass": {"type": "dielectric", "eta": 1.5}},
                    "dispersion": {"glass": {"eta": {"sellmeier": {
                        "b": [0.1, 0.0, 0.0], "c": [0.36, 0.0, 0.0]}}}},
                    "shapes": [
                        {"geometry": {"type": "disk", "center": [0, 0, 1], "normal": [0, 0, -1],
                                      "radius": 1}, "emission": {"radiance": 1}},
                        {"geometry": {"type": "disk", "center": [0, 0, 3], "normal": [0, 0, -1],
                                      "radius": 1}, "material": "glass"}
                    ]
                },
                "measure": {"radiance": {"at": [0, 0, 0], "direction": [0, 0, 1]}},
                "estimators": ["mis"],
                "spectral": spectral
            }));
            crate::case::Case::from_desc(d, std::path::Path::new("c.json"))
        };
        assert!(case(json!({"band": [400, 500]})).is_ok());
        assert!(case(json!({"wavelength": 500})).is_ok());
        assert!(case(json!({"band": [650, 800]})).is_ok());
        for spectral in [
            json!({"band": [500, 700]}),
            json!({"wavelength": 599.5}),
            json!({"band": [360, 830]}),
        ] {
            let e = case(spectral.clone()).err().unwrap();
            assert_eq!(
                e.field, "scene.dispersion.glass.eta.sellmeier.c",
                "{spectral}: {e}"
            );
            assert!(e.reason.contains("pole"), "{spectral}: {e}");
        }
    }

    /// A conductor at η = 1.0001 (which `f32` holds as 1.00010001659): the reference
    /// F = ((η − 1)/(η + 1))² moves by ρ = +3.3·10⁻⁴ relative at the engine's inputs, and
    /// the engine's exact estimate, which is F at its own η, is off from the case's F by
    /// about ρ: it passes with ρ in its allowance (it failed by 40 times the f32 bound
    /// without), and a reference at η = 1.0002 still fails. An index `f32` holds exactly
    /// moves nothing.
    #[test]
    fn references_move_with_the_engines_f32_inputs() {
        let case = |bsdf_eta: f64, ref_eta: f64| {
            let d: CaseDesc = serde_json::from_value(json!({
                "name": "near one", "teaches": "t", "exact": "every sample is F",
                "measure": {"albedo": {"bsdf": {"type": "conductor", "eta": bsdf_eta, "k": 0},
                                       "theta_degrees": 0}},
                "reference": {"closed_form": "fresnel_conductor", "cos_theta": 1,
                              "eta": ref_eta, "k": 0},
                "estimators": ["bsdf"]
            }))
            .unwrap();
            crate::case::Case::from_desc(d, std::path::Path::new("c.json")).unwrap()
        };
        let fresnel = |eta: f64| ((eta - 1.0) / (eta + 1.0)).powi(2);
        let c = case(1.0001, 1.0001);
        let (r, rho) = (c.reference.unwrap(), c.reference_rounding);
        assert!((r - fresnel(1.0001)).abs() <= 1e-12 * r, "{r}");
        let want = fresnel(f64::from(1.0001f32)) - fresnel(1.0001);
        assert!(
            (rho - want).abs() <= 1e-6 * want && rho > 3e-4 * r,
            "{rho} vs {want}"
        );
        let run = |c: &crate::case::Case| {
            let mut o = c.run(
                crate::transport::Estimator::Bsdf,
                crate::sampling::SamplerKind::Independent,
                1024,
                1,
            );
            o.judge(1e-4, 1);
            o
        };
        let o = run(&c);
        assert!(o.exact && o.reference_rounding == rho, "{o:?}");
        assert!(o.passed(), "{:?}", o.verdict);
        // The engine sits at the f32 end of the range: the opposite shift fails it.
        let mut flipped = o.clone();
        flipped.reference_rounding = -rho;
        assert!(!flipped.verdict_against(r, 1e-4, 1).passed);
        let mut bare = o.clone();
        bare.reference_rounding = 0.0;
        assert!(!bare.verdict_against(r, 1e-4, 1).passed);
        let wrong = run(&case(1.0001, 1.0002));
        let why = wrong.verdict.as_ref().unwrap().reason.clone().unwrap();
        assert!(
            !wrong.passed() && why.contains("engine's f32 inputs"),
            "{why}"
        );
        assert_eq!(case(1.5, 1.5).reference_rounding, 0.0);
    }

    /// The model of the loader: points rebased about the origin and rounded there, every
    /// other number rounded (an integer too: 2²⁴ + 1 is no `f32`), nested arrays and
    /// objects walked, strings left alone.
    #[test]
    fn the_engines_view_of_a_reference() {
        let o = [1e6, 0.0, 0.0];
        let mut v = json!({"point": [1e6 + 0.1, 0.1, 3], "radius": 0.1, "radiance": 16777217,
                           "vertices": [[0.1, 0, 0], [0, 0.1, 0], [0, 0, 0.1]],
                           "light": {"center": [0.1, 0.2, 0.3], "name": "x", "on": true}});
        for (k, x) in v.as_object_mut().unwrap().iter_mut() {
            as_engine_sees(x, k, o);
        }
        let r = |x: f64| f64::from(x as f32);
        assert_eq!(v["point"], json!([1e6 + r(1e6 + 0.1 - 1e6), r(0.1), 3.0]));
        assert_eq!(v["radius"], json!(r(0.1)));
        assert_eq!(v["radiance"], json!(16777216.0));
        assert_eq!(v["vertices"][1], json!([1e6 - 1e6, r(0.1), 0.0]));
        assert_eq!(
            v["light"]["center"],
            json!([1e6 + r(0.1 - 1e6), r(0.2), r(0.3)])
        );
        assert_eq!(v["light"]["name"], json!("x"));
        assert_eq!(v["light"]["on"], json!(true));
    }

    /// Only the parameters the engine holds as given are rounded for ρ: an angle it turns
    /// into a direction (a Lambertian intensity at θ 10⁻⁵ rad from the horizon, where
    /// rounding θ itself moved the reference by 0.3%) or a spot light's `f64` axis and
    /// cone are left alone, a length or radiance is rounded; a parameter that rounds out
    /// of the closed form's domain (a radius that underflows to 0) or to a non-finite
    /// value (a radiance past f32's range) moves the reference by 0, not NaN.
    #[test]
    fn only_what_the_engine_holds_as_given_is_rounded() {
        let rho = |reference: serde_json::Value| {
            let d: CaseDesc = serde_json::from_value(json!({
                "name": "n", "teaches": "t",
                "measure": {"albedo": {"bsdf": {"type": "lambertian", "albedo": 0.5},
                                       "theta_degrees": 0}},
                "reference": reference, "estimators": ["bsdf"]
            }))
            .unwrap();
            let name = d.reference.as_ref().unwrap()["closed_form"]
                .as_str()
                .unwrap();
            let mut p = d.reference.clone().unwrap();
            p.remove("closed_form");
            let scale = p.remove("scale").map_or(1.0, |s| s.as_f64().unwrap());
            let value = lightproof_analytic::catalog::evaluate(name, &p).unwrap() * scale;
            (
                reference_rounding(&d, DVec3::ZERO, value.min(f64::MAX)),
                value,
            )
        };
        let theta = std::f64::consts::FRAC_PI_2 - 1e-5;
        let (r, _) = rho(
            json!({"closed_form": "lambertian_intensity", "radiance": 1, "area": 2,
                                "theta": theta}),
        );
        assert_eq!(r, 0.0);
        let (r, v) = rho(
            json!({"closed_form": "disk_irradiance_on_axis", "radius": 0.1,
                                "height": 1, "radiance": 1}),
        );
        assert!(r != 0.0 && r.abs() < 1e-7 * v, "{r} {v}");
        assert!(!engine_holds_as_given("spot_light_irradiance", "axis"));
        assert!(!engine_holds_as_given(
            "spot_light_irradiance",
            "cone_angle_degrees"
        ));
        assert!(engine_holds_as_given("disk_irradiance", "axis"));
        for (k, want) in [
            ("theta", false),
            ("tilt", false),
            ("wavelength", false),
            ("t1", false),
            ("bounces", false),
            ("eta", true),
            ("x0", true),
        ] {
            assert_eq!(engine_holds_as_given("any", k), want, "{k}");
        }
        let (r, v) = rho(
            json!({"closed_form": "disk_irradiance_on_axis", "radius": 1e-46,
                                "height": 1, "radiance": 1}),
        );
        assert!(r == 0.0 && v > 0.0, "{r} {v}");
        let (r, v) = rho(
            json!({"closed_form": "disk_irradiance_on_axis", "radius": 1,
                                "height": 1, "radiance": 1e39}),
        );
        assert!(r == 0.0 && v.is_finite(), "{r} {v}");
        // A unit `scale` scales ρ as it scales the reference; one that takes the value at
        // the engine's inputs past f64's range moves nothing.
        let disk = |scale: f64| {
            json!({"closed_form": "disk_irradiance_on_axis", "radius": 0.1, "height": 1,
                   "radiance": 1, "scale": scale})
        };
        let (one, _) = rho(disk(1.0));
        let (nano, _) = rho(disk(1e-9));
        assert!(
            one != 0.0 && (nano - 1e-9 * one).abs() <= 1e-15 * one.abs(),
            "{one} {nano}"
        );
        let huge = json!({"closed_form": "disk_irradiance_on_axis", "radius": 0.1,
                          "height": 1, "radiance": 1e12, "scale": 1e308});
        assert_eq!(rho(huge).0, 0.0);
    }
}
