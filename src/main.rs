//! The `lightproof` command line: a thin layer over the library.
//!
//! Exit status: 0 when every verdict passes, 1 when one fails, 2 on bad input.

use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use lightproof::bsdf::contract::direction;
use lightproof::bsdf::{Bsdf, BsdfModel};
use lightproof::case::{Case, collect_cases, count_in, seed_for};
use lightproof::error::{Error, InputError, IoError};
use lightproof::sampling::SamplerKind;
use lightproof::stats::{VerdictClass, sidak_alpha};
use lightproof::transport::Estimator;
use lightproof::verdict::{Outcome, judge_family};
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
    /// Run case files or folders (default: the whole catalog, then the chi-square suites,
    /// which run only when no PATH is given).
    Verify {
        /// Case files or folders.
        paths: Vec<PathBuf>,
        /// Base seed.
        #[arg(long, env = "LIGHTPROOF_SEED", default_value_t = DEFAULT_SEED, allow_negative_numbers = true, value_parser = parse_seed)]
        seed: u64,
        /// Worker threads, 1 to 8 × the logical cores (default: all cores).
        #[arg(long, allow_negative_numbers = true, value_parser = parse_threads)]
        threads: Option<usize>,
        /// Samples per estimate, 256 to 2^40, rounded up to a multiple of the 128 batches
        /// (to 128 × a power of two for stratified and sobol) (default: each case's own;
        /// below it a verdict's false-alarm rate is not established, and a failure says so).
        #[arg(long, allow_negative_numbers = true, value_parser = parse_samples)]
        samples: Option<u64>,
        /// Write every outcome as JSON to this file.
        #[arg(long)]
        json: Option<PathBuf>,
        /// Write the verdict page (one self-contained HTML file) to this file.
        #[arg(long)]
        html: Option<PathBuf>,
        /// Skip the chi-square suites (they run only when no PATH is given).
        #[arg(long)]
        no_chi2: bool,
        /// Print each case's name and what it teaches under its rows.
        #[arg(long, short)]
        verbose: bool,
    },
    /// Estimate one case: one JSON object on stdout.
    Estimate {
        /// The case file.
        case: PathBuf,
        /// Samples, 256 to 2^40, rounded up to a multiple of the 128 batches (to 128 × a
        /// power of two for stratified and sobol) (default: the case's own, else 2^18;
        /// below it the verdict's false-alarm rate is not established, and a failure says so).
        #[arg(long, allow_negative_numbers = true, value_parser = parse_samples)]
        samples: Option<u64>,
        /// Seed.
        #[arg(long, env = "LIGHTPROOF_SEED", default_value_t = DEFAULT_SEED, allow_negative_numbers = true, value_parser = parse_seed)]
        seed: u64,
        /// Worker threads, 1 to 8 × the logical cores (default: all cores).
        #[arg(long, allow_negative_numbers = true, value_parser = parse_threads)]
        threads: Option<usize>,
        /// Estimator (default: the case's first).
        #[arg(long, value_parser = parse_estimator)]
        estimator: Option<Estimator>,
        /// Sampler: independent, stratified or sobol (default: the case's first).
        #[arg(long, value_parser = parse_sampler)]
        sampler: Option<SamplerKind>,
    },
    /// Chi-square test of one BSDF configuration; writes observed/expected/residual EXRs.
    Chi2 {
        /// The BSDF as JSON, e.g. '{"type":"lambertian","albedo":0.5}'.
        bsdf: String,
        /// Outgoing direction as θ,φ in degrees, θ in [0, 180], φ in [-360, 360].
        #[arg(long, default_value = "30,0", allow_hyphen_values = true)]
        wo: String,
        /// Samples, 40960 (5 per cell of the 64 × 128 grid) to 2^32.
        #[arg(long, default_value_t = 1_000_000, allow_negative_numbers = true, value_parser = parse_chi2_samples)]
        samples: u64,
        /// Seed.
        #[arg(long, env = "LIGHTPROOF_SEED", default_value_t = DEFAULT_SEED, allow_negative_numbers = true, value_parser = parse_seed)]
        seed: u64,
        /// Folder for the tables (also of a failing test's dump), relative to the current one.
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
        /// this many wall seconds (a series' first point is predicted free: it always
        /// starts).
        #[arg(long, allow_negative_numbers = true, value_parser = parse_budget)]
        budget: Option<f64>,
        /// Largest sweep point, 256 to 2^40 (rounded down to a power of two).
        #[arg(long, default_value_t = lightproof::report::DEFAULT_MAX_SAMPLES, allow_negative_numbers = true, value_parser = parse_max_samples)]
        max_samples: u64,
        /// Smallest sweep point, 256 to 2^40 (rounded up to a power of two).
        #[arg(long, default_value_t = lightproof::report::DEFAULT_MIN_SAMPLES, allow_negative_numbers = true, value_parser = parse_min_samples)]
        min_samples: u64,
        /// Base seed.
        #[arg(long, env = "LIGHTPROOF_SEED", default_value_t = DEFAULT_SEED, allow_negative_numbers = true, value_parser = parse_seed)]
        seed: u64,
        /// Worker threads, 1 to 8 × the logical cores (default: all cores).
        #[arg(long, allow_negative_numbers = true, value_parser = parse_threads)]
        threads: Option<usize>,
        /// Run shard K of N (K from 0) and write its partial file, or `auto` to take the
        /// shard from a Slurm array or Kubernetes indexed Job.
        #[arg(long, allow_hyphen_values = true)]
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
    /// Render a scene with a camera to an EXR (or, named .png, an 8-bit sRGB PNG) image, for looking.
    Render {
        /// Scene file with a `camera`.
        scene: PathBuf,
        /// Samples per pixel, 1 to 2^20 (and width × height × spp at most 2^40).
        #[arg(long, default_value_t = 16, allow_negative_numbers = true, value_parser = parse_spp)]
        spp: u64,
        /// Output image: EXR (linear), or an 8-bit sRGB PNG when the name ends in .png.
        #[arg(short, long, default_value = "out.exr")]
        output: PathBuf,
        /// Seed.
        #[arg(long, env = "LIGHTPROOF_SEED", default_value_t = DEFAULT_SEED, allow_negative_numbers = true, value_parser = parse_seed)]
        seed: u64,
        /// Worker threads, 1 to 8 × the logical cores (default: all cores).
        #[arg(long, allow_negative_numbers = true, value_parser = parse_threads)]
        threads: Option<usize>,
        /// Most scatterings along a path, 0 (emission seen directly) to 2^16 (default:
        /// unlimited, with Russian roulette).
        #[arg(long, allow_negative_numbers = true, value_parser = parse_max_depth)]
        max_depth: Option<u32>,
        /// Multiply the image by 2^STOPS before writing, -64 to 64.
        #[arg(long, default_value_t = 0.0, allow_negative_numbers = true, value_parser = parse_exposure)]
        exposure: f32,
    },
    /// Export a case (or with --all the catalog) as a scene for another renderer.
    Export {
        /// The case file (or with --all, folders; default the catalog).
        paths: Vec<PathBuf>,
        /// Export every expressible case of the paths (default: the catalog) as a suite.
        #[arg(long)]
        all: bool,
        /// The renderer: mitsuba, pbrt or lightproof.
        #[arg(long, value_parser = lightproof::export::Target::parse)]
        to: lightproof::export::Target,
        /// Output folder.
        #[arg(long, default_value = "export")]
        out: PathBuf,
    },
    /// Judge a renderer's EXR renders of a case (or of an exported suite) against the reference.
    Judge {
        /// The case file, then its renders (several independent renders, or one with many pixels).
        files: Vec<PathBuf>,
        /// Judge every rendered case of an exported suite folder as one family.
        #[arg(long)]
        suite: Option<PathBuf>,
        /// The renderer's name, for the output.
        #[arg(long)]
        renderer: Option<String>,
        /// Print JSON instead of the table.
        #[arg(long)]
        json: bool,
    },
}

