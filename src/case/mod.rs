//! Cases: a case file names a scene, a measurement, the oracle's reference and the
//! estimators to run; [`Case::load`] validates and builds it, [`Case::run`] estimates it
//! — the one run path of `verify`, `estimate`, `report`, the examples and the proof.
//!
//! A case file:
//! ```json
//! {
//!   "name": "disk light over a point, on axis",
//!   "teaches": "irradiance E = π L sin²θ from a uniform disk",
//!   "scene": { "shapes": [ { "geometry": { "type": "disk", "center": [0, 0, 2],
//!              "normal": [0, 0, -1], "radius": 1 }, "emission": { "radiance": 1 } } ] },
//!   "measure": { "irradiance": { "at": [0, 0, 0], "normal": [0, 0, 1] } },
//!   "reference": { "closed_form": "disk_irradiance_on_axis", "radius": 1, "height": 2, "radiance": 1 },
//!   "estimators": ["light", "bsdf", "mis"],
//!   "samplers": ["independent"],
//!   "samples": 262144
//! }
//! ```
//! The reference names a closed form of `lightproof-analytic` (the independent oracle)
//! with its parameters; a case without one is simply estimated.
//!
//! Modules: [`schema`] (the file as written), [`build`] (validation, one step per
//! section). Judging the outcomes is [`crate::verdict`]'s job.

pub mod bins;
pub mod build;
pub mod schema;

use crate::error::{InputError, parse_json};
use crate::sampling::{SampleStream, SamplerKind};
use crate::scene::Scene;
use crate::transport::Estimator;
use crate::transport::engine::{Estimate, RunSpec, run};
use crate::transport::measure::Measure;
use crate::transport::plan::{Plan, Plans};
use crate::verdict::Outcome;
use std::path::{Path, PathBuf};
use std::sync::Arc;

pub use crate::transport::engine::BATCHES;
pub use schema::{CameraDesc, CaseDesc, MeasureDesc, SpectralDesc, TimeDesc, WavelengthSampling};

/// Default samples per estimate.
pub const DEFAULT_SAMPLES: u64 = 1 << 18;

/// Fewest samples per estimate: two per batch (the batch-means error needs them).
pub const MIN_SAMPLES: u64 = 2 * BATCHES;

/// Most samples per estimate: 2⁴⁰ ≈ 1.1·10¹² (days of work; no count wraps below it).
pub const MAX_SAMPLES: u64 = 1 << 40;

/// A whole number in [lo, hi] (surrounding spaces ignored), or a message saying the
/// range (`hi_name` names its top): the command line's counts and seeds.
pub fn count_in(s: &str, lo: u64, hi: u64, hi_name: &str) -> Result<u64, String> {
    match s.trim().parse::<u64>() {
        Ok(v) if (lo..=hi).contains(&v) => Ok(v),
        _ => Err(format!(
            "must be a whole number from {lo} to {hi_name}, got `{s}`"
        )),
    }
}

/// The environment variable `name` read as the command line reads `LIGHTPROOF_SEED`
/// (a whole number from `lo` to 2⁶⁴ − 1, [`count_in`]): `None` when unset or empty, an
/// error naming the variable for anything else (text that is not UTF-8 too), so a
/// mistyped value never silently runs the default. For the proof's own seed and scale
/// (`tests/proof/common.rs`) and the unit tests that take the seed.
pub fn env_count(name: &str, lo: u64) -> Result<Option<u64>, String> {
    var_count(name, std::env::var_os(name).as_deref(), lo)
}

/// [`env_count`] of the variable's value (`None`: unset).
fn var_count(name: &str, value: Option<&std::ffi::OsStr>, lo: u64) -> Result<Option<u64>, String> {
    match value {
        None => Ok(None),
        Some(v) if v.is_empty() => Ok(None),
        Some(v) => match v.to_str() {
            Some(text) => count_in(text, lo, u64::MAX, "2^64 − 1")
                .map(Some)
                .map_err(|e| format!("{name}: {e}")),
            None => Err(format!(
                "{name}: is not UTF-8 text, got {:?}",
                v.to_string_lossy()
            )),
        },
    }
}

