//! Shapes: analytic spheres, parallelograms ("rectangles"), disks, and triangles.
//!
//! Each primitive intersects rays in `f32` and reports a conservative bound on the
//! floating-point error of the hit point, so spawned rays can be offset past it
//! (pbrt-v4 §6.8). The sphere uses the numerically robust quadratic of Haines et al.
//! ("Precision Improvements for Ray/Sphere Intersection", Ray Tracing Gems 2019,
//! ch. 7) relative to its centre; triangles use the watertight test of Woop, Benthin &
//! Wald (JCGT 2(1), 2013), so no ray slips between two triangles sharing an edge (obvhs's
//! own triangle test is not watertight, see the shared notes ../shared/STACK.md, outside
//! this repository).

use crate::math::{Frame, gamma, unit_vector};
use crate::sampling::disk::concentric_disk;
use crate::sampling::sphere::uniform_sphere;
use crate::sampling::triangle::sample_triangle;
use glam::{DVec3, Vec2, Vec3};

/// One intersectable primitive.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Primitive {
    /// A sphere.
    Sphere {
        /// Centre.
        center: Vec3,
        /// Radius.
        radius: f32,
    },
    /// The parallelogram `corner + a·u + b·v`, a, b ∈ [0, 1]; normal ∝ u × v.
    Rectangle {
        /// A corner.
        corner: Vec3,
        /// First edge.
        u: Vec3,
        /// Second edge.
        v: Vec3,
    },
    /// A disk of `radius` about `center` facing `normal`.
    Disk {
        /// Centre.
        center: Vec3,
        /// Unit normal.
        normal: Vec3,
        /// Radius.
        radius: f32,
    },
    /// A triangle; normal ∝ (p₁ − p₀) × (p₂ − p₀).
    Triangle {
        /// Vertices.
        p: [Vec3; 3],
    },
    /// The part of a sphere within polar angle θmax of `axis` ([`super::partial`]).
    SphericalCap {
        /// Centre.
        center: Vec3,
        /// Radius.
        radius: f32,
        /// Unit axis (the cap's pole is centre + radius · axis).
        axis: Vec3,
        /// cos θmax (−1: the whole sphere).
        cos_max: f32,
        /// 1 − cos θmax, computed without cancellation.
        one_minus_cos: f32,
    },
    /// A disk of `radius` with a hole of radius `inner` ([`super::partial`]).
    Annulus {
        /// Centre.
        center: Vec3,
        /// Unit normal.
        normal: Vec3,
        /// Inner radius (> 0, < radius).
        inner: f32,
        /// Outer radius.
        radius: f32,
    },
}

/// A ray–primitive hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance along the (unit) ray direction.
    pub t: f32,
    /// The hit point.
    pub p: Vec3,
    /// Conservative absolute error bound of `p`, per axis, as a distance from the surface
    /// (what ray offsetting projects on the normal, pbrt-v4 §6.8). A point re-projected
    /// onto the surface (spheres, rectangles, disks) also carries, along the surface, the
    /// ray's own rounding (~u(|o| + t)), which this does not bound.
    pub p_error: Vec3,
    /// Geometric normal (outward for spheres; before any flip).
    pub n: Vec3,
}

/// A point sampled on a primitive by area.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AreaSample {
    /// The point.
    pub p: Vec3,
    /// Its error bound.
    pub p_error: Vec3,
    /// The normal there.
    pub n: Vec3,
    /// Density per unit area (1/A).
    pub pdf: f32,
}

impl Primitive {
    /// Surface area.
    pub fn area(&self) -> f32 {
        match *self {
            Primitive::Sphere { radius, .. } => 4.0 * std::f32::consts::PI * radius * radius,
            // |u × v|, in f64 where its f32 square leaves the normal range (sides below
            // ~3·10⁻¹⁰ or above ~4·10⁹): the f32 square underflowed to 0 for 10⁻¹⁵ × 10⁻¹⁵
            // (area 10⁻³⁰, which the loader then called degenerate) and overflowed to ∞
            // for 10¹⁸ × 10¹⁸ (area 10³⁶, called too large).
            Primitive::Rectangle { u, v, .. } => {
                let a2 = u.cross(v).length_squared();
                if (f32::MIN_POSITIVE..f32::INFINITY).contains(&a2) {
                    a2.sqrt()
                } else {
                    u.as_dvec3().cross(v.as_dvec3()).length() as f32
                }
            }
            Primitive::Disk { radius, .. } => std::f32::consts::PI * radius * radius,
            // In f64: the f32 cross product of a sliver triangle's edges loses ~5e-4 of its area.
            Primitive::Triangle { p } => {
                (0.5 * (p[1].as_dvec3() - p[0].as_dvec3())
                    .cross(p[2].as_dvec3() - p[0].as_dvec3())
                    .length()) as f32
            }
            Primitive::SphericalCap {
                radius,
                one_minus_cos,
                ..
            } => super::partial::cap_area(radius, one_minus_cos),
            Primitive::Annulus { inner, radius, .. } => super::partial::annulus_area(inner, radius),
        }
    }

    /// Axis-aligned bounds (padded by the error of their own arithmetic).
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let (lo, hi) = match *self {
            Primitive::Sphere { center, radius }
            | Primitive::SphericalCap { center, radius, .. } => {
                (center - Vec3::splat(radius), center + Vec3::splat(radius))
            }
            Primitive::Rectangle { corner, u, v } => {
                let pts = [corner, corner + u, corner + v, corner + u + v];
                (
                    pts.iter().fold(Vec3::INFINITY, |a, &b| a.min(b)),
                    pts.iter().fold(Vec3::NEG_INFINITY, |a, &b| a.max(b)),
                )
            }
            Primitive::Disk {
                center,
                normal,
                radius,
            }
            | Primitive::Annulus {
                center,
                normal,
                radius,
                ..
            } => {
                // Extent of a disk along axis i: r·√(1 − nᵢ²) = r·√(n_j² + n_k²) for a unit
                // normal, formed from the other two components (1 − nᵢ² cancels: a normal
                // 10⁻⁴ from an axis rounds nᵢ² to 1, and the disk, which tilts by r·10⁻⁴
                // along that axis, got no extent there and was missed through a BVH), at
                // most r, widened by γ₅ r for the normal's own rounding (|n| = 1 ± ε).
                let n2 = normal * normal;
                let e = Vec3::from(
                    [n2.y + n2.z, n2.z + n2.x, n2.x + n2.y].map(|s| s.sqrt().min(1.0) * radius),
                ) + Vec3::splat(gamma(5) * radius);
                (center - e, center + e)
            }
            Primitive::Triangle { p } => (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2])),
        };
        // Every axis by the largest coordinate: an f32 test's decision mixes the axes (a
        // rectangle about one ulp of its y coordinate across was culled where its test
        // reported a hit 5·10⁻¹¹ beyond the x bound that padding by |x| alone gave).
        let pad = Vec3::splat(lo.abs().max(hi.abs()).max_element() * gamma(3) + f32::MIN_POSITIVE);
        (lo - pad, hi + pad)
    }

    /// Whether the primitive is flat (cannot see itself).
    pub fn is_planar(&self) -> bool {
        !matches!(
            self,
            Primitive::Sphere { .. } | Primitive::SphericalCap { .. }
        )
    }

    /// The primitive's kind in words, for messages.
    pub fn kind_name(&self) -> &'static str {
        match self {
            Primitive::Sphere { .. } => "sphere",
            Primitive::Rectangle { .. } => "rectangle",
            Primitive::Disk { .. } => "disk",
            Primitive::Triangle { .. } => "triangle",
            Primitive::SphericalCap { .. } => "spherical cap",
            Primitive::Annulus { .. } => "annulus",
        }
    }

    /// Closest hit with t in (tmin, tmax), for a unit direction `d`.
    pub fn intersect(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32) -> Option<Hit> {
        match *self {
            Primitive::Sphere { center, radius } => {
                intersect_sphere(center, radius, o, d, tmin, tmax)
            }
            Primitive::Rectangle { corner, u, v } => {
                intersect_rectangle(corner, u, v, o, d, tmin, tmax)
            }
            Primitive::Disk {
                center,
                normal,
                radius,
            } => intersect_ring(center, normal, 0.0, radius, o, d, tmin, tmax),
            Primitive::Triangle { p } => intersect_triangle(p, &Ray::new(o, d), tmin, tmax),
            Primitive::SphericalCap {
                center,
                radius,
                axis,
                cos_max,
                one_minus_cos,
            } => super::partial::intersect_cap(
                center,
                radius,
                axis,
                (cos_max, one_minus_cos),
                o,
                d,
                tmin,
                tmax,
            ),
            Primitive::Annulus {
                center,
                normal,
                inner,
                radius,
            } => intersect_ring(center, normal, inner, radius, o, d, tmin, tmax),
        }
    }

    /// A point uniformly distributed by area.
    pub fn sample_area(&self, u: Vec2) -> AreaSample {
        let pdf = 1.0 / self.area();
        match *self {
            Primitive::Sphere { center, radius } => {
                let n = uniform_sphere(u);
                let p = center + n * radius;
                AreaSample {
                    p,
                    p_error: gamma(5) * (center.abs() + (n * radius).abs()),
                    n,
                    pdf,
                }
            }
            Primitive::Rectangle {
                corner,
                u: eu,
                v: ev,
            } => {
                let p = corner + eu * u.x + ev * u.y;
                let p_error = gamma(6) * (corner.abs() + (eu * u.x).abs() + (ev * u.y).abs());
                AreaSample {
                    p,
                    p_error,
                    n: unit_vector(eu.cross(ev)),
                    pdf,
                }
            }
            Primitive::Disk {
                center,
                normal,
                radius,
            } => {
                let d = concentric_disk(u) * radius;
                let f = Frame::from_z(normal);
                let rel = f.s * d.x + f.t * d.y;
                AreaSample {
                    p: center + rel,
                    p_error: gamma(6) * (center.abs() + rel.abs()),
                    n: normal,
                    pdf,
                }
            }
            Primitive::Triangle { p } => {
                let q = sample_triangle(p, u);
                let p_error = gamma(6) * (p[0].abs() + p[1].abs() + p[2].abs());
                AreaSample {
                    p: q,
                    p_error,
                    n: unit_vector((p[1] - p[0]).cross(p[2] - p[0])),
                    pdf,
                }
            }
            Primitive::SphericalCap {
                center,
                radius,
                axis,
                one_minus_cos,
                ..
            } => super::partial::sample_cap(center, radius, axis, one_minus_cos, u),
            Primitive::Annulus {
                center,
                normal,
                inner,
                radius,
            } => super::partial::sample_annulus(center, normal, inner, radius, u),
        }
    }
}

/// The coordinates (a, b) of a point `rel` = a·u + b·v of a rectangle's plane (relative
/// to its corner) in its (possibly skewed) edge basis, a = (rel × v)·n / |n|² and
/// b = (u × rel)·n / |n|² with n = u × v, if both lie in [0, 1].
///
/// Decided in `f64`, where the products of `f32` inputs are exact and the sums round at
/// 2⁻⁵³: in `f32` the quotient near 1 rounds down to 1 from up to 2⁻²⁴ above it (ulp(1)
/// is 2⁻²³ above 1 and 2⁻²⁴ below), so the two far edges (a = 1, b = 1; the two through
/// the corner sit at 0, where `f32` resolves far finer) let hits up to 2⁻²⁴|u| beyond the
/// rectangle through, and `f32`'s rounding of n = u × v scales a and b by up to as much.
/// That band is systematic, not noise: a receiver 2·10⁻⁶ from a far edge of a 2 × 2 light
/// read BSDF sampling 5.9% and MIS 3% high, 0.7% at 1.7·10⁻⁵ (session 52's audit;
/// `far_edges_admit_no_band_beyond_them`).
fn edge_coordinates(rel: DVec3, u: DVec3, v: DVec3, n: DVec3) -> Option<(f32, f32)> {
    let nn = n.length_squared();
    let (a, b) = (rel.cross(v).dot(n), u.cross(rel).dot(n));
    ((0.0..=nn).contains(&a) && (0.0..=nn).contains(&b)).then(|| ((a / nn) as f32, (b / nn) as f32))
}

/// Closest hit on a disk (`inner` = 0) or annulus of unit `normal`: the ray's point on
/// its plane, projected into the plane (rel), is kept where r² ≤ |rel|² ≤ R².
///
/// The point ([`plane_hit`]) and the two comparisons are in `f64`. In `f32` the point
/// fell on `f32`'s grid and the sum of squares rounded to R² from up to half an ulp above
/// it: an outward band of a few 10⁻⁸ R all along the rim (and an inward one at the
/// hole's), through which a receiver 2·10⁻⁶ from a unit disk's rim read every estimator
/// 3% high, an annulus's inner rim 1.5% (session 52's audit;
/// `rims_admit_no_band_beyond_them`). The comparisons alone in `f64` turned +3% into
/// −1.4%: the grid point at the rim was then refused with the part of its cell inside.
#[allow(clippy::too_many_arguments)]
fn intersect_ring(
    center: Vec3,
    normal: Vec3,
    inner: f32,
    radius: f32,
    o: Vec3,
    d: Vec3,
    tmin: f32,
    tmax: f32,
) -> Option<Hit> {
    let n = normal.as_dvec3();
    let (t, rel) = plane_hit(center, n, o, d, tmin, tmax)?;
    // Into the plane: rel is off it by f64's rounding (10⁻¹⁷ of a unit disk), which in a
    // coordinate the plane holds at 0 is beyond γ₆ |rel| of that coordinate
    // (`ring_hits_bound_their_point`).
    let rel = rel - n * rel.dot(n);
    let rr = rel.length_squared();
    let (r, big_r) = (f64::from(inner), f64::from(radius));
    if !(rr >= r * r && rr <= big_r * big_r) {
        return None;
    }
    let rel = rel.as_vec3();
    Some(Hit {
        t,
        p: center + rel,
        p_error: gamma(6) * (center.abs() + rel.abs()),
        n: normal,
    })
}

