//! Uniform sampling of a triangle by area.
//!
//! Barycentrics b₀ = 1 − √u₀, b₁ = u₁√u₀ (Turk 1990, Graphics Gems "Generating random
//! points in triangles"); density 1/A with A = ½|(p₁ − p₀) × (p₂ − p₀)|.

use glam::{Vec2, Vec3};

/// Barycentric coordinates (b₀, b₁) of a uniformly distributed point; b₂ = 1 − b₀ − b₁.
#[inline]
pub fn uniform_triangle(u: Vec2) -> Vec2 {
    let su = u.x.sqrt();
    Vec2::new(1.0 - su, u.y * su)
}

/// Inverse of [`uniform_triangle`].
#[inline]
pub fn invert_uniform_triangle(b: Vec2) -> Vec2 {
    let su = 1.0 - b.x;
    let u0 = su * su;
    let u1 = if su > 0.0 {
        (b.y / su).clamp(0.0, 1.0)
    } else {
        0.5
    };
    Vec2::new(u0, u1)
}

/// A uniformly distributed point on the triangle (p₀, p₁, p₂).
#[inline]
pub fn sample_triangle(p: [Vec3; 3], u: Vec2) -> Vec3 {
    let b = uniform_triangle(u);
    // Relative to p0 so that a triangle far from the origin keeps its precision.
    p[0] + (p[1] - p[0]) * b.y + (p[2] - p[0]) * (1.0 - b.x - b.y)
}

/// Area of the triangle.
#[inline]
pub fn triangle_area(p: [Vec3; 3]) -> f32 {
    0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length()
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    proptest! {
        #[test]
        fn barycentrics_valid(u0 in 0.0f32..1.0, u1 in 0.0f32..1.0) {
            let b = uniform_triangle(Vec2::new(u0, u1));
            prop_assert!(b.x >= 0.0 && b.y >= 0.0 && b.x + b.y <= 1.0 + 1e-6);
            let back = invert_uniform_triangle(b);
            prop_assert!((back.x - u0).abs() < 1e-4);
        }
    }

    /// b₀ = 1 − √u₀, b₁ = u₁√u₀ by hand, the point they give on a right triangle with
    /// legs 2 and 3 (area 3), and the inverse at the apex (b₀ = 1).
    #[test]
    fn triangle_by_hand() {
        let b = uniform_triangle(Vec2::new(0.25, 0.6));
        assert!((b - Vec2::new(0.5, 0.3)).abs().max_element() < 1e-7);
        assert!(
            (invert_uniform_triangle(b) - Vec2::new(0.25, 0.6))
                .abs()
                .max_element()
                < 1e-6
        );
        assert_eq!(
            invert_uniform_triangle(Vec2::new(1.0, 0.0)),
            Vec2::new(0.0, 0.5)
        );
        let p = [
            Vec3::new(1.0, 1.0, 1.0),
            Vec3::new(3.0, 1.0, 1.0),
            Vec3::new(1.0, 4.0, 1.0),
        ];
        assert!((triangle_area(p) - 3.0).abs() < 1e-6);
        // b = (0.5, 0.3): p0·0.5 + p1·0.3 + p2·0.2.
        let q = sample_triangle(p, Vec2::new(0.25, 0.6));
        assert!(
            (q - Vec3::new(1.6, 1.6, 1.0)).abs().max_element() < 1e-6,
            "{q}"
        );
    }
}
