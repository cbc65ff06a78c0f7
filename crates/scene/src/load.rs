//! Scene files: TOML, with OBJ (+ MTL) and PLY meshes, parsed, validated (file:line:column
//! errors) and flattened.
//!
//! The format is documented in the README's "Scene format" section. Stages: `parse` (TOML → typed
//! descriptions with spans) → `camera`, `materials`, `lights`, `shapes` (validate and
//! convert, each error at the offending value) → BVH ([`crate::bvh`]) → light tables
//! ([`crate::light_table`]).

mod camera;
mod desc;
mod lights;
mod materials;
mod mesh;
mod parse;
mod shapes;
mod textures;
mod transform;
mod validate;

pub use camera::MAX_RESOLUTION;
pub use transform::euler_xyz;

use crate::light_table::{build_tables, is_unhittable};
use crate::records::{Light, NONE};
use crate::{FlatScene, SceneError, SourceLocation};
use std::path::{Path, PathBuf};
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

/// Load, validate and flatten the scene file at `path`.
pub fn load(path: &Path) -> Result<FlatScene, SceneError> {
    let text = std::fs::read_to_string(path).map_err(|e| {
        SceneError::new(
            SourceLocation::file(path),
            format!("cannot read scene file: {e}"),
        )
    })?;
    load_str(&text, path)
}

/// Load from TOML text; `path` names it in errors and anchors relative mesh paths.
pub fn load_str(text: &str, path: &Path) -> Result<FlatScene, SceneError> {
    let ctx = Ctx::new(path, text);
    let doc = parse::parse(&ctx)?;

    // Camera, film, render settings.
    let settings = camera::settings(&ctx, doc.scene.render.as_ref())?;
    let exact = camera::exact(&ctx, doc.scene.render.as_ref())?;
    let (camera, shutter_open) = camera::camera(&ctx, &doc.scene.camera, doc.scene.film.as_ref())?;

    // Textures, materials, then shapes (meshes may add MTL materials).
    let base_dir = path.parent().unwrap_or(Path::new(""));
    let textures = textures::Textures::from_descs(&ctx, &doc.textures, base_dir)?;
    let mut materials =
        materials::Materials::from_descs(&ctx, &doc.materials, &textures, textures.tables())?;
    let mut shapes = shapes::build(&ctx, &doc.shapes, &mut materials, shutter_open, base_dir)?;

    // Lights that are not surfaces, and the sky.
    let mut unhittable = Vec::new();
    let mut hittable = Vec::new();
    for (desc, _) in &doc.lights {
        if let Some(light) = lights::light(&ctx, desc)? {
            if is_unhittable(&light) {
                &mut unhittable
            } else {
                &mut hittable
            }
            .push(light);
        }
    }
    let sky = match &doc.scene.sky {
        Some(sky) => lights::sky(&ctx, sky, base_dir, &mut materials.tables)?,
        None => None,
    };

    // The texels go last in the tables (records hold the other tables' offsets as floats).
    let (texture_count, texture_bytes) = (doc.textures.len() as u32, textures.bytes() as u64);
    textures.place(&ctx, &mut materials.tables)?;

    // BVH (reorders prims), then world bounds.
    let (bvh, bounds_min, bounds_max) = crate::bvh::build(&mut shapes.geometry, &shapes.motions);
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
        path: path.to_path_buf(),
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
    })
}
