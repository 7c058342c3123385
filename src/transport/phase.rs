//! Phase space beyond position and direction: wavelength and time.
//!
//! A photon's state is position × direction × wavelength; its trajectory adds time. A
//! measurement integrates over all of them:
//!
//! M = ∫_T ∫_Λ R(λ) · [∫ W(x, ω) L(x, ω, λ, t) dx dω] dλ dt,
//!
//! with R(λ) the spectral response of the sensor (1 on a flat band) and the time
//! integral over a shutter (moving emitters) or an arrival-time bin (transient
//! transport). The engine samples a dimension only where the scene or the measurement
//! makes the integrand vary along it ([`crate::transport::effects`]); elsewhere it
//! integrates out exactly:
//!
//! - **wavelength** — in a grey scene L does not depend on λ, so
//!   ∫ R(λ) L dλ = L · ∫ R(λ) dλ: the engine estimates L once and multiplies by the
//!   deterministic factor ∫ R (or ∫ R λ/(hc) dλ for photon counts). Otherwise each path
//!   draws λ from a [`WavelengthSampler`] (uniform, or importance-sampled by the emitters'
//!   spectra times R) and weights its value by R(λ)/p(λ). With *hero wavelengths*
//!   (Wilkie et al., "Hero wavelength spectral sampling", EGSR 2014) one path carries
//!   four wavelengths λⱼ whose sample numbers are rotations u + j/4 of one number: every
//!   lane's marginal density is p(λ), so the lane average (1/4) Σⱼ f(λⱼ) R(λⱼ)/p(λⱼ) is
//!   unbiased and shares one path's geometry. At a dispersive surface the direction
//!   depends on λ, so the secondary lanes end and the hero lane's weight becomes 1
//!   (pbrt-v4's `TerminateSecondary`): unbiased because, conditioned on the shared
//!   prefix, λ₀ alone is distributed by p.
//! - **time of flight** — light travels at c in vacuum, so a path of length ℓ from an
//!   emitter pulsed at t₀ arrives at t₀ + ℓ/c. A time-resolved measurement over the bin
//!   [t₁, t₂] counts a pulsed emitter's contribution when its arrival falls in the bin
//!   (the radiant exposure H = ∫ E dt of a Dirac pulse) and a steady emitter's
//!   contribution times t₂ − t₁ (its exposure over the bin).
//! - **motion** — emitters may move linearly, p(t) = p + v t; a path draws t uniformly
//!   over the shutter [t₀, t₁] and the measurement is the shutter average
//!   (1/(t₁ − t₀)) ∫ M(t) dt. The scene is built at t₀ (moving objects placed at
//!   p + v t₀ in f64) and a path carries τ = t − t₀ ∈ [0, t₁ − t₀] in f32, so a shutter
//!   far from t = 0 keeps its resolution.
//!
//! The path tracer is generic over [`Phase`]: the grey, static instance [`Grey`]
//! compiles to the scalar tracer (no wavelength, no time, no extra work), while
//! [`PhaseSample`] carries one or four wavelengths and a time.

use crate::bsdf::Bsdf;
use crate::sampling::SampleStream;
use crate::scene::Scene;
use crate::spectrum::{Response, SPEED_OF_LIGHT, WavelengthSampler, photon_energy};
use glam::Vec4;
use std::borrow::Cow;
use std::ops::{Add, AddAssign, Mul, MulAssign};

/// The value a path carries: one grey number, or one number per wavelength lane.
pub trait Lanes:
    Copy
    + Send
    + Sync
    + Add<Output = Self>
    + AddAssign
    + Mul<Output = Self>
    + Mul<f32, Output = Self>
    + MulAssign
    + MulAssign<f32>
{
    /// Number of lanes.
    const LANES: usize;
    /// Every lane `x`.
    fn splat(x: f32) -> Self;
    /// Lane `i` is `f(i)`.
    fn from_fn(f: impl FnMut(usize) -> f32) -> Self;
    /// Lane `i`.
    fn lane(self, i: usize) -> f32;
    /// Largest lane (for Russian roulette).
    fn max_lane(self) -> f32;
    /// Whether any lane is non-zero.
    fn any_nonzero(self) -> bool;
    /// Whether every lane is finite.
    fn all_finite(self) -> bool;
}

impl Lanes for f32 {
    const LANES: usize = 1;
    #[inline]
    fn splat(x: f32) -> Self {
        x
    }
    #[inline]
    fn from_fn(mut f: impl FnMut(usize) -> f32) -> Self {
        f(0)
    }
    #[inline]
    fn lane(self, _: usize) -> f32 {
        self
    }
    #[inline]
    fn max_lane(self) -> f32 {
        self
    }
    #[inline]
    fn any_nonzero(self) -> bool {
        self != 0.0
    }
    #[inline]
    fn all_finite(self) -> bool {
        self.is_finite()
    }
}

