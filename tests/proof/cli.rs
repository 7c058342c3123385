//! The command line as users and scripts drive it: bad input exits with status 2 and
//! one message naming file, field and reason (never a panic); a passing case exits 0;
//! `estimate` prints one JSON object with the contract's fields.

use std::path::{Path, PathBuf};
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_lightproof"))
}

/// `lightproof COMMAND CASE ARGS…` on a catalog case, which must fail its verdict (exit
/// 1): its stdout.
#[track_caller]
fn fails_on_catalog_case(command: &str, case: &str, args: &[&str]) -> String {
    let out = bin()
        .arg(command)
        .arg(catalog_case(case))
        .args(args)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert_eq!(out.status.code(), Some(1), "{stdout}");
    stdout
}

/// Run `c`, which must exit 0 (else the test fails with its stderr).
#[track_caller]
fn succeeds(c: &mut Command) -> std::process::Output {
    let out = c.output().unwrap();
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn tmp(name: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("lightproof-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

const GOOD: &str = r#"{
  "name": "disk on axis", "teaches": "E = π L R²/(R² + h²)",
  "scene": { "shapes": [ { "geometry": { "type": "disk", "center": [0, 0, 2], "normal": [0, 0, -1], "radius": 1 }, "emission": { "radiance": 1 } } ] },
  "measure": { "irradiance": { "at": [0, 0, 0], "normal": [0, 0, 1] } },
  "reference": { "closed_form": "disk_irradiance_on_axis", "radius": 1, "height": 2, "radiance": 1 },
  "estimators": ["light", "mis"], "samples": 65536 }"#;

fn bad(name: &str, text: &str, must_contain: &[&str]) {
    let p = tmp(name, text);
    let out = bin().arg("verify").arg(&p).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{name}: {err}");
    assert!(
        !err.contains("panicked") && !err.contains("RUST_BACKTRACE"),
        "{name}: {err}"
    );
    assert!(
        err.contains(&p.display().to_string()),
        "{name}: the message must name the file: {err}"
    );
    for m in must_contain {
        assert!(err.contains(m), "{name}: expected `{m}` in: {err}");
    }
    assert_eq!(err.trim().lines().count(), 1, "{name}: one line: {err}");
}

#[test]
fn bad_input_is_named_and_exits_2() {
    bad("malformed.json", "{ \"name\": ", &["EOF"]);
    bad(
        "unknown.json",
        &GOOD.replace("\"teaches\"", "\"colour\": 1, \"teaches\""),
        &["colour"],
    );
    bad(
        "negative.json",
        &GOOD.replace("\"radiance\": 1 } } ]", "\"radiance\": -1 } } ]"),
        &["scene.shapes[0].emission.radiance", "non-negative"],
    );
    bad(
        "nan.json",
        &GOOD.replace(
            "\"radius\": 1 }, \"emission\"",
            "\"radius\": \"NaN\" }, \"emission\"",
        ),
        &["scene.shapes[0].geometry", "NaN"],
    );
    bad(
        "degenerate.json",
        &GOOD.replace(
            "\"radius\": 1 }, \"emission\"",
            "\"radius\": 0 }, \"emission\"",
        ),
        &["scene.shapes[0].geometry.radius", "positive"],
    );
    bad(
        "eta.json",
        &GOOD.replace(
            "\"shapes\"",
            "\"materials\": { \"glass\": { \"type\": \"dielectric\", \"eta\": -1.5 } }, \"shapes\"",
        ),
        &["materials.glass", "eta"],
    );
    bad(
        "estimator.json",
        &GOOD.replace("\"light\", \"mis\"", "\"area\""),
        &["estimators[0]"],
    );
    bad(
        "closed_form.json",
        &GOOD.replace("disk_irradiance_on_axis", "no_such_form"),
        &["reference"],
    );
    let out = bin()
        .args(["verify", "/no/such/file.json"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn a_passing_case_exits_0_and_prints_the_table() {
    let p = tmp("good.json", GOOD);
    let json = p.with_extension("out.json");
    let html = p.with_extension("out.html");
    let out = bin()
        .args(["verify", "--threads", "2", "--json"])
        .arg(&json)
        .arg("--html")
        .arg(&html)
        .arg(&p)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        stdout.contains("2 passed (2 statistical, 0 exact), 0 failed"),
        "{stdout}"
    );
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(doc["outcomes"].as_array().unwrap().len(), 2);
    // The verdict page: both outcomes, with the case's teaching line.
    let page = std::fs::read_to_string(&html).unwrap();
    assert!(page.starts_with("<!DOCTYPE html>") && page.ends_with("</html>\n"));
    assert_eq!(page.matches("<tr class=\"outcome\"").count(), 2);
    assert!(page.contains("E = π L R²/(R² + h²)"), "{page}");
}

#[test]
fn estimate_prints_the_contract() {
    let p = tmp("est.json", GOOD);
    let v = estimate_json(&p, &["--samples", "20000"]);
    for key in [
        "case",
        "estimate",
        "std_error",
        "samples",
        "seconds",
        "effects",
        "reference",
        "z",
        "verdict",
    ] {
        assert!(v.get(key).is_some(), "missing `{key}` in {v}");
    }
    assert!(v["effects"]["occlusion"]["why"].is_string());
    // Same seed, different thread counts: identical estimates.
    let [a, b] = ["1", "2"].map(|t| estimate_json(&p, &["--samples", "20000", "--threads", t]));
    assert_eq!(a["estimate"], b["estimate"]);
}

#[test]
fn chi2_command_writes_images() {
    let dir = std::env::temp_dir().join(format!("lightproof-chi2-{}", std::process::id()));
    succeeds(
        bin()
            .args([
                "chi2",
                r#"{"type":"lambertian","albedo":0.5}"#,
                "--wo",
                "40,10",
                "--samples",
                "100000",
                "--out",
            ])
            .arg(&dir),
    );
    // The three images README names, and the outcome's JSON beside them.
    for f in [
        "lambertian-observed.exr",
        "lambertian-expected.exr",
        "lambertian-residual.exr",
        "lambertian.json",
    ] {
        assert!(dir.join(f).is_file(), "chi2 did not write {f}");
    }
    let bad = bin()
        .args(["chi2", r#"{"type":"lambertian","albedo":2}"#])
        .output()
        .unwrap();
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("albedo"));
}

/// An output that cannot be written is not bad input: exit 3, the path named, one line,
/// and the case itself still ran (exit 2 is kept for input the user must fix).
#[test]
fn unwritable_output_exits_3() {
    let case = tmp("writable_case.json", GOOD);
    // A folder cannot be created below a regular file.
    let blocker = tmp("not_a_folder", "x");
    let json = blocker.join("verdicts.json");
    let out = bin()
        .args(["verify", "--json"])
        .arg(&json)
        .arg(&case)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(3), "{err}");
    assert!(
        err.contains(&json.display().to_string()) && err.contains("cannot write"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    let html = blocker.join("verdicts.html");
    let out = bin()
        .arg("verify")
        .arg("--html")
        .arg(&html)
        .arg(&case)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(3), "{err}");
    assert!(err.contains(&html.display().to_string()), "{err}");
    let with_camera = tmp(
        "camera_case.json",
        &GOOD.replace(
            "\"measure\"",
            "\"camera\": { \"position\": [0, 0, 0], \"look_at\": [0, 0, 1], \"up\": [0, 1, 0], \"fov_degrees\": 40, \"width\": 4, \"height\": 4 }, \"measure\"",
        ),
    );
    let render = bin()
        .args(["render", "--spp", "1", "-o"])
        .arg(blocker.join("image.exr"))
        .arg(&with_camera)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&render.stderr);
    assert_eq!(render.status.code(), Some(3), "{err}");
}

#[test]
fn verify_table_names_cases_by_file_id_and_verbose_adds_what_they_teach() {
    let out = bin()
        .args(["verify", "--no-chi2", "--samples", "4096"])
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("analytic/cases/power"))
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{text}");
    // The id (path under the folder given, no `.json`), never the name cut short.
    let row = |id: &str| {
        text.lines()
            .any(|l| l.split_whitespace().next() == Some(id))
    };
    for id in ["disk", "rectangle", "sphere", "two_sided_triangle"] {
        assert!(row(id), "no row for `{id}`: {text}");
    }
    assert!(
        !text.contains("Φ = π L A"),
        "names only with --verbose: {text}"
    );
    let verbose = bin()
        .args(["verify", "--no-chi2", "--samples", "4096", "--verbose"])
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("analytic/cases/power/disk.json"))
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&verbose.stdout);
    assert!(text.contains("power of a disk light: Φ = π L A"), "{text}");
}

/// A camera over a diffuse floor lit by a disk light above the camera's view: every
/// pixel sees the floor, so a pixel is bright only through one or more scatterings.
const LIT_FLOOR: &str = r#"{
  "name": "lit floor", "teaches": "direct lighting needs one bounce",
  "scene": {
    "materials": { "white": { "type": "lambertian", "albedo": 0.8 } },
    "shapes": [
      { "geometry": { "type": "rectangle", "corner": [-50, -50, 0], "edge_u": [100, 0, 0], "edge_v": [0, 100, 0] }, "material": "white" },
      { "geometry": { "type": "disk", "center": [0, 0, 3], "normal": [0, 0, -1], "radius": 1 }, "emission": { "radiance": 10 } }
    ]
  },
  "camera": { "position": [0, 0, 2], "look_at": [0, 0, 0], "up": [0, 1, 0], "fov_degrees": 30, "width": 4, "height": 4 },
  "measure": { "irradiance": { "at": [0, 0, 0], "normal": [0, 0, 1] } },
  "estimators": ["light"] }"#;

