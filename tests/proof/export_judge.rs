//! Judging a renderer: `export` → a renderer → `judge`. Without a peer, the renderer is
//! lightproof's own `render` (driven by the exported `render_all.sh`): closed furnaces
//! pass, a wrong reference fails, bad renders exit 2 naming the file, non-finite pixels
//! fail the verdict. Flux and view-factor cases export as a meter on the receiver
//! measuring its mean irradiance: renders made by an independent renderer here (the
//! oracle's point irradiance at random receiver points) pass at the exported scale, and
//! a 4% error fails. With `LIGHTPROOF_MITSUBA=python3` (a Python with `mitsuba`
//! installed), Mitsuba 3 renders the analytic-sphere furnace and a triangle-mesh sphere
//! furnace: the first's known excess radiance must be detected, the second must pass;
//! and it renders three flux cases, which must pass.

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_lightproof"))
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("lightproof-export-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// `lightproof export --all --to TO --out OUT CASES`, which must succeed: its output.
#[track_caller]
fn export_all(to: &str, cases: &Path, out: &Path) -> Output {
    let o = bin()
        .args(["export", "--all", "--to", to, "--out"])
        .arg(out)
        .arg(cases)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o));
    o
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

fn catalog(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("analytic/cases")
        .join(rel)
}

/// The closed furnace with albedo `rho` as a case file: an analytic sphere, or (with
/// `subdivisions`) an icosphere of 20·4ⁿ triangles inscribed in it, normals flipped
/// inward like the sphere's.
fn furnace(rho: f64, subdivisions: Option<u32>) -> String {
    let geometry = match subdivisions {
        None => r#"{ "type": "sphere", "center": [0, 0, 0], "radius": 1 }"#.to_string(),
        Some(n) => {
            let (v, f) = icosphere(n);
            format!(
                r#"{{ "type": "mesh", "vertices": {}, "indices": {} }}"#,
                serde_json::to_string(&v).unwrap(),
                serde_json::to_string(&f).unwrap()
            )
        }
    };
    format!(
        r#"{{ "name": "furnace", "teaches": "L = Le/(1 − ρ)",
  "scene": {{ "materials": {{ "grey": {{ "type": "lambertian", "albedo": {rho} }} }},
    "shapes": [ {{ "geometry": {geometry}, "material": "grey", "flip_normals": true, "emission": {{ "radiance": 1 }} }} ] }},
  "measure": {{ "radiance": {{ "at": [0.1, 0, 0.05], "direction": [0, 0.6, 0.8] }} }},
  "reference": {{ "closed_form": "furnace_closed_enclosure", "emitted_radiance": 1, "albedo": {rho} }},
  "estimators": ["mis"] }}"#
    )
}

/// An icosphere on the unit sphere, counter-clockwise seen from outside.
fn icosphere(n: u32) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut v: Vec<[f64; 3]> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .to_vec();
    let unit = |p: [f64; 3]| {
        let l = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
        [p[0] / l, p[1] / l, p[2] / l]
    };
    v.iter_mut().for_each(|p| *p = unit(*p));
    let mut f: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..n {
        let mut mids = std::collections::HashMap::new();
        let mut mid = |a: u32, b: u32, v: &mut Vec<[f64; 3]>| -> u32 {
            *mids.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (p, q) = (v[a as usize], v[b as usize]);
                v.push(unit([p[0] + q[0], p[1] + q[1], p[2] + q[2]]));
                (v.len() - 1) as u32
            })
        };
        f = f
            .iter()
            .flat_map(|&[a, b, c]| {
                let (ab, bc, ca) = (mid(a, b, &mut v), mid(b, c, &mut v), mid(c, a, &mut v));
                [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
            })
            .collect();
    }
    (v, f)
}

fn judge_suite_json(dir: &Path) -> (Output, Value) {
    let out = bin()
        .args(["judge", "--json", "--suite"])
        .arg(dir)
        .output()
        .unwrap();
    let doc: Value = serde_json::from_slice(&out.stdout).unwrap_or(Value::Null);
    (out, doc)
}

