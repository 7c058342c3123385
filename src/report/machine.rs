//! What a report records about the run that made it, so results can be compared across
//! runs: the lightproof version, the git revision of the build (`build.rs` asks git at
//! build time: `SHA`, `SHA-dirty-DIGEST` where the sources differ from the commit,
//! `unknown-DIGEST` without git), the thread count, the machine (CPU model from
//! `/proc/cpuinfo` where there is one, logical cores, the instruction set of the ray
//! queries) and the start time (UTC).

use super::{Machine, RunInfo};
use std::time::{SystemTime, UNIX_EPOCH};

/// Git revision of this build: the commit, `COMMIT-dirty-DIGEST` when [`SOURCES`] differ
/// from it (DIGEST hashes the sources as built), `unknown-DIGEST` outside a checkout or
/// without git.
pub const GIT_REVISION: &str = env!("LIGHTPROOF_GIT_REVISION");

/// The files and folders (space-separated, relative to the package) whose state the
/// revision stands for: a change to any other file (a test, the README) is not a
/// different build.
pub const SOURCES: &str = env!("LIGHTPROOF_SOURCES");

/// `CARGO_PKG_VERSION`.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// The cargo profile of this build (`release`, `fast`, `debug`, ...): the same revision
/// built as `fast` runs 6–14% faster than as `release`, so timings of the two are not
/// one series.
pub const PROFILE: &str = env!("LIGHTPROOF_PROFILE");

/// CPU model from a `/proc/cpuinfo` text (`model name`, else ARM's `Hardware`/`Model`).
pub fn cpu_model_from(cpuinfo: &str) -> Option<String> {
    ["model name", "Hardware", "Model", "cpu model"]
        .iter()
        .find_map(|key| {
            cpuinfo.lines().find_map(|l| {
                let (k, v) = l.split_once(':')?;
                (k.trim() == *key && !v.trim().is_empty()).then(|| v.trim().to_string())
            })
        })
}

/// This machine.
pub fn machine() -> Machine {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| cpu_model_from(&t))
        .unwrap_or_else(|| "unknown".to_string());
    Machine {
        cpu,
        logical_cores: std::thread::available_parallelism().map_or(1, |n| n.get()),
        os: std::env::consts::OS.to_string(),
        arch: std::env::consts::ARCH.to_string(),
        ray_isa: Some(crate::scene::accel::Isa::current().name().to_string()),
    }
}

/// UTC civil date and time of a Unix time, ISO 8601 (Hinnant's days-to-civil algorithm).
pub fn iso_utc(unix_seconds: u64) -> String {
    let days = (unix_seconds / 86_400) as i64;
    let secs = unix_seconds % 86_400;
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!(
        "{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}Z",
        secs / 3600,
        secs / 60 % 60,
        secs % 60
    )
}

/// Now, ISO 8601 UTC.
pub fn now_utc() -> String {
    iso_utc(
        SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0, |d| d.as_secs()),
    )
}

/// A fresh record of this process's run.
pub fn run_info(threads: usize, budget_seconds: Option<f64>) -> RunInfo {
    RunInfo {
        lightproof_version: VERSION.to_string(),
        git_revision: GIT_REVISION.to_string(),
        profile: Some(PROFILE.to_string()),
        threads,
        machine: machine(),
        started: now_utc(),
        wall_seconds: 0.0,
        budget_seconds,
        budget_cut: false,
        points_computed: 0,
        points_resumed: 0,
        shards: vec![],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The profile is cargo's folder for the build: `debug` for `cargo test` (the `dev`
    /// and `test` profiles), `release` under `--release`, never `unknown` in cargo.
    #[test]
    fn the_profile_is_the_builds_folder() {
        if cfg!(debug_assertions) {
            assert_eq!(PROFILE, "debug");
        } else {
            assert!(!PROFILE.is_empty() && PROFILE != "unknown" && PROFILE != "debug");
        }
        assert_eq!(run_info(1, None).profile.as_deref(), Some(PROFILE));
    }

    #[test]
    fn civil_dates() {
        assert_eq!(iso_utc(0), "1970-01-01T00:00:00Z");
        assert_eq!(iso_utc(951_782_400), "2000-02-29T00:00:00Z");
        assert_eq!(iso_utc(1_700_000_000), "2023-11-14T22:13:20Z");
    }

    #[test]
    fn cpu_models() {
        let x86 = "processor\t: 0\nvendor_id\t: GenuineIntel\nmodel name\t: Intel(R) Xeon(R) CPU @ 2.20GHz\n";
        assert_eq!(
            cpu_model_from(x86).as_deref(),
            Some("Intel(R) Xeon(R) CPU @ 2.20GHz")
        );
        assert_eq!(
            cpu_model_from("Hardware\t: BCM2835\n").as_deref(),
            Some("BCM2835")
        );
        assert_eq!(cpu_model_from("processor : 0\n"), None);
    }
}
