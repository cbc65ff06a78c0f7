//! Scene files: TOML + OBJ/MTL, parsed, validated (file:line:column errors) and flattened.

use crate::{FlatScene, SceneError};
use std::path::Path;

/// Load, validate and flatten the scene file at `path`.
pub fn load(path: &Path) -> Result<FlatScene, SceneError> {
    unimplemented!("{}", path.display())
}

/// Load from TOML text; `path` names it in errors and anchors relative mesh paths.
pub fn load_str(text: &str, path: &Path) -> Result<FlatScene, SceneError> {
    unimplemented!("{} {}", text.len(), path.display())
}
