//! Any bytes as the PLY file of a mesh shape: the scene loads or fails naming the scene and the
//! mesh; ply-rs-bw panics are caught by the loader and reported as a malformed file, any other
//! panic (or an allocation past libFuzzer's limit) is a crash. Seed corpus: PLY files, e.g. the
//! `bumpy.ply` that `python3 ../scripts/make-mesh-scene.py 200 /tmp/seed --ply` writes
//! (`cargo +nightly fuzz run ply corpus/ply /tmp/seed`).
#![no_main]

mod mesh_file;

use libfuzzer_sys::fuzz_target;
use std::path::PathBuf;
use std::sync::OnceLock;

/// A folder with the scene: a mesh shape reading `m.ply` in one material.
fn folder() -> &'static PathBuf {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        mesh_file::folder(
            "ply",
            "[camera]\neye = [0, 0, -5]\nlook_at = [0, 0, 0]\nfov = 40\n\
             [materials.clay]\ntype = \"diffuse\"\nalbedo = 0.5\n\
             [[shapes]]\ntype = \"mesh\"\nfile = \"m.ply\"\nmaterial = \"clay\"\n",
        )
    })
}

fuzz_target!(|data: &[u8]| mesh_file::check(folder(), "m.ply", "ply-rs", data));
