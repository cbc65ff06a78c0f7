//! Light sampling from a shading point (`light.wgsl`) against `stratapt_cpu::light`: random
//! lights of every kind, and the lights of the bundled scenes.

use super::*;

/// WGSL: the `Light` at word `k` of `probe_in` (the 16 words of `gpu::Light`).
const LIGHT_IN: &str = r#"
fn probe_light(k: u32) -> Light {
    return Light(probe_v3(k), probe_in[k + 3u], probe_v3(k + 4u), probe_in[k + 7u],
        probe_v3(k + 8u), probe_f(k + 11u), probe_v3(k + 12u), probe_f(k + 15u), probe_in[k + 16u], 0u, 0u, 0u);
}
"#;

const LIGHT_PROBE: &str = r#"
fn probe(i: u32) {
    let k = i * 32u;
    let o = i * 18u;
    let light = probe_light(k);
    let p = probe_v3(k + 20u);
    let u = probe_v2(k + 23u);
    let dir = probe_v3(k + 25u);
    let s = light_sample(light, p, u);
    probe_put_bool(o, s.valid);
    probe_put3(o + 1u, s.wi);
    probe_put3(o + 4u, s.radiance);
    probe_put(o + 7u, s.dist);
    probe_put(o + 8u, s.pdf);
    probe_put_bool(o + 9u, s.delta);
    probe_put(o + 10u, light_pdf(light, p, s.wi));
    probe_put(o + 11u, light_pdf(light, p, dir));
    probe_put3(o + 12u, light_escaped_radiance(light, dir));
    probe_put_bool(o + 15u, light_is_environment(light));
}
"#;

/// A random light of `kind` near the origin, and a shading point `p` that sometimes sits on it.
fn random_light(rng: &mut Rng, kind: u32, i: usize) -> (stratapt_scene::records::Light, Vec3) {
    use stratapt_scene::records::{light_kind, Light};
    let scale = rng.log_range(1e-2, 3.0);
    let centre = rng.point(1.0);
    let mut p = rng.point(3.0);
    let mut l = Light {
        kind,
        motion: stratapt_scene::records::NONE,
        radiance: [
            rng.range(0.1, 5.0),
            rng.range(0.1, 5.0),
            rng.range(0.1, 5.0),
        ],
        // Every other polygon or disk two-sided: sampled from behind too.
        flags: match i % 2 {
            0 => stratapt_scene::records::light_flag::TWO_SIDED,
            _ => 0,
        },
        ..Default::default()
    };
    let (a, b, c) = match kind {
        light_kind::TRIANGLE => (
            centre + scale * rng.sphere(),
            centre + scale * rng.sphere(),
            centre + scale * rng.sphere(),
        ),
        light_kind::RECTANGLE => {
            let f = Frame::from_normal(rng.sphere());
            let (ex, ey) = (
                f.s * scale * rng.range(0.2, 2.0),
                f.t * scale * rng.range(0.2, 2.0),
            );
            // Every 8th a parallelogram (area sampling); every 9th p in its plane.
            let ey = if i.is_multiple_of(8) {
                ey + 0.3 * ex
            } else {
                ey
            };
            if i.is_multiple_of(9) {
                p = centre + rng.range(-1.0, 2.0) * ex + rng.range(-1.0, 2.0) * ey;
            }
            (centre, ex, ey)
        }
        light_kind::DISK => (centre, rng.sphere(), Vec3::new(scale, 0.0, 0.0)),
        light_kind::SPHERE => {
            // Inside, on, and outside the sphere, far and near.
            match i % 4 {
                0 => p = centre + scale * rng.f32() * rng.sphere(),
                1 => p = centre + scale * rng.sphere(),
                _ => {}
            }
            (centre, Vec3::ZERO, Vec3::new(scale, 0.0, 0.0))
        }
        light_kind::LINE => (centre, centre + scale * rng.sphere(), Vec3::ZERO),
        light_kind::POINT => (centre, Vec3::ZERO, Vec3::ZERO),
        light_kind::SPOT => {
            // Hard edges (every 4th), narrow and wide cones; the point inside and outside.
            let end = rng.range(-1.0, 0.99);
            let start = if i.is_multiple_of(4) {
                end
            } else {
                rng.range(end, 1.0)
            };
            let axis = match i % 3 {
                0 => (p - centre).normalize_or(Vec3::Z),
                _ => rng.sphere(),
            };
            (centre, axis, Vec3::new(end, start, 0.0))
        }
        light_kind::DISTANT => {
            let cos_max = match i % 3 {
                0 => 1.0,
                1 => 1.0 - rng.log_range(1e-6, 1e-2),
                _ => rng.range(0.0, 1.0),
            };
            (rng.sphere(), Vec3::ZERO, Vec3::new(cos_max, 0.0, 0.0))
        }
        _ => (
            rng.sphere(),
            Vec3::new(rng.f32(), rng.f32(), rng.f32()),
            Vec3::ZERO,
        ),
    };
    l.p0 = a.to_array();
    l.p1 = b.to_array();
    l.p2 = c.to_array();
    (l, p)
}

