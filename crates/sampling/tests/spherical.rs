//! Spherical triangles and rectangles: solid angles agree with closed forms and quadrature
//! (tiny to near-2π), samples carry `pdf = 1/Ω` and hit their shape (ray test), and degenerate
//! configurations give `None`.

mod common;

use std::f64::consts::TAU;

use common::{edge_uniforms, simpson_2d};
use glam::{DVec3, Vec2, Vec3};
use stratapt_sampling::warp::{spherical_rectangle, spherical_triangle};

/// Solid angle of the rectangle `[0, a] × [0, b]` at height `h` above its corner (closed form).
fn corner_rect_solid_angle(a: f64, b: f64, h: f64) -> f64 {
    (a * b / (h * (a * a + b * b + h * h).sqrt())).atan()
}

#[test]
fn solid_angles_match_closed_forms() {
    for (a, b, h) in [
        (1.0, 1.0, 1.0),
        (2.0, 0.5, 0.1),
        (1e-3, 2e-3, 10.0),
        (0.01, 0.01, 1000.0),
        (100.0, 100.0, 1e-3),
        (3.0, 1.0, 1e-5),
    ] {
        let exact = corner_rect_solid_angle(a, b, h);
        let p = Vec3::new(0.0, 0.0, h as f32);
        let (ex, ey) = (Vec3::X * a as f32, Vec3::Y * b as f32);
        let rect = f64::from(spherical_rectangle::solid_angle(p, Vec3::ZERO, ex, ey));
        // Same rectangle from the other side, and with its edges given in the other order.
        let below = f64::from(spherical_rectangle::solid_angle(-p, Vec3::ZERO, ex, ey));
        let swapped = f64::from(spherical_rectangle::solid_angle(p, Vec3::ZERO, ey, ex));
        // Two triangles sharing the diagonal.
        let (c0, c1, c2, c3) = (Vec3::ZERO, ex, ex + ey, ey);
        let tris = f64::from(spherical_triangle::solid_angle(p, c0, c1, c2))
            + f64::from(spherical_triangle::solid_angle(p, c0, c2, c3));
        eprintln!(
            "Ω rect {a}×{b} at {h}: exact {exact:.6e}, rect {rect:.6e}, triangles {tris:.6e}"
        );
        for (name, value) in [
            ("rect", rect),
            ("below", below),
            ("swapped", swapped),
            ("triangles", tris),
        ] {
            assert!(
                (value / exact - 1.0).abs() < 2e-4,
                "{name}: {value:e} vs {exact:e} ({a}, {b}, {h})"
            );
        }
        // By symmetry about the diagonal, a square's two halves subtend equal angles.
        if a == b {
            let half = f64::from(spherical_triangle::solid_angle(p, c0, c1, c2));
            assert!(
                (half / (0.5 * exact) - 1.0).abs() < 2e-4,
                "half square: {half:e}"
            );
        }
    }
}

/// `∫ |n·(x − p)| / |x − p|³ dA` over the planar shape `o + s e1 + t e2`, `(s, t) ∈ [0,1]²`
/// (`triangle`: only `s + t ≤ 1`, by the map `(s, t) → (s (1 − t), s t)`).
fn quadrature_solid_angle(p: Vec3, o: Vec3, e1: Vec3, e2: Vec3, triangle: bool) -> f64 {
    let (p, o, e1, e2) = (p.as_dvec3(), o.as_dvec3(), e1.as_dvec3(), e2.as_dvec3());
    let n = e1.cross(e2);
    let f = |s: f64, t: f64| {
        let (u, v, jac) = if triangle {
            (s * (1.0 - t), s * t, s)
        } else {
            (s, t, 1.0)
        };
        let q: DVec3 = o + e1 * u + e2 * v - p;
        n.dot(q).abs() / q.length().powi(3) * jac
    };
    let mut total = 0.0;
    let k = 8;
    for i in 0..k {
        for j in 0..k {
            let s = [i as f64 / k as f64, (i + 1) as f64 / k as f64];
            let t = [j as f64 / k as f64, (j + 1) as f64 / k as f64];
            total += simpson_2d(&f, s, t, 1e-10);
        }
    }
    total
}