fn parse_samples(s: &str) -> Result<u64, String> {
    count_in(
        s,
        lightproof::case::MIN_SAMPLES,
        lightproof::case::MAX_SAMPLES,
        "2^40 (at least two per batch of 128; rounded up to a multiple of 128)",
    )
}

/// `report --max-samples`: the sweep's points are powers of two, so it rounds down to one
/// (not to a multiple of 128, as [`parse_samples`] says for `verify` and `estimate`).
fn parse_max_samples(s: &str) -> Result<u64, String> {
    count_in(
        s,
        lightproof::case::MIN_SAMPLES,
        lightproof::case::MAX_SAMPLES,
        "2^40 (at least two per batch of 128; rounded down to a power of two)",
    )
}

/// `report --min-samples`: rounded up to a power of two.
fn parse_min_samples(s: &str) -> Result<u64, String> {
    count_in(
        s,
        lightproof::case::MIN_SAMPLES,
        lightproof::case::MAX_SAMPLES,
        "2^40 (at least two per batch of 128; rounded up to a power of two)",
    )
}

/// Fewest chi-square samples: 5 expected per cell of the 64 × 128 sphere grid, so that
/// the test has the cells it judges with.
const MIN_CHI2_SAMPLES: u64 = 5 * 64 * 128;

fn parse_chi2_samples(s: &str) -> Result<u64, String> {
    count_in(
        s,
        MIN_CHI2_SAMPLES,
        1 << 32,
        "2^32 (fewer than 5 per cell of the 64 × 128 grid cannot be judged)",
    )
}

fn parse_spp(s: &str) -> Result<u64, String> {
    count_in(s, 1, lightproof::render::MAX_SPP, "2^20")
}

fn parse_max_depth(s: &str) -> Result<u32, String> {
    count_in(s, 0, lightproof::render::MAX_DEPTH as u64, "2^16").map(|v| v as u32)
}

fn parse_exposure(s: &str) -> Result<f32, String> {
    match s.trim().parse::<f32>() {
        Ok(v) if (-64.0..=64.0).contains(&v) => Ok(v),
        _ => Err(format!(
            "must be a number of stops from -64 to 64, got `{s}`"
        )),
    }
}

