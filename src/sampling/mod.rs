//! Warps from the unit square to the domains light transport integrates over, and the
//! samplers that feed them.
//!
//! Every warp is a deterministic function of its uniform input and comes with its
//! density (`*_pdf`), measured in the domain's natural measure (solid angle for
//! directions, area for points), and an inverse where one exists. Each is proven by a
//! chi-square goodness-of-fit test (`tests/sampling_chi2.rs`) and property tests.
//!
//! | module | warp | density |
//! |---|---|---|
//! | [`sphere`] | uniform sphere | 1/(4π) |
//! | [`hemisphere`] | uniform and cosine-weighted hemisphere | 1/(2π), cos θ/π |
//! | [`cone`] | uniform cone of half-angle θmax | 1/(2π(1 − cos θmax)) |
//! | [`disk`] | concentric disk (Shirley & Chiu 1997) | 1/π |
//! | [`triangle`] | uniform triangle area | 1/A |
//! | [`spherical_triangle`] | uniform solid angle of a triangle (Arvo 1995) | 1/Ω |
//! | [`spherical_rectangle`] | uniform solid angle of a rectangle (Ureña et al. 2013) | 1/Ω |
//! | [`sphere_cone`] | directions towards a sphere seen from a point | 1/(2π(1 − cos θmax)) |
//! | [`sphere_inside`] | directions from inside a sphere to where they leave it | 1/(4π) |
//! | [`distribution`] | 1-D and 2-D piecewise-constant densities | f/∫f |
//!
//! [`sampler`] holds the sample streams: independent, stratified (Latin hypercube) and
//! Owen-scrambled Sobol, each addressed by sample index so results do not depend on
//! the number of threads.

pub mod cone;
pub mod disk;
pub mod distribution;
pub mod hemisphere;
pub mod sampler;
pub mod sphere;
pub mod sphere_cone;
pub mod sphere_inside;
pub mod spherical_rectangle;
pub mod spherical_triangle;
pub mod triangle;

pub use sampler::{SampleStream, Sampler, SamplerKind};