impl Lanes for Vec4 {
    const LANES: usize = 4;
    #[inline]
    fn splat(x: f32) -> Self {
        Vec4::splat(x)
    }
    #[inline]
    fn from_fn(mut f: impl FnMut(usize) -> f32) -> Self {
        Vec4::new(f(0), f(1), f(2), f(3))
    }
    #[inline]
    fn lane(self, i: usize) -> f32 {
        self[i]
    }
    #[inline]
    fn max_lane(self) -> f32 {
        self.max_element()
    }
    #[inline]
    fn any_nonzero(self) -> bool {
        self != Vec4::ZERO
    }
    #[inline]
    fn all_finite(self) -> bool {
        self.is_finite()
    }
}

/// Where a sample sits in wavelength and time, and what that does to emission and
/// materials.
pub trait Phase: Sync {
    /// The value a path carries.
    type L: Lanes;
    /// Emission of emitter `emitter` with grey radiance `radiance`, reaching the sensor
    /// after a path of length `length` (scene units, metres): the emitter's spectrum at
    /// each lane's wavelength, gated by arrival time when time resolved.
    fn emission(&self, scene: &Scene, emitter: usize, radiance: f32, length: f32) -> Self::L;
    /// The sample's time (for moving emitters).
    fn time(&self) -> f32;
    /// The material at this sample's (hero) wavelength, and whether it disperses (so
    /// secondary wavelength lanes must end there).
    fn material<'a>(&self, scene: &'a Scene, material: usize) -> (Cow<'a, Bsdf>, bool);
    /// Whether path lengths matter (time-resolved measurement).
    fn tracks_length(&self) -> bool;
}

/// A grey, static sample: no wavelength, no time. The path tracer instantiated with it
/// is the plain scalar tracer.
#[derive(Clone, Copy, Debug, Default)]
pub struct Grey;

impl Phase for Grey {
    type L = f32;
    #[inline(always)]
    fn emission(&self, _: &Scene, _: usize, radiance: f32, _: f32) -> f32 {
        radiance
    }
    #[inline(always)]
    fn time(&self) -> f32 {
        0.0
    }
    #[inline(always)]
    fn material<'a>(&self, scene: &'a Scene, material: usize) -> (Cow<'a, Bsdf>, bool) {
        (Cow::Borrowed(&scene.materials[material].bsdf), false)
    }
    #[inline(always)]
    fn tracks_length(&self) -> bool {
        false
    }
}

/// A sample with wavelength lanes and a time.
#[derive(Clone, Copy, Debug)]
pub struct PhaseSample<L> {
    /// Wavelength of each lane (nm); lane 0 is the hero. Unused lanes repeat lane 0.
    pub lambda: [f32; 4],
    /// Whether wavelength is a dimension of this sample (else emitters are grey).
    pub spectral: bool,
    /// Time (s) since the shutter's start t₀ (the scene's time 0).
    pub time: f32,
    /// Arrival-time bin (s) of a time-resolved measurement (f64: nanosecond bins far
    /// from t = 0 keep their width).
    pub bin: Option<(f64, f64)>,
    /// Per-lane weight R(λ)/p(λ)/lanes (photon factor included) applied at the end.
    pub weight: L,
}

impl<L: Lanes> Phase for PhaseSample<L> {
    type L = L;
    #[inline]
    fn emission(&self, scene: &Scene, emitter: usize, radiance: f32, length: f32) -> L {
        let props = &scene.emitters[emitter].props;
        let gate = match self.bin {
            None => 1.0,
            Some((t1, t2)) => match props.pulse {
                // A Dirac pulse at t₀ arrives at t₀ + ℓ/c, inside [t₁, t₂) when
                // ℓ/c ∈ [t₁ − t₀, t₂ − t₀): compared as times since the pulse, so that
                // a pulse far from t = 0 does not round ℓ/c onto t₀'s grid (2⁻³³ s, 3.5
                // cm of light, at t₀ = 10⁶ s); t₁ − t₀ is exact for a bin near t₀.
                Some(t0) => {
                    let dt = length as f64 / SPEED_OF_LIGHT;
                    if dt >= t1 - t0 && dt < t2 - t0 {
                        1.0
                    } else {
                        0.0
                    }
                }
                // A steady emitter delivers its rate over the whole bin.
                None => (t2 - t1) as f32,
            },
        };
        match &props.spectrum {
            Some(s) if self.spectral => L::from_fn(|j| radiance * gate * s.eval(self.lambda[j])),
            Some(_) | None => L::splat(radiance * gate),
        }
    }
    #[inline]
    fn time(&self) -> f32 {
        self.time
    }
    #[inline]
    fn material<'a>(&self, scene: &'a Scene, material: usize) -> (Cow<'a, Bsdf>, bool) {
        let m = &scene.materials[material];
        match &m.ior {
            Some(ior) if self.spectral => (Cow::Owned(ior.at(&m.bsdf, self.lambda[0])), true),
            Some(_) | None => (Cow::Borrowed(&m.bsdf), false),
        }
    }
    #[inline]
    fn tracks_length(&self) -> bool {
        self.bin.is_some()
    }
}

