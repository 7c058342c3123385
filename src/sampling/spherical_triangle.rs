//! Uniform sampling of the solid angle a triangle subtends (Arvo 1995, "Stratified
//! Sampling of Spherical Triangles", SIGGRAPH; in the robust form of pbrt-v4 §6.5.4).
//!
//! The first uniform number picks the sub-triangle of area A′ = u₀·Ω, which fixes the
//! vertex C′ on arc AC; the second picks cos θ uniformly along arc BC′. The solid angle
//! Ω is computed with Van Oosterom & Strackee's formula
//! tan(Ω/2) = |a·(b×c)| / (1 + a·b + b·c + c·a), which stays accurate for triangles of
//! 1e-6 sr, where Girard's α+β+γ−π loses every digit in `f32`. The warp works in `f64`
//! internally (as Mitsuba's double variants do) and returns `f32` directions.

use glam::{DVec3, Vec2, Vec3};

/// A spherical triangle seen from a point.
#[derive(Clone, Copy, Debug)]
pub struct SphericalTriangle {
    a: DVec3,
    b: DVec3,
    c: DVec3,
    alpha: f64,
    solid_angle: f64,
}

fn angle_between(v1: DVec3, v2: DVec3) -> f64 {
    if v1.dot(v2) < 0.0 {
        std::f64::consts::PI - 2.0 * ((v1 + v2).length() / 2.0).min(1.0).asin()
    } else {
        2.0 * ((v2 - v1).length() / 2.0).min(1.0).asin()
    }
}

fn gram_schmidt(v: DVec3, w: DVec3) -> DVec3 {
    v - w * v.dot(w)
}

impl SphericalTriangle {
    /// The triangle `v` seen from `p`; `None` when it is degenerate (zero solid angle or
    /// `p` in its plane).
    pub fn new(p: Vec3, v: [Vec3; 3]) -> Option<Self> {
        let p = p.as_dvec3();
        let a = (v[0].as_dvec3() - p).normalize_or_zero();
        let b = (v[1].as_dvec3() - p).normalize_or_zero();
        let c = (v[2].as_dvec3() - p).normalize_or_zero();
        if a == DVec3::ZERO || b == DVec3::ZERO || c == DVec3::ZERO {
            return None;
        }
        let triple = a.dot(b.cross(c)).abs();
        let denom = 1.0 + a.dot(b) + b.dot(c) + c.dot(a);
        let solid_angle = 2.0 * triple.atan2(denom);
        if !(solid_angle > 0.0) || !solid_angle.is_finite() {
            return None;
        }
        let n_ab = a.cross(b).normalize_or_zero();
        let n_ca = c.cross(a).normalize_or_zero();
        if n_ab == DVec3::ZERO || n_ca == DVec3::ZERO {
            return None;
        }
        let alpha = angle_between(n_ab, -n_ca);
        Some(SphericalTriangle {
            a,
            b,
            c,
            alpha,
            solid_angle,
        })
    }

    /// Solid angle Ω in steradians.
    pub fn solid_angle(&self) -> f32 {
        self.solid_angle as f32
    }

    /// Density in solid angle, 1/Ω (for directions inside the triangle).
    pub fn pdf(&self) -> f32 {
        (1.0 / self.solid_angle) as f32
    }

    /// A direction uniformly distributed in the triangle's solid angle.
    pub fn sample(&self, u: Vec2) -> Vec3 {
        let (a, b, c) = (self.a, self.b, self.c);
        let area_p = u.x as f64 * self.solid_angle;
        // φ = A′ + π − α, so sin φ = sin(α − A′), cos φ = −cos(α − A′): no π cancellation.
        let (sin_phi, cos_phi) = {
            let (s, c) = (self.alpha - area_p).sin_cos();
            (s, -c)
        };
        let (sin_alpha, cos_alpha) = self.alpha.sin_cos();
        let k1 = cos_phi + cos_alpha;
        let k2 = sin_phi - sin_alpha * a.dot(b);
        let num = k2 + (k2 * cos_phi - k1 * sin_phi) * cos_alpha;
        let den = (k2 * sin_phi + k1 * cos_phi) * sin_alpha;
        let cos_bp = if den != 0.0 {
            (num / den).clamp(-1.0, 1.0)
        } else {
            1.0
        };
        let sin_bp = (1.0 - cos_bp * cos_bp).max(0.0).sqrt();
        let cp = cos_bp * a + sin_bp * gram_schmidt(c, a).normalize_or_zero();
        let cos_theta = 1.0 - u.y as f64 * (1.0 - cp.dot(b));
        let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
        let w = cos_theta * b + sin_theta * gram_schmidt(cp, b).normalize_or_zero();
        w.normalize().as_vec3()
    }

    /// Whether the direction `w` passes through the triangle.
    pub fn contains(&self, w: Vec3) -> bool {
        let w = w.as_dvec3();
        let s1 = w.dot(self.a.cross(self.b));
        let s2 = w.dot(self.b.cross(self.c));
        let s3 = w.dot(self.c.cross(self.a));
        let front = w.dot(self.a + self.b + self.c) > 0.0;
        front && ((s1 >= 0.0 && s2 >= 0.0 && s3 >= 0.0) || (s1 <= 0.0 && s2 <= 0.0 && s3 <= 0.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn octant_is_half_pi() {
        let t = SphericalTriangle::new(Vec3::ZERO, [Vec3::X, Vec3::Y, Vec3::Z]).unwrap();
        assert!((t.solid_angle() - std::f32::consts::FRAC_PI_2).abs() < 1e-6);
    }

    #[test]
    fn tiny_triangle_keeps_its_area() {
        // A right triangle with legs 1e-3 at distance 1: Ω ≈ 5e-7 sr.
        let v = [
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(1e-3, 0.0, 1.0),
            Vec3::new(0.0, 1e-3, 1.0),
        ];
        let t = SphericalTriangle::new(Vec3::ZERO, v).unwrap();
        assert!(
            (t.solid_angle() as f64 / 5e-7 - 1.0).abs() < 1e-3,
            "{}",
            t.solid_angle()
        );
    }

    proptest! {
        #[test]
        fn samples_lie_inside(u0 in 0.0f32..1.0, u1 in 0.0f32..1.0,
                              x in -1.0f32..1.0, y in -1.0f32..1.0) {
            let v = [Vec3::new(x, y, 1.0), Vec3::new(1.0, 0.2, 0.5), Vec3::new(-0.3, 0.9, 0.7)];
            if let Some(t) = SphericalTriangle::new(Vec3::ZERO, v) {
                let w = t.sample(Vec2::new(u0, u1));
                prop_assert!(w.is_finite());
                prop_assert!((w.length() - 1.0).abs() < 1e-5);
                // Inside up to rounding: nudge towards the centroid before testing.
                let centroid = (v[0].normalize() + v[1].normalize() + v[2].normalize()).normalize();
                prop_assert!(t.contains((w + centroid * 1e-4).normalize()));
            }
        }
    }
}
