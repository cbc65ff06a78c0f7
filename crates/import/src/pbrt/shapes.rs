//! pbrt-v4's shapes as strata's: `trianglemesh`, `bilinearmesh` (each patch two triangles),
//! `loopsubdiv` (its control mesh, with a warning), `plymesh` (read in parallel, each file
//! once), `sphere` and `disk` (analytic where the CTM is a similarity, tessellated otherwise).
//!
//! Meshes are baked into strata's world (pbrt's CTM, then the camera's mirror) in f64 and
//! stored in f32. A triangle's front is pbrt's: the side its vertex normals face when the mesh
//! has them, else its winding's, flipped by `ReverseOrientation`, by a CTM that swaps
//! handedness and by the mirror (pbrt-v4's `Triangle` and `BilinearPatch`). Texture
//! coordinates become strata's (`v` → `1 − v`: pbrt's images are looked up upside down, as
//! Mitsuba's are not).

use super::import::{
    find_numbers, fits_f32, similarity_scale, spanned, Builder, Geom, MeshSource, Placed,
};
use super::params::Params;
use super::parse::ParamType;
use crate::desc::{DiskDesc, MeshData, MeshDesc, MeshStore, RectangleDesc, ShapeDesc, SphereDesc};
use glam::{DMat3, DVec3, Vec3};
use rayon::prelude::*;
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;
use stratapt_scene::error::SceneError;

/// Segments round a tessellated sphere or disk, and rings from pole to pole of a sphere.
const SEGMENTS: usize = 96;
const RINGS: usize = 48;

/// The geometry of a `Shape` directive in object space (`None`: a shape strata does not draw,
/// warned).
pub(super) fn geometry(b: &mut Builder, p: &Params) -> Result<Option<Geom>, SceneError> {
    let mesh = |m: MeshData| Some(Geom::Mesh(MeshSource::Data(Arc::new(m))));
    Ok(match p.kind() {
        "trianglemesh" => mesh(triangle_mesh(p, 3)?),
        "bilinearmesh" => {
            let m = triangle_mesh(p, 4)?;
            match m.indices.len() == 6 && m.normals.is_none() && m.uvs.is_none() {
                true => Some(Geom::Patch(Arc::new(m))),
                false => mesh(m),
            }
        }
        "loopsubdiv" => {
            let levels = p.integer("levels", 3)?;
            let m = triangle_mesh(p, 3)?;
            if levels > 0 {
                b.report.warnings.push(p.warning(format!(
                    "drawn as its control mesh, not subdivided {levels} times"
                )));
            }
            mesh(m)
        }
        "plymesh" => {
            let Some(name) = p.string("filename")? else {
                return Err(p.directive_err("Shape \"plymesh\" needs \"string filename\""));
            };
            let (source, at) = p.location();
            Some(Geom::Mesh(MeshSource::Ply(b.resolve(name), source, at)))
        }
        "sphere" => {
            let radius = positive(p, "radius", 1.0)?;
            let (zmin, zmax) = (p.float("zmin", -radius)?, p.float("zmax", radius)?);
            let phimax = p.float("phimax", 360.0)?;
            if zmin > -radius || zmax < radius || phimax < 360.0 {
                b.report.warnings.push(p.warning(
                    "drawn as a whole sphere (zmin, zmax and phimax cut parts strata does not)",
                ));
            }
            Some(Geom::Sphere { radius })
        }
        "disk" => {
            let radius = positive(p, "radius", 1.0)?;
            let height = p.float("height", 0.0)?;
            let (inner, phimax) = (p.float("innerradius", 0.0)?, p.float("phimax", 360.0)?);
            if inner > 0.0 || phimax < 360.0 {
                b.report.warnings.push(p.warning(
                    "drawn as a whole disk (innerradius and phimax cut parts strata does not)",
                ));
            }
            Some(Geom::Disk { height, radius })
        }
        other => {
            b.report
                .warnings
                .push(p.warning(format!("not drawn: strata has no {other} shape")));
            None
        }
    })
}

/// A positive float parameter.
fn positive(p: &Params, name: &str, default: f64) -> Result<f64, SceneError> {
    let x = p.float(name, default)?;
    if !(x > 0.0 && x.is_finite()) {
        let param = p.find(ParamType::Float, name).expect("read above");
        return Err(p.err(param, format!("{name} {x}: above 0")));
    }
    Ok(x)
}

