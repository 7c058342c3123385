//! Measurements: each is an integral estimated one sample at a time.
//!
//! | measurement | integral | estimators |
//! |---|---|---|
//! | solid angle of shape S from p | Ω = ∫ V_S(ω) dω | uniform (sphere), area (dω = \|cos θl\| dA/r²) |
//! | projected solid angle | Ω⊥ = ∫ V_S(ω) cos⁺θ dω | uniform, cosine, area |
//! | irradiance at p, normal n | E = ∫ Li(p, ω) cos⁺θ dω | light, bsdf (cosine), mis, mis_balance, uniform |
//! | radiance at p along d | L = Li(p, −d) | light, bsdf, mis, mis_balance (at every vertex) |
//! | albedo of a BSDF | a(ωo) = ∫ f(ωi → ωo) \|cos θi\| dωi | bsdf, uniform |
//! | power of an emitter | Φ = ∫∫ L cos θ dω dA | uniform |
//! | intensity towards ω | I(ω) = ∫ L cos⁺θ dA | area |
//! | integral of a microfacet distribution | ∫ D cos θm dm, ∫ ⟨ωo, m⟩⁺ D dm, ∫ D_ωo dm ([`super::microfacet_integral`]) | uniform, cosine |
//! | mean path length in an enclosure | ⟨ℓ⟩ = E[distance between diffuse bounces] | cosine |
//! | flux onto a receiver shape R | Φ = ∫_R E(x) dA(x) (a view factor: Φ / (π L A_emitter)) | light, bsdf, mis, mis_balance, uniform |
//!
//! V_S(ω) is 1 where the first surface along ω belongs to S. Irradiance treats p as a
//! virtual receiver with f = 1 (so that "BSDF sampling" is cosine sampling), after which
//! the path tracer estimates Li, including every bounce the effects analysis allows.

use crate::bsdf::{Bsdf, BsdfModel, Microfacet};
use crate::math::{Frame, PI, TWO_PI};
use crate::sampling::SampleStream;
use crate::sampling::hemisphere::{cosine_hemisphere, uniform_hemisphere};
use crate::sampling::sphere::uniform_sphere;
use crate::scene::Scene;
use crate::scene::emitter::EmitterKind;
use crate::transport::microfacet_integral::{self, MicrofacetIntegral};
use crate::transport::path::{Config, Prev, next_event, trace};
use crate::transport::phase::{Dimensions, Grey, Lanes, Phase, finish};
use crate::transport::{Estimator, Geometric, Sampling, Strategy};
use glam::{Vec2, Vec3, Vec4};

/// A measurement in engine coordinates (f32, rebased on the scene origin).
#[derive(Clone, Debug, PartialEq)]
pub enum Measure {
    /// Solid angle of shape `shape` seen from `from`.
    SolidAngle {
        /// Viewpoint.
        from: Vec3,
        /// Shape index.
        shape: usize,
    },
    /// Projected solid angle of `shape` for a receiver at `from` facing `normal`.
    ProjectedSolidAngle {
        /// Viewpoint.
        from: Vec3,
        /// Receiver normal.
        normal: Vec3,
        /// Shape index.
        shape: usize,
    },
    /// Irradiance at `at` on a receiver facing `normal`.
    Irradiance {
        /// Receiver point.
        at: Vec3,
        /// Receiver normal.
        normal: Vec3,
    },
    /// Radiance arriving at `at` travelling against `direction` (seen looking along it).
    Radiance {
        /// Eye point.
        at: Vec3,
        /// Viewing direction.
        direction: Vec3,
    },
    /// Directional albedo of a BSDF for the outgoing direction `wo` (local frame).
    Albedo {
        /// The BSDF.
        bsdf: Box<Bsdf>,
        /// Outgoing direction.
        wo: Vec3,
    },
    /// An integral of a microfacet distribution for the direction `wo` (local frame).
    Microfacet {
        /// The distribution (its masking form is irrelevant here).
        microfacet: Microfacet,
        /// Outgoing direction.
        wo: Vec3,
        /// Which integral.
        integral: MicrofacetIntegral,
    },
    /// Power of emitter `emitter`.
    Power {
        /// Emitter index.
        emitter: usize,
    },
    /// Intensity of emitter `emitter` towards `direction`.
    Intensity {
        /// Emitter index.
        emitter: usize,
        /// Direction.
        direction: Vec3,
    },
    /// Mean length of the first `segments` free flights of a diffuse random walk inside
    /// the closed shape `shape`, started uniformly by area with a cosine direction.
    MeanPathLength {
        /// The enclosure (normals facing inwards do not matter: each flight leaves on
        /// the side it arrived from).
        shape: usize,
        /// Flights averaged per path.
        segments: u32,
    },
    /// Power arriving on the side of shape `shape` its normal faces, Φ = ∫ E dA,
    /// times `factor` (1, or 1/(π L A) of the emitter for a view factor). A point is
    /// sampled on the receiver by area and its irradiance estimated as [`Measure::Irradiance`]
    /// does, from the surface point (rays offset past its error bound).
    Flux {
        /// The receiver.
        shape: usize,
        /// A point of the receiver (the centre of a sphere): where transport starts, for
        /// the effects analysis.
        anchor: Vec3,
        /// Multiplies the flux: 1, or 1/(π L A) of the one emitter (the view factor).
        factor: f32,
    },
}

