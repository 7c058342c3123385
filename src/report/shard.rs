//! Shards: one sweep cut over machines, merged into exactly the single run's report.
//!
//! The unit of work is one batch b of one point k of one series (case × estimator ×
//! sampler). Shard K of N runs the units with
//! `(b + hash_words([series seed, k])) mod N = K`: every shard gets ⌊128/N⌋ or ⌈128/N⌉
//! batches of every point (so shards cost alike; N ≤ 128, so that none is idle), and the
//! assignment depends only on the unit, not on what else is in the run. A shard writes its raw per-batch accumulators to
//! a partial file (`shard-K-of-N.json`); [`merge`] gathers the 128 batches of each point,
//! merges them in batch order with the same code as a single run, and writes the same
//! reports: identical estimates, errors and fits, only the timing fields differ.
//!
//! The shard may come from the environment of an array job ([`shard_from_env`]): a Slurm
//! job array or a Kubernetes indexed Job. No scheduler of our own.

use super::analysis::{assemble_case_report, point_from_batches, summarized_series};
use super::store::{MERGE_ADVICE, check_header, files_in, write_json};
use super::sweep::point_seed;
use super::{
    BATCHES, CaseInfo, CaseReport, ErrorMeasure, Kind, RunInfo, Series, Settings, ShardRun, Status,
};
use crate::error::{Error, InputError, IoError, parse_json};
use crate::sampling::SamplerKind;
use crate::sampling::sampler::hash_words;
use crate::stats::Accumulator;
use crate::transport::Estimator;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Shard K of N (K counts from 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Shard {
    /// K.
    pub index: u32,
    /// N.
    pub count: u32,
}

impl Shard {
    /// The shard of batch `b` of point `k` of the series with seed `series_seed`.
    pub fn owner(count: u32, series_seed: u64, k: u32, b: u64) -> u32 {
        ((b + hash_words(&[series_seed, k as u64])) % count as u64) as u32
    }

    /// The batches of point `k` of a series that this shard runs, in order.
    pub fn batches(&self, series_seed: u64, k: u32) -> Vec<u64> {
        (0..BATCHES)
            .filter(|&b| Shard::owner(self.count, series_seed, k, b) == self.index)
            .collect()
    }

    /// Its partial file name.
    pub fn file_name(&self) -> String {
        format!("shard-{}-of-{}.json", self.index, self.count)
    }
}

fn shard_err(field: &str, reason: impl Into<String>) -> InputError {
    InputError::new("<environment>", field, reason)
}

/// Parse `--shard`: `K/N` with 0 ≤ K < N.
pub fn parse_shard(s: &str) -> Result<Shard, InputError> {
    let bad = |r: &str| InputError::new("<command line>", "--shard", format!("{r}, got `{s}`"));
    let (k, n) = s
        .split_once('/')
        .ok_or_else(|| bad("expected K/N (K from 0) or `auto`"))?;
    let k: u32 = k
        .trim()
        .parse()
        .map_err(|_| bad("K must be a whole number"))?;
    let n: u32 = n
        .trim()
        .parse()
        .map_err(|_| bad("N must be a whole number"))?;
    if n == 0 || k >= n {
        return Err(bad("need 0 ≤ K < N"));
    }
    if n as u64 > BATCHES {
        return Err(bad(&too_many(n as u64)));
    }
    Ok(Shard { index: k, count: n })
}

/// Why N shards are too many: a point has [`BATCHES`] batches, the unit of a shard's
/// work, so beyond that count some shards would get none of a point and run idle.
fn too_many(count: u64) -> String {
    format!(
        "at most {BATCHES} shards (a point has {BATCHES} batches, each run by one shard: with {count} shards some would get none), N is {count}"
    )
}

fn var(env: &BTreeMap<String, String>, name: &str) -> Result<Option<u64>, InputError> {
    match env.get(name).map(|v| v.trim()).filter(|v| !v.is_empty()) {
        None => Ok(None),
        Some(v) => v
            .parse::<u64>()
            .map(Some)
            .map_err(|_| shard_err(name, format!("must be a whole number, got `{v}`"))),
    }
}

/// Shard `index` of `count`, read from the variables `index_var` and `count_var`.
fn make(index: u64, count: u64, index_var: &str, count_var: &str) -> Result<Shard, InputError> {
    if count == 0 {
        return Err(shard_err(
            index_var,
            format!("shard count {count} is out of range"),
        ));
    }
    if count > BATCHES {
        return Err(shard_err(count_var, too_many(count)));
    }
    if index >= count {
        return Err(shard_err(
            index_var,
            format!("shard index {index} is not below the shard count {count}"),
        ));
    }
    Ok(Shard {
        index: index as u32,
        count: count as u32,
    })
}

/// The variables [`shard_from_env`] reads: only these are taken from the environment.
pub const SHARD_VARIABLES: [&str; 8] = [
    "LIGHTPROOF_SHARD_INDEX",
    "LIGHTPROOF_SHARD_COUNT",
    "JOB_COMPLETION_INDEX",
    "SLURM_ARRAY_TASK_ID",
    "SLURM_ARRAY_TASK_COUNT",
    "SLURM_ARRAY_TASK_MIN",
    "SLURM_ARRAY_TASK_MAX",
    "SLURM_ARRAY_TASK_STEP",
];

/// The [`SHARD_VARIABLES`] that `get` (`std::env::var_os`) finds set, as text; one whose
/// value is not UTF-8 is bad input naming it. The rest of the environment is not read:
/// a variable of no concern to lightproof may hold any bytes.
pub fn shard_env(
    get: impl Fn(&str) -> Option<std::ffi::OsString>,
) -> Result<BTreeMap<String, String>, InputError> {
    let mut env = BTreeMap::new();
    for name in SHARD_VARIABLES {
        if let Some(v) = get(name) {
            let v = v.into_string().map_err(|v| {
                shard_err(
                    name,
                    format!("is not UTF-8 text, got {:?}", v.to_string_lossy()),
                )
            })?;
            env.insert(name.to_string(), v);
        }
    }
    Ok(env)
}

/// The shard of `--shard auto`, from environment variables (a pure function of the map):
///
/// 1. `LIGHTPROOF_SHARD_INDEX` and `LIGHTPROOF_SHARD_COUNT`, if set;
/// 2. a Kubernetes indexed Job: `JOB_COMPLETION_INDEX` (from 0), with the count in
///    `LIGHTPROOF_SHARD_COUNT` (the Job's `completions`; Kubernetes does not expose it);
/// 3. a Slurm job array: K = (`SLURM_ARRAY_TASK_ID` − `SLURM_ARRAY_TASK_MIN`) /
///    `SLURM_ARRAY_TASK_STEP` and N = `SLURM_ARRAY_TASK_COUNT`, which holds for
///    `--array=A-B[:S]` (a list such as `1,4,9` is rejected: the tasks are not evenly
///    spaced). With `LIGHTPROOF_SHARD_COUNT` set, K = `SLURM_ARRAY_TASK_ID` itself: for
///    re-submitting some tasks of an array that started at 0 (`--array=3,5`).
pub fn shard_from_env(env: &BTreeMap<String, String>) -> Result<Shard, InputError> {
    let count = var(env, "LIGHTPROOF_SHARD_COUNT")?;
    if let Some(i) = var(env, "LIGHTPROOF_SHARD_INDEX")? {
        let n = count.ok_or_else(|| {
            shard_err(
                "LIGHTPROOF_SHARD_COUNT",
                "must be set with LIGHTPROOF_SHARD_INDEX",
            )
        })?;
        return make(i, n, "LIGHTPROOF_SHARD_INDEX", "LIGHTPROOF_SHARD_COUNT");
    }
    if let Some(i) = var(env, "JOB_COMPLETION_INDEX")? {
        let n = count.ok_or_else(|| {
            shard_err(
                "LIGHTPROOF_SHARD_COUNT",
                "must be set to the Job's completions in an indexed Job",
            )
        })?;
        return make(i, n, "JOB_COMPLETION_INDEX", "LIGHTPROOF_SHARD_COUNT");
    }
    if let Some(id) = var(env, "SLURM_ARRAY_TASK_ID")? {
        if let Some(n) = count {
            return make(id, n, "SLURM_ARRAY_TASK_ID", "LIGHTPROOF_SHARD_COUNT");
        }
        let n = var(env, "SLURM_ARRAY_TASK_COUNT")?
            .ok_or_else(|| shard_err("SLURM_ARRAY_TASK_COUNT", "is not set"))?;
        let min = var(env, "SLURM_ARRAY_TASK_MIN")?.unwrap_or(0);
        let step = var(env, "SLURM_ARRAY_TASK_STEP")?.unwrap_or(1).max(1);
        if id < min || (id - min) % step != 0 {
            return Err(shard_err(
                "SLURM_ARRAY_TASK_ID",
                format!("task {id} is not on the array's grid (min {min}, step {step})"),
            ));
        }
        if let Some(max) = var(env, "SLURM_ARRAY_TASK_MAX")?
            && max >= min
            && (max - min) / step + 1 != n
        {
            return Err(shard_err(
                "SLURM_ARRAY_TASK_COUNT",
                format!(
                    "{n} tasks between {min} and {max} with step {step} are not evenly spaced; set LIGHTPROOF_SHARD_COUNT and number the tasks from 0"
                ),
            ));
        }
        return make(
            (id - min) / step,
            n,
            "SLURM_ARRAY_TASK_ID",
            "SLURM_ARRAY_TASK_COUNT",
        );
    }
    Err(shard_err(
        "-",
        "--shard auto: none of LIGHTPROOF_SHARD_INDEX, JOB_COMPLETION_INDEX, SLURM_ARRAY_TASK_ID is set",
    ))
}

/// One batch's accumulator and compute time.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BatchRecord {
    /// Batch index b.
    pub batch: u64,
    /// Finite samples.
    pub count: u64,
    /// Their mean.
    pub mean: f64,
    /// Σ(x − mean)².
    pub m2: f64,
    /// Non-finite samples.
    pub non_finite: u64,
    /// Compute seconds of the batch.
    pub seconds: f64,
}

