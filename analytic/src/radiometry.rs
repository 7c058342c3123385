//! Basic radiometric relations and physical constants (SI, CODATA 2018 exact values).

use std::f64::consts::PI;

/// Planck constant h (J·s), exact since the 2019 SI redefinition.
pub const PLANCK: f64 = 6.626_070_15e-34;
/// Speed of light in vacuum c (m/s), exact.
pub const SPEED_OF_LIGHT: f64 = 299_792_458.0;
/// Boltzmann constant k_B (J/K), exact.
pub const BOLTZMANN: f64 = 1.380_649e-23;

/// Power leaving one side of a uniform Lambertian emitter of radiance L and area A.
///
/// **Formula.** Φ = π L A. **Derivation.** Φ = ∫_A ∫_{hemisphere} L cos θ dω dA, and
/// ∫ cos θ dω = π. **Source.** pbrt 4th ed. §4.1 / §12.2 (`DiffuseAreaLight::Phi`).
pub fn lambertian_power(radiance: f64, area: f64) -> f64 {
    PI * radiance * area
}

/// Intensity of a flat uniform Lambertian emitter of radiance L and area A at angle θ
/// from its normal (far field).
///
/// **Formula.** I(θ) = L A cos θ (Lambert's cosine law), zero behind the emitter.
/// **Derivation.** I = dΦ/dω = ∫_A L cos θ dA. **Source.** Lambert, *Photometria*;
/// Born & Wolf §4.8.
pub fn lambertian_intensity(radiance: f64, area: f64, theta: f64) -> f64 {
    radiance * area * theta.cos().max(0.0)
}

/// Energy of one photon of vacuum wavelength λ (m).
///
/// **Formula.** E = h c / λ (J). **Source.** Planck–Einstein relation.
pub fn photon_energy(wavelength: f64) -> f64 {
    PLANCK * SPEED_OF_LIGHT / wavelength
}

/// Radiance after crossing a lossless interface from index n₁ into index n₂.
///
/// **Formula.** L₂ = L₁ (n₂/n₁)² (basic radiance L/n² is invariant).
///
/// **Derivation.** Étendue n² cos θ dA dω is conserved by refraction (Snell's law
/// differentiated: n₁² cos θ₁ dω₁ = n₂² cos θ₂ dω₂) while the transmitted flux is kept.
///
/// **Source.** Nicodemus, "Radiance", Am. J. Phys. 31, 1963; pbrt 4th ed. §9.5.2.
pub fn radiance_across_interface(radiance: f64, n1: f64, n2: f64) -> f64 {
    radiance * (n2 / n1) * (n2 / n1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quadrature::{adaptive, adaptive_2d};

    #[test]
    fn power_and_intensity_by_quadrature() {
        let q = adaptive_2d(
            |t, _| t.cos() * t.sin(),
            0.0,
            PI / 2.0,
            |_| 0.0,
            |_| 2.0 * PI,
            1e-13,
        );
        assert!((lambertian_power(2.0, 3.0) - 6.0 * q).abs() < 1e-11);
        // ∫ I(θ) dω = Φ.
        let qi = 2.0
            * PI
            * adaptive(
                |t| lambertian_intensity(2.0, 3.0, t) * t.sin(),
                0.0,
                PI,
                1e-14,
            );
        assert!((qi - lambertian_power(2.0, 3.0)).abs() < 1e-11);
    }

    #[test]
    fn photon_energy_green() {
        // 555 nm ≈ 3.579e-19 J ≈ 2.234 eV.
        let e = photon_energy(555e-9) / 1.602_176_634e-19;
        assert!((e - 2.234).abs() < 1e-3);
    }

    #[test]
    fn etendue_conservation_by_quadrature() {
        // Flux through a cone of half-angle α outside equals that through the refracted
        // cone inside; with L ∝ n², ∫ L cos dω agrees.
        let (n1, n2, alpha) = (1.0f64, 1.5f64, 0.6f64);
        let alpha2 = (n1 / n2 * alpha.sin()).asin();
        let outside = adaptive(|t| t.cos() * t.sin(), 0.0, alpha, 1e-14);
        let inside = adaptive(|t| t.cos() * t.sin(), 0.0, alpha2, 1e-14);
        assert!((outside - radiance_across_interface(1.0, n1, n2) * inside).abs() < 1e-13);
    }
}
