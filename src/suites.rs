//! The chi-square suites `lightproof verify` runs besides the case catalog: every warp
//! of [`crate::sampling`] against its density (the same configurations the test suite
//! proves in `tests/proof/sampling_chi2.rs`).

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

/// The chi-square test of a warp drawing from `domain` at `resolution` (rows, columns;
/// `None`: the default grid), with its sampler (from three uniform numbers) and density.
fn warp<S, P>(
    name: &'static str,
    domain: Domain,
    resolution: Option<(usize, usize)>,
    sample: S,
    pdf: P,
) -> WarpTest
where
    S: Fn(Vec2) -> Option<Vec3> + Sync + 'static,
    P: Fn(Vec3) -> f64 + Sync + 'static,
{
    (
        name,
        Box::new(move |n, seed, alpha| {
            let t = Chi2Test::new(domain, n, seed, alpha);
            let t = match resolution {
                Some((rows, cols)) => t.with_resolution(rows, cols),
                None => t,
            };
            t.run(name, |u| sample(u2(u)), &pdf)
        }),
    )
}

fn spherical_triangle(name: &'static str, v: [Vec3; 3], rows: usize, cols: usize) -> WarpTest {
    let t = SphericalTriangle::new(Vec3::ZERO, v).expect("a non-degenerate triangle");
    warp(
        name,
        Domain::Sphere,
        Some((rows, cols)),
        move |u| Some(t.sample(u)),
        move |w| if t.contains(w) { t.pdf() as f64 } else { 0.0 },
    )
}

/// Whether direction `w` from the origin passes through the parallelogram c + x·ex + y·ey
/// (x, y ∈ [0, 1]), in `f64`: the support of the spherical rectangle's density.
fn through_rectangle((c, ex, ey): (Vec3, Vec3, Vec3), w: Vec3) -> bool {
    let (c, ex, ey, w) = (c.as_dvec3(), ex.as_dvec3(), ey.as_dvec3(), w.as_dvec3());
    let nrm = ex.cross(ey);
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
}

/// Every warp, in a configuration that exercises it.
pub fn warps() -> Vec<WarpTest> {
    let rect = (
        Vec3::new(-0.3, -0.8, 0.6),
        Vec3::new(1.2, 0.0, 0.0),
        Vec3::new(0.0, 0.9, 0.5),
    );
    let r = SphericalRectangle::new(Vec3::ZERO, rect.0, rect.1, rect.2)
        .expect("a rectangle off its plane");
    let narrow = Cone::from_half_angle(0.3);
    let half = Cone::from_half_angle(std::f32::consts::FRAC_PI_2);
    let sc = SphereCone::new(Vec3::ZERO, Vec3::new(0.5, -1.0, 2.0), 1.2).expect("viewer outside");
    let (nu, nv) = (7, 5);
    let values: Vec<f32> = (0..nu * nv)
        .map(|i| ((i * 37 % 11) as f32).powi(2) * if i % 9 == 0 { 0.0 } else { 1.0 })
        .collect();
    let d = Distribution2D::new(&values, nu, nv);
    let d2 = d.clone();
    vec![
        warp(
            "uniform_sphere",
            Domain::Sphere,
            None,
            |u| Some(uniform_sphere(u)),
            |_| uniform_sphere_pdf() as f64,
        ),
        warp(
            "uniform_hemisphere",
            Domain::Sphere,
            None,
            |u| Some(uniform_hemisphere(u)),
            |w| uniform_hemisphere_pdf(w) as f64,
        ),
        warp(
            "cosine_hemisphere",
            Domain::Hemisphere,
            None,
            |u| Some(cosine_hemisphere(u)),
            |w| cosine_hemisphere_pdf(w) as f64,
        ),
        warp(
            "cone_0.3",
            Domain::Sphere,
            None,
            move |u| Some(narrow.sample(u)),
            move |w| narrow.pdf(w) as f64,
        ),
        warp(
            "cone_pi_2",
            Domain::Sphere,
            None,
            move |u| Some(half.sample(u)),
            move |w| half.pdf(w) as f64,
        ),
        warp(
            "concentric_disk",
            Domain::Disk,
            None,
            |u| Some(concentric_disk(u).extend(0.0)),
            |p| concentric_disk_pdf(p.truncate()) as f64,
        ),
        warp(
            "uniform_triangle",
            Domain::Square,
            None,
            |u| {
                let b = uniform_triangle(u);
                Some(Vec3::new(b.x, b.y, 0.0))
            },
            |p| if p.x + p.y <= 1.0 { 2.0 } else { 0.0 },
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
        warp(
            "spherical_rectangle",
            Domain::Sphere,
            None,
            move |u| Some(r.sample(u)),
            move |w| {
                if through_rectangle(rect, w) {
                    r.pdf() as f64
                } else {
                    0.0
                }
            },
        ),
        warp(
            "sphere_cone",
            Domain::Sphere,
            None,
            move |u| Some(sc.sample(Vec3::ZERO, u)),
            move |w| if sc.contains(w) { sc.pdf() as f64 } else { 0.0 },
        ),
        warp(
            "piecewise_constant_2d",
            Domain::Square,
            Some((35, 35)),
            move |u| Some(d.sample(u).0.extend(0.0)),
            move |p| d2.pdf(p.truncate()) as f64,
        ),
    ]
}
