//! Every warp's pdf integrates to one over its domain, every warp stays finite and in its
//! domain at the edges of `[0,1)²` and in hard configurations, and frames are orthonormal.
//! (Spherical triangles and rectangles: `spherical.rs`.)

mod common;

use std::f64::consts::{PI, TAU};

use common::{edge_uniforms, simpson_2d};
use glam::{Vec2, Vec3};
use stratapt_sampling::warp::{self, filter, ggx};
use stratapt_sampling::Frame;

/// Integral over the unit sphere of `f`, in coordinates `(φ/2π, √((1 − cos θ)/2))` around
/// `axis` (which resolves lobes peaked around `axis`), cell by cell.
fn integrate_sphere(f: &dyn Fn(Vec3) -> f64, axis: Vec3) -> f64 {
    let frame = Frame::from_normal(axis);
    let g = |x: f64, y: f64| {
        let omc = 2.0 * y * y;
        let sin = (omc * (2.0 - omc)).max(0.0).sqrt();
        let phi = TAU * x;
        let local = Vec3::new(
            (sin * phi.cos()) as f32,
            (sin * phi.sin()) as f32,
            (1.0 - omc) as f32,
        );
        f(frame.to_world(local)) * 4.0 * TAU * y
    };
    let (nx, ny) = (8, 32);
    let mut total = 0.0;
    for j in 0..ny {
        for i in 0..nx {
            let x = [i as f64 / nx as f64, (i + 1) as f64 / nx as f64];
            let y = [j as f64 / ny as f64, (j + 1) as f64 / ny as f64];
            total += simpson_2d(&g, x, y, 1e-7);
        }
    }
    total
}

fn assert_unit_integral(name: &str, value: f64) {
    eprintln!("∫ pdf {name} = {value:.6}");
    assert!((value - 1.0).abs() < 1e-3, "{name}: ∫ pdf = {value}");
}

#[test]
fn direction_pdfs_integrate_to_one() {
    let z = Vec3::Z;
    let hemi = |v: Vec3| {
        if v.z >= 0.0 {
            f64::from(warp::uniform_hemisphere_pdf())
        } else {
            0.0
        }
    };
    assert_unit_integral("uniform_hemisphere", integrate_sphere(&hemi, z));
    let cosine = |v: Vec3| f64::from(warp::cosine_hemisphere_pdf(v.z));
    assert_unit_integral("cosine_hemisphere", integrate_sphere(&cosine, z));
    let sphere = |_v: Vec3| f64::from(warp::uniform_sphere_pdf());
    assert_unit_integral(
        "uniform_sphere",
        integrate_sphere(&sphere, Vec3::new(0.3, -0.5, 0.8).normalize()),
    );
    for cos_max in [-0.9f32, 0.0, 0.5, 0.99, 0.9999] {
        let cone = |v: Vec3| {
            let inside = v.z >= cos_max;
            if inside {
                f64::from(warp::uniform_cone_pdf(cos_max))
            } else {
                0.0
            }
        };
        // Integrate in coordinates stretched to the cap so narrow cones are resolved.
        let width = f64::from(1.0 - cos_max);
        let cap = |x: f64, y: f64| {
            let v = Vec3::new(0.0, 0.0, (1.0 - y * width) as f32);
            cone(v) * TAU * width + 0.0 * x
        };
        let value = simpson_2d(&cap, [0.0, 1.0], [0.0, 1.0], 1e-9);
        assert_unit_integral(&format!("uniform_cone({cos_max})"), value);
    }
}

#[test]
fn planar_pdfs_integrate_to_one() {
    let disk = |x: f64, y: f64| {
        if x * x + y * y <= 1.0 {
            f64::from(warp::concentric_disk_pdf())
        } else {
            0.0
        }
    };
    // Polar form avoids the circular discontinuity: ∫∫ pdf r dr dφ.
    let polar = |r: f64, phi: f64| disk(r * phi.cos(), r * phi.sin()) * r;
    assert_unit_integral(
        "concentric_disk",
        simpson_2d(&polar, [0.0, 1.0], [0.0, TAU], 1e-9),
    );
    for r in [0.5f32, 1.0, 2.0] {
        let tent = |x: f64, y: f64| f64::from(filter::tent_pdf(Vec2::new(x as f32, y as f32), r));
        let rr = f64::from(r);
        // Split at the kinks (x = 0, y = 0).
        let mut total = 0.0;
        for xs in [[-rr, 0.0], [0.0, rr]] {
            for ys in [[-rr, 0.0], [0.0, rr]] {
                total += simpson_2d(&tent, xs, ys, 1e-9);
            }
        }
        assert_unit_integral(&format!("tent(r = {r})"), total);
    }
    for sigma in [0.3f32, 1.0] {
        let g =
            |x: f64, y: f64| f64::from(filter::gaussian_pdf(Vec2::new(x as f32, y as f32), sigma));
        let e = 8.0 * f64::from(sigma);
        assert_unit_integral(
            &format!("gaussian(σ = {sigma})"),
            simpson_2d(&g, [-e, e], [-e, e], 1e-9),
        );
    }
}