/// Export closed furnaces for lightproof's `render`, render them with the exported
/// driver, judge them: all pass, each able to see a 1.5% bias; then a wrong reference
/// (albedo 0.52 for 0.5: 4% more radiance) fails, also judged from one render's pixels.
#[test]
fn round_trip_through_lightproof_render() {
    let cases = scratch("cases");
    for rel in [
        "furnace/closed_sphere_0_5.json",
        "furnace/closed_cube_mesh_0_5.json",
        "depth/closed_sphere_4_bounces_0_8.json",
    ] {
        let to = cases.join(rel.replace('/', "_"));
        std::fs::copy(catalog(rel), to).unwrap();
    }
    // Not a closed furnace: lightproof's pinhole camera cannot measure it; refused, listed.
    std::fs::copy(
        catalog("irradiance/disk_on_axis.json"),
        cases.join("disk.json"),
    )
    .unwrap();
    let out_dir = scratch("suite");
    let o = export_all("lightproof", &cases, &out_dir);
    assert!(text(&o).contains("exported 3 cases"), "{}", text(&o));
    let o = Command::new("sh")
        .arg(out_dir.join("render_all.sh"))
        .env("LIGHTPROOF", env!("CARGO_BIN_EXE_lightproof"))
        .env("RENDERS", "16")
        .env("SPP", (64 * common_scale()).to_string())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o));
    let (o, doc) = judge_suite_json(&out_dir);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let js = doc["judgements"].as_array().unwrap();
    assert_eq!(js.len(), 3);
    assert_eq!(doc["tests"], 3);
    assert_eq!(doc["refused"].as_array().unwrap().len(), 1, "{doc}");
    for j in js {
        assert_eq!(j["method"], "independent_renders");
        assert_eq!(j["replicates"].as_array().unwrap().len(), 16);
        let v = &j["verdict"];
        assert_eq!(v["passed"], true, "{j}");
        assert!(
            v["detectable_relative_bias"].as_f64().unwrap() < 0.015,
            "{j}"
        );
    }
    // The table: one row per case and the closing count.
    let o = bin()
        .args(["judge", "--suite"])
        .arg(&out_dir)
        .output()
        .unwrap();
    assert!(text(&o).contains("3 passed, 0 failed"), "{}", text(&o));

    // A wrong reference fails, from the same renders.
    let sphere = out_dir.join("furnace_closed_sphere_0_5");
    let wrong = std::fs::read_to_string(sphere.join("case.json"))
        .unwrap()
        .replace("\"albedo\": 0.5 }", "\"albedo\": 0.52 }");
    assert!(wrong.contains("0.52"));
    let wrong_case = cases.join("wrong.json");
    std::fs::write(&wrong_case, wrong).unwrap();
    let renders: Vec<PathBuf> = (0..16)
        .map(|k| sphere.join(format!("renders/{k:03}.exr")))
        .collect();
    let o = bin()
        .args(["judge", "--json"])
        .arg(&wrong_case)
        .args(&renders)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    let j: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(j["z"].as_f64().unwrap() < -5.0, "{j}");
    // One render: batch means over its pixel blocks; right and wrong reference.
    let one = |case: &Path| {
        bin()
            .args(["judge", "--json"])
            .arg(case)
            .arg(&renders[0])
            .output()
            .unwrap()
    };
    let o = one(&sphere.join("case.json"));
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let j: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(j["method"], "pixel_blocks");
    assert_eq!(j["replicates"].as_array().unwrap().len(), 32);
    assert_eq!(one(&wrong_case).status.code(), Some(1));
    let _ = std::fs::remove_dir_all(cases);
    let _ = std::fs::remove_dir_all(out_dir);
}

fn common_scale() -> u64 {
    super::common::scale()
}