impl BatchRecord {
    /// From an accumulator.
    pub fn new(batch: u64, a: &Accumulator, seconds: f64) -> Self {
        BatchRecord {
            batch,
            count: a.count,
            mean: a.mean,
            m2: a.m2,
            non_finite: a.non_finite,
            seconds,
        }
    }

    /// The accumulator.
    pub fn accumulator(&self) -> Accumulator {
        Accumulator {
            count: self.count,
            mean: self.mean,
            m2: self.m2,
            non_finite: self.non_finite,
        }
    }
}

/// A shard's part of one point.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShardPoint {
    /// N.
    pub samples: u64,
    /// The point's seed.
    pub seed: u64,
    /// This shard's batches, in order.
    pub batches: Vec<BatchRecord>,
}

/// A shard's part of one series.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShardSeries {
    /// Estimator.
    pub estimator: Estimator,
    /// Sampler.
    pub sampler: SamplerKind,
    /// Series seed.
    pub seed: u64,
    /// Whether this shard finished its part.
    pub status: Status,
    /// Points in increasing N.
    pub points: Vec<ShardPoint>,
}

/// A shard's part of one case.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShardCase {
    /// Report id.
    pub id: String,
    /// The case.
    pub case: CaseInfo,
    /// One per estimator × sampler of the plan.
    pub series: Vec<ShardSeries>,
}

