//! The plot of a case, three panels:
//!
//! 1. **Error against cost**: relative error against the *fitted* core-seconds
//!    t̂ = t₀ + c·N of each point (the series' cost line, so no curve runs backwards
//!    because one short measurement was noisy), the measured times as faint markers
//!    beside them; one line per estimator × sampler (colour: estimator; marker: circle
//!    independent, triangle stratified, square Sobol), a dashed N^-½ line and finely dashed
//!    grey lines at the 1%, 0.1% and 0.01% targets: where a line crosses 0.1% is what 0.1% costs.
//! 2. **Error against N**, the same lines: the convergence rate alone, cost aside.
//! 3. **Ranking**: core-seconds to 0.1% per series (from the fits), fastest first,
//!    extrapolated times drawn pale.

use super::analysis::{error_of, scale};
use super::{CaseReport, TARGETS};
use crate::sampling::SamplerKind;
use crate::transport::Estimator;
use plotters::prelude::*;

fn colour(e: Estimator) -> RGBColor {
    match e {
        Estimator::Light => RGBColor(31, 119, 180),
        Estimator::Bsdf => RGBColor(214, 39, 40),
        Estimator::Mis => RGBColor(44, 160, 44),
        Estimator::MisBalance => RGBColor(148, 103, 189),
        Estimator::Uniform => RGBColor(255, 127, 14),
        Estimator::Cosine => RGBColor(140, 86, 75),
        Estimator::Area => RGBColor(23, 190, 207),
    }
}

/// One plotted point: (samples, measured core-seconds, fitted core-seconds, relative error).
type Pt = (f64, f64, f64, f64);
type Curve = (Estimator, SamplerKind, Vec<Pt>);

/// The plotted points, all coordinates positive and finite.
fn curves(r: &CaseReport) -> Vec<Curve> {
    r.series
        .iter()
        .filter_map(|s| {
            let scale = scale(s, r.case.reference)?;
            let pts: Vec<Pt> = s
                .points
                .iter()
                .filter_map(|p| {
                    let e = error_of(p, r.error_measure)? / scale;
                    let n = p.samples as f64;
                    let fitted = s.fit_cost.map_or(p.seconds, |c| c.seconds(n));
                    let ok = |v: f64| v > 0.0 && v.is_finite();
                    (ok(e) && ok(p.seconds) && ok(fitted)).then_some((n, p.seconds, fitted, e))
                })
                .collect();
            (!pts.is_empty()).then_some((s.estimator, s.sampler, pts))
        })
        .collect()
}

type DrawResult = Result<(), String>;
type Area<'a> = DrawingArea<SVGBackend<'a>, plotters::coord::Shift>;

fn err(e: DrawingAreaErrorKind<std::io::Error>) -> String {
    e.to_string()
}

/// A log range around `values` (with `extra` included), widened by `pad`; `Err` when it
/// cannot be plotted (a log axis over an infinite range never finishes its ticks).
fn log_range(
    values: impl Iterator<Item = f64>,
    extra: Option<f64>,
    pad: f64,
) -> Result<(f64, f64), String> {
    let (lo, hi) = values
        .chain(extra)
        .fold((f64::INFINITY, 0f64), |(a, b), v| (a.min(v), b.max(v)));
    let (lo, hi) = (lo / pad, hi * pad);
    if lo.is_finite() && hi.is_finite() && lo > 0.0 && lo < hi {
        Ok((lo, hi))
    } else {
        Err(format!("axis range [{lo:e}, {hi:e}] cannot be plotted"))
    }
}

