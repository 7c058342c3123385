//! The verdict table `verify` prints: one row per verdict, each case named by its file id
//! (`view_factor/element_to_coaxial_disk`, the path under the folder given, without
//! `.json`), never cut.
//!
//! The id column is as wide as the longest id, up to what the terminal leaves beside the
//! fixed columns; an id longer than that goes on a line of its own and its numbers on the
//! next, so no name is truncated whatever the width. Without a terminal (a pipe, a file)
//! there is no width limit. `--verbose` adds each case's name and what it teaches under
//! its first row.

use crate::sampling::SamplerKind;
use crate::stats::Verdict;
use crate::stats::chi2::Chi2Outcome;
use crate::verdict::Outcome;
use std::fmt::Write;

/// Narrowest id column: below it, ids go on their own line anyway.
const MIN_ID_WIDTH: usize = 16;

/// The fixed columns after the id: estimator, estimate ± error, reference, z,
/// detectable bias, time, verdict.
const HEADER: [&str; 7] = [
    "estimator",
    "estimate ± std error",
    "reference",
    "z",
    "det.bias",
    "time",
    "verdict",
];
const WIDTHS: [usize; 6] = [12, 26, 12, 8, 9, 8];

/// One row: the id, the fixed cells, and an optional note line (a verdict's reason).
pub struct Row {
    /// The case's file id (or `chi2 NAME` for a chi-square suite).
    pub id: String,
    /// Estimator, estimate ± error, reference, z, detectable bias, time, verdict.
    pub cells: [String; 7],
    /// Lines printed under the row, indented (the reason of a failure, the case's name).
    pub notes: Vec<String>,
}

/// The reference, z, detectable-bias and verdict cells of a verdict (or of its absence:
/// `passed` says whether an outcome without a reference passed).
pub fn verdict_cells(v: Option<&Verdict>, passed: bool) -> [String; 4] {
    match v {
        Some(v) => [
            format!("{:.6}", v.reference),
            format!("{:+.2}", v.z),
            v.detectable_bias_text(),
            v.label().into(),
        ],
        None => [
            "-".into(),
            "-".into(),
            "-".into(),
            if passed { "(no reference)" } else { "FAIL" }.into(),
        ],
    }
}

/// The row of an outcome of the case with file id `id`.
pub fn outcome_row(id: &str, o: &Outcome) -> Row {
    let [r, z, det, verdict] = verdict_cells(o.verdict.as_ref(), o.passed());
    let estimator = match o.sampler {
        SamplerKind::Independent => o.estimator.name().to_string(),
        SamplerKind::Stratified | SamplerKind::Sobol => {
            format!("{}/{}", o.estimator.name(), o.sampler.name())
        }
    };
    let estimate = match o.std_error {
        Some(se) => format!("{:.6} ± {se:.6}", o.estimate),
        None => format!("{:.6} (exact)", o.estimate),
    };
    let mut notes = vec![];
    if let Some(reason) = o.verdict.as_ref().and_then(|v| v.reason.as_ref()) {
        notes.push(format!("↳ {reason}"));
    }
    if o.non_finite > 0 && o.verdict.is_none() {
        notes.push(format!("↳ {} non-finite samples", o.non_finite));
    }
    Row {
        id: format!("{id}{}", o.bin_suffix()),
        cells: [
            estimator,
            estimate,
            r,
            z,
            det,
            format!("{:.2}s", o.seconds),
            verdict,
        ],
        notes,
    }
}

/// The row of a chi-square suite.
pub fn chi2_row(c: &Chi2Outcome) -> Row {
    Row {
        id: format!("chi2 {}", c.name),
        cells: [
            "sampling".into(),
            format!("p = {:.3e}", c.p_value),
            format!("dof {}", c.dof),
            "-".into(),
            "-".into(),
            String::new(),
            if c.passed { "pass" } else { "FAIL" }.into(),
        ],
        notes: c.reason.iter().map(|r| format!("↳ {r}")).collect(),
    }
}

/// The table of `rows` for a terminal `width` columns wide (`None`: no limit).
pub fn render(rows: &[Row], width: Option<usize>) -> String {
    let longest = rows
        .iter()
        .map(|r| r.id.chars().count())
        .chain(std::iter::once(4))
        .max()
        .unwrap_or(4);
    let fixed: usize = WIDTHS.iter().map(|w| w + 1).sum::<usize>() + 1 + HEADER[6].len();
    let id_w = match width {
        Some(w) => longest.min(w.saturating_sub(fixed + 1).max(MIN_ID_WIDTH)),
        None => longest,
    };
    let mut out = String::new();
    let line = |id: &str, cells: [&str; 7]| {
        let mut s = format!("{id:<id_w$} ");
        for (c, w) in cells.iter().zip(WIDTHS) {
            if w == WIDTHS[0] {
                let _ = write!(s, "{c:<w$} ");
            } else {
                let _ = write!(s, "{c:>w$} ");
            }
        }
        let _ = write!(s, " {}", cells[6]);
        s
    };
    out.push_str(line("case", HEADER).trim_end());
    out.push('\n');
    for r in rows {
        let cells = r.cells.each_ref().map(|c| c.as_str());
        if r.id.chars().count() > id_w {
            out.push_str(&r.id);
            out.push('\n');
            out.push_str(line("", cells).trim_end());
        } else {
            out.push_str(line(&r.id, cells).trim_end());
        }
        out.push('\n');
        for n in &r.notes {
            let _ = writeln!(out, "    {n}");
        }
    }
    out
}

