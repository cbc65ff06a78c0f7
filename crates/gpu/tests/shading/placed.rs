//! Lights placed at a shutter time and the alias-table draw (`light.wgsl`) against
//! `stratapt_cpu::light::placed` and `stratapt_scene::light_table::select`, on moving emitters.

use super::*;

/// Moving emitters of every shape kind, the non-surface lights, and a sky.
const MOVING_LIGHTS: &str = r#"
[camera]
eye = [0, 1, -5]
look_at = [0, 1, 0]
fov = 40
shutter = [0, 1]

[film]
width = 8
height = 8

[materials.lamp]
type = "diffuse"
albedo = 0.5
emission = [3, 2, 1]

[[shapes]]
type = "rectangle"
corner = [-1, 3, -1]
edge_u = [2, 0, 0]
edge_v = [0, 0, 1.5]
material = "lamp"
transform = { translate = [0, 0, 0], rotate = [10, 0, 0] }
transform_close = { translate = [0.5, -0.2, 0.1], rotate = [10, 40, 5], scale = 1.3 }

[[shapes]]
type = "triangle"
vertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0.2]]
material = "lamp"
transform = { translate = [1, 1, 1] }
transform_close = { translate = [1, 2, 1], rotate = [0, 90, 30], scale = 0.7 }

[[shapes]]
type = "disk"
center = [0, 0, 0]
normal = [0, -1, 0]
radius = 0.4
material = "lamp"
transform = { translate = [-2, 2, 0], rotate = [20, 0, 0] }
transform_close = { translate = [-2, 2.5, 0], rotate = [-30, 45, 0], scale = 1.5 }

[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = 0.3
material = "lamp"
transform = { translate = [2, 0.5, 0] }
transform_close = { translate = [2, 1.5, -1], scale = 2 }

[[lights]]
type = "point"
position = [0, 4, 0]
intensity = 5

[[lights]]
type = "spot"
position = [0, 4, -1]
look_at = [0, 0, 0]
intensity = 4

[[lights]]
type = "line"
from = [-1, 4, 1]
to = [1, 4, 1]
intensity = 2

[[lights]]
type = "distant"
direction = [0.3, 1, 0.2]
irradiance = 2
angular_diameter = 3

[sky]
top = [0.2, 0.3, 0.8]
bottom = [0.1, 0.1, 0.1]
"#;

const PLACED_PROBE: &str = r#"
fn probe(i: u32) {
    let index = probe_in[4u * i];
    let time = probe_f(4u * i + 1u);
    let u = probe_f(4u * i + 2u);
    let l = light_placed(index, time);
    let o = i * 20u;
    probe_put3(o, l.p0);
    probe_out[o + 3u] = l.kind;
    probe_put3(o + 4u, l.p1);
    probe_out[o + 7u] = l.motion;
    probe_put3(o + 8u, l.p2);
    probe_put(o + 11u, l.select_pdf);
    probe_put3(o + 12u, l.radiance);
    probe_put(o + 15u, l.unhittable_select_pdf);
    let full = light_select(true, u);
    probe_out[o + 16u] = full.index;
    probe_put(o + 17u, full.pdf);
    let unhittable = light_select(false, u);
    probe_out[o + 18u] = unhittable.index;
    probe_put(o + 19u, unhittable.pdf);
}
"#;

#[test]
fn placed_lights_and_selection_match_cpu() {
    use stratapt_cpu::light;
    use stratapt_scene::light_table;
    let scene = stratapt_import::load::load_str(MOVING_LIGHTS, Path::new("moving-lights"))
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(!scene.unhittable_table.is_empty() && scene.lights.len() >= 8);
    let moving = scene
        .lights
        .iter()
        .filter(|l| l.motion != stratapt_scene::records::NONE)
        .count();
    assert!(moving >= 4, "{moving} moving lights");
    let mut rng = Rng(6);
    let count = 2000;
    let mut input = Vec::new();
    for i in 0..count {
        let u = if i < 64 { i as f32 / 64.0 } else { rng.f32() };
        let time = if i % 10 == 0 {
            (i % 20 / 10) as f32
        } else {
            rng.f32()
        };
        let index = (i % scene.lights.len()) as u32;
        input.extend_from_slice(&[f32::from_bits(index), time, u, 0.0]);
    }
    let settings = RenderSettings::default();
    let out = run(
        &scene,
        &settings,
        &["light"],
        PLACED_PROBE,
        &input,
        20,
        count,
    );
    let mut c = Check::new("placed lights, selection");
    for i in 0..count {
        let (index, time, u) = (
            input[4 * i].to_bits() as usize,
            input[4 * i + 1],
            input[4 * i + 2],
        );
        let o = &out[i * 20..];
        let l = light::placed(&scene.lights[index], &scene.motions, time);
        let words = |k: usize| Vec3::new(o[k], o[k + 1], o[k + 2]);
        c.v3("placed p0", i, words(0), Vec3::from_array(l.p0));
        c.v3("placed p1", i, words(4), Vec3::from_array(l.p1));
        c.v3("placed p2", i, words(8), Vec3::from_array(l.p2));
        c.v3(
            "placed radiance",
            i,
            words(12),
            Vec3::from_array(l.radiance),
        );
        c.f("placed select_pdf", i, o[11], l.select_pdf);
        c.f(
            "placed unhittable_select_pdf",
            i,
            o[15],
            l.unhittable_select_pdf,
        );
        c.flag(
            "placed kind/motion",
            i,
            1.0,
            o[3].to_bits() == l.kind && o[7].to_bits() == l.motion,
        );
        let (j, pdf) = light_table::select(&scene.light_table, u);
        c.flag("select index", i, 1.0, o[16].to_bits() as usize == j);
        c.f("select pdf", i, o[17], pdf);
        let (j, pdf) = light_table::select(&scene.unhittable_table, u);
        c.flag(
            "select unhittable index",
            i,
            1.0,
            o[18].to_bits() as usize == j,
        );
        c.f("select unhittable pdf", i, o[19], pdf);
    }
    c.finish();
}
