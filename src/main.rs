//! The `lightproof` command line: a thin layer over the library.
//!
//! Exit status: 0 when every verdict passes, 1 when one fails, 2 on bad input.

use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use lightproof::bsdf::Bsdf;
use lightproof::bsdf::contract::{chi2_bsdf, direction};
use lightproof::error::InputError;
use lightproof::sampling::SamplerKind;
use lightproof::stats::sidak_alpha;
use lightproof::transport::Estimator;
use lightproof::transport::engine::RunSpec;
use lightproof::verify::{Case, Outcome, collect_cases, count_tests, judge, run_case, seed_for};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

/// Default seed of every run (recorded in every output).
const DEFAULT_SEED: u64 = 0x11_9470;
/// Family-wise significance of a verification run.
const ALPHA: f64 = 1e-4;

#[derive(Parser)]
#[command(
    name = "lightproof",
    version,
    about = "Prove a light-transport engine right: Monte Carlo estimates judged against closed forms by statistics"
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Run case files or folders (default: the whole catalog) and the chi-square suites.
    Verify {
        /// Case files or folders.
        paths: Vec<PathBuf>,
        /// Base seed.
        #[arg(long, default_value_t = DEFAULT_SEED)]
        seed: u64,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
        /// Samples per estimate (default: each case's own).
        #[arg(long)]
        samples: Option<u64>,
        /// Write every outcome as JSON to this file.
        #[arg(long)]
        json: Option<PathBuf>,
        /// Skip the chi-square suites.
        #[arg(long)]
        no_chi2: bool,
    },
    /// Estimate one case: one JSON object on stdout.
    Estimate {
        /// The case file.
        case: PathBuf,
        /// Samples.
        #[arg(long)]
        samples: Option<u64>,
        /// Seed.
        #[arg(long, default_value_t = DEFAULT_SEED)]
        seed: u64,
        /// Worker threads.
        #[arg(long)]
        threads: Option<usize>,
        /// Estimator (default: the case's first).
        #[arg(long, value_parser = parse_estimator)]
        estimator: Option<Estimator>,
        /// Sampler: independent, stratified or sobol.
        #[arg(long, value_parser = parse_sampler, default_value = "independent")]
        sampler: SamplerKind,
    },
    /// Chi-square test of one BSDF configuration; writes observed/expected/residual EXRs.
    Chi2 {
        /// The BSDF as JSON, e.g. '{"type":"lambertian","albedo":0.5}'.
        bsdf: String,
        /// Outgoing direction as θ,φ in degrees.
        #[arg(long, default_value = "30,0")]
        wo: String,
        /// Samples.
        #[arg(long, default_value_t = 1_000_000)]
        samples: u64,
        /// Seed.
        #[arg(long, default_value_t = DEFAULT_SEED)]
        seed: u64,
        /// Folder for the tables.
        #[arg(long, default_value = "target/chi2")]
        out: PathBuf,
    },
    /// Convergence reports: sweep every case × estimator × sampler over N = 2^k samples;
    /// one JSON report and one SVG per case, and an index, under --out.
    Report {
        /// Case files or folders (default: the whole catalog).
        paths: Vec<PathBuf>,
        /// Output folder.
        #[arg(long, default_value = "reports")]
        out: PathBuf,
        /// Stop, writing everything, before the predicted end of the next point passes
        /// this many wall seconds.
        #[arg(long)]
        budget: Option<f64>,
        /// Largest sweep point (rounded down to a power of two).
        #[arg(long, default_value_t = lightproof::report::DEFAULT_MAX_SAMPLES)]
        max_samples: u64,
        /// Smallest sweep point (rounded up to a power of two; at least 256).
        #[arg(long, default_value_t = lightproof::report::DEFAULT_MIN_SAMPLES)]
        min_samples: u64,
        /// Base seed.
        #[arg(long, default_value_t = DEFAULT_SEED)]
        seed: u64,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
        /// Run shard K of N (K from 0) and write its partial file, or `auto` to take the
        /// shard from a Slurm array or Kubernetes indexed Job.
        #[arg(long)]
        shard: Option<String>,
        /// Only this estimator (repeatable; default: each case's own).
        #[arg(long = "estimator", value_parser = parse_estimator)]
        estimators: Vec<Estimator>,
        /// Only this sampler (repeatable; default: independent, stratified and sobol).
        #[arg(long = "sampler", value_parser = parse_sampler)]
        samplers: Vec<SamplerKind>,
        /// Ignore earlier reports in --out instead of resuming them.
        #[arg(long)]
        fresh: bool,
    },
    /// Merge the shard partial files of `report --shard` into the single run's reports.
    Merge {
        /// Partial files (shard-K-of-N.json) or folders holding them.
        #[arg(required = true)]
        inputs: Vec<PathBuf>,
        /// Output folder.
        #[arg(long, default_value = "reports")]
        out: PathBuf,
    },
    /// Render a scene with a camera to an EXR image, for looking.
    Render {
        /// Scene file with a `camera`.
        scene: PathBuf,
        /// Samples per pixel.
        #[arg(long, default_value_t = 16)]
        spp: u64,
        /// Output EXR.
        #[arg(short, long, default_value = "out.exr")]
        output: PathBuf,
        /// Seed.
        #[arg(long, default_value_t = DEFAULT_SEED)]
        seed: u64,
    },
}

