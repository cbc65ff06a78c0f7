//! No self-intersection at any scale (pbrt-v4's `Triangle, Reintersect` test, on both
//! renderers): random triangles whose vertex coordinates range over 10⁻⁸ … 10⁸ of either sign,
//! spheres and disks over the same range, and moving triangles; rays from random points at
//! random points of each; from every hit a ray leaves in a random direction through the robust
//! origin (`spawn_origin` with the hit's error bound) and must not hit the primitive it left.
//! The triangle test's t error bound and the origin's error-bound offset together guarantee it.

use super::*;
use stratapt_cpu::intersect::{intersect_prim, surface, Ray};
use stratapt_cpu::offset::spawn_origin;
use stratapt_scene::records::prim_kind;

const REINTERSECT_PROBE: &str = r#"
fn probe(i: u32) {
    let b = i * 10u;
    let id = probe_in[b];
    let ray = ray_new(probe_v(b + 1u), probe_v(b + 4u), f32_infinity());
    let w = probe_v(b + 7u);
    let t = intersect_prim(prim_at(id), ray, 0.0);
    var again = f32_infinity();
    if (t < f32_infinity()) {
        let hit = intersect_surface(id, ray, t, 0.0);
        let out = ray_new(offset_spawn_origin(hit.p, hit.err, hit.ng, w), w, f32_infinity());
        again = intersect_prim(prim_at(id), out, 0.0);
    }
    probe_out[i * 2u] = bitcast<u32>(t);
    probe_out[i * 2u + 1u] = bitcast<u32>(again);
}
"#;

/// `±10^u`, `u` uniform in `[lo, hi]`.
fn signed_exp(rng: &mut Rng, lo: f32, hi: f32) -> f32 {
    let m = 10f32.powf(rng.range(lo, hi));
    if rng.f32() < 0.5 {
        -m
    } else {
        m
    }
}

fn exp_vec(rng: &mut Rng, lo: f32, hi: f32) -> Vec3 {
    Vec3::new(
        signed_exp(rng, lo, hi),
        signed_exp(rng, lo, hi),
        signed_exp(rng, lo, hi),
    )
}

fn toml_vec(v: Vec3) -> String {
    format!("[{}, {}, {}]", v.x, v.y, v.z)
}

/// 700 static triangles with coordinates `±10^[-8, 8]`, 100 spheres and 100 disks with centres
/// there (radii at least 10⁻³ of the centre's magnitude: smaller ones are not representable
/// in f32 around it), and 100 triangles moving by large rotations, translations and scales.
fn wild_scene(rng: &mut Rng) -> FlatScene {
    let mut toml = String::from(
        "[camera]\neye = [0, 0, -12]\nlook_at = [0, 0, 0]\nfov = 40\nshutter = [0, 1]\n\
         [materials.m]\ntype = \"diffuse\"\nalbedo = 0.5\n",
    );
    for i in 0..1000 {
        let shape = match i {
            0..700 => format!(
                "type = \"triangle\"\nvertices = [{}, {}, {}]\n",
                toml_vec(exp_vec(rng, -8.0, 8.0)),
                toml_vec(exp_vec(rng, -8.0, 8.0)),
                toml_vec(exp_vec(rng, -8.0, 8.0))
            ),
            700..900 => {
                let c = exp_vec(rng, -8.0, 8.0);
                let r = c.abs().max_element() * 10f32.powf(rng.range(-3.0, 1.0));
                if i < 800 {
                    format!(
                        "type = \"sphere\"\ncenter = {}\nradius = {r}\n",
                        toml_vec(c)
                    )
                } else {
                    // Half of them facing along an axis: the in-plane coordinates can then be
                    // far larger than the one across it, whose ULPs alone are no offset.
                    let mut n = rng.unit();
                    if i % 2 == 0 {
                        n = Vec3::ZERO;
                        n[i % 3] = 1.0;
                    }
                    format!(
                        "type = \"disk\"\ncenter = {}\nnormal = {}\nradius = {r}\n",
                        toml_vec(c),
                        toml_vec(n)
                    )
                }
            }
            _ => {
                let s = 10f32.powf(rng.range(-4.0, 4.0));
                let v = |rng: &mut Rng| toml_vec(rng.unit() * s);
                let pose = |rng: &mut Rng| {
                    format!(
                        "{{ translate = {}, rotate = {}, scale = {} }}",
                        toml_vec(exp_vec(rng, -4.0, 4.0)),
                        toml_vec(Vec3::new(
                            rng.range(-180.0, 180.0),
                            rng.range(-180.0, 180.0),
                            rng.range(-180.0, 180.0)
                        )),
                        10f32.powf(rng.range(-2.0, 2.0))
                    )
                };
                format!(
                    "type = \"triangle\"\nvertices = [{}, {}, {}]\ntransform = {}\n\
                     transform_close = {}\n",
                    v(rng),
                    v(rng),
                    v(rng),
                    pose(rng),
                    pose(rng)
                )
            }
        };
        toml.push_str(&format!("[[shapes]]\nmaterial = \"m\"\n{shape}"));
    }
    stratapt_import::load::load_str(&toml, Path::new("wild.toml")).unwrap_or_else(|e| panic!("{e}"))
}