/// Where the ray o + t d meets the plane through `origin` with normal `n` (any length),
/// for t in (tmin, tmax): t, and the point relative to `origin`, o − origin + t d.
///
/// Formed in `f64` from the `f32` inputs (their differences and products exact or nearly
/// so): the point's error is then a few 2⁻⁵³ of its distances, where `f32`'s o + t d
/// falls on `f32`'s grid, 2⁻²⁴ of the coordinates' size. A boundary test on that grid
/// moves the boundary to the grid point beside it, the same way for every ray from a
/// receiver beside it (`rims_admit_no_band_beyond_them`).
fn plane_hit(
    origin: Vec3,
    n: DVec3,
    o: Vec3,
    d: Vec3,
    tmin: f32,
    tmax: f32,
) -> Option<(f32, DVec3)> {
    let (c, o, d) = (origin.as_dvec3(), o.as_dvec3(), d.as_dvec3());
    let denom = d.dot(n);
    if denom == 0.0 || !denom.is_finite() {
        return None;
    }
    let t = (c - o).dot(n) / denom;
    let t32 = t as f32;
    if !(t32 > tmin && t32 < tmax) {
        return None;
    }
    Some((t32, o - c + d * t))
}

/// The nearer of a sphere's two ordered roots t0 ≤ t1 inside the open segment
/// (tmin, tmax), else the farther one, else none.
#[inline]
fn nearest_root_within(t0: f32, t1: f32, tmin: f32, tmax: f32) -> Option<f32> {
    if t0 > tmin && t0 < tmax {
        Some(t0)
    } else if t1 > tmin && t1 < tmax {
        Some(t1)
    } else {
        None
    }
}

/// Robust ray–sphere intersection (Haines et al. 2019): with f = o − c and b = −f·d,
/// the discriminant r² − |f + b d|² avoids the cancellation of b² − (|f|² − r²).
fn intersect_sphere(
    center: Vec3,
    radius: f32,
    o: Vec3,
    d: Vec3,
    tmin: f32,
    tmax: f32,
) -> Option<Hit> {
    let f = o - center;
    let (ff, rr) = (f.length_squared(), radius * radius);
    if !(rr >= f32::MIN_POSITIVE && ff < f32::INFINITY) {
        return intersect_sphere_wide(center, radius, o, d, tmin, tmax);
    }
    let b = -f.dot(d);
    let l = f + d * b;
    let disc = rr - l.length_squared();
    let c = ff - rr;
    // A grazing ray's discriminant is noise: r² − |l|² is a difference of two values near
    // r² with an error of order γ r² (for an origin within a few r of the centre), so its
    // square root, half the chord, is off by up to ~√γ r ≈ 10⁻³ r. A nearly tangent ray
    // from an origin inside a sphere of radius 10⁸ read disc < 0 and missed the sphere it
    // starts in (b = −f·d = −0.47 exactly and +0.625 in `f32`), and chords a few 10⁻⁴ r
    // long came out up to 54% long. Below GRAZING r² (half-chords below ~0.022 r, a few
    // hits in 10⁴) the `f64` roots decide, where that error falls below ~10⁻³ of the chord
    // (`nearly_tangent_rays_on_huge_spheres_take_the_exact_far_root`,
    // `grazing_chords_are_exact_to_a_thousandth`).
    if disc.abs() < GRAZING * rr {
        return intersect_sphere_near_surface(center, radius, o, d, f, tmin, tmax);
    }
    if disc < 0.0 {
        return None;
    }
    let q = b + disc.sqrt().copysign(b);
    // The roots are c/q (the one near 0 when the origin is near the surface) and q. The
    // sign of c = |o − centre|² − r² (outside or inside) is known only beyond its error
    // bound: γ₂|f|² from the rounding of f = o − centre, γ₃ from the sum of squares, half
    // an ulp of r² and of the difference (γ₆ on the computed |f|² covers the first two,
    // γ₂ on r² and |c| the last two and the rounding of the bound itself).
    // Within it (~8u r², an origin within ~4u r ≈ 2.4·10⁻⁷ r of the surface, wherever the
    // sphere lies) the origin is on the surface as far as `f32` can tell, and the root
    // near 0 is noise: from a floor 10⁻⁸ … 2.5·10⁻¹⁰ below a sphere light of radius 0.5
    // the computed c was ≤ 0, and every BSDF-sampled ray went on to the sphere's far side
    // (BSDF sampling read 0, MIS 0.20, for 0.5). There the `f64` roots decide
    // ([`intersect_sphere_near_surface`]), and so they do where the root near 0 is met
    // from a little farther ([`near_root_inexact`]); every other hit (grazing ones aside,
    // above) keeps its bits.
    if within_sphere_band(ff, rr, c) {
        return intersect_sphere_near_surface(center, radius, o, d, f, tmin, tmax);
    }
    let (mut t0, mut t1) = (c / q, q);
    if q == 0.0 {
        t0 = 0.0;
        t1 = 0.0;
    }
    let near = t0;
    if t0 > t1 {
        std::mem::swap(&mut t0, &mut t1);
    }
    let t = nearest_root_within(t0, t1, tmin, tmax)?;
    if t == near && near_root_inexact(ff, c) {
        return intersect_sphere_near_surface(center, radius, o, d, f, tmin, tmax);
    }
    sphere_hit(center, radius, o, d, f, t, tmin, tmax)
}

/// The discriminant, as a fraction of r², below which [`intersect_sphere`] takes the `f64`
/// roots: 2⁻¹¹, about 1000 times the `f32` discriminant's own error bound of some
/// γ₄ · 2r² for an origin near the sphere.
const GRAZING: f32 = 1.0 / 2048.0;

/// Whether c = |f|² − r², computed in `f32` from |f|² and r², lies within its error
/// bound ([`intersect_sphere`]): γ₆|f|² + γ₂(r² + |c|).
#[inline]
fn within_sphere_band(ff: f32, rr: f32, c: f32) -> bool {
    c.abs() <= gamma(6) * ff + gamma(2) * (rr + c.abs())
}

/// Whether the root near 0, c/q, where the ray meets it (ahead of the origin: outside
/// and approaching, or inside and leaving), is to come from the `f64` roots: c below
/// [`NEAR_ROOT`] |f|² (an origin within about 3% of r of the surface). That root inherits
/// c's relative error, up to (γ₆|f|² + γ₂(r² + |c|))/|c| beyond the band
/// ([`within_sphere_band`]), the same for every ray from one origin: from 3.8·10⁻⁶ r
/// outside a 60° cap beside its rim, every near root was ~1% long, and the rim decided
/// on it admitted a sliver a few 10⁻⁹ r beyond the rim (+0.12% of the irradiance there,
/// for every estimator). The `f64` roots are exact to the `f32` rounding of t; farther out,
/// c/q keeps within about 43u of it (`roots_ahead_of_near_origins_are_exact`). The far
/// root q (what an origin on a sphere's inside meets: a furnace's bounces) is not
/// affected, and pays one comparison.
#[inline]
fn near_root_inexact(ff: f32, c: f32) -> bool {
    c.abs() < NEAR_ROOT * ff
}

/// The fraction of |f|² below which [`near_root_inexact`] sends a root near 0 to the
/// `f64` roots: 2⁻⁴, where c's relative error bound is about 16(γ₆ + γ₂) ≈ 128u.
const NEAR_ROOT: f32 = 1.0 / 16.0;

/// The hit at distance `t` along the ray of [`intersect_sphere`] (f = o − centre in
/// `f32`), re-projected onto the surface.
#[inline]
#[allow(clippy::too_many_arguments)]
fn sphere_hit(
    center: Vec3,
    radius: f32,
    o: Vec3,
    d: Vec3,
    f: Vec3,
    t: f32,
    tmin: f32,
    tmax: f32,
) -> Option<Hit> {
    // Re-project the hit onto the surface (pbrt-v4 §6.8.5): error γ₅ |p − c| about c.
    let rel = f + d * t;
    let scale = radius / rel.length();
    // A sphere below the rounding of f + d t (radius 10⁻¹⁵ at 10⁵ from the origin, where
    // f32 steps by 0.0078) can leave rel = 0, and r/|rel| = ∞ made the point NaN: the
    // f64 form keeps the direction (`tiny_spheres_far_out_hit_at_a_finite_point`).
    if !scale.is_finite() {
        return intersect_sphere_wide(center, radius, o, d, tmin, tmax);
    }
    let rel = rel * scale;
    let n = rel / radius;
    let p = center + rel;
    let p_error = gamma(5) * rel.abs() + gamma(1) * center.abs();
    Some(Hit { t, p, p_error, n })
}

/// [`intersect_sphere`] for an origin within the error bound of c = |o − centre|² − r²
/// of the surface, where the sign of the `f32` root c/q near 0 is not known, for that
/// root ahead of an origin near the surface, where it carries c's relative error
/// ([`near_root_inexact`]), and for a grazing ray from anywhere ([`GRAZING`]), whose `f32`
/// discriminant is noise: the roots in `f64`, where f = o − centre and its square are
/// exact to ~10⁻¹⁶ r². The root near 0 is c/q, in front of the origin where c and q
/// agree in sign (outside and approaching, or inside and leaving); it is dropped where
/// |c| is within its own `f64` bound (an origin on the surface to ~10⁻¹⁶ r: it cannot be
/// told from a point of the sphere, which does not see itself). A ray spawned from the sphere's own
/// point is offset past that point's error bound, ≥ γ₅r ≈ 3·10⁻⁷ r, to the side it leaves
/// ([`crate::math::offset_ray_origin`]), so its `f64` c has the sign of that side and
/// its root near 0 lies behind it. The other root, q, is the `f64` one too: for a ray
/// nearly tangent to the sphere the `f32` b = −f·d and r² − |f + b d|² are rounding
/// noise (a multiple of ulp(r²)): of 59 983 such rays on spheres of radius 3·10⁷ and 10⁸,
/// 376 missed the sphere they started inside (a negative discriminant) and 10 686 met it
/// more than 10⁻⁶ off the exact distance, up to 35.7 times too far
/// (`nearly_tangent_rays_on_huge_spheres_take_the_exact_far_root`). (pbrt-v4 drops
/// every root whose interval reaches 0, the root near 0 from any origin this close
/// included.)
#[cold]
#[allow(clippy::too_many_arguments)]
fn intersect_sphere_near_surface(
    center: Vec3,
    radius: f32,
    o: Vec3,
    d: Vec3,
    f: Vec3,
    tmin: f32,
    tmax: f32,
) -> Option<Hit> {
    let fw = o.as_dvec3() - center.as_dvec3();
    let dw = d.as_dvec3();
    let (ff, rr) = (fw.length_squared(), f64::from(radius) * f64::from(radius));
    // |f|² to γ₅ (f's own rounding and the sum), r² exact, and the difference.
    let c = ff - rr;
    let b = -fw.dot(dw);
    let a = dw.length_squared();
    let disc = b * b - a * c;
    if !(disc >= 0.0) {
        return None;
    }
    let qw = b + disc.sqrt().copysign(b);
    let g = |n: f64| n * f64::EPSILON * 0.5 / (1.0 - n * f64::EPSILON * 0.5);
    let near = if c.abs() > g(7.0) * (ff + rr) {
        Some((c / qw) as f32)
    } else {
        None
    };
    let far = (qw / a) as f32;
    let within = |t: &f32| *t > tmin && *t < tmax;
    let t = match (near.filter(within), Some(far).filter(within)) {
        (Some(t0), Some(t1)) => t0.min(t1),
        (t0, t1) => t0.or(t1)?,
    };
    sphere_hit(center, radius, o, d, f, t, tmin, tmax)
}

/// [`intersect_sphere`] where its f32 squares leave the normal range: a radius below
/// ~1.1·10⁻¹⁹ (r² underflows, and so does the squared distance of a ray passing a few
/// radii off the centre: 0 − 0 read as a grazing hit, whose point came out NaN), a radius
/// or offset above ~1.8·10¹⁹ (r² or |o − c|² overflows). The same formulas (pbrt-v4
/// §6.8.4: the discriminant from the perpendicular offset l = f + (−f·d) d, the
/// numerically stable roots q and c/q) in f64, whose squares of f32 values never leave
/// its normal range; the point is re-projected in f64 and rounded once more, within
/// γ₁|p| of the f64 point, and the f32 error terms (γ₅|p − c| + γ₁|c|) cover it.
#[cold]
fn intersect_sphere_wide(
    center: Vec3,
    radius: f32,
    o: Vec3,
    d: Vec3,
    tmin: f32,
    tmax: f32,
) -> Option<Hit> {
    let (c, r, d64) = (center.as_dvec3(), radius as f64, d.as_dvec3());
    let f = o.as_dvec3() - c;
    let b = -f.dot(d64);
    let l = f + d64 * b;
    let disc = r * r - l.length_squared();
    if !(disc >= 0.0) {
        return None;
    }
    let cc = f.length_squared() - r * r;
    let q = b + disc.sqrt().copysign(b);
    let (t0, t1) = if q == 0.0 { (0.0, 0.0) } else { (cc / q, q) };
    let (t0d, t1d) = (t0.min(t1), t0.max(t1));
    let (t0, t1) = (t0d as f32, t1d as f32);
    let t = nearest_root_within(t0, t1, tmin, tmax)?;
    // The point from the unrounded root: the f32 one can land on the centre of a sphere
    // smaller than its rounding (t = 0.015625 for radius 10⁻¹⁵, once a NaN point) or on
    // the wrong part of it (a ray down at x = 0.3 r onto r = 10⁻²⁰ from 1 away met it at
    // t = 1 in f32, the point (r, 0, 0) with normal +x instead of (0.3, 0, 0.95)).
    // Formed as l ∓ d √disc (the roots are b ∓ √disc, and l = f + d b is the ray's
    // closest approach), since b ∓ √disc itself rounds √disc away when the sphere is
    // small against the distance (1 ± 10⁻²⁰ is 1 in f64).
    let sq = disc.sqrt() * if t == t0 { -1.0 } else { 1.0 };
    let rel = l + d64 * sq;
    let len = rel.length();
    if !(len > 0.0 && len.is_finite()) {
        return None;
    }
    let n = rel / len;
    let rel = (n * r).as_vec3();
    let p = (c + n * r).as_vec3();
    // (Plus the spacing of subnormals, which a relative bound does not cover.)
    let p_error = gamma(5) * rel.abs() + gamma(2) * center.abs() + Vec3::splat(f32::from_bits(1));
    Some(Hit {
        t,
        p,
        p_error,
        n: n.as_vec3(),
    })
}

