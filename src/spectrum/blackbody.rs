//! Planck's law.

use super::{BOLTZMANN, PLANCK, SPEED_OF_LIGHT};

/// Blackbody spectral radiance per nanometre of wavelength (W·m⁻²·sr⁻¹·nm⁻¹).
///
/// **Formula.** B_λ(λ, T) = 2hc²/λ⁵ · 1/(exp(hc/(λ k T)) − 1) (per metre of λ), times
/// 1e-9 per nm; `exp_m1` keeps the Rayleigh–Jeans end accurate and an overflowing
/// exponent gives 0 (Wien end). **Source.** M. Planck, 1901; Siegel & Howell, *Thermal
/// Radiation Heat Transfer*, ch. 1.
pub fn planck_per_nm(lambda_nm: f64, temperature: f64) -> f64 {
    if !(lambda_nm > 0.0 && temperature > 0.0) || !lambda_nm.is_finite() || !temperature.is_finite()
    {
        return 0.0;
    }
    let l = lambda_nm * 1e-9;
    let x = PLANCK * SPEED_OF_LIGHT / (l * BOLTZMANN * temperature);
    if x > 700.0 {
        return 0.0;
    }
    let b = 2.0 * PLANCK * SPEED_OF_LIGHT * SPEED_OF_LIGHT / l.powi(5) / x.exp_m1() * 1e-9;
    if b.is_finite() && b > 0.0 { b } else { 0.0 }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::{Band, Planck, Spectrum};

    #[test]
    fn stefan_boltzmann_and_wien() {
        let t = 5800.0;
        let s = Spectrum::Blackbody {
            blackbody: Planck {
                temperature: t as f32,
                scale: 1.0,
            },
        };
        // σT⁴/π with σ = 2π⁵k⁴/(15h³c²).
        let pi = std::f64::consts::PI;
        let sigma = 2.0 * pi.powi(5) * BOLTZMANN.powi(4)
            / (15.0 * PLANCK.powi(3) * SPEED_OF_LIGHT.powi(2));
        // Integrate in log λ (wide band) by the same Gauss–Legendre rule.
        let total = crate::spectrum::gauss_legendre((10.0f64).ln(), (1e7f64).ln(), 4096, |x| {
            planck_per_nm(x.exp(), t) * x.exp()
        });
        let rel = (total - sigma * t.powi(4) / pi).abs() / (sigma * t.powi(4) / pi);
        assert!(rel < 1e-6, "{rel}");
        // Wien's peak b/T by golden-section search.
        let (mut a, mut b) = (300.0, 800.0);
        for _ in 0..100 {
            let m1 = b - (b - a) * 0.618_033_988_75;
            let m2 = a + (b - a) * 0.618_033_988_75;
            if planck_per_nm(m1, t) < planck_per_nm(m2, t) {
                a = m1
            } else {
                b = m2
            }
        }
        assert!((0.5 * (a + b) - 2.897_771_955e6 / t).abs() < 0.01);
        let band = Band {
            min: 380.0,
            max: 780.0,
        };
        assert!(s.integral(band) > 0.0);
    }

    #[test]
    fn extremes_are_finite() {
        for (l, t) in [
            (0.0, 5000.0),
            (-1.0, 5000.0),
            (f64::NAN, 5000.0),
            (1e9, 5000.0),
            (500.0, 1.0),
            (500.0, 1e6),
            (1e-3, 1e6),
            (500.0, 0.0),
        ] {
            let b = planck_per_nm(l, t);
            assert!(b.is_finite() && b >= 0.0, "{l} {t} {b}");
        }
    }
}
