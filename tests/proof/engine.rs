//! The engine's proof: white furnaces, estimator agreement, radiance invariance,
//! reciprocity of the whole transport, translation invariance far from the origin, and
//! bit-identical results whatever the thread count.

use crate::common;

use lightproof::case::{Case, CaseDesc};
use lightproof::sampling::SamplerKind;
use lightproof::stats::{MeanTest, Verdict};
use lightproof::transport::Estimator;
use lightproof::transport::engine::{Estimate, RunSpec};
use lightproof::verdict::judge;
use std::path::Path;

/// The three estimators every multi-estimator test runs.
const ESTIMATORS: [Estimator; 3] = [Estimator::Light, Estimator::Bsdf, Estimator::Mis];
/// White furnaces: (albedo ρ, samples, the detectable relative bias each verdict must
/// reach at 99% power). Measured at seeds default, 1, 2, 3 (family of 19): ρ = 0.5
/// sees 0.39–0.80% (light 0.4%, MIS 0.6%, BSDF 0.8%), ρ = 0.9 1.58–1.76% and ρ = 0.99
/// (100 bounces on average, 2¹⁵ paths) 3.71–3.82%; the bounds leave a margin of about
/// 1.25× over the worst seen.
const FURNACES: [(f64, u64, f64); 3] = [
    (0.5, 1 << 17, 0.01),
    (0.9, 1 << 17, 0.022),
    (0.99, 1 << 15, 0.048),
];
/// The distances of the radiance-invariance test.
const DISTANCES: [f64; 3] = [1.0, 100.0, 1e4];
/// The two-sample comparisons of `estimators_agree_with_each_other`.
const AGREEMENTS: usize = 2;
/// Statistical decisions in this file (Šidák family), counted from the lists that make
/// them: every furnace × estimator, the convex object × estimator, the agreement pairs,
/// the invariance distances, reciprocity (1), translation (1) and the floor under a
/// sphere light (`FLOOR_VERDICTS`): 9 + 3 + 2 + 3 + 1 + 1 + 6.
/// (`a_wrong_reference_is_rejected` must fail and the NaN tests judge at level α alone:
/// neither is a pass the family has to cover.)
const FAMILY: usize = FURNACES.len() * ESTIMATORS.len()
    + ESTIMATORS.len()
    + AGREEMENTS
    + DISTANCES.len()
    + 1
    + 1
    + FLOOR_VERDICTS;
/// `a_floor_touching_a_sphere_light_is_lit_by_light_sampling`: three estimators at
/// ρ = 5e-4 and at 5e-5.
const FLOOR_VERDICTS: usize = 6;
/// The detectable relative bias its verdicts must reach at 99% power (2²⁰ samples: light
/// 0.37–0.39%, MIS 0.15%, BSDF within the f32 bound).
const FLOOR_POWER: f64 = 0.005;
const ALPHA: f64 = 1e-4;
/// The detectable relative bias the convex object's verdicts must reach at 99% power
/// (measured at seeds default, 1, 2, 3: light 2.45%, MIS 0.48%; BSDF sampling is exact
/// there, every sample ρ, judged within the f32 bound).
const CONVEX_POWER: f64 = 0.031;
/// The detectable relative difference (99% power) each two-sample comparison must
/// reach, measured at seeds default, 1, 2, 3 with a margin of about 1.2×: estimator
/// agreement light vs BSDF 3.72% (the BSDF-sampled irradiance of a small tilted square
/// is the noisy side), translation 0.40%, reciprocity 6.2% (a 5 mm disk light seen
/// only through the floor's scattering).
const AGREEMENT_POWER: f64 = 0.045;
const TRANSLATION_POWER: f64 = 0.005;
const RECIPROCITY_POWER: f64 = 0.075;

#[test]
fn the_family_counts_every_decision() {
    assert_eq!(FAMILY, 25);
}

fn case(json: &str) -> Case {
    let desc: CaseDesc = serde_json::from_str(json).expect("valid case JSON");
    Case::from_desc(desc, Path::new("<engine test>")).unwrap_or_else(|e| panic!("{e}"))
}

fn spec(samples: u64, salt: u64) -> RunSpec {
    RunSpec {
        samples: samples * common::scale(),
        sampler: SamplerKind::Independent,
        seed: common::seed() ^ salt,
    }
}

