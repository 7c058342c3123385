//! Light transport: the integrands lightproof estimates.
//!
//! Rendering is integration: a measurement is an integral of radiance against a
//! sensitivity, and radiance obeys the rendering equation
//! Lo(x, ωo) = Le(x, ωo) + ∫ f(x, ωi → ωo) Li(x, ωi) |cos θi| dωi with
//! Li(x, ωi) = Lo(x′, −ωi) for the first surface x′ seen along ωi (Kajiya 1986).
//!
//! - [`plan`]: what an estimate simulates — the effects a scene can produce for a
//!   measurement ([`effects`]) and the dimensions it samples, decided together;
//! - [`effects`]: the geometric rules of that decision;
//! - [`path`]: the path tracer (next-event estimation, BSDF sampling, MIS, Russian
//!   roulette) that estimates Li;
//! - [`measure`]: the measurements (solid angle, irradiance, radiance, albedo, power,
//!   intensity, image) as one-sample estimators over the sample streams;
//! - [`microfacet_integral`]: the microfacet distributions' own integrals
//!   (normalisation, projected area, visible normals) as a measurement;
//! - [`phase`]: wavelength and time as dimensions of a sample (hero wavelengths, time
//!   of flight, motion), sampled only where the effects analysis says they matter;
//! - [`engine`]: running N samples in parallel, deterministically, into accumulators.

pub mod effects;
pub mod engine;
pub mod measure;
pub mod microfacet_integral;
pub mod path;
pub mod phase;
pub mod plan;

use serde::{Deserialize, Serialize};

/// How a measurement's integral is sampled, by the name a case file gives it.
///
/// The names form one flat list in case files and on the command line; the engine
/// dispatches on [`Estimator::sampling`], which splits them into the two kinds they
/// are: transport strategies of the path tracer ([`Strategy`]) and geometric sampling
/// choices of the direct measurements ([`Geometric`]). A measurement that takes only
/// geometric choices answers every strategy with one arm, so adding a strategy touches
/// the path tracer, not every measurement.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Estimator {
    /// Emitter sampling (next-event estimation) only.
    Light,
    /// BSDF (or cosine) sampling only.
    Bsdf,
    /// Both, combined by multiple importance sampling with the power heuristic (β = 2).
    Mis,
    /// Both, combined with the balance heuristic.
    MisBalance,
    /// Uniform directions (sphere or hemisphere).
    Uniform,
    /// Cosine-weighted directions.
    Cosine,
    /// Points sampled uniformly by area on the shape or emitter.
    Area,
}

/// The two kinds of estimator.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Sampling {
    /// A strategy of the path tracer.
    Transport(Strategy),
    /// A geometric sampling choice.
    Geometric(Geometric),
}

/// The path tracer's strategies for direct light at each vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Strategy {
    /// Emitter sampling only.
    Light,
    /// BSDF sampling only.
    Bsdf,
    /// Both, weighted by a MIS heuristic.
    Mis(Heuristic),
}

/// Geometric sampling choices: a density over directions or points, no path tracing
/// decisions.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Geometric {
    /// Uniform directions (sphere or hemisphere).
    Uniform,
    /// Cosine-weighted directions.
    Cosine,
    /// Points uniform by area on a shape or emitter.
    Area,
}

impl Estimator {
    /// Every estimator, in the order of the enum (and of the command line's list).
    pub const ALL: [Estimator; 7] = [
        Estimator::Light,
        Estimator::Bsdf,
        Estimator::Mis,
        Estimator::MisBalance,
        Estimator::Uniform,
        Estimator::Cosine,
        Estimator::Area,
    ];

    /// Lower-case name.
    pub fn name(&self) -> &'static str {
        match self {
            Estimator::Light => "light",
            Estimator::Bsdf => "bsdf",
            Estimator::Mis => "mis",
            Estimator::MisBalance => "mis_balance",
            Estimator::Uniform => "uniform",
            Estimator::Cosine => "cosine",
            Estimator::Area => "area",
        }
    }

    /// Which kind of estimator this name is.
    pub fn sampling(&self) -> Sampling {
        match self {
            Estimator::Light => Sampling::Transport(Strategy::Light),
            Estimator::Bsdf => Sampling::Transport(Strategy::Bsdf),
            Estimator::Mis => Sampling::Transport(Strategy::Mis(Heuristic::Power)),
            Estimator::MisBalance => Sampling::Transport(Strategy::Mis(Heuristic::Balance)),
            Estimator::Uniform => Sampling::Geometric(Geometric::Uniform),
            Estimator::Cosine => Sampling::Geometric(Geometric::Cosine),
            Estimator::Area => Sampling::Geometric(Geometric::Area),
        }
    }

    /// The path tracer's strategies for this estimator: (light sampling, BSDF sampling,
    /// the MIS heuristic when both are on). Where a geometric choice drives the path
    /// tracer (irradiance by uniform or cosine directions, an emitter by area), it samples
    /// directions as BSDF sampling does, and area sampling of an emitter is light sampling
    /// combined with the BSDF by MIS.
    pub fn strategies(&self) -> (bool, bool, Heuristic) {
        match self.sampling() {
            Sampling::Transport(Strategy::Light) => (true, false, Heuristic::Power),
            Sampling::Transport(Strategy::Bsdf)
            | Sampling::Geometric(Geometric::Uniform | Geometric::Cosine) => {
                (false, true, Heuristic::Power)
            }
            Sampling::Transport(Strategy::Mis(h)) => (true, true, h),
            Sampling::Geometric(Geometric::Area) => (true, true, Heuristic::Power),
        }
    }
}

