//! Cost of the spectral data module: `Spectrum::eval` per variant, indices and responses,
//! `WavelengthSampler::sample` (uniform against importance), `sample_lanes` (four hero
//! wavelengths), building an importance table, and the closed-form band integrals.
//! `cargo bench --bench spectrum`.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use lightproof::sampling::Sampler;
use lightproof::spectrum::{Band, Ior, Response, Spectrum, VISIBLE, WavelengthSampler, bk7};
use std::hint::black_box;

const N: usize = 4096;

fn uniforms() -> Vec<f32> {
    let s = Sampler::independent(1);
    (0..N as u64).map(|i| s.stream(i).next_1d()).collect()
}

fn wavelengths() -> Vec<f32> {
    uniforms()
        .iter()
        .map(|u| VISIBLE.min + u * VISIBLE.width())
        .collect()
}

/// An 81-entry table over 380–780 nm (the size of a 5-nm CIE table).
fn table() -> Spectrum {
    let w: Vec<f32> = (0..81).map(|k| 380.0 + 5.0 * k as f32).collect();
    let v: Vec<f32> = w.iter().map(|l| 1.0 + ((l - 380.0) * 0.02).sin()).collect();
    Spectrum::sampled(w, v)
}

fn eval(c: &mut Criterion) {
    let l = wavelengths();
    let mut g = c.benchmark_group("spectrum_eval");
    g.throughput(Throughput::Elements(N as u64));
    macro_rules! per_lambda {
        ($name:expr, $f:expr) => {
            g.bench_function($name, |b| {
                b.iter(|| l.iter().map(|&x| $f(black_box(x))).sum::<f32>())
            });
        };
    }
    let constant = Spectrum::Constant(0.5);
    let sampled = table();
    let blackbody = Spectrum::blackbody(5800.0);
    per_lambda!("constant", |x| constant.eval(x));
    per_lambda!("sampled (81 entries)", |x| sampled.eval(x));
    per_lambda!("blackbody", |x| blackbody.eval(x));
    per_lambda!("response photopic", |x| Response::Photopic.eval(x));
    let glass = bk7();
    let cauchy = Ior::Cauchy {
        a: 1.5046,
        b: 0.0042,
        c: 0.0,
    };
    per_lambda!("ior sellmeier (N-BK7)", |x| glass.eval(x));
    per_lambda!("ior cauchy", |x| cauchy.eval(x));
    g.finish();
}

fn sample(c: &mut Criterion) {
    let u = uniforms();
    let bb = Spectrum::blackbody(5800.0);
    let uniform = WavelengthSampler::uniform(VISIBLE);
    let importance = WavelengthSampler::importance(VISIBLE, |l| bb.eval(l));
    let wide = WavelengthSampler::importance(Band::new(10.0, 1e7), |l| bb.eval(l));
    let mut g = c.benchmark_group("wavelength_sample");
    g.throughput(Throughput::Elements(N as u64));
    macro_rules! per_u {
        ($name:expr, $f:expr) => {
            g.bench_function($name, |b| {
                b.iter(|| {
                    u.iter()
                        .map(|&x| {
                            let (l, p) = $f(black_box(x));
                            l + p
                        })
                        .sum::<f32>()
                })
            });
        };
    }
    per_u!("uniform sample", |x| uniform.sample(x));
    per_u!("importance sample (blackbody, visible)", |x| importance
        .sample(x));
    per_u!("importance sample (blackbody, 10 nm-10 mm)", |x| wide
        .sample(x));
    per_u!("importance pdf", |x: f32| (
        x,
        importance.pdf(400.0 + 400.0 * x)
    ));
    per_u!("uniform sample_lanes (4 lambdas)", |x| {
        let (l, p) = uniform.sample_lanes(x);
        (l[0] + l[1] + l[2] + l[3], p[0] + p[1] + p[2] + p[3])
    });
    per_u!("importance sample_lanes (4 lambdas)", |x| {
        let (l, p) = importance.sample_lanes(x);
        (l[0] + l[1] + l[2] + l[3], p[0] + p[1] + p[2] + p[3])
    });
    g.finish();

    let mut g = c.benchmark_group("spectrum_setup");
    g.bench_function("importance table (1024 cells, blackbody)", |b| {
        b.iter(|| WavelengthSampler::importance(black_box(VISIBLE), |l| bb.eval(l)))
    });
    g.bench_function("blackbody band integral (series)", |b| {
        b.iter(|| black_box(&bb).integral(black_box(VISIBLE)))
    });
    g.bench_function("photopic band integral (erf)", |b| {
        b.iter(|| Response::Photopic.integral(black_box(VISIBLE)))
    });
    g.bench_function("ior validate (N-BK7 over visible)", |b| {
        b.iter(|| black_box(&glass_for_bench()).validate(VISIBLE))
    });
    g.finish();
}

fn glass_for_bench() -> Ior {
    bk7()
}

criterion_group!(benches, eval, sample);
criterion_main!(benches);
