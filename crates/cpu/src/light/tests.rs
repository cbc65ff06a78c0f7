//! Light sampling: `pdf` agrees with `sample` for every kind and method, and the inverse pdf
//! estimates the solid angle (so the pdf is the true density, not merely self-consistent).

use super::*;
use glam::DVec3;
use std::f64::consts::PI;
use stratapt_sampling::testing::TestRng;

fn light(kind: u32, p0: [f32; 3], p1: [f32; 3], p2: [f32; 3]) -> Light {
    Light {
        kind,
        p0,
        p1,
        p2,
        radiance: [1.0, 2.0, 3.0],
        motion: u32::MAX,
        ..Default::default()
    }
}

/// Every kind the scene stores converts to the kind that stores it, and nothing else converts.
#[test]
fn stored_kinds_convert_both_ways() {
    let stored = [
        light_kind::TRIANGLE,
        light_kind::RECTANGLE,
        light_kind::DISK,
        light_kind::SPHERE,
        light_kind::LINE,
        light_kind::POINT,
        light_kind::DISTANT,
        light_kind::SKY,
        light_kind::ENVIRONMENT,
        light_kind::OCTAHEDRAL,
        light_kind::SPOT,
    ];
    for (&value, kind) in stored.iter().zip(LightKind::ALL) {
        assert_eq!(LightKind::of(value), Some(kind));
        assert_eq!(kind.stored(), value);
    }
    for value in (0..64).chain([u32::MAX]) {
        assert_eq!(
            LightKind::of(value).is_some(),
            stored.contains(&value),
            "{value}"
        );
    }
    // A light of no known kind gives no light.
    let unknown = light(99, [0.0; 3], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
    let (p, wi) = (Vec3::new(0.0, 0.0, 1.0), Vec3::NEG_Z);
    assert_eq!(sample(&unknown, p, Vec2::splat(0.5)), None);
    assert_eq!(pdf(&unknown, p, wi), 0.0);
    assert_eq!(escaped_radiance(&unknown, wi), Vec3::ZERO);
    assert!(!in_plane(&unknown, Vec3::ZERO, Vec3::ZERO, Vec3::Z));
}

/// Solid angle of triangle `(a, b, c)` from `p` in f64 (Van Oosterom & Strackee 1983).
fn triangle_solid_angle(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let (a, b, c) = (a - p, b - p, c - p);
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let num = a.dot(b.cross(c)).abs();
    let den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    2.0 * num.atan2(den)
}

/// Triangle, rectangle, disk, sphere, distant-cone and sky lights with points that exercise each
/// sampling method, and the exact solid angle each subtends.
fn cases() -> Vec<(&'static str, Light, Vec3, f64)> {
    let d = |v: Vec3| v.as_dvec3();
    let (a, b, c) = (Vec3::ZERO, Vec3::X, Vec3::Y);
    let tri = light(light_kind::TRIANGLE, a.into(), b.into(), c.into());
    let tri_omega = |p: Vec3| triangle_solid_angle(d(p), d(a), d(b), d(c));
    // Facing down (−z): p1 × p2 = (0, 1, 0) × (2, 0, 0).
    let rect = light(
        light_kind::RECTANGLE,
        [-1.0, -0.5, 2.0],
        [0.0, 1.0, 0.0],
        [2.0, 0.0, 0.0],
    );
    let rect_omega = |p: Vec3| {
        let (o, x, y) = (
            DVec3::new(-1.0, -0.5, 2.0),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        );
        triangle_solid_angle(d(p), o, o + x, o + x + y)
            + triangle_solid_angle(d(p), o, o + x + y, o + y)
    };
    let disk = light(
        light_kind::DISK,
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
        [0.5, 0.0, 0.0],
    );
    let disk_omega = |h: f64, r: f64| 2.0 * PI * (1.0 - h / (h * h + r * r).sqrt());
    let sphere = light(
        light_kind::SPHERE,
        [0.0, 0.0, 3.0],
        [0.0; 3],
        [0.5, 0.0, 0.0],
    );
    let cone = |dist: f64, r: f64| 2.0 * PI * (1.0 - (1.0 - r * r / (dist * dist)).sqrt());
    let far_sphere = light(
        light_kind::SPHERE,
        [0.0, 0.0, 300.0],
        [0.0; 3],
        [0.5, 0.0, 0.0],
    );
    let sun = light(
        light_kind::DISTANT,
        Vec3::new(0.3, 0.4, 1.0).normalize().into(),
        [0.0; 3],
        [0.99, 0.0, 0.0],
    );
    let sky = light(light_kind::SKY, [0.0, 0.0, 1.0], [0.5, 0.5, 1.0], [0.0; 3]);
    // The extremes of each method: a triangle 10⁵ away (5·10⁻¹¹ sr), a sphere 10⁵ away
    // (sin²θ = 2.5·10⁻¹¹, deep in the series), a point just outside a sphere (a cone of
    // almost a hemisphere), and a sun cone one f32 ULP of cos θ wide (the narrowest that is not
    // a delta direction).
    let p_remote = Vec3::new(0.3, 0.2, 1e5);
    let remote_sphere = light(
        light_kind::SPHERE,
        [0.0, 0.0, 1e5],
        [0.0; 3],
        [0.5, 0.0, 0.0],
    );
    let grazing_sphere = 0.5 * (1.0f32 + 3e-3).sqrt();
    let narrowest = f32::from_bits(1.0f32.to_bits() - 1);
    let narrow_sun = light(
        light_kind::DISTANT,
        [0.0, 0.0, 1.0],
        [0.0; 3],
        [narrowest, 0.0, 0.0],
    );
    let p_mid = Vec3::new(0.25, 0.25, 0.5);
    let p_far = Vec3::new(0.3, 0.2, 100.0);
    let p_close = Vec3::new(0.3, 0.3, 2e-3);
    let p_rect_close = Vec3::new(0.1, 0.0, 2.0 - 5e-3);
    // Seen under a small angle (AREA_SAMPLED_ANGULAR_SIZE_SQ) with a solid angle far above
    // the spherical method's lower bound: area sampling too.
    let (p_tri_small, p_rect_small) = (Vec3::new(0.3, 0.2, 4.0), Vec3::new(0.2, 0.1, -3.0));
    vec![
        ("triangle, spherical", tri, p_mid, tri_omega(p_mid)),
        ("triangle, tiny (area)", tri, p_far, tri_omega(p_far)),
        ("triangle, close (area)", tri, p_close, tri_omega(p_close)),
        (
            "rectangle, spherical",
            rect,
            Vec3::new(0.3, 0.1, 0.5),
            rect_omega(Vec3::new(0.3, 0.1, 0.5)),
        ),
        (
            "rectangle, tiny (area)",
            rect,
            Vec3::new(0.0, 0.0, -200.0),
            rect_omega(Vec3::new(0.0, 0.0, -200.0)),
        ),
        (
            "rectangle, close (area)",
            rect,
            p_rect_close,
            rect_omega(p_rect_close),
        ),
        (
            "triangle, seen small (area)",
            tri,
            p_tri_small,
            tri_omega(p_tri_small),
        ),
        (
            "rectangle, seen small (area)",
            rect,
            p_rect_small,
            rect_omega(p_rect_small),
        ),
        ("disk", disk, Vec3::ZERO, disk_omega(1.0, 0.5)),
        ("sphere, outside", sphere, Vec3::ZERO, cone(3.0, 0.5)),
        (
            "sphere, far (small-angle series)",
            far_sphere,
            Vec3::ZERO,
            cone(300.0, 0.5),
        ),
        ("sphere, inside", sphere, Vec3::new(0.1, 0.2, 3.1), 4.0 * PI),
        // On the surface the sphere fills the half-space below the tangent plane.
        (
            "sphere, on the surface",
            sphere,
            Vec3::new(0.0, 0.0, 2.5),
            2.0 * PI,
        ),
        ("sun cone", sun, Vec3::ZERO, 2.0 * PI * (1.0 - 0.99)),
        (
            "triangle, 1e5 away (area)",
            tri,
            p_remote,
            tri_omega(p_remote),
        ),
        (
            "sphere, 1e5 away (series)",
            remote_sphere,
            Vec3::ZERO,
            cone(1e5, 0.5),
        ),
        (
            "sphere, just outside",
            sphere,
            Vec3::new(0.0, 0.0, 3.0 - grazing_sphere),
            cone(grazing_sphere as f64, 0.5),
        ),
        (
            "sun cone, one ulp wide",
            narrow_sun,
            Vec3::ZERO,
            2.0 * PI * (1.0 - narrowest as f64),
        ),
        ("sky", sky, Vec3::ZERO, 4.0 * PI),
    ]
}

/// Each polygon case takes the method its name says: the spherical one only where the light is
/// neither seen small nor of a solid angle out of the spherical method's range.
#[test]
fn cases_exercise_both_polygon_methods() {
    let mut methods = Vec::new();
    for (name, l, p, omega) in cases() {
        let (a, b, c) = geometry(&l);
        let spherical = match LightKind::of(l.kind) {
            Some(LightKind::Triangle) => triangle::spherical(a, b, c, p).is_some(),
            Some(LightKind::Rectangle) => {
                rectangle::spherical(&rectangle::Prepared::new(b, c), p, a).is_some()
            }
            _ => continue,
        };
        assert_eq!(spherical, name.ends_with("spherical"), "{name}");
        let small = name.contains("seen small");
        assert!(!small || use_spherical(omega as f32), "{name}: Ω {omega}");
        methods.push((spherical, small));
    }
    // Both methods, and the small angle alone choosing area sampling, for both shapes.
    assert_eq!(methods.iter().filter(|m| m.0).count(), 2);
    assert_eq!(methods.iter().filter(|m| m.1).count(), 2);
}

#[test]
fn pdf_agrees_with_sample_for_every_kind() {
    let mut rng = TestRng(11);
    for (name, l, p, _) in cases() {
        let mut valid = 0;
        for _ in 0..4000 {
            let u = rng.u2();
            let Some(ls) = sample(&l, p, u) else { continue };
            assert!(
                !ls.delta && ls.wi.is_normalized() && ls.dist > 0.0,
                "{name}: {ls:?}"
            );
            let q = pdf(&l, p, ls.wi);
            assert!(
                (q - ls.pdf).abs() <= 2e-3 * ls.pdf,
                "{name}: pdf {q} vs sampled {} ({ls:?})",
                ls.pdf
            );
            if ls.dist.is_finite() {
                // The sampled point lies on the light: the ray towards it reaches it.
                let x = p + ls.wi * ls.dist;
                assert!(on_light(&l, x), "{name}: {x} is not on the light");
            }
            valid += 1;
        }
        assert!(valid > 3900, "{name}: only {valid} valid samples");
    }
}

#[test]
fn inverse_pdf_estimates_the_solid_angle() {
    let mut rng = TestRng(5);
    for (name, l, p, omega) in cases() {
        // Area sampling from close to a large polygon has a heavy tail (relative variance
        // ≈ area / (8π h²)): many more samples there.
        let n = if name.contains("close") {
            1_000_000
        } else {
            40_000
        };
        let (mut sum, mut sum_sq) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let u = rng.u2();
            let x = sample(&l, p, u).map_or(0.0, |ls| 1.0 / ls.pdf as f64);
            sum += x;
            sum_sq += x * x;
        }
        let mean = sum / n as f64;
        let stderr = ((sum_sq / n as f64 - mean * mean).max(0.0) / n as f64).sqrt();
        let tol = 4.5 * stderr + 2e-3 * omega;
        assert!(
            (mean - omega).abs() <= tol,
            "{name}: E[1/pdf] = {mean} ± {stderr}, solid angle {omega}"
        );
    }
}

