//! Convergence reports: what accuracy costs in time.
//!
//! `lightproof report` sweeps every case × estimator × sampler over sample counts
//! N = 2ᵏ and writes, per case, one JSON report (described by `reports/schema.json`), one
//! log–log SVG of error against time, and an index (`index.json`, `index.md`).
//!
//! **A point** is one independent run of N samples in [`BATCHES`] batches with its own
//! seed, `hash_words([seed_for(seed, case, estimator, sampler), k])`, so the points of a
//! series are independent and the residuals of a slope fit measure its uncertainty. A
//! point records the estimate, the batch-means standard error, the plain standard error,
//! the absolute and relative error against the reference, the RMS error against the
//! reference `√(Σ_b (m_b − ref)²/B)/√B` (B batch means m_b; it equals the standard error
//! for an unbiased estimator; the part of the distance |x̄ − ref| beyond what chance
//! explains is added in full, [`analysis::point_from_batches`], so a biased estimator
//! shows a flattening slope), and its cost in **core-seconds**: the sum of the
//! per-batch CPU times of the computing threads ([`clock`]), which is what shards add up
//! to, which does not depend on the thread count (divide by the threads for the wall
//! time on an idle machine) and which other processes on a busy machine do not inflate.
//!
//! **A series** (one estimator × sampler) fits ln e = a + b ln N and ln e = a′ + b′ ln t
//! by least squares (slope standard error from the residuals, see [`crate::stats::slope`]),
//! where e is the RMS error when the case has a reference and the standard error
//! otherwise; fits the cost line t̂(N) = t₀ + c·N through the core-seconds
//! ([`analysis::summarize`]); reports the efficiency 1/(σ̂² t̂) at its largest point (σ̂
//! the standard error, t̂ its fitted core-seconds: the inverse of the work-variance
//! product, Veach 1997 §2.4); and the time to reach 1%, 0.1% and 0.01% relative error
//! along the fits, N* = exp((ln(ε |ref|) − a)/b) (not below the first point) and
//! t* = t̂(N*) (N*·c′ without a cost line, c′ the largest point's core-seconds per
//! sample), marked extrapolated when N* lies past the sweep; a series whose error does
//! not fall (or whose fit has two points) takes the cheapest point with e/|ref| ≤ ε, at
//! its fitted time. A bias the points establish ([`analysis::bias_floor`]) is reported,
//! and no target at or below it gets a time.
//!
//! **A case** names its most efficient series: the least time to 0.1% relative error
//! (for a rate of −½ and a negligible fixed cost t₀ this ranks as 1/(σ²t) does), with
//! the ratios of time and of efficiency to every other series.
//!
//! Modules: [`analysis`] (point statistics, fits, time to accuracy, the best series),
//! [`sweep`] (planning, budget, resume, the run), [`shard`] (shards of the batches,
//! the environment of array jobs, merging), [`store`] (file names, reading, atomic
//! writing), [`publish`] (the reports, plots and index a run or a merge ends with),
//! [`index`], [`plot`], [`machine`] (what a report records about its run).

pub mod analysis;
pub mod clock;
pub mod html;
pub mod index;
pub mod machine;
pub mod plot;
pub mod png;
pub mod publish;
pub mod shard;
pub mod store;
pub mod sweep;
pub mod transient;

use crate::sampling::SamplerKind;
use crate::stats::{CostFit, SlopeFit};
use crate::transport::Estimator;
pub use crate::transport::engine::BATCHES;
use serde::{Deserialize, Serialize};

/// Format tag of every file this module writes.
pub const FORMAT: &str = "lightproof-report/1";

/// Relative errors whose cost every series reports.
pub const TARGETS: [f64; 3] = [1e-2, 1e-3, 1e-4];

/// The relative error the index and the best-series choice are about.
pub const HEADLINE: f64 = 1e-3;

/// Default smallest sweep point (two samples per batch).
pub const DEFAULT_MIN_SAMPLES: u64 = 2 * BATCHES;

/// Default largest sweep point.
pub const DEFAULT_MAX_SAMPLES: u64 = 1 << 20;

/// Which kind of file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// A per-case report.
    Case,
    /// The index of a report folder.
    Index,
    /// A shard's partial result (raw batch accumulators).
    Shard,
}

/// What a sweep was asked for: equal settings (and case, and engine) give equal numbers.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Settings {
    /// Base seed.
    pub seed: u64,
    /// Smallest point, a power of two.
    pub min_samples: u64,
    /// Largest point, a power of two.
    pub max_samples: u64,
    /// Batches per point.
    pub batches: u64,
}

impl Settings {
    /// Exponents k of the points N = 2ᵏ.
    pub fn exponents(&self) -> std::ops::RangeInclusive<u32> {
        self.min_samples.trailing_zeros()..=self.max_samples.trailing_zeros()
    }
}

