//! Irradiance (W·m⁻²) at a receiver point from uniform Lambertian emitters, and the
//! projected solid angle Ω⊥ = E / L for an emitter of uniform radiance L.
//!
//! Emitters are taken to emit towards the receiver (a two-sided emitter, or a one-sided
//! one facing the receiver). Receivers are one-sided: only light arriving from the
//! hemisphere around the receiver normal `n` counts, so every function clips the emitter
//! to that half-space.

use crate::geom::{Vec3, any_nan};
use crate::quadrature::adaptive;
use std::f64::consts::PI;

/// Irradiance from a uniform Lambertian polygon of radiance `radiance` at point `p` with
/// unit normal `n`. The polygon is planar and simple (convex or not), any winding.
///
/// **Formula** (Lambert's edge formula). With uᵢ = vᵢ − p for the polygon *clipped to
/// the half-space n·(x − p) ≥ 0*:
/// E = (L/2) |Σᵢ Θᵢ n·(uᵢ × uᵢ₊₁)/|uᵢ × uᵢ₊₁||,  Θᵢ = ∠(uᵢ, uᵢ₊₁) = atan2(|uᵢ×uᵢ₊₁|, uᵢ·uᵢ₊₁).
///
/// **Derivation.** E = L ∫ n·ω dω = L n·Φ with Φ = ∫ω dω the irradiance vector. By
/// Stokes' theorem on the unit sphere, Φ = ½ ∮ (x × dx)/|x|², which for a straight edge
/// integrates to Θᵢ times the unit normal of the plane through p and the edge. Clipping
/// first is essential: the formula integrates n·ω with its sign, so any part of the
/// emitter below the horizon would subtract.
///
/// **Source.** J. H. Lambert, *Photometria* (1760); J. Arvo, "Applications of irradiance
/// tensors to the simulation of non-Lambertian phenomena", SIGGRAPH 1995, eq. (7);
/// Siegel & Howell, contour-integral configuration factors.
///
/// A NaN in any input gives NaN.
pub fn polygon(p: Vec3, n: Vec3, vertices: &[Vec3], radiance: f64) -> f64 {
    radiance * polygon_projected_solid_angle(p, n, vertices)
}

/// Projected solid angle ∫ max(0, n·ω) dω of a polygon seen from `p` with normal `n`
/// ([`polygon`] with L = 1); NaN where any input holds a NaN (the clipping dropped a
/// NaN vertex as below the horizon, and a NaN point or normal dropped them all: 0).
pub fn polygon_projected_solid_angle(p: Vec3, n: Vec3, vertices: &[Vec3]) -> f64 {
    if any_nan(&[p, n], &[]) || any_nan(vertices, &[]) {
        return f64::NAN;
    }
    let rel: Vec<Vec3> = vertices.iter().map(|&v| v - p).collect();
    let clipped = clip_to_half_space(&rel, n);
    let m = clipped.len();
    if m < 3 {
        return 0.0;
    }
    let mut sum = 0.0;
    for i in 0..m {
        let (a, b) = (clipped[i], clipped[(i + 1) % m]);
        let c = a.cross(b);
        let cl = c.length();
        if cl == 0.0 {
            continue;
        }
        sum += cl.atan2(a.dot(b)) * n.dot(c) / cl;
    }
    0.5 * sum.abs()
}

/// Sutherland–Hodgman clipping of a polygon (given relative to the receiver) to n·x ≥ 0.
fn clip_to_half_space(poly: &[Vec3], n: Vec3) -> Vec<Vec3> {
    let mut out = Vec::with_capacity(poly.len() + 2);
    let m = poly.len();
    for i in 0..m {
        let (a, b) = (poly[i], poly[(i + 1) % m]);
        let (da, db) = (n.dot(a), n.dot(b));
        if da >= 0.0 {
            out.push(a);
        }
        if (da >= 0.0) != (db >= 0.0) {
            let t = da / (da - db);
            let x = a + (b - a) * t;
            // Put the crossing exactly on the horizon plane.
            out.push(x - n * n.dot(x));
        }
    }
    out
}

/// Irradiance on axis from a uniform disk of radius R at distance h, receiver facing it.
///
/// **Formula.** E = π L sin²θ = π L R² / (R² + h²), θ the disk's angular radius.
///
/// **Derivation.** E = L ∫₀^{2π}∫₀^θ cos θ' sin θ' dθ' dφ = π L sin²θ.
///
/// **Source.** Howell's catalog, case B-13 family (element to coaxial parallel disk,
/// F = R²/(R²+h²)); pbrt 4th ed. §4.2 (irradiance from a disk).
pub fn disk_on_axis(radius: f64, height: f64, radiance: f64) -> f64 {
    // π L/(1 + (h/R)²): no R² to overflow (R = h = 10²⁰⁰ gave NaN for π L/2).
    let q = height / radius;
    PI * radiance / (1.0 + q * q)
}

/// Irradiance from a uniform disk of radius `r` at a receiver parallel to the disk, at
/// height `h` above the disk plane and lateral offset `a` from the disk axis.
///
/// **Formula.** E = π L F with
/// F = ½ [1 − (a² + h² − r²)/√Y],  Y = ((a−r)² + h²)((a+r)² + h²),
/// evaluated as F = 2 r² h² / (√Y (√Y + a² + h² − r²)) when a² + h² > r² (no cancellation
/// for small or distant disks; the two forms are equal since Y − (a²+h²−r²)² = 4r²h²).
///
/// **Derivation.** Contour form of [`polygon`] for the circle x(φ) = (a + r cos φ, r sin φ, h):
/// Φ_z = (L/2)∫ r(a cos φ + r)/(A + B cos φ) dφ with A = a²+r²+h², B = 2ar, and the
/// elementary integrals ∫dφ/(A+B cos φ) = 2π/√(A²−B²), Y = A² − B².
///
/// **Source.** Howell's catalog, "plane element to parallel disk, element offset from
/// the axis" (section B); Siegel & Howell, *Thermal Radiation Heat Transfer*, App. C.
pub fn disk_parallel_offset(radius: f64, height: f64, offset: f64, radiance: f64) -> f64 {
    let (parallel, _) = disk_vector_components(radius, height.abs(), offset.abs());
    PI * radiance * parallel
}

/// Components of the irradiance vector (divided by π L) of a whole disk of radius `r` at
/// a point at height `h ≥ 0` above the disk plane and distance `a ≥ 0` from its axis:
/// (towards the disk plane, towards the axis).
///
/// The axial one is the parallel-element factor of [`disk_parallel_offset`]; the radial
/// one is F⊥ = (h/2a)[(a²+h²+r²)/√Y − 1] = 2 a h r² / (√Y (√Y + a²+h²+r²)), from
/// Φ_x = −(L h r/2)∫ cos φ/(A + B cos φ) dφ. F⊥ is Howell's "plane element perpendicular
/// to a disk" factor (valid as stated there when a > r; as a vector component it holds
/// for every a).
fn disk_vector_components(r: f64, h: f64, a: f64) -> (f64, f64) {
    let y = (((a - r) * (a - r) + h * h) * ((a + r) * (a + r) + h * h)).sqrt();
    let x = a * a + h * h - r * r;
    let parallel = if x > 0.0 {
        2.0 * r * r * h * h / (y * (y + x))
    } else {
        0.5 * (1.0 - x / y)
    };
    let radial = 2.0 * a * h * r * r / (y * (y + a * a + h * h + r * r));
    (parallel, radial)
}

/// Irradiance from a uniform disk (centre `center`, unit axis `axis`, `radius`) at a
/// receiver `p` with unit normal `n` in any orientation, including receivers whose
/// horizon cuts the disk.
///
/// **Formula.** When the whole disk is above the receiver's horizon,
/// E = π L n·(F∥ ẑ + F⊥ ρ̂), with ẑ the unit vector from p towards the disk plane along
/// the axis, ρ̂ the unit vector from p's foot towards the axis, and F∥, F⊥ the closed
/// forms of [`disk_parallel_offset`] and Howell's perpendicular-element factor (the
/// irradiance vector is linear in n while nothing is clipped). Entirely below: E = 0.
///
/// When the horizon cuts the disk there is no elementary closed form (Howell's catalog
/// treats only special placements); E is then the *exact* contour integral
/// E = (L/2) |∫_arc n·(x × x′)/|x|² dφ + Θ_chord n·(x_b × x_a)/|x_b × x_a|| over the arc
/// of the rim above the horizon, closed by the chord x_b → x_a along the horizon (which,
/// lying in the receiver's plane, contributes its full angle Θ_chord = ∠(x_a, x_b)); the
/// arc term is a smooth 1-D integral evaluated by adaptive Gauss–Legendre to ~1e-14
/// relative.
///
/// **Source.** Howell's catalog (section B, disk cases); Arvo 1995 (contour form).
///
/// A NaN in any input gives NaN (a NaN radiance came out 0 through the clamp to ≥ 0 and
/// the early return of a disk below the horizon).
pub fn disk(p: Vec3, n: Vec3, center: Vec3, axis: Vec3, radius: f64, radiance: f64) -> f64 {
    if any_nan(&[p, n, center, axis], &[radius, radiance]) {
        return f64::NAN;
    }
    let m = axis;
    let w = center - p; // from receiver to disk centre
    let k = n.dot(w);
    let n_in_plane = n - m * n.dot(m);
    let q = n_in_plane.length();
    if k - radius * q >= 0.0 {
        // Whole disk visible.
        let h_signed = w.dot(m); // component of (centre − p) along m
        let z_hat = if h_signed >= 0.0 { m } else { -m };
        let radial = w - m * h_signed; // from p's foot to the centre, in the plane
        let a = radial.length();
        let (fpar, fperp) = disk_vector_components(radius, h_signed.abs(), a);
        let rho_hat = radial.normalized().unwrap_or_default();
        let e = PI * radiance * (fpar * n.dot(z_hat) + fperp * n.dot(rho_hat));
        return e.max(0.0);
    }
    if k + radius * q <= 0.0 {
        return 0.0;
    }
    // Straddling: contour integral over the visible arc.
    let (e1, e2) = m.orthonormal_basis();
    let phi0 = n.dot(e2).atan2(n.dot(e1));
    let beta = (-k / (radius * q)).clamp(-1.0, 1.0).acos();
    let integrand = |phi: f64| {
        let (s, c) = phi.sin_cos();
        let x = w + (e1 * c + e2 * s) * radius;
        let dx = (e1 * -s + e2 * c) * radius;
        n.dot(x.cross(dx)) / x.length_squared()
    };
    // The integrand peaks where the rim passes nearest the receiver, over a width of
    // their distance: the arc is split there, so the adaptive rule starts at the peak
    // (on the whole arc it missed it for a receiver 10⁻⁶ from the rim: 0.99% high).
    let foot = -(w - m * w.dot(m));
    let near = foot.dot(e2).atan2(foot.dot(e1));
    let near = phi0 + (near - phi0 + PI).rem_euclid(2.0 * PI) - PI;
    let arc = if (near - phi0).abs() < beta {
        adaptive(integrand, phi0 - beta, near, 1e-14)
            + adaptive(integrand, near, phi0 + beta, 1e-14)
    } else {
        adaptive(integrand, phi0 - beta, phi0 + beta, 1e-14)
    };
    let at = |phi: f64| w + (e1 * phi.cos() + e2 * phi.sin()) * radius;
    let (xa, xb) = (at(phi0 - beta), at(phi0 + beta));
    let c = xb.cross(xa);
    let cl = c.length();
    let chord = if cl > 0.0 {
        cl.atan2(xb.dot(xa)) * n.dot(c) / cl
    } else {
        0.0
    };
    0.5 * radiance * (arc + chord).abs()
}

