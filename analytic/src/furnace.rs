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
}
