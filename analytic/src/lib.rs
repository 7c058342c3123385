//! # lightproof-analytic: the independent oracle
//!
//! Closed-form radiometry in f64 against which `lightproof`'s Monte Carlo estimators are
//! judged. Every formula carries, in its doc comment, the formula itself, a derivation
//! sketch and its literature source, and is checked in this crate's tests against an
//! *independent* numerical quadrature ([`quadrature`]) — never the same formula
//! rearranged — including hard parameters (grazing receivers, emitters of ~1e-6 sr and
//! of nearly a hemisphere, sliver triangles, geometry 1e5 units from the origin,
//! η = 1.0001, total internal reflection).
//!
//! This crate depends on nothing in `lightproof`: the oracle never shares code with what
//! it judges.
//!
//! | module | contents |
//! |---|---|
//! | [`catalog`] | the dispatcher case files use: [`catalog::evaluate`] by name, [`catalog::names`] |
//! | [`solid_angle`] | cap, sphere, triangle (Van Oosterom–Strackee), polygon, rectangle |
//! | [`irradiance`] | polygon (Lambert, horizon-clipped), disk on/off axis and tilted, sphere (Snyder), spherical cap seen from outside (contour integral), point, constant environment; projected solid angle |
//! | [`view_factor`] | element→disk, disk→disk, parallel and perpendicular rectangles, element→sphere |
//! | [`furnace`] | closed enclosure, convex object, integrating sphere |
//! | [`partial_shapes`] | annulus (on-axis irradiance, power), spherical cap (area, power, irradiance at the centre), furnace partial sums (closed enclosure, integrating sphere with a port) |
//! | [`fresnel`] | dielectric (with TIR), conductor, hemispherical averages outside and inside |
//! | [`microfacet`] | GGX and Beckmann: Smith Λ, projected area, normalisation, the F ≡ 1 white-furnace albedo (closed form at α = 1, quadrature elsewhere) |
//! | [`oren_nayar`] | directional albedo of the classic (Oren & Nayar 1994) and Fujii Oren–Nayar forms, closed form |
//! | [`radiometry`] | Lambertian power and intensity, photon energy, radiance across an interface, SI constants |
//! | [`spectrum`] | Planck, Stefan–Boltzmann, band fractions, Wien, photon radiance, Cauchy, Sellmeier (BK7), slab transmittance |
//! | [`time`] | pulsed disk by time bin, mean chord length (Cauchy), moving point light shutter average |
//! | [`quadrature`] | Gauss–Legendre, adaptive 1-D and 2-D integration (the tests' independent side) |
//! | [`geom`] | a minimal private `Vec3` |
//!
//! Geometry parameters are absolute positions; every form subtracts first, so a scene
//! placed far from the origin is exactly as accurate as its input coordinates.

pub mod catalog;
pub mod fresnel;
pub mod furnace;
pub mod geom;
pub mod irradiance;
pub mod microfacet;
pub mod oren_nayar;
pub mod partial_shapes;
pub mod quadrature;
pub mod radiometry;
pub mod solid_angle;
pub mod spectrum;
pub mod time;
pub mod view_factor;

pub use catalog::{CatalogError, ClosedFormInfo, evaluate, names};
