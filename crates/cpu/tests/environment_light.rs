//! The environment map as a light, as the integrator samples it: `light::sample_prepared` of
//! `scenes/environment.toml`'s map (rotated, with a small sun carrying most of its light)
//! against `light::pdf_prepared`: a chi-square fit in the map's `(u, v)` with planted errors, the
//! pdf's integral over the sphere, and the radiance an escaping ray sees against the lookup.

use glam::{Vec2, Vec3};
use std::f64::consts::PI;
use stratapt_cpu::light::{self, Prepared};
use stratapt_sampling::testing::chi2::{
    accept, density_bins, fit, print_fit, Family, Fit, Plant, Refusals,
};
use stratapt_sampling::testing::TestRng;
use stratapt_scene::environment;
use stratapt_scene::records::{light_kind, Light};
use stratapt_scene::FlatScene;

const FAMILY: Family = Family {
    alpha: 0.01,
    tests: 4,
};

fn scene() -> FlatScene {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/environment.toml");
    FlatScene::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

fn environment_light(scene: &FlatScene) -> Light {
    *scene
        .lights
        .iter()
        .find(|l| l.kind == light_kind::ENVIRONMENT)
        .expect("an environment light")
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

fn run(plant: Plant, wrong: bool) -> Fit {
    let scene = scene();
    let l = environment_light(&scene);
    let prepared = Prepared::of(&l, &scene.tables);
    // A wrong pdf: the sun's cells 10 % too likely (the densities elsewhere unchanged).
    let sun = |uv: Vec2| (uv.y * 64.0).floor() as i32 / 2 == 8 && (uv.x * 128.0) as i32 / 2 == 25;
    let p = Vec3::new(0.3, 0.5, -0.2);
    let density = |x: f64, y: f64| {
        let uv = Vec2::new(x as f32, y as f32);
        let (d, sin_theta) = environment::uv_to_direction(uv);
        let pdf = light::pdf_prepared(&l, &prepared, p, to_world(&l, d));
        let scale = if wrong && sun(uv) { 1.1 } else { 1.0 };
        f64::from(pdf) * scale * 2.0 * PI * PI * f64::from(sin_theta)
    };
    let (nx, ny) = (64, 32);
    let probs = density_bins(&density, nx, ny);
    let mut rng = TestRng(5);
    let samples = (0..200_000).map(|_| {
        light::sample_prepared(&l, &prepared, p, rng.u2()).map(|s| {
            let uv = environment::direction_to_uv(to_map(&l, s.wi));
            [f64::from(uv.x), f64::from(uv.y)]
        })
    });
    let name = match (plant, wrong) {
        (_, true) => "environment map, sun 10 % too likely in the pdf",
        _ => "environment map",
    };
    fit(
        &FAMILY,
        name,
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
    accept(vec![run(Plant::None, false)]);
}

/// Companions: a bent sampling routine, a pdf 1 % too large and one that makes the sun 10 % too
/// likely are each rejected.
#[test]
fn sampling_test_rejects_planted_errors() {
    for fit in [
        run(Plant::Bend(0.1), false),
        run(Plant::PdfScale(1.01), false),
        run(Plant::None, true),
    ] {
        print_fit(&fit);
        assert!(fit.verdict.is_err(), "{} accepted", fit.name);
    }
}

/// `∫ pdf dω = 1` over the sphere (a fine midpoint rule in the map's (u, v), where the density
/// is piecewise constant), and the sampled radiance is the map's lookup along the direction.
#[test]
fn pdf_integrates_to_one_and_samples_carry_the_maps_radiance() {
    let scene = scene();
    let l = environment_light(&scene);
    let prepared = Prepared::of(&l, &scene.tables);
    let p = Vec3::ZERO;
    let (nu, nv) = (1024, 512);
    let mut total = 0.0f64;
    for j in 0..nv {
        for i in 0..nu {
            let uv = Vec2::new((i as f32 + 0.5) / nu as f32, (j as f32 + 0.5) / nv as f32);
            let (d, sin_theta) = environment::uv_to_direction(uv);
            let pdf = light::pdf_prepared(&l, &prepared, p, to_world(&l, d));
            total += f64::from(pdf) * 2.0 * PI * PI * f64::from(sin_theta) / (nu * nv) as f64;
        }
    }
    println!("∫ pdf dω = {total}");
    assert!((total - 1.0).abs() < 2e-3, "{total}");
    let mut rng = TestRng(8);
    for _ in 0..1000 {
        let s = light::sample_prepared(&l, &prepared, p, rng.u2()).unwrap();
        let seen = light::escaped_radiance_prepared(&l, &prepared, s.wi);
        assert!(
            (s.radiance - seen).abs().max_element() <= 1e-3 * seen.max_element().max(1.0),
            "sampled {} vs escaped {seen}",
            s.radiance
        );
        assert!(s.dist.is_infinite() && !s.delta && s.pdf > 0.0);
    }
}
