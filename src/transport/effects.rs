//! Effects analysis: decide, before estimating, which effects of light transport can
//! contribute to a measurement in a scene, and simulate only those.
//!
//! Each effect is a [`Decision`] with the reason. The rules are conservative — an
//! effect is pruned only when geometry proves it cannot contribute:
//!
//! - **single scattering** needs an emitter and a surface with a material;
//! - **multiple scattering** needs two scattering shapes, or one that can see itself:
//!   a planar shape never sees itself, and a sphere only from inside (when a path of the
//!   measurement may start inside it or on its surface — any point of a flux receiver —
//!   or its material transmits); a mesh may;
//! - **occlusion** (shadow rays) needs a segment that can cross a surface other than its
//!   end points: with no shapes, or one convex shape that is the only emitter (segments
//!   between a point and a plane, between two points of a sphere from inside, or to the
//!   cone-sampled visible cap of a sphere from outside cross nothing else), none can; a
//!   camera ray's first hit on one planar or (from outside) spherical reflector lit
//!   only by lights at infinity needs none either;
//! - **specular chains** and **transmission** follow from the materials' lobes;
//! - **wavelength** and **time** are not dimensions of a grey, static scene (decided by
//!   [`crate::transport::plan`] with the case's spectral and time sections).
//!
//! Soundness is proven per catalog case by comparing the pruned estimate with the full
//! simulation (every effect on) in a two-sample test (`tests/proof/effects_soundness.rs`).

use crate::bsdf::{BsdfModel, LobeFlags, ModelFacts};
use crate::scene::emitter::EmitterKind;
use crate::scene::shape::Primitive;
use crate::scene::{Scene, ShapeKind};
use crate::transport::measure::Measure;
use serde::{Deserialize, Serialize};

/// Whether an effect is simulated, and why.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Decision {
    /// Simulated?
    pub simulated: bool,
    /// Why (or why not).
    pub why: String,
}

fn yes(why: impl Into<String>) -> Decision {
    Decision {
        simulated: true,
        why: why.into(),
    }
}

fn no(why: impl Into<String>) -> Decision {
    Decision {
        simulated: false,
        why: why.into(),
    }
}

/// The effects a measurement in a scene calls for.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Effects {
    /// Emission seen directly.
    pub direct_emission: Decision,
    /// One scattering between emitter and sensor.
    pub single_scattering: Decision,
    /// Two or more scatterings.
    pub multiple_scattering: Decision,
    /// Chains through delta (perfectly specular) lobes.
    pub specular_chains: Decision,
    /// Transmission through surfaces.
    pub transmission: Decision,
    /// Shadow rays.
    pub occlusion: Decision,
    /// Wavelength as a sampled dimension.
    pub wavelength: Decision,
    /// Time as a sampled dimension.
    pub time: Decision,
    /// The most scatterings a path needs (`None`: unbounded, ended by Russian roulette).
    pub max_bounces: Option<u32>,
}

/// Whether the box [`lo`, `hi`] where transport starts (a point, or a flux receiver's
/// bounds) reaches into the sphere primitive's closed ball, its surface included and
/// widened by the `f32` rounding of the coordinates: a sphere can light itself as soon
/// as a path may start inside it or on its inner wall, so only a start provably outside
/// lets multiple scattering be pruned. The distance from the centre c to the box is
/// d² = Σₖ max(loₖ − cₖ, 0, cₖ − hiₖ)², and the ball is widened by
/// δ = 2⁻²⁰ (max|coordinate| + r), far above the few ulps by which the rounded centre,
/// box and radius can misplace a surface point (a start that far outside only turns on
/// bounces that cannot happen: the same expected value at a little more cost).
fn reaches_into(prim: &Primitive, lo: glam::Vec3, hi: glam::Vec3) -> bool {
    match *prim {
        Primitive::Sphere { center, radius } => {
            let gap = (lo - center).max(center - hi).max(glam::Vec3::ZERO);
            let scale = lo.abs().max(hi.abs()).max(center.abs()).max_element() + radius;
            let reach = radius + scale * (1.0 / (1u32 << 20) as f32);
            gap.length_squared() <= reach * reach
        }
        // An open cap is a `Mesh`-kind shape, never treated as closed or convex.
        Primitive::Rectangle { .. }
        | Primitive::Disk { .. }
        | Primitive::Triangle { .. }
        | Primitive::SphericalCap { .. }
        | Primitive::Annulus { .. } => false,
    }
}