/// A path still scattering at the guard of 2¹⁶ scatterings (a white closed sphere:
/// roulette keeps every path) is cut there when `render` has no `--max-depth`, and
/// stderr says how many were; with `--max-depth 65536` the same image, no such line.
#[test]
fn render_says_how_many_paths_the_guard_cut() {
    let case = tmp(
        "white_furnace_camera.json",
        r#"{"name": "white furnace", "teaches": "the guard",
          "scene": {"materials": {"white": {"type": "lambertian", "albedo": 1}},
            "shapes": [{"geometry": {"type": "sphere", "center": [0, 0, 0], "radius": 1},
              "material": "white", "flip_normals": true, "emission": {"radiance": 1}}]},
          "camera": {"position": [0, 0, 0], "look_at": [0, 0, 1], "up": [0, 1, 0], "fov_degrees": 30, "width": 2, "height": 1},
          "measure": {"radiance": {"at": [0, 0, 0], "direction": [0, 0, 1]}}, "estimators": ["mis"]}"#,
    );
    let dir = case.parent().unwrap().to_path_buf();
    let render = |depth: Option<&str>, name: &str| {
        let mut cmd = bin();
        cmd.args(["render", "--spp", "1", "-o"])
            .arg(dir.join(name))
            .arg(&case);
        if let Some(d) = depth {
            cmd.args(["--max-depth", d]);
        }
        let out = cmd.output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr).to_string();
        assert_eq!(out.status.code(), Some(0), "{err}");
        (std::fs::read(dir.join(name)).unwrap(), err)
    };
    let (cut, err) = render(None, "guard.exr");
    assert!(
        err.contains("2 of 2 paths were still scattering at the guard of 65536 scatterings"),
        "{err}"
    );
    let (limited, err) = render(Some("65536"), "limit.exr");
    assert_eq!(cut, limited, "the same paths, cut at the same depth");
    assert!(!err.contains("guard"), "a limit the user chose: {err}");
}

