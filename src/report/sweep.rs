//! The sweep: plan every point of every series, run them cheapest first within the
//! budget, keep what an earlier run left, write as it goes.
//!
//! **Plan.** Each case × estimator (the case's, or those of `--estimator`) × sampler
//! (all three, or those of `--sampler`) is a series; its points are N = 2ᵏ for
//! k = log₂ min … log₂ max, each with the seed `hash_words([series seed, k])`.
//!
//! **Order and budget.** Pending points wait in a queue ordered by predicted wall time:
//! twice the wall time of the series' previous point per doubling of N (a first point is
//! predicted free). The cheapest runs next, so every series gets its small points before
//! any series gets a large one. With `--budget T`, the run stops, writing everything,
//! as soon as the cheapest pending point is predicted to end after T; the series left
//! over are marked `budget_cut` and the run records `budget_cut: true`.
//!
//! **Resume.** A case report already in the output folder, written by the same build
//! (version and git revision) for the same case description and seed, gives back its
//! points: only missing ones run, so a larger `--max-samples` extends a sweep. A shard
//! resumes from its partial file the same way. `--fresh` ignores what is there.
//!
//! **Writing.** Each case report (and a shard's partial) is rewritten atomically after a
//! point finishes, at most once a second (less often when writing takes more than a
//! tenth of the time), and once more at the end with the plots and the index, so a
//! killed run leaves whole, valid files.

use super::analysis::{assemble_case_report, point_from_batches, summarized_series};
use super::machine::{GIT_REVISION, PROFILE, VERSION, run_info};
pub use super::publish::Summary;
use super::publish::publish;
use super::shard::{
    BatchRecord, Shard, ShardCase, ShardPartial, ShardPoint, ShardSeries, error_measure,
    read_partial, write_partial,
};
use super::store::{OUTPUT_ADVICE, case_id, digest, read_case_report, report_file, write_json};
use super::{
    BATCHES, CaseInfo, CaseReport, FORMAT, Kind, Point, RunInfo, Series, Settings, Status,
};
use crate::case::{Case, collect_cases, seed_for};
use crate::error::{Error, InputError};
use crate::sampling::SamplerKind;
use crate::sampling::sampler::hash_words;
use crate::stats::Accumulator;
use crate::transport::Estimator;
use crate::transport::engine::{RunSpec, run_batches};
use rayon::prelude::*;
use std::cmp::Reverse;
use std::collections::{BTreeMap, BinaryHeap};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// What `lightproof report` was asked.
#[derive(Clone, Debug)]
pub struct Options {
    /// Case files or folders.
    pub paths: Vec<PathBuf>,
    /// Output folder.
    pub out: PathBuf,
    /// Wall-time budget in seconds.
    pub budget: Option<f64>,
    /// Smallest point (rounded up to a power of two).
    pub min_samples: u64,
    /// Largest point (rounded down to a power of two).
    pub max_samples: u64,
    /// Base seed.
    pub seed: u64,
    /// Only these estimators (empty: each case's own).
    pub estimators: Vec<Estimator>,
    /// Only these samplers (empty: all three).
    pub samplers: Vec<SamplerKind>,
    /// Run one shard and write its partial file.
    pub shard: Option<Shard>,
    /// Ignore earlier reports in the output folder.
    pub fresh: bool,
}

fn cli_err(field: &str, reason: impl Into<String>) -> InputError {
    InputError::new("<command line>", field, reason)
}

/// Check the options and turn them into sweep settings.
pub fn settings(opts: &Options) -> Result<Settings, InputError> {
    let min_allowed = 2 * BATCHES;
    if opts.min_samples < min_allowed {
        return Err(cli_err(
            "--min-samples",
            format!(
                "must be at least {min_allowed} (two samples per batch), got {}",
                opts.min_samples
            ),
        ));
    }
    if opts.min_samples > 1 << 40 {
        return Err(cli_err(
            "--min-samples",
            format!("must be at most 2^40, got {}", opts.min_samples),
        ));
    }
    if opts.max_samples > 1 << 40 {
        return Err(cli_err(
            "--max-samples",
            format!("must be at most 2^40, got {}", opts.max_samples),
        ));
    }
    let min = opts.min_samples.next_power_of_two();
    let max = if opts.max_samples.is_power_of_two() {
        opts.max_samples
    } else {
        opts.max_samples.next_power_of_two() / 2
    };
    if max < min {
        return Err(cli_err(
            "--max-samples",
            format!(
                "must be at least --min-samples rounded up to a power of two ({min}), got {}",
                opts.max_samples
            ),
        ));
    }
    if let Some(b) = opts.budget
        && !(b.is_finite() && b > 0.0)
    {
        return Err(cli_err(
            "--budget",
            format!("must be a positive number of seconds, got {b}"),
        ));
    }
    Ok(Settings {
        seed: opts.seed,
        min_samples: min,
        max_samples: max,
        batches: BATCHES,
    })
}

