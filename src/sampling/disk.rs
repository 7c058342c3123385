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
}
