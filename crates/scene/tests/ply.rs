//! PLY meshes: every encoding loads to the primitives its OBJ gives, and a malformed PLY is an
//! error naming the scene, the mesh and the reason, never a panic.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use stratapt_scene::load::load;
use stratapt_scene::{FlatScene, Prim};

/// A small bumpy grid: its points and normals (f32 values, so that text and binary files
/// carry the same numbers), and faces of three, four and five corners.
struct Mesh {
    points: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    faces: Vec<Vec<u32>>,
}

fn mesh() -> Mesh {
    let n = 6;
    let mut points = Vec::new();
    let mut normals = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let (x, z) = (i as f32 * 0.37 - 1.0, j as f32 * 0.41 - 1.0);
            let y = 0.2 * (3.0 * x).sin() * (2.0 * z).cos();
            points.push([x, y, z]);
            let normal = glam::Vec3::new(-0.6 * (3.0 * x).cos(), 1.0, 0.4 * (2.0 * z).sin());
            normals.push(normal.normalize().to_array());
        }
    }
    let at = |i: u32, j: u32| i * n + j;
    let mut faces = Vec::new();
    for i in 0..n - 1 {
        for j in 0..n - 1 {
            let quad = vec![at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j)];
            match (i + j) % 3 {
                0 => faces.push(quad),
                _ => {
                    faces.push(vec![quad[0], quad[1], quad[2]]);
                    faces.push(vec![quad[0], quad[2], quad[3]]);
                }
            }
        }
    }
    // A pentagon across the edge of the grid.
    faces.push(vec![at(0, 0), at(1, 0), at(2, 0), at(2, 1), at(0, 1)]);
    Mesh {
        points,
        normals,
        faces,
    }
}

fn obj(m: &Mesh, with_normals: bool) -> Vec<u8> {
    let mut out = String::new();
    for p in &m.points {
        writeln!(out, "v {} {} {}", p[0], p[1], p[2]).unwrap();
    }
    for n in m.normals.iter().filter(|_| with_normals) {
        writeln!(out, "vn {} {} {}", n[0], n[1], n[2]).unwrap();
    }
    for f in &m.faces {
        out.push('f');
        for &c in f {
            match with_normals {
                true => write!(out, " {}//{}", c + 1, c + 1),
                false => write!(out, " {}", c + 1),
            }
            .unwrap();
        }
        out.push('\n');
    }
    out.into_bytes()
}

/// How a PLY is written: its encoding and what it carries besides the mesh.
#[derive(Clone, Copy)]
struct Form {
    encoding: &'static str,
    normals: bool,
    /// Positions as double, corners as `uint`, a colour per vertex, an `edge` element, and
    /// the faces before the vertices.
    unusual: bool,
}

impl Form {
    const ASCII: Self = Self::plain("ascii");
    const LITTLE: Self = Self::plain("binary_little_endian");

    const fn plain(encoding: &'static str) -> Self {
        Self {
            encoding,
            normals: true,
            unusual: false,
        }
    }
}

fn ply(m: &Mesh, form: Form) -> Vec<u8> {
    let mut header = format!(
        "ply\nformat {} 1.0\ncomment made by strata's tests\n",
        form.encoding
    );
    let real = if form.unusual { "double" } else { "float" };
    let vertex_header = {
        let mut h = format!("element vertex {}\n", m.points.len());
        for name in ["x", "y", "z"] {
            writeln!(h, "property {real} {name}").unwrap();
        }
        if form.unusual {
            h.push_str("property uchar red\nproperty uchar green\nproperty uchar blue\n");
        }
        if form.normals {
            h.push_str("property float nx\nproperty float ny\nproperty float nz\n");
        }
        h
    };
    let (index, list) = match form.unusual {
        true => ("uint", "vertex_index"),
        false => ("int", "vertex_indices"),
    };
    let face_header = format!(
        "element face {}\nproperty list uchar {index} {list}\n",
        m.faces.len()
    );
    let edge_header = "element edge 2\nproperty int vertex1\nproperty int vertex2\n";
    match form.unusual {
        true => header += &(face_header.clone() + edge_header + &vertex_header),
        false => header += &(vertex_header.clone() + &face_header),
    }
    header.push_str("end_header\n");

    let mut body = Payload::new(form.encoding);
    let vertices = |body: &mut Payload| {
        for (p, n) in m.points.iter().zip(&m.normals) {
            for &x in p {
                match form.unusual {
                    true => body.f64(x as f64),
                    false => body.f32(x),
                }
            }
            if form.unusual {
                body.u8(200);
                body.u8(100);
                body.u8(50);
            }
            if form.normals {
                n.iter().for_each(|&x| body.f32(x));
            }
            body.end();
        }
    };
    let faces = |body: &mut Payload| {
        for f in &m.faces {
            body.u8(f.len() as u8);
            f.iter().for_each(|&c| body.u32(c));
            body.end();
        }
    };
    match form.unusual {
        true => {
            faces(&mut body);
            for _ in 0..2 {
                body.u32(1);
                body.u32(2);
                body.end();
            }
            vertices(&mut body);
        }
        false => {
            vertices(&mut body);
            faces(&mut body);
        }
    }
    [header.into_bytes(), body.bytes].concat()
}

