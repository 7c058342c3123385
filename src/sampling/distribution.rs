//! Piecewise-constant densities on [0, 1) and [0, 1)², sampled by inverting their
//! cumulative distribution (pbrt-v4 §A.4.2 and §A.5.6). The 2-D form (a marginal over
//! rows and one conditional per row) samples environment maps.
//!
//! For a function with values fᵢ on n equal cells, the density at x in cell i is
//! fᵢ / (Σ f / n); sampling finds i with cdf[i] ≤ u < cdf[i+1] and places x linearly
//! within the cell, so the warp is continuous and invertible. Cumulative sums are in `f64`.

use glam::Vec2;

/// A 1-D piecewise-constant density over [0, 1).
#[derive(Clone, Debug)]
pub struct Distribution1D {
    func: Vec<f32>,
    cdf: Vec<f64>,
    integral: f64,
}

impl Distribution1D {
    /// From non-negative cell values; negative or non-finite values are treated as 0.
    /// An all-zero function becomes uniform (its integral stays 0 for the caller to see).
    pub fn new(values: &[f32]) -> Self {
        let n = values.len().max(1);
        let func: Vec<f32> = (0..n)
            .map(|i| {
                values
                    .get(i)
                    .copied()
                    .filter(|v| v.is_finite() && *v > 0.0)
                    .unwrap_or(0.0)
            })
            .collect();
        let mut cdf = Vec::with_capacity(n + 1);
        cdf.push(0.0);
        for (i, f) in func.iter().enumerate() {
            cdf.push(cdf[i] + *f as f64 / n as f64);
        }
        let integral = cdf[n];
        if integral > 0.0 {
            for c in cdf.iter_mut() {
                *c /= integral;
            }
        } else {
            for (i, c) in cdf.iter_mut().enumerate() {
                *c = i as f64 / n as f64;
            }
        }
        cdf[n] = 1.0;
        Distribution1D {
            func,
            cdf,
            integral,
        }
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.func.len()
    }

    /// Whether there are no cells (never: a distribution has at least one).
    pub fn is_empty(&self) -> bool {
        self.func.is_empty()
    }

    /// ∫ f over [0, 1).
    pub fn integral(&self) -> f64 {
        self.integral
    }

    /// Sample: (x ∈ [0, 1), density at x, cell index).
    pub fn sample(&self, u: f32) -> (f32, f32, usize) {
        let n = self.func.len();
        let u = (u as f64).clamp(0.0, 1.0);
        // Largest i with cdf[i] <= u, restricted to cells of positive mass.
        let mut i = self
            .cdf
            .partition_point(|&c| c <= u)
            .saturating_sub(1)
            .min(n - 1);
        while i > 0 && self.cdf[i + 1] <= self.cdf[i] {
            i -= 1;
        }
        while i + 1 < n && self.cdf[i + 1] <= self.cdf[i] {
            i += 1;
        }
        let width = self.cdf[i + 1] - self.cdf[i];
        let du = if width > 0.0 {
            ((u - self.cdf[i]) / width).clamp(0.0, 1.0)
        } else {
            0.5
        };
        let x = ((i as f64 + du) / n as f64).min(1.0 - f64::EPSILON) as f32;
        (self.keep_in_cell(x, i), self.pdf_cell(i), i)
    }

    /// The cell [`Distribution1D::pdf`] reads for x.
    fn cell_of(&self, x: f32) -> usize {
        ((x * self.func.len() as f32) as usize).min(self.func.len() - 1)
    }

    /// Rounding (i + du)/n to `f32` can land x on the far side of a cell boundary, in a
    /// neighbour whose density may be zero; step x back by ulps until `pdf` reads cell i,
    /// so a sample never lies where its own pdf is zero.
    fn keep_in_cell(&self, mut x: f32, i: usize) -> f32 {
        while self.cell_of(x) > i && x > 0.0 {
            x = x.next_down();
        }
        while self.cell_of(x) < i && x < 1.0 {
            x = x.next_up();
        }
        x.min(1.0f32.next_down())
    }

    fn pdf_cell(&self, i: usize) -> f32 {
        if self.integral > 0.0 {
            (self.func[i] as f64 / self.integral) as f32
        } else {
            1.0
        }
    }

    /// Density at x ∈ [0, 1).
    pub fn pdf(&self, x: f32) -> f32 {
        if !(0.0..1.0).contains(&x) {
            return 0.0;
        }
        self.pdf_cell(self.cell_of(x))
    }

    /// Inverse of [`Distribution1D::sample`].
    pub fn invert(&self, x: f32) -> f32 {
        let n = self.func.len();
        let xs = (x as f64).clamp(0.0, 1.0) * n as f64;
        let i = (xs as usize).min(n - 1);
        let t = xs - i as f64;
        (self.cdf[i] + t * (self.cdf[i + 1] - self.cdf[i])) as f32
    }
}

/// A 2-D piecewise-constant density over [0, 1)², stored row-major (`nu` × `nv`):
/// p(u, v) = p(v) p(u | v).
#[derive(Clone, Debug)]
pub struct Distribution2D {
    conditional: Vec<Distribution1D>,
    marginal: Distribution1D,
}

