//! Chi-square goodness-of-fit of every warp against its own pdf (mitsuba3 `ChiSquareTest`
//! style): sampled points are mapped to coordinates on `[0,1]²`, histogrammed, and compared
//! with bin probabilities integrated from the pdf (adaptive Simpson) or its analytic CDF.

mod common;

use std::f64::consts::{PI, TAU};

use common::{accept, density_bins, fit, reject, uniforms, Fit, Plant};
use glam::{Vec2, Vec3};
use stratapt_sampling::warp::{self, filter, ggx, spherical_rectangle, spherical_triangle};
use stratapt_sampling::Frame;

const N: u32 = 200_000;

/// Azimuth of `v` as a fraction of a turn in `[0, 1)`.
fn azimuth(v: Vec3) -> f64 {
    let phi = f64::from(v.y).atan2(f64::from(v.x)) / TAU;
    if phi < 0.0 {
        phi + 1.0
    } else {
        phi
    }
}

/// Unit direction from `(cos θ, azimuth fraction)`.
fn direction(cos_theta: f64, x: f64) -> Vec3 {
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let phi = TAU * x;
    Vec3::new(
        (sin_theta * phi.cos()) as f32,
        (sin_theta * phi.sin()) as f32,
        cos_theta as f32,
    )
}

/// Hemisphere coordinates `(φ / 2π, cos θ)`; `None` below the horizon.
fn hemisphere_coords(v: Vec3) -> Option<[f64; 2]> {
    (v.z >= 0.0 && (v.length() - 1.0).abs() < 1e-5).then(|| [azimuth(v), f64::from(v.z)])
}

fn uniform_hemisphere(plant: Plant) -> Vec<Fit> {
    let (nx, ny) = (32, 24);
    let pdf = |_x: f64, _y: f64| f64::from(warp::uniform_hemisphere_pdf()) * TAU;
    let probs = density_bins(&pdf, nx, ny);
    let samples = uniforms(N, 1).map(|u| hemisphere_coords(warp::uniform_hemisphere(u)));
    vec![fit("uniform_hemisphere", samples, &probs, nx, ny, plant)]
}

fn cosine_hemisphere(plant: Plant) -> Vec<Fit> {
    let (nx, ny) = (32, 24);
    let pdf = |_x: f64, y: f64| f64::from(warp::cosine_hemisphere_pdf(y as f32)) * TAU;
    let probs = density_bins(&pdf, nx, ny);
    let samples = uniforms(N, 2).map(|u| hemisphere_coords(warp::cosine_hemisphere(u)));
    vec![fit("cosine_hemisphere", samples, &probs, nx, ny, plant)]
}

fn uniform_sphere(plant: Plant) -> Vec<Fit> {
    let (nx, ny) = (32, 32);
    let pdf = |_x: f64, _y: f64| f64::from(warp::uniform_sphere_pdf()) * 2.0 * TAU;
    let probs = density_bins(&pdf, nx, ny);
    let samples = uniforms(N, 3).map(|u| {
        let v = warp::uniform_sphere(u);
        ((v.length() - 1.0).abs() < 1e-5).then(|| [azimuth(v), 0.5 * (f64::from(v.z) + 1.0)])
    });
    vec![fit("uniform_sphere", samples, &probs, nx, ny, plant)]
}

/// Clarberg's equal-area square → sphere map of a uniform point (octahedral environment maps):
/// uniform over the sphere.
fn equal_area_sphere(plant: Plant) -> Vec<Fit> {
    let (nx, ny) = (32, 32);
    let pdf = |_x: f64, _y: f64| f64::from(warp::equal_area::pdf()) * 2.0 * TAU;
    let probs = density_bins(&pdf, nx, ny);
    let samples = uniforms(N, 14).map(|u| {
        let v = warp::equal_area::square_to_sphere(u);
        ((v.length() - 1.0).abs() < 1e-5).then(|| [azimuth(v), 0.5 * (f64::from(v.z) + 1.0)])
    });
    vec![fit(
        "equal_area square to sphere",
        samples,
        &probs,
        nx,
        ny,
        plant,
    )]
}