/// Irradiance from a uniform sphere of radius `radius` centred at `center` at a receiver
/// `p` with unit normal `n`, including the case where the horizon cuts the sphere.
///
/// **Formula.** With sin σ = R/d (d = |c − p|), cos θ = n·(c − p)/d:
/// - cos θ ≥ sin σ (all above the horizon): E = π L sin²σ cos θ;
/// - cos θ ≤ −sin σ (all below): E = 0;
/// - otherwise, with x = cot σ = √(1/sin²σ − 1), y = −x cot θ:
///   E = L [ (cos θ acos y − x sin θ √(1−y²)) sin²σ + atan(sin θ √(1−y²) / x) ].
///
/// **Derivation.** A sphere seen from outside is a cap of half-angle σ, so E is L times
/// the projected solid angle of a cap, clipped by the horizon plane. Integrating cos θ'
/// over the cap ∩ upper hemisphere (e.g. by the contour form of [`polygon`], the cap's
/// boundary being a small circle and the clipped piece a great-circle arc) gives the
/// expression above.
///
/// **Source.** J. Snyder, "Area light sources for real-time graphics", Microsoft
/// Research MSR-TR-96-11, 1996; in this form S. Lagarde & C. de Rousiers, "Moving
/// Frostbite to physically based rendering", SIGGRAPH 2014 course, eq. (19)–(20).
///
/// A NaN in any input gives NaN ([`cap_projected_solid_angle`]).
pub fn sphere(p: Vec3, n: Vec3, center: Vec3, radius: f64, radiance: f64) -> f64 {
    let w = center - p;
    let d = w.length();
    let sin2 = (radius / d) * (radius / d);
    let cos_t = (n.dot(w) / d).clamp(-1.0, 1.0);
    radiance * cap_projected_solid_angle(cos_t, sin2)
}

/// Projected solid angle of a cap of angular radius σ (given sin²σ) whose axis makes
/// angle θ (given cos θ) with the receiver normal; see [`sphere`]. NaN for a NaN input
/// (the comparisons below fail for NaN, and the final clamp to ≥ 0 made it 0).
pub fn cap_projected_solid_angle(cos_theta: f64, sin2_sigma: f64) -> f64 {
    if cos_theta.is_nan() || sin2_sigma.is_nan() {
        return f64::NAN;
    }
    let sin_sigma = sin2_sigma.sqrt();
    if cos_theta >= sin_sigma {
        return PI * sin2_sigma * cos_theta;
    }
    if cos_theta <= -sin_sigma {
        return 0.0;
    }
    let sin_theta = ((1.0 - cos_theta) * (1.0 + cos_theta)).sqrt();
    let x = ((1.0 - sin2_sigma) / sin2_sigma).sqrt();
    let y = (-x * cos_theta / sin_theta).clamp(-1.0, 1.0);
    let st_sqrt_y = sin_theta * ((1.0 - y) * (1.0 + y)).sqrt();
    let e = (cos_theta * y.acos() - x * st_sqrt_y) * sin2_sigma + st_sqrt_y.atan2(x);
    e.max(0.0)
}

/// Irradiance at a receiver `p` (outside the sphere) with unit normal `n` from the outer
/// side of a uniform Lambertian spherical cap: the part of the sphere of centre `center`
/// and radius R = `radius` with (y − c)·a ≥ R cos θmax (`axis` a, unit; `theta_max` θmax
/// in radians, in (0, π]; θmax = π is the whole sphere), emitting only outwards, so that
/// its inside, seen through the hole, sends nothing to p.
///
/// **Formula** (the contour form of [`polygon`] and [`disk`]). In units of R about the
/// centre, P = (p − c)/R (E is scale-free), the part of the cap that p sees lit and above
/// its horizon is an intersection of three caps of the unit sphere,
/// S = {y : |y| = 1, P·y ≥ 1 (in front of the silhouette), a·y ≥ cos θmax (on the cap),
/// n·y ≥ n·P (above the receiver's plane)},
/// bounded by arcs of their circles aₖ·y = bₖ, each met anticlockwise about aₖ as
/// y(t) = bₖ aₖ + rₖ (uₖ cos t + wₖ sin t), rₖ = √(1 − bₖ²), (uₖ, wₖ, aₖ) right-handed.
/// With x = y(t) − P,
/// E = −(L/2) Σ_arcs ∫ n·(x × x′)/|x|² dt,
/// the arcs being the pieces of each circle between its crossings with the others whose
/// midpoints lie in the other two caps (none: S is empty and E = 0). Per circle:
/// - silhouette (P·y = 1; every point at the tangent length √(|P|² − 1) from p, a circle
///   of angular radius σ, sin σ = 1/|P|, about −P̂ in p's view): exactly
///   ∫ = sin σ cos σ [n·u (sin t₁ − sin t₀) + n·w (cos t₀ − cos t₁)] + sin²σ (t₁ − t₀) n·P̂;
/// - receiver's plane (n·y = n·P; the plane holds p, so x × x′ ∥ n): exactly the angle
///   the arc subtends at p, signed about n, ∫ = atan2(n·(x₀ × x₁), x₀·x₁) (p lies outside
///   this circle, which therefore subtends less than π);
/// - rim (a·y = cos θmax): a smooth 1-D integral, by adaptive Gauss–Legendre to ~1e-14
///   relative, in the angle t from the rim point nearest p, split there and at |t| growing
///   by 4 from the peak's width (p's distance to the rim over √(R ρ), ρ its distance from
///   the axis), as in [`disk`].
///
/// **Derivation.** E = L ∫ max(0, n·ω) dω over the directions ω from p that meet S.
/// S lies in front of the silhouette, so it maps one-to-one onto its image on p's sphere
/// of directions, and above the receiver's plane, where max(0, n·ω) = n·ω; so E = L n·Φ,
/// Φ = ∫ ω dω = ½ ∮ ω × dω (Stokes' theorem on the unit sphere), and ω × dω =
/// (x × dx)/|x|². A boundary met anticlockwise about the outward normal (S on its left
/// seen from outside) turns clockwise about S's image seen from p: hence the minus sign.
/// The silhouette, seen from p, is ω(t) = −cos σ P̂ + sin σ (u cos t + w sin t), whose
/// ω × ω′ = sin σ cos σ (u cos t + w sin t) + sin²σ P̂ integrates to the form above. With
/// no rim (θmax = π) this is Snyder's whole sphere, [`sphere`].
///
/// The crossings of circles i and j solve A cos t + B sin t = C on circle i, with
/// √(A² + B²) = rᵢ √(1 − g²), C = bⱼ − bᵢ g, g = aᵢ·aⱼ: t = atan2(B, A) ± atan2(√D, C),
/// D = rᵢ² rⱼ² − (g − bᵢ bⱼ)², solved on the first of the two circles (the silhouette,
/// else the rim); the second circle's angle is read from that point, so that the
/// contour closes (also for circles crossing at a grazing angle).
/// Near the sphere every term is formed without cancellation: |P|² − 1 by error-free
/// products; for the silhouette g − bᵢ bⱼ = (P·aⱼ − bⱼ)/|P| (exactly 0 against the
/// receiver's plane, which crosses it wherever it cuts the sphere); the rim's angle
/// counted from its point nearest p; the corners' offsets x from p taken from the
/// silhouette's or the rim's parametrisation. A receiver 4·10⁻⁶ R from the sphere has a
/// silhouette 2.8·10⁻³ R across, which the rim may cross: there E keeps ~2·10⁻¹² of
/// the exact value for its rounded inputs, the rest being lost to the last bit of
/// cos θmax and sin θmax, to which E is ~5·10⁵ times as sensitive.
///
/// **Source.** J. Arvo, "Applications of irradiance tensors to the simulation of
/// non-Lambertian phenomena", SIGGRAPH 1995 (the irradiance vector as a contour
/// integral); J. H. Lambert, *Photometria* (1760); Siegel & Howell, *Thermal Radiation
/// Heat Transfer*, contour-integral configuration factors; J. Snyder, "Area light sources
/// for real-time graphics", MSR-TR-96-11 (1996), for the whole sphere.
pub fn spherical_cap(
    p: Vec3,
    n: Vec3,
    center: Vec3,
    axis: Vec3,
    radius: f64,
    theta_max: f64,
    radiance: f64,
) -> f64 {
    radiance * spherical_cap_projected_solid_angle(p, n, center, axis, radius, theta_max)
}