/// Bad renders exit 2 naming the file; non-finite pixels fail the verdict (exit 1).
#[test]
fn bad_renders_are_named() {
    let d = scratch("bad");
    let case = catalog("furnace/closed_sphere_0_5.json");
    let write = |name: &str, w: usize, h: usize, v: f32| {
        let p = d.join(name);
        lightproof::render::write_exr(&p, w, h, &vec![[v; 3]; w * h]).unwrap();
        p
    };
    let a = write("a.exr", 4, 4, 2.0);
    let b = write("b.exr", 4, 4, 2.0);
    let small = write("small.exr", 2, 4, 2.0);
    let not_exr = d.join("text.exr");
    std::fs::write(&not_exr, "not an image").unwrap();
    let y_only = d.join("y.exr");
    use exr::prelude::WritableImage;
    exr::prelude::Image::from_channels(
        (2, 2),
        exr::prelude::SpecificChannels::build()
            .with_channel("Y")
            .with_pixel_fn(|_| (1.0f32,)),
    )
    .write()
    .to_file(&y_only)
    .unwrap();
    let mut nan = vec![[2.0f32; 3]; 16];
    nan[5] = [f32::NAN; 3];
    let nan_file = d.join("nan.exr");
    lightproof::render::write_exr(&nan_file, 4, 4, &nan).unwrap();
    let run = |renders: &[&PathBuf]| {
        bin()
            .arg("judge")
            .arg(&case)
            .args(renders)
            .output()
            .unwrap()
    };
    for (renders, bad, why) in [
        (vec![&a, &small], &small, "expected 4 × 4"),
        (vec![&a, &not_exr], &not_exr, "EXR"),
        (vec![&y_only], &y_only, "no R channel"),
    ] {
        let o = run(&renders);
        let err = text(&o);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(
            err.contains(&bad.display().to_string()) && err.contains(why),
            "{err}"
        );
        assert!(!err.contains("panicked"), "{err}");
    }
    let o = run(&[&a, &b, &nan_file]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(
        text(&o).contains(&format!(
            "{}: 1 non-finite pixels, the first at (1, 1)",
            nan_file.display()
        )),
        "{}",
        text(&o)
    );
    // Identical renders: no variance, judged exactly (2 ≠ 2.0 ± f32 rounding? equal: pass).
    let o = run(&[&a, &b]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(text(&o).contains("(exact)"), "{}", text(&o));
    let _ = std::fs::remove_dir_all(d);
}

/// A case a renderer cannot express exits 2 with the reason.
#[test]
fn inexpressible_cases_are_refused() {
    let d = scratch("refused");
    for (case, to, why) in [
        (
            "irradiance/disk_on_axis.json",
            "pbrt",
            "no irradiance sensor",
        ),
        (
            "bsdf_albedo/oren_nayar_fujii_sigma0_5_60.json",
            "mitsuba",
            "Oren–Nayar",
        ),
        (
            "bsdf_albedo/white_ggx_alpha0_5_60.json",
            "mitsuba",
            "height-correlated",
        ),
        ("solid_angle/triangle.json", "mitsuba", "geometric integral"),
    ] {
        let o = bin()
            .args(["export", "--to", to, "--out"])
            .arg(&d)
            .arg(catalog(case))
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(2), "{case}: {}", text(&o));
        assert!(text(&o).contains(why), "{case}: {}", text(&o));
    }
    let _ = std::fs::remove_dir_all(d);
}

/// A flux case without a view factor: a disk of radius 0.5 (area π/4) under a unit sky
/// receives Φ = π L · π/4 (the constant-environment irradiance, scaled by the area).
const SKY_FLUX_CASE: &str = r#"{ "name": "flux onto a disk under a sky", "teaches": "Φ = π L A",
  "scene": { "shapes": [ { "geometry": { "type": "disk", "center": [0, 0, 0], "normal": [0, 0, 1], "radius": 0.5 } } ],
    "emitters": [ { "type": "constant", "radiance": 1 } ] },
  "measure": { "flux": { "shape": 0 } },
  "reference": { "closed_form": "constant_environment_irradiance", "radiance": 1, "scale": 0.7853981633974483 },
  "estimators": ["bsdf"] }"#;

