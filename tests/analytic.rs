//! Analytic scenes: every strategy × sampler must converge to a closed form.
//!
//! - white furnace: a closed diffuse sphere of albedo a that also emits Le, seen from inside;
//!   with at most D scattering vertices the radiance is Le Σ_{k=0}^{D} a^k;
//! - irradiance on an albedo-1 floor (pixel = E / π) under a rectangle (Lambert's polygon
//!   formula), a coaxial disk, a sphere, a line (the sin θ tube profile), a point, a spot in its
//!   falloff band, suns (delta
//!   and cone) and a sky, with direct lighting only (max depth 1).
//!
//! Tolerance: |mean − exact| ≤ 4.5 stderr + 1e-4 exact, stderr from the film's own variance.

mod common;

use common::{
    check_mean, furnace_exact, furnace_toml, polygon_irradiance, relative_tolerance, render, scene,
};
use glam::DVec3;
use std::f64::consts::PI;
use stratapt::film::Film;
use stratapt::scene::{SamplerKind, Strategy};

/// A scene with a closed-form pixel value, rendered with every strategy × sampler.
struct Known {
    name: &'static str,
    toml: String,
    spp: u32,
    max_depth: u32,
    exact: f64,
    /// Whether a strategy's estimator must show variance.
    random: fn(Strategy) -> bool,
}

impl Known {
    /// Every strategy × sampler's film, labelled, with whether its estimator must be random.
    fn render_all(&self) -> Vec<(String, Film, bool)> {
        let scene = scene(self.name, &self.toml);
        let mut films = Vec::new();
        for strategy in Strategy::ALL {
            for sampler in SamplerKind::ALL {
                let (film, _) = render(&scene, strategy, sampler, self.spp, self.max_depth);
                let label = format!("{} / {strategy} / {sampler}", self.name);
                films.push((label, film, (self.random)(strategy)));
            }
        }
        films
    }

    /// Assert that every strategy × sampler converges to the answer.
    fn accept(&self) {
        for (label, film, random) in self.render_all() {
            if let Err(why) = check_mean(&film, [self.exact; 3], random) {
                panic!("{label}, {why}");
            }
        }
    }

    /// Assert that every strategy × sampler's check resolves errors of `2 · max_tolerance` of
    /// the answer (its tolerance is at most `max_tolerance`), and rejects the answer shifted
    /// either way by 2.5 times its own tolerance (beyond any mean that passes).
    fn reject(&self, max_tolerance: f64) {
        let exact = self.exact;
        for (label, film, random) in self.render_all() {
            let tolerance = relative_tolerance(&film, [exact; 3]);
            let shift = 2.5 * tolerance;
            eprintln!(
                "{label}: tolerance {tolerance:.2e} of the answer, planted shift ±{shift:.2e}"
            );
            assert!(
                tolerance <= max_tolerance,
                "{label}: tolerance {tolerance:.3e} > {max_tolerance:.3e} of the answer"
            );
            for shift in [shift, -shift] {
                match check_mean(&film, [exact * (1.0 + shift); 3], random) {
                    Ok(()) => panic!("{label}: the answer shifted by {shift:+.2e} passed"),
                    Err(why) => assert!(why.contains("mean "), "{label}: {why}"),
                }
            }
        }
    }
}

fn always(_: Strategy) -> bool {
    true
}

fn never(_: Strategy) -> bool {
    false
}

fn uniform_only(strategy: Strategy) -> bool {
    strategy == Strategy::Uniform
}

// ---------------------------------------------------------------------------------------------
// White furnace
// ---------------------------------------------------------------------------------------------

/// Depth 8 > ROULETTE_START + 1: Russian roulette makes every strategy random.
fn furnace_with_roulette() -> Known {
    Known {
        name: "furnace-8",
        toml: furnace_toml(4, 8),
        spp: 64,
        max_depth: 8,
        exact: furnace_exact(0.5, 8),
        random: always,
    }
}

