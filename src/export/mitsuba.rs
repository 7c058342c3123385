//! Mitsuba 3 scenes (XML, `version="3.0.0"`) and the Python driver `render_all.py`.
//!
//! What maps to what (each also recorded in `export.json`'s `conventions`):
//!
//! | lightproof | Mitsuba 3 |
//! |---|---|
//! | radiance along a ray | `radiancemeter` (1×1 film, box filter) |
//! | radiance in a closed furnace | `perspective` camera inside, 16×16, fov 60° |
//! | irradiance at a point | `irradiancemeter` on a `disk` of radius d/100 with a `null` BSDF (refused with point, spot or directional lights: its rays can never hit them) |
//! | flux onto shape i, view factor | `irradiancemeter` inside shape i (which keeps its material): the mean irradiance Φ/A, judged against the reference × 1/A (flux) or × π L₁ A₁/A (view factor); delta lights refused as above |
//! | albedo of a BSDF | the BSDF on a 2000-wide plane, `constant` sky 1, a `radiancemeter` from ωo |
//! | `max_depth` k (scatterings) | `path` `max_depth` k + 1 for radiance (Mitsuba counts the emitter seen directly), k for irradiance (the meter's ray is lightproof's first scattering); unbounded: −1 |
//! | `lambertian` ρ | `twosided` `diffuse` reflectance ρ |
//! | `conductor` η, k | `twosided` `conductor` eta, k |
//! | `dielectric` η | `dielectric` int_ior η, ext_ior 1 (radiance scaled by 1/η² on refraction in both) |
//! | `rough_conductor` α (`masking: uncorrelated`) | `twosided` `roughconductor` alpha α (Mitsuba's α is lightproof's α, not a roughness to remap), `distribution`, `material` `none` for F ≡ 1 |
//! | `rough_dielectric` α (`uncorrelated`) | `roughdielectric` alpha α |
//! | `plastic` ρ, η | `twosided` `plastic` diffuse_reflectance ρ, int_ior η, nonlinear true (Mitsuba's base term ρ/(1 − ρ F_dr,int) is lightproof's; `nonlinear` false divides by 1 − F_dr,int instead, 64% too bright at ρ = 0.5, η = 1.5) |
//! | no material | `diffuse` reflectance 0 (a black absorber) |
//! | one-sided `emission` L | `area` emitter radiance L (front side) |
//! | sphere / disk | `sphere` / `disk` (to_world matrix); `flip_normals` kept |
//! | rectangle / triangle / mesh | `ply` (ASCII, `face_normals` true) |
//! | point / spot / directional / constant | `point` / `spot` (cutoff = cone angle, beam width = falloff start) / `directional` / `constant` |
//!
//! Refused: Oren–Nayar (Mitsuba 3 has none), height-correlated masking (Mitsuba's
//! microfacet G is G1·G1), two-sided emission (Mitsuba's area emitter is one-sided),
//! spherical caps and annuli (no such shapes), environment maps (lat-long orientation
//! not yet mapped). Colours are RGB triples of equal values (grey cases); the judge
//! averages R, G and B.

use super::{
    Manifest, Probe, Refusal, Target, Written, albedo_eye, frame, mesh_file, num, probe_scene,
    render_size,
};
use crate::bsdf::{Bsdf, Distribution, FresnelMode, Masking};
use crate::case::CaseDesc;
use crate::scene::load::{EmitterDesc, GeometryDesc};
use glam::DVec3;
use std::fmt::Write;

/// The driver written beside a Mitsuba suite.
pub const DRIVER: &str = include_str!("render_all.py");

