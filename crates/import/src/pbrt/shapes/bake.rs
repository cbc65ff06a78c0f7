//! Placed shapes baked into strata's world: each PLY file read once, in parallel; the
//! triangles counted against strata's limit; each shape placed (pbrt's CTM, then the camera's
//! mirror), in parallel; and the results, in order, as strata's shape descriptions, their
//! meshes and the warnings where strata draws a shape otherwise than pbrt.
//!
//! Meshes are baked in f64 and stored in f32. A triangle's front is pbrt's: the side its
//! vertex normals face when the mesh has them, else its winding's, flipped by
//! `ReverseOrientation`, by a CTM that swaps handedness and by the mirror (pbrt-v4's `Triangle`
//! and `BilinearPatch`). Texture coordinates become strata's (`v` → `1 − v`: pbrt's images are
//! looked up upside down, as Mitsuba's are not).

use super::super::import::{fits_f32, similarity_scale, Builder, Geom, MeshSource, Placed};
use super::super::include::Parsed;
use super::{disk_mesh, sphere_mesh};
use crate::desc::Spanned;
use crate::desc::{DiskDesc, MeshData, MeshDesc, MeshStore, RectangleDesc, ShapeDesc, SphereDesc};
use glam::{DMat3, DMat4, DVec3, Vec3};
use rayon::prelude::*;
use std::collections::{BTreeMap, HashMap};
use std::path::PathBuf;
use std::sync::Arc;
use stratapt_scene::error::SceneError;

/// The PLY files read, by path.
type Plys = HashMap<PathBuf, Arc<MeshData>>;

/// What one placed shape becomes.
enum Baked {
    Mesh(MeshData),
    Rectangle {
        corner: [f32; 3],
        edge_u: [f32; 3],
        edge_v: [f32; 3],
    },
    Sphere {
        center: DVec3,
        radius: f64,
    },
    Disk {
        center: DVec3,
        normal: DVec3,
        radius: f64,
    },
    /// Nothing left to draw, and why.
    Empty(String),
}

/// Every placed shape baked into strata's world, in order: strata's shapes and the meshes they
/// name.
pub(in crate::pbrt) fn bake(
    b: &mut Builder,
    placed: Vec<Placed>,
) -> Result<(Vec<ShapeDesc>, MeshStore), SceneError> {
    let plys = read_plys(b.parsed, &placed)?;
    b.report.ply_files = plys.len();
    check_triangles(b.parsed, &placed, &plys)?;
    let mirror = b.mirror;
    let baked: Vec<Result<Baked, String>> = placed
        .par_iter()
        .map(|s| bake_shape(s, mirror, &plys))
        .collect();
    // In order: each shape's error, its warnings, then its description; the shapes under a
    // singular transform are counted by the directive that made it singular, those it flattens
    // to nothing (`[0]`) dropped, the others (`[1]`) drawn flattened.
    let mut shapes = Vec::new();
    let mut store = MeshStore::new();
    let mut flattened = BTreeMap::new();
    for (s, baked) in placed.iter().zip(baked) {
        let (source, at) = s.at;
        let baked = baked.map_err(|reason| b.parsed.err(source, at, reason))?;
        if let Some(at) = s.flattened_at {
            let empty = matches!(baked, Baked::Empty(_));
            flattened.entry(at).or_insert([0, 0])[!empty as usize] += 1;
            if empty {
                continue;
            }
        }
        warn_quadric(b, s);
        warn_texture_coordinates(b, s);
        if let Some(shape) = describe(b, s, baked, &mut store) {
            shapes.push(shape);
        }
    }
    warn_flattened(b, &flattened);
    Ok((shapes, store))
}