/// `render --threads T --max-depth D`: bounds checked (exit 2 naming the flag), the
/// image identical for any thread count, time and paths/s on stderr, and a depth of 0
/// leaving only the emission seen directly (none here), 1 adding direct lighting.
#[test]
fn render_takes_threads_and_max_depth() {
    let case = tmp("lit_floor.json", LIT_FLOOR);
    let dir = case.parent().unwrap().to_path_buf();
    for (flag, value) in [
        ("--max-depth", "-1"),
        ("--max-depth", "65537"),
        ("--max-depth", "two"),
        ("--threads", "0"),
        ("--threads", "-2"),
    ] {
        let out = bin()
            .args(["render", "--spp", "1", flag, value, "-o"])
            .arg(dir.join("never.exr"))
            .arg(&case)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{flag} {value}: {err}");
        assert!(
            err.contains(flag),
            "{flag} {value}: the flag must be named: {err}"
        );
        assert!(!err.contains("panicked"), "{err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
    }
    let render = |threads: &str, depth: Option<&str>, name: &str| {
        let out_path = dir.join(name);
        let mut cmd = bin();
        cmd.args(["render", "--spp", "8", "--threads", threads, "-o"])
            .arg(&out_path)
            .arg(&case);
        if let Some(d) = depth {
            cmd.args(["--max-depth", d]);
        }
        let out = cmd.output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "{err}");
        assert!(
            err.contains("128 paths in") && err.contains("paths/s"),
            "time and paths/s on stderr: {err}"
        );
        std::fs::read(out_path).unwrap()
    };
    let one = render("1", None, "t1.exr");
    assert_eq!(
        one,
        render("3", None, "t3.exr"),
        "thread count changed the image"
    );
    assert_eq!(one, render("2", Some("65536"), "deep.exr"));
    let pixels = |depth: u32| {
        let image = lightproof::render::render_file(&case, 8, 1, Some(depth)).expect("renders");
        assert_eq!(image.pixels.len(), image.width * image.height);
        image.pixels
    };
    assert!(
        pixels(0).iter().all(|&v| v == [0.0; 3]),
        "depth 0 sees no floor"
    );
    assert!(
        pixels(1)
            .iter()
            .all(|&[r, g, b]| r > 0.0 && r == g && g == b),
        "depth 1 lights the grey floor grey"
    );
    render("2", Some("0"), "d0.exr");
    // Looking up into the light (the disk fills the 30° view): a grey scene renders grey,
    // each pixel R = G = B = the emitted radiance, 10, at any depth (nothing else is seen).
    let up = tmp(
        "into_the_light.json",
        &LIT_FLOOR.replace(r#""look_at": [0, 0, 0]"#, r#""look_at": [0, 0, 3]"#),
    );
    for depth in [Some(0), None] {
        let data = lightproof::render::render_file(&up, 8, 1, depth)
            .expect("renders")
            .pixels;
        assert!(
            !data.is_empty() && data.iter().all(|&p| p == [10.0; 3]),
            "depth {depth:?}: {data:?}"
        );
    }
    // Without `--max-depth` a case's own `max_depth` bounds the paths (it was ignored:
    // a furnace of albedo 0.8 with `max_depth` 1 rendered its whole L = 5, not 1.8);
    // the flag, where given, overrides it.
    let furnace = r#"{
  "name": "furnace", "teaches": "L = Le/(1 − ρ)",
  "scene": {
    "materials": { "grey": { "type": "lambertian", "albedo": 0.8 } },
    "shapes": [ { "geometry": { "type": "sphere", "center": [0, 0, 0], "radius": 1 }, "material": "grey", "flip_normals": true, "emission": { "radiance": 1 } } ]
  },
  "camera": { "position": [0, 0, 0], "look_at": [0, 0, 1], "up": [0, 1, 0], "fov_degrees": 60, "width": 3, "height": 2 },
  "measure": { "radiance": { "at": [0, 0, 0], "direction": [0, 0, 1] } },
  "estimators": ["mis"], "max_depth": 1 }"#;
    let cut = tmp("furnace_depth_1.json", furnace);
    let whole = tmp("furnace.json", &furnace.replace(r#", "max_depth": 1"#, ""));
    let image = |path: &Path, depth: Option<u32>| {
        lightproof::render::render_file(path, 8, 1, depth)
            .expect("renders")
            .pixels
    };
    assert_eq!(image(&cut, None), image(&whole, Some(1)));
    assert_eq!(image(&cut, Some(3)), image(&whole, Some(3)));
    let mean = |p: Vec<[f32; 3]>| p.iter().map(|v| v[0] as f64).sum::<f64>() / p.len() as f64;
    // 48 paths: L₁ = 1.8 exactly at depth 1 (every path sees Le and its one bounce's Le),
    // about 5 without a limit.
    assert!((mean(image(&cut, None)) - 1.8).abs() < 1e-5);
    assert!(mean(image(&whole, None)) > 3.0);
}

fn catalog_case(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("analytic/cases")
        .join(rel)
}

/// `estimate CASE ARGS` (4096 samples unless ARGS give `--samples`), which must exit 0:
/// its JSON.
fn estimate_json(case: &Path, args: &[&str]) -> serde_json::Value {
    let samples: &[&str] = if args.contains(&"--samples") {
        &[]
    } else {
        &["--samples", "4096"]
    };
    let out = succeeds(bin().arg("estimate").arg(case).args(samples).args(args));
    serde_json::from_slice(&out.stdout).unwrap()
}

/// The README's `estimate` contract beyond the common fields: an estimate without
/// variance (a point light's irradiance, light sampling) prints `"exact": true` and no
/// `std_error`; a time-resolved histogram adds `bins`, one object per bin with its range;
/// every effect decision carries its reason.
#[test]
fn estimate_prints_exact_verdicts_bins_and_every_reason() {
    let v = estimate_json(&catalog_case("irradiance/point_light.json"), &[]);
    assert_eq!(v["exact"], serde_json::Value::Bool(true), "{v}");
    assert!(v.get("std_error").is_none(), "{v}");
    assert_eq!(v["verdict"]["class"], "exact", "{v}");
    let effects = v["effects"].as_object().unwrap();
    let decisions: Vec<&String> = effects.keys().filter(|k| *k != "max_bounces").collect();
    assert_eq!(decisions.len(), 8, "{v}");
    for k in decisions {
        let why = effects[k]["why"].as_str().unwrap_or_default();
        assert!(
            effects[k]["simulated"].is_boolean() && why.len() > 10,
            "{k}: {v}"
        );
    }
    let v = estimate_json(&catalog_case("time/pulsed_disk_transient.json"), &[]);
    assert_eq!(v["exact"], serde_json::Value::Bool(false), "{v}");
    assert!(v["std_error"].as_f64().is_some_and(|s| s > 0.0), "{v}");
    let bins = v["bins"].as_array().expect("bins");
    assert_eq!(bins.len(), 6, "{v}");
    for b in bins {
        let [lo, hi] = [0, 1].map(|i| b["bin"][i].as_f64().unwrap());
        assert!(lo < hi && b["verdict"]["passed"].is_boolean(), "{b}");
    }
}

/// `verify --json`'s family size `tests` counts the statistical verdicts only (no warp
/// suite when case files are named): exact verdicts are judged apart.
#[test]
fn verify_family_counts_the_statistical_verdicts() {
    let json =
        std::env::temp_dir().join(format!("lightproof-cli-family-{}.json", std::process::id()));
    let out = bin()
        .args(["verify", "--samples", "4096", "--no-chi2", "--json"])
        .arg(&json)
        .arg(catalog_case("irradiance/point_light.json"))
        .arg(catalog_case("irradiance/disk_on_axis.json"))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{stdout}");
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let classes: Vec<&str> = doc["outcomes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|o| o["verdict"]["class"].as_str().unwrap())
        .collect();
    let statistical = classes.iter().filter(|c| **c == "statistical").count();
    let exact = classes.iter().filter(|c| **c == "exact").count();
    assert_eq!(statistical + exact, classes.len());
    assert!(statistical > 0 && exact > 0, "{classes:?}");
    assert_eq!(doc["tests"].as_u64(), Some(statistical as u64), "{doc}");
    assert!(
        stdout.contains(&format!(
            "{} passed ({statistical} statistical, {exact} exact), 0 failed",
            classes.len()
        )),
        "{stdout}"
    );
    let _ = std::fs::remove_file(json);
}

/// `verify` over the whole catalog (what a bare `lightproof` runs) adds the warp suites'
/// chi-square tests to the family: k = the statistical verdicts + the warps, each warp
/// judged at the Šidák level for that k, as the summary line says. At 256 samples (to
/// keep it short) a few rare-event cases may fail; the family's size does not depend on it.
#[test]
fn the_whole_catalog_family_counts_the_warp_suites() {
    let json =
        std::env::temp_dir().join(format!("lightproof-cli-whole-{}.json", std::process::id()));
    let out = bin()
        .args(["verify", "--samples", "256", "--json"])
        .arg(&json)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(matches!(out.status.code(), Some(0 | 1)), "{stdout}");
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let statistical = doc["outcomes"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|o| o["verdict"]["class"] == "statistical")
        .count();
    let warps = doc["chi2"].as_array().unwrap();
    assert_eq!(warps.len(), lightproof::suites::warps().len());
    assert!(
        warps.len() >= 8 && statistical > 200,
        "{} {statistical}",
        warps.len()
    );
    let k = statistical + warps.len();
    assert_eq!(doc["tests"].as_u64(), Some(k as u64));
    let alpha1 = 1.0 - (1.0 - 1e-4f64).powf(1.0 / k as f64);
    for w in warps {
        let a = w["alpha"].as_f64().unwrap();
        assert!(
            (a / alpha1 - 1.0).abs() < 1e-9,
            "{}: α = {a}, want {alpha1}",
            w["name"]
        );
    }
    assert!(
        stdout.contains(&format!(
            "Šidák-corrected over k = {k} at family α = 0.0001"
        )),
        "{stdout}"
    );
    // `--no-chi2`: the same catalog without the warp suites, k = the statistical verdicts.
    let out = bin()
        .args(["verify", "--samples", "256", "--no-chi2", "--json"])
        .arg(&json)
        .output()
        .unwrap();
    assert!(matches!(out.status.code(), Some(0 | 1)));
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(doc["chi2"].as_array().map(Vec::len), Some(0));
    assert_eq!(doc["tests"].as_u64(), Some(statistical as u64));
    let _ = std::fs::remove_file(json);
}

/// An estimator the case does not list is outside the proof, and its failure says so:
/// BSDF sampling of a sphere light subtending 10⁻⁶ sr draws none of the directions that
/// meet it, so the estimate is 0 without variance; the case's own estimator (light
/// sampling) is the proof. (Until session 44 this was light sampling of the 10⁶-radius
/// blackbody disk, by area, off by eight orders; a disk seen from close by is now
/// sampled by a mixture that gets it right.) The seed is fixed (the default's): the
/// case's 2¹⁸ cosine-distributed directions meet the sphere, of density about
/// 10⁻⁶/π per direction, once or more for about 8% of seeds, and the estimate is then
/// not 0 (`LIGHTPROOF_SEED=2026` failed this test).
#[test]
fn an_estimator_the_case_does_not_list_is_named_in_its_failure() {
    let stdout = fails_on_catalog_case(
        "estimate",
        "irradiance/sphere_tiny_far.json",
        &["--estimator", "bsdf", "--seed", "1152112"],
    );
    assert!(
        stdout.contains("`bsdf` is not among the case's estimators (light), where its false-alarm rate is not established")
            && stdout.contains("run the case's own estimators to tell"),
        "{stdout}"
    );
}

/// A pass must be able to see a 0.5 % bias: a case whose own sample count is too small
/// for its estimators' variance (the disk light at 1024 samples sees only ~2.5 %) fails
/// saying so and how many more samples it needs; below the case's own count
/// (`--samples`) the same verdicts are weak passes, named in the table and the summary.
#[test]
fn a_pass_that_cannot_see_half_a_percent_fails_or_is_weak() {
    let few = tmp("few.json", &GOOD.replace("65536", "1024"));
    let out = bin().arg("verify").arg(&few).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{stdout}");
    for want in [
        "cannot see a relative bias below",
        "must see 0.5%, or its pass proves nothing: raise the case's `samples` to about",
        "0 passed (0 statistical, 0 exact), 2 failed",
    ] {
        assert!(stdout.contains(want), "`{want}` not in\n{stdout}");
    }
    // The factor is (detectable / 0.5%)² rounded up, the detectable bias falling as 1/√N
    // (README's example: 2.553% and 27×); read from each failure's reason.
    let mut reasons = 0;
    for line in stdout
        .lines()
        .filter(|l| l.contains("cannot see a relative bias below"))
    {
        let number_after = |key: &str| -> f64 {
            let rest = &line[line.find(key).unwrap() + key.len()..];
            let end = rest
                .find(|c: char| !(c.is_ascii_digit() || c == '.'))
                .unwrap();
            rest[..end].parse().unwrap()
        };
        let percent = number_after("cannot see a relative bias below ");
        let factor = number_after("to about ");
        // The percentage is printed to 3 decimals: the factor from either end of its
        // rounding interval.
        let bound = |p: f64| (p / 0.5).powi(2).ceil();
        assert!(
            percent > 0.5 && (bound(percent - 5e-4)..=bound(percent + 5e-4)).contains(&factor),
            "{line}"
        );
        reasons += 1;
    }
    assert_eq!(reasons, 2, "{stdout}");
    let (json, html) = (
        few.with_extension("weak.json"),
        few.with_extension("weak.html"),
    );
    let out = succeeds(
        bin()
            .arg("verify")
            .arg(&few)
            .args(["--samples", "256", "--json"])
            .arg(&json)
            .arg("--html")
            .arg(&html),
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    for want in [
        "weak\n",
        "2 passed (2 statistical, 0 exact), 0 failed",
        "2 of the 2 statistical passes are weak",
    ] {
        assert!(stdout.contains(want), "`{want}` not in\n{stdout}");
    }
    // The JSON says `"weak": true` on each verdict, the page labels them.
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let outcomes = doc["outcomes"].as_array().unwrap();
    assert!(
        outcomes.len() == 2
            && outcomes
                .iter()
                .all(|o| o["verdict"]["weak"] == true && o["verdict"]["passed"] == true),
        "{doc}"
    );
    let page = std::fs::read_to_string(&html).unwrap();
    assert_eq!(page.matches(">weak</td>").count(), 2, "{page}");
    assert!(page.contains("2 passed (2 of them weak: they cannot see a 0.5% bias), 0 failed"));
    // At its own count of 65536 the same case sees 0.5 %: plain passes.
    let good = tmp("good.json", GOOD);
    let out = succeeds(bin().arg("verify").arg(&good));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("2 passed (2 statistical, 0 exact), 0 failed"),
        "{stdout}"
    );
    assert!(!stdout.contains("weak"), "{stdout}");
}

/// A statistical pass whose reference is exactly 0 has no relative bias to see: at its
/// case's own count it is not failed but marked weak, with a closing line of its own
/// (README "How a verdict is reached"). The reference here faces away from a sphere light
/// the receiver sees (irradiance 0 by the closed form), so the BSDF-sampled estimate is a
/// few hits of the sphere, about 5 at the case's 4096 samples: noisy, and unable to see
/// an absolute bias of 0.005. The seed is fixed (the default's value): at other seeds
/// no hit at all gives an exact verdict, and 16 or more a failure.
#[test]
fn a_zero_reference_pass_that_cannot_see_its_bias_is_weak_on_a_line_of_its_own() {
    let zero = tmp(
        "zero.json",
        r#"{
  "name": "zero", "teaches": "a zero reference has no relative bias to see",
  "scene": { "shapes": [ { "geometry": { "type": "sphere", "center": [0, 0, 10], "radius": 0.35 }, "emission": { "radiance": 1 } } ] },
  "measure": { "irradiance": { "at": [0, 0, 0], "normal": [0, 0, 1] } },
  "reference": { "closed_form": "sphere_irradiance", "point": [0, 0, 0], "normal": [0, 0, -1], "center": [0, 0, 10], "radius": 0.35, "radiance": 1 },
  "estimators": ["bsdf"], "samples": 4096 }"#,
    );
    let run = |extra: &[&str]| {
        let out = succeeds(
            bin()
                .arg("verify")
                .arg(&zero)
                .args(["--seed", "1152112"])
                .args(extra),
        );
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    let own = run(&[]);
    for want in [
        " weak\n",
        "1 passed (1 statistical, 0 exact), 0 failed",
        "1 of the 1 statistical passes are weak: their reference is 0, so there is no relative bias to see, and they cannot see an absolute one of 0.005 (in their case's units): raise their case's samples",
    ] {
        assert!(own.contains(want), "`{want}` not in\n{own}");
    }
    assert!(!own.contains("fewer samples"), "{own}");
    // Below the case's own count the cause is the count: the other line.
    let fewer = run(&["--samples", "1024"]);
    assert!(
        fewer.contains("1 of the 1 statistical passes are weak: drawn with fewer samples")
            && !fewer.contains("their reference is 0"),
        "{fewer}"
    );
}

/// A case without a reference is estimated, not judged: `verify`'s closing line counts its
/// outcomes apart, never as statistical passes (they were, and the family's k = 2 beside
/// "4 statistical" said otherwise).
#[test]
fn outcomes_without_a_reference_are_not_counted_as_statistical_passes() {
    let good = tmp("judged.json", GOOD);
    let free = tmp(
        "unjudged.json",
        &GOOD
            .replace("disk on axis", "disk on axis, no reference")
            .replace(
                r#""reference": { "closed_form": "disk_irradiance_on_axis", "radius": 1, "height": 2, "radiance": 1 },"#,
                "",
            ),
    );
    let out = succeeds(bin().arg("verify").arg(&good).arg(&free));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains(
            "4 passed (2 statistical, 0 exact, 2 without a reference: estimated, not judged), 0 failed"
        ) && stdout.contains("k = 2 at family"),
        "{stdout}"
    );
}

/// A conductor at η = 1.0001, which `f32` holds as 1.00010001659: its reference moves by
/// 3.3·10⁻⁴ relative at the engine's inputs. `verify` passes it (it failed a correct
/// engine, z = +43.5), writes the movement as `reference_rounding` and says in its closing
/// line how many verdicts took it in; a case whose numbers `f32` holds exactly, and one
/// without a reference, take none.
#[test]
fn verify_takes_in_the_references_change_at_f32_inputs() {
    // η = 1.0001 rounds up in f32 (ρ > 0), η = 1.0004 down (1.00039994716: ρ < 0).
    let conductor = |eta: &str| {
        format!(
            r#"{{ "name": "conductor at {eta}", "teaches": "F = ((η − 1)/(η + 1))²",
  "exact": "a mirror: every sample is F",
  "measure": {{ "albedo": {{ "bsdf": {{ "type": "conductor", "eta": {eta}, "k": 0 }}, "theta_degrees": 0 }} }},
  "reference": {{ "closed_form": "fresnel_conductor", "cos_theta": 1, "eta": {eta}, "k": 0 }},
  "estimators": ["bsdf"], "samples": 4096 }}"#
        )
    };
    let up = tmp("eta_up.json", &conductor("1.0001"));
    let down = tmp("eta_down.json", &conductor("1.0004"));
    let good = tmp("rounding_good.json", GOOD);
    let free = tmp(
        "rounding_free.json",
        &GOOD.replace("disk on axis", "no reference").replace(
            r#""reference": { "closed_form": "disk_irradiance_on_axis", "radius": 1, "height": 2, "radiance": 1 },"#,
            "",
        ),
    );
    let json = up.with_extension("out.json");
    let out = succeeds(
        bin()
            .args(["verify", "--json"])
            .arg(&json)
            .args([&up, &down, &good, &free]),
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains(
            "7.63e-6·|reference|; 2 verdicts also allow the reference's change at the engine's f32 inputs; seed"
        ),
        "{stdout}"
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    for o in v["outcomes"].as_array().unwrap() {
        let rho = o["reference_rounding"].as_f64();
        let r = o["reference"].as_f64().unwrap_or(0.0);
        let want = match o["case"].as_str().unwrap() {
            "conductor at 1.0001" => Some((3e-4, 4e-4)),
            "conductor at 1.0004" => Some((-3e-4, -2e-4)),
            _ => None,
        };
        match (want, rho) {
            (Some((lo, hi)), Some(rho)) => {
                assert!(rho > lo * r && rho < hi * r, "{o}");
                assert_eq!(o["verdict"]["input_rounding"].as_f64(), Some(rho));
            }
            (None, None) => assert!(o["verdict"].get("input_rounding").is_none(), "{o}"),
            _ => panic!("{o}"),
        }
    }
    let out = succeeds(bin().arg("verify").args([&good, &free]));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("7.63e-6·|reference|; seed") && !stdout.contains("engine's f32 inputs"),
        "{stdout}"
    );
}

