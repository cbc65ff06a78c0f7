//! `[[shapes]]` → primitives, and the lights of the emissive ones.
//!
//! Rectangles become two triangles sharing one `RECTANGLE` light; boxes six such faces; quads
//! two triangles, each its own `TRIANGLE` light; disks and spheres stay analytic. Static shapes are
//! baked into world space; moving ones stay in object space with a [`Motion`].

use super::materials::{emits, Materials};
use super::mesh;
use super::textures::Textures;
use super::transform::{place, Placed, Placement};
use super::validate::{Ctx, Result};
use crate::desc::{Geometry, Numbers, RectangleDesc, ShapeDesc, Spanned, Textured};
use glam::Vec3;
use std::path::Path;
use stratapt_scene::records::{
    self, light_flag, light_kind, prim_kind, surface_flag, Light, Motion, Pose, NONE,
};
use stratapt_scene::Alpha;
use stratapt_scene::Geometry as Prims;

/// Relative tolerance for "perpendicular" rectangle edges: |u·v| ≤ PERP_TOLERANCE·|u|·|v|.
pub const PERP_TOLERANCE: f32 = 1e-4;

/// The flattened shapes, before BVH ordering. `Surface::light` indexes `lights` here.
#[derive(Default)]
pub struct Shapes {
    pub geometry: Prims,
    pub lights: Vec<Light>,
    pub motions: Vec<Motion>,
}

/// Where the geometry being emitted goes: a world pose to bake in, or a motion index.
#[derive(Clone, Copy)]
struct ResolvedPlacement {
    pose: Option<Pose>,
    motion: u32,
}

impl ResolvedPlacement {
    fn point(&self, p: Vec3) -> Vec3 {
        self.pose.map_or(p, |pose| pose.point_to_world(p))
    }
    fn vector(&self, v: Vec3) -> Vec3 {
        self.pose.map_or(v, |pose| pose.vector_to_world(v))
    }
    fn normal(&self, n: Vec3) -> Vec3 {
        self.pose.map_or(n, |pose| pose.normal_to_world(n))
    }
    /// Uniform scale factor (spheres, disks).
    fn scale(&self) -> f32 {
        self.pose.map_or(1.0, |pose| pose.scale[0])
    }
}

/// What a surface is made of: its material, when it emits, its radiance, and whether the
/// material reads textures (then a shape's triangles carry texture coordinates).
#[derive(Clone, Copy)]
struct Surface {
    material: u32,
    emission: Option<[f32; 3]>,
    textured: bool,
    /// Its lights emit from both sides ([`light_flag::TWO_SIDED`]).
    two_sided: bool,
    /// Its alpha (cut-outs).
    alpha: Alpha,
}

impl Surface {
    fn of(material: u32, materials: &Materials) -> Self {
        let emission = materials.emission(material);
        Self {
            material,
            emission: emits(emission).then_some(emission),
            textured: materials.reads_texture(material),
            two_sided: false,
            alpha: Alpha::Opaque,
        }
    }

    /// With `alpha`, except on a light (whose emission strata samples as opaque): an alpha
    /// texture needs texture coordinates at hits.
    fn with_alpha(self, alpha: Alpha) -> Self {
        if self.emission.is_some() {
            return self;
        }
        Self {
            alpha,
            textured: self.textured || matches!(alpha, Alpha::Texture(_)),
            ..self
        }
    }
}

/// A shape's `alpha` key: opaque without one (or at 1), a constant in `[0, 1)`, or a texture;
/// an error on a shape that emits (strata samples its lights as opaque surfaces).
fn alpha_of(
    ctx: &Ctx,
    shape: &ShapeDesc,
    textures: &Textures,
    emission: Option<[f32; 3]>,
) -> Result<Alpha> {
    let Some(key) = &shape.common.alpha else {
        return Ok(Alpha::Opaque);
    };
    if emission.is_some_and(emits) {
        return Err(ctx.err(
            key.span(),
            "`alpha` on a shape that emits: strata's lights are opaque (give the alpha to a \
             shape in front of it)",
        ));
    }
    match key.get_ref() {
        Textured::Value(Numbers([v])) => {
            let a = ctx.finite(&Spanned::new(key.span(), *v), "alpha")?;
            if !(0.0..=1.0).contains(&a) {
                return Err(ctx.err(key.span(), format!("alpha {a}: a probability, in [0, 1]")));
            }
            Ok(if a == 1.0 {
                Alpha::Opaque
            } else {
                Alpha::Constant(a)
            })
        }
        Textured::Texture(name) => Ok(Alpha::Texture(textures.lookup(ctx, key.span(), name)?)),
    }
}

