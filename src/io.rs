//! Atomic file writing: write to a temporary file in the same folder, flush it to disk,
//! then rename it over the target, so a reader (or an interrupted run) sees either the
//! old file whole or the new one whole, never a half-written one.

use crate::error::InputError;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Largest JSON input (a case, scene, report or shard partial file): 64 MiB.
pub const MAX_JSON_BYTES: u64 = 64 << 20;

/// Largest asset a scene refers to (an OBJ mesh, an EXR environment map): 1 GiB.
pub const MAX_ASSET_BYTES: u64 = 1 << 30;

/// Check that `path` is a regular file (after following links) of at most `limit`
/// bytes, and return its length. Devices (`/dev/zero`), FIFOs and folders are refused:
/// reading them could block or never end.
pub fn check_input_file(path: &Path, limit: u64) -> Result<u64, String> {
    let meta = std::fs::metadata(path).map_err(|e| format!("cannot read the file: {e}"))?;
    if !meta.is_file() {
        return Err(if meta.is_dir() {
            "is a folder, not a file".to_string()
        } else {
            "is not a regular file (a device, FIFO or socket): refusing to read it".to_string()
        });
    }
    if meta.len() > limit {
        return Err(format!(
            "is {} bytes, larger than the limit of {limit} bytes ({} MiB)",
            meta.len(),
            limit >> 20
        ));
    }
    Ok(meta.len())
}

/// Read a UTF-8 input file of at most `limit` bytes (see [`check_input_file`]); the
/// read itself stops past the limit, should the file grow meanwhile.
pub fn read_input(path: &Path, limit: u64) -> Result<String, String> {
    use std::io::Read;
    check_input_file(path, limit)?;
    let f = std::fs::File::open(path).map_err(|e| format!("cannot read the file: {e}"))?;
    let mut bytes = Vec::new();
    f.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| format!("cannot read the file: {e}"))?;
    if bytes.len() as u64 > limit {
        return Err(format!(
            "grew past the limit of {limit} bytes while being read"
        ));
    }
    String::from_utf8(bytes).map_err(|e| format!("is not UTF-8 text: {e}"))
}

/// The files among `paths` and in the folders among them (and their sub-folders when
/// `recursive`) that `keep` accepts, sorted, each once. Files given directly are kept
/// whatever their name; a path that does not exist is an error naming it. Inside a
/// folder, a symbolic link to a file is kept as the file, and a symbolic link to a
/// folder is skipped (a link to `.` or to a folder above would list it again and again).
pub fn collect_files(
    paths: &[PathBuf],
    recursive: bool,
    keep: impl Fn(&Path) -> bool,
) -> Result<Vec<PathBuf>, InputError> {
    let mut out = Vec::new();
    for p in paths {
        if p.is_dir() {
            let mut stack = vec![p.clone()];
            while let Some(d) = stack.pop() {
                let rd = std::fs::read_dir(&d).map_err(|e| {
                    InputError::new(
                        d.display().to_string(),
                        "-",
                        format!("cannot read folder: {e}"),
                    )
                })?;
                for entry in rd.flatten() {
                    let q = entry.path();
                    // The entry's own type, links not followed: a link to a folder is
                    // not entered (`l -> .` once listed a folder 41 times, and two such
                    // links exponentially often); a link to a file is read as the file.
                    if entry.file_type().is_ok_and(|t| t.is_dir()) {
                        if recursive {
                            stack.push(q);
                        }
                    } else if q.is_file() && keep(&q) {
                        out.push(q);
                    }
                }
            }
        } else if p.exists() {
            out.push(p.clone());
        } else {
            return Err(InputError::new(
                p.display().to_string(),
                "-",
                "no such file or folder",
            ));
        }
    }
    out.sort();
    out.dedup();
    Ok(out)
}

/// Write `bytes` to `path` atomically. The temporary file `.NAME.tmpPID` is removed on
/// every failure (create, write, flush, rename), and temporaries of the same target
/// left by processes that no longer exist (a kill during an earlier write) are cleaned
/// up first.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    write_via_temporary(path, &name, "", |tmp| {
        let mut f = std::fs::File::create(tmp)?;
        f.write_all(bytes)?;
        f.sync_all()
    })
}

