//! Sampling a spherical light of radius r from a point at distance d > r by the cone of
//! directions it subtends (pbrt-v4 §6.2.4): sin²θmax = r²/d², directions uniform in
//! the cone, density 1/(2π(1 − cos θmax)).
//!
//! **Stable point construction.** The point on the sphere is formed from the angle α at
//! the sphere's centre. pbrt-v4's cos α = sin²θ/sin θmax + cos θ √(1 − sin²θ/sin²θmax)
//! followed by sin α = √(1 − cos²α) loses sin α entirely for a viewer close to the
//! surface: at d = r(1 + h) a direction at θ hits the sphere at α ≈ h tan θ, so
//! 1 − cos α ≈ h² tan²θ / 2 falls below the `f32` rounding of 1 for h ≲ 3e-4, every such
//! point collapses onto the pole under the viewer, and the directions actually produced
//! are no longer uniform in the cone (issue 13: E = 3.62 > πL at h = 2e-4). Here both
//! sin α and cos α come from the near root of the ray–sphere quadratic written without
//! cancellation. With s = √((r² − d² sin²θ)/d²) = √((1 − cos θmax)(1 − u₀)(cos θ + cos θmax))
//! (because cos θ − cos θmax = (1 − cos θmax)(1 − u₀) when 1 − cos θ = u₀(1 − cos θmax)),
//! the distance to the near hit is t = d cos²θmax / (cos θ + s), and the law of sines
//! (sin α = t sin θ / r) and d − t cos θ = r cos α give
//!
//!   sin α = cos²θmax sin θ / (sin θmax (cos θ + s)),
//!   cos α = (sin²θmax cos θ + s) / (sin θmax (cos θ + s)),
//!
//! sums of positive terms only. The cone (d, d² − r², the frame) is computed in `f64`
//! from the `f32` inputs, whose differences are exact there, so cos²θmax = (d − r)(d + r)/d²
//! keeps its digits however thin the gap; the point and direction are rounded to `f32`
//! once at the end. Unlike pbrt-v4, which switches to the Taylor approximation
//! sin²θ ≈ u₀ sin²θmax for small cones (a density error of order sin²θmax), 1 − cos θ is
//! sampled directly, which is exact and stable.

use glam::{DVec3, Vec2, Vec3};

/// A sphere seen from a point outside it.
#[derive(Clone, Copy, Debug)]
pub struct SphereCone {
    center: DVec3,
    radius: f64,
    /// Orthonormal frame: `axis_s`, `axis_t` tangents, `axis` from the viewer to the centre.
    axis_s: DVec3,
    axis_t: DVec3,
    axis: DVec3,
    /// sin θmax = r/d.
    sin_max: f64,
    /// sin²θmax.
    sin2_max: f64,
    /// cos θmax = √(d² − r²)/d.
    cos_max: f64,
    /// cos²θmax = (d − r)(d + r)/d².
    cos2_max: f64,
    /// 1 − cos θmax = sin²θmax/(1 + cos θmax).
    one_minus_cos_max: f64,
    /// 1/(2π(1 − cos θmax)), finite and positive.
    pdf: f32,
}

/// Frame about the unit vector `n` (Duff et al. 2017), in `f64`.
fn frame_f64(n: DVec3) -> (DVec3, DVec3) {
    let sign = 1.0f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        DVec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        DVec3::new(b, sign + n.y * n.y * a, -n.y),
    )
}