/// The partial result of one shard.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShardPartial {
    /// [`FORMAT`].
    pub format: String,
    /// [`Kind::Shard`].
    pub kind: Kind,
    /// Which shard.
    pub shard: Shard,
    /// Digest of the plan (settings, cases, series): all shards of a sweep share it.
    pub plan: String,
    /// The sweep.
    pub settings: Settings,
    /// This shard's run.
    pub run: RunInfo,
    /// Every case of the plan.
    pub cases: Vec<ShardCase>,
}

/// Read a partial file; `advice` is for a file of another format (see [`check_header`]).
pub fn read_partial(path: &Path, advice: &str) -> Result<ShardPartial, InputError> {
    let file = path.display().to_string();
    let text = crate::io::read_input(path, crate::io::MAX_JSON_BYTES)
        .map_err(|e| InputError::new(&file, "-", e))?;
    check_header(&file, &text, Kind::Shard, advice)?;
    let partial: ShardPartial = parse_json(&file, &text)?;
    check_settings(&file, &partial.settings)?;
    check_batches(&file, &partial)?;
    Ok(partial)
}

/// The settings are a sweep's that `report` runs: `min_samples` and `max_samples` powers of
/// two from 256 to 2⁴⁰ (what `--min-samples` and `--max-samples` become), the first not
/// above the second, and [`BATCHES`] batches. Unchecked, `min_samples` 0 made the merge's
/// points 2⁶⁴ (a panic with overflow checks, no points without).
fn check_settings(file: &str, s: &Settings) -> Result<(), InputError> {
    let (lo, hi) = (crate::case::MIN_SAMPLES, crate::case::MAX_SAMPLES);
    for (name, n) in [
        ("min_samples", s.min_samples),
        ("max_samples", s.max_samples),
    ] {
        if !(n.is_power_of_two() && (lo..=hi).contains(&n)) {
            return Err(InputError::new(
                file,
                format!("settings.{name}"),
                format!("{n} is not a power of two from {lo} to 2^40 = {hi}"),
            ));
        }
    }
    if s.min_samples > s.max_samples {
        return Err(InputError::new(
            file,
            "settings.max_samples",
            format!(
                "{} is below settings.min_samples {}",
                s.max_samples, s.min_samples
            ),
        ));
    }
    if s.batches != BATCHES {
        return Err(InputError::new(
            file,
            "settings.batches",
            format!(
                "every sweep has {BATCHES} batches per point, got {}",
                s.batches
            ),
        ));
    }
    Ok(())
}

/// The longest compute time of one batch a partial may record: 10⁹ s (32 years). Any
/// bound would keep a point's sum of [`BATCHES`] times finite; this one keeps the fits
/// and extrapolations made from it finite too (a batch of 10³⁰⁸ s once merged into a
/// report with no fits).
pub const MAX_BATCH_SECONDS: f64 = 1e9;

/// The largest |mean| of a batch: a run's samples are f32, so their mean is within its range.
const MAX_BATCH_MEAN: f64 = f32::MAX as f64;

/// Every point and batch record of a partial is one that a run can write: N a power of
/// two from 256 to 2⁴⁰, a batch index below [`BATCHES`], its finite and non-finite samples
/// adding up to the point's batch size N/B, a mean of f32 samples (|mean| ≤ f32::MAX), a
/// Σ(x − mean)² from 0 to what `count` such samples can give, count·(2·f32::MAX)², and
/// compute seconds from 0 to [`MAX_BATCH_SECONDS`]. The schema cannot say these; without
/// them a batch of `count` 0 or a negative `m2` merged into a different estimate or a
/// missing standard error without a word, and means of ±10³⁰⁸ into `"estimate": null`.
fn check_batches(file: &str, p: &ShardPartial) -> Result<(), InputError> {
    for (ci, c) in p.cases.iter().enumerate() {
        for (si, s) in c.series.iter().enumerate() {
            for (pi, pt) in s.points.iter().enumerate() {
                let at = format!("cases[{ci}].series[{si}].points[{pi}]");
                let (lo, hi) = (crate::case::MIN_SAMPLES, crate::case::MAX_SAMPLES);
                if !(pt.samples.is_power_of_two() && (lo..=hi).contains(&pt.samples)) {
                    return Err(InputError::new(
                        file,
                        format!("{at}.samples"),
                        format!(
                            "{} is not a power of two from {lo} to 2^40 = {hi}",
                            pt.samples
                        ),
                    ));
                }
                let size = pt.samples / BATCHES;
                for (bi, b) in pt.batches.iter().enumerate() {
                    let field = |name: &str| format!("{at}.batches[{bi}].{name}");
                    let problem = if b.batch >= BATCHES {
                        Some(("batch", format!("{} is not below {BATCHES}", b.batch)))
                    } else if b.count.checked_add(b.non_finite) != Some(size) {
                        Some((
                            "count",
                            format!(
                                "{} finite and {} non-finite samples, but a batch of {} samples holds {size}",
                                b.count, b.non_finite, pt.samples
                            ),
                        ))
                    } else if !(b.mean.abs() <= MAX_BATCH_MEAN) {
                        Some((
                            "mean",
                            format!(
                                "{:?} is not a mean of f32 samples (|mean| ≤ {MAX_BATCH_MEAN:e})",
                                b.mean
                            ),
                        ))
                    } else if !(0.0..=max_m2(b.count)).contains(&b.m2) {
                        Some((
                            "m2",
                            format!(
                                "{:?} is not a sum of squares from 0 to {:e}, the most {} f32 samples give",
                                b.m2,
                                max_m2(b.count),
                                b.count
                            ),
                        ))
                    } else if !(0.0..=MAX_BATCH_SECONDS).contains(&b.seconds) {
                        Some((
                            "seconds",
                            format!(
                                "{:?} is not a time from 0 to {MAX_BATCH_SECONDS:e} s",
                                b.seconds
                            ),
                        ))
                    } else {
                        None
                    };
                    if let Some((name, reason)) = problem {
                        return Err(InputError::new(file, field(name), reason));
                    }
                }
            }
        }
    }
    Ok(())
}

