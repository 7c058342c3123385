//! Judging another renderer's EXR renders of a case against its closed form, with the
//! same verdict as `estimate` ([`crate::verdict::judge_parts`]: z or t test at a
//! Šidák-corrected level, detectable bias at 99% power, exact class when there is no
//! variance).
//!
//! **Value of a pixel**: the mean of its R, G and B (exported cases are grey); its
//! expected value is the reference times the export's `scale` (1, except for a flux or a
//! view factor, measured as the receiver's mean irradiance: 1/A₂ or π L₁ A₁/A₂). Each
//! replicate is divided by the scale, so estimates are in the case's own units (those of
//! `estimate`: Φ, or F for a view factor).
//!
//! **Standard error.** The pixels of one render share the renderer's sampler (its seed,
//! its sample sequence), so they are not trusted as independent samples:
//! - several renders (independent seeds): each render's pixel mean is one replicate; the
//!   estimate is their mean, the error their standard error, judged by Student's t with
//!   R − 1 degrees of freedom;
//! - one render of n pixels: batch means over B = min([`BLOCKS`], n) contiguous blocks of
//!   pixels (row-major), a block without a finite pixel dropped, t with one degree of
//!   freedom fewer than the blocks kept — valid when blocks are independent, as with
//!   per-pixel seeding; independent renders are the safer choice;
//! - one render of one pixel has no error to estimate: bad input.
//!
//! **A case no sensor measures** (a geometric integral, an emitter's power or intensity:
//! [`crate::export::sensorless`], what `export` refuses for that reason) is bad input
//! naming `measure`: no pixel mean estimates it.
//!
//! **A bad `export.json`** is bad input naming it and the field: a `scale` outside
//! [`crate::export::SCALE_RANGE`], a `width` or `height` of 0, or more pixels than a render
//! may have ([`Manifest::check`]).
//!
//! **Bad renders** are bad input (exit 2, naming the file): empty, not an EXR, no R, G, B
//! channels, a size other than the export's (or than the first render's), more than
//! [`crate::scene::load::MAX_ENVMAP_PIXELS`] pixels, a pixel the file holds no data for (a
//! block missing, or claiming another block's lines: named by its line). **Non-finite pixels** (NaN, ±∞) are
//! the renderer's answer, not a malformed file: they are counted and fail the verdict
//! (exit 1), and the note names the file and the first such pixel. **Negative pixels**
//! (any of R, G, B below zero: a mean of the three could hide one) are negative radiance,
//! the renderer's error too: counted, named in the notes the same way, and the verdict
//! fails (exit 1) whatever the statistic says.

use crate::case::Case;
use crate::error::{Error, InputError};
use crate::export::{Manifest, Suite};
use crate::stats::{Accumulator, Verdict, is_exact};
use crate::verdict::{ErrorBar, judge_parts};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Pixel blocks of a single render's batch means.
pub const BLOCKS: usize = 32;

/// One render: its size and per-pixel grey values (non-finite ones kept), and its pixels
/// with a negative channel.
pub struct Render {
    /// Width.
    pub width: usize,
    /// Height.
    pub height: usize,
    /// Pixels, row-major, (R + G + B)/3.
    pub pixels: Vec<f64>,
    /// The pixels with a channel below zero (their mean may not be: R = −1, G = B = 2
    /// averages to 1).
    pub negative: Negative,
}

/// How many pixels of a render have a negative channel, and the first in row-major
/// order: (x, y) and its (R, G, B).
pub type Negative = (u64, Option<((usize, usize), [f32; 3])>);

/// Read an EXR render's first RGB layer (see the module notes for what is refused).
pub fn read_render(path: &Path) -> Result<Render, InputError> {
    use exr::prelude::*;
    let file = path.display().to_string();
    let bad = |r: String| InputError::new(&file, "-", r);
    let len = crate::io::check_input_file(path, crate::io::MAX_ASSET_BYTES).map_err(bad)?;
    if len == 0 {
        return Err(bad("the file is empty (0 bytes), not an EXR".into()));
    }
    let meta = exr::meta::MetaData::read_from_file(path, false)
        .map_err(|e| bad(format!("not a readable EXR: {e}")))?;
    if meta.headers.is_empty() {
        return Err(bad("the EXR has no layer".into()));
    }
    // The part the reader takes: the first with R, G and B channels (a Z-only part
    // before it was once blamed for the file's "no R channel").
    let names = |h: &exr::meta::header::Header| -> Vec<String> {
        h.channels.list.iter().map(|c| c.name.to_string()).collect()
    };
    let rgb = |h: &&exr::meta::header::Header| {
        let n = names(h);
        ["R", "G", "B"].iter().all(|c| n.iter().any(|x| x == c))
    };
    let Some(header) = meta.headers.iter().find(rgb) else {
        let parts: Vec<String> = meta
            .headers
            .iter()
            .map(|h| names(h).join(", "))
            .map(|n| {
                if meta.headers.len() > 1 {
                    format!("{{{n}}}")
                } else {
                    n
                }
            })
            .collect();
        let missing = ["R", "G", "B"]
            .into_iter()
            .find(|c| !meta.headers.iter().any(|h| names(h).iter().any(|n| n == c)));
        return Err(bad(match missing {
            Some(m) => format!(
                "the EXR has no {m} channel (channels: {}); a render needs R, G and B",
                parts.join("; ")
            ),
            None => format!(
                "no part of the EXR has R, G and B together (its parts' channels: {}); a render needs them in one part",
                parts.join("; ")
            ),
        }));
    };
    let (w, h) = (header.layer_size.width(), header.layer_size.height());
    let max = crate::scene::load::MAX_ENVMAP_PIXELS;
    if w.checked_mul(h).is_none_or(|n| n > max || n == 0) {
        return Err(bad(format!(
            "the EXR claims {w} × {h} pixels (1 to {max} allowed)"
        )));
    }
    let table: u64 = meta.headers.iter().map(|h| h.chunk_count as u64 * 8).sum();
    if table > len {
        return Err(bad(format!(
            "the EXR is truncated: its header claims {w} × {h} pixels, the file is {len} bytes"
        )));
    }
    // Every pixel starts unwritten (NaN, and `written` false): the reader, not pedantic,
    // accepts a chunk table whose blocks skip a line (two blocks claiming the same y), and
    // a pixel it never wrote once counted as 0, a wrong answer from a malformed file.
    let image = read_first_rgba_layer_from_file(
        path,
        move |res, _| -> (usize, Vec<f64>, Vec<bool>, Negative) {
            let n = res.width().saturating_mul(res.height()).min(max);
            (res.width(), vec![f64::NAN; n], vec![false; n], (0, None))
        },
        |(w, data, written, negative), pos, (r, g, b, _a): (f32, f32, f32, f32)| {
            let i = pos.y() * *w + pos.x();
            if let (Some(v), Some(seen)) = (data.get_mut(i), written.get_mut(i)) {
                *v = (r as f64 + g as f64 + b as f64) / 3.0;
                *seen = true;
            }
            if r < 0.0 || g < 0.0 || b < 0.0 {
                negative.0 += 1;
                // Blocks may arrive out of order: keep the first in row-major order.
                if negative.1.is_none_or(|((x, y), _)| i < y * *w + x) {
                    negative.1 = Some(((pos.x(), pos.y()), [r, g, b]));
                }
            }
        },
    )
    .map_err(|e| bad(format!("cannot read the EXR: {e}")))?;
    let (_, pixels, written, negative) = image.layer_data.channel_data.pixels;
    let missing = written.iter().filter(|&&seen| !seen).count();
    if let Some(i) = written.iter().position(|&seen| !seen) {
        return Err(bad(format!(
            "line {} of {h} has no pixel data ({missing} pixels missing, the first at ({}, {})): a block of the file is missing or claims another's lines",
            i / w,
            i % w,
            i / w
        )));
    }
    Ok(Render {
        width: w,
        height: h,
        pixels,
        negative,
    })
}

