//! Flattening: shapes → primitives and lights, motion bounds, light tables, effects.

use glam::Vec3;
use std::path::Path;
use stratapt_import::load::load_str;
use stratapt_sampling::testing::TestRng;
use stratapt_scene::bvh::prim_bounds;
use stratapt_scene::light_table::{luminance, power};
use stratapt_scene::records::{light_kind, prim_kind, NONE};
use stratapt_scene::{DimLayout, Effects, FlatScene, Prim};

const CAMERA: &str = "[camera]\neye = [0, 1, -5]\nlook_at = [0, 0, 0]\nfov = 40\n";

fn scene(text: &str) -> FlatScene {
    load_str(text, Path::new("test.toml")).unwrap_or_else(|e| panic!("{e}"))
}

fn v(a: [f32; 3]) -> Vec3 {
    Vec3::from_array(a)
}

fn tri_normal(p: &Prim) -> Vec3 {
    (v(p.b) - v(p.a)).cross(v(p.c) - v(p.a))
}

const LAMP: &str = "[materials.lamp]\ntype = \"diffuse\"\nalbedo = 0\nemission = [4, 2, 1]\n";

#[test]
fn rectangle_is_two_triangles_and_one_rectangle_light() {
    let s = scene(&format!(
        "{CAMERA}{LAMP}[[shapes]]\ntype = \"rectangle\"\ncorner = [1, 2, 3]\nedge_u = [2, 0, 0]\nedge_v = [0, 0, 3]\nmaterial = \"lamp\"\n"
    ));
    assert_eq!(s.geometry.len(), 2);
    assert_eq!(s.lights.len(), 1);
    let light = &s.lights[0];
    assert_eq!(light.kind, light_kind::RECTANGLE);
    assert_eq!(
        (light.p0, light.p1, light.p2),
        ([1.0, 2.0, 3.0], [2.0, 0.0, 0.0], [0.0, 0.0, 3.0])
    );
    assert_eq!(light.radiance, [4.0, 2.0, 1.0]);
    assert_eq!(light.motion, NONE);
    let n = v(light.p1).cross(v(light.p2));
    assert_eq!(n.length(), 6.0, "area");
    assert_eq!(n.normalize(), Vec3::NEG_Y, "front = edge_u × edge_v");
    assert_eq!(light.select_pdf, 1.0);
    assert_eq!(light.unhittable_select_pdf, 0.0);
    assert!(s.unhittable_table.is_empty());
    let mut area = 0.0;
    for p in s.geometry.iter() {
        assert_eq!(
            (p.kind, p.light, p.motion, p.normals),
            (prim_kind::TRIANGLE, 0, NONE, None)
        );
        assert!(
            tri_normal(&p).normalize().abs_diff_eq(Vec3::NEG_Y, 1e-6),
            "triangles face the light's way"
        );
        area += 0.5 * tri_normal(&p).length();
    }
    assert_eq!(area, 6.0);
    let expected = std::f64::consts::PI * 6.0 * luminance([4.0, 2.0, 1.0]);
    assert!((power(light, &s.motions, 1.0) - expected).abs() < 1e-9);
}

#[test]
fn emissive_box_faces_point_outwards() {
    let s = scene(&format!("{CAMERA}{LAMP}[[shapes]]\ntype = \"box\"\nmin = [-1, 0, 2]\nmax = [1, 3, 4]\nmaterial = \"lamp\"\n"));
    assert_eq!(s.geometry.len(), 12);
    assert_eq!(s.lights.len(), 6);
    let center = Vec3::new(0.0, 1.5, 3.0);
    for (i, light) in s.lights.iter().enumerate() {
        assert_eq!(light.kind, light_kind::RECTANGLE);
        let n = v(light.p1).cross(v(light.p2));
        let face_center = v(light.p0) + 0.5 * (v(light.p1) + v(light.p2));
        assert!(n.dot(face_center - center) > 0.0, "face {i} faces inwards");
        assert_eq!(s.geometry.iter().filter(|p| p.light == i as u32).count(), 2);
    }
    for p in s.geometry.iter() {
        let c = (v(p.a) + v(p.b) + v(p.c)) / 3.0;
        assert!(tri_normal(&p).dot(c - center) > 0.0);
    }
}

