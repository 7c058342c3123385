//! Errors by class, each with its exit status on the command line:
//!
//! - [`InputError`], bad input (status 2): the file, the field (a JSON path such as
//!   `scene.shapes[2].geometry.radius`) and the reason; nothing panics on input;
//! - [`IoError`], the environment failed us (status 3): an output that cannot be
//!   written, worker threads that cannot start — the input was fine;
//! - a failed verdict is not an error of this module: the command line exits 1.
//!
//! [`Error`] is either of the first two, for functions that read input and write output.

/// Bad input, located.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}: {field}: {reason}")]
pub struct InputError {
    /// The file (or `<inline>` for strings).
    pub file: String,
    /// JSON path of the offending field (`-` when the file as a whole is at fault).
    pub field: String,
    /// Why it is rejected.
    pub reason: String,
}

impl InputError {
    /// A located error.
    pub fn new(
        file: impl Into<String>,
        field: impl Into<String>,
        reason: impl Into<String>,
    ) -> Self {
        InputError {
            file: file.into(),
            field: field.into(),
            reason: reason.into(),
        }
    }
}

/// An output that could not be written (or another failure of the environment, not of
/// the input), naming the path.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{path}: {reason}")]
pub struct IoError {
    /// The file or folder (or what failed, e.g. `worker threads`).
    pub path: String,
    /// What went wrong.
    pub reason: String,
}

impl IoError {
    /// A failed write of `path`. Where a folder on the way is a file (`--out report.json`
    /// given an existing file), the reason names it: the system's own message ("File
    /// exists", "Not a directory") does not say which.
    pub fn write(path: &std::path::Path, e: impl std::fmt::Display) -> Self {
        IoError {
            path: path.display().to_string(),
            reason: match not_a_folder(path) {
                Some(why) => format!("cannot write: {why}"),
                None => format!("cannot write: {e}"),
            },
        }
    }

    /// An output folder `out` that cannot hold files because it, or a folder above it, is
    /// an existing file: checked before a command's work, so that a long run does not end
    /// in an unwritable output.
    pub fn check_output_folder(out: &std::path::Path) -> Result<(), IoError> {
        match out.ancestors().find_map(cannot_be_a_folder) {
            Some(why) => Err(IoError {
                path: out.display().to_string(),
                reason: format!("cannot write: {why}"),
            }),
            None => Ok(()),
        }
    }
}

/// Why the first folder above `path` that cannot be one cannot (see [`cannot_be_a_folder`]).
fn not_a_folder(path: &std::path::Path) -> Option<String> {
    path.ancestors().skip(1).find_map(cannot_be_a_folder)
}

/// Why `a` cannot be (or become) a folder: it exists as a file (or a device, a FIFO), or
/// it is a symbolic link that leads to nothing (its target, or a link further on, is
/// missing) or cannot be followed (a loop); the system says "File exists" for these,
/// naming none of them.
fn cannot_be_a_folder(a: &std::path::Path) -> Option<String> {
    if a.as_os_str().is_empty() {
        return None;
    }
    match std::fs::metadata(a) {
        Ok(m) => (!m.is_dir()).then(|| format!("`{}` is a file, not a folder", a.display())),
        Err(e) => {
            let link = std::fs::read_link(a).ok()?;
            let why = match e.kind() {
                std::io::ErrorKind::NotFound => "which leads to nothing".to_string(),
                _ => format!("which cannot be followed ({e})"),
            };
            Some(format!(
                "`{}` is a symbolic link to `{}`, {why}",
                a.display(),
                link.display()
            ))
        }
    }
}

/// Bad input or a failed output.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    /// Bad input (exit status 2).
    #[error(transparent)]
    Input(#[from] InputError),
    /// A failed output or environment (exit status 3).
    #[error(transparent)]
    Io(#[from] IoError),
}

impl Error {
    /// The command line's exit status for this error: 2 for input, 3 for I/O.
    pub fn exit_code(&self) -> u8 {
        match self {
            Error::Input(_) => 2,
            Error::Io(_) => 3,
        }
    }
}

/// Parse JSON into `T`, naming the path of the first field serde rejects.
pub fn parse_json<T: serde::de::DeserializeOwned>(file: &str, text: &str) -> Result<T, InputError> {
    let de = &mut serde_json::Deserializer::from_str(text);
    serde_path_to_error::deserialize(de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner();
        let field = if path.is_empty() || path == "." {
            "-".to_string()
        } else {
            path
        };
        InputError::new(file, field, inner.to_string())
    })
}

/// Largest magnitude of a coordinate or length (in scene units): squared distances
/// (up to (2·10¹⁸)² = 4·10³⁶) then still fit in `f32` (3.4·10³⁸), so no ray test
/// overflows.
pub const MAX_COORDINATE: f64 = 1e18;