/// The box where the measurement's paths start: its point, or for a flux the bounds of
/// the whole receiver (any of its points may start a path, not only its anchor).
fn start_region(scene: &Scene, measure: &Measure, origin: glam::Vec3) -> (glam::Vec3, glam::Vec3) {
    match measure {
        Measure::Flux { shape, .. } => scene.prims()[scene.shapes[*shape].prims.clone()]
            .iter()
            .map(|p| p.bounds())
            .fold((origin, origin), |a, b| (a.0.min(b.0), a.1.max(b.1))),
        Measure::Irradiance { .. }
        | Measure::Radiance { .. }
        | Measure::SolidAngle { .. }
        | Measure::ProjectedSolidAngle { .. }
        | Measure::Albedo { .. }
        | Measure::Microfacet { .. }
        | Measure::Power { .. }
        | Measure::Intensity { .. }
        | Measure::MeanPathLength { .. } => (origin, origin),
    }
}

impl Effects {
    /// Every effect on and paths unbounded: the full simulation the pruned plans are
    /// proven against.
    pub fn everything() -> Effects {
        let y = yes("the full simulation turns every effect on");
        Effects {
            direct_emission: y.clone(),
            single_scattering: y.clone(),
            multiple_scattering: y.clone(),
            specular_chains: y.clone(),
            transmission: y.clone(),
            occlusion: y.clone(),
            wavelength: y.clone(),
            time: y,
            max_bounces: None,
        }
    }
}

/// Analyse `scene` for `measure`; the decisions for the `wavelength` and `time`
/// dimensions come with them (see [`crate::transport::plan`], which decides all at once).
pub fn analyze(scene: &Scene, measure: &Measure, wavelength: Decision, time: Decision) -> Effects {
    let Some(origin) = measure.origin() else {
        return object_property(scene, measure, wavelength, time);
    };
    let scatterers = scatterers(scene);
    let flags = scatterers
        .iter()
        .map(|&i| {
            scene.materials[scene.shapes[i].material.unwrap_or_default()]
                .bsdf
                .flags()
        })
        .fold(LobeFlags::empty(), |a, b| a | b);
    let transmits = flags.contains(LobeFlags::TRANSMISSION);
    let has_emitters = scene.has_emitters();
    let direct_emission = if has_emitters {
        yes("the scene has emitters")
    } else {
        no("the scene has no emitters")
    };
    let single = if !has_emitters {
        no("nothing emits")
    } else if scatterers.is_empty() {
        no("no surface scatters light (no material, or black)")
    } else {
        yes(format!(
            "{} scattering shape(s) and {} emitter(s)",
            scatterers.len(),
            scene.emitters.len()
        ))
    };
    let start = start_region(scene, measure, origin);
    let multiple = multiple_scattering(scene, &single, &scatterers, transmits, start);
    let max_bounces = if !single.simulated {
        Some(0)
    } else if !multiple.simulated {
        Some(1)
    } else {
        None
    };
    Effects {
        direct_emission,
        single_scattering: single,
        multiple_scattering: multiple,
        specular_chains: if flags.contains(LobeFlags::SPECULAR) {
            yes("a material has a delta lobe")
        } else {
            no("no material has a delta lobe")
        },
        transmission: if transmits {
            yes("a material transmits")
        } else {
            no("no material transmits")
        },
        occlusion: occlusion(scene, measure, origin, transmits),
        wavelength,
        time,
        max_bounces,
    }
}

/// A measurement without a viewpoint is a property of one shape, emitter or BSDF: no
/// transport, except that other shapes may hide part of a shape's solid angle.
fn object_property(
    scene: &Scene,
    measure: &Measure,
    wavelength: Decision,
    time: Decision,
) -> Effects {
    let n = no("the measurement is a property of one object, not of light transport");
    Effects {
        direct_emission: n.clone(),
        single_scattering: n.clone(),
        multiple_scattering: n.clone(),
        specular_chains: n.clone(),
        transmission: n.clone(),
        occlusion: if matches!(
            measure,
            Measure::SolidAngle { .. } | Measure::ProjectedSolidAngle { .. }
        ) && scene.shapes.len() > 1
        {
            yes("other shapes may hide part of the shape")
        } else {
            n
        },
        wavelength,
        time,
        max_bounces: Some(0),
    }
}

