//! PLY meshes through ply-rs-bw: binary (either byte order) or ASCII, read element by element
//! straight into the mesh's arrays, never held as a list of elements. A gzip-compressed file
//! (pbrt-v4's `.ply.gz`, told by its first two bytes whatever its name) is decompressed into
//! memory first.
//!
//! The `vertex` element's `x`, `y`, `z` (float or double) are the positions, and its `nx`,
//! `ny`, `nz` the normals when it has them, and its texture coordinates `u`, `v` (else
//! `texture_u`, `texture_v`, else `s`, `t`: Mitsuba 3's order) when it has a pair; the `face`
//! element's `vertex_indices` (or `vertex_index`) list, of any integer type, gives each face's
//! corners (at least three, each below the header's vertex count). Other properties (colours,
//! confidence) and other elements (range grids, edges) are read past, as are tokens after an
//! ASCII element's last property (ply-rs-bw ignores them).

use super::MeshObject;
use ply_rs_bw::parser::{Parser, Reader};
use ply_rs_bw::ply::{
    ElementDef, Encoding, PropertyAccess, PropertyAccessResult, PropertyType, ScalarType,
};
use std::io::{BufRead, BufReader};
use std::panic::AssertUnwindSafe;
use std::path::Path;

/// The names a vertex's texture coordinates go by, in the order they are looked for.
const UV_NAMES: [[&str; 2]; 3] = [["u", "v"], ["texture_u", "texture_v"], ["s", "t"]];

/// Names the `face` element's corner list goes by.
const CORNER_LISTS: [&str; 2] = ["vertex_indices", "vertex_index"];

/// The mesh of the PLY file at `path`, all of it in `material` (a PLY names none). Errors are
/// reasons.
pub fn load(path: &Path, material: Option<u32>) -> Result<Vec<MeshObject>, String> {
    let material = material.ok_or("a PLY file names no materials: give the shape a `material`")?;
    let mut opened = std::fs::File::open(path).map_err(|e| format!("cannot read: {e}"))?;
    let size = opened.metadata().map_or(u64::MAX, |m| m.len());
    let object = match is_gzip(&mut opened).map_err(|e| format!("cannot read: {e}"))? {
        true => {
            let bytes = gunzip(opened)?;
            let size = bytes.len() as u64;
            parse(Reader::new(&bytes[..]), size, material)
        }
        false => parse(
            Reader::new(BufReader::with_capacity(1 << 20, opened)),
            size,
            material,
        ),
    }?;
    Ok(vec![object])
}

/// [`read`], a panic of ply-rs-bw (on input it does not expect) reported as a malformed file.
fn parse<R: BufRead>(
    mut reader: Reader<R>,
    size: u64,
    material: u32,
) -> Result<MeshObject, String> {
    std::panic::catch_unwind(AssertUnwindSafe(|| read(&mut reader, size, material)))
        .map_err(|_| "malformed PLY (the parser gave up)".to_string())?
}

/// Whether `file` starts with gzip's magic bytes `1f 8b` (pbrt-v4 scenes ship meshes as
/// `.ply.gz`; a file is told by its bytes, not its name); the file is left at its start.
fn is_gzip(file: &mut std::fs::File) -> std::io::Result<bool> {
    use std::io::{Read, Seek};
    let mut magic = [0u8; 2];
    // `read_exact`: a plain `read` may return one byte; a file shorter than two is no gzip.
    let gzip = match file.read_exact(&mut magic) {
        Ok(()) => magic == [0x1f, 0x8b],
        Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => false,
        Err(e) => return Err(e),
    };
    file.rewind()?;
    Ok(gzip)
}

/// The most a gzipped PLY file may decompress to: 8 GiB, more than 2²⁸ triangles (strata's
/// limit) take as a binary PLY, so that a small corrupt or hostile file cannot take the memory.
const MAX_GUNZIPPED: u64 = 8 << 30;

