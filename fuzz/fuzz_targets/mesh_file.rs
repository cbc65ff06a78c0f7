//! What the `mesh` (OBJ) and `ply` targets share: a folder holding a scene whose mesh shape
//! reads the fuzzed file, and the check that the scene loads or fails naming the scene and the
//! mesh. Panics of the mesh's parser are caught by the loader (reported as a malformed file);
//! any other panic is a crash.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// A new folder for this process (`strata-fuzz-NAME-PID` in the temporary folder) holding
/// `scene.toml` with `scene` as its text.
pub fn folder(name: &str, scene: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("strata-fuzz-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("scene.toml"), scene).unwrap();
    dir
}

/// Write `data` as the mesh `file` in `dir` and load `dir`'s scene: it loads, or its error names
/// the scene and the mesh. Panics from source files whose path contains `parser` (the mesh
/// parser's own, caught by the loader) are kept out of the log.
pub fn check(dir: &Path, file: &str, parser: &'static str, data: &[u8]) {
    static QUIET: OnceLock<()> = OnceLock::new();
    QUIET.get_or_init(|| {
        let default = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !info.location().is_some_and(|l| l.file().contains(parser)) {
                default(info);
            }
        }));
    });
    std::fs::write(dir.join(file), data).unwrap();
    let scene = dir.join("scene.toml");
    if let Err(e) = stratapt_import::scene_file::load(&scene) {
        let message = e.to_string();
        assert!(message.starts_with(&scene.display().to_string()), "{message}");
        assert!(message.contains(file), "{message}");
    }
}
