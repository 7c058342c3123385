//! Configuration (view) factors between diffuse surfaces: the fraction of the power
//! leaving surface 1 (Lambertian) that arrives at surface 2,
//! F₁₂ = (1/A₁) ∫_{A₁}∫_{A₂} cos θ₁ cos θ₂ / (π s²) dA₂ dA₁.
//! A differential element's factor is its irradiance from a unit-radiance emitter / π.

use crate::irradiance::cap_projected_solid_angle;
use std::f64::consts::PI;

/// Differential element to a parallel coaxial disk of radius r at distance h.
///
/// **Formula.** F = r² / (r² + h²).
///
/// **Derivation.** F = (1/π)∫₀^r h²/(h²+ρ²)² 2πρ dρ = r²/(r²+h²).
///
/// **Source.** Howell, *A Catalog of Radiation Heat Transfer Configuration Factors*,
/// section B (plane element to parallel coaxial disk); Siegel & Howell App. C.
pub fn element_to_coaxial_disk(radius: f64, height: f64) -> f64 {
    // 1/(1 + (h/r)²): no r² to overflow (R = h = 10²⁰⁰ gave NaN); (h/r)² = ∞ gives 0.
    let q = height / radius;
    1.0 / (1.0 + q * q)
}

/// Disk of radius r₁ to a parallel coaxial disk of radius r₂ at distance h.
///
/// **Formula.** With R₁ = r₁/h, R₂ = r₂/h, X = 1 + (1 + R₂²)/R₁²:
/// F₁₂ = ½ [X − √(X² − 4 (R₂/R₁)²)], evaluated as 2(R₂/R₁)² / (X + √(X² − 4(R₂/R₁)²))
/// (no cancellation for small or distant disks). Multiplied through by r₁² and with
/// every length divided by m = max(r₁, r₂, h) (a = r₁/m, b = r₂/m, c = h/m ≤ 1):
/// F₁₂ = 2b²/(S + √(S² − 4a²b²)), S = a² + b² + c², and
/// S² − 4a²b² = ((a − b)² + c²)((a + b)² + c²), so the root is
/// hypot(a − b, c)·hypot(a + b, c): X² is never formed (it overflowed at r₁/h = 10⁻⁸⁰,
/// giving 0 for 0.5) and nothing cancels (h = 10⁻¹⁶⁰ gave NaN for ≈ 1).
///
/// **Derivation.** Average over disk 1 of the offset element-to-disk factor
/// ([`crate::irradiance::disk_parallel_offset`]):
/// F₁₂ = (2/r₁²)∫₀^{r₁} F(a) a da, elementary after the substitution u = a².
///
/// **Source.** Howell's catalog, case C-41 (parallel coaxial disks of unequal radii);
/// Siegel & Howell App. C.
pub fn disk_to_coaxial_disk(r1: f64, r2: f64, height: f64) -> f64 {
    let m = r1.max(r2).max(height);
    let (a, b, c) = (r1 / m, r2 / m, height / m);
    let s = a * a + b * b + c * c;
    2.0 * b * b / (s + (a - b).hypot(c) * (a + b).hypot(c))
}

/// Identical, parallel, directly opposed rectangles a × b at separation c.
///
/// **Formula.** With X = a/c, Y = b/c:
/// F₁₂ = 2/(π X Y) { ½ ln[(1+X²)(1+Y²)/(1+X²+Y²)] + X√(1+Y²) atan(X/√(1+Y²))
///        + Y√(1+X²) atan(Y/√(1+X²)) − X atan X − Y atan Y }.
///
/// **Derivation.** Integrate the differential factor to a rectangle (itself from the
/// contour form) over the emitting rectangle; the four-fold integral is elementary.
///
/// **Source.** Howell's catalog, case C-11; Siegel & Howell App. C.
///
/// **Accuracy.** The braces hold O(1) terms that cancel to F·πXY/2 ~ X²Y² (distant
/// plates) or ~X (a strip, X ≪ 1 ≤ Y): about 2 log₁₀(c/min(a, b)) digits are lost, the
/// relative error growing like 10⁻¹⁶ (c/min(a, b))² (a = 10⁻⁹, b = c = 1 gives 0 for
/// 2.5e-10). The catalog refuses c > [`PARALLEL_RECTANGLES_MAX_RATIO`]·min(a, b); the
/// tests check 1e-7 relative at that limit against 60-digit references.
pub fn parallel_rectangles(a: f64, b: f64, c: f64) -> f64 {
    let (x, y) = (a / c, b / c);
    let (x2, y2) = (x * x, y * y);
    let sx = (1.0 + x2).sqrt();
    let sy = (1.0 + y2).sqrt();
    let t = 0.5 * ((1.0 + x2).ln() + (1.0 + y2).ln() - (1.0 + x2 + y2).ln())
        + x * sy * (x / sy).atan()
        + y * sx * (y / sx).atan()
        - x * x.atan()
        - y * y.atan();
    2.0 * t / (PI * x * y)
}

