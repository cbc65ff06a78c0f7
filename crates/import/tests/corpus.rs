//! No input can crash the scene loader: a bounded, seeded mutation corpus (the in-`cargo test`
//! counterpart of the cargo-fuzz targets in `fuzz/`). Every scene of `scenes/` and
//! `scenes/hard/` is mutated byte by byte (bit flips, deletions, insertions of TOML tokens,
//! duplicated and swapped lines, truncation) and structurally (keys deleted, values replaced by
//! values of other types and extreme numbers, unknown keys added, array entries duplicated), and
//! the meshes' OBJ files line by line (index 0, negative and huge indices, faces of one or two
//! vertices, NaN and huge coordinates, random bytes), and a binary and an ASCII PLY byte by byte
//! (random, flipped and deleted bytes, truncation). Each input must load or fail with an error
//! that names the file; none may panic. (The loader reads; nothing is written.)

// The PLY writers of `ply.rs`; this file takes only the seeds from them.
#[allow(dead_code)]
#[path = "ply/write.rs"]
mod write;

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use stratapt_import::load::{load_str, scene_files};
use stratapt_import::scene_file::load;
use stratapt_sampling::testing::TestRng;

/// Inputs per kind (a few seconds in all in the test profile).
const TOML_BYTE_MUTATIONS: usize = 10_000;
const TOML_STRUCTURE_MUTATIONS: usize = 10_000;
const OBJ_MUTATIONS: usize = 2000;
const PLY_MUTATIONS: usize = 600;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Every bundled scene: path and text.
fn seeds() -> Vec<(PathBuf, String)> {
    let mut out = Vec::new();
    for dir in ["scenes", "scenes/hard", "scenes/mitsuba"] {
        for path in scene_files(&root().join(dir)).unwrap() {
            let text = std::fs::read_to_string(&path).unwrap();
            out.push((path, text));
        }
    }
    assert!(out.len() >= 30, "{} seed scenes", out.len());
    out
}

/// Tokens that make TOML (and the loader's checks) interesting.
const TOKENS: &[&str] = &[
    "[",
    "]",
    "[[",
    "]]",
    "=",
    "\"",
    "'",
    "\n",
    ",",
    "{",
    "}",
    "#",
    ".",
    "-",
    "+",
    "nan",
    "inf",
    "-inf",
    "1e39",
    "-1e39",
    "1e-45",
    "0",
    "-0",
    "-1",
    "4294967296",
    "99999999999999999999",
    "true",
    "\"\"",
    "[]",
    "{}",
    "type",
    "material",
    "shapes",
    "lights",
    "camera",
    "film",
    "render",
    "sky",
    "close",
    "mesh",
    "file",
    "\"../\"",
    "\u{0}",
    "\u{feff}",
    "é",
];

/// One random byte-level change of `text`.
fn mutate_bytes(text: &str, rng: &mut TestRng) -> String {
    let mut bytes = text.as_bytes().to_vec();
    let len = bytes.len().max(1);
    match rng.below(7) {
        0 => {
            let i = rng.below(len).min(bytes.len().saturating_sub(1));
            if let Some(b) = bytes.get_mut(i) {
                *b ^= 1 << rng.below(8);
            }
        }
        1 => {
            let i = rng.below(len);
            let j = (i + 1 + rng.below(16)).min(bytes.len());
            if i < j {
                bytes.drain(i..j);
            }
        }
        2 => {
            let i = rng.below(len).min(bytes.len());
            let token = rng.pick(TOKENS).as_bytes().to_vec();
            bytes.splice(i..i, token);
        }
        3 => bytes.truncate(rng.below(len)),
        _ => {
            // Line-level: duplicate, delete or swap lines.
            let text = String::from_utf8_lossy(&bytes).into_owned();
            let mut lines: Vec<&str> = text.lines().collect();
            if lines.is_empty() {
                return text;
            }
            let (i, j) = (rng.below(lines.len()), rng.below(lines.len()));
            match rng.below(3) {
                0 => lines.insert(j, lines[i]),
                1 => {
                    lines.remove(i);
                }
                _ => lines.swap(i, j),
            }
            return lines.join("\n");
        }
    }
    String::from_utf8_lossy(&bytes).into_owned()
}

