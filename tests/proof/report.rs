//! Convergence reports (`lightproof report`, `lightproof merge`):
//!
//! - the fitted rate of a smooth integrand under independent sampling is −½ within its
//!   uncertainty, and Sobol's is clearly steeper;
//! - the shards of a sweep merge into exactly the single run's reports (and the thread
//!   count changes nothing): only timing fields may differ;
//! - a killed run leaves only whole, valid JSON, and a re-run resumes from it into the
//!   same reports as a fresh run; points another build made are never resumed;
//! - `--estimator` sweeps only the series of the estimators asked for, and exits 2 when no
//!   case names any of them;
//! - `reports/schema.json` validates every file a run writes and the committed examples;
//! - the shard comes from Slurm or Kubernetes variables as documented; bad input exits 2.
//!
//! Small sweeps (≤ 2^18 samples of a disk light): the whole file runs in a few seconds.

use crate::common;

use lightproof::report::shard::{Shard, merge, shard_from_env};
use lightproof::report::sweep::{Options, Summary, run};
use lightproof::report::{CaseReport, DEFAULT_MIN_SAMPLES};
use lightproof::sampling::SamplerKind;
use lightproof::transport::Estimator;
use serde_json::Value;
use statrs::distribution::{ContinuousCDF, StudentsT};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Family-wise significance of the statistical checks here (Šidák over [`FAMILY`]).
const ALPHA: f64 = 1e-4;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn disk_case() -> PathBuf {
    root().join("analytic/cases/irradiance/disk_on_axis.json")
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("lightproof-report-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A case without a reference (its reports fit the standard error), in `dir`.
fn no_reference_case(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(disk_case()).unwrap();
    let mut v: Value = serde_json::from_str(&text).unwrap();
    v.as_object_mut().unwrap().remove("reference");
    v["name"] = "disk light on axis, no reference".into();
    let p = dir.join("cases/disk_no_reference.json");
    std::fs::create_dir_all(p.parent().unwrap()).unwrap();
    std::fs::write(&p, serde_json::to_string_pretty(&v).unwrap()).unwrap();
    p
}

fn options(paths: Vec<PathBuf>, out: &Path, max: u64) -> Options {
    Options {
        paths,
        out: out.to_path_buf(),
        budget: None,
        min_samples: DEFAULT_MIN_SAMPLES,
        max_samples: max,
        seed: common::seed(),
        estimators: vec![],
        samplers: vec![],
        shard: None,
        fresh: false,
    }
}

fn sweep(opts: &Options) -> Summary {
    run(opts, &mut |_| {}).unwrap_or_else(|e| panic!("{e}"))
}

fn validator() -> jsonschema::Validator {
    let text = std::fs::read_to_string(root().join("reports/schema.json")).unwrap();
    let schema: Value = serde_json::from_str(&text).unwrap();
    jsonschema::validator_for(&schema).expect("reports/schema.json is a valid JSON Schema")
}

/// Every `.json` file in `dir` parses and validates; returns how many.
fn validate_dir(dir: &Path) -> usize {
    let v = validator();
    let mut n = 0;
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let p = e.path();
        if p.extension().is_some_and(|x| x == "json") {
            let text = std::fs::read_to_string(&p).unwrap();
            let value: Value = serde_json::from_str(&text)
                .unwrap_or_else(|err| panic!("{}: not JSON: {err}", p.display()));
            let errors: Vec<String> = v
                .iter_errors(&value)
                .map(|e| format!("{} at {}", e, e.instance_path()))
                .take(5)
                .collect();
            assert!(errors.is_empty(), "{}: {errors:#?}", p.display());
            n += 1;
        }
    }
    n
}

/// A report with the fields that depend on timing removed: every `seconds`,
/// `wall_seconds`, `fit_cost`, `fit_seconds`, `efficiency`, `seconds_per_sample`, `best`
/// (chosen by time) and the `run` record.
fn untimed(mut v: Value) -> Value {
    fn strip(v: &mut Value) {
        match v {
            Value::Object(m) => {
                for k in [
                    "seconds",
                    "wall_seconds",
                    "fit_cost",
                    "fit_seconds",
                    "efficiency",
                    "seconds_per_sample",
                    "best",
                    "run",
                ] {
                    m.remove(k);
                }
                m.values_mut().for_each(strip);
            }
            Value::Array(a) => a.iter_mut().for_each(strip),
            _ => {}
        }
    }
    strip(&mut v);
    v
}

fn read(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn case_reports(dir: &Path) -> BTreeMap<String, Value> {
    std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .map(|p| {
            let v = read(&p);
            (p, v)
        })
        .filter(|(_, v)| v["kind"] == "case")
        .map(|(p, v)| (p.file_name().unwrap().to_string_lossy().into_owned(), v))
        .collect()
}

/// The count of resumed points in `report`'s last stdout line (`…, N resumed`).
fn resumed_of(stdout: &str) -> u64 {
    stdout
        .split(" resumed")
        .next()
        .and_then(|s| s.rsplit(' ').next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no resume count in: {stdout}"))
}

/// The statistical decisions of this module, one Šidák family: the independent slope
/// against −½ and Sobol's against it (`independent_rate_is_minus_half_and_sobol_is_steeper`).
const FAMILY: usize = 2;

/// Two-sided critical value of Student's t with `dof` degrees of freedom at the per-test
/// level of `ALPHA` over the [`FAMILY`].
fn t_crit(dof: usize) -> f64 {
    let a = lightproof::stats::sidak_alpha(ALPHA, FAMILY);
    StudentsT::new(0.0, 1.0, dof as f64)
        .unwrap()
        .inverse_cdf(1.0 - a / 2.0)
}

#[test]
fn independent_rate_is_minus_half_and_sobol_is_steeper() {
    let out = tmp("rates");
    let mut opts = options(vec![disk_case()], &out, 1 << 18);
    opts.estimators = vec![Estimator::Light];
    opts.samplers = vec![SamplerKind::Independent, SamplerKind::Sobol];
    let s = sweep(&opts);
    let r: &CaseReport = &s.reports[0];
    let fit = |sampler| {
        r.series
            .iter()
            .find(|x| x.sampler == sampler)
            .and_then(|x| x.fit_samples)
            .unwrap()
    };
    let ind = fit(SamplerKind::Independent);
    let sob = fit(SamplerKind::Sobol);
    let (se_i, se_s) = (ind.slope_std_error.unwrap(), sob.slope_std_error.unwrap());
    let t = t_crit(ind.points - 2);
    println!(
        "disk light, light sampling, 2^8..2^18: independent slope {:.3} ± {:.3}, sobol {:.3} ± {:.3} (t crit {t:.2}, seed {})",
        ind.slope,
        se_i,
        sob.slope,
        se_s,
        common::seed()
    );
    // |b + 1/2| ≤ t·s_b: the fit's residuals give s_b (points are independent runs).
    assert!(
        (ind.slope + 0.5).abs() <= t * se_i,
        "independent slope {} ± {se_i} is not −0.5 (t = {t})",
        ind.slope
    );
    // Power: with s_b < 0.03 and t = 7.2 (9 degrees of freedom, α = 5·10⁻⁵ each), a
    // slope off −½ by (t + t₀.₉₅)·s_b < 0.28 is rejected 95% of the time (0.07 at the
    // default seed's s_b = 0.007): a wrong rate such as −⅓ or −1 is seen.
    assert!(se_i < 0.03, "the fit is too loose to mean anything: {se_i}");
    // Sobol: steeper than −½ beyond both uncertainties, and by a clear margin.
    assert!(
        ind.slope - sob.slope > t * (se_i * se_i + se_s * se_s).sqrt(),
        "sobol {} ± {se_s} vs independent {} ± {se_i}",
        sob.slope,
        ind.slope
    );
    assert!(sob.slope < -0.8, "sobol slope {}", sob.slope);
    // Time to 1% is measured for both, and Sobol gets there at least as cheaply in samples.
    for x in &r.series {
        assert!(!x.time_to[0].extrapolated && x.time_to[0].samples.is_some());
    }
    assert_eq!(validate_dir(&out), 2); // the report and index.json
    // The plot this sweep wrote has its three panels (not only the committed example).
    let svg = std::fs::read_to_string(out.join("disk_on_axis.svg")).unwrap();
    for panel in ["core-seconds (fitted", "samples N", "core-seconds to 0.1%"] {
        assert!(svg.contains(panel), "the plot lacks the panel `{panel}`");
    }
    assert!(
        std::fs::read_to_string(out.join("index.md"))
            .unwrap()
            .contains("disk_on_axis.svg")
    );
    let _ = std::fs::remove_dir_all(out);
}

#[test]
fn merged_shards_equal_the_single_run_whatever_the_threads() {
    let out = tmp("merge");
    let transient = root().join("analytic/cases/time/pulsed_disk_transient.json");
    let cases = vec![disk_case(), no_reference_case(&out), transient];
    let max = 1 << 12;
    // The single run, on one thread.
    let single = out.join("single");
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    pool.install(|| sweep(&options(cases.clone(), &single, max)));
    // Three shards on the default pool, then the merge.
    let shards = out.join("shards");
    for k in 0..3 {
        let mut o = options(cases.clone(), &shards, max);
        o.shard = Some(Shard { index: k, count: 3 });
        let s = sweep(&o);
        assert!(s.partial.is_some() && s.reports.is_empty());
    }
    let merged = out.join("merged");
    let m = merge(std::slice::from_ref(&shards), &merged, 2).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(m.reports.len(), 3);
    let a = case_reports(&single);
    let b = case_reports(&merged);
    assert_eq!(a.keys().collect::<Vec<_>>(), b.keys().collect::<Vec<_>>());
    assert_eq!(a.len(), 3);
    // A time-resolved case merges like any other; only a single run draws its plot.
    let plot = "pulsed_disk_transient.transient.svg";
    assert!(single.join(plot).is_file());
    assert!(!merged.join(plot).exists() && !shards.join(plot).exists());
    for (name, va) in &a {
        let vb = &b[name];
        assert_eq!(untimed(va.clone()), untimed(vb.clone()), "{name}");
        // Merged reports record each shard's run.
        assert_eq!(vb["run"]["shards"].as_array().unwrap().len(), 3);
        assert!(vb["series"][0]["points"][0]["wall_seconds"].is_null());
    }
    // Without a reference the fits use the standard error.
    let nr = &a["disk_no_reference.json"];
    assert_eq!(nr["error_measure"], "std_error");
    assert!(nr["series"][0]["points"][0]["rms_error"].is_null());
    for d in [&single, &shards, &merged] {
        assert!(validate_dir(d) >= 2, "{}", d.display());
    }
    // A missing shard is named; exit-2 input error, not a panic.
    std::fs::remove_file(shards.join("shard-1-of-3.json")).unwrap();
    let e = merge(std::slice::from_ref(&shards), &out.join("bad"), 1).unwrap_err();
    assert!(e.to_string().contains("missing shard(s) 1 of 3"), "{e}");
    let _ = std::fs::remove_dir_all(out);
}

/// A shard set tampered with is refused, naming the file and the field: a partial that
/// carries a batch another shard owns, a batch twice, a point seed that is not the one
/// its series seed gives, a series seed that differs between shards. Before, the merge
/// took the first file's copy of a batch and wrote a report no run computes.
#[test]
fn a_tampered_shard_set_is_refused_naming_file_and_field() {
    let out = tmp("tampered");
    let shards = out.join("shards");
    for k in 0..2 {
        let mut o = options(vec![disk_case()], &shards, 512);
        o.samplers = vec![SamplerKind::Independent];
        o.shard = Some(Shard { index: k, count: 2 });
        sweep(&o);
    }
    let name = |k: usize| format!("shard-{k}-of-2.json");
    let original: Vec<Value> = (0..2).map(|k| read(&shards.join(name(k)))).collect();
    merge(std::slice::from_ref(&shards), &out.join("ok"), 1).unwrap_or_else(|e| panic!("{e}"));
    let at = "cases[0].series[0]";
    fn points(v: &mut Value) -> &mut Vec<Value> {
        v["cases"][0]["series"][0]["points"][1]["batches"]
            .as_array_mut()
            .unwrap()
    }
    type Tamper = Box<dyn Fn(&mut [Value]) -> (usize, String, &'static str)>;
    let tampers: Vec<Tamper> = vec![
        // Shard 0 carries a batch of shard 1 (which has it too), with another mean.
        Box::new(move |v| {
            let mut b = points(&mut v[1])[0].clone();
            b["mean"] = (b["mean"].as_f64().unwrap() + 1.0).into();
            let p = points(&mut v[0]);
            p.push(b);
            let n = p.len() - 1;
            (0, format!("{at}.points[1].batches[{n}].batch"), "shard 1's")
        }),
        // Shard 0 carries one of its own batches twice.
        Box::new(move |v| {
            let p = points(&mut v[0]);
            p.push(p[0].clone());
            let n = p.len() - 1;
            (
                0,
                format!("{at}.points[1].batches[{n}].batch"),
                "present twice",
            )
        }),
        // Shard 1's point seed is not the one its series seed gives.
        Box::new(move |v| {
            let pt = &mut v[1]["cases"][0]["series"][0]["points"][1];
            pt["seed"] = (pt["seed"].as_u64().unwrap() ^ 1).into();
            (1, format!("{at}.points[1].seed"), "is not the seed")
        }),
        // Shard 1's series seed differs from shard 0's.
        Box::new(move |v| {
            let s = &mut v[1]["cases"][0]["series"][0];
            s["seed"] = (s["seed"].as_u64().unwrap() ^ 1).into();
            (1, format!("{at}.seed"), "series seed")
        }),
        // Shard 1 was built in another cargo profile (`fast` runs 6–14% faster than
        // `release` from the same revision).
        Box::new(move |v| {
            v[1]["run"]["profile"] = "another-profile".into();
            (1, "run.profile".to_string(), "another-profile profile")
        }),
    ];
    let mut wrong = vec![];
    for (i, tamper) in tampers.iter().enumerate() {
        let dir = out.join(format!("t{i}"));
        std::fs::create_dir_all(&dir).unwrap();
        let mut v = original.clone();
        let (file, field, reason) = tamper(&mut v);
        for (k, x) in v.iter().enumerate() {
            std::fs::write(dir.join(name(k)), serde_json::to_string(x).unwrap()).unwrap();
        }
        let path = dir.join(name(file)).display().to_string();
        match merge(std::slice::from_ref(&dir), &out.join("bad"), 1) {
            Ok(_) => wrong.push(format!("tamper {i}: merged")),
            Err(e) => {
                let e = e.to_string();
                if !(e.contains(&path) && e.contains(&field) && e.contains(reason)) {
                    wrong.push(format!(
                        "tamper {i}: expected {path}, {field}, `{reason}` in: {e}"
                    ));
                }
            }
        }
    }
    assert!(wrong.is_empty(), "{wrong:#?}");
    // The command exits 2 with the file and field on one line.
    let o = Command::new(env!("CARGO_BIN_EXE_lightproof"))
        .args(["merge", out.join("t0").to_str().unwrap(), "--out"])
        .arg(out.join("bad"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("shard-0-of-2.json") && err.contains("batches["),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(out);
}

/// A rerun with a larger `--max-samples` resumes a shard's partial as it does a single
/// run's reports (before, the plan digest held the settings, so the shard ran afresh);
/// so does one with another `--min-samples`; a narrower rerun says on stderr how many
/// earlier points and series it drops from what it writes.
#[test]
fn a_shard_extends_and_a_narrower_rerun_says_what_it_drops() {
    let out = tmp("extend");
    let dropped = |s: &Summary| -> Vec<String> {
        s.notes
            .iter()
            .filter(|n| n.contains("dropped"))
            .cloned()
            .collect()
    };
    let shard_from = |min: u64, max: u64| {
        let mut o = options(vec![disk_case()], &out.join("shard"), max);
        (o.samplers, o.estimators) = (vec![SamplerKind::Independent], vec![Estimator::Light]);
        o.min_samples = min;
        o.shard = Some(Shard { index: 0, count: 2 });
        sweep(&o)
    };
    let shard = |max: u64| shard_from(DEFAULT_MIN_SAMPLES, max);
    assert_eq!(DEFAULT_MIN_SAMPLES, 256);
    let s = shard(512);
    assert_eq!((s.computed, s.resumed), (2, 0));
    let s = shard(1024);
    assert_eq!((s.computed, s.resumed), (1, 2), "{:?}", s.notes);
    assert!(dropped(&s).is_empty(), "{:?}", s.notes);
    // Another `--min-samples` resumes too: the points of 512 and 1024 are kept and the
    // one of 256, now below the sweep, is dropped with a note.
    let s = shard_from(512, 1024);
    assert_eq!((s.computed, s.resumed), (0, 2), "{:?}", s.notes);
    let d = dropped(&s);
    assert!(
        d.len() == 1 && d[0].contains("1 earlier point(s), 0 whole series"),
        "{d:?}"
    );
    let s = shard(256);
    assert_eq!((s.computed, s.resumed), (1, 0), "{:?}", s.notes);
    let d = dropped(&s);
    assert!(
        d.len() == 1 && d[0].contains("2 earlier point(s), 0 whole series"),
        "{d:?}"
    );
    // A partial of another build, machine or shard (its own record, whatever its file
    // name) runs afresh, saying so; the untouched partial resumes whole.
    let file = out.join("shard/shard-0-of-2.json");
    let s = shard(512);
    assert_eq!((s.computed, s.resumed), (1, 1), "{:?}", s.notes);
    for (field, other) in [
        ("/run/git_revision", Value::from("another-revision")),
        ("/run/profile", Value::from("another-profile")),
        ("/run/machine/cpu", Value::from("another CPU")),
        ("/shard/index", Value::from(1)),
    ] {
        let mut v = read(&file);
        *v.pointer_mut(field).unwrap() = other;
        std::fs::write(&file, serde_json::to_string_pretty(&v).unwrap()).unwrap();
        let s = shard(512);
        assert_eq!((s.computed, s.resumed), (2, 0), "{field}: {:?}", s.notes);
        assert!(
            s.notes
                .iter()
                .any(|n| n.contains("another sweep, build or machine; run afresh")),
            "{field}: {:?}",
            s.notes
        );
    }
    assert_eq!(shard(512).resumed, 2);
    // A single run: two samplers to 512, then one sampler to 256 drops the other
    // sampler's series (2 points) and the kept series' point of 512.
    let single = |max: u64, samplers: Vec<SamplerKind>| {
        let mut o = options(vec![disk_case()], &out.join("single"), max);
        (o.samplers, o.estimators) = (samplers, vec![Estimator::Light]);
        sweep(&o)
    };
    single(512, vec![SamplerKind::Independent, SamplerKind::Sobol]);
    let s = single(256, vec![SamplerKind::Independent]);
    assert_eq!((s.computed, s.resumed), (0, 1), "{:?}", s.notes);
    let d = dropped(&s);
    assert!(
        d.len() == 1 && d[0].contains("3 earlier point(s), 1 whole series"),
        "{d:?}"
    );
    assert_eq!(s.reports[0].series.len(), 1);
    let _ = std::fs::remove_dir_all(out);
}

#[test]
fn a_killed_run_leaves_valid_json_and_resumes() {
    let out = tmp("killed");
    let reports = out.join("reports");
    let case = disk_case();
    let args_seeded = |max: u64, dir: &Path, seed: u64| {
        let mut c = Command::new(env!("CARGO_BIN_EXE_lightproof"));
        c.arg("report")
            .arg(&case)
            .args(["--sampler", "independent", "--sampler", "sobol"])
            .args(["--max-samples", &max.to_string()])
            .args(["--seed", &seed.to_string()])
            .arg("--out")
            .arg(dir);
        c
    };
    let args = |max: u64, dir: &Path| args_seeded(max, dir, common::seed());
    // A sweep to 2^30 samples cannot finish; kill it once it has written a report.
    let mut child = args(1 << 30, &reports)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let t0 = Instant::now();
    let file = reports.join("disk_on_axis.json");
    // A guard against a sweep that never writes, not a speed limit (the first report
    // comes within a second on an idle core).
    while !file.exists() && t0.elapsed() < Duration::from_secs(600) {
        std::thread::sleep(Duration::from_millis(20));
    }
    // Let it run on a little, so that the kill can land in the middle of a write.
    std::thread::sleep(Duration::from_millis(1500));
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(file.exists(), "no report written in ten minutes");
    assert!(validate_dir(&reports) >= 1);
    let killed = read(&file);
    let done: usize = killed["series"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["points"].as_array().unwrap().len())
        .sum();
    assert!(done >= 1);
    assert!(
        killed["series"]
            .as_array()
            .unwrap()
            .iter()
            .all(|s| s["status"] == "in_progress")
    );
    // Re-run to 2^14: what the killed run finished is taken back, the rest computed.
    let o = args(1 << 14, &reports).output().unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{stdout}");
    let resumed = resumed_of(&stdout);
    assert!(resumed >= 1, "{stdout}");
    // The same reports as a fresh run.
    let fresh = out.join("fresh");
    assert!(args(1 << 14, &fresh).output().unwrap().status.success());
    assert_eq!(
        untimed(read(&file)),
        untimed(read(&fresh.join("disk_on_axis.json")))
    );
    assert!(validate_dir(&reports) >= 2);
    // Resuming keeps points only of the same case and seed, and `--fresh` none: the
    // same run again resumes every point it holds; another seed or `--fresh`, none.
    let run = |c: &mut Command| {
        let o = c.output().unwrap();
        let stdout = String::from_utf8_lossy(&o.stdout).into_owned();
        assert!(o.status.success(), "{stdout}");
        resumed_of(&stdout)
    };
    let all: u64 = read(&file)["series"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["points"].as_array().unwrap().len() as u64)
        .sum();
    assert_eq!(run(&mut args(1 << 14, &reports)), all);
    assert_eq!(run(args(1 << 14, &reports).arg("--fresh")), 0);
    assert_eq!(
        run(&mut args_seeded(1 << 14, &reports, common::seed() ^ 0x5eed)),
        0
    );
    // A changed case (same file name and id, another description) resumes nothing
    // either: its points were drawn for another integral.
    let changed = out.join("changed");
    std::fs::create_dir_all(&changed).unwrap();
    let copy = changed.join("disk_on_axis.json");
    let text = std::fs::read_to_string(&case).unwrap();
    std::fs::write(&copy, &text).unwrap();
    let in_changed = |c: &Path| {
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_lightproof"));
        cmd.arg("report")
            .arg(c)
            .args(["--max-samples", "4096", "--seed", "7", "--out"])
            .arg(changed.join("reports"));
        cmd
    };
    run(&mut in_changed(&copy));
    assert!(run(&mut in_changed(&copy)) > 0, "the same case resumes");
    // The emitter and its reference twice as bright.
    let brighter = text.replace("\"radiance\": 1 }", "\"radiance\": 2 }");
    assert_eq!(brighter.matches("\"radiance\": 2 }").count(), 2);
    std::fs::write(&copy, brighter).unwrap();
    assert_eq!(
        run(&mut in_changed(&copy)),
        0,
        "a changed case resumes nothing"
    );
    let _ = std::fs::remove_dir_all(out);
}

/// A report records the instruction set its ray queries ran in (the same answers, not the
/// same speed): `baseline` under `LIGHTPROOF_ISA=baseline`, else the CPU's own choice,
/// in the case's report, the index and the index page's line about the run.
#[test]
fn a_report_records_the_instruction_set_of_its_ray_queries() {
    use lightproof::scene::accel::Isa;
    for (env, want) in [(Some("baseline"), Isa::Baseline), (None, Isa::supported())] {
        let out = tmp(&format!("isa-{}", want.name()));
        let mut c = Command::new(env!("CARGO_BIN_EXE_lightproof"));
        c.arg("report")
            .arg(disk_case())
            .args(["--estimator", "light", "--sampler", "independent"])
            .args(["--max-samples", "1024"])
            .arg("--out")
            .arg(&out)
            .env_remove("LIGHTPROOF_ISA");
        if let Some(v) = env {
            c.env("LIGHTPROOF_ISA", v);
        }
        let o = c.output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        for file in ["disk_on_axis.json", "index.json"] {
            let v: Value =
                serde_json::from_str(&std::fs::read_to_string(out.join(file)).unwrap()).unwrap();
            assert_eq!(v["run"]["machine"]["ray_isa"], want.name(), "{file}");
        }
        let report: Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("disk_on_axis.json")).unwrap())
                .unwrap();
        assert!(validator().is_valid(&report));
        let page = std::fs::read_to_string(out.join("index.md")).unwrap();
        assert!(
            page.contains(&format!("logical cores; ray queries in {})", want.name())),
            "{page}"
        );
        let _ = std::fs::remove_dir_all(&out);
    }
}

/// `report` resumes only the points of its own build and machine (README: "same case,
/// seed, build and machine"). The same run again takes back every point; after the stored
/// report's revision, version or profile, or its machine's CPU, system, architecture or
/// `ray_isa`, is changed to another's, it takes back none, says why, and the report it
/// writes records this build. Fails if `same_build` or `same_machine` accepts any other.
#[test]
fn points_of_another_build_are_not_resumed() {
    use lightproof::report::machine::{GIT_REVISION, PROFILE, VERSION};
    let out = tmp("build");
    let file = out.join("disk_on_axis.json");
    let report = || {
        let o = Command::new(env!("CARGO_BIN_EXE_lightproof"))
            .arg("report")
            .arg(disk_case())
            .args(["--estimator", "light", "--sampler", "independent"])
            .args([
                "--max-samples",
                "4096",
                "--seed",
                &common::seed().to_string(),
            ])
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&o.stdout).into_owned();
        let stderr = String::from_utf8_lossy(&o.stderr).into_owned();
        assert!(o.status.success(), "{stdout}{stderr}");
        (resumed_of(&stdout), stderr)
    };
    let points = |v: &Value| -> u64 {
        v["series"]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| s["points"].as_array().unwrap().len() as u64)
            .sum()
    };
    assert_eq!(report().0, 0);
    let all = points(&read(&file));
    assert_eq!(all, 5, "2^8..2^12, one series");
    // The control: as written, the report is this build's and resumes whole.
    assert_eq!(report().0, all);
    // A build differs in its version, revision or cargo profile (`fast` and `release`
    // share a revision, not a speed); a machine in its CPU model, system or the
    // instruction set of its ray queries (session 56's audit: a resumed run fitted 15
    // points timed in `baseline` on one thread with 3 of its own in x86-64-v3).
    let build = "another build of lightproof";
    let machine = "timed on another machine or instruction set";
    for (field, other, why) in [
        (
            "/run/git_revision",
            "0123456789abcdef0123456789abcdef01234567-dirty-0123456789abcdef",
            build,
        ),
        ("/run/lightproof_version", "0.0.0-another-build", build),
        ("/run/profile", "another-profile", build),
        ("/run/machine/cpu", "another CPU", machine),
        ("/run/machine/os", "another-os", machine),
        ("/run/machine/arch", "another-arch", machine),
        ("/run/machine/ray_isa", "another-isa", machine),
    ] {
        let mut v = read(&file);
        let at = v
            .pointer_mut(field)
            .unwrap_or_else(|| panic!("no {field} in the report"));
        assert!(at.is_string() && *at != other, "{field}: {at}");
        *at = other.into();
        std::fs::write(&file, serde_json::to_string_pretty(&v).unwrap()).unwrap();
        let (resumed, stderr) = report();
        assert_eq!(resumed, 0, "points of another {field} were resumed");
        assert!(stderr.contains(why), "{field}: {stderr}");
        let now = read(&file);
        assert_eq!(now["run"]["git_revision"], GIT_REVISION);
        assert_eq!(now["run"]["lightproof_version"], VERSION);
        assert_eq!(now["run"]["profile"], PROFILE);
        assert_eq!(now["run"]["points_resumed"], 0);
        assert_eq!(now["run"]["points_computed"], all);
        assert_eq!(points(&now), all);
    }
    // A merged report's points were timed by its shards: one shard timed on another CPU
    // (or built in another profile) makes the folder another machine's.
    for (field, other) in [
        ("/machine/cpu", "another CPU"),
        ("/profile", "another-profile"),
    ] {
        let mut v = read(&file);
        let mut shard_run = v["run"].clone();
        *shard_run.pointer_mut(field).unwrap() = other.into();
        let here = v["run"].clone();
        v["run"]["shards"] = serde_json::json!([
            { "index": 0, "count": 2, "run": here },
            { "index": 1, "count": 2, "run": shard_run },
        ]);
        std::fs::write(&file, serde_json::to_string_pretty(&v).unwrap()).unwrap();
        let (resumed, stderr) = report();
        assert_eq!(resumed, 0, "a shard's {field} was not checked");
        assert!(stderr.contains(machine), "{field}: {stderr}");
    }
    // Another thread count or number of logical cores is the same machine: core-seconds
    // do not depend on them.
    let mut v = read(&file);
    v["run"]["threads"] = 7.into();
    v["run"]["machine"]["logical_cores"] = 7.into();
    std::fs::write(&file, serde_json::to_string_pretty(&v).unwrap()).unwrap();
    assert_eq!(report().0, all);
    assert!(validate_dir(&out) >= 2);
    let _ = std::fs::remove_dir_all(out);
}

/// `report --estimator E` (repeatable) sweeps the series of the estimators asked for that
/// the case names, with every sampler asked for, and none of the case's other estimators;
/// when no case names any of them it exits 2 with one line, "nothing to run", and writes
/// no report.
#[test]
fn the_estimator_filter_runs_only_its_series() {
    let out = tmp("estimator");
    let report = |dir: &Path, estimators: &[&str]| {
        let mut c = Command::new(env!("CARGO_BIN_EXE_lightproof"));
        c.arg("report")
            .arg(disk_case())
            .args(["--sampler", "independent", "--sampler", "sobol"])
            .args(["--max-samples", "1024", "--out"])
            .arg(dir);
        for e in estimators {
            c.args(["--estimator", e]);
        }
        c.output().unwrap()
    };
    let series = |dir: &Path, estimators: &[&str]| -> Vec<(String, String)> {
        let o = report(dir, estimators);
        assert!(
            o.status.success(),
            "{estimators:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        let mut s: Vec<(String, String)> = read(&dir.join("disk_on_axis.json"))["series"]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| {
                (
                    s["estimator"].as_str().unwrap().to_string(),
                    s["sampler"].as_str().unwrap().to_string(),
                )
            })
            .collect();
        s.sort();
        s
    };
    let pairs = |estimators: &[&str]| -> Vec<(String, String)> {
        let mut p: Vec<(String, String)> = estimators
            .iter()
            .flat_map(|e| ["independent", "sobol"].map(|s| (e.to_string(), s.to_string())))
            .collect();
        p.sort();
        p
    };
    // The case names light, mis and mis_balance, not bsdf; unfiltered, all three run.
    let case = read(&disk_case());
    assert_eq!(
        case["estimators"],
        serde_json::json!(["light", "mis", "mis_balance"])
    );
    assert_eq!(
        series(&out.join("all"), &[]),
        pairs(&["light", "mis", "mis_balance"])
    );
    assert_eq!(series(&out.join("mis"), &["mis"]), pairs(&["mis"]));
    // Estimators the case does not name are skipped, the others run.
    assert_eq!(
        series(&out.join("two"), &["mis_balance", "bsdf", "light"]),
        pairs(&["light", "mis_balance"])
    );
    // Nothing left to run: input error, exit 2, one line, no report.
    let none = out.join("none");
    let o = report(&none, &["bsdf", "uniform"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("nothing to run"), "{err}");
    assert!(err.contains("--estimator"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    assert!(!none.join("disk_on_axis.json").exists());
    let _ = std::fs::remove_dir_all(out);
}

#[test]
fn the_budget_cuts_cleanly() {
    let out = tmp("budget");
    let mut o = options(vec![disk_case()], &out, 1 << 30);
    o.budget = Some(0.3);
    o.samplers = vec![SamplerKind::Independent];
    let s = sweep(&o);
    assert!(s.budget_cut);
    let r = &s.reports[0];
    assert!(r.run.budget_cut);
    assert!(
        r.series
            .iter()
            .all(|x| x.status == lightproof::report::Status::BudgetCut && !x.points.is_empty())
    );
    // What the budget cut, by count rather than by a clock: no series reached 2³⁰.
    assert!(
        r.series
            .iter()
            .all(|x| x.points.iter().all(|p| p.samples < 1 << 30))
    );
    // Not reached targets are extrapolated from the fit, and say so.
    let last = r.series[0].time_to.last().unwrap();
    assert!(last.extrapolated || last.samples.is_some());
    assert!(validate_dir(&out) >= 2);
    let _ = std::fs::remove_dir_all(&out);
    // A budget already spent before the first point (a large catalog's loading once was):
    // every series still gets its first point, predicted free, and nothing more.
    o.budget = Some(1e-9);
    o.fresh = true;
    let s = sweep(&o);
    assert!(s.budget_cut);
    assert!(s.reports[0].series.iter().all(|x| x.points.len() == 1));
    let _ = std::fs::remove_dir_all(out);
}

#[test]
fn the_schema_validates_the_committed_examples_and_rejects_a_broken_report() {
    let examples = root().join("reports/examples");
    assert!(
        validate_dir(&examples) >= 2,
        "reports/examples holds a report and an index"
    );
    let v = validator();
    let report = std::fs::read_dir(&examples)
        .unwrap()
        .flatten()
        .map(|e| read(&e.path()))
        .find(|v| v.get("kind").is_some_and(|k| k == "case"))
        .expect("an example case report");
    // The cost model: every series has a cost line, so fitted times grow with N and no
    // curve of the plot runs backwards; the plot has its three panels.
    for s in report["series"].as_array().unwrap() {
        let c = &s["fit_cost"];
        assert!(c["per_sample"].as_f64().unwrap() > 0.0, "{s}");
        assert!(c["t0"].as_f64().unwrap() >= 0.0, "{s}");
    }
    let svg = std::fs::read_to_string(examples.join("disk_on_axis.svg")).unwrap();
    for panel in ["core-seconds (fitted", "samples N", "core-seconds to 0.1%"] {
        assert!(svg.contains(panel), "the plot lacks the panel `{panel}`");
    }
    let mut broken = report.clone();
    broken["series"][0]["fit_cost"]["per_sample"] = (-1.0).into();
    assert!(!v.is_valid(&broken));
    let mut broken = report.clone();
    broken["series"][0]["points"][0]
        .as_object_mut()
        .unwrap()
        .remove("std_error");
    assert!(!v.is_valid(&broken));
    let mut broken = report;
    broken["series"][0]["sampler"] = "halton".into();
    assert!(!v.is_valid(&broken));
}

#[test]
fn shards_from_slurm_and_kubernetes() {
    let env = |pairs: &[(&str, &str)]| -> BTreeMap<String, String> {
        pairs
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect()
    };
    // sbatch --array=1-4: tasks 1..4 are shards 0..3.
    let slurm = env(&[
        ("SLURM_ARRAY_TASK_ID", "4"),
        ("SLURM_ARRAY_TASK_MIN", "1"),
        ("SLURM_ARRAY_TASK_MAX", "4"),
        ("SLURM_ARRAY_TASK_COUNT", "4"),
    ]);
    assert_eq!(
        shard_from_env(&slurm).unwrap(),
        Shard { index: 3, count: 4 }
    );
    // Indexed Job with completions: 6.
    let k8s = env(&[
        ("JOB_COMPLETION_INDEX", "0"),
        ("LIGHTPROOF_SHARD_COUNT", "6"),
    ]);
    assert_eq!(shard_from_env(&k8s).unwrap(), Shard { index: 0, count: 6 });
    assert!(shard_from_env(&env(&[("JOB_COMPLETION_INDEX", "0")])).is_err());
    assert!(shard_from_env(&env(&[])).is_err());
}

#[test]
fn bad_input_exits_2_with_one_line() {
    let bad = |args: &[&str], needle: &str| {
        let o = Command::new(env!("CARGO_BIN_EXE_lightproof"))
            .args(args)
            .env_remove("SLURM_ARRAY_TASK_ID")
            .env_remove("JOB_COMPLETION_INDEX")
            .env_remove("LIGHTPROOF_SHARD_INDEX")
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(
            err.contains(needle),
            "{args:?}: expected `{needle}` in {err}"
        );
        assert!(!err.contains("panicked"), "{err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        err.into_owned()
    };
    let out = tmp("bad");
    let o = out.to_str().unwrap();
    let case = disk_case();
    let c = case.to_str().unwrap();
    bad(
        &["report", c, "--out", o, "--min-samples", "100"],
        "--min-samples",
    );
    bad(
        &["report", c, "--out", o, "--max-samples", "200"],
        "--max-samples",
    );
    bad(&["report", c, "--out", o, "--budget=-1"], "--budget");
    bad(&["report", c, "--out", o, "--shard", "3/3"], "--shard");
    bad(
        &["report", c, "--out", o, "--shard", "auto"],
        "--shard auto",
    );
    bad(
        &["report", "no/such/case.json", "--out", o],
        "no/such/case.json",
    );
    // Each message is true of the command: `report` rounds to powers of two (`verify`
    // and `estimate` to multiples of 128); an empty folder given to `merge` is named; a
    // file that is not a partial gets advice about merge's input, not about --out.
    bad(
        &["report", c, "--out", o, "--max-samples", "255"],
        "rounded down to a power of two",
    );
    bad(
        &["report", c, "--out", o, "--min-samples", "255"],
        "rounded up to a power of two",
    );
    bad(
        &["verify", c, "--samples", "255"],
        "rounded up to a multiple of 128",
    );
    bad(
        &["merge", o, "--out", o],
        &format!("{o}: no shard partial files"),
    );
    let err = bad(&["merge", c, "--out", o], "`report --shard K/N` writes");
    assert!(!err.contains("--out"), "{err}");
    // A foreign file where a report would go is not overwritten.
    std::fs::write(out.join("disk_on_axis.json"), "{\"mine\": true}").unwrap();
    bad(&["report", c, "--out", o], "not a lightproof report file");
    let _ = std::fs::remove_dir_all(out);
}

/// The revision a report records (and `report` resumes by) marks a build from sources
/// that differ from the commit: `SHA` exactly when the sources it stands for are as
/// committed, `SHA-dirty-DIGEST` otherwise, `unknown-DIGEST` without git; so a resumed
/// sweep never takes points from an uncommitted build for this one's.
#[test]
fn the_revision_marks_an_uncommitted_build() {
    use lightproof::report::machine::{GIT_REVISION, SOURCES};
    // Set by hand at build time (a source archive's container), it is taken as given.
    if let Some(given) = std::env::var("LIGHTPROOF_GIT_REVISION")
        .ok()
        .filter(|s| !s.is_empty())
    {
        assert_eq!(GIT_REVISION, given);
        return;
    }
    let git = |args: &[&str]| {
        Command::new("git")
            .args(args)
            .current_dir(root())
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    let digest = |s: &str| s.len() == 16 && s.bytes().all(|b| b.is_ascii_hexdigit());
    let Some(head) = git(&["rev-parse", "HEAD"]) else {
        let d = GIT_REVISION.strip_prefix("unknown-");
        assert!(d.is_some_and(digest), "{GIT_REVISION}");
        return;
    };
    let mut status = vec!["status", "--porcelain", "--"];
    status.extend(SOURCES.split(' '));
    let changed = git(&status).expect("git status");
    if changed.is_empty() {
        assert_eq!(GIT_REVISION, head);
    } else {
        let d = GIT_REVISION.strip_prefix(&format!("{head}-dirty-"));
        assert!(
            d.is_some_and(digest),
            "{GIT_REVISION} for a tree with\n{changed}"
        );
    }
}

/// A case with nothing to plot (an exact one: zero error at every point) gets `plot:
/// null`, a note saying why, and no SVG, even where an earlier run left one; a sampler
/// asked for twice is one series.
#[test]
fn an_exact_case_has_no_plot_and_no_stale_one() {
    let out = tmp("noplot");
    std::fs::create_dir_all(&out).unwrap();
    let stale = out.join("disk_behind.svg");
    std::fs::write(&stale, "<svg>an earlier run's</svg>").unwrap();
    let mut o = options(
        vec![root().join("analytic/cases/intensity/disk_behind.json")],
        &out,
        1024,
    );
    o.samplers = vec![SamplerKind::Sobol, SamplerKind::Sobol];
    let s = sweep(&o);
    assert!(
        !stale.exists(),
        "the stale plot is left beside a report without one"
    );
    assert_eq!(s.reports[0].plot, None);
    assert_eq!(s.reports[0].series.len(), 1, "one series per sampler");
    assert!(
        s.notes
            .iter()
            .any(|n| n.starts_with("disk_behind: no plot (")),
        "{:?}",
        s.notes
    );
    assert!(validate_dir(&out) >= 2);
    let _ = std::fs::remove_dir_all(out);
}

/// The transient plot draws the case's first estimator and first sampler whatever
/// `--estimator` / `--sampler` select (README, "Wavelength and time"): a run restricted to
/// `mis` (the case's second estimator) writes the same plot, byte for byte, as one
/// unrestricted.
#[test]
fn the_transient_plot_ignores_the_series_filters() {
    let out = tmp("transient-filters");
    let transient = root().join("analytic/cases/time/pulsed_disk_transient.json");
    let plot = "pulsed_disk_transient.transient.svg";
    let all = out.join("all");
    sweep(&options(vec![transient.clone()], &all, 1 << 10));
    let some = out.join("mis");
    let mut o = options(vec![transient], &some, 1 << 10);
    o.estimators = vec![Estimator::Mis];
    o.samplers = vec![SamplerKind::Sobol];
    sweep(&o);
    let (a, b) = (
        std::fs::read(all.join(plot)).unwrap(),
        std::fs::read(some.join(plot)).unwrap(),
    );
    assert!(a == b, "the transient plot changed with the series filters");
    let _ = std::fs::remove_dir_all(out);
}

/// A reference 0.3% off (the disk light's radiance written 1.003): Sobol sampling's
/// error falls to 10⁻⁵ by 2¹⁶ samples, so every point from a few thousand samples on
/// establishes the bias. The report gives no time to 0.1% or 0.01% (session 56's audit:
/// a sweep whose error fell and flattened at 0.2% was given 0.1% at 1.5·10⁵ samples),
/// records the floor, names no best series, and the index says "never: biased ≥ 0.29%"
/// (the floor as a percentage rounded down, being a lower bound).
/// The floor is a lower bound on |bias|/|ref| = 0.003/1.003 by construction (z σ̂ below
/// it), and with σ̂ ≤ 10⁻⁵ at the largest point it lies within 10⁻⁴ of it.
#[test]
fn a_biased_reference_gets_no_time_below_its_bias() {
    let out = tmp("biased");
    let text = std::fs::read_to_string(disk_case()).unwrap();
    let mut v: Value = serde_json::from_str(&text).unwrap();
    v["reference"]["radiance"] = 1.003.into();
    let case = out.join("cases/disk_off.json");
    std::fs::create_dir_all(case.parent().unwrap()).unwrap();
    std::fs::write(&case, serde_json::to_string_pretty(&v).unwrap()).unwrap();
    let mut opts = options(vec![case], &out.join("r"), 1 << 16);
    opts.estimators = vec![Estimator::Light];
    opts.samplers = vec![SamplerKind::Sobol];
    let s = sweep(&opts);
    let series = &s.reports[0].series[0];
    let bias = 0.003 / 1.003;
    let floor = series
        .bias_floor
        .expect("no bias floor for a reference 0.3% off");
    assert!(
        floor <= bias && floor > bias - 1e-4,
        "{floor} against {bias}"
    );
    assert!(series.time_to[0].seconds.is_some(), "{:?}", series.time_to);
    for t in &series.time_to[1..] {
        assert_eq!((t.samples, t.seconds), (None, None), "{t:?}");
    }
    assert!(s.reports[0].best.is_none());
    let index = read(&out.join("r/index.json"));
    let f = index["cases"][0]["bias_floor"].as_f64().unwrap();
    assert_eq!(f, floor);
    let md = std::fs::read_to_string(out.join("r/index.md")).unwrap();
    let shown = format!("never: biased ≥ {:.2}%", (floor * 1e4).floor() / 1e2);
    assert!(md.contains(&shown), "{shown} not in {md}");
    // The plot draws the floor and names it, and its ranking panel says why it is empty.
    let svg = std::fs::read_to_string(out.join("r/disk_off.svg")).unwrap();
    let label = format!("light / sobol (bias ≥ {:.2}%)", (floor * 1e4).floor() / 1e2);
    assert!(svg.contains(&label), "{label} not in the plot");
    assert!(
        svg.contains("each is biased beyond it"),
        "the ranking panel"
    );
    assert_eq!(validate_dir(&out.join("r")), 2);
    let _ = std::fs::remove_dir_all(out);
}