/// The case a report is about.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaseInfo {
    /// Its name.
    pub name: String,
    /// Its file, as given.
    pub file: String,
    /// What it teaches.
    pub teaches: String,
    /// Its measurement.
    pub measure: String,
    /// The closed-form reference, if any.
    pub reference: Option<f64>,
    /// Hash of the case description (a changed case is swept afresh).
    pub digest: String,
}

/// The error whose convergence a report fits.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ErrorMeasure {
    /// RMS error of the batch means against the reference (cases with a reference).
    RmsError,
    /// Batch-means standard error (cases without one).
    StdError,
}

/// The machine a run used.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Machine {
    /// CPU model (from /proc/cpuinfo where there is one).
    pub cpu: String,
    /// Logical cores.
    pub logical_cores: usize,
    /// Operating system.
    pub os: String,
    /// Architecture.
    pub arch: String,
    /// The instruction set the BVH's ray queries ran in (`baseline` or `x86-64-v3`,
    /// [`crate::scene::accel::Isa`]): the same answers, not the same speed. Absent from
    /// reports written before it was recorded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ray_isa: Option<String>,
}

/// Who made a file, where and how.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunInfo {
    /// `CARGO_PKG_VERSION`.
    pub lightproof_version: String,
    /// Git revision of the build (`unknown` outside a checkout).
    pub git_revision: String,
    /// The cargo profile of the build ([`machine::PROFILE`]). Absent from reports
    /// written before it was recorded.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub profile: Option<String>,
    /// Worker threads.
    pub threads: usize,
    /// The machine.
    pub machine: Machine,
    /// Start, UTC, ISO 8601.
    pub started: String,
    /// Wall seconds of the whole run so far.
    pub wall_seconds: f64,
    /// `--budget`, if given.
    pub budget_seconds: Option<f64>,
    /// Whether the budget stopped some series early.
    pub budget_cut: bool,
    /// Points computed by this run.
    pub points_computed: u64,
    /// Points kept from an earlier run (resume).
    pub points_resumed: u64,
    /// For a merged report: the run of each shard.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub shards: Vec<ShardRun>,
}

/// One shard's run, recorded in a merged report.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShardRun {
    /// Shard index K (from 0).
    pub index: u32,
    /// Shard count N.
    pub count: u32,
    /// Its run.
    pub run: RunInfo,
}

/// Where a series stands.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// Every planned point is there.
    Complete,
    /// Still running (or the run was killed): points are missing.
    InProgress,
    /// `--budget` stopped it before its largest point.
    BudgetCut,
}

/// One sweep point: one independent run of `samples` samples.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Point {
    /// N.
    pub samples: u64,
    /// Its seed.
    pub seed: u64,
    /// Mean of the finite samples; `None` (null) when none is finite: there is no mean.
    pub estimate: Option<f64>,
    /// Batch-means standard error.
    pub std_error: Option<f64>,
    /// Plain standard error √(s²/N) (valid for independent samples only).
    pub plain_std_error: Option<f64>,
    /// RMS error of the batch means against the reference, divided by √B.
    pub rms_error: Option<f64>,
    /// |estimate − reference|.
    pub abs_error: Option<f64>,
    /// |estimate − reference| / |reference|.
    pub rel_error: Option<f64>,
    /// NaN or infinite samples (each one is a defect of the estimator).
    pub non_finite: u64,
    /// Core-seconds: the sum of the batches' compute times.
    pub seconds: f64,
    /// Wall seconds of the point (null in a merged report).
    pub wall_seconds: Option<f64>,
}

/// A least-squares line through log–log points.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Fit {
    /// Slope b.
    pub slope: f64,
    /// Its standard error (null with fewer than three points).
    pub slope_std_error: Option<f64>,
    /// Intercept a.
    pub intercept: f64,
    /// Points used.
    pub points: usize,
}

impl From<SlopeFit> for Fit {
    fn from(f: SlopeFit) -> Self {
        Fit {
            slope: f.slope,
            slope_std_error: f.slope_std_error.is_finite().then_some(f.slope_std_error),
            intercept: f.intercept,
            points: f.points,
        }
    }
}

/// The cost of one relative-error target.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimeTo {
    /// The target ε.
    pub rel_error: f64,
    /// Samples to reach it (null: neither reached nor extrapolable).
    pub samples: Option<f64>,
    /// Core-seconds to reach it.
    pub seconds: Option<f64>,
    /// Whether it comes from the fit rather than a measured point.
    pub extrapolated: bool,
}

