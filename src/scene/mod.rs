//! The scene: shapes made of primitives, their materials and emission, other emitters,
//! and ray queries over them.
//!
//! Scenes are described in JSON ([`load`]); coordinates are read in `f64` and rebased
//! on a scene origin (the measurement's point) before they become `f32`, as engines with
//! large worlds do, so a scene 1e5 units from the origin keeps every digit that matters.

pub mod accel;
pub mod dispersion;
pub mod emitter;
pub mod load;
pub mod partial;
pub mod shape;

use crate::bsdf::Bsdf;
use crate::math::offset_ray_origin;
use crate::sampling::distribution::Distribution1D;
use accel::Accel;
pub use dispersion::SpectralIor;
use emitter::{Emitter, EmitterKind, LightSample, prim_pdf_from, sample_prim_from};
use glam::{Vec2, Vec3};
use shape::{Hit, Primitive};
use std::ops::Range;

/// What kind of surface a shape is (for the effects analysis).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShapeKind {
    /// A sphere: closed and convex.
    Sphere,
    /// A planar shape (rectangle, disk, single triangle or coplanar mesh).
    Planar,
    /// A general triangle mesh.
    Mesh,
}

/// A shape: primitives sharing a material and an emission.
#[derive(Clone, Debug)]
pub struct Shape {
    /// Optional name from the scene file.
    pub name: Option<String>,
    /// Its primitives in [`Scene::prims`].
    pub prims: Range<usize>,
    /// Total area.
    pub area: f32,
    /// Choice of primitive by area.
    pub area_dist: Distribution1D,
    /// Index into [`Scene::materials`], or `None` for a black absorber.
    pub material: Option<usize>,
    /// Index into [`Scene::emitters`] when the shape emits.
    pub emitter: Option<usize>,
    /// Whether normals are flipped (e.g. a sphere seen from inside).
    pub flip_normals: bool,
    /// Geometric kind.
    pub kind: ShapeKind,
    /// Linear velocity (units/s): the shape sits at its rest position + velocity · t, with
    /// t from the scene's time 0 (the shutter's start, where the rest position is taken).
    pub velocity: Vec3,
}

impl Shape {
    /// Probability that light sampling picks its primitive `prim` (by area): A_prim / A.
    /// Divided even for a shape of one primitive (where it is 1): a broken area must
    /// reach the estimate as a NaN, never be masked (`tests/proof/engine.rs`).
    #[inline]
    pub fn prim_choice_pdf(&self, prim: &Primitive) -> f32 {
        prim.area() / self.area
    }
}

/// A ray's first hit on a shape.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceHit {
    /// Geometry of the hit (normal already flipped if the shape says so).
    pub hit: Hit,
    /// The shape.
    pub shape: usize,
    /// The primitive.
    pub prim: usize,
}

/// A material: its BSDF and, when dispersive, its wavelength-dependent index (the BSDF
/// then holds the index at 550 nm, for grey paths).
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// The scattering model.
    pub bsdf: Bsdf,
    /// η(λ) (and k(λ)) of a dispersive material.
    pub ior: Option<SpectralIor>,
}

impl Material {
    /// A material that does not disperse.
    pub fn grey(bsdf: Bsdf) -> Self {
        Material { bsdf, ior: None }
    }
}

/// A built scene.
pub struct Scene {
    /// Shapes.
    pub shapes: Vec<Shape>,
    /// For each primitive, its shape.
    pub prim_shape: Vec<u32>,
    /// Materials.
    pub materials: Vec<Material>,
    /// Emitters (area emitters point at their shape).
    pub emitters: Vec<Emitter>,
    /// Whether any emitter or shape moves.
    moving: bool,
    /// Primitives of moving shapes (the BVH skips them; they are tested one by one,
    /// the ray moved into the shape's rest frame).
    moving_prims: Vec<usize>,
    accel: Accel,
}

/// Relative length of a shadow ray short of its (already offset) target: a few ulps.
/// pbrt-v4 uses 1e-4, which lets shadow rays stop 1e-4·d short: for a light or shape of
/// size ~1e-3 at distance 1 that hides real occlusion (measured: +0.8% on the solid
/// angle of a 1e-6 sr sphere). The target is offset by its error bound instead.
pub const SHADOW_EPSILON: f32 = 1e-6;

