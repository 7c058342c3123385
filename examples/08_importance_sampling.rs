//! # 8. Importance sampling and multiple importance sampling
//!
//! A Monte Carlo estimator draws x with density p and averages f(x)/p(x); it is unbiased
//! for any p that is positive where f is, but its variance V = ∫ f²/p − F² depends on how
//! well p follows f. What matters in practice is the efficiency 1/(V · t): how much
//! error is left after a given time t per sample.
//!
//! The irradiance E = ∫ L cos θ dω under a disk light, sampled four ways:
//!
//! - uniform: directions uniform on the hemisphere, p = 1/(2π);
//! - cosine ("bsdf"): directions with p = cos θ / π, follows the cosine but not the light;
//! - emitter ("light"): points on the disk, p_ω = r² / (cos θl A), follows the light;
//! - MIS: one of each, weighted by the power (or balance) heuristic (Veach & Guibas 1995).
//!
//! Small lights favour emitter sampling, large ones cosine sampling (a disk filling the
//! sky is best found by sampling the cosine; area sampling wastes samples at its far,
//! grazing rim). MIS keeps a robust middle, and how close it stays to the better of the
//! two is Veach's bound for the balance heuristic (Veach 1997, Theorem 9.2): with nᵢ
//! samples from strategy i, V[F_balance] ≤ V[F] + (1/minᵢ nᵢ − 1/Σᵢ nᵢ) μ² for *any*
//! other weighting F of the same samples, using the better strategy alone included. With
//! one sample of each that is V ≤ V_best + μ²/2: a relative variance V/μ² at most the
//! better strategy's + 1/2, checked here. The bound adds, it does not multiply: where the
//! better strategy is nearly exact the balance heuristic can be hundreds of times worse
//! and still within it (R = 0.1: about 10⁻² against emitter sampling's 3·10⁻⁵).
//!
//! Picture: target/examples/08_efficiency.svg, the efficiency of each estimator against
//! the light's radius.
//!
//! Run: `cargo run --release --example 08_importance_sampling -- [SAMPLES]`

use lightproof::case::seed_for;
use lightproof::sampling::SamplerKind;
use lightproof::transport::Estimator;
use lightproof::transport::engine::RunSpec;
use plotters::prelude::*;
use serde_json::json;

const ESTIMATORS: [Estimator; 5] = [
    Estimator::Uniform,
    Estimator::Bsdf,
    Estimator::Light,
    Estimator::Mis,
    Estimator::MisBalance,
];
const RADII: [f64; 5] = [0.1, 0.3, 1.0, 3.0, 10.0];

