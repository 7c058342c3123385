//! The warps of `lightproof::sampling`, each proven by a chi-square test of its samples
//! against its density, with Šidák correction over this suite (family α = 1e-4), and
//! the proof that the proof works: deliberately wrong densities are rejected.

mod common;

use glam::{Vec2, Vec3};
use lightproof::sampling::cone::Cone;
use lightproof::sampling::disk::{concentric_disk, concentric_disk_pdf};
use lightproof::sampling::distribution::Distribution2D;
use lightproof::sampling::hemisphere::*;
use lightproof::sampling::sphere::{uniform_sphere, uniform_sphere_pdf};
use lightproof::sampling::sphere_cone::SphereCone;
use lightproof::sampling::spherical_rectangle::SphericalRectangle;
use lightproof::sampling::spherical_triangle::SphericalTriangle;
use lightproof::sampling::triangle::uniform_triangle;
use lightproof::stats::chi2::{Chi2Outcome, Chi2Test, Domain};
use lightproof::stats::sidak_alpha;
use std::f64::consts::PI;

/// Number of chi-square tests in this suite that must pass (for Šidák).
const SUITE: usize = 14;
const FAMILY_ALPHA: f64 = 1e-4;

fn test(domain: Domain, salt: u64) -> Chi2Test {
    Chi2Test::new(domain, 1_000_000 * common::scale(), common::seed() ^ salt, sidak_alpha(FAMILY_ALPHA, SUITE))
}

fn check(o: Chi2Outcome) {
    assert!(o.passed, "{} (seed {}): {}", o.name, common::seed(), o.reason.unwrap_or_default());
}

fn u2(u: Vec3) -> Vec2 {
    Vec2::new(u.x, u.y)
}

#[test]
fn uniform_sphere_chi2() {
    check(test(Domain::Sphere, 1).run("uniform_sphere", |u| Some(uniform_sphere(u2(u))), |_| uniform_sphere_pdf() as f64));
}

#[test]
fn uniform_hemisphere_chi2() {
    check(test(Domain::Sphere, 2).run("uniform_hemisphere", |u| Some(uniform_hemisphere(u2(u))), |w| uniform_hemisphere_pdf(w) as f64));
}

#[test]
fn cosine_hemisphere_chi2() {
    check(test(Domain::Hemisphere, 3).run("cosine_hemisphere", |u| Some(cosine_hemisphere(u2(u))), |w| cosine_hemisphere_pdf(w) as f64));
}

#[test]
fn cones_chi2() {
    for (k, half_angle) in [0.3f32, std::f32::consts::FRAC_PI_2].into_iter().enumerate() {
        let c = Cone::from_half_angle(half_angle);
        check(test(Domain::Sphere, 4 + k as u64).run(&format!("cone_{half_angle}"), |u| Some(c.sample(u2(u))), |w| c.pdf(w) as f64));
    }
}

#[test]
fn tiny_cone_is_sampled_inside_with_its_density() {
    // A 1e-4 rad cone is far below the chi2 grid; check support and normalisation instead.
    let c = Cone::from_half_angle(1e-4);
    assert!((c.solid_angle() as f64 / (PI * 1e-8) - 1.0).abs() < 1e-3);
    for i in 0..1000 {
        let u = Vec2::new((i as f32 + 0.5) / 1000.0, ((i * 7) % 1000) as f32 / 1000.0);
        let w = c.sample(u);
        assert!(c.contains(w), "{w}");
        assert!(c.pdf(w).is_finite() && c.pdf(w) > 0.0);
    }
}

#[test]
fn concentric_disk_chi2() {
    check(test(Domain::Disk, 6).run("concentric_disk", |u| Some(concentric_disk(u2(u)).extend(0.0)), |p| concentric_disk_pdf(p.truncate()) as f64));
}

#[test]
fn uniform_triangle_chi2() {
    // The unit right triangle in the square: density 2 inside, 0 outside.
    check(test(Domain::Square, 7).run(
        "uniform_triangle",
        |u| {
            let b = uniform_triangle(u2(u));
            Some(Vec3::new(b.x, b.y, 0.0))
        },
        |p| if p.x + p.y <= 1.0 { 2.0 } else { 0.0 },
    ));
}

fn spherical_triangle_case(name: &str, salt: u64, v: [Vec3; 3], res: (usize, usize)) {
    let t = SphericalTriangle::new(Vec3::ZERO, v).expect("non-degenerate");
    check(test(Domain::Sphere, salt).with_resolution(res.0, res.1).run(name, |u| Some(t.sample(u2(u))), |w| if t.contains(w) { t.pdf() as f64 } else { 0.0 }));
}