#[test]
fn ggx_densities_integrate_to_one() {
    for alpha in [
        Vec2::splat(0.05),
        Vec2::splat(0.3),
        Vec2::splat(1.0),
        Vec2::new(0.05, 0.5),
        Vec2::new(0.8, 0.2),
    ] {
        // Projected microfacet area: ∫ D(h) cos θh dh = 1.
        let projected = |h: Vec3| f64::from(ggx::d(h, alpha) * h.z.max(0.0));
        assert_unit_integral(
            &format!("D cos (α = {alpha})"),
            integrate_sphere(&projected, Vec3::Z),
        );
        for theta_deg in [0.0f32, 45.0, 80.0, 89.0] {
            let theta = theta_deg.to_radians();
            let wo = Vec3::new(theta.sin() * 0.6, -theta.sin() * 0.8, theta.cos());
            let vndf = |h: Vec3| f64::from(ggx::vndf_pdf(wo, h, alpha));
            let name = format!("vndf (α = {alpha}, θo = {theta_deg}°)");
            assert_unit_integral(&name, integrate_sphere(&vndf, Vec3::Z));
            let spec = Vec3::new(-wo.x, -wo.y, wo.z);
            let refl = |wi: Vec3| f64::from(ggx::reflection_pdf(wo, wi, alpha));
            let name = format!("reflection (α = {alpha}, θo = {theta_deg}°)");
            assert_unit_integral(&name, integrate_sphere(&refl, spec));
        }
    }
}

#[test]
fn warps_are_finite_and_in_domain_at_the_edges() {
    let unit = |v: Vec3| v.is_finite() && (v.length() - 1.0).abs() < 1e-5;
    for u in edge_uniforms() {
        let v = warp::uniform_hemisphere(u);
        assert!(unit(v) && v.z >= 0.0, "uniform_hemisphere({u}) = {v}");
        let v = warp::cosine_hemisphere(u);
        assert!(unit(v) && v.z >= 0.0, "cosine_hemisphere({u}) = {v}");
        let v = warp::uniform_sphere(u);
        assert!(unit(v), "uniform_sphere({u}) = {v}");
        let d = warp::concentric_disk(u);
        assert!(
            d.is_finite() && d.length() <= 1.0 + 1e-6,
            "concentric_disk({u}) = {d}"
        );
        for cos_max in [-1.0, -0.3, 0.5, 0.999_999, 1.0] {
            let v = warp::uniform_cone(u, cos_max);
            assert!(
                unit(v) && v.z >= cos_max - 1e-6,
                "uniform_cone({u}, {cos_max}) = {v}"
            );
        }
        let b = warp::uniform_triangle(u);
        assert!(
            b.min_element() >= 0.0 && (b.element_sum() - 1.0).abs() < 1e-6,
            "{b}"
        );
        for r in [0.5, 2.0] {
            let t = filter::tent(u, r);
            assert!(
                t.is_finite() && t.abs().max_element() <= r,
                "tent({u}) = {t}"
            );
        }
        let g = filter::gaussian(u, 1.0);
        assert!(g.is_finite(), "gaussian({u}) = {g}");
        for alpha in [1e-4, 0.05, 0.5, 1.0]
            .map(Vec2::splat)
            .into_iter()
            .chain([Vec2::new(1e-4, 1.0), Vec2::new(0.5, 1e-4)])
        {
            for wo in [
                Vec3::Z,
                Vec3::new(0.6, 0.0, 0.8),
                Vec3::new(0.0, 1.0, 1e-6).normalize(),
                Vec3::new(1.0, 0.0, 1e-3).normalize(),
            ] {
                let h = ggx::sample_vndf(wo, alpha, u);
                assert!(
                    unit(h) && h.z >= 0.0,
                    "sample_vndf({wo}, {alpha}, {u}) = {h}"
                );
                let pdf = ggx::vndf_pdf(wo, h, alpha);
                assert!(pdf.is_finite() && pdf >= 0.0, "vndf_pdf = {pdf}");
                let rp = ggx::reflection_pdf(wo, ggx::reflect(wo, h), alpha);
                assert!(rp.is_finite() && rp >= 0.0, "reflection_pdf = {rp}");
            }
        }
    }
    assert_eq!(warp::uniform_cone_pdf(1.0), f32::INFINITY);
    assert!(ggx::d(Vec3::Z, Vec2::splat(1e-10)).is_finite());
    assert!(ggx::d(Vec3::Z, Vec2::new(1e-10, 1.0)).is_finite());
    assert_eq!(ggx::g1(Vec3::X, Vec2::splat(0.5)), 0.0);
    assert_eq!(ggx::g1(Vec3::Y, Vec2::new(0.5, 0.01)), 0.0);
    assert_eq!(ggx::lambda(Vec3::Z, Vec2::new(0.5, 0.1)), 0.0);
}

