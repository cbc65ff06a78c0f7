//! Figures the documentation states about the code agree with the code. One such figure is
//! checked: how many storage buffers the kernel binds. Every "N storage buffers" in `README.md`
//! and `docs/**/*.md` (N in digits or as a word up to twenty, the phrase possibly wrapped over
//! lines) must be the number of storage buffers the kernel declares in group 0 of
//! `shaders/*.wgsl`. The test also checks those declarations against the host's bind group
//! layout: the read-only ones are the scene arrays of `binding::SCENE_ARRAYS`
//! (`crates/gpu/src/shared.rs`) in binding order, and the one read-write buffer is the
//! accumulator, `accum`. `crates/gpu/tests/layout.rs` checks every binding number against the
//! host as well.
//!
//! Two phrasings count something else and are skipped. "as two storage buffers" is one array
//! split over two bindings. "allow(s) 8 storage buffers" and "of 8 storage buffers" state a
//! device's limit, such as WebGPU's default.
//!
//! Measured figures (times, speed-ups, the calibration factor) are not copied into the README;
//! it links to the one current table in `docs/measurements/the-two-commands.md` instead.
//!
//! Std only, so it also runs on its own:
//! `CARGO_MANIFEST_DIR=$PWD rustc --edition 2021 --test tests/docs_figures.rs -o /tmp/docs-figures && /tmp/docs-figures`.

use std::path::{Path, PathBuf};

#[path = "support/markdown.rs"]
mod markdown;
use markdown::documentation;

/// Numbers the documentation writes as words, from zero.
const NUMBER_WORDS: &str = "zero one two three four five six seven eight nine ten eleven twelve \
    thirteen fourteen fifteen sixteen seventeen eighteen nineteen twenty";

/// Words that, just before the number, mean it does not count the kernel's bindings.
const NOT_THE_KERNELS: [&str; 4] = ["as", "allow", "allows", "of"];

/// One storage buffer the kernel declares: its binding in group 0, its WGSL name, and whether
/// the kernel writes it.
#[derive(Debug, PartialEq)]
struct StorageBinding {
    binding: u32,
    name: String,
    read_write: bool,
}

/// A word with the punctuation and markup around it taken off, lowercased.
fn bare(word: &str) -> String {
    word.trim_matches(|c: char| !c.is_alphanumeric())
        .to_lowercase()
}

/// The number a word states, in digits or as a word.
fn number(word: &str) -> Option<u32> {
    let word = bare(word);
    word.parse().ok().or_else(|| {
        NUMBER_WORDS
            .split_whitespace()
            .position(|n| n == word)
            .map(|i| i as u32)
    })
}

/// Every `(line, N)` where `text` says "N storage buffers" of the kernel, numbered from 1.
fn stated_counts(text: &str) -> Vec<(usize, u32)> {
    let words: Vec<(usize, String)> = text
        .lines()
        .enumerate()
        .flat_map(|(i, line)| line.split_whitespace().map(move |w| (i + 1, w.to_string())))
        .collect();
    let mut counts = Vec::new();
    for (i, window) in words.windows(3).enumerate() {
        let [(line, first), (_, storage), (_, buffers)] = window else {
            continue;
        };
        let Some(n) = number(first) else { continue };
        if bare(storage) != "storage" || bare(buffers) != "buffers" {
            continue;
        }
        let before = i.checked_sub(1).map(|j| bare(&words[j].1));
        if before.is_some_and(|w| NOT_THE_KERNELS.contains(&w.as_str())) {
            continue;
        }
        counts.push((*line, n));
    }
    counts
}

/// The value of `@name(value)` in a WGSL declaration, if it has that attribute.
fn attribute(declaration: &str, name: &str) -> Option<u32> {
    let start = declaration.find(&format!("@{name}("))? + name.len() + 2;
    let end = start + declaration[start..].find(')')?;
    declaration[start..end].trim().parse().ok()
}

/// The storage buffers WGSL `source` declares in group 0, in the order it declares them.
fn wgsl_storage_bindings(source: &str) -> Vec<StorageBinding> {
    let mut out = Vec::new();
    for line in source.lines() {
        let code = line.split("//").next().unwrap_or("");
        let Some(at) = code.find("var<storage") else {
            continue;
        };
        if attribute(code, "group") != Some(0) {
            continue;
        }
        let binding = attribute(code, "binding")
            .unwrap_or_else(|| panic!("a storage buffer without a binding: {line}"));
        let access_end = at + code[at..].find('>').expect("`var<storage` without `>`");
        let read_write = code[at..access_end].contains("read_write");
        let name = code[access_end + 1..]
            .split(':')
            .next()
            .unwrap_or("")
            .trim()
            .to_string();
        out.push(StorageBinding {
            binding,
            name,
            read_write,
        });
    }
    out
}

/// The storage buffers of group 0 in every `.wgsl` file of `shaders/`, by binding.
fn kernel_storage_buffers(root: &Path) -> Vec<StorageBinding> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(root.join("shaders"))
        .expect("cannot read shaders/")
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.extension().is_some_and(|e| e == "wgsl"))
        .collect();
    files.sort();
    let mut all: Vec<StorageBinding> = files
        .iter()
        .flat_map(|file| wgsl_storage_bindings(&std::fs::read_to_string(file).unwrap()))
        .collect();
    all.sort_by_key(|b| b.binding);
    for pair in all.windows(2) {
        assert_ne!(
            pair[0].binding, pair[1].binding,
            "two storage buffers at one binding: {pair:?}"
        );
    }
    all
}

