//! The BSDF contract, run on every built-in model over a grid of parameters and
//! outgoing angles (θo up to 89.9°, α ∈ {1e-4, 0.01, 0.1, 0.5, 1},
//! η ∈ {1.0001 (1.001 for a rough dielectric), 1.33, 1.5, 2.4} and their inverses), and the proof that the proof
//! works: deliberately broken models are rejected.
//!
//! Statistical tests form two Šidák families at family-wise α = 1e-4: the chi-square
//! tests ([`CHI2_SUITE`]) and the mean tests on albedos ([`ALBEDO_SUITE`]). Every
//! albedo verdict must have a detectable relative bias ≤ 1% (at 99% power). Albedo runs
//! are sized from a pilot: the z test needs the samples its power and its CLT guard
//! (skewness) ask for; for models whose energy weights lie in a range their theory
//! promises ([`energy_bound`]), the empirical Bernstein test
//! ([`lightproof::stats::bounded`]) needs no CLT guard and is used when it needs fewer.
//! Deterministic checks (consistency, reciprocity, microfacet quadrature) use the
//! tolerances documented in `lightproof::bsdf::contract`.
//!
//! Chi-square runs on the 64 × 128 sphere grid where it resolves the lobe (α ≥ 0.1
//! and not a rough dielectric at η = 1.001, whose transmission lobe is ~α·1e-3 wide),
//! and for near-delta lobes (α ≤ 0.01) on a cap around the ideal reflection or
//! refraction whose cells are a fraction of the lobe's width
//! ([`contract::chi2_bsdf_cap`]); all configurations are proven by consistency,
//! albedo and stability.

// `!(err <= tol)` fails on NaN where `err > tol` would pass it: the negated
// comparisons are the point (as in the library, `src/lib.rs`).
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::common;

use glam::Vec3;
use lightproof::bsdf::contract::{self, direction};
use lightproof::bsdf::microfacet::{Distribution, Masking, Microfacet};
use lightproof::bsdf::*;
use lightproof::stats::chi2::{Chi2Test, Domain};
use lightproof::stats::{MeanTest, Verdict, sidak_alpha};

const FAMILY_ALPHA: f64 = 1e-4;
/// Number of chi-square tests in this file (Šidák family).
const CHI2_SUITE: usize = 40;
/// Number of albedo mean tests in this file (Šidák family), an upper bound.
const ALBEDO_SUITE: usize = 900;

const ALPHAS: [f32; 5] = [1e-4, 0.01, 0.1, 0.5, 1.0];
const ETAS: [f32; 8] = [
    1.0001,
    1.33,
    1.5,
    2.4,
    1.0 / 1.0001,
    1.0 / 1.33,
    1.0 / 1.5,
    1.0 / 2.4,
];
/// [`ETAS`] for a rough dielectric: its index stays `MIN_ETA_GAP` (10⁻³ since session
/// 52, when η = 1.0001 was found to lose samples) from 1, so 1.001 and 0.999 (1/1.001
/// is 0.999001, within the gap) stand in for 1.0001 and its inverse.
const ROUGH_ETAS: [f32; 8] = [
    1.001,
    1.33,
    1.5,
    2.4,
    0.999,
    1.0 / 1.33,
    1.0 / 1.5,
    1.0 / 2.4,
];

fn deg(d: f32) -> f32 {
    d.to_radians()
}

/// Outgoing directions: normal, oblique, steep and 89.9°; φ away from the axes.
fn angles_above() -> Vec<Vec3> {
    [0.0, 30.0, 60.0, 89.9]
        .iter()
        .map(|&t| direction(deg(t), 0.7))
        .collect()
}

/// Plus directions below the surface (through a dielectric from inside).
fn angles_both() -> Vec<Vec3> {
    let mut v = angles_above();
    v.extend([120.0, 179.0, 90.1].iter().map(|&t| direction(deg(t), 2.1)));
    v
}

fn json(b: &Bsdf) -> String {
    serde_json::to_string(b).unwrap()
}

/// Every model configuration of the grid, with the outgoing directions it is tested at.
fn grid() -> Vec<(Bsdf, Vec<Vec3>)> {
    let mut g = vec![
        (Bsdf::Lambertian(Lambertian::new(0.5)), angles_both()),
        (Bsdf::Lambertian(Lambertian::new(1.0)), angles_above()),
    ];
    for sigma in [0.0, 0.1, 0.5, 1.0] {
        g.push((Bsdf::OrenNayar(OrenNayar::new(1.0, sigma)), angles_both()));
    }
    // The classic form gains energy at grazing for small σ (ρ(A + B/2) > ρ): ρ = 0.9
    // keeps it below 1 everywhere, and its albedo is promised by the oracle.
    for sigma in [0.1, 0.5, 1.0] {
        g.push((
            Bsdf::OrenNayarClassic(OrenNayarClassic::new(0.9, sigma)),
            angles_both(),
        ));
    }
    for (eta, k) in [(0.2, 3.9), (1.5, 0.0), (1.0, 0.0), (0.05, 0.0), (2.9, 3.1)] {
        g.push((Bsdf::Conductor(Conductor::new(eta, k)), angles_both()));
    }
    for eta in ETAS {
        g.push((Bsdf::Dielectric(Dielectric::new(eta)), angles_both()));
    }
    for dist in [Distribution::Ggx, Distribution::Beckmann] {
        for alpha in ALPHAS {
            let mut c = RoughConductor::new(alpha, 0.2, 3.9);
            c.distribution = dist;
            g.push((Bsdf::RoughConductor(c), angles_both()));
            for eta in ROUGH_ETAS {
                let mut d = RoughDielectric::new(alpha, eta);
                d.distribution = dist;
                g.push((Bsdf::RoughDielectric(d), angles_both()));
            }
        }
        let mut c = RoughConductor::new(0.5, 1.5, 0.0);
        c.distribution = dist;
        c.masking = Masking::Uncorrelated;
        g.push((Bsdf::RoughConductor(c), angles_above()));
        // F ≡ 1 (`fresnel: none`): the weak white furnace, albedo from the oracle.
        for (alpha, masking) in [
            (1e-4, Masking::HeightCorrelated),
            (0.1, Masking::HeightCorrelated),
            (1.0, Masking::HeightCorrelated),
            (0.5, Masking::Uncorrelated),
        ] {
            let mut w = RoughConductor::white(alpha);
            w.distribution = dist;
            w.masking = masking;
            g.push((Bsdf::RoughConductor(w), angles_both()));
        }
        let mut d = RoughDielectric::new(0.5, 1.5);
        d.distribution = dist;
        d.masking = Masking::Uncorrelated;
        g.push((Bsdf::RoughDielectric(d), angles_both()));
    }
    for (rho, eta) in [(0.5, 1.5), (1.0, 1.33), (1.0, 2.4), (0.0, 1.5), (1.0, 1.0)] {
        g.push((Bsdf::Plastic(Plastic::new(rho, eta)), angles_both()));
    }
    for (b, _) in &g {
        b.validate().unwrap_or_else(|e| panic!("{}: {e}", json(b)));
    }
    g
}

fn seed(salt: u64) -> u64 {
    common::seed() ^ salt.wrapping_mul(0x9e37_79b9_7f4a_7c15)
}

// ---------------------------------------------------------------------------------
// 1. Chi-square
// ---------------------------------------------------------------------------------

