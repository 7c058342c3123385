//! Engine speed: BVH build, closest-hit and shadow rays/s on a 100k-triangle mesh, and
//! path samples/s on the furnace and Cornell-like scenes of `analytic/scenes/`.
//! `cargo bench --bench engine` (use `RAYON_NUM_THREADS=2` for the 2-thread figures).
//!
//! The ray and path groups time **CPU seconds of the process** (all threads together),
//! not wall time: on a shared machine wall time measures the other users' load, while CPU
//! time per ray or per path is what the engine costs. Their `time` is CPU time per
//! iteration, their `thrpt` rays or paths per CPU second (per thread), so 1/thrpt is the
//! CPU cost of one path.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::{Vec2, Vec3};
use lightproof::case::{Case, CaseDesc};
use lightproof::sampling::sphere::uniform_sphere;
use lightproof::sampling::{Sampler, SamplerKind};
use lightproof::scene::accel::{Accel, Isa};
use lightproof::scene::shape::Primitive;
use lightproof::transport::engine::RunSpec;
use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

/// CPU time of the whole process (every thread), from `CLOCK_PROCESS_CPUTIME_ID`.
fn cpu_time() -> Duration {
    #[repr(C)]
    struct Timespec {
        sec: i64,
        nsec: i64,
    }
    unsafe extern "C" {
        fn clock_gettime(clock: i32, tp: *mut Timespec) -> i32;
    }
    /// Linux's CLOCK_PROCESS_CPUTIME_ID.
    const CLOCK_PROCESS_CPUTIME_ID: i32 = 2;
    let mut t = Timespec { sec: 0, nsec: 0 };
    // SAFETY: `t` is a valid, writable timespec for the duration of the call.
    let rc = unsafe { clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &mut t) };
    assert_eq!(rc, 0, "clock_gettime(CLOCK_PROCESS_CPUTIME_ID)");
    Duration::new(t.sec as u64, t.nsec as u32)
}

/// Criterion's `iter_custom` body timing `f` in process CPU time.
fn cpu_iters<R>(iters: u64, mut f: impl FnMut() -> R) -> Duration {
    let t0 = cpu_time();
    for _ in 0..iters {
        black_box(f());
    }
    cpu_time() - t0
}

/// A UV sphere of about 100k triangles.
fn mesh() -> Vec<Primitive> {
    let (nt, np) = (158usize, 316usize);
    let p = |i: usize, j: usize| {
        let t = std::f32::consts::PI * i as f32 / nt as f32;
        let f = 2.0 * std::f32::consts::PI * j as f32 / np as f32;
        Vec3::new(t.sin() * f.cos(), t.sin() * f.sin(), t.cos())
    };
    let mut out = Vec::new();
    for i in 0..nt {
        for j in 0..np {
            let (a, b, c, d) = (p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1));
            out.push(Primitive::Triangle { p: [a, b, c] });
            out.push(Primitive::Triangle { p: [a, c, d] });
        }
    }
    out.retain(|t| t.area() > 0.0);
    out
}

