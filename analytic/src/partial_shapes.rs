//! Partial shapes: the annulus (a disk with a hole) and the spherical cap (a sphere
//! clipped by a polar angle about an axis), and the furnace's partial sums (paths cut
//! after k scatterings), so that an annular light, an emissive cap and an integrating
//! sphere with a port can be judged bounce by bounce.

use std::f64::consts::PI;

/// 1 − cos θ without cancellation for small θ: 2 sin²(θ/2).
fn one_minus_cos(theta: f64) -> f64 {
    let s = (0.5 * theta).sin();
    2.0 * s * s
}

/// Irradiance on the axis of a uniform Lambertian annulus of radiance L (radii r < R)
/// facing the receiver at height h.
///
/// **Formula.** E = π L h² (R² − r²) / ((R² + h²)(r² + h²)).
///
/// **Derivation.** The annulus is the disk of radius R less the disk of radius r, and
/// irradiance is additive over the emitting area: E = π L [R²/(R²+h²) − r²/(r²+h²)]
/// (each disk term from ∫₀^R L h²/(h²+ρ²)² 2πρ dρ); the difference is brought over one
/// denominator so that a thin annulus (r → R) or a far one (h ≫ R) loses no digits.
///
/// **Source.** Howell's catalog, B-13 (element to coaxial annulus, as a difference of
/// disk factors); Siegel & Howell App. C (configuration-factor algebra).
pub fn annulus_irradiance_on_axis(inner: f64, outer: f64, height: f64, radiance: f64) -> f64 {
    let h2 = height * height;
    PI * radiance * h2 * (outer - inner) * (outer + inner)
        / ((outer * outer + h2) * (inner * inner + h2))
}

/// Power of a uniform Lambertian annulus of radiance L (one side): Φ = π L · π (R² − r²).
///
/// **Derivation.** A Lambertian surface emits M = π L per unit area (∫ L cos θ dω over
/// the hemisphere); the annulus's area is π(R² − r²).
///
/// **Source.** Any radiometry text, e.g. McCluskey, *Introduction to Radiometry and
/// Photometry*, §2 (Lambertian exitance).
pub fn annulus_power(inner: f64, outer: f64, radiance: f64) -> f64 {
    PI * radiance * PI * (outer - inner) * (outer + inner)
}

/// Area of a spherical cap of radius R and polar half-angle θmax (rad):
/// A = 2π R² (1 − cos θmax) (Archimedes' hat-box theorem: area is proportional to
/// height along the axis, 2π R per unit height).
pub fn spherical_cap_area(radius: f64, theta_max: f64) -> f64 {
    2.0 * PI * radius * radius * one_minus_cos(theta_max)
}

/// Power of a uniform Lambertian spherical cap of radiance L (one side):
/// Φ = π L · 2π R² (1 − cos θmax).
///
/// **Derivation.** Exitance π L times [`spherical_cap_area`].
///
/// **Source.** Archimedes, *On the Sphere and Cylinder* I.42 (cap area); McCluskey §2.
pub fn spherical_cap_power(radius: f64, theta_max: f64, radiance: f64) -> f64 {
    PI * radiance * spherical_cap_area(radius, theta_max)
}

/// Irradiance at the centre of a sphere from an emissive spherical cap of radiance L
/// (emitting inwards, polar half-angle θmax about the axis), on a receiver facing the
/// cap's axis.
///
/// **Formula.** E = π L sin²θmax for θmax ≤ π/2, and π L beyond (the receiver's
/// hemisphere is then filled).
///
/// **Derivation.** Every ray from the centre meets the cap at normal incidence after a
/// length R, so the cap is seen with radiance L over the cone of half-angle θmax about
/// the axis; E = ∫ L cos θ dω over the cone clipped to the receiver's hemisphere,
/// = 2π L ∫₀^{min(θmax, π/2)} cos θ sin θ dθ = π L sin² min(θmax, π/2).
///
/// **Source.** Siegel & Howell App. C (element to a coaxial cap = element to the disk of
/// its rim: the factor sin²θ).
///
/// A NaN θmax gives NaN (`min` took it for π/2: π L).
pub fn spherical_cap_irradiance_at_centre(theta_max: f64, radiance: f64) -> f64 {
    if theta_max.is_nan() {
        return f64::NAN;
    }
    let t = theta_max.min(0.5 * PI);
    PI * radiance * t.sin() * t.sin()
}

