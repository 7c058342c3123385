//! BSDF throughput: `sample` (and `eval` + `pdf` at the sampled direction, as a path
//! tracer with MIS does) per built-in model, reported by criterion as elements/s
//! (= samples/s on one thread). Uniform numbers come from a fixed PCG-like hash so the
//! random-number cost is small and the same for every model.
//!
//! `chi2_1M`: one whole 1M-sample chi-square test (histogram, pdf quadrature, judge) of
//! the contract's hardest configurations (`cargo bench --bench bsdf -- chi2`). With
//! `LIGHTPROOF_BENCH_STRICT=1` the group `chi2_1M_strict` times the same tests with the
//! previous quadrature ([`Quadrature::Strict`]) in the same run, for a before/after
//! ratio on a loaded machine (it takes minutes: 10 runs of up to 20 s each).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3;
use lightproof::bsdf::contract::direction;
use lightproof::bsdf::microfacet::Distribution;
use lightproof::bsdf::*;
use lightproof::stats::chi2::{Chi2Test, Domain, Quadrature};
use std::hint::black_box;

const N: u64 = 4096;

fn uniforms(i: u64) -> Vec3 {
    let h = lightproof::sampling::sampler::mix64(i);
    let f = |s: u32| ((h >> s) & 0xff_ffff) as f32 / (1u32 << 24) as f32;
    Vec3::new(f(0), f(21), f(42))
}

fn models() -> Vec<(&'static str, Bsdf)> {
    let mut beck_c = RoughConductor::new(0.3, 0.2, 3.9);
    beck_c.distribution = Distribution::Beckmann;
    let mut beck_d = RoughDielectric::new(0.3, 1.5);
    beck_d.distribution = Distribution::Beckmann;
    vec![
        ("lambertian", Bsdf::Lambertian(Lambertian::new(0.8))),
        ("oren_nayar", Bsdf::OrenNayar(OrenNayar::new(0.8, 0.5))),
        ("conductor", Bsdf::Conductor(Conductor::new(0.2, 3.9))),
        ("dielectric", Bsdf::Dielectric(Dielectric::new(1.5))),
        (
            "rough_conductor_ggx",
            Bsdf::RoughConductor(RoughConductor::new(0.3, 0.2, 3.9)),
        ),
        ("rough_conductor_beckmann", Bsdf::RoughConductor(beck_c)),
        (
            "rough_dielectric_ggx",
            Bsdf::RoughDielectric(RoughDielectric::new(0.3, 1.5)),
        ),
        ("rough_dielectric_beckmann", Bsdf::RoughDielectric(beck_d)),
        ("plastic", Bsdf::Plastic(Plastic::new(0.5, 1.5))),
    ]
}

fn bench(c: &mut Criterion) {
    let wo = direction(0.8, 0.3);
    let mut g = c.benchmark_group("bsdf_sample");
    g.throughput(Throughput::Elements(N));
    for (name, b) in models() {
        g.bench_function(name, |bench| {
            bench.iter(|| {
                let mut acc = 0.0f32;
                for i in 0..N {
                    if let Some(s) = b.sample(black_box(wo), uniforms(i)) {
                        acc += s.weight;
                    }
                }
                black_box(acc)
            })
        });
    }
    g.finish();
    let mut g = c.benchmark_group("bsdf_sample_eval_pdf");
    g.throughput(Throughput::Elements(N));
    for (name, b) in models() {
        g.bench_function(name, |bench| {
            bench.iter(|| {
                let mut acc = 0.0f32;
                for i in 0..N {
                    if let Some(s) = b.sample(black_box(wo), uniforms(i)) {
                        acc += s.weight + b.eval(wo, s.wi) + b.pdf(wo, s.wi);
                    }
                }
                black_box(acc)
            })
        });
    }
    g.finish();
}

/// The chi-square configurations timed: (name, model, θo in degrees).
fn chi2_cases() -> Vec<(&'static str, Bsdf, f32)> {
    let mut beck_c = RoughConductor::new(0.5, 0.2, 3.9);
    beck_c.distribution = Distribution::Beckmann;
    let mut beck_d = RoughDielectric::new(0.5, 1.5);
    beck_d.distribution = Distribution::Beckmann;
    vec![
        (
            "ggx_conductor_a0.5",
            Bsdf::RoughConductor(RoughConductor::new(0.5, 0.2, 3.9)),
            60.0,
        ),
        (
            "ggx_dielectric_a0.5",
            Bsdf::RoughDielectric(RoughDielectric::new(0.5, 1.5)),
            60.0,
        ),
        (
            "beckmann_conductor_a0.5",
            Bsdf::RoughConductor(beck_c),
            60.0,
        ),
        (
            "beckmann_dielectric_a0.5",
            Bsdf::RoughDielectric(beck_d),
            60.0,
        ),
        (
            "ggx_conductor_a0.1",
            Bsdf::RoughConductor(RoughConductor::new(0.1, 0.2, 3.9)),
            30.0,
        ),
        (
            "ggx_dielectric_a0.1",
            Bsdf::RoughDielectric(RoughDielectric::new(0.1, 1.5)),
            30.0,
        ),
        (
            "ggx_dielectric_inside",
            Bsdf::RoughDielectric(RoughDielectric::new(0.5, 1.5)),
            140.0,
        ),
        (
            "ggx_dielectric_eta_below_1",
            Bsdf::RoughDielectric(RoughDielectric::new(0.5, 1.0 / 1.5)),
            50.0,
        ),
    ]
}

fn chi2_group(c: &mut Criterion, group: &str, quadrature: Quadrature) {
    let mut g = c.benchmark_group(group);
    g.sample_size(10);
    for (name, b, theta) in chi2_cases() {
        let wo = direction(theta.to_radians(), 0.3);
        g.bench_function(name, |bench| {
            bench.iter(|| {
                let t =
                    Chi2Test::new(Domain::Sphere, 1_000_000, 7, 1e-6).with_quadrature(quadrature);
                black_box(contract::chi2_bsdf_with(&t, &b, name, wo))
            })
        });
    }
    g.finish();
}

fn chi2(c: &mut Criterion) {
    chi2_group(c, "chi2_1M", Quadrature::Statistical);
    if std::env::var_os("LIGHTPROOF_BENCH_STRICT").is_some() {
        chi2_group(c, "chi2_1M_strict", Quadrature::Strict);
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).measurement_time(std::time::Duration::from_secs(1)).warm_up_time(std::time::Duration::from_millis(300));
    targets = bench
}
criterion_group! {
    name = chi2_benches;
    config = Criterion::default().measurement_time(std::time::Duration::from_secs(2)).warm_up_time(std::time::Duration::from_millis(100));
    targets = chi2
}
criterion_main!(benches, chi2_benches);
