//! In every crate of the workspace (`crates/*/src`) and the facade (`src`), the modules depend on
//! each other one way: no module reaches, through `crate::` paths, a module that reaches it back.
//! Read from the sources (a module is its file and its folder of submodules, at any depth);
//! comments are ignored. The WGSL modules' own graph is checked in
//! `crates/gpu/tests/specialize.rs` (`module_needs_are_one_way`).

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

type Graph = BTreeMap<String, BTreeSet<String>>;

/// The code of `source` without its comments (line comments, which include doc comments).
fn code(source: &str) -> String {
    source
        .lines()
        .map(|l| l.split("//").next().unwrap_or_default())
        .collect::<Vec<_>>()
        .join("\n")
}

/// The identifiers `source` reaches through `crate::`: `crate::a::b` gives `a`, and
/// `use crate::{a::b, c}` gives `a` and `c`.
fn crate_paths(source: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let code = code(source);
    let ident = |s: &str| -> String {
        s.chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect()
    };
    for (i, _) in code.match_indices("crate::") {
        let rest = &code[i + "crate::".len()..];
        if let Some(group) = rest.strip_prefix('{') {
            let group = &group[..group.find('}').unwrap_or(group.len())];
            out.extend(group.split(',').map(|p| ident(p.trim())));
        } else {
            out.insert(ident(rest));
        }
    }
    out.retain(|s| !s.is_empty());
    out
}

/// Which module each name the crate root re-exports comes from (`pub use module::{A, B}`).
fn reexports(lib: &str) -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    let code = code(lib).replace('\n', " ");
    for stmt in code.split(';') {
        let Some(path) = stmt.trim().strip_prefix("pub use ") else {
            continue;
        };
        let Some((module, names)) = path.split_once("::") else {
            continue;
        };
        let names = names.trim_matches(|c: char| c == '{' || c == '}' || c.is_whitespace());
        for name in names.split(',') {
            out.insert(name.trim().to_string(), module.trim().to_string());
        }
    }
    out
}

/// The crate's module graph: each top-level module (its file and its folder of submodules) and
/// the modules its code reaches.
fn graph(src: &Path) -> Graph {
    // The crate root: a library's `lib.rs`, else a binary's `main.rs`.
    let root = ["lib", "main"]
        .into_iter()
        .find(|r| src.join(format!("{r}.rs")).is_file())
        .expect("a crate root");
    let lib = std::fs::read_to_string(src.join(format!("{root}.rs"))).unwrap();
    let exported = reexports(&lib);
    let mut sources: BTreeMap<String, String> = BTreeMap::new();
    for entry in std::fs::read_dir(src).unwrap() {
        let path = entry.unwrap().path();
        let stem = path.file_stem().unwrap().to_string_lossy().to_string();
        let text = read_all(&path);
        if stem != root {
            sources.entry(stem).or_default().push_str(&text);
        }
    }
    let modules: BTreeSet<String> = sources.keys().cloned().collect();
    sources
        .iter()
        .map(|(module, text)| {
            let reached = crate_paths(text)
                .into_iter()
                .filter_map(|name| match modules.contains(&name) {
                    true => Some(name),
                    false => exported.get(&name).cloned(),
                })
                .filter(|m| m != module)
                .collect();
            (module.clone(), reached)
        })
        .collect()
}

/// The text of the file at `path`, or of every `.rs` file under the folder at `path`.
fn read_all(path: &Path) -> String {
    if !path.is_dir() {
        return std::fs::read_to_string(path).unwrap();
    }
    let mut entries: Vec<_> = std::fs::read_dir(path)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_dir() || p.extension().is_some_and(|e| e == "rs"))
        .collect();
    entries.sort();
    entries.iter().map(|p| read_all(p)).collect()
}

/// The `src` folders of the workspace's crates and of the facade, by crate folder.
fn crate_sources() -> Vec<(String, std::path::PathBuf)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut out = vec![("stratapt".to_string(), root.join("src"))];
    let mut crates: Vec<_> = std::fs::read_dir(root.join("crates"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.join("src").is_dir())
        .collect();
    crates.sort();
    for c in crates {
        let name = c.file_name().unwrap().to_string_lossy().into_owned();
        out.push((name, c.join("src")));
    }
    out
}

/// A cycle of `graph`, if it has one.
fn cycle(graph: &Graph) -> Option<Vec<String>> {
    fn visit(
        graph: &Graph,
        node: &str,
        path: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(at) = path.iter().position(|n| n == node) {
            let mut found = path[at..].to_vec();
            found.push(node.to_string());
            return Some(found);
        }
        if done.contains(node) {
            return None;
        }
        path.push(node.to_string());
        for next in graph.get(node).into_iter().flatten() {
            if let Some(found) = visit(graph, next, path, done) {
                return Some(found);
            }
        }
        path.pop();
        done.insert(node.to_string());
        None
    }
    let mut done = BTreeSet::new();
    graph
        .keys()
        .find_map(|node| visit(graph, node, &mut Vec::new(), &mut done))
}

#[test]
fn no_crates_modules_form_a_cycle() {
    let mut cycles = Vec::new();
    let mut graphs = BTreeMap::new();
    for (name, src) in crate_sources() {
        let graph = graph(&src);
        for (module, reached) in &graph {
            println!("{name}: {module} -> {reached:?}");
        }
        if let Some(found) = cycle(&graph) {
            cycles.push(format!("{name}: {}", found.join(" -> ")));
        }
        graphs.insert(name, graph);
    }
    // The parse sees the edges that are there (else an empty graph would pass).
    let gpu = &graphs["gpu"];
    assert!(gpu["renderer"].contains("upload"), "{gpu:?}");
    assert!(gpu["upload"].contains("shared"), "{gpu:?}");
    assert!(
        gpu["shared"].is_empty(),
        "gpu's shared must stay a leaf: {gpu:?}"
    );
    assert!(
        graphs["import"]["pbrt"].contains("desc"),
        "{:?}",
        graphs["import"]
    );
    assert!(graphs.len() >= 8, "{:?}", graphs.keys());
    assert!(cycles.is_empty(), "module cycles:\n{}", cycles.join("\n"));
}

/// The cycle check finds a planted cycle, and reads `crate::` paths and groups.
#[test]
fn a_planted_cycle_is_found() {
    let mut graph = Graph::new();
    let edge = |g: &mut Graph, a: &str, b: &str| {
        g.entry(a.into()).or_default().insert(b.into());
    };
    edge(&mut graph, "params", "specialize");
    edge(&mut graph, "specialize", "shader");
    edge(&mut graph, "shader", "shared");
    assert_eq!(cycle(&graph), None);
    edge(&mut graph, "shader", "params");
    let found = cycle(&graph).expect("the planted cycle");
    assert_eq!(found.first(), found.last());
    assert_eq!(found.len(), 4, "{found:?}");
    let paths = crate_paths("use crate::{a::B, c};\nlet x = crate::d::e(); // crate::f\n");
    assert_eq!(paths, ["a", "c", "d"].map(String::from).into());
}
