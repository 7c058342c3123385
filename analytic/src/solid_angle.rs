//! Solid angles subtended at a point (steradians).
//!
//! Every function takes absolute positions and subtracts first, so geometry far from the
//! origin stays as accurate as its input coordinates.

use crate::geom::{Vec3, any_nan};
use std::f64::consts::PI;

/// Solid angle of a spherical cap (a cone of directions) of half-angle `half_angle` ∈ [0, π].
///
/// **Formula.** Ω = 2π (1 − cos α) = 4π sin²(α/2).
///
/// **Derivation.** Ω = ∫₀^{2π} ∫₀^α sin θ dθ dφ = 2π (1 − cos α); the half-angle identity
/// 1 − cos α = 2 sin²(α/2) avoids cancellation for small caps.
///
/// **Source.** Any radiometry text, e.g. Siegel & Howell, *Thermal Radiation Heat Transfer*,
/// ch. 1 (solid angle); pbrt 4th ed. §3.8.2 (`UniformConePDF`).
pub fn cap(half_angle: f64) -> f64 {
    let s = (0.5 * half_angle).sin();
    4.0 * PI * s * s
}

/// Solid angle of a sphere of radius `radius` whose centre is at distance `distance`
/// (> radius) from the observer. Returns 4π when the observer is inside or on the sphere.
///
/// **Formula.** Ω = 2π (1 − cos α), sin α = R/d, computed as
/// Ω = 2π (R/d)² / (1 + cos α) with cos α = √((d−R)(d+R)) / d (no cancellation for
/// tiny or nearly-hemispherical spheres).
///
/// **Derivation.** The silhouette of a sphere seen from outside is a circle; the tangent
/// rays form a cone of half-angle α with sin α = R/d, so the sphere subtends the cap of
/// [`cap`].
///
/// **Source.** Siegel & Howell, *Thermal Radiation Heat Transfer*; pbrt 4th ed. §6.2.4
/// (sphere sampling by the subtended cone).
pub fn sphere(distance: f64, radius: f64) -> f64 {
    if distance <= radius {
        return 4.0 * PI;
    }
    // cos α = √((1 − s)(1 + s)), s = R/d = sin α: no d² to overflow (a centre 10²⁰⁰ away
    // with R = 10¹⁹⁹ gave 0 for 0.0315).
    let s = radius / distance;
    let cos_a = ((1.0 - s) * (1.0 + s)).sqrt();
    2.0 * PI * s * s / (1.0 + cos_a)
}

/// [`sphere`] from positions: observer `p`, sphere `center`, `radius`.
pub fn sphere_from_point(p: Vec3, center: Vec3, radius: f64) -> f64 {
    sphere((center - p).length(), radius)
}

