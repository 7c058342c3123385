//! Throughput of every warp (samples/s) and the cost of one 1M-sample chi-square test on
//! the sphere. `cargo bench --bench sampling`.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::{Vec2, Vec3};
use lightproof::sampling::Sampler;
use lightproof::sampling::cone::Cone;
use lightproof::sampling::disk::concentric_disk;
use lightproof::sampling::distribution::Distribution2D;
use lightproof::sampling::hemisphere::{cosine_hemisphere, uniform_hemisphere};
use lightproof::sampling::sphere::{uniform_sphere, uniform_sphere_pdf};
use lightproof::sampling::sphere_cone::SphereCone;
use lightproof::sampling::spherical_rectangle::SphericalRectangle;
use lightproof::sampling::spherical_triangle::SphericalTriangle;
use lightproof::sampling::triangle::uniform_triangle;
use lightproof::stats::chi2::{Chi2Test, Domain};
use std::hint::black_box;

const N: usize = 4096;

fn uniforms() -> Vec<Vec2> {
    let s = Sampler::independent(1);
    (0..N as u64).map(|i| s.stream(i).next_2d()).collect()
}

fn warps(c: &mut Criterion) {
    let u = uniforms();
    let mut g = c.benchmark_group("warp");
    g.throughput(Throughput::Elements(N as u64));
    macro_rules! warp {
        ($name:expr, $f:expr) => {
            g.bench_function($name, |b| {
                b.iter(|| {
                    u.iter()
                        .map(|&x| $f(black_box(x)))
                        .fold(Vec3::ZERO, |a, v| a + v)
                })
            });
        };
    }
    warp!("uniform_sphere", uniform_sphere);
    warp!("uniform_hemisphere", uniform_hemisphere);
    warp!("cosine_hemisphere", cosine_hemisphere);
    let cone = Cone::from_half_angle(0.3);
    warp!("cone", |x| cone.sample(x));
    warp!("concentric_disk", |x: Vec2| concentric_disk(x).extend(0.0));
    warp!("uniform_triangle", |x: Vec2| uniform_triangle(x)
        .extend(0.0));
    let v = [
        Vec3::new(0.2, 0.1, 1.0),
        Vec3::new(1.0, -0.3, 0.2),
        Vec3::new(-0.4, 0.9, 0.5),
    ];
    warp!("spherical_triangle (setup + sample)", |x| {
        SphericalTriangle::new(Vec3::ZERO, v).unwrap().sample(x)
    });
    let r = (
        Vec3::new(-0.3, -0.8, 0.6),
        Vec3::new(1.2, 0.0, 0.0),
        Vec3::new(0.0, 0.9, 0.5),
    );
    warp!("spherical_rectangle (setup + sample)", |x| {
        SphericalRectangle::new(Vec3::ZERO, r.0, r.1, r.2)
            .unwrap()
            .sample(x)
    });
    warp!("sphere_cone (setup + sample)", |x| SphereCone::new(
        Vec3::ZERO,
        Vec3::new(0.5, -1.0, 2.0),
        1.2
    )
    .unwrap()
    .sample(Vec3::ZERO, x));
    let values: Vec<f32> = (0..256 * 128)
        .map(|i| ((i * 37 % 101) as f32).powi(2))
        .collect();
    let d = Distribution2D::new(&values, 256, 128);
    warp!("piecewise_constant_2d 256x128", |x| d
        .sample(x)
        .0
        .extend(0.0));
    g.finish();
}

fn chi2(c: &mut Criterion) {
    let mut g = c.benchmark_group("chi2");
    g.sample_size(10);
    g.bench_function("uniform_sphere 1M samples, 64x128 cells", |b| {
        b.iter(|| {
            let t = Chi2Test::new(Domain::Sphere, 1_000_000, 7, 1e-4);
            black_box(t.run(
                "bench",
                |u| Some(uniform_sphere(Vec2::new(u.x, u.y))),
                |_| uniform_sphere_pdf() as f64,
            ))
        })
    });
    g.finish();
}

criterion_group!(benches, warps, chi2);
criterion_main!(benches);
