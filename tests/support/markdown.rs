//! The documentation's files, for the std-only documentation tests (`tests/docs.rs`,
//! `tests/docs_figures.rs`), which include this file with `#[path]` so that each still builds
//! alone with `rustc --test`.

use std::path::{Path, PathBuf};

/// `README.md` and every `.md` under `docs/`, relative to the repository root.
pub fn documentation(root: &Path) -> Vec<PathBuf> {
    let mut files = vec![PathBuf::from("README.md")];
    let mut folders = vec![PathBuf::from("docs")];
    while let Some(folder) = folders.pop() {
        let mut entries: Vec<_> = std::fs::read_dir(root.join(&folder))
            .unwrap_or_else(|e| panic!("cannot read {}: {e}", folder.display()))
            .map(|entry| entry.unwrap().file_name())
            .collect();
        entries.sort();
        for name in entries {
            let path = folder.join(&name);
            if root.join(&path).is_dir() {
                folders.push(path);
            } else if path.extension().is_some_and(|e| e == "md") {
                files.push(path);
            }
        }
    }
    files
}