/// A ray with what the watertight triangle test derives from the ray alone (Woop, Benthin
/// & Wald 2013, §3): the axis permutation that makes z the dominant direction component
/// and the shear that maps the direction onto +z. [`Primitive::intersect_ray`] reads it,
/// so a query that tests many triangles (a BVH traversal) computes it once per ray
/// instead of once per triangle; the arithmetic per triangle is unchanged.
#[derive(Clone, Copy, Debug)]
pub struct Ray {
    /// Origin.
    pub o: Vec3,
    /// Unit direction.
    pub d: Vec3,
    /// The permutation (kx, ky, kz): kz the axis of the largest |dᵢ|, then cyclically.
    k: [usize; 3],
    /// The shear (sx, sy, sz) = (−d_kx/d_kz, −d_ky/d_kz, 1/d_kz).
    shear: [f32; 3],
}

impl Ray {
    /// The ray from `o` along the unit direction `d`.
    #[inline]
    pub fn new(o: Vec3, d: Vec3) -> Self {
        let kz = d.abs().max_position();
        let kx = (kz + 1) % 3;
        let ky = (kx + 1) % 3;
        let (dx, dy, dz) = (d[kx], d[ky], d[kz]);
        Ray {
            o,
            d,
            k: [kx, ky, kz],
            shear: [-dx / dz, -dy / dz, 1.0 / dz],
        }
    }
}

impl Primitive {
    /// Whether [`Primitive::intersect_ray`] reads the [`Ray`]'s prepared permutation and
    /// shear (a triangle's watertight test); every other primitive's test takes the origin
    /// and direction as they are, so a query over such primitives need not prepare it.
    #[inline]
    pub fn reads_prepared_ray(&self) -> bool {
        match self {
            Primitive::Triangle { .. } => true,
            Primitive::Sphere { .. }
            | Primitive::Rectangle { .. }
            | Primitive::Disk { .. }
            | Primitive::SphericalCap { .. }
            | Primitive::Annulus { .. } => false,
        }
    }

    /// [`Primitive::intersect`] for a prepared [`Ray`]: the same result, bit for bit.
    #[inline]
    pub fn intersect_ray(&self, ray: &Ray, tmin: f32, tmax: f32) -> Option<Hit> {
        match *self {
            Primitive::Triangle { p } => intersect_triangle(p, ray, tmin, tmax),
            Primitive::Sphere { .. }
            | Primitive::Rectangle { .. }
            | Primitive::Disk { .. }
            | Primitive::SphericalCap { .. }
            | Primitive::Annulus { .. } => self.intersect(ray.o, ray.d, tmin, tmax),
        }
    }

    /// [`Primitive::intersect_ray`] compiled for x86-64-v3 CPUs
    /// ([`crate::scene::accel::Isa::X86_64V3`]): the same source, so the same IEEE
    /// operations in the same order and the same bits; the triangle test's fused
    /// multiply-adds (`f32::mul_add`, correctly rounded either way) become instructions
    /// instead of calls into the runtime library. Other shapes take the baseline code.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma,bmi1,bmi2,lzcnt,popcnt")]
    pub(crate) fn intersect_ray_fma(&self, ray: &Ray, tmin: f32, tmax: f32) -> Option<Hit> {
        if let Primitive::Triangle { p } = *self {
            triangle_hit(p, ray, tmin, tmax)
        } else {
            self.intersect_ray(ray, tmin, tmax)
        }
    }
}

/// Watertight ray–triangle intersection (Woop, Benthin & Wald 2013; pbrt-v4 §6.5.3), the
/// ray's permutation and shear prepared in [`Ray`]. The vertices are held as three
/// columns (their x, y and z coordinates after translation and permutation), so each
/// step treats the three vertices at once; every operation on each coordinate is the one
/// pbrt-v4 performs.
fn intersect_triangle(p: [Vec3; 3], ray: &Ray, tmin: f32, tmax: f32) -> Option<Hit> {
    triangle_hit(p, ray, tmin, tmax)
}

