//! Chi-square goodness of fit of a sampler against its density.
//!
//! The domain (sphere, hemisphere, unit square or unit disk) is cut into equal-area
//! cells of a parameterisation with constant Jacobian: (cos θ, φ) on the sphere and
//! hemisphere, (x, y) on the square and (r², φ) on the disk. N samples are binned; the
//! expected count of a cell is N times the integral of the density over it, computed
//! by adaptive 2-D Gauss–Legendre quadrature (a tensor 4×4 rule against the same rule
//! on the cell's four children, refined where they disagree; pbrt-v4 and Mitsuba 3 use
//! a fixed rule per cell, which misses sharp lobes and falsely rejects). Cells with expected count < 5 are pooled, smallest first.
//! The statistic Σ(O − E)²/E has (cells − 1) degrees of freedom; its p value comes from
//! statrs's `ChiSquared::sf` (accurate to tiny p, unlike `1 − cdf`).
//!
//! Three further checks make the test hard to fool:
//! - a sample in a cell whose expected count is exactly zero fails at once;
//! - the density must integrate over the domain to the fraction of samples the sampler
//!   returned (a density off by a constant factor passes a normalised histogram test);
//! - the quadrature's estimated error must be far below the statistical error
//!   (it may move the statistic by at most a tenth of its standard deviation), else
//!   the test says so instead of judging.
//!
//! On failure the observed, expected and (O − E)/√E tables are written as JSON and EXR
//! images under `target/chi2-failures/`, and [`Chi2Outcome::reason`] names the files.

use crate::sampling::Sampler;
use glam::Vec3;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use statrs::distribution::{ChiSquared, ContinuousCDF, Normal};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

/// The domain a sampler draws from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Domain {
    /// Unit directions; cells in (cos θ ∈ [−1, 1], φ).
    Sphere,
    /// Unit directions with z ≥ 0; cells in (cos θ ∈ [0, 1], φ).
    Hemisphere,
    /// Points (x, y, 0) of [0, 1]²; cells in (y, x).
    Square,
    /// Points (x, y, 0) of the unit disk; cells in (r², φ).
    Disk,
}

impl Domain {
    /// Range of the row parameter.
    fn a_range(&self) -> (f64, f64) {
        match self {
            Domain::Sphere => (-1.0, 1.0),
            Domain::Hemisphere | Domain::Square | Domain::Disk => (0.0, 1.0),
        }
    }

    /// Range of the column parameter.
    fn b_range(&self) -> (f64, f64) {
        match self {
            Domain::Square => (0.0, 1.0),
            Domain::Sphere | Domain::Hemisphere | Domain::Disk => (0.0, 2.0 * PI),
        }
    }

    /// Measure per unit parameter area (dω = d cos θ dφ; dA = ½ d(r²) dφ).
    fn jacobian(&self) -> f64 {
        match self {
            Domain::Disk => 0.5,
            Domain::Sphere | Domain::Hemisphere | Domain::Square => 1.0,
        }
    }

    /// Point at parameters (a, b).
    fn point(&self, a: f64, b: f64) -> Vec3 {
        match self {
            Domain::Sphere | Domain::Hemisphere => {
                let s = (1.0 - a * a).max(0.0).sqrt();
                Vec3::new((s * b.cos()) as f32, (s * b.sin()) as f32, a as f32)
            }
            Domain::Square => Vec3::new(b as f32, a as f32, 0.0),
            Domain::Disk => {
                let r = a.max(0.0).sqrt();
                Vec3::new((r * b.cos()) as f32, (r * b.sin()) as f32, 0.0)
            }
        }
    }

    /// Parameters of a point, or `None` outside the domain.
    fn params(&self, p: Vec3) -> Option<(f64, f64)> {
        let (x, y, z) = (p.x as f64, p.y as f64, p.z as f64);
        let phi = || {
            let f = y.atan2(x);
            if f < 0.0 { f + 2.0 * PI } else { f }
        };
        match self {
            Domain::Sphere => {
                let l = (x * x + y * y + z * z).sqrt();
                ((l - 1.0).abs() < 1e-3).then(|| ((z / l).clamp(-1.0, 1.0), phi()))
            }
            Domain::Hemisphere => {
                let l = (x * x + y * y + z * z).sqrt();
                ((l - 1.0).abs() < 1e-3 && z >= 0.0).then(|| ((z / l).min(1.0), phi()))
            }
            Domain::Square => {
                ((0.0..=1.0).contains(&x) && (0.0..=1.0).contains(&y)).then_some((y, x))
            }
            Domain::Disk => {
                let r2 = x * x + y * y;
                (r2 <= 1.0 + 1e-6).then(|| (r2.min(1.0), phi()))
            }
        }
    }
}

