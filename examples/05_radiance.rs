//! # 5. Radiance and its invariance along a ray
//!
//! Radiance is power per unit area perpendicular to the beam, per unit solid angle:
//! L = d²Φ / (dA cos θ dω), in W/(m²·sr). It is what a pixel of a camera (or an eye)
//! measures, and what a renderer transports.
//!
//! In vacuum radiance is constant along a ray: walk away from a surface and each pixel
//! still sees the same L. The surface looks smaller (its solid angle σ falls as 1/d²)
//! and the irradiance it delivers falls with it (E = L σ⊥), but L = E / σ⊥ stays put.
//! That is why a path tracer can carry radiance from surface to surface unchanged.
//!
//! The checks: an emitting sphere seen from 2, 20 and 200 m (the radiance a ray brings
//! back, and the irradiance the sphere delivers, with L recovered as E/σ⊥), then a grey
//! diffuse sphere under a uniform sky whose reflected radiance ρ L_sky is the same from
//! every distance.
//!
//! Picture: target/examples/05_radiance_near.exr and 05_radiance_far.exr, the grey
//! sphere rendered from 3 m and 12 m: smaller, but its pixels keep their value.
//!
//! Run: `cargo run --release --example 05_radiance -- [SAMPLES]`

use glam::Vec3;
use lightproof::case::Case;
use lightproof::math::Frame;
use lightproof::sampling::Sampler;
use lightproof::stats::Verdict;
use lightproof::transport::Estimator;
use lightproof::transport::path::{Prev, trace};
use lightproof::transport::phase::Grey;
use lightproof_analytic::geom::Vec3 as V;
use lightproof_analytic::irradiance::sphere as sphere_irradiance;
use serde_json::json;

/// A case file: a grey sphere under a uniform sky, seen from 30 m.
const SKY_CASE: &str = r#"{
  "name": "grey sphere under a uniform sky, seen from 30 m",
  "teaches": "a convex diffuse object of albedo ρ under a sky of radiance L reflects ρ L, seen from any distance",
  "scene": {
    "materials": { "grey": { "type": "lambertian", "albedo": 0.6 } },
    "shapes": [ { "geometry": { "type": "sphere", "center": [0, 0, 0], "radius": 1 }, "material": "grey" } ],
    "emitters": [ { "type": "constant", "radiance": 1.5 } ]
  },
  "measure": { "radiance": { "at": [0, 0, 30], "direction": [0.01, 0.005, -1] } },
  "reference": { "closed_form": "furnace_convex_object", "albedo": 0.6, "radiance": 1.5 },
  "estimators": ["light", "bsdf", "mis"],
  "samplers": ["sobol"], "samples": 1048576
}"#;

fn main() {
    let n = samples(1 << 18);
    println!(
        "5. Radiance L = d²Φ / (dA cos θ dω) [W/(m²·sr)] is constant along a ray: E = L σ⊥ falls with distance, L does not"
    );
    print_rule(&format!("{n} samples per estimate"));
    let mut ok = true;

    let le = 3.0;
    println!("An emitting sphere, radius 1 m, L = {le} W/(m²·sr), seen from distance d:");
    for d in [2.0, 20.0, 200.0] {
        let scene = json!({ "shapes": [ { "geometry": { "type": "sphere", "center": [0, 0, 0], "radius": 1 },
                                          "emission": { "radiance": le } } ] });
        // The radiance a ray from the eye brings back (aimed a little off centre).
        let c = load(json!({
            "name": format!("emitting sphere radiance from {d}"), "teaches": "radiance is invariant along a ray",
            "scene": scene, "measure": { "radiance": { "at": [0, 0, d], "direction": [0.3 / d, 0.1 / d, -1] } },
            "estimators": ["mis"]
        }));
        ok &= report(
            &format!("d = {d:<5} radiance along a ray"),
            &estimate(&c, Estimator::Mis, n, le),
        );
        // The irradiance it delivers to a receiver facing it, and σ⊥ = E / L.
        let c = load(json!({
            "name": format!("emitting sphere irradiance from {d}"), "teaches": "E = L σ⊥",
            "scene": scene, "measure": { "irradiance": { "at": [0, 0, d], "normal": [0, 0, -1] } },
            "estimators": ["light"]
        }));
        let (p, nrm, ctr) = (
            V::new(0.0, 0.0, d),
            V::new(0.0, 0.0, -1.0),
            V::new(0.0, 0.0, 0.0),
        );
        let proj = sphere_irradiance(p, nrm, ctr, 1.0, 1.0); // σ⊥: the irradiance of L = 1
        let v = estimate(&c, Estimator::Light, n, le * proj);
        ok &= report(
            &format!("d = {d:<5} irradiance E = L σ⊥, σ⊥ = {proj:.3e} sr"),
            &v,
        );
        println!(
            "  {:<50} {:>12.6}  (L = E / σ⊥ from the estimate above)",
            format!("d = {d:<5} E / σ⊥"),
            v.estimate / proj
        );
    }

    println!(
        "\nA grey sphere (ρ = 0.6) under a uniform sky L_sky = 1.5 reflects ρ L_sky = 0.9 towards every eye:"
    );
    show_case_file("05_grey_sphere.json", SKY_CASE);
    for d in [3.0, 30.0, 300.0] {
        let c = load(json!({
            "name": format!("grey sphere under a uniform sky, seen from {d} m"),
            "teaches": "reflected radiance does not depend on the distance",
            "scene": {
                "materials": { "grey": { "type": "lambertian", "albedo": 0.6 } },
                "shapes": [ { "geometry": { "type": "sphere", "center": [0, 0, 0], "radius": 1 }, "material": "grey" } ],
                "emitters": [ { "type": "constant", "radiance": 1.5 } ]
            },
            "measure": { "radiance": { "at": [0, 0, d], "direction": [0.3 / d, 0.15 / d, -1] } },
            "reference": { "closed_form": "furnace_convex_object", "albedo": 0.6, "radiance": 1.5 },
            "estimators": ["light", "bsdf", "mis"]
        }));
        for &est in &c.desc.estimators {
            ok &= report(
                &format!("d = {d:<5} reflected radiance [{}]", est.name()),
                &estimate(&c, est, n, c.reference.unwrap()),
            );
        }
    }

    // Two pictures of the grey sphere with the same camera at 3 m and 12 m.
    for (d, name) in [(3.0, "05_radiance_near.exr"), (12.0, "05_radiance_far.exr")] {
        match render(d, name, (n / 4096).clamp(4, 64)) {
            Ok((p, count, mean)) => {
                println!(
                    "wrote {p} (camera at {d} m: {count} pixels show the sphere, their mean radiance is {mean:.3})"
                )
            }
            Err(e) => println!("(could not write {name}: {e})"),
        }
    }
    finish(ok);
}

