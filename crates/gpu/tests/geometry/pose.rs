//! Poses of moving objects (`motion.wgsl`) and robust ray origins (`offset.wgsl`) against the
//! CPU.

use super::*;
use glam::Quat;
use stratapt_cpu::offset::spawn_origin;

const MOTION_PROBE: &str = r#"
fn probe(i: u32) {
    let b = i * 8u;
    let pose = motion_at(probe_in[b], probe_f(b + 1u));
    let p = probe_v(b + 2u);
    let v = probe_v(b + 5u);
    let o = i * 25u;
    probe_put(o, pose.translation);
    probe_put(o + 3u, pose.rotation.xyz);
    probe_out[o + 6u] = bitcast<u32>(pose.rotation.w);
    probe_put(o + 7u, pose.scale);
    probe_put(o + 10u, motion_pose_point_to_world(pose, p));
    probe_put(o + 13u, motion_pose_point_to_object(pose, p));
    probe_put(o + 16u, motion_pose_vector_to_world(pose, v));
    probe_put(o + 19u, motion_pose_vector_to_object(pose, v));
    probe_put(o + 22u, motion_pose_normal_to_world(pose, v));
}
"#;

/// Largest component of `|a − b|`, relative to `max(1, |b|)`.
fn rel_err(a: Vec3, b: Vec3) -> f32 {
    (a - b).abs().max_element() / b.abs().max_element().max(1.0)
}

#[test]
fn motion_at_and_pose_transforms_match_cpu() {
    let (device, queue) = device();
    let mut scenes = vec![cluttered_scene()];
    let blur = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/motion-blur-object.toml");
    scenes.push(stratapt_import::scene_file::load(&blur).unwrap());
    // Both rotation paths of slerp: nearly equal (normalized lerp) and the sine blend, both
    // signs of the quaternion dot product.
    let mut extra = scenes.remove(0);
    let q = |axis: Vec3, deg: f32| Quat::from_axis_angle(axis.normalize(), deg.to_radians());
    let pose = |r: Quat| Pose::new(Vec3::new(0.5, -1.0, 2.0), r, Vec3::new(1.0, 2.0, 0.5));
    for (a, b) in [
        (q(Vec3::Y, 0.0), q(Vec3::Y, 0.0)),
        (q(Vec3::Y, 10.0), q(Vec3::Y, 10.00001)),
        (q(Vec3::X, 30.0), q(Vec3::ONE, 300.0)),
        (q(Vec3::Z, 170.0), -q(Vec3::Z, -170.0)),
    ] {
        extra.motions.push(Motion {
            open: pose(a),
            close: pose(b),
        });
    }
    scenes.insert(0, extra);
    let mut rng = Rng(5);
    for scene in &scenes {
        let n = 2048;
        let mut input = Vec::new();
        for _ in 0..n {
            let m = (rng.f32() * scene.motions.len() as f32) as u32 % scene.motions.len() as u32;
            input.push(m);
            input.push(rng.f32().to_bits());
            input.extend(bits(rng.unit() * rng.range(0.1, 5.0)));
            input.extend(bits(rng.unit() * rng.range(0.1, 2.0)));
        }
        let out = testing::run_probe(
            &device,
            &queue,
            scene,
            &scene.settings,
            MODULES,
            &format!("{PROBE_IO}{MOTION_PROBE}"),
            &input,
            n * 25,
            n as u32,
        );
        let mut worst = 0.0f32;
        for i in 0..n {
            let w = &input[i * 8..];
            let pose = scene.motions[w[0] as usize].at(f32::from_bits(w[1]));
            let (p, v) = (vec_at(w, 2), vec_at(w, 5));
            let o = &out[i * 25..];
            let r = pose.rotation();
            let gpu_r = Quat::from_xyzw(
                f32::from_bits(o[3]),
                f32::from_bits(o[4]),
                f32::from_bits(o[5]),
                f32::from_bits(o[6]),
            );
            let checks = [
                ("translation", vec_at(o, 0), pose.translation()),
                ("rotation", gpu_r.xyz(), r.xyz()),
                ("rotation w", Vec3::splat(gpu_r.w), Vec3::splat(r.w)),
                ("scale", vec_at(o, 7), pose.scale()),
                ("point_to_world", vec_at(o, 10), pose.point_to_world(p)),
                ("point_to_object", vec_at(o, 13), pose.point_to_object(p)),
                ("vector_to_world", vec_at(o, 16), pose.vector_to_world(v)),
                ("vector_to_object", vec_at(o, 19), pose.vector_to_object(v)),
                ("normal_to_world", vec_at(o, 22), pose.normal_to_world(v)),
            ];
            for (what, gpu, cpu) in checks {
                let e = rel_err(gpu, cpu);
                worst = worst.max(e);
                assert!(
                    e < 2e-6,
                    "motion {} time {}: {what} gpu {gpu} cpu {cpu}",
                    w[0],
                    f32::from_bits(w[1])
                );
            }
        }
        println!(
            "{}: worst relative pose error {worst:e}",
            scene.path.display()
        );
    }
}