/// Write a `w` × `h` RGB EXR atomically, as [`write_atomic`] does (the temporary is
/// `.STEM.tmpPID.exr`: the exr crate picks its format by the extension);
/// `pixel(x, y)` gives the colour of column x of row y, row 0 at the top.
pub fn write_exr_atomic(
    path: &Path,
    w: usize,
    h: usize,
    pixel: impl Fn(usize, usize) -> (f32, f32, f32) + Sync,
) -> std::io::Result<()> {
    let stem = path
        .file_stem()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    write_via_temporary(path, &stem, ".exr", |tmp| {
        exr::prelude::write_rgb_file(tmp, w, h, pixel)
            .map_err(|e| std::io::Error::other(e.to_string()))
    })
}

/// An output file `out` that cannot be written: a name that ends in a separator (a
/// folder's name), a folder above it that cannot be one
/// ([`crate::error::IoError::check_output_folder`]), `out` itself an existing folder, or a folder
/// that refuses a new file (read-only, `/proc`), found by creating and removing an
/// empty `.NAME.probePID` in the nearest existing folder on the way. Checked before a
/// command's work (a render, a whole `verify`), so that it does not end in an
/// unwritable output.
pub fn check_output_file(out: &Path) -> Result<(), crate::error::IoError> {
    let fail = |why: String| crate::error::IoError {
        path: out.display().to_string(),
        reason: format!("cannot write: {why}"),
    };
    // `file_name` ignores a trailing `/` (and `/.`): `--json newdir/` passed this check
    // and failed only at the rename, after the whole run.
    let text = out.as_os_str().to_string_lossy();
    let last = out.components().next_back();
    if text.ends_with(std::path::is_separator)
        || text.ends_with("/.")
        || !matches!(last, Some(std::path::Component::Normal(_)))
    {
        return Err(fail(format!(
            "`{}` names a folder (it ends in a separator, `.` or `..`), not a file",
            out.display()
        )));
    }
    if let Some(why) = crate::error::not_a_folder(out) {
        return Err(fail(why));
    }
    if out.is_dir() {
        return Err(fail(format!("`{}` is a folder, not a file", out.display())));
    }
    let name = out
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let Some(dir) = out
        .ancestors()
        .skip(1)
        .map(|a| {
            if a.as_os_str().is_empty() {
                std::path::Path::new(".")
            } else {
                a
            }
        })
        .find(|a| a.is_dir())
    else {
        return Ok(());
    };
    probe_new_file(dir, &name)
        .map_err(|e| fail(format!("`{}` takes no new file ({e})", dir.display())))
}

/// A path as the system would resolve it once written: the nearest existing folder on
/// its way made canonical (links and `..` resolved), then the rest as given, so that an
/// output that does not exist yet can be compared with the inputs.
fn resolved(path: &Path) -> Option<PathBuf> {
    use std::path::Component;
    let mut rest = Vec::new();
    for a in path.ancestors() {
        let a = if a.as_os_str().is_empty() {
            Path::new(".")
        } else {
            a
        };
        if let Ok(c) = a.canonicalize() {
            // The part that does not exist has no links: its `..` and `.` are lexical
            // (`newdir/../cases/v.json` is `cases/v.json`; it once resolved to nothing,
            // and the output escaped the check).
            let mut p = c;
            for n in rest.iter().rev() {
                match n {
                    Component::ParentDir => {
                        p.pop();
                    }
                    Component::CurDir => {}
                    Component::Normal(n) => p.push(n),
                    Component::RootDir | Component::Prefix(_) => return None,
                }
            }
            return Some(p);
        }
        rest.push(a.components().next_back()?);
    }
    None
}