/// [`common::same_mean`] at this module's family: the verdict and its detectable
/// relative difference (99% power).
fn same_mean(a: &Estimate, b: &Estimate) -> (Verdict, f64) {
    let v = common::same_mean(a, b, ALPHA, FAMILY);
    let rel = v.detectable_relative_bias;
    (v, rel)
}

fn furnace(albedo: f64) -> Case {
    case(&format!(
        r#"{{ "name": "furnace {albedo}", "teaches": "Le/(1-ρ)",
        "scene": {{ "materials": {{ "m": {{ "type": "lambertian", "albedo": {albedo} }} }},
          "shapes": [ {{ "geometry": {{ "type": "sphere", "center": [0,0,0], "radius": 1 }}, "material": "m",
                        "flip_normals": true, "emission": {{ "radiance": 1 }} }} ] }},
        "measure": {{ "radiance": {{ "at": [0.3, 0.1, -0.2], "direction": [0.2, -0.6, 0.77] }} }},
        "reference": {{ "closed_form": "furnace_closed_enclosure", "emitted_radiance": 1, "albedo": {albedo} }},
        "estimators": ["light", "bsdf", "mis"] }}"#
    ))
}

/// Closed sphere furnaces with Russian roulette: L = Le/(1 − ρ) for every estimator,
/// each verdict required to see the relative bias [`FURNACES`] states for its ρ (about
/// 0.4–0.8% at ρ = 0.5, 1.6% at ρ = 0.9 and 3.7% at ρ = 0.99, whose paths average 100
/// bounces).
#[test]
fn white_furnace_closed_sphere() {
    let mut report = Vec::new();
    for (k, (rho, n, power)) in FURNACES.into_iter().enumerate() {
        let c = furnace(rho);
        for (j, est) in ESTIMATORS.into_iter().enumerate() {
            let e = c.estimate(est, &spec(n, (k * 3 + j) as u64));
            let v = judge(
                &e,
                SamplerKind::Independent,
                c.reference.unwrap(),
                ALPHA,
                FAMILY,
            );
            report.push(format!(
                "ρ={rho} {}: {:.5} ± {:.5} (det {:.2}%)",
                est.name(),
                v.estimate,
                v.std_error,
                100.0 * v.detectable_relative_bias
            ));
            assert!(v.passed, "furnace ρ={rho} {}: {:?}", est.name(), v.reason);
            assert!(
                v.detectable_relative_bias <= power,
                "furnace ρ={rho} {}: detectable relative bias {:.3}% > {}%",
                est.name(),
                100.0 * v.detectable_relative_bias,
                100.0 * power
            );
        }
    }
    println!("{}", report.join("\n"));
}

/// A convex diffuse sphere under constant radiance 1 reflects ρ, seen from outside.
#[test]
fn convex_object_under_constant_sky() {
    let c = case(
        r#"{ "name": "convex", "teaches": "ρ",
        "scene": { "materials": { "m": { "type": "lambertian", "albedo": 0.7 } },
          "shapes": [ { "geometry": { "type": "sphere", "center": [0,0,0], "radius": 2 }, "material": "m" } ],
          "emitters": [ { "type": "constant", "radiance": 1 } ] },
        "measure": { "radiance": { "at": [0.5, 0, 9], "direction": [0, 0, -1] } },
        "reference": { "closed_form": "furnace_convex_object", "albedo": 0.7, "radiance": 1 },
        "estimators": ["light", "bsdf", "mis"] }"#,
    );
    assert_eq!(c.plan.effects.max_bounces, Some(1));
    assert!(!c.plan.effects.occlusion.simulated);
    for (j, est) in ESTIMATORS.into_iter().enumerate() {
        let e = c.estimate(est, &spec(1 << 17, 100 + j as u64));
        let v = judge(&e, SamplerKind::Independent, 0.7, ALPHA, FAMILY);
        println!(
            "convex {}: {:.5} ± {:.5} (det {:.3}%)",
            est.name(),
            v.estimate,
            v.std_error,
            100.0 * v.detectable_relative_bias
        );
        assert!(v.passed, "{}: {:?}", est.name(), v.reason);
        assert!(
            v.detectable_relative_bias <= CONVEX_POWER,
            "{}: detectable relative bias {:.3}% > {}%",
            est.name(),
            100.0 * v.detectable_relative_bias,
            100.0 * CONVEX_POWER
        );
    }
}

