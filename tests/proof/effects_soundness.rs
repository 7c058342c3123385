//! Simulating only the effects a scene calls for changes no expected value: for every
//! transport case of the catalog and every estimator × sampler it runs, the pruned
//! simulation (as `verify` runs it) and the full one (every bounce with Russian
//! roulette, every shadow ray, every wavelength and time dimension) are evaluated on
//! the same random numbers, and the mean of the paired differences d = pruned − full is
//! tested against 0 (Šidák corrected over twice the pairs, since each may be rerun once;
//! batch means for quasi-random samplers). Pairing makes the test sharp: where pruning is sound most differences are
//! exactly 0. Each verdict must be able to see a difference of 0.5 % of the pruned
//! estimate (detectable difference at 99 % power), as the catalog's verdicts do; a pair
//! whose every difference is 0 (within f32 rounding) is judged exactly. A pair too weak
//! at its first sample count is rerun once with the count its power calls for.

use crate::common;

use lightproof::case::{Case, collect_cases, seed_for};
use lightproof::stats::VerdictClass;
use lightproof::transport::engine::{RunSpec, run};
// The largest detectable difference, relative to the pruned estimate: the catalog's.
use lightproof::verdict::DETECTABLE_BOUND as MAX_DETECTABLE;
use lightproof::verdict::judge;
use std::path::PathBuf;

const ALPHA: f64 = 1e-4;

#[test]
fn pruned_and_full_simulations_agree() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("analytic/cases");
    let files = collect_cases(&[root]).expect("catalog");
    let cases: Vec<Case> = files
        .iter()
        .map(|f| Case::load(f).unwrap_or_else(|e| panic!("{e}")))
        .collect();
    // Only transport measurements have anything to prune.
    let cases: Vec<&Case> = cases
        .iter()
        .filter(|c| c.measure.origin().is_some())
        .collect();
    let pairs: usize = cases
        .iter()
        .map(|c| c.desc.estimators.len() * c.samplers().len())
        .sum();
    assert!(pairs > 50, "{pairs} pairs");
    // Each pair may be rerun once with more samples when its first run is too weak:
    // the family counts both runs.
    let family = 2 * pairs;
    let mut lines = Vec::new();
    let mut failures = Vec::new();
    let (mut exact, mut reruns) = (0, 0);
    for c in &cases {
        let reference = c.reference.expect("catalog cases have a reference").abs();
        // The pruned sample skips the two phase dimensions (wavelength, time) when it
        // is grey and static and the full one draws them: both then use the same
        // numbers for every position and direction.
        let offset = if c.plan.dims.is_grey_static() && !c.full.dims.is_grey_static() {
            2
        } else {
            0
        };
        for sampler in c.samplers() {
            for &est in &c.desc.estimators {
                let (pruned, full) = (c.integrand(&c.plan, est), c.integrand(&c.full, est));
                let paired = |n: u64, salt: u64| {
                    let spec = RunSpec {
                        samples: n * common::scale(),
                        sampler,
                        seed: seed_for(common::seed() ^ salt, &c.desc.name, est, sampler),
                    };
                    let d = run(&spec, |s| {
                        let mut twin = s.clone();
                        (0..offset).for_each(|_| {
                            s.next_1d();
                        });
                        pruned(s) - full(&mut twin)
                    });
                    let v = judge(&d, sampler, 0.0, ALPHA, family);
                    let rel = v.detectable_bias / reference.max(f64::MIN_POSITIVE);
                    (d, v, rel)
                };
                let n0 = c.desc.samples.unwrap_or(1 << 18).min(1 << 15);
                let (mut d, mut v, mut rel) = paired(n0, 0xeff);
                if v.class == VerdictClass::Statistical
                    && (rel.is_nan() || rel > MAX_DETECTABLE)
                    && v.passed
                {
                    // Samples for the target power, with a margin, at most 32× more.
                    let k = ((rel / MAX_DETECTABLE).powi(2) * 1.5).ceil().min(32.0) as u64;
                    (d, v, rel) = paired(n0 * k.max(2), 0xeff2);
                    reruns += 1;
                }
                if v.class == VerdictClass::Exact {
                    exact += 1;
                }
                let line = format!(
                    "{:<55} {:<11} {:<11} d̄ {:+.3e} (of {reference:.4e}) z {:+.2} det {:.4}% {}",
                    c.desc.name.chars().take(55).collect::<String>(),
                    est.name(),
                    sampler.name(),
                    d.batches.total.mean,
                    v.z,
                    100.0 * rel,
                    if v.class == VerdictClass::Exact {
                        "exact"
                    } else {
                        ""
                    }
                );
                // An exact pair (every difference 0) has nothing to detect.
                let weak =
                    v.class == VerdictClass::Statistical && (rel.is_nan() || rel > MAX_DETECTABLE);
                if !v.passed {
                    failures.push(format!("{line}  {}", v.reason.clone().unwrap_or_default()));
                } else if weak {
                    failures.push(format!(
                        "{line}  detectable difference above {MAX_DETECTABLE}: the test cannot see a 0.5 % change"
                    ));
                }
                lines.push(line);
            }
        }
    }
    println!(
        "{}\n{pairs} pairs ({exact} exact: identical on every sample, {reruns} rerun with more samples)",
        lines.join("\n")
    );
    assert!(
        failures.is_empty(),
        "pruning changed an expected value (seed {}):\n{}",
        common::seed(),
        failures.join("\n")
    );
}