/// A chi-square test configuration.
#[derive(Clone, Debug)]
pub struct Chi2Test {
    /// Domain.
    pub domain: Domain,
    /// Cells along the row parameter (cos θ, y or r²).
    pub rows: usize,
    /// Cells along the column parameter (φ or x).
    pub cols: usize,
    /// Number of samples drawn.
    pub samples: u64,
    /// Seed of the independent sample stream.
    pub seed: u64,
    /// Per-test significance (already Šidák-corrected for the suite).
    pub alpha: f64,
    /// Folder for the failure tables (default [`failure_dir`]).
    pub dump_dir: PathBuf,
}

/// The outcome of a chi-square test.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Chi2Outcome {
    /// Name of the sampler under test.
    pub name: String,
    /// Σ (O − E)²/E over pooled cells.
    pub statistic: f64,
    /// Degrees of freedom.
    pub dof: usize,
    /// P value of the statistic.
    pub p_value: f64,
    /// Per-test significance used.
    pub alpha: f64,
    /// ∫ pdf over the domain (by quadrature).
    pub pdf_integral: f64,
    /// Fraction of draws the sampler returned a sample for.
    pub success_fraction: f64,
    /// z of (∫ pdf − success fraction).
    pub normalisation_z: f64,
    /// Upper bound of the quadrature error's contribution to the statistic, in units of
    /// the statistic's standard deviation √(2 dof); must stay below 0.1.
    pub quadrature_share: f64,
    /// Whether every check passed.
    pub passed: bool,
    /// Why it failed (naming the dump files).
    pub reason: Option<String>,
    /// Files written on failure.
    pub dump: Vec<PathBuf>,
}

impl Chi2Test {
    /// Default resolution for a domain: 64 × 128 on the sphere (≈ 0.0015 sr per cell),
    /// 32 × 128 on the hemisphere, 64 × 64 on the square and disk.
    pub fn new(domain: Domain, samples: u64, seed: u64, alpha: f64) -> Self {
        let (rows, cols) = match domain {
            Domain::Sphere => (64, 128),
            Domain::Hemisphere => (32, 128),
            Domain::Square | Domain::Disk => (64, 64),
        };
        Chi2Test {
            domain,
            rows,
            cols,
            samples,
            seed,
            alpha,
            dump_dir: failure_dir(),
        }
    }

    /// Write failure tables into `dir` instead of [`failure_dir`].
    pub fn with_dump_dir(mut self, dir: impl Into<PathBuf>) -> Self {
        self.dump_dir = dir.into();
        self
    }

    /// Set the resolution.
    pub fn with_resolution(mut self, rows: usize, cols: usize) -> Self {
        self.rows = rows.max(1);
        self.cols = cols.max(1);
        self
    }

    fn cell_of(&self, a: f64, b: f64) -> usize {
        let (a0, a1) = self.domain.a_range();
        let (b0, b1) = self.domain.b_range();
        let r = (((a - a0) / (a1 - a0)) * self.rows as f64) as usize;
        let c = (((b - b0) / (b1 - b0)) * self.cols as f64) as usize;
        r.min(self.rows - 1) * self.cols + c.min(self.cols - 1)
    }

    /// Histogram of the sampler: (counts per cell, successes, outside-domain samples).
    pub fn histogram<S>(&self, sample: &S) -> (Vec<u64>, u64, u64)
    where
        S: Fn(Vec3) -> Option<Vec3> + Sync,
    {
        let sampler = Sampler::independent(self.seed);
        let cells = self.rows * self.cols;
        const BLOCK: u64 = 1 << 14;
        let blocks = self.samples.div_ceil(BLOCK);
        (0..blocks)
            .into_par_iter()
            .map(|blk| {
                let mut h = vec![0u64; cells];
                let (mut ok, mut outside) = (0u64, 0u64);
                for i in blk * BLOCK..((blk + 1) * BLOCK).min(self.samples) {
                    let mut s = sampler.stream(i);
                    let u = Vec3::new(s.next_1d(), s.next_1d(), s.next_1d());
                    if let Some(p) = sample(u) {
                        ok += 1;
                        match self.domain.params(p) {
                            Some((a, b)) if p.is_finite() => h[self.cell_of(a, b)] += 1,
                            _ => outside += 1,
                        }
                    }
                }
                (h, ok, outside)
            })
            .reduce(
                || (vec![0u64; cells], 0, 0),
                |(mut h1, o1, x1), (h2, o2, x2)| {
                    h1.iter_mut().zip(&h2).for_each(|(a, b)| *a += b);
                    (h1, o1 + o2, x1 + x2)
                },
            )
    }