/// Radiance inside a closed diffuse enclosure (walls emit Le, albedo ρ) when paths are
/// cut after k scatterings: the k-th partial sum of the Neumann series.
///
/// **Formula.** L_k = Le Σ_{j=0}^{k} ρ^j = Le (1 − ρ^{k+1}) / (1 − ρ) (= Le (k + 1) at
/// ρ = 1), evaluated as −Le·expm1((k+1) ln ρ)/(1 − ρ) so that ρ → 1 loses no digits.
///
/// **Derivation.** In a closed enclosure with uniform Le and ρ the radiance is uniform
/// (Σⱼ Fᵢⱼ = 1), and each scattering multiplies the previous order by ρ:
/// L = Le + ρ Le + ρ² Le + …; a path of at most k scatterings keeps the first k + 1
/// terms.
///
/// **Source.** Kajiya, "The Rendering Equation", SIGGRAPH 1986 (the Neumann series);
/// Siegel & Howell ch. 6.
pub fn closed_enclosure_bounces(emitted_radiance: f64, albedo: f64, bounces: u32) -> f64 {
    let n = bounces as f64 + 1.0;
    if albedo == 1.0 {
        return emitted_radiance * n;
    }
    if albedo == 0.0 {
        return emitted_radiance;
    }
    -emitted_radiance * (n * albedo.ln()).exp_m1() / (1.0 - albedo)
}

/// Wall radiance of an emitting integrating sphere with a black port (area fraction f,
/// wall albedo ρ, wall emission Le) when paths are cut after k scatterings.
///
/// **Formula.** L_k = Le Σ_{j=0}^{k} (ρ(1 − f))^j, the partial sums of Goebel's
/// Le / (1 − ρ(1 − f)) ([`crate::furnace::integrating_sphere`]).
///
/// **Derivation.** Inside a sphere the kernel cos θ₁ cos θ₂/(π s²) = 1/(4π R²) is
/// constant, so a uniform wall radiance L illuminates every wall element with
/// E = π L (1 − f) (the port is black); scattering returns ρ(1 − f) L. Each order is the
/// previous times ρ(1 − f), which is the enclosure series with albedo ρ(1 − f).
///
/// **Source.** Goebel, Appl. Opt. 6(1), 1967; Siegel & Howell ch. 6.
pub fn integrating_sphere_bounces(
    emitted_radiance: f64,
    albedo: f64,
    port_fraction: f64,
    bounces: u32,
) -> f64 {
    closed_enclosure_bounces(emitted_radiance, albedo * (1.0 - port_fraction), bounces)
}

/// The port fraction of a sphere whose wall is the cap of half-angle θmax (rad): the
/// port is the complementary cap, f = (1 + cos θmax)/2 = cos²(θmax/2).
pub fn port_fraction_of_cap(theta_max: f64) -> f64 {
    let c = (0.5 * theta_max).cos();
    c * c
}

