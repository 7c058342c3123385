//! From a case's `spectral` and `time` sections to the dimensions its estimator samples,
//! with the reasons for wavelength and time.
//!
//! **Wavelength** is sampled only where the scene varies with it (an emitter with a
//! non-constant spectrum, a dispersive material). A grey scene measured over a band
//! gives ∫ R(λ) L dλ = L ∫ R(λ) dλ: the engine estimates L once and multiplies by the
//! deterministic factor (the band integral of R, or of R λ/(hc) for photons, exact for
//! every kind of response: [`band`]).
//! **Time** is sampled only where an emitter moves (uniformly over the shutter) and path
//! lengths are tracked only when the measurement is time resolved. The *full*
//! dimensions sample everything for the soundness proof: wavelength with the case's own
//! sampler and four hero lanes over its band (uniformly over the visible range for a
//! grey scene without one), time over the shutter or [0, 1] s.

use super::{SpectralDesc, TimeDesc, WavelengthSampling};
use crate::bsdf::BsdfModel;
use crate::error::InputError;
use crate::scene::Scene;
use crate::spectrum::{Band, Response, VISIBLE, WavelengthSampler, photon_energy};
use crate::transport::effects::Decision;
use crate::transport::measure::Measure;
use crate::transport::phase::{Dimensions, SpectralSetup, TimeSetup};

/// The pruned and the full dimensions of a measurement, with the decisions (and their
/// reasons) for wavelength and time.
pub struct Decided {
    /// What the pruned plan samples.
    pub pruned: Dimensions,
    /// Everything sampled, for the soundness proof.
    pub full: Dimensions,
    /// Whether wavelength is a sampled dimension, and why.
    pub wavelength: Decision,
    /// Whether time is a sampled dimension, and why.
    pub time: Decision,
}

/// Decide the dimensions of `measure` in `scene` from the `spectral` and `time` sections.
pub fn dimensions(
    f: &str,
    scene: &Scene,
    measure: &Measure,
    spectral: Option<&SpectralDesc>,
    time: Option<&TimeDesc>,
) -> Result<Decided, InputError> {
    let (pruned_s, full_s, factor, wavelength) = self::wavelength(f, scene, measure, spectral)?;
    let (time_setup, full_time, time) = time_dims(f, scene, measure, time)?;
    Ok(Decided {
        pruned: Dimensions {
            spectral: pruned_s,
            time: time_setup,
            factor,
        },
        full: Dimensions {
            spectral: Some(full_s),
            time: full_time,
            factor: 1.0,
        },
        wavelength,
        time,
    })
}

fn decision(simulated: bool, why: String) -> Decision {
    Decision { simulated, why }
}

/// (pruned setup, full setup, the pruned estimate's deterministic factor, decision).
type WavelengthDims = (Option<SpectralSetup>, SpectralSetup, f32, Decision);

/// What in the scene varies with wavelength (emitter spectra, dispersive materials).
fn what_varies(scene: &Scene) -> Vec<String> {
    scene
        .emitters
        .iter()
        .map(|e| &e.props)
        .enumerate()
        .filter(|(_, p)| p.spectrum.is_some())
        .map(|(i, _)| format!("emitter {i}'s spectrum"))
        .chain(
            scene
                .materials
                .iter()
                .enumerate()
                .filter(|(_, m)| m.ior.is_some())
                .map(|(i, _)| format!("material {i}'s refractive index")),
        )
        .collect()
}

