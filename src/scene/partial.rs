//! Partial shapes: the spherical cap (pbrt's sphere with zmin = r cos θmax, zmax = r,
//! about an axis) and the annulus (pbrt's disk with an inner radius).
//!
//! Both reuse their whole shape's robust intersection and clip the hit: the cap keeps a
//! sphere hit whose polar angle about the axis is at most θmax (trying the far root when
//! the near one is clipped away, so a ray from inside an open sphere finds the wall
//! behind the port), the annulus keeps a disk-plane hit at radius ≥ r. Error bounds are
//! those of the whole shape. Area sampling is uniform: the cap by Archimedes'
//! hat-box theorem (area is linear in height along the axis: z = 1 − u(1 − cos θmax)),
//! the annulus uniformly in ρ² ∈ [r², R²]; both have density 1/A.

use super::shape::{AreaSample, Hit, Primitive};
use crate::math::{Frame, TWO_PI, gamma};
use glam::{Vec2, Vec3};

/// Area of a spherical cap, 2π R² (1 − cos θmax), with `one_minus_cos` = 1 − cos θmax
/// computed without cancellation when the shape was built.
pub fn cap_area(radius: f32, one_minus_cos: f32) -> f32 {
    TWO_PI * radius * radius * one_minus_cos
}

/// Whether the sphere's hit at distance `t` along o + t d lies on the cap: the polar angle
/// of rel = o − c + t d about the axis â has 1 − cos θ = (|rel| − ⟨rel, â⟩)/|rel| at most
/// 1 − cos θmax. The angle, not the height ⟨rel, â⟩: the sphere's root t is off by a few
/// 10⁻⁸ R for an origin near the surface, mostly along the ray, which moves the height
/// but hardly the angle.
///
/// Decided in `f64` from the ray (o − c + t d, the `f32` products exact, with the axis
/// normalised in `f64`), not from the hit's `f32` point: that point lies on `f32`'s grid,
/// about 6·10⁻⁸ R apart near the rim, and a comparison on the grid moves the rim to the
/// grid point beside it the same way for every ray from a receiver beside it (as for the
/// disk's rim, `shape::intersect_ring`; `cap_rims_admit_no_band_beyond_them`).
/// `one_minus_cos` is the cap's own parameter, as its sampling and area read it (cos θmax
/// in `f32` is 1 for any cap narrower than about 3·10⁻⁴ rad).
#[allow(clippy::too_many_arguments)]
fn on_cap(
    o: Vec3,
    d: Vec3,
    t: f32,
    center: Vec3,
    axis: Vec3,
    cos_max: f32,
    one_minus_cos: f32,
) -> bool {
    if cos_max <= -1.0 {
        return true;
    }
    let rel = o.as_dvec3() - center.as_dvec3() + d.as_dvec3() * f64::from(t);
    let r = rel.length();
    r - rel.dot(axis.as_dvec3().normalize()) <= r * f64::from(one_minus_cos)
}

/// Closest hit on the cap with t in (tmin, tmax): the near sphere root if it lies on the
/// cap ([`on_cap`]), else the far root.
#[allow(clippy::too_many_arguments)]
pub fn intersect_cap(
    center: Vec3,
    radius: f32,
    axis: Vec3,
    (cos_max, one_minus_cos): (f32, f32),
    o: Vec3,
    d: Vec3,
    tmin: f32,
    tmax: f32,
) -> Option<Hit> {
    let sphere = Primitive::Sphere { center, radius };
    let on = |t| on_cap(o, d, t, center, axis, cos_max, one_minus_cos);
    let near = sphere.intersect(o, d, tmin, tmax)?;
    if on(near.t) {
        return Some(near);
    }
    let far = sphere.intersect(o, d, near.t, tmax)?;
    on(far.t).then_some(far)
}