/// One warning per directive that made the transform singular, at it: how many shapes under it
/// it flattened to nothing (not drawn: pbrt-v4 never hits a triangle without area, nor a sphere
/// or disk, which it intersects through the transform's inverse) and how many meshes onto a plane
/// (drawn so, shaded by their faces' normals: their vertex normals' transform, the inverse
/// transpose, does not exist; pbrt-v4's turn NaN, and it falls back to the face's).
fn warn_flattened(b: &mut Builder, flattened: &BTreeMap<(usize, usize), [usize; 2]>) {
    for (&(source, at), &[dropped, drawn]) in flattened {
        let name = b
            .parsed
            .directives
            .iter()
            .find(|(s, d)| *s == source && d.at == at)
            .map_or("the transform", |(_, d)| d.name.as_str());
        let shapes = |n: usize| match n {
            1 => "1 shape".to_string(),
            n => format!("{n} shapes"),
        };
        let mut parts = Vec::new();
        if dropped > 0 {
            parts.push(format!(
                "{} under it left without area, not drawn",
                shapes(dropped)
            ));
        }
        if drawn > 0 {
            parts.push(format!(
                "{} under it drawn flattened, without vertex normals",
                shapes(drawn)
            ));
        }
        let message = format!(
            "{name} makes the transform singular (it flattens space onto a plane, a line or a \
             point): {} (as pbrt-v4 draws them)",
            parts.join("; ")
        );
        b.warn(source, at, message);
    }
}

/// Each PLY file the shapes name, read once, in parallel (the first unreadable one in the
/// shapes' order is the error).
fn read_plys(parsed: &Parsed, placed: &[Placed]) -> Result<Plys, SceneError> {
    let mut files: Vec<(PathBuf, usize, usize)> = Vec::new();
    let mut seen = std::collections::HashSet::new();
    for s in placed {
        if let Geom::Mesh(MeshSource::Ply(path, source, at)) = &s.geom {
            if seen.insert(path.clone()) {
                files.push((path.clone(), *source, *at));
            }
        }
    }
    let read: Vec<Result<Arc<MeshData>, SceneError>> = files
        .par_iter()
        .map(|(path, source, at)| {
            crate::load::read_ply(path).map(Arc::new).map_err(|reason| {
                parsed.err(
                    *source,
                    *at,
                    format!("plymesh `{}`: {reason}", path.display()),
                )
            })
        })
        .collect();
    let mut plys = Plys::new();
    for ((path, _, _), mesh) in files.into_iter().zip(read) {
        plys.insert(path, mesh?);
    }
    Ok(plys)
}

/// An error when the shapes' meshes, instances flattened, hold more triangles than strata
/// takes.
fn check_triangles(parsed: &Parsed, placed: &[Placed], plys: &Plys) -> Result<(), SceneError> {
    let triangles: usize = placed
        .iter()
        .map(|s| match &s.geom {
            Geom::Mesh(MeshSource::Data(m)) => m.indices.len() / 3,
            Geom::Mesh(MeshSource::Ply(path, _, _)) => plys[path].indices.len() / 3,
            _ => 0,
        })
        .sum();
    if triangles > super::super::import::MAX_TRIANGLES {
        return Err(SceneError::new(
            stratapt_scene::SourceLocation::file(parsed.sources.main()),
            format!(
                "{triangles} triangles once instances are flattened: strata takes at most {}",
                super::super::import::MAX_TRIANGLES
            ),
        ));
    }
    Ok(())
}

/// One placed shape in strata's world: a sphere or disk analytic where its transform is a
/// similarity, tessellated otherwise; a patch a rectangle where it is one; else a mesh.
fn bake_shape(s: &Placed, mirror: DMat4, plys: &Plys) -> Result<Baked, String> {
    let full = mirror * s.ctm;
    // pbrt-v4 intersects a sphere or disk in its object space, through the inverse of its
    // transform: a singular one has none (NaN), and no ray ever hits the quadric.
    let quadric = matches!(s.geom, Geom::Sphere { .. } | Geom::Disk { .. });
    if quadric && s.flattened_at.is_some() {
        return Ok(Baked::Empty(
            "a sphere or disk under a singular transform".into(),
        ));
    }
    let object = match &s.geom {
        Geom::Patch(m) => return bake_patch(m, s, mirror),
        Geom::Mesh(MeshSource::Data(m)) => m.clone(),
        Geom::Mesh(MeshSource::Ply(path, _, _)) => plys[path].clone(),
        Geom::Sphere { radius } => match similarity_scale(&full) {
            Some(scale) => return analytic_sphere(full, *radius, scale),
            None => Arc::new(sphere_mesh(*radius)),
        },
        Geom::Disk { height, radius } => match similarity_scale(&full) {
            Some(scale) => return analytic_disk(s, full, *height, *radius, scale),
            None => Arc::new(disk_mesh(*height, *radius)),
        },
    };
    bake_mesh(&object, s, mirror, quadric).map(|m| match m {
        Some(m) => Baked::Mesh(m),
        None => Baked::Empty("every triangle has zero area once placed".into()),
    })
}

