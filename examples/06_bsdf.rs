//! # 6. The BSDF: f = dLo / dE
//!
//! A surface answers light with a BSDF f(ωi → ωo), in 1/sr: the radiance it sends
//! towards ωo per unit of irradiance arriving from ωi, f = dLo(ωo) / dE(ωi) with
//! dE = Li cos θi dωi. Summed over every incoming direction this is the reflection
//! integral Lo(ωo) = ∫ f(ωi → ωo) Li(ωi) cos θi dωi.
//!
//! A physically plausible BSDF obeys two laws, checked here numerically for a diffuse
//! (Lambertian, f = ρ/π) and a rough conductor (Cook–Torrance microfacet) model:
//!
//! - Helmholtz reciprocity: f(ωi → ωo) = f(ωo → ωi), light paths can be reversed;
//! - energy conservation: the directional albedo a(ωo) = ∫ f cos θi dωi ≤ 1, a surface
//!   cannot reflect more than it receives (checked one-sided, the rows marked `bound`).
//!   For the Lambertian model a = ρ exactly; a single-scattering microfacet model loses
//!   the light that would scatter between microfacets, more so the rougher it is.
//!
//! Both are laws of reflection. A BSDF that transmits into a medium of another index
//! (a rough dielectric, last) is not symmetric: radiance crossing into the denser side is
//! compressed into a narrower cone and grows by (η_o/η_i)² (basic radiance L/η² is what
//! stays constant), so reciprocity reads f(ωi → ωo)/η_o² = f(ωo → ωi)/η_i², η the index
//! on each direction's side (Veach 1997, eq. 5.14). The albedo a(ωo) of a direction
//! inside the glass can then exceed 1 without creating energy: the bound holds for the
//! power scattered from one incident beam, ∫ f(ωi → ωo) |cos θo| dωo ≤ 1.
//!
//! A bound alone would pass an engine that lost half the energy, so each albedo is also
//! checked two-sided against `lightproof_analytic`: ρ for the Lambertian, the
//! Cook–Torrance integral ∫ F D G2/(4 cos θo) dωi by quadrature over half vectors for
//! the rough conductor (Walter et al. 2007), and for the white (F ≡ 1) GGX mirror at
//! α = 1 the closed form 1 − ln 2 ≈ 0.307 at normal incidence (the quadrature at 60°).
//!
//! Picture: target/examples/06_albedo.svg, the directional albedo a(θo) of each model
//! from normal incidence to grazing (BSDF-sampled estimates, ±2 standard errors): the
//! Lambertian flat at ρ, every curve under the line a = 1, and the white GGX mirror at
//! α = 1 keeping only 1 − ln 2 at normal incidence: what a single-scattering microfacet
//! model loses is the light that would bounce between microfacets, which depends on the
//! angle.
//!
//! Run: `cargo run --release --example 06_bsdf -- [SAMPLES]`

use glam::Vec3;
use lightproof::bsdf::contract::check_reciprocity;
use lightproof::bsdf::{Bsdf, BsdfModel, ModelFacts};
use lightproof::case::{Case, seed_for};
use lightproof::sampling::Sampler;
use lightproof::sampling::SamplerKind;
use lightproof::sampling::sphere::uniform_sphere;
use lightproof::stats::Verdict;
use lightproof::transport::Estimator;
use lightproof::transport::engine::RunSpec;
use lightproof_analytic::fresnel;
use lightproof_analytic::irradiance::disk_on_axis;
use lightproof_analytic::microfacet::{self as mf, Distribution, Masking};
use plotters::prelude::*;
use serde_json::json;
use std::f64::consts::PI;

const LAMBERTIAN: &str = r#"{ "type": "lambertian", "albedo": 0.6 }"#;
const ROUGH_CONDUCTOR: &str =
    r#"{ "type": "rough_conductor", "alpha": 0.3, "eta": 0.2, "k": 3.9 }"#;
/// A rough conductor with Fresnel reflectance F ≡ 1 and the largest roughness: what it
/// loses is the light that would have bounced between microfacets.
const WHITE_ROUGH_CONDUCTOR: &str =
    r#"{ "type": "rough_conductor", "alpha": 1.0, "fresnel": "none" }"#;
