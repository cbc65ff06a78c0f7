//! strata's TOML scene files read into the scene [`Description`] ([`parse`]), and any
//! description validated and flattened into records ([`build`]), with OBJ (+ MTL) and PLY meshes.
//!
//! The format is documented in `docs/reference/scene-format.md`. Stages: `parse` (TOML → typed
//! description with spans) → `camera`, `materials`, `lights`, `shapes` (validate and convert,
//! each error at the offending value, in whichever file the description read it from) → BVH
//! ([`stratapt_scene::bvh`]) → light tables ([`stratapt_scene::light_table`]). Reading a scene file of either
//! format is [`crate::scene_file`]'s.

mod camera;
mod lights;
mod materials;
pub(crate) mod mesh;
mod parse;
mod shapes;
mod textures;
mod transform;
mod validate;

pub use camera::MAX_RESOLUTION;
pub use mesh::{MeshData, MeshStore};
pub use parse::parse;
pub use shapes::PERP_TOLERANCE;
pub use transform::euler_xyz;

use crate::desc::Description;
use std::path::{Path, PathBuf};
use stratapt_scene::light_table::{build_tables, is_unhittable};
use stratapt_scene::records::{Light, NONE};
use stratapt_scene::{FlatScene, SceneError};
use validate::Ctx;

/// The scene files (`*.toml`) in folder `dir`, sorted by name.
pub fn scene_files(dir: &Path) -> std::io::Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir)? {
        let path = entry?.path();
        if path.extension().is_some_and(|e| e == "toml") {
            files.push(path);
        }
    }
    files.sort();
    Ok(files)
}

/// The triangles of the PLY file at `path` (binary or ASCII, faces fan-triangulated), in the
/// file's space; errors are reasons.
pub fn read_ply(path: &Path) -> Result<MeshData, String> {
    let mut objects = mesh::ply::load(path, Some(0))?;
    let o = objects.pop().ok_or("no mesh")?;
    Ok(MeshData {
        positions: o.positions,
        normals: o.normals,
        uvs: o.uvs,
        indices: o.indices,
    })
}

/// Load from TOML text; `path` names it in errors and anchors relative mesh paths.
pub fn load_str(text: &str, path: &Path) -> Result<FlatScene, SceneError> {
    build(parse(text, path)?)
}

