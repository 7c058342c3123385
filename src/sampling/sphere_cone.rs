//! Sampling a spherical light of radius r from a point at distance d > r by the cone of
//! directions it subtends (pbrt-v4 §6.2.4): sin²θmax = r²/d², directions uniform in
//! the cone, density 1/(2π(1 − cos θmax)). The point on the sphere is formed from the
//! angle α at the sphere's centre, cos α = sin²θ/sin θmax + cos θ √(1 − sin²θ/sin²θmax),
//! which avoids the cancellation of a ray–sphere intersection. Unlike pbrt-v4, which
//! switches to the Taylor approximation sin²θ ≈ u₀ sin²θmax for small cones (a density
//! error of order sin²θmax), 1 − cos θ is sampled directly, which is exact and stable.

use crate::math::{Frame, TWO_PI, safe_sqrt, spherical_direction};
use glam::{Vec2, Vec3};

/// A sphere seen from a point outside it.
#[derive(Clone, Copy, Debug)]
pub struct SphereCone {
    center: Vec3,
    radius: f32,
    frame: Frame,
    sin2_max: f32,
    one_minus_cos_max: f32,
}

impl SphereCone {
    /// The sphere (`center`, `radius`) seen from `p`; `None` when `p` is on or inside it.
    pub fn new(p: Vec3, center: Vec3, radius: f32) -> Option<Self> {
        let d = center - p;
        let dc2 = d.length_squared();
        if !(dc2 > radius * radius) {
            return None;
        }
        let sin2_max = (radius * radius) / dc2;
        let cos_max = safe_sqrt(1.0 - sin2_max);
        let one_minus_cos_max = sin2_max / (1.0 + cos_max);
        let frame = Frame::from_z(d / dc2.sqrt());
        Some(SphereCone {
            center,
            radius,
            frame,
            sin2_max,
            one_minus_cos_max,
        })
    }

    /// Solid angle 2π(1 − cos θmax).
    pub fn solid_angle(&self) -> f32 {
        TWO_PI * self.one_minus_cos_max
    }

    /// Density in solid angle.
    pub fn pdf(&self) -> f32 {
        1.0 / self.solid_angle()
    }

    /// A point on the visible cap whose direction from the viewer is uniform in the cone.
    pub fn sample_point(&self, u: Vec2) -> Vec3 {
        // 1 − cos θ is sampled directly, so sin²θ = (1 − cos θ)(1 + cos θ) keeps its
        // digits even for tiny cones.
        let omc = u.x * self.one_minus_cos_max;
        let (sin2_theta, cos_theta) = (omc * (2.0 - omc), 1.0 - omc);
        let sin_max = self.sin2_max.sqrt();
        let cos_alpha =
            sin2_theta / sin_max + cos_theta * safe_sqrt(1.0 - sin2_theta / self.sin2_max);
        let sin_alpha = safe_sqrt(1.0 - cos_alpha * cos_alpha);
        let phi = TWO_PI * u.y;
        // The normal at the sampled point, about the axis from the centre to the viewer.
        let local = spherical_direction(sin_alpha, cos_alpha, phi);
        let n = -self.frame.to_world(local);
        self.center + n * self.radius
    }

    /// A direction uniform in the cone (towards [`SphereCone::sample_point`]).
    pub fn sample(&self, p: Vec3, u: Vec2) -> Vec3 {
        (self.sample_point(u) - p).normalize()
    }

    /// Whether direction `w` from the viewer falls inside the cone.
    pub fn contains(&self, w: Vec3) -> bool {
        let z = w.dot(self.frame.n);
        let omc = if z > 0.0 {
            (1.0 - z * z).max(0.0) / (1.0 + z)
        } else {
            2.0
        };
        omc <= self.one_minus_cos_max * (1.0 + 1e-4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    proptest! {
        #[test]
        fn points_on_sphere_and_visible(u0 in 0.0f32..1.0, u1 in 0.0f32..1.0, d in 1.01f32..1e4) {
            let c = Vec3::new(0.3, d, -0.2);
            let s = SphereCone::new(Vec3::ZERO, c, 1.0).unwrap();
            let q = s.sample_point(Vec2::new(u0, u1));
            prop_assert!(((q - c).length() - 1.0).abs() < 1e-3 * d.max(1.0));
            // Visible: the outward normal faces the viewer (within rounding).
            prop_assert!((q - c).dot(-q) >= -1e-3 * d);
        }
    }
}