impl Scene {
    /// Assemble a scene; primitives are given per shape, in order. An emitting shape
    /// moves with its shape.
    pub fn new(
        shapes: Vec<Shape>,
        prims: Vec<Primitive>,
        materials: Vec<Material>,
        mut emitters: Vec<Emitter>,
    ) -> Self {
        let mut prim_shape = vec![0u32; prims.len()];
        for (i, s) in shapes.iter().enumerate() {
            for p in s.prims.clone() {
                prim_shape[p] = i as u32;
            }
        }
        for e in emitters.iter_mut() {
            if let EmitterKind::Area { shape, .. } = e.kind {
                e.props.velocity = shapes[shape].velocity;
            }
        }
        let moving_prims: Vec<usize> = shapes
            .iter()
            .filter(|s| s.velocity != Vec3::ZERO)
            .flat_map(|s| s.prims.clone())
            .collect();
        let mut accel = Accel::new(prims);
        if !moving_prims.is_empty() {
            let mut skip = vec![false; prim_shape.len()];
            for &p in &moving_prims {
                skip[p] = true;
            }
            accel.set_skip(skip);
        }
        let moving =
            emitters.iter().any(|e| e.props.velocity != Vec3::ZERO) || !moving_prims.is_empty();
        Scene {
            shapes,
            prim_shape,
            materials,
            emitters,
            moving,
            moving_prims,
            accel,
        }
    }

    /// Whether any emitter moves.
    pub fn has_motion(&self) -> bool {
        self.moving
    }

    /// Whether any emitter's spectrum or material's index varies with wavelength.
    pub fn is_spectral(&self) -> bool {
        self.emitters.iter().any(|e| e.props.spectrum.is_some())
            || self.materials.iter().any(|m| m.ior.is_some())
    }

    /// All primitives.
    pub fn prims(&self) -> &[Primitive] {
        self.accel.prims()
    }

    /// Closest surface along the unit direction `d` from `o` (at time 0).
    pub fn intersect(&self, o: Vec3, d: Vec3, tmax: f32) -> Option<SurfaceHit> {
        self.intersect_at(o, d, tmax, 0.0)
    }

    /// Where the primitive `prim` sits at time `t`, relative to its rest position.
    #[inline]
    fn shift(&self, prim: usize, t: f32) -> Vec3 {
        self.shapes[self.prim_shape[prim] as usize].velocity * t
    }

    /// Closest surface along the unit direction `d` from `o` at time `t`: a moving
    /// shape is tested against the ray moved into its rest frame, o − v t.
    pub fn intersect_at(&self, o: Vec3, d: Vec3, tmax: f32, t: f32) -> Option<SurfaceHit> {
        let mut best = self.accel.intersect(o, d, 0.0, tmax);
        for &i in &self.moving_prims {
            let shift = self.shift(i, t);
            let tm = best.as_ref().map_or(tmax, |b| b.1.t);
            if let Some(mut h) = self.prims()[i].intersect(o - shift, d, 0.0, tm) {
                // Translating adds up to an ulp of the larger magnitude to the error.
                h.p_error += h.p.abs().max(shift.abs()) * f32::EPSILON;
                h.p += shift;
                best = Some((i, h));
            }
        }
        let (prim, mut hit) = best?;
        let shape = self.prim_shape[prim] as usize;
        if self.shapes[shape].flip_normals {
            hit.n = -hit.n;
        }
        Some(SurfaceHit { hit, shape, prim })
    }

    /// Spawn a ray from a surface point: origin offset past its error bound.
    pub fn spawn(p: Vec3, p_error: Vec3, n: Vec3, w: Vec3) -> Vec3 {
        offset_ray_origin(p, p_error, n, w)
    }

    /// Whether the segment from `from` (a surface point with error `from_error` and normal
    /// `from_n`, or a free point with zero error) to the light sample is clear.
    pub fn visible(&self, from: Vec3, from_error: Vec3, from_n: Vec3, ls: &LightSample) -> bool {
        self.visible_at(from, from_error, from_n, ls, 0.0)
    }

    /// Whether nothing crosses the ray o + s d, 0 < s < tmax, at time `t`.
    fn unoccluded_at(&self, o: Vec3, d: Vec3, tmax: f32, t: f32) -> bool {
        self.accel.unoccluded(o, d, 0.0, tmax)
            && self.moving_prims.iter().all(|&i| {
                self.prims()[i]
                    .intersect(o - self.shift(i, t), d, 0.0, tmax)
                    .is_none()
            })
    }