fn main() {
    let n = samples(1 << 19);
    println!(
        "8. Importance sampling: E = ∫ L cos θ dω ≈ (1/N) Σ L cos θ / p(ω);  variance V = ∫ (L cos θ)²/p dω − E²;  efficiency = 1 / (V t)"
    );
    println!(
        "   disk light, radiance 1, at height 1 above the receiver; exact E = π L R² / (R² + h²)"
    );
    print_rule(&format!("{n} samples per estimate"));
    let mut ok = true;
    let mut rows = Vec::new();
    for r in RADII {
        let case = load(json!({
            "name": format!("disk light of radius {r}"),
            "teaches": "importance sampling: the estimator whose density follows the integrand wins",
            "scene": { "shapes": [ { "geometry": { "type": "disk", "center": [0, 0, 1], "normal": [0, 0, -1], "radius": r },
                                     "emission": { "radiance": 1 } } ] },
            "measure": { "irradiance": { "at": [0, 0, 0], "normal": [0, 0, 1] } },
            "reference": { "closed_form": "disk_irradiance_on_axis", "radius": r, "height": 1, "radiance": 1 },
            "estimators": ESTIMATORS.iter().map(|e| e.name()).collect::<Vec<_>>()
        }));
        let exact = case.reference.expect("a closed form");
        println!(
            "disk radius R = {r} (σ = {:.4} sr):",
            2.0 * std::f64::consts::PI * (1.0 - 1.0 / (1.0 + r * r).sqrt())
        );
        for est in ESTIMATORS {
            let seed = seed_for(8, &case.desc.name, est, SamplerKind::Independent);
            let e = case.estimate(
                est,
                &RunSpec {
                    samples: n,
                    sampler: SamplerKind::Independent,
                    seed,
                },
            );
            let v = judge_estimate(&e, exact);
            ok &= report(&format!("  [{}]", est_label(est)), &v);
            let count = e.batches.total.count.max(1) as f64;
            let rel_var = e.batches.total.variance() / (exact * exact);
            let (se, batches) = variance_std_error(&e);
            let rel_var_se = se / (exact * exact);
            let ns_per_sample = e.seconds / count * 1e9;
            rows.push(Row {
                radius: r,
                est,
                rel_var,
                rel_var_se,
                batches,
                ns_per_sample,
                efficiency: 1.0 / (rel_var * ns_per_sample * 1e-9),
            });
        }
    }

    println!(
        "\n{:<8} {:<14} {:>16} {:>14} {:>18}",
        "radius", "estimator", "rel. variance", "ns / sample", "efficiency (1/s)"
    );
    for row in &rows {
        println!(
            "{:<8} {:<14} {:>16.4e} {:>14.1} {:>18.4e}{}",
            row.radius,
            est_label(row.est),
            row.rel_var,
            row.ns_per_sample,
            row.efficiency,
            if best(&rows, row) { "  ← best" } else { "" }
        );
    }
    println!(
        "(relative variance V/E² per sample; efficiency 1/(V/E² · t): samples-per-second worth of a zero-variance estimator."
    );
    println!(
        " Times are wall-clock over all threads and noisy at small sample counts; the variances are not.)"
    );
    // Which strategy wins, by the variances (the times are too noisy to decide): emitter
    // sampling on the small lights (R ≤ 1), cosine sampling on the large ones (R ≥ 3); and
    // Veach's bound for the balance heuristic with one sample of each strategy (Veach 1997,
    // Theorem 9.2): V ≤ V_any + (1/min nᵢ − 1/Σ nᵢ) μ² = V_any + μ²/2, V_any the variance
    // of any other weighting of the same two samples (the better strategy alone is one),
    // i.e. a relative variance at most the better strategy's + 1/2. An additive bound, not
    // a factor: at R = 0.1 about 10⁻² against emitter sampling's 3·10⁻⁵ (the cosine
    // strategy's rare hits on the light each carry a full share).
    //
    // Both are one-sided t tests on the variances, each at α = ALPHA: the estimators draw
    // independent samples, and each variance's standard error comes from the spread of its
    // batches' own variances (batch means, as the estimates' errors do). A win must be
    // shown (t = (V_loser − V_winner)/s above the critical value), a breach of the bound
    // must be shown to fail (t = (V_balance − V_better − 1/2)/s above it); Student's t
    // with the batches' degrees of freedom, as the estimates' batch means are judged.
    // Student's t with the batches' degrees of freedom (all runs have the same count).
    let batches = rows.iter().map(|r| r.batches).min().unwrap_or(0);
    let critical = one_sided_critical(batches.saturating_sub(1));
    println!(
        "
checks (relative variances V/E² ± their standard errors, one-sided t tests at α = {ALPHA:e} each, {batches} batches, critical t = {critical:.2}):
emitter < cosine for R ≤ 1, cosine < emitter for R ≥ 3 (the win shown: t ≥ {critical:.2}), and Veach's bound for the
balance heuristic (Theorem 9.2, one sample of each strategy): MIS balance ≤ min(emitter, cosine) + 1/2, an additive
bound, not a factor of the better one (failed only where a breach is shown: t > {critical:.2}):"
    );
    for r in RADII {
        let var = |e: Estimator| {
            rows.iter()
                .find(|row| row.radius == r && row.est == e)
                .map_or((f64::NAN, f64::NAN), |row| (row.rel_var, row.rel_var_se))
        };
        let (light, cosine, balance) = (
            var(Estimator::Light),
            var(Estimator::Bsdf),
            var(Estimator::MisBalance),
        );
        let (winner, loser) = if r <= 1.0 {
            (light, cosine)
        } else {
            (cosine, light)
        };
        let z_win = (loser.0 - winner.0) / winner.1.hypot(loser.1);
        let winner_ok = z_win >= critical;
        let better = if light.0 <= cosine.0 { light } else { cosine };
        let z_bound = (balance.0 - better.0 - 0.5) / balance.1.hypot(better.1);
        let veach_ok = z_bound <= critical;
        println!(
            "  R = {r:<4}: emitter {}, cosine {}: {} wins, t = {z_win:.1}: {}; MIS balance {} ({}× the better) ≤ {:.3e} + 0.5, t = {z_bound:.0}: {}",
            with_error(light),
            with_error(cosine),
            if r <= 1.0 { "emitter" } else { "cosine" },
            if winner_ok { "ok" } else { "FAILED" },
            with_error(balance),
            if balance.0 / better.0 >= 10.0 {
                format!("{:.0}", balance.0 / better.0)
            } else {
                format!("{:.2}", balance.0 / better.0)
            },
            better.0,
            if veach_ok { "ok" } else { "FAILED" }
        );
        ok &= winner_ok && veach_ok;
    }
    match plot(&rows) {
        Ok(p) => println!("\nwrote {p}"),
        Err(err) => println!("\n(could not write the plot: {err})"),
    }
    finish(ok);
}

