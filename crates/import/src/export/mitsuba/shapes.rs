//! strata's primitives as Mitsuba 3 shapes: triangles grouped into one world-space PLY mesh per
//! material, shading, motion and emission; spheres and disks as Mitsuba's analytic ones.

use super::xml::Element;
use super::Writer;
use crate::desc::MeshData;
use glam::{Mat4, Vec3};
use std::collections::{BTreeMap, HashMap};
use stratapt_sampling::frame::Frame;
use stratapt_scene::geometry::Prim;
use stratapt_scene::records::{light_flag, prim_kind, Pose, NONE};
use stratapt_scene::Alpha;

/// What triangles must share to be one mesh.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
struct MeshKey {
    material: u32,
    smooth: bool,
    uv: bool,
    motion: u32,
    /// The emitted radiance's bits (zero: none).
    emission: [u32; 3],
    /// Its alpha, encoded ([`Alpha::encode`]).
    alpha: (u32, u32),
}

impl Writer<'_> {
    /// Every primitive, as shapes.
    pub(super) fn shapes(&mut self) -> Vec<Element> {
        let g = &self.scene.geometry;
        let mut meshes: BTreeMap<MeshKey, Vec<Prim>> = BTreeMap::new();
        let mut out = Vec::new();
        for prim in g.iter() {
            match prim.kind {
                prim_kind::TRIANGLE => {
                    let key = MeshKey {
                        material: prim.material,
                        smooth: prim.normals.is_some(),
                        uv: prim.uvs.is_some(),
                        motion: prim.motion,
                        emission: self.emission(&prim).map(f32::to_bits),
                        alpha: prim.alpha.encode(),
                    };
                    meshes.entry(key).or_default().push(prim);
                }
                prim_kind::SPHERE => out.push(self.sphere(&prim)),
                _ => out.push(self.disk(&prim)),
            }
        }
        for (n, (key, prims)) in meshes.into_iter().enumerate() {
            out.push(self.mesh(n, key, &prims));
        }
        out
    }

    /// The radiance primitive `p` emits (zero if none); a two-sided light's is warned, Mitsuba's
    /// area emitters emit from their front only.
    fn emission(&mut self, p: &Prim) -> [f32; 3] {
        match p.light {
            NONE => [0.0; 3],
            l => {
                let light = self.scene.lights[l as usize];
                if light.has(light_flag::TWO_SIDED) && !self.two_sided_warned {
                    self.two_sided_warned = true;
                    self.warn(
                        "two-sided area lights: Mitsuba's area emitters emit from their front \
                         only; written one-sided, dark from behind"
                            .into(),
                    );
                }
                light.radiance
            }
        }
    }

    /// The pose that places primitives of `motion` at shutter open.
    fn pose(&self, motion: u32) -> Pose {
        match motion {
            NONE => Pose::IDENTITY,
            m => self.scene.motions[m as usize].open,
        }
    }

    /// Triangles as one PLY mesh, its vertices shared where strata's are.
    fn mesh(&mut self, n: usize, key: MeshKey, prims: &[Prim]) -> Element {
        let pose = self.pose(key.motion);
        let mut mesh = MeshData {
            normals: key.smooth.then(Vec::new),
            uvs: key.uv.then(Vec::new),
            ..MeshData::default()
        };
        let mut index: HashMap<([u32; 3], [u32; 3], [u32; 2]), u32> = HashMap::new();
        for p in prims {
            for k in 0..3 {
                let pos = pose.point_to_world(Vec3::from([p.a, p.b, p.c][k]));
                let normal = p.normals.map(|ns| pose.normal_to_world(Vec3::from(ns[k])));
                let uv = p.uvs.map_or([0.0; 2], |uvs| uvs[k]);
                let bits = (
                    pos.to_array().map(f32::to_bits),
                    normal.unwrap_or(Vec3::ZERO).to_array().map(f32::to_bits),
                    uv.map(f32::to_bits),
                );
                let next = (mesh.positions.len() / 3) as u32;
                let i = *index.entry(bits).or_insert_with(|| {
                    mesh.positions.extend(pos.to_array());
                    if let (Some(ns), Some(nv)) = (&mut mesh.normals, normal) {
                        ns.extend(nv.to_array());
                    }
                    if let Some(uvs) = &mut mesh.uvs {
                        uvs.extend(uv);
                    }
                    next
                });
                mesh.indices.push(i);
            }
        }
        let mut bytes = Vec::new();
        crate::load::write_ply_to(&mut bytes, &mesh).expect("writing to memory");
        let file = self.file(format!("mesh{n}.ply"), bytes);
        let shape = Element::plugin("shape", "ply")
            .child(Element::string("filename", &file))
            .child(Element::boolean("face_normals", !key.smooth));
        let alpha = prims[0].alpha;
        self.dress(shape, key.material, alpha, key.emission.map(f32::from_bits))
    }

    /// A sphere: centre `a`, radius `b.x`.
    fn sphere(&mut self, p: &Prim) -> Element {
        let pose = self.pose(p.motion);
        let centre = pose.point_to_world(Vec3::from(p.a));
        let radius = p.b[0] * pose.scale().max_element();
        let shape = Element::plugin("shape", "sphere")
            .child(Element::point("center", centre))
            .child(Element::float("radius", radius));
        let emission = self.emission(p);
        if emission != [0.0; 3] {
            self.warn(
                "sphere light: strata's spheres emit from both sides, Mitsuba's outwards only; \
                 seen from inside it is dark"
                    .into(),
            );
        }
        self.dress(shape, p.material, p.alpha, emission)
    }

    /// A disk: centre `a`, unit normal `b`, radius `c.x`; Mitsuba's unit disk in the plane
    /// z = 0 placed by the frame of its normal.
    fn disk(&mut self, p: &Prim) -> Element {
        let pose = self.pose(p.motion);
        let centre = pose.point_to_world(Vec3::from(p.a));
        let normal = pose.normal_to_world(Vec3::from(p.b));
        let radius = p.c[0] * pose.scale().max_element();
        let f = Frame::from_normal(normal);
        let to_world = Mat4::from_cols(
            (f.s * radius).extend(0.0),
            (f.t * radius).extend(0.0),
            f.n.extend(0.0),
            centre.extend(1.0),
        );
        let shape = Element::plugin("shape", "disk").child(Element::matrix("to_world", to_world));
        let emission = self.emission(p);
        self.dress(shape, p.material, p.alpha, emission)
    }

    /// `shape` with its BSDF (in a `mask` where it has an alpha) and, where it emits, an area
    /// emitter.
    fn dress(
        &mut self,
        shape: Element,
        material: u32,
        alpha: Alpha,
        emission: [f32; 3],
    ) -> Element {
        let bsdf = match alpha {
            Alpha::Opaque => self.bsdf(material),
            _ => self.mask(material, alpha),
        };
        let mut shape = shape.child(Element::new("ref").attr("id", &bsdf));
        if emission != [0.0; 3] {
            shape = shape.child(
                Element::plugin("emitter", "area").child(Element::rgb("radiance", emission)),
            );
        }
        shape
    }
}