impl SphereCone {
    /// The sphere (`center`, `radius`) seen from `p`; `None` when `p` is on or inside it,
    /// when an input is not finite, or when the cone is so small that its density 1/Ω
    /// overflows `f32` (Ω < ~3e-39 sr).
    pub fn new(p: Vec3, center: Vec3, radius: f32) -> Option<Self> {
        if !(p.is_finite() && center.is_finite() && radius.is_finite() && radius > 0.0) {
            return None;
        }
        let (pd, cd, r) = (p.as_dvec3(), center.as_dvec3(), radius as f64);
        // Exact: the difference of two f32 values of similar magnitude fits in f64.
        let w = cd - pd;
        let d = w.length();
        if !(d > r) || !d.is_finite() {
            return None;
        }
        let sin_max = r / d;
        let sin2_max = sin_max * sin_max;
        let cos2_max = ((d - r) / d) * ((d + r) / d);
        let cos_max = cos2_max.sqrt();
        let one_minus_cos_max = sin2_max / (1.0 + cos_max);
        let pdf = (1.0 / (std::f64::consts::TAU * one_minus_cos_max)) as f32;
        if !(cos2_max > 0.0 && one_minus_cos_max > 0.0 && pdf.is_finite() && pdf > 0.0) {
            return None;
        }
        let axis = w / d;
        let (axis_s, axis_t) = frame_f64(axis);
        Some(SphereCone {
            center: cd,
            radius: r,
            axis_s,
            axis_t,
            axis,
            sin_max,
            sin2_max,
            cos_max,
            cos2_max,
            one_minus_cos_max,
            pdf,
        })
    }

    /// Solid angle 2π(1 − cos θmax).
    pub fn solid_angle(&self) -> f32 {
        (std::f64::consts::TAU * self.one_minus_cos_max) as f32
    }

    /// Density in solid angle of [`SphereCone::sample`]: 1/(2π(1 − cos θmax)), uniform
    /// over the cone (finite and positive by construction).
    pub fn pdf(&self) -> f32 {
        self.pdf
    }

    fn to_world(self, v: DVec3) -> DVec3 {
        self.axis_s * v.x + self.axis_t * v.y + self.axis * v.z
    }

    /// The sampled direction from the viewer, the outward normal at the point it hits,
    /// both in `f64` and in world space, and the distance t = d cos²θmax / (cos θ + s)
    /// from the viewer to that point (the near root; see the module's notes).
    fn sample_f64(&self, u: Vec2) -> (DVec3, DVec3, f64) {
        let u0 = (u.x as f64).clamp(0.0, 1.0);
        // 1 − cos θ sampled directly keeps sin²θ = (1 − cos θ)(1 + cos θ) accurate.
        let omc = u0 * self.one_minus_cos_max;
        let cos_t = 1.0 - omc;
        let sin_t = (omc * (2.0 - omc)).max(0.0).sqrt();
        // s² = (r² − d² sin²θ)/d² = (cos θ − cos θmax)(cos θ + cos θmax).
        let s = (self.one_minus_cos_max * (1.0 - u0) * (cos_t + self.cos_max))
            .max(0.0)
            .sqrt();
        let den = self.sin_max * (cos_t + s);
        let sin_a = self.cos2_max * sin_t / den;
        let cos_a = (self.sin2_max * cos_t + s) / den;
        let phi = std::f64::consts::TAU * u.y as f64;
        let (sin_phi, cos_phi) = phi.sin_cos();
        let w = self.to_world(DVec3::new(sin_t * cos_phi, sin_t * sin_phi, cos_t));
        // The normal points back towards the viewer's side: −cos α along the axis.
        let n = self
            .to_world(DVec3::new(sin_a * cos_phi, sin_a * sin_phi, -cos_a))
            .normalize();
        let t = self.radius / self.sin_max * self.cos2_max / (cos_t + s);
        (w, n, t)
    }

    /// A point on the visible cap whose direction from the viewer is uniform in the cone.
    pub fn sample_point(&self, u: Vec2) -> Vec3 {
        let (_, n, _) = self.sample_f64(u);
        (self.center + n * self.radius).as_vec3()
    }

    /// [`SphereCone::sample_point`] with the unit direction towards it and its distance
    /// from the viewer, both formed in `f64` before rounding: from a viewer closer to
    /// the sphere than the rounding of the `f32` points (a floor point 10⁻⁸ below a
    /// sphere light placed 1.5 from the origin, whose coordinates are 1.2·10⁻⁷ apart)
    /// q − p would carry no direction at all.
    pub fn sample_ray(&self, u: Vec2) -> (Vec3, Vec3, f32) {
        let (w, n, t) = self.sample_f64(u);
        (
            (self.center + n * self.radius).as_vec3(),
            w.normalize().as_vec3(),
            t as f32,
        )
    }

    /// A direction uniform in the cone (towards [`SphereCone::sample_point`]); `p` is
    /// the viewer the cone was built for (kept for the signature; the direction is formed
    /// in `f64` inside the cone's frame).
    pub fn sample(&self, _p: Vec3, u: Vec2) -> Vec3 {
        self.sample_f64(u).0.normalize().as_vec3()
    }