/// A rough glass surface (GGX, α = 0.3, η = 1.5 below the surface): reflection and
/// transmission, reciprocal with the η² rule.
const ROUGH_DIELECTRIC: &str = r#"{ "type": "rough_dielectric", "alpha": 0.3, "eta": 1.5 }"#;

/// The directional albedo a(θo) of a model from `lightproof_analytic` (never the
/// engine), with the formula it evaluates (its name in the verdict lines is the text
/// before the colon).
fn albedo_exact(json: &str, theta_degrees: f64) -> (f64, &'static str) {
    let c = theta_degrees.to_radians().cos();
    let (ggx, hc) = (Distribution::Ggx, Masking::HeightCorrelated);
    match json {
        LAMBERTIAN => (0.6, "ρ: the Lambertian albedo"),
        // Walter et al. 2007 eq. 20, by quadrature over half vectors.
        ROUGH_CONDUCTOR => (
            mf::albedo_with_fresnel(ggx, hc, 0.3, c, |x| fresnel::conductor(x, 0.2, 3.9)),
            "a_CT: the Cook–Torrance albedo ∫ F D G2 /(4 cos θo) dωi, GGX, height-correlated G2, conductor F (lightproof_analytic::microfacet::albedo_with_fresnel, quadrature over half vectors)",
        ),
        // At normal incidence the closed form of the module doc of
        // lightproof_analytic::microfacet; elsewhere its quadrature.
        WHITE_ROUGH_CONDUCTOR if theta_degrees == 0.0 => (
            mf::ggx_white_albedo_normal_alpha1(),
            "1 − ln 2: the closed form of ∫ D G2 /(4 cos θo) dωi for GGX at α = 1, θo = 0 (lightproof_analytic::microfacet::ggx_white_albedo_normal_alpha1)",
        ),
        WHITE_ROUGH_CONDUCTOR => (
            mf::white_albedo(ggx, hc, 1.0, c),
            "a_white: ∫ D G2 /(4 cos θo) dωi, GGX, height-correlated G2, F ≡ 1 (lightproof_analytic::microfacet::white_albedo, quadrature over half vectors)",
        ),
        other => panic!("no closed form for {other}"),
    }
}

/// The BSDF-sampled albedo estimates draw this many times the example's count: they
/// trace no scene, and at 2²² samples each two-sided albedo check sees a 0.5% bias. The
/// uniform-direction ones, a cross-check, draw the example's count and print weak.
const ALBEDO_SAMPLES: u64 = 8;

