//! The transient response of a time-resolved histogram (a case with `time.bins`, see
//! [`crate::case::bins`]): the SVG `lightproof report` writes beside a case's
//! convergence plot, `ID.transient.svg` — each bin's estimate as a step with its ±2
//! standard-error bar, and the closed form per bin as a second step line, against
//! arrival time in nanoseconds.

use crate::case::Case;
use crate::sampling::SamplerKind;
use crate::verdict::{Outcome, judge_family};
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// Family-wise significance of the bins' verdicts shown on the plot.
const ALPHA: f64 = 1e-4;

fn err<E: std::fmt::Display>(e: E) -> String {
    e.to_string()
}

/// The SVG of the judged bin outcomes `bins` (in bin order) of the case named `title`.
pub fn svg(title: &str, bins: &[Outcome]) -> Result<String, String> {
    let edges: Vec<[f64; 2]> = bins.iter().filter_map(|o| o.bin).collect();
    if edges.is_empty() || edges.len() != bins.len() {
        return Err("no time bins to plot".into());
    }
    let ns = |t: f64| t * 1e9;
    let se = |o: &Outcome| o.std_error.unwrap_or(0.0);
    let top = bins
        .iter()
        .map(|o| (o.estimate + 2.0 * se(o)).max(o.reference.unwrap_or(0.0)))
        .fold(0.0f64, f64::max);
    if !(top.is_finite() && top > 0.0) {
        return Err("nothing arrived in any bin".into());
    }
    let (t0, t1) = (ns(edges[0][0]), ns(edges[edges.len() - 1][1]));
    let mut buf = String::new();
    {
        let root = SVGBackend::with_string(&mut buf, (900, 520)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let passed = bins.iter().filter(|o| o.passed()).count();
        let weak = match bins.iter().filter(|o| o.is_weak()).count() {
            0 => String::new(),
            w => format!(" ({w} weak)"),
        };
        let caption = format!(
            "{} — {passed} of {} bins pass{weak}",
            title.chars().take(80).collect::<String>(),
            bins.len()
        );
        let mut chart = ChartBuilder::on(&root)
            .caption(caption, ("sans-serif", 17))
            .margin(14)
            .x_label_area_size(44)
            .y_label_area_size(76)
            .build_cartesian_2d(t0..t1, 0.0..top * 1.08)
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc("arrival time (ns)")
            .y_desc("radiant exposure per bin")
            .label_style(("sans-serif", 13))
            .draw()
            .map_err(err)?;
        let steps = |v: &dyn Fn(&Outcome) -> f64| -> Vec<(f64, f64)> {
            bins.iter()
                .zip(&edges)
                .flat_map(|(o, [a, b])| [(ns(*a), v(o)), (ns(*b), v(o))])
                .collect()
        };
        let blue = RGBColor(42, 93, 159);
        let red = RGBColor(204, 0, 51);
        chart
            .draw_series(LineSeries::new(
                steps(&|o| o.reference.unwrap_or(f64::NAN)),
                red.stroke_width(2),
            ))
            .map_err(err)?
            .label("closed form")
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], red.stroke_width(2)));
        chart
            .draw_series(LineSeries::new(
                steps(&|o| o.estimate),
                blue.stroke_width(1),
            ))
            .map_err(err)?
            .label("estimate ± 2 SE")
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], blue));
        chart
            .draw_series(bins.iter().zip(&edges).map(|(o, [a, b])| {
                let m = ns(0.5 * (a + b));
                let (lo, hi) = (o.estimate - 2.0 * se(o), o.estimate + 2.0 * se(o));
                let colour = if o.passed() { blue } else { red };
                PathElement::new(vec![(m, lo), (m, hi)], colour.stroke_width(2))
            }))
            .map_err(err)?;
        chart
            .draw_series(
                bins.iter().zip(&edges).map(|(o, [a, b])| {
                    Circle::new((ns(0.5 * (a + b)), o.estimate), 3, blue.filled())
                }),
            )
            .map_err(err)?;
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .border_style(BLACK)
            .background_style(WHITE)
            .label_font(("sans-serif", 13))
            .draw()
            .map_err(err)?;
        root.present().map_err(err)?;
    }
    Ok(buf)
}