fn concentric_disk(plant: Plant) -> Vec<Fit> {
    // Polar coordinates (φ / 2π, r²): area element π dx dy.
    let (nx, ny) = (32, 24);
    let pdf = |_x: f64, _y: f64| f64::from(warp::concentric_disk_pdf()) * PI;
    let probs = density_bins(&pdf, nx, ny);
    let samples = uniforms(N, 4).map(|u| {
        let p = warp::concentric_disk(u);
        let r2 = f64::from(p.length_squared());
        (r2 <= 1.0).then(|| [azimuth(p.extend(0.0)), r2])
    });
    vec![fit("concentric_disk", samples, &probs, nx, ny, plant)]
}

fn uniform_cone(plant: Plant) -> Vec<Fit> {
    // Coordinates (φ / 2π, (1 − cos θ) / (1 − cos_max)): solid-angle element
    // 2π (1 − cos_max) dx dy; narrow cones keep their resolution.
    let mut fits = Vec::new();
    for (k, cos_max) in [-0.5f32, 0.3, 0.95, 0.99999].into_iter().enumerate() {
        let (nx, ny) = (24, 24);
        let width = f64::from(1.0 - cos_max);
        let pdf = |_x: f64, _y: f64| f64::from(warp::uniform_cone_pdf(cos_max)) * TAU * width;
        let probs = density_bins(&pdf, nx, ny);
        let samples = uniforms(N / 2, 10 + k as u32).map(|u| {
            let v = warp::uniform_cone(u, cos_max);
            let sin2 = f64::from(v.x * v.x + v.y * v.y);
            let z = f64::from(v.z);
            let one_minus_cos = if z > 0.0 { sin2 / (1.0 + z) } else { 1.0 - z };
            Some([azimuth(v), one_minus_cos / width])
        });
        fits.push(fit(
            &format!("uniform_cone(cos_max = {cos_max})"),
            samples,
            &probs,
            nx,
            ny,
            plant,
        ));
    }
    fits
}

fn uniform_triangle(plant: Plant) -> Vec<Fit> {
    // Coordinates s = b0 + b1, t = b1 / s (the square-root map's inverse): density 2s.
    let (nx, ny) = (24, 24);
    let probs = density_bins(&|x: f64, _y: f64| 2.0 * x, nx, ny);
    let samples = uniforms(N, 20).map(|u| {
        let b = warp::uniform_triangle(u);
        let ok = b.min_element() >= 0.0 && (b.element_sum() - 1.0).abs() < 1e-6;
        let s = f64::from(b.x) + f64::from(b.y);
        ok.then(|| [s, if s > 0.0 { f64::from(b.y) / s } else { 0.0 }])
    });
    vec![fit("uniform_triangle", samples, &probs, nx, ny, plant)]
}

/// GGX reflection directions `wi = reflect(wo, h)`, `h` from the VNDF, histogrammed around the
/// specular direction in `(φ / 2π, √((1 − cos θ)/2))` (which spreads narrow lobes over rows);
/// expected density `reflection_pdf = vndf_pdf / (4 |wo·h|)` over the whole sphere.
fn ggx_vndf_reflection(plant: Plant) -> Vec<Fit> {
    let (nx, ny) = (24, 40);
    let mut seed = 30;
    let mut fits = Vec::new();
    for alpha in [
        Vec2::splat(0.05),
        Vec2::splat(0.3),
        Vec2::splat(1.0),
        Vec2::new(0.1, 0.5),
    ] {
        for theta_deg in [0.0f32, 50.0, 87.0] {
            let theta = theta_deg.to_radians();
            let wo = Vec3::new(theta.sin() * 0.8, theta.sin() * 0.6, theta.cos());
            let frame = Frame::from_normal(Vec3::new(-wo.x, -wo.y, wo.z).normalize());
            let pdf = |x: f64, y: f64| {
                let local = direction(1.0 - 2.0 * y * y, x);
                let wi = frame.to_world(local);
                f64::from(ggx::reflection_pdf(wo, wi, alpha)) * 4.0 * TAU * y
            };
            let probs = density_bins(&pdf, nx, ny);
            seed += 1;
            let samples = uniforms(N, seed).map(|u| {
                let h = ggx::sample_vndf(wo, alpha, u);
                if !(h.z >= 0.0 && (h.length() - 1.0).abs() < 1e-4 && wo.dot(h) >= 0.0) {
                    return None;
                }
                let l = frame.to_local(ggx::reflect(wo, h));
                let (lz, sin2) = (f64::from(l.z), f64::from(l.x * l.x + l.y * l.y));
                let one_minus_cos = if lz > 0.0 {
                    sin2 / (1.0 + lz)
                } else {
                    1.0 - lz
                };
                Some([azimuth(l), (0.5 * one_minus_cos).sqrt()])
            });
            let name = format!(
                "ggx vndf reflection (alpha = ({}, {}), theta_o = {theta_deg}°)",
                alpha.x, alpha.y
            );
            fits.push(fit(&name, samples, &probs, nx, ny, plant));
        }
    }
    fits
}