/// A Lambertian floor (albedo 0.5) under a sphere light (r = 0.5, L = 1) resting on
/// it, seen 1.5 away at a point ρ from the contact: its radiance is (ρ_d/π)·E, E the
/// sphere's irradiance at the point (the oracle's `sphere_irradiance`, tilted receiver),
/// ≈ 0.5. At ρ = 5e-4 and 5e-5 the gap ρ²/(2r) (2.5e-7, 2.5e-9) lies within the sphere's
/// f32 band (1.3e-6 here), where a free point is sampled as a point of the sphere, by
/// area: `light` read 0 (issue 43). A floor point is off the sphere however thin the gap,
/// so light sampling takes the cone, its direction and distance formed in f64. BSDF
/// sampling, and so MIS, read 0 and 0.20 at 5e-5 until session 44: the sphere's near hit
/// lay within the f32 error bound of its c = |o − centre|² − r², which now hands it to
/// f64 roots (`shape::intersect_sphere_near_surface`).
#[test]
fn a_floor_touching_a_sphere_light_is_lit_by_light_sampling() {
    let floor = |rho: f64, estimators: &str| {
        let (x0, r) = (1.5f64, 0.5f64);
        // Camera on the +x side, its ray reaching the floor at (ρ, 0, 0) with slope ρ
        // (under the sphere: a ray steeper than 4ρ/(2r) would enter it first).
        let z = (rho * (x0 - rho)) as f32 as f64;
        let n = ((x0 - rho).powi(2) + z * z).sqrt();
        let d = [(rho - x0) / n, 0.0, -z / n].map(|x| x as f32 as f64);
        case(&format!(
            r#"{{ "name": "floor under a sphere light", "teaches": "issue 43",
            "scene": {{ "materials": {{ "g": {{ "type": "lambertian", "albedo": 0.5 }} }},
              "shapes": [ {{ "geometry": {{ "type": "sphere", "center": [0, 0, {r}], "radius": {r} }},
                            "emission": {{ "radiance": 1 }} }},
                          {{ "geometry": {{ "type": "rectangle", "corner": [-2, -2, 0],
                                           "edge_u": [4, 0, 0], "edge_v": [0, 4, 0] }}, "material": "g" }} ] }},
            "measure": {{ "radiance": {{ "at": [{x0}, 0, {z:e}], "direction": [{:e}, 0, {:e}] }} }},
            "reference": {{ "closed_form": "sphere_irradiance", "point": [{rho:e}, 0, 0],
              "normal": [0, 0, 1], "center": [0, 0, {r}], "radius": {r}, "radiance": 1,
              "scale": {} }},
            "estimators": {estimators} }}"#,
            d[0],
            d[2],
            0.5 / std::f64::consts::PI
        ))
    };
    let runs = [
        (5e-4, &ESTIMATORS[..], r#"["light", "bsdf", "mis"]"#),
        (5e-5, &ESTIMATORS[..], r#"["light", "bsdf", "mis"]"#),
    ];
    assert_eq!(
        runs.iter().map(|r| r.1.len()).sum::<usize>(),
        FLOOR_VERDICTS
    );
    for (k, (rho, ests, names)) in runs.into_iter().enumerate() {
        let c = floor(rho, names);
        let reference = c.reference.expect("the oracle's sphere irradiance");
        assert!((reference - 0.5).abs() < 1e-5, "{reference}");
        for (j, &est) in ests.iter().enumerate() {
            let e = c.estimate(est, &spec(1 << 20, 1100 + 10 * k as u64 + j as u64));
            let v = judge(&e, SamplerKind::Independent, reference, ALPHA, FAMILY);
            println!(
                "floor ρ = {rho:e} {}: {:.6} ± {:.6} vs {reference:.6}, z = {:+.2} (det {:.3}%)",
                est.name(),
                v.estimate,
                v.std_error,
                v.z,
                100.0 * v.detectable_relative_bias
            );
            assert!(v.passed, "ρ = {rho:e} {}: {:?}", est.name(), v.reason);
            assert!(
                v.detectable_relative_bias <= FLOOR_POWER,
                "ρ = {rho:e} {}: detectable relative bias {:.3}%",
                est.name(),
                100.0 * v.detectable_relative_bias
            );
        }
    }
}

/// Emitter sampling, BSDF sampling and MIS agree with each other (two-sample tests),
/// not only with the closed form.
#[test]
fn estimators_agree_with_each_other() {
    let c = case(
        r#"{ "name": "tilted square", "teaches": "agreement",
        "scene": { "shapes": [ { "geometry": { "type": "rectangle", "corner": [-0.5, 0.2, 1], "edge_u": [0, 1, 0.4], "edge_v": [1.5, 0, 0.2] },
                                 "emission": { "radiance": 2 } } ] },
        "measure": { "irradiance": { "at": [0, 0, 0], "normal": [0.2, 0, 1] } },
        "estimators": ["light", "bsdf", "mis"] }"#,
    );
    let l = c.estimate(Estimator::Light, &spec(1 << 17, 200));
    let b = c.estimate(Estimator::Bsdf, &spec(1 << 18, 201));
    let m = c.estimate(Estimator::Mis, &spec(1 << 17, 202));
    assert!(
        l.batches.total.mean > 0.1,
        "the emitter must face the receiver"
    );
    let pairs = [(&l, &b, "light vs bsdf"), (&l, &m, "light vs mis")];
    assert_eq!(pairs.len(), AGREEMENTS);
    for (x, y, what) in pairs {
        let (v, det) = same_mean(x, y);
        println!(
            "{what}: z = {:+.2}, detectable relative difference {:.3}%",
            v.z,
            100.0 * det
        );
        assert!(v.passed, "{what}: {v:?}");
        assert!(
            det <= AGREEMENT_POWER,
            "{what}: detectable {:.3}%",
            100.0 * det
        );
    }
}

