//! The verdict page `lightproof verify --html FILE` writes: one self-contained HTML file
//! (inline CSS, SVG, script and `data:` images; nothing fetched from a network).
//!
//! It holds, in order: the failures (each failed verdict with its reason; each failed
//! chi-square suite with its residual image, red where the sampler drew more than the
//! density predicts and blue where fewer, read back from the suite's dump and embedded as
//! a PNG); the **calibration of the whole suite** — a histogram of every statistical
//! verdict's z score against the standard normal density scaled to the count, and a QQ
//! plot of the sorted z scores against the normal quantiles Φ⁻¹((i − ½)/n) (Hazen's
//! plotting positions): under the null hypothesis the z scores are standard normal, so
//! a biased estimator shows as a point in the tails and a wrong error bar as a histogram
//! too wide or too narrow (a QQ line steeper or flatter than the diagonal); the
//! detectable bias of each statistical verdict (log scale, against the catalog's 0.5%
//! requirement); and the verdict table, one row per outcome with each case's `teaches`
//! line, failures first, sortable by clicking a header.
//!
//! Batch-means verdicts report a t statistic with 127 degrees of freedom in `z`; its
//! quantiles differ from the normal ones by under 2% out to |z| = 4, which the plots
//! do not resolve.

use crate::stats::VerdictClass;
use crate::stats::chi2::Chi2Outcome;
use crate::verdict::Outcome;
use std::collections::BTreeMap;
use std::fmt::Write;
use std::path::Path;

/// What the page says about a case file beside its outcomes.
pub struct CaseInfo {
    /// The file id (its path under the folder given, without `.json`).
    pub id: String,
    /// What the case teaches.
    pub teaches: String,
}

/// Each case file's id (from `ids`, file → id; else the case's name) and `teaches` line,
/// by file as [`Outcome::file`] spells it.
pub fn case_infos(
    cases: &[crate::case::Case],
    ids: &BTreeMap<String, String>,
) -> BTreeMap<String, CaseInfo> {
    cases
        .iter()
        .map(|c| {
            let file = c.file.display().to_string();
            let id = ids
                .get(&file)
                .cloned()
                .unwrap_or_else(|| c.desc.name.clone());
            let teaches = c.desc.teaches.clone();
            (file, CaseInfo { id, teaches })
        })
        .collect()
}

/// Everything one `verify` run hands the page.
pub struct Page<'a> {
    /// The judged outcomes.
    pub outcomes: &'a [Outcome],
    /// Per case file (as [`Outcome::file`] spells it): its id and `teaches` line.
    pub cases: &'a BTreeMap<String, CaseInfo>,
    /// The chi-square suites.
    pub chi2: &'a [Chi2Outcome],
    /// Base seed of the run.
    pub seed: u64,
    /// Family-wise significance.
    pub alpha: f64,
    /// Statistical tests in the Šidák family.
    pub tests: usize,
}

/// Width of a z-histogram bin.
pub const Z_BIN: f64 = 0.5;
/// The z histogram spans [−Z_SPAN, Z_SPAN]; scores beyond it count in the end bins.
pub const Z_SPAN: f64 = 5.0;

/// The z scores of the statistical verdicts in bins of [`Z_BIN`] over ±[`Z_SPAN`] (the
/// end bins also hold everything beyond), and the non-finite ones apart.
#[derive(Debug, PartialEq)]
pub struct ZHistogram {
    /// Counts per bin, from −Z_SPAN up.
    pub counts: Vec<u64>,
    /// z scores that are NaN (an estimate with non-finite samples).
    pub not_finite: u64,
}

impl ZHistogram {
    /// The histogram of `zs`.
    pub fn of(zs: &[f64]) -> ZHistogram {
        let bins = (2.0 * Z_SPAN / Z_BIN).round() as usize;
        let mut h = ZHistogram {
            counts: vec![0; bins],
            not_finite: 0,
        };
        for &z in zs {
            if z.is_nan() {
                h.not_finite += 1;
            } else {
                let i = ((z + Z_SPAN) / Z_BIN).floor().clamp(0.0, (bins - 1) as f64);
                h.counts[i as usize] += 1;
            }
        }
        h
    }
}

/// The z scores of the statistical verdicts among `outcomes`.
pub fn statistical_z(outcomes: &[Outcome]) -> Vec<f64> {
    outcomes
        .iter()
        .filter_map(|o| o.verdict.as_ref())
        .filter(|v| v.class == VerdictClass::Statistical)
        .map(|v| v.z)
        .collect()
}

