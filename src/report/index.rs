//! The index of a report folder: `index.json` and `index.md`, one row per case report
//! (those of this run plus those an earlier index listed whose files are still there),
//! so a person sees at a glance what 0.1% accuracy costs and which estimator buys it.

use super::store::{read_case_report, report_file, write_bytes, write_json};
use super::{CaseReport, FORMAT, HEADLINE, Index, IndexBest, IndexRow, Kind, Status};
use crate::error::{Error, parse_json};
use std::collections::BTreeMap;
use std::path::Path;

/// The index row of a report.
pub fn row(r: &CaseReport) -> IndexRow {
    let best = r.best.as_ref().map(|b| {
        let s = r
            .series
            .iter()
            .find(|s| s.estimator == b.estimator && s.sampler == b.sampler);
        let fit = s.and_then(|s| s.fit_samples);
        IndexBest {
            estimator: b.estimator,
            sampler: b.sampler,
            seconds: b.seconds,
            extrapolated: b.extrapolated,
            slope: fit.map(|f| f.slope),
            slope_std_error: fit.and_then(|f| f.slope_std_error),
            runner_up_ratio: b
                .others
                .iter()
                .filter_map(|o| o.time_ratio)
                .min_by(|a, b| a.total_cmp(b)),
            zero_variance: s.is_some_and(|s| {
                !s.points.is_empty() && s.points.iter().all(|p| p.std_error == Some(0.0))
            }),
            bias_floor: s.and_then(|s| s.bias_floor),
        }
    });
    let floors: Option<Vec<f64>> = r.series.iter().map(|s| s.bias_floor).collect();
    IndexRow {
        id: r.id.clone(),
        name: r.case.name.clone(),
        report: report_file(&r.id),
        plot: r.plot.clone(),
        seed: r.settings.seed,
        complete: r.series.iter().all(|s| s.status == Status::Complete),
        best,
        bias_floor: floors.and_then(|f| f.into_iter().min_by(f64::total_cmp)),
    }
}

/// Rewrite `index.json` and `index.md` in `out` with `reports` and the rows of the
/// previous index whose reports are still there.
pub fn update(out: &Path, reports: &[CaseReport]) -> Result<Index, Error> {
    let mut rows: BTreeMap<String, IndexRow> = BTreeMap::new();
    let path = out.join("index.json");
    if let Ok(text) = std::fs::read_to_string(&path)
        && let Ok(old) = parse_json::<Index>(&path.display().to_string(), &text)
        && old.format == FORMAT
    {
        for r in old.cases {
            if let Ok(Some(rep)) = read_case_report(&out.join(&r.report)) {
                rows.insert(rep.id.clone(), row(&rep));
            }
        }
    }
    for r in reports {
        rows.insert(r.id.clone(), row(r));
    }
    let run = match reports.first() {
        Some(r) => r.run.clone(),
        None => super::machine::run_info(rayon::current_num_threads(), None),
    };
    let index = Index {
        format: FORMAT.to_string(),
        kind: Kind::Index,
        run,
        cases: rows.into_values().collect(),
    };
    write_json(&path, &index, true)?;
    write_bytes(&out.join("index.md"), markdown(&index).as_bytes())?;
    Ok(index)
}

/// Seconds in a short human form.
pub fn duration(s: f64) -> String {
    if s < 1e-3 {
        format!("{:.0} µs", s * 1e6)
    } else if s < 1.0 {
        format!("{:.1} ms", s * 1e3)
    } else if s < 120.0 {
        format!("{s:.2} s")
    } else if s < 7200.0 {
        format!("{:.1} min", s / 60.0)
    } else if s < 48.0 * 3600.0 {
        format!("{:.1} h", s / 3600.0)
    } else {
        format!("{:.1} days", s / 86400.0)
    }
}

/// A relative bias floor as a percentage with two decimals, rounded down: it is a lower
/// bound, and "≥ 0.30%" for a floor of 0.2995% would overstate it. The product b·10⁴ is
/// nudged up by 10⁻¹² of itself first, so that a floor of exactly 0.29% (0.0029 ·
/// 10⁴ = 28.999999999999996 in binary) reads 0.29%, not 0.28%.
pub fn percent_at_least(b: f64) -> String {
    format!("{:.2}%", (b * 1e4 * (1.0 + 1e-12)).floor() / 1e2)
}

/// The cells of one index row: best, time to 0.1%, slope, runner-up ratio.
pub fn cells(r: &IndexRow) -> [String; 4] {
    match &r.best {
        None => [
            "—".into(),
            r.bias_floor.map_or("—".into(), |b| {
                format!("never: biased ≥ {}", percent_at_least(b))
            }),
            "—".into(),
            "—".into(),
        ],
        Some(b) => [
            format!("{} / {}", b.estimator.name(), b.sampler.name()),
            match b.seconds {
                Some(t) if b.extrapolated => format!("~{} (extrapolated)", duration(t)),
                Some(t) => duration(t),
                None => "not reached".into(),
            },
            match (b.slope, b.slope_std_error) {
                // Exact only within the f32 rounding an exact verdict allows.
                _ if b.zero_variance => match b.bias_floor {
                    Some(off) if off > crate::stats::exact_relative_tolerance() => {
                        format!("σ = 0, off by {off:.1e}")
                    }
                    _ => "σ = 0 (exact)".into(),
                },
                (Some(s), Some(e)) => format!("{s:+.2} ± {e:.2}"),
                (Some(s), None) => format!("{s:+.2}"),
                _ => "—".into(),
            },
            b.runner_up_ratio.map_or("—".into(), |x| format!("{x:.1}×")),
        ],
    }
}