/// How the replicates were formed.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// One replicate per independent render.
    IndependentRenders,
    /// Batch means over blocks of one render's pixels.
    PixelBlocks,
}

/// The replicates of a set of renders, and what was not finite.
#[derive(Clone, Debug, Serialize)]
pub struct Sample {
    /// The render files.
    pub renders: Vec<String>,
    /// Width × height of every render.
    pub size: [usize; 2],
    /// How replicates were formed.
    pub method: Method,
    /// Replicate means (divided by the export's scale once judged: the case's units).
    pub replicates: Vec<f64>,
    /// Non-finite pixels over all renders.
    pub non_finite: u64,
    /// Pixels with a negative channel over all renders.
    pub negative: u64,
    /// Notes (where non-finite and negative pixels are).
    pub notes: Vec<String>,
}

/// Mean of the finite values and the count of non-finite ones.
fn finite_mean(v: &[f64]) -> (Option<f64>, u64) {
    let mut acc = Accumulator::new();
    for &x in v {
        acc.push(x);
    }
    ((acc.count > 0).then_some(acc.mean), acc.non_finite)
}

/// Read `files` and form the replicates; every render must be `expect` (width, height)
/// when given, else the size of the first.
pub fn sample(files: &[PathBuf], expect: Option<(usize, usize)>) -> Result<Sample, InputError> {
    let Some(first) = files.first() else {
        return Err(InputError::new(
            "<command line>",
            "RENDER.exr",
            "give at least one render",
        ));
    };
    let mut size = expect;
    let mut replicates = Vec::new();
    let mut non_finite = 0;
    let mut negative = 0;
    let mut notes = Vec::new();
    let mut method = Method::IndependentRenders;
    for f in files {
        let r = read_render(f)?;
        let (w, h) = *size.get_or_insert((r.width, r.height));
        if (r.width, r.height) != (w, h) {
            return Err(InputError::new(
                f.display().to_string(),
                "-",
                format!(
                    "the render is {} × {} pixels, expected {w} × {h}",
                    r.width, r.height
                ),
            ));
        }
        if let Some(i) = r.pixels.iter().position(|x| !x.is_finite()) {
            let count = r.pixels.iter().filter(|x| !x.is_finite()).count();
            notes.push(format!(
                "{}: {count} non-finite pixels, the first at ({}, {}) = {}",
                f.display(),
                i % w,
                i / w,
                r.pixels[i]
            ));
        }
        if let (count, Some(((x, y), [cr, cg, cb]))) = r.negative {
            negative += count;
            notes.push(format!(
                "{}: {count} pixels with a negative channel (negative radiance), the first at ({x}, {y}) = ({cr}, {cg}, {cb})",
                f.display()
            ));
        }
        if files.len() == 1 {
            let n = r.pixels.len();
            if n < 2 {
                return Err(InputError::new(
                    first.display().to_string(),
                    "-",
                    "one render of one pixel has no standard error: give several independent renders (different seeds)",
                ));
            }
            method = Method::PixelBlocks;
            let b = BLOCKS.min(n);
            for j in 0..b {
                let (m, bad) = finite_mean(&r.pixels[j * n / b..(j + 1) * n / b]);
                non_finite += bad;
                replicates.extend(m);
            }
        } else {
            let (m, bad) = finite_mean(&r.pixels);
            non_finite += bad;
            replicates.extend(m);
        }
    }
    let (w, h) = size.unwrap_or((0, 0));
    Ok(Sample {
        renders: files.iter().map(|f| f.display().to_string()).collect(),
        size: [w, h],
        method,
        replicates,
        non_finite,
        negative,
        notes,
    })
}

/// A judged case: the sample, the reference and the verdict (as `estimate` prints it).
#[derive(Clone, Debug, Serialize)]
pub struct Judgement {
    /// Case name.
    pub case: String,
    /// Case id (its folder in a suite, else the file).
    pub id: String,
    /// The renderer's name.
    pub renderer: String,
    /// The renders and their replicates.
    #[serde(flatten)]
    pub sample: Sample,
    /// Mean of the replicates (`null` where none is finite: it read 0.0 ± ∞).
    pub estimate: Option<f64>,
    /// Its standard error (absent when exact).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub std_error: Option<f64>,
    /// Degrees of freedom of the t test.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dof: Option<u64>,
    /// The case's reference (the estimate's units).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reference: Option<f64>,
    /// ρ = μ(f32 inputs) − μ, the reference's change when its inputs round to `f32`
    /// ([`crate::verdict::Outcome::reference_rounding`]; a renderer that reads the case's
    /// numbers into `f32` without the case's rebasing rounds points more). Absent when 0.
    #[serde(default, skip_serializing_if = "crate::stats::hypothesis::is_zero")]
    pub reference_rounding: f64,
    /// z score.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub z: Option<f64>,
    /// The verdict.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub verdict: Option<Verdict>,
}

impl Judgement {
    /// Build from a sample (unjudged), its replicates divided by the export's `scale`.
    fn new(case: &Case, id: String, renderer: String, mut sample: Sample, scale: f64) -> Self {
        let mut acc = Accumulator::new();
        for x in &mut sample.replicates {
            *x /= scale;
            acc.push(*x);
        }
        // Fewer than two finite replicates have no spread to tell an exact estimate from
        // one whose error is unknown: no error bar, and no verdict ([`Judgement::judge`]).
        let bar = if acc.count < 2 || is_exact(&acc) {
            ErrorBar {
                std_error: None,
                dof: None,
            }
        } else {
            ErrorBar {
                std_error: Some(acc.std_error()),
                dof: Some(acc.count.saturating_sub(1)),
            }
        };
        Judgement {
            case: case.desc.name.clone(),
            id,
            renderer,
            estimate: (acc.count > 0).then_some(acc.mean),
            std_error: bar.std_error,
            dof: bar.dof,
            reference: case.reference,
            reference_rounding: case.reference_rounding,
            z: None,
            verdict: None,
            sample,
        }
    }

