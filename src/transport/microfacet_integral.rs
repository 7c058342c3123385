//! The identities every microfacet paper states, as measurements (Heitz 2014,
//! "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs", eqs. 2, 4
//! and 38), estimated by Monte Carlo over microfacet normals m on the hemisphere:
//!
//! | integral | value |
//! |---|---|
//! | `normalisation` | ∫ D(m) cos θm dm = 1 |
//! | `projected_area` | ∫ ⟨ωo, m⟩⁺ D(m) dm = cos θo (1 + Λ(ωo)) |
//! | `visible` | ∫ D_ωo(m) dm = ∫ G1(ωo) ⟨ωo, m⟩⁺ D(m)/cos θo dm = 1 |
//!
//! D, Λ, G1 and D_ωo are the engine's ([`crate::bsdf::microfacet`]); the references are
//! the oracle crate's (its `microfacet` module), so a wrong D (not normalised), a
//! wrong Λ (the projected area) or a wrong G1 (the visible normals) fails its case. The
//! estimators sample m with a density that knows nothing of D — `uniform`
//! (1/(2π)) or `cosine` (cos θm/π) — so every estimate has variance.

use crate::bsdf::microfacet::Microfacet;
use crate::math::{PI, TWO_PI};
use crate::sampling::SampleStream;
use crate::sampling::hemisphere::{cosine_hemisphere, uniform_hemisphere};
use crate::transport::{Estimator, Geometric, Sampling};
use glam::Vec3;
use serde::{Deserialize, Serialize};

/// Which integral of a microfacet distribution.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MicrofacetIntegral {
    /// ∫ D(m) cos θm dm.
    Normalisation,
    /// ∫ ⟨ωo, m⟩⁺ D(m) dm.
    ProjectedArea,
    /// ∫ D_ωo(m) dm.
    Visible,
}

impl MicrofacetIntegral {
    /// The integrand at a microfacet normal m (z > 0) for the direction ωo.
    #[inline]
    pub fn integrand(&self, mf: &Microfacet, wo: Vec3, m: Vec3) -> f32 {
        match self {
            MicrofacetIntegral::Normalisation => mf.d(m) * m.z,
            MicrofacetIntegral::ProjectedArea => mf.d(m) * wo.dot(m).max(0.0),
            MicrofacetIntegral::Visible => mf.d_visible(wo, m),
        }
    }

    /// Whether the integral depends on ωo at all (the normalisation does not).
    pub fn depends_on_wo(&self) -> bool {
        match self {
            MicrofacetIntegral::Normalisation => false,
            MicrofacetIntegral::ProjectedArea | MicrofacetIntegral::Visible => true,
        }
    }

    /// Whether the integral needs cos θo > 0 (the visible normals divide by it).
    pub fn needs_wo_above(&self) -> bool {
        match self {
            MicrofacetIntegral::Normalisation | MicrofacetIntegral::ProjectedArea => false,
            MicrofacetIntegral::Visible => true,
        }
    }
}

/// One sample of the microfacet measurement with estimator `est` (`uniform` or
/// `cosine`; any other gives NaN, as for every measurement).
pub fn sample(
    mf: &Microfacet,
    wo: Vec3,
    integral: MicrofacetIntegral,
    est: Estimator,
    s: &mut SampleStream,
) -> f32 {
    match est.sampling() {
        Sampling::Geometric(Geometric::Uniform) => {
            let m = uniform_hemisphere(s.next_2d());
            integral.integrand(mf, wo, m) * TWO_PI
        }
        Sampling::Geometric(Geometric::Cosine) => {
            cosine_weighted(mf, wo, integral, cosine_hemisphere(s.next_2d()))
        }
        Sampling::Geometric(Geometric::Area) | Sampling::Transport(_) => f32::NAN,
    }
}

/// The integrand over the cosine density cos θm/π at a normal `m` drawn from it. Cosine
/// sampling puts a normal exactly on the horizon (m.z = 0, density zero) when the disk
/// point rounds onto the unit circle: such a draw carries no weight.
fn cosine_weighted(mf: &Microfacet, wo: Vec3, integral: MicrofacetIntegral, m: Vec3) -> f32 {
    if !(m.z > 0.0) {
        return 0.0;
    }
    // Not clamped: a non-finite value is counted and fails the verdict.
    integral.integrand(mf, wo, m) * PI / m.z
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::microfacet::{Distribution, Masking};
    use crate::sampling::Sampler;

    /// A cosine draw on the horizon (density zero) weighs nothing, for every integral,
    /// where dividing by its cos θm = 0 would give a non-finite sample.
    #[test]
    fn a_cosine_draw_on_the_horizon_weighs_nothing() {
        let mf = Microfacet::new(Distribution::Ggx, 0.5, Masking::HeightCorrelated);
        let wo = Vec3::new(0.6, 0.0, 0.8);
        for integral in [
            MicrofacetIntegral::Normalisation,
            MicrofacetIntegral::ProjectedArea,
            MicrofacetIntegral::Visible,
        ] {
            for m in [Vec3::X, Vec3::new(0.6, 0.8, 0.0), Vec3::new(0.0, 1.0, -0.0)] {
                assert_eq!(
                    cosine_weighted(&mf, wo, integral, m),
                    0.0,
                    "{integral:?} at {m}"
                );
            }
            // Just above the horizon the sample is the integrand over cos θm/π.
            let m = Vec3::new(1.0, 0.0, 1e-3).normalize();
            let w = cosine_weighted(&mf, wo, integral, m);
            assert!(w.is_finite() && w >= 0.0, "{integral:?}: {w}");
        }
    }

    /// The three integrals by both estimators, with a lax 6σ check (the statistical
    /// verdicts live in the catalog cases).
    #[test]
    fn integrals_converge() {
        let mf = Microfacet::new(Distribution::Beckmann, 0.6, Masking::HeightCorrelated);
        let wo = Vec3::new(0.6, 0.0, 0.8);
        let lambda = mf.lambda(wo) as f64;
        for (integral, exact) in [
            (MicrofacetIntegral::Normalisation, 1.0),
            (MicrofacetIntegral::ProjectedArea, 0.8 * (1.0 + lambda)),
            (MicrofacetIntegral::Visible, 1.0),
        ] {
            for est in [Estimator::Uniform, Estimator::Cosine] {
                let sampler = Sampler::independent(3);
                let n = 200_000u64;
                let (mut m1, mut m2) = (0.0f64, 0.0f64);
                for i in 0..n {
                    let v = sample(&mf, wo, integral, est, &mut sampler.stream(i)) as f64;
                    m1 += v;
                    m2 += v * v;
                }
                let mean = m1 / n as f64;
                let se = ((m2 / n as f64 - mean * mean) / n as f64).sqrt();
                assert!(
                    (mean - exact).abs() < 6.0 * se,
                    "{integral:?} {est:?}: {mean} ± {se} vs {exact}"
                );
            }
        }
        let mut st = Sampler::independent(1).stream(0);
        let v = sample(
            &mf,
            wo,
            MicrofacetIntegral::Visible,
            Estimator::Light,
            &mut st,
        );
        assert!(v.is_nan());
    }
    #[test]
    fn only_the_visible_normals_need_the_direction_above() {
        assert!(MicrofacetIntegral::Visible.needs_wo_above());
        assert!(!MicrofacetIntegral::Normalisation.needs_wo_above());
        assert!(!MicrofacetIntegral::ProjectedArea.needs_wo_above());
    }
}