/// Depth 3, no roulette: only uniform sampling is random. Cosine sampling gives the albedo
/// exactly; so does area sampling of the sphere from a point on it, whose solid-angle pdf
/// dist / (2πr) equals the cosine pdf, so MIS weights are ½ each. Depth 1 is direct lighting
/// only: Le (1 + a).
fn furnaces_with_short_paths() -> [Known; 2] {
    [(3, "furnace-3"), (1, "furnace-1")].map(|(depth, name)| Known {
        name,
        toml: furnace_toml(4, depth),
        spp: 32,
        max_depth: depth,
        exact: furnace_exact(0.5, depth),
        random: uniform_only,
    })
}

#[test]
fn white_furnace_with_roulette() {
    furnace_with_roulette().accept();
}

#[test]
fn white_furnace_short_paths_are_exact() {
    for known in furnaces_with_short_paths() {
        known.accept();
    }
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

/// The floor under `lights` seen at `target`, direct lighting only, with pixel value `exact`.
fn on_the_floor(
    name: &'static str,
    target: [f64; 2],
    lights: &str,
    exact: f64,
    random: fn(Strategy) -> bool,
) -> Known {
    Known {
        name,
        toml: floor_scene(target, lights),
        spp: SPP,
        max_depth: 1,
        exact,
        random,
    }
}

fn under_a_rectangle() -> Known {
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
    on_the_floor("rectangle", [p.x, p.y], lamp, e / PI, always)
}

fn under_a_coaxial_disk() -> Known {
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
    on_the_floor("disk", [0.0, 0.0], lamp, e / PI, always)
}

/// A sphere wholly above the horizon: E = π L (r/d)² cos θ.
fn under_a_sphere() -> Known {
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
    on_the_floor("sphere", [0.0, 0.0], lamp, e / PI, always)
}

/// Line of length l at height h, intensity I per unit length at θ = 90°, element at x:
/// dE = I sin θ cos θ_p / ρ² dx = I h² / ρ⁴ dx, so
/// E = I [ (l/2) / ((l/2)² + h²) + atan(l / 2h) / h ].
const LINE: (f64, f64, f64) = (2.0, 1.0, 3.0);

fn line_irradiance() -> f64 {
    let (l, h, i) = LINE;
    i * ((l / 2.0) / ((l / 2.0).powi(2) + h * h) + (l / (2.0 * h)).atan() / h)
}

fn below_the_middle_of_a_line() -> Known {
    let lamp = r#"
[[lights]]
type = "line"
from = [-1, 0, 1]
to = [1, 0, 1]
intensity = 3
"#;
    on_the_floor("line", [0.0, 0.0], lamp, line_irradiance() / PI, always)
}

fn under_a_point_light() -> Known {
    let q = DVec3::new(0.3, 0.1, 1.0);
    let lamp = r#"
[[lights]]
type = "point"
position = [0.3, 0.1, 1]
intensity = 5
"#;
    let e = 5.0 * q.z / q.length().powi(3);
    on_the_floor("point", [0.0, 0.0], lamp, e / PI, never)
}

/// A spot light aimed past the target, which sits in its falloff band:
/// E = I · smoothstep(cos 40°, cos 25°, cos α) · cos θ / d², α the angle from its axis.
fn under_a_spot_light() -> Known {
    let q = DVec3::new(0.3, 0.1, 1.0);
    let lamp = r#"
[[lights]]
type = "spot"
position = [0.3, 0.1, 1]
look_at = [0.5, 0.3, 0]
intensity = 5
cone_angle = 40
cone_delta = 15
"#;
    let axis = (DVec3::new(0.5, 0.3, 0.0) - q).normalize();
    let cos_alpha = (-q).normalize().dot(axis);
    let (end, start) = (40f64.to_radians().cos(), 25f64.to_radians().cos());
    let t = ((cos_alpha - end) / (start - end)).clamp(0.0, 1.0);
    assert!(t > 0.2 && t < 0.8, "in the falloff band: {t}");
    let e = 5.0 * t * t * (3.0 - 2.0 * t) * q.z / q.length().powi(3);
    on_the_floor("spot", [0.0, 0.0], lamp, e / PI, never)
}

/// E = irradiance · cos θ for a delta sun and for a cone wholly above the horizon (the loader
/// sets the cone's radiance to E / (π sin² θmax)).
fn under_suns() -> [Known; 2] {
    let dir = DVec3::new(0.3, -0.2, 1.0).normalize();
    let e = 2.0 * dir.z;
    let sun = |diameter: f64| {
        format!(
            "[[lights]]\ntype = \"distant\"\ndirection = [0.3, -0.2, 1]\nirradiance = 2\nangular_diameter = {diameter}\n"
        )
    };
    [
        on_the_floor("delta sun", [0.0, 0.0], &sun(0.0), e / PI, never),
        on_the_floor("cone sun", [0.0, 0.0], &sun(20.0), e / PI, always),
    ]
}

/// ∫ lerp(bottom, top, ½(1 + cos θ)) cos θ dω over the upper hemisphere
/// = π bottom + (5π/6)(top − bottom); the pixel is E / π.
fn under_a_gradient_sky() -> Known {
    let (top, bottom) = (1.5, 0.3);
    let sky = "[sky]\ntop = 1.5\nbottom = 0.3\nup = [0, 0, 1]\n";
    let pixel = bottom + 5.0 / 6.0 * (top - bottom);
    on_the_floor("sky", [0.0, 0.0], sky, pixel, always)
}

#[test]
fn irradiance_under_a_rectangle() {
    under_a_rectangle().accept();
}

#[test]
fn irradiance_under_a_coaxial_disk() {
    under_a_coaxial_disk().accept();
}

#[test]
fn irradiance_from_a_sphere() {
    under_a_sphere().accept();
}

#[test]
fn irradiance_below_the_middle_of_a_line() {
    // The closed form against a midpoint sum of dE over the line.
    let ((l, h, i), closed) = (LINE, line_irradiance());
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
    below_the_middle_of_a_line().accept();
}

#[test]
fn irradiance_from_a_point_light() {
    under_a_point_light().accept();
}

#[test]
fn irradiance_from_a_spot_light() {
    under_a_spot_light().accept();
}

#[test]
fn irradiance_from_suns() {
    for known in under_suns() {
        known.accept();
    }
}

#[test]
fn irradiance_from_a_gradient_sky() {
    under_a_gradient_sky().accept();
}

// ---------------------------------------------------------------------------------------------
// Planted errors: each answer shifted by what its check resolves is rejected
// ---------------------------------------------------------------------------------------------

/// Every strategy × sampler's check rejects the answer shifted either way by 2.5 times its
/// tolerance, the tolerance coming from the film's own error estimate ([`relative_tolerance`],
/// printed by this test): the check resolves an error of twice that. Each scene also bounds its
/// tolerances, so that a change that loosens a check fails here. At these sample counts the
/// checks resolve from 2·10⁻⁴ of the answer (exact estimators) and 0.5 % to 2 % (light sampling
/// and MIS of area lights and sun cones) to 120 % (uniform sampling of the sun cone): a check
/// of a strategy that rarely finds a small light sees only gross errors.
#[test]
fn shifted_answers_are_rejected() {
    let exact = 2.0 * common::F32_SLACK;
    let [short_3, short_1] = furnaces_with_short_paths();
    let [delta_sun, cone_sun] = under_suns();
    // The bounds: the largest tolerance measured over strategies × samplers, rounded up.
    let scenes = [
        (furnace_with_roulette(), 0.08),
        (short_3, 0.08),
        (short_1, 0.05),
        (under_a_rectangle(), 0.3),
        (under_a_coaxial_disk(), 0.25),
        (under_a_sphere(), 0.4),
        (below_the_middle_of_a_line(), 0.035),
        (under_a_point_light(), exact),
        (under_a_spot_light(), exact),
        (delta_sun, exact),
        (cone_sun, 0.75),
        (under_a_gradient_sky(), 0.12),
    ];
    for (known, max_tolerance) in scenes {
        known.reject(max_tolerance);
    }
}