fn main() {
    let n = samples(1 << 19);
    println!(
        "6. BSDF f(ωi → ωo) = dLo(ωo) / dE(ωi) [1/sr];  Lo = ∫ f Li cos θi dωi;  reciprocity f(ωi→ωo) = f(ωo→ωi) (transmission: f(ωi→ωo)/ηo² = f(ωo→ωi)/ηi²);  albedo ∫ f cos θi dωi ≤ 1"
    );
    print_rule(&format!(
        "{n} samples per estimate, {} per BSDF-sampled albedo (cheap: no scene)",
        ALBEDO_SAMPLES * n
    ));
    let mut ok = true;

    // f = dLo/dE: a large grey floor lit by a small disk light straight above the
    // origin, seen from an eye looking at the origin at 45°.
    println!(
        "f = Lo / E: a floor of {LAMBERTIAN}, a disk light (R = 0.25, L = 10) 2 m above, an eye at 45°"
    );
    let (r, h, l) = (0.25, 2.0, 10.0);
    let floor = |material: &str| {
        json!({
            "materials": { "floor": serde_json::from_str::<serde_json::Value>(material).unwrap() },
            "shapes": [
                { "geometry": { "type": "disk", "center": [0, 0, 0], "normal": [0, 0, 1], "radius": 20 }, "material": "floor" },
                { "geometry": { "type": "disk", "center": [0, 0, h], "normal": [0, 0, -1], "radius": r }, "emission": { "radiance": l } }
            ]
        })
    };
    let e_exact = disk_on_axis(r, h, l);
    let c = load(json!({
        "name": "irradiance on the floor", "teaches": "E = π L R²/(R² + h²)", "scene": floor(LAMBERTIAN),
        "measure": { "irradiance": { "at": [0, 0, 0], "normal": [0, 0, 1] } }, "estimators": ["light"]
    }));
    let e = estimate(&c, Estimator::Light, n, e_exact);
    ok &= report("irradiance E at the origin", &e);
    let c = load(json!({
        "name": "radiance of the floor", "teaches": "Lo = f E for a small light", "scene": floor(LAMBERTIAN),
        "measure": { "radiance": { "at": [0, -1, 1], "direction": [0, 1, -1] } }, "estimators": ["light", "mis"]
    }));
    let rho = 0.6;
    for &est in &c.desc.estimators {
        let v = estimate(&c, est, n, rho / PI * e_exact);
        ok &= report(
            &format!("radiance Lo towards the eye vs (ρ/π) E [{}]", est.name()),
            &v,
        );
    }
    let lo = estimate(&c, Estimator::Mis, n, rho / PI * e_exact).estimate;
    println!(
        "  {:<50} {:>12.6}  (ρ/π = {:.6}: f = dLo/dE)",
        "Lo / E",
        lo / e.estimate,
        rho / PI
    );

    // For a glossy surface Lo / E depends on both directions: it is f(ωi → ωo) itself,
    // blurred over the light's small solid angle (here about 0.05 sr).
    let c = load(json!({
        "name": "radiance of a rough conductor floor", "teaches": "Lo ≈ f E for a small light",
        "scene": floor(ROUGH_CONDUCTOR), "measure": { "radiance": { "at": [0, -1, 1], "direction": [0, 1, -1] } },
        "estimators": ["mis"]
    }));
    let glossy = Bsdf::from_json(ROUGH_CONDUCTOR).unwrap();
    let wo = Vec3::new(0.0, -1.0, 1.0).normalize();
    let f = glossy.eval(wo, Vec3::Z) as f64;
    let lo = estimate(&c, Estimator::Mis, n, f * e_exact).estimate;
    println!(
        "  {:<50} {:>12.6}  (≈ f(ωi = up → ωo = eye) = {f:.6}, blurred over the light; no verdict)",
        "rough conductor floor: Lo / E",
        lo / e.estimate
    );

    let models = [
        ("Lambertian", LAMBERTIAN),
        ("rough conductor", ROUGH_CONDUCTOR),
        ("white rough conductor", WHITE_ROUGH_CONDUCTOR),
    ];
    for (name, json) in models {
        let bsdf = Bsdf::from_json(json).unwrap();
        println!("\n{name} {json}:");
        // Reciprocity: evaluate both ways for a few direction pairs, then check many.
        let sampler = Sampler::independent(6);
        for i in 0..3 {
            let mut s = sampler.stream(i);
            let mut a = uniform_sphere(s.next_2d());
            let mut b = uniform_sphere(s.next_2d());
            a.z = a.z.abs();
            b.z = b.z.abs();
            println!(
                "  f(a → b) = {:<10.6} f(b → a) = {:<10.6} (a = ({:+.2}, {:+.2}, {:.2}), b = ({:+.2}, {:+.2}, {:.2}))",
                bsdf.eval(b, a),
                bsdf.eval(a, b),
                a.x,
                a.y,
                a.z,
                b.x,
                b.y,
                b.z
            );
        }
        let rec = check_reciprocity(&bsdf, bsdf.eta_inside(), (n / 8).max(1000), 6);
        println!(
            "  {:<50} {} pairs compared, worst error / tolerance = {:.3}  verdict {}",
            "reciprocity f(ωi→ωo) = f(ωo→ωi)",
            rec.compared,
            rec.worst,
            if rec.passed { "PASS" } else { "FAIL" }
        );
        if let Some(why) = &rec.first_failure {
            println!("      ({why})");
        }
        ok &= rec.passed;

        // Energy: the directional albedo, by BSDF sampling and by uniform directions.
        for theta in [0.0f64, 60.0] {
            println!(
                "  exact albedo at θo = {theta}°: {}",
                albedo_exact(json, theta).1.replacen(':', " =", 1)
            );
            let c = load(json!({
                "name": format!("{name} albedo at {theta}"), "teaches": "a(ωo) = ∫ f cos θi dωi ≤ 1",
                "measure": { "albedo": { "bsdf": serde_json::from_str::<serde_json::Value>(json).unwrap(), "theta_degrees": theta } },
                "estimators": ["bsdf", "uniform"]
            }));
            for &est in &c.desc.estimators {
                let seed = seed_for(6, &c.desc.name, est, SamplerKind::Independent);
                let e = c.estimate(
                    est,
                    &RunSpec {
                        samples: if est == Estimator::Bsdf {
                            ALBEDO_SAMPLES * n
                        } else {
                            n
                        },
                        sampler: SamplerKind::Independent,
                        seed,
                    },
                );
                // Two-sided against the albedo of lightproof_analytic: an engine losing
                // (or gaining) energy fails here, not only one reflecting more than 1.
                let (exact, formula) = albedo_exact(json, theta);
                let short = formula.split(':').next().unwrap_or(formula);
                let v = judge_estimate(&e, exact);
                ok &= report(
                    &format!("albedo a(θo = {theta}°) = {short} [{}]", est.name()),
                    &v,
                );
                if v.std_error == 0.0 {
                    // Every BSDF-sampled weight f cos θi / p was the same number: the
                    // sampling is this model's exact importance sampling (cosine
                    // sampling for the Lambertian, whose weight is ρ by construction),
                    // so the row checks the sample's weight, not f itself; the
                    // [uniform] rows check f against the albedo.
                    println!(
                        "      (every sample's weight f cos θi / p was the same: a zero-variance sampler checks its weight, the [uniform] rows check f)"
                    );
                }
                // The law itself, one-sided: fail only if significantly above 1 (for
                // every model; the Lambertian's albedo ρ ≤ 1 is also refused at load
                // above 1, so its rows check that what `eval` and `sample` make of ρ
                // keeps the bound).
                let v = judge_bound(&e.batches.total, 1.0);
                ok &= report_bound(&format!("albedo a(θo = {theta}°) ≤ 1 [{}]", est.name()), &v);
            }
        }
    }
    ok &= transmission(n);
    // The picture: a(θo) of each model from normal incidence to grazing.
    let curves: Vec<Curve> = models
        .iter()
        .map(|&(name, json)| (name, albedo_curve(name, json, (n / 8).max(4096))))
        .collect();
    match plot(&curves) {
        Ok(path) => println!("\nwrote {path} (the directional albedo of each model against θo)"),
        Err(e) => println!("\n(could not write the plot: {e})"),
    }
    finish(ok);
}