    /// [`Scene::visible`] at time `t` (moving shapes where they are then).
    pub fn visible_at(
        &self,
        from: Vec3,
        from_error: Vec3,
        from_n: Vec3,
        ls: &LightSample,
        t: f32,
    ) -> bool {
        let o = if from_error == Vec3::ZERO {
            from
        } else {
            offset_ray_origin(from, from_error, from_n, ls.wi)
        };
        if ls.infinite {
            return self.unoccluded_at(o, ls.wi, f32::INFINITY, t);
        }
        if let Some(dist) = ls.ray_dist {
            // A sphere's cone or inside sample: `wi` and `dist` were formed in f64, and the
            // viewer may lie closer to the sphere than the rounding of either point (a
            // floor point 10⁻⁸ below a sphere light 1.5 from the origin), where a segment
            // towards the offset f32 point would point anywhere (and through the floor).
            // The ray along `wi` is clear unless the first thing it meets before the point
            // is another shape: the sphere is convex and the point on the cap the viewer
            // sees (or, from inside, where the ray leaves it), so the sphere itself cannot
            // stand in front of it (a hit on it is the point, within rounding). A mixture's
            // direction sample (a cap, disk or annulus from close by) is the first point
            // of its primitive along the ray, and such a shape is that one primitive.
            let own = self.emitters.get(ls.emitter).and_then(|e| e.kind.shape());
            return self
                .intersect_at(o, ls.wi, dist * (1.0 - SHADOW_EPSILON), t)
                .is_none_or(|h| Some(h.shape) == own);
        }
        let target = if ls.p_error == Vec3::ZERO {
            ls.p
        } else {
            offset_ray_origin(ls.p, ls.p_error, ls.n, -ls.wi)
        };
        let d = target - o;
        let dist = d.length();
        if dist <= 0.0 {
            return true;
        }
        self.unoccluded_at(o, d / dist, dist * (1.0 - SHADOW_EPSILON), t)
    }

    /// Whether the segment from the free point `p` to the surface point `q` (error bound
    /// `q_error`, normal `q_n`) crosses no surface.
    pub fn segment_clear(&self, p: Vec3, q: Vec3, q_error: Vec3, q_n: Vec3) -> bool {
        let target = offset_ray_origin(q, q_error, q_n, p - q);
        let d = target - p;
        let dist = d.length();
        dist <= 0.0 || self.unoccluded_at(p, d / dist, dist * (1.0 - SHADOW_EPSILON), 0.0)
    }

    /// Radiance emitted by the surface hit towards `wo` (pointing away from it).
    pub fn emitted(&self, sh: &SurfaceHit, wo: Vec3) -> f32 {
        // Only area lights sit on shapes.
        if let Some(EmitterKind::Area {
            radiance,
            two_sided,
            ..
        }) = self.shapes[sh.shape]
            .emitter
            .map(|e| &self.emitters[e].kind)
            && (*two_sided || sh.hit.n.dot(wo) > 0.0)
        {
            *radiance
        } else {
            0.0
        }
    }

    /// Radiance from the lights at infinity along an escaping direction.
    pub fn escaped(&self, d: Vec3) -> f32 {
        self.emitters.iter().map(|e| e.kind.eval_infinite(d)).sum()
    }

