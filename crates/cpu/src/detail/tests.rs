use super::*;
use crate::intersect::{disk_uv, sphere_uv};
use stratapt_sampling::testing::TestRng;
use stratapt_scene::records::{material_kind, texture_wrap, NONE};

fn close(a: Vec3, b: Vec3, tol: f32) -> bool {
    (a - b).abs().max_element() <= tol * (1.0 + b.abs().max_element())
}

fn hit(p: Vec3, ns: Vec3) -> Hit {
    Hit {
        t: 1.0,
        prim: 0,
        p,
        err: Vec3::ZERO,
        ng: ns,
        ns,
        uv: Vec2::ZERO,
    }
}

fn random_point(rng: &mut TestRng) -> Vec3 {
    Vec3::new(rng.f32(), rng.f32(), rng.f32()) * 4.0 - 2.0
}

fn prim(kind: u32, a: Vec3, b: Vec3, c: Vec3) -> Prim {
    Prim {
        a: a.to_array(),
        b: b.to_array(),
        c: c.to_array(),
        kind,
        motion: NONE,
        light: NONE,
        ..Prim::default()
    }
}

/// Tables holding one RGB32F image texture, `w × h`, clamped, identity uv.
fn image(w: u32, h: u32, texels: &[[f32; 3]]) -> Vec<f32> {
    texture::image_tables(w, h, texels, texture_wrap::CLAMP)
}

fn map(kind: u32, textured: bool, value: f32) -> Material {
    let flag = if textured {
        material_flag::COLOR_TEXTURE
    } else {
        0
    };
    Material {
        tag: kind | flag,
        color: [value; 3],
        ..Material::default()
    }
}

#[test]
fn triangle_tangents_carry_its_coordinates_to_its_vertices() {
    let mut rng = TestRng(11);
    for _ in 0..100 {
        let [a, b, c] = [0; 3].map(|_| random_point(&mut rng));
        let uvs = [0; 3].map(|_| [rng.f32() * 3.0, rng.f32() * 3.0]);
        let mut p = prim(prim_kind::TRIANGLE, a, b, c);
        p.uvs = Some(uvs);
        let t = tangents(&p, &[], &hit(a, Vec3::Z), 0.0);
        let [u0, u1, u2] = uvs.map(Vec2::from_array);
        let step = |d: Vec2| t.dpdu * d.x + t.dpdv * d.y;
        let det = (u1 - u0).perp_dot(u2 - u0).abs();
        if det < 1e-2 {
            continue;
        }
        assert!(close(step(u1 - u0), b - a, 1e-3), "{t:?}");
        assert!(close(step(u2 - u0), c - a, 1e-3), "{t:?}");
        assert_eq!((t.dndu, t.dndv), (Vec3::ZERO, Vec3::ZERO));
    }
    // Without coordinates: the barycentrics, (0, 0), (1, 0), (0, 1).
    let (a, b, c) = (
        Vec3::ZERO,
        Vec3::new(2.0, 0.0, 0.0),
        Vec3::new(0.0, 3.0, 1.0),
    );
    let t = tangents(
        &prim(prim_kind::TRIANGLE, a, b, c),
        &[],
        &hit(a, Vec3::Z),
        0.0,
    );
    assert!(
        close(t.dpdu, b - a, 1e-6) && close(t.dpdv, c - a, 1e-6),
        "{t:?}"
    );
}

