//! Wavelength bands.

use serde::{Deserialize, Serialize};

/// A wavelength band [min, max] in nm; JSON `[min, max]`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(from = "[f32; 2]", into = "[f32; 2]")]
pub struct Band {
    /// Shortest wavelength λ₁ (nm).
    pub min: f32,
    /// Longest wavelength λ₂ (nm).
    pub max: f32,
}

/// The visible range of the CIE 1931 tables, 360–830 nm.
pub const VISIBLE: Band = Band {
    min: 360.0,
    max: 830.0,
};

impl From<[f32; 2]> for Band {
    fn from(a: [f32; 2]) -> Self {
        Band {
            min: a[0],
            max: a[1],
        }
    }
}

impl From<Band> for [f32; 2] {
    fn from(b: Band) -> Self {
        [b.min, b.max]
    }
}

impl Band {
    /// A band from its ends (nm).
    pub const fn new(min: f32, max: f32) -> Self {
        Band { min, max }
    }

    /// λ₂ − λ₁ (nm); 0 for an empty or malformed band.
    pub fn width(&self) -> f32 {
        let w = self.max - self.min;
        if w.is_finite() && w > 0.0 { w } else { 0.0 }
    }

    /// Whether λ₁ ≤ λ ≤ λ₂ (false for NaN).
    pub fn contains(&self, lambda_nm: f32) -> bool {
        lambda_nm >= self.min && lambda_nm <= self.max
    }

    /// 0 < λ₁ < λ₂, both finite.
    pub fn validate(&self) -> Result<(), String> {
        if self.min.is_finite() && self.max.is_finite() && self.min > 0.0 && self.max > self.min {
            Ok(())
        } else {
            Err(format!(
                "must be [λ₁, λ₂] in nm with 0 < λ₁ < λ₂, both finite, got [{}, {}]",
                self.min, self.max
            ))
        }
    }

    /// The ends in `f64` if the band can be integrated over: 0 ≤ λ₁ < λ₂ (λ₂ may be +∞).
    pub(crate) fn ends(&self) -> Option<(f64, f64)> {
        let (a, b) = (self.min as f64, self.max as f64);
        (a >= 0.0 && a.is_finite() && b > a).then_some((a, b))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn json_width_contains_validate() {
        let b: Band = serde_json::from_str("[400, 700]").unwrap();
        assert_eq!(b, Band::new(400.0, 700.0));
        assert_eq!(serde_json::to_string(&b).unwrap(), "[400.0,700.0]");
        assert_eq!(b.width(), 300.0);
        assert!(b.contains(400.0) && b.contains(700.0) && !b.contains(f32::NAN));
        assert!(b.validate().is_ok() && VISIBLE.validate().is_ok());
        for bad in [
            [700.0, 400.0],
            [0.0, 1.0],
            [1.0, f32::INFINITY],
            [f32::NAN, 2.0],
        ] {
            let b = Band::from(bad);
            assert!(b.validate().is_err(), "{bad:?}");
            assert!(b.width() >= 0.0 && b.width().is_finite());
        }
        assert!(serde_json::from_str::<Band>("[1, 2, 3]").is_err());
    }
}
