//! # 7. The rendering equation, bounce by bounce
//!
//! Radiance leaving a surface is what it emits plus what it reflects (Kajiya 1986):
//!
//!     Lo(x, ωo) = Le(x, ωo) + ∫ f(x, ωi → ωo) Li(x, ωi) cos θi dωi,
//!
//! and the incident radiance Li is the outgoing radiance of the surface seen along ωi
//! (radiance is invariant along rays, example 5). Expanding the integral again and again
//! gives the Neumann series L = Le + T Le + T² Le + …: light that scattered 0, 1, 2, …
//! times. A path tracer estimates the series; capping its depth at k bounces keeps the
//! first k + 1 terms.
//!
//! The white furnace makes every term known: inside a closed sphere whose walls emit Le
//! and reflect diffusely with albedo ρ, each bounce multiplies by ρ, so the partial sums
//! are Le (1 − ρ^{k+1}) / (1 − ρ) and the full series converges to Le / (1 − ρ). An
//! unbounded path tracer ends paths by Russian roulette, which keeps the estimate
//! unbiased.
//!
//! Picture: target/examples/07_furnace_bounces.svg, the partial sums against k.
//!
//! Run: `cargo run --release --example 07_rendering_equation -- [SAMPLES]`

use lightproof::case::seed_for;
use lightproof::sampling::SamplerKind;
use lightproof::transport::Estimator;
use lightproof::transport::engine::RunSpec;
use lightproof_analytic::partial_shapes::closed_enclosure_bounces;
use plotters::prelude::*;

/// A case file: the radiance inside a closed emitting diffuse sphere.
const FURNACE_CASE: &str = r#"{
  "name": "closed sphere furnace, albedo 0.8",
  "teaches": "inside a closed emitting diffuse sphere every bounce adds ρ times the last: L = Le/(1 − ρ)",
  "scene": {
    "materials": { "grey": { "type": "lambertian", "albedo": 0.8 } },
    "shapes": [ { "geometry": { "type": "sphere", "center": [0, 0, 0], "radius": 1 }, "material": "grey",
                  "flip_normals": true, "emission": { "radiance": 1 } } ]
  },
  "measure": { "radiance": { "at": [0.2, -0.1, 0.3], "direction": [0.3, 0.5, -0.8] } },
  "reference": { "closed_form": "furnace_closed_enclosure", "emitted_radiance": 1, "albedo": 0.8 },
  "estimators": ["mis"],
  "samplers": ["sobol"], "samples": 1048576
}"#;

fn main() {
    let n = samples(1 << 18);
    println!(
        "7. Rendering equation Lo = Le + ∫ f Li cos θi dωi [W/(m²·sr)];  white furnace: L_k = Le (1 − ρ^(k+1)) / (1 − ρ) → Le / (1 − ρ)"
    );
    print_rule(&format!("{n} samples per estimate"));
    show_case_file("07_furnace.json", FURNACE_CASE);
    let case = load(serde_json::from_str(FURNACE_CASE).unwrap());
    let (le, rho) = (1.0f64, 0.8f64);
    let mut ok = true;
    let mut points = Vec::new();
    for k in 0..=12u32 {
        // The case's plan, with its depth capped at k bounces.
        let plan = case.plan.clone().with_max_bounces(k);
        let seed = seed_for(
            7 + k as u64,
            &case.desc.name,
            Estimator::Mis,
            SamplerKind::Independent,
        );
        let spec = RunSpec {
            samples: n,
            sampler: SamplerKind::Independent,
            seed,
        };
        let e = case.estimate_with(&plan, Estimator::Mis, &spec);
        // The partial sum from lightproof_analytic (never the example's own arithmetic).
        let exact = closed_enclosure_bounces(le, rho, k);
        let v = judge_estimate(&e, exact);
        ok &= report(
            &format!("k = {k:<2} bounces: Le (1 − ρ^{}) / (1 − ρ)", k + 1),
            &v,
        );
        points.push((k as f64, v.estimate, v.std_error));
    }
    // Unbounded, with Russian roulette: the whole series.
    let exact = case.reference.expect("the case names a closed form");
    let seed = seed_for(7, &case.desc.name, Estimator::Mis, SamplerKind::Independent);
    let e = case.estimate(
        Estimator::Mis,
        &RunSpec {
            samples: n,
            sampler: SamplerKind::Independent,
            seed,
        },
    );
    let v = judge_estimate(&e, exact);
    ok &= report("unbounded (Russian roulette): Le / (1 − ρ)", &v);

    match plot(&points, exact, le, rho, v.estimate) {
        Ok(p) => println!(
            "\nwrote {p} (each bounce adds ρ times the last; the series converges to Le/(1 − ρ))"
        ),
        Err(err) => println!("\n(could not write the plot: {err})"),
    }
    finish(ok);
}

fn plot(
    points: &[(f64, f64, f64)],
    limit: f64,
    le: f64,
    rho: f64,
    unbounded: f64,
) -> Result<String, Box<dyn std::error::Error>> {
    common::save_svg("07_furnace_bounces.svg", (720, 460), |root| {
        let k_max = points.len() as f64 - 1.0;
        let mut chart = common::chart(root, "White furnace (ρ = 0.8): radiance after k bounces")
            .build_cartesian_2d(-0.5..k_max + 0.5, 0.0..limit * 1.1)?;
        chart
            .configure_mesh()
            .x_desc("maximum number of bounces k")
            .y_desc("radiance L (W/(m²·sr))")
            .draw()?;
        chart
            .draw_series(LineSeries::new(
                (0..points.len() as u32).map(|k| (k as f64, closed_enclosure_bounces(le, rho, k))),
                &BLACK,
            ))?
            .label("Le (1 − ρ^(k+1)) / (1 − ρ)")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK));
        chart
            .draw_series(LineSeries::new([(-0.5, limit), (k_max + 0.5, limit)], BLUE))?
            .label("Le / (1 − ρ)")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLUE));
        chart
            .draw_series(
                points
                    .iter()
                    .map(|&(k, l, _)| Circle::new((k, l), 4, RED.filled())),
            )?
            .label("path tracer capped at k bounces")
            .legend(|(x, y)| Circle::new((x + 10, y), 4, RED.filled()));
        chart
            .draw_series(std::iter::once(Cross::new(
                (k_max, unbounded),
                6,
                GREEN.stroke_width(2),
            )))?
            .label("unbounded, Russian roulette")
            .legend(|(x, y)| Cross::new((x + 10, y), 5, GREEN.stroke_width(2)));
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .position(SeriesLabelPosition::LowerRight)
            .draw()?;
        Ok(())
    })
}

mod common;
#[allow(unused_imports)]
use common::*;