/// The WGSL names listed in the `SCENE_ARRAYS` table of Rust `source` (each entry
/// `("wgsl_name", "what it holds")`), or `None` when `source` has no such table.
fn scene_arrays(source: &str) -> Option<Vec<String>> {
    let start = source.find("SCENE_ARRAYS:")?;
    let body = &source[start..];
    let body = &body[body.find('=')?..body.find("];")?];
    Some(
        body.split("(\"")
            .skip(1)
            .filter_map(|entry| entry.split('"').next())
            .map(str::to_string)
            .collect(),
    )
}

/// Every `.rs` file under `folder`, sorted.
fn rust_files(folder: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut folders = vec![folder.to_path_buf()];
    while let Some(folder) = folders.pop() {
        for entry in std::fs::read_dir(&folder).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                folders.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

/// The host's scene arrays, which the bind group layout binds as read-only storage buffers.
fn host_scene_arrays(root: &Path) -> Vec<String> {
    let found: Vec<Vec<String>> = rust_files(&root.join("crates/gpu/src"))
        .iter()
        .filter_map(|file| scene_arrays(&std::fs::read_to_string(file).unwrap()))
        .collect();
    match found.as_slice() {
        [arrays] => arrays.clone(),
        _ => panic!(
            "expected one `SCENE_ARRAYS` table in crates/gpu/src, found {}; if the host's list \
             of scene arrays moved or was renamed, update `host_scene_arrays` here",
            found.len()
        ),
    }
}

/// Every "N storage buffers" in `text` (of the file `file`) whose N is not `count`.
fn wrong_counts(file: &Path, text: &str, count: u32) -> Vec<String> {
    stated_counts(text)
        .into_iter()
        .filter(|(_, n)| *n != count)
        .map(|(line, n)| {
            format!(
                "{}:{line}: says {n} storage buffers, the kernel binds {count}",
                file.display()
            )
        })
        .collect()
}

#[test]
fn every_stated_storage_buffer_count_is_the_kernels() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let kernel = kernel_storage_buffers(root);
    let read_only: Vec<&str> = kernel
        .iter()
        .filter(|b| !b.read_write)
        .map(|b| b.name.as_str())
        .collect();
    let read_write: Vec<&str> = kernel
        .iter()
        .filter(|b| b.read_write)
        .map(|b| b.name.as_str())
        .collect();
    assert_eq!(
        read_only,
        host_scene_arrays(root),
        "the kernel's read-only storage buffers are not the host's scene arrays"
    );
    assert_eq!(
        read_write,
        ["accum"],
        "the kernel's read-write storage buffers"
    );
    let count = kernel.len() as u32;
    assert!(count > 0, "found no storage buffers in shaders/*.wgsl");

    let mut statements = 0;
    let mut wrong = Vec::new();
    for file in documentation(root) {
        let text = std::fs::read_to_string(root.join(&file)).unwrap();
        statements += stated_counts(&text).len();
        wrong.extend(wrong_counts(&file, &text, count));
    }
    assert!(
        statements > 0,
        "no page states how many storage buffers the kernel binds: this test checks nothing"
    );
    assert!(
        wrong.is_empty(),
        "{} wrong storage-buffer counts:\n{}",
        wrong.len(),
        wrong.join("\n")
    );
}

#[test]
fn a_planted_wrong_count_is_caught() {
    let text = "\
The kernel binds 3 storage
buffers (wrapped), and the library asks for **fourteen** storage buffers.
The tables: the GPU binds them as two storage buffers. WebGPU's defaults
allow 8 storage buffers per stage; a limit of 8 storage buffers. The storage-buffer limit,
4.355e3 read from storage buffers, and 14 storage buffers.
";
    assert_eq!(stated_counts(text), [(1, 3), (2, 14), (5, 14)]);
    assert_eq!(
        wrong_counts(Path::new("README.md"), text, 14),
        ["README.md:1: says 3 storage buffers, the kernel binds 14"]
    );
    assert!(wrong_counts(Path::new("README.md"), text, 3).len() == 2);
}

#[test]
fn the_counter_reads_group_0_declarations_only() {
    let source = "\
@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> prims: array<vec4u>;
// @group(0) @binding(2) var<storage, read> commented_out: array<u32>;
@group(0) @binding(3) var<storage, read_write> accum: array<vec4f>; // the accumulator
@group(1) @binding(0) var<storage, read> probe_in: array<u32>;
";
    let found = wgsl_storage_bindings(source);
    let summary: Vec<(u32, &str, bool)> = found
        .iter()
        .map(|b| (b.binding, b.name.as_str(), b.read_write))
        .collect();
    assert_eq!(summary, [(1, "prims", false), (3, "accum", true)]);

    let rust = "\
pub const SCENE_ARRAYS: [(&str, &str); 2] = [
    (\"prims\", \"primitives\"),
    (\"nodes\", \"BVH nodes\"),
];
";
    assert_eq!(
        scene_arrays(rust),
        Some(vec!["prims".into(), "nodes".into()])
    );
    assert_eq!(scene_arrays("const OTHER: [u32; 0] = [];"), None);
}