    /// Integral of the density over every cell, with the quadrature's error estimate.
    pub fn integrate_pdf<P>(&self, pdf: &P) -> Vec<(f64, f64)>
    where
        P: Fn(Vec3) -> f64 + Sync,
    {
        let (a0, a1) = self.domain.a_range();
        let (b0, b1) = self.domain.b_range();
        let da = (a1 - a0) / self.rows as f64;
        let db = (b1 - b0) / self.cols as f64;
        let jac = self.domain.jacobian();
        let abs_tol = 1e-3 / self.samples.max(1) as f64;
        let f = |a: f64, b: f64| {
            let v = pdf(self.domain.point(a, b));
            if v.is_finite() && v > 0.0 {
                v * jac
            } else {
                0.0
            }
        };
        (0..self.rows * self.cols)
            .into_par_iter()
            .map(|cell| {
                let (r, c) = (cell / self.cols, cell % self.cols);
                let ra = (a0 + r as f64 * da, a0 + (r + 1) as f64 * da);
                let rb = (b0 + c as f64 * db, b0 + (c + 1) as f64 * db);
                let coarse = gauss_4x4(&f, ra, rb);
                adaptive_quadrature_2d(&f, ra, rb, coarse, abs_tol, 0)
            })
            .collect()
    }

    fn integrate_cell_finely<P>(&self, pdf: &P, cell: usize) -> (f64, f64)
    where
        P: Fn(Vec3) -> f64 + Sync,
    {
        let (a0, a1) = self.domain.a_range();
        let (b0, b1) = self.domain.b_range();
        let da = (a1 - a0) / self.rows as f64;
        let db = (b1 - b0) / self.cols as f64;
        let jac = self.domain.jacobian();
        let f = |a: f64, b: f64| {
            let v = pdf(self.domain.point(a, b));
            if v.is_finite() && v > 0.0 {
                v * jac
            } else {
                0.0
            }
        };
        let (r, c) = (cell / self.cols, cell % self.cols);
        const SPLIT: usize = 32;
        let tol = 1e-3 / self.samples.max(1) as f64 / (SPLIT * SPLIT) as f64;
        let mut total = (0.0, 0.0);
        for i in 0..SPLIT {
            for j in 0..SPLIT {
                let sa = da / SPLIT as f64;
                let sb = db / SPLIT as f64;
                let qa = (
                    a0 + r as f64 * da + i as f64 * sa,
                    a0 + r as f64 * da + (i + 1) as f64 * sa,
                );
                let qb = (
                    b0 + c as f64 * db + j as f64 * sb,
                    b0 + c as f64 * db + (j + 1) as f64 * sb,
                );
                let (v, e) = adaptive_quadrature_2d(&f, qa, qb, gauss_4x4(&f, qa, qb), tol, 5);
                total.0 += v;
                total.1 += e;
            }
        }
        total
    }

    /// The histogram of `sample` and the expected counts from `pdf`, cell by cell, each
    /// computed once (where samples fell but the quadrature saw no density, the cell is
    /// integrated again on a 32 × 32 sub-grid: the density may cover a sliver between
    /// the nodes).
    pub fn tables<S, P>(&self, sample: S, pdf: P) -> Chi2Tables
    where
        S: Fn(Vec3) -> Option<Vec3> + Sync,
        P: Fn(Vec3) -> f64 + Sync,
    {
        let (observed, successes, outside) = self.histogram(&sample);
        let mut integrals = self.integrate_pdf(&pdf);
        for (i, cell) in integrals.iter_mut().enumerate() {
            if observed[i] > 0 && cell.0 == 0.0 {
                *cell = self.integrate_cell_finely(&pdf, i);
            }
        }
        let n = self.samples as f64;
        Chi2Tables {
            rows: self.rows,
            cols: self.cols,
            samples: self.samples,
            observed,
            expected: integrals.iter().map(|(v, _)| v * n).collect(),
            quadrature_error: integrals.iter().map(|(_, e)| *e).collect(),
            successes,
            outside,
        }
    }