impl Distribution2D {
    /// From `values[v * nu + u]`.
    pub fn new(values: &[f32], nu: usize, nv: usize) -> Self {
        let nu = nu.max(1);
        let nv = nv.max(1);
        let conditional: Vec<Distribution1D> = (0..nv)
            .map(|v| {
                let start = (v * nu).min(values.len());
                let end = ((v + 1) * nu).min(values.len());
                let mut row = values[start..end].to_vec();
                row.resize(nu, 0.0);
                Distribution1D::new(&row)
            })
            .collect();
        let marginal_values: Vec<f32> = conditional.iter().map(|c| c.integral() as f32).collect();
        Distribution2D {
            marginal: Distribution1D::new(&marginal_values),
            conditional,
        }
    }

    /// ∫∫ f.
    pub fn integral(&self) -> f64 {
        self.marginal.integral()
    }

    /// Sample a point in [0, 1)² and its density.
    pub fn sample(&self, u: Vec2) -> (Vec2, f32) {
        let (y, pdf_v, v) = self.marginal.sample(u.y);
        let (x, pdf_u, _) = self.conditional[v].sample(u.x);
        (Vec2::new(x, y), pdf_u * pdf_v)
    }

    /// Density at a point of [0, 1)².
    pub fn pdf(&self, p: Vec2) -> f32 {
        if !(0.0..1.0).contains(&p.y) || !(0.0..1.0).contains(&p.x) {
            return 0.0;
        }
        let nv = self.conditional.len();
        let v = ((p.y * nv as f32) as usize).min(nv - 1);
        self.marginal.pdf(p.y) * self.conditional[v].pdf(p.x)
    }

    /// Inverse of [`Distribution2D::sample`].
    pub fn invert(&self, p: Vec2) -> Vec2 {
        let nv = self.conditional.len();
        let v = ((p.y * nv as f32) as usize).min(nv - 1);
        Vec2::new(self.conditional[v].invert(p.x), self.marginal.invert(p.y))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Negative and non-finite values count as 0: never drawn, density 0 there, and the
    /// integral of what is left (the mean of 1 and 2 over five cells, 0.6).
    #[test]
    fn negative_and_non_finite_values_are_zero() {
        let d = Distribution1D::new(&[1.0, -1.0, f32::NAN, f32::INFINITY, 2.0]);
        assert!((d.integral() - 0.6).abs() < 1e-12, "{}", d.integral());
        for cell in 1..4 {
            let x = (cell as f32 + 0.5) / 5.0;
            assert_eq!(d.pdf(x), 0.0, "cell {cell}");
        }
        for i in 0..1000 {
            let (_, pdf, cell) = d.sample((i as f32 + 0.5) / 1000.0);
            assert!(
                (cell == 0 || cell == 4) && pdf > 0.0,
                "u = {i}/1000: cell {cell}"
            );
        }
    }

    proptest! {
        #[test]
        fn sample_pdf_invert_agree(u in 0.0f32..1.0, v in 0.0f32..1.0) {
            let d = Distribution2D::new(&[1.0, 0.0, 3.0, 2.0, 5.0, 0.5], 3, 2);
            let (p, pdf) = d.sample(Vec2::new(u, v));
            prop_assert!(pdf > 0.0);
            prop_assert!((pdf - d.pdf(p)).abs() <= 1e-4 * pdf);
            let back = d.invert(p);
            prop_assert!((back - Vec2::new(u, v)).abs().max_element() < 1e-3);
        }
    }

    /// Every cell boundary k/7 rounds to an f32 above or below it; a sample drawn at the
    /// top of a cell (du = 1) must stay in that cell, not land in a zero-density neighbour.
    /// This failed before `keep_in_cell` (chi-square at LIGHTPROOF_SEED=19).
    #[test]
    fn samples_at_cell_edges_stay_in_their_cell() {
        let values = [1.0, 0.0, 2.0, 0.0, 3.0, 0.0, 1.0];
        let d = Distribution1D::new(&values);
        for k in 0..=4096u32 {
            let u = k as f32 / 4096.0;
            for u in [u, u.next_down(), u.next_up()] {
                let (x, pdf, i) = d.sample(u);
                assert!(values[i] > 0.0, "u {u} chose empty cell {i}");
                assert!((0.0..1.0).contains(&x), "u {u}: x {x}");
                assert_eq!(d.pdf(x), pdf, "u {u}: x {x} left cell {i}");
            }
        }
        for i in [0usize, 2, 4, 6] {
            for edge in [i as f64 / 7.0, (i + 1) as f64 / 7.0] {
                let x = d.keep_in_cell(edge as f32, i);
                assert_eq!(d.cell_of(x), i, "edge {edge} of cell {i}");
            }
        }
    }

    /// Size and integral, and u at the very top choosing the last cell of positive mass
    /// even when zero cells follow it (the backward walk past empty cells).
    #[test]
    fn size_integral_and_trailing_empty_cells() {
        let d = Distribution1D::new(&[2.0, 6.0, 0.0, 0.0]);
        assert_eq!((d.len(), d.is_empty()), (4, false));
        assert!((d.integral() - 2.0).abs() < 1e-12);
        let (x, pdf, i) = d.sample(1.0);
        assert_eq!(i, 1, "x {x}");
        assert!((0.25..0.5).contains(&x) && (pdf - 3.0).abs() < 1e-6);
        let (_, _, i) = d.sample(0.0);
        assert_eq!(i, 0);
    }

    #[test]
    fn zero_function_is_uniform() {
        let d = Distribution1D::new(&[0.0, 0.0]);
        assert_eq!(d.integral(), 0.0);
        assert_eq!(d.pdf(0.3), 1.0);
        let (x, p, _) = d.sample(0.7);
        assert!((x - 0.7).abs() < 1e-6 && p == 1.0);
    }
}