/// A box turned and moved 10⁵ from the origin (where f32 steps by 1/128) still has exactly 8
/// distinct vertices: faces sharing an edge share its vertices bit for bit (no cracks).
#[test]
fn a_placed_box_shares_its_corners_bit_for_bit() {
    let s = scene(&format!(
        "{CAMERA}{LAMP}[[shapes]]\ntype = \"box\"\nmin = [-0.5, -0.5, -0.5]\nmax = [0.5, 0.7, 0.9]\n\
         material = \"lamp\"\ntransform = {{ translate = [1e5, 1e5, 1e5], rotate = [30, 40, 10] }}\n"
    ));
    let mut corners: Vec<[u32; 3]> = s
        .geometry
        .iter()
        .flat_map(|p| [p.a, p.b, p.c])
        .map(|v| v.map(f32::to_bits))
        .collect();
    corners.sort();
    corners.dedup();
    assert_eq!(corners.len(), 8, "{corners:?}");
}

#[test]
fn static_transform_is_baked() {
    let s = scene(&format!(
        "{CAMERA}{LAMP}[[shapes]]\ntype = \"sphere\"\ncenter = [1, 0, 0]\nradius = 0.5\nmaterial = \"lamp\"\ntransform = {{ translate = [0, 2, 0], rotate = [0, 0, 90], scale = 2 }}\n"
    ));
    let p = s.geometry.prim(0);
    assert_eq!((p.kind, p.motion), (prim_kind::SPHERE, NONE));
    assert!(
        v(p.a).abs_diff_eq(Vec3::new(0.0, 4.0, 0.0), 1e-5),
        "{:?}",
        p.a
    );
    assert_eq!(p.b[0], 1.0);
    assert_eq!(s.lights[0].kind, light_kind::SPHERE);
    assert_eq!(s.lights[0].p2[0], 1.0);
}

#[test]
fn euler_angles_apply_x_then_y_then_z() {
    let q = stratapt_import::load::euler_xyz(Vec3::new(90.0, 90.0, 0.0));
    // X first: +y → +z; then Y: +z → +x.
    assert!((q * Vec3::Y).abs_diff_eq(Vec3::X, 1e-6));
}

/// A box that translates and turns 120° about a tilted axis: every point of every triangle at
/// any shutter time lies in the primitive's bounds, and so in its BVH leaf's.
#[test]
fn motion_bounds_contain_moving_box_at_all_times() {
    let s = scene(
        "[camera]\neye = [0, 1, -5]\nlook_at = [0, 0, 0]\nfov = 40\nshutter = [0, 1]\n\
         [materials.m]\ntype = \"diffuse\"\nalbedo = 0.5\n\
         [[shapes]]\ntype = \"box\"\nmin = [0.5, -1, -0.2]\nmax = [2, 1, 0.3]\nmaterial = \"m\"\n\
         transform = { translate = [1, 0, 0], rotate = [10, 0, 0], scale = [1, 2, 1] }\n\
         transform_close = { translate = [-1, 2, 3], rotate = [10, 120, 40], scale = [1.5, 1, 0.5] }\n\
         [[shapes]]\ntype = \"sphere\"\ncenter = [0.3, 0, 0]\nradius = 0.4\nmaterial = \"m\"\n\
         transform = { translate = [0, 0, 0] }\ntransform_close = { translate = [0, 1, 0], rotate = [0, 0, 90], scale = 2 }\n\
         [[shapes]]\ntype = \"box\"\nmin = [-1, -1, -1]\nmax = [1, 1, 1]\nmaterial = \"m\"\n\
         transform = { translate = [3, 0, 0] }\ntransform_close = { translate = [3, 0, 4], scale = 0.5 }\n"
    );
    assert_eq!(s.motions.len(), 3);
    assert!(s.geometry.iter().all(|p| p.motion != NONE));
    let effects = Effects::of(&s, &s.settings);
    assert!(effects.time && !effects.lens);

    let mut ts = vec![0.0f32, 0.5, 1.0];
    let mut rng = TestRng(12345);
    ts.extend((0..200).map(|_| rng.f32()));
    let inside =
        |b: &obvhs::aabb::Aabb, p: Vec3| p.cmpge(b.min.into()).all() && p.cmple(b.max.into()).all();
    for p in s.geometry.iter() {
        let bounds = prim_bounds(&p, &s.motions);
        let motion = &s.motions[p.motion as usize];
        for &t in &ts {
            let pose = motion.at(t);
            let points: Vec<Vec3> = match p.kind {
                prim_kind::TRIANGLE => {
                    let [a, b, c] = [p.a, p.b, p.c].map(|x| pose.point_to_world(v(x)));
                    // Vertices and a few interior points.
                    vec![a, b, c, (a + b + c) / 3.0, 0.5 * (a + b)]
                }
                _ => {
                    let (c, r) = (pose.point_to_world(v(p.a)), p.b[0] * pose.scale[0]);
                    [
                        Vec3::X,
                        Vec3::NEG_X,
                        Vec3::Y,
                        Vec3::NEG_Y,
                        Vec3::Z,
                        Vec3::NEG_Z,
                    ]
                    .map(|d| c + r * d)
                    .to_vec()
                }
            };
            for q in points {
                assert!(inside(&bounds, q), "t = {t}: {q} outside {bounds:?}");
            }
        }
    }
    // Each leaf bounds its primitives; the world bounds hold everything.
    for node in &s.bvh.nodes {
        for i in node.first_index..node.first_index + node.prim_count {
            let b = prim_bounds(&s.geometry.prim(i), &s.motions);
            assert!(inside(&node.aabb, b.min.into()) && inside(&node.aabb, b.max.into()));
            assert!(
                b.min.cmpge(s.bounds_min.into()).all() && b.max.cmple(s.bounds_max.into()).all()
            );
        }
    }
}