/// Radiance is invariant along a ray in vacuum: an emitter of radiance L looks equally
/// bright from 1, 100 and 10⁴ units away.
#[test]
fn radiance_is_invariant_along_a_ray() {
    for d in DISTANCES {
        let c = case(&format!(
            r#"{{ "name": "invariance", "teaches": "L is constant along a ray",
            "scene": {{ "shapes": [ {{ "geometry": {{ "type": "rectangle", "corner": [-1e4, -1e4, 0], "edge_u": [2e4, 0, 0], "edge_v": [0, 2e4, 0] }},
                                     "emission": {{ "radiance": 3.5 }} }} ] }},
            "measure": {{ "radiance": {{ "at": [0.1, 0.2, {d}], "direction": [0.01, 0.02, -1] }} }},
            "reference": {{ "closed_form": "radiance_across_interface", "radiance": 3.5, "n1": 1, "n2": 1 }},
            "estimators": ["mis"] }}"#
        ));
        let e = c.estimate(Estimator::Mis, &spec(1 << 10, 300));
        let v = judge(
            &e,
            SamplerKind::Independent,
            c.reference.unwrap(),
            ALPHA,
            FAMILY,
        );
        assert!(v.passed, "distance {d}: {:?}", v.reason);
        // Every sample sees the emitter: an exact verdict (f32 bound γ₁₂₈ ≈ 7.6e-6), or a
        // statistical one that must see 0.5%.
        assert!(
            v.detectable_relative_bias <= 0.005,
            "distance {d}: detectable relative bias {}",
            v.detectable_relative_bias
        );
    }
}

fn reciprocity_case(
    light_at: [f64; 3],
    light_n: [f64; 3],
    sensor_at: [f64; 3],
    sensor_n: [f64; 3],
) -> Case {
    let f = |a: [f64; 3]| format!("[{}, {}, {}]", a[0], a[1], a[2]);
    let r = 0.005;
    case(&format!(
        r#"{{ "name": "reciprocity", "teaches": "transport is reciprocal",
        "scene": {{ "materials": {{ "floor": {{ "type": "lambertian", "albedo": 0.8 }} }},
          "shapes": [
            {{ "geometry": {{ "type": "rectangle", "corner": [-3, -3, 0], "edge_u": [6, 0, 0], "edge_v": [0, 6, 0] }}, "material": "floor" }},
            {{ "geometry": {{ "type": "rectangle", "corner": [0, -3, 0.2], "edge_u": [0, 6, 0], "edge_v": [0, 0, 3] }} }},
            {{ "geometry": {{ "type": "disk", "center": {}, "normal": {}, "radius": {r} }}, "emission": {{ "radiance": 1 }} }}
          ] }},
        "measure": {{ "irradiance": {{ "at": {}, "normal": {} }} }},
        "estimators": ["mis"] }}"#,
        f(light_at),
        f(light_n),
        f(sensor_at),
        f(sensor_n)
    ))
}

