//! Spectral responses of sensors.

use super::{Band, Table, gauss_legendre};
use serde::{Deserialize, Serialize};

/// Maximum luminous efficacy of photopic vision (lm/W) at 555 nm (540 THz), by the SI
/// definition of the candela.
pub const LUMINOUS_EFFICACY: f64 = 683.002;

/// The CIE 1931 photopic luminosity ȳ(λ) (peak ≈ 1 at 555 nm).
///
/// **Formula.** The multi-lobe piecewise-Gaussian fit of Wyman, Sloan & Shirley,
/// "Simple analytic approximations to the CIE XYZ color matching functions", JCGT 2(2),
/// 2013: ȳ = 0.821 g(λ; 568.8, 46.9, 40.5) + 0.286 g(λ; 530.9, 16.3, 31.1) with
/// g(λ; μ, σ₁, σ₂) = exp(−½ ((λ − μ)/σ)²), σ = σ₁ below μ and σ₂ above. The fit follows
/// the 1 nm tables to within about 1% of the peak.
pub fn photopic(lambda_nm: f32) -> f32 {
    fn g(x: f32, mu: f32, s1: f32, s2: f32) -> f32 {
        let t = (x - mu) / if x < mu { s1 } else { s2 };
        (-0.5 * t * t).exp()
    }
    if !lambda_nm.is_finite() {
        return 0.0;
    }
    let y = 0.821 * g(lambda_nm, 568.8, 46.9, 40.5) + 0.286 * g(lambda_nm, 530.9, 16.3, 31.1);
    y.max(0.0)
}

/// A sensor's spectral response R(λ). JSON: `"flat"` (R = 1), `"photopic"` (CIE 1931
/// ȳ; multiply by [`LUMINOUS_EFFICACY`] for lumens), or `{"sampled": {"wavelengths",
/// "values"}}`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Response {
    /// R = 1.
    Flat,
    /// CIE 1931 ȳ(λ).
    Photopic,
    /// A table, linearly interpolated, zero outside.
    Sampled(Table),
}

impl Response {
    /// R(λ), finite and non-negative.
    #[inline]
    pub fn eval(&self, lambda_nm: f32) -> f32 {
        match self {
            Response::Flat => 1.0,
            Response::Photopic => photopic(lambda_nm),
            Response::Sampled(t) => t.eval(lambda_nm),
        }
    }

    /// ∫ R dλ over the band (nm).
    pub fn integral(&self, band: Band) -> f64 {
        match self {
            Response::Flat => band.width() as f64,
            Response::Sampled(t) => t.integral(band),
            Response::Photopic => gauss_legendre(band.min as f64, band.max as f64, 1024, |l| {
                photopic(l as f32) as f64
            }),
        }
    }

    /// Whether R = 1.
    pub fn is_flat(&self) -> bool {
        matches!(self, Response::Flat)
    }

    /// Check a tabulated response.
    pub fn validate(&self) -> Result<(), String> {
        match self {
            Response::Sampled(t) => t.validate(),
            _ => Ok(()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn photopic_peak_and_area() {
        assert!((photopic(555.0) - 1.0).abs() < 0.02);
        // CIE 1931 2° tables: ∫ȳ over 360–830 nm = 106.857 nm.
        let a = Response::Photopic.integral(super::super::VISIBLE);
        assert!((a - 106.857).abs() / 106.857 < 0.01, "{a}");
    }
}