/// Uniform numbers in [0, 1) from a PCG stream (53 bits).
fn uniforms(seed: u64) -> impl FnMut() -> f64 {
    use rand::Rng;
    let mut rng = rand_pcg::Pcg32::new(seed, 0xda3e_39cb_94b9_5bdb);
    move || (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// An independent "renderer" of a receiver's mean irradiance: render k is the mean of the
/// oracle's point irradiance `e(u, v)` at `n` receiver points drawn uniformly by area
/// (`(u, v)` uniform in the unit square, mapped by `e`), written as a 1 × 1 EXR with every
/// value times `bias`.
fn fake_meter_renders(
    dir: &Path,
    renders: u64,
    n: usize,
    bias: f64,
    e: impl Fn(f64, f64) -> f64,
) -> Vec<PathBuf> {
    std::fs::create_dir_all(dir).unwrap();
    (0..renders)
        .map(|k| {
            let mut u = uniforms(super::common::seed() ^ (k << 32));
            let mean = (0..n).map(|_| e(u(), u())).sum::<f64>() / n as f64;
            let v = (mean * bias) as f32;
            let p = dir.join(format!("{k:03}.exr"));
            lightproof::render::write_exr(&p, 1, 1, &[[v; 3]]).unwrap();
            p
        })
        .collect()
}

/// Flux and view factors export as Mitsuba's `irradiancemeter` inside the receiver shape,
/// whose pixel is the mean irradiance Φ/A₂: the manifest's scale must be 1/A₂ for a flux
/// and π L₁ A₁/A₂ for a view factor. Renders of that mean irradiance made here without
/// the engine (the oracle's point irradiance from the emitter, at receiver points drawn by
/// area, 8192 per render) pass; the same renders 4% high fail. pbrt-v4 and lightproof's
/// `render` refuse.
#[test]
fn flux_is_judged_as_mean_irradiance() {
    use lightproof_analytic::geom::Vec3;
    use std::f64::consts::PI;
    let d = scratch("flux");
    let sky = d.join("sky_flux.json");
    std::fs::write(&sky, SKY_FLUX_CASE).unwrap();
    // (case, expected scale, the receiver's mean irradiance at (u, v)).
    type PointIrradiance = Box<dyn Fn(f64, f64) -> f64>;
    let cases: [(PathBuf, f64, PointIrradiance); 3] = [
        // C-41: unit disk emitter at height 1 facing down, receiver disk of radius 0.5.
        (
            catalog("view_factor/coaxial_disks_c41.json"),
            PI * PI / (PI * 0.25),
            Box::new(|u, v| {
                let (r, phi) = (0.5 * u.sqrt(), 2.0 * PI * v);
                let p = Vec3::new(r * phi.cos(), r * phi.sin(), 0.0);
                let z = Vec3::new(0.0, 0.0, 1.0);
                lightproof_analytic::irradiance::disk(p, z, z, z, 1.0, 1.0)
            }),
        ),
        // C-14: unit square emitter in z = 0, receiver the unit square in y = 0 facing +y.
        (
            catalog("view_factor/perpendicular_rectangles_c14.json"),
            PI,
            Box::new(|u, v| {
                let square = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
                    .map(|[x, y]| Vec3::new(x, y, 0.0));
                let p = Vec3::new(v, 0.0, u);
                lightproof_analytic::irradiance::polygon(p, Vec3::new(0.0, 1.0, 0.0), &square, 1.0)
            }),
        ),
        // Under a unit sky every receiver point has E = π.
        (sky.clone(), 1.0 / (PI * 0.25), Box::new(|_, _| PI)),
    ];
    for (case, scale, e) in &cases {
        let out = d.join(case.file_stem().unwrap());
        let o = bin()
            .args(["export", "--to", "mitsuba", "--out"])
            .arg(&out)
            .arg(case)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", text(&o));
        let manifest: Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("export.json")).unwrap())
                .unwrap();
        assert_eq!(manifest["sensor"], "flux", "{manifest}");
        let got = manifest["scale"].as_f64().unwrap();
        assert!(
            (got / scale - 1.0).abs() < 1e-12,
            "{case:?}: scale {got}, expected {scale}"
        );
        let xml = std::fs::read_to_string(out.join("scene.xml")).unwrap();
        assert_eq!(xml.matches("irradiancemeter").count(), 1, "{xml}");
        for (bias, passes) in [(1.0, true), (1.04, false)] {
            let renders = fake_meter_renders(&out.join("renders"), 16, 8192, bias, e);
            let o = bin()
                .args(["judge", "--json"])
                .arg(out.join("case.json"))
                .args(&renders)
                .output()
                .unwrap();
            let j: Value = serde_json::from_slice(&o.stdout).unwrap_or(Value::Null);
            assert_eq!(
                j["verdict"]["passed"],
                passes,
                "{case:?} × {bias}: {}",
                text(&o)
            );
            assert_eq!(o.status.code(), Some(if passes { 0 } else { 1 }));
            // The 4% must lie well past what 16 renders can detect (at 99% power): at
            // 1024 points per render the bound was about 4%, and one seed in a few
            // passed the biased renders.
            let detectable = j["verdict"]["detectable_relative_bias"].as_f64().unwrap();
            assert!(detectable < 0.02, "{case:?} × {bias}: detects {detectable}");
            // Judged in the case's units (Φ, or F), not the meter's.
            let relative = j["estimate"].as_f64().unwrap() / j["reference"].as_f64().unwrap();
            assert!(
                (relative / bias - 1.0).abs() < 0.02,
                "{case:?} × {bias}: {j}"
            );
        }
        // The case file alone has no scale: judging it is refused, not misjudged.
        let renders: Vec<PathBuf> = (0..16)
            .map(|k| out.join(format!("renders/{k:03}.exr")))
            .collect();
        let o = bin()
            .arg("judge")
            .arg(case)
            .args(&renders)
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(2), "{}", text(&o));
        assert!(text(&o).contains("mean irradiance"), "{}", text(&o));
        for to in ["pbrt", "lightproof"] {
            let o = bin()
                .args(["export", "--to", to, "--out"])
                .arg(d.join("refused"))
                .arg(case)
                .output()
                .unwrap();
            assert_eq!(o.status.code(), Some(2), "{to}: {}", text(&o));
            assert!(text(&o).contains("flux"), "{to}: {}", text(&o));
        }
    }
    let _ = std::fs::remove_dir_all(d);
}

