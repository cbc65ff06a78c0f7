//! Eight rays per AVX2 vector (the `stream8` prototype) against one ray at a time, on the same
//! rays: what traversing eight paths together would gain the CPU reference (issue 28).
//!
//!     cargo bench -p stratapt-cpu --bench stream8 [-- SCENE.toml ...] [--rounds N]
//!
//! For each scene (default: the Cornell box and the mesh scene) it makes three sets of rays the
//! way a path tracer with eight paths per vector would meet them: camera rays through eight
//! neighbouring pixels (coherent), the first bounce of each (a cosine-distributed direction at
//! its hit: incoherent), and a shadow ray from each camera ray's hit to a random point in the
//! scene's box (a light's stand-in: traversal does not care what is at the far end). It checks
//! that both traversals
//! find the same primitive at the same distance for every ray (exact ties aside), then times
//! each, alternating, ROUNDS times (default 5), and prints the median rays per second and the
//! median of the rounds' ratios. One thread.

use glam::{Vec2, Vec3};
use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::time::Instant;
use stratapt_cpu::accel::stream8::{PrimHit, WIDTH};
use stratapt_cpu::accel::Accel;
use stratapt_cpu::camera::generate_ray;
use stratapt_cpu::intersect::Ray;
use stratapt_cpu::offset::spawn_origin;
use stratapt_sampling::frame::Frame;
use stratapt_sampling::warp::cosine_hemisphere;
use stratapt_scene::FlatScene;

/// A small, fast generator for the rays (SplitMix64).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    }
    fn vec2(&mut self) -> Vec2 {
        Vec2::new(self.next(), self.next())
    }
}

/// Camera rays (pixels in row order, so eight consecutive rays are neighbours), their first
/// bounces (for those that hit) and shadow rays from the bounce origins.
fn rays(scene: &FlatScene, accel: &Accel, count: usize) -> [Vec<Ray>; 3] {
    let camera = &scene.camera;
    let mut rng = Rng(7);
    let (lo, hi) = scene_box(scene);
    let (mut primary, mut bounce, mut shadow) = (Vec::new(), Vec::new(), Vec::new());
    let pixels = camera.width * camera.height;
    let mut p = 0u32;
    while primary.len() < count {
        let pixel = [p % camera.width, (p / camera.width) % camera.height];
        p = (p + 1) % pixels;
        let (o, d) = generate_ray(camera, pixel, rng.vec2(), None, 0.0);
        let ray = Ray::new(o, d, f32::INFINITY);
        primary.push(ray);
        let Some(hit) = accel.closest_hit(&ray, 0.0) else {
            continue;
        };
        let n = if hit.ng.dot(d) < 0.0 { hit.ng } else { -hit.ng };
        let dir = Frame::from_normal(n).to_world(cosine_hemisphere(rng.vec2()));
        let origin = spawn_origin(hit.p, hit.err, hit.ng, dir);
        bounce.push(Ray::new(origin, dir, f32::INFINITY));
        // A shadow ray towards a random point of the scene's box (a light's stand-in: the
        // traversal does not care what is at the far end).
        let target = lo + (hi - lo) * Vec3::new(rng.next(), rng.next(), rng.next());
        let to = target - hit.p;
        let dir = to.normalize();
        let origin = spawn_origin(hit.p, hit.err, hit.ng, dir);
        shadow.push(Ray::new(origin, dir, to.length() * 0.999));
    }
    for set in [&mut bounce, &mut shadow] {
        let whole = set.len() / WIDTH * WIDTH;
        set.truncate(whole);
    }
    primary.truncate(primary.len() / WIDTH * WIDTH);
    [primary, bounce, shadow]
}

fn scene_box(scene: &FlatScene) -> (Vec3, Vec3) {
    let root = scene.bvh.nodes[0].aabb();
    (Vec3::from(root.min), Vec3::from(root.max))
}

/// The same hit distance (an exact tie may resolve to the other primitive).
fn same(a: PrimHit, b: PrimHit) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some((_, ta)), Some((_, tb))) => ta.to_bits() == tb.to_bits(),
        _ => false,
    }
}

/// Seconds for one pass over `rays`, one at a time or eight at a time.
fn time_pass(accel: &Accel, rays: &[Ray], shadow: bool, packets: bool) -> f64 {
    let start = Instant::now();
    let mut count = 0usize;
    if packets {
        for chunk in rays.chunks_exact(WIDTH) {
            let chunk: &[Ray; WIDTH] = chunk.try_into().unwrap();
            if shadow {
                count += accel.occluded8(chunk, 0.0).iter().filter(|b| **b).count();
            } else {
                count += accel
                    .closest8(chunk, 0.0)
                    .iter()
                    .filter(|h| h.is_some())
                    .count();
            }
        }
    } else {
        for ray in rays {
            if shadow {
                count += accel.occluded_prim(ray, 0.0) as usize;
            } else {
                count += accel.closest_prim(ray, 0.0).is_some() as usize;
            }
        }
    }
    black_box(count);
    start.elapsed().as_secs_f64()
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut scenes = Vec::new();
    let mut rounds = 5;
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--rounds" => rounds = args.next().and_then(|r| r.parse().ok()).unwrap_or(5),
            "--bench" => {}
            other => scenes.push(PathBuf::from(other)),
        }
    }
    if scenes.is_empty() {
        scenes = ["scenes/cornell-box.toml", "scenes/mesh.toml"]
            .map(|s| root.join(s))
            .to_vec();
    }
    println!("eight rays per vector (stream8) against one at a time, one thread, {rounds} rounds");
    for path in &scenes {
        let scene = match stratapt_import::scene_file::load(Path::new(path)) {
            Ok(scene) => scene,
            Err(e) => {
                eprintln!("{}: {e}", path.display());
                std::process::exit(1);
            }
        };
        let accel = Accel::new(&scene);
        let sets = rays(&scene, &accel, 1 << 18);
        println!("{} ({} primitives)", path.display(), scene.geometry.len());
        for (name, set, shadow) in [
            ("camera rays", &sets[0], false),
            ("first bounces", &sets[1], false),
            ("shadow rays", &sets[2], true),
        ] {
            // Both find the same hits.
            let mut differ = 0;
            for chunk in set.chunks_exact(WIDTH) {
                let chunk: &[Ray; WIDTH] = chunk.try_into().unwrap();
                if shadow {
                    let eight = accel.occluded8(chunk, 0.0);
                    differ += chunk
                        .iter()
                        .zip(eight)
                        .filter(|(r, b)| accel.occluded_prim(r, 0.0) != *b)
                        .count();
                } else {
                    let eight = accel.closest8(chunk, 0.0);
                    differ += chunk
                        .iter()
                        .zip(eight)
                        .filter(|(r, h)| !same(accel.closest_prim(r, 0.0), *h))
                        .count();
                }
            }
            let (mut one, mut eight, mut ratio) = (Vec::new(), Vec::new(), Vec::new());
            for _ in 0..rounds {
                let a = time_pass(&accel, set, shadow, false);
                let b = time_pass(&accel, set, shadow, true);
                one.push(set.len() as f64 / a / 1e6);
                eight.push(set.len() as f64 / b / 1e6);
                ratio.push(a / b);
            }
            println!(
                "  {name:<14} {:>7} rays: one at a time {:6.2} M rays/s, eight {:6.2} M rays/s, \
                 speed-up {:.3}× (different hits: {differ})",
                set.len(),
                median(one),
                median(eight),
                median(ratio)
            );
        }
    }
}