/// The texture coordinates of a rectangle's or a quad's corners, in order round it: the first
/// edge along u, the last along v (Mitsuba 3's `rectangle`).
const CORNER_UVS: [[f32; 2]; 4] = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];

/// Whether `shape`, whose material emits `emission`, emits from both sides: its `two_sided`
/// key, which only an emitting shape may set (a sphere emits from both sides already).
fn two_sided(ctx: &Ctx, shape: &ShapeDesc, emission: [f32; 3]) -> Result<bool> {
    let Some(key) = &shape.common.two_sided else {
        return Ok(false);
    };
    if *key.get_ref() && !emits(emission) {
        return Err(ctx.err(
            key.span(),
            "`two_sided` makes an emitting shape emit from both sides; this shape's material \
             emits nothing",
        ));
    }
    Ok(*key.get_ref())
}

/// Flatten every shape.
pub fn build(
    ctx: &Ctx,
    shapes: &[ShapeDesc],
    materials: &mut Materials,
    textures: &Textures,
    shutter_open: bool,
    base_dir: &Path,
    store: &mut mesh::MeshStore,
) -> Result<Shapes> {
    let mut out = Shapes::default();
    for shape in shapes {
        let placed = place(ctx, &shape.common, shape.span.clone(), shutter_open)?;
        let placing = match placed.placement {
            Placement::Static(pose) => ResolvedPlacement {
                pose: (pose != Pose::IDENTITY).then_some(pose),
                motion: NONE,
            },
            Placement::Moving(motion) => {
                out.motions.push(motion);
                ResolvedPlacement {
                    pose: None,
                    motion: out.motions.len() as u32 - 1,
                }
            }
        };
        let material = match &shape.common.material {
            Some(name) => Some(materials.lookup(ctx, name)?),
            None => None,
        };
        let emission = material.map(|m| materials.emission(m));
        let alpha = alpha_of(ctx, shape, textures, emission)?;
        let surface = match (material, &shape.geometry) {
            (Some(material), _) => Some(
                Surface {
                    two_sided: two_sided(ctx, shape, materials.emission(material))?,
                    ..Surface::of(material, materials)
                }
                .with_alpha(alpha),
            ),
            (None, Geometry::Mesh(_)) => None,
            (None, _) => return Err(ctx.err(shape.span.clone(), "missing key `material`")),
        };
        let points = out.geometry.points.len();
        out.shape(
            ctx, shape, &placed, placing, surface, alpha, materials, base_dir, store,
        )?;
        if !out.geometry.finite_from(points) {
            return Err(ctx.err(
                shape.span.clone(),
                "this shape's coordinates overflow f32 once transformed",
            ));
        }
    }
    Ok(out)
}

