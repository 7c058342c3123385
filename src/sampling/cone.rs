//! Uniform sampling of directions within a cone about +z.
//!
//! With θmax the half-angle, 1 − cos θ = u₀ (1 − cos θmax) and φ = 2πu₁; the density
//! is 1/(2π(1 − cos θmax)) per steradian (pbrt-v4 §A.5.4). To stay accurate for
//! half-angles down to 1e-4 (where cos θmax rounds to 1 in `f32`), the cone is
//! described by 1 − cos θmax = 2 sin²(θmax/2) and sin²θ is formed from 1 − cos θ
//! directly: sin²θ = (1 − cos θ)(2 − (1 − cos θ)).

use crate::math::{TWO_PI, safe_sqrt};
use glam::{Vec2, Vec3};

/// A cone described robustly by its half-angle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cone {
    /// 1 − cos θmax, accurate for tiny cones.
    pub one_minus_cos_max: f32,
}

impl Cone {
    /// The cone of half-angle `theta_max` ∈ (0, π]. Its density is an `f32` for
    /// θmax ≥ 3.1·10⁻²⁰ and accurate to rounding for θmax ≥ 2.2·10⁻¹⁹, where
    /// 1 − cos θmax = 2 sin²(θmax/2) is a normal number; below 3.1·10⁻²⁰ the solid angle
    /// 2π(1 − cos θmax) ≈ πθmax² is under 1/`f32::MAX` and [`Cone::pdf`] is +∞ (no `f32`
    /// holds the density of so narrow a cone).
    pub fn from_half_angle(theta_max: f32) -> Self {
        let s = (0.5 * theta_max).sin();
        Cone {
            one_minus_cos_max: 2.0 * s * s,
        }
    }

    /// Solid angle 2π(1 − cos θmax).
    pub fn solid_angle(&self) -> f32 {
        TWO_PI * self.one_minus_cos_max
    }

    /// A uniformly distributed direction inside the cone.
    #[inline]
    pub fn sample(&self, u: Vec2) -> Vec3 {
        let omc = u.x * self.one_minus_cos_max;
        let cos_theta = 1.0 - omc;
        let sin_theta = safe_sqrt(omc * (2.0 - omc));
        let phi = TWO_PI * u.y;
        Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta)
    }

    /// Whether the unit direction `w` lies inside the cone.
    #[inline]
    pub fn contains(&self, w: Vec3) -> bool {
        // 1 − cos θ without cancellation: (x² + y²)/(1 + z) for z > −1.
        let omc = if w.z > 0.0 {
            (w.x * w.x + w.y * w.y) / (1.0 + w.z)
        } else {
            1.0 - w.z
        };
        omc <= self.one_minus_cos_max
    }

    /// Density of [`Cone::sample`] in solid angle.
    #[inline]
    pub fn pdf(&self, w: Vec3) -> f32 {
        if self.contains(w) {
            1.0 / self.solid_angle()
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    proptest! {
        #[test]
        fn samples_inside(theta in 1e-4f32..std::f32::consts::PI, u0 in 0.0f32..1.0, u1 in 0.0f32..1.0) {
            let c = Cone::from_half_angle(theta);
            let w = c.sample(Vec2::new(u0, u1));
            prop_assert!((w.length() - 1.0).abs() < 1e-5);
            prop_assert!(c.pdf(w) > 0.0 && c.pdf(w).is_finite());
        }
    }

    #[test]
    fn tiny_cone_is_not_a_point() {
        let c = Cone::from_half_angle(1e-4);
        let w = c.sample(Vec2::new(0.999, 0.25));
        assert!(w.y > 0.9e-4, "{w}");
        assert!((c.solid_angle() - std::f32::consts::PI * 1e-8).abs() < 1e-12);
    }

    /// Closed forms for θmax = 60° (1 − cos θmax = ½, Ω = π) and θmax = 120°
    /// (1 − cos θmax = 3/2, Ω = 3π), where the cone reaches below the equator.
    #[test]
    fn cone_matches_its_closed_forms() {
        let pi = std::f32::consts::PI;
        let c = Cone::from_half_angle(pi / 3.0);
        assert!((c.one_minus_cos_max - 0.5).abs() < 1e-6);
        assert!((c.solid_angle() - pi).abs() < 1e-5);
        // 1 − cos θ = u₀/2, φ = 2πu₁.
        let w = c.sample(Vec2::new(0.5, 0.125));
        let (ct, phi) = (0.75f32, pi / 4.0);
        let st = (1.0 - ct * ct).sqrt();
        let want = Vec3::new(st * phi.cos(), st * phi.sin(), ct);
        assert!((w - want).abs().max_element() < 1e-6, "{w} vs {want}");
        assert!((c.pdf(w) - 1.0 / pi).abs() < 1e-6);
        // Just inside and just outside the rim (θ = 59° and 61°), and behind.
        let at = |deg: f32| {
            let t = deg.to_radians();
            Vec3::new(t.sin() * 0.6, t.sin() * 0.8, t.cos())
        };
        assert!(c.contains(at(59.0)) && c.pdf(at(59.0)) > 0.0);
        assert!(!c.contains(at(61.0)) && c.pdf(at(61.0)) == 0.0);
        assert!(!c.contains(-Vec3::Z));
        let wide = Cone::from_half_angle(2.0 * pi / 3.0);
        assert!((wide.one_minus_cos_max - 1.5).abs() < 1e-6);
        assert!((wide.pdf(at(110.0)) - 1.0 / (3.0 * pi)).abs() < 1e-6);
        assert!(wide.contains(at(119.0)) && !wide.contains(at(121.0)));
    }

    /// A cone 10⁻⁴ rad wide: 1 − cos θ is 5·10⁻⁹ at its rim, below the f32 spacing of
    /// cos θ near 1 (6·10⁻⁸), so `contains` must not compute 1 − cos θ by subtraction
    /// (then every direction within 3.5·10⁻⁴ rad of the axis would count as inside).
    #[test]
    fn a_tiny_cone_contains_only_its_own_directions() {
        let c = Cone::from_half_angle(1e-4);
        let at = |t: f32| Vec3::new(t.sin() * 0.6, t.sin() * 0.8, t.cos());
        assert!(c.contains(Vec3::Z) && c.contains(at(0.9e-4)));
        for t in [1.1e-4, 2e-4, 3e-4] {
            assert!(!c.contains(at(t)), "θ = {t} rad counted inside");
        }
    }
}
