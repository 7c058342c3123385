//! The warps of `lightproof::sampling`, each proven by a chi-square test of its samples
//! against its density (the suite in `lightproof::suites`), with Šidák correction over
//! the suite (family α = 1e-4), and the proof that the proof works: deliberately wrong
//! densities are rejected.

use crate::common;

use glam::{Vec2, Vec3};
use lightproof::sampling::cone::Cone;
use lightproof::sampling::hemisphere::*;
use lightproof::stats::chi2::{Chi2Test, Domain};
use lightproof::stats::sidak_alpha;
use lightproof::suites::warps;
use rayon::prelude::*;
use std::f64::consts::PI;

const FAMILY_ALPHA: f64 = 1e-4;

#[test]
fn every_warp_passes_chi2() {
    let suite = warps();
    let alpha = sidak_alpha(FAMILY_ALPHA, suite.len());
    let samples = 1_000_000 * common::scale();
    let failures: Vec<String> = suite
        .par_iter()
        .enumerate()
        .map(|(k, (name, test))| {
            let o = test(samples, common::seed() ^ (k as u64 + 1), alpha);
            (name, o)
        })
        .filter(|(_, o)| !o.passed)
        .map(|(name, o)| {
            format!(
                "{name} (seed {}): {}",
                common::seed(),
                o.reason.unwrap_or_default()
            )
        })
        .collect();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
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

fn u2(u: Vec3) -> Vec2 {
    Vec2::new(u.x, u.y)
}

/// The proof that the proof works: three wrong densities must be rejected with p far
/// below α, each for its own reason.
#[test]
fn wrong_densities_are_rejected() {
    let t = Chi2Test::new(Domain::Hemisphere, 200_000, common::seed(), 1e-4);
    // Off by a constant factor: the shape test alone would pass, normalisation catches it.
    let o = t.run(
        "wrong-constant-factor",
        |u| Some(cosine_hemisphere(u2(u))),
        |w| 1.05 * cosine_hemisphere_pdf(w) as f64,
    );
    assert!(!o.passed && o.normalisation_z.abs() > 10.0, "{o:?}");
    // Wrong exponent: claims cos²θ·3/(2π) for cosine samples.
    let o = t.run(
        "wrong-exponent",
        |u| Some(cosine_hemisphere(u2(u))),
        |w| 3.0 * (w.z as f64).powi(2) / (2.0 * PI),
    );
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
    assert!(
        !o.passed && o.reason.as_deref().unwrap_or("").contains("chi2-failures"),
        "{o:?}"
    );
    assert!(o.dump.iter().all(|p| p.exists()));
}