/// The wavelength dimension: sampled only where the scene varies with wavelength and
/// the measurement is radiometric; otherwise a deterministic factor.
fn wavelength(
    f: &str,
    scene: &Scene,
    measure: &Measure,
    spectral: Option<&SpectralDesc>,
) -> Result<WavelengthDims, InputError> {
    let varies = what_varies(scene);
    let err = |field: &str, why: String| InputError::new(f, field, why);
    let radiometric = match measure {
        Measure::Irradiance { .. }
        | Measure::Flux { .. }
        | Measure::Radiance { .. }
        | Measure::Power { .. }
        | Measure::Intensity { .. } => true,
        // Geometric measurements carry no radiance: the scene's spectra do not enter.
        Measure::SolidAngle { .. }
        | Measure::ProjectedSolidAngle { .. }
        | Measure::Albedo { .. }
        | Measure::Microfacet { .. }
        | Measure::MeanPathLength { .. } => false,
    };
    let spectral_scene = !varies.is_empty() && radiometric;
    let Some(sd) = spectral else {
        if spectral_scene {
            return Err(err(
                "spectral",
                format!(
                    "{} varies with wavelength: give `spectral.band` (nm) or `spectral.wavelength` (nm)",
                    varies.join(" and ")
                ),
            ));
        }
        return Ok(grey());
    };
    if !radiometric {
        return Err(err(
            "spectral",
            format!(
                "a {} measurement has no spectrum (use irradiance, radiance, power or intensity)",
                measure.name()
            ),
        ));
    }
    if let Response::Sampled(s) = &sd.response {
        s.validate_at()
            .map_err(|(at, r)| err(&format!("spectral.response{at}"), r))?;
    }
    let varies = spectral_scene.then(|| varies.join(" and "));
    check_sample_scale(f, scene, sd)?;
    check_blackbody_range(f, scene, sd)?;
    match (sd.band, sd.wavelength) {
        (Some(_), Some(_)) | (None, None) => Err(err(
            "spectral",
            "give exactly one of `band` [λ₁, λ₂] or `wavelength` (nm)".into(),
        )),
        (None, Some(l)) => {
            if !(l.is_finite() && l > 0.0) {
                return Err(err(
                    "spectral.wavelength",
                    format!("must be a positive wavelength in nm, got {l}"),
                ));
            }
            Ok(monochromatic(sd, l, varies))
        }
        (Some([a, b]), None) => {
            if !(a.is_finite() && b.is_finite() && a > 0.0 && b > a) {
                return Err(err(
                    "spectral.band",
                    format!("must be [λ₁, λ₂] in nm with 0 < λ₁ < λ₂, got [{a}, {b}]"),
                ));
            }
            Ok(band(scene, sd, a, b, varies))
        }
    }
}

/// A spectral sample weighs an emitter's strength by its spectrum, by the response over
/// the density of the drawn wavelength (R·width for a band drawn uniformly: the largest
/// weight), and when counting photons by λ/(hc) photons per joule (5·10²² at λ = 1 cm).
/// The weight alone, R_max × [λ₂/(hc)] × max(1, λ₂ − λ₁ nm), and times the largest
/// strength × spectrum, must fit f32, or a sample overflows to +∞ (an emitter of
/// radiance 10¹⁸ counted in photons over [10 nm, 1 cm] did; so did a response or an
/// emitter's spectrum of 3·10³⁸ over 100 nm, every sample non-finite). A bound, so a
/// case just below it can still be refused; the field named is `spectral.photons` when
/// counting photons, else `spectral`.
fn check_sample_scale(f: &str, scene: &Scene, sd: &SpectralDesc) -> Result<(), InputError> {
    let (lo, hi) = match (sd.band, sd.wavelength) {
        (Some([a, b]), None) => (a, b),
        (None, Some(l)) => (l, l),
        // Refused with its own message below.
        _ => return Ok(()),
    };
    if !(lo > 0.0 && hi >= lo && hi.is_finite()) {
        return Ok(());
    }
    let band = Band {
        min: lo as f32,
        max: hi as f32,
    };
    let peak = scene
        .emitters
        .iter()
        .map(|e| {
            let spectrum = e.props.spectrum.as_ref().map_or(1.0, |s| s.max_in(band));
            e.kind.peak_strength() as f64 * spectrum as f64
        })
        .fold(0.0f64, f64::max);
    // A sample's weight is R(λ)/p(λ): at most R's peak times the band's width over the
    // sampler's least density share (`emitter` sampling's spikes once overflowed past a
    // bound that assumed a uniform draw).
    let weight = sd.response.max_in(band) as f64
        * photon_factor(sd, hi)
        * (hi - lo).max(1.0)
        * if sd.band.is_some() {
            sd.sampling.weight_factor(scene.emitters.len())
        } else {
            1.0
        };
    let (field, what) = if sd.photons {
        (
            "spectral.photons",
            "the largest photon count of a sample, strength × spectrum × response × λ₂/(hc) × band width (× min(10, n/0.9) for `emitter` sampling over n emitters),",
        )
    } else {
        (
            "spectral",
            "the largest value of a sample, strength × spectrum × response × band width (× min(10, n/0.9) for `emitter` sampling over n emitters),",
        )
    };
    crate::error::check_derived(f, field, weight * peak.max(1.0), what)
}

/// Smallest mean of a blackbody's s·B_λ over the band (and of strength × it):
/// 2²⁴·f32::MIN_POSITIVE ≈ 2·10⁻³¹. S(λ) is rounded to `f32` before the strength and
/// the sample's weight multiply it; where it falls below f32's normal range (1.2·10⁻³⁸)
/// it loses precision or vanishes, and that part of the band holds at most
/// width × 1.2·10⁻³⁸ of the integral: at most 2⁻²⁴ of it above this mean.
pub const MIN_BLACKBODY_MEAN: f64 = 16_777_216.0 * f32::MIN_POSITIVE as f64;