/// Projected solid angle ∫ max(0, n·ω) dω of the outer side of a spherical cap seen from
/// `p` ([`spherical_cap`] with L = 1). 0 for a point on or inside the sphere (which sees
/// only the inner side) and for θmax ≤ 0; NaN where any input is NaN (never masked as a
/// dark receiver).
pub fn spherical_cap_projected_solid_angle(
    p: Vec3,
    n: Vec3,
    center: Vec3,
    axis: Vec3,
    radius: f64,
    theta_max: f64,
) -> f64 {
    if any_nan(&[p, n, center, axis], &[radius, theta_max]) {
        return f64::NAN;
    }
    if theta_max <= 0.0 {
        return 0.0;
    }
    let w = p - center;
    // |P|² − 1, the gap's digits kept.
    let excess = length_squared_minus(w, radius) / (radius * radius);
    if excess.is_nan() || excess <= 0.0 {
        return 0.0;
    }
    let big_p = w * (1.0 / radius);
    let view = CapView {
        p: big_p,
        excess,
        dist2: 1.0 + excess,
        dist: (1.0 + excess).sqrt(),
    };
    let Some(p_hat) = w.normalized() else {
        return 0.0;
    };
    let np = n.dot(big_p);
    if np >= 1.0 {
        // The receiver's plane leaves the sphere behind it.
        return 0.0;
    }
    // In this order (silhouette, rim, receiver's plane): `crossings` solves each crossing
    // on the earlier of its two circles.
    let mut circles = vec![SphereCircle::silhouette(p_hat, &view)];
    if theta_max < PI {
        circles.push(SphereCircle::rim(axis, theta_max, big_p));
    }
    if np > -1.0 {
        circles.push(SphereCircle::receiver_plane(n, big_p));
    }
    // The same circle twice (the rim as the silhouette, for p on the axis at R/cos θmax;
    // the receiver's plane as the rim's) bounds nothing new: keep one. Opposite caps on
    // one circle leave only the circle.
    let mut k = 0;
    while k < circles.len() {
        let (ck, mut dup) = (circles[k], false);
        for c in &circles[..k] {
            let close =
                |s: f64| (c.a - ck.a * s).length() <= 1e-12 && (c.b - ck.b * s).abs() <= 1e-12;
            if close(-1.0) {
                return 0.0;
            }
            dup |= close(1.0);
        }
        if dup {
            circles.remove(k);
        } else {
            k += 1;
        }
    }
    // The corners: each crossing's angle on both circles, and its offset from P.
    let m = circles.len();
    let mut corners: Vec<Vec<Corner>> = vec![Vec::new(); m];
    for i in 0..m {
        for j in i + 1..m {
            for (ti, tj, x) in crossings(&circles[i], &circles[j], &view) {
                corners[i].push(Corner { t: ti, x });
                corners[j].push(Corner { t: tj, x });
            }
        }
    }
    let mut total = 0.0;
    for (i, c) in circles.iter().enumerate() {
        let cs = &mut corners[i];
        cs.sort_by(|a, b| a.t.total_cmp(&b.t));
        // Arcs between consecutive corners, angles in (−π, π]; t1 < t0 for the one
        // through ±π. No corners: the whole circle.
        let arcs: Vec<(Corner, Corner)> = match (cs.first(), cs.last()) {
            (Some(&first), Some(&last)) => cs
                .windows(2)
                .map(|ab| (ab[0], ab[1]))
                .chain([(last, first)])
                .collect(),
            _ => {
                let whole = |t| Corner { t, x: c.offset(t) };
                vec![(whole(-PI), whole(PI))]
            }
        };
        for (c0, c1) in arcs {
            let (t0, t1) = (c0.t, c1.t);
            let len = if t1 >= t0 {
                t1 - t0
            } else {
                t1 - t0 + 2.0 * PI
            };
            if len <= 0.0 {
                continue;
            }
            let mid = c.at(t0 + 0.5 * len);
            let inside = circles
                .iter()
                .enumerate()
                .all(|(j, o)| j == i || o.a.dot(mid) >= o.b);
            if !inside {
                continue;
            }
            total += match c.kind {
                CapCircle::Silhouette => c.silhouette_arc(n, t0, t0 + len),
                CapCircle::ReceiverPlane => {
                    let (x0, x1) = (c0.x, c1.x);
                    n.dot(x0.cross(x1)).atan2(x0.dot(x1))
                }
                CapCircle::Rim if t1 >= t0 => c.rim_arc(n, t0, t1),
                CapCircle::Rim => c.rim_arc(n, t0, PI) + c.rim_arc(n, -PI, t1),
            };
        }
    }
    (-0.5 * total).max(0.0)
}

/// |w|² − r² by error-free products and sums (Ogita, Rump & Oishi 2005, "Dot2"): the gap
/// of a point 10⁻⁶ r from a sphere keeps its digits.
fn length_squared_minus(w: Vec3, r: f64) -> f64 {
    let (mut s, mut err) = (0.0f64, 0.0f64);
    for (a, b) in [(w.x, w.x), (w.y, w.y), (w.z, w.z), (r, -r)] {
        let prod = a * b;
        let prod_err = a.mul_add(b, -prod);
        let t = s + prod;
        let z = t - s;
        err += (s - (t - z)) + (prod - z) + prod_err;
        s = t;
    }
    s + err
}

/// The receiver in units of the radius about the centre: P, |P|² − 1 (formed without
/// cancellation), |P|², |P|.
struct CapView {
    p: Vec3,
    excess: f64,
    dist2: f64,
    dist: f64,
}

/// Which circle of the unit sphere an arc of a cap's visible part lies on
/// ([`spherical_cap`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum CapCircle {
    /// P·y = 1: the sphere's silhouette seen from the receiver.
    Silhouette,
    /// a·y = cos θmax: the cap's rim.
    Rim,
    /// n·y = n·P: where the receiver's plane cuts the sphere.
    ReceiverPlane,
}

/// A corner of the visible region: its angle on one circle and its offset x = y − P.
#[derive(Debug, Clone, Copy)]
struct Corner {
    t: f64,
    x: Vec3,
}

/// The circle {y : |y| = 1, a·y = b} bounding the cap a·y ≥ b of the unit sphere, with
/// r² = 1 − b² formed without cancellation, (u, w, a) right-handed, and P relative to
/// the circle's plane: `depth` = b − P·a, `rho` = P·u (each 0 where it vanishes by
/// construction, so that offsets from P keep their digits).
#[derive(Debug, Clone, Copy)]
struct SphereCircle {
    kind: CapCircle,
    a: Vec3,
    b: f64,
    r: f64,
    r2: f64,
    u: Vec3,
    w: Vec3,
    depth: f64,
    rho: f64,
}

impl SphereCircle {
    /// P·y = 1: b = 1/|P|, r² = (|P|² − 1)/|P|², b − |P| = −(|P|² − 1)/|P|.
    fn silhouette(p_hat: Vec3, v: &CapView) -> Self {
        let (u, w) = p_hat.orthonormal_basis();
        let r2 = v.excess / v.dist2;
        Self {
            kind: CapCircle::Silhouette,
            a: p_hat,
            b: 1.0 / v.dist,
            r: r2.sqrt(),
            r2,
            u,
            w,
            depth: -v.excess / v.dist,
            rho: 0.0,
        }
    }

    /// a·y = cos θmax, its angle counted from the rim point nearest P (u towards P).
    fn rim(axis: Vec3, theta_max: f64, big_p: Vec3) -> Self {
        let (s, c) = theta_max.sin_cos();
        let pa = big_p.dot(axis);
        let across = big_p - axis * pa;
        // Orthogonalised again: for P (nearly) on the axis `across` is rounding noise.
        let (u, w, rho) = match (across - axis * across.dot(axis)).normalized() {
            Some(u) => (u, axis.cross(u), across.length()),
            None => {
                let (u, w) = axis.orthonormal_basis();
                (u, w, 0.0)
            }
        };
        Self {
            kind: CapCircle::Rim,
            a: axis,
            b: c,
            r: s,
            r2: s * s,
            u,
            w,
            depth: c - pa,
            rho,
        }
    }

    /// n·y = n·P: the plane holds P (depth 0).
    fn receiver_plane(n: Vec3, big_p: Vec3) -> Self {
        let (u, w) = n.orthonormal_basis();
        let b = n.dot(big_p);
        let r2 = (1.0 - b) * (1.0 + b);
        Self {
            kind: CapCircle::ReceiverPlane,
            a: n,
            b,
            r: r2.sqrt(),
            r2,
            u,
            w,
            depth: 0.0,
            rho: big_p.dot(u),
        }
    }

    fn at(&self, t: f64) -> Vec3 {
        let (s, c) = t.sin_cos();
        self.a * self.b + (self.u * c + self.w * s) * self.r
    }

    /// y(t) − P = depth a + (r cos t − ρ) u + r sin t w, with
    /// r cos t − ρ = (r − ρ) − 2r sin²(t/2), for P in the half-plane of a and u (P·w = 0:
    /// the silhouette and the rim). Of the receiver's plane only its whole circle's ends
    /// are taken, one point twice, whose arc subtends 0 at p whatever the point.
    fn offset(&self, t: f64) -> Vec3 {
        let h = (0.5 * t).sin();
        let along = (self.r - self.rho) - 2.0 * self.r * h * h;
        self.a * self.depth + self.u * along + self.w * (self.r * t.sin())
    }

    /// The angle in (−π, π] of a point of (or next to) the circle.
    fn angle_of(&self, y: Vec3) -> f64 {
        y.dot(self.w).atan2(y.dot(self.u))
    }

    /// For a crossing with `other` (not the silhouette): g − b b′ (g = a·a′), and C of
    /// A cos t + B sin t = C on the silhouette, without the cancellations of the generic
    /// forms when P is near the sphere.
    fn silhouette_terms(other: &Self, v: &CapView) -> (f64, f64) {
        let pa = v.p.dot(other.a);
        match other.kind {
            // b′ = P·n: C = n·P (1 − 1/|P|²).
            CapCircle::ReceiverPlane => (0.0, other.b * v.excess / v.dist2),
            CapCircle::Rim | CapCircle::Silhouette => {
                ((pa - other.b) / v.dist, other.b - pa / v.dist2)
            }
        }
    }

    /// ∫ n·(x × x′)/|x|² dt over [t0, t1] of the silhouette, in closed form (sin σ = b,
    /// cos σ = r).
    fn silhouette_arc(&self, n: Vec3, t0: f64, t1: f64) -> f64 {
        let sh = (0.5 * (t1 - t0)).sin();
        let (sm, cm) = (0.5 * (t0 + t1)).sin_cos();
        // sin t1 − sin t0 and cos t0 − cos t1.
        let (d_sin, d_cos) = (2.0 * cm * sh, 2.0 * sm * sh);
        self.b * self.r * (n.dot(self.u) * d_sin + n.dot(self.w) * d_cos)
            + self.b * self.b * (t1 - t0) * n.dot(self.a)
    }

    /// ∫ n·(x × x′)/|x|² dt over [t0, t1] ⊂ [−π, π] of the rim, x = y(t) − P, by adaptive
    /// Gauss–Legendre, t counted from the rim point nearest P (u towards P). With
    /// ρ = P·u, d = b − P·a and s = sin(t/2):
    /// n·(x × x′) = r[−d (nᵤ cos t + n_w sin t) + nₐ((r − ρ) + 2ρ s²)],
    /// |x|² = (r − ρ)² + 4rρ s² + d², free of cancellation at the peak, t = 0.
    fn rim_arc(&self, n: Vec3, t0: f64, t1: f64) -> f64 {
        let (nu, nw, na) = (n.dot(self.u), n.dot(self.w), n.dot(self.a));
        let (r, rho, d) = (self.r, self.rho, self.depth);
        let gap = r - rho;
        let f = |t: f64| {
            let (s, c) = t.sin_cos();
            let h = (0.5 * t).sin();
            let h2 = h * h;
            let num = -d * (nu * c + nw * s) + na * (gap + 2.0 * rho * h2);
            r * num / (gap * gap + 4.0 * r * rho * h2 + d * d)
        };
        let mut cuts = vec![t0, t1];
        // Half-width of the peak: P's distance to the rim over √(rρ).
        let width = gap.hypot(d) / (r * rho).sqrt();
        if width > 0.0 && width < PI {
            let mut s = width;
            while s < PI {
                cuts.extend([-s, s].into_iter().filter(|&t| t > t0 && t < t1));
                s *= 4.0;
            }
            if t0 < 0.0 && t1 > 0.0 {
                cuts.push(0.0);
            }
        }
        cuts.sort_by(f64::total_cmp);
        cuts.windows(2)
            .map(|ab| adaptive(f, ab[0], ab[1], 1e-14))
            .sum()
    }
}