/// The SVG text of a case's plot (`Err` when there is nothing to plot).
pub fn svg(r: &CaseReport) -> Result<String, String> {
    let curves = curves(r);
    if curves.is_empty() {
        return Err("no positive errors to plot".into());
    }
    let all = || curves.iter().flat_map(|c| c.2.iter().copied());
    let headline = super::HEADLINE;
    let ys = log_range(all().map(|p| p.3), Some(headline), 3.0)?;
    let ts = log_range(all().flat_map(|p| [p.1, p.2]), None, 2.0)?;
    let ns = log_range(all().map(|p| p.0), None, 2.0)?;
    let mut buf = String::new();
    {
        let root = SVGBackend::with_string(&mut buf, (1100, 860)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let title: String = r.case.name.chars().take(110).collect();
        let root = root.titled(&title, ("sans-serif", 18)).map_err(err)?;
        let (top, bottom) = root.split_vertically(540);
        let (left, right) = top.split_horizontally(550);
        error_panel(&left, r, &curves, Axis::Seconds, ts, ys)?;
        error_panel(&right, r, &curves, Axis::Samples, ns, ys)?;
        ranking_panel(&bottom, r)?;
        root.present().map_err(err)?;
    }
    Ok(buf)
}

/// The x axis of an error panel.
#[derive(Clone, Copy, PartialEq)]
enum Axis {
    /// Fitted core-seconds (measured as faint markers).
    Seconds,
    /// Samples N.
    Samples,
}

type LogChart<'a, 'b> = ChartContext<
    'a,
    SVGBackend<'b>,
    Cartesian2d<
        plotters::coord::combinators::LogCoord<f64>,
        plotters::coord::combinators::LogCoord<f64>,
    >,
>;

/// The sampler's markers (circle, triangle, square) at `pts`.
fn markers(
    chart: &mut LogChart,
    sampler: SamplerKind,
    pts: Vec<(f64, f64)>,
    style: ShapeStyle,
) -> DrawResult {
    let pts = pts.into_iter();
    match sampler {
        SamplerKind::Independent => chart.draw_series(pts.map(|p| Circle::new(p, 3, style))),
        SamplerKind::Stratified => chart.draw_series(pts.map(|p| TriangleMarker::new(p, 4, style))),
        SamplerKind::Sobol => chart.draw_series(
            pts.map(|p| EmptyElement::at(p) + Rectangle::new([(-3, -3), (3, 3)], style)),
        ),
    }
    .map(|_| ())
    .map_err(err)
}

fn error_panel(
    area: &Area,
    r: &CaseReport,
    curves: &[Curve],
    axis: Axis,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
) -> DrawResult {
    let mut chart = ChartBuilder::on(area)
        .margin(14)
        .x_label_area_size(42)
        .y_label_area_size(72)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(match axis {
            Axis::Seconds => "core-seconds (fitted t0 + c N; measured: faint)",
            Axis::Samples => "samples N",
        })
        .y_desc(match r.error_measure {
            super::ErrorMeasure::RmsError => "relative RMS error",
            super::ErrorMeasure::StdError => "relative standard error",
        })
        .x_label_formatter(&|x| format!("{x:.0e}"))
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .draw()
        .map_err(err)?;
    let grey = RGBColor(120, 120, 120);
    for &t in TARGETS.iter().filter(|&&t| t > y0 && t < y1) {
        chart
            .draw_series(DashedLineSeries::new(
                vec![(x0, t), (x1, t)],
                2,
                4,
                grey.stroke_width(1),
            ))
            .map_err(err)?;
        chart
            .draw_series(std::iter::once(Text::new(
                format!("{}%", t * 100.0),
                (x0 * 1.15, t * 1.12),
                ("sans-serif", 12).into_font().color(&grey),
            )))
            .map_err(err)?;
    }
    let x_of = |p: &Pt| match axis {
        Axis::Seconds => p.2,
        Axis::Samples => p.0,
    };
    // N^-1/2 through the middle point of the first independent series (or the first):
    // against N exactly, against cost where the cost is proportional to N.
    let anchor = curves
        .iter()
        .find(|c| c.1 == SamplerKind::Independent)
        .unwrap_or(&curves[0]);
    let mid = anchor.2[anchor.2.len() / 2];
    let (ax, ay) = (x_of(&mid), mid.3);
    let line = |x: f64| ay * (x / ax).powf(-0.5);
    chart
        .draw_series(DashedLineSeries::new(
            vec![(x0, line(x0)), (x1, line(x1))],
            8,
            6,
            BLACK.stroke_width(1),
        ))
        .map_err(err)?
        .label("N^-1/2")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK.stroke_width(1)));
    for (est, sampler, pts) in curves {
        let c = colour(*est);
        let width = if *sampler == SamplerKind::Independent {
            2
        } else {
            1
        };
        let s = *sampler;
        // The bias the series' points establish, dotted in its colour: its error cannot
        // go below it, though a point whose distance chance could still explain plots
        // lower (its RMS error counts only the part beyond 3.89 σ̂).
        let floor = r
            .series
            .iter()
            .find(|x| x.estimator == *est && x.sampler == s)
            .and_then(|x| x.bias_floor)
            .filter(|b| *b > y0 && *b < y1);
        if let Some(b) = floor {
            chart
                .draw_series(DashedLineSeries::new(
                    vec![(x0, b), (x1, b)],
                    1,
                    3,
                    c.stroke_width(1),
                ))
                .map_err(err)?;
        }
        let bias = floor.map_or(String::new(), |b| {
            format!(" (bias ≥ {})", super::index::percent_at_least(b))
        });
        if axis == Axis::Seconds {
            let faint = c.mix(0.3).filled();
            markers(
                &mut chart,
                s,
                pts.iter().map(|p| (p.1, p.3)).collect(),
                faint,
            )?;
        }
        chart
            .draw_series(LineSeries::new(
                pts.iter().map(|p| (x_of(p), p.3)),
                c.stroke_width(width),
            ))
            .map_err(err)?
            .label(format!("{} / {}{bias}", est.name(), sampler.name()))
            .legend(move |(x, y)| {
                EmptyElement::at((x, y))
                    + PathElement::new(vec![(0, 0), (20, 0)], c.stroke_width(width))
                    + match s {
                        SamplerKind::Independent => Circle::new((10, 0), 3, c.filled()).into_dyn(),
                        SamplerKind::Stratified => {
                            TriangleMarker::new((10, 0), 4, c.filled()).into_dyn()
                        }
                        SamplerKind::Sobol => {
                            Rectangle::new([(7, -3), (13, 3)], c.filled()).into_dyn()
                        }
                    }
            });
        markers(
            &mut chart,
            s,
            pts.iter().map(|p| (x_of(p), p.3)).collect(),
            c.filled(),
        )?;
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(err)?;
    Ok(())
}