/// One series being swept.
struct SeriesState {
    est: Estimator,
    sampler: SamplerKind,
    seed: u64,
    /// Finished points by k (single run).
    done: BTreeMap<u32, Point>,
    /// Finished shard parts by k (shard run).
    parts: BTreeMap<u32, ShardPoint>,
    /// Known wall time of finished points by k (for predictions).
    wall: BTreeMap<u32, f64>,
    /// Points still to run, ascending.
    pending: Vec<u32>,
    /// Stopped by the budget.
    cut: bool,
}

impl SeriesState {
    fn status(&self) -> Status {
        if self.pending.is_empty() {
            Status::Complete
        } else if self.cut {
            Status::BudgetCut
        } else {
            Status::InProgress
        }
    }

    /// Predicted wall seconds of point k: the nearest smaller known point, scaled by N.
    fn predict(&self, k: u32) -> f64 {
        self.wall
            .range(..k)
            .next_back()
            .map_or(0.0, |(&k0, &w)| w * 2f64.powi((k - k0) as i32))
    }
}

/// One case being swept.
struct CaseState {
    id: String,
    case: Case,
    info: CaseInfo,
    series: Vec<SeriesState>,
    dirty: bool,
}

/// The seed of point k of a series.
pub fn point_seed(series_seed: u64, k: u32) -> u64 {
    hash_words(&[series_seed, k as u64])
}

/// Run the given batches of one point: per batch, its accumulator and the CPU seconds of
/// the thread that computed it.
/// Batches run in parallel; each is exactly what the engine computes for it.
pub fn run_point(
    case: &Case,
    est: Estimator,
    spec: &RunSpec,
    batches: &[u64],
) -> Vec<(u64, Accumulator, f64)> {
    let f = case.integrand(&case.plan, est);
    batches
        .par_iter()
        .map(|&b| {
            let t = super::clock::CpuTimer::start();
            let acc = run_batches(spec, b..b + 1, &f)
                .into_iter()
                .next()
                .unwrap_or_default();
            (b, acc, t.seconds())
        })
        .collect()
}

/// The digest of what a case computes: its description, then for each external file
/// its scene reads (OBJ meshes, EXR maps: [`crate::scene::load::SceneDesc::external_files`],
/// resolved against the case file's folder as the loader does) the path and the bytes
/// (an unreadable file hashes as its path and a marker), so that editing a mesh or a
/// map changes the digest and no earlier point is resumed.
fn case_digest(case: &Case) -> String {
    let mut bytes = serde_json::to_vec(&case.desc).unwrap_or_default();
    let scene = &case.desc.scene;
    for (path, full) in scene
        .external_files()
        .into_iter()
        .zip(scene.external_paths(&case.file))
    {
        bytes.push(0);
        bytes.extend_from_slice(path.as_bytes());
        bytes.push(0);
        match std::fs::read(full) {
            Ok(data) => {
                bytes.extend_from_slice(&(data.len() as u64).to_le_bytes());
                bytes.extend_from_slice(&data);
            }
            Err(_) => bytes.extend_from_slice(b"unreadable"),
        }
    }
    digest(&bytes)
}

/// Load the cases of the paths, with their report ids.
fn load_cases(paths: &[PathBuf]) -> Result<Vec<(String, Case)>, InputError> {
    let mut out: Vec<(String, Case)> = vec![];
    // By the file stem the id writes (`a/b` and `a.b` write the same `a.b.json`).
    let mut stems: BTreeMap<String, (String, PathBuf)> = BTreeMap::new();
    for p in paths {
        let root = p.is_dir().then_some(p.as_path());
        for f in collect_cases(std::slice::from_ref(p))? {
            let id = case_id(root, &f);
            let stem = super::store::stem(&id);
            let refuse = |why: String| InputError::new(f.display().to_string(), "-", why);
            // The folder's own files: a case `index.json` was replaced by the index, and
            // one named like a shard partial was taken for one by `merge --out` (and its
            // partial replaced by the report).
            if stem == "index" || super::shard::is_partial_name(&format!("{stem}.json")) {
                return Err(refuse(format!(
                    "its report id `{id}` would write `{stem}.json`, a name the report folder keeps for its {}: rename the case file",
                    if stem == "index" {
                        "index"
                    } else {
                        "shard partials"
                    }
                )));
            }
            // `X.transient.svg` is the transient plot of a time-binned case `X`: a case
            // whose stem ends so had its plot written over by it, silently.
            if let Some(x) = stem.strip_suffix(super::store::TRANSIENT_SUFFIX) {
                return Err(refuse(format!(
                    "its report id `{id}` would write its plot to `{stem}.svg`, the name of the transient plot of a case `{x}`: rename the case file"
                )));
            }
            if let Some((other_id, other)) = stems.insert(stem.clone(), (id.clone(), f.clone())) {
                if other == f {
                    continue;
                }
                return Err(refuse(format!(
                    "its report id `{id}` writes `{stem}.json`, as {}'s id `{other_id}` does: give one of them from another folder",
                    other.display()
                )));
            }
            out.push((id, Case::load(&f)?));
        }
    }
    Ok(out)
}

