//! No self-intersection ("acne"): a ray leaving a hit point through the robust origin offset
//! never hits the surface it left — for spheres, disks and triangles at scales from 1e-3 to 1e4
//! and far from the origin — and a ray entering a sphere reaches its far side.

mod common;

use common::{prim, scene_of, Lcg};
use glam::Vec3;
use stratapt::cpu::accel::closest_hit;
use stratapt::cpu::intersect::Ray;
use stratapt::cpu::offset::spawn_origin;
use stratapt::scene::gpu::prim_kind;
use stratapt::scene::FlatScene;

fn single(kind: u32, a: Vec3, b: Vec3, c: Vec3) -> FlatScene {
    scene_of(vec![prim(kind, a, b, c)], Vec::new())
}

/// Shoot rays at the primitive from random outside points, then leave each hit point in random
/// directions on both sides. `convex_inside`: leaving to the back must reach the far side.
fn check(
    name: &str,
    scene: &FlatScene,
    center: Vec3,
    size: f32,
    convex_inside: bool,
    rng: &mut Lcg,
) {
    let mut hits = 0;
    for _ in 0..3000 {
        let origin = center + rng.unit() * (3.0 * size);
        let target = center + rng.unit() * (0.5 * size);
        let Some(hit) = closest_hit(
            scene,
            &Ray::new(origin, (target - origin).normalize(), f32::INFINITY),
            0.0,
        ) else {
            continue;
        };
        hits += 1;
        let facing = if hit.ng.dot(origin - hit.p) > 0.0 {
            hit.ng
        } else {
            -hit.ng
        };
        for _ in 0..4 {
            let mut dir = rng.unit();
            if dir.dot(facing).abs() < 1e-3 {
                continue;
            }
            // Back towards the side the ray came from: nothing to hit.
            if dir.dot(facing) < 0.0 {
                dir = -dir;
            }
            let out = Ray::new(spawn_origin(hit.p, hit.ng, dir), dir, f32::INFINITY);
            let again = closest_hit(scene, &out, 0.0);
            assert!(
                again.is_none(),
                "{name}: self-hit leaving {:?} towards {dir}: {again:?}",
                hit.p
            );
            // Through the surface: a sphere's far side, well away from the start.
            let into = Ray::new(spawn_origin(hit.p, hit.ng, -dir), -dir, f32::INFINITY);
            let far = closest_hit(scene, &into, 0.0);
            if convex_inside {
                let far =
                    far.unwrap_or_else(|| panic!("{name}: entering ray at {:?} escaped", hit.p));
                assert!(
                    far.t > 1e-3 * size * dir.dot(facing).abs(),
                    "{name}: self-hit entering at {:?}: {far:?}",
                    hit.p
                );
            } else {
                assert!(
                    far.is_none(),
                    "{name}: self-hit crossing at {:?}: {far:?}",
                    hit.p
                );
            }
        }
    }
    assert!(hits > 500, "{name}: only {hits} hits");
}

#[test]
fn rays_leaving_a_surface_do_not_hit_it_again() {
    let mut rng = Lcg(17);
    for (scale, offset) in [
        (1e-3f32, Vec3::ZERO),
        (1.0, Vec3::new(0.3, -0.2, 0.1)),
        (1e4, Vec3::ZERO),
        (1.0, Vec3::new(1e3, -2e3, 5e2)),
    ] {
        let c = offset + Vec3::new(0.1, 0.2, -0.3) * scale;
        let sphere = single(prim_kind::SPHERE, c, Vec3::new(scale, 0.0, 0.0), Vec3::ZERO);
        check(
            &format!("sphere ×{scale} at {offset}"),
            &sphere,
            c,
            scale,
            true,
            &mut rng,
        );
        let n = Vec3::new(0.3, 0.9, -0.2).normalize();
        let disk = single(prim_kind::DISK, c, n, Vec3::new(scale, 0.0, 0.0));
        check(
            &format!("disk ×{scale} at {offset}"),
            &disk,
            c,
            scale,
            false,
            &mut rng,
        );
        let (a, b, d) = (
            c + Vec3::new(-1.0, -0.3, 0.2) * scale,
            c + Vec3::new(1.0, -0.2, -0.4) * scale,
            c + Vec3::new(0.1, 1.0, 0.3) * scale,
        );
        let tri = single(prim_kind::TRIANGLE, a, b, d);
        check(
            &format!("triangle ×{scale} at {offset}"),
            &tri,
            (a + b + d) / 3.0,
            scale,
            false,
            &mut rng,
        );
    }
}
