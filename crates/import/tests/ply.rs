//! PLY meshes: every encoding loads to the primitives its OBJ gives, and a malformed PLY is an
//! error naming the scene, the mesh and the reason (mutated PLY files: `corpus.rs`).

#[path = "ply/write.rs"]
mod write;

use stratapt_import::scene_file::load;
use stratapt_scene::{FlatScene, Prim};
use write::{edited, mesh, obj, ply, replaced, scene_with, Form};

/// The mesh as an OBJ with normals, loaded.
fn reference(dir: &tempfile::TempDir) -> FlatScene {
    load(&scene_with(dir.path(), "r.obj", &obj(&mesh(), true), true)).unwrap()
}

fn prims(scene: &FlatScene) -> Vec<Prim> {
    scene.geometry.iter().collect()
}

#[test]
fn every_ply_encoding_loads_the_primitives_its_obj_gives() {
    let dir = tempfile::tempdir().unwrap();
    let m = mesh();
    for normals in [true, false] {
        let reference = load(&scene_with(dir.path(), "m.obj", &obj(&m, normals), true))
            .unwrap_or_else(|e| panic!("{e}"));
        let expected = prims(&reference);
        let triangles: usize = m.faces.iter().map(|f| f.len() - 2).sum();
        assert_eq!(expected.len(), triangles);
        assert_eq!(
            expected.iter().all(|p| p.normals.is_some()),
            normals,
            "smooth exactly when the file has normals"
        );
        for encoding in ["ascii", "binary_little_endian", "binary_big_endian"] {
            for unusual in [false, true] {
                let form = Form {
                    encoding,
                    normals,
                    unusual,
                };
                let path = scene_with(dir.path(), "m.ply", &ply(&m, form), true);
                let scene = load(&path).unwrap_or_else(|e| panic!("{e}"));
                let what = format!("{encoding}, normals {normals}, unusual {unusual}");
                assert_eq!(prims(&scene), expected, "{what}");
                assert_eq!(scene.bvh.nodes.len(), reference.bvh.nodes.len(), "{what}");
            }
        }
    }
    // The extension decides, in any case.
    let path = scene_with(dir.path(), "M.PLY", &ply(&m, Form::LITTLE), true);
    assert_eq!(
        prims(&load(&path).unwrap()).len(),
        prims(&reference(&dir)).len()
    );
}

#[test]
fn unusual_but_valid_ply_files_load_the_same_primitives() {
    let dir = tempfile::tempdir().unwrap();
    let expected = prims(&reference(&dir));
    let mut files = Vec::new();
    // Corner lists of every integer type (the ASCII payload reads the same).
    for t in ["char", "uchar", "short", "ushort", "uint"] {
        let to = format!("uchar {t} vertex_indices");
        files.push((t, edited(Form::ASCII, "uchar int vertex_indices", &to)));
    }
    // A first line with trailing blanks, as ply-rs-bw's grammar allows.
    files.push(("magic", edited(Form::LITTLE, "ply\n", "ply \n")));
    // An element without properties: in binary it takes no bytes, however many the header says
    // (read one by one, 2^64 − 1 of them would never finish).
    let empty = format!("element nothing {}\nend_header", u64::MAX);
    files.push(("empty", edited(Form::LITTLE, "end_header", &empty)));
    for (what, bytes) in files {
        // On a thread, so that a loader that never finishes fails the test instead of hanging it.
        let path = scene_with(dir.path(), &format!("{what}.ply"), &bytes, true);
        let (send, receive) = std::sync::mpsc::channel();
        std::thread::spawn(move || send.send(load(&path).map(|s| prims(&s))));
        let loaded = receive
            .recv_timeout(std::time::Duration::from_secs(60))
            .unwrap_or_else(|_| panic!("{what}: still loading after a minute"));
        let loaded = loaded.unwrap_or_else(|e| panic!("{what}: {e}"));
        assert_eq!(loaded, expected, "{what}");
    }
}

/// Load `bytes` as a PLY (with a material unless `material` is false): it must fail, naming
/// the scene and the mesh, with every word of `reason`.
fn fails(bytes: &[u8], material: bool, reason: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let path = scene_with(dir.path(), "bad.ply", bytes, material);
    let e = load(&path).err().expect("loaded a malformed PLY");
    let message = e.to_string();
    assert!(
        message.starts_with(&path.display().to_string()) && message.contains("mesh `bad.ply`"),
        "does not name the files: {message}"
    );
    for word in reason {
        assert!(message.contains(word), "lacks `{word}`: {message}");
    }
}

