//! Uniform sampling of the unit sphere.
//!
//! z = 1 − 2u₀, φ = 2πu₁ (Archimedes' hat-box theorem: z is uniform on a sphere);
//! density 1/(4π) per steradian (pbrt-v4 §A.5.2).

use crate::math::{INV_FOUR_PI, TWO_PI, azimuth, safe_sqrt};
use glam::{Vec2, Vec3};

/// A uniformly distributed unit vector.
#[inline]
pub fn uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = safe_sqrt(1.0 - z * z);
    let phi = TWO_PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Density of [`uniform_sphere`] in solid angle.
#[inline]
pub fn uniform_sphere_pdf() -> f32 {
    INV_FOUR_PI
}

/// Inverse of [`uniform_sphere`].
#[inline]
pub fn invert_uniform_sphere(w: Vec3) -> Vec2 {
    Vec2::new((1.0 - w.z) * 0.5, azimuth(w) / TWO_PI)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    proptest! {
        #[test]
        fn unit_and_invertible(u0 in 0.0f32..1.0, u1 in 0.0f32..1.0) {
            let w = uniform_sphere(Vec2::new(u0, u1));
            prop_assert!((w.length() - 1.0).abs() < 1e-5);
            let back = invert_uniform_sphere(w);
            prop_assert!((back.x - u0).abs() < 1e-4);
            let dphi = (back.y - u1).abs();
            prop_assert!(dphi < 1e-3 || (1.0 - dphi) < 1e-3 || w.z.abs() > 0.9999);
        }
    }

    /// z = 1 − 2u₀, φ = 2πu₁ by hand; density 1/(4π).
    #[test]
    fn sphere_map_by_hand() {
        let pi = std::f32::consts::PI;
        let w = uniform_sphere(Vec2::new(0.8, 0.375));
        let want = Vec3::new(0.8 * (0.75 * pi).cos(), 0.8 * (0.75 * pi).sin(), -0.6);
        assert!((w - want).abs().max_element() < 1e-6, "{w}");
        assert!((uniform_sphere_pdf() - 0.25 / pi).abs() < 1e-8);
        assert!(
            (invert_uniform_sphere(w) - Vec2::new(0.8, 0.375))
                .abs()
                .max_element()
                < 1e-6
        );
    }
}
