//! Time-resolved and geometric-probability closed forms.

use crate::radiometry::SPEED_OF_LIGHT;
use std::f64::consts::PI;

/// Part of the irradiance at a receiver on the axis of a uniform disk (radius R, height
/// h, radiance L, facing the disk) carried by light whose travel time lies in [t₁, t₂],
/// propagation speed v (use [`SPEED_OF_LIGHT`] for vacuum).
///
/// Equivalently: the radiant exposure (J·m⁻²) received in [t₁, t₂] from a Dirac pulse
/// emitted by the whole disk at t = 0 with time-integrated radiance L (J·m⁻²·sr⁻¹).
///
/// **Formula.** E = π L h² (1/r₁² − 1/r₂²), rᵢ = clamp(v tᵢ, h, √(h² + R²)).
///
/// **Derivation.** The ring of the disk at path length r has cos θ = h/r and
/// d(cos θ) = −h/r² dr, so E = 2π L ∫ cos θ d(−cos θ) = 2π L h² ∫_{r₁}^{r₂} r⁻³ dr.
/// Clamping to the disk's range of path lengths; r₁ = h, r₂ = √(h²+R²) recovers
/// π L R²/(h²+R²).
///
/// **Source.** Derived here; cf. Jarabo et al., "A framework for transient rendering",
/// SIGGRAPH Asia 2014 (time-resolved radiometry).
///
/// A NaN in any input gives NaN (a NaN radius or height, the clamp's bounds, panicked).
pub fn pulsed_disk_on_axis(
    radius: f64,
    height: f64,
    radiance: f64,
    t1: f64,
    t2: f64,
    speed: f64,
) -> f64 {
    if [radius, height, radiance, t1, t2, speed]
        .iter()
        .any(|x| x.is_nan())
    {
        return f64::NAN;
    }
    let rmax = height.hypot(radius);
    let r1 = (speed * t1).clamp(height, rmax);
    let r2 = (speed * t2).clamp(height, rmax);
    // h²(1/r₁² − 1/r₂²) = (q₁ − q₂)(q₁ + q₂) with q = h/r ≤ 1 and
    // q₁ − q₂ = q₁ (r₂ − r₁)/r₂: no h² or r² to underflow (h = 10⁻²⁰⁰ gave 0/0).
    let (q1, q2) = (height / r1, height / r2);
    PI * radiance * q1 * ((r2 - r1) / r2) * (q1 + q2)
}

/// Vacuum speed of light, re-exported for the pulsed-disk form.
pub const C: f64 = SPEED_OF_LIGHT;

/// Mean chord length of a convex body of volume V and surface area S under isotropic
/// uniform (μ-random) chords.
///
/// **Formula.** ⟨ℓ⟩ = 4V/S (sphere: 4R/3; box a×b×c: 2abc/(ab+bc+ca)).
///
/// **Derivation.** For each direction, mean chord = V/A⊥(ω); weighting directions by
/// A⊥ and using Cauchy's surface-area formula ⟨A⊥⟩ = S/4 gives 4V/S.
///
/// **Source.** A. Cauchy, 1832; Santaló, *Integral Geometry and Geometric Probability*.
pub fn mean_chord_length(volume: f64, surface_area: f64) -> f64 {
    4.0 * volume / surface_area
}

/// Mean chord length of a sphere, 4R/3 (see [`mean_chord_length`]).
pub fn mean_chord_sphere(radius: f64) -> f64 {
    4.0 * radius / 3.0
}

/// Mean chord length of an a × b × c box, 2abc/(ab+bc+ca) (see [`mean_chord_length`]).
pub fn mean_chord_box(a: f64, b: f64, c: f64) -> f64 {
    mean_chord_length(a * b * c, 2.0 * (a * b + b * c + c * a))
}