/// Compare `light::sample`, `pdf` (at the sample and along a random direction),
/// `escaped_radiance` and `is_environment` for each `(light, p)`.
fn compare_lights(
    name: &'static str,
    cases: &[(stratapt_scene::records::Light, Vec3)],
    rng: &mut Rng,
) {
    use stratapt_cpu::light;
    let mut input = Vec::new();
    for (l, p) in cases {
        input.extend(
            bytemuck::cast_slice::<_, u32>(&[*l])
                .iter()
                .map(|w| f32::from_bits(*w)),
        );
        push3(&mut input, *p);
        input.extend_from_slice(&[rng.f32(), rng.f32()]);
        // A direction towards the light (near its centre) or anywhere, and padding.
        let towards = (Vec3::from_array(l.p0) - *p).normalize_or(Vec3::Z);
        let dir = if rng.f32() < 0.5 {
            (towards + 0.2 * rng.sphere()).normalize()
        } else {
            rng.sphere()
        };
        push3(&mut input, dir);
        input.extend_from_slice(&[0.0; 4]);
    }
    let scene = load_scene("cornell-box.toml");
    let settings = RenderSettings::default();
    let modules = ["frame", "warp", "motion", "light"];
    let probe = format!("{LIGHT_IN}\n{LIGHT_PROBE}");
    let out = run(&scene, &settings, &modules, &probe, &input, 18, cases.len());
    let mut c = Check::new(name);
    let mut valid = [(0usize, 0usize); stratapt_scene::effects::LIGHT_KIND_NAMES.len()];
    for (i, (l, p)) in cases.iter().enumerate() {
        let inp = &input[i * 32..];
        let o = &out[i * 18..];
        let kind = stratapt_scene::effects::LIGHT_KIND_NAMES[l.kind as usize];
        let u = Vec2::new(inp[23], inp[24]);
        let dir = v3(inp, 25);
        let s = light::sample(l, *p, u);
        valid[l.kind as usize].1 += 1;
        if c.flag(&format!("{kind} sample valid"), i, o[0], s.is_some()) {
            let s = s.unwrap();
            c.v3(&format!("{kind} sample wi"), i, v3(o, 1), s.wi);
            c.v3(&format!("{kind} sample radiance"), i, v3(o, 4), s.radiance);
            c.f(&format!("{kind} sample dist"), i, o[7], s.dist);
            c.f(&format!("{kind} sample pdf"), i, o[8], s.pdf);
            c.flag(&format!("{kind} sample delta"), i, o[9], s.delta);
            c.f(
                &format!("{kind} pdf(sampled)"),
                i,
                o[10],
                light::pdf(l, *p, s.wi),
            );
            valid[l.kind as usize].0 += 1;
        }
        c.f(&format!("{kind} pdf"), i, o[11], light::pdf(l, *p, dir));
        let e = light::escaped_radiance(l, dir);
        c.v3(&format!("{kind} escaped_radiance"), i, v3(o, 12), e);
        c.flag(
            &format!("{kind} is_environment"),
            i,
            o[15],
            l.is_environment(),
        );
    }
    eprintln!("{name}: (valid samples, cases) per light kind: {valid:?}");
    c.finish();
}