/// `estimate` runs the case's first sampler unless told (a Sobol-only case runs Sobol:
/// inside the proof), and a sampler the case does not list is outside it: the sphere
/// light below the horizon by independent sampling sees only ~2.4 % at the case's own
/// count, a weak pass (exit 0, `"weak": true`), where the case's own Sobol run is a plain
/// pass at the same count.
#[test]
fn estimate_runs_the_cases_sampler_and_an_unlisted_one_is_weak() {
    let case = catalog_case("irradiance/sphere_near_surface_centre_below_horizon_gap_1e-3.json");
    let own = estimate_json(&case, &["--samples", "262144"]);
    assert_eq!(own["sampler"], "sobol", "{own}");
    assert!(
        own["verdict"]["passed"] == true && own["verdict"].get("weak").is_none(),
        "{own}"
    );
    let other = estimate_json(&case, &["--samples", "262144", "--sampler", "independent"]);
    assert_eq!(other["sampler"], "independent", "{other}");
    let v = &other["verdict"];
    assert!(
        v["passed"] == true
            && v["weak"] == true
            && v["detectable_relative_bias"].as_f64().unwrap() > 0.005,
        "{other}"
    );
}

/// `estimate` applies `verify`'s rule: at the case's own sample count a statistical pass
/// that cannot see a 0.5% bias fails (exit 1, `"passed": false`, the reason saying how
/// many more samples would see it); below that count the same verdict is a weak pass.
#[test]
fn estimate_fails_a_blind_pass_at_the_cases_own_count() {
    let case = tmp("own_1024.json", &GOOD.replace("65536", "1024"));
    let out = bin()
        .args(["estimate", "--estimator", "light"])
        .arg(&case)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(1), "{stdout}");
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let verdict = &v["verdict"];
    assert!(
        verdict["passed"] == false
            && verdict.get("weak").is_none()
            && verdict["reason"]
                .as_str()
                .is_some_and(|r| r.contains("cannot see a relative bias below")),
        "{v}"
    );
    let below = estimate_json(&case, &["--estimator", "light", "--samples", "512"]);
    assert!(
        below["verdict"]["passed"] == true && below["verdict"]["weak"] == true,
        "{below}"
    );
}