    /// Run the test on `sample` (uniform numbers → point, or `None` for a failed draw)
    /// against `pdf` (point → density in the domain's measure).
    pub fn run<S, P>(&self, name: &str, sample: S, pdf: P) -> Chi2Outcome
    where
        S: Fn(Vec3) -> Option<Vec3> + Sync,
        P: Fn(Vec3) -> f64 + Sync,
    {
        self.judge(name, &self.tables(sample, pdf))
    }

    /// Judge tables made by [`Chi2Test::tables`] with this test's settings.
    pub fn judge(&self, name: &str, t: &Chi2Tables) -> Chi2Outcome {
        let n = self.samples as f64;
        let (observed, expected) = (&t.observed, &t.expected);
        let pdf_integral: f64 = expected.iter().sum::<f64>() / n;
        let quad_err: f64 = t.quadrature_error.iter().sum();
        // What the quadrature error could add to the statistic: Σ (δ N)² / E.
        let quadrature_chi2: f64 = expected
            .iter()
            .zip(&t.quadrature_error)
            .map(|(e_n, e)| (e * n).powi(2) / e_n.max(1.0))
            .sum();
        let success_fraction = t.successes as f64 / n;

        let mut reasons = Vec::new();
        if t.outside > 0 {
            reasons.push(format!(
                "{} samples fell outside the {:?} domain or were not finite",
                t.outside, self.domain
            ));
        }
        let zero_cells: Vec<usize> = (0..observed.len())
            .filter(|&i| observed[i] > 0 && expected[i] == 0.0)
            .collect();
        if !zero_cells.is_empty() {
            reasons.push(format!(
                "{} cells hold samples where the pdf integrates to zero (first: row {}, col {})",
                zero_cells.len(),
                zero_cells[0] / self.cols,
                zero_cells[0] % self.cols
            ));
        }
        let pooled = pool(observed, expected);
        // Too few samples to fill two pooled cells: there is nothing to judge with, and
        // a statistic of 0 with p = 1 would pass vacuously.
        if pooled.iter().filter(|(_, e)| *e >= 5.0).count() < 2 {
            reasons.push(format!(
                "too few samples to judge: {} samples fill fewer than two cells with an expected count ≥ 5 (give at least {} for the {} × {} grid)",
                self.samples,
                5 * self.rows * self.cols,
                self.rows,
                self.cols
            ));
        }
        let statistic: f64 = pooled
            .iter()
            .filter(|(_, e)| *e > 0.0)
            .map(|(o, e)| (o - e) * (o - e) / e)
            .sum();
        let dof = pooled.len().saturating_sub(1).max(1);
        let p_value = ChiSquared::new(dof as f64)
            .map(|d| d.sf(statistic))
            .unwrap_or(0.0);
        if p_value < self.alpha {
            reasons.push(format!(
                "chi-square statistic {statistic:.1} with {dof} dof has p = {p_value:.3e} < α = {:.3e}",
                self.alpha
            ));
        }

        // Normalisation: ∫ pdf = fraction of successful draws.
        let f = success_fraction;
        let binom_var = (f * (1.0 - f)).max(1.0 / n) / n;
        let normalisation_z = (pdf_integral - f) / (binom_var + quad_err * quad_err).sqrt();
        let crit = Normal::standard().inverse_cdf(1.0 - self.alpha / 2.0);
        if normalisation_z.abs() > crit {
            reasons.push(format!(
                "pdf integrates to {pdf_integral:.6} but {:.6} of draws succeeded (z = {normalisation_z:.1})",
                f
            ));
        }
        // The quadrature must not move the statistic by more than a tenth of its
        // standard deviation √(2 dof).
        let quadrature_share = quadrature_chi2 / (2.0 * dof as f64).sqrt();
        if quadrature_share > 0.1 {
            reasons.push(format!(
                "pdf quadrature error could move the statistic by {quadrature_share:.2} standard deviations: refine the grid"
            ));
        }

        let mut outcome = Chi2Outcome {
            name: name.to_string(),
            statistic,
            dof,
            p_value,
            alpha: self.alpha,
            pdf_integral,
            success_fraction,
            normalisation_z,
            quadrature_share,
            passed: reasons.is_empty(),
            reason: None,
            dump: Vec::new(),
        };
        if !outcome.passed {
            outcome.dump = self.dump(name, t, &outcome).unwrap_or_default();
            let files: Vec<String> = outcome
                .dump
                .iter()
                .map(|p| p.display().to_string())
                .collect();
            outcome.reason = Some(format!(
                "{}; tables written to {}",
                reasons.join("; "),
                files.join(", ")
            ));
        }
        outcome
    }