/// The separable masking-shadowing never exceeds the height-correlated one ((1 + Λo)(1 + Λi) ≥
/// 1 + Λo + Λi), both equal G1 of the other direction when one is the normal, and both are 0 at
/// a grazing direction.
#[test]
fn separable_masking_shadows_at_least_as_much_as_correlated() {
    use ggx::Masking::{Correlated, Separable};
    let dirs: Vec<Vec3> = common::uniforms(500, 13)
        .map(warp::uniform_sphere)
        .collect();
    for alpha in [Vec2::splat(0.05), Vec2::splat(0.7), Vec2::new(0.1, 1.3)] {
        for pair in dirs.windows(2) {
            let (wo, wi) = (Vec3::new(pair[0].x, pair[0].y, pair[0].z.abs()), pair[1]);
            let (c, s) = (
                ggx::g2(wo, wi, alpha, Correlated),
                ggx::g2(wo, wi, alpha, Separable),
            );
            assert!(
                (0.0..=1.0).contains(&s) && s <= c * (1.0 + 1e-6),
                "{s} > {c}"
            );
            let g = ggx::g1(wi, alpha);
            for m in [Correlated, Separable] {
                let at_normal = ggx::g2(Vec3::Z, wi, alpha, m);
                assert!(
                    (at_normal - g).abs() <= 1e-6,
                    "{m:?}: {at_normal} vs G1 {g}"
                );
            }
        }
        for m in [Correlated, Separable] {
            assert_eq!(ggx::g2(Vec3::Z, Vec3::X, alpha, m), 0.0);
        }
    }
}

#[test]
fn frame_is_orthonormal_and_right_handed() {
    let mut normals: Vec<Vec3> = common::uniforms(4000, 7)
        .map(warp::uniform_sphere)
        .collect();
    normals.extend([
        Vec3::Z,
        -Vec3::Z,
        Vec3::X,
        Vec3::new(0.0, 0.0, -0.0),
        Vec3::new(1e-4, 0.0, -1.0).normalize(),
    ]);
    normals.retain(|n| n.length() > 0.5);
    for n in normals {
        let f = Frame::from_normal(n);
        for (a, b) in [(f.s, f.t), (f.t, f.n), (f.n, f.s)] {
            assert!(a.dot(b).abs() < 1e-5, "{n}: not orthogonal");
        }
        for v in [f.s, f.t] {
            assert!((v.length() - 1.0).abs() < 1e-5, "{n}: not unit");
        }
        assert!(f.s.cross(f.t).distance(f.n) < 1e-5, "{n}: not right-handed");
        let v = Vec3::new(0.3, -0.7, 0.2);
        assert!(f.to_world(f.to_local(v)).distance(v) < 1e-5);
        assert!(f.to_local(n).distance(Vec3::Z) < 1e-5);
    }
    // The area of the unit sphere through the frame map: sanity of integrate_sphere itself.
    let area = integrate_sphere(&|_| 1.0, Vec3::new(0.0, 0.6, -0.8));
    assert!((area / (4.0 * PI) - 1.0).abs() < 1e-6);
}