/// The shapes with a material that scatters light (not black).
fn scatterers(scene: &Scene) -> Vec<usize> {
    (0..scene.shapes.len())
        .filter(|&i| {
            scene.shapes[i]
                .material
                .is_some_and(|m| !scene.materials[m].bsdf.is_black())
        })
        .collect()
}

/// Two or more scatterings need two scattering shapes, or one that can see itself: a
/// planar shape never does, a sphere only from inside (a path may start inside it or on
/// its surface, it moves, or its material transmits); a mesh may.
fn multiple_scattering(
    scene: &Scene,
    single: &Decision,
    scatterers: &[usize],
    transmits: bool,
    (lo, hi): (glam::Vec3, glam::Vec3),
) -> Decision {
    let self_visible = |i: usize| {
        let s = &scene.shapes[i];
        match s.kind {
            ShapeKind::Planar => false,
            ShapeKind::Mesh => true,
            // A moving sphere may pass over the measurement point during the shutter.
            ShapeKind::Sphere => {
                transmits
                    || s.velocity != glam::Vec3::ZERO
                    || s.prims
                        .clone()
                        .any(|p| reaches_into(&scene.prims()[p], lo, hi))
            }
        }
    };
    if !single.simulated {
        no("not even single scattering is possible")
    } else if scatterers.len() >= 2 {
        yes("two or more scattering shapes can exchange light")
    } else if self_visible(scatterers[0]) {
        yes("the scattering shape can see itself (a mesh, or a sphere seen from inside)")
    } else {
        no("a single planar or convex scatterer seen from outside cannot light itself")
    }
}

/// Shadow rays are needed unless no segment can cross a surface other than its end
/// points: no shapes; one convex shape that is the only emitter; or a camera ray's first
/// hit on one convex reflector seen from outside, lit only from infinity.
fn occlusion(scene: &Scene, measure: &Measure, origin: glam::Vec3, transmits: bool) -> Decision {
    let only_shape_emits = scene
        .emitters
        .iter()
        .all(|e| matches!(e.kind, EmitterKind::Area { shape: 0, .. }));
    let only_infinite = scene.emitters.iter().all(|e| e.kind.is_infinite());
    let one_convex = scene.shapes.len() == 1 && scene.shapes[0].kind != ShapeKind::Mesh;
    if scene.shapes.is_empty() {
        no("there are no shapes to occlude")
    } else if one_convex && only_shape_emits && !transmits {
        no("one convex shape that is the only emitter: no segment crosses another surface")
    } else if one_convex
        && only_infinite
        && !transmits
        && scene.shapes[0].velocity == glam::Vec3::ZERO
        && matches!(measure, Measure::Radiance { .. })
        && !scene.shapes[0]
            .prims
            .clone()
            .any(|p| reaches_into(&scene.prims()[p], origin, origin))
    {
        no(
            "one convex reflector seen from outside and lit from infinity: its lit side faces the lights",
        )
    } else {
        yes("surfaces may block segments between vertices and emitters")
    }
}

#[cfg(test)]
mod tests {
    //! One scene per rule, each on both sides of the rule, so a rule that prunes too much
    //! (unsound) or too little (wasted work) is seen.
    use super::*;
    use glam::Vec3;
    use serde_json::json;

    fn scene(v: serde_json::Value) -> Scene {
        crate::scene::from_json(v)
    }

    /// The geometric rules only: wavelength and time are decided elsewhere.
    fn analyze(scene: &Scene, measure: &Measure) -> Effects {
        super::analyze(scene, measure, no("grey"), no("static"))
    }

    fn radiance_at(at: Vec3) -> Measure {
        Measure::Radiance {
            at,
            direction: Vec3::Z,
        }
    }

    fn irradiance_at(at: Vec3) -> Measure {
        Measure::Irradiance {
            at,
            normal: Vec3::Z,
        }
    }

    fn grey(albedo: f64) -> serde_json::Value {
        json!({ "type": "lambertian", "albedo": albedo })
    }