/// The largest Σ(x − mean)² of `count` f32 samples: each deviation is at most 2·f32::MAX.
fn max_m2(count: u64) -> f64 {
    count as f64 * (2.0 * MAX_BATCH_MEAN).powi(2)
}

/// Whether a file name is a shard partial's.
pub fn is_partial_name(name: &str) -> bool {
    name.starts_with("shard-") && name.ends_with(".json") && name.contains("-of-")
}

/// Case reports from a complete set of shard partials (one per index 0..N, one plan).
///
/// A point is kept when its 128 batches are all present (a shard stopped by its budget
/// leaves the points it did not finish out, and their series `budget_cut`).
pub fn merge_partials(
    partials: &[(PathBuf, ShardPartial)],
    mut run: RunInfo,
) -> Result<Vec<CaseReport>, InputError> {
    let merge_err = |field: &str, r: String| InputError::new("<merge>", field, r);
    let (first_path, first) = partials.first().ok_or_else(|| {
        merge_err(
            "-",
            "no shard partial files (shard-K-of-N.json) given".into(),
        )
    })?;
    check_partials(first_path, first, partials)?;
    run.budget_cut = partials.iter().any(|(_, p)| p.run.budget_cut);
    run.shards = partials
        .iter()
        .map(|(_, p)| ShardRun {
            index: p.shard.index,
            count: p.shard.count,
            run: p.run.clone(),
        })
        .collect();
    run.shards.sort_by_key(|s| s.index);
    let settings = &first.settings;
    let mut reports = vec![];
    for (ci, case) in first.cases.iter().enumerate() {
        let measure = error_measure(&case.case);
        let mut series = vec![];
        for (si, s) in case.series.iter().enumerate() {
            series.push(merge_series(
                partials,
                settings,
                case,
                (ci, si),
                s,
                measure,
            )?);
        }
        run.points_computed += series.iter().map(|s| s.points.len() as u64).sum::<u64>();
        reports.push(assemble_case_report(
            case.id.clone(),
            case.case.clone(),
            settings,
            measure,
            &run,
            series,
        ));
    }
    let total = run.points_computed;
    for r in &mut reports {
        r.run.points_computed = total;
    }
    Ok(reports)
}

/// The partials form one complete set: one plan and build, every index 0..N once.
fn check_partials(
    first_path: &Path,
    first: &ShardPartial,
    partials: &[(PathBuf, ShardPartial)],
) -> Result<(), InputError> {
    let count = first.shard.count;
    if count == 0 {
        return Err(InputError::new(
            first_path.display().to_string(),
            "shard.count",
            "must be at least 1, got 0",
        ));
    }
    // By index, not a slot per shard: a file claiming 2³² − 1 shards allocates nothing.
    let mut seen: BTreeMap<u32, &Path> = BTreeMap::new();
    for (path, p) in partials {
        check_member(first_path, first, path, p)?;
        if let Some(other) = seen.insert(p.shard.index, path) {
            return Err(InputError::new(
                path.display().to_string(),
                "shard.index",
                format!(
                    "shard {} is also given as {}",
                    p.shard.index,
                    other.display()
                ),
            ));
        }
    }
    // The first ten missing indices (bounded work whatever the claimed count).
    check_complete(count, &seen)
}

/// One partial belongs to the same sweep and build as the first, with a valid index.
fn check_member(
    first_path: &Path,
    first: &ShardPartial,
    path: &Path,
    p: &ShardPartial,
) -> Result<(), InputError> {
    let count = first.shard.count;
    let f = path.display().to_string();
    if p.shard.count != count {
        return Err(InputError::new(
            f,
            "shard.count",
            format!(
                "{} shards, but {} has {count}",
                p.shard.count,
                first_path.display()
            ),
        ));
    }
    if p.plan != first.plan || p.settings != first.settings {
        return Err(InputError::new(
            f,
            "plan",
            format!(
                "a different sweep (cases, settings or seed) from {}",
                first_path.display()
            ),
        ));
    }
    // The plan's digest is only carried along: each partial's own cases must be the
    // first's (ids, case records, series; their seeds are checked with their points), or
    // the report took them from
    // whichever file sorted first (an edited reference passed, a dropped series too).
    let differs = |field: String, what: &str| {
        InputError::new(
            &f,
            field,
            format!(
                "{what} differs from {}'s: the partials of one sweep hold the same cases",
                first_path.display()
            ),
        )
    };
    if p.cases.len() != first.cases.len() {
        return Err(differs("cases".into(), "the number of cases"));
    }
    for (ci, (a, b)) in first.cases.iter().zip(&p.cases).enumerate() {
        if a.id != b.id {
            return Err(differs(format!("cases[{ci}].id"), "the case id"));
        }
        if a.case != b.case {
            return Err(differs(format!("cases[{ci}].case"), "the case record"));
        }
        if a.series.len() != b.series.len() {
            return Err(differs(
                format!("cases[{ci}].series"),
                "the number of series",
            ));
        }
        for (si, (x, y)) in a.series.iter().zip(&b.series).enumerate() {
            if (x.estimator, x.sampler) != (y.estimator, y.sampler) {
                return Err(differs(
                    format!("cases[{ci}].series[{si}]"),
                    "the estimator or sampler",
                ));
            }
        }
    }
    if p.run.git_revision != first.run.git_revision
        || p.run.lightproof_version != first.run.lightproof_version
    {
        return Err(InputError::new(
            f,
            "run.git_revision",
            format!(
                "built from {} {}, but {} from {} {}: shards must run the same build",
                p.run.lightproof_version,
                p.run.git_revision,
                first_path.display(),
                first.run.lightproof_version,
                first.run.git_revision
            ),
        ));
    }
    // One revision built as `fast` and as `release` runs at two speeds: not one cost fit.
    if p.run.profile != first.run.profile {
        let name = |x: &Option<String>| x.clone().unwrap_or_else(|| "an unrecorded profile".into());
        return Err(InputError::new(
            f,
            "run.profile",
            format!(
                "built in the {} profile, but {} in {}: shards must run the same build",
                name(&p.run.profile),
                first_path.display(),
                name(&first.run.profile)
            ),
        ));
    }
    if p.shard.index >= count {
        return Err(InputError::new(
            f,
            "shard.index",
            format!(
                "shard index {} is not below the shard count {count}",
                p.shard.index
            ),
        ));
    }
    Ok(())
}

