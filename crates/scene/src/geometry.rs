//! The scene's primitives as both renderers read them: indexed points (a mesh's vertices are
//! stored once, whatever number of triangles share them) and a small table of surfaces that
//! primitives share.
//!
//! The arrays are laid out as the GPU reads them, so they upload as they are: a primitive is
//! one 16-byte word of three point indices and its surface, a point 16 bytes (`xyz`, `w`
//! unused), so that a triangle is fetched in four aligned loads. Per triangle of a closed mesh
//! (about half a vertex per triangle) that is 16 bytes of primitive, 8 of points and, when
//! smooth, 6 of shading normals: about 30 bytes, where a self-contained primitive took 64 and
//! its shading normals 48 more. Ten million triangles fit bindings of 128 MiB: the points in
//! one, the primitives in two.

use crate::records::{prim_kind, surface_flag, Surface, NONE, STATIC_TRIANGLE};
use glam::Vec3;
use std::collections::HashMap;

/// The primitives of a scene, indexed; see the module documentation.
#[derive(Clone, Debug, Default)]
pub struct Geometry {
    /// Triangle vertices, and the parameters of spheres and disks (see [`prim_kind`]); `w` is 0.
    pub points: Vec<[f32; 4]>,
    /// Shading normal of each point, parallel to `points`; empty when no surface is smooth.
    /// Zero for points that have none (they belong to flat surfaces).
    pub normals: Vec<[f32; 3]>,
    /// Texture coordinates `(u, v)` of each point, parallel to `points`; empty when no surface
    /// has any. Zero for points that have none.
    pub uvs: Vec<[f32; 2]>,
    /// Per primitive, in BVH leaf order once loaded: three indices into `points`, and the index
    /// into `surfaces`, with [`STATIC_TRIANGLE`] set for triangles that do not move.
    pub prims: Vec<[u32; 4]>,
    pub surfaces: Vec<Surface>,
    /// Surfaces without a light, by value, so that primitives share them.
    shared: HashMap<Surface, u32>,
}

/// A primitive's alpha: opaque, a constant, or a texture's index.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Alpha {
    #[default]
    Opaque,
    Constant(f32),
    Texture(u32),
}

impl Alpha {
    /// The alpha of a surface.
    pub fn of(s: &Surface) -> Self {
        match (
            s.flags & surface_flag::ALPHA != 0,
            s.flags & surface_flag::ALPHA_TEXTURE != 0,
        ) {
            (false, _) => Alpha::Opaque,
            (true, false) => Alpha::Constant(f32::from_bits(s.alpha)),
            (true, true) => Alpha::Texture(s.alpha),
        }
    }

    /// Its [`surface_flag`]s and [`Surface::alpha`] word.
    pub fn encode(self) -> (u32, u32) {
        match self {
            Alpha::Opaque => (0, 0),
            Alpha::Constant(a) => (surface_flag::ALPHA, a.to_bits()),
            Alpha::Texture(i) => (surface_flag::ALPHA | surface_flag::ALPHA_TEXTURE, i),
        }
    }
}

/// One primitive with its points and surface gathered: how the renderers' scalar code and the
/// tests see a primitive. Not stored.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Prim {
    pub a: [f32; 3],
    pub b: [f32; 3],
    pub c: [f32; 3],
    /// One of [`prim_kind`].
    pub kind: u32,
    pub material: u32,
    /// Index into [`crate::FlatScene::lights`] when the primitive emits, else [`NONE`].
    pub light: u32,
    /// Index into [`crate::FlatScene::motions`], or [`NONE`] for static primitives.
    pub motion: u32,
    /// Its alpha ([`surface_flag::ALPHA`]).
    pub alpha: Alpha,
    /// Smooth triangles: the shading normals at `a`, `b`, `c`.
    pub normals: Option<[[f32; 3]; 3]>,
    /// Triangles with texture coordinates: the `(u, v)` at `a`, `b`, `c`.
    pub uvs: Option<[[f32; 2]; 3]>,
    /// The material reads a texture ([`surface_flag::TEXTURED`]): hits need texture coordinates.
    pub textured: bool,
}