/// The crossings of two circles, `ci` the earlier in the order silhouette, rim,
/// receiver's plane: (angle on `ci`, angle on `cj`, offset from P) of each.
///
/// On circle i, aⱼ·y(t) = bⱼ reads A cos t + B sin t = C with √(A² + B²) = rᵢ √(1 − g²),
/// C = bⱼ − bᵢ g, so t = atan2(B, A) ± atan2(√D, C), D = rᵢ² rⱼ² − (g − bᵢ bⱼ)². The
/// angle is solved on `ci` (the silhouette, else the rim), whose offsets keep their
/// digits near P and give the offset; the angle on `cj` is read from that point, so the
/// contour closes even where the circles cross at a grazing angle.
fn crossings(ci: &SphereCircle, cj: &SphereCircle, v: &CapView) -> Vec<(f64, f64, Vec3)> {
    let (g_minus, c_i) = match ci.kind {
        CapCircle::Silhouette => SphereCircle::silhouette_terms(cj, v),
        CapCircle::Rim | CapCircle::ReceiverPlane => {
            let g = ci.a.dot(cj.a);
            (g - ci.b * cj.b, cj.b - ci.b * g)
        }
    };
    let d = ci.r2 * cj.r2 - g_minus * g_minus;
    if d.is_nan() || d <= 0.0 {
        return Vec::new();
    }
    let phi = cj.a.dot(ci.w).atan2(cj.a.dot(ci.u));
    let half = d.sqrt().atan2(c_i);
    let wrap = |t: f64| {
        if t > PI {
            t - 2.0 * PI
        } else if t <= -PI {
            t + 2.0 * PI
        } else {
            t
        }
    };
    [1.0, -1.0]
        .into_iter()
        .map(|sign| {
            let ti = wrap(phi + sign * half);
            (ti, cj.angle_of(ci.at(ti)), ci.offset(ti))
        })
        .collect()
}

/// Irradiance from an isotropic point light of intensity I (W·sr⁻¹) at `light` on a
/// receiver `p` with unit normal `n`.
///
/// **Formula.** E = I max(0, cos θ) / r² (inverse-square cosine law).
///
/// **Derivation.** The point subtends dω = dA cos θ / r² of the receiver's view; the
/// flux I dω spreads over dA.
///
/// **Source.** pbrt 4th ed. §4.1.3 / §12.1; Born & Wolf §4.8 (photometry).
///
/// A NaN in any input gives NaN (a NaN normal came out 0 through max(0, cos θ)).
pub fn point(p: Vec3, n: Vec3, light: Vec3, intensity: f64) -> f64 {
    if any_nan(&[p, n, light], &[intensity]) {
        return f64::NAN;
    }
    let w = light - p;
    let r2 = w.length_squared();
    intensity * (n.dot(w) / r2.sqrt()).max(0.0) / r2
}

/// Irradiance from a spot light at `light` of intensity I on its axis `axis` (unit, the
/// direction it shines), full within the half-angle `falloff_start` and falling smoothly
/// to 0 at `cone_angle` (radians), on a receiver `p` with unit normal `n`.
///
/// **Formula.** E = I s(θ) max(0, cos θr)/r², where θ is the angle between `axis` and
/// p − light and s is pbrt-v4's smoothstep in cos θ: t = (cos θ − cos θt)/(cos θs −
/// cos θt) clamped to [0, 1], s = t²(3 − 2t); a hard edge (s = 1 up to θt, 0 beyond)
/// where θs = θt.
///
/// **Derivation.** A spot light is a point light whose intensity varies with direction,
/// I(θ) = I s(θ); the inverse-square cosine law of [`point`] applies to I(θ). Here
/// 1 − cos θ is formed as 2 sin²(θ/2) from the angle, so cones a fraction of a degree
/// wide keep their digits.
///
/// **Source.** Pharr, Jakob & Humphreys, pbrt 4th ed. §12.1.2 (`SpotLight`, its
/// `SmoothStep` falloff); Nicodemus 1963 for I cos θ/r².
///
/// A NaN in any input gives NaN (with a hard edge a NaN angle to the axis fell outside
/// the cone: 0).
pub fn spot(
    p: Vec3,
    n: Vec3,
    light: Vec3,
    axis: Vec3,
    intensity: f64,
    cone_angle: f64,
    falloff_start: f64,
) -> f64 {
    if any_nan(
        &[p, n, light, axis],
        &[intensity, cone_angle, falloff_start],
    ) {
        return f64::NAN;
    }
    let w = p - light;
    let theta = axis.angle_between(w);
    let omc = crate::radiometry::one_minus_cos;
    let (o, ot, os) = (omc(theta), omc(cone_angle), omc(falloff_start));
    let s = if os >= ot {
        if o <= ot { 1.0 } else { 0.0 }
    } else {
        let t = ((ot - o) / (ot - os)).clamp(0.0, 1.0);
        t * t * (3.0 - 2.0 * t)
    };
    point(p, n, light, intensity * s)
}

