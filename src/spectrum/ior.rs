//! Refractive index as a function of wavelength (dispersion).

use super::{Band, Table};
use serde::{Deserialize, Serialize};

/// Cauchy coefficients: n = a + b/λ² + c/λ⁴ (λ in µm, b in µm², c in µm⁴).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CauchyCoefficients {
    /// a.
    pub a: f32,
    /// b (µm²).
    #[serde(default)]
    pub b: f32,
    /// c (µm⁴).
    #[serde(default)]
    pub c: f32,
}

/// Sellmeier coefficients: n² = 1 + Σᵢ Bᵢ λ²/(λ² − Cᵢ) (λ in µm, Cᵢ in µm²).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SellmeierCoefficients {
    /// B₁, B₂, B₃.
    pub b: [f32; 3],
    /// C₁, C₂, C₃ (µm²).
    pub c: [f32; 3],
}

/// A refractive index n(λ). JSON: a number, `{"cauchy": {"a", "b", "c"}}`,
/// `{"sellmeier": {"b": [..], "c": [..]}}` or `{"sampled": {"wavelengths", "values"}}`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Ior {
    /// The same index at every wavelength.
    Constant(f32),
    /// Cauchy's formula (A.-L. Cauchy 1836; Born & Wolf §2.3).
    Cauchy {
        /// Coefficients.
        cauchy: CauchyCoefficients,
    },
    /// Sellmeier's formula (W. Sellmeier 1872; Born & Wolf §2.3).
    Sellmeier {
        /// Coefficients.
        sellmeier: SellmeierCoefficients,
    },
    /// A table, linearly interpolated.
    Sampled {
        /// The table.
        sampled: Table,
    },
}

/// Schott N-BK7 (Schott optical glass datasheet, Sellmeier coefficients):
/// B = (1.03961212, 0.231792344, 1.01046945), C = (6.00069867e-3, 2.00179144e-2,
/// 103.560653) µm²; n_d(587.56 nm) = 1.5168.
pub fn bk7() -> Ior {
    Ior::Sellmeier {
        sellmeier: SellmeierCoefficients {
            b: [1.039_612_1, 0.231_792_34, 1.010_469_5],
            c: [6.000_698_7e-3, 2.001_791_4e-2, 103.560_65],
        },
    }
}

impl Ior {
    /// The formula's raw value (may be non-physical outside its range).
    fn raw(&self, lambda_nm: f32) -> f64 {
        let l = lambda_nm as f64 * 1e-3;
        match self {
            Ior::Constant(n) => *n as f64,
            Ior::Cauchy { cauchy: c } => {
                let l2 = l * l;
                c.a as f64 + c.b as f64 / l2 + c.c as f64 / (l2 * l2)
            }
            Ior::Sellmeier { sellmeier: s } => {
                let l2 = l * l;
                let n2 = 1.0
                    + (0..3)
                        .map(|i| s.b[i] as f64 * l2 / (l2 - s.c[i] as f64))
                        .sum::<f64>();
                n2.sqrt()
            }
            Ior::Sampled { sampled } => sampled.eval(lambda_nm) as f64,
        }
    }

    /// n(λ), always finite and positive (1 where the formula gives nothing physical).
    #[inline]
    pub fn eval(&self, lambda_nm: f32) -> f32 {
        let n = self.raw(lambda_nm) as f32;
        if n.is_finite() && n > 1e-4 { n } else { 1.0 }
    }

    /// Whether n is the same at every wavelength.
    pub fn is_constant(&self) -> bool {
        match self {
            Ior::Constant(_) => true,
            Ior::Cauchy { cauchy } => cauchy.b == 0.0 && cauchy.c == 0.0,
            _ => false,
        }
    }

    /// n finite and positive over the band (checked on a 256-point grid plus the
    /// Sellmeier poles, which must lie outside it).
    pub fn validate(&self, band: Band) -> Result<(), String> {
        if let Ior::Sampled { sampled } = self {
            sampled.validate()?;
        }
        if let Ior::Sellmeier { sellmeier } = self {
            for (i, &c) in sellmeier.c.iter().enumerate() {
                if !c.is_finite() || !sellmeier.b[i].is_finite() {
                    return Err(format!("sellmeier coefficient {i} must be finite"));
                }
                let pole = c.max(0.0).sqrt() * 1e3;
                if band.contains(pole) {
                    return Err(format!(
                        "the Sellmeier pole C{} = {c} µm² sits at {pole:.1} nm, inside the band [{}, {}] nm",
                        i + 1,
                        band.min,
                        band.max
                    ));
                }
            }
        }
        for k in 0..=256 {
            let l = band.min + band.width() * k as f32 / 256.0;
            let n = self.raw(l);
            if !(n.is_finite() && n > 0.0) {
                return Err(format!(
                    "the index must be positive and finite over [{}, {}] nm; at {l} nm it is {n}",
                    band.min, band.max
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bk7_d_line_and_cauchy() {
        assert!((bk7().eval(587.56) - 1.5168).abs() < 1e-4);
        let c = Ior::Cauchy {
            cauchy: CauchyCoefficients {
                a: 1.5046,
                b: 0.0042,
                c: 0.0,
            },
        };
        assert!((c.eval(500.0) - (1.5046 + 0.0168)).abs() < 1e-6);
        assert!(bk7().validate(super::super::VISIBLE).is_ok());
        let bad = Ior::Cauchy {
            cauchy: CauchyCoefficients {
                a: -1.0,
                b: 0.0,
                c: 0.0,
            },
        };
        assert!(bad.validate(super::super::VISIBLE).is_err());
        assert_eq!(bad.eval(500.0), 1.0);
    }
}
