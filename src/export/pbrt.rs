//! pbrt-v4 scenes (`scene.pbrt`) and the shell driver `render_all.sh`, checked against a
//! pbrt-v4 build (commit 5f7a6068; reports/pbrt/README.md).
//!
//! | lightproof | pbrt-v4 |
//! |---|---|
//! | radiance along a ray | `perspective` camera at the point, fov 10⁻³°, 1×1 film, `box` filter (rays within 1.2·10⁻⁵ rad of the ray: √2·tan 5·10⁻⁴°, the pixel's corners) |
//! | radiance in a closed furnace | `perspective` camera inside, 16×16, fov 60° |
//! | irradiance | refused: pbrt-v4 has no irradiance sensor |
//! | albedo of a BSDF | the BSDF on a plane, `infinite` light L = 1, a camera from ωo |
//! | `max_depth` k | `path` `maxdepth` k (the same count: 1 is direct lighting); unbounded: 65536 |
//! | `lambertian` ρ | `diffuse` reflectance ρ (pbrt's BSDFs are two-sided) |
//! | `conductor` η, k | `conductor` constant spectra eta, k, roughness 0 |
//! | `dielectric` η | `dielectric` eta η, roughness 0 |
//! | `rough_conductor` / `rough_dielectric` α, GGX, height-correlated | roughness α with `remaproughness` false (pbrt's Trowbridge–Reitz G is 1/(1 + Λ(ωo) + Λ(ωi))); F ≡ 1 as η = 1, k = 10⁶ |
//! | one- or two-sided `emission` L | `AreaLightSource "diffuse"` rgb L, `twosided` |
//! | sphere (cap) / disk (annulus) | `sphere` (zmin = r cos θmax about `axis`) / `disk` (innerradius) |
//! | rectangle / triangle / mesh | `plymesh` (ASCII PLY) |
//! | `flip_normals` | `ReverseOrientation` |
//! | point / spot / directional / constant | `point` / `spot` (`conedeltaangle` = cone − falloff start, pbrt's smoothstep, as lightproof's) / `distant` / `infinite` |
//!
//! RGB: pbrt-v4 turns an RGB light into the colour space's illuminant spectrum scaled to
//! 1 nit per unit, and its `rgb` film maps that back, so a grey (L, L, L) renders as L
//! (0.69995 ± 0.00020 for 0.7 under a sky, 17 renders); the film writes full floats
//! (`savefp16` false: pbrt's default is half floats). Refused: irradiance,
//! Beckmann and uncorrelated masking (pbrt-v4 has Trowbridge–Reitz, height-correlated,
//! only), α < 10⁻³ (pbrt-v4 renders that as a perfect mirror or smooth glass:
//! `EffectivelySmooth`), Oren–Nayar and `plastic` (pbrt-v4's `coateddiffuse` is a
//! stochastic layered model, not the closed form), environment maps.

use super::{
    Manifest, Probe, Refusal, Target, Written, albedo_eye, frame, mesh_file, num, probe_scene,
    render_size,
};
use crate::bsdf::{Bsdf, Distribution, FresnelMode, Masking};
use crate::case::CaseDesc;
use crate::scene::load::{EmitterDesc, GeometryDesc};
use glam::DVec3;
use std::fmt::Write;

/// The driver written beside a pbrt suite.
pub const DRIVER: &str = include_str!("render_all_pbrt.sh");

/// The extinction coefficient k of a conductor with η = 1 that stands for F ≡ 1, which
/// pbrt-v4's conductor has no mode for. With η̃ = 1 + ik the Fresnel equations (Born &
/// Wolf §14.2) give 1 − |r_s|² = 4 cos θ/((1 + cos θ)² + k²) + O(k⁻³) and
/// 1 − |r_p|² ≈ 4/(k² cos θ) for k cos θ ≫ 1, so 1 − F ≤ 4/(k² cos θ) = 4·10⁻¹²/cos θ:
/// below f32 resolution wherever cos θ > 10⁻⁴.
const WHITE_CONDUCTOR_K: f64 = 1e6;

