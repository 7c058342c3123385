//! Statistics that decide pass or fail.
//!
//! - [`accumulator`]: a mergeable running mean and variance (Welford 1962; Chan,
//!   Golub & LeVeque 1979 for merging), which also counts non-finite samples so they
//!   fail a test instead of vanishing; batch means for heavy-tailed estimators.
//! - [`hypothesis`]: the one-sample test of an estimate against a reference: z (or t
//!   for batch means), two-sided p, the verdict at a Šidák-corrected level, and the
//!   smallest relative bias the test detects with 99% power.
//! - [`bounded`]: the empirical Bernstein test for samples in a known range (no
//!   central limit theorem needed: rare-loss weights at any sample count).
//! - [`binomial`]: exact binomial tails and the two-sided test of a count (the
//!   chi-square judge's lost draws, the BSDF suite's reflection fractions).
//! - [`slope`]: least-squares slope of log–log data (convergence rates).
//! - [`cost`]: the cost line t = t₀ + c·N of a sweep (robust, relative least squares).
//! - [`chi2`]: chi-square goodness of fit of a sampler against its density.

pub mod accumulator;
pub mod binomial;
pub mod bounded;
pub mod chi2;
pub mod cost;
pub mod hypothesis;
pub mod slope;

pub use accumulator::{Accumulator, BatchMeans};
pub use bounded::Range;
pub use cost::{CostFit, fit_cost};
pub use hypothesis::{
    MeanTest, Verdict, VerdictClass, exact_relative_tolerance, is_exact, is_exact_at, sidak_alpha,
};
pub use slope::{SlopeFit, fit_slope};