    /// Whether direction `w` from the viewer falls inside the cone, allowing for the
    /// rounding of an `f32` direction: about 3e-7 rad at the rim (5 ulps of a unit vector),
    /// i.e. 1 − cos θ may exceed 1 − cos θmax by 3e-7 sin θmax (plus 1e-6 relative).
    pub fn contains(&self, w: Vec3) -> bool {
        let w = w.as_dvec3();
        let len = w.length();
        if !(len > 0.0) {
            return false;
        }
        let z = w.dot(self.axis) / len;
        let omc = if z > 0.0 {
            (1.0 - z * z).max(0.0) / (1.0 + z)
        } else {
            1.0 - z
        };
        omc <= self.one_minus_cos_max * (1.0 + 1e-6) + 3e-7 * self.sin_max
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::chi2::{Chi2Test, Domain};
    use proptest::prelude::*;

    /// A unit sphere at distance `1 + gap` from `p` along the unit direction `dir`.
    fn setup(p: Vec3, dir: Vec3, gap: f64) -> (Vec3, f64) {
        let c = (p.as_dvec3() + dir.as_dvec3().normalize() * (1.0 + gap)).as_vec3();
        (c, (c.as_dvec3() - p.as_dvec3()).length())
    }

    /// A cone sample's ray (`sample_ray`): the unit direction is the one towards the
    /// point, and p + t w is the point on the sphere, in f64 to the point's own rounding,
    /// from gaps 10⁻⁶ to 10³ radii and every part of the cone (rim included).
    #[test]
    fn a_cone_samples_ray_reaches_its_point() {
        let p = Vec3::new(0.25, -0.5, 0.75);
        for (k, gap) in [1e-6, 1e-3, 0.1, 1.0, 1e3].into_iter().enumerate() {
            let (c, _) = setup(p, Vec3::new(1.0, 2.0, -0.5 + k as f32), gap);
            let s = SphereCone::new(p, c, 1.0).unwrap();
            for (u0, u1) in [
                (0.0, 0.0),
                (0.5, 0.3),
                (0.999, 0.7),
                (1.0, 0.9),
                (0.25, 0.55),
            ] {
                let (q, w, t) = s.sample_ray(Vec2::new(u0, u1));
                assert_eq!(q, s.sample_point(Vec2::new(u0, u1)));
                assert!((w.length() - 1.0).abs() < 1e-6, "{w}");
                let reached = p.as_dvec3() + w.as_dvec3() * t as f64;
                let off = (reached - q.as_dvec3()).length();
                // The f32 roundings of w and t (ε·t each) and of q (ε·|q|).
                let bound = 4.0 * f32::EPSILON as f64 * (t as f64 + q.abs().max_element() as f64);
                assert!(off <= bound, "gap {gap}, u ({u0}, {u1}): {off} > {bound}");
                let r = (q.as_dvec3() - c.as_dvec3()).length();
                assert!(
                    (r - 1.0).abs()
                        <= 4.0 * f32::EPSILON as f64 * (1.0 + c.abs().max_element() as f64)
                );
            }
        }
    }

    proptest! {
        #[test]
        fn points_on_sphere_and_visible(u0 in 0.0f32..1.0, u1 in 0.0f32..1.0,
                                        log_gap in -5.0f64..4.0,
                                        dx in -1.0f32..1.0, dy in -1.0f32..1.0, dz in -1.0f32..1.0,
                                        px in -2.0f32..2.0, py in -2.0f32..2.0) {
            let dir = Vec3::new(dx, dy, dz);
            prop_assume!(dir.length() > 0.1);
            let p = Vec3::new(px, py, 0.5);
            let (c, d) = setup(p, dir, 10f64.powf(log_gap));
            let s = SphereCone::new(p, c, 1.0).unwrap();
            let pdf = s.pdf();
            prop_assert!(pdf.is_finite() && pdf > 0.0);
            prop_assert!(s.solid_angle().is_finite() && s.solid_angle() > 0.0);
            let q = s.sample_point(Vec2::new(u0, u1));
            prop_assert!(q.is_finite());
            // On the sphere to within the rounding of the f32 coordinates.
            let scale = c.abs().max_element().max(1.0) as f64;
            let qd = q.as_dvec3() - c.as_dvec3();
            prop_assert!((qd.length() - 1.0).abs() < 4e-7 * scale, "|q − c| = {}", qd.length());
            // Visible: the outward normal faces the viewer (within rounding).
            let to_p = p.as_dvec3() - q.as_dvec3();
            prop_assert!(qd.dot(to_p) >= -4e-7 * scale * (1.0 + to_p.length()));
            // The direction returned lies in the cone and points at the sampled point.
            let w = s.sample(p, Vec2::new(u0, u1));
            prop_assert!(w.is_finite() && (w.length() - 1.0).abs() < 1e-6);
            prop_assert!(s.contains(w));
            let wq = to_p.normalize() * -1.0;
            let err = (wq - w.as_dvec3()).length();
            prop_assert!(err < 1e-6 + 4e-7 * scale / to_p.length(), "angle {err} at d = {d}");
        }

        #[test]
        fn no_nan_inf_or_negative(px in -1e30f32..1e30, cx in -1e30f32..1e30,
                                  r in 1e-30f32..1e30, u0 in 0.0f32..=1.0, u1 in 0.0f32..=1.0) {
            if let Some(s) = SphereCone::new(Vec3::new(px, 0.0, 0.0), Vec3::new(cx, 1.0, 0.0), r) {
                prop_assert!(s.pdf().is_finite() && s.pdf() > 0.0);
                let w = s.sample(Vec3::ZERO, Vec2::new(u0, u1));
                prop_assert!(w.is_finite() && (w.length() - 1.0).abs() < 1e-5);
                prop_assert!(s.sample_point(Vec2::new(u0, u1)).is_finite() || r > 1e37);
            }
        }
    }

    /// Degenerate and boundary inputs give `None`, never a NaN density.
    #[test]
    fn degenerate_inputs() {
        let c = Vec3::new(0.0, 0.0, 1.0);
        assert!(SphereCone::new(Vec3::ZERO, c, 1.0).is_none()); // on the sphere
        assert!(SphereCone::new(Vec3::ZERO, c, 2.0).is_none()); // inside
        assert!(SphereCone::new(Vec3::ZERO, c, 0.0).is_none());
        assert!(SphereCone::new(Vec3::ZERO, c, f32::NAN).is_none());
        assert!(SphereCone::new(Vec3::splat(f32::INFINITY), c, 1.0).is_none());
        // Ω ≈ π·1e-40 sr: 1/Ω overflows f32.
        assert!(SphereCone::new(Vec3::ZERO, Vec3::new(0.0, 0.0, 1e20), 1.0).is_none());
        // The nearest f32 viewer outside the unit sphere still gets a cone.
        let p = Vec3::new(0.0, 0.0, 1.0 + f32::EPSILON);
        let s = SphereCone::new(p, Vec3::ZERO, 1.0).unwrap();
        assert!(s.pdf().is_finite() && s.pdf() > 0.0);
        let w = s.sample(p, Vec2::new(0.999, 0.3));
        assert!(w.is_finite() && s.contains(w));
    }

    /// Cone integrals of the directions the scene forms, normalize(q − p) from the `f32`
    /// point, against their exact values in `f64`: the solid angle Ω = 2π(1 − cos θmax),
    /// E = ∫ cos θ dω = π sin²θmax (receiver facing the centre), ∫ cos³θ dω =
    /// π(1 − cos⁴θmax)/2 and ∫ sin²θ cos²φ dω about the axis (both weigh the rim).
    /// The old construction failed this at gap 2e-4 by +15 % (the collapse of every
    /// point onto the pole).
    #[test]
    fn cone_integrals_near_and_far() {
        let n = 256usize;
        for gap in [1e-5, 3e-5, 1e-4, 2e-4, 5e-4, 1e-3, 1e-2, 1.0, 1e3] {
            for dir in [Vec3::Z, Vec3::new(0.3, -0.8, 0.5)] {
                let p = Vec3::new(0.25, -0.5, 0.125);
                let (c, d) = setup(p, dir, gap);
                let s = SphereCone::new(p, c, 1.0).unwrap();
                let axis = (c.as_dvec3() - p.as_dvec3()).normalize();
                let (tx, _) = frame_f64(axis);
                let sin2 = 1.0 / (d * d);
                let cos2 = (d - 1.0) * (d + 1.0) / (d * d);
                let omega = std::f64::consts::TAU * sin2 / (1.0 + cos2.sqrt());
                let (mut m1, mut m3, mut mt) = (0.0, 0.0, 0.0);
                // A midpoint grid in (u0, u1): the integrands are smooth in u.
                for i in 0..n {
                    for j in 0..n {
                        let u = Vec2::new(
                            ((i as f64 + 0.5) / n as f64) as f32,
                            ((j as f64 + 0.5) / n as f64) as f32,
                        );
                        let q = s.sample_point(u);
                        let w = (q.as_dvec3() - p.as_dvec3()).normalize();
                        let ct = w.dot(axis);
                        m1 += ct;
                        m3 += ct * ct * ct;
                        mt += w.dot(tx).powi(2);
                    }
                }
                let k = omega / (n * n) as f64;
                let (m1, m3, mt) = (m1 * k, m3 * k, mt * k);
                let pi = std::f64::consts::PI;
                let e1 = pi * sin2;
                let e3 = pi * (1.0 - cos2 * cos2) / 2.0;
                // ∫ sin²θ cos²φ dω = π ∫ sin²θ d(cos θ) = π[(1 − c) − (1 − c³)/3] with c = cos θmax.
                let cm = cos2.sqrt();
                let et = pi * ((1.0 - cm) - (1.0 - cm * cm * cm) / 3.0);
                assert!(
                    ((1.0 / s.pdf() as f64) / omega - 1.0).abs() < 1e-6,
                    "Ω at gap {gap}"
                );
                for (name, got, want) in [("cos", m1, e1), ("cos³", m3, e3), ("tangent²", mt, et)]
                {
                    assert!(
                        (got / want - 1.0).abs() < 2e-4,
                        "gap {gap}, dir {dir}: ∫{name} = {got}, exact {want} ({:+.2e})",
                        got / want - 1.0
                    );
                }
            }
        }
    }

    /// Chi-square of the directions normalize(q − p) against the uniform cone density
    /// for viewers 1e-4 and 2e-5 above a unit sphere (the cone is almost a hemisphere),
    /// the cone's axis along +z so its rim is one row of the grid.
    #[test]
    fn chi2_of_directions_near_the_surface() {
        for (i, gap) in [1e-4f64, 2e-5].into_iter().enumerate() {
            let p = Vec3::ZERO;
            let (c, _) = setup(p, Vec3::Z, gap);
            let s = SphereCone::new(p, c, 1.0).unwrap();
            let outcome = Chi2Test::new(Domain::Sphere, 1_000_000, 17 + i as u64, 1e-4)
                .with_resolution(32, 64)
                .run(
                    "sphere_cone_near_surface",
                    |u| Some((s.sample_point(Vec2::new(u.x, u.y)) - p).normalize()),
                    |w| if s.contains(w) { s.pdf() as f64 } else { 0.0 },
                );
            assert!(outcome.passed, "gap {gap}: {outcome:?}");
        }
    }
    /// u₀ = 1 (accepted, though no sampler draws it) is the cone's rim, where s = 0: the
    /// direction is finite, on the rim, and points at a point of the sphere.
    #[test]
    fn the_rim_is_sampled_at_u0_one() {
        let (p, c) = (Vec3::ZERO, Vec3::new(0.0, 0.0, 3.0));
        let s = SphereCone::new(p, c, 1.0).unwrap();
        for u1 in [0.0f32, 0.3, 0.8] {
            let w = s.sample(p, Vec2::new(1.0, u1));
            let q = s.sample_point(Vec2::new(1.0, u1));
            assert!(w.is_finite() && q.is_finite(), "{w} {q}");
            assert!(s.contains(w));
            // cos θ = cos θmax = √8/3 at the rim.
            assert!((w.z as f64 - 8f64.sqrt() / 3.0).abs() < 1e-6, "{w}");
            assert!(((q - c).length() - 1.0).abs() < 1e-6);
        }
    }
}
