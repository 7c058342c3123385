//! Errors by class, each with its exit status on the command line:
//!
//! - [`InputError`], bad input (status 2): the file, the field (a JSON path such as
//!   `scene.shapes[2].geometry.radius`) and the reason; nothing panics on input;
//! - [`IoError`], the environment failed us (status 3): an output that cannot be
//!   written, worker threads that cannot start — the input was fine;
//! - a failed verdict is not an error of this module: the command line exits 1.
//!
//! [`Error`] is either of the first two, for functions that read input and write output.

use serde_json::Value;
use serde_path_to_error::Segment;

/// Bad input, located.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}: {}{reason}", at_field(field))]
pub struct InputError {
    /// The file (or `<inline>` for strings).
    pub file: String,
    /// JSON path of the offending field (`-` when the file as a whole is at fault).
    pub field: String,
    /// Why it is rejected.
    pub reason: String,
}

/// `FIELD: ` as an error message shows it; nothing for `-` (the file as a whole), so a
/// missing top-level field reads `case.json: missing field `measure``, not `case.json: -: …`.
fn at_field(field: &str) -> String {
    match field {
        "-" => String::new(),
        f => format!("{f}: "),
    }
}

impl InputError {
    /// The error without its file: `FIELD: REASON`, or the reason alone where the file
    /// as a whole is at fault (for a message that names its source another way, such as
    /// a command-line argument).
    pub fn without_file(&self) -> String {
        format!("{}{}", at_field(&self.field), self.reason)
    }

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
pub(crate) fn not_a_folder(path: &std::path::Path) -> Option<String> {
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
///
/// serde reads an internally tagged object (`{"type": "disk", "radius": "NaN"}`: a
/// geometry, an emitter, a BSDF) into a buffer before it knows the variant, so the path it
/// tracks ends at the object; [`field_in_tagged`] then finds the field at fault inside it.
pub fn parse_json<T: serde::de::DeserializeOwned>(file: &str, text: &str) -> Result<T, InputError> {
    let de = &mut serde_json::Deserializer::from_str(text);
    let value = serde_path_to_error::deserialize(&mut *de).map_err(|e| {
        let shown = e.path().to_string();
        let segments: Vec<Segment> = e.path().iter().cloned().collect();
        // The path up to the first segment serde could not name (a key not yet read
        // when a truncated or malformed text ends the parse, shown as `?`): the field is
        // the deepest one read, or none (the file as a whole is at fault).
        let known = known_prefix(&segments);
        let mut keys: Vec<String> = if known.is_empty() {
            vec![]
        } else {
            vec![known]
        };
        let reason = e.into_inner().to_string();
        if let Ok(doc) = serde_json::from_str::<serde_json::Value>(text) {
            keys.extend(field_in_tagged::<T>(&doc, &segments, &shown, &reason));
        }
        let field = if keys.is_empty() {
            "-".to_string()
        } else {
            keys.join(".")
        };
        InputError::new(file, field, reason)
    })?;
    // Text after the document (a second object, stray braces, a pasted fragment) is an
    // error, as `serde_json::from_str` makes it: the file is not the one JSON value it
    // should be, and what follows the first value would be silently ignored.
    de.end()
        .map_err(|e| InputError::new(file, "-", e.to_string()))?;
    Ok(value)
}

/// A path as serde_path_to_error shows it (`scene.shapes[0].geometry`), cut before its
/// first [`Segment::Unknown`]; empty for the document itself or a path that starts with
/// an unknown segment.
fn known_prefix(path: &[Segment]) -> String {
    let mut shown = String::new();
    for (i, seg) in path.iter().enumerate() {
        match seg {
            Segment::Unknown => break,
            Segment::Seq { index } => shown.push_str(&format!("[{index}]")),
            Segment::Map { key } | Segment::Enum { variant: key } => {
                if i > 0 {
                    shown.push('.');
                }
                shown.push_str(key);
            }
        }
    }
    shown
}

/// The JSON Pointer (RFC 6901) of a path of segments, for `Value::pointer`: an
/// externally tagged variant is the key it stands under; `None` for a segment serde could
/// not name.
fn pointer(path: &[Segment]) -> Option<String> {
    path.iter()
        .map(|seg| match seg {
            Segment::Seq { index } => Some(index.to_string()),
            Segment::Map { key } | Segment::Enum { variant: key } => Some(escape(key)),
            Segment::Unknown => None,
        })
        .map(|token| token.map(|t| format!("/{t}")))
        .collect()
}

/// A key as a JSON Pointer reference token: `~` as `~0`, `/` as `~1` (RFC 6901, §3).
fn escape(key: &str) -> String {
    key.replace('~', "~0").replace('/', "~1")
}

/// The error `T` gives for `doc`: its path and message (`None` if `doc` parses).
fn error_of<T: serde::de::DeserializeOwned>(doc: &Value) -> Option<(String, String)> {
    serde_path_to_error::deserialize::<_, T>(doc)
        .err()
        .map(|e| (e.path().to_string(), e.inner().to_string()))
}

/// The keys, outermost first, of the field at fault inside an internally tagged object
/// (one with a `"type"` key) at `path` (shown as `shown`), where serde's own path stops
/// at the object; `reason` is the error the text gave there.
///
/// Delta debugging (Zeller & Hildebrandt, IEEE TSE 28(2), 2002) with the parser as the
/// oracle: serde reports the first field whose value it rejects while it walks the
/// object's fields, so removing any other field leaves that error as it was, and removing
/// the field at fault changes it (to a missing field, a later error, or none). The one key
/// whose removal changes the error is the field; the search then descends into that
/// field's value if it is an object. The tag is never a candidate (serde's path already
/// names an unknown variant's `type`), a missing field is named by serde's own message at
/// the object, and anything ambiguous keeps serde's path: two keys that each change the
/// error, or a tree whose error is not the text's (its objects list keys in sorted order,
/// so with two bad fields it may stop at the other one). Only certain keys are added.
fn field_in_tagged<T: serde::de::DeserializeOwned>(
    doc: &Value,
    path: &[Segment],
    shown: &str,
    reason: &str,
) -> Vec<String> {
    let mut found = Vec::new();
    let Some(mut at) = pointer(path) else {
        return found;
    };
    let tagged = doc.pointer(&at).and_then(|v| v.get("type")).is_some();
    if !tagged || reason.starts_with("missing field") {
        return found;
    }
    let Some(base) = error_of::<T>(doc) else {
        return found;
    };
    // The text's error is the tree's, with the text's position after it.
    let same = base.0 == shown
        && (reason == base.1 || reason.starts_with(&format!("{} at line ", base.1)));
    if !same {
        return found;
    }
    // Each round names one key deeper; a document is finite, so the walk ends.
    while let Some(Value::Object(object)) = doc.pointer(&at) {
        let changes = |key: &str| {
            let mut d = doc.clone();
            if let Some(Value::Object(o)) = d.pointer_mut(&at) {
                o.remove(key);
            }
            error_of::<T>(&d).as_ref() != Some(&base)
        };
        let culprits: Vec<&String> = object
            .keys()
            .filter(|k| *k != "type" && changes(k))
            .collect();
        let [key] = culprits.as_slice() else {
            break;
        };
        let key = (*key).clone();
        at.push('/');
        at.push_str(&escape(&key));
        found.push(key);
    }
    found
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

/// Numbers read from JSON straight into `f32` fields (a BSDF's parameters, a spectrum's
/// or an index's coefficients), through the one check [`f32_problem`]: a value the
/// conversion would overflow to ∞ or flush to zero or a subnormal is a parse error
/// naming the field, not a silent change. Use with
/// `#[serde(deserialize_with = "crate::error::json_f32::scalar")]` (or `optional`,
/// `triple`, `list` for `Option<f32>`, `[f32; 3]`, `Vec<f32>`).
pub mod json_f32 {
    use serde::{Deserialize, Deserializer, de};

    /// An `f64` from JSON that fits `f32` ([`super::f32_problem`] finds nothing wrong);
    /// otherwise the error `f32_problem` gives. Any serde number (and only a number) is
    /// read.
    pub fn checked<E: de::Error>(v: f64) -> Result<f64, E> {
        match super::f32_problem(v) {
            None => Ok(v),
            Some(why) => Err(E::custom(why)),
        }
    }

    /// One `f32` read through [`checked`].
    struct Checked(f32);

    impl<'de> Deserialize<'de> for Checked {
        fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
            let v = f64::deserialize(d)?;
            checked(v).map(|v| Checked(v as f32))
        }
    }

    /// An `f32` field.
    pub fn scalar<'de, D: Deserializer<'de>>(d: D) -> Result<f32, D::Error> {
        Checked::deserialize(d).map(|c| c.0)
    }

    /// An optional `f32` field (give it `#[serde(default)]` too, for when it is absent).
    pub fn optional<'de, D: Deserializer<'de>>(d: D) -> Result<Option<f32>, D::Error> {
        Option::<Checked>::deserialize(d).map(|o| o.map(|c| c.0))
    }

    /// Three `f32`s.
    pub fn triple<'de, D: Deserializer<'de>>(d: D) -> Result<[f32; 3], D::Error> {
        <[Checked; 3]>::deserialize(d).map(|a| a.map(|c| c.0))
    }

    /// A list of `f32`s.
    pub fn list<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<f32>, D::Error> {
        Vec::<Checked>::deserialize(d).map(|v| v.into_iter().map(|c| c.0).collect())
    }

    /// A list of `f32`s read by [`list`], for a hand-written visitor
    /// (`map.next_value::<List>()?.0`).
    pub struct List(pub Vec<f32>);

    impl<'de> Deserialize<'de> for List {
        fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
            list(d).map(List)
        }
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

    /// A document with internally tagged objects, nested, as a case's geometry and
    /// emission are.
    #[derive(Debug, serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Doc {
        #[allow(dead_code)]
        shapes: Vec<Shape>,
        #[allow(dead_code)]
        #[serde(default)]
        named: std::collections::BTreeMap<String, Geometry>,
    }
    #[derive(Debug, serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Shape {
        #[allow(dead_code)]
        geometry: Geometry,
    }
    #[allow(dead_code)]
    #[derive(Debug, serde::Deserialize)]
    #[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
    enum Geometry {
        Disk { center: [f64; 3], radius: f64 },
        Lamp { radius: f64, glow: Glow },
    }
    #[allow(dead_code)]
    #[derive(Debug, serde::Deserialize)]
    #[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
    enum Glow {
        Flat { value: f64 },
    }

