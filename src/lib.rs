//! # lightproof
//!
//! A physically based light-transport verification suite: a minimal Monte Carlo
//! estimator engine run against cases whose answer is known in closed form, with
//! statistics deciding pass or fail.
//!
//! The central types, in the order data meets them: a [`case::Case`] (scene,
//! measurement, the oracle's reference) carries its [`transport::plan::Plan`] (what to
//! simulate); [`case::Case::run`] estimates it into a [`verdict::Outcome`], which
//! [`verdict::judge_family`] judges against the reference. ARCHITECTURE.md has the map.
//!
//! ```
//! use lightproof::case::{Case, CaseDesc};
//! use lightproof::sampling::SamplerKind;
//! use lightproof::transport::Estimator;
//! use lightproof::verdict::judge_family;
//!
//! // A unit disk light of radiance 1 two units above a receiver: E = π R²/(R² + h²).
//! let desc: CaseDesc = serde_json::from_str(r#"{
//!   "name": "disk on axis", "teaches": "E = π L R²/(R² + h²)",
//!   "scene": { "shapes": [ { "geometry": { "type": "disk", "center": [0, 0, 2],
//!              "normal": [0, 0, -1], "radius": 1 }, "emission": { "radiance": 1 } } ] },
//!   "measure": { "irradiance": { "at": [0, 0, 0], "normal": [0, 0, 1] } },
//!   "reference": { "closed_form": "disk_irradiance_on_axis", "radius": 1, "height": 2, "radiance": 1 },
//!   "estimators": ["mis"] }"#).unwrap();
//! let case = Case::from_desc(desc, std::path::Path::new("disk.json")).unwrap();
//! assert_eq!(case.reference, Some(std::f64::consts::PI / 5.0));
//! let mut outcomes = vec![case.run(Estimator::Mis, SamplerKind::Independent, 1 << 14, 7)];
//! judge_family(&mut outcomes, 0, 1e-4);
//! assert!(outcomes[0].passed(), "{:?}", outcomes[0].verdict);
//! ```
//!
//! | module | concept |
//! |---|---|
//! | [`math`] | frames, spherical coordinates, robust float helpers, ray-origin offsetting |
//! | [`quadrature`] | the engine's own Gauss–Legendre rules and adaptive quadrature (never the oracle's) |
//! | [`sampling`] | warps with their densities, and the samplers (independent, stratified, Sobol) |
//! | [`stats`] | mergeable accumulators, mean tests with power, slope fits, chi-square |
//! | [`bsdf`] | BSDF models (enum for the hot path, trait for users, per-model facts) |
//! | [`io`] | atomic file writing, input limits, folder walking |
//! | [`error`] | errors by class: located input errors (file, field, reason), I/O errors |
//! | [`scene`] | shapes, emitters, materials, BVH, JSON scenes |
//! | [`spectrum`] | spectra, refractive indices, spectral responses, wavelength sampling |
//! | [`transport`] | the plan (effects, dimensions), path tracer, measurements, the parallel engine |
//! | [`case`] | case files: schema, validation in steps, the one run path |
//! | [`verdict`] | error bars, statistical and exact verdicts, outcomes, the Šidák family |
//! | [`suites`] | the chi-square suite of every warp, shared by the CLI and the tests |
//! | [`table`] | the verdict table `verify` prints, sized to the terminal |
//! | [`report`] | convergence reports: sweeps, shards and merging, JSON, plots, index; the verdict page |
//! | [`render`] | pinhole-camera images (EXR, or 8-bit sRGB PNG) |
//! | [`export`] | a case as a scene for another renderer (Mitsuba 3, pbrt-v4, lightproof's `render`) |
//! | [`judge`] | another renderer's EXR renders judged against a case's closed form |

// `!(x > 0.0)` is how this crate rejects NaN together with non-positive values.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod bsdf;
pub mod case;
pub mod error;
pub mod export;
pub mod io;
pub mod judge;
pub mod math;
pub mod quadrature;
pub mod render;
pub mod report;
pub mod sampling;
pub mod scene;
pub mod spectrum;
pub mod stats;
pub mod suites;
pub mod table;
pub mod transport;
pub mod verdict;