/// A value of a random type, often an extreme or degenerate one.
fn random_value(rng: &mut TestRng) -> toml::Value {
    use toml::Value;
    match rng.below(14) {
        0 => Value::Integer(0),
        1 => Value::Integer(-1),
        2 => Value::Integer(i64::MAX),
        3 => Value::Float(f64::NAN),
        4 => Value::Float(f64::INFINITY),
        5 => Value::Float(1e39),
        6 => Value::Float(1e-45),
        7 => Value::Float(-0.0),
        8 => Value::String(String::new()),
        9 => Value::String("nonexistent".into()),
        10 => Value::Boolean(true),
        11 => Value::Array(Vec::new()),
        12 => Value::Array(vec![Value::Float(0.0); rng.below(5)]),
        _ => Value::Table(Default::default()),
    }
}

/// One random structural change of the parsed scene (none when it does not parse).
fn mutate_structure(text: &str, rng: &mut TestRng) -> Option<String> {
    let mut doc: toml::Table = text.parse().ok()?;
    // A random table (the root, a top-level table, or an array-of-tables entry).
    let keys: Vec<String> = doc.keys().cloned().collect();
    let table: &mut toml::Table = match rng.below(3) {
        0 => &mut doc,
        _ => {
            let key = rng.pick(&keys).clone();
            match doc.get_mut(&key) {
                Some(toml::Value::Table(t)) => {
                    // Maybe one level further (materials.NAME, camera.close).
                    let inner: Vec<String> = t
                        .iter()
                        .filter(|(_, v)| v.is_table())
                        .map(|(k, _)| k.clone())
                        .collect();
                    if !inner.is_empty() && rng.below(2) == 0 {
                        let k = rng.pick(&inner).clone();
                        t.get_mut(&k)?.as_table_mut()?
                    } else {
                        t
                    }
                }
                Some(toml::Value::Array(a)) if !a.is_empty() => {
                    let i = rng.below(a.len());
                    if rng.below(4) == 0 {
                        let copy = a[i].clone();
                        a.push(copy);
                    }
                    a.get_mut(i)?.as_table_mut()?
                }
                _ => &mut doc,
            }
        }
    };
    let names: Vec<String> = table.keys().cloned().collect();
    match rng.below(4) {
        0 if !names.is_empty() => {
            table.remove(rng.pick(&names).as_str());
        }
        1 => {
            table.insert(format!("unknown{}", rng.below(10)), random_value(rng));
        }
        _ if !names.is_empty() => {
            let key = rng.pick(&names).clone();
            let value = random_value(rng);
            table.insert(key, value);
        }
        _ => {}
    }
    toml::to_string(&doc).ok()
}

/// One random line-level change of an OBJ file.
fn mutate_obj(text: &str, rng: &mut TestRng) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let i = rng.below(lines.len());
    let replacement = match rng.below(12) {
        0 => "f 0 1 2".to_string(),
        1 => "f -1 -2 -3".to_string(),
        2 => "f 1 2 99999999".to_string(),
        3 => "f 1".to_string(),
        4 => "f 1 2".to_string(),
        5 => "v nan 0 0".to_string(),
        6 => "v 1e39 0 0".to_string(),
        7 => "vn 0 0 0".to_string(),
        8 => "f 1//1 2//2 3//99".to_string(),
        9 => "usemtl nonexistent".to_string(),
        10 => "mtllib nonexistent.mtl".to_string(),
        _ => mutate_bytes(&lines[i], rng),
    };
    match rng.below(3) {
        0 => lines.insert(i, replacement),
        _ => lines[i] = replacement,
    }
    lines.join("\n") + "\n"
}

/// Load `text` as `path`: must not panic, and an error must name `path`. Returns whether it
/// loaded.
fn check_one(text: &str, path: &Path, what: &str) -> bool {
    let result = catch_unwind(AssertUnwindSafe(|| load_str(text, path)));
    match result {
        Err(_) => panic!("{what}: the loader panicked on\n{text}"),
        Ok(Ok(_)) => true,
        Ok(Err(e)) => {
            let message = e.to_string();
            assert!(
                message.starts_with(&path.display().to_string()),
                "{what}: the error does not name the file: {message}"
            );
            false
        }
    }
}