/// The decompressed bytes of a gzip file (each member, as `gzip -d` reads concatenated ones).
fn gunzip(file: std::fs::File) -> Result<Vec<u8>, String> {
    use std::io::Read;
    let mut bytes = Vec::new();
    flate2::read::MultiGzDecoder::new(BufReader::with_capacity(1 << 20, file))
        .take(MAX_GUNZIPPED + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| format!("a corrupt gzip file ({e})"))?;
    if bytes.len() as u64 > MAX_GUNZIPPED {
        return Err(format!(
            "a gzip file that decompresses to more than {} GiB",
            MAX_GUNZIPPED >> 30
        ));
    }
    Ok(bytes)
}

/// The header, then every element in the order it declares them.
fn read<R: BufRead>(
    reader: &mut Reader<R>,
    size: u64,
    material: u32,
) -> Result<MeshObject, String> {
    let start = reader.get_mut().fill_buf().map_err(|e| e.to_string())?;
    let first_line = start.split(|&b| b == b'\n').next().unwrap_or_default();
    if first_line.trim_ascii() != b"ply" {
        return Err("not a PLY file (its first line is not `ply`)".into());
    }
    let header = Parser::<Ignored>::new()
        .read_header(reader)
        .map_err(|e| format!("malformed PLY header: {}", one_line(e)))?;
    let vertex = header
        .elements
        .get("vertex")
        .ok_or("the PLY has no `vertex` element")?;
    let face = header
        .elements
        .get("face")
        .ok_or("the PLY has no `face` element (a point cloud has no surface to render)")?;
    let (has_normals, uv_pair) = vertex_layout(vertex)?;
    face_layout(face)?;

    // Capacity from the header, but no more than the file could hold (an ASCII vertex takes at
    // least 6 bytes, a face 4), so that a lying header cannot claim the memory.
    let at_most =
        |count: usize, bytes: u64| count.min(usize::try_from(size / bytes).unwrap_or(count));
    let vertices = at_most(vertex.count, 6);
    let mut positions = Vec::with_capacity(3 * vertices);
    let mut normals = has_normals.then(|| Vec::with_capacity(3 * vertices));
    let mut uvs = uv_pair.map(|_| Vec::with_capacity(2 * vertices));
    let mut indices = Vec::with_capacity(3 * at_most(face.count, 4));
    let mut payload = Payload {
        // ply-rs-bw's reader stands on the first line after the header.
        line: reader.line().saturating_sub(1),
        reader,
        encoding: header.encoding,
        text: String::new(),
    };
    for def in header.elements.values() {
        match def.name.as_str() {
            "vertex" => payload.each(def, |v: Vertex| {
                positions.extend_from_slice(&v.position);
                if let Some(n) = normals.as_mut() {
                    n.extend_from_slice(&v.normal);
                }
                if let (Some(uv), Some(pair)) = (uvs.as_mut(), uv_pair) {
                    uv.extend_from_slice(&v.uv[pair]);
                }
                Ok(())
            })?,
            "face" => payload.each(def, |f: Face| {
                if f.negative {
                    return Err("negative vertex index".into());
                }
                if let Some(&c) = f.corners.iter().find(|&&c| c as usize >= vertex.count) {
                    let count = vertex.count;
                    return Err(format!("vertex index {c} out of range ({count} vertices)"));
                }
                if f.corners.len() < 3 {
                    let n = f.corners.len();
                    return Err(format!("a face of {n} corners (a face needs at least 3)"));
                }
                fan(&f.corners, &mut indices);
                Ok(())
            })?,
            _ => payload.each(def, |_: Ignored| Ok(()))?,
        }
    }
    MeshObject::new(positions, normals, uvs, indices, material)
}

/// Whether the `vertex` element has normals, and which of [`UV_NAMES`] its texture coordinates
/// go by; an error unless its positions are float or double (and its normals and texture
/// coordinates, when it has any, all so).
fn vertex_layout(vertex: &ElementDef) -> Result<(bool, Option<usize>), String> {
    let real = |name: &str| match vertex.properties.get(name).map(|p| &p.data_type) {
        Some(PropertyType::Scalar(ScalarType::Float | ScalarType::Double)) => Ok(true),
        None => Ok(false),
        Some(other) => Err(format!(
            "`vertex` property `{name}` is {}; strata reads float or double",
            type_name(other)
        )),
    };
    for name in ["x", "y", "z"] {
        if !real(name)? {
            return Err(format!("`vertex` has no `{name}` property"));
        }
    }
    let normals = [real("nx")?, real("ny")?, real("nz")?];
    let normals = match normals {
        [true, true, true] => true,
        [false, false, false] => false,
        _ => return Err("`vertex` has some of `nx`, `ny`, `nz` but not all three".into()),
    };
    let mut uv = None;
    for (k, [u, v]) in UV_NAMES.iter().enumerate() {
        if real(u)? && real(v)? && uv.is_none() {
            uv = Some(k);
        }
    }
    Ok((normals, uv))
}

