//! The teaching examples (`examples/01_*.rs` … `examples/08_*.rs`) must keep running and
//! passing: each is run through `cargo run --example NAME -- 20000` (a small sample count;
//! `cargo test` has already built them in the same profile) and must exit 0 and print
//! its verdict, and write the files README.md's table of examples names. The examples
//! run one after another: cargo holds a lock on the build directory, and each example
//! already uses every core. Under `cargo test` they are
//! already built (cargo builds examples with the tests), so this takes a few seconds;
//! under `cargo test --test examples` they are first built in one parallel step.

use std::process::Command;

const EXAMPLES: [&str; 8] = [
    "01_phase_space",
    "02_solid_angle",
    "03_intensity",
    "04_irradiance",
    "05_radiance",
    "06_bsdf",
    "07_rendering_equation",
    "08_importance_sampling",
];

/// `cargo` in this package, in the profile this test was built with.
fn cargo(command: &str) -> Command {
    let mut c = Command::new(env!("CARGO"));
    c.current_dir(env!("CARGO_MANIFEST_DIR"))
        .arg(command)
        .arg("--quiet");
    if !cfg!(debug_assertions) {
        // `cargo test --release`: the examples were built in release too.
        c.arg("--release");
    }
    c
}

/// The files an example writes under `target/examples/`, as README.md's table of
/// examples lists them (its third column).
fn writes_of(name: &str) -> Vec<String> {
    let readme =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/README.md")).unwrap();
    let row = readme
        .lines()
        .find(|l| l.starts_with(&format!("| `{name}` |")))
        .unwrap_or_else(|| panic!("README.md's table has no row for {name}"));
    let column = row.trim_end_matches('|').rsplit('|').next().unwrap();
    column
        .split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect()
}

/// Run example `name` with 20 000 samples: it must pass and write what README.md says;
/// returns what it printed.
fn run_example(name: &str) -> String {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/examples");
    let writes = writes_of(name);
    assert!(!writes.is_empty(), "README.md lists no file for {name}");
    for w in &writes {
        let _ = std::fs::remove_file(dir.join(w));
    }
    let out = cargo("run")
        .args(["--example", name, "--", "20000"])
        .output()
        .unwrap_or_else(|e| panic!("cannot run cargo for example {name}: {e}"));
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "example {name} failed ({}):\n{stdout}\n{stderr}",
        out.status
    );
    assert!(
        stdout.contains("verdict: PASS"),
        "example {name} printed no passing verdict:\n{stdout}\n{stderr}"
    );
    assert!(
        !stdout.contains("verdict FAIL"),
        "example {name} printed a failing check:\n{stdout}"
    );
    for w in &writes {
        let len = std::fs::metadata(dir.join(w)).map(|m| m.len()).unwrap_or(0);
        assert!(
            len > 0,
            "example {name} did not write target/examples/{w}, as README.md says"
        );
    }
    stdout.into_owned()
}

#[test]
fn every_example_runs_and_passes() {
    // Build them all at once (a no-op when `cargo test` already did).
    let mut build = cargo("build");
    for name in EXAMPLES {
        build.args(["--example", name]);
    }
    let out = build.output().expect("cannot run cargo build");
    assert!(
        out.status.success(),
        "building the examples failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let printed: Vec<String> = EXAMPLES.iter().map(|name| run_example(name)).collect();
    // An estimate without variance is marked, not shown as "± 0" (README.md: a point
    // light's intensity, cosine-sampled Lambertian albedo).
    assert!(
        printed
            .iter()
            .any(|p| p.contains("(no variance)") && p.contains("f32 bound")),
        "no example marked an estimate without variance"
    );
    assert!(!printed.iter().any(|p| p.contains("± 0.000000 ")));
    // The case files they save pass `lightproof verify` as README.md says to run it: at
    // the files' own counts every verdict passes and sees a 0.5 % bias (none weak).
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/examples");
    let cases: Vec<String> = EXAMPLES
        .iter()
        .flat_map(|name| writes_of(name))
        .filter(|w| w.ends_with(".json"))
        .collect();
    assert!(cases.len() >= 5, "{cases:?}");
    for w in cases {
        // Each names its own count and sampler (README.md): 2²⁰ Sobol samples.
        let text = std::fs::read_to_string(dir.join(&w)).unwrap();
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert!(
            v["samples"] == 1u64 << 20 && v["samplers"] == serde_json::json!(["sobol"]),
            "target/examples/{w} does not name 2²⁰ Sobol samples: {text}"
        );
        let out = Command::new(env!("CARGO_BIN_EXE_lightproof"))
            .arg("verify")
            .arg(dir.join(&w))
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success() && !stdout.contains("weak"),
            "`lightproof verify target/examples/{w}` did not pass:\n{stdout}{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

#[test]
fn examples_reject_a_bad_sample_count() {
    let out = cargo("run")
        .args(["--example", "02_solid_angle", "--", "many"])
        .output()
        .unwrap();
    assert_eq!(
        out.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