/// A blackbody (of positive scale) whose values over the band, or times its emitter's
/// strength, fall below f32's normal range is refused naming `spectral`: 300 K counted in
/// photons over [380, 400] nm read 3.356·10⁻²⁷ for 6.732·10⁻²⁷ (its B_λ ~10⁻⁴⁶, subnormal),
/// and 150 K over the visible band read exactly 0 for 1.05·10⁻⁴⁷ (below even f32's
/// subnormals), with a radiance of 10³⁰ still 0 for 1.05·10⁻¹⁷. Refused rather than
/// evaluated in `f64`: the spectrum is an `f32` factor of every sample (phase.rs), and the
/// blackbody's `scale` (in `f64` with Planck's law) brings it into range.
fn check_blackbody_range(f: &str, scene: &Scene, sd: &SpectralDesc) -> Result<(), InputError> {
    let band = match (sd.band, sd.wavelength) {
        (Some([a, b]), None) => Band::new(a as f32, b as f32),
        (None, Some(l)) => Band::new(l as f32, l as f32),
        _ => return Ok(()),
    };
    for (i, e) in scene.emitters.iter().enumerate() {
        let Some(s @ crate::spectrum::Spectrum::Blackbody { scale, .. }) = &e.props.spectrum else {
            continue;
        };
        if !(*scale > 0.0) {
            continue;
        }
        let mean = if band.max > band.min {
            s.integral(band) / (band.max as f64 - band.min as f64)
        } else {
            s.eval(band.min) as f64
        };
        let strength = e.kind.peak_strength() as f64;
        let low = if mean < MIN_BLACKBODY_MEAN {
            Some(("its spectrum", mean))
        } else if strength > 0.0 && strength * mean < MIN_BLACKBODY_MEAN {
            Some(("its strength × spectrum", strength * mean))
        } else {
            None
        };
        if let Some((what, v)) = low {
            return Err(InputError::new(
                f,
                "spectral",
                format!(
                    "emitter {i}'s blackbody is too faint for f32 over [{}, {}] nm: {what} averages {v:.3e}, below {MIN_BLACKBODY_MEAN:.1e} (2²⁴ × f32's smallest normal number), where f32 loses it; raise its `scale` (and divide the result)",
                    band.min, band.max
                ),
            ));
        }
    }
    Ok(())
}

/// 1, or 1/(hc/λ) when counting photons.
fn photon_factor(sd: &SpectralDesc, l: f64) -> f64 {
    if sd.photons {
        1.0 / photon_energy(l)
    } else {
        1.0
    }
}

/// Grey scene, grey measurement: nothing sampled; the full proof samples the visible
/// range and divides by its width (the mean over λ of a constant).
fn grey() -> WavelengthDims {
    let full = SpectralSetup {
        sampler: WavelengthSampler::uniform(VISIBLE),
        response: Response::Flat,
        fixed: None,
        hero: true,
        photons: false,
        scale: 1.0 / VISIBLE.width(),
    };
    (
        None,
        full,
        1.0,
        decision(
            false,
            "the scene's spectra are constant and no measurement is spectral: wavelength integrates out".into(),
        ),
    )
}

/// One wavelength `l` (nm): evaluated there; sampled only if the scene `varies`.
fn monochromatic(sd: &SpectralDesc, l: f64, varies: Option<String>) -> WavelengthDims {
    let r = sd.response.eval(l as f32) as f64;
    let setup = SpectralSetup {
        sampler: WavelengthSampler::uniform(Band {
            min: l as f32,
            max: l as f32 + 1.0,
        }),
        response: sd.response.clone(),
        fixed: Some(l as f32),
        hero: false,
        photons: sd.photons,
        scale: r as f32,
    };
    let factor = (r * photon_factor(sd, l)) as f32;
    match varies {
        Some(v) => (
            Some(setup.clone()),
            setup,
            factor,
            decision(
                true,
                format!(
                    "{v} varies with wavelength; the measurement is monochromatic: evaluated at {l} nm"
                ),
            ),
        ),
        None => (
            None,
            setup,
            factor,
            decision(
                false,
                format!("the scene is grey: its value at {l} nm is the grey value"),
            ),
        ),
    }
}