impl Measure {
    /// The point light transport starts from, for transport measurements.
    pub fn origin(&self) -> Option<Vec3> {
        match self {
            Measure::Irradiance { at, .. } | Measure::Radiance { at, .. } => Some(*at),
            Measure::Flux { anchor, .. } => Some(*anchor),
            Measure::SolidAngle { .. }
            | Measure::ProjectedSolidAngle { .. }
            | Measure::Albedo { .. }
            | Measure::Microfacet { .. }
            | Measure::Power { .. }
            | Measure::Intensity { .. }
            | Measure::MeanPathLength { .. } => None,
        }
    }

    /// Short name.
    pub fn name(&self) -> &'static str {
        match self {
            Measure::SolidAngle { .. } => "solid_angle",
            Measure::ProjectedSolidAngle { .. } => "projected_solid_angle",
            Measure::Irradiance { .. } => "irradiance",
            Measure::Radiance { .. } => "radiance",
            Measure::Albedo { .. } => "albedo",
            Measure::Microfacet { .. } => "microfacet",
            Measure::Power { .. } => "power",
            Measure::Intensity { .. } => "intensity",
            Measure::MeanPathLength { .. } => "mean_path_length",
            Measure::Flux { .. } => "flux",
        }
    }

    /// The path tracer's bound on scatterings for a case's `max_depth` (pbrt's count,
    /// ≥ 1): radiance scatters `depth` times after the emission seen directly; the virtual
    /// receiver of irradiance and flux is the first scattering, so `depth − 1` bounces
    /// follow it. `None` for a measurement that is not made of light paths.
    pub fn bounces_for_depth(&self, depth: u32) -> Option<u32> {
        match self {
            Measure::Radiance { .. } => Some(depth),
            Measure::Irradiance { .. } | Measure::Flux { .. } => depth.checked_sub(1),
            Measure::SolidAngle { .. }
            | Measure::ProjectedSolidAngle { .. }
            | Measure::Albedo { .. }
            | Measure::Microfacet { .. }
            | Measure::Power { .. }
            | Measure::Intensity { .. }
            | Measure::MeanPathLength { .. } => None,
        }
    }

    /// The estimators this measurement supports.
    pub fn estimators(&self) -> &'static [Estimator] {
        use Estimator::*;
        match self {
            Measure::SolidAngle { .. } => &[Uniform, Area],
            Measure::ProjectedSolidAngle { .. } => &[Uniform, Cosine, Area],
            Measure::Irradiance { .. } => &[Light, Bsdf, Mis, MisBalance, Uniform],
            Measure::Radiance { .. } => &[Light, Bsdf, Mis, MisBalance],
            Measure::Albedo { .. } => &[Bsdf, Uniform],
            Measure::Microfacet { .. } => &[Uniform, Cosine],
            Measure::Power { .. } => &[Uniform],
            Measure::Intensity { .. } => &[Area],
            Measure::MeanPathLength { .. } => &[Cosine],
            Measure::Flux { .. } => &[Light, Bsdf, Mis, MisBalance, Uniform],
        }
    }

    /// One sample of the estimator `est`, grey and static (see [`Measure::sample_with`]).
    pub fn sample(&self, scene: &Scene, est: Estimator, cfg: &Config, s: &mut SampleStream) -> f32 {
        self.sample_phase(scene, est, cfg, &Grey, s)
    }

    /// One sample of the estimator `est` over every dimension `dims` names: the grey,
    /// static path when wavelength and time integrate out (times the pruned wavelength
    /// factor), else a path carrying one or four wavelengths and a time.
    pub fn sample_with(
        &self,
        scene: &Scene,
        est: Estimator,
        cfg: &Config,
        dims: &Dimensions,
        s: &mut SampleStream,
    ) -> f32 {
        if dims.is_grey_static() {
            return self.sample_phase(scene, est, cfg, &Grey, s) * dims.factor;
        }
        if dims.hero() {
            let phase = dims.draw::<Vec4>(s);
            finish(self.sample_phase(scene, est, cfg, &phase, s), phase.weight)
        } else {
            let phase = dims.draw::<f32>(s);
            finish(self.sample_phase(scene, est, cfg, &phase, s), phase.weight)
        }
    }

    /// One sample of the estimator `est` at the wavelengths and time of `phase`.
    pub fn sample_phase<P: Phase>(
        &self,
        scene: &Scene,
        est: Estimator,
        cfg: &Config,
        phase: &P,
        s: &mut SampleStream,
    ) -> P::L {
        let grey = |v: f32| P::L::splat(v);
        if !self.estimators().contains(&est) {
            return grey(NOT_AN_ESTIMATOR_OF_THIS);
        }
        match self {
            Measure::SolidAngle { from, shape } => grey(match est.sampling() {
                Sampling::Geometric(Geometric::Area) => {
                    area_visibility(scene, *from, *shape, None, s)
                }
                Sampling::Geometric(Geometric::Uniform) => {
                    let w = uniform_sphere(s.next_2d());
                    if first_shape(scene, *from, w) == Some(*shape) {
                        4.0 * PI
                    } else {
                        0.0
                    }
                }
                Sampling::Geometric(Geometric::Cosine) | Sampling::Transport(_) => {
                    NOT_AN_ESTIMATOR_OF_THIS
                }
            }),
            Measure::ProjectedSolidAngle {
                from,
                normal,
                shape,
            } => grey(match est.sampling() {
                Sampling::Geometric(Geometric::Area) => {
                    area_visibility(scene, *from, *shape, Some(*normal), s)
                }
                Sampling::Geometric(Geometric::Cosine) => {
                    let w = Frame::from_z(*normal).to_world(cosine_hemisphere(s.next_2d()));
                    if first_shape(scene, *from, w) == Some(*shape) {
                        PI
                    } else {
                        0.0
                    }
                }
                Sampling::Geometric(Geometric::Uniform) => {
                    let wl = uniform_hemisphere(s.next_2d());
                    let w = Frame::from_z(*normal).to_world(wl);
                    if first_shape(scene, *from, w) == Some(*shape) {
                        TWO_PI * wl.z
                    } else {
                        0.0
                    }
                }
                Sampling::Transport(_) => NOT_AN_ESTIMATOR_OF_THIS,
            }),
            Measure::Irradiance { at, normal } => {
                irradiance(scene, *at, Vec3::ZERO, *normal, est, cfg, phase, s)
            }
            Measure::Flux { shape, factor, .. } => {
                let (x, n, x_err, pdf_a) = shape_area_sample(scene, *shape, s.next_2d());
                irradiance(scene, x, x_err, n, est, cfg, phase, s) * (*factor / pdf_a)
            }
            Measure::Radiance { at, direction } => {
                trace(scene, cfg, phase, *at, *direction, Prev::sensor(*at), 0, s)
            }
            Measure::Albedo { bsdf, wo } => grey(match est.sampling() {
                Sampling::Geometric(Geometric::Uniform) => {
                    let wi = uniform_sphere(s.next_2d());
                    bsdf.eval(*wo, wi) * wi.z.abs() * 4.0 * PI
                }
                // The BSDF's own sampling: the estimator a renderer uses.
                Sampling::Transport(Strategy::Bsdf) => {
                    let u = s.next_2d();
                    let uc = s.next_1d();
                    bsdf.sample(*wo, Vec3::new(u.x, u.y, uc))
                        .map_or(0.0, |b| b.weight)
                }
                Sampling::Transport(Strategy::Light | Strategy::Mis(_))
                | Sampling::Geometric(Geometric::Cosine | Geometric::Area) => {
                    NOT_AN_ESTIMATOR_OF_THIS
                }
            }),
            Measure::Microfacet {
                microfacet,
                wo,
                integral,
            } => grey(microfacet_integral::sample(
                microfacet, *wo, *integral, est, s,
            )),
            Measure::Power { emitter } => {
                phase.emission(scene, *emitter, power_sample(scene, *emitter, s), 0.0)
            }
            Measure::Intensity { emitter, direction } => phase.emission(
                scene,
                *emitter,
                intensity_sample(scene, *emitter, *direction, s),
                0.0,
            ),
            Measure::MeanPathLength { shape, segments } => {
                grey(mean_path_length(scene, *shape, *segments, s))
            }
        }
    }
}

