//! Report files: stable names, atomic writes, and reading them back.
//!
//! A case's report id is its file's path under the folder given on the command line,
//! without `.json` (`irradiance/disk_on_axis`; a file given by itself: its stem). Reports
//! lie flat in the output folder, the id's `/` becoming `.`
//! (`irradiance.disk_on_axis.json`, `irradiance.disk_on_axis.svg`). Every file is written
//! with [`crate::io::write_atomic`] (temporary file, then rename), so an interrupted run
//! leaves each file whole: the old version or the new one.

use super::{CaseReport, FORMAT, Kind};
use crate::error::{InputError, IoError, parse_json};
use serde::Serialize;
use std::path::{Component, Path, PathBuf};

/// The id of a case file found under `root` (or given by itself when `root` is `None`).
pub fn case_id(root: Option<&Path>, file: &Path) -> String {
    let rel = root
        .and_then(|r| file.strip_prefix(r).ok())
        .filter(|r| !r.as_os_str().is_empty())
        .unwrap_or_else(|| Path::new(file.file_name().unwrap_or(file.as_os_str())));
    let parts: Vec<String> = rel
        .with_extension("")
        .components()
        .filter_map(|c| match c {
            Component::Normal(s) => Some(s.to_string_lossy().into_owned()),
            _ => None,
        })
        .collect();
    parts.join("/")
}

/// The file stem of an id: `/` → `.`, and anything but letters, digits, `-`, `_`, `.`
/// → `_`.
pub fn stem(id: &str) -> String {
    id.chars()
        .map(|c| match c {
            '/' => '.',
            c if c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.') => c,
            _ => '_',
        })
        .collect()
}

/// The report file of an id.
pub fn report_file(id: &str) -> String {
    format!("{}.json", stem(id))
}

/// The plot file of an id.
pub fn plot_file(id: &str) -> String {
    format!("{}.svg", stem(id))
}

/// What a time-binned case's transient plot adds to its stem: `ID.transient.svg`, the
/// plot file of a case whose stem is `ID.transient`, which is therefore refused.
pub const TRANSIENT_SUFFIX: &str = ".transient";

/// The transient plot file of an id ([`TRANSIENT_SUFFIX`]).
pub fn transient_plot_file(id: &str) -> String {
    plot_file(&format!("{}{TRANSIENT_SUFFIX}", stem(id)))
}

/// Write a value as pretty JSON, atomically.
pub fn write_json<T: Serialize>(path: &Path, value: &T, pretty: bool) -> Result<(), IoError> {
    let text = if pretty {
        serde_json::to_string_pretty(value)
    } else {
        serde_json::to_string(value)
    }
    .map_err(|e| IoError::write(path, e))?;
    write_bytes(path, format!("{text}\n").as_bytes())
}

/// Write bytes atomically, naming the file on failure.
pub fn write_bytes(path: &Path, bytes: &[u8]) -> Result<(), IoError> {
    crate::io::write_atomic(path, bytes).map_err(|e| IoError::write(path, e))
}

/// Read a case report; `Ok(None)` when the file does not exist. A file that is not a
/// lightproof case report is an error (it is never overwritten silently).
pub fn read_case_report(path: &Path) -> Result<Option<CaseReport>, InputError> {
    if !path.exists() && path.symlink_metadata().is_err() {
        return Ok(None);
    }
    let text = crate::io::read_input(path, crate::io::MAX_JSON_BYTES)
        .map_err(|e| InputError::new(path.display().to_string(), "-", e))?;
    let file = path.display().to_string();
    check_header(&file, &text, Kind::Case, OUTPUT_ADVICE)?;
    parse_json(&file, &text).map(Some)
}

/// What to do about a foreign file in the output folder: it is never overwritten.
pub const OUTPUT_ADVICE: &str = "move it or choose another --out";

/// What to do about a foreign file given to `merge`: it reads only shard partials.
pub const MERGE_ADVICE: &str =
    "merge reads the shard-K-of-N.json files that `report --shard K/N` writes";

/// Check the `format` and `kind` of a JSON text before parsing it whole; a file of
/// another format gets `advice` (whether it is an input or in the way of an output).
pub fn check_header(file: &str, text: &str, kind: Kind, advice: &str) -> Result<(), InputError> {
    let v: serde_json::Value = parse_json(file, text)?;
    let format = v.get("format").and_then(|f| f.as_str());
    if format != Some(FORMAT) {
        return Err(InputError::new(
            file,
            "format",
            format!(
                "not a lightproof report file (expected `{FORMAT}`, got {}); {advice}",
                format.map_or("none".to_string(), |f| format!("`{f}`"))
            ),
        ));
    }
    let want = serde_json::to_value(kind).unwrap_or_default();
    if v.get("kind") != Some(&want) {
        return Err(InputError::new(
            file,
            "kind",
            format!(
                "expected {want}, got {}",
                v.get("kind").cloned().unwrap_or_default()
            ),
        ));
    }
    Ok(())
}

/// Every file directly in the folders among `paths` (not their sub-folders) with a file
/// name accepted by `keep`, and the files given directly, sorted, each once.
pub fn files_in(
    paths: &[PathBuf],
    keep: impl Fn(&str) -> bool,
) -> Result<Vec<PathBuf>, InputError> {
    crate::io::collect_files(paths, false, |q| {
        q.file_name().is_some_and(|n| keep(&n.to_string_lossy()))
    })
}

/// FNV-1a 64 of some bytes, as 16 hex digits (stable across builds and platforms).
pub fn digest(bytes: &[u8]) -> String {
    format!(
        "{:016x}",
        crate::sampling::sampler::fnv1a(bytes.iter().copied())
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ids_and_names() {
        let root = Path::new("analytic/cases");
        let f = Path::new("analytic/cases/irradiance/disk_on_axis.json");
        assert_eq!(case_id(Some(root), f), "irradiance/disk_on_axis");
        assert_eq!(case_id(None, f), "disk_on_axis");
        assert_eq!(
            report_file("irradiance/disk_on_axis"),
            "irradiance.disk_on_axis.json"
        );
        assert_eq!(plot_file("a b/c"), "a_b.c.svg");
    }

    /// A key the schema does not allow in `fit_cost` is refused, naming it, as anywhere
    /// else in a report (before, `CostFit` alone took unknown keys without a word).
    #[test]
    fn an_unknown_key_in_fit_cost_is_refused() {
        let example =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("reports/examples/disk_on_axis.json");
        let text = std::fs::read_to_string(&example).unwrap();
        let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert!(parse_json::<CaseReport>("r.json", &text).is_ok());
        v["series"][0]["fit_cost"]["extra"] = 1.into();
        let e = parse_json::<CaseReport>("r.json", &v.to_string()).unwrap_err();
        assert!(
            e.field.starts_with("series[0].fit_cost") && e.reason.contains("extra"),
            "{e}"
        );
    }
}
