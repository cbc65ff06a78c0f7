//! pbrt-v4's `Shape "loopsubdiv"`, subdivided once, at load, as pbrt-v4's `LoopSubdivide`
//! does (`src/pbrt/util/loopsubdiv.cpp`; Loop's rules, "Smooth Subdivision Surfaces Based on
//! Triangles", 1987, as Physically Based Rendering, 3rd edition, section 3.8 gives them): the
//! control mesh refined `levels` times (each triangle into four: even vertices moved by the
//! one-ring rule with Warren's β, or the boundary rule 1/8, 3/4, 1/8; one odd vertex per edge,
//! 3/8, 3/8, 1/8, 1/8 inside and 1/2, 1/2 on the boundary), then every vertex pushed to its
//! limit position (weight γ(n) = 1 / (n + 3 / (8 β)) on each neighbour inside; 1/5, 3/5, 1/5 on
//! the boundary, pbrt's weights) and given the limit surface's normal, `S × T` of pbrt's
//! tangents. No uv: pbrt-v4 gives the subdivided mesh none. `levels` 0 still moves the control
//! vertices to the limit surface, as pbrt-v4 does. pbrt's boundary limit weights are not the
//! limit of its boundary rules (the cubic B-spline's, 1/6, 2/3, 1/6): kept, as pbrt's.
//!
//! The mesh is held as pbrt's `SDFace` and `SDVertex` hold it, in arrays ([`level`]): per face
//! its corners and the face across each edge, per vertex one face around it and whether it is
//! on the boundary; Loop's weights and pbrt's tangents are in [`rules`]. Vertices are numbered
//! as pbrt numbers them (a vertex keeps its number through the levels, the new edge vertices
//! follow), and the normals are pbrt's to the sign: they face away from the side a triangle
//! winds counter-clockwise (a closed mesh wound counter-clockwise seen from outside, as the
//! killeroo is, gets inward normals), and strata, as pbrt, takes a triangle's front from its
//! vertex normals. Arithmetic is f64 where pbrt's is f32.

use super::super::import::{Builder, MAX_TRIANGLES};
use super::super::params::Params;
use super::super::parse::ParamType;
use super::points_and_indices;
use crate::desc::MeshData;
use glam::DVec3;
use level::Level;
use rules::{boundary_tangents, interior_tangents, loop_gamma, weigh_boundary, weigh_ring};
use std::fmt;
use stratapt_scene::error::SceneError;

mod level;
mod rules;
#[cfg(test)]
mod tests;

/// The mesh a `Shape "loopsubdiv"` draws: `P` and `indices` subdivided `integer levels` times
/// (pbrt-v4's default 3). Where pbrt-v4's subdivision has no answer for the control mesh (see
/// [`Unsupported`]) the control mesh itself is drawn, warned: pbrt-v4 crashes or loops on such
/// a mesh, so there is no picture of pbrt's to be faithful to; the triangles are a valid mesh,
/// an error would lose the whole scene to one shape, and the warning names the vertices to fix.
pub(super) fn shape(b: &mut Builder, p: &Params) -> Result<MeshData, SceneError> {
    let levels = levels(p)?;
    // pbrt-v4 reads `scheme` and subdivides by Loop's rules whatever it names.
    let _ = p.find(ParamType::String, "scheme");
    let (positions, indices) = points_and_indices(p, 3)?;
    check_size(p, indices.len() / 3, levels)?;
    let points: Vec<DVec3> = positions
        .chunks_exact(3)
        .map(|c| DVec3::new(c[0] as f64, c[1] as f64, c[2] as f64))
        .collect();
    let triangles: Vec<[u32; 3]> = indices
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .collect();
    match subdivide(&points, &triangles, levels) {
        Ok(s) => Ok(s.into_mesh()),
        Err(why) => {
            b.report
                .warnings
                .push(p.warning(format!("drawn as its control mesh, not subdivided: {why}")));
            Ok(MeshData {
                positions,
                indices,
                ..Default::default()
            })
        }
    }
}

/// `integer levels`, 3 when not given; an error below 0 (where pbrt-v4 would subdivide 0 times).
fn levels(p: &Params) -> Result<u32, SceneError> {
    let levels = p.integer("levels", 3)?;
    if levels < 0 {
        let param = p.find(ParamType::Integer, "levels").expect("read above");
        return Err(p.err(param, format!("levels {levels}: 0 or more")));
    }
    Ok(levels.min(u32::MAX as i64) as u32)
}