/// Reciprocity of a transmitting BSDF: f(ωi → ωo)/η_o² = f(ωo → ωi)/η_i². One pair
/// shown (straight through a facet facing the normal: ωo 30° above in air, ωi 19.47° below
/// in the glass, sin θ = sin 30°/1.5), where f itself differs by η² = 2.25 between the two
/// ways, then many pairs checked by `lightproof::bsdf::contract::check_reciprocity`.
fn transmission(n: u64) -> bool {
    let bsdf = Bsdf::from_json(ROUGH_DIELECTRIC).unwrap();
    let eta = bsdf.eta_inside();
    println!(
        "\nrough dielectric {ROUGH_DIELECTRIC} (transmits: reciprocity with the η² rule, η = {eta} below the surface, 1 above):"
    );
    let (s, c) = (0.5f32, 0.75f32.sqrt());
    let wo = Vec3::new(s, 0.0, c);
    let st = s / eta;
    let wi = Vec3::new(-st, 0.0, -(1.0 - st * st).sqrt());
    // eval(wo, wi) is f(wi → wo): light from wi (in the glass) leaving towards wo (in air).
    let (into_air, into_glass) = (bsdf.eval(wo, wi), bsdf.eval(wi, wo));
    println!(
        "  f(ωi → ωo) = {into_air:<10.6} f(ωo → ωi) = {into_glass:<10.6} ratio {:.4} = η² (ωo = ({:+.3}, 0, {:.3}) in air, ωi = ({:+.3}, 0, {:.3}) in the glass)",
        into_glass / into_air,
        wo.x,
        wo.z,
        wi.x,
        wi.z
    );
    println!(
        "  f(ωi → ωo)/ηo² = {:<10.6} f(ωo → ωi)/ηi² = {:.6}",
        into_air,
        into_glass / (eta * eta)
    );
    let rec = check_reciprocity(&bsdf, eta, (n / 8).max(1000), 6);
    println!(
        "  {:<50} {} pairs compared, worst error / tolerance = {:.3}  verdict {}",
        "reciprocity f(ωi→ωo)/ηo² = f(ωo→ωi)/ηi²",
        rec.compared,
        rec.worst,
        if rec.passed { "PASS" } else { "FAIL" }
    );
    if let Some(why) = &rec.first_failure {
        println!("      ({why})");
    }
    rec.passed
}