/// A loaded, validated case.
pub struct Case {
    /// Where it came from.
    pub file: PathBuf,
    /// Its description.
    pub desc: CaseDesc,
    /// The built scene (one for a case and all its time bins: they differ only in
    /// the time window they measure).
    pub scene: Arc<Scene>,
    /// The measurement in engine coordinates.
    pub measure: Measure,
    /// The reference value, if any.
    pub reference: Option<f64>,
    /// ρ = μ(f32 inputs) − μ, the reference's change when its inputs take the `f32`
    /// values the engine's scene holds ([`build::reference_rounding`]; 0 without a
    /// reference): every verdict accepts a mean between μ and μ + ρ.
    pub reference_rounding: f64,
    /// What its estimates simulate: the pruned plan.
    pub plan: Plan,
    /// Every effect and dimension on, for the soundness proof.
    pub full: Plan,
    /// The cases of a time-resolved histogram's bins (`time.bins`; empty otherwise); the
    /// case itself then measures the whole span of the bins.
    pub bins: Vec<Case>,
}

impl Case {
    /// Load and validate a case file.
    pub fn load(path: &Path) -> Result<Case, InputError> {
        let file = path.display().to_string();
        let text = crate::io::read_input(path, crate::io::MAX_JSON_BYTES)
            .map_err(|e| InputError::new(&file, "-", e))?;
        let desc: CaseDesc = parse_json(&file, &text)?;
        Case::from_desc(desc, path)
    }

    /// Validate a parsed description (`path` names it and anchors relative paths).
    pub fn from_desc(desc: CaseDesc, path: &Path) -> Result<Case, InputError> {
        let f = path.display().to_string();
        if let Some(e) = bins::edges(&f, &desc)? {
            let mut whole =
                Case::with_scene(bins::with_bin(&desc, e[0], e[e.len() - 1]), path, None)
                    .map_err(|err| bins::name_the_bins(err, "the whole span"))?;
            whole.bins = bins::build(&desc, path, &e, &whole.scene)?;
            whole.desc = desc;
            return Ok(whole);
        }
        Case::with_scene(desc, path, None)
    }

    /// [`Case::from_desc`] of a description without `time.bins`, on `scene` if given
    /// (built from the same `desc.scene` and origin: a time bin's), else on the scene
    /// built from `desc`.
    pub(crate) fn with_scene(
        desc: CaseDesc,
        path: &Path,
        scene: Option<&Arc<Scene>>,
    ) -> Result<Case, InputError> {
        let file = path.display().to_string();
        let f = file.as_str();
        let origin = build::origin(f, &desc)?;
        // Before the scene is built: moving objects are placed at the shutter's start,
        // which must keep them in range (`build::epoch`).
        build::check_spectral_and_time(f, &desc)?;
        let scene = match scene {
            Some(s) => Arc::clone(s),
            None => {
                let base = crate::scene::load::folder_of(path);
                Arc::new(desc.scene.build_over(
                    f,
                    "scene",
                    base,
                    origin,
                    build::epoch(&desc),
                    build::measured_band(&desc),
                )?)
            }
        };
        let measure = build::measure(f, &desc.measure, &scene, origin)?;
        build::check_view_factor(f, &desc, &scene)?;
        build::check_receiver_clear_of_light_surfaces(
            f,
            &measure,
            &scene,
            build::shutter_length(&desc),
        )?;
        build::check_estimators(f, &desc, &measure)?;
        build::check_samples(f, &desc)?;
        let reference = build::reference(f, &desc)?;
        let reference_rounding =
            reference.map_or(0.0, |r| build::reference_rounding(&desc, origin, r));
        let max_bounces = build::max_bounces(f, &desc, &measure)?;
        let Plans {
            mut pruned,
            mut full,
        } = Plans::decide(
            f,
            &scene,
            &measure,
            desc.spectral.as_ref(),
            desc.time.as_ref(),
        )?;
        // A depth limit is part of what is measured, not a pruning: both plans keep it.
        if let Some(b) = max_bounces {
            pruned = pruned.with_max_bounces(b);
            full = full.with_max_bounces(b);
        }
        Ok(Case {
            file: path.to_path_buf(),
            desc,
            scene,
            measure,
            reference,
            reference_rounding,
            plan: pruned,
            full,
            bins: vec![],
        })
    }