/// The chi-square configurations: (model, ωo, samples in units of 1e5).
///
/// Every configuration runs by default: with each cell's quadrature tolerance scaled
/// to its own statistical error ([`Chi2Test::cell_tolerance`]) a 1M-sample test costs
/// a fraction of a second, where the former absolute tolerance of 1e-3/N cost 5–40 s
/// for a lobe of α = 0.1 or a rough dielectric's kinked pdf (issue 16).
fn chi2_cases() -> Vec<(Bsdf, Vec3, u64)> {
    let ggx_c = |alpha| Bsdf::RoughConductor(RoughConductor::new(alpha, 0.2, 3.9));
    let ggx_d = |alpha, eta| Bsdf::RoughDielectric(RoughDielectric::new(alpha, eta));
    let beck_c = |alpha| {
        let mut c = RoughConductor::new(alpha, 0.2, 3.9);
        c.distribution = Distribution::Beckmann;
        Bsdf::RoughConductor(c)
    };
    let beck_d = |alpha, eta| {
        let mut d = RoughDielectric::new(alpha, eta);
        d.distribution = Distribution::Beckmann;
        Bsdf::RoughDielectric(d)
    };
    let at = |theta: f32| direction(deg(theta), 0.3);
    let mut v = vec![
        (Bsdf::Lambertian(Lambertian::new(0.7)), at(40.0), 10),
        (Bsdf::OrenNayar(OrenNayar::new(0.9, 0.8)), at(70.0), 10),
        (
            Bsdf::OrenNayarClassic(OrenNayarClassic::new(0.9, 0.5)),
            at(70.0),
            10,
        ),
        (Bsdf::Plastic(Plastic::new(0.8, 1.5)), at(50.0), 10),
        (Bsdf::Plastic(Plastic::new(0.3, 2.4)), at(150.0), 10),
        (ggx_c(1.0), at(60.0), 10),
        (ggx_c(0.5), at(89.9), 10),
        (ggx_d(0.5, 1.5), at(60.0), 10),
        (ggx_d(1.0, 1.33), at(89.9), 10),
        (beck_d(1.0, 1.33), at(89.9), 10),
        (ggx_d(0.5, 1.0 / 1.5), at(50.0), 2),
        (ggx_c(0.1), at(30.0), 10),
        (ggx_c(0.1), at(89.9), 10),
        (ggx_d(0.1, 1.5), at(30.0), 10),
        (ggx_d(0.5, 2.4), at(20.0), 10),
        (ggx_d(0.5, 1.5), at(140.0), 10),
        (ggx_d(0.1, 1.0 / 2.4), at(10.0), 10),
        (beck_c(0.1), at(30.0), 10),
        (beck_c(0.5), at(89.9), 10),
        (beck_c(1.0), at(60.0), 10),
        (beck_d(0.5, 1.5), at(60.0), 10),
        (beck_d(0.5, 1.0 / 1.5), at(50.0), 10),
        (beck_d(0.5, 2.4), at(20.0), 10),
        (beck_d(0.5, 1.5), at(140.0), 10),
    ];
    let mut d = RoughDielectric::new(0.5, 1.5);
    d.masking = Masking::Uncorrelated;
    v.push((Bsdf::RoughDielectric(d), at(45.0), 10));
    v
}

/// The near-delta configurations, each on a cap around its lobe's ideal direction:
/// (model, ωo, cap axis, cap radius). A reflection lobe of roughness α spreads ωi by
/// about 2α (twice the microfacet's tilt), a transmission lobe at η = 1.5 and
/// θo = 30° by about 0.4α: the radii keep ~90% of the lobe in the cap, which the
/// 64 × 64 cells then cut into slices of 1/16 to 1/4 of its width. The hard ends:
/// α = 10⁻⁴ at normal incidence (a lobe 2·10⁻⁴ rad wide, resolved by the cap's tangent
/// coordinates where the `f32` z component could not), and α = 0.01 at grazing
/// incidence, reflected at θo = 85° (foreshortened by cos θo ≈ 0.09 across the plane of
/// incidence: about 0.004 rad wide there against 0.04 in the plane, so the cells resolve
/// it in the plane and only coarsely across; a corner of the cap lies below the horizon)
/// and refracted at θo = 80° (the cap holds ~90% of that lobe). Each of the last three fails when the GGX
/// visible normals are stretched by 3% in α (tried in a scratch copy of the engine).
fn near_delta_cases() -> Vec<(Bsdf, Vec3, Vec3, f32)> {
    let wo = direction(deg(30.0), 0.3);
    let mirror = |w: Vec3| Vec3::new(-w.x, -w.y, w.z);
    let refracted = fresnel::refract(wo, Vec3::Z, 1.5).expect("no TIR from outside");
    let beck_c = |alpha| {
        let mut c = RoughConductor::new(alpha, 0.2, 3.9);
        c.distribution = Distribution::Beckmann;
        Bsdf::RoughConductor(c)
    };
    let ggx_c = |alpha| Bsdf::RoughConductor(RoughConductor::new(alpha, 0.2, 3.9));
    let ggx_d = |alpha| Bsdf::RoughDielectric(RoughDielectric::new(alpha, 1.5));
    let normal = direction(0.0, 0.0);
    let grazing = direction(deg(85.0), 0.3);
    let grazing_t = direction(deg(80.0), 0.3);
    let refracted_grazing = fresnel::refract(grazing_t, Vec3::Z, 1.5).expect("from outside");
    vec![
        (ggx_c(0.01), wo, mirror(wo), 0.08),
        (beck_c(0.01), wo, mirror(wo), 0.08),
        (ggx_c(1e-3), normal, mirror(normal), 0.008),
        (ggx_d(0.01), wo, mirror(wo), 0.08),
        (ggx_d(0.01), wo, refracted, 0.016),
        (ggx_c(1e-4), normal, mirror(normal), 8e-4),
        (ggx_c(0.01), grazing, mirror(grazing), 0.08),
        (ggx_d(0.01), grazing_t, refracted_grazing, 0.02),
    ]
}