fn parse_seed(s: &str) -> Result<u64, String> {
    count_in(s, 0, u64::MAX, "2^64 − 1")
}

/// Most worker threads: 8 × the logical cores.
fn max_threads() -> usize {
    8 * std::thread::available_parallelism().map_or(1, |n| n.get())
}

fn parse_threads(s: &str) -> Result<usize, String> {
    let max = max_threads();
    count_in(s, 1, max as u64, &format!("{max} (8 × the logical cores)")).map(|v| v as usize)
}

fn parse_budget(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        _ => Err(format!("must be a positive number of seconds, got `{s}`")),
    }
}

fn parse_estimator(s: &str) -> Result<Estimator, String> {
    serde_json::from_value(serde_json::Value::String(s.to_string())).map_err(|_| {
        let names: Vec<&str> = Estimator::ALL.iter().map(|e| e.name()).collect();
        format!("unknown estimator `{s}` ({})", names.join(", "))
    })
}

fn parse_sampler(s: &str) -> Result<SamplerKind, String> {
    serde_json::from_value(serde_json::Value::String(s.to_string()))
        .map_err(|_| format!("unknown sampler `{s}` (independent, stratified, sobol)"))
}

/// How a command fails; each class has its exit status (README, "Exit status").
enum Failure {
    /// Bad input: exit 2.
    Input(String),
    /// An output that cannot be written, or another failure of the environment: exit 3.
    Io(String),
    /// A verdict failed: exit 1.
    Verdict,
}

impl From<InputError> for Failure {
    fn from(e: InputError) -> Self {
        Failure::Input(e.to_string())
    }
}

impl From<IoError> for Failure {
    fn from(e: IoError) -> Self {
        Failure::Io(e.to_string())
    }
}

impl From<Error> for Failure {
    fn from(e: Error) -> Self {
        match e {
            Error::Input(e) => e.into(),
            Error::Io(e) => e.into(),
        }
    }
}

/// Write to stdout and flush: a failed write (`> /dev/full`) is an output that cannot be
/// written, exit 3, where `print!` would panic. A closed pipe never gets here: SIGPIPE
/// ends the process first ([`quiet_on_broken_pipe`]).
fn write_stdout(text: std::fmt::Arguments) -> Result<(), Failure> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    out.write_fmt(text).and_then(|()| out.flush()).map_err(|e| {
        Failure::Io(
            IoError {
                path: "<stdout>".to_string(),
                reason: format!("cannot write: {e}"),
            }
            .to_string(),
        )
    })
}

/// `print!` that fails with exit 3 instead of panicking ([`write_stdout`]).
macro_rules! out {
    ($($t:tt)*) => { write_stdout(format_args!($($t)*)) };
}

/// `println!` that fails with exit 3 instead of panicking ([`write_stdout`]).
macro_rules! outln {
    ($($t:tt)*) => { write_stdout(format_args!("{}\n", format_args!($($t)*))) };
}

/// One line on stderr. A write that fails (stderr closed, or a full disk behind it) is
/// ignored, where `eprintln!` would panic: the exit status still tells the outcome.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr(), $($arg)*);
    }};
}

/// Let a closed pipe end the process quietly, as Unix tools do (`lightproof estimate
/// CASE | head -n 3`): Rust ignores SIGPIPE, which turns the write into a panic.
fn quiet_on_broken_pipe() {
    #[cfg(unix)]
    {
        unsafe extern "C" {
            fn signal(signum: i32, handler: usize) -> usize;
        }
        const SIGPIPE: i32 = 13;
        const SIG_DFL: usize = 0;
        // SAFETY: restores the default disposition of one signal before any thread starts.
        unsafe {
            signal(SIGPIPE, SIG_DFL);
        }
    }
}

/// Parse the command line; a usage error is one line on stderr and exit status 2. Help
/// and the version go to stdout, which that cannot be written (`--help > /dev/full`)
/// exits 3 as every other output does ([`write_stdout`]); help on stderr (a command with
/// its arguments missing) keeps its status whatever becomes of the text.
fn parse_cli() -> Result<Cli, ExitCode> {
    use clap::error::ErrorKind;
    use std::io::Write as _;
    match Cli::try_parse() {
        Ok(cli) => Ok(cli),
        Err(e)
            if matches!(
                e.kind(),
                ErrorKind::DisplayHelp
                    | ErrorKind::DisplayVersion
                    | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
            ) =>
        {
            let printed = e.print().and_then(|()| std::io::stdout().flush());
            match printed {
                Err(why) if !e.use_stderr() => {
                    say!("error: <stdout>: cannot write: {why}");
                    Err(ExitCode::from(3))
                }
                Ok(()) | Err(_) => Err(ExitCode::from(e.exit_code().clamp(0, 255) as u8)),
            }
        }
        Err(e) => Err(usage_error(&e)),
    }
}