/// A bilinear patch in strata's world: a rectangle where it is one, else its triangles.
fn bake_patch(m: &MeshData, s: &Placed, mirror: DMat4) -> Result<Baked, String> {
    bake_mesh(m, s, mirror, false).map(|baked| match baked {
        Some(baked) => rectangle(m, &baked).unwrap_or(Baked::Mesh(baked)),
        None => Baked::Empty("the patch has no area once placed".into()),
    })
}

/// A sphere of `radius` under `full`, a similarity of scale `scale`, as strata's sphere.
fn analytic_sphere(full: DMat4, radius: f64, scale: f64) -> Result<Baked, String> {
    let (center, radius) = (full.transform_point3(DVec3::ZERO), radius * scale);
    match fits_f32(&[center.x, center.y, center.z, radius]) {
        true => Ok(Baked::Sphere { center, radius }),
        false => Err(OUT_OF_RANGE.into()),
    }
}

/// A disk at `height` of `radius` under `full`, a similarity of scale `scale`, as strata's
/// disk.
fn analytic_disk(
    s: &Placed,
    full: DMat4,
    height: f64,
    radius: f64,
    scale: f64,
) -> Result<Baked, String> {
    // pbrt-v4's quadrics: the object-space normal +z, flipped by ReverseOrientation and by a
    // CTM that swaps handedness, then transformed (so it is the transformed tangents' cross
    // product). The similarity's normal transform is its rotation.
    let m3 = DMat3::from_mat4(full) * (1.0 / scale);
    let sign = if s.reverse ^ swaps_handedness(s) {
        -1.0
    } else {
        1.0
    };
    let center = full.transform_point3(DVec3::new(0.0, 0.0, height));
    let normal = sign * (m3 * DVec3::Z).normalize();
    let radius = radius * scale;
    match fits_f32(&[center.x, center.y, center.z, radius]) && normal.is_finite() {
        true => Ok(Baked::Disk {
            center,
            normal,
            radius,
        }),
        false => Err(OUT_OF_RANGE.into()),
    }
}

/// Warnings where strata draws a sphere or disk otherwise than pbrt: tessellated (its
/// transform no similarity), or a sphere facing in.
fn warn_quadric(b: &mut Builder, s: &Placed) {
    let (source, at) = s.at;
    match (&s.geom, similarity_scale(&(b.mirror * s.ctm))) {
        (Geom::Sphere { .. } | Geom::Disk { .. }, None) => b.warn(
            source,
            at,
            "tessellated: its transform is not a rotation and uniform scale, which \
             strata's analytic shapes need",
        ),
        (Geom::Sphere { .. }, Some(_)) if s.reverse ^ swaps_handedness(s) => b.warn(
            source,
            at,
            "faces inwards in pbrt (ReverseOrientation, or a transform that swaps \
             handedness): strata's spheres face out (glass inside) and emit from both sides",
        ),
        _ => {}
    }
}

/// Warnings where a textured sphere or disk has other texture coordinates in strata: in world
/// axes for a sphere (pbrt's turn with the object), (r / R, angle) on a disk (pbrt's
/// (angle, r)).
fn warn_texture_coordinates(b: &mut Builder, s: &Placed) {
    if !b.textured_materials.contains(&s.material) {
        return;
    }
    let (source, at) = s.at;
    let full = b.mirror * s.ctm;
    let turned = similarity_scale(&full).is_some_and(|scale| {
        let r = DMat3::from_mat4(full) * (1.0 / scale);
        !(r - DMat3::IDENTITY)
            .to_cols_array()
            .iter()
            .all(|x| x.abs() < 1e-9)
    });
    match &s.geom {
        Geom::Sphere { .. } if turned => b.warn(
            source,
            at,
            "a textured sphere that is turned or mirrored: strata lays its texture \
             in world axes, pbrt in the sphere's own",
        ),
        Geom::Disk { .. } => b.warn(
            source,
            at,
            "a textured disk: strata's texture coordinates on a disk are (r / R, \
             angle), pbrt's (angle, r)",
        ),
        _ => {}
    }
}

