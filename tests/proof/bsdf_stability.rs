//! Stability of every BSDF over its full parameter range and arbitrary directions:
//! `eval`, `pdf` and `sample` return finite, non-negative values (never NaN or Inf),
//! and the sample weight respects the bound the theory gives (rough conductor
//! F G2/G1 ≤ 1; dielectric energy weight weight·η′² ≤ 1; Lambertian = ρ), including at
//! grazing angles, α → 1e-4, η → 1, across the total-internal-reflection boundary and
//! for directions that are not quite unit length, zero, or exactly in the tangent plane.
//!
//! "Every BSDF" is the enum's own list: [`variant_names`] reads the variants from the
//! `Bsdf` type's serde derive, and the strategy ([`arb_variant`]) and the degenerate
//! models ([`degenerate_models`]) are exhaustive matches on `Bsdf` (no `_` arm), so a new
//! variant does not compile here until it has both, and [`every_variant_is_covered`]
//! fails if a variant is missing from either.

// `!(err <= tol)` fails on NaN where `err > tol` would pass it: the negated
// comparisons are the point (as in the library, `src/lib.rs`).
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::common;

use glam::Vec3;
use lightproof::bsdf::microfacet::{Distribution, Masking};
use lightproof::bsdf::*;
use lightproof::math::ONE_MINUS_EPSILON;
use proptest::prelude::*;
use proptest::test_runner::{FileFailurePersistence, RngSeed};

fn arb_distribution() -> impl Strategy<Value = (Distribution, Masking)> {
    (any::<bool>(), any::<bool>()).prop_map(|(b, m)| {
        (
            if b {
                Distribution::Beckmann
            } else {
                Distribution::Ggx
            },
            if m {
                Masking::Uncorrelated
            } else {
                Masking::HeightCorrelated
            },
        )
    })
}

/// log-uniform in [lo, hi], with the end points themselves drawn often.
fn log_range(lo: f32, hi: f32) -> impl Strategy<Value = f32> {
    prop_oneof![
        1 => Just(lo),
        1 => Just(hi),
        6 => (0.0f32..=1.0).prop_map(move |t| (lo.ln() + t * (hi.ln() - lo.ln())).exp().clamp(lo, hi)),
    ]
}

/// Relative indices: the full range, with η → 1 and common values often.
fn arb_eta() -> impl Strategy<Value = f32> {
    prop_oneof![
        3 => log_range(0.01, 100.0),
        1 => prop::sample::select(vec![1.0f32, 1.0001, 0.9999, 1.001, 0.999, 1.0 + 1e-6, 1.33, 1.5, 2.4, 1.0 / 1.5]),
    ]
}