fn plan_digest(settings: &Settings, cases: &[CaseState]) -> String {
    // (id, case digest, [(estimator, sampler)]) per case.
    type Plan<'a> = Vec<(&'a str, &'a str, Vec<(&'a str, &'a str)>)>;
    let plan: Plan = cases
        .iter()
        .map(|c| {
            (
                c.id.as_str(),
                c.info.digest.as_str(),
                c.series
                    .iter()
                    .map(|s| (s.est.name(), s.sampler.name()))
                    .collect(),
            )
        })
        .collect();
    digest(
        serde_json::to_string(&(FORMAT, settings, plan))
            .unwrap_or_default()
            .as_bytes(),
    )
}

/// Where a sweep stands, reported before each point is computed.
#[derive(Clone, Copy, Debug)]
pub struct Progress<'a> {
    /// Points computed so far.
    pub done: u64,
    /// Points to compute in all.
    pub total: u64,
    /// The point about to be computed (`case estimator/sampler N=2^k`).
    pub current: &'a str,
}

/// `lightproof report`: sweep, write the reports, the plots and the index (or, for a
/// shard, its partial file), calling `progress` before each point. Call it inside the
/// rayon pool that sets the thread count.
pub fn run(opts: &Options, progress: &mut dyn FnMut(Progress)) -> Result<Summary, Error> {
    let t0 = Instant::now();
    let settings = settings(opts)?;
    let mut cases = plan_cases(opts, &settings)?;
    // The cases are good: an output folder blocked by a file is told now, not after the
    // sweep (bad input first, exit 2; then the output, exit 3).
    crate::io::check_output_dir(&opts.out)?;
    let threads = rayon::current_num_threads();
    let plan = plan_digest(&settings, &cases);
    let mut notes = vec![];
    let mut resumed = 0u64;
    if !opts.fresh {
        resumed = match opts.shard {
            None => resume_reports(&opts.out, &settings, &mut cases, threads, &mut notes)?,
            Some(sh) => resume_partial(&opts.out, sh, &settings, &mut cases, threads, &mut notes)?,
        };
    }
    let mut run = run_info(threads, opts.budget);
    run.points_resumed = resumed;

    let mut queue = Queue::default();
    for (ci, c) in cases.iter().enumerate() {
        for (si, s) in c.series.iter().enumerate() {
            queue.push_next(s, ci, si);
        }
    }
    let total: u64 = cases
        .iter()
        .flat_map(|c| &c.series)
        .map(|s| s.pending.len() as u64)
        .sum();
    let mut done = 0u64;
    // Flush at most once a second, and spend at most a tenth of the time writing.
    let mut last_flush: Option<Instant> = None;
    let mut flush_every = Duration::from_secs(1);
    while let Some((predicted, ci, si)) = queue.pop() {
        // A first point is predicted free and always runs (the time spent loading a
        // large catalog once cut every series before its first point).
        if let Some(b) = opts.budget
            && predicted > 0.0
            && t0.elapsed().as_secs_f64() + predicted > b
        {
            run.budget_cut = true;
            cut_pending(&mut cases);
            break;
        }
        let c = &mut cases[ci];
        let k = c.series[si].pending.remove(0);
        progress(Progress {
            done,
            total,
            current: &format!(
                "{} {}/{} N=2^{k}",
                c.id,
                c.series[si].est.name(),
                c.series[si].sampler.name()
            ),
        });
        compute_point(opts.shard, c, si, k);
        run.points_computed += 1;
        queue.push_next(&c.series[si], ci, si);
        done += 1;
        if last_flush.is_none_or(|t| t.elapsed() >= flush_every) {
            let tf = Instant::now();
            run.wall_seconds = t0.elapsed().as_secs_f64();
            flush(opts, &settings, &plan, &mut cases, &run, false)?;
            flush_every = Duration::from_secs(1).max(tf.elapsed() * 10);
            last_flush = Some(Instant::now());
        }
    }
    run.wall_seconds = t0.elapsed().as_secs_f64();
    for c in &mut cases {
        c.dirty = true;
    }
    let written = flush(opts, &settings, &plan, &mut cases, &run, true)?;
    let mut summary = match opts.shard {
        None => {
            let mut reports = written.reports;
            let summary = publish(&opts.out, &mut reports)?;
            let cases = load_cases(&opts.paths)?;
            let mut skipped = vec![];
            let plan = |id: &str, bins: usize| {
                let n = transient_samples(&reports, id, bins, opts, t0.elapsed().as_secs_f64());
                if n.is_none() {
                    skipped.push(id.to_string());
                }
                n
            };
            for p in super::transient::write_all(&cases, &opts.out, plan, opts.seed)? {
                notes.push(format!("wrote the transient response {}", p.display()));
            }
            for id in skipped {
                notes.push(format!(
                    "no transient response for {id}: its bins would run past the budget"
                ));
            }
            summary
        }
        Some(_) => Summary {
            reports: vec![],
            index: None,
            partial: written.partial,
            computed: 0,
            resumed: 0,
            budget_cut: false,
            notes: vec![],
        },
    };
    summary.computed = run.points_computed;
    summary.resumed = resumed;
    summary.budget_cut = run.budget_cut;
    summary.notes.splice(0..0, notes);
    Ok(summary)
}