/// A usage error: one line on stderr, exit status 2. Text that is not UTF-8 in
/// `LIGHTPROOF_SEED` (the default `--seed`, which clap reads) is named: clap's own message
/// says only "invalid UTF-8 was detected in one or more arguments".
fn usage_error(e: &clap::Error) -> ExitCode {
    use clap::error::{ContextKind, ContextValue, ErrorKind};
    let seed = std::env::var_os("LIGHTPROOF_SEED");
    // A bad `--seed` that no argument gave came from the variable: clap blames the flag.
    let seed_flag = matches!(e.get(ContextKind::InvalidArg),
        Some(ContextValue::String(a)) if a.starts_with("--seed"));
    let from_env = e.kind() == ErrorKind::ValueValidation
        && seed_flag
        && !std::env::args_os()
            .skip(1)
            .any(|a| a == "--seed" || a.to_string_lossy().starts_with("--seed="));
    match seed.as_deref().map(|v| (v, v.to_str())) {
        Some((v, None)) if e.kind() == ErrorKind::InvalidUtf8 => say!(
            "error: <environment>: LIGHTPROOF_SEED: is not UTF-8 text, got {:?} (it is the default --seed)",
            v.to_string_lossy()
        ),
        Some((_, Some(text))) if from_env => say!(
            "error: <environment>: LIGHTPROOF_SEED: {} (it is the default --seed; an empty one counts as unset)",
            parse_seed(text).err().unwrap_or_default()
        ),
        _ => {
            let text = e.render().to_string();
            let line: Vec<&str> = text
                .lines()
                .map(str::trim)
                .take_while(|l| !l.starts_with("Usage:") && !l.starts_with("For more information"))
                .filter(|l| !l.is_empty())
                .collect();
            say!("{} (see --help)", line.join(" "));
        }
    }
    ExitCode::from(2)
}

/// The command given, or with none (a bare `lightproof`) `verify` with every default of
/// its own arguments, parsed as `lightproof verify` so the defaults live in one place.
/// (A `LIGHTPROOF_SEED` that is not UTF-8 fails that parse: a usage error naming it.)
fn command_or_verify(cli: Cli) -> Result<Command, clap::Error> {
    match cli.command {
        Some(c) => Ok(c),
        None => Cli::try_parse_from(["lightproof", "verify"])?
            .command
            .ok_or_else(|| clap::Error::new(clap::error::ErrorKind::MissingSubcommand)),
    }
}

/// An empty `LIGHTPROOF_SEED` counts as unset (`LIGHTPROOF_SEED= lightproof`: the
/// default seed), as users of pbrt and Mitsuba expect of an empty variable; clap would
/// read it as `--seed ''`, an error.
fn empty_seed_is_unset() {
    if std::env::var_os("LIGHTPROOF_SEED").is_some_and(|v| v.is_empty()) {
        // SAFETY: called first in `main`, before any thread starts, so nothing reads or
        // writes the environment meanwhile.
        unsafe { std::env::remove_var("LIGHTPROOF_SEED") };
    }
}

/// `LIGHTPROOF_ISA` (README "Ray casting: one answer on every x86-64 CPU"), which the
/// library reads when the first scene is built, is checked first: a value it does not
/// know is a usage error naming the variable, not silently the CPU's own choice.
fn check_isa_variable() -> Result<(), ExitCode> {
    use lightproof::scene::accel::Isa;
    Isa::from_env().map(drop).map_err(|reason| {
        say!("error: <environment>: {}: {reason}", Isa::ENV);
        ExitCode::from(2)
    })
}

/// Ctrl-C, SIGTERM or SIGHUP: let the file write under way end (renamed into place,
/// whole) and start no other, then exit 130, so no `.NAME.tmpPID` is left behind
/// (`lightproof::io::hold_writes`).
fn end_cleanly_on_interrupt() {
    // Where no handler can be set (another one is already), the default stays.
    let _ = ctrlc::set_handler(|| {
        let _writes = lightproof::io::hold_writes();
        let _ = std::io::Write::write_all(
            &mut std::io::stderr(),
            b"interrupted: every file written is whole\n",
        );
        std::process::exit(130);
    });
}