impl Shapes {
    /// Flatten one shape (its material, if any, already resolved into `given`).
    #[allow(clippy::too_many_arguments)]
    fn shape(
        &mut self,
        ctx: &Ctx,
        shape: &ShapeDesc,
        placed: &Placed,
        placing: ResolvedPlacement,
        given: Option<Surface>,
        alpha: Alpha,
        materials: &mut Materials,
        base_dir: &Path,
        store: &mut mesh::MeshStore,
    ) -> Result<()> {
        let surface = || given.expect("non-mesh shapes have a material");
        match &shape.geometry {
            Geometry::Rectangle(d) => self.rectangle_desc(ctx, d, placed, placing, surface()),
            Geometry::Triangle(d) => {
                let v = points(ctx, &d.vertices, "vertices")?;
                match self.triangle(placing, [v[0], v[1], v[2]], surface()) {
                    true => Ok(()),
                    false => Err(ctx.err(
                        d.vertices.span(),
                        "degenerate triangle: its vertices are collinear",
                    )),
                }
            }
            Geometry::Quad(d) => {
                let v = points(ctx, &d.vertices, "vertices")?;
                let uv = |k: [usize; 3]| k.map(|k| CORNER_UVS[k]);
                let a = self.triangle_uv(placing, [v[0], v[1], v[2]], uv([0, 1, 2]), surface());
                let b = self.triangle_uv(placing, [v[0], v[2], v[3]], uv([0, 2, 3]), surface());
                match a || b {
                    true => Ok(()),
                    false => Err(ctx.err(
                        d.vertices.span(),
                        "degenerate quad: its vertices are collinear",
                    )),
                }
            }
            Geometry::Disk(d) => {
                let center = ctx.point(&d.center, "center")?;
                let normal = ctx.direction(&d.normal, "normal")?;
                let radius = ctx.positive(&d.radius, "radius")?;
                placed.require_uniform_scale(ctx, "disk")?;
                let (c, n) = (placing.point(center), placing.normal(normal));
                let r = Vec3::new(radius * placing.scale(), 0.0, 0.0);
                let light = self.light(placing, surface(), light_kind::DISK, [c, n, r]);
                self.push(placing, prim_kind::DISK, [c, n, r], surface(), light);
                Ok(())
            }
            Geometry::Sphere(d) => {
                let center = ctx.point(&d.center, "center")?;
                let radius = ctx.positive(&d.radius, "radius")?;
                placed.require_uniform_scale(ctx, "sphere")?;
                let c = placing.point(center);
                let r = Vec3::new(radius * placing.scale(), 0.0, 0.0);
                let light = self.light(placing, surface(), light_kind::SPHERE, [c, Vec3::ZERO, r]);
                self.push(
                    placing,
                    prim_kind::SPHERE,
                    [c, r, Vec3::ZERO],
                    surface(),
                    light,
                );
                Ok(())
            }
            Geometry::Box(d) => {
                let lo = ctx.point(&d.min, "min")?;
                let hi = ctx.point(&d.max, "max")?;
                if !lo.cmplt(hi).all() {
                    let reason =
                        format!("`max` must exceed `min` on every axis (min {lo}, max {hi})");
                    return Err(ctx.err(d.max.span(), reason));
                }
                // The eight corners placed once: faces sharing an edge share its vertices bit
                // for bit, so the box is watertight at any scale and place; placing each face's
                // corner + edges separately left 1-ULP cracks 10⁵ from the origin, through
                // which rays entered a rotated box. Measured:
                // docs/measurements/far-from-the-origin.md#boxes-whose-faces-share-their-corners
                let corners: [Vec3; 8] = std::array::from_fn(|i| {
                    let pick = |bit: usize, lo: f32, hi: f32| if i & bit == 0 { lo } else { hi };
                    placing.point(Vec3::new(
                        pick(1, lo.x, hi.x),
                        pick(2, lo.y, hi.y),
                        pick(4, lo.z, hi.z),
                    ))
                });
                let first = self
                    .geometry
                    .add_points(&corners.map(|c| c.to_array()), None);
                for face in BOX_FACES {
                    let [p0, p1, _, p3] = face.map(|k| corners[k]);
                    let light = self.light(
                        placing,
                        surface(),
                        light_kind::RECTANGLE,
                        [p0, p1 - p0, p3 - p0],
                    );
                    // A textured face has its own copies of the corners (the same bits: still
                    // watertight), each with its texture coordinates.
                    let [k0, k1, k2, k3] = match surface().textured {
                        true => {
                            let k = self.geometry.add_points_uv(
                                &face.map(|k| corners[k].to_array()),
                                None,
                                Some(&CORNER_UVS),
                            );
                            [k, k + 1, k + 2, k + 3]
                        }
                        false => face.map(|k| first + k as u32),
                    };
                    for tri in [[k0, k1, k2], [k0, k2, k3]] {
                        self.push_triangle(
                            placing,
                            tri,
                            surface(),
                            light,
                            false,
                            surface().textured,
                        );
                    }
                }
                Ok(())
            }
            Geometry::Mesh(d) => {
                let objects = mesh::load(
                    ctx,
                    d,
                    given.map(|s| s.material),
                    materials,
                    base_dir,
                    store,
                )?;
                let mut added = 0;
                // The objects' own emitting materials emit from both sides with the mesh's key.
                let two_sided = shape
                    .common
                    .two_sided
                    .as_ref()
                    .is_some_and(|k| *k.get_ref());
                for object in objects {
                    added += self.mesh_object(placing, object, materials, two_sided, alpha);
                }
                match added {
                    0 => Err(ctx.err(
                        d.file.span(),
                        format!("mesh `{}`: every triangle has zero area", d.file.get_ref()),
                    )),
                    _ => Ok(()),
                }
            }
        }
    }

