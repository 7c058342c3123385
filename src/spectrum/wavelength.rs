//! Drawing wavelengths over a band.

use super::Band;

/// Cells of the tabulated importance density.
const CELLS: usize = 1024;
/// Share of probability spread evenly over the cells (defensive mixture), so the density
/// is positive wherever the tabulated target might have missed a peak.
const DEFENSIVE: f64 = 0.1;

/// A density over a band, piecewise constant on cells (uniform, or equal in log λ for
/// bands wider than a factor of 4), sampled by inverting its CDF.
///
/// **Density.** Cell i of width wᵢ has probability Pᵢ = (1 − δ) Tᵢ/ΣT + δ/n, Tᵢ the
/// target's maximum over the cell's ends and midpoint times wᵢ; within a cell λ is
/// uniform, so p(λ) = Pᵢ/wᵢ exactly. **Hero wavelengths** (Wilkie et al., EGSR 2014):
/// [`WavelengthSampler::sample_lanes`] maps u + j/4 (mod 1) through the same inverse
/// CDF, so each of the four lanes has the marginal density p.
#[derive(Clone, Debug)]
pub struct WavelengthSampler {
    band: Band,
    /// Cell edges (n + 1), nm.
    edges: Vec<f64>,
    /// Cumulative probabilities (n + 1), cdf[0] = 0, cdf[n] = 1.
    cdf: Vec<f64>,
}

impl WavelengthSampler {
    /// Uniform over the band: p = 1/(λ₂ − λ₁).
    pub fn uniform(band: Band) -> Self {
        WavelengthSampler {
            band,
            edges: vec![band.min as f64, band.max as f64],
            cdf: vec![0.0, 1.0],
        }
    }

    /// Proportional to |target| (tabulated), mixed with an even spread over the cells.
    /// Falls back to uniform when the target is zero or not finite everywhere.
    pub fn importance(band: Band, target: impl Fn(f32) -> f32) -> Self {
        if band.validate().is_err() {
            return Self::uniform(band);
        }
        let (a, b) = (band.min as f64, band.max as f64);
        let log = b / a > 4.0;
        let edges: Vec<f64> = (0..=CELLS)
            .map(|i| {
                let t = i as f64 / CELLS as f64;
                if log {
                    a * (b / a).powf(t)
                } else {
                    a + (b - a) * t
                }
            })
            .collect();
        let f = |l: f64| {
            let v = target(l as f32).abs() as f64;
            if v.is_finite() { v } else { 0.0 }
        };
        let weights: Vec<f64> = (0..CELLS)
            .map(|i| {
                let (l0, l1) = (edges[i], edges[i + 1]);
                f(l0).max(f(0.5 * (l0 + l1))).max(f(l1)) * (l1 - l0)
            })
            .collect();
        let total: f64 = weights.iter().sum();
        if !(total > 0.0 && total.is_finite()) {
            return Self::uniform(band);
        }
        let mut cdf = Vec::with_capacity(CELLS + 1);
        cdf.push(0.0);
        let mut c = 0.0;
        for w in &weights {
            c += (1.0 - DEFENSIVE) * w / total + DEFENSIVE / CELLS as f64;
            cdf.push(c);
        }
        for x in cdf.iter_mut() {
            *x /= c;
        }
        *cdf.last_mut().unwrap() = 1.0;
        WavelengthSampler { band, edges, cdf }
    }

    /// The band.
    pub fn band(&self) -> Band {
        self.band
    }

    /// Draw λ (nm) from u ∈ [0, 1): (λ, density per nm), λ in the band, density > 0.
    pub fn sample(&self, u: f32) -> (f32, f32) {
        let u = (u as f64).clamp(0.0, 1.0 - 1e-12);
        let n = self.edges.len() - 1;
        let i = (self.cdf.partition_point(|&c| c <= u).max(1) - 1).min(n - 1);
        let p_cell = self.cdf[i + 1] - self.cdf[i];
        let t = if p_cell > 0.0 {
            ((u - self.cdf[i]) / p_cell).clamp(0.0, 1.0)
        } else {
            0.5
        };
        let (l0, l1) = (self.edges[i], self.edges[i + 1]);
        let l = (l0 + t * (l1 - l0)).clamp(self.band.min as f64, self.band.max as f64);
        (l as f32, (p_cell / (l1 - l0)) as f32)
    }

    /// Density (per nm) of drawing λ; 0 outside the band.
    pub fn pdf(&self, lambda_nm: f32) -> f32 {
        let l = lambda_nm as f64;
        if !(l >= self.edges[0] && l <= *self.edges.last().unwrap()) {
            return 0.0;
        }
        let n = self.edges.len() - 1;
        let i = (self.edges.partition_point(|&e| e <= l).max(1) - 1).min(n - 1);
        ((self.cdf[i + 1] - self.cdf[i]) / (self.edges[i + 1] - self.edges[i])) as f32
    }

    /// Four hero wavelengths from one number: lane j uses u + j/4 (mod 1).
    pub fn sample_lanes(&self, u: f32) -> ([f32; 4], [f32; 4]) {
        let mut l = [0.0; 4];
        let mut p = [0.0; 4];
        for j in 0..4 {
            let uj = (u + 0.25 * j as f32).fract();
            (l[j], p[j]) = self.sample(uj);
        }
        (l, p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sample_matches_pdf_and_band() {
        let band = Band {
            min: 10.0,
            max: 1e7,
        };
        let s = WavelengthSampler::importance(band, |l| {
            super::super::planck_per_nm(l as f64, 5800.0) as f32
        });
        for k in 0..1000 {
            let (l, p) = s.sample((k as f32 + 0.5) / 1000.0);
            assert!(band.contains(l));
            assert!(p > 0.0);
            let q = s.pdf(l);
            assert!((p - q).abs() <= 1e-3 * p, "{l} {p} {q}");
        }
        let u = WavelengthSampler::uniform(Band {
            min: 400.0,
            max: 700.0,
        });
        assert!((u.pdf(500.0) - 1.0 / 300.0).abs() < 1e-9);
        assert_eq!(u.pdf(800.0), 0.0);
    }
}
