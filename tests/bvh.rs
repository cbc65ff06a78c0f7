//! BVH traversal against brute force, and watertightness of the triangle test.
//!
//! - 10k random rays (random times) over a random soup of triangles, spheres, disks and moving
//!   primitives: the BVH's closest hit has the same distance and primitive as testing every
//!   primitive, and shadow rays agree on occlusion;
//! - rays from inside closed meshes (a subdivided cube, icospheres near and far from the origin)
//!   aimed exactly at their vertices and at points of their shared edges always hit, through the
//!   BVH and by brute force; rays at the shared diagonal of a quad never pass through.

mod common;

use common::{prim, scene_of, triangle};
use glam::{Quat, Vec3};
use stratapt::cpu::accel::{closest_hit_brute_force, occluded_brute_force, Accel};
use stratapt::cpu::intersect::Ray;
use stratapt::sampling::testing::TestRng;
use stratapt::scene::records::{prim_kind, Motion, Pose};
use stratapt::scene::Prim;
use stratapt::scene::{bvh, FlatScene};

fn random_soup(rng: &mut TestRng) -> FlatScene {
    let mut prims = Vec::new();
    for _ in 0..3000 {
        let a = rng.point(10.0);
        let size = rng.range(0.05, 2.0);
        prims.push(triangle(a, a + rng.unit() * size, a + rng.unit() * size));
    }
    for _ in 0..300 {
        let r = rng.range(0.01, 1.0);
        prims.push(prim(
            prim_kind::SPHERE,
            rng.point(10.0),
            Vec3::new(r, 0.0, 0.0),
            Vec3::ZERO,
        ));
    }
    for _ in 0..300 {
        let r = rng.range(0.05, 1.5);
        prims.push(prim(
            prim_kind::DISK,
            rng.point(10.0),
            rng.unit(),
            Vec3::new(r, 0.0, 0.0),
        ));
    }
    // Moving primitives: translation + rotation + scale between open and close.
    let mut motions = Vec::new();
    for k in 0..12 {
        let open = Pose::new(
            rng.point(8.0),
            Quat::from_axis_angle(rng.unit(), rng.range(0.0, 3.0)),
            Vec3::splat(rng.range(0.5, 2.0)),
        );
        let close = Pose::new(
            rng.point(8.0),
            Quat::from_axis_angle(rng.unit(), rng.range(0.0, 3.0)),
            Vec3::splat(rng.range(0.5, 2.0)),
        );
        motions.push(Motion { open, close });
        let mut p = match k % 3 {
            0 => triangle(rng.point(1.0), rng.point(1.0), rng.point(1.0)),
            1 => prim(
                prim_kind::SPHERE,
                rng.point(0.5),
                Vec3::new(rng.range(0.2, 1.0), 0.0, 0.0),
                Vec3::ZERO,
            ),
            _ => prim(
                prim_kind::DISK,
                rng.point(0.5),
                rng.unit(),
                Vec3::new(rng.range(0.2, 1.0), 0.0, 0.0),
            ),
        };
        p.motion = k;
        prims.push(p);
    }
    scene_of(prims, motions)
}

/// Both obvhs builds strata uses (`bvh::build_params`: medium below
/// `FAST_BUILD_PRIMS` primitives, fast from there) find what brute force finds.
#[test]
fn bvh_matches_brute_force_on_random_rays() {
    let mut rng = TestRng(42);
    let mut scene = random_soup(&mut rng);
    assert!(scene.geometry.len() < bvh::FAST_BUILD_PRIMS);
    matches_brute_force(&scene, &mut rng);
    let (fast, _, _) = bvh::build_with(
        &mut scene.geometry,
        &scene.motions,
        bvh::build_params(bvh::FAST_BUILD_PRIMS),
    );
    // A different tree: the node counts differ.
    assert_ne!(fast.nodes.len(), scene.bvh.nodes.len());
    scene.bvh = fast;
    matches_brute_force(&scene, &mut rng);
}

fn matches_brute_force(scene: &FlatScene, rng: &mut TestRng) {
    let accel = Accel::new(scene);
    let (mut hits, mut blocked) = (0, 0);
    for i in 0..10_000 {
        let origin = rng.point(14.0);
        let dir = rng.unit();
        let time = rng.f32();
        let ray = Ray::new(origin, dir, f32::INFINITY);
        let (bvh, brute) = (
            accel.closest_hit(&ray, time),
            closest_hit_brute_force(scene, &ray, time),
        );
        match (bvh, brute) {
            (None, None) => {}
            (Some(a), Some(b)) => {
                assert_eq!(
                    (a.t, a.prim),
                    (b.t, b.prim),
                    "ray {i}: bvh {a:?} vs brute force {b:?}"
                );
                hits += 1;
            }
            _ => panic!("ray {i} {ray:?} at t = {time}: bvh {bvh:?} vs brute force {brute:?}"),
        }
        // Shadow ray over a random segment.
        let shadow = Ray::new(origin, dir, rng.range(0.0, 20.0));
        let (a, b) = (
            accel.occluded(&shadow, time),
            occluded_brute_force(scene, &shadow, time),
        );
        assert_eq!(a, b, "shadow ray {i} {shadow:?} at t = {time}");
        blocked += a as u32;
    }
    // The soup is dense enough that both answers occur often.
    assert!(hits > 2000 && hits < 9900, "{hits} hits");
    assert!(blocked > 1000 && blocked < 9900, "{blocked} blocked");
}