impl Geometry {
    /// A geometry holding `prims` in order, each with its own points.
    pub fn from_prims<'a>(prims: impl IntoIterator<Item = &'a Prim>) -> Self {
        let mut out = Self::default();
        for prim in prims {
            out.push(prim);
        }
        out
    }

    /// Primitives.
    pub fn len(&self) -> usize {
        self.prims.len()
    }

    pub fn is_empty(&self) -> bool {
        self.prims.is_empty()
    }

    /// Primitive `id`, gathered.
    #[inline]
    pub fn prim(&self, id: u32) -> Prim {
        let [v0, v1, v2, _] = self.prims[id as usize];
        let v = [v0, v1, v2];
        let s = self.surface(id);
        let [a, b, c] = v.map(|i| xyz(self.points[i as usize]));
        Prim {
            a,
            b,
            c,
            kind: s.kind,
            material: s.material,
            light: s.light,
            motion: s.motion,
            alpha: Alpha::of(s),
            normals: (s.flags & surface_flag::SHADING_NORMALS != 0)
                .then(|| v.map(|i| self.normals[i as usize])),
            uvs: (s.flags & surface_flag::UV != 0).then(|| v.map(|i| self.uvs[i as usize])),
            textured: s.flags & surface_flag::TEXTURED != 0,
        }
    }

    /// The surface of primitive `id`.
    #[inline]
    pub fn surface(&self, id: u32) -> &Surface {
        &self.surfaces[(self.prims[id as usize][3] & !STATIC_TRIANGLE) as usize]
    }

    /// The vertices of primitive `id` (for a triangle; the raw points otherwise).
    #[inline]
    pub fn vertices(&self, id: u32) -> [Vec3; 3] {
        let [v0, v1, v2, _] = self.prims[id as usize];
        [v0, v1, v2].map(|i| Vec3::from_slice(&self.points[i as usize][..3]))
    }

    /// Every primitive, gathered, in order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = Prim> + '_ {
        (0..self.len() as u32).map(|id| self.prim(id))
    }

    /// Append `points` (with their shading normals, or none) and return the index of the first.
    pub fn add_points(&mut self, points: &[[f32; 3]], normals: Option<&[[f32; 3]]>) -> u32 {
        self.add_points_uv(points, normals, None)
    }

    /// [`Geometry::add_points`] with texture coordinates (or none).
    pub fn add_points_uv(
        &mut self,
        points: &[[f32; 3]],
        normals: Option<&[[f32; 3]]>,
        uvs: Option<&[[f32; 2]]>,
    ) -> u32 {
        let first = self.points.len();
        self.points
            .extend(points.iter().map(|&[x, y, z]| [x, y, z, 0.0]));
        let end = self.points.len();
        extend_parallel(&mut self.normals, first, end, normals);
        extend_parallel(&mut self.uvs, first, end, uvs);
        first as u32
    }

    /// Append a primitive over points `v` (indices into `points`) with `surface`.
    pub fn push_indexed(&mut self, v: [u32; 3], surface: Surface) {
        let mut word = self.surface_id(surface);
        let cut = surface.flags & surface_flag::ALPHA != 0;
        if surface.kind == prim_kind::TRIANGLE && surface.motion == NONE && !cut {
            word |= STATIC_TRIANGLE;
        }
        self.prims.push([v[0], v[1], v[2], word]);
    }

    /// Append `prim` with its own points.
    pub fn push(&mut self, prim: &Prim) {
        let points = [prim.a, prim.b, prim.c];
        let first = self.add_points_uv(
            &points,
            prim.normals.as_ref().map(|n| &n[..]),
            prim.uvs.as_ref().map(|uv| &uv[..]),
        );
        let flag = |on: bool, flag: u32| if on { flag } else { 0 };
        let (alpha_flags, alpha) = prim.alpha.encode();
        let surface = Surface {
            kind: prim.kind,
            material: prim.material,
            light: prim.light,
            motion: prim.motion,
            flags: flag(prim.normals.is_some(), surface_flag::SHADING_NORMALS)
                | flag(prim.uvs.is_some(), surface_flag::UV)
                | flag(prim.textured, surface_flag::TEXTURED)
                | alpha_flags,
            alpha,
        };
        self.push_indexed([first, first + 1, first + 2], surface);
    }

    /// The index of `surface` in `surfaces`: a shared one when it has no light, else new.
    fn surface_id(&mut self, surface: Surface) -> u32 {
        assert!(
            self.surfaces.len() < STATIC_TRIANGLE as usize,
            "2³¹ surfaces"
        );
        if surface.light != NONE {
            self.surfaces.push(surface);
            return self.surfaces.len() as u32 - 1;
        }
        *self.shared.entry(surface).or_insert_with(|| {
            self.surfaces.push(surface);
            self.surfaces.len() as u32 - 1
        })
    }

    /// Add `offset` to every light index (the loader puts other lights first).
    pub fn offset_lights(&mut self, offset: u32) {
        // Shared surfaces have no light, so the index of them stays valid.
        for s in &mut self.surfaces {
            if s.light != NONE {
                s.light += offset;
            }
        }
    }

    /// Put the primitives in `order` (primitive `order[i]` becomes `i`); points stay.
    pub fn reorder(&mut self, order: &[u32]) {
        self.prims = order.iter().map(|&i| self.prims[i as usize]).collect();
    }

    /// Whether every point and normal is finite from `points[first..]` on.
    pub fn finite_from(&self, first: usize) -> bool {
        let points = self.points[first..].iter().flatten();
        let normals = self.normals.get(first..).unwrap_or(&[]).iter().flatten();
        let uvs = self.uvs.get(first..).unwrap_or(&[]).iter().flatten();
        points.chain(normals).chain(uvs).all(|x| x.is_finite())
    }

    /// Whether primitive `id` is a triangle placed once for the whole shutter.
    #[inline]
    pub fn is_static_triangle(&self, id: u32) -> bool {
        self.prims[id as usize][3] & STATIC_TRIANGLE != 0
    }
}