#[test]
fn solid_angles_match_quadrature() {
    let cases = [
        (
            Vec3::new(0.2, 0.3, 1.0),
            Vec3::new(-0.5, -0.5, 0.0),
            Vec3::new(1.0, 0.2, 0.0),
            Vec3::new(-0.2, 1.0, 0.0),
        ),
        (
            Vec3::new(1.5, -0.3, -0.6),
            Vec3::ZERO,
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(-0.3, 0.3, 0.5),
        ),
        (
            Vec3::new(3.0, 2.0, 0.5),
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.0, 2.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
        ),
    ];
    for (p, o, e1, e2) in cases {
        let rect = f64::from(spherical_rectangle::solid_angle(p, o, e1, e2));
        let rect_q = quadrature_solid_angle(p, o, e1, e2, false);
        let tri = f64::from(spherical_triangle::solid_angle(p, o, o + e1, o + e2));
        let tri_q = quadrature_solid_angle(p, o, e1, e2, true);
        eprintln!("Ω rect {rect:.6} vs {rect_q:.6}, triangle {tri:.6} vs {tri_q:.6}");
        assert!(
            (rect / rect_q - 1.0).abs() < 1e-4,
            "rect {rect} vs {rect_q}"
        );
        assert!(
            (tri / tri_q - 1.0).abs() < 1e-4,
            "triangle {tri} vs {tri_q}"
        );
    }
}

/// Does the ray `p + λ dir` (λ > 0) hit triangle `(a, b, c)` (relative tolerance 1e-4)?
fn hits_triangle(p: Vec3, dir: Vec3, [a, b, c]: [Vec3; 3]) -> bool {
    let (p, dir, a, b, c) = (
        p.as_dvec3(),
        dir.as_dvec3(),
        a.as_dvec3(),
        b.as_dvec3(),
        c.as_dvec3(),
    );
    let (e1, e2) = (b - a, c - a);
    let pv = dir.cross(e2);
    let det = e1.dot(pv);
    let tv = p - a;
    let qv = tv.cross(e1);
    let (b1, b2, lambda) = (tv.dot(pv) / det, dir.dot(qv) / det, e2.dot(qv) / det);
    let tol = 1e-4;
    lambda > 0.0 && b1 >= -tol && b2 >= -tol && b1 + b2 <= 1.0 + tol
}

#[test]
fn spherical_triangle_samples_hit_with_pdf_one_over_omega() {
    let s = 1e-3f32;
    let cases: [(Vec3, [Vec3; 3]); 5] = [
        (
            Vec3::ZERO,
            [
                Vec3::new(-0.5, -0.3, 1.0),
                Vec3::new(0.7, -0.2, 1.2),
                Vec3::new(0.1, 0.8, 0.9),
            ],
        ),
        // Tiny: Ω ≈ 1e-10.
        (
            Vec3::ZERO,
            [
                Vec3::new(0.0, 0.0, 50.0),
                Vec3::new(s, 0.0, 50.0),
                Vec3::new(0.0, s, 50.0),
            ],
        ),
        // Huge: p a hair above the interior (Ω → 2π).
        (Vec3::new(0.2, 0.3, 1e-4), [Vec3::ZERO, Vec3::X, Vec3::Y]),
        // Grazing: p almost in the plane, outside.
        (Vec3::new(2.0, 2.0, 1e-3), [Vec3::ZERO, Vec3::X, Vec3::Y]),
        // Far off-axis.
        (Vec3::new(-30.0, 40.0, 5.0), [Vec3::ZERO, Vec3::X, Vec3::Y]),
    ];
    let mut rng = common::uniforms(2000, 99).collect::<Vec<_>>();
    rng.extend(edge_uniforms());
    for (p, tri) in cases {
        let [a, b, c] = tri;
        let omega = spherical_triangle::solid_angle(p, a, b, c);
        assert!(
            omega > 0.0 && omega.is_finite() && omega <= TAU as f32,
            "Ω = {omega}"
        );
        for &u in &rng {
            let (dir, pdf) = spherical_triangle::sample(p, a, b, c, u).expect("non-degenerate");
            assert_eq!(pdf, 1.0 / omega);
            assert!(
                dir.is_finite() && (dir.length() - 1.0).abs() < 1e-5,
                "{dir}"
            );
            assert!(
                hits_triangle(p, dir, tri),
                "miss: p {p} tri {tri:?} u {u} dir {dir} Ω {omega}"
            );
        }
    }
}