/// Reciprocity of the whole transport: a tiny Lambertian disk emitter at A seen by a
/// cosine sensor at B equals the swapped configuration (the adjoint of a cosine sensor
/// is a Lambertian emitter); a wall between them leaves only light scattered by the floor.
#[test]
fn transport_is_reciprocal() {
    let (a, na) = ([-1.0, 0.3, 1.0], [0.3, 0.0, -1.0]);
    let (b, nb) = ([1.2, -0.4, 0.7], [-0.5, 0.2, -1.0]);
    let ab = reciprocity_case(a, na, b, nb).estimate(Estimator::Mis, &spec(1 << 18, 400));
    let ba = reciprocity_case(b, nb, a, na).estimate(Estimator::Mis, &spec(1 << 18, 401));
    let (v, det) = same_mean(&ab, &ba);
    assert!(ab.batches.total.mean > 0.0);
    println!(
        "reciprocity: z = {:+.2}, detectable relative difference {:.3}%",
        v.z,
        100.0 * det
    );
    assert!(
        v.passed,
        "E(A→B) = {:.6e}, E(B→A) = {:.6e}, z = {:.2}",
        ab.batches.total.mean, ba.batches.total.mean, v.z
    );
    assert!(det <= RECIPROCITY_POWER, "detectable {:.3}%", 100.0 * det);
}

fn disk_case(offset: f64) -> Case {
    let o = |x: f64, y: f64, z: f64| format!("[{}, {}, {}]", x + offset, y - offset, z + offset);
    case(&format!(
        r#"{{ "name": "far disk", "teaches": "translation invariance",
        "scene": {{ "materials": {{ "m": {{ "type": "lambertian", "albedo": 0.6 }} }},
          "shapes": [ {{ "geometry": {{ "type": "disk", "center": {}, "normal": [0, 0, -1], "radius": 1 }}, "emission": {{ "radiance": 1 }} }},
                      {{ "geometry": {{ "type": "sphere", "center": {}, "radius": 0.4 }}, "material": "m" }} ] }},
        "measure": {{ "irradiance": {{ "at": {}, "normal": [0, 0, 1] }} }},
        "estimators": ["mis"] }}"#,
        o(0.0, 0.0, 2.0),
        o(0.8, 0.0, 0.6),
        o(0.0, 0.0, 0.0)
    ))
}

/// The same scene translated by 1e5 units in every axis gives the same answer.
#[test]
fn translation_far_from_the_origin() {
    let near = disk_case(0.0).estimate(Estimator::Mis, &spec(1 << 17, 500));
    let far = disk_case(1e5).estimate(Estimator::Mis, &spec(1 << 17, 501));
    let (v, det) = same_mean(&near, &far);
    println!(
        "translation: z = {:+.2}, detectable relative difference {:.3}%",
        v.z,
        100.0 * det
    );
    assert!(
        v.passed,
        "near {:.6} far {:.6} z {:.2}",
        near.batches.total.mean, far.batches.total.mean, v.z
    );
    assert!(det <= TRANSLATION_POWER, "detectable {:.3}%", 100.0 * det);
}

/// Same seed, 1 or 2 threads: bit-identical accumulators.
#[test]
fn deterministic_across_thread_counts() {
    let c = disk_case(0.0);
    let s = spec(1 << 14, 600);
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| c.estimate(Estimator::Mis, &s));
    let two = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap()
        .install(|| c.estimate(Estimator::Mis, &s));
    assert_eq!(one.batches, two.batches);
    for sampler in [SamplerKind::Stratified, SamplerKind::Sobol] {
        let s = RunSpec { sampler, ..s };
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap()
            .install(|| c.estimate(Estimator::Mis, &s));
        let two = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap()
            .install(|| c.estimate(Estimator::Mis, &s));
        assert_eq!(one.batches, two.batches);
    }
}

/// A test must be able to fail: a furnace judged against a reference 1% off is rejected.
#[test]
fn a_wrong_reference_is_rejected() {
    let c = furnace(0.5);
    let e = c.estimate(Estimator::Light, &spec(1 << 17, 700));
    let v = MeanTest::new(ALPHA, FAMILY).judge(&e.batches.total, 2.0 * 1.01);
    assert!(!v.passed, "{v:?}");
}

