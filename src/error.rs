//! The one error users see for bad input: the file, the field (a JSON path such as
//! `scene.shapes[2].geometry.radius`) and the reason. The command line prints it and
//! exits with status 2; nothing panics on input.

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

/// Check a number is finite and within bounds; `what` describes the bound.
pub fn check_number(
    file: &str,
    field: &str,
    v: f64,
    ok: impl Fn(f64) -> bool,
    what: &str,
) -> Result<(), InputError> {
    if !v.is_finite() {
        return Err(InputError::new(
            file,
            field,
            format!("must be a finite number, got {v}"),
        ));
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
