//! `mesh` shapes: triangle meshes from OBJ files (with MTL materials, through tobj) or PLY
//! files (binary or ASCII, through ply-rs-bw, gzip-compressed or not), told apart by the file's
//! extension (`.ply` or `.ply.gz`, any case, is PLY; anything else OBJ).
//!
//! Either way faces are triangulated as fans, per-vertex normals become shading normals when
//! every vertex has one, and texture coordinates are kept when every vertex has them (an OBJ's
//! `vt` with `v` flipped to `1 − v`, as Mitsuba 3 reads OBJ files; a PLY's `u v`, `texture_u
//! texture_v` or `s t`, as they are); a PLY carries no materials, so its shape names one.

mod obj;
pub(crate) mod ply;

use super::materials::Materials;
use super::validate::{Ctx, Result};
use crate::desc::MeshDesc;
use glam::Vec3;
use std::path::Path;

/// One object of a mesh, in the file's (object) space, its vertices shared by its faces.
pub struct MeshObject {
    /// Vertex positions, `xyz` after `xyz`, each finite.
    pub positions: Vec<f32>,
    /// Unit vertex normals parallel to `positions` when the file gives every vertex one; zero
    /// where a normal is zero or not finite (the faces using it are flat).
    pub normals: Option<Vec<f32>>,
    /// Texture coordinates `(u, v)` parallel to the vertices, when the file gives every vertex
    /// some; each finite.
    pub uvs: Option<Vec<f32>>,
    /// Three vertex indices per triangle, each in range.
    pub indices: Vec<u32>,
    pub material: u32,
}

impl MeshObject {
    /// Check what a file gave (finite positions, indices in range, three per triangle) and make
    /// its normals unit length (zero where they cannot be). Errors are reasons.
    pub(crate) fn new(
        positions: Vec<f32>,
        mut normals: Option<Vec<f32>>,
        uvs: Option<Vec<f32>>,
        indices: Vec<u32>,
        material: u32,
    ) -> std::result::Result<Self, String> {
        if let Some(i) = positions.iter().position(|x| !x.is_finite()) {
            return Err(format!("vertex {} is not finite", i / 3 + 1));
        }
        if let Some(i) = uvs.iter().flatten().position(|x| !x.is_finite()) {
            return Err(format!(
                "the texture coordinates of vertex {} are not finite",
                i / 2 + 1
            ));
        }
        debug_assert!(uvs
            .as_ref()
            .is_none_or(|uv| uv.len() / 2 == positions.len() / 3));
        let vertices = (positions.len() / 3) as u32;
        if let Some(&i) = indices.iter().find(|&&i| i >= vertices) {
            return Err(format!("face index {i} out of range ({vertices} vertices)"));
        }
        debug_assert_eq!(indices.len() % 3, 0);
        debug_assert!(normals.as_ref().is_none_or(|n| n.len() == positions.len()));
        for n in normals.iter_mut().flat_map(|n| n.chunks_exact_mut(3)) {
            let unit = Vec3::from_slice(n).normalize_or_zero();
            let unit = if unit.is_finite() { unit } else { Vec3::ZERO };
            n.copy_from_slice(&unit.to_array());
        }
        Ok(Self {
            positions,
            normals,
            uvs,
            indices,
            material,
        })
    }
}

pub use crate::desc::{MeshData, MeshStore};

/// Load the mesh of `desc`; `material` overrides the OBJ's MTL (and is required for a PLY).
/// Materials from an MTL are added to `materials` as `FILE:NAME`. A mesh of that `file` name in
/// `store` is taken from there, as a PLY file would be read.
pub fn load(
    ctx: &Ctx,
    desc: &MeshDesc,
    material: Option<u32>,
    materials: &mut Materials,
    base_dir: &Path,
    store: &mut MeshStore,
) -> Result<Vec<MeshObject>> {
    let file = desc.file.get_ref();
    let path = base_dir.join(file);
    let fail = |reason: String| {
        ctx.err(
            desc.file.span(),
            format!("mesh `{file}` ({}): {reason}", path.display()),
        )
    };
    let objects = match (store.remove(file), is_ply(&path)) {
        (Some(m), _) => {
            let material =
                material.ok_or_else(|| fail("a mesh held in memory names no materials".into()))?;
            MeshObject::new(m.positions, m.normals, m.uvs, m.indices, material).map(|o| vec![o])
        }
        (None, true) => ply::load(&path, material),
        (None, false) => obj::load(&path, file, material, materials),
    }
    .map_err(fail)?;
    if objects.iter().all(|o| o.indices.is_empty()) {
        return Err(fail("no triangles".into()));
    }
    Ok(objects)
}

/// Whether `path` names a PLY file (by its extension, in any case: `.ply`, or `.ply.gz`
/// compressed).
fn is_ply(path: &Path) -> bool {
    let ply = |p: &Path| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("ply"));
    let gz = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("gz"));
    ply(path) || (gz && ply(&path.with_extension("")))
}