/// A planar shape parametrized by `(s, t) ∈ [0,1]²`, for the spherical-sampling tests.
trait Shape {
    fn point(&self, s: f64, t: f64) -> Vec3;
    /// Area element `dA / (ds dt)` at `(s, t)`.
    fn jacobian(&self, s: f64) -> f64;
    fn normal(&self) -> Vec3;
}

/// Triangle `(a, b, c)` by `s = b1 + b2`, `t = b2 / s` (barycentrics of `b`, `c`).
struct Tri([Vec3; 3]);
impl Shape for Tri {
    fn point(&self, s: f64, t: f64) -> Vec3 {
        let [a, b, c] = self.0;
        a + (b - a) * (s * (1.0 - t)) as f32 + (c - a) * (s * t) as f32
    }
    fn jacobian(&self, s: f64) -> f64 {
        let [a, b, c] = self.0;
        f64::from((b - a).cross(c - a).length()) * s
    }
    fn normal(&self) -> Vec3 {
        let [a, b, c] = self.0;
        (b - a).cross(c - a).normalize()
    }
}

/// Density over `(s, t)` of directions uniform in solid angle from `p`: `cos / d² / Ω · dA`.
fn solid_angle_density(shape: &dyn Shape, p: Vec3, omega: f64) -> impl Fn(f64, f64) -> f64 + '_ {
    move |s, t| {
        let q = shape.point(s, t) - p;
        let d = f64::from(q.length());
        let cos = f64::from(shape.normal().dot(q)).abs() / d;
        cos / (d * d) / omega * shape.jacobian(s)
    }
}

