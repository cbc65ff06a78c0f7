//! Bump and normal maps (`detail.wgsl`) against `stratapt_cpu::detail`: the shading geometry's
//! derivatives and the tilted normals, at random points of every primitive of
//! `scenes/detail.toml` (flat triangles of rectangles and a box, the smooth mesh tile with its
//! vertex normals and coordinates, a sphere, a disk), under the scene's bump map and its normal
//! map.

use super::*;
use stratapt_cpu::detail::{bump, normal_map, tangents};
use stratapt_cpu::intersect::{surface, Ray};
use stratapt_scene::records::{material_kind, prim_kind};

const DETAIL_PROBE: &str = r#"
fn probe(i: u32) {
    let k = 14u * i;
    let hit = Hit(1.0, u32(probe_f(k)), probe_v3(k + 1u), vec3f(0.0), probe_v3(k + 4u),
                  probe_v3(k + 7u), probe_v2(k + 10u));
    let t = detail_tangents(hit, 0.0);
    let o = 18u * i;
    probe_put3(o, t.dpdu);
    probe_put3(o + 3u, t.dpdv);
    probe_put3(o + 6u, t.dndu);
    probe_put3(o + 9u, t.dndv);
    probe_put3(o + 12u, detail_bump(material_at(u32(probe_f(k + 12u))), t, hit.ns, hit.uv));
    probe_put3(o + 15u, detail_normal_map(material_at(u32(probe_f(k + 13u))), t, hit.ns, hit.uv));
}
"#;

#[test]
fn bump_and_normal_maps_match_cpu() {
    let scene = load_scene("detail.toml");
    let find = |kind| {
        (0..scene.materials.len() as u32)
            .find(|&i| scene.materials[i as usize].kind() == kind)
            .expect("detail.toml has a bump and a normal map")
    };
    let (bump_index, map_index) = (find(material_kind::BUMP), find(material_kind::NORMAL_MAP));
    let mut rng = Rng(17);
    let count = 3000;
    let mut input = Vec::with_capacity(14 * count);
    let mut hits = Vec::with_capacity(count);
    // The primitives of each kind: as many points on spheres and disks as on triangles.
    let of_kind = |k| -> Vec<u32> {
        (0..scene.geometry.len() as u32)
            .filter(|&id| scene.geometry.prim(id).kind == k)
            .collect()
    };
    let ids = [prim_kind::TRIANGLE, prim_kind::SPHERE, prim_kind::DISK].map(of_kind);
    assert!(ids.iter().all(|ids| !ids.is_empty()));
    while hits.len() < count {
        let id = *rng.pick(&ids[hits.len() % 3]);
        let prim = scene.geometry.prim(id);
        let [a, b, c] = [prim.a, prim.b, prim.c].map(Vec3::from_array);
        // A point of the primitive and the way to it from outside.
        let (target, normal) = match prim.kind {
            prim_kind::TRIANGLE => {
                let (x, y) = (rng.f32(), rng.f32());
                let (x, y) = if x + y > 1.0 {
                    (1.0 - x, 1.0 - y)
                } else {
                    (x, y)
                };
                (
                    a + (b - a) * x + (c - a) * y,
                    (b - a).cross(c - a).normalize(),
                )
            }
            prim_kind::SPHERE => {
                let n = warp::uniform_sphere(rng.u2());
                (a + n * b.x, n)
            }
            _ => {
                let f = Frame::from_normal(b);
                let d = warp::concentric_disk(rng.u2()) * c.x;
                (a + f.s * d.x + f.t * d.y, b)
            }
        };
        let ray = Ray::new(target + normal, -normal, f32::INFINITY);
        let hit = surface(id, &prim, &scene.motions, &ray, 1.0, 0.0, None);
        input.push(id as f32);
        input.extend(hit.p.to_array());
        input.extend(hit.ng.to_array());
        input.extend(hit.ns.to_array());
        input.extend(hit.uv.to_array());
        input.extend([bump_index as f32, map_index as f32]);
        hits.push((prim, hit));
    }
    let settings = RenderSettings::default();
    let out = run(
        &scene,
        &settings,
        &["detail"],
        DETAIL_PROBE,
        &input,
        18,
        count,
    );
    let mut c = Check::new("detail");
    let materials = &scene.materials;
    for (i, (prim, hit)) in hits.iter().enumerate() {
        let o = &out[18 * i..];
        let t = tangents(prim, &scene.motions, hit, 0.0);
        c.v3("dpdu", i, v3(o, 0), t.dpdu);
        c.v3("dpdv", i, v3(o, 3), t.dpdv);
        c.v3("dndu", i, v3(o, 6), t.dndu);
        c.v3("dndv", i, v3(o, 9), t.dndv);
        let m = &materials[bump_index as usize];
        c.v3(
            "bump",
            i,
            v3(o, 12),
            bump(m, &scene.tables, &t, hit.ns, hit.uv),
        );
        let m = &materials[map_index as usize];
        c.v3(
            "normal map",
            i,
            v3(o, 15),
            normal_map(m, &scene.tables, &t, hit.ns, hit.uv),
        );
    }
    c.finish();
}
