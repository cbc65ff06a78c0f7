//! `shaders/camera.wgsl` (with `filter.wgsl`, `frame.wgsl` and `warp.wgsl`) against
//! `stratapt_cpu::camera::generate_ray`: origin and direction of camera rays for the scenes of
//! `scenes/` and every pixel filter, over many (pixel, u_pixel, u_lens, time). Runs on lavapipe.

use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};
use stratapt_cpu::camera::generate_ray;
use stratapt_gpu::testing;
use stratapt_sampling::hash::lowbias32;
use stratapt_sampling::sampler::to_unit_float;
use stratapt_scene::records::{filter_kind, Camera};
use stratapt_scene::{FlatScene, RenderSettings};

/// Relative tolerance on origins and directions (vector norm, relative to max(|expected|, 1)).
const TOLERANCE: f32 = 1e-5;

/// The tolerance for rays of `camera` at shutter time `time`. At `time` 0 or 1 the pose lerp
/// `a (1 − t) + b t` is exact, so [`TOLERANCE`]. In between, eye and target are rounded at their
/// own magnitude before `target − eye` is formed (and the GPU may fuse the lerp's multiply-add),
/// so the forward direction is only known to about `ε · max|coordinate| / |target − eye|`: for
/// the Cornell box's camera, a unit in front of an eye 800 units from the origin, that is
/// ~10⁻⁴, not 10⁻⁵. (`lerp_monotonic`, `a + (b − a) t`, would keep a still camera exact.)
fn tolerance(camera: &Camera, time: f32) -> f32 {
    if time == 0.0 || time == 1.0 {
        return TOLERANCE;
    }
    let v = Vec3::from_array;
    let size = [camera.eye0, camera.eye1, camera.target0, camera.target1]
        .into_iter()
        .map(|p| v(p).abs().max_element())
        .fold(0.0, f32::max);
    let reach = (v(camera.target0) - v(camera.eye0))
        .length()
        .min((v(camera.target1) - v(camera.eye1)).length());
    TOLERANCE.max(2.0 * f32::EPSILON * size / reach)
}

/// The modules the camera needs, in composition order.
const MODULES: &[&str] = &["camera"];

const PROBE: &str = r#"
fn probe(i: u32) {
    let b = 8u * i;
    let pixel = vec2u(probe_in[b], probe_in[b + 1u]);
    let u_pixel = vec2f(bitcast<f32>(probe_in[b + 2u]), bitcast<f32>(probe_in[b + 3u]));
    let u_lens = vec2f(bitcast<f32>(probe_in[b + 4u]), bitcast<f32>(probe_in[b + 5u]));
    let time = bitcast<f32>(probe_in[b + 6u]);
    let ray = camera_generate_ray(pixel, u_pixel, u_lens, time);
    let o = 6u * i;
    probe_out[o] = bitcast<u32>(ray.origin.x);
    probe_out[o + 1u] = bitcast<u32>(ray.origin.y);
    probe_out[o + 2u] = bitcast<u32>(ray.origin.z);
    probe_out[o + 3u] = bitcast<u32>(ray.dir.x);
    probe_out[o + 4u] = bitcast<u32>(ray.dir.y);
    probe_out[o + 5u] = bitcast<u32>(ray.dir.z);
}
"#;

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

