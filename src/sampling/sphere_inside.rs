//! Sampling a spherical light from a point inside it: every direction from an interior
//! point meets the sphere exactly once, so directions are drawn uniformly over the whole
//! sphere of directions ([`uniform_sphere`], density 1/(4π)) and the point is where the
//! ray leaves the sphere.
//!
//! **Why not by area.** Area sampling from inside is exact in expectation (every point of
//! the sphere is visible) but its weight L |cos θ| r²/(p_A |cos θl|) grows as 1/r² towards
//! the wall nearest the viewer: a receiver 10⁻³ radii from the wall of an emitting sphere
//! draws the patch that holds half its irradiance with a probability near 10⁻⁶, and
//! `light` read 0.084 ± 0.058 for E = πL (a receiver 10⁻⁴ away: 0.0018 ± 0.0008, z = −3863).
//! Uniform directions bound the weight by 4π L |cos θ|.
//!
//! **Distance.** With v = p − c, b = v·ω and k = (r − |v|)(r + |v|) > 0 (the viewer is
//! inside), the ray p + tω leaves the sphere at the positive root of t² + 2bt − k = 0,
//! t = √(b² + k) − b, in `f64` from the `f32` inputs, whose differences are exact there;
//! the point and the distance are rounded to `f32` once. Where b > 0 (a viewer near the
//! wall looking at it) the difference cancels, but its absolute error, a few `f64`
//! roundings of r, stays some 10⁹ times below the `f32` rounding of the point it reaches:
//! the cancellation-free k/(b + √(b² + k)) gives the same `f32` point.

use crate::sampling::sphere::{uniform_sphere, uniform_sphere_pdf};
use glam::{DVec3, Vec2, Vec3};

/// A sphere seen from a point strictly inside it.
#[derive(Clone, Copy, Debug)]
pub struct SphereInside {
    center: DVec3,
    radius: f64,
    /// v = p − c, exact in `f64`.
    v: DVec3,
    /// k = r² − |v|² > 0.
    k: f64,
}

impl SphereInside {
    /// The sphere (`center`, `radius`) seen from `p`; `None` when `p` is on or outside it
    /// (|p − c| ≥ r in `f64`) or an input is not finite.
    pub fn new(p: Vec3, center: Vec3, radius: f32) -> Option<Self> {
        if !(p.is_finite() && center.is_finite() && radius.is_finite() && radius > 0.0) {
            return None;
        }
        let (cd, r) = (center.as_dvec3(), radius as f64);
        let v = p.as_dvec3() - cd;
        let d = v.length();
        // (r − d)(r + d) rather than r² − d²: no cancellation where d is close to r.
        let k = (r - d) * (r + d);
        (d.is_finite() && k > 0.0).then_some(SphereInside {
            center: cd,
            radius: r,
            v,
            k,
        })
    }

    /// Density in solid angle: 1/(4π) for every direction (each one meets the sphere).
    pub fn pdf(&self) -> f32 {
        uniform_sphere_pdf()
    }

    /// A direction uniform over the sphere of directions, the point where the ray along
    /// it leaves the sphere, the sphere's outward normal there, and the distance to it
    /// (see the module's notes): `(point, normal, direction, distance)`.
    pub fn sample_ray(&self, u: Vec2) -> (Vec3, Vec3, Vec3, f32) {
        let w = uniform_sphere(u);
        let wd = w.as_dvec3().normalize();
        let b = self.v.dot(wd);
        let t = (b * b + self.k).sqrt() - b;
        let n = (self.v + wd * t) / self.radius;
        (
            (self.center + n * self.radius).as_vec3(),
            n.normalize().as_vec3(),
            wd.as_vec3(),
            t as f32,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every sample's ray reaches its point, which lies on the sphere with its outward
    /// normal facing away from the viewer, from the centre to 10⁻⁶ radii from the wall;
    /// on, outside or non-finite viewers have no interior sampler.
    #[test]
    fn an_inside_samples_ray_reaches_the_sphere_where_it_leaves_it() {
        let c = Vec3::new(0.5, -1.0, 2.0);
        let dirs = [
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(1.0, 2.0, -0.5).normalize(),
        ];
        for dir in dirs {
            for depth in [1.0, 0.5, 1e-3, 1e-5, 1e-6] {
                let p = (c.as_dvec3() + dir.as_dvec3() * (1.0 - depth)).as_vec3();
                let s = SphereInside::new(p, c, 1.0).unwrap();
                assert_eq!(s.pdf(), 1.0 / (4.0 * std::f32::consts::PI));
                for k in 0..64 {
                    let u = Vec2::new((k as f32 + 0.5) / 64.0, (k * 37 % 64) as f32 / 64.0);
                    let (q, n, w, t) = s.sample_ray(u);
                    assert!((w.length() - 1.0).abs() < 1e-6, "{w}");
                    assert!(t > 0.0, "depth {depth}: t = {t}");
                    let reached = p.as_dvec3() + w.as_dvec3() * t as f64;
                    let off = (reached - q.as_dvec3()).length();
                    let bound = 8.0 * f32::EPSILON as f64 * (t as f64 + 3.0);
                    assert!(off <= bound, "depth {depth}, u {u}: {off} > {bound}");
                    let r = (q.as_dvec3() - c.as_dvec3()).length();
                    assert!((r - 1.0).abs() <= 8.0 * f32::EPSILON as f64, "{r}");
                    assert!(n.dot(w) > 0.0, "the normal faces away from the viewer");
                    assert!(((q - c) - n).length() < 1e-6);
                }
            }
        }
        assert!(
            SphereInside::new(c + Vec3::X, c, 1.0).is_none(),
            "on the sphere"
        );
        assert!(
            SphereInside::new(c + 2.0 * Vec3::X, c, 1.0).is_none(),
            "outside"
        );
        assert!(SphereInside::new(Vec3::NAN, c, 1.0).is_none());
        assert!(SphereInside::new(c, c, 0.0).is_none());
        assert!(SphereInside::new(c, c, f32::INFINITY).is_none());
    }

    /// Near the wall and looking at it (b > 0, where √(b² + k) − b cancels), the
    /// distance keeps `f32` precision: from 10⁻⁶ radii inside, straight at the wall,
    /// t = 10⁻⁶ within 2ε (k as r² − |v|² in `f32` would keep none of its digits).
    #[test]
    fn the_distance_to_the_near_wall_keeps_its_digits() {
        let p = Vec3::new(0.0, 0.0, 1.0 - 1e-6);
        let s = SphereInside::new(p, Vec3::ZERO, 1.0).unwrap();
        // u.x = 0 gives z = 1: straight up, at the wall 1 − p.z away.
        let (q, _, w, t) = s.sample_ray(Vec2::new(0.0, 0.0));
        assert_eq!(w, Vec3::Z);
        let exact = 1.0 - p.z as f64;
        assert!(
            ((t as f64) - exact).abs() <= 2.0 * f32::EPSILON as f64 * exact,
            "{t}"
        );
        assert_eq!(q, Vec3::Z);
        // Straight down: the far wall, 2 − 10⁻⁶ away.
        let (_, _, w, t) = s.sample_ray(Vec2::new(1.0, 0.0));
        assert_eq!(w, -Vec3::Z);
        assert!(((t as f64) - (1.0 + p.z as f64)).abs() < 1e-6);
    }
}