/// A PLY payload being written in one of the three encodings.
struct Payload {
    encoding: &'static str,
    bytes: Vec<u8>,
}

impl Payload {
    fn new(encoding: &'static str) -> Self {
        Self {
            encoding,
            bytes: Vec::new(),
        }
    }
    fn put(&mut self, text: String, le: &[u8], be: &[u8]) {
        match self.encoding {
            "ascii" => self.bytes.extend(text.as_bytes().iter().chain(b" ")),
            "binary_little_endian" => self.bytes.extend(le),
            _ => self.bytes.extend(be),
        }
    }
    fn f32(&mut self, x: f32) {
        self.put(x.to_string(), &x.to_le_bytes(), &x.to_be_bytes());
    }
    fn f64(&mut self, x: f64) {
        self.put(x.to_string(), &x.to_le_bytes(), &x.to_be_bytes());
    }
    fn u32(&mut self, x: u32) {
        self.put(x.to_string(), &x.to_le_bytes(), &x.to_be_bytes());
    }
    fn u8(&mut self, x: u8) {
        self.put(x.to_string(), &[x], &[x]);
    }
    fn end(&mut self) {
        if self.encoding == "ascii" {
            self.bytes.pop();
            self.bytes.push(b'\n');
        }
    }
}

/// Write `bytes` as `name` beside a scene that renders it in one material; the scene's path.
fn scene_with(dir: &Path, name: &str, bytes: &[u8], material: bool) -> PathBuf {
    std::fs::write(dir.join(name), bytes).unwrap();
    let material = if material {
        "material = \"clay\"\n"
    } else {
        ""
    };
    let text = format!(
        "[camera]\neye = [0, 3, -4]\nlook_at = [0, 0, 0]\nfov = 40\n\
         [materials.clay]\ntype = \"diffuse\"\nalbedo = 0.5\n\
         [[shapes]]\ntype = \"mesh\"\nfile = \"{name}\"\n{material}"
    );
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

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

/// Load `bytes` as a PLY (with a material unless `material` is false): it must fail, naming
/// the scene and the mesh, with every word of `reason`.
fn fails(bytes: &[u8], material: bool, reason: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let path = scene_with(dir.path(), "bad.ply", bytes, material);
    let e = load(&path).err().expect("loaded a malformed PLY");
    let message = e.to_string();
    assert!(
        message.starts_with(&path.display().to_string()) && message.contains("bad.ply"),
        "does not name the files: {message}"
    );
    for word in reason {
        assert!(message.contains(word), "lacks `{word}`: {message}");
    }
}

/// The PLY text of `m` with `from` replaced by `to` (ASCII or header edits).
fn edited(form: Form, from: &str, to: &str) -> Vec<u8> {
    let bytes = ply(&mesh(), form);
    let at = bytes
        .windows(from.len())
        .position(|w| w == from.as_bytes())
        .unwrap_or_else(|| panic!("`{from}` not in the PLY"));
    [&bytes[..at], to.as_bytes(), &bytes[at + from.len()..]].concat()
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
        &[&format!("face index 36 out of range ({vertices} vertices)")],
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
}

#[test]
fn mutated_ply_files_load_or_fail_with_the_files_named_never_panic() {
    let dir = tempfile::tempdir().unwrap();
    let seeds = [ply(&mesh(), Form::LITTLE), ply(&mesh(), Form::ASCII)];
    let mut state = 2026_u64;
    let mut below = |n: usize| {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((state >> 33) % n as u64) as usize
    };
    let (mut loaded, mut total) = (0, 0);
    for k in 0..600 {
        let mut bytes = seeds[k % 2].clone();
        for _ in 0..1 + below(3) {
            let i = below(bytes.len());
            match below(4) {
                0 => bytes[i] = below(256) as u8,
                1 => bytes[i] ^= 1 << below(8),
                2 => {
                    bytes.remove(i);
                }
                _ => bytes.truncate(i),
            }
        }
        let path = scene_with(dir.path(), "m.ply", &bytes, true);
        let result = std::panic::catch_unwind(|| load(&path));
        total += 1;
        match result {
            Err(_) => panic!("PLY mutation {k}: the loader panicked"),
            Ok(Ok(_)) => loaded += 1,
            Ok(Err(e)) => {
                let message = e.to_string();
                assert!(
                    message.starts_with(&path.display().to_string()) && message.contains("m.ply"),
                    "PLY mutation {k}: the error does not name the files: {message}"
                );
            }
        }
    }
    println!("{total} mutated PLY files: {loaded} loaded, the rest refused naming the files");
    assert!(
        loaded > total / 20 && loaded < total * 19 / 20,
        "{loaded} of {total} loaded"
    );
}