/// Time-averaged irradiance over the shutter interval [t₀, t₁] from an isotropic point
/// light of intensity I moving at speed v along a line at closest distance d from the
/// receiver, the receiver's normal pointing at the closest point; t = 0 at closest
/// approach.
///
/// **Formula.** E(t) = I d/(d² + v²t²)^{3/2}, and
/// Ē = I/(d (t₁ − t₀)) [t₁/√(d²+v²t₁²) − t₀/√(d²+v²t₀²)],
/// evaluated as Ē = I d (t₁ + t₀)/(s₀ s₁ (t₁ s₀ + t₀ s₁)) (sᵢ = √(d²+v²tᵢ²)) when t₀ t₁ > 0,
/// which avoids cancellation for short shutters; Ē = I/d² when t₀ = t₁ = 0 or v = 0.
///
/// **Derivation.** cos θ = d/r, r² = d² + v²t², E = I cos θ/r²; d/dt [t/√(d²+v²t²)] =
/// d²/(d²+v²t²)^{3/2}.
///
/// **Source.** Derived here (inverse-square cosine law, pbrt 4th ed. §4.1.3).
pub fn moving_point_light_average(
    intensity: f64,
    distance: f64,
    speed: f64,
    t0: f64,
    t1: f64,
) -> f64 {
    let d = distance;
    let s0 = d.hypot(speed * t0);
    let s1 = d.hypot(speed * t1);
    if t1 == t0 {
        return intensity * d / (s0 * s0 * s0);
    }
    if t0 * t1 > 0.0 {
        intensity * d * (t1 + t0) / (s0 * s1 * (t1 * s0 + t0 * s1))
    } else {
        intensity / (d * (t1 - t0)) * (t1 / s1 - t0 / s0)
    }
}