#[test]
fn chi2_of_sample_against_pdf() {
    let cases = chi2_cases();
    let microfacet_cases = 6;
    assert!(cases.len() + microfacet_cases + near_delta_cases().len() <= CHI2_SUITE);
    let alpha = sidak_alpha(FAMILY_ALPHA, CHI2_SUITE);
    let mut failures = Vec::new();
    for (k, (b, wo, n5)) in cases.iter().enumerate() {
        let name = format!("{}-{k}", b.name());
        let t = Chi2Test::new(
            Domain::Sphere,
            n5 * 100_000 * common::scale(),
            seed(100 + k as u64),
            alpha,
        );
        let o = contract::chi2_bsdf_with(&t, b, &name, *wo);
        if !o.passed {
            failures.push(format!(
                "{} at wo = {wo}: {}",
                json(b),
                o.reason.unwrap_or_default()
            ));
        }
    }
    // The visible-normal samplers on their own, in m space (the spherical cap too).
    let vndf = [
        (Distribution::Ggx, 0.3, 70.0, 10),
        (Distribution::Beckmann, 1.0, 85.0, 2),
        (Distribution::Beckmann, 0.6, 0.0, 10),
        (Distribution::Ggx, 1.0, 20.0, 10),
        (Distribution::Beckmann, 0.3, 70.0, 10),
    ];
    for (k, (dist, alpha_m, theta, n5)) in vndf.into_iter().enumerate() {
        let n = n5 * 100_000 * common::scale();
        let mf = Microfacet::new(dist, alpha_m, Masking::HeightCorrelated);
        let wo = direction(deg(theta), 1.0);
        let o = contract::chi2_microfacet(
            &format!("vndf-{dist:?}-{k}"),
            wo,
            |w, u| mf.sample_m(w, u),
            |w, m| mf.pdf_m(w, m),
            n,
            seed(200 + k as u64),
            alpha,
        );
        if !o.passed {
            failures.push(format!(
                "VNDF {dist:?} α = {alpha_m} θ = {theta}: {}",
                o.reason.unwrap_or_default()
            ));
        }
    }
    let mf = Microfacet::new(Distribution::Ggx, 0.4, Masking::HeightCorrelated);
    let n = 200_000 * common::scale();
    let o = contract::chi2_microfacet(
        "vndf-spherical-cap",
        direction(deg(75.0), 2.0),
        |w, u| mf.sample_vndf_spherical_cap(w, u),
        |w, m| mf.pdf_m(w, m),
        n,
        seed(210),
        alpha,
    );
    if !o.passed {
        failures.push(format!(
            "spherical-cap VNDF: {}",
            o.reason.unwrap_or_default()
        ));
    }
    assert!(
        failures.is_empty(),
        "seed {}:\n{}",
        common::seed(),
        failures.join("\n")
    );
}