/// The multiple importance sampling heuristics of Veach & Guibas 1995.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Heuristic {
    /// w = p / (p + q).
    Balance,
    /// w = p² / (p² + q²).
    Power,
}

impl Heuristic {
    /// Weight of a sample drawn with density `p` when the other strategy has density `q`.
    ///
    /// Formed from the ratio of the smaller density to the larger, x ≤ 1: w = 1/(1 + x^β)
    /// for the larger density, x^β/(1 + x^β) for the smaller (β = 1 balance, 2 power).
    /// The same weights as p^β/(p^β + q^β), but nothing overflows: a light of solid angle
    /// 10⁻²⁰ sr has density 10²⁰, whose square is infinite in f32 (∞/∞ was read as weight
    /// 0, and a tiny sphere light's irradiance came out 0 under the power heuristic). An
    /// infinite `p` (a delta strategy) weighs 1; both densities 0 weigh 0 (no sample can
    /// have them). A NaN density gives a NaN weight, which the accumulator counts.
    #[inline]
    pub fn weight(&self, p: f32, q: f32) -> f32 {
        if p.is_infinite() {
            return 1.0;
        }
        let pow = |x: f32| match self {
            Heuristic::Balance => x,
            Heuristic::Power => x * x,
        };
        if p >= q {
            if p == 0.0 {
                return 0.0;
            }
            1.0 / (1.0 + pow(q / p))
        } else {
            let x = pow(p / q);
            x / (1.0 + x)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both heuristics against p^β/(p^β + q^β) in f64 (within 4 roundings), over
    /// densities from 10⁻³⁰ to 10³⁰, where the f32 squares overflow and underflow; the two
    /// strategies' weights sum to 1; a delta density weighs 1, zero densities 0, a NaN
    /// density NaN.
    #[test]
    fn heuristic_weights_hold_over_every_density() {
        for h in [Heuristic::Balance, Heuristic::Power] {
            let beta = if h == Heuristic::Balance { 1 } else { 2 };
            for i in -30..=30 {
                for j in -30..=30 {
                    let (p, q) = (1.7f32 * 10f32.powi(i), 0.3f32 * 10f32.powi(j));
                    let (pb, qb) = ((p as f64).powi(beta), (q as f64).powi(beta));
                    let want = pb / (pb + qb);
                    let (w, v) = (h.weight(p, q), h.weight(q, p));
                    assert!(
                        (w as f64 - want).abs() <= 4.0 * f32::EPSILON as f64 * want
                            || (want < 1e-38 && w < 1e-37),
                        "{h:?} ({p}, {q}): {w} vs {want}"
                    );
                    assert!(
                        ((w + v) as f64 - 1.0).abs() <= 4.0 * f32::EPSILON as f64,
                        "{h:?} ({p}, {q}): {w} + {v}"
                    );
                }
            }
            assert_eq!(h.weight(f32::INFINITY, 3.0), 1.0);
            assert_eq!(h.weight(0.0, 0.0), 0.0);
            assert_eq!(h.weight(0.0, 2.0), 0.0);
            assert_eq!(h.weight(2.0, 0.0), 1.0);
            assert_eq!(h.weight(2.0, f32::INFINITY), 0.0);
            assert!(h.weight(f32::NAN, 1.0).is_nan() && h.weight(1.0, f32::NAN).is_nan());
        }
    }

    const ALL: [Estimator; 7] = Estimator::ALL;

    #[test]
    fn names_split_into_strategies_and_geometric_choices() {
        let kinds: Vec<Sampling> = ALL.iter().map(|e| e.sampling()).collect();
        // Seven names, seven distinct kinds: the split loses nothing.
        for (i, a) in kinds.iter().enumerate() {
            assert!(kinds[i + 1..].iter().all(|b| b != a), "{a:?} twice");
        }
        let transport = |e: Estimator| matches!(e.sampling(), Sampling::Transport(_));
        assert!(ALL[..4].iter().all(|&e| transport(e)));
        assert!(ALL[4..].iter().all(|&e| !transport(e)));
        // The JSON names are the flat list, unchanged.
        for e in ALL {
            let json = serde_json::to_string(&e).unwrap();
            assert_eq!(json, format!("\"{}\"", e.name()));
            assert_eq!(serde_json::from_str::<Estimator>(&json).unwrap(), e);
        }
    }

    #[test]
    fn strategies_of_each_kind() {
        use Heuristic::*;
        let expect = [
            (true, false, Power),
            (false, true, Power),
            (true, true, Power),
            (true, true, Balance),
            (false, true, Power),
            (false, true, Power),
            (true, true, Power),
        ];
        for (e, x) in ALL.iter().zip(expect) {
            assert_eq!(e.strategies(), x, "{e:?}");
        }
    }
}
