//! Loading the scene a command names: strata's TOML, or a pbrt-v4 file imported on the way,
//! whose warnings (what strata draws differently from what the file asks) are shown, or, with
//! `--strict`, refuse the scene.

use clap::Args;
use std::path::Path;
use stratapt_scene::report::Report;
use stratapt_scene::FlatScene;

/// How many of an import's warnings a command that renders shows (`strata info` lists all).
const SHOWN: usize = 12;

#[derive(Args, Clone, Copy, Debug, Default)]
pub struct ImportArgs {
    /// For a pbrt-v4 scene: refuse it when the import has a warning (anything strata would
    /// draw differently from what the file asks), listing them all.
    #[arg(long)]
    pub strict: bool,
}

/// The warnings of an import (a scene's [`FlatScene::import`], a description's), one per line
/// (`file:line:column: what was done instead`).
pub fn warning_lines(import: Option<&Report>) -> Vec<String> {
    import
        .into_iter()
        .flat_map(|r| &r.warnings)
        .map(|w| format!("{}: {}", w.at, w.message))
        .collect()
}

/// `--strict`: an error listing every warning, if there is any.
pub fn check_strict(path: &Path, lines: &[String], args: ImportArgs) -> anyhow::Result<()> {
    if args.strict && !lines.is_empty() {
        anyhow::bail!(
            "{}: --strict, and the import has {} warning{}:\n  {}",
            path.display(),
            lines.len(),
            if lines.len() == 1 { "" } else { "s" },
            lines.join("\n  ")
        );
    }
    Ok(())
}

/// Load `path`, showing the first few of an import's warnings on stderr (`show`), or refusing
/// the scene under `--strict`.
pub fn load(path: &Path, args: ImportArgs, show: bool) -> anyhow::Result<FlatScene> {
    let scene = stratapt_import::scene_file::load(path)?;
    let lines = warning_lines(scene.import.as_ref());
    check_strict(path, &lines, args)?;
    if show {
        show_warnings(&lines);
    }
    Ok(scene)
}

/// The first [`SHOWN`] warnings on stderr, and how many more there are.
pub fn show_warnings(lines: &[String]) {
    for line in lines.iter().take(SHOWN) {
        eprintln!("warning: {line}");
    }
    if lines.len() > SHOWN {
        eprintln!(
            "warning: … and {} more (`strata info` lists them all; `--strict` refuses them)",
            lines.len() - SHOWN
        );
    }
}