/// Irradiance from a constant environment of radiance L over the upper hemisphere.
///
/// **Formula.** E = π L. **Derivation.** ∫ cos θ dω over the hemisphere = π.
/// **Source.** pbrt 4th ed. §4.2.
pub fn constant_environment(radiance: f64) -> f64 {
    PI * radiance
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::{assert_nan_in_each, vec_at};
    use crate::quadrature::adaptive_2d;

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs().max(1e-300)
    }

    /// E = L ∫ max(0, n·u) (m·(−u)) / |x − p|² dA over the disk, polar coordinates on the
    /// disk, with the azimuth range restricted to the part above the horizon and the radial
    /// range split where the horizon starts cutting the circles (so every piece is smooth).
    fn disk_by_area(p: Vec3, n: Vec3, c: Vec3, m: Vec3, r: f64) -> f64 {
        let (e1, e2) = m.orthonormal_basis();
        let w = c - p;
        let k = n.dot(w);
        let (n1, n2) = (n.dot(e1), n.dot(e2));
        let q = n1.hypot(n2);
        let phi0 = n2.atan2(n1);
        let half_width = move |rho: f64| {
            if rho * q <= k.abs() {
                if k >= 0.0 { PI } else { 0.0 }
            } else {
                (-k / (rho * q)).clamp(-1.0, 1.0).acos()
            }
        };
        let f = |rho: f64, phi: f64| {
            let (s, co) = phi.sin_cos();
            let x = w + (e1 * co + e2 * s) * rho;
            let d2 = x.length_squared();
            let d = d2.sqrt();
            let cos_r = n.dot(x) / d;
            let cos_e = m.dot(x).abs() / d;
            cos_r.max(0.0) * cos_e / d2 * rho
        };
        let split = if q > 0.0 { (k.abs() / q).min(r) } else { r };
        let mut total = 0.0;
        for (lo, hi) in [(0.0, split), (split, r)] {
            if hi > lo {
                total += adaptive_2d(
                    f,
                    lo,
                    hi,
                    |rho| phi0 - half_width(rho),
                    |rho| phi0 + half_width(rho),
                    1e-11,
                );
            }
        }
        total
    }

    #[test]
    fn disk_on_axis_and_offset_match_quadrature() {
        let z = Vec3::new(0.0, 0.0, 1.0);
        for (r, h, a) in [
            (1.0, 2.0, 0.0),
            (1.0, 0.5, 0.7),
            (0.3, 2.0, 3.0),
            (1.0, 1e-3, 0.5),
            (2.0, 1.0, 2.0),
        ] {
            let p = Vec3::new(a, 0.0, 0.0);
            let q = disk_by_area(p, z, Vec3::new(0.0, 0.0, h), z, r);
            assert!(
                rel(disk_parallel_offset(r, h, a, 1.0), q) < 1e-8,
                "r={r} h={h} a={a}"
            );
            assert!(rel(disk(p, z, Vec3::new(0.0, 0.0, h), z, r, 1.0), q) < 1e-8);
            if a == 0.0 {
                assert!(rel(disk_on_axis(r, h, 1.0), q) < 1e-8);
            }
        }
        // Tiny disk far away: point-source limit E = L π r² / h².
        let e = disk_on_axis(1e-3, 1e3, 2.0);
        assert!(rel(e, 2.0 * PI * 1e-12) < 1e-11);
    }

    #[test]
    fn tilted_disk_matches_quadrature() {
        let m = Vec3::new(0.3, -0.2, 1.0).normalized().unwrap();
        let c = Vec3::new(0.4, 0.1, 1.5);
        for n in [
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.5, 0.2, 1.0).normalized().unwrap(),
            // Horizon cuts the disk.
            Vec3::new(1.0, 0.0, 0.2).normalized().unwrap(),
            Vec3::new(-1.0, 0.3, 0.1).normalized().unwrap(),
            // Grazing.
            Vec3::new(0.0, 1.0, 1e-3).normalized().unwrap(),
        ] {
            let p = Vec3::new(0.0, 0.0, 0.0);
            let q = disk_by_area(p, n, c, m, 1.0);
            let got = disk(p, n, c, m, 1.0, 1.0);
            assert!(rel(got, q) < 1e-8, "n={n:?}: {got} vs {q}");
            // The same through the polygon formula on a fine regular 4096-gon is close
            // (polygon area deficit ~ (2π/N)²/6 relative).
            let (e1, e2) = m.orthonormal_basis();
            let nn = 4096;
            let poly: Vec<Vec3> = (0..nn)
                .map(|i| {
                    let t = 2.0 * PI * i as f64 / nn as f64;
                    c + (e1 * t.cos() + e2 * t.sin())
                })
                .collect();
            assert!(rel(polygon(p, n, &poly, 1.0), q) < 1e-5);
            // Far from the origin.
            let off = Vec3::new(1e5, 1e5, -1e5);
            assert!(rel(disk(p + off, n, c + off, m, 1.0, 1.0), q) < 1e-8);
        }
    }

    /// E = L ∫ max(0, n·ω) over the triangle, by area quadrature.
    fn triangle_by_area(p: Vec3, nrm: Vec3, a: Vec3, b: Vec3, c: Vec3) -> f64 {
        crate::solid_angle::tests::triangle_integral_by_area(p, a, b, c, |d| nrm.dot(d).max(0.0))
    }

    #[test]
    fn polygon_matches_quadrature_including_horizon() {
        let tri = [
            Vec3::new(-1.0, -0.5, 0.5),
            Vec3::new(1.5, -0.3, 1.0),
            Vec3::new(0.0, 1.0, -0.6),
        ];
        let p = Vec3::new(0.0, 0.0, 0.0);
        for n in [
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.3, 0.1, 1.0).normalized().unwrap(),
            Vec3::new(0.0, 1.0, 0.0),
        ] {
            // Split the triangle along the horizon so the area quadrature is smooth.
            let q = {
                let mut total = 0.0;
                let rel_t: Vec<Vec3> = tri.iter().map(|&v| v - p).collect();
                let clipped = clip_to_half_space(&rel_t, n);
                for k in 1..clipped.len() - 1 {
                    total +=
                        triangle_by_area(p, n, clipped[0] + p, clipped[k] + p, clipped[k + 1] + p);
                }
                total
            };
            let got = polygon(p, n, &tri, 1.0);
            assert!(rel(got, q) < 1e-9, "{got} vs {q}");
        }
        // Entirely below the horizon.
        assert_eq!(
            polygon(
                p,
                Vec3::new(0.0, 0.0, -1.0),
                &[tri[0], tri[1], Vec3::new(0.0, 1.0, 0.2)],
                1.0
            ),
            0.0
        );
        // Grazing receiver, tiny far square ~1e-6 sr.
        let sq = [
            Vec3::new(1e3, 0.0, 0.0),
            Vec3::new(1e3, 1.0, 0.0),
            Vec3::new(1e3, 1.0, 1.0),
            Vec3::new(1e3, 0.0, 1.0),
        ];
        let n = Vec3::new(0.0, 0.0, 1.0);
        let q = triangle_by_area(p, n, sq[0], sq[1], sq[2])
            + triangle_by_area(p, n, sq[0], sq[2], sq[3]);
        assert!(rel(polygon(p, n, &sq, 1.0), q) < 1e-8);
    }

    /// Projected solid angle of a cap by quadrature in the cap's own frame.
    fn cap_by_quadrature(cos_t: f64, sin2: f64) -> f64 {
        let sigma = sin2.sqrt().asin();
        let sin_t = (1.0 - cos_t * cos_t).sqrt();
        // Cap axis along (sin_t, 0, cos_t) relative to normal z.
        adaptive_2d(
            |a, phi| {
                let (sa, ca) = a.sin_cos();
                // z-component of a direction at polar angle a, azimuth phi about the axis.
                let z = ca * cos_t - sa * phi.cos() * sin_t;
                z.max(0.0) * sa
            },
            0.0,
            sigma,
            // Only the azimuths above the horizon: cos φ < cos a cos θ / (sin a sin θ).
            move |a| visible_phi(a, cos_t, sin_t),
            move |a| 2.0 * PI - visible_phi(a, cos_t, sin_t),
            1e-12,
        )
    }

    fn visible_phi(a: f64, cos_t: f64, sin_t: f64) -> f64 {
        let den = a.sin() * sin_t;
        if den <= 0.0 {
            return if a.cos() * cos_t > 0.0 { 0.0 } else { PI };
        }
        (a.cos() * cos_t / den).clamp(-1.0, 1.0).acos()
    }

    #[test]
    fn sphere_matches_quadrature_including_horizon() {
        for (d, r) in [(3.0, 1.0), (1.05, 1.0), (1e3, 1.0)] {
            for theta in [0.0f64, 0.5, 1.2, PI / 2.0, 1.8, 2.5] {
                let n = Vec3::new(theta.sin(), 0.0, theta.cos());
                let c = Vec3::new(0.0, 0.0, d);
                let got = sphere(Vec3::default(), n, c, r, 1.0);
                let q = cap_by_quadrature(theta.cos(), (r / d) * (r / d));
                if q == 0.0 {
                    assert!(got == 0.0);
                } else {
                    let tol = if d > 100.0 { 1e-6 } else { 1e-8 };
                    assert!(rel(got, q) < tol, "d={d} theta={theta}: {got} vs {q}");
                }
                // Far from the origin.
                let off = Vec3::new(-1e5, 1e5, 1e5);
                let far = sphere(off, n, c + off, r, 1.0);
                assert!((far - got).abs() <= 1e-9 * got.abs() + 1e-300);
            }
        }
    }

    /// A NaN in any input (each vector component in turn) gives NaN, also where the
    /// polygon is below the horizon (0): the clipping dropped a NaN vertex as below it,
    /// and a NaN point or normal dropped them all.
    #[test]
    fn polygon_propagates_nan() {
        let (o, up) = ([0.0; 3], [0.0, 0.0, 1.0]);
        let square = |z: f64| [-1.0, -1.0, z, 1.0, -1.0, z, 1.0, 1.0, z, -1.0, 1.0, z];
        let across = [
            1.0, -1.0, -1.0, 1.0, 1.0, -1.0, 1.0, 1.0, 1.0, 1.0, -1.0, 1.0,
        ];
        let bases: Vec<Vec<f64>> = [square(1.0), square(-1.0), across]
            .iter()
            .map(|verts| [&o[..], &up, verts, &[1.0]].concat())
            .collect();
        let bases: Vec<&[f64]> = bases.iter().map(|b| &b[..]).collect();
        let verts = |x: &[f64]| (0..4).map(|k| vec_at(x, 6 + 3 * k)).collect::<Vec<_>>();
        assert_nan_in_each("polygon", &bases, |x| {
            polygon(vec_at(x, 0), vec_at(x, 3), &verts(x), x[18])
        });
        let bases: Vec<&[f64]> = bases.iter().map(|b| &b[..18]).collect();
        assert_nan_in_each("polygon_projected_solid_angle", &bases, |x| {
            polygon_projected_solid_angle(vec_at(x, 0), vec_at(x, 3), &verts(x))
        });
    }

    /// A NaN in any input gives NaN: a NaN radiance came out 0 where the whole disk is
    /// visible (the clamp to ≥ 0) and where it is below the horizon (the early return).
    #[test]
    fn disk_propagates_nan() {
        let t = Vec3::new(0.3, 0.0, 0.95).normalized().unwrap();
        let bases: [&[f64]; 4] = [
            // Whole disk visible, to a facing and to a tilted receiver.
            &[0., 0., 0., 0., 0., 1., 0., 0., 2., 0., 0., -1., 1., 1.],
            &[0., 0., 0., t.x, t.y, t.z, 0.5, 0., 2., 0., 0., -1., 1., 1.],
            // Below the horizon, and straddling it.
            &[0., 0., 0., 0., 0., 1., 0., 0., -2., 0., 0., 1., 1., 1.],
            &[0., 0., 0., 0., 0., 1., 2., 0., 0., 1., 0., 0., 1., 1.],
        ];
        assert_nan_in_each("disk", &bases, |x| {
            let v = |i| vec_at(x, i);
            disk(v(0), v(3), v(6), v(9), x[12], x[13])
        });
    }

    /// A NaN in any input gives NaN, above, below and across the horizon and from inside
    /// the sphere: the cap's comparisons fail for NaN and its clamp to ≥ 0 made it 0.
    #[test]
    fn sphere_propagates_nan() {
        let bases: [&[f64]; 4] = [
            &[0., 0., 0., 0., 0., 1., 0., 0., 3., 1., 1.],
            &[0., 0., 0., 0., 0., 1., 0., 0., -3., 1., 1.],
            &[0., 0., 0., 0., 0., 1., 3., 0., 0., 1., 1.],
            &[0., 0., 0., 0., 0., 1., 0.5, 0., 0., 1., 1.],
        ];
        assert_nan_in_each("sphere", &bases, |x| {
            sphere(vec_at(x, 0), vec_at(x, 3), vec_at(x, 6), x[9], x[10])
        });
        let bases: [&[f64]; 4] = [&[1.0, 0.1], &[-1.0, 0.1], &[0.0, 0.1], &[0.5, 0.0]];
        assert_nan_in_each("cap_projected_solid_angle", &bases, |x| {
            cap_projected_solid_angle(x[0], x[1])
        });
    }

    /// A NaN in any input gives NaN, lit or not: a NaN normal came out 0 through
    /// max(0, cos θ), and so did a NaN spot axis at a hard edge (outside the cone).
    #[test]
    fn point_and_spot_propagate_nan() {
        let bases: [&[f64]; 3] = [
            &[0., 0., 0., 0., 0., 1., 0., 0., 2., 1.],
            &[0., 0., 0., 0., 0., 1., 0., 0., -2., 1.],
            &[0., 0., 0., 0., 0., 1., 2., 0., 0., 1.],
        ];
        assert_nan_in_each("point", &bases, |x| {
            point(vec_at(x, 0), vec_at(x, 3), vec_at(x, 6), x[9])
        });
        // Inside and outside a smooth and a hard-edged cone, and facing away.
        let bases: [&[f64]; 5] = [
            &[
                0., 0., 0., 0., 0., 1., 0., 0., 2., 0., 0., -1., 1., 0.5, 0.3,
            ],
            &[
                5., 0., 0., 0., 0., 1., 0., 0., 2., 0., 0., -1., 1., 0.5, 0.3,
            ],
            &[
                0., 0., 0., 0., 0., 1., 0., 0., 2., 0., 0., -1., 1., 0.5, 0.5,
            ],
            &[
                5., 0., 0., 0., 0., 1., 0., 0., 2., 0., 0., -1., 1., 0.5, 0.5,
            ],
            &[
                0., 0., 0., 0., 0., -1., 0., 0., 2., 0., 0., -1., 1., 0.5, 0.3,
            ],
        ];
        assert_nan_in_each("spot", &bases, |x| {
            let v = |i| vec_at(x, i);
            spot(v(0), v(3), v(6), v(9), x[12], x[13], x[14])
        });
    }

    #[test]
    fn point_and_environment() {
        let e = point(
            Vec3::default(),
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(3.0, 0.0, 4.0),
            10.0,
        );
        assert!(rel(e, 10.0 * 0.8 / 25.0) < 1e-15);
        let q = adaptive_2d(
            |t, _| t.cos() * t.sin(),
            0.0,
            PI / 2.0,
            |_| 0.0,
            |_| 2.0 * PI,
            1e-13,
        );
        assert!(rel(constant_environment(1.0), q) < 1e-12);
    }

    /// The spot light: the point light's law inside θs, nothing beyond θt, half of it
    /// where cos θ is midway (smoothstep at t = ½), for a 30° cone and for one of 0.1°;
    /// and its power, ∮ E dA over a sphere about it by quadrature, is 2π I [(1 − cos θs)
    /// + (cos θs − cos θt)/2] (pbrt-v4 eq. 12.3).
    #[test]
    fn spot_light_by_its_definition_and_its_power() {
        let light = Vec3::new(0.0, 0.0, 1.0);
        let axis = Vec3::new(0.0, 0.0, -1.0);
        let up = Vec3::new(0.0, 0.0, 1.0);
        for (tt, ts) in [
            (30f64.to_radians(), 10f64.to_radians()),
            (0.1f64.to_radians(), 0.05f64.to_radians()),
        ] {
            let at = |theta: f64| Vec3::new(theta.tan(), 0.0, 0.0);
            let e = |theta: f64| spot(at(theta), up, light, axis, 2.0, tt, ts);
            let inside = 0.5 * ts;
            assert!((e(inside) - point(at(inside), up, light, 2.0)).abs() <= 1e-15 * e(inside));
            assert_eq!(e(tt * 1.0001), 0.0);
            let mid = ((ts.cos() + tt.cos()) / 2.0).acos();
            let half = 0.5 * point(at(mid), up, light, 2.0);
            assert!(
                (e(mid) - half).abs() <= 1e-9 * half,
                "{tt}: {} vs {half}",
                e(mid)
            );
        }
        // Power through a unit sphere about the light, of a 40° cone falling from 25°.
        let (tt, ts, i) = (40f64.to_radians(), 25f64.to_radians(), 3.0);
        let flux = adaptive_2d(
            |th, ph| {
                let (st, ct) = th.sin_cos();
                let d = Vec3::new(st * ph.cos(), st * ph.sin(), -ct);
                // The receiver on the sphere, facing the light.
                spot(light + d, -d, light, axis, i, tt, ts) * st
            },
            0.0,
            PI,
            |_| 0.0,
            |_| 2.0 * PI,
            1e-11,
        );
        let want = 2.0 * PI * i * ((1.0 - ts.cos()) + (ts.cos() - tt.cos()) / 2.0);
        assert!((flux - want).abs() <= 1e-8 * want, "{flux} vs {want}");
    }

    /// Receivers within a few 10⁻⁶ of the rim of a unit disk, whose horizon cuts it,
    /// between the disk's inscribed and circumscribed polygons of 2²⁰ sides through
    /// Lambert's formula ([`polygon`]): the integrand max(0, n·ω) cos θ/r² is never
    /// negative, so E grows with the region, and the two polygons bracket the disk
    /// (within about 2·10⁻⁶ relative here). An audit (session 52) found `disk` 0.99% high
    /// at the first point: the arc's integrand peaks over a width of the receiver's
    /// distance to the rim, which the adaptive rule on the whole arc did not see.
    #[test]
    fn disk_near_its_rim_lies_between_its_polygons() {
        let z = Vec3::new(0.0, 0.0, 1.0);
        let sides = 1 << 20;
        let ring = |r: f64| -> Vec<Vec3> {
            (0..sides)
                .map(|i| {
                    let a = 2.0 * PI * i as f64 / sides as f64;
                    Vec3::new(r * a.cos(), r * a.sin(), 0.0)
                })
                .collect()
        };
        let inner = ring(1.0);
        let outer = ring(1.0 / (PI / sides as f64).cos());
        let unit = |v: Vec3| v.normalized().unwrap();
        for (p, n) in [
            (
                Vec3::new(0.9999990463256836, 0.0, 1.9073486328125e-6),
                unit(Vec3::new(0.6, 0.0, -0.8)),
            ),
            (
                Vec3::new(1.0000019073486328, 0.0, 9.5367431640625e-7),
                unit(Vec3::new(-1.0, 0.0, 0.0)),
            ),
            (
                Vec3::new(0.0, -0.99999, 4e-6),
                unit(Vec3::new(0.3, 0.5, -0.7)),
            ),
            (
                Vec3::new(0.7, 0.714, 1e-5),
                unit(Vec3::new(-0.2, -0.1, -0.3)),
            ),
        ] {
            let (lo, hi) = (polygon(p, n, &inner, 1.0), polygon(p, n, &outer, 1.0));
            let got = disk(p, n, Vec3::new(0.0, 0.0, 0.0), z, 1.0, 1.0);
            assert!(
                lo * (1.0 - 1e-12) <= got && got <= hi * (1.0 + 1e-12) && rel(hi, lo) < 1e-5,
                "{p:?}: {got} not in [{lo}, {hi}]"
            );
        }
    }

    /// E = L ∫ max(0, n·v) max(0, m·(−v)) / |v|⁴ dA over the lit, visible part of a
    /// spherical cap (v = y − p, m the outward normal at y), written apart from the contour
    /// code of [`spherical_cap`]: nested adaptive Gauss–Legendre in the cap's own polar
    /// coordinates (θ from the axis, φ about it), unit sphere. For each θ the azimuths in
    /// front of the silhouette (P·y ≥ 1) and above the receiver's plane (n·y ≥ n·P) are
    /// each one arc cos(φ − φ₀) ≥ k(θ), intersected exactly, so the integrand is smooth on
    /// every φ interval. θ runs over [0, θmax], split where an arc opens or closes
    /// (k = ±1) and where the silhouette and the receiver's plane cross (the arcs' ends
    /// meet); each piece is mapped by θ = θa + (θb − θa)(3s² − 2s³), which makes the
    /// square-root onsets there smooth in s.
    fn cap_by_area(p: Vec3, n: Vec3, c: Vec3, axis: Vec3, r: f64, theta_max: f64) -> f64 {
        let big_p = (p - c) * (1.0 / r);
        let (e1, e2) = axis.orthonormal_basis();
        let polar = |v: Vec3| {
            (
                v.dot(axis),
                v.dot(e1).hypot(v.dot(e2)),
                v.dot(e2).atan2(v.dot(e1)),
            )
        };
        let (pa, rho, phi_p) = polar(big_p);
        let (na, q, phi_n) = polar(n);
        let np = n.dot(big_p);
        // Half-width of the arc amp·cos(φ − φ₀) ≥ rhs: None if empty, π if whole.
        let half = |amp: f64, rhs: f64| -> Option<f64> {
            if amp <= 0.0 {
                return (rhs <= 0.0).then_some(PI);
            }
            let k = rhs / amp;
            if k <= -1.0 {
                Some(PI)
            } else if k >= 1.0 {
                None
            } else {
                Some(k.acos())
            }
        };
        let intervals = |theta: f64| -> Vec<(f64, f64)> {
            let (st, ct) = theta.sin_cos();
            let (Some(b1), Some(b2)) = (half(rho * st, 1.0 - pa * ct), half(q * st, np - na * ct))
            else {
                return Vec::new();
            };
            match (b1 == PI, b2 == PI) {
                (true, true) => vec![(0.0, 2.0 * PI)],
                (true, false) => vec![(phi_n - b2, phi_n + b2)],
                (false, true) => vec![(phi_p - b1, phi_p + b1)],
                (false, false) => {
                    let c2 = phi_p + (phi_n - phi_p + PI).rem_euclid(2.0 * PI) - PI;
                    [-2.0 * PI, 0.0, 2.0 * PI]
                        .iter()
                        .map(|k| ((phi_p - b1).max(c2 - b2 + k), (phi_p + b1).min(c2 + b2 + k)))
                        .filter(|(lo, hi)| hi > lo)
                        .collect()
                }
            }
        };
        let f = |theta: f64, phi: f64| {
            let (st, ct) = theta.sin_cos();
            let y = axis * ct + (e1 * phi.cos() + e2 * phi.sin()) * st;
            let v = y - big_p;
            let d2 = v.length_squared();
            (big_p.dot(y) - 1.0).max(0.0) * n.dot(v).max(0.0) / (d2 * d2) * st
        };
        // θ where A cos θ + B sin θ = C.
        let roots = |a: f64, b: f64, cc: f64| -> Vec<f64> {
            let h = a.hypot(b);
            if h == 0.0 || cc.abs() > h {
                return Vec::new();
            }
            let (base, g) = (b.atan2(a), (cc / h).acos());
            vec![
                (base + g).rem_euclid(2.0 * PI),
                (base - g).rem_euclid(2.0 * PI),
            ]
        };
        let mut edges = vec![0.0, theta_max];
        for s in [1.0, -1.0] {
            edges.extend(roots(pa, s * rho, 1.0));
            edges.extend(roots(na, s * q, np));
        }
        // The silhouette and the receiver's plane cross on the line P·y = 1, n·y = n·P:
        // y = α P + β n + τ (P × n).
        let pn = big_p.cross(n);
        let det = big_p.length_squared() - np * np;
        if pn.length() > 0.0 && det > 0.0 {
            let alpha = (1.0 - np * np) / det;
            let y0 = big_p * alpha + n * (np * (1.0 - alpha));
            let rest = 1.0 - y0.length_squared();
            if rest > 0.0 {
                let tau = rest.sqrt() / pn.length();
                for s in [1.0, -1.0] {
                    edges.push(axis.angle_between(y0 + pn * (s * tau)));
                }
            }
        }
        edges.retain(|&t| (0.0..=theta_max).contains(&t));
        edges.sort_by(f64::total_cmp);
        // Edges closer than this (a tangency and a crossing at one place) would leave
        // pieces too thin to integrate to a relative tolerance.
        edges.dedup_by(|a, b| *a - *b < 1e-12);
        edges
            .windows(2)
            .filter(|ab| ab[1] > ab[0])
            .map(|ab| {
                let (lo, span) = (ab[0], ab[1] - ab[0]);
                adaptive(
                    |s| {
                        let theta = lo + span * s * s * (3.0 - 2.0 * s);
                        let jac = span * 6.0 * s * (1.0 - s);
                        let inner: f64 = intervals(theta)
                            .into_iter()
                            .map(|(a, b)| adaptive(|phi| f(theta, phi), a, b, 1e-12))
                            .sum();
                        inner * jac
                    },
                    0.0,
                    1.0,
                    1e-11,
                )
            })
            .sum()
    }

    /// The whole sphere (θmax = 180°) is Snyder's closed form, [`sphere`], to 1e-12, for
    /// receivers at 1.5 R, 1.01 R and (1 + 10⁻⁵) R, facing the centre and tilted from it
    /// until the receiver's plane cuts the sphere (from 1.2 rad at 1.5 R, from 0.15 rad
    /// at 1.01 R) and nearly misses it; facing away, both are 0.
    #[test]
    fn spherical_cap_of_180_degrees_is_the_sphere() {
        let c = Vec3::new(0.3, -0.2, 0.1);
        let r = 0.7;
        let out = Vec3::new(0.6, 0.0, 0.8);
        let side = Vec3::new(0.0, 1.0, 0.0);
        let axis = Vec3::new(-0.2, 0.5, 0.9).normalized().unwrap();
        let mut worst: f64 = 0.0;
        for d in [1.5, 1.01, 1.0 + 1e-5] {
            let p = c + out * (r * d);
            for tilt in [0.0f64, 0.6, 1.2, PI / 2.0, 2.0, 2.5, 2.9, 3.1] {
                let n = -out * tilt.cos() + side * tilt.sin();
                let want = sphere(p, n, c, r, 1.0);
                let got = spherical_cap(p, n, c, axis, r, PI, 1.0);
                if want < 1e-3 {
                    assert!(
                        got.abs() < 1e-15 && want < 1e-15,
                        "d={d} tilt={tilt}: {got} vs {want}"
                    );
                    continue;
                }
                worst = worst.max(rel(got, want));
                assert!(rel(got, want) < 1e-12, "d={d} tilt={tilt}: {got} vs {want}");
                // Radiance scales it; θmax past the sphere's is the sphere.
                assert!(rel(spherical_cap(p, n, c, axis, r, PI, 2.5), 2.5 * want) < 1e-12);
            }
        }
        assert!(worst < 1e-12, "{worst}");
    }

    /// Against the independent area quadrature [`cap_by_area`]: caps of 30°, 60° and 120°
    /// on tilted axes, receivers over the cap, over the hole, beside the rim (where the
    /// silhouette crosses the rim) and cut by their own plane, at 1.3 R and 2.5 R.
    #[test]
    fn spherical_cap_matches_area_quadrature() {
        let c = Vec3::new(0.3, -0.2, 0.1);
        let r = 0.7;
        let unit = |v: Vec3| v.normalized().unwrap();
        let mut checked = 0;
        for axis in [
            unit(Vec3::new(0.2, -0.4, 1.0)),
            unit(Vec3::new(-1.0, 0.5, 0.3)),
        ] {
            let (e1, _) = axis.orthonormal_basis();
            for deg in [30.0f64, 60.0, 120.0] {
                let theta_max = deg.to_radians();
                // Directions from the centre: over the cap, over its rim, over the hole,
                // the opposite pole.
                let over_rim = unit(axis * theta_max.cos() + e1 * theta_max.sin());
                for dir in [
                    unit(axis + e1 * 0.3),
                    over_rim,
                    unit(axis * (theta_max + 0.5).cos() + e1 * (theta_max + 0.5).sin()),
                    -axis,
                ] {
                    for d in [1.3, 2.5] {
                        let p = c + dir * (r * d);
                        let tangent = unit(e1 - dir * e1.dot(dir));
                        for tilt in [0.0f64, 0.7, 1.4, 2.0] {
                            let n = -dir * tilt.cos() + tangent * tilt.sin();
                            let q = cap_by_area(p, n, c, axis, r, theta_max);
                            let got = spherical_cap(p, n, c, axis, r, theta_max, 1.0);
                            if q < 1e-12 {
                                assert!(got < 1e-12, "{deg}° {dir:?} {d} {tilt}: {got} vs 0");
                                continue;
                            }
                            checked += 1;
                            assert!(
                                rel(got, q) < 1e-9,
                                "{deg}° dir {dir:?} d={d} tilt={tilt}: {got} vs quadrature {q}"
                            );
                        }
                    }
                }
            }
        }
        assert!(checked >= 60, "{checked}");
    }

    /// Two receivers 3.8·10⁻⁶ R from the sphere and 10⁻⁶ R outside and inside the rim of
    /// a 60° cap (unit sphere at the origin, axis +z), whose silhouette (2.8·10⁻³ R
    /// across) the rim crosses, against mpmath references by two methods (the contour
    /// integral and a direct area quadrature about the foot point, agreeing to 10⁻²⁶),
    /// for the inputs rounded as the references rounded them: each coordinate of the
    /// point and of the (unnormalised) normal to f32, then the normal normalised. The
    /// references are for exactly 60°; 60° in f64 radians (cos θmax = ½ + 1.0·10⁻¹⁶) moves
    /// E here by −2.9·10⁻¹¹ and −1.6·10⁻¹¹ relative (mpmath: 1.547721174633479229 and
    /// 2.332054017715241773 for that angle), so the oracle is held to 10⁻¹⁰ against the
    /// first and to 10⁻¹¹ against the second, with at most 2·10⁴ integrand evaluations.
    #[test]
    fn spherical_cap_near_its_rim_and_the_sphere() {
        let f32v =
            |a: [f64; 3]| Vec3::new(a[0] as f32 as f64, a[1] as f32 as f64, a[2] as f32 as f64);
        let z = Vec3::new(0.0, 0.0, 1.0);
        for (point, normal, exact, at_f64_angle) in [
            (
                [0.8660292074106527, 0.0, 0.5000010413196756],
                [-1.0160256439763096, 0.0, -0.24019136283914472],
                1.547_721_174_677_760_8,
                1.547_721_174_633_479_1,
            ),
            (
                [0.8660282074068381, 0.0, 0.5000027733770902],
                [-1.0160251635915518, 0.0, -0.24019339488995212],
                2.332_054_017_752_671_6,
                2.332_054_017_715_241_6,
            ),
        ] {
            let (p, n) = (f32v(point), f32v(normal).normalized().unwrap());
            let before = crate::quadrature::evaluations();
            let got = spherical_cap(p, n, Vec3::default(), z, 1.0, 60f64.to_radians(), 1.0);
            let evaluations = crate::quadrature::evaluations() - before;
            assert!(rel(got, exact) < 1e-10, "{got} vs {exact}");
            assert!(rel(got, at_f64_angle) < 1e-11, "{got} vs {at_f64_angle}");
            assert!(evaluations < 20_000, "{evaluations} evaluations");
        }
    }

    /// Where circles coincide: p on the axis at R/cos θmax, whose silhouette is the rim
    /// (the cap is all the sphere shows: [`sphere`]), and just nearer or farther (a
    /// little less); a receiver in the rim's plane facing along the axis (its plane is
    /// the rim's: the whole visible cap, against the quadrature) and against it (0);
    /// empty regions; a point on or inside the sphere (0: the outer side is out of
    /// sight); far from the origin and at another scale.
    #[test]
    fn spherical_cap_degenerate_placements() {
        let c = Vec3::new(0.3, -0.2, 0.1);
        let r = 0.7;
        let axis = Vec3::new(0.2, -0.4, 1.0).normalized().unwrap();
        let t = 60f64.to_radians();
        let p = c + axis * (2.0 * r);
        let e_sphere = sphere(p, -axis, c, r, 1.0);
        let e = spherical_cap(p, -axis, c, axis, r, t, 1.0);
        assert!(rel(e, e_sphere) < 1e-12, "{e} vs {e_sphere}");
        for k in [1.0 - 1e-9, 1.0 + 1e-9, 1.1] {
            let pk = c + axis * (2.0 * r * k);
            let e = spherical_cap(pk, -axis, c, axis, r, t, 1.0);
            let q = cap_by_area(pk, -axis, c, axis, r, t);
            let whole = sphere(pk, -axis, c, r, 1.0);
            assert!(
                rel(e, q) < 1e-9 && e <= whole * (1.0 + 1e-12),
                "{k}: {e} vs {q}"
            );
        }
        let (e1, _) = axis.orthonormal_basis();
        let in_rim_plane = c + (axis * t.cos() + e1 * (1.5 * t.sin())) * r;
        let e = spherical_cap(in_rim_plane, axis, c, axis, r, t, 1.0);
        let q = cap_by_area(in_rim_plane, axis, c, axis, r, t);
        assert!(q > 0.01 && rel(e, q) < 1e-9, "{e} vs {q}");
        assert_eq!(spherical_cap(in_rim_plane, -axis, c, axis, r, t, 1.0), 0.0);
        // Over the hole of a small cap, and facing away.
        assert_eq!(
            spherical_cap(c - axis * (3.0 * r), axis, c, axis, r, 0.3, 1.0),
            0.0
        );
        assert_eq!(
            spherical_cap(c + axis * (3.0 * r), axis, c, axis, r, t, 1.0),
            0.0
        );
        // On and inside the sphere.
        for s in [1.0 - 1e-9, 0.5, 0.0] {
            assert_eq!(
                spherical_cap(c + axis * (s * r), -axis, c, axis, r, t, 1.0),
                0.0
            );
        }
        // Far from the origin, and at another scale.
        let n = Vec3::new(-0.3, 0.2, -1.0).normalized().unwrap();
        let pg = c + Vec3::new(0.2, 0.1, 1.2) * r;
        let e = spherical_cap(pg, n, c, axis, r, t, 1.0);
        let off = Vec3::new(1e5, -1e5, 1e5);
        assert!(rel(spherical_cap(pg + off, n, c + off, axis, r, t, 1.0), e) < 1e-9);
        let e_scaled = spherical_cap(c + (pg - c) * 1e3, n, c, axis, r * 1e3, t, 1.0);
        assert!(rel(e_scaled, e) < 1e-13, "{e_scaled} vs {e}");
    }

    /// Near the sphere |P|² − 1 keeps its digits (error-free products): a receiver
    /// 10⁻¹² R above a 60° cap, 0.7 rad inside its rim (its silhouette, 2.8·10⁻⁶ R
    /// across, far from the rim: the whole sphere's irradiance), its normal tilted 0.5,
    /// 1.2 and 2 rad from the centre so that its plane cuts the silhouette, against
    /// mpmath for these inputs (the contour integral and Snyder's closed form at 34
    /// digits, agreeing to 10⁻²⁸), to 10⁻¹⁴; |P|² − 1 formed naively moves E by 10⁻¹¹
    /// to 10⁻¹⁰ here.
    #[test]
    fn spherical_cap_keeps_the_gap_of_a_receiver_at_the_surface() {
        let p = Vec3::new(0.2602482011754985, 0.2192040358865404, 0.9403299763582832);
        let z = Vec3::new(0.0, 0.0, 1.0);
        for (n, want) in [
            (
                [
                    -0.5706624341508943,
                    0.14292649503011037,
                    -0.8086509774107641,
                ],
                2.9492984354953284,
            ),
            (
                [-0.7597075456458746, 0.5724104677843945, -0.3085299036715435],
                2.1399839203975857,
            ),
            (
                [-0.5408673216896318, 0.7271569679225627, 0.4227354779645892],
                0.9171118327477665,
            ),
        ] {
            let n = Vec3::new(n[0], n[1], n[2]);
            let got = spherical_cap(p, n, Vec3::default(), z, 1.0, 60f64.to_radians(), 1.0);
            assert!(rel(got, want) < 1e-14, "{got} vs {want}");
        }
    }

    /// The rim's peak kept cheap by its splits: receivers 10⁻¹⁵ to 4·10⁻¹⁴ R from the
    /// sphere and from the rim (caps of 63° to 163°), where the rim's integrand peaks
    /// ~10⁻¹⁴ wide on an arc ~10⁷ times as long, each within 2·10⁴ integrand evaluations
    /// (unsplit, the adaptive rule needs up to 1.7·10⁵) and between 0 and the whole
    /// sphere (so near the rim E is set by the inputs' last bits: no closer check).
    #[test]
    fn spherical_cap_rim_peak_within_ulps_of_the_receiver() {
        let z = Vec3::new(0.0, 0.0, 1.0);
        for (p, n, theta_max) in [
            (
                [0.28091172319842633, 0.8850842910538628, -0.3710989106685695],
                [0.2679320904652398, -0.7581897982583624, 0.5944414392653582],
                1.9509884823887786,
            ),
            (
                [
                    0.09567974065593039,
                    0.27476701162639444,
                    -0.9567384577563443,
                ],
                [
                    -0.25667051674727404,
                    0.29463272667989276,
                    0.9204954112877798,
                ],
                2.846373689357361,
            ),
            (
                [
                    -0.5881855379403775,
                    -0.43265536242533675,
                    -0.6832621095322005,
                ],
                [
                    -0.32259182999189456,
                    -0.22873004371318856,
                    0.9184862972986823,
                ],
                2.323017259789226,
            ),
            (
                [0.4914596491294242, -0.7443936670146056, 0.45204588460258527],
                [
                    -0.6494469552567361,
                    -0.7425079462766682,
                    -0.1640140299601208,
                ],
                1.1017387109180006,
            ),
        ] {
            let (p, n) = (Vec3::new(p[0], p[1], p[2]), Vec3::new(n[0], n[1], n[2]));
            let before = crate::quadrature::evaluations();
            let got = spherical_cap(p, n, Vec3::default(), z, 1.0, theta_max, 1.0);
            let evaluations = crate::quadrature::evaluations() - before;
            let whole = sphere(p, n, Vec3::default(), 1.0, 1.0);
            assert!(got > 0.1 && got <= whole, "{got} vs the sphere's {whole}");
            assert!(evaluations < 20_000, "{evaluations} evaluations");
        }
    }

    /// A receiver beside the rim (0.3 R over it) whose plane hides the rim point nearest
    /// it and shows the rim to one side or the other (the rim's arc then stops short of
    /// its peak, from which its splits are counted), against the area quadrature.
    #[test]
    fn spherical_cap_rim_seen_to_one_side_of_its_nearest_point() {
        let (s, c) = 60f64.to_radians().sin_cos();
        let d = Vec3::new(s, 0.0, c);
        let p = d * 1.3;
        let z = Vec3::new(0.0, 0.0, 1.0);
        for side in [1.0, -1.0] {
            let n = (d * 0.2 + Vec3::new(0.0, side, 0.0)).normalized().unwrap();
            let got = spherical_cap(p, n, Vec3::default(), z, 1.0, 60f64.to_radians(), 1.0);
            let q = cap_by_area(p, n, Vec3::default(), z, 1.0, 60f64.to_radians());
            assert!(q > 0.01 && rel(got, q) < 1e-9, "{side}: {got} vs {q}");
        }
    }

    /// The ends of its domain. θmax ≤ 0 is no cap (0, where θmax = 1 lights the
    /// receiver), a point exactly on the sphere sees no outer side (0); a NaN anywhere
    /// (point, normal, centre, axis, radius, θmax, radiance) gives NaN, never 0.
    /// θmax = π exactly is the whole sphere ([`sphere`]) whatever the axis, even pointing
    /// straight away from a receiver 10⁻¹³ R off the surface, where a rim, if there were
    /// one, would be the silhouette's own circle bounding the opposite cap. A receiver in
    /// the tangent plane at −n, facing the sphere (n·P = −1 exactly: its plane touches
    /// the sphere at one point and bounds nothing), sees the whole sphere too, ½ R from
    /// the tangent point and 5·10⁻¹³ R from it, where that point is the silhouette's
    /// opposite again.
    #[test]
    fn spherical_cap_at_the_ends_of_its_domain() {
        // Dyadic centre and a 3-4-5 offset: |p − c|² − R² is exactly 0.
        let c = Vec3::new(0.5, -0.25, 1.0);
        let r = 5.0;
        let axis = Vec3::new(0.2, -0.4, 1.0).normalized().unwrap();
        let p = c + Vec3::new(-1.0, 3.0, 9.0);
        let n = Vec3::new(0.3, -0.5, -1.0).normalized().unwrap();
        assert!(spherical_cap(p, n, c, axis, r, 1.0, 1.0) > 0.1);
        for t in [0.0, -1e-300, -1.0, -PI, f64::NEG_INFINITY] {
            assert_eq!(spherical_cap(p, n, c, axis, r, t, 1.0), 0.0, "θmax {t}");
        }
        let on = c + Vec3::new(3.0, 4.0, 0.0);
        let inward = Vec3::new(-0.6, -0.8, 0.0);
        for t in [1.0, PI] {
            assert_eq!(spherical_cap(on, inward, c, -inward, r, t, 1.0), 0.0);
        }
        // NaN in any one input, in each of a vector's components, also where the
        // receiver would be dark (θmax ≤ 0, on the sphere) and where it is lit.
        let nan = f64::NAN;
        for t in [1.0, 0.0] {
            assert!(
                spherical_cap(p, n, c, axis, r, t, nan).is_nan(),
                "radiance, θmax {t}"
            );
            assert!(
                spherical_cap(p, n, c, axis, nan, t, 1.0).is_nan(),
                "radius, θmax {t}"
            );
            for k in 0..3 {
                let mut v = [0.0; 3];
                v[k] = nan;
                let bad = Vec3::new(v[0], v[1], v[2]);
                for (what, got) in [
                    ("point", spherical_cap(p + bad, n, c, axis, r, t, 1.0)),
                    ("on", spherical_cap(on + bad, inward, c, axis, r, t, 1.0)),
                    ("normal", spherical_cap(p, n + bad, c, axis, r, t, 1.0)),
                    ("centre", spherical_cap(p, n, c + bad, axis, r, t, 1.0)),
                    ("axis", spherical_cap(p, n, c, axis + bad, r, t, 1.0)),
                ] {
                    assert!(got.is_nan(), "{what}[{k}], θmax {t}: {got}");
                }
            }
        }
        assert!(spherical_cap(p, n, c, axis, r, nan, 1.0).is_nan());
        let out = Vec3::new(0.6, 0.0, 0.8);
        for d in [1.0 + 1e-13, 1.5] {
            let p = c + out * (r * d);
            let want = sphere(p, -out, c, r, 1.0);
            for a in [-out, out, axis] {
                let got = spherical_cap(p, -out, c, a, r, PI, 1.0);
                assert!(rel(got, want) < 1e-12, "d={d} axis {a:?}: {got} vs {want}");
            }
        }
        let up = Vec3::new(0.0, 0.0, 1.0);
        for off in [5e-13, 0.5] {
            let p = Vec3::new(off, 0.0, -1.0);
            let want = sphere(p, up, Vec3::default(), 1.0, 1.0);
            assert!(want > 2.0, "{want}");
            let got = spherical_cap(p, up, Vec3::default(), axis, 1.0, PI, 1.0);
            assert!(rel(got, want) < 1e-12, "{off}: {got} vs {want}");
        }
    }
}

