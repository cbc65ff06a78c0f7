//! The environment map as a light, as the integrator samples it: `light::sample_prepared` of
//! `scenes/environment.toml`'s map (latitude–longitude, rotated, with a small sun carrying most
//! of its light) and of `scenes/environment-octahedral.toml`'s (the same studio in pbrt-v4's
//! equal-area octahedral layout) against `light::pdf_prepared`: a chi-square fit in the map's
//! own coordinates with planted errors, the pdf's integral over the sphere, and the radiance an
//! escaping ray sees against the sampled radiance.

use glam::{Vec2, Vec3};
use std::f64::consts::PI;
use stratapt_cpu::light::{self, Prepared};
use stratapt_sampling::testing::chi2::{
    accept, density_bins, fit, print_fit, Family, Fit, Plant, Refusals,
};
use stratapt_sampling::testing::TestRng;
use stratapt_sampling::warp::equal_area;
use stratapt_scene::environment;
use stratapt_scene::light_table::luminance;
use stratapt_scene::records::{light_kind, Light};
use stratapt_scene::FlatScene;

const FAMILY: Family = Family {
    alpha: 0.01,
    tests: 4,
};

/// The two layouts' bundled scenes.
const SCENES: [&str; 2] = ["environment", "environment-octahedral"];

fn scene(name: &str) -> FlatScene {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../scenes/{name}.toml"));
    stratapt_import::scene_file::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

fn environment_light(scene: &FlatScene) -> Light {
    *scene
        .lights
        .iter()
        .find(|l| l.kind == light_kind::ENVIRONMENT || l.kind == light_kind::OCTAHEDRAL)
        .expect("an environment light")
}

/// The map's own coordinates in `[0, 1]²` of a map direction: latitude–longitude `(u, v)`, or
/// the point of pbrt-v4's equal-area square.
fn coords(l: &Light, d: Vec3) -> Vec2 {
    match l.kind {
        light_kind::OCTAHEDRAL => equal_area::sphere_to_square(d),
        _ => environment::direction_to_uv(d),
    }
}

/// The map direction at `uv` with the solid angle per unit area of `uv` there.
fn direction(l: &Light, uv: Vec2) -> (Vec3, f64) {
    match l.kind {
        light_kind::OCTAHEDRAL => (equal_area::square_to_sphere(uv), 4.0 * PI),
        _ => {
            let (d, sin_theta) = environment::uv_to_direction(uv);
            (d, 2.0 * PI * PI * f64::from(sin_theta))
        }
    }
}

/// World → map rotation of the light (its rows are `p0`, `p1`, `p0 × p1`).
fn to_map(l: &Light, d: Vec3) -> Vec3 {
    let (r0, r1) = (Vec3::from_array(l.p0), Vec3::from_array(l.p1));
    Vec3::new(r0.dot(d), r1.dot(d), r0.cross(r1).dot(d))
}

fn to_world(l: &Light, d: Vec3) -> Vec3 {
    let (r0, r1) = (Vec3::from_array(l.p0), Vec3::from_array(l.p1));
    r0 * d.x + r1 * d.y + r0.cross(r1) * d.z
}

fn run(name: &str, plant: Plant, wrong: bool) -> Fit {
    let scene = scene(name);
    let l = environment_light(&scene);
    let prepared = Prepared::of(&l, &scene.tables);
    let p = Vec3::new(0.3, 0.5, -0.2);
    // A wrong pdf: the sun's directions 10 % too likely (the densities elsewhere unchanged).
    let sun = |wi: Vec3| {
        luminance(light::escaped_radiance_prepared(&l, &prepared, wi).to_array()) > 100.0
    };
    let density = |x: f64, y: f64| {
        let (d, jacobian) = direction(&l, Vec2::new(x as f32, y as f32));
        let wi = to_world(&l, d);
        let pdf = light::pdf_prepared(&l, &prepared, p, wi);
        let scale = if wrong && sun(wi) { 1.1 } else { 1.0 };
        f64::from(pdf) * scale * jacobian
    };
    let (nx, ny) = (64, 32);
    let probs = density_bins(&density, nx, ny);
    let mut rng = TestRng(5);
    let samples = (0..200_000).map(|_| {
        light::sample_prepared(&l, &prepared, p, rng.u2()).map(|s| {
            let uv = coords(&l, to_map(&l, s.wi));
            [f64::from(uv.x), f64::from(uv.y)]
        })
    });
    let name = match wrong {
        true => format!("{name}: sun 10 % too likely in the pdf"),
        false => name.to_string(),
    };
    fit(
        &FAMILY,
        &name,
        samples,
        &probs,
        nx,
        ny,
        Refusals::Never,
        plant,
    )
}

#[test]
fn sampling_matches_the_pdf() {
    accept(SCENES.map(|name| run(name, Plant::None, false)).into());
}

/// Companions: a bent sampling routine, a pdf 1 % too large and one that makes the sun 10 % too
/// likely are each rejected.
#[test]
fn sampling_test_rejects_planted_errors() {
    for name in SCENES {
        for fit in [
            run(name, Plant::Bend(0.1), false),
            run(name, Plant::PdfScale(1.01), false),
            run(name, Plant::None, true),
        ] {
            print_fit(&fit);
            assert!(fit.verdict.is_err(), "{} accepted", fit.name);
        }
    }
}

/// `∫ pdf dω = 1` over the sphere (a fine midpoint rule in the map's (u, v), where the density
/// is piecewise constant), and the sampled radiance is the map's lookup along the direction.
#[test]
fn pdf_integrates_to_one_and_samples_carry_the_maps_radiance() {
    for name in SCENES {
        let scene = scene(name);
        let l = environment_light(&scene);
        let prepared = Prepared::of(&l, &scene.tables);
        let p = Vec3::ZERO;
        let (nu, nv) = (1024, 512);
        let mut total = 0.0f64;
        for j in 0..nv {
            for i in 0..nu {
                let uv = Vec2::new((i as f32 + 0.5) / nu as f32, (j as f32 + 0.5) / nv as f32);
                let (d, jacobian) = direction(&l, uv);
                let pdf = light::pdf_prepared(&l, &prepared, p, to_world(&l, d));
                total += f64::from(pdf) * jacobian / (nu * nv) as f64;
            }
        }
        println!("{name}: ∫ pdf dω = {total}");
        assert!((total - 1.0).abs() < 2e-3, "{name}: {total}");
        // The octahedral map's radiance is constant over a texel: a sample carries its texel's,
        // and an escaping ray along it sees the same but within rounding of a texel's edge.
        let mut rng = TestRng(8);
        let mut elsewhere = 0;
        for _ in 0..1000 {
            let s = light::sample_prepared(&l, &prepared, p, rng.u2()).unwrap();
            let seen = light::escaped_radiance_prepared(&l, &prepared, s.wi);
            if (s.radiance - seen).abs().max_element() > 1e-3 * seen.max_element().max(1.0) {
                elsewhere += 1;
            }
            assert!(s.dist.is_infinite() && !s.delta && s.pdf > 0.0);
        }
        assert!(
            elsewhere <= 10,
            "{name}: {elsewhere} of 1000 samples see another radiance"
        );
    }
}

/// The studio's image under its octahedral map, with `rotate` replaced (`None`: as bundled).
fn octahedral_render(rotate: Option<&str>) -> stratapt_film::Film {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes/environment-octahedral.toml");
    let mut text = std::fs::read_to_string(&path).unwrap();
    if let Some(r) = rotate {
        text = text.replace("rotate = [-90, 30, 0]", r);
    }
    let scene = stratapt_import::load::load_str(&text, &path).unwrap_or_else(|e| panic!("{e}"));
    render_small(scene)
}

fn render_small(mut scene: FlatScene) -> stratapt_film::Film {
    (scene.camera.width, scene.camera.height) = (64, 40);
    let settings = stratapt_scene::RenderSettings {
        pattern_spp: 256,
        ..scene.settings
    };
    stratapt_cpu::render(&scene, &settings, &|_| {}, None).0
}

/// Mean luminance of each of the film's 4 × 4 blocks (16 × 10 pixels).
fn blocks(film: &stratapt_film::Film) -> Vec<f64> {
    let mut out = vec![0.0; 16];
    for y in 0..film.height as usize {
        for x in 0..film.width as usize {
            let m = film.mean(y * film.width as usize + x);
            out[(y / 10) * 4 + x / 16] += luminance(m.map(|v| v as f32)) / 160.0;
        }
    }
    out
}

/// The same studio in both layouts (scripts/make-environment.py resamples the latitude–longitude
/// map into the octahedral one) lights the scene alike: each of 4 × 4 blocks of the image
/// within 6 %, so the octahedral map's orientation, its frame's turn and its sampling are those
/// of the map it was made from. Measured 3.4 % at most (the sky seen just above the horizon,
/// where the ground meets a steep gradient that the two layouts' texels cut differently: 12 %
/// with a 64² octahedral map, 3.4 % with the bundled 128², so it is the resampling); the objects'
/// blocks within 0.5 %. Companions: the map turned upside down (98 % off), or 30° too far about
/// the vertical (62 %), are rejected.
#[test]
fn both_layouts_of_the_studio_render_alike() {
    let latlong = blocks(&render_small(scene("environment")));
    let worst = |b: &[f64]| {
        b.iter()
            .zip(&latlong)
            .map(|(x, y)| (x / y - 1.0).abs())
            .fold(0.0, f64::max)
    };
    let right = worst(&blocks(&octahedral_render(None)));
    let flipped = worst(&blocks(&octahedral_render(Some("rotate = [90, 30, 0]"))));
    let turned = worst(&blocks(&octahedral_render(Some("rotate = [-90, 60, 0]"))));
    println!(
        "largest block difference: {right:.4}; upside down {flipped:.4}, turned 30° {turned:.4}"
    );
    assert!(right < 0.06, "{right}");
    assert!(flipped > 0.06 && turned > 0.06, "{flipped} {turned}");
}