    /// The files its scene reads (OBJ meshes, EXR maps), resolved against the case file's
    /// folder as the loader resolves them.
    pub fn external_paths(&self) -> Vec<PathBuf> {
        self.desc.scene.external_paths(&self.file)
    }

    /// Samplers to run.
    pub fn samplers(&self) -> Vec<SamplerKind> {
        self.desc
            .samplers
            .clone()
            .unwrap_or_else(|| vec![SamplerKind::Independent])
    }

    /// The one-sample estimator of `est` under `plan` (the case's own, its full twin,
    /// or one cut at a depth): a function of a sample stream, for the engine to run.
    pub fn integrand<'a>(
        &'a self,
        plan: &'a Plan,
        est: Estimator,
    ) -> impl Fn(&mut SampleStream) -> f32 + Sync + 'a {
        let cfg = plan.config(est);
        move |s: &mut SampleStream| {
            self.measure
                .sample_with(&self.scene, est, &cfg, &plan.dims, s)
        }
    }

    /// Estimate with `est` under the case's plan.
    pub fn estimate(&self, est: Estimator, spec: &RunSpec) -> Estimate {
        self.estimate_with(&self.plan, est, spec)
    }

    /// Estimate with `est` under `plan` (e.g. [`Case::full`] for the soundness proof).
    pub fn estimate_with(&self, plan: &Plan, est: Estimator, spec: &RunSpec) -> Estimate {
        run(spec, self.integrand(plan, est))
    }

    /// Run estimator `est` with `sampler` for `samples` samples at `seed` under the
    /// case's plan: the unjudged outcome (see [`crate::verdict`]).
    pub fn run(&self, est: Estimator, sampler: SamplerKind, samples: u64, seed: u64) -> Outcome {
        let spec = RunSpec {
            samples,
            sampler,
            seed,
        };
        let e = self.estimate(est, &spec);
        let mut o = Outcome::new(
            &self.desc.name,
            &self.file,
            &self.measure,
            &self.plan,
            self.reference,
            est,
            sampler,
            seed,
            &e,
        );
        o.reference_rounding = self.reference_rounding;
        o
    }

    /// Samples of one estimate: `samples`, else the case's own, else [`DEFAULT_SAMPLES`],
    /// times `scale` (`LIGHTPROOF_SCALE`).
    pub fn samples(&self, samples: Option<u64>, scale: u64) -> u64 {
        samples
            .or(self.desc.samples)
            .unwrap_or(DEFAULT_SAMPLES)
            .saturating_mul(scale.max(1))
    }

    /// Run every estimator × sampler of the case, each with its own seed from
    /// `base_seed` ([`seed_for`]); the outcomes are not yet judged (see
    /// [`crate::verdict::judge_family`]).
    pub fn run_all(&self, base_seed: u64, samples: Option<u64>, scale: u64) -> Vec<Outcome> {
        let n = self.samples(samples, scale);
        let mut out = Vec::new();
        for sampler in self.samplers() {
            for &est in &self.desc.estimators {
                let seed = seed_for(base_seed, &self.desc.name, est, sampler);
                out.push(self.run(est, sampler, n, seed));
                out.extend(self.run_bins(est, sampler, n, base_seed));
            }
        }
        out
    }
}

/// Per-test seed: the base seed mixed with the case's name, estimator and sampler, so the
/// tests of distinct names are independent (Šidák is exact) and reproducible, and a case
/// keeps its seeds when its file moves. Two files of one name (the catalog has none;
/// `catalog_is_well_formed`) draw the same numbers: their two-sided tests are then
/// positively dependent, for which Šidák's correction is conservative (Šidák 1967), so no
/// verdict passes more easily.
pub fn seed_for(base: u64, case: &str, est: Estimator, sampler: SamplerKind) -> u64 {
    use crate::sampling::sampler::{fnv1a, hash_words};
    let names = case
        .bytes()
        .chain(est.name().bytes())
        .chain(sampler.name().bytes());
    hash_words(&[base, fnv1a(names)])
}

