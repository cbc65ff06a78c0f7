//! Alpha cut-outs (pbrt-v4's `alpha`) in traversal: a ray meets a surface of alpha `a` with
//! probability `a`, each layer on its own, for closest hits and shadow rays alike; an alpha
//! texture cuts exactly where its texels say. The fractions are binomial tests on many rays,
//! each shown to reject the error it is there to catch (pbrt-v4's one choice per ray, which
//! makes two layers pass as one; an alpha 0.01 off).

use glam::Vec3;
use std::path::Path;
use stratapt_cpu::accel::{closest_hit_brute_force, occluded_brute_force, Accel};
use stratapt_cpu::intersect::Ray;
use stratapt_import::load::load_str;
use stratapt_sampling::testing::TestRng;
use stratapt_scene::FlatScene;

const RAYS: usize = 100_000;

/// Sheets at z = 0, 1, … (one per alpha, `alpha` = None: opaque) in front of an opaque wall at
/// z = 5; materials `sheet` and `wall`.
fn scene(alphas: &[&str], textures: &str) -> FlatScene {
    let mut text = format!(
        "[camera]\neye = [0, 0, -5]\nlook_at = [0, 0, 0]\nfov = 40\n\n{textures}\n\
         [materials.sheet]\ntype = \"diffuse\"\nalbedo = 0.5\n\n\
         [materials.wall]\ntype = \"diffuse\"\nalbedo = 0.5\n\n\
         [[shapes]]\ntype = \"rectangle\"\ncorner = [-2, -2, 5]\nedge_u = [4, 0, 0]\n\
         edge_v = [0, 4, 0]\nmaterial = \"wall\"\n"
    );
    for (z, alpha) in alphas.iter().enumerate() {
        text += &format!(
            "\n[[shapes]]\ntype = \"rectangle\"\ncorner = [-1, -1, {z}]\nedge_u = [2, 0, 0]\n\
             edge_v = [0, 2, 0]\nmaterial = \"sheet\"\nalpha = {alpha}\n"
        );
    }
    load_str(&text, Path::new("alpha.toml")).unwrap_or_else(|e| panic!("{e}"))
}

/// Rays from z = −1 into the sheets (points of `[−1, 1]²`, directions within 0.2 of +z): how
/// many reach the wall, and each ray with whether it did. Shadow rays (to just before the wall)
/// and brute-force traversal must agree with every closest hit.
fn through(scene: &FlatScene, seed: u64) -> (usize, Vec<(Ray, bool)>) {
    let accel = Accel::new(scene);
    let wall = scene
        .material_names
        .iter()
        .position(|n| n == "wall")
        .unwrap() as u32;
    let mut rng = TestRng(seed);
    let mut rays = Vec::with_capacity(RAYS);
    let mut count = 0;
    for _ in 0..RAYS {
        let origin = Vec3::new(rng.range(-0.9, 0.9), rng.range(-0.9, 0.9), -1.0);
        let dir = Vec3::new(rng.range(-0.02, 0.02), rng.range(-0.02, 0.02), 1.0).normalize();
        let ray = Ray::new(origin, dir, f32::INFINITY);
        let hit = accel
            .closest_hit(&ray, 0.0)
            .expect("the wall stops every ray");
        let reached = scene.geometry.surface(hit.prim).material == wall;
        let brute = closest_hit_brute_force(scene, &ray, 0.0).unwrap();
        assert_eq!(brute.prim, hit.prim);
        // To just before the wall.
        let shadow = Ray::new(origin, dir, 0.999 * (5.0 - origin.z) / dir.z);
        let blocked = accel.occluded(&shadow, 0.0);
        assert_eq!(
            blocked, !reached,
            "a shadow ray sees what the closest hit sees"
        );
        assert_eq!(occluded_brute_force(scene, &shadow, 0.0), blocked);
        count += reached as usize;
        rays.push((ray, reached));
    }
    (count, rays)
}

/// The binomial z-score of `count` of [`RAYS`] against probability `p`.
fn z(count: usize, p: f64) -> f64 {
    let n = RAYS as f64;
    (count as f64 - n * p) / (n * p * (1.0 - p)).sqrt()
}

#[test]
fn a_sheet_of_alpha_a_stops_a_fraction_a_and_each_layer_chooses_on_its_own() {
    // One sheet of alpha 0.3: 70 % through.
    let (one, _) = through(&scene(&["0.3"], ""), 1);
    assert!(z(one, 0.7).abs() < 4.0, "{one} through: z {}", z(one, 0.7));
    // Planted: an alpha 0.01 off is rejected.
    assert!(
        z(one, 0.69).abs() > 4.0,
        "a 0.01 shift passes: z {}",
        z(one, 0.69)
    );
    // Two sheets: 0.7² through, each choosing on its own; pbrt-v4's hash of the ray alone would
    // let 0.7 through (both layers choosing alike), which the test rejects.
    let (two, _) = through(&scene(&["0.3", "0.3"], ""), 2);
    assert!(
        z(two, 0.49).abs() < 4.0,
        "{two} through: z {}",
        z(two, 0.49)
    );
    assert!(z(two, 0.7).abs() > 4.0);
    // Alpha 0 passes everything, 1 nothing.
    assert_eq!(through(&scene(&["0"], ""), 3).0, RAYS);
    assert_eq!(through(&scene(&["1"], ""), 4).0, 0);
}

#[test]
fn an_alpha_texture_cuts_where_its_texels_say() {
    // A checkerboard of 0 and 1, 4 × 4 cells over the sheet: a ray passes exactly where its
    // hit lies in a cell of alpha 0.
    let checks = "[textures.checks]\ntype = \"checkerboard\"\ncolor0 = 0\ncolor1 = 1\n\
                  uv_scale = 2\n";
    let (count, rays) = through(&scene(&["\"checks\""], checks), 5);
    for (ray, reached) in rays {
        // Where the ray crosses z = 0, and the sheet's (u, v) there.
        let p = ray.origin + ray.dir * (-ray.origin.z / ray.dir.z);
        let (u, v) = (2.0 * (p.x + 1.0) / 2.0, 2.0 * (p.y + 1.0) / 2.0);
        let (fu, fv) = (u.fract() > 0.5, v.fract() > 0.5);
        // Too close to a cell's edge to tell from the crossing computed here: skipped.
        let edge = |x: f32| (x.fract() - 0.5).abs().min(x.fract()).min(1.0 - x.fract()) < 1e-3;
        if edge(u) || edge(v) {
            continue;
        }
        assert_eq!(reached, fu == fv, "at uv ({u}, {v})");
    }
    assert!(z(count, 0.5).abs() < 10.0, "{count}");
}