/// Time-averaged irradiance over the shutter [t₀, t₁] from a uniform spherical emitter
/// (radius R, radiance L) whose centre moves as (x₀ + v t, 0, h) above a receiver at the
/// origin facing +z (h > R).
///
/// **Formula.** Ē = (1/(t₁ − t₀)) ∫ E_sphere(t) dt, with E_sphere the closed-form
/// irradiance of a sphere ([`crate::irradiance::sphere`]: L times the projected solid
/// angle of its cap, horizon-clipped), integrated over time by adaptive bisection of a
/// 12-point Gauss–Legendre rule ([`crate::quadrature::adaptive`]; E is smooth in t).
///
/// **Source.** Derived here from the static sphere irradiance (Snyder 1996; pbrt 4th ed.
/// §12.2) and the definition of a shutter average.
///
/// A NaN in any input gives NaN ([`crate::irradiance::sphere`]).
pub fn moving_sphere_light_average(
    radius: f64,
    radiance: f64,
    height: f64,
    x0: f64,
    speed: f64,
    t0: f64,
    t1: f64,
) -> f64 {
    use crate::geom::Vec3;
    let e = |t: f64| {
        crate::irradiance::sphere(
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(x0 + speed * t, 0.0, height),
            radius,
            radiance,
        )
    };
    if t1 <= t0 {
        return e(t0);
    }
    crate::quadrature::adaptive(e, t0, t1, 1e-12) / (t1 - t0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::assert_nan_in_each;
    use crate::quadrature::{adaptive, adaptive_2d};

    /// A NaN in any input gives NaN, with light in the time bin and without: a NaN
    /// radius or height (the clamp's bounds) panicked in the pulsed disk, and the moving
    /// sphere's irradiance took a NaN radius, height, start or speed for 0, over a shutter
    /// and at an instant (t₁ = t₀).
    #[test]
    fn nan_inputs_give_nan() {
        let bases: [&[f64]; 3] = [
            &[1.0, 2.0, 1.0, 0.0, 1e-8, C],
            &[1.0, 2.0, 1.0, 1.0, 2.0, C],
            &[1.0, 2.0, 1.0, 0.0, 1e-10, C],
        ];
        assert_nan_in_each("pulsed disk", &bases, |x| {
            pulsed_disk_on_axis(x[0], x[1], x[2], x[3], x[4], x[5])
        });
        let bases: [&[f64]; 2] = [
            &[1.0, 1.0, 3.0, 0.0, 1.0, -1.0, 1.0],
            &[1.0, 1.0, 3.0, 0.0, 1.0, 1.0, 1.0],
        ];
        assert_nan_in_each("moving sphere", &bases, |x| {
            moving_sphere_light_average(x[0], x[1], x[2], x[3], x[4], x[5], x[6])
        });
    }

    #[test]
    fn moving_sphere_average_by_midpoint_rule() {
        let (r, l, h, x0, v) = (0.3, 2.0, 1.5, -1.0, 2.0);
        let n = 20000;
        let mid: f64 = (0..n)
            .map(|i| {
                let t = (i as f64 + 0.5) / n as f64;
                crate::irradiance::sphere(
                    crate::geom::Vec3::new(0.0, 0.0, 0.0),
                    crate::geom::Vec3::new(0.0, 0.0, 1.0),
                    crate::geom::Vec3::new(x0 + v * t, 0.0, h),
                    r,
                    l,
                )
            })
            .sum::<f64>()
            / n as f64;
        assert!(rel(moving_sphere_light_average(r, l, h, x0, v, 0.0, 1.0), mid) < 1e-7);
        // A sphere at rest is its static irradiance.
        let still = moving_sphere_light_average(r, l, h, 0.0, 0.0, 0.0, 1.0);
        assert!(rel(still, PI * l * (r / h) * (r / h)) < 1e-12);
    }

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs().max(1e-300)
    }

    #[test]
    fn pulsed_disk_by_area_quadrature() {
        let (r, h, l, v) = (1.0f64, 2.0f64, 1.5, 3.0);
        // Integrate the irradiance kernel over the annulus of the disk whose path length
        // lies in [v t1, v t2]: ρ ∈ [√(r1² − h²), √(r2² − h²)].
        for (t1, t2) in [(0.0, 10.0), (0.7, 0.72), (0.68, 0.7), (0.5, 0.7)] {
            let clamp = |t: f64| (v * t).clamp(h, h.hypot(r));
            let (rho1, rho2) = (
                (clamp(t1).powi(2) - h * h).max(0.0).sqrt(),
                (clamp(t2).powi(2) - h * h).max(0.0).sqrt(),
            );
            let q = adaptive(
                |rho| l * h * h / (h * h + rho * rho).powi(2) * 2.0 * PI * rho,
                rho1,
                rho2,
                1e-14,
            );
            let got = pulsed_disk_on_axis(r, h, l, t1, t2, v);
            assert!(
                (got - q).abs() <= 1e-11 * q.max(1e-300),
                "{t1} {t2}: {got} vs {q}"
            );
        }
        let full = pulsed_disk_on_axis(r, h, l, 0.0, 1e9, v);
        assert!(rel(full, crate::irradiance::disk_on_axis(r, h, l)) < 1e-14);
    }

    #[test]
    fn mean_chords_by_quadrature() {
        // Sphere: chords at impact parameter b over the disk of radius R.
        let r = 1.7;
        let q = adaptive(
            |b| 2.0 * (r * r - b * b).sqrt() * 2.0 * PI * b,
            0.0,
            r,
            1e-14,
        ) / (PI * r * r);
        assert!(rel(mean_chord_sphere(r), q) < 1e-10);
        // Box: 4πV / ∫ A⊥(ω) dω, A⊥ = bc|ωx| + ca|ωy| + ab|ωz|.
        let (a, b, c) = (1.0, 2.0, 0.5);
        let proj = adaptive_2d(
            |t, p| {
                let (st, ct) = t.sin_cos();
                let (sp, cp) = p.sin_cos();
                (b * c * (st * cp).abs() + c * a * (st * sp).abs() + a * b * ct.abs()) * st
            },
            0.0,
            PI,
            |_| 0.0,
            |_| 2.0 * PI,
            1e-12,
        );
        assert!(rel(mean_chord_box(a, b, c), 4.0 * PI * a * b * c / proj) < 1e-9);
    }

    #[test]
    fn moving_light_by_quadrature() {
        let (i, d, v) = (3.0, 0.5, 2.0);
        for (t0, t1) in [
            (-1.0, 2.0),
            (0.3, 0.3 + 1e-6),
            (1.0, 5.0),
            (-3.0, -2.0),
            (0.0, 0.0),
        ] {
            let got = moving_point_light_average(i, d, v, t0, t1);
            let want = if t1 == t0 {
                i / (d * d)
            } else {
                adaptive(
                    |t: f64| i * d / (d * d + v * v * t * t).powf(1.5),
                    t0,
                    t1,
                    1e-14,
                ) / (t1 - t0)
            };
            assert!(rel(got, want) < 1e-10, "{t0} {t1}: {got} vs {want}");
        }
    }
}