/// pbrt-v4 renders a Trowbridge–Reitz surface with α below this as a perfect mirror or
/// smooth glass (`TrowbridgeReitzDistribution::EffectivelySmooth`: max(αx, αy) < 10⁻³
/// in f32, `util/scattering.h`), not the rough closed form, which differs at grazing
/// angles (the masking of a rough surface: Λ grows with α tan θ).
const PBRT_SMOOTH_ALPHA: f32 = 1e-3;

/// "unbounded" depth for pbrt's integer `maxdepth`.
const UNBOUNDED_DEPTH: u32 = 65536;

fn v3(p: DVec3) -> String {
    format!("{} {} {}", num(p.x), num(p.y), num(p.z))
}

fn grey(x: f64) -> String {
    let v = num(x);
    format!("[ {v} {v} {v} ]")
}

/// A constant spectrum over the visible range and beyond.
fn constant_spectrum(x: f64) -> String {
    format!("[ 300 {0} 900 {0} ]", num(x))
}

/// `ConcatTransform` taking the local frame (z along `n`) to `c` (pbrt reads the 16
/// numbers column by column).
fn frame_transform(c: DVec3, n: DVec3) -> String {
    let (t, b) = frame(n);
    format!(
        "ConcatTransform [ {} 0 {} 0 {} 0 {} 1 ]",
        v3(t),
        v3(b),
        v3(n),
        v3(c)
    )
}

fn material(b: &Bsdf) -> Result<String, Refusal> {
    let micro = |d: Distribution, m: Masking, what: &str| -> Result<(), Refusal> {
        let why = match (d, m) {
            (Distribution::Ggx, Masking::HeightCorrelated) => return Ok(()),
            (Distribution::Beckmann, Masking::HeightCorrelated | Masking::Uncorrelated) => {
                "Beckmann (pbrt-v4 has Trowbridge–Reitz only)"
            }
            (Distribution::Ggx, Masking::Uncorrelated) => {
                "uncorrelated masking (pbrt-v4's G is height-correlated)"
            }
        };
        Err(Refusal(format!("{what}: {why}")))
    };
    let rough = |alpha: f32, what: &str| -> Result<(), Refusal> {
        if alpha < PBRT_SMOOTH_ALPHA {
            return Err(Refusal(format!(
                "{what}: α = {alpha} < 10⁻³, which pbrt-v4 renders as a perfect mirror or smooth glass (EffectivelySmooth), not this rough BSDF"
            )));
        }
        Ok(())
    };
    Ok(match b {
        Bsdf::Lambertian(l) => format!(
            r#"Material "diffuse" "rgb reflectance" {}"#,
            grey(l.albedo as f64)
        ),
        Bsdf::OrenNayar(_) | Bsdf::OrenNayarClassic(_) => {
            return Err(Refusal(format!(
                "{}: pbrt-v4 has no Oren–Nayar BSDF",
                b.name()
            )));
        }
        Bsdf::Conductor(c) => format!(
            r#"Material "conductor" "spectrum eta" {} "spectrum k" {} "float roughness" [ 0 ]"#,
            constant_spectrum(c.eta as f64),
            constant_spectrum(c.k as f64)
        ),
        Bsdf::Dielectric(d) => format!(
            r#"Material "dielectric" "float eta" [ {} ] "float roughness" [ 0 ]"#,
            num(d.eta as f64)
        ),
        Bsdf::RoughConductor(r) => {
            micro(r.distribution, r.masking, "rough_conductor")?;
            rough(r.alpha, "rough_conductor")?;
            let (eta, k) = match r.fresnel {
                FresnelMode::None => (1.0, WHITE_CONDUCTOR_K),
                FresnelMode::Conductor => (r.eta.unwrap_or(1.0) as f64, r.k.unwrap_or(0.0) as f64),
            };
            format!(
                r#"Material "conductor" "spectrum eta" {} "spectrum k" {} "float roughness" [ {} ] "bool remaproughness" false"#,
                constant_spectrum(eta),
                constant_spectrum(k),
                num(r.alpha as f64)
            )
        }
        Bsdf::RoughDielectric(r) => {
            micro(r.distribution, r.masking, "rough_dielectric")?;
            rough(r.alpha, "rough_dielectric")?;
            format!(
                r#"Material "dielectric" "float eta" [ {} ] "float roughness" [ {} ] "bool remaproughness" false"#,
                num(r.eta as f64),
                num(r.alpha as f64)
            )
        }
        Bsdf::Plastic(_) => {
            return Err(Refusal(
                "plastic: pbrt-v4's coateddiffuse is a stochastic layered model, not this closed form".into(),
            ));
        }
    })
}

