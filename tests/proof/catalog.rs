//! The analytic catalog: every case under `analytic/cases` is estimated with every
//! estimator it names and judged against its closed form, Šidák corrected over the
//! whole catalog (family-wise α = 1e-4). Every verdict must pass, and must be able to
//! see a 0.5 % relative bias (detectable relative bias ≤ `DETECTABLE_BOUND` = 0.005 at
//! 99 % power, `Outcome::require_power`), or the pass proves nothing.
//!
//! `LIGHTPROOF_SEED` picks the base seed, `LIGHTPROOF_SCALE` multiplies every sample
//! count. `LIGHTPROOF_CATALOG_FILTER` (a substring of the file path) runs a subset, still
//! corrected for the whole catalog, for debugging one case.

use crate::common;

use lightproof::case::{Case, collect_cases};
use lightproof::verdict::{Outcome, judge_family};
use std::path::PathBuf;
use std::time::Instant;

/// The catalog's family-wise significance level.
const ALPHA: f64 = 1e-4;
/// The fewest case files the catalog may hold.
const MIN_CASES: usize = 40;

fn load_catalog() -> Vec<Case> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("analytic/cases");
    let files = collect_cases(&[root]).expect("the catalog folder is readable");
    files
        .iter()
        .map(|f| Case::load(f).unwrap_or_else(|e| panic!("{e}")))
        .collect()
}

#[test]
fn catalog_is_well_formed() {
    let cases = load_catalog();
    assert!(
        cases.len() >= MIN_CASES,
        "the catalog holds {} case files, fewer than {MIN_CASES}",
        cases.len()
    );
    let mut bad = Vec::new();
    let mut names = std::collections::BTreeMap::new();
    for c in &cases {
        let file = c.file.display().to_string();
        if c.desc.teaches.trim().is_empty() {
            bad.push(format!("{file}: empty `teaches`"));
        }
        if c.reference.is_none() {
            bad.push(format!("{file}: no closed-form `reference`"));
        }
        if let Some(other) = names.insert(c.desc.name.clone(), file.clone()) {
            // Seeds are derived from the name: two cases of one name would share them.
            bad.push(format!(
                "{file}: name `{}` also used by {other}",
                c.desc.name
            ));
        }
    }
    assert!(
        bad.is_empty(),
        "ill-formed catalog cases:\n{}",
        bad.join("\n")
    );
}

fn row(o: &Outcome) -> String {
    let v = o.verdict.as_ref();
    format!(
        "{:<58} {:<11} {:>14.7e} {:>11.3e} {:>14.7e} {:>8.2} {:>7.4} {:>7.3}s  {}",
        o.file.rsplit("analytic/cases/").next().unwrap_or(&o.file),
        o.estimator.name(),
        o.estimate,
        o.std_error.unwrap_or(0.0),
        o.reference.unwrap_or(f64::NAN),
        o.z.unwrap_or(f64::NAN),
        v.map_or(f64::NAN, |v| v.detectable_relative_bias),
        o.seconds,
        v.and_then(|v| v.reason.clone()).unwrap_or_default(),
    )
}

