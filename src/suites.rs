//! The chi-square suites `lightproof verify` runs besides the case catalog: every warp
//! of [`crate::sampling`] against its density (the same configurations the test suite
//! proves in `tests/sampling_chi2.rs`).

use crate::sampling::cone::Cone;
use crate::sampling::disk::{concentric_disk, concentric_disk_pdf};
use crate::sampling::distribution::Distribution2D;
use crate::sampling::hemisphere::{
    cosine_hemisphere, cosine_hemisphere_pdf, uniform_hemisphere, uniform_hemisphere_pdf,
};
use crate::sampling::sphere::{uniform_sphere, uniform_sphere_pdf};
use crate::sampling::sphere_cone::SphereCone;
use crate::sampling::spherical_rectangle::SphericalRectangle;
use crate::sampling::spherical_triangle::SphericalTriangle;
use crate::sampling::triangle::uniform_triangle;
use crate::stats::chi2::{Chi2Outcome, Chi2Test, Domain};
use glam::{Vec2, Vec3};

/// One chi-square test of a warp: (name, run(samples, seed, per-test α)).
pub type WarpTest = (
    &'static str,
    Box<dyn Fn(u64, u64, f64) -> Chi2Outcome + Sync>,
);

fn u2(u: Vec3) -> Vec2 {
    Vec2::new(u.x, u.y)
}

fn spherical_triangle(name: &'static str, v: [Vec3; 3], rows: usize, cols: usize) -> WarpTest {
    (
        name,
        Box::new(move |n, seed, alpha| {
            let t = SphericalTriangle::new(Vec3::ZERO, v).expect("a non-degenerate triangle");
            Chi2Test::new(Domain::Sphere, n, seed, alpha)
                .with_resolution(rows, cols)
                .run(
                    name,
                    |u| Some(t.sample(u2(u))),
                    |w| if t.contains(w) { t.pdf() as f64 } else { 0.0 },
                )
        }),
    )
}

/// Every warp, in a configuration that exercises it.
pub fn warps() -> Vec<WarpTest> {
    let rect = (
        Vec3::new(-0.3, -0.8, 0.6),
        Vec3::new(1.2, 0.0, 0.0),
        Vec3::new(0.0, 0.9, 0.5),
    );
    vec![
        (
            "uniform_sphere",
            Box::new(|n, s, a| {
                Chi2Test::new(Domain::Sphere, n, s, a).run(
                    "uniform_sphere",
                    |u| Some(uniform_sphere(u2(u))),
                    |_| uniform_sphere_pdf() as f64,
                )
            }),
        ),
        (
            "uniform_hemisphere",
            Box::new(|n, s, a| {
                Chi2Test::new(Domain::Sphere, n, s, a).run(
                    "uniform_hemisphere",
                    |u| Some(uniform_hemisphere(u2(u))),
                    |w| uniform_hemisphere_pdf(w) as f64,
                )
            }),
        ),
        (
            "cosine_hemisphere",
            Box::new(|n, s, a| {
                Chi2Test::new(Domain::Hemisphere, n, s, a).run(
                    "cosine_hemisphere",
                    |u| Some(cosine_hemisphere(u2(u))),
                    |w| cosine_hemisphere_pdf(w) as f64,
                )
            }),
        ),
        (
            "cone_0.3",
            Box::new(|n, s, a| {
                let c = Cone::from_half_angle(0.3);
                Chi2Test::new(Domain::Sphere, n, s, a).run(
                    "cone_0.3",
                    |u| Some(c.sample(u2(u))),
                    |w| c.pdf(w) as f64,
                )
            }),
        ),
        (
            "cone_pi_2",
            Box::new(|n, s, a| {
                let c = Cone::from_half_angle(std::f32::consts::FRAC_PI_2);
                Chi2Test::new(Domain::Sphere, n, s, a).run(
                    "cone_pi_2",
                    |u| Some(c.sample(u2(u))),
                    |w| c.pdf(w) as f64,
                )
            }),
        ),
        (
            "concentric_disk",
            Box::new(|n, s, a| {
                Chi2Test::new(Domain::Disk, n, s, a).run(
                    "concentric_disk",
                    |u| Some(concentric_disk(u2(u)).extend(0.0)),
                    |p| concentric_disk_pdf(p.truncate()) as f64,
                )
            }),
        ),
        (
            "uniform_triangle",
            Box::new(|n, s, a| {
                Chi2Test::new(Domain::Square, n, s, a).run(
                    "uniform_triangle",
                    |u| {
                        let b = uniform_triangle(u2(u));
                        Some(Vec3::new(b.x, b.y, 0.0))
                    },
                    |p| if p.x + p.y <= 1.0 { 2.0 } else { 0.0 },
                )
            }),
        ),
        spherical_triangle(
            "spherical_triangle",
            [
                Vec3::new(0.2, 0.1, 1.0),
                Vec3::new(1.0, -0.3, 0.2),
                Vec3::new(-0.4, 0.9, 0.5),
            ],
            64,
            128,
        ),
        spherical_triangle(
            "sliver_spherical_triangle",
            [
                Vec3::new(-1.0, 0.0, 0.3),
                Vec3::new(1.0, 0.02, 0.3),
                Vec3::new(0.0, -0.01, 0.3),
            ],
            128,
            256,
        ),
        (
            "spherical_rectangle",
            Box::new(move |n, s, a| {
                let r = SphericalRectangle::new(Vec3::ZERO, rect.0, rect.1, rect.2)
                    .expect("a rectangle off its plane");
                let (c, ex, ey) = (rect.0.as_dvec3(), rect.1.as_dvec3(), rect.2.as_dvec3());
                let nrm = ex.cross(ey);
                let inside = move |w: Vec3| {
                    let w = w.as_dvec3();
                    let t = c.dot(nrm) / w.dot(nrm);
                    if t <= 0.0 {
                        return false;
                    }
                    let q = w * t - c;
                    let (x, y) = (
                        q.dot(ex) / ex.length_squared(),
                        q.dot(ey) / ey.length_squared(),
                    );
                    (0.0..=1.0).contains(&x) && (0.0..=1.0).contains(&y)
                };
                Chi2Test::new(Domain::Sphere, n, s, a).run(
                    "spherical_rectangle",
                    |u| Some(r.sample(u2(u))),
                    |w| if inside(w) { r.pdf() as f64 } else { 0.0 },
                )
            }),
        ),
        (
            "sphere_cone",
            Box::new(|n, s, a| {
                let c = SphereCone::new(Vec3::ZERO, Vec3::new(0.5, -1.0, 2.0), 1.2)
                    .expect("viewer outside");
                Chi2Test::new(Domain::Sphere, n, s, a).run(
                    "sphere_cone",
                    |u| Some(c.sample(Vec3::ZERO, u2(u))),
                    |w| if c.contains(w) { c.pdf() as f64 } else { 0.0 },
                )
            }),
        ),
        (
            "piecewise_constant_2d",
            Box::new(|n, s, a| {
                let (nu, nv) = (7, 5);
                let values: Vec<f32> = (0..nu * nv)
                    .map(|i| ((i * 37 % 11) as f32).powi(2) * if i % 9 == 0 { 0.0 } else { 1.0 })
                    .collect();
                let d = Distribution2D::new(&values, nu, nv);
                Chi2Test::new(Domain::Square, n, s, a)
                    .with_resolution(35, 35)
                    .run(
                        "piecewise_constant_2d",
                        |u| Some(d.sample(u2(u)).0.extend(0.0)),
                        |p| d.pdf(p.truncate()) as f64,
                    )
            }),
        ),
    ]
}