/// An error, at `levels` (or the directive when it has none), when `triangles` subdivided
/// `levels` times (4 for 1 each time) would make more triangles than strata takes.
fn check_size(p: &Params, triangles: usize, levels: u32) -> Result<(), SceneError> {
    let made = 4usize
        .checked_pow(levels)
        .and_then(|f| f.checked_mul(triangles));
    if made.is_some_and(|n| n <= MAX_TRIANGLES) {
        return Ok(());
    }
    let made = made.map_or("more than 2⁶⁴".to_string(), |n| n.to_string());
    let reason = format!(
        "levels {levels}: {triangles} triangles subdivided {levels} times make {made}; \
         strata takes at most {MAX_TRIANGLES}"
    );
    Err(match p.find(ParamType::Integer, "levels") {
        Some(param) => p.err(param, reason),
        None => p.directive_err(reason),
    })
}

/// Why a control mesh cannot be subdivided: meshes on which pbrt-v4's `LoopSubdivide` has no
/// answer (it crashes or walks in circles). Vertices are numbered as in the control mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Unsupported {
    /// An edge of more than two triangles.
    SharedEdge(u32, u32),
    /// Two triangles that both run from the first vertex to the second (wound opposite ways).
    Winding(u32, u32),
    /// A vertex whose triangles make more than one fan (they touch there but share no edge).
    Pinched(u32),
}

impl fmt::Display for Unsupported {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        match self {
            Self::SharedEdge(a, b) => write!(
                f,
                "the edge between vertices {a} and {b} belongs to more than two triangles"
            ),
            Self::Winding(a, b) => write!(
                f,
                "two triangles run from vertex {a} to vertex {b} (their windings disagree)"
            ),
            Self::Pinched(v) => write!(
                f,
                "triangles meet at vertex {v} without sharing an edge there"
            ),
        }
    }
}

/// A subdivided mesh on its limit surface.
#[derive(Clone, Debug, Default)]
pub(super) struct Subdivided {
    pub positions: Vec<DVec3>,
    /// Unit, or zero where the limit surface has no tangent plane pbrt's tangents find.
    pub normals: Vec<DVec3>,
    pub triangles: Vec<[u32; 3]>,
}

impl Subdivided {
    /// As a mesh (f32; normals, no uv).
    fn into_mesh(self) -> MeshData {
        let f32s = |v: Vec<DVec3>| v.iter().flat_map(|x| x.as_vec3().to_array()).collect();
        MeshData {
            positions: f32s(self.positions),
            normals: Some(f32s(self.normals)),
            uvs: None,
            indices: self.triangles.into_flattened(),
        }
    }
}

/// `triangles` over `points` subdivided `levels` times and pushed to the limit surface.
/// Triangles that repeat a corner (no area, no edge to share) and points no triangle uses are
/// left out; the rest keep their order.
pub(super) fn subdivide(
    points: &[DVec3],
    triangles: &[[u32; 3]],
    levels: u32,
) -> Result<Subdivided, Unsupported> {
    let mut mesh = Level::new(points, triangles)?;
    for _ in 0..levels {
        mesh = mesh.refine();
    }
    let positions = limit_positions(&mesh);
    let normals = limit_normals(&mesh, &positions);
    Ok(Subdivided {
        positions,
        normals,
        triangles: mesh.faces,
    })
}

/// Every vertex on the limit surface: inside, weight γ(n) on each neighbour; on the
/// boundary, 3/5 p + 1/5 of each boundary neighbour (pbrt's rule).
fn limit_positions(mesh: &Level) -> Vec<DVec3> {
    let mut ring = Vec::new();
    (0..mesh.p.len() as u32)
        .map(|v| {
            mesh.ring(v, &mut ring);
            match mesh.boundary[v as usize] {
                true => weigh_boundary(&mesh.p, v, &ring, 1.0 / 5.0),
                false => weigh_ring(&mesh.p, v, &ring, loop_gamma(ring.len())),
            }
        })
        .collect()
}

/// The limit surface's unit normal at each vertex, `S × T` of pbrt's tangents taken over the
/// limit positions `p`; zero where they are parallel.
fn limit_normals(mesh: &Level, p: &[DVec3]) -> Vec<DVec3> {
    let (mut ring, mut d) = (Vec::new(), Vec::new());
    (0..mesh.p.len() as u32)
        .map(|v| {
            mesh.ring(v, &mut ring);
            // Each tangent weighs the ring by weights that sum to 0: taken relative to the
            // vertex, for precision far from the origin.
            d.clear();
            d.extend(ring.iter().map(|&r| p[r as usize] - p[v as usize]));
            let (s, t) = match mesh.boundary[v as usize] {
                true => boundary_tangents(&d),
                false => interior_tangents(&d),
            };
            s.cross(t).normalize_or_zero()
        })
        .collect()
}