/// Whether `v` survives the conversion to `f32`: finite there, and not flushed to zero
/// or to a subnormal (0 itself is fine).
pub fn fits_f32(v: f64) -> bool {
    v.is_finite() && v.abs() <= f32::MAX as f64 && (v == 0.0 || v.abs() >= f32::MIN_POSITIVE as f64)
}

/// Why `v` does not fit in `f32`, if it does not (see [`fits_f32`]).
pub fn f32_problem(v: f64) -> Option<String> {
    if !v.is_finite() {
        Some(format!("must be a finite number, got {v}"))
    } else if v.abs() > f32::MAX as f64 {
        Some(format!(
            "overflows f32 (magnitude at most {:e}), got {v:e}",
            f32::MAX
        ))
    } else if v != 0.0 && v.abs() < f32::MIN_POSITIVE as f64 {
        Some(format!(
            "underflows f32 (a non-zero magnitude must be at least {:e}), got {v:e}",
            f32::MIN_POSITIVE
        ))
    } else {
        None
    }
}

/// Check a number is finite, representable in `f32` (the engine computes in `f32`:
/// see [`fits_f32`]) and within bounds; `what` describes the bound.
pub fn check_number(
    file: &str,
    field: &str,
    v: f64,
    ok: impl Fn(f64) -> bool,
    what: &str,
) -> Result<(), InputError> {
    if let Some(why) = f32_problem(v) {
        return Err(InputError::new(file, field, why));
    }
    if !ok(v) {
        return Err(InputError::new(
            file,
            field,
            format!("must be {what}, got {v}"),
        ));
    }
    Ok(())
}

/// Check a derived quantity (an area, a power, a product of inputs) is finite in `f32`;
/// `what` names it in the message.
pub fn check_derived(file: &str, field: &str, v: f64, what: &str) -> Result<(), InputError> {
    if v.is_finite() && v.abs() <= f32::MAX as f64 {
        Ok(())
    } else {
        Err(InputError::new(
            file,
            field,
            format!(
                "{what} is {v:e}, which overflows f32 (at most {:e}): use smaller values",
                f32::MAX
            ),
        ))
    }
}

/// A point (or a translation, a velocity): three finite numbers of magnitude at most
/// [`MAX_COORDINATE`].
pub fn check_point(file: &str, field: &str, a: [f64; 3]) -> Result<glam::DVec3, InputError> {
    if let Some(x) = a.iter().find(|x| !x.is_finite()) {
        return Err(InputError::new(
            file,
            field,
            format!("must be three finite numbers, got {x} in {a:?}"),
        ));
    }
    if let Some(x) = a.iter().find(|x| x.abs() > MAX_COORDINATE) {
        return Err(InputError::new(
            file,
            field,
            format!(
                "coordinate {x:e} is out of range: coordinates must lie within ±{MAX_COORDINATE:e} (so that squared distances fit in f32)"
            ),
        ));
    }
    Ok(glam::DVec3::from_array(a))
}