/// Every case × estimator × sampler series the options ask for, none computed yet.
fn plan_cases(opts: &Options, settings: &Settings) -> Result<Vec<CaseState>, Error> {
    // A sampler asked for twice is one series (the same seed would run it twice and
    // compare it with itself as its own runner-up).
    let mut samplers: Vec<SamplerKind> = vec![];
    for &s in if opts.samplers.is_empty() {
        &SamplerKind::ALL[..]
    } else {
        &opts.samplers[..]
    } {
        if !samplers.contains(&s) {
            samplers.push(s);
        }
    }
    let mut cases: Vec<CaseState> = vec![];
    for (id, case) in load_cases(&opts.paths)? {
        let info = CaseInfo {
            name: case.desc.name.clone(),
            file: case.file.display().to_string(),
            teaches: case.desc.teaches.clone(),
            measure: case.measure.name().to_string(),
            reference: case.reference,
            digest: case_digest(&case),
        };
        let mut series = vec![];
        let wanted = |e: &&Estimator| opts.estimators.is_empty() || opts.estimators.contains(e);
        for &est in case.desc.estimators.iter().filter(wanted) {
            for &sampler in &samplers {
                series.push(SeriesState {
                    est,
                    sampler,
                    seed: seed_for(settings.seed, &case.desc.name, est, sampler),
                    done: BTreeMap::new(),
                    parts: BTreeMap::new(),
                    wall: BTreeMap::new(),
                    pending: settings.exponents().collect(),
                    cut: false,
                });
            }
        }
        if !series.is_empty() {
            cases.push(CaseState {
                id,
                case,
                info,
                series,
                dirty: true,
            });
        }
    }
    if cases.is_empty() {
        return Err(Error::Input(cli_err(
            "--estimator",
            "nothing to run: no case names any of the estimators asked for",
        )));
    }
    Ok(cases)
}

/// The pending points, cheapest predicted wall time first (ties in plan order).
#[derive(Default)]
struct Queue {
    heap: BinaryHeap<Reverse<(u64, usize, usize, usize)>>,
    order: usize,
}

impl Queue {
    /// Queue the next pending point of series `si` of case `ci`, if any.
    fn push_next(&mut self, s: &SeriesState, ci: usize, si: usize) {
        if let Some(&k) = s.pending.first() {
            self.heap
                .push(Reverse((nanos(s.predict(k)), self.order, ci, si)));
            self.order += 1;
        }
    }

    /// The cheapest point: (predicted wall seconds, case, series).
    fn pop(&mut self) -> Option<(f64, usize, usize)> {
        self.heap
            .pop()
            .map(|Reverse((ns, _, ci, si))| (ns as f64 * 1e-9, ci, si))
    }
}

/// The sample count of a case's transient plot (each of its `bins` run once): the
/// largest N its first series reached (at most `--max-samples`), halved while the bins'
/// predicted wall time, at that point's seconds per sample, would end past the budget
/// (`elapsed` seconds spent so far); `None` when not even 256 samples fit, or when the
/// case has no computed point.
fn transient_samples(
    reports: &[CaseReport],
    id: &str,
    bins: usize,
    opts: &Options,
    elapsed: f64,
) -> Option<u64> {
    let point = reports
        .iter()
        .find(|r| r.id == id)?
        .series
        .first()?
        .points
        .iter()
        .max_by_key(|p| p.samples)?;
    let per_sample = point.wall_seconds.unwrap_or(point.seconds) / point.samples as f64;
    fit_to_budget(
        point.samples.min(opts.max_samples),
        bins as f64 * per_sample,
        elapsed,
        opts.budget,
    )
}