/// Extend `column`, an array parallel to the points (empty while no point has a value), over
/// the points `first..end` just added: with `values`, padding the points before them with zeros;
/// without, with zeros, unless the column is still empty.
fn extend_parallel<T: Copy + Default>(
    column: &mut Vec<T>,
    first: usize,
    end: usize,
    values: Option<&[T]>,
) {
    match values {
        Some(v) => {
            debug_assert_eq!(v.len(), end - first);
            column.resize(first, T::default());
            column.extend_from_slice(v);
        }
        None if !column.is_empty() => column.resize(end, T::default()),
        None => {}
    }
}

fn xyz([x, y, z, _]: [f32; 4]) -> [f32; 3] {
    [x, y, z]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri(x: f32, light: u32, normals: Option<[[f32; 3]; 3]>) -> Prim {
        Prim {
            a: [x, 0.0, 0.0],
            b: [x, 1.0, 0.0],
            c: [x, 0.0, 1.0],
            kind: prim_kind::TRIANGLE,
            material: 1,
            light,
            motion: NONE,
            alpha: Alpha::Opaque,
            normals,
            uvs: None,
            textured: false,
        }
    }

    #[test]
    fn prims_come_back_as_pushed_and_share_surfaces_without_lights() {
        let n = Some([[1.0, 0.0, 0.0]; 3]);
        let prims = [
            tri(0.0, NONE, None),
            tri(1.0, 4, None),
            tri(2.0, NONE, n),
            tri(3.0, NONE, None),
            tri(4.0, 4, None),
        ];
        let g = Geometry::from_prims(&prims);
        assert_eq!(g.iter().collect::<Vec<_>>(), prims);
        // Flat, smooth, and one per emitting triangle.
        assert_eq!(g.surfaces.len(), 4);
        assert_eq!(g.normals.len(), g.points.len());
        assert_eq!(g.normals[0], [0.0; 3]);
        // Static triangles are marked for traversal, others not.
        assert!((0..5).all(|id| g.is_static_triangle(id)));
        let moving = Prim {
            motion: 0,
            ..prims[0]
        };
        let sphere = Prim {
            kind: prim_kind::SPHERE,
            ..prims[0]
        };
        let g = Geometry::from_prims(&[moving, sphere]);
        assert!(!g.is_static_triangle(0) && !g.is_static_triangle(1));
        assert_eq!(g.iter().collect::<Vec<_>>(), [moving, sphere]);
    }

    #[test]
    fn reorder_permutes_primitives_and_keeps_points() {
        let prims: Vec<Prim> = (0..5).map(|i| tri(i as f32, NONE, None)).collect();
        let mut g = Geometry::from_prims(&prims);
        let points = g.points.clone();
        g.reorder(&[3, 0, 4, 1, 2]);
        assert_eq!(g.points, points);
        let order: Vec<f32> = g.iter().map(|p| p.a[0]).collect();
        assert_eq!(order, [3.0, 0.0, 4.0, 1.0, 2.0]);
    }

    #[test]
    fn offsetting_lights_leaves_shared_surfaces_alone() {
        let mut g = Geometry::from_prims(&[tri(0.0, 2, None), tri(1.0, NONE, None)]);
        g.offset_lights(3);
        assert_eq!(g.prim(0).light, 5);
        assert_eq!(g.prim(1).light, NONE);
        g.push(&tri(2.0, NONE, None));
        assert_eq!(g.surfaces.len(), 2);
    }
}