/// A `trianglemesh` (`corners` 3) or `bilinearmesh` (4: each patch `p00 p10 p01 p11` becomes
/// the triangles `p00 p10 p11` and `p00 p11 p01`) from its parameters.
fn triangle_mesh(p: &Params, corners: usize) -> Result<MeshData, SceneError> {
    let Some((points, param_p)) = find_numbers(p, ParamType::Point3, "P") else {
        return Err(p.directive_err(format!("Shape \"{}\" needs \"point3 P\"", p.kind())));
    };
    let vertices = points.len() / 3;
    let indices: Vec<u32> = match find_numbers(p, ParamType::Integer, "indices") {
        Some((idx, param)) => {
            if idx.is_empty() || idx.len() % corners != 0 {
                return Err(p.err(
                    param,
                    format!("{} indices: a multiple of {corners}", idx.len()),
                ));
            }
            let mut out = Vec::with_capacity(idx.len());
            for &i in idx {
                if !(0.0..vertices as f64).contains(&i) {
                    return Err(p.err(
                        param,
                        format!("index {i} out of range ({vertices} vertices)"),
                    ));
                }
                out.push(i as u32);
            }
            out
        }
        None if vertices == corners => (0..corners as u32).collect(),
        None => {
            return Err(p.directive_err(format!(
                "Shape \"{}\" needs \"integer indices\" ({vertices} vertices)",
                p.kind()
            )))
        }
    };
    if !fits_f32(points) {
        return Err(p.err(param_p, "P holds a number that is not a finite f32"));
    }
    let per_vertex = |ty, name: &str, arity: usize| -> Result<Option<Vec<f32>>, SceneError> {
        let Some((v, param)) = find_numbers(p, ty, name) else {
            return Ok(None);
        };
        if v.len() != vertices * arity {
            return Err(p.err(
                param,
                format!(
                    "{name} has {} values for {vertices} vertices ({arity} each)",
                    v.len()
                ),
            ));
        }
        if v.iter().any(|x| !x.is_finite()) {
            return Err(p.err(param, format!("{name} holds a number that is not finite")));
        }
        Ok(Some(v.iter().map(|&x| x as f32).collect()))
    };
    let normals = per_vertex(ParamType::Normal, "N", 3)?;
    let uvs = match per_vertex(ParamType::Point2, "uv", 2)? {
        Some(uv) => Some(uv),
        None => per_vertex(ParamType::Float, "uv", 2)?,
    };
    // Read, not drawn differently for it: ptex face indices.
    let _ = p.find(ParamType::Integer, "faceIndices");
    let indices = match corners {
        3 => indices,
        _ => indices
            .chunks_exact(4)
            .flat_map(|q| [q[0], q[1], q[3], q[0], q[3], q[2]])
            .collect(),
    };
    Ok(MeshData {
        positions: points.iter().map(|&x| x as f32).collect(),
        normals,
        uvs,
        indices,
    })
}

/// A unit sphere's triangles in pbrt's parametrisation (`u = φ / 2π`, `v = 1 − θ / π`), with
/// outward normals.
fn sphere_mesh(radius: f64) -> MeshData {
    let mut m = MeshData {
        normals: Some(Vec::new()),
        uvs: Some(Vec::new()),
        ..Default::default()
    };
    for ring in 0..=RINGS {
        let theta = std::f64::consts::PI * ring as f64 / RINGS as f64;
        for seg in 0..=SEGMENTS {
            let phi = 2.0 * std::f64::consts::PI * seg as f64 / SEGMENTS as f64;
            let n = DVec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            );
            m.positions
                .extend((n * radius).to_array().map(|x| x as f32));
            m.normals
                .as_mut()
                .unwrap()
                .extend(n.to_array().map(|x| x as f32));
            m.uvs.as_mut().unwrap().extend([
                (seg as f64 / SEGMENTS as f64) as f32,
                (1.0 - ring as f64 / RINGS as f64) as f32,
            ]);
        }
    }
    let at = |ring: usize, seg: usize| (ring * (SEGMENTS + 1) + seg) as u32;
    for ring in 0..RINGS {
        for seg in 0..SEGMENTS {
            let (a, b, c, d) = (
                at(ring, seg),
                at(ring + 1, seg),
                at(ring + 1, seg + 1),
                at(ring, seg + 1),
            );
            m.indices.extend([a, b, c, a, c, d]);
        }
    }
    m
}