    /// The triangles of one mesh object, sharing its vertices; zero-area triangles are dropped.
    /// How many were added.
    fn mesh_object(
        &mut self,
        placing: ResolvedPlacement,
        object: mesh::MeshObject,
        materials: &Materials,
        two_sided: bool,
        alpha: Alpha,
    ) -> usize {
        let vec = |v: &[f32]| Vec3::from_slice(v);
        let points: Vec<[f32; 3]> = object
            .positions
            .chunks_exact(3)
            .map(|p| placing.point(vec(p)).to_array())
            .collect();
        drop(object.positions);
        // A zero normal (none usable) stays zero: the faces using it are flat.
        let normals: Option<Vec<[f32; 3]>> = object.normals.as_ref().map(|n| {
            n.chunks_exact(3)
                .map(|n| match vec(n) == Vec3::ZERO {
                    true => [0.0; 3],
                    false => placing.normal(vec(n)).to_array(),
                })
                .collect()
        });
        // Texture coordinates only where the material reads a texture.
        let surface = Surface {
            two_sided,
            ..Surface::of(object.material, materials)
        }
        .with_alpha(alpha);
        let uvs: Option<Vec<[f32; 2]>> = object
            .uvs
            .as_ref()
            .filter(|_| surface.textured)
            .map(|uv| uv.chunks_exact(2).map(|c| [c[0], c[1]]).collect());
        let first = self
            .geometry
            .add_points_uv(&points, normals.as_deref(), uvs.as_deref());
        let smooth = |v: &[u32; 3]| {
            let n = object.normals.as_deref().unwrap_or(&[]);
            !n.is_empty()
                && v.iter()
                    .all(|&i| vec(&n[3 * i as usize..][..3]) != Vec3::ZERO)
        };
        let mut added = 0;
        for face in object.indices.chunks_exact(3) {
            let v = [face[0], face[1], face[2]];
            let p = v.map(|i| Vec3::from_array(points[i as usize]));
            if !has_area(p) {
                continue;
            }
            let light = self.light(placing, surface, light_kind::TRIANGLE, p);
            self.push_triangle(
                placing,
                v.map(|i| first + i),
                surface,
                light,
                smooth(&v),
                uvs.is_some(),
            );
            added += 1;
        }
        added
    }

    /// A `rectangle` table: non-degenerate, perpendicular edges that the scale does not shear.
    fn rectangle_desc(
        &mut self,
        ctx: &Ctx,
        d: &RectangleDesc,
        placed: &Placed,
        placing: ResolvedPlacement,
        surface: Surface,
    ) -> Result<()> {
        let corner = ctx.point(&d.corner, "corner")?;
        let u = ctx.point(&d.edge_u, "edge_u")?;
        let v = ctx.point(&d.edge_v, "edge_v")?;
        if u.cross(v).length_squared() == 0.0 {
            return Err(ctx.err(
                d.edge_v.span(),
                "degenerate rectangle: `edge_u` and `edge_v` are parallel or zero",
            ));
        }
        if !perpendicular(u, v) {
            let angle = u.angle_between(v).to_degrees();
            let reason = format!("`edge_u` and `edge_v` must be perpendicular (they are {angle:.3}° apart); use a `quad` for other shapes");
            return Err(ctx.err(d.edge_v.span(), reason));
        }
        // A per-axis scale may shear the rectangle: check it at both ends and midway (the
        // squared scales interpolate quadratically, so three zeros mean zero throughout).
        let [s0, s1] = placed.poses().map(|p| p.scale());
        if ![s0, 0.5 * (s0 + s1), s1]
            .iter()
            .all(|&s| perpendicular(s * u, s * v))
        {
            return Err(ctx.err(
                placed.scale_span.clone(),
                "this per-axis `scale` shears the rectangle into a parallelogram",
            ));
        }
        self.rectangle(placing, corner, u, v, surface);
        Ok(())
    }

    /// A rectangle: two triangles sharing one `RECTANGLE` light when it emits.
    fn rectangle(
        &mut self,
        placing: ResolvedPlacement,
        corner: Vec3,
        u: Vec3,
        v: Vec3,
        surface: Surface,
    ) {
        let (c, u, v) = (placing.point(corner), placing.vector(u), placing.vector(v));
        let light = self.light(placing, surface, light_kind::RECTANGLE, [c, u, v]);
        let corners = [c, c + u, c + u + v, c + v].map(|p| p.to_array());
        let uvs = surface.textured.then_some(&CORNER_UVS[..]);
        let k = self.geometry.add_points_uv(&corners, None, uvs);
        for tri in [[k, k + 1, k + 2], [k, k + 2, k + 3]] {
            self.push_triangle(placing, tri, surface, light, false, surface.textured);
        }
    }

    /// A triangle given in the placing's input space, with its own `TRIANGLE` light when it emits;
    /// false (and nothing added) when it has no area.
    fn triangle(&mut self, placing: ResolvedPlacement, v: [Vec3; 3], surface: Surface) -> bool {
        // Without texture coordinates a triangle's (u, v) are its barycentrics.
        let barycentric = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        self.triangle_uv(placing, v, barycentric, surface)
    }