/// Signed solid angle of the triangle `a, b, c` seen from `p`.
///
/// Positive when `p` lies on the side opposite the right-hand normal (b−a)×(c−a)
/// (i.e. `p` sees the back of the triangle), negative otherwise; its magnitude is the
/// solid angle, in [0, 2π].
///
/// **Formula** (Van Oosterom & Strackee 1983). With r₁ = a−p, r₂ = b−p, r₃ = c−p and
/// rᵢ = |rᵢ|:
/// tan(Ω/2) = r₁·(r₂×r₃) / (r₁r₂r₃ + (r₁·r₂)r₃ + (r₁·r₃)r₂ + (r₂·r₃)r₁),
/// evaluated as Ω = 2 atan2(numerator, denominator), which is correct in every quadrant
/// (Ω up to 2π as `p` approaches the triangle's interior).
///
/// **Derivation.** Oosterom & Strackee apply the spherical excess (l'Huilier) to the
/// spherical triangle cut by the three rays and simplify with vector identities.
///
/// **Source.** A. van Oosterom, J. Strackee, "The solid angle of a plane triangle",
/// IEEE Trans. Biomed. Eng. BME-30(2):125–126, 1983.
pub fn triangle_signed(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> f64 {
    let (r1, r2, r3) = (a - p, b - p, c - p);
    let (l1, l2, l3) = (r1.length(), r2.length(), r3.length());
    let num = r1.dot(r2.cross(r3));
    let den = l1 * l2 * l3 + r1.dot(r2) * l3 + r1.dot(r3) * l2 + r2.dot(r3) * l1;
    2.0 * num.atan2(den)
}

/// Unsigned solid angle of the triangle `a, b, c` seen from `p` (see [`triangle_signed`]).
pub fn triangle(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> f64 {
    triangle_signed(p, a, b, c).abs()
}

/// Solid angle of a planar simple polygon (convex or not) seen from `p`.
///
/// **Formula.** Ω = |Σₖ Ω_signed(p; v₀, vₖ, vₖ₊₁)|, the fan of triangles from v₀
/// summed with the signs of [`triangle_signed`].
///
/// **Derivation.** For a planar polygon every fan triangle lies in the same plane, so the
/// signed solid angles of overlapping (oppositely wound) fan triangles cancel exactly
/// where a non-convex polygon folds back; the sum is the signed solid angle of the
/// polygon (the same inclusion–exclusion as the shoelace area formula).
///
/// **Source.** Van Oosterom & Strackee 1983 (per triangle).
///
/// A NaN in `p` or a vertex gives NaN, also for fewer than 3 vertices (otherwise 0).
pub fn polygon(p: Vec3, vertices: &[Vec3]) -> f64 {
    if any_nan(&[p], &[]) || any_nan(vertices, &[]) {
        return f64::NAN;
    }
    if vertices.len() < 3 {
        return 0.0;
    }
    let v0 = vertices[0];
    vertices[1..]
        .windows(2)
        .map(|w| triangle_signed(p, v0, w[0], w[1]))
        .sum::<f64>()
        .abs()
}

/// Solid angle of the rectangle with one corner at `corner` and perpendicular edges
/// `edge_u`, `edge_v`, seen from `p`.
///
/// **Formula.** In the rectangle's frame, `p` projects to (pₓ, p_y) at height d; with
/// x₀ = −pₓ, x₁ = |u| − pₓ, y₀ = −p_y, y₁ = |v| − p_y,
/// Ω = G(x₁,y₁) − G(x₀,y₁) − G(x₁,y₀) + G(x₀,y₀),
/// G(x, y) = atan2(x y, |d| √(x² + y² + d²)).
///
/// **Derivation.** G(x, y) is the solid angle of the rectangle \[0, x\] × \[0, y\] seen from a
/// point at height d above its corner (integrate d/(x²+y²+d²)^{3/2} over the rectangle,
/// first in y then in x). G is odd in x and in y, so inclusion–exclusion of four corner
/// rectangles covers any placement of the foot of `p`, inside or outside the rectangle.
///
/// **Source.** The corner-rectangle decomposition is the configuration-factor algebra of
/// J. R. Howell, *A Catalog of Radiation Heat Transfer Configuration Factors*; the corner
/// solid angle itself is e.g. R. J. Mathar, "Solid angle of a rectangular plate", 2015.
///
/// A NaN in any input gives NaN (a NaN edge does not normalise, which returned the
/// degenerate rectangle's 0).
pub fn rectangle(p: Vec3, corner: Vec3, edge_u: Vec3, edge_v: Vec3) -> f64 {
    if any_nan(&[p, corner, edge_u, edge_v], &[]) {
        return f64::NAN;
    }
    let (a, b) = (edge_u.length(), edge_v.length());
    let (Some(u), Some(v)) = (edge_u.normalized(), edge_v.normalized()) else {
        return 0.0;
    };
    let n = u.cross(v);
    let w = p - corner;
    let (px, py, d) = (w.dot(u), w.dot(v), w.dot(n).abs());
    let g = |x: f64, y: f64| (x * y).atan2(d * (x * x + y * y + d * d).sqrt());
    let (x0, x1, y0, y1) = (-px, a - px, -py, b - py);
    (g(x1, y1) - g(x0, y1) - g(x1, y0) + g(x0, y0)).abs()
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::geom::{assert_nan_in_each, vec_at};
    use crate::quadrature::{adaptive, adaptive_2d};

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs().max(1e-300)
    }

    #[test]
    fn cap_matches_quadrature() {
        for alpha in [1e-4, 0.3, 1.0, PI / 2.0, 3.0, PI] {
            let q = 2.0 * PI * adaptive(f64::sin, 0.0, alpha, 1e-14);
            assert!(rel(cap(alpha), q) < 1e-12, "alpha={alpha}");
        }
    }

    /// Ω = ∫ over the visible sphere surface of cos θ' / s² dA (independent of the cone).
    /// Zones of the surface are parameterised by their distance s to the observer
    /// (s dr-substitution: sin β dβ = s ds /(dR)), giving π (d²−R²−s²)/(d s²) ds, and
    /// then s = eˣ so the near-surface peak is resolved.
    fn sphere_by_surface(d: f64, r: f64) -> f64 {
        let (s0, s1) = (d - r, ((d - r) * (d + r)).sqrt());
        adaptive(
            |x: f64| {
                let s = x.exp();
                PI * ((d - r) * (d + r) - s * s) / (d * s)
            },
            s0.ln(),
            s1.ln(),
            1e-14,
        )
    }

    #[test]
    fn sphere_matches_surface_quadrature() {
        // From ~1e-6 sr to nearly a hemisphere.
        for (d, r) in [(1.0e3, 0.5), (10.0, 1.0), (2.0, 1.0), (1.0 + 1e-6, 1.0)] {
            let q = sphere_by_surface(d, r);
            assert!(
                rel(sphere(d, r), q) < 1e-9,
                "d={d} r={r}: {} vs {q}",
                sphere(d, r)
            );
        }
        assert!(rel(sphere(2.0e6, 1.0), PI / 4.0e12) < 1e-9);
        assert_eq!(sphere(0.5, 1.0), 4.0 * PI);
    }

    /// Ω = ∫_T |n·(x−p)| / |x−p|³ dA over the triangle, in barycentric coordinates.
    pub(crate) fn triangle_by_area(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> f64 {
        triangle_integral_by_area(p, a, b, c, |_| 1.0)
    }

    /// ∫_T w(ω) dω for the directions ω = (x − p)/|x − p| of the triangle's points x,
    /// as the area integral ∫_T w(ω) |n·(x−p)| / |x−p|³ dA in barycentric coordinates
    /// (adaptive, relative tolerance 1e-12). Irradiance takes w(ω) = max(0, n_r·ω).
    pub(crate) fn triangle_integral_by_area(
        p: Vec3,
        a: Vec3,
        b: Vec3,
        c: Vec3,
        w: impl Fn(Vec3) -> f64,
    ) -> f64 {
        let (e1, e2) = (b - a, c - a);
        let nn = e1.cross(e2);
        let area2 = nn.length();
        let n = nn * (1.0 / area2);
        let o = a - p;
        adaptive_2d(
            |s, t| {
                let x = o + e1 * s + e2 * t;
                let r2 = x.length_squared();
                let r = r2.sqrt();
                w(x * (1.0 / r)) * n.dot(x).abs() / (r2 * r)
            },
            0.0,
            1.0,
            |_| 0.0,
            |s| 1.0 - s,
            1e-12,
        ) * area2
    }

    #[test]
    fn triangle_matches_area_quadrature() {
        let o = Vec3::new(0.0, 0.0, 0.0);
        let cases = [
            // ordinary
            (
                o,
                Vec3::new(0.2, -0.3, 1.0),
                Vec3::new(1.0, 0.1, 1.2),
                Vec3::new(-0.3, 0.9, 0.8),
            ),
            // sliver (aspect ~1e4)
            (
                o,
                Vec3::new(-1.0, 0.0, 1.0),
                Vec3::new(1.0, 0.0, 1.0),
                Vec3::new(0.0, 2e-4, 1.0),
            ),
            // tiny, far: ~1e-6 sr
            (
                o,
                Vec3::new(1e3, 0.0, 0.0),
                Vec3::new(1e3, 1.0, 0.0),
                Vec3::new(1e3, 0.0, 1.0),
            ),
            // close to the plane, large solid angle (~2π·0.9)
            (
                Vec3::new(0.1, 0.1, 0.05),
                Vec3::new(-3.0, -3.0, 0.0),
                Vec3::new(3.0, -3.0, 0.0),
                Vec3::new(0.0, 3.0, 0.0),
            ),
        ];
        for (p, a, b, c) in cases {
            let q = triangle_by_area(p, a, b, c);
            let got = triangle(p, a, b, c);
            assert!(rel(got, q) < 1e-9, "{got} vs {q}");
            // orientation flips the sign only
            assert!((triangle_signed(p, a, b, c) + triangle_signed(p, a, c, b)).abs() < 1e-15);
        }
    }

    #[test]
    fn triangle_far_from_origin() {
        let off = Vec3::new(1e5, -1e5, 1e5);
        let (p, a, b, c) = (
            Vec3::new(0.1, 0.2, -0.4),
            Vec3::new(0.2, -0.3, 1.0),
            Vec3::new(1.0, 0.1, 1.2),
            Vec3::new(-0.3, 0.9, 0.8),
        );
        let (pf, af, bf, cf) = (p + off, a + off, b + off, c + off);
        // The reference uses the exactly-representable local differences.
        let q = triangle_by_area(Vec3::default(), af - pf, bf - pf, cf - pf);
        assert!(rel(triangle(pf, af, bf, cf), q) < 1e-9);
        assert!(rel(triangle(pf, af, bf, cf), triangle(p, a, b, c)) < 1e-9);
    }

    #[test]
    fn rectangle_agrees_with_triangles_and_quadrature() {
        let cases = [
            (Vec3::new(0.3, 0.4, 1.0), Vec3::new(0.0, 0.0, 0.0)),
            (Vec3::new(5.0, -2.0, 0.3), Vec3::new(0.0, 0.0, 0.0)),
            (
                Vec3::new(1e5 + 0.5, 1e5 + 0.5, 1e5 + 1e-3),
                Vec3::new(1e5, 1e5, 1e5),
            ),
        ];
        for (p, corner) in cases {
            let (u, v) = (Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0));
            let r = rectangle(p, corner, u, v);
            let quad = [corner, corner + u, corner + u + v, corner + v];
            let t = polygon(p, &quad);
            let q = triangle_by_area(p, quad[0], quad[1], quad[2])
                + triangle_by_area(p, quad[0], quad[2], quad[3]);
            assert!(rel(r, t) < 1e-10, "{r} vs {t}");
            assert!(rel(r, q) < 1e-8, "{r} vs {q}");
        }
        // A tilted rectangle.
        let (u, v) = (Vec3::new(1.0, 1.0, 0.0), Vec3::new(-0.5, 0.5, 2.0));
        let (p, c) = (Vec3::new(0.0, 3.0, 0.5), Vec3::new(0.2, 0.1, -0.3));
        let quad = [c, c + u, c + u + v, c + v];
        assert!(rel(rectangle(p, c, u, v), polygon(p, &quad)) < 1e-12);
    }

    /// A NaN in any input (each vector component in turn) gives NaN: a polygon of fewer
    /// than 3 vertices returned 0, and so did a rectangle with a NaN edge (which does not
    /// normalise: taken as degenerate), or a degenerate one with a NaN point or corner.
    #[test]
    fn polygon_and_rectangle_propagate_nan() {
        let bases: [&[f64]; 3] = [
            &[
                0., 0., 0., -1., -1., 1., 1., -1., 1., 1., 1., 1., -1., 1., 1.,
            ],
            &[0., 0., 0., -1., -1., 1., 1., -1., 1.],
            &[0., 0., 0., -1., -1., 1.],
        ];
        assert_nan_in_each("polygon", &bases, |x| {
            let vertices: Vec<Vec3> = (3..x.len()).step_by(3).map(|i| vec_at(x, i)).collect();
            polygon(vec_at(x, 0), &vertices)
        });
        // Above the rectangle, in its plane, and a degenerate one (a zero edge).
        let bases: [&[f64]; 3] = [
            &[0., 0., 1., -1., -1., 0., 2., 0., 0., 0., 2., 0.],
            &[0., 0., 0., -1., -1., 0., 2., 0., 0., 0., 2., 0.],
            &[0., 0., 1., -1., -1., 0., 0., 0., 0., 0., 2., 0.],
        ];
        assert_nan_in_each("rectangle", &bases, |x| {
            rectangle(vec_at(x, 0), vec_at(x, 3), vec_at(x, 6), vec_at(x, 9))
        });
    }

    #[test]
    fn nonconvex_polygon() {
        // An L-shape = unit square at the corner removed from a 2×2 square.
        let z = 0.7;
        let l = [
            Vec3::new(0.0, 0.0, z),
            Vec3::new(2.0, 0.0, z),
            Vec3::new(2.0, 1.0, z),
            Vec3::new(1.0, 1.0, z),
            Vec3::new(1.0, 2.0, z),
            Vec3::new(0.0, 2.0, z),
        ];
        let p = Vec3::new(0.4, 1.3, 0.0);
        let big = rectangle(
            p,
            Vec3::new(0.0, 0.0, z),
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
        );
        let hole = rectangle(
            p,
            Vec3::new(1.0, 1.0, z),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        );
        assert!(rel(polygon(p, &l), big - hole) < 1e-12);
    }
}