/// [`intersect_triangle`]'s body, inlined into each instruction set's instance of it
/// ([`Primitive::intersect_ray_fma`]).
#[inline(always)]
fn triangle_hit(p: [Vec3; 3], ray: &Ray, tmin: f32, tmax: f32) -> Option<Hit> {
    let [kx, ky, kz] = ray.k;
    let [sx, sy, sz] = ray.shear;
    let o = ray.o.to_array();
    let column = |k: usize| {
        Vec3::new(p[0].to_array()[k], p[1].to_array()[k], p[2].to_array()[k]) - Vec3::splat(o[k])
    };
    // Translate to the ray origin, permute, shear x and y.
    let z = column(kz);
    let x = column(kx) + sx * z;
    let y = column(ky) + sy * z;
    // Every product below (edge functions ~m², the scaled distance and its error bound
    // ~m³) stays finite and normal for coordinates m within 2^±40 of the ray origin;
    // beyond, the same test in f64.
    let max_xt = x.abs().max_element();
    let max_yt = y.abs().max_element();
    let m = max_xt.max(max_yt).max(z.abs().max_element());
    if !(m > TRIANGLE_LO && m < TRIANGLE_HI) {
        return intersect_triangle_wide(p, ray, tmin, tmax);
    }
    // Edge functions e_i = x_j·y_k − y_j·x_k for (i, j, k) cyclic.
    let (xj, xk) = (Vec3::new(x.y, x.z, x.x), Vec3::new(x.z, x.x, x.y));
    let (yj, yk) = (Vec3::new(y.y, y.z, y.x), Vec3::new(y.z, y.x, y.y));
    let mut e = Vec3::new(
        crate::math::difference_of_products(xj.x, yk.x, yj.x, xk.x),
        crate::math::difference_of_products(xj.y, yk.y, yj.y, xk.y),
        crate::math::difference_of_products(xj.z, yk.z, yj.z, xk.z),
    );
    if e.x == 0.0 || e.y == 0.0 || e.z == 0.0 {
        // Fall back to f64 on exact zeros (edge hits), as pbrt-v4 does.
        let (xj, yk, yj, xk) = (xj.as_dvec3(), yk.as_dvec3(), yj.as_dvec3(), xk.as_dvec3());
        e = (xj * yk - yj * xk).as_vec3();
    }
    if (e.x < 0.0 || e.y < 0.0 || e.z < 0.0) && (e.x > 0.0 || e.y > 0.0 || e.z > 0.0) {
        return None;
    }
    let det = e.x + e.y + e.z;
    if det == 0.0 {
        return None;
    }
    let z = z * sz;
    let t_scaled = e.x * z.x + e.y * z.y + e.z * z.z;
    if (det < 0.0 && t_scaled <= tmax * det) || (det > 0.0 && t_scaled >= tmax * det) {
        return None;
    }
    let before_tmin = if det < 0.0 {
        t_scaled >= tmin * det
    } else {
        t_scaled <= tmin * det
    };
    let n = (p[1] - p[0]).cross(p[2] - p[0]);
    if n == Vec3::ZERO {
        return None;
    }
    let inv_det = 1.0 / det;
    let (b0, b1, b2) = (e.x * inv_det, e.y * inv_det, e.z * inv_det);
    let mut t = t_scaled * inv_det;
    // The error bound δ of t (pbrt-v4 §6.8.7): a hit is kept only where t > δ, provably
    // in front of the origin.
    let max_zt = z.abs().max_element();
    let delta_z = gamma(3) * max_zt;
    let delta_x = gamma(5) * (max_xt + max_zt);
    let delta_y = gamma(5) * (max_yt + max_zt);
    let delta_e = 2.0 * (gamma(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
    let max_e = e.abs().max_element();
    let delta_t =
        3.0 * (gamma(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * inv_det.abs();
    if before_tmin || t <= delta_t {
        // δ grows with the triangle's extent along the ray, not with the distance to it:
        // from 10⁻⁶ above a triangle 2 across, two thirds of the rays that meet it have
        // |t| ≤ δ, and pbrt-v4 drops them all (a receiver that close read 45% low, and a
        // ray from a surface touching a mesh slipped through it). Where the sign of t is
        // not known in `f32` (and `tmin` is below δ, so it does not decide), the `f64`
        // distance does; the edge signs stay the watertight `f32` ones.
        if !(t.abs() <= delta_t && tmin < delta_t) {
            return None;
        }
        t = triangle_distance_wide(&triangle_frame_wide(p, ray))? as f32;
        if !(t > tmin && t < tmax) {
            return None;
        }
    }
    let q = p[0] * b0 + p[1] * b1 + p[2] * b2;
    let p_error = gamma(7) * ((p[0] * b0).abs() + (p[1] * b1).abs() + (p[2] * b2).abs());
    Some(Hit {
        t,
        p: q,
        p_error,
        n: unit_vector(n),
    })
}

/// Where [`intersect_triangle`]'s `f32` products would leave the normal range: ray-relative
/// coordinates up to 2^±40.
const TRIANGLE_LO: f32 = 1.0 / (1u64 << 40) as f32;
/// See [`TRIANGLE_LO`].
const TRIANGLE_HI: f32 = (1u64 << 40) as f32;

/// [`intersect_triangle`] for coordinates beyond 2^±40 of the ray origin (a triangle
/// 10¹⁴ across, whose edge functions' products overflowed into a NaN distance, or one
/// 10⁻¹⁵ across, whose normal's square underflowed to 0 and was never hit): the same
/// watertight test (translate, permute, shear, edge functions, signs, scaled distance) in
/// `f64`, where products of three `f32` values neither overflow nor underflow. The edge
/// functions of a shared edge are formed from the same two vertices in the same way, so
/// the test stays watertight; the point is rounded once from `f64`, within the `f32`
/// bound γ₇ Σ|bᵢ vᵢ| that also covers the fast path's.
#[cold]
fn intersect_triangle_wide(p: [Vec3; 3], ray: &Ray, tmin: f32, tmax: f32) -> Option<Hit> {
    let frame = triangle_frame_wide(p, ray);
    let e = frame.edges;
    if !((e.x >= 0.0 && e.y >= 0.0 && e.z >= 0.0) || (e.x <= 0.0 && e.y <= 0.0 && e.z <= 0.0)) {
        return None;
    }
    let t = triangle_distance_wide(&frame)? as f32;
    let b = e / (e.x + e.y + e.z);
    if !(t > tmin && t < tmax) {
        return None;
    }
    let pd = p.map(|v| v.as_dvec3());
    let point = (pd[0] * b.x + pd[1] * b.y + pd[2] * b.z).as_vec3();
    let (b0, b1, b2) = (b.x as f32, b.y as f32, b.z as f32);
    let p_error = gamma(7) * ((p[0] * b0).abs() + (p[1] * b1).abs() + (p[2] * b2).abs());
    let n = (pd[1] - pd[0]).cross(pd[2] - pd[0]).normalize().as_vec3();
    n.is_finite().then_some(Hit {
        t,
        p: point,
        p_error,
        n,
    })
}

/// A triangle in the ray's frame, in `f64`: the vertices translated to the ray origin,
/// permuted and sheared so that the ray runs along +z (`q`), and the edge functions
/// eᵢ = q_j.x q_k.y − q_j.y q_k.x for (i, j, k) cyclic.
struct WideFrame {
    q: [glam::DVec3; 3],
    edges: glam::DVec3,
}

/// [`WideFrame`] of the triangle `p` for `ray`.
#[cold]
fn triangle_frame_wide(p: [Vec3; 3], ray: &Ray) -> WideFrame {
    let [kx, ky, kz] = ray.k;
    let o = ray.o.as_dvec3();
    let d = ray.d.as_dvec3();
    let (sx, sy, sz) = (-d[kx] / d[kz], -d[ky] / d[kz], 1.0 / d[kz]);
    let q = p.map(|v| {
        let r = v.as_dvec3() - o;
        glam::DVec3::new(r[kx] + sx * r[kz], r[ky] + sy * r[kz], r[kz] * sz)
    });
    let edges = glam::DVec3::new(
        q[1].x * q[2].y - q[1].y * q[2].x,
        q[2].x * q[0].y - q[2].y * q[0].x,
        q[0].x * q[1].y - q[0].y * q[1].x,
    );
    WideFrame { q, edges }
}

/// The distance t = Σ bᵢ zᵢ along the ray to the triangle's plane (bᵢ = eᵢ/Σe, which
/// may be of either sign: t is the plane's distance wherever the line meets it), where
/// it is positive beyond the error of its computation: the `f32` test's bound
/// (pbrt-v4 §6.8.7) with `f64`'s γₙ. `None` for a line in the plane or a distance not
/// provably positive.
fn triangle_distance_wide(f: &WideFrame) -> Option<f64> {
    let (q, e) = (&f.q, f.edges);
    let det = e.x + e.y + e.z;
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let b = e / det;
    let t = b.x * q[0].z + b.y * q[1].z + b.z * q[2].z;
    let g = |n: f64| n * f64::EPSILON * 0.5 / (1.0 - n * f64::EPSILON * 0.5);
    let max = |f: fn(&glam::DVec3) -> f64| q.iter().map(f).fold(0.0, f64::max);
    let (max_xt, max_yt, max_zt) = (max(|v| v.x.abs()), max(|v| v.y.abs()), max(|v| v.z.abs()));
    let delta_x = g(5.0) * (max_xt + max_zt);
    let delta_y = g(5.0) * (max_yt + max_zt);
    let delta_e = 2.0 * (g(2.0) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
    let max_e = e.abs().max_element();
    let delta_t =
        3.0 * (g(3.0) * max_e * max_zt + delta_e * max_zt + g(3.0) * max_zt * max_e) / det.abs();
    (t > delta_t).then_some(t)
}

/// The rectangle's hit: the plane's point ([`plane_hit`]) and its edge-basis coordinates
/// ([`edge_coordinates`]) in `f64`, the point rounded once, within the `f32` bound
/// γ₆ (|c| + |a u| + |b v|). `f64` also keeps the products finite and normal for any
/// `f32` edges (|u × v|² beyond 2^±100 overflowed or underflowed in `f32`).
fn intersect_rectangle(
    corner: Vec3,
    u: Vec3,
    v: Vec3,
    o: Vec3,
    d: Vec3,
    tmin: f32,
    tmax: f32,
) -> Option<Hit> {
    let (c, u64, v64) = (corner.as_dvec3(), u.as_dvec3(), v.as_dvec3());
    let n = u64.cross(v64);
    let (t, rel) = plane_hit(corner, n, o, d, tmin, tmax)?;
    let (a, b) = edge_coordinates(rel, u64, v64, n)?;
    let p = (c + u64 * f64::from(a) + v64 * f64::from(b)).as_vec3();
    let p_error = gamma(6) * (corner.abs() + (u * a).abs() + (v * b).abs());
    let n = n.normalize().as_vec3();
    n.is_finite().then_some(Hit { t, p, p_error, n })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rays from `o` (an `f32` point, exact in `f64`) aimed at `f64` targets: whether each
    /// hits `prim`. The aim's own rounding moves a target by about 2⁻²⁴ of its distance
    /// from `o` (a few 10⁻¹³ here), far inside the 10⁻⁸ the targets keep from a boundary.
    fn hits_towards(prim: &Primitive, o: Vec3, targets: &[(DVec3, bool)]) -> Vec<String> {
        targets
            .iter()
            .filter_map(|&(target, inside)| {
                let d = (target - o.as_dvec3()).normalize().as_vec3();
                let hit = prim.intersect(o, d, 0.0, f32::INFINITY).is_some();
                (hit != inside).then(|| format!("{target:?}: hit {hit}, inside {inside}"))
            })
            .collect()
    }

    /// Two orthonormal axes of the plane normal to `normal`, in `f64` (an `f32` frame's
    /// axes are off the plane and off unit length by ~6·10⁻⁸, more than the targets'
    /// 10⁻⁸).
    fn plane_axes(normal: Vec3) -> (DVec3, DVec3) {
        let n = normal.as_dvec3().normalize();
        let s = n
            .cross(if n.x.abs() < 0.9 { DVec3::X } else { DVec3::Y })
            .normalize();
        (s, n.cross(s))
    }

    /// A disk (`inner` = 0) or an annulus.
    fn ring(center: Vec3, normal: Vec3, inner: f32, radius: f32) -> Primitive {
        if inner > 0.0 {
            Primitive::Annulus {
                center,
                normal,
                inner,
                radius,
            }
        } else {
            Primitive::Disk {
                center,
                normal,
                radius,
            }
        }
    }

    /// Targets 10⁻⁸ on either side of a boundary, a quarter of the old band: ⟨centre + ρ
    /// (cos φ s + sin φ t)⟩ for ρ = R(1 ± 10⁻⁸) over a few 10⁻⁶ of arc about φ = 0, inside
    /// when ρ < R (the other way for a hole's rim, `hole`).
    fn ring_targets(center: Vec3, normal: Vec3, r: f32, hole: bool) -> Vec<(DVec3, bool)> {
        let (c, s, t) = (
            center.as_dvec3(),
            plane_axes(normal).0,
            plane_axes(normal).1,
        );
        let mut out = Vec::new();
        for k in -8..=8 {
            let phi = k as f64 * 5e-7;
            for side in [-1.0, 1.0] {
                let rho = f64::from(r) * (1.0 + side * 1e-8);
                out.push((
                    c + (s * phi.cos() + t * phi.sin()) * rho,
                    (side < 0.0) != hole,
                ));
            }
        }
        out
    }

    /// A disk's rim and an annulus's inner rim seen from a few 10⁻⁶ away: every ray aimed 10⁻⁸
    /// inside hits and every one 10⁻⁸ outside misses. Rounded to `f32`'s grid, the plane's
    /// point o + t d moved the rim to the grid point beside it (up to 6·10⁻⁸ out), the same
    /// way for every ray from there: such receivers read every estimator up to 3% high
    /// (session 52's audit). Checked for an axis-aligned and a tilted plane, beside and
    /// above the rim.
    #[test]
    fn rims_admit_no_band_beyond_them() {
        let tilted = Vec3::new(0.3, -0.2, 0.9).normalize();
        for normal in [Vec3::Z, tilted] {
            let center = Vec3::new(0.0, 0.0, 0.0);
            let s = plane_axes(normal).0;
            for (inner, radius, rim, hole) in [(0.0, 1.0, 1.0, false), (1.0, 2.0, 1.0, true)] {
                let prim = ring(center, normal, inner, radius);
                let targets = ring_targets(center, normal, rim, hole);
                for (out, up) in [
                    (2f64.powi(-19), 2f64.powi(-19)),
                    (-2f64.powi(-20), 2f64.powi(-18)),
                ] {
                    let o = (s * (f64::from(rim) + out) + normal.as_dvec3() * up).as_vec3();
                    let wrong = hits_towards(&prim, o, &targets);
                    assert!(wrong.is_empty(), "{prim:?} from {o:?}: {wrong:#?}");
                }
            }
        }
    }

    /// A disk's and an annulus's hits over their faces, tilted and about centres at and off
    /// the origin, from 10⁻⁶ to 10⁶ across: the point lies within its bound of the plane
    /// (what ray offsetting projects on the normal), and the bound is never negative and
    /// within γ₇ (|c| + R) per axis.
    #[test]
    fn ring_hits_bound_their_point() {
        for k in [-6, 0, 6] {
            let s = 10f32.powi(k);
            for center in [
                Vec3::ZERO,
                Vec3::new(0.0, 0.5, -0.25) * s,
                Vec3::new(3.0, -2.0, 1.0) * s,
            ] {
                for normal in [Vec3::new(0.3, -0.2, 0.9).normalize(), Vec3::Y] {
                    let (axis_s, axis_t) = plane_axes(normal);
                    for (inner, radius) in [(0.0, s), (0.25 * s, s)] {
                        let prim = ring(center, normal, inner, radius);
                        for i in 0..64 {
                            let (rho, phi) = (0.3 + 0.01 * i as f64, 0.7 * i as f64);
                            let target = center.as_dvec3()
                                + (axis_s * phi.cos() + axis_t * phi.sin()) * (rho * f64::from(s));
                            let o = (target + DVec3::new(0.2, 0.1, 0.5) * f64::from(s)).as_vec3();
                            let d = (target - o.as_dvec3()).normalize().as_vec3();
                            let h = prim
                                .intersect(o, d, 0.0, f32::INFINITY)
                                .unwrap_or_else(|| panic!("{prim:?} missed from {o:?}"));
                            let m = normal.as_dvec3().normalize();
                            let off = (h.p.as_dvec3() - center.as_dvec3()).dot(m).abs();
                            assert!(h.p_error.cmpge(Vec3::ZERO).all(), "{prim:?}: {h:?}");
                            assert!(
                                off <= m.abs().dot(h.p_error.as_dvec3()),
                                "{prim:?}: {h:?} is {off:e} off its plane"
                            );
                            let tight = gamma(7) * (center.abs() + Vec3::splat(radius));
                            assert!(
                                h.p_error.cmple(tight).all(),
                                "{prim:?}: {h:?} against {tight:?}"
                            );
                        }
                    }
                }
            }
        }
    }

    /// A rectangle's far edges (a = 1 and b = 1) seen from 2·10⁻⁶ away: rays aimed 10⁻⁸ of
    /// an edge inside hit and 10⁻⁸ outside miss, as at the two edges through the corner. In
    /// `f32` the coordinate a = ⟨…⟩/|n|² rounded to 1 from up to 2⁻²⁴ above it, and the
    /// plane's point fell on `f32`'s grid: a receiver that close to a far edge read BSDF
    /// sampling 5.9% high (session 52's audit). An axis-aligned 2 × 2 light and a skewed,
    /// tilted one whose u × v rounds in `f32`.
    #[test]
    fn far_edges_admit_no_band_beyond_them() {
        for (corner, u, v) in [
            (
                Vec3::new(-1.0, -1.0, 0.0),
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(0.0, 2.0, 0.0),
            ),
            (
                Vec3::new(0.3, -0.7, 0.2),
                Vec3::new(1.3, 0.4, -0.3),
                Vec3::new(-0.2, 0.9, 0.7),
            ),
        ] {
            let prim = Primitive::Rectangle { corner, u, v };
            let (c, u64, v64) = (corner.as_dvec3(), u.as_dvec3(), v.as_dvec3());
            let n = u64.cross(v64).normalize();
            let at = |a: f64, b: f64| c + u64 * a + v64 * b;
            for edge in 0..4 {
                // The edge's coordinate (0 or 1) and which of a, b it fixes.
                let (fixed, along_a) = [(1.0, true), (1.0, false), (0.0, true), (0.0, false)][edge];
                let point = |x: f64, y: f64| if along_a { at(x, y) } else { at(y, x) };
                let inward = if fixed == 1.0 { -1.0 } else { 1.0 };
                let du = if along_a { u64.length() } else { v64.length() };
                let mut targets = Vec::new();
                for k in -8..=8 {
                    let y = 0.5 + k as f64 * 5e-7;
                    for side in [-1.0, 1.0] {
                        let x = fixed + inward * side * 1e-8 / du;
                        targets.push((point(x, y), side > 0.0));
                    }
                }
                for (off, up) in [(2e-6, 1e-6), (-1e-6, 2e-6)] {
                    let o = (point(fixed + inward * off / du, 0.5) + n * up).as_vec3();
                    let wrong = hits_towards(&prim, o, &targets);
                    assert!(wrong.is_empty(), "edge {edge} from {o:?}: {wrong:#?}");
                }
            }
        }
    }

    /// A disk's or annulus's box holds the whole disk (the `f32` normal normalised in
    /// `f64`, its exact extent r·√(1 − n̂ᵢ²) about the centre along each axis), and is no
    /// wider than its paddings allow, for normals from 10⁻⁸ to 10⁻¹ off each coordinate
    /// axis, where 1 − nᵢ² in `f32` cancels to 0.
    #[test]
    fn disk_boxes_hold_the_whole_disk_near_an_axis() {
        for axis in 0..3 {
            for tilt in [1e-8f32, 1e-7, 1e-5, 1e-4, 1e-3, 1e-1] {
                for sign in [1.0f32, -1.0] {
                    let mut n = Vec3::ZERO;
                    n[axis] = sign;
                    n[(axis + 1) % 3] = tilt;
                    n[(axis + 2) % 3] = -0.5 * tilt;
                    let normal = n.normalize();
                    let center = Vec3::new(0.25, -0.5, 1.0);
                    for prim in [
                        Primitive::Disk {
                            center,
                            normal,
                            radius: 2.0,
                        },
                        Primitive::Annulus {
                            center,
                            normal,
                            inner: 1.0,
                            radius: 2.0,
                        },
                    ] {
                        let (lo, hi) = prim.bounds();
                        let m = normal.as_dvec3().normalize();
                        for i in 0..3 {
                            let e = 2.0 * (1.0 - m[i] * m[i]).max(0.0).sqrt();
                            let c = f64::from(center[i]);
                            // Holding it, and no wider than its paddings (γ₅ r, γ₃ times the
                            // largest coordinate) and the rounding of the extent allow.
                            let slack = 2.0 * f64::from(gamma(5)) * 2.0
                                + 2.0 * f64::from(gamma(3)) * 3.0
                                + 1e-6 * e;
                            assert!(
                                f64::from(lo[i]) <= c - e
                                    && f64::from(hi[i]) >= c + e
                                    && f64::from(lo[i]) >= c - e - slack
                                    && f64::from(hi[i]) <= c + e + slack,
                                "axis {axis}, tilt {tilt:e}, {prim:?}: [{}, {}] against {c} ± {e:e}",
                                lo[i],
                                hi[i]
                            );
                        }
                    }
                }
            }
        }
    }

    /// A disk's box holds the whole disk whatever the rounding of its `f32` unit normal:
    /// 20 000 random normals (points of a cube normalised), radius 10³ at the origin, where the padding γ₃ times the
    /// largest coordinate is smallest beside the disk (without the box's γ₅ r margin, about
    /// one check in 6 000 of this kind found the disk's exact extent beyond its box).
    #[test]
    fn disk_boxes_hold_the_disk_whatever_the_normals_rounding() {
        let sampler = crate::sampling::Sampler::independent(61);
        for i in 0..20_000u64 {
            let mut st = sampler.stream(i);
            let v = Vec3::new(st.next_1d(), st.next_1d(), st.next_1d()) * 2.0 - Vec3::ONE;
            if v.length_squared() < 1e-3 {
                continue;
            }
            let normal = v.normalize();
            let radius = 1000.0 * (0.5 + st.next_1d());
            let (lo, hi) = Primitive::Disk {
                center: Vec3::ZERO,
                normal,
                radius,
            }
            .bounds();
            let m = normal.as_dvec3().normalize();
            for a in 0..3 {
                let e = f64::from(radius) * (1.0 - m[a] * m[a]).max(0.0).sqrt();
                assert!(
                    f64::from(lo[a]) <= -e && f64::from(hi[a]) >= e,
                    "{normal:?}, r {radius}: axis {a}, [{}, {}] against ±{e}",
                    lo[a],
                    hi[a]
                );
            }
        }
    }

    /// Every area sample lies within its error bound of the exact surface (the shape's
    /// `f32` parameters taken as exact, the distance in `f64`): a sphere or cap point
    /// within |p_error| of the sphere, a planar point within Σ|n̂ᵢ| eᵢ of its plane.
    /// Every primitive kind at 10⁻³, 1 and 10³ across, at the origin and 10⁴ away
    /// (where the centre's rounding dominates), 40 × 40 samples each. Ray offsets rely
    /// on these bounds (`partial`'s and `shape`'s docs: "the shape's own").
    #[test]
    fn area_samples_lie_within_their_error_bounds() {
        use glam::DVec3;
        for scale in [1e-3f32, 1.0, 1e3] {
            for shift in [Vec3::ZERO, Vec3::new(1e4, -7e3, 3e3)] {
                let c = shift + Vec3::new(0.3, -0.1, 0.2) * scale;
                let axis = Vec3::new(0.0, 0.6, 0.8);
                let t = 50f64.to_radians();
                let prims = [
                    Primitive::Sphere {
                        center: c,
                        radius: scale,
                    },
                    Primitive::SphericalCap {
                        center: c,
                        radius: scale,
                        axis,
                        cos_max: t.cos() as f32,
                        one_minus_cos: (2.0 * (0.5 * t).sin().powi(2)) as f32,
                    },
                    Primitive::Rectangle {
                        corner: c,
                        u: Vec3::new(0.7, 0.2, 0.1) * scale,
                        v: Vec3::new(-0.2, 0.7, 0.0) * scale,
                    },
                    Primitive::Disk {
                        center: c,
                        normal: axis,
                        radius: scale,
                    },
                    Primitive::Annulus {
                        center: c,
                        normal: axis,
                        inner: 0.4 * scale,
                        radius: scale,
                    },
                    Primitive::Triangle {
                        p: [
                            c,
                            c + Vec3::new(1.0, 0.1, 0.3) * scale,
                            c + Vec3::new(0.2, 0.9, -0.4) * scale,
                        ],
                    },
                ];
                for prim in prims {
                    for i in 0..1600 {
                        let u = Vec2::new(
                            ((i % 40) as f32 + 0.37) / 40.0,
                            ((i / 40) as f32 + 0.61) / 40.0,
                        );
                        let s = prim.sample_area(u);
                        let (p, e) = (s.p.as_dvec3(), s.p_error.as_dvec3());
                        let (off, bound) = match prim {
                            Primitive::Sphere { center, radius }
                            | Primitive::SphericalCap { center, radius, .. } => (
                                ((p - center.as_dvec3()).length() - radius as f64).abs(),
                                e.length(),
                            ),
                            Primitive::Rectangle { corner, u, v } => {
                                let n = u.as_dvec3().cross(v.as_dvec3()).normalize();
                                ((p - corner.as_dvec3()).dot(n).abs(), n.abs().dot(e))
                            }
                            Primitive::Disk { center, normal, .. }
                            | Primitive::Annulus { center, normal, .. } => {
                                let n = normal.as_dvec3().normalize();
                                ((p - center.as_dvec3()).dot(n).abs(), n.abs().dot(e))
                            }
                            Primitive::Triangle { p: v } => {
                                let v = v.map(|x| x.as_dvec3());
                                let n = (v[1] - v[0]).cross(v[2] - v[0]).normalize();
                                ((p - v[0]).dot(n).abs(), n.abs().dot(e))
                            }
                        };
                        let slack = 1e-12 * (p.length() + DVec3::ONE.length() * scale as f64);
                        assert!(
                            off <= bound + slack,
                            "{prim:?} at u = {u}: {off:e} off the surface, bound {bound:e}"
                        );
                    }
                }
            }
        }
    }

    /// A ray from h = 10⁻⁵ … 10⁻⁷ above the interior of a triangle 2 across meets it at
    /// o + (h/|d_z|) d (within the hit's error bound) whatever its direction below the
    /// plane, and a ray leaving the plane never does; a ray spawned from the triangle's
    /// own points (offset past their error bound) never meets it again. The `f32` test's
    /// bound on t (γ-terms times the vertices' extent along the ray's dominant axis)
    /// exceeded h for every ray not mostly along the normal, and pbrt-v4 reports those
    /// as misses: 2736 of 4096 rays at h = 10⁻⁶ (a receiver there read 45% low).
    #[test]
    fn triangles_are_hit_from_just_above_them() {
        let tri = Primitive::Triangle {
            p: [
                Vec3::ZERO,
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(0.0, 2.0, 0.0),
            ],
        };
        for h in [1e-5f32, 1e-6, 1e-7] {
            let o = Vec3::new(0.5, 0.5, h);
            for i in 0..64 {
                for j in 0..64 {
                    let ct = (i as f32 + 0.5) / 64.0;
                    let phi = (j as f32 + 0.5) / 64.0 * std::f32::consts::TAU;
                    let st = (1.0 - ct * ct).sqrt();
                    let d = Vec3::new(st * phi.cos(), st * phi.sin(), -ct);
                    let hit = tri
                        .intersect(o, d, 0.0, f32::INFINITY)
                        .unwrap_or_else(|| panic!("h = {h:e}: d = {d} missed"));
                    // The exact point o + (h/|d_z|) d, within the hit's own error bound.
                    let want = o.as_dvec3() + d.as_dvec3() * (h as f64 / ct as f64);
                    let off = (hit.p.as_dvec3() - want).abs();
                    // Plus the f64 rounding of `want` itself (coordinates below 1).
                    let slack = glam::DVec3::splat(4.0 * f64::EPSILON);
                    assert!(
                        off.cmple(hit.p_error.as_dvec3() + slack).all(),
                        "h = {h:e}, d = {d}: hit at {}, exact {want}, error bound {}",
                        hit.p,
                        hit.p_error
                    );
                    let up = Vec3::new(d.x, d.y, ct);
                    assert!(
                        tri.intersect(o, up, 0.0, f32::INFINITY).is_none(),
                        "h = {h:e}: {up} leaves the plane yet hit"
                    );
                }
            }
        }
        let sampler = crate::sampling::Sampler::independent(5);
        for i in 0..20_000u64 {
            let mut st = sampler.stream(i);
            let (u, v) = (st.next_1d(), st.next_1d());
            let (a, b) = if u + v > 1.0 {
                (1.0 - u, 1.0 - v)
            } else {
                (u, v)
            };
            let hit = tri
                .intersect(
                    Vec3::new(2.0 * a, 2.0 * b, 1.0),
                    -Vec3::Z,
                    0.0,
                    f32::INFINITY,
                )
                .unwrap();
            let w = crate::sampling::sphere::uniform_sphere(st.next_2d());
            let o = crate::math::offset_ray_origin(hit.p, hit.p_error, hit.n, w);
            assert!(
                tri.intersect(o, w, 0.0, f32::INFINITY).is_none(),
                "spawned at {o} along {w}, re-hit"
            );
        }
    }

    /// A triangle and a rectangle from 10⁻¹⁸ to 10¹⁸ across, hit from 3 sizes away at an
    /// angle: the distance, point and normal equal the f64 closed form (the plane's
    /// t = ⟨c − o, n⟩/⟨d, n⟩) to f32 precision. At 10¹⁴ the f32 edge functions' products
    /// overflowed (t NaN, n = 0), below 10⁻¹⁰ the normal's square underflowed (never hit).
    #[test]
    fn planar_hits_hold_at_every_scale() {
        // Corner off the origin, and at it with the hit far along the first edge (where
        // the point's magnitude comes from a·u alone, so no other term of the bound covers it).
        for (k, (corner, ua, vb)) in (-18..=18).flat_map(|k| {
            [
                (k, (Vec3::new(0.5, -0.3, 0.2), 0.3, 0.4)),
                (k, (Vec3::ZERO, 0.8, 0.1)),
            ]
        }) {
            let s = 10f32.powi(k);
            let (a, b) = (Vec3::new(s, 0.0, 0.0), Vec3::new(0.2 * s, s, 0.1 * s));
            let c = corner * s;
            let target = c + a * ua + b * vb;
            let d = Vec3::new(0.3, -0.2, 1.0).normalize();
            let o = target - d * (3.0 * s);
            for prim in [
                Primitive::Triangle {
                    p: [c, c + a, c + b],
                },
                Primitive::Rectangle {
                    corner: c,
                    u: a,
                    v: b,
                },
            ] {
                let h = prim
                    .intersect(o, d, 0.0, f32::INFINITY)
                    .unwrap_or_else(|| panic!("scale {s:e}: {prim:?} missed"));
                let n = a.as_dvec3().cross(b.as_dvec3());
                let t = (c.as_dvec3() - o.as_dvec3()).dot(n) / d.as_dvec3().dot(n);
                assert!(
                    (f64::from(h.t) - t).abs() <= 1e-5 * t,
                    "scale {s:e}: t {} against {t}",
                    h.t
                );
                let p = o.as_dvec3() + d.as_dvec3() * t;
                let err = (h.p.as_dvec3() - p).abs();
                // The bound holds off the surface (what ray offsetting projects on the
                // normal) in every configuration…
                let m = n.normalize();
                let off = (h.p.as_dvec3() - p).dot(m).abs();
                // A bound is never negative in any component (ray offsetting sums them
                // along |n|, so one negative term would shrink the others' cover).
                assert!(
                    h.p_error.cmpge(Vec3::ZERO).all(),
                    "scale {s:e}: {prim:?} {h:?} has a negative error bound"
                );
                assert!(
                    off <= m.abs().dot(h.p_error.as_dvec3()),
                    "scale {s:e}: {prim:?} {h:?} is {off:e} off the plane"
                );
                // …and per axis where the point's magnitude is the surface's: with the
                // corner at the origin and the viewer farther out than the point, the
                // re-projected point's place along the surface also carries the ray's own
                // rounding, u(|o| + t), which `p_error` (a distance from the surface) does
                // not claim to bound.
                if corner != Vec3::ZERO {
                    assert!(
                        err.cmple(h.p_error.as_dvec3()).all(),
                        "scale {s:e}: {prim:?} {h:?} err {err:?}"
                    );
                }
                // …and not loose: within γ₈ of the vertices' (the corner's and edges')
                // magnitudes, as the f32 analysis gives.
                let tight = match prim {
                    Primitive::Triangle { p } => gamma(8) * (p[0].abs() + p[1].abs() + p[2].abs()),
                    _ => gamma(7) * (c.abs() + a.abs() + b.abs()),
                };
                assert!(
                    h.p_error.cmple(tight).all(),
                    "scale {s:e}: {h:?} against {tight:?}"
                );
                assert!(
                    (h.n.as_dvec3() - n.normalize()).length() < 1e-6,
                    "scale {s:e}: {h:?}"
                );
                // The same ray offset past the edge misses.
                let beside = target + (c - target) * 2.0 - b * 0.5;
                assert!(
                    prim.intersect(beside - d * (3.0 * s), d, 0.0, f32::INFINITY)
                        .is_none()
                );
                // The area sample's normal is a unit vector too.
                let n2 = prim.sample_area(Vec2::new(0.3, 0.6)).n;
                assert!((n2.length() - 1.0).abs() < 1e-6, "scale {s:e}: {n2:?}");
            }
        }
    }

    /// The segment (tmin, tmax) is open at both ends: a sphere whose roots are exactly 4
    /// and 6 is not hit within (0, 4) nor (6, ∞), and from (4, ∞) the far root is the hit.
    #[test]
    fn sphere_roots_at_the_segment_ends_are_excluded() {
        let s = Primitive::Sphere {
            center: Vec3::new(0.0, 0.0, 5.0),
            radius: 1.0,
        };
        let t = |tmin: f32, tmax: f32| s.intersect(Vec3::ZERO, Vec3::Z, tmin, tmax).map(|h| h.t);
        assert_eq!(t(0.0, f32::INFINITY), Some(4.0));
        assert_eq!(t(0.0, 4.0), None);
        assert_eq!(t(4.0, f32::INFINITY), Some(6.0));
        assert_eq!(t(4.0, 6.0), None);
        assert_eq!(t(6.0, f32::INFINITY), None);
        assert_eq!(t(3.5, 4.5), Some(4.0));
    }

    /// The open segment holds at every scale for triangles and rectangles, through the
    /// `f32` tests (side 2) and the `f64` ones for extreme coordinates (side 2⁶⁷, where
    /// `intersect_triangle_wide` and `intersect_rectangle_wide` take over): a plane exactly
    /// s ahead is hit at t = s, not within (0, s) nor (s, ∞).
    #[test]
    fn planar_hits_at_the_segment_ends_are_excluded() {
        for s in [1.0f32, 2f32.powi(66)] {
            let z = Vec3::new(0.0, 0.0, s);
            for prim in [
                Primitive::Triangle {
                    p: [
                        Vec3::new(-s, -s, s),
                        Vec3::new(s, -s, s),
                        Vec3::new(0.0, s, s),
                    ],
                },
                Primitive::Rectangle {
                    corner: Vec3::new(-s, -s, s),
                    u: Vec3::new(2.0 * s, 0.0, 0.0),
                    v: Vec3::new(0.0, 2.0 * s, 0.0),
                },
            ] {
                let t = |tmin: f32, tmax: f32| {
                    prim.intersect(Vec3::ZERO, Vec3::Z, tmin, tmax).map(|h| h.t)
                };
                assert_eq!(t(0.0, f32::INFINITY), Some(z.z), "{prim:?}");
                assert_eq!(t(0.0, s), None, "{prim:?}");
                assert_eq!(t(s, f32::INFINITY), None, "{prim:?}");
                assert_eq!(t(s.next_down(), s.next_up()), Some(s), "{prim:?}");
            }
        }
    }

    /// Planes are met at t = ⟨origin − o, n⟩/⟨d, n⟩ from any ray origin, inside the open
    /// segment: a disk and a rectangle exactly 4 ahead of an origin off the axes are hit
    /// at t = 4, not within (0, 4) nor (4, ∞).
    #[test]
    fn planes_are_met_from_any_origin_inside_the_open_segment() {
        let o = Vec3::new(1.0, 2.0, 1.0);
        for prim in [
            Primitive::Disk {
                center: Vec3::new(1.0, 2.0, 5.0),
                normal: -Vec3::Z,
                radius: 1.0,
            },
            Primitive::Rectangle {
                corner: Vec3::new(0.5, 1.5, 5.0),
                u: Vec3::X,
                v: Vec3::Y,
            },
        ] {
            let t =
                |tmin: f32, tmax: f32| prim.intersect(o, Vec3::Z, tmin, tmax).map(|h| (h.t, h.p));
            assert_eq!(
                t(0.0, f32::INFINITY),
                Some((4.0, Vec3::new(1.0, 2.0, 5.0))),
                "{prim:?}"
            );
            assert_eq!(t(0.0, 4.0), None, "{prim:?}");
            assert_eq!(t(4.0, f32::INFINITY), None, "{prim:?}");
        }
    }

    /// Numbers uniform in [−1, 1) on a 2⁻²³ grid from a fixed 64-bit LCG (Knuth's MMIX
    /// constants) seeded with `state`: the same rays every run.
    fn signed_uniforms(mut state: u64) -> impl FnMut() -> f32 {
        move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 40) as f32 / (1u64 << 23) as f32 - 1.0
        }
    }

    /// Nearly tangent rays from origins on huge spheres (radius 3·10⁷–10⁸, a huge emitter
    /// or a sky dome), within the `f32` band of the surface
    /// ([`intersect_sphere_near_surface`]): every ray meets the sphere where the `f64`
    /// roots of its `f32` inputs say, at their forward root (relative 10⁻⁶), thousands of
    /// units ahead. (Those roots use the engine's own `f64` formulas, so inside the band
    /// the test checks which path a ray takes; their own error is ~10⁻¹⁶ r².)
    /// In `f32` there b = −f·d (each product rounded to a few units) can have the other
    /// sign than the exact one, and the discriminant r² − |f + b d|² is a multiple of
    /// ulp(r²) ≈ 10⁹ where the exact one is ~10⁸: with the `f32` far root, 376 of these
    /// 59 983 rays missed the sphere they started inside and 10 686 met it more than
    /// 10⁻⁶ off, up to 35.7 times too far. At least 100 rays of each sign disagreement
    /// are met, so the far root's sign and size are both tested.
    #[test]
    fn nearly_tangent_rays_on_huge_spheres_take_the_exact_far_root() {
        let mut uniform = signed_uniforms(0x2545_f491_4f6c_dd1d);
        // The band's rays whose b signs disagree: (f32 b > 0 ≥ exact b, exact b > 0 ≥ f32 b).
        let mut mismatched = [0usize; 2];
        for (center, radius) in [
            (Vec3::ZERO, 1e8f32),
            (Vec3::new(3e8, -2e7, 5e6), 1e8),
            (Vec3::new(1e3, 2e3, -4e3), 3e7),
        ] {
            for _ in 0..20_000 {
                let n = Vec3::new(uniform(), uniform(), uniform()).normalize();
                let o = center + n * radius;
                let w = Vec3::new(uniform(), uniform(), uniform());
                let d = n.cross(w).normalize();
                let f = o - center;
                let (ff, rr) = (f.length_squared(), radius * radius);
                let c32 = ff - rr;
                let b32 = -f.dot(d);
                let b = -(o.as_dvec3() - center.as_dvec3()).dot(d.as_dvec3());
                if !within_sphere_band(ff, rr, c32) {
                    continue;
                }
                if (b32 > 0.0) != (b > 0.0) {
                    mismatched[usize::from(b > 0.0)] += 1;
                }
                let hit = Primitive::Sphere { center, radius }.intersect(o, d, 0.0, f32::INFINITY);
                let want = exact_sphere_roots(center, radius, o, d).and_then(|[_, s, big]| {
                    [s, big].into_iter().filter(|&t| t > 0.0).reduce(f64::min)
                });
                let what =
                    format!("sphere {center} r {radius}, o {o}, d {d}: b {b32} in f32, {b} exact");
                match (want, hit) {
                    (Some(want), Some(hit)) => assert!(
                        (f64::from(hit.t) - want).abs() <= 1e-6 * want,
                        "{what}: t {} for {want}",
                        hit.t
                    ),
                    (want, hit) => assert_eq!(want.is_some(), hit.is_some(), "{what}: {hit:?}"),
                }
            }
        }
        assert!(mismatched.iter().all(|&k| k >= 100), "{mismatched:?}");
    }

    /// Rays from origins near a sphere, beyond its band, towards the root near 0 (outside
    /// and approaching, inside and leaving): the root is exact to its `f32` rounding
    /// (2u relative, for the `f64` root's own error and t's rounding) from every origin
    /// within [`NEAR_ROOT`] of |f|², and within c's own error bound beyond (about 128u at
    /// the switch), where the `f32` root is kept (most of them are not the `f64` root's
    /// rounding). Before the switch, c/q from the `f32` c was up to ~5% long from
    /// 10⁻⁶ r, ~1% from 3.8·10⁻⁶ r (where a cap's rim admitted a band beyond it).
    /// Spheres of radius 10⁻³ to 10⁸, one 10⁵ from the origin; gaps from 2·10⁻⁶ to 0.5 r.
    #[test]
    fn roots_ahead_of_near_origins_are_exact() {
        let mut uniform = signed_uniforms(0x5851_f42d_4c95_7f2d);
        let u = f64::from(f32::EPSILON) / 2.0;
        let (mut switched, mut beyond, mut fast) = (0, 0, 0);
        let mut worst = [0.0f64; 2];
        for (center, radius) in [
            (Vec3::ZERO, 1.0f32),
            (Vec3::new(0.3, -0.2, 0.1), 1e-3),
            (Vec3::new(1e5, -1e5, 3e4), 1e3),
            (Vec3::new(1e3, 2e3, -4e3), 1e8),
        ] {
            for gap in [2e-6f32, 1e-5, 1e-4, 1e-3, 0.01, 0.03, 0.05, 0.1, 0.5] {
                for side in [-1.0f32, 1.0] {
                    for _ in 0..400 {
                        let n = Vec3::new(uniform(), uniform(), uniform()).normalize();
                        let o = center + n * (radius * (1.0 + side * gap));
                        // A direction towards the surface from outside, away from the
                        // centre from inside, at least 0.1 rad off the tangent plane.
                        let w = Vec3::new(uniform(), uniform(), uniform()).normalize();
                        let along = -side * (0.1 + 0.9 * uniform().abs());
                        let d = (n * along
                            + (w - n * w.dot(n)).normalize() * (1.0 - along * along).sqrt())
                        .normalize();
                        let Some([c, s, _]) = exact_sphere_roots(center, radius, o, d) else {
                            continue; // a ray from outside passing beside the sphere
                        };
                        if !(s > 0.0) {
                            continue;
                        }
                        let f = o - center;
                        let (ff, rr) = (f.length_squared(), radius * radius);
                        let c32 = ff - rr;
                        if within_sphere_band(ff, rr, c32) {
                            continue;
                        }
                        let hit = Primitive::Sphere { center, radius }
                            .intersect(o, d, 0.0, f32::INFINITY)
                            .unwrap_or_else(|| panic!("o {o} d {d}: no hit, c {c:e}"));
                        let err = (f64::from(hit.t) - s).abs() / s;
                        let (k, bound) = if c32.abs() < NEAR_ROOT * ff {
                            switched += 1;
                            (0, 2.0 * u)
                        } else {
                            beyond += 1;
                            fast += usize::from(hit.t != s as f32);
                            let cb = gamma(6) * ff + gamma(2) * (rr + c32.abs());
                            (1, f64::from(cb / c32.abs()) + 4.0 * u)
                        };
                        worst[k] = worst[k].max(err / u);
                        assert!(
                            err <= bound,
                            "sphere {center} r {radius}, o {o} (gap {gap}, c {c:e}), d {d}: t {} for {s}, {err:e} relative",
                            hit.t
                        );
                    }
                }
            }
        }
        assert!(switched > 5000 && beyond > 5000, "{switched} {beyond}");
        // Beyond the switch the `f32` root is kept: many of its roots are not the `f64`
        // root's rounding (the `f64` path is for the few origins near a sphere).
        assert!(fast > beyond / 4, "{fast} of {beyond} beyond the switch");
        eprintln!("worst relative error in u: {worst:?}; {fast} of {beyond} beyond in f32");
    }

    /// Grazing chords from origins near a sphere, inside and outside, within its band
    /// and up to 10⁻³ r beyond it, on spheres of radius 10⁻³ to 10⁸ (one 10⁵ from the
    /// origin): every ray meets the sphere exactly where the `f64` roots of its `f32`
    /// inputs say it does, at their forward root to 10⁻³ relative. The `f32`
    /// discriminant's noise, ~γ r² under a square root, put chords a few 10⁻⁴ r long up
    /// to 54% off before the [`GRAZING`] switch (a session-47 review: 4 of 5 million such
    /// rays beyond 10⁻³). Tilts from 0 to 0.1 rad span both sides of the switch.
    #[test]
    fn grazing_chords_are_exact_to_a_thousandth() {
        let mut uniform = signed_uniforms(0x9e37_79b9_7f4a_7c15);
        let u = f32::EPSILON / 2.0;
        let (mut f64_side, mut f32_side) = (0, 0);
        for (center, radius) in [
            (Vec3::ZERO, 1.0f32),
            (Vec3::new(0.3, -0.2, 0.1), 1e-3),
            (Vec3::new(1e5, -1e5, 3e4), 1e3),
            (Vec3::new(1e3, 2e3, -4e3), 1e8),
        ] {
            for depth in [0.0, 2.0 * u, 8.0 * u, 16.0 * u, 1e-5, 1e-3] {
                for side in [-1.0f32, 1.0] {
                    for tilt in [0.0f32, 1e-4, 1e-3, 1e-2, 0.02, 0.03, 0.1] {
                        for _ in 0..200 {
                            let n = Vec3::new(uniform(), uniform(), uniform()).normalize();
                            let o = center + n * (radius * (1.0 + side * depth));
                            let w = Vec3::new(uniform(), uniform(), uniform());
                            let t = n.cross(w).normalize();
                            // Into the sphere by `tilt` (or out of it, at random).
                            let d = (t - n * (tilt * uniform().signum())).normalize();
                            let f = o - center;
                            let l = f + d * -f.dot(d);
                            let disc = radius * radius - l.length_squared();
                            if disc.abs() < GRAZING * radius * radius {
                                f64_side += 1;
                            } else {
                                f32_side += 1;
                            }
                            let hit = Primitive::Sphere { center, radius }.intersect(
                                o,
                                d,
                                0.0,
                                f32::INFINITY,
                            );
                            let want =
                                exact_sphere_roots(center, radius, o, d).and_then(|[_, s, big]| {
                                    [s, big].into_iter().filter(|&t| t > 0.0).reduce(f64::min)
                                });
                            let what =
                                format!("sphere {center} r {radius}, o {o}, d {d}, tilt {tilt}");
                            // A root near 0 (c/q: entering from outside, leaving from
                            // inside) also carries c's own f32 error beyond the band,
                            // relative bound/|c| (`within_sphere_band`'s bound); within
                            // it the f64 roots decide.
                            let (ff, rr) = (f.length_squared(), radius * radius);
                            let c = ff - rr;
                            let c_error = if within_sphere_band(ff, rr, c) {
                                0.0
                            } else {
                                f64::from((gamma(6) * ff + gamma(2) * (rr + c.abs())) / c.abs())
                            };
                            match (want, hit) {
                                (Some(want), Some(hit)) => assert!(
                                    (f64::from(hit.t) - want).abs()
                                        <= (1e-3 + 2.0 * c_error) * want,
                                    "{what}: t {} for {want}",
                                    hit.t
                                ),
                                (want, hit) => {
                                    assert_eq!(want.is_some(), hit.is_some(), "{what}: {hit:?}")
                                }
                            }
                        }
                    }
                }
            }
        }
        assert!(f64_side > 5000 && f32_side > 5000, "{f64_side} {f32_side}");
    }

    /// The exact roots of o + t d on the sphere, its `f32` parameters and the ray taken as
    /// exact (in `f64`): (c = |o − centre|² − r², the root c/q near 0, the other q/|d|²).
    fn exact_sphere_roots(center: Vec3, radius: f32, o: Vec3, d: Vec3) -> Option<[f64; 3]> {
        let f = o.as_dvec3() - center.as_dvec3();
        let d = d.as_dvec3();
        let r = f64::from(radius);
        let c = f.length_squared() - r * r;
        let b = -f.dot(d);
        let a = d.length_squared();
        let disc = b * b - a * c;
        (disc >= 0.0).then(|| {
            let q = b + disc.sqrt().copysign(b);
            [c, c / q, q / a]
        })
    }

    /// Rays from origins within 10⁻⁷ r of a sphere (a point ρ ≤ 3·10⁻⁴ r off a pole in its
    /// tangent plane, 4.5·10⁻⁸ r above the sphere at most; and points just inside): from
    /// outside, a ray into the sphere meets it at the exact point o + s d of the root
    /// s = c/q near 0 (within the hit's error bound), a ray away from it misses; from
    /// inside, a ray inward meets the far side at the exact distance, one outward leaves
    /// at its root near 0. The `f32` c = |o − centre|² − r² is noise there (its error bound
    /// ~8u r² exceeds the exact c = ρ² < 10⁻⁷ r²): the fast test read c ≤ 0 from every
    /// origin within ~5·10⁻⁹ of a sphere of radius 0.5 and reported the far side (a floor
    /// that close below a sphere light read 0 with BSDF sampling).
    #[test]
    fn spheres_are_hit_from_just_outside_and_inside_them() {
        let spheres = [
            (Vec3::ZERO, 0.5f32),
            (Vec3::new(0.25, -0.125, 0.5), 0.5),
            // The catalog's floor case rebased on its camera.
            (Vec3::new(-1.5, 0.0, 0.499_85), 0.5),
            (Vec3::new(3.0, -2.0, 1.0), 2.0),
            (Vec3::new(1.0, 0.5, -0.25), 1e-3),
            (Vec3::new(100.0, 50.0, -20.0), 1e-3),
            // Wider spheres, where γ₆|f|² dominates the rescue window.
            (Vec3::new(0.0, 0.0, 3.0), 3.0),
            (Vec3::new(5.0, 5.0, 5.0), 8.0),
            (Vec3::ZERO, 64.0),
            (Vec3::new(-700.0, 300.0, 1000.0), 1e3),
        ];
        let (mut near, mut far) = (0, 0);
        for (center, radius) in spheres {
            for axis in 0..6 {
                // The pole: ±x, ±y or ±z; (u, v) span its tangent plane.
                let mut n = Vec3::ZERO;
                n[axis % 3] = if axis < 3 { 1.0 } else { -1.0 };
                let (ua, va) = ((axis + 1) % 3, (axis + 2) % 3);
                for (x, y, depth) in [
                    (0.0, 3e-4, 0.0),
                    (1e-4, 1e-4, 0.0),
                    (3e-5, 0.0, 0.0),
                    (1e-5, -2e-5, 0.0),
                    (0.0, 0.0, 2f32.powi(-22)),
                    (1e-5, 0.0, 2f32.powi(-20)),
                ] {
                    let mut rel = n * (radius * (1.0 - depth));
                    rel[ua] = x * radius;
                    rel[va] = y * radius;
                    let o = center + rel;
                    let Some([c, ..]) = exact_sphere_roots(center, radius, o, Vec3::X) else {
                        continue;
                    };
                    if c.abs() < 1e-14 * f64::from(radius).powi(2) {
                        continue; // on the surface as far as f64 tells
                    }
                    for i in 0..32 {
                        for j in 0..32 {
                            let ct = (i as f32 + 0.5) / 16.0 - 1.0;
                            if ct.abs() < 1.0 / 16.0 {
                                continue; // nearly tangent
                            }
                            let phi = (j as f32 + 0.5) / 32.0 * std::f32::consts::TAU;
                            let st = (1.0 - ct * ct).sqrt();
                            let mut d = n * ct;
                            d[ua] += st * phi.cos();
                            d[va] += st * phi.sin();
                            let d = d.normalize();
                            let [_, s, big] = exact_sphere_roots(center, radius, o, d).unwrap();
                            let hit = Primitive::Sphere { center, radius }.intersect(
                                o,
                                d,
                                0.0,
                                f32::INFINITY,
                            );
                            let what =
                                format!("sphere {center} r {radius}, o {o} (c {c:e}), d {d}");
                            // The root ahead: c/q near 0 if positive, else the other.
                            let want = if s > 0.0 {
                                Some(s)
                            } else if big > 0.0 {
                                Some(big)
                            } else {
                                None
                            };
                            let (Some(want), Some(hit)) = (want, hit) else {
                                assert_eq!(want.is_some(), hit.is_some(), "{what}: {hit:?}");
                                continue;
                            };
                            if want == s {
                                // The exact point, within the hit's error bound plus that of
                                // t along the ray: the f32 c's relative error ~8u r²/|c| where
                                // the origin lies beyond its bound (the f32 root decides),
                                // rounding alone within it (the f64 root). (A far hit's point
                                // also carries the ray's rounding along the surface.)
                                near += 1;
                                assert!(
                                    hit.t > 0.0 && f64::from(hit.t) < 2.0 * want,
                                    "{what}: t {} for {want:e}",
                                    hit.t
                                );
                                let exact = o.as_dvec3() + d.as_dvec3() * want;
                                let off = (hit.p.as_dvec3() - exact).abs();
                                let u = f64::from(f32::EPSILON) / 2.0;
                                let rr = f64::from(radius).powi(2);
                                // The documented rescue window, in f32 as the test
                                // reads it: inside it the f64 root, rounded once to t.
                                let f = (o - center).length_squared();
                                let c32 = f - radius * radius;
                                let rescued = c32.abs()
                                    <= gamma(6) * f + gamma(2) * (radius * radius + c32.abs());
                                let dt = if rescued {
                                    (u + 4.0 * f64::EPSILON) * want
                                } else {
                                    want * (10.0 * u * rr / c.abs() + 10.0 * u)
                                };
                                let slack = d.abs().as_dvec3() * dt
                                    + 4.0
                                        * f64::EPSILON
                                        * f64::from(center.abs().max_element() + radius);
                                assert!(
                                    off.cmple(hit.p_error.as_dvec3() + slack).all(),
                                    "{what}: hit at {} (t {}), exact {exact} (t {want:e}), error bound {}",
                                    hit.p,
                                    hit.t,
                                    hit.p_error
                                );
                            } else {
                                far += 1;
                                let err = (f64::from(hit.t) - want).abs();
                                assert!(err <= 1e-5 * want, "{what}: t {} for {want}", hit.t);
                            }
                            // A cap about the pole shares the test.
                            let cap = Primitive::SphericalCap {
                                center,
                                radius,
                                axis: n,
                                cos_max: 0.0,
                                one_minus_cos: 1.0,
                            };
                            if want == s {
                                let h = cap.intersect(o, d, 0.0, f32::INFINITY);
                                assert_eq!(h.map(|h| h.t), Some(hit.t), "{what}: cap");
                            }
                        }
                    }
                }
            }
        }
        assert!(near > 10_000 && far > 10_000, "{near} near, {far} far hits");
    }

    /// A ray spawned from a point of a sphere (offset past its error bound towards the
    /// side it leaves, [`crate::math::offset_ray_origin`]) never meets the sphere near its
    /// origin: outward it misses, inward it meets the far side, a chord 2r|cos θ| away.
    /// The furnace is the inside of a sphere, so every path there spawns such rays; the
    /// origin lies ≥ γ₅r ≈ 3·10⁻⁷ r off the surface, where the `f32` sign of c is sometimes
    /// within its bound and the `f64` root decides.
    #[test]
    fn rays_spawned_from_a_sphere_never_meet_it_again() {
        let spheres = [
            (Vec3::ZERO, 1.0f32),
            (Vec3::new(-1.5, 0.0, 0.499_85), 0.5),
            (Vec3::new(0.25, -0.125, 0.5), 1e-3),
            (Vec3::new(1e3, -2e3, 5e2), 10.0),
        ];
        let sampler = crate::sampling::Sampler::independent(7);
        for (k, (center, radius)) in spheres.into_iter().enumerate() {
            let s = Primitive::Sphere { center, radius };
            for i in 0..20_000u64 {
                let mut st = sampler.stream(i + 20_000 * k as u64);
                // A point of the sphere, hit from outside or from its centre.
                let a = crate::sampling::sphere::uniform_sphere(st.next_2d());
                let hit = if i % 2 == 0 {
                    s.intersect(center + a * (3.0 * radius), -a, 0.0, f32::INFINITY)
                } else {
                    s.intersect(center, a, 0.0, f32::INFINITY)
                }
                .unwrap();
                let w = crate::sampling::sphere::uniform_sphere(st.next_2d());
                let cos = w.dot(hit.n);
                if cos.abs() < 1e-3 {
                    continue;
                }
                let o = crate::math::offset_ray_origin(hit.p, hit.p_error, hit.n, w);
                let again = s.intersect(o, w, 0.0, f32::INFINITY);
                if cos > 0.0 {
                    assert!(
                        again.is_none(),
                        "{center} r {radius}: spawned at {o} along {w}, re-hit {again:?}"
                    );
                } else {
                    // The far side: the exact root ahead, about the chord 2r|cos θ|.
                    let [c, near, far] = exact_sphere_roots(center, radius, o, w).unwrap();
                    assert!(c < 0.0 && near < 0.0, "{center} r {radius}: {o} not inside");
                    // Within the f32 root's own error, ~u r²/b² relative (b = r cos θ).
                    let t = again.map_or(0.0, |h| f64::from(h.t));
                    assert!(
                        (t - far).abs() <= far * (1e-5 + 1e-6 / f64::from(cos * cos)),
                        "{center} r {radius}: spawned at {o} along {w}, met at {t} for {far}"
                    );
                }
            }
        }
    }

    #[test]
    fn sphere_hits_from_outside_and_inside() {
        let s = Primitive::Sphere {
            center: Vec3::new(0.0, 0.0, 5.0),
            radius: 1.0,
        };
        let h = s
            .intersect(Vec3::ZERO, Vec3::Z, 0.0, f32::INFINITY)
            .unwrap();
        assert!((h.t - 4.0).abs() < 1e-5 && h.n.z < 0.0);
        let h = s
            .intersect(Vec3::new(0.0, 0.0, 5.0), Vec3::Z, 0.0, f32::INFINITY)
            .unwrap();
        assert!((h.t - 1.0).abs() < 1e-5 && h.n.z > 0.0);
    }

    #[test]
    fn far_from_origin_sphere_hit_is_accurate() {
        let c = Vec3::new(1e5, -1e5, 1e5);
        let s = Primitive::Sphere {
            center: c,
            radius: 1.0,
        };
        let o = c + Vec3::new(0.3, 0.2, -10.0);
        let h = s.intersect(o, Vec3::Z, 0.0, f32::INFINITY).unwrap();
        // The point is on the sphere to within its error bound.
        let dist = ((h.p - c).as_dvec3().length() - 1.0).abs();
        assert!(
            dist <= h.p_error.length() as f64 * 2.0 + 1e-6,
            "{dist} vs {}",
            h.p_error
        );
    }

    /// The hit point is re-projected onto the sphere (pbrt-v4 §6.8.5), so it lies on it
    /// within its error bound γ₅|p − c| + γ₁|c| however far the ray came from: from 10⁴
    /// away, f + d t itself is off the unit sphere by up to ~10⁴ ε ≈ 10⁻³, far beyond
    /// the bound (3·10⁻⁷ about the origin); the reprojection's factor r/|f + d t| is what
    /// brings it back (dividing by it instead doubled the error).
    #[test]
    fn hits_from_far_away_are_reprojected_onto_the_sphere() {
        let mut stream = crate::sampling::Sampler::independent(5).stream(0);
        for c in [Vec3::ZERO, Vec3::new(3.0, -2.0, 1.0)] {
            let s = Primitive::Sphere {
                center: c,
                radius: 1.0,
            };
            for _ in 0..200 {
                let from = uniform_sphere(stream.next_2d()) * 1e4;
                let target = uniform_sphere(stream.next_2d()) * 0.9;
                let o = c + from;
                let d = (target - from).normalize();
                let h = s.intersect(o, d, 0.0, f32::INFINITY).expect("aimed inside");
                let dist = ((h.p.as_dvec3() - c.as_dvec3()).length() - 1.0).abs();
                assert!(
                    dist <= h.p_error.as_dvec3().length(),
                    "{dist:e} off the sphere, bound {:?}",
                    h.p_error
                );
            }
        }
    }

    /// Spheres whose f32 squares leave the normal range (radius 10⁻³⁰ and a subnormal
    /// 10⁻⁴², seen from 1 away; radius 10²⁰ and a centre 10²⁰ out, built in code past the
    /// loader's 10¹⁸ limit): a ray passing 3 radii off the centre misses (it was read as
    /// a grazing hit, the squares 0 − 0, with a NaN point), one passing half a radius off
    /// hits at the distance D − √(r² − r²/4) (in f64) to within 4ε, its point finite and
    /// on the sphere within its error bound, its normal a unit vector. (Seen from 1 away
    /// a sphere of 10⁻³⁰ is below t's resolution: the point is re-projected onto the
    /// sphere, pbrt-v4 §6.8.5, not necessarily where the ray would meet it.)
    #[test]
    fn spheres_beyond_the_f32_squares_hit_and_miss_exactly() {
        for (c, r) in [
            (Vec3::new(0.0, 0.0, 1e-29), 1e-30f32),
            (Vec3::new(0.0, 0.0, 0.0), 1e-42),
            (Vec3::new(0.0, 0.0, 1.0), 1e-30),
            (Vec3::new(1e20, 0.0, 0.0), 1e20),
            (Vec3::new(0.0, 0.0, 5e20), 1e20),
        ] {
            let s = Primitive::Sphere {
                center: c,
                radius: r,
            };
            let o = c - Vec3::Z * (4.0 * r).max(1.0);
            for (off, hit) in [(3.0f32, false), (0.5, true), (-0.5, true), (1.01, false)] {
                let o = o + Vec3::X * (off * r);
                let h = s.intersect(o, Vec3::Z, 0.0, f32::INFINITY);
                assert_eq!(h.is_some(), hit, "r {r}, offset {off} r: {h:?}");
                let Some(h) = h else { continue };
                let (c64, r64) = (c.as_dvec3(), r as f64);
                let dz = c64.z - o.z as f64;
                let want = dz - (r64 * r64 - (off as f64 * r64).powi(2)).sqrt();
                assert!(
                    ((h.t as f64 - want) / want).abs() <= 4.0 * f32::EPSILON as f64,
                    "r {r}: t {} vs {want}",
                    h.t
                );
                assert!(h.p.is_finite() && h.p_error.is_finite(), "{h:?}");
                let dist = ((h.p.as_dvec3() - c64).length() - r64).abs();
                assert!(
                    dist <= h.p_error.as_dvec3().length(),
                    "r {r}: {dist:e} off, {h:?}"
                );
                assert!((h.n.length() - 1.0).abs() < 1e-6, "{h:?}");
            }
        }
    }

    /// A parallelogram's area at every accepted scale: |u × v| for sides 10⁻¹⁸ … 10¹⁸
    /// within 2 ulps of the f64 value, and bit for bit `length()` where the f32 square is
    /// a normal number. It was `u.cross(v).length()`: 0 for sides of 10⁻¹² and below
    /// (|u × v|² underflows), 1% low at 10⁻¹¹ (a subnormal square), and ∞ for sides of
    /// 10¹⁰ and above (|u × v|² past `f32::MAX`).
    #[test]
    fn rectangle_areas_hold_at_every_scale() {
        for e in -18..=18 {
            let l = 10f32.powi(e);
            let (u, v) = (Vec3::new(l, 0.0, 0.0), Vec3::new(0.3 * l, l, 0.0));
            let a = Primitive::Rectangle {
                corner: Vec3::ONE,
                u,
                v,
            }
            .area();
            let want = u.as_dvec3().cross(v.as_dvec3()).length();
            assert!(
                ((a as f64 - want) / want).abs() <= 2.0 * f32::EPSILON as f64,
                "side {l:e}: area {a:e} vs {want:e}"
            );
            let a2 = u.cross(v).length_squared();
            if a2 >= f32::MIN_POSITIVE && a2.is_finite() {
                assert_eq!(a.to_bits(), u.cross(v).length().to_bits(), "side {l:e}");
            }
        }
    }

    /// A sphere smaller than the f32 rounding of its own neighbourhood (radius 10⁻¹⁵,
    /// centred at 10⁵ per axis, where f32 steps by 2⁻⁷): a ray straight down its axis from
    /// 2⁻⁶ above once returned a hit at t = 0.015625 with a NaN point, error and normal
    /// (f + d t rounded to 0, then r/|rel| = ∞); it now hits the top of the sphere, at a
    /// point within its error bound of the surface, with the normal +z. So does the same
    /// ray through a hemispherical cap about +z, which intersects through the sphere.
    #[test]
    fn tiny_spheres_far_out_hit_at_a_finite_point() {
        let c = Vec3::splat(1e5);
        for r in [1e-15f32, 1e-12] {
            let o = c + Vec3::Z * 0.015625;
            for s in [
                Primitive::Sphere {
                    center: c,
                    radius: r,
                },
                Primitive::SphericalCap {
                    center: c,
                    radius: r,
                    axis: Vec3::Z,
                    cos_max: 0.0,
                    one_minus_cos: 1.0,
                },
            ] {
                let h = s
                    .intersect(o, -Vec3::Z, 0.0, f32::INFINITY)
                    .unwrap_or_else(|| panic!("r {r}: no hit on {s:?}"));
                assert!(
                    h.t.is_finite() && h.p.is_finite() && h.p_error.is_finite(),
                    "r {r}: {h:?}"
                );
                assert_eq!(h.n, Vec3::Z, "r {r}: {h:?}");
                let dist = ((h.p.as_dvec3() - c.as_dvec3()).length() - r as f64).abs();
                assert!(
                    dist <= h.p_error.as_dvec3().length(),
                    "r {r}: {dist:e} off, {h:?}"
                );
            }
        }
    }

    /// A sphere of radius 10⁻²⁰ (r² below the normal f32 range: the f64 form) hit off its
    /// axis by a ray straight down at x = 0.3 r: the point is (0.3 r, 0, √0.91 r) and
    /// the normal (0.3, 0, √0.91), on the side the ray comes from (it was (r, 0, 0) and
    /// +x: the point of the root rounded to f32, t = 1).
    #[test]
    fn a_sphere_below_f32_squares_is_hit_where_the_ray_meets_it() {
        let r = 1e-20f32;
        let s = Primitive::Sphere {
            center: Vec3::ZERO,
            radius: r,
        };
        let o = Vec3::new(0.3 * r, 0.0, 1.0);
        let h = s.intersect(o, -Vec3::Z, 0.0, f32::INFINITY).unwrap();
        let want = Vec3::new(0.3, 0.0, 0.91f32.sqrt());
        assert!((h.n - want).length() <= 1e-5, "{h:?}");
        assert!((h.p / r - want).length() <= 1e-5, "{h:?}");
    }

    /// pbrt-v4's watertight triangle test as written there (§6.5.3), everything per
    /// triangle: the reference for the prepared-ray form, which differs only where pbrt
    /// drops a hit whose `f32` distance is within its error bound of 0
    /// (`triangles_are_hit_from_just_above_them`).
    fn pbrt_triangle(p: [Vec3; 3], o: Vec3, d: Vec3, tmin: f32, tmax: f32) -> Option<Hit> {
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        if n.length_squared() == 0.0 {
            return None;
        }
        // Translate to the ray origin, permute so that z is the largest direction component.
        let mut p0t = p[0] - o;
        let mut p1t = p[1] - o;
        let mut p2t = p[2] - o;
        let kz = d.abs().max_position();
        let kx = (kz + 1) % 3;
        let ky = (kx + 1) % 3;
        let perm = |v: Vec3| Vec3::new(v[kx], v[ky], v[kz]);
        let dp = perm(d);
        p0t = perm(p0t);
        p1t = perm(p1t);
        p2t = perm(p2t);
        let sx = -dp.x / dp.z;
        let sy = -dp.y / dp.z;
        let sz = 1.0 / dp.z;
        p0t.x += sx * p0t.z;
        p0t.y += sy * p0t.z;
        p1t.x += sx * p1t.z;
        p1t.y += sy * p1t.z;
        p2t.x += sx * p2t.z;
        p2t.y += sy * p2t.z;
        let mut e0 = crate::math::difference_of_products(p1t.x, p2t.y, p1t.y, p2t.x);
        let mut e1 = crate::math::difference_of_products(p2t.x, p0t.y, p2t.y, p0t.x);
        let mut e2 = crate::math::difference_of_products(p0t.x, p1t.y, p0t.y, p1t.x);
        if e0 == 0.0 || e1 == 0.0 || e2 == 0.0 {
            // Fall back to f64 on exact zeros (edge hits), as pbrt-v4 does.
            let (a, b, c) = (p0t.as_dvec3(), p1t.as_dvec3(), p2t.as_dvec3());
            e0 = (b.x * c.y - b.y * c.x) as f32;
            e1 = (c.x * a.y - c.y * a.x) as f32;
            e2 = (a.x * b.y - a.y * b.x) as f32;
        }
        if (e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0) {
            return None;
        }
        let det = e0 + e1 + e2;
        if det == 0.0 {
            return None;
        }
        p0t.z *= sz;
        p1t.z *= sz;
        p2t.z *= sz;
        let t_scaled = e0 * p0t.z + e1 * p1t.z + e2 * p2t.z;
        if det < 0.0 && (t_scaled >= tmin * det || t_scaled <= tmax * det) {
            return None;
        }
        if det > 0.0 && (t_scaled <= tmin * det || t_scaled >= tmax * det) {
            return None;
        }
        let inv_det = 1.0 / det;
        let (b0, b1, b2) = (e0 * inv_det, e1 * inv_det, e2 * inv_det);
        let t = t_scaled * inv_det;
        // Conservative check that t is positive beyond the error of its computation.
        let max_zt = Vec3::new(p0t.z, p1t.z, p2t.z).abs().max_element();
        let delta_z = gamma(3) * max_zt;
        let max_xt = Vec3::new(p0t.x, p1t.x, p2t.x).abs().max_element();
        let max_yt = Vec3::new(p0t.y, p1t.y, p2t.y).abs().max_element();
        let delta_x = gamma(5) * (max_xt + max_zt);
        let delta_y = gamma(5) * (max_yt + max_zt);
        let delta_e = 2.0 * (gamma(2) * max_xt * max_yt + delta_y * max_xt + delta_x * max_yt);
        let max_e = Vec3::new(e0, e1, e2).abs().max_element();
        let delta_t =
            3.0 * (gamma(3) * max_e * max_zt + delta_e * max_zt + delta_z * max_e) * inv_det.abs();
        if t <= delta_t {
            return None;
        }
        let q = p[0] * b0 + p[1] * b1 + p[2] * b2;
        let p_error = gamma(7) * ((p[0] * b0).abs() + (p[1] * b1).abs() + (p[2] * b2).abs());
        Some(Hit {
            t,
            p: q,
            p_error,
            n: n.normalize(),
        })
    }

    /// The bits of a hit, so that −0.0 and 0.0 differ.
    fn bits(h: Option<Hit>) -> Option<[u32; 10]> {
        h.map(|h| {
            let v = [
                h.t,
                h.p.x,
                h.p.y,
                h.p.z,
                h.p_error.x,
                h.p_error.y,
                h.p_error.z,
                h.n.x,
                h.n.y,
                h.n.z,
            ];
            v.map(f32::to_bits)
        })
    }

    #[test]
    fn prepared_ray_triangle_test_is_pbrt_v4s_bit_for_bit() {
        // Random triangles (near, far from the origin, slivers, degenerate), rays through
        // their vertices, edges and interiors from either side, along and across each
        // axis: the same hit or miss, the same bits.
        let sampler = crate::sampling::Sampler::independent(31);
        let (mut hits, mut rescued) = (0, 0);
        for i in 0..50_000u64 {
            let mut st = sampler.stream(i);
            let base = [Vec3::ZERO, Vec3::new(1e5, -3e4, 7e4), Vec3::splat(-2.5)][i as usize % 3];
            let scale = 10f32.powf(-3.0 + 6.0 * st.next_1d());
            let mut v =
                || base + (Vec3::new(st.next_1d(), st.next_1d(), st.next_1d()) - 0.5) * scale;
            let mut p = [v(), v(), v()];
            match i % 11 {
                0 => p[2] = p[0] + (p[1] - p[0]) * 0.5,
                1 => p[2] = p[1],
                _ => {}
            }
            let mut st = sampler.stream(1 << 40 | i);
            let (b1, b2) = (st.next_1d(), st.next_1d());
            let target = match i % 5 {
                0 => p[(i / 5) as usize % 3],
                1 => p[0] + (p[1] - p[0]) * b1,
                _ => p[0] + (p[1] - p[0]) * b1 * (1.0 - b2) + (p[2] - p[0]) * b2,
            };
            let mut d = crate::sampling::sphere::uniform_sphere(st.next_2d());
            if i % 13 == 0 {
                d = [Vec3::X, -Vec3::Y, Vec3::Z, Vec3::new(0.6, 0.0, -0.8)][(i / 13) as usize % 4];
            }
            let o = target - d * (scale * 2.0 * st.next_1d());
            let (tmin, tmax) = if i % 4 == 0 {
                (scale * 0.5, scale)
            } else {
                (0.0, f32::INFINITY)
            };
            let want = pbrt_triangle(p, o, d, tmin, tmax);
            let got = Primitive::Triangle { p }.intersect_ray(&Ray::new(o, d), tmin, tmax);
            hits += usize::from(want.is_some());
            if let (None, Some(h)) = (want, got) {
                // A hit pbrt drops for an f32 distance within its error bound of 0: the
                // line meets the plane in front of the origin (exact in f64, the inputs
                // being f32) at that distance.
                let pd = p.map(|v| v.as_dvec3());
                let n = (pd[1] - pd[0]).cross(pd[2] - pd[0]);
                let t = (pd[0] - o.as_dvec3()).dot(n) / d.as_dvec3().dot(n);
                let scale = pd
                    .iter()
                    .map(|v| (*v - o.as_dvec3()).length())
                    .fold(0.0, f64::max);
                assert!(
                    t > 0.0 && (h.t as f64 - t).abs() <= 1e-6 * scale,
                    "{p:?} o {o:?} d {d:?}: kept at {} where the plane is at {t}",
                    h.t
                );
                // Its distance is the f64 one (an f32 distance kept inside pbrt's bound
                // would have been dropped by it), and the rest is pbrt's hit there.
                let ray = Ray::new(o, d);
                let t64 = triangle_distance_wide(&triangle_frame_wide(p, &ray)).unwrap();
                assert_eq!(h.t.to_bits(), (t64 as f32).to_bits());
                rescued += 1;
                continue;
            }
            assert_eq!(bits(got), bits(want), "{p:?} o {o:?} d {d:?}");
        }
        assert!(hits > 20_000, "{hits} hits");
        // Rays from up to 2 sizes away: a few start close enough to the plane.
        assert!(rescued > 0 && rescued < 1000, "{rescued} hits pbrt drops");
    }

    #[test]
    fn triangle_edge_is_watertight() {
        // Two triangles sharing the diagonal of the unit square: rays along the diagonal hit one.
        let a = Primitive::Triangle {
            p: [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0)],
        };
        let b = Primitive::Triangle {
            p: [Vec3::ZERO, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
        };
        for i in 1..1000 {
            let x = i as f32 / 1000.0;
            let o = Vec3::new(x, x, 1.0);
            let hit = a.intersect(o, -Vec3::Z, 0.0, f32::INFINITY).is_some()
                || b.intersect(o, -Vec3::Z, 0.0, f32::INFINITY).is_some();
            assert!(hit, "ray at {x} slipped through");
        }
    }

    #[test]
    fn sliver_triangle_hit_and_no_nan() {
        let t = Primitive::Triangle {
            p: [
                Vec3::ZERO,
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(0.5, 1e-6, 0.0),
            ],
        };
        let h = t
            .intersect(Vec3::new(0.5, 2e-7, 1.0), -Vec3::Z, 0.0, f32::INFINITY)
            .unwrap();
        assert!(h.p.is_finite() && h.n.is_finite());
        assert!(
            t.intersect(Vec3::new(0.5, 2e-6, 1.0), -Vec3::Z, 0.0, f32::INFINITY)
                .is_none()
        );
    }

    #[test]
    fn rectangle_and_disk() {
        let r = Primitive::Rectangle {
            corner: Vec3::new(-1.0, -1.0, 2.0),
            u: Vec3::X * 2.0,
            v: Vec3::Y * 2.0,
        };
        assert!(
            r.intersect(Vec3::ZERO, Vec3::Z, 0.0, f32::INFINITY)
                .is_some()
        );
        assert!((r.area() - 4.0).abs() < 1e-6);
        // A skewed parallelogram: (1.2, 0.5) is inside, (0.1, 0.5) is not.
        let s = Primitive::Rectangle {
            corner: Vec3::new(0.0, 0.0, 2.0),
            u: Vec3::X,
            v: Vec3::new(1.0, 1.0, 0.0),
        };
        assert!(
            s.intersect(Vec3::new(1.2, 0.5, 0.0), Vec3::Z, 0.0, f32::INFINITY)
                .is_some()
        );
        assert!(
            s.intersect(Vec3::new(0.1, 0.5, 0.0), Vec3::Z, 0.0, f32::INFINITY)
                .is_none()
        );
        let d = Primitive::Disk {
            center: Vec3::new(0.0, 0.0, 2.0),
            normal: -Vec3::Z,
            radius: 1.0,
        };
        let h = d
            .intersect(Vec3::new(0.99, 0.0, 0.0), Vec3::Z, 0.0, f32::INFINITY)
            .unwrap();
        assert!((h.t - 2.0).abs() < 1e-6);
        assert!(
            d.intersect(Vec3::new(1.01, 0.0, 0.0), Vec3::Z, 0.0, f32::INFINITY)
                .is_none()
        );
    }
}