/// The largest of n, n/2, n/4, … (down to [`MIN_TRANSIENT_SAMPLES`]) whose cost, at
/// `per_sample` seconds, ends within the budget after `elapsed` seconds; n itself
/// without a budget, `None` when none fits.
fn fit_to_budget(mut n: u64, per_sample: f64, elapsed: f64, budget: Option<f64>) -> Option<u64> {
    let Some(budget) = budget else {
        return Some(n);
    };
    let ends_in_budget = |n: u64| elapsed + n as f64 * per_sample <= budget;
    while n > MIN_TRANSIENT_SAMPLES && !ends_in_budget(n) {
        n /= 2;
    }
    ends_in_budget(n).then_some(n)
}

/// The fewest samples a transient plot's bins run with: the fewest any run takes.
const MIN_TRANSIENT_SAMPLES: u64 = crate::case::MIN_SAMPLES;

/// Mark every series with points left as cut by the budget.
fn cut_pending(cases: &mut [CaseState]) {
    for c in cases {
        for s in c.series.iter_mut().filter(|s| !s.pending.is_empty()) {
            s.cut = true;
            c.dirty = true;
        }
    }
}

/// Compute point k of series `si` of case `c` (all batches, or this shard's) and keep it.
fn compute_point(shard: Option<Shard>, c: &mut CaseState, si: usize, k: u32) {
    let s = &mut c.series[si];
    let seed = point_seed(s.seed, k);
    let spec = RunSpec {
        samples: 1 << k,
        sampler: s.sampler,
        seed,
    };
    let batches: Vec<u64> = match shard {
        None => (0..BATCHES).collect(),
        Some(sh) => sh.batches(s.seed, k),
    };
    let tp = Instant::now();
    let results = run_point(&c.case, s.est, &spec, &batches);
    let wall = tp.elapsed().as_secs_f64();
    s.wall.insert(k, wall);
    match shard {
        None => {
            let accs: Vec<Accumulator> = results.iter().map(|r| r.1).collect();
            let seconds = results.iter().map(|r| r.2).sum();
            let p = point_from_batches(1 << k, seed, &accs, seconds, Some(wall), c.case.reference);
            s.done.insert(k, p);
        }
        Some(_) => {
            let batches = results
                .iter()
                .map(|(b, a, t)| BatchRecord::new(*b, a, *t))
                .collect();
            s.parts.insert(
                k,
                ShardPoint {
                    samples: 1 << k,
                    seed,
                    batches,
                },
            );
        }
    }
    c.dirty = true;
}

fn nanos(seconds: f64) -> u64 {
    (seconds.max(0.0) * 1e9).min(u64::MAX as f64) as u64
}

struct Written {
    reports: Vec<CaseReport>,
    partial: Option<PathBuf>,
}

/// The report of a case as it stands.
fn case_report(c: &CaseState, settings: &Settings, run: &RunInfo) -> CaseReport {
    let measure = error_measure(&c.info);
    let series: Vec<Series> = c
        .series
        .iter()
        .map(|s| {
            summarized_series(
                (s.est, s.sampler, s.seed),
                s.status(),
                s.done.values().cloned().collect(),
                measure,
                c.info.reference,
            )
        })
        .collect();
    assemble_case_report(c.id.clone(), c.info.clone(), settings, measure, run, series)
}

/// Write the dirty case reports (or the shard's partial). With `all`, return every
/// case's report.
fn flush(
    opts: &Options,
    settings: &Settings,
    plan: &str,
    cases: &mut [CaseState],
    run: &RunInfo,
    all: bool,
) -> Result<Written, Error> {
    match opts.shard {
        None => {
            let mut reports = vec![];
            for c in cases.iter_mut() {
                if !(c.dirty || all) {
                    continue;
                }
                let r = case_report(c, settings, run);
                if !all {
                    write_json(&opts.out.join(report_file(&c.id)), &r, true)?;
                }
                c.dirty = false;
                reports.push(r);
            }
            Ok(Written {
                reports,
                partial: None,
            })
        }
        Some(sh) => {
            let partial = ShardPartial {
                format: FORMAT.to_string(),
                kind: Kind::Shard,
                shard: sh,
                plan: plan.to_string(),
                settings: settings.clone(),
                run: run.clone(),
                cases: cases
                    .iter()
                    .map(|c| ShardCase {
                        id: c.id.clone(),
                        case: c.info.clone(),
                        series: c
                            .series
                            .iter()
                            .map(|s| ShardSeries {
                                estimator: s.est,
                                sampler: s.sampler,
                                seed: s.seed,
                                status: s.status(),
                                points: s.parts.values().cloned().collect(),
                            })
                            .collect(),
                    })
                    .collect(),
            };
            let path = opts.out.join(sh.file_name());
            write_partial(&path, &partial)?;
            for c in cases.iter_mut() {
                c.dirty = false;
            }
            Ok(Written {
                reports: vec![],
                partial: Some(path),
            })
        }
    }
}

