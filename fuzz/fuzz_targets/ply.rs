//! Any bytes as the PLY file of a mesh shape: the scene loads or fails naming the scene and the
//! mesh; ply-rs-bw panics are caught by the loader and reported as a malformed file, any other
//! panic (or an allocation past libFuzzer's limit) is a crash. Seed corpus: PLY files, e.g. the
//! `bumpy.ply` that `python3 ../scripts/make-mesh-scene.py 200 /tmp/seed --ply` writes, copied
//! into `corpus/ply`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::PathBuf;
use std::sync::OnceLock;

/// A folder with the scene: a mesh shape reading `m.ply` in one material.
fn folder() -> &'static PathBuf {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = std::env::temp_dir().join(format!("strata-fuzz-ply-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(
            dir.join("scene.toml"),
            "[camera]\neye = [0, 0, -5]\nlook_at = [0, 0, 0]\nfov = 40\n\
             [materials.clay]\ntype = \"diffuse\"\nalbedo = 0.5\n\
             [[shapes]]\ntype = \"mesh\"\nfile = \"m.ply\"\nmaterial = \"clay\"\n",
        )
        .unwrap();
        dir
    })
}

fuzz_target!(|data: &[u8]| {
    // ply-rs-bw's own panics are caught by the loader; keep their messages out of the log.
    static QUIET: OnceLock<()> = OnceLock::new();
    QUIET.get_or_init(|| {
        let default = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !info.location().is_some_and(|l| l.file().contains("ply-rs")) {
                default(info);
            }
        }));
    });
    let dir = folder();
    std::fs::write(dir.join("m.ply"), data).unwrap();
    let scene = dir.join("scene.toml");
    if let Err(e) = stratapt_scene::load::load(&scene) {
        let message = e.to_string();
        assert!(message.starts_with(&scene.display().to_string()), "{message}");
        assert!(message.contains("m.ply"), "{message}");
    }
});
