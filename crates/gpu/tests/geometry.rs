//! `shaders/{motion,offset,intersect,bvh,cwbvh}.wgsl` against the CPU reference, on lavapipe: poses of
//! moving objects, robust ray origins, and closest-hit / any-hit BVH queries over every scene of
//! `scenes/` plus a generated cluttered scene (random rays, random shutter times).

use glam::Vec3;
use std::path::{Path, PathBuf};
use stratapt_gpu::cwbvh::Cwbvh;
use stratapt_gpu::testing;
use stratapt_sampling::testing::TestRng as Rng;
use stratapt_scene::records::{Motion, Pose};
use stratapt_scene::FlatScene;

#[path = "geometry/pose.rs"]
mod pose;
#[path = "geometry/queries.rs"]
mod queries;
#[path = "geometry/reintersect.rs"]
mod reintersect;

const MODULES: &[&str] = &["offset", "accel"];

/// WGSL the probes share: read a float or a vec3 of `probe_in`, write a vec3 to `probe_out`.
const PROBE_IO: &str = r#"
fn probe_f(i: u32) -> f32 { return bitcast<f32>(probe_in[i]); }
fn probe_v(i: u32) -> vec3f { return vec3f(probe_f(i), probe_f(i + 1u), probe_f(i + 2u)); }
fn probe_put(i: u32, v: vec3f) {
    probe_out[i] = bitcast<u32>(v.x);
    probe_out[i + 1u] = bitcast<u32>(v.y);
    probe_out[i + 2u] = bitcast<u32>(v.z);
}
"#;

fn bits(v: Vec3) -> [u32; 3] {
    v.to_array().map(f32::to_bits)
}

fn vec_at(words: &[u32], i: usize) -> Vec3 {
    Vec3::new(
        f32::from_bits(words[i]),
        f32::from_bits(words[i + 1]),
        f32::from_bits(words[i + 2]),
    )
}

fn device() -> (wgpu::Device, wgpu::Queue) {
    testing::software_device().unwrap_or_else(|e| panic!("{e}"))
}

fn load(path: &Path) -> FlatScene {
    stratapt_import::scene_file::load(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn scene_files() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let files = stratapt_import::load::scene_files(&dir).unwrap();
    assert!(files.len() >= 10, "scenes/ holds {} scenes", files.len());
    files
}

/// Many small random triangles, spheres and disks, some of them moving (translating, rotating by
/// large angles, scaling), so the BVH is deeper than in the bundled scenes.
fn cluttered_scene() -> FlatScene {
    let mut rng = Rng(99);
    let mut toml = String::from(
        "[camera]\neye = [0, 0, -12]\nlook_at = [0, 0, 0]\nfov = 40\nshutter = [0, 1]\n\
         [materials.m]\ntype = \"diffuse\"\nalbedo = 0.5\n",
    );
    let v = |rng: &mut Rng, s: f32| {
        format!(
            "[{}, {}, {}]",
            rng.range(-s, s),
            rng.range(-s, s),
            rng.range(-s, s)
        )
    };
    for i in 0..600 {
        let c = v(&mut rng, 4.0);
        let shape = match i % 4 {
            0 | 1 => {
                let (a, b) = (v(&mut rng, 0.5), v(&mut rng, 0.5));
                format!("type = \"triangle\"\nvertices = [{c}, {a}, {b}]\n")
            }
            2 => format!(
                "type = \"sphere\"\ncenter = {c}\nradius = {}\n",
                rng.range(0.05, 0.4)
            ),
            _ => format!(
                "type = \"disk\"\ncenter = {c}\nnormal = {}\nradius = {}\n",
                v(&mut rng, 1.0),
                rng.range(0.05, 0.4)
            ),
        };
        toml.push_str(&format!("[[shapes]]\nmaterial = \"m\"\n{shape}"));
        if i % 5 == 0 {
            toml.push_str(&format!(
                "transform = {{ translate = {}, rotate = {}, scale = {} }}\n\
                 transform_close = {{ translate = {}, rotate = {}, scale = {} }}\n",
                v(&mut rng, 1.0),
                v(&mut rng, 180.0),
                rng.range(0.5, 1.5),
                v(&mut rng, 1.0),
                v(&mut rng, 180.0),
                rng.range(0.5, 1.5),
            ));
        }
    }
    stratapt_import::load::load_str(&toml, Path::new("cluttered.toml"))
        .unwrap_or_else(|e| panic!("{e}"))
}

/// Depth of the BVH (root = 0) and, with it, the traversal stack the GPU needs.
fn bvh_depth(scene: &FlatScene) -> usize {
    let nodes = &scene.bvh.nodes;
    if nodes.is_empty() {
        return 0;
    }
    let mut deepest = 0;
    let mut todo = vec![(0usize, 0usize)];
    while let Some((i, depth)) = todo.pop() {
        deepest = deepest.max(depth);
        if nodes[i].prim_count == 0 {
            let first = nodes[i].first_index as usize;
            todo.push((first, depth + 1));
            todo.push((first + 1, depth + 1));
        }
    }
    deepest
}

// ---------------------------------------------------------------------------------------------
// Validation (no device)
// ---------------------------------------------------------------------------------------------

#[test]
fn geometry_modules_validate() {
    testing::compose(MODULES, "").unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn bvh_depth_fits_the_gpu_stack() {
    // bvh.wgsl keeps 64 pending subtrees; a tree of depth d needs at most d.
    for path in scene_files() {
        let scene = stratapt_import::scene_file::load(&path).unwrap_or_else(|e| panic!("{e}"));
        let depth = bvh_depth(&scene);
        println!(
            "{}: {} nodes, depth {depth}",
            path.display(),
            scene.bvh.nodes.len()
        );
        assert!(depth < 64, "{}: BVH depth {depth}", path.display());
    }
    let depth = bvh_depth(&cluttered_scene());
    println!("cluttered: depth {depth}");
    assert!(depth < 64);
}

#[test]
fn cwbvh_depth_fits_the_gpu_stack() {
    // cwbvh.wgsl keeps 64 pending node groups; a tree whose deepest inner node is at level d
    // needs at most d.
    let mut scenes: Vec<FlatScene> = scene_files().iter().map(|p| load(p)).collect();
    scenes.push(cluttered_scene());
    for scene in &scenes {
        let cwbvh = Cwbvh::build(&scene.bvh);
        println!(
            "{}: {} nodes, depth {} (BVH2: {} nodes, depth {})",
            scene.path.display(),
            cwbvh.nodes.len(),
            cwbvh.depth,
            scene.bvh.nodes.len(),
            bvh_depth(scene)
        );
        assert!(
            cwbvh.depth <= stratapt_gpu::testing::MAX_BVH_DEPTH,
            "{}",
            scene.path.display()
        );
    }
}

// ---------------------------------------------------------------------------------------------