#[test]
fn moving_primitive_is_found_where_it_is_at_the_ray_time() {
    // A unit sphere moving from x = −5 to x = 5: a ray down the z axis at x = 5t hits it only
    // around its time.
    let motion = Motion {
        open: Pose::new(Vec3::new(-5.0, 0.0, 0.0), Quat::IDENTITY, Vec3::ONE),
        close: Pose::new(Vec3::new(5.0, 0.0, 0.0), Quat::IDENTITY, Vec3::ONE),
    };
    let mut sphere = prim(
        prim_kind::SPHERE,
        Vec3::ZERO,
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::ZERO,
    );
    sphere.motion = 0;
    let scene = scene_of(vec![sphere], vec![motion]);
    let accel = Accel::new(&scene);
    for k in 0..=10 {
        let t = k as f32 / 10.0;
        let x = -5.0 + 10.0 * t;
        let hit = accel
            .closest_hit(
                &Ray::new(Vec3::new(x, 0.0, -5.0), Vec3::Z, f32::INFINITY),
                t,
            )
            .unwrap();
        assert!(
            (hit.t - 4.0).abs() < 1e-4 && (hit.p - Vec3::new(x, 0.0, -1.0)).length() < 1e-4,
            "{hit:?}"
        );
        assert!((hit.ng + Vec3::Z).length() < 1e-4);
        let other = if t < 0.5 { 0.9 } else { 0.1 };
        assert!(accel
            .closest_hit(
                &Ray::new(Vec3::new(x, 0.0, -5.0), Vec3::Z, f32::INFINITY),
                other
            )
            .is_none());
    }
}

#[test]
fn empty_scene_has_no_hits() {
    let scene = scene_of(Vec::new(), Vec::new());
    let ray = Ray::new(Vec3::ZERO, Vec3::Z, f32::INFINITY);
    let accel = Accel::new(&scene);
    assert!(accel.closest_hit(&ray, 0.0).is_none());
    assert!(!accel.occluded(&ray, 0.0));
}

// ---------------------------------------------------------------------------------------------
// Watertightness
// ---------------------------------------------------------------------------------------------

/// Indexed mesh: vertices shared bit for bit between the triangles that use them.
struct Mesh {
    vertices: Vec<Vec3>,
    triangles: Vec<[usize; 3]>,
}

impl Mesh {
    fn prims(&self) -> Vec<Prim> {
        self.triangles
            .iter()
            .map(|t| {
                triangle(
                    self.vertices[t[0]],
                    self.vertices[t[1]],
                    self.vertices[t[2]],
                )
            })
            .collect()
    }

    fn edges(&self) -> Vec<(Vec3, Vec3)> {
        self.triangles
            .iter()
            .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
            .map(|(a, b)| (self.vertices[a], self.vertices[b]))
            .collect()
    }
}

/// The cube `[-1, 1]³` (scaled and shifted), each face an `n × n` grid of quads split in two.
fn subdivided_cube(n: usize, scale: f32, shift: Vec3) -> Mesh {
    let mut vertices = Vec::new();
    let mut index = std::collections::HashMap::new();
    let mut triangles = Vec::new();
    // Grid coordinate in [-1, 1] from an integer, computed one way only.
    let coord = |i: usize| -1.0 + 2.0 * i as f32 / n as f32;
    let mut vertex = |p: [usize; 3]| -> usize {
        *index.entry(p).or_insert_with(|| {
            vertices.push(Vec3::new(coord(p[0]), coord(p[1]), coord(p[2])) * scale + shift);
            vertices.len() - 1
        })
    };
    for axis in 0..3 {
        for side in [0, n] {
            for i in 0..n {
                for j in 0..n {
                    let at = |di: usize, dj: usize| {
                        let mut p = [0; 3];
                        p[axis] = side;
                        p[(axis + 1) % 3] = i + di;
                        p[(axis + 2) % 3] = j + dj;
                        p
                    };
                    let (a, b, c, d) = (
                        vertex(at(0, 0)),
                        vertex(at(1, 0)),
                        vertex(at(1, 1)),
                        vertex(at(0, 1)),
                    );
                    // Alternate the diagonal so that both orientations are exercised.
                    if (i + j) % 2 == 0 {
                        triangles.extend([[a, b, c], [a, c, d]]);
                    } else {
                        triangles.extend([[a, b, d], [b, c, d]]);
                    }
                }
            }
        }
    }
    Mesh {
        vertices,
        triangles,
    }
}

