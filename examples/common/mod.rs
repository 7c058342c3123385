//! Helpers shared by the teaching examples: the sample-count argument, loading a case
//! from its JSON description, printing verdicts and the closing verdict.
#![allow(dead_code)]

use lightproof::case::{Case, CaseDesc, seed_for};
use lightproof::sampling::SamplerKind;
use lightproof::stats::{Accumulator, MeanTest, Verdict, VerdictClass, exact_relative_tolerance};
use lightproof::transport::Estimator;
use lightproof::transport::engine::Estimate;
use lightproof::verdict::DETECTABLE_BOUND;
use plotters::coord::Shift;
use plotters::prelude::{ChartBuilder, DrawingArea, IntoDrawingArea, SVGBackend, WHITE};
use std::error::Error;
use std::path::{Path, PathBuf};

/// The sample count: the first command-line argument, or `default`; at least 256.
pub fn samples(default: u64) -> u64 {
    samples_at_least(default, 256, "")
}

/// The sample count: the first command-line argument, or `default`; a count below
/// `min` is refused with exit status 2 and `why` (what goes wrong below it), never
/// run into a verdict that would blame the estimates.
pub fn samples_at_least(default: u64, min: u64, why: &str) -> u64 {
    let arg = std::env::args().nth(1);
    match parse_count(arg.as_deref(), default, min) {
        Ok(n) => n,
        Err(msg) => {
            eprintln!("{msg}{why}");
            std::process::exit(2)
        }
    }
}

/// The count `arg` asks for (`default` without one): an integer (`_` allowed) from
/// `min` to the command line's most, [`lightproof::case::MAX_SAMPLES`] = 2^40 (more
/// would run for days, or overflow a count derived from it), or the message saying why
/// not.
pub fn parse_count(arg: Option<&str>, default: u64, min: u64) -> Result<u64, String> {
    let Some(a) = arg else {
        return Ok(default);
    };
    let max = lightproof::case::MAX_SAMPLES;
    match a.replace('_', "").parse::<u64>() {
        Ok(n) if (min..=max).contains(&n) => Ok(n),
        Ok(n) if n > max => Err(format!(
            "count too large: {n} > {max} (2^40), the most this example runs (usage: cargo run --release --example <NAME> -- [SAMPLES ≤ 2^40])"
        )),
        Ok(n) => Err(format!(
            "count too small: {n} < {min}, the least this example runs (usage: cargo run --release --example <NAME> -- [SAMPLES ≥ {min}])"
        )),
        Err(_) => Err(format!(
            "usage: cargo run --release --example <NAME> -- [SAMPLES ≥ {min}], got `{a}`"
        )),
    }
}

/// A case from its JSON description (the format of a case file).
pub fn load(desc: serde_json::Value) -> Case {
    let desc: CaseDesc =
        serde_json::from_value(desc).unwrap_or_else(|e| panic!("invalid case description: {e}"));
    Case::from_desc(desc, Path::new("<example>")).unwrap_or_else(|e| panic!("{e}"))
}

/// The folder the examples write to, `target/examples`, created if missing.
pub fn out_dir() -> std::io::Result<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/examples");
    std::fs::create_dir_all(&dir)?;
    Ok(dir)
}

/// Write `bytes` to target/examples/`name` as the `lightproof` binary writes its outputs
/// (a temporary beside it, then a rename: never half-written); returns the path to show.
pub fn save(name: &str, bytes: &[u8]) -> std::io::Result<String> {
    lightproof::io::write_atomic(&out_dir()?.join(name), bytes)?;
    Ok(format!("target/examples/{name}"))
}

/// Draw an SVG picture of `size` pixels on white with `draw` and [`save`] it as `name`.
pub fn save_svg(
    name: &str,
    size: (u32, u32),
    draw: impl FnOnce(&DrawingArea<SVGBackend<'_>, Shift>) -> Result<(), Box<dyn Error>>,
) -> Result<String, Box<dyn Error>> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE)?;
        draw(&root)?;
        root.present()?;
    }
    Ok(save(name, svg.as_bytes())?)
}

/// The examples' chart on `root`: the title, 12 px margins, room for the axis labels.
pub fn chart<'a, 'b, 's>(
    root: &'a DrawingArea<SVGBackend<'s>, Shift>,
    title: &str,
) -> ChartBuilder<'a, 'b, SVGBackend<'s>> {
    let mut c = ChartBuilder::on(root);
    c.caption(title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60);
    c
}

