//! Drawing wavelengths over a band: uniformly, or by importance with a tabulated
//! density, and four hero wavelengths from one random number.

use super::Band;

/// Cells of an importance table.
const CELLS: usize = 1024;
/// Share δ of probability spread uniformly in λ (defensive mixture, Hesterberg 1995), so
/// the density is positive wherever the tabulated target might have missed a peak.
pub const DEFENSIVE: f64 = 0.1;
/// Bands with λ₂/λ₁ above this get cells of equal width in log λ.
const LOG_RATIO: f32 = 4.0;
/// Where a band cannot be sampled and has no usable end: the middle of the visible.
const FALLBACK_NM: f32 = 555.0;

/// A density over a band of wavelengths, with exact sampling and evaluation.
///
/// **Uniform.** p(λ) = 1/(λ₂ − λ₁); λ = λ₁ + u(λ₂ − λ₁).
///
/// **Importance.** The band is cut into n = 1024 cells (equal in λ, or equal in log λ
/// when λ₂/λ₁ > 4, e.g. 10 nm–10 mm for a whole blackbody); each cell i of width wᵢ
/// gets the probability Pᵢ = (1 − δ) Tᵢ/ΣT + δ wᵢ/(λ₂ − λ₁), with Tᵢ = wᵢ · max of
/// |target| at the cell's ends and middle (a peak inside a cell is not lost) and δ = 0.1,
/// and λ is uniform within its cell: p(λ) = Pᵢ/wᵢ exactly (pbrt-v4 §A.4.2's
/// piecewise-constant 1-D distribution, on cells of unequal width). Sampling inverts the
/// cumulative sums (in `f64`), starting from a guide table of n cut points so the search
/// takes O(1) steps on average (Chen & Asau 1974; Devroye, *Non-Uniform Random Variate
/// Generation*, 1986, §III.2.4); the inverse stays monotone in u, so stratified and Sobol
/// samples stay stratified in λ. Cell edges are `f32` and a sample is kept inside its
/// cell, so [`WavelengthSampler::pdf`] at a returned λ finds the same cell: the density
/// `sample` returns equals `pdf(λ)` bit for bit.
///
/// **Hero wavelengths** (A. Wilkie, S. Nawaz, M. Droske, A. Weidlich, J. Hanika, "Hero
/// Wavelength Spectral Sampling", EGSR 2014): [`WavelengthSampler::sample_lanes`] maps
/// uⱼ = frac(u + j/4), j = 0..3, through the same inverse CDF; each uⱼ is uniform, so each
/// lane's marginal density is p, and ¼ Σⱼ f(λⱼ)/p(λⱼ) is unbiased for ∫ f dλ while the
/// lanes stratify the band.
///
/// **Degenerate bands.** A band that fails [`Band::validate`] (empty, reversed, NaN,
/// non-positive) is treated as one wavelength (its finite positive end, else 555 nm)
/// drawn with "density" 1, so nothing downstream sees NaN or ∞; the scene loader
/// validates bands first.
#[derive(Clone, Debug)]
pub struct WavelengthSampler {
    band: Band,
    kind: Kind,
}

#[derive(Clone, Debug)]
enum Kind {
    /// A single wavelength (degenerate band).
    Point(f32),
    /// Uniform over the band, with its density.
    Uniform { pdf: f32 },
    /// Piecewise constant on cells.
    Table(Box<Table>),
}

#[derive(Clone, Debug)]
struct Table {
    /// Cell edges (n + 1), nm, strictly increasing; edges[0] = λ₁, edges[n] = λ₂.
    edges: Vec<f32>,
    /// Cumulative probabilities (n + 1): cdf[0] = 0, cdf[n] = 1, strictly increasing.
    cdf: Vec<f64>,
    /// Density per nm in each cell, Pᵢ/wᵢ.
    density: Vec<f32>,
    /// guide[k] = the cell holding u = k/n.
    guide: Vec<u32>,
    /// Cells equal in log λ.
    log: bool,
}

