//! Analytic scenes: every strategy × sampler must converge to a closed form.
//!
//! - white furnace: a closed diffuse sphere of albedo a that also emits Le, seen from inside;
//!   with at most D scattering vertices the radiance is Le Σ_{k=0}^{D} a^k;
//! - irradiance on an albedo-1 floor (pixel = E / π) under a rectangle (Lambert's polygon
//!   formula), a coaxial disk, a sphere, a line (the sin θ tube profile), a point, suns (delta
//!   and cone) and a sky, with direct lighting only (max depth 1).
//!
//! Tolerance: |mean − exact| ≤ 4.5 stderr + 1e-4 exact, stderr from the film's own variance.

mod common;

use common::{assert_mean, furnace_exact, furnace_toml, polygon_irradiance, render, scene};
use glam::DVec3;
use std::f64::consts::PI;
use stratapt::scene::{SamplerKind, Strategy};

/// Render `toml` for every strategy × sampler and compare with `exact`; `random(strategy)` says
/// whether that estimator must show variance.
fn check_all(
    name: &str,
    toml: &str,
    spp: u32,
    max_depth: u32,
    exact: f64,
    random: impl Fn(Strategy) -> bool,
) {
    let scene = scene(name, toml);
    for strategy in Strategy::ALL {
        for sampler in SamplerKind::ALL {
            let (film, _) = render(&scene, strategy, sampler, spp, max_depth);
            let label = format!("{name} / {strategy} / {sampler}");
            assert_mean(&label, &film, [exact; 3], random(strategy));
        }
    }
}

// ---------------------------------------------------------------------------------------------
// White furnace
// ---------------------------------------------------------------------------------------------

#[test]
fn white_furnace_with_roulette() {
    // Depth 8 > ROULETTE_START + 1: Russian roulette makes every strategy random.
    check_all(
        "furnace-8",
        &furnace_toml(4, 8),
        64,
        8,
        furnace_exact(0.5, 8),
        |_| true,
    );
}

#[test]
fn white_furnace_short_paths_are_exact() {
    // Depth 3, no roulette: only uniform sampling is random. Cosine sampling gives the albedo
    // exactly; so does area sampling of the sphere from a point on it, whose solid-angle pdf
    // dist / (2πr) equals the cosine pdf, so MIS weights are ½ each.
    let random = |s| s == Strategy::Uniform;
    check_all(
        "furnace-3",
        &furnace_toml(4, 3),
        32,
        3,
        furnace_exact(0.5, 3),
        random,
    );
    // Direct lighting only: Le (1 + a).
    check_all(
        "furnace-1",
        &furnace_toml(4, 1),
        32,
        1,
        furnace_exact(0.5, 1),
        random,
    );
}

// ---------------------------------------------------------------------------------------------
// Irradiance on a floor
// ---------------------------------------------------------------------------------------------

/// A 4×4-pixel camera with a tiny field of view looking straight down at `target` on the
/// albedo-1 floor z = 0, plus `lights` (TOML).
fn floor_scene(target: [f64; 2], lights: &str) -> String {
    let [x, y] = target;
    format!(
        r#"
[camera]
eye = [{x}, {y}, 0.3]
look_at = [{x}, {y}, 0]
up = [0, 1, 0]
fov = 0.02
[film]
width = 4
height = 4
[materials.floor]
type = "diffuse"
albedo = 1
[materials.lamp]
type = "diffuse"
albedo = 0
emission = 2
[[shapes]]
type = "rectangle"
corner = [-10, -10, 0]
edge_u = [20, 0, 0]
edge_v = [0, 20, 0]
material = "floor"
{lights}
"#
    )
}

/// Samples per pixel for the irradiance scenes (16 pixels each).
const SPP: u32 = 256;

#[test]
fn irradiance_under_a_rectangle() {
    let p = DVec3::new(0.3, 0.2, 0.0);
    // Facing down: edge_u × edge_v = (0, 0.8, 0) × (1, 0, 0) = (0, 0, −0.8).
    let lamp = r#"
[[shapes]]
type = "rectangle"
corner = [-0.5, -0.4, 1]
edge_u = [0, 0.8, 0]
edge_v = [1, 0, 0]
material = "lamp"
"#;
    let corners =
        [[-0.5, -0.4], [-0.5, 0.4], [0.5, 0.4], [0.5, -0.4]].map(|[x, y]| DVec3::new(x, y, 1.0));
    let e = polygon_irradiance(p, DVec3::Z, &corners, 2.0);
    check_all(
        "rectangle",
        &floor_scene([p.x, p.y], lamp),
        SPP,
        1,
        e / PI,
        |_| true,
    );
}