fn load(name: &str) -> FlatScene {
    stratapt_import::scene_file::load(&scenes_dir().join(name))
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// One camera-ray query.
#[derive(Clone, Copy, Debug)]
struct Query {
    pixel: [u32; 2],
    u_pixel: Vec2,
    u_lens: Vec2,
    time: f32,
}

/// Hashed unit float number `k` of stream `s` (24-bit, like the samplers').
fn unit(s: u32, k: u32) -> f32 {
    to_unit_float(lowbias32(lowbias32(s) ^ k.wrapping_mul(0x9e37_79b9)))
}

/// Film corners and random pixels; u's at the domain edges, the centre, and random; times at
/// the shutter ends and random.
fn queries(camera: &Camera) -> Vec<Query> {
    let (w, h) = (camera.width, camera.height);
    let last = 1.0 - 1.0 / 16_777_216.0;
    let edge_u = [
        Vec2::ZERO,
        Vec2::splat(0.5),
        Vec2::splat(last),
        Vec2::new(0.0, last),
        Vec2::new(0.25, 0.5),
        Vec2::new(0.5, 0.75),
    ];
    let mut out = Vec::new();
    for (k, pixel) in [
        [0, 0],
        [w - 1, 0],
        [0, h - 1],
        [w - 1, h - 1],
        [w / 2, h / 2],
    ]
    .into_iter()
    .enumerate()
    {
        for (j, &u) in edge_u.iter().enumerate() {
            out.push(Query {
                pixel,
                u_pixel: u,
                u_lens: edge_u[(j + k) % edge_u.len()],
                time: [0.0, 1.0, 0.5][(j + k) % 3],
            });
        }
    }
    for k in 0..500 {
        let r = |s| unit(s, k);
        out.push(Query {
            pixel: [lowbias32(k) % w, lowbias32(k ^ 0x5555) % h],
            u_pixel: Vec2::new(r(1), r(2)),
            u_lens: Vec2::new(r(3), r(4)),
            time: r(5),
        });
    }
    out
}

/// GPU rays for `queries` under the scene's camera: (origin, dir) each.
fn gpu_rays(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    scene: &FlatScene,
    queries: &[Query],
) -> Vec<(Vec3, Vec3)> {
    let input: Vec<u32> = queries
        .iter()
        .flat_map(|q| {
            [
                q.pixel[0],
                q.pixel[1],
                q.u_pixel.x.to_bits(),
                q.u_pixel.y.to_bits(),
                q.u_lens.x.to_bits(),
                q.u_lens.y.to_bits(),
                q.time.to_bits(),
                0,
            ]
        })
        .collect();
    let n = queries.len();
    let out = testing::run_probe(
        device,
        queue,
        scene,
        &RenderSettings::default(),
        MODULES,
        PROBE,
        &input,
        6 * n,
        n as u32,
    );
    out.chunks_exact(6)
        .map(|c| {
            let f = |i: usize| f32::from_bits(c[i]);
            (Vec3::new(f(0), f(1), f(2)), Vec3::new(f(3), f(4), f(5)))
        })
        .collect()
}

/// The CPU ray, called as the CPU integrator calls it: a lens sample only when the scene has
/// a lens domain (`lens_radius > 0`).
fn cpu_ray(camera: &Camera, q: &Query) -> (Vec3, Vec3) {
    let u_lens = (camera.lens_radius > 0.0).then_some(q.u_lens);
    generate_ray(camera, q.pixel, q.u_pixel, u_lens, q.time)
}

fn close(a: Vec3, b: Vec3, tolerance: f32) -> bool {
    (a - b).length() <= tolerance * b.length().max(1.0)
}

/// Compare GPU and CPU rays for `scene`; returns the number compared.
fn check(device: &wgpu::Device, queue: &wgpu::Queue, label: &str, scene: &FlatScene) -> usize {
    let queries = queries(&scene.camera);
    let got = gpu_rays(device, queue, scene, &queries);
    let mut bad = Vec::new();
    for (q, &(o, d)) in queries.iter().zip(&got) {
        let (eo, ed) = cpu_ray(&scene.camera, q);
        let tol = tolerance(&scene.camera, q.time);
        if !close(o, eo, tol) || !close(d, ed, tol) {
            bad.push(format!("{q:?}: gpu ({o}, {d}) cpu ({eo}, {ed})"));
        }
    }
    assert!(
        bad.is_empty(),
        "{label}: {} of {} rays differ, first:\n{}",
        bad.len(),
        queries.len(),
        bad[..bad.len().min(10)].join("\n")
    );
    queries.len()
}

/// Every scene of `scenes/` with its own camera and filter.
#[test]
fn rays_match_cpu_for_every_scene() {
    let (device, queue) = testing::software_device().unwrap_or_else(|e| panic!("{e}"));
    let mut names: Vec<String> = std::fs::read_dir(scenes_dir())
        .unwrap()
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.ends_with(".toml"))
        .collect();
    names.sort();
    assert!(names.iter().any(|n| n == "depth-of-field.toml"));
    assert!(names.iter().any(|n| n == "motion-blur-camera.toml"));
    let mut total = 0;
    for name in &names {
        total += check(&device, &queue, name, &load(name));
    }
    println!("camera: {total} rays over {} scenes agree", names.len());
}

/// Depth of field and camera motion blur under every filter kind and width; and the thin-lens
/// scene with its aperture closed (the CPU passes no lens sample then).
#[test]
fn rays_match_cpu_for_every_filter() {
    let (device, queue) = testing::software_device().unwrap_or_else(|e| panic!("{e}"));
    let filters = [
        (filter_kind::BOX, 1.0),
        (filter_kind::BOX, 2.5),
        (filter_kind::TENT, 1.0),
        (filter_kind::TENT, 1.5),
        (filter_kind::GAUSSIAN, 0.5),
        (filter_kind::GAUSSIAN, 1.2),
    ];
    let mut total = 0;
    for name in ["depth-of-field.toml", "motion-blur-camera.toml"] {
        for (filter, param) in filters {
            let mut scene = load(name);
            scene.camera.filter = filter;
            scene.camera.filter_param = param;
            total += check(
                &device,
                &queue,
                &format!("{name} filter {filter}/{param}"),
                &scene,
            );
        }
    }
    let mut pinhole = load("depth-of-field.toml");
    assert!(pinhole.camera.lens_radius > 0.0);
    pinhole.camera.lens_radius = 0.0;
    total += check(&device, &queue, "depth-of-field, aperture 0", &pinhole);
    println!("camera: {total} rays over every filter agree");
}

/// The camera module and the modules it needs parse and validate (no device).
#[test]
fn modules_validate() {
    let probe = format!(
        "{PROBE}\n@group(1) @binding(0) var<storage, read> probe_in: array<u32>;\n\
         @group(1) @binding(1) var<storage, read_write> probe_out: array<u32>;\n"
    );
    if let Err(e) = testing::compose(MODULES, &probe) {
        panic!("{MODULES:?}: {e}");
    }
}
