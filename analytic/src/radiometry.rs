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
/// Born & Wolf §4.8. A NaN θ gives NaN (`max(0.0)` took cos θ = NaN for 0, behind).
pub fn lambertian_intensity(radiance: f64, area: f64, theta: f64) -> f64 {
    if theta.is_nan() {
        return f64::NAN;
    }
    radiance * area * theta.cos().max(0.0)
}

/// Power of an isotropic point light of intensity I (W/sr).
///
/// **Formula.** Φ = 4π I. **Derivation.** Φ = ∫_{S²} I dω, and the whole sphere of
/// directions is 4π sr. **Source.** pbrt 4th ed. §12.1 (`PointLight::Phi`).
pub fn isotropic_point_power(intensity: f64) -> f64 {
    4.0 * PI * intensity
}

/// Power of a spot light of intensity I (W/sr) on its axis, full within the half-angle
/// θs and falling to 0 at θt by pbrt-v4's smoothstep in cos θ.
///
/// **Formula.** Φ = 2π I [(1 − cos θs) + (cos θs − cos θt)/2].
///
/// **Derivation.** Φ = ∫ I s(θ) dω = 2π I ∫₋₁¹ s(c) dc: 1 over [cos θs, 1], and over
/// [cos θt, cos θs] the smoothstep t²(3 − 2t) in t = (c − cos θt)/(cos θs − cos θt),
/// whose integral over t ∈ [0, 1] is ½. 1 − cos θ is formed as 2 sin²(θ/2).
/// `irradiance::tests::spot_light_by_its_definition_and_its_power` checks it against
/// the flux of [`crate::irradiance::spot`] through a sphere, by quadrature.
///
/// **Source.** pbrt 4th ed. §12.1.2 (`SpotLight::Phi`).
pub fn spot_light_power(intensity: f64, cone_angle: f64, falloff_start: f64) -> f64 {
    let (ot, os) = (one_minus_cos(cone_angle), one_minus_cos(falloff_start));
    2.0 * PI * intensity * (os + (ot - os) / 2.0)
}

/// 1 − cos a, as 2 sin²(a/2): without cancellation for small angles.
pub fn one_minus_cos(a: f64) -> f64 {
    2.0 * (0.5 * a).sin().powi(2)
}

/// Intensity of a uniform Lambertian sphere of radiance L and radius R, the same in
/// every direction.
///
/// **Formula.** I = L π R². **Derivation.** I = dΦ/dω = ∫ L cos θ dA over the hemisphere
/// facing the direction (θ between a patch's normal and the direction):
/// L R² ∫₀^{2π} ∫₀^{π/2} cos θ sin θ dθ dφ = L π R², the radiance times the projected
/// area, a disk of radius R seen from any side. **Source.** Lambert, *Photometria*
/// (a uniformly bright sphere looks like a flat disk); Born & Wolf §4.8.
pub fn lambertian_sphere_intensity(radiance: f64, radius: f64) -> f64 {
    radiance * PI * radius * radius
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

/// Radiance seen from the centre of a smooth dielectric sphere (relative index η, in
/// vacuum) looking at an emitter of radiance L that fills the forward direction, with
/// nothing (black) behind.
///
/// **Formula.** L_c = η² L / (1 + R₀), R₀ = ((η − 1)/(η + 1))².
///
/// **Derivation.** Every ray from the centre meets the sphere at normal incidence, so it
/// is not bent, and its reflection returns through the centre along the same line. The
/// forward ray leaves with transmittance T = 1 − R₀ and gains the factor η² of
/// [`radiance_across_interface`] (from vacuum into the glass, seen from inside); its
/// reflection reaches the back of the sphere, whose exit sees black, and comes back
/// forward after a second reflection. Summing the bounces,
/// L_c = η² L T (1 + R₀² + R₀⁴ + …) = η² L (1 − R₀)/(1 − R₀²) = η² L/(1 + R₀).
/// At η = 1 it is L (radiance invariance in vacuum).
///
/// **Source.** Normal-incidence Fresnel reflectance (Born & Wolf §1.5.3), radiance
/// across an interface (Nicodemus 1963), the multiple-reflection series of a lossless
/// plate (Hecht, *Optics*, §9.6).
pub fn radiance_at_dielectric_sphere_centre(radiance: f64, eta: f64) -> f64 {
    let r0 = crate::fresnel::normal_reflectance(eta);
    radiance * eta * eta / (1.0 + r0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::assert_nan_in_each;
    use crate::quadrature::{adaptive, adaptive_2d};

    #[test]
    fn dielectric_sphere_centre_sums_the_bounce_series() {
        for eta in [1.0, 1.0001, 1.33, 1.5, 2.4, 4.0] {
            // The series bounce by bounce, with the reflectance from the oracle's full
            // Fresnel formula at normal incidence (not the R₀ shortcut).
            let r = crate::fresnel::dielectric(1.0, eta);
            let sum: f64 = (0..400).map(|k| (1.0 - r) * r.powi(2 * k)).sum();
            let want = radiance_across_interface(2.0, 1.0, eta) * sum;
            let got = radiance_at_dielectric_sphere_centre(2.0, eta);
            assert!(
                (got - want).abs() < 1e-12 * want,
                "η = {eta}: {got} vs {want}"
            );
        }
        assert_eq!(radiance_at_dielectric_sphere_centre(3.0, 1.0), 3.0);
    }

    /// A NaN in any input of the Lambertian intensity gives NaN, in front of the emitter
    /// and behind it: `max(0.0)` took cos θ = NaN for 0.
    #[test]
    fn lambertian_intensity_propagates_nan() {
        let bases: [&[f64]; 3] = [&[1.0, 2.0, 0.5], &[1.0, 2.0, 2.0], &[0.0, 2.0, 0.5]];
        assert_nan_in_each("Lambertian intensity", &bases, |x| {
            lambertian_intensity(x[0], x[1], x[2])
        });
    }

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
    fn point_power_and_sphere_intensity_by_quadrature() {
        // Φ = ∫_{S²} I dω over θ ∈ [0, π], φ ∈ [0, 2π].
        let sphere = adaptive_2d(|t, _| t.sin(), 0.0, PI, |_| 0.0, |_| 2.0 * PI, 1e-13);
        assert!((isotropic_point_power(2.0) - 2.0 * sphere).abs() < 1e-11);
        // I = ∫ L max(0, n·d) dA over the whole sphere, d = +z: dA = R² sin θ dθ dφ.
        let (l, r) = (2.0, 0.7);
        let q = adaptive_2d(
            |t, _| l * t.cos().max(0.0) * r * r * t.sin(),
            0.0,
            PI,
            |_| 0.0,
            |_| 2.0 * PI,
            1e-13,
        );
        let want = lambertian_sphere_intensity(l, r);
        assert!((q - want).abs() < 1e-11 * want, "{q} vs {want}");
        // The same as a facing disk of radius R: its projected area.
        assert!((want - lambertian_intensity(l, PI * r * r, 0.0)).abs() < 1e-15);
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
