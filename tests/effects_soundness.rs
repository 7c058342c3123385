//! Simulating only the effects a scene calls for changes no expected value: for every
//! catalog case, the pruned simulation (as `verify` runs it) and the full one (every
//! bounce with Russian roulette, every shadow ray) agree in a two-sample z test, Šidák
//! corrected over the catalog. The speed-up of pruning is printed.

mod common;

use lightproof::sampling::SamplerKind;
use lightproof::stats::sidak_alpha;
use lightproof::transport::engine::RunSpec;
use lightproof::verify::{Case, collect_cases, seed_for};
use statrs::distribution::{ContinuousCDF, Normal};
use std::path::PathBuf;

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
    assert!(!cases.is_empty());
    let crit = Normal::standard().inverse_cdf(1.0 - sidak_alpha(1e-4, cases.len()) / 2.0);
    let mut lines = Vec::new();
    let mut failures = Vec::new();
    let (mut t_pruned, mut t_full) = (0.0, 0.0);
    for c in cases {
        let est = c.desc.estimators[0];
        let n = (1u64 << 15) * common::scale();
        let seed = seed_for(common::seed(), &c.desc.name, est, SamplerKind::Independent);
        let pruned = c.estimate(
            est,
            &RunSpec {
                samples: n,
                sampler: SamplerKind::Independent,
                seed,
            },
            false,
        );
        let full = c.estimate(
            est,
            &RunSpec {
                samples: n,
                sampler: SamplerKind::Independent,
                seed: seed ^ 0xf011,
            },
            true,
        );
        let (a, b) = (&pruned.batches.total, &full.batches.total);
        let se = (a.std_error().powi(2) + b.std_error().powi(2)).sqrt();
        let diff = a.mean - b.mean;
        let z = if diff == 0.0 {
            0.0
        } else {
            diff / se.max(2e-6 * a.mean.abs())
        };
        t_pruned += pruned.seconds;
        t_full += full.seconds;
        lines.push(format!(
            "{:<50} pruned {:.6} full {:.6} z {:+.2} speed-up {:.2}x",
            c.desc.name,
            a.mean,
            b.mean,
            z,
            full.seconds / pruned.seconds.max(1e-9)
        ));
        if z.abs() > crit || a.non_finite + b.non_finite > 0 {
            failures.push(lines.last().unwrap().clone());
        }
    }
    println!(
        "{}\ntotal: pruned {t_pruned:.2}s, full {t_full:.2}s",
        lines.join("\n")
    );
    assert!(
        failures.is_empty(),
        "pruning changed an expected value:\n{}",
        failures.join("\n")
    );
}