/// The pbrt-v4 scene of a case measured by `probe`.
pub fn write(desc: &CaseDesc, probe: &Probe) -> Result<Written, Refusal> {
    let scene = probe_scene(desc, probe);
    let (w, h) = render_size(probe);
    let (at, dir, fov) = match probe {
        Probe::Ray { at, direction } => (*at, *direction, 1e-3),
        Probe::Isotropic { at, direction } => (*at, *direction, 60.0),
        Probe::Albedo { wo, .. } => {
            let (a, d) = albedo_eye(*wo);
            (a, d, 1e-3)
        }
        Probe::Irradiance { .. } => {
            return Err(Refusal(
                "irradiance: pbrt-v4 has no irradiance sensor".into(),
            ));
        }
        Probe::Flux { .. } => {
            return Err(Refusal(
                "flux: pbrt-v4 has no sensor on a shape (no irradiance meter; its cameras measure radiance along rays)".into(),
            ));
        }
    };
    let depth = probe.scatterings(desc.max_depth).unwrap_or(UNBOUNDED_DEPTH);
    let mut files = Vec::new();
    let mut x = format!("# {} (lightproof export to pbrt-v4)\n", desc.name);
    let _ = writeln!(x, "LookAt {} {} {}", v3(at), v3(at + dir), v3(frame(dir).0));
    let _ = writeln!(x, r#"Camera "perspective" "float fov" [ {} ]"#, num(fov));
    let _ = writeln!(x, r#"Sampler "independent" "integer pixelsamples" [ 64 ]"#);
    let _ = writeln!(x, r#"Integrator "path" "integer maxdepth" [ {depth} ]"#);
    let _ = writeln!(
        x,
        r#"PixelFilter "box" "float xradius" [ 0.5 ] "float yradius" [ 0.5 ]"#
    );
    let _ = writeln!(
        x,
        r#"Film "rgb" "integer xresolution" [ {w} ] "integer yresolution" [ {h} ] "string filename" [ "render.exr" ] "bool savefp16" false"#
    );
    x.push_str("WorldBegin\n");
    for (i, e) in scene.emitters.iter().enumerate() {
        let v = DVec3::from_array;
        let el = match e {
            EmitterDesc::Point {
                position,
                intensity,
                ..
            } => format!(
                r#"LightSource "point" "point3 from" [ {} ] "rgb I" {}"#,
                v3(v(*position)),
                grey(*intensity)
            ),
            EmitterDesc::Spot {
                position,
                direction,
                intensity,
                cone_angle,
                falloff_start,
                ..
            } => format!(
                r#"LightSource "spot" "point3 from" [ {} ] "point3 to" [ {} ] "float coneangle" [ {} ] "float conedeltaangle" [ {} ] "rgb I" {}"#,
                v3(v(*position)),
                v3(v(*position) + v(*direction)),
                num(*cone_angle),
                num(cone_angle - falloff_start),
                grey(*intensity)
            ),
            EmitterDesc::Directional {
                direction,
                irradiance,
                ..
            } => format!(
                r#"LightSource "distant" "point3 from" [ 0 0 0 ] "point3 to" [ {} ] "rgb L" {}"#,
                v3(v(*direction)),
                grey(*irradiance)
            ),
            EmitterDesc::Constant { radiance, .. } => {
                format!(r#"LightSource "infinite" "rgb L" {}"#, grey(*radiance))
            }
            EmitterDesc::Envmap { .. } => {
                return Err(Refusal(format!(
                    "scene.emitters[{i}]: environment maps are not exported yet (lat-long orientation conventions differ)"
                )));
            }
        };
        let _ = writeln!(x, "{el}");
    }
    for (i, s) in scene.shapes.iter().enumerate() {
        let field = format!("scene.shapes[{i}]");
        let mat = match &s.material {
            Some(m) => match scene.materials.get(m) {
                Some(b) => material(b)?,
                None => return Err(Refusal(format!("{field}.material: `{m}` is not defined"))),
            },
            None => format!(r#"Material "diffuse" "rgb reflectance" {}"#, grey(0.0)),
        };
        x.push_str("AttributeBegin\n");
        let _ = writeln!(x, "  {mat}");
        if let Some(e) = &s.emission {
            let _ = writeln!(
                x,
                r#"  AreaLightSource "diffuse" "rgb L" {} "bool twosided" {}"#,
                grey(e.radiance),
                e.two_sided
            );
        }
        let v = DVec3::from_array;
        let mut local = String::new();
        let shape = match &s.geometry {
            GeometryDesc::Sphere {
                center,
                radius,
                theta_max,
                axis,
            } => {
                let axis = v(axis.unwrap_or([0.0, 0.0, 1.0])).normalize();
                local = frame_transform(v(*center), axis);
                let zmin = match theta_max {
                    Some(t) if *t < 180.0 => {
                        format!(
                            r#" "float zmin" [ {} ]"#,
                            num(radius * t.to_radians().cos())
                        )
                    }
                    Some(_) | None => String::new(),
                };
                format!(
                    r#"Shape "sphere" "float radius" [ {} ]{zmin}"#,
                    num(*radius)
                )
            }
            GeometryDesc::Disk {
                center,
                normal,
                radius,
                inner_radius,
            } => {
                local = frame_transform(v(*center), v(*normal).normalize());
                format!(
                    r#"Shape "disk" "float radius" [ {} ] "float innerradius" [ {} ]"#,
                    num(*radius),
                    num(inner_radius.unwrap_or(0.0))
                )
            }
            GeometryDesc::Rectangle { .. }
            | GeometryDesc::Triangle { .. }
            | GeometryDesc::Mesh { .. } => {
                let name = mesh_file(i, &s.geometry, &mut files)?;
                format!(r#"Shape "plymesh" "string filename" [ "{name}" ]"#)
            }
            GeometryDesc::Obj { .. } => {
                return Err(Refusal(format!(
                    "{field}: OBJ geometry is not exported yet"
                )));
            }
        };
        if !local.is_empty() {
            let _ = writeln!(x, "  {local}");
        }
        if s.flip_normals {
            x.push_str("  ReverseOrientation\n");
        }
        let _ = writeln!(x, "  {shape}\nAttributeEnd");
    }
    files.push(("scene.pbrt".into(), x.into_bytes()));
    Ok(Written {
        files,
        manifest: Manifest {
            renderer: Target::Pbrt,
            source: String::new(),
            name: desc.name.clone(),
            case: "case.json".into(),
            scene: "scene.pbrt".into(),
            sensor: probe.sensor().into(),
            width: w,
            height: h,
            scale: 1.0,
            conventions: vec![
                "grey RGB; pbrt-v4 normalises RGB lights to the film's white".into(),
                format!("path maxdepth {depth} (lightproof's count)"),
                format!("perspective camera, fov {fov}°, {w}×{h}"),
            ],
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene_of(json: &str) -> String {
        crate::export::mapping::measured(Target::Pbrt, json).unwrap()
    }

    /// pbrt-v4's `rgb` film writes half floats unless told otherwise: a render of an
    /// exact value (a mirror under a constant sky) would be off by up to 2⁻¹² relative.
    #[test]
    fn film_writes_full_floats() {
        let x = scene_of(
            r#"{"name":"n","teaches":"t","scene":{"emitters":[{"type":"constant","radiance":0.7}]},
              "measure":{"radiance":{"at":[0,0,0],"direction":[0,0,1]}},"estimators":["bsdf"]}"#,
        );
        let film = x.lines().find(|l| l.starts_with("Film")).unwrap();
        assert!(film.contains(r#""bool savefp16" false"#), "{film}");
    }
    /// F ≡ 1 (pbrt-v4 has no such conductor) is exported as η = 1, k = 10⁶, the GGX α
    /// as pbrt's roughness itself (no remapping).
    #[test]
    fn white_rough_conductor_is_a_huge_k_conductor() {
        let x = scene_of(
            r#"{"name":"n","teaches":"t","measure":{"albedo":{"bsdf":{"type":"rough_conductor",
              "alpha":0.5,"fresnel":"none"},"theta_degrees":60}},"estimators":["bsdf"]}"#,
        );
        let m = x.lines().find(|l| l.contains("Material")).unwrap();
        assert!(
            m.contains(
                r#""spectrum eta" [ 300 1 900 1 ] "spectrum k" [ 300 1000000 900 1000000 ]"#
            ) && m.contains(r#""float roughness" [ 0.5 ] "bool remaproughness" false"#),
            "{m}"
        );
    }

    fn export(
        materials: &str,
        shapes: &str,
        emitters: &str,
        extra: &str,
    ) -> Result<String, String> {
        crate::export::mapping::export(Target::Pbrt, materials, shapes, emitters, extra)
    }

    /// The parameters pbrt-v4 (commit 5f7a6068) reads for each directive and type this
    /// exporter writes, with their types: an unread parameter makes pbrt-v4 exit
    /// (`ParameterDictionary::ReportUnused`: "unused parameter"), and a misspelt one
    /// would otherwise fall back to pbrt's default. From `lights.cpp`, `materials.cpp`,
    /// `shapes.cpp`, `cameras.cpp`, `samplers.cpp`, `film.cpp`, `filters.cpp` and
    /// `cpu/integrators.cpp` (`parameters.GetOne…("name", …)`).
    const PBRT_V4_PARAMETERS: &[(&str, &str, &[&str])] = &[
        ("Camera", "perspective", &["float fov"]),
        ("Sampler", "independent", &["integer pixelsamples"]),
        ("Integrator", "path", &["integer maxdepth"]),
        ("PixelFilter", "box", &["float xradius", "float yradius"]),
        (
            "Film",
            "rgb",
            &[
                "integer xresolution",
                "integer yresolution",
                "string filename",
                "bool savefp16",
            ],
        ),
        ("LightSource", "point", &["point3 from", "rgb I"]),
        (
            "LightSource",
            "spot",
            &[
                "point3 from",
                "point3 to",
                "float coneangle",
                "float conedeltaangle",
                "rgb I",
            ],
        ),
        (
            "LightSource",
            "distant",
            &["point3 from", "point3 to", "rgb L"],
        ),
        ("LightSource", "infinite", &["rgb L"]),
        ("AreaLightSource", "diffuse", &["rgb L", "bool twosided"]),
        ("Material", "diffuse", &["rgb reflectance"]),
        (
            "Material",
            "conductor",
            &[
                "spectrum eta",
                "spectrum k",
                "float roughness",
                "bool remaproughness",
            ],
        ),
        (
            "Material",
            "dielectric",
            &["float eta", "float roughness", "bool remaproughness"],
        ),
        ("Shape", "sphere", &["float radius", "float zmin"]),
        ("Shape", "disk", &["float radius", "float innerradius"]),
        ("Shape", "plymesh", &["string filename"]),
    ];

    /// Every `"type name"` parameter of every directive in `scene` is one pbrt-v4 reads
    /// for that directive's type (see [`PBRT_V4_PARAMETERS`]); returns how many were
    /// checked.
    fn check_parameters(scene: &str) -> usize {
        let mut n = 0;
        for line in scene.lines().map(str::trim) {
            let Some((directive, rest)) = line.split_once(' ') else {
                continue;
            };
            if !rest.starts_with('"') {
                continue;
            }
            // "kind" "type name" [ ... ] "type name" [ ... ] ...: the quoted strings
            // outside brackets, the first being the directive's type.
            let mut quoted = Vec::new();
            let (mut depth, mut cur, mut inside) = (0, String::new(), false);
            for c in rest.chars() {
                match c {
                    '[' if !inside => depth += 1,
                    ']' if !inside => depth -= 1,
                    '"' if depth == 0 => {
                        if inside {
                            quoted.push(std::mem::take(&mut cur));
                        }
                        inside = !inside;
                    }
                    _ if inside && depth == 0 => cur.push(c),
                    _ => {}
                }
            }
            let Some((kind, params)) = quoted.split_first() else {
                continue;
            };
            let Some((_, _, known)) = PBRT_V4_PARAMETERS
                .iter()
                .find(|(d, k, _)| *d == directive && k == kind)
            else {
                panic!("{directive} \"{kind}\": not in the table of what pbrt-v4 reads\n{line}");
            };
            for p in params {
                assert!(
                    known.contains(&p.as_str()),
                    "{directive} \"{kind}\": pbrt-v4 reads no \"{p}\" (it would exit: unused parameter)\n{line}"
                );
                n += 1;
            }
        }
        n
    }

    /// Every directive the exporter writes, for every light, material and shape it
    /// maps, names parameters pbrt-v4 reads (the spot light's falloff is
    /// `conedeltaangle`: `conedelta` made pbrt-v4 exit on every scene with a spot).
    #[test]
    fn every_parameter_is_one_pbrt_v4_reads() {
        use crate::export::mapping::{DISK_LIGHT, with_material};
        let mut scenes = vec![
            export("", DISK_LIGHT, "", r#","max_depth":3"#),
            export(
                "",
                r#"{"geometry":{"type":"disk","center":[0,0,3],"normal":[0,0,-1],"radius":1,"inner_radius":0.5},"emission":{"radiance":2,"two_sided":true},"flip_normals":true}"#,
                "",
                "",
            ),
            export(
                "",
                &format!(
                    r#"{DISK_LIGHT},{{"geometry":{{"type":"sphere","center":[0,5,0],"radius":2,"theta_max":60}}}},{{"geometry":{{"type":"rectangle","corner":[0,5,0],"edge_u":[1,0,0],"edge_v":[0,1,0]}}}}"#
                ),
                "",
                "",
            ),
            export(
                "",
                "",
                r#"{"type":"point","position":[0,0,2],"intensity":3},{"type":"spot","position":[0,0,2],"direction":[0,0,-1],"intensity":5,"cone_angle":30,"falloff_start":20},{"type":"directional","direction":[0,0,-1],"irradiance":4},{"type":"constant","radiance":1.25}"#,
                "",
            ),
        ];
        for bsdf in [
            r#"{"type":"lambertian","albedo":0.5}"#,
            r#"{"type":"conductor","eta":0.25,"k":3.5}"#,
            r#"{"type":"dielectric","eta":1.5}"#,
            r#"{"type":"rough_conductor","alpha":0.375,"eta":0.25,"k":3.5}"#,
            r#"{"type":"rough_conductor","alpha":0.375,"fresnel":"none"}"#,
            r#"{"type":"rough_dielectric","alpha":0.5,"eta":1.25}"#,
        ] {
            scenes.push(with_material(Target::Pbrt, bsdf));
        }
        let mut checked = 0;
        for s in &scenes {
            let s = s.as_ref().unwrap_or_else(|e| panic!("refused: {e}"));
            checked += check_parameters(s);
        }
        // Each scene's camera, sampler, integrator, filter and film (9 parameters), and
        // the lights, materials and shapes above.
        assert!(checked > 9 * scenes.len() + 40, "{checked}");
    }

    /// pbrt-v4 renders Trowbridge–Reitz with α < 10⁻³ as a perfect specular surface
    /// (`EffectivelySmooth`): such rough BSDFs are refused, α = 10⁻³ itself (the
    /// catalog's smallest) is exported as it is.
    #[test]
    fn roughness_pbrt_treats_as_smooth_is_refused() {
        use crate::export::mapping::{has, refused, with_material};
        let m = |bsdf: &str| with_material(Target::Pbrt, bsdf);
        for bsdf in [
            r#"{"type":"rough_conductor","alpha":0.0005,"fresnel":"none"}"#,
            r#"{"type":"rough_dielectric","alpha":0.0009,"eta":1.5}"#,
        ] {
            refused(&m(bsdf), "EffectivelySmooth");
        }
        has(
            &m(r#"{"type":"rough_conductor","alpha":0.001,"fresnel":"none"}"#),
            &[r#""float roughness" [ 0.0010000000474974513 ]"#],
        );
    }

    /// The README's pbrt column, row by row.
    #[test]
    fn the_mapping_table_holds_for_pbrt() {
        use crate::export::mapping::{DISK_LIGHT, has, refused, with_material};
        let m = |bsdf: &str| with_material(Target::Pbrt, bsdf);
        // max_depth k is pbrt's maxdepth k; unbounded is 65536.
        has(
            &export("", DISK_LIGHT, "", r#","max_depth":4"#),
            &[r#""integer maxdepth" [ 4 ]"#],
        );
        has(
            &export("", DISK_LIGHT, "", ""),
            &[
                r#""integer maxdepth" [ 65536 ]"#,
                // Radiance along a ray: a 1×1 perspective camera of fov 10⁻³°.
                r#"Camera "perspective" "float fov" [ 0.001 ]"#,
                r#""integer xresolution" [ 1 ] "integer yresolution" [ 1 ]"#,
            ],
        );
        has(
            &m(r#"{"type":"lambertian","albedo":0.5}"#),
            &[r#"Material "diffuse" "rgb reflectance" [ 0.5 0.5 0.5 ]"#],
        );
        has(
            &m(r#"{"type":"conductor","eta":0.25,"k":3.5}"#),
            &[
                r#"Material "conductor" "spectrum eta" [ 300 0.25 900 0.25 ] "spectrum k" [ 300 3.5 900 3.5 ] "float roughness" [ 0 ]"#,
            ],
        );
        has(
            &m(r#"{"type":"dielectric","eta":1.5}"#),
            &[r#"Material "dielectric" "float eta" [ 1.5 ] "float roughness" [ 0 ]"#],
        );
        has(
            &m(r#"{"type":"rough_conductor","alpha":0.375,"eta":0.25,"k":3.5}"#),
            &[r#""float roughness" [ 0.375 ] "bool remaproughness" false"#],
        );
        has(
            &m(r#"{"type":"rough_dielectric","alpha":0.5,"eta":1.25}"#),
            &[
                r#"Material "dielectric" "float eta" [ 1.25 ] "float roughness" [ 0.5 ] "bool remaproughness" false"#,
            ],
        );
        refused(
            &m(r#"{"type":"plastic","albedo":0.25,"eta":1.5}"#),
            "coateddiffuse",
        );
        refused(
            &m(r#"{"type":"oren_nayar","albedo":0.5,"sigma":20}"#),
            "no Oren–Nayar",
        );
        refused(
            &m(
                r#"{"type":"rough_conductor","alpha":0.3,"eta":0.25,"k":3.5,"distribution":"beckmann"}"#,
            ),
            "Beckmann",
        );
        refused(
            &m(r#"{"type":"rough_dielectric","alpha":0.3,"eta":1.5,"masking":"uncorrelated"}"#),
            "uncorrelated masking",
        );
        // No material: black diffuse. Emission one- and two-sided.
        has(
            &export(
                "",
                &format!(
                    r#"{DISK_LIGHT},{{"geometry":{{"type":"sphere","center":[0,5,0],"radius":1}}}}"#
                ),
                "",
                "",
            ),
            &[
                r#"Material "diffuse" "rgb reflectance" [ 0 0 0 ]"#,
                r#"AreaLightSource "diffuse" "rgb L" [ 2 2 2 ] "bool twosided" false"#,
            ],
        );
        has(
            &export(
                "",
                r#"{"geometry":{"type":"disk","center":[0,0,3],"normal":[0,0,-1],"radius":1},"emission":{"radiance":2,"two_sided":true}}"#,
                "",
                "",
            ),
            &[r#""bool twosided" true"#],
        );
        // Shapes: a cap by zmin = r cos θmax, an annulus by innerradius, meshes as PLY,
        // flipped normals as ReverseOrientation.
        let shape = |g: &str, rest: &str| {
            export(
                "",
                &format!(r#"{DISK_LIGHT},{{"geometry":{g}{rest}}}"#),
                "",
                "",
            )
        };
        has(
            &shape(
                r#"{"type":"sphere","center":[0,5,0],"radius":2,"theta_max":60}"#,
                "",
            ),
            &[r#"Shape "sphere" "float radius" [ 2 ] "float zmin" [ 1.0000000000000002 ]"#],
        );
        has(
            &shape(
                r#"{"type":"disk","center":[0,5,0],"normal":[0,0,1],"radius":2,"inner_radius":1}"#,
                r#","flip_normals":true"#,
            ),
            &[
                "ReverseOrientation\n  Shape \"disk\" \"float radius\" [ 2 ] \"float innerradius\" [ 1 ]",
            ],
        );
        has(
            &shape(
                r#"{"type":"rectangle","corner":[0,5,0],"edge_u":[1,0,0],"edge_v":[0,1,0]}"#,
                "",
            ),
            &[r#"Shape "plymesh" "string filename" [ "#],
        );
        // Lights.
        let light = |e: &str| export("", "", e, "");
        has(
            &light(r#"{"type":"point","position":[0,0,2],"intensity":3}"#),
            &[r#"LightSource "point" "point3 from" [ 0 0 2 ] "rgb I" [ 3 3 3 ]"#],
        );
        has(
            &light(
                r#"{"type":"spot","position":[0,0,2],"direction":[0,0,-1],"intensity":5,"cone_angle":30,"falloff_start":20}"#,
            ),
            &[
                r#"LightSource "spot" "point3 from" [ 0 0 2 ] "point3 to" [ 0 0 1 ] "float coneangle" [ 30 ] "float conedeltaangle" [ 10 ] "rgb I" [ 5 5 5 ]"#,
            ],
        );
        has(
            &light(r#"{"type":"directional","direction":[0,0,-1],"irradiance":4}"#),
            &[
                r#"LightSource "distant" "point3 from" [ 0 0 0 ] "point3 to" [ 0 0 -1 ] "rgb L" [ 4 4 4 ]"#,
            ],
        );
        has(
            &light(r#"{"type":"constant","radiance":1.25}"#),
            &[r#"LightSource "infinite" "rgb L" [ 1.25 1.25 1.25 ]"#],
        );
    }
}
