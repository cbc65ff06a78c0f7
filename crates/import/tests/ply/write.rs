//! Writers of a small test mesh as OBJ and as PLY in every encoding, and of a scene around a
//! mesh file, for `tests/ply.rs` and `tests/corpus.rs`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// A small bumpy grid: its points and normals (f32 values, so that text and binary files
/// carry the same numbers), and faces of three, four and five corners.
pub struct Mesh {
    pub points: Vec<[f32; 3]>,
    pub normals: Vec<[f32; 3]>,
    pub faces: Vec<Vec<u32>>,
}

pub fn mesh() -> Mesh {
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

pub fn obj(m: &Mesh, with_normals: bool) -> Vec<u8> {
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
pub struct Form {
    pub encoding: &'static str,
    pub normals: bool,
    /// Positions as double, corners as `uint`, a colour per vertex, an `edge` element, and
    /// the faces before the vertices.
    pub unusual: bool,
}

impl Form {
    pub const ASCII: Self = Self::plain("ascii");
    pub const LITTLE: Self = Self::plain("binary_little_endian");

    const fn plain(encoding: &'static str) -> Self {
        Self {
            encoding,
            normals: true,
            unusual: false,
        }
    }
}

pub fn ply(m: &Mesh, form: Form) -> Vec<u8> {
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

/// The PLY of [`mesh`] in `form` with the first `from` replaced by `to` (ASCII or header edits).
pub fn edited(form: Form, from: &str, to: &str) -> Vec<u8> {
    replaced(&ply(&mesh(), form), from, to)
}

/// `bytes` with the first `from` replaced by `to`.
pub fn replaced(bytes: &[u8], from: &str, to: &str) -> Vec<u8> {
    let at = bytes
        .windows(from.len())
        .position(|w| w == from.as_bytes())
        .unwrap_or_else(|| panic!("`{from}` not in the file"));
    [&bytes[..at], to.as_bytes(), &bytes[at + from.len()..]].concat()
}

/// Write `bytes` as `name` beside a scene that renders it in one material; the scene's path.
pub fn scene_with(dir: &Path, name: &str, bytes: &[u8], material: bool) -> PathBuf {
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