/// Every case file README.md shows (its ```json blocks) is a whole case that `verify`
/// runs and passes at its own count, none weak: the README's examples cannot drift from
/// the schema or the oracle.
#[test]
fn the_readmes_case_files_pass_verify() {
    let readme =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md")).unwrap();
    let blocks: Vec<&str> = readme
        .split("```json\n")
        .skip(1)
        .map(|rest| rest.split("```").next().unwrap())
        .collect();
    assert!(
        blocks.len() >= 8,
        "{} JSON blocks in README.md",
        blocks.len()
    );
    let files: Vec<PathBuf> = blocks
        .iter()
        .enumerate()
        .map(|(i, text)| tmp(&format!("readme_{i}.json"), text))
        .collect();
    let out = bin()
        .args(["verify", "--no-chi2"])
        .args(&files)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success()
            && !stdout.contains("weak")
            && stdout.contains(&format!("({} cases,", blocks.len())),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Exit 3 for worker threads that cannot start (README: "3 an output that cannot be
/// written or worker threads that cannot start"): the address space is capped just above
/// what the binary needs to start (found by running `--version` under caps growing by
/// 1/16), so not one thread's stack (2 MiB) can be mapped. With more room (4 MiB above a
/// cap found in steps of 1/4, as before) a thread could map its stack but not the signal
/// stack the standard library gives each thread, and std's own panic message for it
/// joined ours on stderr in about 1 run in 20. Unix shells only.
#[cfg(unix)]
#[test]
fn worker_threads_that_cannot_start_exit_3() {
    let exe = env!("CARGO_BIN_EXE_lightproof");
    let capped = |kib: u64, args: &[&str]| {
        Command::new("sh")
            .arg("-c")
            .arg(format!("ulimit -v {kib} && exec \"$0\" \"$@\""))
            .arg(exe)
            .args(args)
            .output()
            .unwrap()
    };
    let mut kib = 8 * 1024;
    while !capped(kib, &["--version"]).status.success() {
        kib += kib / 16;
        assert!(kib < 4 << 20, "--version never ran under a cap up to 4 GiB");
    }
    let case = tmp("threads.json", GOOD);
    let case = case.to_str().unwrap();
    let out = capped(
        kib + 512,
        &["estimate", case, "--threads", "16", "--samples", "1024"],
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(3), "{err}");
    assert!(
        err.trim_end().lines().count() == 1
            && err.starts_with("error: worker threads: cannot start:"),
        "{err}"
    );
}

/// `verify --samples 16384 --json` on `cases` with `args` and environment `env`, which
/// must exit 0: (stdout, the JSON report without its wall seconds).
fn verify_json(
    label: &str,
    args: &[&str],
    env: &[(&str, &str)],
    cases: &[&str],
) -> (String, serde_json::Value) {
    let json = std::env::temp_dir().join(format!(
        "lightproof-cli-{label}-{}.json",
        std::process::id()
    ));
    let out = bin()
        .args(["verify", "--samples", "16384"])
        .args(args)
        // The C library's own defaults and the CPU's own instruction set for the ray
        // queries unless `env` says otherwise.
        .env_remove("GLIBC_TUNABLES")
        .env_remove("LIGHTPROOF_ISA")
        .envs(env.iter().copied())
        .arg("--json")
        .arg(&json)
        .args(cases.iter().map(|c| catalog_case(c)))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert_eq!(out.status.code(), Some(0), "{stdout}");
    let mut doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let _ = std::fs::remove_file(json);
    for o in doc["outcomes"].as_array_mut().unwrap() {
        o.as_object_mut().unwrap().remove("seconds");
    }
    (stdout, doc)
}

/// `verify` gives the same verdicts whatever `--threads` is (only the wall seconds
/// differ), time bins included: each bin of a time-resolved case is its own row
/// (`ID t∈[t₁, t₂] ns`) and a member of the family.
#[test]
fn verify_is_the_same_whatever_the_threads_and_judges_every_bin() {
    let run = |threads: &str| {
        verify_json(
            &format!("threads-{threads}"),
            &["--threads", threads],
            &[],
            &[
                "time/pulsed_disk_transient.json",
                "irradiance/disk_on_axis.json",
            ],
        )
    };
    let (one, doc1) = run("1");
    let (_, doc2) = run("2");
    assert_eq!(doc1, doc2);
    let outcomes = doc1["outcomes"].as_array().unwrap();
    // Two estimators (light, MIS) × 6 bins.
    let bins = outcomes.iter().filter(|o| o.get("bin").is_some()).count();
    assert_eq!(bins, 12);
    let statistical = outcomes
        .iter()
        .filter(|o| o["verdict"]["class"] == "statistical")
        .count();
    assert!(statistical > bins / 2, "{statistical}");
    assert_eq!(doc1["tests"].as_u64(), Some(statistical as u64));
    let rows = one
        .lines()
        .filter(|l| l.starts_with("pulsed_disk_transient t∈["))
        .count();
    assert_eq!(rows, 12, "{one}");
}

/// `verify` gives the same bits whichever code path the C library picks for this CPU (the
/// README's run over the whole catalog found all 282 estimates equal; here six cases). glibc chooses its `exp`, `log`, `sin`, `atan2`… by the CPU's features (variants
/// built for FMA and AVX2, or for SSE2 alone), and the engine (Beckmann's erf through
/// statrs, the blackbody's exponentials, microfacet and Oren–Nayar trigonometry, the
/// spherical triangle's and the sphere cone's angles) and the oracle call them. With those
/// features masked (`GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA,-AVX512F`, which glibc
/// 2.36 honours: callgrind shows `__ieee754_atan2_avx` and `__sincos_sse2` called instead
/// of the `_fma` ones), `verify` gives the same JSON. Where the C library ignores the
/// tunable, or the CPU has neither FMA nor AVX2, both runs take one path and this proves
/// determinism only.
#[test]
fn verify_is_the_same_whatever_the_c_librarys_cpu_path() {
    let cases = [
        "bsdf_albedo/rough_conductor_beckmann_alpha0_5_0_uncorrelated.json",
        "bsdf_albedo/rough_dielectric_ggx_alpha0_3_60.json",
        "bsdf_albedo/oren_nayar_fujii_sigma0_5_60.json",
        "spectral/blackbody_visible_band_3000K.json",
        "irradiance/triangle_light.json",
        "irradiance/sphere_light.json",
    ];
    let (_, native) = verify_json("libc-native", &[], &[], &cases);
    let (_, baseline) = verify_json(
        "libc-baseline",
        &[],
        &[("GLIBC_TUNABLES", "glibc.cpu.hwcaps=-AVX2,-FMA,-AVX512F")],
        &cases,
    );
    assert!(native["outcomes"].as_array().unwrap().len() > cases.len());
    assert_eq!(native, baseline);
}

/// The BVH's queries give the same bits in the x86-64 baseline (`LIGHTPROOF_ISA=baseline`)
/// as in the x86-64-v3 code a newer CPU runs (the box test eight children wide, FMA and
/// bit counts as instructions): `verify` of catalog cases whose scenes go through boxes
/// (more than three primitives: eight boxes at a time without a tree) gives the same JSON, and `estimate` of the Cornell-like
/// box the same line. On a CPU below x86-64-v3 both runs take the baseline and this proves
/// determinism only (`accel::tests::both_instruction_sets_give_the_same_bits` says which).
#[test]
fn verify_is_the_same_in_every_instruction_set() {
    let cases = [
        "furnace/closed_cube_mesh_0_5.json",
        "depth/closed_cube_mesh_albedo_1_6_bounces.json",
        "depth/closed_cube_mesh_2_bounces_0_5.json",
        "time/mean_chord_box.json",
    ];
    let (_, native) = verify_json("isa-native", &[], &[], &cases);
    let (_, baseline) = verify_json(
        "isa-baseline",
        &[],
        &[("LIGHTPROOF_ISA", "baseline")],
        &cases,
    );
    assert!(native["outcomes"].as_array().unwrap().len() >= cases.len());
    assert_eq!(native, baseline);
    let cornell =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("analytic/scenes/cornell.json");
    let [a, b] = ["native", "baseline"].map(|isa| {
        let out = succeeds(
            bin()
                .arg("estimate")
                .arg(&cornell)
                .args(["--samples", "8192"])
                .env("LIGHTPROOF_ISA", isa),
        );
        let mut v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        v.as_object_mut().unwrap().remove("seconds");
        v
    });
    assert!(a["estimate"].as_f64().unwrap() > 0.0, "{a}");
    assert_eq!(a, b);
}

/// An instruction set `LIGHTPROOF_ISA` does not know is a usage error naming the
/// variable and what it accepts, before any work.
#[test]
fn an_unknown_instruction_set_is_refused() {
    let out = bin()
        .arg("verify")
        .env("LIGHTPROOF_ISA", "avx512")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert_eq!(
        err.trim_end(),
        "error: <environment>: LIGHTPROOF_ISA: must be `baseline` or `native`, got \"avx512\""
    );
    assert!(out.stdout.is_empty());
}

/// An estimate without variance that misses its reference fails, saying what it cannot
/// tell apart: the BSDF estimator of the sphere light 1e-4 radii away hits the sphere with
/// every one of 4096 Sobol samples (it misses only a ring of probability ~2e-4 at grazing
/// angles), so its samples agree and the estimate is π, not the reference's 3.140965. The
/// message names the sample count, the unseen mass (7.3e-4) and the remedy; at the case's
/// own sample count the ring is reached and the verdict is statistical (the catalog).
/// The seed is pinned, not `LIGHTPROOF_SEED`'s: the message is what is tested, and it
/// needs a seed whose 4096 samples all miss the ring, which happens once in 20 seeds
/// (the default is one; at seed 1 a sample reaches it and the verdict is a statistical
/// pass).
#[test]
fn an_estimate_without_variance_that_misses_says_why() {
    let stdout = fails_on_catalog_case(
        "verify",
        "irradiance/sphere_near_surface_on_axis_gap_1e-4.json",
        &["--samples", "4096", "--seed", "1152112"],
    );
    for want in [
        "bsdf/sobol",
        "(exact)",
        "no variance in 4096 samples, yet off by 6.277e-4",
        "a region of probability 7.3e-4 is missed by all of them once in 20 runs",
        "run more samples to tell",
        // --samples below the case's own count (2^18) is named as such.
        "drew 4096 samples, fewer than the case's own 262144",
        "1 of the 1 failures drew fewer samples than their case's own count",
    ] {
        assert!(stdout.contains(want), "`{want}` not in\n{stdout}");
    }
}

/// A time-resolved case exits 1 when any bin fails: the transient of the pulsed disk
/// judged against a reference radiance 5% too high fails every bin (each detects a
/// few-% bias at 4096 samples), and against its own reference passes.
#[test]
fn a_failing_time_bin_fails_the_estimate() {
    let good = catalog_case("time/pulsed_disk_transient.json");
    let mut doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&good).unwrap()).unwrap();
    // Light 3% faster in the reference: the bins' references move, while the whole
    // span, which holds the entire transient (h/c to √(h² + R²)/c), keeps the same
    // total. So only the bins can fail the run.
    doc["reference"]["speed"] = serde_json::json!(299_792_458.0 * 1.03);
    let bad = tmp("transient_wrong.json", &doc.to_string());
    for (case, code) in [(good, 0), (bad, 1)] {
        let out = bin()
            .arg("estimate")
            .arg(&case)
            .args(["--samples", "16384"])
            .output()
            .unwrap();
        assert_eq!(
            out.status.code(),
            Some(code),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let failed = v["bins"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|b| b["verdict"]["passed"] == false)
            .count();
        assert_eq!(failed > 0, code == 1, "{v}");
        assert_eq!(v["verdict"]["passed"], true, "the whole span passes: {v}");
    }
}

/// A standard output that cannot be written (`> /dev/full`) is an output that cannot be
/// written: exit 3 and one line naming it, where `println!` panicked (exit 101). The
/// commands that print a table or a JSON object all write through the same helper.
#[cfg(target_os = "linux")]
#[test]
fn a_stdout_that_cannot_be_written_exits_3() {
    let case = tmp("stdout_full.json", GOOD);
    let case = case.to_str().unwrap();
    for args in [
        &["estimate", case, "--samples", "256"][..],
        &["verify", case, "--samples", "256", "--no-chi2"][..],
    ] {
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap();
        let out = bin()
            .args(args)
            .env_remove("RUST_BACKTRACE")
            .stdout(full)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(3), "{args:?}: {err}");
        assert_eq!(
            err.trim(),
            "error: <stdout>: cannot write: No space left on device (os error 28)",
            "{args:?}"
        );
    }
}