/// Whether a file was written by this build (version, revision and profile).
fn same_build(run: &RunInfo) -> bool {
    run.lightproof_version == VERSION
        && run.git_revision == GIT_REVISION
        && run.profile.as_deref() == Some(PROFILE)
}

/// Whether a file's points were timed on this machine, with the ray queries in the
/// instruction set they run in now: points timed elsewhere would join this run's in one
/// cost fit (a resumed run once fitted 15 points timed in the baseline instruction set
/// with 3 of its own in x86-64-v3, recording only the latter): the same CPU model,
/// system and `ray_isa`. The thread count and the logical cores available may differ:
/// core-seconds do not depend on them.
///
/// A merged report's points were timed by its shards, so each shard's run must pass
/// too (a merged folder once resumed shards timed in another profile, CPU and
/// instruction set as this machine's: session 56's review).
fn same_machine(run: &RunInfo) -> bool {
    let now = super::machine::machine();
    let here = |r: &RunInfo| {
        let old = &r.machine;
        (&old.cpu, &old.os, &old.arch, &old.ray_isa) == (&now.cpu, &now.os, &now.arch, &now.ray_isa)
    };
    here(run)
        && run
            .shards
            .iter()
            .all(|s| here(&s.run) && same_build(&s.run))
}

/// Earlier points a resumed run leaves out of what it writes: those outside a narrower
/// sweep (a smaller `--max-samples`, a larger `--min-samples`, fewer samplers or
/// estimators). The files are rewritten without them, so the user is told.
#[derive(Default)]
struct Dropped {
    /// Points.
    points: u64,
    /// Whole series (their points counted in `points`).
    series: u64,
}

impl Dropped {
    /// The note on stderr, if anything is dropped.
    fn note(&self, out: &Path) -> Option<String> {
        (self.points > 0 || self.series > 0).then(|| {
            format!(
                "{}: {} earlier point(s), {} whole series among them, lie outside this sweep's --min-samples/--max-samples, --sampler and --estimator and are dropped from what it writes",
                out.display(),
                self.points,
                self.series
            )
        })
    }
}

/// Take back the points of earlier case reports; returns how many.
fn resume_reports(
    out: &Path,
    settings: &Settings,
    cases: &mut [CaseState],
    threads: usize,
    notes: &mut Vec<String>,
) -> Result<u64, InputError> {
    let mut kept = 0;
    let mut dropped = Dropped::default();
    for c in cases.iter_mut() {
        let path = out.join(report_file(&c.id));
        let Some(old) = read_case_report(&path)? else {
            continue;
        };
        let why = if old.id != c.id || old.case.digest != c.info.digest {
            Some("the case changed")
        } else if old.settings.seed != settings.seed || old.settings.batches != settings.batches {
            Some("another seed")
        } else if !same_build(&old.run) {
            Some("another build of lightproof")
        } else if !same_machine(&old.run) {
            Some("timed on another machine or instruction set")
        } else {
            None
        };
        if let Some(why) = why {
            notes.push(format!("{}: {why}; swept afresh", path.display()));
            continue;
        }
        for os in &old.series {
            let Some(s) = c
                .series
                .iter_mut()
                .find(|s| os.estimator == s.est && os.sampler == s.sampler && os.seed == s.seed)
            else {
                dropped.series += 1;
                dropped.points += os.points.len() as u64;
                continue;
            };
            for p in &os.points {
                let k = p.samples.trailing_zeros();
                if p.samples.is_power_of_two()
                    && s.pending.contains(&k)
                    && p.seed == point_seed(s.seed, k)
                {
                    s.pending.retain(|&x| x != k);
                    s.wall.insert(k, p.seconds / threads as f64);
                    s.done.insert(k, p.clone());
                    kept += 1;
                } else {
                    dropped.points += 1;
                }
            }
        }
    }
    notes.extend(dropped.note(out));
    Ok(kept)
}

