//! The path tracer: an estimator of incident radiance Li along a ray.
//!
//! At each surface vertex it adds emission (weighted by MIS against the light-sampling
//! density that could have produced the same direction), performs next-event
//! estimation towards one emitter (weighted against the BSDF density), then samples the
//! BSDF to continue. Delta lobes and delta lights are never MIS-weighted (only one
//! strategy can produce them). Russian roulette from the `rr_depth`-th bounce keeps a
//! path with probability q = min(1, β) and divides β by q: the estimate stays unbiased
//! because no path is ever truncated outright (Arvo & Kirk 1990; pbrt-v4 §13.1).
//!
//! The [`Config`] comes from the plan's effects ([`Config::for_estimator`]): a scene
//! that cannot produce a second bounce is traced for one bounce only, and shadow rays are
//! skipped where nothing can occlude.

use crate::bsdf::{BsdfModel, LobeFlags};
use crate::math::Frame;
use crate::sampling::SampleStream;
use crate::scene::Scene;
use crate::scene::emitter::LightSample;
use crate::transport::effects::Effects;
use crate::transport::phase::{Lanes, Phase, terminate_secondary};
use crate::transport::{Estimator, Heuristic};
use glam::{Vec2, Vec3};

/// A guard against a path that never ends (a broken sampler feeding Russian roulette the
/// same number forever): paths stop after this many scatterings. Its bias is the energy
/// of longer paths, below ρ^65536 of the emission for a scene of albedo ρ (< 1e-28 at
/// ρ = 0.999).
pub const MAX_PATH_BOUNCES: u32 = 1 << 16;

/// First bounce at which Russian roulette may end a path (every estimator, every plan).
pub const RR_DEPTH: u32 = 3;

/// What the path tracer simulates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Config {
    /// Use next-event estimation.
    pub light: bool,
    /// Count emission found by BSDF sampling.
    pub bsdf: bool,
    /// The MIS heuristic when both are on.
    pub heuristic: Heuristic,
    /// Most surface scatterings along a path (u32::MAX: unbounded, with roulette).
    pub max_bounces: u32,
    /// Trace shadow rays (false where the effects analysis proved nothing occludes).
    pub shadow_rays: bool,
    /// First bounce at which Russian roulette may end a path.
    pub rr_depth: u32,
}

impl Config {
    /// The configuration of estimator `est` under the effects a plan decided: its
    /// strategies ([`Estimator::strategies`]), paths bounded where the plan bounds them,
    /// shadow rays where occlusion is possible, roulette from bounce [`RR_DEPTH`].
    pub fn for_estimator(est: Estimator, effects: &Effects) -> Self {
        let (light, bsdf, heuristic) = est.strategies();
        Config {
            light,
            bsdf,
            heuristic,
            max_bounces: effects.max_bounces.unwrap_or(u32::MAX),
            shadow_rays: effects.occlusion.simulated,
            rr_depth: RR_DEPTH,
        }
    }

    /// MIS weight for emission reached by BSDF sampling with density `pdf_bsdf`, where
    /// light sampling would have had density `pdf_light()`: asked only when both
    /// strategies could have produced the direction (not after a delta lobe or the
    /// camera ray, nor when a strategy is off), since the light density costs a
    /// strategy choice (and for a spherical rectangle its solid angle) per hit.
    #[inline]
    pub fn emission_weight(
        &self,
        prev_delta: bool,
        pdf_bsdf: f32,
        pdf_light: impl FnOnce() -> f32,
    ) -> f32 {
        if prev_delta || !self.light {
            1.0
        } else if !self.bsdf {
            0.0
        } else {
            self.heuristic.weight(pdf_bsdf, pdf_light())
        }
    }

    /// MIS weight for a light sample, given the BSDF density of the same direction.
    #[inline]
    pub fn light_weight(&self, ls: &LightSample, pdf_bsdf: f32) -> f32 {
        if ls.delta {
            1.0
        } else if !self.light {
            0.0
        } else if !self.bsdf {
            1.0
        } else {
            self.heuristic.weight(ls.pdf, pdf_bsdf)
        }
    }
}

/// The previous vertex of a path, for MIS of emission found by the next segment.
#[derive(Clone, Copy, Debug)]
pub struct Prev {
    /// Its position.
    pub p: Vec3,
    /// BSDF density of the direction taken.
    pub pdf: f32,
    /// Whether that direction came from a delta lobe (or a camera ray).
    pub delta: bool,
    /// Path length from the sensor to `p` (for time of flight).
    pub length: f32,
}

impl Prev {
    /// The sensor itself as the previous vertex of a camera ray (a delta direction).
    pub fn sensor(p: Vec3) -> Self {
        Prev {
            p,
            pdf: 1.0,
            delta: true,
            length: 0.0,
        }
    }
}

