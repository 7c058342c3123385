//! # 4. Irradiance, the inverse-square law and the cosine law
//!
//! Irradiance is the power arriving per unit area of a receiver: E = dΦ/dA, in W/m².
//! It gathers radiance from every direction of the receiver's hemisphere, each weighted
//! by the cosine to the receiver's normal:
//!
//!     E = ∫ L(ω) cos θ dω  (= L σ⊥ for a uniform emitter, σ⊥ its projected solid angle)
//!
//! - A uniform disk of radius R at height h on its axis gives E = π L R² / (R² + h²).
//! - A uniform polygon gives Lambert's contour formula E = ½ L Σ Θᵢ n·γ̂ᵢ.
//! - A point light of intensity I at distance r gives E = I cos θ / r²: the inverse-square
//!   law (the same power spreads over a sphere of area 4πr²) and the cosine law (a tilted
//!   receiver intercepts the beam over a larger area).
//! - Far away, the disk acts as a point light of intensity I = L π R² (E → I / h²): the
//!   point light overestimates by I/h² ÷ E − 1 = (R/h)², 4% at h = 5 R and 1% from
//!   h = 10 R on, five diameters (photometry's "five times rule": five times the
//!   source's largest dimension).
//!
//! Estimators: "light" samples points on the emitter, "bsdf" samples cosine-weighted
//! directions, "mis" combines both (example 8 compares them).
//!
//! Picture: target/examples/04_inverse_square.svg, E against h for the disk, with the
//! point-light asymptote.
//!
//! Run: `cargo run --release --example 04_irradiance -- [SAMPLES]`

use lightproof::case::Case;
use lightproof::stats::Verdict;
use lightproof::transport::Estimator;
use plotters::prelude::*;
use serde_json::json;
use std::f64::consts::PI;

/// A case file: irradiance under a uniform disk light, on its axis.
const DISK_CASE: &str = r#"{
  "name": "disk light on axis",
  "teaches": "a uniform disk of radiance L at height h gives E = π L R²/(R² + h²) on axis",
  "scene": { "shapes": [ { "geometry": { "type": "disk", "center": [0, 0, 2], "normal": [0, 0, -1], "radius": 1 },
                           "emission": { "radiance": 1 } } ] },
  "measure": { "irradiance": { "at": [0, 0, 0], "normal": [0, 0, 1] } },
  "reference": { "closed_form": "disk_irradiance_on_axis", "radius": 1, "height": 2, "radiance": 1 },
  "estimators": ["light", "bsdf", "mis"],
  "samplers": ["sobol"], "samples": 1048576
}"#;

