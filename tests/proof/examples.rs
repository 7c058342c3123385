//! The teaching examples (`examples/01_*.rs` … `examples/08_*.rs`) must keep running and
//! passing: each is run through `cargo run --example NAME -- 20000` (a small sample count;
//! `cargo test` has already built them in the same profile) and must exit 0 and print
//! its verdict, and write the files README.md's table of examples names. The examples
//! run one after another: cargo holds a lock on the build directory, and each example
//! already uses every core. Under `cargo test` they are
//! already built (cargo builds examples with the tests), so this takes a few seconds;
//! under `cargo test --test proof examples::` they are first built in one parallel step.

use std::process::Command;

/// The examples' shared helpers, to test what they print against what they test.
#[path = "../../examples/common/mod.rs"]
mod example_common;

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
    for (name, p) in EXAMPLES.iter().zip(&printed) {
        printed_checks_agree(name, p);
    }
    // Every check goes through common::powered: the examples that judge estimates
    // themselves (01, 06, 07, 08) mark weak passes too, at 20 000 samples plenty.
    for (name, p) in EXAMPLES.iter().zip(&printed) {
        if ["01", "06", "07", "08"].iter().any(|k| name.starts_with(k)) {
            assert!(
                p.contains("PASS (weak: "),
                "example {name} marked no weak pass at 20 000 samples:\n{p}"
            );
        }
    }
    // 06 checks the microfacet albedos two-sided against lightproof_analytic (1 − ln 2 at
    // normal incidence for the white GGX mirror), and the ≤ 1 rows are bounds.
    let bsdf = &printed[5];
    assert!(
        bsdf.contains("albedo a(θo = 0°) = 1 − ln 2 [bsdf]")
            && bsdf.contains("= a_CT [bsdf]")
            && bsdf.contains("= a_white [bsdf]"),
        "{bsdf}"
    );
    // The bound for every model, the Lambertian too (README.md: "for diffuse and
    // rough-conductor BSDFs"): 3 models × 2 angles × 2 estimators.
    assert_eq!(
        bsdf.lines().filter(|l| l.contains("≤ 1 [")).count(),
        12,
        "{bsdf}"
    );
    for line in bsdf.lines().filter(|l| l.contains("≤ 1 [")) {
        assert!(
            line.contains(" bound ") && !line.contains(" exact "),
            "{line}"
        );
    }
    // 06 teaches reciprocity for transmission too, with the η² rule (f itself is not
    // symmetric across an interface), on a rough dielectric, and the rule holds.
    let eta_rule = bsdf
        .lines()
        .find(|l| l.contains("reciprocity f(ωi→ωo)/ηo² = f(ωo→ωi)/ηi²"))
        .unwrap_or_else(|| panic!("06 checks no transmitting BSDF's reciprocity:\n{bsdf}"));
    assert!(eta_rule.contains("verdict PASS"), "{eta_rule}");
    assert!(
        bsdf.contains("rough dielectric ") && bsdf.contains("= η² (ωo"),
        "{bsdf}"
    );
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

/// Every verdict line an example printed shows the z that decided it: a PASS has |z|
/// within the critical value (3.89, or the one the line names: a one-sided bound's
/// `(z ≤ 3.72)`, a t test's), a FAIL beyond it, and each line says what bias it sees.
fn printed_checks_agree(name: &str, printed: &str) {
    let (critical, _) = example_common::rule_numbers();
    let verdict_lines = printed
        .lines()
        .filter(|l| l.contains("  verdict ") && (l.contains(" exact ") || l.contains(" bound ")));
    for line in verdict_lines {
        assert!(line.contains(" sees "), "{name}: {line}");
        let words: Vec<&str> = line.split_whitespace().collect();
        let Some(i) = words.iter().rposition(|w| *w == "z" || *w == "t") else {
            assert!(line.contains("f32 bound"), "{name}: no z in {line}");
            continue;
        };
        let z: f64 = words[i + 1]
            .parse()
            .unwrap_or_else(|_| panic!("{name}: {line}"));
        let limit = match words.get(i + 2) {
            Some(w) if w.starts_with('(') => words[i + 4].trim_end_matches(')').parse().unwrap(),
            _ => critical,
        };
        let one_sided = words.get(i + 2).is_some_and(|w| !w.starts_with("(|"))
            && words.get(i + 2).is_some_and(|w| w.starts_with('('));
        let within = if one_sided {
            z <= limit
        } else {
            z.abs() <= limit
        };
        assert_eq!(
            within,
            line.contains("verdict PASS"),
            "{name}: the printed z {z} and the verdict disagree (limit {limit}): {line}"
        );
    }
}