/// Every shard index below `count` is present.
fn check_complete(count: u32, seen: &BTreeMap<u32, &Path>) -> Result<(), InputError> {
    let merge_err = |field: &str, r: String| InputError::new("<merge>", field, r);
    let missing: Vec<String> = (0..count)
        .filter(|i| !seen.contains_key(i))
        .take(10)
        .map(|i| i.to_string())
        .collect();
    if !missing.is_empty() {
        let absent = count as u64 - seen.len() as u64;
        let more = if absent > 10 {
            format!(" and {} more", absent - 10)
        } else {
            String::new()
        };
        return Err(merge_err(
            "shards",
            format!("missing shard(s) {}{more} of {count}", missing.join(", ")),
        ));
    }
    Ok(())
}

/// One series merged from every shard's batches: the points whose 128 batches are all
/// present, in batch order.
///
/// Every batch must come from the shard that owns it ([`Shard::owner`]), once, in a point
/// whose seed is [`point_seed`] of the series seed, which every shard shares: before,
/// a partial carrying another shard's batch (or one twice) merged without a word, the
/// first file read winning, into a report no run computes.
fn merge_series(
    partials: &[(PathBuf, ShardPartial)],
    settings: &Settings,
    case: &ShardCase,
    (ci, si): (usize, usize),
    s: &ShardSeries,
    measure: ErrorMeasure,
) -> Result<Series, InputError> {
    // Per N, a slot per batch: the record and the index of the partial it came from.
    let mut by_samples: BTreeMap<u64, Vec<Option<(BatchRecord, usize)>>> = BTreeMap::new();
    let mut cut = false;
    for (fi, (path, p)) in partials.iter().enumerate() {
        let file = path.display().to_string();
        let at = format!("cases[{ci}].series[{si}]");
        let ps = p
            .cases
            .get(ci)
            .filter(|c| c.id == case.id)
            .and_then(|c| c.series.get(si))
            .filter(|x| x.estimator == s.estimator && x.sampler == s.sampler)
            .ok_or_else(|| {
                InputError::new(&file, &at, "does not match the plan of the other shards")
            })?;
        if ps.seed != s.seed {
            return Err(InputError::new(
                &file,
                format!("{at}.seed"),
                format!(
                    "series seed {}, but {} has {}: the shards of a sweep share it",
                    ps.seed,
                    partials[0].0.display(),
                    s.seed
                ),
            ));
        }
        cut |= ps.status == Status::BudgetCut;
        for (pi, pt) in ps.points.iter().enumerate() {
            let at = format!("{at}.points[{pi}]");
            // N is a power of two (`check_batches`): k is its exponent.
            let k = pt.samples.trailing_zeros();
            let seed = point_seed(s.seed, k);
            if pt.seed != seed {
                return Err(InputError::new(
                    &file,
                    format!("{at}.seed"),
                    format!(
                        "{} is not the seed of the point of {} samples, {seed} (from the series seed {})",
                        pt.seed, pt.samples, s.seed
                    ),
                ));
            }
            let slots = by_samples
                .entry(pt.samples)
                .or_insert_with(|| vec![None; BATCHES as usize]);
            for (bi, b) in pt.batches.iter().enumerate() {
                let field = format!("{at}.batches[{bi}].batch");
                let owner = Shard::owner(p.shard.count, s.seed, k, b.batch);
                if owner != p.shard.index {
                    return Err(InputError::new(
                        &file,
                        field,
                        format!(
                            "batch {} of this point is shard {owner}'s, not this shard's ({} of {})",
                            b.batch, p.shard.index, p.shard.count
                        ),
                    ));
                }
                // `check_batches` keeps the index below BATCHES.
                let slot = &mut slots[b.batch as usize];
                if let Some((_, other)) = slot {
                    let where_ = if *other == fi {
                        "earlier in this file".to_string()
                    } else {
                        format!("in {}", partials[*other].0.display())
                    };
                    return Err(InputError::new(
                        &file,
                        field,
                        format!("batch {} is present twice: also {where_}", b.batch),
                    ));
                }
                *slot = Some((*b, fi));
            }
        }
    }
    let mut points = vec![];
    for k in settings.exponents() {
        let Some(slots) = by_samples.remove(&(1u64 << k)) else {
            continue;
        };
        // In batch order; a point some shard did not finish is left out.
        let Some(recs) = slots
            .into_iter()
            .map(|x| x.map(|(r, _)| r))
            .collect::<Option<Vec<BatchRecord>>>()
        else {
            continue;
        };
        let accs: Vec<Accumulator> = recs.iter().map(|r| r.accumulator()).collect();
        let seconds = recs.iter().map(|r| r.seconds).sum();
        points.push(point_from_batches(
            1 << k,
            point_seed(s.seed, k),
            &accs,
            seconds,
            None,
            case.case.reference,
        ));
    }
    let planned = settings.exponents().count();
    let status = if points.len() == planned {
        Status::Complete
    } else if cut {
        Status::BudgetCut
    } else {
        Status::InProgress
    };
    Ok(summarized_series(
        (s.estimator, s.sampler, s.seed),
        status,
        points,
        measure,
        case.case.reference,
    ))
}