/// The sample of an estimator a measurement cannot use (not in
/// [`Measure::estimators`], refused when a case is loaded): NaN, so that a direct caller
/// sees every such sample counted as non-finite and the verdict fail, never a silent
/// substitute estimator.
const NOT_AN_ESTIMATOR_OF_THIS: f32 = f32::NAN;

/// Index of the shape first hit from `p` along `w`.
fn first_shape(scene: &Scene, p: Vec3, w: Vec3) -> Option<usize> {
    scene.intersect(p, w, f32::INFINITY).map(|h| h.shape)
}

/// Sample a point of shape `shape` by area: (point, normal, error, density per area).
fn shape_area_sample(scene: &Scene, shape: usize, u: Vec2) -> (Vec3, Vec3, Vec3, f32) {
    let s = &scene.shapes[shape];
    let (x, _, local) = s.area_dist.sample(u.x);
    let ux =
        (x * s.area_dist.len() as f32 - local as f32).clamp(0.0, crate::math::ONE_MINUS_EPSILON);
    let a = scene.prims()[s.prims.start + local].sample_area(Vec2::new(ux, u.y));
    let n = if s.flip_normals { -a.n } else { a.n };
    (a.p, n, a.p_error, 1.0 / s.area)
}

/// Area-sampled (projected) solid angle: |cos θl| / (r² p_A), times cos θ at the receiver.
fn area_visibility(
    scene: &Scene,
    p: Vec3,
    shape: usize,
    normal: Option<Vec3>,
    s: &mut SampleStream,
) -> f32 {
    let (q, n, q_err, pdf_a) = shape_area_sample(scene, shape, s.next_2d());
    let d = q - p;
    let r2 = d.length_squared();
    if !(r2 > 0.0) {
        return 0.0;
    }
    let w = d / r2.sqrt();
    let cos_r = match normal {
        Some(nr) => w.dot(nr).max(0.0),
        None => 1.0,
    };
    if cos_r <= 0.0 {
        return 0.0;
    }
    // Visible if nothing (the shape itself included) lies between p and the sampled point:
    // a shadow ray to the point, offset by its error bound.
    if scene.segment_clear(p, q, q_err, n) {
        w.dot(n).abs() * cos_r / (r2 * pdf_a)
    } else {
        0.0
    }
}

