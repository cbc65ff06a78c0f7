//! pbrt-v4's shapes as strata's: `trianglemesh`, `bilinearmesh` (each patch two triangles),
//! `loopsubdiv` (subdivided at load as pbrt-v4 does, by [`loop_subdiv`](mod@loop_subdiv)),
//! `plymesh` (read in parallel, each file once), `sphere` and `disk` (analytic where the CTM is
//! a similarity, tessellated otherwise).
//!
//! Shapes read here are in object space; [`bake`](mod@bake) places them in strata's world
//! (pbrt's CTM, then the camera's mirror).

mod bake;
mod loop_subdiv;

pub(super) use bake::bake;

use super::import::{find_numbers, fits_f32, Builder, Geom, MeshSource};
use super::params::Params;
use super::parse::ParamType;
use crate::desc::MeshData;
use glam::DVec3;
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
        "loopsubdiv" => mesh(loop_subdiv::shape(b, p)?),
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
    let (positions, indices) = points_and_indices(p, corners)?;
    let vertices = positions.len() / 3;
    let normals = per_vertex(p, vertices, ParamType::Normal, "N", 3)?;
    let uvs = match per_vertex(p, vertices, ParamType::Point2, "uv", 2)? {
        Some(uv) => Some(uv),
        None => per_vertex(p, vertices, ParamType::Float, "uv", 2)?,
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
        positions,
        normals,
        uvs,
        indices,
    })
}

/// A mesh's `point3 P` (as f32, `xyz` after `xyz`) and `integer indices` (`corners` to a face;
/// when there are none, `corners` points make one face).
fn points_and_indices(p: &Params, corners: usize) -> Result<(Vec<f32>, Vec<u32>), SceneError> {
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
    Ok((points.iter().map(|&x| x as f32).collect(), indices))
}

/// The per-vertex parameter `name` of type `ty` (`arity` finite numbers for each of `vertices`),
/// as f32; `None` when the shape has none.
fn per_vertex(
    p: &Params,
    vertices: usize,
    ty: ParamType,
    name: &str,
    arity: usize,
) -> Result<Option<Vec<f32>>, SceneError> {
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