/// The error measure of a case: RMS error with a reference, standard error without.
pub fn error_measure(case: &CaseInfo) -> ErrorMeasure {
    if case.reference.is_some() {
        ErrorMeasure::RmsError
    } else {
        ErrorMeasure::StdError
    }
}

/// `lightproof merge`: read the partials in `inputs` (files, or folders holding
/// `shard-K-of-N.json` files), merge them and write the reports, plots and index to `out`.
pub fn merge(
    inputs: &[PathBuf],
    out: &Path,
    threads: usize,
) -> Result<super::publish::Summary, Error> {
    let t0 = std::time::Instant::now();
    let files = files_in(inputs, is_partial_name)?;
    if files.is_empty() {
        // Only folders find nothing (a file given is read whatever its name): name them.
        let searched: Vec<String> = inputs.iter().map(|p| p.display().to_string()).collect();
        return Err(InputError::new(
            searched.join(", "),
            "-",
            "no shard partial files (shard-K-of-N.json) directly in it (sub-folders are not searched)",
        )
        .into());
    }
    let partials = files
        .iter()
        .map(|f| Ok((f.clone(), read_partial(f, MERGE_ADVICE)?)))
        .collect::<Result<Vec<_>, InputError>>()?;
    let run = super::machine::run_info(threads, None);
    let mut reports = merge_partials(&partials, run)?;
    for r in &mut reports {
        r.run.wall_seconds = t0.elapsed().as_secs_f64();
    }
    let mut summary = super::publish::publish(out, &mut reports)?;
    summary.computed = reports.first().map_or(0, |r| r.run.points_computed);
    Ok(summary)
}

