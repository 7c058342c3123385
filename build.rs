//! Records the git revision of the build in `LIGHTPROOF_GIT_REVISION` (reports carry it,
//! and `report` resumes only from reports of the same revision). A work tree whose
//! sources differ from the commit is marked: `SHA-dirty-DIGEST`, DIGEST a hash of the
//! source files as they are, so two different uncommitted states never pass for the same
//! build. Never fails: without git (a source archive) it says `unknown-DIGEST`; the
//! environment variable of the same name, set at build time, overrides it (e.g. for a
//! container built from a source archive).

use std::path::{Path, PathBuf};
use std::process::Command;

/// What the build is made of: the sources whose change changes the binary.
const SOURCES: [&str; 6] = [
    "src",
    "analytic/src",
    "analytic/Cargo.toml",
    "Cargo.toml",
    "Cargo.lock",
    "build.rs",
];

/// FNV-1a, 64 bits (Fowler, Noll, Vo): a stable hash, the same on every toolchain.
fn fnv1a(h: u64, bytes: &[u8]) -> u64 {
    bytes.iter().fold(h, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// Every file under `path` (or `path` itself), sorted, so the digest does not depend on
/// the order the file system lists them in.
fn files(path: &Path, out: &mut Vec<PathBuf>) {
    if path.is_dir() {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(path)
            .map(|d| d.flatten().map(|e| e.path()).collect())
            .unwrap_or_default();
        entries.sort();
        for e in entries {
            files(&e, out);
        }
    } else if path.is_file() {
        out.push(path.to_path_buf());
    }
}

/// A digest of the sources: each file's path (relative to the package) and contents.
fn source_digest(root: &Path) -> String {
    let mut all = vec![];
    for s in SOURCES {
        files(&root.join(s), &mut all);
    }
    let h = all.iter().fold(0xcbf2_9ce4_8422_2325, |h, f| {
        let rel = f
            .strip_prefix(root)
            .unwrap_or(f)
            .to_string_lossy()
            .into_owned();
        let h = fnv1a(h, rel.as_bytes());
        fnv1a(h, &std::fs::read(f).unwrap_or_default())
    });
    format!("{h:016x}")
}

fn git(args: &[&str]) -> Option<String> {
    let out = Command::new("git").args(args).output().ok()?;
    if !out.status.success() {
        return None;
    }
    let s = String::from_utf8(out.stdout).ok()?.trim().to_string();
    (!s.is_empty()).then_some(s)
}

fn main() {
    let root = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").unwrap_or_default());
    for s in SOURCES {
        if root.join(s).exists() {
            println!("cargo:rerun-if-changed={s}");
        }
    }
    println!("cargo:rerun-if-env-changed=LIGHTPROOF_GIT_REVISION");
    // The list itself, for the test that checks the mark (report::machine::SOURCES).
    println!("cargo:rustc-env=LIGHTPROOF_SOURCES={}", SOURCES.join(" "));
    let revision = std::env::var("LIGHTPROOF_GIT_REVISION")
        .ok()
        .filter(|s| !s.is_empty())
        .or_else(|| {
            let rev = git(&["rev-parse", "HEAD"])?;
            // Rebuild when HEAD moves: watch HEAD, the branch it names and packed-refs
            // (only files that exist, or cargo would rerun this script every build).
            let dir = git(&["rev-parse", "--git-dir"]).map(PathBuf::from);
            let common = git(&["rev-parse", "--git-common-dir"]).map(PathBuf::from);
            let branch = git(&["symbolic-ref", "-q", "HEAD"]);
            let mut watch = vec![];
            if let Some(d) = &dir {
                watch.push(d.join("HEAD"));
            }
            if let Some(c) = common.as_ref().or(dir.as_ref()) {
                watch.push(c.join("packed-refs"));
                if let Some(b) = &branch {
                    watch.push(c.join(b));
                }
            }
            for w in watch.iter().filter(|w| w.exists()) {
                println!("cargo:rerun-if-changed={}", w.display());
            }
            let mut status = vec!["status", "--porcelain", "--"];
            status.extend(SOURCES);
            Some(match git(&status) {
                None => rev,
                Some(_) => format!("{rev}-dirty-{}", source_digest(&root)),
            })
        })
        .unwrap_or_else(|| format!("unknown-{}", source_digest(&root)));
    println!("cargo:rustc-env=LIGHTPROOF_GIT_REVISION={revision}");
    // The cargo profile, which `PROFILE` does not name for a custom one (`fast` reads
    // `release`): the folder above `build/` in OUT_DIR (target/[TRIPLE/]PROFILE/build/
    // PKG-HASH/out; `debug` for the `dev` and `test` profiles).
    let profile = std::env::var_os("OUT_DIR")
        .map(PathBuf::from)
        .and_then(|out| {
            let dir = out.parent()?.parent()?.parent()?;
            Some(dir.file_name()?.to_string_lossy().into_owned())
        })
        .unwrap_or_else(|| "unknown".to_string());
    println!("cargo:rustc-env=LIGHTPROOF_PROFILE={profile}");
}
