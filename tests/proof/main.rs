//! The proof a user runs: one test binary (one link of the crate, not thirteen), one
//! module per area. `cargo test` runs it all; `cargo test --test proof catalog::` (or
//! `bsdf_contract::`, `effects_soundness::`, ...) runs one area.
//!
//! | module | what it proves |
//! |---|---|
//! | [`architecture`] | ARCHITECTURE.md's module layers: dependencies point down, no cycles |
//! | [`catalog`] | every catalog case against the oracle, Šidák over the run; oracle independence |
//! | [`bsdf_contract`] | the BSDF contract on every model over a grid of parameters and angles |
//! | [`bsdf_stability`] | no NaN, Inf or negative value from any BSDF at hostile inputs |
//! | [`sampling_chi2`] | chi-square of every warp, with a deliberately broken one rejected |
//! | [`spectrum`] | spectra, indices, responses and wavelength sampling |
//! | [`engine`] | the engine: furnaces, MIS, determinism across thread counts, NaN counting |
//! | [`phase_space`] | wavelength and time: the sampled and the pruned estimates agree |
//! | [`effects_soundness`] | the effects plan changes no expected value, with stated power |
//! | [`cli`] | the command line: exit statuses, messages, the JSON contract |
//! | [`hostile`] | the committed corpus of hostile inputs (`tests/corpus`) |
//! | [`fuzz_cases`] | property-based mutations of catalog cases never panic |
//! | [`report`] | convergence reports against their schema |
//! | [`examples`] | every example runs and passes |
//! | [`export_judge`] | export → render → judge: furnaces pass, wrong references and bad renders are caught; opt-in Mitsuba |

mod architecture;
mod bsdf_contract;
mod bsdf_stability;
mod catalog;
mod cli;
mod common;
mod effects_soundness;
mod engine;
mod examples;
mod export_judge;
mod fuzz_cases;
mod hostile;
mod phase_space;
mod report;
mod sampling_chi2;
mod spectrum;