/// A random point of `prim` (in its own space; moving primitives are aimed at through their
/// pose at time 0).
fn point_on(scene: &FlatScene, id: usize, rng: &mut Rng) -> Vec3 {
    let prim = &scene.geometry.prim(id as u32);
    let (a, b, c) = (Vec3::from(prim.a), Vec3::from(prim.b), Vec3::from(prim.c));
    let local = match prim.kind {
        prim_kind::TRIANGLE => {
            let (u, v) = (rng.f32(), rng.f32());
            let (u, v) = if u + v > 1.0 {
                (1.0 - u, 1.0 - v)
            } else {
                (u, v)
            };
            a * (1.0 - u - v) + b * u + c * v
        }
        prim_kind::SPHERE => a + rng.unit() * b.x,
        _ => {
            let t = (b.any_orthonormal_vector() * rng.range(-1.0, 1.0)
                + b.cross(b.any_orthonormal_vector()) * rng.range(-1.0, 1.0))
                * 0.7;
            a + t * c.x
        }
    };
    match stratapt_cpu::intersect::pose_at(&scene.motions, prim.motion, 0.0) {
        Some(pose) => pose.point_to_world(local),
        None => local,
    }
}

/// Whether a ray leaving `hit` in direction `w` and next meeting `prim` at `again` re-hit the
/// surface it left: any hit of a plane (triangle, disk); for a sphere, a hit leaving outwards, or
/// one inwards well short of the chord `2r |w · n|` to the far side.
fn rehits(
    prim: &stratapt_scene::Prim,
    hit: &stratapt_cpu::intersect::Hit,
    w: Vec3,
    again: f32,
) -> bool {
    if prim.kind != prim_kind::SPHERE || w.dot(hit.ng) > 0.0 {
        return again.is_finite();
    }
    let chord = 2.0 * prim.b[0] * w.dot(hit.ng).abs();
    // A miss (infinite) is no re-hit; NaN would be one.
    again.is_nan() || again <= 0.5 * chord
}

