//! Records the git revision of the build in `LIGHTPROOF_GIT_REVISION` (reports carry it).
//! Never fails: without git, outside a checkout, or in CI it says `unknown`; the
//! environment variable of the same name, set at build time, overrides it (e.g. for a
//! container built from a source archive).

use std::path::PathBuf;
use std::process::Command;

fn git(args: &[&str]) -> Option<String> {
    let out = Command::new("git").args(args).output().ok()?;
    if !out.status.success() {
        return None;
    }
    let s = String::from_utf8(out.stdout).ok()?.trim().to_string();
    (!s.is_empty()).then_some(s)
}

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed=LIGHTPROOF_GIT_REVISION");
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
            Some(rev)
        })
        .unwrap_or_else(|| "unknown".to_string());
    println!("cargo:rustc-env=LIGHTPROOF_GIT_REVISION={revision}");
}