/// Core-seconds to [`super::HEADLINE`] per series, fastest first.
fn ranking_panel(area: &Area, r: &CaseReport) -> DrawResult {
    let mut bars: Vec<(String, f64, bool, RGBColor)> = r
        .series
        .iter()
        .filter_map(|s| {
            let t = super::analysis::headline_time(s)?;
            let secs = t.seconds.filter(|v| *v > 0.0 && v.is_finite())?;
            let name = format!("{} / {}", s.estimator.name(), s.sampler.name());
            Some((name, secs, t.extrapolated, colour(s.estimator)))
        })
        .collect();
    bars.sort_by(|a, b| a.1.total_cmp(&b.1));
    let caption = format!(
        "core-seconds to {}% relative error (pale: extrapolated past the sweep)",
        super::HEADLINE * 100.0
    );
    if bars.is_empty() {
        let biased = !r.series.is_empty()
            && r.series
                .iter()
                .all(|s| s.bias_floor.is_some_and(|b| b >= super::HEADLINE));
        area.draw(&Text::new(
            format!(
                "{caption}: no series {}",
                if biased {
                    "reaches it: each is biased beyond it (dotted lines above)"
                } else {
                    "reaches or extrapolates to it"
                }
            ),
            (80, 40),
            ("sans-serif", 14),
        ))
        .map_err(err)?;
        return Ok(());
    }
    let (x0, x1) = log_range(bars.iter().map(|b| b.1), None, 4.0)?;
    let n = bars.len() as f64;
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 14))
        .margin(14)
        .x_label_area_size(36)
        .y_label_area_size(12)
        .build_cartesian_2d((x0..x1).log_scale(), 0f64..n)
        .map_err(err)?;
    chart
        .configure_mesh()
        .disable_y_mesh()
        .y_labels(0)
        .x_desc("core-seconds")
        .x_label_formatter(&|x| format!("{x:.0e}"))
        .draw()
        .map_err(err)?;
    for (i, (name, secs, extrapolated, c)) in bars.iter().enumerate() {
        let y = n - 1.0 - i as f64;
        let fill = if *extrapolated {
            c.mix(0.35)
        } else {
            c.mix(0.9)
        };
        chart
            .draw_series(std::iter::once(Rectangle::new(
                [(x0, y + 0.15), (*secs, y + 0.85)],
                fill.filled(),
            )))
            .map_err(err)?;
        chart
            .draw_series(std::iter::once(Text::new(
                format!("{name}  {secs:.3e} s"),
                (secs * 1.1, y + 0.62),
                ("sans-serif", 12).into_font(),
            )))
            .map_err(err)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::ErrorMeasure;

    /// The committed example report (`reports/examples/disk_on_axis.json`).
    fn example() -> CaseReport {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("reports/examples/disk_on_axis.json");
        let text = std::fs::read_to_string(&path).unwrap();
        crate::error::parse_json("r.json", &text).unwrap()
    }

    /// Every series with positive errors is a curve of all its points, scaled by the
    /// reference; without a reference the scale is the last point's estimate, and a
    /// series whose last point has none (no finite sample) is left out, not drawn at a
    /// scale of 0; a point that a log axis cannot show (zero error, infinite time) is left
    /// out.
    #[test]
    fn the_curves_are_the_series_scaled() {
        let mut r = example();
        let reference = r.case.reference.unwrap();
        let c = curves(&r);
        assert_eq!(c.len(), r.series.len());
        for (curve, s) in c.iter().zip(&r.series) {
            assert_eq!((curve.0, curve.1), (s.estimator, s.sampler));
            assert_eq!(curve.2.len(), s.points.len());
            let p = &s.points[0];
            assert_eq!(
                curve.2[0].3,
                error_of(p, r.error_measure).unwrap() / reference
            );
        }
        r.case.reference = None;
        r.error_measure = ErrorMeasure::StdError;
        r.series[0].points.last_mut().unwrap().estimate = None;
        let c = curves(&r);
        assert_eq!(c.len(), r.series.len() - 1);
        assert_eq!(
            (c[0].0, c[0].1),
            (r.series[1].estimator, r.series[1].sampler)
        );
        let s = &r.series[1];
        let p = &s.points[0];
        let last = s.points.last().unwrap().estimate.unwrap().abs();
        assert_eq!(c[0].2[0].3, p.std_error.unwrap() / last);
        assert!(svg(&r).is_ok());
        // A point with a zero error or an infinite time has no place on a log axis.
        assert!(r.series[1].fit_cost.is_some());
        r.series[1].points[0].std_error = Some(0.0);
        r.series[1].points[1].seconds = f64::INFINITY;
        let c = curves(&r);
        assert_eq!(c[0].2.len(), r.series[1].points.len() - 2);
        assert_eq!(c[0].2[0].0, r.series[1].points[2].samples as f64);
    }

    /// A series' bias floor inside the plotted range is dotted in its colour and named in
    /// the legend, "bias ≥ X%" rounded down; outside the range (above the largest error
    /// plotted, or at or below the smallest) it is neither; a series without one is
    /// named plainly. With no series timed to 0.1%, the ranking panel says whether every
    /// series is biased beyond it.
    #[test]
    fn a_bias_floor_is_dotted_and_named() {
        let mut r = example();
        let plain = svg(&r).unwrap();
        let polylines = |s: &str| s.matches("<polyline").count();
        let label = "light / independent (bias ≥ 0.20%)";
        assert!(!plain.contains("(bias ≥"));
        r.series[0].bias_floor = Some(0.002);
        let dotted = svg(&r).unwrap();
        assert!(dotted.contains(label), "no legend label");
        // One series has a floor, named in each of the two error panels' legends.
        assert_eq!(dotted.matches("(bias ≥").count(), 2);
        assert!(
            polylines(&dotted) > polylines(&plain) + 20,
            "no dotted line"
        );
        // Outside the panel's range: neither a line nor a label.
        let y = |c: &Curve| c.2.iter().map(|p| p.3).collect::<Vec<f64>>();
        let all: Vec<f64> = curves(&r).iter().flat_map(y).collect();
        let (lo, hi) = (
            all.iter().cloned().fold(f64::INFINITY, f64::min),
            all.iter().cloned().fold(0.0, f64::max),
        );
        for outside in [hi * 100.0, lo * 1e-3] {
            r.series[0].bias_floor = Some(outside);
            let s = svg(&r).unwrap();
            assert!(!s.contains("(bias ≥"), "{outside}");
            assert_eq!(polylines(&s), polylines(&plain), "{outside}");
        }
        // The ranking panel without a time to 0.1%.
        for s in &mut r.series {
            s.time_to[1].seconds = None;
            s.bias_floor = Some(crate::report::HEADLINE);
        }
        assert!(svg(&r).unwrap().contains("each is biased beyond it"));
        r.series[1].bias_floor = Some(crate::report::HEADLINE * 0.5);
        let s = svg(&r).unwrap();
        assert!(s.contains("no series reaches or extrapolates to it"));
        assert!(!s.contains("each is biased beyond it"));
        r.series.clear();
        assert!(!svg(&r).is_ok_and(|s| s.contains("each is biased beyond it")));
    }
}