#[test]
fn spawned_rays_never_hit_the_primitive_they_leave_from_1e_minus_8_to_1e8() {
    let (device, queue) = device();
    let mut rng = Rng(2024);
    let scene = wild_scene(&mut rng);
    // CPU: 1000 rays per primitive; the GPU gets the first 100 of them.
    let (rays_cpu, rays_gpu) = (1000, 100);
    let mut input = Vec::new();
    let (mut hits, mut self_hits, mut unguarded, mut unoffset) = (0usize, 0usize, 0usize, 0usize);
    for id in 0..scene.geometry.len() {
        let prim = &scene.geometry.prim(id as u32);
        let scale = Vec3::from(prim.a).abs().max_element().max(1e-8);
        for k in 0..rays_cpu {
            let origin = point_on(&scene, id, &mut rng)
                + exp_vec(&mut rng, -8.0, 8.0).clamp_length_max(4.0 * scale)
                + rng.unit() * scale;
            let target = point_on(&scene, id, &mut rng);
            let Some(dir) = (target - origin).try_normalize() else {
                continue;
            };
            let w = rng.unit();
            if k < rays_gpu {
                input.push(id as u32);
                input.extend(bits(origin));
                input.extend(bits(dir));
                input.extend(bits(w));
            }
            let ray = Ray::new(origin, dir, f32::INFINITY);
            let t = intersect_prim(prim, &scene.motions, &scene.tables, &ray, 0.0);
            if !t.is_finite() {
                continue;
            }
            hits += 1;
            let hit = surface(id as u32, prim, &scene.motions, &ray, t, 0.0, None);
            let out = Ray::new(spawn_origin(hit.p, hit.err, hit.ng, w), w, f32::INFINITY);
            let again = intersect_prim(prim, &scene.motions, &scene.tables, &out, 0.0);
            if rehits(prim, &hit, w, again) {
                self_hits += 1;
                if self_hits < 10 {
                    println!("cpu self-hit: prim {id} {prim:?}, ray {ray:?}, hit {hit:?}, out {out:?}, t {again}");
                }
            }
            // The same without the error bound: the origin only stepped by ULPs of itself.
            let bare = Ray::new(spawn_origin(hit.p, Vec3::ZERO, hit.ng, w), w, f32::INFINITY);
            let bare_again = intersect_prim(prim, &scene.motions, &scene.tables, &bare, 0.0);
            unguarded += rehits(prim, &hit, w, bare_again) as usize;
            let none = Ray::new(hit.p, w, f32::INFINITY);
            unoffset += rehits(
                prim,
                &hit,
                w,
                intersect_prim(prim, &scene.motions, &scene.tables, &none, 0.0),
            ) as usize;
        }
    }
    let count = input.len() / 10;
    let out = testing::run_probe(
        &device,
        &queue,
        &scene,
        &scene.settings,
        MODULES,
        &format!("{PROBE_IO}{REINTERSECT_PROBE}"),
        &input,
        count * 2,
        count as u32,
    );
    let (mut gpu_hits, mut gpu_self_hits) = (0usize, 0usize);
    for i in 0..count {
        let [t, again] = [out[i * 2], out[i * 2 + 1]].map(f32::from_bits);
        if t.is_finite() {
            gpu_hits += 1;
            // The CPU's surface at the GPU's distance (for a sphere's normal and radius).
            let id = input[i * 10];
            let prim = &scene.geometry.prim(id);
            let ray = Ray::new(
                vec_at(&input, i * 10 + 1),
                vec_at(&input, i * 10 + 4),
                f32::INFINITY,
            );
            let hit = surface(id, prim, &scene.motions, &ray, t, 0.0, None);
            gpu_self_hits += rehits(prim, &hit, vec_at(&input, i * 10 + 7), again) as usize;
        }
    }
    println!(
        "cpu: {hits} hits, {self_hits} re-hit ({unguarded} without the error bound, {unoffset} from the hit point); \
         gpu: {gpu_hits} of {count} rays hit, {gpu_self_hits} re-hit"
    );
    assert!(
        hits > 300_000 && gpu_hits > 30_000,
        "too few hits to test: {hits}, {gpu_hits}"
    );
    assert_eq!(
        self_hits, 0,
        "cpu: {self_hits} of {hits} spawned rays re-hit their primitive"
    );
    assert_eq!(
        gpu_self_hits, 0,
        "gpu: {gpu_self_hits} of {gpu_hits} spawned rays re-hit"
    );
    // The test can see a missing error bound (axis-facing disks far from the origin) and a
    // missing offset.
    assert!(
        unguarded > 100,
        "without the error bound only {unguarded} re-hits"
    );
    assert!(
        unoffset > 10_000,
        "from the hit point itself only {unoffset} re-hits"
    );
}