/// The peers' drivers run without a peer installed as far as they can: Mitsuba's
/// `render_all.py` parses (its `--help`, which imports Mitsuba only once it renders) and
/// refuses `--renders 1` and `--pass-spp 0` before it needs Mitsuba; pbrt's `render_all.sh` passes `sh -n`
/// and stops, naming it, when `PBRT` names no program. So a default `cargo test`
/// catches a driver broken by an edit, not only the opt-in peer tests below.
#[test]
fn the_peer_drivers_parse_and_refuse_without_a_peer() {
    let cases = scratch("drivers-cases");
    std::fs::write(cases.join("furnace.json"), furnace(0.8, None)).unwrap();
    for to in ["mitsuba", "pbrt"] {
        let out_dir = scratch(&format!("drivers-{to}"));
        export_all(to, &cases, &out_dir);
        if to == "mitsuba" {
            let py = |args: &[&str]| {
                Command::new("python3")
                    .arg(out_dir.join("render_all.py"))
                    .args(args)
                    .output()
            };
            let Ok(help) = py(&["--help"]) else {
                eprintln!("skipped render_all.py: no python3 on this machine");
                continue;
            };
            assert!(
                help.status.success() && text(&help).contains("--pass-spp"),
                "{}",
                text(&help)
            );
            let one = py(&["--renders", "1"]).unwrap();
            assert!(
                !one.status.success() && text(&one).contains("--renders must be at least 2"),
                "{}",
                text(&one)
            );
            // A pass of 0 samples is refused by the parser (it once divided by zero).
            let zero = py(&["--pass-spp", "0"]).unwrap();
            assert!(
                zero.status.code() == Some(2)
                    && text(&zero).contains("--pass-spp: must be a positive integer, got '0'"),
                "{}",
                text(&zero)
            );
        } else {
            let script = out_dir.join("render_all.sh");
            let n = Command::new("sh").arg("-n").arg(&script).output().unwrap();
            assert!(n.status.success(), "{}", text(&n));
            let o = Command::new("sh")
                .arg(&script)
                .env("PBRT", "/nonexistent/pbrt")
                .env("RENDERS", "2")
                .output()
                .unwrap();
            assert!(
                !o.status.success() && text(&o).contains("/nonexistent/pbrt"),
                "{}",
                text(&o)
            );
        }
        let _ = std::fs::remove_dir_all(out_dir);
    }
    let _ = std::fs::remove_dir_all(cases);
}

/// Stand-ins for Mitsuba's and Dr.Jit's Python modules that log what `render_all.py`
/// asks of them (each `render` call's spp and seed, each thread count, the thread count
/// at each EXR write) and answer with a one-pixel image.
const STUB_MITSUBA: &str = r#"import os
import drjit
__version__ = "stub"
LOG = os.environ["LIGHTPROOF_STUB_LOG"]
def log(line):
    with open(LOG, "a") as f:
        f.write(line + "\n")
def set_variant(v):
    log("variant %s" % v)
def load_file(path):
    return path
class Image:
    shape = (1, 1, 3)
    array = [1.0, 1.0, 1.0]
def render(scene, seed=0, spp=0):
    log("render spp=%d seed=%d" % (spp, seed))
    return Image()
def TensorXf(values, shape):
    return values
class util:
    @staticmethod
    def write_bitmap(path, tensor, write_async=True):
        log("write threads=%d" % drjit.THREADS)
        with open(path, "w") as f:
            f.write("stub")
"#;

const STUB_DRJIT: &str = r#"import os
THREADS = 0
def set_thread_count(n):
    global THREADS
    THREADS = n
    with open(os.environ["LIGHTPROOF_STUB_LOG"], "a") as f:
        f.write("threads %d\n" % n)
"#;

/// The Mitsuba driver as README.md describes it, run against stand-in modules (no
/// Mitsuba needed): it renders in passes of at most `--pass-spp` (default 256) samples per
/// pixel with distinct seeds, at least the spp that `--samples` asks for, and with
/// `--threads 1` it writes each EXR with two threads (Mitsuba 3.9.1 deadlocks with one)
/// and goes back to one.
#[test]
fn the_mitsuba_driver_renders_in_passes_and_writes_with_two_threads() {
    let cases = scratch("stub-cases");
    std::fs::write(cases.join("furnace.json"), furnace(0.8, None)).unwrap();
    let out_dir = scratch("stub-mitsuba");
    export_all("mitsuba", &cases, &out_dir);
    let stubs = scratch("stub-modules");
    for (module, code) in [("mitsuba", STUB_MITSUBA), ("drjit", STUB_DRJIT)] {
        std::fs::create_dir_all(stubs.join(module)).unwrap();
        std::fs::write(stubs.join(module).join("__init__.py"), code).unwrap();
    }
    let manifest: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out_dir.join("furnace/export.json")).unwrap(),
    )
    .unwrap();
    let pixels = manifest["width"].as_u64().unwrap() * manifest["height"].as_u64().unwrap();
    for (samples, pass_spp) in [(70_000u64, None), (3_000, Some(100u64)), (100, None)] {
        let log = stubs.join("calls.log");
        let _ = std::fs::remove_file(&log);
        let mut cmd = Command::new("python3");
        cmd.arg(out_dir.join("render_all.py"))
            .args(["--renders", "2", "--threads", "1", "--samples"])
            .arg(samples.to_string())
            .env("PYTHONPATH", &stubs)
            .env("LIGHTPROOF_STUB_LOG", &log);
        if let Some(p) = pass_spp {
            cmd.args(["--pass-spp", &p.to_string()]);
        }
        let Ok(run) = cmd.output() else {
            eprintln!("skipped render_all.py: no python3 on this machine");
            return;
        };
        assert!(run.status.success(), "{}", text(&run));
        let calls = std::fs::read_to_string(&log).unwrap();
        let limit = pass_spp.unwrap_or(256);
        let want = samples.div_ceil(pixels);
        let mut seeds = std::collections::BTreeSet::new();
        let (mut spp_sum, mut writes) = (0, 0);
        // The thread counts set, in order: 1 from `--threads 1`, then 2 and back to 1
        // around each write.
        let threads: Vec<&str> = calls
            .lines()
            .filter_map(|l| l.strip_prefix("threads "))
            .collect();
        assert_eq!(threads, ["1", "2", "1", "2", "1"], "{calls}");
        for line in calls.lines() {
            if let Some(rest) = line.strip_prefix("render spp=") {
                let (spp, seed) = rest.split_once(" seed=").unwrap();
                let spp: u64 = spp.parse().unwrap();
                assert!(
                    spp >= 1 && spp <= limit,
                    "{samples}: a pass of {spp} spp: {calls}"
                );
                assert!(seeds.insert(seed.to_string()), "seed {seed} twice: {calls}");
                spp_sum += spp;
            } else if let Some(t) = line.strip_prefix("write threads=") {
                assert_eq!(t, "2", "an EXR written with {t} threads: {calls}");
                // Each render's passes add up to at least the spp asked for.
                assert!(
                    spp_sum >= want,
                    "{samples}: {spp_sum} spp < {want}: {calls}"
                );
                (spp_sum, writes) = (0, writes + 1);
            }
        }
        assert_eq!(writes, 2, "{calls}");
    }
    let _ = std::fs::remove_dir_all(out_dir);
    let _ = std::fs::remove_dir_all(stubs);
    let _ = std::fs::remove_dir_all(cases);
}