    /// Whether it passed weakly ([`Verdict::weak`]).
    pub fn is_weak(&self) -> bool {
        self.verdict.as_ref().is_some_and(|v| v.weak)
    }

    /// Whether it is a member of the Šidák family.
    pub fn is_statistical(&self) -> bool {
        self.reference.is_some() && self.std_error.is_some()
    }

    /// Fewer than two finite replicates (renders or pixel blocks): nothing to judge.
    fn too_few(&self) -> bool {
        self.sample.replicates.len() < 2
    }

    /// Judge in a family of `tests` statistical tests at level `alpha`. With fewer than
    /// two finite replicates there is no verdict, and the judgement fails ([`passed`]).
    ///
    /// [`passed`]: Judgement::passed
    pub fn judge(&mut self, alpha: f64, tests: usize) {
        if self.too_few() {
            let n = self.sample.replicates.len();
            self.sample.notes.push(format!(
                "{n} finite replicate{}: fewer than two, so no error bar and no verdict",
                if n == 1 { "" } else { "s" }
            ));
            return;
        }
        if let (Some(r), Some(estimate)) = (self.reference, self.estimate) {
            let bar = ErrorBar {
                std_error: self.std_error,
                dof: self.dof,
            };
            let v = judge_parts(
                estimate,
                &bar,
                r,
                self.reference_rounding,
                self.sample.non_finite,
                self.sample.replicates.len() as u64,
                alpha,
                tests,
            );
            self.z = Some(v.z);
            let v = in_renderer_terms(v);
            let mut v = self.fail_negative(v);
            // A renderer's sample count is its own choice, outside the proof's
            // conditions: a pass that cannot see 0.5 % is marked weak, not failed.
            v.require_power(false);
            self.verdict = Some(v);
        }
    }

    /// A verdict failed where a pixel has a negative channel: negative radiance is the
    /// renderer's error whatever the mean (its pixels are averaged like any other, and
    /// the notes name the first), never masked by a passing statistic.
    fn fail_negative(&self, mut v: Verdict) -> Verdict {
        if self.sample.negative > 0 {
            let why = format!(
                "{} pixels with a negative channel (negative radiance)",
                self.sample.negative
            );
            // A verdict carries a reason only when it failed: keep it, add this one.
            v.reason = Some(match v.reason {
                Some(r) => format!("{r}; {why}"),
                None => why,
            });
            v.passed = false;
        }
        v
    }

    /// Passed: the verdict, or without a reference (or with fewer than two finite
    /// replicates, which have none), two or more replicates, no non-finite pixel and no
    /// pixel with a negative channel.
    pub fn passed(&self) -> bool {
        match &self.verdict {
            Some(v) => v.passed,
            None => !self.too_few() && self.sample.non_finite == 0 && self.sample.negative == 0,
        }
    }

    /// Its row in the verdict table.
    pub fn row(&self) -> crate::table::Row {
        let [r, z, det, verdict] =
            crate::table::verdict_cells(self.verdict.as_ref(), self.passed());
        let n = self.sample.replicates.len();
        let how = match self.sample.method {
            Method::IndependentRenders => format!("{n} renders"),
            Method::PixelBlocks => format!("{n} blocks"),
        };
        let estimate = match (self.estimate, self.std_error) {
            (None, _) => "none finite".to_string(),
            (Some(e), Some(se)) => format!("{e:.6} ± {se:.6}"),
            (Some(e), None) if self.too_few() => format!("{e:.6} (one replicate)"),
            (Some(e), None) => format!("{e:.6} (exact)"),
        };
        let mut notes: Vec<String> = self.sample.notes.iter().map(|n| format!("↳ {n}")).collect();
        if let Some(reason) = self.verdict.as_ref().and_then(|v| v.reason.as_ref()) {
            notes.push(format!("↳ {reason}"));
        }
        crate::table::Row {
            id: self.id.clone(),
            cells: [how, estimate, r, z, det, "-".into(), verdict.to_string()],
            notes,
        }
    }
}

/// A verdict's reason in a foreign renderer's terms: the engine's wording names
/// lightproof's 65536-bounce guard (a cause of +Inf no other renderer has) and, for an
/// exact failure, asks for more samples, which `judge` does not take. A non-finite count
/// comes first in every failed verdict, so it is the whole reason.
fn in_renderer_terms(mut v: Verdict) -> Verdict {
    if v.non_finite > 0 {
        v.reason = Some(format!(
            "{} non-finite pixels (NaN or Inf): the renderer's answer is not a number",
            v.non_finite
        ));
    } else if let Some(r) = &mut v.reason
        && let Some(head) = r.strip_suffix(crate::stats::hypothesis::MORE_SAMPLES)
    {
        *r = format!("{head}judge more renders, each with seeds of its own, to tell");
    }
    v
}

/// Judge renders of one case file (a family of one test at `alpha`). When the case is
/// the `case.json` of an export folder (its `export.json` names it), the export's scale
/// and render size apply; a case whose pixels are not the reference itself (a flux,
/// judged as the receiver's mean irradiance) must be judged that way.
pub fn judge_case(
    case_file: &Path,
    renders: &[PathBuf],
    renderer: &str,
    alpha: f64,
) -> Result<Judgement, Error> {
    let case = load_case(case_file)?;
    let manifest = export_manifest(case_file)?;
    let (scale, size) = match &manifest {
        Some(m) => (m.scale, Some((m.width, m.height))),
        None => {
            if let crate::case::MeasureDesc::Flux { .. } = case.desc.measure {
                return Err(InputError::new(
                    case_file.display().to_string(),
                    "measure.flux",
                    "a renderer measures a flux as the receiver's mean irradiance: judge the `case.json` of its export folder (its export.json gives the scale), or `judge --suite`",
                )
                .into());
            }
            (1.0, None)
        }
    };
    let sample = sample(renders, size)?;
    let mut j = Judgement::new(
        &case,
        case_file.display().to_string(),
        renderer.to_string(),
        sample,
        scale,
    );
    j.judge(alpha, 1);
    Ok(j)
}

/// Load a case a render can measure: one `export` refuses for want of a renderer sensor
/// ([`crate::export::sensorless`]: a geometric integral, an emitter's power or intensity)
/// is bad input naming `measure`, since its reference is no pixel mean's expected value.
fn load_case(case_file: &Path) -> Result<Case, Error> {
    let case = Case::load(case_file)?;
    if let Some(why) = crate::export::sensorless(&case.desc.measure) {
        return Err(InputError::new(
            case_file.display().to_string(),
            "measure",
            format!(
                "{why}: a render's pixels cannot measure it (`lightproof export` refuses it too)"
            ),
        )
        .into());
    }
    Ok(case)
}