fn bvh(c: &mut Criterion) {
    let prims = mesh();
    let mut g = c.benchmark_group("bvh");
    g.sample_size(10);
    g.bench_function(format!("build {} triangles", prims.len()), |b| {
        b.iter(|| black_box(Accel::new(prims.clone())))
    });
    let accel = Accel::new(prims);
    let s = Sampler::independent(3);
    let rays: Vec<(Vec3, Vec3)> = (0..65536u64)
        .map(|i| {
            let mut st = s.stream(i);
            let o = uniform_sphere(st.next_2d()) * 3.0;
            let target = uniform_sphere(st.next_2d()) * 0.5;
            (o, (target - o).normalize())
        })
        .collect();
    g.finish();
    let batch: Vec<(Vec3, Vec3, f32, f32)> = rays
        .iter()
        .map(|&(o, d)| (o, d, 0.0, f32::INFINITY))
        .collect();
    let mut g = c.benchmark_group("rays, CPU time");
    g.sample_size(10);
    g.throughput(Throughput::Elements(rays.len() as u64));
    // Each query in both instruction sets where the CPU runs x86-64-v3 (the answers are
    // the same bit for bit: `accel::tests::both_instruction_sets_give_the_same_bits`).
    let mut accel = accel;
    for isa in [Isa::Baseline, Isa::X86_64V3] {
        if accel.set_isa(isa) != isa {
            continue;
        }
        let accel = &accel;
        let name = isa.name();
        g.bench_function(format!("closest hit, 1 thread, {name}"), |b| {
            b.iter_custom(|iters| {
                cpu_iters(iters, || {
                    rays.iter()
                        .filter(|(o, d)| accel.intersect(*o, *d, 0.0, f32::INFINITY).is_some())
                        .count()
                })
            })
        });
        g.bench_function(
            format!("closest hit, interleaved batch, 1 thread, {name}"),
            |b| {
                b.iter_custom(|iters| {
                    cpu_iters(iters, || {
                        accel
                            .intersect_batch(&batch)
                            .iter()
                            .filter(|h| h.is_some())
                            .count()
                    })
                })
            },
        );
        // Shadow segments along the same rays: of length |o| (3), reaching the target's
        // neighbourhood inside the sphere, so every one is blocked (early exit); and of
        // length |o|/2, ending outside the sphere, so nearly all are clear (a full
        // traversal that finds nothing).
        g.bench_function(format!("shadow rays (occluded), 1 thread, {name}"), |b| {
            b.iter_custom(|iters| {
                cpu_iters(iters, || {
                    rays.iter()
                        .filter(|(o, d)| accel.unoccluded(*o, *d, 0.0, o.length()))
                        .count()
                })
            })
        });
        g.bench_function(format!("shadow rays (clear), 1 thread, {name}"), |b| {
            b.iter_custom(|iters| {
                cpu_iters(iters, || {
                    rays.iter()
                        .filter(|(o, d)| accel.unoccluded(*o, *d, 0.0, 0.5 * o.length()))
                        .count()
                })
            })
        });
    }
    g.finish();
    let _ = Vec2::ZERO;
}

fn paths(c: &mut Criterion) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("analytic/scenes");
    let mut g = c.benchmark_group("path samples, CPU time");
    g.sample_size(10);
    for name in ["furnace", "cornell"] {
        let case = Case::load(&root.join(format!("{name}.json"))).expect("bench scene");
        let est = case.desc.estimators[0];
        let spec = RunSpec {
            samples: 1 << 18,
            sampler: SamplerKind::Independent,
            seed: 1,
        };
        g.throughput(Throughput::Elements(spec.total()));
        g.bench_function(name, |b| {
            b.iter_custom(|iters| cpu_iters(iters, || case.estimate(est, &spec)))
        });
    }
    g.finish();
}

/// What spectral sampling and time of flight cost per path: the Cornell-like box grey
/// (the pruned, scalar tracer), with a blackbody light over 380–780 nm (one wavelength
/// per path, four hero wavelengths), and time resolved.
fn phase(c: &mut Criterion) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("analytic/scenes");
    let text = std::fs::read_to_string(root.join("cornell.json")).expect("bench scene");
    let base: serde_json::Value = serde_json::from_str(&text).expect("scene JSON");
    let variant = |spectral: Option<serde_json::Value>, time: Option<serde_json::Value>| {
        let mut v = base.clone();
        if let Some(spectral) = spectral {
            for shape in v["scene"]["shapes"].as_array_mut().expect("shapes") {
                if let Some(e) = shape.get_mut("emission") {
                    e["spectrum"] = serde_json::json!({ "blackbody": { "temperature": 4000 } });
                }
            }
            v["spectral"] = spectral;
        }
        if let Some(t) = time {
            v["time"] = t;
        }
        let desc: CaseDesc = serde_json::from_value(v).expect("case");
        Case::from_desc(desc, &root.join("cornell.json")).expect("valid variant")
    };
    let variants = [
        ("grey", variant(None, None)),
        (
            "spectral, 1 wavelength",
            variant(
                Some(serde_json::json!({ "band": [380, 780], "hero": false })),
                None,
            ),
        ),
        (
            "spectral, 4 hero wavelengths",
            variant(
                Some(serde_json::json!({ "band": [380, 780], "hero": true })),
                None,
            ),
        ),
        (
            "time resolved",
            variant(None, Some(serde_json::json!({ "bin": [0, 1e-8] }))),
        ),
    ];
    let mut g = c.benchmark_group("phase per path");
    g.sample_size(10);
    for (name, case) in &variants {
        let est = case.desc.estimators[0];
        let spec = RunSpec {
            samples: 1 << 17,
            sampler: SamplerKind::Independent,
            seed: 1,
        };
        g.throughput(Throughput::Elements(spec.total()));
        g.bench_function(*name, |b| b.iter(|| black_box(case.estimate(est, &spec))));
    }
    g.finish();
}

criterion_group!(benches, bvh, paths, phase);
criterion_main!(benches);