/// The names of every `Bsdf` variant, from the enum itself: serde's derive lists them
/// all in its "unknown variant" error (`expected one of `lambertian`, ...`).
fn variant_names() -> Vec<String> {
    let e = serde_json::from_str::<Bsdf>(r#"{"type": "no such model"}"#)
        .expect_err("not a model")
        .to_string();
    let list = e
        .split("expected one of")
        .nth(1)
        .unwrap_or_else(|| panic!("serde's message changed: {e}"));
    let names: Vec<String> = list
        .split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect();
    assert!(names.len() >= 8, "{e}");
    names
}

/// One model of each variant, by its JSON name (a name not listed here fails
/// [`every_variant_is_covered`]: add the new variant).
fn representative(name: &str) -> Option<Bsdf> {
    Some(match name {
        "lambertian" => Bsdf::Lambertian(Lambertian::new(0.5)),
        "oren_nayar" => Bsdf::OrenNayar(OrenNayar::new(0.5, 0.5)),
        "oren_nayar_classic" => Bsdf::OrenNayarClassic(OrenNayarClassic::new(0.5, 0.5)),
        "conductor" => Bsdf::Conductor(Conductor::new(0.2, 3.9)),
        "dielectric" => Bsdf::Dielectric(Dielectric::new(1.5)),
        "rough_conductor" => Bsdf::RoughConductor(RoughConductor::new(0.3, 0.2, 3.9)),
        "rough_dielectric" => Bsdf::RoughDielectric(RoughDielectric::new(0.3, 1.5)),
        "plastic" => Bsdf::Plastic(Plastic::new(0.5, 1.5)),
        _ => return None,
    })
}

/// A model of every variant of the enum.
fn every_variant() -> Vec<Bsdf> {
    variant_names()
        .iter()
        .map(|n| representative(n).unwrap_or_else(|| panic!("no representative of `{n}`")))
        .collect()
}

/// The parameter strategy of a variant (`kind`'s parameters are ignored): an
/// exhaustive match, so a new variant needs its strategy to compile.
fn arb_variant(kind: &Bsdf) -> BoxedStrategy<Bsdf> {
    match kind {
        Bsdf::Lambertian(_) => (0.0f32..=1.0)
            .prop_map(|r| Bsdf::Lambertian(Lambertian::new(r)))
            .boxed(),
        Bsdf::OrenNayar(_) => (0.0f32..=1.0, 0.0f32..=1.0)
            .prop_map(|(r, s)| Bsdf::OrenNayar(OrenNayar::new(r, s)))
            .boxed(),
        // σ over its whole range [0, π/2] radians, the ends often.
        Bsdf::OrenNayarClassic(_) => (
            0.0f32..=1.0,
            prop_oneof![
                1 => Just(0.0f32),
                1 => Just(std::f32::consts::FRAC_PI_2),
                4 => 0.0f32..=std::f32::consts::FRAC_PI_2,
            ],
        )
            .prop_map(|(r, s)| Bsdf::OrenNayarClassic(OrenNayarClassic::new(r, s)))
            .boxed(),
        Bsdf::Conductor(_) => (
            log_range(1e-3, 100.0),
            prop_oneof![Just(0.0f32), log_range(1e-3, 100.0)],
        )
            .prop_map(|(e, k)| Bsdf::Conductor(Conductor::new(e, k)))
            .boxed(),
        Bsdf::Dielectric(_) => arb_eta()
            .prop_map(|e| Bsdf::Dielectric(Dielectric::new(e)))
            .boxed(),
        Bsdf::RoughConductor(_) => (
            log_range(1e-4, 1.0),
            log_range(1e-3, 100.0),
            prop_oneof![Just(0.0f32), log_range(1e-3, 100.0)],
            arb_distribution(),
        )
            .prop_map(|(a, e, k, (d, m))| {
                Bsdf::RoughConductor(RoughConductor {
                    alpha: a,
                    // k > 50 (6% of draws) stands for F ≡ 1 (`fresnel: none`), which has no index.
                    eta: (k <= 50.0).then_some(e),
                    k: (k <= 50.0).then_some(k),
                    fresnel: if k <= 50.0 {
                        FresnelMode::Conductor
                    } else {
                        FresnelMode::None
                    },
                    distribution: d,
                    masking: m,
                })
            })
            .boxed(),
        // η within MIN_ETA_GAP of 1 is refused for a rough dielectric (its lobe is not
        // resolved there): the strategy keeps to what `validate` accepts.
        Bsdf::RoughDielectric(_) => (
            log_range(1e-4, 1.0),
            arb_eta().prop_filter("|η − 1| ≥ MIN_ETA_GAP", |e| {
                (e - 1.0).abs() >= lightproof::bsdf::rough_dielectric::MIN_ETA_GAP
            }),
            arb_distribution(),
        )
            .prop_map(|(a, e, (d, m))| {
                Bsdf::RoughDielectric(RoughDielectric {
                    alpha: a,
                    eta: e,
                    distribution: d,
                    masking: m,
                })
            })
            .boxed(),
        Bsdf::Plastic(_) => (
            0.0f32..=1.0,
            prop_oneof![Just(1.0f32), log_range(1.0, 10.0)],
        )
            .prop_map(|(r, e)| Bsdf::Plastic(Plastic::new(r, e)))
            .boxed(),
    }
}

/// Every variant, equally often.
fn arb_bsdf() -> impl Strategy<Value = Bsdf> {
    proptest::strategy::Union::new(every_variant().iter().map(arb_variant).collect::<Vec<_>>())
}

/// Directions: uniform, grazing (|z| down to 1e-30 and exactly 0), poles, and lengths
/// off one by up to 1e-3.
fn arb_dir() -> impl Strategy<Value = Vec3> {
    let uniform = (-1.0f32..=1.0, 0.0f32..std::f32::consts::TAU).prop_map(|(z, phi)| {
        let r = (1.0 - z * z).max(0.0).sqrt();
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    });
    let grazing = (
        prop_oneof![Just(0.0f32), log_range(1e-30, 1e-2)],
        any::<bool>(),
        0.0f32..std::f32::consts::TAU,
    )
        .prop_map(|(z, below, phi)| {
            let z = if below { -z } else { z };
            let r = (1.0 - z * z).max(0.0).sqrt();
            Vec3::new(r * phi.cos(), r * phi.sin(), z)
        });
    let special = prop::sample::select(vec![
        Vec3::Z,
        -Vec3::Z,
        Vec3::X,
        Vec3::new(1e-20, 0.0, 1.0),
        Vec3::new(0.0, 0.0, -1.0),
    ]);
    (
        prop_oneof![4 => uniform, 3 => grazing, 1 => special],
        prop_oneof![3 => Just(1.0f32), 1 => 0.999f32..1.001],
    )
        .prop_map(|(v, s)| v * s)
}

fn arb_u() -> impl Strategy<Value = Vec3> {
    let c = prop_oneof![4 => 0.0f32..1.0, 1 => Just(0.0f32), 1 => Just(ONE_MINUS_EPSILON)];
    (c.clone(), c.clone(), c).prop_map(|(a, b, c)| Vec3::new(a, b, c))
}

fn check(b: &Bsdf, wo: Vec3, wi: Vec3, u: Vec3) -> Result<(), String> {
    let f = b.eval(wo, wi);
    let p = b.pdf(wo, wi);
    if !(f.is_finite() && f >= 0.0) {
        return Err(format!("eval = {f}"));
    }
    if !(p.is_finite() && p >= 0.0) {
        return Err(format!("pdf = {p}"));
    }
    if let Some(s) = b.sample(wo, u) {
        if !(s.wi.is_finite() && s.weight.is_finite() && s.pdf.is_finite() && s.eta.is_finite()) {
            return Err(format!("non-finite sample {s:?}"));
        }
        if !(s.weight >= 0.0 && s.pdf > 0.0 && s.eta > 0.0) {
            return Err(format!("negative weight or non-positive pdf {s:?}"));
        }
        if !((s.wi.length() - 1.0).abs() <= 2e-3) {
            return Err(format!("|wi| = {} in {s:?}", s.wi.length()));
        }
        let energy = s.weight * s.eta * s.eta;
        let bound = match b {
            Bsdf::Lambertian(l) => Some(l.albedo),
            Bsdf::Conductor(_)
            | Bsdf::RoughConductor(_)
            | Bsdf::Dielectric(_)
            | Bsdf::RoughDielectric(_) => Some(1.0),
            // Oren–Nayar's weights exceed ρ by design (ρ(A + B·tan θo)-like terms, and the
            // classic form is not energy conserving); a plastic's base weight exceeds 1
            // (`bsdf_contract::energy_bound`): no per-sample bound to check.
            Bsdf::OrenNayar(_) | Bsdf::OrenNayarClassic(_) | Bsdf::Plastic(_) => None,
        };
        if let Some(bound) = bound
            && !(energy <= bound * (1.0 + 1e-5) + 1e-6)
        {
            return Err(format!("energy weight {energy} > {bound} in {s:?}"));
        }
        // The sampled direction's own eval and pdf are finite too.
        let (f2, p2) = (b.eval(wo, s.wi), b.pdf(wo, s.wi));
        if !(f2.is_finite() && f2 >= 0.0 && p2.is_finite() && p2 >= 0.0) {
            return Err(format!("eval {f2} / pdf {p2} at the sampled wi {s:?}"));
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 10_000,
        failure_persistence: Some(Box::new(FileFailurePersistence::Direct("tests/proof/bsdf_stability.proptest-regressions"))),
        // Fixed and recorded like every other seed: LIGHTPROOF_SEED varies it.
        rng_seed: RngSeed::Fixed(common::seed()),
        ..ProptestConfig::default()
    })]

    #[test]
    fn finite_non_negative_and_bounded(b in arb_bsdf(), wo in arb_dir(), wi in arb_dir(), u in arb_u()) {
        prop_assert!(b.validate().is_ok(), "{:?}: {:?}", b, b.validate());
        if let Err(e) = check(&b, wo, wi, u) {
            return Err(TestCaseError::fail(format!("{} wo = {wo:?} wi = {wi:?} u = {u:?}: {e}", serde_json::to_string(&b).unwrap())));
        }
    }
}

