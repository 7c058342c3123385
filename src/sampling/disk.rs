//! Concentric mapping of the square to the unit disk (Shirley & Chiu 1997, "A
//! Low Distortion Map Between Disk and Square"). Area preserving up to the constant
//! π: density 1/π per unit area.

use crate::math::{INV_PI, PI};
use glam::Vec2;

/// A uniformly distributed point on the unit disk.
#[inline]
pub fn concentric_disk(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o.x == 0.0 && o.y == 0.0 {
        return Vec2::ZERO;
    }
    let (r, theta) = if o.x.abs() > o.y.abs() {
        (o.x, (PI / 4.0) * (o.y / o.x))
    } else {
        (o.y, PI / 2.0 - (PI / 4.0) * (o.x / o.y))
    };
    Vec2::new(r * theta.cos(), r * theta.sin())
}

/// Density of [`concentric_disk`] per unit area.
#[inline]
pub fn concentric_disk_pdf(p: Vec2) -> f32 {
    if p.length_squared() <= 1.0 {
        INV_PI
    } else {
        0.0
    }
}

/// Inverse of [`concentric_disk`].
pub fn invert_concentric_disk(p: Vec2) -> Vec2 {
    let r = p.length().min(1.0);
    if r == 0.0 {
        return Vec2::splat(0.5);
    }
    let mut phi = p.y.atan2(p.x);
    if phi < -PI / 4.0 {
        phi += 2.0 * PI;
    }
    let (a, b) = if phi < PI / 4.0 {
        (r, r * phi * 4.0 / PI)
    } else if phi < 3.0 * PI / 4.0 {
        (-r * (phi - PI / 2.0) * 4.0 / PI, r)
    } else if phi < 5.0 * PI / 4.0 {
        (-r, -r * (phi - PI) * 4.0 / PI)
    } else {
        (r * (phi - 3.0 * PI / 2.0) * 4.0 / PI, -r)
    };
    ((Vec2::new(a, b) + Vec2::ONE) * 0.5).clamp(Vec2::ZERO, Vec2::ONE)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    proptest! {
        #[test]
        fn inside_and_invertible(u0 in 0.0f32..1.0, u1 in 0.0f32..1.0) {
            let u = Vec2::new(u0, u1);
            let p = concentric_disk(u);
            prop_assert!(p.length() <= 1.0 + 1e-6);
            let back = invert_concentric_disk(p);
            prop_assert!((back - u).abs().max_element() < 1e-4);
        }
    }

    /// Shirley–Chiu by hand in each of the four sectors: u = (0.9, 0.6) gives
    /// o = (0.8, 0.2), r = 0.8, θ = (π/4)(0.2/0.8) = π/16; u = (0.6, 0.1) gives
    /// o = (0.2, −0.8), r = −0.8, θ = π/2 − (π/4)(0.2/−0.8) = 9π/16; the other two by
    /// symmetry. The centre maps to the centre, and the inverse maps each point back.
    #[test]
    fn concentric_disk_by_hand() {
        let pi = std::f32::consts::PI;
        let polar = |r: f32, t: f32| Vec2::new(r * t.cos(), r * t.sin());
        for (u, want) in [
            (Vec2::new(0.9, 0.6), polar(0.8, pi / 16.0)),
            (Vec2::new(0.6, 0.1), polar(-0.8, 9.0 * pi / 16.0)),
            (Vec2::new(0.1, 0.4), polar(-0.8, pi / 16.0)),
            (Vec2::new(0.4, 0.9), polar(0.8, 9.0 * pi / 16.0)),
        ] {
            let p = concentric_disk(u);
            assert!((p - want).abs().max_element() < 1e-6, "{u}: {p} vs {want}");
            let back = invert_concentric_disk(p);
            assert!((back - u).abs().max_element() < 1e-5, "{u}: {back}");
            assert_eq!(concentric_disk_pdf(p), INV_PI);
        }
        assert_eq!(concentric_disk(Vec2::splat(0.5)), Vec2::ZERO);
        // On the axes (one of o's components zero, not both) the point is not the centre:
        // u = (0.5, 0.75) gives o = (0, 0.5), r = 0.5, θ = π/2; u = (0.25, 0.5) gives
        // o = (−0.5, 0), r = −0.5, θ = 0.
        for (u, want) in [
            (Vec2::new(0.5, 0.75), polar(0.5, pi / 2.0)),
            (Vec2::new(0.25, 0.5), polar(-0.5, 0.0)),
        ] {
            let p = concentric_disk(u);
            assert!((p - want).abs().max_element() < 1e-6, "{u}: {p} vs {want}");
        }
        assert_eq!(invert_concentric_disk(Vec2::ZERO), Vec2::splat(0.5));
        assert_eq!(concentric_disk_pdf(Vec2::new(0.8, 0.7)), 0.0);
        assert_eq!(concentric_disk_pdf(Vec2::new(1.0, 0.0)), INV_PI);
    }
}