/// Irradiance at `p` (error bound `p_err`: zero for a free point, a surface point's
/// bound for a receiver on a shape) facing `n`.
#[allow(clippy::too_many_arguments)]
fn irradiance<P: Phase>(
    scene: &Scene,
    p: Vec3,
    p_err: Vec3,
    n: Vec3,
    est: Estimator,
    cfg: &Config,
    phase: &P,
    s: &mut SampleStream,
) -> P::L {
    let frame = Frame::from_z(n);
    let uniform = est.sampling() == Sampling::Geometric(Geometric::Uniform);
    let pdf_dir = |wl: Vec3| {
        if wl.z <= 0.0 {
            0.0
        } else if uniform {
            0.5 / PI
        } else {
            wl.z / PI
        }
    };
    let mut e = next_event(scene, cfg, phase, p, p_err, None, &frame, 0.0, s, |wl| {
        (wl.z.max(0.0), pdf_dir(wl))
    });
    // Continue by cosine (or uniform) sampling unless it can contribute nothing.
    if cfg.bsdf || cfg.max_bounces > 0 {
        let wl = if uniform {
            uniform_hemisphere(s.next_2d())
        } else {
            cosine_hemisphere(s.next_2d())
        };
        let pdf = pdf_dir(wl);
        if pdf > 0.0 {
            let w = frame.to_world(wl);
            let o = if p_err == Vec3::ZERO {
                p
            } else {
                Scene::spawn(p, p_err, n, w)
            };
            let li = trace(
                scene,
                cfg,
                phase,
                o,
                w,
                Prev {
                    p,
                    pdf,
                    delta: false,
                    length: 0.0,
                    prim: None,
                },
                0,
                s,
            );
            e += li * (wl.z / pdf);
        }
    }
    e
}