#[test]
fn delta_lights_have_unit_pdf_and_zero_hit_pdf() {
    let point = light(light_kind::POINT, [0.0, 0.0, 2.0], [0.0; 3], [0.0; 3]);
    let ls = sample(&point, Vec3::ZERO, Vec2::splat(0.5)).unwrap();
    assert!(ls.delta && ls.pdf == 1.0 && ls.wi == Vec3::Z && ls.dist == 2.0);
    assert!((ls.radiance - Vec3::new(1.0, 2.0, 3.0) / 4.0).length() < 1e-6);
    assert_eq!(pdf(&point, Vec3::ZERO, Vec3::Z), 0.0);
    let sun = light(
        light_kind::DISTANT,
        [0.0, 0.0, 1.0],
        [0.0; 3],
        [1.0, 0.0, 0.0],
    );
    let ls = sample(&sun, Vec3::ZERO, Vec2::splat(0.5)).unwrap();
    assert!(ls.delta && ls.wi == Vec3::Z && ls.dist.is_infinite());
    assert_eq!(pdf(&sun, Vec3::ZERO, Vec3::Z), 0.0);
    assert_eq!(escaped_radiance(&sun, Vec3::Z), Vec3::ZERO);
    assert!(!sun.is_environment());
}

#[test]
fn line_light_estimates_the_tube_integral() {
    // ∫ I sin θ / dist² dl along a tilted segment, by the midpoint rule in f64.
    let (a, b) = (Vec3::new(-1.0, 0.3, 1.0), Vec3::new(1.5, -0.2, 1.4));
    let l = light(light_kind::LINE, a.into(), b.into(), [0.0; 3]);
    let p = Vec3::new(0.2, 0.1, 0.0);
    let steps = 100_000;
    let (da, db, dp) = (a.as_dvec3(), b.as_dvec3(), p.as_dvec3());
    let exact: f64 = (0..steps)
        .map(|i| {
            let x = da.lerp(db, (i as f64 + 0.5) / steps as f64) - dp;
            let sin = x.normalize().cross((db - da).normalize()).length();
            sin / x.length_squared() * (db - da).length() / steps as f64
        })
        .sum();
    let mut rng = TestRng(3);
    let n = 40_000;
    let (mut sum, mut sum_sq) = (0.0f64, 0.0f64);
    for _ in 0..n {
        let ls = sample(&l, p, rng.u2()).unwrap();
        assert!(ls.delta && ls.pdf == 1.0);
        let x = ls.radiance.x as f64;
        sum += x;
        sum_sq += x * x;
    }
    let mean = sum / n as f64;
    let stderr = ((sum_sq / n as f64 - mean * mean) / n as f64).sqrt();
    assert!(
        (mean - exact).abs() < 4.5 * stderr + 1e-4 * exact,
        "{mean} ± {stderr} vs {exact}"
    );
}