/// Write the page of `page` to `path` atomically.
pub fn write(path: &Path, page: &Page) -> std::io::Result<()> {
    crate::io::write_atomic(path, render(page).as_bytes())
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A number for people: fixed for ordinary magnitudes, scientific otherwise.
fn num(x: f64) -> String {
    if x == 0.0 || (1e-3..1e5).contains(&x.abs()) {
        format!("{x:.6}")
    } else {
        format!("{x:.4e}")
    }
}

const STYLE: &str = "body{font:14px/1.4 system-ui,sans-serif;margin:24px;color:#222}\
h1{font-size:22px}h2{font-size:18px;margin-top:28px}\
table{border-collapse:collapse}td,th{padding:3px 8px;border-bottom:1px solid #ddd;text-align:left;vertical-align:top}\
th{cursor:pointer;background:#f3f3f3;user-select:none}th:hover{background:#e4e4e4}\
td.n{text-align:right;font-variant-numeric:tabular-nums;white-space:nowrap}\
tr.fail td{background:#fde8e8}tr.weak td{background:#fff4dc}.teaches{color:#666;font-size:12px}\
.fig{display:inline-block;margin:0 16px 16px 0;vertical-align:top}\
.fig p{margin:4px 0;max-width:520px;color:#444;font-size:12px}\
img.residual{image-rendering:pixelated;width:512px;border:1px solid #999}\
svg text{font:11px sans-serif;fill:#333}";

/// Sorts a table's body by the clicked column: by each cell's `data-v` (numbers as
/// numbers), ascending first, then descending.
const SCRIPT: &str = "document.querySelectorAll('table.sortable th').forEach(function(th,i){\
th.addEventListener('click',function(){var b=th.closest('table').tBodies[0];\
var up=th.dataset.dir!=='up';th.dataset.dir=up?'up':'down';\
var key=function(r){var c=r.cells[i];return c.dataset.v!==undefined?c.dataset.v:c.textContent};\
Array.from(b.rows).sort(function(x,y){var a=key(x),c=key(y),p=parseFloat(a),q=parseFloat(c);\
var d=(isNaN(p)||isNaN(q))?a.localeCompare(c):p-q;return up?d:-d}).forEach(function(r){b.appendChild(r)})})});";

/// Render the page.
pub fn render(page: &Page) -> String {
    let failed = page.outcomes.iter().filter(|o| !o.passed()).count()
        + page.chi2.iter().filter(|c| !c.passed).count();
    let total = page.outcomes.len() + page.chi2.len();
    let weak = page.outcomes.iter().filter(|o| o.is_weak()).count();
    let weak = if weak > 0 {
        format!(
            " ({weak} of them weak: they cannot see a {}% bias)",
            100.0 * BIAS_REQUIREMENT
        )
    } else {
        String::new()
    };
    let mut s = String::new();
    let _ = write!(
        s,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <title>lightproof verdicts: {} passed, {failed} failed</title>\n<style>{STYLE}</style>\n</head>\n<body>\n\
         <h1>lightproof verdicts</h1>\n<p id=\"summary\">{} passed{weak}, {failed} failed of {total} verdicts \
         ({} outcomes, {} chi-square suites); statistical verdicts Šidák-corrected over k = {} at family α = {}; seed {}.</p>\n",
        total - failed,
        total - failed,
        page.outcomes.len(),
        page.chi2.len(),
        page.tests,
        page.alpha,
        page.seed
    );
    failures(&mut s, page);
    calibration(&mut s, page);
    verdict_table(&mut s, page);
    chi2_table(&mut s, page.chi2);
    let _ = write!(s, "<script>{SCRIPT}</script>\n</body>\n</html>\n");
    s
}

fn id_of(page: &Page, o: &Outcome) -> String {
    let id = page
        .cases
        .get(&o.file)
        .map_or(o.case.as_str(), |c| c.id.as_str());
    format!("{id}{}", o.bin_suffix())
}

fn estimator_label(o: &Outcome) -> String {
    format!("{} / {}", o.estimator.name(), o.sampler.name())
}

fn failures(s: &mut String, page: &Page) {
    let bad: Vec<&Outcome> = page.outcomes.iter().filter(|o| !o.passed()).collect();
    let bad_chi2: Vec<&Chi2Outcome> = page.chi2.iter().filter(|c| !c.passed).collect();
    s.push_str("<h2 id=\"failures\">Failures</h2>\n");
    if bad.is_empty() && bad_chi2.is_empty() {
        s.push_str("<p>None: every verdict passed.</p>\n");
        return;
    }
    s.push_str("<ul>\n");
    for o in bad {
        let why = o
            .verdict
            .as_ref()
            .and_then(|v| v.reason.clone())
            .unwrap_or_else(|| format!("{} non-finite samples", o.non_finite));
        let _ = writeln!(
            s,
            "<li><b>{}</b> ({}): {}</li>",
            esc(&id_of(page, o)),
            esc(&estimator_label(o)),
            esc(&why)
        );
    }
    s.push_str("</ul>\n");
    for c in bad_chi2 {
        let _ = writeln!(
            s,
            "<div class=\"fig\"><p><b>chi2 {}</b>: {}</p>",
            esc(&c.name),
            esc(c.reason.as_deref().unwrap_or("failed"))
        );
        match c
            .dump
            .iter()
            .find(|p| p.to_string_lossy().ends_with("-residual.exr"))
            .and_then(|p| residual_png(p))
        {
            Some(uri) => {
                let _ = writeln!(
                    s,
                    "<img class=\"residual\" alt=\"chi-square residual of {}\" src=\"{uri}\">\n\
                     <p>Residual per cell, (O − E)/√E: red where more samples fell than the density predicts, \
                     blue where fewer; full colour at 4. Rows from the top of the domain down.</p>",
                    esc(&c.name)
                );
            }
            None => s.push_str("<p>(no residual image was written)</p>\n"),
        }
        s.push_str("</div>\n");
    }
}

/// Full colour of a residual image at this many √E.
const RESIDUAL_FULL: f32 = 4.0;

/// The residual EXR of a chi-square dump (red: positive, blue: negative residual, in
/// units of √E) as a PNG data URI on white, or `None` when it cannot be read.
fn residual_png(path: &Path) -> Option<String> {
    crate::io::check_input_file(path, crate::io::MAX_ASSET_BYTES).ok()?;
    let image = exr::prelude::read_first_rgba_layer_from_file(
        path,
        |r, _| {
            (
                r.width(),
                vec![[255u8; 3]; (r.width() * r.height()).min(1 << 22)],
            )
        },
        |(w, px): &mut (usize, Vec<[u8; 3]>), pos, (r, _g, b, _a): (f32, f32, f32, f32)| {
            let shade = |v: f32| 255 - (255.0 * (v / RESIDUAL_FULL).clamp(0.0, 1.0)) as u8;
            if let Some(p) = px.get_mut(pos.y() * *w + pos.x()) {
                *p = if r > 0.0 {
                    [255, shade(r), shade(r)]
                } else {
                    [shade(b), shade(b), 255]
                };
            }
        },
    )
    .ok()?;
    let (w, px) = image.layer_data.channel_data.pixels;
    if w == 0 || px.is_empty() || px.len() % w != 0 {
        return None;
    }
    let rgb: Vec<u8> = px.concat();
    Some(super::png::data_uri(&super::png::encode_rgb(
        w,
        px.len() / w,
        &rgb,
    )))
}

/// A plot's mapping from data to SVG pixels.
struct Frame {
    w: f64,
    h: f64,
    /// Plot area in pixels: left, right, top, bottom.
    area: [f64; 4],
    x: (f64, f64),
    y: (f64, f64),
}

impl Frame {
    fn new(x: (f64, f64), y: (f64, f64)) -> Frame {
        Frame {
            w: 520.0,
            h: 320.0,
            area: [56.0, 505.0, 16.0, 276.0],
            x,
            y,
        }
    }

    fn px(&self, x: f64) -> f64 {
        let [l, r, _, _] = self.area;
        l + (x - self.x.0) / (self.x.1 - self.x.0) * (r - l)
    }

    fn py(&self, y: f64) -> f64 {
        let [_, _, t, b] = self.area;
        b - (y - self.y.0) / (self.y.1 - self.y.0) * (b - t)
    }

    /// The opening tag, the frame, the ticks and the axis labels.
    fn open(
        &self,
        id: &str,
        xt: &[(f64, String)],
        yt: &[(f64, String)],
        labels: [&str; 2],
    ) -> String {
        let [l, r, t, b] = self.area;
        let mut s = format!(
            "<svg id=\"{id}\" width=\"{}\" height=\"{}\" viewBox=\"0 0 {} {}\" role=\"img\">\n\
             <rect x=\"{l}\" y=\"{t}\" width=\"{}\" height=\"{}\" fill=\"white\" stroke=\"#999\"/>\n",
            self.w,
            self.h,
            self.w,
            self.h,
            r - l,
            b - t
        );
        for (v, label) in xt {
            let x = self.px(*v);
            let _ = writeln!(
                s,
                "<line x1=\"{x:.1}\" y1=\"{b}\" x2=\"{x:.1}\" y2=\"{}\" stroke=\"#999\"/>\
                 <text x=\"{x:.1}\" y=\"{}\" text-anchor=\"middle\">{label}</text>",
                b + 4.0,
                b + 16.0
            );
        }
        for (v, label) in yt {
            let y = self.py(*v);
            let _ = writeln!(
                s,
                "<line x1=\"{}\" y1=\"{y:.1}\" x2=\"{l}\" y2=\"{y:.1}\" stroke=\"#999\"/>\
                 <text x=\"{}\" y=\"{:.1}\" text-anchor=\"end\">{label}</text>",
                l - 4.0,
                l - 6.0,
                y + 4.0
            );
        }
        let _ = writeln!(
            s,
            "<text x=\"{:.1}\" y=\"{}\" text-anchor=\"middle\">{}</text>\
             <text transform=\"translate(14 {:.1}) rotate(-90)\" text-anchor=\"middle\">{}</text>",
            (l + r) / 2.0,
            self.h - 8.0,
            labels[0],
            (t + b) / 2.0,
            labels[1]
        );
        s
    }

    fn polyline(&self, pts: impl Iterator<Item = (f64, f64)>, style: &str) -> String {
        let p: Vec<String> = pts
            .map(|(x, y)| format!("{:.1},{:.1}", self.px(x), self.py(y)))
            .collect();
        format!(
            "<polyline points=\"{}\" fill=\"none\" {style}/>\n",
            p.join(" ")
        )
    }
}

fn ticks(lo: i32, hi: i32, step: usize, f: impl Fn(i32) -> String) -> Vec<(f64, String)> {
    (lo..=hi).step_by(step).map(|v| (v as f64, f(v))).collect()
}

/// Standard normal density.
fn phi(z: f64) -> f64 {
    (-0.5 * z * z).exp() / (2.0 * std::f64::consts::PI).sqrt()
}

fn calibration(s: &mut String, page: &Page) {
    let zs = statistical_z(page.outcomes);
    let n = zs.len();
    s.push_str("<h2 id=\"calibration\">Calibration of the whole suite</h2>\n");
    let finite: Vec<f64> = zs.iter().copied().filter(|z| z.is_finite()).collect();
    let mean = finite.iter().sum::<f64>() / finite.len().max(1) as f64;
    let sd = (finite.iter().map(|z| (z - mean).powi(2)).sum::<f64>()
        / (finite.len().max(2) - 1) as f64)
        .sqrt();
    let _ = writeln!(
        s,
        "<p>{n} statistical verdicts: mean z = {mean:.3}, standard deviation {sd:.3} \
         (standard normal: 0 and 1 up to ±{:.3} and ±{:.3} from sampling alone). \
         A biased estimator shows as a point in a tail; a wrong error bar as a spread other than 1.</p>",
        3.0 / (n.max(1) as f64).sqrt(),
        3.0 / (2.0 * n.max(1) as f64).sqrt(),
    );
    // Passes with |z| past the critical value: the difference lies within the f32
    // rounding allowance τ that the null hypothesis |bias| ≤ τ grants.
    let excused: Vec<String> = page
        .outcomes
        .iter()
        .filter(|o| {
            o.verdict.as_ref().is_some_and(|v| {
                v.class == VerdictClass::Statistical && v.passed && v.z.abs() > v.critical
            })
        })
        .map(|o| format!("{} ({})", esc(&id_of(page, o)), esc(&estimator_label(o))))
        .collect();
    if !excused.is_empty() {
        let _ = writeln!(
            s,
            "<p id=\"rounding\">{} passing verdicts have |z| beyond the critical value: the null \
             hypothesis grants the f32 rounding allowance τ = γ₁₂₈·|reference|, and their difference \
             from the reference exceeds τ by no more than the critical value's standard errors: {}.</p>",
            excused.len(),
            excused.join(", ")
        );
    }
    let critical = page
        .outcomes
        .iter()
        .filter_map(|o| o.verdict.as_ref())
        .find(|v| v.class == VerdictClass::Statistical && v.dof.is_none())
        .map(|v| v.critical);
    s.push_str("<div class=\"fig\">");
    s.push_str(&histogram_svg(&zs, critical));
    s.push_str(
        "<p>z scores in bins of 0.5 (scores beyond ±5 in the end bins, NaN apart) against \
         n·0.5·φ(z), the count a standard normal predicts; dashed: the Šidák critical value.</p></div>\n",
    );
    s.push_str("<div class=\"fig\">");
    s.push_str(&qq_svg(&finite));
    s.push_str(
        "<p>QQ plot: sorted z against the normal quantiles Φ⁻¹((i − ½)/n). On the diagonal \
         when calibrated; a tail bending away is a bias, a slope other than 1 a wrong error bar.</p></div>\n",
    );
    s.push_str("<div class=\"fig\">");
    s.push_str(&bias_svg(page.outcomes));
    let _ = writeln!(
        s,
        "<p>Detectable bias of each statistical verdict (the smallest relative bias found \
         with 99% power), smallest first; dashed: the catalog's {}% requirement.</p></div>",
        100.0 * BIAS_REQUIREMENT
    );
}

fn histogram_svg(zs: &[f64], critical: Option<f64>) -> String {
    let h = ZHistogram::of(zs);
    let n = zs.len() as f64;
    let top = h
        .counts
        .iter()
        .map(|&c| c as f64)
        .fold(n * Z_BIN * phi(0.0), f64::max)
        .max(h.not_finite as f64)
        .max(1.0)
        * 1.1;
    let f = Frame::new((-Z_SPAN, Z_SPAN + 2.0 * Z_BIN), (0.0, top));
    let step = (top / 5.0).ceil().max(1.0) as usize;
    let mut s = f.open(
        "z-histogram",
        &ticks(-5, 5, 1, |v| v.to_string()),
        &ticks(0, top as i32, step, |v| v.to_string()),
        ["z", "verdicts"],
    );
    let mut bar = |x0: f64, count: u64, class: &str, fill: &str| {
        let (x, y) = (f.px(x0), f.py(count as f64));
        let _ = writeln!(
            s,
            "<rect class=\"{class}\" data-count=\"{count}\" x=\"{x:.1}\" y=\"{y:.1}\" width=\"{:.1}\" height=\"{:.1}\" fill=\"{fill}\" stroke=\"white\"/>",
            f.px(x0 + Z_BIN) - x,
            f.py(0.0) - y
        );
    };
    for (i, &c) in h.counts.iter().enumerate() {
        bar(-Z_SPAN + i as f64 * Z_BIN, c, "bin", "#7aa6d6");
    }
    bar(Z_SPAN + Z_BIN, h.not_finite, "bin nan", "#d67a7a");
    let _ = writeln!(
        s,
        "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">NaN</text>",
        f.px(Z_SPAN + 1.5 * Z_BIN),
        f.py(0.0) - 4.0
    );
    let curve = (0..=200).map(|i| {
        let z = -Z_SPAN + i as f64 * 2.0 * Z_SPAN / 200.0;
        (z, n * Z_BIN * phi(z))
    });
    s.push_str(&f.polyline(curve, "stroke=\"#c03\" stroke-width=\"2\""));
    if let Some(c) = critical.filter(|c| c.is_finite() && *c < Z_SPAN) {
        for x in [-c, c] {
            s.push_str(&f.polyline(
                [(x, 0.0), (x, top)].into_iter(),
                "stroke=\"#555\" stroke-dasharray=\"4 3\"",
            ));
        }
    }
    s.push_str("</svg>");
    s
}

fn qq_svg(finite: &[f64]) -> String {
    use statrs::distribution::{ContinuousCDF, Normal};
    let mut z = finite.to_vec();
    z.sort_by(f64::total_cmp);
    let n = z.len();
    let lim = z
        .iter()
        .map(|v| v.abs())
        .fold(4.0, f64::max)
        .min(10.0)
        .ceil();
    let f = Frame::new((-lim, lim), (-lim, lim));
    let step = if lim > 6.0 { 2 } else { 1 };
    let t = ticks(-(lim as i32), lim as i32, step, |v| v.to_string());
    let mut s = f.open("qq", &t, &t, ["normal quantile", "z (sorted)"]);
    s.push_str(&f.polyline(
        [(-lim, -lim), (lim, lim)].into_iter(),
        "stroke=\"#c03\" stroke-width=\"1.5\"",
    ));
    let normal = Normal::standard();
    for (i, &v) in z.iter().enumerate() {
        let q = normal.inverse_cdf((i as f64 + 0.5) / n as f64);
        let _ = writeln!(
            s,
            "<circle class=\"qq\" cx=\"{:.1}\" cy=\"{:.1}\" r=\"2.5\" fill=\"#2a5d9f\"/>",
            f.px(q),
            f.py(v.clamp(-lim, lim))
        );
    }
    s.push_str("</svg>");
    s
}

/// The proof's requirement on a statistical verdict's detectable relative bias.
const BIAS_REQUIREMENT: f64 = crate::verdict::DETECTABLE_BOUND;

fn bias_svg(outcomes: &[Outcome]) -> String {
    let mut b: Vec<f64> = outcomes
        .iter()
        .filter_map(|o| o.verdict.as_ref())
        // Relative biases only: a zero reference's is absolute (in the case's units).
        .filter(|v| v.class == VerdictClass::Statistical && v.reference != 0.0)
        .map(|v| v.detectable_relative_bias)
        .filter(|b| b.is_finite() && *b > 0.0)
        .collect();
    b.sort_by(f64::total_cmp);
    let f = Frame::new((0.0, b.len().max(1) as f64), (-7.0, 0.0));
    let mut s = f.open(
        "detectable-bias",
        &[],
        &ticks(-7, 0, 1, |v| format!("1e{v}")),
        [
            "statistical verdicts, smallest detectable bias first",
            "relative bias",
        ],
    );
    let r = BIAS_REQUIREMENT.log10();
    s.push_str(&f.polyline(
        [(0.0, r), (b.len().max(1) as f64, r)].into_iter(),
        "stroke=\"#c03\" stroke-dasharray=\"4 3\"",
    ));
    for (i, v) in b.iter().enumerate() {
        let _ = writeln!(
            s,
            "<circle class=\"bias\" cx=\"{:.1}\" cy=\"{:.1}\" r=\"2.5\" fill=\"{}\"/>",
            f.px(i as f64 + 0.5),
            f.py(v.log10().clamp(-7.0, 0.0)),
            if *v > BIAS_REQUIREMENT {
                "#c03"
            } else {
                "#2a5d9f"
            }
        );
    }
    s.push_str("</svg>");
    s
}

fn verdict_table(s: &mut String, page: &Page) {
    s.push_str(
        "<h2 id=\"verdicts\">Verdicts</h2>\n<p>Click a header to sort; failures come first.</p>\n\
         <table class=\"sortable\" id=\"verdict-table\">\n<thead><tr><th>case</th><th>estimator / sampler</th>\
         <th>estimate</th><th>std error</th><th>reference</th><th>z</th><th>detectable bias</th>\
         <th>class</th><th>time</th><th>verdict</th></tr></thead>\n<tbody>\n",
    );
    let mut order: Vec<&Outcome> = page.outcomes.iter().collect();
    order.sort_by_key(|o| o.passed());
    for o in order {
        let id = &id_of(page, o);
        let teaches = page.cases.get(&o.file).map_or("", |c| c.teaches.as_str());
        let v = o.verdict.as_ref();
        let (verdict, rank) = match (v, o.passed()) {
            (_, false) => ("FAIL", 0),
            (Some(v), true) => (v.label(), 1),
            (None, true) => ("no reference", 2),
        };
        let cell = |x: Option<f64>, f: &dyn Fn(f64) -> String| match x {
            Some(x) => format!("<td class=\"n\" data-v=\"{x:e}\">{}</td>", f(x)),
            None => "<td class=\"n\" data-v=\"-1e308\">–</td>".to_string(),
        };
        let class = match v.map(|v| v.class) {
            Some(VerdictClass::Statistical) => "statistical",
            Some(VerdictClass::Exact) => "exact",
            None => "–",
        };
        let _ = writeln!(
            s,
            "<tr class=\"outcome{}\"><td data-v=\"{}\"><b>{}</b><div class=\"teaches\">{}</div></td>\
             <td>{}</td>{}{}{}{}{}<td>{class}</td>{}<td data-v=\"{rank}\">{verdict}</td></tr>",
            match (o.passed(), o.is_weak()) {
                (false, _) => " fail",
                (true, true) => " weak",
                (true, false) => "",
            },
            esc(id),
            esc(id),
            esc(teaches),
            esc(&estimator_label(o)),
            cell(Some(o.estimate), &num),
            cell(o.std_error, &num),
            cell(o.reference, &num),
            cell(o.z, &|z| format!("{z:+.2}")),
            cell(v.map(|v| v.detectable_relative_bias), &|_| v
                .map(|v| v.detectable_bias_text())
                .unwrap_or_default()),
            cell(Some(o.seconds), &|t| format!("{t:.2} s")),
        );
    }
    s.push_str("</tbody>\n</table>\n");
}

fn chi2_table(s: &mut String, chi2: &[Chi2Outcome]) {
    if chi2.is_empty() {
        return;
    }
    s.push_str(
        "<h2 id=\"chi2\">Chi-square suites of the sampling warps</h2>\n\
         <table class=\"sortable\" id=\"chi2-table\">\n<thead><tr><th>warp</th><th>statistic</th>\
         <th>dof</th><th>p value</th><th>normalisation z</th><th>verdict</th></tr></thead>\n<tbody>\n",
    );
    let mut order: Vec<&Chi2Outcome> = chi2.iter().collect();
    order.sort_by_key(|c| c.passed);
    for c in order {
        let _ = writeln!(
            s,
            "<tr class=\"chi2{}\"><td>{}</td><td class=\"n\" data-v=\"{:e}\">{:.1}</td><td class=\"n\">{}</td>\
             <td class=\"n\" data-v=\"{:e}\">{:.3e}</td><td class=\"n\" data-v=\"{:e}\">{:+.2}</td>\
             <td data-v=\"{}\">{}</td></tr>",
            if c.passed { "" } else { " fail" },
            esc(&c.name),
            c.statistic,
            c.statistic,
            c.dof,
            c.p_value,
            c.p_value,
            c.normalisation_z,
            c.normalisation_z,
            u8::from(c.passed),
            if c.passed { "pass" } else { "FAIL" }
        );
    }
    s.push_str("</tbody>\n</table>\n");
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::SamplerKind;
    use crate::transport::Estimator;
    use crate::verdict::judge_family;

    fn outcome(
        file: &str,
        estimate: f64,
        std_error: Option<f64>,
        reference: Option<f64>,
    ) -> Outcome {
        Outcome {
            case: format!("case {file}"),
            file: file.into(),
            measure: "irradiance".into(),
            estimator: Estimator::Mis,
            sampler: SamplerKind::Independent,
            samples: 1 << 16,
            seed: 7,
            estimate,
            std_error,
            dof: None,
            exact: std_error.is_none(),
            exact_by_batch_means: false,
            non_finite: 0,
            seconds: 0.1,
            effects: crate::transport::effects::Effects::everything(),
            reference,
            reference_rounding: 0.0,
            z: None,
            verdict: None,
            bin: None,
        }
    }

    /// Tags open and close in order (void elements and `<svg>` shapes that close
    /// themselves aside; script and style text skipped); returns the tags seen.
    fn check_structure(html: &str) -> Vec<String> {
        const VOID: [&str; 3] = ["meta", "img", "br"];
        let mut stack: Vec<String> = Vec::new();
        let mut seen = Vec::new();
        let mut rest = html
            .strip_prefix("<!DOCTYPE html>\n")
            .expect("a doctype first");
        while let Some(at) = rest.find('<') {
            let end = rest[at..].find('>').expect("every tag ends") + at;
            let tag = &rest[at + 1..end];
            let name: String = tag
                .trim_start_matches('/')
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric())
                .collect();
            rest = &rest[end + 1..];
            if let Some(closing) = tag.strip_prefix('/') {
                assert_eq!(
                    stack.pop().as_deref(),
                    Some(closing),
                    "misnested </{closing}>"
                );
            } else if !tag.ends_with('/') && !VOID.contains(&name.as_str()) {
                stack.push(name.clone());
                if name == "script" || name == "style" {
                    let close = rest.find(&format!("</{name}>")).expect("raw text ends");
                    assert!(!rest[..close].contains('<'), "no `<` in {name}");
                    rest = &rest[close..];
                }
            }
            seen.push(name);
        }
        assert!(stack.is_empty(), "unclosed: {stack:?}");
        seen
    }

    fn residual_exr(dir: &Path) -> std::path::PathBuf {
        let p = dir.join("warp-residual.exr");
        crate::io::write_exr_atomic(&p, 8, 4, |x, y| {
            if x == y {
                (5.0, 0.0, 0.0)
            } else {
                (0.0, 0.0, 1.0)
            }
        })
        .unwrap();
        p
    }

    /// A zero reference's detectable bias is absolute (in the case's units): the table
    /// shows it without `%` (it showed 0.002 as "0.200%", as `verify`'s table did) and the
    /// relative-bias plot leaves it out.
    #[test]
    fn a_zero_references_bias_is_shown_in_its_own_units() {
        let mut outcomes = vec![outcome("z.json", 0.0005, Some(0.001), Some(0.0))];
        let k = judge_family(&mut outcomes, 0, 1e-4);
        let v = outcomes[0].verdict.clone().unwrap();
        let dir = std::env::temp_dir().join(format!("lightproof-html0-{}", std::process::id()));
        let cases = BTreeMap::new();
        let page = Page {
            outcomes: &outcomes,
            cases: &cases,
            chi2: &[],
            seed: 7,
            alpha: 1e-4,
            tests: k,
        };
        let path = dir.join("verdicts.html");
        write(&path, &page).unwrap();
        let html = std::fs::read_to_string(&path).unwrap();
        let _ = std::fs::remove_dir_all(&dir);
        let text = format!("{:.2e}", v.detectable_bias);
        assert!(html.contains(&format!(">{text}</td>")), "no `{text}` cell");
        assert!(!html.contains(&format!("{:.3}%", 100.0 * v.detectable_relative_bias)));
        assert!(
            !bias_svg(&outcomes).contains("<circle"),
            "plotted as relative"
        );
    }

    #[test]
    fn the_page_holds_every_outcome_and_a_calibration_of_the_statistical_ones() {
        let mut outcomes = vec![
            outcome("a.json", 1.001, Some(0.001), Some(1.0)),
            outcome("a.json", 0.999, Some(0.001), Some(1.0)),
            outcome("b.json", 2.0, Some(0.01), Some(2.5)), // z = −50: fails, lands in the end bin
            outcome("c.json", 3.0, None, Some(3.0)),       // exact
            outcome("d.json", 4.0, Some(0.1), None),       // no reference
            outcome("e.json", f64::NAN, Some(0.01), Some(1.0)), // z = NaN
            outcome("f.json", 1.0 + 5e-6, Some(1e-7), Some(1.0)), // z = 50, within τ: passes
        ];
        outcomes[5].non_finite = 3;
        let k = judge_family(&mut outcomes, 1, 1e-4);
        // Outside the proof's conditions: the two a.json passes (± 0.1 %, detectable
        // ~0.7 %) are weak.
        outcomes.iter_mut().for_each(|o| o.require_power(false));
        let dir = std::env::temp_dir().join(format!("lightproof-html-{}", std::process::id()));
        let chi2 = vec![Chi2Outcome {
            name: "bad <warp>".into(),
            statistic: 900.0,
            dof: 100,
            p_value: 1e-30,
            alpha: 1e-5,
            pdf_integral: 1.0,
            success_fraction: 1.0,
            normalisation_z: 0.1,
            normalisation_p: 0.9,
            quadrature_share: 0.0,
            passed: false,
            reason: Some("p below α".into()),
            dump: vec![residual_exr(&dir)],
        }];
        let mut cases = BTreeMap::new();
        cases.insert(
            "a.json".to_string(),
            CaseInfo {
                id: "irradiance/a".into(),
                teaches: "E = π L R²/(R² + h²) & more".into(),
            },
        );
        let page = Page {
            outcomes: &outcomes,
            cases: &cases,
            chi2: &chi2,
            seed: 7,
            alpha: 1e-4,
            tests: k,
        };
        let path = dir.join("verdicts.html");
        write(&path, &page).unwrap();
        let html = std::fs::read_to_string(&path).unwrap();
        // To look at this page in a browser: LIGHTPROOF_HTML_OUT=FILE keeps a copy.
        if let Some(keep) = std::env::var_os("LIGHTPROOF_HTML_OUT") {
            std::fs::copy(&path, keep).unwrap();
        }
        let tags = check_structure(&html);
        for t in ["html", "head", "body", "table", "svg", "script"] {
            assert!(tags.iter().any(|x| x == t), "no <{t}>");
        }
        // The summary: 7 outcomes and 1 suite, 2 + 1 failed, the weak passes counted.
        assert!(
            html.contains("<p id=\"summary\">5 passed (2 of them weak: they cannot see a 0.5% bias), 3 failed of 8 verdicts (7 outcomes, 1 chi-square suites)"),
            "{html}"
        );
        assert!(html.contains("<title>lightproof verdicts: 5 passed, 3 failed</title>"));
        assert_eq!(html.matches(">weak</td>").count(), 2);
        // Self-contained: nothing fetched.
        assert!(!html.contains("http") && !html.contains("src=\"/") && !html.contains("url("));
        // One row per outcome, failures first, each case's id and teaches line.
        assert_eq!(html.matches("<tr class=\"outcome").count(), outcomes.len());
        let rows: Vec<&str> = html.split("<tr class=\"outcome").skip(1).collect();
        let fails = outcomes.iter().filter(|o| !o.passed()).count();
        assert_eq!(fails, 2);
        assert!(rows[..fails].iter().all(|r| r.starts_with(" fail")));
        // The passes after them: the two weak ones shaded apart (`tr.weak`).
        assert_eq!(rows.iter().filter(|r| r.starts_with(" weak\"")).count(), 2);
        assert!(
            rows[fails..]
                .iter()
                .all(|r| r.starts_with('"') || r.starts_with(" weak\""))
        );
        assert!(html.contains(
            "<b>irradiance/a</b><div class=\"teaches\">E = π L R²/(R² + h²) &amp; more</div>"
        ));
        assert!(html.contains("&lt;warp&gt;") && !html.contains("<warp>"));
        // The histogram counts every statistical verdict once (NaN apart, in its own bar).
        let stat = outcomes
            .iter()
            .filter(|o| {
                o.verdict
                    .as_ref()
                    .is_some_and(|v| v.class == VerdictClass::Statistical)
            })
            .count();
        assert_eq!(stat, 5);
        assert!(
            html.contains("<p id=\"rounding\">1 passing verdicts"),
            "{html}"
        );
        let svg = &html[html.find("id=\"z-histogram\"").unwrap()..];
        let svg = &svg[..svg.find("</svg>").unwrap()];
        let counts: Vec<u64> = svg
            .split("data-count=\"")
            .skip(1)
            .map(|c| c[..c.find('"').unwrap()].parse().unwrap())
            .collect();
        assert_eq!(counts.len(), (2.0 * Z_SPAN / Z_BIN) as usize + 1);
        assert_eq!(counts.iter().sum::<u64>(), stat as u64);
        assert_eq!(counts[0], 1, "z = −50 counts in the lowest bin");
        assert_eq!(*counts.last().unwrap(), 1, "the NaN z has its own bar");
        assert_eq!(html.matches("class=\"qq\"").count(), stat - 1);
        // The failed suite's residual is embedded as a PNG.
        assert_eq!(
            html.matches("src=\"data:image/png;base64,iVBORw0KGgo")
                .count(),
            1
        );
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn z_scores_fall_in_half_unit_bins_with_the_tails_in_the_end_bins() {
        let h = ZHistogram::of(&[
            -7.0,
            -5.0,
            -0.25,
            0.0,
            0.49,
            4.99,
            5.0,
            f64::INFINITY,
            f64::NAN,
        ]);
        let mut want = vec![0; 20];
        want[0] = 2;
        want[9] = 1;
        want[10] = 2;
        want[19] = 3;
        assert_eq!(
            h,
            ZHistogram {
                counts: want,
                not_finite: 1
            }
        );
    }
}
