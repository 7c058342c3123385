//! BSDF throughput: `sample` (and `eval` + `pdf` at the sampled direction, as a path
//! tracer with MIS does) per built-in model, reported by criterion as elements/s
//! (= samples/s on one thread). Uniform numbers come from a fixed PCG-like hash so the
//! random-number cost is small and the same for every model.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3;
use lightproof::bsdf::contract::direction;
use lightproof::bsdf::microfacet::Distribution;
use lightproof::bsdf::*;
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

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).measurement_time(std::time::Duration::from_secs(1)).warm_up_time(std::time::Duration::from_millis(300));
    targets = bench
}
criterion_main!(benches);
