//! # lightproof
//!
//! A physically based light-transport verification suite: a minimal Monte Carlo
//! estimator engine run against cases whose answer is known in closed form, with
//! statistics deciding pass or fail.
//!
//! | module | concept |
//! |---|---|
//! | [`math`] | frames, spherical coordinates, robust float helpers, ray-origin offsetting |
//! | [`quadrature`] | the engine's own Gauss–Legendre rules and adaptive quadrature (never the oracle's) |
//! | [`sampling`] | warps with their densities, and the samplers (independent, stratified, Sobol) |
//! | [`stats`] | mergeable accumulators, mean tests with power, slope fits, chi-square |
//! | [`bsdf`] | BSDF models (enum for the hot path, trait for users) |
//! | [`io`] | atomic file writing |
//! | [`error`] | located input errors (file, field, reason) |
//! | [`scene`] | shapes, emitters, materials, BVH, JSON scenes |
//! | [`spectrum`] | spectra, refractive indices, spectral responses, wavelength sampling |
//! | [`transport`] | effects analysis, path tracer, measurements, the parallel engine |
//! | [`suites`] | the chi-square suite of every warp, shared by the CLI and the tests |
//! | [`verify`] | case files, running estimators, verdicts against the oracle |
//! | [`report`] | convergence reports: sweeps, shards and merging, JSON, plots, index |
//! | [`render`] | pinhole-camera EXR images |

// `!(x > 0.0)` is how this crate rejects NaN together with non-positive values.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod bsdf;
pub mod case;
pub mod error;
pub mod io;
pub mod math;
pub mod quadrature;
pub mod render;
pub mod report;
pub mod sampling;
pub mod scene;
pub mod spectrum;
pub mod stats;
pub mod suites;
pub mod transport;
pub mod verdict;