    /// [`Shapes::triangle`] with the texture coordinates of its vertices (kept only where the
    /// material reads a texture).
    fn triangle_uv(
        &mut self,
        placing: ResolvedPlacement,
        v: [Vec3; 3],
        uv: [[f32; 2]; 3],
        surface: Surface,
    ) -> bool {
        let v = v.map(|p| placing.point(p));
        if !has_area(v) {
            return false;
        }
        let light = self.light(placing, surface, light_kind::TRIANGLE, v);
        let uvs = surface.textured.then_some(&uv[..]);
        let k = self
            .geometry
            .add_points_uv(&v.map(|p| p.to_array()), None, uvs);
        self.push_triangle(
            placing,
            [k, k + 1, k + 2],
            surface,
            light,
            false,
            surface.textured,
        );
        true
    }

    /// Adds a light for an emissive surface; its index or `NONE`.
    fn light(
        &mut self,
        placing: ResolvedPlacement,
        surface: Surface,
        kind: u32,
        p: [Vec3; 3],
    ) -> u32 {
        let Some(radiance) = surface.emission else {
            return NONE;
        };
        self.lights.push(Light {
            p0: p[0].to_array(),
            kind,
            p1: p[1].to_array(),
            motion: placing.motion,
            p2: p[2].to_array(),
            radiance,
            flags: if surface.two_sided {
                light_flag::TWO_SIDED
            } else {
                0
            },
            ..Default::default()
        });
        self.lights.len() as u32 - 1
    }

    /// A triangle over points `v` already added.
    fn push_triangle(
        &mut self,
        placing: ResolvedPlacement,
        v: [u32; 3],
        surface: Surface,
        light: u32,
        smooth: bool,
        uv: bool,
    ) {
        let flag = |on: bool, flag: u32| if on { flag } else { 0 };
        let (alpha_flags, alpha) = surface.alpha.encode();
        let surface = records::Surface {
            kind: prim_kind::TRIANGLE,
            material: surface.material,
            light,
            motion: placing.motion,
            flags: flag(smooth, surface_flag::SHADING_NORMALS)
                | flag(uv, surface_flag::UV)
                | flag(surface.textured, surface_flag::TEXTURED)
                | alpha_flags,
            alpha,
        };
        self.geometry.push_indexed(v, surface);
    }

    /// A sphere or disk: its three points (see [`prim_kind`]).
    fn push(
        &mut self,
        placing: ResolvedPlacement,
        kind: u32,
        p: [Vec3; 3],
        surface: Surface,
        light: u32,
    ) {
        let k = self.geometry.add_points(&p.map(|p| p.to_array()), None);
        let (alpha_flags, alpha) = surface.alpha.encode();
        let surface = records::Surface {
            kind,
            material: surface.material,
            light,
            motion: placing.motion,
            flags: if surface.textured {
                surface_flag::TEXTURED
            } else {
                0
            } | alpha_flags,
            alpha,
        };
        self.geometry.push_indexed([k, k + 1, k + 2], surface);
    }
}

/// Whether a triangle has area (not collinear, not NaN).
fn has_area(v: [Vec3; 3]) -> bool {
    let area2 = (v[1] - v[0]).cross(v[2] - v[0]).length_squared();
    area2 != 0.0 && !area2.is_nan()
}

fn perpendicular(u: Vec3, v: Vec3) -> bool {
    u.dot(v).abs() <= PERP_TOLERANCE * u.length() * v.length()
}

/// The six faces of a box as corner indices `[p0, p1, p2, p3]` (corner `i` takes `max` on x, y,
/// z where bit 0, 1, 2 of `i` is set), going round the face with `(p1 − p0) × (p3 − p0)`
/// pointing outwards; each face is the triangles `(p0, p1, p2)` and `(p0, p2, p3)` and, when it
/// emits, the rectangle light `(p0, p1 − p0, p3 − p0)`.
pub const BOX_FACES: [[usize; 4]; 6] = [
    [0, 4, 6, 2], // −x
    [1, 3, 7, 5], // +x
    [0, 1, 5, 4], // −y
    [2, 6, 7, 3], // +y
    [0, 2, 3, 1], // −z
    [4, 5, 7, 6], // +z
];

/// The points of a `vertices` array, each finite.
fn points<const N: usize>(
    ctx: &Ctx,
    at: &crate::desc::Spanned<[[f64; 3]; N]>,
    key: &str,
) -> Result<[Vec3; N]> {
    let mut out = [Vec3::ZERO; N];
    for (o, p) in out.iter_mut().zip(at.get_ref()) {
        *o = ctx.finite3(*p, at.span(), key)?;
    }
    Ok(out)
}