    fn sphere(material: Option<&str>, emits: bool) -> serde_json::Value {
        let mut s = json!({ "geometry": { "type": "sphere", "center": [0, 0, 0], "radius": 1 } });
        if let Some(m) = material {
            s["material"] = json!(m);
        }
        if emits {
            s["emission"] = json!({ "radiance": 1 });
        }
        s
    }

    fn disk(z: f64, material: Option<&str>) -> serde_json::Value {
        let mut s = json!({ "geometry": { "type": "disk", "center": [0, 0, z], "normal": [0, 0, 1], "radius": 1 } });
        if let Some(m) = material {
            s["material"] = json!(m);
        }
        s
    }

    fn point_light() -> serde_json::Value {
        json!({ "type": "point", "position": [0, 0, 5], "intensity": 1 })
    }

    fn env() -> serde_json::Value {
        json!({ "type": "constant", "radiance": 1 })
    }

    #[test]
    fn a_black_surface_does_not_scatter() {
        for (albedo, scatters) in [(0.0, false), (0.5, true)] {
            let s = scene(json!({
                "materials": { "m": grey(albedo) },
                "shapes": [disk(0.0, Some("m"))],
                "emitters": [point_light()]
            }));
            let e = analyze(&s, &irradiance_at(Vec3::new(0.0, 0.0, 2.0)));
            assert_eq!(e.single_scattering.simulated, scatters, "albedo {albedo}");
            assert_eq!(e.max_bounces, Some(scatters as u32), "albedo {albedo}");
            assert!(e.direct_emission.simulated);
        }
    }

    #[test]
    fn nothing_emits_nothing_scatters() {
        let s = scene(json!({ "materials": { "m": grey(0.5) }, "shapes": [disk(0.0, Some("m"))] }));
        let e = analyze(&s, &irradiance_at(Vec3::new(0.0, 0.0, 2.0)));
        assert!(!e.direct_emission.simulated && !e.single_scattering.simulated);
        assert!(!e.multiple_scattering.simulated);
        assert_eq!(e.max_bounces, Some(0));
    }

    #[test]
    fn a_sphere_sees_itself_only_from_inside() {
        for (at, multiple) in [
            (Vec3::new(0.0, 0.0, 0.5), true),
            (Vec3::new(0.0, 0.0, 3.0), false),
        ] {
            let s = scene(json!({
                "materials": { "m": grey(0.5) },
                "shapes": [sphere(Some("m"), false)],
                "emitters": [point_light()]
            }));
            let e = analyze(&s, &irradiance_at(at));
            assert_eq!(e.multiple_scattering.simulated, multiple, "at {at}");
            assert_eq!(e.max_bounces, if multiple { None } else { Some(1) });
        }
    }

    /// `reaches_into` includes the surface and uses the sphere's own centre and radius:
    /// an off-centre sphere of radius 2, probed inside, on its surface (the wall of an
    /// integrating sphere, where pruning to one bounce read 1.5π for a furnace's 2π) and
    /// just outside (distances chosen so that r², 2r and r/r would disagree).
    #[test]
    fn reaches_into_includes_the_surface_and_is_off_centre() {
        let s = scene(json!({
            "materials": { "m": grey(0.5) },
            "shapes": [{ "geometry": { "type": "sphere", "center": [5, 0, 0], "radius": 2 }, "material": "m" }],
            "emitters": [point_light()]
        }));
        for (at, multiple) in [
            (Vec3::new(6.5, 0.0, 0.0), true),       // 1.5² < 2², but 1.5² > 2/2
            (Vec3::new(5.0, 0.0, 2.0), true),       // on the surface: a path starts on the wall
            (Vec3::new(5.0, 0.0, 2.000005), true),  // within the margin 2⁻²⁰·(5 + 2)
            (Vec3::new(5.0, 0.0, 2.000008), false), // beyond it (2⁻²⁰·5·2 would take it)
            (Vec3::new(5.0, 0.0, 2.0001), false),
            (Vec3::new(7.1, 0.0, 0.0), false),  // 2.1² > 2²
            (Vec3::new(-6.5, 0.0, 0.0), false), // |p + c| would be small: must use p − c
        ] {
            let e = analyze(&s, &irradiance_at(at));
            assert_eq!(e.multiple_scattering.simulated, multiple, "at {at}");
        }
        // Radius 1 at the origin side: 1.5² = 2.25 is outside r² = 1 but inside r + r = 2.
        let unit = scene(json!({
            "materials": { "m": grey(0.5) },
            "shapes": [{ "geometry": { "type": "sphere", "center": [5, 0, 0], "radius": 1 }, "material": "m" }],
            "emitters": [point_light()]
        }));
        let e = analyze(&unit, &irradiance_at(Vec3::new(5.0, 1.4, 0.0)));
        assert!(!e.multiple_scattering.simulated);
    }

