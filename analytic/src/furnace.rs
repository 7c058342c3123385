//! Furnace tests: enclosures in radiative equilibrium, where the answer is known without
//! tracing a single path. A renderer that loses or invents energy fails them.

/// Radiance inside a closed enclosure whose walls all emit Le and reflect diffusely
/// with albedo ρ < 1.
///
/// **Formula.** L = Le / (1 − ρ).
///
/// **Derivation.** By symmetry (a sphere) or by the uniform solution of the radiosity
/// equation (any closed enclosure: Σⱼ Fᵢⱼ = 1), L = Le + ρ L, the Neumann series
/// Σₖ ρᵏ Le.
///
/// **Source.** Siegel & Howell, ch. 6 (enclosure theory); pbrt 4th ed. §13 exercises
/// ("furnace test").
pub fn closed_enclosure(emitted_radiance: f64, albedo: f64) -> f64 {
    emitted_radiance / (1.0 - albedo)
}

/// Reflected radiance of a convex Lambertian object of albedo ρ under a constant
/// environment of radiance L (convex: it never sees itself).
///
/// **Formula.** L_o = ρ L. **Derivation.** L_o = (ρ/π) ∫ L cos θ dω = ρ L.
/// **Source.** pbrt 4th ed. §4.3 (Lambertian reflection), "white furnace".
pub fn convex_object(albedo: f64, environment_radiance: f64) -> f64 {
    albedo * environment_radiance
}

/// Wall radiance of an integrating sphere whose wall emits Le uniformly and reflects
/// diffusely with albedo ρ, with a black (open) port of area fraction f.
///
/// **Formula.** L = Le / (1 − ρ (1 − f)).
///
/// **Derivation.** Inside a sphere, the view factor from any element to any region is
/// that region's share of the sphere's area (cos θ₁ = cos θ₂ = s/2R, so the kernel
/// cos θ₁ cos θ₂/(π s²) = 1/(4πR²) is constant). A uniform wall radiance therefore
/// stays uniform: L = Le + ρ (1 − f) L.
///
/// **Source.** Goebel, "Generalized integrating-sphere theory", Appl. Opt. 6(1), 1967;
/// Siegel & Howell, ch. 6.
///
/// The denominator is evaluated as (1 − ρ) + ρ f, equal to 1 − ρ(1 − f) but without
/// rounding 1 − f to 1: at ρ = 1 and a port of f ~ 10⁻²¹ the direct form gave 1/0 = ∞.
pub fn integrating_sphere(emitted_radiance: f64, albedo: f64, port_fraction: f64) -> f64 {
    emitted_radiance / ((1.0 - albedo) + albedo * port_fraction)
}