/// Every model × a fixed set of nasty directions and uniforms, exhaustively.
#[test]
fn degenerate_directions_exhaustively() {
    let dirs = [
        Vec3::Z,
        -Vec3::Z,
        Vec3::X,
        -Vec3::Y,
        Vec3::ZERO,
        Vec3::new(1.0, 0.0, 1e-7).normalize(),
        Vec3::new(1.0, 0.0, -1e-7).normalize(),
        Vec3::new(1.0, 0.0, 1e-30),
        Vec3::new(0.6, 0.0, 0.8) * 1.001,
        Vec3::new(-0.6, 0.0, -0.8) * 0.999,
        Vec3::new(-1.0, 0.0, 1e-7).normalize(),
        // Near the critical angle of η = 1.5 from inside: sin θ = 1/1.5.
        Vec3::new(1.0 / 1.5, 0.0, -(1.0f32 - 1.0 / 2.25).sqrt()),
    ];
    let us = [
        Vec3::ZERO,
        Vec3::splat(0.5),
        Vec3::splat(ONE_MINUS_EPSILON),
        Vec3::new(0.0, ONE_MINUS_EPSILON, 0.5),
    ];
    let models: Vec<Bsdf> = every_variant().iter().flat_map(degenerate_models).collect();
    for b in &models {
        for wo in dirs {
            for wi in dirs {
                for u in us {
                    if let Err(e) = check(b, wo, wi, u) {
                        panic!(
                            "{} wo = {wo} wi = {wi} u = {u}: {e}",
                            serde_json::to_string(b).unwrap()
                        );
                    }
                }
            }
        }
    }
}

