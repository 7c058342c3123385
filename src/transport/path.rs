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
//! The [`Config`] comes from the effects analysis: a scene that cannot produce a second
//! bounce is traced for one bounce only, and shadow rays are skipped where nothing can
//! occlude.

use crate::bsdf::{BsdfModel, LobeFlags};
use crate::math::Frame;
use crate::sampling::SampleStream;
use crate::scene::Scene;
use crate::scene::emitter::LightSample;
use crate::transport::Heuristic;
use glam::{Vec2, Vec3};

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
    /// Full simulation: everything on, unbounded depth.
    pub fn full(light: bool, bsdf: bool, heuristic: Heuristic) -> Self {
        Config {
            light,
            bsdf,
            heuristic,
            max_bounces: u32::MAX,
            shadow_rays: true,
            rr_depth: 3,
        }
    }

    /// MIS weight for emission reached by BSDF sampling with density `pdf_bsdf`, where
    /// light sampling would have had density `pdf_light`.
    #[inline]
    pub fn emission_weight(&self, prev_delta: bool, pdf_bsdf: f32, pdf_light: f32) -> f32 {
        if prev_delta || !self.light {
            1.0
        } else if !self.bsdf {
            0.0
        } else {
            self.heuristic.weight(pdf_bsdf, pdf_light)
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
}

/// Next-event estimation at a point with local frame `frame`: one light sample, weighted.
/// `f_pdf(wi_local)` returns (f·|cos θi|, BSDF density).
#[inline]
pub fn next_event<F>(
    scene: &Scene,
    cfg: &Config,
    p: Vec3,
    p_error: Vec3,
    frame: &Frame,
    stream: &mut SampleStream,
    f_pdf: F,
) -> f32
where
    F: Fn(Vec3) -> (f32, f32),
{
    let uc = stream.next_1d();
    let u = stream.next_2d();
    if !scene.has_emitters() {
        return 0.0;
    }
    let Some(ls) = scene.sample_light(p, uc, u) else {
        return 0.0;
    };
    if ls.li <= 0.0 {
        return 0.0;
    }
    let w = cfg.light_weight(&ls, 0.0);
    if w == 0.0 && !ls.delta {
        // Light strategy off: only delta lights are sampled.
        return 0.0;
    }
    let wi_l = frame.to_local(ls.wi);
    let (fc, pdf_b) = f_pdf(wi_l);
    if !(fc > 0.0) {
        return 0.0;
    }
    if cfg.shadow_rays && !scene.visible(p, p_error, frame.n, &ls) {
        return 0.0;
    }
    let w = cfg.light_weight(&ls, pdf_b);
    let c = fc * ls.li * w / ls.pdf;
    if c.is_finite() { c } else { 0.0 }
}

/// Estimate the radiance arriving at `o` from direction `-d` (that is, along the ray
/// o + t d), given the previous vertex and that `bounces` scatterings already happened.
pub fn trace(
    scene: &Scene,
    cfg: &Config,
    mut o: Vec3,
    mut d: Vec3,
    mut prev: Prev,
    mut bounces: u32,
    stream: &mut SampleStream,
) -> f32 {
    let mut l = 0.0f32;
    let mut beta = 1.0f32;
    loop {
        let Some(sh) = scene.intersect(o, d, f32::INFINITY) else {
            let le = scene.escaped(d);
            if le > 0.0 {
                let w = cfg.emission_weight(prev.delta, prev.pdf, scene.light_pdf_infinite(d));
                l += beta * le * w;
            }
            break;
        };
        let wo = -d;
        let le = scene.emitted(&sh, wo);
        if le > 0.0 {
            let w = cfg.emission_weight(prev.delta, prev.pdf, scene.light_pdf_surface(prev.p, &sh));
            l += beta * le * w;
        }
        if bounces >= cfg.max_bounces {
            break;
        }
        let Some(mat) = scene.shapes[sh.shape].material.map(|m| &scene.materials[m]) else {
            break;
        };
        let frame = Frame::from_z(sh.hit.n);
        let wo_l = frame.to_local(wo);
        if mat
            .flags()
            .intersects(LobeFlags::DIFFUSE | LobeFlags::GLOSSY)
        {
            l += beta
                * next_event(scene, cfg, sh.hit.p, sh.hit.p_error, &frame, stream, |wi| {
                    (mat.eval(wo_l, wi) * wi.z.abs(), mat.pdf(wo_l, wi))
                });
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
        if !(s.weight > 0.0) || !s.weight.is_finite() {
            break;
        }
        beta *= s.weight;
        let wi = frame.to_world(s.wi);
        prev = Prev {
            p: sh.hit.p,
            pdf: s.pdf,
            delta: s.lobe.is_delta(),
        };
        o = Scene::spawn(sh.hit.p, sh.hit.p_error, sh.hit.n, wi);
        d = wi;
        bounces += 1;
        if bounces >= cfg.rr_depth {
            let q = beta.min(1.0);
            if stream.next_1d() >= q {
                break;
            }
            beta /= q;
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