fn parse_estimator(s: &str) -> Result<Estimator, String> {
    serde_json::from_value(serde_json::Value::String(s.to_string()))
        .map_err(|_| format!("unknown estimator `{s}`"))
}

fn parse_sampler(s: &str) -> Result<SamplerKind, String> {
    serde_json::from_value(serde_json::Value::String(s.to_string()))
        .map_err(|_| format!("unknown sampler `{s}` (independent, stratified, sobol)"))
}

enum Failure {
    Input(String),
    Verdict,
}

impl From<InputError> for Failure {
    fn from(e: InputError) -> Self {
        Failure::Input(e.to_string())
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let command = cli.command.unwrap_or(Command::Verify {
        paths: vec![],
        seed: DEFAULT_SEED,
        threads: None,
        samples: None,
        json: None,
        no_chi2: false,
    });
    let threads = match &command {
        Command::Verify { threads, .. }
        | Command::Estimate { threads, .. }
        | Command::Report { threads, .. } => *threads,
        _ => None,
    };
    let pool = match rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()
    {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: cannot start worker threads: {e}");
            return ExitCode::from(2);
        }
    };
    match pool.install(|| dispatch(command)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Verdict) => ExitCode::from(1),
        Err(Failure::Input(msg)) => {
            eprintln!("error: {msg}");
            ExitCode::from(2)
        }
    }
}

fn default_catalog() -> PathBuf {
    let local = PathBuf::from("analytic/cases");
    if local.is_dir() {
        local
    } else {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("analytic/cases")
    }
}

fn dispatch(command: Command) -> Result<(), Failure> {
    match command {
        Command::Verify {
            paths,
            seed,
            samples,
            json,
            no_chi2,
            ..
        } => verify(paths, seed, samples, json, no_chi2),
        Command::Estimate {
            case,
            samples,
            seed,
            estimator,
            sampler,
            ..
        } => estimate(&case, samples, seed, estimator, sampler),
        Command::Chi2 {
            bsdf,
            wo,
            samples,
            seed,
            out,
        } => chi2(&bsdf, &wo, samples, seed, &out),
        Command::Report {
            paths,
            out,
            budget,
            max_samples,
            min_samples,
            seed,
            shard,
            estimators,
            samplers,
            fresh,
            ..
        } => {
            let shard = match shard.as_deref() {
                None => None,
                Some("auto") => Some(lightproof::report::shard::shard_from_env(
                    &std::env::vars().collect(),
                )?),
                Some(s) => Some(lightproof::report::shard::parse_shard(s)?),
            };
            let opts = lightproof::report::sweep::Options {
                paths: if paths.is_empty() {
                    vec![default_catalog()]
                } else {
                    paths
                },
                out,
                budget,
                min_samples,
                max_samples,
                seed,
                estimators,
                samplers,
                shard,
                fresh,
            };
            report(&opts)
        }
        Command::Merge { inputs, out } => {
            let summary =
                lightproof::report::shard::merge(&inputs, &out, rayon::current_num_threads())?;
            print_summary(&out, &summary);
            Ok(())
        }
        Command::Render {
            scene,
            spp,
            output,
            seed,
        } => {
            let (w, h, data) = lightproof::render::render_file(&scene, spp, seed)?;
            lightproof::render::write_exr(&output, w, h, &data)
                .map_err(|e| Failure::Input(format!("{}: cannot write: {e}", output.display())))?;
            eprintln!("wrote {} ({w}×{h}, {spp} spp)", output.display());
            Ok(())
        }
    }
}