/// For every case with time bins among `cases` (id, case): run each bin once with the
/// case's first estimator and sampler at the count `samples(id, bins)` chooses (`None`:
/// no plot for that case, e.g. when it would run past a budget), judge the bins as one
/// family and write `OUT/ID.transient.svg` atomically; returns the files written.
pub fn write_all(
    cases: &[(String, Case)],
    out: &Path,
    mut samples: impl FnMut(&str, usize) -> Option<u64>,
    seed: u64,
) -> Result<Vec<PathBuf>, crate::error::IoError> {
    let mut written = vec![];
    for (id, c) in cases.iter().filter(|(_, c)| !c.bins.is_empty()) {
        let Some(n) = samples(id, c.bins.len()) else {
            continue;
        };
        let sampler = c
            .samplers()
            .first()
            .copied()
            .unwrap_or(SamplerKind::Independent);
        let mut bins = c.run_bins(c.desc.estimators[0], sampler, n, seed);
        judge_family(&mut bins, 0, ALPHA);
        let own = c.samples(None, 1);
        for b in &mut bins {
            b.require_power(!b.drew_fewer(n, own));
        }
        let Ok(text) = svg(&c.desc.name, &bins) else {
            continue;
        };
        // Flat, as every report file: the id's `/` become `.` (`time/pulse` once wrote
        // `time/pulse.transient.svg`, a sub-folder).
        let path = out.join(super::store::transient_plot_file(id));
        crate::io::write_atomic(&path, text.as_bytes())
            .map_err(|e| crate::error::IoError::write(&path, e))?;
        written.push(path);
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_transient_of_the_pulsed_disk_is_plotted_bin_by_bin() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("analytic/cases/time/pulsed_disk_transient.json");
        let c = Case::load(&path).unwrap();
        let dir = std::env::temp_dir().join(format!("lightproof-transient-{}", std::process::id()));
        let files = write_all(
            &[("time/t".into(), Case::load(&path).unwrap())],
            &dir,
            |_, _| Some(1 << 12),
            5,
        )
        .unwrap();
        // Flat, as every report file (it once went to a sub-folder `time/`).
        assert_eq!(files, vec![dir.join("time.t.transient.svg")]);
        let svg = std::fs::read_to_string(&files[0]).unwrap();
        // 4096 samples, below the case's own count: the four bins with light pass weakly
        // (each sees only a few %), the two empty ones exactly.
        assert!(
            svg.starts_with("<svg") && svg.contains("6 of 6 bins pass (4 weak)"),
            "{svg}"
        );
        assert!(svg.contains("arrival time (ns)") && svg.contains("closed form"));
        // The same run at the case's own count (its `samples` lowered to 4096): the rule of
        // `verify`, a bin that cannot see 0.5% there fails, it is not a weak pass.
        let mut own = Case::load(&path).unwrap();
        own.desc.samples = Some(1 << 12);
        let files = write_all(&[("own".into(), own)], &dir, |_, _| Some(1 << 12), 5).unwrap();
        let svg = std::fs::read_to_string(&files[0]).unwrap();
        assert!(
            svg.contains("2 of 6 bins pass") && !svg.contains("weak"),
            "{svg}"
        );
        std::fs::remove_dir_all(dir).unwrap();
        // Nothing to plot is an error, not an empty picture; so is an outcome that is
        // not a bin among bins.
        assert!(super::svg("none", &[]).is_err());
        let mut bins = c.run_bins(c.desc.estimators[0], SamplerKind::Sobol, 1 << 12, 5);
        assert!(super::svg("bins", &bins).is_ok());
        bins[2].bin = None;
        assert!(super::svg("one not a bin", &bins).is_err());
    }

    /// The y axis reaches the highest error bar and the reference, with a little head-room
    /// (8%), not more: every bin's estimate 1 ± 2·0.5 against a reference of 1 needs the
    /// axis to 2 (its top tick label between 1.8 and 2.6); the bins are moved to 100 ns
    /// and beyond so that the time axis's labels cannot be taken for the y axis's.
    #[test]
    fn the_y_axis_holds_every_error_bar() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("analytic/cases/time/pulsed_disk_transient.json");
        let c = Case::load(&path).unwrap();
        let mut bins = c.run_bins(c.desc.estimators[0], SamplerKind::Sobol, 1 << 10, 5);
        for (i, o) in bins.iter_mut().enumerate() {
            let t = 100e-9 + i as f64 * 1e-9;
            o.bin = Some([t, t + 1e-9]);
            o.estimate = 1.0;
            o.std_error = Some(0.5);
            o.reference = Some(1.0);
        }
        let svg = super::svg("head-room", &bins).unwrap();
        let top = svg
            .split("<text")
            .filter_map(|t| t.split_once('>')?.1.split_once("</text>"))
            .filter_map(|(label, _)| label.trim().parse::<f64>().ok())
            .filter(|v| *v < 50.0)
            .fold(f64::NEG_INFINITY, f64::max);
        assert!((1.8..=2.6).contains(&top), "top y label {top}");
    }
}