#[test]
fn malformed_ply_files_are_errors_naming_the_file_and_the_reason() {
    let m = mesh();
    let (vertices, faces) = (m.points.len(), m.faces.len());
    let good = ply(&m, Form::LITTLE);
    fails(&good, false, &["names no materials", "`material`"]);
    fails(
        b"solid cube\nfacet normal 0 0 1\n",
        true,
        &["not a PLY file"],
    );
    fails(
        &edited(Form::LITTLE, "binary_little_endian", "binary_middle_endian"),
        true,
        &["malformed PLY header", "Line 2"],
    );
    fails(
        &edited(
            Form::LITTLE,
            &format!("element face {faces}"),
            &format!("element polygon {faces}"),
        ),
        true,
        &["no `face` element", "point cloud"],
    );
    fails(
        &edited(Form::LITTLE, "element vertex", "element point"),
        true,
        &["no `vertex` element"],
    );
    fails(
        &edited(Form::LITTLE, "property float y", "property float why"),
        true,
        &["`vertex` has no `y` property"],
    );
    fails(
        &edited(Form::LITTLE, "property float x", "property int x"),
        true,
        &["`x` is int; strata reads float or double"],
    );
    fails(
        &edited(Form::LITTLE, "property float nz", "property float w"),
        true,
        &["some of `nx`, `ny`, `nz`"],
    );
    fails(
        &edited(
            Form::LITTLE,
            "uchar int vertex_indices",
            "uchar float vertex_indices",
        ),
        true,
        &["is list uchar float; strata reads a list of integers"],
    );
    fails(
        &edited(Form::LITTLE, "vertex_indices", "corners"),
        true,
        &["no `vertex_indices`"],
    );
    // Cut short: the binary error says which element; the ASCII one which line.
    fails(
        &good[..good.len() - 7],
        true,
        &[
            "malformed PLY",
            &format!("`face` element {faces} of {faces}"),
        ],
    );
    let ascii = ply(&m, Form::ASCII);
    let header_lines = 13;
    fails(
        &ascii[..ascii.len() - 3],
        true,
        &[
            "malformed PLY",
            &format!("line {}", header_lines + vertices + faces),
        ],
    );
    fails(
        &edited(Form::ASCII, "\n4 0 1 7 6\n", "\n4 0 1 seven 6\n"),
        true,
        &[&format!("line {}", header_lines + vertices + 1)],
    );
    fails(
        &edited(Form::ASCII, "\n4 0 1 7 6\n", "\n4 0 1 -7 6\n"),
        true,
        &["negative vertex index"],
    );
    fails(
        &edited(Form::ASCII, "\n4 0 1 7 6\n", "\n4 0 1 36 6\n"),
        true,
        &[&format!(
            "line {}: vertex index 36 out of range ({vertices} vertices)",
            header_lines + vertices + 1
        )],
    );
    // Not finite: a NaN coordinate, and a double beyond f32's range.
    let payload = |bytes: &[u8]| {
        let end = b"end_header\n";
        bytes.windows(end.len()).position(|w| w == end).unwrap() + end.len()
    };
    let mut nan = good.clone();
    let at = payload(&nan) + 4;
    nan[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    fails(&nan, true, &["vertex 1 is not finite"]);
    let doubles = Form {
        encoding: "binary_big_endian",
        normals: true,
        unusual: true,
    };
    let mut huge = ply(&m, doubles);
    // Past the faces, the two edges, two vertices (three doubles, a colour, a normal each).
    let face_bytes: usize = m.faces.iter().map(|f| 1 + 4 * f.len()).sum();
    let at = payload(&huge) + face_bytes + 2 * 8 + (3 * 8 + 3 + 12) * 2;
    huge[at..at + 8].copy_from_slice(&1e300_f64.to_be_bytes());
    fails(&huge, true, &["vertex 3 is not finite"]);
    fails(
        &edited(
            Form::ASCII,
            &format!("element vertex {vertices}"),
            "element vertex 4000000000",
        ),
        true,
        &["malformed PLY"],
    );
    fails(
        &edited(Form::ASCII, "\n4 0 1 7 6\n", "\n2 0 1\n"),
        true,
        &[&format!(
            "line {}: a face of 2 corners (a face needs at least 3)",
            header_lines + vertices + 1
        )],
    );
    // A negative corner in a list of a signed type other than int.
    fails(
        &replaced(
            &edited(
                Form::ASCII,
                "uchar int vertex_indices",
                "uchar char vertex_indices",
            ),
            "\n4 0 1 7 6\n",
            "\n4 0 1 -7 6\n",
        ),
        true,
        &["negative vertex index"],
    );
    // A line of a megabyte without breaks: the reason quotes a little of it, not all.
    let long = edited(
        Form::ASCII,
        "\n4 0 1 7 6\n",
        &format!("\n4 0 1 {}\n", "7".repeat(1 << 20)),
    );
    let dir = tempfile::tempdir().unwrap();
    let e = load(&scene_with(dir.path(), "long.ply", &long, true))
        .err()
        .unwrap();
    assert!(e.to_string().len() < 600, "{} bytes", e.to_string().len());
}

/// `bytes` gzip-compressed.
fn gzip(bytes: &[u8]) -> Vec<u8> {
    use std::io::Write;
    let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    e.write_all(bytes).unwrap();
    e.finish().unwrap()
}

/// Write `bytes` as `name` beside a pbrt-v4 scene whose one shape is `plymesh` `name`; the
/// scene's path.
fn pbrt_scene_with(dir: &std::path::Path, name: &str, bytes: &[u8]) -> std::path::PathBuf {
    std::fs::write(dir.join(name), bytes).unwrap();
    let text = format!(
        "LookAt 0 3 -4  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" 40\nWorldBegin\n\
         Shape \"plymesh\" \"string filename\" \"{name}\"\n"
    );
    let path = dir.join(format!("{name}.pbrt"));
    std::fs::write(&path, text).unwrap();
    path
}

/// pbrt-v4 scenes ship meshes as `.ply.gz`: a gzipped PLY, binary or ASCII, loads the triangles
/// of the plain file, from a pbrt `plymesh` and from a TOML `mesh` alike, and so does one whose
/// name does not say it is compressed, or says so wrongly (the bytes `1f 8b` decide).
#[test]
fn gzipped_ply_files_load_the_triangles_of_the_plain_file() {
    let dir = tempfile::tempdir().unwrap();
    for form in [Form::ASCII, Form::LITTLE] {
        let plain = ply(&mesh(), form);
        let packed = gzip(&plain);
        let what = form.encoding;
        let expected = prims(&load(&pbrt_scene_with(dir.path(), "m.ply", &plain)).unwrap());
        assert!(!expected.is_empty());
        // A plain file named as a compressed one reads too.
        for (name, bytes) in [
            ("m.ply.gz", &packed),
            ("M.PLY.GZ", &packed),
            ("misnamed.ply", &packed),
            ("plain.ply.gz", &plain),
        ] {
            let scene = load(&pbrt_scene_with(dir.path(), name, bytes))
                .unwrap_or_else(|e| panic!("{what} {name}: {e}"));
            assert_eq!(prims(&scene), expected, "{what} {name}");
        }
        let expected = prims(&load(&scene_with(dir.path(), "m.ply", &plain, true)).unwrap());
        for name in ["m.ply.gz", "misnamed.ply"] {
            let scene = load(&scene_with(dir.path(), name, &packed, true))
                .unwrap_or_else(|e| panic!("{what} {name}: {e}"));
            assert_eq!(prims(&scene), expected, "TOML, {what} {name}");
        }
    }
}

/// A missing `.ply.gz` and a corrupt one are errors that name the file, at the `Shape`.
#[test]
fn missing_and_corrupt_gzipped_ply_files_are_errors_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let packed = gzip(&ply(&mesh(), Form::LITTLE));
    let error = |path: std::path::PathBuf| load(&path).err().expect("loaded").to_string();
    // The scene names a file that is not there.
    let path = pbrt_scene_with(dir.path(), "there.ply.gz", &packed);
    std::fs::remove_file(dir.path().join("there.ply.gz")).unwrap();
    let e = error(path);
    assert!(e.contains(":4:1: ") && e.contains("there.ply.gz"), "{e}");
    assert!(e.contains("cannot read"), "{e}");
    // Cut short, and with its compressed bytes overwritten.
    let mut corrupt = packed.clone();
    corrupt[12..40].fill(0xff);
    for (name, bytes) in [
        ("short.ply.gz", &packed[..packed.len() / 2]),
        ("corrupt.ply.gz", &corrupt[..]),
    ] {
        let e = error(pbrt_scene_with(dir.path(), name, bytes));
        assert!(e.contains(":4:1: ") && e.contains(name), "{e}");
        assert!(e.contains("corrupt gzip"), "{e}");
    }
    // gzip of something that is not a PLY says so.
    let e = error(pbrt_scene_with(
        dir.path(),
        "text.ply.gz",
        &gzip(b"solid\n"),
    ));
    assert!(
        e.contains("text.ply.gz") && e.contains("not a PLY file"),
        "{e}"
    );
}
