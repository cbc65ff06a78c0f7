//! OBJ (+ MTL) meshes through tobj.
//!
//! Without a `material` on the shape, each face uses its MTL material: `Kd` → diffuse albedo,
//! `Ke` → emission; `illum 3`/`5` → conductor (`Ks` reflectance, GGX alpha from `Ns`);
//! `illum 4`/`6`/`7`/`9` → dielectric (`Ni` index of refraction, `Tf` tint).

use super::MeshObject;
use crate::load::materials::{Materials, DEFAULT_IOR};
use std::cell::RefCell;
use std::io::BufReader;
use std::panic::AssertUnwindSafe;
use std::path::Path;
use stratapt_scene::records::{material_kind, Material};

/// Albedo of an MTL material without `Kd` (the MTL default).
pub const DEFAULT_KD: [f32; 3] = [0.8; 3];

/// The objects of the OBJ at `path` (named `file` in the scene); `material` overrides the MTL.
/// Materials from the MTL are added to `materials` as `FILE:NAME`. Errors are reasons.
pub fn load(
    path: &Path,
    file: &str,
    material: Option<u32>,
    materials: &mut Materials,
) -> Result<Vec<MeshObject>, String> {
    // Streamed: the file's text is never held whole (a 4 M-triangle OBJ is 300 MB).
    let opened = std::fs::File::open(path).map_err(|e| format!("cannot read: {e}"))?;
    let mut reader = BufReader::with_capacity(1 << 20, opened);

    // Parse, remembering why an MTL failed (tobj only says "open file failed").
    let obj_dir = path.parent().unwrap_or(Path::new(".")).to_path_buf();
    let mtl_errors = RefCell::new(Vec::new());
    let load_mtl = |mtl: &Path| {
        let full = obj_dir.join(mtl);
        let result = std::fs::read(&full)
            .map_err(|e| e.to_string())
            .and_then(|bytes| normalize_mtl(&String::from_utf8_lossy(&bytes)))
            .map_err(|reason| (reason, tobj::LoadError::OpenFileFailed))
            .and_then(|text| {
                tobj::load_mtl_buf(&mut BufReader::new(text.as_bytes()))
                    .map_err(|e| (e.to_string(), e))
            });
        result.map_err(|(reason, e)| {
            mtl_errors
                .borrow_mut()
                .push(format!("material library `{}`: {reason}", full.display()));
            e
        })
    };
    #[allow(clippy::needless_update)] // tobj's optional features add fields
    let options = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
        ..Default::default()
    };
    // tobj may panic on input it does not expect: report that as a malformed file.
    let parsed = std::panic::catch_unwind(AssertUnwindSafe(|| {
        tobj::load_obj_buf(&mut reader, &options, load_mtl)
    }))
    .map_err(|_| "malformed OBJ or MTL (the parser gave up)".to_string())?;
    let (models, mtl) = parsed.map_err(|e| format!("malformed OBJ: {e}"))?;

    // Materials: the override, or the MTL's, converted and validated.
    let mtl_indices: Vec<u32> = match material {
        Some(_) => Vec::new(),
        None => {
            let mtl = mtl.map_err(|e| {
                let detail = mtl_errors.borrow().join("; ");
                match detail.is_empty() {
                    true => format!("material library: {e}"),
                    false => detail,
                }
            })?;
            mtl.iter()
                .map(|m| {
                    let converted =
                        convert(m).map_err(|r| format!("material `{}`: {r}", m.name))?;
                    Ok(materials.add(format!("{file}:{}", m.name), converted))
                })
                .collect::<Result<_, String>>()?
        }
    };

    let mut objects = Vec::with_capacity(models.len());
    for model in models {
        let mesh = model.mesh;
        let material = match material {
            Some(m) => m,
            None => match mesh.material_id.and_then(|i| mtl_indices.get(i)) {
                Some(&m) => m,
                None => {
                    return Err(format!(
                        "object `{}` has no material (no `usemtl`, or one its MTL lacks); give the shape a `material`",
                        model.name
                    ))
                }
            },
        };
        let normals = (mesh.normals.len() == mesh.positions.len()).then_some(mesh.normals);
        // OBJ's v grows up the image; a texture's v down it (Mitsuba 3 flips it too).
        let uvs = (mesh.texcoords.len() / 2 == mesh.positions.len() / 3
            && !mesh.texcoords.is_empty())
        .then(|| {
            let mut uv = mesh.texcoords;
            uv.iter_mut().skip(1).step_by(2).for_each(|v| *v = 1.0 - *v);
            uv
        });
        let mut indices = mesh.indices;
        indices.truncate(indices.len() / 3 * 3);
        let object = MeshObject::new(mesh.positions, normals, uvs, indices, material)
            .map_err(|reason| format!("object `{}`: {reason}", model.name))?;
        objects.push(object);
    }
    Ok(objects)
}