/// Refuse an output file `out` (the command's `flag`) that is one of the input `files`
/// (the same file once both are canonical: an output that does not exist yet is none of
/// them), or that is a `.json` file inside one of the input `folders`, which are read
/// through their sub-folders: `verify in.json --json in.json` replaced the case file
/// with the verdict, and a verdict written into a catalog is read as a case next run.
/// Bad input (exit 2), told before any work.
pub fn refuse_output_on_input(
    flag: &str,
    out: &Path,
    files: &[PathBuf],
    folders: &[PathBuf],
) -> Result<(), InputError> {
    let refuse =
        |why: String| InputError::new("<command line>", flag, format!("`{}` {why}", out.display()));
    if let Ok(o) = out.canonicalize()
        && let Some(f) = files
            .iter()
            .find(|f| f.canonicalize().is_ok_and(|f| f == o))
    {
        return Err(refuse(format!(
            "is the input file `{}`: writing it would destroy the input",
            f.display()
        )));
    }
    let json = out.extension().is_some_and(|x| x == "json");
    if let (true, Some(o)) = (json, resolved(out))
        && let Some(d) = folders
            .iter()
            .find(|d| d.canonicalize().is_ok_and(|d| o.starts_with(d)))
    {
        return Err(refuse(format!(
            "lies inside the input folder `{}`, read through its sub-folders: it would be read as a case file on the next run",
            d.display()
        )));
    }
    Ok(())
}

/// Refuse two outputs of one command (`flag`, path) that name the same file (compared as
/// [`refuse_output_on_input`] compares them, whether or not it exists yet): the second
/// write would replace the first. Bad input (exit 2), told before any work.
pub fn refuse_same_output(a: (&str, &Path), b: (&str, &Path)) -> Result<(), InputError> {
    match (resolved(a.1), resolved(b.1)) {
        (Some(x), Some(y)) if x == y => Err(InputError::new(
            "<command line>",
            b.0,
            format!(
                "`{}` is the file {} names: one output would replace the other",
                b.1.display(),
                a.0
            ),
        )),
        _ => Ok(()),
    }
}

/// Refuse an output folder `out` (the command's `flag`) that is, or lies inside, one of
/// the input `folders` (its JSON files would be read as cases on the next run), or that
/// holds one of the input `files` itself, where the command writes its own files
/// (`report reports/x.json` wrote its report `reports/x.json` over the case; a folder
/// further down is not written flat, and is let be). Bad input (exit 2), told before
/// any work.
pub fn refuse_output_folder_on_input(
    flag: &str,
    out: &Path,
    files: &[PathBuf],
    folders: &[PathBuf],
) -> Result<(), InputError> {
    let Some(o) = resolved(out) else {
        return Ok(());
    };
    let refuse =
        |why: String| InputError::new("<command line>", flag, format!("`{}` {why}", out.display()));
    if let Some(d) = folders
        .iter()
        .find(|d| d.canonicalize().is_ok_and(|d| o.starts_with(d)))
    {
        return Err(refuse(format!(
            "is or lies inside the input folder `{}`, read through its sub-folders: the files written there would be read as case files on the next run",
            d.display()
        )));
    }
    if let Some(f) = files.iter().find(|f| {
        f.canonicalize()
            .is_ok_and(|f| f.parent().is_some_and(|p| p == o))
    }) {
        return Err(refuse(format!(
            "holds the input file `{}`, which a file written there could replace",
            f.display()
        )));
    }
    Ok(())
}

/// An output folder `out` that cannot be written: a folder on the way that cannot be one
/// ([`crate::error::IoError::check_output_folder`]), or the nearest existing folder on the
/// way (`out` itself when it exists) refusing a new file ([`probe_new_file`]: read-only,
/// `/proc`). Checked before a command's work (`report`'s sweep, `chi2`'s sampling), so
/// that it does not end in an unwritable output.
pub fn check_output_dir(out: &Path) -> Result<(), crate::error::IoError> {
    crate::error::IoError::check_output_folder(out)?;
    let Some(dir) = out
        .ancestors()
        .map(|a| {
            if a.as_os_str().is_empty() {
                Path::new(".")
            } else {
                a
            }
        })
        .find(|a| a.is_dir())
    else {
        return Ok(());
    };
    probe_new_file(dir, "lightproof").map_err(|e| crate::error::IoError {
        path: out.display().to_string(),
        reason: format!("cannot write: `{}` takes no new file ({e})", dir.display()),
    })
}

/// Whether `dir` takes a new file: an empty `.NAME.probePID` is created there and removed
/// at once (a read-only folder, or `/proc`, refuses it). For checking an output before a
/// command's work; nothing is left behind.
pub fn probe_new_file(dir: &Path, name: &str) -> std::io::Result<()> {
    let probe = dir.join(format!(".{name}.probe{}", std::process::id()));
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)?;
    std::fs::remove_file(&probe)
}