/// A point uniformly distributed by area on the cap.
pub fn sample_cap(
    center: Vec3,
    radius: f32,
    axis: Vec3,
    one_minus_cos: f32,
    u: Vec2,
) -> AreaSample {
    // Height below the pole h = u (1 − cos θmax); sin²θ = h (2 − h) without cancellation.
    let h = u.x * one_minus_cos;
    let z = 1.0 - h;
    let sin = (h * (2.0 - h)).max(0.0).sqrt();
    let phi = TWO_PI * u.y;
    let f = Frame::from_z(axis);
    let n = (f.s * (sin * phi.cos()) + f.t * (sin * phi.sin()) + f.n * z).normalize();
    let rel = n * radius;
    AreaSample {
        p: center + rel,
        p_error: gamma(5) * (center.abs() + rel.abs()),
        n,
        pdf: 1.0 / cap_area(radius, one_minus_cos),
    }
}

/// Area of an annulus, π (R − r)(R + r).
pub fn annulus_area(inner: f32, radius: f32) -> f32 {
    std::f32::consts::PI * (radius - inner) * (radius + inner)
}

/// A point uniformly distributed by area on the annulus: ρ² uniform in [r², R²].
pub fn sample_annulus(center: Vec3, normal: Vec3, inner: f32, radius: f32, u: Vec2) -> AreaSample {
    let rho = (inner * inner + u.x * (radius - inner) * (radius + inner))
        .sqrt()
        .clamp(inner, radius);
    let phi = TWO_PI * u.y;
    let f = Frame::from_z(normal);
    let rel = f.s * (rho * phi.cos()) + f.t * (rho * phi.sin());
    AreaSample {
        p: center + rel,
        p_error: gamma(6) * (center.abs() + rel.abs()),
        n: normal,
        pdf: 1.0 / annulus_area(inner, radius),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use statrs::distribution::{ChiSquared, ContinuousCDF};

    /// A cap's rim seen from 10⁻⁵ outside its sphere (beyond the sphere's band), beside the rim: every ray aimed at
    /// a point of the sphere 10⁻⁸ R inside the rim hits there, and every one aimed 10⁻⁸ R
    /// beyond it passes (into the sphere, to the cap's far side if anywhere). Decided from
    /// the hit's `f32` point, the rim moved to the grid point beside it (up to 3·10⁻⁸ R at
    /// a rim height of R/2), the same way for every ray. Axis-aligned at θmax = 60° and
    /// tilted at 37°, receivers over the cap and over the hole.
    #[test]
    fn cap_rims_admit_no_band_beyond_them() {
        use glam::DVec3;
        for (axis, deg) in [
            (Vec3::Z, 60.0f64),
            (Vec3::new(0.3, -0.5, 0.8).normalize(), 37.0),
        ] {
            let center = Vec3::new(0.25, 0.5, -0.75);
            let t = deg.to_radians();
            let prim = Primitive::SphericalCap {
                center,
                radius: 1.0,
                axis,
                cos_max: t.cos() as f32,
                one_minus_cos: (2.0 * (0.5 * t).sin().powi(2)) as f32,
            };
            let Primitive::SphericalCap { one_minus_cos, .. } = prim else {
                unreachable!()
            };
            // The rim the cap's own parameters put there, in f64.
            let rim = (1.0 - f64::from(one_minus_cos)).acos();
            let a = axis.as_dvec3().normalize();
            let s = a
                .cross(if a.x.abs() < 0.9 { DVec3::X } else { DVec3::Y })
                .normalize();
            let u = a.cross(s);
            let at = |theta: f64, phi: f64, r: f64| {
                center.as_dvec3()
                    + (a * theta.cos() + (s * phi.cos() + u * phi.sin()) * theta.sin()) * r
            };
            for beside in [-1e-6, 1e-6] {
                let o = at(rim + beside, 0.0, 1.0 + 1e-5).as_vec3();
                let mut wrong = Vec::new();
                for k in -8..=8 {
                    let phi = k as f64 * 5e-7;
                    for side in [-1.0, 1.0] {
                        let target = at(rim + side * 1e-8, phi, 1.0);
                        let dist = (target - o.as_dvec3()).length();
                        let d = ((target - o.as_dvec3()) / dist).as_vec3();
                        let there = prim
                            .intersect(o, d, 0.0, f32::INFINITY)
                            .is_some_and(|h| (f64::from(h.t) - dist).abs() < 0.1 * dist);
                        if there != (side < 0.0) {
                            wrong.push(format!("φ {phi:e}, side {side}: hit there {there}"));
                        }
                    }
                }
                assert!(
                    wrong.is_empty(),
                    "θmax {deg}°, receiver {beside:e} beside: {wrong:#?}"
                );
            }
        }
    }

    fn cap(theta_max_deg: f64) -> Primitive {
        let t = theta_max_deg.to_radians();
        Primitive::SphericalCap {
            center: Vec3::new(0.5, -0.2, 1.0),
            radius: 2.0,
            axis: Vec3::new(0.0, 0.6, 0.8),
            cos_max: t.cos() as f32,
            one_minus_cos: (2.0 * (0.5 * t).sin().powi(2)) as f32,
        }
    }

    /// A cap's centre, radius, axis and 1 − cos θmax.
    fn cap_parts(p: Primitive) -> (Vec3, f32, Vec3, f32) {
        let Primitive::SphericalCap {
            center,
            radius,
            axis,
            one_minus_cos,
            ..
        } = p
        else {
            unreachable!()
        };
        (center, radius, axis, one_minus_cos)
    }

    fn annulus() -> Primitive {
        Primitive::Annulus {
            center: Vec3::new(0.0, 0.0, 1.0),
            normal: Vec3::new(0.0, 0.0, -1.0),
            inner: 0.4,
            radius: 1.0,
        }
    }

    #[test]
    fn cap_keeps_only_its_polar_range_and_sees_through_the_port() {
        let c = cap(90.0);
        let Primitive::SphericalCap { center, axis, .. } = c else {
            unreachable!()
        };
        // From the centre: along the axis the wall is hit, against it the port lets go.
        let h = c.intersect(center, axis, 0.0, f32::INFINITY).unwrap();
        assert!((h.t - 2.0).abs() < 1e-5);
        assert!(c.intersect(center, -axis, 0.0, f32::INFINITY).is_none());
        // From outside below the port: the near root (in the port) is clipped, the far
        // wall is found.
        let o = center - axis * 5.0;
        let h = c.intersect(o, axis, 0.0, f32::INFINITY).unwrap();
        assert!((h.t - 7.0).abs() < 1e-4, "{}", h.t);
        // The full sphere (θmax = 180°) is the sphere.
        let full = cap(180.0);
        let h = full.intersect(o, axis, 0.0, f32::INFINITY).unwrap();
        assert!((h.t - 3.0).abs() < 1e-4);
    }

    #[test]
    fn annulus_has_a_hole() {
        let a = annulus();
        assert!(
            a.intersect(Vec3::new(0.2, 0.0, 0.0), Vec3::Z, 0.0, f32::INFINITY)
                .is_none()
        );
        assert!(
            a.intersect(Vec3::new(0.5, 0.0, 0.0), Vec3::Z, 0.0, f32::INFINITY)
                .is_some()
        );
        assert!(
            a.intersect(Vec3::new(1.1, 0.0, 0.0), Vec3::Z, 0.0, f32::INFINITY)
                .is_none()
        );
    }

    /// Every sampled point lies on the shape (a ray aimed at it from outside hits it
    /// there), and the density is uniform by area: a chi-square test of the samples'
    /// cells in (height along the axis or ρ², azimuth), each of equal area.
    fn area_sampling_is_uniform(p: Primitive, coords: impl Fn(Vec3) -> (f64, f64)) {
        let (nx, ny) = (16usize, 16usize);
        let n = 160_000u32;
        let mut counts = vec![0.0f64; nx * ny];
        let mut rng = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            rng ^= rng << 13;
            rng ^= rng >> 7;
            rng ^= rng << 17;
            (rng >> 40) as f32 / (1u64 << 24) as f32
        };
        for _ in 0..n {
            let s = p.sample_area(Vec2::new(next(), next()));
            assert!((s.pdf * p.area() - 1.0).abs() < 1e-5);
            // On the shape: its coordinates in [0, 1], to the f32 rounding of the point
            // (a sample past θmax or inside the inner radius fails here, not in a cell).
            let (a, b) = coords(s.p);
            let slack = 1e-5;
            assert!(
                (-slack..=1.0 + slack).contains(&a) && (0.0..=1.0).contains(&b),
                "{a} {b}"
            );
            let a = a.clamp(0.0, 1.0);
            let (i, j) = (
                ((a * nx as f64) as usize).min(nx - 1),
                ((b * ny as f64) as usize).min(ny - 1),
            );
            counts[i * ny + j] += 1.0;
            // Aimed at from 3 units off along the normal: the ray finds the point.
            let o = s.p + s.n * 3.0;
            let h = p
                .intersect(o, -s.n, 0.0, f32::INFINITY)
                .expect("sample on the shape");
            assert!((h.p - s.p).length() < 1e-4, "{} vs {}", h.p, s.p);
        }
        // Pearson's statistic over equal-area cells (625 expected per cell), judged at
        // α = 1e-6 per shape.
        let e = n as f64 / (nx * ny) as f64;
        let stat: f64 = counts.iter().map(|c| (c - e) * (c - e) / e).sum();
        let p_value = ChiSquared::new((nx * ny - 1) as f64).unwrap().sf(stat);
        assert!(p_value > 1e-6, "chi-square {stat}, p = {p_value}");
    }

    #[test]
    fn cap_area_sampling_is_uniform() {
        for deg in [30.0, 150.0, 180.0] {
            let p = cap(deg);
            let (center, radius, axis, one_minus_cos) = cap_parts(p);
            let f = Frame::from_z(axis);
            area_sampling_is_uniform(p, |q| {
                let r = ((q - center) / radius).as_dvec3();
                let h = (1.0 - r.dot(axis.as_dvec3())) / one_minus_cos as f64;
                let phi = r.dot(f.t.as_dvec3()).atan2(r.dot(f.s.as_dvec3()));
                (
                    h,
                    phi.rem_euclid(std::f64::consts::TAU) / std::f64::consts::TAU,
                )
            });
        }
    }

    #[test]
    fn annulus_area_sampling_is_uniform() {
        let p = annulus();
        area_sampling_is_uniform(p, |q| {
            let r = (q - Vec3::new(0.0, 0.0, 1.0)).as_dvec3();
            let rho2 = r.x * r.x + r.y * r.y;
            (
                (rho2 - 0.16) / (1.0 - 0.16),
                r.y.atan2(r.x).rem_euclid(std::f64::consts::TAU) / std::f64::consts::TAU,
            )
        });
    }
    #[test]
    fn areas_match_their_closed_forms() {
        use std::f64::consts::PI as PI64;
        // Cap of a sphere of radius 2 with 1 − cos θmax = ½ (θmax = 60°): 2π·4·½ = 4π;
        // the whole sphere (1 − cos θmax = 2) is 4πR².
        assert!((cap_area(2.0, 0.5) as f64 - 4.0 * PI64).abs() < 1e-5);
        assert!((cap_area(3.0, 2.0) as f64 - 36.0 * PI64).abs() < 1e-4);
        // Annulus r = 0.4, R = 1: π(1 − 0.16).
        assert!((annulus_area(0.4, 1.0) as f64 - 0.84 * PI64).abs() < 1e-6);
        assert!((annulus_area(0.0, 2.0) as f64 - 4.0 * PI64).abs() < 1e-5);
    }

    /// A sampled point's error bound covers at least the last rounding of each of its
    /// coordinates (½ ulp ≤ ε/2 |p|) and is a few ulps of the operands' size, not more.
    fn error_bounds_are_sound_and_tight(p: Primitive, scale: Vec3) {
        for u1 in [0.05f32, 0.3, 0.55, 0.9] {
            for u2 in [0.1f32, 0.45, 0.8] {
                let s = p.sample_area(Vec2::new(u1, u2));
                for k in 0..3 {
                    assert!(
                        s.p_error[k] >= 0.5 * f32::EPSILON * s.p[k].abs(),
                        "{p:?} {u1} {u2}: axis {k}: {} < ulp of {}",
                        s.p_error[k],
                        s.p[k]
                    );
                    assert!(
                        s.p_error[k] <= 8.0 * f32::EPSILON * scale[k],
                        "{p:?}: axis {k}: {} too loose",
                        s.p_error[k]
                    );
                }
            }
        }
    }

    #[test]
    fn sampled_points_carry_sound_error_bounds() {
        // |centre| + R per axis bounds each operand of p = centre + rel.
        let c = cap(120.0);
        error_bounds_are_sound_and_tight(c, Vec3::new(0.5, 0.2, 1.0) + 2.0);
        let a = annulus();
        error_bounds_are_sound_and_tight(a, Vec3::new(0.0, 0.0, 1.0) + 1.0);
    }

    #[test]
    fn sampled_cap_points_have_their_closed_form() {
        // Hat-box: z = 1 − u₁(1 − cos θmax) along the axis, azimuth 2πu₂ in the axis
        // frame, so the point is centre + R (sin θ cos φ s + sin θ sin φ t + z n).
        let c = cap(100.0);
        let (center, radius, axis, one_minus_cos) = cap_parts(c);
        let f = Frame::from_z(axis);
        for (u1, u2) in [(0.2f64, 0.7f64), (0.9, 0.15), (0.5, 0.5)] {
            let z = 1.0 - u1 * one_minus_cos as f64;
            let st = (1.0 - z * z).sqrt();
            let phi = std::f64::consts::TAU * u2;
            let n = f.s.as_dvec3() * (st * phi.cos())
                + f.t.as_dvec3() * (st * phi.sin())
                + f.n.as_dvec3() * z;
            let want = center.as_dvec3() + n * radius as f64;
            let s = c.sample_area(Vec2::new(u1 as f32, u2 as f32));
            assert!((s.p.as_dvec3() - want).length() < 1e-5, "{} vs {want}", s.p);
            assert!((s.n.as_dvec3() - n).length() < 1e-5);
        }
    }
    #[test]
    fn chords_below_the_rim_miss_and_above_it_hit() {
        // A hemisphere (θmax = 90°): a chord perpendicular to the axis at height z
        // (relative to the centre, along the axis) meets the sphere twice at height z;
        // both hits are on the cap for z > 0, neither for z < 0.
        let c = cap(90.0);
        let (center, _, axis, _) = cap_parts(c);
        let f = Frame::from_z(axis);
        for z in [-0.3f32, -0.05, 0.05, 0.3] {
            let o = center + axis * z - f.s * 5.0;
            let h = c.intersect(o, f.s, 0.0, f32::INFINITY);
            if z > 0.0 {
                let h = h.expect("a chord above the rim hits the cap");
                assert!(((h.p - center).dot(axis) - z).abs() < 1e-5);
            } else {
                assert!(h.is_none(), "z = {z}: {:?}", h.map(|h| h.p));
            }
        }
    }
    #[test]
    fn sampled_annulus_points_have_their_closed_form() {
        // ρ² = r² + u₁(R² − r²), φ = 2πu₂ in the frame about the normal:
        // p = centre + ρ (cos φ s + sin φ t).
        let (center, normal, r, big_r) = (
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.0, 0.0, -1.0),
            0.4,
            1.0,
        );
        let a = annulus();
        let f = Frame::from_z(normal);
        for (u1, u2) in [(0.2f64, 0.7f64), (0.9, 0.15), (0.5, 0.4)] {
            let rho = (r * r + u1 * (big_r * big_r - r * r)).sqrt();
            let phi = std::f64::consts::TAU * u2;
            let want =
                center.as_dvec3() + (f.s.as_dvec3() * phi.cos() + f.t.as_dvec3() * phi.sin()) * rho;
            let s = a.sample_area(Vec2::new(u1 as f32, u2 as f32));
            assert!((s.p.as_dvec3() - want).length() < 1e-6, "{} vs {want}", s.p);
            assert_eq!(s.n, normal);
        }
    }
}