#[test]
fn spot_lights_match_cpu() {
    let mut rng = Rng(7);
    let cases: Vec<_> = (0..600)
        .map(|i| random_light(&mut rng, stratapt_scene::records::light_kind::SPOT, i))
        .collect();
    compare_lights("spot lights", &cases, &mut rng);
}

#[test]
fn lights_match_cpu() {
    let mut rng = Rng(5);
    let cases: Vec<_> = (0..8 * 600)
        .map(|i| random_light(&mut rng, (i % 8) as u32, i / 8))
        .collect();
    compare_lights("random lights", &cases, &mut rng);
}

#[test]
fn scene_lights_match_cpu() {
    let mut rng = Rng(7);
    let mut cases = Vec::new();
    for name in [
        "cornell-box.toml",
        "soft-shadow-area.toml",
        "soft-shadow-line.toml",
        "soft-shadow-sun.toml",
        "veach-mis.toml",
        "glass.toml",
    ] {
        let scene = load_scene(name);
        // Shading points anywhere in (and a little around) the scene's bounds.
        let (lo, hi) = (scene.bounds_min, scene.bounds_max);
        for _ in 0..300 {
            for l in &scene.lights {
                let t = Vec3::new(
                    rng.range(-0.1, 1.1),
                    rng.range(-0.1, 1.1),
                    rng.range(-0.1, 1.1),
                );
                cases.push((*l, lo + (hi - lo) * t));
            }
        }
    }
    compare_lights("scene lights", &cases, &mut rng);
}

/// The degenerate lights and points of the CPU's guard test (zero areas, lengths and radii,
/// collinear edges, points on a light's plane, centre or vertex, scales 10⁻²⁰ … 10²⁰): the GPU
/// refuses the same samples and gives the same finite values.
#[test]
fn degenerate_lights_match_cpu() {
    use stratapt_scene::records::light_kind;
    let mut rng = Rng(9);
    let mut cases = Vec::new();
    for scale in [1e-20f32, 1e-6, 1.0, 1e6, 1e20] {
        let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z) * scale;
        let z = Vec3::ZERO;
        let geometry = [
            (light_kind::TRIANGLE, z, z, v(1.0, 0.0, 0.0)),
            (light_kind::TRIANGLE, z, v(1.0, 1.0, 0.0), v(2.0, 2.0, 0.0)),
            (light_kind::RECTANGLE, z, z, v(1.0, 0.0, 0.0)),
            (light_kind::RECTANGLE, z, v(1.0, 0.0, 0.0), v(2.0, 0.0, 0.0)),
            (light_kind::RECTANGLE, z, v(0.0, 1.0, 0.0), v(1.0, 0.0, 0.0)),
            (light_kind::DISK, z, Vec3::Z, Vec3::ZERO),
            (light_kind::DISK, z, Vec3::Z, Vec3::X * scale),
            (light_kind::SPHERE, z, z, Vec3::ZERO),
            (light_kind::SPHERE, z, z, Vec3::X * scale),
            (light_kind::LINE, z, z, z),
            (light_kind::POINT, z, z, z),
        ];
        let points = [
            Vec3::ZERO,
            v(0.3, 0.2, 0.0),
            v(0.0, 0.0, 0.5),
            v(0.5, 0.0, 0.0),
            v(0.0, 0.0, 1e-7),
            v(-3.0, 2.0, -1.0),
        ];
        for (kind, a, b, c) in geometry {
            for p in points {
                for _ in 0..4 {
                    let mut l = random_light(&mut rng, kind, 0).0;
                    l.p0 = a.to_array();
                    l.p1 = b.to_array();
                    l.p2 = c.to_array();
                    cases.push((l, p));
                }
            }
        }
    }
    compare_lights("degenerate lights", &cases, &mut rng);
}
