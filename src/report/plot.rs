//! The plot of a case: relative error against core-seconds on log–log axes, one line
//! per estimator × sampler (colour: estimator; marker: circle independent, triangle
//! stratified, square Sobol), a dashed N^-½ reference line (slope −½ against time at a
//! fixed cost per sample) through the first independent series, and dotted lines at the
//! 1%, 0.1% and 0.01% targets: where a line crosses 0.1% is what 0.1% costs.

use super::analysis::error_of;
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

type Curve = (Estimator, SamplerKind, Vec<(f64, f64)>);

/// The plotted points: (core-seconds, error / scale) with both positive.
fn curves(r: &CaseReport) -> Vec<Curve> {
    r.series
        .iter()
        .filter_map(|s| {
            let scale = match r.case.reference {
                Some(x) => x.abs(),
                None => s.points.last()?.estimate.abs(),
            };
            if !(scale > 0.0 && scale.is_finite()) {
                return None;
            }
            let pts: Vec<(f64, f64)> = s
                .points
                .iter()
                .filter_map(|p| {
                    let e = error_of(p, r.error_measure)? / scale;
                    (e > 0.0 && e.is_finite() && p.seconds > 0.0).then_some((p.seconds, e))
                })
                .collect();
            (!pts.is_empty()).then_some((s.estimator, s.sampler, pts))
        })
        .collect()
}

/// The SVG text of a case's plot (`Err` when there is nothing to plot).
pub fn svg(r: &CaseReport) -> Result<String, String> {
    let curves = curves(r);
    if curves.is_empty() {
        return Err("no positive errors to plot".into());
    }
    let all = || curves.iter().flat_map(|c| c.2.iter().copied());
    let (x0, x1) = all().fold((f64::INFINITY, 0f64), |(a, b), p| (a.min(p.0), b.max(p.0)));
    let (y0, y1) = all().fold((f64::INFINITY, 0f64), |(a, b), p| (a.min(p.1), b.max(p.1)));
    let headline = super::HEADLINE;
    let (x0, x1) = (x0 / 2.0, x1 * 2.0);
    let (y0, y1) = (y0.min(headline) / 3.0, y1.max(headline) * 3.0);
    // A log axis over an infinite range never finishes its ticks (a hostile partial
    // file's `seconds: 1e308`): refuse instead of hanging.
    if !([x0, x1, y0, y1].iter().all(|v| v.is_finite() && *v > 0.0) && x0 < x1 && y0 < y1) {
        return Err(format!(
            "axis range [{x0:e}, {x1:e}] × [{y0:e}, {y1:e}] cannot be plotted"
        ));
    }
    let mut buf = String::new();
    {
        let e = |e: DrawingAreaErrorKind<std::io::Error>| e.to_string();
        let root = SVGBackend::with_string(&mut buf, (820, 540)).into_drawing_area();
        root.fill(&WHITE).map_err(e)?;
        let title: String = r.case.name.chars().take(80).collect();
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 18))
            .margin(14)
            .x_label_area_size(42)
            .y_label_area_size(72)
            .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
            .map_err(e)?;
        chart
            .configure_mesh()
            .x_desc("core-seconds")
            .y_desc(match r.error_measure {
                super::ErrorMeasure::RmsError => "relative RMS error",
                super::ErrorMeasure::StdError => "relative standard error",
            })
            .x_label_formatter(&|x| format!("{x:.0e}"))
            .y_label_formatter(&|y| format!("{y:.0e}"))
            .draw()
            .map_err(e)?;
        let grey = RGBColor(120, 120, 120);
        for &t in TARGETS.iter().filter(|&&t| t > y0 && t < y1) {
            chart
                .draw_series(DashedLineSeries::new(
                    vec![(x0, t), (x1, t)],
                    2,
                    4,
                    grey.stroke_width(1),
                ))
                .map_err(e)?;
            chart
                .draw_series(std::iter::once(Text::new(
                    format!("{}%", t * 100.0),
                    (x0 * 1.15, t * 1.12),
                    ("sans-serif", 12).into_font().color(&grey),
                )))
                .map_err(e)?;
        }
        // N^-1/2 through the middle point of the first independent series (or the first).
        let anchor = curves
            .iter()
            .find(|c| c.1 == SamplerKind::Independent)
            .unwrap_or(&curves[0]);
        let (ax, ay) = anchor.2[anchor.2.len() / 2];
        let line = |x: f64| ay * (x / ax).powf(-0.5);
        chart
            .draw_series(DashedLineSeries::new(
                vec![(x0, line(x0)), (x1, line(x1))],
                8,
                6,
                BLACK.stroke_width(1),
            ))
            .map_err(e)?
            .label("N^-1/2")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK.stroke_width(1)));
        for (est, sampler, pts) in &curves {
            let c = colour(*est);
            let width = if *sampler == SamplerKind::Independent {
                2
            } else {
                1
            };
            let s = *sampler;
            chart
                .draw_series(LineSeries::new(pts.iter().copied(), c.stroke_width(width)))
                .map_err(e)?
                .label(format!("{} / {}", est.name(), sampler.name()))
                .legend(move |(x, y)| {
                    EmptyElement::at((x, y))
                        + PathElement::new(vec![(0, 0), (20, 0)], c.stroke_width(width))
                        + match s {
                            SamplerKind::Independent => {
                                Circle::new((10, 0), 3, c.filled()).into_dyn()
                            }
                            SamplerKind::Stratified => {
                                TriangleMarker::new((10, 0), 4, c.filled()).into_dyn()
                            }
                            SamplerKind::Sobol => {
                                Rectangle::new([(7, -3), (13, 3)], c.filled()).into_dyn()
                            }
                        }
                });
            let pts = pts.iter().copied();
            match sampler {
                SamplerKind::Independent => {
                    chart.draw_series(pts.map(|p| Circle::new(p, 3, c.filled())))
                }
                SamplerKind::Stratified => {
                    chart.draw_series(pts.map(|p| TriangleMarker::new(p, 4, c.filled())))
                }
                SamplerKind::Sobol => {
                    chart.draw_series(pts.map(|p| {
                        EmptyElement::at(p) + Rectangle::new([(-3, -3), (3, 3)], c.filled())
                    }))
                }
            }
            .map_err(e)?;
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(e)?;
        root.present().map_err(e)?;
    }
    Ok(buf)
}
