//! # 3. Radiant intensity
//!
//! Intensity is power per unit solid angle in a direction: I(ω) = dΦ/dω, in W/sr. It
//! describes sources seen from far away, whose size no longer matters.
//!
//! - An isotropic point light has the same I in every direction, so Φ = ∫ I dω = 4π I:
//!   the power that crosses any closed surface around it, Φ = ∮ E dA (Gauss's law for
//!   light), checked on a sphere that does not centre on the light.
//! - A flat Lambertian emitter of radiance L and area A has I(θ) = L A cos θ (Lambert's
//!   cosine law): seen at an angle θ from its normal its projected area is A cos θ. Its
//!   power, one-sided, is Φ = ∫ I dω = π L A.
//!
//! The Monte Carlo estimator of the disk's intensity samples points uniformly on its area:
//! I(ω) = ∫_A L cos θ dA ≈ L cos θ / p_A with p_A = 1/A.
//!
//! - A Lambertian sphere has I = L π R² in every direction: from anywhere it looks like
//!   a disk of radius R and radiance L.
//!
//! Picture: target/examples/03_intensity.svg, I(θ) of the disk, estimates on the cosine.
//!
//! Run: `cargo run --release --example 03_intensity -- [SAMPLES]`

use lightproof::case::Case;
use lightproof::stats::Verdict;
use lightproof::transport::Estimator;
use lightproof_analytic::radiometry::{isotropic_point_power, lambertian_sphere_intensity};
use plotters::prelude::*;
use serde_json::json;
use std::f64::consts::PI;

/// A case file: the intensity of a Lambertian disk 60° off its normal.
const DISK_CASE: &str = r#"{
  "name": "Lambertian disk intensity at 60 degrees",
  "teaches": "a flat Lambertian emitter has I(θ) = L A cos θ",
  "scene": { "shapes": [ { "geometry": { "type": "disk", "center": [0, 0, 0], "normal": [0, 0, 1], "radius": 0.5 },
                           "emission": { "radiance": 2 } } ] },
  "measure": { "intensity": { "shape": 0, "direction": [0.8660254037844386, 0, 0.5] } },
  "reference": { "closed_form": "lambertian_intensity", "radiance": 2, "area": 0.7853981633974483, "theta": 1.0471975511965976 },
  "estimators": ["area"], "samples": 1048576, "samplers": ["sobol"]
}"#;

