//! Drawing wavelengths over a band: uniformly, or by importance with a tabulated
//! density, and four hero wavelengths from one random number.

use super::Band;
use crate::sampling::distribution::Distribution1D;

/// Cells of an importance table.
const CELLS: usize = 1024;
/// Share δ of probability spread uniformly in λ (defensive mixture, Hesterberg 1995), so
/// the density is positive wherever the tabulated target might have missed a peak.
const DEFENSIVE: f64 = 0.1;
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
/// and λ is uniform within its cell: p(λ) = Pᵢ/wᵢ exactly. The cell is chosen by
/// inverting the cumulative sums of a [`Distribution1D`] over [0, 1) (its x is mapped
/// to λ cell by cell, linearly). Cell edges are stored as `f32`, and a sample is kept
/// inside its cell, so [`WavelengthSampler::pdf`] at a returned λ finds the same cell:
/// the density `sample` returns equals `pdf(λ)` bit for bit.
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
    /// Piecewise constant on cells with `f32` edges (n + 1 of them).
    Table {
        edges: Vec<f32>,
        dist: Distribution1D,
    },
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
        if band.validate().is_err() {
            return Self::uniform(band);
        }
        let (a, b) = (band.min as f64, band.max as f64);
        let log = band.max / band.min > LOG_RATIO;
        let mut edges: Vec<f32> = (0..=CELLS)
            .map(|i| {
                let t = i as f64 / CELLS as f64;
                (if log { a * (b / a).powf(t) } else { a + (b - a) * t }) as f32
            })
            .collect();
        edges[0] = band.min;
        edges[CELLS] = band.max;
        if edges.windows(2).any(|e| !(e[1] > e[0])) {
            return Self::uniform(band);
        }
        let f = |l: f32| {
            let v = target(l).abs() as f64;
            if v.is_finite() { v } else { 0.0 }
        };
        let weights: Vec<f64> = edges
            .windows(2)
            .map(|e| {
                let mid = (0.5 * (e[0] as f64 + e[1] as f64)) as f32;
                f(e[0]).max(f(mid)).max(f(e[1])) * (e[1] as f64 - e[0] as f64)
            })
            .collect();
        let total: f64 = weights.iter().sum();
        if !(total > 0.0 && total.is_finite()) {
            return Self::uniform(band);
        }
        let width = b - a;
        let p: Vec<f32> = weights
            .iter()
            .zip(edges.windows(2))
            .map(|(w, e)| {
                ((1.0 - DEFENSIVE) * w / total + DEFENSIVE * (e[1] as f64 - e[0] as f64) / width)
                    as f32
            })
            .collect();
        WavelengthSampler {
            band,
            kind: Kind::Table {
                dist: Distribution1D::new(&p),
                edges,
            },
        }
    }

    /// The band.
    pub fn band(&self) -> Band {
        self.band
    }

    /// Whether the density is uniform over the band (or the band is degenerate).
    pub fn is_uniform(&self) -> bool {
        !matches!(self.kind, Kind::Table { .. })
    }

    /// Density per nm of cell i, from the cell's density in x ∈ [0, 1).
    #[inline]
    fn cell_pdf(edges: &[f32], pdf_x: f32, i: usize) -> f32 {
        let n = (edges.len() - 1) as f64;
        let p = pdf_x as f64 / (n * (edges[i + 1] as f64 - edges[i] as f64));
        p.clamp(f32::MIN_POSITIVE as f64, f32::MAX as f64) as f32
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
            Kind::Table { edges, dist } => {
                let (x, pdf_x, i) = dist.sample(u);
                let n = edges.len() - 1;
                let t = (x as f64 * n as f64 - i as f64).clamp(0.0, 1.0);
                let (e0, e1) = (edges[i], edges[i + 1]);
                // Keep λ in cell i (the next cell owns its lower edge).
                let hi = if i + 1 < n { e1.next_down() } else { e1 };
                let l = ((e0 as f64 + t * (e1 as f64 - e0 as f64)) as f32).clamp(e0, hi);
                (l, Self::cell_pdf(edges, pdf_x, i))
            }
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
            Kind::Table { edges, dist } => {
                let n = edges.len() - 1;
                if !(lambda_nm >= edges[0] && lambda_nm <= edges[n]) {
                    return 0.0;
                }
                let i = edges
                    .partition_point(|&e| e <= lambda_nm)
                    .saturating_sub(1)
                    .min(n - 1);
                let pdf_x = dist.pdf((i as f32 + 0.5) / n as f32);
                Self::cell_pdf(edges, pdf_x, i)
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
            assert!(l.is_finite() && l > 0.0 && p == 1.0 && s.pdf(l) == 1.0, "{band:?}");
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