// ---------------------------------------------------------------------------------
// Nothing is masked: a NaN injected through each path of the engine reaches the
// accumulator as a non-finite sample and fails the verdict (README: "Non-finite
// samples fail a verdict outright; they are never dropped").
// ---------------------------------------------------------------------------------

/// A disk light of radiance 1 at height 2 over a Lambertian floor, measured as
/// irradiance on the floor (next-event and BSDF-found emission) or as the floor's
/// radiance (one scattering: BSDF evaluation and sampling).
fn lit_floor(measure: &str) -> Case {
    case(&format!(
        r#"{{ "name": "nan injection", "teaches": "nothing is masked",
        "scene": {{ "materials": {{ "floor": {{ "type": "lambertian", "albedo": 0.5 }} }},
          "shapes": [
            {{ "geometry": {{ "type": "disk", "center": [0,0,2], "normal": [0,0,-1], "radius": 1 }},
               "emission": {{ "radiance": 1 }} }},
            {{ "geometry": {{ "type": "rectangle", "corner": [-5,-5,0], "edge_u": [10,0,0], "edge_v": [0,10,0] }},
               "material": "floor" }} ] }},
        "measure": {measure},
        "reference": {{ "closed_form": "disk_irradiance_on_axis", "radius": 1, "height": 2, "radiance": 1 }},
        "estimators": ["light", "bsdf", "mis"] }}"#
    ))
}

const IRRADIANCE: &str = r#"{ "irradiance": { "at": [0,0,0], "normal": [0,0,1] } }"#;
const FLOOR_RADIANCE: &str = r#"{ "radiance": { "at": [0.3,0.2,1], "direction": [0.1,0.2,-1] } }"#;

/// Run `est` on `c` and require non-finite samples and a failed verdict.
fn assert_counted(c: &Case, est: Estimator, what: &str) {
    let e = c.estimate(est, &spec(1 << 12, 0x7a7a));
    let nf = e.batches.total.non_finite;
    assert!(
        nf > 0,
        "{what} ({}): the NaN was masked, non_finite = 0",
        est.name()
    );
    let v = judge(&e, SamplerKind::Independent, 1.0, ALPHA, 1);
    assert!(
        !v.passed && v.reason.as_deref().unwrap_or("").contains("non-finite"),
        "{what} ({}): {v:?}",
        est.name()
    );
}

/// A white closed sphere (albedo 1, no `max_depth`) has an infinite answer; roulette
/// keeps nearly every path (β stays 1 up to f32 rounding), so paths reach the guard of
/// 2¹⁶ scatterings (BSDF sampling alone, the cheapest). Each such path is +∞, counted, and the verdict fails: the engine
/// once cut them silently and read a finite 65 275 ± 188. 256 paths, ~1.7·10⁷ bounces.
#[test]
fn paths_cut_at_the_bounce_guard_are_counted() {
    let c = case(
        r#"{ "name": "white furnace", "teaches": "an infinite answer is not a finite one",
        "scene": { "materials": { "white": { "type": "lambertian", "albedo": 1 } },
          "shapes": [ { "geometry": { "type": "sphere", "center": [0,0,0], "radius": 1 },
                        "material": "white", "flip_normals": true, "emission": { "radiance": 1 } } ] },
        "measure": { "radiance": { "at": [0,0,0], "direction": [0,0,1] } },
        "estimators": ["bsdf"] }"#,
    );
    let e = c.estimate(Estimator::Bsdf, &spec(256, 0x7a7a));
    let nf = e.batches.total.non_finite;
    assert!(nf > 128, "{nf} of 256 paths counted at the guard");
    let v = judge(&e, SamplerKind::Independent, 1.0, ALPHA, 1);
    let why = v.reason.as_deref().unwrap_or("");
    assert!(!v.passed && why.contains("65536-bounce guard"), "{v:?}");
}

#[test]
fn nan_emission_is_counted_on_every_strategy() {
    use lightproof::scene::emitter::EmitterKind;
    let mut c = lit_floor(IRRADIANCE);
    let EmitterKind::Area { radiance, .. } = &mut common::scene_mut(&mut c).emitters[0].kind else {
        panic!("the disk is the first emitter")
    };
    *radiance = f32::NAN;
    // Next-event estimation (light), emission found by BSDF sampling (bsdf), both (mis).
    for est in [Estimator::Light, Estimator::Bsdf, Estimator::Mis] {
        assert_counted(&c, est, "NaN area radiance");
    }
    // A negative radiance is as wrong as a NaN: counted, never silently dropped.
    let mut neg = lit_floor(IRRADIANCE);
    if let EmitterKind::Area { radiance, .. } = &mut common::scene_mut(&mut neg).emitters[0].kind {
        *radiance = -1.0;
    }
    assert_counted(&neg, Estimator::Light, "negative area radiance");
}