#[test]
fn chi2_of_near_delta_lobes() {
    let alpha = sidak_alpha(FAMILY_ALPHA, CHI2_SUITE);
    let mut failures = Vec::new();
    for (k, (b, wo, axis, radius)) in near_delta_cases().iter().enumerate() {
        let name = format!("{}-cap-{k}", b.name());
        let t = Chi2Test::new(
            Domain::Square,
            1_000_000 * common::scale(),
            seed(300 + k as u64),
            alpha,
        );
        let o = contract::chi2_bsdf_cap(&t, b, &name, *wo, *axis, *radius);
        // Power: the lobe must fill many cells, not a handful.
        if o.passed && o.dof < 500 {
            failures.push(format!("{} at wo = {wo}: only {} dof", json(b), o.dof));
        }
        if !o.passed {
            failures.push(format!(
                "{} at wo = {wo}, cap around {axis}: {}",
                json(b),
                o.reason.unwrap_or_default()
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "seed {}:\n{}",
        common::seed(),
        failures.join("\n")
    );
}

// ---------------------------------------------------------------------------------
// 2. Consistency and 3. reciprocity
// ---------------------------------------------------------------------------------

#[test]
fn sample_eval_pdf_agree() {
    let n = 5_000 * common::scale();
    let mut failures = Vec::new();
    for (k, (b, angles)) in grid().iter().enumerate() {
        for (j, wo) in angles.iter().enumerate() {
            let r = contract::check_consistency(b, *wo, n, seed(1000 + 16 * k as u64 + j as u64));
            if !r.passed {
                failures.push(format!(
                    "{} at wo = {wo}: {} of {} ({})",
                    json(b),
                    r.failures,
                    r.trials,
                    r.first_failure.unwrap_or_default()
                ));
            }
        }
    }
    assert!(
        failures.is_empty(),
        "seed {}:\n{}",
        common::seed(),
        failures.join("\n")
    );
}

#[test]
fn reciprocity() {
    let n = 20_000 * common::scale();
    let mut failures = Vec::new();
    for (k, (b, _)) in grid().iter().enumerate() {
        let r = contract::check_reciprocity(b, b.eta_inside(), n, seed(3000 + k as u64));
        // A plastic of albedo 0 has a black diffuse lobe under a delta coat: f ≡ 0, so
        // nothing to compare is right for it (every other model must compare pairs).
        let r = match b {
            Bsdf::Plastic(p) if p.albedo == 0.0 => r.accept_black(),
            _ => r,
        };
        if !r.passed {
            failures.push(format!(
                "{}: {} of {} ({})",
                json(b),
                r.failures,
                r.compared,
                r.first_failure.unwrap_or_default()
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "seed {}:\n{}",
        common::seed(),
        failures.join("\n")
    );
}

// ---------------------------------------------------------------------------------
// 4. Energy
// ---------------------------------------------------------------------------------

/// Independent `f64` oracle: unpolarised Fresnel reflectance for a complex relative
/// index n = η + ik, from the amplitude coefficients r_s = (cos i − n cos t)/(cos i + n cos t),
/// r_p = (n cos i − cos t)/(n cos i + cos t), n cos t = √(n² − sin² i) (principal root).
fn fresnel_oracle(cos_i: f64, eta: f64, k: f64) -> f64 {
    #[derive(Clone, Copy)]
    struct C(f64, f64);
    let mul = |a: C, b: C| C(a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0);
    let div = |a: C, b: C| {
        let d = b.0 * b.0 + b.1 * b.1;
        C((a.0 * b.0 + a.1 * b.1) / d, (a.1 * b.0 - a.0 * b.1) / d)
    };
    let sqrt = |a: C| {
        let r = (a.0 * a.0 + a.1 * a.1).sqrt();
        let re = ((r + a.0) / 2.0).max(0.0).sqrt();
        let im = ((r - a.0) / 2.0).max(0.0).sqrt().copysign(a.1);
        C(re, im)
    };
    let ci = cos_i.abs().min(1.0);
    let n = C(eta, k);
    let n2 = mul(n, n);
    let nct = sqrt(C(n2.0 - (1.0 - ci * ci), n2.1)); // n cos t
    let rs = div(C(ci - nct.0, -nct.1), C(ci + nct.0, nct.1));
    // r_p = (n² cos i − n cos t)/(n² cos i + n cos t)
    let a = C(n2.0 * ci, n2.1 * ci);
    let rp = div(C(a.0 - nct.0, a.1 - nct.1), C(a.0 + nct.0, a.1 + nct.1));
    let m2 = |c: C| c.0 * c.0 + c.1 * c.1;
    0.5 * (m2(rs) + m2(rp))
}

/// The reflectance a model promises at ωo, where it promises one.
fn promised(b: &Bsdf, wo: Vec3) -> Option<f64> {
    let c = wo.z.abs() as f64;
    match b {
        Bsdf::Lambertian(l) => Some(l.albedo as f64),
        Bsdf::Conductor(m) => Some(fresnel_oracle(c, m.eta as f64, m.k as f64)),
        Bsdf::Dielectric(_) => Some(1.0),
        // Oren–Nayar at |cos θo| < 0.01 (89.9°): the cosine-sampled weights' second moment
        // grows like ln(1/cos θo), too heavy for a 1% equality test at 5M samples; the
        // catalog checks grazing albedos (Sobol) and ≤ 1 still runs here.
        Bsdf::OrenNayar(_) | Bsdf::OrenNayarClassic(_) if c < 0.01 => None,
        Bsdf::OrenNayar(m) => Some(lightproof_analytic::oren_nayar::albedo(
            lightproof_analytic::oren_nayar::Form::Fujii,
            m.albedo as f64,
            m.sigma as f64,
            c,
        )),
        Bsdf::OrenNayarClassic(m) => Some(lightproof_analytic::oren_nayar::albedo(
            lightproof_analytic::oren_nayar::Form::Classic,
            m.albedo as f64,
            m.sigma as f64,
            c,
        )),
        // F ≡ 1: the oracle's white-furnace quadrature (α ≥ 0.1 keeps it to milliseconds).
        Bsdf::RoughConductor(m) if m.fresnel == FresnelMode::None && m.alpha >= 0.1 => {
            use lightproof_analytic::microfacet as mf;
            let d = match m.distribution {
                Distribution::Ggx => mf::Distribution::Ggx,
                Distribution::Beckmann => mf::Distribution::Beckmann,
            };
            let g = match m.masking {
                Masking::HeightCorrelated => mf::Masking::HeightCorrelated,
                Masking::Uncorrelated => mf::Masking::Uncorrelated,
            };
            Some(mf::white_albedo(d, g, m.alpha as f64, c))
        }
        Bsdf::Plastic(p) => {
            let eta = p.eta as f64;
            let f = fresnel_oracle(c, eta, 0.0);
            // The internal diffuse reflectance from the oracle, never from the engine.
            let fdr = lightproof_analytic::fresnel::dielectric_average_inside(eta);
            let rho = p.albedo as f64;
            Some(f + (1.0 - f) * rho * (1.0 - fdr) / (1.0 - rho * fdr))
        }
        _ => None,
    }
}

/// The larger of a running worst value and a new one, NaN-sticky: `f64::max` drops a
/// NaN, so `worst.max(e)` would hide a NaN error; here it becomes the worst and stays.
fn worse(worst: f64, e: f64) -> f64 {
    if e.is_nan() || e > worst { e } else { worst }
}

fn check_verdict(v: &Verdict, what: &str, failures: &mut Vec<String>, worst_power: &mut f64) {
    *worst_power = worse(*worst_power, v.detectable_relative_bias);
    if !v.passed {
        failures.push(format!("{what}: {}", v.reason.clone().unwrap_or_default()));
    } else if !(v.detectable_relative_bias <= 0.01) {
        // NaN-failing: a NaN detectable bias is no power at all.
        failures.push(format!(
            "{what}: too weak, detectable relative bias {:.4} > 1%",
            v.detectable_relative_bias
        ));
    }
}

/// The largest absolute error in a smooth dielectric's reflection probability that its
/// test may fail to see at 99% power (the Fresnel reflectance is the selection
/// probability of the reflected lobe). The normal test's detectable error is
/// (z₁₋α₁/₂ + z₀.₉₉)·√(r(1 − r)/n) ≤ (z₁₋α₁/₂ + z₀.₉₉)·½/√n, so a smooth dielectric's
/// albedo run draws at least [`fraction_samples`] (≈ 149 000) for 1%; the exact binomial
/// test, used where n r (1 − r) < 25, sees less than 10⁻³ at those counts.
const FRACTION_POWER: f64 = 0.01;

/// The draws at which a reflection fraction's normal test sees [`FRACTION_POWER`] at
/// 99% power whatever r: n = ((z₁₋α₁/₂ + z₀.₉₉)·½/(0.99·FRACTION_POWER))², the 1% margin
/// holding the f32 allowance γ₁₂₈·r the verdict adds to its detectable bias.
fn fraction_samples(test: &MeanTest) -> u64 {
    use statrs::distribution::ContinuousCDF;
    let z = statrs::distribution::Normal::standard();
    let q = z.inverse_cdf(1.0 - test.per_test_alpha() / 2.0) + z.inverse_cdf(0.99);
    (q * 0.5 / (0.99 * FRACTION_POWER)).powi(2).ceil() as u64
}

/// Mean, standard deviation and skewness of a model's energy weights w η² at ωo, from a
/// pilot run on its own stream (the pilot only sets n; the verdict uses fresh samples).
struct Pilot {
    mean: f64,
    sigma: f64,
    skewness: f64,
}

impl Pilot {
    fn run(b: &Bsdf, wo: Vec3, n: u64, seed: u64) -> Pilot {
        let sampler = lightproof::sampling::Sampler::independent(seed);
        let xs: Vec<f64> = (0..n)
            .map(|i| {
                let mut st = sampler.stream(i);
                let u = Vec3::new(st.next_1d(), st.next_1d(), st.next_1d());
                b.sample(wo, u)
                    .map_or(0.0, |s| s.weight as f64 * (s.eta as f64).powi(2))
            })
            .collect();
        let mean = xs.iter().sum::<f64>() / n as f64;
        let moment = |k: i32| xs.iter().map(|x| (x - mean).powi(k)).sum::<f64>() / n as f64;
        let (m2, m3) = (moment(2), moment(3));
        Pilot {
            mean,
            sigma: (m2 * n as f64 / (n - 1) as f64).sqrt(),
            skewness: if m2 > 0.0 { m3 / m2.powf(1.5) } else { 0.0 },
        }
    }
}

/// Sample count that gives a detectable relative bias of 0.75% (below the required 1%)
/// at 99% power for an estimator of the pilot's standard deviation σ around `reference`,
/// n = ((z₁₋α/2 + z₀.₉₉) σ / (0.0075 |reference|))², and at least the count at which
/// the normal tail is trusted for the pilot's skewness in the tails the tests reject in
/// (`two_sided` for an equality test; [`MeanTest::clt_samples`]): a
/// rare lobe (plastic at 90.1°: the base is sampled 0.3% of the time, γ ≈ 18) gave
/// |z| = 5.58 at seed 18 with 20 000 samples, beyond its 5.27 critical value.
fn powered_samples(test: &MeanTest, pilot: &Pilot, reference: f64, two_sided: bool) -> u64 {
    let z = statrs::distribution::Normal::standard();
    use statrs::distribution::ContinuousCDF;
    let q = z.inverse_cdf(1.0 - test.per_test_alpha() / 2.0) + z.inverse_cdf(0.99);
    let n = (q * pilot.sigma / (0.0075 * reference.abs().max(1e-3)))
        .powi(2)
        .ceil();
    // The ≤ 1 test rejects in the upper tail only, which rare large weights (γ > 0)
    // fatten; rare losses (γ < 0) thin it. The equality test has both tails.
    let skew = if two_sided {
        pilot.skewness.abs()
    } else {
        pilot.skewness.max(0.0)
    };
    let n = (n as u64).max(test.clt_samples(skew));
    n.clamp(20_000, 5_000_000) * common::scale()
}

/// The range [0, w] every energy weight of a model lies in, where its theory promises
/// one:
/// - a rough conductor's weight is F·G2/G1 and a rough dielectric's energy weight G2/G1
///   (see their module notes), both ≤ 1 since F ≤ 1 and G2 ≤ G1 (the f32 quotient of
///   g2 ≤ g1 rounds to at most 1; the allowance γ₁₂₈ covers the Fresnel factor);
/// - a plastic's coat sample weighs F/P_s = s = F + (1 − F) a ≤ 1 and its base sample
///   f_d π/(1 − P_s) = s (1 − F(θi))/(η² (1 − F_dr,int)) ≤ 1/(η² (1 − F_dr,int))
///   (module notes of `plastic`), F_dr,int from the oracle; 10⁻³ of slack covers the
///   engine's own F_dr,int and its f32 rounding.
fn energy_bound(b: &Bsdf) -> Option<f64> {
    match b {
        Bsdf::RoughConductor(_) | Bsdf::RoughDielectric(_) => {
            Some(1.0 + lightproof::stats::exact_relative_tolerance())
        }
        Bsdf::Plastic(p) => {
            let eta = p.eta as f64;
            let fdr = lightproof_analytic::fresnel::dielectric_average_inside(eta);
            Some((1.0 / (eta * eta * (1.0 - fdr))).max(1.0) * (1.0 + 1e-3))
        }
        _ => None,
    }
}

/// Sample count at which the empirical Bernstein test of weights in [0, `width`]
/// ([`contract::judge_equal_within`]) detects a relative bias of 0.75% for the pilot's
/// variance (its range term 7bL/(3n) needs ~5 000 samples, its variance term the
/// z test's count times 2L/(z₁₋α/2)² ≈ 1.2); the same floor and cap as
/// [`powered_samples`], without a CLT floor: the bound holds at every n.
fn bounded_samples(
    test: &MeanTest,
    pilot: &Pilot,
    width: f64,
    reference: f64,
    two_sided: bool,
) -> u64 {
    let t = test.with_term_scale(1.0);
    let target = 0.0075 * reference.abs().max(1e-3);
    let det =
        |n: u64| t.bounded_detectable_bias(n, pilot.sigma.powi(2), width, reference, two_sided);
    let (mut lo, mut hi) = (20_000u64, 5_000_000u64);
    if det(lo) <= target {
        return lo * common::scale();
    }
    while hi - lo > lo / 64 {
        let mid = lo + (hi - lo) / 2;
        if det(mid) <= target {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi * common::scale()
}

#[test]
fn energy_conservation_and_promised_albedo() {
    let test = MeanTest::new(FAMILY_ALPHA, ALBEDO_SUITE);
    let mut failures = Vec::new();
    let (mut tests, mut worst_power, mut total_samples) = (0usize, 0.0f64, 0u64);
    let mut worst_fraction_power = 0.0f64;
    let mut bounded = 0usize;
    for (k, (b, angles)) in grid().iter().enumerate() {
        // θo ∈ {0, 60, 89.9} above, and 120°, 90.1° below for the models that transmit.
        for (j, wo) in angles
            .iter()
            .enumerate()
            .filter(|(j, _)| [0, 2, 3, 4, 6].contains(j))
        {
            let salt = 5000 + 16 * k as u64 + j as u64;
            let promise = promised(b, *wo);
            let reference = promise.unwrap_or(1.0);
            let pilot = Pilot::run(b, *wo, 10_000, seed(salt) ^ 0x9107);
            let two_sided = promise.is_some();
            let target = reference.max(pilot.mean);
            let n_clt = powered_samples(&test, &pilot, target, two_sided);
            // Weights in a promised range: the empirical Bernstein test needs no CLT, so
            // a rare loss costs no more than its variance; picked (from the pilot, before
            // the samples are drawn) when it needs fewer samples than the z test.
            let bound = energy_bound(b)
                .map(|w| (w, bounded_samples(&test, &pilot, w, target, two_sided)))
                .filter(|&(_, n)| n < n_clt)
                .map(|(w, _)| w);
            let n = match bound {
                Some(w) => bounded_samples(&test, &pilot, w, target, two_sided),
                None => n_clt,
            };
            // A smooth dielectric's reflection fraction needs its own power (below).
            let n = match b {
                Bsdf::Dielectric(_) => n.max(fraction_samples(&test) * common::scale()),
                _ => n,
            };
            bounded += usize::from(bound.is_some());
            let at_most = |a: &contract::Albedo| match bound {
                Some(w) => contract::judge_at_most_within(&test, a, w, 1.0),
                None => contract::judge_at_most(&test, &a.energy, 1.0),
            };
            let mut a = contract::albedo(b, *wo, n, seed(salt));
            total_samples += n;
            let what = format!("{} at θo = {:.1}°", json(b), wo.z.acos().to_degrees());
            let mut v = at_most(&a);
            if v.detectable_relative_bias > 0.01 && v.detectable_relative_bias.is_finite() {
                // (A NaN or infinite detectable bias is not rerun: `check_verdict` fails it.)
                // Heavy-tailed weights (Oren–Nayar at grazing: tan β has a log-divergent
                // second moment under cosine sampling) fool the pilot; redo the run with
                // the sample count its own variance asks for, on a fresh stream.
                let n2 = ((n as f64) * (v.detectable_relative_bias / 0.0075).powi(2)).ceil() as u64;
                a = contract::albedo(b, *wo, n2, seed(salt) ^ 0x2e57);
                total_samples += n2;
                v = at_most(&a);
            }
            tests += 1;
            check_verdict(
                &v,
                &format!("{what}: energy albedo ≤ 1"),
                &mut failures,
                &mut worst_power,
            );
            if let Some(p) = promise {
                tests += 1;
                let v = match bound {
                    Some(w) => contract::judge_equal_within(&test, &a, w, p),
                    None => contract::judge_equal(&test, &a.energy, p),
                };
                if p > 0.05 {
                    check_verdict(
                        &v,
                        &format!("{what}: albedo = {p:.6}"),
                        &mut failures,
                        &mut worst_power,
                    );
                } else if !v.passed {
                    failures.push(format!(
                        "{what}: albedo = {p:.6}: {}",
                        v.reason.unwrap_or_default()
                    ));
                }
            }
            if let Bsdf::Dielectric(d) = b {
                // The reflection probability is the Fresnel reflectance (1 under TIR).
                let eta = if wo.z > 0.0 {
                    d.eta as f64
                } else {
                    1.0 / d.eta as f64
                };
                let c = wo.z.abs() as f64;
                let r = if (1.0 - c * c) / (eta * eta) >= 1.0 {
                    1.0
                } else {
                    fresnel_oracle(c, eta, 0.0)
                };
                tests += 1;
                // Binomial test of the reflected count k against Binomial(n, r): exact
                // (two-sided, `MeanTest::judge_binomial`) where n r (1 − r) is small,
                // e.g. R ~ 1e-8 at η = 1.0001, where the normal approximation is
                // meaningless.
                let f = &a.reflect_fraction;
                let (n_f, k) = (f.count, (f.mean * f.count as f64).round() as u64);
                let v = if (n_f as f64) * r * (1.0 - r) < 25.0 {
                    test.judge_binomial(k, n_f, r, f.non_finite)
                } else {
                    let se = (r * (1.0 - r) / n_f as f64).sqrt();
                    test.judge_parts(f.mean, se, r, None, f.non_finite, n_f)
                };
                // Power: the smallest absolute error in the reflection probability seen
                // with 99% power (exact binomial quantiles, or (z₁₋α/2 + z₀.₉₉)·SE).
                worst_fraction_power = worse(worst_fraction_power, v.detectable_bias);
                if !(v.detectable_bias <= FRACTION_POWER) {
                    failures.push(format!(
                        "{what}: reflection fraction test too weak: detectable |Δr| {:.2e} > {FRACTION_POWER}",
                        v.detectable_bias
                    ));
                }
                if !v.passed {
                    failures.push(format!(
                        "{what}: reflection fraction ≠ Fresnel {r:.6}: {}",
                        v.reason.unwrap_or_default()
                    ));
                }
            }
        }
    }
    assert!(tests <= ALBEDO_SUITE, "raise ALBEDO_SUITE to {tests}");
    eprintln!(
        "{tests} albedo tests ({bounded} configurations by empirical Bernstein), {total_samples} samples; worst detectable relative bias {worst_power:.4}; dielectric reflection fractions: worst detectable |Δr| {worst_fraction_power:.2e} (99% power)"
    );
    assert!(
        failures.is_empty(),
        "seed {}:\n{}",
        common::seed(),
        failures.join("\n")
    );
}

/// The facts a model states about itself ([`ModelFacts`], read by planning and by the
/// reciprocity rule) agree with what it samples: a model without a transmission lobe has
/// η_inside = 1; a transmitted sample crosses η′ = η_inside from above and 1/η_inside from
/// below, a reflected one η′ = 1; a model is black exactly when none of its samples
/// carries weight (but the conductor at the matched index, which carries none and is not
/// called black); and a conductor's stated reflectance is the Fresnel factor of the
/// oracle (complex arithmetic in `f64`) to `f32` rounding.
#[test]
fn model_facts_agree_with_samples() {
    let n = 1_000;
    let mut models: Vec<(Bsdf, Vec<Vec3>)> = grid();
    models.push((Bsdf::Lambertian(Lambertian::new(0.0)), angles_both()));
    models.push((Bsdf::OrenNayar(OrenNayar::new(0.0, 0.5)), angles_both()));
    models.push((
        Bsdf::OrenNayarClassic(OrenNayarClassic::new(0.0, 0.5)),
        angles_both(),
    ));
    // A black base under a coat of index 1: the coat reflects nothing either.
    models.push((Bsdf::Plastic(Plastic::new(0.0, 1.0)), angles_both()));
    let mut failures = Vec::new();
    for (k, (b, angles)) in models.iter().enumerate() {
        let eta = b.eta_inside();
        if !b.flags().contains(LobeFlags::TRANSMISSION) && eta != 1.0 {
            failures.push(format!(
                "{}: η_inside = {eta} without transmission",
                json(b)
            ));
        }
        let sampler = lightproof::sampling::Sampler::independent(seed(7000 + k as u64));
        let mut carries = false;
        for wo in angles {
            for i in 0..n {
                let mut st = sampler.stream(i);
                let u = Vec3::new(st.next_1d(), st.next_1d(), st.next_1d());
                let Some(s) = b.sample(*wo, u) else { continue };
                carries |= s.weight > 0.0;
                let expected = if s.lobe.contains(LobeFlags::REFLECTION) {
                    1.0
                } else if wo.z > 0.0 {
                    eta
                } else {
                    1.0 / eta
                };
                if s.eta != expected {
                    failures.push(format!(
                        "{} at wo = {wo}: η′ = {} for a {:?} sample, η_inside = {eta}",
                        json(b),
                        s.eta,
                        s.lobe
                    ));
                    break;
                }
            }
        }
        // A conductor at the matched index η = 1, k = 0 reflects nothing (F = 0 exactly)
        // but is not called black, since dispersion may move its index: a claim of
        // "not black" is allowed to be conservative there, and only there.
        let matched = matches!(b, Bsdf::Conductor(c) if c.eta == 1.0 && c.k == 0.0);
        if matched && carries {
            failures.push(format!(
                "{}: the matched index reflects, a sample carried weight",
                json(b)
            ));
        } else if !matched && carries == b.is_black() {
            failures.push(format!(
                "{}: is_black = {} but a sample carried weight: {carries}",
                json(b),
                b.is_black()
            ));
        }
        if let Bsdf::Plastic(m) = b {
            // F_dr,int is the oracle's internal hemispherical Fresnel average: the
            // engine's f64 quadrature (absolute tolerance 1e-12) rounded to f32 once. The
            // promised albedo A(θo) = F + (1 − F) a is the oracle's to the f32 rounding
            // of a few operations.
            let fdr = lightproof_analytic::fresnel::dielectric_average_inside(f64::from(m.eta));
            let stated = f64::from(m.internal_diffuse_reflectance());
            if !((stated - fdr).abs() <= (2.0 * f64::from(f32::EPSILON) * fdr).max(1e-12)) {
                failures.push(format!(
                    "{}: F_dr,int = {stated}, the oracle's {fdr}",
                    json(b)
                ));
            }
            for wo in angles {
                let p = promised(b, *wo).expect("a plastic promises its albedo");
                let a = f64::from(m.albedo_at(wo.z));
                if !((a - p).abs() <= 64.0 * f64::from(f32::EPSILON)) {
                    failures.push(format!(
                        "{}: albedo_at({}) = {a}, the oracle's {p}",
                        json(b),
                        wo.z
                    ));
                }
            }
        }
        if let Bsdf::Conductor(m) = b {
            for c in [1.0f32, 0.7, 0.3, 0.05, 1e-3] {
                let r = f64::from(m.reflectance(c));
                let oracle = fresnel_oracle(f64::from(c), f64::from(m.eta), f64::from(m.k));
                // The f32 formula's rounding: a few dozen operations, each within ε of
                // terms up to 1/cos θ times F's scale (index-matched, η = 1 and k = 0,
                // the oracle's F = 0 comes out as ~0.1ε/cos θ).
                let tol = 64.0 * f64::from(f32::EPSILON) * (oracle + 1.0 / f64::from(c));
                if !((r - oracle).abs() <= tol) {
                    failures.push(format!(
                        "{}: reflectance({c}) = {r}, the oracle's F = {oracle}",
                        json(b)
                    ));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

// ---------------------------------------------------------------------------------
// 5. Microfacet identities
// ---------------------------------------------------------------------------------

#[test]
fn microfacet_identities() {
    let mut failures = Vec::new();
    let mut worst = 0.0f64;
    for dist in [Distribution::Ggx, Distribution::Beckmann] {
        for alpha in ALPHAS {
            let mf = Microfacet::new(dist, alpha, Masking::HeightCorrelated);
            for theta in [0.0, 45.0, 89.9] {
                let wo = direction(deg(theta), 0.4);
                let i = contract::microfacet_integrals(&mf, wo);
                for (what, v) in [
                    ("∫D cos", i.projected_area),
                    ("∫D_ωo", i.visible),
                    ("weak furnace", i.weak_furnace),
                ] {
                    // Fixed composite Gauss rule cut at the kinks: converged to ~1e-9;
                    // the f32 evaluation of D and G1 adds ~1e-7 (measured worst 1e-7).
                    // NaN-failing: a NaN integral is the worst and fails the bound.
                    let err = (v - 1.0).abs();
                    worst = worse(worst, err);
                    if !(err <= 1e-6) {
                        failures.push(format!("{dist:?} α = {alpha} θo = {theta}: {what} = {v}"));
                    }
                }
            }
        }
    }
    eprintln!("microfacet identities: worst |integral − 1| = {worst:.2e}");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(worst <= 1e-6, "worst |integral − 1| = {worst}");
}

// ---------------------------------------------------------------------------------
// The proof that the proof works: broken models are rejected.
// ---------------------------------------------------------------------------------

/// A model with one deliberate defect.
struct Broken {
    inner: Bsdf,
    defect: Defect,
}

#[derive(Clone, Copy, Debug)]
enum Defect {
    /// `eval` 3% high; `sample` and `pdf` right.
    EvalHigh,
    /// `pdf` with the reflection Jacobian 1/(2 ωo·h) instead of 1/(4 ωo·h), also in `sample`.
    WrongJacobian,
    /// `sample` draws a 10% rougher lobe than `pdf` describes.
    SamplerTooRough,
    /// f(ωi→ωo) multiplied by 1 + 0.2 (cos θo − cos θi): not reciprocal.
    NotReciprocal,
    /// Weights 2% high (an energy-creating surface).
    EnergyGain,
    /// A delta reflection mirrored about the xz plane only: (ωo.x, −ωo.y, ωo.z).
    MirrorTwisted,
    /// A delta refraction 1% off Snell's law (its tangential part 1% long).
    SnellOff,
    /// A delta refraction with its tangential part right and its normal component 10⁻⁴
    /// long (within the 10⁻³ of the length check every sample passes).
    SnellNormalOff,
    /// A delta-only model whose `eval` is 1 everywhere.
    DeltaWithDensity,
    /// `flags` names reflection alone while `sample` also transmits.
    FlagsMissTransmission,
}

impl BsdfModel for Broken {
    fn eval(&self, wo: Vec3, wi: Vec3) -> f32 {
        let f = self.inner.eval(wo, wi);
        match self.defect {
            Defect::EvalHigh => 1.03 * f,
            Defect::DeltaWithDensity => 1.0,
            Defect::NotReciprocal => f * (1.0 + 0.2 * (wo.z.abs() - wi.z.abs())),
            _ => f,
        }
    }
    fn sample(&self, wo: Vec3, u: Vec3) -> Option<BsdfSample> {
        match self.defect {
            Defect::SamplerTooRough => {
                let Bsdf::RoughConductor(c) = &self.inner else {
                    unreachable!()
                };
                let mut rougher = *c;
                rougher.alpha *= 1.1;
                let mut s = rougher.sample(wo, u)?;
                s.pdf = c.pdf(wo, s.wi);
                s.weight = c.eval(wo, s.wi) * s.wi.z.abs() / s.pdf;
                Some(s)
            }
            Defect::WrongJacobian => {
                // The weight keeps its (right) closed form F G2/G1, as in a real bug where
                // only the pdf's Jacobian is mistyped.
                let mut s = self.inner.sample(wo, u)?;
                s.pdf *= 2.0;
                Some(s)
            }
            Defect::EnergyGain => {
                let mut s = self.inner.sample(wo, u)?;
                s.weight *= 1.02;
                Some(s)
            }
            Defect::MirrorTwisted => {
                let mut s = self.inner.sample(wo, u)?;
                if s.lobe.contains(LobeFlags::REFLECTION) {
                    s.wi.x = -s.wi.x;
                }
                Some(s)
            }
            Defect::SnellOff => {
                let mut s = self.inner.sample(wo, u)?;
                if s.lobe.contains(LobeFlags::TRANSMISSION) {
                    let t = 1.01 * s.wi.truncate();
                    s.wi = t.extend(s.wi.z.signum() * (1.0 - t.length_squared()).max(0.0).sqrt());
                }
                Some(s)
            }
            Defect::SnellNormalOff => {
                let mut s = self.inner.sample(wo, u)?;
                if s.lobe.contains(LobeFlags::TRANSMISSION) {
                    s.wi.z *= 1.0 + 1e-4;
                }
                Some(s)
            }
            _ => self.inner.sample(wo, u),
        }
    }
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let p = self.inner.pdf(wo, wi);
        if let Defect::WrongJacobian = self.defect {
            2.0 * p
        } else {
            p
        }
    }
    fn flags(&self) -> LobeFlags {
        match self.defect {
            Defect::FlagsMissTransmission => self.inner.flags() - LobeFlags::TRANSMISSION,
            _ => self.inner.flags(),
        }
    }
}

#[test]
fn broken_delta_lobes_are_rejected() {
    // Each defect against a sound model: the consistency check passes the sound one and
    // names the defect in the broken one.
    let wo = direction(deg(50.0), 0.3);
    let s = common::seed();
    let mirror = Bsdf::Conductor(Conductor::new(0.2, 3.9));
    let glass = Bsdf::Dielectric(Dielectric::new(1.5));
    for (inner, defect, says) in [
        (
            &mirror,
            Defect::MirrorTwisted,
            "is not the mirror direction",
        ),
        (&glass, Defect::MirrorTwisted, "is not the mirror direction"),
        (&glass, Defect::SnellOff, "is not Snell's refraction"),
        (&glass, Defect::SnellNormalOff, "is not Snell's refraction"),
        (
            &mirror,
            Defect::DeltaWithDensity,
            "a model of delta lobes only",
        ),
        (
            &glass,
            Defect::FlagsMissTransmission,
            "is not among the model's flags",
        ),
    ] {
        assert!(contract::check_consistency(inner, wo, 2_000, s).passed);
        let b = Broken {
            inner: inner.clone(),
            defect,
        };
        let r = contract::check_consistency(&b, wo, 2_000, s);
        let first = r.first_failure.clone().unwrap_or_default();
        assert!(
            !r.passed && first.contains(says),
            "{defect:?} of {}: {r:?}",
            json(inner)
        );
    }
    // From inside the glass (η′ = 1/1.5), outside the critical angle.
    let below = direction(deg(180.0 - 30.0), 0.3);
    let b = Broken {
        inner: glass.clone(),
        defect: Defect::SnellOff,
    };
    assert!(contract::check_consistency(&glass, below, 2_000, s).passed);
    assert!(!contract::check_consistency(&b, below, 2_000, s).passed);
}

#[test]
fn broken_models_are_rejected() {
    let wo = direction(deg(50.0), 0.3);
    let ggx = Bsdf::RoughConductor(RoughConductor::new(0.5, 0.2, 3.9));
    let lamb = Bsdf::Lambertian(Lambertian::new(0.8));
    let s = common::seed();

    // A Lambertian whose eval is 3% high: chi-square cannot see it (sample and pdf are
    // right), the consistency check does.
    let b = Broken {
        inner: lamb.clone(),
        defect: Defect::EvalHigh,
    };
    assert!(contract::chi2_bsdf(&b, "broken-eval", wo, 200_000, s, 1e-4).passed);
    let r = contract::check_consistency(&b, wo, 2_000, s);
    assert!(!r.passed && r.failures > 1000, "{r:?}");

    // A GGX pdf with the wrong reflection Jacobian: normalisation and consistency fail.
    let b = Broken {
        inner: ggx.clone(),
        defect: Defect::WrongJacobian,
    };
    let o = contract::chi2_bsdf(&b, "broken-jacobian", wo, 200_000, s, 1e-4);
    assert!(!o.passed && o.normalisation_z.abs() > 10.0, "{o:?}");
    assert!(!contract::check_consistency(&b, wo, 2_000, s).passed);

    // A sampler 10% rougher than its pdf, with self-consistent weights: chi-square fails.
    let b = Broken {
        inner: ggx.clone(),
        defect: Defect::SamplerTooRough,
    };
    let o = contract::chi2_bsdf(&b, "broken-sampler", wo, 200_000, s, 1e-4);
    assert!(!o.passed && o.p_value < 1e-10, "{o:?}");

    // A non-reciprocal BRDF.
    let b = Broken {
        inner: ggx.clone(),
        defect: Defect::NotReciprocal,
    };
    assert!(!contract::check_reciprocity(&b, 1.0, 5_000, s).passed);

    // An energy-creating white Lambertian (2% gain) fails albedo ≤ 1, and a 1% error in
    // a promised albedo is seen.
    let white = Bsdf::Lambertian(Lambertian::new(1.0));
    let b = Broken {
        inner: white,
        defect: Defect::EnergyGain,
    };
    let a = contract::albedo(&b, wo, 10_000, s);
    let test = MeanTest::new(FAMILY_ALPHA, ALBEDO_SUITE);
    assert!(!contract::judge_at_most(&test, &a.energy, 1.0).passed);
    // The bounded test fails it on the first weight above 1, whatever its mean.
    assert!(!contract::judge_at_most_within(&test, &a, 1.0, 1.1).passed);
    // A rare-loss weight (F ≡ 1, Beckmann α = 0.1, θo = 60°: skewness ≈ −60) is judged by
    // empirical Bernstein at 20 000 samples, and a 1% error in its albedo is seen.
    let mut w = RoughConductor::white(0.1);
    w.distribution = Distribution::Beckmann;
    let w = Bsdf::RoughConductor(w);
    let w60 = direction(deg(60.0), 0.7);
    let a = contract::albedo(&w, w60, 20_000, s);
    let p = promised(&w, w60).unwrap();
    let bound = energy_bound(&w).unwrap();
    assert!(contract::judge_equal_within(&test, &a, bound, p).passed);
    assert!(!contract::judge_equal_within(&test, &a, bound, p * 1.01).passed);
    assert!(
        !contract::judge_equal_within(&test, &a, 0.9, p).passed,
        "a weight above 0.9 fails"
    );
    let plastic = Bsdf::Plastic(Plastic::new(0.7, 1.5));
    let a = contract::albedo(&plastic, wo, 400_000, s);
    let p = promised(&plastic, wo).unwrap();
    assert!(contract::judge_equal(&test, &a.energy, p).passed);
    assert!(!contract::judge_equal(&test, &a.energy, p * 1.01).passed);
}

#[test]
fn json_round_trip_and_validation_messages() {
    for (b, _) in grid() {
        let text = json(&b);
        let back = Bsdf::from_json(&text).unwrap_or_else(|e| panic!("{text}: {e}"));
        assert_eq!(back, b, "{text}");
    }
    let ok = Bsdf::from_json(
        r#"{"type":"rough_conductor","alpha":0.3,"eta":0.2,"k":3.9,"distribution":"ggx"}"#,
    )
    .unwrap();
    assert_eq!(ok.name(), "rough_conductor");
    for (text, needle) in [
        (r#"{"type":"dielectric","eta":-1.5}"#, "`eta`"),
        (r#"{"type":"dielectric","eta":0}"#, "`eta` must be positive"),
        (r#"{"type":"lambertian","albedo":1.2}"#, "`albedo`"),
        (
            r#"{"type":"rough_conductor","alpha":0,"eta":0.2,"k":3.9}"#,
            "`alpha`",
        ),
        (
            r#"{"type":"rough_dielectric","alpha":2,"eta":1.5}"#,
            "`alpha`",
        ),
        (r#"{"type":"plastic","albedo":0.5,"eta":0.9}"#, "`eta`"),
        (
            r#"{"type":"oren_nayar","albedo":0.5,"sigma":1.5}"#,
            "`sigma`",
        ),
        (r#"{"type":"conductor","eta":0.2,"k":-1}"#, "`k`"),
        (
            r#"{"type":"oren_nayar_classic","albedo":0.5,"sigma":1.6}"#,
            "`sigma`",
        ),
        (
            r#"{"type":"rough_conductor","alpha":0.3,"fresnel":"none","eta":1.5}"#,
            "`eta`",
        ),
        (
            r#"{"type":"rough_conductor","alpha":0.3,"fresnel":"off"}"#,
            "`fresnel`",
        ),
        (r#"{"type":"rough_conductor","alpha":0.3}"#, "`eta`"),
        (
            r#"{"type":"lambertian","albedo":0.5,"colour":1}"#,
            "unknown field",
        ),
        (r#"{"type":"velvet"}"#, "unknown variant"),
        // Numbers that do not fit f32 (a subnormal would be flushed or kept denormal,
        // 1e39 would become ∞): refused at parse time, naming the field.
        (
            r#"{"type":"lambertian","albedo":1e-39}"#,
            "albedo: underflows f32",
        ),
        (
            r#"{"type":"oren_nayar_classic","albedo":0.5,"sigma":5e-324}"#,
            "sigma: underflows f32",
        ),
        (
            r#"{"type":"rough_conductor","alpha":0.3,"eta":0.2,"k":1e-39}"#,
            "k: underflows f32",
        ),
        (
            r#"{"type":"plastic","albedo":0.5,"eta":1e39}"#,
            "eta: overflows f32",
        ),
        (
            r#"{"type":"rough_conductor","alpha":0.3,"eta":0.2,"k":3.9,"distribution":"phong"}"#,
            "unknown variant",
        ),
    ] {
        let e = Bsdf::from_json(text).expect_err(text);
        assert!(e.contains(needle), "{text}: {e}");
    }
}

#[test]
fn chi2_images_for_a_person_to_look_at() {
    let b = Bsdf::from_json(r#"{"type":"rough_conductor","alpha":0.5,"eta":0.2,"k":3.9}"#).unwrap();
    let t = Chi2Test::new(Domain::Sphere, 50_000, common::seed(), 1e-4).with_resolution(16, 32);
    let tables = contract::chi2_tables(&t, &b, direction(deg(40.0), 0.0));
    // Some draws reflect below the horizon and fail: the counts and ∫ pdf agree on the
    // fraction that succeeds (binomial, 6σ).
    let (obs, exp) = (
        tables.observed.iter().sum::<u64>() as f64,
        tables.expected.iter().sum::<f64>(),
    );
    assert!(
        obs < 50_000.0 && (obs - exp).abs() < 6.0 * (exp * (1.0 - exp / 50_000.0)).sqrt() + 1.0,
        "{obs} {exp}"
    );
    let dir = std::env::temp_dir().join(format!("lightproof-chi2-{}", std::process::id()));
    let files = contract::write_chi2_images(&tables, &dir, "rough_conductor").unwrap();
    assert_eq!(files.len(), 4);
    assert!(files.iter().all(|f| f.exists()));
    let _ = std::fs::remove_dir_all(&dir);
}

/// The exact binomial test of a reflection fraction can fail, on either side, and
/// states the power it has.
#[test]
fn exact_binomial_reflection_test_can_fail() {
    let test = MeanTest::new(FAMILY_ALPHA, ALBEDO_SUITE);
    // R ≈ 2.5e-9 (η = 1.0001) at 20 000 draws: none reflected passes, 5 fail.
    let r = 2.5e-9;
    let ok = test.judge_binomial(0, 20_000, r, 0);
    assert!(ok.passed, "{ok:?}");
    assert!(!test.judge_binomial(5, 20_000, r, 0).passed);
    // A true R′ = R + detectable is seen 99% of the time: k ≥ k_hi there.
    assert!(
        ok.detectable_bias > 0.0 && ok.detectable_bias < 1e-3,
        "{ok:?}"
    );
    // Total internal reflection (R = 1): one transmitted draw fails.
    let tir = test.judge_binomial(20_000, 20_000, 1.0, 0);
    assert!(tir.passed && tir.detectable_bias < 1e-3, "{tir:?}");
    assert!(!test.judge_binomial(19_999, 20_000, 1.0, 0).passed);
    // Non-finite samples fail whatever the count.
    assert!(!test.judge_binomial(0, 20_000, r, 1).passed);
}