/// Every `.json` case file under the given files or folders (recursively), sorted.
pub fn collect_cases(paths: &[PathBuf]) -> Result<Vec<PathBuf>, InputError> {
    crate::io::collect_files(paths, true, |q| q.extension().is_some_and(|x| x == "json"))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The proof's `LIGHTPROOF_SEED` and `LIGHTPROOF_SCALE` are read as the command line
    /// reads its seed: unset or empty is the default, spaces around a number are let be,
    /// and anything else (a sign, text, a fraction, past 2⁶⁴ − 1, below the least, not
    /// UTF-8) is an error naming the variable. The proof read `" 77"` as unset once, so
    /// a seed sweep could silently rerun the default seed.
    #[test]
    fn knobs_in_the_environment_are_read_strictly() {
        use std::ffi::OsStr;
        let read = |v: Option<&str>, lo| var_count("KNOB", v.map(OsStr::new), lo);
        assert_eq!(read(None, 0), Ok(None));
        assert_eq!(read(Some(""), 0), Ok(None));
        assert_eq!(read(Some(" 77 "), 0), Ok(Some(77)));
        assert_eq!(read(Some("0"), 0), Ok(Some(0)));
        assert_eq!(read(Some("18446744073709551615"), 0), Ok(Some(u64::MAX)));
        assert_eq!(read(Some("8"), 1), Ok(Some(8)));
        for bad in [
            "abc",
            "-1",
            "+-1",
            "1.5",
            "18446744073709551616",
            " ",
            "7 7",
        ] {
            let e = read(Some(bad), 0).unwrap_err();
            assert!(
                e.starts_with("KNOB: ") && e.contains(&format!("`{bad}`")),
                "{e}"
            );
        }
        assert!(read(Some("0"), 1).unwrap_err().contains("from 1 to"));
        // Through the environment itself, under a name no other test reads.
        const NAME: &str = "LIGHTPROOF_KNOB_UNDER_TEST";
        assert_eq!(env_count(NAME, 0), Ok(None));
        // SAFETY: no other thread reads this variable, and Rust's own environment access
        // is locked against `set_var`.
        unsafe { std::env::set_var(NAME, " 42") };
        assert_eq!(env_count(NAME, 0), Ok(Some(42)));
        unsafe { std::env::set_var(NAME, "x") };
        assert!(env_count(NAME, 0).unwrap_err().starts_with(NAME));
        unsafe { std::env::remove_var(NAME) };
        #[cfg(unix)]
        {
            use std::os::unix::ffi::OsStrExt;
            let e = var_count("KNOB", Some(OsStr::from_bytes(b"7\xff")), 0).unwrap_err();
            assert!(e.starts_with("KNOB: is not UTF-8"), "{e}");
        }
    }

    /// A measurement's name is said twice, by the case file's key (`MeasureDesc::key`,
    /// which error paths use) and by the built measurement (`Measure::name`, which
    /// reports use): over the catalog, both agree with the key serde reads, for every
    /// kind of measurement.
    #[test]
    fn a_measurements_key_and_name_agree() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("analytic/cases");
        let mut kinds = std::collections::BTreeSet::new();
        for file in collect_cases(&[root]).unwrap() {
            let case = Case::load(&file).unwrap();
            let key = case.desc.measure.key();
            let tagged = serde_json::to_value(&case.desc.measure).unwrap();
            let serde_key = tagged.as_object().and_then(|o| o.keys().next()).unwrap();
            assert_eq!(
                (key, key),
                (serde_key.as_str(), case.measure.name()),
                "{}",
                file.display()
            );
            kinds.insert(key);
        }
        assert_eq!(kinds.len(), 10, "the catalog measures {kinds:?}");
    }
}