/// Run `write` on the temporary `.NAME.tmpPID{suffix}` beside `path`, then rename it
/// over `path`; on any failure the temporary is removed.
fn write_via_temporary(
    path: &Path,
    name: &str,
    suffix: &str,
    write: impl FnOnce(&Path) -> std::io::Result<()>,
) -> std::io::Result<()> {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir)?;
    remove_stale_temporaries(dir, name);
    let tmp = dir.join(format!(".{name}.tmp{}{suffix}", std::process::id()));
    // One write at a time, under the lock an interrupt takes before the process exits
    // ([`hold_writes`]): it never ends one half-way, with its temporary left behind.
    let _writing = writes();
    let written = write(&tmp).and_then(|()| std::fs::rename(&tmp, path));
    if written.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    written
}

/// The lock every [`write_via_temporary`] holds.
fn writes() -> std::sync::MutexGuard<'static, ()> {
    static WRITES: std::sync::Mutex<()> = std::sync::Mutex::new(());
    WRITES.lock().unwrap_or_else(|e| e.into_inner())
}

/// Wait for the write under way, if any, to end (renamed into place, or failed and its
/// temporary removed) and hold off the next: for an interrupt (Ctrl-C, SIGTERM, SIGHUP),
/// which then ends the process holding it. Every target is then its old version or its
/// new one, whole, with no `.NAME.tmpPID` beside it (a Ctrl-C once left one, removed
/// only by a later write to the same target). A kill that cannot be caught (SIGKILL)
/// still can, and the next write to its target removes it.
pub fn hold_writes() -> std::sync::MutexGuard<'static, ()> {
    writes()
}