    /// Text after the document is refused, the file as a whole at fault; whitespace
    /// after it is not text.
    #[test]
    fn text_after_the_document_is_refused() {
        let doc = r#"{"shapes": []}"#;
        assert!(parse_json::<Doc>("f.json", &format!("{doc} \n\t")).is_ok());
        // `\u{7d}` is a lone closing brace, written so that brace counters stay balanced.
        for tail in [" {}", "\u{7d}", " xyz", "\n{\"shapes\": []}", " 1"] {
            let e = parse_json::<Doc>("f.json", &format!("{doc}{tail}")).unwrap_err();
            assert_eq!(
                (e.file.as_str(), e.field.as_str()),
                ("f.json", "-"),
                "{tail:?}"
            );
            assert!(e.reason.starts_with("trailing characters"), "{tail:?}: {e}");
        }
    }

    /// The field serde's path stops short of, inside a tagged object: found by removing
    /// one key at a time (a wrong type, an unknown field, an unknown variant, one level
    /// deeper), while a missing field stays at the object and a plain struct's path is
    /// serde's own.
    #[test]
    fn errors_inside_tagged_objects_name_the_field() {
        let field = |text: &str| parse_json::<Doc>("f.json", text).unwrap_err().field;
        let disk =
            |body: &str| format!(r#"{{"shapes": [{{"geometry": {{"type": "disk", {body}}}}}]}}"#);
        assert_eq!(
            field(&disk(r#""center": [0, 0, 0], "radius": "NaN""#)),
            "shapes[0].geometry.radius"
        );
        assert_eq!(
            field(&disk(r#""center": [0, "x", 0], "radius": 1"#)),
            "shapes[0].geometry.center"
        );
        assert_eq!(
            field(&disk(r#""center": [0, 0, 0], "radius": 1, "radiuss": 1"#)),
            "shapes[0].geometry.radiuss"
        );
        assert_eq!(
            field(r#"{"shapes": [{"geometry": {"type": "cube", "radius": 1}}]}"#),
            "shapes[0].geometry.type"
        );
        let missing = parse_json::<Doc>("f.json", &disk(r#""center": [0, 0, 0]"#)).unwrap_err();
        assert_eq!(missing.field, "shapes[0].geometry");
        assert!(
            missing.reason.contains("missing field `radius`"),
            "{missing}"
        );
        assert_eq!(
            field(
                r#"{"shapes": [{"geometry": {"type": "lamp", "radius": 1,
                   "glow": {"type": "flat", "value": true}}}]}"#
            ),
            "shapes[0].geometry.glow.value"
        );
        // Two bad fields: the tree lists keys sorted, so it stops at `center` where the
        // text stopped at `radius`; the search then keeps serde's path.
        assert_eq!(
            field(&disk(r#""radius": "x", "center": "y""#)),
            "shapes[0].geometry"
        );
        assert_eq!(
            field(&disk(r#""center": "y", "radius": "x""#)),
            "shapes[0].geometry.center"
        );
        // Keys with `/` and `~`, which a JSON Pointer escapes.
        assert_eq!(
            field(
                r#"{"shapes": [], "named": {"a/b~c": {"type": "disk", "center": [0, 0, 0],
                   "radius": "x"}}}"#
            ),
            "named.a/b~c.radius"
        );
        // A tagged object at the top of the document.
        let top = parse_json::<Geometry>(
            "f.json",
            r#"{"type": "disk", "center": [0, 0, 0], "radius": []}"#,
        );
        assert_eq!(top.unwrap_err().field, "radius");
        assert_eq!(
            field(r#"{"shapes": [{"geometry": 1}]}"#),
            "shapes[0].geometry"
        );
        assert_eq!(field(r#"{"shapes": [{"geo": 1}]}"#), "shapes[0].geo");
        assert_eq!(field("not json"), "-");
        // The file as a whole (`-`) is not shown as a field; any other field is.
        let whole = InputError::new("case.json", "-", "missing field `measure`");
        assert_eq!(whole.to_string(), "case.json: missing field `measure`");
        let one = InputError::new("case.json", "scene.shapes[0]", "bad");
        assert_eq!(one.to_string(), "case.json: scene.shapes[0]: bad");
    }

    /// A text that ends or breaks before serde has read a key leaves the field out
    /// (serde_path_to_error shows the unread key as `?`); one that ends inside a value
    /// names the deepest field it read.
    #[test]
    fn a_truncated_text_names_no_unread_field() {
        for (text, field, reason) in [
            ("{", "-", "EOF while parsing an object at line 1 column 1"),
            (r#"{"shapes": [], "#, "-", "EOF while parsing a value"),
            (r#"{"shapes": [] "named""#, "-", "expected `,` or `}`"),
            (r#"{"shapes": ["#, "shapes", "EOF while parsing a list"),
            (
                r#"{"shapes": [{"geometry": "#,
                "shapes[0].geometry",
                "EOF while parsing a value",
            ),
        ] {
            let e = parse_json::<Doc>("bad.json", text).unwrap_err();
            assert_eq!(e.field, field, "{text}: {e}");
            assert!(e.reason.starts_with(reason), "{text}: {e}");
            assert!(!e.to_string().contains('?'), "{text}: {e}");
        }
        let e = parse_json::<Doc>("bad.json", "{").unwrap_err();
        assert_eq!(
            e.to_string(),
            "bad.json: EOF while parsing an object at line 1 column 1"
        );
        assert_eq!(
            e.without_file(),
            "EOF while parsing an object at line 1 column 1"
        );
        let one = InputError::new("case.json", "scene.shapes[0]", "bad");
        assert_eq!(one.without_file(), "scene.shapes[0]: bad");
        assert_eq!(known_prefix(&[]), "");
        assert_eq!(
            known_prefix(&[
                Segment::Seq { index: 2 },
                Segment::Map { key: "a".into() },
                Segment::Unknown,
                Segment::Map { key: "b".into() },
            ]),
            "[2].a"
        );
    }

    /// A model whose parameters are read straight into `f32`, as a BSDF's are.
    #[allow(dead_code)]
    #[derive(Debug, serde::Deserialize)]
    #[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
    enum Paint {
        Matte {
            #[serde(deserialize_with = "json_f32::scalar")]
            albedo: f32,
            #[serde(default, deserialize_with = "json_f32::optional")]
            k: Option<f32>,
            #[serde(default, deserialize_with = "json_f32::triple")]
            rgb: [f32; 3],
            #[serde(default, deserialize_with = "json_f32::list")]
            table: Vec<f32>,
        },
    }

    /// Every `f32` field read through [`json_f32`] refuses what [`f32_problem`] refuses,
    /// with its message and the field's name (found inside the tagged object), and keeps
    /// what fits.
    #[test]
    fn numbers_read_into_f32_fields_must_fit() {
        let matte = |body: &str| {
            parse_json::<Paint>(
                "p.json",
                &format!(r#"{{"type": "matte", "albedo": 0.5, {body}}}"#),
            )
        };
        for bad in ["1e-39", "-1e-39", "5e-324", "1e39", "-1e39", "1e308"] {
            let v: f64 = bad.parse().unwrap();
            let why = f32_problem(v).unwrap();
            for (field, body) in [
                ("k", format!(r#""k": {bad}"#)),
                ("rgb", format!(r#""rgb": [0, {bad}, 0]"#)),
                ("table", format!(r#""table": [1, 2, {bad}]"#)),
            ] {
                let e = matte(&body).unwrap_err();
                assert_eq!(e.field, field, "{body}: {e}");
                assert!(e.reason.starts_with(&why), "{body}: {e}");
            }
            let e = parse_json::<Paint>(
                "p.json",
                &format!(r#"{{"type": "matte", "albedo": {bad}}}"#),
            )
            .unwrap_err();
            assert_eq!(
                (e.field.as_str(), e.reason.starts_with(&why)),
                ("albedo", true),
                "{e}"
            );
        }
        for good in ["0", "-0.0", "1", "-1", "1.2e-38", "3e38", "7"] {
            let v = good.parse::<f64>().unwrap() as f32;
            let Ok(Paint::Matte { k, rgb, table, .. }) = matte(&format!(
                r#""k": {good}, "rgb": [{good}, 0, 0], "table": [{good}]"#
            )) else {
                panic!("{good}")
            };
            assert_eq!((k, rgb, table), (Some(v), [v, 0.0, 0.0], vec![v]), "{good}");
        }
        let Ok(Paint::Matte { k: None, .. }) = matte(r#""rgb": [1, 2, 3]"#) else {
            panic!("k is optional")
        };
        let e = matte(r#""k": "NaN""#).unwrap_err();
        assert_eq!(e.field, "k", "{e}");
    }

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