/// Icosahedron subdivided `levels` times, projected onto the sphere of `radius` about `center`.
fn icosphere(levels: usize, radius: f32, center: Vec3) -> Mesh {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut unit: Vec<Vec3> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .map(|p| Vec3::from(p).normalize())
    .to_vec();
    let mut triangles: Vec<[usize; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut midpoints = std::collections::HashMap::new();
        let mut mid = |a: usize, b: usize, unit: &mut Vec<Vec3>| -> usize {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                unit.push((unit[a] + unit[b]).normalize());
                unit.len() - 1
            })
        };
        let mut next = Vec::new();
        for [a, b, c] in triangles {
            let (ab, bc, ca) = (
                mid(a, b, &mut unit),
                mid(b, c, &mut unit),
                mid(c, a, &mut unit),
            );
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        triangles = next;
    }
    Mesh {
        vertices: unit.into_iter().map(|v| v * radius + center).collect(),
        triangles,
    }
}

/// Every ray from each origin towards each vertex, edge point and triangle corner hits the
/// closed mesh, through the BVH and by brute force.
fn assert_closed(name: &str, mesh: &Mesh, origins: &[Vec3]) {
    let scene = scene_of(mesh.prims(), Vec::new());
    let accel = Accel::new(&scene);
    let mut targets: Vec<Vec3> = mesh.vertices.clone();
    for (a, b) in mesh.edges() {
        // Points on the shared edge, as the f32 lerp computes them (on or next to the edge).
        targets.extend([0.5f32, 0.25, 1.0 / 3.0].map(|s| a.lerp(b, s)));
    }
    let mut rays = 0;
    for &o in origins {
        for &target in &targets {
            let dir = (target - o).normalize();
            let ray = Ray::new(o, dir, f32::INFINITY);
            assert!(
                closest_hit_brute_force(&scene, &ray, 0.0).is_some(),
                "{name}: ray from {o} to {target} leaked"
            );
            assert!(
                accel.closest_hit(&ray, 0.0).is_some(),
                "{name}: ray from {o} to {target} leaked (bvh)"
            );
            rays += 1;
        }
    }
    assert!(rays > 1000);
}

#[test]
fn closed_meshes_are_watertight_from_inside() {
    let cube = subdivided_cube(7, 1.3, Vec3::new(0.1, -0.2, 0.3));
    let origins = [
        Vec3::new(0.1, -0.2, 0.3),
        Vec3::new(0.7, 0.5, -0.4),
        Vec3::new(-0.9, 0.9, 1.2),
        Vec3::new(0.1, -0.2, 0.3 + 1.29),
    ];
    assert_closed("cube", &cube, &origins);
    let sphere = icosphere(3, 2.0, Vec3::new(3.0, 1.0, -2.0));
    let origins = [
        Vec3::new(3.0, 1.0, -2.0),
        Vec3::new(3.5, 0.2, -1.1),
        Vec3::new(1.2, 1.3, -2.1),
    ];
    assert_closed("icosphere", &sphere, &origins);
    // Far from the origin, where f32 spacing is coarse.
    let far = icosphere(2, 0.5, Vec3::new(1000.0, -2000.0, 500.0));
    assert_closed("far icosphere", &far, &[Vec3::new(1000.1, -2000.05, 500.0)]);
}

#[test]
fn quad_diagonal_never_leaks() {
    let (p0, p1, p2, p3) = (
        Vec3::new(-1.0, 0.0, -1.0),
        Vec3::new(1.0, 0.0, -1.0),
        Vec3::new(1.0, 0.0, 1.0),
        Vec3::new(-1.0, 0.0, 1.0),
    );
    let scene = scene_of(vec![triangle(p0, p1, p2), triangle(p0, p2, p3)], Vec::new());
    let accel = Accel::new(&scene);
    let mut rng = TestRng(9);
    for i in 0..20_000 {
        let s = if i % 2 == 0 {
            rng.f32()
        } else {
            i as f32 / 20_000.0
        };
        let target = p0.lerp(p2, s);
        let origin = target + rng.unit() * rng.range(0.1, 10.0);
        if (origin.y).abs() < 1e-3 {
            continue;
        }
        let ray = Ray::new(origin, (target - origin).normalize(), f32::INFINITY);
        assert!(
            accel.closest_hit(&ray, 0.0).is_some(),
            "ray {i} from {origin} to {target} leaked"
        );
    }
}