/// A disk's triangles (a fan about its centre at `height`, facing +z).
fn disk_mesh(height: f64, radius: f64) -> MeshData {
    let mut m = MeshData {
        positions: vec![0.0, 0.0, height as f32],
        normals: Some(vec![0.0, 0.0, 1.0]),
        ..Default::default()
    };
    for seg in 0..SEGMENTS {
        let phi = 2.0 * std::f64::consts::PI * seg as f64 / SEGMENTS as f64;
        m.positions.extend([
            (radius * phi.cos()) as f32,
            (radius * phi.sin()) as f32,
            height as f32,
        ]);
        m.normals.as_mut().unwrap().extend([0.0, 0.0, 1.0]);
    }
    for seg in 0..SEGMENTS as u32 {
        m.indices
            .extend([0, 1 + seg, 1 + (seg + 1) % SEGMENTS as u32]);
    }
    m
}

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
pub(super) fn bake(
    b: &mut Builder,
    placed: Vec<Placed>,
) -> Result<(Vec<ShapeDesc>, MeshStore), SceneError> {
    // Each PLY file once, in parallel.
    let mut files: Vec<(PathBuf, usize, usize)> = Vec::new();
    let mut seen = std::collections::HashSet::new();
    for s in &placed {
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
                b.parsed.err(
                    *source,
                    *at,
                    format!("plymesh `{}`: {reason}", path.display()),
                )
            })
        })
        .collect();
    let mut plys: HashMap<PathBuf, Arc<MeshData>> = HashMap::new();
    for ((path, _, _), mesh) in files.into_iter().zip(read) {
        plys.insert(path, mesh?);
    }
    b.report.ply_files = plys.len();

    let mirror = b.mirror;
    let triangles: usize = placed
        .iter()
        .map(|s| match &s.geom {
            Geom::Mesh(MeshSource::Data(m)) => m.indices.len() / 3,
            Geom::Mesh(MeshSource::Ply(path, _, _)) => plys[path].indices.len() / 3,
            _ => 0,
        })
        .sum();
    if triangles > super::import::MAX_TRIANGLES {
        return Err(SceneError::new(
            stratapt_scene::SourceLocation::file(&b.parsed.sources.main()),
            format!(
                "{triangles} triangles once instances are flattened: strata takes at most {}",
                super::import::MAX_TRIANGLES
            ),
        ));
    }
    let baked: Vec<Result<Baked, String>> = placed
        .par_iter()
        .map(|s| {
            let full = mirror * s.ctm;
            let object = match &s.geom {
                Geom::Patch(m) => {
                    return bake_mesh(m, s, mirror, false).map(|baked| match baked {
                        Some(baked) => rectangle(m, &baked).unwrap_or(Baked::Mesh(baked)),
                        None => Baked::Empty("the patch has no area once placed".into()),
                    })
                }
                Geom::Mesh(MeshSource::Data(m)) => m.clone(),
                Geom::Mesh(MeshSource::Ply(path, _, _)) => plys[path].clone(),
                Geom::Sphere { radius } => match similarity_scale(&full) {
                    Some(scale) => {
                        let (center, radius) = (full.transform_point3(DVec3::ZERO), radius * scale);
                        return match fits_f32(&[center.x, center.y, center.z, radius]) {
                            true => Ok(Baked::Sphere { center, radius }),
                            false => Err(OUT_OF_RANGE.into()),
                        };
                    }
                    None => Arc::new(sphere_mesh(*radius)),
                },
                Geom::Disk { height, radius } => match similarity_scale(&full) {
                    Some(scale) => {
                        // pbrt-v4's quadrics: the object-space normal +z, flipped by
                        // ReverseOrientation and by a CTM that swaps handedness, then
                        // transformed (so it is the transformed tangents' cross product). The
                        // similarity's normal transform is its rotation.
                        let m3 = DMat3::from_mat4(full) * (1.0 / scale);
                        let sign = if s.reverse ^ swaps_handedness(s) {
                            -1.0
                        } else {
                            1.0
                        };
                        let center = full.transform_point3(DVec3::new(0.0, 0.0, *height));
                        let normal = sign * (m3 * DVec3::Z).normalize();
                        let radius = radius * scale;
                        return match fits_f32(&[center.x, center.y, center.z, radius])
                            && normal.is_finite()
                        {
                            true => Ok(Baked::Disk {
                                center,
                                normal,
                                radius,
                            }),
                            false => Err(OUT_OF_RANGE.into()),
                        };
                    }
                    None => Arc::new(disk_mesh(*height, *radius)),
                },
            };
            let quadric = matches!(s.geom, Geom::Sphere { .. } | Geom::Disk { .. });
            bake_mesh(&object, s, mirror, quadric).map(|m| match m {
                Some(m) => Baked::Mesh(m),
                None => Baked::Empty("every triangle has zero area once placed".into()),
            })
        })
        .collect();

    let mut shapes = Vec::new();
    let mut store = MeshStore::new();
    for (s, baked) in placed.iter().zip(baked) {
        let (source, at) = s.at;
        let baked = baked.map_err(|reason| b.parsed.err(source, at, reason))?;
        let span = b.parsed.span(source, at);
        let material = Some(spanned(span.clone(), s.material.clone()));
        match (&s.geom, similarity_scale(&(mirror * s.ctm))) {
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
        // strata's spheres and disks have their own texture coordinates: in world axes for a
        // sphere (pbrt's turn with the object), (r / R, angle) on a disk (pbrt's (angle, r)).
        if b.textured_materials.contains(&s.material) {
            let turned = similarity_scale(&(mirror * s.ctm)).is_some_and(|scale| {
                let r = DMat3::from_mat4(mirror * s.ctm) * (1.0 / scale);
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
        let v = |x: [f32; 3]| spanned(span.clone(), x.map(|c| c as f64));
        let shape = match baked {
            Baked::Mesh(m) => {
                let name = b.mesh_name(store.len());
                store.insert(name.clone(), m);
                MeshDesc {
                    file: spanned(span.clone(), name),
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
                ..RectangleDesc::default()
            }
            .into_shape(span),
            Baked::Sphere { center, radius } => SphereDesc {
                center: spanned(span.clone(), center.to_array()),
                radius: spanned(span.clone(), radius),
                material,
                ..SphereDesc::default()
            }
            .into_shape(span),
            Baked::Disk {
                center,
                normal,
                radius,
            } => DiskDesc {
                center: spanned(span.clone(), center.to_array()),
                normal: spanned(span.clone(), normal.to_array()),
                radius: spanned(span.clone(), radius),
                material,
                ..DiskDesc::default()
            }
            .into_shape(span),
            Baked::Empty(why) => {
                b.warn(source, at, format!("not drawn: {why}"));
                continue;
            }
        };
        shapes.push(shape);
    }
    Ok((shapes, store))
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
    mirror: glam::DMat4,
    quadric: bool,
) -> Result<Option<MeshData>, String> {
    let full = mirror * s.ctm;
    let normal_matrix = DMat3::from_mat4(full).inverse().transpose();
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
    let normals: Option<Vec<f32>> = m.normals.as_ref().map(|n| {
        n.chunks_exact(3)
            .flat_map(|n| {
                let v = DVec3::new(n[0] as f64, n[1] as f64, n[2] as f64);
                let w = (normal_matrix * v).normalize_or_zero() * sign;
                [w.x as f32, w.y as f32, w.z as f32]
            })
            .collect()
    });
    let uvs = m.uvs.as_ref().map(|uv| {
        uv.chunks_exact(2)
            .flat_map(|c| [c[0], 1.0 - c[1]])
            .collect()
    });
    // Without normals the front is the winding's, flipped by each mirror on the way.
    let flip = s.reverse
        ^ (DMat3::from_mat4(s.ctm).determinant() < 0.0)
        ^ (DMat3::from_mat4(mirror).determinant() < 0.0);
    let at = |i: u32| Vec3::from_slice(&positions[3 * i as usize..][..3]);
    let mut indices = Vec::with_capacity(m.indices.len());
    for t in m.indices.chunks_exact(3) {
        let p = [at(t[0]), at(t[1]), at(t[2])];
        let cross = (p[1] - p[0]).cross(p[2] - p[0]);
        let area2 = cross.length_squared();
        if area2 == 0.0 || area2.is_nan() {
            continue;
        }
        let swap = match &normals {
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
        indices.extend(match swap {
            true => [t[0], t[2], t[1]],
            false => [t[0], t[1], t[2]],
        });
    }
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
