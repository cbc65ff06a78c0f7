//! Any bytes as the OBJ file of a mesh shape (with the bundled MTL next to it): the scene loads
//! or fails naming the scene and the mesh; tobj panics are caught by the loader and reported as
//! a malformed file, any other panic is a crash. Seed corpus: the bundled meshes
//! (`cargo +nightly fuzz run mesh ../scenes/meshes ../scenes/hard/meshes`).
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::PathBuf;
use std::sync::OnceLock;

/// A folder with the scene (a mesh shape reading `m.obj`) and the bundled MTL.
fn folder() -> &'static PathBuf {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = std::env::temp_dir().join(format!("strata-fuzz-mesh-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mtl = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/meshes/mesh.mtl");
        std::fs::copy(mtl, dir.join("mesh.mtl")).unwrap();
        std::fs::write(
            dir.join("scene.toml"),
            "[camera]\neye = [0, 0, -5]\nlook_at = [0, 0, 0]\nfov = 40\n\
             [[shapes]]\ntype = \"mesh\"\nfile = \"m.obj\"\n",
        )
        .unwrap();
        dir
    })
}

fuzz_target!(|data: &[u8]| {
    // tobj's own panics are caught by the loader; keep their messages out of the log.
    static QUIET: OnceLock<()> = OnceLock::new();
    QUIET.get_or_init(|| {
        let default = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !info.location().is_some_and(|l| l.file().contains("tobj")) {
                default(info);
            }
        }));
    });
    let dir = folder();
    std::fs::write(dir.join("m.obj"), data).unwrap();
    let scene = dir.join("scene.toml");
    if let Err(e) = stratapt_scene::load::load(&scene) {
        let message = e.to_string();
        assert!(message.starts_with(&scene.display().to_string()), "{message}");
        assert!(message.contains("m.obj"), "{message}");
    }
});