/// An MTL material as one of ours.
fn convert(m: &tobj::Material) -> std::result::Result<Material, String> {
    let unit = |key: &str, c: [f32; 3]| {
        if c.iter().all(|x| (0.0..=1.0).contains(x)) {
            Ok(c)
        } else {
            Err(format!("`{key}` components must lie in [0, 1], got {c:?}"))
        }
    };
    let emission = m.emissive.unwrap_or([0.0; 3]);
    if !emission.iter().all(|e| e.is_finite() && *e >= 0.0) {
        return Err(format!(
            "`Ke` must be finite and not negative, got {emission:?}"
        ));
    }
    let material = match m.illumination_model {
        Some(3 | 5) => {
            let ns = m.shininess.unwrap_or(f32::INFINITY);
            if ns.is_nan() || ns < 0.0 {
                return Err(format!("`Ns` must not be negative, got {ns}"));
            }
            // Phong exponent → Beckmann-equivalent alpha (Walter et al. 2007).
            let alpha = (2.0 / (ns + 2.0)).sqrt();
            Material {
                tag: material_kind::CONDUCTOR,
                color: unit("Ks", m.specular.unwrap_or([1.0; 3]))?,
                alpha_u: alpha,
                alpha_v: alpha,
                ..Material::default()
            }
        }
        Some(4 | 6 | 7 | 9) => {
            let ior = m.optical_density.unwrap_or(DEFAULT_IOR);
            if !(ior.is_finite() && ior > 0.0) {
                return Err(format!("`Ni` must be positive, got {ior}"));
            }
            Material {
                tag: material_kind::DIELECTRIC,
                color: unit("Tf", transmission_filter(m)?)?,
                ior,
                ..Material::default()
            }
        }
        _ => Material {
            tag: material_kind::DIFFUSE,
            color: unit("Kd", m.diffuse.unwrap_or(DEFAULT_KD))?,
            ..Material::default()
        },
    };
    Ok(Material {
        emission,
        ..material
    })
}

/// `Tf r g b` (or `Tf x`), which tobj leaves unparsed; white when absent.
fn transmission_filter(m: &tobj::Material) -> std::result::Result<[f32; 3], String> {
    let Some(tf) = m.unknown_param.get("Tf") else {
        return Ok([1.0; 3]);
    };
    let v: Vec<f32> = tf
        .split_whitespace()
        .map(str::parse)
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| format!("malformed `Tf {tf}`"))?;
    match v[..] {
        [x] => Ok([x; 3]),
        [r, g, b] => Ok([r, g, b]),
        _ => Err(format!("malformed `Tf {tf}`")),
    }
}

/// MTL text tobj can parse: a colour given as one number (`Kd 0.5`, which the MTL format allows)
/// is written out as three; a colour with two numbers is an error naming its line.
fn normalize_mtl(text: &str) -> std::result::Result<String, String> {
    let mut out = String::with_capacity(text.len());
    for (i, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        match (words.next(), words.clone().count()) {
            (Some(key @ ("Ka" | "Kd" | "Ks" | "Ke")), 1) => {
                let x = words.next().unwrap_or_default();
                out.push_str(&format!("{key} {x} {x} {x}"));
            }
            (Some(key @ ("Ka" | "Kd" | "Ks" | "Ke")), n) if n != 3 => {
                return Err(format!(
                    "line {}: `{key}` needs 1 or 3 numbers, got {n}",
                    i + 1
                ));
            }
            _ => out.push_str(line),
        }
        out.push('\n');
    }
    Ok(out)
}