/// The manifest of the export folder holding `case_file`, if its `export.json` names it
/// (its `case`). One that names another file is not this case's and is not checked: only
/// its `case` is read (a file that is not JSON at all is bad input, since it may be).
fn export_manifest(case_file: &Path) -> Result<Option<Manifest>, InputError> {
    let dir = case_file.parent().unwrap_or(Path::new("."));
    let path = dir.join("export.json");
    if !path.is_file() {
        return Ok(None);
    }
    let v: serde_json::Value = read_json(&path)?;
    let own = v
        .get("case")
        .and_then(|c| c.as_str())
        .zip(case_file.file_name())
        .is_some_and(|(c, n)| *n == *c);
    if !own {
        return Ok(None);
    }
    read_manifest(&path).map(Some)
}

/// A judged suite: every rendered case, judged as one Šidák family, and the cases that
/// were exported but have no renders yet.
#[derive(Clone, Debug, Serialize)]
pub struct SuiteJudgement {
    /// Family-wise level.
    pub alpha: f64,
    /// Family size k.
    pub tests: usize,
    /// The judged cases.
    pub judgements: Vec<Judgement>,
    /// Exported cases without renders.
    pub not_rendered: Vec<String>,
    /// Cases the export refused, with the reason.
    pub refused: Vec<(String, String)>,
}

fn read_json<T: serde::de::DeserializeOwned>(path: &Path) -> Result<T, InputError> {
    let file = path.display().to_string();
    let text = crate::io::read_input(path, crate::io::MAX_JSON_BYTES)
        .map_err(|e| InputError::new(&file, "-", e))?;
    crate::error::parse_json(&file, &text)
}

/// Read an `export.json` and check the numbers the judge uses ([`Manifest::check`]).
fn read_manifest(path: &Path) -> Result<Manifest, InputError> {
    let m: Manifest = read_json(path)?;
    m.check(&path.display().to_string())?;
    Ok(m)
}

/// A suite's case ids are folders inside it, each listed once: an absolute id or one with
/// a `..` would judge files outside the suite, and a repeated one would count its renders
/// twice in the family (bad input naming `suite.json` and the index). An id that exists is
/// compared by its canonical path too, links resolved: a link to another case's folder, or
/// to a folder outside the suite, passed the names' check.
fn check_ids(dir: &Path, file: &Path, ids: &[String]) -> Result<(), InputError> {
    use std::path::Component;
    let root = dir.canonicalize().ok();
    let mut seen: Vec<(PathBuf, usize)> = Vec::new();
    for (i, id) in ids.iter().enumerate() {
        let field = format!("cases[{i}]");
        let bad = |why: String| InputError::new(file.display().to_string(), &field, why);
        let outside = Path::new(id).components().any(|c| {
            matches!(
                c,
                Component::ParentDir | Component::RootDir | Component::Prefix(_)
            )
        });
        if outside || id.is_empty() {
            return Err(bad(format!(
                "`{id}` is not a folder inside the suite (ids are relative paths without `..`)"
            )));
        }
        // The same folder however written (`c`, `./c`, `c/`): compared by its names.
        let folder = |x: &str| -> Vec<std::ffi::OsString> {
            Path::new(x)
                .components()
                .filter_map(|c| match c {
                    Component::Normal(n) => Some(n.to_os_string()),
                    Component::CurDir
                    | Component::ParentDir
                    | Component::RootDir
                    | Component::Prefix(_) => None,
                })
                .collect()
        };
        if let Some(j) = ids[..i].iter().position(|x| folder(x) == folder(id)) {
            return Err(bad(format!("`{id}` is listed twice (also cases[{j}])")));
        }
        if let (Some(root), Ok(real)) = (&root, dir.join(id).canonicalize()) {
            if !real.starts_with(root) || &real == root {
                return Err(bad(format!(
                    "`{id}` is `{}`, not a folder inside the suite (links resolved)",
                    real.display()
                )));
            }
            if let Some(&(_, j)) = seen.iter().find(|(p, _)| *p == real) {
                return Err(bad(format!(
                    "`{id}` is the folder of cases[{j}] (`{}`, links resolved): its renders would count twice",
                    ids[j]
                )));
            }
            seen.push((real, i));
        }
    }
    Ok(())
}

/// The renders of a suite's case: the `.exr` files (any case: `.EXR` too) of its `renders`
/// folder, hidden ones (`.name`) left out. No folder is a case not yet rendered (empty);
/// one that cannot be listed, or a file in its place, is bad input naming it (it once
/// read as "not rendered").
fn list_renders(folder: &Path) -> Result<Vec<PathBuf>, InputError> {
    let bad = |why: String| InputError::new(folder.display().to_string(), "-", why);
    match std::fs::metadata(folder) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(bad(format!("cannot read the renders folder: {e}"))),
        Ok(m) if !m.is_dir() => {
            return Err(bad("a file, not the folder of the case's renders".into()));
        }
        Ok(_) => {}
    }
    crate::io::collect_files(&[folder.to_path_buf()], false, |p| {
        p.extension().is_some_and(|x| x.eq_ignore_ascii_case("exr"))
            && !p
                .file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with('.'))
    })
}

/// Judge every rendered case of an exported suite folder (`suite.json`), as one family.
pub fn judge_suite(
    dir: &Path,
    renderer: Option<&str>,
    alpha: f64,
) -> Result<SuiteJudgement, Error> {
    let suite: Suite = read_json(&dir.join("suite.json"))?;
    check_ids(dir, &dir.join("suite.json"), &suite.cases)?;
    let mut judgements = Vec::new();
    let mut not_rendered = Vec::new();
    for id in &suite.cases {
        let d = dir.join(id);
        let manifest = read_manifest(&d.join("export.json"))?;
        let renders = list_renders(&d.join("renders"))?;
        if renders.is_empty() {
            not_rendered.push(id.clone());
            continue;
        }
        let label = renderer.map(str::to_string).unwrap_or_else(|| {
            read_json::<serde_json::Value>(&d.join("renders/render.json"))
                .ok()
                .and_then(|v| v.get("renderer").and_then(|r| r.as_str()).map(String::from))
                .unwrap_or_else(|| manifest.renderer.name().to_string())
        });
        let case = load_case(&d.join(&manifest.case))?;
        let sample = sample(&renders, Some((manifest.width, manifest.height)))?;
        judgements.push(Judgement::new(
            &case,
            id.clone(),
            label,
            sample,
            manifest.scale,
        ));
    }
    if judgements.is_empty() {
        return Err(InputError::new(
            dir.display().to_string(),
            "-",
            "no case of the suite has renders yet: run its render_all driver first",
        )
        .into());
    }
    let k = judgements.iter().filter(|j| j.is_statistical()).count();
    for j in &mut judgements {
        j.judge(alpha, k);
    }
    Ok(SuiteJudgement {
        alpha,
        tests: k,
        judgements,
        not_rendered,
        refused: suite.refused,
    })
}

