//! Any bytes as a scene file: the loader loads them or returns an error naming the file; it
//! never panics (a panic is a crash libFuzzer reports). Seed corpus: `scenes/` and
//! `scenes/hard/` (`cargo +nightly fuzz run scene corpus/scene ../scenes ../scenes/hard`; libFuzzer
//! writes what it finds into the first folder); meshes a scene names resolve against `scenes/`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/fuzzed.toml"));
    if let Err(e) = stratapt_import::load::load_str(&text, path) {
        assert!(e.to_string().starts_with(&path.display().to_string()), "{e}");
    }
});