/// The largest separation/min(width, length) the catalog evaluates
/// [`parallel_rectangles`] at (its doc: the error grows like 10⁻¹⁶ times its square).
pub const PARALLEL_RECTANGLES_MAX_RATIO: f64 = 1e4;

/// Perpendicular rectangles sharing an edge of length l: from A₁ = l × w to A₂ = l × h.
///
/// **Formula.** With H = h/l, W = w/l:
/// ```text
/// F₁₂ = 1/(πW) { W atan(1/W) + H atan(1/H) − √(H²+W²) atan(1/√(H²+W²))
///   + ¼ ln( (1+W²)(1+H²)/(1+W²+H²) · [W²(1+W²+H²)/((1+W²)(W²+H²))]^{W²}
///                                 · [H²(1+H²+W²)/((1+H²)(H²+W²))]^{H²} ) },
/// ```
/// the logarithm expanded into a sum of logarithms (no overflow of the powers).
///
/// **Derivation.** Contour-integral (Stokes) reduction of the double area integral; the
/// resulting line integrals along the edges are elementary.
///
/// **Source.** Howell's catalog, case C-14; Siegel & Howell App. C.
pub fn perpendicular_rectangles(l: f64, w: f64, h: f64) -> f64 {
    let (hh, ww) = (h / l, w / l);
    let (h2, w2) = (hh * hh, ww * ww);
    let s = (h2 + w2).sqrt();
    let ln = |v: f64| v.ln();
    let log_term = ln(1.0 + w2) + ln(1.0 + h2) - ln(1.0 + w2 + h2)
        + w2 * (ln(w2) + ln(1.0 + w2 + h2) - ln(1.0 + w2) - ln(w2 + h2))
        + h2 * (ln(h2) + ln(1.0 + h2 + w2) - ln(1.0 + h2) - ln(h2 + w2));
    (ww * (1.0 / ww).atan() + hh * (1.0 / hh).atan() - s * (1.0 / s).atan() + 0.25 * log_term)
        / (PI * ww)
}

/// Differential element to a sphere of radius R whose centre is at distance d, the
/// element's normal pointing at the centre.
///
/// **Formula.** F = (R/d)².
///
/// **Derivation.** The sphere is a cap of sin σ = R/d around the normal; the projected
/// solid angle of a cap centred on the normal is π sin²σ.
///
/// **Source.** Howell's catalog, section B (element to sphere); Siegel & Howell App. C.
pub fn element_to_sphere(distance: f64, radius: f64) -> f64 {
    (radius / distance) * (radius / distance)
}

/// Differential element to a sphere, the element's normal at angle `tilt` (radians) from
/// the direction to the centre, including the partly-below-the-horizon range.
///
/// **Formula.** F = Ω⊥/π with Ω⊥ the horizon-clipped projected solid angle of a cap,
/// [`crate::irradiance::sphere`] (Snyder 1996): F = (R/d)² cos tilt while
/// cos tilt ≥ R/d, zero once cos tilt ≤ −R/d, and the clipped expression between.
///
/// **Source.** Howell's catalog, section B (element to sphere, tilted; element plane
/// intersecting the sphere); Snyder 1996.
pub fn element_to_sphere_tilted(distance: f64, radius: f64, tilt: f64) -> f64 {
    let s = radius / distance;
    cap_projected_solid_angle(tilt.cos(), s * s) / PI
}