const OFFSET_PROBE: &str = r#"
fn probe_v(i: u32) -> vec3f {
    return bitcast<vec3f>(vec3u(probe_in[i], probe_in[i + 1u], probe_in[i + 2u]));
}
fn probe(i: u32) {
    let k = i * 12u;
    let q = offset_spawn_origin(probe_v(k), probe_v(k + 3u), probe_v(k + 6u), probe_v(k + 9u));
    let r = bitcast<vec3u>(q);
    probe_out[i * 3u] = r.x;
    probe_out[i * 3u + 1u] = r.y;
    probe_out[i * 3u + 2u] = r.z;
}
"#;

#[test]
fn spawn_origin_matches_cpu_bit_for_bit() {
    let (device, queue) = device();
    let scene = load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-box.toml"));
    let mut rng = Rng(11);
    let mut cases = Vec::new();
    // Points at scales 1e-30 … 1e30, some near the origin relative to their error bound (that of
    // a triangle of the scale's size), some exactly on it.
    for exp in (-30..=30).step_by(3) {
        let scale = 10f32.powi(exp);
        for k in 0..100 {
            let near = if k % 4 == 0 { 1e-6 } else { 1.0 };
            let p = rng.unit() * scale * near * rng.range(0.1, 1.0);
            let err = Vec3::splat(stratapt_scene::shared::GAMMA_7 * scale * 3.0);
            cases.push((p, err, rng.unit(), rng.unit()));
        }
    }
    // Zero, negative zero and axis-aligned normals.
    for n in [Vec3::X, -Vec3::Y, Vec3::Z] {
        for p in [
            Vec3::ZERO,
            Vec3::splat(-0.0),
            Vec3::new(1e6, -1e6, 0.0),
            Vec3::splat(-3.0),
        ] {
            for err in [Vec3::ZERO, Vec3::splat(1e-7)] {
                cases.push((p, err, n, n));
                cases.push((p, err, n, -n));
            }
        }
    }
    let input: Vec<u32> = cases
        .iter()
        .flat_map(|(p, e, n, d)| [bits(*p), bits(*e), bits(*n), bits(*d)].concat())
        .collect();
    let out = testing::run_probe(
        &device,
        &queue,
        &scene,
        &scene.settings,
        MODULES,
        OFFSET_PROBE,
        &input,
        cases.len() * 3,
        cases.len() as u32,
    );
    for (i, (p, e, n, d)) in cases.iter().enumerate() {
        let cpu = spawn_origin(*p, *e, *n, *d);
        assert_eq!(
            &out[i * 3..i * 3 + 3],
            &bits(cpu),
            "p {p} err {e} ng {n} dir {d}: gpu {} cpu {cpu}",
            vec_at(&out, i * 3)
        );
    }
}

// ---------------------------------------------------------------------------------------------