/// The hard parameter settings of a variant (`kind`'s parameters are ignored): an
/// exhaustive match, so a new variant needs its settings to compile.
fn degenerate_models(kind: &Bsdf) -> Vec<Bsdf> {
    let mut models = Vec::new();
    let alphas = [1e-4, 1e-2, 1.0];
    let dists = [Distribution::Ggx, Distribution::Beckmann];
    match kind {
        Bsdf::RoughDielectric(_) => {
            for alpha in alphas {
                for dist in dists {
                    // 1.001 and 0.999: the least |η − 1| it accepts (MIN_ETA_GAP).
                    for eta in [1.001, 0.999, 1.5, 1.0 / 1.5, 100.0, 0.01] {
                        models.push(Bsdf::RoughDielectric(RoughDielectric {
                            alpha,
                            eta,
                            distribution: dist,
                            masking: Masking::HeightCorrelated,
                        }));
                    }
                }
            }
        }
        Bsdf::RoughConductor(_) => {
            for alpha in alphas {
                for dist in dists {
                    models.push(Bsdf::RoughConductor(RoughConductor {
                        alpha,
                        eta: Some(1.0),
                        k: Some(0.0),
                        fresnel: FresnelMode::Conductor,
                        distribution: dist,
                        masking: Masking::Uncorrelated,
                    }));
                    models.push(Bsdf::RoughConductor(RoughConductor {
                        alpha,
                        eta: Some(0.2),
                        k: Some(3.9),
                        fresnel: FresnelMode::Conductor,
                        distribution: dist,
                        masking: Masking::HeightCorrelated,
                    }));
                    models.push(Bsdf::RoughConductor(RoughConductor {
                        distribution: dist,
                        ..RoughConductor::white(alpha)
                    }));
                }
            }
        }
        Bsdf::Dielectric(_) => {
            for eta in [1.0, 1.0001, 1.5, 0.01, 100.0] {
                models.push(Bsdf::Dielectric(Dielectric::new(eta)));
            }
        }
        Bsdf::Conductor(_) => models.extend([
            Bsdf::Conductor(Conductor::new(1.0, 0.0)),
            Bsdf::Conductor(Conductor::new(0.001, 100.0)),
        ]),
        Bsdf::Lambertian(_) => models.extend([
            Bsdf::Lambertian(Lambertian::new(1.0)),
            Bsdf::Lambertian(Lambertian::new(0.0)),
        ]),
        Bsdf::OrenNayar(_) => models.extend([
            Bsdf::OrenNayar(OrenNayar::new(1.0, 1.0)),
            Bsdf::OrenNayar(OrenNayar::new(1.0, 0.0)),
        ]),
        Bsdf::OrenNayarClassic(_) => models.extend([
            Bsdf::OrenNayarClassic(OrenNayarClassic::new(1.0, std::f32::consts::FRAC_PI_2)),
            Bsdf::OrenNayarClassic(OrenNayarClassic::new(1.0, 0.1)),
            Bsdf::OrenNayarClassic(OrenNayarClassic::new(0.0, 0.0)),
        ]),
        Bsdf::Plastic(_) => models.extend([
            Bsdf::Plastic(Plastic::new(1.0, 1.0)),
            Bsdf::Plastic(Plastic::new(0.0, 1.0)),
            Bsdf::Plastic(Plastic::new(1.0, 10.0)),
        ]),
    }
    models
}