#[test]
fn spherical_triangle_degenerate_is_none() {
    let (a, b, c) = (Vec3::ZERO, Vec3::X, Vec3::Y);
    let u = Vec2::splat(0.3);
    // In the plane (outside and inside), at a vertex, and collinear vertices.
    assert!(spherical_triangle::sample(Vec3::new(2.0, 2.0, 0.0), a, b, c, u).is_none());
    assert!(spherical_triangle::sample(Vec3::new(0.2, 0.2, 0.0), a, b, c, u).is_none());
    assert!(spherical_triangle::sample(a, a, b, c, u).is_none());
    assert!(spherical_triangle::sample(Vec3::Z, a, b, 2.0 * b, u).is_none());
    assert_eq!(
        spherical_triangle::solid_angle(Vec3::new(2.0, 2.0, 0.0), a, b, c),
        0.0
    );
    assert_eq!(spherical_triangle::solid_angle(a, a, b, c), 0.0);
}

#[test]
fn spherical_rectangle_samples_hit_with_pdf_one_over_omega() {
    let cases: [(Vec3, Vec3, Vec3, Vec3); 6] = [
        (
            Vec3::new(0.1, -0.2, 1.0),
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::X * 2.0,
            Vec3::Y * 1.5,
        ),
        (
            Vec3::new(0.1, -0.2, -1.0),
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::X * 2.0,
            Vec3::Y * 1.5,
        ),
        // Tiny (Ω ≈ 1e-10) and far off-axis.
        (
            Vec3::ZERO,
            Vec3::new(30.0, -20.0, 100.0),
            Vec3::X * 1e-3,
            Vec3::Y * 1e-3,
        ),
        // Huge: p a hair above the interior.
        (
            Vec3::new(0.3, 0.6, 1e-4),
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::X * 2.0,
            Vec3::Y * 2.0,
        ),
        // Grazing: p almost in the plane, outside.
        (Vec3::new(3.0, 0.5, 1e-3), Vec3::ZERO, Vec3::X, Vec3::Y),
        // Tilted, p behind.
        (
            Vec3::new(0.5, 0.2, -0.8),
            Vec3::new(0.0, 0.0, 0.3),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(-0.3, 0.3, 0.5),
        ),
    ];
    let mut rng = common::uniforms(2000, 98).collect::<Vec<_>>();
    rng.extend(edge_uniforms());
    for (p, corner, ex, ey) in cases {
        let omega = spherical_rectangle::solid_angle(p, corner, ex, ey);
        assert!(
            omega > 0.0 && omega.is_finite() && omega <= TAU as f32,
            "Ω = {omega}"
        );
        let n = ex.cross(ey).normalize();
        for &u in &rng {
            let (q, pdf) =
                spherical_rectangle::sample(p, corner, ex, ey, u).expect("non-degenerate");
            assert_eq!(pdf, 1.0 / omega);
            // The point lies on the rectangle: in its plane, inside its edges.
            let rel = q - corner;
            assert!(
                q.is_finite() && n.dot(rel).abs() <= 1e-5 * rel.length().max(1.0),
                "{q}"
            );
            let (s, t) = (
                rel.dot(ex) / ex.length_squared(),
                rel.dot(ey) / ey.length_squared(),
            );
            assert!(
                (-1e-5..=1.0 + 1e-5).contains(&s) && (-1e-5..=1.0 + 1e-5).contains(&t),
                "{s} {t}"
            );
            assert!((q - p).length() > 0.0);
        }
    }
}

#[test]
fn spherical_rectangle_degenerate_is_none() {
    let u = Vec2::splat(0.4);
    let (corner, ex, ey) = (Vec3::ZERO, Vec3::X, Vec3::Y);
    // p in the plane (inside and outside), zero-size edges.
    assert!(spherical_rectangle::sample(Vec3::new(0.5, 0.5, 0.0), corner, ex, ey, u).is_none());
    assert!(spherical_rectangle::sample(Vec3::new(3.0, 0.5, 0.0), corner, ex, ey, u).is_none());
    assert!(spherical_rectangle::sample(Vec3::Z, corner, Vec3::ZERO, ey, u).is_none());
    assert!(spherical_rectangle::sample(Vec3::Z, corner, ex, Vec3::ZERO, u).is_none());
    assert_eq!(
        spherical_rectangle::solid_angle(Vec3::new(0.5, 0.5, 0.0), corner, ex, ey),
        0.0
    );
}
