//! Shared knobs of the proof: the seed and the sample scale.

/// The base seed: `LIGHTPROOF_SEED` or a fixed default, recorded in every message. The
/// variable is read as the command line reads it (surrounding spaces ignored, empty as
/// unset); any other value stops the test naming it, rather than rerun the default.
pub fn seed() -> u64 {
    lightproof::case::env_count("LIGHTPROOF_SEED", 0)
        .unwrap_or_else(|e| panic!("{e}"))
        .unwrap_or(0x11_9470)
}

/// `LIGHTPROOF_SCALE` (default 1, at least 1) multiplies every sample count for a deeper
/// proof; read as [`seed`] reads its variable.
pub fn scale() -> u64 {
    lightproof::case::env_count("LIGHTPROOF_SCALE", 1)
        .unwrap_or_else(|e| panic!("{e}"))
        .unwrap_or(1)
}

/// Two-sample z test of equal means at the per-test level of `alpha` over a Šidák family
/// of `family`: x̄_a − x̄_b against 0 with standard error √(s_a² + s_b²), through
/// `MeanTest::judge_parts`. Its null hypothesis allows the f32 rounding of both
/// estimates, |μ_a − μ_b| ≤ τ = γ₁₂₈·(|x̄_a| + |x̄_b|) (`MeanTest::rounding_allowance`,
/// ≈ 7.6e-6 relative to each: the module notes of `lightproof::stats::hypothesis`),
/// instead of a hand floor on the standard error. The verdict's
/// `detectable_relative_bias` is its detectable difference, τ + (z₁₋α₁/₂ + z₀.₉₉)·SE,
/// over the mean of the two (99% power).
pub fn same_mean(
    a: &lightproof::transport::engine::Estimate,
    b: &lightproof::transport::engine::Estimate,
    alpha: f64,
    family: usize,
) -> lightproof::stats::Verdict {
    let (ma, mb) = (&a.batches.total, &b.batches.total);
    let se = (ma.std_error().powi(2) + mb.std_error().powi(2)).sqrt();
    let test = lightproof::stats::MeanTest::new(alpha, family)
        .with_term_scale(ma.mean.abs() + mb.mean.abs());
    let mut v = test.judge_parts(
        ma.mean - mb.mean,
        se,
        0.0,
        None,
        ma.non_finite + mb.non_finite,
        ma.count.min(mb.count),
    );
    v.detectable_relative_bias = v.detectable_bias / (0.5 * (ma.mean + mb.mean)).abs();
    v
}

/// The scene of a freshly loaded case, to corrupt on purpose (the tests that prove a
/// non-finite or negative value is counted, never masked). A case holds its scene
/// behind an `Arc` shared with its time bins; a case without bins is its sole owner.
pub fn scene_mut(c: &mut lightproof::case::Case) -> &mut lightproof::scene::Scene {
    std::sync::Arc::get_mut(&mut c.scene).expect("a case without time bins owns its scene")
}