    /// A flux receiver starts paths from every one of its points, not only from its
    /// anchor (the centre of its bounds): a long strip through the wall of a furnace
    /// sphere, its anchor outside, still lets the sphere light itself (pruned to one
    /// bounce it read 25% low); the same strip wholly outside does not.
    #[test]
    fn a_flux_receiver_reaching_into_a_sphere_keeps_its_bounces() {
        for (corner, multiple) in [(-0.5, true), (1.5, false)] {
            let s = scene(json!({
                "materials": { "m": grey(0.5) },
                "shapes": [
                    { "geometry": { "type": "sphere", "center": [0, 0, 0], "radius": 1 },
                      "material": "m", "flip_normals": true, "emission": { "radiance": 1 } },
                    { "geometry": { "type": "rectangle", "corner": [corner, -0.001, 0],
                                    "edge_u": [10, 0, 0], "edge_v": [0, 0.002, 0] } }
                ]
            }));
            let flux = Measure::Flux {
                shape: 1,
                anchor: Vec3::new(corner as f32 + 5.0, 0.0, 0.0),
                factor: 1.0,
            };
            let e = analyze(&s, &flux);
            assert_eq!(e.multiple_scattering.simulated, multiple, "corner {corner}");
            assert_eq!(e.max_bounces, if multiple { None } else { Some(1) });
        }
    }

    /// Lobe flags of all scatterers are united: two conductors still have a delta lobe.
    #[test]
    fn lobes_of_several_scatterers_are_united() {
        let s = scene(json!({
            "materials": { "m": { "type": "conductor", "eta": 0.2, "k": 3.9 } },
            "shapes": [disk(0.0, Some("m")), disk(1.0, Some("m"))],
            "emitters": [point_light()]
        }));
        let e = analyze(&s, &irradiance_at(Vec3::new(0.0, 0.0, 0.5)));
        assert!(e.specular_chains.simulated && !e.transmission.simulated);
    }

    #[test]
    fn a_moving_or_transmitting_sphere_may_see_itself() {
        let mut moving = sphere(Some("m"), false);
        moving["velocity"] = json!([1, 0, 0]);
        let glass = json!({ "type": "dielectric", "eta": 1.5 });
        for (material, shape) in [(grey(0.5), moving), (glass, sphere(Some("m"), false))] {
            let s = scene(json!({
                "materials": { "m": material },
                "shapes": [shape],
                "emitters": [point_light()]
            }));
            let e = analyze(&s, &irradiance_at(Vec3::new(0.0, 0.0, 3.0)));
            assert!(e.multiple_scattering.simulated, "{e:?}");
            assert!(e.occlusion.simulated);
        }
    }

