//! Every strategy estimates the same integral: on a small scene with a rough GGX conductor, a
//! diffuse sphere, an area light, a point light, a sun cone and a sky, each strategy's image mean
//! agrees with MIS within 4.5 standard errors of the difference (per channel, every sampler).

mod common;

use common::{render, scene, Z};
use stratapt::scene::{SamplerKind, Strategy};

const SCENE: &str = r#"
[camera]
eye = [0, 1.5, -4]
look_at = [0, 0.5, 0]
fov = 40
[film]
width = 8
height = 6
[materials.floor]
type = "conductor"
reflectance = [0.9, 0.7, 0.5]
roughness = 0.35
[materials.ball]
type = "diffuse"
albedo = [0.7, 0.6, 0.5]
[materials.lamp]
type = "diffuse"
albedo = 0
emission = 6
[[shapes]]
type = "rectangle"
corner = [-5, 0, -5]
edge_u = [0, 0, 10]
edge_v = [10, 0, 0]
material = "floor"
[[shapes]]
type = "sphere"
center = [-0.4, 0.6, 0.3]
radius = 0.6
material = "ball"
[[shapes]]   # facing down
type = "rectangle"
corner = [0.5, 2.5, -0.5]
edge_u = [1, 0, 0]
edge_v = [0, 0, 1]
material = "lamp"
[[lights]]
type = "point"
position = [-1.5, 2, -1]
intensity = 3
[[lights]]
type = "distant"
direction = [1, 2, -1]
irradiance = 1.5
angular_diameter = 12
[sky]
color = 0.2
"#;

#[test]
fn strategies_agree_with_mis() {
    let scene = scene("strategies", SCENE);
    for sampler in SamplerKind::ALL {
        let (reference, _) = render(&scene, Strategy::Mis, sampler, 2048, 3);
        let (mis, mis_err) = reference.image_mean();
        for strategy in [
            Strategy::Uniform,
            Strategy::Cosine,
            Strategy::Bsdf,
            Strategy::Light,
        ] {
            let (film, _) = render(&scene, strategy, sampler, 2048, 3);
            let (mean, err) = film.image_mean();
            for c in 0..3 {
                let sigma = (err[c] * err[c] + mis_err[c] * mis_err[c]).sqrt();
                assert!(sigma > 0.0);
                assert!(
                    (mean[c] - mis[c]).abs() <= Z * sigma,
                    "{strategy} / {sampler}, channel {c}: {} ± {} vs mis {} ± {} ({:.2} σ)",
                    mean[c],
                    err[c],
                    mis[c],
                    mis_err[c],
                    (mean[c] - mis[c]).abs() / sigma
                );
            }
        }
    }
}
