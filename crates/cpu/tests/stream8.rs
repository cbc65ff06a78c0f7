//! The eight-rays-per-vector traversal prototype (`accel::stream8`, timed by `cargo bench -p
//! stratapt-cpu --bench stream8`) finds what the one-ray traversal finds.

use glam::Vec3;
use stratapt_cpu::accel::stream8::WIDTH;
use stratapt_cpu::accel::Accel;
use stratapt_cpu::intersect::Ray;

#[test]
fn eight_rays_together_find_what_each_finds_alone() {
    for name in ["cornell-box", "mesh"] {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join(format!("../../scenes/{name}.toml"));
        let scene = stratapt_import::scene_file::load(&path).unwrap();
        let accel = Accel::new(&scene);
        let root = scene.bvh.nodes[0].aabb();
        let (lo, hi) = (Vec3::from(root.min), Vec3::from(root.max));
        // Rays from random points of the scene's box in random directions, and segments
        // between two such points (shadow rays).
        let mut state = 1u64;
        let mut u = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        let (mut hits, mut blocked) = (0, 0);
        for _ in 0..512 {
            let mut point = || lo + (hi - lo) * Vec3::new(u(), u(), u());
            let rays: [Ray; WIDTH] = std::array::from_fn(|_| {
                let (a, b) = (point(), point());
                Ray::new(a, (b - a).normalize(), f32::INFINITY)
            });
            let segments: [Ray; WIDTH] = std::array::from_fn(|_| {
                let (a, b) = (point(), point());
                Ray::new(a, (b - a).normalize(), (b - a).length())
            });
            let eight = accel.closest8(&rays, 0.0);
            let any = accel.occluded8(&segments, 0.0);
            for i in 0..WIDTH {
                let alone = accel.closest_prim(&rays[i], 0.0);
                // The same distance (an exact tie may name the other primitive).
                assert_eq!(
                    alone.map(|(_, t)| t.to_bits()),
                    eight[i].map(|(_, t)| t.to_bits()),
                    "{name}: {:?}",
                    rays[i]
                );
                assert_eq!(accel.occluded_prim(&segments[i], 0.0), any[i], "{name}");
                hits += alone.is_some() as usize;
                blocked += any[i] as usize;
            }
        }
        // Many rays meet the scene (the mesh scene's box is mostly open: 27 %), and some
        // segments are blocked and some are not.
        assert!(hits > 512 * WIDTH / 10, "{name}: {hits} hits");
        assert!(
            blocked > 0 && blocked < 512 * WIDTH,
            "{name}: {blocked} blocked"
        );
    }
}