/// A peer renderer that renders an exported suite with its driver: Mitsuba's
/// `render_all.py` under this Python, or pbrt-v4's `render_all.sh` with this binary.
enum Peer {
    Mitsuba(String),
    Pbrt(String),
}

/// Export `cases` for `peer` into `out_dir`, render each case 16 times with 65 536 paths
/// (× `LIGHTPROOF_SCALE`), and judge the suite: the export's output, the judge's output
/// and its JSON.
fn export_render_judge(peer: Peer, cases: &Path, out_dir: &Path) -> (Output, Output, Value) {
    let to = match peer {
        Peer::Mitsuba(_) => "mitsuba",
        Peer::Pbrt(_) => "pbrt",
    };
    let exported = export_all(to, cases, out_dir);
    let samples = (65536 * common_scale()).to_string();
    let o = match peer {
        Peer::Mitsuba(python) => Command::new(python)
            .arg(out_dir.join("render_all.py"))
            .args(["--renders", "16", "--samples", &samples])
            .output(),
        Peer::Pbrt(pbrt) => Command::new("sh")
            .arg(out_dir.join("render_all.sh"))
            .env("PBRT", pbrt)
            .env("RENDERS", "16")
            .env("SAMPLES", &samples)
            .output(),
    }
    .unwrap();
    assert!(o.status.success(), "{}", text(&o));
    let (o, doc) = judge_suite_json(out_dir);
    (exported, o, doc)
}

/// Opt-in: with `LIGHTPROOF_MITSUBA` naming a Python that has `mitsuba`, Mitsuba 3
/// (scalar_rgb) renders the analytic-sphere furnace (ρ = 0.8, L = 5) and a mesh sphere
/// (1280 triangles) with 16 renders × 65 536 paths each: the analytic sphere's excess
/// radiance is detected, the mesh sphere passes.
#[test]
fn mitsuba_sphere_furnace_bias_is_detected() {
    let Ok(python) = std::env::var("LIGHTPROOF_MITSUBA") else {
        eprintln!("skipped: set LIGHTPROOF_MITSUBA=python3 (a Python with mitsuba) to run");
        return;
    };
    let cases = scratch("mi-cases");
    std::fs::write(cases.join("analytic_sphere.json"), furnace(0.8, None)).unwrap();
    std::fs::write(cases.join("mesh_sphere.json"), furnace(0.8, Some(3))).unwrap();
    let out_dir = scratch("mi-suite");
    let (_, o, doc) = export_render_judge(Peer::Mitsuba(python), &cases, &out_dir);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    let js = doc["judgements"].as_array().unwrap();
    let find = |id: &str| js.iter().find(|j| j["id"] == id).unwrap().clone();
    let sphere = find("analytic_sphere");
    let relative = sphere["estimate"].as_f64().unwrap() / 5.0 - 1.0;
    assert_eq!(sphere["verdict"]["passed"], false, "{sphere}");
    assert!(
        sphere["z"].as_f64().unwrap() > 0.0 && relative > 0.005,
        "{sphere}"
    );
    let mesh = find("mesh_sphere");
    for j in [&sphere, &mesh] {
        eprintln!(
            "{}: {} ± {} (reference 5, {:+.3}%), z = {}, passed {}",
            j["id"],
            j["estimate"],
            j["std_error"],
            100.0 * (j["estimate"].as_f64().unwrap() / 5.0 - 1.0),
            j["z"],
            j["verdict"]["passed"]
        );
    }
    assert_eq!(mesh["verdict"]["passed"], true, "{mesh}");
    assert!(
        mesh["verdict"]["detectable_relative_bias"]
            .as_f64()
            .unwrap()
            < relative,
        "{mesh}"
    );
    let _ = std::fs::remove_dir_all(cases);
    let _ = std::fs::remove_dir_all(out_dir);
}