    fn dump(
        &self,
        name: &str,
        t: &Chi2Tables,
        outcome: &Chi2Outcome,
    ) -> std::io::Result<Vec<PathBuf>> {
        let dir = &self.dump_dir;
        let stem = file_stem(name);
        let json = serde_json::json!({
            "name": name,
            "domain": self.domain,
            "seed": self.seed,
            "outcome": outcome,
            "tables": t,
            "residual": t.residual(),
        });
        let json_path = dir.join(format!("{stem}.json"));
        crate::io::write_atomic(&json_path, serde_json::to_string_pretty(&json)?.as_bytes())?;
        let mut files = vec![json_path];
        files.extend(t.write_images(dir, &stem)?);
        Ok(files)
    }
}

/// Cells with expected count < 5 pooled, smallest first, into (observed, expected)
/// pairs of expected count ≥ 5 (a remainder below 5 joins the smallest pooled cell).
fn pool(observed: &[u64], expected: &[f64]) -> Vec<(f64, f64)> {
    let mut order: Vec<usize> = (0..observed.len()).collect();
    order.sort_by(|&i, &j| expected[i].total_cmp(&expected[j]));
    let mut pooled: Vec<(f64, f64)> = Vec::new();
    let (mut pe, mut po) = (0.0, 0.0);
    for &i in &order {
        if expected[i] < 5.0 {
            pe += expected[i];
            po += observed[i] as f64;
            if pe >= 5.0 {
                pooled.push((po, pe));
                pe = 0.0;
                po = 0.0;
            }
        } else {
            pooled.push((observed[i] as f64, expected[i]));
        }
    }
    if pe > 0.0 || po > 0.0 {
        match pooled.iter_mut().min_by(|x, y| x.1.total_cmp(&y.1)) {
            Some(last) if pe < 5.0 => {
                last.0 += po;
                last.1 += pe;
            }
            _ => pooled.push((po, pe)),
        }
    }
    pooled
}

/// What a chi-square run measured, cell by cell (row-major, `rows` × `cols`).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Chi2Tables {
    /// Cells along the row parameter (cos θ, y or r²), bottom to top.
    pub rows: usize,
    /// Cells along the column parameter (φ or x).
    pub cols: usize,
    /// Samples drawn.
    pub samples: u64,
    /// Observed counts.
    pub observed: Vec<u64>,
    /// Expected counts N ∫_cell pdf.
    pub expected: Vec<f64>,
    /// The quadrature's error estimate of each ∫_cell pdf (a probability).
    pub quadrature_error: Vec<f64>,
    /// Draws that returned a sample.
    pub successes: u64,
    /// Samples outside the domain or not finite.
    pub outside: u64,
}

impl Chi2Tables {
    /// Pearson residuals (O − E)/√E per cell ([`residuals`]).
    pub fn residual(&self) -> Vec<f64> {
        residuals(&self.observed, &self.expected)
    }

    /// The three table images ([`write_table_images`]).
    pub fn write_images(&self, dir: &Path, stem: &str) -> std::io::Result<Vec<PathBuf>> {
        write_table_images(
            dir,
            stem,
            self.rows,
            self.cols,
            &self.observed,
            &self.expected,
        )
    }
}

