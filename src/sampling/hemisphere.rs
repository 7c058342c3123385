//! Uniform and cosine-weighted sampling of the upper (+z) hemisphere.
//!
//! Uniform: z = u₀, φ = 2πu₁, density 1/(2π). Cosine-weighted: Malley's method, a
//! concentric-disk point lifted to the hemisphere, density cos θ/π (pbrt-v4 §A.5.3).

use crate::math::{INV_PI, TWO_PI, safe_sqrt};
use crate::sampling::disk::{concentric_disk, invert_concentric_disk};
use glam::{Vec2, Vec3};

/// A uniformly distributed direction with z ≥ 0.
#[inline]
pub fn uniform_hemisphere(u: Vec2) -> Vec3 {
    let z = u.x;
    let r = safe_sqrt(1.0 - z * z);
    let phi = TWO_PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Density of [`uniform_hemisphere`]: 1/(2π) above the horizon, 0 below.
#[inline]
pub fn uniform_hemisphere_pdf(w: Vec3) -> f32 {
    if w.z >= 0.0 { 0.5 * INV_PI } else { 0.0 }
}

/// A cosine-distributed direction with z ≥ 0 (Malley's method).
#[inline]
pub fn cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = concentric_disk(u);
    let z = safe_sqrt(1.0 - d.x * d.x - d.y * d.y);
    Vec3::new(d.x, d.y, z)
}

/// Density of [`cosine_hemisphere`]: cos θ/π above the horizon, 0 below.
#[inline]
pub fn cosine_hemisphere_pdf(w: Vec3) -> f32 {
    if w.z > 0.0 { w.z * INV_PI } else { 0.0 }
}

/// Inverse of [`cosine_hemisphere`].
#[inline]
pub fn invert_cosine_hemisphere(w: Vec3) -> Vec2 {
    invert_concentric_disk(Vec2::new(w.x, w.y))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    proptest! {
        #[test]
        fn cosine_is_unit_upper_and_invertible(u0 in 0.0f32..1.0, u1 in 0.0f32..1.0) {
            let u = Vec2::new(u0, u1);
            let w = cosine_hemisphere(u);
            prop_assert!((w.length() - 1.0).abs() < 1e-5);
            prop_assert!(w.z >= 0.0);
            let back = invert_cosine_hemisphere(w);
            prop_assert!((back - u).abs().max_element() < 2e-3 || w.z < 1e-2);
            let v = uniform_hemisphere(u);
            prop_assert!(v.z >= 0.0 && (v.length() - 1.0).abs() < 1e-5);
        }
    }

    /// z = u₀, φ = 2πu₁ for the uniform map; Malley's lift of the concentric disk for
    /// the cosine map; densities 1/(2π) and cos θ/π above the horizon, 0 below.
    #[test]
    fn hemisphere_maps_and_densities_by_hand() {
        let pi = std::f32::consts::PI;
        let w = uniform_hemisphere(Vec2::new(0.6, 0.125));
        let want = Vec3::new(0.8 * (pi / 4.0).cos(), 0.8 * (pi / 4.0).sin(), 0.6);
        assert!((w - want).abs().max_element() < 1e-6, "{w}");
        assert!((uniform_hemisphere_pdf(w) - 0.5 / pi).abs() < 1e-7);
        assert_eq!(uniform_hemisphere_pdf(Vec3::X), 0.5 * INV_PI);
        assert_eq!(uniform_hemisphere_pdf(-w), 0.0);
        let u = Vec2::new(0.9, 0.6);
        let d = concentric_disk(u);
        let c = cosine_hemisphere(u);
        assert_eq!(Vec2::new(c.x, c.y), d);
        assert!((c.z - (1.0 - d.length_squared()).sqrt()).abs() < 1e-6);
        assert!((cosine_hemisphere_pdf(c) - c.z / pi).abs() < 1e-7);
        assert_eq!(cosine_hemisphere_pdf(Vec3::new(0.6, 0.0, -0.8)), 0.0);
        assert_eq!(cosine_hemisphere_pdf(Vec3::X), 0.0);
        assert!((invert_cosine_hemisphere(c) - u).abs().max_element() < 1e-5);
    }
}
