//! Any bytes as a pbrt-v4 scene file: the importer reads them into a description and validation
//! makes a scene of it, or either returns an error naming a file of the scene; it never panics
//! (a panic is a crash libFuzzer reports) and never loops. Seed corpus: strata's pbrt-v4 twins of
//! its own scenes (`cargo +nightly fuzz run pbrt corpus/pbrt ../scenes/pbrt`); files a scene
//! names (`Include`, images, PLY meshes) resolve against `scenes/pbrt/`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::Path;
use stratapt_import::pbrt::{import::import_parsed, include::Parsed};

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/pbrt/fuzzed.pbrt"));
    let loaded = Parsed::from_text(&text, path)
        .and_then(|parsed| import_parsed(parsed, "fuzzed-meshes"))
        .and_then(stratapt_import::load::build);
    if let Err(e) = loaded {
        // Every error names the scene's folder (the file itself, or a file it names there).
        let folder = path.parent().unwrap().display().to_string();
        assert!(e.to_string().contains(&folder), "{e}");
    }
});
