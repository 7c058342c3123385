//! Helpers shared by the teaching examples: the sample-count argument, loading a case
//! from its JSON description, printing verdicts and the closing verdict.
#![allow(dead_code)]

use lightproof::case::{Case, CaseDesc, seed_for};
use lightproof::sampling::SamplerKind;
use lightproof::stats::{Verdict, VerdictClass};
use lightproof::transport::Estimator;
use plotters::coord::Shift;
use plotters::prelude::{ChartBuilder, DrawingArea, IntoDrawingArea, SVGBackend, WHITE};
use std::error::Error;
use std::path::{Path, PathBuf};

/// The sample count: the first command-line argument, or `default`.
pub fn samples(default: u64) -> u64 {
    match std::env::args().nth(1) {
        None => default,
        Some(a) => match a.replace('_', "").parse::<u64>() {
            Ok(n) if n >= 256 => n,
            _ => {
                eprintln!(
                    "usage: cargo run --release --example <NAME> -- [SAMPLES ≥ 256], got `{a}`"
                );
                std::process::exit(2)
            }
        },
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

/// Print one verdict line; returns whether it passed.
/// An estimate without variance (a delta light, cosine-sampled Lambertian) is judged
/// exactly, within the f32 error bound, and says so instead of "± 0".
pub fn report(what: &str, v: &Verdict) -> bool {
    let (spread, score) = match v.class {
        VerdictClass::Statistical => (
            format!("± {:<11}", num(v.std_error)),
            format!("z {:+6.2}", v.z),
        ),
        VerdictClass::Exact => (
            format!("{:<13}", "(no variance)"),
            format!("{:>8}", "f32 bound"),
        ),
    };
    println!(
        "  {what:<50} {:>12} {spread} exact {:>12}  {score}  verdict {}",
        num(v.estimate),
        num(v.reference),
        match (v.passed, v.weak) {
            (true, false) => "PASS",
            (true, true) => "PASS (weak: it cannot see a 0.5% bias at this count)",
            (false, _) => "FAIL",
        }
    );
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

/// Run one estimator of a case with independent samples (seed derived from `seed_base`
/// and the case) and judge it against `exact`; a pass that cannot see a 0.5% bias is
/// marked weak (an example's count is the reader's choice, outside the proof).
pub fn judged(case: &Case, est: Estimator, n: u64, seed_base: u64, exact: f64) -> Verdict {
    let seed = seed_for(seed_base, &case.desc.name, est, SamplerKind::Independent);
    let mut v = case
        .run(est, SamplerKind::Independent, n, seed)
        .verdict_against(exact, ALPHA, 1);
    v.require_power(false);
    v
}