/// The width of the terminal standard output is, if it is one.
pub fn terminal_width() -> Option<usize> {
    console::Term::stdout()
        .size_checked()
        .map(|(_, cols)| cols as usize)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(id: &str) -> Row {
        Row {
            id: id.into(),
            cells: [
                "mis".into(),
                "0.628318 ± 0.000100".into(),
                "0.628319".into(),
                "-0.01".into(),
                "0.120%".into(),
                "0.05s".into(),
                "pass".into(),
            ],
            notes: vec!["↳ note".into()],
        }
    }

    fn outcome(non_finite: u64, sampler: SamplerKind, std_error: Option<f64>) -> Outcome {
        use crate::transport::Estimator;
        Outcome {
            case: "c".into(),
            file: "c.json".into(),
            measure: "irradiance".into(),
            estimator: Estimator::Mis,
            sampler,
            samples: 1024,
            seed: 1,
            estimate: 0.5,
            std_error,
            dof: None,
            exact: std_error.is_none(),
            exact_by_batch_means: false,
            non_finite,
            seconds: 0.25,
            effects: crate::transport::effects::Effects::everything(),
            reference: None,
            reference_rounding: 0.0,
            z: None,
            verdict: None,
            bin: None,
        }
    }

    #[test]
    fn an_unjudged_outcome_fails_on_non_finite_samples_and_says_so() {
        let ok = outcome_row("a/b", &outcome(0, SamplerKind::Independent, Some(0.01)));
        assert_eq!(ok.cells[0], "mis");
        assert_eq!(ok.cells[1], "0.500000 ± 0.010000");
        assert_eq!(ok.cells[5], "0.25s");
        assert_eq!(ok.cells[6], "(no reference)");
        assert!(ok.notes.is_empty());
        let bad = outcome_row("a/b", &outcome(3, SamplerKind::Sobol, None));
        assert_eq!(bad.cells[0], "mis/sobol");
        assert_eq!(bad.cells[1], "0.500000 (exact)");
        assert_eq!(bad.cells[6], "FAIL");
        assert_eq!(bad.notes, vec!["↳ 3 non-finite samples".to_string()]);
    }

    /// The detectable bias is relative (a percentage) but for a zero reference, which has
    /// no relative bias: there it is the absolute one, printed without `%` (it printed
    /// 0.002 as "0.200%").
    #[test]
    fn a_zero_reference_shows_its_detectable_bias_in_absolute_units() {
        let judged = |reference: f64| {
            let mut o = outcome(0, SamplerKind::Independent, Some(0.001));
            o.estimate = reference;
            o.reference = Some(reference);
            o.judge(1e-4, 1);
            o
        };
        let zero = judged(0.0);
        let v = zero.verdict.as_ref().unwrap();
        let cells = verdict_cells(Some(v), zero.passed());
        assert_eq!(cells[2], format!("{:.2e}", v.detectable_bias));
        assert!(
            !cells[2].contains('%') && cells[2].parse::<f64>().is_ok(),
            "{cells:?}"
        );
        let half = judged(0.5);
        let v = half.verdict.as_ref().unwrap();
        let cells = verdict_cells(Some(v), half.passed());
        assert_eq!(
            cells[2],
            format!("{:.3}%", 100.0 * v.detectable_bias / 0.5),
            "{cells:?}"
        );
    }

    #[test]
    fn ids_are_never_cut_and_lines_fit_the_width() {
        let long = "irradiance/sphere_near_surface_centre_below_horizon_gap_1e-3";
        let rows = [row("power/disk"), row(long)];
        for width in [60, 100, 120, 200] {
            let t = render(&rows, Some(width));
            assert!(t.contains(long), "{t}");
            assert!(t.contains("power/disk"));
            let fixed: usize = WIDTHS.iter().map(|w| w + 1).sum::<usize>() + 1 + 7;
            for l in t.lines().filter(|l| !l.starts_with(long)) {
                assert!(
                    l.chars().count() <= width.max(fixed + MIN_ID_WIDTH + 1),
                    "{width}: {l}"
                );
            }
        }
        // Wide enough: one line per row, the id first.
        let t = render(&rows, Some(200));
        assert!(
            t.lines()
                .any(|l| l.starts_with(long) && l.ends_with("pass"))
        );
        // Narrow: the long id alone on its line, the numbers under it.
        let t = render(&rows, Some(100));
        let i = t.lines().position(|l| l == long).expect("own line");
        assert!(
            t.lines()
                .nth(i + 1)
                .unwrap()
                .trim_start()
                .starts_with("mis")
        );
        assert!(t.contains("    ↳ note"));
        // No terminal: no limit.
        assert_eq!(render(&rows, None), render(&rows, Some(1000)));
    }
}