/// Take back the batches of this shard's earlier partial file; returns the points kept.
///
/// The file is resumed when its plan is this one but for `--min-samples` and
/// `--max-samples` (same cases, series, seed and build), so a larger `--max-samples`
/// extends a shard as it does a single run; each point is still checked (its N in this
/// sweep, its seed, exactly this shard's batches).
fn resume_partial(
    out: &Path,
    shard: Shard,
    settings: &Settings,
    cases: &mut [CaseState],
    threads: usize,
    notes: &mut Vec<String>,
) -> Result<u64, InputError> {
    let path = out.join(shard.file_name());
    if !path.exists() {
        return Ok(0);
    }
    let old = read_partial(&path, OUTPUT_ADVICE)?;
    let same_range = Settings {
        min_samples: old.settings.min_samples,
        max_samples: old.settings.max_samples,
        ..settings.clone()
    };
    if old.plan != plan_digest(&same_range, cases)
        || old.shard != shard
        || !same_build(&old.run)
        || !same_machine(&old.run)
    {
        notes.push(format!(
            "{}: another sweep, build or machine; run afresh",
            path.display()
        ));
        return Ok(0);
    }
    let mut kept = 0;
    let mut dropped = Dropped::default();
    for (c, oc) in cases.iter_mut().zip(&old.cases) {
        for (s, os) in c.series.iter_mut().zip(&oc.series) {
            for p in &os.points {
                let k = p.samples.trailing_zeros();
                let want = shard.batches(s.seed, k);
                let have: Vec<u64> = p.batches.iter().map(|b| b.batch).collect();
                if p.samples.is_power_of_two()
                    && s.pending.contains(&k)
                    && p.seed == point_seed(s.seed, k)
                    && have == want
                {
                    s.pending.retain(|&x| x != k);
                    let secs: f64 = p.batches.iter().map(|b| b.seconds).sum();
                    s.wall.insert(k, secs / threads as f64);
                    s.parts.insert(k, p.clone());
                    kept += 1;
                } else {
                    dropped.points += 1;
                }
            }
        }
    }
    notes.extend(dropped.note(&path));
    Ok(kept)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A run's own record is this build and machine; another version, revision or
    /// profile is another build, another CPU, system, architecture or `ray_isa` another
    /// machine, and so is a merged report any of whose shards ran elsewhere or in
    /// another build; the thread count and the logical cores are not the machine.
    #[test]
    fn builds_and_machines_are_told_apart() {
        use crate::report::ShardRun;
        let here = run_info(2, None);
        assert!(same_build(&here) && same_machine(&here));
        type Edit = (&'static str, fn(&mut RunInfo));
        let edits: [Edit; 4] = [
            ("version", |r| r.lightproof_version.push('x')),
            ("revision", |r| r.git_revision.push('x')),
            ("profile", |r| r.profile = Some("other".into())),
            ("no profile", |r| r.profile = None),
        ];
        for (what, edit) in edits {
            let mut r = here.clone();
            edit(&mut r);
            assert!(!same_build(&r), "{what}");
        }
        let machines: [Edit; 4] = [
            ("cpu", |r| r.machine.cpu.push('x')),
            ("os", |r| r.machine.os.push('x')),
            ("arch", |r| r.machine.arch.push('x')),
            ("ray_isa", |r| r.machine.ray_isa = Some("other".into())),
        ];
        for (what, edit) in machines {
            let mut r = here.clone();
            edit(&mut r);
            assert!(!same_machine(&r), "{what}");
            let mut merged = here.clone();
            merged.shards = vec![
                ShardRun {
                    index: 0,
                    count: 2,
                    run: here.clone(),
                },
                ShardRun {
                    index: 1,
                    count: 2,
                    run: r,
                },
            ];
            assert!(!same_machine(&merged), "a shard's {what}");
        }
        let mut other_build = here.clone();
        other_build.profile = Some("other".into());
        let mut merged = here.clone();
        merged.shards = vec![ShardRun {
            index: 0,
            count: 1,
            run: other_build,
        }];
        assert!(!same_machine(&merged), "a shard's build");
        merged.shards = vec![ShardRun {
            index: 0,
            count: 1,
            run: here.clone(),
        }];
        assert!(same_machine(&merged));
        let mut busy = here.clone();
        busy.threads = 7;
        busy.machine.logical_cores += 1;
        assert!(same_build(&busy) && same_machine(&busy));
    }

    /// A case whose id ends in `.transient` is refused, naming the time-binned case whose
    /// transient plot would write over its plot (`p.transient.svg` once held `p`'s
    /// transient response in place of `p.transient`'s convergence plot); a stem that
    /// merely contains the word is a case like any other.
    #[test]
    fn a_case_named_like_a_transient_plot_is_refused() {
        let dir = std::env::temp_dir().join(format!("lightproof-transient-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let disk = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("analytic/cases/irradiance/disk_on_axis.json");
        let text = std::fs::read_to_string(disk).unwrap();
        for name in ["p.transient.json", "transient.p.json", "p.transients.json"] {
            std::fs::write(dir.join(name), &text).unwrap();
        }
        let Err(err) = load_cases(&[dir.join("p.transient.json")]) else {
            panic!("p.transient.json was accepted");
        };
        let err = err.to_string();
        assert!(
            err.contains("p.transient.json")
                && err.contains("`p.transient.svg`, the name of the transient plot of a case `p`"),
            "{err}"
        );
        for ok in ["transient.p.json", "p.transients.json"] {
            assert_eq!(load_cases(&[dir.join(ok)]).unwrap().len(), 1, "{ok}");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// Editing a mesh the case reads changes the case's digest (so its points are not
    /// resumed: the resume check compares digests); an unchanged file keeps it, and a
    /// case with no external file digests its description alone, as before. Before the
    /// fix the digest hashed only the description and did not change.
    #[test]
    fn the_case_digest_covers_its_obj_file() {
        let dir = std::env::temp_dir().join(format!("lightproof-digest-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let case = dir.join("c.json");
        std::fs::write(
            &case,
            r#"{"name": "t", "teaches": "t",
                "scene": {"shapes": [{"geometry": {"type": "obj", "path": "tri.obj"},
                                      "emission": {"radiance": 1}}]},
                "measure": {"power": {"shape": 0}}, "estimators": ["uniform"]}"#,
        )
        .unwrap();
        let obj = |k: f64| format!("v 0 0 0\nv {k} 0 0\nv 0 {k} 0\nf 1 2 3\n");
        std::fs::write(dir.join("tri.obj"), obj(1.0)).unwrap();
        let first = case_digest(&Case::load(&case).unwrap());
        assert_eq!(case_digest(&Case::load(&case).unwrap()), first);
        std::fs::write(dir.join("tri.obj"), obj(2.0)).unwrap();
        let loaded = Case::load(&case).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        assert_ne!(case_digest(&loaded), first);
        let c = Case::load(
            &Path::new(env!("CARGO_MANIFEST_DIR")).join("analytic/cases/power/disk.json"),
        )
        .unwrap();
        let json = serde_json::to_string(&c.desc).unwrap();
        assert_eq!(case_digest(&c), digest(json.as_bytes()));
    }

    fn series(wall: &[(u32, f64)], pending: &[u32]) -> SeriesState {
        SeriesState {
            est: Estimator::Light,
            sampler: SamplerKind::Independent,
            seed: 1,
            done: BTreeMap::new(),
            parts: BTreeMap::new(),
            wall: wall.iter().copied().collect(),
            pending: pending.to_vec(),
            cut: false,
        }
    }

    /// The sweep's order (module doc): a point's wall time is predicted from the nearest
    /// smaller known point, doubling per k; the queue pops the cheapest pending point,
    /// ties in plan order, so every series gets its small points before any gets a large
    /// one.
    #[test]
    fn points_run_cheapest_first_ties_in_plan_order() {
        let s = series(&[(10, 0.5), (12, 3.0)], &[13, 14]);
        assert_eq!(s.predict(11), 1.0);
        assert_eq!(s.predict(13), 6.0);
        assert_eq!(s.predict(15), 24.0);
        assert_eq!(s.predict(10), 0.0, "nothing known below k = 10");
        // Three series: next points predicted 6 s, 0 s (nothing known yet), 6 s.
        let all = [
            series(&[(12, 3.0)], &[13]),
            series(&[], &[8, 9]),
            series(&[(12, 3.0)], &[13]),
        ];
        // Queued last series first: a tie goes to the one queued first, not the lower index.
        let mut q = Queue::default();
        for (si, s) in all.iter().enumerate().rev() {
            q.push_next(s, 0, si);
        }
        q.push_next(&series(&[], &[]), 0, 9); // nothing pending: nothing queued
        let order: Vec<(f64, usize)> = std::iter::from_fn(|| q.pop())
            .map(|(t, _, si)| (t, si))
            .collect();
        assert_eq!(order, [(0.0, 1), (6.0, 2), (6.0, 0)]);
    }

    #[test]
    fn transient_plots_fit_the_budget_left() {
        // 6 bins at 1 ms per sample each: 6 ms per sample of the plot.
        let per = 6e-3;
        // No budget: the sweep's own largest N.
        assert_eq!(fit_to_budget(1 << 20, per, 100.0, None), Some(1 << 20));
        // 10 s left: the largest power-of-two fraction costing ≤ 10 s, 1024 (6.1 s);
        // 2048 would cost 12.3 s.
        assert_eq!(fit_to_budget(1 << 20, per, 0.0, Some(10.0)), Some(1024));
        assert_eq!(fit_to_budget(1 << 20, per, 3.0, Some(10.0)), Some(1024));
        assert_eq!(fit_to_budget(1 << 20, per, 4.0, Some(10.0)), Some(512));
        // Ending exactly at the budget fits; with one second left not even 256 samples
        // (1.5 s) fit.
        assert_eq!(
            fit_to_budget(1024, per, 10.0 - 1024.0 * per, Some(10.0)),
            Some(1024)
        );
        assert_eq!(fit_to_budget(1 << 20, per, 9.0, Some(10.0)), None);
        // A sweep that stopped below the floor keeps its own count when it fits.
        assert_eq!(fit_to_budget(128, per, 0.0, Some(10.0)), Some(128));
        assert_eq!(fit_to_budget(128, per, 9.5, Some(10.0)), None);
    }
}