/// A baked shape as strata's shape description, its mesh added to `store` (`None`: nothing to
/// draw, warned).
fn describe(b: &mut Builder, s: &Placed, baked: Baked, store: &mut MeshStore) -> Option<ShapeDesc> {
    let (source, at) = s.at;
    let span = b.parsed.span(source, at);
    let material = Some(Spanned::new(span.clone(), s.material.clone()));
    let two_sided = s.two_sided.then(|| Spanned::new(span.clone(), true));
    let v = |x: [f32; 3]| Spanned::new(span.clone(), x.map(|c| c as f64));
    let alpha = s.alpha.clone().map(|a| Spanned::new(span.clone(), a));
    let mut shape = match baked {
        Baked::Mesh(m) => {
            let name = b.mesh_name(store.len());
            store.insert(name.clone(), m);
            MeshDesc {
                file: Spanned::new(span.clone(), name),
                material,
                ..MeshDesc::default()
            }
            .into_shape(span)
        }
        Baked::Rectangle {
            corner,
            edge_u,
            edge_v,
        } => RectangleDesc {
            corner: v(corner),
            edge_u: v(edge_u),
            edge_v: v(edge_v),
            material,
            two_sided,
            ..RectangleDesc::default()
        }
        .into_shape(span),
        Baked::Sphere { center, radius } => SphereDesc {
            center: Spanned::new(span.clone(), center.to_array()),
            radius: Spanned::new(span.clone(), radius),
            material,
            ..SphereDesc::default()
        }
        .into_shape(span),
        Baked::Disk {
            center,
            normal,
            radius,
        } => DiskDesc {
            center: Spanned::new(span.clone(), center.to_array()),
            normal: Spanned::new(span.clone(), normal.to_array()),
            radius: Spanned::new(span.clone(), radius),
            material,
            two_sided,
            ..DiskDesc::default()
        }
        .into_shape(span),
        Baked::Empty(why) => {
            b.warn(source, at, format!("not drawn: {why}"));
            return None;
        }
    };
    shape.common.alpha = alpha;
    Some(shape)
}

/// The reason a shape's numbers leave f32's range once placed.
const OUT_OF_RANGE: &str = "its numbers leave f32's range once placed";

/// Whether the shape's CTM swaps handedness (negative determinant).
fn swaps_handedness(s: &Placed) -> bool {
    DMat3::from_mat4(s.ctm).determinant() < 0.0
}

/// A bilinear patch `object` (its corners `p00 p10 p01 p11` in order), `baked` into the world,
/// as strata's rectangle if it is one there: `p11 = p10 + p01 − p00` to a millionth of its
/// size, edges perpendicular as strata's rectangles must be, and facing the side its baked
/// triangles face.
fn rectangle(object: &MeshData, baked: &MeshData) -> Option<Baked> {
    if object.indices.len() != 6 || baked.indices.len() != 6 {
        return None;
    }
    let p = |i: u32| Vec3::from_slice(&baked.positions[3 * i as usize..][..3]);
    // The patch's corners from its triangles `p00 p10 p11`, `p00 p11 p01`.
    let o = &object.indices;
    let (p00, p10, p01, p11) = (p(o[0]), p(o[1]), p(o[5]), p(o[2]));
    let (u, v) = (p10 - p00, p01 - p00);
    let size = u.length() + v.length();
    if (p11 - (p10 + v)).length() > 1e-6 * size
        || u.dot(v).abs() > crate::load::PERP_TOLERANCE * u.length() * v.length()
    {
        return None;
    }
    let t = &baked.indices[..3];
    let front = (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0]));
    let (u, v) = match u.cross(v).dot(front) >= 0.0 {
        true => (u, v),
        false => (v, u),
    };
    Some(Baked::Rectangle {
        corner: p00.to_array(),
        edge_u: u.to_array(),
        edge_v: v.to_array(),
    })
}