/// One estimator × sampler of a case.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Series {
    /// Estimator.
    pub estimator: Estimator,
    /// Sampler.
    pub sampler: SamplerKind,
    /// Series seed, `seed_for(seed, case, estimator, sampler)`.
    pub seed: u64,
    /// Where it stands.
    pub status: Status,
    /// Points in increasing N.
    pub points: Vec<Point>,
    /// Core-seconds t = t₀ + c·N through the points (robust, relative; null when the
    /// times describe no cost line).
    pub fit_cost: Option<CostFit>,
    /// ln e against ln N.
    pub fit_samples: Option<Fit>,
    /// ln e against ln t̂, t̂ the fitted core-seconds (measured ones without a cost fit).
    pub fit_seconds: Option<Fit>,
    /// 1/(σ̂² t) at the largest point (null when σ̂ = 0).
    pub efficiency: Option<f64>,
    /// c of `fit_cost`, the fitted core-seconds per sample; without a cost line, the
    /// largest point's core-seconds over its N.
    pub seconds_per_sample: Option<f64>,
    /// Cost of each target of [`TARGETS`].
    pub time_to: Vec<TimeTo>,
    /// The least relative bias the points establish ([`analysis::bias_floor`]): no sample
    /// count brings the error below it, so no target at or below it has a time. Null
    /// where no point's distance to the reference exceeds what chance explains, or
    /// without a reference.
    #[serde(default)]
    pub bias_floor: Option<f64>,
}

/// How another series compares with the best one.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Comparison {
    /// Estimator.
    pub estimator: Estimator,
    /// Sampler.
    pub sampler: SamplerKind,
    /// Its time to [`HEADLINE`] over the best one's.
    pub time_ratio: Option<f64>,
    /// The best one's efficiency over its.
    pub efficiency_ratio: Option<f64>,
}

/// The most efficient series of a case, and by how much.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Best {
    /// Estimator.
    pub estimator: Estimator,
    /// Sampler.
    pub sampler: SamplerKind,
    /// The relative error it is judged at ([`HEADLINE`]).
    pub rel_error: f64,
    /// Its core-seconds to get there.
    pub seconds: Option<f64>,
    /// Whether that time is extrapolated.
    pub extrapolated: bool,
    /// Every other series against it.
    pub others: Vec<Comparison>,
}

/// The report of one case.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaseReport {
    /// [`FORMAT`].
    pub format: String,
    /// [`Kind::Case`].
    pub kind: Kind,
    /// Stable id: the case file's path under the folder given, without `.json`.
    pub id: String,
    /// The case.
    pub case: CaseInfo,
    /// The sweep.
    pub settings: Settings,
    /// What `e` is in the fits.
    pub error_measure: ErrorMeasure,
    /// The run that wrote this file.
    pub run: RunInfo,
    /// One per estimator × sampler.
    pub series: Vec<Series>,
    /// The most efficient series.
    pub best: Option<Best>,
    /// The SVG plot, relative to this file.
    pub plot: Option<String>,
}

/// One row of the index.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IndexRow {
    /// Report id.
    pub id: String,
    /// Case name.
    pub name: String,
    /// Report file, relative to the index.
    pub report: String,
    /// Plot, relative to the index.
    pub plot: Option<String>,
    /// Seed of the report.
    pub seed: u64,
    /// Whether every series is complete.
    pub complete: bool,
    /// The best series, if any.
    pub best: Option<IndexBest>,
    /// Where every series has a [`Series::bias_floor`], the least of them: whatever
    /// estimator, the points disagree with the reference by at least this much.
    #[serde(default)]
    pub bias_floor: Option<f64>,
}

/// The best series as the index shows it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IndexBest {
    /// Estimator.
    pub estimator: Estimator,
    /// Sampler.
    pub sampler: SamplerKind,
    /// Core-seconds to [`HEADLINE`].
    pub seconds: Option<f64>,
    /// Whether extrapolated.
    pub extrapolated: bool,
    /// Its slope of ln e against ln N.
    pub slope: Option<f64>,
    /// That slope's standard error.
    pub slope_std_error: Option<f64>,
    /// How many times slower the runner-up is (time to [`HEADLINE`]).
    pub runner_up_ratio: Option<f64>,
    /// Every point has a zero standard error: the estimator is exact up to f32
    /// rounding, and its error does not fall with N.
    pub zero_variance: bool,
    /// Its [`Series::bias_floor`].
    #[serde(default)]
    pub bias_floor: Option<f64>,
}

/// The index of a report folder.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Index {
    /// [`FORMAT`].
    pub format: String,
    /// [`Kind::Index`].
    pub kind: Kind,
    /// The run that last wrote it.
    pub run: RunInfo,
    /// One row per case report, sorted by id.
    pub cases: Vec<IndexRow>,
}

/// Replace a non-finite number by `None` (JSON has no NaN or infinity).
pub fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}