/// The `judge` command: `files` = CASE.json then its renders, or a `suite` folder.
/// Returns the text to print (the table, or JSON) and whether everything passed.
pub fn run(
    files: &[PathBuf],
    suite: Option<&Path>,
    renderer: Option<&str>,
    json: bool,
    alpha: f64,
) -> Result<(String, bool), Error> {
    let usage = |why: String| Error::from(InputError::new("<command line>", "judge", why));
    // A blank name would label the renderer's row and JSON with nothing.
    if let Some(r) = renderer.filter(|r| r.trim().is_empty()) {
        return Err(InputError::new(
            "<command line>",
            "--renderer",
            format!("must name the renderer, got `{r}` (leave it out for `renderer`)"),
        )
        .into());
    }
    let (judgements, summary, doc) = match (suite, files) {
        (Some(dir), []) => {
            let s = judge_suite(dir, renderer, alpha)?;
            let failed = s.judgements.iter().filter(|j| !j.passed()).count();
            let summary = format!(
                "\n{} passed, {failed} failed  ({} cases judged, Šidák over k = {} at family α = {alpha}; {} exported cases without renders, {} refused by the export)\n",
                s.judgements.len() - failed,
                s.judgements.len(),
                s.tests,
                s.not_rendered.len(),
                s.refused.len()
            );
            let doc = serde_json::to_value(&s).unwrap_or_default();
            (s.judgements, summary, doc)
        }
        // The usage, each way it can be missed: nothing, a case without renders, both.
        (None, []) => {
            return Err(usage(
                "give CASE.json RENDER.exr... or --suite DIR: none was given".into(),
            ));
        }
        (None, [case]) => {
            return Err(usage(format!(
                "give CASE.json RENDER.exr... or --suite DIR: `{}` has no renders after it",
                case.display()
            )));
        }
        (None, [case, renders @ ..]) => {
            let j = judge_case(case, renders, renderer.unwrap_or("renderer"), alpha)?;
            let summary = format!(
                "\n{}  ({}: {} renders; {})\n",
                if j.passed() {
                    "1 passed, 0 failed"
                } else {
                    "0 passed, 1 failed"
                },
                j.renderer,
                j.sample.renders.len(),
                match j.sample.method {
                    Method::IndependentRenders => "replicates: independent renders",
                    Method::PixelBlocks =>
                        "replicates: batch means over pixel blocks of one render",
                }
            );
            let doc = serde_json::to_value(&j).unwrap_or_default();
            (vec![j], summary, doc)
        }
        (Some(_), [_, ..]) => {
            return Err(usage(
                "give CASE.json RENDER.exr... or --suite DIR, not both".into(),
            ));
        }
    };
    let passed = judgements.iter().all(Judgement::passed);
    let weak = judgements.iter().filter(|j| j.is_weak()).count();
    let summary = if weak > 0 {
        format!(
            "{summary}{weak} of the passes are weak: they cannot see a {}% bias, so they show agreement, not a proof: judge more renders (or more samples per render)\n",
            100.0 * crate::verdict::DETECTABLE_BOUND
        )
    } else {
        summary
    };
    let text = if json {
        format!(
            "{}\n",
            serde_json::to_string_pretty(&doc).unwrap_or_default()
        )
    } else {
        let rows: Vec<_> = judgements.iter().map(Judgement::row).collect();
        format!(
            "{}{summary}",
            crate::table::render(&rows, crate::table::terminal_width())
        )
    };
    Ok((text, passed))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Renders of the closed furnace (ρ = 0.5: L = 2) in a scratch folder, 8 × 8 pixels
    /// each, `edit` changing pixels after they are set to 2 ± 0.005.
    fn render(dir: &Path, name: &str, edit: impl Fn(&mut [[f32; 3]])) -> PathBuf {
        // A render's own offset (from its name) keeps renders apart: the replicates vary.
        let shift = 0.002 * (name.len() % 3) as f32 - 0.002;
        let mut px: Vec<[f32; 3]> = (0..64)
            .map(|i| [2.0 + shift + 0.01 * (((i * 37 % 64) as f32 + 0.5) / 64.0 - 0.5); 3])
            .collect();
        edit(&mut px);
        let p = dir.join(name);
        crate::render::write_exr(&p, 8, 8, &px).unwrap();
        p
    }

    fn furnace() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("analytic/cases/furnace/closed_sphere_0_5.json")
    }

    /// A renderer's pass that cannot see a 0.5 % bias is weak (its sample count is the
    /// renderer's choice, outside the proof), named in the table and the summary; one
    /// that can is a plain pass.
    #[test]
    fn a_pass_without_power_is_weak() {
        let dir =
            std::env::temp_dir().join(format!("lightproof-judge-weak-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        // Two renders 1.8 and 2.2: a t test with one degree of freedom sees nothing.
        let wide = [
            render(&dir, "lo.exr", |px| {
                px.iter_mut().for_each(|p| *p = p.map(|c| c - 0.2))
            }),
            render(&dir, "hi.exr", |px| {
                px.iter_mut().for_each(|p| *p = p.map(|c| c + 0.2))
            }),
        ];
        let j = judge_case(&furnace(), &wide, "r", 1e-4).unwrap();
        let v = j.verdict.as_ref().unwrap();
        assert!(j.passed() && v.weak && v.reason.is_none(), "{j:?}");
        assert!(v.detectable_relative_bias > crate::verdict::DETECTABLE_BOUND);
        assert_eq!(j.row().cells[6], "weak");
        let mut files = vec![furnace()];
        files.extend(wide);
        let (json, _) = run(&files, None, None, true, 1e-4).unwrap();
        let doc: serde_json::Value = serde_json::from_str(&json).unwrap();
        assert!(
            doc["verdict"]["weak"] == true && doc["verdict"]["passed"] == true,
            "{doc}"
        );
        let (text, passed) = run(&files, None, None, false, 1e-4).unwrap();
        assert!(passed, "{text}");
        assert!(
            text.contains("1 passed, 0 failed")
                && text.contains("1 of the passes are weak: they cannot see a 0.5% bias"),
            "{text}"
        );
        // One render of 64 pixels 2 ± 0.005 (32 blocks): it sees 0.5 %, a plain pass.
        let one = render(&dir, "one.exr", |_| {});
        let j = judge_case(&furnace(), std::slice::from_ref(&one), "r", 1e-4).unwrap();
        let v = j.verdict.as_ref().unwrap();
        assert!(
            j.passed() && !v.weak && v.detectable_relative_bias <= crate::verdict::DETECTABLE_BOUND,
            "{j:?}"
        );
        let (text, _) = run(&[furnace(), one], None, None, false, 1e-4).unwrap();
        assert!(!text.contains("weak"), "{text}");
        let _ = std::fs::remove_dir_all(dir);
    }

    /// `--renderer NAME` names the renderer in the JSON (`renderer`), and `--json` prints
    /// the judgement as one JSON object instead of the table.
    #[test]
    fn the_renderer_is_named_in_the_json() {
        let dir =
            std::env::temp_dir().join(format!("lightproof-judge-name-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let one = render(&dir, "one.exr", |_| {});
        let files = [furnace(), one];
        let (text, passed) = run(&files, None, Some("mitsuba 3.9.1"), true, 1e-4).unwrap();
        let doc: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert!(passed && doc["renderer"] == "mitsuba 3.9.1", "{doc}");
        assert_eq!(doc["verdict"]["passed"], true, "{doc}");
        let (table, _) = run(&files, None, None, false, 1e-4).unwrap();
        assert!(table.contains("(renderer: 1 renders;"), "{table}");
        // Nothing, a case without renders, or a suite with files besides: the usage, not
        // a verdict, each told as it was missed.
        for (files, suite, why) in [
            (&files[..0], None, ": none was given"),
            (&files[..1], None, "has no renders after it"),
            (&files[..], Some(dir.as_path()), ", not both"),
        ] {
            let err = run(files, suite, None, false, 1e-4)
                .unwrap_err()
                .to_string();
            assert!(
                err.starts_with(
                    "<command line>: judge: give CASE.json RENDER.exr... or --suite DIR"
                ) && err.contains(why),
                "{err}"
            );
        }
        // A blank renderer name is refused, naming the flag.
        for blank in ["", "  "] {
            let err = run(&files, None, Some(blank), false, 1e-4)
                .unwrap_err()
                .to_string();
            assert!(
                err.starts_with("<command line>: --renderer: must name the renderer"),
                "{err}"
            );
        }
        let _ = std::fs::remove_dir_all(dir);
    }

    /// A channel below zero is counted per pixel (in row-major order the first is named)
    /// even where the pixel's mean is the reference, and fails a verdict that passes
    /// without it; non-finite pixels are counted apart.
    #[test]
    fn negative_channels_are_counted_and_fail_the_verdict() {
        let dir = std::env::temp_dir().join(format!("lightproof-judge-neg-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let clean = [
            render(&dir, "a.exr", |_| {}),
            render(&dir, "bb.exr", |_| {}),
        ];
        let j = judge_case(&furnace(), &clean, "r", 1e-4).unwrap();
        assert!(j.passed() && j.sample.negative == 0, "{j:?}");
        // Two pixels whose R is negative, their means kept at 2: (−0.5 + 3.25 + 3.25)/3.
        let neg = render(&dir, "neg.exr", |px| {
            px[42] = [-0.5, 3.25, 3.25];
            px[13] = [3.25, -0.5, 3.25];
            px[20] = [f32::NAN; 3];
        });
        let r = read_render(&neg).unwrap();
        assert_eq!(r.negative, (2, Some(((5, 1), [3.25, -0.5, 3.25]))));
        let j = judge_case(&furnace(), &[clean[0].clone(), neg.clone()], "r", 1e-4).unwrap();
        assert_eq!((j.sample.negative, j.sample.non_finite), (2, 1), "{j:?}");
        assert!(!j.passed(), "{j:?}");
        let v = j.verdict.as_ref().unwrap();
        let why = v.reason.as_deref().unwrap_or_default();
        assert!(
            why.starts_with(
                "1 non-finite pixels (NaN or Inf): the renderer's answer is not a number"
            ) && why.ends_with("; 2 pixels with a negative channel (negative radiance)"),
            "{why}"
        );
        assert!(
            j.sample.notes.iter().any(|n| n.ends_with(
                "2 pixels with a negative channel (negative radiance), the first at (5, 1) = (3.25, -0.5, 3.25)"
            )),
            "{:?}",
            j.sample.notes
        );
        // The negative pixels alone (no NaN): the statistic passes, the verdict does not.
        let only_neg = render(&dir, "only.exr", |px| px[42] = [-0.5, 3.25, 3.25]);
        let j = judge_case(
            &furnace(),
            &[clean[0].clone(), clean[1].clone(), only_neg],
            "r",
            1e-4,
        )
        .unwrap();
        let v = j.verdict.as_ref().unwrap();
        assert!(v.z.abs() < 3.0 && !v.passed && !j.passed(), "{j:?}");
        assert_eq!(
            v.reason.as_deref(),
            Some("1 pixels with a negative channel (negative radiance)")
        );
        // A pixel's value is the mean of its three channels; a channel of 0 is not
        // negative, and a negative blue counts as much as a red.
        let mixed = render(&dir, "mixed.exr", |px| {
            px[0] = [1.0, 2.0, 3.0];
            px[1] = [0.0, 3.0, 3.0];
            px[2] = [3.0, 0.0, 3.0];
            px[3] = [3.0, 3.0, 0.0];
            px[4] = [3.25, 3.25, -0.5];
        });
        let r = read_render(&mixed).unwrap();
        assert_eq!(r.pixels[0], 2.0);
        assert_eq!(r.pixels[1], 2.0);
        assert_eq!(r.negative, (1, Some(((4, 0), [3.25, 3.25, -0.5]))));
        // Blocks stored bottom row first (decreasing line order): the first negative
        // pixel in row-major order is still the one named, whatever order rows arrive in.
        let decreasing = dir.join("decreasing.exr");
        {
            use exr::prelude::*;
            // Rows arrive 7, 6, 5, 4, …: (0, 6) is met first, then (7, 5) and (6, 4),
            // each earlier in row-major order than the one kept before it.
            let neg = |x: usize, y: usize| [(0, 6), (7, 5), (6, 4)].contains(&(x, y));
            let channels = SpecificChannels::rgb(|p: Vec2<usize>| {
                if neg(p.x(), p.y()) {
                    (-1.0f32, 2.0f32, 2.0f32)
                } else {
                    (2.0f32, 2.0f32, 2.0f32)
                }
            });
            let encoding = Encoding {
                line_order: LineOrder::Decreasing,
                ..Encoding::UNCOMPRESSED
            };
            Image::from_encoded_channels((8, 8), encoding, channels)
                .write()
                .to_file(&decreasing)
                .unwrap();
        }
        let r = read_render(&decreasing).unwrap();
        assert_eq!(r.negative, (3, Some(((6, 4), [-1.0, 2.0, 2.0]))));
        // One render: batch means over 32 blocks of pixels.
        let one = judge_case(&furnace(), &[mixed], "r", 1e-4).unwrap();
        assert_eq!(one.sample.method, Method::PixelBlocks);
        assert_eq!((one.sample.replicates.len(), one.dof), (32, Some(31)));
        // Without a reference, the counts alone decide.
        let mut j = j;
        j.verdict = None;
        assert!(!j.passed());
        j.sample.negative = 0;
        assert!(j.passed());
        let _ = std::fs::remove_dir_all(dir);
    }

    /// One render's batch means take min(32, n) blocks of its n pixels and drop a block
    /// without a finite pixel: 40 pixels whose first is NaN give 31 replicates (t with 30
    /// degrees of freedom), 8 pixels 8 blocks of one (7).
    #[test]
    fn one_renders_blocks_follow_its_pixels() {
        let dir = scratch("blocks");
        let write = |name: &str, n: usize, nan_first: bool| {
            let px: Vec<[f32; 3]> = (0..n)
                .map(|i| match i {
                    0 if nan_first => [f32::NAN; 3],
                    _ => [2.0 + 0.01 * ((i * 37 % n) as f32 / n as f32 - 0.5); 3],
                })
                .collect();
            let p = dir.join(name);
            crate::render::write_exr(&p, n, 1, &px).unwrap();
            p
        };
        for (name, n, nan_first, blocks) in [("nan.exr", 40, true, 31), ("eight.exr", 8, false, 8)]
        {
            let j = judge_case(&furnace(), &[write(name, n, nan_first)], "r", 1e-4).unwrap();
            assert_eq!(j.sample.method, Method::PixelBlocks);
            assert_eq!(
                (j.sample.replicates.len(), j.dof),
                (blocks, Some(blocks as u64 - 1)),
                "{name}"
            );
        }
        let _ = std::fs::remove_dir_all(dir);
    }

    fn case(path: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("analytic/cases")
            .join(path)
    }

    fn scratch(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("lightproof-judge-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// A file of two parts, the first holding only depth (Z) and the second R, G and B:
    /// the reader takes the second, and so does the check of its channels (it once
    /// blamed the file for "no R channel (channels: Z)"). With no part holding all three,
    /// the message lists each part's channels (in braces where the file has several parts).
    #[test]
    fn the_part_with_r_g_and_b_is_the_render() {
        use exr::prelude::*;
        let size = Vec2(4, 2);
        let depth = Layer::new(
            size,
            LayerAttributes::named("depth"),
            Encoding::UNCOMPRESSED,
            AnyChannels::sort(SmallVec::from_vec(vec![AnyChannel::new(
                "Z",
                FlatSamples::F32(vec![1.0; 8]),
            )])),
        );
        let colour = |name: &str, rgb: &[&str]| {
            Layer::new(
                size,
                LayerAttributes::named(name),
                Encoding::UNCOMPRESSED,
                AnyChannels::sort(
                    rgb.iter()
                        .map(|c| AnyChannel::new(*c, FlatSamples::F32(vec![0.5; 8])))
                        .collect(),
                ),
            )
        };
        let write = |name: &str, rgb: &[&str]| {
            let path = scratch("parts").join(name);
            Image::from_layers(
                ImageAttributes::new(IntegerBounds::from_dimensions(size)),
                vec![depth.clone(), colour("beauty", rgb)],
            )
            .write()
            .to_file(&path)
            .unwrap();
            path
        };
        let both = write("parts.exr", &["R", "G", "B"]);
        let r = read_render(&both).unwrap();
        assert_eq!((r.width, r.height), (4, 2));
        assert!(r.pixels.iter().all(|&v| v == 0.5), "{:?}", r.pixels);
        let Err(e) = read_render(&write("parts_no_b.exr", &["R", "G"])) else {
            panic!("a file without B read as a render")
        };
        assert!(
            e.reason.contains("no B channel (channels: {Z}; {G, R})"),
            "{e}"
        );
        // One part: its channels listed without braces.
        let path = scratch("parts").join("one_part_no_b.exr");
        Image::from_layers(
            ImageAttributes::new(IntegerBounds::from_dimensions(size)),
            vec![colour("beauty", &["R", "G"])],
        )
        .write()
        .to_file(&path)
        .unwrap();
        let Err(e) = read_render(&path) else {
            panic!("a one-part file without B read as a render")
        };
        assert!(e.reason.contains("no B channel (channels: G, R);"), "{e}");
        let _ = std::fs::remove_file(both);
        let _ = std::fs::remove_file(path);
    }

    /// An EXR whose block of line 1 claims line 0 (the reader, not pedantic, takes it)
    /// leaves line 1 unwritten: refused, naming the line, not read as pixels of 0 (four
    /// renders 14 % high, each missing a line of 8, once passed exactly). An empty file
    /// says it is empty.
    #[test]
    fn a_render_missing_a_line_is_refused() {
        use exr::prelude::*;
        let dir = scratch("line");
        let path = dir.join("dup.exr");
        let v = 16.0f32 / 7.0;
        Image::from_encoded_channels(
            (8, 8),
            Encoding::UNCOMPRESSED,
            SpecificChannels::rgb(|_: Vec2<usize>| (v, v, v)),
        )
        .write()
        .to_file(&path)
        .unwrap();
        let whole = read_render(&path).unwrap();
        assert!(whole.pixels.iter().all(|&p| p == v as f64));
        // The offset table (8 blocks of one line) ends where the first block starts.
        let mut bytes = std::fs::read(&path).unwrap();
        let at = |b: &[u8], i: usize| u64::from_le_bytes(b[i..i + 8].try_into().unwrap()) as usize;
        let table = (0..bytes.len() - 8)
            .find(|&i| at(&bytes, i) == i + 64)
            .unwrap();
        let block = at(&bytes, table + 8);
        assert_eq!(bytes[block..block + 4], 1i32.to_le_bytes());
        bytes[block..block + 4].copy_from_slice(&0i32.to_le_bytes());
        std::fs::write(&path, &bytes).unwrap();
        let e = read_render(&path).err().unwrap();
        assert!(
            e.file.ends_with("dup.exr")
                && e.reason.starts_with(
                    "line 1 of 8 has no pixel data (8 pixels missing, the first at (0, 1))"
                ),
            "{e}"
        );
        let empty = dir.join("empty.exr");
        std::fs::write(&empty, b"").unwrap();
        let e = read_render(&empty).err().unwrap();
        assert_eq!(e.reason, "the file is empty (0 bytes), not an EXR", "{e}");
        let _ = std::fs::remove_dir_all(dir);
    }

    /// A case `export` refuses for want of a renderer sensor (an emitter's power or
    /// intensity, a geometric integral) is refused naming `measure`, however close its
    /// pixels (a power case once passed against pixel means); spectral and time-resolved
    /// cases of a measure a sensor has are judged as before.
    #[test]
    fn cases_without_a_renderer_sensor_are_refused() {
        let dir = scratch("sensor");
        let renders = [
            render(&dir, "a.exr", |_| {}),
            render(&dir, "bb.exr", |_| {}),
        ];
        for c in [
            "power/disk.json",
            "intensity/rectangle_0.json",
            "solid_angle/triangle.json",
        ] {
            let e = judge_case(&case(c), &renders, "r", 1e-4).unwrap_err();
            let Error::Input(e) = e else {
                panic!("{c}: {e}")
            };
            assert!(
                e.file.ends_with(c)
                    && e.field == "measure"
                    && e.reason.contains("a render's pixels cannot measure it"),
                "{e}"
            );
        }
        for c in [
            "time/pulsed_disk_bin.json",
            "spectral/blackbody_total_radiance.json",
        ] {
            let j = judge_case(&case(c), &renders, "r", 1e-4);
            assert!(j.is_ok(), "{c}: {:?}", j.err());
        }
        let _ = std::fs::remove_dir_all(dir);
    }

    /// A foreign renderer's failure is told in its terms: non-finite pixels without
    /// lightproof's bounce guard, and renders that agree exactly yet miss the reference
    /// ask for more renders, not more samples.
    #[test]
    fn failures_are_told_in_the_renderers_terms() {
        let dir = scratch("terms");
        let nan = [
            render(&dir, "a.exr", |_| {}),
            render(&dir, "bb.exr", |px| px[3] = [f32::INFINITY; 3]),
        ];
        let j = judge_case(&furnace(), &nan, "r", 1e-4).unwrap();
        let why = j.verdict.as_ref().unwrap().reason.clone().unwrap();
        assert_eq!(
            why,
            "1 non-finite pixels (NaN or Inf): the renderer's answer is not a number"
        );
        let flat = |name| render(&dir, name, |px| px.iter_mut().for_each(|p| *p = [2.5; 3]));
        let j = judge_case(&furnace(), &[flat("c.exr"), flat("dd.exr")], "r", 1e-4).unwrap();
        let why = j.verdict.as_ref().unwrap().reason.clone().unwrap();
        assert!(
            !j.passed()
                && why.starts_with("no variance in 2 samples")
                && why.ends_with("judge more renders, each with seeds of its own, to tell"),
            "{why}"
        );
        let _ = std::fs::remove_dir_all(dir);
    }

    /// A suite whose `suite.json` lists an id twice, an absolute id or one leaving the
    /// folder is refused naming `cases[i]`; a file in place of a `renders` folder is an
    /// error, not "not rendered"; renders named `.EXR` are judged.
    #[test]
    fn a_suites_ids_and_renders_are_checked() {
        let dir = scratch("suite");
        let c = dir.join("c");
        std::fs::create_dir_all(c.join("renders")).unwrap();
        std::fs::copy(furnace(), c.join("case.json")).unwrap();
        let manifest = Manifest {
            renderer: crate::export::Target::Mitsuba,
            source: "f.json".into(),
            name: "furnace".into(),
            case: "case.json".into(),
            scene: "scene.xml".into(),
            sensor: "camera_inside".into(),
            width: 8,
            height: 8,
            scale: 1.0,
            conventions: vec![],
        };
        std::fs::write(
            c.join("export.json"),
            serde_json::to_string(&manifest).unwrap(),
        )
        .unwrap();
        render(&c.join("renders"), "000.EXR", |_| {});
        render(&c.join("renders"), "001.exr", |_| {});
        // Neither a hidden render nor a file of another kind is a render.
        render(&c.join("renders"), ".002.exr", |_| {});
        std::fs::write(c.join("renders").join("notes.txt"), b"not a render").unwrap();
        let suite = |ids: &[&str]| {
            let doc = serde_json::json!({"renderer": "mitsuba", "cases": ids, "refused": []});
            std::fs::write(dir.join("suite.json"), doc.to_string()).unwrap();
            judge_suite(&dir, None, 1e-4)
        };
        let s = suite(&["c"]).unwrap();
        assert_eq!(s.judgements[0].sample.renders.len(), 2);
        assert!(s.judgements[0].passed());
        for (ids, field, why) in [
            (&["c", "c"][..], "cases[1]", "listed twice (also cases[0])"),
            (
                &["c", "./c"][..],
                "cases[1]",
                "listed twice (also cases[0])",
            ),
            (&["c/", "c"][..], "cases[1]", "listed twice (also cases[0])"),
            (
                &["c", "../c"][..],
                "cases[1]",
                "not a folder inside the suite",
            ),
            (&["/tmp"][..], "cases[0]", "not a folder inside the suite"),
            (
                &["c/x/../../c"][..],
                "cases[0]",
                "not a folder inside the suite",
            ),
        ] {
            let Err(Error::Input(e)) = suite(ids) else {
                panic!("{ids:?} accepted")
            };
            assert!(
                e.file.ends_with("suite.json") && e.field == field && e.reason.contains(why),
                "{ids:?}: {e}"
            );
        }
        std::fs::remove_dir_all(c.join("renders")).unwrap();
        // No renders folder yet: a case not rendered (here the only one, so the suite
        // has nothing to judge), not an error about the folder.
        let Err(Error::Input(e)) = suite(&["c"]) else {
            panic!("a suite without renders judged")
        };
        assert!(
            e.reason.contains("no case of the suite has renders yet"),
            "{e}"
        );
        std::fs::write(c.join("renders"), b"").unwrap();
        let Err(Error::Input(e)) = suite(&["c"]) else {
            panic!("a file for renders/ accepted")
        };
        assert!(
            e.file.ends_with("renders") && e.reason.contains("not the folder"),
            "{e}"
        );
        // A renders folder that cannot be read (a link to itself) is an error, not
        // "not rendered".
        std::fs::remove_file(c.join("renders")).unwrap();
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink("renders", c.join("renders")).unwrap();
            let Err(Error::Input(e)) = suite(&["c"]) else {
                panic!("an unreadable renders/ accepted")
            };
            assert!(e.reason.contains("cannot read the renders folder"), "{e}");
        }
        let _ = std::fs::remove_dir_all(dir);
    }

    /// An `export.json` beside a case is the case's only when its `case` names the file:
    /// one naming another case is not checked (its bad numbers are not this case's).
    #[test]
    fn only_the_cases_own_export_json_is_read() {
        let dir = scratch("own");
        std::fs::copy(furnace(), dir.join("mine.json")).unwrap();
        let other = serde_json::json!({"case": "other.json", "width": 0, "scale": -1});
        std::fs::write(dir.join("export.json"), other.to_string()).unwrap();
        let renders = [
            render(&dir, "a.exr", |_| {}),
            render(&dir, "bb.exr", |_| {}),
        ];
        let j = judge_case(&dir.join("mine.json"), &renders, "r", 1e-4);
        assert!(j.is_ok_and(|j| j.passed()));
        let mine = serde_json::json!({"case": "mine.json", "width": 0, "scale": -1});
        std::fs::write(dir.join("export.json"), mine.to_string()).unwrap();
        assert!(judge_case(&dir.join("mine.json"), &renders, "r", 1e-4).is_err());
        // Read for its `case` whatever it names: one that is not JSON is refused, named.
        std::fs::write(dir.join("export.json"), "{not json").unwrap();
        let e = judge_case(&dir.join("mine.json"), &renders, "r", 1e-4).unwrap_err();
        assert!(e.to_string().contains("export.json"), "{e}");
        let _ = std::fs::remove_dir_all(dir);
    }
}