/// An object-space mesh in strata's world (`None` when no triangle has area there).
fn bake_mesh(
    m: &MeshData,
    s: &Placed,
    mirror: DMat4,
    quadric: bool,
) -> Result<Option<MeshData>, String> {
    let full = mirror * s.ctm;
    // Normals transform by the inverse transpose; a singular transform has none, so its faces
    // are shaded flat (pbrt-v4's normals turn NaN there, and it shades by the face's).
    let linear = DMat3::from_mat4(full);
    let normal_matrix = (linear.determinant() != 0.0).then(|| linear.inverse().transpose());
    let positions: Vec<f32> = m
        .positions
        .chunks_exact(3)
        .flat_map(|p| {
            let w = full.transform_point3(DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64));
            [w.x as f32, w.y as f32, w.z as f32]
        })
        .collect();
    if let Some(i) = positions.iter().position(|x| !x.is_finite()) {
        return Err(format!(
            "vertex {} is not a finite f32 once transformed",
            i / 3 + 1
        ));
    }
    // A tessellated sphere or disk keeps pbrt's quadric rule (its normals flip with a CTM that
    // swaps handedness); a mesh's normals do not.
    let flip_normals = s.reverse ^ (quadric && swaps_handedness(s));
    let sign = if flip_normals { -1.0 } else { 1.0 };
    let normals = match (&m.normals, normal_matrix) {
        (Some(n), Some(normal_matrix)) => Some(transform_normals(n, normal_matrix, sign)),
        _ => None,
    };
    let uvs = m.uvs.as_ref().map(|uv| {
        uv.chunks_exact(2)
            .flat_map(|c| [c[0], 1.0 - c[1]])
            .collect()
    });
    // Without normals the front is the winding's, flipped by each mirror on the way.
    let flip = s.reverse
        ^ (DMat3::from_mat4(s.ctm).determinant() < 0.0)
        ^ (DMat3::from_mat4(mirror).determinant() < 0.0);
    let indices = front_triangles(&m.indices, &positions, normals.as_deref(), flip);
    if indices.is_empty() {
        return Ok(None);
    }
    Ok(Some(MeshData {
        positions,
        normals,
        uvs,
        indices,
    }))
}

/// Unit normals `n` (`xyz` after `xyz`) transformed by `normal_matrix` and multiplied by `sign`
/// (zero where one has no direction left).
fn transform_normals(n: &[f32], normal_matrix: DMat3, sign: f64) -> Vec<f32> {
    n.chunks_exact(3)
        .flat_map(|n| {
            let v = DVec3::new(n[0] as f64, n[1] as f64, n[2] as f64);
            let w = (normal_matrix * v).normalize_or_zero() * sign;
            [w.x as f32, w.y as f32, w.z as f32]
        })
        .collect()
}

/// The triangles of `indices` with area at `positions`, each wound so that its front is pbrt's:
/// the side its vertex `normals` face, else (or where they are edge-on) its winding's, swapped
/// where `flip`.
fn front_triangles(
    indices: &[u32],
    positions: &[f32],
    normals: Option<&[f32]>,
    flip: bool,
) -> Vec<u32> {
    let at = |i: u32| Vec3::from_slice(&positions[3 * i as usize..][..3]);
    let mut out = Vec::with_capacity(indices.len());
    for t in indices.chunks_exact(3) {
        let p = [at(t[0]), at(t[1]), at(t[2])];
        let cross = (p[1] - p[0]).cross(p[2] - p[0]);
        let area2 = cross.length_squared();
        if area2 == 0.0 || area2.is_nan() {
            continue;
        }
        let swap = match normals {
            Some(n) => {
                let sum: Vec3 = t
                    .iter()
                    .map(|&i| Vec3::from_slice(&n[3 * i as usize..][..3]))
                    .sum();
                match sum.dot(cross) {
                    d if d < 0.0 => true,
                    d if d > 0.0 => false,
                    _ => flip,
                }
            }
            None => flip,
        };
        out.extend(match swap {
            true => [t[0], t[2], t[1]],
            false => [t[0], t[1], t[2]],
        });
    }
    out
}
