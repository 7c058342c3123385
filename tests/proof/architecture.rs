//! ARCHITECTURE.md's module layers, kept: every top-level module of `src/` sits in one
//! layer of its table, every module the table names exists, non-test code names only
//! modules of its own layer or below, and the modules' graph has no cycle. The layers are read from ARCHITECTURE.md itself, so
//! the page and the code cannot drift apart silently.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Top-level modules of `src/` (a file `x.rs` or a folder `x/`), without the crate roots.
fn top_modules() -> BTreeSet<String> {
    std::fs::read_dir(root().join("src"))
        .expect("src/ is readable")
        .flatten()
        .filter_map(|e| {
            let p = e.path();
            let name = p.file_stem()?.to_str()?.to_string();
            (p.is_dir() || p.extension().is_some_and(|x| x == "rs")).then_some(name)
        })
        .filter(|n| n != "lib" && n != "main")
        .collect()
}

/// ARCHITECTURE.md's table "Modules (dependencies point down; no cycles)": module →
/// layer index, 0 at the top. A module named in several rows (e.g. `spectrum` in the
/// harness row's "colour through `spectrum::cie`") belongs to the lowest of them, the row
/// where it is listed rather than mentioned.
fn layers(page: &str, modules: &BTreeSet<String>) -> BTreeMap<String, usize> {
    let section = page
        .split("## Modules (dependencies point down; no cycles)")
        .nth(1)
        .expect("ARCHITECTURE.md has the modules table");
    let rows = section
        .lines()
        .skip_while(|l| !l.starts_with('|'))
        .take_while(|l| l.starts_with('|'))
        .skip(2);
    let mut out = BTreeMap::new();
    for (i, row) in rows.enumerate() {
        let cells: Vec<&str> = row.split('|').collect();
        assert!(cells.len() >= 3, "malformed row {row:?}");
        for name in cells[2].split('`').skip(1).step_by(2) {
            let top = name.split("::").next().unwrap().trim_end_matches(".rs");
            if modules.contains(top) {
                out.insert(top.to_string(), i);
            }
        }
    }
    out
}

/// The source without comments and without `#[cfg(test)]` items (the tests of a module
/// may use any layer: they are not part of the library's graph).
fn code_of(text: &str) -> String {
    let mut s = String::with_capacity(text.len());
    let mut rest = text;
    while !rest.is_empty() {
        if let Some(r) = rest.strip_prefix("//") {
            rest = r.find('\n').map_or("", |k| &r[k..]);
        } else if let Some(r) = rest.strip_prefix("/*") {
            rest = r.find("*/").map_or("", |k| &r[k + 2..]);
        } else if let Some(r) = rest.strip_prefix("#[cfg(test)]") {
            // Skip the next item: to its matching brace, or to its `;` if none comes first.
            let open = r.find('{');
            let semi = r.find(';');
            rest = match (open, semi) {
                (Some(o), semi) if semi.is_none_or(|s| o < s) => {
                    let mut depth = 0usize;
                    let mut end = r.len();
                    for (k, c) in r[o..].char_indices() {
                        match c {
                            '{' => depth += 1,
                            '}' => {
                                depth -= 1;
                                if depth == 0 {
                                    end = o + k + 1;
                                    break;
                                }
                            }
                            _ => {}
                        }
                    }
                    &r[end..]
                }
                (_, Some(s)) => &r[s + 1..],
                _ => "",
            };
        } else {
            let c = rest.chars().next().unwrap();
            s.push(c);
            rest = &rest[c.len_utf8()..];
        }
    }
    s
}