impl Table {
    fn cells(&self) -> usize {
        self.density.len()
    }

    /// The cell holding λ ∈ [λ₁, λ₂]: from the cell's formula, corrected against the
    /// rounded `f32` edges.
    #[inline]
    fn cell_of(&self, l: f32) -> usize {
        let n = self.cells();
        let (a, b) = (self.edges[0] as f64, self.edges[n] as f64);
        let x = if self.log {
            (l as f64 / a).ln() / (b / a).ln()
        } else {
            (l as f64 - a) / (b - a)
        };
        let mut i = ((x * n as f64).max(0.0) as usize).min(n - 1);
        while i > 0 && l < self.edges[i] {
            i -= 1;
        }
        while i + 1 < n && l >= self.edges[i + 1] {
            i += 1;
        }
        i
    }

    #[inline]
    fn sample(&self, u: f32) -> (f32, f32) {
        let n = self.cells();
        let u = u as f64;
        let mut i = (self.guide[((u * n as f64) as usize).min(n - 1)] as usize).min(n - 1);
        while i + 1 < n && self.cdf[i + 1] <= u {
            i += 1;
        }
        let p = self.cdf[i + 1] - self.cdf[i];
        let t = if p > 0.0 {
            ((u - self.cdf[i]) / p).clamp(0.0, 1.0)
        } else {
            0.5
        };
        let (e0, e1) = (self.edges[i], self.edges[i + 1]);
        // Keep λ in cell i (the next cell owns its lower edge).
        let hi = if i + 1 < n { e1.next_down() } else { e1 };
        let l = ((e0 as f64 + t * (e1 as f64 - e0 as f64)) as f32).clamp(e0, hi);
        (l, self.density[i])
    }
}

/// u in [0, 1): NaN and negatives give 0, 1 and above the largest float below 1.
#[inline]
fn unit(u: f32) -> f32 {
    if u >= 0.0 {
        u.min(crate::math::ONE_MINUS_EPSILON)
    } else {
        0.0
    }
}

impl WavelengthSampler {
    /// Uniform over the band: p = 1/(λ₂ − λ₁).
    pub fn uniform(band: Band) -> Self {
        let kind = match band.validate() {
            Ok(()) => {
                let pdf = (1.0 / (band.max as f64 - band.min as f64)) as f32;
                if pdf.is_finite() && pdf > 0.0 {
                    Kind::Uniform { pdf }
                } else {
                    Kind::Point(band.min)
                }
            }
            Err(_) => Kind::Point(if band.min.is_finite() && band.min > 0.0 {
                band.min
            } else if band.max.is_finite() && band.max > 0.0 {
                band.max
            } else {
                FALLBACK_NM
            }),
        };
        WavelengthSampler { band, kind }
    }

    /// Proportional to |target(λ)| (tabulated on 1024 cells), mixed with 10 % uniform;
    /// uniform when the target is zero or not finite everywhere, or the band is too
    /// narrow for 1024 distinct `f32` cells.
    pub fn importance(band: Band, target: impl Fn(f32) -> f32) -> Self {
        Self::importance_bounded(band, target, |_| 0.0)
    }