/// A name made safe as a file stem: ASCII letters, digits and `-`; anything else `_`.
pub fn file_stem(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// Pearson residuals (O − E)/√E per cell: 0 where both vanish, 1e6 where E = 0 < O
/// (a sample where the pdf says none can be), clamped to ±1e6 so they stay finite.
pub fn residuals(observed: &[u64], expected: &[f64]) -> Vec<f64> {
    observed
        .iter()
        .zip(expected)
        .map(|(&o, &e)| {
            if e > 0.0 {
                ((o as f64 - e) / e.sqrt()).clamp(-1e6, 1e6)
            } else if o > 0 {
                1e6
            } else {
                0.0
            }
        })
        .collect()
}

/// Write `STEM-observed.exr`, `STEM-expected.exr` (counts scaled by the largest) and
/// `STEM-residual.exr` (red: more samples than expected, blue: fewer, in units of √E)
/// for `rows` × `cols` row-major tables, each atomically. Row 0 of the tables is the
/// bottom of the domain; the images show it at the bottom (row 0 of an image is its
/// top, the largest cos θ).
fn write_table_images(
    dir: &Path,
    stem: &str,
    rows: usize,
    cols: usize,
    observed: &[u64],
    expected: &[f64],
) -> std::io::Result<Vec<PathBuf>> {
    let residual = residuals(observed, expected);
    let max_count = expected
        .iter()
        .cloned()
        .fold(1.0, f64::max)
        .max(observed.iter().map(|&o| o as f64).fold(1.0, f64::max));
    let grey = |v: f64| {
        let v = (v / max_count) as f32;
        (v, v, v)
    };
    let (w, h) = (cols, rows);
    let images: [(&str, PixelFn); 3] = [
        ("observed", Box::new(|i| grey(observed[i] as f64))),
        ("expected", Box::new(|i| grey(expected[i]))),
        (
            "residual",
            Box::new(|i| {
                let r = residual[i] as f32;
                if r > 0.0 {
                    (r, 0.0, 0.0)
                } else {
                    (0.0, 0.0, -r)
                }
            }),
        ),
    ];
    let mut files = Vec::new();
    for (label, f) in images.iter() {
        let path = dir.join(format!("{stem}-{label}.exr"));
        crate::io::write_exr_atomic(&path, w, h, |x, y| f((h - 1 - y) * w + x))?;
        files.push(path);
    }
    Ok(files)
}

/// A pixel of a table image, by cell index.
type PixelFn<'a> = Box<dyn Fn(usize) -> (f32, f32, f32) + Sync + 'a>;

/// Where failure tables go by default: `$CARGO_TARGET_DIR/chi2-failures`, else
/// `target/chi2-failures` under the current folder (where `cargo test` runs), decided at
/// run time — never a path fixed when the binary was built.
pub fn failure_dir() -> PathBuf {
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("target"));
    target.join("chi2-failures")
}

/// Tensor 4-point Gauss–Legendre rule on a rectangle. An open rule: it never evaluates
/// the density on a cell edge, where indicator-shaped densities jump.
fn gauss_4x4<F: Fn(f64, f64) -> f64>(f: &F, (a0, a1): (f64, f64), (b0, b1): (f64, f64)) -> f64 {
    const X: [f64; 4] = [
        -0.861_136_311_594_052_6,
        -0.339_981_043_584_856_3,
        0.339_981_043_584_856_3,
        0.861_136_311_594_052_6,
    ];
    const W: [f64; 4] = [
        0.347_854_845_137_453_9,
        0.652_145_154_862_546_1,
        0.652_145_154_862_546_1,
        0.347_854_845_137_453_9,
    ];
    let (ha, ma) = (0.5 * (a1 - a0), 0.5 * (a1 + a0));
    let (hb, mb) = (0.5 * (b1 - b0), 0.5 * (b1 + b0));
    let mut s = 0.0;
    for i in 0..4 {
        let a = ma + ha * X[i];
        for j in 0..4 {
            s += W[i] * W[j] * f(a, mb + hb * X[j]);
        }
    }
    s * ha * hb
}

/// Tensor 3-point Gauss–Legendre rule: a second opinion whose nodes (0.11, 0.5, 0.89)
/// interleave with the 4-point rule's, so that a jump cannot make both agree by chance
/// (a jump at the middle of a cell fools the 4-point rule against its children).
fn gauss_3x3<F: Fn(f64, f64) -> f64>(f: &F, (a0, a1): (f64, f64), (b0, b1): (f64, f64)) -> f64 {
    const X: [f64; 3] = [-0.774_596_669_241_483_4, 0.0, 0.774_596_669_241_483_4];
    const W: [f64; 3] = [5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0];
    let (ha, ma) = (0.5 * (a1 - a0), 0.5 * (a1 + a0));
    let (hb, mb) = (0.5 * (b1 - b0), 0.5 * (b1 + b0));
    let mut s = 0.0;
    for i in 0..3 {
        let a = ma + ha * X[i];
        for j in 0..3 {
            s += W[i] * W[j] * f(a, mb + hb * X[j]);
        }
    }
    s * ha * hb
}