/// The top-level modules a piece of code names through `crate::`: `crate::a::…`, and
/// each first segment of a `crate::{a::…, b, c::{…}}` group.
fn crate_refs(code: &str) -> BTreeSet<String> {
    let ident = |s: &str| -> String {
        s.trim_start()
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect()
    };
    let mut out = BTreeSet::new();
    for (k, _) in code.match_indices("crate::") {
        if k > 0 && {
            let b = code.as_bytes()[k - 1];
            b.is_ascii_alphanumeric() || b == b'_'
        } {
            continue; // e.g. `lightproof_crate::`
        }
        let after = code[k + "crate::".len()..].trim_start();
        if let Some(group) = after.strip_prefix('{') {
            let mut depth = 1usize;
            let mut start = true;
            for (i, c) in group.char_indices() {
                match c {
                    '{' => depth += 1,
                    '}' => {
                        depth -= 1;
                        if depth == 0 {
                            break;
                        }
                    }
                    ',' if depth == 1 => start = true,
                    c if start && !c.is_whitespace() => {
                        start = false;
                        let name = ident(&group[i..]);
                        if !name.is_empty() {
                            out.insert(name);
                        }
                    }
                    _ => {}
                }
            }
        } else {
            let name = ident(after);
            if !name.is_empty() {
                out.insert(name);
            }
        }
    }
    out
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).expect("readable folder").flatten() {
        let p = e.path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// Module → the other top-level modules its non-test code names, with one file each.
fn graph(modules: &BTreeSet<String>) -> BTreeMap<String, BTreeMap<String, String>> {
    let mut files = Vec::new();
    rust_files(&root().join("src"), &mut files);
    let mut g: BTreeMap<String, BTreeMap<String, String>> = BTreeMap::new();
    for f in files {
        let rel = f.strip_prefix(root()).unwrap().display().to_string();
        let top = rel
            .trim_start_matches("src/")
            .split('/')
            .next()
            .unwrap()
            .trim_end_matches(".rs")
            .to_string();
        if !modules.contains(&top) {
            continue; // lib.rs (the map) and main.rs (the CLI, above every layer)
        }
        let code = code_of(&std::fs::read_to_string(&f).unwrap());
        for m in crate_refs(&code) {
            if m != top && modules.contains(&m) {
                g.entry(top.clone())
                    .or_default()
                    .entry(m)
                    .or_insert(rel.clone());
            }
        }
    }
    g
}

#[test]
fn the_reference_finder_reads_paths_and_groups() {
    let code = code_of(
        "use crate::scene::Scene;\nuse crate::{case::Case, io::{read, write}, math};\n\
         // use crate::report;\n/// [`crate::judge`]\nfn f() { crate::stats::mean(); }\n\
         #[cfg(test)]\nmod tests { use crate::render; }\n#[cfg(test)]\nuse crate::table;\n\
         /* crate::suites */ let s = \"x\";",
    );
    let refs: Vec<String> = crate_refs(&code).into_iter().collect();
    assert_eq!(refs, ["case", "io", "math", "scene", "stats"]);
}

#[test]
fn modules_sit_in_the_layers_architecture_md_gives() {
    let page = std::fs::read_to_string(root().join("ARCHITECTURE.md")).unwrap();
    let modules = top_modules();
    assert!(modules.len() > 15, "{modules:?}");
    let layer = layers(&page, &modules);
    // Every module the table names exists: a top-level module, `a::b`, or a bare submodule
    // of some top-level one (`effects`); capitalised names are types (`Outcome`).
    let src = root().join("src");
    let exists = |p: std::path::PathBuf| p.with_extension("rs").is_file() || p.is_dir();
    let section = page
        .split("## Modules (dependencies point down; no cycles)")
        .nth(1)
        .unwrap();
    let table: Vec<&str> = section
        .lines()
        .skip_while(|l| !l.starts_with('|'))
        .take_while(|l| l.starts_with('|'))
        .skip(2)
        .collect();
    let mut stale = Vec::new();
    for row in &table {
        let cell = row.split('|').nth(2).unwrap_or("");
        for name in cell.split('`').skip(1).step_by(2) {
            if name.starts_with(|c: char| c.is_uppercase()) {
                continue;
            }
            let parts: Vec<&str> = name.trim_end_matches(".rs").split("::").collect();
            let found = match parts[..] {
                ["main"] => src.join("main.rs").is_file(),
                [m] => exists(src.join(m)) || modules.iter().any(|t| exists(src.join(t).join(m))),
                [a, b] => exists(src.join(a).join(b)),
                _ => false,
            };
            if !found {
                stale.push(name.to_string());
            }
        }
    }
    assert!(
        stale.is_empty(),
        "ARCHITECTURE.md names modules that do not exist: {stale:?}"
    );
    let unplaced: Vec<_> = modules.iter().filter(|m| !layer.contains_key(*m)).collect();
    assert!(
        unplaced.is_empty(),
        "modules missing from ARCHITECTURE.md's layer table: {unplaced:?}"
    );
    let g = graph(&modules);
    let mut upward = Vec::new();
    for (from, tos) in &g {
        for (to, file) in tos {
            if layer[to] < layer[from] {
                upward.push(format!(
                    "{file}: `{from}` (layer {}) names `{to}` (layer {})",
                    layer[from], layer[to]
                ));
            }
        }
    }
    assert!(
        upward.is_empty(),
        "dependencies pointing up:\n{}",
        upward.join("\n")
    );
    // No cycle, within a layer or across: depth-first search for a back edge.
    fn visit<'a>(
        m: &'a str,
        g: &'a BTreeMap<String, BTreeMap<String, String>>,
        state: &mut BTreeMap<&'a str, bool>,
        path: &mut Vec<&'a str>,
    ) -> Option<Vec<String>> {
        match state.get(m) {
            Some(true) => return None,
            Some(false) => {
                let at = path.iter().position(|p| *p == m).unwrap();
                return Some(
                    path[at..]
                        .iter()
                        .map(|s| s.to_string())
                        .chain([m.to_string()])
                        .collect(),
                );
            }
            None => {}
        }
        state.insert(m, false);
        path.push(m);
        for to in g.get(m).into_iter().flat_map(|t| t.keys()) {
            if let Some(cycle) = visit(to, g, state, path) {
                return Some(cycle);
            }
        }
        path.pop();
        state.insert(m, true);
        None
    }
    let mut state = BTreeMap::new();
    for m in &modules {
        if let Some(cycle) = visit(m, &g, &mut state, &mut Vec::new()) {
            panic!("an import cycle: {}", cycle.join(" → "));
        }
    }
    // The graph is not empty: the reference finder sees the engine's real imports.
    assert!(
        g.get("transport").is_some_and(|t| t.contains_key("scene")),
        "{g:?}"
    );
}