/// A standard error that cannot be written (`2> /dev/full`) loses the message, never the
/// outcome: each exit status is the one a readable stderr would give (a missing file 2,
/// a usage error 2, a written render 0), where `eprintln!` panicked (exit 101).
#[cfg(target_os = "linux")]
#[test]
fn a_stderr_that_cannot_be_written_keeps_the_exit_status() {
    let dir = std::env::temp_dir().join(format!("lightproof-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("analytic/scenes/cornell.json");
    let png = dir.join("stderr_full.png");
    let missing = dir.join("no such case.json");
    for (args, code) in [
        (vec!["estimate".into(), missing.into_os_string()], 2),
        (vec!["--no-such-flag".into()], 2),
        (
            vec![
                "render".into(),
                scene.into_os_string(),
                "--spp".into(),
                "1".into(),
                "-o".into(),
                png.into_os_string(),
            ],
            0,
        ),
    ] {
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap();
        let out = bin()
            .args(&args)
            .env_remove("RUST_BACKTRACE")
            .stderr(full)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(code), "{args:?}");
    }
}

/// `report --shard auto` reads only its own variables of the environment: a variable of
/// no concern to it may hold any bytes (`JUNK=\xff` once panicked in `std::env::vars`),
/// and one of its own that is not UTF-8 exits 2 naming it.
#[cfg(unix)]
#[test]
fn shard_auto_reads_only_its_own_variables() {
    use std::ffi::OsStr;
    use std::os::unix::ffi::OsStrExt;
    let case = tmp("shard_env.json", GOOD);
    let junk = OsStr::from_bytes(b"\xff");
    let run = |out: &str, env: &[(&str, &OsStr)]| {
        let dir = std::env::temp_dir().join(format!("lightproof-cli-{}-{out}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let mut c = bin();
        c.arg("report")
            .arg(&case)
            .args([
                "--shard",
                "auto",
                "--max-samples",
                "256",
                "--sampler",
                "independent",
            ])
            .arg("--out")
            .arg(&dir)
            .env_remove("RUST_BACKTRACE");
        for (k, v) in env {
            c.env(k, v);
        }
        let o = c.output().unwrap();
        let _ = std::fs::remove_dir_all(&dir);
        o
    };
    let (zero, one) = (OsStr::new("0"), OsStr::new("1"));
    let ok = run(
        "junk",
        &[
            ("JUNK", junk),
            ("LIGHTPROOF_SHARD_INDEX", zero),
            ("LIGHTPROOF_SHARD_COUNT", one),
        ],
    );
    let err = String::from_utf8_lossy(&ok.stderr);
    assert_eq!(ok.status.code(), Some(0), "{err}");
    let bad = run(
        "bad",
        &[
            ("LIGHTPROOF_SHARD_INDEX", junk),
            ("LIGHTPROOF_SHARD_COUNT", one),
        ],
    );
    let err = String::from_utf8_lossy(&bad.stderr);
    assert_eq!(bad.status.code(), Some(2), "{err}");
    assert!(
        err.trim().lines().count() == 1
            && err.contains("LIGHTPROOF_SHARD_INDEX: is not UTF-8 text")
            && !err.contains("panicked"),
        "{err}"
    );
}

/// `LIGHTPROOF_SEED`, the default `--seed` of every command that samples, holding text
/// that is not UTF-8 is a usage error naming it (clap's own message named nothing), for a
/// command given and for a bare `lightproof`; a command without a seed (`merge`) does not
/// read it.
#[cfg(unix)]
#[test]
fn a_seed_variable_that_is_not_text_is_named() {
    use std::os::unix::ffi::OsStrExt;
    let junk = std::ffi::OsStr::from_bytes(b"7\xff");
    let case = tmp("seed_env.json", GOOD);
    let dir = std::env::temp_dir().join(format!("lightproof-cli-seed-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for args in [vec!["estimate".into(), case.display().to_string()], vec![]] {
        let out = bin()
            .args(&args)
            .current_dir(&dir)
            .env("LIGHTPROOF_SEED", junk)
            .env_remove("RUST_BACKTRACE")
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            err.trim().lines().count() == 1
                && err.starts_with("error: <environment>: LIGHTPROOF_SEED: is not UTF-8 text"),
            "{args:?}: {err}"
        );
    }
    let merge = bin()
        .args(["merge", "--out"])
        .arg(dir.join("rep"))
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/corpus/merge/merge_valid"))
        .env("LIGHTPROOF_SEED", junk)
        .output()
        .unwrap();
    assert_eq!(
        merge.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&merge.stderr)
    );
    // A merge computes nothing: its closing line says the shards did (it said "45 points
    // computed").
    let said = String::from_utf8_lossy(&merge.stdout);
    assert!(
        said.contains(" points merged (computed by the shards), 0 resumed"),
        "{said}"
    );
    // Another usage error is told as it is, not blamed on the variable.
    let usage = bin()
        .arg("merge")
        .env("LIGHTPROOF_SEED", junk)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&usage.stderr);
    assert_eq!(usage.status.code(), Some(2), "{err}");
    // One line: clap's usage and its "For more information" are left out.
    assert_eq!(
        err.trim(),
        "error: the following required arguments were not provided: <INPUTS>... (see --help)"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A folder holding `a.json` and two links to itself (`l1 -> .`, `l2 -> .`) is one case,
/// found at once: links to folders are not followed (one such link once listed the case
/// 41 times, two exponentially often).
#[cfg(unix)]
#[test]
fn links_to_folders_are_not_followed() {
    let dir = std::env::temp_dir().join(format!("lightproof-cli-links-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("a.json"), GOOD).unwrap();
    for link in ["l1", "l2"] {
        std::os::unix::fs::symlink(".", dir.join(link)).unwrap();
    }
    let t0 = std::time::Instant::now();
    let out = succeeds(
        bin()
            .arg("verify")
            .arg(&dir)
            .args(["--no-chi2", "--samples", "256"]),
    );
    let seconds = t0.elapsed().as_secs_f64();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("(1 cases, "), "{stdout}");
    // One case of 256 samples: well under a second; 41² copies would take minutes.
    assert!(seconds < 30.0, "{seconds:.1}s");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// An output that is an input is refused before any work, naming the flag, the path and
/// the input, and the input is left as it was: `verify in.json --json in.json` replaced
/// the case with the verdict; a `.json` written inside a folder `verify` reads would be
/// read as a case next run; `report`'s flat `--out` holding the case file would get its
/// report over it; `export` and `render` would write over their own input; `verify`
/// wrote its page over the OBJ a case reads, and one output over the other.
#[test]
fn an_output_on_an_input_is_refused_before_any_work() {
    let dir = std::env::temp_dir().join(format!("lightproof-cli-clash-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("cases")).unwrap();
    let case = dir.join("in.json");
    std::fs::write(&case, GOOD).unwrap();
    std::fs::write(dir.join("cases/case.json"), GOOD).unwrap();
    // The scene of a render by an image's name: `render` reads what it is given.
    let scene = dir.join("scene.exr");
    std::fs::write(
        &scene,
        GOOD.replace(
            "\"measure\"",
            "\"camera\": { \"position\": [0, 0, 0], \"look_at\": [0, 0, 1], \"up\": [0, 1, 0], \"fov_degrees\": 40, \"width\": 4, \"height\": 4 }, \"measure\"",
        ),
    )
    .unwrap();
    // A case lit by a triangle read from an OBJ file.
    const OBJ: &str = "v -5 -5 2\nv 5 -5 2\nv 0 5 2\nf 1 3 2\n";
    std::fs::write(dir.join("tri.obj"), OBJ).unwrap();
    std::fs::write(
        dir.join("mesh.json"),
        GOOD.replace(
            r#"{ "type": "disk", "center": [0, 0, 2], "normal": [0, 0, -1], "radius": 1 }"#,
            r#"{ "type": "obj", "path": "tri.obj" }"#,
        )
        .replace(
            r#"  "reference": { "closed_form": "disk_irradiance_on_axis", "radius": 1, "height": 2, "radiance": 1 },
"#,
            "",
        ),
    )
    .unwrap();
    let runs: [(&[&str], &str, &str); 11] = [
        (
            &["verify", "in.json", "--json", "in.json"],
            "--json: `in.json`",
            "is the input file `in.json`",
        ),
        (
            &["verify", "in.json", "--html", "./in.json"],
            "--html: `./in.json`",
            "is the input file",
        ),
        (
            &["verify", "cases", "--json", "cases/new/v.json"],
            "--json: `cases/new/v.json`",
            "lies inside the input folder `cases`",
        ),
        (
            &["report", "cases", "--out", "cases/rep"],
            "--out: `cases/rep`",
            "inside the input folder `cases`",
        ),
        (
            &["report", "in.json", "--out", "."],
            "--out: `.`",
            "holds the input file `in.json`",
        ),
        (
            &[
                "export",
                "cases/case.json",
                "--to",
                "mitsuba",
                "--out",
                "cases",
            ],
            "--out: `cases/case.json`",
            "is the input file",
        ),
        (
            &[
                "export", "--all", "cases", "--to", "mitsuba", "--out", "cases/x",
            ],
            "--out: `cases/x`",
            "inside the input folder `cases`",
        ),
        (
            &["render", "scene.exr", "--spp", "1", "-o", "scene.exr"],
            "-o: `scene.exr`",
            "is the input file `scene.exr`",
        ),
        (
            &["verify", "mesh.json", "--html", "tri.obj"],
            "--html: `tri.obj`",
            "is the input file",
        ),
        (
            &["verify", "mesh.json", "--json", "./tri.obj"],
            "--json: `./tri.obj`",
            "is the input file",
        ),
        (
            &[
                "verify", "in.json", "--json", "v.json", "--html", "./v.json",
            ],
            "--html: `./v.json`",
            "is the file --json names",
        ),
    ];
    for (args, what, why) in runs {
        let out = bin().args(args).current_dir(&dir).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            err.starts_with(&format!("error: <command line>: {what} ")) && err.contains(why),
            "{args:?}: {err}"
        );
        assert_eq!(std::fs::read_to_string(&case).unwrap(), GOOD, "{args:?}");
        assert_eq!(
            std::fs::read_to_string(dir.join("cases/case.json")).unwrap(),
            GOOD,
            "{args:?}"
        );
        let names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .flatten()
            .map(|e| e.file_name())
            .collect();
        assert_eq!(std::fs::read_to_string(dir.join("tri.obj")).unwrap(), OBJ);
        assert_eq!(names.len(), 5, "{args:?}: nothing written: {names:?}");
        assert_eq!(
            std::fs::read_dir(dir.join("cases")).unwrap().count(),
            1,
            "{args:?}"
        );
    }
    // A verdict beside the case, or HTML in the folder, is written.
    for args in [
        &["verify", "in.json", "--samples", "256", "--json", "v.json"][..],
        &[
            "verify",
            "cases",
            "--samples",
            "256",
            "--html",
            "cases/v.html",
        ][..],
    ] {
        let out = bin().args(args).current_dir(&dir).output().unwrap();
        assert_ne!(
            out.status.code(),
            Some(2),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// An output file named with a trailing separator names a folder: refused before the
/// work (exit 3, as a folder in its place is), where it once failed at the rename after
/// the whole run, and no folder is made.
#[test]
fn an_output_file_ending_in_a_separator_is_refused_before_any_work() {
    let dir = std::env::temp_dir().join(format!("lightproof-cli-slash-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("in.json"), GOOD).unwrap();
    for args in [
        &["verify", "in.json", "--json", "newdir/"][..],
        &["verify", "in.json", "--html", "page.html/"][..],
        &["render", "in.json", "-o", "x.exr/"][..],
    ] {
        let t0 = std::time::Instant::now();
        let out = bin().args(args).current_dir(&dir).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(3), "{args:?}: {err}");
        assert!(err.contains("names a folder"), "{args:?}: {err}");
        assert!(
            t0.elapsed().as_secs_f64() < 5.0,
            "{args:?}: before the work"
        );
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1, "{args:?}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A `LIGHTPROOF_SEED` that is no seed is named as the variable, not as a `--seed` no one
/// gave (an explicit `--seed` wins over it); an empty one counts as unset: the default
/// seed, as with no variable.
#[test]
fn a_seed_variable_that_is_no_number_is_named_and_an_empty_one_is_unset() {
    let case = tmp("seed_abc.json", GOOD);
    let run = |seed: Option<&str>, args: &[&str]| {
        let mut c = bin();
        c.args(args).arg(&case).env_remove("LIGHTPROOF_SEED");
        if let Some(s) = seed {
            c.env("LIGHTPROOF_SEED", s);
        }
        c.output().unwrap()
    };
    let out = run(Some("abc"), &["estimate", "--samples", "256"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.starts_with("error: <environment>: LIGHTPROOF_SEED: must be a whole number")
            && err.contains("got `abc`")
            && !err.contains("'--seed"),
        "{err}"
    );
    // The flag's own bad value is still the flag's.
    let out = run(
        Some("abc"),
        &["estimate", "--samples", "256", "--seed", "x"],
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("'--seed <SEED>'") && err.contains("got `x`"),
        "{err}"
    );
    // An explicit --seed wins over the variable.
    succeeds(
        bin()
            .args(["estimate", "--samples", "256", "--seed", "5"])
            .arg(&case)
            .env("LIGHTPROOF_SEED", "abc"),
    );
    let seed_of = |o: std::process::Output| -> serde_json::Value {
        assert_eq!(
            o.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
        serde_json::from_slice::<serde_json::Value>(&o.stdout).unwrap()["estimate"].clone()
    };
    assert_eq!(
        seed_of(run(Some(""), &["estimate", "--samples", "256"])),
        seed_of(run(None, &["estimate", "--samples", "256"]))
    );
}

/// Help and the version written to a standard output that cannot be written exit 3, as
/// every other output does (they exited 0); `verify --help` says when the chi-square
/// suites run.
#[cfg(target_os = "linux")]
#[test]
fn help_that_cannot_be_written_exits_3() {
    for args in [
        &["--help"][..],
        &["--version"],
        &["verify", "--help"],
        &["help"],
    ] {
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap();
        let out = bin().args(args).stdout(full).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(3), "{args:?}: {err}");
        assert!(
            err.starts_with("error: <stdout>: cannot write:"),
            "{args:?}: {err}"
        );
    }
    let help = succeeds(bin().args(["verify", "--help"]));
    let help = String::from_utf8_lossy(&help.stdout);
    assert!(
        help.contains("which run only when no PATH is given"),
        "{help}"
    );
}

/// Every `--wo` refusal names its source as the other flags' do, `<command line>: --wo:`
/// (the one for text that is no number once lacked it), before any sampling.
#[test]
fn every_wo_refusal_names_the_command_line() {
    for wo in ["", "up", "30", "200,0"] {
        let out = bin()
            .args([
                "chi2",
                r#"{"type":"lambertian","albedo":0.5}"#,
                "--wo",
                wo,
                "--out",
            ])
            .arg(std::env::temp_dir().join(format!("lightproof-cli-wo-{}", std::process::id())))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{wo:?}: {err}");
        assert!(
            err.starts_with("error: <command line>: --wo: "),
            "{wo:?}: {err}"
        );
    }
}

/// Ctrl-C (SIGINT) during a `report`, at several moments while it writes its reports: it
/// exits 130 and leaves every report whole (each parses) and no `.NAME.tmpPID` beside
/// them. A temporary once stayed behind an interrupted write, removed only by a later
/// write to the same target.
#[cfg(unix)]
#[test]
fn an_interrupt_leaves_no_temporary_and_every_file_whole() {
    let cases = Path::new(env!("CARGO_MANIFEST_DIR")).join("analytic/cases");
    let dir = std::env::temp_dir().join(format!("lightproof-cli-sigint-{}", std::process::id()));
    for (k, after) in [0u64, 300, 700].into_iter().enumerate() {
        let out = dir.join(format!("r{k}"));
        let _ = std::fs::remove_dir_all(&out);
        let child = bin()
            .args(["report", "--max-samples", "1048576", "--out"])
            .arg(&out)
            .arg(cases.join("furnace"))
            .arg(cases.join("irradiance"))
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        // Once the first report is written, then `after` ms later.
        let t0 = std::time::Instant::now();
        while std::fs::read_dir(&out).map_or(0, |d| d.count()) == 0 && t0.elapsed().as_secs() < 60 {
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        std::thread::sleep(std::time::Duration::from_millis(after));
        // SAFETY: a plain kill(2) of the child this test spawned.
        assert_eq!(unsafe { libc::kill(child.id() as i32, libc::SIGINT) }, 0);
        let o = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(130), "after {after} ms: {err}");
        assert!(
            err.contains("interrupted: every file written is whole"),
            "{err}"
        );
        let names: Vec<String> = std::fs::read_dir(&out)
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect();
        assert!(!names.is_empty());
        assert!(
            names.iter().all(|n| !n.contains(".tmp")),
            "after {after} ms: {names:?}"
        );
        for n in names.iter().filter(|n| n.ends_with(".json")) {
            let text = std::fs::read_to_string(out.join(n)).unwrap();
            assert!(
                serde_json::from_str::<serde_json::Value>(&text).is_ok(),
                "{n} is not whole"
            );
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