#[test]
fn smooth_triangle_tangents_are_pbrts_shading_pair() {
    let mut rng = TestRng(12);
    for _ in 0..100 {
        let [a, b, c] = [0; 3].map(|_| random_point(&mut rng));
        let ng = (b - a).cross(c - a).normalize();
        let normals = [0; 3].map(|_| (ng + random_point(&mut rng) * 0.2).normalize());
        let uvs = [[0.0, 0.0], [1.0, 0.2], [0.3, 1.0]];
        let mut p = prim(prim_kind::TRIANGLE, a, b, c);
        p.uvs = Some(uvs);
        p.normals = Some(normals.map(|n| n.to_array()));
        let ns = (normals[0] + normals[1] + normals[2]).normalize();
        let t = tangents(&p, &[], &hit(a, ns), 0.0);
        // ∂p/∂u in the shading plane, ∂p/∂v = n × ∂p/∂u.
        assert!(t.dpdu.dot(ns).abs() < 1e-4 * t.dpdu.length(), "{t:?}");
        assert!(close(t.dpdv, ns.cross(t.dpdu), 1e-5), "{t:?}");
        // The normals' derivatives carry n₀ to n₁ and n₂.
        let [u0, u1, u2] = uvs.map(Vec2::from_array);
        let step = |d: Vec2| t.dndu * d.x + t.dndv * d.y;
        assert!(close(step(u1 - u0), normals[1] - normals[0], 1e-4), "{t:?}");
        assert!(close(step(u2 - u0), normals[2] - normals[0], 1e-4), "{t:?}");
    }
}

/// A step of `h` along ∂p/∂u moved (u, v) by `du`, along ∂p/∂v by `dv`: (h, 0) and (0, h).
fn steps_by(du: Vec2, dv: Vec2, h: f32, t: &Tangents) {
    assert!(
        (du - Vec2::new(h, 0.0)).abs().max_element() < 2e-5,
        "{du} {t:?}"
    );
    assert!(
        (dv - Vec2::new(0.0, h)).abs().max_element() < 2e-5,
        "{dv} {t:?}"
    );
}

#[test]
fn sphere_and_disk_tangents_are_their_parametrizations_derivatives() {
    let mut rng = TestRng(13);
    let h = 1e-3;
    for _ in 0..100 {
        let (center, radius) = (random_point(&mut rng), 0.5 + rng.f32());
        let n = (random_point(&mut rng)).normalize();
        if n.z.abs() > 0.95 {
            continue;
        }
        let p = center + n * radius;
        let t = tangents(
            &prim(
                prim_kind::SPHERE,
                center,
                Vec3::new(radius, 0.0, 0.0),
                Vec3::ZERO,
            ),
            &[],
            &hit(p, n),
            0.0,
        );
        // Moving along ∂p/∂u (∂p/∂v) by h changes u (v) by h and the other by nothing.
        let uv = sphere_uv(n);
        let du = sphere_uv((p + t.dpdu * h - center).normalize()) - uv;
        let dv = sphere_uv((p + t.dpdv * h - center).normalize()) - uv;
        steps_by(du, dv, h, &t);
        assert!(close(t.dndu * radius, t.dpdu, 1e-6) && close(t.dndv * radius, t.dpdv, 1e-6));
        // A disk through the same centre, facing n.
        let q = center + Frame::from_normal(n).s * (radius * 0.3) + Frame::from_normal(n).t * 0.1;
        let t = tangents(
            &prim(prim_kind::DISK, center, n, Vec3::new(radius, 0.0, 0.0)),
            &[],
            &hit(q, n),
            0.0,
        );
        let uv = disk_uv(center, n, radius, q);
        let du = disk_uv(center, n, radius, q + t.dpdu * h) - uv;
        let dv = disk_uv(center, n, radius, q + t.dpdv * h) - uv;
        steps_by(du, dv, h, &t);
    }
}

/// A flat unit square in z = 0 whose `(u, v)` are its `(x, y)`.
fn square_tangents() -> Tangents {
    let mut p = prim(prim_kind::TRIANGLE, Vec3::ZERO, Vec3::X, Vec3::Y);
    p.uvs = Some([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]);
    tangents(&p, &[], &hit(Vec3::ZERO, Vec3::Z), 0.0)
}