/// Run one estimator of a case and judge it against `exact`.
fn estimate(case: &Case, est: Estimator, n: u64, exact: f64) -> Verdict {
    judged(case, est, n, 5, exact)
}

/// Render the grey sphere from distance `d` (64 × 64, 50° field of view, `spp` samples
/// per pixel) into target/examples/`name`; returns the path, the number of pixels
/// inside the sphere and their mean.
fn render(
    d: f64,
    name: &str,
    spp: u64,
) -> Result<(String, usize, f64), Box<dyn std::error::Error>> {
    let case = load(json!({
        "name": "grey sphere image", "teaches": "radiance per pixel",
        "scene": {
            "materials": { "grey": { "type": "lambertian", "albedo": 0.6 } },
            "shapes": [ { "geometry": { "type": "sphere", "center": [0, 0, 0], "radius": 1 }, "material": "grey" } ],
            "emitters": [ { "type": "constant", "radiance": 1.5 } ]
        },
        "measure": { "radiance": { "at": [0, 0, d], "direction": [0, 0, -1] } },
        "estimators": ["mis"]
    }));
    let cfg = case.plan.config(Estimator::Mis);
    // Scene coordinates are rebased on the measurement point: the eye.
    let eye = case.measure.origin().unwrap_or(Vec3::ZERO);
    let frame = Frame::from_z(Vec3::NEG_Z);
    let (w, h) = (64usize, 64usize);
    let tan = (25f32).to_radians().tan();
    let sampler = Sampler::independent(5);
    let mut pixels = vec![0f32; w * h];
    for (i, px) in pixels.iter_mut().enumerate() {
        let (x, y) = (i % w, i / w);
        let mut sum = 0.0f64;
        for k in 0..spp {
            let mut s = sampler.stream(i as u64 * spp + k);
            let j = s.next_2d();
            let u = (2.0 * (x as f32 + j.x) / w as f32 - 1.0) * tan;
            let v = (1.0 - 2.0 * (y as f32 + j.y) / h as f32) * tan;
            let dir = frame.to_world(Vec3::new(u, v, 1.0).normalize());
            sum += trace(
                &case.scene,
                &cfg,
                &Grey,
                eye,
                dir,
                Prev::sensor(eye),
                0,
                &mut s,
            ) as f64;
        }
        *px = (sum / spp as f64) as f32;
    }
    lightproof::io::write_exr_atomic(&common::out_dir()?.join(name), w, h, |x, y| {
        let v = pixels[y * w + x];
        (v, v, v)
    })?;
    // The mean of the pixels well inside the sphere's silhouette (half-angle asin(1/d)).
    let inside = (0.9 * (1.0 / d).asin()).tan() as f32 / tan;
    let sphere_pixels: Vec<f32> = (0..w * h)
        .filter(|i| {
            let u = 2.0 * ((i % w) as f32 + 0.5) / w as f32 - 1.0;
            let v = 2.0 * ((i / w) as f32 + 0.5) / h as f32 - 1.0;
            u * u + v * v < inside * inside
        })
        .map(|i| pixels[i])
        .collect();
    let mean =
        sphere_pixels.iter().map(|&v| v as f64).sum::<f64>() / sphere_pixels.len().max(1) as f64;
    Ok((format!("target/examples/{name}"), sphere_pixels.len(), mean))
}

mod common;
#[allow(unused_imports)]
use common::*;