/// How wavelengths of `band` are drawn: uniformly, or by response × the emitters'
/// normalised spectra (× λ when counting photons).
fn band_sampler(scene: &Scene, sd: &SpectralDesc, band: Band) -> WavelengthSampler {
    match sd.sampling {
        WavelengthSampling::Uniform => WavelengthSampler::uniform(band),
        WavelengthSampling::Emitter => {
            let spectra: Vec<_> = scene
                .emitters
                .iter()
                .map(|e| &e.props)
                .map(|p| {
                    p.spectrum
                        .as_ref()
                        .map(|s| (s, s.max_in(band).max(f32::MIN_POSITIVE)))
                })
                .collect();
            let response = sd.response.clone();
            let photons = sd.photons;
            // The target's bound over a cell, from each factor's exact maximum there.
            let cell_bound = {
                let (spectra, response) = (spectra.clone(), response.clone());
                move |cell: Band| {
                    let e: f32 = spectra
                        .iter()
                        .map(|s| s.as_ref().map_or(1.0, |(s, m)| s.max_in(cell) / m))
                        .sum();
                    let p = if photons { cell.max / 550.0 } else { 1.0 };
                    response.max_in(cell) * e.max(0.0) * p
                }
            };
            WavelengthSampler::importance_bounded(
                band,
                move |l| {
                    let e: f32 = spectra
                        .iter()
                        .map(|s| s.as_ref().map_or(1.0, |(s, m)| s.eval(l) / m))
                        .sum();
                    let p = if photons { l / 550.0 } else { 1.0 };
                    response.eval(l) * e.max(0.0) * p
                },
                cell_bound,
            )
        }
    }
}

/// A band [a, b] (nm): sampled if the scene `varies`, else the grey estimate times the
/// band integral ∫ R dλ ([`Response::integral`]) or, counting photons, ∫ R λ/(hc) dλ
/// ([`Response::photon_integral`]), both exact for every kind of response (closed forms,
/// the table's pieces, the blackbody series to ~1e-14), however narrow R is against the
/// band, over the f32 band the sampled path draws from.
fn band(
    scene: &Scene,
    sd: &SpectralDesc,
    a: f64,
    b: f64,
    varies: Option<String>,
) -> WavelengthDims {
    let range = Band {
        min: a as f32,
        max: b as f32,
    };
    let setup = SpectralSetup {
        sampler: band_sampler(scene, sd, range),
        response: sd.response.clone(),
        fixed: None,
        hero: sd.hero,
        photons: sd.photons,
        scale: 1.0,
    };
    let mut full = setup.clone();
    full.hero = true;
    let how = format!(
        "{} over [{a}, {b}] nm{}",
        match sd.sampling {
            WavelengthSampling::Uniform => "sampled uniformly",
            WavelengthSampling::Emitter => "importance-sampled by response × spectra",
        },
        if sd.hero {
            " with four hero wavelengths per path"
        } else {
            ""
        }
    );
    match varies {
        Some(v) => (
            Some(setup),
            full,
            1.0,
            decision(true, format!("{v} varies with wavelength: {how}")),
        ),
        None => {
            let factor = if sd.photons {
                sd.response.photon_integral(range)
            } else {
                sd.response.integral(range)
            };
            (
                None,
                full,
                factor as f32,
                decision(
                    false,
                    format!(
                        "the scene is grey: the band integral is the grey estimate times ∫R{} dλ = {factor:.6e} over [{a}, {b}] nm",
                        if sd.photons { "·λ/(hc)" } else { "" }
                    ),
                ),
            )
        }
    }
}

/// Narrowest time bin, relative to the time since a pulse: (t₂ − t₁) ≥ 10⁻⁴·(t₂ − t₀),
/// so that `f32` path lengths resolve it into ~10³ steps or more (the band rule's bound).
pub const MIN_RELATIVE_BIN: f64 = crate::spectrum::MIN_RELATIVE_BANDWIDTH;