#[test]
fn back_side_of_one_sided_emitters_is_dark() {
    let tri = light(
        light_kind::TRIANGLE,
        [0.0; 3],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
    );
    assert!(sample(&tri, Vec3::new(0.2, 0.2, -1.0), Vec2::splat(0.3)).is_none());
    assert_eq!(pdf(&tri, Vec3::new(0.2, 0.2, -1.0), Vec3::Z), 0.0);
    let disk = light(light_kind::DISK, [0.0; 3], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
    assert!(sample(&disk, Vec3::new(0.0, 0.0, -1.0), Vec2::splat(0.3)).is_none());
}

/// A two-sided triangle, rectangle or disk seen from the mirror image of each case's point
/// through its plane is the same light: its samples' pdf agrees with `pdf`, they land on it, and
/// the inverse pdf estimates the same solid angle; one-sided, it gives nothing there.
#[test]
fn two_sided_emitters_are_sampled_from_behind() {
    let mut rng = TestRng(17);
    let mut checked = 0;
    for (name, l, p, omega) in cases() {
        let (a, b, c) = geometry(&l);
        let n = match LightKind::of(l.kind) {
            Some(LightKind::Triangle) => (b - a).cross(c - a).normalize(),
            Some(LightKind::Rectangle) => b.cross(c).normalize(),
            Some(LightKind::Disk) => b.normalize(),
            _ => continue,
        };
        let behind = p - 2.0 * (p - a).dot(n) * n;
        assert!(sample(&l, behind, Vec2::splat(0.4)).is_none(), "{name}");
        let two_sided = Light {
            flags: light_flag::TWO_SIDED,
            ..l
        };
        let n_samples = if name.contains("close") {
            400_000
        } else {
            40_000
        };
        let (mut sum, mut sum_sq) = (0.0f64, 0.0f64);
        for _ in 0..n_samples {
            let Some(ls) = sample(&two_sided, behind, rng.u2()) else {
                continue;
            };
            let q = pdf(&two_sided, behind, ls.wi);
            assert!((q - ls.pdf).abs() <= 2e-3 * ls.pdf, "{name}: {q} vs {ls:?}");
            assert!(ls.wi.dot(n) > 0.0, "{name}: {ls:?} leaves the light's back");
            assert!(on_light(&l, behind + ls.wi * ls.dist), "{name}: {ls:?}");
            let x = 1.0 / ls.pdf as f64;
            sum += x;
            sum_sq += x * x;
        }
        let mean = sum / n_samples as f64;
        let stderr = ((sum_sq / n_samples as f64 - mean * mean).max(0.0) / n_samples as f64).sqrt();
        assert!(
            (mean - omega).abs() <= 4.5 * stderr + 2e-3 * omega,
            "{name}: E[1/pdf] = {mean} ± {stderr} from behind, solid angle {omega}"
        );
        // From the front, two-sided changes nothing.
        let u = rng.u2();
        assert_eq!(sample(&two_sided, p, u), sample(&l, p, u), "{name}");
        checked += 1;
    }
    assert!(checked >= 6, "{checked}");
}

#[test]
fn moving_light_is_placed_at_the_ray_time() {
    use stratapt_scene::records::Pose;
    let motions = [Motion {
        open: Pose::IDENTITY,
        close: Pose::new(Vec3::new(2.0, 0.0, 0.0), glam::Quat::IDENTITY, Vec3::ONE),
    }];
    let mut rect = light(
        light_kind::RECTANGLE,
        [-0.5, -0.5, 1.0],
        [0.0, 1.0, 0.0],
        [1.0, 0.0, 0.0],
    );
    rect.motion = 0;
    let at_half = placed(&rect, &motions, 0.5);
    assert_eq!(Vec3::from(at_half.p0), Vec3::new(0.5, -0.5, 1.0));
    assert_eq!(Vec3::from(at_half.p2), Vec3::X);
    // Seen from below, its point is always within the moved rectangle.
    let ls = sample(&at_half, Vec3::new(1.0, 0.0, 0.0), Vec2::new(0.9, 0.1)).unwrap();
    let x = Vec3::new(1.0, 0.0, 0.0) + ls.wi * ls.dist;
    assert!(x.x >= 0.5 - 1e-5 && x.x <= 1.5 + 1e-5, "{x}");
}

/// Whether `x` lies on the light's surface (to f32 precision), for the finite kinds.
fn on_light(l: &Light, x: Vec3) -> bool {
    let (a, b, c) = geometry(l);
    let tol = 1e-4 * (1.0 + x.abs().max_element());
    match LightKind::of(l.kind).expect("a stored light kind") {
        LightKind::Triangle => {
            let n = (b - a).cross(c - a).normalize();
            (x - a).dot(n).abs() < tol
        }
        LightKind::Rectangle => {
            let n = b.cross(c).normalize();
            let (s, t) = (
                (x - a).dot(b) / b.length_squared(),
                (x - a).dot(c) / c.length_squared(),
            );
            (x - a).dot(n).abs() < tol
                && (-1e-4..=1.0 + 1e-4).contains(&s)
                && (-1e-4..=1.0 + 1e-4).contains(&t)
        }
        LightKind::Disk => (x - a).dot(b).abs() < tol && (x - a).length() <= c.x * (1.0 + 1e-4),
        LightKind::Sphere => ((x - a).length() - c.x).abs() < tol,
        LightKind::Line
        | LightKind::Point
        | LightKind::Spot
        | LightKind::Distant
        | LightKind::Sky
        | LightKind::Environment
        | LightKind::Octahedral => true,
    }
}

/// Degenerate lights and shading points (zero areas, lengths and radii, collinear edges, points
/// on a light's plane, surface, axis, vertex or centre, tiny and huge scales): a sample is
/// either refused or fully finite with a positive pdf, and every pdf and escaped radiance is
/// finite and non-negative. No division by a zero pdf or distance can get through.
#[test]
fn degenerate_lights_and_points_give_no_sample_or_a_finite_one() {
    let mut rng = TestRng(17);
    let (mut refused, mut total) = (0, 0);
    let z = [0.0f32; 3];
    let scales = [1e-20f32, 1e-6, 1.0, 1e6, 1e20];
    for scale in scales {
        let v = |x: f32, y: f32, zz: f32| [x * scale, y * scale, zz * scale];
        let lights = [
            light(light_kind::TRIANGLE, z, z, v(1.0, 0.0, 0.0)),
            light(light_kind::TRIANGLE, z, v(1.0, 1.0, 0.0), v(2.0, 2.0, 0.0)),
            light(light_kind::TRIANGLE, z, v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0)),
            light(light_kind::RECTANGLE, z, z, v(1.0, 0.0, 0.0)),
            light(light_kind::RECTANGLE, z, v(1.0, 0.0, 0.0), v(2.0, 0.0, 0.0)),
            light(light_kind::RECTANGLE, z, v(0.0, 1.0, 0.0), v(1.0, 0.0, 0.0)),
            light(light_kind::DISK, z, [0.0, 0.0, 1.0], [0.0; 3]),
            light(light_kind::DISK, z, [0.0, 0.0, 1.0], [scale, 0.0, 0.0]),
            light(light_kind::SPHERE, z, z, [0.0; 3]),
            light(light_kind::SPHERE, z, z, [scale, 0.0, 0.0]),
            light(light_kind::LINE, z, z, z),
            light(light_kind::LINE, z, v(0.0, 0.0, 1.0), z),
            light(light_kind::POINT, z, z, z),
        ];
        // Points at the origin (vertex, corner, centre, end), on the plane, on the axis, on the
        // sphere, on an edge, just off each, and anywhere.
        let points = [
            Vec3::ZERO,
            Vec3::from(v(0.3, 0.2, 0.0)),
            Vec3::from(v(0.0, 0.0, 0.5)),
            Vec3::from(v(0.0, 0.0, 1.0)),
            Vec3::from(v(0.5, 0.0, 0.0)),
            Vec3::from(v(0.0, 0.0, 1e-7)),
            Vec3::from(v(1e-30, -1e-30, 1e-30)),
            Vec3::from(v(-3.0, 2.0, -1.0)),
        ];
        for l in &lights {
            for &p in &points {
                for _ in 0..50 {
                    let u = rng.u2();
                    total += 1;
                    match sample(l, p, u) {
                        None => refused += 1,
                        Some(ls) => {
                            assert!(
                                ls.pdf > 0.0
                                    && ls.pdf.is_finite()
                                    && ls.wi.is_finite()
                                    && ls.dist > 0.0
                                    && !ls.dist.is_nan()
                                    && ls.radiance.is_finite()
                                    && ls.radiance.min_element() >= 0.0,
                                "kind {} at scale {scale}, p {p}: {ls:?}",
                                l.kind
                            );
                        }
                    }
                    let wi = rng.point(1.0);
                    let wi = wi.try_normalize().unwrap_or(Vec3::Z);
                    let q = pdf(l, p, wi);
                    assert!(
                        q.is_finite() && q >= 0.0,
                        "kind {} at scale {scale}: pdf {q} from {p} towards {wi}",
                        l.kind
                    );
                }
            }
        }
    }
    // The degenerate cases do reach the guards: many refusals, and many valid samples.
    println!("{refused} of {total} degenerate samples refused");
    assert!(
        refused > total / 10 && refused < total * 9 / 10,
        "{refused} of {total}"
    );
}
