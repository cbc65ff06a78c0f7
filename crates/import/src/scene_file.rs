//! A scene file of any format strata reads, to its [`Description`] and on to records: strata's
//! TOML ([`crate::load::parse`]) or pbrt-v4 (`.pbrt`, `.pbrt.gz`: [`crate::pbrt::import`]).
//! Either way validation ([`crate::load::build`]) names the line of the file the user wrote.

use crate::desc::Description;
use std::path::Path;
use stratapt_scene::{FlatScene, SceneError, SourceLocation};

/// Load, validate and flatten the scene file at `path`: strata's TOML, or a pbrt-v4 file
/// (whose warnings land in [`FlatScene::import`]).
pub fn load(path: &Path) -> Result<FlatScene, SceneError> {
    crate::load::build(describe(path)?)
}

/// The description of the scene file at `path`, not yet validated; a pbrt-v4 scene's meshes are
/// named under [`crate::pbrt::mesh_dir`] of `path`.
pub fn describe(path: &Path) -> Result<Description, SceneError> {
    if crate::pbrt::is_pbrt(path) {
        return crate::pbrt::import::import(path, &crate::pbrt::mesh_dir(path));
    }
    let text = std::fs::read_to_string(path).map_err(|e| {
        SceneError::new(
            SourceLocation::file(path),
            format!("cannot read scene file: {e}"),
        )
    })?;
    crate::load::parse(&text, path)
}