/// Print a case file and save it under target/examples/ for `lightproof verify`.
pub fn show_case_file(name: &str, text: &str) {
    let saved = save(name, text.as_bytes());
    println!(
        "A case file (JSON) describes scene, measurement, closed form and estimators:\n{text}"
    );
    if saved.is_ok() {
        println!(
            "(saved as target/examples/{name}; check it with `cargo run --release -- verify target/examples/{name}`,\n which runs the file's own `samples` and `samplers`, enough to see a 0.5% bias)\n"
        );
    }
}

/// Format a number readably whatever its magnitude.
pub fn num(x: f64) -> String {
    if x == 0.0 || (1e-3..1e5).contains(&x.abs()) {
        format!("{x:.6}")
    } else {
        format!("{x:.5e}")
    }
}

/// The z a statistical verdict was decided by. The engine computes in f32, so a test
/// allows for rounding: only the error beyond τ = γₙ·|exact| (≈ 7.6e-6·|exact|,
/// `lightproof::stats::exact_relative_tolerance`) is tested (`src/stats/hypothesis.rs`,
/// "Rounding allowance"), while `Verdict::z` is the plain (estimate − exact)/std error.
/// This is the tested one, from public API: τ is `MeanTest::rounding_allowance` (the
/// examples never set a term scale, so τ = γₙ·|exact|); two-sided it is
/// sign(d)·(|d| − τ)⁺/s, for a one-sided bound (d − τ)/s, with d = estimate − exact.
/// The verdict passes exactly when it is within `Verdict::critical`
/// (`tests/proof/examples.rs` holds that).
pub fn tested_z(v: &Verdict, one_sided: bool) -> f64 {
    let d = v.estimate - v.reference;
    let tau = MeanTest::new(ALPHA, 1).rounding_allowance(v.reference);
    let excess = if one_sided {
        d - tau
    } else {
        match (d.abs() - tau).max(0.0) {
            0.0 => 0.0,
            e => e.copysign(d),
        }
    };
    let s = v.std_error;
    if s > 0.0 && s.is_finite() {
        excess / s
    } else if excess == 0.0 || (one_sided && excess < 0.0) {
        0.0
    } else {
        f64::INFINITY.copysign(excess)
    }
}

/// The critical |z| of one two-sided check at level [`ALPHA`] (3.89) and the f32
/// allowance γₙ relative to |exact| (7.6e-6), as the tests compute them.
pub fn rule_numbers() -> (f64, f64) {
    let critical = MeanTest::new(ALPHA, 1)
        .judge_parts(0.0, 1.0, 0.0, None, 0, 2)
        .critical;
    (critical, exact_relative_tolerance())
}

/// Print the rule every check follows, under an example's title; `count` says how
/// many samples (or photons) an estimate draws.
pub fn print_rule(count: &str) {
    let (critical, gamma) = rule_numbers();
    println!(
        "   {count}; a check passes when |z| ≤ {critical:.2} (α = {ALPHA:e} each), z = (estimate − exact) / std error\n   \
         counting only the error beyond the f32 rounding allowance τ = {gamma:.1e}·|exact| (the z printed is this tested one);\n   \
         a bound's check is one-sided; an estimate without variance passes when |estimate − exact| ≤ τ (the f32 bound);\n   \
         `sees` is the smallest relative bias a check detects (99% power), and a pass that cannot see {:.1}% says PASS (weak: …)\n",
        100.0 * DETECTABLE_BOUND
    );
}

/// A relative size as a percentage with about two significant digits.
pub fn percent(x: f64) -> String {
    let p = 100.0 * x.abs();
    if !p.is_finite() {
        "∞".into()
    } else if p >= 10.0 {
        format!("{p:.0}%")
    } else if p >= 1.0 {
        format!("{p:.1}%")
    } else if p >= 0.1 {
        format!("{p:.2}%")
    } else if p >= 0.01 {
        format!("{p:.3}%")
    } else {
        format!("{p:.0e}%")
    }
}

/// Print one verdict line against an exact value; returns whether it passed.
/// An estimate without variance (a delta light, cosine-sampled Lambertian) is judged
/// exactly, within the f32 error bound, and says so instead of "± 0".
pub fn report(what: &str, v: &Verdict) -> bool {
    print_verdict(what, v, false)
}

/// Print one verdict line of a one-sided check "estimate ≤ bound"
/// ([`judge_bound`]); returns whether it passed.
pub fn report_bound(what: &str, v: &Verdict) -> bool {
    print_verdict(what, v, true)
}