#[test]
fn nan_light_density_is_counted() {
    let mut c = lit_floor(IRRADIANCE);
    // The shape's area enters the light-sampling density (choice of primitive by area).
    common::scene_mut(&mut c).shapes[0].area = f32::NAN;
    assert_counted(&c, Estimator::Light, "NaN light density");
    let mut inf = lit_floor(IRRADIANCE);
    common::scene_mut(&mut inf).shapes[0].area = 0.0;
    assert_counted(&inf, Estimator::Light, "infinite light density");
}

#[test]
fn nan_bsdf_is_counted_in_evaluation_and_sampling() {
    use lightproof::bsdf::{Bsdf, lambertian::Lambertian};
    let mut c = lit_floor(FLOOR_RADIANCE);
    common::scene_mut(&mut c).materials[0].bsdf = Bsdf::Lambertian(Lambertian { albedo: f32::NAN });
    // light: the BSDF value in next-event estimation; bsdf: the sampled weight.
    for est in [Estimator::Light, Estimator::Bsdf, Estimator::Mis] {
        assert_counted(&c, est, "NaN BSDF");
    }
}

#[test]
fn nan_environment_and_spectrum_are_counted() {
    use lightproof::scene::emitter::EmitterKind;
    use lightproof::spectrum::{Response, Spectrum};
    // A constant environment of NaN radiance seen by an escaping ray.
    let mut env = case(
        r#"{ "name": "nan environment", "teaches": "nothing is masked",
        "scene": { "emitters": [ { "type": "constant", "radiance": 1 } ] },
        "measure": { "irradiance": { "at": [0,0,0], "normal": [0,0,1] } },
        "reference": { "closed_form": "constant_environment_irradiance", "radiance": 1 },
        "estimators": ["light", "bsdf", "mis"] }"#,
    );
    if let Some(EmitterKind::Constant { radiance }) = common::scene_mut(&mut env)
        .emitters
        .last_mut()
        .map(|e| &mut e.kind)
    {
        *radiance = f32::NAN;
    } else {
        panic!("a constant emitter");
    }
    for est in [Estimator::Light, Estimator::Bsdf, Estimator::Mis] {
        assert_counted(&env, est, "NaN environment");
    }
    // A blackbody disk over a band. Spectra and responses clamp out-of-domain data to
    // finite values by contract (tests/spectrum.rs), so the spectral path's non-finite
    // values are overflows: a response or an emission spectrum at f32::MAX makes
    // R(λ)/p(λ) or L·S(λ)·weight infinite, which must be counted, not dropped.
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("analytic/cases/spectral");
    let load = || Case::load(&root.join("blackbody_visible_band_3000K.json")).unwrap();
    let mut c = load();
    let sp = c.plan.dims.spectral.as_mut().expect("a spectral case");
    sp.response = Response::Sampled(Spectrum::Constant(f32::MAX));
    for &est in &c.desc.estimators.clone() {
        assert_counted(&c, est, "overflowing response");
    }
    let mut c = load();
    common::scene_mut(&mut c).emitters[0].props.spectrum = Some(Spectrum::Constant(f32::MAX));
    for &est in &c.desc.estimators.clone() {
        assert_counted(&c, est, "overflowing emission spectrum");
    }
}

#[test]
fn an_outcome_without_reference_fails_on_nan() {
    let mut c = lit_floor(IRRADIANCE);
    c.reference = None;
    common::scene_mut(&mut c).shapes[0].area = f32::NAN;
    let mut o = c.run(Estimator::Light, SamplerKind::Independent, 1 << 10, 0x7a7b);
    o.judge(ALPHA, 1);
    assert!(o.verdict.is_none() && o.non_finite > 0);
    assert!(
        !o.passed(),
        "a case without reference passed with NaN samples"
    );
    // The same case with finite samples passes.
    let ok = lit_floor(IRRADIANCE);
    let o = ok.run(Estimator::Light, SamplerKind::Independent, 1 << 10, 0x7a7c);
    assert!(o.passed() && o.non_finite == 0);
}