#[test]
fn catalog_matches_closed_forms() {
    let cases = load_catalog();
    let (seed, scale) = (common::seed(), common::scale());
    let filter = std::env::var("LIGHTPROOF_CATALOG_FILTER").unwrap_or_default();
    let header = format!(
        "{:<58} {:<11} {:>14} {:>11} {:>14} {:>8} {:>7} {:>8}  reason",
        "case", "estimator", "estimate", "SE", "reference", "z", "det", "time"
    );
    let start = Instant::now();
    let mut failures = Vec::new();
    let mut outcomes = Vec::new();
    for c in cases
        .iter()
        .filter(|c| c.file.display().to_string().contains(&filter))
    {
        let mine = c.run_all(seed, None, scale);
        // Exact cases say why; the others must hold an estimator with variance.
        let all_exact = mine.iter().all(|o| o.exact);
        match (&c.desc.exact, all_exact) {
            (None, true) => failures.push(format!(
                "{}: every estimator is exact (no variance): add an estimator with variance or state the reason in `exact`",
                c.file.display()
            )),
            (Some(_), false) => failures.push(format!(
                "{}: `exact` claims no variance, but an estimator has some",
                c.file.display()
            )),
            (Some(why), true) if why.trim().len() < 20 || why.contains("reads back") => failures
                .push(format!("{}: `exact` must give a reason that is not reading back an input", c.file.display())),
            _ => {}
        }
        outcomes.extend(mine);
    }
    // A filter that matches no case file (a typo) would otherwise pass on no verdict.
    assert!(
        !outcomes.is_empty(),
        "LIGHTPROOF_CATALOG_FILTER = {filter:?} matches no case file under analytic/cases (a substring of the file path, e.g. `spectral/`): no verdict, nothing proven"
    );
    // The family: every statistical verdict of the run. A filtered run cannot know the
    // whole catalog's count, so it uses every estimator × sampler of the catalog (an
    // upper bound: conservative).
    let tests = if filter.is_empty() {
        judge_family(&mut outcomes, 0, ALPHA)
    } else {
        let k = cases
            .iter()
            .map(|c| c.desc.estimators.len() * c.samplers().len() * (1 + c.bins.len()))
            .sum();
        outcomes.iter_mut().for_each(|o| o.judge(ALPHA, k));
        k
    };
    let mut lines = vec![header.clone()];
    for o in &mut outcomes {
        // The catalog runs each case's own estimators × samplers at its own count or
        // more: a verdict that cannot see a 0.5 % bias fails.
        o.require_power(true);
    }
    for o in &outcomes {
        let r = row(o);
        if !o.passed() {
            failures.push(r.clone());
        } else if o.verdict.is_none() {
            failures.push(format!("{r}no reference"));
        } else if o.exact_by_batch_means {
            // README "How a verdict is reached": no catalog verdict is exact only because
            // its batch means agree while its samples vary; such a verdict has no
            // statistic, and a case whose sampler stratifies its integrand exactly is a
            // case to change.
            failures.push(format!(
                "{r}exact by equal batch means, its samples varying"
            ));
        }
        lines.push(r);
    }
    let ran = outcomes.len();
    let exact = outcomes.iter().filter(|o| o.exact).count();
    let total = start.elapsed().as_secs_f64();
    println!("{}", lines.join("\n"));
    println!(
        "catalog: {} cases, {ran} verdicts ({} statistical in a Šidák family of {tests}, {exact} exact), seed {seed}, scale {scale}, total {total:.2}s",
        cases.len(),
        ran - exact
    );
    assert!(
        failures.is_empty(),
        "{} of {ran} catalog verdicts failed (seed {seed}, scale {scale}; rerun with LIGHTPROOF_SEED={seed}):\n{header}\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// The oracle never shares code with what it judges, in either direction: the oracle
/// crate depends on nothing of the engine, and in the engine only the step of building a
/// case that looks its reference up (`src/case/build.rs`) names the oracle.
#[test]
fn oracle_and_engine_share_no_code() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    fn rust_files(dir: &std::path::Path, out: &mut Vec<PathBuf>) {
        for e in std::fs::read_dir(dir)
            .expect("readable source folder")
            .flatten()
        {
            let p = e.path();
            if p.is_dir() {
                rust_files(&p, out);
            } else if p.extension().is_some_and(|x| x == "rs") {
                out.push(p);
            }
        }
    }
    let mut bad = Vec::new();
    let manifest = std::fs::read_to_string(root.join("analytic/Cargo.toml")).unwrap();
    if manifest.contains("lightproof =") || manifest.contains("path = \"..\"") {
        bad.push("analytic/Cargo.toml depends on the engine".to_string());
    }
    let mut oracle = Vec::new();
    rust_files(&root.join("analytic/src"), &mut oracle);
    assert!(oracle.len() > 5);
    for f in &oracle {
        let text = std::fs::read_to_string(f).unwrap();
        if text.contains("lightproof::") || text.contains("extern crate lightproof") {
            bad.push(format!("{} uses the engine", f.display()));
        }
    }
    let mut engine = Vec::new();
    rust_files(&root.join("src"), &mut engine);
    assert!(engine.len() > 20);
    for f in &engine {
        let rel = f.strip_prefix(&root).unwrap().display().to_string();
        let harness = rel == "src/case/build.rs";
        let text = std::fs::read_to_string(f).unwrap();
        if !harness && text.contains("lightproof_analytic") {
            bad.push(format!("{rel} (engine code) uses the oracle"));
        }
    }
    assert!(
        bad.is_empty(),
        "the oracle and the engine share code:\n{}",
        bad.join("\n")
    );
}

/// The oracle answers the question the engine is asked: every case's reference moves by at
/// most the exact class's f32 allowance γ₁₂₈ ≈ 7.6·10⁻⁶ relative when the closed form is
/// evaluated on the numbers the engine's `f32` scene holds (`Case::reference_rounding`,
/// the harness's model of the loader, `lightproof::case::build::as_engine_sees`). The
/// harness adds that movement ρ to every verdict's allowance, so a correct engine is not
/// failed for digits its inputs cannot hold; this test keeps ρ from costing the catalog
/// power. A case whose closed form is that sensitive to its inputs (a sliver triangle
/// whose 10⁻⁴ edge `0.4001` rounds by 3·10⁻⁸) writes its coordinates as exact `f32`
/// values, as the near-touching sphere lights do; before ρ entered the allowance, a
/// sampler with the power to see 10⁻⁴ (Sobol points on a smooth integrand) failed a
/// correct engine there (z = −650), where the catalog's independent sampler (3·10⁻⁴
/// standard error) could not see it.
#[test]
fn references_hold_for_the_engines_f32_inputs() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("analytic/cases");
    let tol = lightproof::stats::exact_relative_tolerance();
    let mut bad = Vec::new();
    let mut checked = 0;
    let mut moved = 0;
    for f in collect_cases(&[root]).unwrap() {
        let case = Case::load(&f).unwrap();
        let Some(r) = case.reference else {
            continue;
        };
        checked += 1;
        let rho = case.reference_rounding.abs();
        moved += usize::from(rho > 0.0);
        let rel = if r == 0.0 { rho } else { rho / r.abs() };
        if rel.is_nan() || rel > tol {
            bad.push(format!(
                "{}: {r} moves by {rho:e} ({rel:.1e} relative) at the engine's f32 inputs",
                f.display()
            ));
        }
    }
    assert!(
        checked > 100 && moved > 10,
        "{checked} checked, {moved} moved"
    );
    assert!(
        bad.is_empty(),
        "references that the engine's f32 inputs change:\n{}",
        bad.join("\n")
    );
}