fn time_dims(
    f: &str,
    scene: &Scene,
    measure: &Measure,
    time: Option<&TimeDesc>,
) -> Result<(TimeSetup, TimeSetup, Decision), InputError> {
    let td = time.cloned().unwrap_or_default();
    let interval = |field: &str, v: Option<[f64; 2]>| -> Result<Option<(f64, f64)>, InputError> {
        match v {
            None => Ok(None),
            Some([a, b]) if a.is_finite() && b.is_finite() && b > a => Ok(Some((a, b))),
            Some([a, b]) => Err(InputError::new(
                f,
                field,
                format!("must be [t₁, t₂] in seconds with t₁ < t₂, got [{a}, {b}]"),
            )),
        }
    };
    // The scene's time 0 is the shutter's start t₀ (moving objects are placed where they
    // are then, `case::build::epoch`): time is sampled as τ = t − t₀ over [0, t₁ − t₀],
    // whose f32 width must be a normal number (a subnormal or zero width cannot be
    // sampled uniformly).
    let shutter = interval("time.shutter", td.shutter)?.map(|(a, b)| (0.0f32, (b - a) as f32));
    if let Some((_, w)) = shutter
        && !w.is_normal()
    {
        return Err(InputError::new(
            f,
            "time.shutter",
            format!(
                "its length t₁ − t₀ = {:e} s is not a normal f32 (between {:e} and {:e} s)",
                w,
                f32::MIN_POSITIVE,
                f32::MAX
            ),
        ));
    }
    let bin = interval("time.bin", td.bin)?;
    // A steady emitter weighs a path by the bin's width (t₂ − t₁) as f32 (phase.rs): a
    // width below f32::MIN_POSITIVE (subnormal or 0) or above f32::MAX would weigh it
    // imprecisely or by 0 or ∞, so such a bin is refused.
    if let Some((a, b)) = bin
        && !((b - a) as f32).is_normal()
    {
        return Err(InputError::new(
            f,
            "time.bin",
            format!(
                "its width t₂ − t₁ = {:e} s is not a normal f32 (between {:e} and {:e} s), got [{a}, {b}]",
                b - a,
                f32::MIN_POSITIVE,
                f32::MAX
            ),
        ));
    }
    // A pulse's arrivals are binned by the path length ℓ, an f32 (`phase.rs`): it steps by
    // up to 2⁻²³·ℓ (0.4 fs of light at 1 m), so a bin narrower than 10⁻⁴ of the time
    // since the pulse, t₂ − t₀ (1.2·10³ such steps), is refused, as a band is: 10 fs bins
    // at 1 m read z = +13 and −9 (paths one step over an edge counted in the next bin).
    if let Some((a, b)) = bin {
        for (i, t0) in scene
            .emitters
            .iter()
            .enumerate()
            .filter_map(|(i, e)| Some((i, e.props.pulse?)))
        {
            let since = b - t0;
            if since > 0.0 && !(b - a >= MIN_RELATIVE_BIN * since) {
                return Err(InputError::new(
                    f,
                    "time.bin",
                    format!(
                        "[{a:e}, {b:e}] s is too narrow for f32 path lengths after emitter {i}'s pulse at {t0:e} s: t₂ − t₁ must be at least {MIN_RELATIVE_BIN}·(t₂ − t₀) ({:.3e} s here)",
                        MIN_RELATIVE_BIN * since
                    ),
                ));
            }
        }
    }
    if bin.is_some() {
        if measure.origin().is_none()
            && !matches!(measure, Measure::Power { .. } | Measure::Intensity { .. })
        {
            return Err(InputError::new(
                f,
                "time.bin",
                format!(
                    "a {} measurement has no time of flight to bin (use irradiance, radiance, power or intensity)",
                    measure.name()
                ),
            ));
        }
        // Path length is converted to time at the vacuum speed of light: a transmitting
        // material (light slower by η inside) would bin arrivals wrongly.
        let transmits = scene.shapes.iter().any(|s| {
            s.material.is_some_and(|m| {
                scene.materials[m]
                    .bsdf
                    .flags()
                    .contains(crate::bsdf::LobeFlags::TRANSMISSION)
            })
        });
        if transmits {
            return Err(InputError::new(
                f,
                "time.bin",
                "time of flight is computed in vacuum; a transmitting material (light at c/η inside) is not supported in a time-resolved measurement",
            ));
        }
    }
    let moving: Vec<String> = (0..scene.shapes.len())
        .filter(|&i| scene.shapes[i].velocity != glam::Vec3::ZERO)
        .map(|i| format!("shape {i}"))
        .chain(
            (0..scene.emitters.len())
                .filter(|&i| {
                    scene.emitters[i].props.velocity != glam::Vec3::ZERO
                        && !matches!(
                            scene.emitters[i].kind,
                            crate::scene::emitter::EmitterKind::Area { .. }
                        )
                })
                .map(|i| format!("emitter {i}")),
        )
        .collect();
    if !moving.is_empty() && shutter.is_none() {
        return Err(InputError::new(
            f,
            "time.shutter",
            format!(
                "{} moves: give the shutter interval [t₀, t₁] in seconds",
                moving[0]
            ),
        ));
    }
    if !moving.is_empty() && measure.origin().is_none() {
        return Err(InputError::new(
            f,
            "time.shutter",
            format!(
                "{} moves, but a {} measurement is taken at rest: motion applies to irradiance and radiance",
                moving[0],
                measure.name()
            ),
        ));
    }
    let pulsed = scene.emitters.iter().any(|e| e.props.pulse.is_some());
    // A path's scene is frozen at its one sampled time, the detection time, while a pulse
    // fixes the time of emission: a pulsed emitter that moved (or in a scene where
    // anything does) would be sampled where it is at the shutter's time, not where it
    // flashed. Refused rather than answered wrongly.
    if let (Some(k), Some(what)) = (
        scene.emitters.iter().position(|e| e.props.pulse.is_some()),
        moving.first(),
    ) {
        return Err(InputError::new(
            f,
            "time.shutter",
            format!(
                "emitter {k} is pulsed (`pulse_at`) while {what} moves: a path sees the scene at one time, so a pulse and motion together are not supported"
            ),
        ));
    }
    let mut why = Vec::new();
    if !moving.is_empty() {
        why.push(format!(
            "{} move(s): time is sampled uniformly over the shutter",
            moving.join(", ")
        ));
    }
    if let Some((t1, t2)) = bin {
        why.push(format!(
            "the measurement is time resolved: path lengths ℓ give arrival times ℓ/c, counted in [{t1:e}, {t2:e}] s"
        ));
    }
    let simulated = !why.is_empty();
    let decision = if simulated {
        decision(true, why.join("; "))
    } else if pulsed {
        decision(
            false,
            "emitters are pulsed but the measurement is not time resolved: it counts the whole pulse".into(),
        )
    } else if shutter.is_some() {
        decision(
            false,
            "nothing moves: the shutter average is the static value".into(),
        )
    } else {
        decision(
            false,
            "nothing moves and the measurement is not time resolved: time integrates out".into(),
        )
    };
    let pruned = TimeSetup {
        shutter: if moving.is_empty() { None } else { shutter },
        bin,
    };
    let full = TimeSetup {
        shutter: Some(shutter.unwrap_or((0.0, 1.0))),
        bin,
    };
    Ok((pruned, full, decision))
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn scene(emitter: serde_json::Value) -> Scene {
        crate::scene::from_json(json!({ "emitters": [emitter] }))
    }

    fn spectral(v: serde_json::Value) -> SpectralDesc {
        serde_json::from_value(v).unwrap()
    }

    /// A blackbody whose values over the band fall below f32's normal range is refused
    /// naming `spectral` (the audit's 300 K photons over [380, 400] nm read −50%, 150 K
    /// over the visible band 0 for 1.05·10⁻⁴⁷ even at a radiance of 10³⁰); its `scale`
    /// brings it back, and 300 K over the visible band (mean 2.7·10⁻²³) runs.
    #[test]
    fn a_blackbody_too_faint_for_f32_is_refused() {
        let bb = |t: f64, scale: f64, radiance: f64| {
            scene(
                json!({ "type": "point", "position": [0, 0, 1], "intensity": radiance,
                          "spectrum": { "blackbody": { "temperature": t, "scale": scale } } }),
            )
        };
        let check =
            |s: &Scene, v: serde_json::Value| check_blackbody_range("c.json", s, &spectral(v));
        for (t, band, radiance) in [
            (300.0, [380.0, 400.0], 1.0),
            (160.0, [380.0, 780.0], 1.0),
            (150.0, [380.0, 780.0], 1.0),
            (150.0, [380.0, 780.0], 1e30),
        ] {
            for photons in [false, true] {
                let e = check(
                    &bb(t, 1.0, radiance),
                    json!({ "band": band, "photons": photons }),
                )
                .unwrap_err();
                assert_eq!(e.field, "spectral", "{t} K: {e}");
                assert!(e.reason.contains("too faint for f32"), "{t} K: {e}");
            }
        }
        assert!(check(&bb(300.0, 1.0, 1.0), json!({ "wavelength": 390 })).is_err());
        assert!(check(&bb(300.0, 1.0, 1.0), json!({ "band": [380, 780] })).is_ok());
        assert!(check(&bb(300.0, 1e30, 1.0), json!({ "band": [380, 400] })).is_ok());
        assert!(check(&bb(150.0, 3e38, 1.0), json!({ "band": [380, 780] })).is_ok());
        // A faint strength over a bright spectrum: their product is what is rounded.
        let e = check(&bb(3000.0, 1.0, 1e-35), json!({ "band": [380, 780] })).unwrap_err();
        assert!(e.reason.contains("strength × spectrum"), "{e}");
        // A scale of 0 is a legitimate dark emitter.
        assert!(check(&bb(150.0, 0.0, 1.0), json!({ "band": [380, 780] })).is_ok());
    }

    /// The sample-scale bound: strength × response × [λ₂/(hc)] × band width against
    /// f32::MAX, on either side of it, for a band and for one wavelength, with the
    /// strength of each kind of emitter, in photons and in energy; a band it does not
    /// judge (refused elsewhere) passes here.
    #[test]
    fn the_largest_sample_fits_f32() {
        let photons = |band: [f64; 2]| {
            spectral(json!({ "band": band, "photons": true, "sampling": "uniform" }))
        };
        // λ₂/(hc) at 1 cm is 5.03e22 per joule; over a band of 1e7 nm a strength s gives
        // s·5.03e29, so 6.7e8 fits and 6.8e8 overflows.
        let e = |s: f64| json!({ "type": "point", "position": [0, 0, 1], "intensity": s });
        let band = photons([1.0, 1e7 + 1.0]);
        assert!(check_sample_scale("c.json", &scene(e(6.7e8)), &band).is_ok());
        let err = check_sample_scale("c.json", &scene(e(6.8e8)), &band).unwrap_err();
        assert_eq!(err.field, "spectral.photons");
        // Drawn from the emitters' table (the default), one emitter: a density at least
        // 0.9 of the target's over its total, so the limit is 0.9 × 6.76e8 = 6.08e8.
        let table = spectral(json!({ "band": [1.0, 1e7 + 1.0], "photons": true }));
        assert!(check_sample_scale("c.json", &scene(e(6.0e8)), &table).is_ok());
        assert!(check_sample_scale("c.json", &scene(e(6.2e8)), &table).is_err());
        // Twenty emitters: min(10, 20/0.9) = 10 times a uniform draw's weight.
        let many = crate::scene::from_json(json!({ "emitters": vec![e(6.7e7); 20] }));
        assert!(check_sample_scale("c.json", &many, &table).is_ok());
        let many = crate::scene::from_json(json!({ "emitters": vec![e(6.8e7); 20] }));
        assert!(check_sample_scale("c.json", &many, &table).is_err());
        // One wavelength: no band width; at 1 cm a strength of 6.7e15 fits, 6.8e15 not.
        let one = spectral(json!({ "wavelength": 1e7, "photons": true }));
        assert!(check_sample_scale("c.json", &scene(e(6.7e15)), &one).is_ok());
        assert!(check_sample_scale("c.json", &scene(e(6.8e15)), &one).is_err());
        // A band narrower than 1 nm counts as 1 nm, not as its own width.
        let narrow = photons([1e7, 1e7 + 0.5]);
        assert!(check_sample_scale("c.json", &scene(e(6.8e15)), &narrow).is_err());
        // Each kind's strength: irradiance of a directional light, radiance of a sky.
        let sun = json!({ "type": "directional", "direction": [0, 0, -1], "irradiance": 6.8e15 });
        assert!(check_sample_scale("c.json", &scene(sun), &one).is_err());
        let sky = json!({ "type": "constant", "radiance": 6.8e15 });
        assert!(check_sample_scale("c.json", &scene(sky), &one).is_err());
        let sky = json!({ "type": "constant", "radiance": 6.7e15 });
        assert!(check_sample_scale("c.json", &scene(sky), &one).is_ok());
        // The band's width, not its ratio: [10⁶, 10⁷] nm is 9·10⁶ nm wide, so the limit is
        // 3.4e38/(5.03e22 · 9e6) = 7.5e8.
        // Energy: the response's peak times the band's width weighs a sample too (R·width
        // for a uniformly drawn wavelength), named `spectral`; 3.3e36 over 100 nm fits,
        // 3.5e36 not, and a strength below 1 does not excuse the weight itself.
        let energy = |r: f64| {
            spectral(json!({ "band": [400, 500], "sampling": "uniform",
                "response": { "sampled": { "wavelengths": [400, 500], "values": [r, r] } } }))
        };
        assert!(check_sample_scale("c.json", &scene(e(1.0)), &energy(3.3e36)).is_ok());
        let err = check_sample_scale("c.json", &scene(e(1.0)), &energy(3.5e36)).unwrap_err();
        assert_eq!(err.field, "spectral");
        assert!(check_sample_scale("c.json", &scene(e(1e-10)), &energy(3.5e36)).is_err());
        assert!(check_sample_scale("c.json", &scene(e(1e2)), &energy(3.3e36)).is_err());
        let wide = photons([1e6, 1e7]);
        assert!(check_sample_scale("c.json", &scene(e(7.4e8)), &wide).is_ok());
        assert!(check_sample_scale("c.json", &scene(e(7.6e8)), &wide).is_err());
        // A spectrum multiplies the strength: peak 4 moves the one-wavelength limit to 1.69e15.
        let shaped = |s: f64| {
            json!({ "type": "constant", "radiance": s,
                    "spectrum": { "sampled": { "wavelengths": [1, 2e7], "values": [4, 4] } } })
        };
        assert!(check_sample_scale("c.json", &scene(shaped(1.6e15)), &one).is_ok());
        assert!(check_sample_scale("c.json", &scene(shaped(1.75e15)), &one).is_err());
        // A band refused elsewhere (λ₁ ≤ 0, λ₂ < λ₁) passes here.
        for bad in [[5.0, 1.0], [0.0, 1e7]] {
            assert!(check_sample_scale("c.json", &scene(e(1e30)), &photons(bad)).is_ok());
        }
    }

    /// A grey scene over a band is the grey estimate times ∫ R dλ (or ∫ R λ/(hc) dλ when
    /// counting photons), whatever the band's width against the response's. References:
    /// the triangle's area 0.8 nm and first moment 0.8 × 632.8 nm² (closed form), and
    /// 4096-panel Gauss–Legendre over [200, 1000] nm of ȳ's f64 formula, outside of which
    /// ȳ < 10⁻¹³.
    /// Before the fix, 256 panels over the whole band gave 0 for ȳ over [10, 10⁷] nm and
    /// −5 % for the triangle over [380, 780] nm.
    #[test]
    fn a_grey_band_factor_is_the_response_integral() {
        let grey = scene(json!({ "type": "point", "position": [0, 0, 1], "intensity": 1 }));
        let per_j = 1e-9 / (crate::spectrum::PLANCK * crate::spectrum::SPEED_OF_LIGHT);
        let factor = |response: serde_json::Value, [a, b]: [f64; 2], photons: bool| {
            let sd = spectral(json!({ "band": [a, b], "response": response, "photons": photons }));
            band(&grey, &sd, a, b, None).2 as f64
        };
        let close = |got: f64, want: f64| {
            assert!((got / want - 1.0).abs() < 1e-6, "{got} against {want}");
        };
        // ȳ in f64 from the fit's formula (Wyman, Sloan and Shirley 2013, eq. 2).
        let g = |l: f64, mu: f64, s1: f64, s2: f64| {
            let t = (l - mu) / if l < mu { s1 } else { s2 };
            (-0.5 * t * t).exp()
        };
        let y = |l: f64| 0.821 * g(l, 568.8, 46.9, 40.5) + 0.286 * g(l, 530.9, 16.3, 31.1);
        for [a, b] in [[10.0f64, 1e7], [100.0, 1e6], [360.0, 830.0]] {
            let (lo, hi) = (a.max(200.0), b.min(1000.0));
            let y0 = crate::spectrum::gauss_legendre(lo, hi, 4096, y);
            let y1 = crate::spectrum::gauss_legendre(lo, hi, 4096, |l| y(l) * l * per_j);
            close(factor(json!("photopic"), [a, b], false), y0);
            close(factor(json!("photopic"), [a, b], true), y1);
        }
        let tri = json!({ "sampled": { "wavelengths": [632, 632.8, 633.6], "values": [0, 1, 0] } });
        // f32 knots: 632.8 is 632.799987…, the triangle stays symmetric about it.
        let mid = 632.8f32 as f64;
        for band in [[380.0, 780.0], [10.0, 1e7]] {
            close(
                factor(tri.clone(), band, false),
                0.8 * (633.6f32 as f64 - 632.0) / 1.6,
            );
            close(
                factor(tri.clone(), band, true),
                0.8 * (633.6f32 as f64 - 632.0) / 1.6 * mid * per_j,
            );
        }
        // A 10 nm box over [300, 3000]: its trapezoids' area (≈ 10 nm).
        let bx = json!({ "sampled": { "wavelengths": [550, 550.001, 560, 560.001], "values": [0, 1, 1, 0] } });
        let k = [550.0f32, 550.001, 560.0, 560.001].map(f64::from);
        let area = 0.5 * (k[1] - k[0]) + (k[2] - k[1]) + 0.5 * (k[3] - k[2]);
        close(factor(bx.clone(), [300.0, 3000.0], false), area);
        // Flat: b − a and (b² − a²)/2 per hc.
        close(factor(json!("flat"), [10.0, 1e7], false), 1e7 - 10.0);
        close(
            factor(json!("flat"), [10.0, 1e7], true),
            (1e14 - 100.0) / 2.0 * per_j,
        );
        // A blackbody response (3000 K, peak near 966 nm) over [0, 10⁷] nm: σT⁴/π and the
        // photon radiance 4ζ(3)k³T³/(h³c²) (Siegel & Howell ch. 1; written out here, since
        // engine code never calls the oracle), less the tail beyond 10⁷ nm:
        // x₂ = hc/(λkT) = 4.8·10⁻⁴, ∫₀^x₂ t²/(eᵗ − 1) dt ≈ x₂²/2 of 2ζ(3), 5·10⁻⁸.
        let (h, c, k): (f64, f64, f64) = (6.626_070_15e-34, 299_792_458.0, 1.380_649e-23);
        let sigma = 2.0 * std::f64::consts::PI.powi(5) * k.powi(4) / (15.0 * h.powi(3) * c * c);
        let t: f64 = 3000.0;
        let bb = json!({ "blackbody": { "temperature": 3000 } });
        close(
            factor(json!({ "sampled": bb }), [1.0, 1e7], false),
            sigma * t.powi(4) / std::f64::consts::PI,
        );
        let photons_bb = 4.0 * 1.202_056_903_159_594_2 * (k * t / h).powi(3) / (c * c);
        close(
            factor(json!({ "sampled": bb }), [1.0, 1e7], true),
            photons_bb,
        );
    }
}