/// Remove `.NAME.tmpPID` (or `.NAME.tmpPID.exr`) files in `dir` whose process is gone (Linux: no `/proc/PID`).
/// Elsewhere nothing is removed (a live writer's temporary must never be).
fn remove_stale_temporaries(dir: &Path, name: &str) {
    if !Path::new("/proc/self").exists() {
        return;
    }
    let prefix = format!(".{name}.tmp");
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let file_name = entry.file_name();
        let Some(pid) = file_name
            .to_str()
            .and_then(|n| n.strip_prefix(&prefix))
            .map(|p| p.strip_suffix(".exr").unwrap_or(p))
            .and_then(|p| p.parse::<u32>().ok())
        else {
            continue;
        };
        if pid != std::process::id() && !Path::new(&format!("/proc/{pid}")).exists() {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An output file checked up front: a file above it, a folder in its place and a
    /// folder that takes no file are named; a new file in a new folder, a file that
    /// exists and a bare name pass, and the probe leaves nothing behind.
    #[test]
    fn an_output_file_that_cannot_be_written_is_named() {
        let dir = std::env::temp_dir().join(format!("lightproof-out-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("afile");
        std::fs::write(&file, b"x").unwrap();
        let reason = |p: &std::path::Path| check_output_file(p).unwrap_err().reason;
        assert_eq!(
            reason(&file.join("x.exr")),
            format!("cannot write: `{}` is a file, not a folder", file.display())
        );
        assert_eq!(
            reason(&dir),
            format!("cannot write: `{}` is a folder, not a file", dir.display())
        );
        if std::path::Path::new("/proc/self").exists() {
            assert!(
                reason(std::path::Path::new("/proc/x.exr")).contains("`/proc` takes no new file")
            );
        }
        for ok in [
            dir.join("new/deeper/x.json"),
            file.clone(),
            dir.join("y.exr"),
        ] {
            assert!(check_output_file(&ok).is_ok(), "{}", ok.display());
        }
        assert!(check_output_file(std::path::Path::new("bare-name.json")).is_ok());
        // A name ending in a separator names a folder, existing or not.
        for folder in [dir.join("newdir/"), dir.join("x.exr/"), dir.join("x.exr/.")] {
            let p = std::path::PathBuf::from(format!("{}/", folder.display()));
            for p in [folder.clone(), p] {
                assert!(
                    reason(&p).contains("names a folder (it ends in a separator"),
                    "{}",
                    p.display()
                );
            }
        }
        assert!(reason(std::path::Path::new("..")).contains("names a folder"));
        let left: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .flatten()
            .map(|e| e.file_name())
            .collect();
        assert_eq!(left, vec![std::ffi::OsString::from("afile")]);
        assert!(!dir.join("new").exists(), "the check creates no folder");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// An output that is an input file (by another name too), or a `.json` output inside
    /// an input folder, is refused naming the flag, the path and the input; a new file
    /// elsewhere, or one that is not JSON inside the folder, passes. An output folder is
    /// refused inside an input folder and around an input file.
    #[test]
    fn an_output_on_an_input_is_refused() {
        let dir = std::env::temp_dir().join(format!("lightproof-io-clash-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("cases/sub")).unwrap();
        let case = dir.join("in.json");
        std::fs::write(&case, b"{}").unwrap();
        let files = [case.clone()];
        let folders = [dir.join("cases")];
        let file = |out: &Path| refuse_output_on_input("--json", out, &files, &folders);
        let e = file(&dir.join("cases/../in.json")).unwrap_err();
        assert_eq!(
            (e.file.as_str(), e.field.as_str()),
            ("<command line>", "--json")
        );
        assert!(e.reason.contains("is the input file"), "{e}");
        for inside in [
            "cases/v.json",
            "cases/new/deeper/v.json",
            "cases/sub/../v.json",
            // Through a folder that does not exist: `..` is lexical there.
            "newdir/../cases/v.json",
            "newdir/./../cases/new/v.json",
        ] {
            let e = file(&dir.join(inside)).unwrap_err();
            assert!(e.reason.contains("lies inside the input folder"), "{e}");
        }
        for ok in [
            "v.json",
            "cases/v.html",
            "casesx/v.json",
            "cases/../newdir/v.json",
        ] {
            assert!(file(&dir.join(ok)).is_ok(), "{ok}");
        }
        let folder = |out: &Path| refuse_output_folder_on_input("--out", out, &files, &folders);
        for bad in ["cases", "cases/sub/rep", ".", "newdir/../cases"] {
            assert!(folder(&dir.join(bad)).is_err(), "{bad}");
        }
        for ok in ["reports", ".."] {
            assert!(folder(&dir.join(ok)).is_ok(), "{ok}");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn collects_files_sorted_once_recursively_or_not() {
        let dir = std::env::temp_dir().join(format!("lightproof-io-walk-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        for f in ["b.json", "a.json", "c.txt", "sub/d.json"] {
            std::fs::write(dir.join(f), b"{}").unwrap();
        }
        let json = |p: &Path| p.extension().is_some_and(|x| x == "json");
        let names = |v: Vec<PathBuf>| -> Vec<String> {
            v.iter()
                .map(|p| p.strip_prefix(&dir).unwrap().display().to_string())
                .collect()
        };
        let given = [dir.clone(), dir.join("a.json"), dir.join("c.txt")];
        assert_eq!(
            names(collect_files(&given, true, json).unwrap()),
            ["a.json", "b.json", "c.txt", "sub/d.json"]
        );
        assert_eq!(
            names(collect_files(std::slice::from_ref(&dir), false, json).unwrap()),
            ["a.json", "b.json"]
        );
        let missing = collect_files(&[dir.join("nope")], true, json).unwrap_err();
        assert!(missing.reason.contains("no such file"), "{missing}");
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// Links to folders are not entered (`l1 -> .` and `l2 -> .` once listed `a.json`
    /// exponentially often); a link to a file is kept as that file.
    #[cfg(unix)]
    #[test]
    fn links_to_folders_are_skipped_and_links_to_files_kept() {
        let dir = std::env::temp_dir().join(format!("lightproof-io-links-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        std::fs::write(dir.join("a.json"), b"{}").unwrap();
        std::fs::write(dir.join("sub/b.json"), b"{}").unwrap();
        for (link, target) in [("l1", "."), ("l2", "."), ("up", ".."), ("f.json", "a.json")] {
            std::os::unix::fs::symlink(target, dir.join(link)).unwrap();
        }
        std::os::unix::fs::symlink("..", dir.join("sub/parent")).unwrap();
        let json = |p: &Path| p.extension().is_some_and(|x| x == "json");
        let found: Vec<String> = collect_files(std::slice::from_ref(&dir), true, json)
            .unwrap()
            .iter()
            .map(|p| p.strip_prefix(&dir).unwrap().display().to_string())
            .collect();
        assert_eq!(found, ["a.json", "f.json", "sub/b.json"]);
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// An output folder is checked for new files in the nearest existing folder on its way
    /// (`/proc` takes none); a writable one passes and keeps nothing of the check.
    #[test]
    fn an_output_folder_that_takes_no_file_is_named() {
        let dir = std::env::temp_dir().join(format!("lightproof-io-outdir-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for ok in [dir.clone(), dir.join("new/deeper")] {
            assert!(check_output_dir(&ok).is_ok(), "{}", ok.display());
        }
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0, "nothing left");
        if Path::new("/proc/self").exists() {
            for out in ["/proc", "/proc/rep", "/proc/rep/deeper"] {
                let e = check_output_dir(Path::new(out)).unwrap_err();
                assert_eq!(e.path, out);
                assert!(e.reason.contains("`/proc` takes no new file"), "{e}");
            }
        }
        // A file on the way is told as before, by `check_output_folder`.
        std::fs::write(dir.join("afile"), b"x").unwrap();
        let e = check_output_dir(&dir.join("afile/sub")).unwrap_err();
        assert!(e.reason.contains("is a file, not a folder"), "{e}");
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn replaces_whole_file() {
        let dir = std::env::temp_dir().join(format!("lightproof-io-{}", std::process::id()));
        let p = dir.join("a.json");
        write_atomic(&p, b"{\"v\":1}").unwrap();
        write_atomic(&p, b"{\"v\":2}").unwrap();
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "{\"v\":2}");
        let leftovers = std::fs::read_dir(&dir).unwrap().count();
        assert_eq!(leftovers, 1);
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn the_target_is_never_half_written() {
        // While the bytes are written the target still holds the old file, the bytes go
        // to a temporary beside it (same folder: the rename is atomic), and a write that
        // fails half-way leaves the old file as it was.
        let dir = std::env::temp_dir().join(format!("lightproof-io-half-{}", std::process::id()));
        let p = dir.join("r.json");
        write_atomic(&p, b"old").unwrap();
        write_via_temporary(&p, "r.json", "", |tmp| {
            assert_ne!(tmp, p.as_path());
            assert_eq!(tmp.parent(), p.parent());
            assert_eq!(std::fs::read(&p)?, b"old");
            std::fs::write(tmp, b"new")?;
            assert_eq!(std::fs::read(&p)?, b"old");
            Ok(())
        })
        .unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"new");
        let failed = write_via_temporary(&p, "r.json", "", |tmp| {
            std::fs::write(tmp, b"ha")?;
            Err(std::io::Error::other("disk full"))
        });
        assert!(failed.is_err());
        assert_eq!(std::fs::read(&p).unwrap(), b"new");
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn failures_leave_no_temporary() {
        let dir = std::env::temp_dir().join(format!("lightproof-io-fail-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("target_is_a_folder")).unwrap();
        // The rename fails (the target is a non-empty folder): the temporary goes.
        std::fs::write(dir.join("target_is_a_folder/x"), b"x").unwrap();
        assert!(write_atomic(&dir.join("target_is_a_folder"), b"{}").is_err());
        // A stale temporary of a dead process is removed by the next write.
        let stale = dir.join(".a.json.tmp4294967295");
        std::fs::write(&stale, b"half").unwrap();
        write_atomic(&dir.join("a.json"), b"{}").unwrap();
        let names: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert!(!names.iter().any(|n| n.contains(".tmp")), "{names:?}");
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn exr_is_written_whole_or_not_at_all() {
        let dir = std::env::temp_dir().join(format!("lightproof-io-exr-{}", std::process::id()));
        let p = dir.join("img.exr");
        write_exr_atomic(&p, 2, 1, |x, _| (x as f32, 0.0, 1.0)).unwrap();
        let img = exr::prelude::read_first_rgba_layer_from_file(
            &p,
            |r, _| vec![(0.0f32, 0.0f32, 0.0f32); r.width() * r.height()],
            |px: &mut Vec<(f32, f32, f32)>, pos, (r, g, b, _): (f32, f32, f32, f32)| {
                px[pos.y() * 2 + pos.x()] = (r, g, b)
            },
        )
        .unwrap();
        assert_eq!(img.layer_data.channel_data.pixels[1], (1.0, 0.0, 1.0));
        // A target that is a non-empty folder: the rename fails, no temporary stays.
        std::fs::create_dir_all(dir.join("busy.exr")).unwrap();
        std::fs::write(dir.join("busy.exr/x"), b"x").unwrap();
        assert!(write_exr_atomic(&dir.join("busy.exr"), 1, 1, |_, _| (0.0, 0.0, 0.0)).is_err());
        let names: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert!(!names.iter().any(|n| n.contains(".tmp")), "{names:?}");
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn inputs_must_be_small_regular_files() {
        assert!(check_input_file(Path::new("/dev/zero"), MAX_JSON_BYTES).is_err());
        let dir = std::env::temp_dir().join(format!("lightproof-io-in-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        assert!(check_input_file(&dir, MAX_JSON_BYTES).is_err());
        let big = dir.join("big.json");
        let f = std::fs::File::create(&big).unwrap();
        f.set_len(MAX_JSON_BYTES + 1).unwrap();
        assert!(
            read_input(&big, MAX_JSON_BYTES)
                .unwrap_err()
                .contains("limit")
        );
        std::fs::write(&big, b"{}").unwrap();
        assert_eq!(read_input(&big, MAX_JSON_BYTES).unwrap(), "{}");
        std::fs::remove_dir_all(dir).unwrap();
    }
    #[test]
    fn the_limit_is_inclusive_and_named_in_the_refusal() {
        let dir = std::env::temp_dir().join(format!("lightproof-io-lim-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("ten.json");
        std::fs::write(&p, b"0123456789").unwrap();
        // Exactly at the limit: accepted and read whole.
        assert_eq!(check_input_file(&p, 10), Ok(10));
        assert_eq!(read_input(&p, 10).unwrap(), "0123456789");
        // One byte over: refused, with the limit in bytes and MiB.
        let e = check_input_file(&p, 9).unwrap_err();
        assert!(
            e.contains("is 10 bytes") && e.contains("limit of 9 bytes"),
            "{e}"
        );
        let e = read_input(&p, 9).unwrap_err();
        assert!(e.contains("limit of 9 bytes"), "{e}");
        std::fs::write(&p, vec![b' '; (3 << 20) + 1]).unwrap();
        let e = check_input_file(&p, 3 << 20).unwrap_err();
        assert!(e.contains("(3 MiB)"), "{e}");
        // Folders and devices are told apart.
        assert!(check_input_file(&dir, 10).unwrap_err().contains("folder"));
        let dev = check_input_file(Path::new("/dev/null"), 10).unwrap_err();
        assert!(dev.contains("not a regular file"), "{dev}");
        // Not UTF-8.
        std::fs::write(&p, [0xffu8, 0xfe]).unwrap();
        assert!(read_input(&p, 10).unwrap_err().contains("UTF-8"));
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn live_writers_temporaries_are_kept() {
        if !Path::new("/proc/self").exists() {
            return;
        }
        let dir = std::env::temp_dir().join(format!("lightproof-io-live-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        // This process's own EXR temporary and one of process 1 (alive on Linux) are
        // not stale; a dead process's is.
        let own = dir.join(format!(".a.json.tmp{}.exr", std::process::id()));
        let init = dir.join(".a.json.tmp1");
        let dead = dir.join(".a.json.tmp4294967295.exr");
        for p in [&own, &init, &dead] {
            std::fs::write(p, b"half").unwrap();
        }
        write_atomic(&dir.join("a.json"), b"{}").unwrap();
        assert!(own.exists() && init.exists());
        assert!(!dead.exists());
        std::fs::remove_dir_all(dir).unwrap();
    }
    #[test]
    fn a_file_that_outgrows_its_size_is_cut_at_the_limit() {
        // Linux's /proc files are regular files that report a length of 0 and read as
        // more: the size check passes, and the read must stop one byte past the limit.
        let status = Path::new("/proc/self/status");
        if !status.exists() {
            return;
        }
        assert_eq!(check_input_file(status, 10), Ok(0));
        let e = read_input(status, 10).unwrap_err();
        assert!(e.contains("grew past the limit of 10 bytes"), "{e}");
    }

    #[test]
    fn asset_limit_is_one_gibibyte_and_json_limit_64_mebibytes() {
        assert_eq!(MAX_ASSET_BYTES, 1024 * 1024 * 1024);
        assert_eq!(MAX_JSON_BYTES, 64 * 1024 * 1024);
    }
}