/// The strategy and the degenerate list cover every variant of `Bsdf` (serde's list of
/// the enum's variants), and nothing else.
#[test]
fn every_variant_is_covered() {
    use proptest::strategy::ValueTree;
    use std::collections::BTreeSet;
    let names: BTreeSet<String> = variant_names().into_iter().collect();
    let missing: Vec<&String> = names
        .iter()
        .filter(|n| representative(n).is_none())
        .collect();
    assert!(
        missing.is_empty(),
        "no representative (nor strategy, nor degenerate models) for {missing:?}"
    );
    for b in every_variant() {
        assert!(
            names.contains(b.name()),
            "{} is not a variant name",
            b.name()
        );
        for m in degenerate_models(&b) {
            assert_eq!(
                m.name(),
                b.name(),
                "degenerate_models({}) gives {m:?}",
                b.name()
            );
            m.validate().unwrap_or_else(|e| panic!("{m:?}: {e}"));
        }
        assert!(
            !degenerate_models(&b).is_empty(),
            "no degenerate {}",
            b.name()
        );
    }
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let strategy = arb_bsdf();
    let mut seen = BTreeSet::new();
    for _ in 0..2000 {
        let b = strategy.new_tree(&mut runner).unwrap().current();
        seen.insert(b.name().to_string());
    }
    assert_eq!(seen, names, "the strategy draws these variants");
}