fn spherical_triangle(plant: Plant) -> Vec<Fit> {
    let configs: [(&str, Vec3, [Vec3; 3]); 5] = [
        (
            "moderate",
            Vec3::ZERO,
            [
                Vec3::new(-0.5, -0.3, 1.0),
                Vec3::new(0.7, -0.2, 1.2),
                Vec3::new(0.1, 0.8, 0.9),
            ],
        ),
        (
            "small (far)",
            Vec3::new(0.3, -0.2, 0.1),
            [
                Vec3::new(10.0, 3.0, 50.0),
                Vec3::new(10.2, 3.05, 50.1),
                Vec3::new(10.05, 3.2, 49.9),
            ],
        ),
        (
            "large (close above)",
            Vec3::new(0.25, 0.2, 0.05),
            [
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
        ),
        (
            "sliver seen obliquely",
            Vec3::new(2.0, 0.5, 0.3),
            [
                Vec3::new(-1.0, 0.0, 1.0),
                Vec3::new(1.0, 0.0, 1.0),
                Vec3::new(0.0, 0.05, 1.1),
            ],
        ),
        (
            "below, clockwise",
            Vec3::new(0.1, 0.1, -0.4),
            [
                Vec3::new(0.0, 1.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(-0.2, -0.3, 0.1),
            ],
        ),
    ];
    let (nx, ny) = (24, 24);
    let mut fits = Vec::new();
    for (k, (name, p, tri)) in configs.into_iter().enumerate() {
        let [a, b, c] = tri;
        let omega = spherical_triangle::solid_angle(p, a, b, c);
        let shape = Tri(tri);
        let probs = density_bins(&solid_angle_density(&shape, p, f64::from(omega)), nx, ny);
        let samples = uniforms(N, 50 + k as u32).map(|u| {
            let (dir, pdf) = spherical_triangle::sample(p, a, b, c, u)?;
            assert_eq!(pdf, 1.0 / omega);
            let [s, t] = triangle_hit(p, dir, tri)?;
            Some([s, t])
        });
        fits.push(fit(
            &format!("spherical_triangle {name} (Ω = {omega:.3e})"),
            samples,
            &probs,
            nx,
            ny,
            plant,
        ));
    }
    fits
}

/// Ray–triangle hit of `p + λ dir` as `(s, t)` coordinates of [`Tri`], `None` on a miss
/// (beyond a relative tolerance of 1e-4).
pub fn triangle_hit(p: Vec3, dir: Vec3, [a, b, c]: [Vec3; 3]) -> Option<[f64; 2]> {
    let (p, dir) = (p.as_dvec3(), dir.as_dvec3());
    let (a, b, c) = (a.as_dvec3(), b.as_dvec3(), c.as_dvec3());
    let (e1, e2) = (b - a, c - a);
    let pv = dir.cross(e2);
    let det = e1.dot(pv);
    let tv = p - a;
    let b1 = tv.dot(pv) / det;
    let qv = tv.cross(e1);
    let b2 = dir.dot(qv) / det;
    let lambda = e2.dot(qv) / det;
    let tol = 1e-4;
    if !(lambda > 0.0 && b1 >= -tol && b2 >= -tol && b1 + b2 <= 1.0 + tol) {
        return None;
    }
    let s = (b1 + b2).clamp(0.0, 1.0);
    let t = if s > 0.0 {
        (b2 / (b1 + b2)).clamp(0.0, 1.0)
    } else {
        0.0
    };
    Some([s, t])
}

/// Rectangle `corner + s ex + t ey`.
struct Rect(Vec3, Vec3, Vec3);
impl Shape for Rect {
    fn point(&self, s: f64, t: f64) -> Vec3 {
        self.0 + self.1 * s as f32 + self.2 * t as f32
    }
    fn jacobian(&self, _s: f64) -> f64 {
        f64::from(self.1.length() * self.2.length())
    }
    fn normal(&self) -> Vec3 {
        self.1.cross(self.2).normalize()
    }
}

fn spherical_rectangle(plant: Plant) -> Vec<Fit> {
    let ey_tilted = Vec3::new(-0.3, 0.3, 0.5);
    let configs: [(&str, Vec3, Rect); 6] = [
        (
            "above the centre",
            Vec3::new(0.1, -0.2, 1.0),
            Rect(Vec3::new(-1.0, -1.0, 0.0), Vec3::X * 2.0, Vec3::Y * 1.5),
        ),
        (
            "off to the side, close",
            Vec3::new(2.5, 0.3, 0.2),
            Rect(Vec3::ZERO, Vec3::X * 2.0, Vec3::Y),
        ),
        (
            "tilted, from below",
            Vec3::new(0.5, 0.2, -0.8),
            Rect(
                Vec3::new(0.0, 0.0, 0.3),
                Vec3::new(1.0, 1.0, 0.0),
                ey_tilted,
            ),
        ),
        (
            "tilted, grazing",
            Vec3::new(0.2, -0.6, -0.4),
            Rect(
                Vec3::new(0.0, 0.0, 0.3),
                Vec3::new(1.0, 1.0, 0.0),
                ey_tilted,
            ),
        ),
        (
            "tiny and far",
            Vec3::new(0.0, 0.5, 0.0),
            Rect(Vec3::new(5.0, -3.0, 100.0), Vec3::X * 0.2, Vec3::Y * 0.1),
        ),
        (
            "huge (close above)",
            Vec3::new(0.3, 0.6, 0.02),
            Rect(Vec3::new(-1.0, -1.0, 0.0), Vec3::X * 2.0, Vec3::Y * 2.0),
        ),
    ];
    let (nx, ny) = (24, 24);
    let mut fits = Vec::new();
    for (k, (name, p, rect)) in configs.into_iter().enumerate() {
        let Rect(corner, ex, ey) = rect;
        let omega = spherical_rectangle::solid_angle(p, corner, ex, ey);
        let probs = density_bins(&solid_angle_density(&rect, p, f64::from(omega)), nx, ny);
        let n = rect.normal();
        let samples = uniforms(N, 60 + k as u32).map(|u| {
            let (q, pdf) = spherical_rectangle::sample(p, corner, ex, ey, u)?;
            assert_eq!(pdf, 1.0 / omega);
            let rel = q - corner;
            if f64::from(n.dot(rel)).abs() > 1e-5 * f64::from(rel.length().max(1.0)) {
                return None;
            }
            let s = f64::from(rel.dot(ex) / ex.length_squared());
            let t = f64::from(rel.dot(ey) / ey.length_squared());
            Some([s, t])
        });
        fits.push(fit(
            &format!("spherical_rectangle {name} (Ω = {omega:.3e})"),
            samples,
            &probs,
            nx,
            ny,
            plant,
        ));
    }
    fits
}

/// Tent CDF on one axis.
fn tent_cdf(x: f64, r: f64) -> f64 {
    let x = x.clamp(-r, r);
    if x < 0.0 {
        (x + r) * (x + r) / (2.0 * r * r)
    } else {
        1.0 - (r - x) * (r - x) / (2.0 * r * r)
    }
}

fn tent_filter(plant: Plant) -> Vec<Fit> {
    let (nx, ny, r) = (20, 20, 1.5f32);
    let rr = f64::from(r);
    let edge = |i: usize, n: usize| -rr + 2.0 * rr * i as f64 / n as f64;
    let axis = |i: usize, n: usize| tent_cdf(edge(i + 1, n), rr) - tent_cdf(edge(i, n), rr);
    let probs: Vec<f64> = (0..ny)
        .flat_map(|j| (0..nx).map(move |i| axis(i, nx) * axis(j, ny)))
        .collect();
    let samples = uniforms(N, 70).map(|u| {
        let p = filter::tent(u, r);
        Some([
            (f64::from(p.x) + rr) / (2.0 * rr),
            (f64::from(p.y) + rr) / (2.0 * rr),
        ])
    });
    vec![fit("tent filter", samples, &probs, nx, ny, plant)]
}

fn gaussian_filter(plant: Plant) -> Vec<Fit> {
    // Through the normal CDF Φ each axis becomes uniform: every bin has probability 1/(nx ny).
    let (nx, ny, sigma) = (20, 20, 0.7f32);
    let probs = vec![1.0 / (nx * ny) as f64; nx * ny];
    let phi = |x: f32| {
        0.5 * statrs::function::erf::erfc(-f64::from(x / sigma) / std::f64::consts::SQRT_2)
    };
    let samples = uniforms(N, 71).map(|u| {
        let p = filter::gaussian(u, sigma);
        p.is_finite().then(|| [phi(p.x), phi(p.y)])
    });
    vec![fit("gaussian filter", samples, &probs, nx, ny, plant)]
}

fn box_filter(plant: Plant) -> Vec<Fit> {
    let (nx, ny) = (16, 16);
    let probs = vec![1.0 / (nx * ny) as f64; nx * ny];
    let samples = uniforms(N / 2, 72).map(|u: Vec2| {
        let p = filter::box_filter(u, 2.0);
        Some([(f64::from(p.x) + 1.0) / 2.0, (f64::from(p.y) + 1.0) / 2.0])
    });
    vec![fit("box filter", samples, &probs, nx, ny, plant)]
}

// ---------------------------------------------------------------------------------------------
// The fits as tests, and their companions with a planted error
// ---------------------------------------------------------------------------------------------

/// The piecewise-constant 2D distribution (environment maps) of a 16 × 8 grid with zero cells,
/// a bright spike and a smooth ramp, histogrammed on the unit square (bins straddle the cells).
fn piecewise_2d(plant: Plant) -> Vec<Fit> {
    use stratapt_sampling::warp::piecewise;
    let (w, h) = (16, 8);
    let weights: Vec<f32> = (0..w * h)
        .map(|k| {
            let (i, j) = (k % w, k / w);
            match (i, j) {
                (5, 2) => 40.0,
                (_, 0) | (3, _) => 0.0,
                _ => 1.0 + (i * j) as f32 * 0.1,
            }
        })
        .collect();
    let tables = piecewise::build(&weights, w, h).unwrap();
    let (nx, ny) = (24, 12);
    let pdf =
        |x: f64, y: f64| f64::from(piecewise::pdf(&tables, w, h, Vec2::new(x as f32, y as f32)));
    let probs = density_bins(&pdf, nx, ny);
    let samples = uniforms(N, 13).map(|u| {
        piecewise::sample(&tables, w, h, u).map(|(p, _)| [f64::from(p.x), f64::from(p.y)])
    });
    vec![fit("piecewise 2D", samples, &probs, nx, ny, plant)]
}

/// Every warp's fits.
const WARPS: [fn(Plant) -> Vec<Fit>; 14] = [
    uniform_hemisphere,
    cosine_hemisphere,
    uniform_sphere,
    equal_area_sphere,
    concentric_disk,
    uniform_cone,
    uniform_triangle,
    ggx_vndf_reflection,
    spherical_triangle,
    spherical_rectangle,
    tent_filter,
    gaussian_filter,
    box_filter,
    piecewise_2d,
];

#[test]
fn chi2_uniform_hemisphere() {
    accept(uniform_hemisphere(Plant::None));
}

#[test]
fn chi2_cosine_hemisphere() {
    accept(cosine_hemisphere(Plant::None));
}

#[test]
fn chi2_uniform_sphere() {
    accept(uniform_sphere(Plant::None));
}

#[test]
fn chi2_equal_area_sphere() {
    accept(equal_area_sphere(Plant::None));
}

#[test]
fn chi2_concentric_disk() {
    accept(concentric_disk(Plant::None));
}

#[test]
fn chi2_uniform_cone() {
    accept(uniform_cone(Plant::None));
}

#[test]
fn chi2_uniform_triangle() {
    accept(uniform_triangle(Plant::None));
}

#[test]
fn chi2_ggx_vndf_reflection() {
    accept(ggx_vndf_reflection(Plant::None));
}

#[test]
fn chi2_spherical_triangle() {
    accept(spherical_triangle(Plant::None));
}

#[test]
fn chi2_spherical_rectangle() {
    accept(spherical_rectangle(Plant::None));
}

#[test]
fn chi2_tent_filter() {
    accept(tent_filter(Plant::None));
}

#[test]
fn chi2_gaussian_filter() {
    accept(gaussian_filter(Plant::None));
}

#[test]
fn chi2_box_filter() {
    accept(box_filter(Plant::None));
}

#[test]
fn chi2_piecewise_2d() {
    accept(piecewise_2d(Plant::None));
}

/// Every fit rejects a pdf 1 % too large everywhere. The histogram alone cannot see a constant
/// factor (it adds about `n · 10⁻⁴`, 20, to a statistic whose deviation is √(2 dof), 23 to 45):
/// the check that the bin probabilities sum to one (within 0.2 %) rejects it.
#[test]
fn chi2_rejects_a_pdf_one_percent_off() {
    for warp in WARPS {
        reject(warp(Plant::PdfScale(1.01)), "Σp");
    }
}

/// Every fit rejects its warp bent by the smallest smooth error it surely sees, by its p-value:
/// a relative density error of up to δ, computed per fit from its sample count, bins and
/// significance ([`common::detectable_bend`]); δ is 4.4 % to 14 % at these counts (a 1 % bend
/// moves the statistic by 7 at most, against a deviation of 23 to 45: no fit here can see it).
#[test]
fn chi2_rejects_a_slightly_wrong_warp() {
    for warp in WARPS {
        reject(warp(Plant::WarpBend), "p =");
    }
}