fn print_verdict(what: &str, v: &Verdict, one_sided: bool) -> bool {
    let (critical, _) = rule_numbers();
    let z = tested_z(v, one_sided);
    let (spread, score) = match v.class {
        VerdictClass::Statistical => {
            let sym = if v.dof.is_some() { "t" } else { "z" };
            let limit = if one_sided {
                format!(" ({sym} ≤ {:.2})", v.critical)
            } else if (v.critical - critical).abs() > 0.005 {
                format!(" (|{sym}| ≤ {:.2})", v.critical)
            } else {
                String::new()
            };
            (
                format!("± {:<11}", num(v.std_error)),
                format!("{sym} {z:+6.2}{limit}"),
            )
        }
        VerdictClass::Exact => (
            format!("{:<13}", "(no variance)"),
            format!("{:>8}", "f32 bound"),
        ),
    };
    println!(
        "  {what:<50} {:>12} {spread} {} {:>12}  {score}  sees {:>6}  verdict {}",
        num(v.estimate),
        if one_sided { "bound" } else { "exact" },
        num(v.reference),
        if v.reference == 0.0 {
            num(v.detectable_bias)
        } else {
            percent(v.detectable_relative_bias)
        },
        match (v.passed, v.weak) {
            (true, false) => "PASS",
            (true, true) => "PASS (weak: it cannot see a 0.5% bias at this count)",
            (false, _) => "FAIL",
        }
    );
    // Where the allowance decided the verdict, say so.
    let beyond = |x: f64| {
        if one_sided {
            x > v.critical
        } else {
            x.abs() > v.critical
        }
    };
    if v.class == VerdictClass::Statistical && beyond(v.z) && !beyond(z) && v.z.is_finite() {
        println!(
            "      (the plain (estimate − exact) / std error is {:+.2}, beyond {:.2}: the error within τ = {} is f32 rounding, not tested)",
            v.z,
            v.critical,
            num(MeanTest::new(ALPHA, 1).rounding_allowance(v.reference))
        );
    }
    if let Some(r) = &v.reason {
        println!("      ({r})");
    }
    v.passed
}

/// Print the overall verdict and exit non-zero if a check failed.
pub fn finish(ok: bool) {
    if ok {
        println!("\nverdict: PASS (every estimate agrees with its closed form)");
    } else {
        println!("\nverdict: FAIL (an estimate disagrees with its closed form)");
        std::process::exit(1);
    }
}

/// Significance of each example check (α = 1e-4, critical |z| = 3.89).
pub const ALPHA: f64 = 1e-4;

/// Every example check passes through here: a pass that cannot see a 0.5% bias
/// (`lightproof::verdict::DETECTABLE_BOUND`, at 99% power) is marked weak
/// (`Verdict::require_power(false)`: an example's count is the reader's choice, outside
/// the proof's conditions, so such a pass is kept and marked rather than failed).
pub fn powered(mut v: Verdict) -> Verdict {
    v.require_power(false);
    v
}

/// Judge an estimate drawn with independent samples against `exact` ([`powered`]).
pub fn judge_estimate(e: &Estimate, exact: f64) -> Verdict {
    powered(lightproof::verdict::judge(
        e,
        SamplerKind::Independent,
        exact,
        ALPHA,
        1,
    ))
}

/// Judge a mean and its standard error, from `count` samples, against `exact`
/// ([`powered`]).
pub fn judge_mean(estimate: f64, std_error: f64, exact: f64, count: u64) -> Verdict {
    powered(MeanTest::new(ALPHA, 1).judge_parts(estimate, std_error, exact, None, 0, count))
}

/// One-sided check that an accumulator's mean is not above `bound` ([`powered`];
/// print it with [`report_bound`]).
pub fn judge_bound(acc: &Accumulator, bound: f64) -> Verdict {
    powered(MeanTest::new(ALPHA, 1).judge_at_most(acc, bound))
}

/// Run one estimator of a case with independent samples (seed derived from `seed_base`
/// and the case) and judge it against `exact` ([`powered`]).
pub fn judged(case: &Case, est: Estimator, n: u64, seed_base: u64, exact: f64) -> Verdict {
    let seed = seed_for(seed_base, &case.desc.name, est, SamplerKind::Independent);
    powered(
        case.run(est, SamplerKind::Independent, n, seed)
            .verdict_against(exact, ALPHA, 1),
    )
}