/// A model's name and its albedo (θo in degrees, estimate, standard error).
type Curve = (&'static str, Vec<(f64, f64, f64)>);

/// The directional albedo a(θo) = ∫ f cos θi dωi at θo = 0°, 10°, …, 80°, 85°, 89°, by
/// BSDF sampling with `n` samples each.
fn albedo_curve(name: &str, json: &str, n: u64) -> Vec<(f64, f64, f64)> {
    let angles = [
        0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0, 85.0, 89.0,
    ];
    angles
        .iter()
        .map(|&theta: &f64| {
            let c = load(json!({
                "name": format!("{name} albedo curve at {theta}"), "teaches": "a(ωo) = ∫ f cos θi dωi ≤ 1",
                "measure": { "albedo": { "bsdf": serde_json::from_str::<serde_json::Value>(json).unwrap(), "theta_degrees": theta } },
                "estimators": ["bsdf"]
            }));
            let spec = RunSpec {
                samples: n,
                sampler: SamplerKind::Independent,
                seed: seed_for(66, &c.desc.name, Estimator::Bsdf, SamplerKind::Independent),
            };
            let t = c.estimate(Estimator::Bsdf, &spec).batches.total;
            (theta, t.mean, t.std_error())
        })
        .collect()
}

fn plot(curves: &[Curve]) -> Result<String, Box<dyn std::error::Error>> {
    common::save_svg("06_albedo.svg", (720, 480), |root| {
        let mut chart = common::chart(root, "Directional albedo a(θo) = ∫ f cos θi dωi ≤ 1")
            .build_cartesian_2d(0f64..90.0, 0f64..1.1)?;
        chart
            .configure_mesh()
            .x_desc("outgoing angle θo (degrees)")
            .y_desc("albedo a(θo)")
            .draw()?;
        chart
            .draw_series(LineSeries::new(
                [(0.0, 1.0), (90.0, 1.0)],
                BLACK.stroke_width(1),
            ))?
            .label("a = 1: energy conservation")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK));
        for (i, (name, pts)) in curves.iter().enumerate() {
            let colour = Palette99::pick(i).to_rgba();
            chart
                .draw_series(LineSeries::new(
                    pts.iter().map(|p| (p.0, p.1)),
                    colour.stroke_width(2),
                ))?
                .label(*name)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
                });
            chart.draw_series(pts.iter().map(|&(t, a, se)| {
                PathElement::new(vec![(t, a - 2.0 * se), (t, a + 2.0 * se)], colour)
            }))?;
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::LowerLeft)
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()?;
        Ok(())
    })
}

/// Run one estimator of a case and judge it against `exact`.
fn estimate(case: &Case, est: Estimator, n: u64, exact: f64) -> Verdict {
    judged(case, est, n, 6, exact)
}

mod common;
#[allow(unused_imports)]
use common::*;