#[test]
fn pinhole_static_scene_draws_no_lens_or_time_dims() {
    let s = scene(&format!("{CAMERA}{LAMP}[[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"lamp\"\n"));
    let effects = Effects::of(&s, &s.settings);
    assert!(!effects.lens && !effects.time);
    let dims = DimLayout::new(&effects);
    assert_eq!(
        (dims.pixel, dims.lens, dims.time, dims.first_vertex),
        (0, None, None, 2)
    );

    // An open shutter with nothing moving draws no time dimension either; a lens does.
    let s = scene(&format!(
        "[camera]\neye = [0, 1, -5]\nlook_at = [0, 0, 0]\nfov = 40\nshutter = [0, 1]\naperture = 0.1\n{LAMP}\
         [[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"lamp\"\n"
    ));
    let effects = Effects::of(&s, &s.settings);
    assert!(effects.lens && !effects.time);
    assert_eq!(DimLayout::new(&effects).lens, Some(2));
}

#[test]
fn camera_motion_uses_time() {
    let s = scene("[camera]\neye = [0, 1, -5]\nlook_at = [0, 0, 0]\nfov = 40\nshutter = [0, 1]\n[camera.close]\neye = [1, 1, -5]\n");
    assert_eq!(s.camera.eye1, [1.0, 1.0, -5.0]);
    assert_eq!(s.camera.target1, s.camera.target0);
    assert!(Effects::of(&s, &s.settings).time);
}

#[test]
fn unhittable_lights_come_first_with_their_own_table() {
    let s = scene(&format!(
        "{CAMERA}{LAMP}[[shapes]]\ntype = \"disk\"\ncenter = [0, 3, 0]\nnormal = [0, -1, 0]\nradius = 1\nmaterial = \"lamp\"\n\
         [[lights]]\ntype = \"distant\"\ndirection = [0, 1, 0]\nirradiance = 1\nangular_diameter = 2\n\
         [[lights]]\ntype = \"point\"\nposition = [0, 2, 0]\nintensity = 3\n\
         [[lights]]\ntype = \"line\"\nfrom = [0, 2, 0]\nto = [2, 2, 0]\nintensity = 1\n\
         [[lights]]\ntype = \"distant\"\ndirection = [1, 1, 0]\nirradiance = 2\n\
         [sky]\ncolor = 0.5\n"
    ));
    let kinds: Vec<u32> = s.lights.iter().map(|l| l.kind).collect();
    use light_kind::*;
    assert_eq!(kinds, [POINT, LINE, DISTANT, DISK, DISTANT, SKY]);
    assert_eq!(s.sky, 5);
    assert_eq!(s.unhittable_table.len(), 3);
    assert_eq!(s.light_table.len(), 6);
    let radius = 0.5 * (s.bounds_max - s.bounds_min).length() as f64;
    let powers: Vec<f64> = s
        .lights
        .iter()
        .map(|l| power(l, &s.motions, radius))
        .collect();
    let total: f64 = powers.iter().sum();
    let delta_total: f64 = powers[..3].iter().sum();
    for (i, l) in s.lights.iter().enumerate() {
        assert!(
            (l.select_pdf as f64 - powers[i] / total).abs() < 1e-6,
            "light {i}"
        );
        let expected = if i < 3 { powers[i] / delta_total } else { 0.0 };
        assert!(
            (l.unhittable_select_pdf as f64 - expected).abs() < 1e-6,
            "light {i}"
        );
        assert_eq!(s.light_table[i].pdf, l.select_pdf);
    }
    // Point: 4π I; line: π² I L.
    assert!((powers[0] - 4.0 * std::f64::consts::PI * 3.0).abs() < 1e-9);
    assert!((powers[1] - std::f64::consts::PI.powi(2) * 2.0).abs() < 1e-9);
    // Cone distant: radiance E / (π sin²θ) inside a cone of cosine cos θ.
    let sun = &s.lights[4];
    let cos = sun.p2[0] as f64;
    assert!(cos < 1.0 && (cos - 1f64.to_radians().cos()).abs() < 1e-7);
    let expected = 1.0 / (std::f64::consts::PI * (1.0 - cos * cos));
    assert!((sun.radiance[0] as f64 / expected - 1.0).abs() < 1e-5);
    // Delta distant: cosine 1, radiance = irradiance.
    assert_eq!((s.lights[2].p2[0], s.lights[2].radiance), (1.0, [2.0; 3]));
    // Prims point at the disk light's new index.
    assert!(s.geometry.iter().all(|p| p.light == 3));
}