/// Adaptive tensor Gauss–Legendre: a cell is split in four until the 4×4 rule on the
/// cell, the 3×3 rule on the cell and the sum of the 4×4 rules on its children agree;
/// returns (integral, error estimate), the estimate being the largest disagreement
/// (conservative where the density jumps).
fn adaptive_quadrature_2d<F: Fn(f64, f64) -> f64>(
    f: &F,
    ra: (f64, f64),
    rb: (f64, f64),
    coarse: f64,
    tol: f64,
    depth: u32,
) -> (f64, f64) {
    let am = 0.5 * (ra.0 + ra.1);
    let bm = 0.5 * (rb.0 + rb.1);
    let quads = [
        ((ra.0, am), (rb.0, bm)),
        ((ra.0, am), (bm, rb.1)),
        ((am, ra.1), (rb.0, bm)),
        ((am, ra.1), (bm, rb.1)),
    ];
    let parts: [f64; 4] = quads.map(|(qa, qb)| gauss_4x4(f, qa, qb));
    let fine: f64 = parts.iter().sum();
    let err = (fine - coarse)
        .abs()
        .max((fine - gauss_3x3(f, ra, rb)).abs());
    if err <= tol.max(1e-9 * fine.abs()) || depth >= MAX_DEPTH {
        return (fine, err);
    }
    let mut total = (0.0, 0.0);
    for (k, (qa, qb)) in quads.iter().enumerate() {
        let (v, e) = adaptive_quadrature_2d(f, *qa, *qb, parts[k], tol / 4.0, depth + 1);
        total.0 += v;
        total.1 += e;
    }
    total
}

/// Deepest subdivision of a cell (4⁹ sub-cells at most, only along features).
const MAX_DEPTH: u32 = 9;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadrature_of_constant_density() {
        let t = Chi2Test::new(Domain::Sphere, 1000, 1, 0.01).with_resolution(8, 16);
        let total: f64 = t
            .integrate_pdf(&|_| 1.0 / (4.0 * PI))
            .iter()
            .map(|c| c.0)
            .sum();
        assert!((total - 1.0).abs() < 1e-12);
        let t = Chi2Test::new(Domain::Disk, 1000, 1, 0.01).with_resolution(8, 16);
        let total: f64 = t.integrate_pdf(&|_| 1.0 / PI).iter().map(|c| c.0).sum();
        assert!((total - 1.0).abs() < 1e-12);
    }

    #[test]
    fn too_few_samples_refuse_to_judge() {
        let dir = std::env::temp_dir().join(format!("lightproof-chi2-few-{}", std::process::id()));
        let uniform = |u: Vec3| Some(crate::sampling::sphere::uniform_sphere(u.truncate()));
        let pdf = |_: Vec3| 1.0 / (4.0 * PI);
        for n in [0, 10] {
            let t = Chi2Test::new(Domain::Sphere, n, 1, 0.01)
                .with_resolution(8, 16)
                .with_dump_dir(&dir);
            let o = t.run("few", uniform, pdf);
            assert!(!o.passed, "{n} samples judged: {o:?}");
            assert!(o.reason.unwrap().contains("too few samples"));
            assert!(o.dump.iter().all(|p| p.starts_with(&dir)), "{:?}", o.dump);
        }
        let t = Chi2Test::new(Domain::Sphere, 20_000, 1, 0.01).with_resolution(8, 16);
        assert!(t.run("enough", uniform, pdf).passed);
        let _ = std::fs::remove_dir_all(dir);
    }

    #[test]
    fn cells_and_params_round_trip() {
        for d in [
            Domain::Sphere,
            Domain::Hemisphere,
            Domain::Square,
            Domain::Disk,
        ] {
            let (a, b) = (0.3, 0.6);
            let p = d.point(a, b);
            let (a2, b2) = d.params(p).unwrap();
            assert!((a - a2).abs() < 1e-6 && (b - b2).abs() < 1e-6, "{d:?}");
        }
    }
}