#[test]
fn irradiance_under_a_coaxial_disk() {
    let (r, h) = (0.5, 1.0);
    let lamp = r#"
[[shapes]]
type = "disk"
center = [0, 0, 1]
normal = [0, 0, -1]
radius = 0.5
material = "lamp"
"#;
    let e = PI * 2.0 * r * r / (r * r + h * h);
    check_all(
        "disk",
        &floor_scene([0.0, 0.0], lamp),
        SPP,
        1,
        e / PI,
        |_| true,
    );
}

#[test]
fn irradiance_from_a_sphere() {
    // A sphere wholly above the horizon: E = π L (r/d)² cos θ.
    let (c, r) = (DVec3::new(0.4, 0.0, 1.5), 0.5);
    let lamp = r#"
[[shapes]]
type = "sphere"
center = [0.4, 0, 1.5]
radius = 0.5
material = "lamp"
"#;
    let d = c.length();
    let e = PI * 2.0 * (r / d).powi(2) * (c.z / d);
    check_all(
        "sphere",
        &floor_scene([0.0, 0.0], lamp),
        SPP,
        1,
        e / PI,
        |_| true,
    );
}

#[test]
fn irradiance_below_the_middle_of_a_line() {
    // Line of length l at height h, intensity I per unit length at θ = 90°, element at x:
    // dE = I sin θ cos θ_p / ρ² dx = I h² / ρ⁴ dx, so
    // E = I [ (l/2) / ((l/2)² + h²) + atan(l / 2h) / h ].
    let (l, h, i) = (2.0f64, 1.0f64, 3.0f64);
    let closed = i * ((l / 2.0) / ((l / 2.0).powi(2) + h * h) + (l / (2.0 * h)).atan() / h);
    let steps = 200_000;
    let numeric: f64 = (0..steps)
        .map(|k| {
            let x = -l / 2.0 + l * (k as f64 + 0.5) / steps as f64;
            i * h * h / (x * x + h * h).powi(2) * l / steps as f64
        })
        .sum();
    assert!(
        (closed - numeric).abs() < 1e-9 * closed,
        "{closed} vs {numeric}"
    );
    let lamp = r#"
[[lights]]
type = "line"
from = [-1, 0, 1]
to = [1, 0, 1]
intensity = 3
"#;
    check_all(
        "line",
        &floor_scene([0.0, 0.0], lamp),
        SPP,
        1,
        closed / PI,
        |_| true,
    );
}

#[test]
fn irradiance_from_a_point_light() {
    let q = DVec3::new(0.3, 0.1, 1.0);
    let lamp = r#"
[[lights]]
type = "point"
position = [0.3, 0.1, 1]
intensity = 5
"#;
    let e = 5.0 * q.z / q.length().powi(3);
    check_all(
        "point",
        &floor_scene([0.0, 0.0], lamp),
        SPP,
        1,
        e / PI,
        |_| false,
    );
}

#[test]
fn irradiance_from_suns() {
    // E = irradiance · cos θ for a delta sun and for a cone wholly above the horizon (the
    // loader sets the cone's radiance to E / (π sin² θmax)).
    let dir = DVec3::new(0.3, -0.2, 1.0).normalize();
    let e = 2.0 * dir.z;
    for (name, diameter, random) in [("delta sun", 0.0, false), ("cone sun", 20.0, true)] {
        let lamp = format!(
            "[[lights]]\ntype = \"distant\"\ndirection = [0.3, -0.2, 1]\nirradiance = 2\nangular_diameter = {diameter}\n"
        );
        check_all(
            name,
            &floor_scene([0.0, 0.0], &lamp),
            SPP,
            1,
            e / PI,
            |_| random,
        );
    }
}

#[test]
fn irradiance_from_a_gradient_sky() {
    // ∫ lerp(bottom, top, ½(1 + cos θ)) cos θ dω over the upper hemisphere
    // = π bottom + (5π/6)(top − bottom); the pixel is E / π.
    let (top, bottom) = (1.5, 0.3);
    let sky = "[sky]\ntop = 1.5\nbottom = 0.3\nup = [0, 0, 1]\n";
    let pixel = bottom + 5.0 / 6.0 * (top - bottom);
    check_all("sky", &floor_scene([0.0, 0.0], sky), SPP, 1, pixel, |_| {
        true
    });
}
