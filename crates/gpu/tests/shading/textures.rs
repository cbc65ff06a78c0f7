//! Texture lookups (`texture.wgsl`) and the analytic shapes' texture coordinates
//! (`intersect.wgsl`) against `stratapt_scene::texture` and `stratapt_cpu::intersect`, on
//! random coordinates over every texture of `scenes/textures.toml` (an 8-bit sRGB image, a
//! clamped one, a grey float map, a checkerboard), and over the same textures brightened and
//! flagged to clamp each lookup to [0, 1]: bit for bit, the lookup being the same operations in
//! the same order on both sides.

use super::*;
use stratapt_cpu::intersect::{disk_uv, sphere_uv};
use stratapt_scene::records::{texture_flag, TEXTURE_WORDS};
use stratapt_scene::texture;

const TEXTURE_PROBE: &str = r#"
fn probe(i: u32) {
    let k = 4u * i;
    let index = u32(probe_f(k));
    let uv = probe_v2(k + 1u);
    probe_put3(8u * i, texture_eval(index, uv));
    probe_put(8u * i + 3u, texture_eval_scalar(index, uv));
    let n = normalize(vec3f(uv.x - 0.5, uv.y - 0.5, probe_f(k + 3u)));
    probe_put2(8u * i + 4u, intersect_sphere_uv(n));
    probe_put2(8u * i + 6u, intersect_disk_uv(vec3f(0.5), n, 0.7, vec3f(0.5) + 0.3 * vec3f(uv, 0.2)));
}
"#;

#[test]
fn texture_lookups_match_cpu_bit_for_bit() {
    lookups_match_cpu_bit_for_bit(&load_scene("textures.toml"), "textures");
}

/// Every texture tripled and flagged [`texture_flag::CLAMP`] (as the pbrt importer flags a
/// diffuse reflectance that can exceed 1): the clamp after the interpolation is the same bits
/// on both sides, and it does clamp (some lookups read exactly 1, some less).
#[test]
fn clamped_texture_lookups_match_cpu_bit_for_bit() {
    let mut scene = load_scene("textures.toml");
    for i in 0..scene.textures {
        let mut t = texture::record(&scene.tables, i);
        t.tag |= texture_flag::CLAMP;
        t.value = t.value.map(|x| 3.0 * x);
        t.other = t.other.map(|x| 3.0 * x);
        let at = TEXTURE_WORDS * i as usize;
        scene.tables[at..at + TEXTURE_WORDS].copy_from_slice(bytemuck::cast_slice(&[t]));
    }
    let values = lookups_match_cpu_bit_for_bit(&scene, "clamped textures");
    let channels = || values.iter().flat_map(|v| v.to_array());
    let ones = channels().filter(|&x| x == 1.0).count();
    let below = channels().filter(|&x| x < 1.0).count();
    assert!(channels().all(|x| (0.0..=1.0).contains(&x)));
    assert!(
        ones > values.len() / 10 && below > values.len() / 10,
        "{ones} ones, {below} below"
    );
}

/// The lookups of every texture of `scene` at random coordinates on the GPU, compared with the
/// CPU's bit for bit (and the analytic shapes' texture coordinates to the harness' tolerance);
/// the CPU's values.
fn lookups_match_cpu_bit_for_bit(scene: &FlatScene, name: &'static str) -> Vec<Vec3> {
    assert!(scene.textures >= 4);
    let mut rng = Rng(11);
    let mut input = Vec::new();
    let count = 2000;
    for i in 0..count {
        let index = (i % scene.textures as usize) as f32;
        // Mostly inside [0, 1)², some far outside (the wraps), some on texel boundaries.
        let (u, v) = match i % 4 {
            0 => (rng.range(-3.0, 4.0), rng.range(-3.0, 4.0)),
            1 => (
                (rng.f32() * 64.0).floor() / 64.0,
                (rng.f32() * 16.0).floor() / 16.0,
            ),
            _ => (rng.f32(), rng.f32()),
        };
        input.extend([index, u, v, rng.range(-1.0, 1.0)]);
    }
    let settings = RenderSettings::default();
    let out = run(
        scene,
        &settings,
        &["texture", "intersect"],
        TEXTURE_PROBE,
        &input,
        8,
        count,
    );
    let mut c = Check::new(name);
    let mut exact = 0;
    let mut values = Vec::with_capacity(count);
    for i in 0..count {
        let inp = &input[4 * i..];
        let (index, uv) = (inp[0] as u32, [inp[1], inp[2]]);
        let o = &out[8 * i..];
        let cpu = Vec3::from_array(texture::eval(&scene.tables, index, uv));
        let gpu = v3(o, 0);
        exact += (cpu == gpu) as usize;
        values.push(cpu);
        if cpu != gpu && std::env::var("TEXTURE_PROBE_DEBUG").is_ok() {
            eprintln!("#{i} texture {index} uv {uv:?}: gpu {gpu:?} cpu {cpu:?}");
        }
        c.v3("eval", i, gpu, cpu);
        c.f(
            "eval_scalar",
            i,
            o[3],
            texture::eval_scalar(&scene.tables, index, uv),
        );
        let n = Vec3::new(uv[0] - 0.5, uv[1] - 0.5, inp[3]).normalize();
        c.v2("sphere_uv", i, Vec2::new(o[4], o[5]), sphere_uv(n));
        let p = Vec3::splat(0.5) + 0.3 * Vec3::new(uv[0], uv[1], 0.2);
        c.v2(
            "disk_uv",
            i,
            Vec2::new(o[6], o[7]),
            disk_uv(Vec3::splat(0.5), n, 0.7, p),
        );
    }
    eprintln!("{name} lookups: {exact} of {count} bit for bit");
    assert_eq!(exact, count, "{name}: lookups differ in their bits");
    c.finish();
    values
}