#[test]
fn mutated_scenes_load_or_fail_with_the_file_named_never_panic() {
    let seeds = seeds();
    let mut rng = TestRng(2026);
    let (mut loaded, mut total) = (0, 0);
    for k in 0..TOML_BYTE_MUTATIONS {
        let (path, text) = rng.pick(&seeds);
        let mut mutated = text.clone();
        for _ in 0..1 + rng.below(3) {
            mutated = mutate_bytes(&mutated, &mut rng);
        }
        loaded += check_one(&mutated, path, &format!("byte mutation {k}")) as usize;
        total += 1;
    }
    let bytes_loaded = loaded;
    for k in 0..TOML_STRUCTURE_MUTATIONS {
        let (path, text) = rng.pick(&seeds);
        let Some(mutated) = mutate_structure(text, &mut rng) else {
            continue;
        };
        loaded += check_one(&mutated, path, &format!("structure mutation {k}")) as usize;
        total += 1;
    }
    println!(
        "{total} mutated scenes: {loaded} loaded ({bytes_loaded} of {TOML_BYTE_MUTATIONS} byte \
         mutations), the rest refused with the file named, none panicked"
    );
    // The corpus reaches both sides of the checks.
    assert!(
        loaded > total / 20 && loaded < total * 19 / 20,
        "{loaded} of {total} loaded"
    );
}

#[test]
fn mutated_meshes_load_or_fail_with_the_file_named_never_panic() {
    let dir = tempfile::tempdir().unwrap();
    let meshes = [
        root().join("scenes/meshes/mesh.obj"),
        root().join("scenes/hard/meshes/degenerate-box.obj"),
    ];
    std::fs::copy(
        root().join("scenes/meshes/mesh.mtl"),
        dir.path().join("mesh.mtl"),
    )
    .unwrap();
    let mut rng = TestRng(7);
    let (mut loaded, mut total) = (0, 0);
    for k in 0..OBJ_MUTATIONS {
        let source = rng.pick(&meshes);
        let mut obj = std::fs::read_to_string(source).unwrap();
        for _ in 0..1 + rng.below(3) {
            obj = mutate_obj(&obj, &mut rng);
        }
        std::fs::write(dir.path().join("m.obj"), &obj).unwrap();
        // With the MTL's materials, or one material for every face.
        let material = if rng.below(2) == 0 {
            "material = \"white\"\n"
        } else {
            ""
        };
        let text = format!(
            "[camera]\neye = [0, 0, -5]\nlook_at = [0, 0, 0]\nfov = 40\n\
             [materials.white]\ntype = \"diffuse\"\nalbedo = 0.5\n\
             [[shapes]]\ntype = \"mesh\"\nfile = \"m.obj\"\n{material}"
        );
        let path = dir.path().join("scene.toml");
        std::fs::write(&path, &text).unwrap();
        loaded += mesh_loads(&path, "m.obj", &format!("OBJ mutation {k}"), &obj) as usize;
        total += 1;
    }
    println!("{total} mutated meshes: {loaded} loaded, the rest refused naming the files");
    assert!(
        loaded > total / 20 && loaded < total * 19 / 20,
        "{loaded} of {total} loaded"
    );
}

/// Load the scene at `path`, whose mesh file is `mesh`: it must not panic (`input`, the mesh's
/// text, is shown if it does), and an error must name the scene and the mesh. Whether it loaded.
fn mesh_loads(path: &Path, mesh: &str, what: &str, input: &str) -> bool {
    match catch_unwind(AssertUnwindSafe(|| load(path))) {
        Err(_) => panic!("{what}: the loader panicked on\n{input}"),
        Ok(Ok(_)) => true,
        Ok(Err(e)) => {
            let message = e.to_string();
            assert!(
                message.starts_with(&path.display().to_string())
                    && message.contains(&format!("mesh `{mesh}`")),
                "{what}: the error does not name the files: {message}"
            );
            false
        }
    }
}

#[test]
fn mutated_ply_files_load_or_fail_with_the_files_named_never_panic() {
    let dir = tempfile::tempdir().unwrap();
    let seeds = [
        write::ply(&write::mesh(), write::Form::LITTLE),
        write::ply(&write::mesh(), write::Form::ASCII),
    ];
    let mut rng = TestRng(2026);
    let (mut loaded, mut total) = (0, 0);
    for k in 0..PLY_MUTATIONS {
        let mut bytes = seeds[k % 2].clone();
        for _ in 0..1 + rng.below(3) {
            let i = rng.below(bytes.len());
            match rng.below(4) {
                0 => bytes[i] = rng.below(256) as u8,
                1 => bytes[i] ^= 1 << rng.below(8),
                2 => {
                    bytes.remove(i);
                }
                _ => bytes.truncate(i),
            }
        }
        let path = write::scene_with(dir.path(), "m.ply", &bytes, true);
        let what = format!("PLY mutation {k}");
        loaded += mesh_loads(&path, "m.ply", &what, "(binary)") as usize;
        total += 1;
    }
    println!("{total} mutated PLY files: {loaded} loaded, the rest refused naming the files");
    assert!(
        loaded > total / 20 && loaded < total * 19 / 20,
        "{loaded} of {total} loaded"
    );
}