/// The markdown page.
pub fn markdown(index: &Index) -> String {
    let run = &index.run;
    let mut s = String::new();
    s.push_str("# lightproof convergence reports\n\n");
    s.push_str(&format!(
        "lightproof {} ({}), {} threads on {} ({} logical cores{}), {}.\n\n",
        run.lightproof_version,
        run.git_revision,
        run.threads,
        run.machine.cpu,
        run.machine.logical_cores,
        run.machine
            .ray_isa
            .as_deref()
            .map(|isa| format!("; ray queries in {isa}"))
            .unwrap_or_default(),
        run.started
    ));
    s.push_str(&format!(
        "Times are core-seconds to reach {}% relative error with the most efficient \
         estimator / sampler: the RMS error over |reference| for a case with a reference, \
         the standard error over |estimate| at the largest point for one without; \
         *extrapolated* times follow the fitted rate past the largest point run; *never*: \
         every series disagrees with the reference by at least the bias shown, which no \
         sample count removes. Slope: d ln(error) / d ln(N) (−0.5 for Monte Carlo; σ = 0: \
         a zero-variance estimator, exact up to f32 rounding, or off by the relative error \
         shown). Runner-up: how many times longer the next best series takes.",
        HEADLINE * 100.0
    ));
    if run.budget_cut {
        s.push_str(" The run's time budget stopped some series early.");
    }
    s.push_str("\n\n| case | best | time to 0.1% | slope | runner-up | plot |\n");
    s.push_str("|---|---|---|---|---|---|\n");
    for r in &index.cases {
        let [best, time, slope, ratio] = cells(r);
        let plot = r
            .plot
            .as_ref()
            .map_or("—".to_string(), |p| format!("[svg]({p})"));
        s.push_str(&format!(
            "| [{}]({}){} | {best} | {time} | {slope} | {ratio} | {plot} |\n",
            r.name.replace('|', "\\|"),
            r.report,
            if r.complete { "" } else { " (incomplete)" },
        ));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::SamplerKind;
    use crate::transport::Estimator;

    fn row_with(best: Option<IndexBest>, bias_floor: Option<f64>) -> IndexRow {
        IndexRow {
            id: "c".into(),
            name: "c".into(),
            report: "c.json".into(),
            plot: None,
            seed: 1,
            complete: true,
            best,
            bias_floor,
        }
    }

    fn zero_variance(bias_floor: Option<f64>) -> IndexBest {
        IndexBest {
            estimator: Estimator::Light,
            sampler: SamplerKind::Independent,
            seconds: Some(1e-4),
            extrapolated: false,
            slope: Some(0.0),
            slope_std_error: Some(0.0),
            runner_up_ratio: None,
            zero_variance: true,
            bias_floor,
        }
    }

    /// A zero-variance series is "exact" only within the f32 rounding an exact verdict
    /// allows (a point light read 1.6·10⁻⁷ off); one 5·10⁻⁴ off its reference said
    /// "σ = 0 (exact)" (session 56's audit) and now says how far off it is. A case whose
    /// every series is biased has no best, and its time says why.
    #[test]
    fn cells_say_when_an_estimate_is_off() {
        let tol = crate::stats::exact_relative_tolerance();
        for floor in [None, Some(1.6e-7), Some(tol)] {
            let [_, _, slope, _] = cells(&row_with(Some(zero_variance(floor)), None));
            assert_eq!(slope, "σ = 0 (exact)", "{floor:?}");
        }
        let [_, _, slope, _] = cells(&row_with(Some(zero_variance(Some(5e-4))), None));
        assert_eq!(slope, "σ = 0, off by 5.0e-4");
        // A series with variance shows its fitted slope, whatever its floor.
        let varying = IndexBest {
            zero_variance: false,
            slope: Some(-0.5),
            slope_std_error: Some(0.01),
            ..zero_variance(Some(5e-4))
        };
        let [_, time, slope, _] = cells(&row_with(Some(varying), None));
        assert_eq!((time.as_str(), slope.as_str()), ("100 µs", "-0.50 ± 0.01"));
        let [best, time, _, _] = cells(&row_with(None, Some(2.299e-3)));
        assert_eq!(
            (best.as_str(), time.as_str()),
            ("—", "never: biased ≥ 0.22%")
        );
        assert_eq!(cells(&row_with(None, None))[1], "—");
        // Rounded down, yet exact where the floor is a whole hundredth of a percent.
        assert_eq!(percent_at_least(0.0029), "0.29%");
        assert_eq!(percent_at_least(0.002_899_9), "0.28%");
        assert_eq!(percent_at_least(1.0), "100.00%");
    }
}