/// Next-event estimation at a point with local frame `frame`: one light sample, weighted.
/// `f_pdf(wi_local)` returns (f·|cos θi|, BSDF density); `length` is the path length
/// from the sensor to `p` (for time of flight).
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn next_event<P: Phase, F>(
    scene: &Scene,
    cfg: &Config,
    phase: &P,
    p: Vec3,
    p_error: Vec3,
    frame: &Frame,
    length: f32,
    stream: &mut SampleStream,
    f_pdf: F,
) -> P::L
where
    F: Fn(Vec3) -> (f32, f32),
{
    let zero = P::L::splat(0.0);
    let uc = stream.next_1d();
    let u = stream.next_2d();
    if !scene.has_emitters() {
        return zero;
    }
    let Some(ls) = scene.sample_light_at(p, uc, u, phase.time()) else {
        return zero;
    };
    // Never masked: an emitter radiance or light density that is not a finite,
    // non-negative number is a bug; it becomes a NaN sample that the accumulator counts
    // and the verdict fails on.
    if !(ls.li >= 0.0 && ls.li.is_finite() && ls.pdf > 0.0 && ls.pdf.is_finite()) {
        return P::L::splat(f32::NAN);
    }
    if ls.li == 0.0 {
        return zero;
    }
    let w = cfg.light_weight(&ls, 0.0);
    if w == 0.0 && !ls.delta {
        // Light strategy off: only delta lights are sampled.
        return zero;
    }
    let wi_l = frame.to_local(ls.wi);
    let (fc, pdf_b) = f_pdf(wi_l);
    if fc == 0.0 {
        return zero;
    }
    if !(fc > 0.0 && fc.is_finite() && pdf_b >= 0.0 && pdf_b.is_finite()) {
        // A BSDF value or density that is negative or not finite: counted, never masked.
        return P::L::splat(f32::NAN);
    }
    if cfg.shadow_rays && !scene.visible_at(p, p_error, frame.n, &ls, phase.time()) {
        return zero;
    }
    let w = cfg.light_weight(&ls, pdf_b);
    let c = fc * w / ls.pdf;
    let dist = if phase.tracks_length() && !ls.infinite {
        (ls.p - p).length()
    } else {
        0.0
    };
    // Not masked: a non-finite product reaches the accumulator, which counts it.
    phase.emission(scene, ls.emitter, ls.li, length + dist) * c
}

/// Estimate the radiance arriving at `o` from direction `-d` (that is, along the ray
/// o + t d), given the previous vertex and that `bounces` scatterings already happened.
#[allow(clippy::too_many_arguments)]
pub fn trace<P: Phase>(
    scene: &Scene,
    cfg: &Config,
    phase: &P,
    mut o: Vec3,
    mut d: Vec3,
    mut prev: Prev,
    mut bounces: u32,
    stream: &mut SampleStream,
) -> P::L {
    let mut l = P::L::splat(0.0);
    let mut beta = P::L::splat(1.0);
    // Path length from the sensor, for time of flight.
    let mut length = prev.length;
    // Whether a dispersive surface already ended the secondary wavelength lanes.
    let mut terminated = false;
    loop {
        let Some(sh) = scene.intersect_at(o, d, f32::INFINITY, phase.time()) else {
            for (e, le) in scene.escaped_each(d) {
                let w = cfg.emission_weight(prev.delta, prev.pdf, || scene.light_pdf_infinite(d));
                l += beta * phase.emission(scene, e, le * w, f32::INFINITY);
            }
            break;
        };
        if phase.tracks_length() {
            length += (sh.hit.p - o).length();
        }
        let wo = -d;
        let le = scene.emitted(&sh, wo);
        // `!= 0`, not `> 0`: a NaN or negative emission must reach the accumulator.
        if le != 0.0 {
            let w = cfg.emission_weight(prev.delta, prev.pdf, || {
                scene.light_pdf_surface_at(prev.p, &sh, phase.time())
            });
            let e = scene.shapes[sh.shape].emitter.unwrap_or(0);
            l += beta * phase.emission(scene, e, le * w, length);
        }
        if bounces >= cfg.max_bounces.min(MAX_PATH_BOUNCES) {
            break;
        }
        let Some(m) = scene.shapes[sh.shape].material else {
            break;
        };
        let (mat, disperses) = phase.material(scene, m);
        if disperses && !terminated {
            beta = terminate_secondary(beta);
            terminated = true;
        }
        let frame = Frame::from_z(sh.hit.n);
        let wo_l = frame.to_local(wo);
        if mat
            .flags()
            .intersects(LobeFlags::DIFFUSE | LobeFlags::GLOSSY)
        {
            l += beta
                * next_event(
                    scene,
                    cfg,
                    phase,
                    sh.hit.p,
                    sh.hit.p_error,
                    &frame,
                    length,
                    stream,
                    |wi| (mat.eval(wo_l, wi) * wi.z.abs(), mat.pdf(wo_l, wi)),
                );
        } else {
            // Keep the stream's dimensions aligned whether or not NEE ran.
            stream.next_1d();
            stream.next_2d();
        }
        let u = stream.next_2d();
        let uc = stream.next_1d();
        let Some(s) = mat.sample(wo_l, Vec3::new(u.x, u.y, uc)) else {
            break;
        };
        if s.weight == 0.0 {
            break;
        }
        if !(s.weight > 0.0 && s.weight.is_finite() && s.pdf >= 0.0 && !s.pdf.is_nan()) {
            // A sampled weight or density that is negative or not finite: the path's
            // value becomes NaN, counted by the accumulator (never a silent end).
            l = P::L::splat(f32::NAN);
            break;
        }
        beta *= s.weight;
        let wi = frame.to_world(s.wi);
        prev = Prev {
            p: sh.hit.p,
            pdf: s.pdf,
            delta: s.lobe.is_delta(),
            length,
        };
        o = Scene::spawn(sh.hit.p, sh.hit.p_error, sh.hit.n, wi);
        d = wi;
        bounces += 1;
        if bounces >= cfg.rr_depth {
            let q = beta.max_lane().min(1.0);
            if stream.next_1d() >= q {
                break;
            }
            beta *= 1.0 / q;
        }
    }
    // Not masked: a NaN here is a bug the accumulator counts and the verdict fails.
    l
}

/// A 2-D sample helper for measurements.
#[inline]
pub fn next2(stream: &mut SampleStream) -> Vec2 {
    stream.next_2d()
}