struct Row {
    radius: f64,
    est: Estimator,
    rel_var: f64,
    /// The standard error of `rel_var` ([`variance_std_error`]).
    rel_var_se: f64,
    /// The number of batches `rel_var_se` comes from.
    batches: usize,
    ns_per_sample: f64,
    efficiency: f64,
}

/// The standard error of an estimate's per-sample variance, by batch means: each batch's
/// sample variance is an unbiased estimate of the same V, so the standard error of their
/// mean, √(Var[batch variances]/B), is that of V's estimate (a heavy tail shows as a
/// large spread among the batches), with the number of batches it comes from. The whole
/// run's variance adds the spread of the batch means to that mean, a small fraction of
/// its standard error for batches of one size.
fn variance_std_error(e: &lightproof::transport::engine::Estimate) -> (f64, usize) {
    let mut of_variances = lightproof::stats::Accumulator::new();
    for b in e.batches.batches.iter().filter(|b| b.count > 1) {
        of_variances.push(b.variance());
    }
    (of_variances.std_error(), of_variances.count as usize)
}

/// The critical value of a one-sided t test at [`ALPHA`] with `dof` degrees of freedom
/// (3.83 for the 128 batches' 127, tending to the normal's 3.72); ∞ without a batch.
fn one_sided_critical(dof: usize) -> f64 {
    use statrs::distribution::{ContinuousCDF, StudentsT};
    StudentsT::new(0.0, 1.0, dof as f64).map_or(f64::INFINITY, |t| t.inverse_cdf(1.0 - ALPHA))
}

/// A relative variance and its standard error.
fn with_error((v, se): (f64, f64)) -> String {
    format!("{v:.3e} ± {se:.1e}")
}

/// Whether `row` has the highest efficiency for its radius.
fn best(rows: &[Row], row: &Row) -> bool {
    rows.iter()
        .filter(|r| r.radius == row.radius)
        .all(|r| r.efficiency <= row.efficiency)
}

fn est_label(e: Estimator) -> &'static str {
    match e {
        Estimator::Uniform => "uniform",
        Estimator::Bsdf => "cosine",
        Estimator::Light => "emitter",
        Estimator::Mis => "MIS power",
        Estimator::MisBalance => "MIS balance",
        // Not among this example's ESTIMATORS: area sampling of the emitter is "light".
        e @ (Estimator::Cosine | Estimator::Area) => e.name(),
    }
}

fn plot(rows: &[Row]) -> Result<String, Box<dyn std::error::Error>> {
    common::save_svg("08_efficiency.svg", (760, 500), |root| {
        let finite = || {
            rows.iter()
                .map(|r| r.efficiency)
                .filter(|e| e.is_finite() && *e > 0.0)
        };
        let lo = finite().fold(f64::INFINITY, f64::min) / 3.0;
        let hi = finite().fold(0.0, f64::max) * 3.0;
        let (lo, hi) = if lo < hi { (lo, hi) } else { (1.0, 10.0) };
        let mut chart = common::chart(
            root,
            "Irradiance under a disk light: efficiency of each estimator",
        )
        .y_label_area_size(70)
        .build_cartesian_2d((0.07f64..14.0).log_scale(), (lo..hi).log_scale())?;
        chart
            .configure_mesh()
            .x_desc("disk radius R (height 1)")
            .y_desc("efficiency 1/(V/E² · t) (1/s)")
            .y_label_formatter(&|y| format!("{y:.0e}"))
            .draw()?;
        let colours = [RGBColor(150, 150, 150), BLUE, RED, GREEN, MAGENTA];
        for (est, colour) in ESTIMATORS.iter().zip(colours) {
            let pts: Vec<(f64, f64)> = rows
                .iter()
                .filter(|r| r.est == *est && r.efficiency.is_finite())
                .map(|r| (r.radius, r.efficiency))
                .collect();
            chart
                .draw_series(LineSeries::new(pts.iter().copied(), colour.stroke_width(2)))?
                .label(est_label(*est))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
                });
            chart.draw_series(pts.iter().map(|&p| Circle::new(p, 3, colour.filled())))?;
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()?;
        Ok(())
    })
}

mod common;
#[allow(unused_imports)]
use common::*;