#[test]
fn sky_only_scene_has_empty_bvh() {
    let s = scene(&format!(
        "{CAMERA}[sky]\ntop = [0.5, 0.7, 1]\nbottom = 0.1\nup = [0, 0, 2]\n"
    ));
    assert!(s.geometry.is_empty() && s.bvh.nodes.is_empty());
    assert_eq!(
        (s.bounds_min, s.bounds_max),
        (Vec3::splat(-1.0), Vec3::splat(1.0))
    );
    let sky = &s.lights[s.sky as usize];
    assert_eq!(
        (sky.kind, sky.p0, sky.p1, sky.radiance),
        (light_kind::SKY, [0.0, 0.0, 1.0], [0.5, 0.7, 1.0], [0.1; 3])
    );
    assert_eq!(sky.select_pdf, 1.0);
    // Traversal of the empty BVH finds nothing and does not panic.
    let ray = obvhs::ray::Ray::new_inf(Vec3::ZERO.into(), Vec3::X.into());
    let mut hit = obvhs::ray::RayHit::none();
    assert!(!s.bvh.ray_traverse(ray, &mut hit, |_, _| 0.0));
}

#[test]
fn mesh_scene_uses_mtl_materials_and_normals() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/mesh.toml");
    let s = stratapt_import::scene_file::load(&path).unwrap_or_else(|e| panic!("{e}"));
    for name in [
        "meshes/mesh.obj:copper",
        "meshes/mesh.obj:clay",
        "meshes/mesh.obj:lamp",
    ] {
        assert!(
            s.material_names.iter().any(|n| n == name),
            "{name} in {:?}",
            s.material_names
        );
    }
    // The lamp quad (2 triangles) emits in the MTL copy only; the overridden copy does not.
    let tri_lights = s
        .lights
        .iter()
        .filter(|l| l.kind == light_kind::TRIANGLE)
        .count();
    assert_eq!(tri_lights, 2);
    for l in s.lights.iter().filter(|l| l.kind == light_kind::TRIANGLE) {
        let n = (v(l.p1) - v(l.p0)).cross(v(l.p2) - v(l.p0));
        assert!(
            n.normalize().abs_diff_eq(Vec3::NEG_Y, 1e-6),
            "lamp faces down"
        );
    }
    // Smooth icosphere: 80 triangles × 2 copies with shading normals, unit length.
    let smooth: Vec<Prim> = s.geometry.iter().filter(|p| p.normals.is_some()).collect();
    assert_eq!(smooth.len(), 160);
    for p in smooth {
        for n in p.normals.unwrap() {
            assert!((v(n).length() - 1.0).abs() < 1e-5);
        }
    }
    // Indexed: each of the OBJ's 52 vertices is stored once per copy, however many triangles
    // share it, and the floor rectangle's four corners once.
    assert_eq!(s.geometry.points.len(), 2 * 52 + 4);
    assert_eq!(s.geometry.normals.len(), s.geometry.points.len());
}

#[test]
fn cornell_box_flattens_as_published() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-box.toml");
    let s = stratapt_import::scene_file::load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.geometry.len(), 2 + 5 * 2 + 10 * 2);
    assert_eq!(s.lights.len(), 1);
    let light = &s.lights[0];
    assert_eq!(light.kind, light_kind::RECTANGLE);
    assert_eq!(v(light.p1).cross(v(light.p2)).normalize(), Vec3::NEG_Y);
    assert!((v(light.p1).cross(v(light.p2)).length() - 130.0 * 105.0).abs() < 1e-2);
    assert!((s.camera.tan_half_fov - (39.3077f32.to_radians() / 2.0).tan()).abs() < 1e-6);
    assert_eq!((s.camera.width, s.camera.height), (256, 256));
}