/// Opt-in: with `LIGHTPROOF_PBRT` naming a pbrt-v4 binary, pbrt renders the catalog's
/// glass-sphere limb case (`transport/radiance_invariance_sphere_far`: the eye at the
/// centre of a glass sphere, η = 1.33, looking at 0.99 of a distant sphere light's
/// angular radius) twice: as exported (the eye ray leaves the glass sphere 0.00099 rad
/// from its pole) and with the glass sphere's axis turned to +x (the ray leaves at its
/// equator). pbrt-v4 computes a sphere's normal from sin θ = √(1 − cos²θ) in f32, off
/// by ~10⁻⁵ rad near the poles: the refracted rays miss the light's limb, so the first
/// must fail low and the second must pass (16 renders × 65 536 paths each).
#[test]
fn pbrt_sphere_pole_normal_bias_is_detected() {
    let Ok(pbrt) = std::env::var("LIGHTPROOF_PBRT") else {
        eprintln!("skipped: set LIGHTPROOF_PBRT=path/to/pbrt (pbrt-v4) to run");
        return;
    };
    let cases = scratch("pbrt-cases");
    let limb =
        std::fs::read_to_string(catalog("transport/radiance_invariance_sphere_far.json")).unwrap();
    let mut equator: Value = serde_json::from_str(&limb).unwrap();
    // The whole sphere (a "cap" of 180°) about +x.
    equator["scene"]["shapes"][0]["geometry"]["axis"] = serde_json::json!([1, 0, 0]);
    equator["scene"]["shapes"][0]["geometry"]["theta_max"] = serde_json::json!(180);
    std::fs::write(cases.join("pole.json"), &limb).unwrap();
    std::fs::write(cases.join("equator.json"), equator.to_string()).unwrap();
    let out_dir = scratch("pbrt-suite");
    let (_, o, doc) = export_render_judge(Peer::Pbrt(pbrt), &cases, &out_dir);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    let js = doc["judgements"].as_array().unwrap();
    let find = |id: &str| js.iter().find(|j| j["id"] == id).unwrap().clone();
    let (pole, equator) = (find("pole"), find("equator"));
    for j in [&pole, &equator] {
        eprintln!(
            "{}: {} ± {} (reference {}), z = {}, passed {}",
            j["id"], j["estimate"], j["std_error"], j["reference"], j["z"], j["verdict"]["passed"]
        );
    }
    assert_eq!(pole["verdict"]["passed"], false, "{pole}");
    assert!(pole["z"].as_f64().unwrap() < 0.0, "{pole}");
    assert_eq!(equator["verdict"]["passed"], true, "{equator}");
    let _ = std::fs::remove_dir_all(cases);
    let _ = std::fs::remove_dir_all(out_dir);
}

/// Opt-in: with `LIGHTPROOF_MITSUBA` naming a Python that has `mitsuba`, Mitsuba 3
/// (scalar_rgb) renders flux cases through its `irradiancemeter` on the receiver (the
/// view factors C-41 and C-14, and a flux under a sky), 16 renders × 65 536 paths each:
/// all pass.
#[test]
fn mitsuba_flux_cases_pass() {
    let Ok(python) = std::env::var("LIGHTPROOF_MITSUBA") else {
        eprintln!("skipped: set LIGHTPROOF_MITSUBA=python3 (a Python with mitsuba) to run");
        return;
    };
    let cases = scratch("mi-flux-cases");
    for rel in [
        "view_factor/coaxial_disks_c41.json",
        "view_factor/perpendicular_rectangles_c14.json",
    ] {
        std::fs::copy(catalog(rel), cases.join(rel.replace('/', "_"))).unwrap();
    }
    std::fs::write(cases.join("sky_flux.json"), SKY_FLUX_CASE).unwrap();
    let out_dir = scratch("mi-flux-suite");
    let (exported, o, doc) = export_render_judge(Peer::Mitsuba(python), &cases, &out_dir);
    assert!(
        text(&exported).contains("exported 3 cases"),
        "{}",
        text(&exported)
    );
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    for j in doc["judgements"].as_array().unwrap() {
        eprintln!(
            "{}: {} ± {} (reference {}), z = {}",
            j["id"], j["estimate"], j["std_error"], j["reference"], j["z"]
        );
        assert_eq!(j["verdict"]["passed"], true, "{j}");
    }
    let _ = std::fs::remove_dir_all(cases);
    let _ = std::fs::remove_dir_all(out_dir);
}