fn verify(
    paths: Vec<PathBuf>,
    seed: u64,
    samples: Option<u64>,
    json: Option<PathBuf>,
    no_chi2: bool,
) -> Result<(), Failure> {
    let whole = paths.is_empty();
    let paths = if whole {
        vec![default_catalog()]
    } else {
        paths
    };
    let files = collect_cases(&paths)?;
    let cases: Vec<Case> = files
        .iter()
        .map(|f| Case::load(f))
        .collect::<Result<_, _>>()?;
    let warp_suite = if whole && !no_chi2 {
        lightproof::suites::warps()
    } else {
        vec![]
    };
    let k = count_tests(&cases) + warp_suite.len();
    let t0 = Instant::now();
    let bar = ProgressBar::new((cases.len() + warp_suite.len()) as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let mut outcomes: Vec<Outcome> = Vec::new();
    for c in &cases {
        bar.set_message(c.desc.name.clone());
        outcomes.extend(run_case(c, seed, samples, 1, ALPHA, k));
        bar.inc(1);
    }
    let mut chi2_rows = Vec::new();
    for (i, (name, test)) in warp_suite.iter().enumerate() {
        bar.set_message(format!("chi2 {name}"));
        chi2_rows.push(test(
            1_000_000,
            seed ^ (i as u64 + 1),
            sidak_alpha(ALPHA, k),
        ));
        bar.inc(1);
    }
    bar.finish_and_clear();
    println!(
        "{:<48} {:<12} {:>24} {:>12} {:>8} {:>9} {:>8}  verdict",
        "case", "estimator", "estimate ± std error", "reference", "z", "det.bias", "time"
    );
    for o in &outcomes {
        let (r, z, det, verdict) = match &o.verdict {
            Some(v) => (
                format!("{:.6}", v.reference),
                format!("{:+.2}", v.z),
                format!("{:.3}%", 100.0 * v.detectable_relative_bias),
                if v.passed { "pass" } else { "FAIL" },
            ),
            None => ("-".into(), "-".into(), "-".into(), "(no reference)"),
        };
        let name: String = o.case.chars().take(48).collect();
        println!(
            "{name:<48} {:<12} {:>24} {r:>12} {z:>8} {det:>9} {:>7.2}s  {verdict}",
            format!(
                "{}{}",
                o.estimator.name(),
                if o.sampler == SamplerKind::Independent {
                    String::new()
                } else {
                    format!("/{}", o.sampler.name())
                }
            ),
            format!("{:.6} ± {:.6}", o.estimate, o.std_error),
            o.seconds
        );
        if let Some(reason) = o.verdict.as_ref().and_then(|v| v.reason.as_ref()) {
            println!("    ↳ {reason}");
        }
    }
    for c in &chi2_rows {
        println!(
            "{:<48} {:<12} {:>24} {:>12} {:>8} {:>9} {:>8}  {}",
            format!("chi2 {}", c.name),
            "sampling",
            format!("p = {:.3e}", c.p_value),
            format!("dof {}", c.dof),
            "-",
            "-",
            "",
            if c.passed { "pass" } else { "FAIL" }
        );
        if let Some(r) = &c.reason {
            println!("    ↳ {r}");
        }
    }
    let failed = outcomes.iter().filter(|o| !o.passed()).count()
        + chi2_rows.iter().filter(|c| !c.passed).count();
    let total = outcomes.len() + chi2_rows.len();
    println!(
        "\n{} passed, {} failed  ({} cases, {} verdicts, Šidák over k = {k} at family α = {ALPHA}, seed {seed}, {:.1}s)",
        total - failed,
        failed,
        cases.len(),
        total,
        t0.elapsed().as_secs_f64()
    );
    if let Some(path) = json {
        let doc = serde_json::json!({ "seed": seed, "alpha": ALPHA, "tests": k, "outcomes": outcomes, "chi2": chi2_rows });
        let text = serde_json::to_string_pretty(&doc).map_err(|e| Failure::Input(e.to_string()))?;
        lightproof::io::write_atomic(&path, text.as_bytes())
            .map_err(|e| Failure::Input(format!("{}: cannot write: {e}", path.display())))?;
    }
    if failed > 0 {
        Err(Failure::Verdict)
    } else {
        Ok(())
    }
}

fn estimate(
    path: &Path,
    samples: Option<u64>,
    seed: u64,
    estimator: Option<Estimator>,
    sampler: SamplerKind,
) -> Result<(), Failure> {
    let case = Case::load(path)?;
    let est = estimator.unwrap_or(case.desc.estimators[0]);
    if !case.measure.estimators().contains(&est) {
        return Err(Failure::Input(format!(
            "{}: --estimator: `{}` cannot estimate {}",
            path.display(),
            est.name(),
            case.measure.name()
        )));
    }
    let n = samples
        .or(case.desc.samples)
        .unwrap_or(lightproof::verify::DEFAULT_SAMPLES);
    let run_seed = seed_for(seed, &case.desc.name, est, sampler);
    let spec = RunSpec {
        samples: n,
        sampler,
        seed: run_seed,
    };
    let e = case.estimate(est, &spec, false);
    let verdict = case.reference.map(|r| judge(&e, sampler, r, ALPHA, 1));
    let mut obj = serde_json::json!({
        "case": case.desc.name,
        "file": path.display().to_string(),
        "measure": case.measure.name(),
        "estimator": est,
        "sampler": sampler,
        "estimate": e.batches.total.mean,
        "std_error": verdict.as_ref().map_or(e.batches.total.std_error(), |v| v.std_error),
        "samples": e.batches.total.count + e.batches.total.non_finite,
        "seed": run_seed,
        "threads": rayon::current_num_threads(),
        "seconds": e.seconds,
        "effects": case.effects,
    });
    if let Some(v) = &verdict {
        obj["reference"] = serde_json::json!(v.reference);
        obj["z"] = serde_json::json!(v.z);
        obj["verdict"] = serde_json::to_value(v).unwrap_or_default();
    }
    println!(
        "{}",
        serde_json::to_string_pretty(&obj).map_err(|e| Failure::Input(e.to_string()))?
    );
    if verdict.is_some_and(|v| !v.passed) {
        Err(Failure::Verdict)
    } else {
        Ok(())
    }
}

fn chi2(json: &str, wo: &str, samples: u64, seed: u64, out: &Path) -> Result<(), Failure> {
    let bsdf =
        Bsdf::from_json(json).map_err(|e| Failure::Input(format!("<bsdf argument>: {e}")))?;
    let parts: Vec<f64> = wo
        .split(',')
        .map(|s| s.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| Failure::Input(format!("--wo: expected θ,φ in degrees, got `{wo}`")))?;
    if parts.len() != 2 || parts.iter().any(|x| !x.is_finite()) {
        return Err(Failure::Input(format!(
            "--wo: expected two finite numbers θ,φ in degrees, got `{wo}`"
        )));
    }
    let w = direction(parts[0].to_radians() as f32, parts[1].to_radians() as f32);
    let o = chi2_bsdf(&bsdf, bsdf.name(), w, samples, seed, ALPHA);
    let test = lightproof::stats::chi2::Chi2Test::new(
        lightproof::stats::chi2::Domain::Sphere,
        samples,
        seed,
        ALPHA,
    );
    let tables = lightproof::bsdf::contract::chi2_tables(&test, &bsdf, w);
    let files = lightproof::bsdf::contract::write_chi2_images(&tables, out, bsdf.name())
        .map_err(|e| Failure::Input(format!("{}: cannot write: {e}", out.display())))?;
    println!(
        "{}",
        serde_json::to_string_pretty(
            &serde_json::json!({ "bsdf": bsdf, "wo_degrees": parts, "outcome": o, "images": files })
        )
        .unwrap_or_default()
    );
    if o.passed {
        Ok(())
    } else {
        Err(Failure::Verdict)
    }
}

fn report(opts: &lightproof::report::sweep::Options) -> Result<(), Failure> {
    let bar = ProgressBar::new(0);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} points {elapsed} {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let summary = lightproof::report::sweep::run(opts, &bar)?;
    bar.finish_and_clear();
    for n in &summary.notes {
        eprintln!("note: {n}");
    }
    if let Some(p) = &summary.partial {
        println!(
            "wrote {} ({} points computed, {} resumed{})",
            p.display(),
            summary.computed,
            summary.resumed,
            if summary.budget_cut {
                ", budget cut"
            } else {
                ""
            }
        );
        return Ok(());
    }
    print_summary(&opts.out, &summary);
    Ok(())
}

fn print_summary(out: &Path, summary: &lightproof::report::sweep::Summary) {
    use lightproof::report::index::{cells, row};
    println!(
        "{:<44} {:<24} {:>28} {:>14} {:>10}",
        "case", "best", "time to 0.1%", "slope", "runner-up"
    );
    for r in &summary.reports {
        let [best, time, slope, ratio] = cells(&row(r));
        let id: String = r.id.chars().take(44).collect();
        println!("{id:<44} {best:<24} {time:>28} {slope:>14} {ratio:>10}");
    }
    println!(
        "\nwrote {} case reports to {} (index.md), {} points computed, {} resumed{}",
        summary.reports.len(),
        out.display(),
        summary.computed,
        summary.resumed,
        if summary.budget_cut {
            ", stopped by the budget"
        } else {
            ""
        }
    );
}