/// An error unless the `face` element has a list of integer corners.
fn face_layout(face: &ElementDef) -> Result<(), String> {
    let list = CORNER_LISTS
        .iter()
        .find_map(|name| face.properties.get(*name))
        .ok_or("`face` has no `vertex_indices` list")?;
    match list.data_type {
        PropertyType::List(_, ScalarType::Float | ScalarType::Double) | PropertyType::Scalar(_) => {
            Err(format!(
                "`face` property `{}` is {}; strata reads a list of integers",
                list.name,
                type_name(&list.data_type)
            ))
        }
        PropertyType::List(..) => Ok(()),
    }
}

/// A type as a PLY header writes it.
fn type_name(t: &PropertyType) -> String {
    let scalar = |t: &ScalarType| match t {
        ScalarType::Char => "char",
        ScalarType::UChar => "uchar",
        ScalarType::Short => "short",
        ScalarType::UShort => "ushort",
        ScalarType::Int => "int",
        ScalarType::UInt => "uint",
        ScalarType::Float => "float",
        ScalarType::Double => "double",
    };
    match t {
        PropertyType::Scalar(t) => scalar(t).into(),
        PropertyType::List(count, t) => format!("list {} {}", scalar(count), scalar(t)),
    }
}

/// ply-rs-bw's message (several lines, with the text it failed on, which may be a whole file
/// without line breaks) as one line of at most [`MAX_REASON`] characters.
fn one_line(e: impl std::fmt::Display) -> String {
    let text = e
        .to_string()
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    match text.char_indices().nth(MAX_REASON) {
        Some((end, _)) => format!("{} …", &text[..end]),
        None => text,
    }
}

/// The longest reason [`one_line`] passes on from ply-rs-bw.
const MAX_REASON: usize = 240;

/// Triangles of a polygon as a fan around its first corner.
fn fan(corners: &[u32], indices: &mut Vec<u32>) {
    for k in 2..corners.len() {
        indices.extend_from_slice(&[corners[0], corners[k - 1], corners[k]]);
    }
}

/// The payload being read: where, and (for ASCII) which line.
struct Payload<'a, R: BufRead> {
    reader: &'a mut Reader<R>,
    encoding: Encoding,
    /// ASCII lines read so far, the header's included.
    line: usize,
    /// The current ASCII line.
    text: String,
}

impl<R: BufRead> Payload<'_, R> {
    /// Read the `def.count` elements of `def`, handing each to `take`; an error names the
    /// element (its line, in ASCII).
    fn each<E: PropertyAccess>(
        &mut self,
        def: &ElementDef,
        mut take: impl FnMut(E) -> Result<(), String>,
    ) -> Result<(), String> {
        if def.properties.is_empty() && self.encoding != Encoding::Ascii {
            // Binary elements without properties take no bytes (however many the header says).
            return Ok(());
        }
        let parser = Parser::<E>::new();
        for i in 0..def.count {
            let element = match self.encoding {
                Encoding::Ascii => {
                    self.line += 1;
                    self.text.clear();
                    match self.reader.get_mut().read_line(&mut self.text) {
                        Ok(0) => Err("the file ends early".to_string()),
                        Ok(_) => parser.read_ascii_element(&self.text, def).map_err(one_line),
                        Err(e) => Err(e.to_string()),
                    }
                }
                Encoding::BinaryLittleEndian => parser
                    .read_little_endian_element(self.reader.get_mut(), def)
                    .map_err(one_line),
                Encoding::BinaryBigEndian => parser
                    .read_big_endian_element(self.reader.get_mut(), def)
                    .map_err(one_line),
            };
            element.and_then(&mut take).map_err(|e| {
                let at = match self.encoding {
                    Encoding::Ascii => format!("line {}", self.line),
                    _ => format!("`{}` element {} of {}", def.name, i + 1, def.count),
                };
                format!("malformed PLY, {at}: {e}")
            })?;
        }
        Ok(())
    }
}