fn main() -> ExitCode {
    end_cleanly_on_interrupt();
    quiet_on_broken_pipe();
    empty_seed_is_unset();
    if let Err(code) = check_isa_variable() {
        return code;
    }
    let cli = match parse_cli() {
        Ok(cli) => cli,
        Err(code) => return code,
    };
    let command = match command_or_verify(cli) {
        Ok(c) => c,
        Err(e) => return usage_error(&e),
    };
    let threads = match &command {
        Command::Verify { threads, .. }
        | Command::Estimate { threads, .. }
        | Command::Report { threads, .. }
        | Command::Render { threads, .. } => *threads,
        Command::Chi2 { .. }
        | Command::Merge { .. }
        | Command::Export { .. }
        | Command::Judge { .. } => None,
    };
    let pool = match rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()
    {
        Ok(p) => p,
        Err(e) => {
            say!("error: worker threads: cannot start: {e}");
            return ExitCode::from(3);
        }
    };
    match pool.install(|| dispatch(command)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Verdict) => ExitCode::from(1),
        Err(Failure::Input(msg)) => {
            say!("error: {msg}");
            ExitCode::from(2)
        }
        Err(Failure::Io(msg)) => {
            say!("error: {msg}");
            ExitCode::from(3)
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

/// Named files or folders must hold at least one case file: an empty folder is bad input,
/// not a vacuous pass.
fn require_cases(paths: &[PathBuf]) -> Result<(), Failure> {
    for p in paths {
        if collect_cases(std::slice::from_ref(p))?.is_empty() {
            return Err(Failure::Input(format!(
                "{}: no case files (*.json) found",
                p.display()
            )));
        }
    }
    Ok(())
}

/// Refuse an `--out` folder that is, or lies inside, an input folder (what is written
/// there would be read as cases on the next run), or that holds an input case file (a
/// report or an exported `case.json` could replace it).
fn refuse_folder_on_input(out: &Path, paths: &[PathBuf]) -> Result<(), Failure> {
    let files = collect_cases(paths)?;
    let folders: Vec<PathBuf> = paths.iter().filter(|p| p.is_dir()).cloned().collect();
    lightproof::io::refuse_output_folder_on_input("--out", out, &files, &folders)?;
    Ok(())
}

fn dispatch(command: Command) -> Result<(), Failure> {
    match command {
        Command::Verify {
            paths,
            seed,
            samples,
            json,
            html,
            no_chi2,
            verbose,
            ..
        } => {
            require_cases(&paths)?;
            verify(paths, seed, samples, [json, html], no_chi2, verbose)
        }
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
                Some("auto") => {
                    use lightproof::report::shard::{shard_env, shard_from_env};
                    Some(shard_from_env(&shard_env(|n| std::env::var_os(n))?)?)
                }
                Some(s) => Some(lightproof::report::shard::parse_shard(s)?),
            };
            require_cases(&paths)?;
            let paths = if paths.is_empty() {
                vec![default_catalog()]
            } else {
                paths
            };
            refuse_folder_on_input(&out, &paths)?;
            let opts = lightproof::report::sweep::Options {
                paths,
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
            print_notes(&summary);
            print_summary(&out, &summary, "merged (computed by the shards)")
        }
        Command::Render {
            scene,
            spp,
            output,
            seed,
            threads: _,
            max_depth,
            exposure,
        } => {
            lightproof::render::check_output_name(&output)?;
            lightproof::io::refuse_output_on_input(
                "-o",
                &output,
                &lightproof::render::input_files(&scene)?,
                &[],
            )?;
            lightproof::io::check_output_file(&output)?;
            let t0 = std::time::Instant::now();
            let image = lightproof::render::render_file(&scene, spp, seed, max_depth)?;
            let (w, h, data) = (image.width, image.height, &image.pixels[..]);
            let seconds = t0.elapsed().as_secs_f64();
            let paths = (w * h) as f64 * spp as f64;
            lightproof::render::write_image(&output, w, h, data, exposure)
                .map_err(|e| IoError::write(&output, e))?;
            say!(
                "wrote {} ({w}×{h}, {spp} spp): {paths} paths in {seconds:.3} s, {:.0} paths/s on {} threads",
                output.display(),
                paths / seconds.max(f64::MIN_POSITIVE),
                rayon::current_num_threads()
            );
            if image.cut_at_guard > 0 {
                say!(
                    "{} of {paths} paths were still scattering at the guard of {} scatterings and were cut there: the image is short of the rest of their energy (give --max-depth to choose the cut)",
                    image.cut_at_guard,
                    lightproof::render::MAX_DEPTH
                );
            }
            // Never masked: a pixel that is not finite is a bug, kept in the image (in a
            // PNG, NaN black and +∞ white) and reported, and the command fails.
            match lightproof::render::non_finite_pixels(w, data) {
                (0, _) => Ok(()),
                (n, first) => {
                    let (x, y) = first.unwrap_or_default();
                    say!(
                        "{n} pixels are not finite (NaN or ±∞), the first at ({x}, {y}): a bug of the engine"
                    );
                    Err(Failure::Verdict)
                }
            }
        }
        Command::Export {
            paths,
            all,
            to,
            out,
        } => {
            let paths = if all && paths.is_empty() {
                vec![default_catalog()]
            } else {
                paths
            };
            if all {
                require_cases(&paths)?;
                refuse_folder_on_input(&out, &paths)?;
            }
            outln!("{}", lightproof::export::run(&paths, all, to, &out)?)?;
            Ok(())
        }
        Command::Judge {
            files,
            suite,
            renderer,
            json,
        } => {
            let (text, passed) =
                lightproof::judge::run(&files, suite.as_deref(), renderer.as_deref(), json, ALPHA)?;
            out!("{text}")?;
            if passed {
                Ok(())
            } else {
                Err(Failure::Verdict)
            }
        }
    }
}

fn verify(
    paths: Vec<PathBuf>,
    seed: u64,
    samples: Option<u64>,
    [json, html]: [Option<PathBuf>; 2],
    no_chi2: bool,
    verbose: bool,
) -> Result<(), Failure> {
    let whole = paths.is_empty();
    let paths = if whole {
        vec![default_catalog()]
    } else {
        paths
    };
    let files = collect_cases(&paths)?;
    // An output on an input (`verify in.json --json in.json`) is refused before any work.
    let folders: Vec<PathBuf> = paths.iter().filter(|p| p.is_dir()).cloned().collect();
    for (flag, out) in [("--json", &json), ("--html", &html)] {
        if let Some(out) = out {
            lightproof::io::refuse_output_on_input(flag, out, &files, &folders)?;
        }
    }
    for out in json.iter().chain(&html) {
        lightproof::io::check_output_file(out)?;
    }
    // Each case's file id: its path under the folder given, without `.json`.
    let mut ids = std::collections::BTreeMap::new();
    for p in &paths {
        let root = p.is_dir().then_some(p.as_path());
        for f in collect_cases(std::slice::from_ref(p))? {
            ids.entry(f.display().to_string())
                .or_insert_with(|| lightproof::report::store::case_id(root, &f));
        }
    }
    let cases: Vec<Case> = files
        .iter()
        .map(|f| Case::load(f))
        .collect::<Result<_, _>>()?;
    // Nor on a file a case's scene reads (an OBJ mesh, an EXR map), nor both outputs on
    // one file (the page would replace the JSON).
    let assets: Vec<PathBuf> = cases.iter().flat_map(Case::external_paths).collect();
    for (flag, out) in [("--json", &json), ("--html", &html)] {
        if let Some(out) = out {
            lightproof::io::refuse_output_on_input(flag, out, &assets, &[])?;
        }
    }
    if let (Some(j), Some(h)) = (&json, &html) {
        lightproof::io::refuse_same_output(("--json", j), ("--html", h))?;
    }
    let warp_suite = if whole && !no_chi2 {
        lightproof::suites::warps()
    } else {
        vec![]
    };
    let t0 = Instant::now();
    let bar = ProgressBar::new((cases.len() + warp_suite.len()) as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let mut outcomes: Vec<Outcome> = Vec::new();
    // Per outcome: the samples it ran and its case's own count.
    let mut counts: Vec<(u64, u64)> = Vec::new();
    for c in &cases {
        bar.set_message(c.desc.name.clone());
        let run = c.run_all(seed, samples, 1);
        counts.extend(std::iter::repeat_n(
            (c.samples(samples, 1), c.samples(None, 1)),
            run.len(),
        ));
        outcomes.extend(run);
        bar.inc(1);
    }
    // One family: the statistical verdicts and the chi-square suites (exact ones apart).
    let k = judge_family(&mut outcomes, warp_suite.len(), ALPHA);
    let mut below = 0;
    for (o, &(ran, own)) in outcomes.iter_mut().zip(&counts) {
        o.require_power(!o.drew_fewer(ran, own));
        below += usize::from(o.note_fewer_samples(ran, own));
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
    let mut rows = Vec::new();
    let mut named = std::collections::BTreeSet::new();
    for o in &outcomes {
        let id = ids.get(&o.file).map_or(o.case.as_str(), |s| s.as_str());
        let mut row = lightproof::table::outcome_row(id, o);
        if verbose && named.insert(o.file.clone()) {
            let teaches = cases
                .iter()
                .find(|c| c.file.display().to_string() == o.file)
                .map_or("", |c| c.desc.teaches.as_str());
            row.notes.insert(0, format!("{}: {teaches}", o.case));
        }
        rows.push(row);
    }
    rows.extend(chi2_rows.iter().map(lightproof::table::chi2_row));
    out!(
        "{}",
        lightproof::table::render(&rows, lightproof::table::terminal_width())
    )?;
    let failed = outcomes.iter().filter(|o| !o.passed()).count()
        + chi2_rows.iter().filter(|c| !c.passed).count();
    let total = outcomes.len() + chi2_rows.len();
    // Passes by the class of their verdict; an outcome without a reference has none (it
    // was estimated, not judged) and is counted apart, never as a statistical pass.
    let passed_of = |class: VerdictClass| {
        outcomes
            .iter()
            .filter(|o| o.passed() && o.verdict.as_ref().is_some_and(|v| v.class == class))
            .count()
    };
    let exact = passed_of(VerdictClass::Exact);
    let statistical =
        passed_of(VerdictClass::Statistical) + chi2_rows.iter().filter(|c| c.passed).count();
    let unjudged = match outcomes
        .iter()
        .filter(|o| o.passed() && o.verdict.is_none())
        .count()
    {
        0 => String::new(),
        n => format!(", {n} without a reference: estimated, not judged"),
    };
    // Verdicts whose reference moves when its inputs round to f32 take that in too.
    let moved = match outcomes
        .iter()
        .filter(|o| o.verdict.is_some() && o.reference_rounding != 0.0)
        .count()
    {
        0 => String::new(),
        n => format!(
            "; {n} verdict{} also allow{} the reference's change at the engine's f32 inputs",
            if n == 1 { "" } else { "s" },
            if n == 1 { "s" } else { "" }
        ),
    };
    outln!(
        "\n{} passed ({statistical} statistical, {exact} exact{unjudged}), {failed} failed  ({} cases, {total} verdicts; statistical ones Šidák-corrected over k = {k} at family α = {ALPHA}; exact ones within the f32 error bound {:.2e}·|reference|{moved}; seed {seed}, {:.1}s)",
        total - failed,
        cases.len(),
        lightproof::stats::exact_relative_tolerance(),
        t0.elapsed().as_secs_f64()
    )?;
    // Weak at the case's own count only where the reference is 0: its own line.
    let (weak, weak_zero) = lightproof::verdict::weak_counts(&outcomes, &counts);
    if weak > 0 {
        outln!(
            "{weak} of the {statistical} statistical passes are weak: drawn with fewer samples than their case's own count (--samples), they cannot see a {}% bias, so they show agreement, not a proof: rerun at the case's own count",
            100.0 * lightproof::verdict::DETECTABLE_BOUND
        )?;
    }
    if weak_zero > 0 {
        outln!(
            "{weak_zero} of the {statistical} statistical passes are weak: their reference is 0, so there is no relative bias to see, and they cannot see an absolute one of {} (in their case's units): raise their case's samples",
            lightproof::verdict::DETECTABLE_BOUND
        )?;
    }
    if below > 0 {
        outln!(
            "{below} of the {failed} failures drew fewer samples than their case's own count (--samples), where a false alarm is possible: see their reasons"
        )?;
    }
    if let Some(path) = json {
        let doc = serde_json::json!({ "seed": seed, "alpha": ALPHA, "tests": k, "outcomes": outcomes, "chi2": chi2_rows });
        let text = serde_json::to_string_pretty(&doc).map_err(|e| Failure::Input(e.to_string()))?;
        lightproof::io::write_atomic(&path, text.as_bytes())
            .map_err(|e| IoError::write(&path, e))?;
    }
    if let Some(path) = html {
        use lightproof::report::html::{Page, case_infos, write};
        let cases = case_infos(&cases, &ids);
        let page = Page {
            outcomes: &outcomes,
            cases: &cases,
            chi2: &chi2_rows,
            seed,
            alpha: ALPHA,
            tests: k,
        };
        write(&path, &page).map_err(|e| IoError::write(&path, e))?;
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
    sampler: Option<SamplerKind>,
) -> Result<(), Failure> {
    let case = Case::load(path)?;
    let est = estimator.unwrap_or(case.desc.estimators[0]);
    let sampler = sampler.unwrap_or(case.samplers()[0]);
    if !case.measure.estimators().contains(&est) {
        return Err(Failure::Input(format!(
            "{}: --estimator: `{}` cannot estimate {}",
            path.display(),
            est.name(),
            case.measure.name()
        )));
    }
    let run_seed = seed_for(seed, &case.desc.name, est, sampler);
    let n = case.samples(samples, 1);
    // A time-resolved histogram adds one outcome per bin; all are judged as one family.
    let mut all = vec![case.run(est, sampler, n, run_seed)];
    all.extend(case.run_bins(est, sampler, n, seed));
    judge_family(&mut all, 0, ALPHA);
    // What puts the run outside the proof's conditions, besides its count: an estimator
    // or a sampler the case does not list.
    let names = |v: Vec<&str>| v.join(", ");
    let unlisted = if !case.desc.estimators.contains(&est) {
        Some((
            format!(
                "`{}` is not among the case's estimators ({})",
                est.name(),
                names(case.desc.estimators.iter().map(|e| e.name()).collect())
            ),
            "run the case's own estimators to tell",
        ))
    } else if !case.samplers().contains(&sampler) {
        Some((
            format!(
                "`{}` is not among the case's samplers ({})",
                sampler.name(),
                names(case.samplers().iter().map(|s| s.name()).collect())
            ),
            "run the case's own samplers to tell",
        ))
    } else {
        None
    };
    let own = case.samples(None, 1);
    for o in &mut all {
        o.require_power(unlisted.is_none() && !o.drew_fewer(n, own));
        o.note_fewer_samples(n, own);
        if let Some((what, remedy)) = &unlisted {
            o.note_outside_the_proof(what, remedy);
        }
    }
    let outcome = &all[0];
    let mut obj = serde_json::to_value(outcome).map_err(|e| Failure::Input(e.to_string()))?;
    obj["threads"] = serde_json::json!(rayon::current_num_threads());
    if all.len() > 1 {
        obj["bins"] = serde_json::json!(all[1..]);
    }
    outln!(
        "{}",
        serde_json::to_string_pretty(&obj).map_err(|e| Failure::Input(e.to_string()))?
    )?;
    // A failed verdict, or non-finite samples without a reference, exit 1.
    if all.iter().all(Outcome::passed) {
        Ok(())
    } else {
        Err(Failure::Verdict)
    }
}

fn chi2(json: &str, wo: &str, samples: u64, seed: u64, out: &Path) -> Result<(), Failure> {
    let bsdf =
        Bsdf::from_json(json).map_err(|e| Failure::Input(format!("<bsdf argument>: {e}")))?;
    if !bsdf.flags().has_density() {
        return Err(Failure::Input(format!(
            "<bsdf argument>: a `{}` has only Dirac delta lobes, so no density to compare sampled directions with: chi-square tests a model with a diffuse or glossy lobe (its delta directions are checked by `cargo test`'s BSDF contract)",
            bsdf.name()
        )));
    }
    let parts: Vec<f64> = wo
        .split(',')
        .map(|s| s.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| {
            Failure::Input(format!(
                "<command line>: --wo: expected θ,φ in degrees, got `{wo}`"
            ))
        })?;
    if parts.len() != 2 || parts.iter().any(|x| !x.is_finite()) {
        return Err(Failure::Input(format!(
            "<command line>: --wo: expected two finite numbers θ,φ in degrees, got `{wo}`"
        )));
    }
    if !((0.0..=180.0).contains(&parts[0]) && (-360.0..=360.0).contains(&parts[1])) {
        return Err(Failure::Input(format!(
            "<command line>: --wo: θ must lie in [0, 180] and φ in [-360, 360] degrees, got `{wo}`"
        )));
    }
    lightproof::io::check_output_dir(out)?;
    let w = direction(parts[0].to_radians() as f32, parts[1].to_radians() as f32);
    // A failing test's dump goes under --out too, never into the build's own tree.
    let test = lightproof::stats::chi2::Chi2Test::new(
        lightproof::stats::chi2::Domain::Sphere,
        samples,
        seed,
        ALPHA,
    )
    .with_dump_dir(out.join("chi2-failures"));
    // One histogram and one quadrature: judged, then shown.
    let tables = lightproof::bsdf::contract::chi2_tables(&test, &bsdf, w);
    let o = test.judge(bsdf.name(), &tables);
    let files = lightproof::bsdf::contract::write_chi2_images(&tables, out, bsdf.name())
        .map_err(|e| IoError::write(out, e))?;
    outln!(
        "{}",
        serde_json::to_string_pretty(
            &serde_json::json!({ "bsdf": bsdf, "wo_degrees": parts, "outcome": o, "images": files })
        )
        .unwrap_or_default()
    )?;
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
    let summary = lightproof::report::sweep::run(opts, &mut |p| {
        bar.set_length(p.total);
        bar.set_position(p.done);
        bar.set_message(p.current.to_string());
    })?;
    bar.finish_and_clear();
    print_notes(&summary);
    if let Some(p) = &summary.partial {
        outln!(
            "wrote {} ({} points computed, {} resumed{})",
            p.display(),
            summary.computed,
            summary.resumed,
            if summary.budget_cut {
                ", budget cut"
            } else {
                ""
            }
        )?;
        return Ok(());
    }
    print_summary(&opts.out, &summary, "computed")
}

/// A sweep's or a merge's notes (a report started afresh, a case with no plot), on stderr.
fn print_notes(summary: &lightproof::report::sweep::Summary) {
    for n in &summary.notes {
        say!("note: {n}");
    }
}

/// The table and closing line of `report` and `merge`; `computed` says what happened to
/// the points this run did not resume (`merge` computes none: its shards did).
fn print_summary(
    out: &Path,
    summary: &lightproof::report::sweep::Summary,
    computed: &str,
) -> Result<(), Failure> {
    use lightproof::report::index::{cells, row};
    outln!(
        "{:<44} {:<24} {:>28} {:>14} {:>10}",
        "case",
        "best",
        "time to 0.1%",
        "slope",
        "runner-up"
    )?;
    for r in &summary.reports {
        let [best, time, slope, ratio] = cells(&row(r));
        let id: String = r.id.chars().take(44).collect();
        outln!("{id:<44} {best:<24} {time:>28} {slope:>14} {ratio:>10}")?;
    }
    outln!(
        "\nwrote {} case reports to {} (index.md), {} points {computed}, {} resumed{}",
        summary.reports.len(),
        out.display(),
        summary.computed,
        summary.resumed,
        if summary.budget_cut {
            ", stopped by the budget"
        } else {
            ""
        }
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bare `lightproof` is `lightproof verify`: the whole catalog at the default seed,
    /// every core, each case's own sample count, the chi-square suites on, no files.
    #[test]
    fn bare_lightproof_is_verify_with_its_defaults() {
        let bare = Cli::try_parse_from(["lightproof"]).unwrap();
        assert!(bare.command.is_none());
        match command_or_verify(bare) {
            Ok(Command::Verify {
                paths,
                seed,
                threads,
                samples,
                json,
                html,
                no_chi2,
                verbose,
            }) => {
                assert!(paths.is_empty());
                assert_eq!(seed, DEFAULT_SEED);
                assert_eq!((threads, samples), (None, None));
                assert_eq!((json, html), (None, None));
                assert!(!no_chi2 && !verbose);
            }
            _ => panic!("a bare `lightproof` must run `verify`"),
        }
        // A command given is kept.
        let given = Cli::try_parse_from(["lightproof", "verify", "--seed", "7"]).unwrap();
        assert!(matches!(
            command_or_verify(given),
            Ok(Command::Verify { seed: 7, .. })
        ));
    }
}