/// The sphere formula [`sphere`] for receivers almost touching the sphere (issue 13),
/// against an independent quadrature over the sphere's surface.
#[cfg(test)]
mod near_surface_sphere {
    use super::*;
    use crate::quadrature::adaptive;

    /// E = L ∫ max(0, n·v) (m·(−v)) / |v|⁴ dA over the visible cap (v = x − p, m the
    /// outward normal at x), in polar coordinates (α, φ) about the axis from the centre
    /// to `p`; the azimuths are restricted to the part above the receiver's horizon,
    /// and the polar range is split geometrically from the gap h = (d − r)/r upwards,
    /// since for a small gap the integrand peaks within α ≲ h of the pole.
    fn sphere_by_area(p: Vec3, n: Vec3, c: Vec3, r: f64) -> f64 {
        let w = p - c;
        let d = w.length();
        let ez = w * (1.0 / d);
        let (e1, e2) = ez.orthonormal_basis();
        let (nz, n1, n2) = (n.dot(ez), n.dot(e1), n.dot(e2));
        let q = n1.hypot(n2);
        let phi0 = n2.atan2(n1);
        let alpha_max = (r / d).acos();
        let integrand = |a: f64, phi: f64| {
            let (sa, ca) = a.sin_cos();
            let (sp, cp) = phi.sin_cos();
            let m = e1 * (sa * cp) + e2 * (sa * sp) + ez * ca;
            let v = c + m * r - p;
            let t2 = v.length_squared();
            let cos_r = n.dot(v).max(0.0);
            let cos_l = -m.dot(v);
            cos_r * cos_l.max(0.0) / (t2 * t2) * r * r * sa
        };
        // Half-width of the visible azimuths at polar angle a: r sin a q cos(φ − φ0) ≥
        // n_z (d − r cos a).
        let half = |a: f64| {
            let den = r * a.sin() * q;
            let num = nz * (d - r * a.cos());
            if den <= 0.0 {
                return if num <= 0.0 { PI } else { 0.0 };
            }
            (num / den).clamp(-1.0, 1.0).acos()
        };
        let h = (d - r) / r;
        let mut edges = vec![0.0];
        let mut e = h;
        while e < alpha_max {
            edges.push(e);
            e *= 4.0;
        }
        edges.push(alpha_max);
        // Where the horizon starts (k = −1) or stops (k = +1) cutting the circles of
        // constant α, k = n_z (d − r cos α)/(r sin α q) being monotone on (0, α_max]: the
        // azimuth range has a square-root onset there, so it becomes an edge too.
        let k = |a: f64| nz * (d - r * a.cos()) / (r * a.sin() * q);
        for target in [-1.0, 1.0] {
            let (mut lo, mut hi) = (alpha_max * 1e-12, alpha_max);
            if q > 0.0 && (k(lo) - target) * (k(hi) - target) < 0.0 {
                for _ in 0..200 {
                    let mid = 0.5 * (lo + hi);
                    if (k(lo) - target) * (k(mid) - target) <= 0.0 {
                        hi = mid;
                    } else {
                        lo = mid;
                    }
                }
                edges.push(0.5 * (lo + hi));
            }
        }
        edges.sort_by(f64::total_cmp);
        edges
            .windows(2)
            .map(|ab| {
                adaptive(
                    |a| {
                        let hw = half(a);
                        adaptive(|phi| integrand(a, phi), phi0 - hw, phi0 + hw, 1e-9)
                    },
                    ab[0],
                    ab[1],
                    1e-8,
                )
            })
            .sum()
    }

    #[test]
    fn sphere_matches_area_quadrature_near_the_surface() {
        let c = Vec3::new(0.3, -0.2, 0.1);
        let r = 0.5;
        for gap in [1e-5, 1e-4, 1e-3, 1e-2] {
            for theta in [0.0f64, 0.6, 0.9273, 1.4, PI / 2.0, 2.2143, 2.8] {
                // The receiver above the sphere's top; its normal tilted by θ from the
                // direction to the centre (−z) towards +x.
                let p = Vec3::new(c.x, c.y, c.z + r * (1.0 + gap));
                let n = Vec3::new(theta.sin(), 0.0, -theta.cos());
                let got = sphere(p, n, c, r, 1.0);
                let q = sphere_by_area(p, n, c, r);
                let err = (got - q).abs() / q.abs().max(1e-300);
                assert!(
                    err < 1e-7,
                    "gap {gap}, θ = {theta}: {got} vs quadrature {q}"
                );
            }
        }
    }
}