/// [`port_fraction_of_cap`] for θmax given in degrees, as the catalog gives it:
/// f = sin²((180° − θmax)/2), the port's own half-angle. 180 − θmax is exact for
/// θmax ≥ 90 (Sterbenz), so a tiny port keeps its digits; converting θmax to radians
/// first rounded π − θmax (relative error ~10⁻¹⁶·π/(π − θmax): 2.5·10⁻¹¹ at
/// θmax = 179.999°, 2.7·10⁻⁸ at 179.999999°, against 40-digit mpmath).
pub fn port_fraction_of_cap_degrees(theta_max_degrees: f64) -> f64 {
    let s = (0.5 * (180.0 - theta_max_degrees)).to_radians().sin();
    s * s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::furnace::integrating_sphere;
    use crate::geom::assert_nan_in_each;
    use crate::quadrature::{adaptive, adaptive_2d};

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs().max(1e-300)
    }

    #[test]
    fn annulus_on_axis_by_area_quadrature() {
        // E = ∫∫ L cos θ cos θ' / s² dA over the annulus, in polar coordinates.
        for (r, big_r, h) in [
            (0.5, 1.0, 2.0),
            (0.999, 1.0, 0.3),
            (1e-3, 2.0, 1e-2),
            (1.0, 3.0, 500.0),
        ] {
            let q = adaptive(
                |rho| {
                    let s2 = h * h + rho * rho;
                    h * h / (s2 * s2) * 2.0 * PI * rho
                },
                r,
                big_r,
                1e-13,
            );
            let e = annulus_irradiance_on_axis(r, big_r, h, 1.0);
            assert!(rel(e, q) < 1e-10, "{r} {big_r} {h}: {e} vs {q}");
        }
    }

    #[test]
    fn annulus_power_by_quadrature() {
        // Φ = ∫ dA ∫ L cos θ dω over the hemisphere: the angular integral by quadrature.
        let m = adaptive_2d(
            |t, _| 1.3 * t.cos() * t.sin(),
            0.0,
            PI / 2.0,
            |_| 0.0,
            |_| 2.0 * PI,
            1e-13,
        );
        let area = adaptive(|rho| 2.0 * PI * rho, 0.25, 0.75, 1e-14);
        assert!(rel(annulus_power(0.25, 0.75, 1.3), m * area) < 1e-12);
    }

    #[test]
    fn cap_area_and_power_by_quadrature() {
        for (r, t) in [(1.0, 0.5), (2.0, PI), (0.3, 1e-3), (1.0, 3.0)] {
            let a = adaptive(|th| 2.0 * PI * r * r * th.sin(), 0.0, t, 1e-14);
            assert!(rel(spherical_cap_area(r, t), a) < 1e-12, "{r} {t}");
            assert!(rel(spherical_cap_power(r, t, 2.0), 2.0 * PI * a) < 1e-12);
        }
    }

    /// A NaN θmax or radiance gives NaN, below and beyond π/2 and at 0: `min` took a NaN
    /// θmax for π/2 (π L).
    #[test]
    fn cap_irradiance_at_centre_propagates_nan() {
        let bases: [&[f64]; 3] = [&[0.5, 1.0], &[2.0, 1.0], &[0.0, 1.0]];
        assert_nan_in_each("cap irradiance at the centre", &bases, |x| {
            spherical_cap_irradiance_at_centre(x[0], x[1])
        });
    }

    #[test]
    fn cap_irradiance_at_centre_by_quadrature() {
        // Directions (θ, φ) about the axis within the cap, clipped to cos θ > 0.
        for t in [0.3, 1.0, PI / 2.0, 2.5, PI] {
            let q = adaptive_2d(
                |th, _| {
                    if th < PI / 2.0 {
                        0.7 * th.cos() * th.sin()
                    } else {
                        0.0
                    }
                },
                0.0,
                t,
                |_| 0.0,
                |_| 2.0 * PI,
                1e-12,
            );
            let e = spherical_cap_irradiance_at_centre(t, 0.7);
            assert!(rel(e, q) < 1e-9, "{t}: {e} vs {q}");
        }
    }

    #[test]
    fn partial_sums_by_summing_the_series() {
        for (le, rho, k) in [
            (1.0, 0.8, 0u32),
            (2.0, 0.5, 3),
            (1.0, 1.0, 5),
            (1.0, 0.999999, 40),
            (0.5, 0.0, 4),
        ] {
            let (mut sum, mut term) = (0.0, le);
            for _ in 0..=k {
                sum += term;
                term *= rho;
            }
            assert!(
                rel(closed_enclosure_bounces(le, rho, k), sum) < 1e-12,
                "{rho} {k}"
            );
        }
        // The integrating sphere's partial sums converge to Goebel's equation.
        let (le, rho, f) = (1.0, 0.9, 0.05);
        let l = integrating_sphere_bounces(le, rho, f, 2000);
        assert!(rel(l, integrating_sphere(le, rho, f)) < 1e-12);
        assert!(
            rel(
                integrating_sphere_bounces(le, rho, f, 1),
                le * (1.0 + rho * (1.0 - f))
            ) < 1e-15
        );
    }

    #[test]
    fn port_fraction_is_the_complementary_cap_share() {
        for t in [0.1, 1.0, 3.0, PI - 1e-3] {
            let total = spherical_cap_area(1.0, PI);
            let port = total - spherical_cap_area(1.0, t);
            assert!(rel(port_fraction_of_cap(t), port / total) < 1e-9 + 1e-12 / port);
        }
    }
}