    /// Each light at infinity seen along an escaping direction: (emitter, radiance ≠ 0).
    pub fn escaped_each(&self, d: Vec3) -> impl Iterator<Item = (usize, f32)> + '_ {
        self.emitters
            .iter()
            .enumerate()
            .filter(|(_, e)| e.kind.is_infinite())
            .map(move |(i, e)| (i, e.kind.eval_infinite(d)))
            // `!= 0`, not `> 0`: a NaN or negative radiance must reach the accumulator.
            .filter(|&(_, l)| l != 0.0)
    }

    /// Probability of choosing one emitter (uniform selection).
    pub fn emitter_choice_pdf(&self) -> f32 {
        match self.emitters.len() {
            0 => 0.0,
            1 => 1.0,
            n => 1.0 / n as f32,
        }
    }

    /// Sample incident light at `p` at time `t`: a moving emitter is sampled from
    /// p − v t in its rest frame and the sample moved by v t. `on`: the primitive `p` lies
    /// on (a scattering point), `None` for a free point (see [`Scene::sample_light_from`]).
    pub fn sample_light_at(
        &self,
        p: Vec3,
        on: Option<usize>,
        u_choice: f32,
        u: Vec2,
        t: f32,
    ) -> Option<LightSample> {
        if !self.moving {
            return self.sample_light_from(p, on, u_choice, u);
        }
        let n = self.emitters.len();
        let k = ((u_choice * n as f32) as usize).min(n.saturating_sub(1));
        let shift = self
            .emitters
            .get(k)
            .map_or(Vec3::ZERO, |e| e.props.velocity * t);
        if shift == Vec3::ZERO {
            return self.sample_light_from(p, on, u_choice, u);
        }
        let mut ls = self.sample_light_from(p - shift, on, u_choice, u)?;
        if !ls.infinite {
            ls.p_error += ls.p.abs().max(shift.abs()) * f32::EPSILON;
            ls.p += shift;
        }
        Some(ls)
    }

    /// Sample incident light at the free point `p` (uniform choice of emitter, then the
    /// emitter's best strategy). The returned density includes the choice.
    pub fn sample_light(&self, p: Vec3, u_choice: f32, u: Vec2) -> Option<LightSample> {
        self.sample_light_from(p, None, u_choice, u)
    }

    /// [`Scene::sample_light`] from a point that lies on the primitive `on` (a scattering
    /// point; `None`: a free point). A point of another primitive is known off a sphere
    /// light however close it comes, and is served by the sphere's cone where a free point
    /// within the sphere's band is sampled by area
    /// ([`emitter::prim_strategy`]); [`Scene::light_pdf_surface_at`] takes the
    /// same `on`.
    pub fn sample_light_from(
        &self,
        p: Vec3,
        on: Option<usize>,
        u_choice: f32,
        u: Vec2,
    ) -> Option<LightSample> {
        let n = self.emitters.len();
        if n == 0 {
            return None;
        }
        let k = ((u_choice * n as f32) as usize).min(n - 1);
        let choice = if n == 1 { 1.0 } else { 1.0 / n as f32 };
        let mut ls = match &self.emitters[k].kind {
            EmitterKind::Area {
                shape,
                radiance,
                two_sided,
            } => {
                let s = &self.shapes[*shape];
                // The position within the chosen cell is a fresh uniform number. A shape
                // of one primitive has one cell, whose sample is u itself (the same bits
                // the distribution returns for u ∈ [0, 1)): no search.
                let (ux, local) = if s.area_dist.len() == 1 {
                    (u.x.clamp(0.0, 1.0), 0)
                } else {
                    let (x, _, local) = s.area_dist.sample(u.x);
                    let n = s.area_dist.len() as f32;
                    ((x * n - local as f32).clamp(0.0, 1.0), local)
                };
                let prim_index = s.prims.start + local;
                let prim = &self.prims()[prim_index];
                let ps = sample_prim_from(
                    prim,
                    p,
                    on.is_some_and(|i| i != prim_index),
                    Vec2::new(ux.min(crate::math::ONE_MINUS_EPSILON), u.y),
                )?;
                let (q, mut nq) = (ps.p, ps.n);
                let d = q - p;
                // A sphere sample's direction and distance come from f64 ([`PrimSample::ray`]).
                let dist = ps.ray.map_or_else(|| d.length(), |(_, t)| t);
                let pdf_w = ps.density.solid_angle(d, dist, nq)?;
                if s.flip_normals {
                    nq = -nq;
                }
                if !(dist > 0.0) {
                    return None;
                }
                let wi = ps.ray.map_or(d / dist, |(w, _)| w);
                let front = match ps.faces_viewer {
                    Some(outward) => outward != s.flip_normals,
                    None => nq.dot(-wi) > 0.0,
                };
                let li = if *two_sided || front { *radiance } else { 0.0 };
                let p_choice_prim = s.prim_choice_pdf(prim);
                LightSample {
                    wi,
                    li,
                    pdf: pdf_w * p_choice_prim,
                    p: q,
                    p_error: ps.p_error,
                    n: nq,
                    infinite: false,
                    delta: false,
                    emitter: k,
                    ray_dist: ps.ray.map(|(_, t)| t),
                }
            }
            e => e.sample_non_area(p, u)?,
        };
        ls.pdf *= choice;
        ls.emitter = k;
        // Only a zero density means "no sample"; a NaN or infinite density or radiance
        // is returned as it is, so that next-event estimation counts it (never masked).
        (ls.pdf != 0.0).then_some(ls)
    }

    /// Density (solid angle, including the emitter choice) with which
    /// [`Scene::sample_light`] would pick the surface point `sh` from `p`.
    pub fn light_pdf_surface(&self, p: Vec3, sh: &SurfaceHit) -> f32 {
        self.light_pdf_surface_at(p, None, sh, 0.0)
    }

    /// [`Scene::light_pdf_surface`] at time `t` from a point on the primitive `on`
    /// (`None`: a free point), as [`Scene::sample_light_from`] samples it: evaluated in
    /// the shape's rest frame.
    pub fn light_pdf_surface_at(&self, p: Vec3, on: Option<usize>, sh: &SurfaceHit, t: f32) -> f32 {
        let s = &self.shapes[sh.shape];
        if s.emitter.is_none() {
            return 0.0;
        }
        let prim = &self.prims()[sh.prim];
        let n = if s.flip_normals { -sh.hit.n } else { sh.hit.n };
        let shift = s.velocity * t;
        prim_pdf_from(
            prim,
            p - shift,
            on.is_some_and(|i| i != sh.prim),
            sh.hit.p - shift,
            n,
        ) * s.prim_choice_pdf(prim)
            * self.emitter_choice_pdf()
    }

    /// Density (including the emitter choice) of sampling the escaping direction `d`.
    pub fn light_pdf_infinite(&self, d: Vec3) -> f32 {
        self.emitters
            .iter()
            .map(|e| e.kind.pdf_infinite(d))
            .sum::<f32>()
            * self.emitter_choice_pdf()
    }

    /// Whether any emitter exists.
    pub fn has_emitters(&self) -> bool {
        !self.emitters.is_empty()
    }
}