/// A vertex: its position, normal and texture coordinates under each of [`UV_NAMES`] (zero
/// where the file has none).
#[derive(Default)]
struct Vertex {
    position: [f32; 3],
    normal: [f32; 3],
    uv: [[f32; 2]; 3],
}

impl Vertex {
    fn set(&mut self, name: &str, value: f32) -> PropertyAccessResult {
        let slot = match name {
            "x" => &mut self.position[0],
            "y" => &mut self.position[1],
            "z" => &mut self.position[2],
            "nx" => &mut self.normal[0],
            "ny" => &mut self.normal[1],
            "nz" => &mut self.normal[2],
            "u" => &mut self.uv[0][0],
            "v" => &mut self.uv[0][1],
            "texture_u" => &mut self.uv[1][0],
            "texture_v" => &mut self.uv[1][1],
            "s" => &mut self.uv[2][0],
            "t" => &mut self.uv[2][1],
            _ => return PropertyAccessResult::Ignored,
        };
        *slot = value;
        PropertyAccessResult::Set
    }
}

impl PropertyAccess for Vertex {
    fn new() -> Self {
        Self::default()
    }
    fn set_float(&mut self, name: &str, value: f32) -> PropertyAccessResult {
        self.set(name, value)
    }
    fn set_double(&mut self, name: &str, value: f64) -> PropertyAccessResult {
        // Beyond f32's range this is infinite, which `MeshObject::new` refuses.
        self.set(name, value as f32)
    }
}

/// A face: its corners, and whether the file gave a negative one.
#[derive(Default)]
struct Face {
    corners: Vec<u32>,
    negative: bool,
}

impl Face {
    /// Take `list` as the corners if `name` is the corner list.
    fn take(&mut self, name: &str, list: Vec<u32>, negative: bool) -> PropertyAccessResult {
        if !CORNER_LISTS.contains(&name) {
            return PropertyAccessResult::Ignored;
        }
        (self.corners, self.negative) = (list, negative);
        PropertyAccessResult::Set
    }

    /// [`Face::take`] for a list of another integer type.
    fn convert<T: TryInto<u32> + Copy>(&mut self, name: &str, list: &[T]) -> PropertyAccessResult {
        let corners: Vec<u32> = list.iter().filter_map(|&c| c.try_into().ok()).collect();
        let negative = corners.len() < list.len();
        self.take(name, corners, negative)
    }
}

impl PropertyAccess for Face {
    fn new() -> Self {
        Self::default()
    }
    fn set_list_char(&mut self, name: &str, list: Vec<i8>) -> PropertyAccessResult {
        self.convert(name, &list)
    }
    fn set_list_uchar(&mut self, name: &str, list: Vec<u8>) -> PropertyAccessResult {
        self.convert(name, &list)
    }
    fn set_list_short(&mut self, name: &str, list: Vec<i16>) -> PropertyAccessResult {
        self.convert(name, &list)
    }
    fn set_list_ushort(&mut self, name: &str, list: Vec<u16>) -> PropertyAccessResult {
        self.convert(name, &list)
    }
    fn set_list_int(&mut self, name: &str, list: Vec<i32>) -> PropertyAccessResult {
        // The common type: reinterpreted in place (no second allocation per face).
        let negative = list.iter().any(|&c| c < 0);
        self.take(name, list.into_iter().map(|c| c as u32).collect(), negative)
    }
    fn set_list_uint(&mut self, name: &str, list: Vec<u32>) -> PropertyAccessResult {
        self.take(name, list, false)
    }
}

/// An element read only to be passed over.
struct Ignored;

impl PropertyAccess for Ignored {
    fn new() -> Self {
        Ignored
    }
}