    /// [`WavelengthSampler::importance`] with `bound(cell)` ≥ |target| over each cell (0
    /// where unknown): a cell's weight is at least its width times that bound, so a peak
    /// narrower than half a cell between the three points looked at is not lost (a
    /// spike 0.01 nm wide got only the defensive share δ, its samples weighing 1/δ = 10
    /// times a uniform draw's and overflowing `f32`), and every drawn λ then has
    /// p(λ) ≥ (1 − δ) |target(λ)| / Σ Tᵢ.
    pub fn importance_bounded(
        band: Band,
        target: impl Fn(f32) -> f32,
        bound: impl Fn(Band) -> f32,
    ) -> Self {
        if band.validate().is_err() {
            return Self::uniform(band);
        }
        let (a, b) = (band.min as f64, band.max as f64);
        let log = band.max / band.min > LOG_RATIO;
        let mut edges: Vec<f32> = (0..=CELLS)
            .map(|i| {
                let t = i as f64 / CELLS as f64;
                (if log {
                    a * (b / a).powf(t)
                } else {
                    a + (b - a) * t
                }) as f32
            })
            .collect();
        edges[0] = band.min;
        edges[CELLS] = band.max;
        if edges.windows(2).any(|e| !(e[1] > e[0])) {
            return Self::uniform(band);
        }
        let width = |i: usize| edges[i + 1] as f64 - edges[i] as f64;
        let f = |l: f32| {
            let v = target(l).abs() as f64;
            if v.is_finite() { v } else { 0.0 }
        };
        let weights: Vec<f64> = (0..CELLS)
            .map(|i| {
                let mid = (0.5 * (edges[i] as f64 + edges[i + 1] as f64)) as f32;
                let cell = Band {
                    min: edges[i],
                    max: edges[i + 1],
                };
                let b = bound(cell) as f64;
                let b = if b.is_finite() { b } else { 0.0 };
                f(edges[i]).max(f(mid)).max(f(edges[i + 1])).max(b) * width(i)
            })
            .collect();
        let total: f64 = weights.iter().sum();
        if !(total > 0.0 && total.is_finite()) {
            return Self::uniform(band);
        }
        let p: Vec<f64> = (0..CELLS)
            .map(|i| (1.0 - DEFENSIVE) * weights[i] / total + DEFENSIVE * width(i) / (b - a))
            .collect();
        let sum: f64 = p.iter().sum();
        let mut cdf = Vec::with_capacity(CELLS + 1);
        cdf.push(0.0);
        for (i, pi) in p.iter().enumerate() {
            cdf.push(cdf[i] + pi / sum);
        }
        cdf[CELLS] = 1.0;
        // The density of what is actually sampled: cell i has probability cdf[i+1] − cdf[i].
        let density: Vec<f32> = (0..CELLS)
            .map(|i| {
                ((cdf[i + 1] - cdf[i]) / width(i)).clamp(f32::MIN_POSITIVE as f64, f32::MAX as f64)
                    as f32
            })
            .collect();
        if cdf.windows(2).any(|c| !(c[1] > c[0])) {
            return Self::uniform(band);
        }
        let guide: Vec<u32> = (0..CELLS)
            .map(|k| {
                let u = k as f64 / CELLS as f64;
                (cdf.partition_point(|&c| c <= u).saturating_sub(1)).min(CELLS - 1) as u32
            })
            .collect();
        WavelengthSampler {
            band,
            kind: Kind::Table(Box::new(Table {
                edges,
                cdf,
                density,
                guide,
                log,
            })),
        }
    }

    /// The band.
    pub fn band(&self) -> Band {
        self.band
    }

    /// Whether the density is uniform over the band (or the band is degenerate).
    pub fn is_uniform(&self) -> bool {
        !matches!(self.kind, Kind::Table(_))
    }

    /// Draw λ (nm) from u ∈ [0, 1): (λ, density per nm); λ lies in the band and the
    /// density is positive and finite and equals [`WavelengthSampler::pdf`] at λ.
    #[inline]
    pub fn sample(&self, u: f32) -> (f32, f32) {
        let u = unit(u);
        match &self.kind {
            Kind::Point(l) => (*l, 1.0),
            Kind::Uniform { pdf } => {
                let (a, b) = (self.band.min as f64, self.band.max as f64);
                let l = ((a + u as f64 * (b - a)) as f32).clamp(self.band.min, self.band.max);
                (l, *pdf)
            }
            Kind::Table(t) => t.sample(u),
        }
    }