/// From any part of a sphere's inner wall to a spherical cap of polar half-angle θ on
/// the same sphere (both facing inwards).
///
/// **Formula.** F = A_cap / (4π R²) = (1 − cos θ)/2 = sin²(θ/2), whatever the emitting
/// part.
///
/// **Derivation.** For two points of a sphere's inner wall at chord s, both polar angles
/// satisfy cos θ₁ = cos θ₂ = s/(2R), so the kernel cos θ₁ cos θ₂/(π s²) = 1/(4π R²) is a
/// constant: every element sees each region in proportion to its area.
///
/// **Source.** Siegel & Howell ch. 6 (the sphere's "area-fraction" view factors);
/// Goebel, Appl. Opt. 6(1), 1967.
pub fn sphere_wall_to_cap(theta: f64) -> f64 {
    let s = (0.5 * theta).sin();
    s * s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Vec3;
    use crate::irradiance::{disk_parallel_offset, polygon_projected_solid_angle, sphere};
    use crate::quadrature::{adaptive, adaptive_2d};

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs().max(1e-300)
    }

    /// Extreme aspect ratios: r₁/h = 10⁻¹⁰⁰ is the element-to-disk limit r₂²/(r₂² + h²);
    /// h/r = 10⁻¹⁰⁰ the touching limit min(1, (r₂/r₁)²); r₁/h = 10¹⁰⁰ with r₂ = h the
    /// reciprocal (r₂/r₁)² F₂₁, F₂₁ → 1. X² overflowed at the first (0 for 0.5) and
    /// cancelled to NaN at h = 10⁻¹⁶⁰.
    #[test]
    fn coaxial_disks_at_extreme_ratios() {
        for (r1, r2, h, want) in [
            (1e-100, 1.0, 1.0, 0.5),
            (1e-80, 1.0, 1.0, 0.5),
            (1e-100, 2.0, 1.0, 0.8),
            (1.0, 1.0, 1e-100, 1.0),
            (1.0, 1.0, 1e-160, 1.0),
            (1.0, 0.5, 1e-100, 0.25),
            (0.5, 1.0, 1e-100, 1.0),
            (1e100, 1.0, 1.0, 1e-200),
            (1e200, 1e200, 1e200, 0.5 * (3.0 - 5f64.sqrt())),
        ] {
            let f = disk_to_coaxial_disk(r1, r2, h);
            assert!(rel(f, want) < 1e-14, "r1 {r1} r2 {r2} h {h}: {f} vs {want}");
        }
        // R = h = 10²⁰⁰ and beyond: 1/2, no overflow.
        assert_eq!(element_to_coaxial_disk(1e200, 1e200), 0.5);
        assert_eq!(element_to_coaxial_disk(1e-200, 1e200), 0.0);
        assert!(rel(element_to_coaxial_disk(3.0, 4.0), 9.0 / 25.0) < 1e-15);
    }

    /// At the catalog's limit c = 10⁴·min(a, b), against Howell's C-11 evaluated with
    /// 60 significant digits (mpmath): a strip, two small squares, distant plates.
    #[test]
    // References printed to 20 significant digits by mpmath; kept verbatim.
    #[allow(clippy::excessive_precision)]
    fn parallel_rectangles_at_the_ratio_limit() {
        for (a, b, c, want) in [
            (1e-4, 1.0, 1.0, 2.499_999_992_423_708_969_2e-5),
            (1e-3, 1e-3, 10.0, 3.183_098_840_617_247_949_4e-9),
            (1.0, 1.0, 1e4, 3.183_098_840_617_247_816_8e-9),
            (0.5, 2.0, 3000.0, 3.536_775_956_438_555_716_5e-8),
        ] {
            assert!(c <= PARALLEL_RECTANGLES_MAX_RATIO * f64::min(a, b));
            let f = parallel_rectangles(a, b, c);
            assert!(rel(f, want) < 1e-7, "{a} × {b} at {c}: {f} vs {want}");
        }
    }

    #[test]
    fn element_to_disk_by_area() {
        for (r, h) in [(1.0, 2.0), (1e-3, 10.0), (10.0, 1e-2)] {
            let q = adaptive(
                |rho| h * h / (h * h + rho * rho).powi(2) * 2.0 * rho,
                0.0,
                r,
                1e-14,
            );
            assert!(rel(element_to_coaxial_disk(r, h), q) < 1e-11);
        }
    }

    #[test]
    fn disk_to_disk_by_averaging_offset_factor() {
        for (r1, r2, h) in [
            (1.0, 1.0, 1.0),
            (0.5, 2.0, 1.0),
            (2.0, 0.1, 3.0),
            (1e-2, 1e-2, 10.0),
        ] {
            let q = 2.0 / (r1 * r1)
                * adaptive(
                    |a| disk_parallel_offset(r2, h, a, 1.0) / PI * a,
                    0.0,
                    r1,
                    1e-13,
                );
            assert!(
                rel(disk_to_coaxial_disk(r1, r2, h), q) < 1e-9,
                "{r1} {r2} {h}"
            );
        }
        // Reciprocity A1 F12 = A2 F21.
        let (r1, r2, h) = (0.5, 2.0, 1.3);
        assert!(
            rel(
                r1 * r1 * disk_to_coaxial_disk(r1, r2, h),
                r2 * r2 * disk_to_coaxial_disk(r2, r1, h)
            ) < 1e-13
        );
    }

    /// Area average over A₁ of Lambert's point-to-polygon factor.
    fn average_over(
        origin: Vec3,
        u: Vec3,
        v: Vec3,
        normal: Vec3,
        target: &[Vec3],
        tol: f64,
    ) -> f64 {
        adaptive_2d(
            |s, t| polygon_projected_solid_angle(origin + u * s + v * t, normal, target) / PI,
            0.0,
            1.0,
            |_| 0.0,
            |_| 1.0,
            tol,
        )
    }

    /// C-11 by quadrature: an a × b rectangle at z = 0 facing +z, the same rectangle
    /// at height c above it.
    fn parallel_by_averaging(a: f64, b: f64, c: f64, tol: f64) -> f64 {
        let target = [
            Vec3::new(0.0, 0.0, c),
            Vec3::new(a, 0.0, c),
            Vec3::new(a, b, c),
            Vec3::new(0.0, b, c),
        ];
        average_over(
            Vec3::default(),
            Vec3::new(a, 0.0, 0.0),
            Vec3::new(0.0, b, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
            &target,
            tol,
        )
    }

    #[test]
    fn parallel_rectangles_by_averaging_lambert() {
        for (a, b, c) in [(1.0, 1.0, 1.0), (2.0, 0.5, 0.3), (1.0, 3.0, 5.0)] {
            let q = parallel_by_averaging(a, b, c, 1e-11);
            assert!(rel(parallel_rectangles(a, b, c), q) < 1e-9, "{a} {b} {c}");
        }
    }

    #[test]
    fn perpendicular_rectangles_by_averaging_lambert() {
        // Common edge along x (length l); A1 in the z = 0 plane spanning y ∈ [0, w];
        // A2 in the y = 0 plane spanning z ∈ [0, h].
        for (l, w, h) in [(1.0, 1.0, 1.0), (2.0, 0.5, 1.5), (0.5, 2.0, 0.2)] {
            let target = [
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(l, 0.0, 0.0),
                Vec3::new(l, 0.0, h),
                Vec3::new(0.0, 0.0, h),
            ];
            let q = average_over(
                Vec3::default(),
                Vec3::new(l, 0.0, 0.0),
                Vec3::new(0.0, w, 0.0),
                Vec3::new(0.0, 0.0, 1.0),
                &target,
                1e-11,
            );
            assert!(
                rel(perpendicular_rectangles(l, w, h), q) < 1e-8,
                "{l} {w} {h}: {q}"
            );
        }
    }

    /// The catalog's near-touching and very distant configurations, each against the
    /// same independent quadratures as above (the cases under
    /// `analytic/cases/view_factor` use exactly these parameters).
    #[test]
    fn catalog_extremes_by_quadrature() {
        // C-11: separations 1e-3 (width 1, length 2) and 100 (width 2, length 1).
        for (a, b, c, tol) in [(1.0, 2.0, 1e-3, 1e-7), (2.0, 1.0, 100.0, 1e-8)] {
            let q = parallel_by_averaging(a, b, c, 1e-10);
            let f = parallel_rectangles(a, b, c);
            assert!(rel(f, q) < tol, "{a} {b} {c}: {f} vs {q}");
        }
        // C-14: a receiver strip 0.01 high on a 2 × 1 emitter's edge, by reciprocity
        // F₁₂ A₁ = F₂₁ A₂ averaged over the strip (the smooth side).
        let (l, w, h) = (2.0, 1.0, 0.01);
        let emitter = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(l, 0.0, 0.0),
            Vec3::new(l, w, 0.0),
            Vec3::new(0.0, w, 0.0),
        ];
        let f21 = average_over(
            Vec3::default(),
            Vec3::new(l, 0.0, 0.0),
            Vec3::new(0.0, 0.0, h),
            Vec3::new(0.0, 1.0, 0.0),
            &emitter,
            1e-10,
        );
        let f12 = perpendicular_rectangles(l, w, h);
        assert!(
            rel(f12 * l * w, f21 * l * h) < 1e-7,
            "{f12} vs {}",
            f21 * h / w
        );
        // C-41: coaxial unit disks 1e-2 and 100 apart.
        for (h, tol) in [(1e-2, 1e-7), (100.0, 1e-9)] {
            let q = 2.0
                * adaptive(
                    |a| disk_parallel_offset(1.0, h, a, 1.0) / PI * a,
                    0.0,
                    1.0,
                    1e-13,
                );
            assert!(rel(disk_to_coaxial_disk(1.0, 1.0, h), q) < tol, "{h}: {q}");
        }
    }

    #[test]
    fn sphere_wall_to_cap_by_quadrature() {
        // From a cap of half-angle 60° about +z to the cap of half-angle 120° about −z:
        // the four-fold integral by averaging, over the emitter, the kernel integrated
        // over the receiver (each by 2-D quadrature in polar coordinates).
        let (t1, t2) = (60f64.to_radians(), 120f64.to_radians());
        let point = |axis: f64, t: f64, p: f64| {
            Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), axis * t.cos())
        };
        let from = |x: Vec3| {
            adaptive_2d(
                |t, p| {
                    let q = point(-1.0, t, p);
                    let d = q - x;
                    let s2 = d.length_squared();
                    let s = s2.sqrt();
                    // Inward normals −x and −q.
                    let c1 = (-x).dot(d) / s;
                    let c2 = q.dot(d) / s;
                    c1 * c2 / (PI * s2) * t.sin()
                },
                0.0,
                t2,
                |_| 0.0,
                |_| 2.0 * PI,
                1e-9,
            )
        };
        // The emitter is rotationally symmetric: average over its polar angle only.
        let area1 = 2.0 * PI * (1.0 - t1.cos());
        let f = adaptive(
            |t| from(point(1.0, t, 0.0)) * 2.0 * PI * t.sin(),
            0.0,
            t1,
            1e-8,
        ) / area1;
        assert!(rel(f, sphere_wall_to_cap(t2)) < 1e-6, "{f}");
    }

    #[test]
    fn element_to_sphere_matches_irradiance_and_quadrature() {
        for (d, r) in [(2.0f64, 1.0f64), (1e3, 1.0), (1.0 + 1e-6, 1.0)] {
            // Facing: independent area quadrature over the visible sphere surface,
            // zones parameterised by distance s: cos θ₁ cos θ₂/(π s²) dA.
            let (s0, s1) = (d - r, ((d - r) * (d + r)).sqrt());
            let q = adaptive(
                |x: f64| {
                    let s = x.exp();
                    // cos θ₁ = (d² + s² − R²)/(2ds), cos θ₂ = (d² − R² − s²)/(2Rs),
                    // dA = 2π R s ds / d (zone area), and ds = s dx.
                    let c1 = (d * d + s * s - r * r) / (2.0 * d * s);
                    let c2 = ((d - r) * (d + r) - s * s) / (2.0 * r * s);
                    c1 * c2 / (PI * s * s) * 2.0 * PI * r * s / d * s
                },
                s0.ln(),
                s1.ln(),
                1e-14,
            );
            assert!(rel(element_to_sphere(d, r), q) < 1e-9, "{d} {r}: {q}");
            for tilt in [0.0f64, 0.7, 1.5, 1.6, 2.0] {
                let n = Vec3::new(tilt.sin(), 0.0, tilt.cos());
                let e = sphere(Vec3::default(), n, Vec3::new(0.0, 0.0, d), r, 1.0) / PI;
                assert!((element_to_sphere_tilted(d, r, tilt) - e).abs() <= 1e-14 * e.max(1e-300));
            }
        }
    }
}
