//! pbrt-v4 scene files: the tokens ([`lexer`]), the directives with their typed parameters
//! ([`parse`]), a scene's files read with their `Include`s and `Import`s spliced in
//! ([`include`](mod@include)), the transformation state the directives change ([`state`]), the
//! perspective camera with its handedness ([`camera`]), the film, sampler, integrator and filter
//! as strata's settings ([`settings`]), parameters read by name and type so that every one left
//! unread is a warning ([`params`]), spectra as RGB ([`spectrum`], [`named`]), and the whole
//! scene as strata's description and meshes ([`import`]: shapes, [`materials`], [`textures`],
//! [`lights`]), each value spanned by the file, line and column it was read from. The design:
//! `docs/design/pbrt-import.md`.

pub mod camera;
pub mod import;
pub mod include;
pub mod lexer;
pub mod lights;
pub mod materials;
pub mod named;
pub mod params;
pub mod parse;
pub mod settings;
mod shapes;
pub mod spectrum;
pub mod state;
pub mod textures;

use std::path::Path;

/// Whether `path` names a pbrt-v4 scene file (`.pbrt`, or `.pbrt.gz`; any case).
pub fn is_pbrt(path: &Path) -> bool {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    name.ends_with(".pbrt") || name.ends_with(".pbrt.gz")
}

/// The folder an imported scene's meshes are named under: `NAME-meshes` for `NAME.pbrt`
/// (where `strata convert` writes them, beside the TOML file).
pub fn mesh_dir(path: &Path) -> String {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    // The extensions, in any case, as `is_pbrt` reads them.
    let mut stem = name.as_str();
    for ext in [".gz", ".pbrt", ".toml"] {
        if stem.to_ascii_lowercase().ends_with(ext) {
            stem = &stem[..stem.len() - ext.len()];
        }
    }
    format!("{stem}-meshes")
}
