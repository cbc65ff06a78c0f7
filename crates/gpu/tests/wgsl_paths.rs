//! The Rust twin of each WGSL module is named in its comments (`crates/cpu/src/light.rs`, …):
//! every such path names a file that exists, so a moved or renamed twin is caught here rather
//! than by a reader who follows a stale header.

use std::path::{Path, PathBuf};

/// The repository's root.
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The `crates/…` paths named in backticks in `wgsl`'s comments, with `{a,b}` expanded.
fn named_paths(wgsl: &str) -> Vec<String> {
    let mut out = Vec::new();
    for line in wgsl.lines() {
        let Some((_, comment)) = line.split_once("//") else {
            continue;
        };
        for (i, quoted) in comment.split('`').enumerate() {
            if i % 2 == 1 && quoted.starts_with("crates/") {
                out.extend(expand(quoted));
            }
        }
    }
    out
}

/// `a/{b,c}.rs` as `a/b.rs` and `a/c.rs`.
fn expand(path: &str) -> Vec<String> {
    match (path.find('{'), path.find('}')) {
        (Some(open), Some(close)) if open < close => path[open + 1..close]
            .split(',')
            .flat_map(|alt| {
                expand(&format!(
                    "{}{}{}",
                    &path[..open],
                    alt.trim(),
                    &path[close + 1..]
                ))
            })
            .collect(),
        _ => vec![path.to_string()],
    }
}

/// The paths `wgsl` names that do not exist under `root`.
fn missing(root: &Path, wgsl: &str) -> Vec<String> {
    named_paths(wgsl)
        .into_iter()
        .filter(|p| !root.join(p).exists())
        .collect()
}

#[test]
fn every_path_a_wgsl_module_names_exists() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let mut named = 0;
    let mut stale = Vec::new();
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "wgsl"))
        .collect();
    files.sort();
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap();
        named += named_paths(&text).len();
        for path in missing(&root(), &text) {
            stale.push(format!("{}: `{path}`", file.display()));
        }
    }
    // The headers do name their twins (else an empty list would pass).
    assert!(named >= 20, "only {named} paths named");
    assert!(
        stale.is_empty(),
        "paths that do not exist:\n{}",
        stale.join("\n")
    );
}

/// A planted stale path is reported, braces expand, and code outside comments is not read.
#[test]
fn a_planted_stale_path_is_reported() {
    let wgsl = "// Mirrors `crates/cpu/src/light.rs` and `crates/cpu/src/{bsdf,gone}.rs`.\n\
                let x = `crates/not/a/comment.rs`;\n";
    assert_eq!(
        named_paths(wgsl),
        [
            "crates/cpu/src/light.rs",
            "crates/cpu/src/bsdf.rs",
            "crates/cpu/src/gone.rs"
        ]
    );
    assert_eq!(missing(&root(), wgsl), ["crates/cpu/src/gone.rs"]);
}