/// A scene from its JSON description, at the origin and time 0 (for unit tests).
#[cfg(test)]
pub(crate) fn from_json(v: serde_json::Value) -> Scene {
    let d: load::SceneDesc = serde_json::from_value(v).unwrap();
    d.build(
        "t.json",
        "scene",
        std::path::Path::new("."),
        glam::DVec3::ZERO,
        0.0,
    )
    .unwrap()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Sampler;
    use crate::stats::{Accumulator, MeanTest};
    use glam::DVec3;
    use serde_json::json;

    fn sphere_light(radius: f64, flip: bool, two_sided: bool) -> Scene {
        from_json(json!({ "shapes": [{
            "geometry": { "type": "sphere", "center": [0.5, 0.3, 2.0], "radius": radius },
            "flip_normals": flip,
            "emission": { "radiance": 3.0, "two_sided": two_sided }
        }]}))
    }

    /// Every cone sample of a sphere light seen from outside lies on the cap that faces
    /// the viewer, however small the sphere against its point's f32 rounding: its
    /// radiance is L (0 for an inward-facing one-sided sphere, L again two-sided), and
    /// its density is the cone's 1/(2π(1 − cos θmax)). Fails where the side is formed
    /// from the rounded point (radius 10⁻⁸: every sample read as back-facing).
    #[test]
    fn sphere_cone_samples_face_the_viewer_at_every_radius() {
        let p = Vec3::ZERO;
        for radius in [1.0, 1e-3, 1e-6, 1e-8, 1e-15] {
            let d = DVec3::new(0.5, 0.3, 2.0).length();
            let s = (radius / d).powi(2);
            // 1 − cos θmax = 1 − √(1 − s), formed without cancellation.
            let one_minus_cos = s / (1.0 + (1.0 - s).sqrt());
            let pdf = 1.0 / (2.0 * std::f64::consts::PI * one_minus_cos);
            for (flip, two_sided, li) in
                [(false, false, 3.0), (true, false, 0.0), (true, true, 3.0)]
            {
                let scene = sphere_light(radius, flip, two_sided);
                let mut st = Sampler::independent(7).stream(0);
                for _ in 0..64 {
                    let ls = scene
                        .sample_light(p, st.next_1d(), st.next_2d())
                        .expect("a visible sphere is always sampled");
                    assert_eq!(
                        ls.li, li,
                        "radius {radius:e} flip {flip} two-sided {two_sided}"
                    );
                    let rel = (ls.pdf as f64 - pdf).abs() / pdf;
                    assert!(
                        rel < 1e-3,
                        "radius {radius:e}: pdf {} against {pdf}",
                        ls.pdf
                    );
                    assert!(ls.wi.is_finite() && ls.p.is_finite());
                }
            }
        }
    }

    /// ∫ cos θ dω over the triangle (a, b, c) seen from the origin with normal +z, by
    /// Lambert's polygon formula (Arvo 1995, eq. 9): ½ Σ βᵢ ⟨n, ĝᵢ⟩, βᵢ the angle an edge
    /// subtends and ĝᵢ the unit normal of the plane through it and the viewer.
    fn triangle_cosine_integral(v: [DVec3; 3]) -> f64 {
        let u = v.map(|x| x.normalize());
        let mut sum = 0.0;
        for i in 0..3 {
            let (a, b) = (u[i], u[(i + 1) % 3]);
            sum += a.angle_between(b) * a.cross(b).normalize().z;
        }
        0.5 * sum.abs()
    }

    /// Next-event estimation of irradiance through `sample_light` alone, E = ⟨Lᵢ cos θ /
    /// pdf⟩, where the choice of emitter, of a triangle of a mesh by area and of the point
    /// within it all matter, and the side a one-sided light shows: a sphere (L = 2), a
    /// mesh of three triangles of unequal areas facing the receiver (L = 1) and a triangle
    /// turned away from it (L = 3, one-sided: it adds nothing) above a receiver at the
    /// origin. The reference is the sum of closed forms, π L (R/D)² cos θ for the sphere
    /// (Lambert) and Lambert's polygon formula per facing triangle. One z test at α = 1e-4
    /// on 2¹⁹ samples; it sees a bias of 1% (asserted): a wrong emitter or triangle
    /// choice, a point drawn outside its own cell, or a wrong side moves E by far more.
    /// The scene a description builds, rebased on the origin.
    fn built(d: load::SceneDesc) -> Scene {
        let here = std::path::Path::new(".");
        d.build("t.json", "scene", here, DVec3::ZERO, 0.0).unwrap()
    }

    #[test]
    fn a_cone_samples_shadow_ray_is_blocked_by_another_shape() {
        // Shape 0 (a black square) hides the sphere light (shape 1) from the origin: every
        // cone sample's ray meets shape 0 first, which is not the light's own shape (a
        // shadow test that took the first shape for the light's own passed them all).
        let d: load::SceneDesc = serde_json::from_value(json!({ "shapes": [
            { "geometry": { "type": "rectangle", "corner": [-2, -2, 1], "edge_u": [4, 0, 0], "edge_v": [0, 4, 0] } },
            { "geometry": { "type": "sphere", "center": [0, 0, 3], "radius": 0.5 },
              "emission": { "radiance": 1.0 } }
        ]}))
        .unwrap();
        let scene = built(d);
        let sampler = Sampler::independent(3);
        for i in 0..256u64 {
            let mut st = sampler.stream(i);
            let ls = scene
                .sample_light_from(Vec3::ZERO, None, st.next_1d(), st.next_2d())
                .unwrap();
            assert!(ls.ray_dist.is_some(), "not a cone sample");
            assert!(!scene.visible_at(Vec3::ZERO, Vec3::ZERO, Vec3::Z, &ls, 0.0));
        }
    }

    /// From inside a sphere light, beyond its band, light samples are directions with
    /// density 1/(4π) reaching the wall where they leave it, lit only where the sphere
    /// emits inward (`flip_normals`); a square inside hides the samples that cross it
    /// and no other; within the band (a point of the sphere) sampling stays by area.
    #[test]
    fn inside_samples_of_a_sphere_light_leave_it_once() {
        let scene_with = |flip: bool| {
            built(
                serde_json::from_value(json!({ "shapes": [
                    { "geometry": { "type": "rectangle", "corner": [-0.2, -0.2, 0.5], "edge_u": [0.4, 0, 0], "edge_v": [0, 0.4, 0] } },
                    { "geometry": { "type": "sphere", "center": [0, 0, 0], "radius": 1 },
                      "flip_normals": flip, "emission": { "radiance": 2.0 } }
                ]}))
                .unwrap(),
            )
        };
        let (inward, outward) = (scene_with(true), scene_with(false));
        let sampler = Sampler::independent(5);
        let p = Vec3::new(0.0, 0.0, 0.3);
        let (mut lit, mut hidden) = (0, 0);
        for i in 0..512u64 {
            let mut st = sampler.stream(i);
            let (uc, u) = (st.next_1d(), st.next_2d());
            let ls = inward.sample_light_from(p, None, uc, u).unwrap();
            let dist = ls.ray_dist.expect("an inside sample carries its ray");
            assert_eq!(ls.pdf, 1.0 / (4.0 * std::f32::consts::PI));
            assert!(((p + ls.wi * dist).length() - 1.0).abs() < 1e-6);
            assert_eq!(ls.li, 2.0, "the inward-emitting wall faces the viewer");
            // The square at z = 0.5 spans |x|, |y| ≤ 0.2.
            let t = (0.5 - p.z) / ls.wi.z;
            let crosses =
                t > 0.0 && (p.x + t * ls.wi.x).abs() < 0.2 && (p.y + t * ls.wi.y).abs() < 0.2;
            let visible = inward.visible_at(p, Vec3::ZERO, Vec3::Z, &ls, 0.0);
            assert_eq!(visible, !crosses, "sample {i}: {:?}", ls.wi);
            lit += visible as u32;
            hidden += !visible as u32;
            let back = outward.sample_light_from(p, None, uc, u).unwrap();
            assert_eq!(
                back.li, 0.0,
                "an outward-emitting sphere does not light its inside"
            );
        }
        assert!(lit > 0 && hidden > 0, "{lit} lit, {hidden} hidden");
        // A point of the sphere itself (within its band): by area, no ray of its own.
        let mut st = sampler.stream(0);
        let ls = inward
            .sample_light_from(Vec3::new(0.6, 0.0, 0.8), None, st.next_1d(), st.next_2d())
            .unwrap();
        assert!(ls.ray_dist.is_none());
    }

    #[test]
    fn light_samples_estimate_irradiance_from_several_emitters() {
        let tri = |a: [f64; 3], b: [f64; 3], c: [f64; 3]| [a, b, c].map(DVec3::from);
        let mesh = [
            tri([-1.0, -1.0, 1.5], [0.0, -1.0, 1.5], [-1.0, 0.5, 1.5]),
            tri([0.2, -0.5, 1.0], [0.4, -0.5, 1.0], [0.2, -0.4, 1.0]),
            tri([1.0, 0.0, 2.0], [2.5, 0.0, 2.0], [1.0, 2.0, 2.5]),
        ];
        let single = tri([-2.0, 1.0, 1.0], [-1.0, 1.0, 1.2], [-2.0, 2.0, 1.0]);
        let vertices: Vec<[f64; 3]> = mesh.iter().flatten().map(|v| v.to_array()).collect();
        let d: load::SceneDesc = serde_json::from_value(json!({ "shapes": [
            { "geometry": { "type": "sphere", "center": [0.5, 0.3, 2.0], "radius": 0.4 },
              "emission": { "radiance": 2.0 } },
            { "geometry": { "type": "mesh", "vertices": vertices,
                            "indices": [[0, 2, 1], [3, 5, 4], [6, 8, 7]] },
              "emission": { "radiance": 1.0 } },
            { "geometry": { "type": "triangle", "vertices": single.map(|v| v.to_array()) },
              "emission": { "radiance": 3.0 } }
        ]}))
        .unwrap();
        let scene = built(d);
        let c = DVec3::new(0.5, 0.3, 2.0);
        let sphere = 2.0 * std::f64::consts::PI * (0.4 / c.length()).powi(2) * c.z / c.length();
        let reference = sphere
            + mesh
                .iter()
                .map(|t| triangle_cosine_integral(*t))
                .sum::<f64>();
        // The single triangle's normal (e₁ × e₂) points away from the receiver.
        let n = (single[1] - single[0]).cross(single[2] - single[0]);
        assert!(n.dot(DVec3::ZERO - single[0]) < 0.0);
        let sampler = Sampler::independent(0x5a3);
        let mut acc = Accumulator::new();
        for i in 0..1u64 << 19 {
            let mut st = sampler.stream(i);
            let v = scene
                .sample_light(Vec3::ZERO, st.next_1d(), st.next_2d())
                .map_or(0.0, |ls| {
                    f64::from(ls.li) * f64::from(ls.wi.z.max(0.0)) / f64::from(ls.pdf)
                });
            acc.push(v);
        }
        let v = MeanTest::new(1e-4, 1).judge(&acc, reference);
        assert!(v.passed, "{v:?}");
        assert!(v.detectable_relative_bias < 0.01, "{v:?}");
    }
}