/// The calls that create or overwrite a file in place; outside `src/io.rs` the non-test
/// code must write through `io::write_atomic` / `write_exr_atomic` instead (temporary
/// file, then rename), so that no report, image or verdict file is ever left
/// half-written.
const IN_PLACE_WRITERS: [&str; 6] = [
    "fs::write(",
    "File::create(",
    "OpenOptions",
    "SVGBackend::new(",
    "BitMapBackend::new(",
    "write_rgb_file(",
];

/// Which in-place writers the non-test code of one file calls.
fn in_place_writers(text: &str) -> Vec<&'static str> {
    let code = code_of(text);
    IN_PLACE_WRITERS
        .into_iter()
        .filter(|w| code.contains(w))
        .collect()
}

#[test]
fn every_output_is_written_through_a_temporary() {
    // The finder sees a writer in code and not in comments or test modules.
    assert_eq!(
        in_place_writers("fn f() { std::fs::write(p, b)?; }"),
        ["fs::write("]
    );
    assert!(
        in_place_writers("// fs::write(p)\n#[cfg(test)]\nmod t { fn g() { File::create(p); } }")
            .is_empty()
    );
    let mut files = vec![];
    rust_files(&root().join("src"), &mut files);
    // The examples too: what they write (pictures, case files) goes through the same
    // writers (`examples/common`'s `save` and `save_svg`).
    rust_files(&root().join("examples"), &mut files);
    let io = root().join("src/io.rs");
    let offenders: Vec<String> = files
        .iter()
        .filter(|f| **f != io)
        .filter_map(|f| {
            let w = in_place_writers(&std::fs::read_to_string(f).unwrap());
            (!w.is_empty()).then(|| format!("{}: {w:?}", f.display()))
        })
        .collect();
    assert!(
        offenders.is_empty(),
        "write through lightproof::io::write_atomic instead:\n{}",
        offenders.join("\n")
    );
    // io.rs holds the writers the rest must use: the finder sees them there.
    assert!(!in_place_writers(&std::fs::read_to_string(&io).unwrap()).is_empty());
}

/// README.md's "Architecture" table and the crate doc's module table (`src/lib.rs`) name
/// every top-level module of `src/`, and every `src/` path README's table names exists:
/// the README table lacked `io`, `error`, `suites` and `render`, the crate doc `export`
/// and `judge`.
#[test]
fn the_readme_and_crate_doc_module_maps_name_every_module() {
    let modules = top_modules();
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let section = readme
        .split("\n## Architecture\n")
        .nth(1)
        .and_then(|s| s.split("\n## ").next())
        .expect("README.md has an Architecture section");
    let mut named = BTreeSet::new();
    for line in section.lines().filter(|l| l.starts_with("| `")) {
        let first = line.split('|').nth(1).unwrap_or("");
        for path in first.split('`').skip(1).step_by(2) {
            if let Some(rest) = path.strip_prefix("src/") {
                assert!(
                    root().join(path).exists(),
                    "README.md's Architecture table names {path}, which does not exist"
                );
                let m = rest.trim_end_matches('/').trim_end_matches(".rs");
                named.insert(m.to_string());
            }
        }
    }
    let missing: Vec<_> = modules.difference(&named).collect();
    assert!(
        missing.is_empty(),
        "README.md's Architecture table does not name src/ modules {missing:?}"
    );
    let lib = std::fs::read_to_string(root().join("src/lib.rs")).unwrap();
    let in_doc: BTreeSet<String> = lib
        .lines()
        .filter_map(|l| l.strip_prefix("//! | [`"))
        .filter_map(|l| l.split('`').next())
        .map(str::to_string)
        .collect();
    let missing: Vec<_> = modules.difference(&in_doc).collect();
    assert!(
        missing.is_empty(),
        "src/lib.rs's module table does not name {missing:?}"
    );
    // Nor a module that does not exist.
    let stale: Vec<_> = in_doc.difference(&modules).collect();
    assert!(
        stale.is_empty(),
        "src/lib.rs's module table names {stale:?}, not modules of src/"
    );
}