    /// Density (per nm) of drawing λ; 0 outside the band.
    #[inline]
    pub fn pdf(&self, lambda_nm: f32) -> f32 {
        match &self.kind {
            Kind::Point(l) => {
                if lambda_nm == *l {
                    1.0
                } else {
                    0.0
                }
            }
            Kind::Uniform { pdf } => {
                if self.band.contains(lambda_nm) {
                    *pdf
                } else {
                    0.0
                }
            }
            Kind::Table(t) => {
                if self.band.contains(lambda_nm) {
                    t.density[t.cell_of(lambda_nm)]
                } else {
                    0.0
                }
            }
        }
    }

    /// Four hero wavelengths from one number: lane j uses uⱼ = frac(u + j/4) through the
    /// same inverse CDF, so every lane's marginal density is [`WavelengthSampler::pdf`].
    /// Returns (λⱼ, pⱼ) with pⱼ = pdf(λⱼ).
    #[inline]
    pub fn sample_lanes(&self, u: f32) -> ([f32; 4], [f32; 4]) {
        let u = unit(u) as f64;
        let mut l = [0.0; 4];
        let mut p = [0.0; 4];
        for j in 0..4 {
            (l[j], p[j]) = self.sample((u + 0.25 * j as f64).fract() as f32);
        }
        (l, p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A spike narrower than half a cell between the three points a cell is looked at:
    /// without a bound its cell gets only the defensive share δ (density 0.1/100 nm), so
    /// its samples weigh 1/δ = 10 times a uniform draw's; with the exact bound per cell
    /// its density is at least (1 − δ) target/ΣT, ΣT ≤ 100 nm × 1 here.
    #[test]
    fn a_spike_between_the_points_looked_at_keeps_its_density() {
        let band = Band::new(400.0, 500.0);
        let (lo, hi) = (450.0102f32, 450.0198f32);
        let spike = |l: f32| if l > lo && l < hi { 1.0 } else { 0.0 };
        let over = |c: Band| if c.max > lo && c.min < hi { 1.0 } else { 0.0 };
        let at = 0.5 * (lo + hi);
        let blind = WavelengthSampler::importance(band, spike);
        assert!(
            blind.is_uniform(),
            "the three points of every cell miss the spike"
        );
        let seen = WavelengthSampler::importance_bounded(band, spike, over);
        assert!(
            seen.pdf(at) as f64 >= (1.0 - DEFENSIVE) / 100.0,
            "{}",
            seen.pdf(at)
        );
        assert!(seen.pdf(at) > 50.0 * blind.pdf(at));
    }
    /// The table reads each cell at its two edges and its centre, weighted by its width:
    /// a peak narrower than a cell at a cell's centre, or just below a cell's upper edge,
    /// gets its cell's share (not only the defensive one), and a constant target over a
    /// log-spaced band (cells of unequal width) gives the uniform density.
    #[test]
    fn the_table_reads_each_cells_centre_and_edges_by_its_width() {
        let band = Band::new(400.0, 500.0);
        let cell = 100.0 / CELLS as f32;
        let uniform = 1.0 / 100.0;
        // A triangle 0.4 cells wide at the centre of cell 300 (none of its edges sees it).
        let centre = 400.0 + 300.5 * cell;
        let tent = |c: f32| move |l: f32| (1.0 - (l - c).abs() / (0.2 * cell)).max(0.0);
        let s = WavelengthSampler::importance(band, tent(centre));
        assert!(s.pdf(centre) > 100.0 * uniform, "{}", s.pdf(centre));
        // The same just below the upper edge of cell 300 (the lower edge of cell 301): the
        // part inside cell 300 keeps its density through that edge.
        let edge = 400.0 + 301.0 * cell;
        let s = WavelengthSampler::importance(band, tent(edge));
        let below = edge - 0.1 * cell;
        assert!(s.pdf(below) > 100.0 * uniform, "{}", s.pdf(below));
        // A constant target over a log-spaced band: the density is 1/(b − a) everywhere.
        let wide = Band::new(100.0, 10_000.0);
        let s = WavelengthSampler::importance(wide, |_| 1.0);
        for l in [100.5f32, 150.0, 1000.0, 5000.0, 9999.0] {
            let rel = s.pdf(l) as f64 * 9900.0 - 1.0;
            assert!(rel.abs() < 1e-4, "p({l}) is {rel:e} off uniform");
        }
    }

    use crate::spectrum::{Spectrum, VISIBLE};

    #[test]
    fn sample_matches_pdf_exactly() {
        let wide = Band::new(10.0, 1e7);
        let bb = Spectrum::blackbody(5800.0);
        for s in [
            WavelengthSampler::uniform(VISIBLE),
            WavelengthSampler::importance(VISIBLE, |l| bb.eval(l)),
            WavelengthSampler::importance(wide, |l| bb.eval(l)),
        ] {
            let band = s.band();
            for k in 0..=10_000 {
                let u = k as f32 / 10_000.0;
                let (l, p) = s.sample(u);
                assert!(band.contains(l), "{l}");
                assert!(p > 0.0 && p.is_finite());
                assert_eq!(p, s.pdf(l), "u = {u}, λ = {l}");
            }
            assert_eq!(s.pdf(band.min.next_down()), 0.0);
            assert_eq!(s.pdf(band.max.next_up()), 0.0);
            assert_eq!(s.pdf(f32::NAN), 0.0);
        }
        let u = WavelengthSampler::uniform(Band::new(400.0, 700.0));
        assert!((u.pdf(500.0) - 1.0 / 300.0).abs() < 1e-9);
        assert!(u.is_uniform());
    }

    #[test]
    fn guide_table_search_inverts_the_cdf() {
        let bb = Spectrum::blackbody(3000.0);
        for band in [VISIBLE, Band::new(10.0, 1e7)] {
            let s = WavelengthSampler::importance(band, |l| bb.eval(l));
            let Kind::Table(t) = &s.kind else {
                panic!("not a table")
            };
            for k in 0..100_000 {
                let u = unit(k as f32 / 100_000.0);
                let (l, _) = t.sample(u);
                let i = t.cell_of(l);
                let j = t.cdf.partition_point(|&c| c <= u as f64) - 1;
                assert_eq!(i, j, "u {u}");
                assert!(t.edges[i] <= l && (l < t.edges[i + 1] || i + 1 == t.cells()));
            }
        }
    }

    #[test]
    fn fallbacks() {
        // A target zero everywhere, or NaN, gives uniform.
        assert!(WavelengthSampler::importance(VISIBLE, |_| 0.0).is_uniform());
        assert!(WavelengthSampler::importance(VISIBLE, |_| f32::NAN).is_uniform());
        // Too narrow for 1024 distinct f32 cells: uniform.
        assert!(WavelengthSampler::importance(Band::new(550.0, 550.001), |l| l).is_uniform());
        // Degenerate bands: one wavelength with density 1.
        for band in [
            Band::new(500.0, 500.0),
            Band::new(700.0, 400.0),
            Band::new(f32::NAN, f32::NAN),
            Band::new(-1.0, 2.0),
        ] {
            let s = WavelengthSampler::importance(band, |l| l);
            let (l, p) = s.sample(0.3);
            assert!(
                l.is_finite() && l > 0.0 && p == 1.0 && s.pdf(l) == 1.0,
                "{band:?}"
            );
        }
    }

    #[test]
    fn lanes_are_shifted_copies() {
        let s = WavelengthSampler::uniform(Band::new(400.0, 800.0));
        let (l, p) = s.sample_lanes(0.1);
        for j in 0..4 {
            assert!((l[j] - (440.0 + 100.0 * j as f32)).abs() < 1e-3, "{l:?}");
            assert_eq!(p[j], s.pdf(l[j]));
        }
        let (l, _) = s.sample_lanes(0.9);
        assert!((l[1] - 460.0).abs() < 1e-3, "{l:?}");
    }
}