#[test]
fn a_height_ramp_tilts_the_normal_as_the_displaced_surface_would() {
    // Heights s·u (linear between texel centres, exactly so for bilinear lookups): the surface
    // z = s·x, whose normal is (−s, 0, 1) normalized.
    let t = square_tangents();
    for s in [0.05f32, 0.3, 2.0, -1.0] {
        let texels: Vec<[f32; 3]> = (0..16).map(|i| [s * (i as f32 + 0.5) / 16.0; 3]).collect();
        let tables = image(16, 1, &texels);
        let m = map(material_kind::BUMP, true, 0.0);
        for u in [0.2, 0.5, 0.77] {
            let n = bump(&m, &tables, &t, Vec3::Z, Vec2::new(u, 0.5));
            let want = Vec3::new(-s, 0.0, 1.0).normalize();
            assert!(close(n, want, 2e-3), "s {s} u {u}: {n} against {want}");
        }
    }
    // A constant height moves a flat surface without tilting it; on a sphere it scales both
    // tangents alike (∂n/∂u = ∂p/∂u / r): the normal stays too.
    let n = bump(
        &map(material_kind::BUMP, false, 0.3),
        &[],
        &t,
        Vec3::Z,
        Vec2::splat(0.5),
    );
    assert_eq!(n, Vec3::Z);
    let p = Vec3::new(0.6, 0.0, 0.8);
    let sphere = prim(prim_kind::SPHERE, Vec3::ZERO, Vec3::X, Vec3::ZERO);
    let ts = tangents(&sphere, &[], &hit(p, p), 0.0);
    let n = bump(
        &map(material_kind::BUMP, false, 0.3),
        &[],
        &ts,
        p,
        Vec2::ZERO,
    );
    assert!(close(n, p, 1e-6), "{n}");
}

#[test]
fn a_normal_map_turns_its_texel_into_the_shading_frame() {
    let t = square_tangents();
    let read = |texel: [f32; 3]| {
        let tables = image(1, 1, &[texel]);
        normal_map(
            &map(material_kind::NORMAL_MAP, true, 0.0),
            &tables,
            &t,
            Vec3::Z,
            Vec2::splat(0.5),
        )
    };
    // Straight up is the shading normal; +x in the map is ∂p/∂u, +y is n × ∂p/∂u.
    assert!(close(read([0.5, 0.5, 1.0]), Vec3::Z, 1e-6));
    assert!(close(
        read([1.0, 0.5, 1.0]),
        Vec3::new(1.0, 0.0, 1.0).normalize(),
        1e-6
    ));
    assert!(close(
        read([0.5, 0.0, 1.0]),
        Vec3::new(0.0, -1.0, 1.0).normalize(),
        1e-6
    ));
    // A texel that encodes no direction leaves the normal alone; one below the surface is
    // turned to the normal's side.
    assert_eq!(read([0.5, 0.5, 0.5]), Vec3::Z);
    assert!(read([0.5, 0.5, 0.0]).z > 0.0);
}

#[test]
fn a_moving_shape_has_its_world_tangents() {
    use stratapt_scene::records::Pose;
    // A sphere moved by a pose: its world tangents are the static sphere's under the pose.
    let pose = Pose::new(
        Vec3::new(1.0, 2.0, 3.0),
        glam::Quat::from_rotation_z(0.7),
        Vec3::splat(2.0),
    );
    let motions = [Motion {
        open: pose,
        close: pose,
    }];
    let mut sphere = prim(prim_kind::SPHERE, Vec3::ZERO, Vec3::X, Vec3::ZERO);
    sphere.motion = 0;
    let local = Vec3::new(0.6, 0.0, 0.8);
    let world = hit(pose.point_to_world(local), pose.normal_to_world(local));
    let t = tangents(&sphere, &motions, &world, 0.5);
    sphere.motion = NONE;
    let s = tangents(&sphere, &[], &hit(local, local), 0.0);
    assert!(close(t.dpdu, pose.vector_to_world(s.dpdu), 1e-5), "{t:?}");
    assert!(close(t.dpdv, pose.vector_to_world(s.dpdv), 1e-5), "{t:?}");
}