/// Write a partial (compact JSON: it is for machines).
pub fn write_partial(path: &Path, p: &ShardPartial) -> Result<(), IoError> {
    write_json(path, p, false)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env(pairs: &[(&str, &str)]) -> BTreeMap<String, String> {
        pairs
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect()
    }

    /// The corpus's valid partial passes; each field a run cannot write is named, at its
    /// limits: a batch count one off either way, m2 just below 0 or not finite, a
    /// negative or infinite time, a non-finite mean, a batch index of 128, N not a
    /// power of two or below 128.
    #[test]
    fn partials_that_disagree_on_their_cases_are_named() {
        // Two partials of one sweep, the second edited where the plan's digest, only
        // carried along, does not look: the merge took the first file's cases as they
        // were (an edited reference gave a 9% error where 1% was measured; a dropped
        // series passed, or not, by which file sorted first).
        let text = std::fs::read_to_string("tests/corpus/assets/shard-0-of-1.json").unwrap();
        let mut a: ShardPartial = parse_json("a.json", &text).unwrap();
        a.shard = Shard { index: 0, count: 2 };
        let mut b = a.clone();
        b.shard.index = 1;
        let check = |b: &ShardPartial| {
            let set = [
                (PathBuf::from("a.json"), a.clone()),
                (PathBuf::from("b.json"), b.clone()),
            ];
            check_partials(&set[0].0, &set[0].1, &set).map_err(|e| (e.file, e.field))
        };
        assert_eq!(check(&b), Ok(()));
        type Edit = fn(&mut ShardPartial);
        let edits: [(Edit, &str); 7] = [
            (|p| p.cases[0].case.reference = Some(0.7), "cases[0].case"),
            (|p| p.cases[0].case.name.push('!'), "cases[0].case"),
            (|p| p.cases[0].case.digest.push('0'), "cases[0].case"),
            (|p| p.cases[0].id.push('!'), "cases[0].id"),
            (|p| drop(p.cases[0].series.pop()), "cases[0].series"),
            (
                |p| {
                    let s = &mut p.cases[0].series[0];
                    s.sampler = match s.sampler {
                        SamplerKind::Independent => SamplerKind::Sobol,
                        _ => SamplerKind::Independent,
                    };
                },
                "cases[0].series[0]",
            ),
            (|p| drop(p.cases.pop()), "cases"),
        ];
        for (edit, field) in edits {
            let mut c = b.clone();
            edit(&mut c);
            let e = check(&c).unwrap_err();
            assert_eq!(e, ("b.json".into(), field.into()), "{field}");
        }
    }

    #[test]
    fn batch_records_a_run_cannot_write_are_named() {
        let text = std::fs::read_to_string("tests/corpus/assets/shard-0-of-1.json").unwrap();
        let valid: ShardPartial = parse_json("p.json", &text).unwrap();
        assert!(check_batches("p.json", &valid).is_ok());
        let at = "cases[0].series[0].points[0]";
        type Edit = fn(&mut ShardPoint);
        let cases: [(Edit, &str); 21] = [
            (|p| p.batches[3].count += 1, "batches[3].count"),
            // Just past what f32 samples give: a mean beyond f32::MAX (10³⁰⁸ once
            // merged into `"estimate": null`), m2 beyond count·(2·f32::MAX)², and a
            // batch time beyond 10⁹ s.
            (|p| p.batches[3].mean = 1e308, "batches[3].mean"),
            (|p| p.batches[3].mean = -1e308, "batches[3].mean"),
            (
                |p| p.batches[3].mean = f64::from(f32::MAX) * (1.0 + 1e-15),
                "batches[3].mean",
            ),
            // Two samples (N = 256) deviate by at most 2·f32::MAX each:
            // m2 ≤ 2·(6.8056469e38)² = 9.2633660e77.
            (|p| p.batches[3].m2 = 9.2634e77, "batches[3].m2"),
            (|p| p.batches[3].m2 = 1e308, "batches[3].m2"),
            (
                |p| p.batches[3].seconds = MAX_BATCH_SECONDS * (1.0 + 1e-15),
                "batches[3].seconds",
            ),
            (|p| p.batches[3].seconds = 1e308, "batches[3].seconds"),
            (|p| p.batches[3].count -= 1, "batches[3].count"),
            (|p| p.batches[3].non_finite = u64::MAX, "batches[3].count"),
            (|p| p.batches[3].m2 = -1e-300, "batches[3].m2"),
            (|p| p.batches[3].m2 = f64::INFINITY, "batches[3].m2"),
            (|p| p.batches[3].m2 = f64::NAN, "batches[3].m2"),
            (|p| p.batches[3].mean = f64::NAN, "batches[3].mean"),
            (|p| p.batches[3].seconds = -1e-9, "batches[3].seconds"),
            (
                |p| p.batches[3].seconds = f64::INFINITY,
                "batches[3].seconds",
            ),
            (|p| p.batches[3].batch = BATCHES, "batches[3].batch"),
            (|p| p.samples = 384, "samples"),
            (|p| p.samples = 128, "samples"),
            (|p| p.samples = 1 << 41, "samples"),
            (|p| p.samples *= 2, "batches[0].count"),
        ];
        for (edit, field) in cases {
            let mut p = valid.clone();
            edit(&mut p.cases[0].series[0].points[0]);
            let e = check_batches("p.json", &p).unwrap_err();
            assert_eq!(e.field, format!("{at}.{field}"), "{e}");
        }
        // Every value at its limit that a run can write passes: the largest mean, m2
        // and time; no samples finite, m2 and seconds 0, the last batch index.
        let mut p = valid.clone();
        let b = &mut p.cases[0].series[0].points[0].batches[3];
        assert_eq!(b.count, 2, "the corpus's partial has points of 256 samples");
        (b.mean, b.m2, b.seconds) = (-f64::from(f32::MAX), 9.2633e77, MAX_BATCH_SECONDS);
        assert!(check_batches("p.json", &p).is_ok());
        let mut p = valid.clone();
        let b = &mut p.cases[0].series[0].points[0].batches[3];
        (b.non_finite, b.count, b.m2, b.seconds, b.batch) = (b.count, 0, 0.0, 0.0, BATCHES - 1);
        assert!(check_batches("p.json", &p).is_ok());
        // The largest point, 2⁴⁰ samples in batches of 2³³.
        let pt = &mut p.cases[0].series[0].points[0];
        pt.samples = 1 << 40;
        for b in &mut pt.batches {
            (b.count, b.non_finite) = (1 << 33, 0);
        }
        assert!(check_batches("p.json", &p).is_ok());
    }

    /// The settings of a partial are a sweep's that `report` runs: powers of two from 256
    /// to 2⁴⁰, min ≤ max, 128 batches. Both 0 once made the merge shift by 64.
    #[test]
    fn settings_a_run_cannot_write_are_named() {
        let ok = Settings {
            seed: 1,
            min_samples: 256,
            max_samples: 1 << 40,
            batches: BATCHES,
        };
        assert!(check_settings("p.json", &ok).is_ok());
        let same = Settings {
            min_samples: 1 << 40,
            ..ok.clone()
        };
        assert!(check_settings("p.json", &same).is_ok());
        type Edit = fn(&mut Settings);
        let cases: [(Edit, &str); 9] = [
            (|s| s.min_samples = 0, "settings.min_samples"),
            (|s| s.min_samples = 128, "settings.min_samples"),
            (|s| s.min_samples = 384, "settings.min_samples"),
            (|s| s.max_samples = 0, "settings.max_samples"),
            (|s| s.max_samples = 1 << 41, "settings.max_samples"),
            (|s| s.max_samples = (1 << 40) - 1, "settings.max_samples"),
            (
                |s| (s.min_samples, s.max_samples) = (512, 256),
                "settings.max_samples",
            ),
            (|s| s.batches = BATCHES - 1, "settings.batches"),
            (|s| s.batches = BATCHES + 1, "settings.batches"),
        ];
        for (edit, field) in cases {
            let mut s = ok.clone();
            edit(&mut s);
            let e = check_settings("p.json", &s).unwrap_err();
            assert_eq!(e.field, field, "{e}");
        }
    }

    /// `--shard auto` reads only its own variables: junk bytes elsewhere in the
    /// environment are not its business; a variable of its own that is not UTF-8 is named.
    #[cfg(unix)]
    #[test]
    fn only_the_shard_variables_are_read_and_must_be_text() {
        use std::ffi::OsString;
        use std::os::unix::ffi::OsStringExt;
        let asked = std::cell::RefCell::new(vec![]);
        let env = shard_env(|n| {
            asked.borrow_mut().push(n.to_string());
            match n {
                "LIGHTPROOF_SHARD_INDEX" => Some(OsString::from("1")),
                "LIGHTPROOF_SHARD_COUNT" => Some(OsString::from("4")),
                _ => None,
            }
        })
        .unwrap();
        assert_eq!(asked.into_inner(), SHARD_VARIABLES);
        assert_eq!(shard_from_env(&env).unwrap(), Shard { index: 1, count: 4 });
        for name in SHARD_VARIABLES {
            let e = shard_env(|n| (n == name).then(|| OsString::from_vec(vec![b'1', 0xff])))
                .unwrap_err();
            assert_eq!(e.field, name);
            assert!(e.reason.contains("not UTF-8"), "{e}");
        }
    }

    #[test]
    fn every_batch_has_one_owner_and_shards_are_balanced() {
        for n in [1u32, 2, 3, 7, 127, 128] {
            let mut counts = vec![0u64; n as usize];
            for b in 0..BATCHES {
                counts[Shard::owner(n, 42, 10, b) as usize] += 1;
            }
            let (lo, hi) = (BATCHES / n as u64, BATCHES.div_ceil(n as u64));
            assert!(
                counts.iter().all(|&c| c == lo || c == hi),
                "{n}: {counts:?}"
            );
            let all: usize = (0..n)
                .map(|i| Shard { index: i, count: n }.batches(42, 10).len())
                .sum();
            assert_eq!(all as u64, BATCHES);
        }
    }

    #[test]
    fn parse() {
        assert_eq!(parse_shard("2/8").unwrap(), Shard { index: 2, count: 8 });
        for bad in ["8/8", "1", "a/2", "0/0", "-1/3"] {
            assert!(parse_shard(bad).is_err(), "{bad}");
        }
        // Up to one shard per batch: beyond, a shard would get none of a point.
        assert_eq!(
            parse_shard("127/128").unwrap(),
            Shard {
                index: 127,
                count: 128
            }
        );
        let e = parse_shard("0/129").unwrap_err();
        assert!(e.reason.contains("at most 128 shards"), "{e}");
        let env = |p: &[(&str, &str)]| shard_from_env(&env(p));
        for (vars, field) in [
            (
                &[
                    ("LIGHTPROOF_SHARD_INDEX", "0"),
                    ("LIGHTPROOF_SHARD_COUNT", "129"),
                ][..],
                "LIGHTPROOF_SHARD_COUNT",
            ),
            (
                &[
                    ("SLURM_ARRAY_TASK_ID", "0"),
                    ("SLURM_ARRAY_TASK_COUNT", "300"),
                ][..],
                "SLURM_ARRAY_TASK_COUNT",
            ),
        ] {
            let e = env(vars).unwrap_err();
            assert!(
                e.field == field && e.reason.contains("at most 128 shards"),
                "{e}"
            );
        }
        assert_eq!(
            env(&[
                ("JOB_COMPLETION_INDEX", "127"),
                ("LIGHTPROOF_SHARD_COUNT", "128")
            ])
            .unwrap(),
            Shard {
                index: 127,
                count: 128
            }
        );
    }

    #[test]
    fn slurm_arrays() {
        let s = |p: &[(&str, &str)]| shard_from_env(&env(p));
        let base = [
            ("SLURM_ARRAY_TASK_ID", "3"),
            ("SLURM_ARRAY_TASK_COUNT", "8"),
            ("SLURM_ARRAY_TASK_MIN", "0"),
            ("SLURM_ARRAY_TASK_MAX", "7"),
        ];
        assert_eq!(s(&base).unwrap(), Shard { index: 3, count: 8 });
        // --array=1-8: ids from 1.
        let one = [
            ("SLURM_ARRAY_TASK_ID", "1"),
            ("SLURM_ARRAY_TASK_COUNT", "8"),
            ("SLURM_ARRAY_TASK_MIN", "1"),
            ("SLURM_ARRAY_TASK_MAX", "8"),
        ];
        assert_eq!(s(&one).unwrap(), Shard { index: 0, count: 8 });
        // --array=0-14:2 → 8 tasks.
        let step = [
            ("SLURM_ARRAY_TASK_ID", "6"),
            ("SLURM_ARRAY_TASK_COUNT", "8"),
            ("SLURM_ARRAY_TASK_MIN", "0"),
            ("SLURM_ARRAY_TASK_MAX", "14"),
            ("SLURM_ARRAY_TASK_STEP", "2"),
        ];
        assert_eq!(s(&step).unwrap(), Shard { index: 3, count: 8 });
        // --array=1,4,9: not evenly spaced.
        let sparse = [
            ("SLURM_ARRAY_TASK_ID", "4"),
            ("SLURM_ARRAY_TASK_COUNT", "3"),
            ("SLURM_ARRAY_TASK_MIN", "1"),
            ("SLURM_ARRAY_TASK_MAX", "9"),
        ];
        assert!(s(&sparse).is_err());
        // Re-submitting task 5 of 8: the count comes from LIGHTPROOF_SHARD_COUNT.
        let resub = [
            ("SLURM_ARRAY_TASK_ID", "5"),
            ("SLURM_ARRAY_TASK_COUNT", "1"),
            ("SLURM_ARRAY_TASK_MIN", "5"),
            ("LIGHTPROOF_SHARD_COUNT", "8"),
        ];
        assert_eq!(s(&resub).unwrap(), Shard { index: 5, count: 8 });
        assert!(
            s(&[
                ("SLURM_ARRAY_TASK_ID", "x"),
                ("SLURM_ARRAY_TASK_COUNT", "2")
            ])
            .is_err()
        );
    }

    #[test]
    fn kubernetes_and_explicit() {
        let s = |p: &[(&str, &str)]| shard_from_env(&env(p));
        assert_eq!(
            s(&[
                ("JOB_COMPLETION_INDEX", "4"),
                ("LIGHTPROOF_SHARD_COUNT", "6")
            ])
            .unwrap(),
            Shard { index: 4, count: 6 }
        );
        let e = s(&[("JOB_COMPLETION_INDEX", "4")]).unwrap_err();
        assert_eq!(e.field, "LIGHTPROOF_SHARD_COUNT");
        assert!(
            s(&[
                ("JOB_COMPLETION_INDEX", "6"),
                ("LIGHTPROOF_SHARD_COUNT", "6")
            ])
            .is_err()
        );
        // The explicit pair wins over a scheduler's variables.
        assert_eq!(
            s(&[
                ("LIGHTPROOF_SHARD_INDEX", "1"),
                ("LIGHTPROOF_SHARD_COUNT", "2"),
                ("JOB_COMPLETION_INDEX", "0"),
            ])
            .unwrap(),
            Shard { index: 1, count: 2 }
        );
        assert!(s(&[]).is_err());
    }
}