fn power_sample(scene: &Scene, emitter: usize, s: &mut SampleStream) -> f32 {
    match &scene.emitters[emitter].kind {
        EmitterKind::Area {
            shape,
            radiance,
            two_sided,
        } => {
            let (_, _, _, pdf_a) = shape_area_sample(scene, *shape, s.next_2d());
            let w = if *two_sided {
                uniform_sphere(s.next_2d())
            } else {
                uniform_hemisphere(s.next_2d())
            };
            let pdf_w = if *two_sided { 0.25 / PI } else { 0.5 / PI };
            radiance * w.z.abs() / (pdf_a * pdf_w)
        }
        EmitterKind::Point { intensity, .. } => {
            let _ = s.next_2d();
            4.0 * PI * intensity
        }
        EmitterKind::Spot {
            intensity, cone, ..
        } => {
            let w = uniform_sphere(s.next_2d());
            4.0 * PI * intensity * cone.falloff(w.as_dvec3())
        }
        // Refused at load: power is not defined for emitters at infinity.
        EmitterKind::Directional { .. } | EmitterKind::Constant { .. } | EmitterKind::Map(_) => {
            f32::NAN
        }
    }
}

fn intensity_sample(scene: &Scene, emitter: usize, dir: Vec3, s: &mut SampleStream) -> f32 {
    match &scene.emitters[emitter].kind {
        EmitterKind::Area {
            shape,
            radiance,
            two_sided,
        } => {
            let (_, n, _, pdf_a) = shape_area_sample(scene, *shape, s.next_2d());
            let c = n.dot(dir);
            let c = if *two_sided { c.abs() } else { c.max(0.0) };
            radiance * c / pdf_a
        }
        EmitterKind::Point { intensity, .. } => *intensity,
        EmitterKind::Spot {
            intensity, cone, ..
        } => intensity * cone.falloff(dir.as_dvec3()),
        // Refused at load: intensity is not defined for emitters at infinity.
        EmitterKind::Directional { .. } | EmitterKind::Constant { .. } | EmitterKind::Map(_) => {
            f32::NAN
        }
    }
}