/// Validate and flatten a scene description; each error names the place in the description's
/// sources that the offending value was read from. Its `mesh` shapes take their meshes from
/// [`Description::meshes`] where it holds their `file` name.
pub fn build(desc: Description) -> Result<FlatScene, SceneError> {
    let Description {
        sources,
        base_dir,
        scene: doc_scene,
        textures: doc_textures,
        materials: doc_materials,
        shapes: doc_shapes,
        lights: doc_lights,
        mut meshes,
        import,
    } = desc;
    let ctx = Ctx::new(&sources);

    // Camera, film, render settings.
    let settings = camera::settings(&ctx, doc_scene.render.as_ref())?;
    let exact = camera::exact(&ctx, doc_scene.render.as_ref())?;
    let (camera, shutter_open) = camera::camera(&ctx, &doc_scene.camera, doc_scene.film.as_ref())?;

    // Textures, materials, then shapes (meshes may add MTL materials).
    let base_dir = base_dir.as_path();
    let textures = textures::Textures::from_descs(&ctx, &doc_textures, base_dir)?;
    let mut materials =
        materials::Materials::from_descs(&ctx, &doc_materials, &textures, textures.tables())?;
    let mut shapes = shapes::build(
        &ctx,
        &doc_shapes,
        &mut materials,
        &textures,
        shutter_open,
        base_dir,
        &mut meshes,
    )?;

    // Lights that are not surfaces, and the sky.
    let mut unhittable = Vec::new();
    let mut hittable = Vec::new();
    for desc in &doc_lights {
        if let Some(light) = lights::light(&ctx, desc.get_ref())? {
            if is_unhittable(&light) {
                &mut unhittable
            } else {
                &mut hittable
            }
            .push(light);
        }
    }
    let sky = match &doc_scene.sky {
        Some(sky) => lights::sky(&ctx, sky, base_dir, &mut materials.tables)?,
        None => None,
    };

    // The texels go last in the tables (records hold the other tables' offsets as floats).
    let (texture_count, texture_bytes) = (doc_textures.len() as u32, textures.bytes() as u64);
    textures.place(&ctx, &mut materials.tables)?;

    // BVH (reorders prims), then world bounds.
    let (bvh, bounds_min, bounds_max) =
        stratapt_scene::bvh::build(&mut shapes.geometry, &shapes.motions);
    let scene_radius = 0.5 * (bounds_max - bounds_min).length() as f64;

    // Light order: unhittable first (so both tables index `lights`), surfaces, the rest, sky.
    let offset = unhittable.len() as u32;
    shapes.geometry.offset_lights(offset);
    let mut all: Vec<Light> = unhittable;
    all.extend(shapes.lights);
    all.extend(hittable);
    let sky_index = match sky {
        Some(light) => {
            all.push(light);
            all.len() as u32 - 1
        }
        None => NONE,
    };
    let (light_table, unhittable_table) = build_tables(&mut all, &shapes.motions, scene_radius);
    // Environment lights (sun cones among `hittable`, then the sky) come last: the renderers
    // loop over `FlatScene::environment_lights`, a range.
    debug_assert!({
        let first = all
            .iter()
            .rposition(|l| !l.is_environment())
            .map_or(0, |i| i + 1);
        all[..first].iter().all(|l| !l.is_environment())
    });

    Ok(FlatScene {
        path: sources.main().to_path_buf(),
        camera,
        geometry: shapes.geometry,
        materials: materials.gpu,
        material_names: materials.names,
        tables: materials.tables,
        textures: texture_count,
        texture_bytes,
        lights: all,
        light_table,
        unhittable_table,
        motions: shapes.motions,
        sky: sky_index,
        bvh,
        bounds_min,
        bounds_max,
        settings,
        exact,
        import,
    })
}

/// Write `mesh` as a binary little-endian PLY file (what [`read_ply`] and a `mesh` shape read
/// back bit for bit): `x y z`, then `nx ny nz` and `u v` when it has them, as floats, and each
/// triangle's `vertex_indices` as a list of three uints.
pub fn write_ply(path: &Path, mesh: &MeshData) -> std::io::Result<()> {
    let out = std::io::BufWriter::with_capacity(1 << 20, std::fs::File::create(path)?);
    write_ply_to(out, mesh)
}

/// [`write_ply`]'s bytes, into `out`.
pub fn write_ply_to(mut out: impl std::io::Write, mesh: &MeshData) -> std::io::Result<()> {
    let vertices = mesh.positions.len() / 3;
    let mut header = format!(
        "ply\nformat binary_little_endian 1.0\ncomment written by strata\nelement vertex {vertices}\n\
         property float x\nproperty float y\nproperty float z\n"
    );
    if mesh.normals.is_some() {
        header.push_str("property float nx\nproperty float ny\nproperty float nz\n");
    }
    if mesh.uvs.is_some() {
        header.push_str("property float u\nproperty float v\n");
    }
    header.push_str(&format!(
        "element face {}\nproperty list uchar uint vertex_indices\nend_header\n",
        mesh.indices.len() / 3
    ));
    out.write_all(header.as_bytes())?;
    for i in 0..vertices {
        let mut put = |v: &[f32]| -> std::io::Result<()> {
            v.iter().try_for_each(|x| out.write_all(&x.to_le_bytes()))
        };
        put(&mesh.positions[3 * i..3 * i + 3])?;
        if let Some(n) = &mesh.normals {
            put(&n[3 * i..3 * i + 3])?;
        }
        if let Some(uv) = &mesh.uvs {
            put(&uv[2 * i..2 * i + 2])?;
        }
    }
    for t in mesh.indices.chunks_exact(3) {
        out.write_all(&[3])?;
        for i in t {
            out.write_all(&i.to_le_bytes())?;
        }
    }
    out.flush()
}