/// Student's t with R − 1 degrees of freedom for R independent renders, and B − 1 = 31
/// for the pixel blocks of one render, at the single test's α = 1e-4 (one case: no Šidák
/// correction): the critical value is the t quantile itself (statrs here, independently
/// of the judge's own formula), 28.0 for 3 dof, where a z test would use 3.89. `--json`
/// carries the counts of non-finite and negative pixels.
#[test]
fn judge_uses_student_t_with_the_replicates_degrees_of_freedom() {
    use statrs::distribution::{ContinuousCDF, StudentsT};
    let d = scratch("student");
    let case = catalog("furnace/closed_sphere_0_5.json");
    // Renders about the reference 2 with spread 0.01 (a pass whatever the test).
    let render = |name: &str, v: f32| {
        let p = d.join(name);
        let px: Vec<[f32; 3]> = (0..64)
            .map(|i| [v + 0.01 * ((i * 37 % 64) as f32 / 64.0 - 0.5); 3])
            .collect();
        lightproof::render::write_exr(&p, 8, 8, &px).unwrap();
        p
    };
    let four = [1.99, 2.005, 1.998, 2.007].map(|v| render(&format!("r{v}.exr"), v));
    let judge_json = |renders: &[&PathBuf]| {
        let o = bin()
            .arg("judge")
            .arg(&case)
            .args(renders)
            .arg("--json")
            .output()
            .unwrap();
        let v: Value = serde_json::from_slice(&o.stdout).unwrap_or(Value::Null);
        (o, v)
    };
    let t_crit = |dof: f64| {
        StudentsT::new(0.0, 1.0, dof)
            .unwrap()
            .inverse_cdf(1.0 - 0.5e-4)
    };
    let (o, v) = judge_json(&four.iter().collect::<Vec<_>>());
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert_eq!(
        (v["dof"].as_u64(), v["verdict"]["dof"].as_u64()),
        (Some(3), Some(3)),
        "{v}"
    );
    let crit = v["verdict"]["critical"].as_f64().unwrap();
    assert!(
        (crit - t_crit(3.0)).abs() < 1e-6 * crit && crit > 27.9,
        "{crit}"
    );
    // With 4 renders the t test at 3 degrees of freedom detects (99% power) a bias of
    // about 55 standard errors (README, "Judge your renderer").
    let ratio = v["verdict"]["detectable_bias"].as_f64().unwrap()
        / v["verdict"]["std_error"].as_f64().unwrap();
    assert!((ratio - 54.5).abs() < 0.5, "{ratio}");
    assert_eq!(
        (v["non_finite"].as_u64(), v["negative"].as_u64()),
        (Some(0), Some(0)),
        "{v}"
    );
    // One render (centred on the reference): 32 blocks, 31 dof.
    let centred = render("r2.exr", 2.0);
    let (o, v) = judge_json(&[&centred]);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert_eq!(v["verdict"]["dof"].as_u64(), Some(31), "{v}");
    let crit = v["verdict"]["critical"].as_f64().unwrap();
    assert!((crit - t_crit(31.0)).abs() < 1e-6 * crit, "{crit}");
    // A negative channel and a NaN pixel are counted in the JSON and fail.
    let bad = d.join("bad.exr");
    let mut px = vec![[2.0f32; 3]; 64];
    px[3] = [-0.5, 3.25, 3.25];
    px[9] = [f32::NAN; 3];
    lightproof::render::write_exr(&bad, 8, 8, &px).unwrap();
    let (o, v) = judge_json(&[&centred, &bad]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert_eq!(
        (v["non_finite"].as_u64(), v["negative"].as_u64()),
        (Some(1), Some(1)),
        "{v}"
    );
    assert_eq!(v["verdict"]["passed"], Value::Bool(false), "{v}");
    let _ = std::fs::remove_dir_all(d);
}

/// A render judged against an exported case must have the export's size (the manifest
/// beside `case.json`), not merely the first render's: a 4 × 2 render of a 16 × 16
/// furnace export exits 2 naming both sizes.
#[test]
fn renders_must_have_the_exported_size() {
    let d = scratch("size");
    let o = bin()
        .arg("export")
        .arg(catalog("furnace/closed_sphere_0_5.json"))
        .args(["--to", "mitsuba", "--out"])
        .arg(&d)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let small = d.join("small.exr");
    lightproof::render::write_exr(&small, 4, 2, &[[2.0f32; 3]; 8]).unwrap();
    let o = bin()
        .arg("judge")
        .arg(d.join("case.json"))
        .arg(&small)
        .arg(&small)
        .output()
        .unwrap();
    let err = text(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains(&small.display().to_string())
            && err.contains("the render is 4 × 2 pixels, expected 16 × 16"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(d);
}