/// How a case samples wavelength.
#[derive(Clone, Debug)]
pub struct SpectralSetup {
    /// The sampler over the band (unused when `fixed`).
    pub sampler: WavelengthSampler,
    /// Sensor response R(λ).
    pub response: Response,
    /// One fixed wavelength (a monochromatic measurement) instead of a band.
    pub fixed: Option<f32>,
    /// Hero wavelengths: four lanes per path.
    pub hero: bool,
    /// Count photons (divide energy by hc/λ).
    pub photons: bool,
    /// Constant factor of every weight (R(λ) of a fixed wavelength; 1/width for the
    /// band mean of a grey value).
    pub scale: f32,
}

/// How a case samples time.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TimeSetup {
    /// Shutter interval (s) over which time is sampled (moving emitters), from the
    /// scene's time 0: [0, t₁ − t₀] for a case's shutter [t₀, t₁].
    pub shutter: Option<(f32, f32)>,
    /// Arrival-time bin (s) of a time-resolved measurement (f64: nanosecond bins far
    /// from t = 0 keep their width).
    pub bin: Option<(f64, f64)>,
}

/// The dimensions a case's estimator samples beyond position and direction.
#[derive(Clone, Debug, Default)]
pub struct Dimensions {
    /// Wavelength sampling (`None`: the scene is grey and wavelength integrates out).
    pub spectral: Option<SpectralSetup>,
    /// Time sampling and binning.
    pub time: TimeSetup,
    /// Deterministic factor of a pruned wavelength integral: ∫ R dλ over the band (or
    /// ∫ R λ/(hc) dλ for photons); 1 without a band.
    pub factor: f32,
}

impl Dimensions {
    /// Grey and static: nothing beyond position and direction.
    pub fn none() -> Self {
        Dimensions {
            spectral: None,
            time: TimeSetup::default(),
            factor: 1.0,
        }
    }

    /// Whether a sample needs the phase machinery at all.
    pub fn is_grey_static(&self) -> bool {
        self.spectral.is_none() && self.time.shutter.is_none() && self.time.bin.is_none()
    }

    /// Whether paths carry four wavelength lanes.
    pub fn hero(&self) -> bool {
        self.spectral
            .as_ref()
            .is_some_and(|s| s.hero && s.fixed.is_none())
    }

    /// Draw this sample's wavelengths and time (consuming two stream dimensions).
    pub fn draw<L: Lanes>(&self, s: &mut SampleStream) -> PhaseSample<L> {
        let u_lambda = s.next_1d();
        let u_time = s.next_1d();
        let time = match self.time.shutter {
            Some((t0, t1)) => t0 + (t1 - t0) * u_time,
            None => 0.0,
        };
        let (lambda, weight, spectral) = match &self.spectral {
            None => ([550.0; 4], L::splat(self.factor), false),
            Some(sp) => {
                let photon = |l: f32| {
                    sp.scale
                        * if sp.photons {
                            (1.0 / photon_energy(l as f64)) as f32
                        } else {
                            1.0
                        }
                };
                if let Some(l) = sp.fixed {
                    ([l; 4], L::splat(photon(l)), true)
                } else if L::LANES == 4 {
                    let (ls, ps) = sp.sampler.sample_lanes(u_lambda);
                    let w = L::from_fn(|j| {
                        lane_weight(sp.response.eval(ls[j]) * photon(ls[j]), ps[j]) / 4.0
                    });
                    (ls, w, true)
                } else {
                    let (l, p) = sp.sampler.sample(u_lambda);
                    let w = lane_weight(sp.response.eval(l) * photon(l), p);
                    ([l; 4], L::splat(w), true)
                }
            }
        };
        PhaseSample {
            lambda,
            spectral,
            time,
            bin: self.time.bin,
            weight,
        }
    }
}

/// R(λ)/p(λ); zero where the response is zero. Never masked: a non-finite response,
/// or a response where the density is zero, gives a non-finite weight that the
/// accumulator counts.
#[inline]
fn lane_weight(r: f32, pdf: f32) -> f32 {
    if r == 0.0 { 0.0 } else { r / pdf }
}

/// Reduce a path's lanes to the sample value: Σⱼ lane · weightⱼ.
#[inline]
pub fn finish<L: Lanes>(value: L, weight: L) -> f32 {
    let v = value * weight;
    (0..L::LANES).map(|j| v.lane(j)).sum()
}

/// End the secondary lanes of a path at a dispersive surface: the hero lane's weight
/// becomes that of all lanes together (see the module notes).
#[inline]
pub fn terminate_secondary<L: Lanes>(beta: L) -> L {
    L::from_fn(|j| {
        if j == 0 {
            beta.lane(0) * L::LANES as f32
        } else {
            0.0
        }
    })
}
