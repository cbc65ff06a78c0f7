//! Any bytes as the OBJ file of a mesh shape (with the bundled MTL next to it): the scene loads
//! or fails naming the scene and the mesh; tobj panics are caught by the loader and reported as
//! a malformed file, any other panic is a crash. Seed corpus: the bundled meshes
//! (`cargo +nightly fuzz run mesh corpus/mesh ../scenes/meshes ../scenes/hard/meshes`; libFuzzer
//! writes what it finds into the first folder, so that one is not a folder of the repository).
#![no_main]

mod mesh_file;

use libfuzzer_sys::fuzz_target;
use std::path::PathBuf;
use std::sync::OnceLock;

/// A folder with the scene (a mesh shape reading `m.obj`) and the bundled MTL.
fn folder() -> &'static PathBuf {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = mesh_file::folder(
            "mesh",
            "[camera]\neye = [0, 0, -5]\nlook_at = [0, 0, 0]\nfov = 40\n\
             [[shapes]]\ntype = \"mesh\"\nfile = \"m.obj\"\n",
        );
        let mtl = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/meshes/mesh.mtl");
        std::fs::copy(mtl, dir.join("mesh.mtl")).unwrap();
        dir
    })
}

fuzz_target!(|data: &[u8]| mesh_file::check(folder(), "m.obj", "tobj", data));