fn main() {
    let n = samples(1 << 20);
    println!(
        "4. Irradiance E = ∫ L cos θ dω [W/m²];  point light E = I cos θ / r²;  disk on axis E = π L R²/(R² + h²)"
    );
    print_rule(&format!("{n} samples per estimate"));
    let mut ok = true;

    show_case_file("04_disk_irradiance.json", DISK_CASE);
    let disk: serde_json::Value = serde_json::from_str(DISK_CASE).unwrap();
    ok &= check_all("disk R = 1, h = 2, on axis", &load(disk), n);

    // The same disk seen by a receiver off the axis and tilted by 40° (horizon clipping
    // included in the closed form).
    let (t, s) = (40f64.to_radians().cos(), 40f64.to_radians().sin());
    let tilted = load(json!({
        "name": "disk light, tilted receiver", "teaches": "irradiance from a disk at any tilt",
        "scene": { "shapes": [ { "geometry": { "type": "disk", "center": [0, 0, 2], "normal": [0, 0, -1], "radius": 1 },
                                 "emission": { "radiance": 1, "two_sided": true } } ] },
        "measure": { "irradiance": { "at": [1.5, 0, 0], "normal": [s, 0.0, t] } },
        "reference": { "closed_form": "disk_irradiance", "point": [1.5, 0, 0], "normal": [s, 0.0, t],
                       "center": [0, 0, 2], "axis": [0, 0, -1], "radius": 1, "radiance": 1 },
        "estimators": ["light", "bsdf", "mis"]
    }));
    ok &= check_all("disk, receiver off axis tilted 40°", &tilted, n);

    // A quadrilateral light (a mesh of two triangles): Lambert's polygon formula.
    let quad = [
        [-1.0, -0.5, 1.5],
        [1.5, -1.0, 1.5],
        [1.0, 1.0, 1.5],
        [-0.5, 0.8, 1.5],
    ];
    let polygon = load(json!({
        "name": "quadrilateral light", "teaches": "E = ½ L Σ Θᵢ n·γ̂ᵢ (Lambert 1760)",
        "scene": { "shapes": [ { "geometry": { "type": "mesh", "vertices": quad, "indices": [[0, 1, 2], [0, 2, 3]] },
                                 "emission": { "radiance": 3, "two_sided": true } } ] },
        "measure": { "irradiance": { "at": [0.3, 0.2, 0], "normal": [0, 0, 1] } },
        "reference": { "closed_form": "polygon_irradiance", "point": [0.3, 0.2, 0], "normal": [0, 0, 1],
                       "vertices": quad, "radiance": 3 },
        "estimators": ["light", "bsdf", "mis"]
    }));
    ok &= check_all("quadrilateral, L = 3", &polygon, n);

    // The two laws with a point light of intensity 1 W/sr (only light sampling can
    // find a point light: it occupies no solid angle).
    println!("\nInverse-square law: point light I = 1 W/sr at distance r, receiver facing it:");
    let point_at = |light: [f64; 3], normal: [f64; 3]| {
        load(json!({
            "name": format!("point light at {light:?}"), "teaches": "E = I cos θ / r²",
            "scene": { "emitters": [ { "type": "point", "position": light, "intensity": 1 } ] },
            "measure": { "irradiance": { "at": [0, 0, 0], "normal": normal } },
            "reference": { "closed_form": "point_light_irradiance", "point": [0, 0, 0], "normal": normal,
                           "light": light, "intensity": 1 },
            "estimators": ["light"]
        }))
    };
    for r in [1.0, 2.0, 4.0] {
        let c = point_at([0.0, 0.0, r], [0.0, 0.0, 1.0]);
        ok &= check_all(&format!("r = {r}: E = I / r² = {}", 1.0 / (r * r)), &c, n);
    }
    println!("\nCosine law: the same light at r = 1, the receiver tilted by θ:");
    for deg in [0.0f64, 60.0, 85.0] {
        let th = deg.to_radians();
        let c = point_at([0.0, 0.0, 1.0], [th.sin(), 0.0, th.cos()]);
        ok &= check_all(&format!("θ = {deg}°: E = I cos θ = {:.4}", th.cos()), &c, n);
    }

    // From disk to point: the disk's irradiance on its axis against h.
    println!(
        "\nFar away a disk is a point light of intensity I = L π R² (R = 1, L = 1); I/h² is off by (R/h)², 1% from h = 10 R on:"
    );
    let mut points = Vec::new();
    for h in [0.25, 0.5, 1.0, 2.0, 5.0, 10.0, 16.0] {
        let c = load(json!({
            "name": format!("disk on axis at h = {h}"), "teaches": "E = π L R²/(R² + h²) → π L R²/h²",
            "scene": { "shapes": [ { "geometry": { "type": "disk", "center": [0, 0, h], "normal": [0, 0, -1], "radius": 1 },
                                     "emission": { "radiance": 1 } } ] },
            "measure": { "irradiance": { "at": [0, 0, 0], "normal": [0, 0, 1] } },
            "reference": { "closed_form": "disk_irradiance_on_axis", "radius": 1, "height": h, "radiance": 1 },
            "estimators": ["mis"]
        }));
        let v = estimate(&c, Estimator::Mis, n);
        let far = PI / (h * h);
        ok &= report(
            &format!(
                "h = {h:<5} I/h² = {far:<8.5} ((R/h)² = {:+.1}% off)",
                100.0 * (far / v.reference - 1.0)
            ),
            &v,
        );
        points.push((h, v.estimate));
    }
    match plot(&points) {
        Ok(p) => println!("\nwrote {p} (log–log: slope −2 is the inverse-square law)"),
        Err(e) => println!("\n(could not write the plot: {e})"),
    }
    finish(ok);
}

/// Run one estimator of a case and judge it against the case's closed form.
fn estimate(case: &Case, est: Estimator, n: u64) -> Verdict {
    judged(case, est, n, 4, case.reference.expect("a closed form"))
}

/// Run and report every estimator of a case.
fn check_all(label: &str, case: &Case, n: u64) -> bool {
    let mut ok = true;
    for &est in &case.desc.estimators {
        ok &= report(
            &format!("{label} [{}]", est.name()),
            &estimate(case, est, n),
        );
    }
    ok
}

fn plot(points: &[(f64, f64)]) -> Result<String, Box<dyn std::error::Error>> {
    common::save_svg("04_inverse_square.svg", (720, 480), |root| {
        let mut chart = common::chart(
            root,
            "Irradiance on the axis of a disk light (R = 1, L = 1)",
        )
        .build_cartesian_2d((0.2f64..20.0).log_scale(), (0.005f64..60.0).log_scale())?;
        chart
            .configure_mesh()
            .x_desc("height h (m)")
            .y_desc("irradiance E (W/m²)")
            .draw()?;
        let hs: Vec<f64> = (0..=100)
            .map(|i| 0.2 * 100f64.powf(i as f64 / 100.0))
            .collect();
        chart
            .draw_series(LineSeries::new(
                hs.iter().map(|&h| (h, PI / (1.0 + h * h))),
                &BLACK,
            ))?
            .label("π L R²/(R² + h²) (disk)")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK));
        chart
            .draw_series(LineSeries::new(
                hs.iter().map(|&h| (h, PI / (h * h))),
                &BLUE,
            ))?
            .label("I / h², I = L π R² (point light)")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLUE));
        chart
            .draw_series(points.iter().map(|&p| Circle::new(p, 4, RED.filled())))?
            .label("Monte Carlo (MIS)")
            .legend(|(x, y)| Circle::new((x + 10, y), 4, RED.filled()));
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