/// A direction, normalised in `f64`: three finite numbers, not all zero, of length at
/// least `f32::MIN_POSITIVE` (smaller vectors cannot be normalised reliably) and
/// components at most `f32::MAX`.
pub fn check_direction(file: &str, field: &str, a: [f64; 3]) -> Result<glam::DVec3, InputError> {
    if let Some(x) = a.iter().find(|x| !x.is_finite()) {
        return Err(InputError::new(
            file,
            field,
            format!("must be three finite numbers, got {x} in {a:?}"),
        ));
    }
    let m = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if m == 0.0 {
        return Err(InputError::new(
            file,
            field,
            "must be a non-zero vector, got [0, 0, 0]",
        ));
    }
    if m < f32::MIN_POSITIVE as f64 {
        return Err(InputError::new(
            file,
            field,
            format!(
                "is too small to normalise (largest component {m:e} < {:e}): give a direction of ordinary size",
                f32::MIN_POSITIVE
            ),
        ));
    }
    if m > f32::MAX as f64 {
        return Err(InputError::new(
            file,
            field,
            format!(
                "overflows f32 (component {m:e} > {:e}): give a direction of ordinary size",
                f32::MAX
            ),
        ));
    }
    // Scale by the largest component first: the length then neither under- nor overflows.
    Ok((glam::DVec3::from_array(a) / m).normalize())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_must_fit_f32() {
        for bad in [1e39, -1e39, 1e308, 1e-40, -1e-320, f64::NAN, f64::INFINITY] {
            assert!(!fits_f32(bad), "{bad}");
            assert!(
                check_number("f", "x", bad, |_| true, "any").is_err(),
                "{bad}"
            );
        }
        for good in [0.0, -0.0, 1.0, -3e38, 1.2e-38, 1e-30] {
            assert!(fits_f32(good), "{good}");
        }
        assert!(check_derived("f", "x", 1e39, "the power").is_err());
        assert!(check_derived("f", "x", 1e30, "the power").is_ok());
    }

    /// A file where a folder is needed is named, for a write below it and for an output
    /// folder checked up front; a folder that is missing or that exists passes the check.
    #[test]
    fn a_file_in_the_way_of_a_folder_is_named() {
        let dir = std::env::temp_dir().join(format!("lightproof-err-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("afile");
        std::fs::write(&file, b"x").unwrap();
        let want = format!("cannot write: `{}` is a file, not a folder", file.display());
        for below in [file.join("x.json"), file.join("sub/x.json")] {
            let e = IoError::write(&below, "File exists (os error 17)");
            assert_eq!(
                (e.path, e.reason),
                (below.display().to_string(), want.clone())
            );
            assert_eq!(
                IoError::check_output_folder(&below).unwrap_err().reason,
                want
            );
        }
        assert_eq!(
            IoError::check_output_folder(&file).unwrap_err().reason,
            want
        );
        // Nothing in the way: the system's reason is kept, and folders pass.
        let e = IoError::write(&dir.join("x.json"), "Permission denied");
        assert_eq!(e.reason, "cannot write: Permission denied");
        assert!(IoError::check_output_folder(&dir).is_ok());
        assert!(IoError::check_output_folder(&dir.join("new/deeper")).is_ok());
        assert!(IoError::check_output_folder(std::path::Path::new("relative-out")).is_ok());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A symbolic link whose target is missing, given as the output folder or met on the
    /// way to a file, is named with its target (the system says "File exists"); a link to
    /// a folder passes, and a link to a file is a file in the way.
    #[cfg(unix)]
    #[test]
    fn a_dangling_link_in_the_way_of_a_folder_is_named() {
        let dir = std::env::temp_dir().join(format!("lightproof-link-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (dangling, to_dir, to_file) =
            (dir.join("out"), dir.join("to-dir"), dir.join("to-file"));
        let missing = dir.join("missing/target");
        std::os::unix::fs::symlink(&missing, &dangling).unwrap();
        std::os::unix::fs::symlink(&dir, &to_dir).unwrap();
        std::fs::write(dir.join("afile"), b"x").unwrap();
        std::os::unix::fs::symlink(dir.join("afile"), &to_file).unwrap();
        let want = format!(
            "cannot write: `{}` is a symbolic link to `{}`, which leads to nothing",
            dangling.display(),
            missing.display()
        );
        assert_eq!(
            IoError::check_output_folder(&dangling).unwrap_err().reason,
            want
        );
        assert_eq!(
            IoError::check_output_folder(&dangling.join("deeper"))
                .unwrap_err()
                .reason,
            want
        );
        let e = IoError::write(&dangling.join("x.json"), "File exists (os error 17)");
        assert_eq!(e.reason, want);
        assert!(IoError::check_output_folder(&to_dir).is_ok());
        assert!(IoError::check_output_folder(&to_dir.join("new")).is_ok());
        assert_eq!(
            IoError::check_output_folder(&to_file).unwrap_err().reason,
            format!(
                "cannot write: `{}` is a file, not a folder",
                to_file.display()
            )
        );
        // A link to a dangling link leads to nothing too; two links to each other cannot
        // be followed, and the system's reason says why.
        let chain = dir.join("chain");
        std::os::unix::fs::symlink(&dangling, &chain).unwrap();
        assert!(
            IoError::check_output_folder(&chain)
                .unwrap_err()
                .reason
                .ends_with(&format!(
                    "to `{}`, which leads to nothing",
                    dangling.display()
                ))
        );
        let (a, b) = (dir.join("loop-a"), dir.join("loop-b"));
        std::os::unix::fs::symlink(&b, &a).unwrap();
        std::os::unix::fs::symlink(&a, &b).unwrap();
        let e = IoError::write(&a.join("x.json"), "File exists (os error 17)").reason;
        assert!(
            e.starts_with(&format!(
                "cannot write: `{}` is a symbolic link to `{}`, which cannot be followed (",
                a.display(),
                b.display()
            )),
            "{e}"
        );
        // The file itself a dangling link: nothing above it is in the way.
        let e = IoError::write(&dangling, "No such file or directory");
        assert_eq!(e.reason, "cannot write: No such file or directory");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn points_and_directions() {
        assert!(check_point("f", "p", [0.0, 1e18, -1e18]).is_ok());
        assert!(check_point("f", "p", [0.0, 1e19, 0.0]).is_err());
        let e = check_direction("f", "d", [0.0, 0.0, 1e-320]).unwrap_err();
        assert!(e.reason.contains("too small to normalise"), "{e}");
        assert!(check_direction("f", "d", [0.0; 3]).is_err());
        assert!(check_direction("f", "d", [0.0, 0.0, 1e39]).is_err());
        let d = check_direction("f", "d", [3e-30, 0.0, 4e-30]).unwrap();
        assert!((d.length() - 1.0).abs() < 1e-12);
    }
}
