//! Tabulated functions of wavelength, linearly interpolated.

use serde::{Deserialize, Serialize};

/// A table {wavelengths (nm, strictly increasing), values}, linearly interpolated and
/// zero outside.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Table {
    /// Wavelengths (nm), strictly increasing.
    pub wavelengths: Vec<f32>,
    /// Values at those wavelengths.
    pub values: Vec<f32>,
}

impl Table {
    /// Linear interpolation, zero outside the table (and for NaN).
    pub fn eval(&self, lambda: f32) -> f32 {
        let w = &self.wavelengths;
        if w.is_empty() || !(lambda >= w[0]) || lambda > w[w.len() - 1] {
            return 0.0;
        }
        let i = w.partition_point(|&x| x <= lambda).clamp(1, w.len() - 1);
        let (l0, l1) = (w[i - 1], w[i]);
        let t = if l1 > l0 { (lambda - l0) / (l1 - l0) } else { 0.0 };
        let v = self.values[i - 1] * (1.0 - t) + self.values[i] * t;
        if v.is_finite() && v > 0.0 { v } else { 0.0 }
    }

    /// At least two entries, equal lengths, strictly increasing positive wavelengths,
    /// finite non-negative values.
    pub fn validate(&self) -> Result<(), String> {
        let (w, v) = (&self.wavelengths, &self.values);
        if w.len() < 2 || w.len() != v.len() {
            return Err(format!(
                "a table needs at least two wavelengths and as many values (got {} and {})",
                w.len(),
                v.len()
            ));
        }
        for (i, &l) in w.iter().enumerate() {
            if !(l.is_finite() && l > 0.0) {
                return Err(format!("wavelengths[{i}] must be a positive wavelength in nm, got {l}"));
            }
            if i > 0 && !(l > w[i - 1]) {
                return Err(format!(
                    "wavelengths must increase strictly: wavelengths[{i}] = {l} follows {}",
                    w[i - 1]
                ));
            }
        }
        for (i, &x) in v.iter().enumerate() {
            if !(x.is_finite() && x >= 0.0) {
                return Err(format!("values[{i}] must be finite and non-negative, got {x}"));
            }
        }
        Ok(())
    }

    /// Exact ∫ over the band of the piecewise-linear function (trapezoids, clipped).
    pub fn integral(&self, band: super::Band) -> f64 {
        let w = &self.wavelengths;
        let mut s = 0.0f64;
        for i in 1..w.len() {
            let a = w[i - 1].max(band.min);
            let b = w[i].min(band.max);
            if b > a {
                s += 0.5 * (self.eval(a) as f64 + self.eval(b) as f64) * (b - a) as f64;
            }
        }
        s
    }
}