    #[test]
    fn two_scatterers_or_a_folded_mesh_exchange_light_a_plane_does_not() {
        let two = scene(json!({
            "materials": { "m": grey(0.5) },
            "shapes": [disk(0.0, Some("m")), disk(1.0, Some("m"))],
            "emitters": [point_light()]
        }));
        let one = scene(json!({
            "materials": { "m": grey(0.5) },
            "shapes": [disk(0.0, Some("m")), disk(1.0, None)],
            "emitters": [point_light()]
        }));
        let mesh = scene(json!({
            "materials": { "m": grey(0.5) },
            "shapes": [{ "geometry": { "type": "mesh", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], "indices": [[0, 1, 2], [0, 3, 1]] }, "material": "m" }],
            "emitters": [point_light()]
        }));
        let at = irradiance_at(Vec3::new(0.2, 0.2, 3.0));
        assert!(analyze(&two, &at).multiple_scattering.simulated);
        assert!(!analyze(&one, &at).multiple_scattering.simulated);
        assert!(analyze(&mesh, &at).multiple_scattering.simulated);
    }

    #[test]
    fn lobes_decide_specular_chains_and_transmission() {
        for (m, specular, transmits) in [
            (grey(0.5), false, false),
            (
                json!({ "type": "conductor", "eta": 0.2, "k": 3.9 }),
                true,
                false,
            ),
            (json!({ "type": "dielectric", "eta": 1.5 }), true, true),
        ] {
            let s = scene(json!({
                "materials": { "m": m },
                "shapes": [disk(0.0, Some("m"))],
                "emitters": [point_light()]
            }));
            let e = analyze(&s, &irradiance_at(Vec3::new(0.0, 0.0, 2.0)));
            assert_eq!(e.specular_chains.simulated, specular, "{m}");
            assert_eq!(e.transmission.simulated, transmits, "{m}");
        }
    }

    #[test]
    fn occlusion_needs_something_between() {
        let at = irradiance_at(Vec3::new(0.0, 0.0, 0.5));
        // No shapes at all.
        let empty = scene(json!({ "emitters": [point_light()] }));
        assert!(!analyze(&empty, &at).occlusion.simulated);
        // One emitting sphere, the only emitter: nothing else to cross.
        let lone =
            scene(json!({ "materials": { "m": grey(0.5) }, "shapes": [sphere(Some("m"), true)] }));
        assert!(!analyze(&lone, &at).occlusion.simulated);
        // ... but a second emitter makes its segments cross the sphere.
        let two_lights = scene(json!({
            "materials": { "m": grey(0.5) },
            "shapes": [sphere(Some("m"), true)],
            "emitters": [point_light()]
        }));
        assert!(analyze(&two_lights, &at).occlusion.simulated);
        // A second shape may block.
        let second = scene(json!({
            "materials": { "m": grey(0.5) },
            "shapes": [sphere(Some("m"), true), disk(0.2, None)]
        }));
        assert!(analyze(&second, &at).occlusion.simulated);
    }

    #[test]
    fn a_convex_reflector_lit_from_infinity_needs_no_shadow_rays_only_from_outside() {
        let s = scene(json!({
            "materials": { "m": grey(0.5) },
            "shapes": [sphere(Some("m"), false)],
            "emitters": [env()]
        }));
        let outside = Vec3::new(0.0, 0.0, -3.0);
        assert!(!analyze(&s, &radiance_at(outside)).occlusion.simulated);
        assert!(
            analyze(&s, &radiance_at(Vec3::new(0.0, 0.0, 0.5)))
                .occlusion
                .simulated
        );
        // Irradiance at an outside point integrates over directions the sphere can block.
        assert!(analyze(&s, &irradiance_at(outside)).occlusion.simulated);
        // A finite light can be hidden by the sphere's own far side.
        let lit = scene(json!({
            "materials": { "m": grey(0.5) },
            "shapes": [sphere(Some("m"), false)],
            "emitters": [point_light()]
        }));
        assert!(analyze(&lit, &radiance_at(outside)).occlusion.simulated);
        let mut moving = sphere(Some("m"), false);
        moving["velocity"] = json!([0, 1, 0]);
        let moving = scene(
            json!({ "materials": { "m": grey(0.5) }, "shapes": [moving], "emitters": [env()] }),
        );
        assert!(analyze(&moving, &radiance_at(outside)).occlusion.simulated);
    }

    #[test]
    fn object_properties_are_not_transport() {
        let one = scene(json!({ "shapes": [disk(0.0, None)] }));
        let two = scene(json!({ "shapes": [disk(0.0, None), disk(1.0, None)] }));
        let from = Vec3::new(0.0, 0.0, 3.0);
        for m in [
            Measure::SolidAngle { from, shape: 0 },
            Measure::ProjectedSolidAngle {
                from,
                normal: -Vec3::Z,
                shape: 0,
            },
        ] {
            let e = analyze(&one, &m);
            assert!(!e.occlusion.simulated && !e.direct_emission.simulated);
            assert_eq!(e.max_bounces, Some(0));
            assert!(analyze(&two, &m).occlusion.simulated, "{m:?}");
        }
        let e = analyze(&two, &Measure::Power { emitter: 0 });
        assert!(!e.occlusion.simulated && !e.single_scattering.simulated);
    }
}