/// Mean free-flight length of a Lambertian random walk inside a closed shape.
///
/// A walk started uniformly by area with a cosine-distributed direction is in the
/// stationary state of diffuse inter-reflection (uniform area density is invariant by
/// the reciprocity A_i F_ij = A_j F_ji), so every flight is an isotropic μ-random chord
/// and its mean length is Cauchy's 4V/S. The flight length divided by c is the time of
/// flight between bounces.
fn mean_path_length(scene: &Scene, shape: usize, segments: u32, s: &mut SampleStream) -> f32 {
    let (mut p, mut n, mut p_err, _) = shape_area_sample(scene, shape, s.next_2d());
    let mut total = 0.0f64;
    let segments = segments.max(1);
    // Leave towards the inside: for a closed shape the inside is where a ray along ±n
    // finds the shape again; orient n by a first probe.
    let probe = Scene::spawn(p, p_err, -n, -n);
    if scene.intersect(probe, -n, f32::INFINITY).is_some() {
        n = -n;
    }
    for _ in 0..segments {
        let w = Frame::from_z(n).to_world(cosine_hemisphere(s.next_2d()));
        let o = Scene::spawn(p, p_err, n, w);
        let Some(h) = scene.intersect(o, w, f32::INFINITY) else {
            // Escaped: the shape is not closed, and the walk counts nothing (a case's
            // verdict then fails against 4V/S rather than on a non-finite value).
            return 0.0;
        };
        total += (h.hit.p - p).length() as f64;
        p = h.hit.p;
        p_err = h.hit.p_error;
        // Continue on the side the flight arrived from.
        n = if h.hit.n.dot(w) < 0.0 {
            h.hit.n
        } else {
            -h.hit.n
        };
    }
    (total / segments as f64) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    /// pbrt's depth count: radiance scatters `depth` times; an irradiance or flux
    /// receiver is the first scattering; object properties have no depth.
    #[test]
    fn depth_maps_to_bounces_per_measurement() {
        let rad = Measure::Radiance {
            at: Vec3::ZERO,
            direction: Vec3::Z,
        };
        let irr = Measure::Irradiance {
            at: Vec3::ZERO,
            normal: Vec3::Z,
        };
        let flux = Measure::Flux {
            shape: 0,
            anchor: Vec3::ZERO,
            factor: 1.0,
        };
        assert_eq!(rad.bounces_for_depth(3), Some(3));
        assert_eq!(irr.bounces_for_depth(1), Some(0));
        assert_eq!(flux.bounces_for_depth(4), Some(3));
        assert_eq!(irr.bounces_for_depth(0), None);
        assert_eq!(Measure::Power { emitter: 0 }.bounces_for_depth(2), None);
    }
    use crate::sampling::{Sampler, SamplerKind};
    use crate::transport::effects::Effects;

    /// Every measurement × estimator pair: the estimators a measurement lists give
    /// finite samples, every other one NaN (never a silent substitute).
    #[test]
    fn estimators_a_measurement_cannot_use_give_nan() {
        let scene = crate::scene::from_json(serde_json::json!({
            "materials": { "m": { "type": "lambertian", "albedo": 0.5 } },
            "shapes": [{ "geometry": { "type": "sphere", "center": [0, 0, 0], "radius": 1 },
                         "material": "m", "emission": { "radiance": 1 } }]
        }));
        let out = Vec3::new(0.0, 0.0, 3.0);
        let measures = [
            Measure::SolidAngle {
                from: out,
                shape: 0,
            },
            Measure::ProjectedSolidAngle {
                from: out,
                normal: -Vec3::Z,
                shape: 0,
            },
            Measure::Irradiance {
                at: out,
                normal: -Vec3::Z,
            },
            Measure::Radiance {
                at: out,
                direction: -Vec3::Z,
            },
            Measure::Albedo {
                bsdf: Box::new(scene.materials[0].bsdf.clone()),
                wo: Vec3::Z,
            },
            Measure::Power { emitter: 0 },
            Measure::Intensity {
                emitter: 0,
                direction: Vec3::Z,
            },
            Measure::MeanPathLength {
                shape: 0,
                segments: 2,
            },
            Measure::Flux {
                shape: 0,
                anchor: Vec3::ZERO,
                factor: 1.0,
            },
        ];
        let all = Estimator::ALL;
        let sampler = Sampler::new(SamplerKind::Independent, 7, 1);
        for m in &measures {
            for est in all {
                let cfg = Config::for_estimator(est, &Effects::everything());
                let v = m.sample(&scene, est, &cfg, &mut sampler.stream(3));
                assert_eq!(
                    v.is_finite(),
                    m.estimators().contains(&est),
                    "{} with {}: {v}",
                    m.name(),
                    est.name()
                );
            }
        }
    }
}