fn main() {
    let n = samples(1 << 20);
    println!(
        "3. Intensity I = dΦ/dω [W/sr]:  point light Φ = 4π I;  Lambertian emitter I(θ) = L A cos θ, Φ = π L A"
    );
    print_rule(&format!("{n} samples per estimate"));
    let mut ok = true;

    // An isotropic point light of intensity 2 W/sr. Its intensity is the given number
    // (I = dΦ/dω, the same every way), so reading it back would check nothing; its power
    // Φ = ∫ I dω = 4π I is checked through the power that crosses a closed surface
    // around it, whatever the surface: a sphere whose centre is not the light's, so the
    // irradiance E = I cos θ / d² varies over it and Φ = ∮ E dA is a true integral
    // (Gauss's law for light; the engine samples points on the sphere by area and
    // estimates E at each from the light).
    println!(
        "Isotropic point light, I = 2 W/sr, at (0.3, −0.2, 0.1) inside a sphere of radius 1 centred at the origin:"
    );
    println!("  the intensity is the given I = dΦ/dω; every direction carries the same 2 W/sr");
    let c = load(json!({
        "name": "point light power through an enclosing sphere",
        "teaches": "the power crossing any closed surface around a point light is Φ = 4π I",
        "scene": { "emitters": [ { "type": "point", "position": [0.3, -0.2, 0.1], "intensity": 2 } ],
                   "shapes": [ { "geometry": { "type": "sphere", "center": [0, 0, 0], "radius": 1 },
                                 "flip_normals": true } ] },
        "measure": { "flux": { "shape": 0 } },
        "estimators": ["light"]
    }));
    ok &= check(
        "power Φ = ∮ E dA over the sphere  vs  4π I",
        &c,
        Estimator::Light,
        n,
        isotropic_point_power(2.0),
    );

    println!("\nLambertian disk, radius 0.5 m, L = 2 W/(m²·sr):");
    show_case_file("03_disk_intensity.json", DISK_CASE);
    let (radiance, radius) = (2.0, 0.5);
    let area = PI * radius * radius;
    let mut points = Vec::new();
    for deg in [0.0f64, 15.0, 30.0, 45.0, 60.0, 75.0, 89.0] {
        let t = deg.to_radians();
        let c = load(json!({
            "name": format!("Lambertian disk intensity at {deg} degrees"),
            "teaches": "a flat Lambertian emitter has I(θ) = L A cos θ",
            "scene": { "shapes": [ { "geometry": { "type": "disk", "center": [0, 0, 0], "normal": [0, 0, 1], "radius": radius },
                                     "emission": { "radiance": radiance } } ] },
            "measure": { "intensity": { "shape": 0, "direction": [t.sin(), 0.0, t.cos()] } },
            "reference": { "closed_form": "lambertian_intensity", "radiance": radiance, "area": area, "theta": t },
            "estimators": ["area"]
        }));
        let v = estimate(&c, Estimator::Area, n);
        ok &= report(&format!("I(θ = {deg}°)  vs  L A cos θ"), &v);
        points.push((deg, v.estimate, v.std_error));
    }
    let c = load(json!({
        "name": "Lambertian disk power", "teaches": "Φ = π L A",
        "scene": { "shapes": [ { "geometry": { "type": "disk", "center": [0, 0, 0], "normal": [0, 0, 1], "radius": radius },
                                 "emission": { "radiance": radiance } } ] },
        "measure": { "power": { "shape": 0 } },
        "reference": { "closed_form": "lambertian_power", "radiance": radiance, "area": area },
        "estimators": ["uniform"]
    }));
    ok &= check(
        "power Φ = ∫∫ L cos θ dω dA  vs  π L A",
        &c,
        Estimator::Uniform,
        n,
        c.reference.unwrap(),
    );

    // A Lambertian sphere: every direction sees a disk of radius R (its projected
    // area), so I = L π R² in all directions, the same as a facing disk of radius R.
    println!(
        "\nLambertian sphere, radius 0.5 m, L = 2 W/(m²·sr): I = L π R² in every direction (the Sun looks like a flat disk):"
    );
    for dir in [[0.0, 0.0, 1.0], [0.6, 0.0, 0.8], [-0.48, 0.6, -0.64]] {
        let c = load(json!({
            "name": format!("sphere intensity towards {dir:?}"), "teaches": "a Lambertian sphere has I = L π R²",
            "scene": { "shapes": [ { "geometry": { "type": "sphere", "center": [0, 0, 0], "radius": radius },
                                     "emission": { "radiance": radiance } } ] },
            "measure": { "intensity": { "shape": 0, "direction": dir } },
            "estimators": ["area"]
        }));
        ok &= check(
            &format!("I towards ({}, {}, {})  vs  L π R²", dir[0], dir[1], dir[2]),
            &c,
            Estimator::Area,
            n,
            lambertian_sphere_intensity(radiance, radius),
        );
    }

    match plot(&points, radiance * area) {
        Ok(p) => println!("\nwrote {p} (the disk's intensity against the angle from its normal)"),
        Err(e) => println!("\n(could not write the plot: {e})"),
    }
    finish(ok);
}

/// Run one estimator of a case and judge it against `exact`.
fn estimate(case: &Case, est: Estimator, n: u64) -> Verdict {
    judged(case, est, n, 3, case.reference.unwrap_or(f64::NAN))
}

/// Run, judge against `exact` and report.
fn check(what: &str, case: &Case, est: Estimator, n: u64, exact: f64) -> bool {
    report(what, &judged(case, est, n, 3, exact))
}

fn plot(points: &[(f64, f64, f64)], i0: f64) -> Result<String, Box<dyn std::error::Error>> {
    common::save_svg("03_intensity.svg", (720, 460), |root| {
        let mut chart = common::chart(root, "Lambert's cosine law: intensity of a Lambertian disk")
            .build_cartesian_2d(0.0..90.0, 0.0..i0 * 1.1)?;
        chart
            .configure_mesh()
            .x_desc("angle from the normal θ (degrees)")
            .y_desc("intensity I (W/sr)")
            .draw()?;
        chart
            .draw_series(LineSeries::new(
                (0..=90).map(|d| (d as f64, i0 * (d as f64).to_radians().cos())),
                &BLACK,
            ))?
            .label("L A cos θ (closed form)")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK));
        chart
            .draw_series(
                points
                    .iter()
                    .map(|&(d, i, _)| Circle::new((d, i), 4, RED.filled())),
            )?
            .label("Monte Carlo (area sampling)")
            .legend(|(x, y)| Circle::new((x + 10, y), 4, RED.filled()));
        chart.draw_series(points.iter().map(|&(d, i, se)| {
            PathElement::new(vec![(d, i - 3.0 * se), (d, i + 3.0 * se)], RED)
        }))?;
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()?;
        Ok(())
    })
}

mod common;
#[allow(unused_imports)]
use common::*;