fn rgb(name: &str, v: f64) -> String {
    let v = num(v);
    format!(r#"<rgb name="{name}" value="{v}, {v}, {v}"/>"#)
}

/// A `point` or `vector` element.
fn xyz(tag: &str, name: &str, p: DVec3) -> String {
    format!(
        r#"<{tag} name="{name}" x="{}" y="{}" z="{}"/>"#,
        num(p.x),
        num(p.y),
        num(p.z)
    )
}

fn point(name: &str, p: DVec3) -> String {
    xyz("point", name, p)
}

fn vector(name: &str, p: DVec3) -> String {
    xyz("vector", name, p)
}

/// A `to_world` matrix taking the unit disk (normal +z) to centre `c`, normal `n`,
/// radius `r` (row-major, as Mitsuba's `<matrix>` reads it).
fn disk_to_world(c: DVec3, n: DVec3, r: f64) -> String {
    let (t, b) = frame(n);
    let cols = [t * r, b * r, n * r, c];
    let mut m = Vec::with_capacity(16);
    for row in 0..3 {
        for col in cols {
            m.push(num(col[row]));
        }
    }
    m.extend(["0", "0", "0", "1"].map(String::from));
    format!(
        r#"<transform name="to_world"><matrix value="{}"/></transform>"#,
        m.join(" ")
    )
}

fn lookat(at: DVec3, dir: DVec3) -> String {
    let up = frame(dir).0;
    let target = at + dir;
    let f = |p: DVec3| format!("{}, {}, {}", num(p.x), num(p.y), num(p.z));
    format!(
        r#"<transform name="to_world"><lookat origin="{}" target="{}" up="{}"/></transform>"#,
        f(at),
        f(target),
        f(up)
    )
}

fn film(w: usize, h: usize) -> String {
    format!(
        r#"<film type="hdrfilm"><integer name="width" value="{w}"/><integer name="height" value="{h}"/><string name="pixel_format" value="rgb"/><rfilter type="box"/></film><sampler type="independent"><integer name="sample_count" value="64"/></sampler>"#
    )
}

/// A BSDF element (with `id` when given).
fn bsdf(b: &Bsdf, id: &str) -> Result<String, Refusal> {
    let micro = |d: Distribution, m: Masking, what: &str| -> Result<&'static str, Refusal> {
        match m {
            Masking::Uncorrelated => {}
            Masking::HeightCorrelated => {
                return Err(Refusal(format!(
                    "{what} with height-correlated masking: Mitsuba 3's microfacet G is the uncorrelated G1(ωi)·G1(ωo)"
                )));
            }
        }
        Ok(match d {
            Distribution::Ggx => "ggx",
            Distribution::Beckmann => "beckmann",
        })
    };
    let two = |inner: String| format!(r#"<bsdf type="twosided" id="{id}">{inner}</bsdf>"#);
    Ok(match b {
        Bsdf::Lambertian(l) => two(format!(
            r#"<bsdf type="diffuse">{}</bsdf>"#,
            rgb("reflectance", l.albedo as f64)
        )),
        Bsdf::OrenNayar(_) | Bsdf::OrenNayarClassic(_) => {
            return Err(Refusal(format!(
                "{}: Mitsuba 3 has no Oren–Nayar BSDF",
                b.name()
            )));
        }
        Bsdf::Conductor(c) => two(format!(
            r#"<bsdf type="conductor">{}{}</bsdf>"#,
            rgb("eta", c.eta as f64),
            rgb("k", c.k as f64)
        )),
        Bsdf::Dielectric(d) => format!(
            r#"<bsdf type="dielectric" id="{id}"><float name="int_ior" value="{}"/><float name="ext_ior" value="1"/></bsdf>"#,
            num(d.eta as f64)
        ),
        Bsdf::RoughConductor(r) => {
            let dist = micro(r.distribution, r.masking, "rough_conductor")?;
            let fresnel = match r.fresnel {
                FresnelMode::None => r#"<string name="material" value="none"/>"#.to_string(),
                FresnelMode::Conductor => format!(
                    "{}{}",
                    rgb("eta", r.eta.unwrap_or(1.0) as f64),
                    rgb("k", r.k.unwrap_or(0.0) as f64)
                ),
            };
            two(format!(
                r#"<bsdf type="roughconductor"><string name="distribution" value="{dist}"/><float name="alpha" value="{}"/>{fresnel}</bsdf>"#,
                num(r.alpha as f64)
            ))
        }
        Bsdf::RoughDielectric(r) => {
            let dist = micro(r.distribution, r.masking, "rough_dielectric")?;
            format!(
                r#"<bsdf type="roughdielectric" id="{id}"><string name="distribution" value="{dist}"/><float name="alpha" value="{}"/><float name="int_ior" value="{}"/><float name="ext_ior" value="1"/></bsdf>"#,
                num(r.alpha as f64),
                num(r.eta as f64)
            )
        }
        Bsdf::Plastic(p) => two(format!(
            r#"<bsdf type="plastic">{}<float name="int_ior" value="{}"/><float name="ext_ior" value="1"/><boolean name="nonlinear" value="true"/></bsdf>"#,
            rgb("diffuse_reflectance", p.albedo as f64),
            num(p.eta as f64)
        )),
    })
}

/// Refuse delta lights for an `irradiancemeter`: its rays leave the receiver and can
/// never hit a point or a direction.
fn no_delta_lights(emitters: &[EmitterDesc]) -> Result<(), Refusal> {
    for (i, e) in emitters.iter().enumerate() {
        match e {
            EmitterDesc::Point { .. }
            | EmitterDesc::Spot { .. }
            | EmitterDesc::Directional { .. } => {
                return Err(Refusal(format!(
                    "scene.emitters[{i}]: a delta light, which Mitsuba's irradiancemeter cannot see (its rays leave the receiver and can never hit a point or direction)"
                )));
            }
            EmitterDesc::Constant { .. } | EmitterDesc::Envmap { .. } => {}
        }
    }
    Ok(())
}

/// The Mitsuba scene of a case measured by `probe`.
pub fn write(desc: &CaseDesc, probe: &Probe) -> Result<Written, Refusal> {
    let scene = probe_scene(desc, probe);
    let mut files = Vec::new();
    let mut x = String::from("<scene version=\"3.0.0\">\n");
    let depth = match (probe.scatterings(desc.max_depth), probe) {
        (None, _) => -1i64,
        (Some(k), Probe::Irradiance { .. } | Probe::Flux { .. }) => k as i64,
        (Some(k), Probe::Ray { .. } | Probe::Isotropic { .. } | Probe::Albedo { .. }) => {
            k as i64 + 1
        }
    };
    let _ = writeln!(
        x,
        r#"  <integrator type="path"><integer name="max_depth" value="{depth}"/></integrator>"#
    );
    let (w, h) = render_size(probe);
    match probe {
        Probe::Ray { at, direction } => {
            let _ = writeln!(
                x,
                r#"  <sensor type="radiancemeter">{}{}{}</sensor>"#,
                point("origin", *at),
                vector("direction", *direction),
                film(w, h)
            );
        }
        Probe::Albedo { wo, .. } => {
            let (at, direction) = albedo_eye(*wo);
            let _ = writeln!(
                x,
                r#"  <sensor type="radiancemeter">{}{}{}</sensor>"#,
                point("origin", at),
                vector("direction", direction),
                film(w, h)
            );
        }
        Probe::Isotropic { at, direction } => {
            let near = (super::clearance(&scene, *at) / 10.0).min(0.01);
            let _ = writeln!(
                x,
                r#"  <sensor type="perspective"><float name="fov" value="60"/><float name="near_clip" value="{}"/>{}{}</sensor>"#,
                num(near),
                lookat(*at, *direction),
                film(w, h)
            );
        }
        Probe::Irradiance { at, normal, radius } => {
            no_delta_lights(&scene.emitters)?;
            let _ = writeln!(
                x,
                r#"  <shape type="disk">{}<bsdf type="null"/><sensor type="irradiancemeter">{}</sensor></shape>"#,
                disk_to_world(*at, *normal, *radius),
                film(w, h)
            );
        }
        // The meter goes inside the receiver's own shape element, below.
        Probe::Flux { .. } => no_delta_lights(&scene.emitters)?,
    }
    let ids: Vec<&String> = scene.materials.keys().collect();
    for (i, (_, b)) in scene.materials.iter().enumerate() {
        let _ = writeln!(x, "  {}", bsdf(b, &format!("mat{i}"))?);
    }
    for (i, s) in scene.shapes.iter().enumerate() {
        let field = format!("scene.shapes[{i}]");
        let mut inner = match &s.material {
            Some(m) => match ids.iter().position(|k| *k == m) {
                Some(j) => format!(r#"<ref id="mat{j}"/>"#),
                None => return Err(Refusal(format!("{field}.material: `{m}` is not defined"))),
            },
            None => format!(r#"<bsdf type="diffuse">{}</bsdf>"#, rgb("reflectance", 0.0)),
        };
        if let Some(e) = &s.emission {
            if e.two_sided {
                return Err(Refusal(format!(
                    "{field}.emission: two-sided emission (Mitsuba 3's area emitter emits on the front side only)"
                )));
            }
            let _ = write!(
                inner,
                r#"<emitter type="area">{}</emitter>"#,
                rgb("radiance", e.radiance)
            );
        }
        match probe {
            Probe::Flux { shape, .. } if *shape == i => {
                let _ = write!(
                    inner,
                    r#"<sensor type="irradiancemeter">{}</sensor>"#,
                    film(w, h)
                );
            }
            Probe::Flux { .. }
            | Probe::Ray { .. }
            | Probe::Isotropic { .. }
            | Probe::Irradiance { .. }
            | Probe::Albedo { .. } => {}
        }
        let flip = format!(
            r#"<boolean name="flip_normals" value="{}"/>"#,
            s.flip_normals
        );
        let v = DVec3::from_array;
        let shape = match &s.geometry {
            GeometryDesc::Sphere {
                center,
                radius,
                theta_max,
                ..
            } => {
                if theta_max.is_some_and(|t| t < 180.0) {
                    return Err(Refusal(format!(
                        "{field}: a spherical cap (Mitsuba 3's sphere is whole)"
                    )));
                }
                format!(
                    r#"<shape type="sphere">{}<float name="radius" value="{}"/>{flip}{inner}</shape>"#,
                    point("center", v(*center)),
                    num(*radius)
                )
            }
            GeometryDesc::Disk {
                center,
                normal,
                radius,
                inner_radius,
            } => {
                if inner_radius.is_some_and(|r| r > 0.0) {
                    return Err(Refusal(format!(
                        "{field}: an annulus (Mitsuba 3's disk has no hole)"
                    )));
                }
                format!(
                    r#"<shape type="disk">{}{flip}{inner}</shape>"#,
                    disk_to_world(v(*center), v(*normal).normalize(), *radius)
                )
            }
            GeometryDesc::Rectangle { .. }
            | GeometryDesc::Triangle { .. }
            | GeometryDesc::Mesh { .. } => {
                let name = mesh_file(i, &s.geometry, &mut files)?;
                format!(
                    r#"<shape type="ply"><string name="filename" value="{name}"/><boolean name="face_normals" value="true"/>{flip}{inner}</shape>"#
                )
            }
            GeometryDesc::Obj { .. } => {
                return Err(Refusal(format!(
                    "{field}: OBJ geometry is not exported yet"
                )));
            }
        };
        let _ = writeln!(x, "  {shape}");
    }
    for (i, e) in scene.emitters.iter().enumerate() {
        let v = DVec3::from_array;
        let el = match e {
            EmitterDesc::Point {
                position,
                intensity,
                ..
            } => format!(
                r#"<emitter type="point">{}{}</emitter>"#,
                point("position", v(*position)),
                rgb("intensity", *intensity)
            ),
            EmitterDesc::Spot {
                position,
                direction,
                intensity,
                cone_angle,
                falloff_start,
                ..
            } => format!(
                r#"<emitter type="spot">{}{}<float name="cutoff_angle" value="{}"/><float name="beam_width" value="{}"/></emitter>"#,
                lookat(v(*position), v(*direction).normalize()),
                rgb("intensity", *intensity),
                num(*cone_angle),
                num(*falloff_start)
            ),
            EmitterDesc::Directional {
                direction,
                irradiance,
                ..
            } => format!(
                r#"<emitter type="directional">{}{}</emitter>"#,
                vector("direction", v(*direction).normalize()),
                rgb("irradiance", *irradiance)
            ),
            EmitterDesc::Constant { radiance, .. } => format!(
                r#"<emitter type="constant">{}</emitter>"#,
                rgb("radiance", *radiance)
            ),
            EmitterDesc::Envmap { .. } => {
                return Err(Refusal(format!(
                    "scene.emitters[{i}]: environment maps are not exported yet (lat-long orientation conventions differ)"
                )));
            }
        };
        let _ = writeln!(x, "  {el}");
    }
    x.push_str("</scene>\n");
    files.push(("scene.xml".into(), x.into_bytes()));
    let mut conventions = vec![
        "RGB triples of equal values; the judge averages R, G, B".to_string(),
        format!(
            "path max_depth {depth} (lightproof max_depth {:?} scatterings)",
            probe.scatterings(desc.max_depth)
        ),
    ];
    conventions.push(match probe {
        Probe::Ray { .. } => "radiancemeter along the measured ray".into(),
        Probe::Isotropic { .. } => {
            "perspective camera inside a closed furnace: every pixel sees the reference".into()
        }
        Probe::Irradiance { radius, .. } => format!(
            "irradiancemeter on a null-BSDF disk of radius {radius:e} (1/100 of the clearance)"
        ),
        Probe::Albedo { .. } => {
            "BSDF on a plane under a constant sky of radiance 1, radiancemeter from ωo".into()
        }
        Probe::Flux { shape, area, scale } => format!(
            "irradiancemeter on scene.shapes[{shape}] (its material kept): the mean irradiance over its area {area:e}, expected reference × {scale:e}"
        ),
    });
    Ok(Written {
        files,
        manifest: Manifest {
            renderer: Target::Mitsuba,
            source: String::new(),
            name: desc.name.clone(),
            case: "case.json".into(),
            scene: "scene.xml".into(),
            sensor: probe.sensor().into(),
            width: w,
            height: h,
            scale: probe.scale(),
            conventions,
        },
    })
}

#[cfg(test)]
mod tests {
    //! The mapping table above, row by row: each case is exported and the scene's XML
    //! checked for the element the row names (or the refusal's reason).
    use crate::export::Target;
    use crate::export::mapping::{DISK_LIGHT, has, refused};

    fn export(
        materials: &str,
        shapes: &str,
        emitters: &str,
        extra: &str,
    ) -> Result<String, String> {
        crate::export::mapping::export(Target::Mitsuba, materials, shapes, emitters, extra)
    }

    fn measured(json: &str) -> Result<String, String> {
        crate::export::mapping::measured(Target::Mitsuba, json)
    }

    fn with_material(bsdf: &str) -> Result<String, String> {
        crate::export::mapping::with_material(Target::Mitsuba, bsdf)
    }

    #[test]
    fn max_depth_counts_the_emitter_seen_directly_for_radiance_only() {
        let radiance = |extra: &str| export("", DISK_LIGHT, "", extra);
        has(
            &radiance(r#","max_depth":4"#),
            &[r#"<integer name="max_depth" value="5"/>"#],
        );
        has(
            &radiance(r#","max_depth":0"#),
            &[r#"<integer name="max_depth" value="1"/>"#],
        );
        has(
            &radiance(""),
            &[r#"<integer name="max_depth" value="-1"/>"#],
        );
        let irradiance = |extra: &str| {
            measured(&format!(
                r#"{{"name":"n","teaches":"t","scene":{{"shapes":[{DISK_LIGHT}]}},
                  "measure":{{"irradiance":{{"at":[0,0,0],"normal":[0,0,1]}}}},
                  "estimators":["mis"]{extra}}}"#
            ))
        };
        has(
            &irradiance(r#","max_depth":2"#),
            &[
                r#"<integer name="max_depth" value="2"/>"#,
                r#"<sensor type="irradiancemeter">"#,
                r#"<bsdf type="null"/>"#,
            ],
        );
        has(
            &irradiance(""),
            &[r#"<integer name="max_depth" value="-1"/>"#],
        );
    }

    #[test]
    fn bsdfs_map_to_their_mitsuba_plugins() {
        // Radiance along a ray: a radiancemeter at the point, along the direction, 1×1.
        has(
            &export("", DISK_LIGHT, "", ""),
            &[
                r#"<sensor type="radiancemeter"><point name="origin" x="0" y="0" z="0"/><vector name="direction" x="0" y="0" z="1"/>"#,
                r#"<integer name="width" value="1"/><integer name="height" value="1"/>"#,
            ],
        );
        has(
            &with_material(r#"{"type":"lambertian","albedo":0.5}"#),
            &[
                r#"<bsdf type="twosided" id="mat0"><bsdf type="diffuse"><rgb name="reflectance" value="0.5, 0.5, 0.5"/></bsdf></bsdf>"#,
                r#"<ref id="mat0"/>"#,
            ],
        );
        has(
            &with_material(r#"{"type":"conductor","eta":0.25,"k":3.5}"#),
            &[
                r#"<bsdf type="twosided" id="mat0"><bsdf type="conductor"><rgb name="eta" value="0.25, 0.25, 0.25"/><rgb name="k" value="3.5, 3.5, 3.5"/>"#,
            ],
        );
        has(
            &with_material(r#"{"type":"dielectric","eta":1.5}"#),
            &[
                r#"<bsdf type="dielectric" id="mat0"><float name="int_ior" value="1.5"/><float name="ext_ior" value="1"/></bsdf>"#,
            ],
        );
        // α itself (no roughness remapping); F ≡ 1 as `material none`.
        has(
            &with_material(
                r#"{"type":"rough_conductor","alpha":0.375,"fresnel":"none","distribution":"beckmann","masking":"uncorrelated"}"#,
            ),
            &[
                r#"<bsdf type="twosided" id="mat0"><bsdf type="roughconductor"><string name="distribution" value="beckmann"/><float name="alpha" value="0.375"/><string name="material" value="none"/>"#,
            ],
        );
        has(
            &with_material(
                r#"{"type":"rough_dielectric","alpha":0.5,"eta":1.25,"masking":"uncorrelated"}"#,
            ),
            &[
                r#"<bsdf type="roughdielectric" id="mat0"><string name="distribution" value="ggx"/><float name="alpha" value="0.5"/><float name="int_ior" value="1.25"/><float name="ext_ior" value="1"/>"#,
            ],
        );
        has(
            &with_material(r#"{"type":"plastic","albedo":0.25,"eta":1.5}"#),
            &[
                r#"<bsdf type="twosided" id="mat0"><bsdf type="plastic"><rgb name="diffuse_reflectance" value="0.25, 0.25, 0.25"/><float name="int_ior" value="1.5"/><float name="ext_ior" value="1"/><boolean name="nonlinear" value="true"/>"#,
            ],
        );
        refused(
            &with_material(r#"{"type":"oren_nayar","albedo":0.5,"sigma":20}"#),
            "no Oren–Nayar",
        );
        refused(
            &with_material(
                r#"{"type":"rough_conductor","alpha":0.3,"fresnel":"none","masking":"height_correlated"}"#,
            ),
            "height-correlated masking",
        );
        // No material: a black diffuse absorber.
        has(
            &export(
                "",
                &format!(
                    r#"{DISK_LIGHT},{{"geometry":{{"type":"sphere","center":[0,5,0],"radius":1}}}}"#
                ),
                "",
                "",
            ),
            &[r#"<bsdf type="diffuse"><rgb name="reflectance" value="0, 0, 0"/></bsdf>"#],
        );
    }

    /// Mitsuba 3's `plastic` (src/bsdfs/plastic.cpp, `eval`): the base term is
    /// ρ/(1 − ρ F_dr,int) with `nonlinear` true, ρ/(1 − F_dr,int) with it false, times
    /// (1 − F(θi))(1 − F(θo))/(π η²). lightproof's [`crate::bsdf::Plastic`] sums the
    /// internal inter-reflection as ρ/(1 − ρ F_dr,int): the exported flag must select
    /// that form. With `nonlinear` false, ρ = 0.5, η = 1.5 rendered 0.5213 for the
    /// albedo 0.3172 at θo = 30° (Mitsuba 3.9.1 scalar_rgb, 8 × 65 536 paths; true:
    /// 0.31734 ± 0.00011).
    #[test]
    fn plastic_is_mitsubas_model_with_the_same_internal_scattering() {
        use crate::bsdf::fresnel::{fr_dielectric, fresnel_diffuse_reflectance};
        use crate::bsdf::{BsdfModel, Plastic};
        use glam::Vec3;
        for (rho, eta) in [(0.25f32, 1.5f32), (0.5, 1.5), (0.9, 1.33), (1.0, 2.0)] {
            let xml = with_material(&format!(
                r#"{{"type":"plastic","albedo":{rho},"eta":{eta}}}"#
            ))
            .unwrap();
            let nonlinear = match (
                xml.contains(r#"<boolean name="nonlinear" value="true"/>"#),
                xml.contains(r#"<boolean name="nonlinear" value="false"/>"#),
            ) {
                (true, false) => true,
                (false, true) => false,
                _ => panic!("no single `nonlinear` flag in\n{xml}"),
            };
            let fdr = fresnel_diffuse_reflectance(1.0 / eta as f64);
            let r = rho as f64;
            let base = r / (1.0 - if nonlinear { r * fdr } else { fdr });
            let plastic = Plastic::new(rho, eta);
            let wo = Vec3::new(0.5, 0.0, 0.75f32.sqrt());
            for wi in [
                Vec3::Z,
                Vec3::new(0.0, 0.8, 0.6),
                Vec3::new(-0.96, 0.0, 0.28),
            ] {
                let (fi, fo) = (fr_dielectric(wi.z, eta), fr_dielectric(wo.z, eta));
                let mitsuba = base * (1.0 - fi as f64) * (1.0 - fo as f64)
                    / (std::f64::consts::PI * (eta as f64).powi(2));
                let ours = plastic.eval(wo, wi) as f64;
                assert!(
                    (mitsuba - ours).abs() <= 1e-5 * ours,
                    "ρ = {rho}, η = {eta}, ωi = {wi}: Mitsuba's plastic (nonlinear {nonlinear}) is {mitsuba}, lightproof's {ours}"
                );
            }
        }
    }

    #[test]
    fn shapes_and_emission_map_or_are_refused() {
        let shape = |geometry: &str, rest: &str| {
            export(
                "",
                &format!(r#"{DISK_LIGHT},{{"geometry":{geometry}{rest}}}"#),
                "",
                "",
            )
        };
        has(
            &shape(
                r#"{"type":"sphere","center":[0,5,0],"radius":2}"#,
                r#","flip_normals":true"#,
            ),
            &[
                r#"<shape type="sphere"><point name="center" x="0" y="5" z="0"/><float name="radius" value="2"/><boolean name="flip_normals" value="true"/>"#,
            ],
        );
        refused(
            &shape(
                r#"{"type":"sphere","center":[0,5,0],"radius":2,"theta_max":90}"#,
                "",
            ),
            "spherical cap",
        );
        refused(
            &shape(
                r#"{"type":"disk","center":[0,5,0],"normal":[0,0,1],"radius":2,"inner_radius":1}"#,
                "",
            ),
            "annulus",
        );
        has(
            &shape(
                r#"{"type":"rectangle","corner":[0,5,0],"edge_u":[1,0,0],"edge_v":[0,1,0]}"#,
                "",
            ),
            &[
                r#"<shape type="ply"><string name="filename" value="#,
                r#"<boolean name="face_normals" value="true"/><boolean name="flip_normals" value="false"/>"#,
            ],
        );
        // The disk light itself: a one-sided area emitter.
        has(
            &shape(r#"{"type":"sphere","center":[0,5,0],"radius":2}"#, ""),
            &[
                r#"<shape type="disk">"#,
                r#"<emitter type="area"><rgb name="radiance" value="2, 2, 2"/></emitter>"#,
            ],
        );
        refused(
            &export(
                "",
                r#"{"geometry":{"type":"disk","center":[0,0,3],"normal":[0,0,-1],"radius":1},"emission":{"radiance":2,"two_sided":true}}"#,
                "",
                "",
            ),
            "two-sided emission",
        );
    }

    #[test]
    fn lights_map_or_are_refused() {
        let light = |e: &str| export("", "", e, "");
        has(
            &light(r#"{"type":"point","position":[0,0,2],"intensity":3}"#),
            &[
                r#"<emitter type="point"><point name="position" x="0" y="0" z="2"/><rgb name="intensity" value="3, 3, 3"/></emitter>"#,
            ],
        );
        has(
            &light(
                r#"{"type":"spot","position":[0,0,2],"direction":[0,0,-1],"intensity":5,"cone_angle":30,"falloff_start":20}"#,
            ),
            &[
                r#"<emitter type="spot">"#,
                r#"<float name="cutoff_angle" value="30"/><float name="beam_width" value="20"/>"#,
            ],
        );
        has(
            &light(r#"{"type":"directional","direction":[0,0,-2],"irradiance":4}"#),
            &[
                r#"<emitter type="directional"><vector name="direction" x="0" y="0" z="-1"/><rgb name="irradiance" value="4, 4, 4"/></emitter>"#,
            ],
        );
        has(
            &light(r#"{"type":"constant","radiance":1.25}"#),
            &[
                r#"<emitter type="constant"><rgb name="radiance" value="1.25, 1.25, 1.25"/></emitter>"#,
            ],
        );
        // An irradiance meter cannot see a delta light.
        refused(
            &measured(
                r#"{"name":"n","teaches":"t","scene":{"emitters":[{"type":"point","position":[0,0,2],"intensity":3}]},
                  "measure":{"irradiance":{"at":[0,0,0],"normal":[0,0,1]}},"estimators":["light"]}"#,
            ),
            "a delta light",
        );
        // Nor can a flux meter (the receiver's irradiancemeter).
        refused(
            &measured(
                r#"{"name":"n","teaches":"t","scene":{"emitters":[{"type":"point","position":[0.5,0.5,2],"intensity":3}],
                  "shapes":[{"geometry":{"type":"rectangle","corner":[0,0,0],"edge_u":[1,0,0],"edge_v":[0,1,0]}}]},
                  "measure":{"flux":{"shape":0}},"estimators":["light"]}"#,
            ),
            "a delta light",
        );
    }
}