/// Irradiance on a receiver beside or inside a lossless smooth dielectric sphere (index
/// η, in vacuum) under a constant environment of radiance L: the dielectric furnace.
///
/// **Formula.** E = π n² L, with n the index of the medium the receiver is in: 1 beside
/// the sphere, η inside it at a distance d < R/η from its centre.
///
/// **Derivation.** At a smooth lossless interface the basic radiance L/n² of a ray is the
/// Fresnel mix of the basic radiances of the two rays it comes from, L/n² = R L_r/n_r² +
/// T L_t/n_t² with R + T = 1 (reflection keeps the medium; transmission scales radiance
/// by (n₂/n₁)², [`crate::radiometry::radiance_across_interface`]). Followed backwards from
/// the receiver, a ray branches at every surface it meets, and the weights of the
/// branches, products of R and T, sum to 1 over those that reach the environment, if no
/// weight stays trapped. Each of those carries basic radiance L/1², so the ray's basic
/// radiance is L and its radiance n² L, whatever its direction: E = ∫ n² L cos θ dω =
/// π n² L. Nothing is trapped: both ends of a chord of a sphere meet the surface at the
/// same angle to the normal, so a ray that entered from vacuum (below the critical angle)
/// is never totally reflected and leaves with T > 0 at each meeting; a ray from a point
/// inside at distance d from the centre meets the surface at sin θ ≤ d/R < 1/η, below
/// the critical angle too. Beyond d = R/η the rays with sin θ > 1/η are trapped by total
/// internal reflection (whispering-gallery rays): no light reaches the receiver along
/// them and E is smaller (`tests::dielectric_furnace_by_quadrature_of_the_fresnel_series`).
///
/// **Source.** Nicodemus, "Radiance", Am. J. Phys. 31, 1963 (basic radiance L/n²);
/// Veach, PhD thesis, Stanford 1997, §5.2 (radiance scaled by η² at refraction);
/// Born & Wolf, *Principles of Optics*, §1.5.3 (R + T = 1).
pub fn dielectric_furnace_irradiance(radiance: f64, index_at_receiver: f64) -> f64 {
    std::f64::consts::PI * index_at_receiver * index_at_receiver * radiance
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Vec3;
    use crate::quadrature::adaptive_2d;
    use std::f64::consts::PI;

    #[test]
    fn neumann_series() {
        for (le, rho) in [(1.0, 0.5), (2.0, 0.99), (0.3, 0.0)] {
            let (mut sum, mut term) = (0.0, le);
            while term > 1e-18 * le {
                sum += term;
                term *= rho;
            }
            assert!((closed_enclosure(le, rho) - sum).abs() < 1e-12 * sum);
        }
    }

    #[test]
    fn convex_object_by_quadrature() {
        let q = adaptive_2d(
            |t, _| 0.7 / PI * 2.0 * t.cos() * t.sin(),
            0.0,
            PI / 2.0,
            |_| 0.0,
            |_| 2.0 * PI,
            1e-13,
        );
        assert!((convex_object(0.7, 2.0) - q).abs() < 1e-12);
    }

    #[test]
    fn sphere_view_factor_is_area_fraction() {
        // From a point on a unit sphere to a cap (the port) of angular radius γ about an
        // arbitrary axis: F = ∫ cos θ₁ cos θ₂ /(π s²) dA must equal the cap's area share.
        let p = Vec3::new(0.0, 0.0, -1.0);
        let axis = Vec3::new(0.6, 0.0, 0.8);
        let (e1, e2) = axis.orthonormal_basis();
        let gamma: f64 = 0.4;
        let f = adaptive_2d(
            |a, phi| {
                let (sa, ca) = a.sin_cos();
                let q = axis * ca + (e1 * phi.cos() + e2 * phi.sin()) * sa;
                let d = q - p;
                let s2 = d.length_squared();
                let s = s2.sqrt();
                let c1 = (-p).dot(d) / s; // inward normal at p is −p
                let c2 = q.dot(d) / s; // inward normal at q is −q, direction q → p is −d
                c1 * c2 / (PI * s2) * sa
            },
            0.0,
            gamma,
            |_| 0.0,
            |_| 2.0 * PI,
            1e-12,
        );
        let share = (1.0 - gamma.cos()) / 2.0;
        assert!((f - share).abs() < 1e-11 * share, "{f} vs {share}");
        // With that property, iterate the radiosity balance L ← Le + ρ(1−f)L.
        let (le, rho) = (1.0, 0.95);
        let mut l = 0.0;
        for _ in 0..2000 {
            l = le + rho * (1.0 - share) * l;
        }
        assert!((integrating_sphere(le, rho, share) - l).abs() < 1e-12 * l);
    }

    /// The dielectric furnace's irradiance as a quadrature over the receiver's hemisphere
    /// of n² L times the weight that reaches the environment. A receiver at distance d
    /// from the centre of the unit sphere, its normal along the line to the centre, sees
    /// each direction at angle α from that line along a ray whose line passes at
    /// b = d sin α from the centre; every meeting with the sphere is then at sin θ = b
    /// from inside (both ends of a chord alike), or sin θ = b/η for a receiver beside it
    /// (refracted), and a weight R(θ)^k is still inside after k of them (k = 10⁹ here).
    /// Within d < R/η of the centre (and beside the sphere) it is π n² L; beyond, the
    /// rays with sin θ > 1/η are trapped and E = π n² L sin²α*, with d sin α* = 1/η.
    #[test]
    fn dielectric_furnace_by_quadrature_of_the_fresnel_series() {
        use crate::quadrature::adaptive;
        let (eta, l) = (1.5, 1.0);
        let irradiance = |d: f64, n: f64| {
            let inside = d < 1.0;
            let share = adaptive(
                |a| {
                    let b = d * a.sin();
                    let trapped = if inside || b < 1.0 {
                        let sin_inside = if inside { b } else { b / eta };
                        // A negative cosine: the meeting is from the inside.
                        let cos_inside = (1.0 - sin_inside * sin_inside).sqrt();
                        crate::fresnel::dielectric(-cos_inside, eta).powi(1_000_000_000)
                    } else {
                        0.0
                    };
                    2.0 * PI * (1.0 - trapped) * a.cos() * a.sin()
                },
                0.0,
                PI / 2.0,
                1e-13,
            );
            n * n * l * share
        };
        // Beside (at the catalog's distance, |(0.3, 0, 1.5)|), and inside at the
        // catalog's 0.6 and nearer the centre.
        for (d, n) in [(0.3f64.hypot(1.5), 1.0), (0.6, eta), (0.245, eta)] {
            let e = dielectric_furnace_irradiance(l, n);
            let q = irradiance(d, n);
            assert!((q - e).abs() < 1e-10 * e, "d = {d}: {q} vs {e}");
        }
        // Beyond R/η = 2/3 the trapped rays take their share.
        let d = 0.9;
        let sin_a = 1.0 / (eta * d);
        let e = dielectric_furnace_irradiance(l, eta) * sin_a * sin_a;
        let q = irradiance(d, eta);
        assert!((q - e).abs() < 1e-8 * e, "{q} vs {e}");
    }
}