#[test]
fn spherical_triangle_chi2() {
    spherical_triangle_case("spherical_triangle", 8, [Vec3::new(0.2, 0.1, 1.0), Vec3::new(1.0, -0.3, 0.2), Vec3::new(-0.4, 0.9, 0.5)], (64, 128));
}

#[test]
fn sliver_spherical_triangle_chi2() {
    // A long thin triangle: one angle near 180 degrees.
    spherical_triangle_case("sliver_spherical_triangle", 9, [Vec3::new(-1.0, 0.0, 0.3), Vec3::new(1.0, 0.02, 0.3), Vec3::new(0.0, -0.01, 0.3)], (128, 256));
}

#[test]
fn spherical_rectangle_chi2() {
    let r = SphericalRectangle::new(Vec3::ZERO, Vec3::new(-0.3, -0.8, 0.6), Vec3::new(1.2, 0.0, 0.0), Vec3::new(0.0, 0.9, 0.5)).unwrap();
    // Membership by ray–plane intersection in f64.
    let (s, ex, ey) = (Vec3::new(-0.3, -0.8, 0.6).as_dvec3(), Vec3::new(1.2, 0.0, 0.0).as_dvec3(), Vec3::new(0.0, 0.9, 0.5).as_dvec3());
    let n = ex.cross(ey);
    let inside = move |w: Vec3| {
        let w = w.as_dvec3();
        let t = s.dot(n) / w.dot(n);
        if t <= 0.0 {
            return false;
        }
        let q = w * t - s;
        let (a, b) = (q.dot(ex) / ex.length_squared(), q.dot(ey) / ey.length_squared());
        (0.0..=1.0).contains(&a) && (0.0..=1.0).contains(&b)
    };
    check(test(Domain::Sphere, 10).run("spherical_rectangle", |u| Some(r.sample(u2(u))), |w| if inside(w) { r.pdf() as f64 } else { 0.0 }));
}

#[test]
fn sphere_cone_chi2() {
    let c = Vec3::new(0.5, -1.0, 2.0);
    let s = SphereCone::new(Vec3::ZERO, c, 1.2).unwrap();
    check(test(Domain::Sphere, 11).run("sphere_cone", |u| Some(s.sample(Vec3::ZERO, u2(u))), |w| if s.contains(w) { s.pdf() as f64 } else { 0.0 }));
}

#[test]
fn piecewise_constant_2d_chi2() {
    let (nu, nv) = (7, 5);
    let values: Vec<f32> = (0..nu * nv).map(|i| ((i * 37 % 11) as f32).powi(2) * if i % 9 == 0 { 0.0 } else { 1.0 }).collect();
    let d = Distribution2D::new(&values, nu, nv);
    check(test(Domain::Square, 12).with_resolution(35, 35).run(
        "piecewise_constant_2d",
        |u| Some(d.sample(u2(u)).0.extend(0.0)),
        |p| d.pdf(p.truncate()) as f64,
    ));
}

/// The proof that the proof works: three wrong densities must be rejected with p far
/// below α, each for its own reason.
#[test]
fn wrong_densities_are_rejected() {
    let t = Chi2Test::new(Domain::Hemisphere, 200_000, common::seed(), 1e-4);
    // Off by a constant factor: the shape test alone would pass, normalisation catches it.
    let o = t.run("wrong-constant-factor", |u| Some(cosine_hemisphere(u2(u))), |w| 1.05 * cosine_hemisphere_pdf(w) as f64);
    assert!(!o.passed && o.normalisation_z.abs() > 10.0, "{o:?}");
    // Wrong exponent: claims cos²θ·3/(2π) for cosine samples.
    let o = t.run("wrong-exponent", |u| Some(cosine_hemisphere(u2(u))), |w| 3.0 * (w.z as f64).powi(2) / (2.0 * PI));
    assert!(!o.passed && o.p_value < 1e-30, "{o:?}");
    // Mirrored lobe: a cone about +x sampled, density claimed about −x.
    let c = Cone::from_half_angle(0.5);
    let t = Chi2Test::new(Domain::Sphere, 200_000, common::seed(), 1e-4);
    let o = t.run(
        "wrong-mirrored-lobe",
        |u| {
            let w = c.sample(u2(u));
            Some(Vec3::new(w.z, w.y, w.x))
        },
        |w| c.pdf(Vec3::new(-w.z, w.y, -w.x)) as f64,
    );
    assert!(!o.passed && o.reason.as_deref().unwrap_or("").contains("chi2-failures"), "{o:?}");
    assert!(o.dump.iter().all(|p| p.exists()));
}