/// The z the examples print is the one the test decided by: the error beyond the f32
/// rounding allowance, in standard errors (the plain z of 4.13 that example 02 printed
/// beside a PASS was within the allowance).
#[test]
fn examples_print_the_tested_z() {
    use example_common::{powered, tested_z};
    use lightproof::stats::{MeanTest, exact_relative_tolerance};
    let g = exact_relative_tolerance();
    let t = MeanTest::new(example_common::ALPHA, 1);
    // 02's small square: 9.99975e-5 ± 1.54e-12, off by 6.4e-12 (z 4.13), τ = 7.6e-10.
    let mu = 9.99975e-5;
    let v = t.judge_parts(mu + 4.13 * 1.54365e-12, 1.54365e-12, mu, None, 0, 1 << 20);
    assert!(v.passed && v.z > 4.0 && tested_z(&v, false) == 0.0, "{v:?}");
    for (off, se) in [
        (0.0f64, 1e-3),
        (3.0, 1e-3),
        (3.95, 1e-3),
        (-3.95, 1e-3),
        (10.0, 1e-9),
        (-100.0, 1e-9),
        (1.0, 1e-7),
    ] {
        for mu in [1.0, 2.5, 1e-4] {
            let est = mu + off * se + off.signum() * 0.5 * g * mu;
            let v = t.judge_parts(est, se, mu, None, 0, 1000);
            let z = tested_z(&v, false);
            assert_eq!(v.passed, z.abs() <= v.critical, "{v:?} z {z}");
            // Its p value is that of the tested z.
            let p = 2.0 * normal_tail(z.abs());
            assert!(
                (v.p_value - p.min(1.0)).abs() <= 1e-6 * p.max(1e-300) + 1e-12,
                "{v:?} {p}"
            );
            // One-sided bounds.
            let mut acc = lightproof::stats::Accumulator::new();
            for i in 0..1000 {
                acc.push(est + se * 31.6 * if i % 2 == 0 { 1.0 } else { -1.0 });
            }
            let b = t.judge_at_most(&acc, mu);
            if b.class == lightproof::stats::VerdictClass::Statistical {
                assert_eq!(b.passed, tested_z(&b, true) <= b.critical, "{b:?}");
            }
        }
    }
    // A pass that cannot see 0.5% is marked weak by the one helper.
    let wide = powered(t.judge_parts(1.0, 0.01, 1.0, None, 0, 1000));
    assert!(wide.passed && wide.weak);
    let narrow = powered(t.judge_parts(1.0, 1e-4, 1.0, None, 0, 1000));
    assert!(narrow.passed && !narrow.weak);
}

/// The upper tail of the standard normal, Φ̄(z) = erfc(z/√2)/2.
fn normal_tail(z: f64) -> f64 {
    0.5 * lightproof_analytic::microfacet::erfc(z / std::f64::consts::SQRT_2)
}

/// Example 01 needs a time window longer than the flight to its detector: a count too
/// small is refused as such (exit 2), not judged as a disagreement.
#[test]
fn examples_refuse_a_count_below_their_minimum() {
    let out = cargo("run")
        .args(["--example", "01_phase_space", "--", "256"])
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stdout}{stderr}");
    assert!(
        stderr.contains("count too small: 256 < 4096") && !stdout.contains("verdict"),
        "{stdout}{stderr}"
    );
    use example_common::parse_count;
    assert_eq!(parse_count(None, 7, 4096), Ok(7));
    assert_eq!(parse_count(Some("4_096"), 7, 4096), Ok(4096));
    assert!(
        parse_count(Some("4095"), 7, 4096)
            .unwrap_err()
            .starts_with("count too small")
    );
    // The command line's most, 2^40 (the library's `case::MAX_SAMPLES`), and no more.
    assert_eq!(parse_count(Some("1099511627776"), 7, 256), Ok(1 << 40));
    assert_eq!(
        parse_count(Some("1099511627777"), 7, 256),
        Err("count too large: 1099511627777 > 1099511627776 (2^40), the most this example runs (usage: cargo run --release --example <NAME> -- [SAMPLES ≤ 2^40])".to_string())
    );
    assert!(
        parse_count(Some("many"), 7, 256)
            .unwrap_err()
            .starts_with("usage")
    );
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
